#pragma once
/// @file hand_picture.hpp
/// The picture of `taskmap hand-info --png`: the hand's collision shapes in its preshape and
/// fully closed, each in three orthographic views of the palm frame, with the palm frame axes
/// and the approach axis (cairo).

#include <string>

#include "taskmap/hands/hand_model.hpp"

namespace taskmap {

/// Draws the hand and writes a 1500 x 1000 PNG atomically (temporary file, then rename).
/// Throws Error naming the file when it cannot be written or the library has no cairo.
void writeHandPicture(const HandModel& hand, const std::string& path);

}  // namespace taskmap
