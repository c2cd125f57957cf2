"""What the Python tests share: the command-line tool run as a user runs it (TASKMAP_CLI), and a
file's bytes, to compare what the CLI and the package write."""
import os
import subprocess

CLI = os.environ["TASKMAP_CLI"]


def cli(*args):
    """Runs `taskmap *args`; returns (exit code, stdout, stderr)."""
    r = subprocess.run([CLI, *args], capture_output=True, text=True)
    return r.returncode, r.stdout, r.stderr


def read(path):
    """The bytes of the file at `path`."""
    with open(path, "rb") as f:
        return f.read()
