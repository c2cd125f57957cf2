#include "taskmap/mapstore/acronym.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "error_matchers.hpp"
#include "synthetic_map.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {

using taskmap::testing::errorMessage;
namespace {

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "/acronym_test_" + std::to_string(::getpid()) + "_" + name;
}

TEST(AcronymTest, ExportThenImportKeepsPosesFlagsAndEpsilon) {
  const TaskMapData map = testing::clusteredBasketMap();
  const std::string path = tempPath("roundtrip.h5");
  writeAcronym(path, map);
  const AcronymGrasps a = readAcronym(path);
  ASSERT_EQ(a.transforms.size(), map.grasps.size());
  for (std::size_t i = 0; i < a.transforms.size(); ++i) {
    // ACRONYM stores the gripper base: palm pose times the inverse base-to-palm transform.
    const Eigen::Matrix4d base =
        (map.grasps.poseAt(i).toIsometry() * acronymFrankaBaseToPalm().inverse()).matrix();
    EXPECT_LT((a.transforms[i] - base).cwiseAbs().maxCoeff(), 1e-15);
  }
  const TaskMapData back = acronymToMap(a, map.object);
  ASSERT_EQ(back.grasps.size(), map.grasps.size());
  for (std::size_t i = 0; i < map.grasps.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    // Same position; same quaternion up to sign (q and -q are one rotation; qw ~ 0 here).
    const Eigen::Matrix<double, 7, 1> a7 = back.grasps.pose.row(row).transpose();
    const Eigen::Matrix<double, 7, 1> b7 = map.grasps.pose.row(row).transpose();
    EXPECT_LT((a7.head<3>() - b7.head<3>()).cwiseAbs().maxCoeff(), 1e-12) << "grasp " << i;
    const double dq = std::min((a7.tail<4>() - b7.tail<4>()).cwiseAbs().maxCoeff(),
                               (a7.tail<4>() + b7.tail<4>()).cwiseAbs().maxCoeff());
    EXPECT_LT(dq, 1e-12) << "grasp " << i;
    EXPECT_EQ(back.grasps.force_closure[i], map.grasps.force_closure[i]);
    EXPECT_EQ(back.grasps.epsilon[i], map.grasps.epsilon[i]);
  }
  EXPECT_FALSE(back.grasps.contacts_available);
  EXPECT_EQ(back.grasps.contact_points.rows(), 0);
  EXPECT_EQ(back.hand.name, "three_finger");
  EXPECT_EQ(back.sampling.trials, map.grasps.size());
  EXPECT_EQ(back.sampling.outcomes.at("force_closure"), 99u);
  EXPECT_EQ(back.sampling.outcomes.at("not_force_closure"), 3u);
  EXPECT_DOUBLE_EQ(back.quality.friction, map.quality.friction);
  // Clustered on import: every grasp labelled, sizes add up.
  ASSERT_TRUE(back.clustering.has_value());
  ASSERT_EQ(back.clustering->labels.size(), map.grasps.size());
  int clustered = 0;
  for (const auto& c : back.clustering->clusters) clustered += c.size;
  const auto outliers =
      std::count(back.clustering->labels.begin(), back.clustering->labels.end(), -1);
  EXPECT_EQ(clustered + outliers, static_cast<long>(map.grasps.size()));
  EXPECT_GE(back.clustering->clusters.size(), 2u);
  back.validate();
  std::filesystem::remove(path);
}

TEST(AcronymTest, SameExportGivesSameBytesAcrossSeconds) {
  // HDF5 object times have one-second resolution: the two writes straddle a second.
  const TaskMapData map = testing::clusteredBasketMap();
  const std::string a = tempPath("same_a.h5"), b = tempPath("same_b.h5");
  writeAcronym(a, map);
  ::usleep(1100 * 1000);
  writeAcronym(b, map);
  auto bytes = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  EXPECT_TRUE(bytes(a) == bytes(b));
  std::remove(a.c_str());
  std::remove(b.c_str());
}

TEST(AcronymTest, ObjectAttributesFollowTheMap) {
  TaskMapData map = testing::clusteredBasketMap(10, 2);
  map.quality.friction = 0.7;
  const std::string path = tempPath("attrs.h5");
  AcronymExportOptions options;
  options.density = 250.0;
  options.object_file = "meshes/Basket/basket.obj";
  writeAcronym(path, map, options);
  const AcronymGrasps a = readAcronym(path);
  EXPECT_EQ(a.object_file, "meshes/Basket/basket.obj");
  EXPECT_EQ(a.gripper_type, "three_finger");
  EXPECT_DOUBLE_EQ(a.object_scale, 1.0);
  ASSERT_TRUE(a.object_density && a.object_mass && a.object_friction && a.object_volume &&
              a.object_com);
  EXPECT_DOUBLE_EQ(*a.object_density, 250.0);
  EXPECT_DOUBLE_EQ(*a.object_mass, 250.0 * map.object.volume);
  EXPECT_DOUBLE_EQ(*a.object_friction, 0.7);
  EXPECT_DOUBLE_EQ(*a.object_volume, map.object.volume);
  EXPECT_EQ(*a.object_com, map.object.center_of_mass);
  EXPECT_TRUE(a.gripper_configuration.empty());
  ASSERT_TRUE(a.epsilon.has_value());
  // Default object file is "<name>.obj".
  writeAcronym(path, map);
  EXPECT_EQ(readAcronym(path).object_file, "basket.obj");
  std::filesystem::remove(path);
}

TEST(AcronymTest, MeshInertiaOfABoxMatchesTheClosedForm) {
  // Box 0.3 x 0.2 x 0.1 centred at (1, 2, 3): I_xx = m (b^2 + c^2) / 12 ...
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  const Eigen::Vector3d c(1, 2, 3), h(0.15, 0.1, 0.05);
  testing::appendBox(v, f, c - h, c + h);
  RowMatrixXd verts(8, 3);
  Eigen::Matrix<std::int64_t, Eigen::Dynamic, 3, Eigen::RowMajor> faces(12, 3);
  for (int i = 0; i < 8; ++i) verts.row(i) = v[static_cast<std::size_t>(i)];
  for (int i = 0; i < 12; ++i) faces.row(i) = f[static_cast<std::size_t>(i)].cast<std::int64_t>();
  const double density = 700, m = density * 0.3 * 0.2 * 0.1;
  const Eigen::Matrix3d inertia = meshInertia(verts, faces, c, density);
  Eigen::Matrix3d expected = Eigen::Matrix3d::Zero();
  expected(0, 0) = m * (0.2 * 0.2 + 0.1 * 0.1) / 12;
  expected(1, 1) = m * (0.3 * 0.3 + 0.1 * 0.1) / 12;
  expected(2, 2) = m * (0.3 * 0.3 + 0.2 * 0.2) / 12;
  EXPECT_LT((inertia - expected).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(AcronymTest, SuccessfulOnlyKeepsTheSuccesses) {
  const TaskMapData map = testing::clusteredBasketMap(10, 4);
  const std::string path = tempPath("success.h5");
  writeAcronym(path, map);
  AcronymImportOptions options;
  options.successful_only = true;
  const TaskMapData back = acronymToMap(readAcronym(path), map.object, options);
  std::size_t successes = 0;
  for (auto fc : map.grasps.force_closure) successes += fc;
  EXPECT_EQ(back.grasps.size(), successes);
  for (auto fc : back.grasps.force_closure) EXPECT_EQ(fc, 1);
  EXPECT_EQ(back.sampling.trials, map.grasps.size());
  std::filesystem::remove(path);
}

// A file as h5py writes the original dataset can differ from ours: fixed-length strings,
// float32 transforms, integer flags of another width, no taskmap epsilon.
TEST(AcronymTest, ReadsOtherNumericAndStringTypes) {
  const std::string path = tempPath("foreign.h5");
  {
    hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    const hsize_t tdims[3] = {2, 4, 4};
    float t[32] = {};
    for (int g = 0; g < 2; ++g)
      for (int k = 0; k < 4; ++k) t[g * 16 + k * 5] = 1.0f;
    t[3] = 0.5f;         // grasp 0 at x = 0.5
    t[16 + 7] = -0.25f;  // grasp 1 at y = -0.25
    hid_t sp = H5Screate_simple(3, tdims, nullptr);
    hid_t ds =
        H5Dcreate2(file, "grasps/transforms", H5T_IEEE_F32LE, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, t);
    H5Dclose(ds);
    H5Sclose(sp);
    const hsize_t sdims[1] = {2};
    const std::uint8_t s[2] = {0, 1};
    sp = H5Screate_simple(1, sdims, nullptr);
    ds = H5Dcreate2(file, "grasps/qualities/flex/object_in_gripper", H5T_STD_U8LE, sp, lcpl,
                    H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, H5T_NATIVE_UINT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, s);
    H5Dclose(ds);
    H5Sclose(sp);
    const char name[] = "meshes/Mug/10f6.obj";
    hid_t st = H5Tcopy(H5T_C_S1);
    H5Tset_size(st, sizeof(name) - 1);
    sp = H5Screate(H5S_SCALAR);
    ds = H5Dcreate2(file, "object/file", st, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, st, H5S_ALL, H5S_ALL, H5P_DEFAULT, name);
    H5Dclose(ds);
    const float scale = 0.5f;
    ds = H5Dcreate2(file, "object/scale", H5T_IEEE_F32LE, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, &scale);
    H5Dclose(ds);
    H5Sclose(sp);
    H5Tclose(st);
    H5Pclose(lcpl);
    H5Fclose(file);
  }
  const AcronymGrasps a = readAcronym(path);
  ASSERT_EQ(a.transforms.size(), 2u);
  EXPECT_EQ(a.transforms[0](0, 3), 0.5);
  EXPECT_EQ(a.transforms[1](1, 3), -0.25);
  EXPECT_EQ(a.success, (std::vector<std::uint8_t>{0, 1}));
  EXPECT_EQ(a.object_file, "meshes/Mug/10f6.obj");
  EXPECT_EQ(a.object_scale, 0.5);
  EXPECT_FALSE(a.epsilon.has_value());
  EXPECT_FALSE(a.object_mass.has_value());
  const TaskMapData m = acronymToMap(a, testing::basketObject());
  // Without a taskmap epsilon, epsilon is the success flag.
  EXPECT_EQ(m.grasps.epsilon, (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(m.hand.name, "acronym_gripper");
  std::filesystem::remove(path);
}

/// An HDF5 file at `path` with 2 identity transforms and flags, then `extra` run on it.
template <typename Extra>
void writeGraspFile(const std::string& path, Extra extra) {
  hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  double t[32] = {};
  for (int g = 0; g < 2; ++g)
    for (int k = 0; k < 4; ++k) t[g * 16 + k * 5] = 1.0;
  const hsize_t tdims[3] = {2, 4, 4};
  hid_t sp = H5Screate_simple(3, tdims, nullptr);
  hid_t ds =
      H5Dcreate2(file, "grasps/transforms", H5T_IEEE_F64LE, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, t);
  H5Dclose(ds);
  H5Sclose(sp);
  const hsize_t sdims[1] = {2};
  const std::int64_t s[2] = {1, 0};
  sp = H5Screate_simple(1, sdims, nullptr);
  ds = H5Dcreate2(file, "grasps/qualities/flex/object_in_gripper", H5T_STD_I64LE, sp, lcpl,
                  H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, s);
  H5Dclose(ds);
  H5Sclose(sp);
  extra(file, lcpl);
  H5Pclose(lcpl);
  H5Fclose(file);
}

/// A fixed-length string dataset of `count` elements of `width` bytes, NUL-padded (what h5py
/// writes for numpy bytes), holding `text` in every element.
void writeFixedStrings(hid_t file, hid_t lcpl, const char* name, const std::string& text,
                       std::size_t width, hsize_t count) {
  hid_t st = H5Tcopy(H5T_C_S1);
  H5Tset_size(st, width);
  H5Tset_strpad(st, H5T_STR_NULLPAD);
  hid_t sp = count == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &count, nullptr);
  std::string data;
  for (hsize_t i = 0; i < std::max<hsize_t>(count, 1); ++i) {
    std::string one = text;
    one.resize(width, '\0');
    data += one;
  }
  hid_t ds = H5Dcreate2(file, name, st, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(ds, st, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Dclose(ds);
  H5Sclose(sp);
  H5Tclose(st);
}

// h5py writes numpy bytes as fixed-length NUL-padded strings exactly as wide as the text: the
// last character is part of the string (the reader before issue 29 dropped it).
TEST(AcronymTest, ReadsFullWidthNullPaddedStringsWhole) {
  const std::string path = tempPath("nullpad.h5");
  writeGraspFile(path, [](hid_t file, hid_t lcpl) {
    writeFixedStrings(file, lcpl, "object/file", "meshes/Mug/abc.obj", 18, 0);
    writeFixedStrings(file, lcpl, "gripper/type", "franka", 6, 0);
  });
  const AcronymGrasps a = readAcronym(path);
  EXPECT_EQ(a.object_file, "meshes/Mug/abc.obj");
  EXPECT_EQ(a.gripper_type, "franka");
  std::filesystem::remove(path);
}

TEST(AcronymTest, DatasetsOfTheWrongKindNameTheFileAndTheDataset) {
  const std::string path = tempPath("kinds.h5");
  const auto expect = [&](const std::string& fragment) {
    const std::string m = errorMessage([&] { readAcronym(path); });
    EXPECT_NE(m.find("'" + path + "': dataset " + fragment + "; is this an ACRONYM grasp file?"),
              std::string::npos)
        << m;
  };
  writeGraspFile(path, [](hid_t file, hid_t lcpl) {
    writeFixedStrings(file, lcpl, "object/file", "a.obj", 8, 2);
  });
  expect("object/file should hold one string");
  writeGraspFile(path, [](hid_t file, hid_t lcpl) {
    H5Gclose(H5Gcreate2(file, "object/scale", lcpl, H5P_DEFAULT, H5P_DEFAULT));
  });
  expect("object/scale cannot be opened (is it a group?)");
  writeGraspFile(path, [](hid_t file, hid_t lcpl) {
    writeFixedStrings(file, lcpl, "object/mass", "heavy", 5, 0);
  });
  expect("object/mass is not numeric");
  writeGraspFile(path, [](hid_t file, hid_t lcpl) {
    const double two[2] = {1.0, 2.0};
    const hsize_t n = 2;
    hid_t sp = H5Screate_simple(1, &n, nullptr);
    hid_t ds = H5Dcreate2(file, "object/file", H5T_IEEE_F64LE, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, two);
    H5Dclose(ds);
    ds = H5Dcreate2(file, "object/scale", H5T_IEEE_F64LE, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, two);
    H5Dclose(ds);
    H5Sclose(sp);
  });
  expect("object/file is not a string");
  std::filesystem::remove(path);
}

TEST(AcronymTest, BadInputGivesClearErrors) {
  EXPECT_NE(errorMessage([] { readAcronym("/nonexistent/grasps.h5"); }).find("does not exist"),
            std::string::npos);
  const std::string text = tempPath("text.h5");
  std::ofstream(text) << "not hdf5\n";
  EXPECT_NE(errorMessage([&] { readAcronym(text); }).find("is not an HDF5 file"),
            std::string::npos);
  std::filesystem::remove(text);

  // An HDF5 file without grasps: our own task-map-like file with only an object dataset.
  const std::string empty = tempPath("empty.h5");
  {
    hid_t file = H5Fcreate(empty.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    H5Gclose(H5Gcreate2(file, "object", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    H5Fclose(file);
  }
  const std::string missing = errorMessage([&] { readAcronym(empty); });
  EXPECT_NE(missing.find("grasps/transforms is missing"), std::string::npos) << missing;
  EXPECT_NE(missing.find(empty), std::string::npos) << missing;
  std::filesystem::remove(empty);

  // A transform that is not rigid.
  AcronymGrasps a;
  a.path = "x.h5";
  a.transforms = {Eigen::Matrix4d::Identity(), Eigen::Matrix4d::Identity()};
  a.transforms[1](0, 0) = 2.0;
  a.success = {1, 1};
  EXPECT_NE(errorMessage([&] {
              acronymToMap(a, testing::basketObject());
            }).find("grasps/transforms[1] is not a rigid transform"),
            std::string::npos);
  a.success = {0, 0};
  AcronymImportOptions only;
  only.successful_only = true;
  EXPECT_NE(errorMessage([&] {
              acronymToMap(a, testing::basketObject(), only);
            }).find("no successful grasp"),
            std::string::npos);
  a.success = {1};
  EXPECT_NE(
      errorMessage([&] { acronymToMap(a, testing::basketObject()); }).find("2 transforms but 1"),
      std::string::npos);
  // Unwritable target.
  EXPECT_NE(errorMessage([] {
              writeAcronym("/nonexistent/dir/x.h5", testing::clusteredBasketMap(5, 0));
            }).find("cannot write '/nonexistent/dir/x.h5'"),
            std::string::npos);
  AcronymExportOptions bad;
  bad.density = -1;
  EXPECT_NE(errorMessage([&] {
              writeAcronym(tempPath("bad.h5"), testing::clusteredBasketMap(5, 0), bad);
            }).find("density"),
            std::string::npos);
}

}  // namespace
}  // namespace taskmap
