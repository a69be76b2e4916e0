#!/usr/bin/env python3
# requirements: rosbags==0.11.9 (as tests/peer/trace_to_rosbag.py)
"""REP 2016 type hashes computed by rosbags (its own implementation of rosidl's type description
hashing), for the standard types from its ROS 2 Jazzy store and for fiveaxis_msgs from our .msg files.

usage: type_hashes.py MSG_DIR TYPE...   (TYPE as pkg/msg/Type)
Prints {TYPE: "RIHS01_..."}.
"""
import json
import pathlib
import sys

from rosbags.typesys import Stores, get_typestore, get_types_from_msg


def main():
    msg_dir = pathlib.Path(sys.argv[1])
    store = get_typestore(Stores.ROS2_JAZZY)
    for f in sorted(msg_dir.glob("*.msg")):
        store.register(get_types_from_msg(f.read_text(), f"fiveaxis_msgs/msg/{f.stem}"))
    print(json.dumps({t: store.hash_rihs01(t) for t in sys.argv[2:]}))


if __name__ == "__main__":
    main()
