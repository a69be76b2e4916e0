//! `RND` and `CHF` in a running Klartext program: the contour element before one is held until the
//! element after it is read, then both are cut back to where the rounding arc or the chamfer
//! ([`crate::program::corner`]) leaves and meets them, and the three go out in order (through radius
//! compensation when it is on: the TNC offsets the rounded contour). iTNC 530 user's manual
//! 60642x-03 §6.4 "Corner rounding RND": "The rounding arc must be machinable by the called tool",
//! "In the preceding and subsequent contour blocks, both coordinates must lie in the plane of the
//! rounding arc", "The feed rate F is effective only in the RND block", "The corner point is cut off
//! by the rounding arc and is not part of the contour"; TNC 620 Klartext 01/2022 §5.4 "Chamfer": "a
//! chamfer ... between two straight lines", "You cannot start a contour with a CHF block".

use nalgebra::{Matrix3, Vector3};

use super::exec::Exec;
use super::{label, FeedWord, KWord, Kind, Shape, Stmt, Val};
use crate::program::corner::{chamfer, round, Element};
use crate::program::cutter_comp::{tnc_said, ArcFeed, Fail, TncComp};
use crate::program::interp::Interpreter;
use crate::program::lex::Diags;
use crate::program::{ArcSpec, Block, Feed, FeedMode, Motion, Plane};
use crate::units::MM;

/// A contour element placed one statement late, in case an `RND` or `CHF` follows it: its block
/// and its programmed start and end (program coordinates, m, rad), with the unit and tilted plane
/// it was read in.
#[derive(Debug, Clone)]
pub(super) struct Held {
    pub(super) b: Block,
    pub(super) start: [f64; 6],
    pub(super) end: [f64; 6],
    pub(super) unit: f64,
    pub(super) tilt: Option<Matrix3<f64>>,
    /// How its feed on an arc is read (M109/M110/M111 in force).
    pub(super) arc_feed: ArcFeed,
}

/// Compensation stopped placing a block: at its line and column, and why.
#[derive(Debug)]
pub(super) struct Stop {
    pub(super) line: usize,
    pub(super) col: usize,
    pub(super) why: Fail,
}

/// The most blocks that move nothing (a pole `CC`) kept behind a held element, in their order: past
/// it the element and they go out, a corner waiting for the next element refused.
const MAX_TRAILING: usize = 1000;

/// An `RND` or `CHF` read, waiting for the element after it: its size (m), its own feed (program
/// unit per minute), and where it stands.
#[derive(Debug, Clone)]
pub(super) struct Pending {
    round: bool,
    size: f64,
    feed: Option<f64>,
    line: usize,
    col: usize,
    number: Option<u64>,
}

impl Pending {
    fn name(&self) -> &'static str {
        if self.round {
            "RND"
        } else {
            "CHF"
        }
    }
}

/// What a contour element an `RND` or `CHF` joins may not be, said of a statement (`comp_on`:
/// radius compensation on before it, so that `RL`/`RR` repeat it): why not, if not.
pub(super) fn not_an_element(kind: &Kind<'_>, comp_on: bool) -> Option<&'static str> {
    match kind {
        Kind::Move { shape: Shape::LineNormal, .. } => Some("an LN block (a line with a surface normal) is not a contour element of the plane"),
        Kind::Move { feed: FeedWord::Max, .. } => Some("a block at FMAX is not a contour element it joins (the corner's feed is not in the manuals read here)"),
        Kind::Move { comp: Some((None, _)), .. } => Some("an R0 block is not a contour element it joins (compensation ends there)"),
        Kind::Move { comp: Some((Some(_), _)), .. } if !comp_on => Some("the block that starts RL/RR is not a contour element it joins (an approach on a rounding arc is not read)"),
        Kind::Move { m, .. } if m.iter().any(|w| matches!(w.val, Val::Num(v) if [89.0, 91.0, 92.0, 99.0].contains(&v))) => {
            Some("a block with M91/M92 machine coordinates or a cycle call (M89, M99) is not a contour element it joins")
        }
        Kind::Move { axes, .. } if axes.is_empty() => Some("a block without coordinates moves nothing: it is no contour element it joins"),
        Kind::Move { .. } => None,
        _ => Some("the block after it is not a contour element (a line or circle in the working plane)"),
    }
}

impl Exec {
    /// Run one statement: an `RND`/`CHF` waits for the element after it, every other statement first
    /// places the element held for one ([`Held`]) unless it is that element. True if the program
    /// ends here (M2, M30, or the TNC stopped).
    pub(super) fn run<'a>(&mut self, s: &Stmt<'a>, interp: &mut Interpreter, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        if let Kind::Corner { round, size, feed } = &s.kind {
            self.corner(s, *round, size, feed.as_ref(), interp, diags);
            return false;
        }
        // A pole (CC) or a parameter set between the elements moves nothing: the corner waits on.
        let between = matches!(s.kind, Kind::Centre(_) | Kind::Assign { .. });
        if let (Some(c), false) = (&self.pending, between) {
            if let Some(why) = not_an_element(&s.kind, self.comp.side().is_some()) {
                let c = c.clone();
                self.refuse(&c, why, diags);
            }
        }
        if self.pending.is_none() && !between && self.flush(out, diags, interp) {
            return true;
        }
        let ends = self.step(s, interp, out, diags);
        if let (Some(c), false) = (self.pending.clone(), between) {
            // The element after it was not read (its error said why): the corner is not made.
            self.refuse(&c, "the block after it was not read", diags);
            if self.flush(out, diags, interp) {
                return true;
            }
        }
        ends
    }

    /// `RND R` or `CHF` at `s`: kept for the element after it, if the one before it is held.
    fn corner(&mut self, s: &Stmt<'_>, round: bool, size: &KWord<'_>, feed: Option<&KWord<'_>>, interp: &Interpreter, diags: &mut Diags) {
        let name = if round { "RND" } else { "CHF" };
        let not_used = |diags: &mut Diags| diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
        if self.pending.is_some() {
            diags.error(s.line, s.col, format!("{name} right after another RND or CHF: no contour element between them"));
            return not_used(diags);
        }
        if self.held.is_none() {
            diags.error(s.line, s.col, format!("{name}: the block before it is not a contour element it joins: a line or circle in the working plane at a feed (not FMAX, R0, the block that starts RL/RR, LN, M91/M92 or a cycle call; \"You cannot start a contour with\" it, TNC 620 user's manual §5.4)"));
            return not_used(diags);
        }
        let unit = interp.unit();
        let Some(v) = self.value(size, s.line, diags) else { return not_used(diags) };
        let feed = match feed {
            Some(f) => match self.value(f, s.line, diags) {
                Some(v) if v > 0.0 && v.is_finite() => Some(v),
                Some(v) => {
                    diags.error(s.line, f.col, format!("F{v}: expected a positive feed"));
                    return not_used(diags);
                }
                None => return not_used(diags),
            },
            None => None,
        };
        self.pending = Some(Pending { round, size: v * unit, feed, line: s.line, col: s.col, number: s.number });
    }

    /// The program ends: a corner still waiting has no element after it.
    pub(super) fn end_corner(&mut self, diags: &mut Diags) {
        if let Some(c) = self.pending.clone() {
            self.refuse(&c, "no contour element after it before the program ends", diags);
        }
    }

    /// The corner `c` is not made: why, at its block.
    fn refuse(&mut self, c: &Pending, why: &str, diags: &mut Diags) {
        diags.error(c.line, c.col, format!("{}: {why}", c.name()));
        diags.warning(c.line, c.col, format!("block {} not used", label(c.number, c.line)));
        self.pending = None;
    }

    /// Place the element held for a corner, if any, as it was programmed, and what stands behind
    /// it. True if compensation stopped the program there.
    pub(super) fn flush(&mut self, out: &mut Vec<Block>, diags: &mut Diags, interp: &mut Interpreter) -> bool {
        let Some(h) = self.held.take() else { return false };
        match self.place_held(h, out) {
            Ok(()) => false,
            Err(stop) => {
                self.stopped(&stop, diags, interp);
                true
            }
        }
    }

    /// The flow leaves the statement after a pending corner (a call, a jump, a return, a block not
    /// read): the corner joins two elements one after the other in the program, so it is refused
    /// there, and the held element goes out. True if compensation stopped the program.
    pub(super) fn interrupt(&mut self, why: &str, out: &mut Vec<Block>, diags: &mut Diags, interp: &mut Interpreter) -> bool {
        let Some(c) = self.pending.clone() else { return false };
        self.refuse(&c, why, diags);
        self.flush(out, diags, interp)
    }

    /// Compensation could not go on: the TNC stops at the block.
    pub(super) fn stopped(&mut self, stop: &Stop, diags: &mut Diags, interp: &mut Interpreter) {
        diags.error(stop.line, stop.col, format!("radius compensation: {}", tnc_said(&stop.why)));
        self.comp = TncComp::default();
        self.held = None;
        self.trailing.clear();
        self.pending = None;
        interp.halted = true;
    }

    /// A block out: through radius compensation while it is on.
    pub(super) fn place(&mut self, h: Held, out: &mut Vec<Block>) -> Result<(), Stop> {
        if self.comp.busy() {
            let (line, col) = (h.b.line, h.b.column);
            self.comp.feed(h.b, h.start, h.end, h.unit, h.tilt, h.arc_feed, out).map_err(|why| Stop { line, col, why })
        } else {
            out.push(h.b);
            Ok(())
        }
    }

    /// The held element out, then the blocks kept behind it.
    fn place_held(&mut self, h: Held, out: &mut Vec<Block>) -> Result<(), Stop> {
        self.place(h, out)?;
        self.place_trailing(out)
    }

    fn place_trailing(&mut self, out: &mut Vec<Block>) -> Result<(), Stop> {
        for t in std::mem::take(&mut self.trailing) {
            self.place(t, out)?;
        }
        Ok(())
    }

    /// The element `n` after a pending corner: the element held before it and `n` cut back to the
    /// corner's ends, the corner between them; `n` held in turn if `hold` (another corner may
    /// follow it). A corner that cannot be made is an error at its block, both elements placed as
    /// programmed.
    pub(super) fn join(&mut self, n: Held, hold: bool, interp: &Interpreter, out: &mut Vec<Block>, diags: &mut Diags) -> Result<(), Stop> {
        if n.b.targets.is_empty() && self.held.is_some() {
            // A block that moves nothing (a pole) waits behind the held element, in its order.
            if self.trailing.len() < MAX_TRAILING {
                self.trailing.push(n);
                return Ok(());
            }
            if let Some(c) = self.pending.take() {
                self.refuse(&c, &format!("more than {MAX_TRAILING} blocks stand between it and the next contour element"), diags);
            }
        }
        let (Some(c), Some(p)) = (self.pending.take(), self.held.take()) else {
            // No corner between (a corner is read only after a held element): what is held goes first.
            if let Some(p) = self.held.take() {
                self.place_held(p, out)?;
            }
            return self.next(n, hold, out);
        };
        match make(&c, &p, &n, interp.plane(), interp.feed_state().2) {
            Ok((p2, corner, n2)) => {
                // The blocks kept behind the element go out in the program's order about the corner.
                self.place(p2, out)?;
                let after = self.trailing.iter().position(|t| t.b.line > c.line).unwrap_or(self.trailing.len());
                let later = self.trailing.split_off(after);
                self.place_trailing(out)?;
                self.place(corner, out)?;
                self.trailing = later;
                self.place_trailing(out)?;
                self.next(n2, hold, out)
            }
            Err(why) => {
                self.refuse(&c, &why, diags);
                self.place_held(p, out)?;
                self.next(n, hold, out)
            }
        }
    }

    /// A contour element placed, or held for a corner after it.
    pub(super) fn next(&mut self, n: Held, hold: bool, out: &mut Vec<Block>) -> Result<(), Stop> {
        if hold {
            self.held = Some(n);
            Ok(())
        } else {
            self.place(n, out)
        }
    }
}

/// The element a held block is in the working plane's coordinates (`axes`: its two axes and the
/// tool axis), or why it cannot be one a corner joins.
fn element(h: &Held, axes: (usize, usize, usize), which: &str) -> Result<Element, String> {
    let (a0, a1, a2) = axes;
    let still = |k: usize| (h.end[k] - h.start[k]).abs() <= 1e-12 * (1.0 + h.end[k].abs());
    if !still(a2) || !(3..6).all(still) {
        return Err(format!("the element {which} it moves along the tool axis or a rotary axis: \"both coordinates must lie in the plane of the rounding arc\" (iTNC 530 user's manual §6.4)"));
    }
    let (from, to) = ([h.start[a0], h.start[a1]], [h.end[a0], h.end[a1]]);
    match (&h.b.arc, h.b.motion) {
        (Some(spec), Motion::ArcCw | Motion::ArcCcw) => {
            if spec.extra_turns > 0 {
                return Err(format!("the element {which} it is a helix of more than one turn"));
            }
            let c = Vector3::from(spec.centre);
            let c = h.tilt.map_or(c, |r| r.transpose() * c);
            Ok(Element::Arc { from, to, centre: [c[a0], c[a1]], ccw: h.b.motion == Motion::ArcCcw })
        }
        (_, Motion::Linear) => Ok(Element::Line { from, to }),
        _ => Err(format!("the element {which} it is not a line or circle at a feed")),
    }
}

/// `v` with its working-plane coordinates (`axes`) at `p`.
fn at(v: [f64; 6], axes: (usize, usize, usize), p: [f64; 2]) -> [f64; 6] {
    let mut v = v;
    (v[axes.0], v[axes.1]) = (p[0], p[1]);
    v
}

/// A block's targets ending at `v` (program coordinates, in a tilted plane the plane's): its two
/// plane axes written, so that it ends there wherever it starts (all three in a tilted plane, whose
/// axes are not the workpiece's).
fn aim(b: &mut Block, v: [f64; 6], axes: (usize, usize, usize), tilt: Option<Matrix3<f64>>) {
    match tilt {
        Some(r) => {
            let w = r * Vector3::new(v[0], v[1], v[2]);
            (b.targets.x, b.targets.y, b.targets.z) = (Some(w.x), Some(w.y), Some(w.z));
        }
        None => {
            for k in [axes.0, axes.1] {
                *[&mut b.targets.x, &mut b.targets.y, &mut b.targets.z][k] = Some(v[k]);
            }
        }
    }
}

/// The element before cut back, the corner, the element after cut back; why not.
fn make(c: &Pending, p: &Held, n: &Held, plane: Plane, mode: FeedMode) -> Result<(Held, Held, Held), String> {
    let axes = plane.axes();
    let (before, after) = (element(p, axes, "before")?, element(n, axes, "after")?);
    let size = c.size;
    let (t1, t2, arc) = if c.round {
        let r = round(&before, &after, size).map_err(|why| format!("R{}: {why}", size / p.unit))?;
        (r.from, r.to, Some((r.centre, r.ccw)))
    } else {
        let (t1, t2) = chamfer(&before, &after, size).map_err(|why| format!("{}: {why}", size / p.unit))?;
        (t1, t2, None)
    };
    // A corner that uses up a whole arc leaves a rest of no length, which reads as a full circle.
    let short = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) <= 1e-9 * (1.0 + size / p.unit);
    if matches!(before, Element::Arc { .. }) && short([p.start[axes.0], p.start[axes.1]], t1) {
        return Err(format!("the corner takes up the whole arc before it: {}", if c.round { "the radius is too large for it" } else { "the chamfer is too long for it" }));
    }
    if matches!(after, Element::Arc { .. }) && short(t2, [n.end[axes.0], n.end[axes.1]]) {
        return Err(format!("the corner takes up the whole arc after it: {}", if c.round { "the radius is too large for it" } else { "the chamfer is too long for it" }));
    }
    let (v1, v2) = (at(p.end, axes, t1), at(p.end, axes, t2));
    let mut p2 = p.clone();
    aim(&mut p2.b, v1, axes, p.tilt);
    p2.end = v1;
    let mut k = p.b.clone();
    (k.line, k.column, k.number) = (c.line, c.col, c.number);
    (k.events, k.dwell_s) = (Vec::new(), None);
    aim(&mut k, v2, axes, p.tilt);
    k.motion = Motion::Linear;
    k.arc = None;
    if let Some((centre, ccw)) = arc {
        k.motion = if ccw { Motion::ArcCcw } else { Motion::ArcCw };
        let v = at(p.end, axes, centre);
        let v = Vector3::new(v[0], v[1], v[2]);
        let (centre, frame) = match p.tilt {
            Some(r) => (r * v, Some(ArcSpec::frame_of(&r))),
            None => (v, None),
        };
        k.arc = Some(Box::new(ArcSpec { plane, centre: [centre.x, centre.y, centre.z], extra_turns: 0, frame }));
    }
    // The corner's own F, for it alone (in the program's unit per minute); else the feed in effect.
    if let Some(f) = c.feed {
        k.feed = Some(Feed { value_per_min: f * p.unit / MM, rotary_per_min: f, mode });
    }
    let corner = Held { b: k, start: v1, end: v2, unit: p.unit, tilt: p.tilt, arc_feed: p.arc_feed };
    let mut n2 = n.clone();
    aim(&mut n2.b, n.end, axes, n.tilt);
    n2.start = v2;
    Ok((p2, corner, n2))
}
