#pragma once
/// @file random.hpp
/// Deterministic, platform-independent random numbers. Trial i of a run seeded with s draws
/// from Rng(s, i) alone, so results do not depend on thread count or scheduling.

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace taskmap {

/// xoshiro256** generator seeded from (seed, stream) by splitmix64. The same (seed, stream)
/// gives the same sequence on every platform and compiler (no std:: distributions are used).
class Rng {
 public:
  /// @param seed run seed. @param stream independent stream index (for example the trial index).
  explicit Rng(std::uint64_t seed, std::uint64_t stream = 0);
  /// Next raw 64-bit value.
  std::uint64_t next();
  /// Uniform double in [0, 1), 53 random bits.
  double uniform();
  /// Uniform double in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n); n > 0. Unbiased (rejection).
  std::uint64_t below(std::uint64_t n);
  /// Standard normal variate (Box-Muller, no cached state).
  double normal();
  /// Uniformly distributed rotation on SO(3) (Shoemake's method), qw >= 0.
  Eigen::Quaterniond rotation();
  /// Uniform unit vector on the sphere S^2.
  Eigen::Vector3d direction();

 private:
  std::uint64_t s_[4];
};

}  // namespace taskmap
