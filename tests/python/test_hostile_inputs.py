"""Hostile inputs through the Python module (issue 32): FIFOs are refused at once with
taskmap.Error naming the file (opening a FIFO must not wait for a writer); taskmap.seal on a tiny
file declaring a huge sparse dataset is refused within the parse limits, not by exhausting the
process."""
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest


class HostileInputs(unittest.TestCase):
    def test_fifo_refused_by_load_and_seal(self):
        with tempfile.TemporaryDirectory() as d:
            fifo = os.path.join(d, "pipe.h5")
            os.mkfifo(fifo)
            # In a child with a timeout, so that a regression hangs the child, not the suite.
            code = ("import taskmap, sys\n"
                    "for f in (taskmap.load, taskmap.seal):\n"
                    "    try:\n"
                    "        f(sys.argv[1])\n"
                    "    except taskmap.Error as e:\n"
                    "        print(e)\n"
                    "    else:\n"
                    "        print('accepted')\n")
            t0 = time.monotonic()
            r = subprocess.run([sys.executable, "-c", code, fifo], capture_output=True, text=True,
                               timeout=30, env=os.environ)
            self.assertLess(time.monotonic() - t0, 20)
            self.assertEqual(r.returncode, 0, r.stderr)
            lines = r.stdout.strip().splitlines()
            self.assertEqual(len(lines), 2, r.stdout)
            for line in lines:
                self.assertIn("FIFO", line)
                self.assertIn(fifo, line)

    def test_seal_of_a_sparse_huge_dataset_is_bounded(self):
        import h5py
        src = os.path.join(os.environ.get("TASKMAP_SOURCE_DIR", "../.."), "tests", "data", "maps",
                           "box_barrett.h5")
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "sparse.h5")
            shutil.copy(src, path)
            with h5py.File(path, "r+") as f:
                del f["grasps/pose"]
                f.create_dataset("grasps/pose", shape=(100000000, 7), dtype="f8",
                                 chunks=(4096, 7))
            self.assertLess(os.path.getsize(path), 1 << 20)
            code = ("import resource, sys, taskmap\n"
                    "try:\n"
                    "    taskmap.seal(sys.argv[1])\n"
                    "    print('accepted')\n"
                    "except taskmap.Error as e:\n"
                    "    print(e)\n"
                    "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)\n")
            t0 = time.monotonic()
            r = subprocess.run([sys.executable, "-c", code, path], capture_output=True, text=True,
                               timeout=120, env=os.environ)
            seconds = time.monotonic() - t0
            self.assertEqual(r.returncode, 0, r.stderr)
            message, maxrss = r.stdout.strip().splitlines()[-2:]
            self.assertNotEqual(message, "accepted")
            self.assertIn(path, message)
            self.assertLess(int(maxrss), 1024 * 1024, "KiB: the caller stayed small")
            print("seal of a sparse 100M x 7 dataset: %s (%.2f s, caller %s KiB)"
                  % (message, seconds, maxrss))


if __name__ == "__main__":
    unittest.main()
