//! A Heidenhain TNC's tool radius compensation (`RL`/`RR` until `R0`) over the blocks a Klartext
//! program makes, by the TNC user's manuals' rules:
//! - "The TNC does not put radius compensation into effect until the end of the block in which it is
//!   first programmed"; in that block and in the `R0` block that ends it "the TNC always positions
//!   the tool perpendicular to the programmed starting or end position" (TNC 620 ISO user's manual,
//!   340 56x-02, p. 146; TNC 370 p. 4-17): the tool ends the first block perpendicular to the
//!   contour's first element at its start, and leaves the last element perpendicular to it at its
//!   end, for the `R0` block's programmed point ("The tool center moves ... to the programmed
//!   coordinates", TNC 620 Klartext 01/2022 p. 134);
//! - it starts in a straight line only ("You cannot activate radius compensation in a circle
//!   block", p. 154), and a change of side needs an `R0` block between (p. 146);
//! - outside corners: "a transitional arc" (TNC 640 ISO 34059x-05 p. 201; the iTNC 530's spline
//!   option, MP7680, is not read), here about the programmed corner with the tool's radius, the
//!   only arc that meets both offset elements tangentially at the radius from the corner;
//! - inside corners: "the intersection of the tool center paths" (iTNC 530 60642x-04 p. 219); a
//!   contour the tool cannot follow stops the program ("Tool radius too large", p. 379).
//!
//! In a tilted working plane the contour is the plane's ("the TNC ... positions the tool in the
//! working plane", the offsets in its coordinates): each block is taken into them and back.
//!
//! The offsets themselves are LinuxCNC's geometry ([`super::geometry`]), which makes the same
//! corners; what differs is where compensation starts ([`super::Rule::Tnc`]).

use super::{ArcFeed, Comp, CompState, Fail, Rule, Side};
use crate::program::{ArcSpec, Block};
use nalgebra::{Matrix3, Vector3};

/// A failure as the TNC reports it: a contour the tool cannot follow stops the program there ("Tool
/// radius too large"), what this reader does not read is said as it is.
pub(crate) fn said(f: &Fail) -> String {
    match f {
        Fail::Contour(why) => format!("{why}; the TNC stops here (\"Tool radius too large\"), and so does this reader"),
        Fail::NotRead(why) => why.clone(),
    }
}

/// Compensation beside a Klartext program's reader: off, or on with the moves it holds.
#[derive(Debug, Clone, Default)]
pub(crate) struct TncComp {
    st: CompState,
}

impl TncComp {
    /// Compensation on (a side and a radius), or moves still held.
    pub(crate) fn busy(&self) -> bool {
        self.st.on.is_some() || !self.st.queue.is_empty()
    }

    /// Compensation was started and no contour element has followed the block that started it.
    pub(crate) fn entry_only(&self) -> bool {
        self.st.on.as_ref().is_some_and(|c| c.radius > 0.0 && (c.entry_held || c.first))
    }

    /// The side in effect, if any.
    pub(crate) fn side(&self) -> Option<Side> {
        self.st.on.as_ref().map(|c| c.side)
    }

    /// `RL`/`RR` from `R0`: the tool's compensation value `radius` (m; a negative one runs on the
    /// other side), the tool centre now at `at` (program coordinates, m).
    pub(crate) fn start(&mut self, side: Side, radius: f64, at: [f64; 3]) {
        let (side, radius) = if radius < 0.0 { (if side == Side::Left { Side::Right } else { Side::Left }, -radius) } else { (side, radius) };
        self.st.on = Some(Comp { rule: Rule::Tnc, entry_held: false, side, radius, first: true, current: at });
        self.st.endpoint = None;
    }

    /// A block the program made while compensation is on: `op` and `p` its programmed start and end
    /// (program coordinates, m). What is settled goes to `out`; the last move is held for the corner
    /// after it. An error: the TNC stops there.
    ///
    /// In a tilted working plane (`tilt`, its axes' columns in the workpiece) the contour is the
    /// plane's: the block is offset in the plane's coordinates and placed back in the workpiece's.
    ///
    /// `arc_feed` is how the block's feed on an arc is read (M109/M110/M111): M110 slows an arc
    /// whose inside the tool runs on so that its cutting edge keeps the programmed feed, the tool
    /// centre at F (rho - r) / rho on an arc of radius rho.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn feed(&mut self, mut b: Block, op: [f64; 6], p: [f64; 6], unit: f64, tilt: Option<Matrix3<f64>>, arc_feed: ArcFeed, out: &mut Vec<Block>) -> Result<(), Fail> {
        let tilt = tilted(tilt);
        if let Some(r) = &tilt {
            if b.targets.a.is_some() || b.targets.b.is_some() || b.targets.c.is_some() {
                return Err(Fail::NotRead("rotary axes moving with radius compensation on in a tilted working plane are not read".into()));
            }
            to_plane(&mut b, r);
        }
        let from = out.len();
        let corners = self.st.corner_arcs;
        let done = self.offset(b, op, p, unit, arc_feed, out);
        if let Some(r) = &tilt {
            out[from..].iter_mut().for_each(|b| to_workpiece(b, r));
        }
        if done.is_ok() && arc_feed == ArcFeed::Edge && self.st.corner_arcs > corners {
            // At an outside corner the control inserts an arc about the corner, a contour of no
            // radius: the feed kept at the cutting edge there ("On very small outside corners the TNC
            // may increase the feed rate so much that the tool or workpiece can be damaged", TNC 640
            // ISO user's manual 34059x-01 §9.4) is in no manual at hand.
            return Err(Fail::NotRead("the feed kept at the cutting edge on outside arcs too (a TNC's M109, the 840D's CFC, its reset state) at an outside corner with radius compensation on: the control's feed on the arc it inserts about the corner is in no manual at hand (M110 or M111, CFIN or CFTCP, are read)".into()));
        }
        done
    }

    fn offset(&mut self, b: Block, op: [f64; 6], p: [f64; 6], unit: f64, arc_feed: ArcFeed, out: &mut Vec<Block>) -> Result<(), Fail> {
        if let Some(why) = self.st.full() {
            return Err(Fail::NotRead(why));
        }
        let metric = unit == crate::units::MM;
        let Some(radius) = self.st.on.as_ref().map(|c| c.radius) else {
            self.st.dequeue(out);
            out.push(b);
            return Ok(());
        };
        let moves = !b.targets.is_empty();
        if !moves || radius == 0.0 {
            if self.st.queue.is_empty() {
                out.push(b);
            } else {
                self.st.queue.push(super::Held::Other(b));
            }
            return Ok(());
        }
        let (op, p) = ([op[0], op[1], op[2]], [p[0], p[1], p[2]]);
        match (&b.arc, b.motion) {
            (Some(spec), m) if m.is_arc() => {
                // A plane tilted by nothing (cycle 19 with A+0) keeps the workpiece's axes.
                let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
                let tilted = spec.frame.is_some_and(|f| f.iter().flatten().zip(identity.iter().flatten()).any(|(a, b)| (a - b).abs() > 1e-12));
                if tilted || spec.plane != crate::program::Plane::Xy {
                    return Err(Fail::NotRead("an arc outside the working plane (XY) with radius compensation on is not read".into()));
                }
                let turns = spec.extra_turns as i32 + 1;
                let turn = if m == crate::program::Motion::ArcCw { -turns } else { turns };
                let centre = [spec.centre[0], spec.centre[1]];
                super::geometry::arc(&mut self.st, &b, op, p, centre, turn, metric, unit, out)?;
                let side = self.st.on.as_ref().map_or(Side::Left, |c| c.side);
                let inside = super::geometry::inside(side, turn);
                if arc_feed == ArcFeed::Edge || (arc_feed == ArcFeed::EdgeInside && inside) {
                    self.edge_feed(centre, [p[0], p[1]], if inside { -radius } else { radius })?;
                }
                Ok(())
            }
            _ => super::geometry::straight(&mut self.st, &b, op, p, metric, unit, out),
        }
    }

    /// M109/M110 (the 840D's CFC/CFIN) on the arc just queued, offset by `r` from the programmed
    /// one of radius rho = |end - centre| (negative: inside it): its feed times (rho + r) / rho, the
    /// cutting edge on the contour at the programmed feed (SINUMERIK 808D Programming and Operating
    /// Manual (Milling) 01/2014 p. 79: F (r_cont + r_tool) / r_cont outside, (r_cont - r_tool) / r_cont
    /// inside).
    fn edge_feed(&mut self, centre: [f64; 2], end: [f64; 2], r: f64) -> Result<(), Fail> {
        let rho = (end[0] - centre[0]).hypot(end[1] - centre[1]);
        let not_read = || Fail::NotRead("the feed at the cutting edge on an arc radius compensation did not offset about its centre is not read".into());
        let Some(super::Held::Arc { block, centre: c, .. }) = self.st.queue.last_mut() else {
            return Err(not_read());
        };
        if (c[0] - centre[0]).hypot(c[1] - centre[1]) > 1e-9 * (1.0 + rho) || !(rho + r > 0.0) {
            return Err(not_read());
        }
        if let Some(f) = block.feed.as_mut() {
            f.value_per_min *= (rho + r) / rho;
        }
        Ok(())
    }

    /// `R0` (or the program's end): the last element's move ends perpendicular to it at its end, and
    /// everything held goes out. An error where the block that started compensation is still held:
    /// no contour element followed it to say where the tool stands.
    pub(crate) fn stop(&mut self, unit: f64, tilt: Option<Matrix3<f64>>, out: &mut Vec<Block>) -> Result<(), Fail> {
        let from = out.len();
        let done = self.release(unit, out);
        if let Some(r) = &tilted(tilt) {
            out[from..].iter_mut().for_each(|b| to_workpiece(b, r));
        }
        done
    }

    /// The block that ends compensation (`R0`, the 840D's `G40`), programmed to `end` (program
    /// coordinates, m): the last element's move ends perpendicular to it at its end, everything held
    /// goes out, then this block runs from there to its programmed point (in a tilted plane, placed
    /// in the workpiece's coordinates).
    pub(crate) fn leave(&mut self, mut b: Block, end: [f64; 6], unit: f64, tilt: Option<Matrix3<f64>>, out: &mut Vec<Block>) -> Result<(), Fail> {
        self.stop(unit, tilt, out)?;
        match tilt {
            Some(r) => {
                let w = r * Vector3::new(end[0], end[1], end[2]);
                (b.targets.x, b.targets.y, b.targets.z) = (Some(w.x), Some(w.y), Some(w.z));
            }
            None => {
                b.targets.x.get_or_insert(end[0]);
                b.targets.y.get_or_insert(end[1]);
            }
        }
        out.push(b);
        Ok(())
    }

    fn release(&mut self, unit: f64, out: &mut Vec<Block>) -> Result<(), Fail> {
        let Some(comp) = self.st.on.take() else {
            self.st.dequeue(out);
            return Ok(());
        };
        if comp.entry_held {
            self.st.dequeue(out);
            return Err(Fail::Contour("RL/RR ended before any contour element: the TNC places the tool perpendicular to the first element after the block that starts compensation, and there is none".into()));
        }
        if !comp.first {
            self.st.move_endpoint_and_flush([comp.current[0], comp.current[1]], unit == crate::units::MM, unit, out)?;
        }
        self.st.dequeue(out);
        self.st.endpoint = None;
        Ok(())
    }
}

/// A tilt that turns something (cycle 19 with every angle 0 leaves the workpiece's axes).
fn tilted(tilt: Option<Matrix3<f64>>) -> Option<Matrix3<f64>> {
    tilt.filter(|r| (r - Matrix3::identity()).abs().max() > 1e-12)
}

/// A block of a tilted plane (its X Y Z, an arc's centre, in the workpiece) in the plane's coordinates.
fn to_plane(b: &mut Block, r: &Matrix3<f64>) {
    let back = r.transpose();
    if let (Some(x), Some(y), Some(z)) = (b.targets.x, b.targets.y, b.targets.z) {
        let v = back * Vector3::new(x, y, z);
        (b.targets.x, b.targets.y, b.targets.z) = (Some(v.x), Some(v.y), Some(v.z));
    }
    if let Some(a) = b.arc.as_mut() {
        let c = back * Vector3::from(a.centre);
        a.centre = [c.x, c.y, c.z];
        a.frame = None;
    }
}

/// A block offset in a tilted plane's coordinates placed back in the workpiece's.
fn to_workpiece(b: &mut Block, r: &Matrix3<f64>) {
    if let (Some(x), Some(y), Some(z)) = (b.targets.x, b.targets.y, b.targets.z) {
        let v = r * Vector3::new(x, y, z);
        (b.targets.x, b.targets.y, b.targets.z) = (Some(v.x), Some(v.y), Some(v.z));
    }
    if let Some(a) = b.arc.as_mut() {
        let c = r * Vector3::from(a.centre);
        a.centre = [c.x, c.y, c.z];
        a.frame = Some(ArcSpec::frame_of(r));
    }
}
