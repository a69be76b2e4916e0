//! Exact stop and exact path: where a program says so, the simulated machine stops at a block's end
//! instead of blending into the next block. LinuxCNC's G61.1 (exact stop) and G61 (exact path: a stop
//! wherever the next block turns away, G-code reference §G61), Fanuc's and Haas' G61 (modal) and G09
//! (one block) ("the tool is decelerated at the end point of a block, then an in-position check is
//! made", FANUC B-64484EN "Exact stop"), Sinumerik's G60 (modal) and G9 (one block: "the motion
//! decelerates to a stop at the end of the block", Programming Manual Fundamentals); G64 blends again,
//! and so does Fanuc's G62 (inner-corner override, which acts under cutter compensation only).
//! A dwell of 0 s (`G4 P0`, `G04 P0`) stops the machine as any dwell does (LinuxCNC's task drains
//! the motion queue before a dwell), and so does Sinumerik's preprocessing stop `STOPRE` (the
//! blocks after it are prepared only once it is executed: the motion before it runs out to a stop).

use fiveaxis::machine::Machine;
use fiveaxis::path::{PathOptions, Trajectory};
use fiveaxis::planner::{plan_each, PlanConfig};
use fiveaxis::program::{read, Dialect, ReadOptions, Severity};

/// The simulated machine's slowest X speed (mm/min) while X is within 0.05 mm of `at_mm`.
fn slowest_near(text: &str, dialect: Dialect, at_mm: f64) -> f64 {
    let machine = Machine::hermle_c600u();
    let p = read(text, dialect, "t", &ReadOptions::default());
    assert!(p.diagnostics.iter().all(|d| d.severity != Severity::Error), "{dialect:?} {text:?}: {:#?}", p.diagnostics);
    let traj = Trajectory::from_program(&p, &machine, &PathOptions::default());
    let mut samples: Vec<(f64, [f64; 5])> = Vec::new();
    plan_each(&traj.segments, &machine, &PlanConfig::default(), |s| {
        samples.push((s.t, s.q));
        true
    });
    samples
        .windows(2)
        .filter(|w| (w[0].1[0] * 1e3 - at_mm).abs() < 0.05)
        .map(|w| (w[1].1[0] - w[0].1[0]).hypot(w[1].1[1] - w[0].1[1]) / (w[1].0 - w[0].0) * 60e3)
        .fold(f64::INFINITY, f64::min)
}

/// X0 -> X10 -> X20 -> X30 at 600 mm/min: with an exact stop at X10 (X20) the machine stands there;
/// blending, it passes at the feed. Each dialect's codes: the modal ones stop every block until G64,
/// the one-block forms only their block.
#[test]
fn exact_stop_codes_stop_the_machine_at_the_block_end() {
    let cases: [(Dialect, &str, (bool, bool)); 17] = [
        (Dialect::Rs274, "G21 G90 G94\nG0 X0 Y0 Z10\nG1 X10 F600\nX20\nX30\nM2\n", (false, false)),
        (Dialect::Rs274, "G21 G90 G94\nG0 X0 Y0 Z10\nG61.1\nG1 X10 F600\nX20\nX30\nM2\n", (true, true)),
        (Dialect::Rs274, "G21 G90 G94\nG0 X0 Y0 Z10\nG61.1\nG1 X10 F600\nG64\nX20\nX30\nM2\n", (true, false)),
        (Dialect::Rs274, "G21 G90 G94\nG0 X0 Y0 Z10\nG61.1\nG64\nG1 X10 F600\nX20\nX30\nM2\n", (false, false)),
        (Dialect::Fanuc, "%\nO0001\nG21 G90 G94\nG0 X0 Y0 Z10.\nG61\nG1 X10. F600.\nX20.\nX30.\nM30\n%\n", (true, true)),
        (Dialect::Fanuc, "%\nO0001\nG21 G90 G94\nG0 X0 Y0 Z10.\nG09 G1 X10. F600.\nX20.\nX30.\nM30\n%\n", (true, false)),
        (Dialect::Fanuc, "%\nO0001\nG21 G90 G94\nG0 X0 Y0 Z10.\nG1 X10. F600.\nX20.\nX30.\nM30\n%\n", (false, false)),
        // G62 (inner-corner override, of G61's group) ends G61: without cutter compensation, as G64.
        (Dialect::Fanuc, "%\nO0001\nG21 G90 G94\nG0 X0 Y0 Z10.\nG61\nG1 X10. F600.\nG62 X20.\nX30.\nM30\n%\n", (true, false)),
        (Dialect::Haas, "%\nO0001\nG21 G90 G94\nG0 X0 Y0 Z10.\nG61\nG1 X10. F600.\nX20.\nX30.\nM30\n%\n", (true, true)),
        (Dialect::Haas, "%\nO0001\nG21 G90 G94\nG0 X0 Y0 Z10.\nG61\nG64\nG1 X10. F600.\nX20.\nX30.\nM30\n%\n", (false, false)),
        (Dialect::Sinumerik, "G90 G71\nG0 X0 Y0 Z10\nG60\nG1 X10 F600\nX20\nX30\nM30\n", (true, true)),
        (Dialect::Sinumerik, "G90 G71\nG0 X0 Y0 Z10\nG1 G9 X10 F600\nX20\nX30\nM30\n", (true, false)),
        (Dialect::Sinumerik, "G90 G71\nG0 X0 Y0 Z10\nG60\nG64\nG1 X10 F600\nX20\nX30\nM30\n", (false, false)),
        // Zero dwells and the preprocessing stop: a stop at X10 only.
        (Dialect::Rs274, "G21 G90 G94\nG0 X0 Y0 Z10\nG1 X10 F600\nG4 P0\nX20\nX30\nM2\n", (true, false)),
        (Dialect::Fanuc, "%\nO0001\nG21 G90 G94\nG0 X0 Y0 Z10.\nG1 X10. F600.\nG04 P0\nX20.\nX30.\nM30\n%\n", (true, false)),
        (Dialect::Sinumerik, "G90 G71\nG0 X0 Y0 Z10\nG1 X10 F600\nG4 F0\nX20\nX30\nM30\n", (true, false)),
        (Dialect::Sinumerik, "G90 G71\nG0 X0 Y0 Z10\nG1 X10 F600\nSTOPRE\nX20\nX30\nM30\n", (true, false)),
    ];
    for (dialect, text, (at_10, at_20)) in cases {
        for (x, stops) in [(10.0, at_10), (20.0, at_20)] {
            let slowest = slowest_near(text, dialect, x);
            if stops {
                assert!(slowest < 1.0, "{dialect:?} {text:?}: {slowest} mm/min at X{x}, expected a stop");
            } else {
                assert!(slowest > 590.0, "{dialect:?} {text:?}: {slowest} mm/min at X{x}, expected the feed");
            }
        }
    }
}

/// LinuxCNC's G61 (exact path) runs colinear blocks on at the feed and stops where the next block
/// turns away, even by 1 deg, which G64 blends (the planner splines through corners up to 30 deg).
#[test]
fn exact_path_stops_only_where_the_path_turns() {
    let colinear = "G21 G90 G94\nG0 X0 Y0 Z10\nG61\nG1 X10 F600\nX20\nM2\n";
    let turned = "G21 G90 G94\nG0 X0 Y0 Z10\nG61\nG1 X10 F600\nX20 Y0.174551\nM2\n"; // 1 deg
    assert!(slowest_near(colinear, Dialect::Rs274, 10.0) > 590.0, "colinear under G61");
    assert!(slowest_near(turned, Dialect::Rs274, 10.0) < 1.0, "1 deg under G61");
    assert!(slowest_near(&turned.replace("G61\n", "G64\n"), Dialect::Rs274, 10.0) > 500.0, "1 deg under G64");
    // The reader says how its exact path differs from LinuxCNC's planner.
    let p = read(turned, Dialect::Rs274, "t", &ReadOptions::default());
    assert!(p.diagnostics.iter().any(|d| d.line == 3 && d.severity == Severity::Warning && d.message.contains("G61 (exact path)")), "{:#?}", p.diagnostics);
}

/// `STOPRE` stands in a block of its own: with anything else it is refused where it stands.
#[test]
fn stopre_with_other_words_is_refused_where_it_stands() {
    let p = read("G90 G71\nG0 X0 Y0 Z10\nG1 X10 F600 STOPRE\nX20\nM30\n", Dialect::Sinumerik, "t", &ReadOptions::default());
    let errors: Vec<_> = p.diagnostics.iter().filter(|d| d.severity == Severity::Error).map(|d| (d.line, d.column, d.message.as_str())).collect();
    assert_eq!(errors, [(3, 13, "STOPRE: the preprocessing stop stands in a block of its own")], "{:#?}", p.diagnostics);
}
