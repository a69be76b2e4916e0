//! What the Rerun bridge draws, in people's units and without Rerun: one [`Row`] per axis-state
//! sample (the monitor recomputed on it, seed 001 eq. 5), region [`Event`]s, the roughness profile
//! along x, and the geometry of the orientation view (unit sphere, singular direction and cone).
//! The live bridge and `fiveaxis replay` feed the same [`Scene`], so a replay draws what the live
//! view drew.

use crate::live::monitor::{Monitor, MonitorConfig};
use crate::machine::Machine;
use crate::record::RecordError;
use crate::roughness::Profile;
use crate::units::RPM;
use fiveaxis_msgs::{AxisState, JointState, RosMessage};
use std::collections::BTreeMap;
use std::path::Path;

/// Timeline of the samples' stamps (machine time), seconds since the first sample.
pub const TIMELINE_TIME: &str = "time";
/// Sequence timeline of the workpiece x of the tool tip, in micrometres (Rerun sequences are integers).
pub const TIMELINE_X_UM: &str = "workpiece_x_um";

/// Which stream a sample comes from, as a short label used in entity paths.
pub fn stream_label(source: u8) -> &'static str {
    match source {
        AxisState::SOURCE_COMMANDED => "commanded",
        AxisState::SOURCE_SIMULATED => "simulated",
        _ => "machine",
    }
}

/// One axis-state sample with the monitor's view of it, in mm, degrees, rpm and mm/min.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub topic: String,
    /// `commanded`, `simulated` or `machine`.
    pub stream: &'static str,
    /// Stamp since the first sample of the scene, s.
    pub t_s: f64,
    /// Workpiece x of the tool tip, um, on feed moves mainly along x (None elsewhere).
    pub x_um: Option<i64>,
    pub a_deg: f64,
    pub c_deg: f64,
    /// Names of the two rotary axes (primary, secondary), e.g. A and C.
    pub rotary: [String; 2],
    /// Secondary-axis speed measured on the stream, and predicted by eq. (5) at the programmed feed.
    pub c_speed_rpm: f64,
    pub predicted_c_speed_rpm: f64,
    pub c_limit_rpm: f64,
    /// Angle between the tool axis and the singular direction, degrees.
    pub distance_deg: f64,
    pub programmed_feed_mm_min: f64,
    pub path_feed_mm_min: f64,
    /// Feed the axis limits allow (seed 002 eq. 5) and the axis that sets it ("" = programmed feed).
    pub feed_limit_mm_min: f64,
    pub limiting_axis: String,
    pub tool_tip_mm: [f64; 3],
    pub tool_axis: [f64; 3],
    pub in_region: bool,
}

/// A region boundary on one stream, for the text log.
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    pub stream: &'static str,
    pub t_s: f64,
    pub x_um: Option<i64>,
    /// True when the region starts here, false when it ends.
    pub enters: bool,
    pub text: String,
}

/// The monitor, recomputed per sample, turned into rows and events.
pub struct Scene {
    monitor: Monitor,
    machine: Machine,
    t0: Option<f64>,
    open: BTreeMap<String, (u32, f64, Option<i64>)>,
    last_tip: BTreeMap<String, fiveaxis_msgs::Point>,
    /// Samples the monitor refused (NaN, out of range, out of order), per topic.
    pub rejected: BTreeMap<String, u64>,
}

impl Scene {
    pub fn new(machine: &Machine, config: MonitorConfig) -> Scene {
        Scene { monitor: Monitor::new(machine, config), machine: machine.clone(), t0: None, open: BTreeMap::new(), last_tip: BTreeMap::new(), rejected: BTreeMap::new() }
    }

    /// The machine's speed limit of the secondary (singular) axis, rpm.
    pub fn c_limit_rpm(&self) -> f64 {
        self.machine.axes[self.machine.secondary_axis()].limits.velocity / RPM
    }

    /// The monitor, e.g. to map a machine's JointState onto axes.
    pub fn monitor(&self) -> &Monitor {
        &self.monitor
    }

    /// Feed one sample; returns its row (None when the monitor refused it) and any region events.
    pub fn push(&mut self, topic: &str, st: &AxisState) -> (Option<Row>, Vec<Event>) {
        if st.source == AxisState::SOURCE_COMMANDED {
            self.monitor.on_commanded_ahead(st);
        }
        let t = st.header.stamp.as_secs();
        let status = match self.monitor.on_state(topic, st, t) {
            Ok(s) => s,
            Err(_) => {
                *self.rejected.entry(topic.to_string()).or_default() += 1;
                return (None, Vec::new());
            }
        };
        let t0 = *self.t0.get_or_insert(t);
        let stream = stream_label(st.source);
        let (pi, si) = (self.machine.primary_axis(), self.machine.secondary_axis());
        let tip = status.workpiece_position;
        // On the x timeline: feed moves that go mainly along x (across the part, as a profilometer
        // trace does); approach, retract and parking moves would fold back over the plots.
        let across = self.last_tip.insert(topic.to_string(), tip).is_some_and(|p| {
            let (dx, dy, dz) = (tip.x - p.x, tip.y - p.y, tip.z - p.z);
            let d = (dx * dx + dy * dy + dz * dz).sqrt();
            d > 0.0 && dx.abs() >= 0.5 * d
        });
        let feed_move = st.programmed_feed > 0.0 || st.program_line == 0;
        let x_um = (across && feed_move).then(|| (tip.x * 1e6).round() as i64);
        let row = Row {
            topic: topic.to_string(),
            stream,
            t_s: t - t0,
            x_um,
            a_deg: st.position.get(pi).copied().unwrap_or(f64::NAN).to_degrees(),
            c_deg: st.position.get(si).copied().unwrap_or(f64::NAN).to_degrees(),
            rotary: [self.machine.axes[pi].name.clone(), self.machine.axes[si].name.clone()],
            c_speed_rpm: status.c_speed / RPM,
            predicted_c_speed_rpm: status.predicted_c_speed / RPM,
            c_limit_rpm: status.c_speed_limit / RPM,
            distance_deg: status.singularity_distance.to_degrees(),
            programmed_feed_mm_min: st.programmed_feed * 60e3,
            path_feed_mm_min: st.path_feed * 60e3,
            feed_limit_mm_min: status.feed_limit * 60e3,
            limiting_axis: status.limiting_axis.clone(),
            tool_tip_mm: [tip.x * 1e3, tip.y * 1e3, tip.z * 1e3],
            tool_axis: [st.tool_axis.x, st.tool_axis.y, st.tool_axis.z],
            in_region: status.in_region,
        };
        let mut events = Vec::new();
        let open = self.open.get(topic).copied();
        match (status.in_region, open) {
            (true, None) => {
                self.open.insert(topic.to_string(), (status.region_id, row.t_s, x_um));
                events.push(Event {
                    stream,
                    t_s: row.t_s,
                    x_um,
                    enters: true,
                    text: format!(
                        "{stream}: region {} starts at x {:.3} mm (N{}): predicted {} speed {:.1} rpm > limit {:.1} rpm, {:.3} deg from the singularity",
                        status.region_id, row.tool_tip_mm[0], st.block_number, row.rotary[1], row.predicted_c_speed_rpm.abs(), row.c_limit_rpm, row.distance_deg
                    ),
                });
            }
            (false, Some((id, ..))) => {
                self.open.remove(topic);
                events.push(self.end_event(topic, stream, id, row.t_s, x_um));
            }
            _ => {}
        }
        (Some(row), events)
    }

    fn end_event(&self, topic: &str, stream: &'static str, id: u32, t_s: f64, x_um: Option<i64>) -> Event {
        let r = self.monitor.region(topic, id);
        let text = match r {
            Some(r) => format!(
                "{stream}: region {id} ends at x {:.3} mm ({}): peak predicted C speed {:.1} rpm, feed down to {:.0} mm/min, {:.2} s lost",
                r.x_end_mm, crate::report::block_span(r.block_start, r.block_end, r.line_start, r.line_end), r.peak_c_speed_rpm, r.min_path_feed_mm_per_min, r.time_lost_s
            ),
            None => format!("{stream}: region {id} ends"),
        };
        Event { stream, t_s, x_um, enters: false, text }
    }

    /// End of the streams: close open regions (their end events).
    pub fn finish(&mut self) -> Vec<Event> {
        self.monitor.finish();
        let open = std::mem::take(&mut self.open);
        open.into_iter()
            .map(|(topic, (id, t, x))| {
                let stream = self.monitor.summary().into_iter().find(|s| s.topic == topic).map_or("machine", |s| stream_label(s.source));
                self.end_event(&topic, stream, id, t, x)
            })
            .collect()
    }
}

/// What a replay read.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReplayStats {
    pub messages_read: u64,
    pub rows: u64,
    pub undecodable: u64,
}

/// Replay the axis-state messages of a recording (ours, or JointState from a machine's bridge when
/// it has no AxisState: all JointState topics, joint names = axis names unless `axis_map` says) into
/// `scene`, handing each row and event to `sink` in recording order.
pub fn replay_mcap(
    path: &Path,
    scene: &mut Scene,
    axis_map: &BTreeMap<String, String>,
    mut sink: impl FnMut(Option<&Row>, &[Event]),
) -> Result<ReplayStats, RecordError> {
    let axis_state_type = AxisState::type_name();
    let has_axis_state = crate::record::read::may_carry_type(path, &axis_state_type)?;
    let joint_state_type = JointState::type_name();
    let mut stats = ReplayStats::default();
    let mut state = AxisState::default();
    let mut joints = JointState::default();
    crate::record::read::for_each_message(path, |msg| {
        stats.messages_read += 1;
        let decoded = if msg.channel.schema_name == axis_state_type {
            state.read_cdr(msg.data).is_ok()
        } else if msg.channel.schema_name == joint_state_type && !has_axis_state {
            match joints.read_cdr(msg.data).ok().and_then(|()| scene.monitor().joint_state_to_axis_state(&joints, axis_map).ok()) {
                Some(s) => {
                    state = s;
                    true
                }
                None => false,
            }
        } else {
            return;
        };
        if !decoded {
            stats.undecodable += 1;
            return;
        }
        let (row, events) = scene.push(&msg.channel.topic, &state);
        stats.rows += row.is_some() as u64;
        sink(row.as_ref(), &events);
    })?;
    let events = scene.finish();
    sink(None, &events);
    Ok(stats)
}

/// The roughness profile for plotting: (x um, roughness height um) after the ISO 16610-21 filter, and
/// the sliding-window Ra (x um, Ra um), both along the workpiece x.
pub fn roughness_series(profile: &Profile, lambda_c: f64) -> (Vec<(i64, f64)>, Vec<(i64, f64)>) {
    let r = profile.roughness(lambda_c);
    let heights = profile.x.iter().zip(&r).map(|(x, z)| ((x * 1e6).round() as i64, z * 1e6)).collect();
    let ra = profile.windows(lambda_c, 0.1e-3).iter().map(|w| ((w.x * 1e6).round() as i64, w.ra * 1e6)).collect();
    (heights, ra)
}

/// Great circles of the unit sphere (meridians every 30 deg, the equator and parallels every 30 deg)
/// around `pole`, as polylines of unit vectors.
pub fn sphere_wireframe(pole: [f64; 3]) -> Vec<Vec<[f32; 3]>> {
    let (u, v, w) = basis(pole);
    let point = |lat: f64, lon: f64| -> [f32; 3] {
        let (cl, sl) = (lat.cos(), lat.sin());
        std::array::from_fn(|i| (cl * (lon.cos() * u[i] + lon.sin() * v[i]) + sl * w[i]) as f32)
    };
    let mut lines = Vec::new();
    for k in 0..6 {
        let lon = (k as f64 * 30.0).to_radians();
        lines.push((0..=72).map(|j| point((j as f64 * 5.0 - 180.0).to_radians(), lon)).collect());
    }
    for lat in [-60.0f64, -30.0, 0.0, 30.0, 60.0] {
        lines.push((0..=72).map(|j| point(lat.to_radians(), (j as f64 * 5.0).to_radians())).collect());
    }
    lines
}

/// The singular cone: tool axes within `half_angle` (rad) of the singular direction `s` (and of -s),
/// as two circles on the unit sphere plus four generators from the centre.
pub fn singular_cone(s: [f64; 3], half_angle: f64) -> Vec<Vec<[f32; 3]>> {
    let (u, v, w) = basis(s);
    let mut lines = Vec::new();
    for sign in [1.0, -1.0] {
        let at = |lon: f64| -> [f32; 3] {
            std::array::from_fn(|i| (half_angle.sin() * (lon.cos() * u[i] + lon.sin() * v[i]) + sign * half_angle.cos() * w[i]) as f32)
        };
        lines.push((0..=72).map(|j| at((j as f64 * 5.0).to_radians())).collect());
        for k in 0..4 {
            lines.push(vec![[0.0; 3], at((k as f64 * 90.0).to_radians())]);
        }
    }
    lines
}

/// An orthonormal basis (u, v, w) with w along `dir`.
fn basis(dir: [f64; 3]) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let w = nalgebra::Vector3::from(dir).normalize();
    let helper = if w.x.abs() < 0.9 { nalgebra::Vector3::x() } else { nalgebra::Vector3::y() };
    let u = helper.cross(&w).normalize();
    let v = w.cross(&u);
    (u.into(), v.into(), w.into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_and_cone_lie_on_the_unit_sphere_at_the_right_angle() {
        for line in sphere_wireframe([0.0, 0.0, 1.0]) {
            for p in line {
                let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                assert!((n - 1.0).abs() < 1e-6);
            }
        }
        let s = [0.0, 0.6, 0.8];
        let cone = singular_cone(s, 10f64.to_radians());
        for p in &cone[0] {
            let cos = p[0] as f64 * s[0] + p[1] as f64 * s[1] + p[2] as f64 * s[2];
            assert!((cos.acos().to_degrees() - 10.0).abs() < 1e-4, "{cos}");
        }
    }
}
