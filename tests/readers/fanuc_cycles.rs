//! Fanuc's and Haas' reference returns and machine coordinates (`G28`, `G53`) on a machine whose
//! file places them, and their drilling cycles as the controls' manuals say: `G80` with a reference
//! return, PS0045, Haas' shrinking pecks, Q kept as modal cycle data.

use super::*;

/// Fanuc's reference returns and machine coordinates on a machine whose file places them: `G91 G28
/// Z0` goes straight up to the reference point, `G28 X10 Y0` (G90) through the intermediate point,
/// `G53 G0 Z-5` to 5 mm below the machine zero; a number without a decimal point is in thousandths
/// of a mm (`X1500` is 1.5 mm); the leader before `%` is skipped; Fanuc's G04 P is milliseconds.
#[test]
fn fanuc_reference_returns_and_decimal_points() {
    let machine = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    let text = "NX listing header\nDate : today\n%\nO0001\nG21 G90 G17 G40\nG91 G28 Z0.\nG90 G0 X1500 Y2. Z3.\nG28 X10. Y0.\nG53 G0 Z-5.\nG04 P250\nM30\n%\ntrailer text\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&machine));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let zero = machine.machine_coordinates.as_ref().unwrap().zero;
    let pts = end_points(&p);
    let mm = |v: f64| v * 1e3;
    // Z to the machine zero (program = machine point + zero, G54 taken as zero).
    assert_eq!(pts[0].0, Motion::Rapid);
    assert!((pts[0].1[2] - mm(zero.z)).abs() < 1e-9, "{pts:?}");
    assert!((pts[1].1[0] - 1.5).abs() < 1e-12 && (pts[1].1[1] - 2.0).abs() < 1e-12);
    // G28 X10 Y0: the intermediate point, then X and Y to the reference (Z stays).
    assert_eq!(&pts[2].1[..3], &[10.0, 0.0, 3.0]);
    assert!((pts[3].1[0] - mm(zero.x)).abs() < 1e-9 && (pts[3].1[1] - mm(zero.y)).abs() < 1e-9 && (pts[3].1[2] - 3.0).abs() < 1e-9, "{pts:?}");
    assert!((pts[4].1[2] - (mm(zero.z) - 5.0)).abs() < 1e-9);
    assert_eq!(p.blocks.iter().filter_map(|b| b.dwell_s).collect::<Vec<_>>(), [0.25]);
    assert!(p.diagnostics.iter().any(|d| d.line == 1 && d.message.contains("leader")));
    // Fanuc's P takes no decimal point; a peck cycle needs the machine's d.
    let p = read("%\nG21 G90\nG04 P1.5\n", Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&machine));
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 3 && m.contains("milliseconds")), "{:?}", errors(&p));
    let bare = fiveaxis::machine::builtin_file("mori-seiki-nmv5000").unwrap().replace("g83_clearance_mm = 0.1\n", "");
    let bare = fiveaxis::machine::Machine::from_toml_str(&bare, "t").unwrap();
    let p = read("%\nG21 G90 F100\nG0 Z10.\nG83 X0 Y0 Z-5. R1. Q2.\n", Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&bare));
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 4 && m.contains("No. 5115")), "{:?}", errors(&p));
    // Without machine coordinates, G28 cannot be placed.
    let p = read("%\nG21 G91 G28 Z0.\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 2 && m.contains("machine_coordinates")), "{:?}", errors(&p));
}

/// `G80 G91 G28 Z0.`, as NX's posts end a drilling operation: G80 (the motion group) ends the cycle
/// and G28 (group 0) takes the axis words, in one block (LinuxCNC's enhance_block refuses axis words
/// with G80 unless a group 0 code takes them; FANUC puts G80 in group 09 and G28 in group 00). The
/// moves after it are rapids, not holes, on Fanuc, Haas and LinuxCNC, and with G53 as with G28.
#[test]
fn g80_with_a_reference_return_ends_the_cycle() {
    let machine = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    // On Fanuc and Haas the motion group keeps its G00 under the cycle (group 09): `G90 Z30.` after
    // G80 is a rapid. LinuxCNC's G80 is of the motion group itself: its next move names G0.
    let body = "G21 G90 G17\nG0 X10. Y10. Z20.\nG98 G81 X10. Y10. Z-2. R2. F100.\nX20.\nG80 G91 G28 Z0.\nG90 Z30.\nX40. Y40.\n";
    for (dialect, text) in [
        (Dialect::Fanuc, format!("%\nO1000\n{body}M30\n%\n")),
        (Dialect::Haas, format!("%\nO1000\n{body}M30\n%\n")),
        (Dialect::Rs274, format!("%\n{}M2\n%\n", body.replace("G90 Z30.", "G90 G0 Z30."))),
        (Dialect::Fanuc, format!("%\nO1000\n{}M30\n%\n", body.replace("G80 G91 G28 Z0.", "G80 G53 Z0."))),
        (Dialect::Haas, format!("%\nO1000\n{}M30\n%\n", body.replace("G80 G91 G28 Z0.", "G80 G53 Z0."))),
    ] {
        let p = read(&text, dialect, "t.nc", &ReadOptions::default().on(&machine));
        assert!(errors(&p).is_empty(), "{dialect:?}: {:?}", errors(&p));
        let pts = end_points(&p);
        // Two holes: one feed move each, to Z-2 at X10 and X20.
        let feeds: Vec<[f64; 6]> = pts.iter().filter(|(m, _)| *m == Motion::Linear).map(|(_, at)| *at).collect();
        assert!(feeds.len() == 2 && feeds.iter().all(|at| (at[2] + 2.0).abs() < 1e-9) && (feeds[1][0] - 20.0).abs() < 1e-9, "{dialect:?}: {pts:?}");
        // Then up to the reference (or machine zero), to Z30, and to X40 Y40 by rapids only.
        let (m, last) = pts.last().unwrap();
        assert!(*m == Motion::Rapid && (last[0] - 40.0).abs() < 1e-9 && (last[1] - 40.0).abs() < 1e-9 && (last[2] - 30.0).abs() < 1e-9, "{dialect:?}: {pts:?}");
    }
}

/// FANUC's alarm PS0045 ADDRESS Q NOT FOUND (G73/G83) is "not specified by address Q, or Q0 is
/// specified" (its alarm list): named for a peck cycle without Q or with Q0, not for a negative Q or
/// a cycle that does not peck, nor on Haas (whose pages say no alarm). Each is refused either way.
#[test]
fn fanuc_names_ps0045_where_its_alarm_list_says() {
    let machine = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    let head = "%\nO1000\nG21 G90 G94 G17\nG0 X0. Y0. Z10.\n";
    // (dialect, cycle blocks, the line refused, PS0045 named)
    for (dialect, cycle, at, named) in [
        (Dialect::Fanuc, "G83 X0. Y0. Z-5. R1. Q0. F100.", 5, true),
        (Dialect::Fanuc, "G73 X0. Y0. Z-5. R1. F100.", 5, true),
        (Dialect::Fanuc, "G83 X0. Y0. Z-5. R1. Q-2. F100.", 5, false),
        // Q is modal cycle data a G81 keeps without using: the G83 after it takes its Q0.
        (Dialect::Fanuc, "G81 X0. Y0. Z-5. R1. Q0. F100.\nG83 X1.", 6, true),
        (Dialect::Haas, "G83 X0. Y0. Z-5. R1. Q0. F100.", 5, false),
    ] {
        let p = read(&format!("{head}{cycle}\nG80\nM30\n%\n"), dialect, "t.nc", &ReadOptions::default().on(&machine));
        let e = errors(&p);
        assert!(e.len() == 1 && e[0].0 == at, "{dialect:?} {cycle}: {e:?}");
        assert_eq!(e[0].2.contains("PS0045"), named, "{dialect:?} {cycle}: {e:?}");
        if dialect == Dialect::Fanuc && cycle.contains("Q-2") {
            assert!(e[0].2.contains("Negative values are ignored"), "{e:?}");
        }
    }
}

/// Haas' G83 with I J K (Mill Operator's Manual 96-8000, G83: "The first pass will cut in by I, each
/// succeeding cut will be reduced by amount J, and the minimum cutting depth is K"): from R1 to Z-10
/// with I3 J1 K1.5 the pecks are 3, 2, 1.5, 1.5, 1.5 and the last 0.5, so the feeds end at -2, -4,
/// -5.5, -7, -8.5 and -10 (worked by hand); the next hole of the cycle pecks alike. I, J and K go
/// together, not with Q, I and K positive.
#[test]
fn a_haas_g83_with_i_j_k_pecks_less_each_pass() {
    let machine = fiveaxis::machine::Machine::builtin("haas-umc-750").unwrap();
    let text = "%\nO1000\nG21 G90 G94 G17\nG0 X0. Y0. Z10.\nG98 G83 X0. Y0. Z-10. R1. I3. J1. K1.5 F100.\nX5.\nG80\nM30\n%\n";
    let p = read(text, Dialect::Haas, "t.nc", &ReadOptions::default().on(&machine));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    for line in [5, 6] {
        let feeds: Vec<f64> = p.blocks.iter().filter(|b| b.line == line && b.motion == Motion::Linear).filter_map(|b| b.targets.z.map(|z| (z / MM * 1e6).round() / 1e6)).collect();
        assert_eq!(feeds, [-2.0, -4.0, -5.5, -7.0, -8.5, -10.0], "line {line}: {:#?}", p.blocks);
    }
    for (cycle, col, needle) in [
        ("G83 X0. Y0. Z-10. R1. I3. J1. F100.", 23, "I, J and K go together"),
        ("G83 X0. Y0. Z-10. R1. Q2. I3. J1. K1. F100.", 23, "either a fixed peck Q or a shrinking one"),
        ("G83 X0. Y0. Z-10. R1. I0. J1. K1. F100.", 23, "must be positive"),
    ] {
        let p = read(&format!("%\nO1000\nG21 G90 G94 G17\nG0 X0. Y0. Z10.\n{cycle}\nG80\nM30\n%\n"), Dialect::Haas, "t.nc", &ReadOptions::default().on(&machine));
        has(&p, 5, col, needle);
    }
}

/// A G81 (or G82, G85, G86, G89) does not use Q: FANUC keeps it as modal cycle data ("Q ... is modal
/// information in a canned cycle, and is also used to specify a depth of cut with G73 and G83",
/// Series 15i-MA Operator's Manual), so a post's `Q0.` on a G81 drills the one plunge G81 makes:
/// to R at rapid, to Z at the feed, back to the initial level (G98) at rapid.
#[test]
fn a_fanuc_g81_keeps_q_without_using_it() {
    let machine = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    for (dialect, q) in [(Dialect::Fanuc, "Q0."), (Dialect::Fanuc, "Q-2."), (Dialect::Haas, "Q0.")] {
        let text = format!("%\nO1000\nG21 G90 G94 G17\nG0 X0. Y0. Z10.\nG98 G81 X3. Y4. Z-5. R1. {q} F100.\nG80\nM30\n%\n");
        let p = read(&text, dialect, "t.nc", &ReadOptions::default().on(&machine));
        assert!(errors(&p).is_empty(), "{dialect:?} {q}: {:?}", errors(&p));
        let z: Vec<(f64, bool)> = p.blocks.iter().filter(|b| b.line == 5).filter_map(|b| b.targets.z.map(|z| ((z / MM * 1e6).round() / 1e6, b.motion == Motion::Rapid))).collect();
        assert_eq!(z, [(1.0, true), (-5.0, false), (10.0, true)], "{dialect:?} {q}: {:#?}", p.blocks);
    }
}

/// G76's shift at the bottom is Q, and Q is modal cycle data: a G76 after a G83 Q2. without G80
/// between takes that shift, which is not modelled, so it is refused; after G80 (which cancels the
/// cycle and its data) the same G76 has no shift and reads.
#[test]
fn a_fanuc_g76_refuses_the_shift_an_earlier_q_left() {
    let machine = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    let head = "%\nO1000\nG21 G90 G94 G17\nG0 X0. Y0. Z10.\nG98 G83 X0. Y0. Z-5. R1. Q2. F100.\n";
    let kept = read(&format!("{head}G76 X5. Z-5. R1.\nG80\nM30\n%\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&machine));
    let e = errors(&kept);
    assert!(e.len() == 1 && e[0].0 == 6 && e[0].2.contains("Q2 kept from an earlier cycle block"), "{e:?}");
    let cancelled = read(&format!("{head}G80\nG76 X5. Z-5. R1.\nG80\nM30\n%\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&machine));
    assert!(errors(&cancelled).is_empty(), "{:?}", errors(&cancelled));
}
