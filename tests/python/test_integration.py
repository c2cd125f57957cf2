"""The Python bindings of the run-time query library (issue 7), with Debian's python3.

Maps come from taskmap.TaskMap.from_arrays (synthetic grasps on three bars), from its save()
(writeMap) and, when the CLI can build maps, from `taskmap build ... --valid 30`.
"""
import json
import os
import shutil
import subprocess
import tempfile
import threading
import unittest

import numpy as np

import taskmap

RHO = 0.1


def rotation_matrix(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def embed(poses, rho=RHO):
    """(p, rho/sqrt2 vec(R)) with vec stacking columns, as taskmap::embedPose."""
    out = np.empty((len(poses), 12))
    for i, p in enumerate(poses):
        out[i, :3] = p[:3]
        out[i, 3:] = rotation_matrix(p[3:]).T.reshape(9) * rho / np.sqrt(2)
    return out


def random_quaternions(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def synthetic(rng, n):
    """Grasps around three bars (a basket handle), labels = bar, epsilons in [0, 0.3]."""
    centres = np.array([[-0.15, 0, 0.15], [0.15, 0, 0.15], [0, 0, 0.30]])
    axes = np.array([[0, 0, 1.0], [0, 0, 1.0], [1.0, 0, 0]])
    poses = np.empty((n, 7))
    labels = np.arange(n) % 3
    for i in range(n):
        b = labels[i]
        a = axes[b]
        u = np.cross(a, [0, 1.0, 0]) if abs(a[1]) < 0.9 else np.cross(a, [1.0, 0, 0])
        u /= np.linalg.norm(u)
        v = np.cross(a, u)
        phi = rng.uniform(0, 2 * np.pi)
        radial = np.cos(phi) * u + np.sin(phi) * v
        poses[i, :3] = centres[b] + rng.uniform(-0.1, 0.1) * a + 0.06 * radial + 0.003 * rng.normal(size=3)
        r = np.column_stack([a, np.cross(-radial, a), -radial])
        # quaternion of r (trace method, r is a proper rotation)
        w = np.sqrt(max(0.0, 1 + np.trace(r))) / 2
        if w > 1e-3:
            q = np.array([w, (r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w), (r[1, 0] - r[0, 1]) / (4 * w)])
        else:
            k = int(np.argmax(np.diag(r)))
            i1, i2 = (k + 1) % 3, (k + 2) % 3
            s = np.sqrt(1 + r[k, k] - r[i1, i1] - r[i2, i2]) * 2
            q = np.zeros(4)
            q[0] = (r[i2, i1] - r[i1, i2]) / s
            q[1 + k] = s / 4
            q[1 + i1] = (r[i1, k] + r[k, i1]) / s
            q[1 + i2] = (r[i2, k] + r[k, i2]) / s
        q += 0.02 * rng.normal(size=4)
        poses[i, 3:] = q / np.linalg.norm(q)
    eps = np.where(rng.uniform(size=n) < 0.1, 0.0, rng.uniform(0, 0.3, size=n))
    return poses, eps, labels


def queries(rng, m, n):
    """Near-map and random poses; every other quaternion negated."""
    base = m.poses[rng.integers(0, len(m), size=n)].copy()
    base[:, :3] += m.position_sigma * rng.normal(size=(n, 3))
    base[:, 3:] += 0.02 * rng.normal(size=(n, 4))
    far = rng.uniform(size=n) < 0.2
    base[far, :3] = rng.uniform(-0.3, 0.3, size=(far.sum(), 3))
    base[far, 3:] = random_quaternions(rng, far.sum())
    base[:, 3:] /= np.linalg.norm(base[:, 3:], axis=1, keepdims=True)
    base[1::2, 3:] *= -1
    return base


class IntegrationTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.rng = np.random.default_rng(1)
        cls.poses, cls.eps, cls.labels = synthetic(cls.rng, 1500)
        cls.map = taskmap.TaskMap.from_arrays(cls.poses, cls.eps, labels=cls.labels.tolist(), rotation_scale=RHO)
        cls.tmp = tempfile.mkdtemp(prefix="taskmap_integration_")
        cls.emb = embed(cls.map.poses)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_nearest_knn_radius_equal_numpy_brute_force(self):
        m = self.map
        qs = queries(self.rng, m, 1000)
        d = np.linalg.norm(embed(qs)[:, None, :] - self.emb[None, :, :], axis=2)
        r = 2 * m.position_sigma
        hits = 0
        for i, q in enumerate(qs):
            order = np.argsort(d[i], kind="stable")
            idx, dist = m.nearest(q)
            self.assertEqual(idx, order[0])
            self.assertAlmostEqual(dist, d[i, order[0]], places=12)
            ks, kd = m.knn(q, 4)
            np.testing.assert_array_equal(ks, order[:4])
            np.testing.assert_allclose(kd, d[i, order[:4]], atol=1e-12)
            rs, _ = m.radius(q, r)
            np.testing.assert_array_equal(np.sort(rs), np.sort(np.nonzero(d[i] <= r)[0]))
            hits += len(rs)
            c = i % 3
            ci, _ = m.nearest(q, cluster=c)
            members = np.nonzero(self.labels == c)[0]
            self.assertEqual(ci, members[np.argmin(d[i, members])])
        self.assertGreater(hits, 1000)
        nn, nd = m.nearest_batch(qs)
        np.testing.assert_array_equal(nn, np.argmin(d, axis=1))

    def test_evaluate_returns_numpy_and_gradient_matches_finite_differences(self):
        m = taskmap.TaskMap.from_arrays(self.poses, self.eps, rotation_scale=RHO, quality_mode="exact")
        x = m.pose(10).copy()
        x[:3] += 0.5 * m.position_sigma
        e = m.evaluate(x)
        self.assertIsInstance(e["gradient"], np.ndarray)
        self.assertEqual(e["gradient"].shape, (6,))
        self.assertLess(e["quality"], 0.0)
        self.assertAlmostEqual(e["cost"], e["proximity"] + e["quality"])
        # Finite differences: p <- p + h e_j, R <- exp(h e_j) R (object frame).
        hs = [1e-4 * m.position_sigma] * 3 + [1e-4 * m.rotation_sigma] * 3
        fd = np.empty(6)
        for j in range(6):
            vals = []
            for sgn in (1, -1):
                y = x.copy()
                h = sgn * hs[j]
                if j < 3:
                    y[j] += h
                else:
                    axis = np.zeros(3)
                    axis[j - 3] = 1
                    dq = np.concatenate([[np.cos(h / 2)], np.sin(h / 2) * axis])
                    w1, v1 = dq[0], dq[1:]
                    w2, v2 = y[3], y[4:7]
                    y[3:] = np.concatenate([[w1 * w2 - v1 @ v2], w1 * v2 + w2 * v1 + np.cross(v1, v2)])
                vals.append(m.evaluate(y)["cost"])
            fd[j] = (vals[0] - vals[1]) / (2 * hs[j])
        self.assertLess(np.linalg.norm(fd - e["gradient"]) / np.linalg.norm(e["gradient"]), 1e-6)

    def test_batch_equals_single_and_threads(self):
        m = self.map
        qs = queries(self.rng, m, 300)
        b = m.evaluate_batch(qs)
        self.assertEqual(b["quality_gradient"].shape, (300, 6))
        for i in range(0, 300, 7):
            e = m.evaluate(qs[i])
            self.assertEqual(b["nearest"][i], e["nearest"])
            self.assertEqual(b["quality"][i], e["quality"])
            np.testing.assert_array_equal(b["proximity_gradient"][i], e["proximity_gradient"])
        out = [None] * 4

        def work(k):
            out[k] = m.evaluate_batch(qs)["quality"]

        threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        for o in out:
            np.testing.assert_array_equal(o, b["quality"])

    def test_truncated_quality_within_bound(self):
        m = self.map
        for q in queries(self.rng, m, 300):
            t = m.quality(q, mode="truncated")
            e = m.quality(q, mode="exact")
            self.assertLessEqual(abs(t["value"] - e["value"]), t["value_bound"] + 1e-12 * abs(e["value"]))

    def test_quality_kernel_is_gaussian_in_the_pose_embedding(self):
        """Exact quality against numpy: f_i = exp(-d_i/2) / Z with
        d_i = |dp|^2/sp^2 + ||R - R_i||_F^2 / (2 sr^2), Z = (2 pi)^3 sp^3 sr^3, for the default
        (isotropic: d_i = embedding distance^2 / sp^2) and an anisotropic rotation_sigma."""
        rs = np.array([rotation_matrix(p[3:]) for p in self.poses])
        for scale in (None, 2.5):
            kw = {} if scale is None else {"rotation_sigma": scale * self.map.rotation_sigma}
            m = taskmap.TaskMap.from_arrays(self.poses, self.eps, rotation_scale=RHO, **kw)
            sp, sr = m.position_sigma, m.rotation_sigma
            if scale is None:
                self.assertAlmostEqual(sr, sp / RHO, delta=1e-15)
            z = (2 * np.pi) ** 3 * (sp * sr) ** 3
            qs = queries(self.rng, m, 40)
            near = 0
            for q in qs:
                r = rotation_matrix(q[3:])
                d = (np.sum((self.poses[:, :3] - q[:3]) ** 2, axis=1) / sp ** 2
                     + np.sum((rs - r) ** 2, axis=(1, 2)) / (2 * sr ** 2))
                if scale is None:
                    d_embedding = np.sum((self.emb - embed([q])[0]) ** 2, axis=1) / sp ** 2
                    np.testing.assert_allclose(d, d_embedding, rtol=1e-9, atol=1e-9)
                expected = -np.sum(self.eps * np.exp(-0.5 * d)) / z / np.sum(self.eps)
                got = m.quality(q, mode="exact")["value"]
                self.assertAlmostEqual(got, expected, delta=1e-9 * abs(expected) + 1e-300)
                near += expected < -1e-6 / z
            self.assertGreater(near, 10)  # the comparison is not vacuous

    def test_validated_map_weighs_samples_by_hold_margin(self):
        """The checked-in reference map carries robust hold labels for every grasp: its quality
        weights are epsilon x robust margin (docs/METHOD.md "Sample weights": 1 - the share of
        the 1 cm / 5 deg margin the pushes used over every variant), checked against numpy with
        the labels read by h5py; sample_weight="epsilon" restores the paper's."""
        import h5py
        path = os.path.join(os.environ.get("TASKMAP_SOURCE_DIR", ""), "meshes", "maps",
                            "basket_humanoid.h5")
        if not os.path.exists(path):
            self.skipTest("the checked-in map is not available")
        with h5py.File(path, "r") as f:
            eps = f["grasps/epsilon"][:]
            robust = f["grasps/robust"][:]
            d, a = f["grasps/hold_push_translation"][:], f["grasps/hold_push_rotation"][:]
            params = json.loads(f["validation"].attrs["robust_json"])
        self.assertTrue(np.all(robust == 1))  # a robust build stores robust grasps only
        margin = np.clip(np.minimum(1 - np.maximum(d, 0) / params["margin_translation"],
                                    1 - np.maximum(a, 0) / params["margin_rotation"]), 0, 1)
        by_margin = taskmap.load(path)
        by_eps = taskmap.load(path, sample_weight="epsilon")
        self.assertEqual(by_margin.sample_weight, "hold_margin")
        self.assertEqual(by_eps.sample_weight, "epsilon")
        poses = by_margin.poses
        for weights, m in ((eps * margin, by_margin), (eps, by_eps)):
            sp, sr = m.position_sigma, m.rotation_sigma
            z = (2 * np.pi) ** 3 * (sp * sr) ** 3
            rs = np.array([rotation_matrix(p[3:]) for p in poses])
            for q in poses[::7]:
                r = rotation_matrix(q[3:])
                dd = (np.sum((poses[:, :3] - q[:3]) ** 2, axis=1) / sp ** 2
                      + np.sum((rs - r) ** 2, axis=(1, 2)) / (2 * sr ** 2))
                expected = -np.sum(weights * np.exp(-0.5 * dd)) / z / np.sum(weights)
                got = m.quality(q, mode="exact")["value"]
                self.assertAlmostEqual(got, expected, delta=1e-9 * abs(expected) + 1e-300)
        self.assertNotAlmostEqual(by_margin.quality(poses[0], mode="exact")["value"],
                                  by_eps.quality(poses[0], mode="exact")["value"], delta=1e-12)
        with self.assertRaisesRegex(taskmap.Error, "hold_margin"):
            taskmap.load(path, sample_weight="holding")

    def test_session_equals_evaluate_on_a_trajectory(self):
        m = self.map
        rng = np.random.default_rng(5)
        for cluster in (None, 2):
            s = m.session(cluster=cluster)
            self.assertAlmostEqual(s.margin, 0.25 * m.cutoff_radius, places=15)
            self.assertEqual(s.cluster, cluster)
            target = m.pose(int(np.nonzero(self.labels == 2)[0][3]))
            x = target.copy()
            x[:3] += 3 * m.position_sigma * rng.normal(size=3)
            for k in range(25):
                x[:3] += 0.25 * (target[:3] - x[:3])  # converge in position, fixed orientation
                a, b = s.evaluate(x), m.evaluate(x, cluster=cluster)
                self.assertEqual(a["nearest"], b["nearest"])
                self.assertEqual(a["nearest_distance"], b["nearest_distance"])
                self.assertEqual(a["proximity"], b["proximity"])
                np.testing.assert_allclose(a["quality"], b["quality"], rtol=1e-12)
                np.testing.assert_allclose(a["gradient"], b["gradient"], rtol=1e-12,
                                           atol=1e-12 * np.linalg.norm(b["gradient"]))
            st = s.stats
            self.assertEqual(st["calls"], 25)
            self.assertGreaterEqual(st["anchors"], 1)
            self.assertLess(st["anchors"], 10)
            s.reset()
            self.assertEqual(s.stats["calls"], 0)
        with self.assertRaisesRegex(taskmap.Error, "margin"):
            m.session(margin=-1.0)
        with self.assertRaisesRegex(taskmap.Error, "cluster 9"):
            m.session(cluster=9)

    def test_session_keeps_its_map_alive(self):
        s = taskmap.TaskMap.from_arrays(self.poses, self.eps, rotation_scale=RHO).session(margin=0.0)
        e = s.evaluate(self.poses[7])
        self.assertEqual(e["nearest"], 7)
        self.assertEqual(s.stats["anchors"], 1)

    def test_save_and_load_roundtrip(self):
        path = os.path.join(self.tmp, "roundtrip.h5")
        self.map.save(path)
        loaded = taskmap.load(path)
        self.assertEqual(len(loaded), len(self.map))
        self.assertEqual(loaded.num_clusters, 3)
        for q in queries(self.rng, self.map, 50):
            a, b = loaded.evaluate(q), self.map.evaluate(q)
            self.assertEqual(a["nearest"], b["nearest"])
            self.assertAlmostEqual(a["cost"], b["cost"], delta=1e-12 * abs(b["cost"]))

    def test_errors_become_python_exceptions(self):
        self.assertTrue(issubclass(taskmap.Error, ValueError))
        bad = os.path.join(self.tmp, "corrupt.h5")
        with open(bad, "wb") as f:
            f.write(b"not an hdf5 file at all")
        with self.assertRaises(taskmap.Error) as ctx:
            taskmap.load(bad)
        self.assertIn("corrupt.h5", str(ctx.exception))
        with self.assertRaises(ValueError):
            taskmap.load(os.path.join(self.tmp, "missing.h5"))
        with self.assertRaisesRegex(taskmap.Error, "cluster 7 does not exist"):
            self.map.nearest(self.poses[0], cluster=7)
        with self.assertRaisesRegex(taskmap.Error, "unknown option 'colour'"):
            taskmap.TaskMap.from_arrays(self.poses, self.eps, colour=1)
        p = self.poses.copy()
        p[3, 0] = np.nan
        with self.assertRaisesRegex(taskmap.Error, "non-finite"):
            taskmap.TaskMap.from_arrays(p, self.eps)
        with self.assertRaisesRegex(taskmap.Error, "/grasps/epsilon has 3 entries"):
            taskmap.TaskMap.from_arrays(self.poses, self.eps[:3])

    def test_wrong_version_map_raises(self):
        import h5py
        path = os.path.join(self.tmp, "newer.h5")
        self.map.save(path)
        with h5py.File(path, "r+") as f:
            f.attrs["schema_version"] = 99
        with self.assertRaisesRegex(taskmap.Error, "changed by another tool"):
            taskmap.load(path)
        with self.assertRaisesRegex(taskmap.Error, "newer"):
            taskmap.seal(path)

    def test_edited_map_loads_after_seal(self):
        import h5py
        path = os.path.join(self.tmp, "edited.h5")
        self.map.save(path)
        with h5py.File(path, "r+") as f:
            f["grasps/epsilon"][0] = 0.5
        with self.assertRaisesRegex(taskmap.Error, "edited.h5.*does not match its seal"):
            taskmap.load(path)
        taskmap.seal(path)
        loaded = taskmap.load(path)
        self.assertEqual(len(loaded), len(self.map))
        self.assertEqual(loaded.epsilon[0], 0.5)

    def test_rank_clusters(self):
        obj = np.array([0.5, 0, 0.8, 1, 0, 0, 0.0])
        ranks = self.map.rank_clusters(
            obj, lambda target: None if target[2] > 1.05 else target[:3].copy(),
            lambda q: taskmap.joint_limit_cost(q, np.array([0, -1, 0.0]), np.array([1, 1, 2.0])))
        self.assertEqual(sorted(r["cluster"] for r in ranks), [0, 1, 2])
        reach = [r for r in ranks if r["reachable"]]
        self.assertEqual(ranks[:len(reach)], reach)  # reachable ones first
        self.assertEqual([r["comfort"] for r in reach], sorted(r["comfort"] for r in reach))

    def test_rank_clusters_tries_members_when_no_representative_is_reachable(self):
        obj = np.array([0.0, 0, 0, 1, 0, 0, 0])
        reps = [r["representative"] for r in self.map.rank_clusters(obj, lambda t: t[:3].copy(),
                                                                     lambda q: 0.0)]
        rep_poses = [self.map.pose(i) for i in reps]

        def ik(target):  # out of reach: the representatives' poses
            return None if any(np.allclose(target, p) for p in rep_poses) else target[:3].copy()

        ranks = self.map.rank_clusters(obj, ik, lambda q: float(np.linalg.norm(q)))
        self.assertFalse(any(r["reachable"] for r in ranks))
        ranks = self.map.rank_clusters(obj, ik, lambda q: float(np.linalg.norm(q)), member_tries=3)
        for r in ranks:
            self.assertTrue(r["reachable"], r)
            self.assertNotEqual(r["target"], r["representative"])
            self.assertEqual(r["tried"], 2)
            np.testing.assert_allclose(r["target_object"], self.map.pose(r["target"]))
        with self.assertRaisesRegex(taskmap.Error, "member_tries must be >= 0"):
            self.map.rank_clusters(obj, ik, lambda q: 0.0, member_tries=-1)

    def test_map_built_by_the_cli(self):
        cli = os.environ.get("TASKMAP_CLI")
        src = os.environ.get("TASKMAP_SOURCE_DIR", "")
        objects = os.path.join(src, "meshes", "objects")
        obj = next((os.path.join(objects, o) for o in ("basket.obj", "box.obj")
                    if os.path.exists(os.path.join(objects, o))), None)
        hand = os.path.join(src, "meshes", "hands", "barrett", "barrett.urdf")
        if not cli or not os.path.exists(cli) or obj is None or not os.path.exists(hand):
            self.skipTest("taskmap CLI, object or hand not available")
        usage = subprocess.run([cli, "--help"], capture_output=True, text=True, timeout=60)
        if " build" not in usage.stdout:
            self.skipTest("the CLI has no build subcommand yet")
        out = os.path.join(self.tmp, "cli_map.h5")
        r = subprocess.run([cli, "build", "--object", obj, "--hand", hand, "--valid", "30", "--seed", "1",
                            "--hold-test", "off", "-o", out], capture_output=True, text=True, timeout=900)
        self.assertEqual(r.returncode, 0, r.stderr)
        m = taskmap.load(out)
        self.assertGreaterEqual(len(m), 30)
        e = m.evaluate(m.pose(0))
        self.assertEqual(e["nearest_distance"], 0.0)
        self.assertTrue(np.all(np.isfinite(e["gradient"])))
        _, dist = m.nearest_batch(m.poses)
        self.assertLess(dist.max(), 1e-12)


if __name__ == "__main__":
    unittest.main()
