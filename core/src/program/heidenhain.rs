//! Heidenhain DIN/ISO programs as in the paper's appendices (`SING.I`, `NON_SING.I`):
//! `%NAME G71 *` header, `N..` block numbers, blocks ending in ` *`, `%`-comment lines, `;` comments,
//! `G54 X.. Y.. Z..` datum shift, `M128`/`M129` tool-centre-point management, `N999999 %NAME G71 *` end;
//! arcs `G02`/`G03` about the modal circle centre `I J K` (absolute; from the last position under G91)
//! or with `R`, `G05` in the last arc's direction (iTNC 530 User's Manual ISO programming, "Circle
//! center I, J" and "Circular path G02/G03/G05 around circle center I, J").
//!
//! Damage is reported where it stands: two blocks run together on one line, a number split by a space,
//! a garbled word, repeated or out-of-order block numbers, a header with a space in the name.

use super::interp::{Dimension, Interpreter, Word};
use super::lex::{excerpt, number_prefix_len, parse_number, Diags};
use super::{Block, Dialect, Program};

/// A lexical token of one line, borrowing its text from the line.
#[derive(Debug, Clone, PartialEq)]
enum Tok<'a> {
    /// Letter + text after it up to the next separator; `value` is None when the text is not a number.
    Word { letter: char, text: &'a str, value: Option<f64>, incremental: bool, col: usize },
    /// A number with no address letter in front.
    Bare { text: &'a str, col: usize },
    /// Anything else that cannot start a word.
    Junk { text: &'a str, col: usize },
    /// ` *`
    End { col: usize },
    /// `%` in a block line: a program begin/end marker with the rest of the line.
    Percent { rest: &'a str, col: usize },
}

fn is_sep(c: char) -> bool {
    c.is_whitespace() || c == '*' || c == ';' || c == '%'
}

/// ASCII bytes that are no separator ([`is_sep`]: `char::is_whitespace` takes 0x09-0x0D and the
/// blank among them): a word's bytes, passed by one look-up each.
const WORD_BYTE: [bool; 256] = {
    let mut t = [false; 256];
    let mut c = 0;
    while c < 128 {
        t[c] = !matches!(c as u8, 0x09..=0x0D | b' ' | b'*' | b';' | b'%');
        c += 1;
    }
    t
};

fn tokenize(line: &str) -> Vec<Tok<'_>> {
    let mut toks = Vec::with_capacity(8);
    // Byte offset `i` and 1-based column `col` (characters) as the scan goes.
    let (mut i, mut col) = (0, 1);
    // The character at byte `i` (a boundary, within the line): an ASCII byte is its own character.
    let char_at = |i: usize| match line.as_bytes()[i] {
        b if b.is_ascii() => char::from(b),
        _ => line[i..].chars().next().unwrap_or(' '),
    };
    while i < line.len() {
        let c = char_at(i);
        if c.is_whitespace() {
            i += c.len_utf8();
            col += 1;
        } else if c == ';' {
            break;
        } else if c == '*' {
            toks.push(Tok::End { col });
            i += 1;
            col += 1;
        } else if c == '%' {
            toks.push(Tok::Percent { rest: &line[i + 1..], col });
            break;
        } else {
            let (start, start_col) = (i, col);
            while i < line.len() {
                // ASCII bytes that separate nothing first: a byte and a column each.
                let plain = line.as_bytes()[i..].iter().take_while(|&&b| WORD_BYTE[usize::from(b)]).count();
                i += plain;
                col += plain;
                if i >= line.len() {
                    break;
                }
                let cc = char_at(i);
                if is_sep(cc) {
                    break;
                }
                i += cc.len_utf8();
                col += 1;
            }
            let run = &line[start..i];
            if c.is_ascii_alphabetic() {
                let letter = c.to_ascii_uppercase();
                let mut body = &run[1..];
                let incremental = letter == 'I' && body.starts_with(|ch: char| "XYZABCxyzabc".contains(ch));
                let letter = if incremental {
                    let l = body.as_bytes()[0].to_ascii_uppercase() as char;
                    body = &body[1..];
                    l
                } else {
                    letter
                };
                // Words written without spaces (`X+0Y+0`) split where a valid number meets a letter.
                let n = number_prefix_len(body);
                if n > 0 && n < body.len() && body[n..].starts_with(|ch: char| ch.is_ascii_alphabetic()) {
                    if let Some(v) = parse_number(&body[..n]) {
                        toks.push(Tok::Word { letter, text: &body[..n], value: Some(v), incremental, col: start_col });
                        // Go on at the letter after the number (all ASCII up to it: a column a byte).
                        let consumed = 1 + usize::from(incremental) + n;
                        i = start + consumed;
                        col = start_col + consumed;
                        continue;
                    }
                }
                toks.push(Tok::Word { letter, text: body, value: parse_number(body), incremental, col: start_col });
            } else if c.is_ascii_digit() || c == '+' || c == '-' || c == '.' {
                toks.push(Tok::Bare { text: run, col: start_col });
            } else {
                toks.push(Tok::Junk { text: run, col: start_col });
            }
        }
    }
    toks
}

/// Parse `NAME G71 *` after a `%`; returns the name. `col` is the column of the `%`.
fn header(rest: &str, line: usize, col: usize, diags: &mut Diags) -> String {
    let body = rest.split('*').next().unwrap_or("");
    let mut parts: Vec<(usize, &str)> = Vec::new();
    let mut offset = 0;
    for piece in body.split(' ') {
        if !piece.is_empty() {
            parts.push((col + 1 + offset, piece));
        }
        offset += piece.chars().count() + 1;
    }
    let unit_at = parts.iter().position(|(_, p)| p.eq_ignore_ascii_case("G71") || p.eq_ignore_ascii_case("G70"));
    let name_parts = &parts[..unit_at.unwrap_or(parts.len().min(1))];
    let name = name_parts.iter().map(|(_, p)| *p).collect::<Vec<_>>().join(" ");
    if name.is_empty() {
        diags.error(line, col + 1, "expected a program name after '%'");
    } else if name_parts.len() > 1 {
        diags.error(
            line,
            name_parts[1].0 - 1,
            format!("program name '{name}' contains a space: expected %NAME G71 * with no space in the name"),
        );
    }
    match unit_at {
        None => diags.error(line, col, "expected G70 (inch) or G71 (mm) after the program name"),
        Some(k) if k + 1 < parts.len() => diags.error(
            line,
            parts[k + 1].0,
            format!("unexpected '{}' after the unit: expected ' *'", excerpt(parts[k + 1].1)),
        ),
        _ => {}
    }
    if !rest.contains('*') {
        diags.error(line, col + rest.chars().count() + 1, "missing block end: expected ' *'");
    }
    name
}

/// Read a Heidenhain DIN/ISO program.
pub fn read_heidenhain(text: &str) -> Program {
    read_heidenhain_with(text, &[], Dialect::Heidenhain.default_orientation())
}

/// Read a Heidenhain DIN/ISO program on a control whose machine-specific M functions do what
/// `m_codes` says and whose orientation interpolation starts as `orientation`.
pub fn read_heidenhain_with(text: &str, m_codes: &[super::MCodeRule], orientation: super::Orientation) -> Program {
    super::stream::read_whole(&mut DinReader::new(&super::Setup::plain(Dialect::Heidenhain, m_codes, orientation)), text, Dialect::Heidenhain)
}

/// The DIN/ISO reader, fed one line at a time.
#[derive(Debug, Clone)]
pub(crate) struct DinReader {
    pub(super) interp: Interpreter,
    name: Option<String>,
    seen: SeenNumbers,
    last_number: Option<(u64, usize)>,
    /// Block numbers went backwards somewhere: a damaged copy whose order may be recovered.
    pub(super) out_of_order: bool,
    ended: bool,
    /// The program stopped at `M02`/`M30` (its line and block number; whether the blocks after it
    /// have been said not to run): the TNC goes back to its first block there.
    stopped: Option<(usize, Option<u64>, bool)>,
    /// The last line with anything on it (where a missing program end is said).
    pub(super) last_line: usize,
    /// Tool radius compensation G41/G42 ([`super::heidenhain_comp`]).
    pub(super) comp: super::heidenhain_comp::DinComp,
}

impl DinReader {
    pub(crate) fn new(setup: &super::Setup) -> Self {
        DinReader {
            interp: setup.interpreter(),
            name: None,
            seen: SeenNumbers::default(),
            last_number: None,
            out_of_order: false,
            ended: false,
            stopped: None,
            last_line: 0,
            comp: Default::default(),
        }
    }
}

impl DinReader {
    /// `M91`/`M92` in a block: its coordinates are the machine's, about the machine datum or the
    /// maker's second one, in this block only (TNC 426 B ISO §7.3), as the Klartext reader reads
    /// them: an absolute straight line (`G00`/`G01`, or that motion in force) whose axes the
    /// interpreter then places. Why not (its column), for a block that cannot take them.
    fn machine_coordinates(&mut self, words: &[Word]) -> Result<(), (usize, String)> {
        let Some(m) = words.iter().find(|w| w.letter == 'M' && (w.value == 91.0 || w.value == 92.0)) else { return Ok(()) };
        let code = m.value as u32;
        let said = |why: String| (m.column, format!("M{}: {why}", m.raw));
        let g = |v: f64| words.iter().any(|w| w.letter == 'G' && w.value == v);
        let motion = if g(0.0) {
            Some(crate::program::Motion::Rapid)
        } else if g(1.0) {
            Some(crate::program::Motion::Linear)
        } else if words.iter().any(|w| w.letter == 'G' && matches!(w.value as i64, 2 | 3 | 5 | 6 | 10..=16)) {
            None
        } else {
            self.interp.feed_state().0.filter(|m| matches!(m, crate::program::Motion::Rapid | crate::program::Motion::Linear))
        };
        let incremental = g(91.0) || (!g(90.0) && !self.interp.absolute()) || words.iter().any(|w| w.dimension == Dimension::Incremental);
        let Some(motion) = motion.filter(|_| !incremental) else {
            return Err(said("machine coordinates are absolute positions of a straight-line block (G00 or G01, with G90)".into()));
        };
        let origin = self.interp.tnc_machine_origin(code).map_err(said)?;
        self.interp.oneshot = Some(super::interp::OneShot { motion, absolute: true, axes: Some(origin), own: false });
        Ok(())
    }
}

impl super::stream::LineReader for DinReader {
    fn line(&mut self, line: usize, text: &str, out: &mut Vec<Block>, diags: &mut Diags) {
        let trimmed = text.trim_end_matches('\r');
        if !trimmed.trim().is_empty() {
            self.last_line = line;
        }
        let lead = trimmed.len() - trimmed.trim_start().len();
        let body = trimmed.trim_start();
        if body.is_empty() || body.starts_with(';') {
            return;
        }
        if let Some(rest) = body.strip_prefix('%') {
            if rest.starts_with(|c: char| c.is_whitespace()) || rest.is_empty() {
                return; // `% DATUM INPUT`: a comment line
            }
            let col = trimmed[..lead].chars().count() + 1;
            let n = header(rest, line, col, diags);
            if self.name.is_some() {
                diags.warning(line, col, format!("second program header '%{n}' ignored"));
            } else {
                if n.contains(' ') || n.is_empty() {
                    // already reported; keep the name as read
                }
                self.name = Some(n);
                let inch = rest.contains("G70");
                if let Err(u) = self.interp.set_inch(inch) {
                    diags.warning(line, col, format!("the header says {}; the program's numbers are read in {} (--units)", if inch { "G70 (inches)" } else { "millimetres" }, u.name()));
                }
            }
            return;
        }
        if self.ended {
            diags.warning(line, lead + 1, "text after the program end ignored");
            return;
        }

        // Split the line's tokens into blocks: each starts at an N word or after ' *'.
        let toks = tokenize(trimmed);
        // Blocks as ranges of the line's tokens, and whether ' *' ended each.
        let mut groups: Vec<(std::ops::Range<usize>, bool)> = Vec::with_capacity(1);
        let mut from = 0;
        for (k, t) in toks.iter().enumerate() {
            match t {
                Tok::End { .. } => {
                    groups.push((from..k, true));
                    from = k + 1;
                }
                Tok::Word { letter: 'N', col, .. } if k > from => {
                    let prev = block_label(&toks[from..k]);
                    diags.error(
                        line,
                        *col,
                        format!("block {} begins before block {prev} ended: expected ' *' before it (two blocks run together)", word_text(t)),
                    );
                    groups.push((from..k, false));
                    from = k;
                }
                _ => {}
            }
        }
        if matches!(toks.last(), Some(Tok::Percent { .. })) && from < toks.len() {
            groups.push((from..toks.len(), true));
            from = toks.len();
        }
        if from < toks.len() {
            let col = trimmed.chars().count() + 1;
            diags.error(line, col, format!("block {} has no block end: expected ' *' at the end of the line", block_label(&toks[from..])));
            groups.push((from..toks.len(), false));
        }
        let complete_groups = groups.iter().filter(|(g, _)| !g.is_empty()).count();
        if complete_groups > 1 && groups.iter().all(|(_, term)| *term) {
            diags.warning(line, lead + 1, "more than one block on this line");
        }

        for (range, _) in groups.into_iter().filter(|(g, _)| !g.is_empty()) {
            let g = &toks[range];
            let first_col = tok_col(&g[0]);
            let errors_before = diags.errors();
            let mut number = None;
            let mut words: Vec<Word> = Vec::new();
            let mut program_end = false;
            for (k, t) in g.iter().enumerate() {
                match t {
                    Tok::Word { letter, text, value, incremental, col } => match value {
                        None => diags.error(
                            line,
                            *col,
                            format!("expected a number after '{letter}', found '{}'", excerpt(text)),
                        ),
                        Some(v) if *letter == 'N' => {
                            if k != 0 {
                                diags.error(line, *col, "block number N must come first in the block");
                            } else if v.fract() != 0.0 || *v < 0.0 {
                                diags.error(line, *col, format!("expected a whole block number after 'N', found '{text}'"));
                            } else {
                                number = Some(*v as u64);
                            }
                        }
                        Some(v) => words.push(Word {
                            letter: *letter,
                            value: *v,
                            raw: (*text).into(),
                            column: *col,
                            dimension: if *incremental { Dimension::Incremental } else { Dimension::Modal },
                        }),
                    },
                    Tok::Bare { text, col } => {
                        let after = match g[..k].last() {
                            Some(Tok::Word { letter, text: prev, .. }) => format!(" after {letter}{prev}"),
                            _ => String::new(),
                        };
                        diags.error(
                            line,
                            *col,
                            format!(
                                "number '{}' without an address letter{after} (a number split by a space?): expected a word such as X+1.5",
                                excerpt(text)
                            ),
                        );
                    }
                    Tok::Junk { text, col } => {
                        diags.error(line, *col, format!("unexpected '{}': expected an address word", excerpt(text)))
                    }
                    Tok::Percent { rest, col } => {
                        let n = header(rest, line, *col, diags);
                        if let Some(start) = &self.name {
                            if *start != n {
                                diags.error(line, *col + 1, format!("program end names '{n}' but the program began as '{start}'"));
                            }
                        }
                        program_end = true;
                    }
                    Tok::End { .. } => {}
                }
            }
            if program_end {
                self.ended = true;
                continue;
            }
            let damaged = diags.errors() > errors_before;
            if let Some(n) = number {
                if let Some(first_line) = self.seen.get(n) {
                    diags.error(line, first_col, format!("block number N{n} repeats the block on line {first_line}"));
                }
                if let Some((prev, prev_line)) = self.last_number {
                    if n < prev {
                        self.out_of_order = true;
                        diags.error(
                            line,
                            first_col,
                            format!("block number N{n} is out of order: it follows N{prev} (line {prev_line})"),
                        );
                    }
                }
                self.seen.insert(n, line);
                self.last_number = Some((n, line));
            }
            // After M02/M30 nothing runs ("M02/M30: stop program run, go to block 1", iTNC 530 ISO
            // Programming, M functions); a block numbered before it stands out of order in a damaged
            // copy, and is read for the order's recovery.
            if let Some((end_line, end_number, said)) = &mut self.stopped {
                if !number.is_some_and(|n| end_number.is_some_and(|e| n < e)) {
                    if !std::mem::replace(said, true) {
                        diags.warning(line, first_col, format!("block {} and after are not run: the program stopped at M02/M30 on line {end_line}", label(number, line)));
                    }
                    continue;
                }
            }
            // Radius compensation stopped the program ("Tool radius too large"): nothing after runs.
            if let Some(at) = self.comp.stopped {
                if !std::mem::replace(&mut self.comp.said, true) {
                    diags.warning(line, first_col, format!("block {} and after are not run: radius compensation stopped the program on line {at}", label(number, line)));
                }
                continue;
            }
            if damaged {
                diags.warning(line, first_col, format!("block {} not used: it is damaged", label(number, line)));
                // Its codes the TNC runs all the same (a mirroring `G28 X`): the holds take them.
                self.interp.refused_damaged(&words, line);
                continue;
            }
            // `M128 F1000`: the feed of the linear axes' compensating movements, not the path's
            // ([`super::interp::m128_feed_said`]).
            if let Some(k) = words.iter().position(|w| w.letter == 'M' && w.value == 128.0) {
                if let Some(f) = words[k + 1..].iter().position(|w| w.letter == 'F').map(|j| k + 1 + j) {
                    let w = words.remove(f);
                    diags.warning(line, w.column, super::interp::m128_feed_said(&format!("F{}", w.raw)));
                }
            }
            if let Err((col, why)) = self.machine_coordinates(&words) {
                diags.error(line, col, why);
                diags.warning(line, first_col, format!("block {} not used", label(number, line)));
                continue;
            }
            let before = out.len();
            let code = match super::heidenhain_comp::take_codes(&mut words) {
                Ok(code) => code,
                Err(col) => {
                    diags.error(line, col, "two of G40, G41 and G42 in one block: which one the TNC takes is not read");
                    diags.warning(line, first_col, format!("block {} not used", label(number, line)));
                    continue;
                }
            };
            let read = if self.comp.busy() || matches!(code, Some((Some(_), _))) {
                // The holds apply under compensation too ([`super::interp::Interpreter::block`]'s): a
                // held block's compensated path is not known, nor are the corners after it, so the
                // reading stops there (said once); a refused one tells the holds what the TNC runs.
                if let Some((c, why)) = self.interp.held(&words) {
                    diags.error(line, c, format!("{why}; under radius compensation (G41/G42) the compensated path from here is not known, so the rest of the program is not read"));
                    self.interp.refused_block(&words, line);
                    self.comp.stopped = Some(line);
                    false
                } else {
                    let done = self.compensated(&words, code, line, first_col, number, out, diags);
                    if done {
                        self.interp.after_held(&words, line, true);
                    } else {
                        self.interp.refused_block(&words, line);
                    }
                    done
                }
            } else {
                self.interp.block(&words, line, first_col, number, diags, out)
            };
            if read {
                self.comp.track(&words);
            } else {
                diags.warning(line, first_col, format!("block {} not used", label(number, line)));
            }
            if self.stopped.is_none() && super::stream::ends_program(&out[before..], &[2.0, 30.0]) {
                self.stopped = Some((line, number, false));
            }
        }
    }

    fn finish(&mut self, blocks: Option<&mut Vec<Block>>, out: &mut Vec<Block>, diags: &mut Diags) {
        self.comp_end(out, diags);
        if self.name.is_none() {
            diags.error(1, 1, "missing program header: expected %NAME G71 * on the first line");
        } else if !self.ended {
            // The TNC's DIN/ISO program ends with the block `N99999999 %NAME G71 *` (its program
            // end, as the header begins it): without it, the file was cut short.
            let name = self.name.as_deref().unwrap_or("NAME");
            diags.error(self.last_line.max(1), 1, format!("missing program end: expected N... %{name} G71 * as the last block (was the file cut short?)"));
        }
        if self.out_of_order {
            match blocks {
                Some(blocks) => recover_order(blocks, diags),
                None => diags.warning(1, 1, "blocks kept in file order: a program read as a stream is not put back in block-number order"),
            }
        }
    }

    fn name(&self) -> Option<String> {
        self.name.clone()
    }
}

/// The block numbers seen so far and their lines: an ascending run kept in a vector (the common case,
/// no hashing per block), any other number in a B-tree.
#[derive(Debug, Clone, Default)]
struct SeenNumbers {
    ascending: Vec<(u64, usize)>,
    others: std::collections::BTreeMap<u64, usize>,
}

impl SeenNumbers {
    fn get(&self, n: u64) -> Option<usize> {
        match self.ascending.binary_search_by_key(&n, |p| p.0) {
            Ok(k) => Some(self.ascending[k].1),
            Err(_) => self.others.get(&n).copied(),
        }
    }
    /// Record `n` at `line` unless it was seen before.
    fn insert(&mut self, n: u64, line: usize) {
        if self.get(n).is_some() {
            return;
        }
        match self.ascending.last() {
            Some(&(last, _)) if n <= last => {
                self.others.insert(n, line);
            }
            _ => self.ascending.push((n, line)),
        }
    }
}

/// Out-of-order numbering in a damaged copy: if the kept blocks all carry distinct numbers, run them
/// in number order (the order the program was written in) and say so.
fn recover_order(blocks: &mut [Block], diags: &mut Diags) {
    let mut numbers: Vec<u64> = blocks.iter().filter_map(|b| b.number).collect();
    let all = numbers.len() == blocks.len();
    numbers.sort_unstable();
    numbers.dedup();
    if all && numbers.len() == blocks.len() {
        blocks.sort_by_key(|b| b.number);
        diags.warning(1, 1, "blocks put back in block-number order to recover from the out-of-order numbering");
    } else {
        diags.warning(1, 1, "blocks kept in file order: the block numbers cannot restore the order");
    }
}

fn tok_col(t: &Tok) -> usize {
    match t {
        Tok::Word { col, .. } | Tok::Bare { col, .. } | Tok::Junk { col, .. } | Tok::End { col } | Tok::Percent { col, .. } => *col,
    }
}

fn word_text(t: &Tok) -> String {
    match t {
        Tok::Word { letter, text, .. } => format!("{letter}{text}"),
        _ => String::new(),
    }
}

fn block_label(toks: &[Tok]) -> String {
    match toks.first() {
        Some(t @ Tok::Word { letter: 'N', .. }) => word_text(t),
        _ => "without a number".to_string(),
    }
}

fn label(number: Option<u64>, line: usize) -> String {
    match number {
        Some(n) => format!("N{n} (line {line})"),
        None => format!("on line {line}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table of a word's bytes says what the separator rule says of every ASCII character, and
    /// leaves the bytes of other characters to it.
    #[test]
    fn word_bytes_are_the_ascii_non_separators() {
        for b in 0..=255u8 {
            assert_eq!(WORD_BYTE[usize::from(b)], b.is_ascii() && !is_sep(char::from(b)), "byte {b:#04x}");
        }
    }
}
