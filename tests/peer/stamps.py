#!/usr/bin/env python3
# requirements: rosbags==0.11.9, cyclonedds==11.0.1 (as tests/peer/bag_peer.py, tests/peer/ros_graph.py)
"""Which clock a run stamped its messages in, read by tools that are not fiveaxis's.

usage:
  stamps.py bag BAG
      Open the rosbag2 directory BAG with rosbags' AnyReader and decode every message (types from
      the bag's definitions, else rosbags' ROS 2 Jazzy store). Prints one JSON object per topic:
      {"/topic": {"type", "count", "stamped", "min_ns", "max_ns", "log_min_ns", "log_max_ns"}}, the
      stamps being each message's header.stamp, stamp (rcl_interfaces/Log, ParameterEvent) or clock
      (rosgraph_msgs/Clock), the log times the bag's receive times.
  stamps.py endpoints --topic /clock --duration-s S [--ready FILE] [--until FILE] [--domain-id N]
      (inside netns-run) Watch DDS discovery (Cyclone DDS's DCPSPublication / DCPSSubscription
      built-in topics) for S seconds and print every writer and reader of the ROS topic with its type:
      {"publications": [[topic, type], ...], "subscriptions": [...]}, types in ROS form. --ready: FILE
      is created once the readers exist (a caller starts the nodes after it, so that none comes and
      goes unseen while Python starts); --until: stop once FILE exists (S is then the limit).
"""
import argparse
import json
import os
import sys
import time


def stamp_ns(msg):
    """The time a message carries, ns, or None."""
    for path in (("header", "stamp"), ("stamp",), ("clock",)):
        v = msg
        for f in path:
            v = getattr(v, f, None)
            if v is None:
                break
        if v is not None and hasattr(v, "sec") and hasattr(v, "nanosec"):
            return int(v.sec) * 1_000_000_000 + int(v.nanosec)
    return None


def bag(args):
    from pathlib import Path
    from rosbags.highlevel import AnyReader
    from rosbags.interfaces import MessageDefinitionFormat
    from rosbags.typesys import Stores, get_typestore

    jazzy = get_typestore(Stores.ROS2_JAZZY)
    out = {}
    with AnyReader([Path(args.bag)], default_typestore=jazzy) as reader:
        for conn, log_ns, data in reader.messages():
            defined = conn.msgdef.format != MessageDefinitionFormat.NONE and bool(conn.msgdef.data.strip())
            msg = reader.deserialize(data, conn.msgtype) if defined else jazzy.deserialize_cdr(bytes(data), conn.msgtype)
            t = out.setdefault(conn.topic, {"type": conn.msgtype, "count": 0, "stamped": 0, "min_ns": None, "max_ns": None,
                                             "log_min_ns": None, "log_max_ns": None})
            t["count"] += 1
            s = stamp_ns(msg)
            if s is not None:
                t["stamped"] += 1
                t["min_ns"] = s if t["min_ns"] is None else min(t["min_ns"], s)
                t["max_ns"] = s if t["max_ns"] is None else max(t["max_ns"], s)
                # The second-earliest stamp: the pacing after the first sample's acknowledgement.
                low = sorted(set(t.pop("_low", []) + [s]))[:2]
                t["_low"] = low
            t["log_min_ns"] = log_ns if t["log_min_ns"] is None else min(t["log_min_ns"], log_ns)
            t["log_max_ns"] = log_ns if t["log_max_ns"] is None else max(t["log_max_ns"], log_ns)
    for t in out.values():
        low = t.pop("_low", [])
        t["second_ns"] = low[1] if len(low) > 1 else None
    print(json.dumps(out))


def endpoints(args):
    from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication, BuiltinTopicDcpsSubscription
    from cyclonedds.domain import DomainParticipant
    from ros_graph import ros_type  # beside this script: DDS type names in ROS form

    dp = DomainParticipant(args.domain_id)
    readers = {"publications": BuiltinDataReader(dp, BuiltinTopicDcpsPublication),
               "subscriptions": BuiltinDataReader(dp, BuiltinTopicDcpsSubscription)}
    seen = {k: {} for k in readers}
    want = "rt" + args.topic
    if args.ready:
        open(args.ready, "w").close()
    end = time.monotonic() + args.duration_s
    while time.monotonic() < end:
        done = bool(args.until) and os.path.exists(args.until)
        for kind, r in readers.items():
            for s in r.take(N=100):
                if s.topic_name == want:
                    seen[kind][s.key.bytes.hex()] = [args.topic, ros_type(s.type_name)]
        if done:
            break
        time.sleep(0.05)
    print(json.dumps({k: sorted(v.values()) for k, v in seen.items()}))


def main():
    ap = argparse.ArgumentParser()
    sub = ap.add_subparsers(dest="cmd", required=True)
    b = sub.add_parser("bag")
    b.add_argument("bag")
    e = sub.add_parser("endpoints")
    e.add_argument("--topic", required=True)
    e.add_argument("--duration-s", type=float, required=True)
    e.add_argument("--ready")
    e.add_argument("--until")
    e.add_argument("--domain-id", type=int, default=int(os.environ.get("ROS_DOMAIN_ID", "0") or 0))
    a = ap.parse_args()
    (bag if a.cmd == "bag" else endpoints)(a)


if __name__ == "__main__":
    sys.exit(main())
