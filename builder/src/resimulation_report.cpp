// The re-simulated final grasp of `taskmap reach --map` as JSON and text (resimulate.hpp).
#include <vector>

#include <nlohmann/json.hpp>

#include "taskmap/builder/resimulate.hpp"
#include "taskmap/core/constants.hpp"
#include "taskmap/core/text.hpp"

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

std::string resimulationText(const Resimulation& r) {
  std::string text =
      formatted("re-simulated      %s, %s, epsilon %.4f, %d contacts (%zu fingers)\n",
                r.outcome.c_str(), r.force_closure ? "force closure" : "no force closure",
                r.epsilon, r.contacts, r.fingers.size());
  if (!r.hold) return text;
  const ResimulatedHold& h = *r.hold;
  return text + formatted("hold test         %s (object moved %.1f mm, turned %.1f deg%s%s)\n",
                          h.status.c_str(), 1000.0 * h.max_translation,
                          h.max_rotation * 180.0 / kPi, h.failed_direction.empty() ? "" : ", push ",
                          h.failed_direction.c_str());
}

}  // namespace taskmap
