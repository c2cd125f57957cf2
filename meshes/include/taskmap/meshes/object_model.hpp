#pragma once
/// @file object_model.hpp
/// An object as a closed solid: loaded, validated, with mass properties, inside test and
/// deterministic volume and surface sampling. Implementation (assimp, CGAL) stays private.

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/random.hpp"
#include "taskmap/core/triangle_mesh.hpp"

namespace taskmap {

/// Options for loading an object mesh.
struct MeshLoadOptions {
  double scale = 1.0;         ///< multiplies every coordinate (file units -> metres); > 0
  bool repair = true;         ///< merge duplicates, stitch borders, orient outward, drop degenerate
  double max_extent = 100.0;  ///< metres; larger bounding boxes are refused as absurd
  std::size_t max_faces = 10'000'000;  ///< larger meshes are refused (memory, time)
  /// Close a surface that stays open or non-manifold after repair by 3D alpha wrapping
  /// (CGAL::alpha_wrap_3): the solid becomes a watertight envelope `wrap_offset` outside the
  /// input that does not enter openings narrower than about `wrap_alpha`. Needs repair.
  bool wrap = false;
  double wrap_alpha = 0.0;   ///< metres, >= 0; 0: bounding-box diagonal / 100
  double wrap_offset = 0.0;  ///< metres, >= 0; 0: bounding-box diagonal / 3000
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// What loading found and did.
struct MeshLoadReport {
  std::string path;                   ///< the file read ("" for an in-memory mesh)
  std::string format;                 ///< assimp's format id or file extension, e.g. "obj"
  std::size_t input_vertices = 0;     ///< vertex count as read, all meshes of the scene merged
  std::size_t input_faces = 0;        ///< triangle count as read
  std::vector<std::string> repairs;   ///< human-readable repairs done, empty if none
  bool closed = false;                ///< closed, manifold, outward solid after repair
  std::vector<std::string> warnings;  ///< accepted defects, e.g. self-intersections
};

/// Mass properties at uniform density 1 kg/m^3 (scale inertia by the real density).
struct MassProperties {
  double volume = 0.0;                                       ///< m^3, > 0 for a valid solid
  Eigen::Vector3d center_of_mass = Eigen::Vector3d::Zero();  ///< metres, object frame
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();         ///< about the centre of mass, kg m^2
  Eigen::Vector3d bounds_min = Eigen::Vector3d::Zero();      ///< axis-aligned bounds, metres
  Eigen::Vector3d bounds_max = Eigen::Vector3d::Zero();      ///< axis-aligned bounds, metres
  double torque_scale = 0.0;  ///< largest distance from the centre of mass to a vertex, metres
};

/// A surface sample: point and outward unit normal, object frame.
struct SurfaceSample {
  Eigen::Vector3d point;   ///< metres
  Eigen::Vector3d normal;  ///< unit, out of the object
  int face = -1;           ///< index of the triangle sampled
};

/// Where a ray first crosses the surface.
struct RayHit {
  double distance = 0.0;                              ///< metres along the unit direction
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    ///< metres, object frame
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< outward unit normal of the face hit
  int face = -1;                                      ///< index of the triangle hit
};

/// A closed, outward-oriented triangle mesh treated as a solid. Immutable after construction;
/// copies share state; every const method is thread-safe.
class ObjectModel {
 public:
  /// Loads any format assimp reads, merges all meshes of the scene, scales, validates and
  /// (optionally) repairs. Throws Error naming the file and the defect when the result is
  /// not a closed solid of positive volume.
  static ObjectModel load(const std::string& path, const MeshLoadOptions& options = {});
  /// Wraps a mesh already in memory (validated and repaired like a file). @param name object name.
  static ObjectModel fromMesh(const TriangleMesh& mesh, const std::string& name,
                              const MeshLoadOptions& options = {});

  /// Object name (file stem for loaded files).
  const std::string& name() const;
  /// SHA-256 of the source file bytes in hex ("" for in-memory meshes).
  const std::string& sourceSha256() const;
  /// Scale applied on load.
  double scale() const;
  /// The validated mesh, metres, outward faces.
  const TriangleMesh& mesh() const;
  /// Volume, centre of mass, inertia, bounds, torque scale.
  const MassProperties& massProperties() const;
  /// What loading found and repaired.
  const MeshLoadReport& report() const;

  /// True when p (metres, object frame) is strictly inside the solid.
  bool contains(const Eigen::Vector3d& p) const;
  /// Unsigned distance from p to the surface, metres.
  double distanceToSurface(const Eigen::Vector3d& p) const;
  /// True when the surface comes nearer p than `distance` (metres, object frame): the bounded
  /// form of distanceToSurface(p) < distance, which stops at the first face found that near.
  bool nearSurface(const Eigen::Vector3d& p, double distance) const;
  /// Nearest surface crossing of the ray origin + t direction for t in (min_distance,
  /// max_distance] (metres, object frame; direction unit). Empty when the ray meets no face
  /// there. Throws Error when direction is not a finite unit vector or the range is not
  /// 0 <= min_distance < max_distance.
  std::optional<RayHit> castRay(
      const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double min_distance = 0.0,
      double max_distance = std::numeric_limits<double>::infinity()) const;
  /// castRay's hit (the same one), and in *again whether the ray crosses the surface again
  /// past it: true when a crossing lies beyond hit + gap within max_distance (or up to 1e-9
  /// relative past it: true may be spurious there, false is exact); false without a hit. For a
  /// walk that would cast again from just past the hit (gap: its restart distance, metres);
  /// throws as castRay does, and on a gap that is not finite and >= 0.
  std::optional<RayHit> castRayAndAgain(const Eigen::Vector3d& origin,
                                        const Eigen::Vector3d& direction, double min_distance,
                                        double max_distance, double gap, bool* again) const;
  /// Uniform point inside the volume (rejection sampling in the bounds).
  Eigen::Vector3d sampleInside(Rng& rng) const;
  /// Area-weighted uniform point on the surface with its outward normal.
  SurfaceSample sampleSurface(Rng& rng) const;

  struct Impl;  ///< private implementation (CGAL, acceleration structures)

 private:
  /// The hit at distance t on face `face` of the ray origin + t direction.
  RayHit hitAt(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t,
               int face) const;
  std::shared_ptr<const Impl> impl_;
};

/// SHA-256 of a file's bytes as 64 lowercase hex digits. Throws Error if unreadable.
std::string sha256File(const std::string& path);

/// SHA-256 of a byte string as 64 lowercase hex digits.
std::string sha256Hex(const std::string& bytes);

}  // namespace taskmap
