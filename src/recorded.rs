//! Axis states out of a recording: which channels carry them and how each message reads (our
//! AxisState as is; a machine bridge's JointState mapped onto the machine's axes by
//! [`JointMap`]). One rule for `fiveaxis analyze` and `replay`, so both see the same streams.
//!
//! The rule: every AxisState channel; JointState channels on the topics asked for, or, when none
//! are asked for, every JointState channel of a recording that has no AxisState (a machine bridge's
//! bag).

use crate::live::joint_map::JointMap;
use crate::live::joint_stream::JointStream;
use crate::live::monitor::Rejection;
use crate::kinematics::Joints;
use crate::machine::Machine;
use crate::record::{read, RecordError};
use fiveaxis_msgs::{AxisState, JointState, RosMessage};
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Which JointState streams to read and how their joints map onto the machine's axes.
#[derive(Debug, Clone, Default)]
pub struct Selection {
    /// JointState topics to read (empty: all, when the recording has no AxisState).
    pub joint_state_topics: Vec<String>,
    /// Machine axis -> joint name in those JointStates (an MTConnect log: data item id or name).
    pub axis_map: BTreeMap<String, String>,
    /// Read the recording as an MTConnect adapter's SHDR log against this device description.
    pub mtconnect: Option<MtconnectSource>,
}

/// An SHDR log's device: its description (an agent's `Devices.xml` or `/probe` answer) and which
/// device of it (None: the only one).
#[derive(Debug, Clone, Default)]
pub struct MtconnectSource {
    pub devices: std::path::PathBuf,
    pub device: Option<String>,
}

/// One stream read: a topic carrying axis states, numbered in order of its first message.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedStream {
    pub topic: String,
    /// A machine bridge's JointState stream (else our AxisState).
    pub joint_state: bool,
    /// JointState streams: the joint names of the first message that decoded.
    pub joint_names: Option<Vec<String>>,
    /// Messages that did not decode.
    pub undecodable: u64,
    /// An MTConnect adapter's log (its values converted to SI from the units the device states).
    pub mtconnect: bool,
    /// JointState and MTConnect streams: the longest a pose waited for every axis to be known at its
    /// instant, s (the latency the per-axis merge cost; [`JointStream`]).
    pub merge_latency_s: Option<f64>,
}

/// Why a message of a read stream gave no axis state.
#[derive(Debug, Clone, PartialEq)]
pub enum Unread {
    /// Not valid CDR of its type.
    Undecodable,
    /// A JointState whose joints do not map onto the machine's axes.
    Unmapped(Rejection),
    /// The stream's source starts a session here (an SHDR log's start, and each time its adapter
    /// connected again): what follows is judged afresh. `change_only`: the source reports a value
    /// only when it changed (SHDR), so gaps between its samples are no evidence of losses.
    Session { change_only: bool },
}

/// One message of a read stream.
#[derive(Debug)]
pub struct Recorded<'a> {
    /// The stream's number (index into [`StatesRead::streams`], in order of first message).
    pub stream: usize,
    pub topic: &'a str,
    /// Receive time, ns.
    pub log_time: u64,
    pub sample: Result<&'a AxisState, Unread>,
    /// A pose merged from per-axis reports: how far each axis may be off in it (SI).
    pub uncertainty: Option<Joints>,
}

/// What reading the recording found.
#[derive(Debug)]
pub struct StatesRead {
    /// Every message of the recording, of any topic.
    pub messages_read: u64,
    pub streams: Vec<RecordedStream>,
    /// Every JointState topic of the recording, read or not (to name them when one asked for is absent).
    pub joint_state_topics: BTreeSet<String>,
    /// Why reading stopped before the end (a damaged or cut recording): what came before it was read.
    pub damage: Option<RecordError>,
    /// The first malformed message of a stream, where the format says where (an SHDR log's line
    /// and column), by stream number.
    pub first_malformed: BTreeMap<usize, String>,
}

impl StatesRead {
    /// Messages of read streams that did not decode.
    pub fn undecodable(&self) -> u64 {
        self.streams.iter().map(|s| s.undecodable).sum()
    }

    /// What the selection asked for and the recording lacks: a JointState topic absent, or no
    /// stream to read at all (bad input for every reader of the recording).
    pub fn selection_errors(&self, selection: &Selection) -> Vec<String> {
        selection_errors(selection, &self.joint_state_topics, self.streams.is_empty())
    }
}

/// [`StatesRead::selection_errors`] from what a read found: every JointState topic of the
/// recording, and whether any stream was read.
pub fn selection_errors(selection: &Selection, joint_state_topics: &BTreeSet<String>, no_stream: bool) -> Vec<String> {
    let list = || if joint_state_topics.is_empty() { "none".to_string() } else { joint_state_topics.iter().cloned().collect::<Vec<_>>().join(", ") };
    let mut errors: Vec<String> = selection
        .joint_state_topics
        .iter()
        .filter(|t| !joint_state_topics.contains(*t))
        .map(|t| format!("JointState topic '{t}' is not in the recording (JointState topics there: {})", list()))
        .collect();
    if no_stream && errors.is_empty() {
        errors.push(format!("no AxisState or JointState stream in the recording (JointState topics: {})", list()));
    }
    errors
}

/// How the messages of a channel are read.
#[derive(Clone, Copy)]
enum Decode {
    AxisState(usize),
    JointState(usize),
    Skip,
}

/// Read the axis states of the recording at `path` (an MCAP file or a rosbag2 directory) in
/// recording order, handing each message of a read stream to `visit`; `progress(bytes read, file
/// size)` is called now and then. Streamed: memory stays flat whatever the recording's size. An
/// unreadable recording is an error; damage after good messages ends the read with
/// [`StatesRead::damage`] set.
pub fn read_states(
    path: &Path,
    machine: &Machine,
    selection: &Selection,
    // Dynamic, so that a progress bar's code stays out of the per-message loop (called rarely).
    progress: &mut dyn FnMut(u64, u64),
    mut visit: impl FnMut(Recorded<'_>),
) -> Result<StatesRead, RecordError> {
    if let Some(source) = &selection.mtconnect {
        return read_shdr(path, machine, selection, source, progress, visit);
    }
    let file_len = read::recording_len(path)?;
    let axis_state_type = AxisState::type_name();
    let joint_state_type = JointState::type_name();
    let has_axis_state = read::may_carry_type(path, &axis_state_type)?;
    let map = JointMap::new(machine, &selection.axis_map);
    let mut out = StatesRead { messages_read: 0, streams: Vec::new(), joint_state_topics: BTreeSet::new(), damage: None, first_malformed: BTreeMap::new() };
    let mut by_topic: BTreeMap<String, usize> = BTreeMap::new();
    // By channel id, in the current file (a rosbag2 directory's files number channels anew).
    let mut decode: Vec<Option<Decode>> = Vec::new();
    let mut file = 0;
    let mut state = AxisState::default();
    let mut joints = JointState::default();
    // JointState streams (by stream number): each message's joints merged into whole poses.
    let mut merges: Vec<Option<JointStream>> = Vec::new();
    let result = read::for_each_message(path, |msg| {
        out.messages_read += 1;
        if out.messages_read.is_multiple_of(65_536) {
            progress(msg.file_position, file_len);
        }
        if msg.file != file {
            file = msg.file;
            decode.clear();
        }
        let slot = usize::from(msg.channel.id);
        if decode.len() <= slot {
            decode.resize(slot + 1, None);
        }
        let how = *decode[slot].get_or_insert_with(|| {
            let c = msg.channel;
            let is_joint_state = c.schema_name == joint_state_type;
            if is_joint_state {
                out.joint_state_topics.insert(c.topic.clone());
            }
            let joint = is_joint_state
                && (selection.joint_state_topics.contains(&c.topic) || (selection.joint_state_topics.is_empty() && !has_axis_state));
            if c.schema_name != axis_state_type && !joint {
                return Decode::Skip;
            }
            let k = *by_topic.entry(c.topic.clone()).or_insert_with(|| {
                out.streams.push(RecordedStream { topic: c.topic.clone(), joint_state: joint, joint_names: None, undecodable: 0, mtconnect: false, merge_latency_s: None });
                out.streams.len() - 1
            });
            if joint {
                Decode::JointState(k)
            } else {
                Decode::AxisState(k)
            }
        });
        let (k, sample) = match how {
            Decode::Skip => return,
            Decode::AxisState(k) => (k, state.read_cdr(msg.data).map(|()| &state).map_err(|_| Unread::Undecodable)),
            Decode::JointState(k) => {
                if joints.read_cdr(msg.data).is_err() {
                    out.streams[k].undecodable += 1;
                    visit(Recorded { stream: k, topic: &out.streams[k].topic, log_time: msg.log_time, sample: Err(Unread::Undecodable), uncertainty: None });
                    return;
                }
                let stream = &mut out.streams[k];
                if stream.joint_names.is_none() {
                    stream.joint_names = Some(joints.name.clone());
                }
                if merges.len() <= k {
                    merges.resize(k + 1, None);
                }
                let merge = merges[k].get_or_insert_with(|| JointStream::new(machine, map.joints()));
                // A recording has no silence to tell a restarted publisher by: a stamp no later than
                // the last is out of order.
                let pushed = merge.push(&map, &joints, msg.log_time as f64 * 1e-9, f64::INFINITY);
                let topic = &out.streams[k].topic;
                push_merged(merge, pushed, |sample, uncertainty| visit(Recorded { stream: k, topic, log_time: msg.log_time, sample, uncertainty }));
                return;
            }
        };
        if matches!(sample, Err(Unread::Undecodable)) {
            out.streams[k].undecodable += 1;
        }
        visit(Recorded { stream: k, topic: &out.streams[k].topic, log_time: msg.log_time, sample, uncertainty: None });
    });
    // The end of the recording: every JointState stream's waiting instants are made, and messages
    // still waiting for an axis never reported are refused as missing it.
    for (k, merge) in merges.iter_mut().enumerate() {
        let Some(merge) = merge else { continue };
        let log_time = merge.last_wall().map_or(0, |w| (w * 1e9) as u64);
        let topic = &out.streams[k].topic;
        let latency = finish_merged(merge, |sample, uncertainty| visit(Recorded { stream: k, topic, log_time, sample, uncertainty }));
        out.streams[k].merge_latency_s = Some(latency);
    }
    match result {
        // Nothing readable at all: nothing to report.
        Err(e) if out.messages_read == 0 => return Err(e),
        Err(e) => out.damage = Some(e),
        Ok(_) => {}
    }
    progress(file_len, file_len);
    Ok(out)
}

/// A stamp this far (s) before the newest of an SHDR log starts a new adapter session.
pub const NEW_SESSION_JUMP_S: f64 = 1.0;

/// Largest device description read (bytes): descriptions of whole shops run to a few megabytes.
const MAX_DEVICES_BYTES: u64 = 64 << 20;

/// [`read_states`] of an MTConnect adapter's SHDR log: one stream, `mtconnect:<device>`, of the
/// machine axes' position reports merged into poses ([`JointStream`]); a refused line counts as a
/// malformed sample (the first one named by line and column in [`StatesRead::first_malformed`]).
fn read_shdr(
    path: &Path,
    machine: &Machine,
    selection: &Selection,
    source: &MtconnectSource,
    progress: &mut dyn FnMut(u64, u64),
    mut visit: impl FnMut(Recorded<'_>),
) -> Result<StatesRead, RecordError> {
    use crate::mtconnect;
    let refuse = |p: &Path, message: String| RecordError::Mtconnect { path: p.to_path_buf(), message };
    let io = |p: &Path| {
        let path = p.to_path_buf();
        move |source| RecordError::Io { path, source }
    };
    let size = std::fs::metadata(&source.devices).map_err(io(&source.devices))?.len();
    if size > MAX_DEVICES_BYTES {
        return Err(refuse(&source.devices, format!("{size} bytes: larger than the {MAX_DEVICES_BYTES} read")));
    }
    let text = std::fs::read_to_string(&source.devices).map_err(io(&source.devices))?;
    let devices = mtconnect::devices::parse(&text).map_err(|e| refuse(&source.devices, e.to_string()))?;
    let device = mtconnect::pick(&devices, source.device.as_deref()).map_err(|e| refuse(&source.devices, e))?;
    let items = mtconnect::axis_items(device, machine, &selection.axis_map, mtconnect::UnitsOf::Adapter).map_err(|e| refuse(&source.devices, e))?;
    let file = std::fs::File::open(path).map_err(io(path))?;
    let file_len = file.metadata().map_err(io(path))?.len();
    let topic = format!("mtconnect:{}", device.name);
    let mut out = StatesRead {
        messages_read: 0,
        streams: vec![RecordedStream { topic: topic.clone(), joint_state: true, joint_names: Some(items.ids.to_vec()), undecodable: 0, mtconnect: true, merge_latency_s: None }],
        joint_state_topics: BTreeSet::new(),
        damage: None,
        first_malformed: BTreeMap::new(),
    };
    let mut merge = JointStream::new(machine, &items.ids);
    let mut last_log = 0;
    // The newest stamp of the adapter's current session.
    let mut newest: Option<f64> = None;
    let lines = mtconnect::read_log(std::io::BufReader::new(file), &devices, device, &items, |report| {
        match report {
            Ok(r) => {
                let log_time = u64::try_from(r.stamp.sec).unwrap_or(0).saturating_mul(1_000_000_000).saturating_add(u64::from(r.stamp.nanosec));
                // An adapter that connects again sends its whole state, stamped anew: a stamp that
                // goes back more than [`NEW_SESSION_JUMP_S`] starts a new session, not a run of
                // samples out of order.
                let t = r.stamp.as_secs();
                let restart = newest.is_some_and(|n| t < n - NEW_SESSION_JUMP_S);
                if restart {
                    merge.restart();
                    drain_merged(&mut merge, |sample, uncertainty| visit(Recorded { stream: 0, topic: &topic, log_time: last_log, sample, uncertainty }));
                }
                if restart || newest.is_none() {
                    visit(Recorded { stream: 0, topic: &topic, log_time, sample: Err(Unread::Session { change_only: true }), uncertainty: None });
                }
                newest = Some(if restart { t } else { newest.map_or(t, |n| n.max(t)) });
                last_log = log_time;
                let stamp = fiveaxis_msgs::Time { sec: r.stamp.sec.clamp(i32::MIN.into(), i32::MAX.into()) as i32, nanosec: r.stamp.nanosec };
                // A log has no silence to tell a restarted adapter by: a stamp no later than the last
                // is out of order.
                let pushed = merge.push_values(stamp, "", &r.values, t, f64::INFINITY);
                push_merged(&mut merge, pushed, |sample, uncertainty| visit(Recorded { stream: 0, topic: &topic, log_time, sample, uncertainty }));
            }
            Err(why) => {
                out.first_malformed.entry(0).or_insert_with(|| why.clone());
                visit(Recorded { stream: 0, topic: &topic, log_time: last_log, sample: Err(Unread::Unmapped(Rejection::Invalid(why))), uncertainty: None });
            }
        }
    });
    out.messages_read = lines.map_err(io(path))?;
    out.streams[0].merge_latency_s = Some(finish_merged(&mut merge, |sample, uncertainty| visit(Recorded { stream: 0, topic: &topic, log_time: last_log, sample, uncertainty })));
    progress(file_len, file_len);
    Ok(out)
}

/// What one message pushed into a merged stream gave: its refusal, if any, then every pose it
/// completed, oldest first.
fn push_merged(merge: &mut JointStream, pushed: Result<(), Rejection>, mut each: impl FnMut(Result<&AxisState, Unread>, Option<Joints>)) {
    if let Err(e) = pushed {
        each(Err(Unread::Unmapped(e)), None);
    }
    drain_merged(merge, each);
}

/// Every pose a merged stream has made, oldest first.
fn drain_merged(merge: &mut JointStream, mut each: impl FnMut(Result<&AxisState, Unread>, Option<Joints>)) {
    while let Some(m) = merge.pop() {
        each(Ok(&m.state), Some(m.uncertainty));
    }
}

/// The end of a merged stream: its waiting instants made, then the messages still waiting for an
/// axis never reported refused as missing it. Returns the merge's latency (s).
fn finish_merged(merge: &mut JointStream, mut each: impl FnMut(Result<&AxisState, Unread>, Option<Joints>)) -> f64 {
    merge.flush();
    drain_merged(merge, &mut each);
    if let Some((n, why)) = merge.unplaced() {
        for _ in 0..n {
            each(Err(Unread::Unmapped(why.clone())), None);
        }
    }
    merge.max_latency()
}
