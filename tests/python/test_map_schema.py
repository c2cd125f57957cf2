"""Schema of a map built by `taskmap build`, read with Debian's h5py (mapstore/SCHEMA.md).

Builds a small map (box, panda hand, 6 grasps that hold, the default) with the CLI, then checks
every group,
dataset and attribute, their types, shapes and invariants; also checks that 1 and 8 threads
give identical files, and that corrupt or edited maps give a clear error from the CLI.
Strings are fixed-length (no HDF5 global heap): h5py returns them as bytes, hence text().
"""
import json
import os
import shutil
import subprocess
import tempfile
import unittest

import h5py
import numpy as np

CLI = os.environ.get("TASKMAP_CLI", "taskmap")
VALID = 6


def write_box_obj(path, sx=0.04, sy=0.05, sz=0.12):
    verts = [((sx / 2 if i & 1 else -sx / 2), (sy / 2 if i & 2 else -sy / 2),
              (sz / 2 if i & 4 else -sz / 2)) for i in range(8)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    with open(path, "w") as f:
        for v in verts:
            f.write("v %.6f %.6f %.6f\n" % v)
        for q in quads:
            f.write("f %d %d %d\n" % (q[0] + 1, q[1] + 1, q[2] + 1))
            f.write("f %d %d %d\n" % (q[0] + 1, q[2] + 1, q[3] + 1))


def text(value):
    """A string attribute as str (h5py returns fixed-length strings as bytes)."""
    return value.decode("utf-8") if isinstance(value, (bytes, np.bytes_)) else value


def build(out, obj, *extra, check=True):
    cmd = [CLI, "build", "--object", obj, "--hand", "panda", "--valid", str(VALID),
           "--seed", "3", "-o", out, *extra]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    if check and proc.returncode != 0:
        raise AssertionError("%s failed (%d): %s" % (" ".join(cmd), proc.returncode, proc.stderr))
    return proc


def datasets(f):
    out = {}
    f.visititems(lambda name, obj: out.__setitem__(name, obj[()])
                 if isinstance(obj, h5py.Dataset) else None)
    return out


class MapSchemaTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="taskmap_schema_")
        cls.obj = os.path.join(cls.tmp, "box.obj")
        write_box_obj(cls.obj)
        cls.map = os.path.join(cls.tmp, "box_panda.h5")
        build(cls.map, cls.obj, "--threads", "2")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_root_attributes(self):
        with h5py.File(self.map, "r") as f:
            self.assertEqual(text(f.attrs["format"]), "taskmap")
            self.assertEqual(int(f.attrs["schema_version"]), 2)
            self.assertEqual(f.attrs["schema_version"].dtype, np.int64)
            self.assertTrue(text(f.attrs["generator"]).startswith("taskmap "))
            self.assertEqual(text(f.attrs["created_utc"]), "")  # no wall clock by default
            self.assertEqual(f.userblock_size, 512)
        with open(self.map, "rb") as raw:
            self.assertTrue(raw.read(512).startswith(b"TASKMAP-SEAL 1\nsha256 "))

    def test_timestamp_only_on_request(self):
        out = os.path.join(self.tmp, "dated.h5")
        env = dict(os.environ, SOURCE_DATE_EPOCH="1700000000")
        proc = subprocess.run([CLI, "build", "--object", self.obj, "--hand", "panda", "--valid",
                               "3", "--seed", "3", "-o", out], capture_output=True, text=True,
                              timeout=600, env=env)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        with h5py.File(out, "r") as f:
            self.assertEqual(text(f.attrs["created_utc"]), "2023-11-14T22:13:20Z")
        build(out, self.obj, "--timestamp")
        with h5py.File(out, "r") as f:
            self.assertRegex(text(f.attrs["created_utc"]), r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ$")

    def test_object(self):
        with h5py.File(self.map, "r") as f:
            o = f["object"]
            v, fa = o["vertices"][()], o["faces"][()]
            self.assertEqual(v.dtype, np.float64)
            self.assertEqual(v.shape[1], 3)
            self.assertEqual(fa.dtype.kind, "i")
            self.assertEqual(fa.shape[1], 3)
            self.assertTrue((fa >= 0).all() and (fa < len(v)).all())
            self.assertEqual(text(o.attrs["name"]), "box")
            self.assertEqual(len(o.attrs["source_sha256"]), 64)
            self.assertEqual(o.attrs["scale"], 1.0)
            self.assertAlmostEqual(o.attrs["volume"], 0.04 * 0.05 * 0.12, places=7)
            np.testing.assert_allclose(o.attrs["center_of_mass"], [0, 0, 0], atol=1e-7)
            self.assertEqual(o.attrs["center_of_mass"].shape, (3,))
            expected_r = np.linalg.norm(v - o.attrs["center_of_mass"], axis=1).max()
            self.assertAlmostEqual(o.attrs["torque_scale"], expected_r, places=7)

    def test_hand(self):
        with h5py.File(self.map, "r") as f:
            h = f["hand"]
            self.assertTrue(h.attrs["name"])
            self.assertEqual(len(h.attrs["urdf_sha256"]), 64)
            names = list(h["joint_names"].asstr()[()])
            self.assertGreaterEqual(len(names), 1)
            self.assertEqual(f["grasps/joints"].shape[1], len(names))

    def test_sampling_and_quality(self):
        with h5py.File(self.map, "r") as f:
            s = f["sampling"]
            # No --sampler: the hand's default, antipodal_palm for the panda's parallel jaws.
            self.assertEqual(text(s.attrs["sampler"]), "antipodal_palm")
            self.assertEqual(int(s.attrs["seed"]), 3)
            trials = int(s.attrs["trials"])
            outcomes = {k[len("outcome_"):]: int(v) for k, v in s.attrs.items()
                        if k.startswith("outcome_")}
            self.assertEqual(sum(outcomes.values()), trials)
            self.assertEqual(outcomes["force_closure"], VALID)
            params = json.loads(s.attrs["params_json"])
            self.assertEqual(params["valid"], VALID)
            self.assertEqual(params["seed"], 3)
            self.assertEqual(params["sampler"], "antipodal_palm")
            self.assertEqual(params["object"], self.obj)
            self.assertNotIn("threads", params)  # the map does not depend on it
            q = f["quality"]
            self.assertEqual(q.attrs["friction"], 0.5)
            self.assertEqual(int(q.attrs["cone_edges"]), 8)
            self.assertEqual(text(q.attrs["contact_model"]), "point_with_friction")

    def test_grasps(self):
        with h5py.File(self.map, "r") as f:
            g = f["grasps"]
            pose = g["pose"][()]
            n = len(pose)
            self.assertEqual(n, VALID)
            self.assertEqual(pose.shape, (n, 7))
            self.assertEqual(pose.dtype, np.float64)
            np.testing.assert_allclose(np.linalg.norm(pose[:, 3:], axis=1), 1.0, atol=1e-9)
            self.assertTrue((pose[:, 3] >= 0).all())
            self.assertEqual(g["joints"].shape[0], n)
            fc = g["force_closure"][()]
            self.assertEqual(fc.dtype, np.uint8)
            self.assertTrue((fc == 1).all())
            eps = g["epsilon"][()]
            self.assertEqual(eps.shape, (n,))
            self.assertTrue((eps > 0).all())
            self.assertEqual(g["volume"].shape, (n,))
            # Not computed by default (docs/METHOD.md 4c): 0, and the params say so.
            self.assertTrue((g["volume"][()] == 0).all())

            params = json.loads(f["sampling"].attrs["params_json"])
            self.assertEqual(params["volume"], "never")
            off = g["contact_offsets"][()]
            self.assertEqual(off.dtype, np.int64)
            self.assertEqual(off.shape, (n + 1,))
            self.assertEqual(off[0], 0)
            self.assertTrue((np.diff(off) >= 2).all())  # force closure needs >= 2 contacts
            m = int(off[-1])
            self.assertEqual(g["contact_points"].shape, (m, 3))
            normals = g["contact_normals"][()]
            self.assertEqual(normals.shape, (m, 3))
            np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-6)
            self.assertEqual(g["contact_depths"].shape, (m,))
            self.assertTrue((g["contact_depths"][()] > 0).all())
            self.assertEqual(g["contact_links"].dtype, np.int32)
            self.assertEqual(g["contact_links"].shape, (m,))
            self.assertGreater(g.attrs["rotation_scale"], 0)
            self.assertEqual(int(g.attrs["contacts_available"]), 1)
            # Contact points lie on the box surface.
            p = np.abs(g["contact_points"][()])
            half = np.array([0.02, 0.025, 0.06])
            self.assertTrue((p <= half + 1e-6).all())
            self.assertTrue((np.abs(p - half) < 1e-6).any(axis=1).all())
            # Chunked, compressed and checksummed.
            self.assertEqual(g["pose"].compression, "gzip")
            self.assertTrue(g["pose"].shuffle)
            self.assertTrue(g["pose"].fletcher32)
            self.assertIsNotNone(g["pose"].chunks)

    def test_robust_hold_labels(self):
        # The default build tests every grasp in physics and keeps the robust ones, with labels.
        with h5py.File(self.map, "r") as f:
            g, v = f["grasps"], f["validation"]
            self.assertEqual(text(v.attrs["protocol"]), "dexgraspbench_fc")
            robust = json.loads(text(v.attrs["robust_json"]))
            names = robust["variants"]
            self.assertEqual(names[0], "nominal")
            self.assertIn("shift+z", names)
            self.assertEqual(robust["margin_translation"], 0.01)
            self.assertEqual(int(v.attrs["robust"]), VALID)
            self.assertEqual(g["robust"].dtype, np.uint8)
            self.assertTrue((g["robust"][()] == 1).all())
            self.assertTrue((g["hold"][()] == 1).all())
            np.testing.assert_array_equal(g["robust_share"][()], 1.0)
            self.assertEqual(g["robust_variants"].shape, (VALID, len(names)))
            self.assertTrue((g["robust_variants"][()] == 1).all())
            push = g["hold_push_translation"][()]
            self.assertTrue(((push >= 0) & (push < robust["margin_translation"])).all())
            params = json.loads(f["sampling"].attrs["params_json"])
            self.assertEqual(params["hold_test"], "robust")

    def test_clustering(self):
        with h5py.File(self.map, "r") as f:
            n = f["grasps/pose"].shape[0]
            labels = f["grasps/cluster"][()]
            self.assertEqual(labels.dtype, np.int32)
            self.assertEqual(labels.shape, (n,))
            c = f["clusters"]
            size = c["size"][()]
            k = len(size)
            self.assertGreaterEqual(k, 1)
            self.assertTrue(((labels >= -1) & (labels < k)).all())
            for j in range(k):
                self.assertEqual(size[j], (labels == j).sum())
                self.assertEqual(labels[c["representative"][j]], j)
                members = f["grasps/epsilon"][()][labels == j]
                self.assertAlmostEqual(c["best_epsilon"][j], members.max())
                self.assertAlmostEqual(c["mean_epsilon"][j], members.mean())
                pos = f["grasps/pose"][()][labels == j, :3]
                np.testing.assert_allclose(c["bounds_min"][j], pos.min(axis=0))
                np.testing.assert_allclose(c["bounds_max"][j], pos.max(axis=0))
            self.assertTrue((np.diff(size) <= 0).all())  # largest first
            self.assertEqual(c["mean_pose"].shape, (k, 7))
            lk = f["clustering/linkage"][()]
            self.assertEqual(lk.shape, (n - 1, 4))
            self.assertEqual(lk[-1, 3], n)
            a = f["clustering"].attrs
            self.assertEqual(text(a["method"]), "average")
            self.assertEqual(a["rotation_scale"], f["grasps"].attrs["rotation_scale"])
            self.assertGreater(a["threshold"], 0)
            self.assertGreaterEqual(int(a["min_size"]), 0)

    def test_same_bytes_for_one_and_two_threads(self):
        outs = [os.path.join(self.tmp, "bytes_%d.h5" % t) for t in (1, 2)]
        for threads, out in zip(("1", "2"), outs):
            proc = build(out, self.obj, "--threads", threads)
            self.assertIn("threads   %s" % threads, proc.stdout)
        with open(outs[0], "rb") as a, open(outs[1], "rb") as b:
            self.assertTrue(a.read() == b.read(), "1 and 2 threads gave different bytes")
        with open(self.map, "rb") as a, open(outs[0], "rb") as b:
            self.assertTrue(a.read() == b.read(), "same arguments gave different bytes")

    def test_same_datasets_for_one_and_eight_threads(self):
        maps = []
        for threads in ("1", "8"):
            out = os.path.join(self.tmp, "threads_%s.h5" % threads)
            build(out, self.obj, "--threads", threads)
            maps.append(out)
        with h5py.File(self.map, "r") as f2, h5py.File(maps[0], "r") as f1, \
                h5py.File(maps[1], "r") as f8:
            d2, d1, d8 = datasets(f2), datasets(f1), datasets(f8)
            self.assertEqual(sorted(d1), sorted(d2))
            for name in d1:
                np.testing.assert_array_equal(d1[name], d2[name], err_msg=name)
                np.testing.assert_array_equal(d1[name], d8[name], err_msg=name)
            self.assertEqual(f1["sampling"].attrs["trials"], f8["sampling"].attrs["trials"])

    def test_volume_on_request_leaves_the_grasps_alone(self):
        out = os.path.join(self.tmp, "with_volume.h5")
        build(out, self.obj, "--threads", "2", "--volume", "force_closure")
        with h5py.File(out, "r") as f, h5py.File(self.map, "r") as g:
            self.assertTrue((f["grasps/volume"][()] > 0).all())
            np.testing.assert_array_equal(f["grasps/pose"][()], g["grasps/pose"][()])
            np.testing.assert_array_equal(f["grasps/epsilon"][()], g["grasps/epsilon"][()])
            params = json.loads(f["sampling"].attrs["params_json"])
            self.assertEqual(params["volume"], "force_closure")
        proc = build(out, self.obj, "--volume", "sometimes", check=False)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("--volume", proc.stderr)

    def test_no_cluster_and_keep_invalid(self):
        out = os.path.join(self.tmp, "all.h5")
        build(out, self.obj, "--no-cluster", "--keep-invalid", "--sampler", "volume")
        with h5py.File(out, "r") as f:
            self.assertNotIn("clustering", f)
            self.assertNotIn("clusters", f)
            self.assertNotIn("cluster", f["grasps"])
            self.assertEqual(text(f["sampling"].attrs["sampler"]), "volume")
            fc = f["grasps/force_closure"][()]
            self.assertEqual(int(fc.sum()), VALID)
            s = f["sampling"].attrs
            self.assertEqual(len(fc), int(s["outcome_force_closure"]) +
                             int(s.get("outcome_not_force_closure", 0)) +
                             int(s.get("outcome_unbalanced", 0)) +
                             int(s.get("outcome_weak_squeeze", 0)) +
                             int(s.get("outcome_not_holding", 0)))

    def test_bad_arguments_give_clear_errors(self):
        out = os.path.join(self.tmp, "never.h5")
        proc = build(out, os.path.join(self.tmp, "missing.obj"), check=False)
        self.assertEqual(proc.returncode, 1)
        self.assertIn("taskmap: error:", proc.stderr)
        self.assertIn("missing.obj", proc.stderr)
        proc = build(out, self.obj, "--sampler", "sideways", check=False)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("sampler", proc.stderr)
        proc = build(os.path.join(self.tmp, "no", "dir", "m.h5"), self.obj, check=False)
        self.assertEqual(proc.returncode, 1)
        self.assertIn("does not exist", proc.stderr)
        self.assertFalse(os.path.exists(out))

    def corrupt(self, name, edit):
        out = os.path.join(self.tmp, name)
        shutil.copy(self.map, out)
        with h5py.File(out, "r+") as f:
            edit(f)
        return out

    def test_corrupt_maps_give_errors_naming_the_dataset(self):
        def nan_pose(f):
            f["grasps/pose"][2, 0] = np.nan

        def offsets(f):
            off = f["grasps/contact_offsets"][()]
            off[-1] += 50
            f["grasps/contact_offsets"][...] = off

        def newer(f):
            f.attrs["schema_version"] = np.int64(7)

        for name, edit, expected in (("nan.h5", nan_pose, "/grasps/pose"),
                                     ("offsets.h5", offsets, "/grasps/contact_offsets"),
                                     ("newer.h5", newer, "newer taskmap (schema 7); upgrade")):
            out = self.corrupt(name, edit)
            # Edited by h5py: refused by every reader until re-sealed on purpose ...
            proc = subprocess.run([CLI, "inspect", out], capture_output=True, text=True,
                                  timeout=60)
            self.assertEqual(proc.returncode, 1, proc.stderr)
            self.assertIn("taskmap: error:", proc.stderr)
            self.assertIn("changed by another tool", proc.stderr)
            self.assertIn("taskmap seal", proc.stderr)
            # ... and sealing validates it, naming what is wrong.
            proc = subprocess.run([CLI, "seal", out], capture_output=True, text=True, timeout=60)
            self.assertEqual(proc.returncode, 1, proc.stderr)
            self.assertIn(name, proc.stderr)
            self.assertIn(expected, proc.stderr)
            self.assertNotIn("HDF5-DIAG", proc.stderr)
        # A deliberate, valid edit is accepted once sealed.
        out = self.corrupt("renamed.h5", lambda f: f["object"].attrs.__setitem__("name", "crate"))
        self.assertEqual(subprocess.run([CLI, "seal", out], timeout=60).returncode, 0)
        proc = subprocess.run([CLI, "inspect", out], capture_output=True, text=True, timeout=60)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn("crate", proc.stdout)
        truncated = os.path.join(self.tmp, "truncated.h5")
        with open(self.map, "rb") as src, open(truncated, "wb") as dst:
            data = src.read()
            dst.write(data[: len(data) // 2])
        proc = subprocess.run([CLI, "inspect", truncated], capture_output=True, text=True,
                              timeout=60)
        self.assertEqual(proc.returncode, 1, proc.stderr)
        self.assertIn("taskmap: error:", proc.stderr)
        self.assertNotIn("HDF5-DIAG", proc.stderr)


if __name__ == "__main__":
    unittest.main()
