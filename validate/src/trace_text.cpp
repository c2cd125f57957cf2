// A traced hold test as JSON and as text (validate/validate_map.hpp traceJson, traceText).
#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "taskmap/core/constants.hpp"
#include "taskmap/validate/validate_map.hpp"

namespace taskmap {
namespace {

const std::string& linkName(const HandModel& hand, int link) {
  return hand.links()[static_cast<std::size_t>(link)].name;
}

constexpr double kDegrees = 180.0 / kPi;

}  // namespace

std::string traceJson(const HoldTrace& t, const HandModel& hand) {
  const Eigen::Vector3d a = hand.approachAxis();
  nlohmann::ordered_json j;
  const HoldResult& r = t.result;
  j["status"] = holdStatusName(r.status);
  j["holds"] = r.holds;
  j["max_translation"] = r.max_translation;
  j["max_rotation"] = r.max_rotation;
  j["failed_direction"] =
      r.failed_direction < 0
          ? nlohmann::ordered_json()
          : nlohmann::ordered_json(
                pushDirectionNames()[static_cast<std::size_t>(r.failed_direction)]);
  j["initial_penetration"] = r.initial_penetration;
  j["approach"] = {a.x(), a.y(), a.z()};
  nlohmann::ordered_json samples = nlohmann::ordered_json::array();
  for (const HoldTraceSample& s : t.samples) {
    nlohmann::ordered_json e;
    e["phase"] = s.phase;
    e["step"] = s.step;
    e["translation"] = s.translation;
    e["rotation"] = s.rotation;
    e["offset"] = {s.offset.x(), s.offset.y(), s.offset.z()};
    e["along_approach"] = s.offset.dot(a);
    nlohmann::ordered_json c = nlohmann::ordered_json::object();
    for (const HoldTraceContact& k : s.contacts) c[linkName(hand, k.link)] = k.force;
    e["contacts"] = c;
    samples.push_back(e);
  }
  j["samples"] = samples;
  return j.dump();
}

std::string traceText(const HoldTrace& t, const HandModel& hand) {
  const Eigen::Vector3d a = hand.approachAxis();
  std::ostringstream os;
  os << "phase     step   moved mm  along approach mm  turned deg  links pressing (N)\n";
  char line[160];
  for (const HoldTraceSample& s : t.samples) {
    std::snprintf(line, sizeof line, "%-8s %5d %10.2f %18.2f %11.2f ", s.phase.c_str(), s.step,
                  1e3 * s.translation, 1e3 * s.offset.dot(a), kDegrees * s.rotation);
    os << line;
    if (s.contacts.empty()) os << " none";
    for (const HoldTraceContact& k : s.contacts) {
      std::snprintf(line, sizeof line, " %s %.1f", linkName(hand, k.link).c_str(), k.force);
      os << line;
    }
    os << "\n";
  }
  const HoldResult& r = t.result;
  std::snprintf(line, sizeof line, "%s: moved up to %.1f mm, turned up to %.1f deg",
                holdStatusName(r.status), 1e3 * r.max_translation, kDegrees * r.max_rotation);
  os << line;
  if (r.failed_direction >= 0)
    os << ", failed under the "
       << pushDirectionNames()[static_cast<std::size_t>(r.failed_direction)] << " push";
  os << "\n";
  return os.str();
}

}  // namespace taskmap
