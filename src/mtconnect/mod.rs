//! MTConnect machine data: a device's description ([`devices`]: what an agent's `/probe` or its
//! `Devices.xml` says) and an adapter's SHDR stream ([`shdr`]), read into per-axis position reports
//! of a machine model's axes (m, rad): each axis reported on its own, when it changed, at the
//! adapter's rate, merged into poses by [`crate::live::joint_stream`].

pub mod devices;
pub mod http;
pub mod live;
pub mod shdr;
pub mod streams;

use crate::machine::{AxisKind, Machine, AXES};
use devices::{DataItem, Device};
use std::collections::BTreeMap;
use std::io::BufRead;

pub use crate::source::AxisReport;

/// Longest SHDR line read (bytes): a longer one is refused, not held (an asset's body is read line
/// by line).
pub const MAX_LINE: usize = 1 << 20;

/// Which data item carries each machine axis' position, and the factor to SI of its values.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisItems {
    /// The data item's id, per machine axis.
    pub ids: [String; AXES],
    pub to_si: [f64; AXES],
}

/// The factor to SI of values in `units` (MTConnect units: MILLIMETER, INCH, DEGREE, RADIAN).
fn factor(units: &str) -> Option<f64> {
    Some(match units {
        "MILLIMETER" => 1e-3,
        "INCH" => 25.4e-3,
        "DEGREE" => std::f64::consts::PI / 180.0,
        "RADIAN" => 1.0,
        _ => return None,
    })
}

fn label(i: &DataItem) -> String {
    match (&i.name, &i.coordinate_system) {
        (Some(n), Some(c)) => format!("{} (name {n}, {c})", i.id),
        (Some(n), None) => format!("{} (name {n})", i.id),
        (None, Some(c)) => format!("{} ({c})", i.id),
        (None, None) => i.id.clone(),
    }
}

impl AxisItems {
    /// The machine axis (index) a data item carries, if any.
    pub fn axis_of(&self, id: &str) -> Option<usize> {
        self.ids.iter().position(|i| i == id)
    }

    /// Axis `i`'s value from its text, in SI: None for `UNAVAILABLE` (the source has no value), an
    /// error for what is not a finite number.
    pub fn value(&self, i: usize, text: &str) -> Result<Option<f64>, String> {
        let v = text.trim();
        if v.eq_ignore_ascii_case("UNAVAILABLE") {
            return Ok(None);
        }
        match v.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(Some(x * self.to_si[i])),
            _ => Err(format!("{} value '{}' is not a number", self.ids[i], v.chars().take(40).collect::<String>())),
        }
    }
}

/// Which units a source's values are in: an adapter sends `nativeUnits` (the agent converts them),
/// an agent answers in `units`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnitsOf {
    Adapter,
    Agent,
}

/// The data items of `device` that carry `machine`'s axes: those `axis_map` names (axis -> data
/// item id or name), else the actual POSITION (linear) or ANGLE (rotary) sample of the device's axis
/// component of the same name, in machine coordinates where it has several. Ambiguity and absence
/// are errors naming the candidates.
pub fn axis_items(device: &Device, machine: &Machine, axis_map: &BTreeMap<String, String>, source: UnitsOf) -> Result<AxisItems, String> {
    let mut ids: [String; AXES] = Default::default();
    let mut to_si = [0.0; AXES];
    for (i, axis) in machine.axes.iter().enumerate() {
        let kind = if axis.kind == AxisKind::Rotary { "ANGLE" } else { "POSITION" };
        let item = match axis_map.get(&axis.name) {
            Some(key) => {
                let item = device.item(key).ok_or_else(|| format!("axis {}: device '{}' has no data item '{key}'", axis.name, device.name))?;
                if item.kind != kind {
                    return Err(format!("axis {}: data item '{key}' is a {}, not a {kind}", axis.name, item.kind));
                }
                if item.representation.as_deref() == Some("TIME_SERIES") {
                    // Its values come in bursts whose instants the burst's rate and stamp imply: not read yet.
                    return Err(format!("axis {}: data item '{key}' is a TIME_SERIES (bursts of samples): not read yet; name its VALUE sample", axis.name));
                }
                item
            }
            None => {
                let candidates: Vec<&DataItem> = device
                    .items
                    .iter()
                    .filter(|d| d.category == "SAMPLE" && d.kind == kind && d.sub_type.as_deref().is_none_or(|s| s == "ACTUAL") && d.representation.as_deref() != Some("TIME_SERIES"))
                    .filter(|d| d.axis.as_ref().is_some_and(|(_, n)| n.eq_ignore_ascii_case(&axis.name)))
                    .collect();
                let machine_coords: Vec<&DataItem> = candidates.iter().copied().filter(|d| d.coordinate_system.as_deref() == Some("MACHINE")).collect();
                let chosen: Option<&DataItem> = match (candidates.as_slice(), machine_coords.as_slice()) {
                    ([one], _) | (_, [one]) => Some(*one),
                    _ => None,
                };
                match (chosen, candidates.as_slice()) {
                    (Some(one), _) => one,
                    (None, []) => {
                        let axes: Vec<String> = device.items.iter().filter(|d| d.kind == kind).map(label).collect();
                        return Err(format!(
                            "axis {}: device '{}' has no axis component named {} with an actual {kind}; its {kind} data items: [{}]; name one with --axis-map {}=ID",
                            axis.name,
                            device.name,
                            axis.name,
                            axes.join(", "),
                            axis.name
                        ));
                    }
                    (None, many) => {
                        return Err(format!(
                            "axis {}: device '{}' has {} actual {kind} data items for it and none alone in machine coordinates: [{}]; name one with --axis-map {}=ID",
                            axis.name,
                            device.name,
                            many.len(),
                            many.iter().map(|d| label(d)).collect::<Vec<_>>().join(", "),
                            axis.name
                        ))
                    }
                }
            }
        };
        // The adapter sends native units where the item has them (the agent converts them).
        let units = match source {
            UnitsOf::Adapter => item.native_units.as_deref().or(item.units.as_deref()),
            UnitsOf::Agent => item.units.as_deref(),
        };
        let units = units.unwrap_or(if kind == "ANGLE" { "DEGREE" } else { "MILLIMETER" });
        to_si[i] = factor(units).ok_or_else(|| format!("axis {}: data item '{}' in {units}: not a length or angle unit", axis.name, item.id))?;
        ids[i] = item.id.clone();
    }
    Ok(AxisItems { ids, to_si })
}

/// The device a log is read for: the one named, else the only one.
pub fn pick<'a>(devices: &'a [Device], name: Option<&str>) -> Result<&'a Device, String> {
    let names = || devices.iter().map(|d| d.name.clone()).collect::<Vec<_>>().join(", ");
    match name {
        Some(n) => devices.iter().find(|d| d.name == n || d.uuid.as_deref() == Some(n)).ok_or_else(|| format!("no device '{n}' in the description (devices: {})", names())),
        None if devices.len() == 1 => Ok(&devices[0]),
        None => Err(format!("the description has {} devices: name one with --mtconnect-device ({})", devices.len(), names())),
    }
}

/// Read an SHDR log: each line that reports one of the axes is handed to `visit` (a refused line as
/// an error naming it by line and column). Returns the lines read. Streamed: one line held at a time.
pub fn read_log<R: BufRead>(reader: R, devices: &[Device], device: &Device, axes: &AxisItems, mut visit: impl FnMut(Result<AxisReport, String>)) -> std::io::Result<u64> {
    let mut reader = reader;
    let reader = &mut reader;
    let mut state = shdr::ShdrReader::default();
    let mut buf = Vec::new();
    let mut line = 0u64;
    loop {
        buf.clear();
        let n = std::io::Read::take(&mut *reader, MAX_LINE as u64 + 1).read_until(b'\n', &mut buf)?;
        if n == 0 {
            return Ok(line);
        }
        line += 1;
        if buf.len() > MAX_LINE && buf.last() != Some(&b'\n') {
            visit(Err(format!("line {line}: longer than {MAX_LINE} bytes")));
            // Skip the rest of it.
            loop {
                buf.clear();
                let m = std::io::Read::take(&mut *reader, MAX_LINE as u64).read_until(b'\n', &mut buf)?;
                if m == 0 || buf.last() == Some(&b'\n') {
                    break;
                }
            }
            continue;
        }
        let text = String::from_utf8_lossy(&buf);
        let text = text.trim_end_matches(['\n', '\r']);
        match shdr_report(&mut state, text, line, devices, device, axes, None) {
            Err(e) => visit(Err(e)),
            Ok(Some(report)) => visit(Ok(report)),
            Ok(None) => {}
        }
    }
}

/// One SHDR line's axis positions (None: it reports none of the axes); `line` names it in errors and
/// in the report; `now`, the receive time, stands for an empty timestamp on a live stream.
pub fn shdr_report(state: &mut shdr::ShdrReader, text: &str, line: u64, devices: &[Device], device: &Device, axes: &AxisItems, now: Option<crate::source::Stamp>) -> Result<Option<AxisReport>, String> {
    match state.line(text, device, devices, now) {
        Err(e) => Err(format!("line {line}: {e}")),
        Ok(shdr::Line::Other) => Ok(None),
        Ok(shdr::Line::Data { stamp, observations }) => {
            let mut values = [None; AXES];
            for o in &observations {
                let Some(i) = axes.axis_of(&o.item.id) else { continue };
                values[i] = axes.value(i, o.fields[0]).map_err(|e| format!("line {line}:{}: {e}", o.col))?;
            }
            Ok(values.iter().any(Option::is_some).then_some(AxisReport { line, stamp, values }))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A TIME_SERIES position is never taken for an axis' value (its first field is a count): it is
    /// passed over when the axes are found by name, and refused when named.
    #[test]
    fn time_series_positions_are_not_misread() {
        let axes: String = ["X", "Y", "Z"]
            .iter()
            .map(|a| {
                let rep = if *a == "X" { r#"representation="TIME_SERIES" sampleRate="100""# } else { "" };
                format!(r#"<Linear id="{a}" name="{a}"><DataItems><DataItem category="SAMPLE" id="{a}ts" type="POSITION" subType="ACTUAL" units="MILLIMETER" {rep}/></DataItems></Linear>"#)
            })
            .chain(["A", "C"].iter().map(|a| format!(r#"<Rotary id="{a}" name="{a}"><DataItems><DataItem category="SAMPLE" id="{a}a" type="ANGLE" subType="ACTUAL" units="DEGREE"/></DataItems></Rotary>"#)))
            .collect();
        let xml = format!(r#"<MTConnectDevices><Devices><Device id="d" name="D"><Components><Axes id="ax">{axes}</Axes></Components></Device></Devices></MTConnectDevices>"#);
        let all = devices::parse(&xml).unwrap();
        let machine = Machine::builtin("hermle-c600u").unwrap();
        let e = axis_items(&all[0], &machine, &BTreeMap::new(), UnitsOf::Adapter).unwrap_err();
        assert!(e.starts_with("axis X: device 'D' has no axis component named X"), "{e}");
        let named = BTreeMap::from([("X".to_string(), "Xts".to_string())]);
        let e = axis_items(&all[0], &machine, &named, UnitsOf::Adapter).unwrap_err();
        assert!(e.contains("is a TIME_SERIES"), "{e}");
    }
}
