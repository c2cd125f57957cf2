"""taskmap.export and taskmap.view on a map against `taskmap export` and `taskmap view`: the same
bytes for ply, glb and acronym exports and for the map's page, and the same refusals."""
import os
import subprocess
import tempfile
import unittest

CLI = os.environ["TASKMAP_CLI"]
SRC = os.environ["TASKMAP_SOURCE_DIR"]
BUILD = os.environ["TASKMAP_BUILD_DIR"]
MAP = os.path.join(SRC, "meshes", "maps", "basket_humanoid.h5")  # checked-in reference map
os.environ["TASKMAP_DATA_DIR"] = os.path.join(BUILD, "share", "taskmap")

import taskmap  # noqa: E402  (after TASKMAP_DATA_DIR is set)


def read(path):
    with open(path, "rb") as f:
        return f.read()


class ExportTest(unittest.TestCase):
    def test_every_format_is_what_the_cli_writes(self):
        with tempfile.TemporaryDirectory() as d:
            for fmt, extra in (("ply", []), ("glb", ["--glyph-size", "0.02"]),
                               ("acronym", ["--palm-offset", "0.1", "--density", "500"])):
                cli_out, py_out = os.path.join(d, "cli." + fmt), os.path.join(d, "py." + fmt)
                r = subprocess.run([CLI, "export", MAP, "--format", fmt, "-o", cli_out, *extra],
                                   capture_output=True, text=True)
                self.assertEqual(r.returncode, 0, r.stderr)
                kwargs = {"glb": {"glyph_size": 0.02},
                          "acronym": {"palm_offset": 0.1, "density": 500.0}}.get(fmt, {})
                self.assertEqual(taskmap.export(MAP, format=fmt, output=py_out, **kwargs), py_out)
                self.assertEqual(read(py_out), read(cli_out), fmt)

    def test_view_of_a_map_is_what_the_cli_writes(self):
        with tempfile.TemporaryDirectory() as d:
            cli_out, py_out = os.path.join(d, "cli.html"), os.path.join(d, "py.html")
            subprocess.run([CLI, "view", MAP, "-o", cli_out, "-q", "--ghosts", "20",
                            "--title", "basket"], check=True)
            taskmap.view(MAP, output=py_out, ghosts=20, title="basket")
            self.assertEqual(read(py_out), read(cli_out))
            # A hand that is not the map's: a warning and palms only, as the CLI warns.
            barrett = os.path.join(SRC, "meshes", "hands", "barrett", "barrett.urdf")
            r = subprocess.run([CLI, "view", MAP, "-o", cli_out, "--hand", barrett],
                               capture_output=True, text=True)
            self.assertIn("warning: drawing palms only", r.stderr)
            with self.assertWarns(UserWarning):
                taskmap.view(MAP, output=py_out, hand=barrett)
            self.assertEqual(read(py_out), read(cli_out))

    def test_bad_arguments_are_refused_naming_them(self):
        with tempfile.TemporaryDirectory() as d:
            with self.assertRaisesRegex(taskmap.Error, "unknown format 'obj'"):
                taskmap.export(MAP, format="obj", output=os.path.join(d, "m.obj"))
            with self.assertRaisesRegex(taskmap.Error, "MAP|basket_humanoid"):
                taskmap.export(MAP, format="ply", output=MAP)  # never over its input
            with self.assertRaisesRegex(taskmap.Error, "does not exist"):
                taskmap.view(os.path.join(d, "none.h5"))
            with self.assertRaisesRegex(taskmap.Error, "ghost"):
                taskmap.view(MAP, output=os.path.join(d, "v.html"), ghosts=0)
            self.assertEqual(os.listdir(d), [])


if __name__ == "__main__":
    unittest.main()
