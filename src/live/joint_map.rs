//! A machine bridge's `sensor_msgs/JointState` onto the machine's axes: each axis finds its joint by
//! name (case-insensitive; an axis map renames it for bridges that call joints otherwise). One rule
//! for the live monitor, the Rerun bridge, `analyze` and `replay`.

use super::monitor::Rejection;
use crate::machine::AXES;
use crate::machine::Machine;
use fiveaxis_msgs::JointState;
use std::collections::BTreeMap;

/// What to tell a user whose JointState does not map: the joints it has, and the `--axis-map`
/// flags that would map them onto `machine`'s axes (keeping those `given`).
pub fn unmapped_hint(machine: &Machine, joints: &[String], given: &BTreeMap<String, String>) -> String {
    format!("joints found: [{}]; map them with {}", joints.join(", "), machine.suggest_axis_map(joints, given))
}

/// Maps JointState messages onto one machine's axes.
#[derive(Debug, Clone)]
pub struct JointMap {
    /// The joint name looked for per axis (the axis' own name unless renamed).
    joints: Vec<String>,
}

impl JointMap {
    /// The map for `machine`, with `rename` (machine axis -> joint name) for bridges that name joints
    /// otherwise.
    pub fn new(machine: &Machine, rename: &BTreeMap<String, String>) -> JointMap {
        let joints = machine.axis_names().iter().map(|a| rename.get(a).unwrap_or(a).clone()).collect();
        JointMap { joints }
    }

    /// The joint names looked for, in the machine's axis order.
    pub fn joints(&self) -> &[String] {
        &self.joints
    }

    /// The machine axes a message reports, in the machine's axis order (None: its joint is not in
    /// this message; a change-only bridge sends some joints only). No mapped joint at all refuses it.
    pub fn reports(&self, js: &JointState) -> Result<[Option<f64>; AXES], Rejection> {
        let mut values = [None; AXES];
        for (i, want) in self.joints.iter().enumerate() {
            if let Some(k) = js.name.iter().position(|n| n.eq_ignore_ascii_case(want)) {
                values[i] = Some(*js.position.get(k).ok_or_else(|| Rejection::Invalid(format!("no position for joint '{want}'")))?);
            }
        }
        if values.iter().all(Option::is_none) {
            return Err(Rejection::MissingJoint(self.joints[0].clone()));
        }
        Ok(values)
    }
}
