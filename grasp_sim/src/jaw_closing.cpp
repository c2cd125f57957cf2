// Parallel jaws closed from open at a fixed palm pose (jaw_closing.hpp). Steps: find the jaws
// (the closing joint's links on two fingers, their closing velocities), put their collision
// shapes in the palm frame at the preshape once; per pose: refuse jaws that already intersect
// the object, sweep each jaw toward the object (exact time of first contact of translating
// triangle meshes), close by the sum of the two sweeps.
#include "taskmap/grasp_sim/jaw_closing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "taskmap/core/error.hpp"
#include "taskmap/hands/shape_mesh.hpp"

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Axis-aligned box.
struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(kInf), hi = Eigen::Vector3d::Constant(-kInf);
  void add(const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  bool overlaps(const Box& b) const {
    return (lo.array() <= b.hi.array()).all() && (b.lo.array() <= hi.array()).all();
  }
};

/// A triangle mesh with its edges (each once) and, for the object, each face's box.
struct Solid {
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  std::vector<std::pair<int, int>> e;
  std::vector<Box> face_box, edge_box;
};

Solid solidOf(const TriangleMesh& mesh) {
  Solid s;
  s.v = mesh.vertices;
  s.f = mesh.faces;
  std::set<std::pair<int, int>> edges;
  for (const auto& t : s.f)
    for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
  s.e.assign(edges.begin(), edges.end());
  return s;
}

void boxFaces(Solid* s) {
  s->face_box.assign(s->f.size(), Box{});
  for (std::size_t i = 0; i < s->f.size(); ++i)
    for (int k = 0; k < 3; ++k) s->face_box[i].add(s->v[static_cast<std::size_t>(s->f[i][k])]);
  s->edge_box.assign(s->e.size(), Box{});
  for (std::size_t i = 0; i < s->e.size(); ++i) {
    s->edge_box[i].add(s->v[static_cast<std::size_t>(s->e[i].first)]);
    s->edge_box[i].add(s->v[static_cast<std::size_t>(s->e[i].second)]);
  }
}

/// Parameter t >= 0 at which p + t d meets triangle (a, b, c) (either side; edges included), or
/// +infinity. Moller-Trumbore.
double rayTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                   const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  constexpr double kEps = 1e-12;
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) <= kEps * e1.norm() * e2.norm() * d.norm()) return kInf;  // parallel
  const Eigen::Vector3d s = p - a;
  const double u = s.dot(h) / det;
  if (u < -1e-12 || u > 1.0 + 1e-12) return kInf;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < -1e-12 || u + v > 1.0 + 1e-12) return kInf;
  const double t = e2.dot(q) / det;
  return t >= 0.0 ? t : kInf;
}

/// Parameter t >= 0 at which segment a0 a1, moved by t d, meets segment b0 b1, or +infinity
/// (parallel configurations are left to the vertex-face tests).
double edgeEdge(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                const Eigen::Vector3d& b1, const Eigen::Vector3d& d) {
  Eigen::Matrix3d m;
  m.col(0) = a1 - a0;
  m.col(1) = b0 - b1;
  m.col(2) = d;
  const double det = m.determinant();
  if (std::abs(det) <= 1e-12 * m.col(0).norm() * m.col(1).norm() * d.norm()) return kInf;
  const Eigen::Vector3d x = m.inverse() * (b0 - a0);  // a0 + s da + t d = b0 + r db
  const double tol = 1e-12;
  if (x[0] < -tol || x[0] > 1 + tol || x[1] < -tol || x[1] > 1 + tol || x[2] < 0) return kInf;
  return x[2];
}

/// A jaw: the finger's collision shapes in the palm frame at the preshape and the velocity of
/// the jaw per unit of the closing joint toward its closed limit.
struct Jaw {
  std::string finger;
  std::vector<Solid> shapes;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // m per unit q, palm frame
};

Solid posed(const Solid& s, const Eigen::Isometry3d& t) {
  Solid out = s;
  for (auto& p : out.v) p = t * p;
  return out;
}

Box boundsOf(const Solid& s) {
  Box b;
  for (const auto& p : s.v) b.add(p);
  return b;
}

/// Does convex solid `shape` intersect the object's solid? Surfaces crossing, or one inside the
/// other.
bool intersects(const Solid& shape, const Solid& object, const ObjectModel& model) {
  const Box sb = boundsOf(shape);
  for (std::size_t i = 0; i < object.f.size(); ++i) {
    if (!object.face_box[i].overlaps(sb)) continue;
    const auto& t = object.f[i];
    const Eigen::Vector3d &a = object.v[static_cast<std::size_t>(t[0])],
                          &b = object.v[static_cast<std::size_t>(t[1])],
                          &c = object.v[static_cast<std::size_t>(t[2])];
    for (const auto& [i0, i1] : shape.e) {
      const Eigen::Vector3d& p = shape.v[static_cast<std::size_t>(i0)];
      if (rayTriangle(p, shape.v[static_cast<std::size_t>(i1)] - p, a, b, c) <= 1.0) return true;
    }
  }
  for (std::size_t i = 0; i < object.e.size(); ++i) {
    if (!object.edge_box[i].overlaps(sb)) continue;
    const Eigen::Vector3d& p = object.v[static_cast<std::size_t>(object.e[i].first)];
    const Eigen::Vector3d d = object.v[static_cast<std::size_t>(object.e[i].second)] - p;
    for (const auto& t : shape.f)
      if (rayTriangle(p, d, shape.v[static_cast<std::size_t>(t[0])],
                      shape.v[static_cast<std::size_t>(t[1])],
                      shape.v[static_cast<std::size_t>(t[2])]) <= 1.0)
        return true;
  }
  // No surfaces cross: the shape is inside the object, or the object inside the (convex) shape.
  if (model.contains(shape.v.front())) return true;
  const Eigen::Vector3d& o = object.v.front();
  for (const auto& t : shape.f) {
    const Eigen::Vector3d &a = shape.v[static_cast<std::size_t>(t[0])],
                          &b = shape.v[static_cast<std::size_t>(t[1])],
                          &c = shape.v[static_cast<std::size_t>(t[2])];
    if ((b - a).cross(c - a).dot(o - a) > 0) return false;  // outside this face's plane
  }
  return true;
}

/// Distance `shape` travels along unit `d` before it first touches the object, at most `reach`
/// (+infinity beyond).
double sweep(const Solid& shape, const Eigen::Vector3d& d, double reach, const Solid& object) {
  Box swept = boundsOf(shape);
  swept.add(swept.lo + reach * d);
  swept.add(swept.hi + reach * d);
  double best = kInf;
  for (std::size_t i = 0; i < object.f.size(); ++i) {
    if (!object.face_box[i].overlaps(swept)) continue;
    const auto& t = object.f[i];
    const Eigen::Vector3d &a = object.v[static_cast<std::size_t>(t[0])],
                          &b = object.v[static_cast<std::size_t>(t[1])],
                          &c = object.v[static_cast<std::size_t>(t[2])];
    for (const auto& p : shape.v) best = std::min(best, rayTriangle(p, d, a, b, c));
    for (const auto& s : shape.f)
      for (int k = 0; k < 3; ++k)
        best = std::min(best, rayTriangle(object.v[static_cast<std::size_t>(t[k])], -d,
                                          shape.v[static_cast<std::size_t>(s[0])],
                                          shape.v[static_cast<std::size_t>(s[1])],
                                          shape.v[static_cast<std::size_t>(s[2])]));
  }
  for (std::size_t i = 0; i < object.e.size(); ++i) {
    if (!object.edge_box[i].overlaps(swept)) continue;
    const Eigen::Vector3d& b0 = object.v[static_cast<std::size_t>(object.e[i].first)];
    const Eigen::Vector3d& b1 = object.v[static_cast<std::size_t>(object.e[i].second)];
    for (const auto& [i0, i1] : shape.e)
      best = std::min(best, edgeEdge(shape.v[static_cast<std::size_t>(i0)],
                                     shape.v[static_cast<std::size_t>(i1)], b0, b1, d));
  }
  return best <= reach ? best : kInf;
}

}  // namespace

const char* toString(JawClosingStatus status) {
  switch (status) {
    case JawClosingStatus::kClosed:
      return "closed";
    case JawClosingStatus::kMissed:
      return "missed";
    case JawClosingStatus::kOverlaps:
      return "overlaps";
  }
  return "unknown";
}

struct JawCloser::Impl {
  HandModel hand;
  ObjectModel object;
  Solid solid;
  int joint = -1;      // index into jointNames()
  double open = 0.0;   // the closing joint's preshape value
  double limit = 0.0;  // its closed limit
  std::vector<Jaw> jaws;
  std::vector<std::string> names;

  Impl(const HandModel& h, const ObjectModel& o) : hand(h), object(o) {}
  void findJaws();
};

void JawCloser::Impl::findJaws() {
  const auto fail = [this](const std::string& why) {
    throw Error("jaw closing: hand '" + hand.name() + "' (" + hand.urdfPath() +
                ") is not a parallel-jaw gripper: " + why +
                "; joint values of pose-only grasps are computed for parallel jaws only (one "
                "prismatic closing joint translating two fingers toward each other)");
  };
  if (hand.closing().size() != 1)
    fail(std::to_string(hand.closing().size()) + " closing joints (sidecar \"closing\")");
  joint = hand.closing()[0].joint;
  const std::string name = hand.jointNames()[static_cast<std::size_t>(joint)];
  for (const auto& j : hand.joints())
    if (j.name == name && j.type != JointType::kPrismatic)
      fail("its closing joint '" + name + "' is not prismatic");
  const Eigen::VectorXd q0 = hand.preshape();
  open = q0[joint];
  limit = hand.closing()[0].target;
  if (!(std::abs(limit - open) > 0)) fail("its closing joint is at its closed limit when open");
  Eigen::VectorXd q1 = q0;
  q1[joint] = limit;
  const std::vector<Eigen::Isometry3d> at0 = hand.linkPoses(q0), at1 = hand.linkPoses(q1);
  const double travel = std::abs(limit - open);
  std::vector<int> finger_jaw(hand.fingerNames().size(), -1);
  for (std::size_t l = 0; l < hand.links().size(); ++l) {
    const auto& drivers = hand.linkDrivers()[l];
    if (std::find(drivers.begin(), drivers.end(), joint) == drivers.end()) continue;
    const HandLink& link = hand.links()[l];
    if (link.finger < 0) fail("link '" + link.name + "' moves with the jaws but is on no finger");
    if (Eigen::Quaterniond(at0[l].linear()).angularDistance(Eigen::Quaterniond(at1[l].linear())) >
        1e-9)
      fail("link '" + link.name + "' turns as the jaws close");
    int& jaw = finger_jaw[static_cast<std::size_t>(link.finger)];
    if (jaw < 0) {
      jaw = static_cast<int>(jaws.size());
      jaws.push_back({hand.fingerNames()[static_cast<std::size_t>(link.finger)],
                      {},
                      (at1[l].translation() - at0[l].translation()) / travel});
    }
    for (const CollisionShape& shape : link.shapes) {
      const TriangleMesh m = collisionShapeMesh(shape);
      if (m.faces.empty()) continue;
      jaws[static_cast<std::size_t>(jaw)].shapes.push_back(
          posed(solidOf(m), at0[l] * shape.origin));
    }
  }
  if (jaws.size() != 2) fail("the closing joint moves " + std::to_string(jaws.size()) + " fingers");
  const Eigen::Vector3d u0 = jaws[0].velocity.normalized(), u1 = jaws[1].velocity.normalized();
  if (!(u0.dot(u1) < -1.0 + 1e-9)) fail("its two jaws do not move toward each other");
  for (const Jaw& j : jaws) {
    if (j.shapes.empty()) fail("finger '" + j.finger + "' has no collision shape");
    names.push_back(j.finger);
  }
}

JawCloser::JawCloser(const HandModel& hand, const ObjectModel& object)
    : impl_(std::make_unique<Impl>(hand, object)) {
  impl_->findJaws();
  impl_->solid = solidOf(object.mesh());
  boxFaces(&impl_->solid);
}

JawCloser::~JawCloser() = default;
JawCloser::JawCloser(JawCloser&&) noexcept = default;
JawCloser& JawCloser::operator=(JawCloser&&) noexcept = default;

const std::vector<std::string>& JawCloser::jawNames() const {
  return impl_->names;
}

int JawCloser::closingJoint() const {
  return impl_->joint;
}

JawClosing JawCloser::close(const Pose& palm) const {
  const Impl& s = *impl_;
  const Eigen::Isometry3d x = palm.toIsometry();
  JawClosing r;
  r.joints = s.hand.preshape();
  const double travel = std::abs(s.limit - s.open);
  const double speed = s.jaws[0].velocity.norm() + s.jaws[1].velocity.norm();
  // Relative to the object a jaw may travel the whole closing of both jaws (the other one
  // touching at once).
  const double reach = speed * travel;
  bool overlaps = false;
  for (const Jaw& jaw : s.jaws) {
    const Eigen::Vector3d d = x.linear() * jaw.velocity.normalized();
    double nearest = kInf;
    for (const Solid& shape : jaw.shapes) {
      const Solid at = posed(shape, x);
      if (intersects(at, s.solid, s.object)) {
        nearest = 0.0;  // this jaw touches (inside) from the start
        overlaps = true;
        break;
      }
      nearest = std::min(nearest, sweep(at, d, reach, s.solid));
    }
    r.sweep.push_back(nearest);
  }
  const double closing = (r.sweep[0] + r.sweep[1]) / speed;  // of the joint; inf when missed
  const double sign = s.limit > s.open ? 1.0 : -1.0;
  if (overlaps) {  // where the other jaw touches too (the closed limit when it passes)
    r.status = JawClosingStatus::kOverlaps;
    r.joints[s.joint] = s.open + sign * std::min(closing, travel);
    return r;
  }
  if (!(closing <= travel + 1e-12)) {
    r.status = JawClosingStatus::kMissed;
    r.joints[s.joint] = s.limit;
    return r;
  }
  r.status = JawClosingStatus::kClosed;
  r.joints[s.joint] = s.open + sign * std::min(closing, travel);
  const std::size_t first = r.sweep[0] <= r.sweep[1] ? 0 : 1;
  r.object_shift = closing * s.jaws[first].velocity.norm() - r.sweep[first];
  return r;
}

}  // namespace taskmap
