"""PEP 517 build backend of the taskmap Python package: `pip install .` drives the CMake build.

No requirement beyond the standard library and the Debian packages the project builds with, so
`pip install .` works offline (build isolation installs nothing). Steps: configure and build the
two extension modules with CMake (ccache reuses objects compiled before), `cmake --install` into a
staging prefix, and write a wheel: the package `taskmap/` (the modules find the stage libraries
through their RPATH, $ORIGIN/../../..), the stage libraries as wheel data in `lib/` (installed
into <venv>/lib) and the bundled data in `share/taskmap/` (installed into <venv>/share/taskmap,
where the library looks beside <venv>/lib/libtaskmap_core: core/data_dir.hpp).

Settings: TASKMAP_BUILD_DIR (environment) or `--config-settings build-dir=DIR` uses that build
tree (configured before; brought up to date there); otherwise
<source>/build-pip is configured (Release, no tests, no tools) and built.
"""
import base64
import hashlib
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import zipfile

_SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_NAME = "taskmap"


def _version():
    with open(os.path.join(_SRC, "CMakeLists.txt"), encoding="utf-8") as f:
        m = re.search(r"project\(TaskMap VERSION ([0-9.]+)", f.read())
    return m.group(1) if m else "0.0.0"


def _run(cmd):
    print("taskmap build backend: " + " ".join(cmd), file=sys.stderr, flush=True)
    subprocess.run(cmd, check=True, stdout=sys.stderr)


def _cache(build_dir):
    values = {}
    with open(os.path.join(build_dir, "CMakeCache.txt"), encoding="utf-8") as f:
        for line in f:
            m = re.match(r"([A-Za-z_0-9]+):[A-Z]+=(.*)$", line.strip())
            if m:
                values[m.group(1)] = m.group(2)
    return values


def _build_tree(config_settings):
    given = (config_settings or {}).get("build-dir") or os.environ.get("TASKMAP_BUILD_DIR")
    if given:
        build_dir = os.path.abspath(given)
        if not os.path.isfile(os.path.join(build_dir, "CMakeCache.txt")):
            raise RuntimeError(f"taskmap: build-dir '{build_dir}' is not a configured CMake build "
                               "tree; configure it first or leave TASKMAP_BUILD_DIR unset")
    else:
        build_dir = os.path.join(_SRC, "build-pip")
        cmd = ["cmake", "-S", _SRC, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release",
               "-DTASKMAP_BUILD_TESTS=OFF", "-DTASKMAP_BUILD_BENCHMARKS=OFF",
               "-DTASKMAP_BUILD_TOOLS=OFF", "-DTASKMAP_BUILD_PYTHON=ON",
               "-DCMAKE_INSTALL_LIBDIR=lib", f"-DPython3_EXECUTABLE={sys.executable}"]
        if shutil.which("ninja") and not os.path.isfile(os.path.join(build_dir, "CMakeCache.txt")):
            cmd += ["-G", "Ninja"]
        if shutil.which("ccache"):
            cmd.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        _run(cmd)
    # Everything the tree builds (the install step copies every stage library); a no-op for a
    # tree that is up to date, such as the one the tests run in.
    _run(["cmake", "--build", build_dir, "-j", str(os.cpu_count() or 1)])
    return build_dir


def _check_layout(cache):
    libdir = cache.get("CMAKE_INSTALL_LIBDIR", "lib")
    want = f"lib/python{sys.version_info[0]}.{sys.version_info[1]}/site-packages"
    pydir = cache.get("TASKMAP_PYTHON_INSTALL_DIR", "")
    if libdir != "lib" or pydir != want:
        raise RuntimeError(
            f"taskmap: the build tree installs libraries into '{libdir}' and the package into "
            f"'{pydir}'; a wheel needs 'lib' and '{want}' (configure with "
            f"-DCMAKE_INSTALL_LIBDIR=lib and the interpreter {sys.executable})")
    return pydir


def _hash(data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"sha256={digest}"


def _tag():
    impl = f"cp{sys.version_info[0]}{sys.version_info[1]}"
    abi = impl + getattr(sys, "abiflags", "")
    plat = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{impl}-{abi}-{plat}"


def _wheel_files(stage, pydir):
    """(archive name, bytes) of the package and of the stage libraries (by their soname)."""
    files = []
    pkg = os.path.join(stage, pydir, _NAME)
    for root, _, names in os.walk(pkg):
        for n in sorted(names):
            if n.endswith((".pyc", ".pyo")):
                continue
            path = os.path.join(root, n)
            rel = os.path.relpath(path, os.path.join(stage, pydir))
            with open(path, "rb") as f:
                files.append((rel.replace(os.sep, "/"), f.read()))
    data = f"{_NAME}-{_version()}.data/data/lib/"
    for n in sorted(os.listdir(os.path.join(stage, "lib"))):
        if re.match(r"^libtaskmap_\w+\.so\.\d+\.\d+$", n):  # the soname the modules load
            with open(os.path.join(stage, "lib", n), "rb") as f:  # follows the symlink
                files.append((data + n, f.read()))
    # The bundled data (hands, objects, maps, robots, regression suite) into <venv>/share/taskmap,
    # where the library finds it beside <venv>/lib/libtaskmap_core (core/data_dir.hpp).
    share = os.path.join(stage, "share", _NAME)
    if not os.path.isdir(os.path.join(share, "hands")):
        raise RuntimeError(f"taskmap: the installed tree has no {share}/hands (bundled data)")
    for root, dirs, names in os.walk(share):
        dirs.sort()
        for n in sorted(names):
            path = os.path.join(root, n)
            rel = os.path.relpath(path, stage).replace(os.sep, "/")
            with open(path, "rb") as f:
                files.append((f"{_NAME}-{_version()}.data/data/{rel}", f.read()))
    if not any(name.startswith(f"{_NAME}/_core") for name, _ in files):
        raise RuntimeError("taskmap: the installed tree has no taskmap/_core module")
    return files


def _metadata():
    return (f"Metadata-Version: 2.1\nName: {_NAME}\nVersion: {_version()}\n"
            "Summary: Grasp task maps: build offline, query at run time\n"
            "Requires-Python: >=3.9\nRequires-Dist: numpy\n").encode()


def get_requires_for_build_wheel(config_settings=None):
    return []


def _wheel_text(tag):
    return (f"Wheel-Version: 1.0\nGenerator: taskmap build_backend\n"
            f"Root-Is-Purelib: false\nTag: {tag}\n").encode()


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    """The package's metadata without building it (pip asks before build_wheel)."""
    dist = f"{_NAME}-{_version()}.dist-info"
    os.makedirs(os.path.join(metadata_directory, dist), exist_ok=True)
    for name, data in (("METADATA", _metadata()), ("WHEEL", _wheel_text(_tag()))):
        with open(os.path.join(metadata_directory, dist, name), "wb") as f:
            f.write(data)
    return dist


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    build_dir = _build_tree(config_settings)
    pydir = _check_layout(_cache(build_dir))
    tag = _tag()
    with tempfile.TemporaryDirectory(prefix="taskmap-wheel-") as stage:
        _run(["cmake", "--install", build_dir, "--prefix", stage])
        files = _wheel_files(stage, pydir)
    dist = f"{_NAME}-{_version()}.dist-info"
    files.append((f"{dist}/METADATA", _metadata()))
    files.append((f"{dist}/WHEEL", _wheel_text(tag)))
    record = "".join(f"{n},{_hash(b)},{len(b)}\n" for n, b in files) + f"{dist}/RECORD,,\n"
    files.append((f"{dist}/RECORD", record.encode()))
    wheel = f"{_NAME}-{_version()}-{tag}.whl"
    with zipfile.ZipFile(os.path.join(wheel_directory, wheel), "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in files:
            info = zipfile.ZipInfo(name, date_time=(2020, 1, 1, 0, 0, 0))
            info.external_attr = 0o755 << 16 if name.endswith(".so") or ".so." in name else 0o644 << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, data)
    return wheel
