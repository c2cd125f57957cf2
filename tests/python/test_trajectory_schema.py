"""Layout of a trajectory file (`taskmap reach --map ... -o`), read with Debian's h5py
(mapstore/TRAJECTORY.md), and its GLB export parsed with the standard library.

Builds a small basket map with the mounted (humanoid) hand, plans a reach at the paper's
reference position, then checks every documented group, dataset and attribute, and relations
computed independently in numpy: the palm in the object frame from the world poses, the palm
body's column of /bodies/poses, the JSON report's numbers, the primitives' axes; and that
taskmap.reach(robot, map) in Python returns the CLI's report for the same problem.
"""
import hashlib
import json
import os
import shutil
import struct
import subprocess
import tempfile
import unittest

import h5py
import numpy as np

CLI = os.environ.get("TASKMAP_CLI", "taskmap")
SRC = os.environ.get("TASKMAP_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))


def text(value):
    return value.decode("utf-8") if isinstance(value, (bytes, np.bytes_)) else value


def matrix(pose):
    """4x4 matrix of x y z qw qx qy qz."""
    x, y, z, w, a, b, c = pose
    r = np.array([[1 - 2 * (b * b + c * c), 2 * (a * b - c * w), 2 * (a * c + b * w)],
                  [2 * (a * b + c * w), 1 - 2 * (a * a + c * c), 2 * (b * c - a * w)],
                  [2 * (a * c - b * w), 2 * (b * c + a * w), 1 - 2 * (a * a + b * b)]])
    t = np.eye(4)
    t[:3, :3] = r
    t[:3, 3] = [x, y, z]
    return t


class TrajectorySchemaTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="trajectory_schema_")
        cls.map = os.path.join(cls.dir, "basket.h5")
        cls.path = os.path.join(cls.dir, "reach.h5")
        cls.glb = os.path.join(cls.dir, "reach.glb")
        # 80 grasps: a map of 40 has so few clusters (smallest max(3, 3 %)) that no cluster's
        # representative is reachable at this pose, and reach then writes no trajectory.
        subprocess.run([CLI, "build", "--object", os.path.join(SRC, "meshes", "objects",
                                                               "basket.obj"),
                        "--hand", "humanoid", "--valid", "80", "--seed", "1", "--threads", "1", "--hold-test", "off",
                        "-o", cls.map], check=True, capture_output=True)
        run = subprocess.run([CLI, "reach", "--map", cls.map, "--scene",
                              os.path.join(SRC, "reaching", "scenes", "basket_reference.json"),
                              "--object-pose", "0.5 0 0 1.5707963267948966", "--iterations", "2",
                              "--json",
                              "-o", cls.path, "--glb", cls.glb],
                             capture_output=True, text=True)
        assert run.returncode in (0, 1), run.stdout + run.stderr
        cls.report = json.loads(run.stdout)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_python_export_glb_and_view_write_the_cli_bytes(self):
        import taskmap
        glb = os.path.join(self.dir, "py.glb")
        self.assertEqual(taskmap.export_glb(self.path, output=glb), glb)
        with open(glb, "rb") as a, open(self.glb, "rb") as b:
            self.assertEqual(a.read(), b.read())  # reach --glb writes what export-glb writes
        html_cli, html_py = os.path.join(self.dir, "cli.html"), os.path.join(self.dir, "py.html")
        subprocess.run([CLI, "view", self.path, "-o", html_cli, "-q"], check=True)
        self.assertEqual(taskmap.view(self.path, output=html_py), html_py)
        with open(html_cli, "rb") as a, open(html_py, "rb") as b:
            self.assertEqual(a.read(), b.read())
        with self.assertRaises(taskmap.Error) as e:  # never over its input
            taskmap.export_glb(self.path, output=self.path)
        self.assertIn(self.path, str(e.exception))

    def test_root_and_seal(self):
        with open(self.path, "rb") as f:
            self.assertTrue(f.read(512).startswith(b"TASKMAP-SEAL 1\n"))
        with h5py.File(self.path, "r") as f:
            self.assertEqual(text(f.attrs["format"]), "taskmap-trajectory")
            self.assertEqual(int(f.attrs["schema_version"]), 1)
            self.assertTrue(text(f.attrs["generator"]).startswith("taskmap "))
            self.assertEqual(sorted(f.keys()), ["bodies", "object", "plan", "robot", "shapes"])

    def test_robot_group(self):
        with h5py.File(self.path, "r") as f:
            g = f["robot"]
            self.assertEqual(text(g.attrs["robot"]), "panda")
            self.assertEqual(text(g.attrs["hand"]), "humanoid")
            self.assertEqual(float(g.attrs["dt_s"]), 0.01)
            names = [text(n) for n in g["joint_names"][()]]
            self.assertEqual(names, ["fer_joint%d" % i for i in range(1, 8)])
            q = g["joints"][()]
            self.assertEqual(q.shape, (301, 7))
            ready = [0.0, -np.pi / 4, 0.0, -3 * np.pi / 4, 0.0, np.pi / 2, np.pi / 4]
            np.testing.assert_allclose(q[0], ready, atol=1e-15)
            np.testing.assert_array_equal(q[-1], self.report["q_final"])
            world, obj = g["palm_world"][()], g["palm_object"][()]
            self.assertEqual(world.shape, (301, 7))
            np.testing.assert_allclose(np.linalg.norm(world[:, 3:], axis=1), 1.0, atol=1e-12)
            object_pose = f["object"].attrs["pose"]
            for t in (0, 150, 300):
                rel = np.linalg.inv(matrix(object_pose)) @ matrix(world[t])
                np.testing.assert_allclose(rel, matrix(obj[t]), atol=1e-12)

    def test_object_and_plan_groups(self):
        with h5py.File(self.path, "r") as f, h5py.File(self.map, "r") as m:
            o = f["object"]
            self.assertEqual(text(o.attrs["name"]), "basket")
            np.testing.assert_allclose(o.attrs["pose"][:3], [0.5, 0, 0], atol=1e-12)
            np.testing.assert_array_equal(o["vertices"][()], m["object/vertices"][()])
            np.testing.assert_array_equal(o["faces"][()], m["object/faces"][()])
            p = f["plan"]
            self.assertEqual(text(p.attrs["map_path"]), self.map)
            with open(self.map, "rb") as mf:
                self.assertEqual(text(p.attrs["map_sha256"]),
                                 hashlib.sha256(mf.read()).hexdigest())
            self.assertEqual(int(p.attrs["cluster"]), self.report["cluster"])
            self.assertEqual(int(p.attrs["start_cluster"]), self.report["start_cluster"])
            self.assertEqual(int(p.attrs["grasp_index"]), self.report["grasp_index"])
            # q*: the quality columns are w_map,q g_q / q*, of the order of w_map,q
            peak = float(p.attrs["quality_peak"])
            self.assertEqual(peak, self.report["map_weights"]["quality_peak"])
            self.assertGreater(peak, 0.0)
            terms = [text(n) for n in p["cost_terms"][()]]
            history = p["cost_history"][()]
            self.assertEqual(history.shape, (self.report["iterations"] + 1, len(terms)))
            for i, row in enumerate(self.report["cost_history"]):
                for k in ("total", "path_length", "proximity", "quality", "nearest_distance_m"):
                    self.assertEqual(history[i, terms.index(k)], row[k])
            np.testing.assert_array_equal(p["proximity_over_movement"][()],
                                          self.report["proximity_over_movement"])
            np.testing.assert_array_equal(p["quality_over_movement"][()],
                                          self.report["quality_over_movement"])
            g = p["grasp"]  # the map's hand and the chosen grasp's joint values
            self.assertEqual(text(g.attrs["hand"]), text(m["hand"].attrs["name"]))
            self.assertEqual(text(g.attrs["hand_sha256"]), text(m["hand"].attrs["urdf_sha256"]))
            self.assertTrue(text(g.attrs["hand_path"]).endswith("humanoid.urdf"))
            self.assertEqual([text(n) for n in g["joint_names"][()]],
                             [text(n) for n in m["hand/joint_names"][()]])
            np.testing.assert_array_equal(g["joints"][()],
                                          m["grasps/joints"][self.report["grasp_index"]])

    def test_bodies_and_shapes(self):
        with h5py.File(self.path, "r") as f:
            names = [text(n) for n in f["bodies/names"][()]]
            parent, role = f["bodies/parent"][()], f["bodies/role"][()]
            poses = f["bodies/poses"][()]
            self.assertEqual(poses.shape, (301, 7 * len(names)))
            for b, p in enumerate(parent):
                self.assertTrue(-1 <= p < b)
            self.assertEqual(role[names.index("fer_link1")], 0)
            self.assertEqual(role[names.index("palm")], 1)
            self.assertEqual(role[names.index("table")], 2)
            palm = names.index("palm")
            np.testing.assert_allclose(poses[:, 7 * palm:7 * palm + 3],
                                       f["robot/palm_world"][:, :3], atol=1e-15)
            body, kind = f["shapes/body"][()], f["shapes/type"][()]
            params = f["shapes/params"][()]
            self.assertEqual(params.shape, (len(body), 15))
            self.assertTrue(set(kind) <= {0, 1})
            self.assertTrue(np.all((0 <= body) & (body < len(names))))
            self.assertNotIn(names.index("basket"), set(body))  # drawn by its mesh
            for row in params:
                axes = row[3:12].reshape(3, 3).T  # stored column-major
                np.testing.assert_allclose(axes.T @ axes, np.eye(3), atol=1e-9)
                self.assertTrue(np.all(row[12:] >= 0))

    def test_glb_container(self):
        with open(self.glb, "rb") as f:
            data = f.read()
        magic, version, length = struct.unpack_from("<4sII", data, 0)
        self.assertEqual((magic, version, length), (b"glTF", 2, len(data)))
        json_length, json_type = struct.unpack_from("<I4s", data, 12)
        self.assertEqual(json_type, b"JSON")
        gltf = json.loads(data[20:20 + json_length])
        bin_length, bin_type = struct.unpack_from("<I4s", data, 20 + json_length)
        self.assertEqual(bin_type, b"BIN\0")
        self.assertEqual(gltf["buffers"][0]["byteLength"], bin_length)
        with h5py.File(self.path, "r") as f:
            bodies = len(f["bodies/names"][()])
            moving = int(np.sum(f["bodies/role"][()] != 2))
        self.assertEqual(len(gltf["nodes"]), bodies + 2)
        anim = gltf["animations"][0]
        self.assertEqual(len(anim["channels"]), 2 * moving)
        times = gltf["accessors"][anim["samplers"][0]["input"]]
        self.assertEqual(times["count"], 301)
        self.assertAlmostEqual(times["max"][0], 3.0, places=5)

    def test_python_reach_returns_the_cli_report(self):
        """taskmap.reach(robot, map) on the same problem: the same keys (plus q) and values."""
        import taskmap
        robot = taskmap.Robot.panda_with_humanoid_hand(os.path.join(SRC, "reaching", "robots"),
                                                       os.path.join(SRC, "meshes", "hands"))
        # The scene file's basket stands where --object-pose puts it (yaw pi/2 at (0.5, 0)).
        robot.add_scene(os.path.join(SRC, "reaching", "scenes", "basket_reference.json"))
        ready = np.array([0.0, -np.pi / 4, 0.0, -3 * np.pi / 4, 0.0, np.pi / 2, np.pi / 4])
        r = taskmap.reach(robot, taskmap.TaskMap.load(self.map), q0=ready, iterations=2)
        c = self.report
        # Both re-simulate the final grasp by default; the CLI adds the map's sample weights (in
        # Python a property of the map: TaskMap.sample_weight).
        self.assertEqual(set(r) - {"q"}, set(c) - {"sample_weight"})
        self.assertEqual(r["resimulated"]["outcome"], c["resimulated"]["outcome"])
        m = taskmap.TaskMap.load(self.map)
        self.assertEqual(m.sample_weight, c["sample_weight"])
        for k in ("status", "cluster", "start_cluster", "grasp_index", "iterations",
                  "iterations_to_manifold", "iterations_to_quality", "collision_free"):
            self.assertEqual(r[k], c[k], k)
        self.assertEqual(len(r["ranking"]), len(c["ranking"]))
        self.assertEqual(len(r["plans"]), len(c["plans"]))
        for a, b in zip(r["cost_history"], c["cost_history"]):
            self.assertEqual(set(a), set(b))
            for k in a:
                self.assertAlmostEqual(a[k], b[k], delta=1e-9 * (1 + abs(b[k])))
        np.testing.assert_allclose(r["proximity_over_movement"], c["proximity_over_movement"],
                                   rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(r["quality_over_movement"], c["quality_over_movement"],
                                   rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(r["q"][-1], c["q_final"], atol=1e-9)
        with h5py.File(self.path, "r") as f:
            np.testing.assert_allclose(r["q"], f["robot/joints"][()], atol=1e-9)

    def test_read_trajectory_matches_h5py(self):
        import taskmap
        t = taskmap.read_trajectory(self.path)
        with h5py.File(self.path, "r") as f:
            np.testing.assert_array_equal(t["joints"], f["robot/joints"][()])
            np.testing.assert_array_equal(t["palm_object"], f["robot/palm_object"][()])
            np.testing.assert_array_equal(t["cost_history"], f["plan/cost_history"][()])
            np.testing.assert_array_equal(t["shapes"]["params"], f["shapes/params"][()])
            poses = f["bodies/poses"][()]
            self.assertEqual(t["body_poses"].shape, (301, len(t["body_names"]), 7))
            np.testing.assert_array_equal(t["body_poses"].reshape(301, -1), poses)
            self.assertEqual(t["joint_names"], [text(n) for n in f["robot/joint_names"][()]])
        self.assertEqual(t["dt"], 0.01)
        self.assertEqual(t["cluster"], self.report["cluster"])
        with h5py.File(self.path, "r") as f:
            np.testing.assert_array_equal(t["grasp_joints"], f["plan/grasp/joints"][()])
            self.assertEqual(t["map_hand"], text(f["plan/grasp"].attrs["hand"]))
        bad = os.path.join(self.dir, "short.h5")
        with open(self.path, "rb") as src, open(bad, "wb") as dst:
            dst.write(src.read()[:4000])
        with self.assertRaisesRegex(taskmap.Error, "short.h5.*truncated"):
            taskmap.read_trajectory(bad)
        with self.assertRaisesRegex(ValueError, "not a trajectory file"):
            taskmap.read_trajectory(self.map)

    def test_damaged_file_is_refused_by_export(self):
        with open(self.path, "rb") as f:
            data = bytearray(f.read())
        data[len(data) // 2] ^= 0x04
        bad = os.path.join(self.dir, "bad.h5")
        with open(bad, "wb") as f:
            f.write(data)
        run = subprocess.run([CLI, "export-glb", bad, "-o", os.path.join(self.dir, "bad.glb")],
                             capture_output=True, text=True)
        self.assertNotEqual(run.returncode, 0)
        self.assertIn(bad, run.stderr)
        self.assertIn("does not match its seal", run.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "bad.glb")))


if __name__ == "__main__":
    unittest.main()
