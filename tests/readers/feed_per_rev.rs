//! G95, feed per revolution: the path feed is F times the spindle speed S ("V = n * F", SINUMERIK
//! Feeds (V1) §2.1; LinuxCNC: F "units per revolution of the spindle"), figured here by hand.

use super::{cycle_time_s, errors, has};
use fiveaxis::program::{read, Dialect, Program, ReadOptions};

fn feeds(p: &Program, line: usize) -> Vec<(f64, f64)> {
    p.blocks.iter().filter(|b| b.line == line).filter_map(|b| b.feed).map(|f| (f.value_per_min, f.rotary_per_min)).collect()
}

/// F0.2 mm/rev at S300 is 60 mm/min, at S600 120 mm/min (the F kept, the speed changed); a move of
/// C alone at F0.5 deg/rev and S300 turns 150 deg/min, in LinuxCNC, Fanuc and Sinumerik.
#[test]
fn g95_feeds_f_times_the_spindle_speed() {
    for (dialect, name, metric) in [(Dialect::Rs274, "t.ngc", "G21"), (Dialect::Fanuc, "t.nc", "G21"), (Dialect::Sinumerik, "t.mpf", "G71")] {
        let p = read(&format!("{metric} G90 G94 G17\nS300 M3\nG95\nG1 X10. F0.2\nS600\nG1 X20.\nG1 C90. F0.5\nS300\nG1 C0.\nM30\n"), dialect, name, &ReadOptions::default());
        assert!(errors(&p).is_empty(), "{dialect:?}: {:?}", errors(&p));
        assert_eq!(feeds(&p, 4), vec![(60.0, 0.2 * 300.0)], "{dialect:?}");
        assert_eq!(feeds(&p, 6), vec![(120.0, 0.2 * 600.0)], "{dialect:?}");
        assert_eq!(feeds(&p, 9), vec![(0.5 * 300.0, 150.0)], "{dialect:?}");
    }
    // Inches: F0.01 in/rev at S500 is 5 in/min, 127 mm/min.
    let p = read("G20 G90 G94 G17\nS500 M3\nG95\nG1 X1. F0.01\nM30\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let (v, _) = feeds(&p, 4)[0];
    assert!((v - 127.0).abs() < 1e-9, "{v} mm/min");
}

/// The planner runs a G95 move at F times S: 10 mm at 0.2 mm/rev and S300 (60 mm/min) take 10 s,
/// then 10 mm at S600 (120 mm/min) 5 s.
#[test]
fn a_g95_move_takes_its_length_over_f_times_s() {
    let t = cycle_time_s("G21 G90 G94 G17\nG0 X0 Y0 Z0\nS300 M3\nG95\nG1 X10 F0.2\nS600\nG1 X20\nM2\n", "ngc", "generic-bc-table");
    assert!((t - 15.0).abs() < 0.1, "{t} s, want 15");
}

/// What a G95 feed move needs and a control refuses or waits on: an F written under G95 (LinuxCNC
/// zeroes it on G95 and G94; Siemens deletes it on any change of G93/G94/G95), a spindle speed
/// (LinuxCNC: "Cannot feed with zero spindle speed in feed per rev mode"), a spindle turning (the
/// axes follow its turns), and, on Fanuc, an F with its decimal point (without one it may count
/// least increments per revolution).
#[test]
fn a_g95_feed_move_without_its_feed_speed_or_spindle_is_refused() {
    for (dialect, name, metric) in [(Dialect::Rs274, "t.ngc", "G21"), (Dialect::Fanuc, "t.nc", "G21"), (Dialect::Sinumerik, "t.mpf", "G71")] {
        let r = |text: &str| read(&format!("{metric} G90 G94 G17\n{text}"), dialect, name, &ReadOptions::default());
        // The F of G94 is not a feed per revolution, nor the reverse.
        has(&r("S300 M3\nG1 X10. F60.\nG95\nG1 X20.\nM30\n"), 5, 1, "without a feed");
        has(&r("S300 M3\nG95 G1 X10. F0.2\nG94\nG1 X20.\nM30\n"), 5, 1, "without a feed");
        has(&r("M3\nG95\nG1 X10. F0.2\nM30\n"), 4, 1, "Cannot feed with zero spindle speed in feed per rev mode");
        has(&r("S0 M3\nG95\nG1 X10. F0.2\nM30\n"), 4, 1, "Cannot feed with zero spindle speed");
        has(&r("S300\nG95\nG1 X10. F0.2\nM30\n"), 4, 1, "no M3 or M4 has started it");
        has(&r("S300 M3\nG95\nG1 X10. F0.2\nM5\nG1 X20.\nM30\n"), 6, 1, "M5 stopped it");
        // A rapid needs neither.
        assert!(errors(&r("G95\nG0 X10.\nM30\n")).is_empty(), "{dialect:?}");
    }
    let fanuc = |text: &str| read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    has(&fanuc("G21 G90 G94\nS300 M3\nG95 G1 X10. F2\nM30\n"), 3, 13, "F2 without a decimal point under G95");
    assert!(errors(&fanuc("G21 G90 G94\nS300 M3\nG95 G1 X10. F2.\nG94 G1 X20. F2\nM30\n")).is_empty());
    // Haas: G95 is not in the mill manual's pages at hand.
    has(&read("G20 G90 G94\nS300 M3\nG95 G1 X1. F0.01\nM30\n", Dialect::Haas, "t.nc", &ReadOptions::default()), 3, 1, "G95 (feed per revolution): not in the Haas mill manual");
    // Sinumerik's corner feed FRC would be per revolution too: not read.
    let p = read("G71 G90 G94 G17\nS300 M3\nG95 F0.2\nG1 X10. Y0 RND=2 FRC=0.1\nG1 X10. Y10.\nM30\n", Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    assert!(errors(&p).iter().any(|(_, _, m)| m.contains("FRC/FRCM under G95")), "{:?}", errors(&p));
}

/// LinuxCNC's M70/M72 restore G95 with F (` F%.1f`), S (` S%.0f`) and the spindle's M code, as its
/// `restore_settings` writes them: after the restore, F0.2 at S300 feeds 60 mm/min again.
#[test]
fn linuxcncs_m72_restores_g95_with_its_speed_and_spindle() {
    let p = read("G21 G90 G94 G17\nS300 M3\nG95 F0.2\nM70\nG94 F100 S500 M5\nG1 X5\nM72\nG1 X10\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert_eq!(feeds(&p, 6), vec![(100.0, 100.0)]);
    assert_eq!(feeds(&p, 8), vec![(60.0, 0.2 * 300.0)]);
}
