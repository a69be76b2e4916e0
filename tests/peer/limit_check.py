#!/usr/bin/env python3
"""Independent axis-limit check of a recorded JointState stream (numpy; not fiveaxis code).

Reads sensor_msgs/JointState from an MCAP with mcap-ros2-support, takes the finite differences of
each joint at a wider stencil than fiveaxis' own check (spacing 2 samples: v = (q[k+2]-q[k-2])/4T,
a = (q[k+2]-2q[k]+q[k-2])/4T^2, j = (q[k+3]-3q[k+1]+3q[k-1]-q[k-3])/8T^3) and prints, as JSON, the
largest |v|/v_max, |a|/a_max, |j|/j_max per joint and overall, and the stream's duration.

usage: limit_check.py FILE.mcap TOPIC NAME=V_MAX,A_MAX,J_MAX ...   (SI units: m or rad)
"""
import json
import sys

import numpy as np
from mcap_ros2.reader import read_ros2_messages


def main():
    path, topic, specs = sys.argv[1], sys.argv[2], sys.argv[3:]
    limits = {}
    for s in specs:
        name, vals = s.split("=")
        limits[name] = [float(x) for x in vals.split(",")]
    t, pos, names = [], [], None
    for m in read_ros2_messages(path, topics=[topic]):
        msg = m.ros_msg
        names = list(msg.name)
        t.append(msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9)
        pos.append(list(msg.position))
    if not pos:
        print(json.dumps({"error": f"no messages on {topic}"}))
        return 2
    t = np.array(t)
    q = np.array(pos)
    T = float(np.median(np.diff(t)))
    # At rest before and after the recording: pad with the end values.
    q = np.vstack([np.repeat(q[:1], 3, axis=0), q, np.repeat(q[-1:], 3, axis=0)])
    v = (q[5:-1] - q[1:-5]) / (4 * T)
    a = (q[5:-1] - 2 * q[3:-3] + q[1:-5]) / (4 * T * T)
    j = (q[6:] - 3 * q[4:-2] + 3 * q[2:-4] - q[:-6]) / (8 * T ** 3)
    out = {"period_s": T, "duration_s": float(t[-1] - t[0]), "samples": int(len(t)), "joints": {}}
    worst = [0.0, 0.0, 0.0]
    for i, n in enumerate(names):
        if n not in limits:
            continue
        lv, la, lj = limits[n]
        r = [float(np.max(np.abs(v[:, i])) / lv), float(np.max(np.abs(a[:, i])) / la), float(np.max(np.abs(j[:, i])) / lj)]
        out["joints"][n] = r
        worst = [max(worst[k], r[k]) for k in range(3)]
    out["worst"] = worst
    if not out["joints"]:
        print(json.dumps({"error": f"none of {list(limits)} in {names}"}))
        return 2
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
