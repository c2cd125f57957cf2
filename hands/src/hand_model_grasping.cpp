// Sidecar keys of the grasping behaviour: "coupled" (closing joints that form one mechanism) and
// "grasp" (palm or fingertip grasps, standoff). Format in meshes/hands/README.md.
#include <cmath>
#include <set>

#include "hand_grasping_keys.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

using json = nlohmann::json;

/// Longest standoff accepted, metres (a hand reaching farther past its palm is no gripper).
constexpr double kMaxStandoff = 0.5;

// Index into h.closing() of the closing joint named by `v`.
int closingIndex(const HandModel& h, const json& v, const std::string& where) {
  if (!v.is_string()) throw Error(where + " must be a joint name");
  const std::string name = v.get<std::string>();
  const int j = h.jointIndex(name);
  for (std::size_t c = 0; c < h.closing().size(); ++c)
    if (j >= 0 && h.closing()[c].joint == j) return static_cast<int>(c);
  throw Error(where + " names joint '" + name +
              "', which is not listed in \"closing\" (only closing joints can be coupled)");
}

std::vector<std::vector<int>> readCoupled(const HandModel& h, const json& v, const std::string& S) {
  if (!v.is_array())
    throw Error(S + "coupled must be an array of joint-name arrays, e.g. [[\"j1\", \"j2\"]]");
  std::vector<std::vector<int>> groups;
  std::set<int> seen;
  for (std::size_t g = 0; g < v.size(); ++g) {
    const std::string where = S + "coupled[" + std::to_string(g) + "]";
    if (!v[g].is_array() || v[g].size() < 2)
      throw Error(where + " must be an array of at least two closing joint names");
    std::vector<int> group;
    for (std::size_t k = 0; k < v[g].size(); ++k) {
      const int c = closingIndex(h, v[g][k], where + "[" + std::to_string(k) + "]");
      if (!seen.insert(c).second)
        throw Error(where + " lists joint '" + v[g][k].get<std::string>() +
                    "' a second time (a joint belongs to one coupled group at most)");
      group.push_back(c);
    }
    groups.push_back(group);
  }
  return groups;
}

}  // namespace

void HandGraspingKeys::read(const json& js, const std::string& S, HandModel* h) {
  if (js.contains("coupled")) h->coupled_ = readCoupled(*h, js["coupled"], S);
  if (!js.contains("grasp")) return;
  const json& g = js["grasp"];
  if (!g.is_object())
    throw Error(S +
                "grasp must be an object such as {\"mode\": \"fingertip\", \"standoff\": 0.01}");
  for (auto it = g.begin(); it != g.end(); ++it)
    if (it.key() != "mode" && it.key() != "standoff")
      throw Error(S + "grasp: unknown key '" + it.key() + "' (allowed: mode, standoff)");
  if (g.contains("mode")) {
    const std::string mode = g["mode"].is_string() ? g["mode"].get<std::string>() : "";
    if (mode == "palm")
      h->grasp_mode_ = GraspMode::kPalm;
    else if (mode == "fingertip")
      h->grasp_mode_ = GraspMode::kFingertip;
    else
      throw Error(S + "grasp.mode must be \"palm\" or \"fingertip\"");
  }
  if (g.contains("standoff")) {
    if (!g["standoff"].is_number()) throw Error(S + "grasp.standoff must be a number (metres)");
    h->standoff_ = g["standoff"].get<double>();
    h->has_standoff_ = true;
    if (!(h->standoff_ >= 0.0 && h->standoff_ <= kMaxStandoff))
      throw Error(S + "grasp.standoff must be in [0, 0.5] metres, got " +
                  std::to_string(h->standoff_));
    if (h->grasp_mode_ != GraspMode::kFingertip)
      throw Error(S +
                  "grasp.standoff applies to fingertip grasps only: add \"mode\": \"fingertip\"");
  }
}

}  // namespace taskmap
