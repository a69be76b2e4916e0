//! The fleet view in one Rerun viewer (or an `.rrd` file): an entity tree per machine,
//! `/fleet/SITE/CELL/MACHINE/...`, with its distance to the singularity (deg) and C demand (rpm) as
//! time series, its state as a text log when it changes, and its regions as text logs; the timeline
//! is the seconds since the view started (`time`, as the node set's Rerun bridge names it).

use fiveaxis::scene::TIMELINE_TIME;
use fiveaxis_fleet::fleet::{Event, Level, Row};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Where the view's Rerun stream goes.
#[derive(Debug, Clone, clap::Args)]
pub struct RerunArgs {
    /// Save the fleet's Rerun stream to this .rrd file.
    #[arg(long = "rrd", value_name = "FILE.rrd", conflicts_with = "rerun_connect")]
    pub rrd: Option<PathBuf>,
    /// Stream the fleet to a running Rerun viewer at this URL (e.g. rerun+http://127.0.0.1:9876/proxy).
    #[arg(long = "rerun-connect", value_name = "URL")]
    pub rerun_connect: Option<String>,
}

pub struct FleetRerun {
    rec: rerun::RecordingStream,
    styled: std::collections::BTreeSet<String>,
    state: BTreeMap<String, Level>,
}

fn entity(machine: &str, leaf: &str) -> String {
    format!("fleet{machine}/{leaf}")
}

impl FleetRerun {
    /// The stream `args` asks for, if any.
    pub fn open(args: &RerunArgs) -> anyhow::Result<Option<FleetRerun>> {
        let builder = rerun::RecordingStreamBuilder::new("fiveaxis_fleet").recording_name("fleet");
        let rec = match (&args.rrd, &args.rerun_connect) {
            (Some(path), _) => builder.save(path).map_err(|e| anyhow::anyhow!("creating {}: {e}", path.display()))?,
            (None, Some(url)) => builder.connect_grpc_opts(url.clone()).map_err(|e| anyhow::anyhow!("connecting to a Rerun viewer at {url}: {e}"))?,
            (None, None) => return Ok(None),
        };
        Ok(Some(FleetRerun { rec, styled: Default::default(), state: BTreeMap::new() }))
    }

    fn scalar(&mut self, machine: &str, leaf: &str, label: &str, v: Option<f64>) -> anyhow::Result<()> {
        let Some(v) = v.filter(|v| v.is_finite()) else { return Ok(()) };
        let path = entity(machine, leaf);
        if self.styled.insert(path.clone()) {
            self.rec.log_static(path.as_str(), &rerun::SeriesLines::new().with_names([label]))?;
        }
        self.rec.log(path.as_str(), &rerun::Scalars::new([v]))?;
        Ok(())
    }

    /// Each machine's line at `t_s` seconds since the view started.
    pub fn rows(&mut self, t_s: f64, rows: &[Row]) -> anyhow::Result<()> {
        self.rec.set_duration_secs(TIMELINE_TIME, t_s);
        for r in rows {
            self.scalar(&r.machine, "distance_deg", "distance to the singularity (deg)", r.distance_deg)?;
            self.scalar(&r.machine, "c_demand_rpm", "C speed the path asks (rpm)", r.c_demand_rpm.map(f64::abs))?;
            if self.state.insert(r.machine.clone(), r.state) != Some(r.state) {
                let level = match r.state {
                    Level::Ok => "INFO",
                    Level::Warn | Level::Stale => "WARN",
                    Level::Error => "ERROR",
                };
                self.rec.log(entity(&r.machine, "state").as_str(), &rerun::TextLog::new(r.state.name()).with_level(level))?;
            }
        }
        Ok(())
    }

    /// The view's events at `t_s`: regions (and joins, staleness, recoveries) as text logs.
    pub fn events(&mut self, t_s: f64, events: &[Event]) -> anyhow::Result<()> {
        self.rec.set_duration_secs(TIMELINE_TIME, t_s);
        for e in events {
            let (machine, leaf, text, level) = match e {
                Event::Region { machine, input_topic, region_id, start_x_mm, end_x_mm, peak_c_demand_rpm, min_distance_deg, caught_up, .. } => (
                    machine,
                    "regions",
                    format!(
                        "{input_topic}: region {region_id} at x {start_x_mm:.3}-{end_x_mm:.3} mm, C demand up to {:.1} rpm, {min_distance_deg:.3} deg from the singularity{}",
                        peak_c_demand_rpm.abs(),
                        if *caught_up { " (caught up after an outage)" } else { "" }
                    ),
                    "WARN",
                ),
                Event::Joined { machine } => (machine, "events", "joined".to_string(), "INFO"),
                Event::Stale { machine, silent_s } => (machine, "events", format!("stale: nothing for {silent_s:.1} s"), "WARN"),
                Event::Recovered { machine, silent_s } => (machine, "events", format!("heard again after {silent_s:.1} s"), "INFO"),
            };
            self.rec.log(entity(machine, leaf).as_str(), &rerun::TextLog::new(text).with_level(level))?;
        }
        Ok(())
    }

    pub fn flush(&mut self) {
        let _ = self.rec.flush_blocking();
    }
}
