//! The 840D's subprograms as they run: a call by the program's name alone in its block (`NAME`,
//! `NAME(1.5, R2, , 4)`, `L123`), the called program's `PROC` line with its parameters, and its end
//! (`RET`, `M17`). The called program runs at its call, a level below (each level a [`FlowRunner`]
//! over its own file: its jumps find their markers in it), its blocks standing at the call's line
//! and its defects said there, naming its file and place. Rules, from the SINUMERIK NC programming
//! manual 12/2019 (6FC5398-2EP40-0BA0, "NCP19"), the 828D Job Planning 07/2010 (6FC5398-2BP40-0BA0)
//! and the 828D NC-Programmierung 01/2023 (A5E48764001A AE):
//! - A program whose name starts with two letters, `_` and a letter, or a letter and `_` (Siemens'
//!   own cycles' `E_`, `F_`, `S_`), is called by its name alone;
//!   `L` and digits is a name too (NCP19 §3.2.1.2, §3.4.1.3). The language does not tell capitals
//!   from small letters (NCP19 §2.2.1). A name written with `_N_` or `_SPF`/`_MPF` is the same name.
//! - Search path (NCP19 §3.4.1.4): the calling program's directory (`name`, `name_SPF`, `name_MPF`:
//!   on a PC `NAME`, `NAME.SPF`, `NAME.MPF`, `_N_NAME_SPF`, `_N_NAME_MPF`, any case), then the
//!   subprogram and cycle directories (`--subroutine-path`: `NAME.SPF`, `_N_NAME_SPF`), searched
//!   anew for each call.
//! - Parameters: `PROC NAME(REAL X, INT N)` "and a complete list of all the parameters"; "if a
//!   parameter is omitted, the default value 0 is transferred" (NCP19 §3.2.1.5-3.2.1.6). REAL, INT
//!   and BOOL by value are read; `VAR` (by reference) and other types are refused.
//! - Variables: a program's own (`DEF`, its parameters) are its level's; R parameters are the
//!   channel's (their number is channel datum MD28050 `$MC_MM_NUM_R_PARAM`), the same at every
//!   level. The main program's `DEF` variables reach its subprograms only where machine datum
//!   MD11120 makes them program-global (PUD: Job Planning §1.1.5; HMI Advanced manual §5.7.1): a
//!   subprogram reading one is refused, naming that.
//! - Modal state (G codes, frames, feed) carries over both ways: only `SAVE` restores it, and what
//!   it restores depends on machine data (Function Manual K2 §10.5.9: MD10617): `SAVE` is refused.
//! - 16 program levels, the main program's level 0 (NC-Programmierung 01/2023 §4.2.1.3).
//! - `CALL "NAME"` calls a program by its name in quotes, which may start with digits (§3.2.1.2).
//! - The end: `RET` or `M17` returns. `M2`/`M30` in a subprogram, a repetition `P`, `CALL` of a
//!   string variable, `PCALL`, `EXTCALL` and `MCALL` of a subprogram are refused: their pages were
//!   not in reach.

use super::flow::{End, FlowRunner};
use super::lex::{call_arguments, Arg};
use super::vars::{Level, Type};
use crate::program::lex::{excerpt, Diags};
use crate::program::stream::{in_memory, Next, Seeking};
use crate::program::Block;

/// The most program levels: the main program's (0) and 15 below it.
pub(super) const PROGRAM_LEVELS: usize = 16;

/// Blocks a running subprogram hands out at a time before the caller's stream asks again.
const RUN_CHUNK: usize = 1024;

/// The longest program name (NCP19 §3.2.1.2: 24 characters).
const MAX_NAME: usize = 24;

/// A call as written alone in its block: the program's name (capitals), its arguments' text and
/// where both stand (bytes of the line).
#[derive(Debug)]
pub(super) struct CallSite<'a> {
    pub name: String,
    pub at: usize,
    pub args: Option<(&'a str, usize)>,
}

/// A name as called (capitals) without the control's `_N_` prefix and `_SPF`/`_MPF` suffix, and
/// the type the suffix names.
fn base_name(name: &str) -> (&str, Option<&'static str>) {
    let base = name.strip_prefix("_N_").unwrap_or(name);
    match (base.strip_suffix("_SPF"), base.strip_suffix("_MPF")) {
        (Some(b), _) => (b, Some("SPF")),
        (_, Some(b)) => (b, Some("MPF")),
        _ => (base, None),
    }
}

/// Whether `name` (capitals, as called) names a program: without its prefix and suffix, two letters,
/// `_` and a letter, or a letter and `_` first (NCP19 §2.15 "Names": "the first two characters
/// should be letters or underscores", the prefixes `S_`, `E_` and `F_` reserved there for Siemens'
/// own cycles, which are called by name; §3.2.1.2's "two letters or an underscore followed by a
/// letter" would refuse those), or `L` and digits; letters, digits and `_`; at most 24 characters.
fn program_name(name: &str) -> bool {
    let b = base_name(name).0.as_bytes();
    let l_number = b.len() >= 2 && b[0] == b'L' && b[1..].iter().all(u8::is_ascii_digit);
    let letter_or_underscore = |c: u8| c.is_ascii_alphabetic() || c == b'_';
    // Two underscores first is the control's own file name prefix (`_N_`), not a name.
    let named = b.len() >= 2 && letter_or_underscore(b[0]) && letter_or_underscore(b[1]) && !(b[0] == b'_' && b[1] == b'_');
    b.len() <= MAX_NAME && (l_number || named) && b.iter().all(|c| c.is_ascii_alphanumeric() || *c == b'_')
}

/// A name alone in its block from byte `body` on (`NAME`, `NAME(args)`, a comment after it): a
/// call's shape, or `None`. `Some(Err)` where it is one with what is not read (a repetition `P`).
pub(super) fn call_site(text: &str, body: usize) -> Option<Result<CallSite<'_>, (usize, String)>> {
    let b = text.as_bytes();
    if let Some(site) = indirect_call(text, body) {
        return Some(Ok(site));
    }
    let end = (body..b.len()).find(|&k| !(b[k].is_ascii_alphanumeric() || b[k] == b'_')).unwrap_or(b.len());
    // Most lines start with an address and its number (`G1`, `X5`): not a name, seen without a copy.
    let second_letter = b.get(body + 1).is_some_and(|c| c.is_ascii_alphabetic() || *c == b'_');
    if end < body + 2 || !(second_letter || b[body].eq_ignore_ascii_case(&b'L')) {
        return None;
    }
    let name = text[body..end].to_ascii_uppercase();
    if !program_name(&name) || super::is_instruction(&name) {
        return None;
    }
    let mut i = end + b[end..].iter().take_while(|c| c.is_ascii_whitespace()).count();
    let mut args = None;
    if b.get(i) == Some(&b'(') {
        let close = super::lex::arguments_end(text.as_bytes(), i)?;
        args = Some((&text[i + 1..close - 1], i + 1));
        i = close + b[close..].iter().take_while(|c| c.is_ascii_whitespace()).count();
    }
    match b.get(i) {
        None | Some(b';') => Some(Ok(CallSite { name, at: body, args })),
        Some(b'P' | b'p') if b.get(i + 1).is_some_and(|c| c.is_ascii_digit() || *c == b'=' || c.is_ascii_whitespace()) => {
            Some(Err((i, format!("{name} P: a repeated call is not read (the manual's page on P is not in reach)"))))
        }
        _ => None,
    }
}

/// The most bytes of called programs kept between their calls (each file at most the readers'
/// [`crate::program::MAX_HELD_BYTES`]); beyond, a file is read again for each call.
const MAX_KEPT_BYTES: usize = 64 << 20;

/// The most distinct programs whose first call is remembered (beyond, every call's lines count as
/// run again).
const MAX_KNOWN: usize = 10_000;

/// A called program's file: where it was found (for messages) and its bytes.
type ProgramFile = (String, std::sync::Arc<[u8]>);

/// The programs called so far: each file's text, kept for its next calls (the files do not change
/// while the program is read), and which were called before.
#[derive(Debug, Default)]
pub(super) struct Called {
    files: std::collections::HashMap<String, ProgramFile>,
    bytes: usize,
    known: std::collections::HashSet<String>,
}

/// Whether `a` and `b` differ by one letter left out, added or changed.
fn one_edit(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    let (short, long) = if a.len() <= b.len() { (a, b) } else { (b, a) };
    if a == b || long.len() - short.len() > 1 {
        return false;
    }
    // Past the common start (shorter than `short` where the lengths agree, as they differ).
    let head = short.iter().zip(long).take_while(|(x, y)| x == y).count();
    if short.len() == long.len() {
        short[head + 1..] == long[head + 1..]
    } else {
        short[head..] == long[head + 1..]
    }
}

/// `CALL "NAME"` alone in its block: the program named by the text, whose name may start with
/// digits ("if the program name starts with digits, the subprogram call is then only possible via
/// the CALL statement", NCP19 §3.2.1.2). A string variable's name, `CALL BLOCK` and the like are
/// not this.
fn indirect_call(text: &str, body: usize) -> Option<CallSite<'_>> {
    let rest = text.get(body..)?;
    if !rest.get(..4).is_some_and(|k| k.eq_ignore_ascii_case("CALL")) || !rest[4..].starts_with(|c: char| c.is_ascii_whitespace()) {
        return None;
    }
    let quoted = rest[4..].trim_start().strip_prefix('"')?;
    let close = quoted.find('"')?;
    let after = quoted[close + 1..].trim_start();
    let name = quoted[..close].to_ascii_uppercase();
    let base = base_name(&name).0;
    let named = !base.is_empty() && base.len() <= MAX_NAME && base.bytes().all(|c| c.is_ascii_alphanumeric() || c == b'_');
    (named && (after.is_empty() || after.starts_with(';'))).then_some(CallSite { name, at: body, args: None })
}

/// A subprogram running below its caller: its own flow over its file, where its call stands, and
/// the caller's variables set aside.
pub(super) struct SubRun {
    run: Seeking<'static, FlowRunner>,
    /// The call's line and 1-based column.
    call: (usize, usize),
    /// Its file, as found (for messages).
    shown: String,
    caller: Level,
    /// The caller's element a corner waited on, out as programmed before the subprogram's blocks.
    released: Vec<Block>,
}

/// The file names a call of `name` looks for: in the calling program's directory, then in the
/// subprogram directories (NCP19 §3.4.1.4).
fn file_names(name: &str) -> (Vec<String>, Vec<String>) {
    let (base, kind) = base_name(name);
    let typed = |k: &str| [format!("{base}.{k}"), format!("_N_{base}_{k}")];
    let own = match kind {
        Some(k) => typed(k).to_vec(),
        None => std::iter::once(base.to_string()).chain(typed("SPF")).chain(typed("MPF")).collect(),
    };
    let dirs = if kind == Some("MPF") { Vec::new() } else { typed("SPF").to_vec() };
    (own, dirs)
}

/// What a subprogram call refused for what is not read in it is, which leaves every axis unknown.
pub(super) const CALL_NOT_READ: &str = "a subprogram call not read, which the control runs";

impl FlowRunner {
    /// Call the subprogram `site` names at `line`: found, its first part run now; the rest as the
    /// stream asks ([`FlowRunner::sub_more`]).
    pub(super) fn call(&mut self, site: CallSite<'_>, text: &str, line: usize, diags: &mut Diags) -> Next {
        let cols = crate::program::lex::Columns::new(text);
        let col = cols.col(site.at);
        let name = &site.name;
        if self.level + 1 >= PROGRAM_LEVELS {
            return crate::program::stream::stop(line, col, format!("{name}: calls nested deeper than the control's {PROGRAM_LEVELS} program levels"), diags);
        }
        // The actual parameters, in the caller's variables: an empty one is 0.
        let args = match site.args.filter(|(t, _)| !t.trim().is_empty()).map(|(t, at)| call_arguments(t, &mut self.reader.vars).map_err(|(k, why)| (at + k, why))).transpose() {
            Ok(a) => a.unwrap_or_default(),
            Err((k, why)) => {
                diags.error(line, cols.col(k), format!("{name}: {why}"));
                self.reader.interp.moved_everywhere(line, name, CALL_NOT_READ);
                self.reader.tangent = None;
                return Next::On;
            }
        };
        let mut values = Vec::with_capacity(args.len());
        for a in &args {
            match a {
                Arg::Empty => values.push(0.0),
                Arg::Value(v) => values.push(*v),
                Arg::Text(t) => {
                    diags.error(line, col, format!("{name}: the text parameter \"{}\" is not read", excerpt(t)));
                    self.reader.interp.moved_everywhere(line, name, CALL_NOT_READ);
                    self.reader.tangent = None;
                    return Next::On;
                }
            }
        }
        let (shown, bytes) = match self.find(name) {
            Ok(Some(f)) => f,
            Ok(None) => {
                let (base, kind) = base_name(name);
                // A keyword mistyped is read as a call too: say which one it is a letter from.
                let like = super::READ_KEYWORDS.iter().filter(|k| k.len() >= 5).find(|k| one_edit(k, base)).map_or(String::new(), |k| format!(" (or is it {k}, mistyped?)"));
                diags.error(line, col, format!("{name}: a call of the subprogram {base}, whose file ({base}.{}) is neither beside the program nor in a directory of --subroutine-path: the motion depends on it{like}", kind.unwrap_or("SPF")));
                self.reader.interp.moved_everywhere(line, name, "a subprogram not found, which the control runs");
                self.reader.tangent = None;
                return Next::On;
            }
            Err(why) => {
                diags.error(line, col, format!("{name}: {why}"));
                self.reader.interp.moved_everywhere(line, name, "a subprogram not read, which the control runs");
                self.reader.tangent = None;
                return Next::On;
            }
        };
        // A program's lines count as the program's own at its first call, as run again after.
        let base = base_name(name).0.to_string();
        let first = !self.called_files.known.contains(&base) && self.called_files.known.len() < MAX_KNOWN;
        if first {
            self.called_files.known.insert(base);
        }
        // A corner waiting for the element after it: the call leaves the caller's block sequence.
        let mut released = Vec::new();
        self.reader.corner_interrupt("a subprogram is called before the element after it", line, col, &mut released, diags);
        if self.reader.stopped {
            // Compensation stopped the program as the held blocks went out: the call does not run
            // (the blocks it placed before the stop are the stop's, dropped with it).
            return Next::Ended;
        }
        let reader = std::mem::replace(&mut self.reader, super::SinumerikReader::new(&self.setup));
        let mut child = FlowRunner::below(self, reader, name, values, !first);
        child.called_files = std::mem::take(&mut self.called_files);
        child.reader.interp.refused_line = None;
        child.reader.interp.refused_feed_line = None;
        let caller = child.reader.vars.enter_level();
        self.sub = Some(Box::new(SubRun { run: Seeking::new(in_memory(bytes), Box::new(child)), call: (line, col), shown, caller, released }));
        Next::Run
    }

    /// The file of the program `name`: kept from an earlier call, else looked for as the search
    /// path says (and kept, within [`MAX_KEPT_BYTES`]).
    fn find(&mut self, name: &str) -> Result<Option<ProgramFile>, String> {
        let base = base_name(name).0.to_string();
        if let Some((shown, bytes)) = self.called_files.files.get(&base) {
            return Ok(Some((shown.clone(), bytes.clone())));
        }
        let Some(files) = &self.setup.subroutine_files else { return Ok(None) };
        let (own, dirs) = file_names(name);
        let found = match files.find_file(&own, true, true)? {
            Some(f) => Some(f),
            None if dirs.is_empty() => None,
            None => files.find_file(&dirs, true, false)?,
        };
        Ok(found.map(|(shown, bytes)| {
            let bytes: std::sync::Arc<[u8]> = bytes.into();
            if self.called_files.bytes + bytes.len() <= MAX_KEPT_BYTES {
                self.called_files.bytes += bytes.len();
                self.called_files.files.insert(base, (shown.clone(), bytes.clone()));
            }
            (shown, bytes)
        }))
    }

    /// The running subprogram's next part: its blocks at the call's line, its diagnostics said
    /// there; `None` when none runs. As it ends the caller's reader and variables come back, and
    /// the caller goes on (`Next::On`) or ends with it (`Next::Ended`: it stopped at a defect).
    pub(super) fn sub_more(&mut self, out: &mut Vec<Block>, diags: &mut Diags) -> Option<Next> {
        let sub = self.sub.as_mut()?;
        let goal = out.len() + RUN_CHUNK;
        let (line, col) = sub.call;
        out.append(&mut sub.released);
        loop {
            let before = out.len();
            let mut d = Diags::default();
            let done = sub.run.fill(out, &mut d);
            for b in &mut out[before..] {
                (b.line, b.column) = (line, col);
            }
            for x in d.0 {
                let message = format!("in {}:{}:{}: {}", sub.shown, x.line, x.column, x.message);
                match x.severity {
                    crate::program::Severity::Error => diags.error(line, col, message),
                    _ => diags.warning(line, col, message),
                }
            }
            // Its run over (RET, M17, a stop), the rest of its file is not read.
            if done || !sub.run.running() {
                break;
            }
            if out.len() >= goal {
                return Some(Next::On);
            }
        }
        let sub = self.sub.take()?;
        let SubRun { run, caller, shown, .. } = *sub;
        let mut child = run.runner;
        // RET with a corner waiting in the subprogram: its element out, at the call's line.
        let (before, mut d) = (out.len(), Diags::default());
        child.reader.corner_interrupt("its subprogram returns before the element after it", child.reached.max(1), 1, out, &mut d);
        for b in &mut out[before..] {
            (b.line, b.column) = (line, col);
        }
        for x in d.0 {
            diags.error(line, col, format!("in {}:{}:{}: {}", shown, x.line, x.column, x.message));
        }
        // Compensation stopped the program as the held blocks went out: nothing after runs.
        let stopped = child.reader.stopped;
        self.again = self.again.saturating_add(child.again);
        self.called_files = std::mem::take(&mut child.called_files);
        let mut reader = std::mem::replace(&mut child.reader, super::SinumerikReader::new(&self.setup));
        reader.vars.leave_level(caller);
        reader.interp.refused_line = None;
        reader.interp.refused_feed_line = None;
        self.reader = reader;
        Some(if child.end == End::Returned && !stopped { Next::On } else { Next::Ended })
    }

    /// A `PROC` line (`text[after..]` past the keyword): the program's parameters, given the
    /// caller's values (at the main level, none: a parameter read is refused as read before set).
    pub(super) fn proc_line(&mut self, text: &str, after: usize, line: usize, col: usize, diags: &mut Diags) -> Next {
        if self.begun {
            return crate::program::stream::stop(line, col, "PROC stands in the program's first line".into(), diags);
        }
        self.begun = true;
        let cols = crate::program::lex::Columns::new(text);
        let body = text[after..].split(';').next().unwrap_or("");
        let start = after + body.len() - body.trim_start().len();
        let b = text.as_bytes();
        let end = (start..after + body.len()).find(|&k| !(b[k].is_ascii_alphanumeric() || b[k] == b'_')).unwrap_or(after + body.len());
        let name = text[start..end].to_ascii_uppercase();
        // A name may start with digits where CALL "NAME" calls it (NCP19 §3.2.1.2).
        let base = base_name(&name).0;
        if base.is_empty() || base.len() > MAX_NAME {
            return crate::program::stream::stop(line, cols.col(start), format!("PROC: expected the program's name, found '{}'", excerpt(&text[start..after + body.len()])), diags);
        }
        if let Some(called) = &self.called {
            let base = |n: &str| n.strip_prefix("_N_").unwrap_or(n).trim_end_matches("_SPF").trim_end_matches("_MPF").to_string();
            if base(called) != base(&name) {
                return crate::program::stream::stop(line, cols.col(start), format!("PROC {name} in the file of {called}: a file's name and its program's are the same (NC-Programmierung 01/2023 §4.2.1.2)"), diags);
            }
        }
        let mut rest = end + b[end..after + body.len()].iter().take_while(|c| c.is_ascii_whitespace()).count();
        let mut formals: Vec<(String, Type, usize)> = Vec::new();
        if b.get(rest) == Some(&b'(') {
            let Some(close) = super::lex::arguments_end(text.as_bytes(), rest) else {
                return crate::program::stream::stop(line, cols.col(rest), "PROC: '(' is not closed".into(), diags);
            };
            let mut at = rest + 1;
            for piece in text[rest + 1..close - 1].split(',') {
                let here = at + piece.len() - piece.trim_start().len();
                at += piece.len() + 1;
                if piece.trim().is_empty() && formals.is_empty() && text[rest + 1..close - 1].trim().is_empty() {
                    break;
                }
                match formal(piece.trim()) {
                    Ok((n, ty)) => formals.push((n, ty, here)),
                    Err(why) => return crate::program::stream::stop(line, cols.col(here), format!("PROC {name}: {why}"), diags),
                }
            }
            rest = close;
        }
        for word in text[rest..after + body.len()].split_whitespace() {
            match word.to_ascii_uppercase().as_str() {
                // Display and single-block attributes: what the HMI shows, not the motion.
                "DISPLOF" | "DISPLON" | "SBLOF" | "SBLON" => {}
                "SAVE" => return crate::program::stream::stop(line, col, format!("PROC {name} SAVE: what the return restores (modal G codes, frames) depends on machine data (MD10617), not read"), diags),
                other => return crate::program::stream::stop(line, col, format!("PROC {name}: unexpected '{}' after the parameters", excerpt(other)), diags),
            }
        }
        let args = self.args.take();
        if let Some(a) = &args {
            if a.len() > formals.len() {
                return crate::program::stream::stop(line, col, format!("PROC {name} has {} parameter(s); its call gives {}", formals.len(), a.len()), diags);
            }
        }
        for (k, (n, ty, here)) in formals.iter().enumerate() {
            // Not given: 0 (NCP19 §3.2.1.6); at the main level none has a value.
            let value = args.as_ref().map(|a| a.get(k).copied().unwrap_or(0.0));
            if let Err(why) = self.reader.vars.parameter(n, *ty, value) {
                self.reader.vars.rollback();
                return crate::program::stream::stop(line, cols.col(*here), format!("PROC {name}: {why}"), diags);
            }
        }
        self.reader.vars.commit();
        Next::On
    }
}

/// A formal parameter `REAL X`: its name (capitals) and type, or why it is not read.
fn formal(text: &str) -> Result<(String, Type), String> {
    let mut words = text.split_whitespace();
    let (first, second, more) = (words.next().unwrap_or(""), words.next(), words.next());
    if first.eq_ignore_ascii_case("VAR") {
        return Err(format!("'{}': a parameter by reference (VAR) is not read", excerpt(text)));
    }
    let ty = match first.to_ascii_uppercase().as_str() {
        "REAL" => Type::Real,
        "INT" => Type::Int,
        "BOOL" => Type::Bool,
        _ => return Err(format!("'{}': only REAL, INT and BOOL parameters are read", excerpt(text))),
    };
    match (second, more) {
        (Some(n), None) if n.len() >= 2 && n.bytes().all(|c| c.is_ascii_alphanumeric() || c == b'_') && !n.as_bytes()[0].is_ascii_digit() => Ok((n.to_ascii_uppercase(), ty)),
        (Some(n), None) if n.len() == 1 => Err(format!("'{}': a variable's name has two characters or more here (a letter alone is an address)", excerpt(text))),
        _ => Err(format!("'{}': expected a type and a name (arrays are not read)", excerpt(text))),
    }
}

#[cfg(test)]
mod tests {
    use crate::program::{read, Dialect, Program, ReadOptions, Severity, SubroutineFiles};
    use std::sync::Arc;

    /// Programs beside the calling one (the program's own directory), by file name, any case.
    #[derive(Debug)]
    struct Beside(Vec<(&'static str, String)>);

    impl SubroutineFiles for Beside {
        fn find_file(&self, names: &[String], any_case: bool, own_dir: bool) -> Result<Option<(String, Vec<u8>)>, String> {
            assert!(any_case);
            if !own_dir {
                return Ok(None);
            }
            Ok(names.iter().find_map(|n| self.0.iter().find(|(f, _)| f.eq_ignore_ascii_case(n))).map(|(f, t)| (f.to_string(), t.as_bytes().to_vec())))
        }
    }

    fn run(main: &str, files: &[(&'static str, &str)]) -> Program {
        let files = Beside(files.iter().map(|(f, t)| (*f, t.to_string())).collect());
        read(main, Dialect::Sinumerik, "MAIN.MPF", &ReadOptions { subroutine_files: Some(Arc::new(files)), ..ReadOptions::default() })
    }

    /// Each block that moves: its line and X Y Z (mm, NaN where not named).
    fn moves(p: &Program) -> Vec<(usize, [f64; 3])> {
        p.blocks.iter().filter(|b| b.targets.x.is_some() || b.targets.y.is_some() || b.targets.z.is_some()).map(|b| (b.line, [b.targets.x, b.targets.y, b.targets.z].map(|v| v.map_or(f64::NAN, |v| (v * 1e3 * 1e9).round() / 1e9)))).collect()
    }

    fn errors(p: &Program) -> Vec<String> {
        p.messages(Severity::Error)
    }

    /// NCP19 §3.2.1.5-3.2.1.6's calls: `CONTOUR(5.5, WIDTH)` passes a value and a variable; a
    /// parameter left out (`SUB_PROG(1, , 3)`) is 0; `L12` is a program without parameters, and
    /// `CALL "12_HOLE"` one whose name starts with digits (§3.2.1.2). Its
    /// moves stand at the call's line; an R parameter it sets is the caller's after it returns.
    #[test]
    fn calls_pass_their_values_and_return() {
        let main = "N10 DEF REAL WIDTH=3\nN20 G90 G71 G94 F500\nN30 CONTOUR(5.5, WIDTH) ; comment\nN40 G1 X=R1\nN50 SUB_PROG(1, , 3)\nN60 L12()\nN65 CALL \"12_HOLE\" ; digits first\nN70 M30\n";
        let contour = "PROC CONTOUR(REAL LENGTH, REAL BREADTH) DISPLOF\nDEF REAL HALF\nHALF = BREADTH/2\nG1 X=LENGTH Y=HALF\nR1 = LENGTH*2\nN100 RET\n";
        let sub = "%_N_SUB_PROG_SPF\n; three values\nPROC SUB_PROG (REAL XA, REAL YA, REAL ZA)\nG1 X=XA Y=YA Z=ZA\nM17\n";
        let p = run(main, &[("contour.spf", contour), ("SUB_PROG.SPF", sub), ("L12.SPF", "G1 X7 Y7\nM17\n"), ("12_hole.spf", "PROC 12_HOLE\nG1 Z-2\nM17\n")]);
        assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
        let nan = f64::NAN;
        let m = moves(&p);
        let want = [(3, [5.5, 1.5, nan]), (4, [11.0, nan, nan]), (5, [1.0, 0.0, 3.0]), (6, [7.0, 7.0, nan]), (7, [nan, nan, -2.0])];
        assert_eq!(m.len(), want.len(), "{m:?}");
        for ((l, xyz), (wl, wxyz)) in m.iter().zip(want) {
            assert_eq!(*l, wl);
            for (a, b) in xyz.iter().zip(wxyz) {
                assert!(a == &b || (a.is_nan() && b.is_nan()), "line {l}: {xyz:?}, expected {wxyz:?}");
            }
        }
    }

    /// Names with a letter and an underscore first (`F_TEST`, `E_TEST(..)`: the prefixes NCP19 §2.15
    /// reserves for Siemens' cycles) are calls: their moves stand at the call's line, X20 Y5 from
    /// F_TEST and Z-2.5 from E_TEST's parameter.
    #[test]
    fn a_letter_and_an_underscore_first_name_a_program() {
        let main = "G90 G71 F500\nF_TEST\nE_TEST(-2.5)\nM30\n";
        let p = run(main, &[("F_TEST.SPF", "PROC F_TEST\nG1 X20 Y5\nRET\n"), ("E_TEST.SPF", "PROC E_TEST(REAL DEPTH)\nG1 Z=DEPTH\nRET\n")]);
        assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
        let got: Vec<String> = moves(&p).iter().map(|(l, v)| format!("{l}:{:?}", v.map(|c| if c.is_nan() { None } else { Some(c) }))).collect();
        assert_eq!(got, ["2:[Some(20.0), Some(5.0), None]", "3:[None, None, Some(-2.5)]"]);
        assert!(super::program_name("S_CYCLE") && super::program_name("_AB") && !super::program_name("__AB") && !super::program_name("1A"));
    }

    /// A subprogram's own flow: its loop, its jump to a marker that the main program has too (each
    /// program's jumps find their own), a variable of the same name as the caller's (each level has
    /// its own), and a call of another subprogram inside it.
    #[test]
    fn each_level_has_its_own_variables_and_markers() {
        let main = "DEF INT COUNT=7\nG90 G71 F500\nHOLES(3)\nG1 Z=COUNT\nGOTOF DONE\nG1 Z99\nDONE:\nM30\n";
        let holes = "PROC HOLES(INT NUMBER)\nDEF INT COUNT\nFOR COUNT=1 TO NUMBER\nG1 X=COUNT*10\nENDFOR\nGOTOF DONE\nG1 X99\nDONE: PECK\nRET\n";
        let p = run(main, &[("HOLES.SPF", holes), ("PECK.SPF", "G1 Z-5\nG1 Z1\nRET\n")]);
        assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
        let xz: Vec<(usize, f64, f64)> = moves(&p).iter().map(|(l, v)| (*l, v[0], v[2])).collect();
        let got: Vec<String> = xz.iter().map(|(l, x, z)| format!("{l}:{x}:{z}")).collect();
        assert_eq!(got, ["3:10:NaN", "3:20:NaN", "3:30:NaN", "3:NaN:-5", "3:NaN:1", "4:NaN:7"]);
    }

    /// What is not read is refused where it stands: a repeated call, a VAR parameter, SAVE, M30 in a
    /// subprogram, parameters given to a program without PROC, more values than parameters, a PROC
    /// naming another program, a program not found, a defect inside the called file (said at the
    /// call, naming the file and its place), and a main program's variable read in a subprogram.
    #[test]
    fn what_is_not_read_is_refused_at_its_place() {
        let files: Vec<(&'static str, String)> = vec![
            ("BYREF.SPF", "PROC BYREF(VAR REAL LENGTH)\nRET\n".into()),
            ("SAVED.SPF", "PROC SAVED(REAL LENGTH) SAVE\nRET\n".into()),
            ("ENDS.SPF", "G1 X1\nM30\n".into()),
            ("PLAIN.SPF", "G1 X1\nM17\n".into()),
            ("TWO.SPF", "PROC TWO(REAL AA, REAL BB)\nRET\n".into()),
            ("OTHER.SPF", "PROC ANOTHER\nRET\n".into()),
            ("BAD.SPF", "G1 X1\nG1 X=NOPE\nRET\n".into()),
            ("SEES.SPF", "G1 X=WIDTH\nRET\n".into()),
            ("MIDDLE.SPF", "DEF REAL DEPTH=1\nSEES_MIDDLE\nRET\n".into()),
            ("SEES_MIDDLE.SPF", "G1 Z=DEPTH\nRET\n".into()),
            ("SHORT.SPF", "PROC SHORT(REAL X)\nRET\n".into()),
            ("MAIN_TWO.MPF", "G0 Z100 M30\n".into()),
            ("EMPTY.SPF", "; nothing\n".into()),
        ];
        let cases = [
            ("PLAIN P3", "PLAIN P: a repeated call is not read"),
            ("BYREF(1)", "by reference (VAR) is not read"),
            ("SAVED(1)", "SAVE: what the return restores"),
            ("ENDS", "M2 or M30 in a subprogram"),
            ("PLAIN(1)", "PLAIN is called with parameters, but its program has no PROC line first"),
            ("TWO(1, 2, 3)", "PROC TWO has 2 parameter(s); its call gives 3"),
            ("OTHER", "PROC ANOTHER in the file of OTHER"),
            ("NOWHERE", "NOWHERE: a call of the subprogram NOWHERE, whose file (NOWHERE.SPF) is neither beside the program"),
            ("BAD", "in BAD.SPF:2:6: X=NOPE: NOPE is not defined"),
            ("SEES", "WIDTH is not defined (DEF) in this subprogram: the main program's variable"),
            ("MIDDLE", "DEPTH is not defined (DEF) in this subprogram: a calling subprogram's own variable"),
            ("SHORT(1)", "'REAL X': a variable's name has two characters or more here"),
            ("MAIN_TWO", "M2 or M30 in a subprogram"),
            ("EMPTY(1)", "EMPTY is called with parameters, but its program has no PROC line first"),
        ];
        for (call, why) in cases {
            let p = run(&format!("DEF REAL WIDTH=2\nG90 G71 F100\n{call}\nM30\n"), &files.iter().map(|(f, t)| (*f, t.as_str())).collect::<Vec<_>>());
            let e = errors(&p);
            assert!(e.iter().any(|m| m.starts_with(if call.contains(" P") { "3:7: " } else { "3:1: " }) && m.contains(why)), "{call}: {e:#?}");
            // A refused line's moves are not used (the main program's M30 block called).
            assert!(p.blocks.iter().all(|b| b.targets.z.is_none()), "{call}");
        }
    }

    /// What Autodesk's SINUMERIK 840D post writes with "Use files for subroutines" (siemens-840d.cps,
    /// `subprogramCall`/`subprogramEnd`): `N15 subPART1 ; SPF CALL` in the main program, and a file
    /// `subPART1.spf` whose first line is `; %_N_SUBPART1_SPF` and last `M17`. Without that option it
    /// writes `CALL BLOCK LABEL1 TO LABEL0`, refused once for its block.
    #[test]
    fn autodesk_posts_subprogram_files_read() {
        let main = "; %_N_PART_MPF\nN10 G90 G71 G94 F600\nN15 subPART1 ; SPF CALL\nN20 CALL BLOCK LABEL1 TO LABEL0\nN25 M30\n";
        let sub = "; %_N_SUBPART1_SPF\nG0 X10 Y20\nG1 Z-1\nG0 Z5\nM17\n";
        let p = run(main, &[("subPART1.spf", sub)]);
        assert_eq!(errors(&p), ["4:5: CALL: a program section call (CALL BLOCK .. TO ..) is not read: its manual page is not in reach"]);
        let got: Vec<String> = moves(&p).iter().map(|(l, v)| format!("{l}:{:?}", v.map(|c| if c.is_nan() { None } else { Some(c) }))).collect();
        assert_eq!(got, ["3:[Some(10.0), Some(20.0), None]", "3:[None, None, Some(-1.0)]", "3:[None, None, Some(5.0)]"]);
    }

    /// A keyword a letter from one the reader knows is still a call (the control's rule), and its
    /// refusal asks whether it is that keyword mistyped (NX's Cincinnati post writes TRAOOF).
    #[test]
    fn a_mistyped_keyword_is_named() {
        let e = errors(&run("G90 G71\nTRAOOF\nTRAORIX\nTRAFO\nM30\n", &[]));
        assert!(e[0].starts_with("2:1: TRAOOF: a call of the subprogram TRAOOF") && e[0].ends_with("(or is it TRAFOOF, mistyped?)"), "{e:#?}");
        assert!(e[1].ends_with("(or is it TRAORI, mistyped?)"), "{e:#?}");
        assert!(e[2].ends_with("the motion depends on it"), "{e:#?}");
        assert!(super::one_edit("ROT", "AROT") && super::one_edit("SUPA", "SUPB") && !super::one_edit("SUPA", "SUPA") && !super::one_edit("ROT", "TRANS"));
    }

    /// A subprogram read alone: its PROC's parameters have no value, and a read of one says so.
    #[test]
    fn a_subprogram_read_alone_asks_for_its_caller() {
        let p = run("PROC EDGE(REAL LENGTH)\nG90 G71 G1 X=LENGTH F100\nRET\n", &[]);
        assert_eq!(errors(&p), ["2:14: X=LENGTH: LENGTH is a parameter of the program's PROC, which its call gives: this program is a subprogram (read the program that calls it) (at 'LENGTH')"]);
    }

    /// A program calling itself stops at the control's 16 program levels, the main program's the
    /// first: the 15th call's own call is refused, said inside each of the 15.
    #[test]
    fn calls_nest_no_deeper_than_sixteen_levels() {
        let p = run("G90 G71 F100\nDEEPER\nM30\n", &[("DEEPER.SPF", "G91 G1 X1\nDEEPER\nRET\n")]);
        let e = errors(&p);
        assert_eq!(e.len(), 1, "{e:#?}");
        assert_eq!(e[0].matches("in DEEPER.SPF:2:1: ").count(), 15, "{e:#?}");
        assert!(e[0].ends_with("DEEPER: calls nested deeper than the control's 16 program levels (the rest of the program is not read)"), "{e:#?}");
        assert_eq!(moves(&p).len(), 15);
    }

    /// A program's lines count as the program's own at its first call, as run again at the next:
    /// a subprogram of 300 moves called once reads within a budget of 100 lines run again, called
    /// twice it does not. After its RET the rest of its file is not read (200,000 comment lines, 500
    /// calls: quick).
    #[test]
    fn a_programs_first_call_is_its_own_lines() {
        let long: String = (1..=300).map(|k| format!("G1 X{k}\n")).chain(std::iter::once("RET\n".to_string())).collect();
        let files = |text: &str| Beside(vec![("LONG.SPF", text.to_string())]);
        let options = |text: &str| ReadOptions { subroutine_files: Some(Arc::new(files(text))), max_run_lines: 100, ..ReadOptions::default() };
        let once = read("G90 G71 F100\nLONG\nM30\n", Dialect::Sinumerik, "t.mpf", &options(&long));
        assert!(errors(&once).is_empty(), "{:?}", errors(&once));
        assert_eq!(moves(&once).len(), 300);
        let twice = read("G90 G71 F100\nLONG\nLONG\nM30\n", Dialect::Sinumerik, "t.mpf", &options(&long));
        assert!(errors(&twice).iter().any(|e| e.contains("more than 100 lines run by loops, jumps and calls")), "{:?}", errors(&twice));
        let after: String = std::iter::once("G91 G1 X1\nRET\n".to_string()).chain((0..200_000).map(|_| "; after\n".to_string())).collect();
        let options = ReadOptions { subroutine_files: Some(Arc::new(files(&after))), ..ReadOptions::default() };
        let p = read("G90 G71 F100\nDEF INT KK\nFOR KK=1 TO 500\nLONG\nENDFOR\nM30\n", Dialect::Sinumerik, "t.mpf", &options);
        assert!(errors(&p).is_empty(), "{:?}", errors(&p));
        assert_eq!(moves(&p).len(), 500);
    }

    /// A subprogram's long loop reaches the caller's stream a part at a time, all of its moves and
    /// then the caller's next line.
    #[test]
    fn a_long_subprogram_streams_its_moves() {
        let text = "G90 G71 F1000\nZIGZAG(30000)\nG1 Z5\nM30\n";
        let zigzag = "PROC ZIGZAG(INT PASSES)\nDEF INT PASS_NO\nFOR PASS_NO=1 TO PASSES\nG1 X=PASS_NO\nENDFOR\nRET\n";
        let files = Beside(vec![("ZIGZAG.SPF", zigzag.into())]);
        let options = ReadOptions { subroutine_files: Some(Arc::new(files)), ..ReadOptions::default() };
        let mut s = crate::program::BlockStream::from_text(text, Some(Dialect::Sinumerik), "t.mpf", &options);
        let (mut n, mut last_x, mut z_after) = (0usize, 0.0, false);
        for b in s.by_ref() {
            if let Some(x) = b.targets.x {
                assert!(!z_after);
                n += 1;
                last_x = x;
            }
            z_after |= b.targets.z.is_some();
        }
        assert_eq!(s.diagnostics().errors(), 0, "{:?}", s.diagnostics().to_vec());
        assert_eq!((n, (last_x * 1e3).round(), z_after), (30000, 30000.0, true));
    }
}
