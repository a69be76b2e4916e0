//! The Zenoh session settings every fleet command takes: a configuration file (TLS, access control,
//! as Zenoh's own DEFAULT_CONFIG.json5 documents them) and the endpoints to listen on and connect to.

use anyhow::Context as _;
use std::path::PathBuf;

#[derive(Debug, Clone, clap::Args)]
pub struct ZenohArgs {
    /// A Zenoh configuration file (JSON5): TLS certificates, access control, timeouts. The command
    /// sets its mode, the endpoints given below, no multicast scouting and endless connect retries.
    #[arg(long = "zenoh-config", value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Listen on this endpoint, e.g. `tcp/10.0.1.1:7447` or `tls/10.0.1.1:7448` (repeatable).
    #[arg(long = "listen", value_name = "ENDPOINT")]
    pub listen: Vec<String>,
    /// Connect to this endpoint, e.g. a site router's `tcp/10.0.1.1:7447` (repeatable).
    #[arg(long = "connect", value_name = "ENDPOINT")]
    pub connect: Vec<String>,
    /// ROS domain id on the fleet network: the first chunk of every key, as rmw_zenoh writes it.
    #[arg(long = "fleet-domain", default_value_t = 0)]
    pub domain: u16,
}

impl ZenohArgs {
    /// The session configuration for `mode` (`client`, `router`), over the file's. Multicast
    /// scouting is off: a fleet is joined by its named endpoints, never by what a LAN answers. A
    /// session starts whether or not its router is up yet, and reconnects when a link returns.
    pub fn config(&self, mode: &str) -> anyhow::Result<zenoh::Config> {
        let mut c = match &self.config {
            Some(path) => zenoh::Config::from_file(path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?,
            None => zenoh::Config::default(),
        };
        let mut set = |key: &str, value: String| c.insert_json5(key, &value).map_err(|e| anyhow::anyhow!("{key} = {value}: {e}"));
        set("mode", format!("\"{mode}\""))?;
        if !self.listen.is_empty() {
            set("listen/endpoints", serde_json::to_string(&self.listen)?).context("--listen")?;
        }
        if !self.connect.is_empty() {
            set("connect/endpoints", serde_json::to_string(&self.connect)?).context("--connect")?;
        }
        set("scouting/multicast/enabled", "false".into())?;
        set("connect/exit_on_failure", "false".into())?;
        set("connect/timeout_ms", "-1".into())?;
        Ok(c)
    }
}
