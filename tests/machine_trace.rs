//! A real control's data, offline: LinuxCNC 2.9's 1 kHz joint trace of the paper's SING and NON_SING
//! cuts (`xyzac-trt-kins`, recordings/machine/linuxcnc/make-traces), written as a rosbag2 MCAP
//! directory by an independent writer (`rosbags`, tests/peer/trace_to_rosbag.py) with foreign topics
//! beside it, then `fiveaxis analyze` as a CI user runs it. The figures are checked against an
//! independent numpy computation from the trace (tests/peer/machine_figures.py), never against what
//! fiveaxis printed.

use crate::common;
use std::path::{Path, PathBuf};
use std::process::Command;

const AXIS_MAP: [&str; 10] = ["--axis-map", "X=x_joint", "--axis-map", "Y=y_joint", "--axis-map", "Z=z_joint", "--axis-map", "A=a_joint", "--axis-map", "C=c_joint"];

fn root() -> &'static Path {
    Path::new(env!("FIVEAXIS_ROOT"))
}

fn trace(name: &str) -> PathBuf {
    root().join("recordings/machine/linuxcnc").join(name)
}

/// A rosbag2 directory of `trace` written by rosbags with `extra` options; one per tag.
fn bag(trace_file: &str, tag: &str, extra: &[&str]) -> PathBuf {
    let out = common::scratch_root().join(format!("machine-{tag}"));
    let _ = std::fs::remove_dir_all(&out);
    let st = Command::new("python3")
        .arg(root().join("tests/peer/trace_to_rosbag.py"))
        .arg(trace(trace_file))
        .arg(&out)
        .args(extra)
        .status()
        .expect("python3 runs (rosbags and numpy come from launch-free-scripts/test)");
    assert!(st.success(), "trace_to_rosbag.py failed");
    out
}

fn fiveaxis(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("FIVEAXIS_EXE")).args(args).current_dir(root()).output().unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stdout).into(), String::from_utf8_lossy(&out.stderr).into())
}

/// `fiveaxis analyze` on a bag with the machine's mapping: (exit code, JSON report, stdout, stderr).
fn analyze(bag: &Path, extra: &[&str]) -> (i32, serde_json::Value, String, String) {
    let json = bag.with_extension("json");
    let _ = std::fs::remove_file(&json);
    let mut args = vec!["analyze", bag.to_str().unwrap(), "--joint-state-topic", "/cnc/joint_states", "--machine", "hermle-c600u", "--json", json.to_str().unwrap()];
    args.extend(AXIS_MAP);
    args.extend(extra);
    let (code, out, err) = fiveaxis(&args);
    let v = std::fs::read_to_string(&json).ok().and_then(|t| serde_json::from_str(&t).ok()).unwrap_or(serde_json::Value::Null);
    (code, v, out, err)
}

/// The independent figures over an x range: numpy forward kinematics of the trace, its own feed and
/// time-lost computation.
fn figures(trace_file: &str, x0: f64, x1: f64) -> serde_json::Value {
    figures_with(trace_file, x0, x1, &[])
}

/// [`figures`] with extra options of machine_figures.py (e.g. `--work-offset X Y Z`).
fn figures_with(trace_file: &str, x0: f64, x1: f64, extra: &[&str]) -> serde_json::Value {
    let out = Command::new("python3")
        .arg(root().join("tests/peer/machine_figures.py"))
        .arg(trace(trace_file))
        .args(["--feed", "2000", "--x-range", &x0.to_string(), &x1.to_string()])
        .args(extra)
        .output()
        .expect("python3 runs");
    assert!(out.status.success(), "machine_figures.py: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("machine_figures.py output ({e}): {}", String::from_utf8_lossy(&out.stdout)))
}

fn f(v: &serde_json::Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("no number '{key}' in {v:#}"))
}

/// One region at x 22-28 (+-0.5) with cause singularity, its lowest feed and time lost as the
/// independent computation finds them over the same stretch, exit 1 at 25 rpm, nothing from rapids.
fn check_sing(trace_file: &str, code: i32, v: &serde_json::Value, out: &str, err: &str) {
    check_sing_with(trace_file, &[], code, v, out, err)
}

/// [`check_sing`] with extra options of the independent computation.
fn check_sing_with(trace_file: &str, extra: &[&str], code: i32, v: &serde_json::Value, out: &str, err: &str) {
    assert_eq!(code, 1, "a C speed above 25 rpm fails the gate\n{out}\n{err}");
    let regions = v["regions"].as_array().unwrap_or_else(|| panic!("no regions: {out}\n{err}"));
    assert_eq!(regions.len(), 1, "one region, none from the rapids: {regions:#?}\n{out}");
    let r = &regions[0];
    assert_eq!(r["cause"], "singularity", "{r:#}");
    let (x0, x1) = (f(r, "x_start_mm"), f(r, "x_end_mm"));
    assert!((x0 - 22.0).abs() <= 0.5 && (x1 - 28.0).abs() <= 0.5, "region x {x0:.3}-{x1:.3} mm, expected 22-28: {out}");
    let peak = f(r, "peak_c_speed_rpm");
    assert!(peak > 150.0 && peak < 200.0, "the path asks about 175 rpm of C at F2000, got {peak}");
    let reference = figures_with(trace_file, x0, x1, extra);
    let (lowest, lost) = (f(r, "lowest_feed_mm_per_min"), f(r, "time_lost_s"));
    let (lowest_ref, lost_ref) = (f(&reference, "lowest_feed_mm_per_min"), f(&reference, "time_lost_s"));
    assert!((lowest - lowest_ref).abs() <= 0.05 * lowest_ref + 10.0, "lowest feed {lowest:.1} mm/min, numpy {lowest_ref:.1}");
    assert!((lost - lost_ref).abs() <= 0.05 * lost_ref + 0.05, "time lost {lost:.3} s, numpy {lost_ref:.3}");
    assert!(lost > 0.3, "LinuxCNC slows down there: {lost} s lost");
    // The independent estimate of the stretch where the path asks more than 25 rpm agrees too.
    assert!((f(&reference, "x_start_mm") - x0).abs() <= 0.5 && (f(&reference, "x_end_mm") - x1).abs() <= 0.5, "{reference:#}");
    assert!(v["violations"].as_array().is_some_and(|a| !a.is_empty()));
}

#[test]
fn sing_trace_with_the_program() {
    let b = bag("sing_trace.csv.gz", "sing-program", &[]);
    let (code, v, out, err) = analyze(&b, &["--program", "bundled:SING.I", "--max-c-speed-rpm", "25"]);
    check_sing("sing_trace.csv.gz", code, &v, &out, &err);
    // The closest approach on five-axis moves is computed (forward kinematics; with the program, the
    // positioning moves that end at A = 0 do not count), not the 180 deg of no tool axis.
    let machine = v["streams"].as_array().unwrap().iter().find(|s| s["topic"] == "/cnc/joint_states").expect("the machine stream");
    let closest = f(machine, "min_singularity_distance_deg");
    let independent = f(&figures("sing_trace.csv.gz", 22.0, 28.0), "min_abs_a_deg");
    assert!((closest - independent).abs() < 0.01, "closest approach {closest} deg, numpy's smallest |A| on the cut {independent}");
    // Aligned with the program: the region has block numbers.
    let r = &v["regions"][0];
    assert!(r["block_start"].as_i64().unwrap() >= 320 && r["block_end"].as_i64().unwrap() <= 400, "{r:#}");
}

/// SING.I run by LinuxCNC with its own G54 datum (G10 L2 P1 Y-7.1 Z+38.054, the program's
/// DATUM INPUT): the bridge's joints are machine coordinates, the datum inside them. Given the control's
/// work offset, or the program (whose datum is aligned with the stream), the region is at the program's
/// x 22-28 mm; given neither, at the workpiece frame's x, shifted by the datum.
#[test]
fn sing_trace_with_the_g54_datum_applied_by_the_control() {
    const G54: [&str; 3] = ["-30.489", "-7.1", "38.054"];
    let b = bag("sing_g54_trace.csv.gz", "sing-g54", &[]);
    let offset = G54.join(",");
    let (code, v, out, err) = analyze(&b, &["--feed", "2000", "--work-offset-mm", &offset, "--max-c-speed-rpm", "25"]);
    let independent = ["--work-offset", G54[0], G54[1], G54[2]];
    check_sing_with("sing_g54_trace.csv.gz", &independent, code, &v, &out, &err);
    let (code, v, out, err) = analyze(&b, &["--program", "bundled:SING.I", "--max-c-speed-rpm", "25"]);
    check_sing_with("sing_g54_trace.csv.gz", &independent, code, &v, &out, &err);
    let r = &v["regions"][0];
    assert!(r["block_start"].as_i64().unwrap() >= 320 && r["block_end"].as_i64().unwrap() <= 400, "{r:#}");
    // Without the offset the x is the workpiece frame's: the datum's -30.489 mm away.
    let (_, v, out, _) = analyze(&b, &["--feed", "2000", "--max-c-speed-rpm", "25"]);
    let r = &v["regions"][0];
    let x0 = f(r, "x_start_mm");
    assert!((x0 - (22.0 - 30.489)).abs() <= 0.5, "region at x {x0:.3} mm without the work offset: {out}");
    // A work offset and a program are one datum too many.
    let (code, _, _, err) = analyze(&b, &["--program", "bundled:SING.I", "--work-offset-mm", &offset]);
    assert_eq!(code, 2, "{err}");
    let (code, _, _, err) = analyze(&b, &["--work-offset-mm", "1,2"]);
    assert!(code == 2 && err.contains("X,Y,Z"), "{err}");
}

#[test]
fn sing_trace_with_a_feed_and_modulo_c() {
    // A control that reports C modulo 360 deg: unwrapped, the same answer.
    let b = bag("sing_trace.csv.gz", "sing-feed", &["--modulo-c"]);
    let (code, v, out, err) = analyze(&b, &["--feed", "2000", "--max-c-speed-rpm", "25"]);
    check_sing("sing_trace.csv.gz", code, &v, &out, &err);
    assert!(out.contains("2000 mm/min for every feed move"), "the report says which feed: {out}");
    // Measured C speed never shows the wrap as a spike: the peak is the path's, not 6000 rad/s.
    let machine = v["streams"].as_array().unwrap().iter().find(|s| s["topic"] == "/cnc/joint_states").unwrap();
    assert!(f(machine, "peak_c_speed_rpm") < 250.0, "{machine:#}");
}

#[test]
fn nonsing_trace_passes() {
    let b = bag("nonsing_trace.csv.gz", "nonsing", &[]);
    let (code, v, out, err) = analyze(&b, &["--program", "bundled:NON_SING.I", "--max-c-speed-rpm", "25"]);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(v["regions"].as_array().unwrap().is_empty(), "{out}");
    let machine = v["streams"].as_array().unwrap().iter().find(|s| s["topic"] == "/cnc/joint_states").unwrap();
    assert!((f(machine, "min_singularity_distance_deg") - 11.0).abs() < 0.2, "{machine:#}");
}

/// Every fail-closed case of the CI gate: exit 2 and a message naming the cause.
#[test]
fn bad_machine_input_fails_closed() {
    let short = ["--limit", "3000"];
    let good = bag("sing_trace.csv.gz", "short", &short);
    // Joints cannot be mapped: no --axis-map for x_joint..c_joint names.
    let json = good.with_extension("nomap.json");
    let (code, out, err) = fiveaxis(&["analyze", good.to_str().unwrap(), "--joint-state-topic", "/cnc/joint_states", "--max-c-speed-rpm", "25", "--json", json.to_str().unwrap()]);
    assert_eq!(code, 2, "{out}\n{err}");
    assert!(err.contains("joints found: [x_joint, y_joint, z_joint, a_joint, c_joint]") && err.contains("--axis-map X=x_joint") && err.contains("--axis-map C=c_joint"), "{err}");
    // An input topic asked for is absent.
    let (code, _, out, err) = analyze(&good, &["--joint-state-topic", "/nope"]);
    assert_eq!(code, 2, "{out}\n{err}");
    assert!(err.contains("'/nope' is not in the recording") && err.contains("/cnc/joint_states"), "{err}");
    // An axis the machine lacks.
    let (code, _, err) = fiveaxis(&["analyze", good.to_str().unwrap(), "--axis-map", "B=b_joint"]);
    assert_eq!(code, 2);
    assert!(err.contains("no axis 'B'") && err.contains("X Y Z A C"), "{err}");
    // Lower-case axis names are the machine's axes.
    let mut args = vec!["analyze", good.to_str().unwrap(), "--joint-state-topic", "/cnc/joint_states", "--feed", "2000"];
    args.extend(["--axis-map", "x=x_joint", "--axis-map", "y=y_joint", "--axis-map", "z=z_joint", "--axis-map", "a=a_joint", "--axis-map", "c=c_joint"]);
    let (code, out, err) = fiveaxis(&args);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(out.contains("/cnc/joint_states: 3000 samples"), "{out}");
    // Values in mm and degrees instead of m and rad.
    let mm = bag("sing_trace.csv.gz", "mm", &["--limit", "3000", "--units", "mm-deg"]);
    let (code, _, out, err) = analyze(&mm, &["--feed", "2000"]);
    assert_eq!(code, 2, "{out}\n{err}");
    assert!(err.contains("REP 103"), "{err}");
    // More than the stated share rejected (one NaN sample in ten).
    let nan = bag("sing_trace.csv.gz", "nan", &["--limit", "3000", "--nan-every", "10"]);
    let (code, v, out, err) = analyze(&nan, &["--feed", "2000"]);
    assert_eq!(code, 2, "{out}\n{err}");
    assert!(err.contains("300 of 3000 samples rejected") && err.contains("300 NaN/Inf"), "{err}");
    let s = v["streams"].as_array().unwrap().iter().find(|s| s["topic"] == "/cnc/joint_states").unwrap();
    assert_eq!(s["rejected"]["non_finite"], 300, "counted by reason in the JSON: {s:#}");
    // No valid sample at all: a joint missing from every message.
    let dropped = bag("sing_trace.csv.gz", "drop", &["--limit", "3000", "--drop-joint", "c_joint"]);
    let (code, _, out, err) = analyze(&dropped, &["--feed", "2000"]);
    assert_eq!(code, 2, "{out}\n{err}");
    assert!(err.contains("no valid sample") && err.contains("3000 missing joint"), "{err}");
    // The bag's MCAP file alone reads like the directory.
    let file = std::fs::read_dir(&good).unwrap().map(|e| e.unwrap().path()).find(|p| p.extension().is_some_and(|e| e == "mcap")).unwrap();
    let (code, out, err) = fiveaxis(&["analyze", file.to_str().unwrap(), "--joint-state-topic", "/cnc/joint_states", "--feed", "2000", "--axis-map", "X=x_joint", "--axis-map", "Y=y_joint", "--axis-map", "Z=z_joint", "--axis-map", "A=a_joint", "--axis-map", "C=c_joint"]);
    assert_eq!(code, 0, "{out}\n{err}");
}

/// A bag whose recorder was killed: no metadata.yaml, its MCAP file cut part way. `analyze` reports
/// what comes before the damage and exits 2; `mcap recover` mends the directory, which then analyses.
#[test]
fn a_killed_recorders_bag_is_reported_and_recovered() {
    let good = bag("sing_trace.csv.gz", "killed", &["--limit", "20000"]);
    let file = std::fs::read_dir(&good).unwrap().map(|e| e.unwrap().path()).find(|p| p.extension().is_some_and(|e| e == "mcap")).unwrap();
    let data = std::fs::read(&file).unwrap();
    let crashed = good.with_extension("crashed");
    let _ = std::fs::remove_dir_all(&crashed);
    std::fs::create_dir_all(&crashed).unwrap();
    std::fs::write(crashed.join(file.file_name().unwrap()), &data[..data.len() * 6 / 10]).unwrap();
    let (code, v, out, err) = analyze(&crashed, &["--feed", "2000"]);
    assert_eq!(code, 2, "{out}\n{err}");
    assert!(out.contains("DAMAGED") && err.contains("is damaged"), "{out}\n{err}");
    let before = v["streams"][0]["samples"].as_u64().unwrap_or(0);
    assert!(before > 5000 && before < 20000, "the samples before the damage are reported: {before}");
    let fixed = good.with_extension("fixed");
    let _ = std::fs::remove_dir_all(&fixed);
    let (code, out, err) = fiveaxis(&["mcap", "recover", crashed.to_str().unwrap(), fixed.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}\n{err}");
    let (code, v, out, err) = analyze(&fixed, &["--feed", "2000"]);
    assert_eq!(code, 0, "{out}\n{err}");
    assert_eq!(v["streams"][0]["samples"].as_u64().unwrap(), before, "every sample of the complete chunks: {out}");
}

/// The same cut with its positioning moves as rapids (G00, LinuxCNC's traverse: the approach turns A
/// and C at their rapid limit under a still tip, then moves Y and Z at rapid speed): the rapids open no
/// region and raise no violation, with the program (which says which moves are rapids) or with a feed.
#[test]
fn rapids_open_no_region() {
    let b = bag("sing_rapid_trace.csv.gz", "rapid", &[]);
    let (code, v, out, err) = analyze(&b, &["--program", "recordings/machine/linuxcnc/SING_RAPID.I", "--max-c-speed-rpm", "25"]);
    check_sing("sing_rapid_trace.csv.gz", code, &v, &out, &err);
    // The samples aligned with the program's rapids are LinuxCNC's own traverse samples (its
    // motion.motion-type pin, recorded beside the joints), within the blends between moves.
    let machine = v["streams"].as_array().unwrap().iter().find(|s| s["topic"] == "/cnc/joint_states").unwrap();
    let ours = machine["rapid_samples"].as_f64().unwrap();
    let linuxcnc = f(&figures("sing_rapid_trace.csv.gz", 22.0, 28.0), "rapid_samples");
    assert!(linuxcnc > 3000.0 && (ours - linuxcnc).abs() <= 0.05 * linuxcnc, "rapid samples: ours {ours}, LinuxCNC's traverse {linuxcnc}");
    let (code, v, out, err) = analyze(&b, &["--feed", "2000", "--max-c-speed-rpm", "25"]);
    check_sing("sing_rapid_trace.csv.gz", code, &v, &out, &err);
    // With neither: the feed is assumed from what the stream holds steady. N70's G00 up to Z100
    // blending into N80's G00 that turns the table away from A = 0 (TCP, the tip still) is no
    // programmed feed and opens nothing (it opened a region at x 0, 79-88 rpm, when a rapid's
    // acceleration counted as a feed held).
    let (code, v, out, _) = analyze(&b, &["--max-c-speed-rpm", "25"]);
    assert_eq!(code, 1, "{out}");
    let regions = v["regions"].as_array().unwrap();
    assert_eq!(regions.len(), 1, "the one region, none from the positioning G0: {regions:#?}\n{out}");
    assert!((f(&regions[0], "x_start_mm") - 22.0).abs() <= 0.5 && (f(&regions[0], "x_end_mm") - 28.0).abs() <= 0.5, "{:#}", regions[0]);
}
