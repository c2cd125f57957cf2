"""Cross-check of taskmap's grasp quality (qhull through libqhull_r) against scipy's
ConvexHull (scipy's own bundled qhull, triangulated output 'Qt'), on random grasps printed by
the quality_dump helper (tests/unit/quality/quality_dump.cpp)."""
import json
import os
import subprocess
import unittest

import numpy as np
from scipy.spatial import ConvexHull


def dump_path():
    build = os.environ.get("TASKMAP_BUILD_DIR", "")
    return os.path.join(build, "tests", "unit", "quality", "quality_dump")


class QualityScipyTest(unittest.TestCase):
    def setUp(self):
        self.exe = dump_path()
        if not os.path.exists(self.exe):
            self.fail("quality_dump not built at %s (set TASKMAP_BUILD_DIR, build target "
                      "quality_dump)" % self.exe)

    def test_epsilon_force_closure_and_volume_match_scipy(self):
        out = subprocess.run([self.exe, "7", "200"], check=True, capture_output=True,
                             text=True).stdout
        rows = [json.loads(line) for line in out.splitlines() if line.strip()]
        self.assertEqual(len(rows), 200)
        closures = 0
        for row in rows:
            w = np.array(row["wrenches"])
            self.assertEqual(w.shape[1], 6)
            if row["status"] == "degenerate":
                self.assertLess(np.linalg.matrix_rank(w - w.mean(axis=0), tol=1e-7 *
                                                      np.abs(w).max()), 6)
                continue
            self.assertEqual(row["status"], "ok", row["set"])
            hull = ConvexHull(w)  # scipy default options: Qt (plus Qx in 5-D and up)
            offsets = hull.equations[:, -1]  # normal . x + offset <= 0 inside
            scale = np.linalg.norm(w, axis=1).max()
            inside = bool(np.all(-offsets > 1e-10 * scale))
            self.assertEqual(row["force_closure"], inside, row["set"])
            if inside:
                closures += 1
                eps = float(np.min(-offsets))
                self.assertAlmostEqual(row["epsilon"], eps, delta=1e-9 * eps)
            else:
                self.assertEqual(row["epsilon"], 0.0)
            self.assertAlmostEqual(row["volume"], hull.volume, delta=1e-8 * hull.volume)
        self.assertGreater(closures, 20)
        self.assertLess(closures, 190)


if __name__ == "__main__":
    unittest.main()
