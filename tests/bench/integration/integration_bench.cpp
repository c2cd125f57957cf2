// Latency of TaskMap::evaluate (nearest + proximity + quality with gradients) on a 1e5-sample
// map, side by side with a brute-force scan and with nanoflann on the same 12-D embedding and
// the same mixture kernel. Per-call latencies give p50 / p99; the summary prints ratios
// against the FLANN-backed TaskMap measured in the same run. One thread (one core).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <nanoflann.hpp>

#include "synthetic_map.hpp"
#include "taskmap/integration/criteria.hpp"
#include "taskmap/integration/task_map.hpp"

namespace taskmap {
namespace {

constexpr std::size_t kSamples = 100000;
constexpr std::size_t kQueries = 4096;

struct Cloud {  // nanoflann dataset adaptor over the row-major embedding
  std::vector<double> e;
  std::size_t kdtree_get_point_count() const { return e.size() / kEmbeddingDim; }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return e[i * kEmbeddingDim + d]; }
  template <class B>
  bool kdtree_get_bbox(B&) const {
    return false;
  }
};
using NanoTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>,
                                                     Cloud, kEmbeddingDim, std::size_t>;

struct Fixture {
  TaskMap map = TaskMap::fromData(testing::syntheticMap(kSamples, 99));
  // Query set 0 ("mixed"): 90% within about two kernel widths per axis of a sample, 10% uniform
  // in the box (far from the map). Set 1 ("near"): one kernel width per axis, an optimizer's
  // iterate once it has reached the manifold. Entries [kQueries, 2 kQueries) hold set 1.
  std::vector<Pose> queries;
  std::vector<PoseEmbedding, Eigen::aligned_allocator<PoseEmbedding>> query_embedding;
  Cloud cloud;
  std::unique_ptr<NanoTree> nano;
  std::vector<Eigen::Vector3d> pos;
  std::vector<Eigen::Quaterniond, Eigen::aligned_allocator<Eigen::Quaterniond>> qconj;
  std::vector<double> w;
  double wsum = 0, isp2 = 0, isr2 = 0, inv_z = 0, wp = 0, wr = 0;
  std::size_t terms = 0, evaluations = 0;

  Fixture() {
    Rng rng(5, 0);
    const double sp = *map.options().position_sigma, sr = *map.options().rotation_sigma;
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
      query_embedding.push_back(embedPose(x, map.rotationScale()));
    }
    for (std::size_t i = 0; i < map.size(); ++i) {
      const Pose p = map.pose(i);
      const PoseEmbedding e = embedPose(p, map.rotationScale());
      cloud.e.insert(cloud.e.end(), e.data(), e.data() + kEmbeddingDim);
      pos.push_back(p.position);
      qconj.push_back(p.orientation.conjugate());
      w.push_back(map.data().grasps.epsilon[i]);
      wsum += w.back();
    }
    nano = std::make_unique<NanoTree>(kEmbeddingDim, cloud,
                                      nanoflann::KDTreeSingleIndexAdaptorParams(10));
    nano->buildIndex();
    isp2 = 1 / (sp * sp);
    isr2 = 1 / (sr * sr);
    inv_z = 1 / gaussianNormaliser(sp, sr);
    wp = map.options().linear_weight;
    wr = *map.options().angular_weight;
  }

  static Eigen::Vector3d relLog(const Eigen::Quaterniond& qc, const Eigen::Quaterniond& q) {
    Eigen::Quaterniond r = qc * q;
    double s = r.vec().norm(), c = r.w();
    Eigen::Vector3d v = r.vec();
    if (c < 0) {
      c = -c;
      v = -v;
    }
    return s < 1e-9 ? Eigen::Vector3d((2.0 / c) * v)
                    : Eigen::Vector3d((2.0 * std::atan2(s, c) / s) * v);
  }

  // The same criteria as TaskMap::evaluate, given the nearest sample and the mixture terms.
  template <typename Terms>
  Evaluation finish(const Pose& x, std::size_t nearest, double nearest_d2,
                    const Terms& terms_list) const {
    const Eigen::Quaterniond q = x.orientation.normalized();
    const Eigen::Matrix3d r = q.toRotationMatrix();
    Evaluation out;
    double sum = 0;
    Eigen::Vector3d gp = Eigen::Vector3d::Zero(), gw = Eigen::Vector3d::Zero();
    for (std::size_t i : terms_list) {
      if (w[i] <= 0) continue;
      const Eigen::Vector3d dp = x.position - pos[i];
      const Eigen::Vector3d om = relLog(qconj[i], q);
      const double c = w[i] * std::exp(-0.5 * (dp.squaredNorm() * isp2 + om.squaredNorm() * isr2));
      sum += c;
      gp += c * dp;
      gw += c * om;
    }
    out.quality.value = -sum * inv_z / wsum;
    out.quality.gradient << gp * (inv_z / wsum * isp2), r * gw * (inv_z / wsum * isr2);
    const Eigen::Vector3d dp = x.position - pos[nearest];
    const Eigen::Vector3d om = relLog(qconj[nearest], q);
    out.proximity.nearest = Neighbor{nearest, std::sqrt(nearest_d2)};
    out.proximity.value = wp * dp.squaredNorm() + wr * om.squaredNorm();
    out.proximity.gradient << 2 * wp * dp, 2 * wr * (r * om);
    return out;
  }

  Evaluation nanoEvaluate(std::size_t qi) const {
    thread_local std::vector<std::pair<std::size_t, double>> hits;
    thread_local std::vector<std::size_t> ids;
    hits.clear();
    ids.clear();
    const double r2 = map.cutoffRadius() * map.cutoffRadius();
    nano->radiusSearch(query_embedding[qi].data(), r2, hits, nanoflann::SearchParams(32, 0, false));
    std::size_t best = 0;
    double best_d2 = std::numeric_limits<double>::max();
    for (const auto& h : hits) {
      ids.push_back(h.first);
      if (h.second < best_d2) {
        best_d2 = h.second;
        best = h.first;
      }
    }
    if (hits.empty()) {
      nanoflann::KNNResultSet<double, std::size_t> rs(1);
      rs.init(&best, &best_d2);
      nano->findNeighbors(rs, query_embedding[qi].data(), nanoflann::SearchParams());
    }
    return finish(queries[qi], best, best_d2, ids);
  }

  std::size_t bruteNearest(std::size_t qi, double* d2_out) const {
    const double* q = query_embedding[qi].data();
    std::size_t best = 0;
    double best_d2 = std::numeric_limits<double>::max();
    for (std::size_t i = 0; i < map.size(); ++i) {
      const double* p = cloud.e.data() + i * kEmbeddingDim;
      double d2 = 0;
      for (int k = 0; k < kEmbeddingDim; ++k) d2 += (p[k] - q[k]) * (p[k] - q[k]);
      if (d2 < best_d2) {
        best_d2 = d2;
        best = i;
      }
    }
    *d2_out = best_d2;
    return best;
  }

  Evaluation bruteEvaluate(std::size_t qi) const {
    double d2 = 0;
    const std::size_t best = bruteNearest(qi, &d2);
    struct All {
      std::size_t n;
      struct It {
        std::size_t i;
        std::size_t operator*() const { return i; }
        It& operator++() {
          ++i;
          return *this;
        }
        bool operator!=(const It& o) const { return i != o.i; }
      };
      It begin() const { return {0}; }
      It end() const { return {n}; }
    };
    return finish(queries[qi], best, d2, All{map.size()});
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

template <typename F>
void timed(benchmark::State& state, std::string key, F&& f) {
  const std::size_t offset = state.range(0) == 1 ? kQueries : 0;
  key += state.range(0) == 1 ? "[near]" : "[mixed]";
  std::vector<double> ns;
  std::size_t i = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = f(offset + i % kQueries);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(r);
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
    ++i;
  }
  std::sort(ns.begin(), ns.end());
  Latency l;
  l.p50 = ns[ns.size() / 2] / 1000.0;
  l.p99 = ns[std::min(ns.size() - 1, ns.size() * 99 / 100)] / 1000.0;
  state.counters["p50_us"] = l.p50;
  state.counters["p99_us"] = l.p99;
  results()[key] = l;
}

void BM_EvaluateTaskMapFlann(benchmark::State& s) {
  Fixture& f = fx();
  std::size_t terms = 0, calls = 0;
  timed(s, "evaluate/taskmap(flann)", [&](std::size_t i) {
    Evaluation e = f.map.evaluate(f.queries[i]);
    terms += e.quality.terms;
    ++calls;
    return e.cost();
  });
  s.counters["terms"] = static_cast<double>(terms) / static_cast<double>(calls);
}
// The same map with a looser truncation tolerance (fewer mixture terms, larger reported bound).
void BM_EvaluateTaskMapFlannTol5e2(benchmark::State& s) {
  Fixture& f = fx();
  static const TaskMap loose = [] {
    TaskMapOptions o;
    o.quality_tolerance = 5e-2;
    return TaskMap::fromData(testing::syntheticMap(kSamples, 99), o);
  }();
  std::size_t terms = 0, calls = 0;
  timed(s, "evaluate/taskmap(flann,tol=5e-2)", [&](std::size_t i) {
    Evaluation e = loose.evaluate(f.queries[i]);
    terms += e.quality.terms;
    ++calls;
    return e.cost();
  });
  s.counters["terms"] = static_cast<double>(terms) / static_cast<double>(calls);
}
void BM_EvaluateNanoflann(benchmark::State& s) {
  Fixture& f = fx();
  timed(s, "evaluate/nanoflann", [&](std::size_t i) { return f.nanoEvaluate(i).cost(); });
}
void BM_EvaluateBruteForce(benchmark::State& s) {
  Fixture& f = fx();
  timed(s, "evaluate/brute", [&](std::size_t i) { return f.bruteEvaluate(i).cost(); });
}
void BM_NearestTaskMapFlann(benchmark::State& s) {
  Fixture& f = fx();
  timed(s, "nearest/taskmap(flann)",
        [&](std::size_t i) { return f.map.nearest(f.queries[i]).index; });
}
void BM_NearestNanoflann(benchmark::State& s) {
  Fixture& f = fx();
  timed(s, "nearest/nanoflann", [&](std::size_t i) {
    std::size_t best = 0;
    double d2 = 0;
    nanoflann::KNNResultSet<double, std::size_t> rs(1);
    rs.init(&best, &d2);
    f.nano->findNeighbors(rs, f.query_embedding[i].data(), nanoflann::SearchParams());
    return best;
  });
}
void BM_NearestBruteForce(benchmark::State& s) {
  Fixture& f = fx();
  timed(s, "nearest/brute", [&](std::size_t i) {
    double d2;
    return f.bruteNearest(i, &d2);
  });
}

// Argument: 0 = mixed query set, 1 = near query set.
BENCHMARK(BM_EvaluateTaskMapFlann)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_EvaluateTaskMapFlannTol5e2)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_EvaluateNanoflann)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_EvaluateBruteForce)->Arg(0)->Iterations(200);
BENCHMARK(BM_NearestTaskMapFlann)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_NearestNanoflann)->Arg(0)->Arg(1)->Iterations(20000);
BENCHMARK(BM_NearestBruteForce)->Arg(0)->Iterations(500);

}  // namespace
}  // namespace taskmap

int main(int argc, char** argv) {
  using namespace taskmap;
  benchmark::Initialize(&argc, argv);
  Fixture& f = fx();
  // Exactness on the benchmark queries: TaskMap's nearest (in evaluate) == brute force,
  // and the three evaluate implementations agree.
  std::size_t mismatches = 0;
  double worst_rel = 0;
  for (std::size_t i = 0; i < 2 * kQueries; i += 16) {
    const Evaluation a = f.map.evaluate(f.queries[i]);
    const Evaluation b = f.nanoEvaluate(i);
    const Evaluation c = f.bruteEvaluate(i);
    if (a.proximity.nearest.index != c.proximity.nearest.index) ++mismatches;
    if (b.proximity.nearest.index != c.proximity.nearest.index) ++mismatches;
    if (a.quality.value != 0)
      worst_rel = std::max(worst_rel,
                           std::abs(a.quality.value - c.quality.value) / std::abs(c.quality.value));
    if (std::abs(a.quality.value - c.quality.value) >
        a.quality.value_bound + 1e-12 * std::abs(c.quality.value))
      ++mismatches;
  }
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
    std::printf("  %-30s p50 %8.3f us  p99 %8.3f us   p50 ratio vs %s: %.1fx\n", a, r[a].p50,
                r[a].p99, b, r[a].p50 / r[b].p50);
  };
  std::printf("summary (ratios > 1: slower than TaskMap/FLANN):\n");
  for (const char* kind : {"evaluate", "nearest"}) {
    for (const char* set : {"[mixed]", "[near]"}) {
      const std::string base = std::string(kind) + "/taskmap(flann)" + set;
      for (const char* impl :
           {"/taskmap(flann)", "/taskmap(flann,tol=5e-2)", "/nanoflann", "/brute"})
        ratio((std::string(kind) + impl + set).c_str(), base.c_str());
    }
    // Brute force is independent of the query set: also against the near-set TaskMap.
    ratio((std::string(kind) + "/brute[mixed]").c_str(),
          (std::string(kind) + "/taskmap(flann)[near]").c_str());
  }
  return mismatches == 0 ? 0 : 1;
}
