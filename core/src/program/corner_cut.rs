//! A corner cut into two contour elements a program made: the element before cut back to where the
//! rounding arc or chamfer ([`super::corner`]) leaves it, the corner as a block of its own, the
//! element after cut back to where it meets it. Shared by the Klartext reader (`RND`, `CHF`) and
//! the Sinumerik reader (`RND=`, `RNDM=`, `CHF=`, `CHR=`); each says which blocks the elements are
//! and what the corner's feed is by its control's rule.

use nalgebra::{Matrix3, Vector3};

use super::corner::{chamfer, chamfer_chord, round, tangential, Element};
use super::cutter_comp::ArcFeed;
use super::{ArcSpec, Block, Feed, FeedMode, Motion, Plane};
use crate::units::MM;

/// A corner to cut: a rounding of radius `size` or a chamfer whose sides (or chords) are `size` long (m), its
/// own feed if it has one (program unit per minute), and the block it was written in.
#[derive(Debug, Clone)]
pub(crate) struct Cut {
    pub(crate) round: bool,
    /// A chamfer's ends lie `size` from the corner as the chord, on lines or arcs (Fanuc's `,C`);
    /// else along two lines.
    pub(crate) chord: bool,
    pub(crate) size: f64,
    pub(crate) feed: Option<f64>,
    pub(crate) line: usize,
    pub(crate) col: usize,
    pub(crate) number: Option<u64>,
}

/// A contour element held back in case a corner is cut at its end (Klartext: an `RND` or `CHF`
/// after it; Sinumerik: `CHF=`/`RND=` in it): its block
/// and its programmed start and end (program coordinates, m, rad), with the unit and tilted plane
/// it was read in.
#[derive(Debug, Clone)]
pub(crate) struct Held {
    pub(crate) b: Block,
    pub(crate) start: [f64; 6],
    pub(crate) end: [f64; 6],
    pub(crate) unit: f64,
    pub(crate) tilt: Option<Matrix3<f64>>,
    /// How its feed on an arc is read (M109/M110/M111 in force).
    pub(crate) arc_feed: ArcFeed,
}

impl Held {
    /// A block the interpreter made, from `start` to where it stands now, as an element (its arc
    /// feed the default: compensation's readers give their own).
    pub(crate) fn made(b: Block, start: [f64; 6], interp: &crate::program::interp::Interpreter) -> Held {
        Held { b, start, end: interp.position(), unit: interp.unit(), tilt: interp.tilt(), arc_feed: ArcFeed::default() }
    }
}

/// A move from `start` to `end` (program coordinates) stays in the working plane whose tool axis
/// is `tool_axis`: that axis and the rotary axes stand still, as a corner's elements must.
pub(crate) fn in_plane(start: [f64; 6], end: [f64; 6], tool_axis: usize) -> bool {
    [tool_axis, 3, 4, 5].into_iter().all(|k| (end[k] - start[k]).abs() <= 1e-12 * (1.0 + end[k].abs()))
}

/// The element a held block is in the working plane's coordinates (`axes`: its two axes and the
/// tool axis), or why it cannot be one a corner joins.
fn element(h: &Held, axes: (usize, usize, usize), which: &str) -> Result<Element, String> {
    let (a0, a1, a2) = axes;
    if !in_plane(h.start, h.end, a2) {
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

/// The held elements `p` and `n` (which starts where `p` ends) meet tangentially in the working
/// plane: there is no corner between them (false where either is no element of the plane).
pub(crate) fn meet_tangentially(p: &Held, n: &Held, plane: Plane) -> bool {
    let axes = plane.axes();
    matches!((element(p, axes, "before"), element(n, axes, "after")), (Ok(a), Ok(b)) if tangential(&a, &b))
}

/// The element before cut back, the corner, the element after cut back; why not.
pub(crate) fn make(c: &Cut, p: &Held, n: &Held, plane: Plane, mode: FeedMode) -> Result<(Held, Held, Held), String> {
    let axes = plane.axes();
    let (before, after) = (element(p, axes, "before")?, element(n, axes, "after")?);
    let size = c.size;
    let (t1, t2, arc) = if c.round {
        let r = round(&before, &after, size)?;
        (r.from, r.to, Some((r.centre, r.ccw)))
    } else {
        let (t1, t2) = if c.chord { chamfer_chord(&before, &after, size)? } else { chamfer(&before, &after, size)? };
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
