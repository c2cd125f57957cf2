#!/usr/bin/env python3
"""Builds the generated reference, every warning an error (docs/REFERENCE.md).

    reference.py --build BUILD [--source ROOT]

- command line: each command's own `taskmap CMD --help` (and `taskmap-mpi --help`), as
  BUILD/docs/src/cli.rst;
- Python: the docstrings of the `taskmap` package in BUILD/python, by Sphinx autodoc
  (tools/docs/sphinx, `sphinx-build -W`); every public name of the package must be documented
  there;
- C++: the Doxygen comments of the public headers (<stage>/include), WARN_AS_ERROR.

Writes BUILD/docs/html/index.html and BUILD/docs/cpp/html/index.html. Exit status 0 when both
build without a warning; 77 (ctest's skip) when sphinx-build or doxygen is missing and CI is not
set; 1 otherwise."""
import argparse
import glob
import os
import re
import shutil
import subprocess
import sys

SKIP = 77


def run_help(exe, args):
    r = subprocess.run([exe] + args + ["--help"], capture_output=True, text=True, timeout=60)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join([exe] + args)} --help failed: {r.stderr}")
    return r.stdout


def literal(text):
    return "::\n\n" + "".join("    " + line + "\n" if line.strip() else "\n"
                              for line in text.rstrip().split("\n")) + "\n"


def cli_rst(bindir):
    """The command-line reference: every command's --help, verbatim."""
    exe = os.path.join(bindir, "taskmap")
    top = run_help(exe, [])
    part = top.split("Subcommands:")[1] if "Subcommands:" in top else ""
    commands = re.findall(r"^  ([a-z][a-z-]*)\s", part, re.M)
    if not commands:
        raise RuntimeError("taskmap --help lists no commands")
    out = ["Command line", "============", "",
           "Generated from ``taskmap --help`` and each command's ``taskmap CMD --help``.", "",
           "taskmap", "-------", "", literal(top)]
    for c in commands:
        title = f"taskmap {c}"
        out += [title, "-" * len(title), "", literal(run_help(exe, [c]))]
    mpi = os.path.join(bindir, "taskmap-mpi")
    if os.path.exists(mpi):
        out += ["taskmap-mpi", "-----------", "", literal(run_help(mpi, []))]
    return "\n".join(out)


def documented_names(rst_dir):
    names = set()
    for f in glob.glob(os.path.join(rst_dir, "*.rst")):
        names |= set(re.findall(r"^\.\. auto\w+:: taskmap\.(\w+)", open(f).read(), re.M))
    return names


def python_names(build):
    env = dict(os.environ, PYTHONPATH=os.path.join(build, "python"))
    code = "import taskmap\nprint('\\n'.join(n for n in dir(taskmap) if not n.startswith('_')))"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                       timeout=120)
    if r.returncode != 0:
        raise RuntimeError("import taskmap failed: " + r.stderr[-800:])
    return set(r.stdout.split())


def sphinx(root, build, out):
    src = os.path.join(out, "src")
    shutil.rmtree(src, ignore_errors=True)
    shutil.copytree(os.path.join(root, "tools", "docs", "sphinx"), src)
    with open(os.path.join(src, "cli.rst"), "w") as f:
        f.write(cli_rst(os.path.join(build, "bin")))
    missing = sorted(python_names(build) - documented_names(src))
    if missing:
        print("reference: Python names left out of tools/docs/sphinx/*.rst: " + ", ".join(missing))
        return False
    env = dict(os.environ, PYTHONPATH=os.path.join(build, "python"), PYTHONDONTWRITEBYTECODE="1")
    r = subprocess.run(["sphinx-build", "-W", "--keep-going", "-E", "-a", "-q", "-b", "html", "-d",
                        os.path.join(out, "doctrees"), src, os.path.join(out, "html")],
                       env=env, capture_output=True, text=True, timeout=600)
    sys.stdout.write(r.stdout + r.stderr)
    return r.returncode == 0


def doxygen(root, out):
    includes = sorted(glob.glob(os.path.join(root, "*", "include")))
    cfg = {
        "PROJECT_NAME": "taskmap",
        "OUTPUT_DIRECTORY": os.path.join(out, "cpp"),
        "INPUT": " ".join(includes),
        "STRIP_FROM_PATH": root,
        "STRIP_FROM_INC_PATH": " ".join(includes),
        "RECURSIVE": "YES",
        "FILE_PATTERNS": "*.hpp",
        "EXTRACT_ALL": "YES",
        "EXTRACT_STATIC": "YES",
        "EXCLUDE_SYMBOLS": "detail",
        "JAVADOC_AUTOBRIEF": "YES",
        "WARN_IF_UNDOCUMENTED": "NO",
        "WARN_IF_INCOMPLETE_DOC": "NO",
        "WARN_IF_DOC_ERROR": "YES",
        "WARN_AS_ERROR": "FAIL_ON_WARNINGS",
        "QUIET": "YES",
        "GENERATE_HTML": "YES",
        "GENERATE_LATEX": "NO",
        "HAVE_DOT": "NO",
        "INPUT_FILTER": '"perl ' + os.path.join(root, "tools", "docs", "doxygen_filter.pl") + '"',
    }
    os.makedirs(os.path.join(out, "cpp"), exist_ok=True)
    doxyfile = os.path.join(out, "Doxyfile")
    with open(doxyfile, "w") as f:
        f.write("".join(f"{k} = {v}\n" for k, v in cfg.items()))
    r = subprocess.run(["doxygen", doxyfile], cwd=root, capture_output=True, text=True,
                       timeout=600)
    sys.stdout.write(r.stdout + r.stderr)
    return r.returncode == 0 and "warning:" not in r.stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--source", default=os.path.dirname(os.path.dirname(
        os.path.dirname(os.path.abspath(__file__)))))
    ap.add_argument("--build", required=True)
    a = ap.parse_args()
    root, build = os.path.abspath(a.source), os.path.abspath(a.build)
    missing = [t for t in ("sphinx-build", "doxygen") if shutil.which(t) is None]
    if missing:
        print("reference: " + " and ".join(missing) + " not installed (tools/dev.sh deps "
              "installs them)")
        return 1 if os.environ.get("CI") == "true" else SKIP
    out = os.path.join(build, "docs")
    ok_py = sphinx(root, build, out)
    ok_cpp = doxygen(root, out)
    print(f"reference: Python and command line {'ok' if ok_py else 'FAILED'} "
          f"({os.path.join(out, 'html', 'index.html')}); C++ {'ok' if ok_cpp else 'FAILED'} "
          f"({os.path.join(out, 'cpp', 'html', 'index.html')})")
    return 0 if ok_py and ok_cpp else 1


if __name__ == "__main__":
    sys.exit(main())
