//! The paper's continuous paths, seed 001 eq. (8)-(11):
//! `P_W = (100/3 (t + 0.75), delta_s, -h)` mm and `O_W = R_x(tilt) R_z(120 deg t) R_x(-10 deg) z`,
//! t in [-0.75, 0.75] s at F2000 mm/min (the reference notes: eq. 9 as printed puts the closest approach
//! at t = 0), tilt 11 deg (singular, eq. 9: closest approach 1 deg) or 21 deg (reoriented, eq. 11: 11 deg).
//! R_x, R_z are right-handed rotations here: with them, the Hermle inverse of eq. (2) reproduces the A/C
//! words of the paper's `%SING` program to the printed three decimals.

use super::{PathOptions, Sample, Segment, SegmentKind, Trajectory};
use crate::kinematics::{Joints, Pose};
use crate::machine::Machine;
use crate::units::{DEG, MM, MM_PER_MIN};
use nalgebra::{Rotation3, Vector3};

/// A built-in path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuiltinPath {
    pub name: &'static str,
    /// Tilt of eq. (9)/(11), degrees: the closest approach to the singularity is `tilt - 10`.
    pub tilt_deg: f64,
    /// Step-over y (delta_s) and depth -h, mm.
    pub y_mm: f64,
    pub z_mm: f64,
    /// Length along x, mm, and programmed feed, mm/min.
    pub length_mm: f64,
    pub feed_mm_per_min: f64,
}

const PATHS: [BuiltinPath; 2] = [
    BuiltinPath { name: "paper-sing", tilt_deg: 11.0, y_mm: 0.0, z_mm: -8.0, length_mm: 50.0, feed_mm_per_min: 2000.0 },
    BuiltinPath { name: "paper-nonsing", tilt_deg: 21.0, y_mm: 0.0, z_mm: -8.0, length_mm: 50.0, feed_mm_per_min: 2000.0 },
];

/// Names of the built-in paths (`builtin:NAME`).
pub fn builtin_names() -> Vec<&'static str> {
    PATHS.iter().map(|p| p.name).collect()
}

/// Tool axis of eq. (9)/(11) at workpiece x (mm) for the given tilt (deg).
pub fn paper_orientation(tilt_deg: f64, x_mm: f64) -> Vector3<f64> {
    let t = 3.0 * x_mm / 100.0 - 0.75;
    let rx = |a: f64| Rotation3::from_axis_angle(&Vector3::x_axis(), a);
    let rz = Rotation3::from_axis_angle(&Vector3::z_axis(), 120.0 * DEG * t);
    rx(tilt_deg * DEG) * (rz * (rx(-10.0 * DEG) * Vector3::z()))
}

/// Knot spacing of the segments that stand for the continuous path (for the feed-limit geometry), mm.
const PIECE_MM: f64 = 0.25;

impl BuiltinPath {
    /// Look a path up by name (with or without the `builtin:` prefix).
    pub fn by_name(name: &str) -> Option<BuiltinPath> {
        let n = name.strip_prefix("builtin:").unwrap_or(name);
        PATHS.iter().copied().find(|p| p.name == n)
    }

    /// The path as cutter-location data: a rapid to the first pose, then a pose every `spacing_mm`
    /// (what a CAM system would output).
    pub fn cl_program(&self, spacing_mm: f64) -> crate::program::Program {
        let n = (self.length_mm / spacing_mm).round().max(1.0) as usize;
        let blocks = (0..=n)
            .map(|k| {
                let p = self.pose(self.length_mm * k as f64 / n as f64);
                crate::program::Block {
                    line: k + 1,
                    column: 1,
                    number: None,
                    // Position at the start first (rapid), then cut.
                    motion: if k == 0 { crate::program::Motion::Rapid } else { crate::program::Motion::Linear },
                    targets: crate::program::Targets {
                        x: Some(p.tip.x),
                        y: Some(p.tip.y),
                        z: Some(p.tip.z),
                        tool_axis: Some([p.axis.x, p.axis.y, p.axis.z]),
                        ..Default::default()
                    },
                    arc: None,
                    feed: Some(crate::program::Feed { value_per_min: self.feed_mm_per_min, rotary_per_min: self.feed_mm_per_min, mode: crate::program::FeedMode::PerMinute }),
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
        crate::program::Program {
            source: format!("builtin:{} (CL every {spacing_mm} mm)", self.name),
            dialect: crate::program::Dialect::Cl,
            name: Some(self.name.to_string()),
            blocks,
            diagnostics: Vec::new(),
        }
    }

    fn pose(&self, x_mm: f64) -> Pose {
        Pose { tip: Vector3::new(x_mm, self.y_mm, self.z_mm) * MM, axis: paper_orientation(self.tilt_deg, x_mm) }
    }

    /// Sample the continuous path on `machine` (inverse kinematics with continuity, starting on the +
    /// branch of seed 001 Table 1). The tool-axis rate is the exact derivative of eq. (9)/(11).
    pub fn trajectory(&self, machine: &Machine, options: &PathOptions) -> Result<Trajectory, crate::kinematics::KinematicsError> {
        let feed = options.feed_override_mm_per_min.unwrap_or(self.feed_mm_per_min) * MM_PER_MIN;
        let length = self.length_mm * MM;
        let duration = length / feed;
        let first = machine.inverse_all(&self.pose(0.0))?;
        let p = machine.primary_axis();
        let mut prev: Joints = if first[0][p] >= 0.0 { first[0] } else { first[1] };
        let ik = |x_mm: f64, prev: &mut Joints| -> Result<Joints, crate::kinematics::KinematicsError> {
            let q = machine.inverse(&self.pose(x_mm), prev)?;
            *prev = q;
            Ok(q)
        };
        // Segments: short pieces, as a fine CL program of this path would be.
        let pieces = (self.length_mm / PIECE_MM).round().max(1.0) as usize;
        let mut segments = Vec::with_capacity(pieces);
        let mut kprev = prev;
        let mut q0 = ik(0.0, &mut kprev)?;
        for k in 0..pieces {
            let (x0, x1) = (self.length_mm * k as f64 / pieces as f64, self.length_mm * (k + 1) as f64 / pieces as f64);
            let q1 = ik(x1, &mut kprev)?;
            let seg_len = (x1 - x0) * MM;
            segments.push(Segment {
                kind: SegmentKind::Tcp,
                block: 0,
                line: 0,
                number: None,
                t0: seg_len * k as f64 / feed,
                duration: seg_len / feed,
                s0: x0 * MM,
                length: seg_len,
                q0,
                q1,
                tip0: self.pose(x0).tip,
                tip1: self.pose(x1).tip,
                datum: Vector3::zeros(),
                orient: None,
                feed,
                arc: None,
                tolerance: machine.contour_tolerance,
                path: true,
                exact: crate::program::Exact::Blend,
            });
            q0 = q1;
        }
        // Samples straight from the continuous path.
        let n = (duration / options.period).floor() as usize;
        let mut samples = Vec::with_capacity(n + 2);
        let h_mm = 1e-4;
        for k in 0..=n + 1 {
            let t = if k <= n { k as f64 * options.period } else { duration };
            if k == n + 1 && (duration - n as f64 * options.period).abs() < 1e-12 {
                break;
            }
            let x_mm = (feed * t / MM).min(self.length_mm);
            let q = ik(x_mm, &mut prev)?;
            let d_axis = (paper_orientation(self.tilt_deg, x_mm + h_mm) - paper_orientation(self.tilt_deg, x_mm - h_mm))
                / (2.0 * h_mm * MM);
            let segment = ((x_mm / self.length_mm * pieces as f64) as usize).min(pieces - 1);
            samples.push(Sample {
                t,
                s: x_mm * MM,
                segment,
                q,
                tip: self.pose(x_mm).tip,
                axis: paper_orientation(self.tilt_deg, x_mm),
                axis_rate: d_axis * feed,
                feed,
            });
        }
        Ok(Trajectory { period: options.period, segments, stored: samples, diagnostics: Vec::new() })
    }
}
