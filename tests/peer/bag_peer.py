#!/usr/bin/env python3
# requirements: cyclonedds==11.0.1 (publish), rosbags (check)
"""Independent ends of the recorder's bag test.

  publish --out SENT.json [--count N] [--wait-s S]
      (inside launch-free-scripts/netns-run) publish, with Cyclone DDS as rmw_cyclonedds does, N
      sensor_msgs/JointState on /cnc/joint_states and N std_msgs/String on /chatter (a type fiveaxis
      has no definition of) once a reader has matched each writer; write every sample's serialized
      bytes (hex, with the CDR encapsulation header) to SENT.json.

  check BAG SENT.json|-
      open BAG (a rosbag2 directory) with rosbags' AnyReader, which reads metadata.yaml, and decode
      every message of every topic (types from the bag's stored definitions; a topic stored without
      one from rosbags' own ROS 2 Jazzy type store). Checks that the published messages are in the
      bag, in order, byte for byte (the encapsulation options aside: RustDDS does not pass them on),
      decode to what was sent (with SENT.json), and that metadata.yaml's counts are the messages in the files. Prints
      one JSON line; exit 1 on a mismatch.
"""
import argparse
import json
import os
import sys
import time
from dataclasses import dataclass

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def publish(args):
    from cyclonedds.idl import IdlStruct
    from cyclonedds.pub import DataWriter
    from cyclonedds.topic import Topic
    from cyclonedds.util import duration
    from cyclone_bridge import JointState, Header, Time, TYPEHASH, make_participant, rmw_qos, default_domain_id

    @dataclass
    class String(IdlStruct, typename="std_msgs::msg::dds_::String_"):
        data: str = ""

    p = make_participant(default_domain_id())
    joints = DataWriter(p, Topic(p, "rt/cnc/joint_states", JointState), qos=rmw_qos("reliable", 1000, TYPEHASH["sensor_msgs/msg/JointState"]))
    chatter = DataWriter(p, Topic(p, "rt/chatter", String), qos=rmw_qos("reliable", 1000))
    deadline = time.monotonic() + args.wait_s
    while time.monotonic() < deadline:
        if all(w.get_publication_matched_status().current_count > 0 for w in (joints, chatter)):
            break
        time.sleep(0.05)
    else:
        raise SystemExit("no reader matched both writers (is the recorder running with --all?)")
    time.sleep(0.3)
    sent = {"/cnc/joint_states": [], "/chatter": []}
    values = {"/cnc/joint_states": [], "/chatter": []}
    for k in range(args.count):
        js = JointState(
            header=Header(stamp=Time(1_700_000_000 + k // 1000, (k % 1000) * 1_000_000), frame_id="table"),
            name=["x_joint", "y_joint", "z_joint", "a_joint", "c_joint"],
            position=[0.001 * k, -0.002 * k, 0.05, 0.01 * k, 0.1 * k],
            velocity=[0.1, 0.0, 0.0, 0.0, 1.0],
            effort=[],
        )
        s = String(data=f"message {k}: é{'x' * (k % 7)}")
        joints.write(js)
        chatter.write(s)
        sent["/cnc/joint_states"].append(js.serialize().hex())
        sent["/chatter"].append(s.serialize().hex())
        values["/cnc/joint_states"].append(js.position)
        values["/chatter"].append(s.data)
        time.sleep(0.005)
    for w in (joints, chatter):
        w.wait_for_acks(duration(seconds=10))
    time.sleep(0.5)
    with open(args.out, "w") as f:
        json.dump({"sent": sent, "values": values}, f)
    print(json.dumps({"published": args.count}))


def check(args):
    from pathlib import Path
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    expected = json.load(open(args.sent)) if args.sent != "-" else {"sent": {}, "values": {}}
    problems = []
    seen = {}
    decoded = {}
    raw = {}
    from rosbags.interfaces import MessageDefinitionFormat
    from ruamel.yaml import YAML
    jazzy = get_typestore(Stores.ROS2_JAZZY)
    with AnyReader([Path(args.bag)], default_typestore=jazzy) as reader:
        counts_meta = {c.topic: c.msgcount for c in reader.connections}
        types = {c.topic: c.msgtype for c in reader.connections}
        defined = {c.topic: c.msgdef.format != MessageDefinitionFormat.NONE and bool(c.msgdef.data.strip()) for c in reader.connections}
        for conn, _t, data in reader.messages():
            # A topic stored without a definition (as ros2 bag stores a type it does not know) is
            # decoded with rosbags' own ROS 2 Jazzy types; AnyReader registers only the bag's.
            if defined[conn.topic]:
                msg = reader.deserialize(data, conn.msgtype)
            else:
                msg = jazzy.deserialize_cdr(bytes(data), conn.msgtype)
            seen[conn.topic] = seen.get(conn.topic, 0) + 1
            if conn.topic == "/cnc/joint_states":
                decoded.setdefault(conn.topic, []).append(list(msg.position))
            elif conn.topic == "/chatter":
                decoded.setdefault(conn.topic, []).append(msg.data)
            if conn.topic in expected["sent"]:
                raw.setdefault(conn.topic, []).append(bytes(data))
    version = YAML(typ="safe").load(Path(args.bag, "metadata.yaml").read_text())["rosbag2_bagfile_information"]["version"]
    for topic, n in seen.items():
        if counts_meta.get(topic) != n:
            problems.append(f"{topic}: metadata.yaml says {counts_meta.get(topic)} messages, the files hold {n}")
    for topic, sent in expected["sent"].items():
        got = raw.get(topic, [])
        if len(got) != len(sent):
            problems.append(f"{topic}: {len(got)} messages in the bag, {len(sent)} sent")
        for k, (g, s) in enumerate(zip(got, sent)):
            s = bytes.fromhex(s)
            body_ok = g[4:4 + len(s) - 4] == s[4:] and all(b == 0 for b in g[len(s):]) and len(g) - len(s) < 4
            if g[:2] != s[:2] or not body_ok:
                problems.append(f"{topic} message {k}: stored {g.hex()} sent {s.hex()}")
                break
        if decoded.get(topic) != expected["values"][topic]:
            problems.append(f"{topic}: decoded values differ from those sent")
    out = {
        "version": version,
        "topics": {t: {"type": types[t], "count": seen.get(t, 0), "definition": defined[t]} for t in types},
        "problems": problems,
    }
    print(json.dumps(out))
    sys.exit(1 if problems else 0)


def main():
    ap = argparse.ArgumentParser()
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("publish")
    p.add_argument("--out", required=True)
    p.add_argument("--count", type=int, default=200)
    p.add_argument("--wait-s", type=float, default=30.0)
    c = sub.add_parser("check")
    c.add_argument("bag")
    c.add_argument("sent")
    a = ap.parse_args()
    publish(a) if a.cmd == "publish" else check(a)


if __name__ == "__main__":
    main()
