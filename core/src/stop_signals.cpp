// SIGINT/SIGTERM -> a lock-free flag for a command's run (core/stop_signals.hpp).
#include "taskmap/core/stop_signals.hpp"

#include <csignal>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

std::atomic<bool> g_stop{false};
std::atomic<bool> g_installed{false};
struct sigaction g_old_int {};  // the handlers before the live instance (one at a time)
struct sigaction g_old_term {};
static_assert(std::atomic<bool>::is_always_lock_free, "a signal handler needs a lock-free flag");

extern "C" void onStopSignal(int sig) {
  g_stop.store(true);
  std::signal(sig, SIG_DFL);  // a second signal ends the process at once
}

}  // namespace

StopSignals::StopSignals() {
  if (g_installed.exchange(true))
    throw Error("StopSignals: another instance is installed; use one per run");
  g_stop.store(false);
  struct sigaction action {};
  action.sa_handler = onStopSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &g_old_int);
  sigaction(SIGTERM, &action, &g_old_term);
}

StopSignals::~StopSignals() {
  sigaction(SIGINT, &g_old_int, nullptr);
  sigaction(SIGTERM, &g_old_term, nullptr);
  g_installed.store(false);
}

const std::atomic<bool>* StopSignals::flag() {
  return &g_stop;
}

}  // namespace taskmap
