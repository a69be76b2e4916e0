//! `CYCL DEF` blocks: which cycle, its parameters, and the cycles read here (7 datum shift, 9 dwell,
//! 19 working plane, 32 tolerance, the drilling cycles and the machine maker's own), parsed, then
//! defined and called as the TNC runs them (`CYCL CALL`, `M99`, `M89`).

use super::*;
use std::borrow::Cow;

use super::exec::Exec;
use crate::program::interp::{Dimension, Interpreter, Word};
use crate::program::tnc_cycles::{tnc_chip_tapping, tnc_hole, tnc_pecking, tnc_single_lip, tnc_universal, TncChipTapping, TncFeed, TncHole, TncLevels, TncPecking, TncSingleLip, TncStep, TncUniversal};
use crate::program::Block;

/// `CYCL DEF 32.0 TOLERANCE` / `32.1 T0.05` / `32.2 HSC-MODE:0 TA0.5` (TNC 620 Cycle Programming, 340
/// 56x-03, §12.5): the contour tolerance on the path (program unit) and, under M128/TCPM, on the rotary
/// axes (deg), for the blocks after it. `32.1` without `T` resets both to the machine's (its file's
/// `contour_tolerance_mm`/`_deg`). `HSC-MODE:0` and `:1` (finishing, roughing) choose the maker's
/// filter within the same tolerance.
pub(super) fn tolerance_cycle<'a>(toks: &[(&'a str, usize)], part: &str, line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
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
pub(super) fn cycle<'a>(toks: &[(&'a str, usize)], line: usize, defined: &mut bool, diags: &mut Diags) -> Option<Kind<'a>> {
    let col = toks[0].1;
    let number = toks.get(2).map_or("", |t| t.0);
    let (cycle, part) = number.split_once('.').unwrap_or((number, ""));
    if cycle == "9" {
        let expected = || format!("CYCL DEF {number}: expected CYCL DEF 9.0 DWELL TIME or CYCL DEF 9.1 DWELL followed by the time, s");
        return match part {
            "0" => None,
            // 9.1, its label in the control's dialog language (DWELL, V.ZEIT, ...), the time, joined
            // to it or not.
            "1" if toks.len() >= 4 && label_words(&toks[3..toks.len() - 1]) => {
                let (last, last_col) = toks[toks.len() - 1];
                match labelled(last, toks.len() > 4) {
                    Some((label, value)) => value_word("DWELL", value, last, last_col + label.chars().count(), line, diags).map(Kind::Dwell),
                    None => {
                        diags.error(line, col, expected());
                        None
                    }
                }
            }
            _ => {
                diags.error(line, col, expected());
                None
            }
        };
    }
    if cycle == "32" {
        return tolerance_cycle(toks, part, line, diags);
    }
    if cycle == "1" && !part.is_empty() {
        return pecking_part(toks, part, line, diags);
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
            // The older cycles' form, a number and its parts: `CYCL DEF 1.0 PECKING`, `1.1 SET UP 2`,
            // ... (NX's TNC posts write it for drilling).
            (_, false, Ok(n)) if part.parse::<u32>().is_ok() => {
                diags.error(line, col, format!("CYCL DEF {number}: cycle {n} in the older numbered form ({n}.0, {n}.1, ...) is not read (it moves the tool)"));
                None
            }
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

/// An older cycle part's last token split into its label and its value (`DIST25.000`, `V.IDŐ2`;
/// `25.000` after a label of its own, `words_before`): the value is the digits and point at the end,
/// a Q before them, a sign before that; the label, in the control's dialog language, ends in a
/// letter. `None` if there is no value, or no label at all.
fn labelled(last: &str, words_before: bool) -> Option<(&str, &str)> {
    let b = last.as_bytes();
    let mut i = b.len();
    while i > 0 && (b[i - 1].is_ascii_digit() || b[i - 1] == b'.') {
        i -= 1;
    }
    if i > 0 && i < b.len() && b[i - 1].eq_ignore_ascii_case(&b'Q') && b[i..].iter().all(u8::is_ascii_digit) {
        i -= 1;
    }
    if i > 0 && matches!(b[i - 1], b'+' | b'-') {
        i -= 1;
    }
    let (label, value) = last.split_at(i);
    let label_ok = label.chars().last().is_none_or(char::is_alphabetic);
    (value.bytes().any(|c| c.is_ascii_digit()) && label_ok && (words_before || !label.is_empty())).then_some((label, value))
}

/// Whether the words before a cycle part's value are its label (`SET UP`, `DWELL`): words without a
/// digit, no second value among them.
fn label_words(words: &[(&str, usize)]) -> bool {
    words.iter().all(|(w, _)| !w.bytes().any(|c| c.is_ascii_digit()))
}

/// The parts of the older cycle 1 PECKING after its name, in order: what each gives (as the
/// manuals name them; the block's label is in the control's language: `SET UP`, `ABST`, `DIST`).
const PECKING_PARTS: [&str; 5] = ["SET UP", "DEPTH", "PECKG", "DWELL", "F"];

/// One block of the older cycle 1 PECKING (TNC 426/425/415 B/407: `CYCL DEF 1.0 PECKING`, `1.1 SET
/// UP -2`, `1.2 DEPTH -20`, `1.3 PECKG -5`, `1.4 DWELL 0`, `1.5 F80`; German `ABST`, `TIEFE`,
/// `ZUSTLG`, `V.ZEIT`): the part's value is the number or Q parameter that ends the block, its
/// label joined to it or not (`DIST25.000`, `SET UP .1181`); part 5 is the feed, `F`.
fn pecking_part<'a>(toks: &[(&'a str, usize)], part: &str, line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let col = toks[0].1;
    let n = match part.parse::<u32>() {
        Ok(0) => return Some(Kind::Pecking { part: 0, value: None }),
        Ok(n @ 1..=5) => n,
        _ => {
            diags.error(line, col, format!("CYCL DEF 1.{part}: cycle 1 PECKING has the parts 1.0 to 1.5"));
            return None;
        }
    };
    let what = PECKING_PARTS[n as usize - 1];
    let Some(&(last, last_col)) = toks.get(3..).and_then(|r| r.last()) else {
        diags.error(line, col, format!("CYCL DEF 1.{n}: expected the {what} value"));
        return None;
    };
    let Some((label, value)) = labelled(last, toks.len() > 4).filter(|_| label_words(&toks[3..toks.len() - 1])) else {
        diags.error(line, last_col, format!("CYCL DEF 1.{n}: expected the {what} (a label, then a number or a Q parameter), found '{}'", excerpt(last)));
        return None;
    };
    // The feed's label is F; the others are in the control's language.
    if n == 5 {
        let feed_label = if label.is_empty() { toks[3..toks.len() - 1].iter().map(|t| t.0).collect::<Vec<_>>().join(" ") } else { label.to_string() };
        if !feed_label.eq_ignore_ascii_case("F") {
            diags.error(line, toks[3].1, format!("CYCL DEF 1.5: expected the feed, F, found '{}'", excerpt(&feed_label)));
            return None;
        }
    }
    value_word(what, value, last, last_col + label.chars().count(), line, diags).map(|w| Kind::Pecking { part: n, value: Some(w) })
}

/// A parameter's value as a message shows it (`MAX` for rapid traverse).
fn shown(v: f64) -> String {
    if v.is_infinite() {
        "MAX".into()
    } else {
        format!("{v}")
    }
}

/// A TNC cycle's feeds, in the program's feed unit as written (infinite: rapid traverse, `MAX`).
#[derive(Debug, Clone, Copy)]
struct Feeds {
    plunge: f64,
    retract: f64,
    preposition: f64,
}

impl Feeds {
    /// All moves at one feed (the older cycles, and cycle 200's, which has one).
    fn one(f: f64) -> Self {
        Self { plunge: f, retract: f, preposition: f }
    }

    fn of(&self, which: TncFeed) -> f64 {
        match which {
            TncFeed::Plunge => self.plunge,
            TncFeed::Retract => self.retract,
            TncFeed::Preposition => self.preposition,
        }
    }
}

impl Exec {
    /// `CYCL DEF n`: the drilling cycles 200, 201, 203, 207, 209, 240 and 241 are kept for the next call;
    /// cycle 247 selects a preset of the machine's table (its values are the operator's: the datum
    /// is taken as the workpiece's, and linear ranges are not judged); the machine maker's own
    /// cycles that move nothing are in its file; any other is refused. A drilling cycle's
    /// parameters are the Q assignments that follow it, up to the first other statement.
    pub(super) fn define_cycle(&mut self, n: u32, s: &Stmt<'_>, interp: &mut Interpreter, diags: &mut Diags) {
        self.collecting_params = false;
        match n {
            200 | 201 | 203 | 207 | 209 | 240 | 241 => {
                (self.cycle, self.refused_cycle) = (Some((n, s.line)), None);
                self.cycle_params.clear();
                self.collecting_params = true;
            }
            247 => interp.set_preset_assumed(),
            _ if self.machine.as_ref().is_some_and(|m| m.state_cycles.contains(&n)) => {}
            _ => {
                diags.error(s.line, s.col, format!("CYCL DEF {n}: this cycle is not read (it may move the tool; the drilling cycles 200, 201, 203, 207, 209, 240 and 241 are, and the machine file names its maker's cycles that move nothing)"));
                // A call runs the cycle defined last: this one.
                (self.cycle, self.refused_cycle) = (None, Some((n, s.line)));
            }
        }
    }

    /// A cycle's parameter as the call finds it: the parameter's value now (infinite for `MAX`), or
    /// `None` if unset. Cycle parameters are Q parameters like any (TNC 320 User's Manual, "Q
    /// parameters": Q200 to Q1199 the cycles'); one changed since the definition wrote it (a maker's
    /// cycle between, a program's own assignment) is refused: whether the cycle takes the
    /// definition's value or the new one is not in the pages at hand.
    fn cycle_value(&self, name: &str) -> Result<Option<f64>, String> {
        let now = if self.q_max.contains(name) { Some(f64::INFINITY) } else { self.q.get(name).copied() };
        match (self.cycle_params.get(name), now) {
            (Some(&defined), Some(v)) if defined != v => Err(format!("{name} was {} in the cycle's definition and is {} at its call: which one the cycle takes is not read", shown(defined), shown(v))),
            (Some(_), None) => Err(format!("{name} was written in the cycle's definition and is unset at its call")),
            (_, v) => Ok(v),
        }
    }

    /// A Q parameter a cycle needs, in SI (`scale` per program unit); why not, if unset or `MAX`.
    pub(super) fn cycle_q(&self, name: &str, scale: f64) -> Result<f64, String> {
        match self.cycle_value(name)? {
            Some(v) if v.is_finite() => Ok(v * scale),
            Some(_) => Err(format!("{name}=MAX: rapid traverse where a number is expected")),
            None => Err(format!("{name} is not set")),
        }
    }

    /// A cycle's feed parameter as written (infinite for `MAX`, rapid traverse); why not, if unset
    /// or negative.
    fn cycle_feed(&self, name: &str) -> Result<f64, String> {
        match self.cycle_value(name)? {
            Some(v) if v < 0.0 => Err(format!("{name}={v}: a feed must not be negative")),
            Some(v) => Ok(v),
            None => Err(format!("{name} is not set")),
        }
    }

    /// A parameter newer software added to a cycle, if its definition writes it (older programs'
    /// definitions do not, and another cycle's value of it is not this cycle's).
    fn cycle_opt(&self, name: &str) -> Result<Option<f64>, String> {
        if !self.cycle_params.contains_key(name) {
            return Ok(None);
        }
        self.cycle_value(name)
    }

    /// A block of the older cycle 1 PECKING: `1.0` begins it (and replaces the cycle defined
    /// before), each part after it must follow the one before, and `1.5` completes it.
    pub(super) fn define_pecking(&mut self, part: u32, value: Option<&KWord<'_>>, s: &Stmt<'_>, diags: &mut Diags) {
        if part == 0 {
            self.pecking = Some(super::exec::Pecking { line: s.line, ..Default::default() });
            (self.cycle, self.refused_cycle) = (None, None);
            return;
        }
        let Some(p) = self.pecking.as_ref() else {
            diags.error(s.line, s.col, format!("CYCL DEF 1.{part} without CYCL DEF 1.0 before it"));
            return;
        };
        if let Some(at) = p.refused {
            diags.error(s.line, s.col, format!("CYCL DEF 1.{part}: the cycle's definition was refused at line {at}"));
            return;
        }
        let expected = p.values.len() + 1;
        let v = if expected != part as usize {
            diags.error(s.line, s.col, format!("CYCL DEF 1.{part}: expected CYCL DEF 1.{expected} next"));
            None
        } else {
            value.and_then(|w| self.value(w, s.line, diags))
        };
        let Some(p) = self.pecking.as_mut() else { return };
        match v {
            Some(v) => p.values.push(v),
            None => p.refused = Some(s.line),
        }
        if p.values.len() == 5 {
            self.cycle = Some((1, p.line));
        }
    }

    /// A drilling cycle's moves (200, 201, 203, 207, 209, 240, 241) from its Q parameters, and its
    /// feeds (in the program's feed unit, `feed_unit` m a unit), or why it cannot run.
    fn drilling_moves(&self, n: u32, unit: f64, feed_unit: f64) -> Result<(Vec<TncStep>, Feeds), String> {
        let q = |name: &str| self.cycle_q(name, unit);
        // A tapping cycle's feed (207, 209): the pitch Q239 (a length, m) per turn times the spindle's
        // turns a minute, in the feed's unit.
        let tapping_feed = || -> Result<f64, String> {
            let speed = self.spindle.ok_or("the spindle speed (TOOL CALL S) is not known")?;
            Ok(q("Q239")?.abs() * speed.abs() / feed_unit)
        };
        let levels = TncLevels { surface: q("Q203")?, clearance: q("Q200")?.abs(), clearance2: q("Q204")?.abs(), depth: q("Q201")? };
        let depth = levels.depth;
        if depth > 0.0 {
            return Err(format!("Q201={}: a positive depth (drilling up) is not read", depth / unit));
        }
        // Q395 DEPTH REFERENCE 1: the depth is to the tool's full diameter, deeper by its point's
        // length, which the program does not give.
        if matches!(n, 200 | 203) && self.cycle_opt("Q395")?.is_some_and(|v| v != 0.0) {
            return Err("Q395=1: a depth to the tool's full diameter (deeper by its point's length) is not read".into());
        }
        // Q206 FEED RATE FOR PLUNGING (cycle 207 has none: its feed is the pitch at the speed).
        let plunge_feed = || self.cycle_feed("Q206");
        // Q208 RETRACTION FEED RATE: "If you enter Q208 = 0, the TNC retracts the tool at feed rate Q206".
        let retract_feed = |plunge: f64| self.cycle_feed("Q208").map(|f| if f == 0.0 { plunge } else { f });
        let mut h = TncHole { levels, plunge: 0.0, dwell_top_s: 0.0, dwell_bottom_s: 0.0, out_at: None };
        let (steps, feeds) = match n {
            200 => {
                h.plunge = q("Q202")?.abs();
                h.dwell_top_s = self.cycle_q("Q210", 1.0)?;
                h.dwell_bottom_s = self.cycle_q("Q211", 1.0)?;
                (tnc_hole(&h), Feeds::one(plunge_feed()?))
            }
            203 => {
                let breaks = self.cycle_q("Q213", 1.0)?;
                if !(breaks >= 0.0 && breaks.fract() == 0.0 && breaks <= f64::from(u32::MAX)) {
                    return Err(format!("Q213={breaks}: the number of chip breaks is a whole number from 0 to {}", u32::MAX));
                }
                let c = TncUniversal {
                    levels,
                    plunge: q("Q202")?.abs(),
                    decrement: q("Q212")?.abs(),
                    min_plunge: q("Q205")?.abs(),
                    breaks: breaks as u32,
                    break_distance: q("Q256")?.abs(),
                    dwell_top_s: self.cycle_q("Q210", 1.0)?,
                    dwell_bottom_s: self.cycle_q("Q211", 1.0)?,
                };
                let plunge = plunge_feed()?;
                (tnc_universal(&c)?, Feeds { retract: retract_feed(plunge)?, ..Feeds::one(plunge) })
            }
            241 => {
                // What later software added to the cycle, read only where it changes nothing: a
                // dwell depth (Q435), infeeds (Q202 less than the depth) and the feed factor after
                // the dwell depth (Q401) are not in the pages at hand.
                if let Some(v) = self.cycle_opt("Q435")?.filter(|v| *v != 0.0) {
                    return Err(format!("Q435={v}: a dwell depth is not read"));
                }
                if let Some(v) = self.cycle_opt("Q202")?.filter(|v| *v != 0.0 && v.abs() * unit < -depth) {
                    return Err(format!("Q202={v}: infeeds less than the depth are not read"));
                }
                if let Some(v) = self.cycle_opt("Q401")?.filter(|v| *v != 100.0) {
                    return Err(format!("Q401={v}: a feed factor other than 100% is not read"));
                }
                let start = q("Q379")?;
                if start < 0.0 {
                    return Err(format!("Q379={}: a deepened starting point above the surface is not read", start / unit));
                }
                let c = TncSingleLip { levels, start, dwell_bottom_s: self.cycle_q("Q211", 1.0)? };
                let plunge = plunge_feed()?;
                let preposition = if start > 0.0 { self.cycle_feed("Q253")? } else { plunge };
                if preposition == 0.0 {
                    return Err("Q253=0: the feed for pre-positioning to the deepened starting point is not positive".into());
                }
                (tnc_single_lip(&c)?, Feeds { retract: retract_feed(plunge)?, preposition, plunge })
            }
            201 => {
                // 201 REAMING: one plunge at Q206, the dwell Q211, out at Q208 (0: Q206's).
                h.dwell_bottom_s = self.cycle_q("Q211", 1.0)?;
                h.out_at = Some(TncFeed::Retract);
                let plunge = plunge_feed()?;
                (tnc_hole(&h), Feeds { retract: retract_feed(plunge)?, ..Feeds::one(plunge) })
            }
            209 => {
                // 209 TAPPING WITH CHIP BREAKING: in at the tapping feed, out at that times the RPM
                // factor Q403 (a later parameter: 1 where the definition lacks it).
                let factor = self.cycle_opt("Q403")?.unwrap_or(1.0);
                if !((0.0001..=10.0).contains(&factor)) {
                    return Err(format!("Q403={}: the RPM factor for retraction is 0.0001 to 10", shown(factor)));
                }
                let back = self.cycle_q("Q256", 1.0)?;
                if back < 0.0 {
                    return Err(format!("Q256={}: the retraction for chip breaking is 0 or more (times the pitch)", shown(back)));
                }
                let c = TncChipTapping { levels, infeed: q("Q257")?.abs(), back_off: (back > 0.0).then_some(back * q("Q239")?.abs()) };
                let tap = tapping_feed()?;
                (tnc_chip_tapping(&c)?, Feeds { plunge: tap, retract: tap * factor, preposition: tap })
            }
            240 => {
                if self.cycle_q("Q343", 1.0)? != 0.0 {
                    return Err("Q343=1: a depth from the centering diameter (the tool's point angle) is not read".into());
                }
                h.dwell_bottom_s = self.cycle_q("Q211", 1.0)?;
                (tnc_hole(&h), Feeds::one(plunge_feed()?))
            }
            _ => {
                // 207 RIGID TAPPING: the tapping feed, in and out.
                h.out_at = Some(TncFeed::Plunge);
                (tnc_hole(&h), Feeds::one(tapping_feed()?))
            }
        };
        if feeds.plunge.is_infinite() {
            return Err("its feed is MAX: drilling at rapid traverse is not read".into());
        }
        if !(feeds.plunge > 0.0) {
            return Err("the cycle's feed is not positive".into());
        }
        // Each plunge makes blocks: a plunging depth a thousand times too small is a typo (and
        // would take memory without bound).
        if n == 200 && h.plunge > 0.0 && crate::program::cycles::too_many_pecks(h.levels.depth, h.plunge) {
            return Err(format!("Q202={} makes more than {} plunges of a {} deep hole: a typo?", h.plunge / unit, crate::program::cycles::MAX_PECKS, -h.levels.depth / unit));
        }
        Ok((steps, feeds))
    }

    /// Cycle 1 PECKING's moves from where the tool stands along the tool axis (m) and its feed, or
    /// why it cannot run.
    fn pecking_moves(&self, unit: f64, start: f64) -> Result<(Vec<TncStep>, Feeds), String> {
        let v = match &self.pecking {
            Some(p) if p.values.len() == 5 => &p.values,
            _ => return Err("its definition is not complete".into()),
        };
        let (setup, depth, peck, dwell_s, feed) = (v[0], v[1], v[2], v[3], v[4]);
        // "The algebraic sign [of the total hole depth] determines the working direction"; the
        // set-up clearance and the pecking depth are distances.
        if depth >= 0.0 {
            return Err(format!("DEPTH {depth}: only a negative total hole depth (drilling towards -Z) is read"));
        }
        if peck == 0.0 {
            return Err("PECKG 0: a pecking depth of 0 never reaches the depth".into());
        }
        if !(dwell_s >= 0.0) {
            return Err(format!("DWELL {dwell_s}: a dwell must be 0 s or more"));
        }
        if !(feed > 0.0) {
            return Err(format!("F{feed}: the cycle's feed is not positive"));
        }
        let c = TncPecking { setup: setup.abs() * unit, depth: -depth * unit, peck: peck.abs() * unit, dwell_s };
        if c.pecks() > crate::program::cycles::MAX_PECKS as f64 {
            return Err(format!("PECKG {peck} makes more than {} pecks of a {} deep hole: a typo?", crate::program::cycles::MAX_PECKS, -depth));
        }
        Ok((tnc_pecking(start, &c), Feeds::one(feed)))
    }

    /// Run the cycle defined last where the tool stands, along the working plane's Z: its moves as
    /// blocks of this statement (the modal feed stays the program's).
    pub(super) fn call_cycle(&mut self, s: &Stmt<'_>, interp: &mut Interpreter, out: &mut Vec<Block>, diags: &mut Diags) {
        let Some((n, _)) = self.cycle else {
            match (self.refused_cycle, &self.pecking) {
                (Some((n, line)), _) => diags.error(s.line, s.col, format!("a call of CYCL DEF {n} (line {line}), which is not read")),
                (None, Some(p)) => diags.error(s.line, s.col, format!("a call of cycle 1 PECKING (line {}), whose definition is not complete", p.line)),
                (None, None) => diags.error(s.line, s.col, "a cycle call with no cycle defined before it (CYCL DEF)"),
            }
            return;
        };
        let unit = interp.unit();
        let moves = if n == 1 { self.pecking_moves(unit, interp.position()[2]) } else { self.drilling_moves(n, unit, interp.feed_unit()) };
        let (steps, feeds) = match moves {
            Ok(m) => m,
            Err(why) => {
                diags.error(s.line, s.col, format!("cycle {n} called: {why}"));
                return;
            }
        };
        let saved = interp.feed_state();
        // A move along the tool axis to `v` (m): rapid, or at `feed` (program units; infinite: MAX, rapid).
        let z = |v: f64, feed: Option<f64>| -> Vec<Word<'static>> {
            let feed = feed.filter(|f| f.is_finite());
            let motion = if feed.is_some() { "1" } else { "0" };
            let mut w = vec![
                Word { letter: 'G', value: if feed.is_some() { 1.0 } else { 0.0 }, raw: Cow::Owned(motion.to_string()), column: s.col, dimension: Dimension::Modal },
                Word { letter: 'Z', value: v / unit, raw: Cow::Owned(format!("{}", v / unit)), column: s.col, dimension: Dimension::Modal },
            ];
            if let Some(f) = feed {
                w.push(Word { letter: 'F', value: f, raw: Cow::Owned(format!("{f}")), column: s.col, dimension: Dimension::Modal });
            }
            w
        };
        for step in steps {
            let block = match step {
                TncStep::Rapid(v) => interp.block_one(&z(v, None), s.line, s.col, s.number, diags),
                TncStep::Feed(v, which) => interp.block_one(&z(v, Some(feeds.of(which))), s.line, s.col, s.number, diags),
                TncStep::Dwell(t) => Some(Block { dwell_s: Some(t), ..interp.still_block(s.line, s.col, s.number) }),
            };
            match block {
                Some(b) => out.push(b),
                None => break,
            }
        }
        interp.restore_feed(saved);
    }
}
