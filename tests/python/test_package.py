"""The Python package: `import taskmap` and queries load no offline library (checked in
/proc/self/maps, as the C++ consumer test checks its link line); the offline names load on first
use; `pip install .` into a fresh virtual environment (offline, reusing this build tree's objects)
gives a package that works from anywhere, bundled hands and objects included."""
import json
import math
import os
import subprocess
import sys
import tempfile
import textwrap
import unittest

SRC = os.environ["TASKMAP_SOURCE_DIR"]
BUILD = os.environ["TASKMAP_BUILD_DIR"]

# Libraries of the offline stages and their dependencies: none may be mapped by `import taskmap`.
OFFLINE_LIBS = ("libBullet", "libLinearMath", "libassimp", "libqhull", "liburdfdom", "libmujoco",
                "libmpfr", "libtinyxml", "libconsole_bridge", "libcairo", "libtaskmap_meshes",
                "libtaskmap_hands", "libtaskmap_grasp_sim", "libtaskmap_quality",
                "libtaskmap_builder", "libtaskmap_reaching", "libtaskmap_validate",
                "libtaskmap_viz", "libtaskmap_inspect", "libtaskmap_picture")

QUERY = textwrap.dedent("""
    import json, os, sys
    import numpy as np
    import taskmap
    rng = np.random.default_rng(1)
    poses = np.zeros((50, 7)); poses[:, :3] = rng.uniform(-0.1, 0.1, (50, 3)); poses[:, 3] = 1
    m = taskmap.TaskMap.from_arrays(poses, rng.uniform(0.01, 0.1, 50))
    path = os.path.join(sys.argv[1], "m.h5")
    m.save(path)
    m = taskmap.load(path)
    q = m.evaluate(poses[0])["quality"]
    touch = sys.argv[2]
    if touch:
        getattr(taskmap, touch)
    maps = open("/proc/self/maps").read()
    print(json.dumps({"file": taskmap.__file__, "quality": float(q), "n": len(m),
                      "maps": sorted({l.split()[-1] for l in maps.splitlines()
                                      if ".so" in l.split()[-1]})}))
""")


# In the virtual environment: the bundled hand and object by name, a few valid grasps.
BUILD_IN_VENV = textwrap.dedent("""
    import json, os, sys
    import taskmap
    d = taskmap.data_dir()
    out = os.path.join(sys.argv[1], "barrett.h5")
    m = taskmap.build(object=os.path.join(d, "objects", "box.obj"), hand="barrett", valid=3,
                      trials=400, seed=1, threads=2, output=out)
    s = taskmap.summary(out)
    print(json.dumps({"data_dir": d, "hand": s["hand"]["name"], "grasps": s["grasps"]["count"],
                      "force_closure": s["grasps"]["force_closure"], "loaded": len(m),
                      "hand_urdf": taskmap.hand_info("barrett")["urdf"]}))
""")


def run_query(python, touch="", env=None, cwd=None):
    with tempfile.TemporaryDirectory() as d:
        out = subprocess.run([python, "-c", QUERY, d, touch], check=True, capture_output=True,
                             text=True, env=env, cwd=cwd)
    return json.loads(out.stdout)


def offline_libs(maps):
    return [m for m in maps if any(os.path.basename(m).startswith(l) for l in OFFLINE_LIBS)]


class PackageTest(unittest.TestCase):
    def test_import_and_queries_load_no_offline_library(self):
        r = run_query(sys.executable)
        self.assertEqual(r["n"], 50)
        self.assertTrue(math.isfinite(r["quality"]))
        self.assertEqual(offline_libs(r["maps"]), [])
        self.assertTrue(any("libtaskmap_integration" in m for m in r["maps"]))

    def test_offline_names_load_on_first_use(self):
        # The check above can fail: touching taskmap.validate maps MuJoCo and the meshes and hands
        # stages.
        r = run_query(sys.executable, touch="validate")
        libs = offline_libs(r["maps"])
        self.assertTrue(any("libmujoco" in m for m in libs), libs)
        self.assertTrue(any("libtaskmap_validate" in m for m in libs), libs)
        # taskmap.build maps the builder and the simulator (Bullet) only when touched.
        r = run_query(sys.executable, touch="build")
        libs = offline_libs(r["maps"])
        self.assertTrue(any("libtaskmap_builder" in m for m in libs), libs)
        self.assertTrue(any("libBullet" in m for m in libs), libs)
        import taskmap
        self.assertIn("reach", dir(taskmap))
        self.assertIn("build", dir(taskmap))
        self.assertIn("dataset", dir(taskmap))
        # The map and hand reports and the pictures: inspect, picture and cairo on first use.
        r = run_query(sys.executable, touch="summary")
        libs = offline_libs(r["maps"])
        for lib in ("libtaskmap_inspect", "libtaskmap_picture", "libcairo"):
            self.assertTrue(any(lib in m for m in libs), (lib, libs))
        for name in ("summary", "hand_info", "picture"):
            self.assertIn(name, dir(taskmap))
        with self.assertRaises(AttributeError):
            taskmap.no_such_name

    def test_errors_of_both_modules_are_taskmap_error(self):
        import taskmap
        with self.assertRaises(taskmap.Error) as e:
            taskmap.load("/nonexistent/map.h5")
        self.assertIn("/nonexistent/map.h5", str(e.exception))
        with self.assertRaises(taskmap.Error) as e:  # raised by taskmap._offline
            taskmap.validate("/nonexistent/map.h5")
        self.assertIn("/nonexistent/map.h5", str(e.exception))

    def test_pip_install_into_a_fresh_virtual_environment(self):
        with tempfile.TemporaryDirectory() as d:
            venv = os.path.join(d, "venv")
            subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", venv],
                           check=True)
            env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
            env["TASKMAP_BUILD_DIR"] = BUILD  # reuse this tree's objects: nothing recompiled
            pip = subprocess.run([os.path.join(venv, "bin", "pip"), "install", "--no-index",
                                  "--no-cache-dir", SRC], capture_output=True, text=True, env=env)
            self.assertEqual(pip.returncode, 0, pip.stdout + pip.stderr)
            r = run_query(os.path.join(venv, "bin", "python"), env=env, cwd=d)
            self.assertTrue(r["file"].startswith(venv), r["file"])
            self.assertEqual(r["n"], 50)
            self.assertEqual(offline_libs(r["maps"]), [])
            libs = [m for m in r["maps"] if "libtaskmap_" in m]
            self.assertTrue(libs and all(m.startswith(os.path.realpath(venv)) or
                                         m.startswith(venv) for m in libs), libs)
            # The wheel carries the bundled data: a map built from the venv alone (no source
            # tree, no TASKMAP_DATA_DIR) with a bundled hand and object.
            env.pop("TASKMAP_DATA_DIR", None)
            out = subprocess.run([os.path.join(venv, "bin", "python"), "-c", BUILD_IN_VENV, d],
                                 capture_output=True, text=True, env=env, cwd=d)
            self.assertEqual(out.returncode, 0, out.stdout + out.stderr)
            b = json.loads(out.stdout.splitlines()[-1])
            share = os.path.join(os.path.realpath(venv), "share", "taskmap")
            self.assertEqual(os.path.realpath(b["data_dir"]), share)
            self.assertTrue(b["hand_urdf"].startswith(share), b["hand_urdf"])
            self.assertTrue(b["hand"].startswith("barrett"), b["hand"])  # the URDF robot name
            self.assertGreaterEqual(b["force_closure"], 3)
            self.assertEqual(b["grasps"], b["loaded"])


if __name__ == "__main__":
    unittest.main()
