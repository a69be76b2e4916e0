#!/usr/bin/env python3
"""Independent reference for great-circle (vector) orientation interpolation on an A/C table.

Reads the tool path of a tool-vector program (a Fanuc-style G43.5 program with `X Y Z I J K F` words,
or Sinumerik with `A3= B3= C3=`; only G0/G1 lines, absolute, mm, the vector in the workpiece frame) and
computes, with numpy and nothing of fiveaxis, what a control that turns the tool axis on the great
circle between the block vectors (slerp, the tip on the straight line, both even in the block's time at
the programmed feed) asks of the C table: C = atan2(o_x, o_y) on an A/C table whose tool axis is
O_W = (sin C sin A, cos C sin A, cos A) (Cripps et al. 2017, eq. 2); dC/dt from the slerp's analytic
derivative. Prints JSON: the peak C speed (rpm) and where, and the x range where C exceeds
--limit-rpm (crossings interpolated on a grid of --points per block).

Usage: slerp_reference.py PROGRAM [--limit-rpm 25] [--points 20001]
"""
import argparse
import json
import re

import numpy as np

WORD = re.compile(r"(A3|B3|C3|[A-Z])\s*=?\s*([+-]?\d*\.?\d+(?:[eE][+-]?\d+)?)")


def blocks(text):
    """(motion, tip mm, vector, feed mm/min) for each motion line, modal words carried."""
    motion, tip, vec, feed = None, np.zeros(3), None, None
    tcp = False
    for raw in text.splitlines():
        line = re.sub(r"\(.*?\)|;.*", "", raw).strip().upper()
        if not line or line.startswith("%"):
            continue
        if "G43.5" in line or "TRAORI" in line:
            tcp = True
        if re.search(r"\bG49\b", line) or "TRAFOOF" in line:
            tcp = False
        words = dict()
        for letter, value in WORD.findall(line):
            if letter == "G":
                g = float(value)
                if g in (0.0, 1.0):
                    motion = int(g)
                continue
            words[letter] = float(value)
        if "G10" in line:
            continue
        moved = False
        for k, axis in enumerate("XYZ"):
            if axis in words:
                tip = tip.copy()
                tip[k] = words[axis]
                moved = True
        v = [words.get(n) for n in (("I", "J", "K") if "I" in words else ("A3", "B3", "C3"))]
        if tcp and all(x is not None for x in v):
            vec = np.array(v) / np.linalg.norm(v)
            moved = True
        if "F" in words:
            feed = words["F"]
        if moved and tcp and motion is not None:
            yield motion, tip, vec, feed


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("program")
    ap.add_argument("--limit-rpm", type=float, default=25.0)
    ap.add_argument("--points", type=int, default=20001)
    args = ap.parse_args()
    bl = list(blocks(open(args.program).read()))
    w = np.linspace(0.0, 1.0, args.points)
    xs, rpms = [], []
    for (_, p0, o0, _), (m1, p1, o1, f1) in zip(bl, bl[1:]):
        if m1 != 1 or o0 is None or o1 is None:
            continue
        length = np.linalg.norm(p1 - p0)
        g = np.arctan2(np.linalg.norm(np.cross(o0, o1)), np.dot(o0, o1))
        if length < 1e-9 or g < 1e-12:
            continue
        duration = length / f1 * 60.0  # s
        o = (np.outer(np.sin((1 - w) * g), o0) + np.outer(np.sin(w * g), o1)) / np.sin(g)
        do = g * (np.outer(np.cos(w * g), o1) - np.outer(np.cos((1 - w) * g), o0)) / np.sin(g)
        # C = atan2(ox, oy): dC/dw = (ox' oy - oy' ox) / (ox^2 + oy^2)
        dc = (do[:, 0] * o[:, 1] - do[:, 1] * o[:, 0]) / (o[:, 0] ** 2 + o[:, 1] ** 2)
        rpms.append(np.abs(dc) / duration * 60.0 / (2 * np.pi))
        xs.append(p0[0] + (p1[0] - p0[0]) * w)
    x, rpm = np.concatenate(xs), np.concatenate(rpms)
    k = int(np.argmax(rpm))
    above = rpm > args.limit_rpm
    out = {"peak_c_speed_rpm": float(rpm[k]), "peak_x_mm": float(x[k])}
    if above.any():
        i0, i1 = int(np.argmax(above)), len(above) - 1 - int(np.argmax(above[::-1]))

        def cross(a, b):
            t = (args.limit_rpm - rpm[a]) / (rpm[b] - rpm[a])
            return float(x[a] + (x[b] - x[a]) * t)

        out["region_x_start_mm"] = cross(i0 - 1, i0) if i0 > 0 else float(x[i0])
        out["region_x_end_mm"] = cross(i1, i1 + 1) if i1 + 1 < len(x) else float(x[i1])
    print(json.dumps(out))


if __name__ == "__main__":
    main()
