//! The planner on dense CAM output and the bound on a program's duration (issue: hours-long programs).
//!
//! - `avoid refine bundled:SING.I` writes ~4,500 blocks, 4,099 of them tiny rotary-only moves: the
//!   look-ahead planner blends through them (no stop per block), so the refined program simulates within
//!   10 % of the original's cycle time, and an independent check (numpy finite differences at a wider
//!   stencil than the planner's, tests/peer/limit_check.py) finds every axis within its velocity,
//!   acceleration and jerk limits on the recorded simulated JointState stream.
//! - A feed typo (`F0.01` over 50 mm, 83 h) is refused with its line and column by `program analyze`,
//!   `run` and the commander node inside a 500 MB address-space limit; a CL file with a zero feed too.

mod common;

use fiveaxis::machine::Machine;
use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_fiveaxis")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fiveaxis-lookahead-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn cycle_time(program: &Path, mcap: Option<&Path>) -> f64 {
    let mut cmd = Command::new(bin());
    cmd.arg("run").arg(program).arg("--json");
    if let Some(m) = mcap {
        cmd.arg("--mcap").arg(m);
    }
    let out = cmd.output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    v["simulated"]["cycle_time_s"].as_f64().unwrap()
}

#[test]
fn refined_sing_blends_through_its_short_blocks_within_the_axis_limits() {
    let refined = tmp("refined.I");
    let st = Command::new(bin()).args(["avoid", "refine", "bundled:SING.I", "--out"]).arg(&refined).output().unwrap();
    assert!(st.status.success(), "{}", String::from_utf8_lossy(&st.stderr));
    let blocks = std::fs::read_to_string(&refined).unwrap().lines().filter(|l| l.contains("G01")).count();
    assert!(blocks > 4000, "the refined program has {blocks} moves");

    let original = tmp("SING.I");
    std::fs::write(&original, include_str!("../recordings/programs/SING.I")).unwrap();
    let mcap = tmp("refined.mcap");
    let t_refined = cycle_time(&refined, Some(&mcap));
    let t_original = cycle_time(&original, None);
    assert!((t_refined / t_original - 1.0).abs() <= 0.10, "refined {t_refined:.2} s against SING.I {t_original:.2} s");

    // Independent limit check on the recorded simulated stream (SI units, REP 103).
    let m = Machine::hermle_c600u();
    let limits = m.limits();
    let mut cmd = Command::new("python3");
    cmd.arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/peer/limit_check.py")).arg(&mcap).arg("/fiveaxis/simulated/joint_states");
    for (axis, l) in m.axes.iter().zip(limits.iter()) {
        cmd.arg(format!("{}={},{},{}", axis.name, l.velocity, l.acceleration, l.jerk));
    }
    let out = cmd.output().expect("python3 runs (numpy and mcap-ros2-support come from launch-free-scripts/test)");
    assert!(out.status.success(), "{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let duration = v["duration_s"].as_f64().unwrap();
    assert!((duration - t_refined).abs() < 0.01, "the check read {duration} s of the {t_refined} s run");
    assert_eq!(v["joints"].as_object().unwrap().len(), 5, "{v}");
    for (k, what) in ["velocity", "acceleration", "jerk"].iter().enumerate() {
        let r = v["worst"][k].as_f64().unwrap();
        // 1e-3: the finite differences of positions rounded by the recording's f64 CDR are exact to
        // far better; the planner's own bound is exactly 1 on the jerk filter's ramps.
        assert!(r <= 1.0 + 1e-3 && r > 0.01, "{what} ratio {r} ({v})");
    }
}

/// Runs `cmd` under a 500 MB address-space limit; returns (exit code, stdout + stderr).
fn limited(cmd: &str) -> (i32, String) {
    let out = Command::new("sh").arg("-c").arg(format!("ulimit -v 512000; exec {cmd}")).output().unwrap();
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    (out.status.code().unwrap_or(-1), text)
}

#[test]
fn a_feed_typo_is_refused_with_its_place_inside_500_mb() {
    let typo = tmp("typo.ngc");
    std::fs::write(&typo, "G21 G90\nG1 X50 F0.01\nM2\n").unwrap();
    let zero = tmp("zero.cl");
    std::fs::write(&zero, "0 0 0 0 0 1 1000\n1 0 0 0 0 1 0\n").unwrap();
    let commander = Path::new(bin()).parent().unwrap().join("fiveaxis-commander");
    let mut cases = vec![
        (format!("'{}' program analyze '{}'", bin(), typo.display()), "typo.ngc:2:1"),
        (format!("'{}' run '{}'", bin(), typo.display()), "typo.ngc:2:1"),
        (format!("'{}' program analyze '{}'", bin(), zero.display()), "zero.cl:2:"),
        (format!("'{}' run '{}'", bin(), zero.display()), "zero.cl:2:"),
    ];
    // The commander refuses before it opens DDS (so no network namespace is needed for it).
    assert!(commander.exists(), "fiveaxis-commander is built beside fiveaxis by `cargo test --workspace`");
    cases.push((format!("'{}' '{}' --wait-for-subscriber-s 0", commander.display(), typo.display()), "typo.ngc:2:1"));
    for (cmd, place) in cases {
        let (code, text) = limited(&cmd);
        assert_eq!(code, 2, "{cmd}: {text}");
        assert!(text.contains(place), "{cmd} names {place}: {text}");
        assert!(!text.contains("panicked") && !text.contains("memory allocation"), "{cmd}: {text}");
    }
    let (_, text) = limited(&format!("'{}' program analyze '{}'", bin(), typo.display()));
    assert!(text.contains("83.3 h") && text.contains("24.0 h"), "{text}");
    // The bound is the user's: raised, the same program is accepted (and would stream 300 M samples:
    // not run here).
    let help = Command::new(bin()).args(["program", "analyze", "--help"]).output().unwrap();
    assert!(String::from_utf8_lossy(&help.stdout).contains("--max-program-hours"));
}


/// The planner evaluates its splines along increasing path length with the last knot interval as a
/// hint: whatever the hint, the interval is the one bisection finds (the last knot at or before `t`,
/// clamped to the first and last interval), and the value is the spline's there. Random knots with
/// near-duplicates (dropped by the fit), parameters on knots, between them and outside.
#[test]
fn a_hinted_knot_search_finds_the_interval_bisection_finds() {
    use fiveaxis::singularity::CubicSpline;
    let mut rng = common::Rng(0x5eed_0017);
    for case in 0..300 {
        let n = 2 + (rng.next() * 40.0) as usize;
        let mut xs = Vec::with_capacity(n);
        let mut x = rng.range(-1.0, 1.0);
        for _ in 0..n {
            xs.push(x);
            x += if rng.next() < 0.1 { 1e-13 } else { rng.range(1e-6, 0.5) };
        }
        let ys: Vec<f64> = xs.iter().map(|_| rng.range(-3.0, 3.0)).collect();
        let spline = CubicSpline::natural(&xs, &ys);
        let knots = spline.knots().to_vec();
        let m = knots.len();
        for _ in 0..50 {
            let t = match (rng.next() * 3.0) as usize {
                0 => knots[(rng.next() * m as f64) as usize % m],
                1 => rng.range(knots[0] - 0.5, knots[m - 1] + 0.5),
                _ => rng.range(knots[0], knots[m - 1]),
            };
            let bisected = knots.iter().rposition(|&k| k <= t).unwrap_or(0).min(m.saturating_sub(2));
            for hint in [0, (rng.next() * (m + 3) as f64) as usize, bisected.saturating_sub(1), bisected, bisected + 1, usize::MAX] {
                let i = spline.interval(t, hint);
                assert_eq!(i, bisected, "case {case}: t {t} hint {hint} knots {knots:?}");
                assert_eq!(spline.value_on(i, t).to_bits(), spline.value(t).to_bits(), "case {case}: t {t}");
            }
        }
    }
}
