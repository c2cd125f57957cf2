"""Deterministic mutation fuzzing through the CLI and the Python module (hostile files).

Mutants (fixed seeds: bit flips, zeroed blocks, truncations, huge numbers) of a real map
(tests/data/maps/box_barrett.h5) go through `taskmap inspect --json` and `taskmap.load`;
mutants of a box in every bounded mesh format (tests/data/meshes/fuzz/) go through
`taskmap mesh-info`; mutants of the map go through `taskmap.seal` too (each parsed in its
bounded child). Each case has a time limit; the Python workers run with CPU and address-space
limits. Required: no crash, no hang, every refusal
names the file and says what is wrong, no accepted map whose grasps differ from the original,
and peak memory of a mesh load within a fixed margin of loading the original. Prints a table
of outcomes per format.
"""
import collections
import json
import os
import random
import select
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

CLI = os.environ.get("TASKMAP_CLI", "taskmap")
SRC = os.environ.get("TASKMAP_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
DATA = os.path.join(SRC, "tests", "data")
MAP = os.path.join(DATA, "maps", "box_barrett.h5")
MESHES = ["box.obj", "box.off", "box_ascii.ply", "box_binary.ply", "box_ascii.stl",
          "box_binary.stl"]
MAP_MUTANTS = 200
SEAL_MUTANTS = 40
WORKER_ADDRESS_SPACE = 4 << 30  # bytes
WORKER_CPU_SECONDS = 600
MESH_MUTANTS = 100
SECONDS = 20.0
KINDS = ("bit_flips", "zeroed_block", "truncation", "huge_number")
HUGE = (b"99999999999999999999", b"4294967296", b"2147483648", b"-1", b"1e308", b"nan")


def mutate(data, seed, index):
    """Mutant `index` of data; the kind cycles with index."""
    rng = random.Random(seed * 1000003 + index)
    b = bytearray(data)
    kind = KINDS[index % 4]
    if kind == "bit_flips":
        for _ in range(rng.randint(1, 8)):
            b[rng.randrange(len(b))] ^= 1 << rng.randrange(8)
    elif kind == "zeroed_block":
        at = rng.randrange(len(b))
        n = rng.randint(1, 256)
        b[at:at + n] = bytes(len(b[at:at + n]))
    elif kind == "truncation":
        del b[rng.randrange(len(b)):]
    else:
        starts = [i for i in range(len(b)) if chr(b[i]).isdigit() and (i == 0 or chr(b[i - 1]).isspace())]
        if starts and 0 not in data:
            at = rng.choice(starts)
            end = at
            while end < len(b) and not chr(b[end]).isspace():
                end += 1
            b[at:end] = rng.choice(HUGE)
        else:
            at = rng.randrange(len(b))
            width = rng.choice((4, 8))
            b[at:at + width] = (b"\xff" * 8 if rng.random() < 0.5 else b"\xff" * 7 + b"\x7f")[:width]
    return kind, bytes(b)


def run_limited(cmd, seconds=SECONDS):
    """Runs cmd; returns (returncode or None on timeout, stdout, stderr, peak RSS in KiB)."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        proc = subprocess.Popen(cmd, stdout=out, stderr=err)
        deadline = time.monotonic() + seconds
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid == proc.pid:
                break
            if time.monotonic() > deadline:
                proc.kill()
                os.wait4(proc.pid, 0)
                proc.returncode = 0
                return None, "", "", 0
            time.sleep(0.002)
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        return (proc.returncode, out.read().decode(errors="replace"),
                err.read().decode(errors="replace"), usage.ru_maxrss)


WORKER = r"""
import json, sys
import numpy as np
import taskmap
ref = taskmap.load(sys.argv[1])
def arrays(m):
    return [np.asarray(m.poses), np.asarray(m.epsilon)]
expected = arrays(ref)
for line in sys.stdin:
    op, path = line.strip().split(" ", 1)
    try:
        if op == "seal":
            taskmap.seal(path)
        m = taskmap.load(path)
        same = len(m) == len(ref) and all(np.array_equal(a, b) for a, b in zip(arrays(m), expected))
        reply = {"outcome": "accepted", "same": bool(same)}
    except taskmap.Error as e:
        reply = {"outcome": "refused", "message": str(e)}
    except MemoryError as e:
        reply = {"outcome": "memory", "message": "MemoryError: %s" % e}
    except Exception as e:
        reply = {"outcome": "other_exception", "message": "%s: %s" % (type(e).__name__, e)}
    print(json.dumps(reply), flush=True)
"""


def limit_worker():
    """In the worker child before exec: CPU-time and address-space limits."""
    import resource
    resource.setrlimit(resource.RLIMIT_AS, (WORKER_ADDRESS_SPACE, WORKER_ADDRESS_SPACE))
    resource.setrlimit(resource.RLIMIT_CPU, (WORKER_CPU_SECONDS, WORKER_CPU_SECONDS))


class PythonWorker:
    """A python process (CPU and memory limits) that loads or seals maps on request; killed and
    restarted on a hang or crash."""

    def __init__(self, reference):
        self.reference = reference
        self.proc = None

    def start(self):
        self.proc = subprocess.Popen([sys.executable, "-c", WORKER, self.reference],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                                     preexec_fn=limit_worker)

    def load(self, path, op="load"):
        if self.proc is None:
            self.start()
        self.proc.stdin.write(op + " " + path + "\n")
        self.proc.stdin.flush()
        ready, _, _ = select.select([self.proc.stdout], [], [], SECONDS)
        if not ready:
            self.stop()
            return {"outcome": "hang"}
        line = self.proc.stdout.readline()
        if not line:
            code = self.proc.wait()
            self.proc = None
            return {"outcome": "crash", "message": "exit %s" % code}
        return json.loads(line)

    def stop(self):
        if self.proc is not None:
            self.proc.kill()
            self.proc.wait()
            self.proc = None


class FuzzTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="taskmap_fuzz_")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def report(self, title, table):
        print("\n[fuzz] %s" % title, file=sys.stderr)
        for key, counts in table.items():
            print("[fuzz]   %-16s %s" % (key, ", ".join("%s %d" % kv for kv in sorted(counts.items()))),
                  file=sys.stderr)

    def check_refusal(self, where, path, message):
        self.assertIn(os.path.basename(path), message, where)
        self.assertNotIn("HDF5-DIAG", message, where)
        self.assertGreater(len(message), len(path) + 20, where)

    def test_map_mutants_through_cli_and_python(self):
        with open(MAP, "rb") as f:
            original = f.read()
        rc, reference, err, _ = run_limited([CLI, "inspect", "--json", MAP])
        self.assertEqual(rc, 0, err)
        reference = json.loads(reference)
        worker = PythonWorker(MAP)
        table = collections.defaultdict(collections.Counter)
        try:
            for i in range(MAP_MUTANTS):
                kind, data = mutate(original, 18, i)
                path = os.path.join(self.tmp, "mutant_%03d.h5" % i)
                with open(path, "wb") as f:
                    f.write(data)
                where = "%s (%s)" % (path, kind)
                rc, out, err, _ = run_limited([CLI, "inspect", "--json", path])
                self.assertIsNotNone(rc, "taskmap inspect hung on " + where)
                self.assertIn(rc, (0, 1), "taskmap inspect crashed (%s) on %s" % (rc, where))
                if rc == 0:
                    got = json.loads(out)
                    got["path"] = reference["path"]
                    self.assertEqual(got, reference, "accepted a changed map: " + where)
                    table["cli " + kind]["accepted identical"] += 1
                else:
                    self.check_refusal(where, path, err)
                    table["cli " + kind]["refused"] += 1
                reply = worker.load(path)
                self.assertNotIn(reply["outcome"], ("hang", "crash", "memory"), "python: %s on %s" % (reply, where))
                self.assertNotEqual(reply["outcome"], "other_exception", "python: %s" % reply)
                if reply["outcome"] == "accepted":
                    self.assertTrue(reply["same"], "python accepted a changed map: " + where)
                    table["python " + kind]["accepted identical"] += 1
                else:
                    self.check_refusal(where, path, reply["message"])
                    table["python " + kind]["refused"] += 1
                os.remove(path)
        finally:
            worker.stop()
        self.report("map mutants (%d each through the CLI and Python)" % MAP_MUTANTS, table)

    def test_map_mutants_through_python_seal(self):
        """taskmap.seal on mutants of a map: sealed (then loads) or refused naming the file."""
        with open(MAP, "rb") as f:
            original = f.read()
        worker = PythonWorker(MAP)
        table = collections.defaultdict(collections.Counter)
        try:
            for i in range(SEAL_MUTANTS):
                kind, data = mutate(original, 32, i)
                path = os.path.join(self.tmp, "seal_%03d.h5" % i)
                with open(path, "wb") as f:
                    f.write(data)
                where = "%s (%s)" % (path, kind)
                reply = worker.load(path, "seal")
                table["seal " + kind][reply["outcome"]] += 1
                self.assertNotIn(reply["outcome"], ("hang", "crash", "memory"),
                                 "python seal: %s on %s" % (reply, where))
                self.assertNotEqual(reply["outcome"], "other_exception", "python seal: %s" % reply)
                if reply["outcome"] == "refused":
                    self.check_refusal(where, path, reply["message"])
                for leftover in os.listdir(self.tmp):
                    self.assertFalse(leftover.startswith("seal_%03d.h5." % i),
                                     "seal left a temporary file: " + leftover)
                os.remove(path)
        finally:
            worker.stop()
        self.report("map mutants through taskmap.seal (%d, then taskmap.load)" % SEAL_MUTANTS, table)

    def test_mesh_mutants_through_cli(self):
        table = collections.defaultdict(collections.Counter)
        worst = {}
        for name in MESHES:
            src = os.path.join(DATA, "meshes", "fuzz", name)
            with open(src, "rb") as f:
                original = f.read()
            rc, _, err, base_kib = run_limited([CLI, "mesh-info", src])
            self.assertEqual(rc, 0, err)
            worst[name] = 0
            for i in range(MESH_MUTANTS):
                kind, data = mutate(original, 18, i)
                path = os.path.join(self.tmp, "m%02d_%s" % (i, name))
                with open(path, "wb") as f:
                    f.write(data)
                where = "%s (%s)" % (path, kind)
                rc, out, err, kib = run_limited([CLI, "mesh-info", path])
                self.assertIsNotNone(rc, "taskmap mesh-info hung on " + where)
                self.assertIn(rc, (0, 1), "taskmap mesh-info crashed (%s) on %s" % (rc, where))
                if rc == 1:
                    self.check_refusal(where, path, err)
                    self.assertNotIn("bad_alloc", err, where)
                table[name]["accepted" if rc == 0 else "refused"] += 1
                # Peak memory: within 32 MiB of loading the original (files are < 2 KiB).
                self.assertLess(kib - base_kib, 32 * 1024, "%s: peak RSS %d KiB" % (where, kib))
                worst[name] = max(worst[name], kib - base_kib)
                os.remove(path)
        self.report("mesh mutants (%d per format through taskmap mesh-info)" % MESH_MUTANTS, table)
        print("[fuzz]   worst peak RSS over loading the original, KiB: %s" % worst, file=sys.stderr)

    def test_every_reader_refuses_a_damaged_map(self):
        """inspect, cluster, export and taskmap.load all go through the verified reader."""
        with open(MAP, "rb") as f:
            data = bytearray(f.read())
        data[len(data) // 2] ^= 0x01
        path = os.path.join(self.tmp, "one_bit.h5")
        with open(path, "wb") as f:
            f.write(data)
        out = os.path.join(self.tmp, "out.ply")
        for args in (["inspect", path], ["cluster", path], ["export", path, "--format", "ply",
                                                             "-o", out]):
            rc, _, err, _ = run_limited([CLI, *args])
            self.assertEqual(rc, 1, args)
            self.assertIn("one_bit.h5", err)
            self.assertIn("does not match its seal", err)
        self.assertFalse(os.path.exists(out))
        worker = PythonWorker(MAP)
        try:
            reply = worker.load(path)
        finally:
            worker.stop()
        self.assertEqual(reply["outcome"], "refused")
        self.assertIn("does not match its seal", reply["message"])
        with open(path, "rb") as f:
            self.assertEqual(f.read(), bytes(data))  # cluster wrote nothing

    def test_acronym_import_bounds_what_it_reads(self):
        """A foreign HDF5 file declaring 1.6e9 values in a few KiB is refused, not allocated."""
        import h5py
        src = os.path.join(self.tmp, "bomb.h5")
        with h5py.File(src, "w") as f:
            f.create_dataset("grasps/transforms", shape=(10 ** 8, 4, 4), dtype="f8",
                             chunks=(1024, 4, 4), compression="gzip")
            f["grasps/qualities/flex/object_in_gripper"] = np.zeros(10 ** 8 // 10 ** 6)
        self.assertLess(os.path.getsize(src), 64 * 1024)
        out = os.path.join(self.tmp, "never.h5")
        rc, _, err, kib = run_limited([CLI, "import", "--acronym", src, "--object",
                                       os.path.join(DATA, "meshes", "fuzz", "box.obj"), "-o", out])
        self.assertEqual(rc, 1, err)
        self.assertIn("bomb.h5", err)
        self.assertIn("grasps/transforms declares more values than the file holds", err)
        self.assertLess(kib, 512 * 1024)
        self.assertFalse(os.path.exists(out))


if __name__ == "__main__":
    unittest.main()
