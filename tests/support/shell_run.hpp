#pragma once
// Running a command line as a user would, for the command-line tests.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace taskmap::testing {

/// What a command did.
struct ShellRun {
  int code = -1;    ///< exit code; -1 when it did not exit normally (signal) or could not start
  std::string out;  ///< stdout and stderr, merged
};

/// Runs `command` through /bin/sh with stderr merged into stdout.
inline ShellRun runShell(const std::string& command) {
  ShellRun r;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buffer;
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    r.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace taskmap::testing
