//! The head office's picture of the fleet, from what reaches it: each machine's monitor state (the
//! worst level of its monitor's `/diagnostics`, as ROS 2's diagnostic aggregator ranks them; STALE
//! when nothing has come for the stale timeout), its latest distance and C demand, and its regions,
//! each once whether it came live or by a catch-up after an outage.

use crate::keys::{MachinePath, Sent};
use fiveaxis_msgs::{DiagnosticArray, DiagnosticStatus, Region, SingularityStatus};
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::time::{Duration, Instant};

/// A machine's state as the fleet view shows it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    Ok,
    Warn,
    Error,
    Stale,
}

impl Serialize for Level {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl Level {
    /// As people read it, and as the JSON lines write it.
    pub fn name(self) -> &'static str {
        match self {
            Level::Ok => "OK",
            Level::Warn => "WARN",
            Level::Error => "ERROR",
            Level::Stale => "STALE",
        }
    }

    /// diagnostic_msgs/DiagnosticStatus levels (OK 0, WARN 1, ERROR 2, STALE 3).
    pub fn of_diagnostic(level: u8) -> Level {
        match level {
            DiagnosticStatus::OK => Level::Ok,
            DiagnosticStatus::WARN => Level::Warn,
            DiagnosticStatus::ERROR => Level::Error,
            _ => Level::Stale,
        }
    }
}

/// Something the view reports as it happens.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum Event {
    /// A machine heard for the first time.
    Joined { machine: String },
    /// A region heard for the first time: live, or by a catch-up (`caught_up`) after an outage.
    Region {
        machine: String,
        input_topic: String,
        region_id: u32,
        cause: u8,
        start_x_mm: f64,
        end_x_mm: f64,
        peak_c_demand_rpm: f64,
        min_distance_deg: f64,
        start_line: u32,
        end_line: u32,
        caught_up: bool,
    },
    /// Nothing heard from the machine for the stale timeout.
    Stale { machine: String, silent_s: f64 },
    /// Heard again after being stale.
    Recovered { machine: String, silent_s: f64 },
}

/// Latency samples kept per machine (the last ones).
const LATENCY_WINDOW: usize = 1000;
/// Publishers whose sequence numbers are followed per machine (a gateway and its restarts).
const PUBLISHERS: usize = 8;
/// A status stamp further than this from the office's clock is no wall time (a cell on
/// `use_sim_time` stamps program time): no latency is taken from it.
const WALL_CLOCK_SLACK_NS: i64 = 3_600_000_000_000;

/// How long statuses took to reach the office, over the last [`LATENCY_WINDOW`] (nearest-rank
/// percentiles, ms): from the monitor's sample stamp (the whole way from the cell, cap included),
/// and from the gateway's send stamp (the fleet network alone).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Latency {
    pub sample_p50_ms: Option<f64>,
    pub sample_p99_ms: Option<f64>,
    pub link_p50_ms: Option<f64>,
    pub link_p99_ms: Option<f64>,
}

/// The nearest-rank `p` percentile (0 < p <= 1).
fn percentile(v: &VecDeque<f64>, p: f64) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut sorted: Vec<f64> = v.iter().copied().collect();
    sorted.sort_by(f64::total_cmp);
    let rank = ((p * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    Some(sorted[rank - 1])
}

fn keep(v: &mut VecDeque<f64>, x: f64) {
    if v.len() == LATENCY_WINDOW {
        v.pop_front();
    }
    v.push_back(x);
}

/// One machine's line in the fleet view.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Row {
    pub machine: String,
    pub state: Level,
    /// The monitor's latest distance to the singularity and C speed demand, of the stream the
    /// machine reports on ([`preferred`]), degrees and rpm.
    pub distance_deg: Option<f64>,
    pub c_demand_rpm: Option<f64>,
    pub stream: Option<String>,
    pub in_region: bool,
    /// Regions heard since the view started (each once, live or caught up).
    pub regions: usize,
    pub last_heard_s: f64,
    /// Status messages in the last second, and at most in any one second so far, by the gateway's
    /// send stamps (what the link carried, whatever delay or burst it added).
    pub status_rate_hz: usize,
    pub max_status_rate_hz: usize,
    /// Status messages missing from the gateway's sequence numbers, followed per publisher (a
    /// restarted gateway numbers from 1 again; the cap drops none: these are the link's losses).
    pub status_missing: u64,
    pub latency: Latency,
}

/// What the view knows of one machine.
#[derive(Debug)]
struct Machine {
    last_heard: Instant,
    stale_since: Option<Instant>,
    level: Option<Level>,
    latest: BTreeMap<String, SingularityStatus>,
    /// The regions heard (stream, id), to report each once: the newest [`Fleet::max_regions`], in
    /// the order heard.
    regions: BTreeSet<(String, u32)>,
    regions_order: VecDeque<(String, u32)>,
    /// Regions heard in all, forgotten ones too.
    regions_heard: usize,
    /// Send stamps of the statuses of the last second, ns.
    recent: VecDeque<i64>,
    max_rate: usize,
    /// The last sequence number of each publisher heard (its gid), the most recently heard last;
    /// at most [`PUBLISHERS`].
    last_seq: Vec<([u8; 16], i64)>,
    missing: u64,
    sample_latency_ms: VecDeque<f64>,
    link_latency_ms: VecDeque<f64>,
}

/// Degrees from radians, rpm from rad/s: the units people read (the one rpm factor, `units::RPM`).
fn deg(rad: f64) -> f64 {
    rad.to_degrees()
}
fn rpm(rad_s: f64) -> f64 {
    rad_s / fiveaxis::units::RPM
}

/// The stream a machine's line shows: the machine's own (a bridge's), else the simulated, else the
/// commanded one (what the machine does before what it was told).
pub fn preferred<'a>(topics: impl Iterator<Item = &'a String>) -> Option<&'a String> {
    topics.min_by_key(|t| if t.contains("/machine/") { 0 } else if t.contains("/simulated/") { 1 } else { 2 })
}

/// The fleet as the head office sees it.
#[derive(Debug)]
pub struct Fleet {
    stale_after: Duration,
    /// Regions remembered per machine (to report each once): memory stays flat however long the
    /// view runs. As many as a gateway's store keeps (its `--max-regions`), so that a catch-up,
    /// which answers from that store, finds its regions here.
    max_regions: usize,
    machines: BTreeMap<MachinePath, Machine>,
}

/// Regions a gateway stores for catch-ups (its `--max-regions` default), and the view remembers per
/// machine unless told otherwise.
pub const MAX_REGIONS: usize = 10_000;

impl Fleet {
    pub fn new(stale_after: Duration) -> Fleet {
        Fleet { stale_after, max_regions: MAX_REGIONS, machines: BTreeMap::new() }
    }

    /// Remember at most `n` regions per machine (at least 1).
    pub fn with_max_regions(mut self, n: usize) -> Fleet {
        self.max_regions = n.max(1);
        self
    }

    fn heard(&mut self, path: &MachinePath, now: Instant, events: &mut Vec<Event>) -> &mut Machine {
        if !self.machines.contains_key(path) {
            events.push(Event::Joined { machine: path.namespace() });
        }
        let m = self.machines.entry(path.clone()).or_insert_with(|| Machine {
            last_heard: now,
            stale_since: None,
            level: None,
            latest: BTreeMap::new(),
            regions: BTreeSet::new(),
            regions_order: VecDeque::new(),
            regions_heard: 0,
            recent: VecDeque::new(),
            max_rate: 0,
            last_seq: Vec::new(),
            missing: 0,
            sample_latency_ms: VecDeque::new(),
            link_latency_ms: VecDeque::new(),
        });
        if m.stale_since.take().is_some() {
            events.push(Event::Recovered { machine: path.namespace(), silent_s: (now - m.last_heard).as_secs_f64() });
        }
        m.last_heard = now;
        m
    }

    /// A status from `path`, with its rmw_zenoh sequence number and send stamp (ns) when known,
    /// received at `received_ns` (ns since the UNIX epoch).
    pub fn on_status(&mut self, path: &MachinePath, s: SingularityStatus, sent: Option<Sent>, received_ns: i64, now: Instant) -> Vec<Event> {
        let mut events = Vec::new();
        let m = self.heard(path, now, &mut events);
        let sampled = s.header.stamp.as_nanos() as i64;
        // Only a new sample says how long it took: a status whose stamp is no newer than its
        // stream's last is of the same sample again (a node set holding its start pose re-sends it
        // with its first stamp, which would read as a latency growing by the cap's period).
        let new_sample = m.latest.get(&s.input_topic).is_none_or(|l| (l.header.stamp.as_nanos() as i64) < sampled);
        if new_sample && (received_ns - sampled).abs() < WALL_CLOCK_SLACK_NS {
            keep(&mut m.sample_latency_ms, (received_ns - sampled) as f64 * 1e-6);
        }
        if let Some(Sent { seq, stamp_ns: stamp, gid }) = sent {
            keep(&mut m.link_latency_ms, (i128::from(received_ns) - i128::from(stamp)) as f64 * 1e-6);
            // Each publisher numbers its messages from its start: a gateway restarted is a new
            // publisher (a new gid), whose gaps count from its own sequence.
            let at = m.last_seq.iter().position(|(g, _)| *g == gid);
            let last = at.map(|k| m.last_seq.remove(k).1);
            if let Some(last) = last {
                let gap = i128::from(seq) - i128::from(last) - 1;
                if gap > 0 {
                    m.missing = m.missing.saturating_add(u64::try_from(gap).unwrap_or(u64::MAX));
                }
            }
            m.last_seq.push((gid, last.map_or(seq, |l| l.max(seq))));
            if m.last_seq.len() > PUBLISHERS {
                m.last_seq.remove(0);
            }
            // The window is a second of send stamps in their order: a stamp before the newest (the
            // publisher's clock stepped back) starts it anew, else it would hold every stamp until
            // the clock caught up again.
            if m.recent.back().is_some_and(|&b| stamp < b) {
                m.recent.clear();
            }
            m.recent.push_back(stamp);
            while m.recent.front().is_some_and(|&f| f <= stamp.saturating_sub(1_000_000_000)) {
                m.recent.pop_front();
            }
            m.max_rate = m.max_rate.max(m.recent.len());
        }
        if m.latest.len() < crate::MAX_STREAMS || m.latest.contains_key(&s.input_topic) {
            m.latest.insert(s.input_topic.clone(), s);
        }
        events
    }

    /// The monitor's `/diagnostics` from `path`: the machine's level is the worst of its statuses.
    pub fn on_diagnostics(&mut self, path: &MachinePath, d: &DiagnosticArray, now: Instant) -> Vec<Event> {
        let mut events = Vec::new();
        let m = self.heard(path, now, &mut events);
        m.level = d.status.iter().map(|s| Level::of_diagnostic(s.level)).max();
        events
    }

    /// A region from `path`: reported once, whether live or caught up (`caught_up`). A caught-up
    /// region of a machine already known is no sign of life (the catch-up answers from the
    /// gateway's store), so it does not refresh the machine's last heard time.
    pub fn on_region(&mut self, path: &MachinePath, r: Region, caught_up: bool, now: Instant) -> Vec<Event> {
        let mut events = Vec::new();
        if !caught_up || !self.machines.contains_key(path) {
            self.heard(path, now, &mut events);
        }
        let Some(m) = self.machines.get_mut(path) else { return events };
        let key = (r.input_topic.clone(), r.region_id);
        if m.regions.contains(&key) {
            return events;
        }
        events.push(Event::Region {
            machine: path.namespace(),
            input_topic: r.input_topic.clone(),
            region_id: r.region_id,
            cause: r.cause,
            start_x_mm: r.start_position.x / fiveaxis::units::MM,
            end_x_mm: r.end_position.x / fiveaxis::units::MM,
            peak_c_demand_rpm: rpm(r.peak_predicted_c_speed),
            min_distance_deg: deg(r.min_singularity_distance),
            start_line: r.start_line,
            end_line: r.end_line,
            caught_up,
        });
        m.regions.insert(key.clone());
        m.regions_order.push_back(key);
        m.regions_heard += 1;
        while m.regions_order.len() > self.max_regions {
            if let Some(old) = m.regions_order.pop_front() {
                m.regions.remove(&old);
            }
        }
        events
    }

    /// Mark the machines not heard for the stale timeout.
    pub fn tick(&mut self, now: Instant) -> Vec<Event> {
        let mut events = Vec::new();
        for (path, m) in &mut self.machines {
            let silent = now.saturating_duration_since(m.last_heard);
            if m.stale_since.is_none() && silent >= self.stale_after {
                m.stale_since = Some(now);
                events.push(Event::Stale { machine: path.namespace(), silent_s: silent.as_secs_f64() });
            }
        }
        events
    }

    /// The machines that are stale now.
    pub fn stale(&self) -> Vec<MachinePath> {
        self.machines.iter().filter(|(_, m)| m.stale_since.is_some()).map(|(p, _)| p.clone()).collect()
    }

    /// The highest status rate seen per machine (messages in any one second of send stamps).
    pub fn max_rate(&self, path: &MachinePath) -> Option<usize> {
        self.machines.get(path).map(|m| m.max_rate)
    }

    /// The fleet view's lines, one per machine.
    pub fn rows(&self, now: Instant) -> Vec<Row> {
        self.machines
            .iter()
            .map(|(path, m)| {
                let stream = preferred(m.latest.keys()).cloned();
                let latest = stream.as_ref().and_then(|t| m.latest.get(t));
                let state = if m.stale_since.is_some() { Level::Stale } else { m.level.unwrap_or(Level::Stale) };
                let newest = m.recent.back().copied().unwrap_or(0);
                Row {
                    machine: path.namespace(),
                    state,
                    distance_deg: latest.map(|s| deg(s.singularity_distance)),
                    c_demand_rpm: latest.map(|s| rpm(s.predicted_c_speed)),
                    in_region: latest.is_some_and(|s| s.in_region),
                    stream,
                    regions: m.regions_heard,
                    last_heard_s: now.saturating_duration_since(m.last_heard).as_secs_f64(),
                    status_rate_hz: m.recent.iter().filter(|&&t| t > newest.saturating_sub(1_000_000_000)).count(),
                    max_status_rate_hz: m.max_rate,
                    latency: Latency {
                        sample_p50_ms: percentile(&m.sample_latency_ms, 0.5),
                        sample_p99_ms: percentile(&m.sample_latency_ms, 0.99),
                        link_p50_ms: percentile(&m.link_latency_ms, 0.5),
                        link_p99_ms: percentile(&m.link_latency_ms, 0.99),
                    },
                    status_missing: m.missing,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fiveaxis_msgs::Point;

    fn path(m: &str) -> MachinePath {
        MachinePath::new("plant", "cell_a", m).unwrap()
    }

    /// A status's attachment from the gateway's one publisher.
    fn sent(seq: i64, stamp_ns: i64) -> Option<Sent> {
        Some(Sent { seq, stamp_ns, gid: [1; 16] })
    }

    fn region(id: u32) -> Region {
        Region { input_topic: "/fiveaxis/simulated/axis_state".into(), region_id: id, start_position: Point { x: 0.022, y: 0.0, z: 0.0 }, end_position: Point { x: 0.028, y: 0.0, z: 0.0 }, peak_predicted_c_speed: std::f64::consts::TAU, min_singularity_distance: 0.01, ..Default::default() }
    }

    #[test]
    fn machines_join_go_stale_and_recover() {
        let t0 = Instant::now();
        let mut f = Fleet::new(Duration::from_secs(3));
        let s = SingularityStatus { input_topic: "/fiveaxis/simulated/axis_state".into(), singularity_distance: 0.5f64.to_radians(), predicted_c_speed: 20.0, ..Default::default() };
        assert_eq!(f.on_status(&path("a"), s.clone(), sent(1, 0), 0, t0), vec![Event::Joined { machine: "/plant/cell_a/a".into() }]);
        assert!(f.on_status(&path("a"), s.clone(), sent(2, 100_000_000), 0, t0).is_empty());
        assert!(f.tick(t0 + Duration::from_millis(2900)).is_empty());
        let e = f.tick(t0 + Duration::from_secs(3));
        assert!(matches!(&e[..], [Event::Stale { machine, .. }] if machine == "/plant/cell_a/a"));
        assert!(f.tick(t0 + Duration::from_secs(4)).is_empty(), "said once");
        assert_eq!(f.rows(t0 + Duration::from_secs(4))[0].state, Level::Stale);
        let e = f.on_status(&path("a"), s, sent(5, 10_000_000_000), 0, t0 + Duration::from_secs(13));
        assert!(matches!(&e[..], [Event::Recovered { silent_s, .. }] if (*silent_s - 13.0).abs() < 1e-9));
        let row = &f.rows(t0 + Duration::from_secs(13))[0];
        assert_eq!(row.status_missing, 2);
        assert!((row.distance_deg.unwrap() - 0.5).abs() < 1e-12);
        assert!((row.c_demand_rpm.unwrap() - 20.0 * 60.0 / std::f64::consts::TAU).abs() < 1e-9);
        assert_eq!(row.state, Level::Stale, "no /diagnostics heard yet");
    }

    #[test]
    fn the_state_is_the_worst_diagnostic_level() {
        let t0 = Instant::now();
        let mut f = Fleet::new(Duration::from_secs(3));
        let d = DiagnosticArray { status: vec![DiagnosticStatus { level: DiagnosticStatus::WARN, ..Default::default() }, DiagnosticStatus { level: DiagnosticStatus::OK, ..Default::default() }], ..Default::default() };
        f.on_diagnostics(&path("a"), &d, t0);
        assert_eq!(f.rows(t0)[0].state, Level::Warn);
    }

    #[test]
    fn a_region_is_reported_once_live_or_caught_up() {
        let t0 = Instant::now();
        let mut f = Fleet::new(Duration::from_secs(3));
        // A view started mid-shift learns of a machine from its catch-up.
        let e = f.on_region(&path("a"), region(1), true, t0);
        assert!(matches!(&e[..], [Event::Joined { .. }, Event::Region { region_id: 1, caught_up: true, peak_c_demand_rpm, .. }] if (*peak_c_demand_rpm - 60.0).abs() < 1e-9));
        assert!(f.on_region(&path("a"), region(1), false, t0).is_empty());
        // A catch-up of a stale machine does not make it heard.
        f.tick(t0 + Duration::from_secs(5));
        assert!(f.on_region(&path("a"), region(3), true, t0 + Duration::from_secs(5)).iter().all(|e| matches!(e, Event::Region { .. })));
        assert_eq!(f.stale().len(), 1);
        let e = f.on_region(&path("a"), region(2), true, t0);
        assert!(matches!(&e[..], [Event::Region { region_id: 2, caught_up: true, start_x_mm, .. }] if (*start_x_mm - 22.0).abs() < 1e-9));
        assert_eq!(f.rows(t0)[0].regions, 3);
    }

    #[test]
    fn the_rate_is_counted_on_send_stamps() {
        let t0 = Instant::now();
        let mut f = Fleet::new(Duration::from_secs(3));
        // 10 Hz for 3 s, delivered all at once (a burst after an outage) still counts 10 a second.
        for i in 0..30i64 {
            f.on_status(&path("a"), SingularityStatus::default(), sent(i + 1, i * 100_000_000), 0, t0);
        }
        assert_eq!(f.max_rate(&path("a")), Some(10));
        assert_eq!((f.rows(t0)[0].status_rate_hz, f.rows(t0)[0].max_status_rate_hz), (10, 10));
    }

    #[test]
    fn latencies_are_percentiles_of_wall_clock_stamps() {
        let t0 = Instant::now();
        let mut f = Fleet::new(Duration::from_secs(3));
        let epoch = 1_800_000_000_000_000_000i64;
        // 100 statuses, sampled 1..=100 ms before arrival, sent 0.5 ms before it.
        for i in 1..=100i64 {
            let received = epoch + i * 100_000_000;
            let s = SingularityStatus { header: fiveaxis_msgs::Header { stamp: fiveaxis_msgs::Time::from_nanos((received - i * 1_000_000) as u64), frame_id: String::new() }, ..Default::default() };
            f.on_status(&path("a"), s, sent(i, received - 500_000), received, t0);
        }
        let l = f.rows(t0)[0].latency.clone();
        assert_eq!((l.sample_p50_ms, l.sample_p99_ms), (Some(50.0), Some(99.0)));
        assert!((l.link_p50_ms.unwrap() - 0.5).abs() < 1e-9 && (l.link_p99_ms.unwrap() - 0.5).abs() < 1e-9);
        // A status of the same sample again (its stamp no newer than the stream's last) is no new
        // latency, however late it arrives.
        let late = epoch + 101 * 100_000_000;
        let again = SingularityStatus { header: fiveaxis_msgs::Header { stamp: fiveaxis_msgs::Time::from_nanos((epoch + 100 * 100_000_000 - 100_000_000) as u64), frame_id: String::new() }, ..Default::default() };
        f.on_status(&path("a"), again, sent(101, late - 500_000), late + 5_000_000_000, t0);
        assert_eq!(f.rows(t0)[0].latency.sample_p99_ms, Some(99.0));
        // Program time (a cell on use_sim_time) is no wall time: no sample latency from it.
        let mut g = Fleet::new(Duration::from_secs(3));
        g.on_status(&path("b"), SingularityStatus::default(), None, epoch, t0);
        assert_eq!(g.rows(t0)[0].latency, Latency::default());
    }

    #[test]
    fn a_restarted_gateway_counts_its_losses_from_its_own_sequence() {
        let t0 = Instant::now();
        let mut f = Fleet::new(Duration::from_secs(3));
        let s = SingularityStatus::default();
        for i in 1..=100i64 {
            f.on_status(&path("a"), s.clone(), sent(i, i * 100_000_000), 0, t0);
        }
        // The gateway restarts (a new publisher, a new gid): its sequence starts at 1 again, and its
        // statuses 4 to 6 are lost on the link.
        let restarted = |seq: i64| Some(Sent { seq, stamp_ns: 20_000_000_000 + seq * 100_000_000, gid: [2; 16] });
        for seq in [1, 2, 3, 7, 8] {
            f.on_status(&path("a"), s.clone(), restarted(seq), 0, t0);
        }
        assert_eq!(f.rows(t0)[0].status_missing, 3);
        // A late status of the first publisher is no loss of the second.
        f.on_status(&path("a"), s.clone(), sent(101, 10_100_000_000), 0, t0);
        f.on_status(&path("a"), s, restarted(9), 0, t0);
        assert_eq!(f.rows(t0)[0].status_missing, 3);
    }

    #[test]
    fn a_publisher_clock_stepping_back_keeps_the_rate_of_a_second() {
        let t0 = Instant::now();
        let mut f = Fleet::new(Duration::from_secs(3));
        let hour = 3_600_000_000_000i64;
        // 10 Hz for 2 s, then the gateway's clock steps back an hour and it goes on at 10 Hz.
        for i in 0..20i64 {
            f.on_status(&path("a"), SingularityStatus::default(), sent(i + 1, hour + i * 100_000_000), 0, t0);
        }
        for i in 0..30i64 {
            f.on_status(&path("a"), SingularityStatus::default(), sent(i + 21, i * 100_000_000), 0, t0);
        }
        assert_eq!(f.max_rate(&path("a")), Some(10));
        assert_eq!(f.rows(t0)[0].status_rate_hz, 10);
    }

    #[test]
    fn attachments_at_the_ends_of_their_range_are_taken_without_overflow() {
        let t0 = Instant::now();
        let mut f = Fleet::new(Duration::from_secs(3));
        let s = SingularityStatus::default();
        for (seq, stamp) in [(i64::MIN, i64::MIN), (i64::MAX, i64::MAX), (i64::MAX, i64::MIN), (0, 0)] {
            f.on_status(&path("a"), s.clone(), sent(seq, stamp), i64::MAX, t0);
        }
        let row = &f.rows(t0)[0];
        // From i64::MIN to i64::MAX, 2^64 - 2 statuses lie between.
        assert_eq!(row.status_missing, u64::MAX - 1);
        assert!(row.latency.link_p99_ms.is_some_and(f64::is_finite));
    }

    #[test]
    fn the_regions_remembered_are_the_newest_however_many_come() {
        let t0 = Instant::now();
        let mut f = Fleet::new(Duration::from_secs(3)).with_max_regions(5);
        for id in 1..=100 {
            assert_eq!(f.on_region(&path("a"), region(id), false, t0).iter().filter(|e| matches!(e, Event::Region { .. })).count(), 1, "region {id}");
        }
        let m = &f.machines[&path("a")];
        assert_eq!((m.regions.len(), m.regions_order.len()), (5, 5));
        // The newest are still reported once, caught up or not.
        assert!(f.on_region(&path("a"), region(100), true, t0).is_empty());
        assert!(f.on_region(&path("a"), region(96), false, t0).is_empty());
        assert_eq!(f.rows(t0)[0].regions, 100);
    }

    #[test]
    fn a_peer_naming_a_new_stream_in_every_status_grows_nothing() {
        let t0 = Instant::now();
        let mut f = Fleet::new(Duration::from_secs(3));
        for k in 0..1000 {
            let s = SingularityStatus { input_topic: format!("/fiveaxis/x{k}/axis_state"), ..Default::default() };
            f.on_status(&path("a"), s, None, 0, t0);
        }
        assert_eq!(f.machines[&path("a")].latest.len(), crate::MAX_STREAMS);
        // A followed stream is still shown.
        let s = SingularityStatus { input_topic: "/fiveaxis/x0/axis_state".into(), singularity_distance: 1.0f64.to_radians(), ..Default::default() };
        f.on_status(&path("a"), s, None, 0, t0);
        assert!(f.rows(t0)[0].distance_deg.is_some());
    }
}
