// Closed configuration, shape points and set-up warnings of a hand (hand_check.hpp).
#include "taskmap/inspect/hand_check.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

namespace taskmap {

Eigen::VectorXd closedConfiguration(const HandModel& hand) {
  Eigen::VectorXd q = hand.preshape();
  for (const ClosingJoint& c : hand.closing()) q[c.joint] = c.target;
  return q;
}

std::vector<Eigen::Vector3d> shapePoints(const CollisionShape& s) {
  std::vector<Eigen::Vector3d> pts;
  switch (s.type) {
    case ShapeType::kBox:
      for (int i = 0; i < 8; ++i)
        pts.emplace_back((i & 1 ? 0.5 : -0.5) * s.box_size.x(),
                         (i & 2 ? 0.5 : -0.5) * s.box_size.y(),
                         (i & 4 ? 0.5 : -0.5) * s.box_size.z());
      break;
    case ShapeType::kSphere:
      for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
          for (int z = -1; z <= 1; ++z)
            if (x || y || z) pts.push_back(s.radius * Eigen::Vector3d(x, y, z).normalized());
      break;
    case ShapeType::kCylinder:
      for (int k = 0; k < 16; ++k) {
        const double a = 2 * 3.14159265358979323846 * k / 16;
        for (double side : {-0.5, 0.5})
          pts.emplace_back(s.radius * std::cos(a), s.radius * std::sin(a), side * s.length);
      }
      break;
    case ShapeType::kConvex:
      pts = s.points;
      break;
  }
  return pts;
}

double frontOf(const HandModel& hand, const Eigen::VectorXd& q, int link) {
  const auto poses = hand.linkPoses(q);
  const Eigen::Vector3d a = hand.approachAxis();
  double front = -std::numeric_limits<double>::infinity();
  const HandLink& l = hand.links()[static_cast<std::size_t>(link)];
  for (const CollisionShape& s : l.shapes) {
    const Eigen::Isometry3d t = poses[static_cast<std::size_t>(link)] * s.origin;
    for (const Eigen::Vector3d& p : shapePoints(s)) front = std::max(front, a.dot(t * p));
  }
  return front;
}

HandReport checkHand(const HandModel& hand) {
  HandReport out;
  char buf[640];
  // Finger reach along the closing motion (21 samples from preshape to closed).
  const Eigen::VectorXd open = hand.preshape(), closed = closedConfiguration(hand);
  double finger_front = -std::numeric_limits<double>::infinity();
  for (int k = 0; k <= 20; ++k) {
    const Eigen::VectorXd q = open + (closed - open) * (k / 20.0);
    for (std::size_t li = 0; li < hand.links().size(); ++li)
      if (hand.links()[li].finger >= 0)
        finger_front = std::max(finger_front, frontOf(hand, q, static_cast<int>(li)));
  }
  // The front of the geometry fixed to the palm: where the palm touches the object.
  double palm_front = -std::numeric_limits<double>::infinity();
  std::string palm_front_link;
  for (std::size_t li = 0; li < hand.links().size(); ++li) {
    const HandLink& l = hand.links()[li];
    if (!l.palm || l.shapes.empty()) continue;
    const double front = frontOf(hand, open, static_cast<int>(li));
    if (front > palm_front) {
      palm_front = front;
      palm_front_link = l.name;
    }
  }
  const bool protrudes = palm_front > kPalmFrontTolerance;
  if (!(finger_front > palm_front)) {
    if (protrudes && finger_front > 0.0)
      std::snprintf(buf, sizeof buf,
                    "link '%s' is fixed to the palm and reaches %.4g m in front of the palm "
                    "frame along the approach axis, as far as or beyond every finger (farthest "
                    "%.4g m while closing): it touches the object first and the fingers cannot "
                    "reach it (trials end not_retractable, no_palm_contact or no_finger_contact); "
                    "drop that geometry (e.g. inflated self-collision capsules) or check "
                    "approach_axis and the closing directions",
                    palm_front_link.c_str(), palm_front, finger_front);
    else
      std::snprintf(buf, sizeof buf,
                    "no finger link reaches in front of the palm along the approach axis while "
                    "closing (farthest %.4g m, the palm's front %.4g m): fingers cannot touch an "
                    "object the palm touches; check approach_axis, palm_frame and the closing "
                    "directions",
                    finger_front, palm_front);
    out.warnings.push_back(buf);
  } else if (protrudes) {
    std::snprintf(buf, sizeof buf,
                  "link '%s' is fixed to the palm and reaches %.4g m in front of the palm frame "
                  "along the approach axis (the fingers reach %.4g m): the hand touches objects "
                  "there, and map poses are those of the palm frame behind it; move palm_frame "
                  "to the front of the palm to have poses at the contact face",
                  palm_front_link.c_str(), palm_front, finger_front);
    out.notes.push_back(buf);
  }
  for (const CollisionMeshInfo& m : hand.collisionMeshes())
    if (m.warning) out.warnings.push_back(m.note);
  return out;
}

}  // namespace taskmap
