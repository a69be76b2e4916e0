//! Pieces shared by the readers: strict number syntax and diagnostics collection.

use super::{Diagnostic, Severity};

/// A decimal number as NC programs write it: `+14.825`, `-8`, `.5`, `3.`. Nothing else is a number
/// (no exponents, no embedded spaces, no `C.L..`), so a damaged value is never read as one.
/// Up to 15 significant digits take Clinger's fast path (an exact integer divided by an exact power
/// of ten: one correctly rounded operation, the same value `str::parse` gives); longer ones go to it.
pub fn parse_number(s: &str) -> Option<f64> {
    let bytes = s.as_bytes();
    let (negative, body) = match bytes.first() {
        Some(b'-') => (true, &bytes[1..]),
        Some(b'+') => (false, &bytes[1..]),
        _ => (false, bytes),
    };
    let mut mantissa: u64 = 0;
    let (mut digits, mut significant, mut fraction, mut dot) = (0u32, 0u32, 0u32, false);
    for &b in body {
        match b {
            b'0'..=b'9' => {
                digits += 1;
                if significant > 0 || b != b'0' {
                    significant += 1;
                }
                mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(b - b'0'));
                fraction += u32::from(dot);
            }
            b'.' if !dot => dot = true,
            _ => return None,
        }
    }
    if digits == 0 {
        return None;
    }
    const POW10: [f64; 23] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22];
    if significant <= 15 && (fraction as usize) < POW10.len() {
        let v = mantissa as f64 / POW10[fraction as usize];
        return Some(if negative { -v } else { v });
    }
    s.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// `s` in capitals, borrowed when it already is (the readers' addresses and keywords: no
/// allocation for the upper case most programs write).
pub(crate) fn upper(s: &str) -> std::borrow::Cow<'_, str> {
    if s.bytes().any(|c| c.is_ascii_lowercase()) {
        std::borrow::Cow::Owned(s.to_ascii_uppercase())
    } else {
        std::borrow::Cow::Borrowed(s)
    }
}

/// How many lines `text` has: the readers reserve a block per line, so that a million-block
/// program is not copied as its block list grows.
pub fn line_count(text: &str) -> usize {
    text.bytes().filter(|&b| b == b'\n').count() + 1
}

/// Length of the longest prefix of `s` made of number characters (`+-.0-9`).
pub fn number_prefix_len(s: &str) -> usize {
    s.char_indices()
        .find(|&(i, c)| !(c.is_ascii_digit() || c == '.' || ((c == '+' || c == '-') && i == 0)))
        .map(|(i, _)| i)
        .unwrap_or(s.len())
}

/// Diagnostics being collected for one program.
#[derive(Debug, Clone, Default)]
pub struct Diags(pub Vec<Diagnostic>);

impl Diags {
    /// How many of the diagnostics so far are errors (a reader compares the count before and after a
    /// block to know whether the block is damaged).
    pub fn errors(&self) -> usize {
        self.0.iter().filter(|d| d.severity == Severity::Error).count()
    }
    pub fn error(&mut self, line: usize, column: usize, message: impl Into<String>) {
        self.0.push(Diagnostic { line, column, severity: Severity::Error, message: message.into() });
    }
    pub fn warning(&mut self, line: usize, column: usize, message: impl Into<String>) {
        self.0.push(Diagnostic { line, column, severity: Severity::Warning, message: message.into() });
    }
}

/// 1-based columns (characters) of byte offsets in one line: a byte a column when the line is ASCII.
pub struct Columns<'a> {
    line: &'a str,
    ascii: bool,
}

impl<'a> Columns<'a> {
    pub fn new(line: &'a str) -> Self {
        Columns { line, ascii: line.is_ascii() }
    }
    pub fn col(&self, byte: usize) -> usize {
        if self.ascii {
            byte + 1
        } else {
            self.line[..byte.min(self.line.len())].chars().count() + 1
        }
    }
}

/// Shorten a damaged piece of text for a message.
pub fn excerpt(s: &str) -> String {
    let mut out: String = s.chars().take(24).collect();
    if s.chars().count() > 24 {
        out.push('…');
    }
    out
}


/// Where a block's words start: past blanks and a block skip `/`, which stands at the block's start,
/// before its number (FANUC "optional block skip"; SINUMERIK 802D Programming 6FC5698-2AA00-1AP4
/// §8.1.4, `/N... word1 ...`), and whether the block had one.
pub(crate) fn past_skip(b: &[u8]) -> (usize, bool) {
    let blank = |from: usize| from + b[from.min(b.len())..].iter().take_while(|c| c.is_ascii_whitespace()).count();
    let i = blank(0);
    if b.get(i) == Some(&b'/') { (blank(i + 1), true) } else { (i, false) }
}

/// The block number (`N100`, at most `max_digits` digits) a line starts with, past a block skip `/`:
/// what a jump to a block number looks for.
pub(crate) fn block_number(b: &[u8], max_digits: usize) -> Option<u64> {
    let (i, _) = past_skip(b);
    if !b.get(i).is_some_and(|c| c.eq_ignore_ascii_case(&b'N')) {
        return None;
    }
    let digits = b[i + 1..].iter().take_while(|c| c.is_ascii_digit()).count();
    if digits == 0 || digits > max_digits {
        return None;
    }
    std::str::from_utf8(&b[i + 1..i + 1 + digits]).ok()?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn numbers() {
        assert_eq!(parse_number("+14.825"), Some(14.825));
        assert_eq!(parse_number("-8"), Some(-8.0));
        assert_eq!(parse_number(".5"), Some(0.5));
        assert_eq!(parse_number("3."), Some(3.0));
        for bad in [".L..", "", "+", ".", "1.2.3", "1e5", "23 162", "nan", "inf", "+-1", "1-"] {
            assert_eq!(parse_number(bad), None, "{bad}");
        }
        // The fast path gives what the standard library's correctly rounded parse gives.
        for good in ["0.1", "-0.3", "+14.825", "123456789012345", "0.000000000000001", "1.0000000000000002", "99999999999999999999.5", "-0.0", "7.", "00000000000000000000012.5"] {
            assert_eq!(parse_number(good).map(f64::to_bits), good.parse::<f64>().ok().map(f64::to_bits), "{good}");
        }
    }
}
