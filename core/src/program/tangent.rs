//! Circles with a tangential transition, the TNC's `CT` and the 840D's `CT`: the direction the
//! contour ends in, and the circle that leaves a point along it to a given end. Pure plane geometry
//! in the working plane's two coordinates (first axis, second axis); the readers keep the tangent
//! and make the G2/G3 of it.

use super::interp::Interpreter;
use super::{Block, Motion};

/// The direction a block leaves the contour in, in the working plane (not of unit length: the
/// readers keep one per block, and [`tangent_circle`] scales it once where a CT uses it): a line's
/// from its start to its end, an arc's tangent at its end in its sense. `None` where it has none in
/// the plane (a move along the plane's normal alone, of rotary axes alone, or no move), or where it
/// is not known: a move from where no move had placed the plane's axes (`placed` before the block)
/// starts where the tool stood, which the program does not say. `start` and `end` are the
/// interpreter's positions before and after the block (in a tilted plane the plane's coordinates;
/// an arc's centre is the workpiece's, taken back into the plane).
pub(crate) fn end_tangent(b: &Block, start: [f64; 6], placed: [bool; 6], end: [f64; 6], interp: &Interpreter) -> Option<[f64; 2]> {
    let (a0, a1, _) = interp.plane().axes();
    if !(placed[a0] && placed[a1]) {
        return None;
    }
    let t = match &b.arc {
        Some(arc) => {
            let c = nalgebra::Vector3::from(arc.centre);
            let c = interp.tilt().map_or(c, |r| r.transpose() * c);
            let r = [end[a0] - c[a0], end[a1] - c[a1]];
            // Counter-clockwise: the radius turned a quarter left; clockwise, right.
            if b.motion == Motion::ArcCcw { [-r[1], r[0]] } else { [r[1], -r[0]] }
        }
        None if !b.targets.is_empty() => [end[a0] - start[a0], end[a1] - start[a1]],
        None => return None,
    };
    (t != [0.0, 0.0]).then_some(t)
}

/// The circle that leaves a point along the tangent `t` (any length but 0) and ends `d` from it
/// (the plane's two coordinates): its centre's offset from the point, on the normal to `t`
/// (`|c| = |c - d|` gives `c = n |d|^2 / (2 n.d)`, `n` the unit tangent turned a quarter left), and
/// whether it runs counter-clockwise (the centre left of the tangent). `None` where the end lies on
/// the tangent's line, within `1e-9` of the chord: no circle (its radius would be infinite), or the
/// start itself.
pub(crate) fn tangent_circle(t: [f64; 2], d: [f64; 2]) -> Option<([f64; 2], bool)> {
    let len = t[0].hypot(t[1]);
    if !(len > 0.0) {
        return None;
    }
    let n = [-t[1] / len, t[0] / len];
    let dn = d[0] * n[0] + d[1] * n[1];
    let dd = d[0] * d[0] + d[1] * d[1];
    if dd == 0.0 || dn.abs() <= 1e-9 * dd.sqrt() {
        return None;
    }
    let rho = dd / (2.0 * dn);
    Some(([rho * n[0], rho * n[1]], dn > 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// By hand: from the origin along +x, to (10, 10) the quarter circle about (0, 10),
    /// counter-clockwise; to (10, -10) the one about (0, -10), clockwise; to (0, 10) the half circle
    /// about (0, 5); to (-10, 10) three quarters about (0, 10). Every centre is as far from the
    /// start as from the end. On the tangent's line, ahead or behind, there is no circle.
    #[test]
    fn the_tangent_circle_through_an_end_point() {
        for (d, c, ccw) in [([10.0, 10.0], [0.0, 10.0], true), ([10.0, -10.0], [0.0, -10.0], false), ([0.0, 10.0], [0.0, 5.0], true), ([-10.0, 10.0], [0.0, 10.0], true)] {
            let (got, sense) = tangent_circle([1.0, 0.0], d).unwrap();
            assert!((got[0] - c[0]).abs() < 1e-12 && (got[1] - c[1]).abs() < 1e-12 && sense == ccw, "{d:?}: {got:?} {sense}");
            let (r0, r1) = (got[0].hypot(got[1]), (got[0] - d[0]).hypot(got[1] - d[1]));
            assert!((r0 - r1).abs() < 1e-12, "{d:?}");
        }
        // A tangent along 45 deg (of any length): to (0, 2) the circle about (-1, 1), counter-clockwise.
        let (c, ccw) = tangent_circle([3.0, 3.0], [0.0, 2.0]).unwrap();
        assert!((c[0] + 1.0).abs() < 1e-12 && (c[1] - 1.0).abs() < 1e-12 && ccw, "{c:?}");
        assert!(tangent_circle([1.0, 0.0], [5.0, 0.0]).is_none());
        assert!(tangent_circle([1.0, 0.0], [-5.0, 0.0]).is_none());
        assert!(tangent_circle([1.0, 0.0], [0.0, 0.0]).is_none());
    }
}
