#!/usr/bin/env python3
# requirements: cyclonedds==11.0.1 (as tests/peer/cyclone_bridge.py)
"""Join /rosout late, as rqt_console or `ros2 topic echo /rosout` started mid-run would, and count
the log history each node's transient-local writer hands over.

usage (inside netns-run): rosout_history.py --duration-s S [--domain-id N]
    Reads rt/rosout (rcl_interfaces/msg/Log) for S seconds with a reliable, transient-local,
    keep-last 100000 reader (far deeper than any writer's history, so the writer's retention is
    what limits the count). Prints JSON: {"by_node": {name: count}, "total": N}.
"""
import argparse
import json
import os
import sys
import time
from dataclasses import dataclass

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cyclone_bridge import Time, make_participant, rmw_qos  # noqa: E402  (as rmw_cyclonedds has them)
from cyclonedds.idl import IdlStruct  # noqa: E402
from cyclonedds.idl.types import uint8, uint32  # noqa: E402


@dataclass
class Log(IdlStruct, typename="rcl_interfaces::msg::dds_::Log_"):
    stamp: Time = None
    level: uint8 = 0
    name: str = ""
    msg: str = ""
    file: str = ""
    function: str = ""
    line: uint32 = 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--duration-s", type=float, required=True)
    ap.add_argument("--domain-id", type=int, default=int(os.environ.get("ROS_DOMAIN_ID", "0") or 0))
    args = ap.parse_args()

    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic

    participant = make_participant(args.domain_id)
    qos = rmw_qos("reliable", 100000, transient_local=True)
    reader = DataReader(participant, Topic(participant, "rt/rosout", Log), qos=qos)
    by_node = {}
    end = time.monotonic() + args.duration_s
    while time.monotonic() < end:
        for log in reader.take(N=10000):
            if isinstance(log, Log):
                by_node[log.name] = by_node.get(log.name, 0) + 1
        time.sleep(0.05)
    print(json.dumps({"by_node": by_node, "total": sum(by_node.values())}))


if __name__ == "__main__":
    main()
