"""ACRONYM interoperability of `taskmap import` / `taskmap export --format acronym` with h5py.

An ACRONYM-style grasp file is written the way the dataset's own files are (h5py, string and
scalar datasets), imported as a task map, inspected, exported back and read with the access
pattern of NVlabs/acronym's acronym_tools (load_grasps, load_mesh).
"""
import json
import os
import subprocess
import tempfile
import unittest

import h5py
import numpy as np
from scipy.spatial.transform import Rotation

CLI = os.environ.get("TASKMAP_CLI", "taskmap")
SOURCE = os.environ.get("TASKMAP_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BOX = os.path.join(SOURCE, "meshes", "objects", "box.obj")


def run(*args):
    return subprocess.run([CLI, *args], capture_output=True, text=True)


def write_acronym_like(path, n, seed=4):
    """Grasps around the box, roughly half successful, as h5py writes ACRONYM files."""
    rng = np.random.default_rng(seed)
    # Three groups (above, right, left of the box) with similar orientations within a group,
    # so that clustering has something to find.
    group = np.arange(n) % 3
    centres = np.array([[0.0, 0.0, 0.2], [0.1, 0.0, 0.06], [-0.1, 0.0, 0.06]])
    bases = Rotation.from_euler("y", [180.0, -90.0, 90.0], degrees=True)
    jitter = Rotation.from_rotvec(0.1 * rng.standard_normal((n, 3)))
    t = np.zeros((n, 4, 4))
    t[:, :3, :3] = (bases[group] * jitter).as_matrix()
    t[:, :3, 3] = centres[group] + 0.005 * rng.standard_normal((n, 3))
    t[:, 3, 3] = 1.0
    success = (rng.random(n) < 0.5).astype(np.int64)
    with h5py.File(path, "w") as f:
        f["grasps/transforms"] = t
        f["grasps/qualities/flex/object_in_gripper"] = success
        f["object/file"] = "meshes/Box/box.obj"
        f["object/scale"] = 1.0
        f["object/mass"] = 0.2
        f["object/density"] = 350.0
        f["object/friction"] = 0.8
        f["object/com"] = np.array([0.0, 0.0, 0.06])
        f["gripper/type"] = "franka_panda"
        f["gripper/configuration"] = np.array([0.04, 0.04])
    return t, success


class AcronymInteropTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def path(self, name):
        return os.path.join(self.dir, name)

    def test_import_inspect_export_round_trip(self):
        src = self.path("Box_abc_1.0.h5")
        t, success = write_acronym_like(src, 90)
        r = run("import", "--acronym", src, "--object", BOX, "-o", self.path("map.h5"))
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)

        r = run("inspect", "--json", self.path("map.h5"))
        self.assertEqual(r.returncode, 0, r.stderr)
        summary = json.loads(r.stdout)
        self.assertEqual(summary["grasps"]["count"], 90)
        self.assertEqual(summary["grasps"]["force_closure"], int(success.sum()))
        self.assertFalse(summary["grasps"]["contacts_available"])
        self.assertEqual(summary["hand"]["name"], "franka_panda")
        self.assertEqual(summary["sampling"]["outcomes"],
                         {"force_closure": int(success.sum()),
                          "not_force_closure": int(90 - success.sum())})
        self.assertIsNotNone(summary["clustering"])
        sizes = [c["size"] for c in summary["clustering"]["clusters"]]
        self.assertEqual(sum(sizes) + summary["clustering"]["outliers"], 90)
        self.assertEqual(len(sizes), 3)

        out = self.path("Box_back.h5")
        r = run("export", self.path("map.h5"), "--format", "acronym", "-o", out,
                "--object-file", "meshes/Box/box.obj", "--density", "350")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        # acronym_tools.load_grasps / load_mesh access pattern.
        data = h5py.File(out, "r")
        back_t = np.array(data["grasps/transforms"])
        back_s = np.array(data["grasps/qualities/flex/object_in_gripper"])
        self.assertEqual(back_t.shape, (90, 4, 4))
        np.testing.assert_allclose(back_t, t, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(back_s, success)
        self.assertEqual(data["object/file"][()], b"meshes/Box/box.obj")
        self.assertEqual(data["object/scale"][()], 1.0)
        self.assertEqual(data["object/density"][()], 350.0)
        self.assertEqual(data["object/friction"][()], 0.8)
        volume = 0.06 * 0.08 * 0.12
        self.assertAlmostEqual(data["object/volume"][()], volume, delta=1e-9)
        self.assertAlmostEqual(data["object/mass"][()], 350.0 * volume, delta=1e-6)
        self.assertEqual(data["object/inertia"].shape, (3, 3))
        np.testing.assert_allclose(data["object/com"][()], [0.0, 0.0, 0.06], atol=1e-9)
        self.assertEqual(data["gripper/type"][()], b"franka_panda")
        data.close()

    def test_python_import_writes_the_cli_bytes(self):
        import taskmap
        src = self.path("Box_abc_1.0.h5")
        write_acronym_like(src, 60)
        r = run("import", "--acronym", src, "--object", BOX, "-o", self.path("cli.h5"),
                "--successful-only", "--clusters", "3")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        m = taskmap.import_acronym(acronym=src, object=BOX, output=self.path("py.h5"),
                                   successful_only=True, clusters=3)
        with open(self.path("cli.h5"), "rb") as a, open(self.path("py.h5"), "rb") as b:
            self.assertEqual(a.read(), b.read())
        self.assertEqual(m.num_clusters, 3)
        with self.assertRaisesRegex(taskmap.Error, "would destroy the input"):
            taskmap.import_acronym(acronym=src, object=BOX, output=src)

    def test_python_import_with_a_hand_closes_its_jaws_and_validates(self):
        """With the real Franka hand the import closes the jaws at each pose (the CLI's bytes),
        records the hand, and taskmap.validate tests the map with the jaws closing from open."""
        import taskmap
        franka = os.path.join(SOURCE, "tests", "data", "real", "hands", "franka_hand",
                              "franka_hand.urdf")
        # Gripper base frames above the 6 cm x 8 cm box, approach down, jaws along x: the pads
        # (5.84 cm + 3.6 to 5.45 cm from the base) on its upper part; the third 40 cm higher.
        rot = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
        t = np.tile(np.eye(4), (3, 1, 1))
        t[:, :3, :3] = rot
        t[:, :3, 3] = [[0.0, 0.0, 0.2084], [0.008, 0.0, 0.2084], [0.0, 0.0, 0.4584]]
        src = self.path("Box_franka_1.0.h5")
        with h5py.File(src, "w") as f:
            f["grasps/transforms"] = t
            f["grasps/qualities/flex/object_in_gripper"] = np.array([1, 1, 0])
            f["object/file"] = "meshes/Box/box.obj"
            f["object/scale"] = 1.0
            f["gripper/type"] = "panda"
        r = run("import", "--acronym", src, "--object", BOX, "--hand", franka, "-o",
                self.path("cli.h5"))
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        m = taskmap.import_acronym(acronym=src, object=BOX, output=self.path("py.h5"),
                                   hand=franka)
        with open(self.path("cli.h5"), "rb") as a, open(self.path("py.h5"), "rb") as b:
            self.assertEqual(a.read(), b.read())
        self.assertEqual(len(m), 2)  # the third grasp's jaws close on nothing: dropped
        with h5py.File(self.path("py.h5"), "r") as f:
            np.testing.assert_allclose(f["grasps/joints"][:, 0], [0.03002, 0.03002], atol=1e-9)
        s = taskmap.validate(self.path("py.h5"), grasps=1, threads=1, output=self.path("v.h5"))
        self.assertEqual(s["tested"], 1)
        self.assertTrue(s["close_from_open"])

    def test_successful_only_and_bad_files(self):
        src = self.path("grasps.h5")
        _, success = write_acronym_like(src, 30)
        r = run("import", "--acronym", src, "--object", BOX, "-o", self.path("ok.h5"),
                "--successful-only", "--no-cluster")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        summary = json.loads(run("inspect", "--json", self.path("ok.h5")).stdout)
        self.assertEqual(summary["grasps"]["count"], int(success.sum()))
        self.assertIsNone(summary["clustering"])

        with h5py.File(self.path("bad.h5"), "w") as f:
            f["grasps/transforms"] = np.zeros((4, 3, 3))
            f["grasps/qualities/flex/object_in_gripper"] = np.zeros(4)
        r = run("import", "--acronym", self.path("bad.h5"), "--object", BOX, "-o",
                self.path("x.h5"))
        self.assertEqual(r.returncode, 1)
        self.assertIn("grasps/transforms should have shape N x 4 x 4", r.stderr)
        self.assertFalse(os.path.exists(self.path("x.h5")))


if __name__ == "__main__":
    unittest.main()
