//! RS274NGC's interpreter state read as LinuxCNC keeps it: axis offsets and polar coordinates,
//! rotated coordinate systems, stored positions, the state parameters, the modal state saved and
//! restored, and feeds across unit changes and per revolution; each against LinuxCNC's own output.

use super::*;

/// LinuxCNC's axis offsets and polar coordinates are read to the moves its own interpreter makes of
/// them (`offsets_g92.ngc`, `polar.ngc`; canonical output by make_canon.sh): G92 makes the current
/// point the block's coordinates in every work offset system, G52 sets the offset itself, G92.2 takes
/// it away keeping its parameters for G92.3, G92.1 zeroes them; G10 L20 counts it, G53 does not.
/// `@` is the distance from the origin and `^` the angle from +X, each kept from the current point
/// when left out under G90, added about the origin under G91 (an arc's end too, and canned cycles'
/// holes on each repeat: `polar_cycles.ngc`, after LinuxCNC's own polar demos). Then LinuxCNC's own
/// refusals of polar coordinates and G92's rotary words that this model does not hold.
#[test]
fn rs274_reads_axis_offsets_and_polar_coordinates_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    for name in ["offsets_g92", "polar", "polar_cycles"] {
        let text = std::fs::read_to_string(dir.join(format!("{name}.ngc"))).unwrap();
        same_moves_as_linuxcnc(name, &read(&text, Dialect::Rs274, "t.ngc", &ReadOptions::default()));
    }
    refuses_each(
        Dialect::Rs274,
        &ReadOptions::default(),
        &[
            ("G21 G90 G18\nG1 @10 ^30 F100\nM2\n", "2:4:", "except in G17 plane"),
            ("G21 G90\nG1 X1 @10 ^30 F100\nM2\n", "2:7:", "both polar coordinate and X word"),
            ("G21 G90\nG0 X0 Y0\nG1 @10 F100\nM2\n", "3:4:", "Must specify angle in polar coordinate if at the origin"),
            ("G21 G91\nG0 X0 Y0\nG1 ^10 F100\nM2\n", "3:4:", "G91 motion with polar coordinates is indeterminate"),
            ("G21 G90\nG53 G0 @10 ^0\nM2\n", "2:8:", "with G53"),
            ("G21 G90\nG92 @10 ^0\nM2\n", "2:1:", "polar coordinates (@, ^) in a block whose axis words set an offset"),
            ("G21 G90\nG0 A10\nG92 A0\nM2\n", "3:5:", "G92 A0: rotary-axis offsets are not modelled (this one would be 10.000000 deg)"),
            ("G21 G90\nG10 L2 P1 X1 G92 X0\nM2\n", "2:14:", "two G codes of modal group 0"),
        ],
    );
}

/// Rotated coordinate systems (`G10 L2 Pn R`) are read to where LinuxCNC places the axes
/// (`rotation.ngc`, rs274's output by make_canon.sh placed as its canonical layer does): moves,
/// arcs in XY and XZ, polar coordinates and a canned cycle's holes in a rotated frame; the rotation
/// of a system not in use, then selected; G92 and G10 L20 in a rotated system; the rotation changed
/// while in use under a G92 offset (which LinuxCNC does not turn in as it re-reads the current
/// point); G53's machine X in it; back to an unrotated system; cutter radius compensation in a
/// rotated system (offset in the program frame, then turned). Each move's end point and each XY
/// arc's centre in the workpiece, to rs274's 4 decimals; then LinuxCNC's refusals.
#[test]
fn rs274_reads_rotated_coordinate_systems_as_linuxcnc_does() {
    let ours = fixture_as_linuxcnc("rotation", &ReadOptions::default());
    let close = |a: f64, b: f64| (a - b).abs() <= 2e-4;
    // The rotation turns the frame: a move along the program's X at R30 goes 30 deg off the machine's.
    let b = &ours[1].1;
    assert!(close(b[0], 10.0 + 20.0 * 30f64.to_radians().cos()) && close(b[1], 5.0 + 20.0 * 30f64.to_radians().sin()), "{b:?}");
    refuses_each(
        Dialect::Rs274,
        &ReadOptions::default(),
        &[
            ("G21 G90\nG10 L20 P1 X0 R10\nM2\n", "2:15:", "R not allowed in G10 L20"),
            ("G21 G90\nG10 L2 P1 R10\nG54 G0 X0 Y0\nG41.1 D0\nG53 G1 X5 F100\nM2\n", "5:1:", "machine coordinates (G53) with cutter radius compensation on in a rotated"),
        ],
    );
}

/// `G10 L2` and `L20` under G91 set what they would under G90, as LinuxCNC does ("Being in
/// incremental distance mode has no effect on the action of G10", interp_convert.cc convert_setup):
/// `offsets_g91.ngc` in the system in use, one not in use and rotated, P0, and under a G92 offset,
/// read to where rs274 places the moves (make_canon.sh). Other dialects still refuse it.
#[test]
fn rs274_sets_offsets_under_g91_as_under_g90() {
    let ours = fixture_as_linuxcnc("offsets_g91", &ReadOptions::default());
    // G91 G10 L2 P1 X10 Y2 Z-1, then G90 G1 X0 Y0: the tool at the offset itself, at its Z 3 (-1 + 3).
    let b = &ours[1].1;
    assert!((b[0] - 10.0).abs() < 1e-9 && (b[1] - 2.0).abs() < 1e-9 && (b[2] - 2.0).abs() < 1e-9, "{b:?}");
    refuses_each(Dialect::Fanuc, &ReadOptions::default(), &[("G21 G91\nG10 L2 P1 X5\nM30\n", "2:1:", "G10 L2 under G91")]);
}

/// A rotated system changed in use under a G92 offset leaves LinuxCNC's current X Y apart from where
/// the machine stands (convert_setup reads the point again without the G92 offset turned in), and its
/// next move goes to them whatever axes it names (`rotation_apart.ngc`, against rs274): an X move
/// after a change to an unrotated system moves Y too, and so do a Z move and a move of A alone.
#[test]
fn rs274_moves_to_its_current_point_after_a_rotated_system_changes_under_g92() {
    let ours = fixture_as_linuxcnc("rotation_apart", &ReadOptions::default());
    // G91 G1 X-10 from the machine's Y -5 (10 - 15): Y goes to 0.5806 (rs274's 15.5806 - 15).
    assert!((ours[0].1[1] - -5.0).abs() < 1e-9 && (ours[1].1[1] - 0.5806).abs() < 1e-3, "{ours:?}");
    // G1 Z2 and G1 A15: X and Y move as well.
    for k in [3, 4] {
        assert!((ours[k].1[0] - ours[k - 1].1[0]).abs() > 1.0 && (ours[k].1[1] - ours[k - 1].1[1]).abs() > 1.0, "move {k}: {ours:?}");
    }
}

/// LinuxCNC's moves to a stored position (`home.ngc`, rs274's output by make_canon.sh) on its xyzac-trt
/// sim, whose parameter file starts empty (stored positions 0): `G28 G91 Z0` (the retract CAM posts
/// write), G28 through an absolute intermediate point in a rotated system, under a G92 offset, after
/// `G28.1` stored a position, `G30`, and `G28` alone moving every axis (A and C too); each move's end
/// in the workpiece against rs274's. Then the refusals: a machine file without machine coordinates,
/// G28 with a motion code, axis words with G28.1.
#[test]
fn rs274_moves_to_stored_positions_as_linuxcnc_does() {
    let machine = fiveaxis::machine::Machine::builtin("linuxcnc-xyzac-trt").unwrap();
    let on = ReadOptions::default().on(&machine);
    let ours = fixture_as_linuxcnc("home", &on);
    // G28 G91 Z0 takes Z to the machine's 0, X Y staying: from Z10 in G54 (Z offset -5), Z 0.
    assert!(ours.iter().any(|m| m.0 == Motion::Rapid && m.1[2].abs() < 1e-9 && m.1[3] == 10.0), "{ours:?}");
    for (text, machine, at, needle) in [
        ("G21 G90\nG28 G91 Z0\nM2\n", "hermle-c600u", "2:1:", "places no machine coordinates"),
        ("G21 G90\nG28 G0 Z0\nM2\n", "linuxcnc-xyzac-trt", "2:5:", "two G codes that both use axis words"),
        ("G21 G90\nG28.1 X0\nM2\n", "linuxcnc-xyzac-trt", "2:7:", "axis words are not read with them"),
    ] {
        let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default().on(&fiveaxis::machine::Machine::builtin(machine).unwrap()));
        let (l, c) = at.trim_end_matches(':').split_once(':').unwrap();
        has(&p, l.parse().unwrap(), c.parse().unwrap(), needle);
    }
}

/// LinuxCNC's predefined parameters of the interpreter's state and subroutines' return values read
/// as its interpreter reads them (`state_parameters.ngc`, rs274's output by make_canon.sh): each
/// value is seen in the move it makes, so every move's end and feed is checked against rs274's. The
/// values are those before the line runs (LinuxCNC reads a line whole, then runs it: `G91
/// X[#<_incremental>]` reads 0). Then the state this reader does not hold stays refused.
#[test]
fn rs274_reads_the_interpreters_state_parameters_as_linuxcnc_does() {
    let ours = fixture_as_linuxcnc("state_parameters", &ReadOptions::default());
    // `o<twice> call [5]` returns 10 by `return [#1 * 2]`, in G55 (offset X10 Y5, rotated 30 deg).
    // A parameter number computed (`#[5000 + 420]` is #5420, X where the tool stands) reads the state too.
    let p = read("G21 G90\nG0 X3 Y4\nG1 X[#[5000 + 420] + 1] Y[##<n>] F100\nM2\n".replace("##<n>", "#[5421]").as_str(), Dialect::Rs274, "t.ngc", &ReadOptions::default());
    let ends: Vec<[f64; 2]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1]]).collect();
    assert_eq!(ends, vec![[3.0, 4.0], [4.0, 4.0]], "{:?}", errors(&p));
    let (s, c) = 30f64.to_radians().sin_cos();
    let at = |x: f64, y: f64| [10.0 + x * c - y * s, 5.0 + x * s + y * c];
    assert!(ours.iter().any(|m| { let w = at(10.0, 1.0); (m.1[0] - w[0]).abs() < 1e-9 && (m.1[1] - w[1]).abs() < 1e-9 }), "{ours:?}");
    refuses_each(
        Dialect::Rs274,
        &ReadOptions::default(),
        &[
            ("G21 G90\nG1 X[#<_spindle_on>] F100\nM2\n", "2:6:", "#<_spindle_on> is the interpreter's or the machine's state"),
            ("G21 G90\nG1 X[#5400] F100\nM2\n", "2:6:", "#5400 is a system parameter"),
            ("G21 G90\nG0 X0 Y0\nG41.1 D2\nG1 X[#<_x> + 10] F100\nM2\n", "4:6:", "#<_x> is the interpreter's or the machine's state"),
        ],
    );
}

/// F in a block with G20 or G21 is in the unit before it, and the feed stays what it was across a
/// unit change: LinuxCNC's order of execution sets F (step 4) before the units (step 16), and its
/// task keeps the feed in its own units (emccanon.cc SET_FEED_RATE, GET_EXTERNAL_FEED_RATE), so
/// `#<_feed>` then reads it in the new unit. (Standalone rs274 keeps the number instead, so this is
/// checked against the source, not against it.)
#[test]
fn a_feed_stays_across_a_unit_change_as_linuxcncs_task_keeps_it() {
    let text = "G21 G90 G17\nG0 X0 Y0\nG20 G1 X1 F5\nG1 X2 Y[#<_feed> * 25.4]\nG21 G1 X80\nG1 X[#<_feed>]\nM2\n";
    let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let moves: Vec<(usize, f64, f64, f64)> = p
        .blocks
        .iter()
        .filter(|b| b.motion == Motion::Linear && !b.targets.is_empty())
        .map(|b| (b.line, b.targets.x.unwrap_or(f64::NAN) / MM, b.targets.y.unwrap_or(0.0) / MM, b.feed.map_or(0.0, |f| f.value_per_min)))
        .collect();
    let want = [(3, 25.4, 0.0, 5.0), (4, 50.8, 127.0, 5.0), (5, 80.0, 0.0, 5.0), (6, 5.0, 0.0, 5.0)];
    assert_eq!(moves.len(), want.len(), "{moves:?}");
    for (g, w) in moves.iter().zip(want) {
        assert!(g.0 == w.0 && (g.1 - w.1).abs() < 1e-9 && (g.2 - w.2).abs() < 1e-9 && (g.3 - w.3).abs() < 1e-9, "{g:?}, expected {w:?}");
    }
}

/// LinuxCNC's saved modal state (`M70`-`M73`) is restored as its interpreter restores it
/// (`modal_state.ngc`, rs274's output by make_canon.sh): after an M73 subroutine's endsub and its
/// `return`, and after M72 in the main program, the moves go in the units, distance mode,
/// coordinate system (a rotated one), plane, feed mode and feed (F to 0.1, as LinuxCNC writes it
/// back) and G92 offsets saved; each move's end, XY centre and feed against rs274's. Then the
/// refusals: M72 with nothing saved (or after M71), two codes of its modal group, F in its block.
#[test]
fn rs274_restores_the_modal_state_as_linuxcnc_does() {
    let ours = fixture_as_linuxcnc("modal_state", &ReadOptions::default());
    // The restores are seen: F123.456 comes back as 123.5 mm/min; the inch subroutine's X0.5 is
    // 12.7 mm in G55 (rotated 30 deg), and the next move is in mm again, in G54.
    assert!(ours.iter().any(|m| m.3 == Some(123.5)), "{ours:?}");
    assert!(ours.iter().any(|m| m.0 == Motion::Linear && m.1[0] == 10.0 && m.1[1] == 10.0 && m.3 == Some(500.0)), "{ours:?}");
    refuses_each(
        Dialect::Rs274,
        &ReadOptions::default(),
        &[
            ("G21 G90\nM72\nM2\n", "2:1:", "missing M70/M73"),
            ("G21 G90\nM70\nM71\nM72\nM2\n", "4:1:", "missing M70/M73"),
            ("G21 G90\nM70 M3\nM2\n", "2:5:", "two M codes of modal group 7"),
            ("G21 G90\nM72 F100\nM2\n", "2:5:", "F100 with M72 in one block"),
            // A feed under 0.05 comes back as F0.0 (gen_settings' F%.1f): no feed for the next move.
            ("G21 G90 S1000 M3\nG95 F0.014\nM70\nG91\nM72\nG1 X1\nM2\n", "6:1:", "G01 move without a feed"),
        ],
    );
    // ... a new F after it feeds again (LinuxCNC only refuses a feed move at a feed of zero).
    let p = read("G21 G90 S1000 M3\nG95 F0.014\nM70\nG91\nM72\nF0.02\nG1 X1\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    // M73 in the main program saves as M70 does, and says so (LinuxCNC's warning).
    let p = read("G21 G90\nG0 X5\nM73\nG91\nM72\nG1 X1 F100\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert!(p.diagnostics.iter().any(|d| d.line == 3 && d.message.contains("M73 in the main program")), "{:?}", p.diagnostics);
    assert_eq!(p.blocks.iter().filter_map(|b| b.targets.x).map(|x| x / MM).collect::<Vec<_>>(), vec![5.0, 1.0]);
}

/// `#5599`, LinuxCNC's flag for `(DEBUG,)` output, is the one system parameter a program may set: it
/// moves nothing, reads 1 until set (rs274ngc_pre.cc), and then what was set. rs274 moves this
/// program to X1, X3, then Y4; a system parameter that is the machine's state stays refused.
#[test]
fn linuxcnc_debug_flag_5599_may_be_set() {
    let p = read("G21 G90 F100\nG1 X#5599\n#5599 = 0\nG1 X[#5599 + 3]\n#5599=[2*2]\nG1 Y#5599\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let ends: Vec<[f64; 2]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1]]).collect();
    assert_eq!(ends, [[1.0, 0.0], [3.0, 0.0], [3.0, 4.0]]);
    refuses_each(Dialect::Rs274, &ReadOptions::default(), &[("G21 G90\n#5598 = 1\nM2\n", "2:1:", "#5598 is a system parameter"), ("G21 G90\n#[5599 - 1] = 1\nM2\n", "2:1:", "#5598 is a system parameter")]);
}

/// LinuxCNC's `#<_rpm>` is the S last set ("Return the current value of S, not the actual spindle
/// speed"), 0 before any: LinuxCNC 2.9.8's rs274 runs this program to X0, then X12 after S1200,
/// and `S[#<_rpm>+300]` sets 1500 (Y15), as here.
#[test]
fn linuxcnc_rpm_is_the_s_last_set() {
    let p = read("G21 G90 G17\nG0 X[#<_rpm>] Y0\nS1200 M3\nG1 X[#<_rpm>/100] F100\nS[#<_rpm>+300]\nG1 Y[#<_rpm>/100]\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let ends: Vec<[f64; 2]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1]]).collect();
    let rs274 = [[0.0, 0.0], [12.0, 0.0], [12.0, 15.0]];
    assert_eq!(ends.len(), rs274.len(), "{ends:?}");
    for (e, w) in ends.iter().zip(rs274) {
        assert!((e[0] - w[0]).abs() < 1e-9 && (e[1] - w[1]).abs() < 1e-9, "{ends:?}");
    }
}

/// Feed per revolution as LinuxCNC's interpreter reads it (`feed_per_rev.ngc`, rs274's output by
/// make_canon.sh, each feed move's feed times the spindle speed in force): `G95` with F per turn,
/// S changing the feed, an arc and a move of C alone under it, M70/M72 restoring G95, its F and
/// its S, F per turn in inches, and back to G94. The errors rs274 stops at are ours too.
#[test]
fn rs274_feeds_per_revolution_as_linuxcnc_does() {
    let ours = fixture_as_linuxcnc("feed_per_rev", &ReadOptions::default());
    // 0.2 mm/rev at S300; the move of C alone at 0.5 deg/rev at S600; after M72, 0.5 at S250.
    let feeds: Vec<f64> = ours.iter().filter_map(|m| m.3).collect();
    assert!(feeds.contains(&60.0) && feeds.contains(&300.0) && feeds.contains(&125.0), "{feeds:?}");
    // rs274: "Cannot do g1 with zero feed rate" after G94, "Cannot feed with zero spindle speed in
    // feed per rev mode" without S.
    refuses_each(
        Dialect::Rs274,
        &ReadOptions::default(),
        &[
            ("G21 G90\nS300 M3\nG95\nG1 X10 F0.2\nG94\nG1 X30\nM2\n", "6:1:", "without a feed"),
            ("G21 G90\nM3\nG95\nG1 X10 F0.2\nM2\n", "4:1:", "Cannot feed with zero spindle speed in feed per rev mode"),
        ],
    );
}
