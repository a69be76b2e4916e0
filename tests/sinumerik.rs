//! The Sinumerik reader on what 840D posts write: variables in axis words, machine coordinates
//! (SUPA with D0), the programmable frame under TRAORI, MCALL drilling cycles, CYCLE832 and G60, and
//! the circle end-point tolerance. Every expected figure is worked by hand from the manual's rule
//! named beside it.

use crate::common;

use fiveaxis::machine::Machine;
use fiveaxis::program::{read, Block, Dialect, Exact, Motion, Program, ReadOptions, Severity};
use fiveaxis::units::MM;

mod circles;

fn errors(p: &Program) -> Vec<(usize, usize, String)> {
    p.diagnostics.iter().filter(|d| d.severity == Severity::Error).map(|d| (d.line, d.column, d.message.clone())).collect()
}

/// The Haas UMC-750's file: a B/C table whose machine zero its file places (X 381, Y 254, Z 610 mm
/// from the rotary axes), read as a Sinumerik program here.
fn on_umc(text: &str) -> Program {
    let m = Machine::builtin("haas-umc-750").unwrap();
    read(text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default().on(&m))
}

/// A program read as an 840D program, with no machine.
fn sin(text: &str) -> Program {
    read(text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default())
}

/// Reading `text` as an 840D program gives one error, at `line` (and `col`, where given), saying
/// `message`.
fn refused_once(text: &str, line: usize, col: Option<usize>, message: &str) {
    let e = errors(&sin(text));
    assert!(e.len() == 1 && e[0].0 == line && col.is_none_or(|c| e[0].1 == c) && e[0].2.contains(message), "{text}: {e:?}");
}

fn blocks_of(p: &Program, line: usize) -> Vec<&Block> {
    p.blocks.iter().filter(|b| b.line == line).collect()
}

fn close(a: Option<f64>, want_mm: f64) -> bool {
    a.is_some_and(|v| (v - want_mm * MM).abs() < 1e-9)
}

/// `SUPA G0 Z=_Z_HOME D0` (the Spinner post's home moves): the variables' values, in machine
/// coordinates: program Z = machine Z + the machine zero's 610 mm; X -371 + 381 = 10.
#[test]
fn supa_moves_to_machine_coordinates_given_by_variables() {
    let p = on_umc("N10 DEF REAL _Z_HOME, _X_HOME\nN20 G90 G71 G94\nN30 _Z_HOME=-100 _X_HOME=-381+10\nN40 SUPA G0 Z=_Z_HOME D0\nN50 SUPA X=_X_HOME Y=0 D1\nN60 G54 G0 X10 Y10 Z50\n");
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let z = blocks_of(&p, 4)[0];
    assert!(close(z.targets.z, 510.0) && z.motion == Motion::Rapid && !z.offset_assumed, "{z:?}");
    let xy = blocks_of(&p, 5)[0];
    assert!(close(xy.targets.x, 10.0) && close(xy.targets.y, 254.0), "{xy:?}");
    // With the tool's offsets on, a Z in machine coordinates would be the tip's: refused.
    let p = on_umc("G90 G71\nD1\nSUPA G0 Z-100\n");
    assert!(errors(&p).iter().any(|(l, c, m)| *l == 3 && *c == 9 && m.contains("D0")), "{:#?}", errors(&p));
    // A variable defined without a value is 0 (Programming Manual 12/2019 §3.1.1: the type's implicit
    // initialization value); one never defined, or an R parameter this program has not set, is an
    // error at its value.
    let p = on_umc("G90 G71\nDEF REAL _A\nDEF INT _K\nG0 X=_A+5 Y=_K-2 Z100\nG0 X=_B Y=R7\n");
    let e = errors(&p);
    assert!(close(blocks_of(&p, 4)[0].targets.x, 5.0) && close(blocks_of(&p, 4)[0].targets.y, -2.0), "{:?}", blocks_of(&p, 4));
    assert!(e.iter().any(|(l, c, m)| *l == 5 && *c == 6 && m.contains("not defined")) && e.iter().any(|(l, c, m)| *l == 5 && *c == 11 && m.contains("R7 is read before this program sets it")), "{e:#?}");
}

/// `G0 B90 C0`, `TRAORI`, `AROT Y90`, `G0 X31 Y-15 Z165` (the Spinner post's 3+2 set-up): the frame
/// turned 90 deg about Y, so frame (x, y, z) is workpiece (z, y, -x): (165, -15, -31); `G1 Z2` keeps
/// the frame's X 31 and Y -15: (2, -15, -31). `TRANS X0 Y0 Z0` resets the frame.
#[test]
fn arot_turns_the_frame_under_traori() {
    let p = on_umc("G90 G71 G94\nG0 B90 C0\nTRAORI\nAROT Y90.\nG0 X31. Y-15.001 Z165.236\nG1 Z2 F1000\nTRANS X0 Y0 Z0\nG0 X1 Y2 Z3\nTRAFOOF\n");
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let b = blocks_of(&p, 5)[0];
    assert!(b.tcp && close(b.targets.x, 165.236) && close(b.targets.y, -15.001) && close(b.targets.z, -31.0), "{:?}", b.targets);
    let b = blocks_of(&p, 6)[0];
    assert!(close(b.targets.x, 2.0) && close(b.targets.y, -15.001) && close(b.targets.z, -31.0), "{:?}", b.targets);
    let b = blocks_of(&p, 8)[0];
    assert!(close(b.targets.x, 1.0) && close(b.targets.z, 3.0), "{:?}", b.targets);
}

/// Without TRAORI (or CYCLE800's swivel data) a rotated frame turns the linear axes' coordinates
/// alone: the frame maps the workpiece coordinates onto the basic system, which without a
/// transformation is the axes' (Fundamentals 12/2019 §"Frames"), so axes = R p + datum however the
/// rotary axes stand (here the UMC's table at B90). `AROT Y90`: (x, y, z) -> (z, y, -x); `ROT Z90`
/// replaces it: (x, y, z) -> (-y, x, z); after TRAORI and TRAFOOF the frame turns the axes again.
#[test]
fn a_rotated_frame_without_traori_turns_the_linear_axes() {
    let p = on_umc("G90 G71 G94\nG0 B90 C0\nAROT Y90\nG0 X1 Y2 Z3\nROT Z90\nG1 X10 Y0 Z-5 F100\nTRAORI\nTRAFOOF\nG0 X1 Y2 Z3\n");
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let at = |line: usize, want: [f64; 3]| {
        let b = blocks_of(&p, line)[0];
        assert!(!b.tcp && close(b.targets.x, want[0]) && close(b.targets.y, want[1]) && close(b.targets.z, want[2]), "line {line}: {:?}", b.targets);
    };
    at(4, [3.0, 2.0, -1.0]);
    at(6, [0.0, 10.0, -5.0]);
    at(9, [-2.0, 1.0, 3.0]);
    // A rotary axis may move in the same block: nothing places the tool through it.
    let p = on_umc("G90 G71\nROT Z30\nG0 X10 Y0 Z0 B5\n");
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let b = blocks_of(&p, 3)[0];
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    assert!(close(b.targets.x, 10.0 * c) && close(b.targets.y, 10.0 * s) && !b.tcp, "{:?}", b.targets);
    // A swivel after such a frame: how CYCLE800 meets the programmed rotation is not read.
    let ftv5 = Machine::builtin("cincinnati-ftv5").unwrap();
    let p = read("G90 G71\nROT Z30\nCYCLE800(0,\"R_DATA\",0,57,0,0,0,30,0,0,0,0,0,1)\nG0 X1\n", Dialect::Sinumerik, "t.mpf", &ReadOptions::default().on(&ftv5));
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 3 && m.contains("after a rotated frame")), "{:#?}", errors(&p));
}

/// `MCALL CYCLE81(10, 0, 2, -5)` (RTP 10, RFP 0, SDIS 2, DP -5): each later positioning block, then
/// G0 to RFP + SDIS = 2, G1 to -5 at the modal F, G0 to RTP 10 (CYCLE81.SPF); `MCALL` alone ends it.
#[test]
fn mcall_drills_at_each_position() {
    let p = on_umc("G90 G71 G94 F200\nG0 X0 Y0 Z50\nMCALL CYCLE81(10, 0, 2, -5)\nX10 Y20\nX30\nMCALL\nX40\n");
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let hole = |line: usize| blocks_of(&p, line).iter().map(|b| (b.motion, b.targets.x.map(|v| (v / MM).round()), b.targets.z.map(|v| (v / MM * 1e6).round() / 1e6))).collect::<Vec<_>>();
    use Motion::{Linear, Rapid};
    assert_eq!(hole(4), vec![(Rapid, Some(10.0), None), (Rapid, None, Some(2.0)), (Linear, None, Some(-5.0)), (Rapid, None, Some(10.0))]);
    assert_eq!(hole(5), vec![(Rapid, Some(30.0), None), (Rapid, None, Some(2.0)), (Linear, None, Some(-5.0)), (Rapid, None, Some(10.0))]);
    assert_eq!(hole(7), vec![(Rapid, Some(40.0), None)]);
    assert_eq!(blocks_of(&p, 4)[2].feed.unwrap().value_per_min, 200.0);
    // The cycle's levels are absolute whatever G90/G91 say ("RTP retraction plane (absolute)", "DP
    // final drilling depth (absolute)"): holes positioned under G91 drill to the same Z.
    let p = on_umc("G90 G71 G94 F200\nG0 X0 Y0 Z50\nMCALL CYCLE81(10, 0, 2, -5)\nG91 X10 Y20\nX20\nG90 MCALL\n");
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let hole = |line: usize| blocks_of(&p, line).iter().map(|b| (b.motion, b.targets.x.map(|v| (v / MM).round()), b.targets.z.map(|v| (v / MM * 1e6).round() / 1e6))).collect::<Vec<_>>();
    assert_eq!(hole(4), vec![(Rapid, Some(10.0), None), (Rapid, None, Some(2.0)), (Linear, None, Some(-5.0)), (Rapid, None, Some(10.0))]);
    assert_eq!(hole(5), vec![(Rapid, Some(30.0), None), (Rapid, None, Some(2.0)), (Linear, None, Some(-5.0)), (Rapid, None, Some(10.0))]);
    // The DMU 70 eVo post's call: RTP (the clearance) below RFP while drilling down, alarm 61101.
    let p = on_umc("G90 G70 F9.8\nMCALL CYCLE81(.2362,2.728,.2362,2.5311,)\n");
    assert!(errors(&p).iter().any(|(l, c, m)| *l == 2 && *c == 7 && m.contains("61101")), "{:#?}", errors(&p));
}

/// `CYCLE81(10, 0, 2, -5)` called without MCALL drills once where the tool stands (Cycles Programming
/// Guide 11.02 §2.1, "the cycle can also be called modally", §2.2): G0 to RFP + SDIS = 2, G1 to -5 at
/// the modal F, G0 to RTP 10; the next positioning block drills nothing. A call beside other words,
/// or under MCALL's cycle, is refused.
#[test]
fn a_drilling_cycle_without_mcall_drills_once_where_the_tool_stands() {
    let p = on_umc("G90 G71 G94 F200\nG0 X10 Y20 Z50\nCYCLE81(10, 0, 2, -5)\nX30\nM30\n");
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let hole = |line: usize| blocks_of(&p, line).iter().map(|b| (b.motion, b.targets.x.map(|v| (v / MM).round()), b.targets.z.map(|v| (v / MM * 1e6).round() / 1e6))).collect::<Vec<_>>();
    use Motion::{Linear, Rapid};
    assert_eq!(hole(3), vec![(Rapid, None, Some(2.0)), (Linear, None, Some(-5.0)), (Rapid, None, Some(10.0))]);
    assert_eq!(hole(4), vec![(Rapid, Some(30.0), None)]);
    assert_eq!(blocks_of(&p, 3)[1].feed.unwrap().value_per_min, 200.0);
    let p = on_umc("G90 G71 G94 F200\nG0 X10 Y20 Z50\nX5 CYCLE81(10, 0, 2, -5)\nM30\n");
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 3 && m.contains("stands alone in its block")), "{:#?}", errors(&p));
    let p = on_umc("G90 G71 G94 F200\nG0 X10 Y20 Z50\nMCALL CYCLE81(10, 0, 2, -5)\nCYCLE82(10, 0, 2, -5, , 1)\nM30\n");
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 4 && m.contains("while MCALL's cycle is in force")), "{:#?}", errors(&p));
}

/// CYCLE832(_TOL, _TOLM, _OTOL): the tolerance for the blocks after it, and a continuous-path mode
/// that ends G60; CYCLE832() deselects it. G60 makes the blocks after it end in an exact stop
/// (tests/exact_stop.rs has the simulated machine stop there).
#[test]
fn cycle832_sets_the_tolerance_and_ends_g60() {
    let p = on_umc("G90 G71 G94 G60 G601\nG0 X1\nCYCLE832(.02,1,1)\nG1 X2 F100\nCYCLE832()\nG1 X3\nG60\nG1 X4\nM30\n");
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    assert!(close(blocks_of(&p, 4)[0].tolerance.linear_m, 0.02));
    assert_eq!(blocks_of(&p, 6)[0].tolerance.linear_m, None);
    let exact = |line: usize| blocks_of(&p, line)[0].exact;
    assert_eq!([exact(2), exact(4), exact(6), exact(8)], [Exact::Stop, Exact::Blend, Exact::Blend, Exact::Stop]);
}

/// CYCLE832's machining types by name (SINUMERIK Operate's plain text for `_TOLM`'s units digit:
/// `_FINISH` 1, `_SEMIFIN` 2, `_ROUGH` 3, `_OFF` 0), as Fusion's and other posts write them; the
/// `_ORI_` types carry an orientation tolerance, which is not read, and are refused at the call.
#[test]
fn cycle832_reads_its_machining_types_by_name() {
    for ty in ["_FINISH", "_SEMIFIN", "_rough"] {
        let p = on_umc(&format!("G90 G71 G94\nG0 X1\nCYCLE832(0.015,{ty},1)\nG1 X2 F100\nCYCLE832(0,_OFF,1)\nG1 X3\nM30\n"));
        assert!(errors(&p).is_empty(), "{ty}: {:#?}", errors(&p));
        assert!(close(blocks_of(&p, 4)[0].tolerance.linear_m, 0.015), "{ty}");
        assert_eq!(blocks_of(&p, 6)[0].tolerance.linear_m, None, "{ty}: _OFF deselects");
    }
    let p = on_umc("G90 G71 G94\nG0 X1\nCYCLE832(0.01,_ORI_FINISH,1)\nM30\n");
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 3 && m.contains("_ORI_FINISH: a machining type with an orientation tolerance")), "{:#?}", errors(&p));
}

/// Alarm 14040's rule: the radii to an arc's start and end may differ by max(0.01 mm, 0.001 R).
#[test]
fn circle_end_points_within_the_840ds_tolerance() {
    let arc = |end_x: f64, i: f64| on_umc(&format!("G90 G71 G17\nG1 X0 Y0 F100\nG2 X{end_x} Y0 I{i} J0\n"));
    assert!(errors(&arc(10.009, 5.0)).is_empty(), "0.009 mm on R 5");
    assert!(errors(&arc(10.012, 5.0)).iter().any(|(_, _, m)| m.contains("0.01000 mm")), "0.012 mm on R 5");
    assert!(errors(&arc(40.015, 20.0)).is_empty(), "0.015 mm on R 20: 0.02 allowed");
    assert!(errors(&arc(40.025, 20.0)).iter().any(|(_, _, m)| m.contains("0.02000 mm")), "0.025 mm on R 20");
}

/// CYCLE800 on the FTV5 (C/A fork head) as NX's 840D post calls it: `_FR` 1 retracts machine Z to the
/// data set's position, then `_DIR` +1 turns A to the higher of its two solutions. The plane of mode 57
/// X 28.5492, Y' -25.5438, Z'' 90 has its Z at (-0.431201, -0.431200, 0.792548), which the head reaches
/// at A = acos(0.792548) = 37.576 deg, C = -45 deg (Rz(C) Rx(A) e_z, worked by hand); X 45, Y' 35.2644,
/// Z'' 150 at A 54.736, C 45. NX's post for the DMU 70 eVo writes the same part's operations with the
/// table at B54.19 C1825.111 and B81.101 C103.826: on that machine's kinematics the tool in the part
/// points the same way, to 0.001 deg (the DMU's turning senses were read off these two planes, so the
/// agreement of both tilts and azimuths is the check). NX's `TRAOOF` before each swivel, a call of a
/// program not given (whose moves would leave the swivel's start unknown), is read as the `TRAFOOF`
/// it stands for.
#[test]
fn cycle800_swivels_the_ftv5_as_the_dmu70_program_tilts_the_same_part() {
    let ftv5 = Machine::builtin("cincinnati-ftv5").unwrap();
    let dmu = Machine::builtin("dmg-dmu-70-evo").unwrap();
    let file = common::outside("programs/sinumerik-840d_nx-post_cincinnati-ftv5_CYCLE800-TRAORI1_sample.mpf");
    let text = std::fs::read_to_string(&file).unwrap().replace("\nTRAOOF", "\nTRAFOOF");
    let p = read(&text, Dialect::Sinumerik, "ftv5.mpf", &ReadOptions::default().on(&ftv5));
    let deg = fiveaxis::units::DEG;
    for (line, a, c, dmu_b, dmu_c) in [(363, 37.576, -45.0, 54.19, 1825.111), (389, 54.736, 45.0, 81.101, 103.826)] {
        let b = blocks_of(&p, line);
        assert_eq!(b.len(), 2, "line {line}: the retraction and the swivel");
        assert!(close(b[0].targets.z, 1300.0) && b[0].motion == Motion::Rapid, "the data set's retract Z: {:?}", b[0].targets);
        let (ga, gc) = (b[1].targets.a.unwrap() / deg, b[1].targets.c.unwrap() / deg);
        assert!((ga - a).abs() < 1e-3 && (gc - c).abs() < 1e-3, "line {line}: A {ga} C {gc}, by hand A {a} C {c}");
        let tool = ftv5.chain.tool_frame(&[gc * deg, ga * deg]).column(2).into_owned();
        let other = dmu.chain.tool_frame(&[dmu_b * deg, dmu_c * deg]).column(2).into_owned();
        let angle = tool.dot(&other).clamp(-1.0, 1.0).acos() / deg;
        assert!(angle < 1e-3, "line {line}: the FTV5's tool and the DMU 70 eVo's are {angle} deg apart");
        // The next block is in the swivelled plane, through the head's kinematics.
        assert!(p.blocks.iter().any(|b| b.line == line + 1 && b.tcp));
    }
}

/// `AC()` and `IC()` dimension one word whatever G90/G91 say (SINUMERIK 802D sl Programming manual,
/// "Absolute/incremental dimensioning": `N180 G91 X40 Y20` then `N190 X-12 Y=AC(17)`, "X still
/// incremental dimensioning, Y absolute"; Programming Manual Fundamentals: "Non-modal absolute
/// dimensions (AC) are also possible for ... interpolation parameters (I, J, K)"). By hand: from X0
/// Y0, N180 goes to X40 Y20 and N190 to X28 Y17; under G90 `X=IC(5)` is X33; the arc about the
/// absolute centre `I=AC(23) J=AC(17)` from X33 Y17 to X23 Y27 has radius 10.
#[test]
fn ac_and_ic_dimension_their_word_only() {
    let p = sin("N10 G71 G90 G94 G17 G1 X0 Y0 F100\nN180 G91 X40 Y20\nN190 X-12 Y=AC(17)\nN200 G90 X=IC(5)\nN210 G2 X23 Y27 I=AC(23) J=AC(17)\nN220 M30\n");
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let at = |line: usize| blocks_of(&p, line)[0];
    assert!(close(at(2).targets.x, 40.0) && close(at(2).targets.y, 20.0), "{:?}", at(2).targets);
    assert!(close(at(3).targets.x, 28.0) && close(at(3).targets.y, 17.0), "{:?}", at(3).targets);
    assert!(close(at(4).targets.x, 33.0), "{:?}", at(4).targets);
    let arc = at(5).arc.as_deref().copied().expect("G2 about an absolute centre");
    assert!((arc.centre[0] - 23.0 * MM).abs() < 1e-12 && (arc.centre[1] - 17.0 * MM).abs() < 1e-12, "{:?}", arc.centre);
}

/// The 840D's subprogram calls of programs not given with this one (NC programming 12/2019 §3.2.1.2:
/// a name alone in its block, `L47`, `CALL "NAME"`) are refused at
/// their column, saying what they call and where it was looked for: the motion would depend on it.
/// The control runs them, so every axis is unknown after them: the move after them is refused (it
/// starts where the calls left the tool), and one writing every axis absolute is read again.
#[test]
fn subprogram_calls_name_the_program_they_call() {
    let p = read("G90 G71\nG0 X0 Y0 Z50\nCALL \"SUB1\"\nSUB1\nL100\nG1 X10 F100\nG0 X0 Y0 Z50\nG1 X20\nM30\n", Dialect::Sinumerik, "calls.mpf", &ReadOptions::default());
    let e = errors(&p);
    assert_eq!(e.len(), 5, "{e:?}");
    assert_eq!((e[0].0, e[0].1), (3, 1));
    assert!(e[0].2.contains("a call of the subprogram SUB1, whose file (SUB1.SPF)"), "{e:?}");
    assert_eq!((e[1].0, e[1].1), (4, 1));
    assert!(e[1].2.contains("a call of the subprogram SUB1, whose file (SUB1.SPF) is neither beside the program nor in a directory of --subroutine-path"), "{e:?}");
    assert_eq!((e[2].0, e[2].1), (5, 1));
    assert!(e[2].2.contains("a call of the subprogram L100"), "{e:?}");
    assert_eq!((e[3].0, e[3].1), (6, 4));
    assert!(e[3].2.contains("a move from where the moves under line 5's L100") && e[3].2.ends_with("once X, Y and Z are written absolute"), "{e:?}");
    assert_eq!((e[4].0, e[4].1), (7, 4));
    assert!(e[4].2.contains("once Y and Z are written absolute"), "{e:?}");
    let after = blocks_of(&p, 8);
    assert!(after.len() == 1 && close(after[0].targets.x, 20.0), "{after:?}");
}

/// A swivel after a call not read, which leaves every axis unknown: the plane it sets is read, its
/// own moves are not (they start where the call left the tool). What it places is known after it:
/// with `_FR` 2 the machine's X Y Z (its retraction, then X and Y to the data set's position) and so
/// the program's in the new plane, with `_FR` 1 only the machine's Z, which the plane's rotation
/// mixes with X and Y, so none of them; the rotary axes it turns, where their travel holds no other
/// turn of the position (the FTV5's A and its C at -45 deg in -200..200). `_DIR` 0 turns nothing
/// (Operating Manual §10.6), so A and C stay unknown, and no move of its own is refused. An additive
/// one (`_ST` 1) builds on a plane not known: refused, and the moves after it held.
#[test]
fn a_swivel_after_a_call_not_read_sets_its_plane_and_places_what_it_moves() {
    let ftv5 = Machine::builtin("cincinnati-ftv5").unwrap();
    let run = |swivel: &str| {
        let text = format!("G90 G71\nG0 X0 Y0 Z50\nSUB1\n{swivel}\nG0 X1 Y2 Z3\nG1 X2 F100\nM30\n");
        let p = read(&text, Dialect::Sinumerik, "swivel.mpf", &ReadOptions::default().on(&ftv5));
        let e: Vec<(usize, String)> = errors(&p).into_iter().map(|(l, _, m)| (l, m)).collect();
        (p, e)
    };
    let lines = |e: &[(usize, String)]| e.iter().map(|e| e.0).collect::<Vec<_>>();
    let (p, e) = run("CYCLE800(1,\"R_DATA\",0,57,0,0,0,30,0,0,0,0,0,1,)");
    assert_eq!(lines(&e), [3, 4, 5], "{e:#?}");
    assert!(e[1].1.contains("line 3's SUB1") && e[1].1.ends_with("the plane it sets is read, but its own moves, which start there, are not"), "{e:#?}");
    assert!(e[2].1.ends_with("once X, Y and Z are written absolute"), "{e:#?}");
    assert!(blocks_of(&p, 4).is_empty(), "the swivel's moves are not made");
    // The plane, 30 deg about X, is read: the program's (2, 2, 3) is the workpiece's
    // (2, 2 cos 30 - 3 sin 30, 2 sin 30 + 3 cos 30) = (2, 0.232051, 3.598076), through the head.
    let (p, e) = run("CYCLE800(2,\"R_DATA\",0,57,0,0,0,30,0,0,0,0,0,1,)");
    assert_eq!(lines(&e), [3, 4], "{e:#?}");
    let b = blocks_of(&p, 6);
    assert!(b.len() == 1 && b[0].tcp, "{b:?}");
    assert!(close(b[0].targets.x, 2.0) && close(b[0].targets.y, 0.232051) && close(b[0].targets.z, 3.598076), "{:?}", b[0].targets);
    let (_, e) = run("CYCLE800(1,\"R_DATA\",0,57,0,0,0,30,0,0,0,0,0,0,)");
    assert_eq!(lines(&e), [3, 5, 6], "{e:#?}");
    assert!(e[1].1.ends_with("once X, Y, Z, A and C are written absolute"), "{e:#?}");
    assert!(e[2].1.ends_with("once A and C are written absolute"), "{e:#?}");
    let (_, e) = run("CYCLE800(2,\"R_DATA\",1,57,0,0,0,30,0,0,0,0,0,1,)");
    assert_eq!(lines(&e), [3, 4, 5, 6], "{e:#?}");
    assert!(e[1].1.contains("_ST=1 (additive) builds on the swivelled plane before it, which is not known here"), "{e:#?}");
    assert!(e[2].1.contains("line 4's CYCLE800 (a swivel (CYCLE800) not read) is in effect"), "{e:#?}");
}

/// What the control runs and this reader does not leaves the tool where it is not known: a repeated
/// call (`SUB1 P3`); a cycle called once with a parameter not read (`CYCLE82` with a dwell in
/// revolutions), which drills all the same; `MCALL` of a program, which the control runs after every
/// later move, so those moves are held until `MCALL` alone, then every axis is unknown. A drilling
/// cycle refused for an alarm (RTP on the depth's side of RFP, 61101: the control stops there) is
/// said once, as the readers' other alarms are. A held block in machine coordinates (`SUPA`) makes
/// the axes it writes known (the DMU 70 eVo's machine zero), line by line.
#[test]
fn calls_not_read_leave_the_tool_unknown_and_an_alarm_is_said_once() {
    let lines = |p: &Program| errors(p).iter().map(|e| e.0).collect::<Vec<_>>();
    let p = sin("G90 G71\nG0 X0 Y0 Z50\nSUB1 P3\nG1 X10 F100\nM30\n");
    assert_eq!(lines(&p), [3, 4], "{:#?}", errors(&p));
    assert!(errors(&p)[1].2.contains("line 3's SUB1 (a subprogram call not read, which the control runs)"), "{:#?}", errors(&p));
    let p = sin("G90 G71\nG0 X0 Y0 Z50\nCYCLE82(10,0,2,-5,,-2)\nG1 X10 F100\nM30\n");
    assert_eq!(lines(&p), [3, 4], "{:#?}", errors(&p));
    assert!(errors(&p)[0].2.contains("is not read") && errors(&p)[1].2.contains("line 3's CYCLE82"), "{:#?}", errors(&p));
    let p = sin("G90 G71\nG0 X0 Y0 Z50\nMCALL SUB1\nG0 X10\nMCALL\nG0 X1 Y2 Z3\nG1 X5 F100\nM30\n");
    assert_eq!(lines(&p), [3, 4, 6], "{:#?}", errors(&p));
    assert!(errors(&p)[1].2.contains("a move while line 3's MCALL (a modal call (MCALL) refused) is in effect on the control until MCALL alone"), "{:#?}", errors(&p));
    assert!(errors(&p)[2].2.contains("a move from where the moves under line 3's MCALL"), "{:#?}", errors(&p));
    assert!(close(blocks_of(&p, 7)[0].targets.x, 5.0), "{:?}", blocks_of(&p, 7));
    let p = sin("G90 G71\nG0 X0 Y0 Z50\nMCALL CYCLE81(0,10,2,5)\nG0 X10\nMCALL\nG0 X1 Y2 Z3\nM30\n");
    assert_eq!(lines(&p), [3], "{:#?}", errors(&p));
    assert!(errors(&p)[0].2.contains("alarm 61101"), "{:#?}", errors(&p));
    let dmu = Machine::builtin("dmg-dmu-70-evo").unwrap();
    let p = read("G90 G710\nG0 X0 Y0 Z50 D0\nSUB1\nSUPA G0 Z-10 D0\nSUPA Y-10\nSUPA X10\nG0 X1 Y2 Z3\nM30\n", Dialect::Sinumerik, "t.mpf", &ReadOptions::default().on(&dmu));
    let e = errors(&p);
    assert_eq!(lines(&p), [3, 4, 5, 6, 7], "{e:#?}");
    for (k, left) in [(1, "X, Y, Z, B and C"), (2, "X, Y, B and C"), (3, "X, B and C"), (4, "B and C")] {
        assert!(e[k].2.ends_with(&format!("once {left} are written absolute")), "{e:#?}");
    }
}

/// A second swivel with its retraction (`_FR` 1) while a `ROT` turns the programmable frame is
/// refused in the 840D's terms (before: a TNC manual's rule about M91/M92 was cited); with a tilted
/// plane in effect, linear and rotary words in one block name TRAORI, the 840D's tool-tip follow-up.
#[test]
fn swivel_refusals_speak_the_840ds_terms() {
    let ftv5 = Machine::builtin("cincinnati-ftv5").unwrap();
    let p = read("G90 G710\nG0 X0 Y0 Z50 A0 C0\nCYCLE800(1,\"R_DATA\",0,57,0,0,0,10,0,0,0,0,0,1,)\nROT Z30\nCYCLE800(1,\"R_DATA\",0,57,0,0,0,20,0,0,0,0,0,1,)\nG0 X1 Y2 Z3 A5\nM30\n", Dialect::Sinumerik, "t.mpf", &ReadOptions::default().on(&ftv5));
    let e = errors(&p);
    let mut lines: Vec<usize> = e.iter().map(|e| e.0).collect();
    lines.dedup();
    assert_eq!(lines, [5, 6], "{e:#?}");
    assert!(e[0].2.contains("CYCLE800 _FR=1 with a rotated frame (ROT, AROT, RPL) in effect") && !e[0].2.contains("TNC"), "{e:#?}");
    assert!(e.iter().any(|e| e.2.contains("without TRAORI")), "{e:#?}");
}

/// A held line with a statement (`SOFT`) is read for where it leaves the tool, as a plain one is:
/// the arc after it starts there (from X100 Y100 its end X20 Y0 lies 134.536 mm from the centre
/// X10 Y0, not 10: refused as the control would, where read from the old point it passed). A cycle
/// called once while a hold is in effect, and an `MCALL` in a line refused for another statement
/// (`FGROUP`) or under radius compensation, are made by the control all the same: the tool is not
/// known after the one, the moves are held after the other. A text where a number is expected is
/// no alarm the reader knows of: held, whatever the text says.
#[test]
fn held_lines_and_refused_calls_leave_the_tool_where_the_control_has_it() {
    let first = |text: &str| -> Vec<(usize, String)> {
        let p = sin(text);
        errors(&p).into_iter().map(|(l, _, m)| (l, m)).collect()
    };
    let e = first("G0 G90 X0 Y0 Z50 F100\nFLIN\nG1 X100 Y100 SOFT\nFNORM\nG2 X20 Y0 I10 J0\nM30\n");
    assert!(e.iter().any(|(l, m)| *l == 5 && m.contains("the radius to the end (134.5362 mm) differs from the radius to the start (10.0000 mm)")), "{e:#?}");
    let e = first("G0 G90 X0 Y0 Z50 D0\nG1 F100\nFLIN\nCYCLE81(10,0,2,-5)\nFNORM\nG18 G2 X20 Z50 I10 K0\nM30\n");
    assert!(e.iter().any(|(l, m)| *l == 6 && m.contains("a move from where the moves under line 4's CYCLE81 (a cycle not read, which the control runs)")), "{e:#?}");
    let e = first("G0 G90 X0 Y0 Z50 F100\nMCALL CYCLE81(10,0,2,-5) FGROUP(X,Y,Z)\nG0 X20 Y20\nM30\n");
    assert!(e.iter().any(|(l, m)| *l == 3 && m.contains("a move while line 2's MCALL (a modal call (MCALL) refused) is in effect")), "{e:#?}");
    let e = first("G0 G90 X0 Y0 Z50\nMCALL CYCLE81(\"alarm 61101\",0,2,-5)\nG0 X10\nM30\n");
    assert!(e.iter().any(|(l, m)| *l == 3 && m.contains("a move while line 2's MCALL")), "{e:#?}");
}

/// `L47` among other words is refused with its line (the call stands alone in its block), and the
/// call it makes leaves every axis unknown all the same.
#[test]
fn an_l_call_among_other_words_leaves_the_axes_unknown() {
    let p = read("G90 G71\nG0 X0 Y0 Z50\nG0 X5 L47\nG1 Z10 F100\nG0 X1 Y2 Z3\nG1 Z4\nM30\n", Dialect::Sinumerik, "l.mpf", &ReadOptions::default());
    let e = errors(&p);
    assert_eq!(e.iter().map(|e| (e.0, e.1)).collect::<Vec<_>>(), [(3, 7), (4, 4), (5, 4)], "{e:?}");
    assert!(e[0].2.contains("L47: a call of the subprogram L47"), "{e:?}");
    assert!(e[1].2.contains("line 3's L47 (a call not read, which the control runs)"), "{e:?}");
    assert!(close(blocks_of(&p, 6)[0].targets.z, 4.0), "{:?}", blocks_of(&p, 6));
}

/// Subprogram files through the CLI, as the 840D's search path finds them (NC programming 12/2019
/// §3.4.1.4): first beside the calling program (`pocket_a.spf` for `POCKET_A`: the language does
/// not tell capitals from small letters), then in the subprogram directories (`--subroutine-path`,
/// here the control's own file name `_N_L20_SPF`); a directory `POCKET_A` is passed over. Without the directory the call of `L20` is
/// refused at its line, naming the program.
#[test]
fn subprograms_are_found_beside_the_program_and_on_the_subroutine_path() {
    let dir = std::env::temp_dir().join(format!("fiveaxis-spf-{}", std::process::id()));
    let (here, subs) = (dir.join("job"), dir.join("spf"));
    std::fs::create_dir_all(&here).unwrap();
    std::fs::create_dir_all(&subs).unwrap();
    std::fs::write(here.join("MAIN.MPF"), "N10 G90 G71 G94 F800\nN20 G0 X0 Y0 Z20\nN30 POCKET_A(12.5, -3)\nN40 L20\nN50 G0 Z50\nN60 M30\n").unwrap();
    std::fs::write(here.join("pocket_a.spf"), "PROC POCKET_A(REAL EDGE, REAL DEPTH)\nG1 Z=DEPTH\nG1 X=EDGE Y=EDGE\nG1 X0 Y0\nRET\n").unwrap();
    std::fs::write(subs.join("_N_L20_SPF"), "G0 Z5\nM17\n").unwrap();
    // A directory of the program's name is no program: the next name is tried.
    std::fs::create_dir_all(here.join("POCKET_A")).unwrap();
    let run = |extra: &[&std::ffi::OsStr]| {
        let out = std::process::Command::new(env!("FIVEAXIS_EXE")).args(["program", "analyze"]).arg(here.join("MAIN.MPF")).args(["--machine", "generic-bc-table"]).args(extra).output().unwrap();
        (out.status.code(), format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr)))
    };
    let (code, all) = run(&[std::ffi::OsStr::new("--subroutine-path"), subs.as_os_str()]);
    assert_eq!(code, Some(0), "{all}");
    let (code, all) = run(&[]);
    assert_eq!(code, Some(2), "{all}");
    assert!(all.contains("MAIN.MPF:4:5: error: L20: a call of the subprogram L20"), "{all}");
    // The call the control makes leaves every axis unknown: N50 moves from an unknown point.
    assert!(all.contains("MAIN.MPF:5:8: error: a move from where the moves under line 4's L20 (a subprogram not found, which the control runs)"), "{all}");
    assert_eq!(all.matches(": error:").count(), 2, "{all}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A program named with a letter and an underscore first (`F_TEST`, `E_TEST`: Siemens reserves the
/// prefixes `E_`, `F_` and `S_` for its own cycles, and "the first two characters should be letters or
/// underscores", NC programming 12/2019 §2.15 "Names") is called by its name alone, as a production
/// 840D sl grinding program calls `F_TP_GRINDING_PARAMETERS(..)` (its moves: the core's unit tests).
/// Two underscores first (`__TEST`) stay no name.
#[test]
fn a_program_named_with_a_letter_and_an_underscore_is_called() {
    let dir = std::env::temp_dir().join(format!("fiveaxis-fname-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("F_TEST.SPF"), "PROC F_TEST\nG1 X20 Y5 F200\nRET\n").unwrap();
    std::fs::write(dir.join("E_TEST.SPF"), "PROC E_TEST(REAL DEPTH)\nG1 Z=DEPTH F200\nRET\n").unwrap();
    std::fs::write(dir.join("__TEST.SPF"), "PROC __TEST\nG1 X1 F200\nRET\n").unwrap();
    let run = |main: &str| {
        let path = dir.join("CALL.MPF");
        std::fs::write(&path, main).unwrap();
        let out = std::process::Command::new(env!("FIVEAXIS_EXE")).args(["program", "analyze"]).arg(&path).args(["--machine", "generic-ac-table", "--json"]).output().unwrap();
        (out.status.code(), String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr))
    };
    let (code, all) = run("G90 G71\nG0 X0 Y0 Z10\nF_TEST\nE_TEST(-2.5)\nG1 X10 F100\nM30\n");
    assert_eq!(code, Some(0), "{all}");
    let (code, all) = run("G90 G71\nG0 X0 Y0 Z10\n__TEST\nM30\n");
    assert_eq!(code, Some(2), "{all}");
    assert!(all.contains("__TEST: not an instruction read here"), "{all}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Words written without blanks between them (`N20 T1D1M6`, `G1X10.5Y-20F300`, `G3X10.5Y-20CR=10`, as shop programs
/// hand-written at the control do): a word is an address letter and its digits, blanks only
/// separate (Programming Manual Fundamentals 12/2019 §2.2.2.1 and its table of characters), so they
/// read as the same program written with blanks. A letter run on after a number that is no word
/// (`X10ABC`) is still refused.
#[test]
fn words_written_without_blanks_read_as_with_them() {
    let joined = "N10 G90 G71 G94 R1=3\nN20 T1D1M6\nN30 S1000M3\nN40 G0X10Y20Z5\nN50 G1X10.5Y-20F300\nN60 G2X20.5Y-10I10J0\nN65 G3X10.5Y-20CR=10\nN66 G1X=R1+2\nN70 M30\n";
    let spaced = "N10 G90 G71 G94 R1=3\nN20 T1 D1 M6\nN30 S1000 M3\nN40 G0 X10 Y20 Z5\nN50 G1 X10.5 Y-20 F300\nN60 G2 X20.5 Y-10 I10 J0\nN65 G3 X10.5 Y-20 CR=10\nN66 G1 X=R1+2\nN70 M30\n";
    let (a, b) = (on_umc(joined), on_umc(spaced));
    assert!(errors(&a).is_empty() && errors(&b).is_empty(), "{:#?}", errors(&a));
    assert_eq!(a.blocks.len(), b.blocks.len());
    for (x, y) in a.blocks.iter().zip(&b.blocks) {
        assert_eq!((x.line, x.motion, x.targets.x, x.targets.y, x.targets.z, &x.events), (y.line, y.motion, y.targets.x, y.targets.y, y.targets.z, &y.events));
        assert_eq!(x.feed.map(|f| f.value_per_min), y.feed.map(|f| f.value_per_min));
    }
    assert!(close(blocks_of(&a, 5)[0].targets.y, -20.0) && blocks_of(&a, 6).iter().all(|b| b.motion == Motion::ArcCw));
    assert!(blocks_of(&a, 7).iter().all(|b| b.motion == Motion::ArcCcw) && close(blocks_of(&a, 8)[0].targets.x, 5.0));
    let p = on_umc("G90 G71\nG0 X10ABC Y5\n");
    assert!(errors(&p).iter().any(|(l, c, _)| *l == 2 && *c == 7), "{:#?}", errors(&p));
}

/// `C=DC(..)`, `C=ACP(..)`, `C=ACN(..)`: a modulo rotary axis to an absolute position (0-360 deg) the
/// shorter way, in the positive or the negative direction (840Di sl Programming Manual 11/2006,
/// "Absolute dimensions for rotary axes (DC, ACP, ACN)"), worked by hand from C at 20 deg on the
/// Spinner U5-620, whose C is a modulo axis (no end stops). On an axis with end stops, on a linear
/// axis and past a turn they are refused.
#[test]
fn dc_acp_and_acn_turn_a_modulo_axis_the_way_they_say() {
    let m = Machine::builtin("spinner-u5-620").unwrap();
    let c_after = |word: &str| -> Result<f64, Vec<(usize, usize, String)>> {
        let text = format!("G90 G71\nG0 X0 Y0 Z200 B0 C20\nG0 {word}\nM30\n");
        let p = read(&text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default().on(&m));
        match errors(&p).is_empty() {
            true => Ok(blocks_of(&p, 3).last().and_then(|b| b.targets.c).map(f64::to_degrees).unwrap_or_else(|| panic!("{word}: no C target"))),
            false => Err(errors(&p)),
        }
    };
    // A word repeated (as posts write them on each block) leaves the axis where it stands: no turn
    // from a position reached by arithmetic that falls a rounding short of the target.
    for word in ["C=ACP(50)", "C=ACN(30)", "C=ACP(0.1)", "C=ACN(359.7)", "C=DC(123.4)"] {
        let text = format!("G90 G71\nG0 X0 Y0 Z200 B0 C20\nG0 {word}\nG0 {word}\nG0 {word}\nM30\n");
        let p = read(&text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default().on(&m));
        assert!(errors(&p).is_empty(), "{word}: {:?}", errors(&p));
        let c: Vec<f64> = (3..=5).map(|l| blocks_of(&p, l).last().and_then(|b| b.targets.c).unwrap().to_degrees()).collect();
        assert!((c[1] - c[0]).abs() < 1e-9 && (c[2] - c[0]).abs() < 1e-9, "{word}: C {c:?} deg");
    }
    // (word, C after it, deg): 350 is 30 deg back from 20 (-10); 10 ahead is 350 on; 30 back is 350
    // back; DC to where C stands, no move; G91 does not make them incremental.
    for (word, want) in [("C=DC(350)", -10.0), ("C=ACP(10)", 370.0), ("C=ACN(10)", 10.0), ("C=ACN(30)", -330.0), ("C=ACP(200)", 200.0), ("C=DC(20)", 20.0), ("G91 C=DC(30)", 30.0)] {
        let c = c_after(word).unwrap_or_else(|e| panic!("{word}: {e:?}"));
        assert!((c - want).abs() < 1e-9, "{word}: C {c} deg, want {want}");
    }
    for (word, why) in [("C=DC(400)", "0 to 360 deg"), ("C=ACP(-10)", "0 to 360 deg"), ("X=DC(5)", "positions a modulo rotary axis (A, B, C), not X")] {
        let e = c_after(word).expect_err(word);
        assert!(e.iter().any(|(l, _, msg)| *l == 3 && msg.contains(why)), "{word}: {e:?}");
    }
    let limited = Machine::builtin("generic-bc-table").unwrap();
    let p = read("G90 G71\nG0 X0 Y0 Z200 B0 C20\nG0 B=DC(10)\nM30\n", Dialect::Sinumerik, "t.mpf", &ReadOptions::default().on(&limited));
    assert!(errors(&p).iter().any(|(l, c, msg)| *l == 3 && *c == 4 && msg.contains("B=DC(10): DC positions a modulo rotary axis, and B is a rotary axis with end stops")), "{:?}", errors(&p));
}

/// Under ORIWKS a tool vector is the frame's: after `ROT Z90` the vector (1, 0, 1) is the
/// workpiece's (0, 1, 1) and (0, 1, 1) its (-1, 0, 1) (Job Planning 03/2006 §7.2: vectors "relate to
/// the active frame and rotate when the frame rotates"); under ORIMKS there it is refused (the
/// machine's or the frame's, as MD21104 says). A plain G90 position of an axis DC/ACP/ACN made modulo
/// is refused where it stands beyond 0-360 deg (MD30455 decides the way); CYCLE84 with `_AXN` 1
/// (tapping along X) is refused.
#[test]
fn vectors_turn_with_the_frame_and_modulo_and_tapping_axes_fail_closed() {
    let m = Machine::builtin("generic-bc-table").unwrap();
    let opts = ReadOptions::default().on(&m);
    let text = "G90 G71 G17 G94\nG0 X0 Y0 Z100 B0 C0\nTRAORI\nG1 X0 Y0 Z100 A3=1 B3=0 C3=1 F1000\nROT Z90\nG1 X10 Y0 Z100 A3=1 B3=0 C3=1\nG1 X10 Y0 Z100 A3=0 B3=1 C3=1\nM30\n";
    let p = read(text, Dialect::Sinumerik, "t.mpf", &opts);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let s = std::f64::consts::FRAC_1_SQRT_2;
    for (line, want) in [(4, [s, 0.0, s]), (6, [0.0, s, s]), (7, [-s, 0.0, s])] {
        let v = blocks_of(&p, line).last().and_then(|b| b.targets.tool_axis).unwrap_or_else(|| panic!("line {line}: no vector"));
        assert!((0..3).all(|k| (v[k] - want[k]).abs() < 1e-9), "line {line}: {v:?}, want {want:?}");
    }
    let mks = read(&text.replace("TRAORI\n", "TRAORI\nORIMKS\n"), Dialect::Sinumerik, "t.mpf", &opts);
    assert!(errors(&mks).iter().any(|(l, _, m)| *l == 7 && m.contains("under ORIMKS in a rotated frame")), "{:?}", errors(&mks));
    // An ORIMKS in a line the control refuses (an arc with no centre) takes no effect: the vectors
    // after it stay the frame's.
    let refused = read(&text.replace("TRAORI\n", "TRAORI\nORIMKS G2 X5\n"), Dialect::Sinumerik, "t.mpf", &opts);
    assert!(!errors(&refused).is_empty() && errors(&refused).iter().all(|e| e.0 == 4), "{:?}", errors(&refused));
    // From 350 ACP(10) turns on to 370: G90 C20 is +10 as AC, -350 on an endless axis.
    let modulo = read("G90 G71 G17 G94\nG0 X0 Y0 Z0 B0 C350\nG0 C=ACP(10)\nG0 C20\nM30\n", Dialect::Sinumerik, "t.mpf", &opts);
    let e = errors(&modulo);
    assert!(e.iter().any(|(l, c, m)| (*l, *c) == (4, 4) && m.contains("MD30455")), "{e:?}");
    // From 0, DC(30) stands at 30: G90 C40 is +10 either way, read.
    let agree = read("G90 G71 G17 G94\nG0 X0 Y0 Z0 B0 C0\nG0 C=DC(30)\nG0 C40\nM30\n", Dialect::Sinumerik, "t.mpf", &opts);
    assert!(errors(&agree).is_empty(), "{:?}", errors(&agree));
    assert!((agree.blocks.iter().filter_map(|b| b.targets.c).last().unwrap().to_degrees() - 40.0).abs() < 1e-9);
    let tap = read("G90 G71 G17 G94\nT1 D1 M6\nS1000 M3\nG0 X0 Y0 Z50 B0 C0\nF100\nCYCLE84(10,0,2,-5,,,3,,1.0,,500,500,1,0,0,0)\nM30\n", Dialect::Sinumerik, "t.mpf", &opts);
    assert!(errors(&tap).iter().any(|(l, _, m)| *l == 6 && m.contains("_AXN=1")), "{:?}", errors(&tap));
}

/// A milling tool's length goes to the axis normal to the plane (NC programming 12/2019 §3.13.3.4
/// "Tool length and plane change": G17 Z, G18 Y, G19 X) unless setting data SD42940
/// TOOL_LENGTH_CONST keeps it: under G18/G19 with the tool's offsets on, the tool tip stands off the
/// programmed point by the length, which is not read: refused at each move there. With D0, or a
/// machine file whose `tool_length_const = 17` keeps the length on Z, the same moves read. A tool
/// change without a D turns the offsets on (the new tool's D1, MD20270 CUTTING_EDGE_DEFAULT).
#[test]
fn moves_under_g18_or_g19_with_tool_offsets_follow_sd42940() {
    let body = |plane: &str, edge: &str| format!("G17 G90 G71 G94\nT1\nM6 {edge}\nG0 X0 Y0 Z50\n{plane}\nG1 F500 X10 Z40\nG17\nG0 Z100\nM30\n");
    let file = fiveaxis::machine::builtin_file("generic-bc-table").unwrap();
    let plain = ReadOptions::default().on(&Machine::builtin("generic-bc-table").unwrap());
    for (plane, axis) in [("G18", "to Y"), ("G19", "to X")] {
        let e = errors(&read(&body(plane, "D1"), Dialect::Sinumerik, "t.mpf", &plain));
        assert!(e.len() == 1 && e[0].0 == 6 && e[0].2.contains(axis) && e[0].2.contains("SD42940"), "{plane}: {e:?}");
        assert!(errors(&read(&body(plane, "D0"), Dialect::Sinumerik, "t.mpf", &plain)).is_empty(), "{plane} D0");
    }
    // A refused line's G18 stays selected: the move after it is refused too; G53 Y (the length's axis
    // under G18) with the offsets on is refused as G53 Z is under G17.
    let e = errors(&read("T1 D1\nM6\nG0 X0 Y0 Z50\nG18 G0 X10 Z40\nG0 X20 Z30\nG17\nG0 Z100\nM30\n", Dialect::Sinumerik, "t.mpf", &plain));
    assert_eq!(e.iter().map(|e| e.0).collect::<Vec<_>>(), vec![4, 5], "{e:?}");
    let e = errors(&read("T1 D1\nM6\nG0 X0 Y0 Z50\nG18\nG53 G0 Y-100\nM30\n", Dialect::Sinumerik, "t.mpf", &plain));
    assert!(e.len() == 1 && e[0].0 == 5 && e[0].2.contains("G53 Y with the tool's offsets on"), "{e:?}");
    // A tool change without a D makes the new tool's D1 active (MD20270's default): D0 before it
    // does not last.
    let e = errors(&read("T1 D0\nM6\nG0 X0 Y0 Z50\nT2\nM6\nG18\nG1 F500 X10 Z40\nM30\n", Dialect::Sinumerik, "t.mpf", &plain));
    assert!(e.len() == 1 && e[0].0 == 7, "{e:?}");
    let kept = Machine::from_toml_str(&format!("tool_length_const = 17\n{file}"), "t").unwrap();
    assert!(errors(&read(&body("G18", "D1"), Dialect::Sinumerik, "t.mpf", &ReadOptions::default().on(&kept))).is_empty());
    let follows = Machine::from_toml_str(&format!("tool_length_const = 0\n{file}"), "t").unwrap();
    assert_eq!(errors(&read(&body("G18", "D1"), Dialect::Sinumerik, "t.mpf", &ReadOptions::default().on(&follows))).len(), 1);
}
