// The build parameters a map stores: one list of keys (visitParams) walked by a writer and by a
// reader, so a key is named once.
#include "taskmap/builder/build_params.hpp"

#include <array>
#include <type_traits>

#include <nlohmann/json.hpp>

#include "params_json.hpp"
#include "taskmap/core/error.hpp"
#include "trial_pool.hpp"

namespace taskmap {
namespace {

using nlohmann::json;

const char* toString(WrenchNorm n) {
  return n == WrenchNorm::kL1 ? "l1" : "linf";
}
const char* toString(GraspMode m) {
  return m == GraspMode::kFingertip ? "fingertip" : "palm";
}
const char* toString(HoldTestOptions::Integrator i) {
  return integratorName(i);
}

[[noreturn]] void wrongValue(const std::string& key, const std::string& what) {
  throw Error("the map's build parameter '" + key + "' " + what);
}

// JSON -> option value, by type; enums by their names.
template <class T>
void fromJson(const json& v, const std::string& key, T& out) {
  try {
    out = v.get<T>();
  } catch (const json::exception&) {
    wrongValue(key, "has the wrong type");
  }
}
std::string nameOf(const json& v, const std::string& key) {
  if (!v.is_string()) wrongValue(key, "has the wrong type");
  return v.get<std::string>();
}
/// An enum by its name through `parse` (which throws Error on an unknown name).
template <class E, class Parse>
void enumFromJson(const json& v, const std::string& key, const char* what, Parse parse, E& out) {
  try {
    out = parse(nameOf(v, key));
  } catch (const Error& e) {
    wrongValue(key, std::string("is not a ") + what + ": " + e.what());
  }
}
void fromJson(const json& v, const std::string& key, SamplerKind& out) {
  enumFromJson(v, key, "sampler", samplerKindFromString, out);
}
void fromJson(const json& v, const std::string& key, ContactModel& out) {
  enumFromJson(v, key, "contact model", contactModelFromString, out);
}
void fromJson(const json& v, const std::string& key, VolumeMode& out) {
  enumFromJson(v, key, "volume mode", volumeModeFromString, out);
}
void fromJson(const json& v, const std::string& key, Linkage& out) {
  enumFromJson(v, key, "linkage", linkageFromString, out);
}
void fromJson(const json& v, const std::string& key, HoldTestOptions::Integrator& out) {
  enumFromJson(v, key, "hold test integrator", integratorFromName, out);
}
void fromJson(const json& v, const std::string& key, WrenchNorm& out) {
  out = nameOf(v, key) == "linf" ? WrenchNorm::kLInf : WrenchNorm::kL1;
}
void fromJson(const json& v, const std::string& key, std::optional<GraspMode>& out) {
  const std::string name = nameOf(v, key);
  if (name != "palm" && name != "fingertip") wrongValue(key, "must be \"palm\" or \"fingertip\"");
  out = name == "fingertip" ? GraspMode::kFingertip : GraspMode::kPalm;
}
void fromJson(const json& v, const std::string& key, StoredGrasps& out) {
  bool all = false;
  fromJson(v, key, all);
  out = all ? StoredGrasps::kAllCompleted : StoredGrasps::kForceClosure;
}
void fromJson(const json& v, const std::string& key, Eigen::Vector3d& out) {
  std::array<double, 3> a{};
  fromJson(v, key, a);
  out = Eigen::Vector3d(a[0], a[1], a[2]);
}
template <class T>
void fromJson(const json& v, const std::string& key, std::optional<T>& out) {
  T value{};
  fromJson(v, key, value);
  out = value;
}

// Option value -> JSON.
template <class T>
json toJson(const T& v) {
  if constexpr (std::is_enum_v<T>)
    return toString(v);
  else
    return v;
}
inline json toJson(const std::optional<GraspMode>& m) {
  return toString(m.value_or(GraspMode::kPalm));
}
inline json toJson(StoredGrasps s) {  // "keep_invalid": a bool, as before the enum
  return s == StoredGrasps::kAllCompleted;
}
inline json toJson(const Eigen::Vector3d& a) {
  return {a.x(), a.y(), a.z()};
}

// Writes every visited field into j (an optional one only when set).
struct Writer {
  json& j;
  static constexpr bool kWriting = true;
  template <class T>
  void operator()(const char* key, const T& v) {
    j[key] = toJson(v);
  }
  template <class T>
  void operator()(const char* key, const std::optional<T>& v) {
    if (v) j[key] = toJson(*v);
  }
  void operator()(const char* key, const std::optional<GraspMode>& v) { j[key] = toJson(v); }
};

// Reads every visited field that j holds (and removes it from j: what is left is extra).
struct Reader {
  json& j;
  static constexpr bool kWriting = false;
  template <class T>
  void operator()(const char* key, T& v) {
    const auto it = j.find(key);
    if (it == j.end()) return;
    if (!it->is_null()) fromJson(*it, key, v);
    j.erase(it);
  }
};

constexpr const char* kHoldFilter = "hold_filter";
constexpr const char* kSqueezeBalance = "squeeze_balance";

// The hold filter's parameters: present only when it is on.
template <class Io, class P>
void visitHoldFilter(Io& io, P& p) {
  auto& h = p.options.hold_filter;
  if constexpr (Io::kWriting) {
    if (!h.enabled) return;
    io.j[kHoldFilter] = kSqueezeBalance;
  } else {
    const auto it = io.j.find(kHoldFilter);
    if (it == io.j.end()) return;
    if (!it->is_string() || it->template get<std::string>() != kSqueezeBalance)
      wrongValue(kHoldFilter, "must be \"squeeze_balance\"");
    io.j.erase(it);
    h.enabled = true;
  }
  io("hold_filter_kp_revolute", h.kp_revolute);
  io("hold_filter_kp_prismatic", h.kp_prismatic);
  io("hold_filter_jaw_force", h.jaw_force);
  io("hold_filter_revolute_gripper_force", h.revolute_gripper_force);
  io("hold_filter_squeeze_fraction", h.squeeze_fraction);
  io("hold_filter_friction", h.balance.friction);
  io("hold_filter_cone_edges", h.balance.cone_edges);
  io("hold_filter_squeeze_tolerance", h.balance.squeeze_tolerance);
  io("hold_filter_push_force", h.balance.push_force);
  io("hold_filter_push_tolerance", h.balance.push_tolerance);
  io("hold_filter_push_joint_weight", h.balance.push_joint_weight);
}

constexpr const char* kClosingCheck = "closing_check";

// The closing check's parameters: present only when it is on (default maps keep their bytes).
template <class Io, class P>
void visitClosingCheck(Io& io, P& p) {
  auto& c = p.options.closing_check;
  if constexpr (Io::kWriting) {
    if (c.mode == ClosingCheckMode::kOff) return;
    io.j[kClosingCheck] = toString(c.mode);
  } else {
    const auto it = io.j.find(kClosingCheck);
    if (it == io.j.end()) return;
    if (!it->is_string()) wrongValue(kClosingCheck, "must be \"closing\"");
    try {
      c.mode = closingCheckModeFromString(it->template get<std::string>());
    } catch (const Error&) {
      wrongValue(kClosingCheck, "must be \"closing\"");
    }
    io.j.erase(it);
  }
  io("closing_object_mass", c.object_mass);
  io("closing_friction", c.friction);
  io("closing_kp_revolute", c.kp_revolute);
  io("closing_damping_revolute", c.damping_revolute);
  io("closing_kp_prismatic", c.kp_prismatic);
  io("closing_damping_prismatic", c.damping_prismatic);
  io("closing_jaw_force", c.jaw_force);
  // Maps from before the key: revolute grippers were driven with kp_revolute.
  if constexpr (!Io::kWriting)
    if (!io.j.contains("closing_revolute_gripper_force")) c.revolute_gripper_force = false;
  io("closing_revolute_gripper_force", c.revolute_gripper_force);
  io("closing_link_density", c.link_density);
  io("closing_pregrasp_fraction", c.pregrasp_fraction);
  io("closing_squeeze_fraction", c.squeeze_fraction);
  io("closing_time", c.closing_time);
  io("closing_interpolation_stages", c.interpolation_stages);
  io("closing_timestep", c.timestep);
  io("closing_substeps", c.substeps);
  io("closing_solver_iterations", c.solver_iterations);
  io("closing_torsional_friction", c.torsional_friction);
  io("closing_warm_start_drives", c.warm_start_drives);
  io("closing_jaw_solver_iterations", c.jaws.solver_iterations);
  io("closing_jaw_torsional_friction", c.jaws.torsional_friction);
  io("closing_jaw_warm_start_drives", c.jaws.warm_start_drives);
  io("closing_contact_erp", c.contact_erp);
  io("closing_max_settle_steps", c.max_settle_steps);
  io("closing_settle_erp", c.settle_erp);
  io("closing_push_force", c.push_force);
  io("closing_push_duration", c.push_duration);
  io("closing_rest_speed", c.rest_speed);
  io("closing_rest_steps", c.rest_steps);
  io("closing_max_translation", c.max_translation);
  io("closing_max_rotation", c.max_rotation);
  io("closing_max_penetration", c.max_penetration);
  io("closing_object_max_pieces", c.object_max_pieces);
  io("closing_margin", c.margin);
  io("closing_push_order", c.push_order);
  io("closing_push_free_bound", c.push_free_bound);
  io("closing_push_bound_creep", c.push_bound_creep);
}

constexpr const char* kHoldTest = "hold_test";

// The build's physics hold test: present only when it is on (maps built without it, and before
// it existed, read as off); the protocol's own numbers are in /validation params_json.
template <class Io, class P>
void visitHoldTest(Io& io, P& p) {
  auto& o = p.options;
  if constexpr (Io::kWriting) {
    if (o.hold_test == BuildHoldTest::kOff) return;
    io.j[kHoldTest] = toString(o.hold_test);
  } else {
    const auto it = io.j.find(kHoldTest);
    if (it == io.j.end()) return;
    if (!it->is_string()) wrongValue(kHoldTest, "must be \"robust\" or \"nominal\"");
    try {
      o.hold_test = buildHoldTestFromString(it->template get<std::string>());
    } catch (const Error&) {
      wrongValue(kHoldTest, "must be \"robust\" or \"nominal\"");
    }
    io.j.erase(it);
  }
  // The integrator only when it is not the default (maps built with `implicit` keep their bytes).
  auto& integrator = o.hold_test_options.hold.integrator;
  if (!Io::kWriting || integrator != HoldTestOptions::Integrator::kImplicit)
    io("hold_integrator", integrator);
  if (o.hold_test != BuildHoldTest::kRobust) return;
  auto& r = o.hold_test_options;
  io("hold_palm_shift", r.palm_shift);
  io("hold_palm_turn", r.palm_turn);
  io("hold_friction", r.friction);
  io("hold_decomposition_faces", r.decomposition_faces);
  io("hold_decomposition_pieces", r.decomposition_pieces);
  io("hold_margin_translation", r.margin_translation);
  io("hold_margin_rotation", r.margin_rotation);
}

// The antipodal and enclosing samplers' parameters: present only for those samplers (maps of
// the other samplers stay the same bytes); the jaws' widths are written for the record (derived
// from the hand, read back as extra keys).
template <class Io, class S>
void visitSamplerExtras(Io& io, S& s) {
  const bool antipodal = s.kind == SamplerKind::kAntipodal || s.kind == SamplerKind::kAntipodalPalm;
  const bool palm_enclose = s.kind == SamplerKind::kPalmEnclose;
  if (!Io::kWriting || antipodal || s.kind == SamplerKind::kEnclose || palm_enclose)
    io("attempts", s.attempts);
  if (!Io::kWriting || palm_enclose) io("enclose_margin", s.enclose_margin);
  if (!Io::kWriting || antipodal) {
    io("antipodal_friction", s.friction);
    io("width_margin", s.width_margin);
  }
  if constexpr (Io::kWriting) {
    if (antipodal && s.jaws) {
      io.j["jaw_open_width"] = s.jaws->open_width;
      io.j["jaw_closed_width"] = s.jaws->closed_width;
      if (s.kind == SamplerKind::kAntipodalPalm) {
        io.j["jaw_palm_front"] = s.jaws->palm_front;
        io.j["place_palm"] = s.place_palm;
      }
    }
    if (palm_enclose && s.enclose) {
      io.j["enclose_span"] = s.enclose->span_max - s.enclose->span_min;
      io.j["enclose_probe_depth"] = s.enclose->probe_depth;
      io.j["enclose_min_depth"] = s.enclose->min_depth;
    }
  }
}

// Every stored key, once. P is BuildParams or const BuildParams.
template <class Io, class P>
void visitParams(Io& io, P& p) {
  auto& o = p.options;
  io("object", p.object.empty() ? std::optional<std::string>() : p.object);
  io("scale", p.scale);
  io("hand", p.hand.empty() ? std::optional<std::string>() : p.hand);
  io("sampler", o.sampler.kind);
  io("standoff_min", o.sampler.standoff_min);
  io("standoff_max", o.sampler.standoff_max);
  io("approach_axis", o.sampler.approach_axis);
  visitSamplerExtras(io, o.sampler);
  io("seed", o.seed);
  io("valid", o.valid_target);
  io("max_trials", o.max_trials);
  io("keep_invalid", o.stored);
  io("cluster", o.cluster);
  io("friction", o.quality.friction);
  io("cone_edges", o.quality.cone_edges);
  io("contact_model", o.quality.contact_model);
  io("torsional_friction", o.quality.torsional_friction);
  io("wrench_norm", o.quality.norm);
  io("volume", o.quality.volume);  // which stored grasps have /grasps/volume
  // Absent: every pressing contact (maps of earlier builds keep their params).
  if (!Io::kWriting || o.quality.contacts_per_link > 0)
    io("contacts_per_link", o.quality.contacts_per_link);
  // Written when on; absent (maps built without the test, and before it existed) reads 0: off.
  if constexpr (!Io::kWriting)
    if (io.j.find("min_squeeze_force") == io.j.end()) o.min_squeeze_force = 0.0;
  if (!Io::kWriting || o.min_squeeze_force > 0.0) io("min_squeeze_force", o.min_squeeze_force);
  visitHoldFilter(io, p);
  visitClosingCheck(io, p);
  visitHoldTest(io, p);
  auto& s = o.simulation;
  io("contact_tolerance", s.contact_tolerance);
  io("max_retraction", s.max_retraction);
  io("squeeze", s.squeeze);
  io("require_palm_contact", s.require_palm_contact);
  io("grasp_mode", s.grasp_mode);  // always written: the mode in force
  if (!Io::kWriting || s.grasp_mode == GraspMode::kFingertip) io("grasp_standoff", s.standoff);
  io("centre_coupled", s.centre_coupled);
  io("check_self_collision", s.check_self_collision);
  io("max_closing_steps", s.max_closing_steps);
  auto& c = o.clustering;
  io("cluster_method", c.method);  // requested; /clustering has the one used
  io("cluster_fallback_to_single", c.fallback_to_single);
  io("cluster_outlier_budget", c.outlier_budget);
  io("cluster_min_size_fraction", c.min_size_fraction);
  io("cluster_min_size", c.min_size);
  io("cluster_threshold", c.threshold);
  io("cluster_count", c.num_clusters);
}

// The reader's side of the inputs: object, scale and hand (the writer passes temporaries).
struct InputReader : Reader {
  BuildParams& p;
  using Reader::operator();
  void operator()(const char* key, const std::optional<std::string>&) {
    std::string& target = std::string(key) == "object" ? p.object : p.hand;
    Reader::operator()(key, target);
  }
};

json parseObject(const std::string& text) {
  try {
    json j = json::parse(text);
    if (j.is_object()) return j;
  } catch (const json::exception&) {
    // Not JSON (a hand-made map): no parameters recorded.
  }
  return json::object();
}

}  // namespace

std::string buildParamsJson(const BuildParams& params) {
  json j = parseObject(params.options.extra_params_json);
  Writer w{j};
  visitParams(w, params);
  return j.dump();
}

BuildParams buildParamsFromJson(const std::string& text) {
  json j = parseObject(text);
  BuildParams p;
  InputReader r{{j}, p};
  visitParams(r, p);
  p.options.extra_params_json = j.dump();
  return p;
}

namespace {

// The options as the build runs them with this hand: the sampler kind resolved (an unset kind is
// the hand's default), the antipodal and enclosing samplers' geometry, the grasp mode and the
// fingertip standoff.
BuildParams resolvedParams(const BuildOptions& options, const HandModel& hand) {
  BuildParams p;
  p.options = options;
  const SamplerKind kind = detail::samplerKindFor(options, hand);
  p.options.sampler.kind = kind;
  if (kind == SamplerKind::kAntipodal || kind == SamplerKind::kAntipodalPalm ||
      kind == SamplerKind::kPalmEnclose)
    p.options.sampler = detail::samplerOptionsFor(options, hand);
  p.options.sampler.approach_axis = hand.approachAxis();
  GraspSimOptions& s = p.options.simulation;
  if (!s.grasp_mode) s.grasp_mode = hand.graspMode();
  if (*s.grasp_mode == GraspMode::kFingertip)
    s.standoff = resolveStandoff(hand, options.simulation);
  return p;
}

}  // namespace

BuildParams buildParamsOf(const BuildOptions& options, const HandModel& hand) {
  // What a map of this build reads back.
  return buildParamsFromJson(buildParamsJson(resolvedParams(options, hand)));
}

namespace detail {

std::string paramsJson(const BuildOptions& o, const HandModel& hand) {
  return buildParamsJson(resolvedParams(o, hand));
}

}  // namespace detail
}  // namespace taskmap
