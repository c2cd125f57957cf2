// taskmap hand-info --png: preshape and closed hand in three views (hand_picture.hpp).
#include "taskmap/picture/hand_picture.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <system_error>
#include <vector>

#include <unistd.h>

#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/inspect/hand_check.hpp"

#ifdef TASKMAP_HAVE_CAIRO
#include <cairo.h>

#include "picture_draw.hpp"
#endif

namespace taskmap {

#ifndef TASKMAP_HAVE_CAIRO

void writeHandPicture(const HandModel&, const std::string& path) {
  throw Error("cannot write '" + path +
              "': this taskmap was built without cairo; install libcairo2-dev and rebuild");
}

#else

namespace {

using namespace picture_draw;  // NOLINT: the drawing helpers of the map picture

/// An orthographic view of the palm frame: axes shown right (u) and up (v).
struct HandView {
  const char* title;
  int u, v;
};

constexpr HandView kHandViews[3] = {
    {"front (x right, z up)", 0, 2}, {"side (y right, z up)", 1, 2}, {"top (x right, y up)", 0, 1}};

/// Every shape of the hand at q as a point set in the palm frame, with its colour.
struct PlacedShape {
  std::vector<Eigen::Vector3d> points;
  Rgb color;
};

std::vector<PlacedShape> placeShapes(const HandModel& hand, const Eigen::VectorXd& q) {
  std::vector<PlacedShape> out;
  const auto poses = hand.linkPoses(q);
  for (std::size_t li = 0; li < hand.links().size(); ++li) {
    const HandLink& l = hand.links()[li];
    for (const CollisionShape& s : l.shapes) {
      PlacedShape p;
      const Eigen::Isometry3d t = poses[li] * s.origin;
      for (const auto& x : shapePoints(s)) p.points.push_back(t * x);
      p.color = l.finger >= 0 ? rgbOf(l.finger) : Rgb{0.6, 0.6, 0.62};
      out.push_back(std::move(p));
    }
  }
  return out;
}

void drawPanel(cairo_t* cr, const HandModel& hand, const std::vector<PlacedShape>& shapes,
               const HandView& view, const Box& cell, double scale, const Eigen::Vector3d& mid) {
  drawCell(cr, cell, view.title, 13);
  const double cx = cell.x + cell.w / 2, cy = cell.y + 10 + cell.h / 2;
  auto px = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector2d(cx + scale * (p[view.u] - mid[view.u]),
                           cy - scale * (p[view.v] - mid[view.v]));
  };
  for (const PlacedShape& s : shapes) {
    std::vector<Eigen::Vector2d> q;
    for (const auto& p : s.points) q.push_back(px(p));
    const auto h = hull2d(q);
    if (h.size() < 3) continue;
    cairo_move_to(cr, h[0].x(), h[0].y());
    for (std::size_t i = 1; i < h.size(); ++i) cairo_line_to(cr, h[i].x(), h[i].y());
    cairo_close_path(cr);
    setColor(cr, s.color, 0.45);
    cairo_fill_preserve(cr);
    setColor(cr, s.color);
    cairo_set_line_width(cr, 1.2);
    cairo_stroke(cr);
  }
  // Palm frame axes (x red, y green, z blue) and the approach axis (black).
  const double len = 40.0 / scale;
  const Eigen::Vector2d o = px(Eigen::Vector3d::Zero());
  const Rgb axis_color[3] = {{0.85, 0.1, 0.1}, {0.1, 0.6, 0.1}, {0.1, 0.25, 0.85}};
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector2d e = px(len * Eigen::Vector3d::Unit(a));
    if ((e - o).norm() > 3) drawArrow(cr, o.x(), o.y(), e.x(), e.y(), axis_color[a], 2.0);
  }
  const Eigen::Vector2d ap = px(1.6 * len * hand.approachAxis());
  if ((ap - o).norm() > 3) drawArrow(cr, o.x(), o.y(), ap.x(), ap.y(), kInk, 1.5);
  // Scale bar.
  const double bar = niceBelow(0.25 * cell.w / scale);
  setColor(cr, kInk);
  cairo_set_line_width(cr, 2.0);
  cairo_move_to(cr, cell.x + 12, cell.y + cell.h - 12);
  cairo_line_to(cr, cell.x + 12 + bar * scale, cell.y + cell.h - 12);
  cairo_stroke(cr);
  text(cr, cell.x + 12, cell.y + cell.h - 18, lengthLabel(bar), 11);
}

}  // namespace

void writeHandPicture(const HandModel& hand, const std::string& path) {
  const int W = 1500, H = 1000;
  const std::vector<PlacedShape> rows[2] = {placeShapes(hand, hand.preshape()),
                                            placeShapes(hand, closedConfiguration(hand))};
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& row : rows)
    for (const auto& s : row)
      for (const auto& p : s.points) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
  lo = lo.cwiseMin(Eigen::Vector3d::Zero());
  hi = hi.cwiseMax(Eigen::Vector3d::Zero());
  const Eigen::Vector3d mid = 0.5 * (lo + hi);
  const double gap = 12, top = 80;
  const double cw = (W - 40 - 2 * gap) / 3, ch = (H - top - 20 - gap) / 2;
  const double scale = 0.85 * std::min(cw, ch - 30) / std::max((hi - lo).maxCoeff(), 1e-6);

  const Canvas canvas(W, H, CAIRO_FORMAT_RGB24, path);
  cairo_t* cr = canvas.cr();
  cairo_set_source_rgb(cr, 0.96, 0.96, 0.95);
  cairo_paint(cr);
  text(cr, 20, 34, "Hand " + hand.name() + ": preshape (top row) and fully closed (bottom row)", 22,
       true);
  text(cr, 20, 58,
       "palm frame axes x red, y green, z blue; black: approach axis; palm grey, fingers "
       "coloured; " +
           hand.urdfPath(),
       13, false, 0.0, Rgb{0.35, 0.35, 0.35});
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c)
      drawPanel(cr, hand, rows[r], kHandViews[c],
                Box{20 + c * (cw + gap), top + r * (ch + gap), cw, ch}, scale, mid);
  canvas.write();
}

#endif  // TASKMAP_HAVE_CAIRO

}  // namespace taskmap
