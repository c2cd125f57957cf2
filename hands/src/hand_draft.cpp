// Drafting a hand sidecar from the URDF alone (hand_draft.hpp; rules in docs/METHOD.md,
// "Drafting a sidecar").
#include "taskmap/hands/hand_draft.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {
namespace {

using ojson = nlohmann::ordered_json;

/// A joint closes when it moves the fingertips toward the palm by at least this share of the
/// most effective joint (spread joints move them around it: 0).
constexpr double kMinClosingShare = 0.05;

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

std::string vec(const Eigen::Vector3d& v) {
  return "(" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + ")";
}

/// Points that bound a collision shape, in its link frame.
std::vector<Eigen::Vector3d> shapePoints(const CollisionShape& s) {
  std::vector<Eigen::Vector3d> p;
  if (s.type == ShapeType::kBox) {
    for (int i = 0; i < 8; ++i)
      p.emplace_back(((i & 1) ? 0.5 : -0.5) * s.box_size.x(),
                     ((i & 2) ? 0.5 : -0.5) * s.box_size.y(),
                     ((i & 4) ? 0.5 : -0.5) * s.box_size.z());
  } else if (s.type == ShapeType::kSphere) {
    for (int a = 0; a < 3; ++a)
      for (double sign : {-1.0, 1.0}) p.push_back(sign * s.radius * Eigen::Vector3d::Unit(a));
  } else if (s.type == ShapeType::kCylinder) {
    for (double z : {-0.5 * s.length, 0.5 * s.length})
      for (int a = 0; a < 2; ++a)
        for (double sign : {-1.0, 1.0})
          p.push_back(sign * s.radius * Eigen::Vector3d::Unit(a) + z * Eigen::Vector3d::UnitZ());
  } else {
    p = s.points;
  }
  for (auto& x : p) x = s.origin * x;
  return p;
}

/// Every point bounding link l's shapes, at link pose `pose`.
std::vector<Eigen::Vector3d> linkPoints(const HandModel& h, int l, const Eigen::Isometry3d& pose) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& s : h.links()[static_cast<std::size_t>(l)].shapes)
    for (const auto& p : shapePoints(s)) out.push_back(pose * p);
  return out;
}

Eigen::Vector3d centroid(const std::vector<Eigen::Vector3d>& pts) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : pts) c += p;
  return pts.empty() ? c : Eigen::Vector3d(c / static_cast<double>(pts.size()));
}

/// Links hanging from `link` by fixed joints only (link included).
std::vector<int> rigidGroup(const HandModel& h, int link) {
  std::vector<int> group = {link};
  for (std::size_t k = 0; k < group.size(); ++k)
    for (const HandJoint& j : h.joints())
      if (j.parent_link == group[k] && j.type == JointType::kFixed) group.push_back(j.child_link);
  return group;
}

/// Links of the subtree rooted at `link` (link included), parents first.
std::vector<int> subtree(const HandModel& h, int link) {
  std::vector<int> links = {link};
  for (std::size_t k = 0; k < links.size(); ++k)
    for (const HandJoint& j : h.joints())
      if (j.parent_link == links[k]) links.push_back(j.child_link);
  return links;
}

struct Finger {
  std::string name;
  std::vector<int> links;  ///< links with shapes
  int tip = -1;            ///< the last of them (deepest in the chain)
};

struct Draft {
  const HandModel& h;
  SidecarDraft out;
  int palm = -1;
  std::vector<int> palm_group;
  Eigen::Vector3d palm_centre = Eigen::Vector3d::Zero();
  std::vector<Finger> fingers;
  std::vector<int> closing;        ///< actuated joint indices that close
  std::vector<bool> toward_upper;  ///< per actuated joint: closing direction
  Eigen::VectorXd open, closed;    ///< preshape and fully closed values

  void note(const std::string& s) { out.notes.push_back(s); }

  Eigen::Vector3d tipAt(const Finger& f, const std::vector<Eigen::Isometry3d>& poses) const {
    return centroid(linkPoints(h, f.tip, poses[static_cast<std::size_t>(f.tip)]));
  }
  /// Sum over fingers of the fingertips' distances to the palm centre at q.
  double spread(const Eigen::VectorXd& q) const {
    const auto poses = h.linkPoses(q);
    double d = 0.0;
    for (const Finger& f : fingers) d += (tipAt(f, poses) - palm_centre).norm();
    return d;
  }

  void choosePalm();
  void findFingers();
  void chooseClosing();
  ojson palmFrame(Eigen::Vector3d* approach_root);
  ojson assemble();
};

void Draft::choosePalm() {
  const std::vector<int> root_group = rigidGroup(h, h.palmLink());
  double best = -1.0;
  for (int l : root_group) {
    const auto pts = linkPoints(h, l, Eigen::Isometry3d::Identity());
    if (pts.empty()) continue;
    Eigen::Vector3d lo = pts[0], hi = pts[0];
    for (const auto& p : pts) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const double size = (hi - lo).norm();
    if (size > best) {
      best = size;
      palm = l;
    }
  }
  if (palm < 0) {
    out.undecided.push_back("palm_link: no link fixed to the root link has collision geometry");
    return;
  }
  palm_group = rigidGroup(h, h.palmLink());
  const auto poses = h.linkPoses(h.preshape());
  std::vector<Eigen::Vector3d> pts;
  for (int l : palm_group) {
    const auto lp = linkPoints(h, l, poses[static_cast<std::size_t>(l)]);
    pts.insert(pts.end(), lp.begin(), lp.end());
  }
  palm_centre = centroid(pts);
  note("palm_link \"" + h.links()[static_cast<std::size_t>(palm)].name +
       "\": the largest collision geometry (extent " + num(best) +
       " m) among the links fixed to the root link");
}

void Draft::findFingers() {
  std::vector<char> in_palm(h.links().size(), 0);
  for (int l : palm_group) in_palm[static_cast<std::size_t>(l)] = 1;
  for (const HandJoint& j : h.joints()) {
    if (j.type == JointType::kFixed || !in_palm[static_cast<std::size_t>(j.parent_link)]) continue;
    Finger f;
    f.name = h.links()[static_cast<std::size_t>(j.child_link)].name;
    for (int l : subtree(h, j.child_link))
      if (!h.links()[static_cast<std::size_t>(l)].shapes.empty()) {
        f.links.push_back(l);
        f.tip = l;
      }
    if (f.links.empty()) {
      note("joint \"" + j.name + "\" leaves the palm but moves no collision geometry: no finger");
      continue;
    }
    std::string chain;
    for (int l : f.links) chain += (chain.empty() ? "" : ", ") + h.links()[l].name;
    note("finger \"" + f.name + "\": the links below joint \"" + j.name + "\" (" + chain + ")" +
         (j.mimic ? ", moved through its <mimic> coupling" : ""));
    fingers.push_back(f);
  }
  if (fingers.empty())
    out.undecided.push_back(
        "fingers: no non-fixed joint leaving the palm moves collision geometry");
}

void Draft::chooseClosing() {
  const auto n = static_cast<Eigen::Index>(h.jointNames().size());
  const Eigen::VectorXd lo = h.lowerLimits(), hi = h.upperLimits();
  std::vector<double> effect(static_cast<std::size_t>(n), 0.0);
  double strongest = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    Eigen::VectorXd a = h.preshape(), b = h.preshape();
    a[k] = lo[k] + 0.25 * (hi[k] - lo[k]);
    b[k] = lo[k] + 0.75 * (hi[k] - lo[k]);
    effect[static_cast<std::size_t>(k)] = spread(a) - spread(b);  // > 0: closing toward upper
    strongest = std::max(strongest, std::abs(effect[static_cast<std::size_t>(k)]));
  }
  toward_upper.assign(static_cast<std::size_t>(n), true);
  open = h.preshape();
  closed = h.preshape();
  for (Eigen::Index k = 0; k < n; ++k) {
    const double e = effect[static_cast<std::size_t>(k)];
    const std::string name = h.jointNames()[static_cast<std::size_t>(k)];
    if (!(std::abs(e) >= kMinClosingShare * strongest) || strongest <= 0.0) {
      note("joint \"" + name + "\" not closing: over half its range it moves the fingertips " +
           num(std::abs(e)) + " m toward or from the palm, under 5 % of the strongest (" +
           num(strongest) + " m); it stays at " + num(open[k]));
      continue;
    }
    const bool up = e > 0.0;
    toward_upper[static_cast<std::size_t>(k)] = up;
    closing.push_back(static_cast<int>(k));
    open[k] = up ? lo[k] : hi[k];
    closed[k] = up ? hi[k] : lo[k];
    note("joint \"" + name + "\" closes toward its " + (up ? "upper" : "lower") +
         " limit: that brings the fingertips " + num(std::abs(e)) +
         " m nearer the palm over half its range; preshape " + num(open[k]) + " (open)");
  }
  if (closing.empty())
    out.undecided.push_back("closing: no joint moves the fingertips toward the palm");
}

/// Palm frame in the palm link frame: z = the approach axis (palm centre -> the fingertips'
/// centroid where they come closest together while closing), origin on the palm's face along
/// it, x across the first two fingers.
ojson Draft::palmFrame(Eigen::Vector3d* approach_root) {
  const auto open_poses = h.linkPoses(open);
  std::vector<Eigen::Vector3d> tips;
  double least = std::numeric_limits<double>::infinity(), at = 1.0;
  for (int step = 10; step >= 0; --step) {  // ties: the more closed
    const double s = 0.1 * step;
    const auto poses = h.linkPoses(open + s * (closed - open));
    std::vector<Eigen::Vector3d> t;
    for (const Finger& f : fingers) t.push_back(tipAt(f, poses));
    const Eigen::Vector3d c = centroid(t);
    double spread_sum = 0.0;
    for (const auto& p : t) spread_sum += (p - c).norm();
    if (spread_sum < least - 1e-9) {
      least = spread_sum;
      tips = t;
      at = s;
    }
  }
  Eigen::Vector3d a = centroid(tips) - palm_centre;
  if (!(a.norm() > 1e-6)) {
    out.undecided.push_back("approach_axis: the fingertips meet at the palm centre");
    a = Eigen::Vector3d::UnitZ();
  }
  a.normalize();
  *approach_root = a;
  double face = 0.0;
  for (int l : palm_group)
    for (const auto& p : linkPoints(h, l, open_poses[static_cast<std::size_t>(l)]))
      face = std::max(face, (p - palm_centre).dot(a));
  const Eigen::Vector3d origin = palm_centre + face * a;
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - a.x() * a;
  if (fingers.size() >= 2) {
    const Eigen::Vector3d across = tipAt(fingers[1], open_poses) - tipAt(fingers[0], open_poses);
    if ((across - across.dot(a) * a).norm() > 1e-6) x = across - across.dot(a) * a;
  }
  if (!(x.norm() > 1e-6)) x = Eigen::Vector3d::UnitY() - a.y() * a;
  x.normalize();
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.linear().col(0) = x;
  frame.linear().col(1) = a.cross(x);
  frame.linear().col(2) = a;
  frame.translation() = origin;
  // Root frame -> palm link frame (the palm link hangs from the root by fixed joints).
  const auto poses = h.linkPoses(h.preshape());
  const Eigen::Isometry3d in_link = poses[static_cast<std::size_t>(palm)].inverse() * frame;
  const Eigen::Vector3d ypr = in_link.linear().eulerAngles(2, 1, 0);
  const Eigen::Vector3d t = in_link.translation();
  note("approach_axis [0, 0, 1] of a palm frame whose z points from the palm centre " +
       vec(palm_centre) + " to the fingertips' centroid " + vec(centroid(tips)) + " where they " +
       "come closest together (" + num(100.0 * at) + " % of the closing motion)" +
       " (root frame): direction " + vec(a) + "; origin on the palm's face along it, " + num(face) +
       " m from the centre; x across the first two fingers");
  auto r4 = [](double v) { return std::round(v * 1e6) / 1e6; };
  return ojson{{"xyz", {r4(t.x()), r4(t.y()), r4(t.z())}},
               {"rpy", {r4(ypr[2]), r4(ypr[1]), r4(ypr[0])}}};
}

ojson Draft::assemble() {
  ojson js;
  js["description"] = "drafted by taskmap hand-init from " +
                      std::filesystem::path(h.urdfPath()).filename().string() +
                      "; check every field (meshes/hands/README.md)";
  js["palm_link"] = h.links()[static_cast<std::size_t>(palm)].name;
  Eigen::Vector3d a;
  js["palm_frame"] = palmFrame(&a);
  js["approach_axis"] = {0, 0, 1};
  ojson pre = ojson::object();
  for (std::size_t k = 0; k < h.jointNames().size(); ++k)
    pre[h.jointNames()[k]] = std::round(open[static_cast<Eigen::Index>(k)] * 1e6) / 1e6;
  js["preshape"] = pre;
  ojson cl = ojson::array();
  for (int k : closing)
    cl.push_back({{"joint", h.jointNames()[static_cast<std::size_t>(k)]},
                  {"toward", toward_upper[static_cast<std::size_t>(k)] ? "upper" : "lower"},
                  {"speed", 1.0}});
  js["closing"] = cl;
  js["squeeze"] = 0.001;
  note("squeeze 0.001 m (1 mm, as the bundled hands); grasp mode palm (the default)");
  ojson fj = ojson::object();
  for (const Finger& f : fingers) {
    ojson links = ojson::array();
    for (int l : f.links) links.push_back(h.links()[static_cast<std::size_t>(l)].name);
    fj[f.name] = links;
  }
  js["fingers"] = fj;
  return js;
}

}  // namespace

SidecarDraft draftHandSidecar(const std::string& urdf_path) {
  const HandModel h = HandModel::loadKinematics(urdf_path);
  Draft d{h, {}, -1, {}, Eigen::Vector3d::Zero(), {}, {}, {}, {}, {}};
  d.choosePalm();
  if (d.palm >= 0) d.findFingers();
  if (!d.fingers.empty()) d.chooseClosing();
  if (!d.out.undecided.empty()) return d.out;
  d.out.json = d.assemble().dump(2) + "\n";
  if (!d.out.undecided.empty()) return d.out;
  // The draft must load as a sidecar of this URDF.
  const std::string tmp = (std::filesystem::temp_directory_path() /
                           ("taskmap_hand_init_" + std::to_string(::getpid()) + ".hand.json"))
                              .string();
  std::ofstream(tmp) << d.out.json;
  try {
    HandModel::load(urdf_path, tmp);
  } catch (const Error& e) {
    d.out.undecided.push_back(std::string("the draft does not load: ") + e.what());
  }
  std::error_code ec;
  std::filesystem::remove(tmp, ec);
  return d.out;
}

}  // namespace taskmap
