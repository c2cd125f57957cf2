// Fig. 1.16: cost terms per iteration of the trajectory optimisation and the map terms over
// the movement, drawn with cairo.
#include "taskmap/picture/cost_picture.hpp"

#include <algorithm>
#include <limits>

#include "taskmap/core/error.hpp"

#ifdef TASKMAP_HAVE_CAIRO
#include <cairo.h>

#include "picture_draw.hpp"
#endif

namespace taskmap {

#ifndef TASKMAP_HAVE_CAIRO
void writeCostPicture(const std::vector<CostPanel>&, const std::string& path) {
  throw Error("cannot write picture '" + path + "': this taskmap was built without cairo");
}
#else
namespace {

constexpr int kPanelWidth = 640, kHeight = 480, kMargin = 60;
const picture_draw::Rgb kColors[] = {{0.1, 0.1, 0.1}, {0.0, 0.45, 0.75}, {0.85, 0.35, 0.0},
                                     {0.0, 0.6, 0.3}, {0.6, 0.2, 0.7},   {0.8, 0.1, 0.1}};

void drawPanel(cairo_t* cr, double x0, const CostPanel& panel) {
  const std::vector<CostSeries>& series = panel.series;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  std::size_t n = 1;
  for (const CostSeries& s : series) {
    for (double v : s.second) lo = std::min(lo, v), hi = std::max(hi, v);
    n = std::max(n, s.second.size());
  }
  if (!(hi > lo)) hi = lo + 1.0;
  const double left = x0 + kMargin, right = x0 + kPanelWidth - 20, top = 40,
               bottom = kHeight - kMargin;
  const auto px = [&](std::size_t i) {
    return left + (right - left) * i / std::max<std::size_t>(1, n - 1);
  };
  const auto py = [&](double v) { return bottom - (bottom - top) * (v - lo) / (hi - lo); };
  picture_draw::setColor(cr, picture_draw::Rgb{0.5, 0.5, 0.5});
  cairo_set_line_width(cr, 1.0);
  cairo_rectangle(cr, left, top, right - left, bottom - top);
  cairo_stroke(cr);
  picture_draw::text(cr, left, 28, panel.title, 16, true);
  picture_draw::text(cr, x0 + 4, top + 10, picture_draw::format("%.3g", hi), 12);
  picture_draw::text(cr, x0 + 4, bottom, picture_draw::format("%.3g", lo), 12);
  picture_draw::text(cr, left, bottom + 20, "0", 12);
  picture_draw::text(cr, right - 30, bottom + 20,
                     picture_draw::format("%.4g", (n - 1) * panel.x_scale), 12);
  picture_draw::text(cr, (left + right) / 2 - 30, bottom + 36, panel.x_label, 13);
  for (std::size_t k = 0; k < series.size(); ++k) {
    const auto& v = series[k].second;
    if (v.empty()) continue;
    picture_draw::setColor(cr, kColors[k % 6]);
    cairo_set_line_width(cr, 2.0);
    cairo_move_to(cr, px(0), py(v[0]));
    for (std::size_t i = 1; i < v.size(); ++i) cairo_line_to(cr, px(i), py(v[i]));
    cairo_stroke(cr);
    const double ly = top + 16 + 18 * k;
    cairo_move_to(cr, right - 190, ly - 4);
    cairo_line_to(cr, right - 174, ly - 4);
    cairo_stroke(cr);
    picture_draw::text(cr, right - 170, ly, series[k].first, 13);
  }
}

}  // namespace

void writeCostPicture(const std::vector<CostPanel>& panels, const std::string& path) {
  const int width = kPanelWidth * static_cast<int>(std::max<std::size_t>(1, panels.size()));
  const picture_draw::Canvas canvas(width, kHeight, CAIRO_FORMAT_ARGB32, path);
  cairo_t* cr = canvas.cr();
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  for (std::size_t i = 0; i < panels.size(); ++i)
    drawPanel(cr, static_cast<double>(kPanelWidth * i), panels[i]);
  canvas.write();
}
#endif

}  // namespace taskmap
