//! Tilted working planes as a block states them: `PLANE SPATIAL/EULER/VECTOR/POINTS/RELATIV/AXIAL/
//! RESET` with `TURN`/`STAY`/`MOVE`, `SEQ`, `COORD ROT`/`TABLE ROT`, and cycle 19 (iTNC 530 User's Manual,
//! "Tilting the working plane"): parsed, then run (the axes the control picks, its Q120-Q122, the
//! frame it sets); the plane's geometry is [`crate::program::plane`]'s.

use super::*;
use std::borrow::Cow;

use super::exec::Exec;
use crate::program::interp::{Dimension, Interpreter, Word};
use crate::program::Block;
use crate::units::DEG;

/// How a `PLANE` states the working plane.
#[derive(Debug, Clone)]
pub(super) enum PlaneForm<'a> {
    /// `SPATIAL SPA SPB SPC`, deg (and cycle 19 with spatial angles).
    Spatial([KWord<'a>; 3]),
    /// `EULER EULPR EULNU EULROT`, deg.
    Euler([KWord<'a>; 3]),
    /// `VECTOR BX BY BZ NX NY NZ`.
    Vector([KWord<'a>; 6]),
    /// `POINTS P1X P1Y P1Z P2X P2Y P2Z P3X P3Y P3Z`: three points of the plane.
    Points([KWord<'a>; 9]),
    /// `RELATIV SPA|SPB|SPC`: one turn about the tilted plane's own axis (0 X, 1 Y, 2 Z).
    Relativ(usize, KWord<'a>),
    /// `AXIAL A B C` (and cycle 19 with axis angles): the rotary axes' positions, deg.
    Axial(Vec<KWord<'a>>),
    /// `RESET`, or cycle 19 with nothing.
    Reset,
}

/// How a `PLANE` positions the rotary axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum PlaneMode {
    /// `TURN`: the rotary axes move, the linear ones stay.
    Turn,
    /// `STAY`: nothing moves; the angles go to Q120 (A), Q121 (B), Q122 (C).
    Stay,
    /// `MOVE DIST`: the rotary axes turn about a point DIST below the tool tip along the tool axis,
    /// which the linear axes keep where it is on the workpiece.
    Move,
    /// Cycle 19: nothing moves (the program positions the axes itself), no Q parameters.
    Cycle,
}

/// A `PLANE` statement.
#[derive(Debug, Clone)]
pub(super) struct PlaneStmt<'a> {
    pub(super) form: PlaneForm<'a>,
    pub(super) mode: PlaneMode,
    pub(super) feed: FeedWord<'a>,
    pub(super) choice: crate::program::plane::Choice,
    /// Cycle 19's spatial angles (a machine setting decides between them and axis angles).
    pub(super) cycle: bool,
    /// `MB n|MAX` with `TURN` or `MOVE`: the retract along the tool axis before tilting, as `M140 MB`
    /// (its distance, `None` for MAX; and the word's column).
    pub(super) retract: Option<(Option<KWord<'a>>, usize)>,
    /// `DIST` with `MOVE`: the centre of rotation's distance from the tool tip, along the tool axis.
    pub(super) dist: Option<KWord<'a>>,
}

/// `PLANE SPATIAL SPA.. SPB.. SPC.. | EULER EULPR.. EULNU.. EULROT.. | VECTOR BX.. BY.. BZ.. NX.. NY..
/// NZ.. | RELATIV SPA..|SPB..|SPC.. | AXIAL A.. B.. C.. | RESET`, then `TURN`, `STAY` or `MOVE DIST..`,
/// `F`/`FMAX`/`F MAX`, `SEQ+`/`SEQ-`, `COORD ROT`/`TABLE ROT`, in any order (iTNC 530 User's Manual
/// 340 422 §9.2-9.8; PLANE RESET without positioning is hyperMILL's `PLANE RESET STAY`).
pub(super) fn plane<'a>(toks: &[(&'a str, usize)], line: usize, col: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let form_name = upper(toks.get(1).map_or("", |t| t.0));
    let mut rest = toks[2.min(toks.len())..].iter().copied().peekable();
    let mut values: Vec<(String, KWord<'a>)> = Vec::new();
    let (mut mode, mut feed, mut choice, mut retract, mut dist) = (None, FeedWord::None, crate::program::plane::Choice::default(), None, None);
    let addresses: &[&str] = match form_name.as_ref() {
        "SPATIAL" => &["SPA", "SPB", "SPC"],
        "EULER" => &["EULPR", "EULNU", "EULROT"],
        "VECTOR" => &["BX", "BY", "BZ", "NX", "NY", "NZ"],
        "POINTS" => &["P1X", "P1Y", "P1Z", "P2X", "P2Y", "P2Z", "P3X", "P3Y", "P3Z"],
        "RELATIV" => &["SPA", "SPB", "SPC"],
        "AXIAL" => &["A", "B", "C"],
        "RESET" => &[],
        "PROJECTED" => {
            diags.error(line, col, "PLANE PROJECTED: this form of the working plane is not modelled yet (the sign of its projection angles is the manual's figure, not at hand; SPATIAL, EULER, VECTOR, POINTS, RELATIV, AXIAL and RESET are)");
            return None;
        }
        other => {
            diags.error(line, col, format!("PLANE {}: expected SPATIAL, PROJECTED, EULER, VECTOR, POINTS, RELATIV, AXIAL or RESET", excerpt(other)));
            return None;
        }
    };
    while let Some((tok, c)) = rest.next() {
        let u = upper(tok);
        let next_is = |rest: &mut std::iter::Peekable<std::iter::Copied<std::slice::Iter<'_, (&'a str, usize)>>>, w: &str| {
            let yes = rest.peek().is_some_and(|(t, _)| t.eq_ignore_ascii_case(w));
            if yes {
                rest.next();
            }
            yes
        };
        match u.as_ref() {
            "TURN" => mode = Some(PlaneMode::Turn),
            "STAY" => mode = Some(PlaneMode::Stay),
            "MOVE" => mode = Some(PlaneMode::Move),
            "FMAX" => feed = FeedWord::Max,
            "F" if next_is(&mut rest, "MAX") => feed = FeedWord::Max,
            "SEQ+" => choice.seq = Some(true),
            "SEQ-" => choice.seq = Some(false),
            "COORD" if next_is(&mut rest, "ROT") => choice.table_rot = Some(false),
            "TABLE" if next_is(&mut rest, "ROT") => choice.table_rot = Some(true),
            // TNC 620 User's Manual 10/2017, "The PLANE function", positioning: "The retraction path
            // MB is effective incrementally from the current tool position in the active tool axis
            // direction that the control approaches before tilting. MB MAX positions the tool just
            // before the software limit switch": M140 MB's rule.
            "MB" if retract.is_none() => match super::blocks::mb_value(rest.peek().copied(), line, diags) {
                Some(d) => {
                    rest.next();
                    retract = Some((d.ok()?, c));
                }
                None => {
                    diags.error(line, c, "PLANE ... MB: expected a retract distance or MAX");
                    return None;
                }
            },
            "DIST" if dist.is_none() => match rest.peek().copied().filter(|(v, _)| v.starts_with(|ch: char| ch.is_ascii_digit() || "+-.Q".contains(ch))) {
                Some((v, vc)) => {
                    rest.next();
                    dist = Some(value_word("DIST", v, v, vc, line, diags)?);
                }
                None => {
                    diags.error(line, c, "PLANE ... DIST: expected the distance of the centre of rotation from the tool tip");
                    return None;
                }
            },
            _ => {
                let (addr, v) = point_word(tok).unwrap_or_else(|| split_word(tok));
                match (addresses.iter().find(|a| **a == addr.as_ref()), addr.as_ref()) {
                    (None, "MB") if retract.is_none() && !v.is_empty() => retract = Some((Some(value_word("MB", v, tok, c, line, diags)?), c)),
                    (None, "DIST") if dist.is_none() && !v.is_empty() => dist = Some(value_word("DIST", v, tok, c, line, diags)?),
                    (Some(a), _) => {
                        if values.iter().any(|(n, _)| n == a) {
                            diags.error(line, c, format!("PLANE: {a} written twice"));
                            return None;
                        }
                        let w = value_word(addr_static(a), v, tok, c, line, diags)?;
                        values.push((a.to_string(), w));
                    }
                    (None, "F") => feed = FeedWord::Value(value_word("F", v, tok, c, line, diags)?),
                    _ => {
                        diags.error(line, c, format!("PLANE {form_name}: unexpected '{}'", excerpt(tok)));
                        return None;
                    }
                }
            }
        }
    }
    let Some(mode) = mode else {
        diags.error(line, col, format!("PLANE {form_name}: expected TURN, MOVE or STAY (how the rotary axes are positioned)"));
        return None;
    };
    // TNC 620 User's Manual 10/2017, "The PLANE function", automatic positioning: DIST is MOVE's
    // ("Dist. tool tip - center of rot."); what the TNC takes without it is not at hand.
    match (&dist, mode) {
        (None, PlaneMode::Move) => {
            diags.error(line, col, format!("PLANE {form_name} ... MOVE without DIST: the distance of the centre of rotation from the tool tip is needed (what the TNC takes without it is not at hand)"));
            return None;
        }
        (Some(d), PlaneMode::Turn | PlaneMode::Stay) => {
            diags.error(line, d.col, format!("PLANE {form_name}: DIST goes with MOVE (the centre of rotation of its compensating move)"));
            return None;
        }
        _ => {}
    }
    if let (Some((_, c)), PlaneMode::Stay) = (&retract, mode) {
        diags.error(line, *c, format!("PLANE {form_name} ... STAY MB: a retract before tilting goes with TURN or MOVE (STAY moves nothing)"));
        return None;
    }
    let take = |name: &str| values.iter().find(|(n, _)| n == name).map(|(_, w)| w.clone());
    let all = |names: &[&str], diags: &mut Diags| -> Option<Vec<KWord<'a>>> {
        let v: Vec<Option<KWord<'a>>> = names.iter().map(|n| take(n)).collect();
        match v.iter().position(Option::is_none) {
            Some(k) => {
                diags.error(line, col, format!("PLANE {form_name}: expected {} (all of {})", names[k], names.join(" ")));
                None
            }
            None => Some(v.into_iter().flatten().collect()),
        }
    };
    let form = match form_name.as_ref() {
        "SPATIAL" => PlaneForm::Spatial(all(addresses, diags)?.try_into().ok()?),
        "EULER" => PlaneForm::Euler(all(addresses, diags)?.try_into().ok()?),
        "VECTOR" => PlaneForm::Vector(all(addresses, diags)?.try_into().ok()?),
        "POINTS" => PlaneForm::Points(all(addresses, diags)?.try_into().ok()?),
        "RELATIV" => match values.as_slice() {
            [(n, w)] => PlaneForm::Relativ(addresses.iter().position(|a| a == n).unwrap_or(0), w.clone()),
            _ => {
                diags.error(line, col, "PLANE RELATIV: expected one of SPA, SPB, SPC");
                return None;
            }
        },
        "AXIAL" if !values.is_empty() => PlaneForm::Axial(values.into_iter().map(|(_, w)| w).collect()),
        "AXIAL" => {
            diags.error(line, col, "PLANE AXIAL: expected the rotary axes' positions A, B or C");
            return None;
        }
        _ => PlaneForm::Reset,
    };
    Some(Kind::Plane(PlaneStmt { form, mode, feed, choice, cycle: false, retract, dist }))
}

/// A `PLANE POINTS` coordinate word (`P1X+0`, `P3Z-12.5`): its address (a digit inside, which
/// [`split_word`] would end it at) and value.
pub(super) fn point_word(tok: &str) -> Option<(Cow<'_, str>, &str)> {
    let b = tok.as_bytes();
    let is = b.len() > 3 && b[0].eq_ignore_ascii_case(&b'P') && (b'1'..=b'3').contains(&b[1]) && matches!(b[2].to_ascii_uppercase(), b'X' | b'Y' | b'Z');
    is.then(|| (upper(&tok[..3]), &tok[3..]))
}

/// The static address of a PLANE word.
pub(super) fn addr_static(a: &str) -> &'static str {
    ["SPA", "SPB", "SPC", "EULPR", "EULNU", "EULROT", "BX", "BY", "BZ", "NX", "NY", "NZ", "P1X", "P1Y", "P1Z", "P2X", "P2Y", "P2Z", "P3X", "P3Y", "P3Z", "A", "B", "C"]
        .into_iter()
        .find(|s| *s == a)
        .unwrap_or("PLANE")
}

/// `CYCL DEF 19.0 WORKING PLANE` (its name in the control's language) and `CYCL DEF 19.1 A.. B..
/// C.. [F..]`, or `19.1` alone, the reset (TNC 320 Cycle Programming 340 55x-04 §11.9): the plane
/// becomes effective as it is defined, nothing moves (the program positions the rotary axes). Its
/// angles are the rotary axes' positions or spatial angles as the machine is set up (iTNC 530 HSCI
/// Technical Manual §6.5.6, MP7500 bit 1): the runner decides.
pub(super) fn cycle19<'a>(toks: &[(&'a str, usize)], part: &str, line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let col = toks[0].1;
    match part {
        "0" => None,
        "1" => {
            let mut values = Vec::new();
            let feed = FeedWord::None;
            for &(tok, c) in &toks[3.min(toks.len())..] {
                let (addr, v) = split_word(tok);
                match addr.as_ref() {
                    "A" | "B" | "C" => values.push(value_word(addr_static(&addr), v, tok, c, line, diags)?),
                    // A feed in cycle 19: the machine positions the rotary axes itself at it (the
                    // cycle asks for one only then, MP7500 bit 2), which is not read.
                    "F" => {
                        diags.error(line, c, format!("CYCL DEF 19.1 with {}: on a machine set to position the rotary axes in cycle 19 (MP7500 bit 2) they turn at that feed, which is not read (position them in the program: L B.. C..)", excerpt(tok)));
                        return None;
                    }
                    _ => {
                        diags.error(line, c, format!("CYCL DEF 19.1: expected A, B, C (and F), found '{}'", excerpt(tok)));
                        return None;
                    }
                }
            }
            let form = if values.is_empty() { PlaneForm::Reset } else { PlaneForm::Axial(values) };
            Some(Kind::Plane(PlaneStmt { form, mode: PlaneMode::Cycle, feed, choice: Default::default(), cycle: true, retract: None, dist: None }))
        }
        _ => {
            diags.error(line, col, "CYCL DEF 19: expected CYCL DEF 19.0 and its name, or CYCL DEF 19.1 with the angles A, B, C");
            None
        }
    }
}

impl Exec {
    /// A `PLANE` or cycle 19: the working plane's frame, the rotary positions the control picks
    /// for it ([`crate::program::plane::solve`]), Q120-Q122 (`STAY`), the rotary move (`TURN`).
    pub(super) fn plane(&mut self, p: &PlaneStmt<'_>, s: &Stmt<'_>, interp: &mut Interpreter, out: &mut Vec<Block>, diags: &mut Diags) {
        use crate::program::plane;
        let what = if p.cycle { "CYCL DEF 19" } else { "PLANE" };
        let Some(machine) = self.machine.clone() else {
            diags.error(s.line, s.col, format!("{what}: a tilted working plane needs the machine's kinematics (--machine)"));
            return;
        };
        let letters: [char; 2] = [3, 4].map(|k| machine.axes[k].name.chars().next().unwrap_or('?').to_ascii_uppercase());
        let pos = interp.position();
        let current = letters.map(|l| "ABC".find(l).map_or(0.0, |k| pos[3 + k]));
        let deg = |w: &KWord<'_>, diags: &mut Diags| self.value(w, s.line, diags).map(|v| v * DEG);
        let before = diags.errors();
        let frame = match &p.form {
            PlaneForm::Reset => None,
            PlaneForm::Spatial(w) => {
                let v: Vec<f64> = w.iter().filter_map(|w| deg(w, diags)).collect();
                (v.len() == 3).then(|| plane::spatial(v[0], v[1], v[2]))
            }
            PlaneForm::Euler(w) => {
                let v: Vec<f64> = w.iter().filter_map(|w| deg(w, diags)).collect();
                (v.len() == 3).then(|| plane::euler_zxz(v[0], v[1], v[2]))
            }
            PlaneForm::Vector(w) => {
                let v: Vec<f64> = w.iter().filter_map(|w| self.value(w, s.line, diags)).collect();
                if v.len() == 6 {
                    match plane::from_vectors(nalgebra::Vector3::new(v[0], v[1], v[2]), nalgebra::Vector3::new(v[3], v[4], v[5])) {
                        Ok(r) => Some(r),
                        Err(why) => {
                            diags.error(s.line, s.col, format!("PLANE VECTOR: {why}"));
                            None
                        }
                    }
                } else {
                    None
                }
            }
            PlaneForm::Points(w) => {
                let v: Vec<f64> = w.iter().filter_map(|w| self.value(w, s.line, diags)).collect();
                let p = |k: usize| nalgebra::Vector3::new(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
                match (v.len() == 9).then(|| plane::from_points(p(0), p(1), p(2))) {
                    Some(Ok(r)) => Some(r),
                    Some(Err(why)) => {
                        diags.error(s.line, s.col, format!("PLANE POINTS: {why}"));
                        None
                    }
                    None => None,
                }
            }
            PlaneForm::Relativ(k, w) => deg(w, diags).map(|a| {
                let axis = nalgebra::Unit::new_normalize(nalgebra::Vector3::ith(*k, 1.0));
                interp.tilt().unwrap_or_else(nalgebra::Matrix3::identity) * *nalgebra::Rotation3::from_axis_angle(&axis, a).matrix()
            }),
            PlaneForm::Axial(w) => {
                // Axis positions: the tool's frame there (cycle 19 set up for spatial angles reads
                // them as those instead).
                let mut rot = current;
                let mut spatial = [0.0; 3];
                for w in w {
                    let Some(v) = deg(w, diags) else { continue };
                    let l = w.addr.chars().next().unwrap_or('?');
                    spatial["ABC".find(l).unwrap_or(0)] = v;
                    match letters.iter().position(|&m| m == l) {
                        Some(k) => rot[k] = v,
                        None if p.cycle && machine.cycle19_spatial => {}
                        None => diags.error(s.line, w.col, format!("{what}: the machine has no axis {l} (its rotary axes are {} and {})", letters[0], letters[1])),
                    }
                }
                Some(if p.cycle && machine.cycle19_spatial { plane::spatial(spatial[0], spatial[1], spatial[2]) } else { machine.chain.tool_frame(&rot) })
            }
        };
        if diags.errors() > before {
            return;
        }
        let Some(r) = frame else {
            // RESET with MOVE or TURN: the TNC turns the rotary axes back to their basic position
            // (STAY leaves them where they are); where that is, and MOVE's compensating move, are
            // not read.
            if matches!(p.mode, PlaneMode::Move | PlaneMode::Turn) {
                let (mode, what) = if p.mode == PlaneMode::Move { ("MOVE", "the rotary axes' turn back to their basic position, with its compensating move,") } else { ("TURN", "the rotary axes' turn back to their basic position") };
                diags.error(s.line, s.col, format!("PLANE RESET ... {mode}: {what} is not read (write PLANE RESET STAY and position the axes)"));
                return;
            }
            interp.set_tilt(None);
            return;
        };
        let axial = matches!(p.form, PlaneForm::Axial(_)) && !(p.cycle && machine.cycle19_spatial);
        let rot = if axial {
            let mut rot = current;
            if let PlaneForm::Axial(w) = &p.form {
                for w in w {
                    if let (Some(v), Some(k)) = (self.value(w, s.line, diags), letters.iter().position(|&m| Some(m) == w.addr.chars().next())) {
                        rot[k] = v * DEG;
                    }
                }
            }
            rot
        } else {
            match plane::solve(&machine, &r, current, p.choice) {
                Ok(sol) => {
                    if let Some(pole) = sol.pole {
                        let name = &machine.axes[pole.free_axis].name;
                        // Degrees to 3 decimals, a rounding of zero without its sign.
                        let deg3 = |v: f64| format!("{:.3}", if v.to_degrees().abs() < 5e-4 { 0.0 } else { v.to_degrees() });
                        let table = pole.table_rot.map_or("cannot turn it to the plane's X (a head axis)".into(), |t| format!("turns it to {} deg", deg3(t)));
                        let said = match p.choice.table_rot {
                            Some(true) => "the program says TABLE ROT",
                            Some(false) => "the program says COORD ROT",
                            None => "the program says neither, so it depends on the control's setting; read as COORD ROT",
                        };
                        diags.warning(
                            s.line,
                            s.col,
                            format!(
                                "{what} at the pole: the tool lies along {name}'s axis, which leaves {name} free; COORD ROT keeps it at {} deg, TABLE ROT {table}; {said} ({name} {} deg)",
                                deg3(pole.coord_rot),
                                deg3(sol.rot[pole.free_axis - 3])
                            ),
                        );
                    }
                    sol.rot
                }
                Err(why) => {
                    diags.error(s.line, s.col, format!("{what}: {why}"));
                    return;
                }
            }
        };
        // MOVE: the compensating move, in the frame before the plane; refused, it tilts nothing.
        if p.mode == PlaneMode::Move {
            let Some(d) = p.dist.as_ref() else { return };
            if !self.plane_move(d, &p.feed, rot, &letters, &machine, s, interp, out, diags) {
                return;
            }
        }
        // STAY, TURN and MOVE: the angles the control computed, in Q120 (A), Q121 (B), Q122 (C).
        if p.mode != PlaneMode::Cycle {
            for (k, l) in letters.iter().enumerate() {
                if let Some(i) = "ABC".find(*l) {
                    self.q.insert(format!("Q{}", 120 + i), rot[k] / DEG);
                }
            }
        } else if machine.cycle19_spatial {
            // Cycle 19 of spatial angles stores the axes' angles in Q120-Q122 too, the solution "on
            // the shorter path from the zero position" (TNC 320 Cycle Programming 340 55x-04 §11.9),
            // which is not the one read here: they are left unset, so a program reading them stops.
            for i in 0..3 {
                self.q.remove(&format!("Q{}", 120 + i));
            }
        }
        interp.set_tilt(Some(r));
        if p.mode == PlaneMode::Turn {
            let mut words: Vec<Word<'static>> = letters.iter().zip(rot).map(|(l, v)| Word { letter: *l, value: v / DEG, raw: Cow::Owned(format!("{:.6}", v / DEG)), column: s.col, dimension: Dimension::Modal }).collect();
            match &p.feed {
                FeedWord::Value(f) => {
                    let Some(v) = self.value(f, s.line, diags) else { return };
                    words.push(Word { letter: 'G', value: 1.0, raw: "1".into(), column: s.col, dimension: Dimension::Modal });
                    words.push(Word { letter: 'F', value: v, raw: Cow::Owned(f.raw.to_string()), column: f.col, dimension: Dimension::Modal });
                }
                _ => words.push(Word { letter: 'G', value: 0.0, raw: "0".into(), column: s.col, dimension: Dimension::Modal }),
            }
            if let Some(b) = interp.block_one(&words, s.line, s.col, s.number, diags) {
                out.push(b);
            }
        }
    }
}
