// GraspSimDiagnostics::separating_axis_contacts against EPA (the option false) on a real scan and
// the reference mug, with box hands (panda, humanoid) and the Franka hand (hull palm): the same
// simulated grasps (status, palm pose, joints: bit for bit on these poses; a finger whose only
// contact is a pair Bullet's GJK calls apart could change the status), and contacts that move only
// at tied features, so that force closure and epsilon (taskmap::quality, the stage that reads
// them) stay within the documented tolerance.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "grasp_fixtures.hpp"
#include "taskmap/grasp_sim/grasp_simulator.hpp"
#include "taskmap/meshes/object_model.hpp"
#include "taskmap/quality/grasp_quality.hpp"

namespace taskmap {
namespace {

TEST(ContactDepths, SameGraspsAndForceClosureWithinTolerance) {
  const std::string real = std::string(TEST_DATA_DIR) + "/real/objects/";
  for (const std::string& object_path :
       {real + "ycb_011_banana.obj", std::string(TASKMAP_OBJECTS_DIR) + "/mug.obj"}) {
    const ObjectModel object = ObjectModel::load(object_path);
    const MassProperties& mp = object.massProperties();
    for (const std::string& hand_path :
         {std::string(TASKMAP_HANDS_DIR) + "/panda/panda.urdf",
          std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf",
          std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf"}) {
      SCOPED_TRACE(object_path + " " + hand_path);
      const HandModel hand = HandModel::load(hand_path);
      GraspSimDiagnostics epa_diagnostics;
      epa_diagnostics.separating_axis_contacts = false;
      const GraspSimulator sat(object, hand), epa(object, hand, {}, epa_diagnostics);
      int ok = 0, fc_agree = 0;
      std::vector<double> rel, moved;
      for (const Pose& p : testing::randomPoses(120, mp.bounds_min, mp.bounds_max, 7)) {
        const GraspResult a = sat.simulate(p), b = epa.simulate(p);
        ASSERT_EQ(a.status, b.status);
        ASSERT_EQ(a.pose.position, b.pose.position);
        ASSERT_EQ(a.joints, b.joints);
        if (a.status != GraspStatus::kOk) continue;
        ++ok;
        // A pair Bullet's GJK calls apart can add a finger's contact (bench: 17 of 23,790
        // trials on meshes of 1000 faces or more, one of which changed status); not here.
        EXPECT_EQ(a.fingers_in_contact, b.fingers_in_contact);
        EXPECT_EQ(a.palm_contact, b.palm_contact);
        // How far each contact lies from the nearest contact of the same link under EPA.
        for (const Contact& ca : a.contacts) {
          double nearest = 1.0;
          for (const Contact& cb : b.contacts)
            if (cb.link == ca.link) nearest = std::min(nearest, (ca.point - cb.point).norm());
          moved.push_back(nearest);
        }
        const QualityResult qa = evaluateGrasp(a.contacts, mp.center_of_mass, mp.torque_scale);
        const QualityResult qb = evaluateGrasp(b.contacts, mp.center_of_mass, mp.torque_scale);
        fc_agree += qa.force_closure == qb.force_closure;
        if (qa.force_closure && qb.force_closure)
          rel.push_back(std::abs(qa.epsilon - qb.epsilon) / qb.epsilon);
      }
      std::sort(rel.begin(), rel.end());
      std::sort(moved.begin(), moved.end());
      auto q = [](const std::vector<double>& v, double f) {
        return v.empty() ? 0.0 : v[static_cast<std::size_t>(f * static_cast<double>(v.size() - 1))];
      };
      std::printf(
          "%d ok, force closure agrees on %d; epsilon relative difference q50 %.4f q90 %.4f max "
          "%.4f (%zu grasps); contact moved q50 %.2g q90 %.2g q99 %.2g m\n",
          ok, fc_agree, q(rel, 0.5), q(rel, 0.9), q(rel, 1.0), rel.size(), q(moved, 0.5),
          q(moved, 0.9), q(moved, 0.99));
      ASSERT_GT(ok, 10);
      // The documented tolerance (GraspSimDiagnostics::separating_axis_contacts): most contacts
      // equal up to rounding, the force-closure verdict kept on at least 97% of the grasps, epsilon
      // within 10% on nine in ten of the grasps both call force closure (Franka x banana: 4.3%).
      EXPECT_LT(q(moved, 0.5), 1e-12);
      EXPECT_GE(fc_agree, ok * 97 / 100);
      EXPECT_LT(q(rel, 0.9), 0.10);
    }
  }
}

}  // namespace
}  // namespace taskmap
