//! LinuxCNC's subroutines defined after their call, in the program's own file: a call of a
//! subroutine not yet defined, and in no file of the search path, skips forward in the file to its
//! `o<name> sub` and runs it (interp_o_word.cc `control_back_to`: "1 -- if o_word is already
//! defined, just go back to it, else 2 -- if there is a file with the name of the o_word, open it
//! and start skipping, 3 -- skip to the o_word"). A main program followed by its subroutines after
//! `M2` is written so. The reader streams; the subroutine is read from the program's text again,
//! from the line after the call, as far as its `endsub` (bounded as a held block is).

use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::sync::{Arc, Mutex};

use super::oword::{parse, Keyword, MAX_HELD_BYTES, MAX_HELD_LINES};
use super::stream::{OpenText, Text, MAX_LINE_BYTES};

/// A line of a program: its 1-based number and text.
pub(crate) type Line = (usize, String);

/// The program's own text, read again for a subroutine defined after its call.
pub(crate) enum ProgramText {
    /// Held whole (a program read from memory).
    Bytes(Arc<[u8]>),
    /// Opened when first needed (a program streamed from its file), then read from its start.
    File(Mutex<(Option<OpenText<'static>>, Option<Box<dyn Text>>)>),
}

impl std::fmt::Debug for ProgramText {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ProgramText::Bytes(_) => "ProgramText::Bytes",
            ProgramText::File(_) => "ProgramText::File",
        })
    }
}

impl ProgramText {
    /// The text a stream reads, opened when first needed.
    pub(crate) fn file(open: OpenText<'static>) -> ProgramText {
        ProgramText::File(Mutex::new((Some(open), None)))
    }

    /// Subroutine `name`'s lines, from its `o<name> sub` after line `after` to its `endsub`;
    /// `Ok(None)` where the text has none there.
    pub(crate) fn sub_after(&self, name: &str, after: usize) -> Result<Option<Vec<Line>>, String> {
        match self {
            ProgramText::Bytes(b) => {
                let lines = b.split(|&c| c == b'\n').enumerate().skip(after).map(|(k, l)| Ok((k + 1, String::from_utf8_lossy(l).into_owned())));
                collect_sub(lines, name, "the program")
            }
            ProgramText::File(m) => {
                let mut guard = m.lock().map_err(|_| "the program's text is not readable again".to_string())?;
                let (open, text) = &mut *guard;
                if text.is_none() {
                    let opener = open.take().ok_or("the program's text is not readable again")?;
                    *text = Some(opener().map_err(|e| format!("the program cannot be read again: {e}"))?);
                }
                let t = text.as_mut().ok_or("the program's text is not readable again")?;
                t.seek(SeekFrom::Start(0)).map_err(|e| format!("the program cannot be read again: {e}"))?;
                let mut reader = BufReader::new(t);
                let mut k = 0;
                let lines = std::iter::from_fn(move || {
                    let mut buf = Vec::new();
                    match reader.by_ref().take(MAX_LINE_BYTES as u64 + 1).read_until(b'\n', &mut buf) {
                        Ok(0) => None,
                        Ok(_) if buf.len() > MAX_LINE_BYTES => Some(Err(format!("line {} is longer than {MAX_LINE_BYTES} bytes", k + 1))),
                        Ok(_) => {
                            k += 1;
                            Some(Ok((k, String::from_utf8_lossy(&buf).trim_end_matches('\n').to_string())))
                        }
                        Err(e) => Some(Err(format!("the program cannot be read again: {e}"))),
                    }
                })
                .skip(after);
                collect_sub(lines, name, "the program")
            }
        }
    }
}

/// Whether `text` may define a subroutine (holds `sub` in any case): only such a program's text is
/// kept for [`ProgramText`].
pub(crate) fn may_define_subs(text: &str) -> bool {
    let b = text.as_bytes();
    memchr::memchr2_iter(b'u', b'U', b).any(|i| i > 0 && b[i - 1].eq_ignore_ascii_case(&b's') && b.get(i + 1).is_some_and(|c| c.eq_ignore_ascii_case(&b'b')))
}

/// The lines of subroutine `name` among `lines`: from its `o<name> sub` to its `endsub`, at most
/// [`MAX_HELD_LINES`] lines and [`MAX_HELD_BYTES`] bytes; `Ok(None)` where there is no `sub` line,
/// an error where it does not end. `shown` names the text in messages.
pub(crate) fn collect_sub(lines: impl Iterator<Item = Result<Line, String>>, name: &str, shown: &str) -> Result<Option<Vec<Line>>, String> {
    let mut held: Vec<Line> = Vec::new();
    let mut bytes = 0;
    for l in lines {
        let (k, raw) = l?;
        let raw = raw.trim_end_matches('\r');
        let o = parse(&raw.trim_start().chars().collect::<Vec<_>>()).filter(|o| o.name.eq_ignore_ascii_case(name));
        match (held.is_empty(), o.map(|o| o.keyword)) {
            (true, Some(Keyword::Sub)) => held.push((k, raw.to_string())),
            (true, _) => {}
            (false, Some(Keyword::EndSub)) => {
                held.push((k, raw.to_string()));
                return Ok(Some(held));
            }
            (false, _) => {
                bytes += raw.len();
                if held.len() >= MAX_HELD_LINES || bytes > MAX_HELD_BYTES {
                    return Err(format!("{shown}: o{name} sub holds more than {MAX_HELD_LINES} lines or {} MiB", MAX_HELD_BYTES >> 20));
                }
                held.push((k, raw.to_string()));
            }
        }
    }
    match held.first() {
        Some((k, _)) => Err(format!("{shown}: o{name} sub at line {k} has no o{name} endsub")),
        None => Ok(None),
    }
}
