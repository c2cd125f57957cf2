// The hand model in the page's JSON (viewer_common.js builds meshes and poses from it).
#include "hand_json.hpp"

#include "page.hpp"

namespace taskmap::viz_detail {
namespace {

nlohmann::json isoJson(const Eigen::Isometry3d& t, int decimals) {
  return poseJson(Pose::fromIsometry(t), decimals);
}

nlohmann::json vectorJson(const Eigen::VectorXd& v, int decimals) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(rounded(v[i], decimals + 2));
  return out;
}

nlohmann::json shapeJson(const CollisionShape& s, int decimals) {
  nlohmann::json j = {{"o", isoJson(s.origin, decimals)}};
  switch (s.type) {
    case ShapeType::kBox:
      j["t"] = "box";
      j["s"] = vectorJson(s.box_size, decimals);
      break;
    case ShapeType::kCylinder:
      j["t"] = "cyl";
      j["r"] = rounded(s.radius, decimals);
      j["l"] = rounded(s.length, decimals);
      break;
    case ShapeType::kSphere:
      j["t"] = "sph";
      j["r"] = rounded(s.radius, decimals);
      break;
    case ShapeType::kConvex: {
      j["t"] = "hull";
      nlohmann::json p = nlohmann::json::array();
      for (const Eigen::Vector3d& v : s.points)
        for (int k = 0; k < 3; ++k) p.push_back(rounded(v[k], decimals));
      j["p"] = p;
      break;
    }
  }
  return j;
}

nlohmann::json linksJson(const HandModel& hand, int decimals) {
  nlohmann::json links = nlohmann::json::array();
  for (const HandLink& l : hand.links()) {
    nlohmann::json shapes = nlohmann::json::array();
    for (const CollisionShape& s : l.shapes) shapes.push_back(shapeJson(s, decimals));
    links.push_back({{"name", l.name}, {"palm", l.palm}, {"finger", l.finger}, {"shapes", shapes}});
  }
  return links;
}

nlohmann::json jointsJson(const HandModel& hand, int decimals) {
  nlohmann::json joints = nlohmann::json::array();
  for (const HandJoint& j : hand.joints()) {
    const char* type = j.type == JointType::kRevolute    ? "r"
                       : j.type == JointType::kPrismatic ? "p"
                                                         : "f";
    joints.push_back({{"name", j.name},
                      {"t", type},
                      {"parent", j.parent_link},
                      {"child", j.child_link},
                      {"o", isoJson(j.origin, decimals)},
                      {"axis", vectorJson(j.axis, decimals)},
                      {"d", j.driver},
                      {"m", j.multiplier},
                      {"off", j.offset}});
  }
  return joints;
}

}  // namespace

Eigen::VectorXd closedJoints(const HandModel& hand) {
  Eigen::VectorXd q = hand.preshape();
  for (const ClosingJoint& c : hand.closing()) q[c.joint] = c.target;
  return q;
}

nlohmann::json handJson(const HandModel& hand, int decimals) {
  return {{"name", hand.name()},
          {"joint_names", hand.jointNames()},
          {"lower", vectorJson(hand.lowerLimits(), decimals)},
          {"upper", vectorJson(hand.upperLimits(), decimals)},
          {"preshape", vectorJson(hand.preshape(), decimals)},
          {"closed", vectorJson(closedJoints(hand), decimals)},
          {"approach", vectorJson(hand.approachAxis(), decimals)},
          {"reach", rounded(hand.reach(), decimals)},
          {"root_to_palm", isoJson(hand.rootToPalm(), decimals)},
          {"palm_link", hand.palmLink()},
          {"links", linksJson(hand, decimals)},
          {"joints", jointsJson(hand, decimals)}};
}

}  // namespace taskmap::viz_detail
