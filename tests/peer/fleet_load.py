#!/usr/bin/env python3
# requirements: eclipse-zenoh==1.10.2, rosbags==0.11.9
"""Simulated machines on a fleet network, as fiveaxis-fleet gateways publish them, for the fleet
benchmark (benches/fleet): each of --machines N publishes a fiveaxis_msgs/SingularityStatus at
--rate-hz on rmw_zenoh's key under /plant/sim/mNN, stamped with the wall clock, with rmw_zenoh's
attachment (sequence number, send stamp, GID), and a DiagnosticArray at 2 Hz. The CDR comes from
rosbags' serializer (our .msg files registered in its ROS 2 Jazzy store), not from our Rust types:
each machine's messages are serialized once (ten phases of its distance) and each send writes its
stamp into the header (the first field: int32 sec, uint32 nanosec after the 4-byte encapsulation),
so that the generator keeps its rate in Python.

usage: fleet_load.py --connect tcp/127.0.0.1:7447 --msg-dir msgs/msg [--machines 49] [--rate-hz 10] [--duration-s 30]
                     [--ready FILE]   (created once the messages are made, before the first is sent)
"""
import argparse
import json
import math
import pathlib
import struct
import time

import zenoh
from zenoh_client import client_config
from rosbags.typesys import Stores, get_typestore, get_types_from_msg


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--connect", required=True)
    ap.add_argument("--msg-dir", required=True)
    ap.add_argument("--machines", type=int, default=49)
    ap.add_argument("--rate-hz", type=float, default=10.0)
    ap.add_argument("--duration-s", type=float, default=30.0)
    ap.add_argument("--ready")
    a = ap.parse_args()
    store = get_typestore(Stores.ROS2_JAZZY)
    for f in sorted(pathlib.Path(a.msg_dir).glob("*.msg")):
        store.register(get_types_from_msg(f.read_text(), f"fiveaxis_msgs/msg/{f.stem}"))
    T = store.types
    status_t, diag_t = "fiveaxis_msgs/msg/SingularityStatus", "diagnostic_msgs/msg/DiagnosticArray"

    def stamp(ns):
        return T["builtin_interfaces/msg/Time"](sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)

    def header(ns):
        return T["std_msgs/msg/Header"](stamp=stamp(ns), frame_id="")

    def status(ns, phase):
        a_rad = 0.02 + 0.3 * abs(math.sin(phase))
        return T[status_t](
            header=header(ns), source=1, input_topic="/fiveaxis/simulated/axis_state", motion=2,
            singularity_distance=a_rad, secondary_axis="C", predicted_c_speed=0.5 / math.sin(a_rad), c_speed=0.4,
            c_speed_limit=2.618, programmed_feed=0.0333, path_feed=0.0333, feed_limit=0.05, limiting_axis="",
            limit_kind=0, in_region=False, region_id=0, region_cause=0,
            workpiece_position=T["geometry_msgs/msg/Point"](x=0.025, y=0.05, z=-0.008), time_to_next_region=-1.0,
            program_line=10, block_number=-1, stale=False, invalid_count=0, missing_joint_count=0, non_finite_count=0,
            out_of_range_count=0, out_of_order_count=0, stale_count=0, lost_count=0)

    def diagnostics(ns):
        ok = T["diagnostic_msgs/msg/DiagnosticStatus"](level=0, name="fiveaxis_monitor: simulated", message="ok",
                                                      hardware_id="", values=[])
        return T[diag_t](header=header(ns), status=[ok])

    conf = client_config(a.connect)
    status_hash, diag_hash = store.hash_rihs01(status_t), store.hash_rihs01(diag_t)
    sent = 0
    phases = 10

    def stamped(cdr, ns):
        b = bytearray(cdr)
        struct.pack_into("<iI", b, 4, ns // 1_000_000_000, ns % 1_000_000_000)
        return bytes(b)

    with zenoh.open(conf) as session:
        machines = []
        for i in range(a.machines):
            ns = f"plant/sim/m{i:02d}"
            machines.append({
                "status": session.declare_publisher(f"0/{ns}/fiveaxis/monitor/status/fiveaxis_msgs::msg::dds_::SingularityStatus_/{status_hash}"),
                "diag": session.declare_publisher(f"0/{ns}/diagnostics/diagnostic_msgs::msg::dds_::DiagnosticArray_/{diag_hash}"),
                "gid": bytes([i]) * 16, "seq": 0,
                "statuses": [bytes(store.serialize_cdr(status(0, k * math.pi / phases + i), status_t)) for k in range(phases)],
                "diagnostics": bytes(store.serialize_cdr(diagnostics(0), diag_t))})
        if a.ready:
            pathlib.Path(a.ready).touch()
        period = 1.0 / a.rate_hz
        start = time.monotonic()
        tick = 0
        while time.monotonic() - start < a.duration_s:
            # The machines' statuses spread over the period, as independent gateways send them.
            for i, m in enumerate(machines):
                due = start + (tick + i / len(machines)) * period
                wait = due - time.monotonic()
                if wait > 0:
                    time.sleep(wait)
                now = time.time_ns()
                m["seq"] += 1
                att = struct.pack("<qqB", m["seq"], now, 16) + m["gid"]
                m["status"].put(stamped(m["statuses"][tick % phases], now), attachment=att)
                sent += 1
                if tick % max(1, round(a.rate_hz / 2)) == 0:
                    m["diag"].put(stamped(m["diagnostics"], now), attachment=att)
            tick += 1
    print(json.dumps({"machines": a.machines, "statuses_sent": sent, "seconds": time.monotonic() - start}))


if __name__ == "__main__":
    main()
