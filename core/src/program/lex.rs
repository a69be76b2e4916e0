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
    // The digits before the point, then after it, into one integer (a digit is a byte 0-9 from '0').
    let n = body.len();
    let mut mantissa: u64 = 0;
    let mut i = digits_into(body, 0, &mut mantissa);
    let whole = i;
    let mut after = i;
    if i < n && body[i] == b'.' {
        after = i + 1;
        i = digits_into(body, after, &mut mantissa);
    }
    let fraction = i - after;
    let digits = whole + fraction;
    if i != n || digits == 0 {
        return None;
    }
    // Significant digits: those from the first that is not 0 (leading zeros add nothing to the integer).
    let significant = if digits <= 15 { digits } else { digits - body.iter().take_while(|&&c| c == b'0' || c == b'.').filter(|&&c| c == b'0').count() };
    const POW10: [f64; 23] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22];
    if significant <= 15 && fraction < POW10.len() {
        let v = mantissa as f64 / POW10[fraction];
        return Some(if negative { -v } else { v });
    }
    s.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// The digits of `body` from `i` on appended to `mantissa` (wrapping: only the first 19 can
/// count); where they end.
#[inline(always)]
fn digits_into(body: &[u8], mut i: usize, mantissa: &mut u64) -> usize {
    while i < body.len() {
        let d = body[i].wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        *mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(d));
        i += 1;
    }
    i
}

/// Bytes that end a word of a line: ASCII whitespace (`u8::is_ascii_whitespace`) and `;`.
const WORD_ENDS: [bool; 256] = {
    let mut t = [false; 256];
    let mut c = 0;
    while c < 256 {
        t[c] = (c as u8).is_ascii_whitespace() || c as u8 == b';';
        c += 1;
    }
    t
};

/// Where the word of `b` that runs from `from` ends: the first ASCII blank or `;` at or after it, or
/// the end. Eight bytes at a time (a Klartext `LN` block is 117 bytes of a dozen words): a byte
/// below 0x21 (every blank among them) or a `;` is flagged in its high bit, the lowest flag exact (a
/// borrow can only flag bytes above a true one), then checked against the table, as a control byte
/// that is not a blank belongs to the word.
pub(crate) fn word_end(b: &[u8], from: usize) -> usize {
    const ONES: u64 = 0x0101_0101_0101_0101;
    const HIGH: u64 = 0x8080_8080_8080_8080;
    let mut i = from;
    // A word that ends where it starts (the 840D's reader asks after each number) costs one look.
    if b.get(i).is_none_or(|&c| WORD_ENDS[usize::from(c)]) {
        return i.min(b.len());
    }
    while let Some(chunk) = b.get(i..i + 8) {
        let x = u64::from_le_bytes(chunk.try_into().unwrap_or_default());
        let below = x.wrapping_sub(ONES * 0x21) & !x & HIGH;
        let y = x ^ (ONES * u64::from(b';'));
        let semicolon = y.wrapping_sub(ONES) & !y & HIGH;
        let flags = below | semicolon;
        if flags == 0 {
            i += 8;
            continue;
        }
        let k = i + (flags.trailing_zeros() / 8) as usize;
        if WORD_ENDS[usize::from(b[k])] {
            return k;
        }
        i = k + 1;
    }
    while i < b.len() && !WORD_ENDS[usize::from(b[i])] {
        i += 1;
    }
    i
}

/// A fixed sequence of pseudo-random numbers (xorshift64) for tests that draw many inputs.
#[cfg(test)]
pub(crate) fn xorshift(mut state: u64) -> impl FnMut() -> u64 {
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    }
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
    memchr::memchr_iter(b'\n', text.as_bytes()).count() + 1
}

/// Length of the longest prefix of `s` a number could be: a sign, then digits and points.
pub fn number_prefix_len(s: &str) -> usize {
    // By bytes: every byte it takes is ASCII, so where it stops is a character's start.
    let b = s.as_bytes();
    let sign = usize::from(matches!(b.first(), Some(b'+' | b'-')));
    sign + b[sign..].iter().take_while(|&&c| c.is_ascii_digit() || c == b'.').count()
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

    /// A number's prefix: a sign only first, then digits and points, ending on a character's start.
    #[test]
    fn number_prefixes() {
        for (text, len) in [("+1.5X", 4), ("-", 1), ("1+2", 1), ("--1", 1), (".5.5;", 4), ("\u{e9}1", 0), ("12\u{e9}", 2), ("", 0), ("X1", 0)] {
            assert_eq!(number_prefix_len(text), len, "{text:?}");
        }
    }

    /// Where a word ends, eight bytes at a time, against the byte-by-byte rule (the first ASCII
    /// blank or `;`): 200,000 lines of up to 40 bytes drawn from blanks, `;`, control bytes (0x0B
    /// is no blank), letters, digits and UTF-8 bytes, from every start.
    #[test]
    fn word_ends_match_the_byte_rule() {
        let alphabet: &[u8] = b" \t\n\r\x0b\x0c\x01\x1f ;;X+.5qQ\x80\xc3\xa9\xff!\"";
        let mut next = xorshift(0x2545_F491_4F6C_DD1D);
        for _ in 0..200_000 {
            let len = (next() % 41) as usize;
            let line: Vec<u8> = (0..len).map(|_| if next() % 3 == 0 { b'A' + (next() % 26) as u8 } else { alphabet[(next() % alphabet.len() as u64) as usize] }).collect();
            for from in 0..=len {
                let by_byte = (from..len).find(|&k| line[k].is_ascii_whitespace() || line[k] == b';').unwrap_or(len);
                assert_eq!(word_end(&line, from), by_byte, "{line:?} from {from}");
            }
        }
    }

    /// Texts of up to 24 characters of a number's alphabet (200,000 drawn by a fixed generator, long
    /// runs of zeros and long numbers among them): a number exactly where the grammar says (a sign,
    /// digits, at most one point, a digit at least), and then the standard library's correctly
    /// rounded value.
    #[test]
    fn numbers_match_the_grammar_and_the_standard_parse() {
        let alphabet = b"0000000123456789..+-x";
        let mut next = xorshift(0x9E37_79B9_7F4A_7C15);
        for _ in 0..200_000 {
            // Half of them long numbers (14 to 24 digits, a point among them): where a fast path's
            // rounding would first go wrong.
            let text: String = if next() % 2 == 0 {
                let len = 14 + (next() % 11) as usize;
                let point = (next() % (len as u64 + 1)) as usize;
                (0..len).map(|k| if k == point { '.' } else { (b'0' + (next() % 10) as u8) as char }).collect()
            } else {
                let len = (next() % 25) as usize;
                (0..len).map(|k| if k == 0 && next() % 3 == 0 { '-' } else { alphabet[(next() % alphabet.len() as u64) as usize] as char }).collect()
            };
            let body = text.strip_prefix(['+', '-']).unwrap_or(&text);
            let grammar = body.bytes().all(|c| c.is_ascii_digit() || c == b'.') && body.bytes().filter(|&c| c == b'.').count() <= 1 && body.bytes().any(|c| c.is_ascii_digit());
            let expected = if grammar { text.parse::<f64>().ok().filter(|v| v.is_finite()) } else { None };
            assert_eq!(parse_number(&text).map(f64::to_bits), expected.map(f64::to_bits), "{text:?}");
        }
    }
}
