#pragma once
// Runs a function in a forked child process with a wall-clock limit (and, outside sanitizer
// builds, an address-space limit), so a test can observe a crash, a hang or a memory blow-up
// as data instead of dying from it. The child's text reply and its peak resident memory come
// back through a pipe.

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <thread>

namespace taskmap::test {

/// What happened in the child.
struct ChildOutcome {
  enum class Kind { kReturned, kCrashed, kTimedOut, kFailed } kind = Kind::kFailed;
  std::string reply;            ///< the function's return value (kReturned)
  int signal = 0;               ///< terminating signal (kCrashed)
  long peak_rss_delta_kib = 0;  ///< growth of peak RSS during the call, KiB
};

/// Peak resident set size of this process, KiB.
inline long peakRssKib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

/// Current virtual memory size of this process, bytes (from /proc/self/statm).
inline unsigned long long virtualBytes() {
  std::ifstream statm("/proc/self/statm");
  unsigned long long pages = 0;
  statm >> pages;
  return pages * static_cast<unsigned long long>(sysconf(_SC_PAGESIZE));
}

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

/// Runs fn in a child. extra_address_space: bytes the child may map beyond what it has at the
/// fork (0: no limit; ignored under AddressSanitizer, which maps terabytes of shadow).
inline ChildOutcome runInChild(const std::function<std::string()>& fn, double seconds,
                               unsigned long long extra_address_space = 0) {
  int fds[2];
  ChildOutcome out;
  if (pipe(fds) != 0) return out;
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) return out;
  if (pid == 0) {
    close(fds[0]);
    if (extra_address_space > 0 && !kAddressSanitizer) {
      const rlim_t limit = static_cast<rlim_t>(virtualBytes() + extra_address_space);
      const rlimit as{limit, limit};
      setrlimit(RLIMIT_AS, &as);
    }
    const long before = peakRssKib();
    std::string reply;
    try {
      reply = fn();
    } catch (const std::exception& e) {
      reply = std::string("exception: ") + e.what();
    } catch (...) {
      reply = "exception: unknown";
    }
    const std::string delta = std::to_string(peakRssKib() - before) + "\n";
    const std::string message = delta + reply;
    ssize_t unused = write(fds[1], message.data(), message.size());
    (void)unused;
    _exit(0);
  }
  close(fds[1]);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  bool done = false;
  std::string raw;
  while (!done) {
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) {
      done = true;
    } else if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      close(fds[0]);
      out.kind = ChildOutcome::Kind::kTimedOut;
      return out;
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    // Drain the pipe as we go so a long reply never blocks the child.
    fd_set set;
    FD_ZERO(&set);
    FD_SET(fds[0], &set);
    timeval zero{0, 0};
    while (select(fds[0] + 1, &set, nullptr, nullptr, &zero) > 0) {
      char buffer[4096];
      const ssize_t n = read(fds[0], buffer, sizeof buffer);
      if (n <= 0) break;
      raw.append(buffer, static_cast<std::size_t>(n));
      FD_ZERO(&set);
      FD_SET(fds[0], &set);
    }
  }
  char buffer[4096];
  for (ssize_t n; (n = read(fds[0], buffer, sizeof buffer)) > 0;)
    raw.append(buffer, static_cast<std::size_t>(n));
  close(fds[0]);
  if (WIFSIGNALED(status)) {
    out.kind = ChildOutcome::Kind::kCrashed;
    out.signal = WTERMSIG(status);
    return out;
  }
  const auto newline = raw.find('\n');
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || newline == std::string::npos) {
    out.kind = ChildOutcome::Kind::kCrashed;  // exited without a reply (abort handler, ...)
    return out;
  }
  out.kind = ChildOutcome::Kind::kReturned;
  out.peak_rss_delta_kib = std::stol(raw.substr(0, newline));
  out.reply = raw.substr(newline + 1);
  return out;
}

}  // namespace taskmap::test
