// The build knobs' checks and their translation into BuildOptions (build_knobs.hpp).
#include "taskmap/builder/build_knobs.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "taskmap/core/error.hpp"
#include "taskmap/quality/grasp_quality.hpp"
#include "taskmap/sampler/sampler.hpp"

namespace taskmap {
namespace {

template <class T>
std::string valueText(const T& v) {
  std::ostringstream out;
  if constexpr (std::is_same_v<T, std::string>)
    out << '"' << v << '"';
  else if constexpr (std::is_same_v<T, bool>)
    out << (v ? "true" : "false");
  else
    out << v;
  return out.str();
}

/// Checks one knob against its description (see checkBuildKnobs).
struct Checker {
  KnobStyle style;
  const BuildKnobs& defaults;

  template <class T>
  void operator()(const KnobInfo& info, const T& value) const {
    // The same field of the defaults: the knobs are visited in the same order.
    if (isDefault(info, value)) return;
    const std::string name = knobName(info.name, style);
    if constexpr (std::is_same_v<T, std::string>) {
      if (info.choices.empty() ||
          std::find(info.choices.begin(), info.choices.end(), value) != info.choices.end())
        return;
      std::string allowed;
      for (const std::string& c : info.choices) allowed += (allowed.empty() ? "" : ", ") + c;
      throw Error(name + " must be one of " + allowed + " (got " + valueText(value) + ")");
    } else if constexpr (!std::is_same_v<T, bool>) {
      const double x = static_cast<double>(value);
      const bool ok = info.check == KnobCheck::kPositive      ? x > 0
                      : info.check == KnobCheck::kNonNegative ? x >= 0
                      : info.check == KnobCheck::kRange       ? x >= info.min && x <= info.max
                                                              : !std::isnan(x);
      if (ok) return;
      const std::string want =
          info.check == KnobCheck::kPositive      ? "positive"
          : info.check == KnobCheck::kNonNegative ? ">= 0"
          : info.check == KnobCheck::kRange
              ? "within [" + valueText(info.min) + ", " + valueText(info.max) + "]"
              : "a number";
      throw Error(name + " must be " + want + " (got " + valueText(value) + ")");
    }
  }

  template <class T>
  bool isDefault(const KnobInfo& info, const T& value) const {
    bool same = false;
    BuildKnobs d = defaults;
    visitBuildKnobs(d, [&](const KnobInfo& i, auto& field) {
      if constexpr (std::is_same_v<std::decay_t<decltype(field)>, T>)
        if (std::string(i.name) == info.name) same = field == value;
    });
    return same;
  }
};

}  // namespace

std::string knobName(const char* name, KnobStyle style) {
  std::string s = name;
  if (style == KnobStyle::kPython) return s;
  std::replace(s.begin(), s.end(), '_', '-');
  return "--" + s;
}

void checkBuildKnobs(const BuildKnobs& knobs, KnobStyle style) {
  const BuildKnobs defaults;
  BuildKnobs copy = knobs;
  const Checker check{style, defaults};
  visitBuildKnobs(copy, [&check](const KnobInfo& info, const auto& field) { check(info, field); });
}

BuildOptions buildOptionsOf(const BuildKnobs& k, KnobStyle style) {
  checkBuildKnobs(k, style);
  BuildOptions o;
  if (!k.sampler.empty()) o.sampler.kind = samplerKindFromString(k.sampler);
  o.valid_target = k.valid;
  o.max_trials = k.trials;
  o.seed = k.seed;
  o.threads = k.threads;
  o.quality.friction = k.friction;
  o.quality.cone_edges = k.cone_edges;
  o.quality.volume = volumeModeFromString(k.volume);
  o.quality.contacts_per_link = k.contacts_per_link;
  if (k.keep_invalid) o.stored = StoredGrasps::kAllCompleted;
  o.cluster = !k.no_cluster;
  o.hold_filter.enabled = k.hold_filter;
  o.min_squeeze_force = k.min_squeeze_force;
  if (k.closing_check == "pushes_early")
    o.closing_check = ClosingCheckOptions::earlyVerdict();
  else
    o.closing_check.mode = closingCheckModeFromString(k.closing_check);
  o.hold_test = buildHoldTestFromString(k.hold_test);
  o.hold_test_options.hold.integrator = integratorFromName(k.integrator);
  o.check_size = !k.allow_size;
  if (k.grasp == "palm") o.simulation.grasp_mode = GraspMode::kPalm;
  if (k.grasp == "fingertip") o.simulation.grasp_mode = GraspMode::kFingertip;
  o.simulation.standoff = k.standoff;
  return o;
}

HoldValidation holdValidationOf(const BuildKnobs& k, KnobStyle style) {
  if (k.keep_holding && !k.validate)
    throw Error(knobName("keep_holding", style) + " needs " + knobName("validate", style) +
                " (the hold labels decide what is kept)");
  if (k.validate && k.hold_test != "off")
    throw Error(knobName("validate", style) + " labels the grasps of a build without the hold " +
                "test; this build tests every grasp already (" + knobName("hold_test", style) +
                " " + k.hold_test + ") and stores its labels: leave " +
                knobName("validate", style) + " out, or add " + knobName("hold_test", style) +
                " off");
  if (!k.validate) return HoldValidation::kOff;
  return k.keep_holding ? HoldValidation::kKeepHolding : HoldValidation::kLabel;
}

}  // namespace taskmap
