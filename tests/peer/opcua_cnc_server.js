#!/usr/bin/env node
// An OPC UA server of a five-axis CNC in the OPC 40502 CNC companion model, written with node-opcua
// (npm) and the CNC nodeset node-opcua-nodesets ships (nodesets.cnc): Objects/CncInterface
// (CncInterfaceType) with one CncAxisType object per axis (X Y Z A C) in its CncAxisList, whose
// PosIndirect and PosDirect carry ActPos and CmdPos with EngineeringUnits (UNECE: MMT millimetre,
// DD degree) and IsRotational. The axes follow a control's joint trace (t_s, x_mm, y_mm, z_mm,
// a_deg, c_deg), sampled every --period s, each value stamped when sampled (SourceTimestamp).
//
// Usage: opcua_cnc_server.js TRACE.csv[.gz] --port P [--period 0.1] [--start S --end E]
//        [--restart-at S --down-s D] [--linger L] [--wait-subscription S]
// --wait-subscription S: start the replay once a client has subscribed (at most S s after start).
// Prints a JSON summary at the end: samples written, restarts.
"use strict";
const fs = require("fs");
const zlib = require("zlib");
const { OPCUAServer, DataType, StatusCodes, makeEUInformation, coerceQualifiedName } = require("node-opcua");
const { nodesets } = require("node-opcua-nodesets");

const CNC_URI = "http://opcfoundation.org/UA/CNC";
const AXES = [["X", "x_mm", false], ["Y", "y_mm", false], ["Z", "z_mm", false], ["A", "a_deg", true], ["C", "c_deg", true]];

function args() {
    const a = { period: 0.1, start: 0, end: null, restartAt: null, downS: 1, linger: 1, waitSubscription: 0 };
    const argv = process.argv.slice(2);
    a.trace = argv[0];
    for (let i = 1; i < argv.length; i += 2) {
        const v = argv[i + 1];
        switch (argv[i]) {
            case "--port": a.port = Number(v); break;
            case "--period": a.period = Number(v); break;
            case "--start": a.start = Number(v); break;
            case "--end": a.end = Number(v); break;
            case "--restart-at": a.restartAt = Number(v); break;
            case "--down-s": a.downS = Number(v); break;
            case "--linger": a.linger = Number(v); break;
            case "--wait-subscription": a.waitSubscription = Number(v); break;
            default: throw new Error(`unknown option ${argv[i]}`);
        }
    }
    return a;
}

function readTrace(path) {
    let text = fs.readFileSync(path);
    if (path.endsWith(".gz")) text = zlib.gunzipSync(text);
    const lines = text.toString().trim().split("\n");
    const head = lines[0].split(",");
    const col = AXES.map(([, k]) => head.indexOf(k));
    const t = head.indexOf("t_s");
    return lines.slice(1).map((l) => {
        const f = l.split(",");
        return [Number(f[t]), col.map((c) => Number(f[c]))];
    });
}

async function build(a) {
    const server = new OPCUAServer({
        port: a.port,
        resourcePath: "/fiveaxis",
        nodeset_filename: [nodesets.standard, nodesets.cnc],
        buildInfo: { productName: "fiveaxis test CNC (node-opcua)" },
    });
    await server.initialize();
    const space = server.engine.addressSpace;
    const ns = space.getNamespaceIndex(CNC_URI);
    const ifaceType = space.findObjectType("CncInterfaceType", ns);
    const axisType = space.findObjectType("CncAxisType", ns);
    const iface = ifaceType.instantiate({ browseName: coerceQualifiedName({ name: "CncInterface", namespaceIndex: ns }), organizedBy: space.rootFolder.objects });
    const list = iface.getComponentByName("CncAxisList", ns);
    const values = {};
    for (const [name, , rotary] of AXES) {
        const axis = axisType.instantiate({ browseName: coerceQualifiedName({ name, namespaceIndex: ns }), componentOf: list });
        axis.getComponentByName("IsRotational", ns).setValueFromSource({ dataType: DataType.Boolean, value: rotary });
        const eu = rotary ? makeEUInformation("DD", "°", "degree") : makeEUInformation("MMT", "mm", "millimetre");
        values[name] = [];
        for (const pos of ["PosIndirect", "PosDirect"]) {
            const p = axis.getComponentByName(pos, ns);
            const units = p.getPropertyByName("EngineeringUnits", ns) || p.getPropertyByName("EngineeringUnits");
            units.setValueFromSource({ dataType: DataType.ExtensionObject, value: eu });
            for (const leaf of ["ActPos", "CmdPos"]) values[name].push(p.getComponentByName(leaf, ns));
        }
    }
    return { server, values };
}

const sleep = (s) => new Promise((r) => setTimeout(r, Math.max(0, s * 1000)));

async function main() {
    const a = args();
    const trace = readTrace(a.trace);
    const end = a.end === null ? trace[trace.length - 1][0] : a.end;
    let { server, values } = await build(a);
    // The server it restarts as is built beforehand (loading the nodesets takes seconds).
    let fresh = a.restartAt === null ? null : await build(a);
    await server.start();
    // The replay (and its restart) counts from a client's first subscription, however long the
    // client took to come (a loaded machine).
    const deadline = Date.now() + a.waitSubscription * 1000;
    while (server.currentSubscriptionCount === 0 && Date.now() < deadline) await sleep(0.02);
    const t0 = Date.now() / 1000;
    let k = 0, i = 0, written = 0, restarts = 0;
    for (;;) {
        const due = k * a.period;
        const t = a.start + due;
        if (t > end) break;
        if (fresh && restarts === 0 && due >= a.restartAt) {
            restarts += 1;
            await server.shutdown(0);
            await sleep(a.downS);
            ({ server, values } = fresh);
            await server.start();
            k = Math.floor((Date.now() / 1000 - t0) / a.period) + 1;
            continue;
        }
        await sleep(t0 + due - Date.now() / 1000);
        while (i + 1 < trace.length && trace[i + 1][0] <= t) i += 1;
        const now = new Date();
        AXES.forEach(([name], j) => {
            for (const node of values[name]) {
                node.setValueFromSource({ dataType: DataType.Double, value: trace[i][1][j] }, StatusCodes.Good, now);
            }
        });
        written += 1;
        k += 1;
    }
    await sleep(a.linger);
    await server.shutdown(0);
    console.log(JSON.stringify({ samples_written: written, restarts, period_s: a.period }));
    process.exit(0);
}

main().catch((e) => {
    console.error(e);
    process.exit(1);
});
