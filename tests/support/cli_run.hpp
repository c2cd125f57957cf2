#pragma once
// Runs the built `taskmap` tool for command-line tests (tests/cli): exit code and output.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace taskmap::testing {

/// Exit code and merged stdout + stderr of one run.
struct CliRun {
  int exit_code = -1;  ///< -1 when the tool did not exit normally
  std::string out;     ///< stdout and stderr, merged
};

/// Runs `<build>/bin/taskmap <args>` through the shell (args are shell words).
inline CliRun runTaskmap(const std::string& args) {
  const std::string command = std::string(TASKMAP_BINARY_DIR) + "/bin/taskmap " + args + " 2>&1";
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.out.append(buffer.data(), n);
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

}  // namespace taskmap::testing
