#pragma once
/// @file text.hpp
/// Numbers in messages: one format for every stage's errors and warnings.

#include <cstdio>
#include <string>

namespace taskmap {

/// `v` with three significant digits (printf "%.3g"), as messages print measured sizes,
/// tolerances and ratios: 0.0123, 1.5e+03.
inline std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace taskmap
