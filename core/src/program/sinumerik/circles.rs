//! The 840D's circles given otherwise than by a centre or a radius, read as the G2 or G3 about the
//! centre they give, so that frames, compensation and corners take them as any circle.
//!
//! `CIP`: a circle through an intermediate point (SINUMERIK 840D sl Programming Manual Fundamentals
//! 12/2019, §2.9 "Circular interpolation through intermediate point (CIP)": `CIP X… Y… Z… I1=…
//! J1=… K1=…`, modal, "the traversing direction is determined by the order of the starting point,
//! intermediate point and end point"; I1 J1 K1 are the intermediate point's X Y Z, dimensioned as the
//! end point is, by G90/G91 or `AC()`/`IC()`, "with incremental dimensions ... the circle starting
//! point is used as the reference for the intermediate point and the end point"). A circle inclined
//! to the working plane is refused.
//!
//! `CT`: a circle with a tangential transition (840D Programming Manual Fundamentals 10.2004 p. 4-33:
//! "The direction of tangent at the start point of a CT block is determined from the end tangent of
//! the programmed contour of the previous block with a traversing movement", CT modal, `CT X… Y…
//! Z…`; SINUMERIK ONE 12/2019 §2.9: "The position of the circle plane depends on the active plane
//! (G17-G19)", and "If the extension of the start tangent runs through the end point, a straight
//! line is produced instead of a circle").
//!
//! `AR=`: the opening angle with the end point or the centre (§2.9.6.4 "Circular interpolation with
//! opening angle and end point / center point (G2/G3, X... Y... Z... / I... J... K..., AR)": `G2/G3
//! X… Y… Z… AR=…` or `G2/G3 I… J… K… AR=…`, AR 0 to 360 deg, no full circle).

use super::{Dimension, Word};
use crate::program::Plane;
use std::borrow::Cow;

/// The intermediate point as written: its X Y Z words (`I1=`, `J1=`, `K1=`), value, dimension and
/// column.
pub(super) type Through = [Option<(f64, Dimension, usize)>; 3];

/// The axes' and the circle centre's addresses, by axis (X Y Z, I J K).
pub(super) const AXES: [char; 3] = ['X', 'Y', 'Z'];
pub(super) const CENTRES: [char; 3] = ['I', 'J', 'K'];

/// The intermediate point's addresses, by axis.
const NAMES: [&str; 3] = ["I1", "J1", "K1"];

/// Points this close (m) along the plane's normal are in the plane: the program's own rounding.
const IN_PLANE: f64 = 1e-7;

/// A CIP block's words as the G2 or G3 (`arc`) with its centre (`I J K`, incremental from the
/// start, program units) that the start (absolute program coordinates, m), the intermediate point
/// `through` and the end point the block's X Y Z give; `None` if the block moves no linear axis and
/// writes no intermediate point (a feed, a function: no circle). The error and its column, if the
/// three points give no circle in the working plane.
pub(super) fn through<'a>(words: &[Word<'a>], through: &Through, start: [f64; 3], plane: Plane, unit: f64, absolute: bool, col: usize) -> Result<Option<Vec<Word<'a>>>, (usize, String)> {
    let written = |k: usize| words.iter().find(|w| w.letter == AXES[k]);
    let moves = (0..3).any(|k| written(k).is_some());
    let through_col = through.iter().flatten().map(|t| t.2).min();
    let rotary = words.iter().any(|w| matches!(w.letter, 'A' | 'B' | 'C'));
    // A centre, radius or turns, with an end point or not (`J-5` alone is no full circle under CIP).
    no_centre(words, "CIP", [Some("a circle through an intermediate point takes no centre"), Some("a circle through an intermediate point takes no radius"), Some("a circle through an intermediate point takes no turns")])?;
    let Some(through_col) = through_col else {
        return if moves {
            Err((col, "CIP: a move without its intermediate point (I1= J1= K1=): every CIP block gives one".into()))
        } else if rotary {
            Err((col, "CIP: a move of the rotary axes alone, without an end point (X Y Z) and intermediate point: every CIP block gives both".into()))
        } else {
            Ok(None)
        };
    };
    if !moves {
        return Err((through_col, "CIP: an intermediate point without an end point (X Y Z)".into()));
    }
    let end = end_point(words, start, unit, absolute);
    let (a, b, n) = plane.axes();
    // The plane's two coordinates of the intermediate point are written; a coordinate along the
    // normal left out is the start's (the manual's examples write the plane's two only).
    for k in [a, b] {
        if through[k].is_none() {
            return Err((through_col, format!("CIP: {} not written: both of the working plane's intermediate coordinates are expected (a left-out one's reading is not in the pages at hand)", NAMES[k])));
        }
    }
    let mid: [f64; 3] = std::array::from_fn(|k| match through[k] {
        Some((v, d, _)) if d.absolute(absolute) => v * unit,
        Some((v, _, _)) => start[k] + v * unit,
        None => start[k],
    });
    if (mid[n] - start[n]).abs() > IN_PLANE || (end[n] - start[n]).abs() > IN_PLANE {
        return Err((through_col, format!("CIP: the start, intermediate and end points are not at one {} (a circle inclined to the working plane is not read)", AXES[n])));
    }
    // The circle through three points of the plane: its centre is where the perpendicular
    // bisectors of start-mid and mid-end meet.
    let (p, q, r) = ([start[a], start[b]], [mid[a], mid[b]], [end[a], end[b]]);
    let d = 2.0 * (p[0] * (q[1] - r[1]) + q[0] * (r[1] - p[1]) + r[0] * (p[1] - q[1]));
    let chord = (r[0] - p[0]).hypot(r[1] - p[1]).max((q[0] - p[0]).hypot(q[1] - p[1]));
    if !(d.abs() > 1e-12 * chord * chord) {
        return Err((through_col, "CIP: the start, intermediate and end points lie on one line (or two of them coincide): no circle".into()));
    }
    let sq = |s: [f64; 2]| s[0] * s[0] + s[1] * s[1];
    let centre = [
        (sq(p) * (q[1] - r[1]) + sq(q) * (r[1] - p[1]) + sq(r) * (p[1] - q[1])) / d,
        (sq(p) * (r[0] - q[0]) + sq(q) * (p[0] - r[0]) + sq(r) * (q[0] - p[0])) / d,
    ];
    if (r[0] - p[0]).hypot(r[1] - p[1]) < IN_PLANE {
        return Err((through_col, "CIP: the end point is the start point: a full circle is not given by an intermediate point".into()));
    }
    // Start, intermediate, end counter-clockwise in the plane (from its first axis to its second): G3.
    let mut out = with_motion(words, if d > 0.0 { 3.0 } else { 2.0 }, col);
    push_centre(&mut out, plane, [centre[0] - start[a], centre[1] - start[b]], unit, through_col);
    Ok(Some(out))
}

/// The end point (absolute program coordinates, m) the block's X Y Z give from `start`, each as
/// G90/G91 or its own `AC()`/`IC()` says; an axis not written stays.
fn end_point(words: &[Word<'_>], start: [f64; 3], unit: f64, absolute: bool) -> [f64; 3] {
    std::array::from_fn(|k| match words.iter().find(|w| w.letter == AXES[k]) {
        Some(w) if w.dimension.absolute(absolute) => w.value * unit,
        Some(w) => start[k] + w.value * unit,
        None => start[k],
    })
}

/// The block's words with its G0-G3 replaced by `g`, the motion a circle form turns into.
fn with_motion<'a>(words: &[Word<'a>], g: f64, col: usize) -> Vec<Word<'a>> {
    let mut out: Vec<Word<'a>> = words.iter().filter(|w| !(w.letter == 'G' && matches!(w.value as i64, 0..=3))).cloned().collect();
    out.push(Word { letter: 'G', value: g, raw: Cow::Owned(format!("{g}")), column: col, dimension: Dimension::Modal });
    out
}

/// The circle centre's words of the working plane, incremental from the start by `offset` (m),
/// in program units.
fn push_centre(out: &mut Vec<Word<'_>>, plane: Plane, offset: [f64; 2], unit: f64, col: usize) {
    let (a, b, _) = plane.axes();
    for (k, c) in [(a, offset[0]), (b, offset[1])] {
        let v = c / unit;
        out.push(Word { letter: CENTRES[k], value: v, raw: Cow::Owned(format!("{v}")), column: col, dimension: Dimension::Incremental });
    }
}

/// The error, at its column, of a block of `mode` (CIP, CT: circles given otherwise) that writes a
/// centre (I J K), a radius (CR=) or, where `why` gives a reason for them, turns (TURN=), each with
/// its reason in `why`.
fn no_centre(words: &[Word<'_>], mode: &str, why: [Option<&str>; 3]) -> Result<(), (usize, String)> {
    let refused = |w: &&Word<'_>| match w.letter {
        'I' | 'J' | 'K' => why[0].is_some(),
        'R' => why[1].is_some(),
        'P' => why[2].is_some(),
        _ => false,
    };
    match words.iter().find(refused) {
        Some(w) => Err((
            w.column,
            match w.letter {
                'R' => format!("{mode} with CR=: {}", why[1].unwrap_or_default()),
                'P' => format!("{mode} with TURN=: {}", why[2].unwrap_or_default()),
                c => format!("{mode} with {c}{}: {}", w.raw, why[0].unwrap_or_default()),
            },
        )),
        None => Ok(()),
    }
}

/// A CT block's words as the G2 or G3 about the centre that the tangent `t` at the start (the
/// working plane's two coordinates, of any length; why there is none, if none) and the end point give, its
/// centre incremental from the start; G1 where the end lies ahead on the tangent's line (the
/// manual's limit case). `None` if the block moves no linear axis (a feed, a function). A move along
/// the plane's normal with it makes a helix, as with G2/G3. The error and its column if the end
/// point is the start or lies behind it on the tangent's line, if the block writes a centre or a
/// radius, or turns (TURN=, which a circle takes as G2/G3 do) where it makes the straight line.
pub(super) fn tangent<'a>(words: &[Word<'a>], t: Result<[f64; 2], String>, start: [f64; 3], plane: Plane, unit: f64, absolute: bool, col: usize) -> Result<Option<Vec<Word<'a>>>, (usize, String)> {
    let written = |k: usize| words.iter().find(|w| w.letter == AXES[k]);
    // A centre or a radius, with an end point or not (`I5` alone is no full circle under CT). Full
    // turns (TURN=) go with the circle, as with G2/G3 (ONE 12/2019 §2.9 allows them but on the
    // straight line).
    no_centre(words, "CT", [Some("the tangent and the end point give the centre"), Some("the tangent and the end point give the radius"), None])?;
    if !(0..3).any(|k| written(k).is_some()) {
        if let Some(w) = words.iter().find(|w| w.letter == 'P') {
            return Err((w.column, format!("CT with TURN={}: full turns without an end point (X Y Z): no circle", w.value - 1.0)));
        }
        return if words.iter().any(|w| matches!(w.letter, 'A' | 'B' | 'C')) { Err((col, "CT: a move of the rotary axes alone, without an end point (X Y Z)".into())) } else { Ok(None) };
    }
    let t = t.map_err(|why| (col, why))?;
    let end = end_point(words, start, unit, absolute);
    let (a, b, _) = plane.axes();
    let d = [end[a] - start[a], end[b] - start[b]];
    let Some((centre, ccw)) = crate::program::tangent::tangent_circle(t, d) else {
        if d[0].hypot(d[1]) < IN_PLANE {
            return Err((col, "CT: the end point is the start point in the working plane: no circle".into()));
        }
        if d[0] * t[0] + d[1] * t[1] < 0.0 {
            return Err((col, "CT: the end point lies behind the start on the tangent: no circle leaves along it".into()));
        }
        // "If the extension of the start tangent runs through the end point, a straight line is
        // produced instead of a circle ... In this special case, TURN must either not be programmed
        // or the value must be TURN=0." (TURN=n is read as P n+1.)
        if let Some(w) = words.iter().find(|w| w.letter == 'P' && w.value != 1.0) {
            return Err((w.column, format!("CT with TURN={}: the end point lies on the start tangent, where the control makes a straight line and TURN must be left out or 0", w.value - 1.0)));
        }
        let line: Vec<Word<'a>> = words.iter().filter(|w| w.letter != 'P').cloned().collect();
        return Ok(Some(with_motion(&line, 1.0, col)));
    };
    let mut out = with_motion(words, if ccw { 3.0 } else { 2.0 }, col);
    push_centre(&mut out, plane, centre, unit, col);
    Ok(Some(out))
}

/// A block's `AR=` (opening angle, deg) and its column.
pub(super) type Opening = Option<(f64, usize)>;

/// A `G2`/`G3` block with `AR=` (`ccw`: G3) as the G2/G3 the control makes of it: with an end point,
/// the centre on the chord's bisector at (c/2)/tan(AR/2) from its middle (left of the chord for a
/// counter-clockwise arc under 180 deg, right of it over 180 deg); with a centre, the end point the
/// start turned about it by AR (absolute words). `start` absolute program coordinates (m); the
/// words' values in program units.
#[allow(clippy::too_many_arguments)]
pub(super) fn opening<'a>(words: &[Word<'a>], (ar, ar_col): (f64, usize), ccw: bool, start: [f64; 3], plane: Plane, unit: f64, absolute: bool) -> Result<Vec<Word<'a>>, (usize, String)> {
    if !(ar > 0.0 && ar < 360.0) {
        return Err((ar_col, format!("AR={ar}: the opening angle is more than 0 and less than 360 deg (a full circle is not programmed with AR)")));
    }
    if let Some(w) = words.iter().find(|w| w.letter == 'R') {
        return Err((w.column, "AR= with CR=: the circle is given by one of them".into()));
    }
    let (a, b, n) = plane.axes();
    let axis = |k: usize| words.iter().find(|w| w.letter == AXES[k]);
    let centre_word = |k: usize| words.iter().find(|w| w.letter == CENTRES[k]);
    if let Some(w) = centre_word(n) {
        return Err((w.column, format!("{}{}: not a centre word of the working plane", w.letter, w.raw)));
    }
    let end_written = axis(a).is_some() || axis(b).is_some();
    let centre_written = centre_word(a).is_some() || centre_word(b).is_some();
    let sweep = ar.to_radians() * if ccw { 1.0 } else { -1.0 };
    let mut out: Vec<Word<'a>> = words.to_vec();
    match (end_written, centre_written) {
        (true, true) => Err((ar_col, "AR= with both an end point and a centre: the circle is given by one of them".into())),
        (false, false) => Err((ar_col, "AR= without an end point or a centre".into())),
        (true, false) => {
            let end = end_point(words, start, unit, absolute);
            let (du, dv) = (end[a] - start[a], end[b] - start[b]);
            let chord = du.hypot(dv);
            if !(chord > 1e-9) {
                return Err((ar_col, "AR= with the end point on the start: no circle".into()));
            }
            // From the chord's middle along its left normal (-dv, du)/c, by (c/2)/tan(AR/2), mirrored
            // for a clockwise arc; over 180 deg the tangent's sign puts the centre on the other side.
            let h = 0.5 * chord / (0.5 * ar.to_radians()).tan() * if ccw { 1.0 } else { -1.0 };
            let centre = [0.5 * (start[a] + end[a]) - h * dv / chord, 0.5 * (start[b] + end[b]) + h * du / chord];
            push_centre(&mut out, plane, [centre[0] - start[a], centre[1] - start[b]], unit, ar_col);
            Ok(out)
        }
        (false, true) => {
            let c: [f64; 2] = [a, b].map(|k| match centre_word(k) {
                Some(w) if w.dimension.absolute(false) => w.value * unit,
                Some(w) => start[k] + w.value * unit,
                None => start[k],
            });
            let (u, v) = (start[a] - c[0], start[b] - c[1]);
            if !(u.hypot(v) > 1e-9) {
                return Err((ar_col, "AR= with the centre on the start: no circle".into()));
            }
            let (sin, cos) = sweep.sin_cos();
            let end = [c[0] + u * cos - v * sin, c[1] + u * sin + v * cos];
            for (k, e) in [(a, end[0]), (b, end[1])] {
                let v = e / unit;
                out.push(Word { letter: AXES[k], value: v, raw: Cow::Owned(format!("{v}")), column: ar_col, dimension: Dimension::Absolute });
            }
            Ok(out)
        }
    }
}
