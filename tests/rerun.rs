//! The Rerun bridge, checked by reading its .rrd files back with Rerun's own CLI (`rerun rrd ...` of
//! the matching rerun-sdk 0.36.3, installed by launch-free-scripts/test): replayed from MCAP and live
//! over DDS. The CLI decodes the file independently of our code.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin(name: &str) -> PathBuf {
    let p = Path::new(env!("CARGO_BIN_EXE_fiveaxis")).parent().unwrap().join(name);
    assert!(p.exists(), "{name} is not built: run `cargo test --workspace` (launch-free-scripts/test)");
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
    let d = std::env::temp_dir().join(format!("fiveaxis-rerun-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Every entity path (temporal or static) and timeline named in `rerun rrd print -vv`.
fn contents(rrd: &Path) -> String {
    rerun_cli(&["rrd", "verify", rrd.to_str().unwrap()]);
    rerun_cli(&["rrd", "print", "-vv", rrd.to_str().unwrap()])
}

const ENTITIES: [&str; 21] = [
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
    "/toolpath/path/commanded",
    "/toolpath/tip/simulated",
    "/roughness/ra",
];

#[test]
fn replay_of_the_sing_run_has_the_entities_timelines_layout_and_the_papers_region() {
    let dir = tmp("replay");
    let (mcap, rrd) = (dir.join("sing.mcap"), dir.join("sing.rrd"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let run = Command::new(env!("CARGO_BIN_EXE_fiveaxis")).args(["run", "bundled:SING.I", "--mcap"]).arg(&mcap).output().unwrap();
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
    for e in ENTITIES.iter().chain(&["/roughness/profile"]) {
        assert!(text.contains(e), "{e} missing from the .rrd");
    }
    for timeline in ["workpiece_x_um", "time"] {
        assert!(text.contains(timeline), "timeline {timeline} missing");
    }
    // The blueprint travels in the same file, with the x timeline selected.
    assert!(text.contains("Blueprint"), "no blueprint store in the file");
    assert!(text.contains("/time_panel") && text.contains("/viewport"), "layout incomplete");

    // The values, as Rerun decodes them: the region text logs carry the paper's figures (SING.I: the
    // commanded region is x 22-28 mm, 175 rpm; seed 001 Fig. 7 and the reference notes).
    let data = rerun_cli(&["rrd", "print", "-vvv", rrd.to_str().unwrap()]);
    assert!(data.contains("commanded: region 1 ends at x 28.000 mm"), "no region end at 28 mm in the text log");
    assert!(data.contains("peak predicted C speed 175.0 rpm"), "no 175.0 rpm peak in the text log");
    assert!(data.contains("SYNTHETIC"), "the synthetic roughness must be labelled as such");

    // The same through the main CLI: `fiveaxis replay` forwards to the bridge, and a damaged
    // recording is refused with exit code 2.
    let bad = dir.join("bad.mcap");
    std::fs::write(&bad, b"not an mcap file").unwrap();
    let code = Command::new(env!("CARGO_BIN_EXE_fiveaxis")).arg("replay").arg(&bad).arg("--save").arg(dir.join("bad.rrd")).output().unwrap().status.code();
    assert_eq!(code, Some(2), "an unreadable recording is bad input");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn live_bridge_over_dds_draws_the_node_set() {
    let dir = tmp("live");
    let rrd = dir.join("live.rrd");
    let status = Command::new(Path::new(env!("CARGO_MANIFEST_DIR")).join("launch-free-scripts/paper-demo"))
        .args(["bundled:SING.I", "--speed", "4", "--rrd"])
        .arg(&rrd)
        .env("FIVEAXIS_BIN", bin("fiveaxis").parent().unwrap())
        .env_remove("FIVEAXIS_IN_NETNS")
        .env("RUST_LOG", "warn")
        .status()
        .expect("paper-demo runs");
    assert!(status.success(), "paper-demo --rrd failed: {status}");
    let text = contents(&rrd);
    for e in ENTITIES.iter().filter(|e| !e.starts_with("/roughness")) {
        assert!(text.contains(e), "{e} missing from the live .rrd");
    }
    let data = rerun_cli(&["rrd", "print", "-vvv", rrd.to_str().unwrap()]);
    assert!(data.contains("commanded: region 1 ends at x 28.000 mm"), "the live bridge saw no region ending at 28 mm");
    let _ = std::fs::remove_dir_all(&dir);
}
