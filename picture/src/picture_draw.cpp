// Drawing helpers and the histogram and legend panels of `taskmap inspect --png`.
#ifdef TASKMAP_HAVE_CAIRO

#include "picture_draw.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include <unistd.h>

#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap::picture_draw {

Rgb rgbOf(int cluster) {
  const auto c = clusterColor(cluster);
  return {c[0] / 255.0, c[1] / 255.0, c[2] / 255.0};
}

void setColor(cairo_t* cr, const Rgb& c, double alpha) {
  cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

void text(cairo_t* cr, double x, double y, const std::string& s, double size, bool bold,
          double align, const Rgb& color) {
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

// Andrew's monotone chain.
std::vector<Eigen::Vector2d> hull2d(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (p.size() < 3) return p;
  std::vector<Eigen::Vector2d> h(2 * p.size());
  std::size_t k = 0;
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

void drawOutline(cairo_t* cr, const std::vector<Eigen::Vector2d>& points, const Rgb& c) {
  const std::vector<Eigen::Vector2d> h = hull2d(points);
  if (h.size() < 3) return;
  cairo_new_path(cr);
  cairo_move_to(cr, h[0].x(), h[0].y());
  for (std::size_t i = 1; i < h.size(); ++i) cairo_line_to(cr, h[i].x(), h[i].y());
  cairo_close_path(cr);
  setColor(cr, c, 0.3);
  cairo_fill_preserve(cr);
  setColor(cr, kInk, 0.85);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
}

void drawCell(cairo_t* cr, const Box& cell, const std::string& title, double size) {
  cairo_rectangle(cr, cell.x, cell.y, cell.w, cell.h);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_fill_preserve(cr);
  setColor(cr, kFrame);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
  text(cr, cell.x + 10, cell.y + 22, title, size, true);
}

void checkStatus(cairo_status_t status, const std::string& path) {
  if (status != CAIRO_STATUS_SUCCESS)
    throw Error("cannot draw picture '" + path + "': " + cairo_status_to_string(status));
}

Canvas::Canvas(int width, int height, cairo_format_t format, const std::string& path)
    : path_(path),
      surface_(cairo_image_surface_create(format, width, height)),
      cr_(cairo_create(surface_)) {
  const cairo_status_t status = cairo_status(cr_);
  if (status != CAIRO_STATUS_SUCCESS) {
    cairo_destroy(cr_);
    cairo_surface_destroy(surface_);
    checkStatus(status, path);
  }
}

Canvas::~Canvas() {
  cairo_destroy(cr_);
  cairo_surface_destroy(surface_);
}

void Canvas::write() const {
  cairo_surface_flush(surface_);
  checkStatus(cairo_status(cr_), path_);
  writePng(surface_, path_);
}

std::string Canvas::png() const {
  cairo_surface_flush(surface_);
  checkStatus(cairo_status(cr_), path_);
  std::string bytes;
  const cairo_status_t st = cairo_surface_write_to_png_stream(
      surface_,
      [](void* closure, const unsigned char* data, unsigned int length) {
        static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
        return CAIRO_STATUS_SUCCESS;
      },
      &bytes);
  checkStatus(st, path_);
  return bytes;
}

void writePng(cairo_surface_t* surface, const std::string& path) {
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  const cairo_status_t st = cairo_surface_write_to_png(surface, tmp.c_str());
  if (st != CAIRO_STATUS_SUCCESS) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw Error("cannot write picture '" + path + "': " + cairo_status_to_string(st) +
                "; check that the directory exists and is writable");
  }
  commitTemporaryFile(tmp, path, "cannot write picture '" + path + "'");
}

void drawHistogram(cairo_t* cr, const Scene& s, const Box& cell) {
  drawCell(cr, cell, "Epsilon per cluster (stacked, all grasps)");

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
  std::vector<std::vector<int> > counts(kBins, std::vector<int>(k_count + 1, 0));
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
  if (!s.hands.empty()) {
    y += 26;
    drawOutline(cr, {{box.x, y - 12}, {box.x + 16, y - 12}, {box.x + 16, y + 4}, {box.x, y + 4}},
                kFrame);
    text(cr, box.x + 24, y + 1, "hand at the representative", 13);
  }
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

}  // namespace taskmap::picture_draw

#endif  // TASKMAP_HAVE_CAIRO
