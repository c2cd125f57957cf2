"""taskmap.validate: the physics hold test from Python, the same labels as the command line."""
import json
import os
import subprocess
import tempfile
import unittest

import h5py
import numpy as np

import taskmap

CLI = os.environ["TASKMAP_CLI"]
SRC = os.environ["TASKMAP_SOURCE_DIR"]


class ValidateTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.map = os.path.join(cls.dir.name, "box.h5")
        subprocess.run([CLI, "build", "--object", os.path.join(SRC, "meshes/objects/box.obj"),
                        "--hand", "panda", "--valid", "6", "--seed", "5", "--hold-test", "off", "-q", "-o",
                        cls.map],
                       check=True)

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_labels_match_the_command_line(self):
        py_out = os.path.join(self.dir.name, "py.h5")
        cli_out = os.path.join(self.dir.name, "cli.h5")
        s = taskmap.validate(self.map, output=py_out, grasps=4, threads=1)
        report = json.loads(subprocess.run(
            [CLI, "validate", self.map, "--grasps", "4", "--json", "-o", cli_out],
            check=True, capture_output=True, text=True).stdout)
        self.assertEqual(s["tested"], 4)
        self.assertEqual(sum(s["statuses"].values()), 4)
        # One summary for both front ends: the same keys, the same counts.
        self.assertEqual(set(report) - {"map", "output"}, set(s))
        for key in ("tested", "holding", "statuses", "slipped_by_direction", "object_pieces"):
            self.assertEqual(report[key], s[key], key)
        with h5py.File(py_out, "r") as a, h5py.File(cli_out, "r") as b:
            hold = a["grasps/hold"][:]
            np.testing.assert_array_equal(hold, b["grasps/hold"][:])
            np.testing.assert_array_equal(a["grasps/hold_translation"][:],
                                          b["grasps/hold_translation"][:])
            self.assertTrue(set(hold.tolist()) <= {0, 1, 255})
            self.assertEqual(int((hold == 1).sum()), s["holding"])
            self.assertEqual(int((hold == 255).sum()), 2)
            self.assertEqual(a["validation"].attrs["protocol"], b"dexgraspbench_fc")
        # The labelled map reads back through the verified reader.
        self.assertEqual(len(taskmap.load(py_out)), 6)

    def test_robust_labels_match_the_command_line(self):
        py_out = os.path.join(self.dir.name, "robust_py.h5")
        cli_out = os.path.join(self.dir.name, "robust_cli.h5")
        s = taskmap.validate(self.map, output=py_out, grasps=2, threads=1, robust=True)
        report = json.loads(subprocess.run(
            [CLI, "validate", self.map, "--grasps", "2", "--robust", "--json", "-o", cli_out],
            check=True, capture_output=True, text=True).stdout)
        for key in ("robust", "variant_failures", "holding"):
            self.assertEqual(report[key], s[key], key)
        m = taskmap.load(py_out)
        names = m.robust_params["variants"]
        self.assertEqual(names[0], "nominal")
        self.assertEqual(m.robust_variants.shape, (6, len(names)))
        np.testing.assert_array_equal(m.robust[2:], 255)  # grasps 2.. not tested
        self.assertEqual(int((m.robust == 1).sum()), s["robust"])
        self.assertTrue(((m.robust_share[:2] >= 0) & (m.robust_share[:2] <= 1)).all())
        self.assertEqual(m.hold_margin.shape, (6, 2))
        with h5py.File(py_out, "r") as a, h5py.File(cli_out, "r") as b:
            np.testing.assert_array_equal(a["grasps/robust_variants"][:],
                                          b["grasps/robust_variants"][:])
            np.testing.assert_array_equal(a["grasps/hold_push_translation"][:],
                                          b["grasps/hold_push_translation"][:])
        # A map without robust labels has none to show.
        self.assertIsNone(taskmap.load(self.map).robust)

    def test_trace_is_the_command_lines(self):
        t = taskmap.trace_hold(self.map, 0)
        cli = json.loads(subprocess.run([CLI, "validate", self.map, "--trace", "0", "--json"],
                                        check=True, capture_output=True, text=True).stdout)
        self.assertEqual(t, cli)
        self.assertEqual(t["samples"][0]["phase"], "closing")
        self.assertIn(t["status"], ("holds", "slipped", "lost_in_closing", "penetration"))
        with self.assertRaises(taskmap.Error) as e:
            taskmap.trace_hold(self.map, 6)
        self.assertIn("is not in the map", str(e.exception))

    def test_refuses_a_file_that_is_not_a_map(self):
        junk = os.path.join(self.dir.name, "junk.h5")
        with open(junk, "w") as f:
            f.write("not a map")
        with self.assertRaises(taskmap.Error) as e:
            taskmap.validate(junk)
        self.assertIn("junk.h5", str(e.exception))


if __name__ == "__main__":
    unittest.main()
