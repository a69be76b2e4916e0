//! A monitored stream's regions, closed from its full-rate status: the samples the monitor marked
//! `in_region` with one `region_id` (the monitor decides what a region is; this only gathers them), so
//! that a head office that sees a rate-capped status still gets every region whole.

use fiveaxis_msgs::{Header, Region, SingularityStatus};
use std::collections::BTreeMap;

/// The open region of each input topic.
#[derive(Debug, Default)]
pub struct RegionTracker {
    open: BTreeMap<String, Region>,
}

impl RegionTracker {
    pub fn new() -> RegionTracker {
        RegionTracker::default()
    }

    /// Take one status; the region it closes, if any. Statuses repeated while the input is stale
    /// (`stale`) neither open nor close a region.
    pub fn on_status(&mut self, s: &SingularityStatus) -> Option<Region> {
        if s.stale {
            return None;
        }
        let continues = matches!(self.open.get(&s.input_topic), Some(r) if s.in_region && r.region_id == s.region_id);
        if continues {
            let r = self.open.get_mut(&s.input_topic)?;
            r.end = s.header.stamp;
            r.end_position = s.workpiece_position;
            r.end_line = s.program_line;
            r.min_singularity_distance = r.min_singularity_distance.min(s.singularity_distance);
            r.peak_predicted_c_speed = r.peak_predicted_c_speed.max(s.predicted_c_speed);
            r.c_speed_limit = s.c_speed_limit;
            r.samples += 1;
            return None;
        }
        let closed = self.open.remove(&s.input_topic).map(|mut r| {
            r.header = Header { stamp: s.header.stamp, frame_id: s.header.frame_id.clone() };
            r
        });
        if s.in_region && self.open.len() < crate::MAX_STREAMS {
            self.open.insert(
                s.input_topic.clone(),
                Region {
                    header: s.header.clone(),
                    input_topic: s.input_topic.clone(),
                    region_id: s.region_id,
                    cause: s.region_cause,
                    start: s.header.stamp,
                    end: s.header.stamp,
                    start_position: s.workpiece_position,
                    end_position: s.workpiece_position,
                    min_singularity_distance: s.singularity_distance,
                    peak_predicted_c_speed: s.predicted_c_speed,
                    c_speed_limit: s.c_speed_limit,
                    start_line: s.program_line,
                    end_line: s.program_line,
                    samples: 1,
                },
            );
        }
        closed
    }

    /// The regions still open (the stream ended inside them), closed at their last sample.
    pub fn finish(&mut self) -> Vec<Region> {
        std::mem::take(&mut self.open)
            .into_values()
            .map(|mut r| {
                r.header.stamp = r.end;
                r
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fiveaxis_msgs::{Point, Time};

    fn status(t: f64, x_mm: f64, region: u32, c_rad_s: f64) -> SingularityStatus {
        SingularityStatus {
            header: Header { stamp: Time::from_secs(t), frame_id: String::new() },
            input_topic: "/fiveaxis/simulated/axis_state".into(),
            in_region: region > 0,
            region_id: region,
            region_cause: if region > 0 { SingularityStatus::CAUSE_SINGULARITY } else { 0 },
            workpiece_position: Point { x: x_mm * 1e-3, y: 0.0, z: 0.0 },
            predicted_c_speed: c_rad_s,
            singularity_distance: 0.1 / (1.0 + c_rad_s),
            c_speed_limit: 2.618,
            program_line: (x_mm as u32) + 1,
            ..Default::default()
        }
    }

    #[test]
    fn a_region_is_its_samples_from_first_to_last() {
        let mut t = RegionTracker::new();
        let mut closed = Vec::new();
        // Outside, then region 1 over x 22..28 mm peaking at 20 rad/s at x 25, a stale repeat in it,
        // then region 2 straight after region 1 (no sample outside between), then outside.
        let mut stream: Vec<SingularityStatus> = (0..20).map(|i| status(i as f64 * 0.01, i as f64, 0, 0.5)).collect();
        for i in 22..=28 {
            stream.push(status(i as f64 * 0.01, i as f64, 1, 20.0 - (i as f64 - 25.0).abs()));
        }
        let mut repeat = status(0.285, 28.0, 1, 99.0);
        repeat.stale = true;
        stream.push(repeat);
        stream.push(status(0.29, 29.0, 2, 5.0));
        stream.push(status(0.30, 30.0, 0, 0.5));
        for s in &stream {
            closed.extend(t.on_status(s));
        }
        assert!(t.finish().is_empty());
        assert_eq!(closed.len(), 2);
        let r = &closed[0];
        assert_eq!((r.region_id, r.samples, r.start_line, r.end_line), (1, 7, 23, 29));
        assert!((r.start_position.x - 0.022).abs() < 1e-12 && (r.end_position.x - 0.028).abs() < 1e-12);
        assert_eq!(r.peak_predicted_c_speed, 20.0);
        assert!((r.min_singularity_distance - 0.1 / 21.0).abs() < 1e-15);
        assert_eq!(r.header.stamp, Time::from_secs(0.29), "closed by the next sample");
        assert_eq!(r.cause, SingularityStatus::CAUSE_SINGULARITY);
        assert_eq!((closed[1].region_id, closed[1].samples), (2, 1));
    }

    #[test]
    fn a_region_open_at_the_end_is_closed_at_its_last_sample() {
        let mut t = RegionTracker::new();
        assert!(t.on_status(&status(1.0, 22.0, 3, 4.0)).is_none());
        assert!(t.on_status(&status(1.1, 23.0, 3, 4.0)).is_none());
        let left = t.finish();
        assert_eq!(left.len(), 1);
        assert_eq!((left[0].region_id, left[0].samples, left[0].header.stamp), (3, 2, Time::from_secs(1.1)));
    }

    #[test]
    fn regions_open_on_at_most_the_streams_followed() {
        let mut t = RegionTracker::new();
        for k in 0..100 {
            let mut s = status(0.0, 1.0, 1, 20.0);
            s.input_topic = format!("/fiveaxis/x{k}/axis_state");
            t.on_status(&s);
        }
        assert_eq!(t.open.len(), crate::MAX_STREAMS);
    }
}
