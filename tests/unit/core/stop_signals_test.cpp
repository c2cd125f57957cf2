// core/stop_signals.hpp: SIGINT and SIGTERM raise the flag while a StopSignals lives, one
// instance at a time, and the previous handlers come back.
#include "taskmap/core/stop_signals.hpp"

#include <csignal>

#include <gtest/gtest.h>

#include "error_matchers.hpp"

namespace taskmap {
namespace {

volatile std::sig_atomic_t g_previous_handler_ran = 0;

extern "C" void previousHandler(int) {
  g_previous_handler_ran = 1;
}

TEST(StopSignalsTest, SignalsRaiseTheFlagAndTheOldHandlersComeBack) {
  std::signal(SIGINT, previousHandler);
  {
    const StopSignals signals;
    EXPECT_FALSE(StopSignals::flag()->load());
    std::raise(SIGINT);
    EXPECT_TRUE(StopSignals::flag()->load());
    EXPECT_EQ(g_previous_handler_ran, 0);
  }
  {
    const StopSignals again;  // a new run starts unstopped
    EXPECT_FALSE(StopSignals::flag()->load());
    std::raise(SIGTERM);
    EXPECT_TRUE(StopSignals::flag()->load());
  }
  std::raise(SIGINT);  // restored: the handler installed before runs
  EXPECT_EQ(g_previous_handler_ran, 1);
  std::signal(SIGINT, SIG_DFL);
}

TEST(StopSignalsTest, OneInstanceAtATime) {
  const StopSignals signals;
  EXPECT_TRUE(testing::throwsError([] { const StopSignals second; }, {"another instance"}));
}

}  // namespace
}  // namespace taskmap
