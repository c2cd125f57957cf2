"""Hostile inputs through the Python module (issue 32): FIFOs and directories are refused at
once with taskmap.Error naming the file (opening a FIFO must not wait for a writer)."""
import os
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


if __name__ == "__main__":
    unittest.main()
