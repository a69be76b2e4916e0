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

use super::cl::ClReader;
use super::heidenhain::DinReader;
use super::lex::Diags;
use super::rs274::Rs274Reader;
use super::sinumerik::SinumerikReader;
use super::{Block, Diagnostic, Dialect, LoadError, Program, ReadOptions, Severity};
use std::collections::VecDeque;
use std::io::{BufRead, Cursor, Read};
use std::path::Path;

/// A dialect's reader, fed the program one line at a time.
pub(crate) trait LineReader {
    /// Read line `line` (1-based; `text` without its newline): blocks go to `out`, defects to `diags`.
    fn line(&mut self, line: usize, text: &str, out: &mut Vec<Block>, diags: &mut Diags);
    /// The input has ended: checks that need all of it (a missing header). `blocks` holds every
    /// block when the program was read whole; a stream has handed them out already (`None`).
    fn finish(&mut self, _blocks: Option<&mut Vec<Block>>, _diags: &mut Diags) {}
    /// The program's name, once its header has been read.
    fn name(&self) -> Option<String> {
        None
    }
}

/// Read the whole of `text` in `dialect` with `reader`: its blocks, and its diagnostics in line order.
pub(crate) fn read_whole(reader: &mut dyn LineReader, text: &str, dialect: Dialect) -> Program {
    let mut blocks = Vec::with_capacity(super::lex::line_count(text));
    let mut diags = Diags::default();
    for (idx, raw) in text.lines().enumerate() {
        reader.line(idx + 1, raw, &mut blocks, &mut diags);
    }
    reader.finish(Some(&mut blocks), &mut diags);
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
    Sinumerik(SinumerikReader),
}

impl Reader {
    /// The reader of `dialect` (`None` for Klartext, which is read whole).
    pub(crate) fn new(dialect: Dialect, options: &ReadOptions) -> Option<Reader> {
        let orientation = options.orientation.unwrap_or(dialect.default_orientation());
        Some(match dialect {
            Dialect::Cl => Reader::Cl(ClReader::new(options.cl_feed_mm_per_min, orientation)),
            Dialect::Rs274 => Reader::Rs274(Rs274Reader::new(&options.m_codes, orientation)),
            Dialect::Heidenhain => Reader::Din(DinReader::new(&options.m_codes, orientation)),
            Dialect::Sinumerik => Reader::Sinumerik(SinumerikReader::new(&options.m_codes, orientation)),
            Dialect::Klartext => return None,
        })
    }

    pub(crate) fn get(&mut self) -> &mut dyn LineReader {
        match self {
            Reader::Cl(r) => r,
            Reader::Rs274(r) => r,
            Reader::Din(r) => r,
            Reader::Sinumerik(r) => r,
        }
    }
}

/// Where the blocks come from: a reader fed line by line, or (Klartext, whose labels and subprogram
/// calls jump about the file) the blocks of the program read whole.
enum Source {
    Lines { input: Box<dyn BufRead + Send>, reader: Reader, line: usize, buf: Vec<u8> },
    Whole(std::vec::IntoIter<Block>),
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

/// How much of a file the dialect is guessed from: the lines [`Dialect::detect`] looks at.
const DETECT_LINES: usize = 2000;
const DETECT_BYTES: usize = 1 << 20;

impl BlockStream {
    /// Read a program from `input` (a file's bytes, as they come), detecting its dialect from its
    /// name (`path`, for the extension) and first lines unless given; `source` names it in reports.
    /// Line-based dialects stream; Klartext is read whole. Opening the file is the caller's.
    pub fn from_reader(
        mut input: impl BufRead + Send + 'static,
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
        let dialect = dialect.unwrap_or_else(|| Dialect::detect(path, &String::from_utf8_lossy(&head)));
        match Reader::new(dialect, options) {
            Some(reader) => Ok(Self::lines(Box::new(Cursor::new(head).chain(input)), reader, dialect, source)),
            None => {
                let mut rest = head;
                super::read_whole_bytes(input, &mut rest, source)?;
                Ok(Self::whole(&String::from_utf8_lossy(&rest), dialect, source, options))
            }
        }
    }

    /// Read `text` as a stream (the dialect detected from it unless given); `source` names it.
    pub fn from_text(text: &str, dialect: Option<Dialect>, source: &str, options: &ReadOptions) -> BlockStream {
        let dialect = dialect.unwrap_or_else(|| Dialect::detect(None, text));
        match Reader::new(dialect, options) {
            Some(reader) => Self::lines(Box::new(Cursor::new(text.as_bytes().to_vec())), reader, dialect, source),
            None => Self::whole(text, dialect, source, options),
        }
    }

    fn whole(text: &str, dialect: Dialect, source: &str, options: &ReadOptions) -> BlockStream {
        let program = super::read(text, dialect, source, options);
        let mut log = DiagnosticLog::default();
        program.diagnostics.into_iter().for_each(|d| log.push(d));
        BlockStream {
            source: source.into(),
            dialect,
            input: Source::Whole(program.blocks.into_iter()),
            pending: VecDeque::new(),
            out: Vec::new(),
            diags: Diags::default(),
            log,
            name: program.name,
            blocks: 0,
            ended: false,
        }
    }

    fn lines(input: Box<dyn BufRead + Send>, reader: Reader, dialect: Dialect, source: &str) -> BlockStream {
        BlockStream {
            source: source.into(),
            dialect,
            input: Source::Lines { input, reader, line: 0, buf: Vec::with_capacity(256) },
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
                Source::Whole(blocks) => match blocks.next() {
                    Some(b) => self.pending.push_back(b),
                    None => self.ended = true,
                },
                Source::Lines { input, reader, line, buf } => {
                    *line += 1;
                    match read_line(input.as_mut(), buf) {
                        Ok(Line::End) => {
                            reader.get().finish(None, &mut self.diags);
                            self.ended = true;
                        }
                        Ok(Line::Text) => {
                            let text = String::from_utf8_lossy(buf);
                            let text = text.strip_suffix('\n').unwrap_or(&text);
                            let text = text.strip_suffix('\r').unwrap_or(text);
                            reader.get().line(*line, text, &mut self.out, &mut self.diags);
                            if self.name.is_none() {
                                self.name = reader.get().name();
                            }
                            self.pending.extend(self.out.drain(..));
                        }
                        Ok(Line::TooLong) => self.diags.error(*line, 1, format!("line {line} is longer than {MAX_LINE_BYTES} bytes: not a program line; skipped")),
                        Err(e) => {
                            self.diags.error(*line, 1, format!("cannot read line {line}: {e}; reading stops here"));
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

enum Line {
    Text,
    TooLong,
    End,
}

/// Read one line into `buf` (with its newline), never more than [`MAX_LINE_BYTES`]: a longer line
/// is skipped to its end.
fn read_line(input: &mut dyn BufRead, buf: &mut Vec<u8>) -> std::io::Result<Line> {
    buf.clear();
    let mut too_long = false;
    loop {
        let chunk = match input.fill_buf() {
            Ok(c) => c,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if chunk.is_empty() {
            return Ok(if too_long { Line::TooLong } else if buf.is_empty() { Line::End } else { Line::Text });
        }
        let (take, done) = match chunk.iter().position(|&b| b == b'\n') {
            Some(i) => (i + 1, true),
            None => (chunk.len(), false),
        };
        if !too_long {
            if buf.len() + take > MAX_LINE_BYTES + 1 {
                too_long = true;
                buf.clear();
            } else {
                buf.extend_from_slice(&chunk[..take]);
            }
        }
        input.consume(take);
        if done {
            return Ok(if too_long { Line::TooLong } else { Line::Text });
        }
    }
}
