"""Dendrograms of taskmap's clustering equal scipy.cluster.hierarchy.linkage.

Runs the helper executable bin/taskmap_linkage_helper (tests/unit/clustering) on 2000
embedded, clustered poses and compares its linkage matrices with scipy's, for single,
average and complete linkage: merge distances within 1e-9 relative, same sizes, and the
same flat clusters at several cuts (ids may differ only where merge distances tie).

StoredCutTest builds a task map (basket x Barrett hand, 300 grasps) with the default
clustering and re-cuts it with scipy: fcluster on the stored dendrogram at the stored
threshold, and on scipy's own average linkage of the embedded poses (merge heights that differ
from ours by rounding, 1e-17), both give the stored labels once clusters below the stored
min_size are outliers. The stored threshold lies in the middle of the gap between two merge
heights (issue 30: it sat exactly on one, and scipy's linkage then split a cluster).
"""
import os
import subprocess
import tempfile
import unittest

import h5py
import numpy as np
from scipy.cluster.hierarchy import fcluster, linkage
from scipy.spatial.transform import Rotation

BUILD = os.environ.get("TASKMAP_BUILD_DIR", "")
HELPER = os.path.join(BUILD, "bin", "taskmap_linkage_helper")
CLI = os.environ.get("TASKMAP_CLI", "taskmap")
SOURCE = os.environ.get("TASKMAP_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))


def same_partition(a, b):
    """True when label vectors a and b describe the same partition."""
    pairs = set(zip(a.tolist(), b.tolist()))
    return len(pairs) == len(set(a.tolist())) == len(set(b.tolist()))


class ScipyLinkageTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not os.path.exists(HELPER):
            raise RuntimeError("helper not built: %s (target taskmap_linkage_helper)" % HELPER)
        cls.tmp = tempfile.TemporaryDirectory()
        cls.points_path = os.path.join(cls.tmp.name, "points.txt")
        subprocess.run([HELPER, "poses", "2000", "7", "0.1", cls.points_path], check=True)
        cls.points = np.loadtxt(cls.points_path)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def ours(self, method):
        out = os.path.join(self.tmp.name, method + ".txt")
        subprocess.run([HELPER, "linkage", method, self.points_path, out], check=True)
        return np.loadtxt(out)

    def test_points_are_embedded_poses(self):
        self.assertEqual(self.points.shape, (2000, 12))
        # Rotation part is (rho / sqrt 2) vec(R): each column of R has unit norm.
        rot = self.points[:, 3:].reshape(-1, 3, 3) / (0.1 / np.sqrt(2.0))
        np.testing.assert_allclose(np.linalg.norm(rot, axis=2), 1.0, atol=1e-12)

    def check(self, method):
        z_ours = self.ours(method)
        z_ref = linkage(self.points, method)
        n = len(self.points)
        self.assertEqual(z_ours.shape, (n - 1, 4))
        np.testing.assert_allclose(z_ours[:, 2], z_ref[:, 2], rtol=1e-9, atol=0)
        self.assertTrue(np.all(z_ours[:, 0] < z_ours[:, 1]), "smaller id first")
        self.assertTrue(np.all(np.diff(z_ours[:, 2]) >= 0))
        np.testing.assert_array_equal(z_ours[:, 3], z_ref[:, 3])
        for k in (2, 5, 40, 200, 1000):
            ours = fcluster(z_ours, k, criterion="maxclust")
            ref = fcluster(z_ref, k, criterion="maxclust")
            self.assertTrue(same_partition(ours, ref), "%s: partitions differ at k=%d" % (method, k))

    def test_single(self):
        self.check("single")

    def test_average(self):
        self.check("average")

    def test_complete(self):
        self.check("complete")

    def test_helper_rejects_unknown_method(self):
        out = os.path.join(self.tmp.name, "bad.txt")
        r = subprocess.run([HELPER, "linkage", "ward", self.points_path, out],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn("unknown linkage method 'ward'", r.stderr)


def embed(poses, rho):
    """Pose embedding of docs/METHOD.md section 4: (p, (rho / sqrt 2) vec(R)), poses N x 7 with
    x y z qw qx qy qz."""
    rot = Rotation.from_quat(poses[:, [4, 5, 6, 3]]).as_matrix()  # scipy: x y z w
    vec = rot.transpose(0, 2, 1).reshape(-1, 9)  # columns of R, as Eigen stores them
    return np.hstack([poses[:, :3], vec * (rho / np.sqrt(2.0))])


def with_outliers(raw, min_size):
    """Flat labels with clusters below min_size replaced by -1."""
    ids, counts = np.unique(raw, return_counts=True)
    small = set(ids[counts < min_size].tolist())
    return np.array([-1 if r in small else r for r in raw.tolist()])


def same_labelling(a, b):
    """True when a and b give the same partition with the same outliers (-1)."""
    if not np.array_equal(a == -1, b == -1):
        return False
    keep = a != -1
    return same_partition(a[keep], b[keep])


class StoredCutTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        path = os.path.join(cls.tmp.name, "basket.h5")
        subprocess.run([CLI, "build", "--object",
                        os.path.join(SOURCE, "meshes", "objects", "basket.obj"),
                        "--hand", "barrett", "--valid", "300", "--seed", "1", "--hold-test", "off", "--quiet",
                        "-o", path], check=True)
        with h5py.File(path, "r") as f:
            cls.z = f["clustering/linkage"][:]
            cls.labels = f["grasps/cluster"][:]
            cls.poses = f["grasps/pose"][:]
            attrs = f["clustering"].attrs
            cls.threshold = float(attrs["threshold"])
            cls.min_size = int(attrs["min_size"])
            cls.method = attrs["method"]
            cls.method = cls.method.decode() if isinstance(cls.method, bytes) else cls.method
            cls.rho = float(attrs["rotation_scale"])

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_default_min_size(self):
        self.assertEqual(self.min_size, max(3, int(np.ceil(0.03 * len(self.labels)))))
        ids, counts = np.unique(self.labels[self.labels >= 0], return_counts=True)
        self.assertGreaterEqual(len(ids), 2)
        self.assertTrue(np.all(counts >= self.min_size))

    def test_threshold_in_the_middle_of_a_gap(self):
        heights = self.z[:, 2]
        self.assertFalse(np.any(heights == self.threshold))
        below = heights[heights <= self.threshold]
        above = heights[heights > self.threshold]
        self.assertGreater(len(below), 0)
        self.assertGreater(len(above), 0)
        self.assertAlmostEqual(self.threshold, 0.5 * (below.max() + above.min()), delta=1e-15)

    def test_recut_stored_dendrogram(self):
        raw = fcluster(self.z, self.threshold, criterion="distance")
        self.assertTrue(same_labelling(with_outliers(raw, self.min_size), self.labels))

    def test_recut_scipy_linkage_of_the_poses(self):
        points = embed(self.poses, self.rho)
        z_ref = linkage(points, self.method)
        np.testing.assert_allclose(z_ref[:, 2], self.z[:, 2], rtol=1e-9, atol=1e-15)
        raw = fcluster(z_ref, self.threshold, criterion="distance")
        self.assertTrue(same_labelling(with_outliers(raw, self.min_size), self.labels))


if __name__ == "__main__":
    unittest.main()
