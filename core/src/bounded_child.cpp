// Untrusted files parsed in a child process with limits (bounded_child.hpp).
#include "taskmap/core/bounded_child.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include "taskmap/core/error.hpp"

#if defined(__SANITIZE_ADDRESS__)
#define TASKMAP_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TASKMAP_ASAN 1
#endif
#endif

#ifdef TASKMAP_ASAN
#include <sanitizer/asan_interface.h>
#include <sanitizer/common_interface_defs.h>
#endif

namespace taskmap {
namespace {

constexpr std::uint64_t kMiB = 1024 * 1024;

#ifndef TASKMAP_ASAN
// The calling process' address space in bytes (VmSize), 0 when unknown.
std::uint64_t memoryBaseline() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (f == nullptr) return 0;
  unsigned long long pages = 0;
  const int n = std::fscanf(f, "%llu", &pages);
  std::fclose(f);
  return n == 1 ? pages * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE)) : 0;
}
#else
// The calling process' private writable memory in bytes (VmData of /proc/self/status, which
// RLIMIT_DATA bounds), 0 when unknown. Under AddressSanitizer it includes the shadow memory
// reserved at start-up (terabytes), so that baseline + budget bounds what the child adds.
std::uint64_t memoryBaseline() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return 0;
  char line[256];
  unsigned long long kib = 0;
  while (std::fgets(line, sizeof line, f) != nullptr) {
    if (std::strncmp(line, "VmData:", 7) == 0) kib = std::strtoull(line + 7, nullptr, 10);
  }
  std::fclose(f);
  return kib * 1024;
}

// The child's pipe, for the sanitizer callbacks below.
int g_report_fd = -1;
bool g_reported = false;

// AddressSanitizer reports an allocation it cannot serve (RLIMIT_DATA reached) as an error
// and dies instead of throwing std::bad_alloc: tell the parent 'M' (memory) for those, 'C'
// (crash) for every other report.
void onSanitizerReport(const char* report) {
  const bool memory = std::strstr(report, "out of memory") != nullptr ||
                      std::strstr(report, "allocation-size-too-big") != nullptr ||
                      std::strstr(report, "exceeds maximum supported size") != nullptr;
  const char status = memory ? 'M' : 'C';
  if (!g_reported && ::write(g_report_fd, &status, 1) == 1) g_reported = true;
}

// The sanitizer dies without a report when its own allocator cannot map memory ("Failed to
// mmap"): under RLIMIT_DATA that is exhausted memory.
void onSanitizerDeath() {
  const char status = 'M';
  if (!g_reported && ::write(g_report_fd, &status, 1) == 1) g_reported = true;
}
#endif

void writeAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
}

[[noreturn]] void child(const std::function<std::string()>& work, const ParseBudget& budget,
                        std::uint64_t baseline, int fd) {
  const rlimit cpu{static_cast<rlim_t>(budget.cpu_seconds),
                   static_cast<rlim_t>(budget.cpu_seconds + 1)};
  setrlimit(RLIMIT_CPU, &cpu);
#ifndef TASKMAP_ASAN
  const rlimit memory{static_cast<rlim_t>(baseline + budget.memory_bytes),
                      static_cast<rlim_t>(baseline + budget.memory_bytes)};
  setrlimit(RLIMIT_AS, &memory);
#else
  // AddressSanitizer reserves terabytes of address space, so RLIMIT_AS cannot bound it; the
  // data limit counts private writable mappings (Linux >= 4.7), which every heap allocation
  // of the sanitizer's allocator is, and its shadow is already in the baseline.
  // Freed blocks stay mapped in the sanitizer's quarantine (256 MiB by default) and every
  // block carries redzones: the sanitized child gets twice the budget plus 512 MiB, which
  // still refuses what a hostile file asks for (gigabytes) with the budget's message.
  g_report_fd = fd;
  __asan_set_error_report_callback(onSanitizerReport);
  __sanitizer_set_death_callback(onSanitizerDeath);
  const rlim_t sanitized = static_cast<rlim_t>(baseline + 2 * budget.memory_bytes + 512 * kMiB);
  const rlimit data{sanitized, sanitized};
  setrlimit(RLIMIT_DATA, &data);
#endif
  const rlimit no_core{0, 0};
  setrlimit(RLIMIT_CORE, &no_core);
  char status = 'O';
  std::string out;
  try {
    out = work();
  } catch (const std::bad_alloc&) {
    status = 'M';
    out.clear();
  } catch (const std::exception& e) {
    status = 'E';
    out = e.what();
  } catch (...) {
    status = 'E';
    out = "unknown failure";
  }
  writeAll(fd, &status, 1);
  writeAll(fd, out.data(), out.size());
  ::close(fd);
  ::_exit(0);
}

std::string mib(std::uint64_t bytes) {
  return std::to_string((bytes + kMiB - 1) / kMiB) + " MiB";
}

}  // namespace

ParseBudget parseBudget(std::uint64_t file_bytes) {
  ParseBudget b{};
  b.memory_bytes = std::max<std::uint64_t>(
      256 * kMiB, file_bytes > (~std::uint64_t{0}) / 20 ? ~std::uint64_t{0} / 2 : 20 * file_bytes);
  b.cpu_seconds = static_cast<int>(std::min<std::uint64_t>(20 + file_bytes / kMiB, 3600));
  return b;
}

namespace {

// The parent's side: fork, read the child's status and result, name the limit it hit.
std::string runWithin(const std::function<std::string()>& work, const ParseBudget& budget,
                      const std::string& what, const std::string& limits) {
  const char* off = std::getenv("TASKMAP_NO_PARSE_CHILD");
  if (off != nullptr && std::strcmp(off, "1") == 0) return work();
  const std::uint64_t baseline = memoryBaseline();
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw Error(what + ": cannot create a pipe (" + std::strerror(errno) + ")");
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw Error(what + ": cannot start a process (" + std::strerror(errno) + ")");
  }
  if (pid == 0) {
    ::close(fds[0]);
    child(work, budget, baseline, fds[1]);
  }
  ::close(fds[1]);
  // Wall-time guard: a child blocked (not spending CPU) is killed too.
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::seconds(2 * budget.cpu_seconds + 10);
  std::string bytes;
  bool timed_out = false;
  char buffer[65536];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) {
      timed_out = true;
      ::kill(pid, SIGKILL);
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left, 1000)));
    if (ready < 0 && errno != EINTR) break;
    if (ready <= 0) continue;
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    bytes.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (timed_out)
    throw Error(what + ": the parser did not finish in " +
                std::to_string(2 * budget.cpu_seconds + 10) + " s; refused (" + limits + ")");
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    if (sig == SIGXCPU || sig == SIGKILL)
      throw Error(what + ": the parser took more than " + std::to_string(budget.cpu_seconds) +
                  " s of CPU; refused (" + limits + ")");
    throw Error(what + ": the parser crashed (signal " + std::to_string(sig) + ", " +
                strsignal(sig) + ") on this file, or ran out of memory; refused (" + limits + ")");
  }
  if (!bytes.empty() && bytes[0] == 'M' && !(WIFEXITED(status) && WEXITSTATUS(status) == 0))
    throw Error(what + ": needs more than " + mib(budget.memory_bytes) +
                " of memory to parse; refused (" + limits + ")");
  if (!bytes.empty() && bytes[0] == 'C' && !(WIFEXITED(status) && WEXITSTATUS(status) == 0))
    throw Error(what +
                ": the parser crashed on this file (AddressSanitizer's report is on "
                "stderr); refused (" +
                limits + ")");
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || bytes.empty())
    throw Error(what + ": the parser failed (exit status " +
                std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + "); refused");
  const char kind = bytes[0];
  bytes.erase(0, 1);
  if (kind == 'M')
    throw Error(what + ": needs more than " + mib(budget.memory_bytes) +
                " of memory to parse; refused (" + limits + ")");
  if (kind == 'E') throw Error(bytes);
  return bytes;
}

}  // namespace

std::string runBounded(const std::function<std::string()>& work, std::uint64_t file_bytes,
                       const std::string& what) {
  const ParseBudget budget = parseBudget(file_bytes);
  return runWithin(work, budget, what,
                   "the limits for a file of " + std::to_string(file_bytes) + " bytes are " +
                       mib(budget.memory_bytes) +
                       " of memory (max(256 MiB, "
                       "20 x its size)) and " +
                       std::to_string(budget.cpu_seconds) + " s of CPU");
}

std::string runBounded(const std::function<std::string()>& work, const ParseBudget& budget,
                       const std::string& what) {
  if (budget.memory_bytes == 0 || budget.cpu_seconds < 1)
    throw Error(what + ": the memory and CPU limits must be positive");
  return runWithin(work, budget, what,
                   "the limits are " + mib(budget.memory_bytes) + " of memory and " +
                       std::to_string(budget.cpu_seconds) + " s of CPU");
}

}  // namespace taskmap
