#!/usr/bin/env python3
"""Write a dense five-axis CAM program as CL data: a raster over a wavy surface with the tool along
the surface normal, a pose every 0.1 mm (`x y z i j k feed`, mm, unit vector, mm/min), long enough to
take HOURS at FEED mm/min. Used by benches/long-program (issue: hours-long programs in flat memory).

usage: long_program.py HOURS OUT.cl [FEED_MM_PER_MIN=2000] [STEP_MM=0.1]
"""
import math
import sys


def main():
    hours, out = float(sys.argv[1]), sys.argv[2]
    feed = float(sys.argv[3]) if len(sys.argv) > 3 else 2000.0
    step = float(sys.argv[4]) if len(sys.argv) > 4 else 0.1
    total = feed * 60.0 * hours  # mm of path
    line_len, stepover = 100.0, 0.5
    per_line = int(round(line_len / step))
    n = int(total / step)
    with open(out, "w") as f:
        for k in range(n + 1):
            row, i = divmod(k, per_line + 1)
            u = i * step if row % 2 == 0 else line_len - i * step
            x, y = u - 50.0, (row % 200) * stepover - 50.0
            # z = A sin(x/L1) cos(y/L2): slopes up to ~35 deg; the tool axis is the surface normal.
            a, l1, l2 = 8.0, 12.0, 17.0
            z = a * math.sin(x / l1) * math.cos(y / l2) - 10.0
            dzdx = a / l1 * math.cos(x / l1) * math.cos(y / l2)
            dzdy = -a / l2 * math.sin(x / l1) * math.sin(y / l2)
            nx, ny, nz = -dzdx, -dzdy, 1.0
            norm = math.sqrt(nx * nx + ny * ny + nz * nz)
            f.write(f"{x:.4f} {y:.4f} {z:.4f} {nx / norm:.7f} {ny / norm:.7f} {nz / norm:.7f} {feed:g}\n")


if __name__ == "__main__":
    main()
