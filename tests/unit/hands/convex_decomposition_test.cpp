// Non-convex hand link meshes through the exact convex decomposition (CGAL Nef polyhedra):
// U- and L-shaped voxel blocks (tests/data/hands/u_block.obj, l_block.obj, 1 cm voxels) checked
// voxel by voxel against a brute-force point-in-hull oracle; the sidecar "collision" options;
// the real Franka hand (nearly convex: kept as its hull); an open real scan decomposed through
// its alpha wrap.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "taskmap/core/error.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

std::string data(const std::string& name) {
  return std::string(TEST_DATA_DIR) + "/hands/" + name;
}

/// Brute-force hull facets: every plane through three vertices with all vertices on one side,
/// as (outward unit normal, offset): the hull is {p : n.p <= offset for every plane}.
std::vector<std::pair<Eigen::Vector3d, double>> facetsOf(const std::vector<Eigen::Vector3d>& v) {
  std::vector<std::pair<Eigen::Vector3d, double>> out;
  const std::size_t n = v.size();
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b)
      for (std::size_t c = b + 1; c < n; ++c) {
        Eigen::Vector3d nrm = (v[b] - v[a]).cross(v[c] - v[a]);
        if (nrm.norm() < 1e-12) continue;
        nrm.normalize();
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (const auto& q : v) {
          lo = std::min(lo, nrm.dot(q - v[a]));
          hi = std::max(hi, nrm.dot(q - v[a]));
        }
        if (hi <= 1e-12) out.emplace_back(nrm, nrm.dot(v[a]));
        if (lo >= -1e-12) out.emplace_back(-nrm, -nrm.dot(v[a]));
      }
  return out;
}

/// p lies in the hull of `v` (closer than `tol` metres outside counts as inside).
bool insideHull(const std::vector<Eigen::Vector3d>& v, const Eigen::Vector3d& p, double tol) {
  for (const auto& [nrm, off] : facetsOf(v))
    if (nrm.dot(p) > off + tol) return false;
  return true;
}

/// Volume of the hull of `v` by counting points of a 40^3 grid over its bounding box.
double hullVolumeOf(const std::vector<Eigen::Vector3d>& v) {
  const auto facets = facetsOf(v);
  Eigen::AlignedBox3d box;
  for (const auto& q : v) box.extend(q);
  const int n = 40;
  const Eigen::Vector3d d = box.sizes() / n;
  int in = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d p =
            box.min() + d.cwiseProduct(Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5));
        in += std::all_of(facets.begin(), facets.end(),
                          [&](const auto& f) { return f.first.dot(p) <= f.second; });
      }
  return in * d.prod();
}

const HandLink& link(const HandModel& h, const std::string& name) {
  return h.links()[static_cast<std::size_t>(h.linkIndex(name))];
}

const CollisionMeshInfo& infoOf(const HandModel& h, const std::string& name) {
  for (const auto& m : h.collisionMeshes())
    if (m.link == name) return m;
  throw Error("no collision mesh on " + name);
}

/// Every voxel centre of the block lies in exactly one piece; every voxel centre of its
/// bounding box outside the block lies in none (voxels of 1 cm; the pieces are in the link
/// frame since the collision origin is the identity).
void expectPiecesTileTheBlock(const HandLink& l, int nx, int ny, int nz,
                              bool (*solid)(int, int, int)) {
  for (int x = 0; x < nx; ++x)
    for (int y = 0; y < ny; ++y)
      for (int z = 0; z < nz; ++z) {
        const Eigen::Vector3d p = 0.01 * Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5);
        int count = 0;
        for (const auto& s : l.shapes) count += insideHull(s.points, p, 1e-9);
        EXPECT_EQ(count, solid(x, y, z) ? 1 : 0)
            << l.name << " voxel " << x << " " << y << " " << z;
      }
}

bool uSolid(int x, int, int z) {
  return !(x >= 1 && x < 4 && z >= 1);
}
bool lSolid(int x, int, int z) {
  return !(x >= 1 && z >= 1);
}

TEST(ConvexDecomposition, UAndLBlocksSplitIntoPiecesOfTheirVolume) {
  const HandModel h = HandModel::load(data("decomp_finger.urdf"));
  const HandLink& u = link(h, "finger_u");
  const HandLink& l = link(h, "finger_l");
  EXPECT_GE(u.shapes.size(), 3u);  // a U needs at least its two arms and its base
  EXPECT_GE(l.shapes.size(), 2u);
  expectPiecesTileTheBlock(u, 5, 2, 4, uSolid);
  expectPiecesTileTheBlock(l, 4, 2, 4, lSolid);
  const CollisionMeshInfo& iu = infoOf(h, "finger_u");
  EXPECT_TRUE(iu.decomposed);
  EXPECT_FALSE(iu.warning);
  EXPECT_EQ(iu.pieces, static_cast<int>(u.shapes.size()));
  EXPECT_NEAR(iu.mesh_volume, 22e-6, 1e-12);  // oracle: 22 voxels of 1 cm^3
  EXPECT_NEAR(iu.hull_volume, 40e-6, 1e-12);
  EXPECT_NEAR(iu.pieces_volume, 22e-6, 1e-12);
  double sum = 0.0;
  for (const auto& s : u.shapes) sum += hullVolumeOf(s.points);
  EXPECT_NEAR(sum, 22e-6, 0.3e-6);  // independent of the reported volumes
  const CollisionMeshInfo& il = infoOf(h, "finger_l");
  EXPECT_NEAR(il.mesh_volume, 14e-6, 1e-12);
  EXPECT_NEAR(il.hull_volume, 23e-6, 1e-12);
  EXPECT_NEAR(il.pieces_volume, 14e-6, 1e-12);
  EXPECT_EQ(il.faces, 92);
}

TEST(ConvexDecomposition, PointInTheNotchIsOutsideEveryPiece) {
  const HandModel h = HandModel::load(data("decomp_finger.urdf"));
  const Eigen::Vector3d notch(0.025, 0.01, 0.025);  // centre of the U's notch
  for (const auto& s : link(h, "finger_u").shapes) EXPECT_FALSE(insideHull(s.points, notch, 0.0));
  const Eigen::Vector3d corner(0.025, 0.01, 0.025);  // inside the L's missing corner
  for (const auto& s : link(h, "finger_l").shapes) EXPECT_FALSE(insideHull(s.points, corner, 0.0));
}

TEST(ConvexDecomposition, OffKeepsTheHullAndMaxPiecesMerges) {
  const HandModel off = HandModel::load(data("decomp_finger.urdf"), data("decomp_off.hand.json"));
  ASSERT_EQ(link(off, "finger_u").shapes.size(), 1u);
  EXPECT_TRUE(insideHull(link(off, "finger_u").shapes[0].points,
                         Eigen::Vector3d(0.025, 0.01, 0.025), 0.0));  // the hull fills the notch
  EXPECT_EQ(infoOf(off, "finger_u").note, "decomposition off");
  EXPECT_NEAR(infoOf(off, "finger_u").pieces_volume, 40e-6, 1e-12);

  const HandModel two = HandModel::load(data("decomp_finger.urdf"), data("decomp_two.hand.json"));
  const HandLink& u = link(two, "finger_u");
  ASSERT_EQ(u.shapes.size(), 2u);
  // Merging adds part of the notch but never all of it; the two pieces still cover the solid.
  const CollisionMeshInfo& iu = infoOf(two, "finger_u");
  EXPECT_GT(iu.pieces_volume, 22e-6);
  EXPECT_LT(iu.pieces_volume, 40e-6);
  for (int x = 0; x < 5; ++x)
    for (int z = 0; z < 4; ++z) {
      if (!uSolid(x, 0, z)) continue;
      const Eigen::Vector3d p = 0.01 * Eigen::Vector3d(x + 0.5, 0.5, z + 0.5);
      EXPECT_TRUE(insideHull(u.shapes[0].points, p, 1e-9) ||
                  insideHull(u.shapes[1].points, p, 1e-9));
    }
  ASSERT_EQ(link(two, "finger_l").shapes.size(), 2u);  // already 2: unchanged
  EXPECT_NEAR(infoOf(two, "finger_l").pieces_volume, 14e-6, 1e-12);
}

TEST(ConvexDecomposition, RealFrankaPalmIsNearlyConvex) {
  const HandModel h =
      HandModel::load(std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf");
  ASSERT_EQ(h.collisionMeshes().size(), 1u);
  const CollisionMeshInfo& m = h.collisionMeshes()[0];
  EXPECT_EQ(m.link, "panda_hand");
  EXPECT_EQ(m.pieces, 1);
  EXPECT_FALSE(m.decomposed);
  EXPECT_EQ(m.note, "nearly convex");
  EXPECT_EQ(m.faces, 200);
  EXPECT_GT(m.mesh_volume, 0.99 * m.hull_volume);
}

/// A hand folder whose link "finger" is the real YCB banana scan with faces [from, from + n)
/// of the file removed (an open scan), and `collision` sidecar options.
std::string openBananaHand(const std::string& tag, int from, int n, const std::string& collision) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("decomp_" + tag);
  fs::create_directories(dir);
  std::ifstream in(std::string(TEST_DATA_DIR) + "/real/objects/ycb_011_banana.obj");
  std::ofstream obj(dir / "banana.obj");
  int face = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("f ", 0) == 0 && face++ >= from && face <= from + n) continue;
    obj << line << "\n";
  }
  std::ofstream(dir / "hand.urdf")
      << "<robot name=\"banana_link\"><link name=\"base\"><collision><geometry><box size=\"0.2 "
         "0.2 0.02\"/></geometry></collision></link><link name=\"finger\"><collision><geometry>"
         "<mesh filename=\"banana.obj\"/></geometry></collision></link><joint name=\"j\" "
         "type=\"prismatic\"><parent link=\"base\"/><child link=\"finger\"/><origin xyz=\"0 0 "
         "0.1\"/><axis xyz=\"1 0 0\"/><limit lower=\"0\" upper=\"0.05\" effort=\"1\" "
         "velocity=\"1\"/></joint></robot>";
  std::ofstream(dir / "hand.hand.json")
      << "{\"palm_link\": \"base\", \"approach_axis\": [0, 0, 1], \"closing\": [{\"joint\": "
         "\"j\", \"toward\": \"upper\"}], \"squeeze\": 0.0005, \"fingers\": {\"a\": "
         "[\"finger\"]}, \"collision\": "
      << collision << "}";
  return (dir / "hand.urdf").string();
}

TEST(ConvexDecomposition, OpenRealScanIsDecomposedThroughItsAlphaWrap) {
  // The closed banana scan encloses 171.5 cm^3 (mesh-info), its hull 265.4 cm^3.
  const HandModel h = HandModel::load(openBananaHand("wrap", 1000, 12, "{}"));
  ASSERT_EQ(h.collisionMeshes().size(), 1u);
  const CollisionMeshInfo& m = h.collisionMeshes()[0];
  EXPECT_TRUE(m.decomposed);
  EXPECT_TRUE(m.wrapped);
  EXPECT_FALSE(m.warning);
  EXPECT_NE(m.note.find("is not closed (it has border edges); decomposed its alpha wrap"),
            std::string::npos)
      << m.note;
  EXPECT_EQ(m.pieces, 16);
  EXPECT_NEAR(m.hull_volume, 265.4e-6, 0.1e-6);
  EXPECT_GT(m.pieces_volume, 171.5e-6);             // the wrap lies outside the scan
  EXPECT_LT(m.pieces_volume, 0.8 * m.hull_volume);  // far tighter than the hull
  // Without wrapping, the open scan keeps its hull, with a warning.
  const HandModel off = HandModel::load(openBananaHand("nowrap", 1000, 12, "{\"wrap\": false}"));
  EXPECT_TRUE(off.collisionMeshes()[0].warning);
  EXPECT_EQ(off.collisionMeshes()[0].pieces, 1);
  fs::remove_all(fs::path(::testing::TempDir()) / "decomp_wrap");
  fs::remove_all(fs::path(::testing::TempDir()) / "decomp_nowrap");
}

TEST(ConvexDecomposition, BadOptionsAreRefusedWithTheKey) {
  const std::string dir = ::testing::TempDir();
  const auto expectError = [&](const std::string& collision, const std::string& needle) {
    const std::string path = dir + "/decomp_bad.hand.json";
    FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fprintf(f,
                 "{\"palm_link\": \"base\", \"approach_axis\": [0, 0, 1], \"closing\": "
                 "[{\"joint\": \"ju\", \"toward\": \"upper\"}], \"squeeze\": 0.0005, "
                 "\"fingers\": {\"u\": [\"finger_u\"]}, \"collision\": %s}",
                 collision.c_str());
    std::fclose(f);
    try {
      HandModel::load(data("decomp_finger.urdf"), path);
      ADD_FAILURE() << collision;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  expectError("{\"max_pieces\": 0}", "collision.max_pieces must be an integer in [1, 64]");
  expectError("{\"decompose\": 1}", "collision.decompose must be true or false");
  expectError("{\"hull\": true}", "collision: unknown key 'hull'");
  expectError("{\"convex_tolerance\": 1}", "collision.convex_tolerance must be a number in [0, 1)");
  expectError("[]", "collision must be an object");
  expectError("{\"wrap\": \"yes\"}", "collision.wrap must be true or false");
  fs::remove(dir + "/decomp_bad.hand.json");
}

}  // namespace
}  // namespace taskmap
