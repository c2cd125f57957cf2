// The URDF of a map's hand (recorded_hand.hpp).
#include "taskmap/mapstore/recorded_hand.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "map_seal.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

// A hand model (URDF or MJCF) is text of a few hundred kilobytes; anything this large is not the
// map's hand.
constexpr std::size_t kMaxUrdfBytes = std::size_t{64} << 20;

/// Does the regular file at path hold the map's hand (same SHA-256 of its bytes)?
bool matchesHand(const std::string& path, const std::string& sha256) {
  std::error_code ec;
  if (path.empty() || !std::filesystem::is_regular_file(path, ec)) return false;
  try {
    return seal::sha256Hex(seal::readWhole(path, kMaxUrdfBytes)) == sha256;
  } catch (const Error&) {
    return false;
  }
}

}  // namespace

std::string recordedHandPath(const TaskMapData& map) {
  const auto params = nlohmann::json::parse(map.sampling.params_json, nullptr, false);
  if (!params.is_object()) return "";
  const auto it = params.find("hand");
  return it != params.end() && it->is_string() ? it->get<std::string>() : "";
}

std::string findMapHandUrdf(const TaskMapData& map, const std::string& hands_dir) {
  const std::string recorded = recordedHandPath(map);
  if (matchesHand(recorded, map.hand.urdf_sha256)) return recorded;
  // A map built elsewhere (another checkout, the install tree): the bundled hand with that content.
  std::vector<std::string> candidates;
  std::error_code ec;
  if (!hands_dir.empty()) {
    for (const auto& entry : std::filesystem::directory_iterator(hands_dir, ec)) {
      const std::string name = entry.path().filename().string();
      candidates.push_back((entry.path() / (name + ".urdf")).string());
      candidates.push_back((entry.path() / (name + ".xml")).string());  // an MJCF hand
    }
  }
  std::sort(candidates.begin(), candidates.end());
  for (const std::string& urdf : candidates)
    if (matchesHand(urdf, map.hand.urdf_sha256)) return urdf;
  throw Error("the map's hand '" + map.hand.name + "' (URDF SHA-256 " +
              map.hand.urdf_sha256.substr(0, 12) + "...) is neither at the recorded path '" +
              recorded + "'" +
              (hands_dir.empty() ? std::string() : " nor a bundled hand under " + hands_dir));
}

std::string findMapHandUrdf(const TaskMapData& map) {
  std::string hands;
  try {
    hands = (std::filesystem::path(dataDir()) / "hands").string();
  } catch (const Error&) {
    // No data directory: only the path the build recorded is tried.
  }
  return findMapHandUrdf(map, hands);
}

}  // namespace taskmap
