// ObjectModel: a closed solid with mass properties, inside test and sampling.
#include "taskmap/meshes/object_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include <openssl/evp.h>

#include "bounded_load.hpp"
#include "mesh_bvh.hpp"
#include "mesh_soup.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/meshes/object_size.hpp"

namespace taskmap {

struct ObjectModel::Impl {
  std::string name;
  std::string sha256;
  double scale = 1.0;
  TriangleMesh mesh;
  MassProperties mass;
  MeshLoadReport report;
  std::unique_ptr<detail::MeshBvh> bvh;
  std::vector<double> cumulative_area;   ///< prefix sums of face areas
  std::vector<Eigen::Vector3d> normals;  ///< unit outward face normals
};

namespace {

std::string formatDouble(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

MassProperties computeMass(const TriangleMesh& mesh) {
  MassProperties m;
  m.bounds_min = m.bounds_max = mesh.vertices.front();
  for (const auto& v : mesh.vertices) {
    m.bounds_min = m.bounds_min.cwiseMin(v);
    m.bounds_max = m.bounds_max.cwiseMax(v);
  }
  // Signed tetrahedra from a reference point inside the bounds (better conditioned than the
  // origin). Second moments via the canonical tetrahedron covariance.
  const Eigen::Vector3d ref = 0.5 * (m.bounds_min + m.bounds_max);
  Eigen::Matrix3d canonical;
  canonical << 2, 1, 1, 1, 2, 1, 1, 1, 2;
  canonical /= 120.0;
  double volume = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const auto& f : mesh.faces) {
    Eigen::Matrix3d a;
    a.col(0) = mesh.vertices[f[0]] - ref;
    a.col(1) = mesh.vertices[f[1]] - ref;
    a.col(2) = mesh.vertices[f[2]] - ref;
    const double det = a.col(0).dot(a.col(1).cross(a.col(2)));
    volume += det / 6.0;
    first += det / 24.0 * (a.col(0) + a.col(1) + a.col(2));
    second += det * (a * canonical * a.transpose());
  }
  m.volume = volume;
  const Eigen::Vector3d c = volume != 0 ? Eigen::Vector3d(first / volume) : Eigen::Vector3d::Zero();
  m.center_of_mass = ref + c;
  const Eigen::Matrix3d central = second - volume * c * c.transpose();
  m.inertia = central.trace() * Eigen::Matrix3d::Identity() - central;
  m.inertia = 0.5 * (m.inertia + m.inertia.transpose()).eval();
  double r = 0;
  for (const auto& v : mesh.vertices) r = std::max(r, (v - m.center_of_mass).norm());
  m.torque_scale = r;
  return m;
}

std::shared_ptr<ObjectModel::Impl> buildModel(detail::MeshSoup soup, const std::string& what,
                                              const MeshLoadOptions& options) {
  if (soup.faces.size() > options.max_faces) {
    throw Error(what + ": " + std::to_string(soup.faces.size()) + " faces exceed the limit of " +
                std::to_string(options.max_faces) + " (max_faces); simplify the mesh first");
  }
  if (!soup.points.empty()) {
    Eigen::Vector3d lo = soup.points.front(), hi = lo;
    for (const auto& p : soup.points) {
      if (!p.allFinite()) break;  // reported by makeSolid
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const double extent = (hi - lo).maxCoeff();
    if (extent > options.max_extent) {
      throw Error(what + ": bounding box is " + formatDouble(extent) +
                  " m across, above the limit of " + formatDouble(options.max_extent) +
                  " m for an object (max_extent); " +
                  scaleAdvice(extent, options.scale, kGraspableMinExtent, kGraspableMaxExtent,
                              kGraspableTypicalExtent));
    }
    if (const auto* check = ScopedLoadBoundsCheck::current(); check != nullptr && *check)
      (*check)(hi - lo);
  }
  const std::size_t input_vertices = soup.points.size();
  const std::size_t input_faces = soup.faces.size();
  detail::SolidResult solid = detail::makeSolid(
      std::move(soup), what,
      detail::SolidOptions{options.repair, options.wrap, options.wrap_alpha, options.wrap_offset});

  auto impl = std::make_shared<ObjectModel::Impl>();
  impl->scale = options.scale;
  impl->report.input_vertices = input_vertices;
  impl->report.input_faces = input_faces;
  impl->report.repairs = std::move(solid.repairs);
  impl->report.warnings = std::move(solid.warnings);
  impl->report.closed = true;
  impl->mesh = std::move(solid.mesh);
  impl->mass = computeMass(impl->mesh);
  if (!(impl->mass.volume > 0) || !impl->mass.center_of_mass.allFinite()) {
    throw Error(what +
                ": mesh encloses zero volume (flat or collapsed); a solid needs positive "
                "volume");
  }
  impl->bvh = std::make_unique<detail::MeshBvh>(impl->mesh);
  impl->cumulative_area.reserve(impl->mesh.faces.size());
  impl->normals.reserve(impl->mesh.faces.size());
  double total = 0;
  for (const auto& f : impl->mesh.faces) {
    const Eigen::Vector3d n = (impl->mesh.vertices[f[1]] - impl->mesh.vertices[f[0]])
                                  .cross(impl->mesh.vertices[f[2]] - impl->mesh.vertices[f[0]]);
    const double norm = n.norm();
    total += 0.5 * norm;
    impl->cumulative_area.push_back(total);
    impl->normals.push_back(norm > 0 ? Eigen::Vector3d(n / norm) : Eigen::Vector3d::UnitZ());
  }
  return impl;
}

}  // namespace

void MeshLoadOptions::validate() const {
  if (!(scale > 0) || !std::isfinite(scale)) {
    throw Error("mesh load option scale must be a positive finite number (got " +
                formatDouble(scale) + ")");
  }
  if (!(max_extent > 0) || !std::isfinite(max_extent)) {
    throw Error("mesh load option max_extent must be a positive finite length in metres (got " +
                formatDouble(max_extent) + ")");
  }
  if (max_faces == 0) throw Error("mesh load option max_faces must be positive");
  if (!(wrap_alpha >= 0) || !std::isfinite(wrap_alpha) || !(wrap_offset >= 0) ||
      !std::isfinite(wrap_offset)) {
    throw Error(
        "mesh load options wrap_alpha and wrap_offset must be finite lengths >= 0 in "
        "metres (0: automatic)");
  }
  if (wrap && !repair) throw Error("mesh load option wrap needs repair (it is a repair)");
}

ObjectModel ObjectModel::load(const std::string& path, const MeshLoadOptions& options) {
  options.validate();
  std::string format;
  // In a child process with memory and CPU limits: no file can crash or exhaust this process.
  detail::MeshSoup soup = detail::importMeshFileBounded(path, options.scale, &format);
  auto impl = buildModel(std::move(soup), "mesh file '" + path + "'", options);
  impl->name = std::filesystem::path(path).stem().string();
  impl->sha256 = sha256File(path);
  impl->report.path = path;
  impl->report.format = format;
  ObjectModel model;
  model.impl_ = std::move(impl);
  return model;
}

ObjectModel ObjectModel::fromMesh(const TriangleMesh& mesh, const std::string& name,
                                  const MeshLoadOptions& options) {
  options.validate();
  detail::MeshSoup soup;
  soup.points.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) soup.points.push_back(options.scale * v);
  soup.faces.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) soup.faces.push_back({f[0], f[1], f[2]});
  auto impl = buildModel(std::move(soup), "mesh '" + name + "'", options);
  impl->name = name;
  impl->report.format = "memory";
  ObjectModel model;
  model.impl_ = std::move(impl);
  return model;
}

const std::string& ObjectModel::name() const {
  return impl_->name;
}
const std::string& ObjectModel::sourceSha256() const {
  return impl_->sha256;
}
double ObjectModel::scale() const {
  return impl_->scale;
}
const TriangleMesh& ObjectModel::mesh() const {
  return impl_->mesh;
}
const MassProperties& ObjectModel::massProperties() const {
  return impl_->mass;
}
const MeshLoadReport& ObjectModel::report() const {
  return impl_->report;
}

bool ObjectModel::contains(const Eigen::Vector3d& p) const {
  return impl_->bvh->contains(p);
}

double ObjectModel::distanceToSurface(const Eigen::Vector3d& p) const {
  return impl_->bvh->closestPoint(p);
}

bool ObjectModel::nearSurface(const Eigen::Vector3d& p, double distance) const {
  return impl_->bvh->within(p, distance);
}

namespace {

void checkRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double min_distance,
              double max_distance) {
  if (!origin.allFinite() || !direction.allFinite() || std::abs(direction.norm() - 1.0) > 1e-9)
    throw Error("castRay needs a finite origin and a finite unit direction");
  if (!(min_distance >= 0.0) || !(max_distance > min_distance))
    throw Error("castRay needs 0 <= min_distance < max_distance (metres)");
}

}  // namespace

std::optional<RayHit> ObjectModel::castRayAndAgain(const Eigen::Vector3d& origin,
                                                   const Eigen::Vector3d& direction,
                                                   double min_distance, double max_distance,
                                                   double gap, bool* again) const {
  checkRay(origin, direction, min_distance, max_distance);
  if (!std::isfinite(gap) || gap < 0.0)
    throw Error("castRayAndAgain needs a finite gap >= 0 (metres)");
  int face = -1;
  const double t = impl_->bvh->firstHitAndAgain(origin, direction, min_distance, max_distance, gap,
                                                &face, again);
  if (face < 0) return std::nullopt;
  return hitAt(origin, direction, t, face);
}

RayHit ObjectModel::hitAt(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t,
                          int face) const {
  RayHit hit;
  hit.distance = t;
  hit.point = origin + t * direction;
  hit.normal = impl_->normals[static_cast<std::size_t>(face)];
  hit.face = face;
  return hit;
}

std::optional<RayHit> ObjectModel::castRay(const Eigen::Vector3d& origin,
                                           const Eigen::Vector3d& direction, double min_distance,
                                           double max_distance) const {
  checkRay(origin, direction, min_distance, max_distance);
  int face = -1;
  const double t = impl_->bvh->firstHit(origin, direction, min_distance, max_distance, &face);
  if (face < 0) return std::nullopt;
  return hitAt(origin, direction, t, face);
}

Eigen::Vector3d ObjectModel::sampleInside(Rng& rng) const {
  const Eigen::Vector3d lo = impl_->mass.bounds_min;
  const Eigen::Vector3d size = impl_->mass.bounds_max - lo;
  // The acceptance rate is volume / box volume; 1e7 tries cannot all fail for a valid solid
  // unless it fills less than ~1e-6 of its box.
  for (int attempt = 0; attempt < 10'000'000; ++attempt) {
    const double x = rng.uniform(), y = rng.uniform(), z = rng.uniform();
    const Eigen::Vector3d p = lo + Eigen::Vector3d(x * size.x(), y * size.y(), z * size.z());
    if (impl_->bvh->contains(p)) return p;
  }
  throw Error("object '" + impl_->name +
              "': no inside point found by rejection sampling; the solid is too thin");
}

SurfaceSample ObjectModel::sampleSurface(Rng& rng) const {
  const auto& cum = impl_->cumulative_area;
  const double target = rng.uniform() * cum.back();
  auto it = std::upper_bound(cum.begin(), cum.end(), target);
  if (it == cum.end()) --it;
  const auto face = static_cast<std::size_t>(std::distance(cum.begin(), it));
  const auto& f = impl_->mesh.faces[face];
  double u = rng.uniform(), v = rng.uniform();
  if (u + v > 1) {
    u = 1 - u;
    v = 1 - v;
  }
  const auto& vs = impl_->mesh.vertices;
  SurfaceSample s;
  s.point = vs[f[0]] + u * (vs[f[1]] - vs[f[0]]) + v * (vs[f[2]] - vs[f[0]]);
  s.normal = impl_->normals[face];
  s.face = static_cast<int>(face);
  return s;
}

std::string sha256Hex(const std::string& bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1) {
    throw Error("SHA-256 computation failed (OpenSSL)");
  }
  static const char* kHex = "0123456789abcdef";
  std::string out;
  out.reserve(2 * length);
  for (unsigned int i = 0; i < length; ++i) {
    out.push_back(kHex[digest[i] >> 4]);
    out.push_back(kHex[digest[i] & 15]);
  }
  return out;
}

std::string sha256File(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open '" + path + "' to hash it");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw Error("cannot read '" + path + "' to hash it");
  return sha256Hex(buffer.str());
}

}  // namespace taskmap
