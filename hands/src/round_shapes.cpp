// Capsules and ellipsoids as points of an inscribed convex polytope (round_shapes.hpp).
#include "round_shapes.hpp"

#include <cmath>

#include "taskmap/core/constants.hpp"

namespace taskmap::detail {
namespace {

constexpr int kAround = 24;  // points per ring
constexpr int kRings = 6;    // rings from the equator (included) to a pole (excluded)

/// Unit-sphere points of one hemisphere (sign +1 north, -1 south): the rings from `first` (0:
/// the equator) and the pole.
void hemisphere(double sign, int first, std::vector<Eigen::Vector3d>* out) {
  for (int k = first; k < kRings; ++k) {
    const double lat = sign * 0.5 * kPi * k / kRings;
    for (int i = 0; i < kAround; ++i) {
      const double lon = 2.0 * kPi * i / kAround;
      out->emplace_back(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon),
                        std::sin(lat));
    }
  }
  out->emplace_back(0.0, 0.0, sign);
}

}  // namespace

std::vector<Eigen::Vector3d> capsulePoints(double r, double length) {
  std::vector<Eigen::Vector3d> north, south, out;
  hemisphere(1.0, 0, &north);
  hemisphere(-1.0, 0, &south);
  for (const auto& p : north) out.push_back(r * p + Eigen::Vector3d(0, 0, 0.5 * length));
  for (const auto& p : south) out.push_back(r * p - Eigen::Vector3d(0, 0, 0.5 * length));
  return out;
}

std::vector<Eigen::Vector3d> ellipsoidPoints(const Eigen::Vector3d& radii) {
  std::vector<Eigen::Vector3d> unit, out;
  hemisphere(1.0, 0, &unit);
  hemisphere(-1.0, 1, &unit);  // the equator once
  for (const auto& p : unit) out.push_back(p.cwiseProduct(radii));
  return out;
}

}  // namespace taskmap::detail
