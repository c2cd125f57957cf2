// `taskmap reach --map ... -o trajectory.h5 --glb out.glb` and `taskmap export-glb`: the
// trajectory file agrees with the JSON, the GLB parses (header, chunks, accessor bounds) and
// assimp (the independent oracle) imports it with the expected nodes and animation; bad input
// gives clear errors.
#include <assimp/anim.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "seal_oracle.hpp"
#include "synthetic_map.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/mapstore/trajectory_file.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

std::string tempPath(const std::string& name) {
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("trajectory_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

nlohmann::json parseJson(const std::string& out) {
  const auto a = out.find('{'), b = out.rfind('}');
  if (a == std::string::npos || b == std::string::npos) return nullptr;
  return nlohmann::json::parse(out.substr(a, b - a + 1));
}

std::uint32_t u32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(b[at + k]);
  return v;
}

/// One plan on the synthetic basket map (three bar clusters), written once for all tests.
struct Planned {
  std::string map, trajectory, glb;
  testing::CliRun run;
  nlohmann::json json;
};

const Planned& planned() {
  static const Planned p = [] {
    Planned r;
    r.map = tempPath("basket.h5");
    r.trajectory = tempPath("reach.h5");
    r.glb = tempPath("reach.glb");
    writeMap(r.map, testing::clusteredBasketMap(30, 0));
    r.run =
        testing::runTaskmap("reach --map " + r.map + " --scene " + std::string(TASKMAP_SOURCE_DIR) +
                            "/reaching/scenes/basket_reference.json --object-pose \"0.5 0 0 "
                            "1.5708\" --iterations 3 --no-resimulate --json -o " +
                            r.trajectory + " --glb " + r.glb + " --png " + tempPath("r.png"));
    r.json = parseJson(r.run.out);
    return r;
  }();
  return p;
}

TEST(TrajectoryCli, FileAgreesWithTheJson) {
  const Planned& p = planned();
  ASSERT_TRUE(p.run.code == 0 || p.run.code == 1) << p.run.out;  // 1: plan unsafe, still written
  ASSERT_FALSE(p.json.is_null()) << p.run.out;
  const TrajectoryRecord r = readTrajectory(p.trajectory);
  EXPECT_EQ(r.rows(), 301u);
  EXPECT_EQ(r.dt, 0.01);
  EXPECT_EQ(r.joint_names.front(), "fer_joint1");
  EXPECT_EQ(r.robot, "panda");
  EXPECT_EQ(r.hand, "humanoid");
  EXPECT_EQ(r.object_name, "basket");
  EXPECT_NEAR(r.object_pose.position.x(), 0.5, 1e-12);
  EXPECT_EQ(r.cluster, p.json["cluster"].get<int>());
  EXPECT_EQ(r.grasp_index, p.json["grasp_index"].get<std::int64_t>());
  const std::string map_bytes = test::fileBytes(p.map);
  EXPECT_EQ(r.map_sha256, test::sha256Hex(map_bytes.data(), map_bytes.size()));
  // /plan/grasp: the map's hand and the chosen grasp's joint values (what `view` closes to).
  const TaskMapData map = readMap(p.map);
  EXPECT_EQ(r.map_hand, map.hand.name);
  EXPECT_EQ(r.grasp_joint_names, map.hand.joint_names);
  ASSERT_GE(r.grasp_index, 0);
  EXPECT_EQ(r.grasp_joints, map.grasps.joints.row(r.grasp_index).transpose());
  const auto q = p.json["q_final"].get<std::vector<double>>();
  for (std::size_t i = 0; i < q.size(); ++i)
    EXPECT_EQ(r.joints(300, static_cast<Eigen::Index>(i)), q[i]);
  const auto& h = p.json["cost_history"];
  ASSERT_EQ(static_cast<std::size_t>(r.cost_history.rows()), h.size());
  EXPECT_EQ(r.cost_terms.front(), "total");
  for (std::size_t i = 0; i < h.size(); ++i)
    EXPECT_EQ(r.cost_history(static_cast<Eigen::Index>(i), 0), h[i]["total"].get<double>());
  // The palm pose in the object frame is the world palm pose seen from the object.
  const Eigen::Isometry3d palm = Pose::fromVector7(r.palm_world.row(300).transpose()).toIsometry();
  const Eigen::Vector3d rel = r.object_pose.toIsometry().inverse() * palm.translation();
  EXPECT_LT((rel - r.palm_object.row(300).head<3>().transpose()).norm(), 1e-12);
}

TEST(TrajectoryCli, MapTermsOverTheMovementEndWhereTheIterationsEnd) {
  const Planned& p = planned();
  ASSERT_FALSE(p.json.is_null()) << p.run.out;
  const auto prox = p.json["proximity_over_movement"].get<std::vector<double>>();
  const auto qual = p.json["quality_over_movement"].get<std::vector<double>>();
  ASSERT_EQ(prox.size(), 301u);
  ASSERT_EQ(qual.size(), 301u);
  // The plan ends on its sample (docs/REACHING.md "Ending on the sample"): the last step's
  // proximity term is 0 there, no more than the last iteration's terminal cost left.
  const auto& last = p.json["cost_history"].back();
  ASSERT_TRUE(p.json["plans"][0]["ends_on_sample"].get<bool>());
  EXPECT_NEAR(prox.back(), 0.0, 1e-9);
  EXPECT_LE(prox.back(), last["proximity"].get<double>() + 1e-12);
  EXPECT_GT(prox.front(), prox.back());  // the hand approaches the manifold
  const TrajectoryRecord r = readTrajectory(p.trajectory);
  for (std::size_t t = 0; t < 301; ++t) {
    EXPECT_EQ(r.proximity_over_movement[static_cast<Eigen::Index>(t)], prox[t]);
    EXPECT_EQ(r.quality_over_movement[static_cast<Eigen::Index>(t)], qual[t]);
  }
  EXPECT_TRUE(fs::exists(tempPath("r_costs.png")));
}

/// Checks the GLB container and every accessor against its buffer view; returns the JSON.
nlohmann::json checkGlb(const std::string& bytes) {
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  EXPECT_EQ(u32(bytes, 4), 2u);
  EXPECT_EQ(u32(bytes, 8), bytes.size());
  const std::uint32_t json_length = u32(bytes, 12);
  EXPECT_EQ(bytes.substr(16, 4), "JSON");
  EXPECT_EQ(json_length % 4, 0u);
  const nlohmann::json j = nlohmann::json::parse(bytes.substr(20, json_length));
  const std::size_t bin_at = 20 + json_length;
  const std::uint32_t bin_length = u32(bytes, bin_at);
  EXPECT_EQ(bytes.substr(bin_at + 4, 4), std::string("BIN\0", 4));
  EXPECT_EQ(bin_at + 8 + bin_length, bytes.size());
  EXPECT_EQ(j["buffers"][0]["byteLength"].get<std::size_t>(), bin_length);
  for (const auto& a : j["accessors"]) {
    const auto& v = j["bufferViews"][a["bufferView"].get<std::size_t>()];
    const std::size_t width = a["type"] == "SCALAR" ? 1 : a["type"] == "VEC3" ? 3 : 4;
    const std::size_t offset = v["byteOffset"].get<std::size_t>();
    EXPECT_EQ(v["byteLength"].get<std::size_t>(), a["count"].get<std::size_t>() * width * 4);
    EXPECT_LE(offset + v["byteLength"].get<std::size_t>(), bin_length);
    EXPECT_EQ(offset % 4, 0u);
    if (a["componentType"] != 5126) continue;
    const float* f = reinterpret_cast<const float*>(bytes.data() + bin_at + 8 + offset);
    for (std::size_t i = 0; i < a["count"].get<std::size_t>() * width; ++i) {
      EXPECT_GE(f[i], a["min"][i % width].get<float>());
      EXPECT_LE(f[i], a["max"][i % width].get<float>());
    }
  }
  for (const auto& m : j["meshes"]) {
    const auto& prim = m["primitives"][0];
    const std::size_t vertices =
        j["accessors"][prim["attributes"]["POSITION"].get<std::size_t>()]["count"];
    const auto& ia = j["accessors"][prim["indices"].get<std::size_t>()];
    const auto& v = j["bufferViews"][ia["bufferView"].get<std::size_t>()];
    const auto* idx = reinterpret_cast<const std::uint32_t*>(bytes.data() + bin_at + 8 +
                                                             v["byteOffset"].get<std::size_t>());
    EXPECT_EQ(ia["count"].get<std::size_t>() % 3, 0u);
    EXPECT_LT(prim["material"].get<std::size_t>(), j["materials"].size());
    for (std::size_t i = 0; i < ia["count"].get<std::size_t>(); ++i) EXPECT_LT(idx[i], vertices);
  }
  return j;
}

std::size_t countNodes(const aiNode* n) {
  std::size_t c = 1;
  for (unsigned i = 0; i < n->mNumChildren; ++i) c += countNodes(n->mChildren[i]);
  return c;
}

TEST(TrajectoryCli, GlbParsesAndAssimpImportsIt) {
  const Planned& p = planned();
  const TrajectoryRecord r = readTrajectory(p.trajectory);
  const std::string bytes = test::fileBytes(p.glb);
  const nlohmann::json j = checkGlb(bytes);
  std::size_t moving = 0;
  for (std::int32_t role : r.body_roles) moving += role != 2;
  EXPECT_EQ(j["nodes"].size(), r.body_names.size() + 2);  // bodies, object mesh, world
  ASSERT_EQ(j["animations"].size(), 1u);
  EXPECT_EQ(j["animations"][0]["channels"].size(), 2 * moving);
  // Every channel's keys are the stored body poses (float32), glTF quaternions x y z w.
  const char* bin = bytes.data() + 20 + u32(bytes, 12) + 8;
  const auto& anim = j["animations"][0];
  for (const auto& c : anim["channels"]) {
    const std::size_t b = c["target"]["node"], sampler = c["sampler"];
    const auto& out = j["accessors"][anim["samplers"][sampler]["output"].get<std::size_t>()];
    const auto& v = j["bufferViews"][out["bufferView"].get<std::size_t>()];
    const float* f = reinterpret_cast<const float*>(bin + v["byteOffset"].get<std::size_t>());
    ASSERT_EQ(out["count"].get<std::size_t>(), r.rows());
    for (std::size_t t : {std::size_t{0}, r.rows() / 2, r.rows() - 1}) {
      const Pose pose = r.bodyPose(t, b);
      if (c["target"]["path"] == "translation") {
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(f[3 * t + k], pose.position[k], 1e-6);
      } else {
        const Eigen::Quaterniond q(f[4 * t + 3], f[4 * t], f[4 * t + 1], f[4 * t + 2]);
        EXPECT_LT(q.angularDistance(pose.orientation), 1e-5) << r.body_names[b];
      }
    }
  }
  // export-glb of the file gives the same bytes as reach --glb.
  const std::string again = tempPath("again.glb");
  const testing::CliRun e = testing::runTaskmap("export-glb " + p.trajectory + " -o " + again);
  ASSERT_EQ(e.code, 0) << e.out;
  EXPECT_TRUE(test::fileBytes(again) == bytes);

  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(p.glb, aiProcess_ValidateDataStructure);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  EXPECT_GE(countNodes(scene->mRootNode), r.body_names.size() + 2);
  EXPECT_LE(countNodes(scene->mRootNode), r.body_names.size() + 3);  // + assimp's own root
  EXPECT_EQ(scene->mNumMeshes, j["meshes"].size());
  EXPECT_GE(scene->mNumMaterials, 4u);  // robot, hand, environment, object
  ASSERT_EQ(scene->mNumAnimations, 1u);
  const aiAnimation* a = scene->mAnimations[0];
  EXPECT_EQ(a->mNumChannels, moving);
  const double ticks = a->mTicksPerSecond > 0 ? a->mTicksPerSecond : 1.0;
  EXPECT_NEAR(a->mDuration / ticks, 300 * 0.01, 1e-4);
  EXPECT_EQ(a->mChannels[0]->mNumPositionKeys, 301u);
}

/// Distance from p (body frame) to the primitive's core (segment or rectangle).
double coreDistance(const TrajectoryShape& s, const Eigen::Vector3d& p) {
  const Eigen::Vector3d local = s.axes.transpose() * (p - s.center);
  const Eigen::Vector3d nearest(std::clamp(local.x(), -s.half_u, s.half_u),
                                std::clamp(local.y(), -s.half_v, s.half_v), 0.0);
  return (local - nearest).norm();
}

/// Volume of a sphere-swept segment or rectangle.
double shapeVolume(const TrajectoryShape& s) {
  const double r = s.radius, u = 2 * s.half_u, v = 2 * s.half_v;
  return 4.0 / 3.0 * M_PI * r * r * r + M_PI * r * r * (u + v) + 2 * r * u * v;
}

TEST(TrajectoryCli, GlbMeshesAreClosedOutwardSurfacesOfThePrimitives) {
  const Planned& p = planned();
  const TrajectoryRecord r = readTrajectory(p.trajectory);
  const std::string bytes = test::fileBytes(p.glb);
  const nlohmann::json j = checkGlb(bytes);
  const char* bin = bytes.data() + 20 + u32(bytes, 12) + 8;
  const auto view = [&](std::size_t accessor) {
    const auto& v = j["bufferViews"][j["accessors"][accessor]["bufferView"].get<std::size_t>()];
    return bin + v["byteOffset"].get<std::size_t>();
  };
  int checked = 0;
  for (std::size_t b = 0; b < r.body_names.size(); ++b) {
    const nlohmann::json& node = j["nodes"][b];
    if (!node.contains("mesh")) continue;
    const auto& prim = j["meshes"][node["mesh"].get<std::size_t>()]["primitives"][0];
    const std::size_t pa = prim["attributes"]["POSITION"], ia = prim["indices"];
    const std::size_t nv = j["accessors"][pa]["count"], ni = j["accessors"][ia]["count"];
    const float* f = reinterpret_cast<const float*>(view(pa));
    const auto* idx = reinterpret_cast<const std::uint32_t*>(view(ia));
    std::vector<Eigen::Vector3d> v(nv);
    for (std::size_t i = 0; i < nv; ++i)
      v[i] = Eigen::Vector3d(f[3 * i], f[3 * i + 1], f[3 * i + 2]);
    double volume = 0.0, expected = 0.0;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (std::size_t t = 0; t + 2 < ni; t += 3) {
      volume += v[idx[t]].dot(v[idx[t + 1]].cross(v[idx[t + 2]])) / 6.0;
      for (int e = 0; e < 3; ++e) ++edges[{idx[t + e], idx[t + (e + 1) % 3]}];
    }
    for (const auto& [edge, count] : edges) {  // closed and consistently oriented
      EXPECT_EQ(count, 1);
      EXPECT_EQ(edges.count({edge.second, edge.first}), 1u);
    }
    std::vector<const TrajectoryShape*> shapes;
    for (const TrajectoryShape& s : r.shapes)
      if (s.body == static_cast<int>(b)) shapes.push_back(&s), expected += shapeVolume(s);
    for (const Eigen::Vector3d& x : v) {  // every vertex on some primitive's surface
      double best = INFINITY;
      for (const TrajectoryShape* s : shapes)
        best = std::min(best, std::abs(coreDistance(*s, x) - s->radius));
      EXPECT_LT(best, 1e-6) << r.body_names[b];
    }
    // Inscribed polyhedra of convex shapes: at most the exact volume, and close to it.
    EXPECT_LE(volume, expected * (1 + 1e-6)) << r.body_names[b];
    EXPECT_GE(volume, 0.9 * expected) << r.body_names[b];
    ++checked;
  }
  EXPECT_GE(checked, 8);  // arm links, palm, table
}

TEST(TrajectoryCli, BadInputGivesClearErrors) {
  const Planned& p = planned();
  testing::CliRun r = testing::runTaskmap("export-glb /nonexistent/t.h5 -o " + tempPath("x.glb"));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("/nonexistent/t.h5"), std::string::npos) << r.out;
  r = testing::runTaskmap("export-glb " + p.map + " -o " + tempPath("x.glb"));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("not a trajectory file"), std::string::npos) << r.out;
  const std::string cut = tempPath("cut.h5");
  const std::string bytes = test::fileBytes(p.trajectory);
  test::writeBytes(cut, bytes.substr(0, bytes.size() / 2));
  r = testing::runTaskmap("export-glb " + cut + " -o " + tempPath("x.glb"));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("truncated"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(tempPath("x.glb")));
  r = testing::runTaskmap("export-glb " + p.trajectory + " -o /nonexistent_dir_tm/x.glb");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("/nonexistent_dir_tm/x.glb"), std::string::npos) << r.out;
  r = testing::runTaskmap("reach --target \"0.5 0 0.2 1 0 0 0\" -o " + tempPath("t.h5"));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("--map"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace taskmap
