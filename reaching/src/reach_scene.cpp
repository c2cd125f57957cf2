// Scene files: JSON bodies of boxes, capsules, spheres and swept rectangles.
#include "taskmap/reaching/reach_scene.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"
#include "taskmap/core/input_file.hpp"
#include "taskmap/core/pose.hpp"

namespace taskmap {
namespace {

using nlohmann::json;

struct SceneReader {
  std::string file;

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw Error("scene '" + file + "', " + where + ": " + what);
  }

  Eigen::VectorXd numbers(const json& j, const std::string& key, int n,
                          const std::string& where) const {
    if (!j.contains(key)) fail(where, "missing \"" + key + "\"");
    const json& v = j[key];
    if (!v.is_array() || static_cast<int>(v.size()) != n)
      fail(where, "\"" + key + "\" must be a list of " + std::to_string(n) + " numbers");
    Eigen::VectorXd out(n);
    for (int k = 0; k < n; ++k) {
      if (!v[k].is_number() || !std::isfinite(v[k].get<double>()))
        fail(where, "\"" + key + "\" must hold finite numbers");
      out[k] = v[k].get<double>();
    }
    return out;
  }

  double number(const json& j, const std::string& key, const std::string& where) const {
    return numbers(json{{key, json::array({j.contains(key) ? j[key] : json()})}}, key, 1, where)[0];
  }

  Eigen::Isometry3d pose(const json& j, const std::string& where) const {
    if (!j.contains("pose")) return Eigen::Isometry3d::Identity();
    const Eigen::VectorXd v = numbers(j, "pose", 7, where);
    try {
      return Pose::fromVector7(v).toIsometry();
    } catch (const Error& e) {
      fail(where, std::string("\"pose\" [x y z qw qx qy qz]: ") + e.what());
    }
  }

  Primitive shape(const json& s, const std::string& where) const {
    if (!s.is_object() || !s.contains("type") || !s["type"].is_string())
      fail(where, "each shape needs a \"type\": box, capsule, sphere or swept_rectangle");
    const std::string type = s["type"];
    try {
      if (type == "box") return Primitive::fromBox(pose(s, where), numbers(s, "size", 3, where));
      if (type == "capsule")
        return Primitive::capsule(numbers(s, "p0", 3, where), numbers(s, "p1", 3, where),
                                  number(s, "radius", where));
      if (type == "sphere") {
        const Eigen::Vector3d c = numbers(s, "center", 3, where);
        return Primitive::capsule(c, c, number(s, "radius", where));
      }
      if (type == "swept_rectangle") {
        const Eigen::Isometry3d t = pose(s, where);
        const Eigen::Vector2d h = numbers(s, "half_extents", 2, where);
        return Primitive::sweptRectangle(t.translation(), t.linear(), h.x(), h.y(),
                                         number(s, "radius", where));
      }
    } catch (const Error& e) {
      if (std::string(e.what()).rfind("scene '", 0) == 0) throw;
      fail(where, e.what());
    }
    fail(where, "unknown shape type \"" + type + "\"; use box, capsule, sphere or swept_rectangle");
  }
};

}  // namespace

ReachScene loadReachScene(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw Error("cannot read scene '" + path + "': no such file or not readable");
  const std::string text = readRegularFile(path, "scene");
  json j;
  try {
    j = json::parse(text);
  } catch (const std::exception& e) {
    throw Error("scene '" + path + "': not valid JSON (" + e.what() + ")");
  }
  const SceneReader r{path};
  if (!j.is_object() || !j.contains("bodies") || !j["bodies"].is_array())
    r.fail("top level", "needs a list \"bodies\"");
  ReachScene scene;
  std::set<std::string> names;
  for (size_t i = 0; i < j["bodies"].size(); ++i) {
    const json& b = j["bodies"][i];
    const std::string where = "bodies[" + std::to_string(i) + "]";
    if (!b.is_object() || !b.contains("name") || !b["name"].is_string())
      r.fail(where, "each body needs a \"name\"");
    SceneBody body;
    body.name = b["name"];
    if (!names.insert(body.name).second) r.fail(where, "duplicate body name '" + body.name + "'");
    body.pose = r.pose(b, where);
    if (!b.contains("shapes") || !b["shapes"].is_array() || b["shapes"].empty())
      r.fail(where, "needs a non-empty list \"shapes\"");
    for (size_t k = 0; k < b["shapes"].size(); ++k)
      body.shapes.push_back(r.shape(b["shapes"][k], where + ".shapes[" + std::to_string(k) + "]"));
    scene.bodies.push_back(std::move(body));
  }
  if (j.contains("object")) {
    if (!j["object"].is_string()) r.fail("object", "must be a body name");
    scene.object = j["object"];
    if (!names.count(scene.object)) r.fail("object", "no body named '" + scene.object + "'");
  }
  return scene;
}

ReachScene defaultReachScene() {
  ReachScene scene;
  SceneBody table;
  table.name = "table";
  table.pose.translation() = Eigen::Vector3d(0.3, 0.0, -0.02);
  table.shapes.push_back(Primitive::fromBox(Eigen::Isometry3d::Identity(), {1.2, 1.6, 0.04}));
  SceneBody object;
  object.name = "object";
  object.pose.translation() = Eigen::Vector3d(0.5, 0.2, 0.1);
  object.shapes.push_back(Primitive::capsule({0, 0, -0.06}, {0, 0, 0.06}, 0.04));
  scene.bodies = {table, object};
  scene.object = "object";
  return scene;
}

void addSceneTo(const ReachScene& scene, RobotModel& robot) {
  for (const SceneBody& b : scene.bodies) robot.addEnvironmentBody(b.name, b.pose, b.shapes);
}

}  // namespace taskmap
