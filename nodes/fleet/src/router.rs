//! `fiveaxis-fleet router`: a Zenoh router of the fleet network, a site's (its cells' gateways
//! connect to it) or the head office's (the sites' routers connect to it, the view too). Routers
//! forward only what a subscriber downstream asks for; access control comes from `--zenoh-config`.

use crate::zenoh_args::ZenohArgs;
use std::time::{Duration, Instant};
use zenoh::Wait;

#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    zenoh: ZenohArgs,
    /// Stop after this long, s (default: until SIGINT or SIGTERM).
    #[arg(long = "duration-s")]
    duration_s: Option<f64>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let shutdown = fiveaxis_bus::Shutdown::install()?;
    let config = args.zenoh.config("router")?;
    let session = zenoh::open(config).wait().map_err(|e| anyhow::anyhow!("opening the router: {e}"))?;
    tracing::info!(zid = %session.zid(), listen = ?args.zenoh.listen, connect = ?args.zenoh.connect, "fleet router up");
    let start = Instant::now();
    while !shutdown.requested() && !args.duration_s.is_some_and(|d| start.elapsed().as_secs_f64() >= d) {
        std::thread::sleep(Duration::from_millis(100));
    }
    let _ = session.close().wait();
    Ok(())
}
