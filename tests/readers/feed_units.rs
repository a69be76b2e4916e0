//! What F means for a move: degrees per minute on the rotary axes alone, Sinumerik's G70 and G700,
//! no feed after a change of feed mode, and FANUC's rotary feeds with and without tool-centre-point
//! control, each timed against the manuals' rule worked here.

use super::*;

/// F on a move of the rotary axes alone is in degrees per minute whatever the length unit (LinuxCNC's
/// SET_FEED_RATE: the angular feed is FROM_PROG_ANG(rate), no inch conversion): `G1 B45` at F60 takes
/// 45 s under G20 as under G21, where the inch feed had been read as 1524 deg/min (1.77 s). A linear
/// move at F60 under G20 covers 60 in a minute: X1 (1 in) in 1 s. Sinumerik's G70 is the geometry's
/// unit only ("Feedrate functions are not affected by G70/G71", 840Di sl Programming Manual
/// 6FC5398-1BP10): X1 at F60 is 25.4 mm at 60 mm/min, 25.4 s, on a metric basic system; G700 makes F
/// inch/min (1 s), as G70 does on an inch basic system (the machine file's `inch_basic_system`).
#[test]
fn a_rotary_feed_is_in_degrees_and_sinumeriks_g70_leaves_f_alone() {
    for (unit, want) in [("G21", 45.0), ("G20", 45.0)] {
        let t = cycle_time_s(&format!("{unit} G90 G94 G17\nG1 X0 F60\nG1 B45\nM2\n"), "ngc", "generic-bc-table");
        assert!((t - want).abs() < 0.05, "{unit}: {t} s");
    }
    let t = cycle_time_s("G20 G90 G94 G17\nG1 X0 Y0 Z0 F60\nG1 X1\nM2\n", "ngc", "generic-bc-table");
    assert!((t - 1.0).abs() < 0.05, "G20 X1 at F60: {t} s");
    for (code, want) in [("G70", 25.4), ("G700", 1.0), ("G71", 1.0)] {
        let t = cycle_time_s(&format!("{code} G90 G94 G17\nG1 X0 Y0 Z0 F60\nG1 X1\nM30\n"), "mpf", "generic-bc-table");
        assert!((t - want).abs() < 0.05 * want.max(1.0), "{code}: {t} s, want {want}");
    }
    // On an inch basic system G70 reads F in inch/min.
    let machine = format!("inch_basic_system = true\n{}", fiveaxis::machine::builtin_file("generic-bc-table").unwrap());
    let path = std::env::temp_dir().join(format!("fiveaxis-inch-basic-{}.toml", std::process::id()));
    std::fs::write(&path, machine).unwrap();
    let t = cycle_time_s("G70 G90 G94 G17\nG1 X0 Y0 Z0 F60\nG1 X1\nM30\n", "mpf", path.to_str().unwrap());
    std::fs::remove_file(&path).ok();
    assert!((t - 1.0).abs() < 0.05, "G70 on an inch basic system: {t} s");
}

/// A change of feed mode leaves no feed (Siemens: "In the event of switching between G93, G94 and
/// G95, the path feedrate value has to be reprogrammed"; LinuxCNC sets it to 0 on every G94): a G1
/// after `G93 ... F6` and `G94` without a new F is refused, not run at "6 mm/min".
#[test]
fn a_change_of_feed_mode_leaves_no_feed() {
    for (dialect, name, metric) in [(Dialect::Rs274, "t.ngc", "G21"), (Dialect::Fanuc, "t.nc", "G21"), (Dialect::Sinumerik, "t.mpf", "G71")] {
        let p = read(&format!("{metric} G90 G94 G17\nG1 X10. F60.\nG93 G1 X20. F6.\nG94 G1 X30.\nM30\n"), dialect, name, &ReadOptions::default());
        has(&p, 4, 1, "without a feed");
        let p = read(&format!("{metric} G90 G94 G17\nG1 X10. F60.\nG93 G1 X20. F6.\nG94 G1 X30. F60.\nM30\n"), dialect, name, &ReadOptions::default());
        assert!(errors(&p).is_empty(), "{dialect:?}: {:?}", errors(&p));
    }
    // Fanuc's inverse-time F without a decimal point counts thousandths ("F1 -> 0.001", FANUC 16/18-C
    // MC Operator's Manual, inverse time feed), as its lengths do; with one it is the number.
    let p = read("G21 G90 G94 G17\nG1 X10. F60.\nG93 G1 X20. F6\nG1 X30. F6.\nM30\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let frn: Vec<f64> = p.blocks.iter().filter(|b| (3..=4).contains(&b.line)).filter_map(|b| b.feed).map(|f| f.value_per_min).collect();
    assert_eq!(frn, vec![0.006, 6.0]);
    // LinuxCNC: even a G94 in G94 mode leaves the feed 0.
    has(&read_rs274("G21 G90 G94\nG1 X10 F60\nG94 G1 X20\nM2\n"), 3, 1, "without a feed");
    assert!(errors(&read("G21 G90 G94\nG1 X10. F60.\nG94 G1 X20.\nM30\n", Dialect::Fanuc, "t.nc", &ReadOptions::default())).is_empty());
}

/// FANUC under G43.4 feeds a move of the rotary axes alone (the tool tip standing on the workpiece) at
/// F or at the maximum cutting feedrate, as parameter No. 19696 bit 6 RFC says (A-79348E: "0: The
/// maximum cutting feedrate (parameter No. 1422). 1: A specified feedrate."): refused unless the
/// machine file gives `tcp_rotary_feed = "programmed"`, which times it at F in deg/min (B30 C90 at
/// F500: sqrt(30^2 + 90^2) / 500 min); "max-cutting" stays refused (parameter 1422 is not modelled).
/// A move of the tip with the rotaries is read either way.
#[test]
fn fanuc_rotary_moves_alone_under_g43_4_follow_parameter_rfc() {
    use fiveaxis::path::{PathOptions, Trajectory};
    let nmv = fiveaxis::machine::builtin_file("mori-seiki-nmv5000").unwrap();
    let text = "%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z150. B0. C0.\nG43.4 H1\nG01 X0. Y0. Z120. F500.\nB30. C90.\nX10. B20. C80.\nG49\nM30\n%\n";
    let unset = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    let e = errors(&read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&unset)));
    assert!(e.len() == 1 && e[0].0 == 7 && e[0].2.contains("parameter No. 19696 bit 6 RFC"), "{e:?}");
    let max = fiveaxis::machine::Machine::from_toml_str(&format!("tcp_rotary_feed = \"max-cutting\"\n{nmv}"), "t").unwrap();
    let e = errors(&read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&max)));
    assert!(e.len() == 1 && e[0].0 == 7 && e[0].2.contains("parameter No. 1422"), "{e:?}");
    let programmed = fiveaxis::machine::Machine::from_toml_str(&format!("tcp_rotary_feed = \"programmed\"\n{nmv}"), "t").unwrap();
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&programmed));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let t = Trajectory::from_program(&p, &programmed, &PathOptions::default());
    let time: f64 = t.segments.iter().filter(|s| s.line == 7).map(|s| s.duration).sum();
    let expect = (30f64.powi(2) + 90f64.powi(2)).sqrt() / 500.0 * 60.0;
    assert!((time - expect).abs() < 1e-9, "{time} s, not {expect} s");
    // G43.5: a new tool vector with the tip standing is the same move; the same vector again moves nothing.
    let g435 = "%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z150. B0. C0.\nG43.5 H1\nG01 X0. Y0. Z120. I0. J0. K1. F500.\nI0. J0. K1.\nI0.5 J0. K0.866\nG49\nM30\n%\n";
    let e = errors(&read(g435, Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&unset)));
    assert!(e.len() == 1 && e[0].0 == 8 && e[0].2.contains("RFC"), "{e:?}");
    let bad = fiveaxis::machine::Machine::from_toml_str(&format!("tcp_rotary_feed = \"fast\"\n{nmv}"), "t").unwrap_err().to_string();
    assert!(bad.contains("tcp_rotary_feed") && bad.contains("RFC"), "{bad}");
}

/// Fanuc without tool-centre-point control: a move of linear and rotary axes together takes F along a
/// path whose rotary part counts degrees as millimetres (FANUC B-63174EN §4.2, "G91 G01 X20.0 C40.0
/// F300.0 ... time = sqrt(20^2 + 40^2) / 300 = 0.14907 min"): `G1 X10. B30.` at F60 takes
/// sqrt(10^2 + 30^2) s = 31.62 s, where LinuxCNC and Siemens give F to X (10 s, B following).
#[test]
fn fanuc_counts_degrees_in_the_path_of_a_combined_move() {
    let fanuc = cycle_time_s("%\nO1000\nG21 G90 G94 G17\nG1 X0. Y0. Z0. B0. F60.\nG1 X10. B30.\nM30\n%\n", "nc", "mori-seiki-nmv5000");
    let want = (10.0f64.powi(2) + 30.0f64.powi(2)).sqrt();
    assert!((fanuc - want).abs() < 0.1, "Fanuc: {fanuc} s, want {want}");
    let linuxcnc = cycle_time_s("G21 G90 G94 G17\nG1 X0 Y0 Z0 B0 F60\nG1 X10 B30\nM2\n", "ngc", "generic-bc-table");
    assert!((linuxcnc - 10.0).abs() < 0.1, "LinuxCNC: {linuxcnc} s");
}
