//! Heidenhain conversational programs (Klartext, `.H`), as a TNC runs them: `BEGIN PGM NAME MM` ...
//! `END PGM NAME MM`, numbered blocks, `;` comments and `*` structure lines; `L` lines (`R0`, `F`,
//! `FMAX` for its block only, `FAUTO` the `TOOL CALL`'s feed; also written `F MAX`, `F AUTO`), `LN`
//! lines with the surface normal `NX NY NZ` and the tool vector `TX TY TZ`; circles `CC` (pole), `C`
//! about it, `CR` by radius, `CT` tangent to the contour before it (`DR+` counter-clockwise); `M128`
//! and `FUNCTION TCPM` (`F TCP`, `AXIS POS`, `PATHCTRL AXIS`/`VECTOR`); `M91`/`M92` machine
//! coordinates, `M126`/`M127`; `CYCL DEF 7` datum shift; `CYCL DEF 9` dwell; `CYCL DEF 32` contour
//! tolerance; tilted working planes `PLANE SPATIAL`/`EULER`/`VECTOR`/`POINTS`/`RELATIV`/`AXIAL`/`RESET` with
//! `TURN`/`STAY`, `SEQ`, `COORD ROT`/`TABLE ROT`, and cycle 19 ([`crate::program::plane`]); the
//! drilling cycles 200, 201, 203, 207, 209, 240 and 241 ([`crate::program::tnc_cycles`]) called by `CYCL CALL`,
//! `M99`, `M89`; cycle 247 (a preset of the
//! machine's table); the machine maker's cycles its file names; polar contours `LP` and `CP` about the
//! pole `CC` (`PR`/`IPR`, `PA`/`IPA`; a helix by `CP IPA` with the tool axis' coordinate, several turns
//! beyond 360 deg; IPA's sign and DR's must agree); `M140 MB`; `LBL` with `CALL LBL ... REP`
//! (section repeats and subprograms); `Q` parameters with formulas, `FN 0`-`FN 8` and the jumps
//! `FN 9`-`FN 12` ([`formula`]).
//!
//! The program runs as it is read ([`Runner`], fed a line at a time): a first pass finds the labels,
//! then the reader reads on from wherever a call, a repeat or a jump goes, so memory holds the label
//! table and the call stack, never the program (an hours-long CAM program in flat memory).
//!
//! Written from the iTNC 530 User's Manual, Conversational Programming (Heidenhain 670388): "Path
//! contours - Cartesian coordinates" (CC, C, CR: R > 0 the arc under 180 deg, CT; "DR+" the
//! mathematically positive, counter-clockwise turn), "Subprograms and program section repeats" (a
//! section repeat runs REP more times; a subprogram ends at LBL 0 and is written after M2/M30), "Three-
//! dimensional tool compensation" (LN "must always indicate all of the coordinates and all of the
//! surface-normal vectors"; under M128 or FUNCTION TCPM a block without T keeps the tool
//! perpendicular to the contour, without them "the control ignores the direction vector T"),
//! "TCPM FUNCTION" and cycle 7 DATUM SHIFT (absolute from the workpiece datum, incremental from the
//! last shift).
//!
//! Tool radius compensation `RL`/`RR` until `R0` runs by the TNC's rules
//! ([`crate::program::cutter_comp::TncComp`]), in a tilted plane in the plane's coordinates, by the
//! called tool's radius in the tool table; refused under it: `R0` in a circle, TCPM (M128), a cycle
//! called among the held blocks (M89 in force, M99), a negative radius.
//!
//! Corners `RND R` and `CHF` between two contour elements ([`corners`]) are cut before compensation
//! offsets the contour.
//!
//! Refused at line:col, never guessed: `CTP` and free contours
//! (`FK`), approach/departure, `PLANE PROJECTED` and
//! `MOVE`, machining cycles other than those above and touch probes, tool deltas `DL`/`DR`, and
//! `FUNCTION TCPM` options that read the program differently (`F CONT`, `AXIS SPAT`, a reference
//! point other than the tool tip). The surface normal of an `LN` line moves the tool only by the
//! tool deltas, which are refused, so it is read only as the tool axis when `T` is missing.

mod blocks;
mod corners;
mod cycles;
mod formula;
mod held;
mod params;
mod plane_move;
mod exec;
mod run;
mod spline;
mod tilt;

use blocks::{call, centre, corner, function, joined_direction, misc, motion, text_from, tool_call, value_word};
use cycles::cycle;
use params::{assign, fn_statement, Cmp};
use tilt::{cycle19, plane, PlaneStmt};

pub(crate) use run::Runner;
pub use run::MAX_LABELS;

use std::borrow::Cow;

use super::lex::{excerpt, parse_number, upper, word_end, Columns, Diags};
use super::{Dialect, MCodeRule, Orientation, Program};

/// Subprogram nesting depth of the TNC (iTNC 530: "up to 19 levels").
const MAX_NESTING: usize = 19;

/// A number as written or a `Q` parameter (`X+Q1`, `FQ5`).
#[derive(Debug, Clone, PartialEq)]
enum Val<'a> {
    Num(f64),
    Q { name: &'a str, negative: bool },
}

/// One address word of a block: address (`X`, `IX`, `NX`, `M`), its value and where it stands,
/// borrowing the program's text.
#[derive(Debug, Clone)]
struct KWord<'a> {
    addr: &'static str,
    val: Val<'a>,
    raw: &'a str,
    col: usize,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    /// `L`
    Line,
    /// `LN`
    LineNormal,
    /// `C`
    Circle,
    /// `CR`
    CircleRadius,
    /// `CT`
    CircleTangent,
    /// `LP`: a line to a point in polar coordinates about the pole CC.
    LinePolar,
    /// `CP`: a circle about the pole CC to a polar angle (a helix with the tool axis' coordinate).
    CirclePolar,
}

#[derive(Debug, Clone)]
enum FeedWord<'a> {
    None,
    Value(KWord<'a>),
    Max,
    Auto(usize),
}

#[derive(Debug, Clone)]
enum Kind<'a> {
    Move {
        shape: Shape,
        /// Axis words, then `NX NY NZ` and `TX TY TZ` (an LN block), in one list.
        axes: Vec<KWord<'a>>,
        /// `DR+` (true) / `DR-`.
        ccw: Option<bool>,
        radius: Option<KWord<'a>>,
        feed: FeedWord<'a>,
        m: Vec<KWord<'a>>,
        /// `RL`/`RR` (the side, left true) or `R0`, and its column; `None`: as before.
        comp: Option<(Option<bool>, usize)>,
    },
    /// `CC`: the pole.
    Centre(Vec<KWord<'a>>),
    /// A block of `M` functions only.
    Misc(Vec<KWord<'a>>),
    /// `M140 MB n|MAX [F..|FMAX]`: back along the tool axis by n (program unit) or to the end of
    /// the travel (None), at the feed given (else at rapid traverse).
    Retract { distance: Option<KWord<'a>>, feed: FeedWord<'a>, col: usize },
    Tool { events: Vec<String>, feed: Option<KWord<'a>> },
    Tcp { on: bool, orientation: Option<Orientation> },
    /// `CYCL DEF 7.x X..`: axis, value, incremental.
    Datum(usize, KWord<'a>, bool),
    /// `CYCL DEF 9.1 DWELL 1.5`: the machine stands still, s.
    Dwell(KWord<'a>),
    /// `CYCL DEF 32.1 T0.05` (the contour tolerance, program unit; `32.1` alone resets both parts to
    /// the machine's) or `CYCL DEF 32.2 HSC-MODE:0 TA0.5` (the rotary axes', deg).
    Tolerance { linear: Option<KWord<'a>>, rotary: Option<KWord<'a>>, reset: bool },
    Label(&'a str),
    Call { label: &'a str, rep: Option<KWord<'a>> },
    /// `Q1 = formula`, `FN 0..8: Q1 = ...`: the parameter and the formula that sets it.
    Assign { name: String, formula: Cow<'a, str> },
    /// `Q208=MAX` in a cycle's parameters: a feed at rapid traverse (FMAX).
    AssignMax { name: String },
    /// `FN 9..12: IF a EQU|NE|GT|LT b GOTO LBL n`.
    Jump { a: String, cmp: Cmp, b: String, label: &'a str },
    /// `PLANE ...` and cycle 19: a tilted working plane.
    Plane(PlaneStmt<'a>),
    /// `CYCL DEF n NAME`: a cycle defined (its parameters are the Q assignments that follow).
    CycleDef(u32),
    /// `CYCL DEF 1.0 PECKING` (part 0, no value) and `1.1 SET UP 2` ... `1.5 F80`: the older cycle
    /// 1, one part per block.
    Pecking { part: u32, value: Option<KWord<'a>> },
    /// `CYCL CALL`: the cycle runs where the tool stands.
    /// `CYCL CALL`, with the M functions the block gives (those acting at its start, before the cycle).
    CycleCall(Vec<KWord<'a>>),
    /// `RND R5 [F100]` (`round`) or `CHF 12 [F250]`: the corner between the contour elements before
    /// and after it rounded by an arc of radius R or cut by a chamfer of that side length, at the
    /// feed F in this block only ([`super::corner`]).
    Corner { round: bool, size: KWord<'a>, feed: Option<KWord<'a>> },
    /// `SPL X.. Y.. Z.. K3X.. K2X.. K1X.. ...`: the TNC's spline, a cubic per axis from the tool's
    /// position to the end point ([`exec::Exec`]'s `spline`): the end points, then each axis'
    /// coefficients K3, K2, K1 (X Y Z A B C), and the feed.
    Spline { ends: Vec<KWord<'a>>, coefficients: [Option<[f64; 3]>; 6], feed: FeedWord<'a> },
    /// `STOP`: a programmed stop, as M0.
    Stop,
    /// `TRANS DATUM RESET` (TNC 640/TNC7, the NC function's datum shift reset), read where no datum
    /// shift is in effect; the other `TRANS` functions are refused (their rules are not at hand).
    TransReset,
    End,
}

#[derive(Debug, Clone)]
struct Stmt<'a> {
    line: usize,
    col: usize,
    number: Option<u64>,
    kind: Kind<'a>,
}

/// Read a Heidenhain conversational program on a control whose machine-specific M functions do what
/// `m_codes` says and whose orientation interpolation starts as `orientation`: run as a stream
/// over the text ([`super::stream`]), its blocks collected.
pub fn read_klartext_with(text: &str, m_codes: &[MCodeRule], orientation: Orientation) -> Program {
    super::stream::read_jumping(text, Dialect::Klartext, Box::new(Runner::new(&super::Setup::plain(Dialect::Klartext, m_codes, orientation))))
}

/// Whitespace-separated tokens of a line, borrowed, with their 1-based columns (characters).
fn tokens(line: &str) -> Vec<(&str, usize)> {
    let b = line.as_bytes();
    let cols = Columns::new(line);
    let mut out = Vec::with_capacity(12);
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_whitespace() {
            i += 1;
            continue;
        }
        if b[i] == b';' {
            break;
        }
        let start = i;
        if b[i] == b'"' {
            // A quoted name ("MILL_D10"), spaces and all.
            i += 1;
            while i < b.len() && b[i] != b'"' {
                i += 1;
            }
            i = (i + 1).min(b.len());
        } else {
            // A blank or `;` ends it.
            i = word_end(b, i);
        }
        // Ends fall on ASCII bytes (a blank, `;`, `"`) or the line's end, so on char boundaries.
        out.push((&line[start..i], cols.col(start)));
    }
    out
}

/// A value as written after an address: a number or a `Q` parameter with an optional sign.
fn parse_val(rest: &str) -> Option<Val<'_>> {
    let (negative, body) = match rest.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, rest.strip_prefix('+').unwrap_or(rest)),
    };
    if body.starts_with('Q') {
        for prefix in ["QL", "QR", "Q"] {
            if let Some(digits) = body.strip_prefix(prefix) {
                if !digits.is_empty() && digits.bytes().all(|c| c.is_ascii_digit()) {
                    return Some(Val::Q { name: body, negative });
                }
                return None;
            }
        }
    }
    parse_number(rest).map(Val::Num)
}

/// Split a word into its address (in capitals) and value text: `IX+5` -> (`IX`, `+5`), `FQ5` ->
/// (`F`, `Q5`), `X+Q1` -> (`X`, `+Q1`), `FMAX` -> (`FMAX`, ``).
fn split_word(tok: &str) -> (Cow<'_, str>, &str) {
    // (By bytes: the first that is not an ASCII letter starts a character.)
    let n = tok.bytes().position(|c| !c.is_ascii_alphabetic()).unwrap_or(tok.len());
    let (letters, rest) = tok.split_at(n);
    if n > 1 && letters.ends_with(['Q', 'q']) && rest.starts_with(|c: char| c.is_ascii_digit()) {
        return (upper(&letters[..n - 1]), &tok[n - 1..]);
    }
    (upper(letters), rest)
}

/// The address of a motion word as a static name and its bit in a block's set, if it is one.
fn motion_address(a: &str) -> Option<(&'static str, u32)> {
    Some(match a {
        "X" => ("X", 0),
        "Y" => ("Y", 1),
        "Z" => ("Z", 2),
        "A" => ("A", 3),
        "B" => ("B", 4),
        "C" => ("C", 5),
        "IX" => ("IX", 0),
        "IY" => ("IY", 1),
        "IZ" => ("IZ", 2),
        "IA" => ("IA", 3),
        "IB" => ("IB", 4),
        "IC" => ("IC", 5),
        "NX" => ("NX", 6),
        "NY" => ("NY", 7),
        "NZ" => ("NZ", 8),
        "TX" => ("TX", 9),
        "TY" => ("TY", 10),
        "TZ" => ("TZ", 11),
        _ => return None,
    })
}

/// X, Y or Z (0, 1, 2) from a linear address' last letter (`X`, `IY`, `NZ`, `TX`).
fn axis_index(addr: &str) -> usize {
    usize::from(addr.as_bytes()[addr.len() - 1] - b'X')
}

/// What reading has learnt so far, in the order the program runs.
#[derive(Debug, Clone, Default)]
struct ParseState {
    name: Option<String>,
    inch: bool,
    began: bool,
    ended: bool,
    datum_defined: bool,
    /// `DR+F2777` (a direction and the next word written together) has been said once.
    joined_said: bool,
    /// The line before was a comment ending in `~`: this line goes on with its text.
    comment_goes_on: bool,
    /// The line before was a `CYCL DEF` or one of its parameters ending in `~`: this line's Q
    /// assignment is one of the cycle's parameters.
    cycle_goes_on: bool,
}

/// Parse one line (1-based `line`) into its statement; defects go to `diags` and drop it. Lines are
/// parsed as they run, so a repeated section is parsed again rather than held: memory stays that of
/// the blocks.
fn parse_line<'a>(line: usize, raw: &'a str, st: &mut ParseState, diags: &mut Diags) -> Option<Stmt<'a>> {
    let ParseState { name, inch, began, ended, datum_defined, joined_said, comment_goes_on, cycle_goes_on } = st;
    let in_cycle = std::mem::take(cycle_goes_on);
    let (goes_on, open) = comment_line(*comment_goes_on, raw.as_bytes());
    if goes_on {
        *comment_goes_on = open;
        return None;
    }
    if std::mem::replace(comment_goes_on, open) {
        diags.warning(line, 1, "the comment before ends in '~' (it goes on in the next line), but this line does not begin with a blank as its continuation would: read as a block of its own");
    }
    let all = tokens(raw.trim_end_matches('\r'));
    let &(first, first_col) = all.first()?;
    // The block number, then the block.
    let (number, toks) = if first.bytes().all(|c| c.is_ascii_digit()) { (first.parse::<u64>().ok(), &all[1..]) } else { (None, &all[..]) };
    let &(head, head_col) = toks.first()?;
    if head.starts_with('*') {
        return None; // `* - SECTION`: a structure line
    }
    let owned: Vec<(&'a str, usize)>;
    let mut number = number;
    let toks: &[(&'a str, usize)] = match head.strip_prefix('/') {
        Some(rest) => {
            diags.warning(line, head_col, "block skip '/' is not modelled: the block is run");
            // `/290 M30`: the skip mark before the block number.
            let rest = if number.is_none() && !rest.is_empty() && rest.bytes().all(|c| c.is_ascii_digit()) {
                number = rest.parse::<u64>().ok();
                None
            } else {
                (!rest.is_empty()).then_some((rest, head_col + 1))
            };
            owned = rest.into_iter().chain(toks[1..].iter().copied()).collect();
            &owned
        }
        None => toks,
    };
    if toks.is_empty() {
        return None;
    }
    if *ended {
        diags.warning(line, first_col, "text after END PGM ignored");
        return None;
    }
    let col = toks[0].1;
    let before = diags.errors();
    let key = |k: usize| upper(toks.get(k).map_or("", |t| t.0));
    let k0 = key(0);
    let kind: Option<Kind<'a>> = match k0.as_ref() {
        "BEGIN" if key(1) == "PGM" => {
            if *began {
                diags.error(line, col, "a second BEGIN PGM: one program per file");
            } else if toks.len() != 4 || !matches!(key(3).as_ref(), "MM" | "INCH" | "IN") {
                diags.error(line, col, "expected BEGIN PGM NAME MM (or INCH)");
            } else {
                *name = Some(toks[2].0.to_string());
                *inch = key(3) != "MM";
                if key(3) == "IN" {
                    // NX's TNC posts write IN for INCH: the unit is not in doubt.
                    diags.warning(line, toks[3].1, "BEGIN PGM ... IN: the TNC writes INCH; read as inches");
                }
            }
            *began = true;
            None
        }
        "END" if key(1) == "PGM" => {
            match (toks.get(2), &*name) {
                (Some((n, c)), Some(start)) if n != start => {
                    diags.error(line, *c, format!("END PGM names '{n}' but the program began as '{start}'"))
                }
                _ => {}
            }
            *ended = true;
            Some(Kind::End)
        }
        _ if !*began => {
            diags.error(line, col, "expected BEGIN PGM NAME MM before the first block");
            *began = true; // said once
            None
        }
        "BLK" if key(1) == "FORM" => None, // the workpiece blank: drawing only
        "TOOL" if key(1) == "DEF" => None, // tool preselection: no motion
        "TOOL" if key(1) == "CALL" => tool_call(toks, line, diags),
        // `L M140 MB MAX`: the retract, written in an L block (hyperMILL's posts).
        "L" if toks.len() > 1 && split_word(toks[1].0) == (Cow::Borrowed("M"), "140") => misc(&toks[1..], line, diags),
        "L" | "LN" | "C" | "CR" | "CT" | "LP" | "CP" => match joined_direction(toks) {
            Some((split, col)) => {
                if !*joined_said {
                    *joined_said = true;
                    diags.warning(line, col, "DR+ or DR- written together with the word after it (as hyperMILL's TNC posts write `DR+F2777`): read as two words, the direction ending at its sign (said once)");
                }
                motion(&split, &k0, line, diags)
            }
            None => motion(toks, &k0, line, diags),
        },
        "CC" => centre(toks, line, diags),
        "SPL" => blocks::spline(toks, line, diags),
        "STOP" => Some(Kind::Stop),
        // TRANS DATUM RESET (as posts write it in their safe start, beside PLANE RESET and FUNCTION
        // RESET TCPM); TRANS DATUM AXIS|TABLE, MIRROR, ROTATION, SCALE not read.
        "TRANS" if toks.len() == 3 && key(1) == "DATUM" && key(2) == "RESET" => Some(Kind::TransReset),
        "TRANS" => {
            diags.error(line, col, format!("TRANS {}: the TNC's transformation functions are not read (their rules are not at hand): write cycle 7, 8, 10 or 11", excerpt(toks.get(1).map_or("", |t| t.0))));
            None
        }
        "LBL" => match toks.get(1) {
            Some((l, _)) if toks.len() == 2 => Some(Kind::Label(l.trim_matches('"'))),
            _ => {
                diags.error(line, col, "expected LBL n or LBL \"NAME\"");
                None
            }
        },
        "CALL" if key(1) == "LBL" => call(toks, line, diags),
        "CALL" | "SEL" => {
            diags.error(line, col, format!("{} {}: calling another program is not read", k0, key(1)));
            None
        }
        "FUNCTION" => function(toks, line, col, diags),
        "CYCL" if key(1) == "DEF" => {
            *cycle_goes_on = raw.trim_end().ends_with('~');
            cycle(toks, line, datum_defined, diags)
        }
        "CYCL" if key(1) == "CALL" && toks.len() == 2 => Some(Kind::CycleCall(Vec::new())),
        // `CYCL CALL M13` (TNC 640 User's Manual, "Calling cycles": CYCL CALL takes a miscellaneous
        // function): read where it acts at the block's start, before the cycle runs (spindle, coolant).
        "CYCL" if key(1) == "CALL" && toks[2..].iter().all(|(t, _)| split_word(t).0 == "M" && !split_word(t).1.is_empty()) => match misc(&toks[2..], line, diags) {
            Some(Kind::Misc(m)) => {
                if let Some(w) = m.iter().find(|w| !matches!(w.val, Val::Num(v) if [3.0, 4.0, 8.0, 13.0, 14.0].contains(&v))) {
                    diags.error(line, w.col, format!("CYCL CALL M{}: only M functions acting at the block's start (M3, M4, M8, M13, M14) are read with a cycle call (where another acts, before or after the cycle, is not read)", excerpt(w.raw)));
                    None
                } else {
                    Some(Kind::CycleCall(m))
                }
            }
            _ => None,
        },
        // `CYCL DEF9.0` (a shop's hand-made dwell): the TNC's editor writes every cycle block with a
        // blank before the number (`CYCL DEF 9.0 DWELL TIME`), and no manual read here says a block
        // without it is read: refused, naming the blank rather than "expected CYCL DEF".
        "CYCL" if key(1).strip_prefix("DEF").is_some_and(|n| n.starts_with(|c: char| c.is_ascii_digit())) => {
            diags.error(line, toks[1].1, format!("CYCL {}: expected a blank between CYCL DEF and the cycle's number (CYCL DEF {}), as the TNC writes it", excerpt(toks[1].0), excerpt(toks[1].0.get(3..).unwrap_or(""))));
            None
        }
        "CYCL" => {
            diags.error(line, col, format!("CYCL {}: expected CYCL DEF or CYCL CALL (CYCL CALL PAT and POS are not read)", excerpt(&key(1))));
            None
        }
        "PLANE" => plane(toks, line, col, diags),
        "FN" => fn_statement(raw, toks, line, col, diags),
        k if k.starts_with('Q') => {
            *cycle_goes_on = in_cycle && raw.trim_end().ends_with('~');
            assign(raw, toks, in_cycle, line, col, diags)
        }
        k if k.starts_with('M') && split_word(k).0 == "M" => misc(toks, line, diags),
        "RND" | "CHF" => corner(toks, &k0, line, diags),
        k @ ("APPR" | "DEP" | "CTP" | "FL" | "FLT" | "FC" | "FCT" | "FPOL" | "FSELECT" | "TCH") => {
            diags.error(line, col, format!("{}: {} is not read (it changes the motion)", toks[0].0, unsupported(k)));
            None
        }
        _ => {
            diags.error(line, col, format!("unknown block '{}': not read (it may change the motion)", excerpt(toks[0].0)));
            None
        }
    };
    if diags.errors() > before {
        diags.warning(line, col, format!("block {} not used", label(number, line)));
        return None;
    }
    kind.map(|kind| Stmt { line, col, number, kind })
}

/// The TNC writes a block longer than a line over several: a `~` ends each line but the last, and
/// the next begins with a blank (as its cycles' parameters stand, [`text_from`]). For a comment block
/// (`12 ;text ~`): whether line `b` goes on with the comment the line before left open (`open`), and
/// whether it leaves one open itself. A line that does not begin with a blank is a block of its own.
pub(super) fn comment_line(open: bool, b: &[u8]) -> (bool, bool) {
    let mut end = b.len();
    while end > 0 && b[end - 1].is_ascii_whitespace() {
        end -= 1;
    }
    let tilde = end > 0 && b[end - 1] == b'~';
    if open && b.first().is_some_and(|c| *c == b' ' || *c == b'\t') {
        return (true, tilde);
    }
    if !tilde {
        return (false, false);
    }
    // Its number, if any, then `;`.
    let mut i = b.iter().position(|c| !c.is_ascii_whitespace()).unwrap_or(end);
    while i < end && b[i].is_ascii_digit() {
        i += 1;
    }
    while i < end && b[i].is_ascii_whitespace() {
        i += 1;
    }
    (false, i < end && b[i] == b';')
}

fn unsupported(k: &str) -> &'static str {
    match k {
        "APPR" | "DEP" => "approach or departure on a contour",
        "LP" | "CP" | "CTP" => "a contour in polar coordinates",
        "TCH" => "a touch probe cycle",
        _ => "a free contour (FK)",
    }
}

fn label(number: Option<u64>, line: usize) -> String {
    match number {
        Some(n) => format!("{n} (line {line})"),
        None => format!("on line {line}"),
    }
}
