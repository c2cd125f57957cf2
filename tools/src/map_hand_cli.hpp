#pragma once
/// @file map_hand_cli.hpp
/// The map's hand as the commands take it (`inspect --png`, `export`, `view`): --hand is a URDF
/// or a bundled hand name; without it the map's own hand is looked for at its recorded path and
/// among the bundled hands (taskmap/inspect/map_hand.hpp).

#include <optional>
#include <string>

#include "taskmap/inspect/map_hand.hpp"

namespace taskmap::cli {

/// Where the commands look for a map's hand: `hand` (a URDF path or a bundled hand name; empty:
/// the map's own) and the bundled hands of dataDir() (none when there is no data directory).
MapHandOptions commandHandOptions(const std::string& hand);

/// findMapHand with `hand` (a URDF path or a bundled hand name; empty: the map's) and the
/// bundled hands of dataDir() (none when there is no data directory). Throws Error when an
/// explicit `hand` does not load.
MapHandResult findCommandMapHand(const TaskMapData& map, const std::string& hand);

/// The map's hand for `inspect --png` and `export`: prints "<who>: warning: <reason>; drawing no
/// hand" on stderr and returns nullopt when there is none.
std::optional<HandModel> mapHand(const TaskMapData& map, const std::string& hand,
                                 const std::string& who);

}  // namespace taskmap::cli
