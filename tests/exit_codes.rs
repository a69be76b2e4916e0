//! Every exit code of every `fiveaxis` command (issue 16): 0 done, 1 a threshold violated (or the
//! command itself failed: `fiveaxis-rerun` missing), 2 bad input (usage, unreadable or invalid input,
//! a program with defects, an output that cannot be written). Each case also checks that stderr
//! names the reason, so a code is never right by accident.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("FIVEAXIS_ROOT"))
}

/// Run `exe` with `args` from the repository; exit code and stderr.
fn run_exe(exe: &Path, args: &[&str]) -> (i32, String) {
    let out = Command::new(exe).args(args).current_dir(root()).output().unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).into())
}

/// `fiveaxis ARGS` exits with `code` and says `why` on stderr (empty: no reason to check, code 0).
fn expect(args: &[&str], code: i32, why: &str) {
    let (got, err) = run_exe(Path::new(env!("FIVEAXIS_EXE")), args);
    assert_eq!(got, code, "fiveaxis {}: {err}", args.join(" "));
    assert!(err.contains(why), "fiveaxis {}: stderr does not say '{why}': {err}", args.join(" "));
}

fn tmp(name: &str) -> PathBuf {
    common::scratch_path("exit-codes", name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A recording of `program` run in process (as `fiveaxis run --mcap` writes it).
fn recording(program: &str, name: &str) -> PathBuf {
    let path = tmp(name);
    expect(&["run", program, "--mcap", s(&path)], 0, "recorded");
    path
}

/// An output path in a directory that does not exist.
fn unwritable(name: &str) -> PathBuf {
    tmp("no-such-dir").join("deeper").join(name)
}

#[test]
fn usage_errors_exit_2_for_every_command() {
    for cmd in [&["program", "analyze"][..], &["run"], &["analyze"], &["mcap", "recover"], &["roughness", "synthesize"], &["avoid", "reorient"], &["avoid", "smooth"], &["avoid", "refine"], &["machine", "show"], &["machine", "urdf"], &["demo", "--no-such-flag"], &["machine", "list", "extra"], &["no-such-command"]] {
        let (code, err) = run_exe(Path::new(env!("FIVEAXIS_EXE")), cmd);
        assert_eq!(code, 2, "fiveaxis {cmd:?}: {err}");
        assert!(err.contains("Usage") || err.contains("usage"), "fiveaxis {cmd:?}: {err}");
    }
    // --help documents the codes.
    let out = Command::new(env!("FIVEAXIS_EXE")).arg("--help").output().unwrap();
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && help.contains("Exit codes: 0") && help.contains("2 bad input"), "{help}");
}

#[test]
fn program_analyze_exits_0_or_2() {
    expect(&["program", "analyze", "bundled:SING.I"], 0, "");
    expect(&["program", "analyze", "no/such/file.I"], 2, "no/such/file.I");
    expect(&["program", "analyze", "recordings/programs/damaged/SING_ocr.I"], 2, "defect");
    expect(&["program", "analyze", "bundled:SING.I", "--machine", "no-such-machine"], 2, "unknown machine");
    expect(&["program", "analyze", "bundled:SING.I", "--period-ms", "0"], 2, "--period-ms");
    expect(&["program", "analyze", "bundled:SING.I", "--max-c-speed-rpm=-1"], 2, "--max-c-speed-rpm");
}

#[test]
fn run_exits_0_1_or_2() {
    expect(&["run", "bundled:NON_SING.I"], 0, "");
    expect(&["run", "no/such/file.I"], 2, "no/such/file.I");
    expect(&["run", "recordings/programs/damaged/NON_SING_ocr.I"], 2, "defect");
    expect(&["run", "bundled:NON_SING.I", "--feed", "0"], 2, "--feed");
    expect(&["run", "bundled:NON_SING.I", "--mcap", s(&unwritable("run.mcap"))], 2, "no-such-dir");
    // --rrd needs fiveaxis-rerun: a copy of fiveaxis with no bridge beside it and none on the PATH
    // fails itself (1), naming what it could not run.
    let lone = common::scratch_dir("exit-codes-lone");
    let exe = lone.join("fiveaxis");
    std::fs::copy(env!("FIVEAXIS_EXE"), &exe).unwrap();
    let rrd = tmp("run.rrd");
    let out = Command::new(&exe).args(["run", "bundled:NON_SING.I", "--rrd", s(&rrd)]).env("PATH", s(&lone)).current_dir(root()).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("fiveaxis-rerun"), "{err}");
}

#[test]
fn analyze_exits_0_1_or_2() {
    let sing = recording("bundled:SING.I", "sing.mcap");
    let nonsing = recording("bundled:NON_SING.I", "nonsing.mcap");
    // SING asks up to 175 rpm of the 25 rpm table; NON_SING stays far below it.
    expect(&["analyze", s(&nonsing), "--max-c-speed-rpm", "25"], 0, "");
    expect(&["analyze", s(&sing), "--max-c-speed-rpm", "25"], 1, "");
    expect(&["analyze", s(&sing), "--min-distance-deg", "5"], 1, "");
    expect(&["analyze", "no/such/recording.mcap"], 2, "no/such/recording.mcap");
    expect(&["analyze", s(&nonsing), "--max-c-speed-rpm", "0"], 2, "--max-c-speed-rpm");
    expect(&["analyze", s(&nonsing), "--min-distance-deg=-2"], 2, "--min-distance-deg");
    expect(&["analyze", s(&nonsing), "--machine", "no-such-machine"], 2, "unknown machine");
    expect(&["analyze", s(&nonsing), "--json", s(&unwritable("report.json"))], 2, "no-such-dir");
    // A truncated recording is damaged input: 2, with the report of what was readable.
    let bytes = std::fs::read(&nonsing).unwrap();
    let cut = tmp("truncated.mcap");
    std::fs::write(&cut, &bytes[..bytes.len() * 2 / 3]).unwrap();
    expect(&["analyze", s(&cut)], 2, "damaged");
    // Several recordings: the worst code of theirs.
    expect(&["analyze", s(&nonsing), s(&sing), "--max-c-speed-rpm", "25"], 1, "");
    expect(&["analyze", s(&nonsing), s(&cut), s(&sing), "--max-c-speed-rpm", "25"], 2, "damaged");
}

#[test]
fn mcap_recover_exits_0_or_2() {
    let nonsing = recording("bundled:NON_SING.I", "nonsing-recover.mcap");
    expect(&["mcap", "recover", s(&nonsing), s(&tmp("recovered.mcap"))], 0, "");
    let not_mcap = tmp("not.mcap");
    std::fs::write(&not_mcap, b"this is not an MCAP file").unwrap();
    expect(&["mcap", "recover", s(&not_mcap), s(&tmp("recovered2.mcap"))], 2, "not.mcap");
    expect(&["mcap", "recover", "no/such/input.mcap", s(&tmp("recovered3.mcap"))], 2, "no/such/input.mcap");
}

#[test]
fn roughness_synthesize_exits_0_or_2() {
    expect(&["roughness", "synthesize", "--out", s(&tmp("profile.csv"))], 0, "");
    expect(&["roughness", "synthesize", "--program", "no/such/file.I", "--out", s(&tmp("p2.csv"))], 2, "no/such/file.I");
    expect(&["roughness", "synthesize", "--out", s(&unwritable("profile.x3p"))], 2, "no-such-dir");
}

#[test]
fn avoid_commands_exit_0_or_2() {
    expect(&["avoid", "reorient", "bundled:SING.I", "--out", s(&tmp("reoriented.I"))], 0, "");
    expect(&["avoid", "reorient", "bundled:SING.I", "--max-tilt-deg", "0"], 2, "--max-tilt-deg");
    expect(&["avoid", "smooth", "bundled:SING.I", "--tool", "ball:3"], 0, "");
    expect(&["avoid", "smooth", "bundled:SING.I", "--tool", "flat:3"], 2, "ball-end");
    expect(&["avoid", "smooth", "recordings/programs/damaged/SING_ocr.I", "--tool", "ball:3"], 2, "defects");
    expect(&["avoid", "refine", "builtin:semi-cylinder"], 0, "");
    expect(&["avoid", "refine", "builtin:semi-cylinder", "--out", s(&unwritable("r.I"))], 2, "no-such-dir");
    expect(&["avoid", "refine", "builtin:no-such-path"], 2, "no-such-path");
    expect(&["avoid", "refine", "builtin:semi-cylinder", "--machine", "no-such-machine"], 2, "unknown machine");
    // A program's contour tolerance (cycle 32) is written where the dialect has a form for it
    // (RS274NGC: LinuxCNC's G64 P, the linear part); elsewhere the written program would run under
    // the control's own, so writing is refused rather than the tolerance dropped.
    let tolerant = tmp("tolerant.h");
    let sing = include_str!("../recordings/programs/twins/SING_tnc.h");
    let cycle = "\n64 CYCL DEF 32.0 TOLERANCE\n64 CYCL DEF 32.1 T0.02\n65 L M128\n";
    std::fs::write(&tolerant, sing.replacen("\n65 L M128\n", cycle, 1)).unwrap();
    expect(&["avoid", "refine", s(&tolerant)], 0, "");
    expect(&["avoid", "refine", s(&tolerant), "--out", s(&tmp("tolerant.I"))], 2, "contour tolerance cannot be written in Heidenhain");
    expect(&["avoid", "smooth", s(&tolerant), "--tool", "ball:3", "--out", s(&tmp("tolerant.I"))], 2, "contour tolerance cannot be written in Heidenhain");
    // Refused before the jig search (which takes minutes in a debug build), not after it.
    expect(&["avoid", "reorient", s(&tolerant), "--out", s(&tmp("tolerant.I"))], 2, "contour tolerance cannot be written in Heidenhain");
    // LinuxCNC's SING with G64 P0.02: written back as G64 P0.0200 (the same tolerance read back).
    let blended = tmp("blended.ngc");
    let ngc = include_str!("../recordings/machine/linuxcnc/SING.ngc");
    assert_eq!(ngc.matches(" G64 G92.1").count(), 1);
    std::fs::write(&blended, ngc.replacen(" G64 G92.1", " G64 P0.02 G92.1", 1)).unwrap();
    let written = tmp("blended_refined.ngc");
    expect(&["avoid", "refine", s(&blended), "--m-code", "428=tcp-on", "--m-code", "429=tcp-off", "--out", s(&written)], 0, "");
    let text = std::fs::read_to_string(&written).unwrap();
    assert!(text.lines().any(|l| l.ends_with(" G64 P0.0200")), "{text}");
}

#[test]
fn machine_commands_exit_0_or_2() {
    expect(&["machine", "list"], 0, "");
    expect(&["machine", "show", "hermle-c600u"], 0, "");
    expect(&["machine", "show", "no-such-machine"], 2, "unknown machine");
    expect(&["machine", "urdf", "hermle-c600u", "--out", s(&tmp("hermle.urdf"))], 0, "");
    expect(&["machine", "urdf", "no-such-machine"], 2, "unknown machine");
    expect(&["machine", "urdf", "hermle-c600u", "--out", s(&unwritable("h.urdf"))], 2, "no-such-dir");
}

#[test]
fn replay_passes_the_bridge_code_and_fails_without_it() {
    let bridge = Path::new(env!("FIVEAXIS_EXE")).with_file_name("fiveaxis-rerun");
    assert!(bridge.exists(), "{} is built by launch-free-scripts/test (cargo build --workspace --bins)", bridge.display());
    let nonsing = recording("bundled:NON_SING.I", "nonsing-replay.mcap");
    expect(&["replay", s(&nonsing), "--save", s(&tmp("replay.rrd"))], 0, "");
    expect(&["replay", "no/such/recording.mcap", "--save", s(&tmp("replay2.rrd"))], 2, "no/such/recording.mcap");
    let lone = common::scratch_dir("exit-codes-lone-replay");
    let exe = lone.join("fiveaxis");
    std::fs::copy(env!("FIVEAXIS_EXE"), &exe).unwrap();
    let out = Command::new(&exe).args(["replay", s(&nonsing)]).env("PATH", s(&lone)).current_dir(root()).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("fiveaxis-rerun"), "{err}");
}

#[test]
fn demo_exits_0() {
    expect(&["demo", "--json"], 0, "");
}

/// The nodes and the Rerun bridge share `--machine` (fiveaxis::args::MachineArgs) and its exit code:
/// an unknown machine is bad input, exit 2 naming it, before anything joins the DDS graph.
#[test]
fn nodes_and_the_bridge_refuse_an_unknown_machine_with_exit_2() {
    let dir = Path::new(env!("FIVEAXIS_EXE")).parent().unwrap();
    let cases: [(&str, &[&str]); 5] = [
        ("fiveaxis-commander", &["bundled:SING.I", "--machine", "no-such-machine"]),
        ("fiveaxis-simulator", &["bundled:SING.I", "--machine", "no-such-machine"]),
        ("fiveaxis-monitor", &["--machine", "no-such-machine"]),
        ("fiveaxis-rerun", &["live", "--machine", "no-such-machine"]),
        ("fiveaxis-rerun", &["replay", "recordings/no.mcap", "--machine", "no-such-machine"]),
    ];
    for (exe, args) in cases {
        let path = dir.join(exe);
        assert!(path.exists(), "{} is built by launch-free-scripts/test", path.display());
        let (code, err) = run_exe(&path, args);
        assert_eq!(code, 2, "{exe} {args:?}: {err}");
        assert!(err.contains("unknown machine 'no-such-machine'"), "{exe} {args:?}: {err}");
    }
}

/// A four-axis machine (the Deckel DMC 75V, one rotary axis): `program analyze` and `run` read its
/// program (exit 0); what names five axes is refused, exit 2 saying so, before it reads or joins
/// anything: a recording (`run --mcap`, `analyze`), `avoid`, the nodes and the Rerun bridge.
#[test]
fn a_four_axis_machine_is_read_and_refused_where_five_axes_are_named() {
    let program = tmp("four-axis.h");
    std::fs::write(&program, "0 BEGIN PGM F MM\n1 TOOL CALL 1 Z S1000\n2 L X+0 Y+0 Z+100 A+0 R0 FMAX M3\n3 L A-90 FMAX\n4 L X+10 Y-20 Z+50 FMAX\n5 L X+60 F500\n6 L A-60 F2000\n7 L Z+100 FMAX\n8 END PGM F MM\n").unwrap();
    let m = ["--machine", "deckel-dmc-75v"];
    let out = Command::new(env!("FIVEAXIS_EXE")).args(["program", "analyze", s(&program)]).args(m).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("(four-axis: one rotary axis, A; no singular orientation)"));
    expect(&["run", s(&program), m[0], m[1]], 0, "");
    let refused = "is a four-axis machine (one rotary axis, no singular orientation)";
    expect(&["run", s(&program), m[0], m[1], "--mcap", s(&tmp("four-axis.mcap"))], 2, refused);
    expect(&["analyze", "recordings/no.mcap", m[0], m[1]], 2, refused);
    expect(&["avoid", "refine", "builtin:semi-cylinder", m[0], m[1]], 2, refused);
    let dir = Path::new(env!("FIVEAXIS_EXE")).parent().unwrap();
    let cases: [(&str, &[&str]); 4] = [
        ("fiveaxis-commander", &["bundled:SING.I", m[0], m[1]]),
        ("fiveaxis-simulator", &["bundled:SING.I", m[0], m[1]]),
        ("fiveaxis-monitor", &m),
        ("fiveaxis-rerun", &["live", m[0], m[1]]),
    ];
    for (exe, args) in cases {
        let (code, err) = run_exe(&dir.join(exe), args);
        assert_eq!(code, 2, "{exe} {args:?}: {err}");
        assert!(err.contains(refused), "{exe} {args:?}: {err}");
    }
}
