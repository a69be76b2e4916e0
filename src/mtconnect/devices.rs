//! An MTConnect device description (`MTConnectDevices`: an agent's `/probe` answer, or the
//! `Devices.xml` it serves): each device's data items with what a reader of their values needs,
//! their category, type, representation and units (MTConnect Part 2, Devices Information Model),
//! and the axis component each belongs to.

use std::collections::BTreeMap;

/// One `DataItem`.
#[derive(Debug, Clone, PartialEq)]
pub struct DataItem {
    pub id: String,
    pub name: Option<String>,
    /// SAMPLE, EVENT or CONDITION.
    pub category: String,
    /// `type` (POSITION, ANGLE, MESSAGE, ...), `subType` (ACTUAL, COMMANDED, ...), `representation`.
    pub kind: String,
    pub sub_type: Option<String>,
    pub representation: Option<String>,
    /// `units` (what the agent reports) and `nativeUnits` (what the adapter sends, converted by the
    /// agent unless the adapter says it converted them itself).
    pub units: Option<String>,
    pub native_units: Option<String>,
    /// The coordinate system the position is in: a `coordinateSystemIdRef`'s `CoordinateSystem` type
    /// (MACHINE, WORK, ...), or the legacy `coordinateSystem` attribute.
    pub coordinate_system: Option<String>,
    /// The `Linear` or `Rotary` axis component it belongs to: (element, its `name`).
    pub axis: Option<(String, String)>,
}

impl DataItem {
    /// Fields an SHDR line gives this item after its key (cppagent's Adapter Agent Protocol): a
    /// condition five (level, native code, native severity, qualifier, message), a message two
    /// (native code, text), a legacy alarm four, a time series three (count, rate, values), any
    /// other one.
    pub fn shdr_fields(&self) -> usize {
        if self.category == "CONDITION" {
            5
        } else if self.kind == "MESSAGE" {
            2
        } else if self.kind == "ALARM" {
            4
        } else if self.representation.as_deref() == Some("TIME_SERIES") {
            3
        } else {
            1
        }
    }
}

/// One `Device`.
#[derive(Debug, Clone, PartialEq)]
pub struct Device {
    pub name: String,
    pub uuid: Option<String>,
    pub items: Vec<DataItem>,
    /// Data item by SHDR key: its id and its name.
    keys: BTreeMap<String, usize>,
}

impl Device {
    /// The data item an SHDR key names (its id or its name, as the agent maps keys).
    pub fn item(&self, key: &str) -> Option<&DataItem> {
        self.keys.get(key).map(|&k| &self.items[k])
    }
}

/// Why a device description was refused.
#[derive(Debug, thiserror::Error)]
pub enum DevicesError {
    #[error("XML: {0}")]
    Xml(#[from] roxmltree::Error),
    #[error("the root element is <{0}>, not <MTConnectDevices>")]
    NotDevices(String),
    #[error("line {line}: a DataItem without an id")]
    NoId { line: u32 },
    #[error("no <Device> in the description")]
    Empty,
}

/// Read a device description's text.
pub fn parse(text: &str) -> Result<Vec<Device>, DevicesError> {
    let doc = roxmltree::Document::parse(text)?;
    let root = doc.root_element();
    if root.tag_name().name() != "MTConnectDevices" {
        return Err(DevicesError::NotDevices(root.tag_name().name().to_string()));
    }
    // Coordinate systems by id, for `coordinateSystemIdRef`.
    let systems: BTreeMap<&str, &str> = root
        .descendants()
        .filter(|n| n.tag_name().name() == "CoordinateSystem")
        .filter_map(|n| Some((n.attribute("id")?, n.attribute("type")?)))
        .collect();
    let mut devices = Vec::new();
    for dev in root.descendants().filter(|n| n.tag_name().name() == "Device") {
        let mut items = Vec::new();
        let mut keys = BTreeMap::new();
        for di in dev.descendants().filter(|n| n.tag_name().name() == "DataItem") {
            let line = doc.text_pos_at(di.range().start).row;
            let id = di.attribute("id").ok_or(DevicesError::NoId { line })?.to_string();
            let axis = di.ancestors().find(|a| matches!(a.tag_name().name(), "Linear" | "Rotary")).map(|a| (a.tag_name().name().to_string(), a.attribute("name").unwrap_or("").to_string()));
            let coordinate_system = di
                .attribute("coordinateSystemIdRef")
                .map(|r| systems.get(r).map_or(r.to_string(), |t| t.to_string()))
                .or_else(|| di.attribute("coordinateSystem").map(str::to_string));
            let item = DataItem {
                id: id.clone(),
                name: di.attribute("name").map(str::to_string),
                category: di.attribute("category").unwrap_or("").to_string(),
                kind: di.attribute("type").unwrap_or("").to_string(),
                sub_type: di.attribute("subType").map(str::to_string),
                representation: di.attribute("representation").map(str::to_string),
                units: di.attribute("units").map(str::to_string),
                native_units: di.attribute("nativeUnits").map(str::to_string),
                coordinate_system,
                axis,
            };
            keys.insert(id, items.len());
            if let Some(n) = &item.name {
                keys.entry(n.clone()).or_insert(items.len());
            }
            items.push(item);
        }
        devices.push(Device { name: dev.attribute("name").unwrap_or("").to_string(), uuid: dev.attribute("uuid").map(str::to_string), items, keys });
    }
    if devices.is_empty() {
        return Err(DevicesError::Empty);
    }
    Ok(devices)
}
