//! The 840D's program control as it runs (Job Planning 6FC5398-2BP20, "Flexible NC programming":
//! "Program jumps to jump markers", "Program branches", "Control structures"). Every other line is
//! the block reader's ([`SinumerikReader`]).
//!
//! Rules:
//! - Jump markers: `NAME:` at a block's start (after its `N` number), a name whose "first two
//!   characters must be letters or underscores" (Programming Manual Fundamentals 6FC5298-7AB00-0BP1
//!   10.2004 §2.2, identifiers and jump markers); a jump goes to a marker or to a
//!   block number (`N100`). `GOTOF` looks forward, `GOTOB` backward, `GOTO` both, `GOTOC` as `GOTO`
//!   without an alarm when the marker is missing (the block after it runs); `IF <condition> GOTOF ..`
//!   jumps when the condition holds. A marker written twice is refused (the manual: "must be unique").
//!   A block skip `/` before the block number and marker leaves both found: the skip is not modelled
//!   (the block runs, with a warning), so a block that has one is a jump's destination as any other.
//! - Control structures: `IF` ... `ELSE` ... `ENDIF`, `WHILE` ... `ENDWHILE`, `FOR var = a TO b` ...
//!   `ENDFOR` (the variable counts up by 1), `LOOP` ... `ENDLOOP`, `REPEAT` ... `UNTIL`. A jump leaves
//!   the structures open around it (a jump into one, or within one, is refused at its end).
//! - The program ends at `M30`, `M2` or `M17`; loops and jumps run at most the program's lines and
//!   `max_run_lines` more (an endless loop is refused at the line it had reached; a subprogram's
//!   lines all count). Section repeats (`REPEAT marker P=n`, `REPEATB`) are refused.
//! - Subprograms: a name alone in its block calls the program of that name, which runs a level
//!   below in a runner of its own ([`super::subprogram`]); `PROC` and `RET` are its lines.

use super::SinumerikReader;
use crate::program::lex::{block_number, past_skip, Diags};
use crate::program::stream::{ends_program, stop, At, Find, Jumping, LineReader, Next, Places};
use crate::program::Block;

/// Deepest nesting of control structures (the 840D's: 16 per level).
const MAX_NESTING: usize = 16;

/// A control structure running, and where it goes back to.
#[derive(Debug, Clone)]
enum Open {
    If,
    Else,
    While(At),
    For { var: String, end: f64, body: At },
    Loop(At),
    Repeat(At),
}

impl Open {
    fn name(&self) -> &'static str {
        match self {
            Open::If | Open::Else => "IF",
            Open::While(_) => "WHILE",
            Open::For { .. } => "FOR",
            Open::Loop(_) => "LOOP",
            Open::Repeat(_) => "REPEAT",
        }
    }
}

/// Lines passed over to a structure's end: which keywords close what is skipped, how deep.
#[derive(Debug, Clone, Copy)]
struct Skip {
    open: &'static str,
    close: &'static str,
    /// An `ELSE` at depth 0 ends it too (an IF whose condition failed).
    at_else: bool,
    depth: usize,
    line: usize,
}

/// A jump's direction.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Way {
    Forward,
    Back,
    Either,
    /// GOTOC: either way, no alarm when the marker is missing.
    Quiet,
}

/// How a program level's run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum End {
    /// At a defect, or at the program's end (`M30`): its caller ends too.
    Stopped,
    /// `RET` or `M17`, or its file's end: its caller goes on.
    Returned,
}

/// A Sinumerik program run as the control runs it, line by line; a subprogram it calls runs in a
/// runner of its own, a level below ([`super::subprogram`]).
pub(crate) struct FlowRunner {
    pub(super) reader: SinumerikReader,
    /// The furthest line reached: a line at or before it runs again, and counts against `budget`.
    pub(super) reached: usize,
    budget: usize,
    /// Lines run beyond the program's own (at a subprogram's level, every line run).
    pub(super) again: usize,
    /// The program level (the main program's 0).
    pub(super) level: usize,
    pub(super) setup: crate::program::Setup,
    /// The subprogram a call of this level runs.
    pub(super) sub: Option<Box<super::subprogram::SubRun>>,
    /// The name this level was called by, and its call's values for its PROC's parameters.
    pub(super) called: Option<String>,
    pub(super) args: Option<Vec<f64>>,
    /// A statement has run (a PROC comes first).
    pub(super) begun: bool,
    /// Every line run counts against the budget (a program called before: its lines are not the
    /// program's own again).
    count_all: bool,
    /// The programs called so far (their files kept for the next calls), handed down to the level
    /// that runs and back.
    pub(super) called_files: super::subprogram::Called,
    pub(super) end: End,
    open: Vec<Open>,
    skipping: Option<Skip>,
    /// The jump being looked for: its marker (capitals, or `N` and digits), way, line and column, and
    /// where it stands.
    wanted: Option<(String, Way, usize, usize, At)>,
    /// Where each target searched before stands.
    places: Places<String>,
}

impl FlowRunner {
    pub(crate) fn new(setup: &crate::program::Setup) -> Self {
        FlowRunner {
            reader: SinumerikReader::new(setup),
            reached: 0,
            budget: setup.max_run_lines,
            again: 0,
            level: 0,
            setup: setup.clone(),
            sub: None,
            called: None,
            args: None,
            begun: false,
            count_all: false,
            called_files: Default::default(),
            end: End::Stopped,
            open: Vec::new(),
            skipping: None,
            wanted: None,
            places: Places::new(),
        }
    }

    /// The runner of a subprogram `parent` calls by `name` with `args`, on the caller's `reader`:
    /// the lines it may run are what `parent` has left, its every line counting where `count_all`.
    pub(super) fn below(parent: &FlowRunner, reader: SinumerikReader, name: &str, args: Vec<f64>, count_all: bool) -> FlowRunner {
        FlowRunner {
            reader,
            budget: parent.budget.saturating_sub(parent.again),
            count_all,
            level: parent.level + 1,
            called: Some(name.to_string()),
            args: Some(args),
            ..FlowRunner::new(&parent.setup)
        }
    }

    fn condition(&mut self, text: &str) -> Result<bool, String> {
        let text = text.split(';').next().unwrap_or("").trim();
        if text.is_empty() {
            return Err("expected a condition".into());
        }
        self.reader.vars.eval(text).map(|v| v != 0.0).map_err(|e| e.message)
    }
}

/// The most digits of a block number a jump looks for.
const MAX_N_DIGITS: usize = 18;

/// A line split: where its block starts (past blanks, a block skip `/` and its `N` number), its jump
/// marker (capitals) and where the block after the marker starts.
fn split(text: &str) -> (usize, Option<(String, usize)>, usize) {
    let b = text.as_bytes();
    let (mut i, _) = past_skip(b);
    if b.get(i).is_some_and(|c| c.eq_ignore_ascii_case(&b'N')) && b.get(i + 1).is_some_and(u8::is_ascii_digit) {
        i += 1;
        while b.get(i).is_some_and(u8::is_ascii_digit) {
            i += 1;
        }
        while b.get(i).is_some_and(u8::is_ascii_whitespace) {
            i += 1;
        }
    }
    let start = i;
    let name_end = (i..b.len()).find(|&k| !(b[k].is_ascii_alphanumeric() || b[k] == b'_')).unwrap_or(b.len());
    // A marker: two characters or more, the first two letters or underscores, then ':'.
    let marker = name_end >= start + 2 && b[start..start + 2].iter().all(|c| c.is_ascii_alphabetic() || *c == b'_') && b.get(name_end) == Some(&b':');
    if marker {
        let body = name_end + 1 + b[name_end + 1..].iter().take_while(|c| c.is_ascii_whitespace()).count();
        return (start, Some((text[start..name_end].to_ascii_uppercase(), name_end + 1)), body);
    }
    (start, None, start)
}

/// The first word of `text` from `at`, and where what follows it starts.
fn first_word(text: &str, at: usize) -> (&str, usize) {
    let b = text.as_bytes();
    let end = (at..b.len()).find(|&k| !(b[k].is_ascii_alphanumeric() || b[k] == b'_')).unwrap_or(b.len());
    (&text[at..end], end)
}

/// Whether the line is a statement (not blank, a comment or a transfer header `%_N_..`), from its
/// block's start `body`.
fn statement(text: &str, body: usize) -> bool {
    let t = text[body.min(text.len())..].trim_start();
    !(t.is_empty() || t.starts_with(';') || text.trim_start().starts_with('%'))
}

/// A jump keyword's way.
fn way(word: &str) -> Option<Way> {
    Some(match word {
        "GOTOF" => Way::Forward,
        "GOTOB" => Way::Back,
        "GOTO" => Way::Either,
        "GOTOC" => Way::Quiet,
        _ => return None,
    })
}

/// The words that open a line of program control.
const CONTROL: [&str; 18] = ["IF", "ELSE", "ENDIF", "WHILE", "ENDWHILE", "FOR", "ENDFOR", "LOOP", "ENDLOOP", "REPEAT", "REPEATB", "UNTIL", "GOTOF", "GOTOB", "GOTO", "GOTOC", "RET", "PROC"];

/// Whether a line's first word is program control: most lines are moves, passed on after a look
/// at it (any case, no copy).
fn control_word(word: &str) -> bool {
    (2..=8).contains(&word.len()) && CONTROL.iter().any(|k| k.eq_ignore_ascii_case(word))
}

impl FlowRunner {
    /// A jump to `target` (after the keyword at byte `at` of `text`).
    fn jump(&mut self, text: &str, at: usize, w: Way, line: usize, here: At, diags: &mut Diags) -> Next {
        let rest = text[at..].split(';').next().unwrap_or("");
        let column = crate::program::lex::Columns::new(text).col(at + (rest.len() - rest.trim_start().len()));
        let rest = rest.trim();
        let target = rest.to_ascii_uppercase();
        let ok = target.len() >= 2 && target.bytes().all(|c| c.is_ascii_alphanumeric() || c == b'_');
        if !ok {
            return stop(line, column, format!("expected a jump marker or a block number after the jump, found '{}'", crate::program::lex::excerpt(rest)), diags);
        }
        if let Some(hits) = self.places.get(&target) {
            return self.resolve(target, w, line, column, here, &hits, diags);
        }
        self.wanted = Some((target, w, line, column, here));
        Next::Find(Find { from: At { line: 1, offset: 0 }, to: None, key: 0 })
    }

    /// A control keyword's line: what it does.
    #[allow(clippy::too_many_arguments)]
    fn control(&mut self, word: &str, text: &str, after: usize, line: usize, here: At, next: At, diags: &mut Diags) -> Next {
        let col = after - word.len() + 1;
        let rest = &text[after..];
        if self.open.len() >= MAX_NESTING && matches!(word, "IF" | "WHILE" | "FOR" | "LOOP" | "REPEAT") && !rest.to_ascii_uppercase().contains("GOTO") {
            return stop(line, col, format!("control structures nested more than {MAX_NESTING} deep"), diags);
        }
        let pop = |open: &mut Vec<Open>, want: &[&str]| -> Option<Open> { open.last().filter(|o| want.contains(&o.name())).is_some().then(|| open.pop()).flatten() };
        match word {
            "IF" => {
                let rest = rest.split(';').next().unwrap_or("");
                let upper = rest.to_ascii_uppercase();
                // IF <condition> GOTOx <marker>: a conditional jump.
                let jump = ["GOTOF", "GOTOB", "GOTOC", "GOTO"].iter().find_map(|k| upper.find(&format!(" {k} ")).map(|p| (p, *k)));
                let (cond, jump) = match jump {
                    Some((p, k)) => (&rest[..p], Some((k, after + p + 1 + k.len()))),
                    None => (rest, None),
                };
                let holds = match self.condition(cond) {
                    Ok(h) => h,
                    Err(why) => return stop(line, col, format!("IF: {why}"), diags),
                };
                match (jump, holds) {
                    (Some((k, at)), true) => self.jump(text, at, way(k).expect("a jump keyword"), line, here, diags),
                    (Some(_), false) => Next::On,
                    (None, true) => {
                        self.open.push(Open::If);
                        Next::On
                    }
                    (None, false) => {
                        self.skipping = Some(Skip { open: "IF", close: "ENDIF", at_else: true, depth: 0, line });
                        Next::On
                    }
                }
            }
            "ELSE" => match pop(&mut self.open, &["IF"]) {
                Some(Open::If) => {
                    self.skipping = Some(Skip { open: "IF", close: "ENDIF", at_else: false, depth: 0, line });
                    Next::On
                }
                _ => stop(line, col, "ELSE with no IF open here".into(), diags),
            },
            "ENDIF" => match pop(&mut self.open, &["IF"]) {
                Some(_) => Next::On,
                None => stop(line, col, "ENDIF with no IF open here (a jump into or within a structure is not read)".into(), diags),
            },
            "WHILE" => match self.condition(rest) {
                Ok(true) => {
                    self.open.push(Open::While(here));
                    Next::On
                }
                Ok(false) => {
                    self.skipping = Some(Skip { open: "WHILE", close: "ENDWHILE", at_else: false, depth: 0, line });
                    Next::On
                }
                Err(why) => stop(line, col, format!("WHILE: {why}"), diags),
            },
            "ENDWHILE" => match pop(&mut self.open, &["WHILE"]) {
                Some(Open::While(head)) => Next::Jump(head),
                _ => stop(line, col, "ENDWHILE with no WHILE open here (a jump into or within a structure is not read)".into(), diags),
            },
            "FOR" => {
                let r = rest.split(';').next().unwrap_or("");
                let upper = r.to_ascii_uppercase();
                let (Some(eq), Some(to)) = (r.find('='), upper.find(" TO ")) else {
                    return stop(line, col, "FOR: expected FOR variable = start TO end".into(), diags);
                };
                let var = r[..eq].trim().to_ascii_uppercase();
                if eq > to || !self.reader.vars.is_variable(&var) {
                    return stop(line, col, format!("FOR: '{}' is not a variable of this program (DEF, or an R parameter)", crate::program::lex::excerpt(r[..eq.min(r.len())].trim())), diags);
                }
                let mut eval = |t: &str| self.reader.vars.eval(t.trim()).map_err(|e| e.message);
                let (start, end) = match (eval(&r[eq + 1..to]), eval(&r[to + 4..])) {
                    (Ok(a), Ok(b)) => (a, b),
                    (Err(why), _) | (_, Err(why)) => return stop(line, col, format!("FOR: {why}"), diags),
                };
                if let Err(why) = self.reader.vars.assign(&var, start) {
                    return stop(line, col, format!("FOR: {why}"), diags);
                }
                self.reader.vars.commit();
                if start > end {
                    self.skipping = Some(Skip { open: "FOR", close: "ENDFOR", at_else: false, depth: 0, line });
                } else {
                    self.open.push(Open::For { var, end, body: next });
                }
                Next::On
            }
            "ENDFOR" => match self.open.last().cloned() {
                Some(Open::For { var, end, body }) => {
                    let v = self.reader.vars.get(&var).unwrap_or(f64::INFINITY) + 1.0;
                    if let Err(why) = self.reader.vars.assign(&var, v) {
                        return stop(line, col, format!("ENDFOR: {why}"), diags);
                    }
                    self.reader.vars.commit();
                    if v <= end {
                        Next::Jump(body)
                    } else {
                        self.open.pop();
                        Next::On
                    }
                }
                _ => stop(line, col, "ENDFOR with no FOR open here (a jump into or within a structure is not read)".into(), diags),
            },
            "LOOP" => {
                self.open.push(Open::Loop(next));
                Next::On
            }
            "ENDLOOP" => match self.open.last() {
                Some(Open::Loop(body)) => Next::Jump(*body),
                _ => stop(line, col, "ENDLOOP with no LOOP open here (a jump into or within a structure is not read)".into(), diags),
            },
            "REPEAT" if rest.split(';').next().unwrap_or("").trim().is_empty() => {
                self.open.push(Open::Repeat(next));
                Next::On
            }
            "REPEAT" | "REPEATB" => stop(line, col, format!("{word} with a marker: a section repeat is not read yet"), diags),
            // RET ends a subprogram (its caller goes on); in the main program, the program.
            "RET" if rest.split(';').next().unwrap_or("").trim().is_empty() => {
                self.end = End::Returned;
                Next::Ended
            }
            "RET" => stop(line, col, "RET with a destination or levels is not read".into(), diags),
            "PROC" => self.proc_line(text, after, line, col, diags),
            "UNTIL" => match (self.open.last().cloned(), self.condition(rest)) {
                (Some(Open::Repeat(body)), Ok(false)) => Next::Jump(body),
                (Some(Open::Repeat(_)), Ok(true)) => {
                    self.open.pop();
                    Next::On
                }
                (Some(Open::Repeat(_)), Err(why)) => stop(line, col, format!("UNTIL: {why}"), diags),
                _ => stop(line, col, "UNTIL with no REPEAT open here (a jump into or within a structure is not read)".into(), diags),
            },
            _ => match way(word) {
                Some(w) => self.jump(text, after, w, line, here, diags),
                None => Next::On,
            },
        }
    }

    /// A plain block: the reader's, its marker blanked; an end of program (M30, M2, M17) ends the run.
    fn plain(&mut self, line: usize, text: &str, marker: Option<(usize, usize)>, out: &mut Vec<Block>, diags: &mut Diags) -> Next {
        let before = out.len();
        match marker {
            Some((from, to)) => {
                let mut t = String::with_capacity(text.len());
                t.push_str(&text[..from]);
                t.extend(std::iter::repeat_n(' ', to - from));
                t.push_str(&text[to..]);
                self.reader.line(line, &t, out, diags);
            }
            None => self.reader.line(line, text, out, diags),
        }
        // Tool radius compensation could not go on: the program stops there.
        if self.reader.stopped {
            return Next::Ended;
        }
        let program_end = ends_program(&out[before..], &[2.0, 30.0]);
        if self.level > 0 && program_end {
            out.truncate(before);
            return stop(line, 1, "M2 or M30 in a subprogram: whether it returns or ends the program is not read (the manual's page is not in reach)".into(), diags);
        }
        // M17 read in this line (a block tool radius compensation holds comes out later, maybe in
        // the caller's line: its events do not end that one).
        if std::mem::take(&mut self.reader.returned) {
            self.end = End::Returned;
            return Next::Ended;
        }
        if program_end { Next::Ended } else { Next::On }
    }
}

impl Jumping for FlowRunner {
    fn wants_scan(&self) -> bool {
        false
    }

    fn scan(&mut self, _line: usize, _bytes: &[u8], _next: At, _diags: &mut Diags) {}

    fn line(&mut self, line: usize, text: &str, here: At, next: At, out: &mut Vec<Block>, diags: &mut Diags) -> Next {
        let again = line <= self.reached || self.count_all;
        if again {
            self.again += 1;
        }
        self.reader.vars.again = again;
        self.reached = self.reached.max(line);
        if self.again > self.budget {
            return stop(line, 1, format!("more than {} lines run by loops, jumps and calls beyond the programs' own: an endless loop?", self.setup.max_run_lines), diags);
        }
        let text = text.trim_end_matches('\r');
        let (start, marker, body) = split(text);
        let (word, after) = first_word(text, body);
        if self.skipping.is_none() && !self.begun && statement(text, body) && !word.eq_ignore_ascii_case("PROC") {
            self.begun = true;
            // A program called with parameters has a PROC line first.
            if let (Some(args), Some(name)) = (&self.args, &self.called) {
                if !args.is_empty() {
                    return stop(line, 1, format!("{name} is called with parameters, but its program has no PROC line first"), diags);
                }
            }
        }
        if self.skipping.is_none() && !control_word(word) {
            if let Some(site) = super::subprogram::call_site(text, body) {
                if past_skip(text.as_bytes()).1 {
                    diags.warning(line, text.find('/').map_or(1, |c| c + 1), "block skip '/' is not modelled: the block is run");
                }
                return match site {
                    Ok(site) => self.call(site, text, line, diags),
                    Err((k, why)) => {
                        diags.error(line, crate::program::lex::Columns::new(text).col(k), why);
                        // The control runs the call all the same: where it leaves the tool is not known.
                        let name: String = text[body..].chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
                        self.reader.interp.moved_everywhere(line, &name, super::subprogram::CALL_NOT_READ);
                        self.reader.tangent = None;
                        Next::On
                    }
                };
            }
            let blank = marker.as_ref().map(|(_, end)| (start, *end));
            return self.plain(line, text, blank, out, diags);
        }
        let word = word.to_ascii_uppercase();
        if self.skipping.is_none() && past_skip(text.as_bytes()).1 {
            // The block reader says so of the blocks it reads; a flow statement is run here.
            diags.warning(line, text.find('/').map_or(1, |c| c + 1), "block skip '/' is not modelled: the block is run");
        }
        if let Some(mut s) = self.skipping {
            if word == s.close && s.depth == 0 || word == "ELSE" && s.at_else && s.depth == 0 {
                self.skipping = None;
                if word == "ELSE" {
                    self.open.push(Open::Else);
                }
            } else if word == s.close {
                s.depth -= 1;
                self.skipping = Some(s);
            } else if word == s.open && !(s.open == "IF" && text[after..].to_ascii_uppercase().contains(" GOTO")) {
                s.depth += 1;
                self.skipping = Some(s);
            }
            return Next::On;
        }
        self.control(&word, text, after, line, here, next, diags)
    }

    fn finish(&mut self, ended: bool, out: &mut Vec<Block>, diags: &mut Diags) {
        self.reader.finish(None, out, diags);
        // A corner still waiting has no element after it.
        if self.level == 0 {
            self.reader.corner_end(self.reached.max(1), out, diags);
        }
        // The main program's end: compensation still on lets its held blocks out.
        if self.level == 0 {
            self.reader.trc_end(self.reached.max(1), out, diags);
        }
        if ended {
            return;
        }
        // A program ends with M2 or M30 (M17 a subprogram: SINUMERIK 840D sl Programming Manual
        // Fundamentals, "M functions"): a file without one was cut short, or is not all of the program.
        if self.reached > 0 && self.level > 0 {
            diags.warning(self.reached, 1, "the file ends before the subprogram's end (RET or M17); was the file cut short?");
        } else if self.reached > 0 {
            diags.warning(self.reached, 1, "the file ends before the program's end (M30, M2 or M17); was the file cut short?");
        }
        if let (Some(args), Some(name), false) = (&self.args, &self.called, self.begun) {
            if !args.is_empty() {
                diags.error(1, 1, format!("{name} is called with parameters, but its program has no PROC line first"));
                return;
            }
        }
        if self.skipping.is_none() && self.open.is_empty() {
            self.end = End::Returned;
        }
        // The input ended while the program ran: what it left open.
        if let Some(s) = self.skipping {
            diags.error(s.line, 1, format!("the program ends inside {} (no {})", s.open, s.close));
        } else if let Some(o) = self.open.last() {
            diags.error(self.reached, 1, format!("the program ends inside {} (its end never comes)", o.name()));
        }
    }

    fn name(&self) -> Option<String> {
        None
    }

    fn not_read(&mut self, line: usize, out: &mut Vec<Block>, diags: &mut Diags) {
        self.reader.corner_interrupt("the block after it was not read", line, 1, out, diags);
    }

    fn matches(&self, _key: u64, bytes: &[u8]) -> bool {
        let Some((target, ..)) = &self.wanted else { return false };
        if target.starts_with('N') && target[1..].bytes().all(|c| c.is_ascii_digit()) {
            return block_number(bytes, MAX_N_DIGITS).is_some_and(|n| target[1..].parse::<u64>().ok() == Some(n));
        }
        split(&String::from_utf8_lossy(bytes)).1.is_some_and(|(m, _)| m == *target)
    }

    fn more(&mut self, out: &mut Vec<Block>, diags: &mut Diags) -> Option<Next> {
        self.sub_more(out, diags)
    }

    fn found(&mut self, _find: Find, hits: &[At], read: usize, diags: &mut Diags) -> Next {
        let Some((target, w, line, column, here)) = self.wanted.take() else { return Next::On };
        // The lines a search reads count as run again: a jump taken a million times stays bounded.
        self.again = self.again.saturating_add(read);
        self.places.remember(target.clone(), hits);
        self.resolve(target, w, line, column, here, hits, diags)
    }
}

impl FlowRunner {

    /// Where a jump to `target` goes, its marker found at `hits`.
    #[allow(clippy::too_many_arguments)]
    fn resolve(&mut self, target: String, w: Way, line: usize, column: usize, here: At, hits: &[At], diags: &mut Diags) -> Next {
        let at = match hits {
            [] if w == Way::Quiet => return Next::On,
            [] => return stop(line, column, format!("jump destination {target} not found in the program (alarm 14080)"), diags),
            [at] => *at,
            _ => return stop(line, column, format!("jump marker {target} written more than once: which one the control takes is not read"), diags),
        };
        let ok = match w {
            Way::Forward => at.offset > here.offset,
            Way::Back => at.offset <= here.offset,
            Way::Either | Way::Quiet => true,
        };
        if !ok {
            let (kw, side) = if w == Way::Forward { ("GOTOF", "before") } else { ("GOTOB", "after") };
            return stop(line, column, format!("{kw} {target}: the marker stands {side} the jump (alarm 14080)"), diags);
        }
        // A jump leaves the structures it stands in.
        self.open.clear();
        Next::Jump(at)
    }
}

#[cfg(test)]
mod tests {
    use crate::program::{read, Dialect, Program, ReadOptions, Severity};

    fn run(text: &str, options: &ReadOptions) -> Program {
        read(text, Dialect::Sinumerik, "t.mpf", options)
    }


    /// Each block that moves: its line and X Y Z (mm, NaN where not named).
    fn moves(p: &Program) -> Vec<(usize, [f64; 3])> {
        p.blocks.iter().filter(|b| b.targets.x.is_some() || b.targets.y.is_some() || b.targets.z.is_some()).map(|b| (b.line, [b.targets.x, b.targets.y, b.targets.z].map(|v| v.map_or(f64::NAN, |v| v * 1e3)))).collect()
    }

    /// A bolt circle by `WHILE` ... `ENDWHILE`: six holes 60 deg apart on a 50 mm radius, computed
    /// here from the circle; then `FOR` counting 1 to 3.
    /// A refused block leaves the reader as it was, a block of plain words as any other (the 840D
    /// reader says nothing of an earlier refused line in a later defect, as before).
    #[test]
    fn a_refused_plain_block_leaves_the_state_as_it_was() {
        let p = run("N1 G90 G71 G94 G17 F500 TRAORI\nN2 G1 X0 Y0 Z0 A3=0 B3=0 C3=1\nN3 G1 X10 X11 A3=0 B3=1 C3=1\nN4 G1 X20 I5\nN5 G1 X30\nM30\n", &ReadOptions::default());
        let e = p.messages(Severity::Error);
        assert_eq!(e.len(), 2, "{e:#?}");
        assert!(e.iter().all(|m| !m.contains("was refused before it")), "{e:#?}");
        // Line 3's tool vector did not carry over to line 5's move.
        let last = p.blocks.iter().rev().find(|b| b.targets.x.is_some()).unwrap();
        assert_eq!(last.line, 5);
        assert!(last.targets.tool_axis.is_none(), "{:?}", last.targets.tool_axis);
    }

    #[test]
    fn while_and_for_loops_run_as_their_conditions_say() {
        let text = "DEF INT COUNT\nR1=0\nWHILE R1<6\nG1 X=50*COS(R1*60) Y=50*SIN(R1*60) F500\nR1=R1+1\nENDWHILE\nFOR COUNT=1 TO 3\nG1 Z=COUNT*10\nENDFOR\nM30\n";
        let p = run(text, &ReadOptions::default());
        assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
        let m = moves(&p);
        assert_eq!(m.len(), 9, "{m:?}");
        for (k, (line, at)) in m[..6].iter().enumerate() {
            let a = (60.0 * k as f64).to_radians();
            assert!(*line == 4 && (at[0] - 50.0 * a.cos()).abs() < 1e-9 && (at[1] - 50.0 * a.sin()).abs() < 1e-9, "hole {k}: {m:?}");
        }
        for (k, (line, at)) in m[6..].iter().enumerate() {
            assert!(*line == 8 && (at[2] - 10.0 * (k + 1) as f64).abs() < 1e-9, "{m:?}");
        }
    }

    /// A loop's expressions, compiled on the first pass run again (a cache keyed by their text), take
    /// each pass's values: the pass that divides by zero (CNT = 3) is a defect at its line and
    /// column, and the passes before and after it move where 10 / (3 - CNT) says.
    #[test]
    fn a_loops_expressions_take_each_passs_values() {
        let text = "DEF INT CNT\nCNT=0\nWHILE CNT<5\nG1 X=10/(3-CNT) Y=CNT F100\nCNT=CNT+1\nENDWHILE\nM30\n";
        let p = run(text, &ReadOptions::default());
        let e = p.messages(Severity::Error);
        assert!(e.len() == 1 && e[0].starts_with("4:6: X=10/(3-CNT): division by zero"), "{e:#?}");
        let m = moves(&p);
        let want = [0.0, 1.0, 2.0, 4.0].map(|n: f64| (10.0 / (3.0 - n), n));
        assert_eq!(m.len(), want.len(), "{m:?}");
        for ((line, at), (x, y)) in m.iter().zip(want) {
            assert!(*line == 4 && (at[0] - x).abs() < 1e-9 && (at[1] - y).abs() < 1e-9, "{m:?}");
        }
    }

    /// `IF` ... `ELSE` ... `ENDIF` takes one branch; `REPEAT` ... `UNTIL` runs until its condition.
    #[test]
    fn branches_and_repeats_take_their_way() {
        let text = "R2=5\nIF R2>3\nG1 Y1 F100\nELSE\nG1 Y2\nENDIF\nIF R2<3\nG1 Y3\nELSE\nG1 Y4\nENDIF\nR4=0\nREPEAT\nR4=R4+1\nG1 X=R4\nUNTIL R4>=2\nM30\n";
        let p = run(text, &ReadOptions::default());
        assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
        let lines: Vec<usize> = moves(&p).iter().map(|m| m.0).collect();
        assert_eq!(lines, [3, 10, 15, 15], "{:?}", moves(&p));
    }

    /// Jumps to markers: `GOTOB` back while a condition holds, `GOTOF` past blocks that then never run.
    #[test]
    fn jumps_go_to_their_markers() {
        let text = "R3=0\nMARK1: G1 Z=R3 F100\nR3=R3+1\nIF R3<3 GOTOB MARK1\nGOTOF DONE\nG1 X99\nDONE: G1 Y7\nGOTOC NOWHERE\nM30\nG1 X98\n";
        let p = run(text, &ReadOptions::default());
        assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
        let m = moves(&p);
        let z: Vec<f64> = m.iter().filter(|m| m.0 == 2).map(|m| m.1[2]).collect();
        assert_eq!(z, [0.0, 1.0, 2.0], "{m:?}");
        assert!(!m.iter().any(|m| m.0 == 6 || m.0 == 10), "{m:?}");
        assert!(m.iter().any(|m| m.0 == 7 && (m.1[1] - 7.0).abs() < 1e-9), "{m:?}");
    }

    /// A block skip `/` stands before the block number (802D §8.1.4: `/N... word1 ...`): a jump finds
    /// `/N20` and `/ SKIP1:` as it finds them without it, and a flow statement after `/` runs, with
    /// the warning the block reader gives its blocks (the skip switch is not modelled: off).
    #[test]
    fn a_block_skip_before_the_number_or_marker_leaves_them_found() {
        let text = "G90 G1 X0 Y0 F100\nGOTOF N20\nN10 G1 X5\n/N20 G1 X10\n/ GOTOF SKIP1\nG1 X15\n/ SKIP1: G1 X20\nR1=0\n/ N30 G1 Y=R1\nR1=R1+1\nIF R1<2 GOTOB N30\nM30\n";
        let p = run(text, &ReadOptions::default());
        assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
        let m = moves(&p);
        let lines: Vec<usize> = m.iter().map(|m| m.0).collect();
        assert_eq!(lines, [1, 4, 7, 9, 9], "{m:?}");
        assert!((m[1].1[0] - 10.0).abs() < 1e-9 && (m[2].1[0] - 20.0).abs() < 1e-9, "{m:?}");
        assert!((m[4].1[1] - 1.0).abs() < 1e-9, "{m:?}");
        let w = p.messages(Severity::Warning);
        for at in ["4:1:", "5:1:", "7:1:", "9:1:"] {
            assert!(w.iter().any(|m| m.starts_with(at) && m.contains("block skip '/'")), "{at}: {w:#?}");
        }
    }

    /// A jump taken again goes where it went without searching again (5,000 turns before 2,000 lines,
    /// within a bound a search per turn would pass many times over); a `GOTOF` in a comment is none.
    #[test]
    fn a_jump_taken_again_does_not_search_again() {
        let mut text = String::from("R1=0\nMARK: R1=R1+1\nIF R1<5000 GOTOB MARK\nIF R1==5000 ; GOTOF LATER\nG1 Y1 F100\nENDIF\n");
        text.push_str(&"G1 X1\n".repeat(2000));
        text.push_str("M30\n");
        let p = run(&text, &ReadOptions { max_run_lines: 14_000, ..ReadOptions::default() });
        assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
        assert_eq!(moves(&p).len(), 2001);
    }

    /// What the flow cannot follow is refused where it stands.
    #[test]
    fn control_defects_are_refused_where_they_stand() {
        for (text, at, needle) in [
            ("BACK: G1 X1 F100\nGOTOF BACK\n", "2:7:", "stands before the jump"),
            ("GOTOF NOWHERE\n", "1:7:", "NOWHERE not found"),
            ("GOTOF TWICE\nTWICE: G1 X1 F100\nTWICE: G1 X2\n", "1:7:", "more than once"),
            ("ENDIF\n", "1:1:", "ENDIF with no IF"),
            ("REPEAT MARK1 P=2\n", "1:1:", "section repeat"),
            ("LOOP\nG1 X1 F100\nENDLOOP\n", "", "an endless loop"),
            ("WHILE 1==0\nG1 X1 F100\n", "1:1:", "ends inside WHILE"),
            ("FOR NOPE=1 TO 3\nENDFOR\n", "1:1:", "not a variable"),
            ("WHILE 1==1\nG1 X1 F100\n", "2:1:", "ends inside WHILE"),
            ("GOTOF   NOWHERE\n", "1:9:", "NOWHERE not found"),
        ] {
            let p = run(text, &ReadOptions { max_run_lines: 1000, ..ReadOptions::default() });
            let e = p.messages(Severity::Error);
            assert!(e.iter().any(|m| m.starts_with(at) && m.contains(needle)), "{text:?}: {e:#?}");
        }
    }
}
