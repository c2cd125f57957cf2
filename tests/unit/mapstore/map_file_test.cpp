// Task map files: exact round trip, edge sizes, and a clear error for every corruption.
#include "taskmap/mapstore/map_file.hpp"

#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "map_compare.hpp"
#include "seal_oracle.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/random.hpp"
#include "taskmap/mapstore/grasp_contacts.hpp"

namespace taskmap {
namespace {

std::string tempDir() {
  static const std::string dir = [] {
    std::string d = ::testing::TempDir() + "map_file_test_" + std::to_string(::getpid());
    std::string cmd = "mkdir -p '" + d + "'";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    return d;
  }();
  return dir;
}

std::string tempPath(const std::string& name) {
  return tempDir() + "/" + name;
}

// A map of n grasps with random but valid content; clustering when n >= 1 and cluster.
TaskMapData sampleMap(int n, bool cluster = true, int joints = 4) {
  Rng rng(7, static_cast<std::uint64_t>(n));
  TaskMapData m;
  m.generator = "taskmap test";
  m.created_utc = "2026-01-01T00:00:00Z";
  m.object.name = "box";
  m.object.source_sha256 = std::string(64, 'a');
  m.object.scale = 0.5;
  m.object.volume = 0.001;
  m.object.center_of_mass = Eigen::Vector3d(0.01, -0.02, 0.03);
  m.object.torque_scale = 0.0866;
  m.object.vertices = RowMatrixXd::Random(8, 3);
  m.object.faces.resize(2, 3);
  m.object.faces << 0, 1, 2, 5, 6, 7;
  m.hand.name = "panda";
  m.hand.urdf_sha256 = std::string(64, 'b');
  for (int j = 0; j < joints; ++j) m.hand.joint_names.push_back("joint_" + std::to_string(j));
  m.sampling.sampler = "volume";
  m.sampling.seed = 12345678901234ull;
  m.sampling.trials = 100;
  m.sampling.outcomes = {{"force_closure", static_cast<std::uint64_t>(n)},
                         {"no_contact", 100 - static_cast<std::uint64_t>(n)}};
  m.sampling.params_json = R"({"valid": 3})";
  m.quality.friction = 0.7;
  m.quality.cone_edges = 6;
  m.quality.contact_model = "soft_finger";
  MapGrasps& g = m.grasps;
  g.rotation_scale = 0.12;
  g.pose.resize(n, 7);
  g.joints = RowMatrixXd::Random(n, joints);
  g.contact_offsets.push_back(0);
  std::vector<Pose> poses;
  for (int i = 0; i < n; ++i) {
    Pose p;
    p.position = Eigen::Vector3d(rng.uniform(), rng.uniform(), rng.uniform());
    p.orientation = rng.rotation();
    poses.push_back(p);
    g.pose.row(i) = p.toVector7().transpose();
    g.force_closure.push_back(static_cast<std::uint8_t>(i % 2));
    g.epsilon.push_back(rng.uniform());
    g.volume.push_back(rng.uniform() * 1e-3);
    g.contact_offsets.push_back(g.contact_offsets.back() + (i % 3) + 1);
  }
  const auto contacts = static_cast<Eigen::Index>(g.contact_offsets.back());
  g.contact_points = RowMatrixXd::Random(contacts, 3);
  g.contact_normals.resize(contacts, 3);
  for (Eigen::Index c = 0; c < contacts; ++c) {
    g.contact_normals.row(c) = rng.direction().transpose();
    g.contact_depths.push_back(rng.uniform() * 1e-3);
    g.contact_links.push_back(static_cast<std::int32_t>(c % 5) - 1);
  }
  if (cluster && n >= 1) {
    ClusteringResult c;
    c.method = Linkage::kAverage;
    c.rotation_scale = 0.12;
    c.threshold = 0.05;
    c.min_size = 1;
    c.linkage.resize(n - 1, 4);
    for (int r = 0; r + 1 < n; ++r)
      c.linkage.row(r) << (r == 0 ? 0 : n + r - 1), r + 1, 0.01 * r, r + 2;
    // Two clusters when possible: first half and second half; last grasp an outlier if n > 2.
    c.labels.assign(static_cast<std::size_t>(n), 0);
    for (int i = n / 2; i < n; ++i) c.labels[static_cast<std::size_t>(i)] = n >= 2 ? 1 : 0;
    if (n > 2) c.labels.back() = -1;
    const int k = n >= 2 ? 2 : 1;
    for (int j = 0; j < k; ++j) {
      ClusterSummary s;
      for (int i = 0; i < n; ++i)
        if (c.labels[static_cast<std::size_t>(i)] == j) {
          if (s.size == 0) s.representative = i;
          ++s.size;
        }
      s.mean_pose = poses[static_cast<std::size_t>(s.representative)];
      s.mean_pose.orientation =
          Eigen::Quaterniond(s.mean_pose.toVector7()(3), s.mean_pose.toVector7()(4),
                             s.mean_pose.toVector7()(5), s.mean_pose.toVector7()(6));
      s.mean_epsilon = 0.1 * j;
      s.best_epsilon = 0.2 * j;
      s.bounds_min = Eigen::Vector3d(-1, -2, -3 + j);
      s.bounds_max = Eigen::Vector3d(1, 2, 3 + j);
      c.clusters.push_back(s);
    }
    m.clustering = c;
  }
  return m;
}

void expectSameMap(const TaskMapData& a, const TaskMapData& b) {
  testing::expectSameMapContent(a, b, /*compare_created_utc=*/true);
}

// Expects readMap(path) to throw an Error whose message contains every part.
void expectReadError(const std::string& path, const std::vector<std::string>& parts) {
  const std::string msg = testing::errorMessage([&] { readMap(path); });
  ASSERT_FALSE(msg.empty()) << "readMap accepted " << path;
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << msg;
}

// ---- HDF5 edits for corrupt files (the test links HDF5 itself) ----
// Each edit is re-sealed without validation, so the reader's schema checks are what refuse it.
struct File {
  explicit File(const std::string& p)
      : path(p), id(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT)) {
    EXPECT_GE(id, 0);
  }
  ~File() {
    H5Fclose(id);
    test::forceReseal(path);
  }
  std::string path;
  hid_t id;
};

void setIntAttr(const std::string& path, const char* obj, const char* name, std::int64_t v) {
  File f(path);
  hid_t a = H5Aopen_by_name(f.id, obj, name, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(a, 0);
  EXPECT_GE(H5Awrite(a, H5T_NATIVE_INT64, &v), 0);
  H5Aclose(a);
}

template <typename T>
void editDataset(const std::string& path, const char* name, hid_t mem_type, std::size_t count,
                 const std::function<void(std::vector<T>&)>& edit) {
  File f(path);
  hid_t d = H5Dopen2(f.id, name, H5P_DEFAULT);
  ASSERT_GE(d, 0);
  std::vector<T> values(count);
  ASSERT_GE(H5Dread(d, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  edit(values);
  EXPECT_GE(H5Dwrite(d, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  H5Dclose(d);
}

void deleteLink(const std::string& path, const char* name) {
  File f(path);
  EXPECT_GE(H5Ldelete(f.id, name, H5P_DEFAULT), 0);
}

// ------------------------------------------------------------------------- tests

TEST(MapFileTest, GraspContactsAreTheRowsOfTheirGrasp) {
  const TaskMapData m = sampleMap(5);
  const MapGrasps& g = m.grasps;
  std::size_t total = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const std::vector<Contact> c = graspContacts(g, i);
    ASSERT_EQ(static_cast<std::int64_t>(c.size()), g.contact_offsets[i + 1] - g.contact_offsets[i]);
    for (std::size_t k = 0; k < c.size(); ++k) {
      const auto r = g.contact_offsets[i] + static_cast<std::int64_t>(k);
      EXPECT_EQ(c[k].point, g.contact_points.row(r).transpose());
      EXPECT_EQ(c[k].normal, g.contact_normals.row(r).transpose());
      EXPECT_EQ(c[k].depth, g.contact_depths[static_cast<std::size_t>(r)]);
      EXPECT_EQ(c[k].link, g.contact_links[static_cast<std::size_t>(r)]);
    }
    total += c.size();
  }
  EXPECT_EQ(static_cast<Eigen::Index>(total), g.contact_points.rows());
  EXPECT_GT(total, 0u);
}

TEST(MapFileTest, RoundTripIsExact) {
  const TaskMapData m = sampleMap(9);
  const std::string path = tempPath("round_trip.h5");
  writeMap(path, m);
  expectSameMap(m, readMap(path));
}

TEST(MapFileTest, RoundTripOfEmptyAndSingleGraspMaps) {
  for (int n : {0, 1, 2}) {
    for (bool cluster : {false, true}) {
      SCOPED_TRACE("n=" + std::to_string(n) + " cluster=" + std::to_string(cluster));
      const TaskMapData m = sampleMap(n, cluster);
      const std::string path = tempPath("small_" + std::to_string(n) + ".h5");
      writeMap(path, m);
      const TaskMapData r = readMap(path);
      expectSameMap(m, r);
      EXPECT_EQ(r.grasps.size(), static_cast<std::size_t>(n));
    }
  }
}

TEST(MapFileTest, RoundTripWithoutContactsOrJoints) {
  TaskMapData m = sampleMap(3, false, 0);
  m.grasps.contacts_available = false;
  m.grasps.contact_offsets.assign(4, 0);
  m.grasps.contact_points.resize(0, 3);
  m.grasps.contact_normals.resize(0, 3);
  m.grasps.contact_depths.clear();
  m.grasps.contact_links.clear();
  m.sampling.outcomes.clear();
  const std::string path = tempPath("no_contacts.h5");
  writeMap(path, m);
  expectSameMap(m, readMap(path));
}

TEST(MapFileTest, LargeMapSpansSeveralChunks) {
  const TaskMapData m = sampleMap(5000, false);
  const std::string path = tempPath("large.h5");
  writeMap(path, m);
  expectSameMap(m, readMap(path));
}

TEST(MapFileTest, PoseAtReturnsTheStoredRow) {
  const TaskMapData m = sampleMap(4);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_TRUE(m.grasps.poseAt(i).toVector7().isApprox(
        m.grasps.pose.row(static_cast<Eigen::Index>(i)).transpose(), 1e-15));
}

TEST(MapFileTest, WriteReplacesAtomicallyAndLeavesNoTemporaryFile) {
  const std::string dir = tempPath("atomic");
  ASSERT_EQ(std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "'").c_str()), 0);
  const std::string path = dir + "/map.h5";
  writeMap(path, sampleMap(2));
  writeMap(path, sampleMap(5));
  EXPECT_EQ(readMap(path).grasps.size(), 5u);
  // Only the map itself is in the directory.
  const std::string listing = dir + "/listing.txt";
  ASSERT_EQ(std::system(("ls '" + dir + "' > '" + listing + "'").c_str()), 0);
  std::ifstream in(listing);
  std::string line, all;
  while (std::getline(in, line)) all += line + "\n";
  EXPECT_EQ(all, "listing.txt\nmap.h5\n");
}

TEST(MapFileTest, InvalidMapIsRefusedAndPreviousFileKept) {
  const std::string path = tempPath("keep.h5");
  writeMap(path, sampleMap(3));
  TaskMapData bad = sampleMap(4);
  bad.grasps.pose(2, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(testing::throwsError([&] { writeMap(path, bad); }, {"/grasps/pose"}));
  EXPECT_EQ(readMap(path).grasps.size(), 3u);
}

TEST(MapFileTest, UnwritableDirectoryGivesErrorNamingPath) {
  const std::string path = tempPath("no/such/dir/map.h5");
  try {
    writeMap(path, sampleMap(2));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(MapFileTest, MissingFile) {
  expectReadError(tempPath("missing.h5"), {"missing"});
}

TEST(MapFileTest, GarbageFile) {
  const std::string path = tempPath("garbage.h5");
  std::ofstream(path) << "this is not an HDF5 file at all\n";
  expectReadError(path, {"not a task map", "no taskmap seal"});
}

TEST(MapFileTest, TruncatedFilesGiveErrorsNotCrashes) {
  const std::string path = tempPath("full.h5");
  writeMap(path, sampleMap(200));
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 1000u);
  for (double fraction : {0.0, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99}) {
    const std::string cut = tempPath("truncated.h5");
    std::ofstream(cut, std::ios::binary)
        .write(bytes.data(),
               static_cast<std::streamsize>(fraction * static_cast<double>(bytes.size())));
    SCOPED_TRACE(fraction);
    expectReadError(cut, {});
  }
}

TEST(MapFileTest, HdfFileOfAnotherKind) {
  const std::string path = tempPath("other.h5");
  hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  H5Fclose(f);
  expectReadError(path, {"no taskmap seal", "taskmap seal FILE"});
  EXPECT_TRUE(testing::throwsError([&] { sealMap(path); }, {path, "not a task map"}));
}

TEST(MapFileTest, NewerSchemaVersionAsksToUpgrade) {
  const std::string path = tempPath("newer.h5");
  writeMap(path, sampleMap(3));
  setIntAttr(path, "/", "schema_version", 3);
  expectReadError(path, {"written by a newer taskmap (schema 3); upgrade"});
}

TEST(MapFileTest, ZeroSchemaVersion) {
  const std::string path = tempPath("zero.h5");
  writeMap(path, sampleMap(3));
  setIntAttr(path, "/", "schema_version", 0);
  expectReadError(path, {"schema_version"});
}

TEST(MapFileTest, OffsetsOutOfBounds) {
  const std::string path = tempPath("offsets.h5");
  writeMap(path, sampleMap(5));
  editDataset<std::int64_t>(path, "/grasps/contact_offsets", H5T_NATIVE_INT64, 6,
                            [](std::vector<std::int64_t>& v) { v.back() += 100; });
  expectReadError(path, {"/grasps/contact_offsets", "out of bounds"});
}

TEST(MapFileTest, OffsetsNotMonotone) {
  const std::string path = tempPath("monotone.h5");
  writeMap(path, sampleMap(5));
  editDataset<std::int64_t>(path, "/grasps/contact_offsets", H5T_NATIVE_INT64, 6,
                            [](std::vector<std::int64_t>& v) { v[2] = v[3] + 1; });
  expectReadError(path, {"/grasps/contact_offsets", "decreases"});
}

TEST(MapFileTest, NanPose) {
  const std::string path = tempPath("nan.h5");
  writeMap(path, sampleMap(5));
  editDataset<double>(path, "/grasps/pose", H5T_NATIVE_DOUBLE, 35, [](std::vector<double>& v) {
    v[7 * 3 + 1] = std::numeric_limits<double>::quiet_NaN();
  });
  expectReadError(path, {"/grasps/pose", "row 3", "non-finite"});
}

TEST(MapFileTest, NonUnitQuaternion) {
  const std::string path = tempPath("quat.h5");
  writeMap(path, sampleMap(5));
  editDataset<double>(path, "/grasps/pose", H5T_NATIVE_DOUBLE, 35,
                      [](std::vector<double>& v) { v[7 * 4 + 3] *= 2.0; });
  expectReadError(path, {"/grasps/pose", "row 4", "non-unit quaternion"});
}

TEST(MapFileTest, MissingDatasetIsNamed) {
  const std::string path = tempPath("missing_dataset.h5");
  writeMap(path, sampleMap(5));
  deleteLink(path, "/grasps/epsilon");
  expectReadError(path, {"missing dataset /grasps/epsilon"});
}

TEST(MapFileTest, ClusterLabelOutOfRange) {
  const std::string path = tempPath("labels.h5");
  writeMap(path, sampleMap(5));
  editDataset<std::int32_t>(path, "/grasps/cluster", H5T_NATIVE_INT32, 5,
                            [](std::vector<std::int32_t>& v) { v[1] = 7; });
  expectReadError(path, {"/grasps/cluster", "entry 1"});
}

TEST(MapFileTest, ForceClosureNotBoolean) {
  const std::string path = tempPath("fc.h5");
  writeMap(path, sampleMap(5));
  editDataset<std::uint8_t>(path, "/grasps/force_closure", H5T_NATIVE_UINT8, 5,
                            [](std::vector<std::uint8_t>& v) { v[4] = 3; });
  expectReadError(path, {"/grasps/force_closure", "entry 4"});
}

TEST(MapFileTest, ValidateNamesTheViolatedDataset) {
  {
    TaskMapData m = sampleMap(4);
    m.grasps.epsilon.pop_back();
    EXPECT_THROW(m.validate(), Error);
  }
  {
    TaskMapData m = sampleMap(4);
    m.object.faces(1, 2) = 8;
    EXPECT_TRUE(testing::throwsError([&] { m.validate(); }, {"/object/faces"}));
  }
  {
    TaskMapData m = sampleMap(4);
    m.sampling.trials = 99;
    EXPECT_TRUE(testing::throwsError([&] { m.validate(); }, {"/sampling"}));
  }
  {
    TaskMapData m = sampleMap(4);
    m.clustering->clusters[0].size += 1;
    EXPECT_TRUE(testing::throwsError([&] { m.validate(); }, {"/clusters/size"}));
  }
  {
    TaskMapData m = sampleMap(4);
    m.grasps.joints.resize(4, 3);
    m.grasps.joints.setZero();
    EXPECT_TRUE(testing::throwsError([&] { m.validate(); }, {"/grasps/joints"}));
  }
  EXPECT_NO_THROW(sampleMap(6).validate());
}

// ---- the seal (mapstore/SCHEMA.md, "Seal"), checked against an independent oracle ----

TEST(MapSealTest, FileStartsWithTheDocumentedSeal) {
  const std::string path = tempPath("sealed.h5");
  writeMap(path, sampleMap(6));
  const std::string bytes = test::fileBytes(path);
  ASSERT_GT(bytes.size(), 512u);
  EXPECT_TRUE(bytes.substr(0, 512) == test::sealBlock(bytes.substr(512)));
  EXPECT_EQ(bytes.compare(512, 8, "\x89HDF\r\n\x1a\n"), 0);
}

TEST(MapSealTest, SameMapGivesSameBytes) {
  const std::string a = tempPath("same_a.h5"), b = tempPath("same_b.h5");
  const TaskMapData m = sampleMap(40);
  writeMap(a, m);
  writeMap(b, m);
  EXPECT_TRUE(test::fileBytes(a) == test::fileBytes(b));
}

TEST(MapSealTest, EveryFlippedByteIsRefusedBeforeHdf5) {
  const std::string path = tempPath("flip_src.h5");
  writeMap(path, sampleMap(8));
  const std::string bytes = test::fileBytes(path);
  const std::string flipped = tempPath("flip.h5");
  for (std::size_t at = 0; at < bytes.size(); at += 97) {
    std::string b = bytes;
    b[at] = static_cast<char>(b[at] ^ 0x10);
    test::writeBytes(flipped, b);
    SCOPED_TRACE(at);
    expectReadError(flipped, {at < 512 ? "seal" : "does not match its seal"});
  }
}

TEST(MapSealTest, EditByAnotherToolIsRefusedUntilResealed) {
  const std::string path = tempPath("edited.h5");
  writeMap(path, sampleMap(5));
  {
    hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);  // no re-seal: another tool
    ASSERT_GE(f, 0);
    hid_t a = H5Aopen_by_name(f, "/", "generator", H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(a, 0);
    hid_t type = H5Aget_type(a);
    std::string name = "other tool";
    name.resize(H5Tget_size(type), '\0');
    EXPECT_GE(H5Awrite(a, type, name.data()), 0);
    H5Tclose(type);
    H5Aclose(a);
    H5Fclose(f);
  }
  expectReadError(path, {"changed by another tool", "taskmap seal FILE"});
  sealMap(path);
  EXPECT_EQ(readMap(path).generator, "other tool");
}

TEST(MapSealTest, UnsealedMapIsRefusedAndSealingPrependsTheBlock) {
  const std::string sealed = tempPath("to_strip.h5");
  const TaskMapData m = sampleMap(7);
  writeMap(sealed, m);
  // Without its user block the HDF5 content is an unsealed map (as other tools write them).
  const std::string path = tempPath("unsealed.h5");
  test::writeBytes(path, test::fileBytes(sealed).substr(512));
  expectReadError(path, {"no taskmap seal"});
  sealMap(path);
  EXPECT_TRUE(test::fileBytes(path) == test::fileBytes(sealed));
  expectSameMap(m, readMap(path));
}

TEST(MapSealTest, SealingRefusesAnInvalidMapAndLeavesItUnchanged) {
  const std::string path = tempPath("invalid_unsealed.h5");
  writeMap(path, sampleMap(5));
  editDataset<double>(path, "/grasps/pose", H5T_NATIVE_DOUBLE, 35,
                      [](std::vector<double>& v) { v[7 * 2 + 3] = 5.0; });
  const std::string stripped = test::fileBytes(path).substr(512);
  test::writeBytes(path, stripped);
  EXPECT_TRUE(testing::throwsError([&] { sealMap(path); }, {path, "/grasps/pose"}));
  EXPECT_TRUE(test::fileBytes(path) == stripped);
}

TEST(MapSealTest, TruncatedAndExtendedFilesNameTheLengths) {
  const std::string path = tempPath("length.h5");
  writeMap(path, sampleMap(5));
  const std::string bytes = test::fileBytes(path);
  const std::string cut = tempPath("length_cut.h5");
  test::writeBytes(cut, bytes.substr(0, bytes.size() - 10));
  expectReadError(cut, {"truncated", std::to_string(bytes.size() - 522), "declares"});
  test::writeBytes(cut, bytes + "x");
  expectReadError(cut, {"extended", "declares " + std::to_string(bytes.size() - 512)});
  test::writeBytes(cut, bytes.substr(0, 100));
  expectReadError(cut, {"truncated"});
}

TEST(MapSealTest, NewerSealVersionAsksToUpgrade) {
  const std::string path = tempPath("newer_seal.h5");
  writeMap(path, sampleMap(3));
  std::string bytes = test::fileBytes(path);
  bytes[13] = '7';  // "TASKMAP-SEAL 7"
  test::writeBytes(path, bytes);
  expectReadError(path, {"newer taskmap (seal version 7)"});
}

TEST(MapSealTest, CreationTimeFollowsSourceDateEpoch) {
  ASSERT_EQ(::unsetenv("SOURCE_DATE_EPOCH"), 0);
  EXPECT_EQ(mapCreationTime(), "");
  EXPECT_EQ(mapCreationTime(true).size(), 20u);
  ASSERT_EQ(::setenv("SOURCE_DATE_EPOCH", "1700000000", 1), 0);
  EXPECT_EQ(mapCreationTime(), "2023-11-14T22:13:20Z");
  EXPECT_EQ(mapCreationTime(true), "2023-11-14T22:13:20Z");
  ASSERT_EQ(::setenv("SOURCE_DATE_EPOCH", "yesterday", 1), 0);
  EXPECT_TRUE(testing::throwsError([] { mapCreationTime(); }, {"SOURCE_DATE_EPOCH='yesterday'"}));
  ASSERT_EQ(::unsetenv("SOURCE_DATE_EPOCH"), 0);
}

}  // namespace
}  // namespace taskmap
