//! RS274NGC programs (LinuxCNC, Fanuc style): `G0/G1`, arcs `G2/G3` (`G17/G18/G19`, centre `I J K`
//! or radius `R`, `P` turns, helical), `G90/G91`, `G90.1/G91.1`, `G93/G94`, `G20/G21`, `F`, `(...)`
//! and `;` comments, spaces between letter and value (`X  16.339`), optional `N` numbers,
//! `G43.4`/`G49` tool-centre-point control on/off, Fanuc's `G43.5` with the tool axis as a vector
//! `I J K`, work offsets the program sets (`G10 L2 Pn`, `G54`-`G59.3`). Codes and words that would
//! change the motion and are not modelled are errors; machine-specific M codes are read only as
//! `--m-code` says. LinuxCNC's parameters and expressions (`#<feed>=1000`, `F#<feed>`, `X[#1*2]`,
//! `XSIN[30]`) are evaluated as its interpreter does ([`super::params`]).

mod decimal;
mod line;

pub(crate) use line::{Now, ReadLine};
use line::{written, Item, Value};

use super::fanuc_corners::Ran;
use super::interp::{Dimension, Interpreter, Word};
use super::lex::Diags;
use super::params::{Parameters, Target};
use super::{Block, Dialect, MCodeRule, Program};

/// Read an RS274NGC program (no machine-specific M codes).
pub fn read_rs274(text: &str) -> Program {
    read_rs274_with(text, &[])
}

/// Read an RS274NGC program with these machine-specific M codes.
pub fn read_rs274_with(text: &str, m_codes: &[MCodeRule]) -> Program {
    read_rs274_setup(text, m_codes, Dialect::Rs274.default_orientation())
}

/// Read an RS274NGC program with these machine-specific M codes, on a control whose orientation
/// interpolation starts as `orientation`.
pub fn read_rs274_setup(text: &str, m_codes: &[MCodeRule], orientation: super::Orientation) -> Program {
    super::stream::read_whole(&mut Rs274Reader::new(&super::Setup::plain(Dialect::Rs274, m_codes, orientation)), text, Dialect::Rs274)
}

/// The RS274NGC reader, fed one line at a time.
#[derive(Debug, Clone)]
pub(crate) struct Rs274Reader {
    pub(super) interp: Interpreter,
    /// A line with words has been read (a program number may come only before).
    pub(super) started: bool,
    /// The program number (`O1234`), if the program opens with one.
    pub(super) number: Option<String>,
    /// The parameters the program has set so far.
    pub(super) params: Parameters,
    /// RS274NGC, Fanuc or Haas.
    pub(super) dialect: Dialect,
    /// Fanuc and Haas: the lines before the program's first `%`, held until it comes (they are the
    /// tape's leader, which the control skips: an NX listing's header) or until it cannot (then
    /// read as program). `None` once decided.
    leader: Option<Vec<(usize, String)>>,
    /// Fanuc, Haas: the tape's end `%` has been read: nothing after it is program.
    refused: bool,
    /// LinuxCNC: the program ended (`M2`/`M30`, or the `%` closing a file that opens with one) on
    /// this line; what follows is not run (and whether that has been said).
    ended: Option<(usize, bool)>,
    /// LinuxCNC: a subroutine defined after the program's end is being passed over (true: a
    /// Fanuc-style one, which ends with M99 outside the O-word blocks open in it).
    in_later_sub: Option<(bool, super::oword::OpenBlocks)>,
    /// LinuxCNC: the file opens with `%`, so the next `%` line ends it.
    pub(super) percent: bool,
    /// Fanuc, Haas: a macro alarm (`#3000`) stopped the control.
    alarmed: bool,
    /// Fanuc, Haas: a length or angle without a decimal point has been said (once).
    pub(super) said_no_point: bool,
    /// Fanuc, Haas: the machine reads a number without a decimal point in the program's unit
    /// (calculator-type input, its file's `decimal_point_input`), not in least input increments.
    pub(super) calculator_input: bool,
    /// The last line read with anything on it (where a missing program end is said).
    last_line: usize,
    /// LinuxCNC's O-word blocks held and run ([`super::oword`]).
    pub(super) flow: super::oword::Flow,
    /// The machine's quill, where it has one ([`super::quill`]).
    pub(super) quill: Option<super::quill::QuillState>,
    /// The memory the lines kept as read hold ([`Rs274Reader::loop_line`]), at most [`MAX_KEPT_BYTES`].
    kept_bytes: usize,
    /// LinuxCNC: the modal state M70/M73 saved in each call frame ([`super::modal_context`]).
    pub(super) contexts: super::modal_context::Contexts,
    /// Fanuc, Haas: chamfering and corner R (`,C`, `,R`) waiting for the block after theirs.
    pub(super) corners: super::fanuc_corners::Corners,
    /// A line's characters and items are read into these, kept from line to line (no two
    /// allocations per line); let go past [`KEEP_BUFFER`] entries, so a long line's room is not held.
    chars_buf: Vec<char>,
    items_buf: Vec<Item>,
}

/// The most entries a line's buffers keep from one line to the next.
const KEEP_BUFFER: usize = 4096;

/// The most memory lines kept as read may hold, over every loop and call that keeps them: a line as
/// read holds several times its text; beyond this, lines are read again on each pass.
const MAX_KEPT_BYTES: usize = 64 << 20;

/// The most leader held back, lines and bytes: an NX "Information listing" header is a few lines.
pub(super) const MAX_LEADER_LINES: usize = 64;
pub(super) const MAX_LEADER_BYTES: usize = 16 * 1024;

impl Rs274Reader {
    /// A reader for this setup; a machine's HAL pins can be read (`#<_hal[...]>`).
    pub(crate) fn new(setup: &super::Setup) -> Self {
        let mut params = match &setup.machine {
            Some(m) => Parameters::with_hal_pins(m.hal_pins.clone()),
            None => Parameters::default(),
        };
        if setup.dialect.is_fanuc() {
            params.fanuc_system_variables();
        }
        let leader = setup.dialect.is_fanuc().then(Vec::new);
        Rs274Reader { interp: setup.interpreter(), started: false, number: None, params, dialect: setup.dialect, leader, refused: false, ended: None, percent: false, alarmed: false, said_no_point: false, calculator_input: setup.machine.as_ref().is_some_and(|m| m.calculator_input), last_line: 0, flow: super::oword::Flow::new(setup.max_run_lines, setup.subroutine_files.clone()), quill: setup.machine.as_ref().and_then(|m| m.quill).map(super::quill::QuillState::new), kept_bytes: 0, contexts: Default::default(), in_later_sub: None, corners: Default::default(), chars_buf: Vec::new(), items_buf: Vec::new() }
    }
}

/// [`reads_state`] of a line's text: a line without `#` (most of a program) found so by a byte
/// search, without decoding its characters.
pub(super) fn text_reads_state(text: &str) -> bool {
    text.contains('#') && reads_state(text.chars())
}

/// Whether a line's text may read a predefined parameter of the interpreter's state: a named one
/// (`#<_...>`), a numbered one from 5000 up (`#5...`) or Fanuc's modal information (`#4...`), or one
/// whose number is computed (`##1`, `#[...]`). Most lines, a loop's own parameters among them, read none: the state is not gathered
/// for them.
pub(super) fn reads_state(mut text: impl Iterator<Item = char>) -> bool {
    while text.by_ref().any(|c| c == '#') {
        let mut rest = text.by_ref().skip_while(|c| *c == ' ' || *c == '\t');
        match rest.next() {
            Some('<') => {
                if text.by_ref().find(|c| *c != ' ' && *c != '\t') == Some('_') {
                    return true;
                }
            }
            // (`#4003`: Fanuc's modal information.)
            Some('4' | '5' | '#' | '[') => return true,
            _ => {}
        }
    }
    false
}

impl Rs274Reader {
    /// Fanuc, Haas: the lines read now are the program's (past the tape's leader, before its end `%`).
    pub(super) fn in_program(&self) -> bool {
        self.leader.is_none() && !self.refused
    }

    /// LinuxCNC: the program's own text, for subroutines defined after their call (Fanuc and Haas
    /// find their subprograms in their macro runner).
    pub(super) fn set_program_text(&mut self, text: impl FnOnce() -> super::later_subs::ProgramText) {
        if self.dialect == Dialect::Rs274 {
            self.flow.own = Some(std::sync::Arc::new(text()));
        }
    }

    /// The tape's end `%` has been read: nothing after it is program.
    pub(super) fn at_tape_end(&self) -> bool {
        self.refused
    }

    /// A macro alarm (`#3000`) stopped the control: nothing after it runs.
    pub(super) fn alarmed(&self) -> bool {
        self.alarmed
    }

    /// The last line read with anything on it.
    pub(super) fn last_line(&self) -> usize {
        self.last_line
    }

    /// A line with words has been read (an `O` number now is another program's).
    pub(super) fn started(&self) -> bool {
        self.started
    }

    /// The text has no `%`: no line of it is the tape's leader.
    pub(super) fn no_leader(&mut self) {
        self.leader = None;
    }
}

impl super::stream::LineReader for Rs274Reader {
    fn line(&mut self, line: usize, text: &str, out: &mut Vec<Block>, diags: &mut Diags) {
        // A run under way ends before the next line is read (the stream asks for it part by part
        // with `more`; a caller that does not, gets it here whole).
        while self.flow_more(out, diags) {}
        if !text.trim().is_empty() {
            self.last_line = line;
        }
        if self.refused || self.after_end(line, text, diags) {
            return;
        }
        // Fanuc, Haas: what comes before the first `%` is the leader, skipped ("Leader section: the
        // data before the first % is ignored": FANUC 30i Operator's Manual B-64484EN, "Program
        // configuration"). Held until the `%` says so; a file without one is all program.
        if let Some(held) = &mut self.leader {
            if text.trim() == "%" || text.trim_start().starts_with('%') {
                let held = std::mem::take(held);
                self.leader = None;
                if let (Some((first, _)), Some((last, _))) = (held.first(), held.last()) {
                    diags.warning(*first, 1, format!("lines {first}-{last} before the program's first % are the tape's leader: skipped, as the control does"));
                }
                return;
            }
            let bytes: usize = held.iter().map(|(_, t)| t.len()).sum::<usize>() + text.len();
            if held.len() < MAX_LEADER_LINES && bytes <= MAX_LEADER_BYTES {
                held.push((line, text.to_string()));
                return;
            }
            self.release_leader(out, diags);
        }
        self.program_line(line, text, out, diags);
    }

    fn more(&mut self, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        self.flow_more(out, diags)
    }

    fn finish(&mut self, _blocks: Option<&mut Vec<Block>>, out: &mut Vec<Block>, diags: &mut Diags) {
        while self.flow_more(out, diags) {}
        self.release_leader(out, diags);
        out.extend(self.corners.interrupt("the program ends before the block after it", diags));
        self.flow_finish(diags);
        // Moves cutter radius compensation still holds are never run.
        super::cutter_comp::finish(&mut self.interp, diags);
        // A NURBS curve whose knots have not all come is never run.
        super::fanuc_nurbs::finish(&mut self.interp, self.last_line, diags);
        // LinuxCNC: a file must end its program (interp_read.cc, read_text: "if the file started with a
        // percent line, it must end with a percent line ... if [not], it must have a program ending
        // command (M2 or M30) in it"); at the end of the file it stops with an error, after the moves
        // before it. A file cut short ends so too.
        // (Not where reading stopped early: what follows was not read.)
        if self.dialect == Dialect::Rs274 && self.ended.is_none() && self.started && !self.flow.stopped {
            let what = if self.percent { "File ended with no percent sign" } else { "File ended with no percent sign or program end" };
            diags.warning(self.last_line, 1, format!("the file ends without {}: LinuxCNC stops here with \"{what}\" after running the moves before it; was the file cut short?", if self.percent { "the % closing the one that opens it" } else { "M2, M30 or a closing %" }));
        }
    }

    fn name(&self) -> Option<String> {
        self.number.clone()
    }

    fn not_read(&mut self, _line: usize, out: &mut Vec<Block>, diags: &mut Diags) {
        self.corners_not_read(out, diags);
    }
}

impl Rs274Reader {
    /// LinuxCNC: whether the program has ended before this line (said once, at the first line
    /// after the end with anything on it), or ends with it: a file that opens with a `%` line ends
    /// at the next one ("The useful contents of a file demarcated by percents stop after the second
    /// percent line", NIST IR 6556 §3.3.1).
    fn after_end(&mut self, line: usize, text: &str, diags: &mut Diags) -> bool {
        if self.dialect != Dialect::Rs274 {
            return false;
        }
        let body = text.trim();
        if let Some((end, said)) = &mut self.ended {
            // The closing `%` and comments after the end move nothing: said only for a line with words.
            // Subroutines defined after the end are where calls skip forward to (super::later_subs):
            // their lines are no program cut off.
            if !*said && !body.is_empty() && !body.starts_with(['%', '(', ';']) {
                use super::oword::{Keyword, OpenBlocks};
                let o = super::oword::parse(&body.chars().collect::<Vec<_>>());
                match (o, &mut self.in_later_sub) {
                    (Some(o), None) if o.keyword == Keyword::Sub => self.in_later_sub = Some((false, OpenBlocks::default())),
                    (Some(o), None) if o.keyword == Keyword::Title => self.in_later_sub = Some((true, OpenBlocks::default())),
                    (Some(o), Some((false, _))) if o.keyword == Keyword::EndSub => self.in_later_sub = None,
                    // A Fanuc-style one ends with the first M99 outside its O-word blocks.
                    (Some(o), Some((true, open))) if o.keyword == Keyword::M99 && open.is_empty() => self.in_later_sub = None,
                    (Some(o), Some((true, open))) => open.pass(o),
                    (_, Some(_)) => {}
                    _ => {
                        *said = true;
                        diags.warning(line, 1, format!("line {line} and after are not run: the program ended on line {end}, and LinuxCNC runs nothing after its end"));
                    }
                }
            }
            return true;
        }
        if body.starts_with('%') {
            if self.percent {
                self.ended = Some((line, false));
                return true;
            }
            // Only a `%` before any word opens the demarcated file; another is read as before.
            self.percent = !self.started;
        }
        false
    }

    /// LinuxCNC: the program has ended (`M2`/`M30`): nothing runs after it, in a loop or not.
    pub(super) fn program_ended(&self) -> bool {
        self.ended.is_some()
    }

    /// LinuxCNC: the interpreter's state as its predefined parameters give it, for a line about to
    /// read parameters (`reads`): as it stands after the lines before ([`Interpreter::state_parameters`],
    /// the call level and the last subroutine's return value).
    pub(super) fn refresh_state(&mut self, reads: bool) {
        if !reads {
            return;
        }
        if self.dialect.is_fanuc() {
            self.params.set_state(self.interp.fanuc_modal_information());
            return;
        }
        if self.dialect != Dialect::Rs274 {
            return;
        }
        let mut state = self.interp.state_parameters();
        let (value, returned) = self.flow.value;
        state.named.extend([("_call_level", self.flow.depth() as f64), ("_value", value), ("_value_returned", if returned { 1.0 } else { 0.0 })]);
        self.params.set_state(state);
    }

    /// No `%` came: the lines held as leader are the program's, read now.
    fn release_leader(&mut self, out: &mut Vec<Block>, diags: &mut Diags) {
        if let Some(held) = self.leader.take() {
            for (n, t) in held {
                self.program_line(n, &t, out, diags);
            }
        }
    }

    /// A line of the program as it streams: O-word blocks are held and run, other lines read.
    fn program_line(&mut self, line: usize, text: &str, out: &mut Vec<Block>, diags: &mut Diags) {
        if self.refused || (self.dialect == Dialect::Rs274 && self.flow_line(line, text, out, diags)) {
            return;
        }
        self.plain_line(line, text, out, diags);
    }

    /// One line read as the interpreter reads it (O-word lines are the flow's).
    pub(super) fn plain_line(&mut self, line: usize, text: &str, out: &mut Vec<Block>, diags: &mut Diags) {
        if self.refused || self.ended.is_some() {
            return;
        }
        let text = text.trim_end_matches('\r');
        let said = diags.0.len();
        match self.read_line(line, text, diags) {
            Some((read, now)) => {
                self.run_line(line, text, &read, Some(now), out, diags);
                self.recycle(read);
            }
            None => self.corners_after_damaged(said, out, diags),
        }
    }

    /// A line a loop runs on each pass: read once (when reading it says nothing, so each pass says
    /// what the first did, and while the kept lines' memory allows), kept in `kept`, then run from
    /// what was read. A kept line [`let_go`](Self::let_go) frees its share of the memory.
    pub(super) fn loop_line(&mut self, line: usize, text: &str, kept: &mut Option<ReadLine>, out: &mut Vec<Block>, diags: &mut Diags) {
        if self.refused || self.ended.is_some() {
            return;
        }
        let text = text.trim_end_matches('\r');
        if let Some(read) = kept {
            self.refresh_state(text_reads_state(text));
            return self.run_line(line, text, read, None, out, diags);
        }
        let before = diags.0.len();
        let read = self.read_line(line, text, diags);
        if read.is_none() {
            self.corners_after_damaged(before, out, diags);
        }
        if let Some((mut read, now)) = read {
            let quiet = diags.0.len() == before;
            self.run_line(line, text, &read, Some(now), out, diags);
            // Kept at its own size, not the room a longer line left in the buffer.
            read.items.shrink_to_fit();
            let size = read.size();
            if quiet && self.kept_bytes + size <= MAX_KEPT_BYTES {
                self.kept_bytes += size;
                *kept = Some(read);
            } else {
                self.recycle(read);
            }
        }
    }

    /// Lines kept by [`loop_line`](Self::loop_line) that are let go: their memory counts no more.
    pub(super) fn let_go<'a>(&mut self, kept: impl Iterator<Item = &'a ReadLine>) {
        self.kept_bytes -= kept.map(ReadLine::size).sum::<usize>();
    }

    /// Run a line as read: its values as evaluated when it was read (`now`), or evaluated with the
    /// parameters as they stand, left to right (the first that cannot be is the line's defect); its
    /// settings made after every value is read (`#3=6 G1 X#3` moves to the old `#3`); then its words
    /// interpreted.
    pub(super) fn run_line(&mut self, line: usize, text: &str, read: &ReadLine, now: Option<Vec<Now>>, out: &mut Vec<Block>, diags: &mut Diags) {
        let (start, before) = (self.interp.position(), out.len());
        let mut ask = None;
        let ran = self.run_words(line, text, read, now, &mut ask, out, diags);
        if ask.is_some() || self.corners.busy() {
            self.corners_after(ran, ask, start, before, out, diags);
        }
    }

    /// [`Rs274Reader::run_line`]'s words run; the corner its comma words ask for in `ask`.
    #[allow(clippy::too_many_arguments)]
    fn run_words(&mut self, line: usize, text: &str, read: &ReadLine, now: Option<Vec<Now>>, ask: &mut Option<super::fanuc_corners::Ask>, out: &mut Vec<Block>, diags: &mut Diags) -> Ran {
        let errors_before = diags.errors();
        let mut now = now.map(Vec::into_iter);
        let mut words: Vec<Word> = Vec::with_capacity(read.items.len());
        // Words whose value was computed (parameters, expressions): they carry their decimal point.
        let mut computed: Vec<usize> = Vec::new();
        let mut settings: Vec<(Target, f64, usize)> = Vec::new();
        // Fanuc's comma words (`,C`, `,R`), and whether each was computed.
        let mut commas: Vec<(Word, bool)> = Vec::new();
        for item in &read.items {
            match item {
                Item::Word { letter, comma: true, column, raw, value, .. } => {
                    let value = match value {
                        Value::Written(v) => Ok((*v, false)),
                        Value::Computed(c) => now.as_mut().and_then(Iterator::next).map_or_else(|| c.eval(&self.params), Now::value).map(|v| (v, true)),
                    };
                    match value {
                        Ok((value, computed)) => commas.push((Word { letter: *letter, value, raw: text[raw.0..raw.1].trim_end().into(), column: *column, dimension: Dimension::Modal }, computed)),
                        Err(e) => {
                            diags.error(line, e.column, format!(",{letter}: {}", e.message));
                            break;
                        }
                    }
                }
                Item::Word { letter, column, raw, spaced, value: Value::Written(v), .. } => {
                    let raw = line::word_text(&text[raw.0..raw.1], *spaced);
                    words.push(Word { letter: *letter, value: *v, raw, column: *column, dimension: Dimension::Modal })
                }
                Item::Word { letter, column, raw, value: Value::Computed(c), .. } => match now.as_mut().and_then(Iterator::next).map_or_else(|| c.eval(&self.params), Now::value) {
                    Ok(value) => {
                        computed.push(words.len());
                        // A coordinate's, feed's or arc's computed value: its text is the expression
                        // as written (for messages; formatting the number costs more than reading
                        // it). Codes and events carry the number.
                        let raw: std::borrow::Cow<str> = match letter {
                            'X' | 'Y' | 'Z' | 'A' | 'B' | 'C' | 'U' | 'V' | 'W' | 'I' | 'J' | 'K' | 'R' | 'F' => text[raw.0..raw.1].trim_end().into(),
                            _ => written(*letter, value).into(),
                        };
                        words.push(Word { letter: *letter, value, raw, column: *column, dimension: Dimension::Modal });
                    }
                    Err(e) => {
                        diags.error(line, e.column, format!("{letter}: {}", e.message));
                        break;
                    }
                },
                Item::Setting { setting, column } => match now.as_mut().and_then(Iterator::next).map_or_else(|| setting.run(&self.params), Now::setting) {
                    Ok((target, value)) => settings.push((target, value, *column)),
                    Err(e) => {
                        diags.error(line, e.column, e.message);
                        break;
                    }
                },
            }
        }
        if diags.errors() == errors_before {
            for (target, value, column) in settings {
                if let Err(e) = self.params.set(target, value, column) {
                    diags.error(line, e.column, e.message);
                }
            }
        }
        let first = read.first;
        let damaged = diags.errors() > errors_before;
        if damaged {
            diags.warning(line, first + 1, format!("line {line} not used: it is damaged"));
            self.interp.refused(&words, line);
            return Ran::NotUsed;
        }
        if words.is_empty() && commas.is_empty() {
            return Ran::Nothing;
        }
        // Fanuc's program number: `O` and a whole number alone in the program's first block (with its
        // name as a comment, `O1001 (DWG. A-124D)`), naming the program in memory; it moves nothing.
        // Any other O word (LinuxCNC's `o100 sub`, a second program after `%`) stays an error below.
        let started = std::mem::replace(&mut self.started, true);
        if let [w] = &words[..] {
            if !started && read.number.is_none() && w.letter == 'O' && w.value.fract() == 0.0 && w.value >= 1.0 && !w.raw.contains(['.', '+', '-']) {
                self.number = Some(format!("O{}", w.raw));
                return Ran::Nothing;
            }
        }
        let col = words.first().map_or(first + 1, |w| w.column.min(first + 1));
        if self.dialect.is_fanuc() && !self.calculator_input {
            // Under G95 an F without a decimal point may count least increments per revolution, as a
            // length word does (F300 as 0.300 mm/rev); which one this control takes is not at hand.
            let per_rev = self.block_feed_mode(&words).1;
            if let Some((_, w)) = words.iter().enumerate().find(|(i, w)| per_rev && w.letter == 'F' && computed.binary_search(i).is_err() && !w.raw.contains('.')) {
                diags.error(line, w.column, format!("F{} without a decimal point under G95 (feed per revolution): whether the control reads it in mm (in) per revolution or in least input increments is not read; write it with a decimal point", w.raw));
                diags.warning(line, first + 1, format!("line {line} not used: it is damaged"));
                self.interp.refused(&words, line);
                return Ran::NotUsed;
            }
            if let Some(i) = self.decimal_points(&mut words, &computed) {
                if !std::mem::replace(&mut self.said_no_point, true) {
                    let w = &words[i];
                    // A knot and a weight count the reference axis' increments and have no unit (B-63324EN §4.17).
                    let nurbs = self.interp.nurbs.is_some() || words.iter().any(|w| w.letter == 'G' && w.value == 6.2);
                    let unit = match w.letter {
                        'K' if nurbs => "(a knot)",
                        'R' if nurbs => "(a weight)",
                        'A' | 'B' | 'C' => "deg",
                        _ if self.inch_words(&words) => "in",
                        _ => "mm",
                    };
                    diags.warning(line, w.column, format!("{}{} has no decimal point: read as {} {unit}, in least input increments, as the control reads it unless its parameter says otherwise (FANUC DPI No. 3401#0, Haas Setting 162: the machine file's decimal_point_input); said once", w.letter, w.raw, w.value));
                }
            }
        }
        // A corner word refused (said at it) leaves the block as written.
        *ask = self.corner_words(&mut commas, &words, line, read.number, diags);
        if !self.quill_words(&mut words, line, diags) {
            diags.warning(line, first + 1, format!("line {line} not used: it is damaged"));
            self.interp.refused(&words, line);
            return Ran::NotUsed;
        }
        let before = out.len();
        // LinuxCNC: M99 returns from a Fanuc-style subprogram only first in its line (read by the flow,
        // super::lcnc_m98); elsewhere in a subprogram it stops the interpreter.
        let m99 = self.dialect == Dialect::Rs274 && words.iter().any(|w| w.letter == 'M' && w.value == 99.0);
        if let (true, 0, Some(&at)) = (m99, self.flow.depth() - self.flow.raised.len(), self.flow.raised.first()) {
            diags.error(line, col, super::lcnc_m98::after_l0("M99 in the main program", at));
            self.flow.stopped = true;
            return Ran::NotUsed;
        }
        if m99 && self.flow.depth() > 0 {
            diags.error(line, col, "M99 returns from a subprogram only as the first word of its line (LinuxCNC: \"Reached convert_stop() from M99 as subprogram return\")");
            self.flow.stopped = true;
            return Ran::NotUsed;
        }
        // LinuxCNC's M70-M73 act before the block's G codes (its order of execution).
        if self.dialect == Dialect::Rs274 && !self.modal_context(&mut words, line, read.number, diags, out) {
            diags.warning(line, first + 1, format!("line {line} not used"));
            return Ran::NotUsed;
        }
        let mut ran = Ran::Taken;
        if !words.is_empty() && !self.interp.block(&words, line, col, read.number, diags, out) {
            if self.interp.halted {
                self.flow.stopped = true;
                return Ran::NotUsed;
            }
            diags.warning(line, first + 1, format!("line {line} not used"));
            // What the line made before its defect (a settings block with M2) still ends the program.
            ran = Ran::NotUsed;
        }
        // LinuxCNC: "Lines of a file that occur after the end of a program are not to be executed"
        // (RS274/NGC Interpreter v3, NIST IR 6556, §3.3.1; M2 and M30 end it, §3.6.1). Fanuc and Haas
        // end in their macro runner, whose subprograms stand after M30.
        if self.dialect == Dialect::Rs274 && self.ended.is_none() && super::stream::ends_program(&out[before..], &[2.0, 30.0, 99.0]) {
            self.ended = Some((line, false));
            // M99 in the main program (interp_convert.cc convert_stop): LinuxCNC's task loops to the
            // program's start, its standalone interpreter ends the program as M2 does.
            if m99 {
                diags.warning(line, col, "M99 in the main program: LinuxCNC's task runs the program again from its start, endlessly (its standalone interpreter ends it here); read once");
            }
        }
        ran
    }

}
