//! The DDS participant the ROS 2 environment asks for: domain, discovery range, DDS Security.

use crate::security;
use anyhow::{bail, Context as _};
use ros2_client::dds::{rustdds, Context};

/// Which peers discovery may reach, from the ROS 2 environment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DiscoveryRange {
    /// Only this host (loopback).
    Localhost,
    /// The local networks (the DDS default).
    Subnet,
    /// No discovery beyond this process.
    Off,
}

/// The participant settings the ROS 2 environment asks for: `(domain id, range)`.
pub fn ros_environment(get: impl Fn(&str) -> Option<String>) -> anyhow::Result<(u16, DiscoveryRange)> {
    let domain = match get("ROS_DOMAIN_ID").map(|s| s.trim().to_string()).filter(|s| !s.is_empty()) {
        None => 0,
        Some(s) => match s.parse::<u16>() {
            Ok(d) if d <= 232 => d,
            _ => bail!("ROS_DOMAIN_ID must be a number from 0 to 232, got '{s}'"),
        },
    };
    let range = match get("ROS_AUTOMATIC_DISCOVERY_RANGE").map(|s| s.trim().to_ascii_uppercase()).filter(|s| !s.is_empty()) {
        Some(r) => match r.as_str() {
            "LOCALHOST" => DiscoveryRange::Localhost,
            "SUBNET" | "SYSTEM_DEFAULT" => DiscoveryRange::Subnet,
            "OFF" => DiscoveryRange::Off,
            _ => bail!("ROS_AUTOMATIC_DISCOVERY_RANGE must be OFF, LOCALHOST, SUBNET or SYSTEM_DEFAULT, got '{r}'"),
        },
        None if get("ROS_LOCALHOST_ONLY").is_some_and(|v| v.trim() == "1") => DiscoveryRange::Localhost,
        None => DiscoveryRange::Subnet,
    };
    Ok((domain, range))
}

/// What the ROS 2 environment asks of the participant: domain, discovery range, DDS Security.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParticipantSettings {
    pub domain: u16,
    pub range: DiscoveryRange,
    pub security: security::Security,
}

/// Read the participant's settings from the environment, the DDS Security enclave being `enclave`
/// (`--enclave`) when `ROS_SECURITY_ENABLE=true` ([`security`]). An error is bad input (exit 2).
pub fn participant_settings(enclave: Option<&str>) -> anyhow::Result<ParticipantSettings> {
    let (domain, range) = ros_environment(|k| std::env::var(k).ok())?;
    let security = security::from_env(|k| std::env::var(k).ok(), enclave).context("DDS Security")?;
    Ok(ParticipantSettings { domain, range, security })
}

/// A ROS 2 context with these settings.
pub fn context_with(settings: &ParticipantSettings) -> anyhow::Result<Context> {
    let ParticipantSettings { domain, range, security } = settings;
    let mut builder = rustdds::DomainParticipantBuilder::new(*domain);
    match security {
        security::Security::Off => {}
        security::Security::Permissive(why) => tracing::warn!("DDS Security asked for but not used (ROS_SECURITY_STRATEGY is not Enforce): {why}"),
        security::Security::Enclave(dir) => {
            tracing::info!(enclave = %dir.display(), "DDS Security: authenticating with the enclave");
            builder = builder.builtin_security(rustdds::DomainParticipantSecurityConfigFiles::with_ros_default_names(dir, String::new()));
        }
    }
    let builder = match range {
        DiscoveryRange::Localhost => builder.with_only_networks([std::net::IpAddr::from([127, 0, 0, 1])]),
        // OFF: no interface is advertised or joined; only same-host loopback peers remain reachable.
        DiscoveryRange::Off => builder.with_only_networks(Vec::<std::net::IpAddr>::new()),
        DiscoveryRange::Subnet => builder,
    };
    let participant = builder.build().context("creating the DDS participant")?;
    tracing::info!(domain, ?range, secured = matches!(security, security::Security::Enclave(_)), "DDS participant");
    Context::from_domain_participant(participant).context("creating the ROS 2 context")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn environment() {
        let env = |pairs: &'static [(&'static str, &'static str)]| move |k: &str| pairs.iter().find(|(a, _)| *a == k).map(|(_, v)| v.to_string());
        assert_eq!(ros_environment(env(&[])).unwrap(), (0, DiscoveryRange::Subnet));
        assert_eq!(ros_environment(env(&[("ROS_DOMAIN_ID", "42")])).unwrap().0, 42);
        assert!(ros_environment(env(&[("ROS_DOMAIN_ID", "300")])).is_err());
        assert!(ros_environment(env(&[("ROS_DOMAIN_ID", "x")])).is_err());
        assert_eq!(ros_environment(env(&[("ROS_LOCALHOST_ONLY", "1")])).unwrap().1, DiscoveryRange::Localhost);
        // The newer variable wins over the older one.
        assert_eq!(
            ros_environment(env(&[("ROS_LOCALHOST_ONLY", "1"), ("ROS_AUTOMATIC_DISCOVERY_RANGE", "SUBNET")])).unwrap().1,
            DiscoveryRange::Subnet
        );
        assert_eq!(ros_environment(env(&[("ROS_AUTOMATIC_DISCOVERY_RANGE", "localhost")])).unwrap().1, DiscoveryRange::Localhost);
        assert!(ros_environment(env(&[("ROS_AUTOMATIC_DISCOVERY_RANGE", "MOON")])).is_err());
    }
}
