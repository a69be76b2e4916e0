//! Running a Klartext program: its labels, calls, repeats and jumps, and each statement's block.

use std::collections::HashMap;

use super::exec::Exec;
use super::{parse_line, tokens, KWord, Kind, ParseState, Stmt, MAX_NESTING};
use crate::program::interp::Interpreter;
use crate::program::lex::Diags;
use crate::program::stream::{At, Jumping, Next};
use crate::program::Block;

/// The most labels a program may define (the TNC 640 numbers them 1 to 65535 and names others): a
/// label beyond is an error where it stands, and a call to it fails. It bounds the label table.
pub const MAX_LABELS: usize = 100_000;

/// The labels of a program, from a first pass over it (a call may jump forward to a subprogram
/// written after M2/M30): each label's line and where the line after it starts.
#[derive(Debug, Default)]
pub(crate) struct Labels {
    at: HashMap<String, (usize, At)>,
    lines: usize,
    /// The line before was a comment ending in `~` ([`super::comment_line`]).
    comment_open: bool,
}

impl Labels {
    /// Take line `line` (its bytes, without the newline), the line after it starting at `next`.
    pub(crate) fn line(&mut self, line: usize, bytes: &[u8], next: At, diags: &mut Diags) {
        self.lines = line;
        // A comment's continuation is no label, however it reads.
        let (goes_on, open) = super::comment_line(self.comment_open, bytes);
        self.comment_open = open;
        if goes_on {
            return;
        }
        // Most lines are moves: find a `B` before anything else.
        let mut rest = bytes;
        let has_lbl = loop {
            let Some(i) = memchr::memchr2(b'B', b'b', rest) else { break false };
            let (before, after) = (&rest[..i], &rest[i + 1..]);
            if before.last().is_some_and(|c| c.eq_ignore_ascii_case(&b'L')) && after.first().is_some_and(|c| c.eq_ignore_ascii_case(&b'L')) {
                break true;
            }
            rest = after;
        };
        if !has_lbl {
            return;
        }
        let text = String::from_utf8_lossy(bytes);
        let t = tokens(text.trim_end_matches('\r'));
        let body = if t.first().is_some_and(|f| f.0.bytes().all(|c| c.is_ascii_digit())) { &t[1..] } else { &t[..] };
        if let [(kw, col), (label, _)] = body {
            let label = label.trim_matches('"');
            if !kw.eq_ignore_ascii_case("LBL") || label == "0" {
                return;
            }
            if let Some(old) = self.at.get_mut(label) {
                // Said where it stands; calls go to the last one, as they always have.
                diags.error(line, *col, format!("LBL {label} defined twice"));
                *old = (line, next);
            } else if self.at.len() >= MAX_LABELS {
                diags.error(line, *col, format!("LBL {label}: more than {MAX_LABELS} labels in one program; not kept"));
            } else {
                self.at.insert(label.to_string(), (line, next));
            }
        }
    }
}

/// A Klartext program run as the TNC runs it (labels, section repeats, subprograms) one line at a
/// time, sans I/O: the reader feeds it the line where it stands and goes where it says next, so
/// memory holds the label table and the call stack, never the program. Each line is parsed as it
/// runs (a repeated section is parsed again rather than held).
pub(crate) struct Runner {
    interp: Interpreter,
    ex: Exec,
    st: ParseState,
    labels: Labels,
    /// Subprogram calls: where to come back to, and the call's line and column.
    stack: Vec<(At, usize, usize)>,
    /// Section repeats under way: the call's line and the runs left.
    repeats: HashMap<usize, u64>,
    /// Statements that may run beyond the program's own lines: the setup's `max_run_lines` (a
    /// bound on memory for a program such as `LBL 1` / `CALL LBL 1 REP65534` nested).
    budget: usize,
    executed: usize,
    /// Refused statements whose effect lasts on the TNC ([`super::held`]).
    holds: super::held::Holds,
}

impl Runner {
    pub(crate) fn new(setup: &crate::program::Setup) -> Runner {
        Runner {
            interp: setup.interpreter(),
            ex: Exec { machine: setup.machine.clone(), ..Exec::default() },
            st: ParseState::default(),
            budget: setup.max_run_lines,
            labels: Labels::default(),
            stack: Vec::new(),
            repeats: HashMap::new(),
            executed: 0,
            holds: super::held::Holds::new(setup.machine.iter().flat_map(|m| [3, 4].map(|k| m.axes[k].name.chars().next().unwrap_or('?')))),
        }
    }

    /// Run line `line` (without its newline), the line after it starting at `next`: its block
    /// goes to `out`, its defects to `diags`.
    pub(crate) fn line(&mut self, line: usize, raw: &str, next: At, out: &mut Vec<Block>, diags: &mut Diags) -> Next {
        let (was_inch, was_begun, errors) = (self.st.inch, self.st.began, diags.errors());
        let Some(s) = parse_line(line, raw, &mut self.st, diags) else {
            if self.st.inch != was_inch {
                if let Err(u) = self.interp.set_inch(self.st.inch) {
                    diags.warning(line, 1, format!("the program header says {}; its numbers are read in {} (--units)", if self.st.inch { "INCH" } else { "MM" }, u.name()));
                }
            }
            if self.st.began && !was_begun {
                // Q113: the main program's unit as it is read, 0 mm or 1 inch (iTNC 530 user's manual
                // 340 49x-03 §11.11 "Preassigned Q parameters").
                self.ex.q.insert("Q113".into(), if self.interp.unit() == crate::units::INCH { 1.0 } else { 0.0 });
            }
            if diags.errors() > errors {
                self.holds.refused(line, raw);
            }
            // An inch program's F is in 1/10 inch/min (the TNC7 user's manual, "Cutting data", as a
            // TNC7 programming station reads `F100` at 254 mm/min; Autodesk's Klartext post writes its
            // feeds tenfold in inch), where NX's sample posts write whole inch/min: the machine file
            // says which (tnc_inch_feed); without it, tenths, and the program is refused once here.
            if self.st.began && !was_begun && self.st.inch && self.interp.unit() == crate::units::INCH {
                let tenths = self.interp.machine().and_then(|m| m.tnc_inch_feed_tenths);
                if tenths != Some(false) {
                    self.interp.set_feed_unit(crate::units::INCH / 10.0);
                }
                if tenths.is_none() {
                    diags.error(line, 1, "an inch program: its F is read in 1/10 inch/min (the TNC7 user's manual, \"Cutting data\"; Autodesk's post writes tenths), where NX's posts write inch/min; the machine file's tnc_inch_feed (\"tenths\" or \"whole\") settles it");
                }
            }
            // A statement refused where it stands, after an RND or CHF: the corner is not made.
            if diags.errors() > errors && self.ex.interrupt("the block after it was not read", out, diags, &mut self.interp) {
                return Next::Ended;
            }
            return Next::On;
        };
        self.executed += 1;
        if self.executed > self.labels.lines.saturating_add(self.budget) {
            diags.error(s.line, s.col, format!("the repeats and calls run more than {} blocks beyond the program's own: not read further", self.budget));
            return Next::Ended;
        }
        match &s.kind {
            Kind::End => Next::Ended,
            Kind::Label("0") => match self.stack.pop() {
                Some((back, _, _)) => {
                    if self.ex.interrupt("the subprogram returns after it (LBL 0): it joins two elements one after the other", out, diags, &mut self.interp) {
                        return Next::Ended;
                    }
                    Next::Jump(back)
                }
                None => Next::On,
            },
            Kind::Label(_) => Next::On,
            Kind::Call { label, rep } => {
                if self.ex.interrupt("a call after it (CALL LBL): it joins two elements one after the other", out, diags, &mut self.interp) {
                    return Next::Ended;
                }
                self.call(&s, label, rep.as_ref(), next, diags)
            }
            // A conditional jump (FN 9-12): on to the line after the label when it holds.
            Kind::Jump { a, cmp, b, label } => match (self.ex.formula(a, s.line, s.col, diags), self.ex.formula(b, s.line, s.col, diags)) {
                (Some(x), Some(y)) if cmp.holds(x, y) && self.ex.interrupt("a jump after it (FN 9-12): it joins two elements one after the other", out, diags, &mut self.interp) => Next::Ended,
                (Some(x), Some(y)) if cmp.holds(x, y) => match self.labels.at.get(*label) {
                    Some(&(_, target)) => Next::Jump(target),
                    None => {
                        diags.error(s.line, s.col, format!("GOTO LBL {label}: no LBL {label} in the program"));
                        Next::On
                    }
                },
                _ => Next::On,
            },
            _ => {
                let (start, errors) = (out.len(), diags.errors());
                let ends = self.ex.run(&s, &mut self.interp, out, diags);
                let ok = diags.errors() == errors;
                // What it ends or starts first: the statement that ends a hold moves from where the
                // held moves left the tool.
                self.holds.ran(&s, ok, self.interp.ran_unread.take());
                if self.holds.active() {
                    // It moves: by its words, or by what it made (a cycle call, a PLANE's turn); what
                    // it made may come out later (held for a corner or by radius compensation).
                    let moves = match &s.kind {
                        Kind::Move { axes, .. } => !axes.is_empty(),
                        Kind::Spline { .. } | Kind::CycleCall(_) | Kind::Retract { .. } => true,
                        _ => false,
                    } || out[start.min(out.len())..].iter().any(|b| b.line == s.line && !b.targets.is_empty());
                    self.holds.after(&s, moves, ok, diags);
                    // Its blocks judged, then, if nothing is held anywhere, the held lines forgotten.
                    self.holds.drop_held(out, start);
                    if !self.ex.comp.busy() && self.ex.held.is_none() {
                        self.holds.settled();
                    }
                }
                if self.interp.halted || ends && self.stack.is_empty() {
                    Next::Ended // M2 / M30: the program ends (subprograms follow it); or the TNC stopped
                } else {
                    Next::On
                }
            }
        }
    }

    /// `CALL LBL label [REP n]` at `s`, the line after it starting at `next`.
    fn call(&mut self, s: &Stmt<'_>, label: &str, rep: Option<&KWord<'_>>, next: At, diags: &mut Diags) -> Next {
        let Some(&(label_line, target)) = self.labels.at.get(label) else {
            diags.error(s.line, s.col, format!("CALL LBL {label}: no LBL {label} in the program"));
            return Next::On;
        };
        let Some(w) = rep else {
            if self.stack.len() >= MAX_NESTING {
                diags.error(s.line, s.col, format!("CALL LBL {label}: subprograms nested deeper than {MAX_NESTING} levels"));
                return Next::Ended;
            }
            self.stack.push((next, s.line, s.col));
            return Next::Jump(target);
        };
        let count = match self.ex.value(w, s.line, diags) {
            Some(v) if v.fract() == 0.0 && (0.0..=65534.0).contains(&v) => v as u64,
            Some(v) => {
                diags.error(s.line, w.col, format!("REP {v}: expected a whole number of repeats, 0 to 65534"));
                return Next::On;
            }
            None => return Next::On,
        };
        // A program section repeat: back to the label `count` more times.
        if label_line >= s.line {
            diags.error(s.line, s.col, format!("CALL LBL {label} REP: the label must come before the call"));
            return Next::On;
        }
        let left = self.repeats.entry(s.line).or_insert(count);
        if *left > 0 {
            *left -= 1;
            Next::Jump(target)
        } else {
            self.repeats.remove(&s.line);
            Next::On
        }
    }

    /// After the end: a line that does not run (a subprogram never called) is checked all the same.
    pub(crate) fn check(&mut self, line: usize, raw: &str, diags: &mut Diags) {
        let _ = parse_line(line, raw, &mut self.st, diags);
    }

    /// The input has ended: a subprogram left open, a program without its start.
    pub(crate) fn finish(&mut self, diags: &mut Diags) {
        if let Some(&(_, line, col)) = self.stack.last() {
            diags.error(line, col, "the subprogram called here has no LBL 0 before the program ends");
        }
        if !self.st.began {
            diags.error(1, 1, "missing program start: expected BEGIN PGM NAME MM");
        } else if !self.st.ended {
            // The TNC's program ends with the block END PGM (TNC 640 User's Manual, "Program
            // structure": BEGIN PGM first, END PGM last): without it, the file was cut short.
            diags.error(self.labels.lines.max(1), 1, "missing program end: expected END PGM NAME MM as the last block (was the file cut short?)");
        }
    }

    /// The program's name, once its `BEGIN PGM` has run.
    pub(crate) fn name(&self) -> Option<&str> {
        self.st.name.as_deref()
    }
}

impl Jumping for Runner {
    fn scan(&mut self, line: usize, bytes: &[u8], next: At, diags: &mut Diags) {
        self.labels.line(line, bytes, next, diags);
    }

    fn line(&mut self, line: usize, text: &str, _here: At, next: At, out: &mut Vec<Block>, diags: &mut Diags) -> Next {
        let start = out.len();
        let next = Runner::line(self, line, text, next, out, diags);
        // Blocks of statements refused under a hold, wherever they come out.
        self.holds.drop_held(out, start);
        next
    }

    fn check(&mut self, line: usize, text: &str, diags: &mut Diags) {
        Runner::check(self, line, text, diags);
    }

    fn finish(&mut self, _ended: bool, out: &mut Vec<Block>, diags: &mut Diags) {
        // The element held for a corner, then the moves held for radius compensation, go out at the
        // program's end; a corner with no element after it is not made.
        let start = out.len();
        self.ex.end_corner(diags);
        self.ex.flush(out, diags, &mut self.interp);
        if let Err(why) = self.ex.comp.stop(self.interp.unit(), self.interp.tilt(), out) {
            diags.error(self.labels.lines.max(1), 1, format!("radius compensation: {}", why.why()));
        }
        self.holds.drop_held(out, start);
        Runner::finish(self, diags);
    }

    fn name(&self) -> Option<String> {
        Runner::name(self).map(String::from)
    }

    fn not_read(&mut self, _line: usize, out: &mut Vec<Block>, diags: &mut Diags) {
        // A stop of compensation there halts the interpreter, which ends the run.
        let start = out.len();
        self.ex.interrupt("the block after it was not read", out, diags, &mut self.interp);
        self.holds.drop_held(out, start);
    }
}
