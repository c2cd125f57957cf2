#pragma once
/// @file build_knobs.hpp
/// The knobs of a build as its users name them, one definition for every front end: the
/// command line (`taskmap build --cone-edges 8`, `taskmap dataset`, `taskmap-mpi build`) and
/// Python (`taskmap.build(cone_edges=8)`, `taskmap.dataset`). Each knob has its name, help,
/// allowed values and range here; the front ends walk visitBuildKnobs to declare them, and
/// buildOptionsOf / holdValidationOf turn them into the library's options. A knob added here
/// appears in both front ends (tests/unit/builder/build_knobs_test.cpp, tests/python).

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "taskmap/builder/map_builder.hpp"
#include "taskmap/builder/map_file_build.hpp"
#include "taskmap/validate/hold_test.hpp"

namespace taskmap {

/// The knob values, named as the command line's options with '_' for '-'.
struct BuildKnobs {
  std::string sampler;  ///< initial poses (SamplerKind's names; "" = the hand's)
  /// stop after this many grasps that hold (force-closure grasps with hold_test "off")
  std::uint64_t valid = 1000;
  std::uint64_t trials = 200000;  ///< trial budget
  std::uint64_t seed = 1;         ///< run seed
  int threads = 0;                ///< worker threads, 0 = all cores
  double friction = 0.5;          ///< Coulomb friction coefficient mu
  int cone_edges = 8;             ///< friction-cone edges
  std::string volume = "never";   ///< which stored grasps get the wrench-space volume
  int contacts_per_link = 0;      ///< per-link contact reduction before the hull, 0 = none
  std::string grasp;              ///< "", "palm" or "fingertip" ("" = the hand sidecar's)
  double standoff = -1.0;         ///< fingertip standoff, metres; negative = the hand's
  bool allow_size = false;        ///< build an object whose size is implausible for the hand
  bool keep_invalid = false;      ///< store every completed trial, not only force closure
  bool no_cluster = false;        ///< do not cluster the grasps
  /// "robust" (default), "nominal" or "off" (BuildHoldTest): the physics hold test that decides
  /// which force-closure grasps are stored
  std::string hold_test = "robust";
  bool validate = false;      ///< hold_test "off": label the grasps with the physics hold test
  bool keep_holding = false;  ///< with validate: store only the grasps that hold
  bool hold_filter = false;   ///< refuse grasps the squeeze-balance filter finds unbalanced
  /// N: refuse grasps whose squeeze presses no contact this hard (0: off)
  double min_squeeze_force = kDefaultMinSqueezeForce;
  /// the hold test's integrator: "implicit" (default) or "implicitfast" (HoldTestOptions)
  std::string integrator = "implicit";
  /// "off", "closing", "pushes" (ClosingCheckMode) or "pushes_early" (earlyVerdict settings)
  std::string closing_check = "off";
  bool timestamp = false;  ///< store the current time as created_utc
};

/// How a front end checks a numeric knob before the library does (the command line's
/// validators; Python raises the same condition as taskmap.Error).
enum class KnobCheck {
  kNone,
  kPositive,     ///< > 0
  kNonNegative,  ///< >= 0
  kRange,        ///< within [min, max]
};

/// Description of one knob.
struct KnobInfo {
  /// The fields in order; the trailing ones have their defaults.
  KnobInfo(const char* name_, const char* help_, std::vector<std::string> choices_ = {},
           KnobCheck check_ = KnobCheck::kNone, double min_ = 0.0, double max_ = 0.0,
           bool capture_default_ = true)
      : name(name_),
        help(help_),
        choices(std::move(choices_)),
        check(check_),
        min(min_),
        max(max_),
        capture_default(capture_default_) {}
  const char* name;                  ///< snake_case; the CLI option is "--" + name with '-'
  const char* help;                  ///< one paragraph for --help and the Python docstring
  std::vector<std::string> choices;  ///< allowed strings (empty: any)
  KnobCheck check;                   ///< the numeric check
  double min, max;                   ///< kRange bounds (inclusive)
  bool capture_default;              ///< the CLI shows the default in --help
};

/// How a knob is spelt in messages: on the command line ("--cone-edges") or in Python
/// ("cone_edges").
enum class KnobStyle { kCommandLine, kPython };

/// The knob's name as `style` spells it.
std::string knobName(const char* name, KnobStyle style);

/// Calls v(info, field) for every knob of `k` in the command line's order, field a reference
/// of the knob's type (std::string, std::uint64_t, int, double or bool). The one list of knobs.
template <class Visitor>
void visitBuildKnobs(BuildKnobs& k, Visitor&& v);

/// The library's BuildOptions of the knobs (sampler, counts, seed, threads, quality, stored
/// grasps, clustering on/off, hold filter, size check, grasp mode, standoff), validated. Throws
/// Error naming the knob as `style` spells it (a value outside its choices or range; a standoff
/// without fingertip grasps is refused later, by checkGraspOptions, when the hand is known).
BuildOptions buildOptionsOf(const BuildKnobs& knobs, KnobStyle style);

/// validate and keep_holding as the library's mode. Throws Error for keep_holding alone
/// ("--keep-holding needs --validate", spelt as `style`).
HoldValidation holdValidationOf(const BuildKnobs& knobs, KnobStyle style);

/// Throws Error when a knob's value is outside its choices or range, naming the knob as
/// `style` spells it, the value and what is allowed. A knob at its default value is never
/// refused (the defaults "" of grasp and -1 of standoff mean "the hand's").
void checkBuildKnobs(const BuildKnobs& knobs, KnobStyle style);

template <class Visitor>
void visitBuildKnobs(BuildKnobs& k, Visitor&& v) {
  using C = KnobCheck;
  v(KnobInfo{"sampler",
             "initial poses: volume (paper: point inside, uniform orientation), surface "
             "(approach along the inward normal of an area-weighted surface point, random roll "
             "and standoff; finds handles), mixed (even trials volume, odd surface), antipodal "
             "(parallel jaws: the pads on two surface points whose normals lie in each other's "
             "friction cones), enclose (palm on a surface point, no open finger inside the "
             "object), antipodal_palm (parallel jaws: an antipodal pair, the palm placed where "
             "it meets the surface behind it, no open finger inside the object), palm_enclose "
             "(multi-finger hands: the palm's front on a surface point, the fingers closing "
             "across the object's narrowest chord that fits them, no open finger inside). "
             "Default: antipodal_palm for parallel jaws; palm_enclose for a hand it can place "
             "on the object (multi-finger hands), else mixed",
             {"volume", "surface", "mixed", "antipodal", "enclose", "antipodal_palm",
              "palm_enclose"}},
    k.sampler);
  v(KnobInfo{"valid",
             "stop after this many grasps that hold (with --hold-test off: force-closure grasps)",
             {},
             C::kPositive},
    k.valid);
  v(KnobInfo{"trials", "trial budget", {}, C::kPositive}, k.trials);
  v(KnobInfo{"seed", "random seed"}, k.seed);
  v(KnobInfo{"threads", "worker threads (0 = all cores)", {}, C::kRange, 0, 1024}, k.threads);
  v(KnobInfo{"friction", "Coulomb friction coefficient mu", {}, C::kNonNegative}, k.friction);
  v(KnobInfo{"cone_edges", "friction cone edges", {}, C::kRange, 3, 64}, k.cone_edges);
  v(KnobInfo{"volume",
             "wrench-space volume of the stored grasps: never (force closure and epsilon only; "
             "the volume needs the whole 6-D hull, most of the quality time on fine meshes), "
             "force_closure (every stored grasp: the builds before issue 33), always",
             {"never", "force_closure", "always"}},
    k.volume);
  v(KnobInfo{"contacts_per_link",
             "reduce each link's contacts to at most this many representatives before the "
             "wrench hull (docs/METHOD.md 4; changes force-closure verdicts), 0 = all",
             {},
             C::kRange,
             0,
             64},
    k.contacts_per_link);
  v(KnobInfo{"grasp",
             "palm: the approach stops when the palm touches, the palm is pressed (power "
             "grasps); fingertip: it stops at the first contact or when the palm is --standoff "
             "from the object, no palm contact needed (pinch grasps). Default: the hand "
             "sidecar's grasp.mode (palm)",
             {"palm", "fingertip"},
             C::kNone,
             0,
             0,
             false},
    k.grasp);
  v(KnobInfo{"standoff",
             "fingertip grasps: palm-to-object distance where the approach stops, metres "
             "(default: the hand sidecar's grasp.standoff, else a tenth of the hand's "
             "palm-to-fingertip length, which keeps the palm off the object)",
             {},
             C::kRange,
             0.0,
             0.5,
             false},
    k.standoff);
  v(KnobInfo{"allow_size",
             "build an object whose size is implausible for the hand (over 20 times its "
             "reach, or thinner than its thinnest finger link), refused by default as a file "
             "in other units"},
    k.allow_size);
  v(KnobInfo{"keep_invalid",
             "store every simulated grasp (status ok), not only force-closure ones"},
    k.keep_invalid);
  v(KnobInfo{"no_cluster", "do not cluster the grasps"}, k.no_cluster);
  v(KnobInfo{"hold_test",
             "which force-closure grasps the map stores, tested in physics as they are found "
             "(MuJoCo, DexGraspBench's protocol; docs/VALIDATION.md): robust (default: grasps "
             "that hold at their pose and with the palm 1 mm and 2 deg off along and about each "
             "axis, friction 0.5 and a second decomposition of the object, each within 1 cm and "
             "5 deg under the pushes), nominal (grasps that hold under the protocol at their "
             "pose), off (every force-closure grasp, untested: the paper's map, fastest)",
             {"robust", "nominal", "off"}},
    k.hold_test);
  v(KnobInfo{"integrator",
             "how MuJoCo integrates the hold test: implicit (default; every map's labels so "
             "far) or implicitfast (DexGraspBench's, about 1.3x fewer CPU seconds per grasp; "
             "docs/VALIDATION.md, \"The integrator\")",
             integratorNames()},
    k.integrator);
  v(KnobInfo{"validate",
             "with --hold-test off: label every stored grasp with the physics hold test before "
             "writing (taskmap validate; docs/VALIDATION.md)"},
    k.validate);
  v(KnobInfo{"keep_holding",
             "with --hold-test off --validate: store only the grasps that hold in the physics "
             "test (the others are dropped before clustering)"},
    k.keep_holding);
  v(KnobInfo{"hold_filter",
             "store only grasps whose squeeze the hold filter finds balanced: the "
             "position-controlled hand presses the free object into equilibrium and resists 1 N "
             "pushes (docs/METHOD.md 4b; costs trials)"},
    k.hold_filter);
  v(KnobInfo{"min_squeeze_force",
             "N: store only grasps whose squeeze (the hold test's position servos driven 1.1 "
             "of the way from the preshape) presses some contact with at least this force; the "
             "default, 1 N / (2 x 0.6), lets friction on two opposing contacts resist the hold "
             "test's 1 N push (docs/METHOD.md 4e); 0: off",
             {},
             C::kNonNegative},
    k.min_squeeze_force);
  v(KnobInfo{"closing_check",
             "closing: store only force-closure grasps whose closing, simulated in Bullet with "
             "the object free to move (the hold test's drive, 0.1 kg, friction 0.6), leaves the "
             "object within 1 cm and 15 degrees; pushes: the same, then six 1 N pushes of 0.2 s "
             "(docs/METHOD.md 4d; costs CPU time per grasp); pushes_early: pushes with the early "
             "verdict (8 ms steps, short closing, pushes that end at rest or past the threshold: "
             "about 30x cheaper, fewer holding grasps pass; docs/VALIDATION.md)",
             {"off", "closing", "pushes", "pushes_early"}},
    k.closing_check);
  v(KnobInfo{"timestamp",
             "store the current time as created_utc (default: SOURCE_DATE_EPOCH if set, else "
             "none, so the same arguments give the same bytes)"},
    k.timestamp);
}

}  // namespace taskmap
