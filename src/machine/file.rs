//! The TOML machine description (units in field names: mm, deg, mm/min) and its validation.

use super::{joint, Axis, AxisKind, AxisLimits, Machine, MachineError};
use crate::kinematics::{Carrier, TwoRotaryChain};
use crate::units::{DEG, MM, MM_PER_MIN};
use nalgebra::Vector3;
use serde::Deserialize;

/// A whole machine file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MachineFile {
    pub name: String,
    #[serde(default)]
    pub description: String,
    /// Tool axis O_M in the spindle frame at home (unit vector; default +Z).
    #[serde(default = "default_tool_axis")]
    pub tool_axis: [f64; 3],
    /// Tool tip at home relative to the linear-axis origin, mm (head machines: pivot minus tool length).
    #[serde(default)]
    pub tool_tip_mm: [f64; 3],
    pub linear: Vec<LinearAxisFile>,
    /// Exactly two rotary axes, in chain order from the machine base outwards on each side.
    pub rotary: Vec<RotaryAxisFile>,
}

fn default_tool_axis() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

/// A linear axis of a machine file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearAxisFile {
    pub name: String,
    pub min_mm: f64,
    pub max_mm: f64,
    pub velocity_mm_per_min: f64,
    pub acceleration_mm_per_s2: f64,
    pub jerk_mm_per_s3: f64,
}

/// A rotary axis of a machine file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotaryAxisFile {
    pub name: String,
    /// "table" (turns the workpiece) or "head" (turns the spindle).
    pub carrier: Carrier,
    /// Direction about which a positive move turns its carrier (right-handed), machine frame at home.
    pub axis: [f64; 3],
    /// A point on the axis, machine frame at home, mm.
    #[serde(default)]
    pub center_mm: [f64; 3],
    /// Range in degrees; omit both for an unlimited (multi-turn) axis.
    pub min_deg: Option<f64>,
    pub max_deg: Option<f64>,
    pub velocity_deg_per_s: f64,
    pub acceleration_deg_per_s2: f64,
    pub jerk_deg_per_s3: f64,
}

fn vec3(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

impl MachineFile {
    /// Validate and build the machine (SI inside).
    pub fn build(&self) -> Result<Machine, MachineError> {
        let invalid = |message: String| MachineError::Invalid { name: self.name.clone(), message };
        if self.linear.len() != 3 {
            return Err(invalid(format!("needs exactly 3 [[linear]] axes, found {}", self.linear.len())));
        }
        if self.rotary.len() != 2 {
            return Err(invalid(format!("needs exactly 2 [[rotary]] axes, found {}", self.rotary.len())));
        }
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let mut axes: Vec<Axis> = Vec::with_capacity(5);
        for l in &self.linear {
            if !(l.min_mm.is_finite() && l.max_mm.is_finite() && l.min_mm < l.max_mm) {
                return Err(invalid(format!("axis {}: min_mm must be below max_mm", l.name)));
            }
            if !(positive(l.velocity_mm_per_min) && positive(l.acceleration_mm_per_s2) && positive(l.jerk_mm_per_s3)) {
                return Err(invalid(format!("axis {}: velocity, acceleration and jerk must be positive", l.name)));
            }
            axes.push(Axis {
                name: l.name.clone(),
                kind: AxisKind::Linear,
                limits: AxisLimits {
                    min: l.min_mm * MM,
                    max: l.max_mm * MM,
                    velocity: l.velocity_mm_per_min * MM_PER_MIN,
                    acceleration: l.acceleration_mm_per_s2 * MM,
                    jerk: l.jerk_mm_per_s3 * MM,
                },
            });
        }
        let mut joints = Vec::with_capacity(2);
        for r in &self.rotary {
            let (min, max) = match (r.min_deg, r.max_deg) {
                (None, None) => (f64::NEG_INFINITY, f64::INFINITY),
                (Some(a), Some(b)) if a.is_finite() && b.is_finite() && a < b => (a * DEG, b * DEG),
                _ => return Err(invalid(format!("axis {}: give both min_deg < max_deg, or neither (unlimited)", r.name))),
            };
            if !(positive(r.velocity_deg_per_s) && positive(r.acceleration_deg_per_s2) && positive(r.jerk_deg_per_s3)) {
                return Err(invalid(format!("axis {}: velocity, acceleration and jerk must be positive", r.name)));
            }
            let axis = vec3(r.axis);
            if !(axis.iter().all(|v| v.is_finite()) && axis.norm() > 1e-9) {
                return Err(invalid(format!("axis {}: axis vector must be non-zero", r.name)));
            }
            axes.push(Axis {
                name: r.name.clone(),
                kind: AxisKind::Rotary,
                limits: AxisLimits {
                    min,
                    max,
                    velocity: r.velocity_deg_per_s * DEG,
                    acceleration: r.acceleration_deg_per_s2 * DEG,
                    jerk: r.jerk_deg_per_s3 * DEG,
                },
            });
            joints.push(joint(&r.name, r.carrier, axis, vec3(r.center_mm) * MM));
        }
        let mut names: Vec<String> = axes.iter().map(|a| a.name.to_ascii_uppercase()).collect();
        names.sort();
        names.dedup();
        if names.len() != 5 {
            return Err(invalid("axis names must be distinct".into()));
        }
        let tool_axis = vec3(self.tool_axis);
        if !(tool_axis.norm() > 1e-9) {
            return Err(invalid("tool_axis must be non-zero".into()));
        }
        let chain = TwoRotaryChain::new(
            [joints[0].clone(), joints[1].clone()],
            tool_axis.normalize(),
            vec3(self.tool_tip_mm) * MM,
        )
        .map_err(|e| invalid(e.to_string()))?;
        let axes: [Axis; 5] = axes.try_into().expect("five axes");
        Ok(Machine { name: self.name.clone(), description: self.description.clone(), axes, chain })
    }
}
