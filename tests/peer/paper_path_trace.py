#!/usr/bin/env python3
"""The paper's continuous SING path (Cripps et al. 2017, seed 001 eq. 8-9) as a 1 kHz joint trace of
a Hermle C600U-style A/C table, at the programmed feed with no slowdown: what a bridge republishing a
control's interpolated set-points sends. Written with numpy only, in the trace format of
recordings/machine/linuxcnc (t_s,x_mm,y_mm,z_mm,a_deg,c_deg,program_line,motion_type), for
trace_to_rosbag.py.

P_W = (100/3 (t + 0.75), 0, -8) mm, O_W = R_x(11 deg) R_z(120 deg t) R_x(-10 deg) z, t in [-0.75, 0.75] s
(F2000 mm/min along x). The table's inverse: P_M = R_x(A) R_z(C) P_W with R_x(A) R_z(C) O_W = z, so
O_W = (sin A sin C, sin A cos C, cos A): A = acos(O_z), C = atan2(O_x, O_y), unwrapped.

Also prints, as JSON on stderr, the independent figures: the closest approach (deg), and the peak of
dC/dt (rpm) and where it exceeds 25 rpm along x (mm).

Usage: paper_path_trace.py OUT.csv [--still-s 0.1]
"""
import argparse
import json
import math
import sys

import numpy as np


def rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--still-s", type=float, default=0.1)
    a = ap.parse_args()
    ts = np.round(np.arange(-0.75, 0.75 + 5e-7, 1e-3), 6)
    rows = []
    prev_c = None
    for t in ts:
        p_w = np.array([100.0 / 3.0 * (t + 0.75), 0.0, -8.0])
        o_w = rx(math.radians(11)) @ rz(math.radians(120 * t)) @ rx(math.radians(-10)) @ np.array([0, 0, 1.0])
        A = math.acos(max(-1.0, min(1.0, o_w[2])))
        C = math.atan2(o_w[0], o_w[1])
        if prev_c is not None:
            C += 2 * math.pi * round((prev_c - C) / (2 * math.pi))
        prev_c = C
        p_m = rx(A) @ rz(C) @ p_w
        assert np.allclose(rx(A) @ rz(C) @ o_w, [0, 0, 1], atol=1e-12)
        rows.append((p_m, math.degrees(A), math.degrees(C), p_w[0]))
    still = int(round(a.still_s * 1000))
    with open(a.out, "w") as f:
        f.write("t_s,x_mm,y_mm,z_mm,a_deg,c_deg,program_line,motion_type\n")
        k = 0
        seq = [rows[0]] * still + rows + [rows[-1]] * still
        for r in seq:
            f.write(f"{k / 1000:.3f},{r[0][0]:.6f},{r[0][1]:.6f},{r[0][2]:.6f},{r[1]:.6f},{r[2]:.6f},0,2\n")
            k += 1
    c = np.array([r[2] for r in rows])
    x = np.array([r[3] for r in rows])
    rpm = np.abs(np.diff(c)) / 1e-3 / 6.0  # deg/s -> rpm
    xm = (x[1:] + x[:-1]) / 2
    over = xm[rpm > 25.0]
    json.dump({"closest_deg": min(r[1] for r in rows), "peak_rpm": float(rpm.max()),
               "x_over_25rpm_mm": [float(over.min()), float(over.max())]}, sys.stderr)


if __name__ == "__main__":
    main()
