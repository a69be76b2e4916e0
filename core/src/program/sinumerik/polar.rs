//! Polar coordinates (SINUMERIK 840D sl Programming Manual Fundamentals 12/2019, §2.9.3): the pole,
//! set by `G110` (from the position last programmed), `G111` (from the workpiece's zero) or `G112`
//! (from the last pole), the workpiece's zero where none is set; and moves `G0`-`G3 AP= RP=`: the
//! polar angle AP from the working plane's first axis, counter-clockwise (`AP=IC()` from the last
//! angle), and the polar radius RP, each kept ("the polar angle remains stored until a new pole is
//! defined or the working plane is changed"; "the polar radius remains stored until a new value is
//! entered"), a circle's centre the pole. Read as the Cartesian words they give, so frames,
//! compensation and corners take them as any move.

use super::circles::{AXES, CENTRES};
use super::{Dimension, Word};
use crate::program::Plane;
use std::borrow::Cow;

/// A polar word as written: value, dimension, column.
pub(super) type PolarWord = Option<(f64, Dimension, usize)>;

/// The pole and the polar angle and radius in effect.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Polar {
    /// The pole, absolute program coordinates (m); `None`: the workpiece's zero.
    pole: Option<[f64; 3]>,
    /// The last polar angle, deg.
    angle: Option<f64>,
    /// The last polar radius, m.
    radius: Option<f64>,
}


impl Polar {
    /// The working plane changed: the angle is forgotten.
    pub(super) fn plane_changed(&mut self) {
        self.angle = None;
    }

    /// A pole block (`g` 110, 111 or 112) with the plane's X Y (or AP RP): the pole it sets; the
    /// words left for the rest of the block (its axis words are the pole's, no move).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn set_pole<'a>(&mut self, g: u32, g_col: usize, words: &[Word<'a>], (ap, rp): (PolarWord, PolarWord), last: [f64; 3], plane: Plane, unit: f64) -> Result<Vec<Word<'a>>, (usize, String)> {
        let (a, b, n) = plane.axes();
        let name = format!("G{g}");
        if let Some(w) = words.iter().find(|w| w.letter == AXES[n]) {
            return Err((w.column, format!("{name} with {}{}: the pole lies in the working plane (its two axes)", w.letter, w.raw)));
        }
        if let Some(w) = words.iter().find(|w| w.letter == 'G' && matches!(w.value as i64, 17..=19)) {
            return Err((w.column, format!("{name} with G{}: the pole is given in the plane in effect (set the plane in a block before)", w.raw)));
        }
        let from = match g {
            110 => last,
            111 => [0.0; 3],
            _ => self.pole.unwrap_or([0.0; 3]),
        };
        let written = |k: usize| words.iter().find(|w| w.letter == AXES[k]);
        let mut pole = from;
        match (ap.or(rp), written(a).or(written(b))) {
            (Some(_), Some(w)) => return Err((w.column, format!("{name}: a pole in Cartesian (X Y) or polar (AP RP) coordinates, not both"))),
            (None, None) => return Err((g_col, format!("{name} without the pole's coordinates"))),
            (None, Some(_)) => {
                for k in [a, b] {
                    let Some(w) = written(k) else {
                        return Err((g_col, format!("{name}: both of the plane's coordinates of the pole are expected ({} missing)", AXES[k])));
                    };
                    if w.dimension != Dimension::Modal {
                        return Err((w.column, format!("{name} {}={}: a pole's coordinates are not dimensioned by AC() or IC() (G110-G112 say from where)", w.letter, w.raw)));
                    }
                    pole[k] = from[k] + w.value * unit;
                }
            }
            (Some(_), None) => {
                // G110 AP= RP=: "with reference to the last approached pole" in one edition and the
                // position in another: not read.
                if g == 110 {
                    return Err((g_col, "G110 AP= RP=: a pole in polar coordinates from the last position is not read (G111 and G112 are)".into()));
                }
                let (Some((angle, ad, acol)), Some((radius, _, rcol))) = (ap, rp) else {
                    return Err((g_col, format!("{name}: a pole in polar coordinates takes both AP= and RP=")));
                };
                if ad != Dimension::Modal {
                    return Err((acol, format!("{name} AP={angle}: a pole's angle is not dimensioned by AC() or IC()")));
                }
                if !(radius >= 0.0) {
                    return Err((rcol, format!("RP={radius}: the polar radius is not negative")));
                }
                let (s, c) = angle.to_radians().sin_cos();
                pole[a] = from[a] + radius * unit * c;
                pole[b] = from[b] + radius * unit * s;
            }
        }
        self.pole = Some(pole);
        self.angle = None;
        Ok(words.iter().filter(|w| !(w.letter == AXES[a] || w.letter == AXES[b] || w.letter == 'G' && w.value == f64::from(g))).cloned().collect())
    }

    /// A move with AP= and/or RP= (`arc`: a G2/G3, whose centre is the pole): its words with the
    /// plane's end point (absolute) and, for a circle, the centre, in place of the polar ones.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn resolve<'a>(&mut self, words: &[Word<'a>], (ap, rp): (PolarWord, PolarWord), arc: bool, plane: Plane, unit: f64, absolute: bool, col: usize) -> Result<Vec<Word<'a>>, (usize, String)> {
        let (a, b, _) = plane.axes();
        if let Some(w) = words.iter().find(|w| w.letter == AXES[a] || w.letter == AXES[b]) {
            return Err((w.column, format!("{}{} with AP=/RP=: the end point is given in polar or in Cartesian coordinates of the plane, not both", w.letter, w.raw)));
        }
        if let Some(w) = words.iter().find(|w| w.letter == 'R' || CENTRES.contains(&w.letter)) {
            return Err((w.column, format!("{}{} with AP=/RP=: a polar circle's centre is the pole", w.letter, w.raw)));
        }
        let angle = match ap {
            Some((v, Dimension::Incremental, c)) => match self.angle {
                Some(last) => last + v,
                None => return Err((c, format!("AP=IC({v}): no polar angle before it since the pole was set or the plane changed"))),
            },
            Some((v, Dimension::Modal, c)) if !absolute => return Err((c, format!("AP={v} under G91: write AP=AC() or AP=IC() (whether G91 makes it incremental is not in the pages at hand)"))),
            Some((v, _, _)) => v,
            None => match self.angle {
                Some(v) => v,
                None => return Err((col, "RP= without AP=, and no polar angle before it since the pole was set or the plane changed".into())),
            },
        };
        let radius = match rp {
            Some((v, _, c)) if !(v >= 0.0) => return Err((c, format!("RP={v}: the polar radius is not negative"))),
            Some((v, _, _)) => v * unit,
            None => match self.radius {
                Some(r) => r,
                None => return Err((col, "AP= without RP=, and no polar radius before it".into())),
            },
        };
        self.angle = Some(angle);
        self.radius = Some(radius);
        let pole = self.pole.unwrap_or([0.0; 3]);
        let (s, c) = angle.to_radians().sin_cos();
        let mut out = words.to_vec();
        let word = |letter: char, v: f64| Word { letter, value: v / unit, raw: Cow::Owned(format!("{}", v / unit)), column: col, dimension: Dimension::Absolute };
        out.push(word(AXES[a], pole[a] + radius * c));
        out.push(word(AXES[b], pole[b] + radius * s));
        if arc {
            out.push(word(CENTRES[a], pole[a]));
            out.push(word(CENTRES[b], pole[b]));
        }
        Ok(out)
    }
}
