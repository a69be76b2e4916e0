//! A real control's data, live: LinuxCNC's 1 kHz joint trace of the SING cut published over DDS by an
//! independent stack (Cyclone DDS from PyPI, tests/peer/cyclone_bridge.py: `sensor_msgs/JointState` on
//! `rt/cnc/joint_states` as rmw_cyclonedds puts it on the wire), the way real bridges do it: reliable
//! or best effort, stamps on the sample grid or at send time with jitter, an outage, C modulo 360 deg. The
//! monitor runs beside it as a process; the peer listens to the monitor's status and `/diagnostics`.
//! Everything runs in a private loopback-only network namespace.

use crate::common;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("FIVEAXIS_ROOT"))
}

fn monitor_bin() -> PathBuf {
    let b = Path::new(env!("FIVEAXIS_EXE")).parent().unwrap().join("fiveaxis-monitor");
    assert!(b.exists(), "fiveaxis-monitor is not built: run launch-free-scripts/test (or cargo build --workspace --bins)");
    b
}

/// The monitor's summary (per input) and the peer's publish and listen summaries.
struct Live {
    summary: serde_json::Value,
    published: serde_json::Value,
    heard: serde_json::Value,
    log: String,
}

/// The SING trace (program coordinates: G54 at the machine's zero) and its cut, trace time 11.0-17.0 s
/// (x 0 to 50 mm).
const SING: Trace = Trace { file: "sing_trace.csv.gz", window_s: (11.0, 17.0), monitor_args: "" };

/// A control's trace of one program and the monitor flags it needs.
struct Trace {
    file: &'static str,
    window_s: (f64, f64),
    monitor_args: &'static str,
}

/// Publish the trace's cut with `peer` options, the monitor at --feed 2000 beside it; the publisher then
/// falls silent (the input goes stale).
fn live(tag: &str, peer: &str) -> Live {
    live_trace(tag, peer, &SING)
}

fn live_trace(tag: &str, peer: &str, trace: &Trace) -> Live {
    // One live run at a time: two 1 kHz publishers on two cores would starve each other.
    static ONE: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _one = ONE.lock().unwrap_or_else(|e| e.into_inner());
    let dir = common::scratch_dir(&format!("live-{tag}"));
    let d = dir.display();
    let script = format!(
        "set -e
        '{monitor}' --joint-state-input /cnc/joint_states --machine hermle-c600u --feed 2000 --lookahead '' \
            --axis-map X=x_joint --axis-map Y=y_joint --axis-map Z=z_joint --axis-map A=a_joint --axis-map C=c_joint \
            --summary-json {d}/summary.json --exit-when-idle-s 3 {extra} > {d}/monitor.log 2>&1 &
        python3 '{peer_py}' run '{trace}' --start {start} --end {end} --wait-subscribers 1 --wait-s 30 \
            --out {d}/heard.jsonl --linger 1.5 {peer} > {d}/peer.json
        wait",
        monitor = monitor_bin().display(),
        peer_py = root().join("tests/peer/cyclone_bridge.py").display(),
        trace = root().join("recordings/machine/linuxcnc").join(trace.file).display(),
        extra = trace.monitor_args,
        start = trace.window_s.0,
        end = trace.window_s.1,
    );
    let out = Command::new(root().join("launch-free-scripts/netns-run")).args(["bash", "-c", &script]).env("RUST_LOG", "warn").output().expect("netns-run runs");
    let log = std::fs::read_to_string(dir.join("monitor.log")).unwrap_or_default();
    assert!(out.status.success(), "live run failed: {}\n{}\nmonitor: {log}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let peer = std::fs::read_to_string(dir.join("peer.json")).unwrap();
    let mut lines = peer.lines().filter(|l| l.starts_with('{')).map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap());
    let published = lines.next().expect("the publisher's summary");
    let heard = lines.next().expect("the listener's summary");
    let summary = serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    Live { summary, published, heard, log }
}

fn check(l: &Live) {
    check_lost(l, 0);
}

/// [`check`] for a publisher that skipped `lost` samples: the monitor counts exactly those, or, when
/// the publisher stamps at send time, at most one more for each send it made over a period late (a
/// starved sender's stamps; no reader of them can tell such a send from one after a lost sample).
fn check_lost(l: &Live, lost: u64) {
    let input = l.summary.as_array().unwrap().iter().find(|i| i["topic"] == "/cnc/joint_states").unwrap_or_else(|| panic!("{:#}", l.summary));
    let sent = l.published["samples_sent"].as_u64().unwrap_or_else(|| panic!("{:#}", l.published));
    assert_eq!(input["samples"].as_u64().unwrap(), sent, "every sample heard: {input:#}\n{}", l.log);
    let late = if l.published["stamp_mode"] == "send" { l.published["late_ms"]["over_1ms"].as_u64().unwrap_or(0) } else { 0 };
    let counted = input["lost"].as_u64().unwrap();
    assert!(counted >= lost && counted <= lost + late, "the samples not sent ({lost}) reported lost, {late} sends over 1 ms late: {input:#}\n{:#}", l.published["late_ms"]);
    assert_eq!(input["rejected"]["out_of_order"], 0, "{input:#}");
    let regions = input["regions"].as_array().unwrap();
    assert_eq!(regions.len(), 1, "one region for the pass, no false one: {regions:#?}");
    let r = &regions[0];
    assert_eq!(r["cause"], "singularity");
    let (x0, x1) = (r["x_start_mm"].as_f64().unwrap(), r["x_end_mm"].as_f64().unwrap());
    assert!((x0 - 22.0).abs() <= 0.5 && (x1 - 28.0).abs() <= 0.5, "region x {x0:.3}-{x1:.3}");
    // The status topic says the input is stale within 150 ms of the last sample.
    let latency = l.heard["stale_latency_s"].as_f64().unwrap_or_else(|| panic!("no stale status heard: {:#}", l.heard));
    assert!(latency < 0.150, "stale reported {latency:.3} s after the last sample");
    eprintln!(
        "live: {} samples, lost {}, region x {x0:.3}-{x1:.3} mm, peak {:.1} rpm, lowest feed {:.0} mm/min, {:.2} s lost, stale after {:.0} ms, publish rate {} Hz",
        input["samples"], input["lost"], r["peak_c_speed_rpm"].as_f64().unwrap_or(0.0), r["min_path_feed_mm_per_min"].as_f64().unwrap_or(0.0), r["time_lost_s"].as_f64().unwrap_or(0.0), latency * 1e3, l.published["rate_hz_achieved"]
    );
    // The region's ERROR reached /diagnostics.
    let levels = &l.heard["diagnostics_levels"]["fiveaxis monitor: /cnc/joint_states"];
    assert!(levels["ERROR"].as_u64().is_some_and(|n| n >= 1), "ERROR on /diagnostics: {levels:#}");
    // And the status carried the region with its cause.
    assert!(l.heard["regions"].as_object().is_some_and(|m| m.len() == 1 && m.values().all(|v| v["cause"] == 1)), "{:#}", l.heard["regions"]);
}

#[test]
fn reliable_bridge_with_grid_stamps_and_modulo_c() {
    let l = live("reliable", "--reliability reliable --stamp grid --modulo-c");
    check(&l);
}

#[test]
fn best_effort_bridge_stamping_at_send_time_with_jitter() {
    let l = live("best-effort", "--reliability best-effort --stamp send --jitter-ms 1 --seed 7");
    check(&l);
}

/// A best-effort bridge stamping at send time that goes silent for 40 ms of wall time at x 8 mm (its
/// schedule skips those samples, as a bridge that drops what it could not send in time): the monitor
/// counts the samples not sent, and the pass is judged as before. Stamps taken at send time carry
/// the sender's lateness: a publisher that runs 5 ms late before the gap and on time after it (a
/// loaded machine: CI runs other tests beside this one) makes stamps that span 35 ms over the gap,
/// which no reader of those stamps can tell from 34 lost and a late sender. So the count must lie
/// between the truth (40) and what the peer's own stamps over the gap say, give or take one.
#[test]
fn best_effort_bridge_outage_is_counted_exactly() {
    let l = live("outage", "--reliability best-effort --stamp send --jitter-ms 1 --seed 11 --gap-at 12 --gap-ms 40");
    assert_eq!(l.published["skipped_gap"], 40, "{:#}", l.published);
    let input = l.summary.as_array().unwrap().iter().find(|i| i["topic"] == "/cnc/joint_states").unwrap_or_else(|| panic!("{:#}", l.summary));
    let lost = input["lost"].as_u64().unwrap();
    let span_ms = l.published["gap_stamp_span_s"].as_f64().unwrap_or_else(|| panic!("the peer's stamps around the gap: {:#}", l.published)) * 1e3;
    // 1 kHz: the stamps over the gap say round(span / 1 ms) - 1 samples are missing.
    let said = (span_ms.round() as u64).saturating_sub(1);
    let (lo, hi) = (said.min(40).saturating_sub(1), said.max(40) + 1);
    assert!((lo..=hi).contains(&lost), "{lost} lost: 40 not sent, the peer's stamps span {span_ms:.1} ms over the gap ({said}): {input:#}");
    check_lost(&l, lost);
}

/// A bridged machine whose control applies SING.I's own G54 datum (G10 L2 P1 Y-7.1 Z+38.054):
/// the JointState carries machine coordinates, and the monitor told the work offset puts the region at
/// the program's x 22-28 mm (without it: x -9 to -2). LinuxCNC's trace of SING_G54.ngc, whose cut comes
/// 1.516 s later than SING's (the datum moves lengthen the approach).
#[test]
fn bridge_in_machine_coordinates_with_the_g54_datum_applied_by_the_control() {
    let g54 = Trace { file: "sing_g54_trace.csv.gz", window_s: (12.52, 18.52), monitor_args: "--work-offset-mm -30.489,-7.1,38.054" };
    let l = live_trace("g54", "--reliability reliable --stamp grid", &g54);
    check(&l);
}

/// A bridge fed by MTConnect: each joint on its own clock at ~3 Hz, sent only when it changed, in
/// JointStates that carry only the joints sent (legal in ROS). The monitor merges them per axis into
/// whole poses and finds the one region live; nothing is refused for a missing joint, nothing is
/// called lost, and the stream is not stale between its samples.
#[test]
fn per_axis_partial_joint_states_live() {
    let l = live("per-axis", "--per-axis-period 0.33");
    let input = l.summary.as_array().unwrap().iter().find(|i| i["topic"] == "/cnc/joint_states").unwrap_or_else(|| panic!("{:#}", l.summary));
    let sent = l.published["samples_sent"].as_u64().unwrap_or_else(|| panic!("{:#}", l.published));
    let samples = input["samples"].as_u64().unwrap();
    // A pose per message, less those before every joint had been sent once (five at most).
    assert!(samples + 5 >= sent && samples <= sent, "{samples} poses of {sent} messages: {input:#}\n{}", l.log);
    assert_eq!(input["rejected"]["missing_joint"], 0, "{input:#}");
    assert_eq!(input["rejected"]["out_of_order"], 0, "{input:#}");
    assert_eq!(input["lost"], 0, "{input:#}");
    assert!(input["stale"].as_u64().unwrap() <= 2, "stale at the end (and at most once before a period is known): {input:#}");
    let regions = input["regions"].as_array().unwrap();
    assert_eq!(regions.len(), 1, "{regions:#?}\n{}", l.log);
    let r = &regions[0];
    assert_eq!(r["cause"], "singularity");
    let (x0, x1) = (r["x_start_mm"].as_f64().unwrap(), r["x_end_mm"].as_f64().unwrap());
    assert!((x0 - 22.0).abs() <= 1.0 && (x1 - 28.0).abs() <= 1.0, "region x {x0:.3}-{x1:.3}");
    let peak = r["peak_c_speed_rpm"].as_f64().unwrap();
    assert!((peak - 175.0).abs() <= 0.05 * 175.0, "peak {peak:.1} rpm (numpy: 175.0 on the 1 kHz trace)");
}

/// A bridge that was down for 2 s and comes back where its clock left off (grid stamps go on; the
/// samples of the outage are never sent): the outage is one stale episode, not 2,000 samples lost,
/// and the summary, the status and `/diagnostics` say the same (before, the summary said about
/// 3,000 lost for a 3 s outage while /diagnostics said 0). Shorter than the monitor's 3 s idle exit
/// by a whole second: at 3 s a loaded machine let the monitor end inside the outage.
#[test]
fn a_bridge_down_for_seconds_is_stale_not_lost_everywhere() {
    let l = live("down-2s", "--reliability reliable --stamp grid --gap-at 12 --gap-ms 2000");
    assert_eq!(l.published["skipped_gap"], 2000, "{:#}", l.published);
    let input = l.summary.as_array().unwrap().iter().find(|i| i["topic"] == "/cnc/joint_states").unwrap_or_else(|| panic!("{:#}", l.summary));
    assert_eq!(input["lost"], 0, "summary: {input:#}");
    // Stale for the outage, and again once the publisher stops at the end.
    assert_eq!(input["stale"], 2, "summary: {input:#}");
    let diag = &l.heard["diagnostics_last"]["fiveaxis monitor: /cnc/joint_states"]["values"];
    assert_eq!(diag["lost_samples"], "0", "/diagnostics: {diag:#}");
    assert_eq!(diag["stale_count"], "2", "/diagnostics: {diag:#}");
    let status = &l.heard["last_status"];
    assert_eq!(status["lost_count"], 0, "status: {status:#}");
    // The pass is still judged: the one region.
    let regions = input["regions"].as_array().unwrap();
    assert_eq!(regions.len(), 1, "{regions:#?}");
}

/// The bridge's view of a CNC's OPC UA server: an independent server has its five CncAxis (OPC 40502,
/// the CNC nodeset as node-opcua-nodesets ships it) follow LinuxCNC's SING trace, sampled every
/// 100 ms as a Sinumerik's server samples at best, each value stamped when sampled;
/// `fiveaxis-bridge --opcua-server` browses the model, subscribes to the axes' ActPos and publishes
/// JointState; the monitor watches it. The server replays from the bridge's subscription (however
/// long a loaded machine took to start the bridge), restarts 1.2 s before the cut and is down for 1 s
/// (a new session, its nodes browsed again); the bridge waits for it as long as it takes (node-opcua
/// loading the CNC nodeset again took over 4 s on a loaded CI machine) and is stopped (SIGINT) once
/// the server has finished, the monitor after it: an idle exit of 3 s ended the monitor inside the
/// restart (down 1 s, the bridge back 3.5 s after the session died on a loaded machine, session 72),
/// so its idle exit only bounds a run gone wrong. `server`: the peer's command before its options;
/// `bridge`: the bridge's options beyond the server and machine.
fn opcua_live(tag: &str, server: &str, bridge: &str) {
    static ONE: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _one = ONE.lock().unwrap_or_else(|e| e.into_inner());
    let dir = common::scratch_dir(&format!("live-opcua-{tag}"));
    let d = dir.display();
    let bin = monitor_bin().parent().unwrap().to_path_buf();
    let listening = common::wait_for_port_sh(4840);
    // Every process bounded (the peer at most its 60 s wait for a subscription and the trace's 9.5 s):
    // a peer that hangs fails the test with its logs, not at nextest's five-minute limit (seen once,
    // session 61: the asyncua server's first try ran until nextest stopped it, the retry passed).
    let script = format!(
        "timeout 90 '{bin}/fiveaxis-monitor' --joint-state-input /fiveaxis/machine/joint_states --machine hermle-c600u --feed 2000 --lookahead '' \
            --summary-json {d}/summary.json --exit-when-idle-s 30 > {d}/monitor.log 2>&1 &
        M=$!
        timeout 120 {server} --port 4840 --start 8.0 --end 17.5 --restart-at 0.8 --down-s 1.0 --linger 2 --wait-subscription 60 > {d}/peer.json 2> {d}/peer.err &
        P=$!
        {listening}
        FIVEAXIS_OPCUA_PKI={d}/pki FIVEAXIS_OPCUA_PASSWORD=s3cret '{bin}/fiveaxis-bridge' --opcua-server opc.tcp://127.0.0.1:4840/fiveaxis --machine hermle-c600u --exit-when-down-s 30 \
            --wait-for-subscriber-s 10 --summary-json {d}/bridge.json {bridge} > {d}/bridge.log 2>&1 &
        B=$!
        wait $P; kill -INT $B 2>/dev/null; wait $B; kill -INT $M 2>/dev/null; wait $M",
        bin = bin.display(),
    );
    let out = Command::new(root().join("launch-free-scripts/netns-run")).args(["bash", "-c", &script]).env("RUST_LOG", "info").output().expect("netns-run runs");
    let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap_or_default();
    let logs = format!("{}\n{}\nbridge: {}\nmonitor: {}\npeer: {}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr), read("bridge.log"), read("monitor.log"), read("peer.err"));
    assert!(out.status.success(), "{logs}");
    // A whole JSON file, or the last JSON line of a peer's output.
    let json = |f: &str| -> serde_json::Value {
        let text = read(f);
        serde_json::from_str(&text).or_else(|_| serde_json::from_str(text.lines().rfind(|l| l.starts_with('{')).unwrap_or(""))).unwrap_or_else(|e| panic!("{f}: {e}\n{logs}"))
    };
    let (summary, bridge, peer) = (serde_json::from_str::<serde_json::Value>(&read("summary.json")).unwrap_or_else(|e| panic!("{e}\n{logs}")), json("bridge.json"), json("peer.json"));
    assert_eq!(peer["restarts"], 1, "{peer}");
    // The restart was seen and got over: two sessions, nothing refused.
    assert_eq!((bridge["connections"].as_u64(), bridge["refused"].as_u64()), (Some(2), Some(0)), "{bridge:#}\n{logs}");
    let input = summary.as_array().unwrap().iter().find(|i| i["topic"] == "/fiveaxis/machine/joint_states").unwrap_or_else(|| panic!("{summary:#}\n{logs}"));
    assert_eq!(input["lost"], 0, "{input:#}");
    assert_eq!(input["rejected"]["missing_joint"], 0, "{input:#}");
    assert_eq!(input["rejected"]["out_of_order"], 0, "{input:#}");
    // A pose per sample the server took while the bridge was subscribed (less the outage's).
    assert!(input["samples"].as_u64().unwrap() >= 60, "{input:#}\n{peer}\n{logs}");
    let regions = input["regions"].as_array().unwrap();
    assert_eq!(regions.len(), 1, "{regions:#?}\n{logs}");
    let r = &regions[0];
    assert_eq!(r["cause"], "singularity");
    let (x0, x1) = (r["x_start_mm"].as_f64().unwrap(), r["x_end_mm"].as_f64().unwrap());
    assert!((x0 - 22.0).abs() <= 1.0 && (x1 - 28.0).abs() <= 1.0, "region x {x0:.2}-{x1:.2}");
    let peak = r["peak_c_speed_rpm"].as_f64().unwrap();
    assert!((peak - 175.0).abs() <= 0.05 * 175.0, "peak {peak:.1} rpm (numpy: 175.0 on the 1 kHz trace)");
    eprintln!("OPC UA ({tag}) at 100 ms: region x {x0:.2}-{x1:.2} mm, peak {peak:.1} rpm, {} poses, bridge {bridge}", input["samples"]);
    let _ = std::fs::remove_dir_all(&dir);
}

fn npm_modules() -> PathBuf {
    let m = root().join("target/npm/node_modules");
    assert!(m.join("node-opcua-nodesets/nodesets/Opc.Ua.CNC.NodeSet.xml").exists(), "{} is installed by launch-free-scripts/test (npm)", m.display());
    m
}

/// node-opcua's server (npm) with the CNC nodeset loaded as node-opcua loads nodesets.
#[test]
fn node_opcuas_cnc_server_at_100_ms_through_the_bridge_and_its_restart() {
    let server = format!("env NODE_PATH='{}' node '{}' '{}'", npm_modules().display(), root().join("tests/peer/opcua_cnc_server.js").display(), root().join("recordings/machine/linuxcnc/sing_trace.csv.gz").display());
    opcua_live("node", &server, "");
}

/// asyncua's server (PyPI) with the same nodeset imported.
#[test]
fn asyncuas_cnc_server_at_100_ms_through_the_bridge_and_its_restart() {
    let nodeset = npm_modules().join("node-opcua-nodesets/nodesets/Opc.Ua.CNC.NodeSet.xml");
    let server = format!("python3 '{}' '{}' --nodeset '{}'", root().join("tests/peer/opcua_cnc_server.py").display(), root().join("recordings/machine/linuxcnc/sing_trace.csv.gz").display(), nodeset.display());
    opcua_live("asyncua", &server, "");
}

/// The Sinumerik node map of the README: the control's own NC variables
/// (`ns=2;s=/Channel/MachineAxis/actToolBasePos[u1,N]`, no EngineeringUnits: mm and degrees said
/// with --assume-mm-deg), served by asyncua as a Sinumerik's server names them.
fn sinumerik_nodes() -> String {
    "XYZAC".chars().enumerate().map(|(k, a)| format!("--opcua-node '{a}=ns=2;s=/Channel/MachineAxis/actToolBasePos[u1,{}]' ", k + 1)).collect()
}

/// As a Sinumerik's server is set up by default: no anonymous session, Basic256Sha256 signed and
/// encrypted only.
#[test]
fn a_sinumeriks_own_nc_variables_by_node_map_through_the_bridge() {
    let pki = common::scratch_root().join("opcua-sinumerik-server-pki");
    let server = format!(
        "python3 '{}' '{}' --sinumerik --user OpcUaClient:s3cret --secure '{}'",
        root().join("tests/peer/opcua_cnc_server.py").display(),
        root().join("recordings/machine/linuxcnc/sing_trace.csv.gz").display(),
        pki.display()
    );
    opcua_live("sinumerik", &server, &format!("--opcua-security sign-and-encrypt --opcua-user OpcUaClient --assume-mm-deg {}", sinumerik_nodes()));
}

/// Fail closed: a server without the CNC model and no node map, a node map whose positions carry no
/// units and none assumed, a secured server asked for no security, and a wrong password, are each
/// refused at once (exit 2) saying why.
#[test]
fn an_opc_ua_server_without_the_axes_is_refused_with_why() {
    let dir = common::scratch_dir("opcua-refused");
    let d = dir.display();
    let bridge = format!("FIVEAXIS_OPCUA_PKI={d}/pki '{}' --opcua-server opc.tcp://127.0.0.1:4840/fiveaxis --machine hermle-c600u --exit-when-down-s 20", monitor_bin().parent().unwrap().join("fiveaxis-bridge").display());
    let listening = common::wait_for_port_sh(4840);
    let script = format!(
        "python3 '{peer}' '{trace}' --sinumerik --port 4840 --start 8 --end 12 --linger 0 > /dev/null 2>&1 &
        {listening}
        {bridge} > {d}/model.log 2>&1; echo \"model $?\"
        {bridge} {nodes} > {d}/units.log 2>&1; echo \"units $?\"
        kill %1; wait
        python3 '{peer}' '{trace}' --sinumerik --user OpcUaClient:s3cret --secure {d}/server-pki --port 4840 --start 8 --end 30 --linger 0 > /dev/null 2>&1 &
        {listening}
        {bridge} --assume-mm-deg {nodes} > {d}/security.log 2>&1; echo \"security $?\"
        FIVEAXIS_OPCUA_PASSWORD=wrong {bridge} --assume-mm-deg --opcua-security sign-and-encrypt --opcua-user OpcUaClient {nodes} > {d}/password.log 2>&1; echo \"password $?\"
        kill %1",
        peer = root().join("tests/peer/opcua_cnc_server.py").display(),
        trace = root().join("recordings/machine/linuxcnc/sing_trace.csv.gz").display(),
        nodes = sinumerik_nodes(),
    );
    let out = Command::new(root().join("launch-free-scripts/netns-run")).args(["bash", "-c", &script]).output().expect("netns-run runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let log = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap_or_default();
    assert!(stdout.contains("model 2") && stdout.contains("units 2"), "{stdout}\n{}\n{}", log("model.log"), log("units.log"));
    assert!(log("model.log").contains("no OPC 40502 CNC model (namespace http://opcfoundation.org/UA/CNC not among"), "{}", log("model.log"));
    assert!(log("units.log").contains("axis X: its position has no EngineeringUnits (say --assume-mm-deg"), "{}", log("units.log"));
    assert!(stdout.contains("security 2") && stdout.contains("password 2"), "{stdout}\n{}\n{}", log("security.log"), log("password.log"));
    assert!(log("security.log").contains("the server offers no endpoint with security None"), "{}", log("security.log"));
    assert!(log("password.log").contains("the server refused the session's identity: BadUserAccessDenied"), "{}", log("password.log"));
    let _ = std::fs::remove_dir_all(&dir);
}
