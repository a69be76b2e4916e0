//! What the Rerun bridge draws, in people's units and without Rerun: one [`Row`] per axis-state
//! sample (the monitor recomputed on it, seed 001 eq. 5), region [`Event`]s, the roughness profile
//! along x, and the geometry of the orientation view (unit sphere, singular direction and cone).
//! The live bridge and `fiveaxis replay` feed the same [`Scene`], so a replay draws what the live
//! view drew.

use crate::kinematics::Joints;
use crate::live::monitor::{Monitor, MonitorConfig, Rejection};
use crate::machine::Machine;
use crate::record::RecordError;
use crate::live::joint_map::unmapped_hint;
use crate::recorded::{read_states, Selection, StatesRead, Unread};
use crate::roughness::Profile;
use crate::units::{mm_per_min, RPM};
use fiveaxis_msgs::AxisState;
use std::collections::BTreeMap;
use std::path::Path;

/// Timeline of the samples' stamps (machine time), seconds since the first sample.
pub const TIMELINE_TIME: &str = "time";

/// A cutting pass runs along the workpiece x: each step of the tool tip within this angle of the x axis.
pub const PASS_MAX_ANGLE_DEG: f64 = 20.0;
/// Passes shorter than this along x (mm) are not drawn across the part (corners, short links).
pub const PASS_MIN_LENGTH_MM: f64 = 1.0;
/// Default height band of the passes in contact, mm: a pass whose lowest tool-tip z is more than this
/// above the lowest pass is taken for a move at a clearance height (the view has no stock model).
pub const CONTACT_BAND_MM: f64 = 10.0;
/// Steps shorter than this (mm) are rests: they neither start nor end a pass.
const REST_MM: f64 = 1e-6;

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
    /// The pass along x this sample belongs to (None: not on a pass; see [`PassTracker`]).
    pub pass: Option<PassMark>,
    pub a_deg: f64,
    pub c_deg: f64,
    /// Every axis value in the machine's axis order (m, rad; NaN where the message has none).
    pub q: crate::kinematics::Joints,
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
    /// True when the region starts here, false when it ends.
    pub enters: bool,
    pub text: String,
}

/// A sample's place on a pass along x: the pass number on its stream (1-based, in order; a pass that
/// ends shorter than [`PASS_MIN_LENGTH_MM`] gives its number to the next), and whether this sample
/// starts it (a consumer drops what it kept of an earlier pass of that number).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PassMark {
    pub id: u32,
    pub starts: bool,
}

/// Splits one stream into passes across the part, the stretches a profilometer trace lines up with:
/// feed moves (or moves of unknown kind, from a machine) whose every step of the tool tip (workpiece
/// frame) runs within [`PASS_MAX_ANGLE_DEG`] of x, one way. Rests stay in the pass; rapids, rotary-only
/// moves, dwells, a step off x or a reversal end it. Whether a pass is in contact with the part is
/// [`in_contact`]'s question.
#[derive(Debug, Clone, Default)]
pub struct PassTracker {
    last: Option<[f64; 3]>,
    /// The open pass: number, direction along x (+1/-1), x where it started, x travelled so far (mm).
    open: Option<(u32, f64, f64, f64)>,
    /// Passes that reached the minimum length.
    done: u32,
}

impl PassTracker {
    /// The pass of a sample at tool tip `tip_mm` (workpiece frame) of motion kind `motion` (AxisState::MOTION_*).
    pub fn step(&mut self, tip_mm: [f64; 3], motion: u8) -> Option<PassMark> {
        let last = self.last.replace(tip_mm);
        if !matches!(motion, AxisState::MOTION_FEED | AxisState::MOTION_UNKNOWN) {
            self.close();
            return None;
        }
        let p = last?;
        let d: [f64; 3] = std::array::from_fn(|i| tip_mm[i] - p[i]);
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if !len.is_finite() {
            self.close();
            return None;
        }
        if len < REST_MM {
            return self.open.map(|(id, ..)| PassMark { id, starts: false });
        }
        let along_x = d[0].abs() >= PASS_MAX_ANGLE_DEG.to_radians().cos() * len;
        let dir = d[0].signum();
        match self.open {
            Some((id, open_dir, x0, _)) if along_x && open_dir == dir => {
                self.open = Some((id, dir, x0, (tip_mm[0] - x0).abs()));
                Some(PassMark { id, starts: false })
            }
            _ => {
                self.close();
                if !along_x {
                    return None;
                }
                let id = self.done + 1;
                // The pass starts at the previous sample, where the tip began to move along x.
                self.open = Some((id, dir, p[0], (tip_mm[0] - p[0]).abs()));
                Some(PassMark { id, starts: true })
            }
        }
    }

    fn close(&mut self) {
        if let Some((.., travel)) = self.open.take() {
            if travel >= PASS_MIN_LENGTH_MM {
                self.done += 1;
            }
        }
    }
}

/// True when a pass whose lowest tool-tip z is `pass_z_min_mm` touches the part, given the lowest
/// pass of the run so far (`floor_mm`) and the contact band (mm, [`CONTACT_BAND_MM`] by default): a
/// pass well above the others runs at a clearance height (a retract or a repositioning move).
pub fn in_contact(pass_z_min_mm: f64, floor_mm: f64, band_mm: f64) -> bool {
    pass_z_min_mm <= floor_mm + band_mm
}

/// Rigid transform of one moving part of the machine, relative to its parent: `p' = rotation * p +
/// translation`, rotation as a unit quaternion `[x, y, z, w]`, translation in mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartPose {
    pub rotation_xyzw: [f64; 4],
    pub translation_mm: [f64; 3],
}

/// The machine's moving parts at axis values `q` (m, rad), each relative to the one that carries it,
/// as a 3D view draws them (seed 001 eq. 1): the table joints in the order of the chain's
/// [`table_slots`](crate::kinematics::TwoRotaryChain::table_slots) (the workpiece rides on the
/// last), then the head: the linear axes' translation, then the head joints in the order of its
/// [`head_slots`](crate::kinematics::TwoRotaryChain::head_slots) (the tool rides on the last).
pub struct MachinePose {
    pub table: Vec<PartPose>,
    pub head_linear_mm: [f64; 3],
    pub head: Vec<PartPose>,
}

/// The pose of the machine's parts at `q` (see [`MachinePose`]); composing them maps the workpiece
/// frame and the tool frame into the machine frame as [`Machine::forward`] does.
pub fn machine_pose(machine: &Machine, q: &crate::kinematics::Joints) -> MachinePose {
    let chain = &machine.chain;
    let parts = |slots: &[usize]| -> Vec<PartPose> {
        slots
            .iter()
            .map(|&slot| {
                let turn = chain.joints()[slot].turn(q[3 + slot]);
                let (r, t) = (turn.rotation.coords, turn.translation.vector * 1e3);
                PartPose { rotation_xyzw: [r.x, r.y, r.z, r.w], translation_mm: [t.x, t.y, t.z] }
            })
            .collect()
    };
    MachinePose { table: parts(chain.table_slots()), head_linear_mm: [q[0] * 1e3, q[1] * 1e3, q[2] * 1e3], head: parts(chain.head_slots()) }
}

/// The monitor, recomputed per sample, turned into rows and events.
pub struct Scene {
    monitor: Monitor,
    machine: Machine,
    t0: Option<f64>,
    open: BTreeMap<String, (u32, f64)>,
    passes: BTreeMap<String, PassTracker>,
    /// Samples refused (a joint missing, NaN, out of range, out of order), per topic.
    pub rejected: BTreeMap<String, u64>,
}

impl Scene {
    pub fn new(machine: &Machine, config: MonitorConfig) -> Scene {
        Scene { monitor: Monitor::new(machine, config), machine: machine.clone(), t0: None, open: BTreeMap::new(), passes: BTreeMap::new(), rejected: BTreeMap::new() }
    }

    /// The machine's speed limit of the secondary (singular) axis, rpm.
    pub fn c_limit_rpm(&self) -> f64 {
        self.machine.axes[self.machine.secondary_axis()].limits.velocity / RPM
    }

    /// The monitor, e.g. to map a machine's JointState onto axes.
    pub fn monitor(&self) -> &Monitor {
        &self.monitor
    }

    /// The machine the scene is drawn for.
    pub fn machine(&self) -> &Machine {
        &self.machine
    }

    /// Stream `topic`'s source starts a session (its stamps start over; `change_only`: it reports
    /// values only when they change).
    pub fn new_session(&mut self, topic: &str, change_only: bool) {
        let id = self.monitor.input(topic);
        self.monitor.new_session(id);
        self.monitor.set_change_only(id, change_only);
    }

    /// Count a sample refused before the monitor (a JointState that does not map onto the axes).
    pub fn reject(&mut self, topic: &str, why: &Rejection) {
        let id = self.monitor.input(topic);
        self.monitor.reject(id, why);
        *self.rejected.entry(topic.to_string()).or_default() += 1;
    }

    /// Feed one sample; returns its row (None when the monitor refused it) and any region events.
    pub fn push(&mut self, topic: &str, st: &AxisState) -> (Option<Row>, Vec<Event>) {
        self.push_merged(topic, st, None)
    }

    /// [`Scene::push`] of a pose merged from per-axis reports, with how far each axis may be off in
    /// it (SI).
    pub fn push_merged(&mut self, topic: &str, st: &AxisState, uncertainty: Option<&Joints>) -> (Option<Row>, Vec<Event>) {
        if st.source == AxisState::SOURCE_COMMANDED {
            self.monitor.on_commanded_ahead(st);
        }
        let t = st.header.stamp.as_secs();
        let status = match self.monitor.on_merged_state(topic, st, uncertainty, t) {
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
        let tip_mm = [tip.x * 1e3, tip.y * 1e3, tip.z * 1e3];
        let pass = self.passes.entry(topic.to_string()).or_default().step(tip_mm, st.motion);
        let q: crate::kinematics::Joints = std::array::from_fn(|i| st.position.get(i).copied().unwrap_or(f64::NAN));
        let row = Row {
            topic: topic.to_string(),
            stream,
            t_s: t - t0,
            pass,
            a_deg: q[pi].to_degrees(),
            c_deg: q[si].to_degrees(),
            q,
            rotary: [self.machine.axes[pi].name.clone(), self.machine.axes[si].name.clone()],
            c_speed_rpm: status.c_speed / RPM,
            predicted_c_speed_rpm: status.predicted_c_speed / RPM,
            c_limit_rpm: status.c_speed_limit / RPM,
            distance_deg: status.singularity_distance.to_degrees(),
            programmed_feed_mm_min: mm_per_min(st.programmed_feed),
            path_feed_mm_min: mm_per_min(st.path_feed),
            feed_limit_mm_min: mm_per_min(status.feed_limit),
            limiting_axis: status.limiting_axis.clone(),
            tool_tip_mm: tip_mm,
            tool_axis: [st.tool_axis.x, st.tool_axis.y, st.tool_axis.z],
            in_region: status.in_region,
        };
        let mut events = Vec::new();
        let open = self.open.get(topic).copied();
        match (status.in_region, open) {
            (true, None) => {
                self.open.insert(topic.to_string(), (status.region_id, row.t_s));
                events.push(Event {
                    stream,
                    t_s: row.t_s,
                    enters: true,
                    text: format!(
                        "{stream}: region {} starts at x {:.3} mm (N{}): predicted {} speed {:.1} rpm > limit {:.1} rpm, {:.3} deg from the singularity",
                        status.region_id, row.tool_tip_mm[0], st.block_number, row.rotary[1], row.predicted_c_speed_rpm.abs(), row.c_limit_rpm, row.distance_deg
                    ),
                });
            }
            (false, Some((id, ..))) => {
                self.open.remove(topic);
                events.push(self.end_event(topic, stream, id, row.t_s));
            }
            _ => {}
        }
        (Some(row), events)
    }

    fn end_event(&self, topic: &str, stream: &'static str, id: u32, t_s: f64) -> Event {
        let r = self.monitor.region(topic, id);
        let text = match r {
            Some(r) => format!(
                "{stream}: region {id} ends at x {:.3} mm ({}): peak predicted C speed {:.1} rpm, feed down to {:.0} mm/min, {} s lost",
                r.x_end_mm, crate::report::block_span(r.block_start, r.block_end, r.line_start, r.line_end), r.peak_c_speed_rpm, r.min_path_feed_mm_per_min, crate::report::seconds(r.time_lost_s)
            ),
            None => format!("{stream}: region {id} ends"),
        };
        Event { stream, t_s, enters: false, text }
    }

    /// End of the streams: close open regions (their end events).
    pub fn finish(&mut self) -> Vec<Event> {
        self.monitor.finish();
        let open = std::mem::take(&mut self.open);
        open.into_iter()
            .map(|(topic, (id, t))| {
                let stream = self.monitor.summary().into_iter().find(|s| s.topic == topic).map_or("machine", |s| stream_label(s.source));
                self.end_event(&topic, stream, id, t)
            })
            .collect()
    }
}

/// What a replay read, and how many rows it drew.
#[derive(Debug)]
pub struct ReplayStats {
    /// The messages, streams (topics, JointState joint names) and JointState topics of the recording.
    pub read: StatesRead,
    pub rows: u64,
}

impl ReplayStats {
    /// What the replay could not draw, as `fiveaxis analyze` says it: (errors: a JointState topic
    /// asked for and absent, or no stream at all; streams read of which no sample was drawn, a
    /// JointState's with the joints found and the axis map to give).
    pub fn input_errors(&self, scene: &Scene, selection: &Selection) -> (Vec<String>, Vec<String>) {
        let errors = self.read.selection_errors(selection);
        let summary = scene.monitor().summary();
        let undrawn = self
            .read
            .streams
            .iter()
            .filter_map(|s| {
                let input = summary.iter().find(|i| i.topic == s.topic);
                if input.is_some_and(|i| i.samples > 0) {
                    return None;
                }
                let refused = scene.rejected.get(&s.topic).copied().unwrap_or(0);
                Some(match (&s.joint_names, input) {
                    (Some(names), Some(i)) if i.rejected.missing_joint > 0 => format!(
                        "{}: no sample drawn, {refused} without a joint for every machine axis; {}",
                        s.topic,
                        unmapped_hint(scene.machine(), names, &selection.axis_map)
                    ),
                    _ => format!("{}: no sample drawn ({refused} refused, {} undecodable)", s.topic, s.undecodable),
                })
            })
            .collect();
        (errors, undrawn)
    }
}

/// Replay the axis-state messages of a recording into `scene`, handing each row and event to `sink`
/// in recording order. The streams are those `analyze` reads ([`crate::recorded`]): our AxisState,
/// or a machine bridge's JointState (joints named as `selection` says). Damage after good messages
/// is an error once those were handed on.
pub fn replay_mcap(path: &Path, scene: &mut Scene, selection: &Selection, mut sink: impl FnMut(Option<&Row>, &[Event])) -> Result<ReplayStats, RecordError> {
    let mut rows = 0;
    let machine = scene.machine().clone();
    let read = read_states(path, &machine, selection, &mut |_, _| {}, |msg| match msg.sample {
        Ok(state) => {
            let (row, events) = scene.push_merged(msg.topic, state, msg.uncertainty.as_ref());
            rows += row.is_some() as u64;
            sink(row.as_ref(), &events);
        }
        Err(Unread::Unmapped(e)) => scene.reject(msg.topic, &e),
        Err(Unread::Session { change_only }) => scene.new_session(msg.topic, change_only),
        Err(Unread::Undecodable) => {}
    })?;
    let mut read = read;
    if let Some(e) = read.damage.take() {
        return Err(e);
    }
    let events = scene.finish();
    sink(None, &events);
    Ok(ReplayStats { read, rows })
}

/// The roughness profile for plotting: (x mm, roughness height um) after the ISO 16610-21 filter, and
/// the sliding-window Ra (x mm, Ra um), both along the workpiece x.
pub fn roughness_series(profile: &Profile, lambda_c: f64) -> (Vec<(f64, f64)>, Vec<(f64, f64)>) {
    let r = profile.roughness(lambda_c);
    let heights = profile.x.iter().zip(&r).map(|(x, z)| (x * 1e3, z * 1e6)).collect();
    let ra = profile.windows(lambda_c, 0.1e-3).iter().map(|w| (w.x * 1e3, w.ra * 1e6)).collect();
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

    /// The parts' transforms, composed as a 3D view composes its entity tree, put the workpiece point
    /// under the tool tip (from the chain's forward transform) where the head puts the tool tip, and
    /// turn the tool axis alike: on every built-in machine (table/table, table/head, head/head).
    #[test]
    fn machine_pose_composes_to_the_forward_transform() {
        use nalgebra::{Quaternion, UnitQuaternion, Vector3};
        let apply = |parts: &[PartPose], p: Vector3<f64>, is_point: bool| {
            parts.iter().rev().fold(p, |v, pp| {
                let [x, y, z, w] = pp.rotation_xyzw;
                let r = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
                r * v + if is_point { Vector3::from(pp.translation_mm) * 1e-3 } else { Vector3::zeros() }
            })
        };
        for name in crate::machine::BUILTIN_NAMES {
            let m = Machine::builtin(name).unwrap();
            for k in 0..20 {
                let f = k as f64;
                let q = [0.01 * f - 0.1, 0.2 - 0.02 * f, 0.05 * f.sin(), 0.3 * f.cos() - 0.2, 0.7 * f - 3.0];
                let pose = machine_pose(&m, &q);
                let fwd = m.forward(&q);
                let from_table = apply(&pose.table, fwd.tip, true);
                let from_head = Vector3::from(pose.head_linear_mm) * 1e-3 + apply(&pose.head, m.chain.tool_tip(), true);
                assert!((from_table - from_head).norm() < 1e-9, "{name} q {q:?}: {from_table} vs {from_head}");
                let axis_table = apply(&pose.table, fwd.axis, false);
                let axis_head = apply(&pose.head, m.chain.tool_axis(), false);
                assert!((axis_table - axis_head).norm() < 1e-9, "{name} q {q:?}: axis {axis_table} vs {axis_head}");
            }
        }
    }

    /// Passes on a path written out by hand: an approach, a cut along +x (with a rest in it), a step
    /// along y, a 0.5 mm stub along x, a return along -x, a rapid and a diagonal.
    #[test]
    fn passes_follow_feed_moves_along_x() {
        let mut tr = PassTracker::default();
        let feed = AxisState::MOTION_FEED;
        let mut marks = Vec::new();
        let mut go = |tr: &mut PassTracker, from: [f64; 3], to: [f64; 3], n: usize, motion: u8| {
            for i in 1..=n {
                let u = i as f64 / n as f64;
                marks.push((std::array::from_fn::<f64, 3, _>(|k| from[k] + u * (to[k] - from[k])), tr.step(std::array::from_fn(|k| from[k] + u * (to[k] - from[k])), motion)));
            }
        };
        tr.step([0.0, -20.0, 100.0], feed);
        go(&mut tr, [0.0, -20.0, 100.0], [0.0, -20.0, -8.0], 10, feed); // plunge
        go(&mut tr, [0.0, -20.0, -8.0], [0.0, 0.0, -8.0], 10, feed); // lead-in along y
        go(&mut tr, [0.0, 0.0, -8.0], [25.0, 0.0, -8.0], 25, feed); // cut
        go(&mut tr, [25.0, 0.0, -8.0], [25.0, 0.0, -8.0], 5, feed); // rest
        go(&mut tr, [25.0, 0.0, -8.0], [50.0, 0.0, -8.0], 25, feed);
        go(&mut tr, [50.0, 0.0, -8.0], [50.0, 1.0, -8.0], 2, feed); // step over
        go(&mut tr, [50.0, 1.0, -8.0], [49.5, 1.0, -8.0], 5, feed); // stub, too short
        go(&mut tr, [49.5, 1.0, -8.0], [49.5, 1.2, -8.0], 2, feed);
        go(&mut tr, [49.5, 1.2, -8.0], [0.0, 1.2, -8.0], 50, feed); // return pass
        go(&mut tr, [0.0, 1.2, -8.0], [30.0, 1.2, 100.0], 10, AxisState::MOTION_RAPID);
        go(&mut tr, [30.0, 1.2, 100.0], [60.0, 20.0, 100.0], 10, feed); // 32 deg off x
        let ids = |lo: usize, hi: usize| marks[lo..hi].iter().map(|(_, m)| m.map(|m| m.id)).collect::<Vec<_>>();
        assert!(ids(0, 20).iter().all(Option::is_none), "plunge and lead-in are not passes");
        assert!(ids(20, 75).iter().all(|m| *m == Some(1)), "the cut, rest included, is pass 1");
        assert_eq!(marks[20].1, Some(PassMark { id: 1, starts: true }));
        assert!(ids(75, 77).iter().all(Option::is_none));
        assert!(ids(77, 82).iter().all(|m| *m == Some(2)), "the stub is tried as pass 2");
        assert_eq!(marks[84].1, Some(PassMark { id: 2, starts: true }), "the stub was short: the return pass takes its number");
        assert!(ids(84, 134).iter().all(|m| *m == Some(2)));
        assert!(ids(134, 154).iter().all(Option::is_none), "rapid and diagonal");
        assert!(in_contact(-8.0, -8.0, CONTACT_BAND_MM) && !in_contact(112.0, -8.0, CONTACT_BAND_MM));
    }

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
