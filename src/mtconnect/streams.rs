//! An agent's `MTConnectStreams` document (the answer to `/current` and `/sample`, and each part of
//! a streamed `/sample`): its header's sequence numbers and instance, and every observation of a
//! data item with its timestamp and sequence (MTConnect Part 1, Fundamentals, "Streams Response
//! Document"; Part 3, Observation Information Model). An `MTConnectError` answer is an error with its
//! codes (e.g. `OUT_OF_RANGE` when `from` has left the agent's buffer).

use crate::source::Stamp;

/// The `Header` of a streams document: which agent run it comes from and where its buffer stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Header {
    /// Changes when the agent restarts: sequence numbers of another instance mean nothing.
    pub instance_id: u64,
    /// The sequence the next `/sample?from=` continues at.
    pub next_sequence: u64,
    pub first_sequence: u64,
    pub last_sequence: u64,
}

/// One observation (a `Samples`, `Events` or `Condition` child of a `ComponentStream`).
#[derive(Debug, Clone, PartialEq)]
pub struct Observation {
    pub data_item_id: String,
    pub stamp: Stamp,
    pub sequence: u64,
    /// The element's text (`UNAVAILABLE` when the agent has no value).
    pub value: String,
    /// Its line in the document, to name it in an error.
    pub line: u32,
}

/// A streams document, its observations in document order.
#[derive(Debug, Clone, PartialEq)]
pub struct Streams {
    pub header: Header,
    pub observations: Vec<Observation>,
}

/// Why a document was refused.
#[derive(Debug, thiserror::Error)]
pub enum StreamsError {
    #[error("XML: {0}")]
    Xml(#[from] roxmltree::Error),
    /// The agent answered with an `MTConnectError` document.
    #[error("the agent answered {}", .0.iter().map(|(c, t)| format!("{c}: {t}")).collect::<Vec<_>>().join("; "))]
    Agent(Vec<(String, String)>),
    #[error("the root element is <{0}>, not <MTConnectStreams>")]
    NotStreams(String),
    #[error("line {line}: Header attribute '{name}' missing or not an unsigned number")]
    Header { line: u32, name: &'static str },
    #[error("line {line}: <{element}> attribute '{name}' is '{text}': {why}")]
    Attribute { line: u32, element: String, name: &'static str, text: String, why: &'static str },
}

impl StreamsError {
    /// The error codes of an `MTConnectError` answer (empty for any other refusal).
    pub fn agent_codes(&self) -> Vec<&str> {
        match self {
            StreamsError::Agent(v) => v.iter().map(|(c, _)| c.as_str()).collect(),
            _ => Vec::new(),
        }
    }
}

/// The observation categories of a `ComponentStream`.
const CATEGORIES: [&str; 3] = ["Samples", "Events", "Condition"];

/// Read a streams document's text.
pub fn parse(text: &str) -> Result<Streams, StreamsError> {
    let doc = roxmltree::Document::parse(text)?;
    let root = doc.root_element();
    let line = |n: roxmltree::Node| doc.text_pos_at(n.range().start).row;
    match root.tag_name().name() {
        "MTConnectStreams" => {}
        "MTConnectError" => {
            let errors = root
                .descendants()
                .filter(|n| n.tag_name().name() == "Error")
                .map(|n| (n.attribute("errorCode").unwrap_or("").to_string(), n.text().unwrap_or("").trim().to_string()))
                .collect();
            return Err(StreamsError::Agent(errors));
        }
        other => return Err(StreamsError::NotStreams(other.to_string())),
    }
    let head = root.children().find(|n| n.tag_name().name() == "Header").ok_or(StreamsError::Header { line: line(root), name: "Header" })?;
    let number = |name: &'static str| -> Result<u64, StreamsError> { head.attribute(name).and_then(|v| v.trim().parse().ok()).ok_or(StreamsError::Header { line: line(head), name }) };
    let header = Header {
        instance_id: number("instanceId")?,
        next_sequence: number("nextSequence")?,
        first_sequence: number("firstSequence")?,
        last_sequence: number("lastSequence")?,
    };
    let mut observations = Vec::new();
    for group in root.descendants().filter(|n| CATEGORIES.contains(&n.tag_name().name()) && n.parent().is_some_and(|p| p.tag_name().name() == "ComponentStream")) {
        for o in group.children().filter(|n| n.is_element()) {
            let element = o.tag_name().name();
            let attr = |name: &'static str| -> Result<&str, StreamsError> {
                o.attribute(name).ok_or_else(|| StreamsError::Attribute { line: line(o), element: element.to_string(), name, text: String::new(), why: "missing" })
            };
            let id = attr("dataItemId")?;
            let stamp_text = attr("timestamp")?;
            let stamp = Stamp::parse(stamp_text.trim())
                .ok_or_else(|| StreamsError::Attribute { line: line(o), element: element.to_string(), name: "timestamp", text: stamp_text.to_string(), why: "not an ISO 8601 UTC timestamp" })?;
            let seq_text = attr("sequence")?;
            let sequence = seq_text
                .trim()
                .parse()
                .map_err(|_| StreamsError::Attribute { line: line(o), element: element.to_string(), name: "sequence", text: seq_text.to_string(), why: "not an unsigned number" })?;
            // A condition's state is its element (Normal, Warning, Fault, Unavailable).
            let value = if group.tag_name().name() == "Condition" { element.to_string() } else { o.text().unwrap_or("").trim().to_string() };
            observations.push(Observation { data_item_id: id.to_string(), stamp, sequence, value, line: line(o) });
        }
    }
    Ok(Streams { header, observations })
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOC: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<MTConnectStreams xmlns="urn:mtconnect.org:MTConnectStreams:2.0">
  <Header creationTime="2026-01-01T00:00:01Z" sender="a" instanceId="1700000000" version="2.0" bufferSize="131072" nextSequence="45" firstSequence="1" lastSequence="44"/>
  <Streams>
    <DeviceStream name="C600U" uuid="u">
      <ComponentStream component="Linear" name="X" componentId="x">
        <Samples>
          <Position dataItemId="x_act" timestamp="2026-01-01T00:00:00.250Z" sequence="40" subType="ACTUAL">12.5</Position>
          <Position dataItemId="x_act" timestamp="2026-01-01T00:00:00.500Z" sequence="43" subType="ACTUAL">UNAVAILABLE</Position>
        </Samples>
        <Condition><Normal dataItemId="x_travel" timestamp="2026-01-01T00:00:00Z" sequence="2" type="POSITION"/></Condition>
      </ComponentStream>
    </DeviceStream>
  </Streams>
</MTConnectStreams>"#;

    #[test]
    fn a_sample_answer() {
        let s = parse(DOC).unwrap();
        assert_eq!(s.header, Header { instance_id: 1_700_000_000, next_sequence: 45, first_sequence: 1, last_sequence: 44 });
        assert_eq!(s.observations.len(), 3);
        assert_eq!((s.observations[0].data_item_id.as_str(), s.observations[0].value.as_str(), s.observations[0].sequence), ("x_act", "12.5", 40));
        assert_eq!(s.observations[0].stamp, Stamp { sec: 1_767_225_600, nanosec: 250_000_000 });
        assert_eq!(s.observations[1].value, "UNAVAILABLE");
        assert_eq!(s.observations[2].value, "Normal");
    }

    #[test]
    fn refusals_name_where() {
        let e = parse(&DOC.replace("sequence=\"43\"", "sequence=\"-3\"")).unwrap_err();
        assert_eq!(e.to_string(), "line 9: <Position> attribute 'sequence' is '-3': not an unsigned number");
        let e = parse(&DOC.replace("nextSequence=\"45\"", "")).unwrap_err();
        assert!(e.to_string().contains("'nextSequence'"), "{e}");
        let err = r#"<MTConnectError><Header instanceId="1"/><Errors><Error errorCode="OUT_OF_RANGE">'from' must be greater than 10</Error></Errors></MTConnectError>"#;
        let e = parse(err).unwrap_err();
        assert_eq!(e.agent_codes(), ["OUT_OF_RANGE"]);
    }
}
