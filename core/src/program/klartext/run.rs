//! Running a Klartext program: its labels, calls, repeats and jumps, and each statement's block.

use std::borrow::Cow;
use std::collections::HashMap;

use super::{axis_index, label, parse_line, tokens, FeedWord, KWord, Kind, ParseState, PlaneForm, PlaneMode, PlaneStmt, Shape, Stmt, Val, MAX_NESTING};
use crate::machine::ContourTolerance;
use crate::program::interp::{Interpreter, OneShot, Word};
use crate::program::lex::Diags;
use crate::program::stream::{At, Jumping, Next};
use crate::program::{Block, ProgrammedTolerance};
use crate::units::{DEG, MM};

/// The most labels a program may define (the TNC 640 numbers them 1 to 65535 and names others): a
/// label beyond is an error where it stands, and a call to it fails. It bounds the label table.
pub const MAX_LABELS: usize = 100_000;

/// The labels of a program, from a first pass over it (a call may jump forward to a subprogram
/// written after M2/M30): each label's line and where the line after it starts.
#[derive(Debug, Default)]
pub(crate) struct Labels {
    at: HashMap<String, (usize, At)>,
    lines: usize,
}

impl Labels {
    /// Take line `line` (its bytes, without the newline), the line after it starting at `next`.
    pub(crate) fn line(&mut self, line: usize, bytes: &[u8], next: At, diags: &mut Diags) {
        self.lines = line;
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
        }
    }

    /// Run line `line` (without its newline), the line after it starting at `next`: its block
    /// goes to `out`, its defects to `diags`.
    pub(crate) fn line(&mut self, line: usize, raw: &str, next: At, out: &mut Vec<Block>, diags: &mut Diags) -> Next {
        let was_inch = self.st.inch;
        let Some(s) = parse_line(line, raw, &mut self.st, diags) else {
            if self.st.inch != was_inch {
                if let Err(u) = self.interp.set_inch(self.st.inch) {
                    diags.warning(line, 1, format!("the program header says {}; its numbers are read in {} (--units)", if self.st.inch { "INCH" } else { "MM" }, u.name()));
                }
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
                Some((back, _, _)) => Next::Jump(back),
                None => Next::On,
            },
            Kind::Label(_) => Next::On,
            Kind::Call { label, rep } => self.call(&s, label, rep.as_ref(), next, diags),
            // A conditional jump (FN 9-12): on to the line after the label when it holds.
            Kind::Jump { a, cmp, b, label } => match (self.ex.formula(a, s.line, s.col, diags), self.ex.formula(b, s.line, s.col, diags)) {
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
                if self.ex.run(&s, &mut self.interp, out, diags) && self.stack.is_empty() {
                    Next::Ended // M2 / M30: the program ends (subprograms follow it)
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
        Runner::line(self, line, text, next, out, diags)
    }

    fn check(&mut self, line: usize, text: &str, diags: &mut Diags) {
        Runner::check(self, line, text, diags);
    }

    fn finish(&mut self, _ended: bool, _out: &mut Vec<Block>, diags: &mut Diags) {
        Runner::finish(self, diags);
    }

    fn name(&self) -> Option<String> {
        Runner::name(self).map(String::from)
    }
}

/// Run-time state besides the interpreter's.
#[derive(Debug, Default)]
struct Exec {
    q: HashMap<String, f64>,
    /// The machine, for tilted working planes (its kinematics and limits).
    machine: Option<std::sync::Arc<crate::machine::Machine>>,
    /// The cycle defined last (CYCL DEF), which CYCL CALL, M99 and M89 run.
    cycle: Option<(u32, usize)>,
    /// M89: the cycle runs after every positioning block until M99 or CYCL CALL.
    modal_call: bool,
    /// The spindle speed of the last TOOL CALL (1/min), for tapping.
    spindle: Option<f64>,
    /// The feed of the last TOOL CALL (program units per minute, as written), for FAUTO.
    tool_feed: Option<(f64, String)>,
    /// Direction of the contour at its end in the working plane, for CT.
    tangent: Option<[f64; 2]>,
    /// The pole CC in the working plane (its two axes and coordinates, m), for LP and CP.
    pole: Option<([usize; 2], [f64; 2])>,
}

impl Exec {
    /// A formula's value with the parameters set so far; a defect goes to `diags`.
    fn formula(&self, text: &str, line: usize, col: usize, diags: &mut Diags) -> Option<f64> {
        match super::formula::eval(text, &|n| self.q.get(n).copied()) {
            Ok(v) => Some(v),
            Err(e) => {
                diags.error(line, col, format!("'{}': {}", crate::program::lex::excerpt(text), e.message));
                None
            }
        }
    }

    fn value(&self, w: &KWord<'_>, line: usize, diags: &mut Diags) -> Option<f64> {
        match &w.val {
            Val::Num(v) => Some(*v),
            Val::Q { name, negative } => match self.q.get(*name) {
                Some(v) => Some(if *negative { -v } else { *v }),
                None => {
                    diags.error(line, w.col, format!("{}: {name} is used before it is set", w.addr));
                    None
                }
            },
        }
    }

    /// Run one statement, its block to `out`; true if it ends the program (M2, M30).
    fn run<'a>(&mut self, s: &Stmt<'a>, interp: &mut Interpreter, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        let unit = interp.unit();
        // Statements that set state and run no block.
        match &s.kind {
            Kind::Assign { name, formula } => {
                match self.formula(formula, s.line, s.col, diags) {
                    Some(v) => {
                        self.q.insert(name.clone(), v);
                    }
                    None => diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line))),
                }
                return false;
            }
            Kind::Tolerance { linear, rotary, reset } => {
                let mut tolerance = if *reset { ProgrammedTolerance::default() } else { interp.tolerance() };
                let max = ContourTolerance::MAX;
                // Each part written: its value in SI (from the program's unit, or deg), within 0..=max.
                let parts: [(_, _, _, _, _, _, fn(f64) -> bool); 2] = [
                    (linear, "32.1 T", unit, max.linear_m, MM, "mm", ContourTolerance::linear_ok),
                    (rotary, "32.2 TA", DEG, max.rotary_rad, DEG, "deg", ContourTolerance::rotary_ok),
                ];
                let [l, r] = parts.map(|(w, name, to_si, max, shown, shown_name, ok)| {
                    let w = w.as_ref()?;
                    let v = self.value(w, s.line, diags)? * to_si;
                    if !ok(v) {
                        diags.error(s.line, w.col, format!("CYCL DEF {name}: {} {shown_name} is outside 0 to {} {shown_name}", v / shown, max / shown));
                        return None;
                    }
                    Some(v)
                });
                tolerance.linear_m = l.or(tolerance.linear_m);
                tolerance.rotary_rad = r.or(tolerance.rotary_rad);
                interp.set_tolerance(tolerance);
                return false;
            }
            Kind::Tcp { on, orientation } => {
                interp.set_tcp(*on);
                if let Some(o) = orientation {
                    interp.set_orientation(*o);
                }
                return false;
            }
            Kind::Datum(k, w, incremental) => {
                if let Some(v) = self.value(w, s.line, diags) {
                    let mut datum = interp.datum();
                    datum[*k] = if *incremental { datum[*k] + v * unit } else { v * unit };
                    interp.set_datum(datum);
                }
                return false;
            }
            Kind::Plane(p) => {
                self.plane(p, s, interp, out, diags);
                return false;
            }
            Kind::CycleDef(n) => {
                self.define_cycle(*n, s, interp, diags);
                return false;
            }
            Kind::CycleCall => {
                self.modal_call = false;
                self.call_cycle(s, interp, out, diags);
                return false;
            }
            Kind::End | Kind::Label(_) | Kind::Call { .. } | Kind::Jump { .. } => return false,
            _ => {}
        }
        let before = diags.errors();
        let mut words: Vec<Word<'a>> = Vec::with_capacity(12);
        let word = |letter: char, value: f64, raw: Cow<'a, str>, column: usize, incremental: bool| Word { letter, value, raw, column, incremental };
        let mut ends = false;
        let mut vector = None;
        match &s.kind {
            Kind::Stop => words.push(word('M', 0.0, "0".into(), s.col, false)),
            // The interpreter reads a TNC dwell as G04 F, s.
            Kind::Dwell(w) => {
                if let Some(v) = self.value(w, s.line, diags) {
                    words.push(word('G', 4.0, "04".into(), s.col, false));
                    words.push(word('F', v, w.raw.into(), w.col, false));
                }
            }
            Kind::Tool { events, feed } => {
                if let Some(sp) = events.iter().find_map(|e| e.strip_prefix('S')) {
                    self.spindle = super::parse_val(sp).and_then(|v| match v {
                        Val::Num(n) => Some(n),
                        Val::Q { name, negative } => self.q.get(name).map(|v| if negative { -v } else { *v }),
                    });
                }
                for e in events {
                    let (l, rest) = e.split_at(1);
                    words.push(word(l.chars().next().unwrap_or('T'), 0.0, rest.to_string().into(), s.col, false));
                }
                if let Some(f) = feed {
                    self.tool_feed = self.value(f, s.line, diags).map(|v| (v, f.raw.to_string()));
                }
            }
            Kind::Misc(m) => ends = self.m_words(m, &mut words, s.line, diags),
            Kind::Retract { distance, feed, col } => {
                let d = match distance {
                    Some(w) => self.value(w, s.line, diags).map(|v| Some(v * unit)),
                    None => Some(None),
                };
                if let Some(d) = d {
                    match interp.retract_target(d) {
                        Ok(axes) => {
                            // A move of the axes themselves (origin zero), as M91's are of the machine's.
                            // Without F (or with FMAX) at rapid traverse.
                            let motion = if matches!(feed, FeedWord::Value(_)) { crate::program::Motion::Linear } else { crate::program::Motion::Rapid };
                            interp.oneshot = Some(OneShot { motion, absolute: true, axes: Some([0.0; 3]), own: true });
                            for (k, letter) in ['X', 'Y', 'Z'].into_iter().enumerate() {
                                words.push(word(letter, axes[k] / unit, format!("{}", axes[k] / unit).into(), *col, false));
                            }
                            if let FeedWord::Value(f) = feed {
                                if let Some(v) = self.value(f, s.line, diags) {
                                    words.push(word('F', v, f.raw.into(), f.col, false));
                                }
                            }
                        }
                        Err(why) => diags.error(s.line, *col, format!("M140: {why}")),
                    }
                }
            }
            Kind::Centre(axes) => {
                let pos = interp.position();
                let (a0, a1, _) = interp.plane().axes();
                let mut c = [pos[a0], pos[a1]];
                for w in axes {
                    let k = axis_index(w.addr);
                    let Some(v) = self.value(w, s.line, diags) else { continue };
                    let incremental = w.addr.starts_with('I');
                    let slot = if k == a0 {
                        0
                    } else if k == a1 {
                        1
                    } else {
                        diags.error(
                            s.line,
                            w.col,
                            format!(
                                "CC {}: not an axis of the working plane ({}{}, from the TOOL CALL's axis): \"the TNC assigns a circle to one of the main planes\", \"defined when you set the spindle axis during TOOL CALL\" (TNC 425/415 B/407 user's manual §5, Circles in the main planes)",
                                w.addr,
                                ['X', 'Y', 'Z'][a0],
                                ['X', 'Y', 'Z'][a1]
                            ),
                        );
                        continue;
                    };
                    c[slot] = if incremental { pos[k] + v * unit } else { v * unit };
                }
                for (slot, k) in [a0, a1].into_iter().enumerate() {
                    words.push(word(['I', 'J', 'K'][k], c[slot] / unit, format!("{}", c[slot] / unit).into(), s.col, false));
                }
                self.pole = Some(([a0, a1], c));
            }
            Kind::Move { shape, axes, ccw, radius, feed, m } => {
                let mut tool = [None; 3];
                let mut normal = [None; 3];
                if matches!(shape, Shape::LinePolar | Shape::CirclePolar) {
                    match self.polar(*shape, axes, *ccw, interp, s, diags) {
                        Some((end, turns)) => {
                            let (a0, a1, _) = interp.plane().axes();
                            for (k, v) in [(a0, end[0]), (a1, end[1])] {
                                words.push(word(['X', 'Y', 'Z'][k], v / unit, format!("{}", v / unit).into(), s.col, false));
                            }
                            if turns > 1 {
                                words.push(word('P', turns as f64, format!("{turns}").into(), s.col, false));
                            }
                        }
                        None => return false,
                    }
                }
                for w in axes.iter().filter(|w| !w.addr.ends_with("PR") && !w.addr.ends_with("PA")) {
                    let Some(v) = self.value(w, s.line, diags) else { continue };
                    match w.addr.as_bytes()[0] {
                        b'N' => normal[axis_index(w.addr)] = Some(v),
                        b'T' => tool[axis_index(w.addr)] = Some(v),
                        _ => {
                            let letter = w.addr.as_bytes()[w.addr.len() - 1] as char;
                            words.push(word(letter, v, w.raw.into(), w.col, w.addr.len() == 2))
                        }
                    }
                }
                ends = self.m_words(m, &mut words, s.line, diags);
                let g = match (shape, feed) {
                    (Shape::Line | Shape::LineNormal | Shape::LinePolar, FeedWord::Max) => "0",
                    (Shape::Line | Shape::LineNormal | Shape::LinePolar, _) => "1",
                    (Shape::Circle | Shape::CircleRadius | Shape::CirclePolar, _) if *ccw == Some(true) => "3",
                    (Shape::Circle | Shape::CircleRadius | Shape::CirclePolar, _) => "2",
                    (Shape::CircleTangent, _) => match self.tangent_arc(&words, interp, s, diags) {
                        Some((g, r)) => {
                            words.push(word('R', r, format!("{r}").into(), s.col, false));
                            g
                        }
                        None => "1",
                    },
                };
                words.push(word('G', if g == "0" { 0.0 } else { g.parse().unwrap_or(1.0) }, g.into(), s.col, false));
                if let Some(r) = radius {
                    if let Some(v) = self.value(r, s.line, diags) {
                        words.push(word('R', v, r.raw.into(), r.col, false));
                    }
                }
                match feed {
                    FeedWord::Value(f) => {
                        if let Some(v) = self.value(f, s.line, diags) {
                            words.push(word('F', v, f.raw.into(), f.col, false));
                        }
                    }
                    FeedWord::Auto(col) => match &self.tool_feed {
                        Some((v, raw)) => words.push(word('F', *v, raw.clone().into(), *col, false)),
                        None => diags.error(s.line, *col, "FAUTO without a feed in the TOOL CALL before it"),
                    },
                    FeedWord::Max | FeedWord::None => {}
                }
                if *shape == Shape::LineNormal {
                    let full = |v: [Option<f64>; 3]| -> Option<[f64; 3]> { Some([v[0]?, v[1]?, v[2]?]) };
                    let m128 = m.iter().any(|w| w.val == Val::Num(128.0));
                    let t = full(tool);
                    if interp.tcp() || m128 {
                        // Under TCPM the tool keeps the orientation T, or without T stands on the normal.
                        let given = if t.is_some() { "TX TY TZ" } else { "NX NY NZ" };
                        if let Some(v) = t.or_else(|| full(normal)) {
                            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                            if n > 1e-9 && n.is_finite() {
                                vector = Some(v.map(|c| c / n));
                            } else {
                                diags.error(s.line, s.col, format!("LN: the vector {given} has zero length: expected a direction"));
                            }
                        }
                    } else if t.is_some() {
                        diags.warning(
                            s.line,
                            s.col,
                            "LN with TX TY TZ but neither M128 nor FUNCTION TCPM: the TNC ignores the tool vector, and so does this reader",
                        );
                    }
                }
            }
            Kind::Assign { .. } | Kind::Tcp { .. } | Kind::Tolerance { .. } | Kind::Datum(..) | Kind::End | Kind::Label(_) | Kind::Call { .. } | Kind::Jump { .. } | Kind::Plane(_) | Kind::CycleDef(_) | Kind::CycleCall => {}
        }
        // M91 / M92: the block's coordinates are the machine's, about its machine datum or the
        // maker's second datum (TNC 426 B ISO §7.3: "M91 and M92 are effective only in the blocks in
        // which they are programmed"; the tool length is not compensated, so they place the axes).
        if let Kind::Move { shape, m, feed, .. } = &s.kind {
            let code = m.iter().find_map(|w| match w.val {
                Val::Num(v) if v == 91.0 || v == 92.0 => Some((v as u32, w.col)),
                _ => None,
            });
            if let Some((code, col)) = code {
                match self.machine_axes(code, interp, *shape, words.iter().any(|w| w.incremental)) {
                    Ok(origin) => {
                        let motion = if matches!(feed, FeedWord::Max) { crate::program::Motion::Rapid } else { crate::program::Motion::Linear };
                        interp.oneshot = Some(OneShot { motion, absolute: true, axes: Some(origin), own: false });
                    }
                    Err(why) => diags.error(s.line, col, format!("M{code}: {why}")),
                }
            }
        }
        if diags.errors() > before {
            diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
            return false;
        }
        if let Some(v) = vector {
            interp.set_pending_vector(v);
        }
        // M99 runs the cycle at the block's end point, M89 from here on after every positioning.
        let (m99, m89) = match &s.kind {
            Kind::Move { m, .. } | Kind::Misc(m) => (m.iter().any(|w| w.val == Val::Num(99.0)), m.iter().any(|w| w.val == Val::Num(89.0))),
            _ => (false, false),
        };
        let words: Vec<Word<'a>> = words.into_iter().filter(|w| !(w.letter == 'M' && (w.value == 99.0 || w.value == 89.0))).collect();
        let start = interp.position();
        let result = interp.block_one(&words, s.line, s.col, s.number, diags);
        match result {
            Some(b) => {
                self.follow(&b, start, interp.position(), interp);
                let moved = !b.targets.is_empty();
                out.push(b);
                if m89 {
                    self.modal_call = true;
                }
                if m99 {
                    self.modal_call = false;
                }
                if m99 || (self.modal_call && moved && !m89) {
                    self.call_cycle(s, interp, out, diags);
                }
                ends
            }
            None => {
                diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
                false
            }
        }
    }

    /// A `PLANE` or cycle 19: the working plane's frame, the rotary positions the control picks
    /// for it ([`crate::program::plane::solve`]), Q120-Q122 (`STAY`), the rotary move (`TURN`).
    fn plane(&mut self, p: &PlaneStmt<'_>, s: &Stmt<'_>, interp: &mut Interpreter, out: &mut Vec<Block>, diags: &mut Diags) {
        use crate::program::plane;
        let what = if p.cycle { "CYCL DEF 19" } else { "PLANE" };
        let Some(machine) = self.machine.clone() else {
            diags.error(s.line, s.col, format!("{what}: a tilted working plane needs the machine's kinematics (--machine)"));
            return;
        };
        let letters: [char; 2] = [3, 4].map(|k| machine.axes[k].name.chars().next().unwrap_or('?').to_ascii_uppercase());
        let pos = interp.position();
        let current = letters.map(|l| "ABC".find(l).map_or(0.0, |k| pos[3 + k]));
        let deg = |w: &KWord<'_>, diags: &mut Diags| self.value(w, s.line, diags).map(|v| v * DEG);
        let before = diags.errors();
        let frame = match &p.form {
            PlaneForm::Reset => None,
            PlaneForm::Spatial(w) => {
                let v: Vec<f64> = w.iter().filter_map(|w| deg(w, diags)).collect();
                (v.len() == 3).then(|| plane::spatial(v[0], v[1], v[2]))
            }
            PlaneForm::Euler(w) => {
                let v: Vec<f64> = w.iter().filter_map(|w| deg(w, diags)).collect();
                (v.len() == 3).then(|| plane::euler_zxz(v[0], v[1], v[2]))
            }
            PlaneForm::Vector(w) => {
                let v: Vec<f64> = w.iter().filter_map(|w| self.value(w, s.line, diags)).collect();
                if v.len() == 6 {
                    match plane::from_vectors(nalgebra::Vector3::new(v[0], v[1], v[2]), nalgebra::Vector3::new(v[3], v[4], v[5])) {
                        Ok(r) => Some(r),
                        Err(why) => {
                            diags.error(s.line, s.col, format!("PLANE VECTOR: {why}"));
                            None
                        }
                    }
                } else {
                    None
                }
            }
            PlaneForm::Points(w) => {
                let v: Vec<f64> = w.iter().filter_map(|w| self.value(w, s.line, diags)).collect();
                let p = |k: usize| nalgebra::Vector3::new(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
                match (v.len() == 9).then(|| plane::from_points(p(0), p(1), p(2))) {
                    Some(Ok(r)) => Some(r),
                    Some(Err(why)) => {
                        diags.error(s.line, s.col, format!("PLANE POINTS: {why}"));
                        None
                    }
                    None => None,
                }
            }
            PlaneForm::Relativ(k, w) => deg(w, diags).map(|a| {
                let axis = nalgebra::Unit::new_normalize(nalgebra::Vector3::ith(*k, 1.0));
                interp.tilt().unwrap_or_else(nalgebra::Matrix3::identity) * *nalgebra::Rotation3::from_axis_angle(&axis, a).matrix()
            }),
            PlaneForm::Axial(w) => {
                // Axis positions: the tool's frame there (cycle 19 set up for spatial angles reads
                // them as those instead).
                let mut rot = current;
                let mut spatial = [0.0; 3];
                for w in w {
                    let Some(v) = deg(w, diags) else { continue };
                    let l = w.addr.chars().next().unwrap_or('?');
                    spatial["ABC".find(l).unwrap_or(0)] = v;
                    match letters.iter().position(|&m| m == l) {
                        Some(k) => rot[k] = v,
                        None if p.cycle && machine.cycle19_spatial => {}
                        None => diags.error(s.line, w.col, format!("{what}: the machine has no axis {l} (its rotary axes are {} and {})", letters[0], letters[1])),
                    }
                }
                Some(if p.cycle && machine.cycle19_spatial { plane::spatial(spatial[0], spatial[1], spatial[2]) } else { machine.chain.tool_frame(&rot) })
            }
        };
        if diags.errors() > before {
            return;
        }
        let Some(r) = frame else {
            interp.set_tilt(None);
            return;
        };
        let axial = matches!(p.form, PlaneForm::Axial(_)) && !(p.cycle && machine.cycle19_spatial);
        let rot = if axial {
            let mut rot = current;
            if let PlaneForm::Axial(w) = &p.form {
                for w in w {
                    if let (Some(v), Some(k)) = (self.value(w, s.line, diags), letters.iter().position(|&m| Some(m) == w.addr.chars().next())) {
                        rot[k] = v * DEG;
                    }
                }
            }
            rot
        } else {
            match plane::solve(&machine, &r, current, p.choice) {
                Ok(sol) => {
                    if let Some(pole) = sol.pole {
                        let name = &machine.axes[pole.free_axis].name;
                        // Degrees to 3 decimals, a rounding of zero without its sign.
                        let deg3 = |v: f64| format!("{:.3}", if v.to_degrees().abs() < 5e-4 { 0.0 } else { v.to_degrees() });
                        let table = pole.table_rot.map_or("cannot turn it to the plane's X (a head axis)".into(), |t| format!("turns it to {} deg", deg3(t)));
                        let said = match p.choice.table_rot {
                            Some(true) => "the program says TABLE ROT",
                            Some(false) => "the program says COORD ROT",
                            None => "the program says neither, so it depends on the control's setting; read as COORD ROT",
                        };
                        diags.warning(
                            s.line,
                            s.col,
                            format!(
                                "{what} at the pole: the tool lies along {name}'s axis, which leaves {name} free; COORD ROT keeps it at {} deg, TABLE ROT {table}; {said} ({name} {} deg)",
                                deg3(pole.coord_rot),
                                deg3(sol.rot[pole.free_axis - 3])
                            ),
                        );
                    }
                    sol.rot
                }
                Err(why) => {
                    diags.error(s.line, s.col, format!("{what}: {why}"));
                    return;
                }
            }
        };
        // STAY (and TURN): the angles the control computed, in Q120 (A), Q121 (B), Q122 (C).
        if p.mode != PlaneMode::Cycle {
            for (k, l) in letters.iter().enumerate() {
                if let Some(i) = "ABC".find(*l) {
                    self.q.insert(format!("Q{}", 120 + i), rot[k] / DEG);
                }
            }
        }
        interp.set_tilt(Some(r));
        if p.mode == PlaneMode::Turn {
            let mut words: Vec<Word<'static>> = letters.iter().zip(rot).map(|(l, v)| Word { letter: *l, value: v / DEG, raw: Cow::Owned(format!("{:.6}", v / DEG)), column: s.col, incremental: false }).collect();
            match &p.feed {
                FeedWord::Value(f) => {
                    let Some(v) = self.value(f, s.line, diags) else { return };
                    words.push(Word { letter: 'G', value: 1.0, raw: "1".into(), column: s.col, incremental: false });
                    words.push(Word { letter: 'F', value: v, raw: Cow::Owned(f.raw.to_string()), column: f.col, incremental: false });
                }
                _ => words.push(Word { letter: 'G', value: 0.0, raw: "0".into(), column: s.col, incremental: false }),
            }
            if let Some(b) = interp.block_one(&words, s.line, s.col, s.number, diags) {
                out.push(b);
            }
        }
    }

    /// `CYCL DEF n`: the drilling cycles 200, 207, 240 are kept for the next call; cycle 247 selects
    /// a preset of the machine's table (its values are the operator's: the datum is taken as the
    /// workpiece's, and linear ranges are not judged); the machine maker's own cycles that move
    /// nothing are in its file; any other is refused.
    fn define_cycle(&mut self, n: u32, s: &Stmt<'_>, interp: &mut Interpreter, diags: &mut Diags) {
        match n {
            200 | 207 | 240 => self.cycle = Some((n, s.line)),
            247 => interp.set_preset_assumed(),
            _ if self.machine.as_ref().is_some_and(|m| m.state_cycles.contains(&n)) => {}
            _ => diags.error(s.line, s.col, format!("CYCL DEF {n}: this cycle is not read (it may move the tool; the drilling cycles 200, 207 and 240 are, and the machine file names its maker's cycles that move nothing)")),
        }
    }

    /// A Q parameter a cycle needs, in SI (`scale` per program unit); why not, if unset.
    fn cycle_q(&self, name: &str, scale: f64) -> Result<f64, String> {
        self.q.get(name).map(|v| v * scale).ok_or_else(|| format!("{name} is not set"))
    }

    /// Run the cycle defined last where the tool stands, along the working plane's Z: its moves as
    /// blocks of this statement (the modal feed stays the program's).
    fn call_cycle(&mut self, s: &Stmt<'_>, interp: &mut Interpreter, out: &mut Vec<Block>, diags: &mut Diags) {
        let Some((n, _)) = self.cycle else {
            diags.error(s.line, s.col, "a cycle call with no cycle defined before it (CYCL DEF)");
            return;
        };
        let unit = interp.unit();
        let hole = (|| -> Result<(crate::program::cycles::TncHole, f64), String> {
            let q = |name: &str| self.cycle_q(name, unit);
            let mut h = crate::program::cycles::TncHole {
                surface: q("Q203")?,
                clearance: q("Q200")?.abs(),
                clearance2: q("Q204")?.abs(),
                depth: q("Q201")?,
                plunge: 0.0,
                dwell_top_s: 0.0,
                dwell_bottom_s: 0.0,
                feed_out: false,
            };
            let feed = match n {
                200 => {
                    h.plunge = q("Q202")?.abs();
                    h.dwell_top_s = self.cycle_q("Q210", 1.0)?;
                    h.dwell_bottom_s = self.cycle_q("Q211", 1.0)?;
                    self.cycle_q("Q206", 1.0)?
                }
                240 => {
                    if self.cycle_q("Q343", 1.0)? != 0.0 {
                        return Err("Q343=1: a depth from the centering diameter (the tool's point angle) is not read".into());
                    }
                    h.dwell_bottom_s = self.cycle_q("Q211", 1.0)?;
                    self.cycle_q("Q206", 1.0)?
                }
                _ => {
                    // 207 RIGID TAPPING: the feed is the pitch Q239 at the spindle speed.
                    h.feed_out = true;
                    let pitch = self.cycle_q("Q239", 1.0)?.abs();
                    let speed = self.spindle.ok_or("the spindle speed (TOOL CALL S) is not known")?;
                    pitch * speed.abs()
                }
            };
            if h.depth > 0.0 {
                return Err(format!("Q201={}: a positive depth (drilling up) is not read", h.depth / unit));
            }
            if !(feed > 0.0) {
                return Err("the cycle's feed is not positive".into());
            }
            Ok((h, feed))
        })();
        let (h, feed) = match hole {
            Ok(h) => h,
            Err(why) => {
                diags.error(s.line, s.col, format!("cycle {n} called: {why}"));
                return;
            }
        };
        let saved = interp.feed_state();
        let z = |v: f64, motion: &str| -> Vec<Word<'static>> {
            let mut w = vec![
                Word { letter: 'G', value: if motion == "0" { 0.0 } else { 1.0 }, raw: Cow::Owned(motion.to_string()), column: s.col, incremental: false },
                Word { letter: 'Z', value: v / unit, raw: Cow::Owned(format!("{}", v / unit)), column: s.col, incremental: false },
            ];
            if motion == "1" {
                w.push(Word { letter: 'F', value: feed, raw: Cow::Owned(format!("{feed}")), column: s.col, incremental: false });
            }
            w
        };
        for step in crate::program::cycles::tnc_hole(&h) {
            let block = match step {
                crate::program::cycles::Step::Rapid(v) => interp.block_one(&z(v, "0"), s.line, s.col, s.number, diags),
                crate::program::cycles::Step::Feed(v) => interp.block_one(&z(v, "1"), s.line, s.col, s.number, diags),
                crate::program::cycles::Step::Dwell(t) => Some(Block { dwell_s: Some(t), ..interp.still_block(s.line, s.col, s.number) }),
            };
            match block {
                Some(b) => out.push(b),
                None => break,
            }
        }
        interp.restore_feed(saved);
    }

    /// `LP` and `CP` (iTNC 530 user's manual §6.5 "Path contours—Polar coordinates"): the end point in
    /// the working plane from the pole CC, the polar radius PR (CP: the start's distance to the pole)
    /// and angle PA from the plane's reference axis (X in XY, Y in YZ, Z in ZX), IPR and IPA from
    /// the start's; and a CP's turns (P of its arc: `IPA+720` is two). A plane axis written beside
    /// them, a pole of another plane, a CP whose IPA and DR differ in sign ("Define the same algebraic
    /// sign for the direction of rotation DR and the incremental total angle IPA. The tool may
    /// otherwise move on a wrong path", TNC7 user's manual, Programming a helix) are refused.
    fn polar(&self, shape: Shape, axes: &[KWord<'_>], ccw: Option<bool>, interp: &Interpreter, s: &Stmt<'_>, diags: &mut Diags) -> Option<([f64; 2], u64)> {
        let (a0, a1, _) = interp.plane().axes();
        let key = if shape == Shape::LinePolar { "LP" } else { "CP" };
        let Some((_, pole)) = self.pole.filter(|(axes, _)| *axes == [a0, a1]) else {
            diags.error(s.line, s.col, format!("{key}: no pole CC in the working plane before it"));
            return None;
        };
        // A linear word of the working plane (X, Y, Z or IX ...; not the rotary A B C, nor LN's N and T).
        let linear = |a: &str| a.ends_with(['X', 'Y', 'Z']) && !a.starts_with(['N', 'T']);
        if let Some(w) = axes.iter().find(|w| linear(w.addr) && [a0, a1].contains(&axis_index(w.addr))) {
            diags.error(s.line, w.col, format!("{key} with {}: the end point in the working plane is the polar one", w.addr));
            return None;
        }
        let unit = interp.unit();
        let pos = interp.position();
        let (d0, d1) = (pos[a0] - pole[0], pos[a1] - pole[1]);
        let (r_start, pa_start) = (d0.hypot(d1), d1.atan2(d0).to_degrees());
        let mut get = |name: &str| axes.iter().find(|w| w.addr == name).and_then(|w| self.value(w, s.line, diags));
        let (pr, ipr, pa, ipa) = (get("PR"), get("IPR"), get("PA"), get("IPA"));
        let r = match (pr, ipr) {
            (Some(v), _) => v * unit,
            (_, Some(v)) => r_start + v * unit,
            _ => r_start,
        };
        let (pa, turns) = match (pa, ipa) {
            (Some(v), _) => (v, 1),
            (_, Some(v)) => {
                if shape == Shape::CirclePolar && v != 0.0 && (v > 0.0) != (ccw == Some(true)) {
                    diags.error(s.line, s.col, format!("CP IPA{v:+} with DR{}: the TNC wants the same sign for both, or the tool may move on a wrong path", if ccw == Some(true) { "+" } else { "-" }));
                    return None;
                }
                // Whole turns beyond the first (the arc's P), the end where the total angle ends.
                (pa_start + v, ((v.abs() - 1e-9) / 360.0).floor().max(0.0) as u64 + 1)
            }
            _ => return None,
        };
        if !(r >= 0.0 && r.is_finite()) {
            diags.error(s.line, s.col, format!("{key}: a negative polar radius ({:.4})", r / unit));
            return None;
        }
        if shape == Shape::CirclePolar && r_start < 1e-9 {
            diags.error(s.line, s.col, "CP from the pole itself: a circle of radius 0");
            return None;
        }
        let (sin, cos) = pa.to_radians().sin_cos();
        Some(([pole[0] + r * cos, pole[1] + r * sin], turns))
    }

    /// Where M91's (machine datum) or M92's (the maker's datum) coordinates start, in the model's
    /// frame; why not, if the machine file does not place them or the block cannot take them.
    fn machine_axes(&self, code: u32, interp: &Interpreter, shape: Shape, incremental: bool) -> Result<[f64; 3], String> {
        if interp.tcp() {
            return Err("machine coordinates under M128 / FUNCTION TCPM: the TNC wants it reset first (M129, FUNCTION RESET TCPM)".into());
        }
        if shape != Shape::Line || incremental {
            return Err("machine coordinates are absolute positions of an L block".into());
        }
        let machine = interp.machine_coords().ok_or("the machine file places no machine coordinates ([machine_coordinates] zero_mm)")?;
        let datum = match code {
            92 => machine.m92_datum.ok_or("the machine file gives no M92 datum (machine_coordinates.m92_datum_mm)")?,
            _ => nalgebra::Vector3::zeros(),
        };
        let o = machine.to_axes(datum);
        Ok([o.x, o.y, o.z])
    }

    /// The block's M functions as words; true if one ends the program (M2, M30).
    fn m_words<'a>(&self, m: &[KWord<'a>], words: &mut Vec<Word<'a>>, line: usize, diags: &mut Diags) -> bool {
        let mut ends = false;
        for w in m {
            let v = self.value(w, line, diags).unwrap_or(0.0);
            ends |= v == 2.0 || v == 30.0;
            words.push(Word { letter: 'M', value: v, raw: w.raw.into(), column: w.col, incremental: false });
        }
        ends
    }

    /// `CT`: the arc from the current point, tangent to the contour before it, to the block's end in
    /// the working plane: its direction (G02/G03) and signed radius (negative over 180 deg).
    fn tangent_arc(&self, words: &[Word<'_>], interp: &Interpreter, s: &Stmt, diags: &mut Diags) -> Option<(&'static str, f64)> {
        let Some(t) = self.tangent else {
            diags.error(s.line, s.col, "CT: no contour element before it to be tangent to");
            return None;
        };
        let unit = interp.unit();
        let pos = interp.position();
        let (a0, a1, _) = interp.plane().axes();
        let mut end = [pos[a0], pos[a1]];
        for w in words {
            let Some(k) = "XYZ".find(w.letter) else { continue };
            let slot = if k == a0 { 0 } else if k == a1 { 1 } else { continue };
            end[slot] = if w.incremental { pos[k] + w.value * unit } else { w.value * unit };
        }
        let d = [end[0] - pos[a0], end[1] - pos[a1]];
        let n = [-t[1], t[0]]; // left of the tangent
        let dn = d[0] * n[0] + d[1] * n[1];
        let dd = d[0] * d[0] + d[1] * d[1];
        if dd == 0.0 || dn.abs() <= 1e-9 * dd.sqrt() {
            diags.error(s.line, s.col, "CT: the end point lies on the tangent (a straight line, not an arc)");
            return None;
        }
        let signed = dd / (2.0 * dn); // centre = start + signed * n
        let over_half = d[0] * t[0] + d[1] * t[1] < 0.0;
        let r = signed.abs() / unit * if over_half { -1.0 } else { 1.0 };
        Some((if signed > 0.0 { "3" } else { "2" }, r))
    }

    /// Keep the contour's end direction for a later CT.
    fn follow(&mut self, b: &Block, start: [f64; 6], end: [f64; 6], interp: &Interpreter) {
        let (a0, a1, _) = interp.plane().axes();
        if let Some(arc) = &b.arc {
            let r = [end[a0] - arc.centre[a0], end[a1] - arc.centre[a1]];
            let n = r[0].hypot(r[1]);
            if n > 0.0 {
                let ccw = b.motion == crate::program::Motion::ArcCcw;
                self.tangent = Some(if ccw { [-r[1] / n, r[0] / n] } else { [r[1] / n, -r[0] / n] });
            }
        } else if !b.targets.is_empty() {
            let d = [end[a0] - start[a0], end[a1] - start[a1]];
            let n = d[0].hypot(d[1]);
            self.tangent = if n > 0.0 { Some([d[0] / n, d[1] / n]) } else { None };
        }
    }
}
