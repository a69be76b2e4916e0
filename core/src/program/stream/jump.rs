//! Programs that jump: a runner ([`Jumping`]) fed lines from wherever a call, a repeat or a jump
//! goes, the file searched for the lines it looks for ([`Seeking`]), so that memory holds the
//! runner's state, never the program.

use super::super::lex::Diags;
use super::super::{Block, Diagnostic, Dialect, Program};
use super::{cannot_read, line_bytes, line_text, too_long, with_line, Got, OpenText, Text, MAX_DIAGNOSTICS};
use std::collections::HashSet;
use std::io::{BufReader, Cursor, Seek, SeekFrom};

/// Where a line of the program starts: its number (1-based) and byte offset. A jump (a call, a
/// repeat, a return) tells the reader to read on from here.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct At {
    pub line: usize,
    pub offset: u64,
}

/// What the reader does after a line: read the next one, read on from elsewhere, look for lines
/// (a label the program jumps to), or (the program has ended) only check the lines after it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Next {
    On,
    /// On, once the run this line began (an 840D subprogram call) has given its blocks
    /// ([`Jumping::more`], asked before each line until it answers `None`).
    Run,
    Jump(At),
    Find(Find),
    Ended,
}

/// A search a program's flow asks for: the lines from `from` on, up to the byte offset `to` (the
/// text's end if `None`), that the reader's [`Jumping::matches`] takes for `key`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Find {
    pub from: At,
    pub to: Option<u64>,
    pub key: u64,
}

/// The most lines a search reports: enough to tell a label from one written twice.
const MAX_HITS: usize = 2;

/// The most targets whose places a runner remembers ([`Places`]).
pub(crate) const MAX_PLACES: usize = 10_000;

/// Where the lines a jump looked for stand, by what it looked for (a Fanuc block number in its
/// program, an 840D marker): a jump taken again does not search again. At most [`MAX_PLACES`]
/// targets are remembered; a search for one more is made each time it is taken.
#[derive(Debug, Clone)]
pub(crate) struct Places<K> {
    map: std::collections::HashMap<K, Vec<At>>,
}

impl<K: std::hash::Hash + Eq> Places<K> {
    pub(crate) fn new() -> Self {
        Places { map: std::collections::HashMap::new() }
    }

    /// The places found before for `key`, if it was looked for.
    pub(crate) fn get<Q: std::hash::Hash + Eq + ?Sized>(&self, key: &Q) -> Option<Vec<At>>
    where
        K: std::borrow::Borrow<Q>,
    {
        self.map.get(key).cloned()
    }

    /// Remember a search's answer (within the bound).
    pub(crate) fn remember(&mut self, key: K, hits: &[At]) {
        if self.map.len() < MAX_PLACES {
            self.map.insert(key, hits.to_vec());
        }
    }
}

/// A dialect's reader whose programs jump (Klartext's labels and calls, Fanuc's macro branches and
/// subprograms), run by [`Seeking`], sans I/O.
pub(crate) trait Jumping: Send {
    /// Whether the reader needs [`Jumping::scan`]'s first pass over the text.
    fn wants_scan(&self) -> bool {
        true
    }
    /// The first pass over the text, before the run: line `line`'s bytes, the next line at `next`.
    fn scan(&mut self, line: usize, bytes: &[u8], next: At, diags: &mut Diags);
    /// Run line `line` (`text`, without its newline), which starts at `here`, the next at `next`:
    /// its blocks to `out`, its defects to `diags`; where to read on.
    fn line(&mut self, line: usize, text: &str, here: At, next: At, out: &mut Vec<Block>, diags: &mut Diags) -> Next;
    /// A line after the program's end: checked, not run (by default not looked at).
    fn check(&mut self, _line: usize, _text: &str, _diags: &mut Diags) {}
    /// The input has ended, the program too (`ended`: its run ended before, at its end or at a
    /// defect) or not (it ran to the input's end, or a read failed): blocks only the end completes go
    /// to `out`.
    fn finish(&mut self, ended: bool, out: &mut Vec<Block>, diags: &mut Diags);
    /// The program's name, once read.
    fn name(&self) -> Option<String>;
    /// Whether line `bytes` is one a search for `key` looks for.
    fn matches(&self, _key: u64, _bytes: &[u8]) -> bool {
        false
    }
    /// A search's answer: where the lines it looked for start (at most [`MAX_HITS`]) and how many
    /// lines it read (a reader bounds what its jumps cost by them); where to read on.
    fn found(&mut self, _find: Find, _hits: &[At], _read: usize, _diags: &mut Diags) -> Next {
        Next::Ended
    }
    /// A run a line began ([`Next::Run`]: an 840D subprogram call) gives its blocks a part at a
    /// time, before the next line is read: `None` when none is running, else the next part to `out`
    /// and whether the program goes on ([`Next::On`]: ask again) or ended in it ([`Next::Ended`]).
    fn more(&mut self, _out: &mut Vec<Block>, _diags: &mut Diags) -> Option<Next> {
        None
    }
    /// Line `line` could not be read (too long, said by the stream): as [`LineReader::not_read`].
    fn not_read(&mut self, _line: usize, _out: &mut Vec<Block>, _diags: &mut Diags) {}
}

/// A defect in a program's flow: said at its place, and the run ends (what follows would run from a
/// state the flow left unknown).
pub(crate) fn stop(line: usize, column: usize, message: String, diags: &mut Diags) -> Next {
    diags.error(line, column, format!("{message} (the rest of the program is not read)"));
    Next::Ended
}

/// Whether the blocks a line made end the program: an M function among `codes` (the control's
/// ends of program) in their events.
pub(crate) fn ends_program(blocks: &[Block], codes: &[f64]) -> bool {
    blocks.iter().flat_map(|b| &b.events).any(|e| e.strip_prefix('M').and_then(|c| c.parse::<f64>().ok()).is_some_and(|c| codes.contains(&c)))
}

/// A program read as it runs: a first pass over the text ([`Jumping::scan`]: Klartext's labels,
/// Fanuc's programs), then line by line from where the program's flow goes, seeking to a byte
/// offset for each jump (within the read buffer when the target is in it: a short repeated section
/// is not read again from the file). Memory holds one line, the read buffer and what the reader
/// keeps (a label table, a call stack), whatever the program's length.
pub(crate) struct Seeking<'a, R: Jumping + ?Sized + 'a = dyn Jumping + 'a> {
    input: BufReader<Box<dyn Text + 'a>>,
    /// The line to read next.
    at: At,
    pub(crate) runner: Box<R>,
    /// False once the program has ended: the lines after it are only checked.
    running: bool,
    buf: Vec<u8>,
    /// The label pass's diagnostics, given with the first lines.
    early: Diags,
    /// Diagnostics given so far (a section run again would give its own again), the first
    /// [`MAX_DIAGNOSTICS`] of them.
    given: HashSet<(usize, usize, String)>,
    /// An opening, a read of the label pass or the seek back to the start that failed.
    pub(super) broken: Option<std::io::Error>,
    /// A run a line began gives its blocks before the next line ([`Next::Run`]).
    run: bool,
}

impl<'a, R: Jumping + ?Sized + 'a> Seeking<'a, R> {
    /// Read `open()` for `runner`'s first pass; run it from its start. A failure is kept in
    /// `broken` (a file's reader turns it into a [`LoadError`]; otherwise the first
    /// [`Seeking::fill`] reports it).
    pub(crate) fn new(open: OpenText<'a>, mut runner: Box<R>) -> Self {
        let mut early = Diags::default();
        let (mut buf, mut at) = (Vec::with_capacity(256), At { line: 1, offset: 0 });
        let (text, mut broken) = match open() {
            Ok(t) => (t, None),
            Err(e) => (Box::new(Cursor::new([0u8; 0])) as Box<dyn Text + 'a>, Some(e)),
        };
        let mut input = BufReader::with_capacity(1 << 16, text);
        let scan = runner.wants_scan();
        while broken.is_none() && scan {
            let read = with_line(&mut input, &mut buf, |bytes| {
                let next = At { line: at.line + 1, offset: at.offset + bytes.len() as u64 };
                runner.scan(at.line, line_bytes(bytes, at.line), next, &mut early);
            });
            let len = match read {
                Ok(Got::End) => break,
                Ok(Got::TooLong(n) | Got::Text(n, ())) => n,
                Err(e) => {
                    broken = Some(e);
                    break;
                }
            };
            at = At { line: at.line + 1, offset: at.offset + len };
        }
        if broken.is_none() && scan {
            broken = input.rewind().err();
        }
        Seeking { input, at: At { line: 1, offset: 0 }, runner, running: true, buf, early, given: HashSet::new(), broken, run: false }
    }

    /// Read one line and run (or check) it: its blocks to `out`, its diagnostics not given before to
    /// `diags`. True once the input has ended.
    pub(crate) fn fill(&mut self, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        let mut d = std::mem::take(&mut self.early);
        let Seeking { input, at, runner, running, buf, broken, run, .. } = self;
        // A run the last line began gives its part before the next line is read.
        if *run && *running && broken.is_none() {
            match runner.more(out, &mut d) {
                Some(next) => {
                    if next == Next::Ended {
                        *running = false;
                    }
                    self.give(d, diags);
                    return false;
                }
                None => *run = false,
            }
        }
        let line = at.line;
        let here = *at;
        let read = match broken.take() {
            Some(e) => Err(e),
            None => with_line(input, buf, |bytes| {
                let next = At { line: line + 1, offset: at.offset + bytes.len() as u64 };
                let text = line_text(bytes, line);
                if *running {
                    runner.line(line, &text, here, next, out, &mut d)
                } else {
                    runner.check(line, &text, &mut d);
                    Next::On
                }
            }),
        };
        let ended = match read {
            Ok(Got::End) => {
                runner.finish(!*running, out, &mut d);
                true
            }
            Ok(Got::TooLong(n)) => {
                d.error(line, 1, too_long(line));
                runner.not_read(line, out, &mut d);
                *at = At { line: line + 1, offset: at.offset + n };
                false
            }
            Ok(Got::Text(len, next)) => {
                *at = At { line: line + 1, offset: at.offset + len };
                let mut next = next;
                // A search, then where its answer says: the reader stands after the lines it read.
                let mut stands = at.offset;
                let mut result = Ok(());
                if let Next::Find(find) = next {
                    result = search(input, buf, &mut stands, find, runner.as_ref()).map(|(hits, read)| {
                        next = runner.found(find, &hits, read, &mut d);
                        // A search answers with a place, not another search; a run its answer began
                        // gives its blocks before the line after.
                        *run |= next == Next::Run;
                        if matches!(next, Next::On | Next::Run | Next::Find(_)) {
                            next = Next::Jump(*at);
                        }
                    });
                }
                match (result, next) {
                    (Err(e), _) => {
                        d.error(line, 1, cannot_read(line, e));
                        runner.finish(!*running, out, &mut d);
                        true
                    }
                    (Ok(()), Next::On) => false,
                    (Ok(()), Next::Run) => {
                        *run = true;
                        false
                    }
                    (Ok(()), next) => {
                        // Read on from the jump's line, or (the program has ended: its lines after the
                        // end are only checked) from the next.
                        match next {
                            Next::Jump(to) => *at = to,
                            _ => *running = false,
                        }
                        match seek(input, stands, at.offset) {
                            Ok(()) => false,
                            Err(e) => {
                                d.error(at.line, 1, cannot_read(at.line, e));
                                runner.finish(!*running, out, &mut d);
                                true
                            }
                        }
                    }
                }
            }
            Err(e) => {
                d.error(line, 1, cannot_read(line, e));
                runner.finish(!*running, out, &mut d);
                true
            }
        };
        self.give(d, diags);
        ended
    }

    /// Whether the program still runs (its lines after its end are only checked).
    pub(crate) fn running(&self) -> bool {
        self.running
    }

    /// Pass on the diagnostics `d` not given before.
    fn give(&mut self, d: Diags, diags: &mut Diags) {
        for x in d.0 {
            let key = (x.line, x.column, x.message);
            if self.given.contains(&key) {
                continue;
            }
            let x = Diagnostic { line: key.0, column: key.1, severity: x.severity, message: key.2.clone() };
            if self.given.len() < MAX_DIAGNOSTICS {
                self.given.insert(key);
            }
            diags.0.push(x);
        }
    }
}

/// The lines from `find.from` up to `find.to` that `runner` takes for `find.key`, and how many lines
/// were read, the reader standing at byte `stands` (moved to where the search stopped).
fn search<R: Jumping + ?Sized>(input: &mut BufReader<Box<dyn Text + '_>>, buf: &mut Vec<u8>, stands: &mut u64, find: Find, runner: &R) -> std::io::Result<(Vec<At>, usize)> {
    seek(input, *stands, find.from.offset)?;
    *stands = find.from.offset;
    let mut at = find.from;
    let mut hits = Vec::new();
    let first = at.line;
    while find.to.is_none_or(|to| at.offset < to) && hits.len() < MAX_HITS {
        let line = at.line;
        let hit = match with_line(input, buf, |bytes| runner.matches(find.key, line_bytes(bytes, line)))? {
            Got::End => break,
            Got::TooLong(n) => {
                at = At { line: at.line + 1, offset: at.offset + n };
                *stands = at.offset;
                continue;
            }
            Got::Text(n, hit) => {
                let here = at;
                at = At { line: at.line + 1, offset: at.offset + n };
                *stands = at.offset;
                hit.then_some(here)
            }
        };
        hits.extend(hit);
    }
    Ok((hits, at.line - first))
}

/// Move a reader standing at byte `from` to byte `to`: within its buffer when `to` is in it,
/// else by seeking the text.
fn seek(input: &mut BufReader<Box<dyn Text + '_>>, from: u64, to: u64) -> std::io::Result<()> {
    match i64::try_from(to).ok().zip(i64::try_from(from).ok()) {
        Some((to, from)) => input.seek_relative(to - from),
        None => input.seek(SeekFrom::Start(to)).map(drop),
    }
}

/// A text in memory (borrowed or shared).
pub(crate) fn in_memory<'a, T: AsRef<[u8]> + Send + 'a>(text: T) -> OpenText<'a> {
    Box::new(move || Ok(Box::new(Cursor::new(text)) as Box<dyn Text + 'a>))
}

/// Read a program that jumps from `text` as the stream does (`runner`, a reader of `dialect`), its
/// blocks and diagnostics collected.
pub(crate) fn read_jumping(text: &str, dialect: Dialect, runner: Box<dyn Jumping + '_>) -> Program {
    let mut k = Seeking::new(in_memory(text.as_bytes()), runner);
    let (mut blocks, mut diags) = (Vec::with_capacity(super::super::lex::line_count(text)), Diags::default());
    while !k.fill(&mut blocks, &mut diags) {}
    diags.0.sort_by_key(|d| (d.line, d.column));
    Program { source: String::new(), dialect, name: k.runner.name(), blocks, diagnostics: diags.0 }
}
