//! REP 2016 type hashes (`RIHS01_` + SHA-256 of the type description's canonical JSON), as
//! `rosidl_generator_type_description` computes them from the `.msg` files: rmw_zenoh puts them in
//! every topic key, so a ROS 2 subscriber on rmw_zenoh matches only a publisher with its type's hash.

use crate::schema::{fields, DEFINITIONS};
use sha2::{Digest, Sha256};

/// `type_description_interfaces/msg/FieldType` ids of the .msg primitive types (REP 2016).
fn primitive_id(ty: &str) -> Option<u8> {
    Some(match ty {
        "int8" => 2,
        "uint8" | "char" => 3,
        "int16" => 4,
        "uint16" => 5,
        "int32" => 6,
        "uint32" => 7,
        "int64" => 8,
        "uint64" => 9,
        "float32" => 10,
        "float64" => 11,
        "bool" => 15,
        "byte" => 16,
        "string" => 17,
        "wstring" => 18,
        _ => return None,
    })
}

/// `pkg/Type` or `pkg/msg/Type` as `pkg/msg/Type`.
fn full_name(ty: &str) -> String {
    match ty.split_once('/') {
        Some((pkg, rest)) if !rest.starts_with("msg/") => format!("{pkg}/msg/{rest}"),
        _ => ty.to_string(),
    }
}

fn json_string(s: &str, out: &mut String) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
}

/// One field's `{"type_id", "capacity", "string_capacity", "nested_type_name"}`: the base type's
/// id, plus 48 for an array `[N]`, 96 for a bounded sequence `[<=N]`, 144 for a sequence `[]`;
/// bounded strings `string<=N` are id 21 (22 wide) with their bound.
fn field_type(ty: &str, nested: &mut Vec<String>) -> Option<String> {
    let (base, offset, capacity) = match ty.split_once('[') {
        None => (ty, 0u32, 0u64),
        Some((b, rest)) => {
            let inner = rest.strip_suffix(']')?;
            if inner.is_empty() {
                (b, 144, 0)
            } else if let Some(n) = inner.strip_prefix("<=") {
                (b, 96, n.parse().ok()?)
            } else {
                (b, 48, inner.parse().ok()?)
            }
        }
    };
    let (id, string_capacity, nested_name) = if let Some((s, n)) = base.split_once("<=") {
        let id = match s {
            "string" => 21,
            "wstring" => 22,
            _ => return None,
        };
        (id, n.parse::<u64>().ok()?, String::new())
    } else if let Some(id) = primitive_id(base) {
        (id, 0, String::new())
    } else if base.contains('/') {
        let name = full_name(base);
        nested.push(name.clone());
        (1, 0, name)
    } else {
        return None;
    };
    let mut out = format!("{{\"type_id\": {}, \"capacity\": {capacity}, \"string_capacity\": {string_capacity}, \"nested_type_name\": ", id as u32 + offset);
    json_string(&nested_name, &mut out);
    out.push('}');
    Some(out)
}

/// The individual description of `pkg/msg/Type` as canonical JSON, and the types it references.
fn individual(type_name: &str) -> Option<(String, Vec<String>)> {
    let key = type_name.replace("/msg/", "/");
    let text = DEFINITIONS.iter().find(|(n, _)| *n == key)?.1;
    let mut nested = Vec::new();
    let mut out = String::from("{\"type_name\": ");
    json_string(type_name, &mut out);
    out.push_str(", \"fields\": [");
    for (i, f) in fields(text).iter().enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        out.push_str("{\"name\": ");
        json_string(&f.name, &mut out);
        out.push_str(", \"type\": ");
        out.push_str(&field_type(&f.ty, &mut nested)?);
        out.push('}');
    }
    out.push_str("]}");
    Some((out, nested))
}

/// The REP 2016 hash of `pkg/msg/Type` (or `pkg/Type`), one of [`DEFINITIONS`]: `RIHS01_` and the
/// lowercase hex SHA-256 of `{"type_description": ..., "referenced_type_descriptions": [...]}`,
/// the references being every type it uses, transitively, once each, sorted by name (REP 2016,
/// "Type Hash"; `json.dumps` with `", "` and `": "` separators, default values left out).
pub fn rihs01(type_name: &str) -> Option<String> {
    let name = full_name(type_name);
    let (top, mut todo) = individual(&name)?;
    let mut referenced: Vec<(String, String)> = Vec::new();
    while let Some(t) = todo.pop() {
        if t == name || referenced.iter().any(|(n, _)| *n == t) {
            continue;
        }
        let (json, more) = individual(&t)?;
        referenced.push((t, json));
        todo.extend(more);
    }
    referenced.sort();
    let refs: Vec<&str> = referenced.iter().map(|(_, j)| j.as_str()).collect();
    let json = format!("{{\"type_description\": {top}, \"referenced_type_descriptions\": [{}]}}", refs.join(", "));
    let digest = Sha256::digest(json.as_bytes());
    Some(format!("RIHS01_{}", digest.iter().map(|b| format!("{b:02x}")).collect::<String>()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_definition_hashes_and_unknown_types_do_not() {
        for (name, _) in DEFINITIONS {
            let h = rihs01(name).unwrap_or_else(|| panic!("{name}"));
            assert_eq!(h.len(), 71, "{h}");
            assert_eq!(rihs01(&full_name(name)), Some(h));
        }
        assert_eq!(rihs01("std_msgs/msg/Nope"), None);
    }

    #[test]
    fn field_types_follow_rep_2016() {
        let mut n = Vec::new();
        let ty = |t: &str, n: &mut Vec<String>| field_type(t, n).unwrap();
        assert!(ty("float64[]", &mut n).starts_with("{\"type_id\": 155, \"capacity\": 0,"));
        assert!(ty("uint8[3]", &mut n).starts_with("{\"type_id\": 51, \"capacity\": 3,"));
        assert!(ty("int32[<=4]", &mut n).starts_with("{\"type_id\": 102, \"capacity\": 4,"));
        assert!(ty("string<=8", &mut n).starts_with("{\"type_id\": 21, \"capacity\": 0, \"string_capacity\": 8,"));
        assert!(ty("geometry_msgs/Point[]", &mut n).ends_with("\"nested_type_name\": \"geometry_msgs/msg/Point\"}"));
        assert_eq!(n, ["geometry_msgs/msg/Point"]);
    }
}
