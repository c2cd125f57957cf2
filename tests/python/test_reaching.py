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
