#!/usr/bin/env python3
# requirements: eclipse-zenoh==1.10.2
"""An independent Zenoh peer (Eclipse Zenoh's Python API, not our Rust crates) reading a machine's
monitor status (or its simulated axis states) from a fleet router, as an rmw_zenoh subscriber would:
the key `<domain>/<namespace>/fiveaxis/monitor/status/<DDS type>/<type hash>`, the payload CDR with
its 4-byte encapsulation header (fiveaxis_msgs/msg/SingularityStatus or sensor_msgs/msg/JointState,
decoded here from the .msg layout with CDR's alignment rules), and rmw_zenoh's 33-byte attachment
(sequence number, source stamp, GID).

usage: zenoh_peer.py --connect tcp/127.0.0.1:7447 --machine /plant/cell_a/c600u [--count 5] [--timeout-s 20]
                     [--root-ca ca.pem] [--topic status|joint_states]
Prints one JSON object: {"samples": [{"key", "seq", "stamp_ns" (the send stamp), "received_ns",
"header_stamp_ns", "input_topic", "singularity_distance",
"predicted_c_speed", "in_region", "region_id", "x"}...]} (for joint_states: "name", "position"), and
"error" when the router refused the session.
"""
import argparse
import json
import queue
import struct
import time

import zenoh
from zenoh_client import client_config


class Cdr:
    """Little-endian CDR body reader; alignment counts from the body's start (after the header)."""

    def __init__(self, data):
        if len(data) < 4 or data[0:2] not in (b"\x00\x01", b"\x00\x03"):
            raise ValueError(f"not a CDR_LE payload: {data[:4]!r}")
        self.b = data[4:]
        self.i = 0

    def align(self, n):
        self.i += (-self.i) % n

    def take(self, fmt, n):
        self.align(n)
        (v,) = struct.unpack_from("<" + fmt, self.b, self.i)
        self.i += n
        return v

    def u8(self):
        return self.take("B", 1)

    def u32(self):
        return self.take("I", 4)

    def i32(self):
        return self.take("i", 4)

    def f64(self):
        return self.take("d", 8)

    def string(self):
        n = self.u32()
        s = self.b[self.i:self.i + n - 1].decode()
        self.i += n
        return s


def status(payload):
    c = Cdr(payload)
    sec, nanosec = c.i32(), c.u32()
    c.string()  # header: frame_id
    c.u8()  # source
    out = {"header_stamp_ns": sec * 1_000_000_000 + nanosec, "input_topic": c.string()}
    c.u8()  # motion
    out["singularity_distance"] = c.f64()
    c.string()  # secondary_axis
    out["predicted_c_speed"] = c.f64()
    for _ in range(5):  # c_speed, c_speed_limit, programmed_feed, path_feed, feed_limit
        c.f64()
    c.string()  # limiting_axis
    c.u8()  # limit_kind
    out["in_region"] = bool(c.u8())
    out["region_id"] = c.u32()
    c.u8()  # region_cause
    out["x"] = c.f64()
    return out


def joint_state(payload):
    c = Cdr(payload)
    c.i32(), c.u32(), c.string()  # header: stamp, frame_id
    names = [c.string() for _ in range(c.u32())]
    position = [c.f64() for _ in range(c.u32())]
    return {"name": names, "position": position}


TOPICS = {
    "status": ("fiveaxis/monitor/status/fiveaxis_msgs::msg::dds_::SingularityStatus_", status),
    "joint_states": ("fiveaxis/simulated/joint_states/sensor_msgs::msg::dds_::JointState_", joint_state),
}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--connect", required=True)
    ap.add_argument("--machine", required=True)
    ap.add_argument("--domain", type=int, default=0)
    ap.add_argument("--count", type=int, default=5)
    ap.add_argument("--timeout-s", type=float, default=20.0)
    ap.add_argument("--topic", choices=sorted(TOPICS), default="status")
    ap.add_argument("--root-ca", help="for a tls/ endpoint: the CA to trust (no client certificate is presented)")
    a = ap.parse_args()
    conf = client_config(a.connect, a.root_ca)
    topic, decode = TOPICS[a.topic]
    key = f"{a.domain}/{a.machine.strip('/')}/{topic}/*"
    got = queue.Queue()
    try:
        session = zenoh.open(conf)
    except Exception as e:  # a router that refuses us (mTLS without a certificate)
        print(json.dumps({"samples": [], "error": str(e)}))
        return
    with session:
        sub = session.declare_subscriber(key, lambda s: got.put((str(s.key_expr), s.payload.to_bytes(),
                                                                  s.attachment.to_bytes() if s.attachment else b"",
                                                                  time.time_ns())))
        samples = []
        end = time.monotonic() + a.timeout_s
        while len(samples) < a.count and time.monotonic() < end:
            try:
                k, payload, att, received = got.get(timeout=0.2)
            except queue.Empty:
                continue
            if len(att) != 33 or att[16] != 16:
                raise SystemExit(f"{k}: attachment of {len(att)} bytes, not rmw_zenoh's 33")
            seq, stamp = struct.unpack_from("<qq", att, 0)
            samples.append({"key": k, "seq": seq, "stamp_ns": stamp, "received_ns": received, **decode(payload)})
        sub.undeclare()
    print(json.dumps({"samples": samples}))


if __name__ == "__main__":
    main()
