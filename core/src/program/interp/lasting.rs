//! What a refused block leaves: none of its codes take effect here (later defects name it), but the
//! control runs it, so its cutter compensation, scaling, mirroring, tilted plane, canned cycle or
//! feed mode then shapes every move until the code that cancels it, and a move it made (a spline)
//! leaves its axes where this reader does not know. Such moves are refused, naming the block,
//! instead of being read as if it had not been written.

use super::{codes, Interpreter, Word};
use crate::program::{Dialect, Motion};

/// A modal code of a refused block, in effect on the control until one of its cancel codes.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Lasting {
    /// The refused block's line and its code as written (`41`, `51.1`).
    line: usize,
    code: String,
    rule: &'static Rule,
}

/// A modal group's codes that shape the path, and the codes that cancel them (× 10: G41 is 410).
#[derive(Debug)]
pub(crate) struct Rule {
    /// The codes' letter: `G`, or `M` for the TNC's M functions.
    letter: char,
    what: &'static str,
    codes: &'static [i64],
    cancels: &'static [i64],
    /// Only feed moves change under it (a feed mode: rapids run as written).
    feed_only: bool,
    /// How messages name its cancels, where not by listing them.
    until: Option<&'static str>,
    /// Its own code with these words ends it too (the TNC's DIN/ISO cycles: `G73 H+0`), the
    /// program's dimensions absolute or not (G90/G91, the block's own first).
    reset: Option<fn(&[Word], bool) -> bool>,
}

/// Cutter radius compensation, G40 its cancel (FANUC B-64484EN "Cutter compensation C"; Haas Mill
/// Operator's Manual, G40-G42).
const COMP: Rule = Rule { letter: 'G', what: "cutter radius compensation", codes: &[410, 420], cancels: &[400], feed_only: false, until: None, reset: None };
/// Fanuc's normal direction control G41.1/G42.1, cancelled by G40.1 (FANUC B-64484EN "Normal
/// direction control").
const NORMAL: Rule = Rule { letter: 'G', what: "normal direction control", codes: &[411, 421], cancels: &[401], feed_only: false, until: None, reset: None };
/// Tool length offset along the tool axis or added (Fanuc G43.1; LinuxCNC G43.1 dynamic, G43.2
/// additional), cancelled by G49 or replaced by another code of its group (G43, G44, G43.4, G43.5).
const LENGTH: Rule = Rule { letter: 'G', what: "dynamic or additional tool length offset", codes: &[431, 432], cancels: &[490, 430, 440, 434, 435], feed_only: false, until: None, reset: None };
/// Tilted working planes, G69 their cancel (FANUC B-64484EN "Tilted working plane indexing"). Fanuc's
/// G68.2 with Euler angles is read ([`crate::program::feature`]); refused (its other forms, under
/// G91, a second one; any on Haas), the control runs it all the same.
const TILT: Rule = Rule { letter: 'G', what: "tilted working plane", codes: &[682, 683, 684], cancels: &[690], feed_only: false, until: None, reset: None };
/// Scaling G51, cancelled by G50; programmable mirror image G51.1, cancelled by G50.1 (FANUC
/// B-64484EN "Scaling", "Programmable mirror image"; Haas G50-G51, G50.1-G51.1).
const SCALING: Rule = Rule { letter: 'G', what: "scaling", codes: &[510], cancels: &[500], feed_only: false, until: None, reset: None };
const MIRROR: Rule = Rule { letter: 'G', what: "mirror image", codes: &[511], cancels: &[501], feed_only: false, until: None, reset: None };
/// A canned cycle the reader refuses but the control runs (Fanuc's G76/G87 with a shift, LinuxCNC's
/// G87/G88 and its taps outside G17, [`Interpreter::hold_cycle`]): it drills at every later position
/// until "G80 or a G code of group 01" (FANUC B-64484EN "Canned cycle cancel"; LinuxCNC: any other
/// motion code). Its codes are the cycles the reader reads in other forms, so it is held where it is
/// refused for what is not read, never for a defect.
/// Another cycle replaces it (one of its group 09), as a group-01 code ends it.
const CYCLE: Rule = Rule {
    letter: 'G',
    what: "canned cycle: the control drills at every later position",
    codes: &[],
    cancels: &[800, 0, 10, 20, 30, 730, 740, 760, 810, 820, 830, 840, 850, 860, 870, 880, 890],
    feed_only: false,
    until: Some("G80, a G00-G03 or another canned cycle"),
    reset: None,
};
/// An additional work offset (Fanuc's `G54.1 Pn`, Haas' `G154 Pn` or `G110`-`G129`) in effect after a
/// refused `G10 L20 Pn` set it: the control's offset is the program's, not read here, until another
/// work offset is selected (G54-G59, or another additional one, read), in the dialect's codes.
const WORK: Rule = Rule {
    letter: 'G',
    what: "an additional work offset its refused G10 L20 set",
    codes: &[],
    cancels: &[540, 550, 560, 570, 580, 590, 591, 592, 593, 541],
    feed_only: false,
    until: Some("G54-G59 or another additional work offset"),
    reset: None,
};
const WORK_HAAS: Rule = Rule {
    cancels: &[
        540, 550, 560, 570, 580, 590, 591, 592, 593, 541, 1540, 1100, 1110, 1120, 1130, 1140, 1150, 1160, 1170, 1180, 1190, 1200, 1210, 1220, 1230, 1240, 1250, 1260,
        1270, 1280, 1290,
    ],
    ..WORK
};
/// The 840D's statements this reader refuses whose effect lasts until another that it reads (letter
/// `_`: the code is the statement's name; which statements end each: the Sinumerik reader's table).
/// A programmable frame (`SCALE`, `MIRROR`, `ROTS` and their additive forms, `CROTS`) until a `TRANS`
/// or `ROT` replaces it ("old instructions for offsetting, rotation, scaling factor, mirroring"
/// cleared: NC programming 6FC5398-2EP40 12/2019 §2.12).
pub(crate) const SIN_FRAME: Rule = Rule {
    letter: '_',
    what: "a programmable frame not read: scaling, mirroring or a solid-angle rotation",
    codes: &[],
    cancels: &[],
    feed_only: false,
    until: Some("a TRANS or ROT that is read, which replaces the programmable frame"),
    reset: None,
};
/// A kinematic transformation not read (`TRANSMIT`, `TRACYL`, `TRAANG`, `TRAORI` with arguments) until
/// `TRAFOOF`.
pub(crate) const SIN_TRANSFORM: Rule = Rule { what: "a kinematic transformation not read", until: Some("TRAFOOF"), ..SIN_FRAME };
/// An orientation interpolation not read (a cone, `ORICON..`, a curve, `ORICURVE`, or relative to the
/// path, `ORIPATH`/`ORIPATHS`: G group 51, NC programming 12/2019 §4.3.51) until another of its group
/// that is read (`ORIVECT`, `ORIPLANE`, `ORIAXES`).
pub(crate) const SIN_ORIENT: Rule = Rule { what: "an orientation interpolation not read", until: Some("ORIVECT, ORIPLANE or ORIAXES"), ..SIN_FRAME };
/// The rotation vector's interpolation not read (`ORIROTR`, `ORIROTT`, `ORIROTC`: G group 54,
/// Fundamentals 10.2004 §12.3; Job Planning 03/2006 §7.4) until `ORIROTA`, the group's default.
pub(crate) const SIN_ROTATE: Rule = Rule { what: "an interpolation of the tool's rotation vector not read", until: Some("ORIROTA"), ..SIN_FRAME };
/// A modal call refused (`MCALL` of a cycle or program not read, or of a drilling cycle whose
/// parameters are refused): the control calls it after every later move until `MCALL` alone ends it
/// or another `MCALL` replaces it (NC programming 12/2019, "Modal subprogram call (MCALL)").
pub(crate) const SIN_MCALL: Rule = Rule { what: "a modal call (MCALL) refused", until: Some("MCALL alone or a modal call that is read"), ..SIN_FRAME };
/// A swivel `CYCLE800` refused (the control swivels all the same) until a `CYCLE800` that is read.
pub(crate) const SIN_SWIVEL: Rule = Rule { what: "a swivel (CYCLE800) not read", until: Some("a CYCLE800 that is read"), ..SIN_FRAME };
/// A feed profile over the block (`FLIN`, `FCUB`, `FPO`) until `FNORM`: feed moves only.
pub(crate) const SIN_FEED: Rule = Rule { what: "a feed profile over the block not read", until: Some("FNORM"), feed_only: true, ..SIN_FRAME };
/// Fanuc's coordinate modes refused here, whose axis words mean other things until their cancel
/// (FANUC B-64484EN "Polar coordinate command (G15, G16)": X Y a radius and an angle until G15;
/// "Polar coordinate interpolation (G12.1, G13.1)"; "Cylindrical interpolation (G07.1)": on until
/// `G07.1` with the rotary axis' radius 0).
const POLAR: Rule = Rule { letter: 'G', what: "polar coordinate command", codes: &[160], cancels: &[150], feed_only: false, until: None, reset: None };
const POLAR_INTERP: Rule = Rule { letter: 'G', what: "polar coordinate interpolation", codes: &[121], cancels: &[131], feed_only: false, until: None, reset: None };
const CYLINDRICAL: Rule = Rule {
    letter: 'G',
    what: "cylindrical interpolation",
    codes: &[71],
    cancels: &[],
    feed_only: false,
    until: Some("its cancel (G07.1 with the rotary axis' radius 0)"),
    reset: Some(|w, _| w.iter().any(|w| matches!(w.letter, 'A' | 'B' | 'C') && w.value == 0.0)),
};
/// Feed per revolution, cancelled by G94 or G93.
const PER_REV: Rule = Rule { letter: 'G', what: "feed per revolution", codes: &[950], cancels: &[940, 930], feed_only: true, until: None, reset: None };

/// The TNC's M functions this model refuses whose effect lasts until their reset (one code each):
/// M112 rounding arcs between straight lines (and M124 under it) until M113 (TNC 407 user's manual
/// 280 580 §5, "Insert rounding arc between straight lines: M112"; "M124 T... is cancelled by
/// M113"); M114 automatic compensation of the machine geometry with tilted axes until M115 (iTNC
/// 530 ISO user's manual 340 420 §7.5: "To cancel M114, enter M115"); M144 the kinematics' offsets
/// at the block end until M145 (iTNC 530 user's manual 60642x-03 §12.5: "You can cancel M144 by
/// programming M145"); M134 exact stop at non-tangential transitions until M135, and M136 feed per
/// spindle revolution until M137 (ibid. §12.6, §12.4): the feed and timing only; M89, the modal
/// cycle call, until M99 or a cycle call (TNC 306/406 technical manual §7.4: "M89 as a cycle-call
/// is modally effective ... M89 is canceled by M99 or a CYCL CALL-block").
const TNC_M: [Rule; 6] = [
    Rule { letter: 'M', what: "rounding arcs between straight lines", codes: &[1120, 1240], cancels: &[1130], feed_only: false, until: None, reset: None },
    Rule { letter: 'M', what: "compensation of the machine geometry with tilted axes", codes: &[1140], cancels: &[1150], feed_only: false, until: None, reset: None },
    Rule { letter: 'M', what: "exact stop at non-tangential transitions", codes: &[1340], cancels: &[1350], feed_only: true, until: None, reset: None },
    Rule { letter: 'M', what: "feed per spindle revolution", codes: &[1360], cancels: &[1370], feed_only: true, until: None, reset: None },
    Rule { letter: 'M', what: "the kinematics' offsets at the block end", codes: &[1440], cancels: &[1450], feed_only: false, until: None, reset: None },
    Rule { letter: 'M', what: "the modal cycle call: the TNC drills at every later position", codes: &[890], cancels: &[990], feed_only: false, until: Some("M99 or a cycle call"), reset: None },
];
/// The TNC's DIN/ISO coordinate transformations, its cycles 8, 10, 11 and 19 in G codes, refused
/// here: mirroring `G28` until a `G28` without axes, rotation `G73` until `G73 H+0` (not under a
/// `G91` in its block: an increment of 0 keeps the rotation; TNC 360 ISO manual's example "N100 G73
/// G90 H+0 * Cancel rotation"), scaling `G72` until `G72 F1` (iTNC 530 ISO user's manual 340 422
/// §8.10: "Cancellation: Program the SCALING FACTOR cycle once again with a scaling factor of 1"),
/// the working plane `G80` until `G80` with its angles 0 (the cycles' resets, TNC 320 Cycle
/// Programming "Coordinate transformation cycles": mirroring no axis, a rotation angle of 0, the
/// factor 1, cycle 19's angles 0).
const TNC_G: [Rule; 4] = [
    Rule { letter: 'G', what: "mirroring (cycle 8)", codes: &[280], cancels: &[], feed_only: false, until: Some("its reset (G28 with no axis)"), reset: Some(|w, _| !w.iter().any(|w| matches!(w.letter, 'X' | 'Y' | 'Z' | 'A' | 'B' | 'C' | 'U' | 'V' | 'W'))) },
    Rule { letter: 'G', what: "rotation (cycle 10)", codes: &[730], cancels: &[], feed_only: false, until: Some("its reset (G73 H+0)"), reset: Some(|w, absolute| w.iter().any(|w| w.letter == 'H' && w.value == 0.0) && absolute_in(w, absolute)) },
    Rule { letter: 'G', what: "scaling (cycle 11)", codes: &[720], cancels: &[], feed_only: false, until: Some("its reset (G72 F1)"), reset: Some(|w, _| w.iter().any(|w| w.letter == 'F' && w.value == 1.0)) },
    Rule {
        letter: 'G',
        what: "tilted working plane (cycle 19)",
        codes: &[800],
        cancels: &[],
        feed_only: false,
        until: Some("its reset (G80 with the angles 0)"),
        reset: Some(|w, _| w.iter().filter(|w| matches!(w.letter, 'A' | 'B' | 'C')).all(|w| w.value == 0.0)),
    },
];
const TNC_RULES: [&Rule; 10] = [&TNC_M[0], &TNC_M[1], &TNC_M[2], &TNC_M[3], &TNC_M[4], &TNC_M[5], &TNC_G[0], &TNC_G[1], &TNC_G[2], &TNC_G[3]];

/// The lasting TNC M function `code` (M144: 144), if it is one ([`TNC_M`]); the Klartext reader's
/// holds use the same rules.
pub(crate) fn tnc_m_rule(code: i64) -> Option<&'static Rule> {
    TNC_M.iter().find(|r| r.codes.contains(&(code * 10)))
}

impl Lasting {
    /// How a message names the refused code: `G41`, `M144`, `MIRROR`.
    fn named(&self) -> String {
        if self.rule.letter == '_' { self.code.clone() } else { format!("{}{}", self.rule.letter, self.code) }
    }

    /// The hold as messages say it: `line 5's G41 (cutter radius compensation) is in effect on the
    /// control until G40`.
    fn in_effect(&self) -> String {
        format!("line {}'s {} ({}) is in effect on the control until {}", self.line, self.named(), self.rule.what, self.rule.until())
    }
}

/// Rules are one by what they are and their codes (the reset's function is no identity).
impl PartialEq for Rule {
    fn eq(&self, other: &Rule) -> bool {
        self.letter == other.letter && self.what == other.what && self.codes == other.codes
    }
}
impl Eq for Rule {}

impl Rule {
    /// The rule's name in a message: its code and what it does (`M144 (the kinematics' offsets at the
    /// block end)`).
    pub(crate) fn said(&self) -> String {
        format!("{}{} ({})", self.letter, self.codes.first().map_or(String::new(), |c| code_said(*c)), self.what)
    }

    /// Its cancels as a message names them (`M145`; `G40`).
    pub(crate) fn until(&self) -> String {
        self.until.map_or_else(|| self.cancels.iter().map(|c| format!("{}{}", self.letter, code_said(*c))).collect::<Vec<_>>().join(" or "), String::from)
    }

    /// Whether only feed moves change under it (rapids run as written).
    pub(crate) fn feed_only(&self) -> bool {
        self.feed_only
    }

    /// Whether a code (× 10) of its letter ends it.
    pub(crate) fn cancelled_by(&self, code: i64) -> bool {
        self.cancels.contains(&code)
    }
}

/// A code × 10 as written: 400 `40`, 501 `50.1`.
fn code_said(c: i64) -> String {
    if c % 10 == 0 { (c / 10).to_string() } else { format!("{}.{}", c / 10, c % 10) }
}

/// The rules of a dialect: the modal codes its control runs and this reader refuses (always, or in
/// some forms: G68.2). Codes it reads (canned cycles, G68, LinuxCNC's G41/G42) hold nothing when
/// refused: that is for a defect of the block, at which the control stops too. LinuxCNC has no
/// scaling, mirror or tilted plane codes (it stops at them as at any unknown code); the 840D's and
/// the TNC's cutter compensation are read.
fn rules(dialect: Dialect) -> &'static [&'static Rule] {
    match dialect {
        Dialect::Fanuc => &[&COMP, &NORMAL, &LENGTH, &TILT, &SCALING, &MIRROR, &POLAR, &POLAR_INTERP, &CYLINDRICAL],
        Dialect::Haas => &[&COMP, &LENGTH, &TILT, &SCALING, &MIRROR, &PER_REV],
        Dialect::Rs274 => &[&LENGTH],
        Dialect::Heidenhain => &TNC_RULES,
        _ => &[],
    }
}

/// Codes whose block's axis words are offsets, a time or a radius, not a move: G10, G04, G92 (and its
/// .1-.3), G52, Fanuc's G07.1 (the rotary axis' radius).
const NO_MOVE: [i64; 8] = [100, 40, 920, 921, 922, 923, 520, 71];
/// The TNC's DIN/ISO codes whose axis words move nothing: G54 (a datum shift), G30/G31 (the blank),
/// G99 (a tool definition), G04 (a dwell), G80 (the working plane's angles).
const NO_MOVE_TNC: [i64; 6] = [540, 300, 310, 990, 40, 800];

/// Whether a block's axis words move nothing, by its G codes (× 10) in the dialect.
fn moves_nothing(dialect: Dialect, mut g: impl Iterator<Item = i64>) -> bool {
    let list: &[i64] = if dialect == Dialect::Heidenhain { &NO_MOVE_TNC } else { &NO_MOVE };
    g.any(|c| list.contains(&c))
}

/// A word that moves an axis; `arc`: an arc's centre or radius too (a full circle has no end point).
fn axis_word(w: &Word, arc: bool) -> bool {
    matches!(w.letter, 'X' | 'Y' | 'Z' | 'A' | 'B' | 'C' | 'U' | 'V' | 'W') || arc && matches!(w.letter, 'I' | 'J' | 'K' | 'R')
}

/// Where the moves under a hold left the tool, after its cancel: the axes not yet written absolute
/// since (X Y Z A B C), and the hold's line, name (`G41`, `BSPLINE`) and what it was.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Stale {
    axes: [bool; 6],
    line: usize,
    name: String,
    what: &'static str,
}

/// What a block refused for a TNC M function not read that the control runs did ([`Interpreter::block`]).
pub(crate) const RAN_UNREAD: &str = "an M function not read, which the control runs";

/// The axes (X Y Z A B C) a block refused for the TNC's M function `m`, which the TNC runs, leaves
/// unknown: those it names (`named`), X Y Z too for a cycle call (M89/M99), and the machine's rotary
/// axes (`rotary`, A B C) for M94, which reduces their display. Both TNC readers' rule.
pub(crate) fn ran_unread_axes(m: i64, named: [bool; 6], rotary: [bool; 3]) -> [bool; 6] {
    let mut axes = named;
    match m {
        89 | 99 => axes[..3].fill(true),
        94 => (0..3).for_each(|k| axes[3 + k] |= rotary[k]),
        _ => {}
    }
    axes
}

/// Whether a block's dimensions are absolute: its own G90 or G91, else the program's (`absolute`).
/// `G73 G91 H+0` turns by nothing, and so does `G73 H+0` under a modal G91 (TNC 360 ISO: "N100 G73
/// G90 H+0 * Cancel rotation").
fn absolute_in(words: &[Word], absolute: bool) -> bool {
    words.iter().rev().filter(|w| w.letter == 'G').find_map(|w| match super::x10(w) {
        900 => Some(true),
        910 => Some(false),
        _ => None,
    }).unwrap_or(absolute)
}

/// What a block does under the holds: its G and M codes (× 10), the word a move is said at.
struct Look {
    g: Vec<i64>,
    m: Vec<i64>,
    axis: Option<(usize, bool)>,
}

impl Look {
    /// Whether the block holds one of the rule's cancels, or its own code with its reset's words.
    fn cancels(&self, rule: &Rule, words: &[Word], absolute: bool) -> bool {
        let codes = if rule.letter == 'M' { &self.m } else { &self.g };
        rule.cancels.iter().any(|c| codes.contains(c)) || rule.reset.is_some_and(|reset| rule.codes.iter().any(|c| codes.contains(c)) && reset(words, absolute))
    }
}

impl Interpreter {
    /// The block's G codes, and its first word that moves an axis (with whether it moves at rapid).
    fn look(&self, words: &[Word]) -> Look {
        let g: Vec<i64> = words.iter().filter(|w| w.letter == 'G').map(super::x10).collect();
        // The block's motion: its own group-01 code or canned cycle, else the modal one.
        let own = g.iter().find_map(|&c| match c {
            0 => Some(Some(Motion::Rapid)),
            10 => Some(Some(Motion::Linear)),
            20 => Some(Some(Motion::ArcCw)),
            30 => Some(Some(Motion::ArcCcw)),
            730..=890 if c != 800 => Some(None),
            _ => None,
        });
        let motion = own.unwrap_or(self.motion);
        let arc = matches!(motion, Some(Motion::ArcCw | Motion::ArcCcw));
        let moves = !moves_nothing(self.dialect, g.iter().copied());
        let axis = words.iter().find(|w| moves && axis_word(w, arc)).map(|w| (w.column, motion == Some(Motion::Rapid)));
        let m = if self.dialect == Dialect::Heidenhain { words.iter().filter(|w| w.letter == 'M').map(super::x10).collect() } else { Vec::new() };
        Look { g, m, axis }
    }

    /// Before a block is read: why it is refused if it moves while a refused block's code is in
    /// effect on the control, or from where such moves left the tool (its column and the message).
    /// The block is read all the same, so that the program's state (position, feed, modes) follows
    /// the program as the control's does; only its moves are not made.
    pub(crate) fn held(&self, words: &[Word]) -> Option<(usize, String)> {
        if self.lasting.is_empty() && self.stale.is_none() {
            return None;
        }
        let look = self.look(words);
        let (column, rapid) = look.axis?;
        for l in &self.lasting {
            let cancelled = look.cancels(l.rule, words, self.absolute);
            if l.rule.feed_only && (cancelled || rapid) {
                continue;
            }
            let cancel = l.rule.until();
            let named = l.named();
            // The cancel's own move starts where the held moves left the tool.
            let from = if l.rule.what == COMP.what { "at the point its compensation made" } else { "where the moves under it left the tool" };
            return Some((column, if cancelled {
                format!("{cancel} with a move after line {}'s {named} ({}), which was refused: the control starts this move {from}, which is not known", l.line, l.rule.what)
            } else {
                format!("a move while {}: that block was refused, so this move is not read as the control runs it", l.in_effect())
            }));
        }
        let s = self.stale.as_ref()?;
        // A single block's move (an M function not read) or the moves under a mode.
        let under = if s.what == RAN_UNREAD { "" } else { "the moves under " };
        Some((column, format!("a move from where {under}line {}'s {} ({}) left the tool, which is not known (the control ran them, this reader did not): moves are read again once {} written absolute", s.line, s.name, s.what, axes_said(s.axes))))
    }

    /// After a block is read or refused: its cancel codes end their holds (the axes the held moves
    /// placed stay unknown until written absolute), and a block read clears the axes it writes absolute.
    pub(crate) fn after_held(&mut self, words: &[Word], line: usize, done: bool) {
        if self.lasting.is_empty() && self.stale.is_none() {
            return;
        }
        let look = self.look(words);
        let (plane, absolute) = (self.plane.axes(), self.absolute);
        let mut ended = Vec::new();
        self.lasting.retain(|l| {
            // A hold its own block set (a refused G87) is not ended by its own code.
            let cancelled = l.line != line && look.cancels(l.rule, words, absolute);
            if cancelled && !l.rule.feed_only {
                ended.push(l.clone());
            }
            !cancelled
        });
        for l in ended {
            // Cutter compensation offsets the plane's two axes, a canned cycle leaves the drilling axis
            // at its initial or R level; the other holds place all three, and a tilted plane the
            // machine's rotary axes too (G53.1 under it turned them).
            let mut axes = [false; 6];
            if l.rule.what == COMP.what {
                axes[plane.0] = true;
                axes[plane.1] = true;
            } else if l.rule.what == CYCLE.what {
                axes[plane.2] = true;
            } else {
                axes[..3].fill(true);
            }
            if [TILT.what, TNC_G[3].what, POLAR_INTERP.what].contains(&l.rule.what) {
                axes = self.with_rotary(axes);
            }
            self.moved_unread(l.line, &l.named(), l.rule.what, axes);
        }
        if !done || look.axis.is_none() {
            return;
        }
        if self.stale.is_some() {
            let mut written = [false; 6];
            for k in words.iter().filter(|w| w.dimension.absolute(absolute)).filter_map(|w| "XYZABC".find(w.letter)) {
                written[k] = true;
            }
            self.placed(written);
        }
    }

    /// A move the control makes and the reader does not read (a spline, a 3D circle, the moves under a
    /// hold just ended: `what`, by `name`): where it leaves the axes it names (`axes`, X Y Z A B C),
    /// beside those already unknown, is not known until they are written absolute.
    pub(crate) fn moved_unread(&mut self, line: usize, name: &str, what: &'static str, axes: [bool; 6]) {
        if !axes.contains(&true) {
            return;
        }
        let before = self.stale.take().map_or([false; 6], |s| s.axes);
        self.stale = Some(Stale { axes: [0, 1, 2, 3, 4, 5].map(|k| axes[k] || before[k]), line, name: name.to_string(), what });
    }

    /// A move refused while the motion mode is one not read ([`Interpreter::forget_motion`]): the
    /// control made it, so the axes it names (`axes`, X Y Z A B C) are unknown until written absolute.
    pub(crate) fn moved_in_unread_mode(&mut self, axes: [bool; 6]) {
        if let (None, Some((l, name, what))) = (self.motion, self.forgotten.clone()) {
            self.moved_unread(l, &name, what, axes);
        }
    }

    /// A refused block's additional work offsets (Fanuc, Haas): a `G10 L20 Pn` refused leaves offset n
    /// unknown on the control (its P and line kept, and its moves held at once where n is in
    /// effect); selecting such an offset holds the moves in it until another is selected.
    fn note_offset_set(&mut self, words: &[Word], line: usize) {
        let value = |l: char| words.iter().find(|w| w.letter == l).map(|w| w.value);
        let g10 = words.iter().any(|w| w.letter == 'G' && codes::x10(w) == 100);
        if let (true, Some(20.0), Some(p)) = (g10, value('L'), value('P')) {
            if p.fract() == 0.0 && (1.0..=300.0).contains(&p) {
                self.refused_offsets.retain(|(q, _)| f64::from(*q) != p);
                self.refused_offsets.push((p as u32, line));
                if self.extra_offset && f64::from(self.extra_p) == p {
                    self.hold_offset(line, "10 L20");
                }
            }
        }
        // Its selection refused in turn (its offset not read): the control runs in that offset.
        if let Some((p, code)) = super::g_codes::extra_offset_selected(self.dialect, words) {
            if let Some(at) = self.offset_refused(f64::from(p)) {
                self.hold_offset(at.max(line), &code);
            }
        }
    }

    /// The 840D's statement `name` refused at `line`, whose effect lasts ([`SIN_FRAME`] and the
    /// like): the moves are held until a statement the reader reads ends it ([`Interpreter::end_keyword_hold`]).
    pub(crate) fn hold_keyword(&mut self, line: usize, name: &str, rule: &'static Rule) {
        self.hold(line, name.to_string(), rule);
    }

    /// A hold of `rule` from `line`'s `code`, in place of one of the same rule.
    fn hold(&mut self, line: usize, code: String, rule: &'static Rule) {
        self.lasting.retain(|l| l.rule.what != rule.what);
        self.lasting.push(Lasting { line, code, rule });
    }

    /// A statement read ends the hold of `rule`: the axes its held moves displaced (`axes`, X Y Z A B C;
    /// the machine's rotary axes where `rotary`) are unknown until written absolute.
    pub(crate) fn end_keyword_hold(&mut self, rule: &'static Rule, axes: [bool; 3], rotary: bool) {
        if let Some(k) = self.lasting.iter().position(|l| l.rule.what == rule.what) {
            let l = self.lasting.remove(k);
            let linear = [axes[0], axes[1], axes[2], false, false, false];
            let all = if rotary { self.with_rotary(linear) } else { linear };
            self.moved_unread(l.line, &l.named(), l.rule.what, all);
        }
    }

    /// Whether a hold of `rule` is in effect.
    pub(crate) fn held_by(&self, rule: &Rule) -> bool {
        self.lasting.iter().any(|l| l.rule.what == rule.what)
    }

    /// The axes left unknown, set aside while a statement that places axes itself is read (a
    /// swivel), to come back with [`Interpreter::restore_stale`].
    pub(crate) fn take_stale(&mut self) -> Option<Stale> {
        self.stale.take()
    }

    /// The axes set aside by [`Interpreter::take_stale`] unknown again, beside any left unknown since.
    pub(crate) fn restore_stale(&mut self, stale: Option<Stale>) {
        if let Some(s) = stale {
            self.moved_unread(s.line, &s.name, s.what, s.axes);
        }
    }

    /// A statement moved `placed` (X Y Z A B C) to positions this reader knows (absolute, or in
    /// machine coordinates): they are no longer unknown.
    pub(crate) fn placed(&mut self, placed: [bool; 6]) {
        if let Some(s) = self.stale.as_mut() {
            (0..6).filter(|&k| placed[k]).for_each(|k| s.axes[k] = false);
            if s.axes == [false; 6] {
                self.stale = None;
            }
        }
    }

    /// Whether the only thing holding the moves is axes left unknown (no hold in effect).
    pub(crate) fn only_stale(&self) -> bool {
        self.lasting.is_empty() && self.stale.is_some()
    }

    /// A call the control runs and this reader does not (`name`, `what`): every axis (X Y Z and the
    /// machine's rotary axes) is where this reader does not know.
    pub(crate) fn moved_everywhere(&mut self, line: usize, name: &str, what: &'static str) {
        let axes = self.with_rotary([true, true, true, false, false, false]);
        self.moved_unread(line, name, what, axes);
    }

    /// The machine's rotary axes among A B C.
    pub(crate) fn rotary_axes(&self) -> [bool; 3] {
        let mut r = [false; 3];
        for k in self.rotary_letters.iter().flatten().filter_map(|c| "ABC".find(*c)) {
            r[k] = true;
        }
        r
    }

    /// `axes` (X Y Z A B C) with the machine's rotary axes too.
    fn with_rotary(&self, axes: [bool; 6]) -> [bool; 6] {
        let r = self.rotary_axes();
        [axes[0], axes[1], axes[2], axes[3] || r[0], axes[4] || r[1], axes[5] || r[2]]
    }

    /// The first hold in effect, or the axes left unknown, as a message says it, whatever the block
    /// moves (for statements that move by what they call: a cycle, a swivel).
    pub(crate) fn holding(&self) -> Option<String> {
        if let Some(l) = self.lasting.first() {
            return Some(format!("{}: that block was refused, so what this one moves is not read as the control runs it", l.in_effect()));
        }
        let s = self.stale.as_ref()?;
        Some(format!("the moves under line {}'s {} ({}) left the tool where this reader does not know, until {} written absolute", s.line, s.name, s.what, axes_said(s.axes)))
    }

    /// Moves held in an additional work offset a refused `G10 L20` set (`code` the refused block's).
    fn hold_offset(&mut self, line: usize, code: &str) {
        let rule = if self.dialect == Dialect::Haas { &WORK_HAAS } else { &WORK };
        self.hold(line, code.to_string(), rule);
    }

    /// The refused `G10 L20` that set the additional work offset `p`, if any (its line).
    pub(crate) fn offset_refused(&self, p: f64) -> Option<usize> {
        self.refused_offsets.iter().find(|(q, _)| f64::from(*q) == p).map(|(_, l)| *l)
    }

    /// A canned cycle refused for what is not read (`code` as the control names it, `87`): the
    /// control runs it at every later position until its cancel.
    pub(crate) fn hold_cycle(&mut self, line: usize, code: &str) {
        self.hold(line, code.to_string(), &CYCLE);
    }

    /// After a block is refused: its codes that the control keeps in effect (until their cancel).
    /// A feed mode's own block moved at the feed it sets, to where this reader did not go: the axes
    /// it names are unknown (the other holds' own moves are their moves, held).
    pub(crate) fn note_lasting(&mut self, words: &[Word], line: usize) {
        self.note_lasting_of(words, line, false);
    }

    /// [`Interpreter::note_lasting`]; `damaged`: the block's words are not all read, so a reset
    /// (`G28` without axes) is not told from its code (`G28 X` damaged).
    fn note_lasting_of(&mut self, words: &[Word], line: usize, damaged: bool) {
        for w in words.iter().filter(|w| matches!(w.letter, 'G' | 'M')) {
            let c = super::x10(w);
            if let Some(rule) = rules(self.dialect).iter().find(|r| r.letter == w.letter && r.codes.contains(&c)) {
                // Its reset holds nothing (a refused `G73 H+0` the control runs all the same).
                if !damaged && rule.reset.is_some_and(|reset| reset(words, self.absolute)) {
                    continue;
                }
                let code = w.raw.trim_start_matches('0').to_string();
                if rule.feed_only {
                    self.moved_unread(line, &format!("{}{code}", rule.letter), rule.what, axes_named(self.dialect, words));
                }
                self.hold(line, code, rule);
            }
        }
    }

    /// A damaged block (its words not all read) of the TNC's DIN/ISO: its codes the TNC runs all the
    /// same hold the moves after it ([`Interpreter::refused`]), a reset among them not told.
    pub(crate) fn refused_damaged(&mut self, words: &[Word], line: usize) {
        self.note_lasting_of(words, line, true);
        self.refused(words, line);
    }

    /// A block with G codes was refused: none of them took effect here, which later defects name;
    /// a spline mode leaves the motion unknown, and the codes the control keeps hold later moves.
    pub(crate) fn refused(&mut self, words: &[Word], line: usize) {
        if !words.iter().any(|w| w.letter == 'G') {
            // The TNC's lasting M functions (DIN/ISO) in a block without G codes.
            if self.dialect == Dialect::Heidenhain && words.iter().any(|w| w.letter == 'M') {
                self.note_lasting(words, line);
                self.after_held(words, line, false);
            }
            return;
        }
        self.refused_line = Some(line);
        // A refused spline, NURBS or 3D circle mode (G group 01, modal): the moves after it on the
        // control are its points, not lines of the mode before.
        let unread = words.iter().filter(|w| w.letter == 'G').find_map(|w| codes::unread_motion(self.dialect, codes::x10(w)).map(|what| (w, what)));
        if let (true, Some((w, what))) = (matches!(self.dialect, Dialect::Rs274 | Dialect::Fanuc | Dialect::Haas), unread) {
            // Its move (the control makes it) leaves the tool where this reader does not know.
            self.forget_motion(line, &format!("G{}", w.raw.trim_start_matches('0')), what, axes_named(self.dialect, words));
        }
        // A move of its own the control makes (a reference return, a skip): the axes it names, or
        // every axis for LinuxCNC's G28/G30 and Haas' G28 alone, where this reader does not know.
        let moved = words.iter().filter(|w| w.letter == 'G').find_map(|w| codes::unread_move(self.dialect, codes::x10(w)).map(|what| (w, what)));
        if let (true, Some((w, what))) = (self.dialect.is_rs274_family(), moved) {
            let mut axes = axes_named(self.dialect, words);
            if !axes.contains(&true) && (self.dialect == Dialect::Rs274 || self.dialect == Dialect::Haas && codes::x10(w) == 280) {
                axes = self.with_rotary([true, true, true, false, false, false]);
            }
            self.moved_unread(line, &format!("G{}", w.raw.trim_start_matches('0')), what, axes);
        }
        self.note_lasting(words, line);
        if self.dialect.is_fanuc() {
            self.note_offset_set(words, line);
        }
        // Its cancel codes act on the control all the same.
        self.after_held(words, line, false);
    }

    /// What to add to a defect that a refused block's codes, had they taken effect, might have
    /// avoided (a word its modal code would take, a centre word of its plane).
    pub(crate) fn after_refused(&self) -> String {
        self.refused_line.map_or(String::new(), |l| format!(" (line {l} was refused before it, and none of its codes took effect)"))
    }

    /// After a block is read (`done`) or refused: a refused block with an F word is the one a later
    /// move without a feed names, until a block sets a feed.
    pub(crate) fn note_feed(&mut self, done: bool, has_f: bool, line: usize) {
        if !done && has_f {
            self.refused_feed_line = Some(line);
        } else if done && self.feed.is_some() {
            self.refused_feed_line = None;
        }
    }

    /// A refused block set a modal motion this reader does not read (an 840D spline, `CIP`, `CT`;
    /// `name` and `what` it is): the motion mode is unknown until a block gives one, so a later move
    /// without its own is refused, naming the block; the axes it moved (`axes`, X Y Z A B C), and
    /// those of the moves refused in the mode after it, are unknown until written absolute.
    pub(crate) fn forget_motion(&mut self, line: usize, name: &str, what: &'static str, axes: [bool; 6]) {
        self.motion = None;
        self.refused_line = Some(line);
        self.forgotten = Some((line, name.to_string(), what));
        self.moved_unread(line, name, what, axes);
    }

    /// What to add to "move without a feed" where a refused block since the last feed carried one.
    pub(crate) fn after_refused_feed(&self) -> String {
        self.refused_feed_line.map_or(String::new(), |l| format!(" (line {l}, refused before it, gave one, and none of its words took effect)"))
    }
}

/// The axes a block's words move (X Y Z A B C): none in a block of G10, G04, G92 or G52, whose
/// words are offsets or a time (the TNC's DIN/ISO: G54, G30/G31, G99, G04).
pub(crate) fn axes_named(dialect: Dialect, words: &[Word]) -> [bool; 6] {
    if moves_nothing(dialect, words.iter().filter(|w| w.letter == 'G').map(codes::x10)) {
        return [false; 6];
    }
    ['X', 'Y', 'Z', 'A', 'B', 'C'].map(|l| words.iter().any(|w| w.letter == l))
}

/// Axes not yet known (X Y Z A B C) as a message names them: `Z is`, `X, Y and Z are`.
pub(crate) fn axes_said(axes: [bool; 6]) -> String {
    let names: Vec<&str> = (0..6).filter(|&k| axes[k]).map(|k| ["X", "Y", "Z", "A", "B", "C"][k]).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last} are", rest.join(", ")),
        _ => format!("{} is", names.concat()),
    }
}
