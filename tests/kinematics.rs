//! Kinematics against the papers' equations, written out here independently of the library.

use fiveaxis::kinematics::{KinematicsError, Pose};
use fiveaxis::machine::Machine;
use fiveaxis::units::{DEG, MM};
use nalgebra::{Matrix3, Vector3};
use proptest::prelude::*;

/// Seed 001 eq. (1), the matrices exactly as printed.
fn rz_paper(c: f64) -> Matrix3<f64> {
    Matrix3::new(c.cos(), c.sin(), 0.0, -c.sin(), c.cos(), 0.0, 0.0, 0.0, 1.0)
}
fn rx_paper(a: f64) -> Matrix3<f64> {
    Matrix3::new(1.0, 0.0, 0.0, 0.0, a.cos(), a.sin(), 0.0, -a.sin(), a.cos())
}

fn close(a: &Vector3<f64>, b: &Vector3<f64>, tol: f64) -> bool {
    (a - b).norm() <= tol
}

proptest! {
    /// Hermle: P_W = R_z(C) R_x(A) P_M (eq. 1) and O_W = (sinC sinA, cosC sinA, cosA) (eq. 2).
    #[test]
    fn hermle_forward_is_eq_1_and_2(a in -110.0f64..110.0, c in -720.0f64..720.0,
                                    x in -300.0f64..300.0, y in -225.0f64..225.0, z in -100.0f64..350.0) {
        let m = Machine::hermle_c600u();
        let (a, c) = (a * DEG, c * DEG);
        let pm = Vector3::new(x, y, z) * MM;
        let pose = m.forward(&[pm.x, pm.y, pm.z, a, c]);
        let pw = rz_paper(c) * rx_paper(a) * pm;
        prop_assert!(close(&pose.tip, &pw, 1e-12), "tip {:?} vs eq. 1 {:?}", pose.tip, pw);
        let ow = Vector3::new(c.sin() * a.sin(), c.cos() * a.sin(), a.cos());
        prop_assert!(close(&pose.axis, &ow, 1e-12));
    }

    /// Mikron UCP 710: i = sinC sinA, j = -cosC sinA, k = cosA (seed 002 eq. 1).
    #[test]
    fn mikron_orientation_is_seed002_eq_1(a in -100.0f64..120.0, c in -360.0f64..360.0) {
        let m = Machine::builtin("mikron-ucp710").unwrap();
        let (a, c) = (a * DEG, c * DEG);
        let pose = m.forward(&[0.0, 0.0, 0.0, a, c]);
        let want = Vector3::new(c.sin() * a.sin(), -c.cos() * a.sin(), a.cos());
        prop_assert!(close(&pose.axis, &want, 1e-12));
    }

    /// FK(IK(p)) = p to 1e-9 over random reachable poses, on every built-in machine and on a
    /// head-head and a table-head machine from TOML files with offset axes.
    #[test]
    fn round_trip_fk_ik(machine in 0usize..5, u in proptest::array::uniform5(0.0f64..1.0),
                        jitter in proptest::array::uniform2(-0.2f64..0.2)) {
        let m = machines()[machine].clone();
        let q: [f64; 5] = std::array::from_fn(|i| {
            let l = m.axes[i].limits;
            let (lo, hi) = if l.is_unlimited() { (-3.0 * std::f64::consts::PI, 3.0 * std::f64::consts::PI) } else { (l.min, l.max) };
            // Keep linear axes well inside their travel so that the other IK branch stays in range too.
            let (lo, hi) = if i < 3 { (lo * 0.3, hi * 0.3) } else { (lo, hi) };
            lo + (hi - lo) * u[i]
        });
        let pose = m.forward(&q);
        let prev = [q[0], q[1], q[2], q[3] + jitter[0], q[4] + jitter[1]];
        match m.inverse(&pose, &prev) {
            Ok(sol) => {
                let back = m.forward(&sol);
                prop_assert!(close(&back.tip, &pose.tip, 1e-9), "tip {:?} -> {:?}", pose.tip, back.tip);
                prop_assert!(close(&back.axis, &pose.axis, 1e-9), "axis {:?} -> {:?}", pose.axis, back.axis);
                // Away from the singularity the nearest solution is the original axis values.
                let sd = m.singular_direction();
                if pose.axis.cross(&sd).norm() > 1e-3 {
                    for i in 3..5 {
                        prop_assert!((sol[i] - q[i]).abs() < 1e-7, "axis {} {} -> {}", i, q[i], sol[i]);
                    }
                }
            }
            Err(KinematicsError::OutOfRange { .. }) => {} // the pose's linear axes may leave the travel
            Err(e) => prop_assert!(false, "unexpected {e}"),
        }
    }
}

fn machines() -> Vec<Machine> {
    let head_head = r#"
name = "test-head-head"
tool_tip_mm = [0.0, 0.0, -150.0]
[[linear]]
name = "X"
min_mm = -1000.0
max_mm = 1000.0
velocity_mm_per_min = 30000.0
acceleration_mm_per_s2 = 3000.0
jerk_mm_per_s3 = 30000.0
[[linear]]
name = "Y"
min_mm = -1000.0
max_mm = 1000.0
velocity_mm_per_min = 30000.0
acceleration_mm_per_s2 = 3000.0
jerk_mm_per_s3 = 30000.0
[[linear]]
name = "Z"
min_mm = -1000.0
max_mm = 1000.0
velocity_mm_per_min = 30000.0
acceleration_mm_per_s2 = 3000.0
jerk_mm_per_s3 = 30000.0
[[rotary]]
name = "C"
carrier = "head"
axis = [0.0, 0.0, 1.0]
center_mm = [10.0, 0.0, 0.0]
velocity_deg_per_s = 90.0
acceleration_deg_per_s2 = 400.0
jerk_deg_per_s3 = 4000.0
[[rotary]]
name = "A"
carrier = "head"
axis = [1.0, 0.0, 0.0]
center_mm = [10.0, 5.0, -20.0]
min_deg = -100.0
max_deg = 100.0
velocity_deg_per_s = 90.0
acceleration_deg_per_s2 = 400.0
jerk_deg_per_s3 = 4000.0
"#;
    let table_head = head_head
        .replace("test-head-head", "test-table-head")
        .replacen("carrier = \"head\"\naxis = [0.0, 0.0, 1.0]", "carrier = \"table\"\naxis = [0.0, 0.0, 1.0]", 1)
        .replace("name = \"A\"\ncarrier = \"head\"\naxis = [1.0, 0.0, 0.0]", "name = \"B\"\ncarrier = \"head\"\naxis = [0.0, 1.0, 0.0]");
    vec![
        Machine::hermle_c600u(),
        Machine::builtin("mikron-ucp710").unwrap(),
        Machine::builtin("seed003-ttttr").unwrap(),
        Machine::from_toml_str(head_head, "test").unwrap(),
        Machine::from_toml_str(&table_head, "test").unwrap(),
    ]
}

#[test]
fn singular_directions_follow_seed001_section_2_4() {
    let ms = machines();
    let z = Vector3::z();
    // Table-table: the inner table axis (C); head-head: the outer head axis (C on the ram);
    // table-head: the table axis. All vertical here.
    for m in &ms {
        assert!(m.singular_direction().cross(&z).norm() < 1e-12, "{}", m.name);
        assert_eq!(m.axes[m.secondary_axis()].name, "C", "{}", m.name);
    }
}

/// Seed 001 Table 1: both solutions (A, C) and (-A, C + pi).
#[test]
fn hermle_has_both_table_1_solutions() {
    let m = Machine::hermle_c600u();
    let (a, c) = (30.0 * DEG, 40.0 * DEG);
    let pose = m.forward(&[0.01, 0.02, 0.03, a, c]);
    let all = m.inverse_all(&pose).unwrap();
    let mut rot: Vec<(f64, f64)> = all.iter().map(|q| (q[3] / DEG, q[4].rem_euclid(std::f64::consts::TAU) / DEG)).collect();
    rot.sort_by(|p, q| p.0.total_cmp(&q.0));
    assert!((rot[0].0 + 30.0).abs() < 1e-9 && (rot[0].1 - 220.0).abs() < 1e-9, "{rot:?}");
    assert!((rot[1].0 - 30.0).abs() < 1e-9 && (rot[1].1 - 40.0).abs() < 1e-9, "{rot:?}");
    // The nearest to a previous state on the negative branch is the negative solution.
    let q = m.inverse(&pose, &[0.0, 0.0, 0.0, -25.0 * DEG, 215.0 * DEG]).unwrap();
    assert!((q[3] / DEG + 30.0).abs() < 1e-9 && (q[4] / DEG - 220.0).abs() < 1e-9);
}

#[test]
fn singular_pose_keeps_the_previous_c() {
    let m = Machine::hermle_c600u();
    let pose = Pose { tip: Vector3::new(0.01, 0.0, 0.0), axis: Vector3::z() };
    let q = m.inverse(&pose, &[0.0, 0.0, 0.0, 0.5 * DEG, 123.0 * DEG]).unwrap();
    assert!(q[3].abs() < 1e-12);
    assert!((q[4] / DEG - 123.0).abs() < 1e-12);
    let back = m.forward(&q);
    assert!(close(&back.tip, &pose.tip, 1e-12));
}

#[test]
fn c_unwraps_to_the_turn_nearest_the_previous_state() {
    let m = Machine::hermle_c600u();
    let pose = m.forward(&[0.0, 0.0, 0.0, 20.0 * DEG, 26.198 * DEG]);
    let q = m.inverse(&pose, &[0.0, 0.0, 0.0, 20.0 * DEG, 380.0 * DEG]).unwrap();
    assert!((q[4] / DEG - 386.198).abs() < 1e-9, "{}", q[4] / DEG);
}

#[test]
fn orientation_beyond_the_a_range_is_refused_with_the_reason() {
    let m = Machine::hermle_c600u();
    let a = 115.0 * DEG;
    let pose = Pose { tip: Vector3::zeros(), axis: Vector3::new(0.0, a.sin(), a.cos()) };
    match m.inverse(&pose, &[0.0; 5]) {
        Err(KinematicsError::OutOfRange { axis, value, .. }) => {
            assert_eq!(axis, "A");
            assert!((value.abs() - 115.0).abs() < 1e-9);
        }
        other => panic!("expected OutOfRange, got {other:?}"),
    }
    let nan = Pose { tip: Vector3::new(f64::NAN, 0.0, 0.0), axis: Vector3::z() };
    assert_eq!(m.inverse(&nan, &[0.0; 5]), Err(KinematicsError::NotFinite));
    let zero = Pose { tip: Vector3::zeros(), axis: Vector3::zeros() };
    assert_eq!(m.inverse(&zero, &[0.0; 5]), Err(KinematicsError::ZeroToolAxis));
}

/// Seed 003's worked example: CL (x 23.193, y -76.899, z -7.464, i -0.612, j 0.354, k 0.707) gives
/// B 45.0087 and C 30.0464. The paper takes B = acos(k) of the printed, slightly non-unit axis
/// (|ijk| = 0.99985); the library normalises first and gets 45.0003: within 0.01 deg of the paper.
/// C does not depend on the normalisation and agrees to the printed four decimals.
#[test]
fn seed003_worked_example_orientation() {
    let m = Machine::builtin("seed003-ttttr").unwrap();
    let pose = Pose { tip: Vector3::new(23.193, -76.899, -7.464) * MM, axis: Vector3::new(-0.612, 0.354, 0.707) };
    let q = m.inverse(&pose, &[0.0; 5]).unwrap();
    let (b, c) = (q[m.axis_index("B").unwrap()] / DEG, q[m.axis_index("C").unwrap()] / DEG);
    assert!((c - 30.0464).abs() < 5e-5, "C {c}");
    assert!((b - 45.0087).abs() < 0.01, "B {b}");
    assert!((b - (0.707 / pose.axis.norm()).acos().to_degrees()).abs() < 1e-9);
    // Round trip of the example pose.
    let back = m.forward(&q);
    assert!(close(&back.tip, &pose.tip, 1e-12));
    assert!(close(&back.axis, &pose.axis.normalize(), 1e-12));
}

#[test]
fn machine_files_report_what_is_wrong() {
    let bad = Machine::from_toml_str("name = \"x\"\nlinear = []\nrotary = []\n", "bad.toml").unwrap_err();
    assert!(bad.to_string().contains("3 [[linear]]"), "{bad}");
    let unknown = Machine::from_toml_str("name = \"x\"\nfoo = 1\nlinear = []\nrotary = []\n", "bad.toml").unwrap_err();
    assert!(unknown.to_string().contains("foo"), "{unknown}");
    assert!(fiveaxis::machine::load("no-such-machine").is_err());
    // A contour tolerance outside 0 to 10 mm / 10 deg (cycle 32's input range), named by its field;
    // within it, taken in SI.
    let hermle = include_str!("../machines/hermle-c600u.toml");
    let with = |fields: &str| Machine::from_toml_str(&hermle.replacen("\n[[linear]]", &format!("\n{fields}\n\n[[linear]]"), 1), "t.toml");
    for (fields, named) in [("contour_tolerance_mm = 11", "`contour_tolerance_mm` = 11"), ("contour_tolerance_deg = -0.1", "`contour_tolerance_deg` = -0.1"), ("contour_tolerance_mm = nan", "`contour_tolerance_mm` = NaN")] {
        let e = with(fields).unwrap_err().to_string();
        assert!(e.contains(named) && e.contains("expected a tolerance from 0 to 10"), "{fields}: {e}");
    }
    let m = with("contour_tolerance_mm = 10\ncontour_tolerance_deg = 0.5").unwrap();
    assert!((m.contour_tolerance.linear_m - 0.01).abs() < 1e-15 && (m.contour_tolerance.rotary_rad - 0.5f64.to_radians()).abs() < 1e-15, "{:?}", m.contour_tolerance);
}
