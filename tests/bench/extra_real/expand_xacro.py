#!/usr/bin/python3
"""Expand the Robotiq 2F-85 xacro into a plain URDF without ROS.

Usage: expand_xacro.py ROBOTIQ_GIT COMMIT OUT.urdf

Reads robotiq_2f_85_gripper_visualization/urdf/robotiq_arg2f_85_model.xacro and the files it
includes from a git checkout or mirror of ros-industrial/robotiq at COMMIT (`git show`), and
does what xacro does with them: <xacro:include filename="$(find PKG)/..."> (PKG must be the
package the file is in), <xacro:macro> definitions and calls (string parameters, no defaults
needed here), and ${...} expressions (Python arithmetic on the parameters and pi). Anything else
in the xacro namespace is an error, so a later version of the files that uses more of xacro
fails here instead of expanding wrongly. Comments are dropped (xacro keeps them).
"""
import math
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

XACRO = "http://ros.org/wiki/xacro"
PKG = "robotiq_2f_85_gripper_visualization"
TOP = PKG + "/urdf/robotiq_arg2f_85_model.xacro"


def git_show(repo, commit, path):
    return subprocess.run(["git", "-C", repo, "show", f"{commit}:{path}"], check=True,
                          capture_output=True).stdout


def tag(e, name):
    return e.tag == f"{{{XACRO}}}{name}"


def substitute(text, params):
    def one(m):
        value = eval(m.group(1), {"__builtins__": {}}, dict(params, pi=math.pi))
        return str(value)
    return re.sub(r"\$\{([^}]*)\}", one, text)


def numeric(params):
    out = {}
    for k, v in params.items():
        try:
            out[k] = float(v) if re.fullmatch(r"[-+0-9.eE]+", v) else v
        except ValueError:
            out[k] = v
    return out


class Expander:
    def __init__(self, repo, commit):
        self.repo, self.commit, self.macros = repo, commit, {}

    def load(self, path):
        return ET.fromstring(git_show(self.repo, self.commit, path))

    def define(self, root):
        """Collect macros and includes of a file (its top level), return its other children."""
        rest = []
        for e in list(root):
            if tag(e, "include"):
                m = re.fullmatch(r"\$\(find ([^)]+)\)/(.+)", e.get("filename"))
                if not m or m.group(1) != PKG:
                    sys.exit(f"unsupported include {e.get('filename')}")
                rest += self.define(self.load(PKG + "/" + m.group(2)))
            elif tag(e, "macro"):
                self.macros[e.get("name")] = (e.get("params").split(), e)
            else:
                rest.append(e)
        return rest

    def expand(self, elements, params):
        out = []
        for e in elements:
            if not isinstance(e.tag, str):
                continue  # comment or processing instruction
            if e.tag.startswith(f"{{{XACRO}}}"):
                name = e.tag.split("}")[1]
                if name not in self.macros:
                    sys.exit(f"unsupported xacro element {name}")
                names, body = self.macros[name]
                args = {k: substitute(v, params) for k, v in e.attrib.items()}
                if sorted(args) != sorted(names):
                    sys.exit(f"macro {name}: parameters {names}, call gives {sorted(args)}")
                out += self.expand(list(body), numeric(args))
                continue
            c = ET.Element(e.tag, {k: substitute(v, params) for k, v in e.attrib.items()})
            c.text = substitute(e.text, params) if e.text and e.text.strip() else None
            for child in self.expand(list(e), params):
                c.append(child)
            out.append(c)
        return out


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    repo, commit, out = sys.argv[1:]
    x = Expander(repo, commit)
    top = x.load(TOP)
    robot = ET.Element("robot", {"name": top.get("name")})
    for e in x.expand(x.define(top), {}):
        robot.append(e)
    ET.indent(robot, space="  ")
    header = (f"<?xml version=\"1.0\"?>\n<!-- Expanded by tests/bench/extra_real/expand_xacro.py"
              f" from ros-industrial/robotiq {commit}:{TOP}\n     (BSD licence, LICENSE beside"
              f" this file). Do not edit: re-run the script. -->\n")
    with open(out, "w") as f:
        f.write(header + ET.tostring(robot, encoding="unicode") + "\n")


if __name__ == "__main__":
    main()
