//! A streaming MCAP writer whose memory does not grow with the recording (MCAP spec,
//! <https://mcap.dev/spec>): one chunk of records in memory (closed at a size or by the caller), its
//! message indexes, and the schemas and channels. Each closed chunk's Chunk Index record is encoded
//! into an unlinked temporary file and copied into the summary at the end, so a 10-hour recording
//! (tens of thousands of chunks) holds no index in memory. The `mcap` crate's writer keeps every
//! chunk index until it finishes (O(chunks)); its readers still read what this writes.
//!
//! Layout written: magic, Header; data section of Metadata records and zstd Chunks (Schema, Channel
//! and Message records), each chunk followed by its Message Index records; Data End with the data
//! section's CRC; summary of Schemas, Channels, Statistics, Chunk Indexes, Metadata Indexes and their
//! Summary Offsets; Footer with the summary's CRC; magic.

use mcap::records::op;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufWriter, Read, Seek, Write};

/// MCAP's magic bytes, at the start and the end of a file.
const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// zstd level of the chunks, compressed whole on the recorder's thread. At level 1 the 1-hour bench
/// recording (benches/long-program) takes 3.35 GB (3.8:1), against 3.34 GB from the `mcap` crate's
/// default (level 3, multithreaded), and `run --mcap` took 26 s instead of 47.
const ZSTD_LEVEL: i32 = 1;

/// A write refused before any byte reached the file, or a failed write.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    #[error(transparent)]
    Io(#[from] io::Error),
    #[error("message on channel {0}, which was not added")]
    UnknownChannel(u16),
    #[error("more than 65535 {0}")]
    TooMany(&'static str),
    #[error("the writer has finished")]
    Finished,
}

/// A schema or channel as the summary repeats it: its id and its encoded record body.
struct Declared {
    id: u16,
    body: Vec<u8>,
}

/// The output, counting the bytes handed to it and hashing them (CRC-32) for the data section's
/// and the summary's checksums.
struct Counted<W: Write> {
    out: W,
    position: u64,
    crc: crc32fast::Hasher,
}

impl<W: Write> Counted<W> {
    fn put(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.out.write_all(bytes)?;
        self.crc.update(bytes);
        self.position += bytes.len() as u64;
        Ok(())
    }

    /// One record: opcode, body length (u64) and body.
    fn record(&mut self, opcode: u8, body: &[u8]) -> io::Result<()> {
        self.put(&record_head(opcode, body.len() as u64))?;
        self.put(body)
    }
}

fn record_head(opcode: u8, len: u64) -> [u8; 9] {
    let mut h = [0u8; 9];
    h[0] = opcode;
    h[1..].copy_from_slice(&len.to_le_bytes());
    h
}

/// Little-endian field encoders over a body buffer (MCAP's primitive types).
trait Body {
    fn u16(&mut self, v: u16) -> &mut Self;
    fn u32(&mut self, v: u32) -> &mut Self;
    fn u64(&mut self, v: u64) -> &mut Self;
    /// `uint32` length-prefixed bytes (String, Bytes).
    fn prefixed(&mut self, v: &[u8]) -> &mut Self;
    fn string_map(&mut self, map: &BTreeMap<String, String>) -> &mut Self;
}

impl Body for Vec<u8> {
    fn u16(&mut self, v: u16) -> &mut Self {
        self.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn u32(&mut self, v: u32) -> &mut Self {
        self.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn u64(&mut self, v: u64) -> &mut Self {
        self.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn prefixed(&mut self, v: &[u8]) -> &mut Self {
        self.u32(v.len() as u32);
        self.extend_from_slice(v);
        self
    }
    fn string_map(&mut self, map: &BTreeMap<String, String>) -> &mut Self {
        let len: usize = map.iter().map(|(k, v)| 8 + k.len() + v.len()).sum();
        self.u32(len as u32);
        for (k, v) in map {
            self.prefixed(k.as_bytes()).prefixed(v.as_bytes());
        }
        self
    }
}

/// Writes one MCAP file in the `ros2` profile to `W` (which need not seek). Schema and Channel
/// records go into the chunk open when they are declared (as the `mcap` crate writes them) and are
/// repeated in the summary.
pub struct McapWriter<W: Write> {
    out: Counted<W>,
    /// Close a chunk once its uncompressed records reach this many bytes.
    chunk_bytes: usize,
    /// The open chunk's records, uncompressed, and its message time bounds.
    chunk: Vec<u8>,
    chunk_times: Option<(u64, u64)>,
    /// The open chunk's message index entries per channel: (log time, offset in the chunk's records).
    /// Kept across chunks (cleared, capacity reused).
    chunk_index: Vec<Vec<(u64, u64)>>,
    compressor: zstd::bulk::Compressor<'static>,
    compressed: Vec<u8>,
    scratch: Vec<u8>,
    schemas: Vec<Declared>,
    channels: Vec<Declared>,
    /// Messages written per channel, and the first and last log time.
    message_counts: Vec<u64>,
    message_times: Option<(u64, u64)>,
    chunk_count: u32,
    /// Encoded Chunk Index records of the chunks written, spilled to an unlinked temporary file.
    chunk_indexes: BufWriter<File>,
    chunk_indexes_len: u64,
    /// Metadata Index records (few: one per Metadata record written).
    metadata_indexes: Vec<u8>,
    metadata_count: u32,
    finished: bool,
}

impl<W: Write> McapWriter<W> {
    /// Start a file on `out`: magic and Header (profile `ros2`, `library`).
    pub fn new(out: W, library: &str, chunk_bytes: u64) -> Result<Self, WriteError> {
        let mut w = McapWriter {
            out: Counted { out, position: 0, crc: crc32fast::Hasher::new() },
            chunk_bytes: chunk_bytes.clamp(1, 1 << 30) as usize,
            chunk: Vec::new(),
            chunk_times: None,
            chunk_index: Vec::new(),
            compressor: zstd::bulk::Compressor::new(ZSTD_LEVEL)?,
            compressed: Vec::new(),
            scratch: Vec::new(),
            schemas: Vec::new(),
            channels: Vec::new(),
            message_counts: Vec::new(),
            message_times: None,
            chunk_count: 0,
            chunk_indexes: BufWriter::new(tempfile::tempfile()?),
            chunk_indexes_len: 0,
            metadata_indexes: Vec::new(),
            metadata_count: 0,
            finished: false,
        };
        w.out.put(MAGIC)?;
        let mut body = Vec::new();
        body.prefixed(b"ros2").prefixed(library.as_bytes());
        w.out.record(op::HEADER, &body)?;
        Ok(w)
    }

    fn live(&self) -> Result<(), WriteError> {
        if self.finished {
            return Err(WriteError::Finished);
        }
        Ok(())
    }

    /// Messages written on each channel, by channel id.
    pub fn message_counts(&self) -> &[u64] {
        &self.message_counts
    }

    /// Bytes handed to the output so far (the file offset of the next record outside a chunk).
    pub fn position(&self) -> u64 {
        self.out.position
    }

    /// Declare a schema; the same name, encoding and text twice give the same id (ids from 1).
    pub fn add_schema(&mut self, name: &str, encoding: &str, data: &[u8]) -> Result<u16, WriteError> {
        self.live()?;
        let mut tail = Vec::new();
        tail.prefixed(name.as_bytes()).prefixed(encoding.as_bytes()).prefixed(data);
        if let Some(s) = self.schemas.iter().find(|s| s.body[2..] == tail[..]) {
            return Ok(s.id);
        }
        let id = u16::try_from(self.schemas.len() + 1).map_err(|_| WriteError::TooMany("schemas"))?;
        let mut body = id.to_le_bytes().to_vec();
        body.extend_from_slice(&tail);
        self.chunk_record(op::SCHEMA, &body);
        self.schemas.push(Declared { id, body });
        Ok(id)
    }

    /// Declare a channel (`schema_id` 0: no schema); the same declaration twice gives the same id.
    pub fn add_channel(&mut self, schema_id: u16, topic: &str, encoding: &str, metadata: &BTreeMap<String, String>) -> Result<u16, WriteError> {
        self.live()?;
        let mut tail = Vec::new();
        tail.u16(schema_id).prefixed(topic.as_bytes()).prefixed(encoding.as_bytes()).string_map(metadata);
        if let Some(c) = self.channels.iter().find(|c| c.body[2..] == tail[..]) {
            return Ok(c.id);
        }
        let id = u16::try_from(self.channels.len()).map_err(|_| WriteError::TooMany("channels"))?;
        let mut body = id.to_le_bytes().to_vec();
        body.extend_from_slice(&tail);
        self.chunk_record(op::CHANNEL, &body);
        self.channels.push(Declared { id, body });
        self.chunk_index.push(Vec::new());
        self.message_counts.push(0);
        Ok(id)
    }

    /// Append a record to the open chunk.
    fn chunk_record(&mut self, opcode: u8, body: &[u8]) {
        self.chunk.extend_from_slice(&record_head(opcode, body.len() as u64));
        self.chunk.extend_from_slice(body);
    }

    /// Write one message (`data` already encoded) into the open chunk; the chunk is closed once it
    /// holds the chunk size.
    pub fn write_message(&mut self, channel: u16, sequence: u32, log_time: u64, publish_time: u64, data: &[u8]) -> Result<(), WriteError> {
        self.live()?;
        if usize::from(channel) >= self.channels.len() {
            return Err(WriteError::UnknownChannel(channel));
        }
        let offset = self.chunk.len() as u64;
        self.chunk.extend_from_slice(&record_head(op::MESSAGE, 22 + data.len() as u64));
        self.chunk.extend_from_slice(&channel.to_le_bytes());
        self.chunk.extend_from_slice(&sequence.to_le_bytes());
        self.chunk.extend_from_slice(&log_time.to_le_bytes());
        self.chunk.extend_from_slice(&publish_time.to_le_bytes());
        self.chunk.extend_from_slice(data);
        self.chunk_index[usize::from(channel)].push((log_time, offset));
        self.chunk_times = Some(self.chunk_times.map_or((log_time, log_time), |(a, b)| (a.min(log_time), b.max(log_time))));
        self.message_times = Some(self.message_times.map_or((log_time, log_time), |(a, b)| (a.min(log_time), b.max(log_time))));
        self.message_counts[usize::from(channel)] += 1;
        if self.chunk.len() >= self.chunk_bytes {
            self.close_chunk()?;
        }
        Ok(())
    }

    /// Compress and write the open chunk (if it holds any record) and its Message Index records, and
    /// spill its Chunk Index record.
    pub fn close_chunk(&mut self) -> Result<(), WriteError> {
        self.live()?;
        if self.chunk.is_empty() {
            return Ok(());
        }
        let chunk_start = self.out.position;
        self.compressed.clear();
        self.compressed.reserve(zstd::zstd_safe::compress_bound(self.chunk.len()));
        self.compressor.compress_to_buffer(&self.chunk[..], &mut self.compressed)?;
        let (start, end) = self.chunk_times.unwrap_or((0, 0));
        let head = &mut self.scratch;
        head.clear();
        head.u64(start).u64(end).u64(self.chunk.len() as u64).u32(crc32fast::hash(&self.chunk)).prefixed(b"zstd").u64(self.compressed.len() as u64);
        self.out.put(&record_head(op::CHUNK, (head.len() + self.compressed.len()) as u64))?;
        self.out.put(head)?;
        self.out.put(&self.compressed)?;
        let chunk_length = self.out.position - chunk_start;
        // Message Index records, one per channel with messages in the chunk, in channel order.
        let mut offsets = Vec::new();
        let index_start = self.out.position;
        for (channel, entries) in self.chunk_index.iter_mut().enumerate().filter(|(_, e)| !e.is_empty()) {
            let channel = channel as u16;
            offsets.push((channel, self.out.position));
            let body = &mut self.scratch;
            body.clear();
            body.u16(channel).u32((entries.len() * 16) as u32);
            for &(t, o) in entries.iter() {
                body.u64(t).u64(o);
            }
            entries.clear();
            self.out.record(op::MESSAGE_INDEX, body)?;
        }
        let index_length = self.out.position - index_start;
        let mut body = Vec::with_capacity(80 + offsets.len() * 10);
        body.u64(start).u64(end).u64(chunk_start).u64(chunk_length).u32((offsets.len() * 10) as u32);
        for (channel, at) in offsets {
            body.u16(channel).u64(at);
        }
        body.u64(index_length).prefixed(b"zstd").u64(self.compressed.len() as u64).u64(self.chunk.len() as u64);
        self.chunk_indexes.write_all(&record_head(op::CHUNK_INDEX, body.len() as u64))?;
        self.chunk_indexes.write_all(&body)?;
        self.chunk_indexes_len += 9 + body.len() as u64;
        self.chunk_count += 1;
        self.chunk.clear();
        self.chunk_times = None;
        Ok(())
    }

    /// Write a Metadata record (closing the open chunk first, as Metadata sits outside chunks).
    pub fn write_metadata(&mut self, name: &str, metadata: &BTreeMap<String, String>) -> Result<(), WriteError> {
        self.close_chunk()?;
        let offset = self.out.position;
        let mut body = Vec::new();
        body.prefixed(name.as_bytes()).string_map(metadata);
        self.out.record(op::METADATA, &body)?;
        let mut index = Vec::new();
        index.u64(offset).u64(9 + body.len() as u64).prefixed(name.as_bytes());
        self.metadata_indexes.extend_from_slice(&record_head(op::METADATA_INDEX, index.len() as u64));
        self.metadata_indexes.extend_from_slice(&index);
        self.metadata_count += 1;
        Ok(())
    }

    /// Close the open chunk and flush the output: what a reader can recover up to.
    pub fn flush(&mut self) -> Result<(), WriteError> {
        self.close_chunk()?;
        self.out.out.flush()?;
        Ok(())
    }

    /// Close the open chunk and write Data End, the summary and the Footer; flush the output.
    pub fn finish(&mut self) -> Result<(), WriteError> {
        self.close_chunk()?;
        self.finished = true;
        let data_crc = std::mem::replace(&mut self.out.crc, crc32fast::Hasher::new()).finalize();
        self.out.record(op::DATA_END, &data_crc.to_le_bytes())?;
        // The summary's CRC runs from its start through the Footer's summary_offset_start.
        self.out.crc = crc32fast::Hasher::new();
        let summary_start = self.out.position;
        let mut groups: Vec<(u8, u64, u64)> = Vec::new();
        let group = |groups: &mut Vec<(u8, u64, u64)>, opcode: u8, start: u64, end: u64| {
            if end > start {
                groups.push((opcode, start, end - start));
            }
        };
        let start = self.out.position;
        for s in &self.schemas {
            self.out.record(op::SCHEMA, &s.body)?;
        }
        group(&mut groups, op::SCHEMA, start, self.out.position);
        let start = self.out.position;
        for c in &self.channels {
            self.out.record(op::CHANNEL, &c.body)?;
        }
        group(&mut groups, op::CHANNEL, start, self.out.position);
        let start = self.out.position;
        let (first, last) = self.message_times.unwrap_or((0, 0));
        let mut stats = Vec::new();
        stats
            .u64(self.message_counts.iter().sum())
            .u16(self.schemas.len() as u16)
            .u32(self.channels.len() as u32)
            .u32(0)
            .u32(self.metadata_count)
            .u32(self.chunk_count)
            .u64(first)
            .u64(last)
            .u32((self.message_counts.iter().filter(|&&n| n > 0).count() * 10) as u32);
        for (channel, &n) in self.message_counts.iter().enumerate().filter(|(_, &n)| n > 0) {
            stats.u16(channel as u16).u64(n);
        }
        self.out.record(op::STATISTICS, &stats)?;
        group(&mut groups, op::STATISTICS, start, self.out.position);
        // The spilled chunk indexes, copied through.
        let start = self.out.position;
        self.chunk_indexes.flush()?;
        let spill = self.chunk_indexes.get_mut();
        spill.rewind()?;
        let mut left = self.chunk_indexes_len;
        let mut buf = vec![0u8; 1 << 16];
        while left > 0 {
            let n = spill.read(&mut buf[..left.min(1 << 16) as usize])?;
            if n == 0 {
                return Err(io::Error::new(io::ErrorKind::UnexpectedEof, "the chunk index spill file ended early").into());
            }
            self.out.put(&buf[..n])?;
            left -= n as u64;
        }
        group(&mut groups, op::CHUNK_INDEX, start, self.out.position);
        let start = self.out.position;
        self.out.put(&self.metadata_indexes)?;
        group(&mut groups, op::METADATA_INDEX, start, self.out.position);
        let offsets_start = self.out.position;
        for (opcode, start, len) in groups {
            let mut body = vec![opcode];
            body.u64(start).u64(len);
            self.out.record(op::SUMMARY_OFFSET, &body)?;
        }
        let mut footer = Vec::new();
        footer.u64(summary_start).u64(offsets_start);
        self.out.put(&record_head(op::FOOTER, 20))?;
        self.out.put(&footer)?;
        let summary_crc = std::mem::replace(&mut self.out.crc, crc32fast::Hasher::new()).finalize();
        self.out.put(&summary_crc.to_le_bytes())?;
        self.out.put(MAGIC)?;
        self.out.out.flush()?;
        Ok(())
    }

    /// The output, as it stands (after [`finish`](Self::finish): the whole file).
    pub fn into_inner(self) -> W {
        self.out.out
    }
}

#[cfg(test)]
mod tests {
    //! What this writer writes, read back by Foxglove's `mcap` crate (its linear reader checks the
    //! chunk CRCs; its summary reader follows the chunk and message indexes).
    use super::*;

    /// Three channels over two schemas (one shared), 2000 messages, chunks of about 4 KB.
    fn sample() -> (Vec<u8>, Vec<(u16, u32, u64, Vec<u8>)>) {
        let mut w = McapWriter::new(Vec::new(), "test", 4096).unwrap();
        let mut meta = BTreeMap::new();
        meta.insert("ROS_DISTRO".to_string(), "jazzy".to_string());
        w.write_metadata("rosbag2", &meta).unwrap();
        let a = w.add_schema("pkg/msg/A", "ros2msg", b"float64 x").unwrap();
        let b = w.add_schema("pkg/msg/B", "ros2msg", b"int32 y").unwrap();
        assert_eq!(w.add_schema("pkg/msg/A", "ros2msg", b"float64 x").unwrap(), a, "the same schema twice: one id");
        let qos = BTreeMap::from([("offered_qos_profiles".to_string(), "- history: keep_last".to_string())]);
        let channels = [
            w.add_channel(a, "/a", "cdr", &qos).unwrap(),
            w.add_channel(b, "/b", "cdr", &qos).unwrap(),
            w.add_channel(a, "/c", "cdr", &BTreeMap::new()).unwrap(),
        ];
        assert_eq!(w.add_channel(b, "/b", "cdr", &qos).unwrap(), channels[1]);
        assert!(matches!(w.write_message(9, 0, 0, 0, b""), Err(WriteError::UnknownChannel(9))));
        let mut sent = Vec::new();
        for i in 0..2000u64 {
            let channel = channels[(i % 3) as usize];
            let data: Vec<u8> = (0..(i % 40) as u8).collect();
            let t = 1_000_000_000 + i * 1_000_000;
            w.write_message(channel, i as u32, t, t - 5, &data).unwrap();
            sent.push((channel, i as u32, t, data));
            if i == 999 {
                w.flush().unwrap();
            }
        }
        w.finish().unwrap();
        assert!(matches!(w.write_message(channels[0], 0, 0, 0, b""), Err(WriteError::Finished)));
        (w.into_inner(), sent)
    }

    #[test]
    fn the_mcap_crate_reads_every_message_in_order() {
        let (file, sent) = sample();
        let got: Vec<_> = mcap::MessageStream::new(&file)
            .unwrap()
            .map(|m| {
                let m = m.unwrap();
                assert_eq!(m.publish_time + 5, m.log_time);
                (m.channel.id, m.sequence, m.log_time, m.data.to_vec())
            })
            .collect();
        assert_eq!(got, sent);
        let topics: Vec<_> = mcap::MessageStream::new(&file).unwrap().take(3).map(|m| m.unwrap().channel.topic.clone()).collect();
        assert_eq!(topics, ["/a", "/b", "/c"]);
    }

    #[test]
    fn summary_statistics_and_indexes_agree_with_the_messages() {
        let (file, sent) = sample();
        let summary = mcap::Summary::read(&file).unwrap().expect("a summary");
        let stats = summary.stats.as_ref().expect("statistics");
        assert_eq!(stats.message_count, 2000);
        assert_eq!((stats.schema_count, stats.channel_count, stats.metadata_count), (2, 3, 1));
        assert_eq!((stats.message_start_time, stats.message_end_time), (sent[0].2, sent[1999].2));
        assert_eq!(stats.channel_message_counts.values().copied().collect::<Vec<_>>(), [667, 667, 666]);
        assert_eq!(summary.channels.len(), 3);
        assert_eq!(summary.schemas.len(), 2);
        assert_eq!(summary.metadata_indexes.len(), 1);
        // 2000 messages of 31-70 bytes in chunks closed at 4096 bytes: dozens of chunks.
        assert!(summary.chunk_indexes.len() > 20, "{} chunks", summary.chunk_indexes.len());
        assert_eq!(stats.chunk_count as usize, summary.chunk_indexes.len());
        let mut read = Vec::new();
        for index in &summary.chunk_indexes {
            let in_chunk: Vec<_> = summary.stream_chunk(&file, index).unwrap().map(|m| m.unwrap()).collect();
            assert_eq!(index.message_start_time, in_chunk[0].log_time);
            assert_eq!(index.message_end_time, in_chunk.last().unwrap().log_time);
            // The message indexes point at each message of the chunk.
            let by_channel = summary.read_message_indexes(&file, index).unwrap();
            let entries: usize = by_channel.values().map(Vec::len).sum();
            assert_eq!(entries, in_chunk.len());
            for (channel, entries) in &by_channel {
                for e in entries {
                    let m = summary.seek_message(&file, index, e).unwrap();
                    assert_eq!((m.channel.id, m.log_time), (channel.id, e.log_time));
                }
            }
            read.extend(in_chunk.into_iter().map(|m| (m.channel.id, m.sequence, m.log_time, m.data.to_vec())));
        }
        assert_eq!(read, sent);
    }

    #[test]
    fn checksums_cover_the_data_section_and_the_summary() {
        let (file, _) = sample();
        let n = file.len();
        let footer = &file[n - 8 - 29..n - 8];
        let summary_start = u64::from_le_bytes(footer[9..17].try_into().unwrap()) as usize;
        let summary_crc = u32::from_le_bytes(footer[25..29].try_into().unwrap());
        assert_eq!(crc32fast::hash(&file[summary_start..n - 8 - 4]), summary_crc);
        // Data End is the 13 bytes before the summary; its CRC covers everything before it.
        let data_end = &file[summary_start - 13..summary_start];
        assert_eq!(data_end[0], op::DATA_END);
        assert_eq!(crc32fast::hash(&file[..summary_start - 13]), u32::from_le_bytes(data_end[9..13].try_into().unwrap()));
    }
}
