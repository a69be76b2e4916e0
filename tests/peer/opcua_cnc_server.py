#!/usr/bin/env python3
"""An OPC UA server of a five-axis CNC in the OPC 40502 CNC companion model, written with asyncua
(PyPI) and the CNC nodeset as the OPC Foundation publishes it (Opc.Ua.CNC.NodeSet.xml, from the npm
package node-opcua-nodesets): Objects/CncInterface (CncInterfaceType), its CncAxisList holding one
CncAxisType object per axis (X Y Z A C) whose PosIndirect and PosDirect carry ActPos and CmdPos with
their EngineeringUnits (UNECE codes: MMT millimetre, DD degree) and IsRotational. The axes follow a
control's joint trace (t_s, x_mm, y_mm, z_mm, a_deg, c_deg), sampled every `--period` s as a
Sinumerik's OPC UA server samples (100 ms at best), each value stamped with the time it was sampled
(its SourceTimestamp).

`--sinumerik`: no CNC model; a Sinumerik's own NC variable paths instead (see `sinumerik`).
`--user NAME:PASSWORD --secure DIR`: as a Sinumerik's server is set up by default, no anonymous
session and only Basic256Sha256 SignAndEncrypt (a self-signed server certificate made in DIR).

Usage: opcua_cnc_server.py TRACE.csv[.gz] (--nodeset Opc.Ua.CNC.NodeSet.xml | --sinumerik) --port P [--period 0.1]
       [--start S --end E] [--restart-at S --down-s D] [--linger L] [--wait-subscription S]
Prints a JSON summary at the end: samples written per axis, restarts.
"""

import argparse
import asyncio
import sys
import csv
import datetime
import gzip
import json
import logging

from pathlib import Path

from asyncua import Server, ua
from asyncua.crypto.cert_gen import setup_self_signed_certificate
from asyncua.server.user_managers import User, UserManager, UserRole
from cryptography.x509.oid import ExtendedKeyUsageOID

CNC_URI = "http://opcfoundation.org/UA/CNC"
AXES = [("X", "x_mm", False), ("Y", "y_mm", False), ("Z", "z_mm", False), ("A", "a_deg", True), ("C", "c_deg", True)]
# UNECE Recommendation 20 codes as OPC UA EUInformation UnitIds (Part 8, 5.6.3): the code's
# letters as a base-256 number.
UNECE = "http://www.opcfoundation.org/UA/units/un/cefact"


def unit_id(code):
    n = 0
    for ch in code:
        n = (n << 8) | ord(ch)
    return n


def read_trace(path):
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        return [(float(r["t_s"]), [float(r[k]) for _, k, _ in AXES]) for r in csv.DictReader(f)]


def importable(path):
    """The nodeset's text with its orphan objects organized under Objects: the published CNC nodeset
    1.0.0 holds leftover objects that nothing references (`Axes`, `Spindles`, `Channels`, `X`,
    `Channel_1`, ...), which asyncua's importer refuses (BadParentNodeIdInvalid). Nothing else
    changes."""
    import re
    text = open(path, encoding="utf-8").read()

    def adopt(m):
        block = m.group(0)
        if "ParentNodeId=" in block or 'IsForward="false"' in block:
            return block
        return block.replace("<References>", '<References>\n      <Reference ReferenceType="Organizes" IsForward="false">i=85</Reference>', 1)

    return re.sub(r"<UAObject [^>]*>.*?</UAObject>", adopt, text, flags=re.S)


async def sinumerik(server):
    """A Sinumerik's own address space as its OPC UA server shows NC variables (SINUMERIK Integrate
    Access MyMachine / OPC UA, Commissioning Manual 10/2015, 4.3.1 "Variable paths"): string node ids
    in its namespace (ns=2), `/Channel/MachineAxis/actToolBasePos[u1,N]` the position of machine axis
    N of channel 1, with no EngineeringUnits (the control's units: mm and degrees here)."""
    ns = await server.register_namespace("SinumerikVarProvider")
    folder = await server.nodes.objects.add_folder(ua.NodeId("Sinumerik", ns), "Sinumerik")
    values = {}
    for k, (name, _, _) in enumerate(AXES):
        path = f"/Channel/MachineAxis/actToolBasePos[u1,{k + 1}]"
        values[name] = [await folder.add_variable(ua.NodeId(path, ns), path, 0.0, varianttype=ua.VariantType.Double)]
    return values


class OneUser(UserManager):
    """The one user a Sinumerik's server is set up with (it refuses anonymous sessions by default)."""

    def __init__(self, name, password):
        self.name, self.password = name, password

    def get_user(self, iserver, username=None, password=None, certificate=None):
        return User(role=UserRole.User) if (username, password) == (self.name, self.password) else None


async def build(a):
    if a.user:
        name, password = a.user.split(":", 1)
        server = Server(user_manager=OneUser(name, password))
    else:
        server = Server()
    await server.init()
    await server.set_application_uri("urn:fiveaxis:test:cnc")
    server.set_endpoint(f"opc.tcp://127.0.0.1:{a.port}/fiveaxis/")
    server.set_server_name("fiveaxis test CNC")
    if a.secure:
        # Basic256Sha256, signed and encrypted only, with a self-signed certificate of the server's.
        key, cert = Path(a.secure) / "server-key.pem", Path(a.secure) / "server-cert.der"
        if not cert.exists():
            Path(a.secure).mkdir(parents=True, exist_ok=True)
            await setup_self_signed_certificate(key, cert, "urn:fiveaxis:test:cnc", "127.0.0.1",
                                                [ExtendedKeyUsageOID.SERVER_AUTH], {"commonName": "fiveaxis test CNC"})
        await server.load_certificate(str(cert))
        await server.load_private_key(str(key))
        server.set_security_policy([ua.SecurityPolicyType.Basic256Sha256_SignAndEncrypt])
    else:
        server.set_security_policy([ua.SecurityPolicyType.NoSecurity])
    if a.user:
        server.set_identity_tokens([ua.UserNameIdentityToken])
    if a.sinumerik:
        return server, await sinumerik(server)
    await server.import_xml(xmlstring=importable(a.nodeset))
    ns = await server.get_namespace_index(CNC_URI)
    objects = server.nodes.objects
    iface = await objects.add_object(ua.NodeId(1, 100), ua.QualifiedName("CncInterface", ns), objecttype=ua.NodeId(1007, ns))
    axis_list = await iface.get_child([f"{ns}:CncAxisList"])
    values = {}
    for k, (name, _, rotary) in enumerate(AXES):
        axis = await axis_list.add_object(ua.NodeId(1, 200 + k), ua.QualifiedName(name, ns), objecttype=ua.NodeId(1004, ns))
        await (await axis.get_child([f"{ns}:IsRotational"])).write_value(rotary)
        eu = ua.EUInformation(NamespaceUri=UNECE, UnitId=unit_id("DD" if rotary else "MMT"),
                              DisplayName=ua.LocalizedText("°" if rotary else "mm"),
                              Description=ua.LocalizedText("degree" if rotary else "millimetre"))
        nodes = []
        for pos in ("PosIndirect", "PosDirect"):
            p = await axis.get_child([f"{ns}:{pos}"])
            await (await p.get_child([f"{ns}:EngineeringUnits"])).write_value(eu)
            for leaf in ("ActPos", "CmdPos"):
                nodes.append(await p.get_child([f"{ns}:{leaf}"]))
        values[name] = nodes
    return server, values


async def stop(server):
    """Stop a server as a machine's restart does: no new connection, every connection closed.

    asyncua 2.1's stop closes the connections it has, then closes its listener and waits (Python
    3.11 Server.wait_closed) until every connection is gone; one the bridge opened in between
    (reconnecting at once) stayed open and the wait never ended (the peer hung in session 62's
    clean-clone run). So the listener is closed first, and any connection still open while the
    stop runs is closed as the others were; the stop is bounded at 10 s all the same.
    """
    listener = getattr(getattr(server, "bserver", None), "_server", None)
    if listener is not None:
        listener.close()

    async def close_the_rest():
        while True:
            await asyncio.sleep(0.05)
            for transport in list(server.iserver.asyncio_transports):
                transport.close()

    closer = asyncio.create_task(close_the_rest())
    try:
        await asyncio.wait_for(server.stop(), 10.0)
    except asyncio.TimeoutError:
        print("stop: not done after 10 s", file=sys.stderr)
    finally:
        closer.cancel()


async def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("trace")
    ap.add_argument("--nodeset")
    ap.add_argument("--sinumerik", action="store_true", help="a Sinumerik's own NC variable paths instead of the CNC model")
    ap.add_argument("--user", help="NAME:PASSWORD: the only identity accepted (no anonymous sessions)")
    ap.add_argument("--secure", metavar="DIR", help="Basic256Sha256 SignAndEncrypt only, the server's certificate made in DIR")
    ap.add_argument("--port", type=int, required=True)
    ap.add_argument("--period", type=float, default=0.1)
    ap.add_argument("--start", type=float, default=0.0)
    ap.add_argument("--end", type=float)
    ap.add_argument("--restart-at", type=float)
    ap.add_argument("--down-s", type=float, default=1.0)
    ap.add_argument("--linger", type=float, default=1.0)
    ap.add_argument("--wait-subscription", type=float, default=0.0, help="start the replay once a client has subscribed (at most S s after start)")
    a = ap.parse_args()
    logging.getLogger("asyncua").setLevel(logging.ERROR)
    trace = read_trace(a.trace)
    times = [t for t, _ in trace]
    end = a.end if a.end is not None else times[-1]
    server, values = await build(a)
    # The server it restarts as is built beforehand (the nodeset's import takes seconds): the
    # outage is --down-s.
    fresh = await build(a) if a.restart_at is not None else None
    await server.start()
    written = 0
    restarts = 0
    loop = asyncio.get_running_loop()
    # The replay (and its restart) counts from a client's first subscription, however long the
    # client took to come (a loaded machine).
    deadline = loop.time() + a.wait_subscription
    while not server.iserver.subscription_service.subscriptions and loop.time() < deadline:
        await asyncio.sleep(0.02)
    t0 = loop.time()
    k = 0
    i = 0
    while True:
        due = k * a.period
        t = a.start + due
        if t > end:
            break
        if a.restart_at is not None and restarts == 0 and due >= a.restart_at:
            restarts += 1
            await stop(server)
            await asyncio.sleep(a.down_s)
            server, values = fresh
            await server.start()
            # The samples of the outage were never taken.
            k = int((loop.time() - t0) / a.period) + 1
            continue
        await asyncio.sleep(max(0.0, t0 + due - loop.time()))
        while i + 1 < len(times) and times[i + 1] <= t:
            i += 1
        now = datetime.datetime.now(datetime.timezone.utc)
        for j, (name, _, _) in enumerate(AXES):
            dv = ua.DataValue(ua.Variant(trace[i][1][j], ua.VariantType.Double), SourceTimestamp=now, ServerTimestamp=now)
            for node in values[name]:
                await node.write_value(dv)
        written += 1
        k += 1
    await asyncio.sleep(a.linger)
    await stop(server)
    print(json.dumps({"samples_written": written, "restarts": restarts, "period_s": a.period}))


if __name__ == "__main__":
    asyncio.run(main())
