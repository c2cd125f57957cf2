// Face-level repairs of a triangle soup (no CGAL): repeated and degenerate faces, fins of
// opposite faces, border welding, unused points. Declared in mesh_soup.hpp.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numeric>
#include <unordered_map>

#include "mesh_soup.hpp"

namespace taskmap::detail {
namespace {

/// Directed uses of each undirected edge: (face index, +1 when traversed from the smaller
/// vertex index to the larger, -1 otherwise).
using EdgeUses = std::unordered_map<std::uint64_t, std::vector<std::pair<std::size_t, int>>>;

EdgeUses edgeUses(const MeshSoup& soup, const std::vector<char>& keep) {
  EdgeUses uses;
  for (std::size_t i = 0; i < soup.faces.size(); ++i) {
    if (!keep[i]) continue;
    const auto& f = soup.faces[i];
    for (int c = 0; c < 3; ++c) {
      const int a = f[c], b = f[(c + 1) % 3];
      uses[edgeKey(a, b)].emplace_back(i, a < b ? 1 : -1);
    }
  }
  return uses;
}

/// For faces on the same vertices in both orientations: the orientation (+1: that of `face`,
/// -1: the opposite) that the rest of the surface asks for, when each of the three edges has
/// exactly one other face and all three agree; 0 otherwise (a fin: no face belongs there).
int neighbourOrientation(const MeshSoup& soup, const EdgeUses& uses, std::size_t face,
                         const std::vector<std::size_t>& group) {
  const auto& f = soup.faces[face];
  int vote = 0;
  for (int c = 0; c < 3; ++c) {
    const int a = f[c], b = f[(c + 1) % 3];
    const int dir = a < b ? 1 : -1;
    int outside = 0, agree = 0;
    for (const auto& [other, odir] : uses.at(edgeKey(a, b))) {
      if (std::find(group.begin(), group.end(), other) != group.end()) continue;
      ++outside;
      agree = odir == -dir ? 1 : -1;  // a neighbour traverses the shared edge the other way
    }
    if (outside != 1 || (vote != 0 && agree != vote)) return 0;
    vote = agree;
  }
  return vote;
}

}  // namespace

/// Drops faces with a repeated vertex and repeated faces. Identical faces with opposite
/// orientation: when the surrounding surface asks for one orientation (each edge has one other
/// face, all consistent), one face of it stays; otherwise (a zero-volume fin of a scan, whose
/// edges already have two other faces each) both faces go, since keeping either would leave
/// the surface open or non-manifold there.
DroppedFaces dropBadFaces(MeshSoup* soup) {
  DroppedFaces d;
  std::map<std::array<int, 3>, std::vector<std::size_t>> groups;
  std::vector<char> keep(soup->faces.size(), 1);
  for (std::size_t i = 0; i < soup->faces.size(); ++i) {
    const auto& f = soup->faces[i];
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) {
      ++d.degenerate;
      keep[i] = 0;
      continue;
    }
    std::array<int, 3> key = f;
    std::sort(key.begin(), key.end());
    groups[key].push_back(i);
  }
  std::unique_ptr<EdgeUses> uses;  // built on the first group with both orientations
  for (const auto& [key, faces] : groups) {
    if (faces.size() < 2) continue;
    // Faces of the group in the orientation of its first face, and in the opposite one.
    const auto first = canonicalCycle(soup->faces[faces[0]]);
    std::vector<std::size_t> same, other;
    for (std::size_t i : faces)
      (canonicalCycle(soup->faces[i]) == first ? same : other).push_back(i);
    for (std::size_t i : faces) keep[i] = 0;
    if (same.size() != other.size()) {
      // Keep the first face of the majority orientation (the minority pairs with the rest).
      const std::vector<std::size_t>& rest = same.size() > other.size() ? same : other;
      keep[rest[0]] = 1;
      d.duplicate += rest.size() - 1 - std::min(same.size(), other.size());
      d.opposite += std::min(same.size(), other.size());
      continue;
    }
    if (!uses)
      uses = std::make_unique<EdgeUses>(edgeUses(*soup, std::vector<char>(keep.size(), 1)));
    const int vote = neighbourOrientation(*soup, *uses, same[0], faces);
    if (vote == 0) {
      d.opposite += same.size();
    } else {
      keep[vote > 0 ? same[0] : other[0]] = 1;
      d.duplicate += faces.size() - 1;
    }
  }
  std::vector<std::array<int, 3>> kept;
  kept.reserve(soup->faces.size());
  for (std::size_t i = 0; i < soup->faces.size(); ++i)
    if (keep[i]) kept.push_back(soup->faces[i]);
  soup->faces = std::move(kept);
  return d;
}

/// Welds border vertices closer than tol (union-find over a hash grid). Returns the count.
std::size_t weldBorderVertices(MeshSoup* soup, const std::vector<int>& border, double tol) {
  std::vector<int> parent(soup->points.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  struct CellHash {
    std::size_t operator()(const Eigen::Vector3i& c) const {
      return static_cast<std::size_t>(c.x()) * 73856093u ^
             static_cast<std::size_t>(c.y()) * 19349663u ^
             static_cast<std::size_t>(c.z()) * 83492791u;
    }
  };
  struct CellEq {
    bool operator()(const Eigen::Vector3i& a, const Eigen::Vector3i& b) const { return a == b; }
  };
  std::unordered_map<Eigen::Vector3i, std::vector<int>, CellHash, CellEq> grid;
  auto cellOf = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / tol)),
                           static_cast<int>(std::floor(p.y() / tol)),
                           static_cast<int>(std::floor(p.z() / tol)));
  };
  std::size_t welded = 0;
  for (int v : border) {
    const Eigen::Vector3d& p = soup->points[v];
    const Eigen::Vector3i c = cellOf(p);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = grid.find(c + Eigen::Vector3i(dx, dy, dz));
          if (it == grid.end()) continue;
          for (int w : it->second) {
            if ((soup->points[w] - p).norm() <= tol) {
              const int rv = find(v), rw = find(w);
              if (rv != rw) {
                parent[rv] = rw;
                ++welded;
              }
            }
          }
        }
      }
    }
    grid[c].push_back(v);
  }
  if (welded == 0) return 0;
  for (auto& f : soup->faces) {
    for (int& v : f) v = find(v);
  }
  return welded;
}

/// Removes points no face references (left by welding, or unused in the file).
void dropUnusedPoints(MeshSoup* soup) {
  std::vector<int> remap(soup->points.size(), -1);
  std::vector<Eigen::Vector3d> points;
  for (auto& f : soup->faces) {
    for (int& v : f) {
      if (remap[v] < 0) {
        remap[v] = static_cast<int>(points.size());
        points.push_back(soup->points[v]);
      }
      v = remap[v];
    }
  }
  soup->points = std::move(points);
}

}  // namespace taskmap::detail
