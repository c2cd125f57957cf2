"""Dendrograms of taskmap's clustering equal scipy.cluster.hierarchy.linkage.

Runs the helper executable bin/taskmap_linkage_helper (tests/unit/clustering) on 2000
embedded, clustered poses and compares its linkage matrices with scipy's, for single,
average and complete linkage: merge distances within 1e-9 relative, same sizes, and the
same flat clusters at several cuts (ids may differ only where merge distances tie).
"""
import os
import subprocess
import tempfile
import unittest

import numpy as np
from scipy.cluster.hierarchy import fcluster, linkage

BUILD = os.environ.get("TASKMAP_BUILD_DIR", "")
HELPER = os.path.join(BUILD, "bin", "taskmap_linkage_helper")


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


if __name__ == "__main__":
    unittest.main()
