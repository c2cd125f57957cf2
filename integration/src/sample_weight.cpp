// Sample weights of the quality criterion: epsilon, or epsilon x the physics hold margin
// (docs/METHOD.md §4 "Sample weights").
#include "sample_weight.hpp"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"

namespace taskmap {

const char* toString(SampleWeight weight) {
  switch (weight) {
    case SampleWeight::kAuto:
      return "auto";
    case SampleWeight::kEpsilon:
      return "epsilon";
    case SampleWeight::kHoldMargin:
      return "hold_margin";
  }
  return "?";
}

SampleWeight sampleWeightFromString(const std::string& name) {
  if (name == "auto") return SampleWeight::kAuto;
  if (name == "epsilon") return SampleWeight::kEpsilon;
  if (name == "hold_margin") return SampleWeight::kHoldMargin;
  throw Error("sample weight '" + name + "' is unknown; use 'auto', 'epsilon' or 'hold_margin'");
}

namespace detail {
namespace {

/// A positive finite limit of the hold test from /validation params_json, else `fallback`.
double holdLimit(const nlohmann::json& params, const char* key, double fallback) {
  const auto it = params.find(key);
  if (it == params.end() || !it->is_number()) return fallback;
  const double v = it->get<double>();
  if (!(std::isfinite(v) && v > 0))
    throw Error(std::string("/validation params_json ") + key + " is not a finite value > 0");
  return v;
}

bool fullyValidated(const TaskMapData& map) {
  if (!map.validation) return false;
  const MapValidation& v = *map.validation;
  return v.hold.size() == map.grasps.size() && v.tested() == map.grasps.size();
}

}  // namespace

SampleWeight resolveSampleWeight(const TaskMapData& map, SampleWeight requested) {
  if (requested == SampleWeight::kAuto)
    return fullyValidated(map) ? SampleWeight::kHoldMargin : SampleWeight::kEpsilon;
  if (requested == SampleWeight::kHoldMargin && !fullyValidated(map)) {
    const std::size_t tested = map.validation ? map.validation->tested() : 0;
    throw Error(
        "sample weight 'hold_margin' needs physics hold labels for every grasp; the map "
        "has " +
        std::to_string(tested) + " of " + std::to_string(map.grasps.size()) +
        " tested: run `taskmap validate MAP` (all grasps) or use 'epsilon'");
  }
  return requested;
}

namespace {

/// A JSON object from text, or an empty one when the text is not one.
nlohmann::json objectOf(const std::string& text) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  return j.is_object() ? j : nlohmann::json::object();
}

/// The robust label's margins: 0 for a grasp that is not robust, else how much of the margin
/// its pushes left, min(1 - d_c / d_m, 1 - a_c / a_m), d_c and a_c measured from the closed
/// state over every variant.
std::vector<double> robustMargins(const MapValidation& v) {
  const nlohmann::json robust = objectOf(v.robust_json);
  const double d_max = holdLimit(robust, "margin_translation", 0.01);
  const double a_max = holdLimit(robust, "margin_rotation", 5.0 * M_PI / 180.0);
  std::vector<double> margin(v.robust.size(), 0.0);
  for (std::size_t i = 0; i < margin.size(); ++i) {
    if (v.robust[i] != 1) continue;
    const double d = std::max(0.0, v.push_translation[i]), a = std::max(0.0, v.push_rotation[i]);
    margin[i] = std::clamp(std::min(1.0 - d / d_max, 1.0 - a / a_max), 0.0, 1.0);
  }
  return margin;
}

}  // namespace

std::vector<double> holdMargins(const TaskMapData& map) {
  assert(fullyValidated(map));
  const MapValidation& v = *map.validation;
  if (!v.robust_json.empty() && v.robust.size() == v.hold.size() &&
      std::find(v.robust.begin(), v.robust.end(), MapValidation::kNotTested) == v.robust.end())
    return robustMargins(v);
  const nlohmann::json object = objectOf(v.params_json);
  // The protocol's defaults (validate/hold_test.hpp) for labels that do not record them.
  const double d_max = holdLimit(object, "max_translation", 0.05);
  const double a_max = holdLimit(object, "max_rotation", 15.0 * M_PI / 180.0);
  std::vector<double> margin(v.hold.size(), 0.0);
  for (std::size_t i = 0; i < margin.size(); ++i) {
    if (v.hold[i] != 1) continue;
    const double d = std::max(0.0, v.translation[i]), a = std::max(0.0, v.rotation[i]);
    margin[i] = std::clamp(std::min(1.0 - d / d_max, 1.0 - a / a_max), 0.0, 1.0);
  }
  return margin;
}

}  // namespace detail
}  // namespace taskmap
