#include "taskmap/inspect/regression.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

// Tolerances, per statistic, and why:
// - Counts (trials per outcome, valid grasps, cluster count and sizes, outliers): exact. The
//   pipeline is deterministic for a seed: trial i draws from Rng(seed, i) alone and results
//   are gathered in trial order, whatever the thread count, so the same build gives the same
//   counts. A count that moves means the grasps changed.
// - Valid rate: derived from two exact counts, compared to 1e-12.
// - Epsilon quantiles: 2 % relative (plus 1e-9 absolute). Epsilon is a hull distance summed
//   and normalised in floating point; another compiler or libm may reorder sums and move the
//   last digits, and the contact points themselves come from bisections whose last step can
//   land on the other side of a tolerance. 2 % is far below what a physical change does
//   (friction 0.5 -> 0.3 moves the median by tens of percent).
// - Representative poses: 1 mm in position and 0.01 rad in orientation: the representative
//   is the best-epsilon grasp of its cluster, so the same build picks the same grasp; the
//   slack only absorbs the floating-point noise named above.
constexpr double kEpsilonRelTol = 0.02;
constexpr double kEpsilonAbsTol = 1e-9;
constexpr double kPositionTol = 1e-3;
constexpr double kAngleTol = 0.01;

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

std::string fmt(double x) {
  std::ostringstream os;
  os << std::setprecision(6) << x;
  return os.str();
}

std::string fmtSizes(const std::vector<int>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + std::to_string(v[i]);
  return s + "]";
}

std::string fmtPose(const std::vector<double>& p) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(4) << "(" << p[0] << "," << p[1] << "," << p[2] << ")";
  return os.str();
}

ComparisonRow row(const std::string& c, const std::string& stat, const std::string& g,
                  const std::string& n, bool pass) {
  return ComparisonRow{c, stat, g, n, pass};
}

}  // namespace

MapStatistics computeStatistics(const TaskMapData& map) {
  MapStatistics s;
  s.trials = map.sampling.trials;
  s.outcomes = map.sampling.outcomes;
  std::vector<double> eps;
  for (std::size_t i = 0; i < map.grasps.size(); ++i) {
    if (map.grasps.force_closure[i]) eps.push_back(map.grasps.epsilon[i]);
  }
  s.valid = eps.size();
  s.valid_rate = s.trials ? static_cast<double>(s.valid) / static_cast<double>(s.trials) : 0.0;
  s.epsilon_q10 = quantile(eps, 0.1);
  s.epsilon_q50 = quantile(eps, 0.5);
  s.epsilon_q90 = quantile(eps, 0.9);
  if (map.clustering) {
    for (const auto& c : map.clustering->clusters) {
      s.cluster_sizes.push_back(c.size);
      const auto v = map.grasps.poseAt(static_cast<std::size_t>(c.representative)).toVector7();
      s.representatives.emplace_back(v.data(), v.data() + 7);
    }
    s.outliers = static_cast<int>(
        std::count(map.clustering->labels.begin(), map.clustering->labels.end(), -1));
  }
  return s;
}

namespace {

nlohmann::json toJson(const MapStatistics& s) {
  nlohmann::json j;
  j["trials"] = s.trials;
  j["outcomes"] = s.outcomes;
  j["valid"] = s.valid;
  j["valid_rate"] = s.valid_rate;
  j["epsilon_quantiles"] = {{"q10", s.epsilon_q10}, {"q50", s.epsilon_q50}, {"q90", s.epsilon_q90}};
  j["clusters"] = s.cluster_sizes.size();
  j["cluster_sizes"] = s.cluster_sizes;
  j["outliers"] = s.outliers;
  j["representatives"] = s.representatives;
  return j;
}

MapStatistics statisticsFromJson(const nlohmann::json& j, const std::string& source) {
  try {
    MapStatistics s;
    s.trials = j.at("trials").get<std::uint64_t>();
    s.outcomes = j.at("outcomes").get<std::map<std::string, std::uint64_t>>();
    s.valid = j.at("valid").get<std::uint64_t>();
    s.valid_rate = j.at("valid_rate").get<double>();
    s.epsilon_q10 = j.at("epsilon_quantiles").at("q10").get<double>();
    s.epsilon_q50 = j.at("epsilon_quantiles").at("q50").get<double>();
    s.epsilon_q90 = j.at("epsilon_quantiles").at("q90").get<double>();
    s.cluster_sizes = j.at("cluster_sizes").get<std::vector<int>>();
    s.outliers = j.at("outliers").get<int>();
    s.representatives = j.at("representatives").get<std::vector<std::vector<double>>>();
    for (const auto& r : s.representatives) {
      if (r.size() != 7) throw Error("a representative pose needs 7 numbers");
    }
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw Error(source + ": not a golden statistics file (" + e.what() +
                "); regenerate it with `taskmap regress --update`");
  }
}

}  // namespace

MapStatistics statisticsFromJsonText(const std::string& text, const std::string& source) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(source + ": not valid JSON (" + e.what() + ")");
  }
  return statisticsFromJson(j, source);
}

std::optional<MapStatistics> readGoldenFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return statisticsFromJsonText(text.str(), path);
}

std::string goldenFileText(const MapStatistics& s, const RegressionCase& c) {
  nlohmann::json j = toJson(s);
  j["case"] = {{"object", c.object},
               {"hand", c.hand},
               {"sampler", c.sampler},
               {"seed", c.seed},
               {"trials", c.trials}};
  if (!c.sidecar.empty()) j["case"]["sidecar"] = c.sidecar;
  return j.dump(2) + "\n";
}

RegressionResult compareWithGolden(const std::string& case_name, const MapStatistics& golden,
                                   const MapStatistics& now) {
  RegressionResult r;
  r.rows = compareStatistics(case_name, golden, now);
  const auto failed = std::count_if(r.rows.begin(), r.rows.end(),
                                    [](const ComparisonRow& row) { return !row.pass; });
  if (failed > 0) {
    r.status = RegressionResult::Status::kFail;
    r.message = std::to_string(failed) + " statistic(s) failed";
  }
  return r;
}

std::vector<ComparisonRow> compareStatistics(const std::string& c, const MapStatistics& g,
                                             const MapStatistics& n) {
  std::vector<ComparisonRow> rows;
  rows.push_back(
      row(c, "trials", std::to_string(g.trials), std::to_string(n.trials), g.trials == n.trials));
  std::map<std::string, std::uint64_t> all = g.outcomes;
  for (const auto& [k, v] : n.outcomes) all.emplace(k, 0);
  for (const auto& kv : all) {
    const std::string& k = kv.first;
    const auto gi = g.outcomes.count(k) ? g.outcomes.at(k) : 0;
    const auto ni = n.outcomes.count(k) ? n.outcomes.at(k) : 0;
    rows.push_back(row(c, "outcome " + k, std::to_string(gi), std::to_string(ni), gi == ni));
  }
  rows.push_back(
      row(c, "valid", std::to_string(g.valid), std::to_string(n.valid), g.valid == n.valid));
  rows.push_back(row(c, "valid rate", fmt(g.valid_rate), fmt(n.valid_rate),
                     std::abs(g.valid_rate - n.valid_rate) <= 1e-12));
  const std::pair<const char*, std::pair<double, double>> qs[] = {
      {"epsilon q10", {g.epsilon_q10, n.epsilon_q10}},
      {"epsilon q50", {g.epsilon_q50, n.epsilon_q50}},
      {"epsilon q90", {g.epsilon_q90, n.epsilon_q90}}};
  for (const auto& q : qs) {
    const double gv = q.second.first, nv = q.second.second;
    rows.push_back(row(c, q.first, fmt(gv), fmt(nv),
                       std::abs(gv - nv) <= kEpsilonRelTol * std::abs(gv) + kEpsilonAbsTol));
  }
  rows.push_back(row(c, "clusters", std::to_string(g.cluster_sizes.size()),
                     std::to_string(n.cluster_sizes.size()),
                     g.cluster_sizes.size() == n.cluster_sizes.size()));
  rows.push_back(row(c, "cluster sizes", fmtSizes(g.cluster_sizes), fmtSizes(n.cluster_sizes),
                     g.cluster_sizes == n.cluster_sizes));
  rows.push_back(row(c, "outliers", std::to_string(g.outliers), std::to_string(n.outliers),
                     g.outliers == n.outliers));
  const std::size_t k = std::max(g.representatives.size(), n.representatives.size());
  for (std::size_t i = 0; i < k; ++i) {
    const std::string stat = "cluster " + std::to_string(i) + " representative";
    if (i >= g.representatives.size() || i >= n.representatives.size()) {
      rows.push_back(
          row(c, stat, i < g.representatives.size() ? fmtPose(g.representatives[i]) : "-",
              i < n.representatives.size() ? fmtPose(n.representatives[i]) : "-", false));
      continue;
    }
    const auto& a = g.representatives[i];
    const auto& b = n.representatives[i];
    const double dp = std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                (a[2] - b[2]) * (a[2] - b[2]));
    const double dot = std::abs(a[3] * b[3] + a[4] * b[4] + a[5] * b[5] + a[6] * b[6]);
    const double angle = 2.0 * std::acos(std::min(1.0, dot));
    rows.push_back(row(c, stat, fmtPose(a), fmtPose(b), dp <= kPositionTol && angle <= kAngleTol));
  }
  return rows;
}

std::vector<RegressionCase> readCases(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open the regression case list");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw Error(path + ": not valid JSON (" + e.what() + ")");
  }
  std::vector<RegressionCase> cases;
  try {
    for (const auto& e : j.at("cases")) {
      RegressionCase c;
      c.name = e.at("name").get<std::string>();
      c.object = e.at("object").get<std::string>();
      c.hand = e.at("hand").get<std::string>();
      c.sidecar = e.value("sidecar", std::string());
      c.sampler = e.value("sampler", std::string("mixed"));
      c.seed = e.value("seed", std::uint64_t{1});
      c.trials = e.at("trials").get<std::uint64_t>();
      if (c.trials == 0)
        throw Error(path + ": case " + c.name + " has trials = 0; give at least 1");
      cases.push_back(c);
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(path + ": bad case entry (" + e.what() +
                "); each case needs name, object, hand, trials");
  }
  return cases;
}

}  // namespace taskmap
