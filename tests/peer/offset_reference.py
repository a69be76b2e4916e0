#!/usr/bin/env python3
"""Independent reference for tool radius compensation: a programmed contour's offset by shapely
(GEOS' OffsetCurve: round joins at outside corners, the offset elements meeting at inside ones),
against the tool-centre path a reader made.

Input (JSON on stdin): {"radius": r, "side": "left"|"right", "contour": [elements], "path": [elements]}
where an element is {"kind": "line", "from": [x, y], "to": [x, y]} or {"kind": "arc", "from": [x, y],
"to": [x, y], "centre": [x, y], "ccw": bool}, in mm. Prints JSON: how far the path's points are from
standing the radius from the contour (mm, exact), the Hausdorff distance (mm) between the path and
shapely's offset curve (which GEOS simplifies by a hundredth of the radius), and that curve's first
and last points.
"""
import json
import math
import os
import sys

import numpy as np
import shapely

STEP_DEG = 0.1


def sample(elements):
    pts = []
    for e in elements:
        a = np.array(e["from"], float)
        b = np.array(e["to"], float)
        if e["kind"] == "line":
            n = max(2, int(np.linalg.norm(b - a) / 0.02) + 1)
            seg = [a + (b - a) * t for t in np.linspace(0.0, 1.0, n)]
        else:
            c = np.array(e["centre"], float)
            r = np.linalg.norm(a - c)
            t0 = math.atan2(a[1] - c[1], a[0] - c[0])
            t1 = math.atan2(b[1] - c[1], b[0] - c[0])
            if e["ccw"]:
                sweep = (t1 - t0) % (2 * math.pi) or 2 * math.pi
            else:
                sweep = -((t0 - t1) % (2 * math.pi) or 2 * math.pi)
            n = max(2, int(abs(math.degrees(sweep)) / STEP_DEG) + 1)
            seg = [c + r * np.array([math.cos(t0 + sweep * t), math.sin(t0 + sweep * t)]) for t in np.linspace(0.0, 1.0, n)]
        if pts and np.linalg.norm(pts[-1] - seg[0]) < 1e-9:
            seg = seg[1:]
        pts.extend(seg)
    return np.array(pts)


def main():
    data = json.load(sys.stdin)
    if os.environ.get("OFFSET_REFERENCE_DUMP"):
        with open(os.environ["OFFSET_REFERENCE_DUMP"], "a") as f:
            f.write(json.dumps(data) + "\n")
    r = data["radius"]
    contour = shapely.LineString(sample(data["contour"]))
    # shapely: a positive distance offsets to the left of the line's direction, a negative one to the right.
    offset = contour.offset_curve(r if data["side"] == "left" else -r, quad_segs=256, join_style="round")
    ours = sample(data["path"])
    path = shapely.LineString(ours)
    coords = list(offset.coords) if offset.geom_type == "LineString" else []
    # Where each curve strays furthest from the other (for a failure's message).
    off_pts = np.array([c for g in getattr(offset, "geoms", [offset]) for c in g.coords])
    d_ours = shapely.distance(shapely.points(ours), offset)
    d_off = shapely.distance(shapely.points(off_pts), path)
    # Exactly, without GEOS' simplification: every point of the path stands the radius from the contour.
    d_contour = shapely.distance(shapely.points(ours), contour)
    print(json.dumps({
        "radius_error_mm": float(np.abs(d_contour - r).max()),
        "hausdorff_mm": max(float(d_ours.max()), float(d_off.max())),
        "worst_path_point": ours[int(d_ours.argmax())].tolist(),
        "worst_offset_point": off_pts[int(d_off.argmax())].tolist(),
        "offset_type": offset.geom_type,
        "first": coords[0] if coords else None,
        "last": coords[-1] if coords else None,
    }))


if __name__ == "__main__":
    main()
