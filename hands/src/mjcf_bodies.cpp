// The body tree of an MJCF hand (mjcf_reader.hpp): bodies as links depth-first in document
// order, hinge and slide joints (a body with k joints is a chain of k links; each link's frame
// is its joint's anchor, so the body's contents are shifted by the last anchor), colliding
// geoms as collision shapes, <inertial>s, <frame>s.
#include <filesystem>

#include "mjcf_reader.hpp"
#include "taskmap/core/constants.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/xml_scan.hpp"

namespace taskmap::detail {
namespace {

namespace fs = std::filesystem;

Eigen::Isometry3d translation(const Eigen::Vector3d& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = p;
  return t;
}

Eigen::Vector3d vec3(const std::vector<double>& v) {
  return {v[0], v[1], v[2]};
}

}  // namespace

void MjcfReader::readWorld() {
  std::vector<const TiXmlElement*> tops;
  for (const TiXmlElement* w : doc_.children(doc_.root(), "worldbody"))
    collectTopBodies(w, &tops, 2);
  if (tops.empty()) throw Error(doc_.prefix() + "no <body> in <worldbody>: no hand to read");
  if (tops.size() > 1)
    doc_.fail(tops[1], "a second body under <worldbody> (the first is at line " +
                           std::to_string(tops[0]->Row()) +
                           "): a hand is one tree under one top body (load the hand's own file, "
                           "not a scene)");
  addBody(tops[0], Scope{}, Eigen::Isometry3d::Identity(), defaults_.main(), 2);
}

void MjcfReader::collectTopBodies(const TiXmlElement* e, std::vector<const TiXmlElement*>* bodies,
                                  int depth) {
  if (depth > kMaxMjcfDepth) doc_.fail(e, "elements nested too deep");
  for (const TiXmlElement* c : doc_.children(e)) {
    const std::string tag = c->Value();
    if (tag == "body") {
      bodies->push_back(c);
    } else if (tag == "frame") {
      collectTopBodies(c, bodies, depth + 1);
    } else if (tag == "geom") {
      const int cls = defaults_.classOf(c, defaults_.main());
      if (number(c, "geom", cls, "contype", 1) != 0 ||
          number(c, "geom", cls, "conaffinity", 1) != 0)
        doc_.fail(c,
                  "a colliding geom fixed to the world (a floor, a table) is not part of a "
                  "hand: load the hand's own file, not a scene");
    } else if (tag != "site" && tag != "camera" && tag != "light") {
      doc_.fail(c, "<" + tag + "> is not supported in <worldbody> of a hand");
    }
  }
}

void MjcfReader::addBody(const TiXmlElement* b, const Scope& parent, const Eigen::Isometry3d& pose,
                         int inherited, int depth) {
  if (depth > kMaxMjcfDepth)
    doc_.fail(b, "bodies and frames nested more than " + std::to_string(kMaxMjcfDepth) + " deep");
  const int cls =
      b->Attribute("childclass") ? defaults_.classNamed(b->Attribute("childclass"), b) : inherited;
  ++body_count_[0];
  const char* n = b->Attribute("name");
  const std::string name = n ? n : "body" + std::to_string(body_count_[0]);
  Eigen::Isometry3d x = pose;
  if (const char* p = b->Attribute("pos"))
    x.translate(vec3(mjcfNumbers(doc_, {p, b}, "pos", 3, 3)));
  x.rotate(mjcfOrientation(doc_, defaults_, compiler_, b, {}, cls));
  Scope scope;
  addLinks(b, name, parent, x, cls, &scope);
  if (!bodies_.emplace(name, scope.link).second) doc_.fail(b, "a second body named '" + name + "'");
  const auto inertials = doc_.children(b, "inertial");
  if (inertials.size() > 1) doc_.fail(inertials[1], "a body has one <inertial>");
  if (!inertials.empty()) addInertial(inertials[0], scope);
  addContents(b, scope, Eigen::Isometry3d::Identity(), cls, depth);
}

int MjcfReader::addLinks(const TiXmlElement* b, const std::string& name, const Scope& parent,
                         const Eigen::Isometry3d& pose, int cls, Scope* scope) {
  std::vector<const TiXmlElement*> moving;
  for (const TiXmlElement* j : doc_.children(b)) {
    const std::string tag = j->Value();
    if (tag != "joint" && tag != "freejoint") continue;
    const auto type = find(j, "joint", defaults_.classOf(j, cls), "type");
    if (tag == "freejoint" || (type && type->text == "free")) {
      if (parent.link >= 0)
        doc_.fail(j,
                  "a free joint inside the hand: taskmap's hands are trees of hinge and "
                  "slide joints");
      out_.warnings.push_back(doc_.where(j) +
                              ": free joint of the top body ignored (taskmap fixes the hand's "
                              "base at the palm pose)");
      continue;
    }
    moving.push_back(j);
  }
  auto pushLink = [&](const std::string& link_name) {
    if (out_.tree.links.size() >= kMaxHandLinks)
      doc_.fail(b, "more than " + std::to_string(kMaxHandLinks) +
                       " links (bodies, and a link per extra joint of a body): the limit of a "
                       "hand; refused");
    out_.tree.links.push_back(
        {link_name, static_cast<int>(out_.tree.joints.size()) - 1, {}, {}, {}});
    out_.dynamics.links.emplace_back();
    out_.dynamics.shapes.emplace_back();
    return static_cast<int>(out_.tree.links.size()) - 1;
  };
  auto pushJoint = [&](UrdfJoint joint, const JointDynamics& d) {
    joint.parent_link = scope->link;
    joint.child_link = static_cast<int>(out_.tree.links.size());
    out_.tree.joints.push_back(std::move(joint));
    out_.dynamics.joints.push_back(d);
    out_.dynamics.actuators.emplace_back();
  };
  if (parent.link < 0) {  // the top body: the root link
    if (!moving.empty())
      doc_.fail(moving[0],
                "the hand's top body has a joint: taskmap fixes the hand's base at "
                "the palm pose; put the joint in a child body");
    scope->link = pushLink(name);
    return scope->link;
  }
  scope->link = parent.link;
  const Eigen::Isometry3d origin = parent.in_link * pose;
  if (moving.empty()) {
    UrdfJoint fixed;
    fixed.name = name + "_fixed";
    fixed.type = UrdfJointType::kFixed;
    fixed.origin = origin;
    pushJoint(fixed, {});
    scope->link = pushLink(name);
    return scope->link;
  }
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < moving.size(); ++i) {
    UrdfJoint joint;
    JointDynamics d;
    readJoint(moving[i], defaults_.classOf(moving[i], cls), &joint, &d);
    const Eigen::Vector3d anchor = joint.origin.translation();
    joint.origin = i == 0 ? origin * translation(anchor) : translation(anchor - previous);
    previous = anchor;
    const std::string link_name = i + 1 == moving.size() ? name : name + "/" + joint.name;
    pushJoint(joint, d);
    scope->link = pushLink(link_name);
  }
  scope->in_link = translation(-previous);
  return scope->link;
}

void MjcfReader::readJoint(const TiXmlElement* j, int cls, UrdfJoint* joint, JointDynamics* d) {
  const auto type_attr = find(j, "joint", cls, "type");
  const std::string type = type_attr ? type_attr->text : "hinge";
  if (type == "ball")
    doc_.fail(j, "ball joints are not supported: write the rotation as hinge joints");
  if (type != "hinge" && type != "slide")
    doc_.fail(j, "joint type '" + type + "' is not hinge, slide or free");
  const bool hinge = type == "hinge";
  const double angle = hinge && compiler_.degrees ? kPi / 180.0 : 1.0;
  const char* n = j->Attribute("name");
  joint->name = n ? n : "joint" + std::to_string(body_count_[1]);
  ++body_count_[1];
  if (!joints_.emplace(joint->name, static_cast<int>(out_.tree.joints.size())).second)
    doc_.fail(j, "a second joint named '" + joint->name + "'");
  if (auto p = find(j, "joint", cls, "pos"))
    joint->origin.translation() = vec3(mjcfNumbers(doc_, *p, "pos", 3, 3));
  joint->axis = Eigen::Vector3d::UnitZ();
  if (auto a = find(j, "joint", cls, "axis")) {
    joint->axis = vec3(mjcfNumbers(doc_, *a, "axis", 3, 3));
    if (!(joint->axis.norm() > 1e-12)) doc_.fail(a->at, "axis must not be zero");
    joint->axis.normalize();
  }
  if (number(j, "joint", cls, "ref", 0.0) != 0.0)
    doc_.fail(j, "a non-zero ref (the joint value at the pose as written) is not supported");
  const auto range = find(j, "joint", cls, "range");
  const auto limited = find(j, "joint", cls, "limited");
  int limit = limited ? mjcfBool(doc_, *limited, "limited", true) : -1;
  if (limit < 0) {
    if (range && !compiler_.autolimits)
      doc_.fail(range->at,
                "has a range but no limited=\"true\", and the compiler's autolimits "
                "is false: say whether the joint is limited");
    limit = range ? 1 : 0;
  }
  if (limit == 1) {
    const std::vector<double> r =
        range ? mjcfNumbers(doc_, *range, "range", 2, 2) : std::vector<double>{0, 0};
    if (!(r[0] < r[1]))
      doc_.fail(range ? range->at : j, "a limited joint needs range lower < upper");
    joint->limits = UrdfLimits{r[0] * angle, r[1] * angle, 0.0, 0.0};
    joint->type = hinge ? UrdfJointType::kRevolute : UrdfJointType::kPrismatic;
  } else {
    if (!hinge) doc_.fail(j, "a slide joint needs limits (range) for taskmap to close it");
    joint->type = UrdfJointType::kContinuous;  // an unlimited hinge, as a URDF continuous joint
  }
  auto stated = [&](const char* key, std::optional<double>* out, double scale) {
    if (auto a = find(j, "joint", cls, key)) *out = mjcfNumbers(doc_, *a, key, 1, 1)[0] * scale;
  };
  stated("damping", &d->damping, 1.0);
  stated("armature", &d->armature, 1.0);
  stated("frictionloss", &d->frictionloss, 1.0);
  stated("stiffness", &d->stiffness, 1.0);
  stated("springref", &d->springref, angle);
}

void MjcfReader::addInertial(const TiXmlElement* i, const Scope& scope) {
  if (compiler_.inertia_from_geom) return;  // MuJoCo ignores them too
  UrdfInertial in;
  const char* mass = i->Attribute("mass");
  if (!mass) doc_.fail(i, "<inertial> needs mass");
  in.mass = mjcfNumbers(doc_, {mass, i}, "mass", 1, 1)[0];
  if (!(in.mass >= 0.0)) doc_.fail(i, "mass must not be negative");
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  if (const char* p = i->Attribute("pos"))
    frame.translation() = vec3(mjcfNumbers(doc_, {p, i}, "pos", 3, 3));
  const Eigen::Quaterniond q = mjcfOrientation(doc_, defaults_, compiler_, i, {}, -1);
  frame.linear() = q.toRotationMatrix();
  if (const char* d = i->Attribute("diaginertia")) {
    in.inertia = vec3(mjcfNumbers(doc_, {d, i}, "diaginertia", 3, 3)).asDiagonal();
  } else if (const char* f = i->Attribute("fullinertia")) {
    if (!q.coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs()))
      doc_.fail(i, "fullinertia is in the body's axes: give no orientation with it");
    const auto v = mjcfNumbers(doc_, {f, i}, "fullinertia", 6, 6);
    in.inertia << v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2];
  } else {
    doc_.fail(i, "<inertial> needs diaginertia or fullinertia");
  }
  in.origin = scope.in_link * frame;
  out_.tree.links[static_cast<std::size_t>(scope.link)].inertial = in;
  out_.dynamics.links[static_cast<std::size_t>(scope.link)] = in;
}

void MjcfReader::addContents(const TiXmlElement* container, const Scope& scope,
                             const Eigen::Isometry3d& frame, int cls, int depth) {
  const bool in_frame = std::string(container->Value()) == "frame";
  for (const TiXmlElement* c : doc_.children(container)) {
    const std::string tag = c->Value();
    if (tag == "body") {
      addBody(c, scope, frame, cls, depth + 1);
    } else if (tag == "frame") {
      if (depth + 1 > kMaxMjcfDepth) doc_.fail(c, "frames nested too deep");
      Eigen::Isometry3d f = frame;
      if (const char* p = c->Attribute("pos"))
        f.translate(vec3(mjcfNumbers(doc_, {p, c}, "pos", 3, 3)));
      f.rotate(mjcfOrientation(doc_, defaults_, compiler_, c, {}, cls));
      const char* child = c->Attribute("childclass");
      addContents(c, scope, f, child ? defaults_.classNamed(child, c) : cls, depth + 1);
    } else if (tag == "geom") {
      addGeom(c, scope, frame, cls);
    } else if (tag == "joint" || tag == "freejoint" || tag == "inertial") {
      if (in_frame) doc_.fail(c, "<" + tag + "> inside a <frame> is not supported");
    } else if (tag != "site" && tag != "camera" && tag != "light") {
      doc_.fail(c, "<" + tag + "> is not supported in a hand's body");
    }
  }
}

}  // namespace taskmap::detail
