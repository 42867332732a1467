// SPDX-License-Identifier: Zlib
/// @file PlyGuard.cpp
/// See PlyGuard.hpp. Only what assimp trips on is checked; everything else is its reader's job.

#include "mesh/PlyGuard.hpp"
#include "mesh/TextCase.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <limits>
#include <sstream>
#include <vector>

namespace hydrotex::detail {
namespace {

bool isBlank(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }


/// Bytes of one binary value of a PLY type name (0: not a type).
std::size_t typeBytes(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" || type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

struct PlyProperty {
  bool list = false;
  std::size_t bytes = 1;       ///< binary size of a scalar, or of a list's count
  std::size_t valueBytes = 0;  ///< binary size of a list's value
};
struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

/// Offset of the byte after the header's "end_header" line, as assimp finds it (the token at a
/// line start, then a blank or the end), or npos.
std::size_t headerEnd(std::string_view bytes) {
  constexpr std::string_view kEnd = "end_header";
  for (std::size_t at = bytes.find(kEnd); at != std::string_view::npos; at = bytes.find(kEnd, at + 1)) {
    std::size_t lineStart = at;
    while (lineStart > 0 && (bytes[lineStart - 1] == ' ' || bytes[lineStart - 1] == '\t')) --lineStart;
    const bool startsLine = lineStart == 0 || bytes[lineStart - 1] == '\n' || bytes[lineStart - 1] == '\r';
    const std::size_t after = at + kEnd.size();
    if (!startsLine || (after != bytes.size() && !isBlank(bytes[after]))) continue;
    const std::size_t newline = bytes.find('\n', after);
    return newline == std::string_view::npos ? bytes.size() : newline + 1;
  }
  return std::string_view::npos;
}

/// assimp's line ends (ParsingUtils' IsLineEnd) and value separators (IsSpace).
bool isLineEnd(char c) { return c == '\n' || c == '\r' || c == '\0' || c == '\f'; }
bool isSeparator(char c) { return c == ' ' || c == '\t'; }

/// An ASCII body's lines as assimp 5.2's IOStreamBuffer::getNextLine hands them to the PLY
/// reader, one element entry each: a line stops at any line end, and a line end where a line
/// would start is skipped up to and including the next '\n' ("\r\n" is one line end; so is
/// "\0 anything \n", whose bytes the reader never sees).
class Lines {
 public:
  explicit Lines(std::string_view text) : text_(text) {}
  std::optional<std::string_view> next() {
    if (at_ >= text_.size()) return std::nullopt;
    if (isLineEnd(text_[at_])) {
      while (at_ < text_.size() && text_[at_] != '\n') ++at_;
      if (++at_ >= text_.size()) return std::nullopt;
    }
    const std::size_t start = at_;
    while (at_ < text_.size() && !isLineEnd(text_[at_])) ++at_;
    const std::string_view line = text_.substr(start, at_ - start);
    ++at_;
    return line;
  }

 private:
  std::string_view text_;
  std::size_t at_ = 0;
};

/// The values of one line, in order, split where the reader splits them.
class Values {
 public:
  explicit Values(std::string_view line) : line_(line) {}
  std::optional<std::string_view> next() {
    while (at_ < line_.size() && isSeparator(line_[at_])) ++at_;
    if (at_ >= line_.size()) return std::nullopt;
    const std::size_t start = at_;
    while (at_ < line_.size() && !isSeparator(line_[at_])) ++at_;
    return line_.substr(start, at_ - start);
  }
  /// How many values the whole line holds.
  std::size_t total() const {
    Values all(line_);
    std::size_t count = 0;
    while (all.next()) ++count;
    return count;
  }

 private:
  std::string_view line_;
  std::size_t at_ = 0;
};

/// Whether a body token is one number as the PLY format writes it (an optional sign, digits, a
/// fraction or exponent). assimp's reader stops at the first character that is not part of a
/// number and goes on from there, so a token such as "3]0" splits differently for it than here.
bool isNumber(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  double value = 0.0;
  const auto [stop, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  return !token.empty() && stop == token.data() + token.size() &&
         (error == std::errc() || error == std::errc::result_out_of_range);
}

/// Binary bodies: every list's count, read as assimp reads it (as an unsigned number of the count
/// type's size), must fit in what is left of the body, for the reader allocates for it first.
std::optional<std::string> binaryListTrap(const std::vector<PlyElement>& elements, std::string_view body, bool bigEndian) {
  std::size_t at = 0;
  for (const PlyElement& element : elements) {
    for (std::uint64_t i = 0; i < element.count; ++i) {
      for (const PlyProperty& property : element.properties) {
        if (body.size() - at < property.bytes) return std::nullopt;  // truncated: assimp's reader says so
        if (!property.list) {
          at += property.bytes;
          continue;
        }
        std::uint64_t count = 0;
        for (std::size_t b = 0; b < property.bytes; ++b) {
          const auto byte = static_cast<unsigned char>(body[at + (bigEndian ? b : property.bytes - 1 - b)]);
          count = (count << 8) | byte;
        }
        at += property.bytes;
        if (count > (body.size() - at) / property.valueBytes)
          return "PLY element '" + element.name + "' entry " + std::to_string(i) + " declares a list of " +
                 std::to_string(count) + " values, more than the file holds";
        at += static_cast<std::size_t>(count) * property.valueBytes;
      }
    }
  }
  return std::nullopt;
}

}  // namespace

bool isPly(std::string_view head) {
  const std::size_t start = head.find_first_not_of(" \t\r\n");
  return start != std::string_view::npos && head.size() - start >= 3 && lowered(head.substr(start, 3)) == "ply";
}

std::optional<std::string> plyTrap(std::string_view bytes, std::size_t fileSize) {
  if (!isPly(bytes)) return std::nullopt;
  const std::size_t end = headerEnd(bytes);
  if (end == std::string_view::npos)
    return std::string("PLY header has no end_header line");

  // The header must be what the format allows, line by line: assimp's reader is lenient with
  // anything else and may see other elements than a strict reading does (a garbled "element"
  // line let a list count of 3e33 through; fuzz_mesh), so nothing else is passed on to it.
  std::vector<PlyElement> elements;
  bool ascii = false, bigEndian = false, sawPly = false;
  std::istringstream header{std::string(bytes.substr(0, end))};
  std::size_t lineNumber = 0;
  for (std::string line; std::getline(header, line);) {
    ++lineNumber;
    std::istringstream words(lowered(line));
    auto refuse = [&](const std::string& what) {
      return "PLY header line " + std::to_string(lineNumber) + " ('" + line.substr(0, 48) + "') " + what;
    };
    auto word = [&] {
      std::string w;
      words >> w;
      return w;
    };
    auto ended = [&] {
      std::string rest;
      return !(words >> rest);
    };
    const std::string keyword = word();
    if (keyword.empty()) continue;
    if (!sawPly) {
      if (keyword != "ply" || !ended()) return refuse("is not 'ply'");
      sawPly = true;
    } else if (keyword == "comment" || keyword == "obj_info") {
      continue;
    } else if (keyword == "format") {
      const std::string format = word(), version = word();
      if ((format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian") || version.empty() ||
          !ended())
        return refuse("is not 'format ascii|binary_little_endian|binary_big_endian <version>'");
      ascii = format == "ascii";
      bigEndian = format == "binary_big_endian";
    } else if (keyword == "element") {
      PlyElement element;
      element.name = word();
      const std::string count = word();
      const auto [stop, error] = std::from_chars(count.data(), count.data() + count.size(), element.count);
      if (element.name.empty() || count.empty() || stop != count.data() + count.size() || !ended())
        return refuse("is not 'element <name> <count>'");
      if (error != std::errc()) element.count = std::numeric_limits<std::uint64_t>::max();  // refused below
      elements.push_back(element);
    } else if (keyword == "property") {
      if (elements.empty()) return refuse("comes before any element");
      PlyProperty property;
      const std::string type = word();
      if (type == "list") {
        property.list = true;
        const std::string countType = word(), valueType = word();
        property.bytes = typeBytes(countType);
        property.valueBytes = typeBytes(valueType);
        const bool integerCount = countType.find("float") == std::string::npos && countType != "double";
        if (property.bytes == 0 || !integerCount || property.valueBytes == 0 || word().empty() || !ended())
          return refuse("is not 'property list <integer type> <type> <name>'");
      } else {
        property.bytes = typeBytes(type);
        if (property.bytes == 0 || word().empty() || !ended()) return refuse("is not 'property <type> <name>'");
      }
      elements.back().properties.push_back(property);
    } else if (keyword != "end_header") {
      return refuse("is none of the lines a PLY header holds");
    }
  }

  // Each instance takes at least 2 bytes per property in ASCII (a digit and a blank), and its
  // scalars plus list counts in binary: a count beyond the body is not data, only an allocation.
  // An ASCII file's last value may lack its blank, hence one byte of grace.
  const std::uint64_t body = fileSize > end ? fileSize - end : 0;
  const std::uint64_t room = ascii ? body + 1 : body;
  for (const PlyElement& element : elements) {
    // An entry without properties still costs the reader an instance (and an ASCII file a line):
    // one byte each at least, or a binary walk over 2^64 empty entries would never end.
    std::uint64_t instanceBytes = element.properties.empty() ? 1 : 0;
    for (const PlyProperty& property : element.properties) instanceBytes += ascii ? 2 : property.bytes;
    if (element.count > room / instanceBytes)
      return "PLY element '" + element.name + "' declares " + std::to_string(element.count) +
             " entries, more than the file's " + std::to_string(body) + " bytes of data hold";
  }
  if (bytes.size() < fileSize) return std::nullopt;
  if (!ascii) return binaryListTrap(elements, bytes.substr(end), bigEndian);

  // ASCII: assimp's reader takes one entry per line and reads a list's count before its values,
  // allocating for the count first. Where a line holds fewer values than its properties take, it
  // stops that entry early, and where a value is no number its parser stops inside it: either way
  // a later value is taken for a count (11 GB for one list; both found by fuzz_mesh). So every
  // entry must be one line holding exactly the numbers its properties take, each list count a
  // whole number within what the file holds.
  Lines lines(bytes.substr(end));
  for (const PlyElement& element : elements) {
    for (std::uint64_t i = 0; i < element.count; ++i) {
      const std::string entry = "PLY element '" + element.name + "' entry " + std::to_string(i);
      const std::optional<std::string_view> line = lines.next();
      if (!line)
        return "PLY element '" + element.name + "' has " + std::to_string(i) + " of its " +
               std::to_string(element.count) + " entries: the file ends first";
      Values values(*line);
      auto tooFew = [&] {
        return entry + " has " + std::to_string(values.total()) + " values on its line, fewer than its properties take";
      };
      auto notANumber = [&](std::string_view token, const char* what) {
        return entry + " holds '" + std::string(token.substr(0, 32)) + "' where " + what + " belongs";
      };
      for (const PlyProperty& property : element.properties) {
        const std::optional<std::string_view> token = values.next();
        if (!token) return tooFew();
        if (!property.list) {
          if (!isNumber(*token)) return notANumber(*token, "a number");
          continue;
        }
        std::uint64_t count = 0;
        const auto [stop, error] = std::from_chars(token->data(), token->data() + token->size(), count);
        const bool whole = stop == token->data() + token->size();
        if (!whole || (error != std::errc() && error != std::errc::result_out_of_range))
          return notANumber(*token, "a list count");
        if (error == std::errc::result_out_of_range || count > room / 2)
          return entry + " declares a list of " + std::string(token->substr(0, 32)) + " values, more than the file holds";
        for (std::uint64_t k = 0; k < count; ++k) {
          const std::optional<std::string_view> value = values.next();
          if (!value) return tooFew();
          if (!isNumber(*value)) return notANumber(*value, "a number");
        }
      }
      if (values.next())
        return entry + " has " + std::to_string(values.total()) + " values on its line, more than its properties take";
    }
  }
  return std::nullopt;
}

}  // namespace hydrotex::detail
