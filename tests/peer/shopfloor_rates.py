#!/usr/bin/env python3
"""A control's 1 kHz joint trace as shop-floor interfaces deliver it, written without fiveaxis:

- `together --period P`: every axis sampled at once every P s (an OPC UA subscription's sampling
  interval: a Sinumerik allows 100, 250, 500 ms ...), stamped when sent (a latency of 2-40 ms after
  the sample, random).
- `per-axis --period P`: each axis sampled on its own clock (period P +-10 %, its own phase) and
  reported only when it changed (an MTConnect adapter's SHDR: a data item is sent when its value
  differs from the last one sent), stamped with the adapter's clock when read (to the millisecond,
  as SHDR timestamps are written; MTConnect Part 1, "timestamp: the time the data was observed").

Output: a rosbag2 directory (`rosbags` from PyPI) of `sensor_msgs/msg/JointState` (REP 103, m and
rad) on /cnc/joint_states, either `--held` (a bridge that republishes every joint at each report,
the others held at their last reported value) or partial (only the joints reported: legal in ROS,
what a change-only bridge publishes); or `--shdr FILE`, an adapter's SHDR log
(`2026-01-01T00:00:01.234000Z|Xact|12.3456`, mm and degrees, as cppagent's demo log is written),
with the device's description beside it (OUT.devices.xml: MTConnectDevices 2.0 with Linear X Y Z and
Rotary A C, each an actual POSITION or ANGLE sample in machine coordinates).

Usage: shopfloor_rates.py TRACE.csv[.gz] OUT (together|per-axis) --period P [--held] [--shdr]
       [--seed N] [--t0 S] [--t1 S]
"""
import argparse
import csv
import datetime
import gzip
import math

import numpy as np

EPOCH_NS = 1_767_225_600 * 10**9  # 2026-01-01T00:00:00Z
NAMES = ["x_joint", "y_joint", "z_joint", "a_joint", "c_joint"]
SHDR_NAMES = ["Xact", "Yact", "Zact", "Aact", "Cact"]


def read_trace(path):
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        rows = list(csv.DictReader(f))
    t = np.array([float(r["t_s"]) for r in rows])
    q = np.array([[float(r[k]) for k in ("x_mm", "y_mm", "z_mm", "a_deg", "c_deg")] for r in rows])
    return t, q


def reports(t, q, mode, period, rng):
    """(send time s, axis index, value in mm/deg) in send order."""
    out = []
    t_end = t[-1]
    if mode == "together":
        k = 0
        while k * period <= t_end:
            ts = k * period
            i = min(np.searchsorted(t, ts), len(t) - 1)
            send = ts + rng.uniform(0.002, 0.040)
            for j in range(5):
                out.append((send, j, q[i, j], k))
            k += 1
    else:
        for j in range(5):
            ts = rng.uniform(0.0, period)
            last = None
            while ts <= t_end:
                i = min(np.searchsorted(t, ts), len(t) - 1)
                v = round(q[i, j], 4)
                if last is None or v != last:
                    out.append((round(ts, 3), j, v, None))
                    last = v
                ts += period * rng.uniform(0.9, 1.1)
    out.sort(key=lambda r: r[0])
    return out


def stamp_text(seconds):
    ns = EPOCH_NS + round(seconds * 1e9)
    d = datetime.datetime.fromtimestamp(ns // 10**9, datetime.timezone.utc)
    return d.strftime("%Y-%m-%dT%H:%M:%S") + f".{(ns % 10**9) // 1000:06d}Z"


def si(j, v):
    return v * 1e-3 if j < 3 else math.radians(v)


def write_devices(path):
    axes = []
    for j, name in enumerate("XYZAC"):
        linear = j < 3
        element = "Linear" if linear else "Rotary"
        kind, units = ("POSITION", "MILLIMETER") if linear else ("ANGLE", "DEGREE")
        axes.append(f"""        <{element} id="{name.lower()}" name="{name}">
          <DataItems>
            <DataItem category="SAMPLE" id="{name.lower()}_act" name="{SHDR_NAMES[j]}" type="{kind}" subType="ACTUAL" units="{units}" coordinateSystemIdRef="machcoord"/>
            <DataItem category="SAMPLE" id="{name.lower()}_load" name="{name}load" type="LOAD" units="PERCENT"/>
            <DataItem category="CONDITION" id="{name.lower()}_travel" type="POSITION"/>
          </DataItems>
        </{element}>""")
    with open(path, "w") as f:
        f.write(f"""<?xml version="1.0" encoding="UTF-8"?>
<MTConnectDevices xmlns="urn:mtconnect.org:MTConnectDevices:2.0">
  <Header creationTime="2026-01-01T00:00:00Z" sender="shopfloor_rates.py" instanceId="1" version="2.0" bufferSize="131072"/>
  <Devices>
    <Device id="c600u" name="C600U" uuid="hermle-c600u-sim">
      <Configuration>
        <CoordinateSystems>
          <CoordinateSystem id="machcoord" type="MACHINE"/>
        </CoordinateSystems>
      </Configuration>
      <DataItems>
        <DataItem category="EVENT" id="avail" name="avail" type="AVAILABILITY"/>
      </DataItems>
      <Components>
        <Axes id="axes" name="base">
          <Components>
{chr(10).join(axes)}
          </Components>
        </Axes>
        <Controller id="cont" name="controller">
          <DataItems>
            <DataItem category="EVENT" id="exec" name="execution" type="EXECUTION"/>
            <DataItem category="EVENT" id="msg" name="message" type="MESSAGE"/>
          </DataItems>
        </Controller>
      </Components>
    </Device>
  </Devices>
</MTConnectDevices>
""")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("trace")
    ap.add_argument("out")
    ap.add_argument("mode", choices=["together", "per-axis"])
    ap.add_argument("--period", type=float, required=True)
    ap.add_argument("--held", action="store_true")
    ap.add_argument("--shdr", action="store_true")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    t, q = read_trace(a.trace)
    reps = reports(t, q, a.mode, a.period, rng)

    if a.shdr:
        write_devices(a.out + ".devices.xml")
        with open(a.out, "w") as f:
            f.write(f"{stamp_text(0.0)}|avail|AVAILABLE|execution|ACTIVE\n")
            k = 0
            while k < len(reps):
                send = reps[k][0]
                items = []
                # What one sample of the adapter sends together goes on one line.
                while k < len(reps) and reps[k][0] == send:
                    items.append(f"{SHDR_NAMES[reps[k][1]]}|{reps[k][2]:.4f}")
                    k += 1
                f.write(f"{stamp_text(send)}|{'|'.join(items)}\n")
        print(f"wrote {len(reps)} axis reports to {a.out}")
        return

    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS2_HUMBLE)
    JointState = ts.types["sensor_msgs/msg/JointState"]
    Header = ts.types["std_msgs/msg/Header"]
    Time = ts.types["builtin_interfaces/msg/Time"]
    held = [None] * 5
    count = 0
    with Writer(a.out, version=8, storage_plugin=StoragePlugin.MCAP) as w:
        conn = w.add_connection("/cnc/joint_states", JointState.__msgtype__, typestore=ts)
        k = 0
        while k < len(reps):
            send = reps[k][0]
            names, pos = [], []
            while k < len(reps) and reps[k][0] == send:
                _, j, v, _ = reps[k]
                held[j] = si(j, v)
                names.append(NAMES[j])
                pos.append(si(j, v))
                k += 1
            if a.held:
                if any(h is None for h in held):
                    continue
                names, pos = list(NAMES), list(held)
            ns = EPOCH_NS + round(send * 1e9)
            msg = JointState(header=Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id=""), name=names,
                             position=np.array(pos, dtype=np.float64), velocity=np.zeros(0), effort=np.zeros(0))
            w.write(conn, ns, ts.serialize_cdr(msg, JointState.__msgtype__))
            count += 1
    print(f"wrote {count} JointState messages ({len(reps)} axis reports) to {a.out}")


if __name__ == "__main__":
    main()
