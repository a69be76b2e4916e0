#!/usr/bin/env python3
"""Capture the UDP datagrams on the loopback interface (a raw AF_PACKET socket; run inside the
test's private network namespace, where the namespace's root may open one) until told to stop, and
count those that carry a given byte string in the clear. Prints JSON: {"datagrams": N, "bytes": B,
"with_needle": K}. Used to check that DDS Security encrypts what it protects: the same topic
without security shows the needle (a string field of every message) in the clear.

Usage: sniff.py --needle TEXT --duration-s S [--ready FILE] [--stop FILE]

--duration-s is the longest it listens; with --stop it ends sooner, once FILE exists (the test makes
it when the publisher it watches has ended, so a slow machine does not cut the capture short).
"""
import argparse
import json
import socket
import struct
import time
from pathlib import Path

ETH_P_ALL = 0x0003


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--needle", required=True)
    ap.add_argument("--duration-s", type=float, required=True)
    ap.add_argument("--ready", help="file created once the socket listens")
    ap.add_argument("--stop", help="stop listening once this file exists")
    args = ap.parse_args()
    needle = args.needle.encode()
    s = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.ntohs(ETH_P_ALL))
    s.bind(("lo", 0))
    s.settimeout(0.2)
    if args.ready:
        Path(args.ready).write_text("ready\n")
    datagrams = total = hits = 0
    end = time.monotonic() + args.duration_s
    stop = Path(args.stop) if args.stop else None
    while time.monotonic() < end and not (stop and stop.exists()):
        try:
            frame, addr = s.recvfrom(70000)
        except socket.timeout:
            continue
        # Loopback frames carry an Ethernet header (14 bytes); each datagram is seen once outgoing
        # (PACKET_OUTGOING) and once incoming: count the outgoing copy only.
        if addr[2] == socket.PACKET_OUTGOING or len(frame) < 14 + 20 + 8:
            continue
        if struct.unpack_from("!H", frame, 12)[0] != 0x0800:
            continue
        ihl = (frame[14] & 0x0F) * 4
        if frame[14 + 9] != 17:  # UDP
            continue
        payload = frame[14 + ihl + 8:]
        datagrams += 1
        total += len(payload)
        if needle in payload:
            hits += 1
    print(json.dumps({"datagrams": datagrams, "bytes": total, "with_needle": hits}))


if __name__ == "__main__":
    main()
