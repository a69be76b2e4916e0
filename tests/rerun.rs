//! The Rerun bridge, checked by reading its .rrd files back with Rerun's own CLI (`rerun rrd ...` of
//! the matching rerun-sdk 0.36.3, installed by launch-free-scripts/test): replayed from MCAP and live
//! over DDS. The CLI decodes the file independently of our code.

use crate::common;
use std::path::{Path, PathBuf};
use std::process::Command;

fn bin(name: &str) -> PathBuf {
    let p = Path::new(env!("FIVEAXIS_EXE")).parent().unwrap().join(name);
    assert!(p.exists(), "{name} is not built: run launch-free-scripts/test (or cargo build --workspace --bins)");
    p
}

/// `rerun ARGS` (the rerun-sdk CLI), its stdout; panics with stderr on failure.
fn rerun_cli(args: &[&str]) -> String {
    let out = Command::new("rerun")
        .args(args)
        .env("RERUN_ANALYTICS", "0")
        .output()
        .or_else(|_| Command::new("python3").args(["-m", "rerun"]).args(args).output())
        .expect("the rerun CLI (pip install rerun-sdk==0.36.3) runs");
    assert!(out.status.success(), "rerun {args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn tmp(tag: &str) -> PathBuf {
    common::scratch_dir(&format!("rerun-{tag}"))
}

/// Every entity path (temporal or static) and timeline named in `rerun rrd print -vv`.
fn contents(rrd: &Path) -> String {
    rerun_cli(&["rrd", "verify", rrd.to_str().unwrap()]);
    rerun_cli(&["rrd", "print", "-vv", rrd.to_str().unwrap()])
}

const ENTITIES: [&str; 28] = [
    "/c_speed/commanded",
    "/c_speed/simulated",
    "/c_speed/predicted",
    "/c_speed/limit",
    "/feed/programmed",
    "/feed/commanded",
    "/feed/simulated",
    "/feed/axis_limit",
    "/axes/A/commanded",
    "/axes/C/simulated",
    "/distance/commanded",
    "/distance/simulated",
    "/events/regions",
    "/orientation/unit_sphere",
    "/orientation/singular_direction",
    "/orientation/singular_cone",
    "/orientation/tool_axis/simulated",
    "/orientation/trace/commanded",
    "/machine/bed",
    "/machine/table/A",
    "/machine/table/A/C/cut/simulated",
    "/machine/head",
    "/machine/head/tool",
    "/across/c_speed/pass_1/commanded",
    "/across/c_speed/pass_1/simulated",
    "/across/feed/pass_1/programmed",
    "/across/ticks/0",
    "/across/roughness/ra",
];

#[test]
fn replay_of_the_sing_run_has_the_entities_timelines_layout_and_the_papers_region() {
    let dir = tmp("replay");
    let (mcap, rrd) = (dir.join("sing.mcap"), dir.join("sing.rrd"));
    let root = Path::new(env!("FIVEAXIS_ROOT"));
    let run = Command::new(env!("FIVEAXIS_EXE")).args(["run", "bundled:SING.I", "--mcap"]).arg(&mcap).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let out = Command::new(bin("fiveaxis-rerun"))
        .args(["replay"])
        .arg(&mcap)
        .arg("--roughness")
        .arg(root.join("recordings/roughness/SYNTHETIC_sing_profile.x3p"))
        .arg("--save")
        .arg(&rrd)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = contents(&rrd);
    for e in ENTITIES.iter().chain(&["/across/roughness/profile"]) {
        assert!(text.contains(e), "{e} missing from the .rrd");
    }
    assert!(text.contains("time"), "timeline time missing");
    assert!(!text.contains("workpiece_x_um"), "the unit-less x sequence timeline is gone");
    // SING.I cuts one pass, N120-N610: X0 to X50 at Y0 Z-8. The plunge (Z), the lead-in and lead-out
    // (Y), the datum move (diagonal), the rotary-only moves and the return at Z150 after M129 are not
    // passes across the part.
    assert!(!text.contains("/across/c_speed/pass_2"), "only one cutting pass in SING.I");
    // The blueprint travels in the same file, with the time timeline selected.
    assert!(text.contains("Blueprint"), "no blueprint store in the file");
    assert!(text.contains("/time_panel") && text.contains("/viewport"), "layout incomplete");

    // The values, as Rerun decodes them: the region text logs carry the paper's figures (SING.I: the
    // commanded region is x 22-28 mm, 175 rpm; seed 001 Fig. 7 and the reference notes).
    let data = rerun_cli(&["rrd", "print", "-vvv", rrd.to_str().unwrap()]);
    assert!(data.contains("commanded: region 1 ends at x 28.000 mm"), "no region end at 28 mm in the text log");
    assert!(data.contains("peak predicted C speed 175.0 rpm"), "no 175.0 rpm peak in the text log");
    assert!(data.contains("SYNTHETIC"), "the synthetic roughness must be labelled as such");
    assert!(data.contains("pass 1: x 0.0 to 50.0 mm at y 0.00 mm, z -8.00 mm, roughness measured here"), "the pass legend does not name SING's cut");
    for tick in ["0 mm", "25 mm", "50 mm", "rpm", "mm/min"] {
        assert!(data.contains(tick), "no '{tick}' tick label across the part");
    }

    // What Rerun makes of the same MCAP without us (the book's account, docs/src/rerun.md): JointState decoded into
    // scalars per joint, AxisState as one reflected struct per message, on the MCAP's timelines.
    let native = dir.join("native.rrd");
    rerun_cli(&["mcap", "convert", mcap.to_str().unwrap(), "-o", native.to_str().unwrap()]);
    let text = rerun_cli(&["rrd", "print", "-vv", native.to_str().unwrap()]);
    for want in ["/fiveaxis/commanded/joint_states/position", "/fiveaxis/simulated/joint_states/velocity", "fiveaxis_msgs.msg.AxisState:message", "ros2_timestamp", "message_log_time"] {
        assert!(text.contains(want), "rerun mcap convert: no {want}");
    }

    // The same through the main CLI: `fiveaxis replay` forwards to the bridge, and a damaged
    // recording is refused with exit code 2.
    let bad = dir.join("bad.mcap");
    std::fs::write(&bad, b"not an mcap file").unwrap();
    let code = Command::new(env!("FIVEAXIS_EXE")).arg("replay").arg(&bad).arg("--save").arg(dir.join("bad.rrd")).output().unwrap().status.code();
    assert_eq!(code, Some(2), "an unreadable recording is bad input");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn live_bridge_over_dds_draws_the_node_set() {
    let dir = tmp("live");
    let rrd = dir.join("live.rrd");
    let status = Command::new(Path::new(env!("FIVEAXIS_ROOT")).join("launch-free-scripts/paper-demo"))
        .args(["bundled:SING.I", "--speed", "4", "--rrd"])
        .arg(&rrd)
        .env("FIVEAXIS_BIN", bin("fiveaxis").parent().unwrap())
        .env_remove("FIVEAXIS_IN_NETNS")
        .env("RUST_LOG", "warn")
        .status()
        .expect("paper-demo runs");
    assert!(status.success(), "paper-demo --rrd failed: {status}");
    let text = contents(&rrd);
    for e in ENTITIES.iter().filter(|e| !e.contains("/roughness")) {
        assert!(text.contains(e), "{e} missing from the live .rrd");
    }
    let data = rerun_cli(&["rrd", "print", "-vvv", rrd.to_str().unwrap()]);
    assert!(data.contains("commanded: region 1 ends at x 28.000 mm"), "the live bridge saw no region ending at 28 mm");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The x of a region's end in the bridge's text log of a machine stream (`machine: region 1 ends at x ...`).
fn region_end_x(rrd: &Path) -> f64 {
    let data = rerun_cli(&["rrd", "print", "-vvv", rrd.to_str().unwrap()]);
    let at = data.find("machine: region 1 ends at x ").unwrap_or_else(|| panic!("no region end in the text log of {}", rrd.display()));
    let rest = &data[at + "machine: region 1 ends at x ".len()..];
    rest.split_whitespace().next().and_then(|v| v.parse().ok()).unwrap_or_else(|| panic!("unreadable region end: {}", &rest[..40.min(rest.len())]))
}

/// Replay of a machine's recording in machine coordinates (LinuxCNC's trace of SING.I with its G54
/// datum applied by the control, as a rosbag2 written by `rosbags`): with `--work-offset-mm` the region
/// ends at the program's x 28 mm (the independent figure of tests/machine_trace.rs: 28 +- 0.5), without
/// it 30.489 mm lower.
#[test]
fn replay_of_a_machine_recording_with_the_controls_work_offset() {
    let dir = tmp("g54");
    let root = Path::new(env!("FIVEAXIS_ROOT"));
    let bag = dir.join("bag");
    let st = Command::new("python3")
        .arg(root.join("tests/peer/trace_to_rosbag.py"))
        .arg(root.join("recordings/machine/linuxcnc/sing_g54_trace.csv.gz"))
        .arg(&bag)
        .status()
        .expect("python3 runs (rosbags comes from launch-free-scripts/test)");
    assert!(st.success(), "trace_to_rosbag.py failed");
    let mut ends = Vec::new();
    for offset in [Some("-30.489,-7.1,38.054"), None] {
        let rrd = dir.join(format!("g54-{}.rrd", offset.is_some()));
        let mut cmd = Command::new(bin("fiveaxis-rerun"));
        cmd.arg("replay").arg(&bag).args(["--axis-map", "X=x_joint", "--axis-map", "Y=y_joint", "--axis-map", "Z=z_joint", "--axis-map", "A=a_joint", "--axis-map", "C=c_joint", "--save"]).arg(&rrd);
        if let Some(o) = offset {
            cmd.arg(format!("--work-offset-mm={o}"));
        }
        let out = cmd.output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        ends.push(region_end_x(&rrd));
    }
    assert!((ends[0] - 28.0).abs() <= 0.5, "with the work offset the region ends at x {:.3} mm", ends[0]);
    assert!((ends[1] - (ends[0] - 30.489)).abs() <= 0.05, "without it, 30.489 mm lower: {:.3} mm", ends[1]);
    // Without the axis map no joint of the bag (written by rosbags, named by LinuxCNC's HAL) maps
    // onto the machine's axes: replay draws nothing and says so as `fiveaxis analyze` does (exit 2,
    // the joints found and the map to give), the same rule over the same streams.
    let out = Command::new(bin("fiveaxis-rerun")).arg("replay").arg(&bag).arg("--save").arg(dir.join("unmapped.rrd")).output().unwrap();
    let replay_err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{replay_err}");
    let analyze = Command::new(env!("FIVEAXIS_EXE")).arg("analyze").arg(&bag).output().unwrap();
    let analyze_out = format!("{}{}", String::from_utf8_lossy(&analyze.stdout), String::from_utf8_lossy(&analyze.stderr));
    assert_eq!(analyze.status.code(), Some(2), "{analyze_out}");
    // A JointState topic asked for and absent: both refuse it, naming it and the topics there.
    let map = ["--axis-map", "X=x_joint", "--axis-map", "Y=y_joint", "--axis-map", "Z=z_joint", "--axis-map", "A=a_joint", "--axis-map", "C=c_joint"];
    let out = Command::new(bin("fiveaxis-rerun")).arg("replay").arg(&bag).args(map).args(["--joint-state-topic", "/no/such", "--save"]).arg(dir.join("absent.rrd")).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("'/no/such' is not in the recording") && err.contains("/cnc/joint_states"), "{err}");
    for text in [&*replay_err, &*analyze_out] {
        assert!(text.contains("/joint_states") || text.contains("joint_states"), "names the stream: {text}");
        assert!(text.contains("x_joint") && text.contains("--axis-map X=x_joint"), "names the joints and the map: {text}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
