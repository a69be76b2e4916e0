//! Fanuc custom macro B's flow statements and calls as a line writes them (FANUC B-64484EN,
//! "Custom macro" and "Subprogram"): which statement a line holds, its condition, its label, the
//! words of a call. The runner ([`super::MacroRunner`]) does what they say.

use super::super::interp::{Dimension, Word};
use super::super::lex::excerpt;
use super::super::params::skip_blanks;
use super::MacroRunner;

/// A line's flow statement.
pub(super) enum Stmt {
    If { cond: usize, then: Then },
    Goto(usize),
    While { cond: Option<usize>, m: u8 },
    End(u8),
    Call(Vec<Word<'static>>),
}

pub(super) enum Then {
    Goto(usize),
    Set(usize),
}

/// Where a line's text starts: past blanks, a block delete `/` and its `N` number.
pub(super) fn body_start(chars: &[char]) -> usize {
    let mut i = skip_blanks(chars, 0);
    if chars.get(i) == Some(&'/') {
        i = skip_blanks(chars, i + 1);
    }
    if chars.get(i).is_some_and(|c| c.eq_ignore_ascii_case(&'N')) && chars.get(i + 1).is_some_and(|c| c.is_ascii_digit()) {
        i += 1;
        while chars.get(i).is_some_and(|c| c.is_ascii_digit()) {
            i += 1;
        }
    }
    skip_blanks(chars, i)
}

/// The program number an `O` (or `:`) line starts, if it is one.
pub(super) fn program_number(bytes: &[u8]) -> Option<u64> {
    let i = bytes.iter().position(|b| !b.is_ascii_whitespace())?;
    if !(bytes[i].eq_ignore_ascii_case(&b'O') || bytes[i] == b':') {
        return None;
    }
    let digits = bytes[i + 1..].iter().take_while(|b| b.is_ascii_digit()).count();
    if digits == 0 || digits > 9 {
        return None;
    }
    std::str::from_utf8(&bytes[i + 1..i + 1 + digits]).ok()?.parse().ok()
}

/// Whether a line may hold a flow statement or a call (`IF`, `GOTO`, `WHILE`, `DO`, `END`, `M9x`,
/// `M0..`, `G6x`): most lines are moves, passed on unparsed after a look at each byte.
pub(super) fn maybe_flow(text: &str) -> bool {
    /// The bytes that may begin one of them (a table: one look per byte of a move's line).
    const STARTS: [bool; 256] = {
        let mut t = [false; 256];
        let mut c = 0;
        while c < 256 {
            t[c] = matches!(c as u8 | 0x20, b'i' | b'g' | b'w' | b'd' | b'e' | b'm');
            c += 1;
        }
        t
    };
    let b = text.as_bytes();
    let Some(last) = b.len().checked_sub(1) else { return false };
    let mut from = 0;
    while let Some(k) = b[from..last].iter().position(|&c| STARTS[usize::from(c)]) {
        let i = from + k;
        // The letter's next character, past blanks (`M 98`).
        let next = b[i + 1..].iter().find(|c| **c != b' ' && **c != b'\t').map_or(0, u8::to_ascii_uppercase);
        let flow = match b[i] | 0x20 {
            b'i' => next == b'F',
            b'g' => next == b'O' || next == b'6',
            b'w' => next == b'H',
            b'd' => next == b'O',
            b'e' => next == b'N',
            b'm' => next == b'9' || next == b'0',
            _ => false,
        };
        if flow {
            return true;
        }
        from = i + 1;
    }
    false
}

/// Whether `chars[i..]` starts with the keyword `kw` (any case).
pub(super) fn keyword(chars: &[char], i: usize, kw: &str) -> bool {
    kw.chars().enumerate().all(|(k, c)| chars.get(i + k).is_some_and(|x| x.eq_ignore_ascii_case(&c)))
}

/// The one-digit loop number at `chars[i..]` (after blanks), 1 to 3, and the index after it.
pub(super) fn loop_number(chars: &[char], i: usize) -> Result<(u8, usize), usize> {
    let i = skip_blanks(chars, i);
    match chars.get(i).and_then(|c| c.to_digit(10)) {
        Some(m @ 1..=3) if !chars.get(i + 1).is_some_and(|c| c.is_ascii_digit()) => Ok((m as u8, i + 1)),
        _ => Err(i),
    }
}

/// Whether the rest of a line from `i` is blank or comments.
pub(super) fn rest_is_empty(chars: &[char], i: usize) -> bool {
    let mut i = skip_blanks(chars, i);
    loop {
        match chars.get(i) {
            None | Some(';') => return true,
            Some('(') => match chars[i..].iter().position(|&c| c == ')') {
                Some(p) => i = skip_blanks(chars, i + p + 1),
                None => return false,
            },
            _ => return false,
        }
    }
}

impl MacroRunner {
    /// The flow statement of a line (`None`: a plain line), or a defect (column, message).
    pub(super) fn statement(&self, chars: &[char]) -> Result<Option<Stmt>, (usize, String)> {
        let i = body_start(chars);
        if keyword(chars, i, "IF") {
            let (c, end) = self.condition_at(chars, i + 2, "IF")?;
            let j = skip_blanks(chars, end);
            return if keyword(chars, j, "GOTO") {
                Ok(Some(Stmt::If { cond: c, then: Then::Goto(j + 4) }))
            } else if keyword(chars, j, "THEN") {
                Ok(Some(Stmt::If { cond: c, then: Then::Set(skip_blanks(chars, j + 4)) }))
            } else {
                Err((j + 1, "IF [..]: expected GOTO n or THEN #i = ...".into()))
            };
        }
        if keyword(chars, i, "GOTO") {
            return Ok(Some(Stmt::Goto(i + 4)));
        }
        if keyword(chars, i, "WHILE") {
            let (c, end) = self.condition_at(chars, i + 5, "WHILE")?;
            let j = skip_blanks(chars, end);
            if !keyword(chars, j, "DO") {
                return Err((j + 1, "WHILE [..]: expected DO1, DO2 or DO3".into()));
            }
            let (m, k) = loop_number(chars, j + 2).map_err(|k| (k + 1, "WHILE [..] DO: expected the loop's number 1, 2 or 3".into()))?;
            if !rest_is_empty(chars, k) {
                return Err((k + 1, format!("unexpected '{}' after DO{m}", excerpt(&chars[k..].iter().collect::<String>()))));
            }
            return Ok(Some(Stmt::While { cond: Some(c), m }));
        }
        if keyword(chars, i, "DO") {
            if let Ok((m, k)) = loop_number(chars, i + 2) {
                if rest_is_empty(chars, k) {
                    return Ok(Some(Stmt::While { cond: None, m }));
                }
            }
        }
        if keyword(chars, i, "END") {
            if let Ok((m, k)) = loop_number(chars, i + 3) {
                if rest_is_empty(chars, k) {
                    return Ok(Some(Stmt::End(m)));
                }
            }
        }
        self.call_words(chars, i)
    }

    /// The `[condition]` after a keyword that ends at `from`: where it starts and ends (its value
    /// is read where it runs).
    pub(super) fn condition_at(&self, chars: &[char], from: usize, what: &str) -> Result<(usize, usize), (usize, String)> {
        let c = skip_blanks(chars, from);
        if chars.get(c) != Some(&'[') {
            return Err((c + 1, format!("{what}: expected a [condition]")));
        }
        let end = self.reader.params.real_value(chars, c, true).map_err(|e| (e.column, format!("{what}: {}", e.message)))?.1;
        Ok((c, end))
    }

    /// A block holding a call code (`M98`, `M97`, `M99`, `G65`, `G66`, `G67`): its words, values
    /// evaluated; `None` for a block without one.
    pub(super) fn call_words(&self, chars: &[char], from: usize) -> Result<Option<Stmt>, (usize, String)> {
        // Only a block with a call code is parsed here: M or G and the code's digits.
        let mut i = from;
        let mut calls = false;
        while i < chars.len() {
            match chars[i] {
                ';' => break,
                '(' => i += chars[i..].iter().position(|&c| c == ')').unwrap_or(chars.len() - i),
                c if c.eq_ignore_ascii_case(&'M') || c.eq_ignore_ascii_case(&'G') => {
                    let j = skip_blanks(chars, i + 1);
                    let k = (j..chars.len()).find(|&k| !chars[k].is_ascii_digit()).unwrap_or(chars.len());
                    let code: String = chars[j..k].iter().collect();
                    let code = code.trim_start_matches('0');
                    let m = c.eq_ignore_ascii_case(&'M');
                    if chars.get(k) != Some(&'.') && (m && matches!(code, "97" | "98" | "99") || !m && matches!(code, "65" | "66" | "67")) {
                        calls = true;
                    }
                }
                _ => {}
            }
            i += 1;
        }
        if !calls {
            return Ok(None);
        }
        let mut words = Vec::new();
        let mut i = from;
        loop {
            i = skip_blanks(chars, i);
            let Some(&c) = chars.get(i) else { break };
            if c == ';' {
                break;
            }
            if c == '(' {
                i += chars[i..].iter().position(|&c| c == ')').map_or(chars.len(), |p| p + 1);
                continue;
            }
            if !c.is_ascii_alphabetic() {
                return Err((i + 1, format!("unexpected '{}' in a call's block", excerpt(&chars[i..].iter().collect::<String>()))));
            }
            let at = skip_blanks(chars, i + 1);
            let (value, end) = self.reader.params.real_value(chars, at, true).map_err(|e| (e.column, format!("{c}: {}", e.message)))?;
            let raw: String = chars[at..end].iter().filter(|c| !c.is_whitespace()).collect();
            words.push(Word { letter: c.to_ascii_uppercase(), value, raw: raw.into(), column: i + 1, dimension: Dimension::Modal });
            i = end;
        }
        Ok(Some(Stmt::Call(words)))
    }

    /// The value at `chars[at..]` (a number, `#i` or `[..]`) as a block number, the index after it
    /// and its column.
    pub(super) fn label(&self, chars: &[char], at: usize, what: &str) -> Result<(u64, usize, usize), (usize, String)> {
        let at = skip_blanks(chars, at);
        let (v, end) = self.reader.params.real_value(chars, at, true).map_err(|e| (e.column, format!("{what}: {}", e.message)))?;
        if v.fract() != 0.0 || !(1.0..=99_999_999.0).contains(&v) {
            return Err((at + 1, format!("{what} {v}: expected a block number 1 to 99999999")));
        }
        Ok((v as u64, end, at + 1))
    }
}

#[cfg(test)]
mod tests {
    use super::maybe_flow;

    /// The pre-scan passes on a line exactly when one of its letters is followed, past blanks, by a
    /// character that continues a statement or call: checked against that rule written out plainly,
    /// on 100,000 lines drawn from the letters and digits of statements and moves.
    #[test]
    fn the_prescan_finds_every_statement_start() {
        let plain = |text: &str| {
            let b: Vec<char> = text.chars().collect();
            (0..b.len()).any(|i| {
                let next = b[i + 1..].iter().find(|c| **c != ' ' && **c != '\t').map_or('\0', char::to_ascii_uppercase);
                match b[i].to_ascii_lowercase() {
                    'i' => next == 'F',
                    'g' => next == 'O' || next == '6',
                    'w' => next == 'H',
                    'd' => next == 'O',
                    'e' => next == 'N',
                    'm' => next == '9' || next == '0',
                    _ => false,
                }
            })
        };
        let alphabet: Vec<char> = "IiFfGgOo6WwHhDdEeNnMm9801X. \t-#[]".chars().collect();
        let mut next = crate::program::lex::xorshift(0x2545_F491_4F6C_DD1D);
        for _ in 0..100_000 {
            let len = (next() % 12) as usize;
            let text: String = (0..len).map(|_| alphabet[(next() % alphabet.len() as u64) as usize]).collect();
            assert_eq!(maybe_flow(&text), plain(&text), "{text:?}");
        }
        assert!(maybe_flow("N10 WHILE [#1 LT 5] DO1") && maybe_flow("M 98 P100") && !maybe_flow("N10 G1 X-50.0000 Y-50.0000 Z-10.4409 A12.2101 C-144.3218"));
    }
}
