//! LinuxCNC's Fanuc-style subprograms (LinuxCNC manual, O codes, "Fanuc-Style Numbered Programs";
//! interp_read.cc `read_items`/`read_o`, interp_o_word.cc `execute_call`), on by default (INI
//! `DISABLE_FANUC_STYLE_SUB`):
//! - `M98 P<n> [L<count>]`, first in its line after its `N` number, runs the subprogram `O<n>`
//!   (`P0002` is `O2`: both are read as numbers) `L` times, once without `L`, not at all for `L0`;
//!   nothing else of its block is run;
//! - the subprogram starts at a line holding `O<n>` alone (a comment may follow) and ends with `M99`
//!   first in its line; found as an `o<n> sub` is (defined before, a file of the search path, else
//!   forward in the file), and must be of the call's kind;
//! - `#1`-`#30` are not the subprogram's own, as they are an `o-call`'s: the caller's, shared; named
//!   parameters are its own;
//! - an `O<n>` line the program runs into outside a call is a program's title and runs on; `M99`
//!   in the main program ends it in the standalone interpreter, and restarts it in LinuxCNC's task
//!   (read once here, said).

use super::lex::{excerpt, Diags};
use super::oword::{End, Keyword, OLine};
use super::params::skip_blanks;
use super::rs274::Rs274Reader;

/// `M98` or `M99` first in a line (after an optional `N` number; blanks anywhere, as LinuxCNC reads
/// a line without them): which, and the index after its number. LinuxCNC takes the M code's value
/// as a whole number (`M098`, `M98.0`).
pub(crate) fn call_or_return(chars: impl Iterator<Item = char>) -> Option<(Keyword, usize)> {
    let mut it = chars.enumerate().filter(|(_, c)| *c != ' ' && *c != '\t').peekable();
    if it.next_if(|(_, c)| matches!(c, 'n' | 'N')).is_some() {
        while it.next_if(|(_, c)| c.is_ascii_digit() || *c == '.').is_some() {}
    }
    it.next_if(|(_, c)| matches!(c, 'm' | 'M'))?;
    let mut value = 0u32;
    let mut digits = 0;
    let mut end = 0;
    while let Some((i, c)) = it.next_if(|(_, c)| c.is_ascii_digit()) {
        value = value.saturating_mul(10).saturating_add(c.to_digit(10).unwrap_or(0));
        digits += 1;
        end = i + 1;
    }
    if digits == 0 {
        return None;
    }
    if let Some((i, _)) = it.next_if(|(_, c)| *c == '.') {
        end = i + 1;
        while let Some((i, _)) = it.next_if(|(_, c)| *c == '0') {
            end = i + 1;
        }
        if it.peek().is_some_and(|(_, c)| c.is_ascii_digit()) {
            return None;
        }
    }
    match value {
        98 => Some((Keyword::M98, end)),
        99 => Some((Keyword::M99, end)),
        _ => None,
    }
}

/// Whether a line (blanks before it trimmed) may be one the O-word flow reads: an O word, or a
/// Fanuc-style call or return.
pub(crate) fn may_be_flow(text: &str) -> bool {
    text.starts_with(['o', 'O']) || (text.starts_with(['m', 'M', 'n', 'N']) && call_or_return(text.chars()).is_some())
}

/// Whether nothing but blanks and comments stands in `chars` from `i` on.
pub(crate) fn only_comments(chars: &[char], mut i: usize) -> bool {
    loop {
        i = skip_blanks(chars, i);
        match chars.get(i) {
            None | Some(';') => return true,
            Some('(') => match chars[i..].iter().position(|&c| c == ')') {
                Some(k) => i += k + 1,
                None => return false,
            },
            Some(_) => return false,
        }
    }
}

/// Why a construct after `M98 ... L0` (on line `at`) is not read: LinuxCNC 2.9 runs it one call
/// level down, inside the frame the L0 call left, where it fails (a subroutine's definition) or
/// returns to the line after that call (M99).
pub(crate) fn after_l0(what: &str, at: usize) -> String {
    format!("{what} after M98 L0 (line {at}): LinuxCNC 2.9 runs it inside the call level M98 L0 entered and did not leave, where it does not do what it says (interp_o_word.cc execute_call); not read")
}

/// The most times one `M98` may run its subprogram (each pass counts against the read's budget
/// of lines run too).
const MAX_M98_COUNT: f64 = 1e9;

impl Rs274Reader {
    /// `O<n>` alone where the flow runs into it: a program's title (LinuxCNC's convert_control_functions,
    /// "continue executing into Fanuc-style programs w/o skipping"); the program's number if it is
    /// the first.
    pub(super) fn title(&mut self, chars: &[char], o: &OLine) {
        if !self.started && self.number.is_none() {
            let raw: String = chars[..o.rest].iter().filter(|c| !c.is_whitespace()).collect();
            self.number = Some(raw);
        }
        self.started = true;
    }

    /// `M98 P<n> [L<count>]` (`chars` from the line's first character, which stands at 0-based column
    /// `col`; its words from `rest`): subprogram `O<n>` run `L` times.
    pub(super) fn m98(&mut self, chars: &[char], rest: usize, line: usize, col: usize, diags: &mut Diags) -> Result<Option<super::oword_run::SubRun>, End> {
        self.refresh_state(super::rs274::reads_state(chars.iter().copied()));
        let (mut p, mut l): (Option<f64>, Option<(f64, usize)>) = (None, None);
        let mut i = rest;
        loop {
            i = skip_blanks(chars, i);
            let letter = match chars.get(i) {
                None | Some(';') => break,
                Some('(') => match chars[i..].iter().position(|&c| c == ')') {
                    Some(k) => {
                        i += k + 1;
                        continue;
                    }
                    None => return Err(self.stop(line, col + i + 1, "M98: comment '(' is not closed".into(), diags)),
                },
                Some(c) => c.to_ascii_uppercase(),
            };
            if !matches!(letter, 'P' | 'L') {
                let found = excerpt(&chars[i..].iter().collect::<String>());
                return Err(self.stop(line, col + i + 1, format!("M98: only P (the program) and L (how many times) are read in its block, found '{found}': LinuxCNC runs nothing else of an M98 block"), diags));
            }
            if (letter == 'P' && p.is_some()) || (letter == 'L' && l.is_some()) {
                return Err(self.stop(line, col + i + 1, format!("M98: two {letter} words"), diags));
            }
            match self.params.real_value(chars, skip_blanks(chars, i + 1), false) {
                Ok((v, end)) => {
                    if letter == 'P' {
                        p = Some(v);
                    } else {
                        l = Some((v, i));
                    }
                    i = end;
                }
                Err(e) => return Err(self.stop(line, col + e.column, format!("M98 {letter}: {}", e.message), diags)),
            }
        }
        let Some(p) = p else {
            return Err(self.stop(line, col + 1, "M98 without P: expected the number of the program to run (LinuxCNC: \"Found 'm98' code with no P-word\")".into(), diags));
        };
        // P made whole as LinuxCNC's read_o makes it: within 0.0001 below or above a whole number.
        let n = if p - p.floor() > 0.9999 { p.ceil() } else { p.floor() };
        if (p - n).abs() > 1e-4 || !(0.0..=99_999_999.0).contains(&n) {
            return Err(self.stop(line, col + 1, format!("M98 P{p}: expected a program number, a whole number 0 or more"), diags));
        }
        let name = format!("{}", n as u64);
        let count = match l {
            None => 1.0,
            Some((v, _)) if v >= -0.5 && (v - v.round()).abs() <= 1e-4 && v.round() <= MAX_M98_COUNT => v.round(),
            Some((v, at)) => return Err(self.stop(line, col + at + 1, format!("M98 L{v}: expected how many times to run O{name}, a whole number 0 or more"), diags)),
        };
        if count == 0.0 {
            // "M98 L0 instruction; skipping call" (interp_o_word.cc execute_call), after entering a
            // call level it does not leave: what follows runs one level down.
            if self.flow.depth() >= super::oword::MAX_CALL_DEPTH {
                return Err(self.stop(line, col + 1, format!("M98 P{name} L0: calls nested more than {} deep", super::oword::MAX_CALL_DEPTH), diags));
            }
            if self.flow.raised.is_empty() {
                diags.warning(line, col + 1, format!("M98 P{name} L0: O{name} is not run; LinuxCNC 2.9 enters a call level for it and stays there (#<_call_level> reads one more after it), which only a later subroutine definition or M99 in the main program would show (refused)"));
            }
            self.flow.raised.push(line);
            return Ok(None);
        }
        let shown = format!("M98 P{name}");
        let sub = self.find_sub(&name, true, &shown, line, col, diags)?;
        // LinuxCNC runs the M98 block again for each pass: each counts as a line run (the first
        // here, the others as each pass ends: [`super::oword_run`]).
        if !self.spend_line(line, diags) {
            return Err(End::Stopped);
        }
        Ok(Some(super::oword_run::SubRun::new(&name, &shown, sub, None, line, col, count)))
    }
}
