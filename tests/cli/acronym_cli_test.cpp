// Third-party grasps get the hold test: `taskmap import --acronym ... --hand URDF` closes the
// real Franka hand's jaws at each pose (joint values), records the hand, and `taskmap validate`
// tests the imported map with the jaws closing from open; without a hand, validate says what to
// do. On a small ACRONYM file written here, and on ACRONYM's own mug file (CC BY-NC: read from
// TASKMAP_REAL_DIR, never copied; skipped when absent).
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/mapstore/acronym.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

const std::string kFranka = std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf";
const std::string kBox = std::string(TASKMAP_OBJECTS_DIR) + "/box.obj";  // 6 x 8 x 12 cm, z >= 0

/// The Franka hand's palm frame in its base frame (the sidecar: at the finger joints).
Eigen::Isometry3d frankaBaseToPalm() {
  Eigen::Isometry3d b = Eigen::Isometry3d::Identity();
  b.translation() = Eigen::Vector3d(0, 0, 0.0584);
  return b;
}

/// A palm above the box at (x, y, z), approach down, jaws closing along the object's x turned
/// by `turn` radians about z.
Pose above(double x, double y, double z, double turn = 0.0) {
  Eigen::Matrix3d r;
  r << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  return {Eigen::Vector3d(x, y, z),
          Eigen::Quaterniond(Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()) * r)};
}

class AcronymCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("acronym_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  /// Six Franka grasps of the box in ACRONYM's layout: five with the pads on its upper part
  /// (centred, 8 mm off along the jaws, 2 cm across them, higher, turned 20 degrees) and one
  /// 40 cm above it, whose jaws close on nothing.
  std::string writeBoxGrasps() {
    poses_ = {above(0, 0, 0.15), above(0.008, 0, 0.15), above(0, 0.02, 0.15),
              above(0, 0, 0.16), above(0, 0, 0.40),     above(0, 0, 0.15, 0.35)};
    TaskMapData m;
    m.generator = "taskmap test";
    m.object = mapObjectOf(ObjectModel::load(kBox));
    m.hand.name = "panda";
    const auto n = static_cast<Eigen::Index>(poses_.size());
    m.grasps.pose.resize(n, 7);
    for (Eigen::Index i = 0; i < n; ++i)
      m.grasps.pose.row(i) = poses_[static_cast<std::size_t>(i)].toVector7().transpose();
    m.grasps.joints.resize(n, 0);
    m.grasps.force_closure = {1, 1, 1, 1, 0, 1};
    m.grasps.epsilon = {1, 1, 1, 1, 0, 1};
    m.grasps.volume.assign(poses_.size(), 0.0);
    m.grasps.contact_offsets.assign(poses_.size() + 1, 0);
    m.grasps.contact_points.resize(0, 3);
    m.grasps.contact_normals.resize(0, 3);
    m.grasps.contacts_available = false;
    AcronymExportOptions o;
    o.base_to_palm = frankaBaseToPalm();
    writeAcronym(path("box_grasps.h5"), m, o);
    return path("box_grasps.h5");
  }

  std::vector<Pose> poses_;
  fs::path dir_;
};

TEST_F(AcronymCliTest, ImportedGraspsGetJointsAndTheHoldTest) {
  const std::string acronym = writeBoxGrasps();
  auto r = testing::runTaskmap("import --acronym " + acronym + " --object " + kBox + " --hand " +
                               kFranka + " --no-cluster -o " + path("box.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("dropped 1 grasps whose jaws miss the object; kept 0 whose open jaws "
                       "intersect it"),
            std::string::npos)
      << r.out;
  const TaskMapData map = readMap(path("box.h5"));
  ASSERT_EQ(map.grasps.size(), 5u);
  EXPECT_EQ(map.hand.name, "franka_hand");
  EXPECT_EQ(map.hand.joint_names, std::vector<std::string>{"panda_finger_joint1"});
  const auto params = nlohmann::json::parse(map.sampling.params_json);
  EXPECT_EQ(params.at("jaws_missed"), nlohmann::json::array({4}));
  EXPECT_EQ(params.at("jaws_overlap"), nlohmann::json::array());
  EXPECT_EQ(params.at("hold_closing"), "from_open");
  EXPECT_EQ(map.sampling.outcomes.at("jaws_missed"), 1u);
  // Poses exactly as imported; the jaws closed on the 6 cm box: 3 cm each (to the pad's 0.02 mm).
  const std::vector<std::size_t> kept = {0, 1, 2, 3, 5};
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const Pose p = map.grasps.poseAt(k);
    EXPECT_LT((p.position - poses_[kept[k]].position).norm(), 1e-12) << k;
    EXPECT_LT(p.orientation.angularDistance(poses_[kept[k]].orientation), 1e-9) << k;
  }
  for (Eigen::Index k = 0; k < 4; ++k) EXPECT_NEAR(map.grasps.joints(k, 0), 0.03, 1e-4) << k;
  EXPECT_GT(map.grasps.joints(4, 0), 0.03 + 1e-3);  // turned: the jaws meet the box wider

  // The recorded hand is found; the jaws close from open and press with 70 N: the box holds.
  r = testing::runTaskmap("validate " + path("box.h5") + " --robust --threads 2 --json -o " +
                          path("labelled.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["tested"], 5);
  EXPECT_TRUE(j["close_from_open"].get<bool>());
  EXPECT_GE(j["holding"].get<int>(), 4) << r.out;
  EXPECT_GE(j["robust"].get<int>(), 3) << r.out;
  const TaskMapData labelled = readMap(path("labelled.h5"));
  ASSERT_TRUE(labelled.validation);
  EXPECT_TRUE(nlohmann::json::parse(labelled.validation->params_json).at("close_from_open"));
  // The hand given explicitly, and one grasp traced.
  r = testing::runTaskmap("validate " + path("box.h5") + " --hand " + kFranka + " --grasps 1 -o " +
                          path("explicit.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("jaws closed from open"), std::string::npos) << r.out;
  r = testing::runTaskmap("validate " + path("box.h5") + " --trace 0");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("panda_leftfinger"), std::string::npos) << r.out;
}

TEST_F(AcronymCliTest, WithoutAHandTheMapSaysHowToGetOne) {
  const std::string acronym = writeBoxGrasps();
  auto r = testing::runTaskmap("import --acronym " + acronym + " --object " + kBox + " -o " +
                               path("poses.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("joint values: none"), std::string::npos) << r.out;
  for (const std::string& hand : {std::string(), " --hand " + kFranka}) {
    r = testing::runTaskmap("validate " + path("poses.h5") + hand);
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.out.find("have no joint values"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("--hand URDF"), std::string::npos) << r.out;
  }
  // A hand that is not a parallel-jaw gripper is refused at import, nothing written.
  r = testing::runTaskmap("import --acronym " + acronym + " --object " + kBox +
                          " --hand barrett -o " + path("barrett.h5"));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("is not a parallel-jaw gripper"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(path("barrett.h5")));
}

std::string realDir() {
  const char* env = std::getenv("TASKMAP_REAL_DIR");
  return env ? env : TASKMAP_REAL_DIR;
}

/// ACRONYM's mug file and its mesh under realDir(), or nothing.
std::optional<std::pair<std::string, std::string>> realMug() {
  const fs::path dir = realDir();
  std::string grasps, mesh;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir / "acronym", ec))
    if (e.path().filename().string().rfind("Mug_", 0) == 0) grasps = e.path().string();
  for (const auto& e : fs::directory_iterator(dir / "objects", ec))
    if (e.path().filename().string().rfind("acronym_mug_", 0) == 0) mesh = e.path().string();
  if (grasps.empty() || mesh.empty()) return std::nullopt;
  return std::make_pair(grasps, mesh);
}

TEST_F(AcronymCliTest, ACRONYMsOwnMugFileIsImportedWithTheFrankaHandAndValidated) {
  const auto mug = realMug();
  if (!mug) GTEST_SKIP() << "ACRONYM example not found under " << realDir();
  const std::string source = " --acronym " + mug->first + " --object " + mug->second;
  auto r = testing::runTaskmap("import" + source + " --hand " + kFranka + " --no-cluster -o " +
                               path("mug.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("closed from open"), std::string::npos) << r.out;
  const TaskMapData map = readMap(path("mug.h5"));
  const auto params = nlohmann::json::parse(map.sampling.params_json);
  // Every one of the 2000 grasps is kept but those whose jaws close on nothing.
  EXPECT_EQ(map.grasps.size() + params.at("jaws_missed").size(), 2000u);
  EXPECT_GT(map.grasps.size(), 1900u);
  EXPECT_EQ(map.hand.name, "franka_hand");
  EXPECT_EQ(params.at("hand"), fs::absolute(kFranka).string());
  for (Eigen::Index i = 0; i < map.grasps.joints.rows(); ++i) {
    EXPECT_GE(map.grasps.joints(i, 0), 0.0) << i;
    EXPECT_LE(map.grasps.joints(i, 0), 0.04) << i;
  }
  // The recorded hand is found: the first grasps get the robust label, the jaws closing from
  // open.
  r = testing::runTaskmap("validate " + path("mug.h5") +
                          " --robust --grasps 2 --threads 2 --json -o " + path("labelled.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["tested"], 2);
  EXPECT_TRUE(j["close_from_open"].get<bool>());
  EXPECT_TRUE(j.contains("force_closure_robust"));
  // Imported without a hand: validate says to import again with --hand.
  r = testing::runTaskmap("import" + source + " --no-cluster -o " + path("poses.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  r = testing::runTaskmap("validate " + path("poses.h5") + " --grasps 1");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("--hand URDF"), std::string::npos) << r.out;
}

TEST_F(AcronymCliTest, AMissingRecordedHandIsNamedWithWhatToPass) {
  // The hand imported from a copy that is then removed: validate names the recorded path and
  // asks for --hand.
  const std::string acronym = writeBoxGrasps();
  const fs::path copy = dir_ / "hand";
  fs::create_directories(copy);
  fs::copy(fs::path(kFranka).parent_path(), copy, fs::copy_options::recursive);
  const std::string urdf = (copy / "franka_hand.urdf").string();
  auto r = testing::runTaskmap("import --acronym " + acronym + " --object " + kBox + " --hand " +
                               urdf + " --no-cluster -o " + path("box.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  fs::remove_all(copy);
  r = testing::runTaskmap("validate " + path("box.h5") + " --grasps 1");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find(urdf), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("pass --hand URDF"), std::string::npos) << r.out;
  r = testing::runTaskmap("validate " + path("box.h5") + " --grasps 1 --hand " + kFranka + " -o " +
                          path("labelled.h5"));
  EXPECT_EQ(r.code, 0) << r.out;
}

}  // namespace
}  // namespace taskmap
