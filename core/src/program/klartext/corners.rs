//! `RND` and `CHF` in a running Klartext program: the contour element before one is held until the
//! element after it is read, then both are cut back to where the rounding arc or the chamfer
//! ([`crate::program::corner`]) leaves and meets them, and the three go out in order (through radius
//! compensation when it is on: the TNC offsets the rounded contour). iTNC 530 user's manual
//! 60642x-03 §6.4 "Corner rounding RND": "The rounding arc must be machinable by the called tool",
//! "In the preceding and subsequent contour blocks, both coordinates must lie in the plane of the
//! rounding arc", "The feed rate F is effective only in the RND block", "The corner point is cut off
//! by the rounding arc and is not part of the contour"; TNC 620 Klartext 01/2022 §5.4 "Chamfer": "a
//! chamfer ... between two straight lines", "You cannot start a contour with a CHF block".

use super::exec::Exec;
use super::{label, FeedWord, KWord, Kind, Shape, Stmt, Val};
pub(super) use crate::program::corner_cut::{Cut, Held};
use crate::program::corner_cut::make;
use crate::program::cutter_comp::{tnc_said, Fail, TncComp};
use crate::program::interp::Interpreter;
use crate::program::lex::Diags;
use crate::program::Block;

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

/// An `RND` or `CHF` read, waiting for the element after it.
pub(super) type Pending = Cut;

/// The word a pending corner was written with.
fn name(c: &Pending) -> &'static str {
    if c.round {
        "RND"
    } else {
        "CHF"
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
        let between = matches!(s.kind, Kind::Centre(_) | Kind::Assign { .. } | Kind::AssignMax { .. });
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
        self.pending = Some(Cut { round, chord: false, size: v * unit, feed, line: s.line, col: s.col, number: s.number });
    }

    /// The program ends: a corner still waiting has no element after it.
    pub(super) fn end_corner(&mut self, diags: &mut Diags) {
        if let Some(c) = self.pending.clone() {
            self.refuse(&c, "no contour element after it before the program ends", diags);
        }
    }

    /// The corner `c` is not made: why, at its block.
    fn refuse(&mut self, c: &Pending, why: &str, diags: &mut Diags) {
        diags.error(c.line, c.col, format!("{}: {why}", name(c)));
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
