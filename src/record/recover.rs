//! Rebuild a valid MCAP from a damaged one (a recorder killed with SIGKILL, power loss, a truncated
//! copy): every message of every complete chunk before the damage is kept, with its schema and
//! channel; the rest is reported.

use super::RecordError;
use std::collections::HashMap;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// What recovery kept and why it stopped.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RecoverReport {
    pub messages: u64,
    pub channels: usize,
    /// Size of the input, bytes.
    pub bytes_total: u64,
    /// Why reading stopped before the end of a complete file (None: the input was complete).
    pub stopped: Option<String>,
}

/// [`recover`] for a recording: one MCAP file into `output`, or a rosbag2 directory (with or without
/// its metadata.yaml) file by file into the directory `output`, under the same file names. The
/// recovered directory has no metadata.yaml (fiveaxis reads it as it is; `ros2 bag reindex` writes one
/// for the ROS tools).
pub fn recover_recording(input: &Path, output: &Path) -> Result<Vec<(PathBuf, RecoverReport)>, RecordError> {
    if !input.is_dir() {
        return Ok(vec![(output.to_path_buf(), recover(input, output)?)]);
    }
    let files = super::read::recording_files(input)?;
    std::fs::create_dir_all(output).map_err(|source| RecordError::Io { path: output.to_path_buf(), source })?;
    let mut done = Vec::new();
    for f in files {
        let name = f.file_name().map(std::ffi::OsStr::to_os_string).unwrap_or_default();
        let out = output.join(name);
        let report = recover(&f, &out)?;
        done.push((out, report));
    }
    Ok(done)
}

/// Read `input` as far as it is sound and write the result to `output`.
pub fn recover(input: &Path, output: &Path) -> Result<RecoverReport, RecordError> {
    let data = std::fs::read(input).map_err(|source| RecordError::Io { path: input.to_path_buf(), source })?;
    let io = |path: &Path| {
        let p: PathBuf = path.to_path_buf();
        move |source| RecordError::Io { path: p.clone(), source }
    };
    let file = std::fs::File::create(output).map_err(io(output))?;
    let opts = mcap::WriteOptions::new()
        .profile("ros2")
        .library(concat!("fiveaxis ", env!("CARGO_PKG_VERSION"), " (recovered)"))
        .compression(Some(mcap::Compression::Zstd));
    let mut writer = mcap::Writer::with_options(BufWriter::new(file), opts).map_err(|e| super::mcap_err(output, e))?;

    let mut schema_ids: HashMap<u16, u16> = HashMap::new();
    let mut channel_ids: HashMap<u16, u16> = HashMap::new();
    let mut schemas: HashMap<u16, (String, String, Vec<u8>)> = HashMap::new();
    let mut report = RecoverReport { messages: 0, channels: 0, bytes_total: data.len() as u64, stopped: None };
    let reader = mcap::read::LinearReader::new_with_options(&data, enumset::enum_set!(mcap::read::Options::IgnoreEndMagic))
        .map_err(|e| RecordError::Mcap { path: input.to_path_buf(), message: e.to_string() })?;
    let mut ended = false;
    for rec in reader {
        let rec = match rec {
            Ok(r) => r.into_owned(),
            Err(e) => {
                report.stopped = Some(e.to_string());
                break;
            }
        };
        // A chunk is only used whole: decompress it first, so a damaged chunk drops out entirely.
        let records: Vec<mcap::records::Record<'static>> = match rec {
            mcap::records::Record::Chunk { header, data: chunk } => {
                match mcap::read::ChunkReader::new(header, &chunk).and_then(|r| r.map(|x| x.map(|y| y.into_owned())).collect::<Result<Vec<_>, _>>()) {
                    Ok(v) => v,
                    Err(e) => {
                        report.stopped = Some(format!("damaged chunk: {e}"));
                        break;
                    }
                }
            }
            mcap::records::Record::DataEnd(_) | mcap::records::Record::Footer(_) => {
                ended = true;
                break;
            }
            other => vec![other],
        };
        for r in records {
            match r {
                mcap::records::Record::Schema { header, data } => {
                    schemas.insert(header.id, (header.name.clone(), header.encoding.clone(), data.into_owned()));
                }
                mcap::records::Record::Channel(c) => {
                    if channel_ids.contains_key(&c.id) {
                        continue;
                    }
                    let schema = match c.schema_id {
                        0 => 0,
                        sid => match schema_ids.get(&sid) {
                            Some(id) => *id,
                            None => {
                                let Some((name, enc, text)) = schemas.get(&sid) else { continue };
                                let id = writer.add_schema(name, enc, text).map_err(|e| super::mcap_err(output, e))?;
                                schema_ids.insert(sid, id);
                                id
                            }
                        },
                    };
                    let id = writer.add_channel(schema, &c.topic, &c.message_encoding, &c.metadata).map_err(|e| super::mcap_err(output, e))?;
                    channel_ids.insert(c.id, id);
                }
                mcap::records::Record::Message { header, data } => {
                    let Some(&id) = channel_ids.get(&header.channel_id) else { continue };
                    let h = mcap::records::MessageHeader { channel_id: id, ..header };
                    writer.write_to_known_channel(&h, &data).map_err(|e| super::mcap_err(output, e))?;
                    report.messages += 1;
                }
                mcap::records::Record::Metadata(m) => writer.write_metadata(&m).map_err(|e| super::mcap_err(output, e))?,
                _ => {}
            }
        }
    }
    if !ended && report.stopped.is_none() {
        report.stopped = Some("the file ends without its summary and footer (truncated)".into());
    }
    report.channels = channel_ids.len();
    writer.finish().map_err(|e| super::mcap_err(output, e))?;
    Ok(report)
}
