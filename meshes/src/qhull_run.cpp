// runQhull (taskmap/meshes/qhull_run.hpp): the reentrant qhull C API behind Eigen values.
// Every call owns its qhT, so hulls are built in parallel without a lock.
#include "taskmap/meshes/qhull_run.hpp"

#include <cstdio>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

/// qhull must not print: warnings and errors go to /dev/null (opened once, stdio locks it).
FILE* silentSink() {
  static FILE* sink = std::fopen("/dev/null", "w");
  return sink;
}

const char* exitName(int code) {
  switch (code) {
    case qh_ERRinput:
      return "input error";
    case qh_ERRsingular:
      return "singular input (initial simplex is flat)";
    case qh_ERRprec:
      return "precision error";
    case qh_ERRmem:
      return "out of memory";
    case qh_ERRqhull:
      return "internal error";
    case qh_ERRtopology:
      return "topology error";
    case qh_ERRwide:
      return "wide facet error";
    case qh_ERRdebug:
      return "debug exit";
    default:
      return "unknown error";
  }
}

/// Owns one qhull instance; frees it on every path.
class QhullRun {
 public:
  explicit QhullRun(FILE* err) { qh_zero(&qh_, err); }
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

void copyFacets(qhT* qh, int dim, QhullOutput* out) {
  int n = 0;
  for (facetT* f = qh->facet_list; f && f->next; f = f->next) ++n;
  out->normals.resize(dim, n);
  out->offsets.resize(n);
  int i = 0;
  for (facetT* f = qh->facet_list; f && f->next; f = f->next, ++i) {
    for (int k = 0; k < dim; ++k) out->normals(k, i) = f->normal[k];
    out->offsets(i) = f->offset;
  }
}

}  // namespace

QhullOutput runQhull(int dim, const std::vector<double>& coords, const std::string& flags,
                     bool facets, bool vertices) {
  if (dim < 2 || dim > 9 || coords.size() % static_cast<std::size_t>(dim) != 0)
    throw Error("runQhull: " + std::to_string(coords.size()) +
                " coordinates are not points of dimension " + std::to_string(dim) + " in [2, 9]");
  QhullOutput out;
  FILE* sink = silentSink();
  if (sink == nullptr) {
    out.exit_code = qh_ERRqhull;
    out.error = "cannot open /dev/null to keep qhull silent";
    return out;
  }
  // qhull takes non-const pointers: copies.
  std::vector<coordT> points(coords.begin(), coords.end());
  std::string flag_text = "qhull " + flags;
  QhullRun run(sink);
  qhT* qh = run.get();
  const int n = static_cast<int>(coords.size() / static_cast<std::size_t>(dim));
  out.exit_code = qh_new_qhull(qh, dim, n, points.data(), False, flag_text.data(), nullptr, sink);
  if (out.exit_code != 0) {
    out.singular = out.exit_code == qh_ERRsingular;
    out.error = exitName(out.exit_code);
    return out;
  }
  if (facets) copyFacets(qh, dim, &out);
  if (vertices)
    for (vertexT* v = qh->vertex_list; v && v->next; v = v->next)
      out.vertices.push_back(qh_pointid(qh, v->point));
  out.volume = qh->hasAreaVolume ? qh->totvol : 0.0;
  return out;
}

}  // namespace taskmap
