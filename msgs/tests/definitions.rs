//! The Rust types match the ROS 2 definitions exactly: field order, names and types. A recording
//! serde serializer reads each Rust struct's fields; the .msg files are parsed independently.

use fiveaxis_msgs::schema::{fields, ros2msg, DEFINITIONS};
use fiveaxis_msgs::*;
use serde::ser::{self, Serialize};
use std::fmt;

#[derive(Debug)]
struct E(String);
impl fmt::Display for E {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for E {}
impl ser::Error for E {
    fn custom<T: fmt::Display>(m: T) -> Self {
        E(m.to_string())
    }
}

/// Rust struct name -> ROS type.
fn ros_type(rust: &str) -> String {
    match rust {
        "Time" => "builtin_interfaces/Time",
        "Header" => "std_msgs/Header",
        "Point" => "geometry_msgs/Point",
        "Vector3" => "geometry_msgs/Vector3",
        "KeyValue" => "diagnostic_msgs/KeyValue",
        "DiagnosticStatus" => "diagnostic_msgs/DiagnosticStatus",
        other => other,
    }
    .to_string()
}

/// Serializes a value into its ROS type name (`float64`, `string[]`, `std_msgs/Header`).
struct TypeOf;
struct SeqType(Option<String>);
struct Opaque(String);

macro_rules! prim {
    ($($f:ident $t:ty => $n:literal),*) => { $(fn $f(self, _: $t) -> Result<String, E> { Ok($n.into()) })* };
}

impl ser::Serializer for TypeOf {
    type Ok = String;
    type Error = E;
    type SerializeSeq = SeqType;
    type SerializeTuple = ser::Impossible<String, E>;
    type SerializeTupleStruct = ser::Impossible<String, E>;
    type SerializeTupleVariant = ser::Impossible<String, E>;
    type SerializeMap = ser::Impossible<String, E>;
    type SerializeStruct = Opaque;
    type SerializeStructVariant = ser::Impossible<String, E>;
    prim!(serialize_bool bool => "bool", serialize_i8 i8 => "int8", serialize_i16 i16 => "int16",
          serialize_i32 i32 => "int32", serialize_i64 i64 => "int64", serialize_u8 u8 => "uint8",
          serialize_u16 u16 => "uint16", serialize_u32 u32 => "uint32", serialize_u64 u64 => "uint64",
          serialize_f32 f32 => "float32", serialize_f64 f64 => "float64", serialize_char char => "char",
          serialize_str &str => "string");
    fn serialize_bytes(self, _: &[u8]) -> Result<String, E> { Ok("uint8[]".into()) }
    fn serialize_none(self) -> Result<String, E> { Err(E("Option is not a ROS type".into())) }
    fn serialize_some<T: ?Sized + Serialize>(self, _: &T) -> Result<String, E> { Err(E("Option".into())) }
    fn serialize_unit(self) -> Result<String, E> { Err(E("unit".into())) }
    fn serialize_unit_struct(self, n: &'static str) -> Result<String, E> { Err(E(n.into())) }
    fn serialize_unit_variant(self, n: &'static str, _: u32, _: &'static str) -> Result<String, E> { Err(E(n.into())) }
    fn serialize_newtype_struct<T: ?Sized + Serialize>(self, _: &'static str, v: &T) -> Result<String, E> { v.serialize(TypeOf) }
    fn serialize_newtype_variant<T: ?Sized + Serialize>(self, n: &'static str, _: u32, _: &'static str, _: &T) -> Result<String, E> { Err(E(n.into())) }
    fn serialize_seq(self, _: Option<usize>) -> Result<SeqType, E> { Ok(SeqType(None)) }
    fn serialize_tuple(self, _: usize) -> Result<Self::SerializeTuple, E> { Err(E("tuple".into())) }
    fn serialize_tuple_struct(self, n: &'static str, _: usize) -> Result<Self::SerializeTupleStruct, E> { Err(E(n.into())) }
    fn serialize_tuple_variant(self, n: &'static str, _: u32, _: &'static str, _: usize) -> Result<Self::SerializeTupleVariant, E> { Err(E(n.into())) }
    fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, E> { Err(E("map".into())) }
    fn serialize_struct(self, name: &'static str, _: usize) -> Result<Opaque, E> { Ok(Opaque(ros_type(name))) }
    fn serialize_struct_variant(self, n: &'static str, _: u32, _: &'static str, _: usize) -> Result<Self::SerializeStructVariant, E> { Err(E(n.into())) }
}

impl ser::SerializeSeq for SeqType {
    type Ok = String;
    type Error = E;
    fn serialize_element<T: ?Sized + Serialize>(&mut self, v: &T) -> Result<(), E> {
        self.0 = Some(v.serialize(TypeOf)?);
        Ok(())
    }
    fn end(self) -> Result<String, E> {
        self.0.map(|t| format!("{t}[]")).ok_or_else(|| E("empty sequence in the sample: cannot tell its type".into()))
    }
}

impl ser::SerializeStruct for Opaque {
    type Ok = String;
    type Error = E;
    fn serialize_field<T: ?Sized + Serialize>(&mut self, _: &'static str, _: &T) -> Result<(), E> { Ok(()) }
    fn end(self) -> Result<String, E> { Ok(self.0) }
}

/// Records the top-level struct's fields as (type, name).
struct Fields(Vec<(String, String)>);
impl ser::SerializeStruct for &mut Fields {
    type Ok = ();
    type Error = E;
    fn serialize_field<T: ?Sized + Serialize>(&mut self, key: &'static str, v: &T) -> Result<(), E> {
        self.0.push((v.serialize(TypeOf)?, key.to_string()));
        Ok(())
    }
    fn end(self) -> Result<(), E> { Ok(()) }
}

fn rust_fields<T: Serialize>(sample: &T) -> Vec<(String, String)> {
    struct Top<'a>(&'a mut Fields);
    impl<'a> ser::Serializer for Top<'a> {
        type Ok = ();
        type Error = E;
        type SerializeSeq = ser::Impossible<(), E>;
        type SerializeTuple = ser::Impossible<(), E>;
        type SerializeTupleStruct = ser::Impossible<(), E>;
        type SerializeTupleVariant = ser::Impossible<(), E>;
        type SerializeMap = ser::Impossible<(), E>;
        type SerializeStruct = &'a mut Fields;
        type SerializeStructVariant = ser::Impossible<(), E>;
        fn serialize_struct(self, _: &'static str, _: usize) -> Result<&'a mut Fields, E> { Ok(self.0) }
        fn serialize_bool(self, _: bool) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_i8(self, _: i8) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_i16(self, _: i16) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_i32(self, _: i32) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_i64(self, _: i64) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_u8(self, _: u8) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_u16(self, _: u16) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_u32(self, _: u32) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_u64(self, _: u64) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_f32(self, _: f32) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_f64(self, _: f64) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_char(self, _: char) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_str(self, _: &str) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_bytes(self, _: &[u8]) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_none(self) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_some<T: ?Sized + Serialize>(self, _: &T) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_unit(self) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_unit_struct(self, _: &'static str) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_unit_variant(self, _: &'static str, _: u32, _: &'static str) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_newtype_struct<T: ?Sized + Serialize>(self, _: &'static str, _: &T) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_newtype_variant<T: ?Sized + Serialize>(self, _: &'static str, _: u32, _: &'static str, _: &T) -> Result<(), E> { Err(E("top".into())) }
        fn serialize_seq(self, _: Option<usize>) -> Result<Self::SerializeSeq, E> { Err(E("top".into())) }
        fn serialize_tuple(self, _: usize) -> Result<Self::SerializeTuple, E> { Err(E("top".into())) }
        fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Self::SerializeTupleStruct, E> { Err(E("top".into())) }
        fn serialize_tuple_variant(self, _: &'static str, _: u32, _: &'static str, _: usize) -> Result<Self::SerializeTupleVariant, E> { Err(E("top".into())) }
        fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, E> { Err(E("top".into())) }
        fn serialize_struct_variant(self, _: &'static str, _: u32, _: &'static str, _: usize) -> Result<Self::SerializeStructVariant, E> { Err(E("top".into())) }
    }
    let mut f = Fields(Vec::new());
    sample.serialize(Top(&mut f)).expect("a struct");
    f.0
}

/// Compare a Rust sample with the named definition; `byte` in ROS is uint8 on the wire.
fn check<T: Serialize + RosMessage>(sample: &T) {
    let key = format!("{}/{}", T::PACKAGE, T::NAME);
    let def = DEFINITIONS.iter().find(|(n, _)| *n == key).unwrap_or_else(|| panic!("no definition for {key}")).1;
    let want: Vec<(String, String)> = fields(def)
        .into_iter()
        .map(|f| {
            let ty = f.ty.replace("byte", "uint8");
            // Types of the same package may be written without it.
            let ty = if !ty.contains('/') && ty.chars().next().is_some_and(char::is_uppercase) { format!("{}/{}", T::PACKAGE, ty) } else { ty };
            (ty, f.name)
        })
        .collect();
    assert_eq!(rust_fields(sample), want, "{key}: Rust type and .msg differ");
}

fn s() -> String {
    "x".into()
}

#[test]
fn rust_types_match_the_definitions() {
    check(&Time::default());
    check(&Header::default());
    check(&Point::default());
    check(&Vector3::default());
    check(&AxisState { name: vec![s()], position: vec![0.0], velocity: vec![0.0], acceleration: vec![0.0], ..Default::default() });
    check(&SingularityStatus::default());
    check(&Region::default());
    check(&JointState { name: vec![s()], position: vec![0.0], velocity: vec![0.0], effort: vec![0.0], ..Default::default() });
    check(&KeyValue::default());
    check(&DiagnosticStatus { values: vec![KeyValue::default()], ..Default::default() });
    check(&DiagnosticArray { status: vec![DiagnosticStatus::default()], ..Default::default() });
    check(&Clock::default());
}

#[test]
fn constants_match() {
    let text = include_str!("../msg/AxisState.msg");
    assert!(text.contains(&format!("uint8 SOURCE_SIMULATED={}", AxisState::SOURCE_SIMULATED)));
    assert!(text.contains(&format!("uint8 SOURCE_MACHINE={}", AxisState::SOURCE_MACHINE)));
    let text = include_str!("../msg/SingularityStatus.msg");
    assert!(text.contains(&format!("uint8 LIMIT_JERK={}", SingularityStatus::LIMIT_JERK)));
}

/// rosbag2's layout: the type's own text, then each dependency once after 80 '=' and `MSG: pkg/Type`.
#[test]
fn schema_text_has_every_dependency_once() {
    let s = ros2msg("fiveaxis_msgs/msg/AxisState").unwrap();
    let sep = format!("{}\nMSG: ", "=".repeat(80));
    let deps: Vec<&str> = s.split(&sep).skip(1).map(|b| b.lines().next().unwrap()).collect();
    let mut sorted = deps.clone();
    sorted.sort();
    assert_eq!(sorted, vec!["builtin_interfaces/Time", "geometry_msgs/Point", "geometry_msgs/Vector3", "std_msgs/Header"]);
    assert!(s.starts_with("# The state of a five-axis machine"));
    let d = ros2msg("diagnostic_msgs/msg/DiagnosticArray").unwrap();
    assert!(d.contains("MSG: diagnostic_msgs/DiagnosticStatus") && d.contains("MSG: diagnostic_msgs/KeyValue"));
    assert!(ros2msg("no_pkg/msg/Nothing").is_none());
}

#[test]
fn time_conversions() {
    let t = Time::from_secs(1.5);
    assert_eq!(t, Time { sec: 1, nanosec: 500_000_000 });
    assert_eq!(Time::from_secs(f64::NAN), Time::default());
    assert_eq!(Time::from_secs(2.9999999999).nanosec, 0);
    assert_eq!(t.as_nanos(), 1_500_000_000);
}

/// The check catches a field out of order (a type claiming to be std_msgs/Header).
#[test]
#[should_panic(expected = "Rust type and .msg differ")]
fn a_misordered_type_is_caught() {
    #[derive(serde::Serialize)]
    struct Header {
        frame_id: String,
        stamp: Time,
    }
    impl RosMessage for Header {
        const PACKAGE: &'static str = "std_msgs";
        const NAME: &'static str = "Header";
    }
    check(&Header { frame_id: s(), stamp: Time::default() });
}
