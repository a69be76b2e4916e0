#!/usr/bin/env python3
"""The peer of benches/recording.rs: decode AxisState messages of an MCAP with mcap-ros2-support and
compute, per sample, the distance to the singularity (|A| on the Hermle: the angle between the tool
axis and z) and the predicted C speed (seed 001 eq. 5) from consecutive tool axes. Usage:
peer_analyze.py FILE N  -> prints `messages=... seconds=...`."""
import math
import sys
import time

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory


def main():
    path, limit = sys.argv[1], int(sys.argv[2])
    start = time.perf_counter()
    count = 0
    prev = None
    peak = 0.0
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        for _schema, _channel, _message, st in reader.iter_decoded_messages():
            o = (st.tool_axis.x, st.tool_axis.y, st.tool_axis.z)
            n = (-o[1], o[0], 0.0)  # z x o
            n2 = n[0] * n[0] + n[1] * n[1]
            distance = math.atan2(math.sqrt(n2), abs(o[2]))
            t = st.header.stamp.sec + st.header.stamp.nanosec * 1e-9
            if prev is not None and n2 > 1e-24 and t > prev[1]:
                dt = t - prev[1]
                rate = ((o[0] - prev[0][0]) * n[0] + (o[1] - prev[0][1]) * n[1]) / dt / n2
                peak = max(peak, abs(rate))
            prev = (o, t)
            count += 1
            if count >= limit:
                break
    secs = time.perf_counter() - start
    print(f"messages={count} seconds={secs:.3f} peak_rad_s={peak:.3f} last_distance={distance:.6f}")


if __name__ == "__main__":
    main()
