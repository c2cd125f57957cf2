#include "taskmap/sampler/sampler.hpp"

#include <cmath>
#include <utility>

#include <Eigen/Geometry>

#include "taskmap/core/error.hpp"
#include "taskmap/core/random.hpp"

namespace taskmap {

const char* toString(SamplerKind kind) {
  switch (kind) {
    case SamplerKind::kVolume:
      return "volume";
    case SamplerKind::kSurface:
      return "surface";
    case SamplerKind::kMixed:
      return "mixed";
  }
  return "mixed";
}

SamplerKind samplerKindFromString(const std::string& name) {
  if (name == "volume") return SamplerKind::kVolume;
  if (name == "surface") return SamplerKind::kSurface;
  if (name == "mixed") return SamplerKind::kMixed;
  throw Error("unknown sampler '" + name + "': use volume, surface or mixed");
}

void SamplerOptions::validate() const {
  if (!approach_axis.allFinite() || std::abs(approach_axis.norm() - 1.0) > 1e-6)
    throw Error("sampler approach_axis must be a finite unit vector");
  if (!std::isfinite(standoff_min) || !std::isfinite(standoff_max))
    throw Error("sampler standoff_min and standoff_max must be finite (metres)");
  if (standoff_min > standoff_max) throw Error("sampler standoff_min must not exceed standoff_max");
}

Sampler::Sampler(ObjectModel object, const SamplerOptions& options)
    : object_(std::move(object)), options_(options) {
  options_.validate();
}

SamplerKind Sampler::kindOfTrial(std::uint64_t trial) const {
  if (options_.kind != SamplerKind::kMixed) return options_.kind;
  return trial % 2 == 0 ? SamplerKind::kVolume : SamplerKind::kSurface;
}

Eigen::Quaterniond alignAxis(const Eigen::Vector3d& axis, const Eigen::Vector3d& direction,
                             double roll) {
  const Eigen::Quaterniond align = Eigen::Quaterniond::FromTwoVectors(axis, direction);
  const Eigen::Quaterniond spin(Eigen::AngleAxisd(roll, direction));
  return (spin * align).normalized();
}

Pose Sampler::sample(std::uint64_t seed, std::uint64_t trial) const {
  Rng rng(seed, trial);
  Pose pose;
  if (kindOfTrial(trial) == SamplerKind::kVolume) {
    pose.position = object_.sampleInside(rng);
    pose.orientation = rng.rotation();
    return pose;
  }
  const SurfaceSample s = object_.sampleSurface(rng);
  const double roll = rng.uniform(0.0, 2.0 * M_PI);
  const double standoff = rng.uniform(options_.standoff_min, options_.standoff_max);
  pose.orientation = alignAxis(options_.approach_axis, -s.normal, roll);
  pose.position = s.point + standoff * s.normal;
  return pose;
}

}  // namespace taskmap
