//! ros2msg definition texts, with dependencies, as rosbag2 stores them in MCAP schemas.

/// Definition text of each known type by `pkg/Type` (without `msg/`).
pub const DEFINITIONS: [(&str, &str); 12] = [
    ("fiveaxis_msgs/AxisState", include_str!("../msg/AxisState.msg")),
    ("fiveaxis_msgs/SingularityStatus", include_str!("../msg/SingularityStatus.msg")),
    ("fiveaxis_msgs/Region", include_str!("../msg/Region.msg")),
    ("builtin_interfaces/Time", include_str!("../defs/builtin_interfaces__Time.msg")),
    ("std_msgs/Header", include_str!("../defs/std_msgs__Header.msg")),
    ("geometry_msgs/Point", include_str!("../defs/geometry_msgs__Point.msg")),
    ("geometry_msgs/Vector3", include_str!("../defs/geometry_msgs__Vector3.msg")),
    ("sensor_msgs/JointState", include_str!("../defs/sensor_msgs__JointState.msg")),
    ("diagnostic_msgs/DiagnosticArray", include_str!("../defs/diagnostic_msgs__DiagnosticArray.msg")),
    ("diagnostic_msgs/DiagnosticStatus", include_str!("../defs/diagnostic_msgs__DiagnosticStatus.msg")),
    ("diagnostic_msgs/KeyValue", include_str!("../defs/diagnostic_msgs__KeyValue.msg")),
    ("rosgraph_msgs/Clock", include_str!("../defs/rosgraph_msgs__Clock.msg")),
];

/// One field of a definition: its type as written (`float64[]`, `std_msgs/Header`) and name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Field {
    pub ty: String,
    pub name: String,
}

/// The fields of a definition text, in order (comments, blank lines and constants skipped).
pub fn fields(text: &str) -> Vec<Field> {
    text.lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .filter(|l| !l.is_empty())
        .filter_map(|l| {
            let mut parts = l.split_whitespace();
            let ty = parts.next()?;
            let rest: String = parts.collect::<Vec<_>>().join(" ");
            if rest.contains('=') {
                return None; // a constant
            }
            Some(Field { ty: ty.to_string(), name: rest })
        })
        .collect()
}

/// The package-qualified complex types a definition of `package` uses (`Header` inside std_msgs
/// would be `std_msgs/Header`).
fn dependencies(text: &str) -> Vec<String> {
    const PRIMITIVES: [&str; 16] = [
        "bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64",
        "uint64", "string", "wstring", "time",
    ];
    fields(text)
        .into_iter()
        .map(|f| f.ty.split('[').next().unwrap_or("").to_string())
        .filter(|t| !PRIMITIVES.contains(&t.as_str()) && t.contains('/'))
        .collect()
}

/// The MCAP `ros2msg` schema text of `pkg/msg/Type` or `pkg/Type`: its definition, then each
/// dependency (depth first, once) after a line of 80 `=` and `MSG: pkg/Type`.
pub fn ros2msg(type_name: &str) -> Option<String> {
    let key = type_name.replace("/msg/", "/");
    let main = DEFINITIONS.iter().find(|(n, _)| *n == key)?.1;
    let mut out = main.trim_end().to_string();
    out.push('\n');
    let mut seen: Vec<String> = vec![key];
    let mut stack: Vec<String> = dependencies(main).into_iter().rev().collect();
    while let Some(dep) = stack.pop() {
        if seen.contains(&dep) {
            continue;
        }
        let text = DEFINITIONS.iter().find(|(n, _)| *n == dep)?.1;
        out.push_str(&"=".repeat(80));
        out.push_str("\nMSG: ");
        out.push_str(&dep);
        out.push('\n');
        out.push_str(text.trim_end());
        out.push('\n');
        stack.extend(dependencies(text).into_iter().rev());
        seen.push(dep);
    }
    Some(out)
}
