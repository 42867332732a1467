// SPDX-License-Identifier: Zlib
#pragma once
// Running the `hydrotex` tool from a test as a user would: arguments on a shell line, stdout and
// stderr captured, the exit status decoded, a time limit so that a hang fails instead of blocking.
#include <string>

namespace hydrotex::test {

/// What one run of a program produced.
struct ToolRun {
  int exitCode = -1;      ///< exit status; 128 + signal number when killed by a signal
  bool timedOut = false;  ///< killed by the time limit (a hang)
  std::string out;        ///< everything written to stdout
  std::string err;        ///< everything written to stderr
};

/// Runs `program` with `arguments` (already shell-quoted where needed) under a time limit of
/// `timeoutSeconds` (s); stdout and stderr go to scratch files in the test output directory.
ToolRun runProgram(const std::string& program, const std::string& arguments, int timeoutSeconds = 600);

/// The whole content of a file (empty when it cannot be read).
std::string readFile(const std::string& path);

/// Writes `content` (bytes) to the scratch file `name` in the test output directory; its path.
std::string writeScratch(const std::string& name, const std::string& content);

/// Checks that a run failed cleanly: exactly one line on stderr that mentions `needle`, nothing
/// on stdout, a non-zero exit status that is not a signal (a crash) and not the time limit.
void requireCleanFailure(const ToolRun& run, const std::string& needle);

#ifdef HYDROTEX_TOOL_PATH
/// Runs the `hydrotex` tool (suites that define HYDROTEX_TOOL_PATH) with `arguments`.
inline ToolRun runTool(const std::string& arguments, int timeoutSeconds = 600) {
  return runProgram(HYDROTEX_TOOL_PATH, arguments, timeoutSeconds);
}
#endif

}  // namespace hydrotex::test
