//! Statements the TNC runs and this reader refuses, whose effect lasts: a mirroring, rotation or
//! scaling cycle (`CYCL DEF 8`, `10`, `11`, `26`), a datum shift it does not read (`CYCL DEF 7` from
//! a table, on a rotary axis, of a value not known), a tilted plane it does not read (`PLANE
//! PROJECTED`, any `PLANE` or `CYCL DEF 19` refused), a `FUNCTION TCPM` of a form not read. Until the
//! statement that ends it, every statement that moves is refused, naming the refused one (it is run
//! for the program's state, its moves not made); after it, moves are refused until the axes the held
//! moves displaced are written absolute, as the TNC's tool stands where its held moves left it. The
//! G-code readers' rule ([`crate::program::interp`]'s `lasting`), for the TNC's statements.

use super::tilt::PlaneForm;
use super::{Kind, Stmt, Val};
use crate::program::interp::{axes_said, ran_unread_axes, tnc_m_rule, Rule};
use crate::program::lex::{upper, Diags};
use crate::program::Block;

/// What a refused statement holds on the TNC.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum What {
    /// A coordinate transformation cycle (8 mirroring, 10 rotation, 11 scaling, 26 axis-specific
    /// scaling), until its own reset (TNC 320 Cycle Programming, "Coordinate transformation cycles":
    /// ROT 0, SCL 1, mirroring no axis, the factors 1).
    Transform(u32),
    /// A datum shift not read, until a `CYCL DEF 7` that is read sets each linear axis absolute.
    Datum,
    /// A tilted working plane not read, until a `PLANE` that is read (RESET among them; not RELATIV).
    Plane,
    /// Tool-centre-point management of a form not read, until `FUNCTION RESET TCPM`, `M129` or a
    /// `FUNCTION TCPM` that is read.
    Tcpm,
    /// Radius compensation an `APPR ... RL|RR` turned on, until a `DEP` or an `R0` block.
    Comp,
    /// A move not read (`APPR`, `DEP`, `CTP`, FK, a touch probe): where it left the tool is not known.
    Moved(&'static str),
    /// A statement refused for an M function not read (its code), which the TNC runs.
    Ran(i64),
    /// A `TRANS` function (TNC 640/TNC7): `TRANS DATUM` until `TRANS DATUM RESET` (true), the
    /// others until a reset this reader does not read.
    Trans(bool),
    /// A `TRANS DATUM RESET` refused with cycle 7's shift in effect: the datum, reset or not, is not
    /// known until a `CYCL DEF 7` that is read sets each linear axis absolute (as [`What::Datum`]).
    TransReset,
    /// A lasting M function not read (M112, M114, M134, M136, M144), until its reset (the G-code
    /// readers' rule, [`tnc_m_rule`]).
    Modal(&'static Rule),
}

impl What {
    fn said(self) -> String {
        match self {
            What::Transform(8) => "CYCL DEF 8 (mirroring)".into(),
            What::Transform(10) => "CYCL DEF 10 (rotation)".into(),
            What::Transform(n) => format!("CYCL DEF {n} (scaling)"),
            What::Datum => "CYCL DEF 7 (datum shift)".into(),
            What::Plane => "PLANE (tilted working plane)".into(),
            What::Tcpm => "FUNCTION TCPM".into(),
            What::Comp => "APPR (radius compensation RL/RR)".into(),
            What::Moved(name) => name.into(),
            What::Modal(r) => r.said(),
            What::Ran(m) => format!("M{m} (an M function not read, which the TNC runs)"),
            What::Trans(true) => "TRANS DATUM (a datum shift)".into(),
            What::Trans(false) => "TRANS (a mirroring, rotation or scaling)".into(),
            What::TransReset => "TRANS DATUM RESET (with cycle 7's datum shift in effect)".into(),
        }
    }

    /// Where the tool stands after it, for the message of a move that starts there.
    fn left(self, line: usize) -> String {
        match self {
            What::Moved(_) | What::Ran(_) => format!("line {line}'s {}", self.said()),
            _ => format!("the moves under line {line}'s {}", self.said()),
        }
    }

    fn until(self) -> String {
        match self {
            What::Transform(8) => "its reset (CYCL DEF 8 with no axis)",
            What::Transform(10) => "its reset (CYCL DEF 10 with ROT+0)",
            What::Transform(11) => "its reset (CYCL DEF 11 with SCL 1)",
            What::Transform(_) => "its reset (CYCL DEF 26 with the factors 1)",
            What::Datum | What::TransReset => "a CYCL DEF 7 that is read sets X, Y and Z",
            What::Plane => "a PLANE that is read (PLANE RESET)",
            What::Tcpm => "FUNCTION RESET TCPM or M129",
            What::Comp => "a DEP or an R0 block",
            What::Moved(_) | What::Ran(_) => "",
            What::Trans(true) => "TRANS DATUM RESET",
            What::Trans(false) => "its reset (not read)",
            What::Modal(r) => return r.until(),
        }
        .to_string()
    }

    /// Whether only feed moves change under it (FMAX moves run as written).
    fn feed_only(self) -> bool {
        matches!(self, What::Modal(r) if r.feed_only())
    }
}

/// A hold in effect: what, its line, and the axes (X Y Z) a datum shift or cycle 26 left unknown.
#[derive(Debug, Clone, Copy)]
struct On {
    what: What,
    line: usize,
    axes: [bool; 3],
    /// The statement (its run's serial) whose own refusal began it, 0 for any other.
    made: u64,
}

/// How many statements' lines are remembered as held: radius compensation places a block a few
/// statements after it runs, so a held one is dropped where it comes out.
const RECENT: usize = 16;

/// The holds in effect and, after the last ended, the axes (X Y Z A B C) not yet written absolute.
#[derive(Debug, Clone, Default)]
pub(super) struct Holds {
    on: Vec<On>,
    /// The axes, the line and what left them, and the statement whose own refusal did (as `On`'s).
    stale: Option<([bool; 6], usize, What, u64)>,
    /// The machine's rotary axes among A B C (a plane or a TCPM form turns them).
    rotary: [bool; 3],
    /// The lines of the last statements refused under a hold: their blocks, wherever they come out.
    recent: Vec<usize>,
    /// The statement running (counted), and the one whose refusal is being noted (0: none): what it
    /// begins is said at its own refusal, not again as a hold on it (a loop runs a line again).
    serial: u64,
    making: u64,
}

/// A refused line's tokens in capitals, past a block skip `/` and its block number.
fn tokens(raw: &str) -> Vec<std::borrow::Cow<'_, str>> {
    let mut t: Vec<_> = raw.split(';').next().unwrap_or("").split_whitespace().map(|w| upper(w.trim_start_matches('/'))).filter(|w| !w.is_empty()).collect();
    // `/3 L ..`, `3 /L ..`: the skip and the number (a digit after `/` is its level, then the number).
    while t.first().is_some_and(|w| w.bytes().all(|b| b.is_ascii_digit())) {
        t.remove(0);
    }
    t
}

/// A number as a transformation cycle's reset writes it (`ROT+0`, `SCL1`, `X1`), its letters off.
fn number(s: &str) -> Option<f64> {
    s.trim_start_matches(|c: char| c.is_ascii_alphabetic()).parse().ok()
}

impl Holds {
    /// Holds on a machine whose rotary axes are named `letters` (none without a machine).
    pub(super) fn new(letters: impl IntoIterator<Item = char>) -> Holds {
        let mut rotary = [false; 3];
        for k in letters.into_iter().filter_map(|c| "ABC".find(c.to_ascii_uppercase())) {
            rotary[k] = true;
        }
        Holds { rotary, ..Holds::default() }
    }

    /// A line the parser refused (its `raw` text): what it holds, or which hold its reset ends.
    pub(super) fn refused(&mut self, line: usize, raw: &str) {
        let t = tokens(raw);
        let at = |k: usize| t.get(k).map_or("", |s| s.as_ref());
        if at(0) == "PLANE" {
            return self.hold(What::Plane, line, [true; 3]);
        }
        if at(0) == "FUNCTION" && at(1) == "TCPM" {
            return self.hold(What::Tcpm, line, [true; 3]);
        }
        if at(0) == "TRANS" {
            return self.hold(What::Trans(at(1) == "DATUM"), line, [true; 3]);
        }
        // Its lasting M functions (`L X+5 M112 T0.05 A10`): the TNC runs them all the same.
        for rule in t.iter().filter_map(|w| w.strip_prefix('M')?.parse::<i64>().ok()).filter_map(tnc_m_rule) {
            self.hold(What::Modal(rule), line, [true; 3]);
        }
        // A move the TNC makes and this reader does not read: the tool's position after it is not
        // known. APPR with RL/RR turns on radius compensation; DEP turns it off.
        let moved = match at(0) {
            "CALL" if at(1) == "PGM" => Some("CALL PGM (a program called)"),
            "APPR" => Some("APPR (approach on a contour)"),
            "DEP" => Some("DEP (departure from a contour)"),
            "CTP" => Some("CTP (a polar tangential arc)"),
            "FL" | "FLT" | "FC" | "FCT" => Some("FK (a free contour element)"),
            "TCH" => Some("TCH PROBE (a touch probe cycle)"),
            _ => None,
        };
        if let Some(name) = moved {
            if at(0) == "DEP" {
                self.on.retain(|o| o.what != What::Comp);
            }
            if at(0) == "APPR" && t.iter().any(|w| w == "RL" || w == "RR") {
                self.hold(What::Comp, line, [true; 3]);
            }
            // In the working plane (X Y) and any axis it names; a probe cycle or a called program any.
            let all = matches!(at(0), "TCH" | "CALL");
            let r = self.rotary;
            let mut axes = if all { [true, true, true, r[0], r[1], r[2]] } else { [true, true, false, false, false, false] };
            for w in t.iter().skip(1) {
                let mut c = w.chars();
                if let (Some(l), Some(n)) = (c.next(), c.next()) {
                    if let Some(k) = "XYZABC".find(l).filter(|_| n.is_ascii_digit() || n == '+' || n == '-') {
                        axes[k] = true;
                    }
                }
            }
            return self.unknown(axes, line, What::Moved(name));
        }
        if at(0) != "CYCL" || at(1) != "DEF" {
            return;
        }
        let (cycle, part) = at(2).split_once('.').unwrap_or((at(2), ""));
        // The words after the number: values (`ROT+0`, `SCL 1`, `X1`), not the centre (`CCX+15`).
        let rest: Vec<&str> = t.iter().skip(3).map(|s| s.as_ref()).filter(|w| !w.starts_with("CC")).collect();
        match (cycle, part) {
            ("7", _) => self.hold(What::Datum, line, [true; 3]),
            ("19", _) => self.hold(What::Plane, line, [true; 3]),
            ("8" | "10" | "11" | "26", "0" | "") => {}
            ("10", _) => {
                // `ROT+0`, `ROT 0`, `ROT+0.000`; a Q parameter or an increment is not known: held.
                let v = match rest.as_slice() {
                    [w] if w.starts_with("ROT") => number(w),
                    ["ROT", v] => number(v),
                    _ => None,
                };
                if v == Some(0.0) {
                    self.end(What::Transform(10));
                } else {
                    self.hold(What::Transform(10), line, [true; 3]);
                }
            }
            ("8", _) if rest.is_empty() => self.end(What::Transform(8)),
            ("8", _) => self.hold(What::Transform(8), line, [true; 3]),
            ("11", _) => {
                let values: Vec<Option<f64>> = rest.iter().filter(|w| w.bytes().any(|b| b.is_ascii_digit()) || w.contains('Q')).map(|w| number(w)).collect();
                if !values.is_empty() && values.iter().all(|v| *v == Some(1.0)) {
                    self.end(What::Transform(11));
                } else {
                    self.hold(What::Transform(11), line, [true; 3]);
                }
            }
            ("26", _) => {
                // Per axis: a factor 1 resets its axis, another (or a Q parameter) scales it.
                let mut axes = self.on.iter().find(|o| o.what == What::Transform(26)).map_or([false; 3], |o| o.axes);
                for w in &rest {
                    if let Some(k) = "XYZ".find(w.chars().next().unwrap_or(' ')) {
                        axes[k] = number(w) != Some(1.0);
                    }
                }
                if axes == [false; 3] {
                    self.end(What::Transform(26));
                } else {
                    self.hold(What::Transform(26), line, axes);
                }
            }
            _ => {}
        }
    }

    fn hold(&mut self, what: What, line: usize, axes: [bool; 3]) {
        self.on.retain(|o| o.what != what);
        self.on.push(On { what, line, axes, made: self.making });
    }

    /// End a hold: the axes its moves displaced stay unknown until written absolute.
    fn end(&mut self, what: What) {
        let Some(k) = self.on.iter().position(|o| o.what == what) else { return };
        let On { line, .. } = self.on.remove(k);
        // A plane and a TCPM form (AXIS SPAT) turned the rotary axes too; the others displaced the
        // linear axes (all three: the reader's tool axis may be any).
        let r = self.rotary;
        let axes = match what {
            // A feed or timing: the positions are the programmed ones.
            What::Modal(m) if m.feed_only() => return,
            What::Plane | What::Tcpm => [true, true, true, r[0], r[1], r[2]],
            // Radius compensation offsets the working plane's X and Y.
            What::Comp => [true, true, false, false, false, false],
            _ => [true, true, true, false, false, false],
        };
        self.unknown(axes, line, what);
    }

    /// The axes (X Y Z A B C) `what` at `line` left where the reader does not know, beside those
    /// already unknown.
    fn unknown(&mut self, axes: [bool; 6], line: usize, what: What) {
        // (A refused statement that adds to them is said at its own refusal, not again.)
        let (before, made) = self.stale.map_or(([false; 6], self.making), |s| (s.0, if self.making != 0 { self.making } else { s.3 }));
        self.stale = Some(([0, 1, 2, 3, 4, 5].map(|k| axes[k] || before[k]), line, what, made));
    }

    /// A statement ran without a defect of its own (`ok`): the holds it ends. One the reader
    /// refused while running (a PLANE, a datum shift, a TCPM form with a value not known) holds; one
    /// refused for an M function the TNC runs (`ran_unread`: its line and code) moved the axes it
    /// names where this reader does not know (a cycle call's M89/M99 X Y Z, M94 the rotary axes).
    pub(super) fn ran(&mut self, s: &Stmt<'_>, ok: bool, ran_unread: Option<(usize, i64)>) {
        self.serial += 1;
        // Its M functions (as numbers: a Q parameter's is not known here).
        let m: &[super::KWord<'_>] = match &s.kind {
            Kind::Move { m, .. } | Kind::Misc(m) => m,
            _ => &[],
        };
        let codes = || m.iter().filter_map(|w| if let Val::Num(v) = w.val { (v.fract() == 0.0 && v.abs() < 1e6).then_some(v as i64) } else { None });
        if !ok {
            self.making = self.serial;
            match &s.kind {
                Kind::Plane(_) => self.hold(What::Plane, s.line, [true; 3]),
                Kind::Datum(..) => self.hold(What::Datum, s.line, [true; 3]),
                Kind::Tcp { on: true, .. } => self.hold(What::Tcpm, s.line, [true; 3]),
                // Cycle 7's shift reset or not: the datum is not known until cycle 7 sets it again.
                Kind::TransReset => self.hold(What::TransReset, s.line, [true; 3]),
                _ => {}
            }
            // A lasting M function refused (or in a statement refused): the TNC runs it all the same.
            for rule in codes().filter_map(tnc_m_rule) {
                self.hold(What::Modal(rule), s.line, [true; 3]);
            }
            // (A lasting one holds the moves instead, above; a feed mode's own move went where the
            // reader did not.)
            if let Some((line, m)) = ran_unread.filter(|(l, m)| *l == s.line && tnc_m_rule(*m).is_none_or(|r| r.feed_only())) {
                let mut named = [false; 6];
                if let Kind::Move { axes: words, .. } = &s.kind {
                    for w in words {
                        if let Some(k) = ["X", "Y", "Z", "A", "B", "C"].iter().position(|a| *a == w.addr.trim_start_matches('I')) {
                            named[k] = true;
                        }
                    }
                }
                let axes = ran_unread_axes(m, named, self.rotary);
                if axes.contains(&true) {
                    self.unknown(axes, line, What::Ran(m));
                }
            }
            self.making = 0;
            return;
        }
        if self.on.is_empty() {
            return;
        }
        for c in codes() {
            let ended: Vec<What> = self.on.iter().filter_map(|o| match o.what {
                What::Modal(r) if r.cancelled_by(c * 10) => Some(o.what),
                _ => None,
            }).collect();
            for what in ended {
                self.end(what);
            }
        }
        match &s.kind {
            Kind::Plane(p) if !matches!(p.form, PlaneForm::Relativ(..)) => self.end(What::Plane),
            Kind::Tcp { .. } => self.end(What::Tcpm),
            Kind::TransReset => self.end(What::Trans(true)),
            // A cycle call ends the modal one (M89).
            Kind::CycleCall(_) => {
                if let Some(r) = tnc_m_rule(89) {
                    self.end(What::Modal(r));
                }
            }
            Kind::Move { comp: Some((None, _)), .. } => self.end(What::Comp),
            Kind::Move { m, .. } | Kind::Misc(m) if m.iter().any(|w| matches!(w.val, Val::Num(v) if v == 129.0)) => self.end(What::Tcpm),
            // An absolute shift of one axis sets it; the hold ends when every axis is set again.
            Kind::Datum(k, _, false) => {
                for what in [What::Datum, What::TransReset] {
                    if let Some(o) = self.on.iter_mut().find(|o| o.what == what) {
                        if let Some(a) = o.axes.get_mut(*k) {
                            *a = false;
                        }
                        if o.axes == [false; 3] {
                            self.end(what);
                        }
                    }
                }
            }
            _ => {}
        }
    }

    /// Whether a statement's moves must be checked: a hold in effect, axes unknown since one, or
    /// blocks of held statements not yet out.
    pub(super) fn active(&self) -> bool {
        !self.on.is_empty() || self.stale.is_some() || !self.recent.is_empty()
    }

    /// Nothing is held, nor unknown, nor waiting to come out (no radius compensation, no element held
    /// for a corner): the lines of the held statements are forgotten, so that a later run of them (a
    /// subprogram called again) is read.
    pub(super) fn settled(&mut self) {
        if self.on.is_empty() && self.stale.is_none() {
            self.recent.clear();
        }
    }

    /// The blocks that came out from `start` on: those of held statements are dropped.
    pub(super) fn drop_held(&mut self, out: &mut Vec<Block>, start: usize) {
        if self.recent.is_empty() || start >= out.len() {
            return;
        }
        let recent = &self.recent;
        let tail = out.split_off(start);
        out.extend(tail.into_iter().filter(|b| b.targets.is_empty() || !recent.contains(&b.line)));
    }

    /// After a statement ran under a hold (`moves`: it moves the tool; `ok`: without a defect of its
    /// own): refused if it moves (said at the statement; its blocks dropped wherever they come out);
    /// the axes it wrote absolute are known again.
    pub(super) fn after(&mut self, s: &Stmt<'_>, moves: bool, ok: bool, diags: &mut Diags) {
        // FMAX moves run as written under a feed's hold.
        let rapid = matches!(&s.kind, Kind::Move { feed: super::FeedWord::Max, .. });
        // (A hold this statement began, refused, is said at its own refusal.)
        let serial = self.serial;
        let holding = self.on.iter().find(|o| o.made != serial && !(rapid && o.what.feed_only()));
        let stale = self.stale.filter(|st| st.3 != serial);
        if moves && (holding.is_some() || stale.is_some()) {
            let why = match (holding, &stale) {
                (Some(o), _) => format!("a move while line {}'s {} is in effect on the TNC until {}: that block was refused, so this move is not read as the TNC runs it", o.line, o.what.said(), o.what.until()),
                (None, Some((axes, line, what, _))) => {
                    format!("a move from where {} left the tool, which is not known (the TNC ran it, this reader did not): moves are read again once {} written absolute", what.left(*line), axes_said(*axes))
                }
                (None, None) => return,
            };
            diags.error(s.line, s.col, why);
            if self.recent.len() == RECENT {
                self.recent.remove(0);
            }
            self.recent.push(s.line);
        }
        if let (true, Some(stale), Kind::Move { axes, .. }) = (ok && holding.is_none(), self.stale.as_mut(), &s.kind) {
            for w in axes {
                if let Some(k) = ["X", "Y", "Z", "A", "B", "C"].iter().position(|a| *a == w.addr) {
                    stale.0[k] = false;
                }
            }
            if stale.0 == [false; 6] {
                self.stale = None;
            }
        }
    }
}
