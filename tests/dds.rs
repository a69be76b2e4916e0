//! End to end over real DDS: the node executables as separate processes, started by the launch-free
//! scripts inside private network namespaces (loopback only, or two namespaces joined by a veth pair).
//! Needs the node executables, which launch-free-scripts/test builds (cargo build --workspace --bins).

use crate::common;
use std::path::{Path, PathBuf};
use std::process::Command;

mod recorder;
mod security;

fn bins() -> PathBuf {
    let dir = Path::new(env!("FIVEAXIS_EXE")).parent().unwrap().to_path_buf();
    for b in ["fiveaxis-commander", "fiveaxis-simulator", "fiveaxis-monitor", "fiveaxis-recorder"] {
        assert!(dir.join(b).exists(), "{b} is not built in {}: run launch-free-scripts/test (or cargo build --workspace --bins)", dir.display());
    }
    dir
}

struct Row {
    topic: String,
    x: f64,
    y: f64,
    z: f64,
    path_feed: f64,
    predicted: f64,
    in_region: bool,
}

fn rows(csv: &Path) -> Vec<Row> {
    let text = std::fs::read_to_string(csv).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let n = |i: usize| f[i].parse::<f64>().unwrap();
            Row { topic: f[0].to_string(), x: n(2), y: n(3), z: n(4), path_feed: n(5), predicted: n(7), in_region: f[12] == "1" }
        })
        .collect()
}

/// Run a launch-free script on a program; returns the monitor's summary and samples.
fn launch(script: &str, program: &str, tag: &str) -> (serde_json::Value, Vec<Row>) {
    let dir = common::scratch_dir(&format!("dds-{tag}"));
    let (summary, csv) = (dir.join("summary.json"), dir.join("samples.csv"));
    let status = Command::new(Path::new(env!("FIVEAXIS_ROOT")).join("launch-free-scripts").join(script))
        .args([program, "--speed", "4", "--summary-json"])
        .arg(&summary)
        .arg("--samples-csv")
        .arg(&csv)
        .env("FIVEAXIS_BIN", bins())
        .env_remove("FIVEAXIS_IN_NETNS")
        .env("RUST_LOG", "warn")
        .status()
        .expect("launch script runs");
    assert!(status.success(), "{script} {program} failed: {status}");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    let r = rows(&csv);
    let _ = std::fs::remove_dir_all(&dir);
    (v, r)
}

fn input<'a>(summary: &'a serde_json::Value, topic: &str) -> &'a serde_json::Value {
    summary.as_array().unwrap().iter().find(|i| i["topic"] == topic).unwrap_or_else(|| panic!("no input {topic} in {summary}"))
}

/// Run a bash script inside a private loopback-only network namespace.
fn netns_bash(script: &str) -> std::process::Output {
    Command::new(Path::new(env!("FIVEAXIS_ROOT")).join("launch-free-scripts/netns-run"))
        .args(["bash", "-c", script])
        .env("RUST_LOG", "warn")
        .output()
        .expect("netns-run runs")
}

const CMD: &str = fiveaxis::topics::COMMANDED_STATE.absolute;
const SIM: &str = fiveaxis::topics::SIMULATED_STATE.absolute;

fn check_sing(summary: &serde_json::Value, rows: &[Row]) {
    for topic in [CMD, SIM] {
        let i = input(summary, topic);
        for k in ["lost", "invalid", "out_of_order"] {
            assert_eq!(i[k], 0, "{topic}: {k} in {i}");
        }
    }
    // Every commanded sample arrived: SING.I at 1 kHz is 28243 samples (the core's trajectory).
    let job = fiveaxis::job::run("bundled:SING.I", &fiveaxis::machine::Machine::hermle_c600u(), &Default::default()).unwrap();
    assert_eq!(input(summary, CMD)["samples"], job.trajectory.sample_count() as u64);
    // The monitor's statuses on the commanded stream: the core's reference figures.
    let peak = rows.iter().filter(|r| r.topic == CMD).map(|r| r.predicted.abs()).fold(0.0, f64::max);
    assert!((peak - 175.0).abs() < 0.5, "peak {peak}");
    let regions = input(summary, CMD)["regions"].as_array().unwrap();
    assert_eq!(regions.len(), 1, "{regions:?}");
    let (a, b) = (regions[0]["x_start_mm"].as_f64().unwrap(), regions[0]["x_end_mm"].as_f64().unwrap());
    assert!((a - 22.0).abs() < 0.05 && (b - 28.0).abs() < 0.05, "region {a}-{b}");
    let inside: Vec<_> = rows.iter().filter(|r| r.topic == CMD && r.in_region).collect();
    assert!(inside.iter().all(|r| (21.99..=28.01).contains(&r.x)));
    // The simulated feed on the cut: below half of F throughout x 23-27, back at F at x 5-10.
    let cut = |r: &&Row| r.topic == SIM && (r.z + 8.0).abs() < 0.05 && r.y.abs() < 0.05;
    let mid: Vec<_> = rows.iter().filter(cut).filter(|r| (23.0..=27.0).contains(&r.x)).collect();
    assert!(mid.len() > 100);
    assert!(mid.iter().all(|r| r.path_feed < 1000.0), "max {}", mid.iter().map(|r| r.path_feed).fold(0.0, f64::max));
    let at_f = rows.iter().filter(cut).filter(|r| (5.0..=10.0).contains(&r.x) && r.path_feed > 1990.0).count();
    assert!(at_f > 50, "{at_f} samples at F2000 in x 5-10");
}

#[test]
fn paper_demo_over_dds_stutters_on_sing() {
    let (summary, rows) = launch("paper-demo", "bundled:SING.I", "sing");
    check_sing(&summary, &rows);
}

#[test]
fn nonsing_over_dds_shows_no_region_and_no_feed_drop() {
    let (summary, rows) = launch("paper-demo", "bundled:NON_SING.I", "nonsing");
    for topic in [CMD, SIM] {
        let i = input(&summary, topic);
        assert_eq!(i["lost"], 0);
        assert!(i["regions"].as_array().unwrap().is_empty(), "{i}");
    }
    let mid: Vec<_> = rows.iter().filter(|r| r.topic == SIM && (r.z + 8.0).abs() < 0.05 && (r.y - 50.0).abs() < 0.05 && (10.0..=40.0).contains(&r.x)).collect();
    assert!(mid.len() > 300);
    assert!(mid.iter().all(|r| (r.path_feed - 2000.0).abs() < 10.0), "min {}", mid.iter().map(|r| r.path_feed).fold(f64::MAX, f64::min));
}

/// Commander and simulator on one host, the monitor on another, joined by a veth pair.
#[test]
fn two_hosts_joined_by_a_veth_pair() {
    let (summary, rows) = launch("two-hosts", "bundled:SING.I", "twohosts");
    check_sing(&summary, &rows);
}

/// A publisher killed (SIGKILL) mid-run and restarted: the monitor counts the stale episode, keeps
/// running, and takes the restarted stream (its clock starting again at zero) as a new session.
#[test]
fn monitor_survives_a_killed_and_restarted_publisher() {
    let b = bins();
    let dir = common::scratch_dir("dds-restart");
    let summary = dir.join("summary.json");
    let script = format!(
        r#"set -e
B="{b}"
"$B/fiveaxis-monitor" --input commanded/axis_state --stale-ms 100 --exit-when-idle-s 2 --summary-json "{s}" &
M=$!
"$B/fiveaxis-commander" builtin:paper-sing --use-sim-time --speed 1 &
C=$!
sleep 1.0
kill -KILL $C
wait $C || true
sleep 0.5
"$B/fiveaxis-commander" builtin:paper-sing --use-sim-time --speed 4
wait $M
"#,
        b = b.display(),
        s = summary.display()
    );
    let out = netns_bash(&script);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    let i = input(&v, CMD);
    // The first run delivered part of the path, the second all 1501 samples.
    let samples = i["samples"].as_u64().unwrap();
    assert!(samples > 1501 && samples < 2 * 1501, "{samples}");
    assert!(i["stale"].as_u64().unwrap() >= 1, "{i}");
    assert_eq!(i["out_of_order"], 0, "the restart is a new session: {i}");
    assert_eq!(i["invalid"], 0);
    // The region of the full second run was seen (21.58-28.42 on the continuous path).
    let regions = i["regions"].as_array().unwrap();
    assert!(regions.iter().any(|r| (r["x_start_mm"].as_f64().unwrap() - 21.58).abs() < 0.05 && (r["x_end_mm"].as_f64().unwrap() - 28.42).abs() < 0.05), "{regions:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The monitor's input publisher killed (SIGKILL) at a random moment and restarted, 100 times in a
/// row: the monitor keeps running and its counters add up against a recorder subscribed to the same
/// topic the whole time. Every sample the recorder holds is counted by the monitor, up to one per
/// session in flight at the kill; each session that published is a new session (nothing out of
/// order, nothing judged lost) that went stale once.
#[test]
fn monitor_counters_add_up_over_100_publisher_kills() {
    let b = bins();
    let dir = common::scratch_dir("dds-restart-100");
    let (summary, rec) = (dir.join("summary.json"), dir.join("rec.mcap"));
    let script = format!(
        r#"set -e
B="{b}"
"$B/fiveaxis-monitor" --input commanded/axis_state --stale-ms 100 --summary-json "{s}" &
M=$!
"$B/fiveaxis-recorder" --output "{rec}" --topic commanded/axis_state:AxisState &
R=$!
sleep 0.5
for k in $(seq 100); do
    "$B/fiveaxis-commander" builtin:paper-sing --use-sim-time --speed 1 --min-subscribers 2 &
    C=$!
    sleep 0.$((RANDOM % 6 + 2))
    kill -KILL $C
    wait $C || true
    sleep 0.2
    kill -0 $M
done
# Each node must stop within 30 s of SIGINT; if one does not, say which and what its threads wait on.
stop() {{
    kill -INT $1
    for i in $(seq 300); do kill -0 $1 2>/dev/null || {{ wait $1; return $?; }}; sleep 0.1; done
    echo "$2 did not stop within 30 s of SIGINT; its threads:" >&2
    for t in /proc/$1/task/*; do echo "$(cat $t/comm): $(cat $t/wchan 2>/dev/null) $(grep State $t/status)" >&2; done
    kill -KILL $1
    return 1
}}
stop $R recorder
stop $M monitor
"#,
        b = b.display(),
        s = summary.display(),
        rec = rec.display()
    );
    let out = netns_bash(&script);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // What the recorder holds, split into sessions where the program-time stamps start again.
    let mut sessions: Vec<u64> = Vec::new();
    let mut last = f64::INFINITY;
    let recorded = fiveaxis::record::read::for_each_message(&rec, |m| {
        let st: fiveaxis_msgs::AxisState = fiveaxis::record::from_cdr(m.data).unwrap();
        let t = st.header.stamp.as_secs();
        if t <= last {
            sessions.push(0);
        }
        *sessions.last_mut().unwrap() += 1;
        last = t;
    })
    .unwrap();
    let published = sessions.len() as u64;
    assert!(published >= 50, "most of the 100 publishers got to publish: {published} ({sessions:?})");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    let i = input(&v, CMD);
    let counted = i["samples"].as_u64().unwrap() + i["invalid"].as_u64().unwrap() + i["out_of_order"].as_u64().unwrap();
    assert!(counted.abs_diff(recorded) <= published, "monitor counted {counted}, recorder holds {recorded} over {published} sessions: {i}");
    assert_eq!(i["out_of_order"], 0, "every restart is a new session: {i}");
    assert_eq!(i["invalid"], 0, "{i}");
    assert_eq!(i["lost"], 0, "nothing judged lost inside a session: {i}");
    let stale = i["stale"].as_u64().unwrap();
    assert!(stale >= published && stale <= published + 2, "{stale} stale episodes for {published} sessions that published: {i}");
    eprintln!("100 kills: {published} sessions published, recorder {recorded}, monitor {counted}, stale {stale}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// SIGKILL of any node of the set at a random moment, then of the recorder at another: in 8 rounds
/// of the full node set (commander, simulator, monitor, recorder), `fiveaxis mcap recover` mends
/// every recording the recorder left, and the mended file reads through to its footer with our
/// reader and with Foxglove's independent stream reader, message for message.
#[test]
fn sigkill_of_any_node_leaves_a_recording_recover_mends() {
    let b = bins();
    let dir = common::scratch_dir("dds-sigkill");
    let script = format!(
        r#"set -e
B="{b}"
D="{d}"
for r in $(seq 8); do
    "$B/fiveaxis-recorder" --use-sim-time --output "$D/round$r.mcap" &
    R=$!
    "$B/fiveaxis-monitor" --use-sim-time --input commanded/axis_state --input simulated/axis_state &
    M=$!
    "$B/fiveaxis-commander" --use-sim-time builtin:paper-sing --speed 0.5 --min-subscribers 2 &
    C=$!
    "$B/fiveaxis-simulator" --use-sim-time builtin:paper-sing --speed 0.5 --min-subscribers 2 &
    S=$!
    nodes=($C $S $M)
    victim=${{nodes[$((RANDOM % 3))]}}
    sleep 1.$((RANDOM % 10))
    kill -KILL $victim 2>/dev/null || true
    echo "round $r: killed $( [ $victim = $C ] && echo commander || ([ $victim = $S ] && echo simulator || echo monitor))"
    sleep 0.$((RANDOM % 10))
    # Not before the recorder's first chunk of messages is on disk (16 KiB; up to 10 s on a loaded
    # machine): a file cut before its first message has nothing to recover, and recover says so.
    for i in $(seq 100); do [ "$(stat -c %s "$D/round$r.mcap" 2>/dev/null || echo 0)" -gt 16384 ] && break; sleep 0.1; done
    kill -KILL $R
    wait $R || true
    kill -KILL $C $S $M 2>/dev/null || true
    wait $C $S $M 2>/dev/null || true
done
"#,
        b = b.display(),
        d = dir.display()
    );
    let out = netns_bash(&script);
    assert!(out.status.success(), "{}\n{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let peer = Path::new(env!("FIVEAXIS_ROOT")).join("tests/peer/read_linear.py");
    let mut mended = 0;
    for r in 1..=8 {
        let (killed, fixed) = (dir.join(format!("round{r}.mcap")), dir.join(format!("fixed{r}.mcap")));
        let status = Command::new(env!("FIVEAXIS_EXE")).args(["mcap", "recover"]).arg(&killed).arg(&fixed).output().unwrap();
        assert!(status.status.success(), "round {r}: recover failed: {}", String::from_utf8_lossy(&status.stderr));
        let ours = fiveaxis::record::read::for_each_message(&fixed, |_| {}).unwrap_or_else(|e| panic!("round {r}: the mended file: {e}"));
        let theirs = Command::new("python3").arg(&peer).arg(&fixed).output().unwrap();
        assert!(theirs.status.success(), "round {r}: Foxglove's reader: {}", String::from_utf8_lossy(&theirs.stderr));
        let v: serde_json::Value = serde_json::from_slice(&theirs.stdout).unwrap();
        assert_eq!(v["messages"].as_array().unwrap().len() as u64, ours, "round {r}");
        assert_eq!(v["summary"], true, "round {r}: the mended file has its summary");
        mended += u64::from(ours > 0);
    }
    // The recorder lived 1 to 2.8 s in every round and flushes a chunk every second of wall time.
    assert!(mended >= 4, "recordings with messages: {mended} of 8\n{}", String::from_utf8_lossy(&out.stdout));
    let _ = std::fs::remove_dir_all(&dir);
}

/// SIGTERM (as Ctrl-C's SIGINT) stops a node cleanly: the monitor finishes, writes its summary and
/// exits 0; the commander stops publishing and exits 0.
#[test]
fn nodes_stop_cleanly_on_sigterm() {
    let b = bins();
    let dir = common::scratch_dir("dds-term");
    let summary = dir.join("summary.json");
    let script = format!(
        r#"B="{b}"
"$B/fiveaxis-monitor" --input commanded/axis_state --summary-json "{s}" &
M=$!
"$B/fiveaxis-commander" bundled:SING.I --speed 1 &
C=$!
sleep 2
kill -TERM $C
wait $C; rc_c=$?
kill -INT $M
wait $M; rc_m=$?
echo "commander=$rc_c monitor=$rc_m"
[ "$rc_c" = 0 ] && [ "$rc_m" = 0 ]
"#,
        b = b.display(),
        s = summary.display()
    );
    let out = netns_bash(&script);
    let text = String::from_utf8_lossy(&out.stdout);
    let logs = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{text}\n{logs}");
    // RUST_LOG=warn: RustDDS's warning on every datagram over 1500 bytes (discovery, each batch of
    // samples) is not in the nodes' logs.
    assert!(!logs.contains("Message size"), "{logs}");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    let samples = input(&v, CMD)["samples"].as_u64().unwrap();
    // About 1.5 s of a 28 s program at 1 kHz arrived before the commander stopped.
    assert!(samples > 200 && samples < 28243, "{samples}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A node's log history on /rosout is bounded: a reader joining late (rqt_console started mid-shift)
/// gets at most about the last 1000 messages (rcl's rosout depth), however many the node has logged. Before,
/// RustDDS kept up to 8192 of a transient-local writer's samples whatever its depth: several MB of a
/// monitor's memory over a long program, one region message per second. The late joiner is Cyclone DDS.
#[test]
fn a_late_rosout_reader_gets_a_bounded_log_history() {
    let b = bins();
    let dir = common::scratch_dir("dds-rosout");
    // 3000 regions in 9 s of program: 2 mm with the tool axis still 1 deg from the singularity, then
    // 1 mm turning its azimuth 90 deg (C asked 500 rpm of a 25 rpm table), alternately, back and
    // forth over 90 mm of X.
    let program = dir.join("regions.cl");
    let (t, mut x, mut text) = (1.0f64.to_radians(), -45.0f64, String::new());
    let (s, c) = (t.sin(), t.cos());
    for group in 0..1500 {
        let way = if (group / 15) % 2 == 0 { 1.0 } else { -1.0 };
        for (i, j, run) in [(s, 0.0, 2.0), (s, 0.0, 1.0), (0.0, s, 2.0), (0.0, s, 1.0)] {
            text.push_str(&format!("{x:.3} 0 0 {i:.7} {j:.7} {c:.7} 2000\n"));
            x += way * run;
        }
    }
    std::fs::write(&program, text).unwrap();
    let peer = Path::new(env!("FIVEAXIS_ROOT")).join("tests/peer/rosout_history.py");
    let script = format!(
        r#"B="{b}"
RUST_LOG=info "$B/fiveaxis-monitor" --input commanded/axis_state --exit-when-idle-s 30 > /dev/null 2> "{d}/monitor.err" &
M=$!
"$B/fiveaxis-commander" "{p}" --fast --use-sim-time --wait-for-subscriber-s 20 || exit 3
# The writer trims its history every 6 s: join after one trim that follows the monitor's last log.
sleep 8
python3 "{peer}" --duration-s 5 || exit 4
kill -INT $M
wait $M
"#,
        b = b.display(),
        d = dir.display(),
        p = program.display(),
        peer = peer.display()
    );
    let out = netns_bash(&script);
    let text = String::from_utf8_lossy(&out.stdout);
    let logs = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{text}\n{logs}");
    let monitor_log = std::fs::read_to_string(dir.join("monitor.err")).unwrap();
    let logged = monitor_log.lines().filter(|l| l.contains("[rosout] (fiveaxis_monitor)")).count();
    let v: serde_json::Value = serde_json::from_str(text.trim()).unwrap_or_else(|e| panic!("{e}: {text}"));
    let got = v["by_node"]["fiveaxis_monitor"].as_u64().unwrap_or(0);
    assert!(logged > 2000, "the monitor logged {logged} messages on /rosout: {text}");
    // 1000 and the newest: RustDDS's trim keeps the samples from the last minus the limit on.
    assert!(got > 0 && got <= 1001, "a late reader got {got} of the monitor's {logged} log messages: {text}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A defect at the end of a long program (a damaged number on its last line, past what the check reads
/// before the nodes start publishing): the commander and the simulator stream the program as they
/// check it, and stop with exit code 2 naming the defect's line and column, never publishing past it.
#[test]
fn a_defect_deep_in_a_long_program_stops_the_publishing_nodes() {
    let dir = common::scratch_dir("dds-defect");
    let program = dir.join("long.cl");
    // 6 minutes of a dense five-axis raster (120,000 poses), then one damaged line.
    let made = Command::new("python3")
        .arg(Path::new(env!("FIVEAXIS_ROOT")).join("benches/long_program.py"))
        .args(["0.1"])
        .arg(&program)
        .status()
        .expect("python3 runs");
    assert!(made.success());
    let poses = std::fs::read_to_string(&program).unwrap().lines().count();
    let mut text = std::fs::read_to_string(&program).unwrap();
    text.push_str("1.0 2.0 x3.0 0 0 1 2000\n");
    std::fs::write(&program, text).unwrap();
    let place = format!("long.cl:{}:9:", poses + 1);
    // Publishing at once, while the check runs (what a program too long to check in a second does),
    // and checking it all first (the default for a program this short).
    for (node, settle, outcome) in [
        ("fiveaxis-commander", "0", "stopped before the first"),
        ("fiveaxis-simulator", "0", "stopped before the first"),
        ("fiveaxis-commander", "30", "refused (nothing published)"),
        ("fiveaxis-simulator", "30", "refused (nothing published)"),
    ] {
        let out = netns_bash(&format!(
            "'{}' '{}' --fast --use-sim-time --wait-for-subscriber-s 0 --check-before-publish-s {settle}",
            bins().join(node).display(),
            program.display()
        ));
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{node}: {err}");
        assert!(err.contains(&place), "{node} names {place}: {err}");
        assert!(err.contains(outcome), "{node} --check-before-publish-s {settle}: {outcome}: {err}");
        assert!(!err.contains("panicked"), "{node}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// One clock per run, chosen by `use_sim_time` as ROS 2 nodes do (issue 14 item 3). The node set
/// (commander, simulator, monitor, recorder --all) runs a program twice at real-time speed:
/// - with `use_sim_time`, every message in the bag (states, JointStates, status, /diagnostics,
///   /rosout, /clock) carries program time, the recorder's receive times are /clock's, and every
///   writer and reader of /clock is `rosgraph_msgs/msg/Clock` as an independent Cyclone DDS
///   participant sees them;
/// - without it, every stamp is wall time within the run, and nothing publishes /clock.
///
/// Either way no node logs RustDDS's inconsistent-topic error. Stamps are read by rosbags.
#[test]
fn stamps_follow_use_sim_time() {
    let b = bins();
    let peer = Path::new(env!("FIVEAXIS_ROOT")).join("tests/peer/stamps.py");
    for sim in [true, false] {
        let dir = common::scratch_dir(if sim { "dds-time-sim" } else { "dds-time-wall" });
        let bag = dir.join("run");
        let flag = if sim { "--use-sim-time" } else { "" };
        let script = format!(
            r#"set -e
B="{b}"; D="{d}"
date +%s%N > "$D/start_ns"
"$B/fiveaxis-recorder" --all {flag} --output "{bag}" > "$D/recorder.log" 2>&1 &
R=$!
python3 "{peer}" endpoints --topic /clock --duration-s 120 --ready "$D/peer_ready" --until "$D/nodes_done" > "$D/clock.json" &
P=$!
# The nodes start once the peer's discovery readers exist: a first import of Cyclone DDS (compiling
# its modules on a fresh machine) took longer than the commander's whole run, which went unseen.
for i in $(seq 600); do [ -f "$D/peer_ready" ] || sleep 0.1; done
[ -f "$D/peer_ready" ]
"$B/fiveaxis-monitor" {flag} --exit-when-idle-s 2 > "$D/monitor.log" 2>&1 &
M=$!
"$B/fiveaxis-simulator" {flag} builtin:paper-sing --min-subscribers 2 > "$D/simulator.log" 2>&1 &
S=$!
"$B/fiveaxis-commander" {flag} builtin:paper-sing --min-subscribers 2 > "$D/commander.log" 2>&1
wait $S
wait $M
sleep 0.5
kill -INT $R
wait $R
date +%s%N > "$D/end_ns"
touch "$D/nodes_done"
wait $P
"#,
            b = b.display(),
            d = dir.display(),
            bag = bag.display(),
            peer = peer.display(),
        );
        let out = netns_bash(&script);
        let logs: String = ["recorder", "monitor", "simulator", "commander"]
            .iter()
            .map(|n| format!("--- {n}\n{}", std::fs::read_to_string(dir.join(format!("{n}.log"))).unwrap_or_default()))
            .collect();
        assert!(out.status.success(), "sim {sim}: {}\n{logs}", String::from_utf8_lossy(&out.stderr));
        assert!(!logs.contains("Inconsistent topic"), "sim {sim}: {logs}");
        let ns = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap().trim().parse::<u64>().unwrap();
        let (start, end) = (ns("start_ns"), ns("end_ns"));
        let check = Command::new("python3").arg(&peer).arg("bag").arg(&bag).output().expect("python3 runs");
        assert!(check.status.success(), "rosbags: {}", String::from_utf8_lossy(&check.stderr));
        let topics: serde_json::Value = serde_json::from_slice(&check.stdout).unwrap();
        let clock: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("clock.json")).unwrap()).unwrap();
        let u = |v: &serde_json::Value| v.as_u64().unwrap();
        // Every topic of the node set was recorded, every message of a stamped type with its stamp.
        let mut expected = vec!["/fiveaxis/commanded/axis_state", "/fiveaxis/commanded/joint_states", "/fiveaxis/simulated/axis_state", "/fiveaxis/simulated/joint_states", "/fiveaxis/monitor/status", "/diagnostics", "/rosout"];
        if sim {
            expected.push("/clock");
        }
        for t in &expected {
            let v = &topics[*t];
            assert!(u(&v["count"]) > 0 && v["stamped"] == v["count"], "sim {sim}: {t}: {v}\n{topics}");
        }
        // The program is 1.5 s long (1501 samples at 1 kHz); the simulated machine takes longer.
        let program_ns = 1_500_000_000;
        for (t, v) in topics.as_object().unwrap() {
            if u(&v["stamped"]) == 0 {
                continue;
            }
            let (lo, hi) = (u(&v["min_ns"]), u(&v["max_ns"]));
            if sim {
                assert!(hi < 60_000_000_000, "sim: {t} stamped up to {hi} ns: not program time: {v}");
                assert!(u(&v["log_max_ns"]) < 60_000_000_000, "sim: {t}: the recorder's receive times are /clock's: {v}");
            } else {
                assert!(lo >= start && hi <= end, "wall: {t} stamped {lo}..{hi} ns, outside the run {start}..{end}: {v}");
            }
        }
        let cmd = &topics["/fiveaxis/commanded/axis_state"];
        if sim {
            assert_eq!((u(&cmd["min_ns"]), u(&cmd["max_ns"])), (0, program_ns), "program time runs from 0 to the program's end");
            assert_eq!(topics["/clock"]["type"], "rosgraph_msgs/msg/Clock");
            assert_eq!(topics["/clock"]["max_ns"], cmd["max_ns"], "/clock ends where the program does");
            assert!(!clock["publications"].as_array().unwrap().is_empty(), "the commander publishes /clock: {clock}");
        } else {
            // Wall stamps are due times, 1 ms apart. The first sample waits for its acknowledgement:
            // a wait up to 0.5 s is caught up, a longer one (a loaded machine) moves the pacing,
            // leaving one gap after the first sample (publish_states); from the second on, the
            // stamps span the rest of the program.
            let (first, second, last) = (u(&cmd["min_ns"]), u(&cmd["second_ns"]), u(&cmd["max_ns"]));
            let (gap, span) = (second - first, last - second);
            assert!(span.abs_diff(program_ns - 1_000_000) < 1_000_000, "at real time the wall stamps span the program: {span} ns from the second sample");
            assert!(gap.abs_diff(1_000_000) < 1_000_000 || gap > 500_000_000, "the first sample's wait is caught up, or moves the pacing only past 0.5 s: a gap of {gap} ns");
            assert!(topics.get("/clock").is_none() && clock["publications"].as_array().unwrap().is_empty(), "no /clock without use_sim_time: {clock}");
        }
        // Every node's spinner reads /clock (ROS 2's use_sim_time), all as the type ROS 2 uses.
        let subs = clock["subscriptions"].as_array().unwrap();
        assert!(subs.len() >= 4, "sim {sim}: {clock}");
        for e in subs.iter().chain(clock["publications"].as_array().unwrap()) {
            assert_eq!(e[1], "rosgraph_msgs/msg/Clock", "sim {sim}: {clock}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// Domain isolation (issue 15): the commander on ROS_DOMAIN_ID 7 is recorded by a recorder on domain 7
/// and never heard by one on domain 0; an independent Cyclone DDS participant on domain 0 sees neither
/// the node nor its topic while one on domain 7 sees both.
#[test]
fn another_ros_domain_is_never_heard() {
    let b = bins();
    let dir = common::scratch_dir("dds-domain");
    let peer = Path::new(env!("FIVEAXIS_ROOT")).join("tests/peer/ros_graph.py");
    let script = format!(
        r#"set -e
B="{b}"; D="{d}"
ROS_DOMAIN_ID=7 "$B/fiveaxis-recorder" --output "$D/seven.mcap" --topic commanded/axis_state:AxisState > "$D/r7.log" 2>&1 &
R7=$!
ROS_DOMAIN_ID=0 "$B/fiveaxis-recorder" --output "$D/zero.mcap" --topic commanded/axis_state:AxisState > "$D/r0.log" 2>&1 &
R0=$!
ROS_DOMAIN_ID=7 "$B/fiveaxis-commander" builtin:paper-sing --use-sim-time --speed 0.25 --min-subscribers 1 > "$D/c.log" 2>&1 &
C=$!
python3 "{peer}" --node /fiveaxis/fiveaxis_commander --domain-id 0 --timeout-s 4 > "$D/g0.json" &
G0=$!
python3 "{peer}" --node /fiveaxis/fiveaxis_commander --domain-id 7 --timeout-s 20 > "$D/g7.json"
wait $G0
wait $C
sleep 0.5
kill -INT $R7 $R0
wait $R7
wait $R0
"#,
        b = b.display(),
        d = dir.display(),
        peer = peer.display(),
    );
    let out = netns_bash(&script);
    let logs: String = ["c.log", "r0.log", "r7.log"].iter().map(|f| format!("{f}: {}\n", std::fs::read_to_string(dir.join(f)).unwrap_or_default())).collect();
    assert!(out.status.success(), "{}\n{logs}", String::from_utf8_lossy(&out.stderr));
    let count = |f: &str| mcap::Summary::read(&std::fs::read(dir.join(f)).unwrap()).unwrap().expect("a finished file").stats.unwrap().message_count;
    assert_eq!(count("seven.mcap"), 1501, "domain 7 records the whole run\n{logs}");
    assert_eq!(count("zero.mcap"), 0, "domain 0 hears nothing of domain 7\n{logs}");
    let graph = |f: &str| -> serde_json::Value { serde_json::from_str(&std::fs::read_to_string(dir.join(f)).unwrap()).unwrap() };
    let (g0, g7) = (graph("g0.json"), graph("g7.json"));
    let publishes = |g: &serde_json::Value| g["publications"].as_array().unwrap().iter().any(|p| p[0] == CMD);
    assert!(g7["node"].is_object() && publishes(&g7), "domain 7's peer sees the commander: {g7}");
    assert!(g0["node"].is_null() && !publishes(&g0), "domain 0's peer sees nothing of it: {g0}");
    let _ = std::fs::remove_dir_all(&dir);
}
