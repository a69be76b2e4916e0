//! Statements the TNC runs and this reader refuses, whose effect lasts: a mirroring, rotation or
//! scaling cycle (`CYCL DEF 8`, `10`, `11`, `26`), a datum shift it does not read (`CYCL DEF 7` from
//! a table or on a rotary axis), `PLANE PROJECTED`, a `FUNCTION TCPM` of a form not read. Until the
//! statement that ends it, every statement that moves is refused, naming the refused one (it is run
//! for the program's state, its moves not made); after it, moves are refused until the axes the held
//! moves displaced are written absolute, as the TNC's tool stands where its held moves left it. The
//! G-code readers' rule ([`crate::program::interp`]'s `lasting`), for the TNC's statements.

use super::{Kind, Stmt, Val};
use crate::program::lex::{upper, Diags};
use crate::program::Block;

/// What a refused statement holds on the TNC.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum What {
    /// A coordinate transformation cycle (8 mirroring, 10 rotation, 11 scaling, 26 axis-specific
    /// scaling), until its own reset (TNC 320 Cycle Programming, "Coordinate transformation cycles":
    /// ROT 0, SCL 1, mirroring no axis, all factors 1).
    Transform(u32),
    /// A datum shift not read (a datum table, a rotary axis), until a `CYCL DEF 7` that is read.
    Datum,
    /// A tilted working plane not read, until a `PLANE` that is read (RESET among them).
    Plane,
    /// Tool-centre-point management of a form not read, until `FUNCTION RESET TCPM`, `M129` or a
    /// `FUNCTION TCPM` that is read.
    Tcpm,
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
        }
    }

    fn until(self) -> &'static str {
        match self {
            What::Transform(8) => "its reset (CYCL DEF 8 with no axis)",
            What::Transform(10) => "its reset (CYCL DEF 10 with ROT+0)",
            What::Transform(11) => "its reset (CYCL DEF 11 with SCL 1)",
            What::Transform(_) => "its reset (CYCL DEF 26 with all factors 1)",
            What::Datum => "a CYCL DEF 7 that is read",
            What::Plane => "a PLANE that is read (PLANE RESET)",
            What::Tcpm => "FUNCTION RESET TCPM or M129",
        }
    }
}

/// The holds in effect and, after the last ended, the axes (X Y Z A B C) not yet written absolute.
#[derive(Debug, Clone, Default)]
pub(super) struct Holds {
    on: Vec<(What, usize)>,
    stale: Option<([bool; 6], usize, What)>,
    /// The machine's rotary axes among A B C (a plane turns them).
    rotary: [bool; 3],
}

/// A refused line's tokens in capitals, past its block number.
fn tokens(raw: &str) -> Vec<std::borrow::Cow<'_, str>> {
    let mut t: Vec<_> = raw.split(';').next().unwrap_or("").split_whitespace().map(upper).collect();
    if t.first().is_some_and(|w| w.bytes().all(|b| b.is_ascii_digit())) {
        t.remove(0);
    }
    t
}

/// A number as a transformation cycle's reset writes it (`ROT+0`, `SCL1`, `SCL 1`), its letters off.
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

    /// A line the reader refused (its `raw` text): what it holds, or which hold its reset ends.
    pub(super) fn refused(&mut self, line: usize, raw: &str) {
        let t = tokens(raw);
        let at = |k: usize| t.get(k).map_or("", |s| s.as_ref());
        if at(0) == "PLANE" && at(1) == "PROJECTED" {
            return self.hold(What::Plane, line);
        }
        if at(0) == "FUNCTION" && at(1) == "TCPM" {
            return self.hold(What::Tcpm, line);
        }
        if at(0) != "CYCL" || at(1) != "DEF" {
            return;
        }
        let (cycle, part) = at(2).split_once('.').unwrap_or((at(2), ""));
        let rest: Vec<&str> = t.iter().skip(3).map(|s| s.as_ref()).collect();
        match (cycle, part) {
            ("7", _) => self.hold(What::Datum, line),
            ("8" | "10" | "11" | "26", "0" | "") => {}
            ("8" | "10" | "11" | "26", _) => {
                let n: u32 = cycle.parse().unwrap_or(0);
                // The reset as the manual writes it; a value from a Q parameter is not known, so held.
                let reset = match n {
                    8 => rest.is_empty(),
                    10 => matches!(rest.as_slice(), ["ROT+0" | "ROT0" | "ROT-0"] | ["ROT", "0" | "+0"]),
                    _ => {
                        let values: Vec<Option<f64>> = rest.iter().filter(|w| w.bytes().any(|b| b.is_ascii_digit())).map(|w| number(w)).collect();
                        !values.is_empty() && values.iter().all(|v| *v == Some(1.0))
                    }
                };
                if reset {
                    self.end(What::Transform(n));
                } else {
                    self.hold(What::Transform(n), line);
                }
            }
            _ => {}
        }
    }

    fn hold(&mut self, what: What, line: usize) {
        self.on.retain(|(w, _)| *w != what);
        self.on.push((what, line));
    }

    /// End a hold: the axes its moves displaced stay unknown until written absolute.
    fn end(&mut self, what: What) {
        let Some(k) = self.on.iter().position(|(w, _)| *w == what) else { return };
        let (_, line) = self.on.remove(k);
        // A rotation turns the working plane's X and Y (tool axis Z); a plane the rotary axes too;
        // the others displace the linear axes.
        let r = self.rotary;
        let axes = match what {
            What::Transform(10) => [true, true, false, false, false, false],
            What::Plane => [true, true, true, r[0], r[1], r[2]],
            _ => [true, true, true, false, false, false],
        };
        let before = self.stale.map_or([false; 6], |s| s.0);
        self.stale = Some(([0, 1, 2, 3, 4, 5].map(|k| axes[k] || before[k]), line, what));
    }

    /// Before a statement that was read runs: the holds it ends.
    pub(super) fn ends(&mut self, s: &Stmt<'_>) {
        if self.on.is_empty() {
            return;
        }
        match &s.kind {
            Kind::Plane(_) => self.end(What::Plane),
            Kind::Tcp { .. } => self.end(What::Tcpm),
            Kind::Move { m, .. } | Kind::Misc(m) if m.iter().any(|w| matches!(w.val, Val::Num(v) if v == 129.0)) => self.end(What::Tcpm),
            Kind::Datum(..) => self.end(What::Datum),
            _ => {}
        }
    }

    /// Whether a statement's moves must be checked: a hold in effect, or axes unknown since one.
    pub(super) fn active(&self) -> bool {
        !self.on.is_empty() || self.stale.is_some()
    }

    /// After a statement ran under a hold (its blocks from `start` on): refused if it moved (its
    /// blocks dropped, said at the statement); the axes it wrote absolute are known again.
    pub(super) fn after(&mut self, s: &Stmt<'_>, start: usize, ok: bool, out: &mut Vec<Block>, diags: &mut Diags) {
        let moved = out[start.min(out.len())..].iter().any(|b| !b.targets.is_empty());
        if moved {
            out.truncate(start);
            let why = match (self.on.first(), &self.stale) {
                (Some((what, line)), _) => format!("a move while line {line}'s {} is in effect on the TNC until {}: that block was refused, so this move is not read as the TNC runs it", what.said(), what.until()),
                (None, Some((axes, line, what))) => {
                    let names: Vec<&str> = (0..6).filter(|&k| axes[k]).map(|k| ["X", "Y", "Z", "A", "B", "C"][k]).collect();
                    let names = match names.split_last() {
                        Some((last, rest)) if !rest.is_empty() => format!("{} and {last} are", rest.join(", ")),
                        _ => format!("{} is", names.concat()),
                    };
                    format!("a move from where the moves under line {line}'s {} left the tool, which is not known (the TNC ran them, this reader did not): moves are read again once {names} written absolute", what.said())
                }
                (None, None) => return,
            };
            diags.error(s.line, s.col, why);
        }
        if let (true, Some(stale), Kind::Move { axes, .. }) = (ok && self.on.is_empty(), self.stale.as_mut(), &s.kind) {
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
