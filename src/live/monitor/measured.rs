//! A machine stream's sample: the measured path, the path's demand on the secondary axis at the
//! programmed feed, the feed limit over the same stretch and the region rule.

use super::*;

impl Monitor {
    /// A machine stream's sample (a bridge's JointState): the measured path (unwrapped axes, forward
    /// kinematics, actual feed), the path's demand on the secondary axis at the programmed feed (seed
    /// 001 eq. 5 as dC/ds * F over a stretch of path), the feed limit on the same stretch (seed 002
    /// eq. 5, velocity and acceleration terms) and the region rule ([`RegionTracker`]).
    pub(super) fn evaluate_measured(&mut self, id: InputId, st: &AxisState, q: Joints, uncertainty: &Joints, t: f64) -> Evaluation {
        let input = &mut self.inputs[id.0];
        let measured = input.measured.get_or_insert_with(|| MeasuredPath::new(&self.machine, MeasuredConfig::default()));
        if input.aligner.is_none() {
            if let FeedSource::Program(plan) = &self.feed_source {
                input.aligner = Some(Aligner::new(plan.segments.clone()));
            }
        }
        // Where in the program (needs the tip: forward kinematics of the unwrapped axes first).
        // A source that knows the motion kind (an AxisState of source MACHINE from a bridge that has the
        // program) says whether this is a rapid; a JointState does not.
        let hint = (st.motion != AxisState::MOTION_UNKNOWN).then_some(st.motion == AxisState::MOTION_RAPID);
        let m = measured.push(&self.machine, t, &q, uncertainty, hint);
        let place = input.aligner.as_mut().and_then(|a| a.place(&m.tip, &m.q));
        let motion = match place {
            Some(p) if p.rapid => Motion::Rapid,
            // The program says a path move; the stream may still be stopped or turning at its ends.
            Some(p) if p.path_move && m.motion == Motion::Rapid => Motion::Feed,
            Some(p) if !p.path_move && m.motion == Motion::Feed => Motion::Rotary,
            _ => m.motion,
        };
        match motion {
            Motion::Rapid => input.rapid_samples += 1,
            Motion::Feed => input.feed_samples += 1,
            _ => {}
        }
        // The feed held over 0.1 s of uninterrupted feed motion (a blend's overshoot or a rapid
        // misjudged for one sample does not count).
        if motion == Motion::Feed {
            input.feed_run.push_back((t, m.s));
            // At least 0.1 s and three samples (a sparse stream's feed is held over its samples).
            while input.feed_run.len() > 3 && t - input.feed_run[1].0 >= HELD {
                input.feed_run.pop_front();
            }
            while input.feed_run.len() > 4096 {
                input.feed_run.pop_front();
            }
            // Held: about the same speed over both halves of the window (within 20 %): a rapid's
            // acceleration or deceleration below rapid speed (its halves differ by half or more)
            // is no programmed feed.
            let steady = |run: &VecDeque<(f64, f64)>, t0: f64, s0: f64| {
                let mid_t = (t0 + t) / 2.0;
                let (tm, sm) = run[run.partition_point(|p| p.0 < mid_t).min(run.len() - 1)];
                let (h1, h2) = ((sm - s0) / (tm - t0), (m.s - sm) / (t - tm));
                tm > t0 && tm < t && (h1 - h2).abs() <= 0.2 * h1.max(h2)
            };
            if let Some(&(t0, s0)) = input.feed_run.front().filter(|f| t - f.0 >= HELD && input.feed_run.len() >= 3 && steady(&input.feed_run, f.0, f.1)) {
                let held = (m.s - s0) / (t - t0);
                input.max_feed = input.max_feed.max(held);
                let dt = input.feed_run.get(input.feed_run.len().wrapping_sub(2)).map_or(0.0, |p| t - p.0);
                if let Some(k) = feed_bin(held) {
                    if input.feed_time.is_empty() {
                        input.feed_time = vec![0.0; FEED_BINS];
                    }
                    input.feed_time[k] += dt;
                    if input.feed_mode.is_none_or(|b| input.feed_time[k] > input.feed_time[b]) {
                        input.feed_mode = Some(k);
                    }
                }
            }
        } else {
            input.feed_run.clear();
        }
        let f_prog = match (&self.feed_source, place) {
            (FeedSource::Program(_), Some(p)) => p.feed,
            (FeedSource::Program(_), None) => 0.0,
            (FeedSource::Fixed(f), _) => *f,
            (FeedSource::Assumed, _) => input.feed_mode.map_or(0.0, feed_of_bin),
        };
        let f_prog = if motion == Motion::Feed { f_prog } else { 0.0 };
        // Program coordinates: the stream's tip less the datum shift in effect: the aligned program's,
        // else the work offset the control was given.
        let offset = place.map_or(self.config.work_offset, |p| p.offset);
        let dist = distance(&m.axis, &self.singular);
        let predicted = m.demand.map(|d| d.per_metre * f_prog);
        let fl = match m.demand {
            Some(d) if f_prog > 0.0 && !self.regions_only => {
                let f = self.limiter.limit(f_prog, &d.q_s, &d.q_ss, &[0.0; AXES]);
                (f.feed, f.axis, f.kind)
            }
            _ => (f_prog, None, LimitKind::Programmed),
        };
        // The rule runs on the window's middle sample, where the estimate belongs.
        let rule_sample = match m.demand {
            Some(d) => {
                let (dt, ds) = input.lagged.map_or((0.0, 0.0), |(lt, ls)| (d.t - lt, d.s - ls));
                input.lagged = Some((d.t, d.s));
                // The middle sample's motion, except where the program says rapid now.
                let lag_motion = if motion == Motion::Rapid { Motion::Rapid } else { d.motion };
                RuleSample {
                    t: d.t,
                    s: d.s,
                    tip: d.tip - offset,
                    motion: lag_motion,
                    predicted,
                    uncertainty: d.tip_uncertainty,
                    distance: distance(&d.axis, &self.singular),
                    path_feed: d.path_feed,
                    programmed_feed: f_prog,
                    dt,
                    ds,
                    block: place.map_or(-1, |p| p.block),
                    line: place.map_or(st.program_line, |p| p.line),
                }
            }
            None => {
                input.lagged = None;
                RuleSample { t, s: m.s, tip: m.tip - offset, motion, predicted: None, uncertainty: 0.0, distance: dist, path_feed: m.path_feed, programmed_feed: f_prog, dt: 0.0, ds: 0.0, block: place.map_or(-1, |p| p.block), line: place.map_or(st.program_line, |p| p.line) }
            }
        };
        let (verdict, closed) = input.tracker.push(&self.rule, &rule_sample);
        // Look-ahead with the program: the next of the program's regions after this sample's place in
        // it, in program time at the programmed feed.
        let time_to_next = match (&self.feed_source, place) {
            _ if verdict.region_id != 0 => 0.0,
            (FeedSource::Program(plan), Some(p)) => plan.time_to_next_region(p.program_time),
            _ => -1.0,
        };
        if let Some(r) = closed {
            input.close(&r, self.config.max_listed_regions);
        }
        let evaluation = Evaluation {
            stamp: st.header.stamp,
            source: st.source,
            singularity_distance: dist,
            predicted_c_speed: predicted.unwrap_or(0.0),
            c_speed: m.c_speed,
            feed_limit: fl.0,
            limiting_axis: fl.1,
            limit_kind: fl.2,
            in_region: verdict.beyond,
            region_id: if verdict.beyond { verdict.region_id } else { 0 },
            workpiece_position: m.tip - offset,
            time_to_next_region: time_to_next,
            program_line: place.map_or(st.program_line, |p| p.line),
            block_number: place.map_or(st.block_number, |p| p.block),
            motion,
            cause: verdict.cause,
            path_feed: m.path_feed,
            programmed_feed: f_prog,
            // Five-axis motion: the tool axis turns, on a move the program makes five-axis (if known).
            turning: m.turning && place.is_none_or(|p| p.five_axis),
            five_axis_distance: m
                .demand
                .filter(|d| d.motion == Motion::Feed && d.turning && place.is_none_or(|p| p.five_axis))
                .map(|d| distance(&d.axis, &self.singular)),
        };
        input.history.push_back(Past { t, s: m.s, q: m.q, axis: m.axis, tip: m.tip });
        while input.history.len() > 1 {
            input.history.pop_front();
        }
        input.latch(&evaluation, self.config.warn_distance, self.config.warn_ahead);
        input.last = Some(evaluation);
        evaluation
    }
}
