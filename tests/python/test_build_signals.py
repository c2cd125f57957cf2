"""Ctrl-C (SIGINT), SIGTERM and SIGKILL during `taskmap build` never leave a half-written map:
the output path holds either nothing or the previous map, untouched. Ctrl-C during `taskmap
dataset` stops the running job unwritten and leaves it pending in the manifest (exit 130)."""
import hashlib
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

import h5py

from test_map_schema import write_box_obj

CLI = os.environ.get("TASKMAP_CLI", "taskmap")


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


class BuildSignalsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="taskmap_signals_")
        cls.obj = os.path.join(cls.tmp, "box.obj")
        write_box_obj(cls.obj)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def command(self, out, valid, trials=10_000_000):
        return [CLI, "build", "--object", self.obj, "--hand", "panda", "--valid", str(valid),
                "--trials", str(trials), "--seed", "5", "--threads", "2", "-o", out]

    def start_long_build(self, out):
        proc = subprocess.Popen(self.command(out, 1_000_000), stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
        time.sleep(1.5)  # well into the trials
        self.assertIsNone(proc.poll(), "the long build ended early")
        return proc

    def test_sigint_writes_nothing(self):
        out = os.path.join(self.tmp, "sigint.h5")
        proc = self.start_long_build(out)
        start = time.time()
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
        self.assertLess(time.time() - start, 30, "Ctrl-C did not stop the build promptly")
        self.assertEqual(proc.returncode, 130, err)
        self.assertIn("interrupted", err)
        self.assertIn("nothing written", err)
        self.assertFalse(os.path.exists(out))
        self.assertEqual([n for n in os.listdir(self.tmp) if n.startswith("sigint")], [])

    def test_sigterm_keeps_previous_map(self):
        out = os.path.join(self.tmp, "sigterm.h5")
        subprocess.run(self.command(out, 3), check=True, capture_output=True, timeout=300)
        before = digest(out)
        proc = self.start_long_build(out)
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
        self.assertEqual(proc.returncode, 130, err)
        self.assertEqual(digest(out), before)

    def test_sigkill_keeps_previous_map(self):
        out = os.path.join(self.tmp, "sigkill.h5")
        subprocess.run(self.command(out, 3), check=True, capture_output=True, timeout=300)
        before = digest(out)
        proc = self.start_long_build(out)
        proc.kill()
        proc.communicate(timeout=60)
        self.assertEqual(proc.returncode, -signal.SIGKILL)
        self.assertEqual(digest(out), before)

    def test_sigkill_at_any_moment_leaves_no_partial_map(self):
        # Kills at spread-out moments of a short build, including during the write: the path
        # holds either no file or a complete, readable map.
        for i, delay in enumerate((0.05, 0.3, 0.6, 0.9, 1.2, 1.6, 2.0, 3.0)):
            out = os.path.join(self.tmp, "kill_%d.h5" % i)
            proc = subprocess.Popen(self.command(out, 8), stdout=subprocess.DEVNULL,
                                    stderr=subprocess.DEVNULL)
            time.sleep(delay)
            proc.kill()
            proc.wait(timeout=60)
            if os.path.exists(out):
                with h5py.File(out, "r") as f:
                    self.assertEqual(f.attrs["format"], b"taskmap")  # fixed-length string
                    self.assertEqual(f["grasps/pose"].shape[0], 8)
                    self.assertEqual(int(f["sampling"].attrs["outcome_force_closure"]), 8)
        # Sanity: an uninterrupted build of the same size completes.
        out = os.path.join(self.tmp, "kill_none.h5")
        subprocess.run(self.command(out, 8), check=True, capture_output=True, timeout=300)
        self.assertTrue(os.path.exists(out))


    def test_sigint_stops_a_dataset_and_leaves_its_job_pending(self):
        d = os.path.join(self.tmp, "dataset")
        objects = os.path.join(self.tmp, "objects.txt")
        with open(objects, "w") as f:
            f.write("box.obj\n")
        proc = subprocess.Popen([CLI, "dataset", "--objects", objects, "--hands", "panda",
                                 "--valid", "1000000", "--trials", "10000000", "--seed", "5",
                                 "--threads", "2", "-o", d], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
        time.sleep(2.0)  # into the first job's trials
        self.assertIsNone(proc.poll(), "the long data set ended early")
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
        self.assertEqual(proc.returncode, 130, err)
        self.assertIn("interrupted", err)
        with open(os.path.join(d, "manifest.json")) as f:
            manifest = json.load(f)
        self.assertEqual([j["status"] for j in manifest["jobs"]], ["pending"])
        self.assertEqual([n for n in os.listdir(d) if n.endswith(".h5")], [])


if __name__ == "__main__":
    unittest.main()
