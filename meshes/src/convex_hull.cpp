// Convex hull of a 3-D point set through runQhull (taskmap/meshes/qhull_run.hpp).
#include "taskmap/meshes/convex_hull.hpp"

#include <algorithm>

#include "taskmap/core/error.hpp"
#include "taskmap/meshes/qhull_run.hpp"

namespace taskmap {

PointHull convexHull(const std::vector<Eigen::Vector3d>& points, const std::string& what) {
  if (points.size() < 4) throw Error(what + " has fewer than 4 distinct vertices");
  std::vector<double> coords;
  coords.reserve(3 * points.size());
  for (const auto& p : points) coords.insert(coords.end(), {p.x(), p.y(), p.z()});
  const QhullOutput q = runQhull(3, coords, "Qt FA", false, true);
  if (q.exit_code != 0)
    throw Error(what + " is flat or degenerate: qhull could not build its convex hull (exit " +
                std::to_string(q.exit_code) + ")");
  PointHull hull;
  for (const int id : q.vertices) hull.vertices.push_back(points[static_cast<std::size_t>(id)]);
  std::sort(hull.vertices.begin(), hull.vertices.end(),
            [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
              return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
            });
  hull.volume = q.volume;
  return hull;
}

}  // namespace taskmap
