//! Fanuc's and Haas' program flow as the control runs it: custom macro B's branches and loops and
//! the subprograms a file holds. Every other line is the RS274 reader's ([`Rs274Reader`]).
//!
//! Rules (FANUC Series 0i-MODEL F Operator's Manual B-64604EN and 30i B-64484EN, "Custom macro" and
//! "Subprogram"; Haas Mill Operator's Manual, M97-M99 and G65):
//! - `GOTO n`, `IF [c] GOTO n`: to the block numbered `N n` of the program running (a number written
//!   twice there is refused: which one the control takes is not read); `IF [c] THEN #i = e`.
//! - `WHILE [c] DOm` ... `ENDm` (`m` 1 to 3, nested by different numbers), `DOm` alone loops for
//!   ever; a branch out of a loop leaves it (a branch within one is refused at its `END`).
//! - `M98 P<program> L<count>` runs the file's program `O<program>` `L` times, `M99` returns (to the
//!   block after the call; `M99 P n` to the caller's `N n`); `G65 P L` with arguments `A`-`Z`
//!   (argument specification I: `#1`-`#26`) runs it with local variables `#1`-`#33` of its own;
//!   Haas' `M97 P n` runs the program's own blocks from `N n`. A program not in the file is refused
//!   (the motion would depend on it); calls nest 10 deep.
//! - The program ends at `M30` or `M02` (the file's subprograms after it run only when called), at
//!   the tape's end `%`, or where another program starts. `M99` in the main program (the control
//!   runs it again from its start, endlessly) is read once and said.
//! - Loops, branches and calls run at most the program's lines and `max_run_lines` more: an endless
//!   loop is refused at the line it had reached.

mod statement;

use statement::{maybe_flow, program_number, rest_is_empty, Stmt, Then};
use super::interp::Word;
use super::lex::{block_number, Diags};
use super::params::Scope;
use super::rs274::{ReadLine, Rs274Reader};
use super::stream::{ends_program, stop, At, Find, Jumping, LineReader, Next, Places};
use super::{Block, Dialect};

/// The most digits of a sequence number (`N`) a branch looks for.
const MAX_N_DIGITS: usize = 9;
/// Deepest nesting of subprogram and macro calls (FANUC: subprograms 10 levels).
pub const MAX_CALL_DEPTH: usize = 10;
/// Most programs one file may hold.
pub const MAX_PROGRAMS: usize = 10_000;
/// Deepest nesting of `DO` loops (FANUC: identification numbers 1 to 3).
const MAX_LOOPS: usize = 3;
/// Most lines kept as read for the passes that run them again (their memory is the reader's to
/// bound, [`Rs274Reader::loop_line`]).
const MAX_KEPT_LINES: usize = 10_000;

/// A program the file holds: its number, and where its blocks start and end (byte offset).
#[derive(Debug, Clone, Copy)]
struct Program {
    number: u64,
    body: At,
    end: Option<u64>,
}

/// A call under way, or the main program (the first frame).
#[derive(Debug)]
struct Frame {
    /// Where its program's text starts and ends (byte offset): a branch looks there.
    unit: At,
    end: Option<u64>,
    /// Where a repeat starts again.
    start: At,
    /// Where to come back to, and the runs left after this one.
    back: At,
    repeats: u64,
    /// Its `DO` loops open: the identification number and where the loop's head stands.
    loops: Vec<(u8, At)>,
    /// A macro call's (G65) caller's locals, restored at its return.
    locals: Option<Scope>,
    /// The call's line and column.
    call: (usize, usize),
}

/// What a search for a block number is for.
#[derive(Debug, Clone, Copy)]
enum Wanted {
    Goto,
    /// Haas M97: a call of the program's own blocks from there.
    LocalCall { back: At, repeats: u64, call: (usize, usize) },
    /// M99 P: the caller's block to return to.
    Return,
}

/// Fanuc and Haas programs run line by line as the control runs them (sans I/O: the reader feeds
/// the line where it stands and goes where the flow says, [`super::stream::Seeking`]).
pub(crate) struct MacroRunner {
    reader: Rs274Reader,
    dialect: Dialect,
    /// The programs after the main one, from the first pass.
    programs: Vec<Program>,
    /// First pass: lines, whether a `%` was seen, whether program text came before the first `O`.
    lines: usize,
    scanned: u64,
    percent: bool,
    /// Lines and bytes before the first `%` (the tape's leader, if the reader can hold it).
    leader: (usize, usize),
    /// A line with words came after the first `%`: it started the tape rather than ended it.
    after_percent: bool,
    content: bool,
    main_numbered: bool,
    frames: Vec<Frame>,
    /// Lines skipped to the `END` of a loop whose test failed: its number, loops nested in it.
    skipping: Option<(u8, usize, usize)>,
    wanted: Option<(Wanted, u64, usize, usize)>,
    /// The places of block numbers searched before, by the program's start and the number.
    places: Places<(u64, u64)>,
    /// Lines run again (loops, branches back, subprograms) as read, by offset: a pass runs them
    /// from what was read ([`Rs274Reader::loop_line`]).
    kept: std::collections::HashMap<u64, ReadLine>,
    /// The furthest offset run so far in each program of the file (by where it starts): a line of it
    /// before that runs again. The program running keeps its own in `furthest_now` (unit, offset),
    /// not looked up for every line.
    furthest: std::collections::HashMap<u64, u64>,
    furthest_now: (u64, u64),
    executed: usize,
    budget: usize,
    /// The main program has ended (M30, M02, or M99 in it, or the next program of the file).
    program_end: bool,
}

impl MacroRunner {
    pub(crate) fn new(setup: &super::Setup) -> Self {
        MacroRunner {
            reader: Rs274Reader::new(setup),
            dialect: setup.dialect,
            programs: Vec::new(),
            lines: 0,
            scanned: 0,
            percent: false,
            leader: (0, 0),
            after_percent: false,
            content: false,
            main_numbered: false,
            frames: vec![Frame { unit: At { line: 1, offset: 0 }, end: None, start: At { line: 1, offset: 0 }, back: At { line: 1, offset: 0 }, repeats: 0, loops: Vec::new(), locals: None, call: (0, 0) }],
            skipping: None,
            program_end: false,
            wanted: None,
            places: Places::new(),
            kept: std::collections::HashMap::new(),
            furthest: std::collections::HashMap::new(),
            furthest_now: (0, 0),
            executed: 0,
            budget: setup.max_run_lines,
        }
    }

    fn frame(&mut self) -> &mut Frame {
        self.frames.last_mut().expect("the main program's frame")
    }
}

impl MacroRunner {
    /// Look for block `N n` in the program running, for `wanted` (where it was found before, if it was).
    fn find(&mut self, n: u64, wanted: Wanted, line: usize, column: usize, diags: &mut Diags) -> Next {
        let f = self.frames.last().expect("a frame");
        let find = Find { from: f.unit, to: f.end, key: n };
        if let Some(hits) = self.places.get(&(find.from.offset, n)) {
            return self.resolve(wanted, n, line, column, &hits, diags);
        }
        self.wanted = Some((wanted, n, line, column));
        Next::Find(find)
    }

    /// A call of the file's program `number`: its frame, and the jump to its first block.
    #[allow(clippy::too_many_arguments)]
    fn call(&mut self, number: u64, repeats: u64, locals: Option<Vec<(u32, f64)>>, back: At, line: usize, column: usize, diags: &mut Diags) -> Next {
        let Some(p) = self.programs.iter().find(|p| p.number == number).copied() else {
            return stop(line, column, format!("O{number} is not in this file: the motion depends on a program not read"), diags);
        };
        if self.frames.len() > MAX_CALL_DEPTH {
            return stop(line, column, format!("calls nested more than {MAX_CALL_DEPTH} deep"), diags);
        }
        if repeats == 0 {
            return Next::On;
        }
        let locals = locals.map(|args| self.reader.params.enter_locals(&args));
        self.frames.push(Frame { unit: p.body, end: p.end, start: p.body, back, repeats: repeats - 1, loops: Vec::new(), locals, call: (line, column) });
        Next::Jump(p.body)
    }

    /// `M99`: the end of a subprogram's run (again, if repeats are left), back to the caller.
    fn ret(&mut self, to: Option<u64>, line: usize, column: usize, diags: &mut Diags) -> Next {
        // Haas: "M99 P" in a subprogram branches to that block of the subprogram itself, "It does not
        // return control to the calling" program (Haas mill manual 96-8000, Macros); FANUC returns
        // to the caller's block. Which the Haas controls of today do is not at hand.
        if let (Some(n), true) = (to, self.dialect == Dialect::Haas && self.frames.len() > 1) {
            return stop(line, column, format!("M99 P{n} in a subprogram: Haas' manual has it branch to N{n} of the subprogram itself, FANUC's return to N{n} of the caller; which this control does is not read"), diags);
        }
        if self.frames.len() == 1 {
            self.program_end = true;
            diags.warning(line, column, "M99 in the main program: the control runs it again from its start, endlessly; read once");
            return Next::Ended;
        }
        let f = self.frame();
        if f.repeats > 0 && to.is_none() {
            f.repeats -= 1;
            f.loops.clear();
            return Next::Jump(f.start);
        }
        let f = self.frames.pop().expect("a call's frame");
        if let Some(scope) = f.locals {
            self.reader.params.leave_locals(scope);
        }
        match to {
            Some(n) => self.find(n, Wanted::Return, line, column, diags),
            None => Next::Jump(f.back),
        }
    }

    /// Run a call block's words.
    fn call_block(&mut self, words: &[Word<'static>], line: usize, next: At, diags: &mut Diags) -> Next {
        let code = |w: &Word| (w.letter, w.raw.trim_start_matches('0').to_string());
        let call = words.iter().find(|w| matches!(code(w), ('M', ref c) if c == "97" || c == "98" || c == "99") || matches!(code(w), ('G', ref c) if c == "65" || c == "66" || c == "67"));
        let Some(call) = call else { return Next::On };
        let (letter, c) = code(call);
        let name = format!("{letter}{c}");
        // FANUC 15i-MA §4.17: "In NURBS interpolation mode, commands (such as auxiliary functions)
        // other than NURBS interpolation cannot be specified."
        if self.reader.interp.nurbs.is_some() {
            return stop(line, call.column, format!("{name} in NURBS mode (G06.2): commands other than NURBS interpolation cannot be specified (FANUC 15i-MA §4.17); a G00-G03 ends the mode"), diags);
        }
        let get = |l: char| words.iter().find(|w| w.letter == l);
        let whole = |w: &Word| w.value.fract() == 0.0 && w.value >= 0.0 && w.value <= 99_999_999.0;
        if letter == 'G' && c != "65" {
            return stop(line, call.column, format!("{name}: a modal macro call is not read (each later move would call the macro)"), diags);
        }
        if c == "97" && self.dialect != Dialect::Haas {
            return stop(line, call.column, "M97 is Haas' local subprogram call, not a Fanuc control's".into(), diags);
        }
        // G65's arguments (argument specification I: A B C I J K D E F H M Q R S T U V W X Y Z).
        let args = "ABCIJKDEFHMQRSTUVWXYZ";
        let allowed = |l: char| matches!(l, 'N' | 'P' | 'L') || l == letter || c == "65" && args.contains(l);
        if let Some(w) = words.iter().find(|w| !allowed(w.letter) || w.letter == letter && !std::ptr::eq(*w, call)) {
            return stop(line, w.column, format!("{}{} in a {name} block: give {name} a block of its own (other words with a call are not read)", w.letter, w.raw, name = name), diags);
        }
        // An argument letter written twice is argument specification II (I J K repeated for #4-#33),
        // which is not read: refused rather than one of them dropped.
        if let Some(w) = words.iter().enumerate().find(|(k, w)| c == "65" && args.contains(w.letter) && words[..*k].iter().any(|v| v.letter == w.letter)).map(|(_, w)| w) {
            return stop(line, w.column, format!("{}{}: {} given twice in a G65 call (argument specification II) is not read", w.letter, w.raw, w.letter), diags);
        }
        let repeats = match get('L') {
            Some(w) if whole(w) => w.value as u64,
            Some(w) => return stop(line, w.column, format!("L{}: expected a whole count of runs", w.raw), diags),
            None => 1,
        };
        let p = get('P');
        if let Some(w) = p.filter(|w| !whole(w)) {
            return stop(line, w.column, format!("P{}: expected a whole program or block number", w.raw), diags);
        }
        match c.as_str() {
            "99" => self.ret(p.map(|w| w.value as u64), line, call.column, diags),
            "97" => match p {
                Some(w) => self.find(w.value as u64, Wanted::LocalCall { back: next, repeats, call: (line, call.column) }, line, w.column, diags),
                None => stop(line, call.column, "M97 without P: expected the block number to run from".into(), diags),
            },
            _ => {
                let Some(w) = p else {
                    return stop(line, call.column, format!("{name} without P: expected the program to call"), diags);
                };
                // Fanuc's packed form (M98 P<count><program>) or an eight-digit program number: the
                // control's parameter says which.
                if c == "65" && repeats != 1 {
                    return stop(line, call.column, format!("G65 L{repeats}: a macro called more than once is not read (whether its arguments are set again each time is not at hand)"), diags);
                }
                if self.dialect == Dialect::Fanuc && c == "98" && get('L').is_none() && w.value > 9999.0 {
                    return stop(line, w.column, format!("M98 P{}: a count and a program number packed in P, or an eight-digit program number, as the control's parameter says: write M98 P<program> L<count>", w.raw), diags);
                }
                let locals = (c == "65").then(|| {
                    let increments = |l: char, v: f64, raw: &str| {
                        // A value without a decimal point counts the address' least increments
                        // (on a calculator-type machine it is in the program's unit).
                        let step = if self.reader.calculator_input || raw.contains('.') || raw.contains('#') || raw.contains('[') {
                            1.0
                        } else if "XYZIJKRQUVW".contains(l) {
                            if self.reader.interp.unit() == crate::units::INCH { 1e-4 } else { 1e-3 }
                        } else if "ABC".contains(l) {
                            1e-3
                        } else {
                            1.0
                        };
                        v * step
                    };
                    words.iter().filter_map(|w| args.find(w.letter).map(|k| ([1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 13, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26][k], increments(w.letter, w.value, &w.raw)))).collect()
                });
                self.call(w.value as u64, repeats, locals, next, line, w.column, diags)
            }
        }
    }
}

impl Jumping for MacroRunner {
    /// The first pass: the programs the file holds after the main one, and whether it has a `%`.
    fn scan(&mut self, line: usize, bytes: &[u8], next: At, diags: &mut Diags) {
        self.lines = line;
        let here = std::mem::replace(&mut self.scanned, next.offset);
        let text = bytes.trim_ascii();
        if !self.percent && text.first() != Some(&b'%') {
            self.leader = (self.leader.0 + 1, self.leader.1 + bytes.len());
        }
        if self.percent && !text.is_empty() && text.first() != Some(&b'%') {
            self.after_percent = true;
        }
        if text.first() == Some(&b'%') {
            self.percent = true;
            if self.programs.is_empty() {
                // What came before the first % is the tape's leader, not program.
                self.content = false;
            }
            if let Some(p) = self.programs.last_mut().filter(|p| p.end.is_none()) {
                p.end = Some(here);
            }
            return;
        }
        if let Some(number) = program_number(text) {
            if !self.content && self.programs.is_empty() && !self.main_numbered {
                // The main program's own number.
                self.main_numbered = true;
                return;
            }
            if self.frames[0].end.is_none() && self.programs.is_empty() {
                self.frames[0].end = Some(here);
            }
            if let Some(p) = self.programs.last_mut().filter(|p| p.end.is_none()) {
                p.end = Some(here);
            }
            if self.programs.len() >= MAX_PROGRAMS {
                diags.error(line, 1, format!("more than {MAX_PROGRAMS} programs in one file: O{number} is not kept"));
                return;
            }
            self.programs.push(Program { number, body: next, end: None });
            return;
        }
        if !text.is_empty() && text.first() != Some(&b'(') {
            self.content = true;
        }
    }

    fn line(&mut self, line: usize, text: &str, here: At, next: At, out: &mut Vec<Block>, diags: &mut Diags) -> Next {
        // The tape's leader is decided by the first pass: no `%`, one with nothing after it (the
        // file's end: "a file starts with % or LF ... always ends with %", FANUC 16i/18i Operator's
        // Manual B-63524EN, "File format"), or one too far for the reader to hold what comes before
        // it, and every line is program, run as such.
        let (lead_lines, lead_bytes) = self.leader;
        if line == 1 && (!self.percent || !self.after_percent || lead_lines >= super::rs274::MAX_LEADER_LINES || lead_bytes > super::rs274::MAX_LEADER_BYTES) {
            self.reader.no_leader();
        }
        self.executed += 1;
        if self.executed > self.lines.saturating_add(self.budget) {
            return stop(line, 1, format!("more than {} lines run by loops, branches and calls beyond the program's own: an endless loop?", self.budget), diags);
        }
        if !self.reader.in_program() {
            self.reader.line(line, text, out, diags);
            return if self.reader.at_tape_end() { Next::Ended } else { Next::On };
        }
        // Another program starts here: the one running has no end before it.
        if self.reader.started() && program_number(text.as_bytes()).is_some() {
            if self.frames.len() == 1 {
                diags.warning(line, 1, "the main program runs into the next program of the file without M30 or M02: read as its end");
                self.program_end = true;
                return Next::Ended;
            }
            return stop(line, 1, "the subprogram runs into the next program of the file without M99".into(), diags);
        }
        if text.trim_start().starts_with('%') {
            // The tape's end (the reader's to say), whatever the flow is doing.
            self.reader.line(line, text, out, diags);
            return if self.reader.at_tape_end() { Next::Ended } else { Next::On };
        }
        if let Some((m, depth, _)) = self.skipping {
            // Past a loop whose test failed: to its END.
            let chars: Vec<char> = text.trim_end_matches('\r').chars().collect();
            if let Ok(Some(s)) = self.statement(&chars) {
                match s {
                    Stmt::While { m: n, .. } if n == m => self.skipping = Some((m, depth + 1, line)),
                    Stmt::End(n) if n == m && depth == 0 => self.skipping = None,
                    Stmt::End(n) if n == m => self.skipping = Some((m, depth - 1, line)),
                    _ => {}
                }
            }
            return Next::On;
        }
        // Within the program running (a line of the main program after a subprogram's return has
        // not run before, though the subprogram stands after it).
        let unit = self.frames.last().map_or(0, |f| f.unit.offset);
        if self.furthest_now.0 != unit {
            let (was, offset) = self.furthest_now;
            self.furthest.insert(was, offset);
            self.furthest_now = (unit, self.furthest.get(&unit).copied().unwrap_or(0));
        }
        let again = here.offset < self.furthest_now.1;
        self.furthest_now.1 = self.furthest_now.1.max(here.offset);
        if !maybe_flow(text) {
            return if again { self.again(line, text, here, out, diags) } else { self.plain(line, text, out, diags) };
        }
        let chars: Vec<char> = text.trim_end_matches('\r').chars().collect();
        // The modal information a statement may read (#4001-#4130), as the blocks before left it.
        self.reader.refresh_state(super::rs274::reads_state(chars.iter().copied()));
        let stmt = match self.statement(&chars) {
            Ok(Some(s)) => s,
            Ok(None) => return self.plain(line, text, out, diags),
            Err((col, why)) => return stop(line, col, why, diags),
        };
        // A chamfer or corner R waiting for its next block does not reach past a statement.
        self.reader.corner_interrupt(out, diags);
        let params = &self.reader.params;
        let cond = |at: usize| params.real_value(&chars, at, true).map(|(v, _)| v != 0.0).map_err(|e| (e.column, e.message));
        match stmt {
            Stmt::If { cond: c, then } => {
                let holds = match cond(c) {
                    Ok(h) => h,
                    Err((col, why)) => return stop(line, col, format!("IF: {why}"), diags),
                };
                match then {
                    Then::Goto(at) => {
                        let (n, end, col) = match self.label(&chars, at, "GOTO") {
                            Ok(v) => v,
                            Err((col, why)) => return stop(line, col, why, diags),
                        };
                        if !rest_is_empty(&chars, end) {
                            return stop(line, end + 1, "unexpected text after GOTO n".into(), diags);
                        }
                        if holds {
                            return self.find(n, Wanted::Goto, line, col, diags);
                        }
                        Next::On
                    }
                    Then::Set(at) => {
                        if chars.get(at) != Some(&'#') {
                            return stop(line, at + 1, "IF [..] THEN: only a macro statement (#i = ...) is read after THEN".into(), diags);
                        }
                        let (target, value, end) = match self.reader.params.macro_setting(&chars, at) {
                            Ok(s) => s,
                            Err(e) => return stop(line, e.column, e.message, diags),
                        };
                        if !rest_is_empty(&chars, end) {
                            return stop(line, end + 1, "unexpected text after the statement".into(), diags);
                        }
                        if holds {
                            if let Err(e) = self.reader.params.set(target, value, at + 1) {
                                return stop(line, e.column, e.message, diags);
                            }
                        }
                        Next::On
                    }
                }
            }
            Stmt::Goto(at) => match self.label(&chars, at, "GOTO") {
                Ok((n, end, col)) if rest_is_empty(&chars, end) => self.find(n, Wanted::Goto, line, col, diags),
                Ok((_, end, _)) => stop(line, end + 1, "unexpected text after GOTO n".into(), diags),
                Err((col, why)) => stop(line, col, why, diags),
            },
            Stmt::While { cond: c, m } => {
                let holds = match c.map(cond) {
                    None => true,
                    Some(Ok(h)) => h,
                    Some(Err((col, why))) => return stop(line, col, format!("WHILE: {why}"), diags),
                };
                let f = self.frame();
                if f.loops.iter().any(|(n, _)| *n == m) {
                    return stop(line, 1, format!("DO{m} inside a loop DO{m}: nested loops take different numbers"), diags);
                }
                if f.loops.len() >= MAX_LOOPS {
                    return stop(line, 1, format!("loops nested more than {MAX_LOOPS} deep"), diags);
                }
                if holds {
                    f.loops.push((m, here));
                } else {
                    self.skipping = Some((m, 0, line));
                }
                Next::On
            }
            Stmt::End(m) => match self.frame().loops.pop() {
                Some((n, head)) if n == m => Next::Jump(head),
                _ => stop(line, 1, format!("END{m} with no DO{m} open here (a branch into a loop, or within one, is not read)"), diags),
            },
            Stmt::Call(words) => self.call_block(&words, line, next, diags),
        }
    }

    fn finish(&mut self, ended: bool, out: &mut Vec<Block>, diags: &mut Diags) {
        self.reader.finish(None, out, diags);
        // A program ends with M30, M02 or M99 (FANUC B-64484EN, "Program end"; Haas Mill Operator's
        // Manual, M30 and M99): the tape's end `%` before it stops a Fanuc control with alarm PS5010
        // END OF RECORD, after the moves before it; a file without either was cut short, or is not all
        // of the program.
        if !self.program_end && !self.reader.alarmed() && self.reader.started() && (!ended || self.reader.at_tape_end()) {
            let (at, what) = (self.reader.last_line(), if self.reader.at_tape_end() { "the tape's end % comes" } else { "the file ends" });
            let alarm = if self.dialect == Dialect::Fanuc && self.reader.at_tape_end() { " (Fanuc: alarm PS5010 END OF RECORD, after running the moves before it)" } else { "" };
            diags.warning(at, 1, format!("{what} before the program's end (M30, M02 or M99){alarm}; was the file cut short?"));
        }
        if ended {
            return;
        }
        // The input ended while the program ran: what it left open.
        if let Some((m, _, at)) = self.skipping {
            diags.error(at, 1, format!("the program ends inside a loop DO{m} whose END{m} never comes"));
        }
        for f in &self.frames {
            if let Some((m, head)) = f.loops.last() {
                diags.error(head.line, 1, format!("the program ends inside the loop DO{m} begun here (no END{m})"));
            }
        }
        if let Some(f) = self.frames.get(1) {
            diags.error(f.call.0, f.call.1, "the program called here ends before its M99");
        }
    }

    fn name(&self) -> Option<String> {
        LineReader::name(&self.reader)
    }

    fn not_read(&mut self, line: usize, out: &mut Vec<Block>, diags: &mut Diags) {
        LineReader::not_read(&mut self.reader, line, out, diags);
    }

    fn matches(&self, key: u64, bytes: &[u8]) -> bool {
        block_number(bytes, MAX_N_DIGITS) == Some(key)
    }

    fn found(&mut self, find: Find, hits: &[At], read: usize, diags: &mut Diags) -> Next {
        let Some((wanted, n, line, column)) = self.wanted.take() else { return Next::On };
        // The lines a search reads count as run: a branch taken a million times over a long
        // program stays bounded.
        self.executed = self.executed.saturating_add(read);
        self.places.remember((find.from.offset, n), hits);
        self.resolve(wanted, n, line, column, hits, diags)
    }
}

impl MacroRunner {

    /// Where a branch, call or return to block `N n` goes, its block found at `hits`.
    fn resolve(&mut self, wanted: Wanted, n: u64, line: usize, column: usize, hits: &[At], diags: &mut Diags) -> Next {
        match hits {
            [] => stop(line, column, format!("no block N{n} in the program running"), diags),
            [at] => match wanted {
                Wanted::Goto => {
                    // A branch leaves the loops it stands in.
                    self.frame().loops.clear();
                    Next::Jump(*at)
                }
                Wanted::Return => Next::Jump(*at),
                Wanted::LocalCall { back, repeats, call } => {
                    if self.frames.len() > MAX_CALL_DEPTH {
                        return stop(line, column, format!("calls nested more than {MAX_CALL_DEPTH} deep"), diags);
                    }
                    if repeats == 0 {
                        return Next::On;
                    }
                    let (unit, end) = self.frames.last().map_or((At { line: 1, offset: 0 }, None), |f| (f.unit, f.end));
                    self.frames.push(Frame { unit, end, start: *at, back, repeats: repeats - 1, loops: Vec::new(), locals: None, call });
                    Next::Jump(*at)
                }
            },
            _ => stop(line, column, format!("N{n} numbers more than one block of the program running: which one the control takes is not read"), diags),
        }
    }

    /// A line run again (a loop's pass, a branch back, a subprogram called again): run from what
    /// was read the time before, or read and kept (when reading it says nothing), within bounds.
    fn again(&mut self, line: usize, text: &str, here: At, out: &mut Vec<Block>, diags: &mut Diags) -> Next {
        if line == 1 || !self.reader.started() {
            return self.plain(line, text, out, diags);
        }
        let before = out.len();
        match self.kept.get(&here.offset) {
            Some(read) => self.reader.run_line(line, text.trim_end_matches('\r'), read, None, out, diags),
            None if self.kept.len() < MAX_KEPT_LINES => {
                let mut kept = None;
                self.reader.loop_line(line, text, &mut kept, out, diags);
                if let Some(read) = kept {
                    self.kept.insert(here.offset, read);
                }
            }
            None => return self.plain(line, text, out, diags),
        }
        self.ended(&out[before..])
    }

    /// A line without flow: the reader's; an end of program (M30, M02) ends the run.
    fn plain(&mut self, line: usize, text: &str, out: &mut Vec<Block>, diags: &mut Diags) -> Next {
        let before = out.len();
        self.reader.line(line, text, out, diags);
        self.ended(&out[before..])
    }

    /// After a line made `made`: the run ends at the tape's end or an end of program (M30, M02).
    fn ended(&mut self, made: &[Block]) -> Next {
        if ends_program(made, &[2.0, 30.0]) {
            self.program_end = true;
        }
        if self.reader.at_tape_end() || self.reader.alarmed() || self.program_end {
            Next::Ended
        } else {
            Next::On
        }
    }
}

#[cfg(test)]
mod tests;
