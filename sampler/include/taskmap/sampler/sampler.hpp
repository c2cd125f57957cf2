#pragma once
/// @file sampler.hpp
/// Initial hand poses for grasp trials (docs/METHOD.md §2 step 1). Trial i of a run seeded
/// with s draws only from Rng(s, i), so the set of trials never depends on thread count.

#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {

/// How the initial palm pose of a trial is drawn.
enum class SamplerKind {
  /// The paper's sampler: palm origin uniform inside the object volume, orientation uniform
  /// on SO(3). The simulator then retracts the hand out of the object.
  kVolume,
  /// Area-weighted surface point, approach axis along the inward normal, uniform roll about
  /// the normal, palm origin at a uniform signed standoff along the outward normal. Finds thin
  /// parts (handles) that volume sampling rarely hits.
  kSurface,
  /// Even trial indices volume, odd trial indices surface.
  kMixed,
};

/// "volume", "surface", "mixed".
const char* toString(SamplerKind kind);
/// Parses a sampler name; throws Error listing the valid names on an unknown one.
SamplerKind samplerKindFromString(const std::string& name);

/// Options of the sampler.
struct SamplerOptions {
  SamplerKind kind = SamplerKind::kMixed;
  /// Unit direction, palm frame, in which the hand moves toward the object
  /// (HandModel::approachAxis()).
  Eigen::Vector3d approach_axis = Eigen::Vector3d::UnitZ();
  /// Surface sampler: signed distance of the palm origin from the surface point along the
  /// outward normal, uniform in [standoff_min, standoff_max], metres. Positive starts the palm
  /// outside (the simulator advances it along the approach axis until it touches), negative
  /// inside (the simulator retracts it out of the object).
  double standoff_min = 0.0;
  double standoff_max = 0.02;  ///< metres, >= standoff_min
  /// Throws Error naming the option when a value is out of range (non-unit axis, bad range).
  void validate() const;
};

/// Draws initial palm poses (palm frame in the object frame). Immutable, thread-safe.
class Sampler {
 public:
  /// @param object the solid to sample (copies share state). Throws Error on invalid options.
  Sampler(ObjectModel object, const SamplerOptions& options);

  /// Initial pose of trial `trial` of a run seeded with `seed`: a pure function of both.
  Pose sample(std::uint64_t seed, std::uint64_t trial) const;
  /// The concrete kind (kVolume or kSurface) trial `trial` uses.
  SamplerKind kindOfTrial(std::uint64_t trial) const;
  /// The options given at construction.
  const SamplerOptions& options() const { return options_; }

 private:
  ObjectModel object_;
  SamplerOptions options_;
};

/// Orientation whose rotation maps the palm-frame axis onto `direction` (both unit), followed
/// by a rotation of `roll` radians about `direction`.
Eigen::Quaterniond alignAxis(const Eigen::Vector3d& axis, const Eigen::Vector3d& direction,
                             double roll);

}  // namespace taskmap
