//! Allocation-free CDR decoding of the hot messages ([`AxisState`], [`JointState`]) into a reused
//! value, for the offline analysis of recordings with millions of them. The wire format is the one
//! serde + `cdr_encoding` writes and ROS 2 uses (plain CDR / XCDR1: a 4-byte encapsulation header,
//! then primitives aligned to their size relative to the body start, strings and sequences as a u32
//! count then the elements). The values are the same as serde's decoding gives (tested against it);
//! strings and vectors of the target keep their capacity, so a warm decode allocates nothing.

use crate::bounds::{MAX_FRAME_ID_BYTES, MAX_JOINTS, MAX_NAME_BYTES};

// The reasons below spell the bounds out (a `&'static str` cannot format them): kept equal here.
const _: () = assert!(MAX_JOINTS == 256 && MAX_NAME_BYTES == 256 && MAX_FRAME_ID_BYTES == 1024);
use crate::{AxisState, Header, JointState, Point, Time, Vector3};

/// Why a CDR message did not decode: the field and the byte offset (from the encapsulation header).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CdrError {
    pub offset: usize,
    pub field: &'static str,
    pub reason: &'static str,
}

impl std::fmt::Display for CdrError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} at byte {}: {}", self.field, self.offset, self.reason)
    }
}

impl std::error::Error for CdrError {}

/// Byte equality without a library call for the short strings of these messages.
#[inline]
fn same_bytes(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && if a.len() <= 16 { a.iter().zip(b).all(|(x, y)| x == y) } else { a == b }
}

/// Values from their CDR bytes in the message's byte order: the one place it is applied (a
/// sequence of doubles, [`CdrReader::f64s_into`], chooses it once for the whole run instead).
#[inline]
fn u32_in(b: [u8; 4], big_endian: bool) -> u32 {
    if big_endian { u32::from_be_bytes(b) } else { u32::from_le_bytes(b) }
}

#[inline]
fn i64_in(b: [u8; 8], big_endian: bool) -> i64 {
    if big_endian { i64::from_be_bytes(b) } else { i64::from_le_bytes(b) }
}

#[inline]
fn f64_in(b: [u8; 8], big_endian: bool) -> f64 {
    if big_endian { f64::from_be_bytes(b) } else { f64::from_le_bytes(b) }
}

#[cold]
fn cut_short(body_offset: usize, field: &'static str) -> CdrError {
    CdrError { offset: 4 + body_offset, field, reason: "message ends inside the field" }
}

/// A cursor over a CDR body (after the 4-byte encapsulation header).
pub struct CdrReader<'a> {
    body: &'a [u8],
    pos: usize,
    big_endian: bool,
}

impl<'a> CdrReader<'a> {
    /// Start on a whole message: checks the encapsulation header (CDR_LE/CDR_BE, PL_CDR_LE/BE).
    pub fn new(data: &'a [u8]) -> Result<Self, CdrError> {
        if data.len() < 4 {
            return Err(CdrError { offset: 0, field: "encapsulation header", reason: "shorter than 4 bytes" });
        }
        let big_endian = match data[1] {
            0x01 | 0x03 => false,
            0x00 | 0x02 => true,
            _ => return Err(CdrError { offset: 1, field: "encapsulation header", reason: "unsupported encapsulation kind" }),
        };
        Ok(CdrReader { body: &data[4..], pos: 0, big_endian })
    }

    #[inline]
    fn take<const N: usize>(&mut self, field: &'static str) -> Result<[u8; N], CdrError> {
        // Primitives are aligned to their size, relative to the body start.
        let start = self.pos.next_multiple_of(N);
        match self.body.get(start..start + N) {
            Some(bytes) => {
                self.pos = start + N;
                Ok(bytes.try_into().expect("N bytes"))
            }
            None => Err(cut_short(start, field)),
        }
    }

    pub fn u8(&mut self, field: &'static str) -> Result<u8, CdrError> {
        Ok(self.take::<1>(field)?[0])
    }

    pub fn u32(&mut self, field: &'static str) -> Result<u32, CdrError> {
        Ok(u32_in(self.take(field)?, self.big_endian))
    }

    pub fn i32(&mut self, field: &'static str) -> Result<i32, CdrError> {
        Ok(self.u32(field)? as i32)
    }

    pub fn i64(&mut self, field: &'static str) -> Result<i64, CdrError> {
        Ok(i64_in(self.take(field)?, self.big_endian))
    }

    pub fn f64(&mut self, field: &'static str) -> Result<f64, CdrError> {
        Ok(f64_in(self.take(field)?, self.big_endian))
    }

    /// A sequence count, checked against the bytes left (at `min_size` bytes per element).
    fn count(&mut self, field: &'static str, min_size: usize) -> Result<usize, CdrError> {
        let n = self.u32(field)? as usize;
        if n.saturating_mul(min_size) > self.body.len() - self.pos {
            return Err(CdrError { offset: self.pos, field, reason: "count larger than the message" });
        }
        Ok(n)
    }

    /// A count of at most `max` elements (the bounds of [`crate::bounds`]), checked before anything
    /// is read or allocated for them.
    fn bounded_count(&mut self, field: &'static str, min_size: usize, max: usize, reason: &'static str) -> Result<usize, CdrError> {
        let at = self.pos;
        let n = self.count(field, min_size)?;
        if n > max {
            return Err(CdrError { offset: 4 + at.next_multiple_of(4), field, reason });
        }
        Ok(n)
    }

    /// A string of at most `max` bytes (NUL included) into `out` (its buffer reused). The count
    /// includes the NUL terminator, which is dropped; a zero count is an empty string (as
    /// `cdr_encoding` accepts).
    fn bounded_string_into(&mut self, field: &'static str, out: &mut String, max: usize, reason: &'static str) -> Result<(), CdrError> {
        let n = self.bounded_count(field, 1, max, reason)?;
        let bytes = &self.body[self.pos..self.pos + n];
        let bytes = bytes.split_last().map_or(bytes, |(_, s)| s);
        // A stream repeats its strings (frame, axis names): when unchanged, nothing to check or copy.
        if !same_bytes(out.as_bytes(), bytes) {
            let text = std::str::from_utf8(bytes).map_err(|_| CdrError { offset: 4 + self.pos, field, reason: "not UTF-8" })?;
            out.clear();
            out.push_str(text);
        }
        self.pos += n;
        Ok(())
    }

    /// The joint names of a state message into `out`, reusing its strings: at most [`MAX_JOINTS`]
    /// names of at most [`MAX_NAME_BYTES`].
    pub fn names_into(&mut self, field: &'static str, out: &mut Vec<String>) -> Result<(), CdrError> {
        let n = self.bounded_count(field, 4, MAX_JOINTS, "more than 256 joints (MAX_JOINTS)")?;
        out.truncate(n);
        for k in 0..n {
            if k == out.len() {
                out.push(String::new());
            }
            // A stream repeats its joint names: one that is the name already held is stepped over.
            if let Some(end) = self.repeated_string(out[k].as_bytes(), MAX_NAME_BYTES + 1) {
                self.pos = end;
                continue;
            }
            self.bounded_string_into(field, &mut out[k], MAX_NAME_BYTES + 1, "a joint name longer than 256 bytes (MAX_NAME_BYTES)")?;
        }
        Ok(())
    }

    /// Where the string at the cursor ends if it is `held` (its count, within `max`, and its bytes;
    /// the terminator is not read, as [`CdrReader::bounded_string_into`] drops it unread): what that
    /// reading would accept without a change, found in one comparison. None for anything else,
    /// which the full reading then takes (and refuses where it must).
    #[inline]
    fn repeated_string(&self, held: &[u8], max: usize) -> Option<usize> {
        let start = self.pos.next_multiple_of(4);
        let count: [u8; 4] = self.body.get(start..start + 4)?.try_into().ok()?;
        let count = u32_in(count, self.big_endian) as usize;
        let end = start + 4 + count;
        if count != held.len() + 1 || count > max || end > self.body.len() {
            return None;
        }
        same_bytes(&self.body[start + 4..end - 1], held).then_some(end)
    }

    /// The joint values of a state message into `out`, reusing its buffer: at most [`MAX_JOINTS`].
    pub fn f64s_into(&mut self, field: &'static str, out: &mut Vec<f64>) -> Result<(), CdrError> {
        let n = self.bounded_count(field, 8, MAX_JOINTS, "more than 256 values (MAX_JOINTS)")?;
        out.clear();
        if n == 0 {
            return Ok(());
        }
        let start = self.pos.next_multiple_of(8);
        let bytes = self
            .body
            .get(start..start + 8 * n)
            .ok_or(CdrError { offset: 4 + start, field, reason: "message ends inside the sequence" })?;
        // The byte order chosen once for the sequence, not per value.
        let values = bytes.chunks_exact(8).map(|b| -> [u8; 8] { b.try_into().expect("8 bytes") });
        if self.big_endian {
            out.extend(values.map(f64::from_be_bytes));
        } else {
            out.extend(values.map(f64::from_le_bytes));
        }
        self.pos = start + 8 * n;
        Ok(())
    }

    fn time(&mut self) -> Result<Time, CdrError> {
        Ok(Time { sec: self.i32("header.stamp.sec")?, nanosec: self.u32("header.stamp.nanosec")? })
    }

    fn header_into(&mut self, out: &mut Header) -> Result<(), CdrError> {
        out.stamp = self.time()?;
        self.bounded_string_into("header.frame_id", &mut out.frame_id, MAX_FRAME_ID_BYTES + 1, "longer than 1024 bytes (MAX_FRAME_ID_BYTES)")
    }

    fn xyz(&mut self, field: &'static str) -> Result<[f64; 3], CdrError> {
        Ok([self.f64(field)?, self.f64(field)?, self.f64(field)?])
    }

    /// The `N` bytes from the next multiple of 8 if the message holds them (the cursor moved past
    /// them), else None with the cursor unmoved: a run of fields laid out from an 8-byte boundary,
    /// read with one bounds check.
    #[inline]
    fn block8<const N: usize>(&mut self) -> Option<&'a [u8; N]> {
        let start = self.pos.next_multiple_of(8);
        let block = self.body.get(start..start.checked_add(N)?)?.try_into().ok()?;
        self.pos = start + N;
        Some(block)
    }
}

/// Little- or big-endian values at fixed offsets of a block read by [`CdrReader::block8`].
struct Fixed<'b, const N: usize> {
    bytes: &'b [u8; N],
    big_endian: bool,
}

impl<const N: usize> Fixed<'_, N> {
    #[inline]
    fn word<const W: usize>(&self, at: usize) -> [u8; W] {
        let mut w = [0; W];
        w.copy_from_slice(&self.bytes[at..at + W]);
        w
    }
    #[inline]
    fn f64(&self, at: usize) -> f64 {
        f64_in(self.word(at), self.big_endian)
    }
    #[inline]
    fn i64(&self, at: usize) -> i64 {
        i64_in(self.word(at), self.big_endian)
    }
    #[inline]
    fn u32(&self, at: usize) -> u32 {
        u32_in(self.word(at), self.big_endian)
    }
}

/// AxisState's fields after the acceleration sequence, from the 8-byte boundary where its tool tip
/// starts: tool_tip (0), tool_axis (24), programmed_feed (48), path_feed (56), program_line (64, u32),
/// 4 bytes of padding, block_number (72, i64), motion (80, u8). CDR aligns each to its size relative
/// to the body, so from an 8-byte boundary these offsets are the sequential reading's.
const AXIS_STATE_TAIL: usize = 81;

impl AxisState {
    /// Decode a CDR message (with its encapsulation header) into `self`, reusing its buffers. On
    /// error `self` holds a partial value.
    pub fn read_cdr(&mut self, data: &[u8]) -> Result<(), CdrError> {
        let mut r = CdrReader::new(data)?;
        r.header_into(&mut self.header)?;
        self.source = r.u8("source")?;
        r.names_into("name", &mut self.name)?;
        r.f64s_into("position", &mut self.position)?;
        r.f64s_into("velocity", &mut self.velocity)?;
        r.f64s_into("acceleration", &mut self.acceleration)?;
        // The fixed-size rest in one read; a message that ends inside it is read field by field,
        // which names the field it ends in.
        let big_endian = r.big_endian;
        if let Some(bytes) = r.block8::<AXIS_STATE_TAIL>() {
            let t = Fixed { bytes, big_endian };
            self.tool_tip = Point { x: t.f64(0), y: t.f64(8), z: t.f64(16) };
            self.tool_axis = Vector3 { x: t.f64(24), y: t.f64(32), z: t.f64(40) };
            self.programmed_feed = t.f64(48);
            self.path_feed = t.f64(56);
            self.program_line = t.u32(64);
            self.block_number = t.i64(72);
            self.motion = bytes[80];
            return Ok(());
        }
        let [x, y, z] = r.xyz("tool_tip")?;
        self.tool_tip = Point { x, y, z };
        let [x, y, z] = r.xyz("tool_axis")?;
        self.tool_axis = Vector3 { x, y, z };
        self.programmed_feed = r.f64("programmed_feed")?;
        self.path_feed = r.f64("path_feed")?;
        self.program_line = r.u32("program_line")?;
        self.block_number = r.i64("block_number")?;
        self.motion = r.u8("motion")?;
        Ok(())
    }
}

impl JointState {
    /// Decode a CDR message (with its encapsulation header) into `self`, reusing its buffers.
    pub fn read_cdr(&mut self, data: &[u8]) -> Result<(), CdrError> {
        let mut r = CdrReader::new(data)?;
        r.header_into(&mut self.header)?;
        r.names_into("name", &mut self.name)?;
        r.f64s_into("position", &mut self.position)?;
        r.f64s_into("velocity", &mut self.velocity)?;
        r.f64s_into("effort", &mut self.effort)
    }
}
