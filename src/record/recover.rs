//! Rebuild a valid MCAP from a damaged one (a recorder killed with SIGKILL, power loss, a truncated
//! copy): every message of every complete chunk before the damage is kept, with its schema and
//! channel; the rest is reported.

use super::read::{scan_records, Stop};
use super::writer::McapWriter;
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

/// Read `input` as far as it is sound and write the result to `output`. The input is streamed
/// (memory stays within one chunk, whatever its length) and read by the same record reader as the
/// analysis, so a record the analysis refuses ends recovery there.
pub fn recover(input: &Path, output: &Path) -> Result<RecoverReport, RecordError> {
    use mcap::records::{op, Record};
    let io = |path: &Path| {
        let p: PathBuf = path.to_path_buf();
        move |source| RecordError::Io { path: p.clone(), source }
    };
    let bytes_total = std::fs::metadata(input).map_err(io(input))?.len();
    let file = std::fs::File::create(output).map_err(io(output))?;
    let library = concat!("fiveaxis ", env!("CARGO_PKG_VERSION"), " (recovered)");
    let mut writer =
        McapWriter::new(BufWriter::new(file), library, super::RecordOptions::default().chunk_bytes).map_err(|e| super::write_err(output, e))?;

    let mut schema_ids: HashMap<u16, u16> = HashMap::new();
    let mut channel_ids: HashMap<u16, u16> = HashMap::new();
    let mut schemas: HashMap<u16, (String, String, Vec<u8>)> = HashMap::new();
    let mut report = RecoverReport { messages: 0, channels: 0, bytes_total, stopped: None };
    let mut ended = false;
    let out = |e| Stop::Visitor(super::write_err(output, e));
    let damaged = |position: u64, e: String| Stop::Damaged(RecordError::Mcap { path: input.to_path_buf(), message: format!("record before byte {position}: {e}") });
    let mut copy = |opcode: u8, data: &[u8], position: u64| -> Result<(), Stop> {
        match opcode {
            op::DATA_END | op::FOOTER => {
                ended = true;
                return Ok(());
            }
            op::MESSAGE => {
                let Some((header, body)) = super::read::message_header(data) else {
                    return Err(damaged(position, format!("a message record of {} bytes", data.len())));
                };
                let Some(&id) = channel_ids.get(&header.channel_id) else { return Ok(()) };
                writer.write_message(id, header.sequence, header.log_time, header.publish_time, body).map_err(out)?;
                report.messages += 1;
                return Ok(());
            }
            op::SCHEMA | op::CHANNEL | op::METADATA => {}
            _ => return Ok(()),
        }
        match super::read::parse_checked(opcode, data).map_err(|e| damaged(position, e))? {
            Record::Schema { header, data } => {
                schemas.insert(header.id, (header.name, header.encoding, data.into_owned()));
            }
            Record::Channel(c) => {
                if channel_ids.contains_key(&c.id) {
                    return Ok(());
                }
                let schema = match c.schema_id {
                    0 => 0,
                    sid => match schema_ids.get(&sid) {
                        Some(id) => *id,
                        None => {
                            let Some((name, enc, text)) = schemas.get(&sid) else { return Ok(()) };
                            let id = writer.add_schema(name, enc, text).map_err(out)?;
                            schema_ids.insert(sid, id);
                            id
                        }
                    },
                };
                let id = writer.add_channel(schema, &c.topic, &c.message_encoding, &c.metadata).map_err(out)?;
                channel_ids.insert(c.id, id);
            }
            Record::Metadata(m) => writer.write_metadata(&m.name, &m.metadata).map_err(out)?,
            _ => {}
        }
        Ok(())
    };
    match scan_records(input, 0, &mut copy) {
        Ok(()) => {}
        // A write to the output failing is an error; damage in the input ends recovery there.
        Err(Stop::Visitor(e)) => return Err(e),
        Err(Stop::Damaged(e)) => report.stopped = Some(e.to_string()),
    }
    if !ended && report.stopped.is_none() {
        report.stopped = Some("the file ends without its summary and footer (truncated)".into());
    }
    report.channels = channel_ids.len();
    writer.finish().map_err(|e| super::write_err(output, e))?;
    // Damaged input that gave back nothing (not an MCAP at all, or cut before its first message)
    // recovered nothing: an error, with no empty file left to pass for a recording.
    if let (0, Some(why)) = (report.messages, &report.stopped) {
        let _ = std::fs::remove_file(output);
        return Err(RecordError::Mcap { path: input.to_path_buf(), message: format!("nothing recoverable ({why})") });
    }
    Ok(report)
}
