//! Program files: opening them is the only part of reading a program that touches the file
//! system, so it lives here and the core's readers take text or bytes.

use fiveaxis_core::program::{read, BlockStream, Dialect, LoadError, Program, ReadOptions};
use std::io::BufReader;
use std::path::Path;

/// Read a program file whole, detecting its dialect unless given. Bytes that are not UTF-8 are
/// replaced (and reported where they stand).
pub fn load(path: &Path, dialect: Option<Dialect>, options: &ReadOptions) -> Result<Program, LoadError> {
    let bytes = std::fs::read(path).map_err(|source| LoadError::Io { path: path.display().to_string(), source })?;
    let text = String::from_utf8_lossy(&bytes);
    let dialect = dialect.unwrap_or_else(|| Dialect::detect(Some(path), &text));
    Ok(read(&text, dialect, &path.display().to_string(), options))
}

/// Open a program file as a stream of blocks (memory flat in its length), detecting its dialect
/// from its name and first lines unless given.
pub fn open(path: &Path, dialect: Option<Dialect>, options: &ReadOptions) -> Result<BlockStream, LoadError> {
    let file = std::fs::File::open(path).map_err(|source| LoadError::Io { path: path.display().to_string(), source })?;
    BlockStream::from_reader(BufReader::with_capacity(1 << 16, file), Some(path), &path.display().to_string(), dialect, options)
}
