//! Siemens Sinumerik 840D programs (`.MPF`/`.SPF`), as written from the 840D sl Programming Manual
//! Job Planning (6FC5398-2BP20, 5-axis transformation TRAORI) and Fundamentals: `N` numbers, `;`
//! comments, `G0/G1/G2/G3` (arcs: `I J K` from the start, or `CR=` radius, `TURN=` full turns),
//! `G17-G19`, `G90/G91`, `G93/G94`, `G70/G700/G71/G710`, `G54-G57`/`G500`, blending `G64`/`G641`-`G645`,
//! `TRAORI`/`TRAFOOF` (tool-centre point), the tool vector `A3= B3= C3=` (a missing component is 0;
//! it points from the tip to the tool holder), rotary axes `A= B= C=`, `ORIWKS`/`ORIVECT`/`ORIPLANE`
//! (the tool axis on a great circle in the workpiece, the reset state) and `ORIMKS`/`ORIAXES` (the
//! rotary axes linear), `TRANS`/`ATRANS` frames (a datum shift), `T`, `D`, `S`, `M`, `F`, `M30`.
//!
//! What changes the motion and is not modelled is an error at its line and column, never skipped:
//! `ROT`/`AROT`/`SCALE`/`MIRROR` frames, `CYCLE800` (a swivel: a tilted working plane), other cycles
//! and subprogram calls, R parameters and expressions (`X=R1+5`, `AC(..)`), exact stop (`G60`, `G9`),
//! cutter compensation, orientation by angles (`A2=`) or cone/polynomial orientation.
//!
//! Orientation interpolation: which of ORIWKS/ORIMKS and ORIVECT/ORIAXES governs depends on machine
//! datum MD21104 `ORI_IPO_WITH_G_CODE`; here the one programmed last governs (at reset ORIWKS and
//! ORIVECT agree: the great circle).

use super::interp::{Interpreter, Word};
use super::lex::{excerpt, parse_number, Columns, Diags};
use super::{Dialect, MCodeRule, Orientation, Program};

/// Read a Sinumerik program on a control whose orientation interpolation starts as `orientation`
/// (the reset state is [`Orientation::GreatCircle`], ORIWKS/ORIVECT).
pub fn read_sinumerik_with(text: &str, m_codes: &[MCodeRule], orientation: Orientation) -> Program {
    super::stream::read_whole(&mut SinumerikReader::new(&super::Setup::plain(Dialect::Sinumerik, m_codes, orientation)), text, Dialect::Sinumerik)
}

/// The Sinumerik reader, fed one line at a time.
#[derive(Debug, Clone)]
pub(crate) struct SinumerikReader {
    interp: Interpreter,
}

impl SinumerikReader {
    pub(crate) fn new(setup: &super::Setup) -> Self {
        SinumerikReader { interp: setup.interpreter() }
    }
}

impl super::stream::LineReader for SinumerikReader {
    fn line(&mut self, line: usize, text: &str, out: &mut Vec<super::Block>, diags: &mut Diags) {
        let text_line = text.trim_end_matches('\r');
        let Some(first) = text_line.find(|c: char| !c.is_whitespace()) else { return };
        if text_line[first..].starts_with('%') {
            return; // `%_N_NAME_MPF` transfer header
        }
        let errors_before = diags.errors();
        let cols = Columns::new(text_line);
        let first = cols.col(first) - 1;
        let lexed = lex_line(text_line, &cols, line, diags);
        if diags.errors() > errors_before {
            diags.warning(line, first + 1, format!("line {line} not used: it is damaged"));
            return;
        }
        let Lexed { mut words, number, keywords, vector, frame } = lexed;
        let saved = self.interp.clone();
        for (k, col) in &keywords {
            match k.as_str() {
                "TRAORI" => self.interp.set_tcp(true),
                "TRAFOOF" => self.interp.set_tcp(false),
                "ORIWKS" | "ORIVECT" | "ORIPLANE" => self.interp.set_orientation(Orientation::GreatCircle),
                "ORIMKS" | "ORIAXES" => self.interp.set_orientation(Orientation::AxisLinear),
                // Angle conventions for A2 B2 C2, which are not read: no effect on these programs.
                "ORIEULER" | "ORIRPY" => {}
                // Acceleration modes: the planner always limits jerk.
                "SOFT" | "BRISK" => {}
                "TRANS" | "ATRANS" => {}
                other => diags.error(line, *col, format!("{other}: {}", unsupported_keyword(other))),
            }
        }
        if let Some(kind) = frame {
            // TRANS X Y Z: the frame's offset, not a move (and alone in its block, as the manual asks).
            let unit = self.interp.unit();
            let mut datum = if kind == "ATRANS" { self.interp.datum() } else { [0.0; 3] };
            for w in words.drain(..) {
                match "XYZ".find(w.letter) {
                    Some(k) => datum[k] += w.value * unit,
                    None => diags.error(line, w.column, format!("{}{} in a {kind} block: a frame block holds only the offset X Y Z", w.letter, w.raw)),
                }
            }
            if diags.errors() > errors_before {
                self.interp = saved;
                return;
            }
            self.interp.set_datum(datum);
            return;
        }
        if diags.errors() > errors_before {
            self.interp = saved;
            diags.warning(line, first + 1, format!("line {line} not used"));
            return;
        }
        // A block of only a tool vector still moves.
        match vector {
            Some(v) => self.interp.set_pending_vector(v),
            None if words.is_empty() => return,
            None => {}
        }
        let col = words.iter().map(|w| w.column).min().unwrap_or(first + 1).min(first + 1);
        if !self.interp.block(&words, line, col, number, diags, out) {
            self.interp = saved;
            diags.warning(line, first + 1, format!("line {line} not used"));
        }
    }
}

/// Why a keyword is refused.
fn unsupported_keyword(k: &str) -> &'static str {
    match k {
        "ROT" | "AROT" | "SCALE" | "ASCALE" | "MIRROR" | "AMIRROR" | "ROTS" | "AROTS" | "CROTS" => {
            "frame rotation, scaling or mirroring is not modelled (it changes the motion)"
        }
        "CYCLE800" => "swivel (CYCLE800): a tilted working plane, not modelled (it changes the motion)",
        "TRAFOOF_" | "TRANSMIT" | "TRACYL" | "TRAANG" => "this transformation is not modelled",
        "ORICONCW" | "ORICONCCW" | "ORICONTO" | "ORICONIO" | "ORICURVE" | "ORIPATH" | "ORIPATHS" | "ORIROTA" | "ORIROTR" | "ORIROTT" | "ORIROTC" => {
            "this orientation interpolation (cone, curve or path-relative) is not modelled"
        }
        "G60" | "G9" => "exact stop is not modelled: the planner blends blocks as G64 does",
        "OFFN" | "CUT2D" | "CUT3DC" | "CUT3DF" => "cutter compensation is not modelled",
        "FGROUP" | "FGREF" => "feed reference axes are not modelled (they change how F is read)",
        "GOTOF" | "GOTOB" | "GOTO" | "CALL" | "REPEAT" | "IF" | "ELSE" | "ENDIF" | "WHILE" | "ENDWHILE" | "FOR" | "ENDFOR" | "LOOP" | "ENDLOOP" | "DEF" | "PROC" | "RET" => {
            "program control (jumps, loops, calls, definitions) is not modelled"
        }
        _ => "unknown instruction: not read (it may change the motion)",
    }
}

struct Lexed<'a> {
    words: Vec<Word<'a>>,
    number: Option<u64>,
    /// Keywords and their columns.
    keywords: Vec<(String, usize)>,
    /// A3 B3 C3, unit.
    vector: Option<[f64; 3]>,
    /// TRANS or ATRANS.
    frame: Option<&'static str>,
}

/// Split one line into words; defects go to `diags`. Works on bytes: every character that can
/// form a word is ASCII, and any other one is reported where it stands.
fn lex_line<'a>(src: &'a str, cols: &Columns<'_>, line_no: usize, diags: &mut Diags) -> Lexed<'a> {
    let b = src.as_bytes();
    let n = b.len();
    let mut out = Lexed { words: Vec::with_capacity(8), number: None, keywords: Vec::new(), vector: None, frame: None };
    let mut vec3: [Option<f64>; 3] = [None; 3];
    let mut vec_col = 0;
    let mut i = src.find(|c: char| !c.is_whitespace()).unwrap_or(n);
    let line = line_no;
    if i < n && b[i] == b'/' {
        diags.warning(line, cols.col(i), "block skip '/' is not modelled: the block is run");
        i += 1;
    }
    // The end of a token from byte `from`: the next whitespace or ';'.
    let token_end = |from: usize| {
        let mut e = from;
        while e < n && !b[e].is_ascii_whitespace() && b[e] != b';' {
            e += 1;
        }
        // Stay on a character boundary (a non-ASCII byte belongs to the token).
        while e < n && !src.is_char_boundary(e) {
            e += 1;
        }
        e
    };
    while i < n {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        if !src.is_char_boundary(i) {
            i += 1;
            continue;
        }
        if c == b';' {
            break;
        }
        let col = cols.col(i);
        if !c.is_ascii_alphabetic() && c != b'_' {
            let end = token_end(i).max(i + 1);
            let end = (end..=n).find(|&e| src.is_char_boundary(e)).unwrap_or(n);
            diags.error(line, col, format!("unexpected '{}': expected a word such as G1 or X=10.5", excerpt(&src[i..end])));
            i = end;
            continue;
        }
        // Address: letters, then digits that belong to it only when '=' follows (A3=, CR=, TURN=).
        let mut j = i;
        while j < n && (b[j].is_ascii_alphabetic() || b[j] == b'_') {
            j += 1;
        }
        let mut k = j;
        while k < n && b[k].is_ascii_digit() {
            k += 1;
        }
        let mut e = k;
        while e < n && (b[e] == b' ' || b[e] == b'\t') {
            e += 1;
        }
        let with_eq = e < n && b[e] == b'=';
        let letters = &src[i..j];
        let (address, value_start) = if with_eq { (&src[i..k], e + 1) } else { (letters, j) };
        let is = |a: &str, w: &str| a.eq_ignore_ascii_case(w);
        // Keywords: more than one letter and no '=' (TRAORI, ORIWKS, MSG(...), CYCLE800(...)).
        if !with_eq && letters.len() > 1 {
            let mut end = k;
            if end < n && b[end] == b'(' {
                // Arguments: up to the matching ')'.
                let mut depth = 0;
                while end < n {
                    match b[end] {
                        b'(' => depth += 1,
                        b')' => {
                            depth -= 1;
                            if depth == 0 {
                                end += 1;
                                break;
                            }
                        }
                        _ => {}
                    }
                    end += 1;
                }
            }
            let name = src[i..k].to_ascii_uppercase();
            match name.as_str() {
                "MSG" => {}
                "TRANS" => out.frame = Some("TRANS"),
                "ATRANS" => out.frame = Some("ATRANS"),
                _ => out.keywords.push((name, col)),
            }
            // TRAORI(1): the first transformation, as plain TRAORI.
            i = end.max(k);
            while i < n && !src.is_char_boundary(i) {
                i += 1;
            }
            continue;
        }
        let mut v = value_start;
        while with_eq && v < n && (b[v] == b' ' || b[v] == b'\t') {
            v += 1;
        }
        if is(address, "T") && v < n && b[v] == b'"' {
            // T="NAME": a tool called by name (an event, as T5 is).
            match src[v + 1..].find('"') {
                Some(p) => {
                    let e = v + 1 + p + 1;
                    out.words.push(Word { letter: 'T', value: 0.0, raw: src[v..e].into(), column: col, incremental: false });
                    i = e;
                }
                None => {
                    diags.error(line, col, "T=\"...: the tool name's quote is not closed on this line");
                    i = n;
                }
            }
            continue;
        }
        let start = v;
        let mut end = v;
        while end < n && (b[end].is_ascii_digit() || b[end] == b'.' || ((b[end] == b'+' || b[end] == b'-') && end == start)) {
            end += 1;
        }
        let text = &src[start..end];
        let stop = token_end(end);
        let parsed = parse_number(text);
        if stop > end || parsed.is_none() {
            let found = &src[start..token_end(start)];
            let what = if found.contains('(') || found.contains('R') || found.chars().any(|c| "+-*/".contains(c)) && !found.is_empty() {
                "an expression or R parameter, which is not read"
            } else {
                "not a number"
            };
            diags.error(line, col, format!("{address}: expected a number, found '{}' ({what})", excerpt(found)));
            i = token_end(start).max(i + 1);
            while i < n && !src.is_char_boundary(i) {
                i += 1;
            }
            continue;
        }
        let value = parsed.unwrap_or(0.0);
        i = end;
        let word = |letter: char, value: f64, raw: std::borrow::Cow<'a, str>| Word { letter, value, raw, column: col, incremental: false };
        let upper_letter = |a: &str| a.as_bytes()[0].to_ascii_uppercase() as char;
        match address.len() {
            1 => match upper_letter(address) {
                'N' if value.fract() == 0.0 && value >= 0.0 => out.number = Some(value as u64),
                'N' => diags.error(line, col, format!("expected a whole block number after 'N', found '{text}'")),
                'G' => match sinumerik_g(text) {
                    Ok(Some(g)) => out.words.push(word('G', parse_number(g).unwrap_or(0.0), g.into())),
                    Ok(None) => {}
                    Err(why) => diags.error(line, col, format!("G{text}: {why}")),
                },
                l @ ('X' | 'Y' | 'Z' | 'A' | 'B' | 'C' | 'I' | 'J' | 'K' | 'F' | 'M' | 'S' | 'T') => out.words.push(word(l, value, text.into())),
                'D' => {} // tool offset number: the tool length is the machine file's
                'H' => diags.error(line, col, format!("H{text}: auxiliary function not read")),
                _ => diags.error(line, col, format!("unsupported word {address}={text}: not read (it may change the motion)")),
            },
            _ if is(address, "A3") || is(address, "B3") || is(address, "C3") => {
                vec3[usize::from(upper_letter(address) as u8 - b'A')] = Some(value);
                vec_col = if vec_col == 0 { col } else { vec_col };
            }
            _ if is(address, "CR") => out.words.push(word('R', value, text.into())),
            _ if is(address, "TURN") && value.fract() == 0.0 && (0.0..1000.0).contains(&value) => {
                out.words.push(word('P', value + 1.0, format!("{}", value + 1.0).into()))
            }
            _ if is(address, "TURN") => diags.error(line, col, format!("TURN={text}: expected a whole number of turns, 0 to 999")),
            _ => diags.error(line, col, format!("unsupported word {}={text}: not read (it may change the motion)", address.to_ascii_uppercase())),
        }
    }
    if vec3.iter().any(Option::is_some) {
        let v = vec3.map(|c| c.unwrap_or(0.0)); // a component not written is 0 (840D: not modal)
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if n > 1e-9 {
            out.vector = Some(v.map(|c| c / n));
        } else {
            diags.error(line, vec_col, "tool vector A3 B3 C3 has zero length: expected a direction");
        }
    }
    out
}

/// A Sinumerik G code as the shared interpreter reads it (`Ok(None)`: no effect on the path), or why
/// it is refused.
fn sinumerik_g(code: &str) -> Result<Option<&'static str>, &'static str> {
    let n = code.trim_start_matches('0');
    Ok(Some(match n {
        "" => "0",
        "1" => "1",
        "2" => "2",
        "3" => "3",
        "17" => "17",
        "18" => "18",
        "19" => "19",
        "40" => "40",
        "90" => "90",
        "91" => "91",
        "93" => "93",
        "94" => "94",
        "54" => "54",
        "55" => "55",
        "56" => "56",
        "57" => "57",
        // Settable frames off: the offsets taken as zero, as G54 without offsets is.
        "500" => "54",
        "70" | "700" => "20",
        "71" | "710" => "21",
        // Continuous-path modes and smoothing: what the planner does.
        "64" | "641" | "642" | "643" | "644" | "645" => return Ok(None),
        "60" | "9" => return Err("exact stop is not modelled: the planner blends blocks as G64 does"),
        "4" => "4",
        "41" | "42" => return Err("cutter radius compensation is not supported"),
        "53" | "153" => return Err("suppressing the frames is not modelled (machine coordinates)"),
        "95" | "96" | "97" => return Err("feed per revolution or constant cutting speed is not supported"),
        "110" | "111" | "112" => return Err("polar coordinates are not supported"),
        "25" | "26" | "74" | "75" => return Err("working-area limits and reference-point moves are not supported"),
        "33" | "331" | "332" | "63" => return Err("threading and tapping are not supported"),
        _ => return Err("unknown G code: not read (it may change the motion)"),
    }))
}
