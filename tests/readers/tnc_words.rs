//! Klartext words that change how a TNC reads the feed or the tool, as hyperMILL's and NX's posts
//! write them: M109/M110/M111 (the feed on arcs at the cutting edge, iTNC 530 ISO user's manual
//! §7.4), M116/M117 (a rotary axis' feed in mm/min, iTNC 530 user's manual §12.5), `TOOL CALL
//! "NAME"` with the tool table's NAME column (TNC7 user's manual, "Tool name"), and `DR+F2777`.

use super::tnc_comp::table;
use super::*;

fn feed(b: &fiveaxis::program::Block) -> f64 {
    b.feed.unwrap().value_per_min
}

/// A pocket corner run with RL counter-clockwise (the tool inside): block 5 a quarter circle of
/// radius 20 about (20, 20) whose inside the tool runs on, block 7 one about (60, 20) bulging into
/// the pocket (the tool on its outside). `{m}` stands before the contour.
fn pocket(m: &str) -> String {
    format!(
        "0 BEGIN PGM M110 MM\n1 TOOL CALL 3 Z S3000\n2 L X+20 Y+20 Z-2 R0 FMAX\n3 {m}\n4 L X+20 Y+0 RL F400\n\
         5 CC X+20 Y+20\n6 C X+40 Y+20 DR+\n7 CC X+60 Y+20\n8 C X+80 Y+20 DR-\n9 L X+80 Y+40\n10 L X+60 Y+40 R0\n11 END PGM M110 MM\n"
    )
}

/// M110 slows the tool centre on an arc whose inside it runs on so that the cutting edge keeps F:
/// F (rho - r) / rho, rho the programmed radius (20 mm), r the tool's (3 mm); an arc whose outside
/// it runs on keeps F, and so does every arc under M111 or without compensation. M109 also speeds
/// up the outside arcs, F (rho + r) / rho; the TNC's transitional arcs at outside corners, whose
/// feed under it no manual gives, are refused.
#[test]
fn m110_keeps_the_feed_at_the_cutting_edge_on_inside_arcs() {
    let t = table("T3 P3 D6\n");
    let p = read(&pocket("M110"), Dialect::Klartext, "m.h", &t);
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let arcs: Vec<_> = p.blocks.iter().filter(|b| b.motion.is_arc() && matches!(b.number, Some(6 | 8))).collect();
    assert_eq!(arcs.len(), 2, "{arcs:#?}");
    let (inside, outside) = (arcs[0], arcs[1]);
    // The inside arc's tool-centre radius is 20 - 3: the cutting edge on 20 mm at 400 mm/min.
    let c = inside.arc.as_ref().unwrap().centre;
    let rc = (inside.targets.x.unwrap() - c[0]).hypot(inside.targets.y.unwrap() - c[1]) / MM;
    assert!((rc - 17.0).abs() < 1e-9, "{rc}");
    assert!((feed(inside) - 400.0 * 17.0 / 20.0).abs() < 1e-9, "{}", feed(inside));
    assert_eq!(feed(outside), 400.0);
    for m in ["M111", "M5"] {
        let p = read(&pocket(m), Dialect::Klartext, "m.h", &t);
        assert!(errors(&p).is_empty(), "{m}: {:#?}", p.diagnostics);
        assert!(p.blocks.iter().filter(|b| b.motion.is_arc()).all(|b| feed(b) == 400.0), "{m}");
    }
    // Without compensation the tool centre is on the contour: nothing to adjust.
    let plain = pocket("M110").replace(" RL F400", " F400").replace(" R0\n", "\n");
    let p = read(&plain, Dialect::Klartext, "m.h", &t);
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    assert!(p.blocks.iter().filter(|b| b.motion.is_arc()).all(|b| feed(b) == 400.0));
    // M109 speeds up the outside arc too: 400 x 23/20 = 460.
    let p = read(&pocket("M109"), Dialect::Klartext, "m.h", &t);
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let arcs: Vec<f64> = p.blocks.iter().filter(|b| b.motion.is_arc() && matches!(b.number, Some(6 | 8))).map(feed).collect();
    assert!((arcs[0] - 340.0).abs() < 1e-9 && (arcs[1] - 460.0).abs() < 1e-9, "{arcs:?}");
    // At an outside corner the TNC's transitional arc has no radius on the contour: its feed under
    // M109 is in no manual, refused there (block 6, after the corner at (40, 0) turning right).
    let corner = "0 BEGIN PGM M MM\n1 TOOL CALL 3 Z S3000\n2 L X-20 Y+20 Z-2 R0 FMAX\n3 M109\n4 L X+0 Y+0 RL F400\n5 L X+40\n6 L Y-40\n7 L X+60 Y-60 R0\n8 END PGM M MM\n";
    let p = read(corner, Dialect::Klartext, "m.h", &t);
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 7 && m.contains("M109")), "{:#?}", errors(&p));
}

/// M116 reads a rotary axis' F in mm/min at the tool's distance from the axis, which is not
/// modelled: a feed move of a rotary axis under it is refused, unless TCPM is on (M116 acts with
/// M128 only on axes M138 leaves out) or M117 has reset it; a rapid is not a feed move.
#[test]
fn m116_is_refused_only_where_it_sets_a_rotary_feed() {
    let hermle = fiveaxis::machine::Machine::hermle_c600u();
    let options = ReadOptions::default().on(&hermle);
    let run = |body: &str| read(&format!("0 BEGIN PGM M MM\n1 TOOL CALL 1 Z S3000\n{body}9 END PGM M MM\n"), Dialect::Klartext, "m.h", &options);
    let p = run("2 L M116\n3 L C+90 F1000\n");
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 4 && m.contains("M116")), "{:#?}", errors(&p));
    for ok in ["2 L M116\n3 L M128\n4 L C+90 F1000\n", "2 L M116\n3 L M117\n4 L C+90 F1000\n", "2 L M116\n3 L C+90 FMAX\n", "2 L M116\n3 L X+10 F1000\n"] {
        let p = run(ok);
        assert!(errors(&p).is_empty(), "{ok}: {:#?}", p.diagnostics);
    }
}

/// `TOOL CALL "NAME"`: RL/RR take the radius of the tool the table's NAME column names (in
/// capitals or not); tools sharing a name must share the radius, as which one the TNC calls depends
/// on the magazine.
#[test]
fn a_tool_called_by_name_compensates_by_its_row() {
    let text = "0 BEGIN PGM N MM\n1 TOOL CALL \"mill_d8\" Z S3000\n2 L X-10 Y+0 Z-2 R0 FMAX\n3 L X+0 Y+0 RL F300\n4 L X+20\n5 L X+30 Y+10 R0\n6 END PGM N MM\n";
    let tnc = |rows: &str| table(&format!("BEGIN TOOL.T MM\nT    NAME        L        R      DR\n{rows}[END]\n"));
    let p = read(text, Dialect::Klartext, "n.h", &tnc("1    MILL_D6     +50      +3     +0\n2    MILL_D8     +60      +4     -0.1\n"));
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    // Block 3 ends left of the first element (+X) at its start: (0, R + DR) = (0, 3.9).
    let b = p.blocks.iter().find(|b| b.number == Some(3)).unwrap();
    assert!((b.targets.y.unwrap() / MM - 3.9).abs() < 1e-12, "{:?}", b.targets);
    let p = read(text, Dialect::Klartext, "n.h", &tnc("2    MILL_D8     +60      +4     +0\n7    MILL_D8     +61      +4     +0\n"));
    assert!(errors(&p).is_empty(), "sister tools of one radius: {:#?}", p.diagnostics);
    let p = read(text, Dialect::Klartext, "n.h", &tnc("2    MILL_D8     +60      +4     +0\n7    MILL_D8     +61      +4.5   +0\n"));
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 4 && m.contains("tools 2 and 7")), "{:#?}", errors(&p));
    let p = read(text, Dialect::Klartext, "n.h", &tnc("1    MILL_D6     +50      +3     +0\n"));
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 4 && m.contains("no tool named \"mill_d8\"")), "{:#?}", errors(&p));
}

/// `CP IPA+90 IZ-1 DR+F200`, as hyperMILL writes it: the same blocks as with a space, said once.
#[test]
fn a_direction_written_together_with_the_next_word() {
    let body = |sep: &str| format!("0 BEGIN PGM H MM\n1 L X+10 Y+0 Z+0 F500\n2 CC X+0 Y+0\n3 CP IPA+90 IZ-1 DR+{sep}F200\n4 CP IPA-90 IZ-1 DR-{sep}F300\n5 END PGM H MM\n");
    let (spaced, joined) = (read(&body(" "), Dialect::Klartext, "h.h", &ReadOptions::default()), read(&body(""), Dialect::Klartext, "h.h", &ReadOptions::default()));
    assert!(errors(&spaced).is_empty() && errors(&joined).is_empty(), "{:#?}", joined.diagnostics);
    assert_eq!(spaced.blocks.len(), joined.blocks.len());
    for (a, b) in spaced.blocks.iter().zip(&joined.blocks) {
        assert_eq!((a.motion, a.targets, a.feed), (b.motion, b.targets, b.feed));
    }
    let said = joined.diagnostics.iter().filter(|d| d.message.contains("written together")).count();
    assert_eq!(said, 1, "{:#?}", joined.diagnostics);
}

/// `M128 F1000`: the F after M128 is the feed of the linear axes' compensating movements (iTNC 530
/// ISO user's manual §7.5, "L X+0 Y+38.5 IB-15 RL F125 M128 F1000"), not the path's: the path keeps
/// its own F (NX's posts write `L M128 F10000.` before cutting at F500), with a warning.
#[test]
fn the_feed_after_m128_is_not_the_paths() {
    let text = "0 BEGIN PGM T MM\n1 L X+0 Y+0 Z+10 F500\n2 L M128 F10000.\n3 L X+10\n4 L Y+10 F125 M128 F1000\n5 M128 F25000\n6 L X+0\n7 END PGM T MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let at = |n: u64| p.blocks.iter().find(|b| b.number == Some(n) && !b.targets.is_empty()).unwrap();
    assert_eq!([3, 4, 6].map(|n| feed(at(n))), [500.0, 125.0, 125.0]);
    let said: Vec<_> = p.diagnostics.iter().filter(|d| d.message.contains("compensating movements")).map(|d| d.line).collect();
    assert_eq!(said, [3, 5, 6], "{:#?}", p.diagnostics);
    // Heidenhain DIN/ISO alike (the manual quoted is its ISO one).
    let p = read("%T G71 *\nN10 G01 G90 X+0 Y+0 Z+10 F500 *\nN20 G01 X+10 F125 M128 F1000 *\nN30 X+20 *\nN99999999 %T G71 *\n", Dialect::Heidenhain, "t.i", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let at = |n: u64| p.blocks.iter().find(|b| b.number == Some(n) && !b.targets.is_empty()).unwrap();
    assert_eq!([20, 30].map(|n| feed(at(n))), [125.0, 125.0]);
    assert_eq!(p.diagnostics.iter().filter(|d| d.message.contains("compensating movements")).count(), 1, "{:#?}", p.diagnostics);
}

/// The TNC's preassigned parameters (iTNC 530 user's manual §11.11): Q108 the called tool's radius
/// R + DR from the tool table, in the program's unit; Q109 the tool axis (Z: 2); Q113 the main
/// program's unit (0 mm, 1 inch). Q108 without a tool table is refused, saying what it is.
#[test]
fn preassigned_q_parameters_hold_the_tool_and_the_unit() {
    let t = table("BEGIN TOOL.T MM\nT    NAME     L      R      DR\n2    D8       +60    +4     -0.1\n[END]\n");
    let text = |unit: &str| format!("0 BEGIN PGM Q {unit}\n1 TOOL CALL 2 Z S3000\n2 Q1 = Q108 * 2 + Q109 * 10 + Q113 * 100\n3 L X+Q1 Y+0 Z+0 F100\n4 END PGM Q {unit}\n");
    let x = |p: &Program| p.blocks.iter().find(|b| b.number == Some(3)).and_then(|b| b.targets.x);
    let p = read(&text("MM"), Dialect::Klartext, "q.h", &t);
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    // 2 x 3.9 + 2 x 10 + 0: 27.8 mm.
    assert!((x(&p).unwrap() / MM - 27.8).abs() < 1e-9, "{:?}", x(&p));
    let tenths = fiveaxis::machine::Machine::from_toml_str(&format!("tnc_inch_feed = \"tenths\"\n{}", fiveaxis::machine::builtin_file("generic-bc-table").unwrap()), "t").unwrap();
    let p = read(&text("INCH"), Dialect::Klartext, "q.h", &t.clone().on(&tenths));
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    // 2 x 3.9 mm in inches + 20 + 100, in inches.
    let want = (2.0 * 3.9 / 25.4 + 120.0) * 25.4;
    assert!((x(&p).unwrap() / MM - want).abs() < 1e-9, "{:?} {want}", x(&p).map(|v| v / MM));
    let p = read(&text("MM"), Dialect::Klartext, "q.h", &ReadOptions::default());
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 3 && m.contains("Q108 is the TNC's")), "{:#?}", errors(&p));
}

/// A datum shift leaves the tool where it stands: after X+10 and a shift of X+5 (cycle 7, DIN/ISO
/// G54), Y+5 keeps the tool at X 10 and the incremental X+1 takes it to X 11 ("incremental
/// coordinates ... referenced to the last programmed nominal position of the tool", iTNC 530 ISO
/// user's manual), X+6 of the new origin. G54 under G91, or with a rotary axis, is refused at the word.
#[test]
fn a_datum_shift_leaves_the_tool_where_it_stands() {
    let klartext = "0 BEGIN PGM K MM\n1 L X+10 Y+0 Z+0 R0 F1000\n2 CYCL DEF 7.0 DATUM SHIFT\n3 CYCL DEF 7.1 X+5\n4 L Y+5\n5 L IX+1\n6 L Y+6\n7 END PGM K MM\n";
    let iso = "%D G71 *\nN10 G01 X+10 Y+0 Z+0 F1000 *\nN20 G54 X+5 *\nN30 G01 Y+5 *\nN40 G91 G01 X+1 *\nN50 G90 G01 Y+6 *\nN99999 %D G71 *\n";
    for (text, dialect) in [(klartext, Dialect::Klartext), (iso, Dialect::Heidenhain)] {
        let p = read(text, dialect, "t", &ReadOptions::default());
        assert!(errors(&p).is_empty(), "{dialect:?}: {:?}", errors(&p));
        let xy: Vec<[f64; 2]> = ends(&p).into_iter().map(|e| [e[0], e[1]]).collect();
        assert_eq!(xy, vec![[10.0, 0.0], [10.0, 5.0], [11.0, 5.0], [11.0, 6.0]], "{dialect:?}");
    }
    refuses_each(
        Dialect::Heidenhain,
        &ReadOptions::default(),
        &[
            ("%D G71 *\nN10 G01 X+10 Y+0 Z+0 F1000 *\nN20 G91 G54 X+5 *\nN99999 %D G71 *\n", "3:13:", "under G91: an incremental shift is not read"),
            ("%D G71 *\nN10 G01 X+10 Y+0 Z+0 F1000 *\nN20 G54 X+0 Y+0 Z+0 C+90 *\nN99999 %D G71 *\n", "3:21:", "a rotary axis' shift is not read"),
        ],
    );
    // M118's axis values are the handwheel's travel (iTNC 530: "L X+0 Y+38.5 RL F125 M118 X1 Y1"):
    // the block moves Z only.
    let p = read("%D G71 *\nN10 G01 X+10 Y+0 Z+0 F1000 *\nN20 G00 Z+60 M118 X+2 Y+2 *\nN99999 %D G71 *\n", Dialect::Heidenhain, "t", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert_eq!(ends(&p).last().copied(), Some([10.0, 0.0, 60.0]));
}

/// The TNC's M118 takes the axis values after it: the handwheel's travel ("L X+0 Y+38.5 RL F125 M118
/// X1 Y1", iTNC 530 user's manual), no move: in Klartext `L X+5 Y+0 F125 M118 X1 Y1` goes to X 5
/// Y 0, and `L R0 F125 M118 X1 Y1` moves nothing.
#[test]
fn m118_values_are_the_handwheels_in_klartext() {
    let text = "0 BEGIN PGM K MM\n1 L X+0 Y+0 Z+0 R0 F1000\n2 L X+5 Y+0 F125 M118 X1 Y1\n3 L R0 F125 M118 X1 Y1\n4 END PGM K MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert_eq!(ends(&p).last().copied(), Some([5.0, 0.0, 0.0]));
}
