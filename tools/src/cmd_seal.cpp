// taskmap seal: re-seal a task map on purpose (after an edit with h5py or another HDF5 tool,
// or a schema-1 map written before seals). HDF5 parses the unverified file here, so the work
// runs in a child process with CPU-time and memory limits: a file that crashes or hangs HDF5
// is refused instead of taking the tool down.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <iostream>
#include <memory>
#include <string>

#include "command.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/meshes/error.hpp"

namespace taskmap::cli {
namespace {

struct SealArgs {
  std::string map;
  int cpu_seconds = 120;
  double memory_gib = 8.0;
  bool quiet = false;
};

// Child: limits, sealMap, the error message (if any) into the pipe; exit 0 on success.
[[noreturn]] void sealInChild(const SealArgs& args, int out_fd) {
  const rlim_t cpu = static_cast<rlim_t>(args.cpu_seconds);
  const rlimit cpu_limit{cpu, cpu + 1};
  const auto bytes = static_cast<rlim_t>(args.memory_gib * 1024.0 * 1024.0 * 1024.0);
  const rlimit memory_limit{bytes, bytes};
  setrlimit(RLIMIT_CPU, &cpu_limit);
  setrlimit(RLIMIT_AS, &memory_limit);
  std::string message;
  try {
    sealMap(args.map);
  } catch (const std::bad_alloc&) {
    message = "cannot seal task map '" + args.map + "': validating it needs more than " +
              std::to_string(args.memory_gib) + " GiB (damaged file?)";
  } catch (const std::exception& e) {
    message = e.what();
  }
  if (!message.empty() && ::write(out_fd, message.data(), message.size()) < 0) message += "";
  ::_exit(message.empty() ? 0 : 1);
}

std::string describeStatus(const SealArgs& args, int status) {
  const std::string head = "cannot seal task map '" + args.map + "': ";
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    if (sig == SIGXCPU || sig == SIGKILL)
      return head + "validating it took more than " + std::to_string(args.cpu_seconds) +
             " s of CPU time (HDF5 hangs on some damaged files); the file is left unchanged";
    return head + "HDF5 crashed while reading it (signal " + std::to_string(sig) + ", " +
           strsignal(sig) + "): the file is damaged; it is left unchanged";
  }
  return head + "validation failed (exit status " + std::to_string(WEXITSTATUS(status)) + ")";
}

void runSeal(const SealArgs& args) {
  int fds[2];
  if (::pipe(fds) != 0) throw Error(std::string("seal: cannot create a pipe: ") + strerror(errno));
  std::cout.flush();
  std::cerr.flush();
  const pid_t pid = ::fork();
  if (pid < 0) throw Error(std::string("seal: cannot start a process: ") + strerror(errno));
  if (pid == 0) {
    ::close(fds[0]);
    sealInChild(args, fds[1]);
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
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) throw Error(describeStatus(args, status));
  if (!args.quiet) std::cout << "taskmap seal: sealed " << args.map << "\n";
}

const CommandRegistrar kRegistrar("seal", [](CLI::App& app) {
  auto args = std::make_shared<SealArgs>();
  CLI::App* cmd = app.add_subcommand(
      "seal",
      "Re-seal a task map on purpose. Every reader refuses a map whose content does not match "
      "the SHA-256 in its first 512 bytes (damaged, or edited with h5py or another HDF5 tool) "
      "and maps without a seal (written by other tools or before schema 2). If you trust the "
      "file, this validates it as a task map (in a separate process with CPU and memory "
      "limits) and rewrites it atomically with a fresh seal.");
  cmd->add_option("map", args->map, "task map (.h5), rewritten in place (atomically)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--cpu-seconds", args->cpu_seconds, "CPU-time limit of the validation")
      ->check(CLI::Range(1, 86400));
  cmd->add_option("--memory-gib", args->memory_gib, "address-space limit of the validation")
      ->check(CLI::Range(0.25, 1024.0));
  cmd->add_flag("-q,--quiet", args->quiet, "print nothing");
  cmd->callback([args]() { runSeal(*args); });
});

}  // namespace
}  // namespace taskmap::cli
