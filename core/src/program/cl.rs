//! Cutter-location data: one pose `x y z i j k [feed]` per line (mm, unit tool axis, mm/min),
//! separated by commas, spaces or tabs; an optional header line; `#` or `;` comment lines. Numbers
//! are decimals, also in exponent notation (`-6.0e-05`, as numpy and many exports write them).
//! Or APT CLDATA (`GOTO/x,y,z,i,j,k`, [`super::apt`]), known by its first statement.
//! Poses are tool tips in the workpiece frame, so tool-centre-point control is on throughout.

use super::apt::{is_apt_line, AptReader};
use super::lex::{excerpt, parse_number, Diags};
use super::{Block, Dialect, Feed, FeedMode, Motion, Orientation, Program, Targets};
use crate::units::MM;

/// Read CL data; `feed_mm_per_min` applies where a line has no feed column.
pub fn read_cl(text: &str, feed_mm_per_min: f64) -> Program {
    read_cl_with(text, feed_mm_per_min, Dialect::Cl.default_orientation())
}

/// Read CL data for a control that interpolates the tool orientation as `orientation` says.
pub fn read_cl_with(text: &str, feed_mm_per_min: f64, orientation: Orientation) -> Program {
    let setup = super::ReadOptions { cl_feed_mm_per_min: feed_mm_per_min, orientation: Some(orientation), ..Default::default() }.setup(Dialect::Cl);
    super::stream::read_whole(&mut ClReader::new(&setup), text, Dialect::Cl)
}

/// A CL field: an NC decimal, or a finite number in exponent notation (`1.5e-3`; not `inf`, `nan`
/// or an exponent that overflows).
pub(crate) fn parse_field(f: &str) -> Option<f64> {
    parse_number(f).or_else(|| {
        let exponent = f.bytes().any(|b| b == b'e' || b == b'E');
        let plain = f.bytes().all(|b| b.is_ascii_digit() || matches!(b, b'+' | b'-' | b'.' | b'e' | b'E'));
        if exponent && plain {
            f.parse::<f64>().ok().filter(|v| v.is_finite())
        } else {
            None
        }
    })
}

/// The fields of a line (separated by commas and white space) with their columns (1-based, in
/// characters). An ASCII line (a CAM export's) is split by its bytes, where a byte is a column.
fn split_fields(l: &str) -> impl Iterator<Item = (usize, &str)> {
    let ascii = l.is_ascii();
    let by_bytes = ascii.then(|| split_ascii_fields(l));
    let by_chars = (!ascii).then(|| split_char_fields(l));
    by_bytes.into_iter().flatten().chain(by_chars.into_iter().flatten())
}

/// [`split_fields`] of an ASCII line: the white space of `char::is_whitespace` among ASCII (tab,
/// line feed, vertical tab, form feed, carriage return, space) and commas separate.
fn split_ascii_fields(l: &str) -> impl Iterator<Item = (usize, &str)> {
    let bytes = l.as_bytes();
    let mut k = 0;
    std::iter::from_fn(move || {
        let sep = |b: u8| b == b',' || b == b' ' || (b'\t'..=b'\r').contains(&b);
        while k < bytes.len() && sep(bytes[k]) {
            k += 1;
        }
        if k == bytes.len() {
            return None;
        }
        let start = k;
        while k < bytes.len() && !sep(bytes[k]) {
            k += 1;
        }
        Some((start + 1, &l[start..k]))
    })
}

/// [`split_fields`] by characters, for a line that is not ASCII.
fn split_char_fields(l: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut start = None;
    l.char_indices().chain(std::iter::once((l.len(), ' '))).enumerate().filter_map(move |(col, (k, c))| {
        let sep = c == ',' || c.is_whitespace();
        match (sep, start) {
            (false, None) => {
                start = Some((k, col + 1));
                None
            }
            (true, Some((s, col))) => {
                start = None;
                Some((col, &l[s..k]))
            }
            _ => None,
        }
    })
}

/// A tool axis as written (i j k), made a unit vector: zero length is an error, a length off 1 by
/// over 1 % a warning (CAM writes unit vectors; a longer one is likely a wrong column).
pub(crate) fn unit_tool_axis(v: [f64; 3], line: usize, column: usize, diags: &mut Diags) -> Option<[f64; 3]> {
    let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if !(norm > 1e-9) {
        diags.error(line, column, "tool axis (i j k) has zero length: expected a direction");
        return None;
    }
    if (norm - 1.0).abs() > 1e-2 {
        diags.warning(line, column, format!("tool axis length {norm:.4} is not 1: normalised"));
    }
    Some(v.map(|c| c / norm))
}

/// The CL reader, fed one line at a time.
#[derive(Debug, Clone)]
pub(crate) struct ClReader {
    feed_mm_per_min: f64,
    orientation: Orientation,
    units: Option<super::LengthUnit>,
    angles: super::AngleUnit,
    seen_data: bool,
    /// APT CLDATA, known by the first line that is not blank or a comment.
    apt: Option<Box<AptReader>>,
}

impl ClReader {
    pub(crate) fn new(setup: &super::Setup) -> Self {
        ClReader { feed_mm_per_min: setup.cl_feed_mm_per_min, orientation: setup.orientation, units: setup.units, angles: setup.cl_angles, seen_data: false, apt: None }
    }
}

impl super::stream::LineReader for ClReader {
    fn line(&mut self, line: usize, l: &str, out: &mut Vec<Block>, diags: &mut Diags) {
        let (feed_mm_per_min, orientation) = (self.feed_mm_per_min, self.orientation);
        let l = l.trim_end_matches('\r');
        if let Some(apt) = &mut self.apt {
            return apt.line(line, l, out, diags);
        }
        let t = l.trim();
        if t.is_empty() || t.starts_with('#') || t.starts_with(';') {
            return;
        }
        if !self.seen_data && is_apt_line(t) {
            let mut apt = Box::new(AptReader::new(feed_mm_per_min, orientation, self.units, self.angles));
            apt.line(line, l, out, diags);
            self.apt = Some(apt);
            return;
        }
        // Fields with their columns, the first eight kept: a pose has six or seven, and a longer
        // line is counted, then refused.
        let mut fields = [(0usize, ""); 8];
        let mut split = split_fields(l);
        let mut count = 0;
        for (slot, f) in fields.iter_mut().zip(split.by_ref()) {
            *slot = f;
            count += 1;
        }
        count += split.count();
        let fields = &fields[..count.min(8)];
        let mut v = [0.0f64; 8];
        let mut numbers = 0;
        for (x, (_, f)) in v.iter_mut().zip(fields) {
            if let Some(n) = parse_field(f) {
                *x = n;
                numbers += 1;
            }
        }
        if !self.seen_data && numbers == 0 && split_fields(l).all(|(_, f)| parse_field(f).is_none()) {
            // A header line such as `x,y,z,i,j,k`: its names must be these columns' (a header that
            // names others, `x,y,z,a,c,f`, says the numbers are not these).
            let names: Vec<(usize, String)> = split_fields(l).map(|(c, f)| (c, f.to_ascii_lowercase())).collect();
            let want: [&[&str]; 7] = [&["x"], &["y"], &["z"], &["i", "nx", "u", "tx"], &["j", "ny", "v", "ty"], &["k", "nz", "w", "tz"], &["f", "feed"]];
            let bad = names.iter().enumerate().find(|(k, (_, n))| want.get(*k).is_none_or(|w| !w.contains(&n.as_str())));
            if let Some((k, (col, n))) = bad.filter(|_| names.len() >= 2) {
                let what = if k >= 7 { "more columns than x y z i j k feed".to_string() } else { format!("column {} is {}", k + 1, want[k].join(" or ")) };
                diags.error(line, *col, format!("header '{}' names '{n}' where {what}: CL data here are x y z i j k [feed] (commas, spaces or tabs)", excerpt(t)));
                self.seen_data = true;
            }
            return;
        }
        self.seen_data = true;
        if !(6..=7).contains(&count) {
            diags.error(line, 1, format!("expected 6 or 7 fields (x y z i j k [feed]), found {count}"));
            return;
        }
        if numbers < count {
            for (col, f) in fields {
                if parse_field(f).is_none() {
                    diags.error(line, *col, format!("expected a number, found '{}'", excerpt(f)));
                }
            }
            return;
        }
        let Some(axis) = unit_tool_axis([v[3], v[4], v[5]], line, fields[3].0, diags) else { return };
        // `--units`: the numbers' length unit (millimetres unless said), the feed's per minute.
        let unit = self.units.map_or(MM, |u| u.metres());
        let feed = if count == 7 {
            if !(v[6] > 0.0) {
                diags.error(line, fields[6].0, "expected a positive feed (mm/min)");
                return;
            }
            v[6] * unit / MM
        } else {
            feed_mm_per_min
        };
        out.push(Block {
            line,
            column: fields[0].0,
            number: None,
            motion: Motion::Linear,
            targets: Targets {
                x: Some(v[0] * unit),
                y: Some(v[1] * unit),
                z: Some(v[2] * unit),
                tool_axis: Some(axis),
                ..Targets::default()
            },
            arc: None,
            feed: Some(Feed { value_per_min: feed, rotary_per_min: feed, mode: FeedMode::PerMinute }),
            tcp: true,
            datum: [0.0; 3],
            orientation,
            events: Vec::new(),
            dwell_s: None,
            tolerance: Default::default(),
            offset_assumed: false,
            exact: crate::program::Exact::Blend,
        });
    }

    fn finish(&mut self, _blocks: Option<&mut Vec<Block>>, out: &mut Vec<Block>, diags: &mut Diags) {
        if let Some(apt) = &mut self.apt {
            apt.finish(out, diags);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The byte splitter of ASCII lines finds the fields and columns the character splitter finds,
    /// with every ASCII separator and field character.
    #[test]
    fn ascii_lines_split_as_by_characters() {
        let alphabet = [" ", ",", "\t", "\x0b", "\x0c", "\r", "\n", "1", "-", ".", "e", "x", "#", "\x1c", "\x7f"];
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..20_000 {
            let mut l = String::new();
            for _ in 0..(seed % 13) {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                l.push_str(alphabet[(seed % alphabet.len() as u64) as usize]);
            }
            let a: Vec<_> = split_ascii_fields(&l).collect();
            let c: Vec<_> = split_char_fields(&l).collect();
            assert_eq!(a, c, "{l:?}");
        }
    }

    #[test]
    fn exponent_notation_is_read_and_non_finite_refused() {
        let p = read_cl("x,y,z,i,j,k\n1.5e1 -2E-1 0 -6.0e-05 0 1 1.2e3\n", 1000.0);
        assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
        assert_eq!(p.blocks.len(), 1);
        let t = &p.blocks[0].targets;
        assert!((t.x.unwrap() - 15.0 * MM).abs() < 1e-15 && (t.y.unwrap() + 0.2 * MM).abs() < 1e-15);
        for bad in ["1e400", "inf", "nan", "1e", "1e-3x"] {
            let p = read_cl(&format!("0 0 0 0 0 1\n{bad} 0 0 0 0 1\n"), 1000.0);
            assert_eq!(p.diagnostics.len(), 1, "{bad}: {:?}", p.diagnostics);
            assert_eq!((p.diagnostics[0].line, p.diagnostics[0].column), (2, 1), "{bad}");
        }
    }
}
