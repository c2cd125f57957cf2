"""taskmap.summary, taskmap.hand_info, taskmap.mesh_info, taskmap.recluster and taskmap.picture
(the inspect, builder and picture stages) against the command-line tool on the same inputs: the
same numbers as `taskmap inspect --json`, `taskmap hand-info --json` and `taskmap mesh-info
--json`, the same map bytes as `taskmap cluster`, the same PNG bytes as `inspect --png` and
`hand-info --png`, and the same errors for bad input."""
import json
import os
import re
import tempfile
import unittest
import warnings

SRC = os.environ["TASKMAP_SOURCE_DIR"]
BUILD = os.environ["TASKMAP_BUILD_DIR"]
MAP = os.path.join(SRC, "meshes", "maps", "basket_humanoid.h5")  # checked-in reference map
HANDS = os.path.join(SRC, "meshes", "hands")
MAP_OBJECT = os.path.join(SRC, "meshes", "objects", "basket.obj")
# The bundled hands, for the CLI and for the package's bundled hand names alike.
os.environ["TASKMAP_DATA_DIR"] = os.path.join(BUILD, "share", "taskmap")

from cli_support import cli, read  # noqa: E402
import taskmap  # noqa: E402  (after TASKMAP_DATA_DIR is set)


class SummaryTest(unittest.TestCase):
    def test_summary_is_what_inspect_json_prints(self):
        code, out, err = cli("inspect", "--json", MAP)
        self.assertEqual(code, 0, err)
        s = taskmap.summary(MAP)
        self.assertEqual(s, json.loads(out))
        self.assertEqual(s["grasps"]["count"], 40)
        self.assertEqual(len(s["clustering"]["clusters"]), 3)
        # A loaded TaskMap gives the same numbers; it has no path.
        from_map = taskmap.summary(taskmap.load(MAP))
        self.assertEqual(from_map["path"], "")
        self.assertEqual({k: v for k, v in from_map.items() if k != "path"},
                         {k: v for k, v in s.items() if k != "path"})

    def test_summary_of_a_missing_file_names_it(self):
        with self.assertRaises(taskmap.Error) as e:
            taskmap.summary("/nonexistent/m.h5")
        self.assertIn("map file '/nonexistent/m.h5' does not exist", str(e.exception))
        with tempfile.NamedTemporaryFile(suffix=".h5") as f:
            f.write(b"not a map")
            f.flush()
            with self.assertRaises(taskmap.Error) as e:
                taskmap.summary(f.name)
            self.assertIn(f.name, str(e.exception))


class MeshInfoTest(unittest.TestCase):
    def test_mesh_info_is_what_mesh_info_json_prints(self):
        real = os.path.join(SRC, "..", "shared", "real", "objects", "ycb_011_banana.obj")
        objects = [os.path.join(SRC, "meshes", "objects", n) for n in ("mug.obj", "basket.obj")]
        for path in objects + ([real] if os.path.exists(real) else []):
            code, out, err = cli("mesh-info", "--json", path)
            self.assertEqual(code, 0, err)
            self.assertEqual(taskmap.mesh_info(path), json.loads(out), path)
        code, out, err = cli("mesh-info", "--json", "--scale", "10", objects[0])
        info = taskmap.mesh_info(objects[0], scale=10)
        self.assertEqual(info, json.loads(out))
        self.assertFalse(info["graspable_size"])

    def test_bad_inputs_name_the_file_or_argument(self):
        with self.assertRaises(taskmap.Error) as e:
            taskmap.mesh_info("/nonexistent/a.obj")
        self.assertIn("/nonexistent/a.obj", str(e.exception))
        with self.assertRaises(taskmap.Error) as e:
            taskmap.mesh_info(MAP_OBJECT, repair="wrap", no_repair=True)
        self.assertIn("no_repair", str(e.exception))
        with self.assertRaises(taskmap.Error) as e:
            taskmap.mesh_info(MAP_OBJECT, scale=0)
        self.assertIn("scale must be positive", str(e.exception))


class ReclusterTest(unittest.TestCase):
    def test_recluster_writes_what_cluster_writes(self):
        with tempfile.TemporaryDirectory() as d:
            by_cli, by_py = os.path.join(d, "cli.h5"), os.path.join(d, "py.h5")
            for p in (by_cli, by_py):
                with open(p, "wb") as f:
                    f.write(read(MAP))
            code, out, err = cli("cluster", "--clusters", "3", "--method", "single", "-q",
                                 by_cli)
            self.assertEqual(code, 0, err)
            m = taskmap.recluster(by_py, clusters=3, method="single")
            self.assertEqual(read(by_py), read(by_cli))
            self.assertLessEqual(len(taskmap.summary(m)["clustering"]["clusters"]), 3)
            # Into another file, the input untouched; contradicting arguments refused.
            other = os.path.join(d, "other.h5")
            taskmap.recluster(MAP, threshold=0.05, output=other)
            self.assertTrue(os.path.exists(other))
            with self.assertRaises(taskmap.Error) as e:
                taskmap.recluster(by_py, threshold=0.1, clusters=2)
            self.assertIn("not both", str(e.exception))
            with self.assertRaises(taskmap.Error) as e:  # output given: never the input
                taskmap.recluster(by_py, output=by_py)
            self.assertIn(by_py, str(e.exception))


class HandInfoTest(unittest.TestCase):
    def test_hand_info_is_what_hand_info_json_prints(self):
        with tempfile.TemporaryDirectory() as d:
            for name in ("barrett", "humanoid", "panda"):
                urdf = os.path.join(HANDS, name, name + ".urdf")
                code, out, err = cli("hand-info", "--json", "--png", os.path.join(d, "cli.png"),
                                     urdf)
                self.assertEqual(code, 0, err)
                info = taskmap.hand_info(urdf, png=os.path.join(d, "py.png"))
                self.assertEqual(info, json.loads(out), name)
                self.assertEqual(read(os.path.join(d, "py.png")), read(os.path.join(d, "cli.png")))
            # A bundled name, as the CLI takes it.
            self.assertEqual(taskmap.hand_info("barrett")["name"], "barrett_bh8_282")

    def test_bad_hand_names_the_input(self):
        with self.assertRaises(taskmap.Error) as e:
            taskmap.hand_info("no_such_hand")
        self.assertIn("hand 'no_such_hand' is neither a hand file (URDF or MJCF) nor a bundled "
                      "hand name", str(e.exception))
        with tempfile.TemporaryDirectory() as d:
            bad = os.path.join(d, "bad.urdf")
            with open(bad, "w") as f:
                f.write("<robot name='x'><link name='a'/>")
            with self.assertRaises(taskmap.Error) as e:
                taskmap.hand_info(bad)
            self.assertIn(bad, str(e.exception))


class HandInitTest(unittest.TestCase):
    def test_hand_init_drafts_what_hand_init_prints(self):
        real = os.path.join(SRC, "..", "shared", "real", "hands")
        urdfs = [os.path.join(HANDS, "barrett", "barrett.urdf")]
        if os.path.isdir(real):
            urdfs.append(os.path.join(real, "franka_hand", "franka_hand.urdf"))
        with tempfile.TemporaryDirectory() as d:
            for k, urdf in enumerate(urdfs):
                by_cli, by_py = os.path.join(d, "cli%d.json" % k), os.path.join(d, "py%d.json" % k)
                code, out, err = cli("hand-init", "-o", by_cli, urdf)
                self.assertEqual(code, 0, err)
                draft = taskmap.hand_init(urdf, output=by_py)
                self.assertEqual(read(by_py), read(by_cli), urdf)
                self.assertEqual(draft["sidecar"], json.loads(draft["json"]))
                guesses = [line[len("guess: "):] for line in out.splitlines()
                           if line.startswith("guess: ")]
                self.assertEqual(draft["notes"], guesses)
            with self.assertRaisesRegex(taskmap.Error, "exists; pass force=True"):
                taskmap.hand_init(urdfs[0], output=os.path.join(d, "py0.json"))
            with self.assertRaisesRegex(taskmap.Error, "no URDF file '/nonexistent.urdf'"):
                taskmap.hand_init("/nonexistent.urdf")


class RegressTest(unittest.TestCase):
    def test_regress_reports_what_the_cli_prints(self):
        code, out, err = cli("regress", "--only", "basket_panda", "--threads", "2")
        self.assertEqual(code, 0, out + err)
        r = taskmap.regress(only=["basket_panda"], threads=1)
        self.assertEqual(r["failures"], 0)
        [case] = r["cases"]
        self.assertEqual((case["name"], case["outcome"]), ("basket_panda", "compared"))
        self.assertTrue(all(row["pass"] for row in case["rows"]))
        mask = lambda text: re.sub(r"\([0-9.]+ s\)", "(T s)", text)  # build time
        self.assertIn(mask(case["text"]), mask(out))
        with self.assertRaisesRegex(taskmap.Error, "no regression case matched"):
            taskmap.regress(only=["no_such_case"])


class PictureTest(unittest.TestCase):
    def test_picture_is_what_inspect_png_draws(self):
        with tempfile.TemporaryDirectory() as d:
            code, _, err = cli("inspect", "--png", os.path.join(d, "cli.png"), "--width", "1000",
                               "--height", "700", MAP)
            self.assertEqual(code, 0, err)
            out = taskmap.picture(MAP, png=os.path.join(d, "py.png"), width=1000, height=700)
            self.assertEqual(out, os.path.join(d, "py.png"))
            self.assertEqual(read(out), read(os.path.join(d, "cli.png")))
            self.assertEqual(read(out)[:8], b"\x89PNG\r\n\x1a\n")
            # Another hand than the map's: a warning, no hand drawn, as the CLI does.
            code, _, err = cli("inspect", "--png", os.path.join(d, "cli2.png"), "--hand",
                               "barrett", MAP)
            self.assertIn("other actuated joints", err)
            with warnings.catch_warnings(record=True) as w:
                warnings.simplefilter("always")
                taskmap.picture(MAP, png=os.path.join(d, "py2.png"), hand="barrett")
            self.assertTrue(any("other actuated joints" in str(x.message) for x in w), w)
            self.assertEqual(read(os.path.join(d, "py2.png")), read(os.path.join(d, "cli2.png")))

    def test_bad_sizes_and_paths_leave_nothing(self):
        with tempfile.TemporaryDirectory() as d:
            png = os.path.join(d, "x.png")
            with self.assertRaises(taskmap.Error) as e:
                taskmap.picture(MAP, png=png, width=10)
            self.assertIn("--width 10 is out of range", str(e.exception))
            with self.assertRaises(taskmap.Error) as e:
                taskmap.picture(MAP, png="/nonexistent/dir/x.png")
            self.assertIn("/nonexistent/dir/x.png", str(e.exception))
            self.assertEqual(os.listdir(d), [])


if __name__ == "__main__":
    unittest.main()
