#!/usr/bin/env python3
"""Independent check of a fiveaxis MCAP recording with Foxglove's mcap-ros2-support (PyPI), which
decodes messages from the ros2msg schemas stored in the file, not from our Rust types. The file is
read through its summary (the seeking reader follows the chunk indexes), with CRCs checked, and the
summary's statistics must agree with the messages read.

Usage: check_mcap.py RECORDING EXPECTED.json
EXPECTED holds, per topic, the message count and, for some messages (by index), field values that
must decode identically. Prints a summary; exits 1 on any mismatch.
"""
import json
import sys

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory


def main():
    path, expected_path = sys.argv[1], sys.argv[2]
    expected = json.load(open(expected_path))
    counts = {}
    seen = {}
    problems = []
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True, decoder_factories=[DecoderFactory()])
        header = reader.get_header()
        if header.profile != "ros2":
            problems.append(f"profile {header.profile!r}, expected 'ros2'")
        for schema, channel, message, decoded in reader.iter_decoded_messages():
            if schema.encoding != "ros2msg" or channel.message_encoding != "cdr":
                problems.append(f"{channel.topic}: encodings {schema.encoding}/{channel.message_encoding}")
            if "offered_qos_profiles" not in channel.metadata:
                problems.append(f"{channel.topic}: no offered_qos_profiles")
            i = counts.get(channel.topic, 0)
            counts[channel.topic] = i + 1
            want = expected.get(channel.topic, {}).get("samples", {}).get(str(i))
            if want is not None:
                for field, value in want.items():
                    got = getattr(decoded, field)
                    if hasattr(got, "__dict__") and isinstance(value, dict):
                        got = {k: getattr(got, k) for k in value}
                    if isinstance(got, (list, tuple)):
                        got = list(got)
                    if got != value:
                        problems.append(f"{channel.topic}[{i}].{field}: {got!r} != {value!r}")
                seen[channel.topic] = seen.get(channel.topic, 0) + 1
        summary = reader.get_summary()
    if summary is None or summary.statistics is None:
        problems.append("no summary with statistics")
    else:
        stats = summary.statistics
        if stats.message_count != sum(counts.values()):
            problems.append(f"statistics: {stats.message_count} messages, read {sum(counts.values())}")
        if stats.chunk_count != len(summary.chunk_indexes) or not summary.chunk_indexes:
            problems.append(f"statistics: {stats.chunk_count} chunks, {len(summary.chunk_indexes)} chunk indexes")
        by_topic = {summary.channels[c].topic: n for c, n in stats.channel_message_counts.items()}
        if by_topic != counts:
            problems.append(f"statistics per topic {by_topic} != read {counts}")
    for topic, e in expected.items():
        if counts.get(topic, 0) != e["count"]:
            problems.append(f"{topic}: {counts.get(topic, 0)} messages, expected {e['count']}")
        if seen.get(topic, 0) != len(e.get("samples", {})):
            problems.append(f"{topic}: compared {seen.get(topic, 0)} of {len(e.get('samples', {}))} samples")
    print(json.dumps({"counts": counts, "compared": seen, "problems": problems[:20]}))
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
