// Latency of TaskMap::evaluate (nearest + proximity + quality with gradients) on a 1e5-sample
// map. evaluate searches its ball tree over the 7 float coordinates (p, 2 rho q) and filters
// the candidates by the exact 12-D embedding distance (ball_tree.hpp). Compared, with the same
// mixture kernel (the Gaussian in the embedding of criteria.hpp; baselines.hpp):
//   nanoflann(7-D): a nanoflann kd-tree over the same 7-D float points, the same 7-D radius
//     and -q search, the same exact 12-D filter; nanoflann(12-D): a nanoflann kd-tree over the
//     12-D embedding, radius r_c; brute: a scan of every sample.
// nearest/* times TaskMap::nearest (FLANN's 12-D index), the 12-D nanoflann tree and brute
// force; radius(cut-off)/* times TaskMap::radius at the cut-off (the ball tree's candidates
// filtered by the index's distance, then sorted). Per-call latencies give p50 / p99; the summary
// prints ratios against TaskMap measured in the same run. One thread (one core).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "baselines.hpp"
#include "synthetic_map.hpp"
#include "taskmap/integration/criteria.hpp"
#include "taskmap/integration/evaluation_session.hpp"
#include "taskmap/integration/task_map.hpp"

namespace taskmap {
namespace {

constexpr std::size_t kSamples = 100000;
constexpr std::size_t kQueries = 4096;
// The optimizer-trajectory query set (a separate set; the rows above keep theirs).
constexpr std::size_t kTrajectories = 256;
constexpr std::size_t kIterates = 25;

struct Fixture {
  TaskMap map = TaskMap::fromData(testing::syntheticMap(kSamples, 99));
  // Query set 0 ("mixed"): 90% within about two kernel widths per axis of a sample, 10% uniform
  // in the box (far from the map). Set 1 ("near"): one kernel width per axis, an optimizer's
  // iterate once it has reached the manifold. Entries [kQueries, 2 kQueries) hold set 1.
  std::vector<Pose> queries;
  // Trajectory set: kTrajectories x kIterates poses, trajectory t at [t kIterates, ...). Each
  // starts 3 kernel widths per axis (position and rotation) from a random map sample and
  // converges to it, x_{k+1} = x_k + 0.25 (target - x_k) (rotation: along the geodesic), plus
  // noise of 0.1 kernel width per axis: an optimizer's iterates (docs/METHOD.md §3).
  std::vector<Pose> trajectory;
  std::unique_ptr<bench::Baselines> baselines;  // over map, for queries

  Fixture() {
    Rng rng(5, 0);
    const double sp = *map.options().position_sigma;
    const double sr = *map.options().rotation_sigma;
    for (std::size_t i = 0; i < 2 * kQueries; ++i) {
      const bool near_set = i >= kQueries;
      const bool far = !near_set && i % 10 == 9;
      const double k = near_set ? 1.0 : 2.0;
      Pose x = far ? testing::randomPose(rng) : map.pose(rng.below(map.size()));
      if (!far) {
        x.position += k * sp * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
        x.orientation = Eigen::Quaterniond(
            rotationExp(k * sr * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal())) *
            x.orientation.toRotationMatrix());
      }
      queries.push_back(x);
    }
    Rng trng(6, 0);
    auto jitter = [&](Pose x, double k) {
      x.position += k * sp * Eigen::Vector3d(trng.normal(), trng.normal(), trng.normal());
      x.orientation = Eigen::Quaterniond(
          rotationExp(k * sr * Eigen::Vector3d(trng.normal(), trng.normal(), trng.normal())) *
          x.orientation.toRotationMatrix());
      return x;
    };
    for (std::size_t t = 0; t < kTrajectories; ++t) {
      const Pose target = map.pose(trng.below(map.size()));
      Pose x = jitter(target, 3.0);
      for (std::size_t k = 0; k < kIterates; ++k) {
        trajectory.push_back(x);
        Pose y;
        y.position = x.position + 0.25 * (target.position - x.position);
        const Eigen::Matrix3d r = x.orientation.toRotationMatrix();
        y.orientation = Eigen::Quaterniond(
            rotationExp(0.25 * rotationLog(target.orientation.toRotationMatrix() * r.transpose())) *
            r);
        x = jitter(y, 0.1);
      }
    }
    baselines = std::make_unique<bench::Baselines>(map, queries);
  }
};

Fixture& fx() {
  static Fixture f;
  return f;
}

struct Latency {
  double p50 = 0, p99 = 0;
};
std::map<std::string, Latency>& results() {
  static std::map<std::string, Latency> r;
  return r;
}

/// p50 / p99 of per-call latencies (ns, sorted here) as counters and into results()[key].
void record(benchmark::State& state, const std::string& key, std::vector<double>& ns) {
  std::sort(ns.begin(), ns.end());
  Latency l;
  l.p50 = ns[ns.size() / 2] / 1000.0;
  l.p99 = ns[std::min(ns.size() - 1, ns.size() * 99 / 100)] / 1000.0;
  state.counters["p50_us"] = l.p50;
  state.counters["p99_us"] = l.p99;
  results()[key] = l;
}

// Times f(query index) per call; each query is used `repeat` times in a row (1: every call
// goes to another part of the map, as in the query sets; more: warm caches).
template <typename F>
void timed(benchmark::State& state, std::string key, F&& f, std::size_t repeat = 1) {
  const std::size_t offset = state.range(0) == 1 ? kQueries : 0;
  key += state.range(0) == 1 ? "[near]" : "[mixed]";
  std::vector<double> ns;
  std::size_t i = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = f(offset + (i / repeat) % kQueries);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(r);
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
    ++i;
  }
  record(state, key, ns);
}

void BM_EvaluateTaskMap(benchmark::State& s) {
  Fixture& f = fx();
  std::size_t terms = 0, calls = 0;
  timed(s, "evaluate/taskmap", [&](std::size_t i) {
    Evaluation e = f.map.evaluate(f.queries[i]);
    terms += e.quality.terms;
    ++calls;
    return e.cost();
  });
  s.counters["terms"] = static_cast<double>(terms) / static_cast<double>(calls);
}
// Diagnostic, not a query set: each query 8 times in a row, as an optimizer's iterates near
// one pose would be, so the map's memory the query touches is in cache. The difference to
// the plain row is the cost of fetching that memory.
void BM_EvaluateTaskMapWarm(benchmark::State& s) {
  Fixture& f = fx();
  timed(
      s, "evaluate/taskmap(same query x8)",
      [&](std::size_t i) { return f.map.evaluate(f.queries[i]).cost(); }, 8);
}
// The same map with a looser truncation tolerance (fewer mixture terms, larger reported bound).
void BM_EvaluateTaskMapTol5e2(benchmark::State& s) {
  Fixture& f = fx();
  static const TaskMap loose = [] {
    TaskMapOptions o;
    o.quality_tolerance = 5e-2;
    return TaskMap::fromData(testing::syntheticMap(kSamples, 99), o);
  }();
  std::size_t terms = 0, calls = 0;
  timed(s, "evaluate/taskmap(tol=5e-2)", [&](std::size_t i) {
    Evaluation e = loose.evaluate(f.queries[i]);
    terms += e.quality.terms;
    ++calls;
    return e.cost();
  });
  s.counters["terms"] = static_cast<double>(terms) / static_cast<double>(calls);
}
void BM_EvaluateNanoflann(benchmark::State& s) {
  Fixture& f = fx();
  timed(s, "evaluate/nanoflann(12-D)",
        [&](std::size_t i) { return f.baselines->nanoflann12(i).cost(); });
}
void BM_EvaluateNanoflann7(benchmark::State& s) {
  Fixture& f = fx();
  timed(s, "evaluate/nanoflann(7-D)",
        [&](std::size_t i) { return f.baselines->nanoflann7(i).cost(); });
}
void BM_EvaluateBruteForce(benchmark::State& s) {
  Fixture& f = fx();
  timed(s, "evaluate/brute", [&](std::size_t i) { return f.baselines->brute(i).cost(); });
}
void BM_NearestTaskMap(benchmark::State& s) {
  Fixture& f = fx();
  timed(s, "nearest/taskmap", [&](std::size_t i) { return f.map.nearest(f.queries[i]).index; });
}
// TaskMap::radius at the quality cut-off (public API: the ball tree's search as in evaluate,
// plus sorting the hits and the output vector).
void BM_RadiusCutoffTaskMap(benchmark::State& s) {
  Fixture& f = fx();
  timed(s, "radius(cut-off)/taskmap",
        [&](std::size_t i) { return f.map.radius(f.queries[i], f.map.cutoffRadius()).size(); });
}
void BM_NearestNanoflann(benchmark::State& s) {
  Fixture& f = fx();
  timed(s, "nearest/nanoflann", [&](std::size_t i) { return f.baselines->nearestNanoflann(i); });
}
void BM_NearestBruteForce(benchmark::State& s) {
  Fixture& f = fx();
  timed(s, "nearest/brute", [&](std::size_t i) {
    double d2;
    return f.baselines->nearestBrute(i, &d2);
  });
}

// The trajectory set in trajectory order (3 passes).
// Margin sweep (1e5 samples, 256 x 25 iterates, medians of 3 runs, p50 / p99 in us,
// anchors per trajectory; evaluate on the same set 5.4 / 9.8):
//   margin 0: 6.1 / 10.5, 25;  0.25 r_c: 3.5 / 13.4, 6.7;  0.5 r_c: 3.7 / 19.1, 4.0;
//   1.0 r_c: 4.3 / 31.6, 2.4;  1.5 r_c: 4.6 / 47.8, 1.9.
// A cached call costs the mixture terms (the same batched exps as evaluate) plus a scan of the
// cached shells it can reach; a refill costs a radius search of r_c + margin and the copy, so
// p99 (refills) grows with the margin. 0.25 has the lowest p50 and p99 of the margins that
// reuse the cache; it is the default. evaluate:
// TaskMap::evaluate per iterate. session: one EvaluationSession per trajectory (constructed outside
// the timed call; its first call, which searches the index, is timed). Argument: margin in percent
// of the cut-off radius, -1 for the default.
std::map<std::string, SessionStats>& sessionStats() {
  static std::map<std::string, SessionStats> r;
  return r;
}
template <typename F>
void timedTrajectories(benchmark::State& state, const std::string& key, F&& f) {
  std::vector<double> ns;
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t q = i % (kTrajectories * kIterates);
    const double t = f(
        q, q % kIterates == 0, [&] { return std::chrono::steady_clock::now(); }, ns);
    benchmark::DoNotOptimize(t);
    ++i;
  }
  record(state, key, ns);
}
void BM_TrajectoryEvaluate(benchmark::State& s) {
  Fixture& f = fx();
  timedTrajectories(s, "trajectory/evaluate", [&](std::size_t q, bool, auto now, auto& ns) {
    const auto t0 = now();
    const Evaluation e = f.map.evaluate(f.trajectory[q]);
    const auto t1 = now();
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
    return e.cost();
  });
}
void BM_TrajectorySession(benchmark::State& s) {
  Fixture& f = fx();
  const bool by_default = s.range(0) < 0;
  const std::optional<double> margin =
      by_default
          ? std::nullopt
          : std::optional<double>(static_cast<double>(s.range(0)) / 100.0 * f.map.cutoffRadius());
  const std::string key =
      by_default ? std::string("trajectory/session(default margin)")
                 : "trajectory/session(margin " + std::to_string(s.range(0)) + "% r_c)";
  std::optional<EvaluationSession> session;
  SessionStats total;
  std::size_t cached = 0;
  auto collect = [&] {
    if (!session) return;
    total.calls += session->stats().calls;
    total.anchors += session->stats().anchors;
    total.fallbacks += session->stats().fallbacks;
  };
  timedTrajectories(s, key, [&](std::size_t q, bool first, auto now, auto& ns) {
    if (first) {
      collect();
      session.emplace(f.map, std::nullopt, margin);
    }
    const auto t0 = now();
    const Evaluation e = session->evaluate(f.trajectory[q]);
    const auto t1 = now();
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
    cached += session->cachedSamples();
    return e.cost();
  });
  collect();
  const double trajectories = static_cast<double>(total.calls) / kIterates;
  s.counters["anchors/traj"] = static_cast<double>(total.anchors) / trajectories;
  s.counters["fallbacks/traj"] = static_cast<double>(total.fallbacks) / trajectories;
  s.counters["cached"] = static_cast<double>(cached) / static_cast<double>(total.calls);
  sessionStats()[key] = total;
}

// Argument: 0 = mixed query set, 1 = near query set.
BENCHMARK(BM_EvaluateTaskMap)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_EvaluateTaskMapTol5e2)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_EvaluateTaskMapWarm)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_EvaluateNanoflann7)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_EvaluateNanoflann)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_EvaluateBruteForce)->Arg(0)->Iterations(200);
BENCHMARK(BM_NearestTaskMap)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_RadiusCutoffTaskMap)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_NearestNanoflann)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_NearestBruteForce)->Arg(0)->Iterations(500);
constexpr int kTrajectoryCalls = 3 * kTrajectories * kIterates;
BENCHMARK(BM_TrajectoryEvaluate)->Iterations(kTrajectoryCalls);
BENCHMARK(BM_TrajectorySession)->Arg(-1)->Iterations(kTrajectoryCalls);
// Margin sweep (percent of the cut-off radius), for EvaluationSession::kDefaultMarginFactor.
BENCHMARK(BM_TrajectorySession)
    ->Arg(0)
    ->Arg(25)
    ->Arg(50)
    ->Arg(100)
    ->Arg(150)
    ->Iterations(kTrajectoryCalls);

}  // namespace
}  // namespace taskmap

int main(int argc, char** argv) {
  using namespace taskmap;
  benchmark::Initialize(&argc, argv);
  Fixture& f = fx();
  // Exactness on the benchmark queries: the nearest in evaluate (TaskMap, both nanoflann) ==
  // brute force, the four evaluate implementations agree within TaskMap's reported bounds, and
  // TaskMap's exact mode equals the brute-force mixture (the same kernel).
  std::size_t mismatches = 0;
  double worst_rel = 0;
  for (std::size_t i = 0; i < 2 * kQueries; i += 16) {
    const Evaluation a = f.map.evaluate(f.queries[i]);
    const Evaluation b = f.baselines->nanoflann12(i);
    const Evaluation b7 = f.baselines->nanoflann7(i);
    const Evaluation c = f.baselines->brute(i);
    const QualityCriterion exact = f.map.quality(f.queries[i], std::nullopt, QualityMode::kExact);
    if (a.proximity.nearest.index != c.proximity.nearest.index) ++mismatches;
    if (b.proximity.nearest.index != c.proximity.nearest.index) ++mismatches;
    if (b7.proximity.nearest.index != c.proximity.nearest.index) ++mismatches;
    if (std::abs(a.proximity.value - c.proximity.value) > 1e-12 * c.proximity.value) ++mismatches;
    if (a.quality.value != 0)
      worst_rel = std::max(worst_rel,
                           std::abs(a.quality.value - c.quality.value) / std::abs(c.quality.value));
    const double tol = 1e-12 * std::abs(c.quality.value);
    for (const Evaluation* t : {&a, &b, &b7})
      if (std::abs(t->quality.value - c.quality.value) > a.quality.value_bound + tol ||
          (t->quality.gradient - c.quality.gradient).norm() >
              a.quality.gradient_bound + 1e-9 * c.quality.gradient.norm())
        ++mismatches;
    if (std::abs(exact.value - c.quality.value) > tol ||
        (exact.gradient - c.quality.gradient).norm() > 1e-9 * c.quality.gradient.norm())
      ++mismatches;
  }
  // Exactness of the session on the trajectory set: the same nearest sample and distance and
  // term count as evaluate, value within 1e-12 relative.
  std::size_t session_mismatches = 0;
  for (std::size_t t = 0; t < kTrajectories; ++t) {
    EvaluationSession session(f.map);
    for (std::size_t k = 0; k < kIterates; ++k) {
      const Pose& x = f.trajectory[t * kIterates + k];
      const Evaluation a = f.map.evaluate(x), b = session.evaluate(x);
      if (a.proximity.nearest.index != b.proximity.nearest.index ||
          a.proximity.nearest.distance != b.proximity.nearest.distance ||
          a.quality.terms != b.quality.terms ||
          std::abs(a.quality.value - b.quality.value) > 1e-12 * std::abs(a.quality.value))
        ++session_mismatches;
    }
  }
  mismatches += session_mismatches;
  std::printf("trajectory set: %zu x %zu iterates; session vs evaluate: %zu mismatches\n",
              kTrajectories, kIterates, session_mismatches);
  std::printf(
      "map: %zu samples, sigma_p %.4g m, sigma_r %.4g rad, cut-off %.4g m; exactness check on 512 "
      "queries: %zu mismatches, worst relative truncation error %.3g\n",
      f.map.size(), *f.map.options().position_sigma, *f.map.options().rotation_sigma,
      f.map.cutoffRadius(), mismatches, worst_rel);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  auto& r = results();
  auto ratio = [&](const char* a, const char* b) {
    if (!r.count(a) || !r.count(b)) return;
    std::printf("  %-38s p50 %8.3f us  p99 %8.3f us   p50 ratio vs %s: %.1fx\n", a, r[a].p50,
                r[a].p99, b, r[a].p50 / r[b].p50);
  };
  std::printf("summary (ratios > 1: slower than TaskMap):\n");
  for (const char* kind : {"evaluate", "nearest", "radius(cut-off)"}) {
    for (const char* set : {"[mixed]", "[near]"}) {
      const std::string base = std::string(kind) + "/taskmap" + set;
      for (const char* impl : {"/taskmap", "/taskmap(tol=5e-2)", "/taskmap(same query x8)",
                               "/nanoflann(7-D)", "/nanoflann(12-D)", "/nanoflann", "/brute"})
        ratio((std::string(kind) + impl + set).c_str(), base.c_str());
      if (std::string(kind) == "radius(cut-off)")  // FLANN's cut-off search against evaluate
        ratio((std::string(kind) + "/taskmap" + set).c_str(),
              (std::string("evaluate/taskmap") + set).c_str());
    }
    // Brute force is independent of the query set: also against the near-set TaskMap.
    ratio((std::string(kind) + "/brute[mixed]").c_str(),
          (std::string(kind) + "/taskmap[near]").c_str());
  }
  std::printf("trajectory set (%zu trajectories x %zu iterates, one session per trajectory):\n",
              kTrajectories, kIterates);
  for (const auto& [key, st] : sessionStats()) {
    if (!r.count(key)) continue;
    const double trajectories = static_cast<double>(st.calls) / kIterates;
    std::printf(
        "  %-40s p50 %7.3f us  p99 %7.3f us  anchors/traj %5.2f  fallbacks/traj %5.2f"
        "  p50 ratio evaluate/session %.2fx, p99 %.2fx\n",
        key.c_str(), r[key].p50, r[key].p99, static_cast<double>(st.anchors) / trajectories,
        static_cast<double>(st.fallbacks) / trajectories, r["trajectory/evaluate"].p50 / r[key].p50,
        r["trajectory/evaluate"].p99 / r[key].p99);
  }
  if (r.count("trajectory/evaluate"))
    std::printf("  %-40s p50 %7.3f us  p99 %7.3f us\n", "trajectory/evaluate",
                r["trajectory/evaluate"].p50, r["trajectory/evaluate"].p99);
  return mismatches == 0 ? 0 : 1;
}
