#!/usr/bin/env python3
"""The secondary rotary axis' speed of each block of a five-axis program, computed here from the
program's words alone, as an independent reference for tests/corpus.rs.

The control's interpolation for the blocks read (Fanuc G43.4 and Siemens TRAORI with the rotary axes
moving as written, linear in the block): the tool tip moves on a straight line at the programmed feed
F (program units per minute), so a block lasts |tip displacement| / F, and the rotary axis turns its
whole change in that time at a constant rate. Reads absolute (G90) blocks of address words from
FIRST_LINE to LAST_LINE (1-based, inclusive), the modal values before it from STATE ("X0 Y0 Z0 B0 C0
F1"); prints JSON: the peak speed (rpm) and its line, every block above LIMIT_RPM, and each block's
time (`seconds`, line to s). With TILT (the
tilting axis of a table whose tool lies along the other axis at TILT = 0, such as B on a B/C table),
also each block's closest approach to that axis' line: the angle min(|TILT|, 180 - |TILT|) (TILT taken
in -180..180), smallest over the block (TILT linear in the block: at an end, or 0 where it passes 0 or
180), degrees, and the angle at its end: `tilt_deg` maps each line to [closest, at the end].

usage: block_speeds.py PROGRAM FIRST_LINE LAST_LINE AXIS LIMIT_RPM [STATE] [TILT]
"""
import json
import re
import sys

import numpy as np


def closest_to_line(t0, t1):
    """The smallest angle between the tool and the axis line over a block whose tilt goes linearly from
    t0 to t1 (degrees): 0 where it passes a multiple of 180, else the nearer end's."""
    lo, hi = min(t0, t1), max(t0, t1)
    if np.floor(lo / 180.0) != np.floor(hi / 180.0) or lo % 180.0 == 0.0:
        return 0.0
    d = lambda t: min(t % 180.0, 180.0 - t % 180.0)
    return min(d(t0), d(t1))


def main():
    path, first, last, axis, limit = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4].upper(), float(sys.argv[5])
    state = {"X": 0.0, "Y": 0.0, "Z": 0.0, "A": 0.0, "B": 0.0, "C": 0.0, "F": None}
    for w in re.findall(r"([A-Z])\s*([-+]?\d*\.?\d+)", sys.argv[6].upper() if len(sys.argv) > 6 else ""):
        state[w[0]] = float(w[1])
    tilt_axis = sys.argv[7].upper() if len(sys.argv) > 7 else None
    lines = open(path, encoding="latin-1").read().splitlines()
    rows = []
    tilts = {}
    seconds = {}
    for n in range(first, last + 1):
        text = re.sub(r"\(.*?\)|;.*$", "", lines[n - 1]).upper()
        words = dict((a, float(v)) for a, v in re.findall(r"([XYZABCF])\s*([-+]?\d*\.?\d+)", text))
        if not any(k in words for k in "XYZABC"):
            state.update({k: v for k, v in words.items() if k == "F"})
            continue
        start = np.array([state["X"], state["Y"], state["Z"]])
        turn0 = state[axis]
        tilt0 = state[tilt_axis] if tilt_axis else None
        state.update(words)
        if tilt_axis:
            t1 = state[tilt_axis]
            tilts[n] = [closest_to_line(tilt0, t1), closest_to_line(t1, t1)]
        length = float(np.linalg.norm(np.array([state["X"], state["Y"], state["Z"]]) - start))
        minutes = length / state["F"]
        seconds[n] = minutes * 60.0
        rpm = abs(state[axis] - turn0) / 360.0 / minutes if minutes > 0 else float("inf")
        rows.append((n, rpm))
    peak_line, peak = max(rows, key=lambda r: r[1])
    over = [n for n, rpm in rows if rpm > limit]
    out = {"peak_rpm": peak, "peak_line": peak_line, "over_limit_lines": over, "blocks": len(rows), "seconds": seconds}
    if tilt_axis:
        out["tilt_deg"] = tilts
    print(json.dumps(out))


if __name__ == "__main__":
    main()
