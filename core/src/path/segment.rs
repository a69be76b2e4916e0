//! Blocks -> segments: resolve each move's start and end axis values, length and duration.

use super::{PathOptions, Sample};
use crate::kinematics::{Joints, Pose, SinCos, Turn, TwoRotaryChain};
use crate::machine::{ContourTolerance, Machine};
use crate::program::{Block, Diagnostic, FeedMode, Motion, Orientation, Program, Severity};
use crate::units::{DEG_PER_MIN, MM, MM_PER_MIN};
use nalgebra::Vector3;

use super::geometry::{ArcPath, GreatCircle};

/// How a segment moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SegmentKind {
    /// G00: every axis linear, the slowest at its maximum velocity.
    Rapid,
    /// Feed move with tool-centre-point management: tip on a line in the workpiece, rotaries linear.
    Tcp,
    /// Feed move without TCPM: machine axes linear.
    Axes,
    /// A dwell (`G4`, `DELAY/`): every axis stands still at `q0` for the duration.
    Dwell,
}

/// One move of the program.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    pub kind: SegmentKind,
    /// Index of the block in [`Program::blocks`], its line and number.
    pub block: usize,
    pub line: usize,
    pub number: Option<u64>,
    /// Start time and duration, s.
    pub t0: f64,
    pub duration: f64,
    /// Tool-tip path length at the start and length of this move (workpiece frame), m.
    pub s0: f64,
    pub length: f64,
    pub q0: Joints,
    pub q1: Joints,
    /// Tool tip at start and end, program coordinates, m.
    pub tip0: Vector3<f64>,
    pub tip1: Vector3<f64>,
    /// Datum shift in effect, m.
    pub datum: Vector3<f64>,
    /// Programmed tool-tip feed, m/s (0 for rapid and rotary-only moves).
    pub feed: f64,
    /// For a piece of a G02/G03 arc, its circle (program coordinates): the tool tip (TCPM) or the
    /// linear machine axes (no TCPM) follow it instead of the line `tip0..tip1`.
    pub arc: Option<Box<ArcPath>>,
    /// For a piece of a TCPM move whose tool axis turns on a great circle
    /// ([`Orientation::GreatCircle`]): the tool axis follows it and the rotaries follow the axis.
    pub orient: Option<Box<GreatCircle>>,
    /// The contour tolerance in effect (the program's, else the machine's): how far the control may
    /// smooth the path away from this segment's start point ([`crate::singularity::Knots`]).
    pub tolerance: ContourTolerance,
    /// Whether the move's block is a path move (its programmed path, the tip under TCPM or the
    /// linear axes without, at least [`MIN_PATH`]): decided per block, so that a piece beside the
    /// pole, short because the rotaries turn fast there, is part of the path as its block is.
    pub path: bool,
    /// Whether the machine stops at the end of the segment's block ([`crate::program::Exact`]).
    pub exact: crate::program::Exact,
}

/// Largest turn of a rotary axis over one piece of a great-circle move: the planners fit splines
/// through piece ends, and the rotaries are not linear along a great circle (near the pole C turns
/// much faster in the middle of a move than at its ends).
pub const ORIENT_PIECE_RAD: f64 = 0.25 * std::f64::consts::PI / 180.0;

/// Largest turn of the tool axis over one piece of a great-circle move.
const ORIENT_STEP_RAD: f64 = 1.0 * std::f64::consts::PI / 180.0;

/// A tool axis closer than this to the singular direction (rad) is on the pole: the secondary
/// rotary axis' angle is undefined there.
const POLE_EPS: f64 = 1e-9;

/// Most pieces one great-circle move is cut into: a circle through the pole itself would need C to
/// jump; refining stops here and the move is refused.
const MAX_ORIENT_PIECES: usize = 1 << 16;

/// Under exact path (LinuxCNC G61), the largest turn between blocks that runs on without a stop:
/// colinear to rounding (LinuxCNC's TP_ANGLE_EPSILON, 1e-6 rad).
pub const EXACT_PATH_RAD: f64 = 1e-6;

impl Segment {
    /// Whether the machine stops between this segment and `next` because this one's block ends in
    /// an exact stop, or under exact path turns by more than [`EXACT_PATH_RAD`] into `next`'s
    /// direction (`turn`, rad) ([`crate::program::Exact`]).
    pub fn stops_before(&self, next: &Segment, turn: f64) -> bool {
        use crate::program::Exact;
        self.block != next.block
            && match self.exact {
                Exact::Blend => false,
                Exact::Path => turn > EXACT_PATH_RAD,
                Exact::Stop => true,
            }
    }

    /// What the control interpolates along the segment, at its start or end: the tool tip (m) and
    /// the rotaries (rad) under TCPM, else the machine axes. Spline knots are thinned on it.
    pub fn interpolated(&self, end: bool) -> Joints {
        let q = if end { self.q1 } else { self.q0 };
        match self.kind {
            SegmentKind::Tcp => {
                let tip = if end { self.tip1 } else { self.tip0 };
                [tip.x, tip.y, tip.z, q[3], q[4]]
            }
            _ => q,
        }
    }

    /// The programmed linear path at fraction `u`, program coordinates: the tool tip under TCPM,
    /// the linear machine axes minus the datum without it (the arc for arc pieces, else the line).
    fn linear_at(&self, u: f64) -> Vector3<f64> {
        match &self.arc {
            Some(arc) => arc.point(u),
            None if self.kind == SegmentKind::Tcp => self.tip0 + (self.tip1 - self.tip0) * u,
            None => {
                let (a, b) = (Vector3::new(self.q0[0], self.q0[1], self.q0[2]), Vector3::new(self.q1[0], self.q1[1], self.q1[2]));
                a + (b - a) * u - self.datum
            }
        }
    }

    /// Length of the linear machine axes' path (the arc's for an arc piece without TCPM), m.
    pub fn linear_axes_length(&self) -> f64 {
        match (&self.arc, self.kind) {
            (Some(arc), SegmentKind::Axes) => arc.length(),
            _ => ((self.q1[0] - self.q0[0]).powi(2) + (self.q1[1] - self.q0[1]).powi(2) + (self.q1[2] - self.q0[2]).powi(2)).sqrt(),
        }
    }

    /// True for a simultaneous five-axis feed move: the programmed linear motion (the tool tip under
    /// TCPM, the linear machine axes without it) and the rotary axes both move. A rotary-only move
    /// without TCPM (the table turning under a retracted tool) is positioning, not five-axis.
    pub fn is_five_axis(&self) -> bool {
        let rotates = (self.q1[3] - self.q0[3]).abs() > 1e-12 || (self.q1[4] - self.q0[4]).abs() > 1e-12;
        rotates && self.is_path_move()
    }

    /// True for a feed move along a programmed path: the tool tip (TCPM) or the linear machine axes
    /// (no TCPM) move. Rapids and rotary-only moves are not path moves.
    pub fn is_path_move(&self) -> bool {
        match self.kind {
            SegmentKind::Rapid | SegmentKind::Dwell => false,
            SegmentKind::Tcp | SegmentKind::Axes => self.path,
        }
    }

    /// Axis values at fraction `u` of the move.
    pub fn joints_at(&self, u: f64, machine: &Machine) -> Joints {
        let rot = self.rotaries_at(u, machine);
        self.joints_with(u, rot, || TwoRotaryChain::turns(&rot), machine)
    }

    /// The rotary angles at fraction `u`.
    fn rotaries_at(&self, u: f64, machine: &Machine) -> [f64; 2] {
        let lerp = |a: f64, b: f64| a + (b - a) * u;
        let rot = [lerp(self.q0[3], self.q1[3]), lerp(self.q0[4], self.q1[4])];
        match (&self.orient, self.kind) {
            // The rotaries that put the tool axis on the great circle, the solution nearest the
            // piece's own linear blend (a piece turns each rotary by at most ORIENT_PIECE_RAD).
            (Some(gc), SegmentKind::Tcp) => machine.rotaries_near(&gc.axis(u), &rot).unwrap_or(rot),
            _ => rot,
        }
    }

    /// [`Segment::joints_at`] with the rotaries `rot` there and their turns (asked only if needed).
    fn joints_with(&self, u: f64, rot: [f64; 2], turns: impl FnOnce() -> [Turn; 2], machine: &Machine) -> Joints {
        let lerp = |a: f64, b: f64| a + (b - a) * u;
        match self.kind {
            SegmentKind::Tcp => {
                let tip = self.linear_at(u) + self.datum;
                let l = machine.chain.linear_for_turns(&tip, &turns());
                [l.x, l.y, l.z, rot[0], rot[1]]
            }
            SegmentKind::Axes if self.arc.is_some() => {
                let l = self.linear_at(u) + self.datum;
                [l.x, l.y, l.z, rot[0], rot[1]]
            }
            _ => std::array::from_fn(|i| lerp(self.q0[i], self.q1[i])),
        }
    }

    /// The commanded sample at fraction `u` (time `t`); `index` is this segment's index.
    pub fn sample(&self, index: usize, u: f64, t: f64, machine: &Machine) -> Sample {
        // The rotaries' sines and cosines once, for the linear axes, the tip and the tool axis.
        let rot = self.rotaries_at(u, machine);
        self.sample_turns(index, u, t, machine, rot, TwoRotaryChain::turns(&rot))
    }

    /// [`Segment::sample`] for a sampler moving along the path: the rotaries' sines and cosines
    /// follow the samples from `turns` ([`SinCos`], the same to rounding).
    pub fn sample_along(&self, index: usize, u: f64, t: f64, machine: &Machine, turns: &mut [SinCos; 2]) -> Sample {
        let rot = self.rotaries_at(u, machine);
        let turned = [turns[0].at(rot[0]), turns[1].at(rot[1])];
        self.sample_turns(index, u, t, machine, rot, turned)
    }

    fn sample_turns(&self, index: usize, u: f64, t: f64, machine: &Machine, rot: [f64; 2], turns: [Turn; 2]) -> Sample {
        let q = self.joints_with(u, rot, || turns, machine);
        // A dwell of 0 s has no rate (it moves nothing in no time).
        let per_s = if self.duration > 0.0 { 1.0 / self.duration } else { 0.0 };
        let rate = [(self.q1[3] - self.q0[3]) * per_s, (self.q1[4] - self.q0[4]) * per_s];
        let tip = match self.kind {
            SegmentKind::Tcp => self.linear_at(u),
            _ => machine.chain.forward_turns(&q, &turns).tip - self.datum,
        };
        let (axis, axis_rate) = match (&self.orient, self.kind) {
            (Some(gc), SegmentKind::Tcp) => (gc.axis(u), gc.axis_rate(u) * per_s),
            _ => (machine.chain.orientation_of(&turns), machine.chain.orientation_rate_of(&turns, &rate)),
        };
        Sample { t, s: self.s0 + self.length * u, segment: index, q, tip, axis, axis_rate, feed: self.feed }
    }
}

/// A block whose programmed path (m) is shorter than this is a rotary move, F in deg/min: LinuxCNC
/// counts an axis as moving from 1e-7 mm (emccanon.cc, `tiny`); Fanuc, Siemens and Heidenhain time
/// any programmed linear motion as a path. A stated 1 um next to a C flip is a path, however
/// short: the control runs C at its limit there. Decided per block, never per piece.
const MIN_PATH: f64 = 1e-10;

/// Why planning stops at a block that would run the program to `end_s`, past the bound `bound_s`.
fn beyond_bound(what: &str, hint: &str, end_s: f64, bound_s: f64) -> String {
    format!(
        "{what} would make the program run {:.1} h, beyond the bound of {:.1} h: {hint}planning stops here \
         (raise the bound with --max-program-hours if the program is meant to run this long)",
        end_s / 3600.0,
        bound_s / 3600.0
    )
}

fn diag(b: &Block, message: String) -> Diagnostic {
    Diagnostic { line: b.line, column: b.column, severity: Severity::Error, message }
}

/// Plan every motion block of `program` on `machine`, starting from all axes at zero (NC programs)
/// or at the first pose (CL data, [`crate::program::Dialect::starts_at_first_pose`]). An arc block
/// becomes pieces of at most [`ARC_PIECE_RAD`](super::geometry::ARC_PIECE_RAD), each exact on the arc. Blocks that cannot be run (an
/// axis the machine lacks, an unreachable pose) are reported and skipped.
pub fn plan(program: &Program, machine: &Machine, options: &PathOptions) -> (Vec<Segment>, Vec<Diagnostic>) {
    let mut planner = SegmentPlanner::new(machine, program.dialect, options);
    let (mut segments, mut diags) = (Vec::new(), Vec::new());
    for (bi, b) in program.blocks.iter().enumerate() {
        if !planner.push(machine, bi, b, &mut segments, &mut diags) {
            break;
        }
    }
    (segments, diags)
}

/// Blocks to segments one block at a time (the state a control carries from block to block: where
/// the axes are, the time and the path length so far), so that a program is planned as it is read.
#[derive(Debug, Clone)]
pub struct SegmentPlanner {
    options: PathOptions,
    q: Joints,
    t: f64,
    s: f64,
    letters: [char; 2],
    first_orientation: bool,
    at_start: bool,
    /// The control counts degrees in a combined move's feed path ([`crate::program::Dialect::counts_degrees_in_feed_path`]).
    degrees_in_path: bool,
    stopped: bool,
    /// Linear axes already warned of beyond their range under a work offset the program never set.
    warned_range: [bool; 3],
}

impl SegmentPlanner {
    /// A planner at the program start of a program in `dialect` on `machine` (the machine each
    /// [`push`](Self::push) is given).
    pub fn new(machine: &Machine, dialect: crate::program::Dialect, options: &PathOptions) -> Self {
        let letters: [char; 2] = [3, 4].map(|i| machine.axes[i].name.chars().next().unwrap_or('?').to_ascii_uppercase());
        SegmentPlanner { options: *options, q: [0.0; 5], t: 0.0, s: 0.0, letters, first_orientation: true, at_start: dialect.starts_at_first_pose(), degrees_in_path: dialect.counts_degrees_in_feed_path(), stopped: false, warned_range: [false; 3] }
    }

    /// Plan block `bi`: its segments go to `segments`, what stops it to `diags`. False once planning
    /// has stopped (the program would run beyond the bound on its duration): no later block is planned.
    pub fn push(&mut self, machine: &Machine, bi: usize, b: &Block, segments: &mut Vec<Segment>, diags: &mut Vec<Diagnostic>) -> bool {
        if self.stopped {
            return false;
        }
        let (options, letters) = (&self.options.clone(), self.letters);
        let (mut q, mut t, mut s) = (self.q, self.t, self.s);
        let (mut first_orientation, mut at_start) = (self.first_orientation, self.at_start);
        let tolerance = b.tolerance.on(machine.contour_tolerance);
        let stopped = 'blocks: {
            // A dwell comes before the block's motion. Before CL data's first pose nothing has started.
            // A dwell of 0 s is a segment too: the machine stops for it all the same, as LinuxCNC's
            // task waits for the motion queue to drain before any dwell (emctask.cc: EMC_TRAJ_DELAY
            // waits for motion and IO) and controls document `G4 P0` as a stop (Yaskawa iCube G04: "a
            // negative or zero length dwell results in a stop in motion"); the planner ends its run there.
            if let Some(d) = b.dwell_s.filter(|d| *d >= 0.0 && !at_start) {
                if t + d > options.max_duration_s {
                    diags.push(diag(b, beyond_bound(&format!("this dwell ({d} s)"), "", t + d, options.max_duration_s)));
                    break 'blocks true;
                }
                let datum = Vector3::from(b.datum);
                let tip = machine.forward(&q).tip - datum;
                segments.push(Segment { kind: SegmentKind::Dwell, block: bi, line: b.line, number: b.number, t0: t, duration: d, s0: s, length: 0.0, q0: q, q1: q, tip0: tip, tip1: tip, datum, feed: 0.0, arc: None, orient: None, tolerance, path: false, exact: b.exact });
                t += d;
            }
            if b.targets.is_empty() {
                break 'blocks false;
            }
            if let Some(l) = ['A', 'B', 'C'].into_iter().find(|l| b.targets.rotary(*l).is_some() && !letters.contains(l)) {
                diags.push(diag(b, format!("axis {l} does not exist on machine {}: block skipped", machine.name)));
                break 'blocks false;
            }
            let datum = Vector3::from(b.datum);
            let tcp = b.tcp;
            let tip0 = machine.forward(&q).tip - datum;
            let mut rot1 = [q[3], q[4]];
            for slot in 0..2 {
                if let Some(v) = b.targets.rotary(letters[slot]) {
                    rot1[slot] = v;
                }
            }
            // Rotaries the program puts off the pole: a tool axis after them takes the solution
            // nearest them, not the first pose's convention (which stays where they say nothing of
            // the side, on the pole: SING.I's `A0 C0` before its first tool vector); once the block
            // is in range.
            let rotaries_set = letters.iter().any(|l| b.targets.rotary(*l).is_some()) && machine.chain.singular_direction().cross(&machine.chain.orientation(&rot1)).norm() > 1e-9;
            let q1: Joints;
            let tip1: Vector3<f64>;
            // Said once the block's pieces are planned (a great circle the range breaks is an error).
            let mut range_note: Option<String> = None;
            if tcp {
                let tip = Vector3::new(b.targets.x.unwrap_or(tip0.x), b.targets.y.unwrap_or(tip0.y), b.targets.z.unwrap_or(tip0.z));
                if let Some(axis) = b.targets.tool_axis {
                    let pose = Pose { tip: tip + datum, axis: Vector3::from(axis) };
                    let mut previous = q;
                    if first_orientation {
                        // First pose: the + sign of seed 001 Table 1 (non-negative primary angle).
                        if let Ok(all) = machine.inverse_all(&pose) {
                            let p = machine.primary_axis();
                            let pick = if all[0][p] >= 0.0 { all[0] } else { all[1] };
                            previous[3] = pick[3];
                            previous[4] = pick[4];
                        }
                    }
                    let solved = inverse(machine, &pose, &previous, b.offset_assumed);
                    match solved {
                        Ok(sol) => {
                            rot1 = [sol[3], sol[4]];
                            // The range, not the path, turned the axes onto the other solution (or
                            // another turn of C): said, as the motion it makes is the machine's choice.
                            range_note = range_forced_warning(machine, &pose.axis, &[previous[3], previous[4]], &rot1).filter(|_| !first_orientation);
                        }
                        Err(e) => {
                            diags.push(diag(b, format!("tool pose cannot be reached: {e}; block skipped")));
                            break 'blocks false;
                        }
                    }
                    first_orientation = false;
                }
                let l = machine.chain.linear_for(&(tip + datum), &rot1);
                q1 = [l.x, l.y, l.z, rot1[0], rot1[1]];
                tip1 = tip;
            } else {
                let lin = |k: usize, w: Option<f64>| w.map_or(q[k], |v| v + datum[k]);
                q1 = [lin(0, b.targets.x), lin(1, b.targets.y), lin(2, b.targets.z), rot1[0], rot1[1]];
                tip1 = machine.forward(&q1).tip - datum;
            }
            if self.range_stops(b, machine, &q, &q1, diags) {
                break 'blocks false;
            }
            if rotaries_set {
                first_orientation = false;
            }
            if at_start {
                // CL data: the first pose is where the tool is; nothing moves to it.
                at_start = false;
                q = q1;
                break 'blocks false;
            }
            let kind = match (b.motion, tcp) {
                (Motion::Rapid, _) => SegmentKind::Rapid,
                (_, true) => SegmentKind::Tcp,
                (_, false) => SegmentKind::Axes,
            };
            // The move's pieces: one for a line, arcs cut at most ARC_PIECE_RAD apart.
            let arc = match (kind, &b.arc) {
                (SegmentKind::Rapid, _) | (_, None) => None,
                (_, Some(spec)) => {
                    let (start, end) = if tcp {
                        (tip0, tip1)
                    } else {
                        (Vector3::new(q[0], q[1], q[2]) - datum, Vector3::new(q1[0], q1[1], q1[2]) - datum)
                    };
                    Some(ArcPath::new(spec, b.motion == Motion::ArcCcw, start, end))
                }
            };
            // A TCPM feed move whose tool axis turns, under vector interpolation: pieces along the great circle.
            let great_circle = match (kind, b.orientation) {
                (SegmentKind::Tcp, Orientation::GreatCircle) => {
                    let (o0, o1) = (machine.chain.orientation(&[q[3], q[4]]), machine.chain.orientation(&[q1[3], q1[4]]));
                    let sd = machine.singular_direction();
                    let on_pole = |o: &Vector3<f64>| o.cross(&sd).norm() < POLE_EPS;
                    match GreatCircle::new(o0, o1) {
                        // A move from or to the pole: the secondary axis is undefined there, so the great
                        // circle (a meridian) would ask it to stand at the other end's angle from the
                        // start; C turns from where it stands instead, the rotaries linear.
                        Some(_) if on_pole(&o0) || on_pole(&o1) => None,
                        Some(gc) => Some(gc),
                        None if o0.dot(&o1) < 0.0 => {
                            diags.push(diag(b, "the tool axis turns by 180 deg: no single great circle joins its start and end directions; block skipped".into()));
                            break 'blocks false;
                        }
                        None => None,
                    }
                }
                _ => None,
            };
            let circle = match great_circle {
                Some(gc) => match great_circle_pieces(&gc, arc.as_ref(), q, tip0, tip1, datum, machine, b.offset_assumed) {
                    Ok(p) if b.targets.tool_axis.is_none() && p.last().is_some_and(|l| other_solution(&l.1, &q1)) => {
                        // Said, and made with the rotaries linear to the written positions (the
                        // CAM system's path in the axes), so the blocks after it start where the
                        // control stands.
                        diags.push(diag(b, other_solution_message(machine, &p[p.len() - 1].1, &q1)));
                        None
                    }
                    Ok(p) => Some(p),
                    Err(e) => {
                        diags.push(diag(b, e));
                        break 'blocks false;
                    }
                },
                None => None,
            };
            let pieces = match (arc, circle) {
                (_, Some(p)) => p,
                (None, None) => vec![(q, q1, tip0, tip1, None, None)],
                (Some(arc), None) => {
                    // The whole move as one segment gives each piece end its axes (the arc's point, the
                    // rotaries linear in the fraction), the same as sampling it would.
                    let whole = Segment { kind, block: bi, line: b.line, number: b.number, t0: 0.0, duration: 0.0, s0: 0.0, length: 0.0, q0: q, q1, tip0, tip1, datum, feed: 0.0, arc: Some(Box::new(arc)), orient: None, tolerance, path: false, exact: b.exact };
                    let n = arc.pieces();
                    let end = |k: usize| -> (Joints, Vector3<f64>) {
                        let u = k as f64 / n as f64;
                        let qk = match k {
                            0 => q,
                            k if k == n => q1,
                            _ => whole.joints_at(u, machine),
                        };
                        (qk, if tcp { arc.point(u) } else { machine.forward(&qk).tip - datum })
                    };
                    let mut pieces = Vec::with_capacity(n);
                    for k in 0..n {
                        let ((qa, ta), (qb, tb)) = (end(k), end(k + 1));
                        if self.range_stops(b, machine, &q, &qb, diags) {
                            break 'blocks false;
                        }
                        pieces.push((qa, qb, ta, tb, Some(Box::new(arc.piece(k as f64 / n as f64, (k + 1) as f64 / n as f64))), None));
                    }
                    pieces
                }
            };
            if let Some(w) = range_note {
                diags.push(Diagnostic { severity: Severity::Warning, ..diag(b, w) });
            }
            let n = pieces.len() as f64;
            let mut segs: Vec<Segment> = Vec::with_capacity(pieces.len());
            for (pq0, pq1, ptip0, ptip1, parc, porient) in pieces {
                let mut seg = Segment {
                    kind,
                    block: bi,
                    line: b.line,
                    number: b.number,
                    t0: 0.0,
                    duration: 0.0,
                    s0: 0.0,
                    length: 0.0,
                    q0: pq0,
                    q1: pq1,
                    tip0: ptip0,
                    tip1: ptip1,
                    datum,
                    feed: 0.0,
                    arc: parc,
                    orient: porient,
                    tolerance,
                    path: false,
                    exact: b.exact,
                };
                seg.length = tip_length(&seg, machine);
                segs.push(seg);
            }
            // The path F runs along (the tip under TCPM, the linear axes without), over the whole
            // block: whether the block is a path move is the block's, not its pieces'.
            let path_of = |seg: &Segment| if kind == SegmentKind::Tcp { seg.length } else { seg.linear_axes_length() };
            let block_path: f64 = segs.iter().map(path_of).sum();
            let rotary_only = block_path < MIN_PATH;
            for mut seg in segs {
                (seg.t0, seg.s0, seg.path) = (t, s, !rotary_only);
                let (pq0, pq1) = (seg.q0, seg.q1);
                let rot_len = ((pq1[3] - pq0[3]).powi(2) + (pq1[4] - pq0[4]).powi(2)).sqrt();
                let duration = match kind {
                    SegmentKind::Rapid => rapid_duration(&pq0, &pq1, machine),
                    _ => {
                        let Some(feed) = b.feed else {
                            diags.push(diag(b, "feed move without a feed: block skipped".into()));
                            break 'blocks false;
                        };
                        match feed.mode {
                            // The block's time, shared by its pieces: evenly (equal arc lengths) or by
                            // their share of the great circle (tip and axis both move evenly in it).
                            // `--feed` gives the tool tip its feed on every path move, inverse-time
                            // ones too (a move of the rotary axes alone keeps its programmed time).
                            // (Fanuc without TCP counts degrees in the path of F: such a move of
                            // linear and rotary axes keeps its programmed time, as the tip feed
                            // does not give it.)
                            FeedMode::InverseTime if options.feed_override_mm_per_min.is_some() && !rotary_only && !(self.degrees_in_path && kind != SegmentKind::Tcp && rot_len > 0.0) => {
                                let f = options.feed_override_mm_per_min.unwrap_or(0.0) * MM_PER_MIN;
                                let path_len = path_of(&seg);
                                seg.feed = seg.length / (path_len / f);
                                path_len / f
                            }
                            FeedMode::InverseTime => match &seg.orient {
                                Some(gc) => 60.0 / feed.value_per_min * (gc.u1 - gc.u0),
                                None => 60.0 / feed.value_per_min / n,
                            },
                            FeedMode::PerMinute if self.degrees_in_path && kind != SegmentKind::Tcp => {
                                // Fanuc: degrees count as the program's length unit in the path F is along.
                                let unit = MM * feed.value_per_min / feed.rotary_per_min;
                                let f = options.feed_override_mm_per_min.map_or(feed.rotary_per_min, |o| o * feed.rotary_per_min / feed.value_per_min);
                                let t = ((seg.linear_axes_length() / unit).powi(2) + rot_len.to_degrees().powi(2)).sqrt() / f * 60.0;
                                if seg.length > 1e-9 && t > 0.0 {
                                    seg.feed = seg.length / t;
                                }
                                t
                            }
                            FeedMode::PerMinute => {
                                let path_len = path_of(&seg);
                                if !rotary_only {
                                    let f = options.feed_override_mm_per_min.unwrap_or(feed.value_per_min) * MM_PER_MIN;
                                    seg.feed = seg.length / (path_len / f);
                                    path_len / f
                                } else {
                                    // Rotary axes only: F is read in degrees per minute.
                                    rot_len / (feed.rotary_per_min * DEG_PER_MIN)
                                }
                            }
                        }
                    }
                };
                if !(duration > 1e-12) {
                    // Nothing moves, or a piece too short to time: the next starts where it ends.
                    q = pq1;
                    continue;
                }
                if t + duration > options.max_duration_s {
                    let what = match (kind, b.feed) {
                        (SegmentKind::Rapid, _) => "this rapid move".to_string(),
                        (_, Some(f)) if f.mode == FeedMode::InverseTime => format!("this move (inverse-time F{})", f.value_per_min),
                        (_, Some(f)) => format!("this move (F{} over {:.3} mm)", options.feed_override_mm_per_min.unwrap_or(f.value_per_min), seg.length * n * 1e3),
                        (_, None) => "this move".to_string(),
                    };
                    let what = format!("{what} takes {:.1} h and", duration * n / 3600.0);
                    diags.push(diag(b, beyond_bound(&what, "a feed typo? ", t + duration * n, options.max_duration_s)));
                    break 'blocks true;
                }
                if seg.feed == 0.0 {
                    // Rapid, inverse-time and rotary-only moves: the tool-tip speed they result in.
                    seg.feed = seg.length / duration;
                }
                seg.duration = duration;
                t += duration;
                s += seg.length;
                q = pq1;
                segments.push(seg);
            }
            false
        };
        (self.q, self.t, self.s, self.first_orientation, self.at_start, self.stopped) = (q, t, s, first_orientation, at_start, stopped);
        !stopped
    }
}

/// One piece of a move: start and end axes, start and end tool tips, its part of an arc and of a
/// great circle.
type Piece = (Joints, Joints, Vector3<f64>, Vector3<f64>, Option<Box<ArcPath>>, Option<Box<GreatCircle>>);

/// The pieces of a TCPM move from axes `q` whose tool axis turns on `gc` while the tip runs from
/// `tip0` to `tip1` on a line or on `arc`: cut at most [`ORIENT_STEP_RAD`] of the tool axis and
/// [`ARC_PIECE_RAD`](super::geometry::ARC_PIECE_RAD) of the arc apart, and halved until no rotary turns more than
/// [`ORIENT_PIECE_RAD`] over a piece. Each end's rotaries are the inverse solution nearest the
/// previous end's, so the axes follow the circle continuously; a circle too close to the pole for
/// that (C would have to jump), or an end outside an axis range, is an error.
/// The joints for `pose` nearest `previous`: within every range, or within the rotary ranges only
/// where the work offset is assumed (the linear ranges are then the range check's, which warns).
fn inverse(machine: &Machine, pose: &Pose, previous: &Joints, offset_assumed: bool) -> Result<Joints, crate::kinematics::KinematicsError> {
    if offset_assumed {
        machine.inverse_in_rotary_ranges(pose, previous)
    } else {
        machine.inverse(pose, previous)
    }
}

/// What a move does where the ranges chose its rotaries ([`Machine::range_forced`]): the axis that
/// would leave its range, and the turn the machine makes instead.
fn range_forced_warning(machine: &Machine, axis: &Vector3<f64>, previous: &[f64; 2], chosen: &[f64; 2]) -> Option<String> {
    let (k, v) = machine.range_forced(axis, previous, chosen)?;
    let (a, names) = (&machine.axes[3 + k], [&machine.axes[3].name, &machine.axes[4].name]);
    Some(format!(
        "{} would reach {:.3} deg on the solution nearest the last block's, outside its range {:.3}..{:.3} deg: \
         the axes turn to {} {:.3} deg, {} {:.3} deg instead ({:.1} and {:.1} deg in this block, the tool \
         axis' path between them the machine's)",
        a.name,
        v.to_degrees(),
        a.limits.min.to_degrees(),
        a.limits.max.to_degrees(),
        names[0],
        chosen[0].to_degrees(),
        names[1],
        chosen[1].to_degrees(),
        (chosen[0] - previous[0]).abs().to_degrees(),
        (chosen[1] - previous[1]).abs().to_degrees(),
    ))
}

fn great_circle_pieces(gc: &GreatCircle, arc: Option<&ArcPath>, q: Joints, tip0: Vector3<f64>, tip1: Vector3<f64>, datum: Vector3<f64>, machine: &Machine, offset_assumed: bool) -> Result<Vec<Piece>, String> {
    let tip_at = |u: f64| arc.map_or_else(|| tip0 + (tip1 - tip0) * u, |a| a.point(u));
    let steps = ((gc.angle / ORIENT_STEP_RAD).ceil() as usize).max(arc.map_or(1, ArcPath::pieces)).max(1);
    // Fractions still to reach, the next on top.
    let mut todo: Vec<f64> = (1..=steps).rev().map(|k| k as f64 / steps as f64).collect();
    let mut ends: Vec<(f64, Joints)> = vec![(0.0, q)];
    while let Some(ub) = todo.pop() {
        let &(ua, qa) = ends.last().expect("starts with the move's start");
        let pose = Pose { tip: tip_at(ub) + datum, axis: gc.axis(ub) };
        let qb = inverse(machine, &pose, &qa, offset_assumed).map_err(|e| format!("the tool axis cannot follow its great circle {:.1} % into the move: {e}; block skipped", ub * 100.0))?;
        let turn = (qb[3] - qa[3]).abs().max((qb[4] - qa[4]).abs());
        if turn > ORIENT_PIECE_RAD {
            if ends.len() + todo.len() >= MAX_ORIENT_PIECES || ub - ua < 1e-9 {
                // The circle stays off the pole, but a rotary axis' range sends the axes to the other
                // solution (or another turn of C): a jump of the axes, not of the geometry.
                if let Some((k, v)) = machine.range_forced(&pose.axis, &[qa[3], qa[4]], &[qb[3], qb[4]]) {
                    let a = &machine.axes[3 + k];
                    return Err(format!(
                        "{} would leave its range {:.3}..{:.3} deg {:.1} % into the move (at {:.3} deg): the rotary axes \
                         cannot follow the tool axis' great circle on the other solution without a jump of {:.1} deg; block skipped",
                        a.name,
                        a.limits.min.to_degrees(),
                        a.limits.max.to_degrees(),
                        ua * 100.0,
                        v.to_degrees(),
                        turn.to_degrees()
                    ));
                }
                return Err(format!(
                    "the tool axis' great circle passes through the singular direction {:.1} % into the move: \
                     the rotary axes cannot follow it (C would jump by {:.1} deg); block skipped",
                    ua * 100.0,
                    turn.to_degrees()
                ));
            }
            todo.push(ub);
            todo.push(0.5 * (ua + ub));
            continue;
        }
        ends.push((ub, qb));
    }
    Ok(ends
        .windows(2)
        .map(|w| {
            let ((ua, qa), (ub, qb)) = (w[0], w[1]);
            (qa, qb, tip_at(ua), tip_at(ub), arc.map(|a| Box::new(a.piece(ua, ub))), Some(Box::new(gc.piece(ua, ub))))
        })
        .collect())
}

/// Whether the rotaries `tracked` at the end of a great circle, followed from the block's start, are
/// not the `programmed` ones: the same tool axis on the other solution, or another turn of an axis
/// (1e-6 rad apart: the tracked end solves the programmed axes' own tool axis, far closer than that
/// off the pole, which such a move never starts or ends on).
fn other_solution(tracked: &Joints, programmed: &Joints) -> bool {
    (tracked[3] - programmed[3]).abs() > 1e-6 || (tracked[4] - programmed[4]).abs() > 1e-6
}

/// A great-circle move whose programmed rotary positions are not where the great circle takes the
/// axes from the block's start. The controls' manuals at hand say the end orientation may be given
/// by the rotary axis positions (840D Job Planning 02/2011 §6.2.3: "the ultimate orientation of each
/// block can be set ... by programming the rotary axis positions") but not how the axes reach the
/// programmed solution from the circle's: the motion is not known.
fn other_solution_message(machine: &Machine, tracked: &Joints, programmed: &Joints) -> String {
    let d = |v: f64| v.to_degrees();
    // A four-axis machine's second slot is locked and unnamed: its axis alone.
    let axes = |q: &Joints| match machine.chain.is_four_axis() {
        true => format!("{} {:.3} deg", machine.axes[3].name, d(q[3])),
        false => format!("{} {:.3} deg {} {:.3} deg", machine.axes[3].name, d(q[3]), machine.axes[4].name, d(q[4])),
    };
    let whole_turns = |x: f64| (x / std::f64::consts::TAU - (x / std::f64::consts::TAU).round()).abs() < 1e-6;
    let how = if whole_turns(tracked[3] - programmed[3]) && whole_turns(tracked[4] - programmed[4]) { "another turn of the same axis positions" } else { "the other solution for the same tool axis" };
    format!(
        "the programmed {} set the tool axis, but on its great circle from the block's start the axes reach it at {} \
         ({how}): how the control turns the axes to the programmed positions under vector interpolation is not \
         known (program the tool vector, or interpolate the axes: ORIAXES, PATHCTRL AXIS); modelled with the \
         rotary axes linear to the programmed positions",
        axes(programmed),
        axes(tracked),
    )
}

/// The error for a block whose end (or arc point) `q` lies outside an axis range, if it does.
impl SegmentPlanner {
    /// Whether an axis beyond its range stops the block (an error, in `diags`). A linear axis, where
    /// the block's datum holds a work offset the program never set ([`Block::offset_assumed`]), is
    /// where the unknown offset puts it: warned of once per axis, and the block runs; such an axis
    /// a later block leaves where it was (`from`, the block's start: a machine-coordinate move of
    /// another axis) is not blamed again.
    fn range_stops(&mut self, b: &Block, machine: &Machine, from: &Joints, q: &Joints, diags: &mut Vec<Diagnostic>) -> bool {
        for (i, v) in q.iter().enumerate() {
            if machine.axes[i].limits.contains(*v) || (i < 3 && self.warned_range[i] && (v - from[i]).abs() < 1e-9) {
                continue;
            }
            if i < 3 && b.offset_assumed {
                if !std::mem::replace(&mut self.warned_range[i], true) {
                    let a = &machine.axes[i];
                    let message = format!(
                        "axis {} would move to {:.3} mm, outside its range {:.3}..{:.3} mm, with the program's work offset taken as zero: the operator's offset decides (not checked for this axis again)",
                        a.name,
                        v * 1e3,
                        a.limits.min * 1e3,
                        a.limits.max * 1e3
                    );
                    diags.push(Diagnostic { severity: Severity::Warning, ..diag(b, message) });
                }
                continue;
            }
            if let Some(d) = out_of_range(b, machine, q) {
                diags.push(d);
            }
            return true;
        }
        false
    }
}

fn out_of_range(b: &Block, machine: &Machine, q: &Joints) -> Option<Diagnostic> {
    let (i, _) = q.iter().enumerate().find(|(i, v)| !machine.axes[*i].limits.contains(**v))?;
    let a = &machine.axes[i];
    let (unit, f) = if i < 3 { ("mm", 1e3) } else { ("deg", 1f64.to_degrees()) };
    Some(diag(
        b,
        format!(
            "axis {} would move to {:.3} {unit}, outside its range {:.3}..{:.3} {unit}: block skipped",
            a.name,
            q[i] * f,
            a.limits.min * f,
            a.limits.max * f
        ),
    ))
}

/// Tool-tip path length of a segment in the workpiece frame (exact for TCP moves, else integrated).
/// How long a rapid (G00) from `q0` to `q1` takes: every axis linear, the slowest at its maximum
/// velocity.
pub(super) fn rapid_duration(q0: &Joints, q1: &Joints, machine: &Machine) -> f64 {
    (0..5).map(|i| (q1[i] - q0[i]).abs() / machine.axes[i].limits.velocity).fold(0.0, f64::max)
}

pub(super) fn tip_length(seg: &Segment, machine: &Machine) -> f64 {
    if seg.kind == SegmentKind::Tcp {
        return seg.arc.as_ref().map_or_else(|| (seg.tip1 - seg.tip0).norm(), |a| a.length());
    }
    const N: usize = 64;
    let mut len = 0.0;
    let mut prev = machine.forward(&seg.q0).tip;
    for k in 1..=N {
        let u = k as f64 / N as f64;
        let p = machine.forward(&seg.joints_at(u, machine)).tip;
        len += (p - prev).norm();
        prev = p;
    }
    len
}
