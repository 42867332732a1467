#pragma once
// Small pieces shared by the verbs: option helpers, JSON and text output, error reporting.

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>

#include "hydrotex/Expected.hpp"

namespace hydrotex::tool {

/// Adds an option that takes three comma-separated numbers ("1,2,3") into `target`.
CLI::Option* addVector3Option(CLI::App& app, const std::string& name, Eigen::Vector3d& target,
                              const std::string& description);

/// Adds `--resolution N` (texels per side, 16..4096).
CLI::Option* addResolutionOption(CLI::App& app, int& resolution);

/// Prints the error on one line to stderr, prefixed "hydrotex: ", and returns exit code 1.
int reportError(const Error& error);

/// A 3-vector as a JSON array.
nlohmann::json toJson(const Eigen::Vector3d& v);
/// A 3x3 matrix as a JSON array of three rows.
nlohmann::json toJson(const Eigen::Matrix3d& m);

/// Prints `object` as one JSON object on stdout (with --json), or the readable text otherwise.
void printResult(bool json, const nlohmann::json& object, const std::string& text);

/// Formats a vector as "(x, y, z)" with 6 significant digits for readable output.
std::string formatVector(const Eigen::Vector3d& v);

}  // namespace hydrotex::tool
