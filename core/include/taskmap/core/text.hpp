#pragma once
/// @file text.hpp
/// Numbers in messages: one format for every stage's errors and warnings; printf into a string
/// for the reports the stages write.

#include <cstdio>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace taskmap {

/// `v` with three significant digits (printf "%.3g"), as messages print measured sizes,
/// tolerances and ratios: 0.0123, 1.5e+03.
inline std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

/// printf's output as a string, of any length (the arguments checked against the format by the
/// compiler).
std::string formatted(const char* format, ...) __attribute__((format(printf, 1, 2)));

/// The numbers of `text` separated by white space (a command-line value such as "0.1 0 0.3").
/// Throws Error naming `option` when a word is not a number, a value is not finite, or n >= 0
/// and the count is not n.
Eigen::VectorXd parseNumbers(const std::string& text, int n, const std::string& option);

/// A pose from "x y z qw qx qy qz" (metres, a quaternion normalised by Pose::fromVector7).
/// Throws Error naming `option` and the expected form.
Eigen::Isometry3d parsePoseText(const std::string& text, const std::string& option);

/// A pose from "x y z yaw" (metres; yaw about +z, radians), e.g. an object standing on a table.
/// Throws Error naming `option` unless exactly 4 finite numbers are given.
Eigen::Isometry3d parseXyzYaw(const std::string& text, const std::string& option);

}  // namespace taskmap
