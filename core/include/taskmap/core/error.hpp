#pragma once
/// @file error.hpp
/// The one exception type of taskmap: caller mistakes and bad input.

#include <stdexcept>
#include <string>

namespace taskmap {

/// Thrown for caller mistakes and bad input (unreadable files, invalid options, corrupt maps).
/// The message names the file or option and says what to do; internal invariants use assert.
class Error : public std::runtime_error {
 public:
  /// @param message what went wrong and what to do about it.
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace taskmap
