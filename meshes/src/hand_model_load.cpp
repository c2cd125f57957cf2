// HandModel::load: URDF through urdfdom (console_bridge captured), mesh collision geometry
// through assimp (vertex sets, used as convex hulls), sidecar JSON through nlohmann-json.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <console_bridge/console.h>
#include <openssl/evp.h>
#include <urdf_parser/urdf_parser.h>
#include <assimp/Importer.hpp>
#include <nlohmann/json.hpp>

#include "hand_grasping_keys.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/meshes/hand_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

std::string readFile(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(std::string("cannot read ") + what + " '" + path + "': check the path");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string sha256Of(const std::string& bytes) {
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  EVP_Digest(bytes.data(), bytes.size(), md, &len, EVP_sha256(), nullptr);
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (unsigned int i = 0; i < len; ++i) {
    out += hex[md[i] >> 4];
    out += hex[md[i] & 15];
  }
  return out;
}

/// Collects console_bridge messages of urdfdom while parsing (the parser reports the element).
class CaptureHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) {
      if (!messages.empty()) messages += "; ";
      messages += text;
    }
  }
  std::string messages;
};

urdf::ModelInterfaceSharedPtr parseUrdf(const std::string& xml, const std::string& path) {
  static std::mutex mutex;  // console_bridge's handler is process-global
  std::lock_guard<std::mutex> lock(mutex);
  CaptureHandler handler;
  console_bridge::useOutputHandler(&handler);
  const auto old_level = console_bridge::getLogLevel();
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_WARN);
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    handler.messages += e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  console_bridge::setLogLevel(old_level);
  if (!model)
    throw Error("cannot parse URDF '" + path + "': " +
                (handler.messages.empty() ? std::string("malformed XML") : handler.messages));
  return model;
}

Eigen::Isometry3d toIso(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  Eigen::Quaterniond q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  if (q.norm() < 1e-12) q = Eigen::Quaterniond::Identity();
  t.linear() = q.normalized().toRotationMatrix();
  return t;
}

std::vector<Eigen::Vector3d> loadMeshPoints(const std::string& file, const Eigen::Vector3d& scale,
                                            const std::string& urdf_path, const std::string& link) {
  std::string f = file;
  if (f.rfind("file://", 0) == 0) f = f.substr(7);
  if (f.rfind("package://", 0) == 0)
    throw Error("URDF '" + urdf_path + "': link '" + link + "' mesh '" + file +
                "' uses package://, which is not supported: use a path relative to the URDF");
  fs::path p(f);
  if (p.is_relative()) p = fs::path(urdf_path).parent_path() / p;
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(p.string(), aiProcess_JoinIdenticalVertices);
  if (!scene || scene->mNumMeshes == 0)
    throw Error("URDF '" + urdf_path + "': link '" + link + "': cannot read collision mesh '" +
                p.string() + "': " + importer.GetErrorString());
  std::vector<Eigen::Vector3d> pts;
  std::function<void(const aiNode*, const aiMatrix4x4&)> walk = [&](const aiNode* node,
                                                                    const aiMatrix4x4& parent) {
    const aiMatrix4x4 t = parent * node->mTransformation;
    for (unsigned m = 0; m < node->mNumMeshes; ++m) {
      const aiMesh* mesh = scene->mMeshes[node->mMeshes[m]];
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const aiVector3D a = t * mesh->mVertices[v];
        pts.emplace_back(a.x * scale.x(), a.y * scale.y(), a.z * scale.z());
      }
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) walk(node->mChildren[c], t);
  };
  walk(scene->mRootNode, aiMatrix4x4());
  if (pts.size() < 4)
    throw Error("URDF '" + urdf_path + "': link '" + link + "': collision mesh '" + p.string() +
                "' has fewer than 4 vertices");
  std::sort(pts.begin(), pts.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  return pts;
}

Eigen::Vector3d vec3(const json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) throw Error(where + " must be an array of 3 numbers");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) {
    if (!j[static_cast<std::size_t>(i)].is_number()) throw Error(where + " must hold numbers");
    v[i] = j[static_cast<std::size_t>(i)].get<double>();
  }
  if (!v.allFinite()) throw Error(where + " must be finite");
  return v;
}

double number(const json& j, const std::string& where) {
  if (!j.is_number()) throw Error(where + " must be a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw Error(where + " must be finite");
  return v;
}

/// Largest distance from the origin to a point of shape `s` placed at pose `t`, metres.
double farthestPoint(const CollisionShape& s, const Eigen::Isometry3d& t) {
  double r = 0.0;
  switch (s.type) {
    case ShapeType::kBox:
      for (int i = 0; i < 8; ++i) {
        const Eigen::Vector3d c((i & 1 ? 0.5 : -0.5) * s.box_size.x(),
                                (i & 2 ? 0.5 : -0.5) * s.box_size.y(),
                                (i & 4 ? 0.5 : -0.5) * s.box_size.z());
        r = std::max(r, (t * c).norm());
      }
      break;
    case ShapeType::kCylinder:
      // Farthest point of each end disc: axial offset and radial offset plus the radius.
      for (double side : {-0.5, 0.5}) {
        const Eigen::Vector3d c = t * Eigen::Vector3d(0, 0, side * s.length);
        const Eigen::Vector3d n = t.linear().col(2);
        const double axial = c.dot(n);
        const double radial = (c - axial * n).norm() + s.radius;
        r = std::max(r, std::hypot(axial, radial));
      }
      break;
    case ShapeType::kSphere:
      r = t.translation().norm() + s.radius;
      break;
    case ShapeType::kConvex:
      for (const auto& p : s.points) r = std::max(r, (t * p).norm());
      break;
  }
  return r;
}

}  // namespace

struct HandModelBuilder {
  static HandModel build(const std::string& urdf_path, const std::string& sidecar_arg);
};

HandModel HandModelBuilder::build(const std::string& urdf_path, const std::string& sidecar_arg) {
  HandModel h;
  const std::string xml = readFile(urdf_path, "URDF");
  h.urdf_path_ = urdf_path;
  h.sha_ = sha256Of(xml);
  const urdf::ModelInterfaceSharedPtr model = parseUrdf(xml, urdf_path);
  h.name_ = model->getName();
  const std::string U = "URDF '" + urdf_path + "': ";

  // Links and joints in depth-first order from the root (children by joint name).
  std::map<std::string, int> link_index;
  std::function<void(const urdf::LinkConstSharedPtr&, int)> add_link;
  add_link = [&](const urdf::LinkConstSharedPtr& link, int parent_joint) {
    HandLink hl;
    hl.name = link->name;
    hl.parent_joint = parent_joint;
    for (const auto& col : link->collision_array) {
      if (!col || !col->geometry) continue;
      CollisionShape s;
      s.origin = toIso(col->origin);
      const urdf::Geometry& g = *col->geometry;
      switch (g.type) {
        case urdf::Geometry::BOX: {
          const auto& b = static_cast<const urdf::Box&>(g);
          s.type = ShapeType::kBox;
          s.box_size = Eigen::Vector3d(b.dim.x, b.dim.y, b.dim.z);
          if (!(s.box_size.minCoeff() > 0.0))
            throw Error(U + "link '" + link->name + "': <box size> must be positive");
          break;
        }
        case urdf::Geometry::CYLINDER: {
          const auto& c = static_cast<const urdf::Cylinder&>(g);
          s.type = ShapeType::kCylinder;
          s.radius = c.radius;
          s.length = c.length;
          if (!(s.radius > 0.0 && s.length > 0.0))
            throw Error(U + "link '" + link->name +
                        "': <cylinder> radius and length must be positive");
          break;
        }
        case urdf::Geometry::SPHERE: {
          const auto& sp = static_cast<const urdf::Sphere&>(g);
          s.type = ShapeType::kSphere;
          s.radius = sp.radius;
          if (!(s.radius > 0.0))
            throw Error(U + "link '" + link->name + "': <sphere radius> must be positive");
          break;
        }
        case urdf::Geometry::MESH: {
          const auto& m = static_cast<const urdf::Mesh&>(g);
          s.type = ShapeType::kConvex;
          s.points = loadMeshPoints(m.filename, Eigen::Vector3d(m.scale.x, m.scale.y, m.scale.z),
                                    urdf_path, link->name);
          break;
        }
      }
      hl.shapes.push_back(std::move(s));
    }
    const int li = static_cast<int>(h.links_.size());
    link_index[hl.name] = li;
    h.links_.push_back(std::move(hl));
    for (const auto& child_joint : link->child_joints) {
      const urdf::Joint& uj = *child_joint;
      HandJoint j;
      j.name = uj.name;
      j.parent_link = li;
      j.origin = toIso(uj.parent_to_joint_origin_transform);
      Eigen::Vector3d axis(uj.axis.x, uj.axis.y, uj.axis.z);
      switch (uj.type) {
        case urdf::Joint::REVOLUTE:
        case urdf::Joint::CONTINUOUS:
          j.type = JointType::kRevolute;
          break;
        case urdf::Joint::PRISMATIC:
          j.type = JointType::kPrismatic;
          break;
        case urdf::Joint::FIXED:
          j.type = JointType::kFixed;
          break;
        default:
          throw Error(U + "joint '" + uj.name +
                      "' is floating or planar, which hands cannot have: use revolute, "
                      "prismatic, continuous or fixed");
      }
      if (j.type != JointType::kFixed) {
        if (!(axis.norm() > 1e-9)) throw Error(U + "joint '" + uj.name + "' has a zero <axis>");
        j.axis = axis.normalized();
        if (uj.type == urdf::Joint::CONTINUOUS) {
          j.lower = -kPi;
          j.upper = kPi;
        } else {
          if (!uj.limits) throw Error(U + "joint '" + uj.name + "' has no <limit lower upper>");
          j.lower = uj.limits->lower;
          j.upper = uj.limits->upper;
          if (!(j.lower <= j.upper))
            throw Error(U + "joint '" + uj.name + "': <limit> lower must not exceed upper");
        }
        if (uj.mimic) {
          j.mimic = true;
          j.multiplier = uj.mimic->multiplier;
          j.offset = uj.mimic->offset;
        }
      }
      const int ji = static_cast<int>(h.joints_.size());
      h.joints_.push_back(j);
      add_link(model->getLink(uj.child_link_name), ji);
      h.joints_[static_cast<std::size_t>(ji)].child_link = link_index.at(uj.child_link_name);
    }
  };
  if (!model->getRoot()) throw Error(U + "has no root link");
  add_link(model->getRoot(), -1);

  // Actuated joints: movable, not mimic; mimic joints resolve to their (transitive) driver.
  for (HandJoint& j : h.joints_) {
    if (j.type == JointType::kFixed || j.mimic) continue;
    j.driver = static_cast<int>(h.actuated_.size());
    h.actuated_.push_back(j.name);
    h.lower_.push_back(j.lower);
    h.upper_.push_back(j.upper);
  }
  for (std::size_t k = 0; k < h.joints_.size(); ++k) {
    HandJoint& j = h.joints_[k];
    if (!j.mimic) continue;
    double mult = 1.0, off = 0.0;
    const HandJoint* cur = &j;
    std::set<std::string> seen{j.name};
    while (cur->mimic) {
      const auto uj = model->getJoint(cur->name);
      const std::string target = uj->mimic->joint_name;
      auto it = std::find_if(h.joints_.begin(), h.joints_.end(),
                             [&](const HandJoint& x) { return x.name == target; });
      if (it == h.joints_.end() || it->type == JointType::kFixed)
        throw Error(U + "joint '" + j.name + "': <mimic joint='" + target +
                    "'> names no movable joint of the URDF");
      if (!seen.insert(target).second)
        throw Error(U + "joint '" + j.name + "': <mimic> chain is cyclic");
      // q_cur = m_cur * q_target + o_cur; accumulated q_j = mult * q_cur + off.
      off += mult * cur->offset;
      mult *= cur->multiplier;
      cur = &*it;
    }
    j.multiplier = mult;
    j.offset = off;
    j.driver = cur->driver;
  }
  if (h.actuated_.empty()) throw Error(U + "has no actuated (non-fixed, non-mimic) joint");

  // ---- Sidecar ----
  std::string sidecar = sidecar_arg;
  if (sidecar.empty()) {
    const fs::path p(urdf_path);
    sidecar = (p.parent_path() / (p.stem().string() + ".hand.json")).string();
  }
  h.sidecar_path_ = sidecar;
  const std::string text = readFile(sidecar, "hand sidecar");
  const std::string S = "hand sidecar '" + sidecar + "': ";
  json js;
  try {
    js = json::parse(text);
  } catch (const std::exception& e) {
    throw Error(S + "invalid JSON: " + e.what());
  }
  if (!js.is_object()) throw Error(S + "must be a JSON object");
  static const std::set<std::string> kKeys = {
      "palm_link", "palm_frame",     "approach_axis", "preshape",   "closing", "squeeze",
      "fingers",   "rotation_scale", "description",   "dimensions", "coupled", "grasp"};
  for (auto it = js.begin(); it != js.end(); ++it)
    if (!kKeys.count(it.key()))
      throw Error(S + "unknown key '" + it.key() + "' (see meshes/hands/README.md)");
  for (const char* k : {"palm_link", "approach_axis", "closing", "squeeze", "fingers"})
    if (!js.contains(k)) throw Error(S + "missing required key '" + k + "'");

  auto need_geometry = [&](int li, const std::string& role) {
    if (h.links_[static_cast<std::size_t>(li)].shapes.empty())
      throw Error(S + role + " link '" + h.links_[static_cast<std::size_t>(li)].name +
                  "' has no <collision> geometry in '" + urdf_path + "'");
  };
  auto find_link = [&](const json& v, const std::string& where) {
    if (!v.is_string()) throw Error(S + where + " must be a link name");
    const int li = h.linkIndex(v.get<std::string>());
    if (li < 0)
      throw Error(S + where + " names link '" + v.get<std::string>() + "', which '" + urdf_path +
                  "' does not have");
    return li;
  };
  auto find_joint = [&](const json& v, const std::string& where) {
    if (!v.is_string()) throw Error(S + where + " must be a joint name");
    const int ji = h.jointIndex(v.get<std::string>());
    if (ji < 0)
      throw Error(S + where + " names joint '" + v.get<std::string>() +
                  "', which is not an actuated (non-fixed, non-mimic) joint of '" + urdf_path +
                  "'");
    return ji;
  };

  h.palm_link_ = find_link(js["palm_link"], "palm_link");
  need_geometry(h.palm_link_, "palm");
  if (js.contains("palm_frame")) {
    const json& pf = js["palm_frame"];
    if (!pf.is_object()) throw Error(S + "palm_frame must be an object with xyz and rpy");
    Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
    if (pf.contains("xyz")) xyz = vec3(pf["xyz"], S + "palm_frame.xyz");
    if (pf.contains("rpy")) rpy = vec3(pf["rpy"], S + "palm_frame.rpy");
    h.palm_frame_ = Eigen::Isometry3d::Identity();
    h.palm_frame_.translation() = xyz;
    h.palm_frame_.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                              Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                              Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                                 .toRotationMatrix();
  }
  // The palm must be the root or hang from it by fixed joints only.
  {
    int li = h.palm_link_;
    while (h.links_[static_cast<std::size_t>(li)].parent_joint >= 0) {
      const HandJoint& j =
          h.joints_[static_cast<std::size_t>(h.links_[static_cast<std::size_t>(li)].parent_joint)];
      if (j.type != JointType::kFixed)
        throw Error(S + "palm_link '" + h.links_[static_cast<std::size_t>(h.palm_link_)].name +
                    "' is moved by joint '" + j.name +
                    "': the palm must be the URDF root or fixed to it");
      li = j.parent_link;
    }
  }
  const Eigen::Vector3d approach = vec3(js["approach_axis"], S + "approach_axis");
  if (!(approach.norm() > 1e-9)) throw Error(S + "approach_axis must not be zero");
  h.approach_ = approach.normalized();

  // Preshape: listed joints take their value, others their value nearest 0 within limits.
  const std::size_t n = h.actuated_.size();
  h.preshape_ = Eigen::VectorXd(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i)
    h.preshape_[static_cast<Eigen::Index>(i)] = std::clamp(0.0, h.lower_[i], h.upper_[i]);
  if (js.contains("preshape")) {
    if (!js["preshape"].is_object()) throw Error(S + "preshape must map joint names to values");
    for (auto it = js["preshape"].begin(); it != js["preshape"].end(); ++it) {
      const int ji = find_joint(json(it.key()), "preshape");
      const double v = number(it.value(), S + "preshape." + it.key());
      const auto u = static_cast<std::size_t>(ji);
      if (v < h.lower_[u] - 1e-12 || v > h.upper_[u] + 1e-12)
        throw Error(S + "preshape." + it.key() + " = " + std::to_string(v) +
                    " is outside the joint limits [" + std::to_string(h.lower_[u]) + ", " +
                    std::to_string(h.upper_[u]) + "]");
      h.preshape_[ji] = v;
    }
  }

  // Closing motion.
  if (!js["closing"].is_array() || js["closing"].empty())
    throw Error(S + "closing must be a non-empty array of {joint, toward, speed}");
  std::set<int> closing_seen;
  for (std::size_t c = 0; c < js["closing"].size(); ++c) {
    const json& e = js["closing"][c];
    const std::string where = "closing[" + std::to_string(c) + "]";
    if (!e.is_object() || !e.contains("joint"))
      throw Error(S + where + " must be an object with a joint");
    ClosingJoint cj;
    cj.joint = find_joint(e["joint"], where + ".joint");
    if (!closing_seen.insert(cj.joint).second)
      throw Error(S + where + ".joint '" + e["joint"].get<std::string>() + "' is listed twice");
    const std::string toward = e.value("toward", std::string("upper"));
    const auto u = static_cast<std::size_t>(cj.joint);
    if (toward == "upper")
      cj.target = h.upper_[u];
    else if (toward == "lower")
      cj.target = h.lower_[u];
    else
      throw Error(S + where + ".toward must be \"lower\" or \"upper\", not \"" + toward + "\"");
    cj.speed = e.contains("speed") ? number(e["speed"], S + where + ".speed") : 1.0;
    if (!(cj.speed > 0.0)) throw Error(S + where + ".speed must be positive");
    h.closing_.push_back(cj);
  }
  h.squeeze_ = number(js["squeeze"], S + "squeeze");
  if (h.squeeze_ < 0.0 || h.squeeze_ > 0.01) throw Error(S + "squeeze must be in [0, 0.01] metres");
  HandGraspingKeys::read(js, S, &h);

  // Fingers.
  if (!js["fingers"].is_object() || js["fingers"].empty())
    throw Error(S + "fingers must map finger names to arrays of link names");
  for (auto it = js["fingers"].begin(); it != js["fingers"].end(); ++it) {
    const int fi = static_cast<int>(h.fingers_.size());
    h.fingers_.push_back(it.key());
    if (!it.value().is_array() || it.value().empty())
      throw Error(S + "fingers." + it.key() + " must be a non-empty array of link names");
    for (const json& l : it.value()) {
      const int li = find_link(l, "fingers." + it.key());
      need_geometry(li, "finger");
      HandLink& hl = h.links_[static_cast<std::size_t>(li)];
      if (hl.finger >= 0) throw Error(S + "link '" + hl.name + "' belongs to two fingers");
      hl.finger = fi;
    }
  }

  // Palm-rigid links: the palm link and every link reached from it by fixed joints.
  h.links_[static_cast<std::size_t>(h.palm_link_)].palm = true;
  for (const HandJoint& j : h.joints_) {
    const auto child = static_cast<std::size_t>(j.child_link);
    if (j.type == JointType::kFixed && h.links_[static_cast<std::size_t>(j.parent_link)].palm)
      h.links_[child].palm = true;
  }
  // Links above the palm attached by fixed joints also move with it.
  for (int pass = 0; pass < 2; ++pass)
    for (const HandJoint& j : h.joints_) {
      if (j.type != JointType::kFixed) continue;
      auto& parent = h.links_[static_cast<std::size_t>(j.parent_link)];
      auto& child = h.links_[static_cast<std::size_t>(j.child_link)];
      if (child.palm) parent.palm = true;
      if (parent.palm) child.palm = true;
    }
  for (const HandLink& l : h.links_)
    if (l.palm && l.finger >= 0)
      throw Error(S + "finger link '" + l.name + "' is rigidly attached to the palm");

  // Palm frame in the root frame (constant: the palm hangs from the root by fixed joints).
  {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    int li = h.palm_link_;
    std::vector<const HandJoint*> chain;
    while (h.links_[static_cast<std::size_t>(li)].parent_joint >= 0) {
      const HandJoint& j =
          h.joints_[static_cast<std::size_t>(h.links_[static_cast<std::size_t>(li)].parent_joint)];
      chain.push_back(&j);
      li = j.parent_link;
    }
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) t = t * (*it)->origin;
    h.root_to_palm_ = t * h.palm_frame_;
  }

  // Drivers of each link, and lever bounds of each actuated joint.
  h.link_drivers_.assign(h.links_.size(), {});
  for (std::size_t li = 0; li < h.links_.size(); ++li) {
    std::set<int> drivers;
    int cur = static_cast<int>(li);
    while (h.links_[static_cast<std::size_t>(cur)].parent_joint >= 0) {
      const HandJoint& j =
          h.joints_[static_cast<std::size_t>(h.links_[static_cast<std::size_t>(cur)].parent_joint)];
      if (j.driver >= 0 && !h.links_[li].palm) drivers.insert(j.driver);
      cur = j.parent_link;
    }
    h.link_drivers_[li].assign(drivers.begin(), drivers.end());
  }
  // Max distance from a joint origin to any point of its subtree, independent of joint values:
  // sum of joint offsets (+ prismatic travel) down the chain plus the shape's bounding radius.
  std::function<double(int)> subtree_extent = [&](int li) {
    const HandLink& l = h.links_[static_cast<std::size_t>(li)];
    double r = 0.0;
    for (const auto& s : l.shapes)
      r = std::max(r, s.origin.translation().norm() + s.boundingRadius());
    for (std::size_t k = 0; k < h.joints_.size(); ++k) {
      const HandJoint& j = h.joints_[k];
      if (j.parent_link != li) continue;
      double travel = j.origin.translation().norm();
      if (j.type == JointType::kPrismatic) travel += std::max(std::abs(j.lower), std::abs(j.upper));
      r = std::max(r, travel + subtree_extent(j.child_link));
    }
    return r;
  };
  h.levers_.assign(n, 0.0);
  for (const HandJoint& j : h.joints_) {
    if (j.driver < 0) continue;
    const double lever = j.type == JointType::kPrismatic ? 1.0 : subtree_extent(j.child_link);
    double& l = h.levers_[static_cast<std::size_t>(j.driver)];
    l = std::max(l, std::abs(j.multiplier) * lever);
  }

  // Reach and rotation scale from the open hand: the farthest point of any (finger) shape
  // from the palm origin.
  const auto poses = h.linkPoses(h.preshape_);
  double reach = 0.0, finger_reach = 0.0;
  for (std::size_t li = 0; li < h.links_.size(); ++li)
    for (const auto& s : h.links_[li].shapes) {
      const double r = farthestPoint(s, poses[li] * s.origin);
      reach = std::max(reach, r);
      if (h.links_[li].finger >= 0) finger_reach = std::max(finger_reach, r);
    }
  h.reach_ = reach;
  h.rotation_scale_ = finger_reach > 0.0 ? finger_reach : reach;
  if (js.contains("rotation_scale")) {
    h.rotation_scale_ = number(js["rotation_scale"], S + "rotation_scale");
    if (!(h.rotation_scale_ > 0.0)) throw Error(S + "rotation_scale must be positive");
  }
  return h;
}

HandModel HandModel::load(const std::string& urdf_path, const std::string& sidecar_path) {
  return HandModelBuilder::build(urdf_path, sidecar_path);
}

}  // namespace taskmap
