//! Program files: opening them is the only part of reading a program that touches the file
//! system, so it lives here and the core's readers take text or bytes.

use fiveaxis_core::program::{read, BlockStream, Dialect, LoadError, Program, ReadOptions, OpenText, Text};
use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Read a program file whole (once: a pipe is read as it comes), detecting its dialect unless
/// given. Bytes that are not UTF-8 are replaced (and reported where they stand).
pub fn load(path: &Path, dialect: Option<Dialect>, options: &ReadOptions) -> Result<Program, LoadError> {
    ProgramFile::Path(path.to_path_buf()).load(dialect, options)
}

/// Open a program file as a stream of blocks (memory flat in its length), detecting its dialect
/// from its name and first lines unless given.
pub fn open(path: &Path, dialect: Option<Dialect>, options: &ReadOptions) -> Result<BlockStream, LoadError> {
    ProgramFile::Path(path.to_path_buf()).open(dialect, options)
}

/// The spec that names standard input.
pub const STDIN: &str = "-";

/// Standard input's name in diagnostics.
const STDIN_NAME: &str = "stdin";

/// The most a pipe or standard input may hold, bytes: it is copied to a temporary file so that every
/// reader can read it again, and a stream that never ends (`yes | fiveaxis run -`) must not fill the
/// disk. 8 GiB is over 100 hours of CAM output at a block every 0.1 mm and F2000.
pub const MAX_SPOOL_BYTES: u64 = 8 << 30;

/// A program file that every consumer can read from its start, each at its own pace (the commander,
/// the planner and its scout, the analysis and the check each read the program for themselves).
/// A regular file is opened again by each; a pipe, a FIFO (`<(zcat prog.ngc.gz)`) or standard input
/// (`-`) can be read only once, so it is copied here, as it comes, to an unlinked temporary file in
/// `$TMPDIR` (gone when the last reader is), which each reader reads at its own offset.
#[derive(Debug, Clone)]
pub enum ProgramFile {
    Path(PathBuf),
    Spooled { name: String, file: Arc<File> },
}

impl ProgramFile {
    /// Resolve `spec` (a path, or `-` for standard input): a regular file is checked to open; anything
    /// else is read to its end now, up to [`MAX_SPOOL_BYTES`].
    pub fn resolve(spec: &str) -> Result<ProgramFile, LoadError> {
        let io = |source| LoadError::Io { path: spec.to_string(), source };
        if spec == STDIN {
            return Self::spool(std::io::stdin().lock(), STDIN_NAME).map_err(io);
        }
        let path = Path::new(spec);
        let file = File::open(path).map_err(io)?;
        if file.metadata().map_err(io)?.file_type().is_file() {
            return Ok(ProgramFile::Path(path.to_path_buf()));
        }
        Self::spool(file, spec).map_err(io)
    }

    /// Copy `input` to an unlinked temporary file, at most [`MAX_SPOOL_BYTES`], named `name`.
    fn spool(input: impl Read, name: &str) -> std::io::Result<ProgramFile> {
        let mut file = tempfile::tempfile().map_err(|e| std::io::Error::new(e.kind(), format!("cannot make a temporary file to hold it in {}: {e}", std::env::temp_dir().display())))?;
        let mut input = input.take(MAX_SPOOL_BYTES + 1);
        let copied = std::io::copy(&mut input, &mut file)?;
        if copied > MAX_SPOOL_BYTES {
            return Err(std::io::Error::other(format!(
                "more than {} GiB from a pipe or standard input (the most that is held to be read again); save the program to a file",
                MAX_SPOOL_BYTES >> 30
            )));
        }
        Ok(ProgramFile::Spooled { name: name.to_string(), file: Arc::new(file) })
    }

    /// The name diagnostics give the program (`stdin` for `-`).
    pub fn name(&self) -> String {
        match self {
            ProgramFile::Path(p) => p.display().to_string(),
            ProgramFile::Spooled { name, .. } => name.clone(),
        }
    }

    /// The name's path, for the dialect's file extension (none for standard input; `P.ngc` for
    /// `P.ngc.gz`).
    fn path(&self) -> Option<PathBuf> {
        let path = match self {
            ProgramFile::Path(p) => p.clone(),
            ProgramFile::Spooled { name, .. } if name != STDIN_NAME => PathBuf::from(name),
            ProgramFile::Spooled { .. } => return None,
        };
        let compressed = path.extension().is_some_and(|e| ["gz", "zst"].iter().any(|c| e.eq_ignore_ascii_case(c)));
        Some(if compressed { path.with_extension("") } else { path })
    }

    /// The program's text from its start: the file's bytes, buffered, or, if they are gzip or zstd
    /// (known by their first bytes, whatever the name), decompressed as they are read.
    fn text(&self) -> std::io::Result<Opened> {
        let mut raw = BufReader::with_capacity(1 << 16, self.seekable()?);
        let head = raw.fill_buf()?;
        Ok(if head.starts_with(&GZIP_MAGIC) {
            Opened::Packed(Box::new(BufReader::with_capacity(1 << 16, flate2::bufread::MultiGzDecoder::new(raw))))
        } else if head.starts_with(&ZSTD_MAGIC) {
            Opened::Packed(Box::new(BufReader::with_capacity(1 << 16, zstd::stream::read::Decoder::with_buffer(raw)?)))
        } else {
            Opened::Plain(raw)
        })
    }

    fn reader(&self) -> Result<Box<dyn BufRead + Send>, LoadError> {
        match self.text() {
            Ok(Opened::Plain(r)) => Ok(Box::new(r)),
            Ok(Opened::Packed(r)) => Ok(r),
            Err(source) => Err(LoadError::Io { path: self.name(), source }),
        }
    }

    /// The file's bytes as stored (compressed or not), from its start, unbuffered.
    fn seekable(&self) -> std::io::Result<Box<dyn Text>> {
        Ok(match self {
            ProgramFile::Path(p) => Box::new(File::open(p)?),
            ProgramFile::Spooled { file, .. } => Box::new(AtOffset { file: file.clone(), offset: 0 }),
        })
    }

    /// The program's text for a reader that jumps (Klartext's calls and repeats), opened when
    /// first read: a plain file as it is; a compressed one unpacked then to an unlinked temporary
    /// file (at most [`MAX_SPOOL_BYTES`]).
    fn open_text(&self) -> OpenText<'static> {
        let this = self.clone();
        Box::new(move || match this.text()? {
            Opened::Plain(r) => {
                let mut text = r.into_inner();
                text.rewind()?;
                Ok(text)
            }
            Opened::Packed(r) => ProgramFile::spool(r, &this.name())?.seekable(),
        })
    }

    /// Open the program as a stream of blocks (memory flat in its length), detecting its dialect
    /// from its name and first lines unless given.
    pub fn open(&self, dialect: Option<Dialect>, options: &ReadOptions) -> Result<BlockStream, LoadError> {
        BlockStream::from_reader(self.reader()?, self.open_text(), self.path().as_deref(), &self.name(), dialect, &self.own_dir_first(options))
    }

    /// `options` with the program's own directory searched first where a control does so for the
    /// programs it calls (the 840D's subprograms).
    fn own_dir_first(&self, options: &ReadOptions) -> ReadOptions {
        let Some(path) = self.path() else { return options.clone() };
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        ReadOptions { subroutine_files: Some(Arc::new(OwnDirFirst { dir, then: options.subroutine_files.clone() })), ..options.clone() }
    }

    /// Read the program whole, detecting its dialect unless given. Bytes that are not UTF-8 are
    /// replaced (and reported where they stand).
    pub fn load(&self, dialect: Option<Dialect>, options: &ReadOptions) -> Result<Program, LoadError> {
        let mut bytes = Vec::new();
        fiveaxis_core::program::read_whole_bytes(self.reader()?, &mut bytes, &self.name())?;
        let text = String::from_utf8_lossy(&bytes);
        let given = dialect.is_some();
        let dialect = dialect.unwrap_or_else(|| Dialect::detect(self.path().as_deref(), &text));
        if let Some(d) = Dialect::unread(given, dialect, &text) {
            return Ok(fiveaxis_core::program::Program { source: self.name(), dialect, name: None, blocks: Vec::new(), diagnostics: vec![d] });
        }
        Ok(read(&text, dialect, &self.name(), &self.own_dir_first(options)))
    }
}

/// A program file opened at its start: plain text, or a decompressing reader of gzip or zstd.
enum Opened {
    Plain(BufReader<Box<dyn Text>>),
    Packed(Box<dyn BufRead + Send>),
}

/// The first bytes of a gzip member (RFC 1952) and of a zstd frame (RFC 8878).
const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];
const ZSTD_MAGIC: [u8; 4] = [0x28, 0xb5, 0x2f, 0xfd];

/// A reader of a shared file at its own offset (positioned reads: the file's own offset is not used).
struct AtOffset {
    file: Arc<File>,
    offset: u64,
}

impl Read for AtOffset {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        #[cfg(unix)]
        let n = std::os::unix::fs::FileExt::read_at(&*self.file, buf, self.offset)?;
        #[cfg(windows)]
        let n = std::os::windows::fs::FileExt::seek_read(&*self.file, buf, self.offset)?;
        self.offset += n as u64;
        Ok(n)
    }
}

impl Seek for AtOffset {
    fn seek(&mut self, to: SeekFrom) -> std::io::Result<u64> {
        let (base, by) = match to {
            SeekFrom::Start(n) => (0, n as i128),
            SeekFrom::Current(d) => (self.offset, d as i128),
            SeekFrom::End(d) => (self.file.metadata()?.len(), d as i128),
        };
        let at = u64::try_from(base as i128 + by).map_err(|_| std::io::Error::new(std::io::ErrorKind::InvalidInput, "seek before the start or past 2^64"))?;
        self.offset = at;
        Ok(at)
    }
}

/// Subprogram directories searched in order (`--subroutine-path`): LinuxCNC's SUBROUTINE_PATH for
/// `NAME.ngc`, the 840D's search path after the program's own directory for `NAME.SPF`; each file
/// read whole but no larger than the readers hold a block.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SubroutineDirs(pub Vec<PathBuf>);

impl fiveaxis_core::program::SubroutineFiles for SubroutineDirs {
    fn find_file(&self, names: &[String], any_case: bool, own_dir: bool) -> Result<Option<(String, Vec<u8>)>, String> {
        if own_dir {
            return Ok(None);
        }
        for dir in &self.0 {
            if let Some(found) = find_in(dir, names, any_case)? {
                return Ok(Some(found));
            }
        }
        Ok(None)
    }
}

/// The program's own directory beside the directories given (the 840D's search path begins in the
/// calling program's directory).
#[derive(Debug)]
struct OwnDirFirst {
    dir: PathBuf,
    then: Option<Arc<dyn fiveaxis_core::program::SubroutineFiles>>,
}

impl fiveaxis_core::program::SubroutineFiles for OwnDirFirst {
    fn find_file(&self, names: &[String], any_case: bool, own_dir: bool) -> Result<Option<(String, Vec<u8>)>, String> {
        match (own_dir, &self.then) {
            (true, _) => find_in(&self.dir, names, any_case),
            (false, Some(then)) => then.find_file(names, any_case, false),
            (false, None) => Ok(None),
        }
    }

    fn has_dirs(&self) -> bool {
        self.then.is_some()
    }
}

/// The first of `names` in `dir` (letters' case aside where `any_case`), read whole up to the
/// readers' bound.
fn find_in(dir: &Path, names: &[String], any_case: bool) -> Result<Option<(String, Vec<u8>)>, String> {
    // The directory's files, listed once for all the names (letters' case aside).
    let listed: Option<Vec<PathBuf>> = any_case.then(|| std::fs::read_dir(dir).map(|entries| entries.flatten().map(|e| e.path()).filter(|p| p.is_file()).collect()).unwrap_or_default());
    for name in names {
        // A name is a file name, not a path (LinuxCNC's find_ngc_file also expands one; not here).
        if name.is_empty() || name.contains(['/', '\\']) || name == ".." {
            return Err(format!("{name}: not a file name"));
        }
        let path = match &listed {
            Some(files) => match files.iter().find(|p| p.file_name().and_then(|f| f.to_str()).is_some_and(|f| f.eq_ignore_ascii_case(name))) {
                Some(p) => p.clone(),
                None => continue,
            },
            None => dir.join(name),
        };
        let shown = path.display().to_string();
        // A directory of that name is no program: the next name is tried.
        if !path.is_file() {
            continue;
        }
        let Ok(file) = File::open(&path) else { continue };
        let limit = fiveaxis_core::program::MAX_HELD_BYTES as u64;
        let mut bytes = Vec::new();
        file.take(limit + 1).read_to_end(&mut bytes).map_err(|e| format!("{shown}: {e}"))?;
        if bytes.len() as u64 > limit {
            return Err(format!("{shown} is larger than {limit} bytes"));
        }
        return Ok(Some((shown, bytes)));
    }
    Ok(None)
}
