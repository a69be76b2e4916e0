//! The messages of the fiveaxis node set, as Rust types whose field order and types match the ROS 2
//! interface definitions exactly (`msg/*.msg` of this package and the standard ones in `defs/`), so
//! that CDR (de)serialization with serde is wire-compatible with ROS 2. SI units (REP 103).
//!
//! [`schema`] gives the ros2msg definition text of each type with its dependencies appended, in the
//! layout rosbag2 writes into MCAP (`=` x 80, `MSG: pkg/Type`).

pub mod bounds;
pub mod cdr;
pub mod schema;
pub mod type_hash;

use serde::{Deserialize, Serialize};

/// A ROS 2 message type: its `pkg/msg/Type` name.
pub trait RosMessage {
    /// Package name, e.g. `fiveaxis_msgs`.
    const PACKAGE: &'static str;
    /// Type name, e.g. `AxisState`.
    const NAME: &'static str;
    /// `pkg/msg/Type`.
    fn type_name() -> String {
        format!("{}/msg/{}", Self::PACKAGE, Self::NAME)
    }
}

macro_rules! ros_message {
    ($t:ty, $pkg:literal, $name:literal) => {
        impl RosMessage for $t {
            const PACKAGE: &'static str = $pkg;
            const NAME: &'static str = $name;
        }
    };
}

/// builtin_interfaces/Time.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Time {
    pub sec: i32,
    pub nanosec: u32,
}
ros_message!(Time, "builtin_interfaces", "Time");

impl Time {
    /// From seconds (negative or non-finite values give zero).
    pub fn from_secs(t: f64) -> Time {
        if !(t.is_finite() && t > 0.0) {
            return Time::default();
        }
        let sec = t.floor();
        let mut nanosec = ((t - sec) * 1e9).round() as u32;
        let mut sec = sec.min(i32::MAX as f64) as i32;
        if nanosec >= 1_000_000_000 {
            sec = sec.saturating_add(1);
            nanosec -= 1_000_000_000;
        }
        Time { sec, nanosec }
    }
    /// To seconds.
    pub fn as_secs(&self) -> f64 {
        self.sec as f64 + self.nanosec as f64 * 1e-9
    }
    /// Nanoseconds since the epoch of the clock (negative times clamp to 0).
    pub fn as_nanos(&self) -> u64 {
        (self.sec.max(0) as u64) * 1_000_000_000 + self.nanosec as u64
    }
    /// From nanoseconds since the epoch of the clock, exactly (seconds saturate at `i32::MAX`).
    pub fn from_nanos(ns: u64) -> Time {
        Time { sec: (ns / 1_000_000_000).min(i32::MAX as u64) as i32, nanosec: (ns % 1_000_000_000) as u32 }
    }
}

/// std_msgs/Header.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Header {
    pub stamp: Time,
    #[serde(deserialize_with = "bounds::frame_id")]
    pub frame_id: String,
}
ros_message!(Header, "std_msgs", "Header");

/// geometry_msgs/Point.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Point {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}
ros_message!(Point, "geometry_msgs", "Point");

/// geometry_msgs/Vector3.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}
ros_message!(Vector3, "geometry_msgs", "Vector3");

/// fiveaxis_msgs/AxisState: see `msg/AxisState.msg`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisState {
    pub header: Header,
    pub source: u8,
    #[serde(deserialize_with = "bounds::names")]
    pub name: Vec<String>,
    #[serde(deserialize_with = "bounds::values")]
    pub position: Vec<f64>,
    #[serde(deserialize_with = "bounds::values")]
    pub velocity: Vec<f64>,
    #[serde(deserialize_with = "bounds::values")]
    pub acceleration: Vec<f64>,
    pub tool_tip: Point,
    pub tool_axis: Vector3,
    pub programmed_feed: f64,
    pub path_feed: f64,
    pub program_line: u32,
    pub block_number: i64,
    pub motion: u8,
}
ros_message!(AxisState, "fiveaxis_msgs", "AxisState");

impl AxisState {
    pub const SOURCE_COMMANDED: u8 = 0;
    pub const SOURCE_SIMULATED: u8 = 1;
    pub const SOURCE_MACHINE: u8 = 2;
    pub const MOTION_UNKNOWN: u8 = 0;
    pub const MOTION_RAPID: u8 = 1;
    pub const MOTION_FEED: u8 = 2;
    pub const MOTION_ROTARY: u8 = 3;
    pub const MOTION_DWELL: u8 = 4;

    /// The same state as a sensor_msgs/JointState (names, positions and velocities; no effort).
    pub fn to_joint_state(&self) -> JointState {
        JointState {
            header: self.header.clone(),
            name: self.name.clone(),
            position: self.position.clone(),
            velocity: self.velocity.clone(),
            effort: Vec::new(),
        }
    }
}

/// fiveaxis_msgs/SingularityStatus: see `msg/SingularityStatus.msg`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SingularityStatus {
    pub header: Header,
    pub source: u8,
    pub input_topic: String,
    pub motion: u8,
    pub singularity_distance: f64,
    pub secondary_axis: String,
    pub predicted_c_speed: f64,
    pub c_speed: f64,
    pub c_speed_limit: f64,
    pub programmed_feed: f64,
    pub path_feed: f64,
    pub feed_limit: f64,
    pub limiting_axis: String,
    pub limit_kind: u8,
    pub in_region: bool,
    pub region_id: u32,
    pub region_cause: u8,
    pub workpiece_position: Point,
    pub time_to_next_region: f64,
    pub program_line: u32,
    pub block_number: i64,
    pub stale: bool,
    pub invalid_count: u64,
    pub missing_joint_count: u64,
    pub non_finite_count: u64,
    pub out_of_range_count: u64,
    pub out_of_order_count: u64,
    pub stale_count: u64,
    pub lost_count: u64,
}
ros_message!(SingularityStatus, "fiveaxis_msgs", "SingularityStatus");

impl SingularityStatus {
    pub const LIMIT_PROGRAMMED: u8 = 0;
    pub const LIMIT_VELOCITY: u8 = 1;
    pub const LIMIT_ACCELERATION: u8 = 2;
    pub const LIMIT_JERK: u8 = 3;
    pub const MOTION_UNKNOWN: u8 = 0;
    pub const MOTION_RAPID: u8 = 1;
    pub const MOTION_FEED: u8 = 2;
    pub const MOTION_ROTARY: u8 = 3;
    pub const MOTION_DWELL: u8 = 4;
    pub const CAUSE_NONE: u8 = 0;
    pub const CAUSE_SINGULARITY: u8 = 1;
    pub const CAUSE_ROTARY_FEED: u8 = 2;
}

/// fiveaxis_msgs/Region: see `msg/Region.msg`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Region {
    pub header: Header,
    pub input_topic: String,
    pub region_id: u32,
    pub cause: u8,
    pub start: Time,
    pub end: Time,
    pub start_position: Point,
    pub end_position: Point,
    pub min_singularity_distance: f64,
    pub peak_predicted_c_speed: f64,
    pub c_speed_limit: f64,
    pub start_line: u32,
    pub end_line: u32,
    pub samples: u64,
}
ros_message!(Region, "fiveaxis_msgs", "Region");

/// sensor_msgs/JointState.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct JointState {
    pub header: Header,
    #[serde(deserialize_with = "bounds::names")]
    pub name: Vec<String>,
    #[serde(deserialize_with = "bounds::values")]
    pub position: Vec<f64>,
    #[serde(deserialize_with = "bounds::values")]
    pub velocity: Vec<f64>,
    #[serde(deserialize_with = "bounds::values")]
    pub effort: Vec<f64>,
}
ros_message!(JointState, "sensor_msgs", "JointState");

/// diagnostic_msgs/KeyValue.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct KeyValue {
    pub key: String,
    pub value: String,
}
ros_message!(KeyValue, "diagnostic_msgs", "KeyValue");

/// diagnostic_msgs/DiagnosticStatus.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct DiagnosticStatus {
    pub level: u8,
    pub name: String,
    pub message: String,
    pub hardware_id: String,
    pub values: Vec<KeyValue>,
}
ros_message!(DiagnosticStatus, "diagnostic_msgs", "DiagnosticStatus");

impl DiagnosticStatus {
    pub const OK: u8 = 0;
    pub const WARN: u8 = 1;
    pub const ERROR: u8 = 2;
    pub const STALE: u8 = 3;
}

/// diagnostic_msgs/DiagnosticArray.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct DiagnosticArray {
    pub header: Header,
    pub status: Vec<DiagnosticStatus>,
}
ros_message!(DiagnosticArray, "diagnostic_msgs", "DiagnosticArray");

/// rosgraph_msgs/Clock.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Clock {
    pub clock: Time,
}
ros_message!(Clock, "rosgraph_msgs", "Clock");
