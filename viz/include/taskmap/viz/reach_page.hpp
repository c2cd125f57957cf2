#pragma once
/// @file reach_page.hpp
/// `taskmap view reach.h5`: a reaching trajectory (mapstore/TRAJECTORY.md) as a self-contained
/// HTML page: robot, hand and scene primitives moving along the path with a time slider, the
/// object mesh, the chosen grasp's palm frame and the cost terms.

#include <string>

#include "taskmap/mapstore/trajectory_file.hpp"
#include "taskmap/viz/page_options.hpp"

namespace taskmap {

/// The page as a string; the body gets data-ready="1" once the first step is drawn.
std::string reachPageHtml(const TrajectoryRecord& record, const PageOptions& options = {});

/// Writes reachPageHtml atomically; throws Error naming the path.
void writeReachPage(const TrajectoryRecord& record, const std::string& path,
                    const PageOptions& options = {});

}  // namespace taskmap
