//! The `fiveaxis` binary as users and CI call it: exit codes, JSON keys, damaged input.

use crate::common;
use std::process::Command;

fn fiveaxis(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("FIVEAXIS_EXE")).args(args).current_dir(env!("FIVEAXIS_ROOT")).output().unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stdout).into(), String::from_utf8_lossy(&out.stderr).into())
}

fn json(args: &[&str]) -> (i32, serde_json::Value) {
    let (code, out, err) = fiveaxis(args);
    let v = serde_json::from_str(&out).unwrap_or_else(|e| panic!("not JSON ({e}): {out}\n{err}"));
    (code, v)
}

#[test]
fn analyze_json_has_the_documented_keys() {
    let (code, v) = json(&["program", "analyze", "recordings/programs/SING.I", "--json"]);
    assert_eq!(code, 0);
    for key in ["peak_c_speed_rpm", "peak_c_speed_x_mm", "min_singularity_distance_deg", "c_max_rpm", "regions", "diagnostics"] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert!((v["peak_c_speed_rpm"].as_f64().unwrap() - 175.0).abs() < 0.05);
    assert!((v["c_max_rpm"].as_f64().unwrap() - 25.0).abs() < 1e-9);
    let r = &v["regions"][0];
    for key in ["x_start_mm", "x_end_mm", "peak_c_speed_rpm"] {
        assert!(r.get(key).is_some(), "region misses {key}");
    }
    assert!((r["x_start_mm"].as_f64().unwrap() - 22.0).abs() < 1e-6);
}

#[test]
fn damaged_program_exits_2_naming_every_defect_and_still_analyzes() {
    let (code, v) = json(&["program", "analyze", "recordings/programs/damaged/SING_ocr.I", "--json"]);
    assert_eq!(code, 2);
    let d = v["diagnostics"].as_array().unwrap();
    let errors: Vec<_> = d.iter().filter(|d| d["severity"] == "error").collect();
    assert_eq!(errors.len(), 4, "{errors:#?}");
    assert!(errors.iter().any(|e| e["line"] == 52 && e["column"] == 27));
    // What the good blocks allow: the same figures as the clean program.
    assert!((v["peak_c_speed_rpm"].as_f64().unwrap() - 175.0).abs() < 0.05);
    let (code, out, err) = fiveaxis(&["program", "analyze", "recordings/programs/damaged/NON_SING_ocr.I"]);
    assert_eq!(code, 2);
    assert!(out.contains("NON_SING_ocr.I:65:24: error"), "{out}");
    assert!(err.contains("defect"), "{err}");
}

#[test]
fn builtin_paths_and_feed_override() {
    let (code, v) = json(&["program", "analyze", "builtin:paper-sing", "--json"]);
    assert_eq!(code, 0);
    assert!((v["peak_c_speed_rpm"].as_f64().unwrap() - 199.0).abs() < 0.05);
    // eq. 5 is linear in the feed: half the feed, half the C speed.
    let (_, half) = json(&["program", "analyze", "builtin:paper-sing", "--feed", "1000", "--json"]);
    assert!((half["peak_c_speed_rpm"].as_f64().unwrap() - 99.5).abs() < 0.05);
}

#[test]
fn unreadable_input_and_bad_flags_exit_2() {
    let (code, _, err) = fiveaxis(&["program", "analyze", "no/such/file.I"]);
    assert_eq!(code, 2);
    assert!(err.contains("no/such/file.I"), "{err}");
    let (code, _, err) = fiveaxis(&["program", "analyze", "builtin:paper-sing", "--feed=-5"]);
    assert_eq!(code, 2);
    assert!(err.contains("--feed"), "{err}");
    let (code, _, err) = fiveaxis(&["program", "analyze", "builtin:paper-sing", "--machine", "nope"]);
    assert_eq!(code, 2);
    assert!(err.contains("unknown machine"), "{err}");
}

#[test]
fn a_program_without_moves_exits_2_not_0() {
    // A gate that read nothing never passes: an empty Sinumerik file, a comment-only RS274 file, a
    // Klartext program whose only move is refused.
    let dir = common::scratch_dir("nomoves");
    let files = [("empty.mpf", ""), ("comments.ngc", "(only a comment)\n; and another\n"), ("refused.h", "0 BEGIN PGM R MM\n1 L X+5 RL F100\n2 END PGM R MM\n")];
    for (name, text) in files {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        for cmd in [&["program", "analyze"][..], &["run"][..]] {
            let mut args = cmd.to_vec();
            let p = path.display().to_string();
            args.push(&p);
            let (code, out, err) = fiveaxis(&args);
            assert_eq!(code, 2, "{name} {cmd:?}: {out}{err}");
            assert!(out.contains("no moves") || err.contains("no moves"), "{name} {cmd:?}: {out}{err}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn demo_runs_the_bundled_programs() {
    let (code, out, _) = fiveaxis(&["demo"]);
    assert_eq!(code, 0);
    assert!(out.contains("bundled:SING.I") && out.contains("175.0") && out.contains("199.0"), "{out}");
}

/// The three remedies share their JSON shape: `before` and `after` with the figures a user compares.
#[test]
fn remedies_print_before_and_after_as_json_and_refuse_what_they_cannot_treat() {
    let runs: [&[&str]; 3] = [
        &["avoid", "reorient", "bundled:SING.I", "--json"],
        &["avoid", "smooth", "bundled:SING.I", "--tool", "ball:3", "--json"],
        &["avoid", "refine", "builtin:semi-cylinder", "--json"],
    ];
    for args in runs {
        let (code, v) = json(args);
        assert_eq!(code, 0, "{args:?}");
        for side in ["before", "after"] {
            for key in ["peak_c_speed_rpm", "min_singularity_distance_deg", "cycle_time_s", "time_lost_s", "max_orientation_deviation_deg"] {
                assert!(v[side][key].is_number(), "{args:?}: {side}.{key} missing in {v}");
            }
        }
        assert!(v["after"]["peak_c_speed_rpm"].as_f64().unwrap() < 25.0, "{args:?}: {v}");
        assert!(v["after"]["time_lost_s"].as_f64().unwrap() < v["before"]["time_lost_s"].as_f64().unwrap(), "{args:?}: {v}");
    }
    let (code, _, err) = fiveaxis(&["avoid", "smooth", "bundled:SING.I", "--tool", "flat:3"]);
    assert_eq!(code, 2);
    assert!(err.contains("ball-end"), "{err}");
    let (code, _, err) = fiveaxis(&["avoid", "smooth", "bundled:SING.I", "--tool", "ball"]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn a_closed_stdout_ends_the_cli_quietly() {
    // `fiveaxis program analyze ... | head -1`: the reader goes away after the first line. The CLI
    // ends by SIGPIPE as Unix tools do, not by a panic in println! (exit 101, "failed printing to
    // stdout: Broken pipe", as before).
    use std::os::unix::process::ExitStatusExt;
    // The pipe's read end is closed before the CLI starts: its first write meets a closed pipe.
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let out = std::process::Command::new(env!("FIVEAXIS_EXE"))
        .args(["program", "analyze", "bundled:SING.I", "--json"])
        .stdout(writer)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked") && !stderr.contains("Broken pipe"), "{stderr}");
    assert_eq!(out.status.signal(), Some(13), "{:?}: {stderr}", out.status);
}

/// A 3+2 program turns C only in its positioning rapid, at the Hermle's C limit (25 rpm, its
/// machine file): the finite-difference peak says so apart from the feed moves', which turn nothing,
/// and where; eq. (5) asks nothing of C on the path.
#[test]
fn a_rapid_turning_the_axis_is_told_apart_from_the_feed_moves() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("r.h");
    std::fs::write(&path, "0 BEGIN PGM R MM\n1 L X+0 Y+0 Z+50 A+0 C+0 FMAX\n2 L A+30 C+180 FMAX\n3 L X+10 F500\n4 L Y+10\n5 END PGM R MM\n").unwrap();
    let p = path.to_str().unwrap();
    let (code, v) = json(&["program", "analyze", p, "--json"]);
    assert_eq!(code, 0, "{v}");
    assert!(v["peak_c_speed_rpm"].as_f64().unwrap() < 0.05, "{v}");
    assert!(v["peak_c_speed_fd_feed_rpm"].as_f64().unwrap() < 0.05, "{v}");
    let rapid = &v["peak_c_speed_fd_rapid"];
    assert!((rapid["rpm"].as_f64().unwrap() - 25.0).abs() < 0.25, "{rapid}");
    assert_eq!(rapid["line"], 3);
    let (_, out, _) = fiveaxis(&["program", "analyze", p]);
    assert!(out.contains("0.0 rpm on feed moves; 25.0 rpm on a rapid (N2, line 3)"), "{out}");
}
