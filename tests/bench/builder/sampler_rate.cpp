// sampler_rate: stored grasps per CPU-second of a one-thread build, the previous sampler against
// the new one, in one process, per hand x object of the reference set (bundled hands, the
// Robotiq 2F-85 style test hand; bundled objects and the YCB banana of tests/data/real) and the
// real set (--real DIR, default $TASKMAP_REAL_DIR or ../shared/real: the Franka and Allegro
// hands; YCB banana, YCB mug, ACRONYM mug; the bundled barrett and humanoid on the two mugs; the
// Allegro on the bundled cylinder, box, basket and mug).
// Default build options otherwise (clustering off: it is
// not part of the trial CPU time). Parallel-jaw hands (jawGeometry) compare `mixed` with
// `antipodal`, other hands `mixed` with --multi (default `enclose`).
// Prints per pair: stored grasps per CPU-second old and new (the build's own CPU time: sampling
// + simulation + quality, summed over its worker thread), their ratio, trials per stored grasp,
// the share of each trial outcome, old -> new, and the share of the first --hold (60) stored grasps
// that hold in the physics test (validateMap, what `taskmap validate MAP --grasps 60` runs).
// Rates are medians over --rounds interleaved builds (old, new, old, new, ...).
// --jaw KIND (default antipodal) is the new sampler of the parallel-jaw hands; --extra DIR
// (default ../extra_real) adds issue 33's own pairs where their inputs exist there (the real
// Robotiq 2F-85 URDF and sidecar, YCB soup can, mustard bottle, cracker box, scissors).
// --closing-check KIND (off, closing, pushes, pushes_early: what `taskmap build --closing-check`
// takes; pushes_early_bound: pushes_early with ClosingCheckOptions::push_free_bound and
// push_bound_creep 2.5 cm/s) adds a third build per round, the new sampler with the closing
// check, and prints its stored grasps per CPU-second, its ratios to mixed and to the new sampler
// alone, its hold rate, the check's CPU per checked grasp and the share of checked grasps it
// passes; --trials N caps every build's trials (default: BuildOptions' 200000).
// --previous 1 adds a build per round with palm_enclose as it was before the minimum part depth
// (EncloseGeometry::min_depth 0: no test) and prints its rate, the new sampler's ratio to it,
// its trials per stored grasp, hold rate and outcome shares (palm_enclose pairs only).
// --only A|B|... runs the pairs whose "hand object" name contains any of the substrings.
//   sampler_rate [--real DIR] [--extra DIR] [--valid N] [--rounds R] [--only SUBSTRING]
//                [--multi KIND] [--jaw KIND] [--hold N] [--closing-check KIND] [--trials N]
//                [--previous 1]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "bench_only.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/validate/validate_map.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

struct Item {
  std::string name, path, sidecar;
  double scale = 1.0;
};

struct Run {
  double rate = 0.0;                       ///< stored grasps per CPU-second
  double simulation = 0.0, quality = 0.0;  ///< CPU seconds (sampling counted with simulation)
  double sampling = 0.0;                   ///< CPU seconds in Sampler::sample alone
  std::uint64_t trials = 0, stored = 0;
  std::map<std::string, std::uint64_t> outcomes;
  std::size_t tested = 0, holding = 0;  ///< physics hold test of the first --hold grasps
  std::uint64_t checks = 0;             ///< grasps the closing check ran on
  double check_seconds = 0.0;           ///< CPU seconds of the closing check
};

/// The closing check of `taskmap build --closing-check KIND` (off: none).
ClosingCheckOptions closingCheck(const std::string& kind) {
  if (kind == "pushes_early") return ClosingCheckOptions::earlyVerdict();
  if (kind == "pushes_early_bound") {  // the early verdict with the free-body bound (off in it)
    ClosingCheckOptions c = ClosingCheckOptions::earlyVerdict();
    c.push_free_bound = true;
    c.push_bound_creep = 0.025;  // the hold test's 5 cm over its 2 s push
    return c;
  }
  ClosingCheckOptions c;
  c.mode = closingCheckModeFromString(kind);
  return c;
}

Run build(const ObjectModel& object, const HandModel& hand, SamplerKind kind, std::uint64_t valid,
          std::size_t hold, const ClosingCheckOptions& check, std::uint64_t trials,
          bool previous = false) {
  BuildOptions o;
  if (previous) {
    // palm_enclose before the minimum part depth: the same geometry with the test off.
    o.sampler.enclose = encloseGeometry(hand);
    if (o.sampler.enclose) o.sampler.enclose->min_depth = 0.0;
  }
  o.threads = 1;
  o.valid_target = valid;
  o.cluster = false;
  o.sampler.kind = kind;
  o.closing_check = check;
  if (trials > 0) o.max_trials = trials;
  const BuildResult r = buildMap(object, hand, o);
  const BuildTiming& t = r.timing;
  const double cpu = t.sampling_seconds + t.simulation_seconds + t.quality_seconds;
  Run run;
  run.stored = r.map.grasps.size();
  run.trials = r.map.sampling.trials;
  run.rate = cpu > 0 ? static_cast<double>(run.stored) / cpu : 0.0;
  run.simulation = t.sampling_seconds + t.simulation_seconds;
  run.sampling = t.sampling_seconds;
  run.quality = t.quality_seconds;
  run.outcomes = r.map.sampling.outcomes;
  run.checks = t.closing_checks;
  run.check_seconds = t.closing_check_seconds;
  if (hold > 0 && run.stored > 0) {
    // What `taskmap validate MAP --grasps N --threads 1` computes.
    TaskMapData map = r.map;
    ValidateOptions v;
    v.threads = 1;
    v.grasps = hold;
    const ValidationSummary s = validateMap(&map, hand, v);
    run.tested = s.tested;
    run.holding = s.holding;
  }
  return run;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

std::string shares(const Run& a, const Run& b) {
  std::map<std::string, int> names;
  for (const auto& [n, c] : a.outcomes) names[n] = 1;
  for (const auto& [n, c] : b.outcomes) names[n] = 1;
  std::string out;
  for (const auto& [n, unused] : names) {
    const auto share = [&](const Run& r) {
      const auto it = r.outcomes.find(n);
      return r.trials && it != r.outcomes.end()
                 ? 100.0 * static_cast<double>(it->second) / static_cast<double>(r.trials)
                 : 0.0;
    };
    char s[96];
    std::snprintf(s, sizeof s, " %s %.1f->%.1f%%", n.c_str(), share(a), share(b));
    out += s;
  }
  return out;
}

/// Whether `name` contains one of the '|'-separated substrings of `only` (all when empty).
int benchMain(int argc, char** argv) {
  const char* env = std::getenv("TASKMAP_REAL_DIR");
  std::string real = env != nullptr ? env : std::string(TASKMAP_SOURCE_DIR) + "/../shared/real";
  std::uint64_t valid = 300;
  int rounds = 1;
  std::size_t hold = 60;
  std::string only, multi = "enclose", jaw = "antipodal", check_kind = "off";
  std::uint64_t trials = 0;
  bool previous = false;
  std::string extra = std::string(TASKMAP_SOURCE_DIR) + "/../extra_real";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--real")
      real = v;
    else if (a == "--valid")
      valid = std::stoull(v);
    else if (a == "--rounds")
      rounds = std::max(1, std::stoi(v));
    else if (a == "--only")
      only = v;
    else if (a == "--multi")
      multi = v;
    else if (a == "--hold")
      hold = std::stoull(v);
    else if (a == "--jaw")
      jaw = v;
    else if (a == "--extra")
      extra = v;
    else if (a == "--closing-check")
      check_kind = v;
    else if (a == "--trials")
      trials = std::stoull(v);
    else if (a == "--previous")
      previous = v != "0";
    else
      throw Error("unknown option " + a +
                  " (--real, --extra, --valid, --rounds, --only, --multi, --jaw, --hold, "
                  "--closing-check, --trials, --previous)");
  }
  const ClosingCheckOptions check = closingCheck(check_kind);
  const bool with_check = check.mode != ClosingCheckMode::kOff;
  const SamplerKind multi_kind = samplerKindFromString(multi);
  const SamplerKind jaw_kind = samplerKindFromString(jaw);
  const std::string src = TASKMAP_SOURCE_DIR;
  std::vector<std::pair<Item, std::vector<Item>>> sets;
  const std::vector<Item> reference_objects = {
      {"cylinder", src + "/meshes/objects/cylinder.obj", "", 1.0},
      {"box", src + "/meshes/objects/box.obj", "", 1.0},
      {"basket", src + "/meshes/objects/basket.obj", "", 1.0},
      {"mug", src + "/meshes/objects/mug.obj", "", 1.0},
      {"ycb_banana", src + "/tests/data/real/objects/ycb_011_banana.obj", "", 1.0}};
  for (const std::string h : {"panda", "barrett", "humanoid"})
    sets.push_back(
        {{h, src + "/meshes/hands/" + h + "/" + h + ".urdf", "", 1.0}, reference_objects});
  sets.push_back({{"robotiq_2f85_style",
                   src + "/tests/data/hands/robotiq_2f85_style/robotiq_2f85_style.urdf", "", 1.0},
                  reference_objects});
  const std::vector<Item> real_objects = {
      {"ycb_banana", real + "/objects/ycb_011_banana.obj", "", 1.0},
      {"ycb_mug", real + "/objects/ycb_025_mug.obj", "", 1.0},
      {"acronym_mug", real + "/objects/acronym_mug_10f6e09036350e92b3f21f1137c3c347.obj", "",
       0.0002682457830986903}};
  if (fs::exists(real)) {
    sets.push_back(
        {{"franka", real + "/hands/franka_hand/franka_hand.urdf", "", 1.0}, real_objects});
    sets.push_back(
        {{"allegro", real + "/hands/allegro_right/allegro_hand_description_right.urdf", "", 1.0},
         real_objects});
    // The Allegro on the reference objects but the YCB banana (in its real set above).
    sets.push_back(
        {{"allegro", real + "/hands/allegro_right/allegro_hand_description_right.urdf", "", 1.0},
         {reference_objects[0], reference_objects[1], reference_objects[2], reference_objects[3]}});
    // The bundled multi-finger hands on the real mugs (the YCB banana is in the reference set).
    for (const std::string h : {"barrett", "humanoid"})
      sets.push_back({{h, src + "/meshes/hands/" + h + "/" + h + ".urdf", "", 1.0},
                      {real_objects[1], real_objects[2]}});
  } else {
    std::printf("real set not found at %s: reference set only\n", real.c_str());
  }
  // Issue 33's own pairs where a copy of their inputs exists (see its README): the real Robotiq
  // 2F-85 URDF with its sidecar, YCB soup can, mustard bottle, cracker box, scissors.
  if (fs::exists(extra)) {
    const std::string o = extra + "/objects/ycb_";
    const std::vector<Item> extra_objects = {
        {"ycb_soup_can", o + "005_tomato_soup_can.obj", "", 1.0},
        {"ycb_mustard", o + "006_mustard_bottle.obj", "", 1.0},
        {"ycb_cracker_box", o + "003_cracker_box.obj", "", 1.0},
        {"ycb_scissors", o + "037_scissors.obj", "", 1.0}};
    sets.push_back({{"robotiq_2f85", extra + "/hands/robotiq_2f85/robotiq_arg2f_85.urdf", "", 1.0},
                    extra_objects});
    if (fs::exists(real)) {
      sets.push_back(
          {{"franka", real + "/hands/franka_hand/franka_hand.urdf", "", 1.0}, extra_objects});
      sets.push_back(
          {{"allegro", real + "/hands/allegro_right/allegro_hand_description_right.urdf", "", 1.0},
           extra_objects});
    }
    for (const std::string h : {"barrett", "humanoid"})
      sets.push_back({{h, src + "/meshes/hands/" + h + "/" + h + ".urdf", "", 1.0}, extra_objects});
  }
  std::printf("%-20s %-15s %-14s %10s %10s %7s %9s %9s %13s  outcomes old->new\n", "hand", "object",
              "new", "old g/s", "new g/s", "ratio", "old t/g", "new t/g", "hold old/new");
  for (const auto& [hi, objects] : sets) {
    const HandModel hand = HandModel::load(hi.path);
    const SamplerKind new_kind = jawGeometry(hand) ? jaw_kind : multi_kind;
    for (const Item& oi : objects) {
      if (!testing::selectedByOnly(only, hi.name + " " + oi.name)) continue;
      if (!fs::exists(oi.path)) continue;
      MeshLoadOptions lo;
      lo.scale = oi.scale;
      const ObjectModel object = ObjectModel::load(oi.path, lo);
      std::vector<double> old_rates, new_rates, check_rates, prev_rates;
      Run old_first, new_first, check_first, prev_first;
      const bool with_prev = previous && new_kind == SamplerKind::kPalmEnclose;
      const ClosingCheckOptions off;
      for (int r = 0; r < rounds; ++r) {
        // The hold test once (its labels do not depend on timing).
        const std::size_t h = r == 0 ? hold : 0;
        const Run old_run = build(object, hand, SamplerKind::kMixed, valid, h, off, trials);
        const Run new_run = build(object, hand, new_kind, valid, h, off, trials);
        if (r == 0) old_first = old_run, new_first = new_run;
        old_rates.push_back(old_run.rate);
        new_rates.push_back(new_run.rate);
        if (with_prev) {
          const Run prev_run = build(object, hand, new_kind, valid, h, off, trials, true);
          if (r == 0) prev_first = prev_run;
          prev_rates.push_back(prev_run.rate);
        }
        if (with_check) {
          const Run check_run = build(object, hand, new_kind, valid, h, check, trials);
          if (r == 0) check_first = check_run;
          check_rates.push_back(check_run.rate);
        }
      }
      const double o = median(old_rates), n = median(new_rates);
      const auto per = [](const Run& r) {
        return r.stored ? static_cast<double>(r.trials) / static_cast<double>(r.stored) : 0.0;
      };
      const auto pct = [](const Run& r) {
        return r.tested ? 100.0 * static_cast<double>(r.holding) / static_cast<double>(r.tested)
                        : 0.0;
      };
      char hold_text[64];
      std::snprintf(hold_text, sizeof hold_text, "%.0f%%/%.0f%% (%zu)", pct(old_first),
                    pct(new_first), std::min(old_first.tested, new_first.tested));
      const auto ms = [](const Run& r, double sec) {
        return r.stored ? 1e3 * sec / static_cast<double>(r.stored) : 0.0;
      };
      std::printf(
          "%-20s %-15s %-14s %10.1f %10.1f %6.2fx %9.1f %9.1f %13s  ms/grasp sim %.2f->%.2f "
          "(of it sampling %.2f->%.2f) quality %.2f->%.2f %s\n",
          hi.name.c_str(), oi.name.c_str(), toString(new_kind), o, n, o > 0 ? n / o : 0.0,
          per(old_first), per(new_first), hold_text, ms(old_first, old_first.simulation),
          ms(new_first, new_first.simulation), ms(old_first, old_first.sampling),
          ms(new_first, new_first.sampling), ms(old_first, old_first.quality),
          ms(new_first, new_first.quality), shares(old_first, new_first).c_str());
      if (with_prev) {
        const double p = median(prev_rates);
        std::printf(
            "%-20s %-15s previous palm_enclose: %.1f stored g/s (new %.2fx it, %.2fx mixed), "
            "%.1f trials per stored grasp, hold %.0f%% (%zu/%zu), sampling %.2f ms/grasp; "
            "outcomes previous->new%s\n",
            hi.name.c_str(), oi.name.c_str(), p, p > 0 ? n / p : 0.0, o > 0 ? p / o : 0.0,
            per(prev_first), pct(prev_first), prev_first.holding, prev_first.tested,
            ms(prev_first, prev_first.sampling), shares(prev_first, new_first).c_str());
      }
      if (with_check) {
        const double c = median(check_rates);
        const Run& k = check_first;
        std::printf(
            "%-20s %-15s %-14s with --closing-check %s: %.1f stored g/s (%.2fx mixed, %.2fx "
            "%s alone), %llu stored in %llu trials, hold %.0f%% (%zu/%zu), check %.2f ms/grasp "
            "CPU, passes %.0f%% of %llu checked\n",
            hi.name.c_str(), oi.name.c_str(), toString(new_kind), check_kind.c_str(), c,
            o > 0 ? c / o : 0.0, n > 0 ? c / n : 0.0, toString(new_kind),
            static_cast<unsigned long long>(k.stored), static_cast<unsigned long long>(k.trials),
            pct(k), k.holding, k.tested,
            k.checks ? 1e3 * k.check_seconds / static_cast<double>(k.checks) : 0.0,
            k.checks ? 100.0 * static_cast<double>(k.stored) / static_cast<double>(k.checks) : 0.0,
            static_cast<unsigned long long>(k.checks));
      }
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace
}  // namespace taskmap

int main(int argc, char** argv) {
  try {
    return taskmap::benchMain(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sampler_rate: %s\n", e.what());
    return 1;
  }
}
