#pragma once
// Runs the built `taskmap` tool for command-line tests: exit code and merged stdout + stderr.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace taskmap::testing {

struct CliRun {
  int code = -1;
  std::string out;  // stdout and stderr
};

/// Runs `<build>/bin/taskmap <args>` through the shell (args are not quoted here).
inline CliRun runTaskmap(const std::string& args) {
  const std::string cmd = std::string(TASKMAP_BINARY_DIR) + "/bin/taskmap " + args + " 2>&1";
  CliRun r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace taskmap::testing
