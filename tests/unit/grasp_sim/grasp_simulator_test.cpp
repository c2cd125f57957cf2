#include "taskmap/grasp_sim/grasp_simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <thread>

#include "error_matchers.hpp"
#include "grasp_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/random.hpp"
#include "test_meshes.hpp"

namespace taskmap {
namespace {

HandModel loadHand(const std::string& name) {
  return testing::referenceHand(name);
}
using testing::fromAbove;

bool hasFinger(const GraspResult& r, const std::string& f) {
  for (const auto& x : r.fingers_in_contact)
    if (x == f) return true;
  return false;
}

constexpr double kTol = testing::kContactTolerance;

TEST(GraspSimulator, StatusNamesAndOptions) {
  ASSERT_EQ(allGraspStatuses().size(), 6u);
  EXPECT_STREQ(toString(GraspStatus::kOk), "ok");
  EXPECT_STREQ(toString(GraspStatus::kNotRetractable), "not_retractable");
  EXPECT_STREQ(toString(GraspStatus::kNoPalmContact), "no_palm_contact");
  EXPECT_STREQ(toString(GraspStatus::kNoFingerContact), "no_finger_contact");
  EXPECT_STREQ(toString(GraspStatus::kSelfCollision), "self_collision");
  EXPECT_STREQ(toString(GraspStatus::kStepLimit), "step_limit");
  GraspSimOptions o;
  EXPECT_NO_THROW(o.validate());
  o.contact_tolerance = 0.0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"contact_tolerance"}));
  o = GraspSimOptions();
  o.max_retraction = -1;
  EXPECT_THROW(o.validate(), Error);
  o = GraspSimOptions();
  o.squeeze = 0.5;
  EXPECT_THROW(o.validate(), Error);
  o = GraspSimOptions();
  o.max_closing_steps = 1;
  EXPECT_THROW(o.validate(), Error);
  // The constructor validates too.
  const HandModel hand = loadHand("panda");
  o = GraspSimOptions();
  o.contact_tolerance = -1;
  EXPECT_THROW(GraspSimulator(testing::makeBox(0.05, 0.05, 0.05), hand, o), Error);
}

TEST(GraspSimulator, ParallelJawClosesOnBoxesOfSeveralWidths) {
  const HandModel hand = loadHand("panda");
  const double squeeze = hand.squeeze();
  const double height = 0.10;
  for (double w : {0.02, 0.035, 0.05, 0.07}) {
    SCOPED_TRACE("width " + std::to_string(w));
    GraspSimulator sim(testing::makeBox(w, 0.03, height), hand);
    const GraspResult r = sim.simulate(fromAbove(Eigen::Vector3d(0.003, 0.001, -0.01)));
    ASSERT_EQ(r.status, GraspStatus::kOk) << r.message;
    EXPECT_TRUE(r.palm_contact);
    EXPECT_TRUE(hasFinger(r, "left"));
    EXPECT_TRUE(hasFinger(r, "right"));
    // Opening between the inner finger faces: the width less the squeeze of both fingers.
    const double opening = r.joints[0] + r.joints[1];
    EXPECT_NEAR(opening, w - 2 * squeeze, kTol);
    // The palm was pressed onto the top face by the squeeze (the contacts' depth below); the
    // reported pose has it touching the face.
    EXPECT_NEAR(r.pose.position.z(), 0.5 * height, kTol);
    int side_contacts[2] = {0, 0};
    for (const Contact& c : r.contacts) {
      EXPECT_GT(c.depth, 0.0);
      EXPECT_NEAR(c.depth, squeeze, kTol);
      const std::string& link = hand.links()[static_cast<std::size_t>(c.link)].name;
      if (link == "panda_hand") {
        EXPECT_NEAR(c.point.z(), 0.5 * height, 1e-6);
        EXPECT_GT(c.normal.z(), 0.999);
        continue;
      }
      // Finger contacts lie on the two x faces with normals along +-x.
      EXPECT_NEAR(std::abs(c.point.x()), 0.5 * w, 1e-6) << link;
      EXPECT_GT(std::abs(c.normal.x()), 0.999) << link;
      EXPECT_GT(c.normal.x() * c.point.x(), 0.0) << link;  // outward
      EXPECT_EQ(link == "panda_leftfinger", c.point.x() > 0) << link;
      ++side_contacts[c.point.x() > 0 ? 0 : 1];
    }
    EXPECT_GE(side_contacts[0], 1);
    EXPECT_GE(side_contacts[1], 1);
  }
}

TEST(GraspSimulator, ThreeFingerHandWrapsCylinder) {
  const HandModel hand = loadHand("barrett");
  const double r = 0.035;
  const int sides = 64;
  GraspSimulator sim(testing::makeCylinder(r, 0.20, sides, 1), hand);
  for (double offset : {0.0, 0.003, -0.004}) {
    SCOPED_TRACE("offset " + std::to_string(offset));
    const GraspResult res = sim.simulate(fromAbove(Eigen::Vector3d(offset, 0.01, 0.0)));
    ASSERT_EQ(res.status, GraspStatus::kOk) << res.message;
    EXPECT_TRUE(res.palm_contact);
    for (const char* f : {"f1", "f2", "f3"}) EXPECT_TRUE(hasFinger(res, f)) << f;
    const double inner = r * std::cos(M_PI / sides);  // facet centre distance
    for (const Contact& c : res.contacts) {
      const Eigen::Vector2d radial(c.point.x(), c.point.z());  // axis along y
      EXPECT_GE(radial.norm(), inner - 1e-6);
      EXPECT_LE(radial.norm(), r + 1e-6);
      EXPECT_NEAR(c.normal.y(), 0.0, 1e-9);
      EXPECT_GT(Eigen::Vector2d(c.normal.x(), c.normal.z()).dot(radial.normalized()),
                std::cos(M_PI / sides) - 1e-9);
      EXPECT_GT(c.depth, 0.0);
      EXPECT_LT(c.depth, 3 * hand.squeeze());
    }
  }
}

TEST(GraspSimulator, HumanoidPowerGraspUsesEveryFinger) {
  const HandModel hand = loadHand("humanoid");
  GraspSimulator sim(testing::makeCylinder(0.035, 0.20, 48, 1), hand);
  const GraspResult res = sim.simulate(fromAbove(Eigen::Vector3d(0.0, 0.01, 0.0)));
  ASSERT_EQ(res.status, GraspStatus::kOk) << res.message;
  EXPECT_TRUE(res.palm_contact);
  EXPECT_EQ(res.fingers_in_contact.size(), 5u);
}

TEST(GraspSimulator, HandStartingOutsideAdvancesToTheSurface) {
  const HandModel hand = loadHand("panda");
  GraspSimulator sim(testing::makeBox(0.04, 0.03, 0.10), hand);
  const GraspResult inside = sim.simulate(fromAbove(Eigen::Vector3d(0.0, 0.0, 0.0)));
  const GraspResult outside = sim.simulate(fromAbove(Eigen::Vector3d(0.0, 0.0, 0.25)));
  ASSERT_EQ(outside.status, GraspStatus::kOk) << outside.message;
  EXPECT_LT(outside.stats.retraction, 0.0);  // advanced
  EXPECT_NEAR(outside.pose.position.z(), inside.pose.position.z(), kTol);
  EXPECT_NEAR(outside.joints[0] + outside.joints[1], inside.joints[0] + inside.joints[1], kTol);
  // Pointing away from the object: nothing to touch.
  Pose away = fromAbove(Eigen::Vector3d(0.0, 0.0, 0.25));
  away.orientation =
      away.orientation * Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  const GraspResult none = sim.simulate(away);
  EXPECT_EQ(none.status, GraspStatus::kNoPalmContact);
  EXPECT_NE(none.message.find("touches nothing"), std::string::npos) << none.message;
}

TEST(GraspSimulator, NotRetractableWithinMaxRetraction) {
  const HandModel hand = loadHand("barrett");
  GraspSimOptions o;
  o.max_retraction = 0.05;
  GraspSimulator sim(testing::makeBox(0.30, 0.30, 0.30), hand, o);
  const GraspResult r = sim.simulate(fromAbove(Eigen::Vector3d(0.01, 0.02, 0.0)));
  EXPECT_EQ(r.status, GraspStatus::kNotRetractable);
  EXPECT_NE(r.message.find("still penetrates"), std::string::npos) << r.message;
  EXPECT_DOUBLE_EQ(r.stats.retraction, 0.05);
  EXPECT_TRUE(r.contacts.empty());
  // With the automatic limit the same pose retracts out of the top face: the hand is free
  // once the fingertips (0.125 m ahead of the palm) leave it, so the fingers touch first.
  GraspSimulator sim_auto(testing::makeBox(0.30, 0.30, 0.30), hand);
  const GraspResult out = sim_auto.simulate(fromAbove(Eigen::Vector3d(0.01, 0.02, 0.0)));
  EXPECT_EQ(out.status, GraspStatus::kNoPalmContact);
  EXPECT_GE(out.stats.retraction, 0.15 + 0.125);
  EXPECT_LE(out.stats.retraction, 0.15 + 0.125 + kTol);
}

TEST(GraspSimulator, FingersFirstGiveNoPalmContactUnlessAllowed) {
  const HandModel hand = loadHand("panda");
  // Wider than the open gripper: the fingertips land on the top face first.
  GraspSimulator sim(testing::makeBox(0.12, 0.03, 0.10), hand);
  const GraspResult r = sim.simulate(fromAbove(Eigen::Vector3d(0.0, 0.0, 0.0)));
  EXPECT_EQ(r.status, GraspStatus::kNoPalmContact);
  EXPECT_NE(r.message.find("before the palm"), std::string::npos) << r.message;
  // Fingertips rest on the top face: palm 0.045 m (finger length) above it.
  EXPECT_NEAR(r.pose.position.z(), 0.05 + 0.045, kTol);
  GraspSimOptions o;
  o.require_palm_contact = false;
  GraspSimulator lenient(testing::makeBox(0.12, 0.03, 0.10), hand, o);
  const GraspResult l = lenient.simulate(fromAbove(Eigen::Vector3d(0.0, 0.0, 0.0)));
  // The fingers touch the top face and stop at once; sliding along it presses nothing.
  EXPECT_EQ(l.status, GraspStatus::kNoFingerContact) << l.message;
  EXPECT_FALSE(l.palm_contact);
}

TEST(GraspSimulator, ThinObjectLeavesFingersClosedWithoutContact) {
  const HandModel hand = loadHand("panda");
  // A 1 cm post narrower than the finger pads: the fingers reach it.
  GraspSimulator sim(testing::makeBox(0.01, 0.01, 0.10), hand);
  const GraspResult r = sim.simulate(fromAbove(Eigen::Vector3d(0.0, 0.0, 0.0)));
  ASSERT_EQ(r.status, GraspStatus::kOk) << r.message;
  EXPECT_NEAR(r.joints[0] + r.joints[1], 0.01 - 2 * hand.squeeze(), kTol);
  // A 4 mm post under the palm but beside the finger pads (pads span +-0.01 m across):
  // the fingers close to their limit without touching it.
  GraspSimulator far(testing::makeBox(0.004, 0.004, 0.10), hand);
  Pose side = fromAbove(Eigen::Vector3d(0.0, 0.02, 0.0));  // post beside the finger pads
  const GraspResult n = far.simulate(side);
  EXPECT_EQ(n.status, GraspStatus::kNoFingerContact) << n.message;
  EXPECT_TRUE(n.palm_contact);
  EXPECT_NEAR(n.joints[0], 0.0, 1e-12);  // closed to the limit
  EXPECT_NEAR(n.joints[1], 0.0, 1e-12);
}

using testing::randomPoses;

/// Same trial outcome bit for bit; `same_queries`: also the same number of collision queries
/// (lean queries stop early, so the baseline comparison leaves it out).
void expectSame(const GraspResult& a, const GraspResult& b, bool same_queries = true) {
  ASSERT_EQ(a.status, b.status);
  EXPECT_EQ(a.message, b.message);
  EXPECT_EQ(a.pose.position, b.pose.position);
  EXPECT_EQ(a.pose.orientation.coeffs(), b.pose.orientation.coeffs());
  EXPECT_EQ(a.joints, b.joints);
  ASSERT_EQ(a.contacts.size(), b.contacts.size());
  for (std::size_t i = 0; i < a.contacts.size(); ++i) {
    EXPECT_EQ(a.contacts[i].point, b.contacts[i].point);
    EXPECT_EQ(a.contacts[i].normal, b.contacts[i].normal);
    EXPECT_EQ(a.contacts[i].depth, b.contacts[i].depth);
    EXPECT_EQ(a.contacts[i].link, b.contacts[i].link);
  }
  EXPECT_EQ(a.fingers_in_contact, b.fingers_in_contact);
  EXPECT_EQ(a.palm_contact, b.palm_contact);
  if (same_queries) {
    EXPECT_EQ(a.stats.queries, b.stats.queries);
  }
}

/// Simulates each pose with both simulators and expects the same trials (expectSame, and the
/// same number of closing steps); returns how many ended kOk.
int sameTrials(const GraspSimulator& x, const GraspSimulator& y, const std::vector<Pose>& poses,
               bool same_queries) {
  int ok = 0;
  for (const Pose& p : poses) {
    const GraspResult a = x.simulate(p), b = y.simulate(p);
    expectSame(a, b, same_queries);
    EXPECT_EQ(a.stats.closing_steps, b.stats.closing_steps);
    ok += a.status == GraspStatus::kOk;
  }
  return ok;
}

TEST(GraspSimulator, ParallelThreadsMatchSequentialRun) {
  const HandModel hand = loadHand("barrett");
  GraspSimulator sim(testing::makeCylinder(0.035, 0.20, 32, 2), hand);
  const auto poses =
      randomPoses(48, Eigen::Vector3d(-0.035, -0.035, -0.1), Eigen::Vector3d(0.035, 0.035, 0.1));
  std::vector<GraspResult> seq;
  for (const Pose& p : poses) seq.push_back(sim.simulate(p));
  std::vector<GraspResult> par(poses.size());
  std::vector<std::thread> threads;
  const int kThreads = 4;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      // Interleaved, reversed order per thread: a different schedule than the sequential run.
      for (int i = static_cast<int>(poses.size()) - 1 - t; i >= 0; i -= kThreads)
        par[static_cast<std::size_t>(i)] = sim.simulate(poses[static_cast<std::size_t>(i)]);
    });
  for (auto& th : threads) th.join();
  int ok = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    SCOPED_TRACE("trial " + std::to_string(i));
    expectSame(seq[i], par[i]);
    ok += seq[i].status == GraspStatus::kOk;
  }
  EXPECT_GT(ok, 0);  // the set exercises the closing path
}

// The culled and lean queries (default) against the baseline (Bullet's BVH query, every exact
// hit) on fixed trials: same statuses, poses, joints and contacts bit for bit, for box hands, a
// hand with mesh (hull) links and a mimic jaw pair (coupled closing), on the reference mug (3590
// faces) and bowl (6272 faces).
TEST(GraspSimulator, CulledQueriesGiveTheBaselineTrials) {
  const std::string data = std::string(TEST_DATA_DIR) + "/hands/";
  for (const char* object_name : {"mug", "bowl"}) {
    const ObjectModel object =
        ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/" + object_name + ".obj");
    const Eigen::Vector3d lo = object.massProperties().bounds_min;
    const Eigen::Vector3d hi = object.massProperties().bounds_max;
    for (const std::string& hand_path :
         {std::string(TASKMAP_HANDS_DIR) + "/panda/panda.urdf",
          std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf", data + "hull_palm.urdf",
          testing::testHandPath("panda_mimic")}) {
      SCOPED_TRACE(std::string(object_name) + " " + hand_path);
      const HandModel hand = HandModel::load(hand_path);
      GraspSimDiagnostics baseline, culled;
      baseline.culled_queries = false;
      culled.separating_axis_contacts =
          false;  // EPA, as the baseline (contact_depths_test.cpp has the rest)
      const GraspSimulator fast(object, hand, {}, culled), slow(object, hand, {}, baseline);
      // the trials reach closing, squeeze and contacts
      EXPECT_GT(sameTrials(fast, slow, randomPoses(40, lo, hi), false), 0);
    }
  }
}

// The closing's self-collision test with each link pair's separating axis carried (default)
// against GJK on every pair within its bounding spheres: the same trials bit for bit (statuses,
// poses, joints, contacts, query counts) for hands with self-collision partners: the humanoid
// hand (boxes), a hand with hull links and a mimic jaw pair (coupled closing).
TEST(GraspSimulator, SelfCollisionAxesGiveTheSameTrials) {
  const ObjectModel object = ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/mug.obj");
  const Eigen::Vector3d lo = object.massProperties().bounds_min;
  const Eigen::Vector3d hi = object.massProperties().bounds_max;
  for (const std::string& hand_path : {std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf",
                                       std::string(TEST_DATA_DIR) + "/hands/hull_palm.urdf",
                                       testing::testHandPath("panda_mimic")}) {
    SCOPED_TRACE(hand_path);
    const HandModel hand = HandModel::load(hand_path);
    GraspSimDiagnostics plain;
    plain.self_collision_axes = false;
    const GraspSimulator with_axes(object, hand), without(object, hand, {}, plain);
    // the trials reach the closing
    EXPECT_GT(sameTrials(with_axes, without, randomPoses(40, lo, hi), true), 0);
  }
}

// Self-collision pairs proven apart over their joint's range (default) against testing every
// pair: the same trials bit for bit (statuses, poses, joints, contacts, query counts) for the
// knuckle jaw, whose six pairs are all proven apart (self_pair_proof_test.cpp), on a cylinder
// its jaws grip.
TEST(GraspSimulator, SelfPairProofsGiveTheSameTrials) {
  const HandModel hand = HandModel::load(testing::testHandPath("knuckle_jaw"));
  const TriangleMesh cylinder = testing::makeCylinder(0.03, 0.12, 32, 2);
  GraspSimDiagnostics every;
  every.self_pair_proofs = false;
  const GraspSimulator proofs(cylinder, hand), plain(cylinder, hand, {}, every);
  const auto poses =
      randomPoses(60, Eigen::Vector3d(-0.03, -0.03, -0.06), Eigen::Vector3d(0.03, 0.03, 0.06));
  EXPECT_GT(sameTrials(proofs, plain, poses, true), 0);  // the trials reach the closing
}

// FailureDetail::kStatus (what a build asks) against kFull on the same trials: the same status
// on every trial, successful trials the same bit for bit; failures may end early, and on these
// sets no_palm_contact trials do (fewer queries in all), for box hands and a hull palm, on the
// reference mug and basket (palms starting inside the objects' boxes, retracted).
TEST(GraspSimulator, StatusDetailKeepsEveryStatusAndEndsFailuresEarly) {
  for (const char* object_name : {"mug", "basket"}) {
    const ObjectModel object =
        ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/" + object_name + ".obj");
    const Eigen::Vector3d lo = object.massProperties().bounds_min;
    const Eigen::Vector3d hi = object.massProperties().bounds_max;
    for (const std::string& hand_path : {std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf",
                                         std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf",
                                         std::string(TEST_DATA_DIR) + "/hands/hull_palm.urdf"}) {
      SCOPED_TRACE(std::string(object_name) + " " + hand_path);
      const GraspSimulator sim(object, HandModel::load(hand_path));
      int ok = 0, no_palm = 0, shorter = 0;
      long full_queries = 0, status_queries = 0;
      for (const Pose& p : randomPoses(60, lo, hi)) {
        const GraspResult full = sim.simulate(p);
        const GraspResult status = sim.simulate(p, FailureDetail::kStatus);
        ASSERT_EQ(full.status, status.status);
        full_queries += full.stats.queries;
        status_queries += status.stats.queries;
        if (full.status == GraspStatus::kOk) {
          ++ok;
          expectSame(full, status);
        } else if (full.status == GraspStatus::kNoPalmContact) {
          ++no_palm;
          EXPECT_LE(status.stats.queries, full.stats.queries);
          shorter += status.stats.queries < full.stats.queries;
        }
      }
      EXPECT_GT(ok, 0);
      EXPECT_GT(no_palm, 0);
      EXPECT_GT(shorter, 0);
      EXPECT_LT(status_queries, full_queries);
    }
  }
}

TEST(GraspSimulator, ReferenceBasketTrialsKeepTheirInvariants) {
  const ObjectModel basket = ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/basket.obj");
  for (const char* name : {"panda", "barrett", "humanoid"}) {
    SCOPED_TRACE(name);
    const HandModel hand = loadHand(name);
    GraspSimOptions o;
    o.require_palm_contact = false;  // more closing trials
    GraspSimulator sim(basket, hand, o);
    const Eigen::VectorXd lo = hand.lowerLimits(), hi = hand.upperLimits();
    int ok = 0;
    for (int i = 0; i < 40; ++i) {
      Rng rng(11, static_cast<std::uint64_t>(i));
      Pose p;
      p.position = basket.sampleInside(rng);
      p.orientation = rng.rotation();
      const GraspResult r = sim.simulate(p);
      ok += r.status == GraspStatus::kOk;
      EXPECT_NEAR(r.pose.orientation.norm(), 1.0, 1e-12);
      // The pose only moved along the approach axis.
      const Eigen::Vector3d a = p.orientation * hand.approachAxis();
      const Eigen::Vector3d moved = r.pose.position - p.position;
      EXPECT_LT((moved - moved.dot(a) * a).norm(), 1e-9);
      // Retracted, then pressed by at most the squeeze plus the tolerance when the palm touched.
      EXPECT_GE(moved.dot(a), -r.stats.retraction - 1e-9);
      EXPECT_LE(moved.dot(a), -r.stats.retraction + hand.squeeze() + kTol + 1e-9);
      for (Eigen::Index j = 0; j < r.joints.size(); ++j) {
        EXPECT_GE(r.joints[j], lo[j]);
        EXPECT_LE(r.joints[j], hi[j]);
      }
      std::set<std::string> fingers;
      bool palm = false;
      for (const Contact& c : r.contacts) {
        EXPECT_LT(basket.distanceToSurface(c.point), 1e-7);
        EXPECT_NEAR(c.normal.norm(), 1.0, 1e-12);
        EXPECT_GT(c.depth, 0.0);
        EXPECT_LE(c.depth, 2 * hand.squeeze() + kTol + 1e-9);
        // Just outside along the normal is outside the solid, just inside is inside.
        const auto& link = hand.links()[static_cast<std::size_t>(c.link)];
        if (link.finger >= 0)
          fingers.insert(hand.fingerNames()[static_cast<std::size_t>(link.finger)]);
        palm = palm || link.palm;
      }
      EXPECT_EQ(std::set<std::string>(r.fingers_in_contact.begin(), r.fingers_in_contact.end()),
                fingers);
      EXPECT_EQ(r.palm_contact, palm);
      if (r.status == GraspStatus::kOk) {
        EXPECT_FALSE(fingers.empty());
      }
    }
    EXPECT_GT(ok, 0);
  }
}

}  // namespace
}  // namespace taskmap
