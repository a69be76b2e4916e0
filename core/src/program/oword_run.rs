//! Running LinuxCNC's O-word blocks a part at a time: a held block, and each subroutine a call runs
//! in it, is a [`Frame`] on a stack (its lines, where it stands, what matching its lines learnt);
//! [`Rs274Reader::flow_more`] runs the frames until they have made [`RUN_CHUNK`] moves, and the
//! stream hands those out before it asks for more (the next line of the program is read once the
//! stack is empty). A loop of any length so holds its lines and a chunk of moves, not every move it
//! makes ([`super::oword`] holds the blocks and reads the O words).

use super::lex::Diags;
use super::later_subs::Line;
use super::oword::{closer, opens, parse, word, End, OLine, Keyword, MAX_CALL_DEPTH, MAX_HELD_LINES};
use super::params::expr::Compiled;
use super::params::Scope;
use super::rs274::{ReadLine, Rs274Reader};
use super::Block;
use std::collections::HashMap;
use std::sync::Arc;

/// How many moves a run makes before the stream hands them out and asks for more.
pub const RUN_CHUNK: usize = 1024;

/// A line's O word, the column it stands at and its characters from there, if it is a control line.
type Control = Option<(OLine, usize, Vec<char>)>;

/// Line `text` read as a control line, if it is one.
fn control(text: &str) -> Control {
    let chars: Vec<char> = text.trim_end_matches('\r').chars().collect();
    let first = chars.iter().position(|c| !c.is_whitespace()).unwrap_or(chars.len());
    parse(&chars[first..]).map(|o| (o, first, chars[first..].to_vec()))
}

/// The most distinct labels of `if`, `while` and `repeat` blocks a run keeps (for LinuxCNC's
/// duplicate-label check): memory bounded whatever the program's length.
const MAX_LABELS: usize = 100_000;

/// One run of lines in progress: a held block (the program's level) or a subroutine's body.
#[derive(Debug, Clone)]
pub(super) struct Frame {
    lines: Arc<Vec<Line>>,
    /// The lines run are `lines[start..start + parsed.len()]` (a subroutine's without its `sub` and
    /// `endsub` lines).
    start: usize,
    /// Each line's O word, the column it stands at and its characters from there (a loop's test is
    /// evaluated from them on every pass); for each opening line its end, for each end or branch
    /// its opener, for each `if` its branches.
    parsed: Vec<Control>,
    ends: Vec<Option<usize>>,
    openers: Vec<Option<usize>>,
    branches: HashMap<usize, Vec<usize>>,
    /// Each test compiled once, when first run; each plain line read once, when first run (a
    /// loop's passes evaluate it with the parameters as they stand), let go when the run ends.
    tests: Vec<Option<Compiled>>,
    kept: Vec<Option<ReadLine>>,
    repeats: HashMap<usize, f64>,
    /// Each line whose label has been checked against the others' (the flow's `labels`): once a run.
    labelled: Vec<bool>,
    pc: usize,
    /// Its lines' blocks did not match (said, the flow stopped): it ends at once.
    broken: bool,
    sub: Option<SubRun>,
}

/// What a subroutine's frame gives back when it ends, and how to run it again (`M98 L`).
#[derive(Debug, Clone)]
pub(super) struct SubRun {
    pub name: String,
    pub shown: String,
    pub sub: (Arc<Vec<Line>>, bool),
    pub args: Option<Vec<f64>>,
    /// The call's line and 0-based column.
    pub line: usize,
    pub col: usize,
    scope: Option<Scope>,
    /// The `endsub` line, whose `[value]` is returned when the body runs to it (M99 returns none).
    endsub: Option<Line>,
    /// A subroutine of another file: the file (its blocks and diagnostics stand at the call, a
    /// diagnostic naming its own line there).
    file: Option<String>,
    /// `M98 L`: passes still to run after this one.
    pub passes_left: f64,
}

impl SubRun {
    /// A call of `name` (`shown` in messages) at `line`, 0-based column `col`, run `passes` times.
    pub fn new(name: &str, shown: &str, sub: (Arc<Vec<Line>>, bool), args: Option<Vec<f64>>, line: usize, col: usize, passes: f64) -> SubRun {
        SubRun { name: name.to_string(), shown: shown.to_string(), sub, args, line, col, scope: None, endsub: None, file: None, passes_left: passes - 1.0 }
    }
}

/// A subroutine of another file running: where its call stands (line, 1-based column) and what its
/// lines said (said at the call, naming the file, when it returns).
#[derive(Debug, Clone)]
pub(super) struct FileRun {
    call: (usize, usize),
    diags: Diags,
}

/// Blocks made inside a subroutine of another file stand at the outermost such call (`call`: its
/// line and 1-based column, None outside any).
fn at_file_call(call: Option<(usize, usize)>, blocks: &mut [Block]) {
    if let Some((line, col)) = call {
        for b in blocks {
            (b.line, b.column) = (line, col);
        }
    }
}

/// What one step of a frame came to.
enum Step {
    Next,
    /// A call: its subroutine's frame runs next, then this one goes on (boxed: a frame is large).
    Call(Box<Frame>),
    Done(End),
}

impl Rs274Reader {
    /// Run `lines` (a held block, or a call alone on its line) from the program's level: its first
    /// moves now, the rest as the stream asks ([`Rs274Reader::flow_more`]).
    pub(super) fn run_block(&mut self, lines: Vec<Line>, out: &mut Vec<Block>, diags: &mut Diags) {
        let len = lines.len();
        let frame = self.frame(Arc::new(lines), 0, len, None, diags);
        self.flow.stack.push(frame);
        self.flow_more(out, diags);
    }

    /// Run the frames on the stack until they have made [`RUN_CHUNK`] more moves or none is left;
    /// true if a run goes on (ask again before the next line).
    pub(super) fn flow_more(&mut self, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        let goal = out.len() + RUN_CHUNK;
        while let Some(mut f) = self.flow.stack.pop() {
            let before = out.len();
            // Where the blocks of these steps stand: taken before a call among them enters another.
            let file_call = self.flow.file_runs.first().map(|r| r.call);
            // The frame runs on until it calls, ends, or the chunk is full.
            let step = loop {
                if out.len() >= goal {
                    break None;
                }
                match self.in_target(diags, |this, target| this.step(&mut f, out, target)) {
                    Step::Next => {}
                    other => break Some(other),
                }
            };
            // A subroutine of another file runs at its call: its blocks stand at the outermost
            // such call's line (what its end gives back, as a caller's, below).
            at_file_call(file_call, &mut out[before..]);
            let mid = out.len();
            match step {
                None | Some(Step::Next) => self.flow.stack.push(f),
                Some(Step::Call(child)) => {
                    self.flow.stack.push(f);
                    self.flow.stack.push(*child);
                }
                Some(Step::Done(end)) => {
                    if self.end_frame(f, end, out, diags) {
                        // A stop ends every run under it, each subroutine leaving its scope.
                        while let Some(parent) = self.flow.stack.pop() {
                            self.end_frame(parent, End::Stopped, out, diags);
                        }
                    }
                }
            }
            at_file_call(self.flow.file_runs.first().map(|r| r.call), &mut out[mid..]);
            if out.len() >= goal && !self.flow.stack.is_empty() {
                return true;
            }
        }
        false
    }

    /// Run `f` with the diagnostics of the innermost subroutine of another file running (said at
    /// its call when it ends), else `diags`. Taken from its place and put back there: `f` may
    /// enter another file's subroutine, whose own come after it.
    fn in_target<R>(&mut self, diags: &mut Diags, f: impl FnOnce(&mut Self, &mut Diags) -> R) -> R {
        match self.flow.file_runs.len().checked_sub(1) {
            Some(k) => {
                let mut inner = std::mem::take(&mut self.flow.file_runs[k].diags);
                let r = f(self, &mut inner);
                self.flow.file_runs[k].diags = inner;
                r
            }
            None => f(self, diags),
        }
    }

    /// The frame of `lines[start..start + len]`. Every control block in them is matched first: a
    /// name closed by another's end, or a `break` outside its loop, stops the run before anything
    /// moves (the frame is then broken).
    fn frame(&mut self, lines: Arc<Vec<Line>>, start: usize, len: usize, sub: Option<SubRun>, diags: &mut Diags) -> Frame {
        let parsed: Vec<Control> = lines[start..start + len].iter().map(|(_, t)| control(t)).collect();
        let mut f = Frame {
            ends: vec![None; len],
            openers: vec![None; len],
            branches: HashMap::new(),
            tests: vec![None; len],
            kept: vec![None; len],
            repeats: HashMap::new(),
            labelled: vec![false; len],
            pc: 0,
            broken: false,
            sub,
            parsed,
            lines,
            start,
        };
        f.broken = self.match_blocks(&mut f, diags).is_err();
        f
    }

    /// Match the frame's blocks: for each opening line its end, and for an if its branches.
    fn match_blocks(&mut self, f: &mut Frame, diags: &mut Diags) -> Result<(), End> {
        let mut open: Vec<(String, Keyword, usize)> = Vec::new();
        for (i, p) in f.parsed.iter().enumerate() {
            let Some((o, col, _)) = p else { continue };
            if opens(o, open.last().map(|(n, k, _)| (n.as_str(), *k))) {
                open.push((o.name.clone(), o.keyword, i));
                continue;
            }
            let (line, col) = (f.lines[f.start + i].0, col + 1);
            match o.keyword {
                Keyword::ElseIf | Keyword::Else => match open.last() {
                    Some((n, Keyword::If, at)) if *n == o.name => {
                        f.branches.entry(*at).or_default().push(i);
                        f.openers[i] = Some(*at);
                    }
                    _ => return Err(self.stop(line, col, format!("o{} {}: not inside o{} if", o.name, word(o.keyword), o.name), diags)),
                },
                Keyword::EndSub | Keyword::While | Keyword::EndWhile | Keyword::EndIf | Keyword::EndRepeat => match open.pop() {
                    Some((n, k, at)) if n == o.name && closer(k) == o.keyword => {
                        f.ends[at] = Some(i);
                        f.openers[i] = Some(at);
                    }
                    Some((n, k, _)) => return Err(self.stop(line, col, format!("o{} {} ends no block: o{n} {} is open", o.name, word(o.keyword), word(k)), diags)),
                    None if o.keyword == Keyword::EndSub && self.flow.in_m98() => return Err(self.stop(line, col, super::oword::m99_ends(o), diags)),
                    None => return Err(self.stop(line, col, format!("o{} {}: no block of that name is open", o.name, word(o.keyword)), diags)),
                },
                // LinuxCNC's: of a while or do loop only ("no matching while/do label" for a repeat).
                Keyword::Break | Keyword::Continue if !open.iter().any(|(n, k, _)| *n == o.name && matches!(k, Keyword::While | Keyword::Do)) => {
                    return Err(self.stop(line, col, format!("o{} {}: not inside a while or do loop of that name", o.name, word(o.keyword)), diags));
                }
                _ => {}
            }
        }
        if let Some((n, k, at)) = open.first() {
            return Err(self.stop(f.lines[f.start + *at].0, 1, format!("o{n} {}: its block does not end (no o{n} {})", word(*k), word(closer(*k))), diags));
        }
        Ok(())
    }

    /// Run the frame's line at `pc` as the flow says.
    fn step(&mut self, f: &mut Frame, out: &mut Vec<Block>, diags: &mut Diags) -> Step {
        // A defect stopped the flow, or the program ended (M2/M30) inside the block.
        if f.broken || self.flow.stopped || self.program_ended() {
            return Step::Done(End::Stopped);
        }
        let Frame { lines, start, parsed, ends, openers, branches, tests, kept, repeats, labelled, pc, .. } = f;
        let (start, here) = (*start, *pc);
        if here >= parsed.len() {
            return Step::Done(End::Done);
        }
        let (line, text) = (lines[start + here].0, &lines[start + here].1);
        if !self.spend_line(line, diags) {
            return Step::Done(End::Stopped);
        }
        let end_of = |k: usize| ends[k].expect("matched above");
        let opener_of = |k: usize| openers[k].expect("matched above");
        // The main program's M99 is its end, read as a line.
        let depth = self.flow.depth;
        let control = parsed[here].as_ref().filter(|(o, _, _)| !(o.keyword == Keyword::M99 && depth == 0));
        let Some((o, col, chars)) = control else {
            let before = diags.0.len();
            self.loop_line(line, text, &mut kept[here], out, diags);
            // Said once per line, however often the flow runs it.
            let fresh: Vec<_> = diags.0.drain(before..).collect();
            for d in fresh {
                // A full memory of what was said (bounded) says everything again.
                if self.flow.said.len() >= MAX_HELD_LINES || self.flow.said.insert((d.line, d.column, d.message.clone())) {
                    diags.0.push(d);
                }
            }
            *pc += 1;
            return Step::Next;
        };
        let col = *col;
        let opens = matches!(o.keyword, Keyword::If | Keyword::Repeat | Keyword::Do) || o.keyword == Keyword::While && ends[here].is_some();
        if opens && !std::mem::replace(&mut labelled[here], true) {
            // A block's label is its subroutine's (LinuxCNC keys it "sub#label", interp_read.cc
            // read_o): two subroutines may each open `o100 if`; the main program's are its own.
            let key = format!("{}#{}", f.sub.as_ref().map_or("", |s| s.name.as_str()), o.name);
            let labels = &mut self.flow.labels;
            let first = match labels.get(&key) {
                Some(&at) => at,
                None if labels.len() >= MAX_LABELS => return Step::Done(self.stop(line, col + 1, format!("o{}: more than {MAX_LABELS} labels opening blocks", o.name), diags)),
                None => *labels.entry(key).or_insert(line),
            };
            if first != line {
                return Step::Done(self.stop(line, col + 1, format!("o{} {}: the label opens another block on line {first}; LinuxCNC refuses it (\"duplicate O-word label\")", o.name, word(o.keyword)), diags));
            }
        }
        match o.keyword {
            Keyword::Sub => {
                // A subroutine defined inside a block: kept, its body skipped.
                if let (0, Some(&at)) = (self.flow.depth, self.flow.raised.first()) {
                    return Step::Done(self.stop(line, col + 1, super::lcnc_m98::after_l0("a subroutine's definition", at), diags));
                }
                let end = end_of(here);
                self.flow.subs.insert(o.name.clone(), (Arc::new(lines[start + here..=start + end].to_vec()), false));
                *pc = end + 1;
            }
            Keyword::EndSub | Keyword::Return if self.flow.in_m98() => {
                return Step::Done(self.stop(line, col + 1, super::oword::m99_ends(o), diags));
            }
            Keyword::EndSub | Keyword::Return => {
                return match self.return_value(o, chars, line, col, diags) {
                    true => Step::Done(End::Return),
                    false => Step::Done(End::Stopped),
                };
            }
            Keyword::Call | Keyword::M98 => {
                let call = if o.keyword == Keyword::Call { self.call(o, chars, line, col, diags) } else { self.m98(chars, o.rest, line, col, diags) };
                *pc += 1;
                return match call {
                    Ok(Some(sub)) => match self.enter_sub(sub, diags) {
                        Ok(child) => Step::Call(Box::new(child)),
                        Err(end) => Step::Done(end),
                    },
                    Ok(None) => Step::Next,
                    Err(end) => Step::Done(end),
                };
            }
            Keyword::M99 => {
                if !self.flow.in_m98() {
                    return Step::Done(self.stop(line, col + 1, "M99 in a subroutine called by o-call: it ends with o endsub or o return (LinuxCNC: \"'O.... endsub' or 'O.... return' must follow 'O.... sub' subroutine definition\")".into(), diags));
                }
                if !super::lcnc_m98::only_comments(chars, o.rest) {
                    return Step::Done(self.stop(line, col + 1, "M99: nothing but a comment may follow it on its line (LinuxCNC: \"Unexpected character after O-word\")".into(), diags));
                }
                self.flow.value = (0.0, false);
                return Step::Done(End::Return);
            }
            Keyword::Title => {
                if self.flow.depth > 0 && !self.flow.in_m98() {
                    return Step::Done(self.stop(line, col + 1, format!("O{}: a Fanuc-style program start inside a subroutine called by o-call (LinuxCNC: \"Fanuc 'O....' subroutine must be called with 'M98'\")", o.name), diags));
                }
                *pc += 1;
            }
            Keyword::Do => *pc += 1,
            Keyword::While if ends[here].is_some() => {
                // A while loop: its condition, here.
                let Some(c) = self.condition(o, chars, line, col, &mut tests[here], diags) else { return Step::Done(End::Stopped) };
                *pc = if c { here + 1 } else { end_of(here) + 1 };
            }
            Keyword::While => {
                // The end of a do loop: again while its condition holds.
                let Some(c) = self.condition(o, chars, line, col, &mut tests[here], diags) else { return Step::Done(End::Stopped) };
                *pc = if c { opener_of(here) + 1 } else { here + 1 };
            }
            Keyword::EndWhile => *pc = opener_of(here),
            Keyword::Repeat => {
                let Some(n) = self.count(o, chars, line, col, &mut tests[here], diags) else { return Step::Done(End::Stopped) };
                if n >= 1.0 {
                    repeats.insert(here, n);
                    *pc += 1;
                } else {
                    *pc = end_of(here) + 1;
                }
            }
            Keyword::EndRepeat => {
                let opener = opener_of(here);
                let left = repeats.get(&opener).copied().unwrap_or(0.0) - 1.0;
                repeats.insert(opener, left);
                *pc = if left >= 1.0 { opener + 1 } else { here + 1 };
            }
            Keyword::If => {
                let Some(c) = self.condition(o, chars, line, col, &mut tests[here], diags) else { return Step::Done(End::Stopped) };
                if c {
                    *pc += 1;
                    return Step::Next;
                }
                let mut next = end_of(here) + 1;
                for &b in branches.get(&here).map_or(&[][..], |v| &v[..]) {
                    let (bo, bcol, bchars) = parsed[b].as_ref().expect("a branch is an O line");
                    if bo.keyword == Keyword::Else {
                        next = b + 1;
                        break;
                    }
                    let Some(c) = self.condition(bo, bchars, lines[start + b].0, *bcol, &mut tests[b], diags) else { return Step::Done(End::Stopped) };
                    if c {
                        next = b + 1;
                        break;
                    }
                }
                *pc = next;
            }
            // The branch taken has ended: past the if's end.
            Keyword::ElseIf | Keyword::Else => *pc = end_of(opener_of(here)) + 1,
            Keyword::EndIf => *pc += 1,
            Keyword::Break | Keyword::Continue => {
                // The innermost open loop of that name around this line.
                let opener = (0..here)
                    .rev()
                    .find(|&k| parsed[k].as_ref().is_some_and(|(l, _, _)| l.name == o.name && matches!(l.keyword, Keyword::While | Keyword::Do) && ends.get(k).copied().flatten().is_some_and(|e| e > here)))
                    .expect("matched above");
                let end = end_of(opener);
                *pc = match (o.keyword, parsed[opener].as_ref().map(|(l, _, _)| l.keyword)) {
                    (Keyword::Break, _) => end + 1,
                    // Continue: to the loop's test (a while's head, a do's tail).
                    (_, Some(Keyword::While)) => opener,
                    _ => end,
                };
            }
        }
        Step::Next
    }

    /// A call begins: the subroutine's scope entered (`#1`-`#30` its arguments, or kept for an
    /// `M98`), one call level deeper, and its body's frame.
    pub(super) fn enter_sub(&mut self, mut sub: SubRun, diags: &mut Diags) -> Result<Frame, End> {
        if self.flow.depth() >= MAX_CALL_DEPTH {
            return Err(self.stop(sub.line, sub.col + 1, format!("{}: calls nested more than {MAX_CALL_DEPTH} deep", sub.shown), diags));
        }
        let fanuc = sub.sub.1;
        sub.scope = Some(match &sub.args {
            Some(args) => self.params.enter_call(args),
            None => self.params.enter_m98(),
        });
        self.flow.depth += 1;
        self.flow.frames.push(fanuc);
        self.contexts.enter(self.flow.depth);
        let body = Arc::clone(&sub.sub.0);
        // The body, without its `sub` and `endsub` lines.
        let len = body.len().saturating_sub(2);
        sub.endsub = body.last().filter(|_| body.len() > 1 && !fanuc).cloned();
        if fanuc {
            self.flow.value = (0.0, false);
        }
        // A subroutine of another file runs at the call: its blocks and diagnostics stand at the
        // call's line, a diagnostic naming its own.
        sub.file = self.flow.files.get(&sub.name).cloned();
        if sub.file.is_some() {
            self.flow.file_runs.push(FileRun { call: (sub.line, sub.col + 1), diags: Diags::default() });
        }
        let start = 1.min(body.len());
        // Its lines' defects: in its own file's diagnostics (just pushed), else the caller's.
        let frame = match sub.file.is_some() {
            true => self.in_target(diags, |this, target| this.frame(body, start, len, Some(sub), target)),
            false => self.frame(body, start, len, Some(sub), diags),
        };
        Ok(frame)
    }

    /// A frame has ended (`end`): its lines let go; a subroutine's scope left, its value returned,
    /// the caller's modal state back (M73), and an `M98`'s next pass begun. True if the flow
    /// stopped (every frame under it ends too).
    fn end_frame(&mut self, f: Frame, end: End, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        self.let_go(f.kept.iter().flatten());
        let Some(mut sub) = f.sub else {
            // A held block at the program's level: a return in it ends it.
            return matches!(end, End::Stopped);
        };
        let (line, col) = (sub.line, sub.col);
        if let Some(file) = &sub.file {
            let inner = self.flow.file_runs.pop().map_or_else(Diags::default, |r| r.diags);
            self.in_target(diags, |_, target| {
                for d in inner.0 {
                    let message = format!("in {file}:{}:{}: {}", d.line, d.column, d.message);
                    match d.severity {
                        super::Severity::Error => target.error(line, col + 1, message),
                        _ => target.warning(line, col + 1, message),
                    }
                }
            });
        }
        let end = match (end, &sub.endsub) {
            (End::Done, Some((l, text))) => match control(text) {
                Some((e, first, chars)) if !self.in_target(diags, |this, target| this.return_value(&e, &chars, *l, first, target)) => End::Stopped,
                _ => End::Done,
            },
            (end, _) => end,
        };
        let restore = self.contexts.leave(self.flow.depth);
        self.flow.depth -= 1;
        self.flow.frames.pop();
        if let Some(scope) = sub.scope.take() {
            self.params.leave_call(scope);
        }
        if matches!(end, End::Stopped) {
            return true;
        }
        // M73 in the subroutine: its caller's state comes back as it returns.
        if let Some(state) = restore {
            let restored = self.in_target(diags, |this, target| this.interp.restore_modal(&state, line, col + 1, None, target, out));
            if !restored {
                self.in_target(diags, |this, target| this.stop(line, col + 1, format!("{}: the modal state M73 saved could not be restored as it returns", sub.shown), target));
                return true;
            }
        }
        // M98 L: LinuxCNC runs the M98 block again for each pass, each a line run.
        if sub.passes_left >= 1.0 && !self.program_ended() {
            if !self.in_target(diags, |this, target| this.spend_line(line, target)) {
                return true;
            }
            let next = SubRun { passes_left: sub.passes_left - 1.0, scope: None, endsub: None, file: None, ..sub };
            match self.in_target(diags, |this, target| this.enter_sub(next, target)) {
                Ok(child) => self.flow.stack.push(child),
                Err(_) => return true,
            }
        }
        false
    }
}
