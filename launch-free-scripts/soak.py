#!/usr/bin/env python3
"""Soak test of the DDS node set (issue 15 item 3), run by `soak` inside a private network namespace.

The commander and the simulator publish a program again and again (`--loop`) at 1 kHz in real time,
stamped in wall time; the monitor watches both streams and a recorder writes them to one MCAP file.
Every few seconds the nodes' resident memory and CPU time are sampled from /proc. After the given
time the publishers are stopped (SIGINT), then the monitor and the recorder, and the run is judged:

- memory flat: after the first minute, no node's resident memory grows: the peak over the second
  half of the rest of the run is within 10 % of the peak over its first half (a leak of any rate
  shows there; bounded working sets do not: the monitor's look-ahead fills its 120 s of commanded
  samples in the first two minutes, the simulator's planner takes and returns a pass's plan);
  the spread (max over min after the first minute) is reported beside it;
- nothing lost: the monitor judged no sample lost or out of order on either stream, the recording's
  stamps have no gap, and each stream's recorded count equals what its publisher says it sent;
- the recording complete and recoverable: `fiveaxis mcap recover` rebuilds it with every message.

Latency is read from the recording itself (independently of our nodes' counters): the recorder's
log time (receive) less the DDS source timestamp (the writer's send), and less the header stamp
(when the sample was due). Prints a report, writes soak.json, rss.csv and the nodes' logs to --out,
exits 1 when a criterion fails.
"""
import argparse
import json
import os
import re
import signal
import struct
import subprocess
import sys
import time
from array import array
from pathlib import Path

PAGE = os.sysconf("SC_PAGE_SIZE")
TICK = os.sysconf("SC_CLK_TCK")
TOPICS = ["commanded/axis_state", "simulated/axis_state"]
PERIOD_NS = 1_000_000  # 1 kHz
ANSI = re.compile(r"\x1b\[[0-9;]*m")


def short(topic):
    """A topic without the node set's namespace: /fiveaxis/commanded/axis_state -> commanded/axis_state."""
    return topic[len("/fiveaxis/"):] if topic.startswith("/fiveaxis/") else topic.lstrip("/")


def rss_kib(pid):
    with open(f"/proc/{pid}/statm") as f:
        return int(f.read().split()[1]) * PAGE // 1024


def cpu_s(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICK


def sent_count(log):
    """The publisher's own count of samples sent (its last `sent=N` log field)."""
    text = ANSI.sub("", log.read_text(errors="replace"))
    found = re.findall(r"\bsent=(\d+)", text)
    return int(found[-1]) if found else None


def percentiles(values, ps=(50, 90, 99, 99.9)):
    if not values:
        return {}
    import numpy as np

    a = np.frombuffer(values, dtype=np.int64) / 1e6  # ns -> ms
    out = {f"p{p:g}": float(np.percentile(a, p)) for p in ps}
    out["max"] = float(a.max())
    out["mean"] = float(a.mean())
    return out


def read_recording(path):
    """Per topic: count, stamp gaps (missing samples at 1 kHz), latencies (ns), straight from the file."""
    from mcap.reader import make_reader

    per = {}
    with open(path, "rb") as f:
        for _schema, channel, msg in make_reader(f).iter_messages():
            topic = short(channel.topic)
            p = per.setdefault(topic, {"count": 0, "missing": 0, "not_increasing": 0, "last": None,
                                       "transport": array("q"), "since_stamp": array("q")})
            data = msg.data
            # CDR encapsulation (4 bytes), then builtin_interfaces/Time: int32 sec, uint32 nanosec.
            little = data[1] == 1
            sec, nsec = struct.unpack_from("<iI" if little else ">iI", data, 4)
            stamp = sec * 1_000_000_000 + nsec
            if p["last"] is not None:
                dt = stamp - p["last"]
                if dt <= 0:
                    p["not_increasing"] += 1
                elif dt > PERIOD_NS * 3 // 2:
                    p["missing"] += round(dt / PERIOD_NS) - 1
            p["last"] = stamp
            p["count"] += 1
            p["transport"].append(msg.log_time - msg.publish_time)
            p["since_stamp"].append(msg.log_time - stamp)
    return per


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", required=True, help="folder of fiveaxis, fiveaxis-commander, -simulator, -monitor, -recorder")
    ap.add_argument("--duration-s", type=float, default=3600.0, help="how long the publishers run, s (default 3600)")
    ap.add_argument("--program", default="bundled:SING.I", help="the looped program (default bundled:SING.I)")
    ap.add_argument("--sample-s", type=float, default=None, help="memory sampling interval, s (default duration/360, 1-10 s)")
    ap.add_argument("--warmup-s", type=float, default=60.0, help="memory is judged flat after this, s (default 60)")
    ap.add_argument("--out", required=True, help="folder for soak.mcap, soak.json, rss.csv and the logs (created)")
    args = ap.parse_args()
    b, out = Path(args.bin), Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rec = out / "soak.mcap"
    for stale in (rec, out / "recovered.mcap"):
        stale.unlink(missing_ok=True)
    interval = args.sample_s or min(10.0, max(1.0, args.duration_s / 360))
    # The nodes' own default log level (info, the DDS stack at warn): their final counts are read from it.
    env = dict(os.environ, NO_COLOR="1")
    env.pop("RUST_LOG", None)

    procs, logs = {}, {}

    def start(name, argv):
        logs[name] = out / f"{name}.log"
        procs[name] = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=open(logs[name], "w"), env=env)

    topic_args = [a for t in TOPICS for a in ("--topic", f"{t}:AxisState")]
    start("recorder", [b / "fiveaxis-recorder", "--output", rec, *topic_args])
    start("monitor", [b / "fiveaxis-monitor", *[a for t in TOPICS for a in ("--input", t)], "--summary-json", out / "monitor.json"])
    time.sleep(1.0)
    pub = [args.program, "--loop", "--min-subscribers", "2", "--wait-for-subscriber-s", "30"]
    start("simulator", [b / "fiveaxis-simulator", *pub])
    start("commander", [b / "fiveaxis-commander", *pub])

    t0 = time.monotonic()
    rows, failures = [], []
    next_sample = interval
    while True:
        now = time.monotonic() - t0
        if now >= next_sample:
            row = {"t_s": round(now, 1)}
            for name, p in procs.items():
                try:
                    row[f"{name}_rss_kib"] = rss_kib(p.pid)
                    row[f"{name}_cpu_s"] = round(cpu_s(p.pid), 2)
                except OSError:
                    row[f"{name}_rss_kib"] = row[f"{name}_cpu_s"] = None
            row["recording_bytes"] = rec.stat().st_size if rec.exists() else 0
            rows.append(row)
            next_sample += interval
        dead = [n for n, p in procs.items() if p.poll() is not None]
        if dead:
            failures.append(f"{', '.join(dead)} stopped before the end (exit {[procs[n].returncode for n in dead]})")
            break
        if now >= args.duration_s:
            break
        time.sleep(min(0.5, max(0.0, next_sample - now)))
    elapsed = time.monotonic() - t0

    def stop(names, timeout):
        for n in names:
            if procs[n].poll() is None:
                procs[n].send_signal(signal.SIGINT)
        for n in names:
            try:
                procs[n].wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                procs[n].kill()
                procs[n].wait()
                failures.append(f"{n} did not stop within {timeout} s of SIGINT")

    stop(["commander", "simulator"], 30)
    time.sleep(1.0)  # the last samples reach the subscribers (reliable)
    stop(["monitor", "recorder"], 120)
    for n, p in procs.items():
        if p.returncode not in (0, -signal.SIGINT, 130) and not any(n in f for f in failures):
            failures.append(f"{n} exited {p.returncode}")

    with open(out / "rss.csv", "w") as f:
        keys = list(rows[0].keys())
        f.write(",".join(keys) + "\n")
        for r in rows:
            f.write(",".join("" if r.get(k) is None else str(r[k]) for k in keys) + "\n")

    report = {"program": args.program, "duration_s": round(elapsed, 1), "sample_interval_s": interval, "nodes": {}, "streams": {}}
    for n in procs:
        series = [(r["t_s"], r[f"{n}_rss_kib"]) for r in rows if r.get(f"{n}_rss_kib")]
        after = [(t, k) for t, k in series if t >= args.warmup_s]
        mid = (after[0][0] + after[-1][0]) / 2 if after else 0.0
        first_half = [k for t, k in after if t <= mid]
        second_half = [k for t, k in after if t > mid]
        after = [k for _, k in after]
        cpu = [r[f"{n}_cpu_s"] for r in rows if r.get(f"{n}_cpu_s") is not None]
        node = {
            "rss_first_kib": series[0][1] if series else None,
            "rss_at_warmup_kib": after[0] if after else None,
            "rss_end_kib": series[-1][1] if series else None,
            "rss_peak_kib": max(k for _, k in series) if series else None,
            "rss_spread_after_warmup": (max(after) - min(after)) / min(after) if after else None,
            "rss_peak_first_half_kib": max(first_half) if first_half else None,
            "rss_peak_second_half_kib": max(second_half) if second_half else None,
            "rss_growth_after_warmup": max(second_half) / max(first_half) - 1 if first_half and second_half else None,
            "cpu_percent": 100.0 * (cpu[-1] - cpu[0]) / (rows[-1]["t_s"] - rows[0]["t_s"]) if len(cpu) > 1 and rows[-1]["t_s"] > rows[0]["t_s"] else None,
        }
        report["nodes"][n] = node
        if node["rss_growth_after_warmup"] is None:
            failures.append(f"{n}: too few memory samples after the {args.warmup_s:g} s warm-up (run longer)")
        elif node["rss_growth_after_warmup"] > 0.10:
            failures.append(
                f"{n}: resident memory grew {100 * node['rss_growth_after_warmup']:.1f} % "
                f"(peak {node['rss_peak_first_half_kib']} KiB in the first half after the warm-up, {node['rss_peak_second_half_kib']} KiB in the second)"
            )

    monitor = {}
    try:
        for i in json.loads((out / "monitor.json").read_text()):
            monitor[short(i["topic"])] = i
    except (OSError, ValueError) as e:
        failures.append(f"monitor summary unreadable: {e}")
    recorded = read_recording(rec) if rec.exists() else {}
    sent = {"commanded/axis_state": sent_count(logs["commander"]), "simulated/axis_state": sent_count(logs["simulator"])}
    for topic in TOPICS:
        m, r = monitor.get(topic, {}), recorded.get(topic)
        s = {
            "sent": sent[topic],
            "monitor_samples": m.get("samples"),
            "monitor_lost": m.get("lost"),
            "monitor_out_of_order": m.get("out_of_order"),
            "monitor_invalid": m.get("invalid"),
            "monitor_stale_episodes": m.get("stale"),
            "recorded": r["count"] if r else 0,
            "recorded_stamp_gaps_samples": r["missing"] if r else None,
            "recorded_not_increasing": r["not_increasing"] if r else None,
            "latency_transport_ms": percentiles(r["transport"]) if r else {},
            "latency_since_stamp_ms": percentiles(r["since_stamp"]) if r else {},
        }
        report["streams"][topic] = s
        if not s["sent"]:
            failures.append(f"{topic}: the publisher reported no samples sent")
        if s["recorded"] != s["sent"] or s["monitor_samples"] != s["sent"]:
            failures.append(f"{topic}: sent {s['sent']}, monitor received {s['monitor_samples']}, recorded {s['recorded']}")
        for k in ("monitor_lost", "monitor_out_of_order", "monitor_invalid", "recorded_stamp_gaps_samples", "recorded_not_increasing"):
            if s[k] != 0:
                failures.append(f"{topic}: {k} = {s[k]}")

    recovered = subprocess.run([b / "fiveaxis", "mcap", "recover", rec, out / "recovered.mcap"], capture_output=True, text=True)
    found = re.search(r"recovered (\d+) messages", recovered.stdout)
    total = sum(r["count"] for r in recorded.values())
    report["recording"] = {
        "bytes": rec.stat().st_size if rec.exists() else 0,
        "messages": total,
        "recover_exit": recovered.returncode,
        "recovered_messages": int(found.group(1)) if found else None,
    }
    if recovered.returncode != 0 or report["recording"]["recovered_messages"] != total:
        failures.append(f"mcap recover: exit {recovered.returncode}, {recovered.stdout.strip()} {recovered.stderr.strip()} (recording holds {total})")
    (out / "recovered.mcap").unlink(missing_ok=True)
    report["failures"] = failures
    (out / "soak.json").write_text(json.dumps(report, indent=2))

    print(f"soak: {args.program} looped at 1 kHz for {elapsed:.0f} s; memory sampled every {interval:g} s")
    print(f"resident memory, MiB (warm-up {args.warmup_s:g} s; growth: peak of the second half after it over the first half's)")
    print(f"{'node':10} {'first':>7} {'warm-up':>8} {'end':>7} {'peak':>7} {'peak 1st':>9} {'peak 2nd':>9} {'growth':>7} {'spread':>7} {'CPU':>5}")
    pct = lambda v: f"{100 * v:.1f} %" if v is not None else "-"
    for n, d in report["nodes"].items():
        mib = lambda k: f"{d[k] / 1024:.1f}" if d[k] else "-"
        c = f"{d['cpu_percent']:.0f} %" if d["cpu_percent"] is not None else "-"
        print(f"{n:10} {mib('rss_first_kib'):>7} {mib('rss_at_warmup_kib'):>8} {mib('rss_end_kib'):>7} {mib('rss_peak_kib'):>7} "
              f"{mib('rss_peak_first_half_kib'):>9} {mib('rss_peak_second_half_kib'):>9} {pct(d['rss_growth_after_warmup']):>7} {pct(d['rss_spread_after_warmup']):>7} {c:>5}")
    for topic, s in report["streams"].items():
        print(f"{topic}: sent {s['sent']}, monitor {s['monitor_samples']} (lost {s['monitor_lost']}, out of order {s['monitor_out_of_order']}, "
              f"stale {s['monitor_stale_episodes']}), recorded {s['recorded']} (stamp gaps {s['recorded_stamp_gaps_samples']})")
        for k, label in (("latency_transport_ms", "send -> receive"), ("latency_since_stamp_ms", "stamp -> receive")):
            l = s[k]
            if l:
                print(f"  {label:16} ms: p50 {l['p50']:.3f}  p90 {l['p90']:.3f}  p99 {l['p99']:.3f}  p99.9 {l['p99.9']:.3f}  max {l['max']:.3f}")
    r = report["recording"]
    print(f"recording: {r['bytes'] / 1e6:.1f} MB, {r['messages']} messages; mcap recover: {r['recovered_messages']} messages (exit {r['recover_exit']})")
    for f in failures:
        print(f"FAIL: {f}")
    print("soak: " + ("FAILED" if failures else "passed"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
