"""Clusters a person would name, on the paper's basket map (issue 30).

Reads the README's main map (basket x Barrett hand, grasps that hold robustly, seed 1; the
readme_map fixture of ctest builds it with tools/readme_map.args, else this test does) and labels
each grasp, independently of the clustering, by the parts of the basket its contacts touch:
the left bar, the right bar, the top bar of the handle, or the body (rim and walls). The
geometry is the one meshes/objects/basket.obj states in its header (and
meshes/objects/README.md): body 0.30 x 0.20 x 0.12 m centred on the origin in x and y, bars
0.02 x 0.02 m at x = +-0.146 rising from z = 0.08 to 0.28, top bar at z = 0.26 .. 0.279.

The default clustering must give between 3 and 12 clusters (issue 50: clusters a person would
name), none smaller than max(3, 3 % of the map), each lying on one handle part: at least 90 % of
its grasps touch the same part, and the left, right and top bars each carry one. The labelling
itself is tested on the mesh's own vertices and on hand-placed points.
"""
import collections
import math
import os
import subprocess
import tempfile
import unittest

import h5py
import numpy as np

CLI = os.environ.get("TASKMAP_CLI", "taskmap")
SOURCE = os.environ.get("TASKMAP_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))

# Basket geometry (metres), from the header of meshes/objects/basket.obj.
BAR_INNER_X = 0.136  # the side bars span |x| in [0.136, 0.156], |y| <= 0.01
BAR_HALF_Y = 0.01
BAR_BOTTOM_Z = 0.08  # the side bars rise from z = 0.08 (embedded in the end walls) to 0.28
TOP_BAR_Z = 0.26  # the top bar spans z in [0.26, 0.279], |y| <= 0.0095
TOP_BAR_HALF_Y = 0.0095
BODY_TOP_Z = 0.12  # the rim
TOL = 0.0015  # contacts lie on the surface up to the simulation's penetration


def part_of(point):
    """The basket part a surface point lies on: 'left', 'right', 'top' or 'body'.

    A point inside a side bar's extent (|x| >= 0.136, |y| <= 0.01, z >= 0.08, widened by TOL)
    is on that bar, its upper end above the top bar included; else a point at the top bar's
    height and width is on the top bar; everything else (walls, rim, bottom) is the body.
    """
    x, y, z = point
    if abs(x) >= BAR_INNER_X - TOL and abs(y) <= BAR_HALF_Y + TOL and z >= BAR_BOTTOM_Z - TOL:
        return "right" if x > 0 else "left"
    if z >= TOP_BAR_Z - TOL and abs(y) <= TOP_BAR_HALF_Y + TOL:
        return "top"
    return "body"


def parts_touched(points):
    """Set of basket parts touched by a grasp's contact points."""
    return frozenset(part_of(p) for p in points)


def cluster_purity(labels, touched):
    """Per cluster id: (size, the part touched by most of its grasps, share touching it)."""
    out = {}
    for c in sorted(set(labels.tolist()) - {-1}):
        idx = np.flatnonzero(labels == c)
        count = collections.Counter(p for i in idx for p in touched[i])
        part, hits = count.most_common(1)[0]
        out[c] = (len(idx), part, hits / len(idx))
    return out


class PartLabellingTest(unittest.TestCase):
    def test_hand_placed_points(self):
        self.assertEqual(part_of((-0.146, 0.0, 0.2)), "left")
        self.assertEqual(part_of((0.156, 0.01, 0.2)), "right")
        self.assertEqual(part_of((0.155, 0.0, 0.09)), "right")  # bar outside the end wall
        self.assertEqual(part_of((0.137, 0.005, 0.1)), "right")  # bar inside the end wall
        self.assertEqual(part_of((-0.15, 0.0, 0.28)), "left")  # upper end of the bar
        self.assertEqual(part_of((0.0, 0.0095, 0.27)), "top")
        self.assertEqual(part_of((0.1, 0.0, 0.279)), "top")
        self.assertEqual(part_of((0.1, 0.1, 0.12)), "body")  # rim
        self.assertEqual(part_of((0.15, 0.05, 0.1)), "body")  # end wall beside the bar
        self.assertEqual(part_of((0.15, 0.0, 0.06)), "body")  # end wall below the bar
        self.assertEqual(part_of((0.0, -0.1, 0.0)), "body")
        self.assertEqual(parts_touched([(0.0, 0.0, 0.279), (0.146, 0.01, 0.27)]),
                         frozenset({"top", "right"}))

    def test_mesh_vertices(self):
        # Above the rim the basket is only its handle; below it, the bars lie within
        # |y| <= 0.01 and every other vertex is the body.
        path = os.path.join(SOURCE, "meshes", "objects", "basket.obj")
        with open(path) as f:
            verts = np.array([list(map(float, line.split()[1:4])) for line in f
                              if line.startswith("v ")])
        parts = [part_of(v) for v in verts]
        for v, p in zip(verts, parts):
            if v[2] > BODY_TOP_Z + TOL:
                self.assertNotEqual(p, "body", v)
            if abs(v[1]) > BAR_HALF_Y + TOL:
                self.assertEqual(p, "body", v)
        count = collections.Counter(parts)
        self.assertEqual(count["left"], count["right"])  # the mesh is mirror-symmetric in x
        # (The top bar is a box between the side bars: its vertices are where it meets them.)
        for p in ("left", "right", "body"):
            self.assertGreater(count[p], 0, p)


class BasketClustersTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        with open(os.path.join(SOURCE, "tools", "readme_map.args")) as f:
            cls.args = f.read().split()
        cls.map_path = os.environ.get("TASKMAP_BASKET_MAP")
        if not cls.map_path or not os.path.exists(cls.map_path):
            cls.map_path = os.path.join(cls.tmp.name, "basket.h5")
            r = subprocess.run([CLI, "build"] + cls.args + ["-o", cls.map_path],
                               capture_output=True, text=True, cwd=SOURCE)
            if r.returncode != 0:
                raise RuntimeError("taskmap build failed: " + r.stderr)
        with h5py.File(cls.map_path, "r") as f:
            cls.labels = f["grasps/cluster"][:]
            points = f["grasps/contact_points"][:]
            offsets = f["grasps/contact_offsets"][:]
            cls.min_size = int(f["clustering"].attrs["min_size"])
        cls.touched = [parts_touched(points[offsets[i]:offsets[i + 1]])
                       for i in range(len(cls.labels))]

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_every_grasp_touches_the_basket(self):
        self.assertEqual(len(self.labels), int(self.args[self.args.index("--valid") + 1]))
        self.assertTrue(all(self.touched))

    def test_cluster_count_and_sizes(self):
        n = len(self.labels)
        self.assertEqual(self.min_size, max(3, math.ceil(0.03 * n)))
        ids = set(self.labels.tolist()) - {-1}
        self.assertGreaterEqual(len(ids), 3)
        self.assertLessEqual(len(ids), 12)
        for c in ids:
            self.assertGreaterEqual(int((self.labels == c).sum()), self.min_size)
        self.assertLessEqual(int((self.labels == -1).sum()), 0.1 * n)

    def test_each_cluster_lies_on_one_handle_part(self):
        purity = cluster_purity(self.labels, self.touched)
        for c, (size, part, share) in purity.items():
            self.assertGreaterEqual(share, 0.9, "cluster %d (%d grasps): %.0f %% on %s" %
                                    (c, size, 100 * share, part))
        # The three bars of the handle each carry a cluster (the paper's left, right, top).
        self.assertTrue({"left", "right", "top"} <= {p for _, p, _ in purity.values()})

    def test_purity_test_can_fail(self):
        # All grasps as one cluster: no part is touched by 90 % of them.
        purity = cluster_purity(np.zeros(len(self.labels), dtype=int), self.touched)
        self.assertLess(purity[0][2], 0.9)


if __name__ == "__main__":
    unittest.main()
