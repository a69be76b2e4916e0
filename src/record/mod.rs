//! Recordings: MCAP in the rosbag2 layout, so that `ros2 bag info/play`, Foxglove and the Python
//! readers (`rosbags`, `mcap-ros2-support`) open them.
//!
//! - profile `ros2`; one schema per type named `pkg/msg/Type`, encoding `ros2msg`, its text with the
//!   dependencies appended after lines of 80 `=` and `MSG: pkg/Type` ([`fiveaxis_msgs::schema`]);
//! - channels with message encoding `cdr` (4-byte CDR_LE encapsulation header + XCDR1 body) and
//!   `offered_qos_profiles` metadata (rosbag2's YAML);
//! - log time = receive time; publish time = the send time (the writer's DDS source timestamp) for
//!   what the recorder node receives, the message's stamp for the in-process run;
//! - a rosbag2 directory (`metadata.yaml` and `NAME_0.mcap`, ...) unless the output is named
//!   `*.mcap` ([`bag`]);
//! - zstd chunks, closed at least every [`RecordOptions::chunk_interval_ns`] (1 s) of log time, so a
//!   recorder killed mid-run loses at most the last chunk ([`recover`] rebuilds the rest), with
//!   message indexes, chunk indexes and statistics in the summary.

pub mod bag;
pub mod read;
mod recover;
pub mod sqlite;
pub mod writer;

pub use recover::{recover, recover_recording, RecoverReport};

use fiveaxis_msgs::{schema, RosMessage};
use serde::{de::DeserializeOwned, Serialize};
use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};
use writer::{McapWriter, WriteError};

/// CDR_LE encapsulation header (XCDR1, little endian).
pub const CDR_LE: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// Errors of the recorder and readers, naming the file.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}: MCAP: {message}")]
    Mcap { path: PathBuf, message: String },
    #[error("{path}: rosbag2 SQLite3: {message}")]
    Sqlite { path: PathBuf, message: String },
    /// An MTConnect device description that cannot be used for the log (unreadable, no such
    /// device, an axis without a data item).
    #[error("{path}: MTConnect: {message}")]
    Mtconnect { path: PathBuf, message: String },
    #[error("no ros2msg schema known for {0}")]
    UnknownType(String),
    #[error("CDR: {0}")]
    Cdr(String),
    /// A write failed (a full disk, say): the file was cut back to the last chunk flushed whole and
    /// closed there, so it holds every message up to that chunk and reads without repair.
    #[error("{path}: {source}: the recording ends at the last chunk written whole ({kept} messages), closed and readable")]
    WriteFailed { path: PathBuf, source: std::io::Error, kept: u64 },
    /// A write failed and the file could not even be closed at its last whole chunk: it holds what
    /// was written up to then, which `fiveaxis mcap recover` mends.
    #[error("{path}: {source}; closing it at its last whole chunk ({kept} messages) failed too ({close}): mend it with `fiveaxis mcap recover`")]
    WriteFailedUnclosed { path: PathBuf, source: std::io::Error, kept: u64, close: std::io::Error },
}

/// The wall clock in ns since the UNIX epoch, as a recorder takes a message's log time when it
/// arrives (0 before the epoch).
pub fn wall_clock_ns() -> u64 {
    std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos() as u64)
}

/// Encode a message as rosbag2 stores it: CDR_LE header + XCDR1 body.
pub fn to_cdr<M: Serialize>(msg: &M) -> Result<Vec<u8>, RecordError> {
    let body = cdr_encoding::to_vec::<M, byteorder::LittleEndian>(msg).map_err(|e| RecordError::Cdr(e.to_string()))?;
    let mut out = Vec::with_capacity(4 + body.len());
    out.extend_from_slice(&CDR_LE);
    out.extend_from_slice(&body);
    Ok(out)
}

/// Decode a CDR message (with its encapsulation header; big-endian bodies are accepted too).
pub fn from_cdr<M: DeserializeOwned>(data: &[u8]) -> Result<M, RecordError> {
    if data.len() < 4 {
        return Err(RecordError::Cdr(format!("{} bytes: shorter than the encapsulation header", data.len())));
    }
    let body = &data[4..];
    let r = match data[1] {
        0x01 | 0x03 => cdr_encoding::from_bytes::<M, byteorder::LittleEndian>(body),
        0x00 | 0x02 => cdr_encoding::from_bytes::<M, byteorder::BigEndian>(body),
        k => return Err(RecordError::Cdr(format!("unsupported encapsulation kind 0x{k:02x}"))),
    };
    r.map(|(m, _)| m).map_err(|e| RecordError::Cdr(e.to_string()))
}

/// The QoS a topic was offered with, as rosbag2 writes it (`offered_qos_profiles`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OfferedQos {
    pub reliable: bool,
    pub transient_local: bool,
    /// Keep-last depth (None: keep all).
    pub depth: Option<u32>,
}

impl OfferedQos {
    /// The node set's state streams: reliable, volatile, keep-last 1000.
    pub const STATE: OfferedQos = OfferedQos { reliable: true, transient_local: false, depth: Some(1000) };
    /// /diagnostics: reliable keep-last 10.
    pub const DIAGNOSTICS: OfferedQos = OfferedQos { reliable: true, transient_local: false, depth: Some(10) };
    /// /clock: best effort keep-last 1.
    pub const CLOCK: OfferedQos = OfferedQos { reliable: false, transient_local: false, depth: Some(1) };

    /// rosbag2's YAML, as rosbag2 metadata version 9 writes it (enum names; "infinite" durations
    /// as rmw's RMW_DURATION_INFINITE): a list of one profile. The same text goes into each MCAP
    /// channel's `offered_qos_profiles` and into `metadata.yaml` ([`bag`]), as readers that match
    /// the two (rosbags) require.
    pub fn to_yaml(&self) -> String {
        let never = "    sec: 9223372036\n    nsec: 854775807\n";
        format!(
            "- history: {}\n  depth: {}\n  reliability: {}\n  durability: {}\n  deadline:\n{never}  lifespan:\n{never}  liveliness: automatic\n  liveliness_lease_duration:\n{never}  avoid_ros_namespace_conventions: false\n",
            if self.depth.is_some() { "keep_last" } else { "keep_all" },
            self.depth.unwrap_or(0),
            if self.reliable { "reliable" } else { "best_effort" },
            if self.transient_local { "transient_local" } else { "volatile" },
        )
    }
}

/// Recorder settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordOptions {
    /// Close the current chunk once it spans this much log time, ns (default 1 s).
    pub chunk_interval_ns: u64,
    /// ... or holds this many uncompressed bytes.
    pub chunk_bytes: u64,
}

impl Default for RecordOptions {
    fn default() -> Self {
        RecordOptions { chunk_interval_ns: 1_000_000_000, chunk_bytes: 4 << 20 }
    }
}

/// MCAP's closing records for a file without a summary: Data End (data section CRC 0: not
/// computed), Footer (no summary: offsets and CRC 0) and the magic (MCAP spec, "Footer", "Data End").
const CLOSE_WITHOUT_SUMMARY: [u8; 50] = {
    let mut b = [0u8; 50];
    // Data End: opcode 0x0F, record length 4, data_section_crc 0.
    b[0] = 0x0F;
    b[1] = 4;
    // Footer at 13: opcode 0x02, record length 20, summary_start, summary_offset_start, summary_crc all 0.
    b[13] = 0x02;
    b[14] = 20;
    // Magic at 42.
    let magic = *b"\x89MCAP0\r\n";
    let mut i = 0;
    while i < 8 {
        b[42 + i] = magic[i];
        i += 1;
    }
    b
};

/// Writes one MCAP recording. A failed write (a full disk) is never left half-done: the file is cut
/// back to the last chunk flushed whole and closed there ([`RecordError::WriteFailed`]).
pub struct Recorder {
    path: PathBuf,
    /// `None` once finished or failed.
    writer: Option<McapWriter<BufWriter<File>>>,
    /// File offset and message count at the end of the last chunk flushed whole.
    committed: (u64, u64),
    /// Messages per channel (by id) at the end of the last chunk flushed whole.
    committed_per_channel: Vec<u64>,
    channels: HashMap<String, (u16, String)>,
    chunk_start: Option<u64>,
    options: RecordOptions,
    messages: u64,
}

impl Recorder {
    /// Create `path` (an unwritable path or a full disk is reported with the path).
    pub fn create(path: &Path, options: RecordOptions) -> Result<Self, RecordError> {
        let file = File::create(path).map_err(|source| RecordError::Io { path: path.to_path_buf(), source })?;
        let sink = BufWriter::with_capacity(1 << 20, file);
        let mut writer =
            McapWriter::new(sink, concat!("fiveaxis ", env!("CARGO_PKG_VERSION")), options.chunk_bytes).map_err(|e| write_err(path, e))?;
        let mut meta = BTreeMap::new();
        meta.insert("ROS_DISTRO".to_string(), "jazzy".to_string());
        writer.write_metadata("rosbag2", &meta).map_err(|e| write_err(path, e))?;
        let mut rec = Recorder {
            path: path.to_path_buf(),
            writer: Some(writer),
            committed: (0, 0),
            committed_per_channel: Vec::new(),
            channels: HashMap::new(),
            chunk_start: None,
            options,
            messages: 0,
        };
        // The header and metadata on disk: from here on a failed write leaves a closed file.
        rec.flush()?;
        Ok(rec)
    }

    /// The writer, or the error a failed recorder keeps giving.
    fn writer(&mut self) -> Result<&mut McapWriter<BufWriter<File>>, RecordError> {
        let path = &self.path;
        self.writer.as_mut().ok_or_else(|| RecordError::Mcap { path: path.clone(), message: "the recorder already failed or finished".into() })
    }

    /// Run one write on the MCAP writer; on failure, close the file at its last whole chunk.
    fn attempt<T>(&mut self, op: impl FnOnce(&mut McapWriter<BufWriter<File>>) -> Result<T, WriteError>) -> Result<T, RecordError> {
        let w = self.writer()?;
        match op(w) {
            Ok(v) => Ok(v),
            Err(WriteError::Io(source)) => Err(self.close_at_committed(source)),
            Err(e) => Err(write_err(&self.path, e)),
        }
    }

    /// After a failed write: drop what is buffered, cut the file back to the end of the last chunk
    /// flushed whole (which frees the space the failed chunk took) and close it there without a
    /// summary.
    fn close_at_committed(&mut self, source: std::io::Error) -> RecordError {
        let path = self.path.clone();
        let Some(writer) = self.writer.take() else {
            return RecordError::Io { path, source };
        };
        // into_inner neither finishes nor flushes.
        close_at(writer.into_inner(), path, source, self.committed)
    }

    /// Declare `topic` with type `M`; returns its channel id (the same topic twice gives the same id).
    pub fn add_topic<M: RosMessage>(&mut self, topic: &str, qos: OfferedQos) -> Result<u16, RecordError> {
        self.add_topic_type(topic, &M::type_name(), qos)
    }

    /// Declare `topic` with the type named `pkg/msg/Type`.
    pub fn add_topic_type(&mut self, topic: &str, type_name: &str, qos: OfferedQos) -> Result<u16, RecordError> {
        if let Some((id, ty)) = self.channels.get(topic) {
            if ty == type_name {
                return Ok(*id);
            }
        }
        let text = schema::ros2msg(type_name).ok_or_else(|| RecordError::UnknownType(type_name.to_string()))?;
        self.add_topic_schema(topic, type_name, &text, qos)
    }

    /// Declare `topic` with the type named `type_name` and its `ros2msg` text: empty for a type
    /// whose definition is not known, as `ros2 bag record` stores it (readers then need the type
    /// from elsewhere to decode it).
    pub fn add_topic_schema(&mut self, topic: &str, type_name: &str, text: &str, qos: OfferedQos) -> Result<u16, RecordError> {
        if let Some((id, ty)) = self.channels.get(topic) {
            if ty == type_name {
                return Ok(*id);
            }
        }
        let schema_id = self.attempt(|w| w.add_schema(type_name, "ros2msg", text.as_bytes()))?;
        let mut meta = BTreeMap::new();
        meta.insert("offered_qos_profiles".to_string(), qos.to_yaml());
        let id = self.attempt(|w| w.add_channel(schema_id, topic, "cdr", &meta))?;
        self.channels.insert(topic.to_string(), (id, type_name.to_string()));
        Ok(id)
    }

    /// Write one message: `log_time_ns` = when it was received, `publish_time_ns` = its stamp.
    pub fn write<M: Serialize>(&mut self, channel: u16, msg: &M, log_time_ns: u64, publish_time_ns: u64) -> Result<(), RecordError> {
        let data = to_cdr(msg)?;
        self.write_raw(channel, &data, log_time_ns, publish_time_ns)
    }

    /// Write an already encoded message (CDR with its header).
    pub fn write_raw(&mut self, channel: u16, data: &[u8], log_time_ns: u64, publish_time_ns: u64) -> Result<(), RecordError> {
        // Close the chunk every interval of log time, so that a kill loses at most that much.
        match self.chunk_start {
            Some(start) if log_time_ns.saturating_sub(start) >= self.options.chunk_interval_ns => {
                self.flush()?;
                self.chunk_start = Some(log_time_ns);
            }
            None => self.chunk_start = Some(log_time_ns),
            _ => {}
        }
        // The sequence is the channel's message count, wrapping at 2^32 as the field does.
        self.attempt(|w| {
            let n = w.message_counts().get(usize::from(channel)).copied().unwrap_or(0) + 1;
            w.write_message(channel, n as u32, log_time_ns, publish_time_ns, data)
        })?;
        self.messages += 1;
        Ok(())
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Messages written so far.
    pub fn messages(&self) -> u64 {
        self.messages
    }

    /// Close the current chunk and flush it to the file (what a reader can recover up to, and
    /// where a later failed write closes the file).
    pub fn flush(&mut self) -> Result<(), RecordError> {
        let at = self.attempt(|w| w.flush().map(|()| w.position()))?;
        self.committed = (at, self.messages);
        let counts = self.writer.as_ref().map_or(&[][..], |w| w.message_counts());
        self.committed_per_channel.clear();
        self.committed_per_channel.extend_from_slice(counts);
        Ok(())
    }

    /// Messages on `channel` up to the end of the last chunk flushed whole: what the file holds
    /// after a failed write ([`RecordError::WriteFailed`]).
    pub fn committed_on(&self, channel: u16) -> u64 {
        self.committed_per_channel.get(usize::from(channel)).copied().unwrap_or(0)
    }

    /// Write the summary (indexes, statistics) and the footer; the recorder takes no more writes.
    pub fn finish(&mut self) -> Result<u64, RecordError> {
        // Writes the summary and flushes it; a failure closes the file at the last chunk.
        self.attempt(|w| w.finish())?;
        self.writer = None;
        Ok(self.messages)
    }
}

/// Close a file whose write failed with `source` at `committed` (offset, messages there): drop what
/// is buffered, cut the file back (freeing what the failed chunk took) and append
/// [`CLOSE_WITHOUT_SUMMARY`].
fn close_at(out: BufWriter<File>, path: PathBuf, source: std::io::Error, committed: (u64, u64)) -> RecordError {
    let (at, kept) = committed;
    let (mut file, _unwritten) = out.into_parts();
    let closed = file
        .set_len(at)
        .and_then(|()| file.seek(std::io::SeekFrom::Start(at)).map(drop))
        .and_then(|()| file.write_all(&CLOSE_WITHOUT_SUMMARY))
        .and_then(|()| file.sync_data());
    match closed {
        Ok(()) => RecordError::WriteFailed { path, source, kept },
        Err(close) => RecordError::WriteFailedUnclosed { path, source, kept, close },
    }
}

fn write_err(path: &Path, e: WriteError) -> RecordError {
    match e {
        WriteError::Io(source) => RecordError::Io { path: path.to_path_buf(), source },
        other => RecordError::Mcap { path: path.to_path_buf(), message: other.to_string() },
    }
}
