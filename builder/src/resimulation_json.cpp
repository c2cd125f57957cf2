// The re-simulated final grasp of `taskmap reach --map` as JSON (resimulate.hpp).
#include <vector>

#include <nlohmann/json.hpp>

#include "taskmap/builder/resimulate.hpp"

namespace taskmap {
namespace {

nlohmann::json poseJson(const Pose& p) {
  const Eigen::Matrix<double, 7, 1> v = p.toVector7();
  return std::vector<double>(v.data(), v.data() + 7);
}

}  // namespace

std::string resimulationJson(const Resimulation& r) {
  nlohmann::json j = {{"outcome", r.outcome},
                      {"message", r.message},
                      {"force_closure", r.force_closure},
                      {"epsilon", r.epsilon},
                      {"contacts", r.contacts},
                      {"fingers", r.fingers},
                      {"retraction_m", r.retraction_m},
                      {"start", poseJson(r.start)},
                      {"final", poseJson(r.final_pose)},
                      {"hand", r.hand_urdf}};
  if (r.hold) {
    const ResimulatedHold& h = *r.hold;
    j["hold"] = {
        {"holds", h.holds},
        {"status", h.status},
        {"max_translation_m", h.max_translation},
        {"max_rotation_rad", h.max_rotation},
        {"failed_direction", h.failed_direction.empty() ? nlohmann::json(nullptr)
                                                        : nlohmann::json(h.failed_direction)}};
  }
  return j.dump();
}

}  // namespace taskmap
