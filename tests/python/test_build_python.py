"""taskmap.build and taskmap.dataset (python/src/builder_bindings.cpp): the same map bytes and
manifest as `taskmap build` / `taskmap dataset` with the same options; progress callbacks;
Ctrl-C (SIGINT to a Python process building a map) raises KeyboardInterrupt and writes nothing;
an exception from the callback stops the build and reaches the caller; option errors."""
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import textwrap
import unittest

import taskmap
from test_map_schema import write_box_obj

CLI = os.environ.get("TASKMAP_CLI", "taskmap")

# A child that builds a long map, says "started" from its first progress report, and reports
# what Ctrl-C did.
CHILD = textwrap.dedent("""
    import json, os, sys
    import taskmap
    obj, out = sys.argv[1], sys.argv[2]
    started = []
    def progress(p):
        if not started:
            started.append(1)
            print("started", flush=True)
    try:
        taskmap.build(object=obj, hand="panda", output=out, valid=1000000, trials=100000000,
                      threads=2, progress=progress)
        result = "finished"
    except KeyboardInterrupt:
        result = "KeyboardInterrupt"
    print(json.dumps({"result": result, "exists": os.path.exists(out)}), flush=True)
""")


class BuildPythonTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="taskmap_pybuild_")
        cls.obj = os.path.join(cls.tmp, "box.obj")
        write_box_obj(cls.obj)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.tmp, name)

    def bytes_of(self, name):
        with open(self.path(name), "rb") as f:
            return f.read()

    def test_same_map_bytes_as_the_cli(self):
        # The default build: its grasps tested in physics, their labels stored (same bytes).
        knobs = ["--valid", "4", "--seed", "7", "--sampler", "surface", "--friction", "0.6"]
        subprocess.run([CLI, "build", "--object", self.obj, "--hand", "panda", "-q", "-o",
                        self.path("cli.h5")] + knobs, check=True)
        reports = []
        m = taskmap.build(object=self.obj, hand="panda", output=self.path("py.h5"), valid=4,
                          seed=7, sampler="surface", friction=0.6, threads=2,
                          progress=reports.append)
        self.assertEqual(self.bytes_of("py.h5"), self.bytes_of("cli.h5"))
        self.assertEqual(len(m), len(taskmap.load(self.path("cli.h5"))))
        self.assertGreaterEqual(len(reports), 1)
        self.assertEqual(reports[-1]["valid_target"], 4)
        self.assertIsNotNone(m.robust)
        self.assertEqual(int(m.robust.sum()), 4)
        self.assertLessEqual(reports[-1]["trials_done"], reports[-1]["max_trials"])

    def test_same_data_set_as_the_cli(self):
        objects = self.path("objects.txt")
        with open(objects, "w") as f:
            f.write("box.obj\nmissing.obj\n")
        subprocess.run([CLI, "dataset", "--objects", objects, "--hands", "panda,barrett",
                        "--valid", "3", "--trials", "4000", "-q", "-o", self.path("ds_cli")])
        jobs = []
        r = taskmap.dataset(objects=objects, hands=["panda", "barrett"],
                            output=self.path("ds_py"), valid=3, trials=4000,
                            progress=jobs.append)
        self.assertEqual((r["jobs"], r["skipped"], r["failed"]), (4, 0, 2))
        self.assertEqual(sorted(os.listdir(self.path("ds_py"))),
                         sorted(os.listdir(self.path("ds_cli"))))
        for name in ["manifest.json", "box__panda.h5", "box__barrett.h5"]:
            self.assertEqual(self.bytes_of(os.path.join("ds_py", name)),
                             self.bytes_of(os.path.join("ds_cli", name)), name)
        self.assertEqual([j["done"] for j in jobs], [1, 2, 3, 4])
        self.assertEqual(sorted(j["entry"]["status"] for j in jobs),
                         ["complete", "complete", "failed", "failed"])
        again = taskmap.dataset(objects=objects, hands=["panda", "barrett"],
                                output=self.path("ds_py"), valid=3, trials=4000)
        self.assertEqual(again["skipped"], 2)

    def test_ctrl_c_raises_keyboard_interrupt_and_writes_nothing(self):
        out = self.path("sigint.h5")
        proc = subprocess.Popen([sys.executable, "-c", CHILD, self.obj, out],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.assertEqual(proc.stdout.readline().strip(), "started")
        proc.send_signal(signal.SIGINT)
        stdout, stderr = proc.communicate(timeout=60)
        self.assertEqual(proc.returncode, 0, stderr)
        self.assertEqual(json.loads(stdout), {"result": "KeyboardInterrupt", "exists": False})
        self.assertEqual([n for n in os.listdir(self.tmp) if n.startswith("sigint")], [])

    def test_an_exception_from_the_callback_stops_the_build(self):
        def fail(report):
            raise RuntimeError("stop here")
        with self.assertRaisesRegex(RuntimeError, "stop here"):
            taskmap.build(object=self.obj, hand="panda", output=self.path("cb.h5"),
                          valid=1000000, trials=100000000, threads=2, progress=fail)
        self.assertFalse(os.path.exists(self.path("cb.h5")))

    def test_bundled_objects_by_name(self):
        # Objects are named like hands: "box" is <data dir>/objects/box.obj.
        m = taskmap.build(object="box", hand="panda", output=self.path("named.h5"), valid=3,
                          seed=1, hold_test="off")
        self.assertEqual(len(m), 3)
        self.assertTrue(taskmap.mesh_info("basket")["closed"])
        with self.assertRaisesRegex(taskmap.Error, "did you mean 'basket'"):
            taskmap.mesh_info("baskt")

    def test_errors_name_the_option(self):
        with self.assertRaisesRegex(taskmap.Error, "keep_holding needs validate"):
            taskmap.build(object=self.obj, hand="panda", output=self.path("e.h5"),
                          keep_holding=True)
        with self.assertRaisesRegex(taskmap.Error, "did you mean 'panda'"):
            taskmap.build(object=self.obj, hand="pandaa", output=self.path("e.h5"))
        with self.assertRaisesRegex(taskmap.Error, "does not exist; create it first"):
            taskmap.build(object=self.obj, hand="panda", output="/nonexistent/dir/m.h5")
        with self.assertRaises(TypeError):  # keyword arguments only, named as the CLI's
            taskmap.build(self.obj, "panda", self.path("e.h5"))
        with self.assertRaisesRegex(taskmap.Error, "cone_edges must be within \\[3, 64\\]"):
            taskmap.build(object=self.obj, hand="panda", output=self.path("e.h5"), cone_edges=2)
        with self.assertRaisesRegex(TypeError, "unexpected keyword argument 'cone_edge'"):
            taskmap.build(object=self.obj, hand="panda", output=self.path("e.h5"), cone_edge=8)
        with self.assertRaisesRegex(TypeError, "valid must be a non-negative int, not str"):
            taskmap.build(object=self.obj, hand="panda", output=self.path("e.h5"), valid="10")
        self.assertFalse(os.path.exists(self.path("e.h5")))

    def test_every_cli_command_is_a_python_call(self):
        # Library first: what a command computes, Python calls; a new command needs its call.
        text = subprocess.run([CLI, "--help"], capture_output=True, text=True, check=True).stdout
        commands = re.findall(r"^  ([a-z][a-z-]*)\s", text.split("Subcommands:")[1], re.M)
        python = {"build": "build", "dataset": "dataset", "import": "import_acronym",
                  "cluster": "recluster", "regress": "regress", "validate": "validate",
                  "inspect": "summary", "hand-info": "hand_info", "hand-init": "hand_init",
                  "mesh-info": "mesh_info", "export": "export", "export-glb": "export_glb",
                  "view": "view", "reach": "reach", "seal": "seal"}
        self.assertGreaterEqual(len(commands), 15)
        for command in commands:
            with self.subTest(command=command):
                self.assertIn(command, python)
                self.assertTrue(callable(getattr(taskmap, python[command])))
        self.assertTrue(callable(taskmap.picture))  # inspect --png

    def test_every_cli_option_is_a_keyword(self):
        # The knobs come from one list (taskmap/builder/build_knobs.hpp): every option of
        # `taskmap build --help` is a keyword of taskmap.build and of taskmap.dataset, except the
        # command line's own (-q, --progress, --package-path, --help) and the files and mesh
        # options, which are taskmap.build's own parameters.
        text = subprocess.run([CLI, "build", "--help"], capture_output=True, text=True,
                              check=True).stdout
        options = sorted(set(re.findall(r"^\s+(?:-\w,)?(--[a-z][a-z0-9-]*)", text, re.M)))
        cli_only = {"--quiet", "--progress", "--package-path", "--help"}
        files = {"object", "hand", "output", "scale", "no_repair", "repair", "wrap_alpha",
                 "wrap_offset", "force"}
        names = [o[2:].replace("-", "_") for o in options if o not in cli_only]
        for name in files:  # the files and mesh options: parameters of taskmap.build
            self.assertIn(name, names)
            self.assertIn(name, taskmap.build.__doc__)
        names = [n for n in names if n not in files]
        self.assertIn("cone_edges", names)
        self.assertIn("contacts_per_link", names)
        for function in (taskmap.build, taskmap.dataset):
            for name in names:
                with self.subTest(function=function.__name__, name=name):
                    self.assertIn(name, function.__doc__)
                    kwargs = {name: object()}  # a value of no knob's type
                    if function is taskmap.build:
                        kwargs.update(object=self.obj, hand="panda", output=self.path("k.h5"))
                    else:
                        kwargs.update(objects=self.obj, hands=["panda"],
                                      output=self.path("kdir"))
                    try:
                        function(**kwargs)
                    except TypeError as e:  # refused for its type, not as an unknown name
                        self.assertNotIn("unexpected keyword", str(e))
                    else:
                        self.fail(name + " accepted an object()")
        self.assertFalse(os.path.exists(self.path("k.h5")))


if __name__ == "__main__":
    unittest.main()
