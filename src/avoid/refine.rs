//! CL refinement near the singularity (seed 003 §5): examine the distance and the tool-axis angle
//! between consecutive CL points, and the machine-axis change the inverse kinematics makes of them;
//! where a step exceeds a threshold, insert points by linear interpolation of the tool tip and of the
//! tool-axis vector (normalised), and solve each point on the branch of seed 002 Table 1 closest to
//! its predecessor, so that passing the singular direction flips A's sign instead of turning C by 180
//! deg. Also measures the error the original discretisation makes: between two points, a control
//! without TCPM interpolates the machine axes linearly, and the tool tip leaves the straight CL chord;
//! its component along the tool axis is an overcut (into the part) or an undercut.

use super::AvoidError;
use crate::kinematics::{Joints, Pose};
use crate::machine::Machine;
use crate::path::{SegmentKind, Trajectory};
use crate::program::{Block, Motion, Program, Targets};
use crate::units::{DEG, MM};
use nalgebra::Vector3;

/// Refinement thresholds between neighbouring points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefineOptions {
    /// Largest tool-tip step, m.
    pub max_step: f64,
    /// Largest tool-axis angle, rad.
    pub max_angle: f64,
    /// Largest change of a rotary machine axis, rad.
    pub max_axis_step: f64,
}

impl Default for RefineOptions {
    fn default() -> Self {
        RefineOptions { max_step: 1.0 * MM, max_angle: 1.0 * DEG, max_axis_step: 2.0 * DEG }
    }
}

/// Chord errors of a program run in machine coordinates (linear interpolation of the axes).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ChordError {
    /// Deepest tool-tip excursion into the part along the tool axis, mm (>= 0).
    pub overcut_mm: f64,
    /// Largest excursion away from the part along the tool axis, mm (>= 0).
    pub undercut_mm: f64,
    /// Largest tool-tip distance from the chord, mm, and the workpiece x where it happens.
    pub max_deviation_mm: f64,
    pub at_x_mm: f64,
    /// Largest change of the secondary (C) axis between two points, degrees, and steps turning it by
    /// more than 90 deg (the 180 deg flips).
    pub max_c_step_deg: f64,
    pub c_flips: usize,
}

/// What refinement did.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Refinement {
    pub points_before: usize,
    pub points_after: usize,
    pub before: ChordError,
    pub after: ChordError,
    /// Largest distance of a refined tool tip from the original CL polyline, m.
    pub max_tip_error_m: f64,
}

/// The semi-cylinder test piece of seed 003 §5 (Fig. 11-13): a diagonal groove over a half cylinder,
/// the tool axis normal to the surface, 141 CL poses; crossing the top, the tool axis passes the
/// singular direction (vertical) exactly. Cylinder radius 50 mm about the workpiece y axis, groove
/// 2 mm deep, the tool tip from -60 to +60 deg around the cylinder while y goes -30 to +30 mm (chordal
/// deviation below the paper's 0.01 mm), F1000.
pub fn semi_cylinder() -> Program {
    let (radius, depth, n) = (50.0 * MM, 2.0 * MM, 141usize);
    let blocks = (0..n)
        .map(|k| {
            let u = k as f64 / (n - 1) as f64;
            let theta = (-60.0 + 120.0 * u) * DEG;
            let normal = Vector3::new(theta.sin(), 0.0, theta.cos());
            let tip = normal * (radius - depth) + Vector3::new(0.0, (-30.0 + 60.0 * u) * MM, 0.0);
            Block {
                line: k + 1,
                column: 1,
                number: None,
                motion: if k == 0 { Motion::Rapid } else { Motion::Linear },
                targets: Targets { x: Some(tip.x), y: Some(tip.y), z: Some(tip.z), tool_axis: Some([normal.x, normal.y, normal.z]), ..Default::default() },
                arc: None,
                feed: Some(crate::program::Feed { value_per_min: 1000.0, rotary_per_min: 1000.0, mode: crate::program::FeedMode::PerMinute }),
                tcp: true,
                datum: [0.0; 3],
                orientation: crate::program::Orientation::AxisLinear,
                events: Vec::new(),
                dwell_s: None,
                tolerance: Default::default(),
                offset_assumed: false,
                exact: crate::program::Exact::Blend,
            }
        })
        .collect();
    Program {
        source: "builtin:semi-cylinder (seed 003 test piece, 141 CL poses)".into(),
        dialect: crate::program::Dialect::Cl,
        name: Some("SEMI_CYLINDER".into()),
        blocks,
        diagnostics: Vec::new(),
    }
}

/// The poses of the TCPM blocks (tool tip and axis in the workpiece frame), by block index.
fn poses(program: &Program, machine: &Machine, options: &crate::job::JobOptions) -> Result<Vec<(usize, Pose)>, AvoidError> {
    let traj = Trajectory::from_program(program, machine, &options.path);
    if let Some(d) = traj.diagnostics.iter().find(|d| d.severity == crate::program::Severity::Error) {
        return Err(AvoidError::Refused(format!("line {}: {}", d.line, d.message)));
    }
    let mut out: Vec<(usize, Pose)> = Vec::new();
    if let Some((b, seg)) = super::start_pose(program, &traj).filter(|(b, _)| program.blocks[*b].tcp) {
        out.push((b, Pose { tip: seg.tip0, axis: machine.forward(&seg.q0).axis }));
    }
    for seg in &traj.segments {
        // A dwell is not a point: its block keeps its time (and its motion, if any, has a segment).
        if seg.kind == SegmentKind::Dwell || !program.blocks.get(seg.block).is_some_and(|b| b.tcp) {
            continue;
        }
        let pose = Pose { tip: seg.tip1, axis: machine.forward(&seg.q1).axis };
        match out.last_mut() {
            Some(last) if last.0 == seg.block => last.1 = pose,
            _ => out.push((seg.block, pose)),
        }
    }
    Ok(out)
}

/// True if the tool axis of `pose` lies on the machine's singular direction, where C is free (seed 001
/// Table 1: C undefined).
fn on_singular_direction(machine: &Machine, pose: &Pose) -> bool {
    machine.singular_direction().cross(&pose.axis).norm() < 1e-9
}

fn with_joints(block: &Block, machine: &Machine, pose: &Pose, q: &Joints) -> Block {
    let mut b = block.clone();
    let names = machine.axis_names();
    let mut t = Targets { x: Some(pose.tip.x), y: Some(pose.tip.y), z: Some(pose.tip.z), ..Targets::default() };
    for i in [machine.primary_axis(), machine.secondary_axis()] {
        t.set_rotary(names[i].chars().next().unwrap_or('C'), q[i]);
    }
    b.targets = t;
    b
}

/// The conventional postprocessor (seed 002 Table 1's first solution, seed 003 Fig. 15): every TCPM
/// pose on the branch with the primary axis >= 0, C kept continuous (multi-turn) and held on the
/// singular direction itself. Crossing the singular direction, C turns by 180 deg in one step.
pub fn conventional(program: &Program, machine: &Machine, options: &crate::job::JobOptions) -> Result<Program, AvoidError> {
    let (pi, si) = (machine.primary_axis(), machine.secondary_axis());
    let mut out = program.clone();
    let mut prev_c: Option<f64> = None;
    for (block, pose) in poses(program, machine, options)? {
        let sols = machine.inverse_all(&pose).map_err(|e| AvoidError::Refused(format!("line {}: {e}", program.blocks[block].line)))?;
        let mut q = if sols[0][pi] >= 0.0 { sols[0] } else { sols[1] };
        let singular = on_singular_direction(machine, &pose);
        if let Some(c) = prev_c {
            q[si] = if singular { c } else { c + (q[si] - c + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI };
        }
        prev_c = Some(q[si]);
        out.blocks[block] = with_joints(&program.blocks[block], machine, &pose, &q);
    }
    out.source = format!("{} (conventional post)", program.source);
    Ok(out)
}

/// Refine `program` (CL data, or TCPM axis blocks read as CL): densify where a step exceeds a threshold
/// and solve each point on the branch nearest its predecessor.
pub fn refine(program: &Program, machine: &Machine, opts: &RefineOptions, options: &crate::job::JobOptions) -> Result<(Program, Refinement), AvoidError> {
    if !(opts.max_step > 0.0 && opts.max_angle > 0.0 && opts.max_axis_step > 0.0) {
        return Err(AvoidError::Refused("refinement thresholds must be positive".into()));
    }
    let ps = poses(program, machine, options)?;
    if ps.len() < 2 {
        return Err(AvoidError::Refused("fewer than two CL points under TCPM: nothing to refine".into()));
    }
    let before_prog = conventional(program, machine, options)?;
    let mut out = program.clone();
    out.blocks.clear();
    let mut prev: Option<(Pose, Joints)> = None;
    // The program's first points while all are on the singular direction (where each was written in
    // `out`, its block, its pose and joints): their C is free until a step leaves the direction.
    let mut leading: Vec<(usize, usize, Pose, Joints)> = Vec::new();
    let mut left_singular = false;
    // A point written at `out_at` for block `at_block`: one of the leading points while none has left
    // the direction (left other than by a feed step, they keep their C).
    let mut mark = |leading: &mut Vec<(usize, usize, Pose, Joints)>, out_at: usize, at_block: usize, p: &Pose, q: &Joints| {
        if !left_singular {
            if on_singular_direction(machine, p) {
                leading.push((out_at, at_block, *p, *q));
            } else {
                left_singular = true;
                leading.clear();
            }
        }
    };
    let si = machine.secondary_axis();
    let by_block: std::collections::BTreeMap<usize, Pose> = ps.iter().copied().collect();
    let mut points_after = 0;
    let mut max_tip_error: f64 = 0.0;
    for (bi, block) in program.blocks.iter().enumerate() {
        let Some(pose) = by_block.get(&bi).copied() else {
            match prev {
                // A TCPM move that goes nowhere (it has no segment): it stays where the last point
                // is, on the refined branch; its own words would now move the axes.
                Some((p, q)) if block.tcp && !block.targets.is_empty() => {
                    mark(&mut leading, out.blocks.len(), bi, &p, &q);
                    out.blocks.push(with_joints(block, machine, &p, &q));
                }
                _ => out.blocks.push(block.clone()),
            }
            continue;
        };
        let solve = |p: &Pose, q_prev: &Joints| machine.inverse(p, q_prev).map_err(|e| AvoidError::Refused(format!("line {}: {e}", block.line)));
        let q_end = match &prev {
            None => {
                // The first point: the conventional branch (A >= 0), as a post would start.
                let sols = machine.inverse_all(&pose).map_err(|e| AvoidError::Refused(format!("line {}: {e}", block.line)))?;
                if sols[0][machine.primary_axis()] >= 0.0 { sols[0] } else { sols[1] }
            }
            Some((_, q_prev)) => solve(&pose, q_prev)?,
        };
        if let (Some((p0, mut q0)), Motion::Linear) = (prev, block.motion) {
            // The program's first points on the singular direction: their C is free (every C gives
            // the same tool axis), so they take the C the first step off it needs, as a post starts;
            // kept, C would turn in one step however finely that step is cut.
            if !leading.is_empty() && !on_singular_direction(machine, &pose) {
                let off = (p0.axis * (1.0 - 1e-6) + pose.axis * 1e-6).try_normalize(1e-12).unwrap_or(pose.axis);
                q0[si] = solve(&Pose { tip: p0.tip, axis: off }, &q0)?[si];
                for (out_at, at_block, at_pose, mut q) in leading.drain(..) {
                    q[si] = q0[si];
                    out.blocks[out_at] = with_joints(&program.blocks[at_block], machine, &at_pose, &q);
                }
            }
            // How many pieces this step needs.
            let angle = p0.axis.angle(&pose.axis);
            let mut pieces = ((pose.tip - p0.tip).norm() / opts.max_step).ceil().max((angle / opts.max_angle).ceil()).max(1.0) as usize;
            let axis_step = |q0: &Joints, q1: &Joints| (3..5).map(|i| (q1[i] - q0[i]).abs()).fold(0.0, f64::max);
            pieces = pieces.max((axis_step(&q0, &q_end) / opts.max_axis_step).ceil() as usize).min(4096);
            // Densify until every sub-step keeps within the axis threshold (or 4096 pieces), or until
            // halving the sub-steps no longer shrinks the largest: a turn of C where the tool axis
            // passes the singular direction itself, which no cutting removes.
            let mut inserted: Vec<(Pose, Joints)>;
            let mut coarser: Option<(f64, Vec<(Pose, Joints)>)> = None;
            loop {
                inserted = Vec::with_capacity(pieces);
                let mut q = q0;
                let mut worst: f64 = 0.0;
                for j in 1..=pieces {
                    let u = j as f64 / pieces as f64;
                    let axis = (p0.axis * (1.0 - u) + pose.axis * u).try_normalize(1e-12).unwrap_or(pose.axis);
                    let p = Pose { tip: p0.tip * (1.0 - u) + pose.tip * u, axis };
                    let qj = solve(&p, &q)?;
                    worst = worst.max(axis_step(&q, &qj));
                    inserted.push((p, qj));
                    q = qj;
                }
                if worst <= opts.max_axis_step * (1.0 + 1e-9) || pieces >= 4096 {
                    break;
                }
                if let Some((w, fewer)) = coarser.take() {
                    if worst > 0.75 * w {
                        inserted = fewer;
                        break;
                    }
                }
                coarser = Some((worst, inserted));
                pieces = (pieces * 2).min(4096);
            }
            for (j, (p, q)) in inserted.iter().enumerate() {
                // Points on the chord between two original points: distance to it is rounding only.
                let chord = pose.tip - p0.tip;
                let along = if chord.norm() > 0.0 { (p.tip - p0.tip).dot(&chord) / chord.norm_squared() } else { 0.0 };
                max_tip_error = max_tip_error.max((p0.tip + chord * along.clamp(0.0, 1.0) - p.tip).norm());
                let mut b = with_joints(block, machine, p, q);
                if j + 1 < inserted.len() {
                    b.number = None;
                }
                // The block's dwell and events come before its motion: once, with the first piece.
                if j > 0 {
                    b.dwell_s = None;
                    b.events.clear();
                }
                mark(&mut leading, out.blocks.len(), bi, p, q);
                out.blocks.push(b);
                points_after += 1;
            }
            prev = inserted.last().copied();
            continue;
        }
        mark(&mut leading, out.blocks.len(), bi, &pose, &q_end);
        out.blocks.push(with_joints(block, machine, &pose, &q_end));
        points_after += 1;
        prev = Some((pose, q_end));
    }
    out.source = format!("{} (refined)", program.source);
    let before = chord_error(&before_prog, machine, options);
    let after = chord_error(&out, machine, options);
    Ok((out, Refinement { points_before: ps.len(), points_after, before, after, max_tip_error_m: max_tip_error }))
}

/// The chord errors of a program executed in machine coordinates: each five-axis feed step with its
/// machine axes interpolated linearly, the tool tip compared with the straight chord between the
/// step's end points (21 samples per step), along the interpolated tool axis.
pub fn chord_error(program: &Program, machine: &Machine, options: &crate::job::JobOptions) -> ChordError {
    let traj = Trajectory::from_program(program, machine, &options.path);
    let si = machine.secondary_axis();
    let mut e = ChordError { overcut_mm: 0.0, undercut_mm: 0.0, max_deviation_mm: 0.0, at_x_mm: f64::NAN, max_c_step_deg: 0.0, c_flips: 0 };
    // Steps between CL points only: where the program does not start at its first pose, the move into
    // it comes from wherever the machine stands (its C there is the start's, not a step of the path).
    let mut before_first = super::start_pose(program, &traj).is_none();
    for seg in &traj.segments {
        if before_first && program.blocks.get(seg.block).is_some_and(|b| b.tcp) {
            before_first = false;
            continue;
        }
        if !seg.is_path_move() || seg.feed <= 0.0 {
            continue;
        }
        let dc = (seg.q1[si] - seg.q0[si]).abs().to_degrees();
        e.max_c_step_deg = e.max_c_step_deg.max(dc);
        if dc > 90.0 {
            e.c_flips += 1;
        }
        let (a0, a1) = (machine.forward(&seg.q0).axis, machine.forward(&seg.q1).axis);
        for k in 1..20 {
            let u = k as f64 / 20.0;
            let q: Joints = std::array::from_fn(|i| seg.q0[i] * (1.0 - u) + seg.q1[i] * u);
            let tip = machine.forward(&q).tip - seg.datum;
            let chord = seg.tip0 * (1.0 - u) + seg.tip1 * u;
            let n = (a0 * (1.0 - u) + a1 * u).try_normalize(1e-12).unwrap_or(a1);
            let d = tip - chord;
            let along = d.dot(&n) / MM;
            e.overcut_mm = e.overcut_mm.max(-along);
            e.undercut_mm = e.undercut_mm.max(along);
            if d.norm() / MM > e.max_deviation_mm {
                e.max_deviation_mm = d.norm() / MM;
                e.at_x_mm = chord.x / MM;
            }
        }
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_test_piece_has_141_poses_normal_to_the_cylinder_and_crosses_the_pole() {
        let p = semi_cylinder();
        assert_eq!(p.blocks.len(), 141);
        let top = &p.blocks[70].targets;
        let a = top.tool_axis.expect("CL");
        assert!((a[2] - 1.0).abs() < 1e-12, "vertical at the top");
        // The tip lies 48 mm from the cylinder axis (50 mm radius, 2 mm groove).
        for b in &p.blocks {
            let (x, z) = (b.targets.x.unwrap(), b.targets.z.unwrap());
            assert!(((x * x + z * z).sqrt() - 0.048).abs() < 1e-12);
        }
    }
}
