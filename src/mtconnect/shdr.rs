//! SHDR, the MTConnect adapter's text stream (cppagent's "Adapter Agent Protocol"), read one line
//! at a time without I/O: `timestamp|key|value|key|value...`, where each key names a data item of
//! the device and takes as many fields as its kind has ([`DataItem::shdr_fields`]: a condition
//! five, a message two); `* command` lines; assets (`@ASSET@`, with `--multiline--TAG` bodies
//! running to the line that starts with the same tag), `@REMOVE_ASSET@`, `@REMOVE_ALL_ASSETS@`,
//! `@UPDATE_ASSET@`. Keys may carry a device prefix (`device:key`).

use super::devices::{DataItem, Device};
use crate::source::Stamp;

/// Why a line was refused (1-based column of the field).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShdrError {
    #[error("col {col}: '{text}' is not an ISO 8601 UTC timestamp")]
    Timestamp { col: usize, text: String },
    #[error("col {col}: data item '{key}' needs {need} fields after its key, the line has {have}")]
    Short { col: usize, key: String, need: usize, have: usize },
}

/// One observation of a data item of the device read.
#[derive(Debug, Clone, PartialEq)]
pub struct Observation<'a> {
    pub item: &'a DataItem,
    pub fields: Vec<&'a str>,
    /// 1-based column of its first value.
    pub col: usize,
}

/// What a line held.
#[derive(Debug, Clone, PartialEq)]
pub enum Line<'a> {
    /// Observations of the device's data items at a time (keys of unknown items and of other
    /// devices are skipped, as the agent skips them).
    Data { stamp: Stamp, observations: Vec<Observation<'a>> },
    /// A command (`* PING`, `* shdrVersion: 2`), an asset or a line of an asset's body, a blank line.
    Other,
}

/// The reader's state between lines: a multiline asset's closing tag while inside one.
#[derive(Debug, Default)]
pub struct ShdrReader {
    multiline: Option<String>,
}

impl ShdrReader {
    /// Read one line (without its line end) against `device` (the one its keys name, `devices`
    /// for keys prefixed with another's name). A timestamp may carry a duration (`T@seconds`, cut
    /// off); an empty one is the time it was received, `now`, as the agent takes it
    /// (cppagent's timestamp_extractor.cpp), and refused where there is none (a log read later).
    pub fn line<'a>(&mut self, text: &'a str, device: &'a Device, devices: &'a [Device], now: Option<Stamp>) -> Result<Line<'a>, ShdrError> {
        if let Some(tag) = &self.multiline {
            if text.starts_with(tag.as_str()) {
                self.multiline = None;
            }
            return Ok(Line::Other);
        }
        if text.trim().is_empty() || text.starts_with('*') {
            return Ok(Line::Other);
        }
        let fields: Vec<&str> = text.split('|').collect();
        let stamp_text = fields[0].split('@').next().unwrap_or("").trim();
        let stamp = match (stamp_text, now) {
            ("", Some(now)) => Some(now),
            (t, _) => Stamp::parse(t),
        };
        let stamp = stamp.ok_or_else(|| ShdrError::Timestamp { col: 1, text: fields[0].chars().take(40).collect() })?;
        let col_of = |k: usize| fields[..k].iter().map(|f| f.len() + 1).sum::<usize>() + 1;
        let mut observations = Vec::new();
        let mut k = 1;
        while k < fields.len() {
            let key = fields[k];
            if key.starts_with('@') && key.ends_with('@') {
                // An asset command takes the rest of the line; a multiline body follows.
                if key == "@ASSET@" {
                    if let Some(tag) = fields.last().and_then(|l| l.strip_prefix("--multiline--")) {
                        self.multiline = Some(format!("--multiline--{tag}"));
                    }
                }
                break;
            }
            let (dev, name) = match key.split_once(':') {
                Some((d, n)) => (devices.iter().find(|x| x.name == d || x.uuid.as_deref() == Some(d)), n),
                None => (Some(device), key),
            };
            let item = dev.and_then(|d| d.item(name));
            let need = item.map_or(1, DataItem::shdr_fields);
            let have = fields.len() - k - 1;
            if have < need {
                return Err(ShdrError::Short { col: col_of(k), key: key.to_string(), need, have });
            }
            if let Some(item) = item.filter(|_| dev.is_some_and(|d| std::ptr::eq(d, device))) {
                observations.push(Observation { item, fields: fields[k + 1..k + 1 + need].to_vec(), col: col_of(k + 1) });
            }
            k += 1 + need;
        }
        Ok(Line::Data { stamp, observations })
    }
}
