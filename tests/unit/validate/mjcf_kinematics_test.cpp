// MuJoCo's own compiler as the oracle of the MJCF reader (issue 52): the test hand with every
// form MuJoCo 2.2.2 compiles (tests/data/hands/mjcf/forms.xml) and the real LEAP hand (with the
// README's four edits that 2.2.2 needs) loaded by HandModel and by mj_loadXML; over random joint
// values, every collision geom's frame (and the mesh's vertices) relative to the top body agree
// to 1e-9 m.
#include <gtest/gtest.h>

#include <mujoco/mujoco.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>

#include "scratch_dir.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;
const testing::ScratchDir kScratch("mjcf_kinematics");

Eigen::Isometry3d frameOf(const mjtNum* pos, const mjtNum* mat) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(pos[0], pos[1], pos[2]);
  t.linear() = Eigen::Map<const Eigen::Matrix<mjtNum, 3, 3, Eigen::RowMajor>>(mat);
  return t;
}

/// Largest distance between a HandModel's collision geometry and MuJoCo's, over `trials` random
/// joint configurations, relative to the top body (the hand's root link).
double largestError(const std::string& path, int trials, std::string* where) {
  const HandModel hand = HandModel::loadKinematics(path);
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  EXPECT_NE(m, nullptr) << error;
  if (!m) return 1.0;
  mjData* d = mj_makeData(m);
  std::mt19937_64 rng(52);
  double worst = 0.0;
  const auto note = [&](double e, const std::string& link, int shape) {
    if (e <= worst) return;
    worst = e;
    *where = "link " + link + " shape " + std::to_string(shape - 1);
  };
  const int root = mj_name2id(m, mjOBJ_BODY, hand.links()[0].name.c_str());
  for (int t = 0; t < trials; ++t) {
    Eigen::VectorXd q(static_cast<Eigen::Index>(hand.jointNames().size()));
    for (Eigen::Index i = 0; i < q.size(); ++i)
      q[i] =
          std::uniform_real_distribution<double>(hand.lowerLimits()[i], hand.upperLimits()[i])(rng);
    const Eigen::VectorXd all = hand.allJointValues(q);
    for (std::size_t j = 0; j < hand.joints().size(); ++j) {
      if (hand.joints()[j].type == JointType::kFixed) continue;
      const int id = mj_name2id(m, mjOBJ_JOINT, hand.joints()[j].name.c_str());
      EXPECT_GE(id, 0) << hand.joints()[j].name;
      if (id >= 0) d->qpos[m->jnt_qposadr[id]] = all[static_cast<Eigen::Index>(j)];
    }
    mj_kinematics(m, d);
    const Eigen::Isometry3d world_root = frameOf(d->xpos + 3 * root, d->xmat + 9 * root);
    const std::vector<Eigen::Isometry3d> poses = hand.linkPoses(q);
    for (std::size_t l = 0; l < hand.links().size(); ++l) {
      const HandLink& link = hand.links()[l];
      if (link.shapes.empty()) continue;
      const int b = mj_name2id(m, mjOBJ_BODY, link.name.c_str());
      EXPECT_GE(b, 0) << link.name;
      if (b < 0) continue;
      EXPECT_EQ(m->body_geomnum[b] >= static_cast<int>(link.shapes.size()), true) << link.name;
      int k = 0;
      for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
        if (m->geom_contype[g] == 0 && m->geom_conaffinity[g] == 0) continue;  // visual
        const CollisionShape& s = link.shapes[static_cast<std::size_t>(k++)];
        const Eigen::Isometry3d mine = poses[l] * s.origin;
        const Eigen::Isometry3d theirs =
            world_root.inverse() * frameOf(d->geom_xpos + 3 * g, d->geom_xmat + 9 * g);
        if (m->geom_type[g] == mjGEOM_MESH) {  // MuJoCo moves a mesh's frame: compare vertices
          const int mesh = m->geom_dataid[g];
          for (int v = 0; v < m->mesh_vertnum[mesh]; ++v) {
            const float* p = m->mesh_vert + 3 * (m->mesh_vertadr[mesh] + v);
            const Eigen::Vector3d at = theirs * Eigen::Vector3d(p[0], p[1], p[2]);
            double nearest = 1e9;
            for (const auto& x : s.points) nearest = std::min(nearest, (mine * x - at).norm());
            note(std::max(0.0, nearest - 1e-7), link.name, k);  // mesh_vert is float
          }
          continue;
        }
        note((mine.translation() - theirs.translation()).norm(), link.name, k);
        note(0.1 * (mine.linear() - theirs.linear()).norm(), link.name, k);  // a 10 cm lever
      }
    }
  }
  mj_deleteData(d);
  mj_deleteModel(m);
  return worst;
}

TEST(MjcfKinematics, TheTestHandMatchesMuJoCo) {
  std::string where;
  const double e = largestError(std::string(TEST_DATA_DIR) + "/hands/mjcf/forms.xml", 200, &where);
  EXPECT_LT(e, 1e-9) << where;
  std::printf("forms.xml: largest geometry difference to MuJoCo %.3g m (%s)\n", e, where.c_str());
}

TEST(MjcfKinematics, TheLeapHandMatchesMuJoCo) {
  // The README's edits for MuJoCo 2.2.2 (tests/data/real/hands/leap_hand_mjcf/README.md).
  const fs::path src = fs::path(TEST_DATA_DIR) / "real/hands/leap_hand_mjcf";
  std::ifstream in(src / "right_hand.xml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string xml = ss.str();
  xml = std::regex_replace(xml, std::regex(" kv=\"0.01\""), "");
  xml = std::regex_replace(xml, std::regex("implicitfast"), "implicit");
  xml = std::regex_replace(xml, std::regex("<compiler "), "<compiler autolimits=\"true\" ");
  xml = std::regex_replace(xml, std::regex("<geom name=\"[a-z_]+visual\"[^>]*/>"), "");
  xml = std::regex_replace(
      xml, std::regex("<mesh name=\"(?!tip|thumb_tip)[a-z_]+\" file=\"[a-z_]+.obj\"/>"), "");
  const fs::path dir = kScratch.path("leap");
  fs::create_directories(dir / "assets");
  for (const char* f : {"tip.obj", "thumb_tip.obj"})
    fs::copy_file(src / "assets" / f, dir / "assets" / f, fs::copy_options::overwrite_existing);
  std::ofstream(dir / "right_hand.xml") << xml;
  std::string where;
  const double e = largestError((dir / "right_hand.xml").string(), 200, &where);
  EXPECT_LT(e, 1e-9) << where;
  std::printf("LEAP hand: largest geometry difference to MuJoCo %.3g m (%s)\n", e, where.c_str());
}

}  // namespace
}  // namespace taskmap
