//! The reference figures of seed 001 (Cripps et al. 2017) and of `../shared/reference/README.md`,
//! reproduced by the library. Tolerances are stated with each assertion.

use fiveaxis::job::{self, JobOptions};
use fiveaxis::kinematics::{unwrap_near, Pose};
use fiveaxis::machine::Machine;
use fiveaxis::path::paper_orientation;
use fiveaxis::program::{read, Dialect, ReadOptions};
use fiveaxis::units::{DEG, MM};
use nalgebra::Vector3;

fn run(spec: &str) -> job::Job {
    job::run(spec, &Machine::hermle_c600u(), &JobOptions::default()).expect("job runs")
}

fn assert_close(what: &str, got: f64, want: f64, tol: f64) {
    assert!((got - want).abs() <= tol, "{what}: got {got}, want {want} +- {tol}");
}

/// The peak of eq. (9) follows from the geometry alone: the tool axis runs on a circle of radius
/// sin(10 deg) at 120 deg/s, tangentially (horizontally) at the zenith, 1 deg from the pole:
/// dC/dt = sin(10 deg) * 120 deg/s / sin(1 deg) (eq. 5).
#[test]
fn continuous_singular_path_peak_is_eq5_at_the_zenith() {
    let j = run("builtin:paper-sing");
    let hand = (10f64.to_radians().sin() * 120f64.to_radians() / 1f64.to_radians().sin()) * 60.0 / std::f64::consts::TAU;
    assert_close("hand-computed peak (rpm)", hand, 199.0, 0.05);
    assert_close("peak C speed (rpm)", j.report.peak_c_speed_rpm, hand, 0.01);
    assert_close("peak C speed x (mm)", j.report.peak_c_speed_x_mm, 25.0, 0.02);
    // The finite difference of the sampled C axis agrees with eq. (5) to 0.5 %.
    assert_close("finite-difference peak (rpm)", j.report.peak_c_speed_fd_rpm, hand, hand * 0.005);
    assert_close("closest approach (deg)", j.report.min_singularity_distance_deg.unwrap(), 1.0, 1e-3);
}

#[test]
fn continuous_singular_path_region_is_21_58_to_28_42() {
    let j = run("builtin:paper-sing");
    assert_eq!(j.report.regions.len(), 1, "one region: {:?}", j.report.regions);
    let r = &j.report.regions[0];
    // Sampled at 1 ms = 0.033 mm; the boundary is interpolated between samples.
    assert_close("region start (mm)", r.x_start_mm, 21.58, 0.01);
    assert_close("region end (mm)", r.x_end_mm, 28.42, 0.01);
    assert_close("region peak (rpm)", r.peak_c_speed_rpm, 199.0, 0.05);
}

#[test]
fn continuous_reoriented_path_peaks_at_18_2_rpm() {
    let j = run("builtin:paper-nonsing");
    assert_close("peak C speed (rpm)", j.report.peak_c_speed_rpm, 18.2, 0.05);
    assert!(j.report.regions.is_empty(), "no region: {:?}", j.report.regions);
    assert_close("closest approach (deg)", j.report.min_singularity_distance_deg.unwrap(), 11.0, 1e-3);
}

#[test]
fn sing_program_peaks_at_175_rpm_with_blocks_22_to_28_above_the_limit() {
    let j = run("bundled:SING.I");
    assert_eq!(j.report.errors, 0, "{:?}", j.report.diagnostics);
    // Block x 24-25: C 148.494 -> 180 in 1 mm at 2000 mm/min (0.03 s): 31.506 deg / 0.03 s = 175.0 rpm.
    assert_close("peak C speed (rpm)", j.report.peak_c_speed_rpm, 175.0, 0.05);
    assert!((24.0..=26.0).contains(&j.report.peak_c_speed_x_mm), "peak in blocks x 24-26: {}", j.report.peak_c_speed_x_mm);
    assert_eq!(j.report.regions.len(), 1, "{:?}", j.report.regions);
    let r = &j.report.regions[0];
    assert_close("region start (mm)", r.x_start_mm, 22.0, 1e-6);
    assert_close("region end (mm)", r.x_end_mm, 28.0, 1e-6);
    assert_eq!((r.block_start, r.block_end), (Some(340), Some(390)));
    assert_close("closest approach (deg)", j.report.min_singularity_distance_deg.unwrap(), 1.0, 1e-9);
}

#[test]
fn nonsing_program_peaks_at_18_1_rpm_and_stays_11_degrees_away() {
    let j = run("bundled:NON_SING.I");
    assert_eq!(j.report.errors, 0, "{:?}", j.report.diagnostics);
    assert_close("peak C speed (rpm)", j.report.peak_c_speed_rpm, 18.1, 0.05);
    assert!(j.report.regions.is_empty());
    assert_close("closest approach (deg)", j.report.min_singularity_distance_deg.unwrap(), 11.0, 1e-9);
}

/// Cutting blocks (Z-8 with A and C words) of a bundled program: (x mm, y mm, A deg, C deg).
fn cutting_blocks(name: &str) -> Vec<(f64, f64, f64, f64)> {
    let (_, text) = job::BUNDLED.iter().find(|(n, _)| *n == name).unwrap();
    let p = read(text, Dialect::Heidenhain, name, &ReadOptions::default());
    p.blocks
        .iter()
        .filter(|b| b.tcp && b.targets.z == Some(-8.0 * MM) && b.targets.a.is_some())
        .map(|b| (b.targets.x.unwrap() / MM, b.targets.y.unwrap() / MM, b.targets.a.unwrap() / DEG, b.targets.c.unwrap() / DEG))
        .collect()
}

/// Inverse kinematics of the continuous path, following the program from its first block, must give
/// the printed A and C to the printed three decimals (|error| <= 0.0005 deg), C unwrapped as printed.
fn check_program_against_eq(name: &str, tilt: f64, mirror_y: bool) {
    let m = Machine::hermle_c600u();
    let blocks = cutting_blocks(name);
    let moving: Vec<_> = blocks.iter().filter(|b| b.1 == 0.0 || b.1 == 50.0).collect();
    assert!(moving.len() >= 51, "{name}: {} cutting blocks", moving.len());
    let first = moving[0];
    let mut prev = [0.0, 0.0, 0.0, first.2 * DEG, first.3 * DEG];
    for &&(x, _, a, c) in &moving {
        let mut o = paper_orientation(tilt, x);
        if mirror_y {
            o.y = -o.y;
        }
        let q = m.inverse(&Pose { tip: Vector3::new(x, 0.0, -8.0) * MM, axis: o }, &prev).unwrap();
        prev = q;
        let (ga, gc) = (q[3] / DEG, q[4] / DEG);
        assert!((ga - a).abs() <= 0.0005 + 1e-9, "{name} x={x}: A {ga:.4} vs printed {a}");
        assert!((gc - c).abs() <= 0.0005 + 1e-9, "{name} x={x}: C {gc:.4} vs printed {c} (unwrapped)");
    }
}

#[test]
fn sing_program_is_the_inverse_kinematics_of_eq_9() {
    check_program_against_eq("SING.I", 11.0, false);
}

/// The reoriented program was cut on the opposite face of the block (y = 50, traversed from x = 50 to
/// 0): its orientations are eq. (11) mirrored in y. Its C runs past 360 deg (C+386.198): unwrapping.
#[test]
fn nonsing_program_is_eq_11_mirrored_to_the_far_face() {
    check_program_against_eq("NON_SING.I", 21.0, true);
    assert!(cutting_blocks("NON_SING.I").iter().any(|b| b.3 > 386.0));
}

/// The reference note's example: x = 26 mm gives A = 1.196, C = 211.506 (from C = 180 at x = 25).
#[test]
fn reference_note_example_x26() {
    let m = Machine::hermle_c600u();
    let pose = Pose { tip: Vector3::new(26.0, 0.0, -8.0) * MM, axis: paper_orientation(11.0, 26.0) };
    let q = m.inverse(&pose, &[0.0, 0.0, 0.0, 1.0 * DEG, 180.0 * DEG]).unwrap();
    assert_close("A (deg)", q[3] / DEG, 1.196, 0.0005);
    assert_close("C (deg)", unwrap_near(q[4], 180.0 * DEG) / DEG, 211.506, 0.0005);
}
