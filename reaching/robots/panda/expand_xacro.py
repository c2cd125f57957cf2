#!/usr/bin/env python3
"""Expands the Franka Emika Panda ("fer") arm xacro of franka_description into the plain URDF
panda.urdf and the capsule model panda.capsules.json of this folder (Debian has no xacro).

Usage: expand_xacro.py <franka_description dir> <output dir>

Only what the arm macro (robots/common/franka_arm.xacro, arm_id fer, no hand, connected_to
base, gazebo false) produces is expanded: links with inertials, joints with origins
(kinematics.yaml), limits (joint_limits.yaml). Visual and mesh collision elements are left
out; each link's collision elements are its capsules (cylinder + two spheres, as the xacro's
collision_capsule macro writes them) at safety distance 0. The capsule model lists the same
capsules as segments (p0, p1 in the link frame, metres) and radii.
"""
import json
import math
import re
import sys

import yaml


def capsules_of(xacro_text):
    """{link: [(xyz, direction, base_radius, length, link_rpy)]} from franka_arm.xacro."""
    out = {}
    for m in re.finditer(r'<xacro:link_with_sc[^>]*name="(link\d)"([^>]*)>(.*?)</xacro:link_with_sc>',
                         xacro_text, re.S):
        name, attrs, body = m.group(1), m.group(2), m.group(3)
        rpy = re.search(r'rpy="([^"]*)"', attrs)
        yaw = 0.0
        if rpy:
            parts = rpy.group(1).replace("${pi/4}", str(math.pi / 4)).split()
            assert parts[0] == "0" and parts[1] == "0", "only a yaw of the _sc link is expanded"
            yaw = float(parts[2])
        caps = []
        for c in re.finditer(r"<xacro:collision_capsule([^/]*)/>", body):
            a = dict(re.findall(r'(\w+)="([^"]*)"', c.group(1)))
            xyz = [float(v) for v in a.get("xyz", "0 0 0").split()]
            r = re.match(r"\$\{([0-9.]+)\+safety_distance\}", a["radius"])
            caps.append((xyz, a.get("direction", "z"), float(r.group(1)), float(a["length"]), yaw))
        out[name] = caps
    return out


def rotz(yaw, v):
    c, s = math.cos(yaw), math.sin(yaw)
    return [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]


def fmt(v):
    return " ".join("%.12g" % x for x in v)


def main():
    src, dst = sys.argv[1], sys.argv[2]
    load = lambda p: yaml.safe_load(open(f"{src}/robots/fer/{p}"))
    kin, lim, inert = load("kinematics.yaml"), load("joint_limits.yaml"), load("inertials.yaml")
    caps = capsules_of(open(f"{src}/robots/common/franka_arm.xacro").read())
    model = {"description": "Capsule model of the Franka Emika Panda arm, expanded by "
                            "expand_xacro.py from franka_description (Apache-2.0, see NOTICE): "
                            "segment end points p0, p1 in the link frame (metres), radius at "
                            "safety distance 0 (the xacro default adds 0.03 m)",
             "links": {}}
    lines = ['<?xml version="1.0"?>',
             "<!-- Franka Emika Panda (fer) arm, expanded by expand_xacro.py from franka_description",
             "     (Apache-2.0, LICENSE and NOTICE beside this file). Collision: capsules as cylinder +",
             "     two spheres (safety distance 0); the same capsules are in panda.capsules.json. -->",
             '<robot name="panda">', '  <link name="base"/>',
             '  <joint name="fer_base_joint" type="fixed">', '    <parent link="base"/>',
             '    <child link="fer_link0"/>', '    <origin xyz="0 0 0" rpy="0 0 0"/>', "  </joint>"]
    for i in range(0, 9):
        link = f"link{i}"
        lines.append(f'  <link name="fer_{link}">')
        if link in inert:
            it = inert[link]
            I = it["inertia"]
            lines += [f'    <inertial>',
                      f'      <origin xyz="{it["origin"]["xyz"]}" rpy="{it["origin"]["rpy"]}"/>',
                      f'      <mass value="{it["mass"]}"/>',
                      f'      <inertia ixx="{I["xx"]}" ixy="{I["xy"]}" ixz="{I["xz"]}" iyy="{I["yy"]}" '
                      f'iyz="{I["yz"]}" izz="{I["zz"]}"/>', '    </inertial>']
        segs = []
        for xyz, direction, radius, length, yaw in caps.get(link, []):
            axis = {"x": [1, 0, 0], "y": [0, 1, 0], "z": [0, 0, 1]}[direction.strip("-")]
            p0 = rotz(yaw, [xyz[k] - 0.5 * length * axis[k] for k in range(3)])
            p1 = rotz(yaw, [xyz[k] + 0.5 * length * axis[k] for k in range(3)])
            segs.append({"p0": [round(v, 12) for v in p0], "p1": [round(v, 12) for v in p1],
                         "radius": radius})
            mid = [(a + b) / 2 for a, b in zip(p0, p1)]
            d = [b - a for a, b in zip(p0, p1)]
            n = math.sqrt(sum(x * x for x in d))
            pitch = math.acos(max(-1.0, min(1.0, d[2] / n)))
            yaw_c = math.atan2(d[1], d[0]) if pitch > 1e-12 else 0.0
            lines += ["    <collision>", f'      <origin xyz="{fmt(mid)}" rpy="0 {pitch:.12g} {yaw_c:.12g}"/>',
                      f'      <geometry><cylinder radius="{radius}" length="{length}"/></geometry>',
                      "    </collision>"]
            for p in (p0, p1):
                lines += ["    <collision>", f'      <origin xyz="{fmt(p)}" rpy="0 0 0"/>',
                          f'      <geometry><sphere radius="{radius}"/></geometry>', "    </collision>"]
        if segs:
            model["links"][f"fer_{link}"] = segs
        lines.append("  </link>")
        if i == 0:
            continue
        j = f"joint{i}"
        k = kin[j]["kinematic"]
        fixed = j not in lim
        lines += [f'  <joint name="fer_{j}" type="{"fixed" if fixed else "revolute"}">',
                  f'    <parent link="fer_link{i - 1}"/>', f'    <child link="fer_{link}"/>',
                  f'    <origin xyz="{k["x"]} {k["y"]} {k["z"]}" rpy="{k["roll"]} {k["pitch"]} {k["yaw"]}"/>']
        if not fixed:
            L = lim[j]["limit"]
            lines += ['    <axis xyz="0 0 1"/>',
                      f'    <limit lower="{L["lower"]}" upper="{L["upper"]}" effort="{L["effort"]}" '
                      f'velocity="{L["velocity"]}"/>']
        lines.append("  </joint>")
    lines.append("</robot>")
    open(f"{dst}/panda.urdf", "w").write("\n".join(lines) + "\n")
    links = ",\n".join(f'  "{k}": [\n' + ",\n".join("    " + json.dumps(c) for c in v) + "\n  ]"
                        for k, v in model["links"].items())
    text = '{\n "description": ' + json.dumps(model["description"]) + ',\n "links": {\n' + links + "\n }\n}\n"
    json.loads(text)
    open(f"{dst}/panda.capsules.json", "w").write(text)


if __name__ == "__main__":
    main()
