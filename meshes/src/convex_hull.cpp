// Convex hull of a 3-D point set through reentrant qhull (libqhull_r C API); every call owns
// its qhT, so hand models load in parallel without a lock.
#include "convex_hull.hpp"

#include <algorithm>
#include <cstdio>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include "taskmap/core/error.hpp"

namespace taskmap::detail {
namespace {

/// qhull must not print: warnings and errors go to /dev/null (opened once, stdio locks it).
FILE* silentSink() {
  static FILE* sink = std::fopen("/dev/null", "w");
  return sink;
}

/// Owns one qhull instance; frees it on every path.
class QhullRun {
 public:
  QhullRun() { qh_zero(&qh_, silentSink()); }
  ~QhullRun() {
    qh_freeqhull(&qh_, !qh_ALL);
    int curlong = 0, totlong = 0;
    qh_memfreeshort(&qh_, &curlong, &totlong);
  }
  QhullRun(const QhullRun&) = delete;
  QhullRun& operator=(const QhullRun&) = delete;
  qhT* get() { return &qh_; }

 private:
  qhT qh_;
};

}  // namespace

PointHull convexHull(const std::vector<Eigen::Vector3d>& points, const std::string& what) {
  if (points.size() < 4) throw Error(what + " has fewer than 4 distinct vertices");
  std::vector<coordT> coords;
  coords.reserve(3 * points.size());
  for (const auto& p : points) coords.insert(coords.end(), {p.x(), p.y(), p.z()});
  char flags[] = "qhull Qt FA";
  QhullRun run;
  qhT* qh = run.get();
  const int code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False, flags,
                                nullptr, silentSink());
  if (code != 0)
    throw Error(what + " is flat or degenerate: qhull could not build its convex hull (exit " +
                std::to_string(code) + ")");
  PointHull hull;
  for (vertexT* v = qh->vertex_list; v && v->next; v = v->next) {
    const int id = qh_pointid(qh, v->point);
    hull.vertices.push_back(points[static_cast<std::size_t>(id)]);
  }
  std::sort(hull.vertices.begin(), hull.vertices.end(),
            [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
              return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
            });
  hull.volume = qh->totvol;
  return hull;
}

}  // namespace taskmap::detail
