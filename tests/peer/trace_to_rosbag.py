#!/usr/bin/env python3
"""Write a control's joint trace as a rosbag2 MCAP directory with an independent writer (`rosbags`
from PyPI), the way a machine's ROS 2 bridge recorded with `ros2 bag record` looks: the machine's
`sensor_msgs/msg/JointState` on one topic, with foreign topics beside it (`/tf` as
`tf2_msgs/msg/TFMessage`, `/rosout` as `rcl_interfaces/msg/Log`, and a second JointState topic of
another device). Nothing here comes from fiveaxis.

Usage: trace_to_rosbag.py TRACE.csv[.gz] OUT_DIR [--topic /cnc/joint_states]
       [--names x_joint,y_joint,z_joint,a_joint,c_joint] [--modulo-c] [--units si|mm-deg]
       [--drop-joint NAME] [--nan-every N] [--limit N] [--storage mcap|sqlite3]

The trace's header is `t_s,x_mm,y_mm,z_mm,a_deg,c_deg,...` (joint positions as the control reports
them); the bag carries REP 103 units (m, rad) unless `--units mm-deg` (a bridge that forgot to
convert). Stamps and log times: 2026-01-01T00:00:00Z plus the trace's time.
"""
import argparse
import csv
import gzip
import math
import sys

import numpy as np

from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

EPOCH_NS = 1_767_225_600 * 10**9  # 2026-01-01T00:00:00Z


def read_trace(path, limit=None):
    opener = gzip.open if path.endswith(".gz") else open
    rows = []
    with opener(path, "rt") as f:
        for k, row in enumerate(csv.DictReader(f)):
            if limit is not None and k >= limit:
                break
            rows.append(row)
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("trace")
    ap.add_argument("out")
    ap.add_argument("--topic", default="/cnc/joint_states")
    ap.add_argument("--names", default="x_joint,y_joint,z_joint,a_joint,c_joint")
    ap.add_argument("--modulo-c", action="store_true")
    ap.add_argument("--units", choices=["si", "mm-deg"], default="si")
    ap.add_argument("--drop-joint")
    ap.add_argument("--nan-every", type=int)
    ap.add_argument("--limit", type=int)
    ap.add_argument("--storage", choices=["mcap", "sqlite3"], default="mcap")
    a = ap.parse_args()

    ts = get_typestore(Stores.ROS2_HUMBLE)
    JointState = ts.types["sensor_msgs/msg/JointState"]
    Header = ts.types["std_msgs/msg/Header"]
    Time = ts.types["builtin_interfaces/msg/Time"]
    TFMessage = ts.types["tf2_msgs/msg/TFMessage"]
    TransformStamped = ts.types["geometry_msgs/msg/TransformStamped"]
    Transform = ts.types["geometry_msgs/msg/Transform"]
    Vector3 = ts.types["geometry_msgs/msg/Vector3"]
    Quaternion = ts.types["geometry_msgs/msg/Quaternion"]
    Log = ts.types["rcl_interfaces/msg/Log"]

    names = a.names.split(",")
    rows = read_trace(a.trace, a.limit)
    if not rows:
        sys.exit("empty trace")

    def stamp(ns):
        return Time(sec=ns // 10**9, nanosec=ns % 10**9)

    plugin = StoragePlugin.SQLITE3 if a.storage == "sqlite3" else StoragePlugin.MCAP
    with Writer(a.out, version=8, storage_plugin=plugin) as w:
        tf = w.add_connection("/tf", TFMessage.__msgtype__, typestore=ts)
        log = w.add_connection("/rosout", Log.__msgtype__, typestore=ts)
        joints = w.add_connection(a.topic, JointState.__msgtype__, typestore=ts)
        other = w.add_connection("/gripper/joint_states", JointState.__msgtype__, typestore=ts)

        def write(conn, ns, msg):
            w.write(conn, ns, ts.serialize_cdr(msg, type(msg).__msgtype__))

        write(log, EPOCH_NS, Log(stamp=stamp(EPOCH_NS), level=20, name="cnc_bridge", msg="bridge up: LinuxCNC joint trace",
                                 file="bridge.py", function="main", line=1))
        for k, r in enumerate(rows):
            ns = EPOCH_NS + round(float(r["t_s"]) * 1e9)
            mm = [float(r["x_mm"]), float(r["y_mm"]), float(r["z_mm"])]
            deg = [float(r["a_deg"]), float(r["c_deg"])]
            if a.units == "si":
                pos = [v * 1e-3 for v in mm] + [math.radians(v) for v in deg]
                if a.modulo_c:
                    pos[4] = pos[4] % (2 * math.pi)
            else:
                pos = mm + deg
                if a.modulo_c:
                    pos[4] = pos[4] % 360.0
            if a.nan_every and k % a.nan_every == 0:
                pos[3] = float("nan")
            c_rad = pos[4] if a.units == "si" else math.radians(pos[4])
            n = list(names)
            if a.drop_joint:
                i = n.index(a.drop_joint)
                del n[i]
                del pos[i]
            msg = JointState(header=Header(stamp=stamp(ns), frame_id=""), name=n, position=np.array(pos, dtype=np.float64),
                             velocity=np.zeros(0), effort=np.zeros(0))
            write(joints, ns, msg)
            if k % 10 == 0:
                write(other, ns, JointState(header=Header(stamp=stamp(ns), frame_id=""), name=["finger"], position=np.array([0.01]), velocity=np.zeros(0), effort=np.zeros(0)))
            if k % 100 == 0:
                q = Quaternion(x=0.0, y=0.0, z=math.sin(c_rad / 2), w=math.cos(c_rad / 2))
                t = TransformStamped(header=Header(stamp=stamp(ns), frame_id="a_table"), child_frame_id="c_table",
                                     transform=Transform(translation=Vector3(x=0.0, y=0.0, z=0.0), rotation=q))
                write(tf, ns, TFMessage(transforms=[t]))
    print(f"wrote {len(rows)} JointState messages to {a.out}")


if __name__ == "__main__":
    main()
