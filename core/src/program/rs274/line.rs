//! An RS274NGC line read into its words and parameter settings, each value compiled (and evaluated
//! as LinuxCNC's reader does, left to right), for [`Rs274Reader::run_line`] to run once or on each
//! pass of a loop.

use super::{text_reads_state, Rs274Reader, KEEP_BUFFER};
use crate::program::lex::{excerpt, parse_number, Diags};
use crate::program::params::expr::{self, Compiled, Setting};
use crate::program::params::{skip_blanks, ExprError, Target};
use crate::program::Dialect;

impl Rs274Reader {
    /// A line's words and settings as read from its text (`\r` trimmed), values compiled: what
    /// [`Rs274Reader::run_line`] runs, once or on each pass of a loop. Each value is evaluated as it
    /// is read too, as LinuxCNC's reader does, so that the line's first defect from the left is the
    /// one said; those values (`Now`) are this pass's. None when the line has nothing to run (blank,
    /// the tape's `%`, a title) or is damaged (said here).
    pub(crate) fn read_line(&mut self, line: usize, text: &str, diags: &mut Diags) -> Option<(ReadLine, Vec<Now>)> {
        let mut buf = std::mem::take(&mut self.chars_buf);
        let read = self.read_line_into(line, text, &mut buf, diags);
        if buf.capacity() <= KEEP_BUFFER {
            self.chars_buf = buf;
        }
        read
    }

    /// A line read and run: its items' room kept for the next line's.
    pub(super) fn recycle(&mut self, read: ReadLine) {
        let mut items = read.items;
        if items.capacity() <= KEEP_BUFFER && items.capacity() > self.items_buf.capacity() {
            items.clear();
            self.items_buf = items;
        }
    }

    /// [`Rs274Reader::read_line`] with its characters in `buf`.
    fn read_line_into(&mut self, line: usize, text: &str, buf: &mut Vec<char>, diags: &mut Diags) -> Option<(ReadLine, Vec<Now>)> {
        self.refresh_state(text_reads_state(text));
        // Room for every character at once (a char per byte at most): no regrowing as it fills.
        buf.clear();
        buf.reserve(text.len());
        let ascii = text.is_ascii();
        if ascii {
            // A byte per character: copied as a slice is (no decoding).
            buf.extend(text.bytes().map(char::from));
        } else {
            buf.extend(text.chars());
        }
        let chars: &[char] = buf;
        // Where each character starts in the text (a word's text is a byte range of it).
        let offsets: Vec<usize> = if ascii { Vec::new() } else { text.char_indices().map(|(b, _)| b).chain([text.len()]).collect() };
        let byte = |i: usize| if ascii { i } else { offsets[i] };
        let first = chars.iter().position(|c| !c.is_whitespace())?;
        if chars[first] == '%' {
            // Fanuc, Haas: the `%` after the program ends the tape ("end of record"); what follows
            // it (an NX listing's line count) is not program.
            self.refused = self.dialect.is_fanuc() && self.started;
            return None;
        }
        let errors_before = diags.errors();
        // Fanuc, Haas: the program opens with its number, `O` and digits (FANUC B-64014EN §2.5: "an O
        // number or ... a file name ... enclosed by < and >"; Haas: `O` and 4 or 5 digits). Anything
        // else there (an NX post's placeholder `O ENTER OP AND LAST 3 DIGITS`, a name `OFinal ToolPath`)
        // is the program's title line, which moves nothing: noted, and the control may refuse to
        // load the program for it.
        if self.dialect.is_fanuc() && !self.started && matches!(chars[first], 'O' | 'o') {
            // What follows the O: its digits, and what stands after them.
            let rest = &chars[first + 1..];
            let rest = &rest[rest.iter().position(|c| !c.is_whitespace()).unwrap_or(rest.len())..];
            let digits = rest.iter().take_while(|c| c.is_ascii_digit()).count();
            // `O0000` (a post's placeholder, as Mastercam's): program number 0, read as a title too
            // (it moves nothing either way; whether the control stores a program under it is its own).
            let zero = digits > 0 && rest[..digits].iter().all(|c| *c == '0') && rest.get(digits).is_none_or(|c| c.is_whitespace() || *c == '(' || *c == ';');
            if digits == 0 || zero {
                let what = if zero { "program number 0" } else { "not a program number (O and digits)" };
                diags.warning(line, first + 1, format!("'{}' is {what}: read as the program's title; the control may refuse to load the program for it", excerpt(text[byte(first)..].trim_end())));
                self.started = true;
                return None;
            }
        }
        if let Some(keyword) = o_word_control(&chars[first..]) {
            diags.error(line, first + 1, format!("O-word '{keyword}': LinuxCNC's control flow, not this dialect's"));
            return None;
        }
        // A five-axis move has about eight words (N G X Y Z A C F), held without regrowing.
        let mut items = std::mem::take(&mut self.items_buf);
        items.reserve(10);
        let mut read = ReadLine { first, number: None, items };
        let mut now = Vec::new();
        let mut i = first;
        if chars[i] == '/' {
            if chars.get(i + 1).is_some_and(char::is_ascii_digit) {
                // Fanuc's optional block skip 2-9 (`/2`) is not in the manuals in reach, nor in LinuxCNC's.
                let level: String = chars[i..].iter().take_while(|c| **c == '/' || c.is_ascii_digit()).collect();
                diags.error(line, i + 1, format!("block delete level '{level}' is not read (only the plain block delete '/' is)"));
                return None;
            }
            diags.warning(line, i + 1, "block delete '/' is not modelled: the block is run");
            i += 1;
        }
        // Where the line's words start (after a block delete): LinuxCNC reads N only there.
        let words_start = skip_blanks(&chars, i);
        // Fanuc, Haas: the column of a `,` that makes the next word a comma word (`,C`, `,R`).
        let mut comma: Option<usize> = None;
        while i < chars.len() {
            let c = chars[i];
            if c.is_whitespace() {
                i += 1;
            } else if c == ';' {
                break;
            } else if c == ',' && self.dialect.is_fanuc() && comma.is_none() && chars.get(skip_blanks(&chars, i + 1)).is_some_and(char::is_ascii_alphabetic) {
                // Chamfering and corner R (`,C`, `,R`, [`crate::program::fanuc_corners`]): `,A` (a line's
                // angle) and the rest are refused with the word.
                comma = Some(i + 1);
                i = skip_blanks(&chars, i + 1);
            } else if c == '(' {
                match chars[i..].iter().position(|&ch| ch == ')') {
                    // LinuxCNC: "Nested comment found" (interp_internal.cc close_and_downcase).
                    Some(close) if self.dialect == Dialect::Rs274 && chars[i + 1..i + close].contains(&'(') => {
                        let at = i + 2 + chars[i + 1..i + close].iter().position(|&ch| ch == '(').unwrap_or(0);
                        diags.error(line, at, "'(' inside a comment: LinuxCNC refuses the line (\"Nested comment found\")");
                        break;
                    }
                    Some(close) => i += close + 1,
                    None => {
                        diags.error(line, i + 1, "comment '(' is not closed: expected ')' on the same line");
                        break;
                    }
                }
            } else if c == '#' {
                match expr::setting(&chars, i, self.dialect.is_fanuc()).and_then(|(setting, end)| Ok((setting.run(&self.params)?, setting, end))) {
                    Ok(((target, value), setting, end)) => {
                        read.items.push(Item::Setting { setting, column: i + 1 });
                        now.push(Now::Set(target, value));
                        i = end;
                    }
                    Err(e) => {
                        self.alarmed |= e.stops;
                        diags.error(line, e.column, e.message);
                        break;
                    }
                }
            } else if c.is_ascii_alphabetic() || (self.dialect == Dialect::Rs274 && (c == '@' || c == '^')) {
                if let Some(word) = macro_control(&chars[i..]) {
                    diags.error(line, i + 1, format!("Fanuc macro '{word}': control flow (IF, WHILE, GOTO) is not read (the motion would depend on it)"));
                    break;
                }
                let letter = c.to_ascii_uppercase();
                // A comma word stands at its comma.
                let (comma, column) = match comma.take() {
                    Some(at) if matches!(letter, 'C' | 'R') => (true, at),
                    Some(at) => {
                        let what = if letter == 'A' { "a line's angle (,A) is not read: give the line's end point" } else { "only ,C (chamfer) and ,R (corner R) are read after a comma" };
                        diags.error(line, at, format!(",{letter}: {what}"));
                        break;
                    }
                    None => (false, i + 1),
                };
                i += 1;
                while i < chars.len() && (chars[i] == ' ' || chars[i] == '\t') {
                    i += 1;
                }
                let start = i;
                if computed_value_at(&chars, start) {
                    match expr::address_value(&chars, start, self.dialect.is_fanuc()).and_then(|(c, end)| Ok((c.eval(&self.params)?, c, end))) {
                        Ok((_, _, end)) if letter == 'N' => {
                            diags.error(line, column, "a line number 'N' must be written as a number");
                            i = end;
                        }
                        Ok((v, value, end)) => {
                            read.items.push(Item::Word { letter, comma, column, raw: (byte(start), byte(end)), spaced: false, value: Value::Computed(value) });
                            now.push(Now::Value(v));
                            i = end;
                        }
                        Err(e) => {
                            diags.error(line, e.column, format!("{letter}: {}", e.message));
                            break;
                        }
                    }
                    continue;
                }
                // A sign first, then digits and points: ASCII, a character a byte.
                i += crate::program::lex::number_prefix_len(&text[byte(start)..]);
                // LinuxCNC: "Spaces and tabs are allowed anywhere on a line of code and do not change
                // the meaning of the line, except inside comments" (G-code overview, "Format of a
                // line"): `X1 0` is X10, `G4 0` is G40.
                let unbroken = i;
                if self.dialect == Dialect::Rs274 {
                    i = blanks_within_number(chars, start, i);
                }
                let spaced = i != unbroken;
                let compact = word_text(&text[byte(start)..byte(i)], spaced);
                let number_text = compact.as_ref();
                match parse_number(number_text) {
                    Some(_) if letter == 'N' && self.dialect == Dialect::Rs274 && column - 1 != words_start => {
                        diags.error(line, column, format!("N{number_text} after other words: LinuxCNC reads a line number only at the line's start (\"Bad character 'n' used\")"));
                    }
                    Some(v) if letter == 'N' => {
                        // LinuxCNC accepts and ignores a fractional part ("accept & ignore fractional
                        // line numbers", interp_read.cc read_n_number): N4567.789 is block 4567.
                        let digits = |s: &str| !s.is_empty() && s.bytes().all(|c| c.is_ascii_digit());
                        let fractional = self.dialect == Dialect::Rs274 && number_text.split_once('.').is_some_and(|(a, b)| digits(a) && digits(b));
                        if v.fract() == 0.0 && v >= 0.0 || fractional {
                            read.number = Some(v.trunc() as u64);
                        } else {
                            diags.error(line, column, format!("expected a whole line number after 'N', found '{number_text}'"));
                        }
                    }
                    Some(v) => read.items.push(Item::Word { letter, comma, column, raw: (byte(start), byte(i)), spaced, value: Value::Written(v) }),
                    None => {
                        let mut end = i;
                        while end < chars.len() && !chars[end].is_whitespace() {
                            end += 1;
                        }
                        diags.error(line, column, format!("expected a number after '{letter}', found '{}'", excerpt(&text[byte(start)..byte(end)])));
                        i = end.max(i + usize::from(i == start));
                    }
                }
            } else if c == ')' && self.dialect.is_fanuc() {
                // A comment ends at its first ')' (control-in); one more closes nothing and says
                // nothing (NX's Haas post writes `(#508= (MILL_.25_PROFILE ))`).
                diags.warning(line, i + 1, "')' closes no comment: skipped");
                i += 1;
            } else {
                let mut end = i;
                while end < chars.len() && !chars[end].is_whitespace() {
                    end += 1;
                }
                diags.error(line, i + 1, format!("unexpected '{}': expected a word such as G1 or X10.5", excerpt(&text[byte(i)..byte(end)])));
                i = end;
            }
        }
        if diags.errors() > errors_before {
            diags.warning(line, first + 1, format!("line {line} not used: it is damaged"));
            // Its G codes as written: the control runs the line, and those it keeps hold later moves.
            let g: Vec<crate::program::interp::Word> = read
                .items
                .iter()
                .filter_map(|item| match item {
                    Item::Word { letter: 'G', comma: false, column, raw, spaced, value: Value::Written(v) } => {
                        Some(crate::program::interp::Word { letter: 'G', value: *v, raw: word_text(&text[raw.0..raw.1], *spaced), column: *column, dimension: crate::program::interp::Dimension::Modal })
                    }
                    _ => None,
                })
                .collect();
            self.interp.refused(&g, line);
            return None;
        }
        Some((read, now))
    }
}

/// Where a number that starts at `start` and whose first unbroken part ends at `end` ends when the
/// blanks within it are the line's (LinuxCNC reads a line with its blanks taken out): on over each
/// run of blanks that a digit or a point follows.
fn blanks_within_number(chars: &[char], start: usize, mut end: usize) -> usize {
    loop {
        let after = skip_blanks(chars, end);
        let more = chars[after..].iter().take_while(|c| c.is_ascii_digit() || **c == '.').count();
        // Nothing number-like at the start (a letter, a bracket) is no number to go on with; a sign
        // alone (`X- 5`) is.
        if after == end || more == 0 || end == start {
            return end;
        }
        end = after + more;
    }
}

/// A word's written text without the blanks a LinuxCNC line may hold within it (`1 0` is `10`),
/// where it has any (`spaced`, as the line was read); borrowed otherwise, as nearly every word is, on
/// the hot path.
pub(super) fn word_text(s: &str, spaced: bool) -> std::borrow::Cow<'_, str> {
    if spaced {
        s.chars().filter(|c| *c != ' ' && *c != '\t').collect::<String>().into()
    } else {
        s.into()
    }
}

/// A line as read, to run once or on each pass of a loop ([`Rs274Reader::read_line`]).
#[derive(Debug, Clone)]
pub(crate) struct ReadLine {
    /// The 0-based column of its first character that is not blank.
    pub(super) first: usize,
    /// Its `N` number.
    pub(super) number: Option<u64>,
    /// Its words and settings, in order.
    pub(super) items: Vec<Item>,
}

/// A word or a parameter setting of a line; a word's text is a byte range of the line.
#[derive(Debug, Clone)]
pub(super) enum Item {
    /// `comma`: Fanuc's `,C` or `,R` (its column the comma's); `spaced`: its number has blanks within
    /// it, which LinuxCNC takes out (`X1 0`).
    Word { letter: char, comma: bool, column: usize, raw: (usize, usize), spaced: bool, value: Value },
    Setting { setting: Setting, column: usize },
}

/// A value as evaluated when its line was read: a computed word's, or a setting's parameter and value.
#[derive(Debug)]
pub(crate) enum Now {
    Value(f64),
    Set(Target, f64),
}

impl Now {
    pub(super) fn value(self) -> Result<f64, ExprError> {
        match self {
            Now::Value(v) => Ok(v),
            Now::Set(..) => Err(ExprError { column: 1, message: "a setting's value where a word's was read (internal)".into(), stops: false }),
        }
    }

    pub(super) fn setting(self) -> Result<(Target, f64), ExprError> {
        match self {
            Now::Set(t, v) => Ok((t, v)),
            Now::Value(_) => Err(ExprError { column: 1, message: "a word's value where a setting's was read (internal)".into(), stops: false }),
        }
    }
}

impl ReadLine {
    /// The memory it holds, bytes (what a runner keeping lines bounds).
    pub(crate) fn size(&self) -> usize {
        std::mem::size_of::<ReadLine>()
            + self.items.capacity() * std::mem::size_of::<Item>()
            + self
                .items
                .iter()
                .map(|item| match item {
                    Item::Word { value: Value::Computed(c), .. } => c.size(),
                    Item::Word { .. } => 0,
                    Item::Setting { setting, .. } => setting.size(),
                })
                .sum::<usize>()
    }
}

/// A word's value: written, or compiled from parameters and expressions.
#[derive(Debug, Clone)]
pub(super) enum Value {
    Written(f64),
    Computed(Compiled),
}

/// Whether the value at `chars[i]` is one the parameters evaluate (LinuxCNC `read_real_value`): a
/// parameter, an expression, a unary function, or a sign before one of those; a plain number is not.
fn computed_value_at(chars: &[char], i: usize) -> bool {
    let blank = |k: usize| skip_blanks(chars, k);
    let function = |k: usize| {
        let end = (k..chars.len()).find(|&e| !chars[e].is_ascii_alphabetic()).unwrap_or(chars.len());
        end > k && chars.get(blank(end)) == Some(&'[')
    };
    match chars.get(i) {
        Some('#' | '[') => true,
        Some('+' | '-') => {
            let k = blank(i + 1);
            matches!(chars.get(k), Some('#' | '[')) || function(k)
        }
        Some(c) if c.is_ascii_alphabetic() => function(i),
        _ => false,
    }
}

/// A computed value as a word's text: G and M codes to their tenth (a code is a whole number or has
/// one decimal; LinuxCNC takes a value within 0.0001 of it), other words as the shortest exact decimal.
pub(super) fn written(letter: char, value: f64) -> String {
    if matches!(letter, 'G' | 'M') {
        let tenth = (value * 10.0).round() / 10.0;
        if (value - tenth).abs() <= 1e-4 {
            return format!("{tenth}");
        }
    }
    format!("{value}")
}

/// LinuxCNC's O-word control flow at the start of a line (`o100 while [...]`, `o<name> sub`): its
/// keyword, lower case.
fn o_word_control(chars: &[char]) -> Option<String> {
    if !matches!(chars.first(), Some('o' | 'O')) {
        return None;
    }
    let mut i = skip_blanks(chars, 1);
    if chars.get(i) == Some(&'<') {
        i += chars[i..].iter().position(|&c| c == '>')? + 1;
    } else {
        let digits = i;
        while chars.get(i).is_some_and(|c| c.is_ascii_digit()) {
            i += 1;
        }
        if i == digits {
            return None;
        }
    }
    let i = skip_blanks(chars, i);
    let (word, _) = crate::program::oword::keyword_at(chars, i)?;
    crate::program::oword::Keyword::of(&word)?;
    Some(format!("{} {word}", chars[..i].iter().collect::<String>().trim_end()))
}

/// Fanuc custom macro B's control words (`IF [..] GOTO n`, `WHILE [..] DO1`, `END1`) where a word
/// letter would stand: the word, upper case.
fn macro_control(chars: &[char]) -> Option<&'static str> {
    // A word letter stands alone before its value: only a run of two letters or more can be one.
    if !chars.get(1).is_some_and(|c| c.is_ascii_alphabetic()) {
        return None;
    }
    let len = chars.iter().take_while(|c| c.is_ascii_alphabetic()).count();
    ["IF", "WHILE", "GOTO", "DO", "END", "THEN"]
        .into_iter()
        .find(|w| w.len() == len && chars.iter().zip(w.chars()).all(|(c, u)| c.to_ascii_uppercase() == u))
}
