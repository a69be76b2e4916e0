//! Corners a program asks the control to cut off between two contour elements, in the working
//! plane: a rounding arc tangent to both (Heidenhain `RND R`, iTNC 530 user's manual 60642x-03
//! §6.4 "Corner rounding RND": "The tool moves on an arc that is tangentially connected to both the
//! preceding and subsequent contour elements ... The corner point is cut off by the rounding arc
//! and is not part of the contour"), or a chamfer between two straight lines (`CHF`, TNC 620
//! Klartext user's manual 01/2022 §5.4: "Chamfer between two straight lines", its side length).
//! Pure geometry on plane coordinates; the readers say which blocks the elements are.

/// A contour element in the working plane: a line, or an arc about `centre` (less than a turn).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Element {
    Line { from: [f64; 2], to: [f64; 2] },
    Arc { from: [f64; 2], to: [f64; 2], centre: [f64; 2], ccw: bool },
}

/// The rounding arc: where it leaves the element before (`from`) and meets the one after (`to`),
/// its centre and direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rounding {
    pub from: [f64; 2],
    pub to: [f64; 2],
    pub centre: [f64; 2],
    pub ccw: bool,
}

/// Elements meeting within this angle (rad) have no corner to cut: a rounding arc sweeps the turn,
/// and one of 1e-9 rad would read as a full circle (`path::segment`'s threshold).
const STRAIGHT: f64 = 1e-7;

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}

fn at(p: [f64; 2], d: [f64; 2], s: f64) -> [f64; 2] {
    [p[0] + d[0] * s, p[1] + d[1] * s]
}

impl Element {
    fn from(&self) -> [f64; 2] {
        match *self {
            Element::Line { from, .. } | Element::Arc { from, .. } => from,
        }
    }

    fn to(&self) -> [f64; 2] {
        match *self {
            Element::Line { to, .. } | Element::Arc { to, .. } => to,
        }
    }

    /// The unit direction of travel at `p` (a point of the element), or None for a line of no length.
    fn direction(&self, p: [f64; 2]) -> Option<[f64; 2]> {
        let (d, n) = match *self {
            Element::Line { from, to } => {
                let d = sub(to, from);
                (d, norm(d))
            }
            Element::Arc { centre, ccw, .. } => {
                let r = sub(p, centre);
                (if ccw { [-r[1], r[0]] } else { [r[1], -r[0]] }, norm(r))
            }
        };
        (n > 0.0 && n.is_finite()).then(|| [d[0] / n, d[1] / n])
    }

    /// The closest point of the element's line or circle to `p`.
    fn foot(&self, p: [f64; 2]) -> [f64; 2] {
        match *self {
            Element::Line { from, to } => {
                let d = sub(to, from);
                let l = norm(d);
                at(from, [d[0] / l, d[1] / l], dot(sub(p, from), d) / l)
            }
            Element::Arc { from, centre, .. } => {
                let (r, v) = (norm(sub(from, centre)), sub(p, centre));
                at(centre, v, r / norm(v))
            }
        }
    }

    /// Whether `p` (on the element's line or circle) lies within it, to `eps`.
    fn holds(&self, p: [f64; 2], eps: f64) -> bool {
        match *self {
            Element::Line { from, to } => {
                let d = sub(to, from);
                let l = norm(d);
                let s = dot(sub(p, from), d) / l;
                s >= -eps && s <= l + eps
            }
            Element::Arc { from, to, centre, ccw } => {
                let sweep = |a: [f64; 2]| {
                    let (u, v) = (sub(from, centre), sub(a, centre));
                    let t = cross(u, v).atan2(dot(u, v));
                    let t = if ccw { t } else { -t };
                    if t < 0.0 {
                        t + std::f64::consts::TAU
                    } else {
                        t
                    }
                };
                let whole = if norm(sub(to, from)) < eps { std::f64::consts::TAU } else { sweep(to) };
                let r = norm(sub(from, centre));
                let s = sweep(p);
                // Within the sweep, or a hair before its start (the angle wraps there).
                s * r <= whole * r + eps || (std::f64::consts::TAU - s) * r <= eps
            }
        }
    }

    /// The element's line or circle moved `d` to the left of its direction of travel: a point and
    /// direction, or a centre and radius (None where the circle shrinks to nothing).
    fn offset(&self, d: f64) -> Option<Offset> {
        match *self {
            Element::Line { from, .. } => {
                let t = self.direction(from)?;
                Some(Offset::Line(at(from, [-t[1], t[0]], d), t))
            }
            Element::Arc { from, centre, ccw, .. } => {
                // Left of a counter-clockwise arc is towards its centre.
                let r = norm(sub(from, centre)) - if ccw { d } else { -d };
                (r > 0.0).then_some(Offset::Circle(centre, r))
            }
        }
    }
}

#[derive(Debug, Clone, Copy)]
enum Offset {
    Line([f64; 2], [f64; 2]),
    Circle([f64; 2], f64),
}

/// Where two offset lines or circles meet (none, one or two points).
fn meet(a: Offset, b: Offset) -> Vec<[f64; 2]> {
    match (a, b) {
        (Offset::Line(p, d), Offset::Line(q, e)) => {
            let den = cross(d, e);
            if den.abs() < STRAIGHT {
                return Vec::new();
            }
            vec![at(p, d, cross(sub(q, p), e) / den)]
        }
        (Offset::Line(p, d), Offset::Circle(c, r)) | (Offset::Circle(c, r), Offset::Line(p, d)) => {
            // |p + s d - c| = r, d a unit vector.
            let w = sub(p, c);
            let b = dot(w, d);
            let disc = b * b - (dot(w, w) - r * r);
            if disc < 0.0 {
                return Vec::new();
            }
            let s = disc.sqrt();
            vec![at(p, d, -b - s), at(p, d, -b + s)]
        }
        (Offset::Circle(c1, r1), Offset::Circle(c2, r2)) => {
            let v = sub(c2, c1);
            let l = norm(v);
            if l == 0.0 || l > r1 + r2 || l < (r1 - r2).abs() {
                return Vec::new();
            }
            let a = (r1 * r1 - r2 * r2 + l * l) / (2.0 * l);
            let h = (r1 * r1 - a * a).max(0.0).sqrt();
            let u = [v[0] / l, v[1] / l];
            let m = at(c1, u, a);
            vec![at(m, [-u[1], u[0]], h), at(m, [u[1], -u[0]], h)]
        }
    }
}

/// The corner between `before` and `after` (which starts where `before` ends): the sign of the turn
/// (positive to the left), or why there is none to cut.
fn turn(before: &Element, after: &Element) -> Result<f64, String> {
    let (Some(t1), Some(t2)) = joint(before, after) else {
        return Err("an element of no length beside it".into());
    };
    let s = cross(t1, t2);
    if s.abs() < STRAIGHT {
        return Err(if dot(t1, t2) > 0.0 { "the elements meet tangentially: there is no corner to cut off".into() } else { "the contour turns back on itself here".into() });
    }
    Ok(s.signum())
}

/// The directions of travel where `before` ends and `after` starts (None for an element of no
/// length).
fn joint(before: &Element, after: &Element) -> (Option<[f64; 2]>, Option<[f64; 2]>) {
    (before.direction(before.to()), after.direction(after.from()))
}

/// `after` leaves where `before` ends in the same direction: there is no corner to cut ([`turn`]'s
/// "meet tangentially").
pub(crate) fn tangential(before: &Element, after: &Element) -> bool {
    matches!(joint(before, after), (Some(t1), Some(t2)) if cross(t1, t2).abs() < STRAIGHT && dot(t1, t2) > 0.0)
}

/// The arc of radius `r` tangent to `before` and `after` inside their corner, nearest the corner;
/// an error where none fits on both elements ("The rounding arc must be machinable", iTNC 530
/// §6.4; a radius longer than an element leaves no arc).
pub(crate) fn round(before: &Element, after: &Element, r: f64) -> Result<Rounding, String> {
    if !(r > 0.0 && r.is_finite()) {
        return Err(format!("a rounding radius must be positive, found {r}"));
    }
    let side = turn(before, after)?;
    let k = before.to();
    let (Some(a), Some(b)) = (before.offset(side * r), after.offset(side * r)) else {
        return Err("the radius is larger than an arc it joins".into());
    };
    let eps = 1e-9 * (1.0 + r + norm(k));
    let centre = meet(a, b)
        .into_iter()
        .filter(|c| before.holds(before.foot(*c), eps) && after.holds(after.foot(*c), eps))
        .min_by(|p, q| norm(sub(*p, k)).total_cmp(&norm(sub(*q, k))))
        .ok_or("no arc of this radius fits on both elements: the radius is too large for them")?;
    Ok(Rounding { from: before.foot(centre), to: after.foot(centre), centre, ccw: side > 0.0 })
}

/// The chamfer of side length `length` between two straight lines: where it leaves the first and
/// meets the second, each `length` from their corner.
pub(crate) fn chamfer(before: &Element, after: &Element, length: f64) -> Result<([f64; 2], [f64; 2]), String> {
    let (Element::Line { from: a, to: k }, Element::Line { to: c, .. }) = (*before, *after) else {
        return Err("a chamfer joins two straight lines (L), and an arc is beside it".into());
    };
    if !(length > 0.0 && length.is_finite()) {
        return Err(format!("a chamfer's side length must be positive, found {length}"));
    }
    turn(before, after)?;
    let (l1, l2) = (norm(sub(k, a)), norm(sub(c, k)));
    let eps = 1e-9 * (1.0 + length);
    if length > l1 + eps || length > l2 + eps {
        return Err("the side length is longer than a line it joins".into());
    }
    Ok((at(k, sub(a, k), length / l1), at(k, sub(c, k), length / l2)))
}

/// The point of `e` whose chord from the corner `k` (its end if `at_end`, else its start) is `c`
/// long, nearest `k` along it; None where `e` is too short for it.
fn chord_point(e: &Element, k: [f64; 2], at_end: bool, c: f64, eps: f64) -> Option<[f64; 2]> {
    match *e {
        Element::Line { from, to } => {
            let l = norm(sub(to, from));
            (c <= l + eps).then(|| if at_end { at(k, sub(from, k), c / l) } else { at(k, sub(to, k), c / l) })
        }
        Element::Arc { from, to, centre, ccw } => {
            let rho = norm(sub(k, centre));
            if c > 2.0 * rho {
                return None;
            }
            // The chord c = 2 rho sin(phi / 2) turns phi about the centre, back from the end or on
            // from the start, in the arc's direction.
            let phi = 2.0 * (c / (2.0 * rho)).min(1.0).asin();
            let turn = if ccw == at_end { -phi } else { phi };
            let (s, cs) = turn.sin_cos();
            let v = sub(k, centre);
            let p = [centre[0] + v[0] * cs - v[1] * s, centre[1] + v[0] * s + v[1] * cs];
            let probe = Element::Arc { from, to, centre, ccw };
            probe.holds(p, eps).then_some(p)
        }
    }
}

/// The chamfer whose ends lie `length` from the corner as the chord, on lines or arcs (Fanuc's
/// `,C`: "the length of the chord drawn from [the] intersection" where a circle is beside it, NCT
/// 2000M §16.1, a Fanuc-compatible control): where it leaves the first element and meets the second.
pub(crate) fn chamfer_chord(before: &Element, after: &Element, length: f64) -> Result<([f64; 2], [f64; 2]), String> {
    if !(length > 0.0 && length.is_finite()) {
        return Err(format!("a chamfer's length must be positive, found {length}"));
    }
    turn(before, after)?;
    let k = before.to();
    let eps = 1e-9 * (1.0 + length + norm(k));
    let p = chord_point(before, k, true, length, eps).ok_or("the chamfer is longer than the element before it")?;
    let q = chord_point(after, k, false, length, eps).ok_or("the chamfer is longer than the element after it")?;
    Ok((p, q))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 2], b: [f64; 2]) -> bool {
        norm(sub(a, b)) < 1e-9
    }

    /// The manual's example (iTNC 530 §6.4: L X+10 Y+40, L X+40 Y+25, RND R5, L X+10 Y+5): two
    /// lines; the tangent points lie R / tan(theta/2) from the corner, theta the angle between the
    /// lines, and the centre on the bisector R / sin(theta/2) from it.
    #[test]
    fn rounding_between_lines_is_the_bisector_fillet() {
        let (p, k, q) = ([10.0, 40.0], [40.0, 25.0], [10.0, 5.0]);
        let r = round(&Element::Line { from: p, to: k }, &Element::Line { from: k, to: q }, 5.0).unwrap();
        let (u, v) = (sub(p, k), sub(q, k));
        let (u, v) = ([u[0] / norm(u), u[1] / norm(u)], [v[0] / norm(v), v[1] / norm(v)]);
        let theta = dot(u, v).acos();
        let d = 5.0 / (theta / 2.0).tan();
        assert!(close(r.from, at(k, u, d)) && close(r.to, at(k, v, d)), "{r:?}");
        let bis = [u[0] + v[0], u[1] + v[1]];
        let bis = [bis[0] / norm(bis), bis[1] / norm(bis)];
        assert!(close(r.centre, at(k, bis, 5.0 / (theta / 2.0).sin())), "{r:?}");
        // From (10, 40) to (40, 25) then back down to (10, 5): a right turn.
        assert!(!r.ccw);
    }

    /// A line into a counter-clockwise arc that turns right at the joint: the centre of the
    /// rounding arc is R below the line and R + rho from the arc's centre (worked by hand: the line
    /// y = 0 from (0, 0) to (10, 0), the arc about (20, 0) of radius 10 from (10, 0), R = 2).
    #[test]
    fn rounding_a_line_into_an_arc() {
        let k = [10.0, 0.0];
        let arc = Element::Arc { from: k, to: [20.0, -10.0], centre: [20.0, 0.0], ccw: true };
        let r = round(&Element::Line { from: [0.0, 0.0], to: k }, &arc, 2.0).unwrap();
        let x = 20.0 - (12.0f64 * 12.0 - 4.0).sqrt();
        assert!(close(r.centre, [x, -2.0]), "{r:?}");
        assert!(close(r.from, [x, 0.0]), "{r:?}");
        let v = sub(r.centre, [20.0, 0.0]);
        assert!(close(r.to, at([20.0, 0.0], v, 10.0 / norm(v))), "{r:?}");
        assert!(!r.ccw);
        // And back: the arc reversed into the line reversed rounds the same corner.
        let back = round(&Element::Arc { from: [20.0, -10.0], to: k, centre: [20.0, 0.0], ccw: false }, &Element::Line { from: k, to: [0.0, 0.0] }, 2.0).unwrap();
        assert!(close(back.centre, r.centre) && close(back.from, r.to) && close(back.to, r.from) && back.ccw, "{back:?}");
    }

    #[test]
    fn what_does_not_fit_is_refused() {
        let (a, k, c) = ([0.0, 0.0], [10.0, 0.0], [10.0, 3.0]);
        let (l1, l2) = (Element::Line { from: a, to: k }, Element::Line { from: k, to: c });
        // A right angle: the tangent points lie R from the corner, so R = 3 fits and 3.5 does not.
        assert!(round(&l1, &l2, 3.0).is_ok());
        assert!(round(&l1, &l2, 3.5).unwrap_err().contains("too large"));
        assert!(round(&l1, &Element::Line { from: k, to: [20.0, 0.0] }, 1.0).unwrap_err().contains("tangentially"));
        assert!(round(&l1, &Element::Line { from: k, to: [5.0, 0.0] }, 1.0).unwrap_err().contains("back"));
        assert!(round(&l1, &l2, 0.0).is_err());
        assert_eq!(chamfer(&l1, &l2, 2.0).unwrap(), ([8.0, 0.0], [10.0, 2.0]));
        assert!(chamfer(&l1, &l2, 4.0).unwrap_err().contains("longer"));
        let arc = Element::Arc { from: k, to: [20.0, 0.0], centre: [15.0, 0.0], ccw: true };
        assert!(chamfer(&l1, &arc, 1.0).unwrap_err().contains("arc"));
        // A circle smaller than the radius on the side the rounding arc runs.
        let small = Element::Arc { from: k, to: [10.0, 2.0], centre: [9.0, 1.0], ccw: true };
        assert!(round(&l1, &small, 1.5).unwrap_err().contains("larger than an arc"));
    }
}
