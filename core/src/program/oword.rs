//! LinuxCNC's O-word control flow (LinuxCNC manual, "O Codes"): `sub`/`endsub`/`call`/`return`,
//! `while`/`endwhile`, `do`/`while`, `repeat`/`endrepeat`, `if`/`elseif`/`else`/`endif`, `break`,
//! `continue` (of a while or do loop), each block named by its O number (`o100`) or name (`o<name>`), the same on every line
//! of the block, conditions and counts in `[...]` as the parameters evaluate them.
//!
//! The reader streams lines; a control block is held (bounded) from its opening line to its end,
//! then run: its lines read as the interpreter would, as many times as the flow says, within a
//! budget of lines run (an endless loop is an error at its line, not a hang). A subroutine is held
//! until called; its arguments are `#1`-`#30`, and its numbered `#1`-`#30` and named parameters
//! without a leading `_` are its own (LinuxCNC's scoping), restored when it returns. A call of a
//! subroutine not defined before it is read from its own file `name.ngc` where the reader was given
//! LinuxCNC's SUBROUTINE_PATH ([`SubroutineFiles`]), and refused otherwise: the motion would depend
//! on a program not read.

use super::lex::{excerpt, Diags};
use super::later_subs::Line;
use super::params::skip_blanks;
use super::params::expr::{self, Compiled};
use super::params::ExprError;
use super::rs274::Rs274Reader;
use super::Block;
use std::collections::HashMap;
use std::sync::Arc;

/// Where an RS274NGC program's subroutines of other files come from (LinuxCNC's SUBROUTINE_PATH):
/// the core reads no file, whoever does (the command line's `--subroutine-path`) finds them.
pub trait SubroutineFiles: Send + Sync + std::fmt::Debug {
    /// The first file named as one of `names` (in that order; `any_case`: letters' case aside, as
    /// the 840D's names are), in the program's own directory where `own_dir` (the 840D's search path
    /// starts there), else in the directories given: where it was found (for messages) and its
    /// bytes, at most [`MAX_HELD_BYTES`]; `Ok(None)` where there is none; an error names the file
    /// and why.
    fn find_file(&self, names: &[String], any_case: bool, own_dir: bool) -> Result<Option<(String, Vec<u8>)>, String>;

    /// LinuxCNC's subroutine file `STEM.ngc`, on the directories given.
    fn find(&self, stem: &str) -> Result<Option<(String, Vec<u8>)>, String> {
        // A name is a file name, not a path (LinuxCNC's find_ngc_file also expands one; not here).
        if stem.is_empty() || stem.contains(['/', '\\']) || stem == ".." {
            return Err(format!("o<{stem}>: not a file name"));
        }
        self.find_file(&[format!("{stem}.ngc")], false, false)
    }

    /// Whether directories were given to search (not only the program's own).
    fn has_dirs(&self) -> bool {
        true
    }
}

/// The most lines one held block (a loop, a condition, a subroutine) may have, and bytes.
pub const MAX_HELD_LINES: usize = 100_000;
pub const MAX_HELD_BYTES: usize = 16 << 20;
/// Deepest nesting of subroutine calls (LinuxCNC's `MAX_NESTED_CALLS`... its stack is 10 deep).
pub const MAX_CALL_DEPTH: usize = 10;
/// Most subroutines one program may define.
pub const MAX_SUBS: usize = 10_000;

/// An O word's keyword.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Keyword {
    Sub,
    EndSub,
    Call,
    Return,
    Do,
    While,
    EndWhile,
    If,
    ElseIf,
    Else,
    EndIf,
    Repeat,
    EndRepeat,
    Break,
    Continue,
    /// An O word alone (`O1000`, `O<name>`, a comment after it): LinuxCNC's Fanuc-style program or
    /// subprogram start ([`super::lcnc_m98`]).
    Title,
    /// `M98` first in its line: a Fanuc-style call.
    M98,
    /// `M99` first in its line: a Fanuc-style return (the program's end in the main program).
    M99,
}

impl Keyword {
    /// The keyword a lower-case word names, if any.
    pub(crate) fn of(word: &str) -> Option<Keyword> {
        Some(match word {
            "sub" => Keyword::Sub,
            "endsub" => Keyword::EndSub,
            "call" => Keyword::Call,
            "return" => Keyword::Return,
            "do" => Keyword::Do,
            "while" => Keyword::While,
            "endwhile" => Keyword::EndWhile,
            "if" => Keyword::If,
            "elseif" => Keyword::ElseIf,
            "else" => Keyword::Else,
            "endif" => Keyword::EndIf,
            "repeat" => Keyword::Repeat,
            "endrepeat" => Keyword::EndRepeat,
            "break" => Keyword::Break,
            "continue" => Keyword::Continue,
            _ => return None,
        })
    }
}

/// One O-word line: the block's name (lower case, `100` or `<name>`), its keyword, and where what
/// follows the keyword starts (a condition, a count, a call's arguments).
#[derive(Debug, Clone)]
pub struct OLine {
    pub name: String,
    pub keyword: Keyword,
    pub rest: usize,
    /// A call's subroutine named by an expression (`o[#2 * 10] call`, `o#<sub> call`, LinuxCNC's
    /// tests/interp o-expression-call and oword-bug315): where it starts, evaluated when the call runs.
    pub name_expr: Option<usize>,
}

/// The O-word control line at the start of `chars`, if it is one (or LinuxCNC's Fanuc-style `M98`
/// or `M99` line, [`super::lcnc_m98::call_or_return`]).
pub fn parse(chars: &[char]) -> Option<OLine> {
    if let Some((keyword, rest)) = super::lcnc_m98::call_or_return(chars.iter().copied()) {
        return Some(OLine { name: String::new(), keyword, rest, name_expr: None });
    }
    if !matches!(chars.first(), Some('o' | 'O')) {
        return None;
    }
    let mut i = skip_blanks(chars, 1);
    let start = i;
    if matches!(chars.get(i), Some('#' | '[')) {
        // A call's name computed: the expression, then `call`.
        let (_, end) = expr::value(chars, i, false).ok()?;
        let k = skip_blanks(chars, end);
        let e = (k..chars.len()).find(|&e| !chars[e].is_ascii_alphabetic()).unwrap_or(chars.len());
        let word: String = chars[k..e].iter().flat_map(|c| c.to_lowercase()).collect();
        return (Keyword::of(&word)? == Keyword::Call).then_some(OLine { name: String::new(), keyword: Keyword::Call, rest: e, name_expr: Some(i) });
    }
    if chars.get(i) == Some(&'<') {
        i += chars[i..].iter().position(|&c| c == '>')? + 1;
    } else {
        while chars.get(i).is_some_and(|c| c.is_ascii_digit()) {
            i += 1;
        }
        if i == start {
            return None;
        }
    }
    let name: String = chars[start..i].iter().filter(|c| !c.is_whitespace()).flat_map(|c| c.to_lowercase()).collect();
    // `o0100` is `o100` (LinuxCNC reads the number, then prints it); `o0` stays `0`.
    let name = match name.trim_start_matches('0') {
        "" if !name.is_empty() => "0".to_string(),
        trimmed => trimmed.to_string(),
    };
    let k = skip_blanks(chars, i);
    // Nothing but a comment after it: a Fanuc-style program start (interp_read.cc read_o, "O2000" with
    // no following args).
    if matches!(chars.get(k), None | Some('(' | ';')) {
        return Some(OLine { name, keyword: Keyword::Title, rest: k, name_expr: None });
    }
    let (word, end) = keyword_at(chars, k)?;
    Some(OLine { name, keyword: Keyword::of(&word)?, rest: end, name_expr: None })
}

/// The O word's keyword at `k`, lower case, and where it ends. LinuxCNC takes the blanks out of a
/// line before reading it ("Spaces and tabs are allowed anywhere on a line of code and do not change
/// the meaning of the line, except inside comments", G-code reference, "Format of a Line"), so
/// `end sub`, `end while` and `else if` are its `endsub`, `endwhile` and `elseif`: the letters are
/// read across blanks where that makes a keyword, else as they run together (`sub G1` stays `sub`).
pub(crate) fn keyword_at(chars: &[char], k: usize) -> Option<(String, usize)> {
    let end = (k..chars.len()).find(|&e| !chars[e].is_ascii_alphabetic()).unwrap_or(chars.len());
    let word: String = chars[k..end].iter().flat_map(|c| c.to_lowercase()).collect();
    // The letters across blanks (a blank run counts only where a letter follows it).
    let (mut joined, mut i, mut joined_end) = (String::new(), k, k);
    while i < chars.len() {
        if chars[i].is_ascii_alphabetic() {
            joined.extend(chars[i].to_lowercase());
            i += 1;
            joined_end = i;
        } else if (chars[i] == ' ' || chars[i] == '\t') && chars[skip_blanks(chars, i)..].first().is_some_and(char::is_ascii_alphabetic) {
            i = skip_blanks(chars, i);
        } else {
            break;
        }
    }
    if joined_end > end && Keyword::of(&joined).is_some() {
        return Some((joined, joined_end));
    }
    (end > k).then_some((word, end))
}

/// The O-word blocks open so far in lines passed over without running them (a Fanuc-style
/// subprogram's body, found or skipped): an `M99` inside one is not the body's end.
#[derive(Debug, Clone, Default)]
pub(crate) struct OpenBlocks(Vec<(String, Keyword)>);

impl OpenBlocks {
    /// Line `o` passed: a block it opens, or the innermost one it closes.
    pub(crate) fn pass(&mut self, o: OLine) {
        if opens(&o, self.0.last().map(|(n, k)| (n.as_str(), *k))) {
            self.0.push((o.name, o.keyword));
        } else if self.0.last().is_some_and(|(n, k)| *n == o.name && closer(*k) == o.keyword) {
            self.0.pop();
        }
    }

    /// Whether no block is open.
    pub(crate) fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// Whether `l` opens a block that must be held to its end (a subroutine, a loop, a condition);
/// `innermost` is the block open around it, if any (a `while` ends the `do` of its name).
pub(super) fn opens(l: &OLine, innermost: Option<(&str, Keyword)>) -> bool {
    match l.keyword {
        Keyword::Sub | Keyword::Do | Keyword::If | Keyword::Repeat => true,
        Keyword::While => innermost != Some((l.name.as_str(), Keyword::Do)),
        _ => false,
    }
}

/// The keyword that ends a block opened by `k`.
pub(super) fn closer(k: Keyword) -> Keyword {
    match k {
        Keyword::Sub => Keyword::EndSub,
        Keyword::Do => Keyword::While,
        Keyword::If => Keyword::EndIf,
        Keyword::Repeat => Keyword::EndRepeat,
        _ => Keyword::EndWhile,
    }
}

pub(super) fn word(k: Keyword) -> &'static str {
    match k {
        Keyword::Sub => "sub",
        Keyword::EndSub => "endsub",
        Keyword::Call => "call",
        Keyword::Return => "return",
        Keyword::Do => "do",
        Keyword::While => "while",
        Keyword::EndWhile => "endwhile",
        Keyword::If => "if",
        Keyword::ElseIf => "elseif",
        Keyword::Else => "else",
        Keyword::EndIf => "endif",
        Keyword::Repeat => "repeat",
        Keyword::EndRepeat => "endrepeat",
        Keyword::Break => "break",
        Keyword::Continue => "continue",
        Keyword::Title => "",
        Keyword::M98 => "M98",
        Keyword::M99 => "M99",
    }
}

/// Why `endsub` or `return` cannot end a Fanuc-style subprogram.
pub(super) fn m99_ends(o: &OLine) -> String {
    format!("o{} {}: a Fanuc-style subprogram (called by M98) ends with M99 (LinuxCNC: \"Fanuc 'O....' subroutine definition must end with 'M99'\")", o.name, word(o.keyword))
}


/// A block being held: its lines so far and the blocks open in it.
#[derive(Debug, Clone, Default)]
struct Held {
    lines: Vec<Line>,
    bytes: usize,
    open: Vec<(String, Keyword, usize)>,
}

/// The control-flow state of one read (no `Default`: a flow without its bound would refuse every
/// loop; [`Flow::new`] takes it).
#[derive(Debug, Clone)]
pub struct Flow {
    held: Option<Held>,
    /// The subroutines known by name (LinuxCNC's one table for both kinds): their lines, with their
    /// `sub` and `endsub` lines (a Fanuc-style one's `O` line and `M99`), and whether Fanuc-style.
    pub(super) subs: HashMap<String, (Arc<Vec<Line>>, bool)>,
    run_lines: usize,
    /// The most lines control blocks may run ([`crate::program::ReadOptions::max_run_lines`]).
    budget: usize,
    pub(super) depth: usize,
    /// The diagnostics said by lines run so far: a loop's second pass over a defect says it once.
    pub(super) said: std::collections::HashSet<(usize, usize, String)>,
    /// Each label's first `if`, `while` or `repeat` run and its line: LinuxCNC keeps one table of
    /// labels for the run and refuses another block opening with one ("duplicate O-word label",
    /// interp_o_word.cc, by line number).
    pub(super) labels: HashMap<String, usize>,
    /// The run was stopped (budget, a defect in the flow): what is left of the block is not read.
    pub(crate) stopped: bool,
    /// Where subroutines not defined in the program are looked for (`--subroutine-path`, LinuxCNC's
    /// SUBROUTINE_PATH), and the file each one loaded from there came from.
    sub_files: Option<Arc<dyn SubroutineFiles>>,
    pub(super) files: HashMap<String, String>,
    /// The value the last subroutine returned (`return [expr]`, `endsub [expr]`; LinuxCNC's
    /// `#<_value>`), and whether it returned one (`#<_value_returned>`).
    pub(crate) value: (f64, bool),
    /// The program's own text, read again for a subroutine defined after its call
    /// ([`super::later_subs`]), where the reader was given it.
    pub(crate) own: Option<Arc<super::later_subs::ProgramText>>,
    /// For each call running, innermost last: whether it is a Fanuc-style `M98` call.
    pub(super) frames: Vec<bool>,
    /// The lines of the `M98 ... L0` run so far: LinuxCNC 2.9 enters a call level for each and never
    /// leaves it ([`super::lcnc_m98`]).
    pub(crate) raised: Vec<usize>,
    /// The runs under way, innermost last ([`super::oword_run`]).
    pub(super) stack: Vec<super::oword_run::Frame>,
    /// The subroutines of other files running, outermost first (a call in one skips forward in
    /// that file, which is not read here).
    pub(super) file_runs: Vec<super::oword_run::FileRun>,
}

impl Flow {
    /// The flow of a read whose control blocks may run `budget` lines, its subroutines not defined
    /// in the program looked for in `sub_files`.
    pub fn new(budget: usize, sub_files: Option<Arc<dyn SubroutineFiles>>) -> Flow {
        let sub_files = sub_files.filter(|f| f.has_dirs());
        Flow { held: None, subs: HashMap::new(), run_lines: 0, budget, depth: 0, said: Default::default(), labels: HashMap::new(), stopped: false, sub_files, files: HashMap::new(), value: (0.0, false), own: None, frames: Vec::new(), raised: Vec::new(), stack: Vec::new(), file_runs: Vec::new() }
    }

    /// How deep in subroutine calls the run stands (0: the main program), as LinuxCNC counts it
    /// (`#<_call_level>`: with the levels `M98 L0` left raised).
    pub(crate) fn depth(&self) -> usize {
        self.depth + self.raised.len()
    }

    /// Whether the innermost call running is a Fanuc-style `M98` call.
    pub(crate) fn in_m98(&self) -> bool {
        self.frames.last() == Some(&true)
    }

    /// The subroutine `name` from its own file on the search path (LinuxCNC's find_ngc_file: `NAME.ngc`
    /// in each directory, the file then skipped to its `o<name> sub` or `O<name>` and run to its end):
    /// its lines, numbered in that file, whether Fanuc-style, and the file's path; `Ok(None)` where
    /// no directory has it.
    fn load(&self, name: &str) -> Result<Option<(super::later_subs::SubLines, String)>, String> {
        let stem = name.trim_start_matches('<').trim_end_matches('>');
        let Some(files) = &self.sub_files else { return Ok(None) };
        if let Some((shown, bytes)) = files.find(stem)? {
            if bytes.len() > MAX_HELD_BYTES {
                return Err(format!("{shown} is larger than {MAX_HELD_BYTES} bytes"));
            }
            let text = String::from_utf8_lossy(&bytes);
            let lines = text.lines().enumerate().map(|(k, l)| Ok((k + 1, l.to_string())));
            return match super::later_subs::collect_sub(lines, name, &shown)? {
                Some(lines) => Ok(Some((lines, shown))),
                None => Err(format!("{shown} has no o{name} sub ... o{name} endsub, nor O{name} ... M99")),
            };
        }
        Ok(None)
    }
}

/// How a run of lines ended.
pub(super) enum End {
    Done,
    Return,
    Stopped,
}

impl Rs274Reader {
    /// A streamed line: held while a block is open, run when its block closes; true if the line
    /// was taken here (the caller reads it otherwise).
    pub(super) fn flow_line(&mut self, line: usize, text: &str, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        // Most lines are neither held nor O words: passed on without a copy.
        if self.flow.held.is_none() && !self.flow.stopped && !super::lcnc_m98::may_be_flow(text.trim_start()) {
            return false;
        }
        let chars: Vec<char> = text.trim_end_matches('\r').chars().collect();
        let first = chars.iter().position(|c| !c.is_whitespace()).unwrap_or(chars.len());
        let o = parse(&chars[first..]);
        if let Some(held) = &mut self.flow.held {
            if held.lines.len() >= MAX_HELD_LINES || held.bytes + text.len() > MAX_HELD_BYTES {
                let (name, k, at) = held.open[0].clone();
                diags.error(at, 1, format!("o{name} {}: the block runs over {MAX_HELD_LINES} lines or {} MiB: not read", word(k), MAX_HELD_BYTES >> 20));
                self.flow.held = None;
                self.flow.stopped = true;
                return true;
            }
            held.lines.push((line, text.to_string()));
            held.bytes += text.len();
            if let Some(o) = o {
                if opens(&o, held.open.last().map(|(n, k, _)| (n.as_str(), *k))) {
                    held.open.push((o.name, o.keyword, line));
                } else if let Some((name, k, _)) = held.open.last().cloned() {
                    if o.keyword == closer(k) && o.name == name {
                        held.open.pop();
                    } else if matches!(o.keyword, Keyword::EndSub | Keyword::EndWhile | Keyword::EndIf | Keyword::EndRepeat) {
                        // An end of another block: what it closes is unknown, so is all after it.
                        self.flow.held = None;
                        self.stop(line, first + 1, format!("o{} {} ends no block: o{name} {} is open", o.name, word(o.keyword), word(k)), diags);
                        return true;
                    }
                }
            }
            if held.open.is_empty() {
                let held = self.flow.held.take().unwrap_or_default();
                self.run_held(held.lines, out, diags);
            }
            return true;
        }
        if self.flow.stopped {
            return true;
        }
        let Some(o) = o else { return false };
        match o.keyword {
            // The main program's M99: its end, read as a line.
            Keyword::M99 => return false,
            Keyword::Title => {
                self.title(&chars[first..], &o);
                return true;
            }
            _ => {}
        }
        if opens(&o, None) {
            self.flow.held = Some(Held { lines: vec![(line, text.to_string())], bytes: text.len(), open: vec![(o.name, o.keyword, line)] });
            return true;
        }
        // A lone keyword outside any block: a call runs now; anything else ends nothing.
        if matches!(o.keyword, Keyword::Call | Keyword::M98) {
            self.run_block(vec![(line, text.to_string())], out, diags);
        } else {
            diags.error(line, first + 1, format!("o{} {}: no block of that name is open", o.name, word(o.keyword)));
        }
        true
    }

    /// The input has ended: a block still held never closed.
    pub(super) fn flow_finish(&mut self, diags: &mut Diags) {
        if let Some(held) = self.flow.held.take() {
            let (name, k, at) = &held.open[0];
            diags.error(*at, 1, format!("the program ends inside o{name} {} (no o{name} {})", word(*k), word(closer(*k))));
        }
    }

    /// A held block closed: a subroutine is kept for its calls, anything else runs.
    fn run_held(&mut self, lines: Vec<Line>, out: &mut Vec<Block>, diags: &mut Diags) {
        let first = lines.first().and_then(|(_, t)| parse(&t.trim_start().chars().collect::<Vec<_>>()));
        if let Some(o) = first.filter(|o| o.keyword == Keyword::Sub) {
            if let Some(&at) = self.flow.raised.first() {
                self.stop(lines[0].0, 1, super::lcnc_m98::after_l0("a subroutine's definition", at), diags);
                return;
            }
            if self.flow.subs.len() >= MAX_SUBS && !self.flow.subs.contains_key(&o.name) {
                diags.error(lines[0].0, 1, format!("more than {MAX_SUBS} subroutines"));
                return;
            }
            self.flow.subs.insert(o.name, (Arc::new(lines), false));
            return;
        }
        self.run_block(lines, out, diags);
    }

    /// `return` or `endsub` with its optional `[value]` (interp_read.cc: "optional return value
    /// expression"): LinuxCNC's `#<_value>` and `#<_value_returned>`, 0 without one. False if the
    /// value cannot be read (the run stopped).
    pub(super) fn return_value(&mut self, o: &OLine, chars: &[char], line: usize, col: usize, diags: &mut Diags) -> bool {
        let start = skip_blanks(chars, o.rest);
        if chars.get(start) != Some(&'[') {
            self.flow.value = (0.0, false);
            return true;
        }
        let mut kept = None;
        match self.bracket(o, chars, line, col, &mut kept, diags) {
            Some(v) => {
                self.flow.value = (v, true);
                true
            }
            None => false,
        }
    }

    /// One more line run by the flow (at `line`), within the read's budget; false (said, the run
    /// stopped) past it.
    pub(super) fn spend_line(&mut self, line: usize, diags: &mut Diags) -> bool {
        self.flow.run_lines += 1;
        if self.flow.run_lines > self.flow.budget {
            self.stop(line, 1, format!("more than {} lines run by O-word loops and calls: an endless loop? not read further", self.flow.budget), diags);
            return false;
        }
        true
    }

    /// A defect in the flow: said at its line, and nothing more is read (what follows would run
    /// from a state the flow left unknown).
    pub(super) fn stop(&mut self, line: usize, column: usize, message: String, diags: &mut Diags) -> End {
        if !self.flow.stopped {
            diags.error(line, column, format!("{message} (the rest of the program is not read)"));
        }
        self.flow.stopped = true;
        End::Stopped
    }

    /// The `[...]` after a keyword, evaluated: its value, or None (the defect said, the run stopped).
    /// `chars` is the line from its O word on, which stands at 0-based column `col`; `kept` the
    /// value compiled when first run.
    fn bracket(&mut self, o: &OLine, chars: &[char], line: usize, col: usize, kept: &mut Option<Compiled>, diags: &mut Diags) -> Option<f64> {
        self.refresh_state(super::rs274::reads_state(chars.iter().copied()));
        let fail = |this: &mut Self, e: ExprError, diags: &mut Diags| {
            this.stop(line, col + e.column, format!("o{} {}: {}", o.name, word(o.keyword), e.message), diags);
            None
        };
        if let Some(c) = kept {
            return match c.eval(&self.params) {
                Ok(v) => Some(v),
                Err(e) => fail(self, e, diags),
            };
        }
        // First run: read and evaluated as LinuxCNC does (its value, then what follows it).
        let start = skip_blanks(chars, o.rest);
        if chars.get(start) != Some(&'[') {
            self.stop(line, col + start + 1, format!("o{} {}: expected a [condition] or [count]", o.name, word(o.keyword)), diags);
            return None;
        }
        let (c, end) = match expr::value(chars, start, false) {
            Ok(read) => read,
            Err(e) => return fail(self, e, diags),
        };
        let v = match c.eval(&self.params) {
            Ok(v) => v,
            Err(e) => return fail(self, e, diags),
        };
        let rest: String = chars[end..].iter().collect();
        let rest = rest.trim();
        if !(rest.is_empty() || rest.starts_with(';') || rest.starts_with('(')) {
            self.stop(line, col + end + 1, format!("o{} {}: unexpected '{}' after its [...]", o.name, word(o.keyword), excerpt(rest)), diags);
            return None;
        }
        *kept = Some(c);
        Some(v)
    }

    pub(super) fn condition(&mut self, o: &OLine, chars: &[char], line: usize, col: usize, kept: &mut Option<Compiled>, diags: &mut Diags) -> Option<bool> {
        self.bracket(o, chars, line, col, kept, diags).map(|v| v != 0.0)
    }

    pub(super) fn count(&mut self, o: &OLine, chars: &[char], line: usize, col: usize, kept: &mut Option<Compiled>, diags: &mut Diags) -> Option<f64> {
        let n = self.bracket(o, chars, line, col, kept, diags)?;
        if n.fract().abs() > 1e-4 && (1.0 - n.fract()).abs() > 1e-4 {
            self.stop(line, col + 1, format!("o{} repeat [{n}]: expected a whole count", o.name), diags);
            return None;
        }
        Some(n.round())
    }

    /// `oN call [a] [b] ...`: the subroutine to run with `#1`.. set to the arguments, in its own
    /// scope (`chars` from the O word on, which stands at 0-based column `col`), or why not (said,
    /// the run stopped).
    pub(super) fn call(&mut self, o: &OLine, chars: &[char], line: usize, col: usize, diags: &mut Diags) -> Result<Option<super::oword_run::SubRun>, End> {
        let named;
        let o = match o.name_expr {
            None => o,
            Some(at) => {
                self.refresh_state(super::rs274::reads_state(chars.iter().copied()));
                match self.params.real_value(chars, at, false) {
                    Ok((v, _)) if v >= 0.0 && (v - v.round()).abs() < 1e-4 && v <= u32::MAX as f64 => {
                        named = OLine { name: format!("{}", v.round() as u64), ..o.clone() };
                        &named
                    }
                    Ok((v, _)) => return Err(self.stop(line, col + at + 1, format!("o[{v}] call: an O word's number is a whole number 0 or more"), diags)),
                    Err(e) => return Err(self.stop(line, col + e.column, format!("o call: {}", e.message), diags)),
                }
            }
        };
        let shown = format!("o{} call", o.name);
        let body = self.find_sub(&o.name, false, &shown, line, col, diags)?;
        self.refresh_state(super::rs274::reads_state(chars.iter().copied()));
        let mut args = Vec::new();
        let mut i = o.rest;
        loop {
            i = skip_blanks(chars, i);
            match chars.get(i) {
                None | Some(';') => break,
                // A comment between arguments is read past, as LinuxCNC's read_o reads it.
                Some('(') => match chars[i..].iter().position(|&c| c == ')') {
                    Some(k) => i += k + 1,
                    None => return Err(self.stop(line, col + i + 1, format!("o{} call: comment '(' is not closed", o.name), diags)),
                },
                Some('[') => match self.params.real_value(chars, i, false) {
                    Ok((v, end)) => {
                        args.push(v);
                        i = end;
                    }
                    Err(e) => return Err(self.stop(line, col + e.column, format!("o{} call: {}", o.name, e.message), diags)),
                },
                Some(_) => return Err(self.stop(line, col + i + 1, format!("o{} call: expected arguments in [...], found '{}'", o.name, excerpt(&chars[i..].iter().collect::<String>())), diags)),
            }
        }
        if args.len() > 30 {
            return Err(self.stop(line, col + 1, format!("o{} call: {} arguments, LinuxCNC takes 30 (#1-#30)", o.name, args.len()), diags));
        }
        Ok(Some(super::oword_run::SubRun::new(&o.name, &shown, body, Some(args), line, col, 1.0)))
    }

    /// The subroutine `name` a call runs (`o<name> call`, or `M98 P<name>` where `m98`; `shown` says
    /// which in messages): as defined before, else from a file of the search path, else forward in
    /// this file (LinuxCNC's control_back_to). The one found must be of the call's kind (LinuxCNC:
    /// "Fanuc 'O....' subroutine must be called with 'M98'", "'O.... sub' subroutine must be called
    /// with 'O.... call'"). Err: the run stopped, said.
    pub(super) fn find_sub(&mut self, name: &str, m98: bool, shown: &str, line: usize, col: usize, diags: &mut Diags) -> Result<(Arc<Vec<Line>>, bool), End> {
        let found = match self.flow.subs.get(name).cloned() {
            Some(found) => found,
            // LinuxCNC's order (control_back_to): a file of the search path, else forward in this
            // file ([`super::later_subs`]; not from a subroutine of another file).
            None => {
                let own = self.flow.own.clone().filter(|_| self.flow.file_runs.is_empty());
                let found = match self.flow.load(name) {
                    Ok(None) => own.as_ref().map_or(Ok(None), |t| t.sub_after(name, line, self.percent)).map(|l| l.map(|sub| (sub, None))),
                    found => found.map(|f| f.map(|(sub, file)| (sub, Some(file)))),
                };
                match found {
                    Ok(Some(_)) if self.flow.subs.len() >= MAX_SUBS => return Err(self.stop(line, col + 1, format!("more than {MAX_SUBS} subroutines"), diags)),
                    Ok(Some(((lines, fanuc), file))) => {
                        let found = (Arc::new(lines), fanuc);
                        self.flow.subs.insert(name.to_string(), found.clone());
                        if let Some(file) = file {
                            self.flow.files.insert(name.to_string(), file);
                        }
                        found
                    }
                    Ok(None) => {
                        let after = if own.is_some() { " (before the call or after it)" } else { "" };
                        let why = match self.flow.sub_files {
                            None => " (LinuxCNC would look on its SUBROUTINE_PATH first: give it with --subroutine-path): the motion depends on a program not read",
                            Some(_) => ", nor in a file of --subroutine-path",
                        };
                        let what = if m98 { format!("program O{name}") } else { format!("subroutine o{name}") };
                        return Err(self.stop(line, col + 1, format!("{shown}: no {what} is defined in this file{after}{why}"), diags));
                    }
                    Err(why) => return Err(self.stop(line, col + 1, format!("{shown}: {why}"), diags)),
                }
            }
        };
        match (found.1, m98) {
            (true, false) => Err(self.stop(line, col + 1, format!("{shown}: O{name} is a Fanuc-style subprogram (O{name} ... M99), called by M98 P{name} (LinuxCNC: \"Fanuc 'O....' subroutine must be called with 'M98'\")"), diags)),
            (false, true) => Err(self.stop(line, col + 1, format!("{shown}: o{name} sub is called by o{name} call (LinuxCNC: \"'O.... sub' subroutine must be called with 'O.... call'\")"), diags)),
            _ => Ok(found),
        }
    }
}
