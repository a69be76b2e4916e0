#!/usr/bin/env python3
"""An SHDR log read independently of fiveaxis (Python's xml.etree and str.split only), by the
field counts of cppagent's Adapter Agent Protocol: a CONDITION data item takes five fields after its
key, a MESSAGE two, a legacy ALARM four, a TIME_SERIES three, any other one; `@ASSET@` lines with
`--multiline--TAG` bodies run to the line starting with the tag; `*` lines are commands.

Prints JSON: lines, data lines, the data lines that report any of the keys given (a value other
than UNAVAILABLE), and for each data item key given: reports (values other than
UNAVAILABLE), changes, and the median interval between its reports (s).

Usage: shdr_counts.py LOG DEVICES.XML DEVICE KEY [KEY ...]
"""
import datetime
import json
import statistics
import sys
import xml.etree.ElementTree as ET


def main():
    log, devices, device, keys = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    root = ET.parse(devices).getroot()
    ns = root.tag.split("}")[0] + "}" if root.tag.startswith("{") else ""
    dev = [d for d in root.iter(ns + "Device") if d.get("name") == device][0]
    items = {}
    for di in dev.iter(ns + "DataItem"):
        for k in (di.get("id"), di.get("name")):
            if k:
                items[k] = di

    def width(k):
        di = items.get(k)
        if di is None:
            return 1
        if di.get("category") == "CONDITION":
            return 5
        if di.get("type") == "MESSAGE":
            return 2
        if di.get("type") == "ALARM":
            return 4
        if di.get("representation") == "TIME_SERIES":
            return 3
        return 1

    def stamp(s):
        s = s.rstrip("Z")
        whole, _, frac = s.partition(".")
        t = datetime.datetime.strptime(whole, "%Y-%m-%dT%H:%M:%S").replace(tzinfo=datetime.timezone.utc).timestamp()
        return t + (float("0." + frac) if frac else 0.0)

    reports = {k: [] for k in keys}
    lines = data = with_any = 0
    multi = None
    with open(log, encoding="utf-8", errors="replace", newline="") as f:
        for raw in f:
            lines += 1
            line = raw.rstrip("\r\n")
            if multi:
                if line.startswith(multi):
                    multi = None
                continue
            if not line.strip() or line.startswith("*"):
                continue
            fields = line.split("|")
            data += 1
            t = stamp(fields[0])
            any_here = False
            j = 1
            while j < len(fields):
                k = fields[j]
                if k.startswith("@") and k.endswith("@"):
                    if k == "@ASSET@" and fields[-1].startswith("--multiline--"):
                        multi = fields[-1]
                    break
                w = width(k)
                if k in reports and fields[j + 1].strip().upper() != "UNAVAILABLE":
                    reports[k].append((t, float(fields[j + 1])))
                    any_here = True
                j += 1 + w
            with_any += any_here
    out = {"lines": lines, "data_lines": data, "lines_with_any": with_any, "items": {}}
    for k, r in reports.items():
        changes = sum(1 for a, b in zip(r, r[1:]) if a[1] != b[1])
        gaps = [b[0] - a[0] for a, b in zip(r, r[1:]) if b[0] > a[0]]
        out["items"][k] = {"reports": len(r), "changes": changes, "median_interval_s": statistics.median(gaps) if gaps else None}
    json.dump(out, sys.stdout)


if __name__ == "__main__":
    main()
