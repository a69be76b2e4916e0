#!/usr/bin/env python3
"""Independent figures from a control's joint trace of the paper's cut (numpy only; nothing here comes
from fiveaxis): the LinuxCNC traces of recordings/machine/linuxcnc (make-traces) or any trace with the
header `t_s,x_mm,y_mm,z_mm,a_deg,c_deg[,program_line,motion_type]` (joint positions of a Hermle C600U
type A/C table-table: machine X Y Z of the tool tip in mm, A and C in degrees).

Usage: machine_figures.py TRACE.csv[.gz] [--feed 2000] [--x-range 22 28] [--rpm-limit 25]
       [--window 0.5] [--z -8] [--z-tol 0.05]
Prints one JSON object:
  cut (the feed pass in contact: tool tip z within z-tol of z, moving along x):
    cut_time_s, cut_x_from_mm, cut_x_to_mm, cut_y_mm, cut_length_mm, cut_samples, min_abs_a_deg,
    max_measured_c_rpm (C speed from the trace, central difference over +-2 samples),
    x_start_mm, x_end_mm: smallest and largest tip x of the cut's samples where the predicted C speed
      exceeds --rpm-limit (whole cut, independent of --x-range; null if none),
  over the x range (default: the whole cut), samples of the cut with x0 <= x <= x1:
    peak_predicted_c_rpm: |dC/ds| * feed, with dC/ds from the trace's own path geometry (C against the
      tip's arc length s in workpiece coordinates, difference over a --window mm of path, 0.5 mm),
    lowest_feed_mm_per_min: tip speed in workpiece coordinates, central difference over +-2 ms,
    time_lost_s: time spent with the tip in the range minus the path length in it / feed,
    time_in_range_s, path_in_range_mm,
  whole trace: samples, rapid_samples (motion_type 1), rapid_or_non_cut_samples (every sample
    outside the cut), max_measured_c_rpm_trace.

Also a module: load_trace(path), forward_kinematics(x, y, z, a_deg, c_deg), tip_speed(...),
find_cut(...), figures(trace, feed, x_range, ...).
"""
import argparse
import csv
import gzip
import json
import math
import sys

import numpy as np


def load_trace(path):
    """The trace as a dict of numpy arrays: t, x, y, z, a, c (mm, deg) and line, mtype (0 if absent)."""
    opener = gzip.open if str(path).endswith(".gz") else open
    with opener(path, "rt", newline="") as f:
        r = csv.reader(f)
        head = next(r)
        rows = [row for row in r if row]
    col = {name: i for i, name in enumerate(head)}
    need = ["t_s", "x_mm", "y_mm", "z_mm", "a_deg", "c_deg"]
    missing = [n for n in need if n not in col]
    if missing:
        raise ValueError(f"{path}: no column(s) {missing} in header {head}")
    data = np.array([[float(row[col[n]]) for n in need] for row in rows], dtype=float)
    out = dict(zip(["t", "x", "y", "z", "a", "c"], data.T))
    for key, name in (("line", "program_line"), ("mtype", "motion_type")):
        out[key] = np.array([int(row[col[name]]) for row in rows]) if name in col else np.zeros(len(rows), dtype=int)
    return out


def forward_kinematics(x, y, z, a_deg, c_deg):
    """Tool tip in workpiece coordinates from the joints.

    The machine model (machines/hermle-c600u.toml, Cripps et al. 2017 eq. 1-2) maps the workpiece to
    the machine as P_M = Rot_x(A) Rot_z(C) P_W with right-handed rotations about axes through the
    common origin. Rotations are orthogonal, so the inverse is the transpose taken in reverse order:
    P_W = Rot_z(-C) Rot_x(-A) P_M. P_M is the tool tip in the machine frame, i.e. the X Y Z joints
    (the tip sits at the machine origin offset 0: no tool length, no axis offsets).
    """
    a = np.radians(a_deg)
    c = np.radians(c_deg)
    ca, sa, cc, sc = np.cos(a), np.sin(a), np.cos(c), np.sin(c)
    # Rot_x(-A)
    u = x
    v = ca * y + sa * z
    w = -sa * y + ca * z
    # Rot_z(-C)
    return cc * u + sc * v, -sc * u + cc * v, w


def central_diff(values, t, half=2):
    """d(values)/dt by central difference over +-half samples (one-sided, shorter, at the ends)."""
    n = len(t)
    i = np.arange(n)
    hi = np.minimum(i + half, n - 1)
    lo = np.maximum(i - half, 0)
    dt = t[hi] - t[lo]
    dt[dt == 0] = np.nan
    return (values[hi] - values[lo]) / dt if values.ndim == 1 else (values[hi] - values[lo]) / dt[:, None]


def tip_speed(p, t, half=2):
    """Tool-tip speed (mm/s) of positions p (n x 3), central difference over +-half samples."""
    return np.linalg.norm(central_diff(p, t, half), axis=1)


def find_cut(p, t, z_plane=-8.0, z_tol=0.05):
    """(first, last) sample index of the cut: the tip within z_tol of z_plane and moving mainly along x,
    taken inside the longest stretch at that z (which also holds the approach and leave moves along y)."""
    in_plane = np.abs(p[:, 2] - z_plane) < z_tol
    if not in_plane.any():
        raise ValueError(f"the tip never comes within {z_tol} mm of z = {z_plane} mm")
    v = central_diff(p, t)
    speed = np.linalg.norm(v, axis=1)
    along_x = in_plane & (speed > 1e-3) & (np.abs(v[:, 0]) > 0.5 * speed)
    # longest run of in_plane samples
    edges = np.flatnonzero(np.diff(np.concatenate(([0], in_plane.astype(int), [0]))))
    runs = list(zip(edges[::2], edges[1::2]))
    lo, hi = max(runs, key=lambda r: r[1] - r[0])
    idx = np.flatnonzero(along_x[lo:hi]) + lo
    if len(idx) == 0:
        raise ValueError("no move along x in the cut plane")
    return int(idx[0]), int(idx[-1])


def path_rate(s, values, window):
    """d(values)/ds along arc length s (non-decreasing), each as the difference over `window` of path
    centred on the sample (shorter at the ends of the path), evaluated on a 0.01 mm grid."""
    keep = np.concatenate(([True], np.diff(s) > 1e-9))
    s_u, v_u = s[keep], values[keep]
    step = 0.01
    grid = np.arange(s_u[0], s_u[-1] + step / 2, step)
    g = np.interp(grid, s_u, v_u)
    h = max(1, int(round(window / 2 / step)))
    k = np.arange(len(grid))
    hi = np.minimum(k + h, len(grid) - 1)
    lo = np.maximum(k - h, 0)
    rate = (g[hi] - g[lo]) / np.maximum(grid[hi] - grid[lo], step)
    return np.interp(s, grid, rate)


def _num(v, nd=4):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return None
    return round(float(v), nd)


def figures(trace, feed=2000.0, x_range=None, rpm_limit=25.0, window=0.5, z_plane=-8.0, z_tol=0.05, work_offset=(0.0, 0.0, 0.0)):
    """The figures as a dict (see the module docstring). `trace` is a path or load_trace()'s dict.
    `work_offset` (mm): the control's G54 datum; positions are reported in program coordinates,
    the workpiece point less it."""
    tr = trace if isinstance(trace, dict) else load_trace(trace)
    t = tr["t"]
    xw, yw, zw = forward_kinematics(tr["x"], tr["y"], tr["z"], tr["a"], tr["c"])
    p = np.column_stack([xw, yw, zw]) - np.asarray(work_offset, dtype=float)
    c_unwrapped = np.degrees(np.unwrap(np.radians(tr["c"])))
    dt = float(np.median(np.diff(t)))
    speed = tip_speed(p, t)  # mm/s
    c_rpm = np.abs(central_diff(c_unwrapped, t)) / 6.0  # deg/s -> rev/min
    first, last = find_cut(p, t, z_plane, z_tol)
    cut = slice(first, last + 1)
    pc, tc = p[cut], t[cut]
    ds = np.linalg.norm(np.diff(pc, axis=0), axis=1)
    s = np.concatenate(([0.0], np.cumsum(ds)))
    dcds = path_rate(s, c_unwrapped[cut], window)  # deg/mm
    predicted = np.abs(dcds) * feed / 360.0  # rpm at the programmed feed
    fast = predicted > rpm_limit
    xc = pc[:, 0]
    if x_range is None:
        x0, x1 = float(xc.min()), float(xc.max())
    else:
        x0, x1 = sorted(map(float, x_range))
    inr = (xc >= x0) & (xc <= x1)
    both = inr[:-1] & inr[1:]
    path_in = float(ds[both].sum())
    time_in = float(inr.sum() * dt)
    res = {
        "trace_samples": int(len(t)),
        "feed_mm_per_min": feed,
        "rpm_limit": rpm_limit,
        "x_range_mm": [x0, x1],
        "x_start_mm": _num(xc[fast].min()) if fast.any() else None,
        "x_end_mm": _num(xc[fast].max()) if fast.any() else None,
        "peak_predicted_c_rpm": _num(predicted[inr].max()) if inr.any() else None,
        "lowest_feed_mm_per_min": _num(speed[cut][inr].min() * 60.0, 2) if inr.any() else None,
        "time_lost_s": _num(time_in - path_in / (feed / 60.0)) if inr.any() else None,
        "time_in_range_s": _num(time_in),
        "path_in_range_mm": _num(path_in),
        "cut_time_s": _num(tc[-1] - tc[0]),
        "cut_x_from_mm": _num(xc[0]),
        "cut_x_to_mm": _num(xc[-1]),
        "cut_y_mm": _num(np.median(pc[:, 1])),
        "cut_length_mm": _num(s[-1]),
        "cut_samples": int(last - first + 1),
        "cut_mean_feed_mm_per_min": _num(s[-1] / (tc[-1] - tc[0]) * 60.0, 2),
        "min_abs_a_deg": _num(np.abs(tr["a"][cut]).min()),
        "max_measured_c_rpm": _num(c_rpm[cut].max()),
        "max_measured_c_rpm_trace": _num(np.nanmax(c_rpm)),
        "samples": int(len(t)),
        "rapid_samples": int((tr["mtype"] == 1).sum()),
        "rapid_or_non_cut_samples": int(len(t) - (last - first + 1)),
    }
    return res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("trace")
    ap.add_argument("--feed", type=float, default=2000.0, help="programmed feed, mm/min")
    ap.add_argument("--x-range", type=float, nargs=2, metavar=("X0", "X1"))
    ap.add_argument("--rpm-limit", type=float, default=25.0)
    ap.add_argument("--window", type=float, default=0.5, help="path window for dC/ds, mm")
    ap.add_argument("--z", type=float, default=-8.0, help="cut plane, workpiece z in mm")
    ap.add_argument("--z-tol", type=float, default=0.05)
    ap.add_argument("--work-offset", type=float, nargs=3, default=(0.0, 0.0, 0.0), metavar=("X", "Y", "Z"),
                    help="the control's G54 datum, mm: positions in program coordinates")
    a = ap.parse_args(argv)
    res = figures(a.trace, a.feed, a.x_range, a.rpm_limit, a.window, a.z, a.z_tol, a.work_offset)
    json.dump(res, sys.stdout)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
