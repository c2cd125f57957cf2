#pragma once
/// @file map_picture.hpp
/// The picture of `taskmap inspect --png`: the object's silhouette in three orthographic
/// views with every grasp's palm position coloured by cluster, each cluster representative
/// with its approach direction, and a histogram of epsilon per cluster (cairo).

#include <string>

#include "map_summary.hpp"
#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap::cli {

/// Size of the picture.
struct PictureOptions {
  int width = 1600;   ///< pixels, >= 800
  int height = 1100;  ///< pixels, >= 600
  /// Throws Error naming the option when a size is out of range.
  void validate() const;
};

/// True when the tool was built with cairo (otherwise writeMapPicture throws).
bool pictureSupported();

/// Draws the map and writes a PNG atomically (temporary file beside path, then rename).
/// Approach direction: the palm frame's +z axis (maps store no hand geometry).
/// Throws Error naming the file when it cannot be written.
void writeMapPicture(const TaskMapData& map, const MapSummary& summary, const std::string& path,
                     const PictureOptions& options = {});

}  // namespace taskmap::cli
