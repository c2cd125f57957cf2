#include "taskmap/inspect/map_summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", digits, v);
  return buf;
}

std::string general(double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.4g", v);
  return buf;
}

Pose poseOfRow(const RowMatrixXd& poses, Eigen::Index i) {
  return Pose::fromVector7(poses.row(i).transpose());
}

// HSV (h in turns, s, v in [0, 1]) to 8-bit RGB.
std::array<std::uint8_t, 3> hsvToRgb(double h, double s, double v) {
  h = (h - std::floor(h)) * 6.0;
  const int sector = static_cast<int>(h) % 6;
  const double f = h - std::floor(h);
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r = v, g = t, b = p;
  switch (sector) {
    case 0:
      r = v, g = t, b = p;
      break;
    case 1:
      r = q, g = v, b = p;
      break;
    case 2:
      r = p, g = v, b = t;
      break;
    case 3:
      r = p, g = q, b = v;
      break;
    case 4:
      r = t, g = p, b = v;
      break;
    default:
      r = v, g = p, b = q;
      break;
  }
  auto byte = [](double x) { return static_cast<std::uint8_t>(std::lround(255.0 * x)); };
  return {byte(r), byte(g), byte(b)};
}

}  // namespace

EpsilonStats epsilonStats(std::vector<double> values) {
  EpsilonStats s;
  s.count = values.size();
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  s.min = values.front();
  s.max = values.back();
  const std::size_t n = values.size();
  s.median = n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  return s;
}

std::array<std::uint8_t, 3> clusterColor(int k) {
  // Tableau 10 with its grey replaced by indigo: grey is reserved for outliers.
  static constexpr std::uint8_t kTableau[10][3] = {
      {31, 119, 180}, {255, 127, 14},  {44, 160, 44},  {214, 39, 40},  {148, 103, 189},
      {140, 86, 75},  {227, 119, 194}, {188, 189, 34}, {23, 190, 207}, {57, 59, 121}};
  if (k < 0) return {150, 150, 150};
  if (k < 10) return {kTableau[k][0], kTableau[k][1], kTableau[k][2]};
  // Golden-angle hues with alternating saturation / value, skipping exact repeats and
  // near-greys so that every cluster keeps its own colour.
  std::vector<std::array<std::uint8_t, 3>> used;
  for (int i = 0; i < 10; ++i) used.push_back(clusterColor(i));
  std::array<std::uint8_t, 3> c{};
  int step = 0;
  for (int j = 10; j <= k; ++j) {
    for (;; ++step) {
      const double h = 0.137 + 0.6180339887498949 * step;
      const double s = 0.55 + 0.15 * (step % 3);
      const double v = 0.95 - 0.12 * ((step / 3) % 3);
      c = hsvToRgb(h, s, v);
      if (std::find(used.begin(), used.end(), c) == used.end()) break;
    }
    ++step;
    used.push_back(c);
  }
  return c;
}

std::string clusterColorHex(int k) {
  const auto c = clusterColor(k);
  char buf[8];
  std::snprintf(buf, sizeof(buf), "#%02x%02x%02x", c[0], c[1], c[2]);
  return buf;
}

Eigen::Vector3d approachAxis(const Pose& palm) {
  return palm.orientation.normalized().toRotationMatrix().col(2);
}

MapSummary summarizeMap(const TaskMapData& map, const std::string& path) {
  MapSummary s;
  s.path = path;
  s.generator = map.generator;
  s.created_utc = map.created_utc;
  s.object_name = map.object.name;
  s.object_vertices = static_cast<std::size_t>(map.object.vertices.rows());
  s.object_faces = static_cast<std::size_t>(map.object.faces.rows());
  s.object_volume = map.object.volume;
  if (map.object.vertices.rows() > 0 && map.object.vertices.cols() == 3) {
    s.bounds_min = map.object.vertices.colwise().minCoeff().transpose();
    s.bounds_max = map.object.vertices.colwise().maxCoeff().transpose();
  }
  s.hand_name = map.hand.name;
  s.hand_joints = map.hand.joint_names.size();
  s.sampler = map.sampling.sampler;
  s.seed = map.sampling.seed;
  s.trials = map.sampling.trials;
  s.outcomes = map.sampling.outcomes;
  const auto& g = map.grasps;
  s.grasps = g.size();
  std::vector<double> fc_eps;
  for (std::size_t i = 0; i < g.force_closure.size(); ++i) {
    if (g.force_closure[i] == 0) continue;
    ++s.force_closure;
    if (i < g.epsilon.size()) fc_eps.push_back(g.epsilon[i]);
  }
  const double denom = s.trials > 0 ? static_cast<double>(s.trials) : static_cast<double>(s.grasps);
  s.valid_rate = denom > 0 ? static_cast<double>(s.force_closure) / denom : 0.0;
  s.epsilon = epsilonStats(std::move(fc_eps));
  s.contacts_available = g.contacts_available;
  s.rotation_scale = g.rotation_scale;
  if (map.clustering) {
    const ClusteringResult& c = *map.clustering;
    s.clustered = true;
    s.linkage = toString(c.method);
    s.threshold = c.threshold;
    s.min_size = c.min_size;
    s.outliers = static_cast<std::size_t>(std::count(c.labels.begin(), c.labels.end(), -1));
    for (std::size_t k = 0; k < c.clusters.size(); ++k) {
      const ClusterSummary& cs = c.clusters[k];
      ClusterRow row;
      row.id = static_cast<int>(k);
      row.size = cs.size;
      row.representative = cs.representative;
      const Pose rep = cs.representative >= 0 && cs.representative < g.pose.rows()
                           ? poseOfRow(g.pose, cs.representative)
                           : cs.mean_pose;
      row.pose = rep.toVector7();
      row.approach = approachAxis(rep);
      row.mean_epsilon = cs.mean_epsilon;
      row.best_epsilon = cs.best_epsilon;
      row.color = clusterColorHex(row.id);
      s.clusters.push_back(row);
    }
  }
  return s;
}

std::string formatSummary(const MapSummary& s) {
  std::ostringstream o;
  o << "task map   " << s.path << "\n";
  o << "generator  " << s.generator << (s.created_utc.empty() ? "" : ", created " + s.created_utc)
    << "\n";
  o << "object     " << s.object_name << ": " << s.object_vertices << " vertices, "
    << s.object_faces << " faces, volume " << general(s.object_volume * 1e6) << " cm^3, size "
    << fixed((s.bounds_max - s.bounds_min).x() * 100, 1) << " x "
    << fixed((s.bounds_max - s.bounds_min).y() * 100, 1) << " x "
    << fixed((s.bounds_max - s.bounds_min).z() * 100, 1) << " cm\n";
  o << "hand       " << s.hand_name << " (" << s.hand_joints << " joints)\n";
  o << "sampling   " << (s.sampler.empty() ? "-" : s.sampler) << " sampler, seed " << s.seed << ", "
    << s.trials << " trials\n";
  if (!s.outcomes.empty()) {
    o << "outcomes   ";
    const char* sep = "";
    for (const auto& [name, n] : s.outcomes) {
      o << sep << name << " " << n;
      sep = ", ";
    }
    o << "\n";
  }
  o << "grasps     " << s.grasps << " stored, " << s.force_closure
    << " in force closure, valid rate " << fixed(100.0 * s.valid_rate, 1) << "% of "
    << (s.trials > 0 ? "trials" : "grasps") << "\n";
  o << "epsilon    min " << general(s.epsilon.min) << "  median " << general(s.epsilon.median)
    << "  max " << general(s.epsilon.max) << "  (over " << s.epsilon.count
    << " force-closure grasps)\n";
  o << "metric     rho " << general(s.rotation_scale) << " m/rad; contacts "
    << (s.contacts_available ? "stored" : "absent (imported map)") << "\n";
  if (!s.clustered) {
    o << "clusters   none (the map holds no clustering)\n";
    return o.str();
  }
  o << "clusters   " << s.clusters.size() << " (" << s.linkage << " linkage, cut at "
    << general(s.threshold) << " m, min size " << s.min_size << "), " << s.outliers
    << " outliers\n";
  char line[256];
  std::snprintf(line, sizeof(line), "  %3s %6s %6s  %-26s %-28s %9s %9s\n", "id", "size", "rep",
                "position (m)", "orientation (qw qx qy qz)", "mean eps", "best eps");
  o << line;
  for (const ClusterRow& r : s.clusters) {
    std::snprintf(line, sizeof(line),
                  "  %3d %6d %6d  %8.4f %8.4f %8.4f  %6.3f %6.3f %6.3f %6.3f  %9.4g %9.4g\n", r.id,
                  r.size, r.representative, r.pose[0], r.pose[1], r.pose[2], r.pose[3], r.pose[4],
                  r.pose[5], r.pose[6], r.mean_epsilon, r.best_epsilon);
    o << line;
  }
  return o.str();
}

namespace {

nlohmann::json summaryToJson(const MapSummary& s) {
  using nlohmann::json;
  auto vec = [](const auto& v) {
    json a = json::array();
    for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v[i]);
    return a;
  };
  json j;
  j["path"] = s.path;
  j["generator"] = s.generator;
  j["created_utc"] = s.created_utc;
  j["object"] = {{"name", s.object_name},           {"vertices", s.object_vertices},
                 {"faces", s.object_faces},         {"volume", s.object_volume},
                 {"bounds_min", vec(s.bounds_min)}, {"bounds_max", vec(s.bounds_max)}};
  j["hand"] = {{"name", s.hand_name}, {"joints", s.hand_joints}};
  j["sampling"] = {
      {"sampler", s.sampler}, {"seed", s.seed}, {"trials", s.trials}, {"outcomes", s.outcomes}};
  j["grasps"] = {{"count", s.grasps},
                 {"force_closure", s.force_closure},
                 {"valid_rate", s.valid_rate},
                 {"contacts_available", s.contacts_available},
                 {"rotation_scale", s.rotation_scale}};
  j["epsilon"] = {{"count", s.epsilon.count},
                  {"min", s.epsilon.min},
                  {"median", s.epsilon.median},
                  {"max", s.epsilon.max}};
  if (s.clustered) {
    json c = {{"linkage", s.linkage},
              {"threshold", s.threshold},
              {"min_size", s.min_size},
              {"outliers", s.outliers},
              {"clusters", json::array()}};
    for (const ClusterRow& r : s.clusters) {
      c["clusters"].push_back({{"id", r.id},
                               {"size", r.size},
                               {"representative", r.representative},
                               {"pose", vec(r.pose)},
                               {"approach", vec(r.approach)},
                               {"mean_epsilon", r.mean_epsilon},
                               {"best_epsilon", r.best_epsilon},
                               {"color", r.color}});
    }
    j["clustering"] = c;
  } else {
    j["clustering"] = nullptr;
  }
  return j;
}

}  // namespace

std::string summaryJson(const MapSummary& summary) {
  return summaryToJson(summary).dump(2);
}

void InspectOptions::validate() const {
  if (!std::filesystem::exists(map))
    throw Error("map file '" + map + "' does not exist; give the path of a task map (.h5)");
}

InspectResult inspectMap(const InspectOptions& options) {
  options.validate();
  InspectResult r;
  r.map = readMap(options.map);
  r.summary = summarizeMap(r.map, options.map);
  if (!r.summary.clustered) {
    r.status = InspectResult::Status::kNotClustered;
    r.message = "the map holds no clustering";
  }
  return r;
}

}  // namespace taskmap
