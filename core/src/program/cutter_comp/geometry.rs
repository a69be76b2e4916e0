//! LinuxCNC's corner rules for cutter radius compensation (interp_convert.cc
//! `convert_straight_comp1/2`, `convert_arc_comp1/2`), and its queue of held moves (interp_queue.cc
//! `dequeue_canons`, `move_endpoint_and_flush`): pure geometry on the program's coordinates.

use super::{CompState, Fail, Held, Rule, Side};
use crate::program::{ArcSpec, Block, Motion, Plane};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

pub(super) fn inside(side: Side, turn: i32) -> bool {
    (side == Side::Left && turn > 0) || (side == Side::Right && turn < 0)
}

/// The counter-clockwise sweep from `p1` to `p2` about `c` in `turn` turns (interp_find.cc find_turn).
fn find_turn(p1: [f64; 2], c: [f64; 2], turn: i32, p2: [f64; 2]) -> f64 {
    if turn == 0 {
        return 0.0;
    }
    let mut alpha = (p1[1] - c[1]).atan2(p1[0] - c[0]);
    let mut beta = (p2[1] - c[1]).atan2(p2[0] - c[0]);
    if turn > 0 {
        if beta <= alpha {
            beta += TAU;
        }
        beta - alpha + (turn - 1) as f64 * TAU
    } else {
        if alpha <= beta {
            alpha += TAU;
        }
        beta - alpha + (turn + 1) as f64 * TAU
    }
}

fn polar(c: [f64; 2], r: f64, angle: f64) -> [f64; 2] {
    [c[0] + r * angle.cos(), c[1] + r * angle.sin()]
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn atan2(to: [f64; 2], from: [f64; 2]) -> f64 {
    (to[1] - from[1]).atan2(to[0] - from[0])
}

/// A block moved to `end` (x, y; z and the rotaries as the block has them).
fn ended(mut b: Block, end: [f64; 2], z: Option<f64>) -> Block {
    b.targets.x = Some(end[0]);
    b.targets.y = Some(end[1]);
    if z.is_some() {
        b.targets.z = z;
    }
    b
}

/// A compensated arc block: `b` ending at `end`, about `centre`, `turn` turns.
fn arc_block(b: &Block, end: [f64; 2], z: Option<f64>, centre: [f64; 2], turn: i32) -> Block {
    let mut a = ended(b.clone(), end, z);
    a.motion = if turn < 0 { Motion::ArcCw } else { Motion::ArcCcw };
    a.arc = Some(Box::new(ArcSpec { plane: Plane::Xy, centre: [centre[0], centre[1], 0.0], extra_turns: turn.unsigned_abs().saturating_sub(1), frame: None }));
    a
}

impl CompState {
    /// Emit every held block (interp_queue.cc dequeue_canons): the endpoint is then unknown.
    pub(super) fn dequeue(&mut self, out: &mut Vec<Block>) {
        self.endpoint = None;
        out.extend(self.queue.drain(..).map(|h| match h {
            Held::Straight { block, .. } | Held::Arc { block, .. } | Held::Other(block) => block,
        }));
    }

    /// Move the held moves' end to `p` and emit them (move_endpoint_and_flush): a move that would
    /// then run backwards, or an arc that would sweep further, gouges.
    pub(super) fn move_endpoint_and_flush(&mut self, p: [f64; 2], metric: bool, unit: f64, out: &mut Vec<Block>) -> Result<(), Fail> {
        if self.queue.is_empty() {
            return Ok(());
        }
        let endpoint = self.endpoint;
        for h in &mut self.queue {
            match h {
                Held::Arc { block, centre, turn, original } => {
                    let r1 = dist([block.targets.x.unwrap_or(0.0), block.targets.y.unwrap_or(0.0)], *centre);
                    let r2 = dist(p, *centre);
                    if (r1 - r2).abs() > 0.01 * unit {
                        return Err(format!("cutter compensation made an arc with mismatched radii {:.4} and {:.4} (LinuxCNC: a bug)", r1 / unit, r2 / unit).into());
                    }
                    if let Some(e) = endpoint {
                        let l2 = find_turn(e, *centre, *turn, p);
                        if *original != 0.0 && l2.abs() > original.abs() + if metric { 0.0254 } else { 0.001 } {
                            return Err("Arc move in concave corner cannot be reached by the tool without gouging".into());
                        }
                    }
                    block.targets.x = Some(p[0]);
                    block.targets.y = Some(p[1]);
                }
                Held::Straight { block, dir, rapid } => {
                    if let Some(e) = endpoint {
                        if dir[0] * (p[0] - e[0]) + dir[1] * (p[1] - e[1]) < 0.0 {
                            let kind = if *rapid { "Straight traverse" } else { "Straight feed" };
                            return Err(format!("{kind} in concave corner cannot be reached by the tool without gouging").into());
                        }
                    }
                    block.targets.x = Some(p[0]);
                    block.targets.y = Some(p[1]);
                }
                Held::Other(_) => {}
            }
        }
        self.dequeue(out);
        self.endpoint = Some(p);
        Ok(())
    }

    /// TNC: the block that started compensation, held at its programmed point, ends where the
    /// contour's first element puts the tool (`at`, perpendicular to it at its start: "the TNC
    /// always positions the tool perpendicular to the programmed starting or end position", TNC 620
    /// ISO user's manual p. 146); the moves held after it (in the tool axis only) go there too.
    pub(super) fn place_entry(&mut self, at: [f64; 2], out: &mut Vec<Block>) {
        let Some(on) = self.on.as_mut().filter(|c| c.entry_held) else { return };
        on.entry_held = false;
        on.current = [at[0], at[1], on.current[2]];
        for h in &mut self.queue {
            if let Held::Straight { block, .. } = h {
                block.targets.x = Some(at[0]);
                block.targets.y = Some(at[1]);
            }
        }
        self.dequeue(out);
        self.endpoint = Some(at);
    }

    /// The first held arc, if the queue starts with one (LinuxCNC looks at `qc().front()`).
    fn front_arc(&self) -> Option<([f64; 2], [f64; 2], i32)> {
        match self.queue.first() {
            Some(Held::Arc { block, centre, turn, .. }) => Some(([block.targets.x.unwrap_or(0.0), block.targets.y.unwrap_or(0.0)], *centre, *turn)),
            _ => None,
        }
    }
}

/// A straight move under compensation: `b` programmed from `op` to `p` (x, y, z).
pub(super) fn straight(st: &mut CompState, b: &Block, op: [f64; 3], p: [f64; 3], metric: bool, unit: f64, out: &mut Vec<Block>) -> Result<(), Fail> {
    let (pxy, opxy) = ([p[0], p[1]], [op[0], op[1]]);
    if pxy != opxy {
        let normal = {
            let on = st.on.as_ref().expect("compensation on");
            atan2(pxy, opxy) + if on.side == Side::Left { FRAC_PI_2 } else { -FRAC_PI_2 }
        };
        st.place_entry(polar(opxy, st.on.as_ref().map_or(0.0, |c| c.radius), normal), out);
    }
    let comp = st.on.clone().expect("compensation on");
    let small = comp.rule.small_corner();
    let (r, side) = (comp.radius, comp.side);
    let rapid = b.motion == Motion::Rapid;
    let c = comp.current;
    let cxy = [c[0], c[1]];
    let end;
    if comp.first && comp.rule == Rule::Tnc {
        // The block that starts compensation: held at its programmed point until the contour's
        // first element places it ([`CompState::place_entry`]).
        if pxy == cxy {
            return Err("radius compensation starts in a straight line in the working plane (TNC user's manual: \"The radius compensation must be in the block in which you move to the first contour element\"); this block does not move in it".into());
        }
        end = pxy;
        st.endpoint = None;
        st.queue.push(Held::Straight { block: ended(b.clone(), end, Some(p[2])), dir: [pxy[0] - cxy[0], pxy[1] - cxy[1]], rapid });
        if let Some(on) = &mut st.on {
            on.entry_held = true;
        }
    } else if comp.first {
        // convert_straight_comp1: the entry move ends perpendicular to its own direction.
        if dist(pxy, cxy) <= r {
            return Err("Length of cutter compensation entry move is not greater than the tool radius".into());
        }
        let alpha = atan2(pxy, cxy) + if side == Side::Left { FRAC_PI_2 } else { -FRAC_PI_2 };
        end = polar(pxy, r, alpha);
        st.endpoint = Some(cxy);
        st.queue.push(Held::Straight { block: ended(b.clone(), end, Some(p[2])), dir: [alpha.cos(), alpha.sin()], rapid });
    } else if pxy == opxy {
        // No XY motion: the tool stays where it is in XY.
        end = cxy;
        st.queue.push(Held::Straight { block: ended(b.clone(), end, Some(p[2])), dir: [0.0, 0.0], rapid });
    } else {
        // convert_straight_comp2.
        let mut theta = atan2(cxy, opxy);
        let mut alpha = atan2(pxy, opxy);
        let (beta, gamma) = match side {
            Side::Left => {
                if theta < alpha {
                    theta += TAU;
                }
                (theta - alpha - FRAC_PI_2, FRAC_PI_2)
            }
            Side::Right => {
                if alpha < theta {
                    alpha += TAU;
                }
                (alpha - theta - FRAC_PI_2, -FRAC_PI_2)
            }
        };
        end = polar(pxy, r, alpha + gamma);
        let mut mid = polar(opxy, r, alpha + gamma);
        let front = st.front_arc();
        let concave = !(-small..=PI + small).contains(&beta)
            || (beta > PI - small && front.is_some_and(|(_, _, turn)| (side == Side::Right && turn > 0) || (side == Side::Left && turn < 0)));
        if !concave && beta > small {
            // A convex corner: an arc about the programmed corner (a rapid goes straight).
            if rapid && comp.rule == Rule::Tnc {
                // The TNC rounds every outside corner with a transitional arc ("If necessary, the TNC
                // reduces the feed rate at outside corners", TNC 640 ISO user's manual 1/2015 p. 201);
                // at what feed it runs the arc before a rapid, or whether it goes straight as LinuxCNC
                // does, no manual at hand says.
                return Err(Fail::NotRead(
                    "an outside corner before a rapid (FMAX) with radius compensation on: the TNC rounds it with a transitional arc (TNC 640 ISO user's manual 1/2015 p. 201) at a feed its manuals do not give; not read (program the block with a feed F)".into(),
                ));
            }
            st.move_endpoint_and_flush(cxy, metric, unit, out)?;
            let corner = if rapid && comp.rule == Rule::LinuxCnc {
                ended(b.clone(), mid, Some(c[2]))
            } else {
                arc_block(b, mid, Some(c[2]), opxy, if side == Side::Left { -1 } else { 1 })
            };
            st.queue.push(Held::Other(corner));
            st.corner_arcs += 1;
            st.dequeue(out);
            st.endpoint = Some(mid);
        } else if concave {
            match front {
                None => {
                    // Line to line: back along the compensated path to where the offset lines meet.
                    let halfcorner = (beta + PI) / 2.0;
                    if halfcorner == 0.0 {
                        return Err("Zero degree inside corner is invalid for cutter compensation".into());
                    }
                    let retreat = r / halfcorner.tan();
                    mid = polar(cxy, retreat, theta + gamma);
                    st.move_endpoint_and_flush(mid, metric, unit, out)?;
                }
                Some((prev_end, prev_centre, prev_turn)) => {
                    // Arc to line: where the offset line meets the offset arc before it.
                    let oldrad = dist(prev_end, prev_centre);
                    let base_dir = atan2(pxy, opxy);
                    let theta = if prev_turn > 0 { base_dir + FRAC_PI_2 } else { base_dir - FRAC_PI_2 };
                    let phi = atan2(prev_centre, opxy);
                    let inside_prev = inside(side, prev_turn);
                    let oldrad_uncomp = if inside_prev { oldrad + r } else { oldrad - r };
                    let d = oldrad_uncomp * (theta - phi).cos();
                    let l = if inside_prev { (d - r) / oldrad } else { (d + r) / oldrad };
                    if !(-1.0..=1.0).contains(&l) {
                        return Err("Arc to straight motion makes a corner the compensated tool can't fit in without gouging".into());
                    }
                    let angle = match (inside_prev, prev_turn > 0) {
                        (true, true) | (false, false) => -l.acos() + theta + PI,
                        (true, false) | (false, true) => l.acos() + theta + PI,
                    };
                    mid = polar(prev_centre, oldrad, angle);
                    st.move_endpoint_and_flush(mid, metric, unit, out)?;
                }
            }
        } else {
            // Colinear, or an arc going on tangentially: nothing between.
            st.dequeue(out);
            st.endpoint = Some(cxy);
        }
        st.queue.push(Held::Straight { block: ended(b.clone(), end, Some(p[2])), dir: [pxy[0] - opxy[0], pxy[1] - opxy[1]], rapid });
    }
    if let Some(on) = &mut st.on {
        on.first = false;
        on.current = [end[0], end[1], p[2]];
    }
    Ok(())
}

/// An arc under compensation: `b` programmed from `op` to `p` about `centre`, `turn` turns.
#[allow(clippy::too_many_arguments)]
pub(super) fn arc(st: &mut CompState, b: &Block, op: [f64; 3], p: [f64; 3], centre: [f64; 2], turn: i32, metric: bool, unit: f64, out: &mut Vec<Block>) -> Result<(), Fail> {
    let (pxy, opxy) = ([p[0], p[1]], [op[0], op[1]]);
    let ccw = turn > 0;
    let (side, r) = st.on.as_ref().map(|c| (c.side, c.radius)).expect("compensation on");
    let tool_inside = (side == Side::Left && ccw) || (side == Side::Right && !ccw);
    let too_small = || Err(Fail::from("Tool radius not less than arc radius with comp"));
    if st.on.as_ref().is_some_and(|c| c.entry_held) {
        // The tool stands on the arc's offset at its start: towards the centre when inside it.
        let start_radius = dist(opxy, centre);
        if tool_inside && start_radius <= r {
            return too_small();
        }
        let toward = atan2(opxy, centre);
        st.place_entry(polar(centre, if tool_inside { start_radius - r } else { start_radius + r }, toward), out);
    }
    let comp = st.on.clone().expect("compensation on");
    let small = comp.rule.small_corner();
    let c = comp.current;
    let cxy = [c[0], c[1]];
    let arc_radius = dist(pxy, centre);
    let new_end;
    if comp.first && comp.rule == Rule::Tnc {
        return Err("radius compensation cannot start in a circle block (TNC user's manual: \"You cannot activate radius compensation in a circle block. Activate it beforehand in a straight-line block\")".into());
    } else if comp.first {
        // convert_arc_comp1: the entry arc ends on its end's radius, its centre moved to keep it an arc.
        if dist(pxy, cxy) <= r {
            return Err("Radius of cutter compensation entry arc is not greater than the tool radius".into());
        }
        if tool_inside && dist(cxy, centre) <= r {
            return too_small();
        }
        let gamma = if inside(side, turn) { atan2(centre, pxy) } else { atan2(pxy, centre) };
        let end = polar(pxy, r, gamma);
        let b_len = dist(cxy, end) / 2.0;
        let ab_ang = atan2(centre, end);
        let a_ang = atan2(cxy, end) - ab_ang;
        if a_ang.cos().abs() < 1e-6 {
            return Err("Tool radius not less than arc radius with comp".into());
        }
        let new_centre = polar(end, b_len / a_ang.cos(), ab_ang);
        st.queue.push(Held::Arc { block: arc_block(b, end, Some(p[2]), new_centre, turn), centre: new_centre, turn, original: find_turn(cxy, new_centre, turn, end) });
        new_end = end;
    } else {
        // convert_arc_comp2.
        let theta = atan2(cxy, opxy) + if side == Side::Left { -FRAC_PI_2 } else { FRAC_PI_2 };
        let mut delta = atan2(centre, opxy);
        let alpha = if ccw { delta - FRAC_PI_2 } else { delta + FRAC_PI_2 };
        let mut beta = if side == Side::Left { theta - alpha } else { alpha - theta };
        beta = if beta > 1.5 * PI { beta - TAU } else if beta < -FRAC_PI_2 { beta + TAU } else { beta };
        let gamma = if tool_inside {
            if arc_radius <= r {
                return too_small();
            }
            atan2(centre, pxy)
        } else {
            delta += PI;
            atan2(pxy, centre)
        };
        let end = polar(pxy, r, gamma);
        if !(-small..=PI + small).contains(&beta) || ((beta - PI).abs() < small && !inside(side, turn)) {
            match st.front_arc() {
                None => {
                    // Line to arc: where the offset line meets the offset arc.
                    let cy = arc_radius * (beta - FRAC_PI_2).sin();
                    let (dist_from_centre, l, angle);
                    if inside(side, turn) {
                        dist_from_centre = arc_radius - r;
                        l = (cy + r) / dist_from_centre;
                        if !(-1.0..=1.0).contains(&l) {
                            return Err("Arc move in concave corner cannot be reached by the tool without gouging".into());
                        }
                        angle = if turn > 0 { theta + l.asin() } else { theta - l.asin() };
                    } else {
                        dist_from_centre = arc_radius + r;
                        l = (cy - r) / dist_from_centre;
                        if !(-1.0..=1.0).contains(&l) {
                            return Err("Arc move in concave corner cannot be reached by the tool without gouging".into());
                        }
                        angle = if turn > 0 { theta + PI - l.asin() } else { theta + PI + l.asin() };
                    }
                    st.move_endpoint_and_flush(polar(centre, dist_from_centre, angle), metric, unit, out)?;
                }
                Some((prev_end, prev_centre, prev_turn)) => {
                    // Arc to arc: where the two offset circles meet.
                    let oldrad = dist(prev_end, prev_centre);
                    let newrad = if inside(side, turn) { arc_radius - r } else { arc_radius + r };
                    let arc_cc = dist(prev_centre, centre);
                    if oldrad == 0.0 || arc_cc == 0.0 {
                        return Err("Arc to arc motion is invalid because the arcs have the same center".into());
                    }
                    let a = (oldrad * oldrad + arc_cc * arc_cc - newrad * newrad) / (2.0 * oldrad * arc_cc);
                    if !(-1.0..=1.0).contains(&a) {
                        return Err("Arc to arc motion makes a corner the compensated tool can't fit in without gouging".into());
                    }
                    let pullback = a.acos();
                    let cc_dir = atan2(centre, prev_centre);
                    let dir = match (inside(side, prev_turn), turn > 0) {
                        (true, true) | (false, false) => cc_dir + pullback,
                        (true, false) | (false, true) => cc_dir - pullback,
                    };
                    st.move_endpoint_and_flush(polar(prev_centre, oldrad, dir), metric, unit, out)?;
                }
            }
        } else if beta > small {
            // A convex corner: an arc about the programmed corner first.
            let mid = polar(opxy, r, delta);
            st.dequeue(out);
            st.queue.push(Held::Other(arc_block(b, mid, Some(c[2]), opxy, if side == Side::Left { -1 } else { 1 })));
            st.corner_arcs += 1;
            st.dequeue(out);
            st.endpoint = Some(mid);
        } else {
            st.dequeue(out);
            st.endpoint = Some(cxy);
        }
        st.queue.push(Held::Arc { block: arc_block(b, end, Some(p[2]), centre, turn), centre, turn, original: find_turn(opxy, centre, turn, pxy) });
        new_end = end;
    }
    if let Some(on) = &mut st.on {
        on.first = false;
        on.current = [new_end[0], new_end[1], p[2]];
    }
    Ok(())
}
