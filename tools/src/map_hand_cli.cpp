// The map's hand as the commands take it (map_hand_cli.hpp).
#include "map_hand_cli.hpp"

#include <filesystem>
#include <iostream>

#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap::cli {

MapHandOptions commandHandOptions(const std::string& hand) {
  MapHandOptions options;
  if (!hand.empty()) options.hand = std::filesystem::exists(hand) ? hand : bundledHandUrdf(hand);
  try {
    options.hands_dir = (std::filesystem::path(dataDir()) / "hands").string();
  } catch (const Error&) {
    // No data directory: only the path the build recorded is tried.
  }
  return options;
}

MapHandResult findCommandMapHand(const TaskMapData& map, const std::string& hand) {
  return findMapHand(map, commandHandOptions(hand));
}

std::optional<HandModel> mapHand(const TaskMapData& map, const std::string& hand,
                                 const std::string& who) {
  MapHandResult r = findCommandMapHand(map, hand);
  if (r.status == MapHandResult::Status::kLoaded) return std::move(r.hand);
  std::cerr << who << ": warning: " << r.message << "; drawing no hand"
            << (r.status == MapHandResult::Status::kNotFound ? " (give --hand)" : "") << "\n";
  return std::nullopt;
}

}  // namespace taskmap::cli
