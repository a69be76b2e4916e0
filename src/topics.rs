//! The node set's topics in one table, used by the nodes, the in-process pipeline, the recorder and
//! the tests: each name as the nodes declare it (relative to the node namespace, or absolute for the
//! ROS-wide `/diagnostics` and `/clock`), as it resolves in the default namespace, and its type.

/// The node set's default namespace.
pub const NAMESPACE: &str = "/fiveaxis";

/// One topic of the node set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Topic {
    /// As the nodes declare it: relative to their namespace unless it starts with `/`.
    pub name: &'static str,
    /// Resolved in the default namespace [`NAMESPACE`], as recordings of the node set hold it.
    pub absolute: &'static str,
    /// The message type's short name (`AxisState`, as `fiveaxis-recorder --topic NAME:TYPE` takes it).
    pub ty: &'static str,
}

macro_rules! in_namespace {
    ($name:literal, $ty:literal) => {
        Topic { name: $name, absolute: concat!("/fiveaxis/", $name), ty: $ty }
    };
}

/// Commanded axis states (the commander, from the program).
pub const COMMANDED_STATE: Topic = in_namespace!("commanded/axis_state", "AxisState");
/// The commanded axes as `sensor_msgs/JointState` (robot_state_publisher, RViz, machine bridges).
pub const COMMANDED_JOINTS: Topic = in_namespace!("commanded/joint_states", "JointState");
/// What the simulated machine does (the simulator: planner and servo).
pub const SIMULATED_STATE: Topic = in_namespace!("simulated/axis_state", "AxisState");
pub const SIMULATED_JOINTS: Topic = in_namespace!("simulated/joint_states", "JointState");
/// A machine's own axis positions as a bridge publishes them (`fiveaxis-bridge`: MTConnect), each
/// message the axes reported at one instant.
pub const MACHINE_JOINTS: Topic = in_namespace!("machine/joint_states", "JointState");
/// The monitor's per-sample singularity status.
pub const STATUS: Topic = in_namespace!("monitor/status", "SingularityStatus");
/// The regions of the monitor's status, one message per closed region (the fleet gateway, in each
/// machine's namespace on the fleet network).
pub const REGIONS: Topic = in_namespace!("fleet/regions", "Region");
/// ROS-wide diagnostics (the monitor, 2 Hz).
pub const DIAGNOSTICS: Topic = Topic { name: "/diagnostics", absolute: "/diagnostics", ty: "DiagnosticArray" };
/// Program time, with `use_sim_time` (the commander).
pub const CLOCK: Topic = Topic { name: "/clock", absolute: "/clock", ty: "Clock" };

/// Every topic of the node set, in the order recordings list them.
pub const NODE_SET: [Topic; 7] = [COMMANDED_STATE, COMMANDED_JOINTS, SIMULATED_STATE, SIMULATED_JOINTS, STATUS, DIAGNOSTICS, CLOCK];

/// A machine's axes as JointState (m and rad): the node set's and a real machine's, which the fleet
/// gateway forwards rate-capped.
pub const JOINT_STATES: [Topic; 3] = [COMMANDED_JOINTS, SIMULATED_JOINTS, MACHINE_JOINTS];

/// The axis-state streams the monitor watches by default (commanded and simulated).
pub const MONITORED: [Topic; 2] = [COMMANDED_STATE, SIMULATED_STATE];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn absolute_names_are_the_names_in_the_default_namespace() {
        for t in NODE_SET {
            let want = if t.name.starts_with('/') { t.name.to_string() } else { format!("{NAMESPACE}/{}", t.name) };
            assert_eq!(t.absolute, want);
        }
    }
}
