//! Streaming reads of a recording: every message in file order, borrowed from the reader's buffers,
//! with the file read piecewise (memory stays flat on recordings of any size) and chunk CRCs checked.
//! Built on the `mcap` crate's sans-I/O readers; the offline analysis and the Rerun replay use it.

use super::RecordError;
use mcap::records::Record;
use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};
use std::collections::HashMap;
use std::fs::File;
use std::io::{Read, Seek};
use std::path::Path;

/// A channel of a recording: topic, schema name (`pkg/msg/Type`, empty without a schema) and
/// message encoding.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChannelInfo {
    pub id: u16,
    pub topic: String,
    pub schema_name: String,
    pub message_encoding: String,
}

/// One message, borrowed from the reader until the visitor returns.
#[derive(Debug, Clone, Copy)]
pub struct MessageView<'a> {
    pub channel: &'a ChannelInfo,
    pub sequence: u32,
    /// Receive time, ns.
    pub log_time: u64,
    /// Source stamp, ns.
    pub publish_time: u64,
    pub data: &'a [u8],
    /// Bytes of the recording read so far (for progress; over all files of a rosbag2 directory).
    pub file_position: u64,
    /// Which file of the recording (0 for a single MCAP file; the split files of a rosbag2 directory
    /// in order): channel ids are per file.
    pub file: usize,
}

/// The files of a recording, in order: the file itself, or for a rosbag2 directory (what `ros2 bag
/// record` writes) the files its `metadata.yaml` lists under `relative_file_paths` (without one, as a
/// killed recorder leaves it, its `.mcap` or `.db3` files in their split order). MCAP and SQLite3
/// (`.db3`, [`super::sqlite`]) storage.
pub fn recording_files(path: &Path) -> Result<Vec<std::path::PathBuf>, RecordError> {
    Ok(recording(path)?.0)
}

/// A recording's files and whether its messages are each zstd-compressed (rosbag2's
/// `compression_mode: MESSAGE`, SQLite3 bags).
fn recording(path: &Path) -> Result<(Vec<std::path::PathBuf>, bool), RecordError> {
    if !path.is_dir() {
        return Ok((vec![path.to_path_buf()], false));
    }
    let meta = path.join("metadata.yaml");
    if !meta.exists() {
        // A bag whose recorder died before closing it has no metadata.yaml (rosbag2 writes it last):
        // its MCAP files in their numbered order.
        let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(path)
            .map_err(io_error(path))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "mcap") || super::sqlite::is_db3(p))
            .collect();
        files.sort_by_key(|p| split_number(p));
        if files.is_empty() {
            return Err(mcap_error(path, "a directory with neither metadata.yaml nor .mcap or .db3 files: not a rosbag2 bag".to_string()));
        }
        return Ok((files, false));
    }
    let text = std::fs::read_to_string(&meta).map_err(|source| RecordError::Io { path: meta.clone(), source })?;
    let bad = |line: usize, why: String| mcap_error(&meta, format!("line {line}: {why}"));
    let mut files = Vec::new();
    let mut storage = None;
    let mut compression = (String::new(), String::new());
    let mut list_indent: Option<usize> = None;
    for (k, line) in text.lines().enumerate() {
        let indent = line.len() - line.trim_start().len();
        let body = line.trim();
        if body.is_empty() || body.starts_with('#') {
            continue;
        }
        if let Some(ind) = list_indent {
            if let Some(item) = body.strip_prefix("- ").or_else(|| body.strip_prefix('-')) {
                if indent >= ind {
                    files.push(unquote(item.trim()));
                    continue;
                }
            }
            if indent <= ind {
                list_indent = None;
            }
        }
        if let Some(v) = body.strip_prefix("storage_identifier:") {
            storage = Some(unquote(v.trim()));
        } else if let Some(v) = body.strip_prefix("compression_format:") {
            compression.0 = unquote(v.trim()).to_ascii_lowercase();
        } else if let Some(v) = body.strip_prefix("compression_mode:") {
            compression.1 = unquote(v.trim()).to_ascii_lowercase();
        } else if let Some(v) = body.strip_prefix("relative_file_paths:") {
            let v = v.trim();
            if let Some(flow) = v.strip_prefix('[') {
                let flow = flow.strip_suffix(']').ok_or_else(|| bad(k + 1, "unterminated [ list".into()))?;
                files.extend(flow.split(',').map(|s| unquote(s.trim())).filter(|s| !s.is_empty()));
            } else if v.is_empty() {
                list_indent = Some(indent);
            } else {
                return Err(bad(k + 1, format!("relative_file_paths is '{v}', not a list")));
            }
        }
    }
    if let Some(s) = storage.as_deref().filter(|s| !matches!(*s, "mcap" | "sqlite3")) {
        return Err(mcap_error(&meta, format!("storage_identifier is '{s}': only MCAP and SQLite3 bags are read (convert with `ros2 bag convert`)")));
    }
    let message_zstd = match (compression.0.as_str(), compression.1.as_str()) {
        ("", _) | (_, "" | "none") => false,
        ("zstd", "message") => true,
        ("zstd", "file") => false,
        (f, m) => return Err(mcap_error(&meta, format!("compression {f}, mode {m}: only zstd, by message or by file, is read"))),
    };
    if files.is_empty() {
        return Err(mcap_error(&meta, "lists no files under relative_file_paths".to_string()));
    }
    Ok((files.into_iter().map(|f| path.join(f)).collect(), message_zstd && storage.as_deref() == Some("sqlite3")))
}

/// A split file's order: `NAME_12.mcap` (or `.db3`, `.db3.zstd`) sorts by (NAME, 12), so that `_10`
/// follows `_9`.
fn split_number(p: &Path) -> (String, u64) {
    let name = p.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    // The storage's extensions come off (a bag's own name may hold dots).
    let mut stem = name.as_str();
    for ext in [".zstd", ".db3", ".mcap"] {
        stem = stem.strip_suffix(ext).unwrap_or(stem);
    }
    let stem = stem.to_string();
    match stem.rsplit_once('_') {
        Some((name, n)) if n.chars().all(|c| c.is_ascii_digit()) && !n.is_empty() => (name.to_string(), n.parse().unwrap_or(u64::MAX)),
        _ => (stem, 0),
    }
}

fn unquote(s: &str) -> String {
    let s = s.trim();
    s.strip_prefix('"').and_then(|x| x.strip_suffix('"')).or_else(|| s.strip_prefix('\'').and_then(|x| x.strip_suffix('\''))).unwrap_or(s).to_string()
}

/// Total size of a recording's files, bytes.
pub fn recording_len(path: &Path) -> Result<u64, RecordError> {
    let mut n = 0;
    for f in recording_files(path)? {
        n += std::fs::metadata(&f).map_err(io_error(&f))?.len();
    }
    Ok(n)
}

fn mcap_error(path: &Path, e: impl std::fmt::Display) -> RecordError {
    RecordError::Mcap { path: path.to_path_buf(), message: e.to_string() }
}

pub(super) fn io_error(path: &Path) -> impl Fn(std::io::Error) -> RecordError + '_ {
    move |source| RecordError::Io { path: path.to_path_buf(), source }
}

/// The channels listed in the summary section of the recording at `path`, read from its end;
/// `None` when it has no readable summary (a recording cut short, no end magic: read the messages
/// themselves). Only I/O errors are errors.
pub fn summary_channels(path: &Path) -> Result<Option<Vec<ChannelInfo>>, RecordError> {
    use mcap::records::op;
    const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";
    // Footer record (opcode, length 20, summary_start, summary_offset_start, summary_crc) + magic.
    const TAIL: u64 = 1 + 8 + 20 + 8;
    /// Largest Schema or Channel record read from a summary (a schema text is a few kB).
    const MAX_SUMMARY_RECORD: u64 = 16 << 20;
    let mut file = File::open(path).map_err(io_error(path))?;
    let len = file.metadata().map_err(io_error(path))?.len();
    if len < 8 + TAIL {
        return Ok(None);
    }
    let mut tail = [0u8; TAIL as usize];
    file.seek(std::io::SeekFrom::Start(len - TAIL)).map_err(io_error(path))?;
    file.read_exact(&mut tail).map_err(io_error(path))?;
    let u64_at = |b: &[u8], k: usize| u64::from_le_bytes(b[k..k + 8].try_into().expect("8 bytes"));
    if tail[0] != op::FOOTER || u64_at(&tail, 1) != 20 || &tail[29..] != MAGIC {
        return Ok(None);
    }
    let (start, offsets) = (u64_at(&tail, 9), u64_at(&tail, 17));
    let end = if offsets != 0 { offsets } else { len - TAIL };
    if start < 8 || start >= end || end > len - TAIL {
        return Ok(None);
    }
    // The summary section's records in order: Schema and Channel records read and checked, every
    // other record skipped; anything inconsistent means no usable summary (the caller then reads
    // the data section, which reports damage where it is).
    let mut reader = std::io::BufReader::new(file);
    reader.seek(std::io::SeekFrom::Start(start)).map_err(io_error(path))?;
    let (mut at, mut schemas, mut channels) = (start, HashMap::new(), Vec::new());
    let mut body = Vec::new();
    while at < end {
        let mut head = [0u8; 9];
        if end - at < 9 || reader.read_exact(&mut head).is_err() {
            return Ok(None);
        }
        let (opcode, size) = (head[0], u64_at(&head, 1));
        at += 9;
        if size > end - at {
            return Ok(None);
        }
        if opcode == op::SCHEMA || opcode == op::CHANNEL {
            if size > MAX_SUMMARY_RECORD {
                return Ok(None);
            }
            body.clear();
            if (&mut reader).take(size).read_to_end(&mut body).map_err(io_error(path))? as u64 != size {
                return Ok(None);
            }
            match parse_checked(opcode, &body) {
                Ok(Record::Schema { header, .. }) => {
                    schemas.insert(header.id, header.name);
                }
                Ok(Record::Channel(c)) => channels.push(c),
                _ => return Ok(None),
            }
        } else {
            reader.seek_relative(size as i64).map_err(io_error(path))?;
        }
        at += size;
    }
    let mut out = Vec::with_capacity(channels.len());
    for c in channels {
        let schema_name = match c.schema_id {
            0 => String::new(),
            id => match schemas.get(&id) {
                Some(name) => String::clone(name),
                None => return Ok(None),
            },
        };
        out.push(ChannelInfo { id: c.id, topic: c.topic, schema_name, message_encoding: c.message_encoding });
    }
    out.sort_by_key(|c| c.id);
    Ok(Some(out))
}

pub fn may_carry_type(path: &Path, type_name: &str) -> Result<bool, RecordError> {
    for f in recording_files(path)? {
        // A SQLite3 file's topics are not read ahead: it may carry the type.
        if super::sqlite::is_db3(&f) {
            return Ok(true);
        }
        if summary_channels(&f)?.is_none_or(|channels| channels.iter().any(|c| c.schema_name == type_name)) {
            return Ok(true);
        }
    }
    Ok(false)
}

/// Call `visit` for every message of the recording at `path`, in file order, and return how many
/// there were. Schema and Channel records are collected on the way (a message on a channel not yet
/// declared is an error). Errors name the file and what broke; the messages before it were visited.
///
/// Chunks are decompressed whole into one reused buffer (zstd's one-shot decoder, or an LZ4 frame
/// decoder, then the CRC of the uncompressed records): faster than streaming them through the record
/// reader.
pub fn for_each_message(path: &Path, mut visit: impl FnMut(MessageView<'_>)) -> Result<u64, RecordError> {
    let mut count = 0;
    let mut offset = 0;
    let (files, message_zstd) = recording(path)?;
    for (k, f) in files.iter().enumerate() {
        count += if super::sqlite::is_db3(f) { super::sqlite::for_each_message_in_db(f, k, offset, message_zstd, &mut visit)? } else { for_each_message_in_file(f, k, offset, &mut visit)? };
        offset += std::fs::metadata(f).map_err(io_error(f))?.len();
    }
    Ok(count)
}

fn for_each_message_in_file(path: &Path, file_index: usize, offset: u64, visit: &mut impl FnMut(MessageView<'_>)) -> Result<u64, RecordError> {
    let mut records = Records { schemas: HashMap::new(), channels: Vec::new(), count: 0, file: file_index };
    scan_records(path, offset, &mut |opcode, data, position| records.record(path, opcode, data, position, visit).map_err(Stop::Damaged)).map_err(Stop::into_inner)?;
    Ok(records.count)
}

/// Why [`scan_records`] stopped early: the file is damaged there (found by the scan or by the
/// visitor), or the visitor failed at its own work (writing its output, say).
pub(crate) enum Stop {
    Damaged(RecordError),
    Visitor(RecordError),
}

impl Stop {
    pub(crate) fn into_inner(self) -> RecordError {
        match self {
            Stop::Damaged(e) | Stop::Visitor(e) => e,
        }
    }
}

/// Stream the records of one MCAP file in order to `visit(opcode, body, position)`: the records
/// of each chunk after the chunk is decompressed whole and its CRC checked (the Chunk record itself
/// is not passed on), every other record as it comes; `position` is the bytes read so far plus
/// `offset`. Memory stays within one chunk (at most [`MAX_CHUNK`]) whatever the file's length.
///
/// Chunks are decompressed into one reused buffer (zstd's one-shot decoder, or an LZ4 frame decoder,
/// then the CRC of the uncompressed records): faster than streaming them through the record reader.
pub(crate) fn scan_records(path: &Path, offset: u64, visit: &mut impl FnMut(u8, &[u8], u64) -> Result<(), Stop>) -> Result<(), Stop> {
    let mut file = File::open(path).map_err(io_error(path)).map_err(Stop::Damaged)?;
    let len = file.metadata().map_err(io_error(path)).map_err(Stop::Damaged)?.len();
    let mut reader = LinearReader::new_with_options(
        LinearReaderOptions::default().with_emit_chunks(true).with_record_length_limit(usize::try_from(len).unwrap_or(usize::MAX)),
    );
    let mut position = offset;
    let mut chunk = Vec::new();
    let mut zstd = zstd::bulk::Decompressor::new().map_err(io_error(path)).map_err(Stop::Damaged)?;
    while let Some(event) = reader.next_event() {
        match event.map_err(|e| Stop::Damaged(mcap_error(path, e)))? {
            LinearReadEvent::ReadRequest(need) => {
                // Read in large pieces: fewer system calls.
                let n = file.read(reader.insert(need.max(1 << 20))).map_err(io_error(path)).map_err(Stop::Damaged)?;
                reader.notify_read(n);
                position += n as u64;
            }
            LinearReadEvent::Record { data, opcode: mcap::records::op::CHUNK } => {
                let body = decompress_chunk(data, position, &mut zstd, &mut chunk).map_err(|e| Stop::Damaged(mcap_error(path, e)))?;
                let mut rest = body;
                while !rest.is_empty() {
                    let (opcode, record, tail) = split_record(rest)
                        .ok_or_else(|| Stop::Damaged(mcap_error(path, format!("chunk record before byte {position}: a record cut short {} bytes from its end", rest.len()))))?;
                    visit(opcode, record, position)?;
                    rest = tail;
                }
            }
            LinearReadEvent::Record { data, opcode } => visit(opcode, data, position)?,
        }
    }
    Ok(())
}

/// The records of a Chunk record `data` (read up to byte `position`): decompressed into `chunk`
/// (or borrowed, uncompressed) and checked against the chunk's CRC.
fn decompress_chunk<'a>(data: &'a [u8], position: u64, zstd: &mut zstd::bulk::Decompressor<'_>, chunk: &'a mut Vec<u8>) -> Result<&'a [u8], String> {
    let Record::Chunk { header, data: compressed } = parse_checked(mcap::records::op::CHUNK, data).map_err(|e| format!("chunk record before byte {position}: {e}"))? else {
        unreachable!("a chunk opcode parses as a chunk")
    };
    let start = header.message_start_time;
    let damaged = |what: String| format!("chunk starting at log time {start} ns: {what}");
    let size = usize::try_from(header.uncompressed_size).ok().filter(|n| *n <= MAX_CHUNK).ok_or_else(|| damaged(format!("claims {} bytes uncompressed", header.uncompressed_size)))?;
    let body: &[u8] = match header.compression.as_str() {
        "" => match compressed {
            std::borrow::Cow::Borrowed(b) => b,
            std::borrow::Cow::Owned(b) => {
                *chunk = b;
                chunk
            }
        },
        "zstd" if size <= RESERVE_CHUNK => {
            // Into a buffer of the claimed size, reused from chunk to chunk (the fast path).
            chunk.clear();
            chunk.reserve(size);
            let n = zstd.decompress_to_buffer(&compressed, chunk).map_err(|e| damaged(format!("zstd: {e}")))?;
            if n != size {
                return Err(damaged(format!("{n} bytes uncompressed, header says {size}")));
            }
            chunk
        }
        "zstd" => {
            // A large claim is streamed, not reserved: memory follows what the data
            // decompresses to (at most the claim, at most MAX_CHUNK), never a damaged header.
            let decoder = zstd::stream::read::Decoder::with_buffer(&compressed[..]).map_err(|e| damaged(format!("zstd: {e}")))?;
            decompress_claimed("zstd", decoder, size, chunk).map_err(damaged)?;
            chunk
        }
        // LZ4 frames (rosbag2's and the mcap CLI's other choice), streamed the same way.
        "lz4" => {
            decompress_claimed("lz4", lz4_flex::frame::FrameDecoder::new(&compressed[..]), size, chunk).map_err(damaged)?;
            chunk
        }
        other => return Err(damaged(format!("unsupported compression '{other}' (zstd, lz4 or none)"))),
    };
    if header.uncompressed_crc != 0 && crc32fast::hash(body) != header.uncompressed_crc {
        return Err(damaged("CRC mismatch".into()));
    }
    Ok(body)
}

/// Decompress `decoder` into `out` (cleared first), reading at most one byte past the chunk's claimed
/// `size`: memory follows what the data holds, never more than the claim; a size other than the claim
/// is an error. `codec` names the decoder in its errors.
fn decompress_claimed(codec: &str, decoder: impl Read, size: usize, out: &mut Vec<u8>) -> Result<(), String> {
    out.clear();
    let n = decoder.take(size as u64 + 1).read_to_end(out).map_err(|e| format!("{codec}: {e}"))?;
    if n != size {
        return Err(format!("{} bytes uncompressed, header says {size}", if n > size { format!("more than {size}") } else { n.to_string() }));
    }
    Ok(())
}

/// Largest uncompressed chunk accepted, bytes (a damaged header or a zstd bomb must not make us allocate
/// without bound): 256 MiB, far above rosbag2's and the mcap CLI's chunk sizes (about 1-4 MiB).
pub const MAX_CHUNK: usize = 256 << 20;
/// Chunks claiming up to this are decompressed into a buffer reserved for the claim (16 MiB at most);
/// larger claims are streamed.
const RESERVE_CHUNK: usize = 16 << 20;

/// One record of a chunk's records: (opcode, body, what follows).
fn split_record(data: &[u8]) -> Option<(u8, &[u8], &[u8])> {
    let (&opcode, rest) = data.split_first()?;
    let (len, rest) = rest.split_at_checked(8)?;
    let len = usize::try_from(u64::from_le_bytes(len.try_into().ok()?)).ok()?;
    let (body, tail) = rest.split_at_checked(len)?;
    Some((opcode, body, tail))
}

/// The schemas and channels seen so far, and the messages visited.
struct Records {
    schemas: HashMap<u16, String>,
    /// By channel id.
    channels: Vec<Option<ChannelInfo>>,
    count: u64,
    file: usize,
}

impl Records {
    fn record(&mut self, path: &Path, opcode: u8, data: &[u8], position: u64, visit: &mut impl FnMut(MessageView<'_>)) -> Result<(), RecordError> {
        match opcode {
            mcap::records::op::MESSAGE => {
                let (header, body) = message_header(data).ok_or_else(|| mcap_error(path, format!("message record of {} bytes is too short", data.len())))?;
                let channel = self
                    .channels
                    .get(usize::from(header.channel_id))
                    .and_then(Option::as_ref)
                    .ok_or_else(|| mcap_error(path, format!("message on channel {} before its Channel record", header.channel_id)))?;
                self.count += 1;
                visit(MessageView {
                    channel,
                    sequence: header.sequence,
                    log_time: header.log_time,
                    publish_time: header.publish_time,
                    data: body,
                    file_position: position,
                    file: self.file,
                });
            }
            mcap::records::op::SCHEMA | mcap::records::op::CHANNEL => match parse_checked(opcode, data)
                .map_err(|e| mcap_error(path, format!("{} record before byte {position}: {e}", if opcode == mcap::records::op::SCHEMA { "schema" } else { "channel" })))?
            {
                Record::Schema { header, .. } => {
                    self.schemas.insert(header.id, header.name);
                }
                Record::Channel(c) => {
                    let schema_name = if c.schema_id == 0 {
                        String::new()
                    } else {
                        self.schemas
                            .get(&c.schema_id)
                            .cloned()
                            .ok_or_else(|| mcap_error(path, format!("channel {} '{}' names unknown schema {}", c.id, c.topic, c.schema_id)))?
                    };
                    let slot = usize::from(c.id);
                    if self.channels.len() <= slot {
                        self.channels.resize(slot + 1, None);
                    }
                    self.channels[slot] = Some(ChannelInfo { id: c.id, topic: c.topic, schema_name, message_encoding: c.message_encoding });
                }
                _ => {}
            },
            _ => {}
        }
        Ok(())
    }
}

/// Parse a record with the mcap crate, its length prefixes checked first ([`check_prefixes`]): the
/// one way records are parsed here, so that no caller can skip the check.
pub(crate) fn parse_checked(opcode: u8, data: &[u8]) -> Result<Record<'_>, String> {
    check_prefixes(opcode, data)?;
    mcap::parse_record(opcode, data).map_err(|e| e.to_string())
}

/// A field of a record, for [`check_prefixes`].
enum Field {
    /// Fixed-width fields, bytes.
    Fixed(usize),
    /// A string or byte array after its u32 length.
    Prefixed32(&'static str),
    /// A byte array after its u64 length.
    Prefixed64(&'static str),
    /// A map of strings to strings after its u32 byte length.
    StringMap(&'static str),
}

/// Check the length-prefixed fields of a Chunk, Schema, Channel or Metadata record (MCAP spec, "Records")
/// against the bytes the record holds, before the mcap crate parses it: its parser reserves what a
/// prefix claims before reading, so a damaged prefix (up to 4 GiB for a string, 2^64 bytes for a
/// chunk's records) would allocate without bound.
fn check_prefixes(opcode: u8, data: &[u8]) -> Result<(), String> {
    use mcap::records::op;
    use Field::*;
    let layout: &[Field] = match opcode {
        // message_start_time, message_end_time, uncompressed_size, uncompressed_crc.
        op::CHUNK => &[Fixed(8 + 8 + 8 + 4), Prefixed32("compression"), Prefixed64("records")],
        op::SCHEMA => &[Fixed(2), Prefixed32("name"), Prefixed32("encoding"), Prefixed32("data")],
        // id, schema_id.
        op::CHANNEL => &[Fixed(2 + 2), Prefixed32("topic"), Prefixed32("message_encoding"), StringMap("metadata")],
        op::METADATA => &[Prefixed32("name"), StringMap("metadata")],
        _ => &[],
    };
    let mut at = 0usize;
    let take = |at: &mut usize, width: usize, field: &str, data: &[u8]| -> Result<u64, String> {
        let b = data.get(*at..*at + width).ok_or_else(|| format!("{field}: the record ends at byte {} of its {}", *at, data.len()))?;
        *at += width;
        Ok(b.iter().rev().fold(0u64, |v, &x| (v << 8) | u64::from(x)))
    };
    let skip = |at: &mut usize, len: u64, field: &str, data: &[u8]| -> Result<(), String> {
        let left = (data.len() - *at) as u64;
        if len > left {
            return Err(format!("{field} claims {len} bytes, {left} remain in the record"));
        }
        *at += len as usize;
        Ok(())
    };
    for f in layout {
        match *f {
            Fixed(n) => skip(&mut at, n as u64, "fixed fields", data)?,
            Prefixed32(field) => {
                let n = take(&mut at, 4, field, data)?;
                skip(&mut at, n, field, data)?;
            }
            Prefixed64(field) => {
                let n = take(&mut at, 8, field, data)?;
                skip(&mut at, n, field, data)?;
            }
            StringMap(field) => {
                let n = take(&mut at, 4, field, data)?;
                let end = at;
                skip(&mut at, n, field, data)?;
                // Each key and value inside the map, against the map's own bytes.
                let map = &data[end..at];
                let mut k = 0usize;
                while k < map.len() {
                    for part in ["key", "value"] {
                        let len = take(&mut k, 4, field, map).map_err(|e| format!("{e} ({part})"))?;
                        skip(&mut k, len, field, map).map_err(|e| format!("{e} ({part})"))?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// The fixed part of a Message record (channel id u16, sequence u32, log time u64, publish time
/// u64, little endian) and the message data after it.
pub(crate) fn message_header(data: &[u8]) -> Option<(mcap::records::MessageHeader, &[u8])> {
    let (head, body) = data.split_at_checked(22)?;
    let u64_at = |k: usize| u64::from_le_bytes(head[k..k + 8].try_into().expect("8 bytes"));
    let header = mcap::records::MessageHeader {
        channel_id: u16::from_le_bytes([head[0], head[1]]),
        sequence: u32::from_le_bytes(head[2..6].try_into().expect("4 bytes")),
        log_time: u64_at(6),
        publish_time: u64_at(14),
    };
    Some((header, body))
}
