// SPDX-License-Identifier: Zlib
#include "ToolRun.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "TestPaths.hpp"

namespace hydrotex::test {

std::string readFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

std::string writeScratch(const std::string& name, const std::string& content) {
  const std::string path = outputPath(name);
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

ToolRun runProgram(const std::string& program, const std::string& arguments, int timeoutSeconds) {
  // Suites run in parallel and share the output directory: the process id keeps names apart.
  static int counter = 0;
  const std::string base = outputPath("tool_run_" + std::to_string(::getpid()) + "_" + std::to_string(++counter));
  // coreutils timeout exits with 124 when the limit is hit (and kills with SIGKILL 5 s later).
  const std::string command = "timeout -k 5 " + std::to_string(timeoutSeconds) + " " + program + " " + arguments +
                              " >" + base + ".out 2>" + base + ".err";
  const int status = std::system(command.c_str());
  ToolRun run;
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  run.timedOut = run.exitCode == 124 || run.exitCode == 128 + 9;
  run.out = readFile(base + ".out");
  run.err = readFile(base + ".err");
  return run;
}

void requireCleanFailure(const ToolRun& run, const std::string& needle) {
  INFO("stderr: " << run.err);
  CHECK(run.exitCode != 0);
  CHECK(run.exitCode < 128);  // not killed by a signal
  CHECK(!run.timedOut);
  CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
  CHECK(run.err.find(needle) != std::string::npos);
  CHECK(run.out.empty());
}

}  // namespace hydrotex::test
