// The inside grid of MeshBvh: cells the surface cannot cross, labelled inside or outside once,
// so that most inside tests are a lookup (docs/METHOD.md §2, "Inside tests").
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "mesh_bvh.hpp"

namespace taskmap::detail {
namespace {

/// Cells per triangle, and the bounds of the grid's size: 16 per triangle between 32 Ki and
/// 256 Ki cells (a 16k-face scan: 256 KiB of labels, built in a few milliseconds; the reference
/// objects' few hundred faces: 32 Ki). A flat or long box may take up to 4 times more.
constexpr double kCellsPerTriangle = 16.0;
constexpr double kMinCells = 32768.0;
constexpr double kMaxCells = 262144.0;

}  // namespace

void MeshBvh::buildInsideGrid() {
  const Eigen::Vector3d lo = nodes_[0].lo, hi = nodes_[0].hi;
  const Eigen::Vector3d extent = (hi - lo).cwiseMax(1e-3 * (hi - lo).maxCoeff());
  if (!(extent.maxCoeff() > 0.0) || !extent.allFinite()) return;
  const double target =
      std::clamp(kCellsPerTriangle * static_cast<double>(a_.size()), kMinCells, kMaxCells);
  double h = std::cbrt(extent.prod() / target);
  // One free cell around the root box on each side: the outside wraps around the object.
  const auto cells = [&] { return ((hi - lo) / h).array().ceil().cast<int>() + 2; };
  while (static_cast<double>(cells().cast<double>().prod()) > 4.0 * target) h *= 1.25;
  grid_.cell = h;
  grid_.n = cells().matrix();
  grid_.origin = lo - Eigen::Vector3d::Constant(h);
  grid_.label.assign(static_cast<std::size_t>(grid_.n.prod()), InsideGrid::kUnknown);
  markSurfaceCells();
  labelFreeCells();
}

void MeshBvh::markSurfaceCells() {
  const double h = grid_.cell;
  // A cell holds no surface point when no triangle comes within its half diagonal of its
  // centre; the radius is grown so that rounding in the cell index of a point near a cell's
  // border (relative 1e-16) and here cannot matter.
  const double r = 0.5 * std::sqrt(3.0) * h * (1.0 + 1e-9) + 4.0 * eps_;
  const double r2 = r * r;
  const Eigen::Array3i top = grid_.n.array() - 1;
  const auto index = [&](const Eigen::Vector3d& x) {
    return ((x - grid_.origin) / h).array().floor().cast<int>().max(0).min(top);
  };
  for (std::size_t i = 0; i < a_.size(); ++i) {
    const Eigen::Vector3d tlo = a_[i].cwiseMin(b_[i]).cwiseMin(c_[i]).array() - r;
    const Eigen::Vector3d thi = a_[i].cwiseMax(b_[i]).cwiseMax(c_[i]).array() + r;
    const Eigen::Array3i from = index(tlo), to = index(thi);
    const Eigen::Vector3d normal = e1_[i].cross(e2_[i]);
    const double nn = normal.norm();
    for (int z = from.z(); z <= to.z(); ++z)
      for (int y = from.y(); y <= to.y(); ++y)
        for (int x = from.x(); x <= to.x(); ++x) {
          const std::size_t k = static_cast<std::size_t>(x + grid_.n.x() * (y + grid_.n.y() * z));
          if (grid_.label[k] == InsideGrid::kSurface) continue;
          const Eigen::Vector3d centre =
              grid_.origin + h * Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5);
          // The plane first: most cells of the box lie off the triangle's plane.
          if (nn > 0.0 && std::abs(normal.dot(centre - a_[i])) > r * nn * (1.0 + 1e-9)) continue;
          if ((closestOnTriangle(centre, a_[i], b_[i], c_[i]) - centre).squaredNorm() <= r2)
            grid_.label[k] = InsideGrid::kSurface;
        }
  }
}

void MeshBvh::labelFreeCells() {
  const Eigen::Vector3i n = grid_.n;
  const std::int64_t sx = 1, sy = n.x(), sz = static_cast<std::int64_t>(n.x()) * n.y();
  std::vector<std::int64_t> queue;
  for (std::int64_t k = 0; k < static_cast<std::int64_t>(grid_.label.size()); ++k) {
    if (grid_.label[static_cast<std::size_t>(k)] != InsideGrid::kUnknown) continue;
    const int x = static_cast<int>(k % sy), y = static_cast<int>((k / sy) % n.y()),
              z = static_cast<int>(k / sz);
    const Eigen::Vector3d centre =
        grid_.origin + grid_.cell * Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5);
    const unsigned char lab = containsByRays(centre) ? InsideGrid::kInside : InsideGrid::kOutside;
    // Flood the group of free cells 6-connected to this one: the segment between two
    // neighbouring centres stays in the two cells, which hold no surface point.
    grid_.label[static_cast<std::size_t>(k)] = lab;
    queue.assign(1, k);
    while (!queue.empty()) {
      const std::int64_t c = queue.back();
      queue.pop_back();
      const int cx = static_cast<int>(c % sy), cy = static_cast<int>((c / sy) % n.y()),
                cz = static_cast<int>(c / sz);
      const std::int64_t nb[6] = {cx > 0 ? c - sx : -1, cx + 1 < n.x() ? c + sx : -1,
                                  cy > 0 ? c - sy : -1, cy + 1 < n.y() ? c + sy : -1,
                                  cz > 0 ? c - sz : -1, cz + 1 < n.z() ? c + sz : -1};
      for (const std::int64_t m : nb) {
        if (m < 0 || grid_.label[static_cast<std::size_t>(m)] != InsideGrid::kUnknown) continue;
        grid_.label[static_cast<std::size_t>(m)] = lab;
        queue.push_back(m);
      }
    }
  }
}

MeshBvh::InsideGrid::Label MeshBvh::gridLabel(const Eigen::Vector3d& p) const {
  if (grid_.label.empty()) return InsideGrid::kUnknown;
  const Eigen::Vector3d u = (p - grid_.origin) / grid_.cell;
  const Eigen::Vector3d f = u.array().floor();
  if ((f.array() < 0.0).any() || (f.array() >= grid_.n.cast<double>().array()).any())
    return InsideGrid::kUnknown;
  const std::size_t k = static_cast<std::size_t>(
      f.x() + grid_.n.x() * (f.y() + static_cast<double>(grid_.n.y()) * f.z()));
  return static_cast<InsideGrid::Label>(grid_.label[k]);
}

}  // namespace taskmap::detail
