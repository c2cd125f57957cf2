// Analytic gradients of both criteria against central finite differences on the manifold
// (p <- p + h e_j, R <- exp(h e_j) R), in the object frame, the world frame and joint space.
#include <cmath>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "synthetic_map.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/integration/criteria.hpp"
#include "taskmap/integration/frames.hpp"
#include "taskmap/integration/task_map.hpp"

namespace taskmap {
namespace {

Pose perturb(const Pose& x, const Twist& d) {
  Pose y;
  y.position = x.position + d.head<3>();
  y.orientation = Eigen::Quaterniond(rotationExp(d.tail<3>()) * x.orientation.toRotationMatrix());
  return y;
}

Pose compose(const Pose& a, const Pose& b) {  // a * b
  Pose c;
  c.position = a.position + a.orientation * b.position;
  c.orientation = (a.orientation * b.orientation).normalized();
  return c;
}

// Central differences of f at x with steps hl (linear) and ha (angular).
template <typename F>
Twist finiteDifference(F&& f, const Pose& x, double hl, double ha) {
  Twist g;
  for (int j = 0; j < 6; ++j) {
    const double h = j < 3 ? hl : ha;
    Twist d = Twist::Zero();
    d[j] = h;
    g[j] = (f(perturb(x, d)) - f(perturb(x, -d))) / (2 * h);
  }
  return g;
}

double relError(const Twist& a, const Twist& b) {
  return (a - b).norm() / b.norm();
}

struct Fixture : ::testing::Test {
  static const TaskMap& map() {
    static const TaskMap m = [] {
      TaskMapOptions o;
      o.quality_mode = QualityMode::kExact;  // smooth everywhere (no cut-off sphere)
      o.linear_weight = 3.0;
      o.angular_weight = 0.05;
      return TaskMap::fromData(testing::syntheticMap(600), o);
    }();
    return m;
  }
  // A pose near a sample (within about two kernel widths) with random sign.
  static Pose nearMap(Rng& rng) {
    const TaskMap& m = map();
    Pose x = m.pose(rng.below(m.size()));
    const double sp = *m.options().position_sigma, sr = *m.options().rotation_sigma;
    x.position += sp * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    x.orientation = Eigen::Quaterniond(
        rotationExp(sr * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal())) *
        x.orientation.toRotationMatrix());
    if (rng.uniform() < 0.5) x.orientation.coeffs() *= -1.0;
    return x;
  }
};

TEST_F(Fixture, ProximityGradientMatchesFiniteDifferences) {
  Rng rng(1, 0);
  int tested = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Pose x = trial % 2 ? nearMap(rng) : testing::randomPose(rng);
    const ProximityResult p = map().proximity(x);
    if (p.difference.tail<3>().norm() > 3.0) continue;  // log is not smooth near pi
    bool same = true;
    const Twist fd = finiteDifference(
        [&](const Pose& y) {
          const ProximityResult q = map().proximity(y);
          same = same && q.nearest.index == p.nearest.index;
          return q.value;
        },
        x, 1e-6, 1e-6);
    if (!same) continue;  // the nearest sample switched inside the stencil
    ++tested;
    ASSERT_LT(relError(fd, p.gradient), 1e-6) << "trial " << trial;
  }
  EXPECT_GT(tested, 250);
}

TEST_F(Fixture, QualityGradientMatchesFiniteDifferences) {
  // The default (isotropic) kernel, then anisotropic ones: rho sr above and below sp.
  for (int variant = 0; variant < 3; ++variant) {
    TaskMapOptions o = map().options();
    if (variant > 0) o.rotation_sigma = *o.rotation_sigma * (variant == 1 ? 3.0 : 0.4);
    const TaskMap m = TaskMap::fromData(map().data(), o);
    Rng rng(2, 0);
    const double hl = 1e-4 * *m.options().position_sigma;
    const double ha = 1e-4 * *m.options().rotation_sigma;
    for (int trial = 0; trial < 100; ++trial) {
      const Pose x = nearMap(rng);
      const QualityCriterion q = m.quality(x);
      ASSERT_LT(q.value, 0.0);
      const Twist fd =
          finiteDifference([&](const Pose& y) { return m.quality(y).value; }, x, hl, ha);
      ASSERT_LT(relError(fd, q.gradient), 1e-6) << "variant " << variant << " trial " << trial;
    }
  }
}

TEST_F(Fixture, SingleSampleCriteriaMatchFiniteDifferences) {
  Rng rng(3, 0);
  for (int trial = 0; trial < 200; ++trial) {
    const Pose mu = testing::randomPose(rng);
    Pose x = perturb(mu, Twist(0.02 * rng.normal(), 0.02 * rng.normal(), 0.02 * rng.normal(),
                               0.5 * rng.normal(), 0.5 * rng.normal(), 0.5 * rng.normal()));
    if (poseDifference(x, mu).tail<3>().norm() > 3.0) continue;
    Twist g;
    proximityCost(x, mu, 2.0, 0.3, &g);
    Twist fd = finiteDifference([&](const Pose& y) { return proximityCost(y, mu, 2.0, 0.3); }, x,
                                1e-6, 1e-6);
    ASSERT_LT(relError(fd, g), 1e-6);
    gaussianDensity(x, mu, 0.02, 0.5, &g);
    fd = finiteDifference([&](const Pose& y) { return gaussianDensity(y, mu, 0.02, 0.5); }, x, 2e-6,
                          5e-5);
    ASSERT_LT(relError(fd, g), 1e-6);
  }
}

TEST_F(Fixture, WorldFrameGradientsMatchFiniteDifferences) {
  Rng rng(4, 0);
  const double hl = 1e-4 * *map().options().position_sigma;
  const double ha = 1e-4 * *map().options().rotation_sigma;
  int tested = 0;
  for (int trial = 0; trial < 100; ++trial) {
    Pose object;
    object.position = Eigen::Vector3d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0, 1));
    object.orientation = rng.rotation();
    const Pose x = nearMap(rng);
    const Pose hand = compose(object, x);
    ASSERT_LT(poseDistance(handInObject(hand, object), x, 0.1), 1e-12);
    const Evaluation e = map().evaluate(x);
    bool same = true;
    auto cost = [&](const Pose& h, const Pose& o) {
      const Evaluation ev = map().evaluate(handInObject(h, o));
      same = same && ev.proximity.nearest.index == e.proximity.nearest.index;
      return ev.cost();
    };
    const Twist fd_hand =
        finiteDifference([&](const Pose& h) { return cost(h, object); }, hand, hl, ha);
    const Twist fd_obj =
        finiteDifference([&](const Pose& o) { return cost(hand, o); }, object, hl, ha);
    if (!same) continue;
    ++tested;
    ASSERT_LT(relError(fd_hand, handGradientToWorld(e.gradient(), object)), 1e-6);
    ASSERT_LT(relError(fd_obj, objectGradientToWorld(e.gradient(), hand, object)), 1e-6);

    // Joint space (eq. 1.22): hand and object both move with 4 joints.
    Eigen::MatrixXd jh(6, 4), jo(6, 4);
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 4; ++c) {
        jh(r, c) = rng.uniform(-1, 1);
        jo(r, c) = rng.uniform(-1, 1);
      }
    const Eigen::VectorXd gq = jointGradient(e.gradient(), hand, object, jh, jo);
    for (int j = 0; j < 4; ++j) {
      const double h = 1e-4 * *map().options().position_sigma;
      const Twist th = h * jh.col(j), to = h * jo.col(j);
      const double d = (cost(perturb(hand, th), perturb(object, to)) -
                        cost(perturb(hand, -th), perturb(object, -to))) /
                       (2 * h);
      if (same) {
        ASSERT_NEAR(d, gq[j], 1e-6 * gq.norm());
      }
    }
  }
  EXPECT_GT(tested, 80);
}

TEST(Frames, ChainRejectsWrongJacobianShape) {
  EXPECT_EQ(
      testing::errorMessage([&] { chainToJoints(Twist::Zero(), Eigen::MatrixXd::Zero(5, 3)); }),
      "Jacobian has 5 rows; expected 6 (linear then angular, world frame)");
}

}  // namespace
}  // namespace taskmap
