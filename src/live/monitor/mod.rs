//! Monitor: per axis-state sample, the distance to the singularity, the predicted secondary-axis speed
//! (seed 001 eq. 5), the feed limit and limiting axis (seed 002 eq. 5), region entry and exit, a
//! look-ahead from the commanded stream, and input health (NaN/Inf, out of range, out of order, stale).
//! The same math as the offline analysis ([`crate::singularity`]), fed one sample at a time.

use crate::kinematics::Joints;
use crate::machine::{Machine, AXES};
use crate::path::align::{Aligner, OpenSegments};
use crate::path::Segment;
use crate::singularity::measured::{MeasuredConfig, MeasuredPath, Motion};
use crate::singularity::tracker::{Cause, RegionRule, RegionTracker, RuleSample, TrackedRegion};
use crate::singularity::{distance, FeedLimiter, LimitKind};
use std::sync::Arc;
use fiveaxis_msgs::{AxisState, DiagnosticArray, DiagnosticStatus, Header, KeyValue, Point, SingularityStatus, Time};
use nalgebra::Vector3;
use std::collections::{BTreeMap, VecDeque};

mod diagnostics;
mod feed;
mod input;
mod lookahead;
mod loss;
mod measured;
mod types;

use diagnostics::level_of;
use feed::{feed_bin, feed_limit_from_history, feed_of_bin, limit_kind_code, FEED_BINS, HELD};
use input::{Input, Past};
use lookahead::{lookahead, Ahead, Timeline};
pub use lookahead::AHEAD_RETENTION_S;
use loss::{close_loss_episode, count_lost, LossEpisode, LossEvent};
use types::{Reason, OUT_OF_RANGE};
pub use types::{Evaluation, FeedSource, InputSummary, LiveRegion, MonitorConfig, ProgramPlan, Rejected, Rejection};

/// A stream of the monitor, by index (see [`Monitor::input`]): no topic lookup per sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InputId(usize);

/// Tip travel into a block below which the monitor holds the previous prediction (m).
const MIN_DEMAND_PATH: f64 = 1e-6;

/// The monitor's state.
#[derive(Debug)]
pub struct Monitor {
    machine: Machine,
    config: MonitorConfig,
    singular: Vector3<f64>,
    secondary: usize,
    limit: f64,
    limiter: FeedLimiter,
    /// The streams, and their indices by topic (sorted: summaries list them in topic order).
    inputs: Vec<Input>,
    index: BTreeMap<String, usize>,
    ahead: Timeline,
    prev_commanded_axis: Option<Vector3<f64>>,
    /// Machine streams: where the programmed feed comes from, and the region rule.
    feed_source: FeedSource,
    rule: RegionRule,
    /// Evaluations of program streams carry no feed limit ([`Monitor::set_regions_only`]).
    regions_only: bool,
}

fn vec3(p: &Point) -> Vector3<f64> {
    Vector3::new(p.x, p.y, p.z)
}

impl Monitor {
    pub fn new(machine: &Machine, config: MonitorConfig) -> Monitor {
        let secondary = machine.secondary_axis();
        let limits = machine.limits();
        Monitor {
            machine: machine.clone(),
            config,
            singular: machine.singular_direction(),
            secondary,
            limit: config.rate_limit.unwrap_or(limits[secondary].velocity),
            limiter: FeedLimiter::new(&limits),
            inputs: Vec::new(),
            index: BTreeMap::new(),
            ahead: Timeline::default(),
            prev_commanded_axis: None,
            feed_source: FeedSource::Assumed,
            rule: RegionRule::new(config.rate_limit.unwrap_or(limits[secondary].velocity), config.min_distance),
            regions_only: false,
        }
    }

    /// For a caller that keeps only the regions and counters (an in-process run's report, which
    /// records no status; the offline analysis of a recording): every evaluation then carries the
    /// programmed feed as its feed limit, with no limiting axis, instead of seed 002 eq. (5) on the
    /// divided differences (machine streams: on the measured path), which nothing would read.
    /// Regions, counters and the C speeds are the same.
    pub fn set_regions_only(&mut self, on: bool) {
        self.regions_only = on;
    }

    /// Where machine streams' programmed feed comes from (default [`FeedSource::Assumed`]).
    pub fn set_feed_source(&mut self, source: FeedSource) {
        self.feed_source = source;
    }

    /// Count a sample of stream `id` that could not even be turned into axis positions (a JointState
    /// without a mapped joint): every rejection is counted by reason.
    pub fn reject(&mut self, id: InputId, rejection: &Rejection) {
        self.inputs[id.0].rejected.count(match rejection {
            Rejection::MissingJoint(_) => Reason::MissingJoint,
            Rejection::OutOfOrder { .. } => Reason::OutOfOrder,
            Rejection::Invalid(_) => Reason::Malformed,
            Rejection::NonFinite(_) => Reason::NonFinite,
        });
    }

    /// The sample's tool axis and tool tip (workpiece coordinates): as the message gives them (the
    /// commander and the simulator fill them in), else by forward kinematics of its axis positions
    /// (a machine bridge's JointState carries positions only).
    fn axis_and_tip(machine: &Machine, st: &AxisState, q: &Joints) -> (Vector3<f64>, Vector3<f64>) {
        let given_axis = Vector3::new(st.tool_axis.x, st.tool_axis.y, st.tool_axis.z);
        let axis_given = (given_axis.norm() - 1.0).abs() < 1e-6;
        let tip_given = st.program_line > 0 || st.tool_tip != Point::default();
        if axis_given && tip_given {
            return (given_axis, vec3(&st.tool_tip));
        }
        let pose = machine.forward(q);
        (if axis_given { given_axis } else { pose.axis }, if tip_given { vec3(&st.tool_tip) } else { pose.tip })
    }

    fn validate(&self, st: &AxisState) -> Result<Joints, (Reason, Rejection)> {
        if st.position.len() != AXES {
            return Err((Reason::Malformed, Rejection::Invalid(format!("expected {AXES} positions, got {}", st.position.len()))));
        }
        let q: Joints = std::array::from_fn(|i| st.position[i]);
        for (i, v) in q.iter().enumerate() {
            let a = &self.machine.axes[i];
            if !v.is_finite() {
                return Err((Reason::NonFinite, Rejection::Invalid(format!("{} position is {v}", a.name))));
            }
            // A little slack for servo overshoot and rounding at the end stops.
            let slack = if i < 3 { 1e-3 } else { 1e-3f64.to_radians() };
            if *v < a.limits.min - slack || *v > a.limits.max + slack {
                return Err((Reason::OutOfRange, Rejection::Invalid(format!("{} position {v:.6} {OUT_OF_RANGE}", a.name))));
            }
        }
        let stamp = st.header.stamp;
        if stamp.nanosec >= 1_000_000_000 {
            return Err((Reason::Malformed, Rejection::Invalid("header stamp nanosec out of range".into())));
        }
        for (what, v) in [("programmed_feed", st.programmed_feed), ("path_feed", st.path_feed)] {
            if !v.is_finite() {
                return Err((Reason::NonFinite, Rejection::Invalid(format!("{what} is {v}"))));
            }
            if v < 0.0 {
                return Err((Reason::Malformed, Rejection::Invalid(format!("{what} is {v}"))));
            }
        }
        Ok(q)
    }

    /// Remember a commanded sample for the look-ahead (call for each commanded state, in order).
    pub fn on_commanded_ahead(&mut self, st: &AxisState) {
        let Ok(q) = self.validate(st) else { return };
        let (axis, tip) = Self::axis_and_tip(&self.machine, st, &q);
        let t = st.header.stamp.as_secs();
        if self.ahead.last().is_some_and(|a| t <= a.t) {
            return;
        }
        // In a region if the step from the previous commanded sample demands more than the limit.
        let in_region = match self.ahead.last() {
            Some(prev) => {
                let prev_q = self.prev_commanded_axis.unwrap_or(axis);
                let dt = t - prev.t;
                let rate = if dt > 0.0 { self.machine.chain.secondary_rate(&axis, &((axis - prev_q) / dt), &[q[3], q[4]]) } else { 0.0 };
                rate.abs() > self.limit
            }
            None => false,
        };
        self.prev_commanded_axis = Some(axis);
        self.ahead.push(Ahead { t, line: st.program_line, tip }, in_region);
    }

    /// The stream of `topic`, created on first use.
    pub fn input(&mut self, topic: &str) -> InputId {
        if let Some(&k) = self.index.get(topic) {
            return InputId(k);
        }
        self.inputs.push(Input::default());
        self.index.insert(topic.to_string(), self.inputs.len() - 1);
        InputId(self.inputs.len() - 1)
    }

    fn get(&self, topic: &str) -> Option<&Input> {
        self.index.get(topic).map(|&k| &self.inputs[k])
    }

    /// The streams in topic order.
    fn each(&self) -> impl Iterator<Item = (&String, &Input)> {
        self.index.iter().map(|(t, &k)| (t, &self.inputs[k]))
    }

    /// Evaluate one sample of stream `topic`; `wall` is the arrival time (s, any monotonic clock).
    pub fn on_state(&mut self, topic: &str, st: &AxisState, wall: f64) -> Result<SingularityStatus, Rejection> {
        self.on_merged_state(topic, st, None, wall)
    }

    /// [`Monitor::on_state`] of a pose merged from per-axis reports, with how far each axis may be
    /// off in it (SI; None: exact, as [`Monitor::on_state`]).
    pub fn on_merged_state(&mut self, topic: &str, st: &AxisState, uncertainty: Option<&Joints>, wall: f64) -> Result<SingularityStatus, Rejection> {
        let id = self.input(topic);
        let e = self.evaluate_merged(id, st, uncertainty, wall)?;
        Ok(self.status_of(id, topic, &e, &st.header.frame_id, false))
    }

    /// The status message of an evaluation of stream `id` (`stale`: published while the input is
    /// silent, repeating the last evaluation).
    fn status_of(&self, id: InputId, topic: &str, e: &Evaluation, frame_id: &str, stale: bool) -> SingularityStatus {
        let input = &self.inputs[id.0];
        SingularityStatus {
            header: Header { stamp: e.stamp, frame_id: frame_id.to_string() },
            source: e.source,
            input_topic: topic.to_string(),
            motion: e.motion.code(),
            singularity_distance: e.singularity_distance,
            secondary_axis: self.machine.axes[self.secondary].name.clone(),
            predicted_c_speed: e.predicted_c_speed,
            c_speed: e.c_speed,
            c_speed_limit: self.limit,
            programmed_feed: e.programmed_feed,
            path_feed: e.path_feed,
            feed_limit: e.feed_limit,
            limiting_axis: e.limiting_axis.map_or(String::new(), |i| self.machine.axes[i].name.clone()),
            limit_kind: limit_kind_code(e.limit_kind),
            in_region: e.in_region,
            region_id: e.region_id,
            region_cause: e.cause.filter(|_| e.in_region).map_or(SingularityStatus::CAUSE_NONE, Cause::code),
            workpiece_position: Point { x: e.workpiece_position.x, y: e.workpiece_position.y, z: e.workpiece_position.z },
            time_to_next_region: e.time_to_next_region,
            program_line: e.program_line,
            block_number: e.block_number,
            stale,
            invalid_count: input.rejected.invalid(),
            missing_joint_count: input.rejected.missing_joint,
            non_finite_count: input.rejected.non_finite,
            out_of_range_count: input.rejected.out_of_range,
            out_of_order_count: input.rejected.out_of_order,
            stale_count: input.stale,
            lost_count: input.lost,
        }
    }

    /// A status for every input that is stale now (the last sample's figures, `stale` set), so that
    /// the status topic says so while the input is silent.
    pub fn stale_statuses(&self) -> Vec<SingularityStatus> {
        self.each()
            .filter(|(_, i)| i.stale_now)
            .filter_map(|(topic, i)| {
                let id = InputId(self.index[topic]);
                let mut e = i.last?;
                e.in_region = false;
                e.region_id = 0;
                Some(self.status_of(id, topic, &e, "", true))
            })
            .collect()
    }

    /// Stream `id` starts a new session where its source says so (an SHDR log whose adapter connected
    /// again: its stamps start over): as for a publisher restarted after going stale.
    pub fn new_session(&mut self, id: InputId) {
        self.inputs[id.0].new_session(self.config.max_listed_regions);
    }

    /// Stream `id`'s source reports values only when they change (an MTConnect adapter): a gap in
    /// its stamps is a machine at rest as likely as a loss, so none is judged lost.
    pub fn set_change_only(&mut self, id: InputId, on: bool) {
        self.inputs[id.0].change_only = on;
    }

    /// A message of `topic` arrived at `wall` without completing a sample yet (one joint of a
    /// bridge that sends each on its own): the source is alive, not stale.
    pub fn heard(&mut self, topic: &str, wall: f64) {
        if let Some(&k) = self.index.get(topic) {
            self.inputs[k].last_arrival = Some(wall);
        }
    }

    /// The stream of `topic`, if seen.
    pub fn input_id(&self, topic: &str) -> Option<InputId> {
        self.index.get(topic).map(|&k| InputId(k))
    }

    /// [`Monitor::on_state`] without building the status message: the figures only.
    pub fn evaluate(&mut self, id: InputId, st: &AxisState, wall: f64) -> Result<Evaluation, Rejection> {
        self.evaluate_merged(id, st, None, wall)
    }

    /// [`Monitor::evaluate`] of a pose merged from per-axis reports, with how far each axis may be
    /// off in it (SI; [`crate::live::joint_stream::Merged`]): a region is announced only once the
    /// path inside it is longer than the tool tip's uncertainty at its ends ([`RegionTracker`]).
    pub fn evaluate_merged(&mut self, id: InputId, st: &AxisState, uncertainty: Option<&Joints>, wall: f64) -> Result<Evaluation, Rejection> {
        let q = match self.validate(st) {
            Ok(q) => q,
            Err((reason, e)) => {
                self.inputs[id.0].rejected.count(reason);
                return Err(e);
            }
        };
        let t = st.header.stamp.as_secs();
        let input = &mut self.inputs[id.0];
        // A sample that arrived no later than the last one (a pose a merge made because its stream
        // fell silent) says nothing of the source being alive: it neither ends nor starts a stale episode.
        let arrived = input.last_arrival.is_none_or(|last| wall > last);
        if arrived {
            input.last_arrival = Some(wall);
        }
        // The stream had gone stale and comes back with its clock restarted (stamped no later than
        // before): a restarted publisher, a new session (a gap still being judged is judged on what
        // came before). A stream that comes back where it left off (a publisher that stalled) goes on.
        if input.stale_now && input.history.back().is_some_and(|h| t <= h.t) {
            input.new_session(self.config.max_listed_regions);
        }
        // The stream went stale and goes on where it left off (a bridge that was down, a publisher
        // that stalled): the gap in its stamps is stale time, already counted as such, not samples
        // lost. The loss judgement starts again after it.
        let outage = arrived && std::mem::replace(&mut input.stale_now, false);
        if let Some(last) = input.history.back() {
            if t <= last.t {
                input.rejected.count(Reason::OutOfOrder);
                return Err(Rejection::OutOfOrder { stamp: t, last: last.t });
            }
        }
        input.source = st.source;
        input.samples += 1;
        if let Some(last) = input.history.back().map(|h| h.t) {
            if outage {
                close_loss_episode(input, last);
                input.stamps.clear();
                input.loss_events.clear();
            }
            input.last_interval = Some(t - last);
            count_lost(input, t - last, t);
        }
        if st.source == AxisState::SOURCE_MACHINE {
            return Ok(self.evaluate_measured(id, st, q, uncertainty.unwrap_or(&[0.0; AXES]), t));
        }
        let (axis, tip) = Self::axis_and_tip(&self.machine, st, &q);
        let prev = input.history.back().copied();
        let ds = prev.map_or(0.0, |p| (tip - p.tip).norm());
        input.s += ds;
        let now = Past { t, s: input.s, q, axis, tip };
        input.history.push_back(now);
        while input.history.len() > 4 {
            input.history.pop_front();
        }

        // Seed 001 eq. (5) at the programmed feed: dO/ds times F (dO/dt where the tip does not move).
        // A step that crosses into another block mixes two moves (a rotary-only block's turn over the
        // next block's first micrometres): there the previous sample's prediction holds.
        // So does the block's first micrometre of tip travel: a servo still settling the rotary axes
        // of a reorientation while the tip starts from rest turns the tool over almost no path.
        if input.block_start.0 != st.program_line || prev.is_none() {
            input.block_start = (st.program_line, input.s - ds);
        }
        let settling = input.s - input.block_start.1 < MIN_DEMAND_PATH && ds > 0.0;
        let held = input.last.as_ref().filter(|l| l.program_line != st.program_line || settling).map(|l| l.predicted_c_speed);
        let (predicted, c_speed) = match prev {
            Some(p) => {
                let dt = t - p.t;
                let f = if st.programmed_feed > 0.0 { st.programmed_feed } else { ds / dt };
                let rate = if ds > 1e-12 { (axis - p.axis) / ds * f } else { (axis - p.axis) / dt };
                // The chord is a mid-step quantity: evaluate eq. (5) at the mid-step orientation.
                let mid = (axis + p.axis).try_normalize(1e-12).unwrap_or(axis);
                let predicted = held.unwrap_or_else(|| self.machine.chain.secondary_rate(&mid, &rate, &[q[3], q[4]]));
                (predicted, (q[self.secondary] - p.q[self.secondary]) / dt)
            }
            None => (0.0, 0.0),
        };
        // Seed 002 eq. (5) from divided differences over the last samples along the path.
        let fl = if self.regions_only {
            (st.programmed_feed, None, LimitKind::Programmed)
        } else {
            feed_limit_from_history(&input.history, &self.limiter, st.programmed_feed)
        };
        let dist = distance(&axis, &self.singular);
        let moving = ds > 1e-12;
        // The region rule ([`RegionTracker`], the same as for machine streams): the motion kind from the
        // program where the stream carries it, else from the stream (tip moving: feed; axis turning
        // under a still tip: rotary-only). A rapid never opens a region.
        let motion = match Motion::from_code(st.motion) {
            Motion::Unknown if moving => Motion::Feed,
            Motion::Unknown if prev.is_some_and(|p| (axis - p.axis).norm() > 0.0) => Motion::Rotary,
            Motion::Unknown => Motion::Dwell,
            m => m,
        };
        let rule_sample = RuleSample {
            t,
            s: input.s,
            tip,
            motion,
            predicted: Some(predicted),
            uncertainty: 0.0,
            distance: dist,
            path_feed: st.path_feed,
            programmed_feed: st.programmed_feed,
            dt: prev.map_or(0.0, |p| t - p.t),
            ds,
            block: st.block_number,
            line: st.program_line,
        };
        let (verdict, closed) = input.tracker.push(&self.rule, &rule_sample);
        if let Some(r) = closed {
            input.close(&r, self.config.max_listed_regions);
        }
        let in_region = verdict.beyond;

        // Look-ahead on the commanded timeline: where is this sample on it, and what comes next?
        let time_to_next = if in_region {
            0.0
        } else {
            let (cursor, ahead) = lookahead(&self.ahead, input.cursor, st.program_line, &tip);
            input.cursor = cursor;
            ahead
        };
        let evaluation = Evaluation {
            stamp: st.header.stamp,
            source: st.source,
            singularity_distance: dist,
            predicted_c_speed: predicted,
            c_speed,
            feed_limit: fl.0,
            limiting_axis: fl.1,
            limit_kind: fl.2,
            in_region,
            region_id: if in_region { verdict.region_id } else { 0 },
            workpiece_position: tip,
            time_to_next_region: time_to_next,
            program_line: st.program_line,
            block_number: st.block_number,
            motion,
            cause: verdict.cause,
            path_feed: st.path_feed,
            programmed_feed: st.programmed_feed,
            turning: true,
            five_axis_distance: None,
        };
        input.latch(&evaluation, self.config.warn_distance, self.config.warn_ahead);
        input.last = Some(evaluation);
        Ok(evaluation)
    }

    /// Check every input for staleness at wall time `wall`; returns the topics that just went stale.
    pub fn tick(&mut self, wall: f64) -> Vec<String> {
        let mut gone = Vec::new();
        for (topic, &k) in &self.index {
            let input = &mut self.inputs[k];
            if let Some(last) = input.last_arrival {
                if !input.stale_now && wall - last > input.stale_after(self.config.stale_timeout) {
                    input.stale_now = true;
                    input.stale += 1;
                    gone.push(topic.clone());
                }
            }
        }
        gone
    }

    /// Close any open region (end of a stream).
    pub fn finish(&mut self) {
        for input in self.inputs.iter_mut() {
            if let Some(last) = input.history.back().map(|h| h.t) {
                close_loss_episode(input, last);
            }
            if let Some(r) = input.tracker.finish() {
                input.close(&r, self.config.max_listed_regions);
            }
        }
    }

    /// Regions a stream went through, in order: the first ones listed (see
    /// [`MonitorConfig::max_listed_regions`]) and the open one.
    pub fn regions(&self, topic: &str) -> Vec<LiveRegion> {
        self.get(topic).map_or_else(Vec::new, |i| i.all_regions())
    }

    /// The regions of a stream past the listing cap, folded.
    pub fn unlisted_regions(&self, topic: &str) -> crate::listing::Unlisted {
        self.get(topic).map_or_else(Default::default, |i| i.unlisted)
    }

    /// The region `id` of a stream if it is open or the last closed (a region's end event), else a
    /// listed one.
    pub fn region(&self, topic: &str, id: u32) -> Option<LiveRegion> {
        let i = self.get(topic)?;
        match (i.tracker.open(), &i.last_closed) {
            (Some(r), _) if r.id == id => Some(LiveRegion::from_tracked(r)),
            (_, Some(r)) if r.id == id => Some(r.clone()),
            _ => i.regions.iter().find(|r| r.id == id).cloned(),
        }
    }

    /// (samples, invalid, out of order, stale) of a stream.
    pub fn counters(&self, topic: &str) -> (u64, u64, u64, u64) {
        self.get(topic).map_or((0, 0, 0, 0), |i| (i.samples, i.rejected.invalid(), i.rejected.out_of_order, i.stale))
    }

    /// Samples missing from a stream, judged by gaps in its stamps against its period.
    pub fn lost(&self, topic: &str) -> u64 {
        self.get(topic).map_or(0, |i| i.lost)
    }

    /// The topics seen so far.
    pub fn topics(&self) -> Vec<String> {
        self.index.keys().cloned().collect()
    }

    /// The first stream whose program (`--program`) could not be read again to place its samples,
    /// and why: the node fails then (its samples have no program place).
    pub fn program_unreadable(&self) -> Option<(&str, &str)> {
        self.each().find_map(|(topic, i)| i.program_failure().map(|why| (topic.as_str(), why)))
    }

    /// A summary of every stream, for people and CI.
    pub fn summary(&self) -> Vec<InputSummary> {
        self.each()
            .map(|(topic, i)| InputSummary {
                topic: topic.clone(),
                source: i.source,
                samples: i.samples,
                invalid: i.rejected.invalid(),
                out_of_order: i.rejected.out_of_order,
                stale: i.stale,
                lost: i.lost,
                rejected: i.rejected,
                period_s: i.period.map(|p| p.0),
                rapid_samples: i.rapid_samples,
                feed_samples: i.feed_samples,
                max_path_feed_mm_per_min: i.max_feed / crate::units::MM_PER_MIN,
                feed_source: (i.source == AxisState::SOURCE_MACHINE && i.samples > 0).then(|| self.feed_source.describe()),
                program_unreadable: i.program_failure().map(str::to_string),
                regions: i.all_regions(),
                unlisted_regions: i.unlisted,
                unconfirmed_regions: i.tracker.unconfirmed(),
            })
            .collect()
    }

}

#[cfg(test)]
mod tests {
    use super::*;

    /// The binary search gives what the definition (the first region starting after t) gives.
    #[test]
    fn time_to_next_region_is_the_first_start_after_the_sample() {
        let regions: Vec<(f64, f64)> = (0..500).map(|k| (k as f64 * 2.0 + (k % 3) as f64 * 0.1, k as f64 * 2.0 + 1.0)).collect();
        let plan = ProgramPlan::held(Vec::new(), regions.clone());
        for k in 0..4000 {
            let t = k as f64 * 0.2537 - 3.0;
            let want = regions.iter().find(|r| r.0 > t).map_or(-1.0, |r| r.0 - t);
            assert_eq!(plan.time_to_next_region(t), want, "t {t}");
        }
        assert_eq!(plan.time_to_next_region(0.0), regions[1].0, "a region starting exactly at t is not ahead");
    }
}
