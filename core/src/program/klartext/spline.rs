//! The TNC's spline block `SPL`, run: per axis the cubic `X(t) = K3X t^3 + K2X t^2 + K1X t + X`
//! with `t` running from 1 to 0 (iTNC 530 User's Manual 340 49x, "Contour movements – Spline
//! interpolation (software option 2)"), from the tool's position (`t = 1`, which "can deviate from
//! the end point of the previous contour by no more than 1 µm. Larger deviations will provoke an
//! error message") to the end point (`t = 0`), made as the chords its path lies within
//! ([`crate::program::chords`]). Refused: under radius compensation (held there) and an M
//! function in the block (where it acts along the curve is not said).


use super::corners::Held;
use super::exec::Exec;
use super::{label, Kind, Stmt};
use crate::program::chords::{Chording, CHORD_TOLERANCE_M, CHORD_TOLERANCE_RAD};
use crate::program::interp::{Dimension, Interpreter, Word};
use crate::program::lex::Diags;
use crate::program::Block;

const LETTERS: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

impl Exec {
    /// Run an `SPL` block: its chords to `out`; true if the program stops here.
    pub(super) fn spline(&mut self, s: &Stmt<'_>, interp: &mut Interpreter, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        let Kind::Spline { ends, coefficients, feed } = &s.kind else { return false };
        let not_used = |diags: &mut Diags| diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
        if self.modal_call {
            diags.error(s.line, s.col, "SPL with the modal cycle call M89 in force: where along the curve the cycle runs is not read (M99 ends it)");
            not_used(diags);
            return false;
        }
        let before = diags.errors();
        let unit = interp.unit();
        let here = interp.position();
        let (mut axes, mut end, mut tolerance) = ([false; 6], [0.0; 6], [0.0; 6]);
        for w in ends {
            let k = LETTERS.iter().position(|l| w.addr.starts_with(*l)).unwrap_or(0);
            if !interp.has_axis(LETTERS[k]) {
                diags.error(s.line, w.col, format!("{}: the machine has no {} axis", w.addr, LETTERS[k]));
                continue;
            }
            if k >= 3 && interp.modulo(k - 3) {
                diags.error(s.line, w.col, format!("{}: a spline on a rotary axis that turns without end: which way the TNC turns it along the curve is not read", w.addr));
                continue;
            }
            if !interp.placed[k] {
                diags.error(s.line, w.col, format!("{}: no move has placed {} before the spline, so whether it starts where the tool stands is not known", w.addr, LETTERS[k]));
                continue;
            }
            let Some(v) = self.value(w, s.line, diags) else { continue };
            // "Spline end point: -99 999.9999 to +99 999.9999".
            if !(v.abs() <= 99_999.999_9) {
                diags.error(s.line, w.col, format!("{}: a spline's end point is -99999.9999 to +99999.9999", w.addr));
                continue;
            }
            axes[k] = true;
            end[k] = v;
            tolerance[k] = if k < 3 { CHORD_TOLERANCE_M / unit } else { CHORD_TOLERANCE_RAD / interp.rotary_unit(k - 3) };
        }
        if diags.errors() > before {
            not_used(diags);
            return false;
        }
        let c = coefficients;
        let at = move |t: f64| {
            let mut p = [0.0; 6];
            for k in 0..6 {
                if let Some([k3, k2, k1]) = c[k].filter(|_| axes[k]) {
                    p[k] = ((k3 * t + k2) * t + k1) * t + end[k];
                }
            }
            p
        };
        // The spline starts where the tool stands, within 1 µm (0.001 deg on a rotary axis), axis by
        // axis: the manual's own example starts 0.71 µm off in X and 0.92 µm in Y, 1.16 µm apart.
        let start = at(1.0);
        for k in (0..6).filter(|k| axes[*k]) {
            let per = if k < 3 { unit } else { interp.rotary_unit(k - 3) };
            let stands = here[k] / per;
            if !((start[k] - stands).abs() <= tolerance[k]) {
                diags.error(s.line, s.col, format!("SPL: the spline starts at {}{} (its end point plus K3 + K2 + K1), but the tool stands at {}{}: more than 1 µm (0.001 deg) apart, an error on the TNC", LETTERS[k], trim(start[k]), LETTERS[k], trim(stands)));
                not_used(diags);
                return false;
            }
        }
        let mut points = Vec::new();
        if !(Chording { axes, tolerance }).chords(&at, 1.0, 0.0, &mut points) {
            diags.error(s.line, s.col, format!("SPL: the spline {}: a typo?", Chording::too_many()));
            not_used(diags);
            return false;
        }
        // The last chord ends at the end point as written.
        if let Some(p) = points.last_mut() {
            *p = end;
        }
        let Ok(feed_word) = self.feed_word(feed, s.line, diags) else {
            not_used(diags);
            return false;
        };
        // All chords made first, the interpreter put back if one is refused: the block runs whole or
        // not at all.
        let saved = interp.clone();
        let mut made = Vec::with_capacity(points.len());
        for (n, p) in points.iter().enumerate() {
            let mut words: Vec<Word> = vec![Word { letter: 'G', value: 1.0, raw: "1".into(), column: s.col, dimension: Dimension::Modal }];
            for k in (0..6).filter(|k| axes[*k]) {
                words.push(Word { letter: LETTERS[k], value: p[k], raw: format!("{}", p[k]).into(), column: s.col, dimension: Dimension::Absolute });
            }
            if let Some((v, raw, col)) = feed_word.as_ref().filter(|_| n == 0) {
                words.push(Word { letter: 'F', value: *v, raw: raw.clone(), column: *col, dimension: Dimension::Modal });
            }
            let from = interp.position();
            let Some(b) = interp.block_one(&words, s.line, s.col, s.number, diags) else {
                *interp = saved;
                not_used(diags);
                return false;
            };
            made.push((b, from, interp.position()));
        }
        for (b, from, to) in made {
            // (A spline starts only where a move has placed the axes it names.)
            self.follow(&b, from, interp.placed, to, interp);
            let h = Held { b, start: from, end: to, unit, tilt: interp.tilt(), arc_feed: interp.arc_feed() };
            if let Err(stop) = self.join(h, false, interp, out, diags) {
                self.stopped(&stop, diags, interp);
                return true;
            }
        }
        // The contour's direction at the end (for a CT after it): the curve's, -K1 of the plane's two
        // axes as t falls to 0, not the last chord's.
        let (a0, a1, _) = interp.plane().axes();
        let d = [a0, a1].map(|k| if axes[k] { -c[k].map_or(0.0, |c| c[2]) } else { 0.0 });
        let n = d[0].hypot(d[1]);
        if n > 0.0 && n.is_finite() {
            self.tangent = Some([d[0] / n, d[1] / n]);
        }
        false
    }
}

/// A coordinate for a message, as few digits as it needs.
fn trim(v: f64) -> String {
    let s = format!("{v:+.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}
