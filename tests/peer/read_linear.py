#!/usr/bin/env python3
"""Read an MCAP file front to back with Foxglove's `mcap` package (PyPI) as a stream: every record,
chunk CRCs checked, the file required to end in a Footer and the closing magic (the stream reader
raises on a file cut short). Prints JSON: message count, whether a summary is present, and per
message its channel topic, log time and the MD5 of its data (to compare against another file).

Usage: read_linear.py FILE.mcap
"""
import hashlib
import json
import sys

from mcap.records import Channel, Footer, Message
from mcap.stream_reader import StreamReader


def main() -> int:
    topics, messages, footer = {}, [], None
    with open(sys.argv[1], "rb") as f:
        for record in StreamReader(f, skip_magic=False, emit_chunks=False, validate_crcs=True).records:
            if isinstance(record, Channel):
                topics[record.id] = record.topic
            elif isinstance(record, Message):
                messages.append([topics[record.channel_id], record.log_time, hashlib.md5(record.data).hexdigest()])
            elif isinstance(record, Footer):
                footer = record
    if footer is None:
        print("no footer", file=sys.stderr)
        return 1
    print(json.dumps({"messages": messages, "summary": footer.summary_start != 0}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
