#!/usr/bin/python3
"""Throughput of taskmap-mpi build against taskmap build on the same cores.

Every run simulates exactly --trials trials (the valid target is out of reach), so trials per
second compare like with like. Configurations run interleaved, --repeats rounds, and the median
of each is reported with its ratio to the baseline `taskmap build --threads <cores>` (measured in
the same rounds, so a loaded machine slows both alike). Two rates: the trial phase as the tool
reports it, and end to end (process start to exit: mpirun start-up, set-up on every rank,
clustering and writing included); and the CPU time per trial of all processes (mpirun and the
ranks included), which a loaded machine changes least: its ratio is the cost of MPI.

  tests/bench/mpi/mpi_bench.py --build build [--trials 20000] [--repeats 3] [--cores 2]
"""
import argparse
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(cmd, env):
    t0, cpu0 = time.monotonic(), children_cpu()
    p = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall, cpu = time.monotonic() - t0, children_cpu() - cpu0
    if p.returncode != 0:
        sys.exit("failed: %s\n%s" % (" ".join(cmd), p.stdout))
    m = re.search(r"trials ([0-9.]+) s \((\d+) simulated, ([0-9.]+) trials/s\)", p.stdout)
    if not m:
        sys.exit("no timing line in:\n" + p.stdout)
    return int(m.group(2)), float(m.group(3)), int(m.group(2)) / wall, 1e6 * cpu / int(m.group(2))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--trials", type=int, default=20000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--cores", type=int, default=len(os.sched_getaffinity(0)))
    ap.add_argument("--object", default=os.path.join(ROOT, "meshes", "objects", "basket.obj"))
    ap.add_argument("--hand", default="barrett")
    args = ap.parse_args()
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               SOURCE_DATE_EPOCH="1700000000")
    tmp = tempfile.mkdtemp(prefix="taskmap_mpi_bench_")
    out = os.path.join(tmp, "map.h5")
    common = ["build", "--object", args.object, "--hand", args.hand, "--valid", "1000000000",
              "--trials", str(args.trials), "--seed", "1", "--no-cluster", "-o", out]
    taskmap = os.path.join(args.build, "bin", "taskmap")
    mpi = os.path.join(args.build, "bin", "taskmap-mpi")
    mpirun = ["mpirun", "--oversubscribe", "--bind-to", "none"]
    c = args.cores
    configs = [("taskmap build, %d threads (baseline)" % c, [taskmap] + common + ["--threads", str(c)])]
    for ranks in (1, 2, 4):
        threads = max(1, c // ranks) if ranks > 1 else c
        configs.append(("taskmap-mpi, %d rank%s x %d thread%s" % (
            ranks, "s" if ranks > 1 else "", threads, "s" if threads > 1 else ""),
            mpirun + ["-n", str(ranks), mpi] + common + ["--threads", str(threads)]))
    results = {name: ([], [], []) for name, _ in configs}
    for _ in range(args.repeats):
        for name, cmd in configs:
            simulated, phase, end_to_end, cpu = run(cmd, env)
            assert simulated == args.trials, (simulated, args.trials)
            for k, v in enumerate((phase, end_to_end, cpu)):
                results[name][k].append(v)
    base = [statistics.median(v) for v in results[configs[0][0]]]
    print("%d trials of %s with %s on %d cores, median of %d rounds" % (
        args.trials, os.path.basename(args.object), args.hand, c, args.repeats))
    print("%-38s %13s %6s %13s %6s %12s %6s" % ("configuration", "trial phase/s", "ratio",
                                                "end-to-end/s", "ratio", "CPU us/trial", "ratio"))
    for name, _ in configs:
        phase, e2e, cpu = (statistics.median(v) for v in results[name])
        print("%-38s %13.0f %6.2f %13.0f %6.2f %12.0f %6.2f" % (
            name, phase, phase / base[0], e2e, e2e / base[1], cpu, cpu / base[2]))
    if os.path.exists(out):
        os.remove(out)
    os.rmdir(tmp)


if __name__ == "__main__":
    main()
