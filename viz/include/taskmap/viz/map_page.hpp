#pragma once
/// @file map_page.hpp
/// `taskmap view MAP.h5`: one self-contained HTML page (three.js inlined, data as JSON) showing
/// the object, every grasp's palm as a glyph coloured by cluster, cluster representatives
/// marked, and the hand's collision shapes posed with a grasp's pose and joint values for the
/// selection (or for the filtered grasps as ghosts); filters by cluster, epsilon and physics hold
/// label (map.validation, when the map has /grasps/hold), and each grasp's numbers, contacts
/// with normals and touching links. Opens offline.

#include <string>

#include "taskmap/hands/hand_model.hpp"
#include "taskmap/mapstore/task_map_data.hpp"
#include "taskmap/viz/page_options.hpp"

namespace taskmap {

/// What a map page shows besides the map itself.
struct MapPageInput {
  const TaskMapData* map = nullptr;  ///< the map (required)
  /// The map's hand (joint names must match the map's); nullptr draws palms only.
  const HandModel* hand = nullptr;
  std::string source;  ///< file name shown in the page ("" for none)
};

/// The page as a string. The body gets data-ready="N" (N grasps drawn) once drawn; errors go
/// to the console and to the element #tm-error. Throws Error on a hand whose joints differ
/// from the map's.
std::string mapPageHtml(const MapPageInput& input, const PageOptions& options = {});

/// Writes mapPageHtml atomically (temporary file, then rename); throws Error naming the path.
void writeMapPage(const MapPageInput& input, const std::string& path,
                  const PageOptions& options = {});

}  // namespace taskmap
