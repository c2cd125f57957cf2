#pragma once
/// @file map_export.hpp
/// A map file exported for other tools, as `taskmap export` and Python's `taskmap.export` do it:
/// ply or glb (the export scene of inspect/map_scene.hpp, with the map's hand when found) or
/// ACRONYM's HDF5 layout (mapstore/acronym.hpp, the gripper frame of acronymBaseToPalm).

#include <cstddef>
#include <optional>
#include <string>

#include "taskmap/inspect/map_hand.hpp"

namespace taskmap {

/// What to export and where. Lengths in metres.
struct MapExportOptions {
  std::string map;                    ///< task map file (.h5)
  std::string format;                 ///< "ply", "glb" or "acronym"
  std::string output;                 ///< file to write (atomically; never an input)
  double glyph_size = 0.0;            ///< ply/glb: hand glyph finger length, 0: automatic
  double density = 1000.0;            ///< acronym: object density, kg/m^3
  std::string object_file;            ///< acronym: object/file ("": <object name>.obj)
  std::optional<double> palm_offset;  ///< acronym: base-to-palm offset along the base z axis
  /// ply/glb: the hand to draw (URDF or bundled name; "": the map's, by its SHA-256 at the
  /// recorded path or among the bundled hands); acronym: the hand whose root-to-palm frames it
  std::string hand;
  bool force = false;                ///< replace an output that is not of the format
  std::string output_option = "-o";  ///< how the front end names the output, for messages
};

/// What exportMapFile wrote.
struct MapExportResult {
  std::size_t grasps = 0;           ///< grasps of the map
  std::size_t clusters = 0;         ///< clusters of the map (0 without clustering)
  std::size_t object_vertices = 0;  ///< vertices of the map's object
  /// ply/glb: the hand lookup (status kLoaded when drawn; else message says why not);
  /// acronym: kLoaded.
  MapHandResult::Status hand_status = MapHandResult::Status::kLoaded;
  std::string hand_message;  ///< why no hand was drawn ("" when drawn or acronym)
};

/// Writes options.output. Throws Error naming the file or option: an unknown format, a missing
/// map, an output that is an input or another kind of file (unless force), a glyph size out of
/// range, an explicit hand that does not load.
MapExportResult exportMapFile(const MapExportOptions& options);

}  // namespace taskmap
