#pragma once
// The one way tests check taskmap::Error messages: a caller mistake or bad input must throw
// taskmap::Error whose message names the culprit and says what to do.
//   EXPECT_TRUE(throwsError([&] { o.validate(); }, {"friction", ">= 0"}));
//   EXPECT_NE(errorMessage([&] { load(path); }).find(path), std::string::npos);

#include <initializer_list>
#include <string>

#include <gtest/gtest.h>

#include "taskmap/core/error.hpp"

namespace taskmap::testing {

/// The message of the taskmap::Error that f() throws, or "" when f() returns normally (other
/// exception types propagate, so the test fails on them).
template <typename F>
std::string errorMessage(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

/// Success when f() throws a taskmap::Error whose message contains every fragment; otherwise a
/// failure that shows the message (or that nothing was thrown).
template <typename F>
::testing::AssertionResult throwsError(F&& f, std::initializer_list<std::string> fragments) {
  bool threw = false;
  std::string message;
  try {
    f();
  } catch (const Error& e) {
    threw = true;
    message = e.what();
  }
  if (!threw) return ::testing::AssertionFailure() << "no taskmap::Error was thrown";
  for (const std::string& fragment : fragments) {
    if (message.find(fragment) == std::string::npos)
      return ::testing::AssertionFailure()
             << "the message \"" << message << "\" does not contain \"" << fragment << "\"";
  }
  return ::testing::AssertionSuccess() << message;
}

}  // namespace taskmap::testing
