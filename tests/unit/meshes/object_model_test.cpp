// ObjectModel: mass properties against analytic values, inside test against a brute-force
// winding-number oracle, uniformity and determinism of sampling, surface samples.
#include "taskmap/meshes/object_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Geometry>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

std::string object(const std::string& name) {
  return std::string(TASKMAP_OBJECTS_DIR) + "/" + name + ".obj";
}

/// Independent oracle: generalized winding number summed over every triangle (Van Oosterom and
/// Strackee solid angles). About 1 inside, 0 outside a closed outward mesh.
double windingNumber(const TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double total = 0;
  for (const auto& f : mesh.faces) {
    const Eigen::Vector3d a = mesh.vertices[f[0]] - p, b = mesh.vertices[f[1]] - p,
                          c = mesh.vertices[f[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    total += 2 * std::atan2(a.dot(b.cross(c)),
                            la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
  }
  return total / (4 * M_PI);
}

struct Analytic {
  std::string name;
  double volume;
  Eigen::Vector3d com;
};

TEST(ObjectModelTest, VolumeAndCentreOfMassMatchAnalyticSolids) {
  // Box: exact. Cylinder: a 64-gon has area n/(2 pi) sin(2 pi/n) = 0.99839 of the circle, so
  // the prism is 0.16 % small. Sphere: vertices on the sphere on a 64 x 48 grid; the inscribed
  // polyhedron loses about a^2/6 + b^2/6 (a = 2 pi/64, b = pi/48), 0.16 % + 0.07 %, plus the
  // polar fans: measured 0.25 %. All below the 0.5 % bound.
  const double kPi = M_PI;
  const std::vector<Analytic> cases = {
      {"box", 0.06 * 0.08 * 0.12, {0, 0, 0.06}},
      {"cylinder", kPi * 0.035 * 0.035 * 0.20, {0, 0, 0.10}},
      {"sphere", 4.0 / 3.0 * kPi * std::pow(0.04, 3), {0, 0, 0}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const ObjectModel model = ObjectModel::load(object(c.name));
    const MassProperties& m = model.massProperties();
    EXPECT_NEAR(m.volume, c.volume, 0.005 * c.volume);
    const double size = (m.bounds_max - m.bounds_min).maxCoeff();
    EXPECT_LT((m.center_of_mass - c.com).norm(), 0.005 * size);
  }
}

TEST(ObjectModelTest, BoxInertiaAndTorqueScaleAreExact) {
  const ObjectModel model = ObjectModel::load(object("box"));
  const MassProperties& m = model.massProperties();
  const double a = 0.06, b = 0.08, c = 0.12, mass = a * b * c;
  Eigen::Matrix3d expected =
      Eigen::Vector3d(mass / 12 * (b * b + c * c), mass / 12 * (a * a + c * c),
                      mass / 12 * (a * a + b * b))
          .asDiagonal();
  EXPECT_LT((m.inertia - expected).norm(), 1e-5 * expected.norm());
  EXPECT_NEAR(m.torque_scale, 0.5 * std::sqrt(a * a + b * b + c * c), 1e-7);
  EXPECT_NEAR(m.bounds_min.x(), -0.03, 1e-7);
  EXPECT_NEAR(m.bounds_max.z(), 0.12, 1e-7);
}

TEST(ObjectModelTest, InertiaOfAnOffsetBoxIsAboutItsCentreOfMass) {
  // Same box far from the origin: inertia about the centre of mass must not change.
  TriangleMesh mesh = ObjectModel::load(object("box")).mesh();
  for (auto& v : mesh.vertices) v += Eigen::Vector3d(3.0, -2.0, 5.0);
  const ObjectModel moved = ObjectModel::fromMesh(mesh, "moved");
  const ObjectModel original = ObjectModel::load(object("box"));
  EXPECT_LT((moved.massProperties().inertia - original.massProperties().inertia).norm(),
            1e-6 * original.massProperties().inertia.norm());
  EXPECT_LT((moved.massProperties().center_of_mass - original.massProperties().center_of_mass -
             Eigen::Vector3d(3, -2, 5))
                .norm(),
            1e-9);
}

TEST(ObjectModelTest, ContainsOnScansAgreesWithTheWindingNumberOracleNearTheSurface) {
  // contains() answers from the inside grid where a point's cell holds no surface and by rays
  // elsewhere: points 0.1-4 mm off the surface of two 16k-face scans (both sides; the cells
  // next to the surface are where a wrong label would show) and uniform in their bounds.
  for (const std::string name : {"ycb_011_banana", "ycb_025_mug"}) {
    SCOPED_TRACE(name);
    const ObjectModel model =
        ObjectModel::load(std::string(TEST_DATA_DIR) + "/real/objects/" + name + ".obj");
    const auto& m = model.massProperties();
    Rng rng(13, 4);
    int inside = 0, outside = 0;
    for (int i = 0; i < 700; ++i) {
      Eigen::Vector3d p;
      if (i % 7 == 6) {
        p = m.bounds_min +
            (m.bounds_max - m.bounds_min)
                .cwiseProduct(Eigen::Vector3d(rng.uniform(), rng.uniform(), rng.uniform()));
      } else {
        const SurfaceSample s = model.sampleSurface(rng);
        const double off = std::array<double, 6>{1e-4, 3e-4, 1e-3, 2e-3, 3e-3, 4e-3}[i % 7];
        p = s.point + (i % 2 == 0 ? off : -off) * s.normal;
      }
      const double w = windingNumber(model.mesh(), p);
      if (std::abs(w - 0.5) < 0.4) continue;  // too near a fold of the scan to call
      ASSERT_EQ(model.contains(p), w > 0.5) << p.transpose() << " winding " << w;
      (w > 0.5 ? inside : outside) += 1;
    }
    EXPECT_GT(inside, 200);
    EXPECT_GT(outside, 200);
  }
}

TEST(ObjectModelTest, InsideSamplesAreInsideByTheWindingNumberOracle) {
  for (const std::string name : {"mug", "basket", "bowl", "sphere"}) {
    SCOPED_TRACE(name);
    const ObjectModel model = ObjectModel::load(object(name));
    Rng rng(7, 1);
    for (int i = 0; i < 400; ++i) {
      const Eigen::Vector3d p = model.sampleInside(rng);
      ASSERT_GT(windingNumber(model.mesh(), p), 0.5) << p.transpose();
    }
  }
}

TEST(ObjectModelTest, ContainsAgreesWithTheWindingNumberOracle) {
  // Random points in the (slightly grown) bounds of non-convex objects, plus the grid points
  // that hit vertices and edges of the box exactly (ambiguous rays).
  for (const std::string name : {"mug", "basket", "box"}) {
    SCOPED_TRACE(name);
    const ObjectModel model = ObjectModel::load(object(name));
    const auto& m = model.massProperties();
    const Eigen::Vector3d lo = m.bounds_min.array() - 0.01, hi = m.bounds_max.array() + 0.01;
    Rng rng(11, 2);
    int inside = 0;
    for (int i = 0; i < 1500; ++i) {
      const Eigen::Vector3d p(rng.uniform(lo.x(), hi.x()), rng.uniform(lo.y(), hi.y()),
                              rng.uniform(lo.z(), hi.z()));
      const double w = windingNumber(model.mesh(), p);
      ASSERT_EQ(model.contains(p), w > 0.5) << p.transpose() << " winding " << w;
      inside += w > 0.5;
    }
    EXPECT_GT(inside, 0);
  }
  const ObjectModel box = ObjectModel::load(object("box"));
  for (double x : {-0.03, -0.015, 0.0, 0.015}) {
    for (double y : {-0.04, 0.0, 0.02}) {
      for (double z : {0.0, 0.03, 0.06}) {
        const Eigen::Vector3d p(x, y, z);
        const double w = windingNumber(box.mesh(), p);
        if (std::abs(w - 0.5) < 0.49) continue;  // on the surface: either answer is fine
        EXPECT_EQ(box.contains(p), w > 0.5) << p.transpose();
      }
    }
  }
  EXPECT_FALSE(box.contains(Eigen::Vector3d(0.0, 0.0, 1.0)));
  EXPECT_FALSE(box.contains(Eigen::Vector3d(std::nan(""), 0.0, 0.0)));
}

TEST(ObjectModelTest, InsideSamplesAreUniform) {
  // The cylinder's polygon has 64 segments, symmetric under quarter turns: the quadrant
  // x > 0, y > 0 holds exactly 1/4 of the volume, and z < 0.05 holds exactly 1/4 too.
  // Tolerance: 5 binomial standard deviations.
  const ObjectModel model = ObjectModel::load(object("cylinder"));
  Rng rng(3, 0);
  const int n = 20000;
  int quadrant = 0, low = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p = model.sampleInside(rng);
    quadrant += p.x() > 0 && p.y() > 0;
    low += p.z() < 0.05;
  }
  const double p = 0.25, sigma = std::sqrt(p * (1 - p) / n);
  EXPECT_NEAR(static_cast<double>(quadrant) / n, p, 5 * sigma);
  EXPECT_NEAR(static_cast<double>(low) / n, p, 5 * sigma);
}

TEST(ObjectModelTest, SamplingIsDeterministicPerSeedAndStream) {
  const ObjectModel model = ObjectModel::load(object("mug"));
  Rng a(42, 5), b(42, 5), c(42, 6);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d pa = model.sampleInside(a), pb = model.sampleInside(b);
    EXPECT_EQ(pa, pb);
    const SurfaceSample sa = model.sampleSurface(a), sb = model.sampleSurface(b);
    EXPECT_EQ(sa.point, sb.point);
    EXPECT_EQ(sa.face, sb.face);
  }
  EXPECT_NE(model.sampleInside(a), model.sampleInside(c));
}

TEST(ObjectModelTest, SurfaceSamplesLieOnTheSurfaceWithOutwardUnitNormals) {
  for (const std::string name : {"sphere", "box", "cylinder"}) {  // convex objects
    SCOPED_TRACE(name);
    const ObjectModel model = ObjectModel::load(object(name));
    Rng rng(5, 9);
    for (int i = 0; i < 300; ++i) {
      const SurfaceSample s = model.sampleSurface(rng);
      EXPECT_NEAR(s.normal.norm(), 1.0, 1e-12);
      EXPECT_LT(model.distanceToSurface(s.point), 1e-9);
      EXPECT_FALSE(model.contains(s.point + 1e-4 * s.normal)) << s.point.transpose();
      EXPECT_TRUE(model.contains(s.point - 1e-4 * s.normal)) << s.point.transpose();
    }
  }
}

TEST(ObjectModelTest, SurfaceSamplesAreAreaWeighted) {
  // Box 0.06 x 0.08 x 0.12: the two faces normal to z hold 2*0.06*0.08 of the area.
  const ObjectModel model = ObjectModel::load(object("box"));
  const double area = 2 * (0.06 * 0.08 + 0.06 * 0.12 + 0.08 * 0.12);
  const double p = 2 * 0.06 * 0.08 / area;
  Rng rng(8, 0);
  const int n = 20000;
  int hits = 0;
  for (int i = 0; i < n; ++i) hits += std::abs(model.sampleSurface(rng).normal.z()) > 0.99;
  EXPECT_NEAR(static_cast<double>(hits) / n, p, 5 * std::sqrt(p * (1 - p) / n));
}

TEST(ObjectModelTest, DistanceToSurfaceMatchesBruteForceOnTheBox) {
  const ObjectModel model = ObjectModel::load(object("box"));
  // Inside the box the distance is the smallest distance to the six planes.
  Rng rng(1, 1);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(rng.uniform(-0.03, 0.03), rng.uniform(-0.04, 0.04),
                            rng.uniform(0.0, 0.12));
    const double expected =
        std::min({p.x() + 0.03, 0.03 - p.x(), p.y() + 0.04, 0.04 - p.y(), p.z(), 0.12 - p.z()});
    EXPECT_NEAR(model.distanceToSurface(p), expected, 1e-7);
  }
  // Outside, along the z axis above the top face.
  EXPECT_NEAR(model.distanceToSurface(Eigen::Vector3d(0, 0, 0.5)), 0.38, 1e-7);
}

TEST(ObjectModelTest, NearSurfaceIsTheBoundedDistanceTest) {
  // Oracle: the box's distance by its planes (inside) and by the clamped offset (outside); the
  // bounded query agrees with it at every radius, including points on both sides of the radius.
  const ObjectModel model = ObjectModel::load(object("box"));
  const Eigen::Vector3d lo(-0.03, -0.04, 0.0), hi(0.03, 0.04, 0.12);
  Rng rng(2, 1);
  int near = 0, far = 0;
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector3d p(rng.uniform(-0.05, 0.05), rng.uniform(-0.06, 0.06),
                            rng.uniform(-0.02, 0.14));
    const Eigen::Vector3d outside = (p.cwiseMax(lo).cwiseMin(hi) - p);
    const double d = outside.norm() > 0.0
                         ? outside.norm()
                         : std::min({p.x() - lo.x(), hi.x() - p.x(), p.y() - lo.y(), hi.y() - p.y(),
                                     p.z() - lo.z(), hi.z() - p.z()});
    for (const double r : {0.0005, 0.005, 0.02}) {
      if (std::abs(d - r) < 1e-9) continue;
      EXPECT_EQ(model.nearSurface(p, r), d < r) << "distance " << d << " radius " << r;
      (d < r ? near : far) += 1;
    }
  }
  EXPECT_GT(near, 100);
  EXPECT_GT(far, 100);
  EXPECT_FALSE(model.nearSurface(Eigen::Vector3d(0, 0, 0.5), 0.38 - 1e-6));
  EXPECT_TRUE(model.nearSurface(Eigen::Vector3d(0, 0, 0.5), 0.38 + 1e-6));
  EXPECT_FALSE(model.nearSurface(Eigen::Vector3d(0, 0, 0.06), 0.0));
}

TEST(ObjectModelTest, QueriesAreThreadSafe) {
  const ObjectModel model = ObjectModel::load(object("basket"));
  std::vector<int> serial(2000), parallel(2000);
  auto work = [&](std::vector<int>* out, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      Rng rng(99, static_cast<std::uint64_t>(i));
      const Eigen::Vector3d p = model.sampleInside(rng);
      (*out)[i] = model.contains(p + Eigen::Vector3d(0.01, 0, 0)) ? 1 : 0;
    }
  };
  work(&serial, 0, 2000);
  std::thread t1(work, &parallel, 0, 1000), t2(work, &parallel, 1000, 2000);
  t1.join();
  t2.join();
  EXPECT_EQ(serial, parallel);
}

TEST(ObjectModelTest, Sha256AndNames) {
  EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  const ObjectModel model = ObjectModel::load(object("box"));
  EXPECT_EQ(model.name(), "box");
  EXPECT_EQ(model.sourceSha256(), sha256File(object("box")));
  EXPECT_EQ(model.sourceSha256().size(), 64u);
  EXPECT_THROW(sha256File("/nonexistent/file"), Error);
}

/// Independent oracle for castRay: every triangle intersected by the plane-then-inside test
/// (the ray meets the triangle's plane at t; the point lies inside when its three edge cross
/// products point along the normal), the smallest t in the range.
double bruteForceRay(const TriangleMesh& mesh, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                     double t_min) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& f : mesh.faces) {
    const Eigen::Vector3d a = mesh.vertices[f[0]], b = mesh.vertices[f[1]], c = mesh.vertices[f[2]];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double nd = n.dot(d);
    if (std::abs(nd) < 1e-15) continue;
    const double t = n.dot(a - o) / nd;
    if (t <= t_min || t >= best) continue;
    const Eigen::Vector3d q = o + t * d;
    if ((b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
        (a - c).cross(q - c).dot(n) >= 0)
      best = t;
  }
  return best;
}

TEST(ObjectModelTest, CastRayMatchesABruteForceOracle) {
  // Rays from inside along the inward normal (the antipodal sampler's use), from random outside
  // points toward the object and in random directions, on a fine curved mesh and a box.
  for (const std::string name : {"mug", "box"}) {
    SCOPED_TRACE(name);
    const ObjectModel model = ObjectModel::load(object(name));
    const TriangleMesh& mesh = model.mesh();
    Rng rng(5, 0);
    int hits = 0;
    for (int i = 0; i < 300; ++i) {
      Eigen::Vector3d o, d;
      if (i % 3 == 0) {
        const SurfaceSample s = model.sampleSurface(rng);
        o = s.point;
        d = -s.normal;
      } else {
        const Eigen::Vector3d c = model.massProperties().center_of_mass;
        o = c + 0.3 * rng.direction();
        d = i % 3 == 1 ? Eigen::Vector3d((c - o).normalized()) : rng.direction();
      }
      const double t_min = i % 3 == 0 ? 1e-7 : 0.0;
      const double expected = bruteForceRay(mesh, o, d, t_min);
      const std::optional<RayHit> hit = model.castRay(o, d, t_min);
      if (!std::isfinite(expected)) {
        EXPECT_FALSE(hit.has_value()) << "ray " << i;
        continue;
      }
      ASSERT_TRUE(hit.has_value()) << "ray " << i;
      ++hits;
      EXPECT_NEAR(hit->distance, expected, 1e-9) << "ray " << i;
      EXPECT_LT((hit->point - (o + expected * d)).norm(), 1e-9);
      const auto& f = mesh.faces[static_cast<std::size_t>(hit->face)];
      const Eigen::Vector3d n = (mesh.vertices[f[1]] - mesh.vertices[f[0]])
                                    .cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]);
      EXPECT_LT((hit->normal - n.normalized()).norm(), 1e-9);
      if (i % 3 == 0) {
        EXPECT_GT(hit->normal.dot(d), 0.0) << "a ray from the surface inward leaves";
      }
    }
    EXPECT_GT(hits, 150);
    // The range bounds the answer.
    const SurfaceSample s = model.sampleSurface(rng);
    const std::optional<RayHit> far = model.castRay(s.point, -s.normal, 1e-7);
    ASSERT_TRUE(far.has_value());
    EXPECT_FALSE(model.castRay(s.point, -s.normal, 1e-7, 0.5 * far->distance).has_value());
  }
}

TEST(ObjectModelTest, CastRayAlongAxesAndOnBoxPlanesMatchesTheOracle) {
  // Directions with zero components (their slab tests divide by zero) from origins on the box's
  // face planes, and random rays on a 16k-face scan (a tree deeper than the box's).
  const ObjectModel box = ObjectModel::load(object("box"));  // x +-0.03, y +-0.04, z 0..0.12
  const double planes[3][4] = {
      {-0.03, 0.0, 0.03, 0.05}, {-0.04, 0.01, 0.04, 0.06}, {0.0, 0.06, 0.12, -0.01}};
  int hits = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2)
      for (double a : planes[(axis + 1) % 3])
        for (double b : planes[(axis + 2) % 3]) {
          Eigen::Vector3d o = Eigen::Vector3d::Zero(), d = Eigen::Vector3d::Zero();
          o[axis] = -0.2 * sign;
          o[(axis + 1) % 3] = a;
          o[(axis + 2) % 3] = b;
          d[axis] = sign;
          const double expected = bruteForceRay(box.mesh(), o, d, 0.0);
          const std::optional<RayHit> hit = box.castRay(o, d, 0.0);
          ASSERT_EQ(hit.has_value(), std::isfinite(expected))
              << o.transpose() << " " << d.transpose();
          if (!hit) continue;
          ++hits;
          EXPECT_NEAR(hit->distance, expected, 1e-12) << o.transpose() << " " << d.transpose();
        }
  EXPECT_GE(hits, 6);  // the centre lines and the rays along the box's faces and edges
  const ObjectModel scan =
      ObjectModel::load(std::string(TEST_DATA_DIR) + "/real/objects/ycb_025_mug.obj");
  Rng rng(11, 0);
  for (int i = 0; i < 200; ++i) {
    const SurfaceSample s = scan.sampleSurface(rng);
    const Eigen::Vector3d o = s.point - 0.003 * s.normal, d = rng.direction();
    const double expected = bruteForceRay(scan.mesh(), o, d, 0.0);
    const std::optional<RayHit> hit = scan.castRay(o, d, 0.0);
    ASSERT_EQ(hit.has_value(), std::isfinite(expected)) << "ray " << i;
    if (hit) {
      EXPECT_NEAR(hit->distance, expected, 1e-9) << "ray " << i;
    }
  }
}

TEST(ObjectModelTest, CastRayAndAgainIsCastRayWithTheCrossingsPastItsHit) {
  // On the reference mug (a hollow: rays cross its walls several times) and the YCB mug scan,
  // from inside the wall and from outside: the hit is castRay's, and `again` is whether the
  // brute-force crossings (every triangle) include one in (hit + gap, range].
  for (const std::string& path :
       {object("mug"), std::string(TEST_DATA_DIR) + "/real/objects/ycb_025_mug.obj"}) {
    SCOPED_TRACE(path);
    const ObjectModel model = ObjectModel::load(path);
    const TriangleMesh& mesh = model.mesh();
    Rng rng(13, 0);
    int again_true = 0, again_false = 0;
    for (int i = 0; i < 200; ++i) {
      const SurfaceSample s = model.sampleSurface(rng);
      const Eigen::Vector3d o = s.point + (i % 2 == 0 ? -0.001 : 0.02) * s.normal;
      const Eigen::Vector3d d = i % 2 == 0 ? rng.direction() : Eigen::Vector3d(-s.normal);
      const double range = rng.uniform(0.01, 0.2), gap = 1e-7;
      bool again = false;
      const std::optional<RayHit> hit = model.castRayAndAgain(o, d, 0.0, range, gap, &again);
      const std::optional<RayHit> plain = model.castRay(o, d, 0.0, range);
      ASSERT_EQ(hit.has_value(), plain.has_value()) << "ray " << i;
      if (!hit) {
        EXPECT_FALSE(again);
        continue;
      }
      EXPECT_EQ(hit->distance, plain->distance) << "ray " << i;
      EXPECT_EQ(hit->face, plain->face) << "ray " << i;
      // Crossings past the hit: the oracle's smallest t beyond hit + gap.
      const double next = bruteForceRay(mesh, o, d, hit->distance + gap);
      EXPECT_EQ(again, next <= range)
          << "ray " << i << ": next crossing " << next << ", range " << range;
      (again ? again_true : again_false) += 1;
    }
    EXPECT_GT(again_true, 10);
    EXPECT_GT(again_false, 10);
  }
  const ObjectModel box = ObjectModel::load(object("box"));
  bool again = false;
  EXPECT_THROW(box.castRayAndAgain(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 0.0, 1.0,
                                   -1.0, &again),
               Error);
}

TEST(ObjectModelTest, CastRayRefusesBadArguments) {
  const ObjectModel model = ObjectModel::load(object("box"));
  EXPECT_THROW(model.castRay(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 1, 0)), Error);
  EXPECT_THROW(model.castRay(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 0.1, 0.1), Error);
  EXPECT_THROW(model.castRay(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), -1.0), Error);
}

}  // namespace
}  // namespace taskmap
