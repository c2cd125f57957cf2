#include "map_picture.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

#include "taskmap/meshes/error.hpp"

#ifdef TASKMAP_HAVE_CAIRO
#include <cairo.h>
#endif

namespace taskmap::cli {

void PictureOptions::validate() const {
  if (width < 800 || width > 8000) {
    throw Error("--width " + std::to_string(width) + " is out of range; give 800 to 8000 pixels");
  }
  if (height < 600 || height > 8000) {
    throw Error("--height " + std::to_string(height) +
                " is out of range; give 600 to 8000 pixels");
  }
}

#ifndef TASKMAP_HAVE_CAIRO

bool pictureSupported() { return false; }

void writeMapPicture(const TaskMapData&, const MapSummary&, const std::string& path,
                     const PictureOptions&) {
  throw Error("cannot write '" + path +
              "': this taskmap was built without cairo; install libcairo2-dev and rebuild");
}

#else

bool pictureSupported() { return true; }

namespace {

struct Rgb {
  double r, g, b;
};

Rgb rgbOf(int cluster) {
  const auto c = clusterColor(cluster);
  return {c[0] / 255.0, c[1] / 255.0, c[2] / 255.0};
}

void setColor(cairo_t* cr, const Rgb& c, double alpha = 1.0) {
  cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

constexpr double kPi = 3.14159265358979323846;
constexpr Rgb kInk{0.12, 0.12, 0.12};
constexpr Rgb kSilhouette{0.80, 0.80, 0.80};
constexpr Rgb kFrame{0.55, 0.55, 0.55};

struct Box {
  double x, y, w, h;
};

void text(cairo_t* cr, double x, double y, const std::string& s, double size, bool bold = false,
          double align = 0.0, const Rgb& color = kInk) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t ext;
  cairo_text_extents(cr, s.c_str(), &ext);
  setColor(cr, color);
  cairo_move_to(cr, x - align * ext.x_advance, y);
  cairo_show_text(cr, s.c_str());
}

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, v);
  return buf;
}

// A "nice" number (1, 2 or 5 times a power of ten) not above x.
double niceBelow(double x) {
  if (!(x > 0)) return 1.0;
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {5.0, 2.0, 1.0}) {
    if (m * p <= x) return m * p;
  }
  return p;
}

std::string lengthLabel(double metres) {
  if (metres >= 1.0) return format("%g m", metres);
  if (metres >= 0.01) return format("%g cm", std::round(metres * 1e4) / 100.0);
  return format("%g mm", std::round(metres * 1e6) / 1000.0);
}

// One orthographic view: screen right = axis u, screen up = axis v, viewer looks along -w.
struct View {
  const char* title;
  int u, v;           // object axes shown to the right and upwards
  double toward;      // sign of the third axis pointing at the viewer
  const char* u_name;
  const char* v_name;
};

constexpr View kViews[3] = {
    {"Top view (looking down -z)", 0, 1, +1.0, "x", "y"},
    {"Front view (looking along +y)", 0, 2, -1.0, "x", "z"},
    {"Side view (looking along -x)", 1, 2, +1.0, "y", "z"},
};

int thirdAxis(const View& v) { return 3 - v.u - v.v; }

struct Projector {
  Box box;
  double scale;       // pixels per metre
  double cu, cv;      // view-centre in object coordinates
  const View* view;
  double px(const Eigen::Vector3d& p) const { return box.x + box.w / 2 + scale * (p[view->u] - cu); }
  double py(const Eigen::Vector3d& p) const { return box.y + box.h / 2 - scale * (p[view->v] - cv); }
};

void drawArrow(cairo_t* cr, double x0, double y0, double x1, double y1, const Rgb& c,
               double width) {
  const double dx = x1 - x0, dy = y1 - y0;
  const double len = std::hypot(dx, dy);
  if (len < 1e-9) return;
  const double ux = dx / len, uy = dy / len;
  const double head = std::min(12.0, 0.5 * len);
  const double bx = x1 - head * ux, by = y1 - head * uy;
  for (int pass = 0; pass < 2; ++pass) {
    const double w = pass == 0 ? width + 2.5 : width;
    if (pass == 0) {
      setColor(cr, kInk);
    } else {
      setColor(cr, c);
    }
    cairo_set_line_width(cr, w);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    cairo_move_to(cr, x0, y0);
    cairo_line_to(cr, bx, by);
    cairo_stroke(cr);
    cairo_move_to(cr, x1 + (pass == 0 ? 1.5 * ux : 0), y1 + (pass == 0 ? 1.5 * uy : 0));
    const double hw = 0.55 * head + (pass == 0 ? 1.3 : 0.0);
    cairo_line_to(cr, bx - hw * uy - (pass == 0 ? ux : 0), by + hw * ux - (pass == 0 ? uy : 0));
    cairo_line_to(cr, bx + hw * uy - (pass == 0 ? ux : 0), by - hw * ux - (pass == 0 ? uy : 0));
    cairo_close_path(cr);
    cairo_fill(cr);
  }
}

// Representative marker: filled disc in the cluster colour with a dark rim; a dot inside if
// the approach axis points at the viewer, a cross if it points away (when it is mostly
// perpendicular to the view plane).
void drawRepresentative(cairo_t* cr, double x, double y, const Rgb& c, double toward_viewer,
                        bool axial) {
  const double r = 7.0;
  cairo_new_path(cr);
  cairo_arc(cr, x, y, r, 0, 2 * kPi);
  setColor(cr, c);
  cairo_fill_preserve(cr);
  setColor(cr, kInk);
  cairo_set_line_width(cr, 2.0);
  cairo_stroke(cr);
  if (!axial) return;
  cairo_new_path(cr);
  if (toward_viewer > 0) {
    cairo_arc(cr, x, y, 2.2, 0, 2 * kPi);
    cairo_fill(cr);
  } else {
    cairo_set_line_width(cr, 1.8);
    const double d = 0.6 * r;
    cairo_move_to(cr, x - d, y - d);
    cairo_line_to(cr, x + d, y + d);
    cairo_move_to(cr, x - d, y + d);
    cairo_line_to(cr, x + d, y - d);
    cairo_stroke(cr);
  }
}

struct Scene {
  const TaskMapData* map;
  const MapSummary* summary;
  std::vector<int> labels;           // per grasp, -1 outlier (all -1 when not clustered)
  Eigen::Vector3d lo, hi;            // bounds of object and palm positions, metres
  double arrow_length;               // metres
};

void drawView(cairo_t* cr, const Scene& s, const View& view, const Box& cell, double scale) {
  // Frame and title.
  cairo_rectangle(cr, cell.x, cell.y, cell.w, cell.h);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_fill_preserve(cr);
  setColor(cr, kFrame);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
  text(cr, cell.x + 10, cell.y + 22, view.title, 15, true);
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

  // Representatives with their approach axis (palm +z).
  const int w = thirdAxis(view);
  for (const ClusterRow& row : s.summary->clusters) {
    const Eigen::Vector3d p = row.pose.head<3>();
    const Eigen::Vector3d tip = p + s.arrow_length * row.approach;
    const double x0 = pr.px(p), y0 = pr.py(p), x1 = pr.px(tip), y1 = pr.py(tip);
    const double in_plane = std::hypot(row.approach[view.u], row.approach[view.v]);
    if (in_plane > 0.15) drawArrow(cr, x0, y0, x1, y1, rgbOf(row.id), 2.5);
    drawRepresentative(cr, x0, y0, rgbOf(row.id), view.toward * row.approach[w],
                       in_plane < 0.5);
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

void drawHistogram(cairo_t* cr, const Scene& s, const Box& cell) {
  cairo_rectangle(cr, cell.x, cell.y, cell.w, cell.h);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_fill_preserve(cr);
  setColor(cr, kFrame);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
  text(cr, cell.x + 10, cell.y + 22, "Epsilon per cluster (stacked, all grasps)", 15, true);

  const auto& eps = s.map->grasps.epsilon;
  const int k_count = static_cast<int>(s.summary->clusters.size());
  double emax = 0.0;
  for (double e : eps) emax = std::max(emax, e);
  if (!(emax > 0)) emax = 1.0;
  // Round the range up to a multiple of a nice tick step.
  double xstep = niceBelow(emax / 4.0);
  if (emax / xstep > 6) xstep = niceBelow(emax / 2.5);
  const int xticks = static_cast<int>(std::ceil(emax / xstep - 1e-9));
  emax = xticks * xstep;
  constexpr int kBins = 20;
  // counts[bin][cluster + 1], column 0 = outliers.
  std::vector<std::vector<int>> counts(kBins, std::vector<int>(k_count + 1, 0));
  for (std::size_t i = 0; i < eps.size() && i < s.labels.size(); ++i) {
    int b = static_cast<int>(std::floor(eps[i] / emax * kBins));
    b = std::clamp(b, 0, kBins - 1);
    ++counts[b][s.labels[i] + 1];
  }
  int cmax = 1;
  for (const auto& bin : counts) {
    int t = 0;
    for (int c : bin) t += c;
    cmax = std::max(cmax, t);
  }
  const Box plot{cell.x + 70, cell.y + 45, cell.w - 95, cell.h - 100};
  // Y ticks.
  const double ystep = std::max(1.0, niceBelow(cmax / 4.0));
  cairo_set_line_width(cr, 1.0);
  for (double yv = 0; yv <= cmax + 1e-9; yv += ystep) {
    const double y = plot.y + plot.h - plot.h * yv / cmax;
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, plot.x, y);
    cairo_line_to(cr, plot.x + plot.w, y);
    cairo_stroke(cr);
    text(cr, plot.x - 8, y + 4, format("%.0f", yv), 12, false, 1.0);
  }
  // Bars: clusters 0..K-1 from the bottom, outliers on top.
  const double bw = plot.w / kBins;
  for (int b = 0; b < kBins; ++b) {
    double base = 0;
    for (int col = 1; col <= k_count + 1; ++col) {
      const int c = col == k_count + 1 ? 0 : col;
      const int cnt = counts[b][c];
      if (cnt == 0) continue;
      const double y0 = plot.y + plot.h - plot.h * (base + cnt) / cmax;
      const double hgt = plot.h * cnt / cmax;
      cairo_rectangle(cr, plot.x + b * bw + 1, y0, bw - 2, hgt);
      setColor(cr, rgbOf(c - 1));
      cairo_fill(cr);
      base += cnt;
    }
  }
  // Axes and x ticks.
  setColor(cr, kInk);
  cairo_set_line_width(cr, 1.5);
  cairo_move_to(cr, plot.x, plot.y);
  cairo_line_to(cr, plot.x, plot.y + plot.h);
  cairo_line_to(cr, plot.x + plot.w, plot.y + plot.h);
  cairo_stroke(cr);
  for (int t = 0; t <= xticks; ++t) {
    const double x = plot.x + plot.w * t / xticks;
    cairo_move_to(cr, x, plot.y + plot.h);
    cairo_line_to(cr, x, plot.y + plot.h + 5);
    cairo_stroke(cr);
    text(cr, x, plot.y + plot.h + 20, format("%.3g", xstep * t), 12, false, 0.5);
  }
  text(cr, plot.x + plot.w / 2, plot.y + plot.h + 42,
       "epsilon (Ferrari-Canny, largest ball in the grasp wrench space)", 13, false, 0.5);
  cairo_save(cr);
  cairo_translate(cr, cell.x + 20, plot.y + plot.h / 2);
  cairo_rotate(cr, -kPi / 2);
  text(cr, 0, 0, "grasps", 13, false, 0.5);
  cairo_restore(cr);
}

void drawLegend(cairo_t* cr, const Scene& s, const Box& box) {
  double y = box.y + 20;
  text(cr, box.x, y, "Clusters", 16, true);
  y += 10;
  const auto& rows = s.summary->clusters;
  const std::size_t shown = std::min<std::size_t>(rows.size(), 28);
  for (std::size_t k = 0; k < shown; ++k) {
    y += 22;
    cairo_rectangle(cr, box.x, y - 12, 16, 16);
    setColor(cr, rgbOf(rows[k].id));
    cairo_fill(cr);
    text(cr, box.x + 24, y + 1,
         std::to_string(rows[k].id) + ": " + std::to_string(rows[k].size) + " grasps, best " +
             format("%.3g", rows[k].best_epsilon),
         13);
  }
  if (shown < rows.size()) {
    y += 22;
    text(cr, box.x, y, "... and " + std::to_string(rows.size() - shown) + " more", 13);
  }
  if (!s.summary->clustered) {
    y += 22;
    text(cr, box.x, y, "(map holds no clustering)", 13);
  }
  y += 22;
  cairo_new_path(cr);
  cairo_arc(cr, box.x + 8, y - 4, 4, 0, 2 * kPi);
  setColor(cr, rgbOf(-1));
  cairo_fill(cr);
  text(cr, box.x + 24, y + 1,
       "outliers: " + std::to_string(std::count(s.labels.begin(), s.labels.end(), -1)), 13);
  y += 36;
  text(cr, box.x, y, "Markers", 16, true);
  y += 26;
  cairo_new_path(cr);
  cairo_arc(cr, box.x + 8, y - 4, 3, 0, 2 * kPi);
  setColor(cr, kInk);
  cairo_fill(cr);
  text(cr, box.x + 24, y + 1, "palm position of a grasp", 13);
  y += 26;
  drawArrow(cr, box.x + 8, y - 4, box.x + 8 + 40, y - 4, kFrame, 2.5);
  drawRepresentative(cr, box.x + 8, y - 4, kFrame, 1, false);
  text(cr, box.x + 56, y + 1, "representative, arrow =", 13);
  y += 18;
  text(cr, box.x + 56, y + 1, "approach (palm +z axis)", 13);
  y += 26;
  drawRepresentative(cr, box.x + 8, y - 4, kFrame, 1, true);
  text(cr, box.x + 24, y + 1, "approach towards viewer", 13);
  y += 24;
  drawRepresentative(cr, box.x + 8, y - 4, kFrame, -1, true);
  text(cr, box.x + 24, y + 1, "approach away from viewer", 13);
  y += 26;
  cairo_rectangle(cr, box.x, y - 12, 16, 16);
  setColor(cr, kSilhouette);
  cairo_fill(cr);
  text(cr, box.x + 24, y + 1, "object silhouette", 13);
  y += 36;
  const MapSummary& m = *s.summary;
  text(cr, box.x, y, "Map", 16, true);
  auto line = [&](const std::string& str) {
    y += 20;
    text(cr, box.x, y, str, 12);
  };
  line("sampler " + (m.sampler.empty() ? std::string("-") : m.sampler) + ", seed " +
       std::to_string(m.seed));
  line(std::to_string(m.trials) + " trials, " + std::to_string(m.grasps) + " grasps");
  line(std::to_string(m.force_closure) + " force closure (" + format("%.1f", 100 * m.valid_rate) +
       "%)");
  line("epsilon min " + format("%.3g", m.epsilon.min) + ", median " +
       format("%.3g", m.epsilon.median));
  line("          max " + format("%.3g", m.epsilon.max));
  if (m.clustered) line(m.linkage + " linkage, cut " + lengthLabel(m.threshold));
}

void checkCairo(cairo_status_t status, const std::string& path) {
  if (status != CAIRO_STATUS_SUCCESS) {
    throw Error("cannot draw picture '" + path + "': " + cairo_status_to_string(status));
  }
}

}  // namespace

void writeMapPicture(const TaskMapData& map, const MapSummary& summary, const std::string& path,
                     const PictureOptions& options) {
  options.validate();
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
  // Bounds of everything drawn: object vertices and palm positions.
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
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, options.width, options.height);
  cairo_t* cr = cairo_create(surface);
  struct Cleanup {
    cairo_surface_t* s;
    cairo_t* c;
    ~Cleanup() {
      cairo_destroy(c);
      cairo_surface_destroy(s);
    }
  } cleanup{surface, cr};
  checkCairo(cairo_status(cr), path);

  cairo_set_source_rgb(cr, 0.96, 0.96, 0.95);
  cairo_paint(cr);
  const std::string title = "Task map: " + summary.object_name + " with " + summary.hand_name +
                            " hand, " + std::to_string(summary.grasps) + " grasps, " +
                            std::to_string(summary.clusters.size()) + " clusters";
  text(cr, 20, 34, title, 22, true);
  text(cr, 20, 58, summary.path, 13, false, 0.0, Rgb{0.35, 0.35, 0.35});

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
  cairo_surface_flush(surface);
  checkCairo(cairo_status(cr), path);

  // Atomic write: temporary file beside the target, then rename.
  const std::filesystem::path target(path);
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  const cairo_status_t st = cairo_surface_write_to_png(surface, tmp.c_str());
  if (st != CAIRO_STATUS_SUCCESS) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw Error("cannot write picture '" + path + "': " + cairo_status_to_string(st) +
                "; check that the directory exists and is writable");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, target, ec);
  if (ec) {
    const std::string why = ec.message();
    std::filesystem::remove(tmp, ec);
    throw Error("cannot write picture '" + path + "': rename failed (" + why + ")");
  }
}

#endif  // TASKMAP_HAVE_CAIRO

}  // namespace taskmap::cli
