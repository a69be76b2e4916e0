//! Where a machine's topics live on the fleet's Zenoh network: the one rule for a machine's namespace
//! (`/site/cell/machine`) and the key expressions rmw_zenoh gives its topics
//! (`<domain>/<topic name without its leading '/'>/<DDS type name>/<type hash>`, rmw_zenoh's
//! design.md, "Topic key expressions"), so that `ros2 topic echo` on rmw_zenoh reads them.

use fiveaxis::topics::Topic;
use thiserror::Error;

/// A name the fleet cannot place.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum KeyError {
    #[error("{what} '{name}': a ROS name token is a letter or '_' then letters, digits and '_' (REP 144)")]
    Token { what: &'static str, name: String },
    #[error("machine namespace '{0}': expected /SITE/CELL/MACHINE")]
    Namespace(String),
}

/// A machine's place in the shop: its site, cell and name, each a ROS name token.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct MachinePath {
    pub site: String,
    pub cell: String,
    pub machine: String,
}

fn token(what: &'static str, name: &str) -> Result<String, KeyError> {
    let mut chars = name.chars();
    let ok = matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_') && chars.all(|c| c.is_ascii_alphanumeric() || c == '_');
    if ok {
        Ok(name.to_string())
    } else {
        Err(KeyError::Token { what, name: name.to_string() })
    }
}

impl MachinePath {
    pub fn new(site: &str, cell: &str, machine: &str) -> Result<MachinePath, KeyError> {
        Ok(MachinePath { site: token("site", site)?, cell: token("cell", cell)?, machine: token("machine", machine)? })
    }

    /// From `/site/cell/machine`.
    pub fn parse(namespace: &str) -> Result<MachinePath, KeyError> {
        let parts: Vec<&str> = namespace.strip_prefix('/').unwrap_or(namespace).split('/').collect();
        match parts.as_slice() {
            [s, c, m] => MachinePath::new(s, c, m),
            _ => Err(KeyError::Namespace(namespace.to_string())),
        }
    }

    /// `/site/cell/machine`: the namespace of the machine's topics on the fleet network.
    pub fn namespace(&self) -> String {
        format!("/{}/{}/{}", self.site, self.cell, self.machine)
    }

    /// A node-set topic under the machine's namespace: `/site/cell/m/fiveaxis/monitor/status`, and
    /// the ROS-wide `/diagnostics` as `/site/cell/m/diagnostics`.
    pub fn topic(&self, topic: &Topic) -> String {
        format!("{}{}", self.namespace(), topic.absolute)
    }
}

impl std::fmt::Display for MachinePath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.namespace())
    }
}

/// The DDS form of a ROS type name, as rmw_zenoh writes it in keys: `fiveaxis_msgs::msg::dds_::Region_`.
pub fn dds_type(package: &str, name: &str) -> String {
    format!("{package}::msg::dds_::{name}_")
}

/// The key expression that matches `topic` of type `package/name` on every machine of the domain:
/// `0/*/*/*/fiveaxis/monitor/status/fiveaxis_msgs::msg::dds_::SingularityStatus_/*` (any type hash).
pub fn every_machine(domain: u16, topic: &Topic, package: &str, name: &str) -> String {
    format!("{domain}/*/*/*{}/{}/*", topic.absolute, dds_type(package, name))
}

/// The machine whose `topic` a data key belongs to (the inverse of [`every_machine`]'s match).
pub fn machine_of(key: &str, domain: u16, topic: &Topic) -> Option<MachinePath> {
    let rest = key.strip_prefix(&format!("{domain}/"))?;
    let (site, rest) = rest.split_once('/')?;
    let (cell, rest) = rest.split_once('/')?;
    let (machine, rest) = rest.split_once('/')?;
    let after = rest.strip_prefix(topic.absolute.trim_start_matches('/'))?;
    // Then exactly `/type/hash`.
    let parts: Vec<&str> = after.strip_prefix('/')?.split('/').collect();
    if parts.len() != 2 {
        return None;
    }
    MachinePath::new(site, cell, machine).ok()
}

/// The key of a gateway's regions of this shift, answered to catch up after a link outage. Outside
/// the ROS key space (it is no topic): `fiveaxis_fleet/0/site/cell/machine/regions`.
pub fn regions_query(domain: u16, path: &MachinePath) -> String {
    format!("fiveaxis_fleet/{domain}{}/regions", path.namespace())
}

/// Every gateway's regions key, for a view that asks them all.
pub fn every_regions_query(domain: u16) -> String {
    format!("fiveaxis_fleet/{domain}/*/*/*/regions")
}

/// The machine of a regions key.
pub fn machine_of_regions(key: &str, domain: u16) -> Option<MachinePath> {
    let rest = key.strip_prefix(&format!("fiveaxis_fleet/{domain}/"))?.strip_suffix("/regions")?;
    MachinePath::parse(rest).ok()
}

/// What an rmw_zenoh message attachment says of its sending: the publisher's sequence number, its
/// source stamp (ns since the UNIX epoch) and the publisher's gid, which a restarted publisher
/// changes (its sequence starts anew).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sent {
    pub seq: i64,
    pub stamp_ns: i64,
    pub gid: [u8; 16],
}

/// An rmw_zenoh message attachment: `seq: i64 LE | source_timestamp: i64 LE | 0x10 | gid: 16
/// bytes` (rmw_zenoh's design.md, "Publishers": the attachment; 33 bytes).
pub fn attachment(bytes: &[u8]) -> Option<Sent> {
    if bytes.len() != 33 || bytes[16] != 16 {
        return None;
    }
    let seq = i64::from_le_bytes(bytes[0..8].try_into().ok()?);
    let stamp_ns = i64::from_le_bytes(bytes[8..16].try_into().ok()?);
    let gid = bytes[17..33].try_into().ok()?;
    Some(Sent { seq, stamp_ns, gid })
}

#[cfg(test)]
mod tests {
    use super::*;
    use fiveaxis::topics;

    #[test]
    fn names_are_ros_tokens() {
        assert!(MachinePath::new("plant_1", "cell_a", "c600u").is_ok());
        for bad in ["", "1cell", "cell-a", "a/b", "a*", "a b"] {
            assert!(MachinePath::new("s", bad, "m").is_err(), "{bad}");
        }
        assert_eq!(MachinePath::parse("/s/c/m").unwrap().namespace(), "/s/c/m");
        assert!(MachinePath::parse("/s/c").is_err());
        assert!(MachinePath::parse("/s/c/m/x").is_err());
    }

    #[test]
    fn keys_follow_rmw_zenohs_mapping_and_parse_back() {
        let p = MachinePath::new("plant", "cell_a", "hermle").unwrap();
        assert_eq!(p.topic(&topics::STATUS), "/plant/cell_a/hermle/fiveaxis/monitor/status");
        assert_eq!(p.topic(&topics::DIAGNOSTICS), "/plant/cell_a/hermle/diagnostics");
        let key = format!("0/plant/cell_a/hermle/fiveaxis/monitor/status/{}/RIHS01_00", dds_type("fiveaxis_msgs", "SingularityStatus"));
        assert_eq!(machine_of(&key, 0, &topics::STATUS), Some(p.clone()));
        assert_eq!(machine_of(&key, 1, &topics::STATUS), None);
        assert_eq!(machine_of(&key, 0, &topics::REGIONS), None);
        assert_eq!(every_machine(0, &topics::STATUS, "fiveaxis_msgs", "SingularityStatus"), "0/*/*/*/fiveaxis/monitor/status/fiveaxis_msgs::msg::dds_::SingularityStatus_/*");
        assert_eq!(machine_of_regions(&regions_query(0, &p), 0), Some(p));
    }

    #[test]
    fn attachments_read_as_rmw_zenoh_writes_them() {
        let mut b = Vec::new();
        b.extend_from_slice(&7i64.to_le_bytes());
        b.extend_from_slice(&1_700_000_000_123_456_789i64.to_le_bytes());
        b.push(16);
        b.extend_from_slice(&[0xab; 16]);
        assert_eq!(attachment(&b), Some(Sent { seq: 7, stamp_ns: 1_700_000_000_123_456_789, gid: [0xab; 16] }));
        assert_eq!(attachment(&b[..32]), None);
        b[16] = 15;
        assert_eq!(attachment(&b), None);
    }
}
