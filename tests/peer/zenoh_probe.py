#!/usr/bin/env python3
# requirements: eclipse-zenoh==1.10.2
"""A Zenoh client (Eclipse Zenoh's Python API) that probes what a router lets through: `put` sends a
small payload on each --key every 100 ms; `watch` subscribes to each --key expression and lists
the keys it received. The fleet test runs one of each in a cell, to try what its router's access
control must refuse (another cell's keys, either way), and a watcher at the head office.

usage: zenoh_probe.py put|watch --connect tcp/10.81.2.1:7447 --key KEYEXPR [--key ...] [--for-s 6]
Prints one JSON object: {"sent": {key: n}} or {"received": {key: n}}.
"""
import argparse
import json
import threading
import time

import zenoh
from zenoh_client import client_config


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mode", choices=["put", "watch"])
    ap.add_argument("--connect", required=True)
    ap.add_argument("--key", action="append", required=True)
    ap.add_argument("--for-s", type=float, default=6.0)
    a = ap.parse_args()
    conf = client_config(a.connect)
    counts = {}
    lock = threading.Lock()
    with zenoh.open(conf) as session:
        if a.mode == "put":
            end = time.monotonic() + a.for_s
            while time.monotonic() < end:
                for k in a.key:
                    session.put(k, b"probe")
                    counts[k] = counts.get(k, 0) + 1
                time.sleep(0.1)
            print(json.dumps({"sent": counts}))
        else:
            def got(sample):
                with lock:
                    k = str(sample.key_expr)
                    counts[k] = counts.get(k, 0) + 1
            subs = [session.declare_subscriber(k, got) for k in a.key]
            time.sleep(a.for_s)
            for s in subs:
                s.undeclare()
            with lock:
                print(json.dumps({"received": counts}))


if __name__ == "__main__":
    main()
