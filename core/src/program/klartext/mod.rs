//! Heidenhain conversational programs (Klartext, `.H`), as a TNC runs them: `BEGIN PGM NAME MM` ...
//! `END PGM NAME MM`, numbered blocks, `;` comments and `*` structure lines; `L` lines (`R0`, `F`,
//! `FMAX` for its block only, `FAUTO` the `TOOL CALL`'s feed; also written `F MAX`, `F AUTO`), `LN`
//! lines with the surface normal `NX NY NZ` and the tool vector `TX TY TZ`; circles `CC` (pole), `C`
//! about it, `CR` by radius, `CT` tangent to the contour before it (`DR+` counter-clockwise); `M128`
//! and `FUNCTION TCPM` (`F TCP`, `AXIS POS`, `PATHCTRL AXIS`/`VECTOR`); `M91`/`M92` machine
//! coordinates, `M126`/`M127`; `CYCL DEF 7` datum shift; `CYCL DEF 9` dwell; `CYCL DEF 32` contour
//! tolerance; tilted working planes `PLANE SPATIAL`/`EULER`/`VECTOR`/`POINTS`/`RELATIV`/`AXIAL`/`RESET` with
//! `TURN`/`STAY`, `SEQ`, `COORD ROT`/`TABLE ROT`, and cycle 19 ([`crate::program::plane`]); the
//! drilling cycles 200, 207, 240 called by `CYCL CALL`, `M99`, `M89`; cycle 247 (a preset of the
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
//! Refused at line:col, never guessed: radius compensation `RL`/`RR`, `CTP` and free contours
//! (`FK`), rounding and chamfers, approach/departure, `PLANE PROJECTED` and
//! `MOVE`, machining cycles other than those above and touch probes, tool deltas `DL`/`DR`, and
//! `FUNCTION TCPM` options that read the program differently (`F CONT`, `AXIS SPAT`, a reference
//! point other than the tool tip). The surface normal of an `LN` line moves the tool only by the
//! tool deltas, which are refused, so it is read only as the tool axis when `T` is missing.

mod formula;
mod run;

pub(crate) use run::Runner;
pub use run::MAX_LABELS;

use std::borrow::Cow;

use super::lex::{excerpt, parse_number, upper, Columns, Diags};
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
    /// `FN 9..12: IF a EQU|NE|GT|LT b GOTO LBL n`.
    Jump { a: String, cmp: Cmp, b: String, label: &'a str },
    /// `PLANE ...` and cycle 19: a tilted working plane.
    Plane(PlaneStmt<'a>),
    /// `CYCL DEF n NAME`: a cycle defined (its parameters are the Q assignments that follow).
    CycleDef(u32),
    /// `CYCL CALL`: the cycle runs where the tool stands.
    CycleCall,
    /// `STOP`: a programmed stop, as M0.
    Stop,
    End,
}

/// How a `PLANE` states the working plane.
#[derive(Debug, Clone)]
enum PlaneForm<'a> {
    /// `SPATIAL SPA SPB SPC`, deg (and cycle 19 with spatial angles).
    Spatial([KWord<'a>; 3]),
    /// `EULER EULPR EULNU EULROT`, deg.
    Euler([KWord<'a>; 3]),
    /// `VECTOR BX BY BZ NX NY NZ`.
    Vector([KWord<'a>; 6]),
    /// `POINTS P1X P1Y P1Z P2X P2Y P2Z P3X P3Y P3Z`: three points of the plane.
    Points([KWord<'a>; 9]),
    /// `RELATIV SPA|SPB|SPC`: one turn about the tilted plane's own axis (0 X, 1 Y, 2 Z).
    Relativ(usize, KWord<'a>),
    /// `AXIAL A B C` (and cycle 19 with axis angles): the rotary axes' positions, deg.
    Axial(Vec<KWord<'a>>),
    /// `RESET`, or cycle 19 with nothing.
    Reset,
}

/// How a `PLANE` positions the rotary axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PlaneMode {
    /// `TURN`: the rotary axes move, the linear ones stay.
    Turn,
    /// `STAY`: nothing moves; the angles go to Q120 (A), Q121 (B), Q122 (C).
    Stay,
    /// Cycle 19: nothing moves (the program positions the axes itself), no Q parameters.
    Cycle,
}

/// A `PLANE` statement.
#[derive(Debug, Clone)]
struct PlaneStmt<'a> {
    form: PlaneForm<'a>,
    mode: PlaneMode,
    feed: FeedWord<'a>,
    choice: super::plane::Choice,
    /// Cycle 19's spatial angles (a machine setting decides between them and axis angles).
    cycle: bool,
}

/// The comparison of a conditional jump (FN 9 EQU, FN 10 NE, FN 11 GT, FN 12 LT).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Cmp {
    Eq,
    Ne,
    Gt,
    Lt,
}

impl Cmp {
    fn holds(self, a: f64, b: f64) -> bool {
        match self {
            Cmp::Eq => a == b,
            Cmp::Ne => a != b,
            Cmp::Gt => a > b,
            Cmp::Lt => a < b,
        }
    }
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
            while i < b.len() && !b[i].is_ascii_whitespace() && b[i] != b';' {
                i += 1;
            }
        }
        while i < b.len() && !line.is_char_boundary(i) {
            i += 1;
        }
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
    let n = tok.find(|c: char| !c.is_ascii_alphabetic()).unwrap_or(tok.len());
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
}

/// Parse one line (1-based `line`) into its statement; defects go to `diags` and drop it. Lines are
/// parsed as they run, so a repeated section is parsed again rather than held: memory stays that of
/// the blocks.
fn parse_line<'a>(line: usize, raw: &'a str, st: &mut ParseState, diags: &mut Diags) -> Option<Stmt<'a>> {
    let ParseState { name, inch, began, ended, datum_defined } = st;
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
        "L" | "LN" | "C" | "CR" | "CT" | "LP" | "CP" => motion(toks, &k0, line, diags),
        "CC" => centre(toks, line, diags),
        "STOP" => Some(Kind::Stop),
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
        "CYCL" if key(1) == "DEF" => cycle(toks, line, datum_defined, diags),
        "CYCL" if key(1) == "CALL" && toks.len() == 2 => Some(Kind::CycleCall),
        "CYCL" => {
            diags.error(line, col, format!("CYCL {}: expected CYCL DEF or CYCL CALL (CYCL CALL PAT and POS are not read)", excerpt(&key(1))));
            None
        }
        "PLANE" => plane(toks, line, col, diags),
        "FN" => fn_statement(raw, toks, line, col, diags),
        k if k.starts_with('Q') => assign(raw, toks, line, col, diags),
        k if k.starts_with('M') && split_word(k).0 == "M" => misc(toks, line, diags),
        k @ ("APPR" | "DEP" | "RND" | "CHF" | "CTP" | "FL" | "FLT" | "FC" | "FCT" | "FPOL" | "FSELECT" | "TCH") => {
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

fn unsupported(k: &str) -> &'static str {
    match k {
        "APPR" | "DEP" => "approach or departure on a contour",
        "RND" | "CHF" => "rounding or chamfer between contour elements",
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

/// One value word; defects go to `diags`.
fn value_word<'a>(addr: &'static str, rest: &'a str, tok: &str, col: usize, line: usize, diags: &mut Diags) -> Option<KWord<'a>> {
    match parse_val(rest) {
        Some(val) => Some(KWord { addr, val, raw: rest, col }),
        None => {
            let why = if rest.contains(['(', '*', '/']) || rest.chars().skip(1).any(|c| c == '+' || c == '-') {
                " (an expression, which is not read)"
            } else {
                ""
            };
            diags.error(line, col, format!("{addr}: expected a number or a Q parameter, found '{}'{why}", excerpt(tok)));
            None
        }
    }
}

/// `L`, `LN`, `C`, `CR`, `CT` blocks.
fn motion<'a>(toks: &[(&'a str, usize)], key: &str, line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let shape = match key {
        "L" => Shape::Line,
        "LN" => Shape::LineNormal,
        "C" => Shape::Circle,
        "CR" => Shape::CircleRadius,
        "LP" => Shape::LinePolar,
        "CP" => Shape::CirclePolar,
        _ => Shape::CircleTangent,
    };
    let arc = matches!(shape, Shape::Circle | Shape::CircleRadius | Shape::CircleTangent | Shape::CirclePolar);
    let polar = matches!(shape, Shape::LinePolar | Shape::CirclePolar);
    let mut axes: Vec<KWord<'a>> = Vec::with_capacity(if shape == Shape::LineNormal { 9 } else { 5 });
    let (mut ccw, mut radius, mut feed, mut m) = (None, None, FeedWord::None, Vec::new());
    let mut seen = 0u32;
    let mut words = toks[1..].iter().copied().peekable();
    while let Some((tok, col)) = words.next() {
        let (addr, rest) = split_word(tok);
        // `F MAX` and `F AUTO`, as many posts (hyperMILL among them) write FMAX and FAUTO.
        let spaced = (addr == "F" && rest.is_empty())
            .then(|| words.peek().map(|&(next, _)| upper(next)).filter(|n| n == "MAX" || n == "AUTO"))
            .flatten();
        let addr: Cow<'_, str> = match spaced {
            Some(n) => {
                words.next();
                Cow::Owned(format!("F{n}"))
            }
            None => addr,
        };
        let addr = addr.as_ref();
        match (motion_address(addr), addr) {
            (Some((_, bit)), _) if bit >= 6 && shape != Shape::LineNormal => {
                diags.error(line, col, format!("unexpected word '{}' in an {key} block (NX NY NZ, TX TY TZ belong to LN)", excerpt(tok)))
            }
            (Some((a, bit)), _) => {
                if seen & (1 << bit) != 0 {
                    diags.error(line, col, format!("{a} written twice in one block"));
                }
                seen |= 1 << bit;
                if let Some(w) = value_word(a, rest, tok, col, line, diags) {
                    axes.push(w);
                }
            }
            // Polar coordinates about the pole: radius PR (not on CP: its radius is the start's) and angle PA.
            (None, a @ ("PR" | "IPR" | "PA" | "IPA")) if polar && !(shape == Shape::CirclePolar && a.ends_with("PR")) => {
                let (name, bit) = match a {
                    "PR" => ("PR", 12),
                    "IPR" => ("IPR", 12),
                    "PA" => ("PA", 13),
                    _ => ("IPA", 13),
                };
                if seen & (1 << bit) != 0 {
                    diags.error(line, col, format!("{name} written twice in one block"));
                }
                seen |= 1 << bit;
                if let Some(w) = value_word(name, rest, tok, col, line, diags) {
                    axes.push(w);
                }
            }
            (None, "F") => feed = value_word("F", rest, tok, col, line, diags).map_or(FeedWord::None, FeedWord::Value),
            (None, "FMAX") if rest.is_empty() && !arc => feed = FeedWord::Max,
            (None, "FMAX") if rest.is_empty() => diags.error(line, col, "FMAX on a circle: expected a feed F"),
            (None, "FAUTO") if rest.is_empty() => feed = FeedWord::Auto(col),
            (None, "FU" | "FZ") => diags.error(line, col, format!("{tok}: feed per revolution or per tooth is not supported")),
            (None, "M") => {
                if let Some(w) = value_word("M", rest, tok, col, line, diags) {
                    m.push(w);
                }
            }
            (None, "R") if rest == "0" => {} // radius compensation off
            (None, "R") if shape == Shape::CircleRadius && rest.starts_with(['+', '-']) => radius = value_word("R", rest, tok, col, line, diags),
            (None, "RL" | "RR") if rest.is_empty() => diags.error(line, col, format!("{tok}: tool radius compensation is not read: the radius is the tool table's, which the program does not give (expected R0)")),
            (None, "DR") if arc && (rest == "+" || rest == "-") && shape != Shape::CircleTangent => ccw = Some(rest == "+"),
            _ => diags.error(line, col, format!("unexpected word '{}' in an {key} block", excerpt(tok))),
        }
    }
    let at = toks[0].1;
    match shape {
        Shape::Circle | Shape::CircleRadius | Shape::CirclePolar if ccw.is_none() => diags.error(line, at, format!("{key}: expected the direction DR+ or DR-")),
        Shape::LinePolar if seen & (3 << 12) != 3 << 12 => diags.error(line, at, "LP: expected the polar radius PR (or IPR) and angle PA (or IPA)"),
        Shape::CirclePolar if seen & (1 << 13) == 0 => diags.error(line, at, "CP: expected the polar angle PA (or IPA) of the arc's end"),
        Shape::CircleRadius if radius.is_none() => diags.error(line, at, "CR: expected the radius R+.. (R- for an arc over 180 deg)"),
        Shape::LineNormal => {
            // Bits: X Y Z 0-2, A B C 3-5, NX NY NZ 6-8, TX TY TZ 9-11.
            if seen & 0o707 != 0o707 {
                diags.error(line, at, "LN: expected X Y Z and NX NY NZ, all of them (as the TNC writes LN blocks)");
            }
            if seen & 0o7000 != 0 && seen & 0o7000 != 0o7000 {
                diags.error(line, at, "LN: expected TX TY TZ together");
            }
            if seen & 0o70 != 0 {
                diags.error(line, at, "LN with rotary-axis words: the tool axis is the vector TX TY TZ");
            }
        }
        _ => {}
    }
    Some(Kind::Move { shape, axes, ccw, radius, feed, m })
}

/// `CC X.. Y..`: the pole (circle centre) in the working plane.
fn centre<'a>(toks: &[(&'a str, usize)], line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let mut axes = Vec::new();
    for &(tok, col) in &toks[1..] {
        let (addr, rest) = split_word(tok);
        match motion_address(&addr) {
            Some((a, 0..=2)) => {
                if let Some(w) = value_word(a, rest, tok, col, line, diags) {
                    axes.push(w);
                }
            }
            _ => diags.error(line, col, format!("unexpected word '{}' in a CC block: expected the pole's coordinates", excerpt(tok))),
        }
    }
    Some(Kind::Centre(axes))
}

/// A block of M functions only (`M128`, `M3 M8`), or `M140 MB MAX F..` (iTNC 530 user's manual,
/// "Miscellaneous functions for contouring behavior", "Retraction from the contour in the tool-axis
/// direction: M140": MB the distance, MAX to the end of the traverse range, F its feed, rapid
/// without one; along the tool axis also when tilted or under M128).
fn misc<'a>(toks: &[(&'a str, usize)], line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    if let Some(&(first, col)) = toks.first() {
        if split_word(first) == (Cow::Borrowed("M"), "140") {
            let (mut distance, mut feed, mut mb) = (None, FeedWord::None, false);
            let mut k = 1;
            while let Some(&(tok, c)) = toks.get(k) {
                let (addr, rest) = split_word(tok);
                match (addr.as_ref(), rest) {
                    ("MB", "") if !mb => {
                        mb = true;
                        match toks.get(k + 1) {
                            Some(&(v, _)) if v.eq_ignore_ascii_case("MAX") => k += 1,
                            Some(&(v, vc)) if v.starts_with(|ch: char| ch.is_ascii_digit() || "+-.Q".contains(ch)) => {
                                distance = value_word("MB", v, v, vc, line, diags);
                                k += 1;
                            }
                            _ => diags.error(line, c, "M140 MB: expected a distance or MAX"),
                        }
                    }
                    ("MB", v) if !mb => {
                        mb = true;
                        distance = value_word("MB", v, tok, c, line, diags);
                    }
                    ("F", v) if !v.is_empty() => feed = value_word("F", v, tok, c, line, diags).map_or(FeedWord::None, FeedWord::Value),
                    ("FMAX", "") => feed = FeedWord::Max,
                    _ => diags.error(line, c, format!("unexpected word '{}' in M140: expected MB and a distance or MAX, and F", excerpt(tok))),
                }
                k += 1;
            }
            if !mb {
                diags.error(line, col, "M140 without MB: expected MB and a distance or MAX");
            }
            return Some(Kind::Retract { distance, feed, col });
        }
    }
    let mut m = Vec::new();
    for &(tok, col) in toks {
        let (addr, rest) = split_word(tok);
        if addr == "M" {
            if let Some(w) = value_word("M", rest, tok, col, line, diags) {
                m.push(w);
            }
        } else {
            diags.error(line, col, format!("unexpected word '{}' after an M function", excerpt(tok)));
        }
    }
    Some(Kind::Misc(m))
}

/// `TOOL CALL 5 Z S12000 F500`: events, and the feed FAUTO takes.
fn tool_call<'a>(toks: &[(&'a str, usize)], line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let mut events = Vec::new();
    let mut feed = None;
    let mut rest_from = 2;
    if let Some(&(t, _)) = toks.get(2) {
        let u = upper(t);
        let is_axis = matches!(u.as_ref(), "X" | "Y" | "Z");
        if !is_axis && !u.starts_with(['S', 'F', 'D']) || t.starts_with('"') {
            events.push(format!("T{t}"));
            rest_from = 3;
        }
    }
    for (k, &(tok, col)) in toks.iter().enumerate().skip(rest_from) {
        let (addr, rest) = split_word(tok);
        match addr.as_ref() {
            "Z" if rest.is_empty() => {}
            a @ ("X" | "Y") if rest.is_empty() => {
                diags.error(line, col, format!("TOOL CALL with tool axis {a}: only tool axis Z is modelled (the machine file's)"))
            }
            "S" => match parse_val(rest) {
                Some(_) => events.push(format!("S{rest}")),
                None => diags.error(line, col, format!("S: expected a spindle speed, found '{}'", excerpt(tok))),
            },
            "F" => feed = value_word("F", rest, tok, col, line, diags),
            "DL" | "DR" => match parse_val(rest) {
                Some(Val::Num(0.0)) => {}
                _ => diags.error(
                    line,
                    col,
                    format!("{tok}: a tool length or radius delta is not modelled (it moves the tool tip; the tool is the machine file's)"),
                ),
            },
            _ => diags.error(line, col, format!("unexpected word '{}' in TOOL CALL (word {})", excerpt(tok), k + 1)),
        }
    }
    Some(Kind::Tool { events, feed })
}

/// `CALL LBL n [REP m]`.
fn call<'a>(toks: &[(&'a str, usize)], line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let Some(&(label, _)) = toks.get(2) else {
        diags.error(line, toks[0].1, "CALL LBL: expected the label");
        return None;
    };
    let mut rep = None;
    let mut k = 3;
    while k < toks.len() {
        let (tok, col) = toks[k];
        let after = tok.get(3..).filter(|_| tok.get(..3).is_some_and(|p| p.eq_ignore_ascii_case("REP")));
        if let Some(r) = after {
            // `REP 3`, `REP3`, `REPQ9`, and the `REP3/3` the TNC displays (count left / count).
            let r = if r.is_empty() && k + 1 < toks.len() {
                k += 1;
                toks[k].0
            } else {
                r
            };
            let count = r.split('/').next().unwrap_or("");
            rep = value_word("REP", count, tok, col, line, diags);
        } else {
            diags.error(line, col, format!("unexpected '{}' in CALL LBL: expected REP n", excerpt(tok)));
        }
        k += 1;
    }
    Some(Kind::Call { label: label.trim_matches('"'), rep })
}

/// `FUNCTION TCPM ...` and `FUNCTION RESET TCPM`.
fn function<'a>(toks: &[(&'a str, usize)], line: usize, col: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let words: Vec<Cow<'_, str>> = toks.iter().map(|t| upper(t.0)).collect();
    let words: Vec<&str> = words.iter().map(|w| w.as_ref()).collect();
    match words.get(1..) {
        Some(["RESET", "TCPM"]) => return Some(Kind::Tcp { on: false, orientation: None }),
        Some(["TCPM", ..]) => {}
        _ => {
            diags.error(line, col, format!("FUNCTION {}: not read (it may change the motion)", words.get(1).unwrap_or(&"")));
            return None;
        }
    }
    let mut orientation = None;
    let mut k = 2;
    while k < words.len() {
        let pair = (words[k], words.get(k + 1).copied().unwrap_or(""));
        match pair {
            ("F", "TCP") | ("AXIS", "POS") | ("REFPNT", "TIP-TIP") => k += 2,
            ("PATHCTRL", "AXIS") => {
                orientation = Some(Orientation::AxisLinear);
                k += 2
            }
            ("PATHCTRL", "VECTOR") => {
                orientation = Some(Orientation::GreatCircle);
                k += 2
            }
            ("F", "CONT") => {
                diags.error(line, col, "FUNCTION TCPM F CONT: the feed as a contouring feed over all axes is not modelled (expected F TCP)");
                k += 2
            }
            ("AXIS", "SPAT") => {
                diags.error(line, col, "FUNCTION TCPM AXIS SPAT: rotary words as spatial angles are not modelled (expected AXIS POS)");
                k += 2
            }
            ("REFPNT", other) => {
                diags.error(line, col, format!("FUNCTION TCPM REFPNT {other}: a reference point other than the tool tip is not modelled"));
                k += 2
            }
            // The feed limit of the compensating moves: the axes' limits are the machine file's.
            (f, _) if f.starts_with('F') && parse_number(&f[1..]).is_some() => k += 1,
            (other, _) => {
                diags.error(line, col, format!("FUNCTION TCPM: unexpected '{}'", excerpt(other)));
                k += 1
            }
        }
    }
    Some(Kind::Tcp { on: true, orientation })
}

/// `CYCL DEF 32.0 TOLERANCE` / `32.1 T0.05` / `32.2 HSC-MODE:0 TA0.5` (TNC 620 Cycle Programming, 340
/// 56x-03, §12.5): the contour tolerance on the path (program unit) and, under M128/TCPM, on the rotary
/// axes (deg), for the blocks after it. `32.1` without `T` resets both to the machine's (its file's
/// `contour_tolerance_mm`/`_deg`). `HSC-MODE:0` and `:1` (finishing, roughing) choose the maker's
/// filter within the same tolerance.
fn tolerance_cycle<'a>(toks: &[(&'a str, usize)], part: &str, line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let col = toks[0].1;
    let rest = &toks[3.min(toks.len())..];
    match part {
        // The cycle's name, in the control's language.
        "0" if rest.len() <= 1 => None,
        "1" if rest.is_empty() => Some(Kind::Tolerance { linear: None, rotary: None, reset: true }),
        "1" if rest.len() == 1 && upper(rest[0].0).starts_with('T') => {
            let (tok, c) = rest[0];
            value_word("T", &tok[1..], tok, c, line, diags).map(|w| Kind::Tolerance { linear: Some(w), rotary: None, reset: false })
        }
        "2" if !rest.is_empty() => {
            let mut rotary = None;
            for &(tok, c) in rest {
                let u = upper(tok);
                if let Some(mode) = u.strip_prefix("HSC-MODE:") {
                    match mode {
                        // HSC-MODE:1 (roughing) picks the maker's other filter: "Even if the control
                        // does not move the axes with reduced speed, it will always comply with the
                        // tolerance that you have defined" (TNC7 basic User's Manual 81762x-19, cycle
                        // 32), so T stays the bound the planner keeps either way.
                        "0" | "1" => {}
                        _ => {
                            diags.error(line, c, format!("CYCL DEF 32.2: expected HSC-MODE:0 or HSC-MODE:1, found '{}'", excerpt(tok)));
                            return None;
                        }
                    }
                } else if u.starts_with("TA") {
                    rotary = Some(value_word("TA", &tok[2..], tok, c, line, diags)?);
                } else {
                    diags.error(line, c, format!("CYCL DEF 32.2: expected HSC-MODE:0 and TA (the rotary axes' tolerance, deg), found '{}'", excerpt(tok)));
                    return None;
                }
            }
            rotary.map(|w| Kind::Tolerance { linear: None, rotary: Some(w), reset: false })
        }
        _ => {
            diags.error(line, col, "CYCL DEF 32: expected CYCL DEF 32.0 TOLERANCE, CYCL DEF 32.1 T followed by the tolerance, or CYCL DEF 32.2 HSC-MODE:0 TA followed by the rotary axes' tolerance, deg");
            None
        }
    }
}

/// `CYCL DEF 7.0 DATUM SHIFT` / `7.1 X+..` / `7.2 Y+..` / `7.3 Z+..`, `CYCL DEF 9.0 DWELL TIME` /
/// `9.1 DWELL 1.5` (German `V.ZEIT`: the dwell, s, active where it is defined); every other cycle is refused.
fn cycle<'a>(toks: &[(&'a str, usize)], line: usize, defined: &mut bool, diags: &mut Diags) -> Option<Kind<'a>> {
    let col = toks[0].1;
    let number = toks.get(2).map_or("", |t| t.0);
    let (cycle, part) = number.split_once('.').unwrap_or((number, ""));
    if cycle == "9" {
        return match (part, toks.len()) {
            ("0", _) => None,
            // 9.1, its label (in the control's language), the time.
            ("1", 5) => value_word("DWELL", toks[4].0, toks[4].0, toks[4].1, line, diags).map(Kind::Dwell),
            _ => {
                diags.error(line, col, format!("CYCL DEF {number}: expected CYCL DEF 9.0 DWELL TIME or CYCL DEF 9.1 DWELL followed by the time, s"));
                None
            }
        };
    }
    if cycle == "32" {
        return tolerance_cycle(toks, part, line, diags);
    }
    if cycle == "19" {
        return cycle19(toks, part, line, diags);
    }
    if cycle != "7" {
        return match (cycle, part.is_empty(), cycle.parse::<u32>()) {
            ("8" | "10" | "11" | "26", _, _) => {
                diags.error(line, col, format!("CYCL DEF {number}: mirroring, rotation or scaling is not modelled"));
                None
            }
            // A cycle and its name; its Q parameters follow on the lines after it. Whether it is read
            // is the runner's (the machine's own cycles are in its file).
            (_, true, Ok(n)) => Some(Kind::CycleDef(n)),
            _ => {
                diags.error(line, col, format!("CYCL DEF {number}: expected a cycle number"));
                None
            }
        };
    }
    if part == "0" {
        *defined = true;
        return None;
    }
    if !*defined {
        diags.error(line, col, format!("CYCL DEF {number} without CYCL DEF 7.0 before it"));
        return None;
    }
    let Some(&(tok, wcol)) = toks.get(3) else {
        diags.error(line, col, format!("CYCL DEF {number}: expected an axis value such as X+10"));
        return None;
    };
    if tok.starts_with('#') {
        diags.error(line, wcol, "CYCL DEF 7 with a datum table (#): not modelled");
        return None;
    }
    let (addr, rest) = split_word(tok);
    let (a, incremental) = match motion_address(&addr) {
        Some((a, 0..=2)) => (a, a.starts_with('I')),
        _ => {
            diags.error(line, wcol, format!("CYCL DEF {number}: expected X, Y or Z, found '{}' (a rotary datum shift is not modelled)", excerpt(tok)));
            return None;
        }
    };
    if toks.len() > 4 {
        diags.error(line, toks[4].1, format!("CYCL DEF {number}: one axis per block"));
    }
    let k = axis_index(a);
    value_word(a, rest, tok, wcol, line, diags).map(|w| Kind::Datum(k, w, incremental))
}

/// The text of a line from token `k` on, to its comment (`;`), as written.
fn text_from<'a>(raw: &'a str, toks: &[(&'a str, usize)], k: usize) -> &'a str {
    let Some(&(t, _)) = toks.get(k) else { return "" };
    // Tokens borrow from `raw`: the offset of the token in it.
    let start = t.as_ptr() as usize - raw.as_ptr() as usize;
    let rest = &raw[start..];
    rest.split(';').next().unwrap_or(rest).trim_end_matches('\r').trim_end()
}

/// A Q parameter's name in capitals (`Q1`, `QL3`, `QR20`), if `s` is one.
fn q_name(s: &str) -> Option<String> {
    let u = s.trim().to_ascii_uppercase();
    ["QL", "QR", "Q"].iter().any(|p| u.strip_prefix(p).is_some_and(|d| !d.is_empty() && d.bytes().all(|c| c.is_ascii_digit()))).then_some(u)
}

/// `Q1 = formula` (TNC 320 DIN/ISO 3/2014 §9.9, "Entering formulas directly").
fn assign<'a>(raw: &'a str, toks: &[(&'a str, usize)], line: usize, col: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let text = text_from(raw, toks, 0);
    let Some((lhs, rhs)) = text.split_once('=') else {
        diags.error(line, col, format!("'{}': expected Qn = a value or formula", excerpt(text)));
        return None;
    };
    let Some(name) = q_name(lhs) else {
        diags.error(line, col, format!("'{}': expected a Q parameter name such as Q1", excerpt(lhs.trim())));
        return None;
    };
    formula_kind(name, Cow::Borrowed(rhs.trim()), line, col + text.find('=').map_or(0, |k| k + 1), diags)
}

fn formula_kind<'a>(name: String, formula: Cow<'a, str>, line: usize, col: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    match formula::check(&formula) {
        Ok(()) => Some(Kind::Assign { name, formula }),
        Err(e) => {
            diags.error(line, col + e.at, format!("{name} = {}: {}", excerpt(&formula), e.message));
            None
        }
    }
}

/// `FN n: ...`: the arithmetic functions FN 0 to FN 8 (a formula), the jumps FN 9 to FN 12.
fn fn_statement<'a>(raw: &'a str, toks: &[(&'a str, usize)], line: usize, col: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let text = text_from(raw, toks, 1);
    let Some((number, body)) = text.split_once(':') else {
        diags.error(line, col, format!("FN {}: expected FN n: followed by its operands", excerpt(text)));
        return None;
    };
    let Ok(n) = number.trim().parse::<u32>() else {
        diags.error(line, col, format!("FN {}: expected a function number", excerpt(number)));
        return None;
    };
    match n {
        0..=8 => {
            let Some((lhs, rhs)) = body.split_once('=') else {
                diags.error(line, col, format!("FN {n}: expected Qn = its operands"));
                return None;
            };
            let Some(name) = q_name(lhs) else {
                diags.error(line, col, format!("FN {n}: '{}' is not a Q parameter", excerpt(lhs.trim())));
                return None;
            };
            match formula::fn_formula(n, rhs) {
                Ok(f) => formula_kind(name, Cow::Owned(f), line, col, diags),
                Err(why) => {
                    diags.error(line, col, why);
                    None
                }
            }
        }
        9..=12 => {
            // IF a OP b GOTO LBL label
            let u = body.to_ascii_uppercase();
            let (op, cmp) = [("EQU", Cmp::Eq), ("NE", Cmp::Ne), ("GT", Cmp::Gt), ("LT", Cmp::Lt)][(n - 9) as usize];
            let (Some(if_at), Some(op_at), Some(goto_at)) = (u.find("IF"), u.find(op), u.find("GOTO")) else {
                diags.error(line, col, format!("FN {n}: expected IF a {op} b GOTO LBL label"));
                return None;
            };
            if !(if_at < op_at && op_at < goto_at) {
                diags.error(line, col, format!("FN {n}: expected IF a {op} b GOTO LBL label"));
                return None;
            }
            let a = body[if_at + 2..op_at].trim().to_string();
            let b = body[op_at + op.len()..goto_at].trim().to_string();
            let after = body[goto_at + 4..].trim_start();
            let Some(label) = after.get(..3).filter(|l| l.eq_ignore_ascii_case("LBL")).map(|_| after[3..].trim().trim_matches('"')) else {
                diags.error(line, col, format!("FN {n}: expected GOTO LBL and the label"));
                return None;
            };
            for v in [&a, &b] {
                if let Err(e) = formula::check(v) {
                    diags.error(line, col, format!("FN {n}: '{}': {}", excerpt(v), e.message));
                    return None;
                }
            }
            if label.is_empty() {
                diags.error(line, col, format!("FN {n}: GOTO LBL without a label"));
                return None;
            }
            // The label borrows from the line's text.
            let start = label.as_ptr() as usize - raw.as_ptr() as usize;
            Some(Kind::Jump { a, cmp, b, label: &raw[start..start + label.len()] })
        }
        _ => {
            diags.error(line, col, format!("FN {n}: not read (only the arithmetic FN 0 to FN 8 and the jumps FN 9 to FN 12)"));
            None
        }
    }
}

/// `PLANE SPATIAL SPA.. SPB.. SPC.. | EULER EULPR.. EULNU.. EULROT.. | VECTOR BX.. BY.. BZ.. NX.. NY..
/// NZ.. | RELATIV SPA..|SPB..|SPC.. | AXIAL A.. B.. C.. | RESET`, then `TURN` or `STAY` (`MOVE`, the
/// compensating move about DIST, is refused), `F`/`FMAX`/`F MAX`, `SEQ+`/`SEQ-`, `COORD ROT`/`TABLE
/// ROT`, in any order (iTNC 530 User's Manual 340 422 §9.2-9.8; PLANE RESET without positioning is
/// hyperMILL's `PLANE RESET STAY`).
fn plane<'a>(toks: &[(&'a str, usize)], line: usize, col: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let form_name = upper(toks.get(1).map_or("", |t| t.0));
    let mut rest = toks[2.min(toks.len())..].iter().copied().peekable();
    let mut values: Vec<(String, KWord<'a>)> = Vec::new();
    let (mut mode, mut feed, mut choice) = (None, FeedWord::None, super::plane::Choice::default());
    let addresses: &[&str] = match form_name.as_ref() {
        "SPATIAL" => &["SPA", "SPB", "SPC"],
        "EULER" => &["EULPR", "EULNU", "EULROT"],
        "VECTOR" => &["BX", "BY", "BZ", "NX", "NY", "NZ"],
        "POINTS" => &["P1X", "P1Y", "P1Z", "P2X", "P2Y", "P2Z", "P3X", "P3Y", "P3Z"],
        "RELATIV" => &["SPA", "SPB", "SPC"],
        "AXIAL" => &["A", "B", "C"],
        "RESET" => &[],
        "PROJECTED" => {
            diags.error(line, col, "PLANE PROJECTED: this form of the working plane is not modelled yet (the sign of its projection angles is the manual's figure, not at hand; SPATIAL, EULER, VECTOR, POINTS, RELATIV, AXIAL and RESET are)");
            return None;
        }
        other => {
            diags.error(line, col, format!("PLANE {}: expected SPATIAL, PROJECTED, EULER, VECTOR, POINTS, RELATIV, AXIAL or RESET", excerpt(other)));
            return None;
        }
    };
    while let Some((tok, c)) = rest.next() {
        let u = upper(tok);
        let next_is = |rest: &mut std::iter::Peekable<std::iter::Copied<std::slice::Iter<'_, (&'a str, usize)>>>, w: &str| {
            let yes = rest.peek().is_some_and(|(t, _)| t.eq_ignore_ascii_case(w));
            if yes {
                rest.next();
            }
            yes
        };
        match u.as_ref() {
            "TURN" => mode = Some(PlaneMode::Turn),
            "STAY" => mode = Some(PlaneMode::Stay),
            "MOVE" => {
                diags.error(line, c, "PLANE ... MOVE: the compensating move about DIST is not modelled (TURN and STAY are)");
                return None;
            }
            "FMAX" => feed = FeedWord::Max,
            "F" if next_is(&mut rest, "MAX") => feed = FeedWord::Max,
            "SEQ+" => choice.seq = Some(true),
            "SEQ-" => choice.seq = Some(false),
            "COORD" if next_is(&mut rest, "ROT") => choice.table_rot = Some(false),
            "TABLE" if next_is(&mut rest, "ROT") => choice.table_rot = Some(true),
            "MB" | "DIST" => {
                diags.error(line, c, format!("PLANE ... {u}: a retract or a distance before tilting is not modelled"));
                return None;
            }
            _ => {
                let (addr, v) = point_word(tok).unwrap_or_else(|| split_word(tok));
                match (addresses.iter().find(|a| **a == addr.as_ref()), addr.as_ref()) {
                    (Some(a), _) => {
                        if values.iter().any(|(n, _)| n == a) {
                            diags.error(line, c, format!("PLANE: {a} written twice"));
                            return None;
                        }
                        let w = value_word(addr_static(a), v, tok, c, line, diags)?;
                        values.push((a.to_string(), w));
                    }
                    (None, "F") => feed = FeedWord::Value(value_word("F", v, tok, c, line, diags)?),
                    _ => {
                        diags.error(line, c, format!("PLANE {form_name}: unexpected '{}'", excerpt(tok)));
                        return None;
                    }
                }
            }
        }
    }
    let Some(mode) = mode else {
        diags.error(line, col, format!("PLANE {form_name}: expected TURN or STAY (how the rotary axes are positioned)"));
        return None;
    };
    let take = |name: &str| values.iter().find(|(n, _)| n == name).map(|(_, w)| w.clone());
    let all = |names: &[&str], diags: &mut Diags| -> Option<Vec<KWord<'a>>> {
        let v: Vec<Option<KWord<'a>>> = names.iter().map(|n| take(n)).collect();
        match v.iter().position(Option::is_none) {
            Some(k) => {
                diags.error(line, col, format!("PLANE {form_name}: expected {} (all of {})", names[k], names.join(" ")));
                None
            }
            None => Some(v.into_iter().flatten().collect()),
        }
    };
    let form = match form_name.as_ref() {
        "SPATIAL" => PlaneForm::Spatial(all(addresses, diags)?.try_into().ok()?),
        "EULER" => PlaneForm::Euler(all(addresses, diags)?.try_into().ok()?),
        "VECTOR" => PlaneForm::Vector(all(addresses, diags)?.try_into().ok()?),
        "POINTS" => PlaneForm::Points(all(addresses, diags)?.try_into().ok()?),
        "RELATIV" => match values.as_slice() {
            [(n, w)] => PlaneForm::Relativ(addresses.iter().position(|a| a == n).unwrap_or(0), w.clone()),
            _ => {
                diags.error(line, col, "PLANE RELATIV: expected one of SPA, SPB, SPC");
                return None;
            }
        },
        "AXIAL" if !values.is_empty() => PlaneForm::Axial(values.into_iter().map(|(_, w)| w).collect()),
        "AXIAL" => {
            diags.error(line, col, "PLANE AXIAL: expected the rotary axes' positions A, B or C");
            return None;
        }
        _ => PlaneForm::Reset,
    };
    Some(Kind::Plane(PlaneStmt { form, mode, feed, choice, cycle: false }))
}

/// A `PLANE POINTS` coordinate word (`P1X+0`, `P3Z-12.5`): its address (a digit inside, which
/// [`split_word`] would end it at) and value.
fn point_word(tok: &str) -> Option<(Cow<'_, str>, &str)> {
    let b = tok.as_bytes();
    let is = b.len() > 3 && b[0].eq_ignore_ascii_case(&b'P') && (b'1'..=b'3').contains(&b[1]) && matches!(b[2].to_ascii_uppercase(), b'X' | b'Y' | b'Z');
    is.then(|| (upper(&tok[..3]), &tok[3..]))
}

/// The static address of a PLANE word.
fn addr_static(a: &str) -> &'static str {
    ["SPA", "SPB", "SPC", "EULPR", "EULNU", "EULROT", "BX", "BY", "BZ", "NX", "NY", "NZ", "P1X", "P1Y", "P1Z", "P2X", "P2Y", "P2Z", "P3X", "P3Y", "P3Z", "A", "B", "C"]
        .into_iter()
        .find(|s| *s == a)
        .unwrap_or("PLANE")
}

/// `CYCL DEF 19.0 WORKING PLANE` (its name in the control's language) and `CYCL DEF 19.1 A.. B..
/// C.. [F..]`, or `19.1` alone, the reset (TNC 320 Cycle Programming 340 55x-04 §11.9): the plane
/// becomes effective as it is defined, nothing moves (the program positions the rotary axes). Its
/// angles are the rotary axes' positions or spatial angles as the machine is set up (iTNC 530 HSCI
/// Technical Manual §6.5.6, MP7500 bit 1): the runner decides.
fn cycle19<'a>(toks: &[(&'a str, usize)], part: &str, line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let col = toks[0].1;
    match part {
        "0" => None,
        "1" => {
            let mut values = Vec::new();
            let mut feed = FeedWord::None;
            for &(tok, c) in &toks[3.min(toks.len())..] {
                let (addr, v) = split_word(tok);
                match addr.as_ref() {
                    "A" | "B" | "C" => values.push(value_word(addr_static(&addr), v, tok, c, line, diags)?),
                    "F" => feed = FeedWord::Value(value_word("F", v, tok, c, line, diags)?),
                    _ => {
                        diags.error(line, c, format!("CYCL DEF 19.1: expected A, B, C (and F), found '{}'", excerpt(tok)));
                        return None;
                    }
                }
            }
            let form = if values.is_empty() { PlaneForm::Reset } else { PlaneForm::Axial(values) };
            Some(Kind::Plane(PlaneStmt { form, mode: PlaneMode::Cycle, feed, choice: Default::default(), cycle: true }))
        }
        _ => {
            diags.error(line, col, "CYCL DEF 19: expected CYCL DEF 19.0 and its name, or CYCL DEF 19.1 with the angles A, B, C");
            None
        }
    }
}
