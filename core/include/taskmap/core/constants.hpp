#pragma once
/// @file constants.hpp
/// Mathematical constants shared by every stage (one definition; C++17 has no std::numbers).

namespace taskmap {

/// π, radians in a half turn.
constexpr double kPi = 3.14159265358979323846;

}  // namespace taskmap
