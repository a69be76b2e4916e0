//! End to end over real DDS: the node executables as separate processes, started by the launch-free
//! scripts inside private network namespaces (loopback only, or two namespaces joined by a veth pair).
//! Needs the node executables, which launch-free-scripts/test builds (cargo build --workspace --bins).

use crate::common;
use std::path::{Path, PathBuf};
use std::process::Command;

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

/// The recorder over DDS: SIGINT finishes a complete file holding every commanded sample; after
/// SIGKILL, `fiveaxis mcap recover` keeps everything up to at most about a second before the kill.
#[test]
fn recorder_finishes_on_sigint_and_is_recovered_after_sigkill() {
    let b = bins();
    let dir = common::scratch_dir("dds-rec");
    let (full, killed, kill_ns) = (dir.join("full.mcap"), dir.join("killed.mcap"), dir.join("kill_ns"));
    let script = format!(
        r#"set -e
B="{b}"
"$B/fiveaxis-recorder" --output "{full}" --topic commanded/axis_state:AxisState &
R1=$!
"$B/fiveaxis-recorder" --output "{killed}" --topic commanded/axis_state:AxisState &
R2=$!
sleep 0.5
"$B/fiveaxis-commander" builtin:paper-sing --use-sim-time --speed 0.5 --min-subscribers 2 &
C=$!
sleep 2.5
date +%s%N > "{kill_ns}"
kill -KILL $R2
wait $C
sleep 0.5
kill -INT $R1
wait $R1
"#,
        b = b.display(),
        full = full.display(),
        killed = killed.display(),
        kill_ns = kill_ns.display()
    );
    let out = netns_bash(&script);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // SIGINT: a complete file with all 1501 samples of the path.
    let data = std::fs::read(&full).unwrap();
    let summary = mcap::Summary::read(&data).unwrap().expect("finished file has a summary");
    assert_eq!(summary.stats.unwrap().message_count, 1501);
    // SIGKILL: recovered up to about a second before the kill.
    let fixed = dir.join("fixed.mcap");
    let report = fiveaxis::record::recover(&killed, &fixed).unwrap();
    let back = std::fs::read(&fixed).unwrap();
    let last_log = mcap::MessageStream::new(&back).unwrap().map(|m| m.unwrap().log_time).max().unwrap();
    let killed_at: u64 = std::fs::read_to_string(&kill_ns).unwrap().trim().parse().unwrap();
    assert!(report.messages > 0);
    assert!(killed_at - last_log < 1_600_000_000, "lost {:.2} s before the kill", (killed_at - last_log) as f64 * 1e-9);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The recorder splits by duration into NAME_0.mcap, NAME_1.mcap, ...: every file complete, every
/// sample in exactly one of them.
#[test]
fn recorder_splits_by_duration() {
    let b = bins();
    let dir = common::scratch_dir("dds-split");
    let script = format!(
        r#"set -e
B="{b}"
"$B/fiveaxis-recorder" --output "{out}" --topic commanded/axis_state:AxisState --split-duration-s 1 &
R=$!
"$B/fiveaxis-commander" builtin:paper-sing --use-sim-time --speed 0.5
sleep 0.5
kill -INT $R
wait $R
"#,
        b = b.display(),
        out = dir.join("run.mcap").display()
    );
    let out = netns_bash(&script);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut total = 0;
    let mut files = 0;
    for k in 0.. {
        let Ok(data) = std::fs::read(dir.join(format!("run_{k}.mcap"))) else { break };
        let summary = mcap::Summary::read(&data).unwrap().expect("each split is a complete file");
        total += summary.stats.unwrap().message_count;
        files += 1;
    }
    assert!(files >= 3, "{files} files for about 4 s of recording");
    assert_eq!(total, 1501);
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

/// `fiveaxis-recorder --all` beside an independent Cyclone DDS peer publishing as rmw_cyclonedds
/// does: a rosbag2 directory that rosbags' reader opens, holding the peer's JointState and
/// std_msgs/String (a type fiveaxis has no definition of: stored with an empty one, as `ros2 bag`
/// does) byte for byte as sent, each decoding to the values sent, metadata.yaml's counts matching.
#[test]
fn recorder_all_writes_a_rosbag2_directory_of_what_it_received() {
    let b = bins();
    let dir = common::scratch_dir("dds-bag");
    let (bag, sent) = (dir.join("cell_bag"), dir.join("sent.json"));
    let peer = Path::new(env!("FIVEAXIS_ROOT")).join("tests/peer/bag_peer.py");
    let script = format!(
        r#"set -e
"{b}/fiveaxis-recorder" --all --output "{bag}" --duration-s 15 &
R=$!
python3 "{peer}" publish --out "{sent}" --count 300
kill -INT $R
wait $R
"#,
        b = b.display(),
        bag = bag.display(),
        sent = sent.display(),
        peer = peer.display(),
    );
    let out = netns_bash(&script);
    assert!(out.status.success(), "{}\n{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(bag.join("metadata.yaml").exists() && bag.join("cell_bag_0.mcap").exists());
    let check = Command::new("python3").arg(&peer).arg("check").arg(&bag).arg(&sent).output().expect("python3 runs");
    let report = String::from_utf8_lossy(&check.stdout);
    assert!(check.status.success(), "rosbags: {report}\n{}", String::from_utf8_lossy(&check.stderr));
    let v: serde_json::Value = serde_json::from_str(report.trim()).unwrap();
    assert_eq!(v["version"], 9);
    assert_eq!(v["topics"]["/cnc/joint_states"]["type"], "sensor_msgs/msg/JointState");
    assert_eq!(v["topics"]["/cnc/joint_states"]["definition"], true);
    assert_eq!(v["topics"]["/cnc/joint_states"]["count"], 300);
    assert_eq!(v["topics"]["/chatter"]["type"], "std_msgs/msg/String");
    assert_eq!(v["topics"]["/chatter"]["definition"], false);
    assert_eq!(v["topics"]["/chatter"]["count"], 300);
    // Our own reader takes the directory too.
    let files = fiveaxis::record::read::recording_files(&bag).unwrap();
    assert_eq!(files, vec![bag.join("cell_bag_0.mcap")]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The recorder refuses, before joining DDS, what it cannot record: exit 2 naming the reason.
#[test]
fn recorder_refuses_a_used_bag_directory_and_a_bad_topic() {
    let b = bins();
    let dir = common::scratch_dir("dds-bag-refused");
    std::fs::create_dir_all(dir.join("used")).unwrap();
    std::fs::write(dir.join("used/metadata.yaml"), "rosbag2_bagfile_information: {}\n").unwrap();
    let cases: [(&[&str], &str); 3] = [
        (&["--output", "used"], "not empty"),
        (&["--output", "new", "--topic", "/a"], "expected TOPIC:TYPE"),
        (&["--output", "new", "--topic", "/a:NoSuchType"], "unknown type 'NoSuchType'"),
    ];
    for (args, why) in cases {
        let out = Command::new(b.join("fiveaxis-recorder")).args(args).current_dir(&dir).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(why), "{args:?}: no {why:?} in {err}");
    }
    // Nothing already there was touched, nothing new was made.
    assert_eq!(std::fs::read_to_string(dir.join("used/metadata.yaml")).unwrap(), "rosbag2_bagfile_information: {}\n");
    assert!(!dir.join("new").exists());
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
python3 "{peer}" endpoints --topic /clock --duration-s 8 > "$D/clock.json" &
P=$!
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

/// Messages in a finished MCAP file (0 for a file with none).
fn message_count(path: &Path) -> u64 {
    let data = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    mcap::Summary::read(&data).unwrap().and_then(|s| s.stats).map_or(0, |s| s.message_count)
}

/// DDS Security (issue 15 item 5), with an SROS2 keystore made by `launch-free-scripts/keystore`
/// (openssl). A keyed commander publishes under `ROS_SECURITY_STRATEGY=Enforce`: a keyed recorder
/// records every sample; an unkeyed recorder and one keyed by another keystore's CA record none,
/// and a sniffer on the loopback sees the messages' text nowhere in the clear. Then an unsecured
/// commander: the unkeyed recorder records it and the sniffer sees the text (the check can fail),
/// while the keyed recorders, refusing unauthenticated peers, record nothing of it.
#[test]
fn dds_security_keyed_nodes_talk_and_unkeyed_ones_hear_nothing() {
    let b = bins();
    let dir = common::scratch_dir("dds-security");
    let root = Path::new(env!("FIVEAXIS_ROOT"));
    let (ks, other) = (dir.join("keystore"), dir.join("other-keystore"));
    for (store, enclaves) in [(&ks, &["/fiveaxis/commander", "/fiveaxis/recorder"][..]), (&other, &["/fiveaxis/recorder"][..])] {
        let made = Command::new(root.join("launch-free-scripts/keystore")).arg(store).args(enclaves).output().expect("keystore runs");
        assert!(made.status.success(), "keystore: {}", String::from_utf8_lossy(&made.stderr));
    }
    let sniff = root.join("tests/peer/sniff.py");
    let script = format!(
        r#"set -u
B="{b}"; D="{d}"
export ROS_SECURITY_STRATEGY=Enforce
# exec: the recorder itself is the background job (a subshell would ignore the SIGINT that stops it).
rec() {{ exec "$B/fiveaxis-recorder" --output "$D/$1.mcap" --topic commanded/axis_state:AxisState "${{@:2}}" > "$D/$1.log" 2>&1; }}
ROS_SECURITY_ENABLE=true ROS_SECURITY_KEYSTORE="{ks}" rec keyed --ros-args --enclave /fiveaxis/recorder &
R1=$!
rec unkeyed &
R2=$!
ROS_SECURITY_ENABLE=true ROS_SECURITY_KEYSTORE="{other}" rec stranger --ros-args --enclave /fiveaxis/recorder &
R3=$!
python3 "{sniff}" --needle workpiece --duration-s 120 --ready "$D/ready1" --stop "$D/stop1" > "$D/secure.json" &
S=$!
while [ ! -e "$D/ready1" ]; do sleep 0.1; done
# The secure handshake (authentication, then key exchange) can take seconds on a loaded machine:
# wait for it up to 60 s rather than the default 10 (the recorder's count below checks it completed).
ROS_SECURITY_ENABLE=true ROS_SECURITY_KEYSTORE="{ks}" "$B/fiveaxis-commander" builtin:paper-sing --use-sim-time --speed 0.5 --min-subscribers 1 \
    --wait-for-subscriber-s 60 --ros-args --enclave /fiveaxis/commander > "$D/commander.log" 2>&1
echo "secure commander: $?"
sleep 1; touch "$D/stop1"
wait $S
python3 "{sniff}" --needle workpiece --duration-s 120 --ready "$D/ready2" --stop "$D/stop2" > "$D/plain.json" &
S=$!
while [ ! -e "$D/ready2" ]; do sleep 0.1; done
"$B/fiveaxis-commander" builtin:paper-sing --use-sim-time --speed 0.5 --min-subscribers 1 --wait-for-subscriber-s 60 > "$D/plain-commander.log" 2>&1
echo "plain commander: $?"
sleep 1; touch "$D/stop2"
wait $S
# Enforce with an enclave that is not in the keystore: refused, naming it.
ROS_SECURITY_ENABLE=true ROS_SECURITY_KEYSTORE="{ks}" "$B/fiveaxis-commander" builtin:paper-sing --ros-args --enclave /fiveaxis/absent > "$D/absent.log" 2>&1
echo "absent enclave: $?"
kill -INT $R1 $R2 $R3
# Bounded: a recorder that does not stop (RustDDS deadlocked at its start once) fails the test, not CI.
for i in $(seq 200); do kill -0 $R1 2> /dev/null || kill -0 $R2 2> /dev/null || kill -0 $R3 2> /dev/null || break; sleep 0.1; done
for r in keyed:$R1 unkeyed:$R2 stranger:$R3; do kill -0 ${{r#*:}} 2> /dev/null && {{ echo "$r did not stop on SIGINT"; kill -9 ${{r#*:}}; }}; done
wait $R1 $R2 $R3
"#,
        b = b.display(),
        d = dir.display(),
        ks = ks.display(),
        other = other.display(),
        sniff = sniff.display(),
    );
    let out = netns_bash(&script);
    let said = String::from_utf8_lossy(&out.stdout).to_string();
    let logs = ["keyed", "unkeyed", "stranger", "commander", "plain-commander", "absent"]
        .map(|n| format!("--- {n}.log\n{}", std::fs::read_to_string(dir.join(format!("{n}.log"))).unwrap_or_default()))
        .join("\n");
    let context = format!("{said}\n{}\n{logs}", String::from_utf8_lossy(&out.stderr));
    assert!(said.contains("secure commander: 0") && said.contains("plain commander: 0"), "{context}");
    assert!(!said.contains("did not stop"), "{context}");
    let absent = std::fs::read_to_string(dir.join("absent.log")).unwrap_or_default();
    // Bad input: exit 2, naming the enclave.
    assert!(said.contains("absent enclave: 2") && absent.contains("/fiveaxis/absent"), "{context}");
    // builtin:paper-sing is 1501 samples. All three counts are read before any is asserted, so a
    // failure reports them together.
    let counts = ["keyed", "unkeyed", "stranger"].map(|n| message_count(&dir.join(format!("{n}.mcap"))));
    let counts_said = format!("keyed {}, unkeyed (the plain commander's only) {}, keyed by another CA {}", counts[0], counts[1], counts[2]);
    assert_eq!(counts, [1501, 1501, 0], "recorders' counts: {counts_said}\n{context}");
    let sniffed = |f: &str| -> serde_json::Value { serde_json::from_str(&std::fs::read_to_string(dir.join(f)).unwrap_or_default()).unwrap_or_else(|e| panic!("{f}: {e}\n{context}")) };
    let (secure, plain) = (sniffed("secure.json"), sniffed("plain.json"));
    assert!(secure["datagrams"].as_u64().unwrap() > 1000, "secure phase: {secure}");
    assert_eq!(secure["with_needle"].as_u64(), Some(0), "text in the clear under DDS Security: {secure}");
    assert!(plain["with_needle"].as_u64().unwrap() > 1000, "the sniffer must see the unsecured messages' text: {plain}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// DDS Security's handshake answered late completes (vendor/rustdds, `handshake-resend.patch` and
/// `poll-eintr.patch`). The keyed recorder starts the handshake (the lower GUID prefix, derived from
/// its certificate); the keyed commander is stopped (SIGSTOP) from the recorder's first request
/// until after its 10 resends (11 s), then continued. Upstream RustDDS 0.15.1 removed the request
/// with its last resend, so every reply was "not related to the message that we have sent" and the
/// pair never matched (0 of 1501: the CI failure of the security test above, where the commander
/// learned of the recorder only at its periodic announcement 10 s after start); and the continued
/// commander's discovery thread ended on EINTR. Now the commander, at 4x, delivers all 1501 samples.
#[test]
fn dds_security_handshake_answered_after_the_requests_resends_completes() {
    let b = bins();
    let dir = common::scratch_dir("dds-security-late");
    let root = Path::new(env!("FIVEAXIS_ROOT"));
    let ks = dir.join("keystore");
    let made = Command::new(root.join("launch-free-scripts/keystore")).arg(&ks).args(["/fiveaxis/commander", "/fiveaxis/recorder"]).output().expect("keystore runs");
    assert!(made.status.success(), "keystore: {}", String::from_utf8_lossy(&made.stderr));
    // Up to 3 attempts: one only counts when the commander was stopped before the handshake
    // completed (the recorder's log shows its request's resends run out first).
    let mut scenario = String::new();
    for attempt in 1..=3 {
        let d = dir.join(format!("attempt-{attempt}"));
        std::fs::create_dir_all(&d).unwrap();
        let script = format!(
            r#"set -u
B="{b}"; D="{d}"
export ROS_SECURITY_ENABLE=true ROS_SECURITY_STRATEGY=Enforce ROS_SECURITY_KEYSTORE="{ks}"
export RUST_LOG=warn,rustdds::discovery::secure_discovery=debug
( exec "$B/fiveaxis-recorder" --output "$D/keyed.mcap" --topic commanded/axis_state:AxisState --ros-args --enclave /fiveaxis/recorder > "$D/keyed.log" 2>&1 ) &
R=$!
sleep 0.5
"$B/fiveaxis-commander" builtin:paper-sing --use-sim-time --speed 4 --min-subscribers 1 --wait-for-subscriber-s 60 \
    --ros-args --enclave /fiveaxis/commander > "$D/commander.log" 2>&1 &
C=$!
for i in $(seq 3000); do grep -q "Sending a handshake request message" "$D/keyed.log" && break; sleep 0.01; done
kill -STOP $C; sleep 11; kill -CONT $C
wait $C; echo "commander: $?"
sleep 0.5; kill -INT $R
for i in $(seq 100); do kill -0 $R 2> /dev/null || break; sleep 0.1; done
kill -0 $R 2> /dev/null && {{ echo "recorder did not stop on SIGINT"; kill -9 $R; }}
wait $R
"#,
            b = b.display(),
            d = d.display(),
            ks = ks.display(),
        );
        let out = netns_bash(&script);
        let said = String::from_utf8_lossy(&out.stdout).to_string();
        let read = |n: &str| std::fs::read_to_string(d.join(n)).unwrap_or_default();
        let (keyed, commander) = (read("keyed.log"), read("commander.log"));
        let context = format!("{said}\n{}\n--- keyed.log\n{keyed}\n--- commander.log\n{commander}", String::from_utf8_lossy(&out.stderr));
        let exhausted = keyed.find("Resending at most 0 more times");
        let authenticated = keyed.find("Authenticated successfully");
        if exhausted.is_none() || authenticated.is_some_and(|a| a < exhausted.unwrap()) {
            scenario = format!("attempt {attempt}: the handshake completed before the commander was stopped\n{context}");
            continue;
        }
        assert!(said.contains("commander: 0") && !said.contains("did not stop"), "{context}");
        assert!(!commander.contains("Failed in waiting of poll in discovery"), "the continued commander's discovery ended on EINTR: {context}");
        assert!(authenticated.is_some(), "the handshake never completed: {context}");
        assert_eq!(message_count(&d.join("keyed.mcap")), 1501, "keyed recorder: {context}");
        let _ = std::fs::remove_dir_all(&dir);
        return;
    }
    panic!("the scenario (commander stopped before the handshake completed) was never set up:\n{scenario}");
}

/// The recorder node on a full disk (a 1 MiB tmpfs in a private mount namespace) ends as `fiveaxis
/// run --mcap` does: exit 2 naming the file and the cause, the file closed at its last whole chunk
/// and read through by our reader, as many messages as the error says.
#[test]
fn recorder_on_a_full_disk_exits_2_with_a_closed_readable_file() {
    let b = bins();
    let mnt = common::scratch_dir("dds-full-disk-mnt");
    let out = common::scratch_dir("dds-full-disk-out");
    let script = format!(
        r#"B="{b}"
unshare --mount --map-root-user sh -c 'mount -t tmpfs -o size=1m tmpfs "$1" || exit 99
"$2/fiveaxis-recorder" --output "$1/rec.mcap" --topic commanded/axis_state:AxisState --topic commanded/joint_states:JointState; rc=$?
cp -r "$1/." "$3/"; exit $rc' sh "{mnt}" "$B" "{out}" &
R=$!
sleep 0.5
"$B/fiveaxis-commander" bundled:SING.I --use-sim-time --speed 8 --passes 4 --min-subscribers 1 > /dev/null 2>&1 &
C=$!
# The disk fills within seconds; the commander's four passes (about a minute) only bound the wait.
while kill -0 $R 2> /dev/null && kill -0 $C 2> /dev/null; do sleep 0.1; done
kill $C 2> /dev/null
for i in $(seq 50); do kill -0 $C 2> /dev/null || break; sleep 0.1; done
kill -KILL $C 2> /dev/null; wait $C; echo "commander exit $?" >&2
for i in $(seq 100); do kill -0 $R 2> /dev/null || break; sleep 0.1; done
kill -INT $R 2> /dev/null
wait $R; echo "recorder exit $?" >&2
"#,
        b = b.display(),
        mnt = mnt.display(),
        out = out.display()
    );
    let run = netns_bash(&script);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!stderr.contains("recorder exit 99"), "mounting a tmpfs in a user namespace: {stderr}");
    assert!(stderr.contains("recorder exit 2"), "{stderr}");
    assert!(stderr.contains("No space left on device") && stderr.contains("rec.mcap"), "the error names the file and the cause: {stderr}");
    let kept: u64 = stderr
        .split(" messages), closed and readable")
        .next()
        .and_then(|s| s.rsplit('(').next())
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("the error says how many messages the file kept: {stderr}"));
    let n = fiveaxis::record::read::for_each_message(&out.join("rec.mcap"), |_| {}).unwrap();
    assert!(n > 1000, "most of the 1 MiB holds messages: {n}: {stderr}");
    assert_eq!(n, kept);
    let _ = std::fs::remove_dir_all(&out);
}
