// Trajectory files: exact round trip, same bytes for the same record, invalid records refused,
// and a clear error (never HDF5 on unverified bytes) for missing, garbage, truncated,
// corrupted and foreign files.
#include "taskmap/mapstore/trajectory_file.hpp"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "seal_oracle.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

std::string tempPath(const std::string& name) {
  static const std::string dir = [] {
    const std::string d =
        ::testing::TempDir() + "trajectory_file_test_" + std::to_string(::getpid());
    EXPECT_EQ(std::system(("mkdir -p '" + d + "'").c_str()), 0);
    return d;
  }();
  return dir + "/" + name;
}

RowMatrixXd randomPoses(Eigen::Index rows, Eigen::Index bodies) {
  RowMatrixXd m = RowMatrixXd::Random(rows, 7 * bodies);
  for (Eigen::Index r = 0; r < rows; ++r)
    for (Eigen::Index b = 0; b < bodies; ++b) {
      auto q = m.row(r).segment<4>(7 * b + 3);
      q *= (q(0) < 0 ? -1.0 : 1.0) / q.norm();  // unit, canonical sign qw >= 0 (as Pose)
    }
  return m;
}

// A record of `steps` + 1 rows with random but valid content: 3 joints, 4 bodies, 3 shapes.
TrajectoryRecord sampleRecord(int steps) {
  std::srand(7);  // Eigen's Random: the same record on every call
  const Eigen::Index s = steps + 1;
  TrajectoryRecord r;
  r.generator = "taskmap test";
  r.robot = "panda";
  r.hand = "humanoid";
  r.dt = 0.01;
  r.joint_names = {"j1", "j2", "j3"};
  r.joints = RowMatrixXd::Random(s, 3);
  r.palm_world = randomPoses(s, 1);
  r.palm_object = randomPoses(s, 1);
  r.object_name = "basket";
  r.object_pose.position = Eigen::Vector3d(0.5, 0.1, 0.0);
  r.object_pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  r.object_vertices = RowMatrixXd::Random(5, 3);
  r.object_faces.resize(2, 3);
  r.object_faces << 0, 1, 2, 2, 3, 4;
  r.map_path = "/maps/basket.h5";
  r.map_sha256 = std::string(64, 'c');
  r.start_cluster = 2;
  r.cluster = 3;
  r.grasp_index = 41;
  r.quality_peak = 4.17e7;
  r.map_hand = "humanoid";
  r.map_hand_sha256 = std::string(64, 'd');
  r.map_hand_path = "/hands/humanoid/humanoid.urdf";
  r.grasp_joint_names = {"thumb", "index"};
  r.grasp_joints = Eigen::Vector2d(0.25, 1.5);
  r.cost_terms = {"total", "path_length", "proximity"};
  r.cost_history = RowMatrixXd::Random(6, 3);
  r.proximity_over_movement = Eigen::VectorXd::Random(s);
  r.quality_over_movement = Eigen::VectorXd::Random(s);
  r.body_names = {"base", "link1", "palm", "table"};
  r.body_parents = {-1, 0, 1, -1};
  r.body_roles = {0, 0, 1, 2};
  r.body_poses = randomPoses(s, 4);
  TrajectoryShape capsule;
  capsule.body = 1;
  capsule.center = Eigen::Vector3d(0, 0, 0.1);
  capsule.half_u = 0.05;
  capsule.radius = 0.04;
  TrajectoryShape box;
  box.body = 3;
  box.type = TrajectoryShapeType::kSweptRectangle;
  box.axes = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()).toRotationMatrix();
  box.half_u = 0.5;
  box.half_v = 0.7;
  box.radius = 0.02;
  r.shapes = {capsule, box, capsule};
  r.shapes[2].body = 2;
  return r;
}

void expectSame(const TrajectoryRecord& a, const TrajectoryRecord& b) {
  EXPECT_EQ(a.generator, b.generator);
  EXPECT_EQ(a.robot, b.robot);
  EXPECT_EQ(a.hand, b.hand);
  EXPECT_EQ(a.dt, b.dt);
  EXPECT_EQ(a.joint_names, b.joint_names);
  EXPECT_EQ(a.joints, b.joints);
  EXPECT_EQ(a.palm_world, b.palm_world);
  EXPECT_EQ(a.palm_object, b.palm_object);
  EXPECT_EQ(a.object_name, b.object_name);
  EXPECT_EQ(a.object_pose.toVector7(), b.object_pose.toVector7());
  EXPECT_EQ(a.object_vertices, b.object_vertices);
  EXPECT_EQ(a.object_faces, b.object_faces);
  EXPECT_EQ(a.map_path, b.map_path);
  EXPECT_EQ(a.map_sha256, b.map_sha256);
  EXPECT_EQ(a.start_cluster, b.start_cluster);
  EXPECT_EQ(a.cluster, b.cluster);
  EXPECT_EQ(a.grasp_index, b.grasp_index);
  EXPECT_EQ(a.quality_peak, b.quality_peak);
  EXPECT_EQ(a.map_hand, b.map_hand);
  EXPECT_EQ(a.map_hand_sha256, b.map_hand_sha256);
  EXPECT_EQ(a.map_hand_path, b.map_hand_path);
  EXPECT_EQ(a.grasp_joint_names, b.grasp_joint_names);
  EXPECT_EQ(a.grasp_joints, b.grasp_joints);
  EXPECT_EQ(a.cost_terms, b.cost_terms);
  EXPECT_EQ(a.cost_history, b.cost_history);
  EXPECT_EQ(a.proximity_over_movement, b.proximity_over_movement);
  EXPECT_EQ(a.quality_over_movement, b.quality_over_movement);
  EXPECT_EQ(a.body_names, b.body_names);
  EXPECT_EQ(a.body_parents, b.body_parents);
  EXPECT_EQ(a.body_roles, b.body_roles);
  EXPECT_EQ(a.body_poses, b.body_poses);
  ASSERT_EQ(a.shapes.size(), b.shapes.size());
  for (std::size_t i = 0; i < a.shapes.size(); ++i) {
    EXPECT_EQ(a.shapes[i].body, b.shapes[i].body);
    EXPECT_EQ(a.shapes[i].type, b.shapes[i].type);
    EXPECT_EQ(a.shapes[i].center, b.shapes[i].center);
    EXPECT_EQ(a.shapes[i].axes, b.shapes[i].axes);
    EXPECT_EQ(a.shapes[i].half_u, b.shapes[i].half_u);
    EXPECT_EQ(a.shapes[i].half_v, b.shapes[i].half_v);
    EXPECT_EQ(a.shapes[i].radius, b.shapes[i].radius);
  }
}

void expectReadError(const std::string& path, std::initializer_list<std::string> fragments) {
  const std::string message = testing::errorMessage([&] { readTrajectory(path); });
  ASSERT_FALSE(message.empty()) << "no error for " << path;
  EXPECT_NE(message.find(path), std::string::npos) << message;
  for (const std::string& f : fragments) EXPECT_NE(message.find(f), std::string::npos) << message;
}

TEST(TrajectoryFileTest, RoundTripIsExact) {
  const std::string path = tempPath("round.h5");
  const TrajectoryRecord r = sampleRecord(300);
  writeTrajectory(path, r);
  expectSame(r, readTrajectory(path));
  EXPECT_LT((readTrajectory(path).bodyPose(7, 2).toVector7() -
             r.body_poses.row(7).segment<7>(14).transpose())
                .norm(),
            1e-15);
}

TEST(TrajectoryFileTest, RoundTripOfASingleStepWithoutShapesOrHistory) {
  const std::string path = tempPath("single.h5");
  TrajectoryRecord r = sampleRecord(0);
  r.shapes.clear();
  r.cost_history.resize(0, 3);
  r.object_vertices.resize(0, 3);
  r.object_faces.resize(0, 3);
  writeTrajectory(path, r);
  expectSame(r, readTrajectory(path));
}

// A plan on a map without joint values (an ACRONYM import) and with g_q unscaled, like every
// file written before /plan/grasp and /plan quality_peak existed: no such group or attribute,
// and the reader leaves the fields empty and q* 1.
TEST(TrajectoryFileTest, WithoutTheGraspGroupTheFileStillLoads) {
  const std::string path = tempPath("no_grasp.h5");
  TrajectoryRecord r = sampleRecord(4);
  r.quality_peak = 1.0;
  r.map_hand.clear();
  r.map_hand_sha256.clear();
  r.map_hand_path.clear();
  r.grasp_joint_names.clear();
  r.grasp_joints.resize(0);
  writeTrajectory(path, r);
  EXPECT_EQ(test::fileBytes(path).find("hand_sha256"), std::string::npos);
  EXPECT_EQ(test::fileBytes(path).find("quality_peak"), std::string::npos);
  const TrajectoryRecord back = readTrajectory(path);
  expectSame(r, back);
  EXPECT_TRUE(back.grasp_joint_names.empty());
  EXPECT_EQ(back.quality_peak, 1.0);
  // With them, the group and the attribute are there.
  writeTrajectory(path, sampleRecord(4));
  EXPECT_NE(test::fileBytes(path).find("hand_sha256"), std::string::npos);
  EXPECT_NE(test::fileBytes(path).find("quality_peak"), std::string::npos);
}

TEST(TrajectoryFileTest, SameRecordGivesSameBytesAndNoTemporaryFileRemains) {
  const std::string a = tempPath("same_a.h5"), b = tempPath("same_b.h5");
  writeTrajectory(a, sampleRecord(20));
  writeTrajectory(b, sampleRecord(20));
  EXPECT_TRUE(test::fileBytes(a) == test::fileBytes(b));
  EXPECT_EQ(std::system(("ls '" + a + "'.tmp.* >/dev/null 2>&1").c_str()) == 0, false);
}

TEST(TrajectoryFileTest, InvalidRecordIsRefusedAndPreviousFileKept) {
  const std::string path = tempPath("kept.h5");
  writeTrajectory(path, sampleRecord(5));
  const std::string before = test::fileBytes(path);
  TrajectoryRecord r = sampleRecord(5);
  r.palm_world(2, 3) = 3.0;
  EXPECT_TRUE(testing::throwsError([&] { writeTrajectory(path, r); },
                                   {path, "palm_world row 2", "quaternion"}));
  r = sampleRecord(5);
  r.quality_over_movement.resize(3);
  EXPECT_TRUE(testing::throwsError([&] { writeTrajectory(path, r); }, {"quality_over_movement"}));
  r = sampleRecord(5);
  r.shapes[0].body = 9;
  EXPECT_TRUE(testing::throwsError([&] { writeTrajectory(path, r); }, {"shape 0", "body 9"}));
  r = sampleRecord(5);
  r.quality_peak = 0.0;
  EXPECT_TRUE(testing::throwsError([&] { writeTrajectory(path, r); }, {"quality_peak"}));
  r = sampleRecord(5);
  r.grasp_joints.resize(1);
  EXPECT_TRUE(testing::throwsError([&] { writeTrajectory(path, r); }, {"grasp joints"}));
  r = sampleRecord(5);
  r.dt = 0.0;
  EXPECT_TRUE(testing::throwsError([&] { writeTrajectory(path, r); }, {"dt_s"}));
  r = sampleRecord(5);
  r.joints(1, 1) = std::nan("");
  EXPECT_TRUE(testing::throwsError([&] { writeTrajectory(path, r); }, {"joints", "non-finite"}));
  EXPECT_TRUE(test::fileBytes(path) == before);
}

TEST(TrajectoryFileTest, UnwritableDirectoryNamesThePath) {
  const std::string path = "/nonexistent_dir_for_taskmap/t.h5";
  EXPECT_TRUE(testing::throwsError([&] { writeTrajectory(path, sampleRecord(2)); }, {path}));
}

TEST(TrajectoryFileTest, MissingAndGarbageFiles) {
  expectReadError(tempPath("missing.h5"), {"cannot open"});
  const std::string garbage = tempPath("garbage.h5");
  std::ofstream(garbage) << "not an HDF5 file\n";
  expectReadError(garbage, {"not a trajectory file", "no taskmap seal"});
}

TEST(TrajectoryFileTest, TruncatedFilesGiveClearErrors) {
  const std::string path = tempPath("full.h5");
  writeTrajectory(path, sampleRecord(300));
  const std::string bytes = test::fileBytes(path);
  ASSERT_GT(bytes.size(), 10000u);
  const std::string cut = tempPath("cut.h5");
  for (double fraction : {0.0, 0.05, 0.3, 0.6, 0.99}) {
    SCOPED_TRACE(fraction);
    test::writeBytes(cut, bytes.substr(0, static_cast<std::size_t>(fraction * bytes.size())));
    expectReadError(cut, {});
  }
  test::writeBytes(cut, bytes.substr(0, bytes.size() - 10));
  expectReadError(cut, {"truncated"});
}

TEST(TrajectoryFileTest, CorruptedBytesAreRefusedBeforeHdf5) {
  const std::string path = tempPath("flip_src.h5");
  writeTrajectory(path, sampleRecord(30));
  const std::string bytes = test::fileBytes(path);
  const std::string flipped = tempPath("flip.h5");
  for (std::size_t at = 600; at < bytes.size(); at += 997) {
    std::string b = bytes;
    b[at] = static_cast<char>(b[at] ^ 0x01);
    test::writeBytes(flipped, b);
    SCOPED_TRACE(at);
    expectReadError(flipped, {"does not match its seal", "write it again"});
    EXPECT_EQ(testing::errorMessage([&] { readTrajectory(flipped); }).find("taskmap seal"),
              std::string::npos);  // re-sealing would validate it as a task map
  }
}

TEST(TrajectoryFileTest, ATaskMapIsNotATrajectory) {
  // A sealed task map passes the seal but is refused by its format attribute.
  TaskMapData m;
  m.generator = "test";
  m.hand.name = "h";
  m.object.name = "o";
  m.object.vertices.resize(0, 3);
  m.object.faces.resize(0, 3);
  m.grasps.contact_offsets = {0};
  m.grasps.pose.resize(0, 7);
  m.grasps.joints.resize(0, 0);
  m.grasps.contact_points.resize(0, 3);
  m.grasps.contact_normals.resize(0, 3);
  const std::string path = tempPath("a_map.h5");
  writeMap(path, m);
  expectReadError(path, {"not a trajectory file"});
}

}  // namespace
}  // namespace taskmap
