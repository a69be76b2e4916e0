#!/usr/bin/env python3
"""An MTConnect adapter or agent serving a real SHDR log in real time, written from the protocols
alone (no fiveaxis code), for the bridge's live tests.

`adapter LOG DEVICES.XML --port P`: an adapter (cppagent's Adapter Agent Protocol): listens on TCP;
to each client it first sends the latest value of every data item seen before the replay window
(what an adapter sends a new agent), then the log's lines at their own pace, stamped now; it answers
`* PING` with `* PONG <ms>`. `--restart-at S --down-s D`: drops the client and stops listening at
log time S for D seconds (an adapter restarted).

`agent LOG DEVICES.XML --port P`: an agent (MTConnect Part 1 REST): the log replayed into a buffer
of sequence-numbered observations, stamped now; `/probe` answers the description as given,
`/current`, `/sample` (`from`, `count`; with `interval` a stream as cppagent 2 writes it:
`multipart/mixed;boundary=`, one part per chunk, an empty document every `heartbeat` ms),
`MTConnectError OUT_OF_RANGE` for a `from` outside the buffer; device paths (`/NAME/sample`).
`--restart-at S --down-s D`: the agent stops (connections dropped) and comes back as a new instance.

Both: `--start S --end E` replay the log between S and E s after its first line; `--speed K` runs K
times faster (stamps compressed alike); a JSON summary goes to stdout at the end (lines or
observations served, per data item).
"""

import argparse
import datetime
import json
import socket
import sys
import threading
import time
import uuid
import xml.etree.ElementTree as ET
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from urllib.parse import parse_qs, urlparse


def local(tag):
    return tag.rsplit("}", 1)[-1]


def read_devices(path):
    """{device name: {key: item}} where key is the id and the name; item: dict of attributes + the
    axis component (element, name)."""
    root = ET.parse(path).getroot()
    devices = {}
    for dev in root.iter():
        if local(dev.tag) != "Device":
            continue
        items = {}

        def walk(node, component):
            for child in node:
                t = local(child.tag)
                comp = component
                if t not in ("DataItems", "DataItem", "Components", "Configuration", "Description", "References", "Compositions"):
                    comp = (t, child.get("name") or child.get("id"), child.get("id"))
                if t == "DataItem":
                    item = dict(child.attrib)
                    item["component"] = component
                    items[item["id"]] = item
                    if item.get("name"):
                        items.setdefault(item["name"], item)
                elif t != "Configuration":
                    walk(child, comp)

        walk(dev, ("Device", dev.get("name"), dev.get("id")))
        devices[dev.get("name")] = {"uuid": dev.get("uuid"), "id": dev.get("id"), "items": items}
    return devices


def fields_of(item):
    """Values an SHDR key takes (the Adapter Agent Protocol)."""
    if item is None:
        return 1
    if item.get("category") == "CONDITION":
        return 5
    if item.get("type") == "MESSAGE":
        return 2
    if item.get("type") == "ALARM":
        return 4
    if item.get("representation") == "TIME_SERIES":
        return 3
    return 1


def parse_time(text):
    text = text.split("@")[0].strip()
    if text.endswith("Z"):
        text = text[:-1]
    frac = 0.0
    if "." in text:
        text, f = text.split(".")
        frac = float("0." + f)
    d = datetime.datetime.strptime(text, "%Y-%m-%dT%H:%M:%S").replace(tzinfo=datetime.timezone.utc)
    return d.timestamp() + frac


def stamp_text(t):
    d = datetime.datetime.fromtimestamp(t, datetime.timezone.utc)
    return d.strftime("%Y-%m-%dT%H:%M:%S.%f") + "Z"


def read_log(path, device):
    """[(seconds after the first line, [(key, [fields])])]; asset and command lines skipped."""
    out = []
    t0 = None
    multiline = None
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            line = line.rstrip("\r\n")
            if multiline:
                if line.startswith(multiline):
                    multiline = None
                continue
            if not line or line.startswith("*"):
                continue
            parts = line.split("|")
            t = parse_time(parts[0])
            t0 = t if t0 is None else t0
            obs = []
            k = 1
            while k < len(parts):
                key = parts[k]
                if key.startswith("@") and key.endswith("@"):
                    if key == "@ASSET@" and parts[-1].startswith("--multiline--"):
                        multiline = parts[-1]
                    break
                name = key.split(":", 1)[-1]
                n = fields_of(device["items"].get(name))
                obs.append((name, parts[k + 1:k + 1 + n]))
                k += 1 + n
            out.append((t - t0, obs))
    return out


def window(log, start, end):
    """The latest fields of each key before `start`, and the lines from start to end."""
    latest = {}
    lines = []
    for t, obs in log:
        if t < start:
            for key, f in obs:
                latest[key] = f
        elif end is None or t <= end:
            lines.append((t - start, obs))
    return latest, lines


# -- adapter ---------------------------------------------------------------------------------------

def serve_adapter(a, device, log):
    latest, lines = window(log, a.start, a.end)
    summary = {"lines_sent": 0, "clients": 0, "per_key": {}}
    t_begin = time.time()

    def log_time():
        return (time.time() - t_begin) * a.speed

    def listen():
        s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        s.bind(("127.0.0.1", a.port))
        s.listen(4)
        s.settimeout(0.05)
        return s

    server = listen()
    client = None
    k = 0
    restarted = False
    inbuf = b""

    def send(conn, text):
        conn.sendall((text + "\n").encode())

    while k < len(lines):
        now = log_time()
        if a.restart_at is not None and not restarted and now >= a.restart_at:
            restarted = True
            if client:
                client.close()
                client = None
            server.close()
            time.sleep(a.down_s)
            # The lines of the outage are not sent (the adapter was down).
            t_begin -= 0  # the log's clock keeps running through the outage
            server = listen()
            continue
        if client is None:
            try:
                client, _ = server.accept()
                client.settimeout(0.0)
                summary["clients"] += 1
                # A new client first gets the current value of every data item.
                cur = dict(latest)
                for t, obs in lines:
                    if t > now:
                        break
                    for key, f in obs:
                        cur[key] = f
                # Skip what was due while no client listened.
                while k < len(lines) and lines[k][0] <= now:
                    k += 1
                snapshot = "|".join(f"{key}|{'|'.join(f)}" for key, f in cur.items())
                if snapshot:
                    send(client, f"{stamp_text(time.time())}|{snapshot}")
            except socket.timeout:
                continue
        try:
            data = client.recv(4096)
            if data == b"":
                client.close()
                client = None
                continue
            inbuf += data
            while b"\n" in inbuf:
                line, inbuf = inbuf.split(b"\n", 1)
                if line.strip() == b"* PING":
                    send(client, f"* PONG {a.heartbeat_ms}")
        except (BlockingIOError, socket.timeout):
            pass
        except OSError:
            client = None
            continue
        t, obs = lines[k]
        if t > now:
            time.sleep(min(0.005, (t - now) / a.speed))
            continue
        body = "|".join(f"{key}|{'|'.join(f)}" for key, f in obs)
        try:
            send(client, f"{stamp_text(time.time())}|{body}")
        except OSError:
            client = None
            continue
        summary["lines_sent"] += 1
        for key, _ in obs:
            summary["per_key"][key] = summary["per_key"].get(key, 0) + 1
        k += 1
    time.sleep(a.linger)
    if client:
        client.close()
    server.close()
    print(json.dumps(summary))


# -- agent -----------------------------------------------------------------------------------------

ELEMENTS = {"Samples": "SAMPLE", "Events": "EVENT", "Condition": "CONDITION"}


def pascal(kind):
    return "".join(w.capitalize() for w in kind.split("_"))


class Buffer:
    """The agent's observation buffer: (sequence, item, timestamp, fields)."""

    def __init__(self, size):
        self.size = size
        self.obs = []
        self.next = 1
        self.instance = int(time.time())
        self.latest = {}
        self.cond = threading.Condition()
        self.running = True

    def add(self, item, stamp, fields):
        with self.cond:
            o = (self.next, item, stamp, fields)
            self.next += 1
            self.obs.append(o)
            if len(self.obs) > self.size:
                del self.obs[: len(self.obs) - self.size]
            self.latest[item["id"]] = o
            self.cond.notify_all()

    def first(self):
        return self.obs[0][0] if self.obs else self.next


def document(buf, device_name, device, obs, next_seq):
    ns = "urn:mtconnect.org:MTConnectStreams:2.0"
    root = ET.Element("MTConnectStreams", {"xmlns": ns})
    ET.SubElement(root, "Header", {
        "creationTime": stamp_text(time.time()), "sender": "mtconnect_peer.py", "instanceId": str(buf.instance),
        "version": "2.0", "bufferSize": str(buf.size), "nextSequence": str(next_seq),
        "firstSequence": str(buf.first()), "lastSequence": str(buf.next - 1)})
    streams = ET.SubElement(root, "Streams")
    ds = ET.SubElement(streams, "DeviceStream", {"name": device_name, "uuid": device["uuid"] or ""})
    comps = {}
    for seq, item, stamp, fields in obs:
        comp = item["component"]
        if comp not in comps:
            comps[comp] = ET.SubElement(ds, "ComponentStream", {"component": comp[0], "name": comp[1] or "", "componentId": comp[2] or ""})
        cs = comps[comp]
        cat = {"SAMPLE": "Samples", "EVENT": "Events", "CONDITION": "Condition"}[item["category"]]
        group = cs.find(cat)
        if group is None:
            group = ET.SubElement(cs, cat)
        attrs = {"dataItemId": item["id"], "timestamp": stamp_text(stamp), "sequence": str(seq)}
        if item.get("name"):
            attrs["name"] = item["name"]
        if item.get("subType"):
            attrs["subType"] = item["subType"]
        if cat == "Condition":
            level = (fields[0] or "UNAVAILABLE").capitalize()
            e = ET.SubElement(group, level, dict(attrs, type=item.get("type", "")))
            if len(fields) > 4 and fields[4]:
                e.text = fields[4]
        else:
            e = ET.SubElement(group, pascal(item.get("type", "UNKNOWN")), attrs)
            e.text = fields[-1] if item.get("type") == "MESSAGE" else fields[0]
            if e.text == "":
                e.text = "UNAVAILABLE"
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root)


def error_document(buf, code, text):
    root = ET.Element("MTConnectError", {"xmlns": "urn:mtconnect.org:MTConnectError:2.0"})
    ET.SubElement(root, "Header", {"creationTime": stamp_text(time.time()), "sender": "mtconnect_peer.py", "instanceId": str(buf.instance), "version": "2.0", "bufferSize": str(buf.size)})
    errors = ET.SubElement(root, "Errors")
    e = ET.SubElement(errors, "Error", {"errorCode": code})
    e.text = text
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root)


def serve_agent(a, devices_path, devices, name, log):
    device = devices[name]
    probe = open(devices_path, "rb").read()
    state = {"buf": Buffer(a.buffer), "served": 0, "streams": 0, "per_item": {}, "values": {}}

    def count_values(obs):
        """Values (not UNAVAILABLE) handed to a client, per data item: in /current and streams."""
        for o in obs:
            if o[3] and o[3][0] not in ("", "UNAVAILABLE"):
                # Under the item's id and its name (what the adapter's keys and --axis-map use).
                for k in {o[1]["id"], o[1].get("name") or o[1]["id"]}:
                    state["values"][k] = state["values"].get(k, 0) + 1

    class Handler(BaseHTTPRequestHandler):
        protocol_version = "HTTP/1.1"

        def log_message(self, *args):
            pass

        def reply(self, code, body):
            self.send_response(code)
            self.send_header("Content-Type", "text/xml")
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Connection", "close")
            self.end_headers()
            self.wfile.write(body)
            self.close_connection = True

        def do_GET(self):
            buf = state["buf"]
            u = urlparse(self.path)
            q = {k: v[-1] for k, v in parse_qs(u.query).items()}
            parts = [p for p in u.path.split("/") if p]
            if parts and parts[0] in (name, device["uuid"]):
                parts = parts[1:]
            what = parts[0] if parts else "probe"
            if what == "probe":
                return self.reply(200, probe)
            if what == "current":
                with buf.cond:
                    obs = sorted(buf.latest.values(), key=lambda o: o[0])
                    count_values(obs)
                    return self.reply(200, document(buf, name, device, obs, buf.next))
            if what != "sample":
                return self.reply(404, error_document(buf, "UNSUPPORTED", f"no such request {u.path}"))
            count = int(q.get("count", "100"))
            with buf.cond:
                start = int(q["from"]) if "from" in q else buf.first()
                if start < buf.first() or start > buf.next:
                    return self.reply(400, error_document(buf, "OUT_OF_RANGE", f"'from' must be in {buf.first()}..{buf.next}"))
            if "interval" not in q:
                with buf.cond:
                    obs = [o for o in buf.obs if o[0] >= start][:count]
                    nxt = obs[-1][0] + 1 if obs else start
                    return self.reply(200, document(buf, name, device, obs, nxt))
            interval = int(q["interval"]) / 1000.0
            heartbeat = int(q.get("heartbeat", "10000")) / 1000.0
            boundary = str(uuid.uuid4())
            self.send_response(200)
            self.send_header("Server", "MTConnectAgent")
            self.send_header("Connection", "close")
            self.send_header("Content-Type", f"multipart/mixed;boundary={boundary}")
            self.send_header("Transfer-Encoding", "chunked")
            self.end_headers()
            state["streams"] += 1
            instance = buf.instance
            at = start
            try:
                while True:
                    with buf.cond:
                        deadline = time.time() + heartbeat
                        while buf.running and buf.instance == instance and buf.next <= at and time.time() < deadline:
                            buf.cond.wait(min(0.05, max(0.0, deadline - time.time())))
                        if not buf.running or buf.instance != instance:
                            break
                        if at < buf.first():
                            body = error_document(buf, "OUT_OF_RANGE", f"'from' {at} left the buffer")
                            obs = None
                        else:
                            obs = [o for o in buf.obs if o[0] >= at][:count]
                            nxt = obs[-1][0] + 1 if obs else at
                            body = document(buf, name, device, obs, nxt)
                    part = (f"--{boundary}\r\nContent-type: text/xml\r\nContent-length: {len(body)}\r\n\r\n").encode() + body + b"\r\n"
                    self.wfile.write(f"{len(part):x}\r\n".encode() + part + b"\r\n")
                    self.wfile.flush()
                    if obs is None:
                        break
                    count_values(obs)
                    for o in obs:
                        state["per_item"][o[1]["id"]] = state["per_item"].get(o[1]["id"], 0) + 1
                    state["served"] += len(obs)
                    at = nxt
                    if interval > 0:
                        time.sleep(interval)
            except (BrokenPipeError, ConnectionResetError):
                pass
            self.close_connection = True

    def start_server():
        srv = ThreadingHTTPServer(("127.0.0.1", a.port), Handler)
        srv.daemon_threads = True
        threading.Thread(target=srv.serve_forever, kwargs={"poll_interval": 0.05}, daemon=True).start()
        return srv

    latest, lines = window(log, a.start, a.end)
    buf = state["buf"]
    now = time.time()
    # What the agent holds when it starts serving: every item's latest value.
    for key, f in latest.items():
        item = device["items"].get(key)
        if item:
            buf.add(item, now, f)
    srv = start_server()
    t_begin = time.time()
    restarted = False
    for t, obs in lines:
        while True:
            now = (time.time() - t_begin) * a.speed
            if a.restart_at is not None and not restarted and now >= a.restart_at:
                restarted = True
                srv.shutdown()
                srv.server_close()
                with buf.cond:
                    buf.running = False
                    buf.cond.notify_all()
                time.sleep(a.down_s)
                # A new instance: a new buffer holding the current values.
                fresh = Buffer(a.buffer)
                fresh.instance = buf.instance + 1
                stamp = time.time()
                for o in sorted(buf.latest.values(), key=lambda o: o[0]):
                    fresh.add(o[1], stamp, o[3])
                state["buf"] = buf = fresh
                srv = start_server()
                continue
            if now >= t:
                break
            time.sleep(min(0.005, (t - now) / a.speed))
        stamp = time.time()
        for key, f in obs:
            item = device["items"].get(key)
            if item:
                buf.add(item, stamp, f)
    time.sleep(a.linger)
    with buf.cond:
        buf.running = False
        buf.cond.notify_all()
    srv.shutdown()
    print(json.dumps({"observations_served": state["served"], "streams": state["streams"], "per_item": state["per_item"], "values_per_item": state["values"]}))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("role", choices=["adapter", "agent"])
    ap.add_argument("log")
    ap.add_argument("devices")
    ap.add_argument("--device")
    ap.add_argument("--port", type=int, required=True)
    ap.add_argument("--start", type=float, default=0.0)
    ap.add_argument("--end", type=float)
    ap.add_argument("--speed", type=float, default=1.0)
    ap.add_argument("--heartbeat-ms", type=int, default=1000)
    ap.add_argument("--buffer", type=int, default=131072)
    ap.add_argument("--restart-at", type=float)
    ap.add_argument("--down-s", type=float, default=1.0)
    ap.add_argument("--linger", type=float, default=1.0)
    a = ap.parse_args()
    devices = read_devices(a.devices)
    name = a.device or next(iter(devices))
    log = read_log(a.log, devices[name])
    if a.role == "adapter":
        serve_adapter(a, devices[name], log)
    else:
        serve_agent(a, a.devices, devices, name, log)


if __name__ == "__main__":
    sys.exit(main())
