// taskmap reach --png: capsules as round-capped strokes (the exact outline of a projected
// capsule), swept rectangles as round-joined stroked polygons, three orthographic views.
#include "taskmap/picture/reach_picture.hpp"

#include <algorithm>
#include <array>
#include <limits>

#include "taskmap/core/error.hpp"

#ifdef TASKMAP_HAVE_CAIRO
#include <cairo.h>

#include "picture_draw.hpp"
#endif

namespace taskmap {

#ifndef TASKMAP_HAVE_CAIRO
void writeReachPicture(const RobotModel&, const ReachResult&, int, const std::vector<int>&,
                       const Eigen::Isometry3d&, const std::string& path) {
  throw Error("cannot write picture '" + path + "': this taskmap was built without cairo");
}
#else
namespace {

using picture_draw::Rgb;

struct View {
  int u, v;          // world axes drawn right and up
  const char* name;  // title
};
constexpr std::array<View, 3> kViews = {{{0, 1, "top (x right, y up)"},
                                         {1, 2, "front (y right, z up)"},
                                         {0, 2, "side (x right, z up)"}}};

/// Projection of world points into one panel.
struct Panel {
  View view;
  double x0, y0, scale;  // pixel of the world bounds' low corner, pixels per metre
  Eigen::Vector3d lo;
  double px(const Eigen::Vector3d& p) const { return x0 + (p[view.u] - lo[view.u]) * scale; }
  double py(const Eigen::Vector3d& p) const { return y0 - (p[view.v] - lo[view.v]) * scale; }
};

std::vector<Eigen::Vector3d> coreCorners(const Primitive& p, const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d c = pose * p.center;
  const Eigen::Matrix3d a = pose.linear() * p.axes;
  if (p.type == PrimitiveType::kCapsule) return {c - p.half_u * a.col(0), c + p.half_u * a.col(0)};
  return {
      c - p.half_u * a.col(0) - p.half_v * a.col(1), c + p.half_u * a.col(0) - p.half_v * a.col(1),
      c + p.half_u * a.col(0) + p.half_v * a.col(1), c - p.half_u * a.col(0) + p.half_v * a.col(1)};
}

void drawPrimitive(cairo_t* cr, const Panel& panel, const Primitive& p,
                   const Eigen::Isometry3d& pose, const Rgb& color, double alpha) {
  const std::vector<Eigen::Vector3d> corners = coreCorners(p, pose);
  cairo_new_path(cr);
  cairo_move_to(cr, panel.px(corners[0]), panel.py(corners[0]));
  for (size_t i = 1; i < corners.size(); ++i)
    cairo_line_to(cr, panel.px(corners[i]), panel.py(corners[i]));
  if (corners.size() > 2) cairo_close_path(cr);
  if (corners.size() == 2 && (corners[0] - corners[1]).norm() < 1e-12)
    cairo_line_to(cr, panel.px(corners[0]) + 1e-3, panel.py(corners[0]));  // a sphere
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_width(cr, std::max(1.0, 2.0 * p.radius * panel.scale));
  picture_draw::setColor(cr, color, alpha);
  if (corners.size() > 2) cairo_fill_preserve(cr);
  cairo_stroke(cr);
}

void drawBodies(cairo_t* cr, const Panel& panel, const RobotModel& robot, const Kinematics& kin,
                bool environment, const Rgb& color, double alpha) {
  for (size_t b = 0; b < robot.bodies().size(); ++b) {
    const RobotBody& body = robot.bodies()[b];
    if ((body.role == BodyRole::kEnvironment) != environment) continue;
    for (const Primitive& p : body.shapes)
      drawPrimitive(cr, panel, p, kin.pose(static_cast<int>(b)), color, alpha);
  }
}

/// World bounds of every primitive over the drawn frames.
void bounds(const RobotModel& robot, const ReachResult& result, const std::vector<int>& frames,
            Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  lo.setConstant(std::numeric_limits<double>::infinity());
  hi = -lo;
  Kinematics kin(robot);
  for (int f : frames) {
    kin.update(result.q[f]);
    for (size_t b = 0; b < robot.bodies().size(); ++b)
      for (const Primitive& p : robot.bodies()[b].shapes)
        for (const Eigen::Vector3d& c : coreCorners(p, kin.pose(static_cast<int>(b)))) {
          lo = lo.cwiseMin(c - Eigen::Vector3d::Constant(p.radius));
          hi = hi.cwiseMax(c + Eigen::Vector3d::Constant(p.radius));
        }
  }
}

}  // namespace

void writeReachPicture(const RobotModel& robot, const ReachResult& result, int body,
                       const std::vector<int>& frames, const Eigen::Isometry3d& target_world,
                       const std::string& path) {
  constexpr int kWidth = 1800, kHeight = 700;
  Eigen::Vector3d lo, hi;
  bounds(robot, result, frames, lo, hi);
  const double cell = kWidth / 3.0, margin = 30.0, title = 40.0;
  double scale = std::numeric_limits<double>::infinity();
  for (const View& v : kViews)
    scale = std::min({scale, (cell - 2 * margin) / std::max(1e-6, hi[v.u] - lo[v.u]),
                      (kHeight - title - 2 * margin) / std::max(1e-6, hi[v.v] - lo[v.v])});
  const picture_draw::Canvas canvas(kWidth, kHeight, CAIRO_FORMAT_ARGB32, path);
  cairo_t* cr = canvas.cr();
  picture_draw::setColor(cr, Rgb{1, 1, 1});
  cairo_paint(cr);
  Kinematics kin(robot);
  std::vector<Eigen::Vector3d> trail;
  for (const Eigen::VectorXd& q : result.q) {
    kin.update(q);
    trail.push_back(kin.pose(body).translation());
  }
  for (size_t i = 0; i < kViews.size(); ++i) {
    const View& v = kViews[i];
    const double x0 = i * cell + 0.5 * (cell - (hi[v.u] - lo[v.u]) * scale);
    const double y0 =
        kHeight - margin - 0.5 * (kHeight - title - 2 * margin - (hi[v.v] - lo[v.v]) * scale);
    const Panel panel{v, x0, y0, scale, lo};
    picture_draw::text(cr, i * cell + cell / 2, 28, v.name, 18, true, 0.5);
    drawBodies(cr, panel, robot, kin, true, Rgb{0.75, 0.75, 0.75}, 1.0);
    for (size_t k = 0; k < frames.size(); ++k) {
      kin.update(result.q[frames[k]]);
      const double s = frames.size() > 1 ? static_cast<double>(k) / (frames.size() - 1) : 1.0;
      drawBodies(cr, panel, robot, kin, false, Rgb{0.2 + 0.7 * s, 0.45 - 0.2 * s, 0.85 - 0.7 * s},
                 0.25 + 0.55 * s);
    }
    picture_draw::setColor(cr, Rgb{0.1, 0.1, 0.1}, 0.9);
    cairo_set_line_width(cr, 1.5);
    cairo_move_to(cr, panel.px(trail[0]), panel.py(trail[0]));
    for (const Eigen::Vector3d& p : trail) cairo_line_to(cr, panel.px(p), panel.py(p));
    cairo_stroke(cr);
    const Eigen::Vector3d t = target_world.translation();
    picture_draw::setColor(cr, Rgb{0.85, 0.0, 0.0});
    cairo_set_line_width(cr, 2.5);
    cairo_move_to(cr, panel.px(t) - 8, panel.py(t) - 8);
    cairo_line_to(cr, panel.px(t) + 8, panel.py(t) + 8);
    cairo_move_to(cr, panel.px(t) - 8, panel.py(t) + 8);
    cairo_line_to(cr, panel.px(t) + 8, panel.py(t) - 8);
    cairo_stroke(cr);
  }
  picture_draw::text(
      cr, 10, kHeight - 8,
      "robot at steps " +
          [&] {
            std::string s;
            for (int f : frames) s += (s.empty() ? "" : ", ") + std::to_string(f);
            return s;
          }() +
          " (blue to orange), palm path black, environment grey, target red",
      14);
  canvas.write();
}
#endif

}  // namespace taskmap
