#!/usr/bin/env python3
"""Forward kinematics of a URDF by an independent parser (yourdfpy, PyPI): the tool pose in the
workpiece frame for each row of joint values.

usage: urdf_fk.py MACHINE.urdf JOINTS.csv OUT.csv [MACHINE.urdf JOINTS.csv OUT.csv ...] [--workpiece LINK] [--tool LINK]
(several machines in one run: the imports take a second)

JOINTS.csv: a header of URDF joint names, then one row of joint values (m, rad) per pose.
OUT.csv: tip_x_mm,tip_y_mm,tip_z_mm,axis_x,axis_y,axis_z per row: the origin of the tool link and its
+z axis, in the workpiece link's frame (yourdfpy's scene graph: get_transform(tool, workpiece)).
Also checks that yourdfpy validates the file and that every movable joint it found is named in the CSV.
"""
import argparse
import csv
import sys

import numpy as np
import yourdfpy


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("files", nargs="+", help="MACHINE.urdf JOINTS.csv OUT.csv, repeated")
    ap.add_argument("--workpiece", default="workpiece")
    ap.add_argument("--tool", default="tool")
    a = ap.parse_args()
    if len(a.files) % 3:
        sys.exit("urdf_fk.py: arguments come in threes: MACHINE.urdf JOINTS.csv OUT.csv")
    for k in range(0, len(a.files), 3):
        one(a.files[k], a.files[k + 1], a.files[k + 2], a.tool, a.workpiece)


def one(urdf, joints, out, tool, workpiece):
    robot = yourdfpy.URDF.load(urdf, build_scene_graph=True, load_meshes=False, build_collision_scene_graph=False)
    if not robot.validate():
        sys.exit(f"yourdfpy: {urdf} does not validate")
    with open(joints) as f:
        rows = list(csv.reader(f))
    names, values = rows[0], [[float(v) for v in r] for r in rows[1:]]
    actuated = list(robot.actuated_joint_names)
    missing = [j for j in actuated if j not in names]
    if missing:
        sys.exit(f"yourdfpy found movable joints {actuated}; the CSV lacks {missing}")
    with open(out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["tip_x_mm", "tip_y_mm", "tip_z_mm", "axis_x", "axis_y", "axis_z"])
        for row in values:
            cfg = {n: v for n, v in zip(names, row) if n in actuated}
            robot.update_cfg(cfg)
            t = np.asarray(robot.get_transform(tool, workpiece))
            tip, axis = t[:3, 3] * 1000.0, t[:3, 2]
            w.writerow([repr(float(v)) for v in (*tip, *axis)])


if __name__ == "__main__":
    main()
