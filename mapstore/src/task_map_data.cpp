#include "taskmap/mapstore/task_map_data.hpp"

#include <cassert>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/grasp_contacts.hpp"

namespace taskmap {
namespace {

// Quaternions and normals within this of unit length are accepted.
constexpr double kUnitTolerance = 1e-6;
constexpr double kNormalTolerance = 1e-3;

[[noreturn]] void fail(const std::string& dataset, const std::string& what) {
  throw Error(dataset + ": " + what);
}

template <typename Derived>
void requireFinite(const Eigen::DenseBase<Derived>& m, const std::string& dataset) {
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c)
      if (!std::isfinite(static_cast<double>(m(r, c))))
        fail(dataset, "row " + std::to_string(r) + " holds a non-finite value");
}

void requireFinite(const std::vector<double>& v, const std::string& dataset) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i])) fail(dataset, "entry " + std::to_string(i) + " is not finite");
}

void requireRows(std::size_t actual, std::size_t expected, const std::string& dataset,
                 const std::string& why) {
  if (actual != expected)
    fail(dataset, "has " + std::to_string(actual) + " rows, expected " + std::to_string(expected) +
                      " (" + why + ")");
}

void requireCols(Eigen::Index actual, Eigen::Index expected, const std::string& dataset) {
  if (actual != expected)
    fail(dataset,
         "has " + std::to_string(actual) + " columns, expected " + std::to_string(expected));
}

void requireUnitQuaternions(const RowMatrixXd& poses, const std::string& dataset) {
  for (Eigen::Index r = 0; r < poses.rows(); ++r) {
    const double norm = poses.row(r).segment<4>(3).norm();
    if (std::abs(norm - 1.0) > kUnitTolerance) {
      std::ostringstream os;
      os << "row " << r << " has a non-unit quaternion (norm " << norm << ")";
      fail(dataset, os.str());
    }
  }
}

void requireScalar(double v, bool positive, const std::string& name) {
  if (!std::isfinite(v) || v < 0.0 || (positive && v == 0.0))
    fail(name, std::string("must be finite and ") + (positive ? "positive" : "non-negative"));
}

void validateObject(const MapObject& o) {
  requireCols(o.vertices.cols(), 3, "/object/vertices");
  requireFinite(o.vertices, "/object/vertices");
  const auto v = o.vertices.rows();
  for (Eigen::Index f = 0; f < o.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (o.faces(f, k) < 0 || o.faces(f, k) >= v)
        fail("/object/faces", "row " + std::to_string(f) + " indexes vertex " +
                                  std::to_string(o.faces(f, k)) + " of " + std::to_string(v));
  requireScalar(o.scale, true, "/object attribute scale");
  requireScalar(o.volume, false, "/object attribute volume");
  requireScalar(o.torque_scale, false, "/object attribute torque_scale");
  if (!o.center_of_mass.allFinite()) fail("/object attribute center_of_mass", "must be finite");
}

void validateGrasps(const MapGrasps& g, std::size_t joints) {
  requireCols(g.pose.cols(), 7, "/grasps/pose");
  const std::size_t n = g.size();
  requireFinite(g.pose, "/grasps/pose");
  requireUnitQuaternions(g.pose, "/grasps/pose");
  requireRows(static_cast<std::size_t>(g.joints.rows()), n, "/grasps/joints", "one per grasp");
  requireCols(g.joints.cols(), static_cast<Eigen::Index>(joints), "/grasps/joints");
  requireFinite(g.joints, "/grasps/joints");
  requireRows(g.force_closure.size(), n, "/grasps/force_closure", "one per grasp");
  for (std::size_t i = 0; i < n; ++i)
    if (g.force_closure[i] > 1)
      fail("/grasps/force_closure", "entry " + std::to_string(i) + " is neither 0 nor 1");
  requireRows(g.epsilon.size(), n, "/grasps/epsilon", "one per grasp");
  requireFinite(g.epsilon, "/grasps/epsilon");
  requireRows(g.volume.size(), n, "/grasps/volume", "one per grasp");
  requireFinite(g.volume, "/grasps/volume");
  if (!std::isfinite(g.rotation_scale) || g.rotation_scale <= 0.0)
    fail("/grasps attribute rotation_scale", "must be finite and positive");

  requireRows(g.contact_offsets.size(), n + 1, "/grasps/contact_offsets", "one per grasp + 1");
  const auto m = static_cast<std::size_t>(g.contact_points.rows());
  if (g.contact_offsets.front() != 0) fail("/grasps/contact_offsets", "must start at 0");
  for (std::size_t i = 0; i < n; ++i)
    if (g.contact_offsets[i + 1] < g.contact_offsets[i])
      fail("/grasps/contact_offsets", "decreases at entry " + std::to_string(i + 1));
  if (g.contact_offsets.back() != static_cast<std::int64_t>(m))
    fail("/grasps/contact_offsets", "ends at " + std::to_string(g.contact_offsets.back()) +
                                        " but there are " + std::to_string(m) +
                                        " contacts (out of bounds)");
  if (!g.contacts_available && m != 0)
    fail("/grasps/contact_points", "contacts stored although contacts_available is false");
  requireCols(g.contact_points.cols(), 3, "/grasps/contact_points");
  requireFinite(g.contact_points, "/grasps/contact_points");
  requireCols(g.contact_normals.cols(), 3, "/grasps/contact_normals");
  requireRows(static_cast<std::size_t>(g.contact_normals.rows()), m, "/grasps/contact_normals",
              "one per contact");
  requireFinite(g.contact_normals, "/grasps/contact_normals");
  for (Eigen::Index r = 0; r < g.contact_normals.rows(); ++r)
    if (std::abs(g.contact_normals.row(r).norm() - 1.0) > kNormalTolerance)
      fail("/grasps/contact_normals", "row " + std::to_string(r) + " is not a unit vector");
  requireRows(g.contact_depths.size(), m, "/grasps/contact_depths", "one per contact");
  requireFinite(g.contact_depths, "/grasps/contact_depths");
  requireRows(g.contact_links.size(), m, "/grasps/contact_links", "one per contact");
  for (std::size_t i = 0; i < m; ++i)
    if (g.contact_links[i] < -1)
      fail("/grasps/contact_links", "entry " + std::to_string(i) + " is below -1");
}

void validateClustering(const ClusteringResult& c, std::size_t n) {
  requireRows(c.labels.size(), n, "/grasps/cluster", "one per grasp");
  const auto k = static_cast<int>(c.clusters.size());
  std::vector<int> counts(c.clusters.size(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (c.labels[i] < -1 || c.labels[i] >= k)
      fail("/grasps/cluster", "entry " + std::to_string(i) + " is label " +
                                  std::to_string(c.labels[i]) + " outside [-1, " +
                                  std::to_string(k) + ")");
    if (c.labels[i] >= 0) ++counts[static_cast<std::size_t>(c.labels[i])];
  }
  for (int j = 0; j < k; ++j) {
    const ClusterSummary& s = c.clusters[static_cast<std::size_t>(j)];
    const std::string row = "row " + std::to_string(j);
    if (s.size != counts[static_cast<std::size_t>(j)])
      fail("/clusters/size", row + " says " + std::to_string(s.size) + " but " +
                                 std::to_string(counts[static_cast<std::size_t>(j)]) +
                                 " grasps carry that label");
    if (s.representative < 0 || static_cast<std::size_t>(s.representative) >= n ||
        c.labels[static_cast<std::size_t>(s.representative)] != j)
      fail("/clusters/representative", row + " is not a grasp of its cluster");
    if (!s.mean_pose.position.allFinite() || !s.mean_pose.orientation.coeffs().allFinite())
      fail("/clusters/mean_pose", row + " holds a non-finite value");
    if (std::abs(s.mean_pose.orientation.norm() - 1.0) > kUnitTolerance)
      fail("/clusters/mean_pose", row + " has a non-unit quaternion");
    if (!std::isfinite(s.mean_epsilon)) fail("/clusters/mean_epsilon", row + " is not finite");
    if (!std::isfinite(s.best_epsilon)) fail("/clusters/best_epsilon", row + " is not finite");
    if (!s.bounds_min.allFinite()) fail("/clusters/bounds_min", row + " is not finite");
    if (!s.bounds_max.allFinite()) fail("/clusters/bounds_max", row + " is not finite");
  }
  const std::size_t merges = n > 0 ? n - 1 : 0;
  requireRows(static_cast<std::size_t>(c.linkage.rows()), merges, "/clustering/linkage",
              "N - 1 merges");
  requireFinite(c.linkage, "/clustering/linkage");
  for (Eigen::Index r = 0; r < c.linkage.rows(); ++r) {
    const double limit = static_cast<double>(n) + static_cast<double>(r);
    for (int col = 0; col < 2; ++col) {
      const double id = c.linkage(r, col);
      if (id < 0.0 || id >= limit || id != std::floor(id))
        fail("/clustering/linkage", "row " + std::to_string(r) + " merges an invalid id");
    }
    if (c.linkage(r, 2) < 0.0)
      fail("/clustering/linkage", "row " + std::to_string(r) + " has a negative distance");
    if (c.linkage(r, 3) < 2.0 || c.linkage(r, 3) > static_cast<double>(n))
      fail("/clustering/linkage", "row " + std::to_string(r) + " has an invalid size");
  }
  requireScalar(c.rotation_scale, true, "/clustering attribute rotation_scale");
  requireScalar(c.threshold, false, "/clustering attribute threshold");
  if (c.min_size < 0) fail("/clustering attribute min_size", "must not be negative");
}

void validateRobust(const MapValidation& v, std::size_t n) {
  const std::size_t variants = v.variantCount();
  if (variants == 0) fail("/validation attribute robust_json", "names no variants");
  requireRows(v.robust.size(), n, "/grasps/robust", "one per grasp");
  requireRows(v.robust_share.size(), n, "/grasps/robust_share", "one per grasp");
  requireRows(v.push_translation.size(), n, "/grasps/hold_push_translation", "one per grasp");
  requireRows(v.push_rotation.size(), n, "/grasps/hold_push_rotation", "one per grasp");
  requireRows(v.variant_held.size(), n * variants, "/grasps/robust_variants",
              "one row per grasp, one column per variant");
  requireFinite(v.robust_share, "/grasps/robust_share");
  requireFinite(v.push_translation, "/grasps/hold_push_translation");
  requireFinite(v.push_rotation, "/grasps/hold_push_rotation");
  for (std::size_t i = 0; i < n; ++i) {
    const std::string e = "entry " + std::to_string(i);
    const bool untested = v.robust[i] == MapValidation::kNotTested;
    if (v.robust[i] > 1 && !untested) fail("/grasps/robust", e + " is not 0, 1 or 255");
    if (v.robust[i] == 1 && v.hold[i] != 1)
      fail("/grasps/robust", e + " is robust but does not hold (/grasps/hold)");
    const double share = v.robust_share[i];
    if (untested ? share != -1.0 : !(share >= 0.0 && share <= 1.0))
      fail("/grasps/robust_share", e + " is not in [0, 1] (-1 when not tested)");
    if (v.robust[i] == 1 && share != 1.0)
      fail("/grasps/robust_share", e + " of a robust grasp is not 1");
    for (std::size_t k = 0; k < variants; ++k) {
      const auto h = v.variant_held[i * variants + k];
      if (h > 1 && h != MapValidation::kNotTested)
        fail("/grasps/robust_variants", e + " holds a value other than 0, 1 or 255");
      if (v.robust[i] == 1 && h != 1)
        fail("/grasps/robust_variants", e + " of a robust grasp has a variant that failed");
    }
  }
}

void validateValidation(const MapValidation& v, std::size_t n) {
  requireRows(v.hold.size(), n, "/grasps/hold", "one per grasp");
  requireRows(v.status.size(), n, "/grasps/hold_status", "one per grasp");
  requireRows(v.translation.size(), n, "/grasps/hold_translation", "one per grasp");
  requireRows(v.rotation.size(), n, "/grasps/hold_rotation", "one per grasp");
  requireRows(v.direction.size(), n, "/grasps/hold_direction", "one per grasp");
  requireFinite(v.translation, "/grasps/hold_translation");
  requireFinite(v.rotation, "/grasps/hold_rotation");
  for (std::size_t i = 0; i < n; ++i) {
    const std::string e = "entry " + std::to_string(i);
    const bool untested = v.hold[i] == MapValidation::kNotTested;
    if (v.hold[i] > 1 && !untested) fail("/grasps/hold", e + " is not 0, 1 or 255");
    if (untested != (v.status[i] == MapValidation::kNotTested) || (!untested && v.status[i] > 4))
      fail("/grasps/hold_status", e + " is not a status code matching /grasps/hold");
    if ((v.status[i] == 0) != (v.hold[i] == 1))
      fail("/grasps/hold_status", e + " disagrees with /grasps/hold");
    if (v.direction[i] < -1 || v.direction[i] > 5)
      fail("/grasps/hold_direction", e + " is outside [-1, 5]");
  }
  if (v.robust_json.empty()) {
    if (!v.robust.empty() || !v.robust_share.empty() || !v.push_translation.empty() ||
        !v.push_rotation.empty() || !v.variant_held.empty())
      fail("/grasps/robust", "robust labels without /validation attribute robust_json");
    return;
  }
  validateRobust(v, n);
}

}  // namespace

std::size_t MapValidation::tested() const {
  std::size_t n = 0;
  for (auto h : hold) n += h != kNotTested;
  return n;
}

std::size_t MapValidation::robustCount() const {
  std::size_t n = 0;
  for (auto r : robust) n += r == 1;
  return n;
}

std::size_t MapValidation::variantCount() const {
  if (robust_json.empty()) return 0;
  const nlohmann::json j = nlohmann::json::parse(robust_json, nullptr, false);
  if (!j.is_object() || !j.contains("variants") || !j["variants"].is_array()) return 0;
  return j["variants"].size();
}

std::size_t MapValidation::holding() const {
  std::size_t n = 0;
  for (auto h : hold) n += h == 1;
  return n;
}

Pose MapGrasps::poseAt(std::size_t i) const {
  assert(i < size());
  const Eigen::Matrix<double, 7, 1> v = pose.row(static_cast<Eigen::Index>(i)).transpose();
  return Pose::fromVector7(v);
}

void TaskMapData::validate() const {
  validateObject(object);
  validateGrasps(grasps, hand.joint_names.size());
  if (!hand.link_names.empty())
    for (std::size_t i = 0; i < grasps.contact_links.size(); ++i)
      if (grasps.contact_links[i] >= static_cast<std::int32_t>(hand.link_names.size()))
        fail("/grasps/contact_links", "entry " + std::to_string(i) + " is " +
                                          std::to_string(grasps.contact_links[i]) +
                                          ", beyond the " + std::to_string(hand.link_names.size()) +
                                          " links of /hand/link_names");
  std::uint64_t total = 0;
  for (const auto& [name, count] : sampling.outcomes) {
    if (name.empty()) fail("/sampling", "an outcome has an empty name");
    total += count;
  }
  if (!sampling.outcomes.empty() && total != sampling.trials)
    fail("/sampling", "outcome counts sum to " + std::to_string(total) + " but trials is " +
                          std::to_string(sampling.trials));
  requireScalar(quality.friction, false, "/quality attribute friction");
  if (quality.cone_edges < 0) fail("/quality attribute cone_edges", "must not be negative");
  if (clustering) validateClustering(*clustering, grasps.size());
  if (validation) validateValidation(*validation, grasps.size());
}

std::vector<Contact> graspContacts(const MapGrasps& g, std::size_t i) {
  assert(i < g.size() && i + 1 < g.contact_offsets.size());  // a valid map: N + 1 offsets
  std::vector<Contact> out;
  for (auto r = g.contact_offsets[i]; r < g.contact_offsets[i + 1]; ++r) {
    Contact c;
    c.point = g.contact_points.row(r).transpose();
    c.normal = g.contact_normals.row(r).transpose();
    c.depth = g.contact_depths[static_cast<std::size_t>(r)];
    c.link = g.contact_links[static_cast<std::size_t>(r)];
    out.push_back(c);
  }
  return out;
}

}  // namespace taskmap
