// Work on unverified files in a child process with limits (isolated.hpp).
#include "isolated.hpp"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <iostream>
#include <new>

#include "taskmap/core/error.hpp"

namespace taskmap::cli {
namespace {

// Child: limits, body, the error message (if any) into the pipe; exit 0 on success.
[[noreturn]] void runChild(const std::function<void()>& body, const IsolationLimits& limits,
                           const std::string& what, int out_fd) {
  const auto cpu = static_cast<rlim_t>(limits.cpu_seconds);
  const rlimit cpu_limit{cpu, cpu + 1};
  const auto bytes = static_cast<rlim_t>(limits.memory_gib * 1024.0 * 1024.0 * 1024.0);
  const rlimit memory_limit{bytes, bytes};
  setrlimit(RLIMIT_CPU, &cpu_limit);
  setrlimit(RLIMIT_AS, &memory_limit);
  std::string message;
  try {
    body();
  } catch (const std::bad_alloc&) {
    message = what + ": needs more than " + std::to_string(limits.memory_gib) +
              " GiB of memory (damaged file?)";
  } catch (const std::exception& e) {
    message = e.what();
    if (message.empty()) message = what + ": failed";
  }
  std::cout.flush();
  std::cerr.flush();
  if (!message.empty() && ::write(out_fd, message.data(), message.size()) < 0) message.clear();
  ::_exit(message.empty() ? 0 : 1);
}

std::string describeStatus(const IsolationLimits& limits, const std::string& what, int status) {
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    if (sig == SIGXCPU || sig == SIGKILL)
      return what + ": took more than " + std::to_string(limits.cpu_seconds) +
             " s of CPU time (HDF5 hangs on some damaged files); nothing was written";
    return what + ": the reader crashed (signal " + std::to_string(sig) + ", " + strsignal(sig) +
           "): the file is damaged; nothing was written";
  }
  return what + ": failed (exit status " + std::to_string(WEXITSTATUS(status)) + ")";
}

}  // namespace

void runIsolated(const std::function<void()>& body, const IsolationLimits& limits,
                 const std::string& what) {
  int fds[2];
  if (::pipe(fds) != 0) throw Error(what + ": cannot create a pipe: " + strerror(errno));
  std::cout.flush();
  std::cerr.flush();
  const pid_t pid = ::fork();
  if (pid < 0) throw Error(what + ": cannot start a process: " + strerror(errno));
  if (pid == 0) {
    ::close(fds[0]);
    runChild(body, limits, what, fds[1]);
  }
  ::close(fds[1]);
  std::string message;
  char buffer[4096];
  for (ssize_t n; (n = ::read(fds[0], buffer, sizeof buffer)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    message.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!message.empty()) throw Error(message);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw Error(describeStatus(limits, what, status));
}

}  // namespace taskmap::cli
