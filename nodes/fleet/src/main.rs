//! `fiveaxis-fleet`: a shop's fleet over Zenoh (issue 67). Each cell stays on DDS; `gateway` (one
//! per machine, in its cell) forwards the machine's monitor under `/site/cell/machine` to the
//! fleet's Zenoh network; `router` joins cells, sites and the head office; `view` (at the head
//! office) shows every machine it hears, records them and catches up on regions after an outage.
//! Exit 2 on bad input (a name, an endpoint, a Zenoh configuration file), with the reason.

mod gateway;
mod rerun_out;
mod router;
mod view;
mod zenoh_args;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "fiveaxis-fleet", version, about = "A shop's fleet over Zenoh: gateway (per machine), router (per site and office), view (head office)")]
struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Forward one machine's monitor from its cell's DDS domain to the fleet network.
    Gateway(gateway::Args),
    /// A Zenoh router of the fleet network (a site's, or the head office's).
    Router(router::Args),
    /// The head office's view of every machine on the fleet network.
    View(view::Args),
}

fn main() {
    let (args, ros) = fiveaxis_bus::ros_args::parse::<Args>("fiveaxis_fleet");
    fiveaxis_bus::init_tracing(&ros);
    let done = match args.command {
        Command::Gateway(a) => gateway::run(a, &ros),
        Command::Router(a) => router::run(a),
        Command::View(a) => view::run(a),
    };
    if let Err(e) = done {
        eprintln!("fiveaxis-fleet: {e:#}");
        std::process::exit(2);
    }
}
