//! rosbag2's SQLite3 storage (`storage_identifier: sqlite3`, the default up to Humble): a `.db3` file
//! holds the tables `topics(id, name, type, serialization_format, offered_qos_profiles)` and
//! `messages(id, topic_id, timestamp, data)` (rosbag2_storage_sqlite3, `sqlite_storage.cpp`), and
//! rosbag2 reads its messages in timestamp order (`ORDER BY messages.timestamp`), as here. With
//! `compression_mode: MESSAGE` each message's data is a zstd frame; with `FILE` the whole file is one
//! (`.db3.zstd`), unpacked here to an unlinked temporary file. Rows are read one at a time: memory
//! holds one message, whatever the bag's size.

use super::read::{io_error, ChannelInfo, MessageView};
use super::RecordError;
use std::path::Path;

/// The largest message read (a JointState is a few hundred bytes; an image some MB): a row larger
/// than this is damage, refused rather than held.
const MAX_MESSAGE_BYTES: usize = 256 << 20;

/// Whether `path` is a rosbag2 SQLite3 file (`.db3`, or `.db3.zstd` compressed whole).
pub fn is_db3(path: &Path) -> bool {
    let name = path.file_name().map(|n| n.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    name.ends_with(".db3") || name.ends_with(".db3.zstd")
}

fn error(path: &Path, message: impl std::fmt::Display) -> RecordError {
    RecordError::Sqlite { path: path.to_path_buf(), message: message.to_string() }
}

/// Visit every message of the `.db3` file at `path` (file `file_index` of its bag, `offset` bytes of
/// the bag before it), in rosbag2's read order; `message_zstd`: each message's data is a zstd frame
/// (the bag's `compression_mode: MESSAGE`). Returns how many there were.
pub fn for_each_message_in_db(path: &Path, file_index: usize, offset: u64, message_zstd: bool, visit: &mut impl FnMut(MessageView<'_>)) -> Result<u64, RecordError> {
    // A whole-file zstd bag: unpacked to a temporary file that goes when it closes.
    let unpacked;
    let db_path = if path.to_string_lossy().to_ascii_lowercase().ends_with(".zstd") {
        let mut input = std::fs::File::open(path).map_err(io_error(path))?;
        let mut tmp = tempfile::NamedTempFile::new().map_err(io_error(path))?;
        zstd::stream::copy_decode(&mut input, tmp.as_file_mut()).map_err(|e| error(path, format!("its zstd compression: {e}")))?;
        unpacked = tmp;
        unpacked.path().to_path_buf()
    } else {
        path.to_path_buf()
    };
    let db = rusqlite::Connection::open_with_flags(&db_path, rusqlite::OpenFlags::SQLITE_OPEN_READ_ONLY | rusqlite::OpenFlags::SQLITE_OPEN_NO_MUTEX)
        .map_err(|e| error(path, format!("not an SQLite database: {e}")))?;
    // The topics, by id (a message's topic_id names one).
    let mut channels: Vec<(i64, ChannelInfo)> = Vec::new();
    {
        // rosbag2's first bags (metadata version 1, Crystal) have no serialization_format column: their
        // one format, named once in metadata.yaml, was CDR.
        let with_format = db.prepare("SELECT serialization_format FROM topics LIMIT 0").is_ok();
        let sql = if with_format { "SELECT id, name, type, serialization_format FROM topics ORDER BY id" } else { "SELECT id, name, type, 'cdr' FROM topics ORDER BY id" };
        let mut q = db.prepare(sql).map_err(|e| error(path, format!("no rosbag2 topics table: {e}")))?;
        let rows = q
            .query_map([], |r| Ok((r.get::<_, i64>(0)?, r.get::<_, String>(1)?, r.get::<_, String>(2)?, r.get::<_, String>(3)?)))
            .map_err(|e| error(path, format!("topics: {e}")))?;
        for (k, row) in rows.enumerate() {
            let (id, topic, schema_name, message_encoding) = row.map_err(|e| error(path, format!("topics row {}: {e}", k + 1)))?;
            let id16 = u16::try_from(k).map_err(|_| error(path, "more than 65,535 topics"))?;
            channels.push((id, ChannelInfo { id: id16, topic, schema_name, message_encoding }));
        }
    }
    channels.sort_by_key(|(id, _)| *id);
    let mut q = db
        .prepare("SELECT topic_id, timestamp, data FROM messages ORDER BY timestamp, id")
        .map_err(|e| error(path, format!("no rosbag2 messages table: {e}")))?;
    let mut rows = q.query([]).map_err(|e| error(path, format!("messages: {e}")))?;
    let (mut count, mut position) = (0u64, offset);
    let mut unpacked_data: Vec<u8>;
    let mut zstd = zstd::bulk::Decompressor::new().map_err(|e| error(path, format!("zstd: {e}")))?;
    while let Some(row) = rows.next().map_err(|e| error(path, format!("message {}: {e}", count + 1)))? {
        let topic_id: i64 = row.get(0).map_err(|e| error(path, format!("message {}: topic_id: {e}", count + 1)))?;
        let time: i64 = row.get(1).map_err(|e| error(path, format!("message {}: timestamp: {e}", count + 1)))?;
        let data = row.get_ref(2).map_err(|e| error(path, format!("message {}: data: {e}", count + 1)))?;
        let data = data.as_blob().map_err(|e| error(path, format!("message {}: data is not a blob: {e}", count + 1)))?;
        if data.len() > MAX_MESSAGE_BYTES {
            return Err(error(path, format!("message {}: {} bytes, more than {} MiB: damage", count + 1, data.len(), MAX_MESSAGE_BYTES >> 20)));
        }
        let Ok(k) = channels.binary_search_by_key(&topic_id, |(id, _)| *id) else {
            return Err(error(path, format!("message {} names topic_id {topic_id}, which the topics table has not", count + 1)));
        };
        let Ok(time) = u64::try_from(time) else {
            return Err(error(path, format!("message {}: a timestamp before 1970 ({time} ns)", count + 1)));
        };
        position += data.len() as u64;
        let data: &[u8] = if message_zstd {
            unpacked_data = zstd.decompress(data, MAX_MESSAGE_BYTES).map_err(|e| error(path, format!("message {}: its zstd frame: {e}", count + 1)))?;
            &unpacked_data
        } else {
            data
        };
        count += 1;
        // SQLite3 bags keep one time per message: the receive time, which is also its publish time here.
        visit(MessageView { channel: &channels[k].1, sequence: 0, log_time: time, publish_time: time, data, file_position: position, file: file_index });
    }
    Ok(count)
}
