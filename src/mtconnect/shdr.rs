//! SHDR, the MTConnect adapter's text stream (cppagent's "Adapter Agent Protocol"), read one line
//! at a time without I/O: `timestamp|key|value|key|value...`, where each key names a data item of
//! the device and takes as many fields as its kind has ([`DataItem::shdr_fields`]: a condition
//! five, a message two); `* command` lines; assets (`@ASSET@`, with `--multiline--TAG` bodies
//! running to the line that starts with the same tag), `@REMOVE_ASSET@`, `@REMOVE_ALL_ASSETS@`,
//! `@UPDATE_ASSET@`. Keys may carry a device prefix (`device:key`).

use super::devices::{DataItem, Device};

/// A line's timestamp: seconds since the Unix epoch and nanoseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Stamp {
    pub sec: i64,
    pub nanosec: u32,
}

impl Stamp {
    /// The wall clock now.
    pub fn now() -> Stamp {
        let d = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap_or_default();
        Stamp { sec: i64::try_from(d.as_secs()).unwrap_or(i64::MAX), nanosec: d.subsec_nanos() }
    }

    /// ISO 8601 in UTC as adapters write it: `2022-08-08T13:51:34.7167146Z` (fraction optional, up
    /// to nine digits; `Z`, `+HH:MM`, `-HH:MM` or nothing, taken as UTC).
    pub fn parse(text: &str) -> Option<Stamp> {
        let b = text.as_bytes();
        let num = |r: std::ops::Range<usize>| -> Option<i64> {
            let s = text.get(r)?;
            (!s.is_empty() && s.bytes().all(|c| c.is_ascii_digit())).then(|| s.parse().ok())?
        };
        if b.len() < 19 || b[4] != b'-' || b[7] != b'-' || !matches!(b[10], b'T' | b' ') || b[13] != b':' || b[16] != b':' {
            return None;
        }
        let (y, mo, d, h, mi, s) = (num(0..4)?, num(5..7)?, num(8..10)?, num(11..13)?, num(14..16)?, num(17..19)?);
        if !(1..=12).contains(&mo) || !(1..=31).contains(&d) || h > 23 || mi > 59 || s > 60 {
            return None;
        }
        let mut k = 19;
        let mut nanosec = 0u32;
        if b.get(k) == Some(&b'.') {
            let start = k + 1;
            k = start;
            while k < b.len() && b[k].is_ascii_digit() {
                k += 1;
            }
            let digits = &text[start..k];
            if digits.is_empty() {
                return None;
            }
            let mut scaled = 0u64;
            for (i, c) in digits.bytes().enumerate() {
                if i < 9 {
                    scaled = scaled * 10 + u64::from(c - b'0');
                }
            }
            for _ in digits.len()..9 {
                scaled *= 10;
            }
            nanosec = scaled as u32;
        }
        let offset = match &text[k..] {
            "" | "Z" => 0,
            tz if tz.len() == 6 && (tz.starts_with('+') || tz.starts_with('-')) && tz.as_bytes()[3] == b':' => {
                let (oh, om) = (num(k + 1..k + 3)?, num(k + 4..k + 6)?);
                let sign = if tz.starts_with('-') { -1 } else { 1 };
                sign * (oh * 3600 + om * 60)
            }
            _ => return None,
        };
        // Days from the civil date (H. Hinnant's days_from_civil).
        let y = if mo <= 2 { y - 1 } else { y };
        let era = y.div_euclid(400);
        let yoe = y - era * 400;
        let mp = (mo + 9) % 12;
        let doy = (153 * mp + 2) / 5 + d - 1;
        let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
        let days = era * 146_097 + doe - 719_468;
        Some(Stamp { sec: days * 86_400 + h * 3600 + mi * 60 + s - offset, nanosec })
    }

    pub fn as_secs(self) -> f64 {
        self.sec as f64 + f64::from(self.nanosec) * 1e-9
    }
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timestamps() {
        // 2022-08-08T13:51:34Z is 1659966694 s after the epoch (date -u -d ... +%s).
        assert_eq!(Stamp::parse("2022-08-08T13:51:34.7167146Z"), Some(Stamp { sec: 1_659_966_694, nanosec: 716_714_600 }));
        assert_eq!(Stamp::parse("2026-01-01T00:00:00Z"), Some(Stamp { sec: 1_767_225_600, nanosec: 0 }));
        assert_eq!(Stamp::parse("2026-01-01T01:00:00+01:00"), Some(Stamp { sec: 1_767_225_600, nanosec: 0 }));
        assert_eq!(Stamp::parse("2000-02-29T00:00:00.5"), Some(Stamp { sec: 951_782_400, nanosec: 500_000_000 }));
        for bad in ["", "12.5", "2022-13-01T00:00:00Z", "2022-08-08T13:51:34.Z", "2022-08-08T13:51:34Q", "2022-08-08X13:51:34"] {
            assert_eq!(Stamp::parse(bad), None, "{bad}");
        }
    }
}
