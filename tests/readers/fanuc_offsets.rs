//! Fanuc's G92 (the work coordinate system set where the tool stands, every system shifted alike)
//! and G52 (a local coordinate system in every work system), and Haas' G92, against their rules
//! worked by hand: the current point reads the G92 block's values; G52's origin is the point it
//! names in the work system; G92 cancels G52 on the axes it names (Haas Mill Operator's Manual,
//! G92; SINUMERIK ISO Milling 04.07 §3.1 and Mitsubishi M700V §14.10-14.11 for the FANUC dialect).

use super::*;

fn close(got: &[[f64; 3]], want: &[[f64; 3]]) {
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!((0..3).all(|i| (g[i] - w[i]).abs() < 1e-9), "move {k}: {g:?}, the rule {w:?}; all {got:?}");
    }
}

/// G54 at X100 Y50 (G10 L2 P1), G55 at X300: `G92 X0 Y0` where the tool stands at G54 X10 Y20
/// (offset-free X110 Y70) puts the new zero there, in G55 too (all systems move in parallel);
/// `G52 X5` adds a local origin 5 mm on; `G92 X1` cancels G52 on X only; `G52 X0 Y0` ends it.
#[test]
fn fanuc_g92_and_g52_move_every_work_system() {
    let text = "%\nO1000\nG21 G90 G17 G94\nG10 L2 P1 X100. Y50. Z0.\nG10 L2 P2 X300. Y0. Z0.\nG54 G0 X10. Y20. Z5.\nG92 X0. Y0.\nG1 X2. Y3. F500.\nG55 G1 X0. Y0.\nG54 G52 X5. Y-4.\nG1 X0. Y0.\nG92 X1.\nG1 X2. Y1.\nG52 X0. Y0.\nG1 X0. Y0.\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    // The shift G92 makes: the point (110, 70) reads (0, 0) in G54 (100, 50): (10, 20) in every system.
    let shift = [10.0, 20.0];
    let want = [
        [110.0, 70.0, 5.0],                           // G54 X10 Y20
        [100.0 + shift[0] + 2.0, 50.0 + shift[1] + 3.0, 5.0], // X2 Y3 after G92
        [300.0 + shift[0], 0.0 + shift[1], 5.0],      // G55 X0 Y0: G55 shifted alike
        [100.0 + shift[0] + 5.0, 50.0 + shift[1] - 4.0, 5.0], // G54 G52 X5 Y-4, X0 Y0: the local origin
        // G92 X1 at (115, 66): X reads 1 there, G52 gone on X (shift X 14); Y keeps G52's -4.
        [115.0 + 1.0, 50.0 + shift[1] - 4.0 + 1.0, 5.0],
        // G52 X0 Y0: X's local is already gone; Y's -4 ends.
        [100.0 + 14.0, 50.0 + shift[1], 5.0],
    ];
    close(&ends(&p), &want);
}

/// Haas: G92 shifts every system alike (Setting 33 FANUC, the default); G52 is Haas' own code with
/// no manual page in reach and stays refused.
#[test]
fn haas_g92_shifts_and_its_g52_is_refused() {
    let text = "%\nO1000\nG20 G90 G17 G94\nG54 G0 X1. Y2. Z0.5\nG92 X0. Y0.\nG1 X0.5 Y0.5 F20.\nM30\n%\n";
    let p = read(text, Dialect::Haas, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let inch = 25.4;
    close(&ends(&p), &[[1.0 * inch, 2.0 * inch, 0.5 * inch], [1.5 * inch, 2.5 * inch, 0.5 * inch]]);
    let p = read("%\nG21 G90 G0 X1. Y2. Z3.\nG52 X5.\nM30\n%\n", Dialect::Haas, "t.nc", &ReadOptions::default());
    has(&p, 3, 1, "G52");
}

/// What no manual in reach settles is refused at the word: G92 or G52 under G91, under G43.4, under
/// a canned cycle; a rotary-axis shift; G92.1 with a shift set; G28 with a local system set.
#[test]
fn fanuc_offsets_refuse_what_their_rules_leave_open() {
    let machine = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    let on = ReadOptions::default().on(&machine);
    refuses_each(
        Dialect::Fanuc,
        &on,
        &[
            ("%\nG21 G91 G0 X1.\nG92 X0.\n", "3:1:", "G92 under G91"),
            ("%\nG21 G90 G0 X1.\nG91 G52 X5.\n", "3:5:", "G52 under G91"),
            ("%\nG21 G90 G0 X1. Y1. Z50.\nG43.4 H1\nG92 X0.\n", "4:1:", "under tool centre point control"),
            ("%\nG21 G90 G0 X1. Y1. Z50.\nG99 G81 X0. Y0. Z-5. R2. F100.\nG92 X0. Y0.\n", "4:1:", "G92 under a canned cycle"),
            ("%\nG21 G90 G0 X1. B10.\nG92 B0.\n", "3:5:", "rotary-axis offsets are not modelled"),
            ("%\nG21 G90 G0 X1.\nG92 X0.\nG92.1 X0.\n", "4:1:", "G92.1 with a G92 or G52 offset set"),
            ("%\nG21 G90 G0 X1.\nG52 X5.\nG91 G28 Z0.\n", "4:5:", "local coordinate system (G52) set"),
            ("%\nG21 G90 G0 X1.\nG92\n", "3:1:", "G92 without an axis word"),
        ],
    );
    // With nothing shifted, G92.1 has nothing to preset and its X0 is no move; a G28 after
    // G52 X0 Y0 Z0 is read: X stays at 1 through both.
    let p = read("%\nG21 G90 G0 X1.\nG92.1 X0.\nG52 X5.\nG52 X0.\nG91 G28 Z0.\nM30\n%\n", Dialect::Fanuc, "t.nc", &on);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let moves = ends(&p);
    assert_eq!(moves.len(), 2, "G0 X1. and G28's move to the reference point only: {moves:?}");
    assert!(moves.iter().all(|m| (m[0] - 1.0).abs() < 1e-9), "{moves:?}");
    // G92 takes where the tool stands: before any move has placed an axis, the program does not
    // say where that is (the classic opening G92 X200. Y100. Z50. assumes the operator's position).
    refuses_each(
        Dialect::Fanuc,
        &on,
        &[
            ("%\nG21 G90\nG92 X200. Y100. Z50.\n", "3:5:", "no move before it placed X"),
            ("%\nG21 G90 G0 Z50.\nG92 X0. Z0.\n", "3:5:", "no move before it placed X"),
            ("%\nG21 G91 G0 X10.\nG90\nG92 X0.\n", "4:5:", "no move before it placed X"),
            ("%\nG21 G90 G0 X1.\nG10 L2 P0 X5.\n", "3:8:", "external workpiece zero offset"),
            ("%\nG21 G90 G0 X1.\nG92.2 X3.\n", "3:7:", "expected IP0"),
        ],
    );
}

/// Fanuc's `G54.1 Pn` offsets are the operator's, taken as zero, whichever system was active before
/// (`G55` here), and a `G10 L2 P1` under `G54.1` sets G54 without moving the origin in use.
#[test]
fn fanuc_g54_1_stays_at_zero_after_g55_and_g10() {
    let text = "%\nG21 G90 G17 G94\nG10 L2 P1 X100. Y0. Z0.\nG10 L2 P2 X300. Y0. Z0.\nG55 G0 X0. Y0. Z10.\nG54.1 P1\nG0 X0.\nG10 L2 P1 X50.\nG0 X1.\nG54 G0 X0.\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    close(&ends(&p), &[[300.0, 0.0, 10.0], [0.0, 0.0, 10.0], [1.0, 0.0, 10.0], [50.0, 0.0, 10.0]]);
}

/// `G54.1 P1` (its offset the operator's, taken as zero) and back to `G54`: the same system number
/// as before, but the program's own G54 offset (G10 L2 P1 X100) applies again; a G92 shift set
/// under G54.1 stays in G54 (every system shifts alike).
#[test]
fn fanuc_g54_after_g54_1_takes_its_offset_again() {
    let text = "%\nG21 G90 G17 G94\nG10 L2 P1 X100. Y0. Z0.\nG54.1 P1\nG0 X0. Y0. Z10.\nG92 X-5.\nG54 G0 X0.\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    // Under G54.1 X0 is at 0; G92 X-5 there shifts X by 5; G54 X0 is at 100 + 5.
    close(&ends(&p), &[[0.0, 0.0, 10.0], [105.0, 0.0, 10.0]]);
}

/// Haas' additional work offsets (Haas, "Programmable Offsets": G10 L20 P1-P20 set G110-G129, P1-P99
/// G154 P1-P99), which the program does not set here: `G154 P5` and `G110` put the origin at zero
/// (the operator's offset, said once each as a warning), `G55` takes the program's G10 L2 P2 offset
/// again. `G154` without P, or P0 or P100, is refused at its word.
#[test]
fn haas_g154_and_g110_g129_are_additional_work_offsets() {
    let text = "%\nG21 G90 G17 G94\nG10 L2 P2 X300. Y0. Z0.\nG55 G0 X0. Y0. Z10.\nG154 P5\nG0 X1.\nG55 G0 X2.\nG110 G0 X3.\nG129 X4.\nG55 X5.\nM30\n%\n";
    let p = read(text, Dialect::Haas, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    close(&ends(&p), &[[300.0, 0.0, 10.0], [1.0, 0.0, 10.0], [302.0, 0.0, 10.0], [3.0, 0.0, 10.0], [4.0, 0.0, 10.0], [305.0, 0.0, 10.0]]);
    assert!(p.diagnostics.iter().any(|d| d.line == 5 && d.message.contains("G154: additional work offsets")), "{:?}", p.diagnostics);
    for (block, col, needle) in [("G154", 1, "G154 without P"), ("G154 P0", 6, "G154 P0: expected P1 to P99"), ("G154 P100", 6, "expected P1 to P99")] {
        let p = read(&format!("%\nG21 G90 G0 X0. Y0. Z10.\n{block}\nG0 X1.\nM30\n%\n"), Dialect::Haas, "t.nc", &ReadOptions::default());
        has(&p, 3, col, needle);
    }
}

/// `G10 L20 Pn` sets additional work offset n from the machine zero, as G10 L2 sets G54-G59
/// (Mitsubishi M700V §14.10, "G10 L20 Pn X__ Y__ Z__", for the FANUC dialect; Haas,
/// "Programmable Offsets": "G10 L20 P2 G90 X100. Y80. Sets offset G111 to X100. Y80."): `G54.1 Pn`
/// (Fanuc) or `G154 Pn` and `G110`-`G129` for P1-P20 (Haas) select it. Axes not named keep theirs;
/// one set while in effect moves the origin at once (the tool stays); an offset never set is the
/// operator's, zero, with a warning. Each end point below is the offset plus the block's words.
#[test]
fn g10_l20_sets_the_additional_work_offsets() {
    let text = "%\nG21 G90 G17 G94\nG10 L20 P1 X100. Y50. Z0.\nG10 L20 P2 X-20. Z5.\nG0 X0. Y0. Z10.\nG54.1 P1\nG0 X1.\nG10 L20 P1 X200.\nG0 X1.\nG54.1 P2 G0 X0.\nG54.1 P3\nG0 X0. Y0. Z0.\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    close(
        &ends(&p),
        &[
            [0.0, 0.0, 10.0],    // G54 (the operator's, zero)
            [101.0, 0.0, 10.0],  // G54.1 P1 at (100, 50, 0): X1; Y and Z stay where the tool is
            [201.0, 0.0, 10.0],  // P1's X now 200 (its Y 50 kept)
            [-20.0, 0.0, 10.0],  // G54.1 P2 at (-20, 0, 5): X0
            [0.0, 0.0, 0.0],     // G54.1 P3, never set: zero
        ],
    );
    let zero = |l: usize| p.diagnostics.iter().any(|d| d.line == l && d.message.contains("additional work offsets are not set by the program"));
    assert!(!zero(6) && !zero(10) && zero(11), "{:?}", p.diagnostics);

    let text = "%\nG21 G90 G17 G94\nG10 L20 P2 X100. Y80.\nG0 X0. Y0. Z10.\nG111 G0 X1.\nG154 P2 G0 Y1.\nG10 L20 P21 X-7. Y0. Z0.\nG154 P21 G0 X0. Y0.\nG110 X0. Y0.\nM30\n%\n";
    let p = read(text, Dialect::Haas, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    close(&ends(&p), &[[0.0, 0.0, 10.0], [101.0, 0.0, 10.0], [101.0, 81.0, 10.0], [-7.0, 0.0, 10.0], [0.0, 0.0, 10.0]]);

    // What is not read is refused at its word: P out of the control's range, G91, a rotary offset.
    refuses_each(
        Dialect::Haas,
        &ReadOptions::default(),
        &[
            ("%\nG21 G90\nG10 L20 P100 X1.\nM30\n%\n", "3:9:", "G10 L20 P100: expected P1 to P99"),
            ("%\nG21 G90\nG10 L20 X1.\nM30\n%\n", "3:1:", "G10 L20 without P"),
            ("%\nG21 G91\nG10 L20 P1 X1.\nM30\n%\n", "3:1:", "G10 L20 under G91"),
            ("%\nG21 G90\nG10 L20 P1 X1. A5.\nM30\n%\n", "3:16:", "G10 L20 A5.: rotary-axis work offsets are not modelled"),
        ],
    );
    refuses_each(Dialect::Fanuc, &ReadOptions::default(), &[("%\nG21 G90\nG10 L20 P301 X1.\nM30\n%\n", "3:9:", "expected P1 to P48 (P300 with the option")]);
}
