//! Pieces shared by the readers: strict number syntax and diagnostics collection.

use super::{Diagnostic, Severity};

/// A decimal number as NC programs write it: `+14.825`, `-8`, `.5`, `3.`. Nothing else is a number
/// (no exponents, no embedded spaces, no `C.L..`), so a damaged value is never read as one.
/// Up to 15 significant digits take Clinger's fast path (an exact integer divided by an exact power
/// of ten: one correctly rounded operation, the same value `str::parse` gives); up to 19 digits (a
/// float printed to round-trip has 17) Eisel-Lemire ([`eisel_lemire`]); longer ones go
/// to `str::parse`.
pub fn parse_number(s: &str) -> Option<f64> {
    parse_number_prefix(s.as_bytes()).filter(|&(_, len)| len == s.len()).map(|(v, _)| v)
}

/// The number `b` starts with, as [`parse_number`] reads one, and its length in bytes: a sign,
/// digits, a point and digits, stopping at the first other byte (`12.5X` gives 12.5 and 4). One
/// pass for a reader that finds a word's end and its value together.
pub fn parse_number_prefix(b: &[u8]) -> Option<(f64, usize)> {
    let (negative, sign) = match b.first() {
        Some(b'-') => (true, 1),
        Some(b'+') => (false, 1),
        _ => (false, 0),
    };
    let body = &b[sign..];
    // The digits before the point, then after it, into one integer (a digit is a byte 0-9 from '0').
    let mut mantissa: u64 = 0;
    let mut i = digits_into(body, 0, &mut mantissa);
    let whole = i;
    let mut after = i;
    if body.get(i) == Some(&b'.') {
        after = i + 1;
        i = digits_into(body, after, &mut mantissa);
    }
    let fraction = i - after;
    let digits = whole + fraction;
    if digits == 0 {
        return None;
    }
    let len = sign + i;
    // Significant digits: those from the first that is not 0 (leading zeros add nothing to the integer).
    let significant = if digits <= 15 { digits } else { digits - body[..i].iter().take_while(|&&c| c == b'0' || c == b'.').filter(|&&c| c == b'0').count() };
    const POW10: [f64; 23] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22];
    let v = if significant <= 15 && fraction < POW10.len() {
        mantissa as f64 / POW10[fraction]
    } else if digits <= 19 {
        // At most 19 digits: the integer did not wrap (10^19 < 2^64).
        eisel_lemire(mantissa, fraction)
    } else {
        // The bytes taken are ASCII: a str.
        return std::str::from_utf8(&b[..len]).ok()?.parse::<f64>().ok().filter(|v| v.is_finite()).map(|v| (v, len));
    };
    Some((if negative { -v } else { v }, len))
}

/// `w / 10^f` correctly rounded (to nearest, ties to even), for `0 < w < 2^64` and `f <= 19`, as
/// `str::parse` rounds it: Eisel and Lemire's algorithm (D. Lemire, "Number Parsing at a Gigabyte
/// per Second", 2021, §5 and §6), `w` times a 128-bit 5^-f and the exponent by `2^-f`. For these
/// exponents the product always decides the rounding (§9.1: it fails only outside -27..=55) and
/// the mantissa is exact, so no fallback is needed; the table's entries are the paper's (5^-q
/// rounded up to 128 bits, 5^0 exact).
fn eisel_lemire(w: u64, f: usize) -> f64 {
    const POW5: [(u64, u64); 20] = [
        (0xec1e4a7db69561a5, 0x2b31e9e3d06c32e6), // 5^-19
        (0x9392ee8e921d5d07, 0x3aff322e62439fd0),
        (0xb877aa3236a4b449, 0x09befeb9fad487c3),
        (0xe69594bec44de15b, 0x4c2ebe687989a9b4),
        (0x901d7cf73ab0acd9, 0x0f9d37014bf60a11), // 5^-15
        (0xb424dc35095cd80f, 0x538484c19ef38c95),
        (0xe12e13424bb40e13, 0x2865a5f206b06fba),
        (0x8cbccc096f5088cb, 0xf93f87b7442e45d4),
        (0xafebff0bcb24aafe, 0xf78f69a51539d749),
        (0xdbe6fecebdedd5be, 0xb573440e5a884d1c), // 5^-10
        (0x89705f4136b4a597, 0x31680a88f8953031),
        (0xabcc77118461cefc, 0xfdc20d2b36ba7c3e),
        (0xd6bf94d5e57a42bc, 0x3d32907604691b4d),
        (0x8637bd05af6c69b5, 0xa63f9a49c2c1b110),
        (0xa7c5ac471b478423, 0x0fcf80dc33721d54), // 5^-5
        (0xd1b71758e219652b, 0xd3c36113404ea4a9),
        (0x83126e978d4fdf3b, 0x645a1cac083126ea),
        (0xa3d70a3d70a3d70a, 0x3d70a3d70a3d70a4),
        (0xcccccccccccccccc, 0xcccccccccccccccd),
        (0x8000000000000000, 0x0000000000000000), // 5^0
    ];
    let mul = |a: u64, b: u64| {
        let r = u128::from(a) * u128::from(b);
        (r as u64, (r >> 64) as u64)
    };
    let q = -(f as i32);
    let lz = w.leading_zeros();
    let w = w << lz;
    let (hi5, lo5) = POW5[19 - f];
    // The product's top 55 bits (52 stored, the hidden one, one to round by, one for a leading
    // zero): a second product only where the first leaves them all ones below.
    const MASK: u64 = u64::MAX >> 55;
    let (mut lo, mut hi) = mul(w, hi5);
    if hi & MASK == MASK {
        let (_, second) = mul(w, lo5);
        lo = lo.wrapping_add(second);
        hi += u64::from(second > lo);
    }
    let upper = (hi >> 63) as i32;
    let mut mantissa = hi >> (upper + 9);
    // The binary exponent, biased: floor(log2(10^q)) + 63 by the paper's fixed-point log.
    let mut exponent = ((q * (152_170 + 65_536)) >> 16) + 63 + upper - lz as i32 + 1022 + 1;
    // Exactly halfway (5^-q fits 64 bits, q >= -4): ties to even.
    if lo <= 1 && q >= -4 && mantissa & 3 == 1 && mantissa << (upper + 9) == hi {
        mantissa &= !1;
    }
    mantissa += mantissa & 1;
    mantissa >>= 1;
    if mantissa >= 2 << 52 {
        mantissa = 1 << 52;
        exponent += 1;
    }
    // 10^-19 <= value < 2^64: a normal number, the exponent in 1..0x7FF.
    f64::from_bits(mantissa & !(1 << 52) | (exponent as u64) << 52)
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

    /// 16 to 19 digits, read by Eisel-Lemire, give what `str::parse` gives: every f64 printed to
    /// round-trip (17 significant digits, as a converter writes them) in 100,000 drawn, with 16-19
    /// digit truncations of them, exact halfway cases between two doubles (an odd multiple of half a
    /// unit in the last place, as an integer and with `.0`/`.00`: ties to even), and 200,000 integers
    /// of 16-19 digits with the point anywhere.
    #[test]
    fn long_numbers_are_correctly_rounded() {
        let mut next = xorshift(0xD1B5_4A32_D192_ED03);
        let check = |text: &str| assert_eq!(parse_number(text).map(f64::to_bits), text.parse::<f64>().ok().map(f64::to_bits), "{text:?}");
        for _ in 0..100_000 {
            // A double of any magnitude a program writes: 1e-6 to 1e12.
            let v = f64::from_bits(next() >> 12 | 0x3FF0_0000_0000_0000) * 10f64.powi((next() % 19) as i32 - 6);
            let text = format!("{v}");
            check(&text);
            check(&format!("-{text}"));
            // Its digits cut to 16-19 with the point kept.
            let digits: String = format!("{v:.20}").chars().take(17 + (next() % 4) as usize).collect();
            check(&digits);
        }
        for _ in 0..100_000 {
            // (2m + 1) * 2^(k - 1) with 2^52 <= m < 2^53: halfway between two doubles whose spacing is 2^k.
            let m = (1u64 << 52) | next() >> 12;
            let k = 1 + (next() % 11) as u32;
            let tie = u128::from(2 * m + 1) << (k - 1);
            if tie < 1u128 << 64 {
                check(&tie.to_string());
                check(&format!("{tie}.0"));
                check(&format!("{tie}.00"));
            }
        }
        for _ in 0..200_000 {
            // Any 16-19 digit integer with its point anywhere (0 to 19 digits after it).
            let w = 10u64.pow(15) + next() % (10u64.pow(19) - 10u64.pow(15));
            let digits = w.to_string();
            let point = digits.len() - (next() % (digits.len() as u64 + 1)) as usize;
            check(&format!("{}.{}", &digits[..point], &digits[point..]));
        }
        for text in ["9007199254740993", "9007199254740993.0", "18446744073709551615", "1844674407370955161.5", "0.1000000000000000055511151231257827", "121.28050702225332", "-1.5708076944948968", "0.0000000000000000001"] {
            check(text);
        }
    }

    /// A number's prefix: a sign only first, then digits and points, ending on a character's start.
    #[test]
    fn number_prefixes() {
        for (text, len) in [("+1.5X", 4), ("-", 1), ("1+2", 1), ("--1", 1), (".5.5;", 4), ("\u{e9}1", 0), ("12\u{e9}", 2), ("", 0), ("X1", 0)] {
            assert_eq!(number_prefix_len(text), len, "{text:?}");
        }
    }

    /// A number read from a text's start: the longest prefix the grammar allows (a sign, digits, at
    /// most one point, a digit at least), and the standard library's value of it, for 200,000 texts
    /// drawn from a number's alphabet and letters (what follows a number on a line).
    #[test]
    fn number_prefixes_match_the_grammar_and_the_standard_parse() {
        let alphabet = b"000123456789..+-X; ";
        let mut next = xorshift(0x6A09_E667_F3BC_C908);
        for _ in 0..200_000 {
            let len = (next() % 24) as usize;
            let text: String = (0..len).map(|_| alphabet[(next() % alphabet.len() as u64) as usize] as char).collect();
            let b = text.as_bytes();
            let sign = usize::from(matches!(b.first(), Some(b'+' | b'-')));
            let whole = b[sign..].iter().take_while(|c| c.is_ascii_digit()).count();
            let mut end = sign + whole;
            if b.get(end) == Some(&b'.') {
                end += 1 + b[end + 1..].iter().take_while(|c| c.is_ascii_digit()).count();
            }
            let expected = (b[sign..end].iter().any(u8::is_ascii_digit)).then(|| (text[..end].parse::<f64>().unwrap().to_bits(), end));
            assert_eq!(parse_number_prefix(b).map(|(v, n)| (v.to_bits(), n)), expected, "{text:?}");
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
