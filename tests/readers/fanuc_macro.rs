//! Fanuc's and Haas' custom macro and dwell where their rules leave the value to the control (a
//! parameter, an increment) or to a manual not at hand: refused at the word, never read by
//! LinuxCNC's rule; the forms whose rule is plain read, with values worked by hand.

use super::*;

/// The X (mm) of each move of a metric Fanuc program `body`, refused nowhere.
fn xs(dialect: Dialect, body: &str) -> Vec<f64> {
    let p = read(&format!("%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z5.\n{body}M30\n%\n"), dialect, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{body}: {:?}", errors(&p));
    ends(&p).into_iter().skip(1).map(|e| e[0]).collect()
}

/// Line 5 (the body's first) of a metric Fanuc program `body` has an error at `column` holding `needle`.
fn refused(dialect: Dialect, body: &str, line: usize, column: usize, needle: &str) {
    let p = read(&format!("%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z5.\n{body}M30\n%\n"), dialect, "t.nc", &ReadOptions::default());
    has(&p, line, column, needle);
}

/// In a G04 block X is the dwell's time ("G04 X_ ; or G04 P_ ;"): an X beside P, or another axis
/// word with G04, is no move the reader may make; G04 P alone dwells and moves nothing.
#[test]
fn a_g04_block_with_axis_words_is_refused_not_moved() {
    for dialect in [Dialect::Fanuc, Dialect::Haas] {
        refused(dialect, "G01 X10. F600.\nG04 P1000 X30.\n", 6, 11, "in a G04 block X is the dwell's time");
        refused(dialect, "G01 X40. G04 P500\n", 5, 5, "in a G04 block X is the dwell's time");
        refused(dialect, "G04 P500 Z-1.\n", 5, 10, "not a move");
        assert_eq!(xs(dialect, "G01 X10. F600.\nG04 P500\nG01 X20.\n"), vec![10.0, 20.0], "{dialect:?}");
    }
    // FANUC's G04 X with a decimal point: seconds, and no move (X stays at 10).
    let p = read("%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z5.\nG01 X10. F600.\nG04 X2.5\nG01 X20.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert_eq!(p.blocks.iter().filter_map(|b| b.dwell_s.map(|d| (b.line, d))).collect::<Vec<_>>(), vec![(6, 2.5)]);
    assert_eq!(ends(&p).iter().map(|e| e[0]).collect::<Vec<_>>(), vec![0.0, 10.0, 20.0]);
    refused(Dialect::Fanuc, "G04 X25\n", 5, 5, "seconds with a decimal point");
}

/// ATAN and ASIN give a negative angle in -180..180 and -90..90, or the same angle plus 360, as
/// parameter 6004#0 (NAT) says: refused where the two differ; read where they agree (45 and 30 deg).
#[test]
fn atan_and_asin_of_a_negative_angle_are_the_parameters_and_refused() {
    refused(Dialect::Fanuc, "#1=ATAN[-1]/[-1]\n", 5, 4, "6004#0 (NAT)");
    refused(Dialect::Fanuc, "#1=ASIN[-1]\n", 5, 4, "6004#0 (NAT)");
    refused(Dialect::Haas, "G01 X[ATAN[-1]/[1]] F100.\n", 5, 7, "-45 deg, or 315 deg");
    let want = [1.0f64.atan2(1.0).to_degrees() / 10.0, 0.5f64.asin().to_degrees() / 10.0];
    let got = xs(Dialect::Fanuc, "#1=ATAN[1]/[1]\n#2=ASIN[0.5]\nG01 X[#1/10] F100.\nG01 X[#2/10]\n");
    assert!(got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-9), "{got:?} against {want:?}");
}

/// AND, OR and XOR beside arithmetic or a comparison at one bracket level: where FANUC ranks them
/// is not at hand, so refused at the operator; bracketed, read bit by bit ([4+3] AND 1 = 7 AND 1 = 1,
/// [4+3] OR 8 = 15).
#[test]
fn bitwise_operators_beside_others_need_brackets() {
    refused(Dialect::Fanuc, "#1=4+3 AND 1\n", 5, 8, "AND beside arithmetic");
    refused(Dialect::Haas, "#2=2.\nIF [#2 GT 1 AND #2 LT 4] GOTO 10\nN10 G01 X1. F100.\n", 6, 13, "AND beside arithmetic, a comparison");
    refused(Dialect::Fanuc, "G01 X[1 OR 2 * 4] F100.\n", 5, 9, "OR beside");
    // AND beside OR: AND ranked with * in some tables (4 OR [2 AND 1] = 4), with OR in others (0).
    refused(Dialect::Fanuc, "#1=4 OR 2 AND 1\n", 5, 6, "OR beside arithmetic, a comparison or another");
    assert_eq!(xs(Dialect::Fanuc, "#1=4 OR 2 XOR 1\nG01 X#1 F100.\n"), vec![7.0]);
    assert_eq!(xs(Dialect::Fanuc, "#1=[4+3] AND 1\n#2=[4+3] OR 8\nG01 X#1 F100.\nG01 X#2\n"), vec![1.0, 15.0]);
    // Comparisons each in brackets, joined by AND: both true, the jump is taken past X99.
    assert_eq!(xs(Dialect::Fanuc, "#2=2.\nIF [[#2 GT 1] AND [#2 LT 4]] GOTO 10\nG01 X99. F100.\nN10 G01 X3. F100.\n"), vec![3.0]);
}

/// ROUND in an address rounds to the address's least input increment (FANUC; Haas: X[ROUND[#1] +
/// ROUND[#1]] with #1 = 1.00333 moves to 2.0066), not to a whole number: refused there; in a macro
/// statement it rounds to a whole number (1.5 to 2).
#[test]
fn round_in_an_address_is_refused_and_read_in_a_statement() {
    refused(Dialect::Haas, "#1=1.00333\nG01 X[ROUND[#1]+ROUND[#1]] F100.\n", 6, 7, "ROUND in an address");
    refused(Dialect::Fanuc, "#1=1.2345\nG01 X[ROUND[#1]] F100.\n", 6, 7, "least input increment");
    assert_eq!(xs(Dialect::Fanuc, "#1=1.5\n#2=ROUND[#1]\nG01 X#2 F100.\n"), vec![2.0]);
}

/// MOD of whole numbers 0 or more is the remainder (10 MOD 3 = 1, 27 MOD 20 = 7, Haas' example); a
/// negative or fractional operand, whose rounding and sign the manuals at hand do not give, is refused.
#[test]
fn mod_is_read_for_whole_numbers_only() {
    assert_eq!(xs(Dialect::Haas, "#1=10 MOD 3\n#2=27 MOD 20\nG01 X#1 F100.\nG01 X#2\n"), vec![1.0, 7.0]);
    refused(Dialect::Fanuc, "#1=-10 MOD 3\n", 5, 8, "negative or fractional");
    refused(Dialect::Fanuc, "#1=10.7 MOD 3\n", 5, 9, "negative or fractional");
}

/// Haas' M99 P in a subprogram branches within it (its manual) where FANUC returns to the caller's
/// block: refused on Haas; FANUC's return to N10 of the caller is read (Y1 in the subprogram, then X3).
#[test]
fn m99_p_in_a_subprogram_is_read_on_fanuc_and_refused_on_haas() {
    let text = |dialect: Dialect| {
        let p = read(
            "%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z5.\nG01 F100.\nM98 P2000\nG01 X9.\nN10 G01 X3.\nM30\nO2000\nG01 Y1.\nM99 P10\n%\n",
            dialect,
            "t.nc",
            &ReadOptions::default(),
        );
        p
    };
    let fanuc = text(Dialect::Fanuc);
    assert!(errors(&fanuc).is_empty(), "{:?}", errors(&fanuc));
    let e = ends(&fanuc);
    assert_eq!(e[1..].iter().map(|p| [p[0], p[1]]).collect::<Vec<_>>(), vec![[0.0, 1.0], [3.0, 1.0]]);
    has(&text(Dialect::Haas), 12, 1, "M99 P10 in a subprogram");
}

/// P on an arc is LinuxCNC's count of turns; FANUC's and Haas' G02/G03 take none: refused there, not
/// run as three circles.
#[test]
fn p_on_a_fanuc_or_haas_arc_is_refused() {
    for dialect in [Dialect::Fanuc, Dialect::Haas] {
        refused(dialect, "G01 X10. F100.\nG03 X10. Y0. I-10. J0. P3\n", 6, 24, "word P3 without a G code that takes it");
    }
}

/// G84 with a Q, written or kept from an earlier cycle, is the peck rigid tapping cycle under rigid
/// tapping (FANUC 0i, "Peck rigid tapping cycle (G84 or G88)": back off by parameter No. 5213 or to
/// R by No. 5200#5), not read: refused at the Q. Haas: G234 (TCPC) and G254 (DWO) together are
/// refused ("Cancel G254 with G255 any time simultaneous 4- or 5-axis machining is performed"), and
/// so is a cutting move after G254 before X, Y and Z are given ("you must specify an X, Y, and Z
/// position prior to any cutting command"); NX's order (X Y at rapid, then Z, then cutting) reads.
#[test]
fn peck_tapping_and_haas_dwo_with_tcpc_fail_closed() {
    refused(Dialect::Fanuc, "S500 M3\nG99 G84 X10. Y0. Z-10. R2. Q5. F500.\nG80\n", 6, 28, "G84 with Q5.");
    refused(Dialect::Fanuc, "S500 M3\nG99 G83 X5. Y0. Z-10. R2. Q2. F100.\nG84 X10. Y0. Z-10. R2. F500.\nG80\n", 7, 1, "G84 with the Q2 kept");
    for (body, line, needle) in [
        ("G254\nG234 H1\nG0 X1. Y0. Z2.\nG49\nG255\n", 6, "G234 (TCPC) and G254 (dynamic work offset) together"),
        ("G234 H1\nG254\nG49\nG255\n", 6, "G234 (TCPC) and G254 (dynamic work offset) together"),
        ("G254\nG0 X1.\nG1 Y1. F10.\nG255\n", 7, "before Z is written"),
    ] {
        let text = format!("%\nO1000\nG20 G90 G17 G94\nG0 X0. Y0. Z5.\n{body}M30\n%\n");
        let p = read(&text, Dialect::Haas, "t.nc", &ReadOptions::default().on(&fiveaxis::machine::Machine::builtin("haas-umc-750").unwrap()));
        assert!(errors(&p).iter().any(|(l, _, m)| *l == line && m.contains(needle)), "{body:?}: {:?}", errors(&p));
    }
    // NX's order, and a cancel in the block that switches the other on, read.
    for nx in [
        "G254\nG54 G90 G00 X-1.9222 Y-2.3215\nG43 H01 D01 Z.2772\nG01 Y-2.5254 Z.2665 F9.8\nG255\n",
        "G254\nG255 G234 H1\nG0 X1. Y0. Z2.\nG49\n",
        "G234 H1\nG49 G254\nG255\n",
    ] {
        let text = format!("%\nO1000\nG20 G90 G17 G94\nG0 X0. Y0. Z5.\n{nx}M30\n%\n");
        let p = read(&text, Dialect::Haas, "t.nc", &ReadOptions::default().on(&fiveaxis::machine::Machine::builtin("haas-umc-750").unwrap()));
        assert!(errors(&p).is_empty(), "{nx:?}: {:?}", errors(&p));
    }
}

/// FANUC times an arc by its own rules. Under G93 F is the feed over the arc's radius ("FRN =
/// feedrate / arc radius", B-62764EN §5: "calculated not from the actual amount of movement in the
/// block but from the arc radius"), so an arc of angle th takes th / FRN minutes, where Haas' takes
/// 60 / F seconds as any of its G93 moves ("the time (in seconds) to complete the programmed motion
/// using G93 is, 60 (seconds) divided by the F value"). On a helix (or with a rotary axis) F is
/// along the arc or the whole path as FANUC's parameter HTG says: refused. A plain arc in its plane
/// reads.
#[test]
fn fanuc_inverse_time_arcs_take_their_angle_over_frn_and_helical_arcs_are_refused() {
    use fiveaxis::path::{PathOptions, Trajectory};
    // A half circle of radius 30 at FRN 1, then a quarter circle at FRN 2, each block's time in s.
    let times = |dialect: Dialect| {
        let p = read("%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z5.\nG93 G02 X60. Y0. R30. F1.\nG03 X90. Y30. R30. F2.\nG94\nM30\n%\n", dialect, "t.nc", &ReadOptions::default());
        assert!(errors(&p).is_empty(), "{:?}", errors(&p));
        let t = Trajectory::from_program(&p, &fiveaxis::machine::Machine::builtin("generic-bc-table").unwrap(), &PathOptions::default());
        assert!(t.diagnostics.is_empty(), "{:?}", t.diagnostics);
        [5, 6].map(|line| t.segments.iter().filter(|s| s.line == line).map(|s| s.duration).sum::<f64>())
    };
    let pi = std::f64::consts::PI;
    let fanuc = times(Dialect::Fanuc);
    assert!((fanuc[0] - pi / 1.0 * 60.0).abs() < 1e-9 && (fanuc[1] - pi / 2.0 / 2.0 * 60.0).abs() < 1e-9, "{fanuc:?}");
    let haas = times(Dialect::Haas);
    assert!((haas[0] - 60.0).abs() < 1e-9 && (haas[1] - 30.0).abs() < 1e-9, "{haas:?}");
    refused(Dialect::Fanuc, "G93 G02 X60. Y0. Z-5. R30. F1.\n", 5, 1, "a helix");
    refused(Dialect::Fanuc, "G94 G02 X60. Y0. Z-5. R30. F100.\n", 5, 1, "a helix");
    refused(Dialect::Fanuc, "G94 G02 X60. Y0. C90. R30. F100.\n", 5, 1, "parameter HTG");
    assert_eq!(xs(Dialect::Fanuc, "G94 G01 X0. F100.\nG02 X60. Y0. R30.\n"), vec![0.0, 60.0]);
}

/// Haas feeds a rotary axis at the part diameter Setting 34 or 79 gives ("the control must know the
/// diameter of the part being machined ... to compute angular feedrate"), a setting of the job not
/// read, and asks for G93 for simultaneous 4- or 5-axis motion (G94 only under G234; Mill NGC
/// Operator's Manual, 2017): a feed move of A or B without G234 is refused, with linear axes too
/// by that rule, said once for a stretch of them (whose moves are read as written); under G234 (F
/// along the tool tip) or as a rapid it reads.
#[test]
fn haas_rotary_feed_without_tcpc_is_refused_once_a_stretch() {
    let vf2 = ReadOptions::default().on(&fiveaxis::machine::Machine::builtin("haas-vf2-tr").unwrap());
    let run = |body: &str| read(&format!("%\nO1000\nG20 G90 G17 G94\nG0 X0. Y0. Z5. A0. B0.\n{body}M30\n%\n"), Dialect::Haas, "t.nc", &vf2);
    let p = run("G01 X1. A-5. B30. F9.8\n");
    assert!(errors(&p).iter().any(|(l, c, m)| (*l, *c) == (5, 1) && m.contains("Setting 34 or 79") && m.contains("G93 inverse time for simultaneous")), "{:?}", errors(&p));
    // A rotary axis alone: the diameter, not the simultaneous-motion rule.
    let p = run("G01 B30. F9.8\n");
    assert!(errors(&p).iter().any(|(l, c, m)| (*l, *c) == (5, 1) && m.contains("Setting 34 or 79") && !m.contains("simultaneous")), "{:?}", errors(&p));
    let p = run("G00 A-5. B30.\nG01 X1. F9.8\n");
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    // Said once for a stretch of such moves (an operation of hundreds), which stand as written: the
    // two after the first are feed moves (G01 kept), not refused and not read in the mode before;
    // a feed move of the linear axes alone ends the stretch, and the next one is said again.
    let p = run("G01 X1. A-5. B30. F9.8\nX2. A-6. B35.\nX3. A-7. B40.\nX4.\nX5. A-8.\n");
    let e = errors(&p);
    assert!(e.len() == 2 && (e[0].0, e[0].1) == (5, 1) && (e[1].0, e[1].1) == (9, 1) && e.iter().all(|m| m.2.contains("said once")), "{e:?}");
    let feeds: Vec<usize> = p.blocks.iter().filter(|b| b.motion == Motion::Linear && !b.targets.is_empty()).map(|b| b.line).collect();
    assert_eq!(feeds, [5, 6, 7, 8, 9], "{:#?}", p.blocks);
    // A block that moves nothing (coolant, a feed, a dwell) under G01 does not end the stretch; a
    // rapid does (the next operation's first such move is said again).
    let p = run("G01 X1. A-5. B30. F9.8\nM08\nF12.\nG04 P1.\nX2. A-6.\n");
    let e = errors(&p);
    assert!(e.len() == 1 && (e[0].0, e[0].1) == (5, 1), "{e:?}");
    let p = run("G01 X1. A-5. B30. F9.8\nG00 Z5.\nG01 X2. A-6. F9.8\n");
    let e = errors(&p);
    assert!(e.len() == 2 && (e[0].0, e[1].0) == (5, 7), "{e:?}");
}
