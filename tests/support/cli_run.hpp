#pragma once
// Runs the built tools (or any command line) for command-line tests: exit code and merged
// stdout + stderr.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace taskmap::testing {

struct CliRun {
  int code = -1;
  std::string out;  // stdout and stderr
};

/// Runs `command` through /bin/sh with stderr merged into stdout.
inline CliRun runShell(const std::string& command) {
  CliRun r;
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;  // -1: killed by a signal
  return r;
}

/// Runs `<build>/bin/taskmap <args>` through the shell (args are not quoted here).
inline CliRun runTaskmap(const std::string& args) {
  return runShell(std::string(TASKMAP_BINARY_DIR) + "/bin/taskmap " + args);
}

}  // namespace taskmap::testing
