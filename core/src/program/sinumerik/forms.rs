//! The block's circle forms before the interpreter reads it: `CIP` and `CT` (G group 1's modal
//! circles, [`circles`]), `AR=`, and polar coordinates ([`polar`]), each turned into the G2/G3 or
//! Cartesian words it gives; and the contour's end direction that a later `CT` leaves along.

use super::{circles, lex, motion_g, SinumerikReader, UNREAD_MOTION};
use crate::program::interp::Word;
use crate::program::lex::Diags;
use crate::program::{Block, Motion, Plane};

/// G group 1's circle in effect, modal: `CIP` through an intermediate point, `CT` tangential.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum CircleMode {
    Cip,
    Ct,
}

impl CircleMode {
    /// Its keyword.
    pub(super) fn name(self) -> &'static str {
        match self {
            CircleMode::Cip => "CIP",
            CircleMode::Ct => "CT",
        }
    }

    /// The mode a keyword (capitals) selects.
    pub(super) fn of(name: &str) -> Option<CircleMode> {
        match name {
            "CIP" => Some(CircleMode::Cip),
            "CT" => Some(CircleMode::Ct),
            _ => None,
        }
    }
}

/// The direction the programmed contour ends in, for a `CT` after it: a vector in the working
/// plane's two coordinates (unscaled, [`crate::program::tangent::end_tangent`]), the plane and frame
/// rotation it was taken in, and its line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Tangent {
    t: [f64; 2],
    plane: Plane,
    tilt: Option<nalgebra::Matrix3<f64>>,
    line: usize,
}

impl SinumerikReader {
    /// A block's circle forms and polar coordinates ([`circles`], [`polar`]) turned into the G2/G3
    /// and Cartesian words they give, in `words`; false (an error in `diags`) if refused.
    #[inline(never)]
    pub(super) fn circle_forms(&mut self, words: &mut Vec<Word<'_>>, keywords: &mut Vec<lex::Keyword<'_>>, circle: lex::CircleWords, line: usize, first_col: usize, diags: &mut Diags) -> bool {
        let lex::CircleWords { through, ar, ap, rp } = circle;
        // CIP or CT, where one is written or in effect.
        let mode_at = keywords.iter().position(|k| CircleMode::of(&k.name).is_some());
        // Where a CT's errors point: at the CT written in this block, else at the block.
        let mode_col = mode_at.map_or(first_col, |p| keywords[p].col);
        if self.circle_mode.is_some() || mode_at.is_some() {
            // G group 1: a G0-G3 (or another of the group's motions) ends CIP and CT.
            let group1 = motion_g(words);
            let other = keywords.iter().enumerate().find(|(i, k)| Some(*i) != mode_at && UNREAD_MOTION.contains(&k.name.as_str())).map(|(i, _)| i);
            if let Some(p) = mode_at {
                let name = keywords[p].name.clone();
                let clash = group1.map(|g| (g.column, format!("G{}", g.raw))).or_else(|| other.map(|k| (keywords[k].col, keywords[k].name.clone())));
                if let Some((col, other)) = clash {
                    diags.error(line, col, format!("{other} with {name} in one block: G group 1 takes one motion"));
                    return false;
                }
                if keywords[p].args.is_some() {
                    diags.error(line, keywords[p].col, format!("{name}(: {name} takes no arguments"));
                    return false;
                }
                keywords.remove(p);
                self.circle_mode = CircleMode::of(&name);
            } else if group1.is_some() || other.is_some() {
                self.circle_mode = None;
            }
        }
        if self.circle_mode != Some(CircleMode::Cip) {
            if let Some(col) = through.iter().flatten().map(|c| c.2).min() {
                diags.error(line, col, "I1= J1= K1= (an intermediate point) without CIP in effect");
                return false;
            }
        }
        if let Some(mode) = self.circle_mode {
            let (absolute, plane, unit) = self.circle_settings(words);
            let start = self.interp.position();
            let start = [start[0], start[1], start[2]];
            let made = match mode {
                CircleMode::Cip => circles::through(words, &through, start, plane, unit, absolute, first_col),
                CircleMode::Ct => circles::tangent(words, self.tangent_in(plane), start, plane, unit, absolute, mode_col),
            };
            match made {
                Ok(Some(arc)) => *words = arc,
                Ok(None) => {}
                Err((col, why)) => {
                    diags.error(line, col, why);
                    return false;
                }
            }
        }
        // Polar coordinates: a pole (G110-G112), or a move by AP= RP=; a change of the working
        // plane forgets the polar angle.
        if words.iter().any(|w| w.letter == 'G' && matches!(w.value as i64, 17..=19)) && self.circle_settings(words).1 != self.interp.plane() {
            self.polar.plane_changed();
        }
        let pole_g = words.iter().find(|w| w.letter == 'G' && matches!(w.value as i64, 110..=112) && w.value.fract() == 0.0).map(|w| (w.value as u32, w.column));
        if let Some((g, g_col)) = pole_g {
            let (_, plane, unit) = self.circle_settings(words);
            let start = self.interp.position();
            match self.polar.set_pole(g, g_col, words, (ap, rp), [start[0], start[1], start[2]], plane, unit) {
                Ok(rest) => *words = rest,
                Err((col, why)) => {
                    diags.error(line, col, why);
                    return false;
                }
            }
        } else if ap.is_some() || rp.is_some() {
            let (absolute, plane, unit) = self.circle_settings(words);
            let col = ap.or(rp).map_or(first_col, |w| w.2);
            let g = motion_g(words).map(|w| w.value);
            let arc = match (g, self.interp.motion()) {
                _ if self.circle_mode.is_some() || ar.is_some() => {
                    diags.error(line, col, "AP=/RP= with CIP, CT or AR=: a polar end point goes with G0-G3 about the pole");
                    return false;
                }
                (Some(v), _) => v >= 2.0,
                (None, m) => m.is_some_and(Motion::is_arc),
            };
            match self.polar.resolve(words, (ap, rp), arc, plane, unit, absolute, col) {
                Ok(w) => *words = w,
                Err((col, why)) => {
                    diags.error(line, col, why);
                    return false;
                }
            }
        }
        // AR=: a G2/G3 given by its opening angle, with its end point or its centre.
        if let Some((angle, col)) = ar {
            let g = motion_g(words).map(|w| w.value);
            let ccw = match (g, self.interp.motion()) {
                _ if self.circle_mode.is_some() => None,
                (Some(v), _) => (v >= 2.0).then_some(v == 3.0),
                (None, Some(Motion::ArcCw)) => Some(false),
                (None, Some(Motion::ArcCcw)) => Some(true),
                _ => None,
            };
            let Some(ccw) = ccw else {
                diags.error(line, col, format!("AR={angle}: an opening angle belongs to a circle, G2 or G3"));
                return false;
            };
            let (absolute, plane, unit) = self.circle_settings(words);
            let start = self.interp.position();
            match circles::opening(words, (angle, col), ccw, [start[0], start[1], start[2]], plane, unit, absolute) {
                Ok(arc) => *words = arc,
                Err((col, why)) => {
                    diags.error(line, col, why);
                    return false;
                }
            }
        }
        true
    }


    /// The tangent a CT in `plane` leaves along, or why there is none: the end direction of the last
    /// block that moved, taken in the same plane and frame rotation ("If a frame change takes place
    /// between the block that defines the tangent and the CT block, the tangent is also subjected to
    /// this change", ONE 12/2019 §2.9: not read, refused).
    fn tangent_in(&self, plane: Plane) -> Result<[f64; 2], String> {
        match &self.tangent {
            Some(t) if t.plane == plane && t.tilt == self.interp.tilt() => Ok(t.t),
            Some(t) => Err(format!("CT: the working plane or the frame's rotation changed since line {}, whose end the circle would be tangent to: a tangent carried over is not read", t.line)),
            None => Err("CT: no contour element in the working plane before it to be tangent to (the last move left the plane, moved rotary axes alone, made a cycle's moves, started where no move had placed the plane's axes, ran under tool radius compensation or was refused)".into()),
        }
    }

    /// Keep the end direction of a line read well for a later CT: the end tangent of its one block
    /// that moves ([`crate::program::tangent::end_tangent`]); a line that moves nothing leaves it,
    /// one of several moves (a cycle), one from where no move had placed the plane's axes (`placed`
    /// before the line), or one under tool radius compensation (its path is the compensation's)
    /// forgets it, as a refused line does.
    pub(super) fn follow(&mut self, start: [f64; 6], placed: [bool; 6], blocks: &[Block], line: usize) {
        if self.trc.busy() {
            self.tangent = None;
            return;
        }
        let mut moving = blocks.iter().filter(|b| !b.targets.is_empty() || b.arc.is_some());
        match (moving.next(), moving.next()) {
            (None, _) => {}
            (Some(b), None) => {
                let end = self.interp.position();
                self.tangent = crate::program::tangent::end_tangent(b, start, placed, end, &self.interp).map(|t| Tangent { t, plane: self.interp.plane(), tilt: self.interp.tilt(), line });
            }
            _ => self.tangent = None,
        }
    }
}
