#!/usr/bin/env python3
# requirements: cyclonedds==11.0.1
#   (Eclipse Cyclone DDS Python binding with its bundled C library. rmw_cyclonedds of ROS 2 Jazzy
#   uses Cyclone DDS 0.10.x, but cyclonedds 0.10.x on PyPI has no CPython 3.11 wheels; 11.0.1 does.
#   The wire format relevant here -- RTPS 2.x, XCDR1 "CDR_LE" payloads of final structs, SEDP
#   topic/type names -- is the same in both.)
#   rosbags (optional, only for the `selftest` subcommand's independent CDR encoder).
"""An independent DDS peer for fiveaxis' end-to-end tests, built on Eclipse Cyclone DDS (not on
RustDDS), that behaves like a machine's ROS 2 bridge running on rmw_cyclonedds.

It puts `sensor_msgs/msg/JointState` on the wire as rmw_cyclonedds does: DDS topic `rt/<topic>`,
type `sensor_msgs::msg::dds_::JointState_`, final struct, XCDR1 (encapsulation CDR_LE 0x0001,
options 0), writer QoS as rmw_cyclonedds maps ROS QoS (reliability RELIABLE with infinite max
blocking time or BEST_EFFORT, KEEP_LAST depth, VOLATILE, autodispose off, data representation
[XCDR1], user data `typehash=RIHS01_...;`, participant user data `enclave=/;`); and it listens to
the monitor's `/diagnostics` and `/fiveaxis/monitor/status` (reliable), writing JSON lines.

Subcommands (every one that opens DDS must run inside `launch-free-scripts/netns-run`):

  publish TRACE.csv[.gz] [options]   publish a joint trace (t_s,x_mm,y_mm,z_mm,a_deg,c_deg,...) as
                                     JointState, paced on absolute monotonic deadlines; prints one
                                     JSON line at the end (samples, stamps, rate, lateness, and the
                                     time.monotonic() of the first/last send)
  listen [options]                   subscribe to the monitor's outputs; JSON lines to --out, one
                                     summary JSON line to stdout at the end
  run TRACE.csv[.gz] [options]       publish and listen in one process (two threads, one participant),
                                     so every timestamp is on one clock; prints the publish JSON line
                                     and then the listen summary JSON line (with stale latency)
  sniff [--duration S] [--ready F]   raw RTPS capture on `lo` (AF_PACKET; needs CAP_NET_RAW, which
                                     netns-run gives): reports, for every endpoint discovered through
                                     SEDP, topic/type name, reliability, announced data
                                     representation and the encapsulation ids of the samples its
                                     writers actually sent. Independent of any DDS library. Start it
                                     first and wait for --ready F to exist (SEDP is sent only once);
                                     stop it with SIGINT/SIGTERM or --duration.
  selftest                           offline: round trip of our IDL types against an independent
                                     CDR encoder (rosbags), no DDS

Examples (from the repository root):
  launch-free-scripts/netns-run bash -c '
    target/debug/fiveaxis-monitor --joint-state-input /cnc/joint_states --axis-map X=x_joint ... &
    python3 tests/peer/cyclone_bridge.py run trace.csv.gz --wait-subscribers 1 --out /tmp/l.jsonl
    wait'

Publish options: --topic /cnc/joint_states --names x_joint,y_joint,z_joint,a_joint,c_joint
  --frame-id ID --domain-id N (default $ROS_DOMAIN_ID or 0) --rate-hz 1000 --speed 1.0
  --start S --end S (trace time window, s) --limit N (samples sent) --reliability reliable|best-effort
  --stamp grid|send --epoch S (grid: stamp = epoch + t_s; default epoch = wall time at start - start)
  --jitter-ms J --seed N (send: uniform 0..J ms extra send delay per sample) --modulo-c
  --units si|mm-deg --drop-joint NAME --gap-at S --gap-ms MS (no sends for MS ms of wall time from
  the first sample at or after trace time S) --wait-subscribers N --wait-s S --ack-timeout-s S
  --send-log FILE (CSV: seq,mono,stamp_sec,stamp_nanosec,trace_t,late_ms)
Listen options: --status-topic /fiveaxis/monitor/status --diagnostics-topic /diagnostics --out FILE
  --duration S --idle-exit S --last-send-mono T (listen only) --linger S --stop-on-stale (run only)
"""
import argparse
import bisect
import csv
import dataclasses
import gzip
import io
import json
import math
import os
import random
import signal
import socket
import struct
import sys
import threading
import time
from dataclasses import dataclass, field
from typing import Optional

# --------------------------------------------------------------------------------------------
# IDL types, as rosidl generates them for rmw_cyclonedds (module::msg::dds_::Name_; final structs)
# --------------------------------------------------------------------------------------------

try:
    from cyclonedds.idl import IdlStruct
    from cyclonedds.idl.types import byte, float64, int32, int64, sequence, uint8, uint32, uint64
except ImportError:  # pragma: no cover
    sys.stderr.write("cyclone_bridge.py: needs `pip install cyclonedds==11.0.1`\n")
    raise

# RIHS01 type hashes (ROS 2 Iron and later put them in the endpoints' USER_DATA as
# "typehash=RIHS01_<hex>;"). Checked by `selftest` against rosbags' hash_rihs01.
TYPEHASH = {
    "sensor_msgs/msg/JointState": "RIHS01_a13ee3a330e346c9d87b5aa18d24e11690752bd33a0350f11c5882bc9179260e",
}


@dataclass
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: int32 = 0
    nanosec: uint32 = 0


@dataclass
class Header(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    stamp: Time = field(default_factory=Time)
    frame_id: str = ""


@dataclass
class JointState(IdlStruct, typename="sensor_msgs::msg::dds_::JointState_"):
    header: Header = field(default_factory=Header)
    name: sequence[str] = field(default_factory=list)
    position: sequence[float64] = field(default_factory=list)
    velocity: sequence[float64] = field(default_factory=list)
    effort: sequence[float64] = field(default_factory=list)


@dataclass
class KeyValue(IdlStruct, typename="diagnostic_msgs::msg::dds_::KeyValue_"):
    key: str = ""
    value: str = ""


@dataclass
class DiagnosticStatus(IdlStruct, typename="diagnostic_msgs::msg::dds_::DiagnosticStatus_"):
    level: byte = 0  # `byte` in the .msg, `octet` in IDL: OK=0 WARN=1 ERROR=2 STALE=3
    name: str = ""
    message: str = ""
    hardware_id: str = ""
    values: sequence[KeyValue] = field(default_factory=list)


@dataclass
class DiagnosticArray(IdlStruct, typename="diagnostic_msgs::msg::dds_::DiagnosticArray_"):
    header: Header = field(default_factory=Header)
    status: sequence[DiagnosticStatus] = field(default_factory=list)


@dataclass
class Point(IdlStruct, typename="geometry_msgs::msg::dds_::Point_"):
    x: float64 = 0.0
    y: float64 = 0.0
    z: float64 = 0.0


@dataclass
class SingularityStatus(IdlStruct, typename="fiveaxis_msgs::msg::dds_::SingularityStatus_"):
    header: Header = field(default_factory=Header)
    source: uint8 = 0
    input_topic: str = ""
    motion: uint8 = 0
    singularity_distance: float64 = 0.0
    secondary_axis: str = ""
    predicted_c_speed: float64 = 0.0
    c_speed: float64 = 0.0
    c_speed_limit: float64 = 0.0
    programmed_feed: float64 = 0.0
    path_feed: float64 = 0.0
    feed_limit: float64 = 0.0
    limiting_axis: str = ""
    limit_kind: uint8 = 0
    in_region: bool = False
    region_id: uint32 = 0
    region_cause: uint8 = 0
    workpiece_position: Point = field(default_factory=Point)
    time_to_next_region: float64 = 0.0
    program_line: uint32 = 0
    block_number: int64 = 0
    stale: bool = False
    invalid_count: uint64 = 0
    missing_joint_count: uint64 = 0
    non_finite_count: uint64 = 0
    out_of_range_count: uint64 = 0
    out_of_order_count: uint64 = 0
    stale_count: uint64 = 0
    lost_count: uint64 = 0


# The same layout as a ROS .msg, for the independent encoder in `selftest` (field order = above).
SINGULARITY_STATUS_MSG = """
std_msgs/Header header
uint8 source
string input_topic
uint8 motion
float64 singularity_distance
string secondary_axis
float64 predicted_c_speed
float64 c_speed
float64 c_speed_limit
float64 programmed_feed
float64 path_feed
float64 feed_limit
string limiting_axis
uint8 limit_kind
bool in_region
uint32 region_id
uint8 region_cause
geometry_msgs/Point workpiece_position
float64 time_to_next_region
uint32 program_line
int64 block_number
bool stale
uint64 invalid_count
uint64 missing_joint_count
uint64 non_finite_count
uint64 out_of_range_count
uint64 out_of_order_count
uint64 stale_count
uint64 lost_count
"""


def dds_topic(ros_topic: str) -> str:
    """ROS topic name -> DDS topic name as rmw does it (topics get the `rt` prefix)."""
    if not ros_topic.startswith("/"):
        raise SystemExit(f"topic must be absolute: {ros_topic}")
    return "rt" + ros_topic


def serialize_xcdr1(sample) -> bytes:
    """Serialize as the writer does with data representation [XCDR1]."""
    return sample.serialize(use_version_2=False)


class DecodeError(Exception):
    pass


def decode_strict(cls, data: bytes):
    """Decode a serialized sample and check it is exactly one `cls` (whatever follows the last
    field must be at most 3 bytes of zero padding): a layout mismatch is an error, not garbage."""
    from cyclonedds.idl._support import Buffer
    if len(data) < 4:
        raise DecodeError(f"{len(data)} bytes: no encapsulation header")
    enc = (data[0] << 8) | data[1]
    buf = Buffer(data, align_offset=4)
    try:
        sample = cls.deserialize(buf)
    except Exception as e:  # the Python deserializer raises on a short or malformed payload
        raise DecodeError(f"encapsulation 0x{enc:04x}, {len(data)} bytes: {type(e).__name__}: {e}") from None
    rest = len(data) - buf.tell()
    if rest < 0 or rest > 3 or any(data[buf.tell():]):
        raise DecodeError(f"encapsulation 0x{enc:04x}, {len(data)} bytes: decoded {buf.tell()} bytes, "
                          f"{rest} left over (layout mismatch)")
    return sample, enc


def to_jsonable(sample):
    d = dataclasses.asdict(sample)
    return d


def stamp_float(h) -> float:
    return h.stamp.sec + h.stamp.nanosec * 1e-9


# --------------------------------------------------------------------------------------------
# DDS entities
# --------------------------------------------------------------------------------------------

def default_domain_id() -> int:
    v = os.environ.get("ROS_DOMAIN_ID", "").strip()
    return int(v) if v else 0


def make_participant(domain_id: int):
    from cyclonedds.core import Policy, Qos
    from cyclonedds.domain import DomainParticipant
    # rmw_cyclonedds puts the security enclave in the participant's USER_DATA.
    return DomainParticipant(domain_id, qos=Qos(Policy.Userdata(data=b"enclave=/;")))


def rmw_qos(reliability: str, depth: int, typehash: Optional[str] = None, transient_local: bool = False):
    """Reader/writer QoS as rmw_cyclonedds' create_readwrite_qos maps a ROS QoS profile
    (volatile unless transient_local, automatic liveliness, infinite lease) plus the sertype's
    XCDR1-only representation."""
    from cyclonedds.core import Policy, Qos
    from cyclonedds.util import duration
    policies = [
        Policy.WriterDataLifecycle(autodispose=False),
        Policy.History.KeepLast(depth),
        (Policy.Reliability.Reliable(max_blocking_time=duration(infinite=True)) if reliability == "reliable"
         else Policy.Reliability.BestEffort),
        Policy.Durability.TransientLocal if transient_local else Policy.Durability.Volatile,
        Policy.Liveliness.Automatic(lease_duration=duration(infinite=True)),
        Policy.DataRepresentation(use_cdrv0_representation=True, use_xcdrv2_representation=False),
    ]
    if typehash:
        policies.append(Policy.Userdata(data=f"typehash={typehash};".encode()))
    return Qos(*policies)


# --------------------------------------------------------------------------------------------
# publish
# --------------------------------------------------------------------------------------------

def open_text(path):
    f = open(path, "rb")
    magic = f.read(2)
    f.seek(0)
    if magic == b"\x1f\x8b":
        return io.TextIOWrapper(gzip.GzipFile(fileobj=f), newline="")
    return io.TextIOWrapper(f, newline="")


def load_trace(path, start=None, end=None):
    """Joint trace -> (t, x_mm, y_mm, z_mm, a_deg, c_deg) lists within [start, end]."""
    cols = ("t_s", "x_mm", "y_mm", "z_mm", "a_deg", "c_deg")
    out = [[] for _ in cols]
    with open_text(path) as f:
        r = csv.reader(f)
        head = next(r)
        try:
            idx = [head.index(c) for c in cols]
        except ValueError:
            raise SystemExit(f"{path}: header {head} lacks one of {cols}")
        for row in r:
            if not row:
                continue
            t = float(row[idx[0]])
            if start is not None and t < start - 1e-9:
                continue
            if end is not None and t > end + 1e-9:
                break
            for k, i in enumerate(idx):
                out[k].append(float(row[i]))
    if not out[0]:
        raise SystemExit(f"{path}: no samples in the window")
    return out


def wrap_2pi(v: float, period: float) -> float:
    w = math.fmod(v, period)
    if w < 0:
        w += period
    if w >= period:
        w -= period
    return w


class Publisher:
    def __init__(self, args, participant):
        self.args = args
        from cyclonedds.pub import DataWriter
        from cyclonedds.topic import Topic
        names = [n.strip() for n in args.names.split(",")]
        if len(names) != 5:
            raise SystemExit("--names needs 5 joint names (X,Y,Z,A,C order)")
        self.all_names = names
        if args.drop_joint and args.drop_joint not in names:
            raise SystemExit(f"--drop-joint {args.drop_joint}: not one of {names}")
        self.keep = [i for i, n in enumerate(names) if n != args.drop_joint]
        self.names = [names[i] for i in self.keep]
        depth = 1000 if args.reliability == "reliable" else 5
        self.topic = Topic(participant, dds_topic(args.topic), JointState)
        self.writer = DataWriter(participant, self.topic,
                                 qos=rmw_qos(args.reliability, depth, TYPEHASH["sensor_msgs/msg/JointState"]))
        self.result = None
        self.last_send_mono = None
        self.send_monos = []  # time.monotonic() after each write, for the listener's latencies
        self.done = threading.Event()

    def positions(self, x, y, z, a, c):
        if self.args.units == "si":
            p = [x * 1e-3, y * 1e-3, z * 1e-3, math.radians(a), math.radians(c)]
            period = 2 * math.pi
        else:
            p = [x, y, z, a, c]
            period = 360.0
        if self.args.modulo_c:
            p[4] = wrap_2pi(p[4], period)
        return [p[i] for i in self.keep]

    def wait_subscribers(self, stop):
        a = self.args
        if a.wait_subscribers <= 0:
            return 0
        deadline = time.monotonic() + a.wait_s
        while not stop.is_set():
            n = self.writer.get_publication_matched_status().current_count
            if n >= a.wait_subscribers:
                return n
            if time.monotonic() > deadline:
                raise TimeoutError(f"{n} matched readers after {a.wait_s} s, wanted {a.wait_subscribers}")
            time.sleep(0.01)
        return 0

    def run(self, stop: threading.Event):
        try:
            return self._run(stop)
        finally:
            self.done.set()

    def _run(self, stop):
        a = self.args
        t, xs, ys, zs, as_, cs = load_trace(a.trace, a.start, a.end)
        t0, t1 = t[0], t[-1]
        rate = a.rate_hz
        step = a.speed / rate
        # Ticks: trace time t0 + k*step; the sample is the latest trace row at or before it.
        ticks = []
        k = 0
        while True:
            tt = t0 + k * step
            if tt > t1 + 1e-9:
                break
            i = bisect.bisect_right(t, tt + 1e-9) - 1
            ticks.append((k, i))
            k += 1
        # Gap: no sends for gap_ms of wall time from the first tick at trace time >= gap_at.
        gap = None
        if a.gap_at is not None and a.gap_ms > 0:
            kg = next((k for k, i in ticks if t0 + k * step >= a.gap_at - 1e-9), None)
            if kg is not None:
                gap = (kg, kg + int(round(a.gap_ms * 1e-3 * rate)))
        pos = [self.positions(xs[i], ys[i], zs[i], as_[i], cs[i]) for _, i in ticks]
        rng = random.Random(a.seed)
        # Per axis (an MTConnect-fed bridge): each joint sampled on its own clock (period +-10 %, its
        # own phase), sent only when it changed (4 decimals of mm/deg), in a JointState that carries
        # the joints sent at that instant only. Schedule: (trace time, names, positions).
        schedule = None
        if a.per_axis_period:
            events = []
            for j in self.keep:
                tt = t0 + rng.uniform(0.0, a.per_axis_period)
                last_v = None
                while tt <= t1:
                    i = bisect.bisect_right(t, tt + 1e-9) - 1
                    raw = [xs[i], ys[i], zs[i], as_[i], cs[i]][j]
                    if last_v is None or round(raw, 4) != last_v:
                        last_v = round(raw, 4)
                        full = self.positions(*[round(v, 4) for v in (xs[i], ys[i], zs[i], as_[i], cs[i])])
                        events.append((round(tt, 3), self.all_names[j], full[self.keep.index(j)]))
                    tt += a.per_axis_period * rng.uniform(0.9, 1.1)
            events.sort()
            schedule = []
            for tt, name, v in events:
                if schedule and schedule[-1][0] == tt:
                    schedule[-1][1].append(name)
                    schedule[-1][2].append(v)
                else:
                    schedule.append((tt, [name], [v]))
            # The loop below runs over (k, i) ticks: here one per message, at its own trace time.
            ticks = [(k, bisect.bisect_right(t, tt + 1e-9) - 1) for k, (tt, _, _) in enumerate(schedule)]
            pos = [p for _, _, p in schedule]

        matched = self.wait_subscribers(stop)
        # Grid stamps in integer ns (a float epoch + t_s would lose ~0.1 us to rounding).
        if a.epoch is not None:
            epoch_ns = int(round(a.epoch * 1e9))
        else:
            epoch_ns = time.time_ns() - int(round(t0 * 1e9))
        t_ns = [int(round(v * 1e9)) for v in t]
        msg = JointState(header=Header(frame_id=a.frame_id), name=list(self.names))
        write = self.writer.write
        period = 1.0 / rate
        jitter = a.jitter_ms * 1e-3
        n_sent = 0
        skipped_gap = 0
        gap_stamps = [None, None]  # stamps (s) of the last sample before the gap and the first after it
        late = []
        send_log = [] if a.send_log else None
        first = last = None  # (mono, wall, stamp)
        sleep = time.sleep
        mono = time.monotonic
        start_mono = mono() + 0.02
        for (k, i), p in zip(ticks, pos):
            if stop.is_set() or (a.limit is not None and n_sent >= a.limit):
                break
            if gap and gap[0] <= k < gap[1]:
                skipped_gap += 1
                continue
            deadline = start_mono + (k * period if schedule is None else (schedule[k][0] - t0) / a.speed)
            if jitter > 0:
                deadline += rng.uniform(0.0, jitter)
            rem = deadline - mono()
            if rem > 0:
                sleep(rem)
            if a.stamp == "grid" and schedule is not None:
                sec, nsec = divmod(epoch_ns + int(round(schedule[k][0] * 1e9)), 1_000_000_000)
            elif a.stamp == "grid":
                sec, nsec = divmod(epoch_ns + t_ns[i], 1_000_000_000)
            else:
                ns = time.time_ns()
                sec, nsec = divmod(ns, 1_000_000_000)
            msg.header.stamp.sec = int(sec)
            msg.header.stamp.nanosec = int(nsec)
            if schedule is not None:
                msg.name = schedule[k][1]
            msg.position = p
            write(msg)
            now = mono()
            late.append(now - deadline)
            if send_log is not None:
                send_log.append((n_sent, now, int(sec), int(nsec), t[i], (now - deadline) * 1e3))
            if first is None:
                first = (now, sec + nsec * 1e-9, [int(sec), int(nsec)])
            last = (now, sec + nsec * 1e-9, [int(sec), int(nsec)])
            if gap and k < gap[0]:
                gap_stamps[0] = last[1]
            elif gap and k >= gap[1] and gap_stamps[1] is None:
                gap_stamps[1] = last[1]
            self.last_send_mono = now
            self.send_monos.append(now)
            n_sent += 1
        acked = None
        if a.reliability == "reliable" and n_sent:
            from cyclonedds.util import duration
            acked = self.writer.wait_for_acks(duration(seconds=a.ack_timeout_s))
        if send_log is not None:
            with open(a.send_log, "w") as f:
                f.write("seq,mono,stamp_sec,stamp_nanosec,trace_t,late_ms\n")
                for r in send_log:
                    f.write("%d,%.6f,%d,%d,%.6f,%.4f\n" % r)
        res = {
            "kind": "publish",
            "topic": a.topic,
            "dds_topic": dds_topic(a.topic),
            "type": "sensor_msgs::msg::dds_::JointState_",
            "reliability": a.reliability,
            "names": self.names,
            "units": a.units,
            "stamp_mode": a.stamp,
            "samples_sent": n_sent,
            "skipped_gap": skipped_gap,
            # The stamps' own span over the gap: with send-time stamps it is the gap plus each side's lateness.
            "gap_stamp_span_s": (gap_stamps[1] - gap_stamps[0]) if None not in gap_stamps else None,
            "matched_readers_at_start": matched,
            "matched_readers_at_end": self.writer.get_publication_matched_status().current_count,
            "acked": acked,
            "trace_window_s": [t0, t1],
        }
        if n_sent:
            lat = sorted(late)
            dur = last[0] - first[0]
            res.update({
                "first_stamp": first[1],
                "last_stamp": last[1],
                "first_stamp_sec_nanosec": first[2],
                "last_stamp_sec_nanosec": last[2],
                "first_send_mono": first[0],
                "last_send_mono": last[0],
                "wall_duration_s": dur,
                "rate_hz_target": rate,
                # Sends per second of wall time, gap excluded (the samples it skipped are not counted).
                "rate_hz_achieved": ((n_sent - 1) / (dur - skipped_gap * period)) if n_sent > 1 and dur - skipped_gap * period > 0 else None,
                "late_ms": {
                    "p50": lat[len(lat) // 2] * 1e3,
                    "p99": lat[min(len(lat) - 1, int(len(lat) * 0.99))] * 1e3,
                    "max": lat[-1] * 1e3,
                    "over_1ms": sum(1 for v in lat if v > 1e-3),
                },
            })
        self.result = res
        return res


# --------------------------------------------------------------------------------------------
# listen
# --------------------------------------------------------------------------------------------

LEVEL_NAMES = {0: "OK", 1: "WARN", 2: "ERROR", 3: "STALE"}


class Listener:
    def __init__(self, args, participant):
        from cyclonedds.core import InstanceState, ReadCondition, SampleState, ViewState, WaitSet
        from cyclonedds.sub import DataReader
        from cyclonedds.topic import Topic
        self.args = args
        self.out = open(args.out, "w") if args.out and args.out != "-" else None
        self.readers = []
        self.ws = WaitSet(participant)
        mask = SampleState.Any | ViewState.Any | InstanceState.Any
        for ros_topic, cls, kind in ((args.status_topic, SingularityStatus, "status"),
                                     (args.diagnostics_topic, DiagnosticArray, "diagnostics")):
            if not ros_topic:
                continue
            topic = Topic(participant, dds_topic(ros_topic), cls)
            # Reader depth far above the writers' so that nothing is lost on our side.
            reader = DataReader(participant, topic, qos=rmw_qos("reliable", 100000))
            cond = ReadCondition(reader, mask)
            self.ws.attach(cond)
            self.readers.append((reader, cls, kind, ros_topic, mask))
        self.lock = threading.Lock()
        self.status_count = 0
        self.diag_count = 0
        self.decode_errors = {}
        self.first_decode_error = {}
        self.encapsulations = {}
        self.first_arrival = None
        self.last_arrival = None
        self.stale_transitions = []  # monotonic arrival of each stale false->true (or first stale)
        self.prev_stale = None
        self.stale_arrivals = []  # (mono, stamp) of stale statuses, bounded
        self.regions = {}  # region_id -> {"cause":..., "first_mono":..., "count":...}
        self.sources = {}
        self.input_topics = {}
        self.last_status = None
        self.diag_max = {}
        self.diag_levels = {}
        self.diag_last = {}
        self.out_of_order_stamps = 0
        self.last_stamp = None

    def emit(self, rec):
        line = json.dumps(rec, separators=(",", ":"))
        if self.out:
            self.out.write(line + "\n")
        else:
            sys.stdout.write(line + "\n")

    def poll(self, timeout_s: float):
        from cyclonedds._clayer import ddspy_take
        from cyclonedds.util import duration
        self.ws.wait(duration(seconds=timeout_s))
        got = 0
        for reader, cls, kind, ros_topic, mask in self.readers:
            while True:
                ret = ddspy_take(reader._ref, mask, 256)
                if isinstance(ret, int):
                    raise RuntimeError(f"take on {ros_topic}: error {ret}")
                if not ret:
                    break
                now = time.monotonic()
                for data, info in ret:
                    if not info.valid_data:
                        continue
                    got += 1
                    self.handle(kind, ros_topic, cls, data, info, now)
                if len(ret) < 256:
                    break
        return got

    def handle(self, kind, ros_topic, cls, data, info, now):
        with self.lock:
            if self.first_arrival is None:
                self.first_arrival = now
            self.last_arrival = now
            try:
                msg, enc = decode_strict(cls, data)
            except DecodeError as e:
                self.decode_errors[kind] = self.decode_errors.get(kind, 0) + 1
                self.first_decode_error.setdefault(kind, {"error": str(e), "bytes": len(data),
                                                          "head_hex": bytes(data[:64]).hex()})
                self.emit({"topic": ros_topic, "mono": now, "decode_error": str(e), "bytes": len(data)})
                return
            self.encapsulations[kind] = self.encapsulations.get(kind, {})
            ek = f"0x{enc:04x}"
            self.encapsulations[kind][ek] = self.encapsulations[kind].get(ek, 0) + 1
            rec = {"topic": ros_topic, "mono": now, "source_timestamp_ns": info.source_timestamp,
                   "stamp": stamp_float(msg.header), "msg": to_jsonable(msg)}
            self.emit(rec)
            if kind == "status":
                self.status_count += 1
                st = stamp_float(msg.header)
                if self.last_stamp is not None and st < self.last_stamp:
                    self.out_of_order_stamps += 1
                self.last_stamp = st
                if msg.stale and not self.prev_stale:
                    self.stale_transitions.append(now)
                if msg.stale and len(self.stale_arrivals) < 10000:
                    self.stale_arrivals.append(now)
                self.prev_stale = msg.stale
                if msg.in_region:
                    r = self.regions.setdefault(msg.region_id, {"cause": msg.region_cause, "first_mono": now,
                                                                "first_stamp": st, "count": 0})
                    r["count"] += 1
                    r["last_stamp"] = st
                self.sources[msg.source] = self.sources.get(msg.source, 0) + 1
                self.input_topics[msg.input_topic] = self.input_topics.get(msg.input_topic, 0) + 1
                self.last_status = msg
            else:
                self.diag_count += 1
                for s in msg.status:
                    lv = int(s.level)
                    self.diag_max[s.name] = max(self.diag_max.get(s.name, lv), lv)
                    hist = self.diag_levels.setdefault(s.name, {})
                    hist[LEVEL_NAMES.get(lv, str(lv))] = hist.get(LEVEL_NAMES.get(lv, str(lv)), 0) + 1
                    self.diag_last[s.name] = {"level": lv, "message": s.message, "hardware_id": s.hardware_id,
                                              "values": {kv.key: kv.value for kv in s.values}}

    def summary(self, last_send_mono=None, send_monos=None):
        with self.lock:
            s = {
                "kind": "listen",
                "status_topic": self.args.status_topic,
                "diagnostics_topic": self.args.diagnostics_topic,
                "status_count": self.status_count,
                "diagnostics_count": self.diag_count,
                "decode_errors": self.decode_errors,
                "first_decode_error": self.first_decode_error,
                "encapsulations": self.encapsulations,
                "first_arrival_mono": self.first_arrival,
                "last_arrival_mono": self.last_arrival,
                "status_stamps_out_of_order": self.out_of_order_stamps,
                "stale_transitions_mono": self.stale_transitions[:100],
                "regions": {str(k): v for k, v in sorted(self.regions.items())},
                "region_ids": sorted(self.regions),
                "sources": {str(k): v for k, v in self.sources.items()},
                "input_topics": self.input_topics,
                "diagnostics_max_level": self.diag_max,
                "diagnostics_levels": self.diag_levels,
                "diagnostics_last": self.diag_last,
                "matched_writers": {kind: r.get_subscription_matched_status().current_count
                                    for r, _, kind, _, _ in self.readers},
            }
            if self.last_status is not None:
                ls = self.last_status
                s["last_status"] = {k: getattr(ls, k) for k in (
                    "stale", "invalid_count", "missing_joint_count", "non_finite_count", "out_of_range_count",
                    "out_of_order_count", "stale_count", "lost_count", "in_region", "region_id")}
                s["last_status"]["stamp"] = stamp_float(ls.header)
            if last_send_mono is not None:
                s["last_send_mono"] = last_send_mono
                after = [m for m in self.stale_arrivals if m > last_send_mono]
                s["first_stale_after_last_send_mono"] = after[0] if after else None
                s["stale_latency_s"] = (after[0] - last_send_mono) if after else None
            if send_monos:
                # every stale transition, with the time since the last send before it (run only)
                ev = []
                for m in self.stale_transitions[:100]:
                    j = bisect.bisect_left(send_monos, m) - 1
                    ev.append({"mono": m, "since_last_send_s": (m - send_monos[j]) if j >= 0 else None})
                s["stale_events"] = ev
            return s

    def close(self):
        if self.out:
            self.out.close()


def listen_loop(listener, stop, args, publisher=None):
    """Poll until stop, --duration, --idle-exit, or (run) publisher done + --linger / stale."""
    t_start = time.monotonic()
    while not stop.is_set():
        listener.poll(0.05)
        now = time.monotonic()
        if args.duration and now - t_start > args.duration:
            break
        if args.idle_exit and listener.last_arrival is not None and now - listener.last_arrival > args.idle_exit:
            break
        if publisher is not None and publisher.done.is_set():
            lm = publisher.last_send_mono
            if getattr(args, "stop_on_stale", False) and lm is not None and any(m > lm for m in listener.stale_arrivals[-5:]):
                # let a few more statuses arrive (the same publication burst), then stop
                end = time.monotonic() + 0.2
                while time.monotonic() < end:
                    listener.poll(0.05)
                break
            if publisher.done_at is None:
                publisher.done_at = now
            if now - publisher.done_at > args.linger:
                break
    # drain
    listener.poll(0.0)


# --------------------------------------------------------------------------------------------
# sniff: raw RTPS on lo
# --------------------------------------------------------------------------------------------

PID_TOPIC_NAME, PID_TYPE_NAME, PID_RELIABILITY, PID_ENDPOINT_GUID = 0x0005, 0x0007, 0x001A, 0x005A
PID_DATA_REPRESENTATION, PID_USER_DATA, PID_HISTORY, PID_DURABILITY = 0x0073, 0x002C, 0x0040, 0x001D
ENC_NAMES = {0x0000: "CDR_BE", 0x0001: "CDR_LE", 0x0002: "PL_CDR_BE", 0x0003: "PL_CDR_LE",
             0x0006: "CDR2_BE", 0x0007: "CDR2_LE", 0x0008: "D_CDR2_BE", 0x0009: "D_CDR2_LE",
             0x000A: "PL_CDR2_BE", 0x000B: "PL_CDR2_LE"}
REPR_NAMES = {0: "XCDR1", 1: "XML", 2: "XCDR2"}


def parse_plist(buf, le):
    e = "<" if le else ">"
    out = {}
    i = 0
    while i + 4 <= len(buf):
        pid, ln = struct.unpack_from(e + "HH", buf, i)
        i += 4
        if pid == 0x0001:
            break
        out.setdefault(pid, []).append(bytes(buf[i:i + ln]))
        i += ln
    return out


def cdr_string(b, le):
    n = struct.unpack_from("<I" if le else ">I", b, 0)[0]
    return b[4:4 + n].rstrip(b"\0").decode(errors="replace")


class Sniffer:
    SEDP_PUB, SEDP_SUB = 0x000003C2, 0x000004C2

    def __init__(self):
        self.endpoints = {}  # guid hex -> info
        self.samples = {}  # writer guid hex -> {enc: count}
        self.sizes = {}
        self.packets = 0

    def endpoint_from_sedp(self, payload, kind, prefix):
        if len(payload) < 4:
            return
        enc = struct.unpack_from(">H", payload, 0)[0]
        if enc not in (0x0002, 0x0003):
            return
        le = enc == 0x0003
        pl = parse_plist(payload[4:], le)
        if PID_TOPIC_NAME not in pl:
            return
        e = "<" if le else ">"
        guid = pl[PID_ENDPOINT_GUID][0].hex() if PID_ENDPOINT_GUID in pl else None
        info = {"kind": kind, "topic": cdr_string(pl[PID_TOPIC_NAME][0], le),
                "type": cdr_string(pl[PID_TYPE_NAME][0], le) if PID_TYPE_NAME in pl else None}
        if PID_RELIABILITY in pl:
            k = struct.unpack_from(e + "I", pl[PID_RELIABILITY][0], 0)[0]
            info["reliability"] = {1: "BEST_EFFORT", 2: "RELIABLE"}.get(k, k)
        else:  # RTPS defaults: writers RELIABLE, readers BEST_EFFORT
            info["reliability"] = "RELIABLE (default)" if kind == "writer" else "BEST_EFFORT (default)"
        if PID_DURABILITY in pl:
            k = struct.unpack_from(e + "I", pl[PID_DURABILITY][0], 0)[0]
            info["durability"] = {0: "VOLATILE", 1: "TRANSIENT_LOCAL", 2: "TRANSIENT", 3: "PERSISTENT"}.get(k, k)
        if PID_HISTORY in pl:
            k, d = struct.unpack_from(e + "Ii", pl[PID_HISTORY][0], 0)
            info["history"] = ["KEEP_LAST", d] if k == 0 else ["KEEP_ALL"]
        if PID_DATA_REPRESENTATION in pl:
            b = pl[PID_DATA_REPRESENTATION][0]
            n = struct.unpack_from(e + "I", b, 0)[0]
            info["data_representation"] = [REPR_NAMES.get(v, v) for v in struct.unpack_from(e + "%dh" % n, b, 4)]
        else:
            info["data_representation"] = "absent (= [XCDR1])"
        if PID_USER_DATA in pl:
            b = pl[PID_USER_DATA][0]
            n = struct.unpack_from(e + "I", b, 0)[0]
            info["user_data"] = b[4:4 + n].decode(errors="replace")
        if guid:
            self.endpoints[guid] = info

    def packet(self, pkt):
        # Ethernet (lo: 14 bytes, type 0x0800) / IPv4 / UDP / RTPS
        if len(pkt) < 14 + 20 + 8 + 20 or pkt[12:14] != b"\x08\x00":
            return
        ip = pkt[14:]
        ihl = (ip[0] & 0x0F) * 4
        if ip[9] != 17:
            return
        udp = ip[ihl:]
        rtps = udp[8:]
        if rtps[:4] != b"RTPS":
            return
        self.packets += 1
        prefix = rtps[8:20]
        i = 20
        while i + 4 <= len(rtps):
            sid, flags = rtps[i], rtps[i + 1]
            le = flags & 1
            ln = struct.unpack_from("<H" if le else ">H", rtps, i + 2)[0]
            body = rtps[i + 4: (i + 4 + ln) if ln else len(rtps)]
            i = i + 4 + ln if ln else len(rtps)
            if sid == 0x0C and len(body) >= 12:  # INFO_SRC
                prefix = body[8:20]
                continue
            if sid not in (0x15, 0x16) or len(body) < 20:
                continue
            e = "<" if le else ">"
            otiq = struct.unpack_from(e + "H", body, 2)[0]
            writer_id = struct.unpack_from(">I", body, 8)[0]
            if sid == 0x15:
                j = 4 + otiq
                if flags & 0x02:  # inline QoS
                    while j + 4 <= len(body):
                        pid, pl = struct.unpack_from(e + "HH", body, j)
                        j += 4 + pl
                        if pid == 0x0001:
                            break
                if not (flags & 0x04):  # no serialized data
                    continue
                payload = body[j:]
            else:
                frag_start = struct.unpack_from(e + "I", body, 20)[0] if len(body) >= 24 else 0
                j = 4 + otiq
                if flags & 0x02:
                    while j + 4 <= len(body):
                        pid, pl = struct.unpack_from(e + "HH", body, j)
                        j += 4 + pl
                        if pid == 0x0001:
                            break
                if frag_start != 1:
                    continue
                payload = body[j:]
            if writer_id == self.SEDP_PUB:
                self.endpoint_from_sedp(payload, "writer", prefix)
            elif writer_id == self.SEDP_SUB:
                self.endpoint_from_sedp(payload, "reader", prefix)
            elif (writer_id & 0xC0) == 0:  # user-defined entity
                guid = (prefix + struct.pack(">I", writer_id)).hex()
                enc = "0x%04x" % struct.unpack_from(">H", payload, 0)[0] if len(payload) >= 4 else "short"
                opt = "0x%04x" % struct.unpack_from(">H", payload, 2)[0] if len(payload) >= 4 else ""
                d = self.samples.setdefault(guid, {})
                d[enc + "/options " + opt] = d.get(enc + "/options " + opt, 0) + 1
                sz = self.sizes.setdefault(guid, [len(payload), len(payload)])
                sz[0] = min(sz[0], len(payload))
                sz[1] = max(sz[1], len(payload))

    def report(self):
        writers = []
        for guid, info in sorted(self.endpoints.items(), key=lambda kv: kv[1]["topic"]):
            r = dict(info, guid=guid)
            if info["kind"] == "writer":
                r["samples_seen"] = self.samples.get(guid, {})
                r["sample_bytes_min_max"] = self.sizes.get(guid)
                r["encapsulations"] = {ENC_NAMES.get(int(k.split("/")[0], 16), k): v
                                       for k, v in self.samples.get(guid, {}).items() if k.startswith("0x")}
            writers.append(r)
        unknown = {g: v for g, v in self.samples.items() if g not in self.endpoints}
        return {"kind": "sniff", "rtps_packets": self.packets, "endpoints": writers,
                "samples_from_undiscovered_writers": unknown}


def cmd_sniff(args):
    ETH_P_ALL = 0x0003
    s = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(ETH_P_ALL))
    for opt in (getattr(socket, "SO_RCVBUFFORCE", 33), socket.SO_RCVBUF):
        try:
            s.setsockopt(socket.SOL_SOCKET, opt, 32 << 20)
            break
        except OSError:
            continue
    s.bind(("lo", 0))
    s.settimeout(0.2)
    if args.ready:
        # Start the sniffer before any participant and wait for this file: SEDP is sent once.
        open(args.ready, "w").close()
    sn = Sniffer()
    stop = install_stop()
    t_end = time.monotonic() + args.duration if args.duration else None
    while not stop.is_set() and (t_end is None or time.monotonic() < t_end):
        try:
            pkt, addr = s.recvfrom(65536)
        except socket.timeout:
            continue
        if addr[2] == socket.PACKET_OUTGOING:
            continue
        try:
            sn.packet(pkt)
        except (struct.error, IndexError, KeyError, UnicodeDecodeError):
            pass
    rep = sn.report()
    try:  # SOL_PACKET, PACKET_STATISTICS: kernel drops (then the sample counts are lower bounds)
        rep["socket_drops"] = struct.unpack("II", s.getsockopt(263, 6, 8))[1]
    except OSError:
        pass
    text = json.dumps(rep, indent=None if not args.pretty else 1)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    else:
        print(text)


# --------------------------------------------------------------------------------------------
# selftest: our IDL vs an independent CDR encoder (rosbags)
# --------------------------------------------------------------------------------------------

def cmd_selftest(args):
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore
    ts = get_typestore(Stores.ROS2_JAZZY)
    ts.register(get_types_from_msg(SINGULARITY_STATUS_MSG, "fiveaxis_msgs/msg/SingularityStatus"))
    problems = []
    checked = {}

    def compare(name, ours, ros_msg, typename):
        theirs = bytes(ts.serialize_cdr(ros_msg, typename))
        mine = serialize_xcdr1(ours)
        # rosbags does not pad the end; the DDS writer pads to 4 bytes (as rmw_cyclonedds does).
        if mine != theirs:
            problems.append(f"{name}: ours {mine.hex()} != rosbags {theirs.hex()}")
        if mine[:4] != b"\x00\x01\x00\x00":
            problems.append(f"{name}: encapsulation {mine[:4].hex()}, expected 00010000 (CDR_LE)")
        back, enc = decode_strict(type(ours), theirs + b"\0" * ((4 - len(theirs) % 4) % 4))
        if back != ours:
            problems.append(f"{name}: decode(rosbags bytes) != original: {back} vs {ours}")
        again = ts.deserialize_cdr(mine, typename)
        checked[name] = len(mine)
        return again

    T = ts.types
    hdr = lambda s, n, f: T["std_msgs/msg/Header"](stamp=T["builtin_interfaces/msg/Time"](sec=s, nanosec=n), frame_id=f)
    import numpy as np
    js = JointState(header=Header(Time(1767225600, 123456789), "machine"),
                    name=["x_joint", "y_joint", "z_joint", "a_joint", "c_joint"],
                    position=[0.01, -0.02, 0.1, math.radians(-30.0), math.radians(359.9)])
    r = compare("JointState", js, T["sensor_msgs/msg/JointState"](
        header=hdr(1767225600, 123456789, "machine"), name=list(js.name),
        position=np.array(js.position), velocity=np.array([], dtype=np.float64),
        effort=np.array([], dtype=np.float64)), "sensor_msgs/msg/JointState")
    if list(r.position) != js.position:
        problems.append("JointState: rosbags decode of ours differs")
    da = DiagnosticArray(header=Header(Time(5, 6), ""), status=[
        DiagnosticStatus(level=2, name="fiveaxis_monitor: input", message="stale", hardware_id="hermle",
                         values=[KeyValue("samples", "12"), KeyValue("a", "")]),
        DiagnosticStatus(level=0, name="b", message="", hardware_id="", values=[])])
    KV, DS = T["diagnostic_msgs/msg/KeyValue"], T["diagnostic_msgs/msg/DiagnosticStatus"]
    compare("DiagnosticArray", da, T["diagnostic_msgs/msg/DiagnosticArray"](header=hdr(5, 6, ""), status=[
        DS(level=2, name="fiveaxis_monitor: input", message="stale", hardware_id="hermle",
           values=[KV(key="samples", value="12"), KV(key="a", value="")]),
        DS(level=0, name="b", message="", hardware_id="", values=[])]), "diagnostic_msgs/msg/DiagnosticArray")
    vals = dict(source=2, input_topic="/cnc/joint_states", motion=2, singularity_distance=0.0123,
                secondary_axis="C", predicted_c_speed=3.5, c_speed=-1.25, c_speed_limit=2.0,
                programmed_feed=0.05, path_feed=0.049, feed_limit=0.02, limiting_axis="C", limit_kind=1,
                in_region=True, region_id=7, region_cause=1, time_to_next_region=-1.0, program_line=4242,
                block_number=-1, stale=True, invalid_count=1, missing_joint_count=2, non_finite_count=3,
                out_of_range_count=4, out_of_order_count=5, stale_count=6, lost_count=2**64 - 1)
    ss = SingularityStatus(header=Header(Time(-1, 999999999), "workpiece"), workpiece_position=Point(0.1, -0.2, 0.3), **vals)
    r = compare("SingularityStatus", ss, T["fiveaxis_msgs/msg/SingularityStatus"](
        header=hdr(-1, 999999999, "workpiece"), workpiece_position=T["geometry_msgs/msg/Point"](x=0.1, y=-0.2, z=0.3),
        **vals), "fiveaxis_msgs/msg/SingularityStatus")
    # a status one field short must be refused, not decoded as garbage
    short = serialize_xcdr1(ss)[:-8]
    try:
        decode_strict(SingularityStatus, short)
        problems.append("SingularityStatus: truncated payload decoded")
    except DecodeError:
        pass
    long_ = serialize_xcdr1(ss) + b"\1\0\0\0\0\0\0\0"
    try:
        decode_strict(SingularityStatus, long_)
        problems.append("SingularityStatus: over-long payload decoded")
    except DecodeError:
        pass
    h = ts.hash_rihs01("sensor_msgs/msg/JointState")
    if h != TYPEHASH["sensor_msgs/msg/JointState"]:
        problems.append(f"JointState RIHS01 {h} != {TYPEHASH['sensor_msgs/msg/JointState']}")
    print(json.dumps({"kind": "selftest", "bytes": checked, "problems": problems}))
    return 1 if problems else 0


# --------------------------------------------------------------------------------------------
# CLI
# --------------------------------------------------------------------------------------------

def install_stop():
    stop = threading.Event()

    def on_sig(signum, frame):
        stop.set()
    signal.signal(signal.SIGINT, on_sig)
    signal.signal(signal.SIGTERM, on_sig)
    return stop


def add_publish_args(p):
    p.add_argument("trace", help="joint trace CSV(.gz): t_s,x_mm,y_mm,z_mm,a_deg,c_deg,...")
    p.add_argument("--topic", default="/cnc/joint_states")
    p.add_argument("--names", default="x_joint,y_joint,z_joint,a_joint,c_joint", help="joint names of X,Y,Z,A,C")
    p.add_argument("--frame-id", default="")
    p.add_argument("--rate-hz", type=float, default=1000.0)
    p.add_argument("--speed", type=float, default=1.0, help="real-time factor (trace s per wall s)")
    p.add_argument("--start", type=float, default=None, help="trace window start, s of t_s")
    p.add_argument("--end", type=float, default=None, help="trace window end, s of t_s")
    p.add_argument("--limit", type=int, default=None, help="at most N samples sent")
    p.add_argument("--reliability", choices=["reliable", "best-effort"], default="reliable")
    p.add_argument("--stamp", choices=["grid", "send"], default="grid")
    p.add_argument("--epoch", type=float, default=None, help="grid stamps: epoch + t_s (default: wall time at start - start)")
    p.add_argument("--jitter-ms", type=float, default=0.0)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--modulo-c", action="store_true", help="publish C wrapped into [0, 2 pi)")
    p.add_argument("--units", choices=["si", "mm-deg"], default="si")
    p.add_argument("--drop-joint", default=None)
    p.add_argument("--gap-at", type=float, default=None, help="trace time at which sends stop")
    p.add_argument("--gap-ms", type=float, default=0.0, help="wall time without sends")
    p.add_argument("--wait-subscribers", type=int, default=0)
    p.add_argument("--wait-s", type=float, default=10.0)
    p.add_argument("--ack-timeout-s", type=float, default=5.0)
    p.add_argument("--send-log", default=None)
    p.add_argument("--per-axis-period", type=float, default=None,
                   help="each joint on its own clock every S s of trace time (+-10 %%), sent when it changed, alone")


def add_listen_args(p):
    p.add_argument("--status-topic", default="/fiveaxis/monitor/status")
    p.add_argument("--diagnostics-topic", default="/diagnostics")
    p.add_argument("--out", default=None, help="JSON lines of received messages (default: stdout)")
    p.add_argument("--duration", type=float, default=None, help="stop after S s")
    p.add_argument("--idle-exit", type=float, default=None, help="stop S s after the last message")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--domain-id", type=int, default=default_domain_id())
    sub = ap.add_subparsers(dest="cmd", required=True)
    pp = sub.add_parser("publish")
    add_publish_args(pp)
    pl = sub.add_parser("listen")
    add_listen_args(pl)
    pl.add_argument("--last-send-mono", type=float, default=None)
    pr = sub.add_parser("run")
    add_publish_args(pr)
    add_listen_args(pr)
    pr.add_argument("--linger", type=float, default=5.0, help="listen S s after the last send")
    pr.add_argument("--stop-on-stale", action="store_true", help="stop listening at the first stale status after the last send")
    ps = sub.add_parser("sniff")
    ps.add_argument("--duration", type=float, default=None)
    ps.add_argument("--out", default=None)
    ps.add_argument("--pretty", action="store_true")
    ps.add_argument("--ready", default=None, help="create this file once capturing")
    sub.add_parser("selftest")
    # --domain-id also accepted after the subcommand
    for p in (pp, pl, pr):
        p.add_argument("--domain-id", type=int, default=argparse.SUPPRESS)
    args = ap.parse_args(argv)

    if args.cmd == "selftest":
        return cmd_selftest(args)
    if args.cmd == "sniff":
        return cmd_sniff(args)

    stop = install_stop()
    dp = make_participant(args.domain_id)
    if args.cmd == "publish":
        pub = Publisher(args, dp)
        try:
            res = pub.run(stop)
        except TimeoutError as e:
            print(json.dumps({"kind": "publish", "error": str(e)}))
            return 2
        print(json.dumps(res))
        return 0
    if args.cmd == "listen":
        lis = Listener(args, dp)
        try:
            listen_loop(lis, stop, args)
        finally:
            lis.close()
        print(json.dumps(lis.summary(args.last_send_mono)))
        return 0
    if args.cmd == "run":
        lis = Listener(args, dp)
        pub = Publisher(args, dp)
        pub.done_at = None
        box = {}

        def pub_thread():
            try:
                box["res"] = pub.run(stop)
            except TimeoutError as e:
                box["res"] = {"kind": "publish", "error": str(e)}
            except BaseException as e:  # report, do not hang the listener
                box["res"] = {"kind": "publish", "error": f"{type(e).__name__}: {e}"}
        th = threading.Thread(target=pub_thread, name="publisher", daemon=True)
        th.start()
        try:
            listen_loop(lis, stop, args, publisher=pub)
        finally:
            lis.close()
        stop.set()
        th.join()
        res = box.get("res", {})
        print(json.dumps(res))
        print(json.dumps(lis.summary(res.get("last_send_mono"), pub.send_monos)))
        return 0 if "error" not in res else 2


if __name__ == "__main__":
    sys.exit(main())
