//! rosbag2 bags as `ros2 bag record` writes them: a directory `NAME/` holding `NAME_0.mcap`,
//! `NAME_1.mcap`, ... and `metadata.yaml` (rosbag2 metadata version 9, the version rosbag2 writes
//! since Jazzy), which `ros2 bag info/play` and Python's `rosbags` open; or one `.mcap` file when
//! the output is named `*.mcap` (split files then go beside it as `NAME_k.mcap`).
//!
//! `metadata.yaml` is written when the bag is finished and again at each split, so a recorder killed
//! mid-run leaves the files before the last split listed; [`super::read`] reads a directory without
//! it too, and `fiveaxis mcap recover` mends its last file.

use super::{OfferedQos, RecordError, RecordOptions, Recorder};
use fiveaxis_msgs::{schema, RosMessage};
use serde::Serialize;
use std::path::{Path, PathBuf};
use yaml_rust2::{yaml::Hash, Yaml, YamlEmitter};

/// The rosbag2 metadata version written (rosbag2 Jazzy and later; `rosbags` reads 1-9).
pub const METADATA_VERSION: i64 = 9;

/// Where a bag's messages go: a rosbag2 directory, or a bare `.mcap` file (the output's name says).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    Directory,
    File,
}

impl Layout {
    /// A name ending in `.mcap` is a single file; anything else a rosbag2 directory.
    pub fn of(output: &Path) -> Layout {
        if output.extension().is_some_and(|e| e.eq_ignore_ascii_case("mcap")) {
            Layout::File
        } else {
            Layout::Directory
        }
    }
}

/// A topic of the bag: its name, type `pkg/msg/Type`, the QoS it was offered with, and its
/// `ros2msg` definition (empty when the type is not known, as rosbag2 stores it).
#[derive(Debug, Clone, PartialEq)]
pub struct BagTopic {
    pub name: String,
    pub type_name: String,
    pub qos: OfferedQos,
    pub definition: String,
}

impl BagTopic {
    /// A topic of one of our message types (definition from [`fiveaxis_msgs::schema`]).
    pub fn of<M: RosMessage>(name: &str, qos: OfferedQos) -> BagTopic {
        BagTopic::named(name, &M::type_name(), qos)
    }

    /// A topic of the type named `type_name`, with its definition where our messages know it.
    pub fn named(name: &str, type_name: &str, qos: OfferedQos) -> BagTopic {
        let definition = schema::ros2msg(type_name).unwrap_or_default();
        BagTopic { name: name.to_string(), type_name: type_name.to_string(), qos, definition }
    }
}

/// What one file of the bag holds (for `metadata.yaml`).
#[derive(Debug, Clone, Default)]
struct FileStats {
    name: String,
    first_ns: Option<u64>,
    last_ns: u64,
    messages: u64,
}

impl FileStats {
    fn add(&mut self, log_ns: u64) {
        self.first_ns = Some(self.first_ns.map_or(log_ns, |f| f.min(log_ns)));
        self.last_ns = self.last_ns.max(log_ns);
        self.messages += 1;
    }
}

/// Writes a bag: topics declared once (by index), messages by topic index, split on demand.
pub struct Bag {
    output: PathBuf,
    layout: Layout,
    split: bool,
    options: RecordOptions,
    topics: Vec<BagTopic>,
    counts: Vec<u64>,
    /// Per topic, the messages in the files before the current one.
    base_counts: Vec<u64>,
    files: Vec<FileStats>,
    current: Recorder,
    /// Channel id in the current file of each topic.
    channels: Vec<u16>,
}

impl Bag {
    /// Start a bag at `output` (see [`Layout::of`]); `split`: a bare `.mcap` output is written as
    /// `NAME_0.mcap`, ... beside it. A directory output must not exist yet or be empty (as `ros2 bag
    /// record` refuses to overwrite a bag).
    pub fn create(output: &Path, split: bool, options: RecordOptions) -> Result<Bag, RecordError> {
        let layout = Layout::of(output);
        if layout == Layout::Directory {
            let io = |source| RecordError::Io { path: output.to_path_buf(), source };
            if output.exists() {
                let mut entries = std::fs::read_dir(output).map_err(io)?;
                if entries.next().is_some() {
                    return Err(RecordError::Io {
                        path: output.to_path_buf(),
                        source: std::io::Error::new(std::io::ErrorKind::AlreadyExists, "the bag directory exists and is not empty: choose a new name"),
                    });
                }
            }
            std::fs::create_dir_all(output).map_err(io)?;
        }
        let path = file_path(output, layout, split, 0);
        let current = Recorder::create(&path, options)?;
        Ok(Bag {
            output: output.to_path_buf(),
            layout,
            split,
            options,
            topics: Vec::new(),
            counts: Vec::new(),
            base_counts: Vec::new(),
            files: vec![FileStats { name: file_name(&path), ..Default::default() }],
            current,
            channels: Vec::new(),
        })
    }

    /// Declare a topic; returns its index for [`Bag::write_raw`] (the same name and type twice give
    /// the same index).
    pub fn add_topic(&mut self, topic: BagTopic) -> Result<usize, RecordError> {
        if let Some(k) = self.topics.iter().position(|t| t.name == topic.name && t.type_name == topic.type_name) {
            return Ok(k);
        }
        let id = self.current.add_topic_schema(&topic.name, &topic.type_name, &topic.definition, topic.qos)?;
        self.channels.push(id);
        self.topics.push(topic);
        self.counts.push(0);
        self.base_counts.push(0);
        Ok(self.topics.len() - 1)
    }

    /// Declare a topic of one of our message types.
    pub fn add<M: RosMessage>(&mut self, name: &str, qos: OfferedQos) -> Result<usize, RecordError> {
        self.add_topic(BagTopic::of::<M>(name, qos))
    }

    /// Write one message as received (CDR with its encapsulation header): `log_ns` = receive time,
    /// `publish_ns` = send time.
    pub fn write_raw(&mut self, topic: usize, data: &[u8], log_ns: u64, publish_ns: u64) -> Result<(), RecordError> {
        let id = *self.channels.get(topic).ok_or_else(|| RecordError::UnknownType(format!("topic index {topic} was never declared")))?;
        if let Err(e) = self.current.write_raw(id, data, log_ns, publish_ns) {
            return Err(self.failed(e));
        }
        self.counts[topic] += 1;
        if let Some(f) = self.files.last_mut() {
            f.add(log_ns);
        }
        Ok(())
    }

    /// Encode and write one of our messages.
    pub fn write<M: Serialize>(&mut self, topic: usize, msg: &M, log_ns: u64, publish_ns: u64) -> Result<(), RecordError> {
        let data = super::to_cdr(msg)?;
        self.write_raw(topic, &data, log_ns, publish_ns)
    }

    /// Close the current chunk and flush it (what a reader can recover after a kill).
    pub fn flush(&mut self) -> Result<(), RecordError> {
        self.current.flush().map_err(|e| self.failed(e))
    }

    /// After a failed write of the current file (closed at its last whole chunk, see
    /// [`RecordError::WriteFailed`]): a directory's `metadata.yaml` lists it with what it kept, or,
    /// when even that cannot be written, is removed, so that readers list the bag's `.mcap` files
    /// instead of trusting a list without the last one.
    fn failed(&mut self, e: RecordError) -> RecordError {
        let kept = match &e {
            RecordError::WriteFailed { kept, .. } | RecordError::WriteFailedUnclosed { kept, .. } => *kept,
            _ => return e,
        };
        if self.layout != Layout::Directory {
            return e;
        }
        if let Some(f) = self.files.last_mut() {
            f.messages = kept;
        }
        for (t, n) in self.counts.iter_mut().enumerate() {
            *n = self.base_counts[t] + self.channels.get(t).map_or(0, |&c| self.current.committed_on(c));
        }
        if write_metadata(&self.output, self.layout, &self.topics, &self.counts, &self.files).is_err() {
            let _ = std::fs::remove_file(self.output.join(".metadata.yaml.tmp"));
            let _ = std::fs::remove_file(self.output.join("metadata.yaml"));
        }
        e
    }

    /// The file being written.
    pub fn current_path(&self) -> &Path {
        self.current.path()
    }

    /// Finish the current file and go on in the next (`NAME_k+1.mcap`), every topic declared again;
    /// `metadata.yaml` then lists the files so far.
    pub fn split(&mut self) -> Result<(), RecordError> {
        let k = self.files.len();
        let path = file_path(&self.output, self.layout, self.split, k);
        let mut next = Recorder::create(&path, self.options)?;
        let mut channels = Vec::with_capacity(self.topics.len());
        for t in &self.topics {
            channels.push(next.add_topic_schema(&t.name, &t.type_name, &t.definition, t.qos)?);
        }
        if let Err(e) = self.current.finish() {
            let _ = std::fs::remove_file(&path);
            return Err(self.failed(e));
        }
        self.current = next;
        self.base_counts.clone_from(&self.counts);
        self.channels = channels;
        self.files.push(FileStats { name: file_name(&path), ..Default::default() });
        let closed = self.files.len() - 1;
        write_metadata(&self.output, self.layout, &self.topics, &self.counts, &self.files[..closed])
    }

    /// Finish the bag: the last file's summary and, for a directory, `metadata.yaml`. Returns the
    /// number of messages written.
    pub fn finish(mut self) -> Result<u64, RecordError> {
        if let Err(e) = self.current.finish() {
            return Err(self.failed(e));
        }
        write_metadata(&self.output, self.layout, &self.topics, &self.counts, &self.files)?;
        Ok(self.counts.iter().sum())
    }
}

/// `metadata.yaml` in the bag directory `output` listing `files` (nothing for a bare file).
fn write_metadata(output: &Path, layout: Layout, topics: &[BagTopic], counts: &[u64], files: &[FileStats]) -> Result<(), RecordError> {
    if layout != Layout::Directory {
        return Ok(());
    }
    let text = metadata_yaml(topics, counts, files);
    let path = output.join("metadata.yaml");
    // Written beside and renamed, so that a reader never sees half a file.
    let tmp = output.join(".metadata.yaml.tmp");
    std::fs::write(&tmp, text).map_err(|source| RecordError::Io { path: tmp.clone(), source })?;
    std::fs::rename(&tmp, &path).map_err(|source| RecordError::Io { path, source })
}

/// The path of file `k`: `DIR/DIR_k.mcap` in a directory; the output itself, or `NAME_k.mcap`
/// beside it when splitting, for a bare file.
fn file_path(output: &Path, layout: Layout, split: bool, k: usize) -> PathBuf {
    let stem = output.file_stem().map_or("recording".into(), |s| s.to_string_lossy().into_owned());
    match layout {
        Layout::Directory => {
            let name = output.file_name().map_or("recording".into(), |s| s.to_string_lossy().into_owned());
            output.join(format!("{name}_{k}.mcap"))
        }
        Layout::File if !split => output.to_path_buf(),
        Layout::File => output.with_file_name(format!("{stem}_{k}.mcap")),
    }
}

fn file_name(path: &Path) -> String {
    path.file_name().map_or(String::new(), |s| s.to_string_lossy().into_owned())
}

fn int(v: u64) -> Yaml {
    Yaml::Integer(i64::try_from(v).unwrap_or(i64::MAX))
}

fn map(entries: Vec<(&str, Yaml)>) -> Yaml {
    let mut h = Hash::new();
    for (k, v) in entries {
        h.insert(Yaml::String(k.to_string()), v);
    }
    Yaml::Hash(h)
}

fn string(s: &str) -> Yaml {
    Yaml::String(s.to_string())
}

/// The topic's QoS profile list: [`OfferedQos::to_yaml`]'s text (what each MCAP channel carries),
/// parsed, so that metadata.yaml and the channels say the same.
fn qos_yaml(q: &OfferedQos) -> Yaml {
    yaml_rust2::YamlLoader::load_from_str(&q.to_yaml()).ok().and_then(|mut docs| docs.pop()).unwrap_or(Yaml::Array(Vec::new()))
}

/// The text of `metadata.yaml` for `files` (rosbag2 metadata version 9).
fn metadata_yaml(topics: &[BagTopic], counts: &[u64], files: &[FileStats]) -> String {
    let start = files.iter().filter_map(|f| f.first_ns).min().unwrap_or(0);
    let end = files.iter().filter(|f| f.first_ns.is_some()).map(|f| f.last_ns).max().unwrap_or(start);
    let total: u64 = files.iter().map(|f| f.messages).sum();
    // Per-topic counts cover every message written; with a file still open they run ahead of the
    // closed files', which is what a reader of the closed files finds at most.
    let topics_yaml = topics
        .iter()
        .zip(counts)
        .map(|(t, n)| {
            map(vec![
                (
                    "topic_metadata",
                    map(vec![
                        ("name", string(&t.name)),
                        ("type", string(&t.type_name)),
                        ("serialization_format", string("cdr")),
                        ("offered_qos_profiles", qos_yaml(&t.qos)),
                        ("type_description_hash", string("")),
                    ]),
                ),
                ("message_count", int(*n)),
            ])
        })
        .collect();
    let files_yaml = files
        .iter()
        .map(|f| {
            let first = f.first_ns.unwrap_or(start);
            map(vec![
                ("path", string(&f.name)),
                ("starting_time", map(vec![("nanoseconds_since_epoch", int(first))])),
                ("duration", map(vec![("nanoseconds", int(f.last_ns.saturating_sub(first)))])),
                ("message_count", int(f.messages)),
            ])
        })
        .collect();
    let info = map(vec![
        ("version", Yaml::Integer(METADATA_VERSION)),
        ("storage_identifier", string("mcap")),
        ("duration", map(vec![("nanoseconds", int(end.saturating_sub(start)))])),
        ("starting_time", map(vec![("nanoseconds_since_epoch", int(start))])),
        ("message_count", int(total)),
        ("topics_with_message_count", Yaml::Array(topics_yaml)),
        ("compression_format", string("")),
        ("compression_mode", string("")),
        ("relative_file_paths", Yaml::Array(files.iter().map(|f| string(&f.name)).collect())),
        ("files", Yaml::Array(files_yaml)),
        ("custom_data", Yaml::Hash(Hash::new())),
        ("ros_distro", string("jazzy")),
    ]);
    let doc = map(vec![("rosbag2_bagfile_information", info)]);
    let mut out = String::new();
    // Emitting into a String cannot fail but for a fmt error, which String never returns.
    if YamlEmitter::new(&mut out).dump(&doc).is_err() {
        out.clear();
    }
    let body = out.strip_prefix("---\n").unwrap_or(&out).to_string();
    body + "\n"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_and_file_names() {
        assert_eq!(Layout::of(Path::new("run.mcap")), Layout::File);
        assert_eq!(Layout::of(Path::new("bags/run")), Layout::Directory);
        assert_eq!(file_path(Path::new("bags/run"), Layout::Directory, false, 0), PathBuf::from("bags/run/run_0.mcap"));
        assert_eq!(file_path(Path::new("bags/run"), Layout::Directory, true, 3), PathBuf::from("bags/run/run_3.mcap"));
        assert_eq!(file_path(Path::new("x/run.mcap"), Layout::File, false, 0), PathBuf::from("x/run.mcap"));
        assert_eq!(file_path(Path::new("x/run.mcap"), Layout::File, true, 2), PathBuf::from("x/run_2.mcap"));
    }
}
