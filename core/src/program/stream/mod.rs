//! Programs read as streams. Each dialect's reader is fed one line at a time (sans I/O), so the same
//! code reads a string ([`super::read`]) and a file of any length in memory bounded by one line and
//! one block's output ([`BlockStream`]): a ten-hour CAM program is never held whole.
//!
//! ```
//! use fiveaxis_core::program::{BlockStream, Dialect, ReadOptions};
//! let text = "1 2 3 0 0 1 1000\n2 2 3 0 0.1 0.995 1000\n";
//! let mut stream = BlockStream::from_text(text, Some(Dialect::Cl), "two poses", &ReadOptions::default());
//! assert_eq!(stream.by_ref().count(), 2);
//! assert_eq!(stream.diagnostics().errors(), 0);
//! ```

mod jump;

pub(crate) use jump::{ends_program, in_memory, read_jumping, stop, At, Find, Jumping, Next, Places, Seeking};

use super::cl::ClReader;
use super::heidenhain::DinReader;
use super::klartext::Runner;
use super::lex::Diags;
use super::rs274::Rs274Reader;
use super::{Block, Diagnostic, Dialect, LoadError, Program, ReadOptions, Severity, DETECT_LINES};
use std::collections::VecDeque;
use std::io::{BufRead, Cursor, Read, Seek};
use std::path::Path;

/// A dialect's reader, fed the program one line at a time.
pub(crate) trait LineReader {
    /// Read line `line` (1-based; `text` without its newline): blocks go to `out`, defects to `diags`.
    fn line(&mut self, line: usize, text: &str, out: &mut Vec<Block>, diags: &mut Diags);
    /// A run a line began (a LinuxCNC O-word loop) gives its blocks a part at a time: the next part
    /// to `out`; true while more is to come (the next line waits until then).
    fn more(&mut self, _out: &mut Vec<Block>, _diags: &mut Diags) -> bool {
        false
    }
    /// The input has ended: checks that need all of it (a missing header), and blocks only the end
    /// completes go to `out`. `blocks` holds every block when the program was read whole; a stream
    /// has handed them out already (`None`).
    fn finish(&mut self, _blocks: Option<&mut Vec<Block>>, _out: &mut Vec<Block>, _diags: &mut Diags) {}
    /// The program's name, once its header has been read.
    fn name(&self) -> Option<String> {
        None
    }
    /// Line `line` could not be read (too long, said by the stream): what waits for the line after
    /// it (a chamfer or rounding) is refused there, and what it holds goes to `out`.
    fn not_read(&mut self, _line: usize, _out: &mut Vec<Block>, _diags: &mut Diags) {}
}

/// Read the whole of `text` in `dialect` with `reader`: its blocks, and its diagnostics in line order.
pub(crate) fn read_whole(reader: &mut dyn LineReader, text: &str, dialect: Dialect) -> Program {
    let mut blocks = Vec::with_capacity(super::lex::line_count(text));
    let mut diags = Diags::default();
    for (idx, raw) in text.strip_prefix(BOM).unwrap_or(text).lines().enumerate() {
        reader.line(idx + 1, raw, &mut blocks, &mut diags);
        while reader.more(&mut blocks, &mut diags) {}
    }
    let mut tail = Vec::new();
    reader.finish(Some(&mut blocks), &mut tail, &mut diags);
    blocks.append(&mut tail);
    diags.0.sort_by_key(|d| (d.line, d.column));
    Program { source: String::new(), dialect, name: reader.name(), blocks, diagnostics: diags.0 }
}

/// Longest line read, bytes: a longer one is an error at its line (NC and CL lines are short; a
/// file without newlines is not a program), and nothing larger is ever allocated for one.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// Diagnostics kept in full; beyond them only counted (a damaged hours-long program could otherwise
/// hold one message per line).
pub const MAX_DIAGNOSTICS: usize = 10_000;

/// The diagnostics of a stream: the first [`MAX_DIAGNOSTICS`] in full, the rest counted.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DiagnosticLog {
    kept: Vec<Diagnostic>,
    errors: usize,
    warnings: usize,
}

impl DiagnosticLog {
    /// Take one diagnostic.
    pub fn push(&mut self, d: Diagnostic) {
        match d.severity {
            Severity::Error => self.errors += 1,
            Severity::Warning => self.warnings += 1,
        }
        if self.kept.len() < MAX_DIAGNOSTICS {
            self.kept.push(d);
        }
    }

    /// Errors seen, kept or not.
    pub fn errors(&self) -> usize {
        self.errors
    }

    /// Warnings seen, kept or not.
    pub fn warnings(&self) -> usize {
        self.warnings
    }

    /// The diagnostics in line order; if some were only counted, a last one says how many (an error
    /// if any of them was).
    pub fn to_vec(&self) -> Vec<Diagnostic> {
        let mut out = self.kept.clone();
        out.sort_by_key(|d| (d.line, d.column));
        let (kept_errors, kept) = (self.kept.iter().filter(|d| d.severity == Severity::Error).count(), self.kept.len());
        let dropped = self.errors + self.warnings - kept;
        if dropped > 0 {
            let dropped_errors = self.errors - kept_errors;
            out.push(Diagnostic {
                line: out.last().map_or(1, |d| d.line),
                column: 1,
                severity: if dropped_errors > 0 { Severity::Error } else { Severity::Warning },
                message: format!("{dropped} more diagnostics ({dropped_errors} errors) not listed: only the first {MAX_DIAGNOSTICS} are"),
            });
        }
        out
    }
}

/// The line readers of the dialects that are read line by line.
#[derive(Debug, Clone)]
pub(crate) enum Reader {
    Cl(ClReader),
    Rs274(Rs274Reader),
    Din(DinReader),
}

impl Reader {
    /// The reader of `dialect` (`None` for the dialects whose programs jump: [`jumping`]).
    pub(crate) fn new(dialect: Dialect, options: &ReadOptions) -> Option<Reader> {
        let setup = options.setup(dialect);
        Some(match dialect {
            Dialect::Cl => Reader::Cl(ClReader::new(&setup)),
            Dialect::Rs274 => Reader::Rs274(Rs274Reader::new(&setup)),
            Dialect::Heidenhain => Reader::Din(DinReader::new(&setup)),
            Dialect::Klartext | Dialect::Fanuc | Dialect::Haas | Dialect::Sinumerik => return None,
        })
    }

    /// An RS274NGC reader is given the program's own text, for subroutines defined after their
    /// call ([`super::later_subs`]); other readers need none.
    pub(crate) fn with_program_text(&mut self, text: impl FnOnce() -> super::later_subs::ProgramText) {
        if let Reader::Rs274(r) = self {
            r.set_program_text(text);
        }
    }

    pub(crate) fn get(&mut self) -> &mut dyn LineReader {
        match self {
            Reader::Cl(r) => r,
            Reader::Rs274(r) => r,
            Reader::Din(r) => r,
        }
    }
}

/// The reader of a dialect whose programs jump, read by [`Seeking`]: Klartext (labels, calls,
/// repeats), Fanuc and Haas (macro branches and loops, subprograms), Sinumerik (jumps, control
/// structures).
pub(crate) fn jumping(dialect: Dialect, options: &ReadOptions) -> Box<dyn Jumping> {
    let setup = options.setup(dialect);
    match dialect {
        Dialect::Fanuc | Dialect::Haas => Box::new(super::macro_b::MacroRunner::new(&setup)),
        Dialect::Sinumerik => Box::new(super::sinumerik::FlowRunner::new(&setup)),
        _ => Box::new(Runner::new(&setup)),
    }
}

/// A program's text, readable from any byte offset.
pub trait Text: Read + Seek + Send {}
impl<T: Read + Seek + Send + ?Sized> Text for T {}

/// Opens the program's text for a reader that jumps: Klartext's calls and repeats go back and
/// forth, so its reader reads parts of the program again rather than hold it. Called once, when
/// the program is first read (a compressed one is unpacked then).
pub type OpenText<'a> = Box<dyn FnOnce() -> std::io::Result<Box<dyn Text + 'a>> + Send + 'a>;

/// Where the blocks come from: a reader fed line by line, or a program read as it runs.
enum Source {
    Lines { input: Box<dyn BufRead + Send>, reader: Reader, line: usize, buf: Vec<u8> },
    Seeking(Box<Seeking<'static>>),
}

/// The blocks of a program, read as they are asked for: memory holds one line and the blocks it
/// made, not the program. Diagnostics are collected as it goes ([`BlockStream::diagnostics`]; in
/// full once the stream has ended).
pub struct BlockStream {
    source: String,
    dialect: Dialect,
    input: Source,
    pending: VecDeque<Block>,
    out: Vec<Block>,
    diags: Diags,
    log: DiagnosticLog,
    name: Option<String>,
    blocks: usize,
    ended: bool,
}

impl std::fmt::Debug for BlockStream {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BlockStream").field("source", &self.source).field("dialect", &self.dialect).field("blocks", &self.blocks).finish()
    }
}

/// How much of a file the dialect is guessed from: the lines [`Dialect::detect`] looks at
/// ([`DETECT_LINES`]), at most this many bytes.
const DETECT_BYTES: usize = 1 << 20;

impl BlockStream {
    /// Read a program from `input` (a file's bytes, as they come), detecting its dialect from its
    /// name (`path`, for the extension) and first lines unless given; `source` names it in reports.
    /// Klartext reads `open()` for its labels, then runs it from its start, seeking wherever a
    /// call or a repeat jumps. Opening the file is the caller's.
    pub fn from_reader(
        mut input: impl BufRead + Send + 'static,
        open: OpenText<'static>,
        path: Option<&Path>,
        source: &str,
        dialect: Option<Dialect>,
        options: &ReadOptions,
    ) -> Result<BlockStream, LoadError> {
        let io = |e| LoadError::Io { path: source.to_string(), source: e };
        // The first lines, for the dialect, then read again by the reader.
        let mut head = Vec::new();
        let mut lines = 0;
        while lines < DETECT_LINES && head.len() < DETECT_BYTES {
            let n = input.by_ref().take((DETECT_BYTES - head.len()) as u64).read_until(b'\n', &mut head).map_err(io)?;
            if n == 0 {
                break;
            }
            lines += 1;
        }
        let control = options.machine.as_ref().and_then(|m| m.dialect);
        let given = dialect.is_some();
        // UTF-8 checked first (word-at-a-time over ASCII), replaced only where it is not.
        let text = std::str::from_utf8(&head).map_or_else(|_| String::from_utf8_lossy(&head), std::borrow::Cow::Borrowed);
        let dialect = dialect.unwrap_or_else(|| Dialect::detect_for(path, &text, control));
        if let Some(d) = Dialect::unread(given, dialect, &text) {
            return Ok(Self::refused(d, dialect, source));
        }
        match Reader::new(dialect, options) {
            Some(mut reader) => {
                reader.with_program_text(|| super::later_subs::ProgramText::file(open));
                Ok(Self::lines(Box::new(Cursor::new(head).chain(input)), reader, dialect, source))
            }
            None => {
                let mut k = Seeking::new(open, jumping(dialect, options));
                match k.broken.take() {
                    Some(e) => Err(io(e)),
                    None => Ok(Self::seeking(k, dialect, source)),
                }
            }
        }
    }

    /// Read `text` as a stream (the dialect detected from it unless given); `source` names it.
    pub fn from_text(text: &str, dialect: Option<Dialect>, source: &str, options: &ReadOptions) -> BlockStream {
        let given = dialect.is_some();
        let dialect = dialect.unwrap_or_else(|| Dialect::detect_for(None, text, options.machine.as_ref().and_then(|m| m.dialect)));
        if let Some(d) = Dialect::unread(given, dialect, text) {
            return Self::refused(d, dialect, source);
        }
        match Reader::new(dialect, options) {
            Some(mut reader) => {
                let bytes: std::sync::Arc<[u8]> = text.as_bytes().into();
                reader.with_program_text(|| super::later_subs::ProgramText::Bytes(bytes.clone()));
                Self::lines(Box::new(Cursor::new(bytes.to_vec())), reader, dialect, source)
            }
            None => {
                let text: std::sync::Arc<[u8]> = text.as_bytes().into();
                Self::seeking(Seeking::new(in_memory(text), jumping(dialect, options)), dialect, source)
            }
        }
    }

    /// A stream that hands out no block and says why, once.
    fn refused(d: Diagnostic, dialect: Dialect, source: &str) -> BlockStream {
        let mut log = DiagnosticLog::default();
        log.push(d);
        BlockStream {
            source: source.into(),
            dialect,
            input: Source::Lines { input: Box::new(Cursor::new(Vec::new())), reader: Reader::new(Dialect::Rs274, &ReadOptions::default()).expect("RS274 reads by lines"), line: 0, buf: Vec::new() },
            pending: VecDeque::new(),
            out: Vec::new(),
            diags: Diags::default(),
            log,
            name: None,
            blocks: 0,
            ended: true,
        }
    }

    fn seeking(k: Seeking<'static>, dialect: Dialect, source: &str) -> BlockStream {
        Self::on(Source::Seeking(Box::new(k)), dialect, source)
    }

    fn lines(input: Box<dyn BufRead + Send>, reader: Reader, dialect: Dialect, source: &str) -> BlockStream {
        Self::on(Source::Lines { input, reader, line: 0, buf: Vec::with_capacity(256) }, dialect, source)
    }

    /// A stream of `input` with nothing read yet.
    fn on(input: Source, dialect: Dialect, source: &str) -> BlockStream {
        BlockStream {
            source: source.into(),
            dialect,
            input,
            pending: VecDeque::new(),
            out: Vec::new(),
            diags: Diags::default(),
            log: DiagnosticLog::default(),
            name: None,
            blocks: 0,
            ended: false,
        }
    }

    /// Where the program came from.
    pub fn source(&self) -> &str {
        &self.source
    }

    pub fn dialect(&self) -> Dialect {
        self.dialect
    }

    /// The program's name from its header, once read.
    pub fn name(&self) -> Option<&str> {
        self.name.as_deref()
    }

    /// Blocks handed out so far.
    pub fn blocks_read(&self) -> usize {
        self.blocks
    }

    /// The diagnostics so far.
    pub fn diagnostics(&self) -> &DiagnosticLog {
        &self.log
    }

    /// Read lines until a block is ready or the input ends.
    fn fill(&mut self) {
        while self.pending.is_empty() && !self.ended {
            match &mut self.input {
                Source::Seeking(k) => {
                    self.ended = k.fill(&mut self.out, &mut self.diags);
                    if self.name.is_none() {
                        self.name = k.runner.name();
                    }
                    self.pending.extend(self.out.drain(..));
                }
                Source::Lines { input, reader, line, buf } => {
                    // A run the last line began gives its blocks before the next line is read
                    // (its last part too, handed out before the next line's).
                    let running = reader.get().more(&mut self.out, &mut self.diags);
                    self.pending.extend(self.out.drain(..));
                    for d in self.diags.0.drain(..) {
                        self.log.push(d);
                    }
                    if running || !self.pending.is_empty() {
                        continue;
                    }
                    *line += 1;
                    let (n, out, diags) = (*line, &mut self.out, &mut self.diags);
                    match with_line(input.as_mut(), buf, |bytes| reader.get().line(n, &line_text(bytes, n), out, diags)) {
                        Ok(Got::End) => {
                            reader.get().finish(None, &mut self.out, &mut self.diags);
                            self.pending.extend(self.out.drain(..));
                            self.ended = true;
                        }
                        Ok(Got::Text(..)) => {
                            if self.name.is_none() {
                                self.name = reader.get().name();
                            }
                            self.pending.extend(self.out.drain(..));
                        }
                        Ok(Got::TooLong(_)) => {
                            self.diags.error(*line, 1, too_long(*line));
                            reader.get().not_read(*line, &mut self.out, &mut self.diags);
                            self.pending.extend(self.out.drain(..));
                        }
                        Err(e) => {
                            self.diags.error(*line, 1, cannot_read(*line, e));
                            self.ended = true;
                        }
                    }
                }
            }
            for d in self.diags.0.drain(..) {
                self.log.push(d);
            }
        }
    }
}

impl Iterator for BlockStream {
    type Item = Block;
    fn next(&mut self) -> Option<Block> {
        self.fill();
        let b = self.pending.pop_front()?;
        self.blocks += 1;
        Some(b)
    }
}

/// A line read: its length with its newline and what was made of it, or the length of a line
/// longer than [`MAX_LINE_BYTES`] (skipped), or the input's end.
enum Got<R> {
    Text(u64, R),
    TooLong(u64),
    End,
}

/// Hand the next line (its bytes with the newline) to `f`: borrowed from the input's buffer where
/// it lies there whole (most lines: no copy), else gathered in `buf` by [`read_line`].
fn with_line<R>(input: &mut dyn BufRead, buf: &mut Vec<u8>, f: impl FnOnce(&[u8]) -> R) -> std::io::Result<Got<R>> {
    let chunk = loop {
        match input.fill_buf() {
            Ok(c) => break c,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        }
    };
    if let Some(i) = memchr::memchr(b'\n', chunk).filter(|&i| i <= MAX_LINE_BYTES) {
        let r = f(&chunk[..=i]);
        input.consume(i + 1);
        return Ok(Got::Text(i as u64 + 1, r));
    }
    Ok(match read_line(input, buf)? {
        Got::Text(n, ()) => Got::Text(n, f(buf)),
        Got::TooLong(n) => Got::TooLong(n),
        Got::End => Got::End,
    })
}

fn too_long(line: usize) -> String {
    format!("line {line} is longer than {MAX_LINE_BYTES} bytes: not a program line; skipped")
}

fn cannot_read(line: usize, e: std::io::Error) -> String {
    format!("cannot read line {line}: {e}; reading stops here")
}

/// Read one line into `buf` (with its newline), never more than [`MAX_LINE_BYTES`]: a longer line
/// is skipped to its end.
fn read_line(input: &mut dyn BufRead, buf: &mut Vec<u8>) -> std::io::Result<Got<()>> {
    buf.clear();
    let mut too_long = false;
    let mut skipped = 0u64;
    loop {
        let chunk = match input.fill_buf() {
            Ok(c) => c,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if chunk.is_empty() {
            return Ok(if too_long { Got::TooLong(skipped) } else if buf.is_empty() { Got::End } else { Got::Text(buf.len() as u64, ()) });
        }
        let (take, done) = match chunk.iter().position(|&b| b == b'\n') {
            Some(i) => (i + 1, true),
            None => (chunk.len(), false),
        };
        if !too_long {
            if buf.len() + take > MAX_LINE_BYTES + 1 {
                too_long = true;
                skipped = buf.len() as u64;
                buf.clear();
            } else {
                buf.extend_from_slice(&chunk[..take]);
            }
        }
        if too_long {
            skipped += take as u64;
        }
        input.consume(take);
        if done {
            return Ok(if too_long { Got::TooLong(skipped) } else { Got::Text(buf.len() as u64, ()) });
        }
    }
}

/// A line's bytes without its line end (`\n` or `\r\n`).
fn without_eol(line: &[u8]) -> &[u8] {
    let b = line.strip_suffix(b"\n").unwrap_or(line);
    b.strip_suffix(b"\r").unwrap_or(b)
}

/// The UTF-8 byte-order mark some editors write before a file's first line: the file's encoding,
/// not its text (no control's language has a word U+FEFF).
pub(crate) const BOM: &str = "\u{feff}";

/// Line `line`'s bytes without its line end, and on the first line without a byte-order mark.
fn line_bytes(buf: &[u8], line: usize) -> &[u8] {
    let b = without_eol(buf);
    if line == 1 {
        b.strip_prefix(BOM.as_bytes()).unwrap_or(b)
    } else {
        b
    }
}

/// The text of line `line`, read into `buf`: without its line end or a byte-order mark before the
/// file's first line (bytes that are not UTF-8 replaced).
fn line_text(buf: &[u8], line: usize) -> std::borrow::Cow<'_, str> {
    let b = line_bytes(buf, line);
    // The check alone is faster than the lossy conversion's, and almost every line passes it.
    match std::str::from_utf8(b) {
        Ok(s) => std::borrow::Cow::Borrowed(s),
        Err(_) => String::from_utf8_lossy(b),
    }
}
