#!/usr/bin/python3
"""Re-measures the table of docs/HOSTILE_INPUTS.md (issue 32): each hostile input made here,
run through the built tools; prints one Markdown row per case with the outcome, wall time and
the tool's peak RSS (GNU time's %M of the tool's process; a bounded parse child's own use is
at most its limit and not included).

Usage: tools/measure_hostile_inputs.py BUILD_DIR   (needs BUILD_DIR/bin/taskmap, /usr/bin/python3
with numpy and h5py, the taskmap Python module in BUILD_DIR/python; taskmap-mpi and mpirun
optional)
"""
import os
import shutil
import subprocess
import sys
import tempfile
import time
import zipfile

BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "build")
SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
TASKMAP = os.path.join(BUILD, "bin", "taskmap")
MPI = os.path.join(BUILD, "bin", "taskmap-mpi")
BOX = os.path.join(SRC, "meshes", "objects", "box.obj")
BOX_SIDECAR = ("{\"palm_link\": \"base\", \"approach_axis\": [0, 0, 1], \"preshape\": {\"j1\": 0.0},"
               " \"closing\": [{\"joint\": \"j1\", \"toward\": \"lower\", \"speed\": 1}],"
               " \"squeeze\": 0.001, \"fingers\": {\"a\": [\"l1\"]}}")
BOXGEOM = "<collision><geometry><box size=\"0.01 0.01 0.01\"/></geometry></collision>"


def run(cmd, timeout=120, env=None):
    """(exit code or 'timeout', seconds, peak RSS MiB, output) of cmd under /usr/bin/time (its
    own fork and exec: the peak RSS is the tool's alone, not inherited from this script)."""
    out = tempfile.TemporaryFile()
    stats = tempfile.NamedTemporaryFile(suffix=".time")
    t0 = time.monotonic()
    proc = subprocess.Popen(["/usr/bin/time", "-q", "-o", stats.name, "-f", "%M"] + cmd,
                            stdout=out, stderr=subprocess.STDOUT, env=env)
    try:
        code = proc.wait(timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        code = "timeout"
    seconds = time.monotonic() - t0
    out.seek(0)
    text = out.read().decode(errors="replace")
    try:
        kib = int(open(stats.name).read().split()[-1])
    except (ValueError, IndexError):
        kib = 0
    return code, seconds, kib / 1024, text


def row(name, result):
    code, seconds, mib, text = result
    lines = [l for l in text.splitlines() if not l.startswith("Command exited")]
    first = next((l for l in lines if "error" in l or "warning" in l),
                 lines[0] if lines else "")
    print("| %s | exit %s, %.2f s, %.0f MiB | %s |" % (name, code, seconds, mib, first[:220]),
          flush=True)


def chain_urdf(n):
    parts = ["<?xml version=\"1.0\"?>\n<robot name=\"chain\">\n<link name=\"base\">%s</link>\n" % BOXGEOM]
    for i in range(1, n + 1):
        parent = "base" if i == 1 else "l%d" % (i - 1)
        parts.append("<link name=\"l%d\">%s</link>\n<joint name=\"j%d\" type=\"revolute\"><parent "
                     "link=\"%s\"/><child link=\"l%d\"/><origin xyz=\"0 0 0.01\"/><axis xyz=\"1 0 0\"/>"
                     "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n"
                     % (i, BOXGEOM, i, parent, i))
    return "".join(parts) + "</robot>\n"


def write_hand(d, name, urdf):
    path = os.path.join(d, name + ".urdf")
    with open(path, "w") as f:
        f.write(urdf)
    with open(os.path.join(d, name + ".hand.json"), "w") as f:
        f.write(BOX_SIDECAR)
    return path


def missing_part_3mf(path):
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("[Content_Types].xml", '<?xml version="1.0" encoding="UTF-8"?>'
                   '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
                   '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
                   '<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>'
                   '</Types>')
        z.writestr("_rels/.rels", '<?xml version="1.0" encoding="UTF-8"?>'
                   '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
                   '<Relationship Target="/3D/missing.model" Id="rel0" '
                   'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>')


def vertex_bomb_3mf(path, vertices):
    """A valid 3MF package whose model holds `vertices` identical vertices and one triangle."""
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=9) as z:
        z.writestr("[Content_Types].xml", '<?xml version="1.0" encoding="UTF-8"?>'
                   '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
                   '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
                   '<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>'
                   '</Types>')
        z.writestr("_rels/.rels", '<?xml version="1.0" encoding="UTF-8"?>'
                   '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
                   '<Relationship Target="/3D/3dmodel.model" Id="rel0" '
                   'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>')
        with z.open("3D/3dmodel.model", "w", force_zip64=True) as m:
            m.write(b'<?xml version="1.0" encoding="UTF-8"?><model unit="millimeter" '
                    b'xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02"><resources>'
                    b'<object id="1" type="model"><mesh><vertices>')
            chunk = b'<vertex x="0" y="0" z="0"/>' * 100000
            for _ in range(vertices // 100000):
                m.write(chunk)
            m.write(b'</vertices><triangles><triangle v1="0" v2="1" v3="2"/></triangles></mesh>'
                    b'</object></resources><build><item objectid="1"/></build></model>')


def main():
    d = tempfile.mkdtemp(prefix="taskmap_hostile_")
    os.chdir(d)
    print("| input | now (exit, wall time, tool peak RSS) | message |\n|---|---|---|")
    missing_part_3mf("missing.3mf")
    print("<!-- missing.3mf: %d bytes -->" % os.path.getsize("missing.3mf"))
    row("3MF missing part: mesh-info", run([TASKMAP, "mesh-info", "missing.3mf"]))
    row("3MF missing part: build", run([TASKMAP, "build", "--object", "missing.3mf", "--hand",
                                         "panda", "--valid", "5", "-q", "-o", "m.h5"]))
    link = chain_urdf(1).replace('<box size="0.01 0.01 0.01"/>', '<mesh filename="missing.3mf"/>', 1)
    row("3MF missing part: hand-info (link mesh)", run([TASKMAP, "hand-info", write_hand(d, "h3mf", link)]))
    shutil.copy(BOX, "mybox.obj")
    with open("list.txt", "w") as f:
        f.write("mybox.obj\nmissing.3mf\n")
    row("3MF missing part: dataset", run([TASKMAP, "dataset", "--objects", "list.txt", "--hands",
                                           "panda", "--valid", "5", "--seed", "1", "-o", "ds"], 300))
    t0 = time.monotonic()
    vertex_bomb_3mf("bomb.3mf", 38000000)
    print("<!-- bomb.3mf: %d bytes, 38M vertices, written in %.0f s -->"
          % (os.path.getsize("bomb.3mf"), time.monotonic() - t0))
    row("3MF with 38M vertices (%.1f MB)" % (os.path.getsize("bomb.3mf") / 1e6),
        run([TASKMAP, "mesh-info", "bomb.3mf"]))
    for n in ("250000000", "1000000000"):
        with open("huge.x", "w") as f:
            f.write("xof 0302txt 0064\nMesh {\n %s;\n 0.0;0.0;0.0;;\n 1;\n 3;0,0,0;;\n}\n" % n)
        row(".x of %d B declaring %s vertices" % (os.path.getsize("huge.x"), n),
            run([TASKMAP, "mesh-info", "huge.x"]))
    before = open("mybox.obj", "rb").read()
    row("build --object mybox.obj -o mybox.obj", run([TASKMAP, "build", "--object", "mybox.obj",
                                                      "--hand", "panda", "--valid", "5", "-o", "mybox.obj"]))
    os.link("mybox.obj", "hard.obj")
    os.symlink("mybox.obj", "soft.obj")
    for out in ("hard.obj", "soft.obj"):
        row("build -o " + out + " (link to the object)",
            run([TASKMAP, "build", "--object", "mybox.obj", "--hand", "panda", "--valid", "5", "-o", out]))
    print("<!-- mybox.obj intact: %s -->" % (open("mybox.obj", "rb").read() == before))
    os.mkfifo("fifo.obj")
    row("mesh-info on a FIFO", run([TASKMAP, "mesh-info", "fifo.obj"], 20))
    for n in (255, 12000, 100000):
        row("hand URDF chain of %d joints: hand-info" % n,
            run([TASKMAP, "hand-info", write_hand(d, "chain%d" % n, chain_urdf(n))]))
    deep = "<robot name=\"deep\"><link name=\"base\">" + "<a>" * 100000 + "</a>" * 100000 + "</link></robot>\n"
    row("URDF with 100,000 nested elements", run([TASKMAP, "hand-info", write_hand(d, "deep", deep)]))
    cyc = chain_urdf(2).replace("</robot>\n", "")
    cyc += ("<link name=\"c1\">%s</link><link name=\"c2\">%s</link>\n"
            "<joint name=\"k1\" type=\"fixed\"><parent link=\"c1\"/><child link=\"c2\"/></joint>\n"
            "<joint name=\"k2\" type=\"fixed\"><parent link=\"c2\"/><child link=\"c1\"/></joint>\n</robot>\n"
            % (BOXGEOM, BOXGEOM))
    row("URDF with a detached cycle", run([TASKMAP, "hand-info", write_hand(d, "cycle", cyc)]))
    row("--trials 18446744073709551615", run([TASKMAP, "build", "--object", BOX, "--hand", "panda",
                                               "--trials", "18446744073709551615", "-q", "-o", "t1.h5"]))
    row("--trials 17179869184 --valid 5", run([TASKMAP, "build", "--object", BOX, "--hand", "panda",
                                                "--trials", "17179869184", "--valid", "5", "-q", "-o", "t2.h5"], 300))
    # taskmap.seal on a sparse 100M x 7 grasps/pose (the Python module).
    import h5py
    shutil.copy(os.path.join(SRC, "tests", "data", "maps", "box_barrett.h5"), "sparse.h5")
    with h5py.File("sparse.h5", "r+") as f:
        del f["grasps/pose"]
        f.create_dataset("grasps/pose", shape=(100000000, 7), dtype="f8", chunks=(4096, 7))
    env = dict(os.environ, PYTHONPATH=os.path.join(BUILD, "python"))
    row("taskmap.seal on a sparse 100M x 7 grasps/pose (%d KiB)" % (os.path.getsize("sparse.h5") // 1024),
        run([sys.executable, "-c", "import sys, taskmap\ntry:\n    taskmap.seal(sys.argv[1])\n"
             "    print('accepted')\nexcept taskmap.Error as e:\n    print('error: %s' % e)\n",
             "sparse.h5"], env=env))
    # Two runs on one data-set directory / one output at once.
    with open("one.txt", "w") as f:
        f.write("mybox.obj\n")
    first = subprocess.Popen([TASKMAP, "dataset", "--objects", "one.txt", "--hands", "panda",
                              "--valid", "100000", "--seed", "1", "-q", "-o", "ds2"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    lock = os.path.join("ds2", ".taskmap-dataset.lock")
    for _ in range(600):
        if os.path.exists(lock) and open(lock).read().strip() == str(first.pid):
            break
        time.sleep(0.05)
    row("second dataset run into a directory in use (first PID %d)" % first.pid,
        run([TASKMAP, "dataset", "--objects", "one.txt", "--hands", "panda", "--valid", "5",
             "--seed", "1", "-q", "-o", "ds2"]))
    first.kill()
    first.wait()
    if os.path.exists(MPI) and shutil.which("mpirun"):
        first = subprocess.Popen([TASKMAP, "build", "--object", BOX, "--hand", "panda", "--valid",
                                  "100000", "--threads", "1", "-q", "-o", "locked.h5"],
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for _ in range(600):
            if os.path.exists("locked.h5.lock") and open("locked.h5.lock").read().strip() == str(first.pid):
                break
            time.sleep(0.05)
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        row("taskmap-mpi build on an output a taskmap build holds (PID %d)" % first.pid,
            run(["mpirun", "-n", "2", "--oversubscribe", "--bind-to", "none", MPI, "build",
                 "--object", BOX, "--hand", "panda", "--valid", "5", "-o", "locked.h5"], env=env))
        first.kill()
        first.wait()
    shutil.rmtree(d, ignore_errors=True)


if __name__ == "__main__":
    main()
