//! Tilted working planes (3+2): the working plane's frame from the angles a program gives, and the
//! rotary axis positions a control picks to put the tool along its Z.
//!
//! Conventions, from the controls' manuals:
//! - Heidenhain `PLANE SPATIAL SPA SPB SPC` (and cycle 19 with spatial angles): "rotations about the
//!   fixed machine coordinate system ... first around the A axis, then B, and then C" (iTNC 530
//!   User's Manual 340 422 §9.2), so `R = Rz(SPC) Ry(SPB) Rx(SPA)`.
//! - Heidenhain `PLANE EULER EULPR EULNU EULROT` and Fanuc `G68.2 I J K`: Z, then the new X, then the
//!   new Z (TNC 620 ISO 5/2013 p.322; FANUC B-63942EN §5.44): `R = Rz(I) Rx(J) Rz(K)`.
//! - Heidenhain `PLANE VECTOR BX BY BZ NX NY NZ`: the normal is the plane's Z, the base vector its X
//!   (TNC 620 10/2017 p.548; both normalised, the base made square to the normal).
//! The columns of `R` are the plane's X, Y and Z in the untilted workpiece frame; a point written
//! in the plane is `R p` there.
//!
//! The axis solution (iTNC 530 ISO 6/2010 §12.2, the worked example for an A/C table with
//! `PLANE SPATIAL SPA+0 SPB+45 SPC+0`): `SEQ+` / `SEQ-` fix the sign of the master (primary) axis,
//! and a solution they pick outside the limits is an error; without `SEQ` the solution within the
//! limits nearest the axes' positions, the positive one on a tie. At the pole (the tool along the
//! secondary axis) that axis is free: `COORD ROT` leaves it where it stands and rotates the
//! coordinates only, `TABLE ROT` turns it so that the plane's X is the machine's X (iTNC 530 ISO
//! 6/2010 §12.2 "Selecting the type of transformation"; TNC7 81762x-17: COORD ROT and TABLE ROT act
//! through "the axis position of a free rotary axis"). Where the program does not say, the result
//! depends on the control's setting: a finding the caller reports.

use crate::kinematics::unwrap_near;
use crate::machine::{AxisLimits, Machine};
use nalgebra::{Matrix3, Rotation3, Vector3};

/// `Rz(c) Ry(b) Rx(a)`, angles in radians: Heidenhain's spatial angles.
pub fn spatial(a: f64, b: f64, c: f64) -> Matrix3<f64> {
    let r = |axis: Vector3<f64>, t: f64| *Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), t).matrix();
    r(Vector3::z(), c) * r(Vector3::y(), b) * r(Vector3::x(), a)
}

/// `Rz(p) Rx(n) Rz(r)`, radians: Euler angles Z, X', Z'' (Heidenhain PLANE EULER, Fanuc G68.2).
pub fn euler_zxz(p: f64, n: f64, r: f64) -> Matrix3<f64> {
    let rot = |axis: Vector3<f64>, t: f64| *Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), t).matrix();
    rot(Vector3::z(), p) * rot(Vector3::x(), n) * rot(Vector3::z(), r)
}

/// The frame whose Z is `normal` and whose X is `base` made square to it (both normalised).
pub fn from_vectors(base: Vector3<f64>, normal: Vector3<f64>) -> Result<Matrix3<f64>, String> {
    let z = normal.try_normalize(1e-9).ok_or("the normal vector has no length")?;
    let x = (base - z * z.dot(&base)).try_normalize(1e-9).ok_or("the base vector is parallel to the normal")?;
    Ok(Matrix3::from_columns(&[x, z.cross(&x), z]))
}

/// The frame of `PLANE POINTS` (iTNC 530 User's Manual ISO programming 340 49x-03 §9.6, p.476; TNC 640
/// 34059x-05 p.424): "The connection from Point 1 to Point 2 determines the direction of the tilted
/// principal axis" (X); by the right-hand rule, "thumb (X axis) points from Point 1 to Point 2, index
/// finger (Y axis) points parallel to the tilted Y axis in the direction of Point 3. Then the middle
/// finger points in the direction of the tilted tool axis" (Z). Only the points' differences count:
/// the plane's orientation, not its place.
pub fn from_points(p1: Vector3<f64>, p2: Vector3<f64>, p3: Vector3<f64>) -> Result<Matrix3<f64>, String> {
    let x = p2 - p1;
    if x.norm() < 1e-9 {
        return Err("points 1 and 2 coincide: they give no direction for the tilted X axis".into());
    }
    let z = x.cross(&(p3 - p1));
    if z.norm() < 1e-9 * x.norm() * (p3 - p1).norm().max(1e-9) {
        return Err("the three points lie on one line: they give no plane".into());
    }
    from_vectors(x, z)
}

/// What the program says of the solution: `SEQ+`/`SEQ-` (the master axis' sign) and what a free
/// axis does at the pole (`TABLE ROT` true, `COORD ROT` false; `None`: not said).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Choice {
    pub seq: Option<bool>,
    pub table_rot: Option<bool>,
}

/// The pole: the tool along the secondary axis, which is then free.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pole {
    /// The free axis' index among the machine's axes (3 or 4).
    pub free_axis: usize,
    /// Its position under COORD ROT (it stays) and under TABLE ROT (turned so the plane's X is the
    /// machine's; `None` where turning it cannot do that, a head axis), rad.
    pub coord_rot: f64,
    pub table_rot: Option<f64>,
}

/// The rotary positions a control picks for a plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Solution {
    /// The two rotary axes, in the machine's order (its axes 3 and 4), rad.
    pub rot: [f64; 2],
    /// Set when the plane is at the pole.
    pub pole: Option<Pole>,
}

/// A place for `target` (rad, in (-pi, pi]) within `limits`: a multi-turn axis takes it as it is
/// (the control shows such an axis modulo 360 deg, and the manual's solutions read so: from C-135,
/// SEQ+ gives C+90, not C-270); a limited one the turn within its range nearest `current`.
fn place(target: f64, current: f64, limits: &AxisLimits) -> Option<f64> {
    if limits.is_unlimited() {
        return Some(target);
    }
    let tau = std::f64::consts::TAU;
    let near = unwrap_near(target, current);
    [near, near - tau, near + tau].into_iter().filter(|v| limits.contains(*v)).min_by(|a, b| (a - current).abs().total_cmp(&(b - current).abs()))
}

/// The rotary positions that put the tool along `r`'s Z on `machine`, its axes standing at
/// `current` (rad, machine order), as `choice` says; an error says why none can.
pub fn solve(machine: &Machine, r: &Matrix3<f64>, current: [f64; 2], choice: Choice) -> Result<Solution, String> {
    let n: Vector3<f64> = r.column(2).into();
    let sol = machine.chain.orientation_solutions(&n).map_err(|e| format!("the machine cannot point the tool along the plane's normal: {e}"))?;
    let sec = machine.chain.secondary_slot();
    let pri = 1 - sec;
    let limits = [machine.axes[3].limits, machine.axes[4].limits];
    let names = [machine.axes[3].name.as_str(), machine.axes[4].name.as_str()];
    let pole = sol.singular.then(|| {
        // The free axis: under COORD ROT where it stands; under TABLE ROT turned so that the
        // spindle frame's X (the machine's X) lies along the plane's X.
        let mut at = [0.0; 2];
        at[pri] = sol.solutions[0][pri];
        let angle = |theta: f64| {
            let mut rot = at;
            rot[sec] = theta;
            let x = machine.chain.tool_frame(&rot).column(0).into_owned();
            x.dot(&r.column(1)).atan2(x.dot(&r.column(0)))
        };
        let c0 = current[sec];
        let (a0, a1) = (angle(c0), angle(c0 + 1e-3));
        let slope = crate::kinematics::wrap_pi(a1 - a0) / 1e-3;
        let table = (slope.abs() > 0.5).then(|| {
            let mut theta = c0 - a0 / slope;
            for _ in 0..4 {
                theta -= crate::kinematics::wrap_pi(angle(theta)) / slope;
            }
            theta
        });
        Pole { free_axis: 3 + sec, coord_rot: c0, table_rot: table }
    });
    // Each raw solution placed within the limits nearest where the axes stand.
    let mut candidates: Vec<[f64; 2]> = Vec::new();
    let mut outside: Vec<String> = Vec::new();
    for raw in sol.solutions {
        let mut target = raw;
        if let Some(p) = &pole {
            target[sec] = match (choice.table_rot, p.table_rot) {
                (Some(true), Some(t)) => t,
                _ => p.coord_rot,
            };
        }
        let placed: Vec<Option<f64>> = (0..2).map(|k| place(target[k], current[k], &limits[k])).collect();
        match (placed[0], placed[1]) {
            (Some(a), Some(b)) => candidates.push([a, b]),
            _ => {
                let k = if placed[0].is_none() { 0 } else { 1 };
                outside.push(format!("{} {:.3} deg", names[k], unwrap_near(target[k], current[k]).to_degrees()));
            }
        }
    }
    candidates.dedup_by(|a, b| (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12);
    let positive = |c: &[f64; 2]| c[pri] >= -1e-12;
    let pick = match choice.seq {
        Some(plus) => {
            // The master axis' sign as SEQ says: both raw solutions, within the limits or not.
            let wanted: Vec<&[f64; 2]> = candidates.iter().filter(|c| positive(c) == plus || c[pri].abs() < 1e-12).collect();
            match wanted.first() {
                Some(c) => **c,
                None => {
                    return Err(format!(
                        "SEQ{}: the solution with {} {} lies outside the axes' limits{}",
                        if plus { '+' } else { '-' },
                        names[pri],
                        if plus { "positive" } else { "negative" },
                        if outside.is_empty() { String::new() } else { format!(" ({})", outside.join(", ")) }
                    ))
                }
            }
        }
        None => {
            // Distances from where the axes stand, a multi-turn one as shown (modulo 360 deg).
            let shown: [f64; 2] = std::array::from_fn(|k| if limits[k].is_unlimited() { crate::kinematics::wrap_pi(current[k]) } else { current[k] });
            let cost = |c: &[f64; 2]| (c[0] - shown[0]).abs() + (c[1] - shown[1]).abs();
            let best = candidates.iter().copied().min_by(|a, b| {
                let (ca, cb) = (cost(a), cost(b));
                if (ca - cb).abs() < 1e-9 {
                    // A tie goes to the positive master axis (the manual's table, from A0 C0).
                    positive(b).cmp(&positive(a))
                } else {
                    ca.total_cmp(&cb)
                }
            });
            match best {
                Some(c) => c,
                None => return Err(format!("no solution within the axes' limits ({})", outside.join(", "))),
            }
        }
    };
    Ok(Solution { rot: pick, pole })
}

/// The rotary positions a Fanuc control outputs for `G53.1` (tool axis direction control): of the
/// computed angles (each solution, turned by any multiple of 360 deg) within both axes' ranges, the
/// pair whose master axis moves least; on a tie the slave's move, then the master's angle nearest 0
/// deg (modulo 360), then the slave's (FANUC 16i/18i-MB Operator's Manual B-63534EN, "Angle of
/// rotation axis": the "output judgement conditions"; 30i B-63944EN/02 §21, p.677: on a mixed
/// machine the table axis is judged first). The master is the axis nearer the machine's base, the
/// one carrying the other, on a mixed machine the table's (parameter PRI, No. 19608#5, at 0). At the
/// pole the free axis stays where it stands (B-63944EN/02 p.680: "the master axis does not move from
/// the current angle").
pub fn solve_fanuc(machine: &Machine, r: &Matrix3<f64>, current: [f64; 2]) -> Result<Solution, String> {
    let n: Vector3<f64> = r.column(2).into();
    let sol = machine.chain.orientation_solutions(&n).map_err(|e| format!("the machine cannot point the tool along the plane's Z: {e}"))?;
    let sec = machine.chain.secondary_slot();
    let master = machine.chain.table_slots().first().or(machine.chain.head_slots().first()).copied().unwrap_or(0);
    let slave = 1 - master;
    let limits = [machine.axes[3].limits, machine.axes[4].limits];
    let names = [machine.axes[3].name.as_str(), machine.axes[4].name.as_str()];
    let pole = sol.singular.then_some(Pole { free_axis: 3 + sec, coord_rot: current[sec], table_rot: None });
    let tau = std::f64::consts::TAU;
    // The judgement's measures, in order: what the master moves, what the slave moves, how far each
    // lies from 0 deg.
    let key = |c: &[f64; 2]| [(c[master] - current[master]).abs(), (c[slave] - current[slave]).abs(), crate::kinematics::wrap_pi(c[master]).abs(), crate::kinematics::wrap_pi(c[slave]).abs()];
    let better = |a: &[f64; 2], b: &[f64; 2]| {
        for (x, y) in key(a).iter().zip(key(b)) {
            if (x - y).abs() > 1e-9 {
                return x < &y;
            }
        }
        false
    };
    let mut best: Option<[f64; 2]> = None;
    let mut outside: Vec<String> = Vec::new();
    for raw in sol.solutions {
        let mut target = raw;
        if pole.is_some() {
            target[sec] = current[sec];
        }
        let images: [Vec<f64>; 2] = std::array::from_fn(|k| {
            let near = unwrap_near(target[k], current[k]);
            [near, near - tau, near + tau].into_iter().filter(|v| limits[k].contains(*v)).collect()
        });
        if let Some(k) = (0..2).find(|&k| images[k].is_empty()) {
            outside.push(format!("{} {:.3} deg", names[k], unwrap_near(target[k], current[k]).to_degrees()));
        }
        for &a in &images[0] {
            for &b in &images[1] {
                if best.as_ref().is_none_or(|c| better(&[a, b], c)) {
                    best = Some([a, b]);
                }
            }
        }
    }
    match best {
        Some(rot) => Ok(Solution { rot, pole }),
        None => Err(format!("no solution within the axes' limits ({})", outside.join(", "))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    const D: f64 = std::f64::consts::PI / 180.0;

    /// The spatial angles' product is A, then B, then C about the fixed axes, which is C, then B
    /// about the new Y, then A about the new X (TNC 620 10/2017 p.540: "the result is identical").
    #[test]
    fn spatial_angles_are_fixed_axes_a_b_c() {
        let (a, b, c) = (20.0 * D, -35.0 * D, 70.0 * D);
        let fixed = spatial(a, b, c);
        let rz = spatial(0.0, 0.0, c);
        let ry_new = Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(rz * Vector3::y()), b);
        let after_b = *ry_new.matrix() * rz;
        let rx_new = Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(after_b * Vector3::x()), a);
        assert!((*rx_new.matrix() * after_b - fixed).norm() < 1e-12);
        // Euler Z X Z and the vector form.
        let e = euler_zxz(90.0 * D, 45.0 * D, -90.0 * D);
        assert!((e - spatial(0.0, 45.0 * D, 0.0)).norm() < 1e-12, "G68.2 I90 J45 K-90 is 45 deg about Y");
        let v = from_vectors(Vector3::new(1.0, 0.0, 0.3), Vector3::new(0.0, 0.0, 2.0)).unwrap();
        assert!((v - Matrix3::identity()).norm() < 1e-12);
        assert!(from_vectors(Vector3::z(), Vector3::z()).is_err());
    }

    /// `PLANE POINTS` by the manual's right-hand rule: points 1 and 2 along X, point 3 on the plane's
    /// +Y side, which gives the frame of the spatial angles of the same plane (a turn about X, about
    /// Y, and both with one about Z; worked out here from the angles, not from the points); point 3
    /// below the line turns the tool axis over (TNC 620 10/2017 p.549: "to have the positive tool
    /// axis pointing away from the workpiece, Point 3 must be located above the connection line");
    /// only the points' differences count; points on a line or coinciding are no plane.
    #[test]
    fn three_points_give_the_frame_of_the_right_hand_rule() {
        let (s30, c30) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
        let p1 = Vector3::new(10.0, -5.0, 20.0);
        let about_x = from_points(p1, p1 + Vector3::new(40.0, 0.0, 0.0), p1 + Vector3::new(7.0, 10.0 * c30, 10.0 * s30)).unwrap();
        assert!((about_x - spatial(30.0 * D, 0.0, 0.0)).norm() < 1e-12, "{about_x}");
        let about_y = from_points(p1, p1 + Vector3::new(c30, 0.0, -s30), p1 + Vector3::new(0.0, 3.0, 0.0)).unwrap();
        assert!((about_y - spatial(0.0, 30.0 * D, 0.0)).norm() < 1e-12, "{about_y}");
        let r = spatial(20.0 * D, -35.0 * D, 70.0 * D);
        let (x, y) = (r.column(0).into_owned(), r.column(1).into_owned());
        let general = from_points(p1, p1 + 25.0 * x, p1 + 12.0 * y - 4.0 * x).unwrap();
        assert!((general - r).norm() < 1e-12, "{general}");
        let below = from_points(p1, p1 + 25.0 * x, p1 - 12.0 * y).unwrap();
        assert!((below.column(2) + r.column(2)).norm() < 1e-12 && (below.column(0) - r.column(0)).norm() < 1e-12);
        assert!(from_points(p1, p1, p1 + y).is_err());
        assert!(from_points(p1, p1 + x, p1 + 3.0 * x).is_err());
    }

    /// The iTNC 530's worked example (User's Manual DIN/ISO 6/2010 §12.2, "machine with a rotary
    /// table C and a tilting table A", `PLANE SPATIAL SPA+0 SPB+45 SPC+0`) on the Hermle C600U, every
    /// row of its table: start position, limit, SEQ and the axes the control picks (to 0.001 deg).
    #[test]
    fn the_manuals_seq_table_on_an_a_c_table() {
        let hermle = Machine::hermle_c600u();
        let mut limited = hermle.clone();
        limited.axes[3].limits.min = -90.0 * D;
        limited.axes[3].limits.max = 10.0 * D;
        let r = spatial(0.0, 45.0 * D, 0.0);
        let rows: [(&Machine, [f64; 2], Option<bool>, Option<[f64; 2]>); 8] = [
            (&hermle, [0.0, 0.0], None, Some([45.0, 90.0])),
            (&hermle, [0.0, 0.0], Some(true), Some([45.0, 90.0])),
            (&hermle, [0.0, 0.0], Some(false), Some([-45.0, -90.0])),
            (&hermle, [0.0, -105.0], None, Some([-45.0, -90.0])),
            (&hermle, [0.0, -105.0], Some(true), Some([45.0, 90.0])),
            (&hermle, [0.0, -105.0], Some(false), Some([-45.0, -90.0])),
            (&limited, [0.0, 0.0], None, Some([-45.0, -90.0])),
            (&limited, [0.0, 0.0], Some(true), None),
        ];
        for (m, start, seq, want) in rows {
            let got = solve(m, &r, start.map(|v| v * D), Choice { seq, table_rot: None });
            match (got, want) {
                (Ok(s), Some(w)) => assert!((0..2).all(|k| (s.rot[k] / D - w[k]).abs() < 1e-3), "{start:?} {seq:?}: {:?} deg, manual {w:?}", s.rot.map(|v| v / D)),
                (Err(e), None) => assert!(e.contains("SEQ+"), "{e}"),
                (got, want) => panic!("{start:?} {seq:?}: {got:?}, manual {want:?}"),
            }
        }
        let s = solve(&hermle, &r, [0.0, -135.0 * D], Choice { seq: Some(true), table_rot: None }).unwrap();
        assert!((s.rot[0] / D - 45.0).abs() < 1e-3 && (s.rot[1] / D - 90.0).abs() < 1e-3, "from C-135 SEQ+: {:?}", s.rot.map(|v| v / D));
        // The pole: C free; COORD ROT keeps it, TABLE ROT turns the plane's X onto the machine's.
        let pole = solve(&hermle, &spatial(0.0, 0.0, 30.0 * D), [0.0, 10.0 * D], Choice { seq: None, table_rot: Some(true) }).unwrap();
        let p = pole.pole.expect("at the pole");
        assert!((p.coord_rot / D - 10.0).abs() < 1e-9 && (pole.rot[0]).abs() < 1e-9);
        let x = hermle.chain.tool_frame(&pole.rot).column(0).into_owned();
        assert!((x - spatial(0.0, 0.0, 30.0 * D).column(0)).norm() < 1e-9, "TABLE ROT: the plane's X is the machine's X");
    }

    /// FANUC's worked examples of G53.1's output angles (30i User's Manual B-63944EN/02 §21, p.680;
    /// 15i-B Connection Manual B-63783EN-1/01 p.1257), "BC type tool axis Z" (a C head carrying the B
    /// head, `generic-bc-head`, its ranges widened to a turn each way as the example's B270 needs):
    /// from B180 C90 the candidates B90 C180 and B270 C0 (the tool along -X) tie on both axes' moves,
    /// and the master C nearer 0 deg decides: B270 C0. From B45 C90, the tool along Z (B0): C, free,
    /// "does not move from the current angle": B0 C90.
    #[test]
    fn fanucs_output_angle_examples_on_a_bc_head() {
        let mut m = Machine::builtin("generic-bc-head").unwrap();
        for k in [3, 4] {
            (m.axes[k].limits.min, m.axes[k].limits.max) = (-360.0 * D, 360.0 * D);
        }
        let (c, b) = (m.axes.iter().position(|a| a.name == "C").unwrap() - 3, m.axes.iter().position(|a| a.name == "B").unwrap() - 3);
        let at = |bv: f64, cv: f64| {
            let mut q = [0.0; 2];
            (q[b], q[c]) = (bv * D, cv * D);
            q
        };
        let minus_x = Matrix3::from_columns(&[Vector3::y(), Vector3::z(), -Vector3::x()]);
        let s = solve_fanuc(&m, &minus_x, at(180.0, 90.0)).unwrap();
        assert!((s.rot[b] / D - 270.0).abs() < 1e-3 && (s.rot[c] / D).abs() < 1e-3, "manual B270 C0, got B{} C{}", s.rot[b] / D, s.rot[c] / D);
        assert!(s.pole.is_none());
        // Both candidates point the tool along -X (the example's direction, as its two pairs say).
        for q in [at(90.0, 180.0), at(270.0, 0.0)] {
            assert!((m.chain.tool_frame(&q).column(2) + Vector3::x()).norm() < 1e-12);
        }
        let s = solve_fanuc(&m, &Matrix3::identity(), at(45.0, 90.0)).unwrap();
        assert!((s.rot[b] / D).abs() < 1e-3 && (s.rot[c] / D - 90.0).abs() < 1e-3, "manual B0 C90, got B{} C{}", s.rot[b] / D, s.rot[c] / D);
        assert_eq!(s.pole.map(|p| p.free_axis), Some(3 + c));
        // From B100 C90 the two tie on C's move (90 deg each way), and B's smaller move decides.
        let own = Machine::builtin("generic-bc-head").unwrap();
        let s = solve_fanuc(&own, &minus_x, at(100.0, 90.0)).unwrap();
        assert!((s.rot[b] / D - 90.0).abs() < 1e-3 && (s.rot[c] / D - 180.0).abs() < 1e-3, "B{} C{}", s.rot[b] / D, s.rot[c] / D);
    }
}
