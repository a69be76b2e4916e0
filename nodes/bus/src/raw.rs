//! Raw subscriptions: a topic's serialized messages as they arrived, of any type, for the recorder
//! (rosbag2 stores the bytes received, and `--all` records types we have no definition of).
//!
//! ros2-client's subscriptions always deserialize, so these readers are made on its DDS participant
//! with a RustDDS adapter that keeps the payload. DDS discovery lists them like any reader, but
//! ros2-client has no way to add them to the node's `ros_discovery_info` entry, so `ros2 node info`
//! does not show them. (A second, never-read ros2-client subscription per topic would list them, but
//! publishers would count it as a subscriber: `--min-subscribers` would start too early.)

use ros2_client::dds::rustdds::{
    self,
    no_key::{Decode, DefaultDecoder, DeserializerAdapter, SimpleDataReader},
    RepresentationIdentifier,
};
use ros2_client::{MessageTypeName, QosProfile};

/// One message as received: the CDR encapsulation header (representation identifier and zero
/// options; RustDDS passes the identifier on but not the option bytes) followed by the payload.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RawSample(pub Vec<u8>);

/// The encodings kept: every plain and parameter-list CDR flavour ROS 2 middlewares write.
const ENCODINGS: [RepresentationIdentifier; 8] = [
    RepresentationIdentifier::CDR_LE,
    RepresentationIdentifier::CDR_BE,
    RepresentationIdentifier::PL_CDR_LE,
    RepresentationIdentifier::PL_CDR_BE,
    RepresentationIdentifier::CDR2_LE,
    RepresentationIdentifier::CDR2_BE,
    RepresentationIdentifier::D_CDR2_LE,
    RepresentationIdentifier::D_CDR2_BE,
];

/// The RustDDS adapter that keeps the bytes.
pub struct RawAdapter;

/// Its decoder: a copy of the payload behind a rebuilt encapsulation header.
#[derive(Clone, Copy)]
pub struct RawDecoder;

impl<'de> Decode<'de, RawSample> for RawDecoder {
    type Error = std::convert::Infallible;
    fn decode_bytes(self, input_bytes: &'de [u8], encoding: RepresentationIdentifier) -> Result<RawSample, Self::Error> {
        let mut data = Vec::with_capacity(4 + input_bytes.len());
        data.extend_from_slice(&encoding.to_bytes());
        data.extend_from_slice(&[0, 0]);
        data.extend_from_slice(input_bytes);
        Ok(RawSample(data))
    }
}

impl DeserializerAdapter<RawSample> for RawAdapter {
    type Error = std::convert::Infallible;
    type Decoded = RawSample;
    fn supported_encodings() -> &'static [RepresentationIdentifier] {
        &ENCODINGS
    }
    fn transform_decoded(decoded: RawSample) -> RawSample {
        decoded
    }
}

impl DefaultDecoder<RawSample> for RawAdapter {
    type Decoder = RawDecoder;
    const DECODER: RawDecoder = RawDecoder;
}

/// A raw reader of one topic.
pub struct RawSubscription {
    reader: SimpleDataReader<RawSample, RawAdapter>,
}

/// A message taken from a [`RawSubscription`]: its bytes and the writer's send time (DDS source
/// timestamp), ns since the Unix epoch, when the writer gave one.
pub struct RawMessage {
    pub data: Vec<u8>,
    pub sent_ns: Option<u64>,
}

impl RawSubscription {
    /// The next message (waits for it).
    pub async fn take(&self) -> anyhow::Result<RawMessage> {
        use smol::stream::StreamExt as _;
        let stream = self.reader.as_async_stream();
        let mut stream = std::pin::pin!(stream);
        match stream.next().await {
            Some(Ok(dcc)) => {
                let sent_ns = dcc.source_timestamp().map(timestamp_ns);
                Ok(RawMessage { data: dcc.into_value().0, sent_ns })
            }
            Some(Err(e)) => Err(anyhow::anyhow!("read error: {e:?}")),
            None => Err(anyhow::anyhow!("the reader closed")),
        }
    }
}

/// RTPS time (seconds and 2^-32 fractions since the Unix epoch) in ns.
fn timestamp_ns(t: rustdds::Timestamp) -> u64 {
    let ticks = t.to_ticks();
    (ticks >> 32) * 1_000_000_000 + (((ticks & 0xFFFF_FFFF) * 1_000_000_000) >> 32)
}

/// The DDS type name of a ROS type `pkg/msg/Type` (`pkg::msg::dds_::Type_`); a name in any other
/// form is taken as a DDS type name already.
pub fn dds_type_name(ros_type: &str) -> String {
    let parts: Vec<&str> = ros_type.split('/').collect();
    match parts.as_slice() {
        [pkg, "msg", name] => MessageTypeName::new(pkg, name).dds_msg_type(),
        _ => ros_type.to_string(),
    }
}

/// The ROS type `pkg/msg/Type` of a DDS type name `pkg::msg::dds_::Type_`, as `ros2 bag` names it;
/// `None` for a type that is not a ROS message type.
pub fn ros_type_name(dds_type: &str) -> Option<String> {
    let parts: Vec<&str> = dds_type.split("::").collect();
    match parts.as_slice() {
        [pkg, kind, "dds_", name] if !pkg.is_empty() && name.len() > 1 => Some(format!("{pkg}/{kind}/{}", name.strip_suffix('_')?)),
        _ => None,
    }
}

impl crate::Bus {
    /// A raw reader of `topic` (resolved like any topic of the node) whose DDS type is `dds_type`.
    pub fn raw_subscription(&mut self, topic: &str, dds_type: &str, qos: &QosProfile) -> anyhow::Result<RawSubscription> {
        let full = self.resolve(topic);
        let dds_qos = rustdds::QosPolicies::from(qos);
        let participant = self.context().domain_participant();
        let dds_topic = participant
            .create_topic(format!("rt{full}"), dds_type.to_string(), &dds_qos, rustdds::TopicKind::NoKey)
            .map_err(|e| anyhow::anyhow!("topic {full} ({dds_type}): {e:?}"))?;
        let subscriber = participant.create_subscriber(&dds_qos).map_err(|e| anyhow::anyhow!("subscriber for {full}: {e:?}"))?;
        let reader = subscriber
            .create_simple_datareader_no_key::<RawSample, RawAdapter>(&dds_topic, Some(dds_qos))
            .map_err(|e| anyhow::anyhow!("raw reader of {full}: {e:?}"))?;
        Ok(RawSubscription { reader })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn type_names_both_ways() {
        assert_eq!(dds_type_name("sensor_msgs/msg/JointState"), "sensor_msgs::msg::dds_::JointState_");
        assert_eq!(ros_type_name("sensor_msgs::msg::dds_::JointState_").as_deref(), Some("sensor_msgs/msg/JointState"));
        assert_eq!(ros_type_name("rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_").as_deref(), Some("rmw_dds_common/msg/ParticipantEntitiesInfo"));
        assert_eq!(ros_type_name("DDS::ParticipantBuiltinTopicData"), None);
        assert_eq!(dds_type_name("Plain"), "Plain");
    }

    #[test]
    fn rtps_time_in_ns() {
        // 1.5 s: fraction 2^31.
        assert_eq!(timestamp_ns(rustdds::Timestamp::from_ticks((1u64 << 32) | (1u64 << 31))), 1_500_000_000);
    }
}
