//! The dialects the readers understand, their names, and how a program's own words tell which it is
//! written in.

use super::{apt, Diagnostic, Orientation, Severity};
use std::path::Path;

/// The dialects the readers understand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Dialect {
    /// Heidenhain DIN/ISO (`%NAME G71 *`, `N10 G01 X+0 *`).
    Heidenhain,
    /// RS274NGC (LinuxCNC, Fanuc style).
    Rs274,
    /// Cutter-location data: one `x y z i j k` pose per line, or APT CLDATA (`GOTO/x,y,z,i,j,k`).
    Cl,
    /// Siemens Sinumerik 840D (`.MPF`, `TRAORI`, tool vectors `A3= B3= C3=`).
    Sinumerik,
    /// Heidenhain conversational (Klartext, `.H`: `BEGIN PGM NAME MM`, `L X+0 Y+0 R0 F1000`).
    Klartext,
    /// Fanuc Series 30i/31i and the controls that follow it (Mori Seiki's MAPPS): G-code as
    /// RS274NGC, with Fanuc's own reference returns, canned cycles, dwell in ms and codes.
    Fanuc,
    /// Haas NGC mills: Fanuc-style G-code with Haas' own rules (G28 with no axis homes every axis,
    /// G234 TCPC, G254 DWO, G187, dwell in seconds, L as the repeat count).
    Haas,
}

/// How many of a program's first lines its dialect is judged from.
pub const DETECT_LINES: usize = 2000;

/// A dialect by the names people call it (`--dialect`): heidenhain (din, iso), rs274 (ngc, gcode,
/// linuxcnc), cl, sinumerik (840d, siemens), klartext (conversational), fanuc, haas; case-insensitive.
impl std::str::FromStr for Dialect {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "heidenhain" | "din" | "iso" => Ok(Dialect::Heidenhain),
            "rs274" | "ngc" | "gcode" | "linuxcnc" => Ok(Dialect::Rs274),
            "cl" => Ok(Dialect::Cl),
            "sinumerik" | "840d" | "siemens" => Ok(Dialect::Sinumerik),
            "klartext" | "conversational" => Ok(Dialect::Klartext),
            "fanuc" => Ok(Dialect::Fanuc),
            "haas" => Ok(Dialect::Haas),
            _ => Err(format!("unknown dialect '{s}': expected heidenhain, rs274, cl, sinumerik, klartext, fanuc or haas")),
        }
    }
}

impl Dialect {
    /// True if a program in this dialect starts at its first pose (CL data: the first line is where
    /// the tool is), false if its first move starts from the machine's home (NC programs).
    pub fn starts_at_first_pose(self) -> bool {
        self == Dialect::Cl
    }

    /// True if, without tool-centre-point control, a move of linear and rotary axes together takes F
    /// along a path whose rotary part counts degrees as the program's length unit: Fanuc's (FANUC
    /// B-63174EN §4.2, "G91 G01 X20.0 C40.0 F300.0 ... time = sqrt(20^2 + 40^2) / 300"). LinuxCNC and
    /// Siemens give F to the linear axes, the rotary ones following.
    pub fn counts_degrees_in_feed_path(self) -> bool {
        self == Dialect::Fanuc
    }

    /// How a control of this dialect interpolates the tool orientation under tool-centre-point
    /// management unless told otherwise. Heidenhain: `M128` moves the rotary axes linearly (as
    /// FUNCTION TCPM's `PATHCTRL AXIS`, with which "the tool circumference does not describe a defined
    /// path"). RS274NGC: LinuxCNC interpolates the joints linearly (src/emc/tp/tc.c; its TCP
    /// kinematics map the axes only), and Fanuc's G43.4/G43.5 by default move "the two rotary axes
    /// independently" (30i Tool Posture Control, A-79294E: the great circle is an option). CL data:
    /// the control that runs it decides; axis-linear, as the post-processed program runs on a TNC.
    pub fn default_orientation(self) -> Orientation {
        match self {
            Dialect::Heidenhain | Dialect::Rs274 | Dialect::Cl | Dialect::Klartext | Dialect::Fanuc | Dialect::Haas => Orientation::AxisLinear,
            // ORIWKS and ORIVECT are the reset state (840D sl Programming Manual Job Planning
            // 03/2006 §7.1.2: "The default setting is ORIWKS"; G group 51 default ORIVECT, large-circle
            // interpolation, Fundamentals 10/2004 §12.3).
            Dialect::Sinumerik => Orientation::GreatCircle,
        }
    }

    /// True for the Fanuc-style dialects (Fanuc, Haas): reference returns, canned cycles and work
    /// offsets as Fanuc reads them.
    pub fn is_fanuc(self) -> bool {
        matches!(self, Dialect::Fanuc | Dialect::Haas)
    }

    /// True for the dialects read by the RS274 reader (LinuxCNC, Fanuc, Haas).
    pub fn is_rs274_family(self) -> bool {
        matches!(self, Dialect::Rs274 | Dialect::Fanuc | Dialect::Haas)
    }

    /// An arc's radius address as programs in this dialect write it, for messages: the 840D's is
    /// `CR=` (Programming Manual Fundamentals, "Circular interpolation with radius and end point"),
    /// every other dialect's `R`. The readers take both as the word R.
    pub fn radius_address(self) -> &'static str {
        if self == Dialect::Sinumerik { "CR=" } else { "R" }
    }

    /// The dialect of a program for a machine whose control reads `control`: a file whose content
    /// or name says nothing beyond generic G-code (what [`Dialect::detect`] calls RS274NGC) is read
    /// in the control's own G-code dialect.
    pub fn detect_for(path: Option<&Path>, text: &str, control: Option<Dialect>) -> Dialect {
        match (Dialect::detect(path, text), control) {
            (Dialect::Rs274, Some(c)) if c.is_rs274_family() => c,
            (d, _) => d,
        }
    }

    /// The refusal of a program whose dialect was detected (`given` false) as the RS274 family but
    /// whose first lines are in a language no reader follows ([`Dialect::unread_language`]).
    pub fn unread(given: bool, detected: Dialect, text: &str) -> Option<Diagnostic> {
        Dialect::listing_header(text, detected).or_else(|| (!given && detected.is_rs274_family()).then(|| Dialect::unread_language(text)).flatten())
    }

    /// Siemens NX's "Information listing" header before a program (`====`, `Information listing
    /// created by : user`, `Date : ..`, `Current work part : ..`, `Node name : ..`, `====`): what NX's
    /// listing window writes when a post's output is sent there and saved with it. It is no NC code
    /// in any dialect and no control reads it: refused once, at its line, rather than as one defect
    /// per line. Before a Fanuc or Haas tape's first `%` it is the tape's leader, skipped as such.
    pub fn listing_header(text: &str, dialect: Dialect) -> Option<Diagnostic> {
        let text = text.strip_prefix(super::stream::BOM).unwrap_or(text);
        const HEAD: &str = "information listing created by";
        // Looked for line by line first: the lines are gathered only where it stands (rarely).
        let at = head_lines(text).position(|l| l.trim_start().get(..HEAD.len()).is_some_and(|h| h.eq_ignore_ascii_case(HEAD)))?;
        let lines: Vec<&str> = head_lines(text).collect();
        // Before a Fanuc or Haas tape's first %, it is the leader, skipped as such; after it, code.
        if dialect.is_fanuc() && lines[at..].iter().any(|l| l.trim() == "%") {
            return None;
        }
        let rule = |l: &&str| l.trim().len() >= 10 && l.trim().bytes().all(|b| b == b'=');
        let first = if at > 0 && rule(&lines[at - 1]) { at - 1 } else { at };
        let last = lines[at + 1..].iter().take(12).position(rule).map_or(at, |k| at + 1 + k);
        Some(Diagnostic {
            line: at + 1,
            column: lines[at].len() - lines[at].trim_start().len() + 1,
            severity: Severity::Error,
            message: format!(
                "lines {}-{}: NX's \"Information listing\" header, which NX's listing window writes before a post's output: no NC code, and no control reads it; delete it from the file (nothing was read)",
                first + 1,
                last + 1
            ),
        })
    }

    /// A program that its name or first lines send to the RS274 family but that is written in a
    /// language no reader here follows: Heidenhain MillPlus's ISO dialect, recognised by a `G7` block
    /// with MillPlus's angle words `A5=` `B5=` `C5=` (its tilted working plane, as NX's and Autodesk's
    /// MillPlus posts write it; no RS274 word holds `=`). Read as G-code it would give an error on
    /// nearly every block: refused once instead, at that block (within the first [`DETECT_LINES`]).
    pub fn unread_language(text: &str) -> Option<Diagnostic> {
        // Columns count from the line's first character, not from a byte-order mark before it.
        let text = text.strip_prefix(super::stream::BOM).unwrap_or(text);
        head_lines(text).enumerate().find_map(|(i, raw)| {
            // A line without `=` or `7` holds neither the angle words nor `G7`: passed over without
            // the copy below (most lines of most programs).
            if !raw.contains('=') || !raw.contains('7') {
                return None;
            }
            // The code of the line: no `( )` comment, nothing after `;`.
            let mut code = String::with_capacity(raw.len());
            let mut depth = 0usize;
            for c in raw.chars().take_while(|&c| c != ';') {
                match c {
                    '(' => depth += 1,
                    ')' => depth = depth.saturating_sub(1),
                    _ if depth == 0 => code.push(c.to_ascii_uppercase()),
                    _ => code.push(' '),
                }
            }
            let words: Vec<&str> = code.split_whitespace().collect();
            let g7 = words.iter().position(|w| *w == "G7" || *w == "G07")?;
            words.iter().any(|w| ["A5=", "B5=", "C5="].iter().any(|a| w.starts_with(a))).then(|| Diagnostic {
                line: i + 1,
                column: code.find(words[g7]).map_or(1, |b| code[..b].chars().count() + 1),
                severity: Severity::Error,
                message: format!(
                    "{}: a Heidenhain MillPlus program (its tilted plane G7 with A5= B5= C5=): fiveaxis does not read MillPlus ISO (its G7, G141 and G74 follow no manual within reach); nothing was read",
                    words.join(" ")
                ),
            })
        })
    }

    /// Guess the dialect from the file name, then from the text.
    pub fn detect(path: Option<&Path>, text: &str) -> Dialect {
        let ext = path
            .and_then(|p| p.extension())
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        let text = text.strip_prefix(super::stream::BOM).unwrap_or(text);
        // The first line that is not a comment (`;` in every dialect, `#` in CL data, `(` in RS274NGC):
        // a comment's words say nothing of the dialect (a `; ...` header of six words is not CL data).
        let first = lines(text).map(str::trim).find(|l| !l.is_empty() && !l.starts_with([';', '#', '('])).unwrap_or("");
        // Content that only one dialect writes decides before the extension (`.h` is both
        // Heidenhain's DIN/ISO and conversational; `.nc` is used by every control).
        let upper = |l: &str| l.to_ascii_uppercase();
        // One pass over the first lines: Klartext's `BEGIN PGM` in the first 50, APT's `GOTO/` and
        // the 840D's words in all of them (each looked for until found).
        let (mut klartext, mut goto, mut sinumerik) = (false, false, false);
        for (i, l) in head_lines(text).enumerate() {
            if i < 50 && !klartext {
                let u = upper(l);
                let body = u.trim_start().trim_start_matches(|c: char| c.is_ascii_digit()).trim_start();
                klartext = body.starts_with("BEGIN PGM");
            }
            goto = goto || apt::is_goto(l);
            sinumerik = sinumerik || sinumerik_word(&l.as_bytes()[..memchr::memchr(b';', l.as_bytes()).unwrap_or(l.len())]) || sinumerik_line(l);
            if klartext || goto && sinumerik {
                break;
            }
        }
        if klartext {
            return Dialect::Klartext;
        }
        // APT CLDATA: a motion statement (`GOTO/`) no NC dialect writes, or a first statement that is
        // APT's (`PARTNO`, `$$`, `MACHIN/`, ...), as the CL reader itself takes it.
        if apt::is_apt_line(first) || goto {
            return Dialect::Cl;
        }
        match ext.as_str() {
            "i" | "iso" => return Dialect::Heidenhain,
            "mpf" | "spf" => return Dialect::Sinumerik,
            _ if sinumerik => return Dialect::Sinumerik,
            "h" => return Dialect::Heidenhain,
            "ngc" | "nc" | "gcode" | "tap" | "cnc" => return Dialect::Rs274,
            "cl" | "csv" | "cls" | "apt" | "clsf" | "aptsource" => return Dialect::Cl,
            _ => {}
        }
        if first.starts_with('%') && first.ends_with('*') || text.contains(" *\n") {
            Dialect::Heidenhain
        } else if first
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
            .count()
            >= 6
            && !first.chars().next().is_some_and(|c| c.is_ascii_alphabetic() && "GMNXYZgmnxyz".contains(c))
        {
            Dialect::Cl
        } else {
            Dialect::Rs274
        }
    }
}

/// The lines of `text` as `str::lines` splits them (at `\n`, a `\r` before it dropped), found with
/// the memchr crate's vector search: the dialect's tests pass over the first lines three times.
fn lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = Some(text).filter(|t| !t.is_empty());
    std::iter::from_fn(move || {
        let t = rest?;
        Some(match memchr::memchr(b'\n', t.as_bytes()) {
            Some(k) => {
                rest = Some(&t[k + 1..]).filter(|n| !n.is_empty());
                t[..k].strip_suffix('\r').unwrap_or(&t[..k])
            }
            None => {
                rest = None;
                t
            }
        })
    })
}

/// The first [`DETECT_LINES`] lines of `text`, those the dialect is told from.
fn head_lines(text: &str) -> impl Iterator<Item = &str> {
    lines(text).take(DETECT_LINES)
}

/// Lines only the 840D writes: its transfer header `%_N_NAME_MPF` (or `_SPF`: Job Planning, "Program
/// management", a program's name as the control stores it) and a definition of a variable
/// (`DEF REAL X1`, `N10 DEF INT CNT`: Job Planning, "Variable definition"), which no other dialect
/// read here has.
fn sinumerik_line(l: &str) -> bool {
    let t = l.trim_start();
    if t.get(..4).is_some_and(|p| p.eq_ignore_ascii_case("%_N_")) {
        return true;
    }
    // After a block number, `DEF` and a type.
    let t = match t.strip_prefix(['N', 'n']) {
        Some(r) if r.starts_with(|c: char| c.is_ascii_digit()) => r.trim_start_matches(|c: char| c.is_ascii_digit()).trim_start(),
        _ => t,
    };
    let Some(rest) = t.get(..4).filter(|p| p.eq_ignore_ascii_case("DEF ")).map(|_| t[4..].trim_start()) else { return false };
    ["REAL", "INT", "BOOL", "CHAR", "STRING", "AXIS", "FRAME"].iter().any(|ty| rest.get(..ty.len()).is_some_and(|p| p.eq_ignore_ascii_case(ty)) && rest[ty.len()..].starts_with([' ', '\t', '[']))
}

/// Words only the 840D writes among the dialects read here (its transformations, orientation modes,
/// swivel cycle, tool-vector words, and G codes of its own), in capitals.
const SINUMERIK_WORDS: [&[u8]; 12] = [b"TRAORI", b"TRAFOOF", b"ORIWKS", b"ORIMKS", b"ORIVECT", b"ORIAXES", b"CYCLE800", b"A3=", b"B3=", b"C3=", b"G642", b"G500"];

/// Whether `code` holds one of [`SINUMERIK_WORDS`] in any case: a pass over its bytes, comparing
/// only where a word's first letter stands, and only the words it starts (no copy of the line in
/// capitals). Eight bytes at a time are passed over where none is a letter (bit 0x40 clear: the
/// digits, blanks, signs and points that most of a G-code line is), as no word starts there.
fn sinumerik_word(code: &[u8]) -> bool {
    // For each byte, the words it starts (bit k: word k), in either case: from the words themselves.
    const STARTS: [u16; 256] = {
        let mut t = [0u16; 256];
        let mut k = 0;
        while k < SINUMERIK_WORDS.len() {
            let c = SINUMERIK_WORDS[k][0];
            t[c as usize] |= 1 << k;
            t[c.to_ascii_lowercase() as usize] |= 1 << k;
            k += 1;
        }
        t
    };
    // Every word starts with a letter, whose byte has bit 0x40 set in either case.
    const _: () = {
        let mut k = 0;
        while k < SINUMERIK_WORDS.len() {
            assert!(SINUMERIK_WORDS[k][0].is_ascii_alphabetic());
            k += 1;
        }
    };
    const LETTER_BITS: u64 = 0x4040_4040_4040_4040;
    let starts_at = |i: usize| {
        let mut words = STARTS[usize::from(code[i])];
        while words != 0 {
            let w = SINUMERIK_WORDS[words.trailing_zeros() as usize];
            if code[i..].get(..w.len()).is_some_and(|s| s.eq_ignore_ascii_case(w)) {
                return true;
            }
            words &= words - 1;
        }
        false
    };
    let mut chunks = code.chunks_exact(8);
    for (k, chunk) in chunks.by_ref().enumerate() {
        let bytes = u64::from_le_bytes([chunk[0], chunk[1], chunk[2], chunk[3], chunk[4], chunk[5], chunk[6], chunk[7]]);
        if bytes & LETTER_BITS != 0 && (8 * k..8 * k + 8).any(starts_at) {
            return true;
        }
    }
    let tail = code.len() - chunks.remainder().len();
    (tail..code.len()).any(starts_at)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::program::lex;

    /// The 840D's words are found in any case, anywhere in a line's code, as the line copied in
    /// capitals and searched word by word finds them (the definition the scanner replaces), over
    /// 200,000 lines drawn from pieces of the words, in either case, with `=`, `;`, blanks and a
    /// non-ASCII letter.
    #[test]
    fn sinumerik_words_are_found_as_in_the_line_in_capitals() {
        let mut next = lex::xorshift(0x1234_5678_9ABC_DEF1);
        let pieces = ["TRA", "tra", "ORI", "oRi", "FOOF", "WKS", "mks", "VECT", "AXES", "CYCLE", "cycle", "800", "A3", "b3", "C", "3=", "=", "G6", "g5", "42", "00", " ", ";", "Ä", "X1"];
        let mut found = 0;
        for _ in 0..200_000 {
            let len = (next() % 10) as usize;
            let line: String = (0..len).map(|_| pieces[(next() % pieces.len() as u64) as usize]).collect();
            let code = line.split(';').next().unwrap_or("");
            let reference = SINUMERIK_WORDS.iter().any(|w| code.to_ascii_uppercase().contains(std::str::from_utf8(w).unwrap()));
            assert_eq!(sinumerik_word(code.as_bytes()), reference, "{line:?}");
            found += usize::from(reference);
        }
        // Both answers drawn often enough to tell them apart.
        assert!((1_000..199_000).contains(&found), "{found} lines with a word");
    }

    /// The lines are those `str::lines` gives, with `\r\n`, a lone `\r`, empty lines and no final
    /// line end, over texts drawn from those pieces.
    #[test]
    fn lines_are_those_str_lines_gives() {
        let mut next = lex::xorshift(0x0BAD_5EED_1234_5678);
        let pieces = ["G1", "\n", "\r\n", "\r", " ", "Ä", "\n\n", "X1"];
        for _ in 0..20_000 {
            let len = (next() % 8) as usize;
            let text: String = (0..len).map(|_| pieces[(next() % pieces.len() as u64) as usize]).collect();
            assert_eq!(lines(&text).collect::<Vec<_>>(), text.lines().collect::<Vec<_>>(), "{text:?}");
        }
    }

    /// NX's listing header is refused once at its line, naming its lines, in any dialect; never in a
    /// comment, nor in a Fanuc tape's leader before its first `%` (skipped with the leader).
    #[test]
    fn an_nx_listing_header_is_refused_once() {
        let head = "==============================================================\nInformation listing created by : user\nDate                           : 12/6/2026\nCurrent work part              : C:\\part.prt\nNode name                      : pc1\n==============================================================\n";
        for (given, dialect, body) in [(false, Dialect::Fanuc, "N10 G0 X1.\n"), (true, Dialect::Klartext, "0 BEGIN PGM P MM\n"), (true, Dialect::Sinumerik, "G0 X1\n")] {
            let d = Dialect::unread(given, dialect, &format!("{head}{body}")).unwrap();
            assert_eq!((d.line, d.column, d.severity), (2, 1, Severity::Error));
            assert!(d.message.starts_with("lines 1-6: NX's \"Information listing\" header"), "{}", d.message);
        }
        for text in [format!("({})\nG0 X1\n", "Information listing created by : user"), format!("; Information listing created by : x\nG0 X1\n")] {
            assert_eq!(Dialect::listing_header(&text, Dialect::Fanuc), None, "{text:?}");
        }
        // In a Fanuc or Haas tape's leader, before its first %: skipped with it. Elsewhere, refused.
        let tape = format!("{head}%\nO1\nG0 X1.\n%\n");
        assert_eq!(Dialect::listing_header(&tape, Dialect::Haas), None);
        assert_eq!(Dialect::listing_header(&tape, Dialect::Rs274).map(|d| d.line), Some(2));
    }

    /// MillPlus is recognised by G7 with its angle words in code, at the G7; never in a comment,
    /// and never by G7 or an `A5` alone.
    #[test]
    fn millplus_is_recognised_by_its_tilted_plane() {
        let d = Dialect::unread_language("%\nN10 G17\nN20 G7 A5=15. B5=0.0 C5=210. B7=254 C7=255\n").unwrap();
        assert_eq!((d.line, d.column, d.severity), (3, 5, Severity::Error));
        assert!(d.message.contains("MillPlus"), "{}", d.message);
        // A byte-order mark before the G7 on line 1 is not a column of it.
        let d = Dialect::unread_language("\u{feff}G7 A5=15. B5=0.0 C5=210.\n").unwrap();
        assert_eq!((d.line, d.column), (1, 1));
        for text in ["N20 (G7 A5=15.) G1 X1\n", "N20 G1 X1 ; G7 A5=15.\n", "N20 G7 X1\n", "N20 G1 A5 X1\n", "G17 G7\nG1 A5.0\n"] {
            assert_eq!(Dialect::unread_language(text), None, "{text:?}");
        }
    }
}
