//! LinuxCNC's subroutines defined after their call, in the program's own file: a call of a
//! subroutine not yet defined, and in no file of the search path, skips forward in the file to its
//! `o<name> sub` and runs it (interp_o_word.cc `control_back_to`: "1 -- if o_word is already
//! defined, just go back to it, else 2 -- if there is a file with the name of the o_word, open it
//! and start skipping, 3 -- skip to the o_word"). A main program followed by its subroutines after
//! `M2` is written so. The reader streams; the subroutine is read from the program's text again,
//! from the line after the call, as far as its `endsub` (bounded as a held block is).

use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::sync::{Arc, Mutex};

use super::oword::{parse, Keyword, OpenBlocks, MAX_HELD_BYTES, MAX_HELD_LINES};
use super::stream::{OpenText, Text, MAX_LINE_BYTES};

/// A line of a program: its 1-based number and text.
pub(crate) type Line = (usize, String);

/// A subroutine's lines, from the one that starts it to its end, and whether it is Fanuc-style
/// (`O<name>` ... `M99`) rather than `o<name> sub` ... `endsub`.
pub(crate) type SubLines = (Vec<Line>, bool);

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

    /// Subroutine `name`'s lines, from its start after line `after` to its end, and whether it is
    /// Fanuc-style ([`collect_sub`]); `Ok(None)` where the text has none there. In a file that opens
    /// with `%` (`percent`), nothing after the next `%` line is looked at: "The useful contents of a
    /// file demarcated by percents stop after the second percent line" (NIST IR 6556 §3.3.1).
    pub(crate) fn sub_after(&self, name: &str, after: usize, percent: bool) -> Result<Option<SubLines>, String> {
        match self {
            ProgramText::Bytes(b) => {
                let lines = b.split(|&c| c == b'\n').enumerate().skip(after).map(|(k, l)| Ok((k + 1, String::from_utf8_lossy(l).into_owned())));
                collect_sub(lines.take_while(|l| !(percent && ends_tape(l))), name, "the program")
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
                .skip(after)
                .take_while(|l| !(percent && ends_tape(l)));
                collect_sub(lines, name, "the program")
            }
        }
    }
}

/// Whether a line read is a `%` line.
fn ends_tape(line: &Result<Line, String>) -> bool {
    line.as_ref().is_ok_and(|(_, t)| t.trim_start().starts_with('%'))
}

/// Whether `text` may call a subroutine defined after the call (holds `call` or `M98`, in any case):
/// only such a program's text is kept for [`ProgramText`].
pub(crate) fn may_define_subs(text: &str) -> bool {
    let b = text.as_bytes();
    let ci = |at: usize, word: &[u8]| b.get(at..at + word.len()).is_some_and(|w| w.eq_ignore_ascii_case(word));
    memchr::memchr2_iter(b'c', b'C', b).any(|i| ci(i, b"call"))
        || memchr::memmem::find_iter(b, b"98").any(|i| b[..i].iter().rev().find(|c| !matches!(c, b' ' | b'\t' | b'0')).is_some_and(|c| c.eq_ignore_ascii_case(&b'm')))
}

/// The lines of subroutine `name` among `lines`, from the first line that starts it, `o<name> sub`
/// or a Fanuc-style `O<name>` alone (LinuxCNC skips to whichever comes first), to its end: its
/// `o<name> endsub`, or the first `M99` outside the O-word blocks in it. At most [`MAX_HELD_LINES`]
/// lines and [`MAX_HELD_BYTES`] bytes; `Ok(None)` where nothing starts it, an error where it does
/// not end; true with the lines where it is Fanuc-style. `shown` names the text in messages.
pub(crate) fn collect_sub(lines: impl Iterator<Item = Result<Line, String>>, name: &str, shown: &str) -> Result<Option<SubLines>, String> {
    let mut held: Vec<Line> = Vec::new();
    let mut fanuc = false;
    // A Fanuc-style body's O-word blocks open so far (an M99 in one is not its end).
    let mut open = OpenBlocks::default();
    let mut bytes = 0;
    for l in lines {
        let (k, raw) = l?;
        let raw = raw.trim_end_matches('\r');
        let o = parse(&raw.trim_start().chars().collect::<Vec<_>>());
        if held.is_empty() {
            match o {
                Some(o) if o.name.eq_ignore_ascii_case(name) && matches!(o.keyword, Keyword::Sub | Keyword::Title) => {
                    fanuc = o.keyword == Keyword::Title;
                    held.push((k, raw.to_string()));
                }
                _ => {}
            }
            continue;
        }
        let ends = match o {
            Some(o) if !fanuc => o.keyword == Keyword::EndSub && o.name.eq_ignore_ascii_case(name),
            Some(o) if o.keyword == Keyword::M99 => open.is_empty(),
            Some(o) => {
                open.pass(o);
                false
            }
            None => false,
        };
        if ends {
            held.push((k, raw.to_string()));
            return Ok(Some((held, fanuc)));
        }
        bytes += raw.len();
        if held.len() >= MAX_HELD_LINES || bytes > MAX_HELD_BYTES {
            return Err(format!("{shown}: {} holds more than {MAX_HELD_LINES} lines or {} MiB", start(name, fanuc), MAX_HELD_BYTES >> 20));
        }
        held.push((k, raw.to_string()));
    }
    match held.first() {
        Some((k, _)) if fanuc => Err(format!("{shown}: O{name} at line {k} has no M99 (a Fanuc-style subprogram ends with it)")),
        Some((k, _)) => Err(format!("{shown}: o{name} sub at line {k} has no o{name} endsub")),
        None => Ok(None),
    }
}

/// How a subroutine's start reads in messages.
fn start(name: &str, fanuc: bool) -> String {
    if fanuc {
        format!("O{name}")
    } else {
        format!("o{name} sub")
    }
}
