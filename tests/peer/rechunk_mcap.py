#!/usr/bin/env python3
"""Rewrite an MCAP with another chunk compression, using the `mcap` Python package (Foxglove's, the
library rosbag2's Python tools and mcap-ros2-support build on): every schema, channel and message
copied as bytes with its log and publish times. Prints the compressions of the written file's chunks
(read back from its summary) and the message count.

Usage: rechunk_mcap.py IN.mcap OUT.mcap {lz4,zstd,none} [CHUNK_BYTES]
"""
import sys

from mcap.reader import make_reader
from mcap.writer import CompressionType, Writer


def main() -> int:
    src, dst, kind = sys.argv[1], sys.argv[2], sys.argv[3]
    chunk = int(sys.argv[4]) if len(sys.argv) > 4 else 1 << 20
    compression = {"lz4": CompressionType.LZ4, "zstd": CompressionType.ZSTD, "none": CompressionType.NONE}[kind]
    schemas, channels, n = {}, {}, 0
    with open(src, "rb") as f, open(dst, "wb") as g:
        w = Writer(g, chunk_size=chunk, compression=compression)
        w.start(profile="ros2", library="rechunk_mcap.py")
        for schema, channel, message in make_reader(f).iter_messages(log_time_order=False):
            if schema is not None and schema.id not in schemas:
                schemas[schema.id] = w.register_schema(schema.name, schema.encoding, schema.data)
            if channel.id not in channels:
                channels[channel.id] = w.register_channel(
                    channel.topic, channel.message_encoding, schemas.get(channel.schema_id, 0), channel.metadata
                )
            w.add_message(channels[channel.id], message.log_time, message.data, message.publish_time, message.sequence)
            n += 1
        w.finish()
    with open(dst, "rb") as g:
        summary = make_reader(g).get_summary()
        kinds = sorted({c.compression for c in summary.chunk_indexes})
    print(" ".join(kinds) or "-", len(summary.chunk_indexes), n)
    return 0


if __name__ == "__main__":
    sys.exit(main())
