#include "taskmap/picture/map_picture.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/error.hpp"

#ifdef TASKMAP_HAVE_CAIRO
#include <cairo.h>

#include "picture_draw.hpp"
#endif

namespace taskmap {

void PictureOptions::validate() const {
  if (width < 800 || width > 8000) {
    throw Error("--width " + std::to_string(width) + " is out of range; give 800 to 8000 pixels");
  }
  if (height < 600 || height > 8000) {
    throw Error("--height " + std::to_string(height) + " is out of range; give 600 to 8000 pixels");
  }
}

#ifndef TASKMAP_HAVE_CAIRO

bool pictureSupported() {
  return false;
}

void writeMapPicture(const TaskMapData&, const MapSummary&, const std::string& path,
                     const PictureOptions&, const HandModel*) {
  throw Error("cannot write '" + path +
              "': this taskmap was built without cairo; install libcairo2-dev and rebuild");
}

std::string mapPicturePng(const TaskMapData&, const MapSummary& summary, const PictureOptions&,
                          const HandModel*) {
  throw Error("cannot draw the picture of '" + summary.path +
              "': this taskmap was built without cairo; install libcairo2-dev and rebuild");
}

#else

bool pictureSupported() {
  return true;
}

namespace {

using namespace picture_draw;  // NOLINT: the private drawing helpers

// One orthographic view: screen right = axis u, screen up = axis v, viewer looks along -w.
struct View {
  const char* title;
  int u, v;       // object axes shown to the right and upwards
  double toward;  // sign of the third axis pointing at the viewer
  const char* u_name;
  const char* v_name;
};

constexpr View kViews[3] = {
    {"Top view (looking down -z)", 0, 1, +1.0, "x", "y"},
    {"Front view (looking along +y)", 0, 2, -1.0, "x", "z"},
    {"Side view (looking along -x)", 1, 2, +1.0, "y", "z"},
};

int thirdAxis(const View& v) {
  return 3 - v.u - v.v;
}

struct Projector {
  Box box;
  double scale;   // pixels per metre
  double cu, cv;  // view-centre in object coordinates
  const View* view;
  double px(const Eigen::Vector3d& p) const {
    return box.x + box.w / 2 + scale * (p[view->u] - cu);
  }
  double py(const Eigen::Vector3d& p) const {
    return box.y + box.h / 2 - scale * (p[view->v] - cv);
  }
};

void drawView(cairo_t* cr, const Scene& s, const View& view, const Box& cell, double scale) {
  drawCell(cr, cell, view.title);
  const Box plot{cell.x + 10, cell.y + 34, cell.w - 20, cell.h - 44};
  Projector pr{plot, scale, 0.5 * (s.lo[view.u] + s.hi[view.u]),
               0.5 * (s.lo[view.v] + s.hi[view.v]), &view};
  cairo_save(cr);
  cairo_rectangle(cr, cell.x, cell.y + 28, cell.w, cell.h - 28);
  cairo_clip(cr);

  // Silhouette: every triangle projected, oriented counter-clockwise on screen so that the
  // non-zero fill of the whole path is the union of the triangles.
  const auto& verts = s.map->object.vertices;
  const auto& faces = s.map->object.faces;
  cairo_new_path(cr);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    double x[3], y[3];
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
      const auto idx = faces(f, k);
      if (idx < 0 || idx >= verts.rows()) {
        ok = false;
        break;
      }
      const Eigen::Vector3d p = verts.row(idx).transpose();
      x[k] = pr.px(p);
      y[k] = pr.py(p);
    }
    if (!ok) continue;
    const double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    if (area == 0.0) continue;
    const int order[3] = {0, area > 0 ? 1 : 2, area > 0 ? 2 : 1};
    cairo_move_to(cr, x[order[0]], y[order[0]]);
    cairo_line_to(cr, x[order[1]], y[order[1]]);
    cairo_line_to(cr, x[order[2]], y[order[2]]);
    cairo_close_path(cr);
  }
  cairo_set_fill_rule(cr, CAIRO_FILL_RULE_WINDING);
  setColor(cr, kSilhouette);
  cairo_fill(cr);

  // Palm positions: outliers first, then clusters from the largest (id 0) to the smallest
  // so that small clusters stay visible.
  const auto& poses = s.map->grasps.pose;
  const std::size_t n = s.map->grasps.size();
  const double radius = n <= 2000 ? 3.0 : (n <= 20000 ? 2.0 : 1.2);
  const int k_count = static_cast<int>(s.summary->clusters.size());
  for (int pass = -1; pass < k_count; ++pass) {
    setColor(cr, rgbOf(pass), pass < 0 ? 0.7 : 1.0);  // clusters opaque: exact colours
    for (std::size_t i = 0; i < n; ++i) {
      if (s.labels[i] != pass) continue;
      const Eigen::Vector3d p = poses.row(static_cast<Eigen::Index>(i)).head<3>().transpose();
      cairo_arc(cr, pr.px(p), pr.py(p), radius, 0, 2 * kPi);
      cairo_fill(cr);
    }
  }

  // The hand at each representative: the outline of every collision shape.
  for (std::size_t k = 0; k < s.hands.size(); ++k) {
    for (const PosedShapePoints& shape : s.hands[k]) {
      std::vector<Eigen::Vector2d> q;
      for (const Eigen::Vector3d& p : shape.points) q.emplace_back(pr.px(p), pr.py(p));
      drawOutline(cr, q, rgbOf(s.summary->clusters[k].id));
    }
  }

  // Representatives with their approach axis (palm +z).
  const int w = thirdAxis(view);
  for (const ClusterRow& row : s.summary->clusters) {
    const Eigen::Vector3d p = row.pose.head<3>();
    const Eigen::Vector3d tip = p + s.arrow_length * row.approach;
    const double x0 = pr.px(p), y0 = pr.py(p), x1 = pr.px(tip), y1 = pr.py(tip);
    const double in_plane = std::hypot(row.approach[view.u], row.approach[view.v]);
    if (in_plane > 0.15) drawArrow(cr, x0, y0, x1, y1, rgbOf(row.id), 2.5);
    drawRepresentative(cr, x0, y0, rgbOf(row.id), view.toward * row.approach[w], in_plane < 0.5);
    text(cr, x0 + 9, y0 - 8, std::to_string(row.id), 12, true);
  }
  cairo_restore(cr);

  // Axes glyph (bottom left) and scale bar (bottom right).
  const double ax = cell.x + 22, ay = cell.y + cell.h - 22;
  drawArrow(cr, ax, ay, ax + 38, ay, kInk, 1.2);
  drawArrow(cr, ax, ay, ax, ay - 38, kInk, 1.2);
  text(cr, ax + 42, ay + 4, view.u_name, 13, true);
  text(cr, ax - 4, ay - 44, view.v_name, 13, true);
  const double bar_m = niceBelow(0.22 * plot.w / scale);
  const double bar_px = bar_m * scale;
  const double bx = cell.x + cell.w - 20 - bar_px, by = cell.y + cell.h - 18;
  setColor(cr, kInk);
  cairo_set_line_width(cr, 2.0);
  cairo_move_to(cr, bx, by - 5);
  cairo_line_to(cr, bx, by);
  cairo_line_to(cr, bx + bar_px, by);
  cairo_line_to(cr, bx + bar_px, by - 5);
  cairo_stroke(cr);
  text(cr, bx + bar_px / 2, by - 8, lengthLabel(bar_m), 12, false, 0.5);
}

/// Draws the map picture on canvas (options.width x options.height).
void drawMapPicture(const Canvas& canvas, const TaskMapData& map, const MapSummary& summary,
                    const PictureOptions& options, const HandModel* hand) {
  Scene s;
  s.map = &map;
  s.summary = &summary;
  const std::size_t n = map.grasps.size();
  s.labels.assign(n, -1);
  if (map.clustering && map.clustering->labels.size() == n) s.labels = map.clustering->labels;
  const int k_count = static_cast<int>(summary.clusters.size());
  for (int& l : s.labels) {
    if (l >= k_count) l = -1;
  }
  if (hand != nullptr) {
    for (const ClusterRow& row : summary.clusters) {
      const bool known =
          row.representative >= 0 && static_cast<std::size_t>(row.representative) < n;
      s.hands.push_back(known ? posedShapePoints(*hand, graspPosture(map, row.representative))
                              : std::vector<PosedShapePoints>{});
    }
  }
  // Bounds of everything drawn: object vertices, palm positions and the hands.
  s.lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  s.hi = -s.lo;
  for (Eigen::Index i = 0; i < map.object.vertices.rows(); ++i) {
    s.lo = s.lo.cwiseMin(map.object.vertices.row(i).transpose());
    s.hi = s.hi.cwiseMax(map.object.vertices.row(i).transpose());
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p = map.grasps.pose.row(static_cast<Eigen::Index>(i)).head<3>();
    s.lo = s.lo.cwiseMin(p);
    s.hi = s.hi.cwiseMax(p);
  }
  for (const auto& shapes : s.hands) {
    for (const PosedShapePoints& shape : shapes) {
      for (const Eigen::Vector3d& p : shape.points) {
        s.lo = s.lo.cwiseMin(p);
        s.hi = s.hi.cwiseMax(p);
      }
    }
  }
  if (!(s.lo.allFinite() && s.hi.allFinite())) {
    s.lo = Eigen::Vector3d::Constant(-0.05);
    s.hi = Eigen::Vector3d::Constant(0.05);
  }
  const double extent = std::max((s.hi - s.lo).maxCoeff(), 1e-6);
  s.arrow_length = 0.18 * extent;
  // Arrows may reach beyond the bounds: pad by the arrow length.
  s.lo -= Eigen::Vector3d::Constant(s.arrow_length);
  s.hi += Eigen::Vector3d::Constant(s.arrow_length);

  const double W = options.width, H = options.height;
  cairo_t* cr = canvas.cr();

  cairo_set_source_rgb(cr, 0.96, 0.96, 0.95);
  cairo_paint(cr);
  const std::string title = "Task map: " + summary.object_name + " with " + summary.hand_name +
                            " hand, " + std::to_string(summary.grasps) + " grasps, " +
                            std::to_string(summary.clusters.size()) + " clusters";
  text(cr, 20, 34, title, 22, true);
  // The file name only: a picture checked into docs/ must not show the machine's directories.
  text(cr, 20, 58, std::filesystem::path(summary.path).filename().string(), 13, false, 0.0,
       Rgb{0.35, 0.35, 0.35});

  const double legend_w = 300;
  const Box area{20, 72, W - 40 - legend_w - 10, H - 72 - 20};
  const double gap = 12;
  const double cw = (area.w - gap) / 2, ch = (area.h - gap) / 2;
  const Box cells[4] = {{area.x, area.y, cw, ch},
                        {area.x + cw + gap, area.y, cw, ch},
                        {area.x, area.y + ch + gap, cw, ch},
                        {area.x + cw + gap, area.y + ch + gap, cw, ch}};
  // One scale for the three views so that they compare.
  double scale = std::numeric_limits<double>::infinity();
  for (const View& v : kViews) {
    const double pw = cw - 20 - 20, ph = ch - 44 - 40;  // room for title and scale bar
    const double du = std::max(s.hi[v.u] - s.lo[v.u], 1e-9);
    const double dv = std::max(s.hi[v.v] - s.lo[v.v], 1e-9);
    scale = std::min({scale, pw / du, ph / dv});
  }
  drawView(cr, s, kViews[0], cells[0], scale);
  drawView(cr, s, kViews[1], cells[1], scale);
  drawView(cr, s, kViews[2], cells[2], scale);
  drawHistogram(cr, s, cells[3]);
  drawLegend(cr, s, Box{W - 20 - legend_w, area.y, legend_w, area.h});
}

}  // namespace

void writeMapPicture(const TaskMapData& map, const MapSummary& summary, const std::string& path,
                     const PictureOptions& options, const HandModel* hand) {
  options.validate();
  const Canvas canvas(options.width, options.height, CAIRO_FORMAT_RGB24, path);
  drawMapPicture(canvas, map, summary, options, hand);
  canvas.write();
}

std::string mapPicturePng(const TaskMapData& map, const MapSummary& summary,
                          const PictureOptions& options, const HandModel* hand) {
  options.validate();
  const Canvas canvas(options.width, options.height, CAIRO_FORMAT_RGB24, summary.path);
  drawMapPicture(canvas, map, summary, options, hand);
  return canvas.png();
}

#endif  // TASKMAP_HAVE_CAIRO

}  // namespace taskmap
