//! `/diagnostics`: one status per input at the worst level since the last report, naming the region
//! or the condition that caused it, with the counters every other report gives.

use super::*;

impl Monitor {
    /// The diagnostics: one status per input, at the worst level since the last report (ERROR inside
    /// a region, WARN near the singularity or a region ahead, STALE without samples, OK), naming the
    /// region that caused it. Call [`Monitor::reported`] after publishing them.
    pub fn diagnostics(&self, stamp: Time) -> DiagnosticArray {
        let rpm = crate::units::RPM;
        let secondary = &self.machine.axes[self.secondary].name;
        let status = self
            .each()
            .map(|(topic, input)| {
                let event = |level: u8, s: &Evaluation| -> (u8, String) {
                    let when = if input.last.as_ref().is_some_and(|l| l.stamp == s.stamp) { String::new() } else { " since the last report".to_string() };
                    let message = match level {
                        DiagnosticStatus::ERROR => format!(
                            "{secondary} speed {:.1} rpm above its {:.1} rpm limit (region {}, {}){when}",
                            s.predicted_c_speed.abs() / rpm,
                            self.limit / rpm,
                            s.region_id,
                            match s.cause {
                                Some(Cause::Singularity) => "singularity",
                                Some(Cause::RotaryFeed) => "rotary feed",
                                None => "limit",
                            }
                        ),
                        DiagnosticStatus::WARN if s.singularity_distance < self.config.warn_distance => {
                            format!("{:.2} deg from the singularity{when}", s.singularity_distance.to_degrees())
                        }
                        DiagnosticStatus::WARN => format!("region ahead in {:.2} s{when}", s.time_to_next_region),
                        _ => "clear of the singularity".to_string(),
                    };
                    (level, message)
                };
                let current = input.last.as_ref().map(|s| (level_of(s, self.config.warn_distance, self.config.warn_ahead), s));
                let worst = match (current, &input.worst) {
                    (Some(c), Some((l, w))) if *l > c.0 => Some((*l, w)),
                    (c, _) => c,
                };
                let (level, message) = match (input.program_failure(), worst) {
                    (Some(why), _) => {
                        (DiagnosticStatus::ERROR, format!("the program (--program) cannot be read again to place the samples: {why}"))
                    }
                    (None, Some((l, w))) if l == DiagnosticStatus::ERROR => event(l, w),
                    _ if input.stale_now => (DiagnosticStatus::STALE, format!("no sample for {:.0} ms", input.stale_after(self.config.stale_timeout) * 1e3)),
                    (None, None) => (DiagnosticStatus::STALE, "no valid sample yet".to_string()),
                    (None, Some((l, w))) => event(l, w),
                };
                let mut values = vec![
                    KeyValue { key: "invalid_samples".into(), value: input.rejected.invalid().to_string() },
                    KeyValue { key: "missing_joint_samples".into(), value: input.rejected.missing_joint.to_string() },
                    KeyValue { key: "non_finite_samples".into(), value: input.rejected.non_finite.to_string() },
                    KeyValue { key: "out_of_range_samples".into(), value: input.rejected.out_of_range.to_string() },
                    KeyValue { key: "out_of_order_samples".into(), value: input.rejected.out_of_order.to_string() },
                    KeyValue { key: "stale_count".into(), value: input.stale.to_string() },
                    KeyValue { key: "lost_samples".into(), value: input.lost.to_string() },
                ];
                if let Some(s) = &input.last {
                    let machine_stream = s.source == AxisState::SOURCE_MACHINE;
                    values.extend([
                        KeyValue { key: "singularity_distance_deg".into(), value: format!("{:.4}", s.singularity_distance.to_degrees()) },
                        KeyValue { key: "predicted_c_speed_rpm".into(), value: format!("{:.2}", s.predicted_c_speed / rpm) },
                        KeyValue { key: "measured_c_speed_rpm".into(), value: format!("{:.2}", s.c_speed / rpm) },
                        KeyValue { key: "path_feed_mm_per_min".into(), value: format!("{:.1}", s.path_feed / crate::units::MM_PER_MIN) },
                        KeyValue { key: "programmed_feed_mm_per_min".into(), value: format!("{:.1}", s.programmed_feed / crate::units::MM_PER_MIN) },
                        KeyValue { key: "region_id".into(), value: s.region_id.to_string() },
                    ]);
                    // A feed limit only where the sample is on a feed move with a known programmed feed.
                    if s.programmed_feed > 0.0 {
                        values.extend([
                            KeyValue { key: "feed_limit_mm_per_min".into(), value: format!("{:.1}", s.feed_limit / crate::units::MM_PER_MIN) },
                            KeyValue { key: "limiting_axis".into(), value: s.limiting_axis.map_or(String::new(), |i| self.machine.axes[i].name.clone()) },
                        ]);
                    }
                    if machine_stream {
                        values.push(KeyValue { key: "feed_source".into(), value: self.feed_source.describe() });
                    }
                }
                DiagnosticStatus { level, name: format!("fiveaxis monitor: {topic}"), message, hardware_id: self.machine.name.clone(), values }
            })
            .collect();
        DiagnosticArray { header: Header { stamp, frame_id: String::new() }, status }
    }

    /// The diagnostics were published: the worst-since-last-report starts again.
    pub fn reported(&mut self) {
        for input in self.inputs.iter_mut() {
            input.worst = None;
        }
    }
}

/// The `/diagnostics` level of one evaluation: ERROR inside a region, WARN near the singularity or a
/// region ahead, OK otherwise.
pub(super) fn level_of(e: &Evaluation, warn_distance: f64, warn_ahead: f64) -> u8 {
    if e.in_region {
        DiagnosticStatus::ERROR
    } else if e.singularity_distance < warn_distance || (e.time_to_next_region > 0.0 && e.time_to_next_region < warn_ahead) {
        DiagnosticStatus::WARN
    } else {
        DiagnosticStatus::OK
    }
}
