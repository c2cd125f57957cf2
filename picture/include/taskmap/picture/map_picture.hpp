#pragma once
/// @file map_picture.hpp
/// The picture of `taskmap inspect --png`: the object's silhouette in three orthographic
/// views with every grasp's palm position coloured by cluster, each cluster representative
/// with its approach direction and the outline of the hand posed by it, and a histogram of
/// epsilon per cluster (cairo).

#include <string>

#include "taskmap/hands/hand_model.hpp"
#include "taskmap/inspect/map_summary.hpp"
#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {

/// Size of the picture.
struct PictureOptions {
  int width = 1600;   ///< pixels, >= 800
  int height = 1100;  ///< pixels, >= 600
  /// Throws Error naming the option when a size is out of range.
  void validate() const;
};

/// True when the library was built with cairo (otherwise the picture functions throw).
bool pictureSupported();

/// Draws the map and writes a PNG atomically (temporary file beside path, then rename).
/// Approach direction: the palm frame's +z axis. With a hand (the map's: same actuated joints),
/// each representative also shows the hand's outline: every collision shape posed with the
/// stored pose and joint values, projected, as its convex outline in the cluster colour.
/// Throws Error naming the file when it cannot be written.
void writeMapPicture(const TaskMapData& map, const MapSummary& summary, const std::string& path,
                     const PictureOptions& options = {}, const HandModel* hand = nullptr);

/// The PNG bytes writeMapPicture writes (the same picture, drawn in memory). Throws Error
/// naming summary.path when cairo cannot draw it or the library has no cairo.
std::string mapPicturePng(const TaskMapData& map, const MapSummary& summary,
                          const PictureOptions& options = {}, const HandModel* hand = nullptr);

}  // namespace taskmap
