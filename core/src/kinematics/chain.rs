//! The two-rotary kinematic chain: forward transform, closed-form orientation inverse, linear axes.

use super::{subproblem1, wrap_pi, Carrier, Joints, KinematicsError, RotaryJoint, SinCos, Turn};
use nalgebra::Vector3;

/// sin of the angle from the singular direction below which the secondary rate is undefined.
pub const POLE: f64 = 1e-12;

/// Tool pose in the workpiece frame: tool tip (m) and unit tool axis (pointing from tip to spindle).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    pub tip: Vector3<f64>,
    pub axis: Vector3<f64>,
}

/// The chain of a machine with two rotary axes, in the file's slot order (slot 0 = axis index 3); or
/// of a four-axis machine ([`TwoRotaryChain::four_axis`]), whose slot 1 is a locked joint that never
/// turns.
#[derive(Debug, Clone)]
pub struct TwoRotaryChain {
    joints: [RotaryJoint; 2],
    /// A four-axis machine: slot 1 is locked at 0 (coaxial with slot 0, so the tool keeps a fixed
    /// angle to it and nothing diverges); every orientation is slot 0's turn alone.
    locked: bool,
    tool_axis: Vector3<f64>,
    tool_tip: Vector3<f64>,
    /// Slot of r2 (fixed in the workpiece frame) and of r1.
    r2: usize,
    r1: usize,
    /// Slots of the table joints, base outwards, and of the head joints, ram outwards.
    table: Vec<usize>,
    head: Vec<usize>,
}

/// Both orientation solutions of seed 001 Table 1, as rotary angles `[slot0, slot1]` in (-pi, pi].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrientationSolutions {
    pub solutions: [[f64; 2]; 2],
    /// True when the tool axis is parallel to r2: r2's angle is undefined (set to 0 here).
    pub singular: bool,
}

fn sign(c: Carrier) -> f64 {
    match c {
        Carrier::Table => -1.0,
        Carrier::Head => 1.0,
    }
}

impl TwoRotaryChain {
    /// Build a chain; joints in file order (on each side, from the machine base outwards).
    pub fn new(joints: [RotaryJoint; 2], tool_axis: Vector3<f64>, tool_tip: Vector3<f64>) -> Result<Self, KinematicsError> {
        if joints[0].axis.cross(&joints[1].axis).norm() < 1e-9 {
            return Err(KinematicsError::ParallelAxes);
        }
        let table: Vec<usize> = (0..2).filter(|&i| joints[i].carrier == Carrier::Table).collect();
        let head: Vec<usize> = (0..2).filter(|&i| joints[i].carrier == Carrier::Head).collect();
        // r2 is the axis fixed relative to the workpiece: the innermost table axis, else the outer head axis.
        let r2 = match table.last() {
            Some(&i) => i,
            None => head[0],
        };
        Ok(TwoRotaryChain { joints, tool_axis, tool_tip, locked: false, r2, r1: 1 - r2, table, head })
    }

    /// The chain of a four-axis machine (three linear axes and `joint`): a second joint, locked at 0,
    /// fills slot 1 so that the five-axis transforms serve it unchanged. The locked joint lies on
    /// `joint`'s line: the tool's angle to it is fixed (the angle between the tool and the rotary
    /// axis), so such a machine has no singular orientation, and its secondary rate is 0.
    pub fn four_axis(joint: RotaryJoint, tool_axis: Vector3<f64>, tool_tip: Vector3<f64>) -> Result<Self, KinematicsError> {
        if joint.axis.cross(&tool_axis).norm() < 1e-9 {
            return Err(KinematicsError::ToolAlongRotary);
        }
        let locked = RotaryJoint { name: String::new(), ..joint.clone() };
        let side = vec![0, 1];
        let (table, head) = match joint.carrier {
            Carrier::Table => (side, Vec::new()),
            Carrier::Head => (Vec::new(), side),
        };
        Ok(TwoRotaryChain { joints: [joint, locked], tool_axis, tool_tip, locked: true, r2: 1, r1: 0, table, head })
    }

    /// True for a four-axis machine's chain: slot 1 is locked at 0 ([`Self::four_axis`]).
    pub fn is_four_axis(&self) -> bool {
        self.locked
    }

    /// The joints in slot order.
    pub fn joints(&self) -> &[RotaryJoint; 2] {
        &self.joints
    }

    /// Slots of the table joints, from the machine base outwards (the workpiece rides on the last).
    pub fn table_slots(&self) -> &[usize] {
        &self.table
    }

    /// Slots of the head joints, from the ram outwards (the tool rides on the last).
    pub fn head_slots(&self) -> &[usize] {
        &self.head
    }

    /// Tool axis O_M in the spindle frame at home (unit vector, tip to spindle).
    pub fn tool_axis(&self) -> Vector3<f64> {
        self.tool_axis
    }

    /// Tool tip at home relative to the linear-axis origin, m.
    pub fn tool_tip(&self) -> Vector3<f64> {
        self.tool_tip
    }

    /// Slot (0 or 1) of the secondary axis r2, whose direction is the singular direction.
    pub fn secondary_slot(&self) -> usize {
        self.r2
    }

    /// Singular tool direction in the workpiece frame (seed 001 §2.4: O_W parallel to r2).
    pub fn singular_direction(&self) -> Vector3<f64> {
        self.joints[self.r2].axis
    }

    /// Point `p` turned by the joints in `slots` (listed from the base outwards: the outer joint's
    /// turn applied last), `turn(slot, p)` turning it about one joint.
    fn turned(slots: &[usize], p: &Vector3<f64>, turn: impl Fn(usize, &Vector3<f64>) -> Vector3<f64>) -> Vector3<f64> {
        slots.iter().rev().fold(*p, |v, &i| turn(i, &v))
    }

    /// Each joint's turn for the rotary angles `rot` (one `sin_cos` per joint): computed once, it
    /// serves every `*_turns` evaluation at that pose.
    pub fn turns(rot: &[f64; 2]) -> [Turn; 2] {
        rot.map(f64::sin_cos)
    }

    /// A joint's turn as the rotation of its side: a table axis turns the workpiece, so it enters
    /// the orientation with `phi = -theta` (`sin` negated), a head axis with `phi = +theta`.
    fn phi(&self, slot: usize, (sin, cos): Turn) -> Turn {
        (sign(self.joints[slot].carrier) * sin, cos)
    }

    /// Workpiece point -> machine frame for the table turns (outer table axis applied last).
    fn table_to_machine(&self, turns: &[Turn; 2], p: &Vector3<f64>) -> Vector3<f64> {
        Self::turned(&self.table, p, |i, v| self.joints[i].turn_point(turns[i], v))
    }

    /// Machine point -> workpiece frame (inverse of `table_to_machine`: each turn undone, inner last).
    fn machine_to_table(&self, turns: &[Turn; 2], p: &Vector3<f64>) -> Vector3<f64> {
        let mut v = *p;
        for &i in self.table.iter() {
            let (sin, cos) = turns[i];
            v = self.joints[i].turn_point((-sin, cos), &v);
        }
        v
    }

    /// Spindle-frame point -> machine frame at zero linear axes (outer head axis applied last).
    fn head_to_machine(&self, turns: &[Turn; 2], p: &Vector3<f64>) -> Vector3<f64> {
        Self::turned(&self.head, p, |i, v| self.joints[i].turn_point(turns[i], v))
    }

    /// Tool axis in the workpiece frame for the joints' turns (seed 001 eq. 2 on the Hermle).
    pub fn orientation_of(&self, turns: &[Turn; 2]) -> Vector3<f64> {
        let (j1, j2) = (&self.joints[self.r1], &self.joints[self.r2]);
        let inner = j1.turn_vector(self.phi(self.r1, turns[self.r1]), &self.tool_axis);
        j2.turn_vector(self.phi(self.r2, turns[self.r2]), &inner)
    }

    /// Tool axis in the workpiece frame for rotary angles `rot` (seed 001 eq. 2 on the Hermle).
    pub fn orientation(&self, rot: &[f64; 2]) -> Vector3<f64> {
        self.orientation_of(&Self::turns(rot))
    }

    /// Time derivative of the tool axis for rotary angles `rot` moving at `rate` (rad/s).
    pub fn orientation_rate(&self, rot: &[f64; 2], rate: &[f64; 2]) -> Vector3<f64> {
        self.orientation_rate_of(&Self::turns(rot), rate)
    }

    /// [`orientation_rate`](Self::orientation_rate) given the joints' turns.
    pub fn orientation_rate_of(&self, turns: &[Turn; 2], rate: &[f64; 2]) -> Vector3<f64> {
        let (j1, j2) = (&self.joints[self.r1], &self.joints[self.r2]);
        let (s1, s2) = (sign(j1.carrier), sign(j2.carrier));
        let (t1, t2) = (self.phi(self.r1, turns[self.r1]), self.phi(self.r2, turns[self.r2]));
        let inner = j1.turn_vector(t1, &self.tool_axis);
        let o = j2.turn_vector(t2, &inner);
        let d_phi2 = j2.axis.cross(&o);
        let d_phi1 = j2.turn_vector(t2, &j1.axis.cross(&inner));
        d_phi1 * (s1 * rate[self.r1]) + d_phi2 * (s2 * rate[self.r2])
    }

    /// Seed 001 eq. (5), exact for any two-rotary chain: the rate of the secondary axis r2 (rad/s,
    /// machine sign) that the unit tool axis `axis` moving at `axis_rate` asks; `rot` (the rotary
    /// angles there, approximately) only picks the inverse's branch.
    ///
    /// With the tangents of seed 001 §2.4, `o_dot = phi1' (t1 x o) + phi2' (t2 x o)` where t2 = a2 and
    /// t1 = R2(phi2) a1, so `phi2' = (o_dot . t1) / ((t1 x t2) . o)`. t1 follows from `o` alone up to
    /// that branch (t1 . a2 = a1 . a2, t1 . o = a1 . o_M): t1 = alpha a2 + beta o + gamma w with
    /// w = a2 x o, which gives `phi2' = (o_dot . w) / |w|^2 + alpha (o_dot_perp . a2) / (gamma |w|^2)`.
    /// The first term is eq. (5) as printed (`dTheta_h/dt / sin A`); the second vanishes on machines
    /// whose primary axis is orthogonal to both a2 and the tool (the Hermle, alpha = 0) and corrects it on
    /// the others (a 45 deg nutating head). Undefined on the pole (|a2 x o| below [`POLE`]) and at the rim
    /// of a non-orthogonal machine's reachable cone (gamma = 0, where r1 folds back): 0 is returned there.
    pub fn secondary_rate(&self, axis: &Vector3<f64>, axis_rate: &Vector3<f64>, rot: &[f64; 2]) -> f64 {
        if self.locked {
            // A four-axis machine's locked joint never turns, whatever the path.
            return 0.0;
        }
        let (j1, j2) = (&self.joints[self.r1], &self.joints[self.r2]);
        let (a1, a2, o) = (j1.axis, j2.axis, *axis);
        let w = a2.cross(&o);
        let w2 = w.norm_squared();
        if w2 <= POLE * POLE {
            return 0.0;
        }
        // Eq. (5) as printed: the rate about a2 of the tool axis' component across it.
        let mut rate = axis_rate.dot(&w) / w2;
        let delta = a2.dot(&o);
        // alpha's numerator first: zero on the orthogonal machines, which then skip a division.
        let alpha_w2 = a1.dot(&a2) - delta * a1.dot(&self.tool_axis);
        if alpha_w2 != 0.0 {
            let alpha = alpha_w2 / w2;
            let beta = (a1.dot(&self.tool_axis) - delta * a1.dot(&a2)) / w2;
            let g2w = 1.0 - alpha * alpha - beta * beta - 2.0 * alpha * beta * delta; // gamma^2 |w|^2
            if g2w <= POLE * POLE {
                return 0.0;
            }
            // The branch: the sign of t1 . w for the primary axis' direction at these angles.
            let t1 = j2.turn_vector(self.phi(self.r2, rot[self.r2].sin_cos()), &a1);
            let gamma = g2w.sqrt() / w2.sqrt() * if t1.dot(&w) < 0.0 { -1.0 } else { 1.0 };
            let rate_perp_a2 = axis_rate.dot(&a2) - axis_rate.dot(&o) * delta;
            rate += alpha * rate_perp_a2 / (gamma * w2);
        }
        sign(j2.carrier) * rate
    }

    /// Forward kinematics: axis values -> tool tip and tool axis in the workpiece frame.
    pub fn forward(&self, q: &Joints) -> Pose {
        self.forward_turns(q, &Self::turns(&[q[3], q[4]]))
    }

    /// [`forward`](Self::forward) given the turns of the joints at `q`'s rotary angles.
    pub fn forward_turns(&self, q: &Joints, turns: &[Turn; 2]) -> Pose {
        let linear = Vector3::new(q[0], q[1], q[2]);
        let tip_m = linear + self.head_to_machine(turns, &self.tool_tip);
        Pose { tip: self.machine_to_table(turns, &tip_m), axis: self.orientation_of(turns) }
    }

    /// Linear axis values that put the tool tip at workpiece point `tip` with rotary angles `rot`.
    pub fn linear_for(&self, tip: &Vector3<f64>, rot: &[f64; 2]) -> Vector3<f64> {
        self.linear_for_turns(tip, &Self::turns(rot))
    }

    /// [`linear_for`](Self::linear_for) given the joints' turns.
    #[inline]
    pub fn linear_for_turns(&self, tip: &Vector3<f64>, turns: &[Turn; 2]) -> Vector3<f64> {
        self.table_to_machine(turns, tip) - self.head_to_machine(turns, &self.tool_tip)
    }

    /// [`linear_for`](Self::linear_for) along a sequence of nearby angles: each joint's sine and
    /// cosine from `turns` (one per slot), which follows the sequence.
    #[inline]
    pub fn linear_for_along(&self, tip: &Vector3<f64>, rot: &[f64; 2], turns: &mut [SinCos; 2]) -> Vector3<f64> {
        self.linear_for_turns(tip, &std::array::from_fn(|i| turns[i].at(rot[i])))
    }

    /// The spindle's frame in the workpiece at rotary angles `rot`: the rotation that takes a
    /// direction fixed to the spindle (given in the machine frame at home) to the workpiece frame,
    /// head turns applied, table turns undone. Its third column is the tool axis when the tool is
    /// along Z; its first, the machine's X as the tilted tool sees it.
    pub fn tool_frame(&self, rot: &[f64; 2]) -> nalgebra::Matrix3<f64> {
        let turns = Self::turns(rot);
        let dir = |v: Vector3<f64>| {
            let m = self.head_to_machine(&turns, &v) - self.head_to_machine(&turns, &Vector3::zeros());
            self.machine_to_table(&turns, &m) - self.machine_to_table(&turns, &Vector3::zeros())
        };
        nalgebra::Matrix3::from_columns(&[dir(Vector3::x()), dir(Vector3::y()), dir(Vector3::z())])
    }

    /// Both rotary solutions for a tool axis (need not be unit; must be finite and non-zero).
    /// When the axis is parallel to r2 (the singularity), r2's angle is undefined: it is returned as 0
    /// and `singular` is set, so the caller can keep the previous value.
    pub fn orientation_solutions(&self, axis: &Vector3<f64>) -> Result<OrientationSolutions, KinematicsError> {
        if !axis.iter().all(|v| v.is_finite()) {
            return Err(KinematicsError::NotFinite);
        }
        let n = axis.norm();
        if n < 1e-12 {
            return Err(KinematicsError::ZeroToolAxis);
        }
        let q = axis / n;
        if self.locked {
            return self.four_axis_solution(&q);
        }
        let (j1, j2) = (&self.joints[self.r1], &self.joints[self.r2]);
        let (a1, a2, o) = (j1.axis, j2.axis, self.tool_axis);
        // Subproblem 2: c with a1.c = a1.o, a2.c = a2.q, |c| = 1; then R(a1,phi1) o = c, R(a2,phi2) c = q.
        let d = a1.dot(&a2);
        let w = a1.cross(&a2);
        let w2 = w.norm_squared();
        let (al1, al2) = (a1.dot(&o), a2.dot(&q));
        let alpha = (al1 - d * al2) / w2;
        let beta = (al2 - d * al1) / w2;
        let mut g2 = (1.0 - alpha * alpha - beta * beta - 2.0 * alpha * beta * d) / w2;
        if g2 < -1e-9 {
            return Err(KinematicsError::Unreachable);
        }
        g2 = g2.max(0.0);
        let gamma = g2.sqrt();
        let singular = a2.cross(&q).norm() < 1e-12;
        let mut out = [[0.0; 2]; 2];
        for (k, gs) in [gamma, -gamma].into_iter().enumerate() {
            let c = a1 * alpha + a2 * beta + w * gs;
            let phi1 = subproblem1(&a1, &o, &c).unwrap_or(0.0);
            let phi2 = if singular { 0.0 } else { subproblem1(&a2, &c, &q).unwrap_or(0.0) };
            out[k][self.r1] = wrap_pi(sign(j1.carrier) * phi1);
            out[k][self.r2] = wrap_pi(sign(j2.carrier) * phi2);
        }
        Ok(OrientationSolutions { solutions: out, singular })
    }

    /// A four-axis machine's one solution for the unit tool axis `q` (both entries alike): the turn
    /// of the free joint that takes the tool onto `q` (Paden-Kahan subproblem 1), the locked one at 0.
    /// The tool reaches only the cone about the joint's axis on which it lies: elsewhere, unreachable.
    fn four_axis_solution(&self, q: &Vector3<f64>) -> Result<OrientationSolutions, KinematicsError> {
        let j = &self.joints[0];
        let (a, o) = (j.axis, self.tool_axis);
        // The same angle to the axis: within 1e-9 rad of the cone (as the two-rotary solution's g2 >= -1e-9).
        if (a.dot(&o) - a.dot(q)).abs() > 1e-9 {
            return Err(KinematicsError::Unreachable);
        }
        // Off the axis (four_axis refuses a tool along it), so the angle is defined.
        let phi = subproblem1(&a, &o, q).ok_or(KinematicsError::Unreachable)?;
        let sol = [wrap_pi(sign(j.carrier) * phi), 0.0];
        Ok(OrientationSolutions { solutions: [sol, sol], singular: false })
    }
}
