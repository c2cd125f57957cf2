#pragma once
/// @file hand_page.hpp
/// `taskmap hand-info HAND --html`: the hand's collision shapes open (preshape) and closed,
/// the palm frame, the approach axis and one slider per actuated joint (self-contained HTML).

#include <string>

#include "taskmap/hands/hand_model.hpp"
#include "taskmap/viz/page_options.hpp"

namespace taskmap {

/// The page as a string; the body gets data-ready="1" once the hand is drawn.
std::string handPageHtml(const HandModel& hand, const PageOptions& options = {});

/// Writes handPageHtml atomically; throws Error naming the path.
void writeHandPage(const HandModel& hand, const std::string& path, const PageOptions& options = {});

}  // namespace taskmap
