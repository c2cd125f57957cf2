"""Python bindings of the reaching stage: model, forward kinematics, Jacobians, rollout."""
import os
import unittest

import numpy as np

import taskmap

SRC = os.environ.get("TASKMAP_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
READY = np.array([0.0, -np.pi / 4, 0.0, -3 * np.pi / 4, 0.0, np.pi / 2, np.pi / 4])
SIDE_GRASP = np.array([-0.07, 0.0, 0.02, np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0])


def panda():
    robot = taskmap.Robot.panda_with_humanoid_hand(os.path.join(SRC, "reaching", "robots"),
                                                   os.path.join(SRC, "meshes", "hands"))
    robot.add_scene()
    return robot


class ReachingTest(unittest.TestCase):
    def test_model_and_forward_kinematics(self):
        robot = panda()
        self.assertEqual(robot.dofs, 7)
        self.assertEqual(robot.dof_names[0], "fer_joint1")
        self.assertEqual(robot.object, "object")
        poses = robot.forward_kinematics(READY)
        self.assertEqual(len(poses), len(robot.body_names))
        flange = poses[robot.body_names.index("fer_link8")]
        self.assertEqual(flange.shape, (4, 4))
        np.testing.assert_allclose(flange[:3, :3] @ flange[:3, :3].T, np.eye(3), atol=1e-12)
        # Ready pose: the flange is in front of the base, above the table, pointing down.
        self.assertGreater(flange[0, 3], 0.25)
        self.assertGreater(flange[2, 3], 0.3)
        self.assertLess(flange[2, 2], -0.99)

    def test_jacobian_matches_finite_differences(self):
        robot = panda()
        names = robot.body_names
        q = READY + 0.1
        j = robot.jacobian(q, "palm", "fer_link2")
        self.assertEqual(j.shape, (6, 7))
        link2, palm = names.index("fer_link2"), names.index("palm")

        def rel(qq):
            t = robot.forward_kinematics(qq)
            return np.linalg.inv(t[link2]) @ t[palm]
        h = 1e-6
        for i in range(7):
            dq = np.zeros(7)
            dq[i] = h
            fd = (rel(q + dq)[:3, 3] - rel(q - dq)[:3, 3]) / (2 * h)
            np.testing.assert_allclose(j[:3, i], fd, atol=1e-7)

    def test_reach_side_grasp(self):
        robot = panda()
        r = taskmap.reach(robot, SIDE_GRASP, q0=READY)
        self.assertEqual(r["status"], "reached", r["message"])
        self.assertEqual(r["q"].shape, (301, 7))
        self.assertLess(r["position_error"], 1e-3)
        self.assertGreater(r["min_clearance"], 0.0)
        self.assertTrue(np.all(r["q"] >= robot.lower - 1e-12))
        self.assertTrue(np.all(r["q"] <= robot.upper + 1e-12))

    def test_plan_grasp_with_a_map(self):
        robot = panda()
        # Side grasps of the default object, 1 cm apart in height: two clusters (below, above).
        poses = np.array([SIDE_GRASP + np.array([0, 0, dz, 0, 0, 0, 0])
                          for dz in np.linspace(-0.03, 0.03, 12)])
        labels = [0 if p[2] < 0.02 else 1 for p in poses]
        eps = np.linspace(0.05, 0.2, 12)
        m = taskmap.TaskMap.from_arrays(poses, eps, labels)
        r = taskmap.plan_grasp(robot, m, q0=READY, iterations=5)
        self.assertIn(r["status"], ("planned", "unsafe"), r["message"])
        self.assertEqual(len(r["cost_history"]), r["iterations"] + 1)
        self.assertLess(r["cost_history"][-1], r["cost_history"][0])
        self.assertEqual(r["q"].shape, (301, 7))
        self.assertIn(r["cluster"], (0, 1))
        self.assertTrue(r["collision_free"])
        with self.assertRaises(ValueError):
            bare = taskmap.Robot.panda_with_humanoid_hand(os.path.join(SRC, "reaching", "robots"),
                                                          os.path.join(SRC, "meshes", "hands"))
            taskmap.plan_grasp(bare, m)

    def test_reach_with_a_map_returns_the_cli_report(self):
        robot = panda()
        poses = np.array([SIDE_GRASP + np.array([0, 0, dz, 0, 0, 0, 0])
                          for dz in np.linspace(-0.03, 0.03, 12)])
        labels = [0 if p[2] < 0.02 else 1 for p in poses]
        m = taskmap.TaskMap.from_arrays(poses, np.linspace(0.05, 0.2, 12), labels)
        r = taskmap.reach(robot, m, q0=READY, iterations=4, steps=250)
        self.assertIn(r["status"], ("planned", "unsafe"), r["message"])
        # A map from arrays has no hand or object: not re-simulated unless asked, then refused.
        self.assertNotIn("resimulated", r)
        with self.assertRaisesRegex(taskmap.Error, "cannot re-simulate"):
            taskmap.reach(robot, m, q0=READY, iterations=4, steps=250, resimulate=True)
        for key in ("iterations", "iterations_to_manifold", "iterations_to_quality", "cluster",
                    "grasp_index", "min_clearance_m", "joint_limit_margin_rad", "collision_free",
                    "ms_per_iteration", "ms_per_plan", "ranking", "plans", "q_final"):
            self.assertIn(key, r)
        self.assertEqual(r["q"].shape, (251, 7))
        np.testing.assert_array_equal(r["q"][-1], r["q_final"])
        np.testing.assert_array_equal(r["q"][0], READY)
        history = r["cost_history"]
        self.assertEqual(len(history), r["iterations"] + 1)
        self.assertLess(history[-1]["total"], history[0]["total"])
        self.assertEqual(len(r["proximity_over_movement"]), 251)
        self.assertEqual(len(r["quality_over_movement"]), 251)
        # The plan ends on its sample (docs/REACHING.md "Ending on the sample"): the last step's
        # proximity term is 0 there, no more than the optimiser's last iteration left.
        self.assertTrue(r["plans"][0]["ends_on_sample"])
        self.assertAlmostEqual(r["proximity_over_movement"][-1], 0.0, delta=1e-9)
        self.assertLessEqual(r["proximity_over_movement"][-1], history[-1]["proximity"] + 1e-12)
        self.assertGreater(r["proximity_over_movement"][0], r["proximity_over_movement"][-1])
        # The fixed-target reach keeps its signature.
        self.assertEqual(taskmap.reach(robot, SIDE_GRASP, q0=READY, steps=50)["q"].shape, (51, 7))

    def test_reach_with_the_reference_map_resimulates_and_tests_the_hold(self):
        # The checked-in map (humanoid hand, basket, grasps that hold): the final palm pose is
        # re-simulated with the map's own hand, object and options and held in physics, as
        # `taskmap reach --map ... --hold-test` reports it.
        robot = taskmap.Robot.panda_with_humanoid_hand(os.path.join(SRC, "reaching", "robots"),
                                                       os.path.join(SRC, "meshes", "hands"))
        robot.add_scene(os.path.join(SRC, "reaching", "scenes", "basket_reference.json"))
        m = taskmap.load(os.path.join(SRC, "meshes", "maps", "basket_humanoid.h5"))
        r = taskmap.reach(robot, m, q0=READY, iterations=3, resimulate=True, hold_test=True)
        self.assertEqual(r["status"], "planned", r["message"])
        res = r["resimulated"]
        self.assertEqual(res["outcome"], "ok", res["message"])
        for key in ("force_closure", "epsilon", "contacts", "fingers", "start", "final", "hand"):
            self.assertIn(key, res)
        np.testing.assert_allclose(res["start"][:3], res["final"][:3], atol=0.01)
        self.assertIn(res["hold"]["holds"], (True, False))
        self.assertGreaterEqual(res["hold"]["max_translation_m"], 0.0)
        # As the CLI: a built map is re-simulated by default, without the hold test.
        self.assertNotIn("hold", taskmap.reach(robot, m, q0=READY, iterations=1)["resimulated"])
        self.assertNotIn("resimulated", taskmap.reach(robot, m, q0=READY, iterations=1,
                                                      resimulate=False))
        with self.assertRaisesRegex(taskmap.Error, "drop resimulate=False"):
            taskmap.reach(robot, m, q0=READY, iterations=1, resimulate=False, hold_test=True)

    def test_errors_are_value_errors(self):
        robot = panda()
        with self.assertRaises(taskmap.Error):
            robot.forward_kinematics(np.zeros(3))
        with self.assertRaisesRegex(ValueError, "no body 'elbow'"):
            robot.jacobian(READY, "elbow")
        with self.assertRaisesRegex(ValueError, "dt"):
            taskmap.reach(robot, SIDE_GRASP, q0=READY, dt=0.0)


if __name__ == "__main__":
    unittest.main()
