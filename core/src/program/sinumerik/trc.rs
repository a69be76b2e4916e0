//! The 840D's tool radius compensation (TRC) in the working plane G17: `G41`/`G42` to `G40` with
//! the active tool's radius, as Programming Manual Fundamentals (NC programming 12/2019,
//! 6FC5398-2EP40-0BA0, §2.10 "Tool radius compensation") gives it. With the reset settings its
//! path is the TNC's ([`crate::program::cutter_comp::TncComp`], whose geometry this reuses):
//! - selection and deselection in a `G0`/`G1` block; with `NORM` (the reset approach) "the tool
//!   travels directly on a straight line to the contour and is positioned perpendicular to the path
//!   tangent in the start point", and leaves the last element perpendicular at its end for `G40`'s
//!   programmed point (§2.10.2 "Approaching and leaving contour");
//! - outside corners with `G450` (the reset state): "the tool center point travels around the
//!   workpiece corner across an arc with tool radius" (§2.10.3), which belongs to the next travel
//!   command; inside corners at the intersection of the equidistant paths;
//! - the radius is the active tool's edge `D1` (the tool `M6` loaded): its radius in the tool table
//!   (`--tool-table`; `D0` none).
//!
//! What changes the path and is not read is refused where it stands: `KONT`/`KONTC`/`KONTT`
//! (approach round the start point), `G451` (outside corners at the equidistants' intersection),
//! `DISC` above 0, `OFFN` other than 0, a change of side without `G40`, G18/G19, TRAORI, and what
//! would move the contour's frame, machine or tool while compensation is on.

use crate::program::cutter_comp::{ArcFeed, Fail, Side, TncComp, ToolTable};
use crate::program::interp::Word;
use crate::program::lex::Diags;
use crate::program::{Block, Motion, Plane};

/// Blocks in a row without a move in the plane while compensation is on that the 840D takes:
/// machine datum MD20250 `CUTCOM_MAXNUM_DUMMY_BLOCKS`, whose default is 3; beyond, alarm 10762
/// ("Too many empty blocks between two traversing blocks with active tool radius compensation").
pub(super) const MAX_DUMMY_BLOCKS: usize = 3;

/// A tool as the program names it: `T5` or `T="MILL_D10"`.
#[derive(Debug, Clone, PartialEq)]
enum ToolRef {
    Number(u32),
    Name(std::sync::Arc<str>),
}

impl std::fmt::Display for ToolRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ToolRef::Number(n) => write!(f, "T{n}"),
            ToolRef::Name(n) => write!(f, "T=\"{n}\""),
        }
    }
}

/// What a block says to compensation, taken from its words before the interpreter reads them.
#[derive(Debug, Clone, Default)]
pub(super) struct Codes {
    /// `G40` (`None`), `G41` (left), `G42` (right), and its column.
    pub select: Option<(Option<Side>, usize)>,
    /// `G450` (false) or `G451` (true).
    pub corners: Option<bool>,
    /// `NORM` (true) or `KONT`/`KONTC`/`KONTT` (false, the name), and the column.
    pub approach: Option<(Option<&'static str>, usize)>,
    /// `G62`/`G621` (on) or `FENDNORM` (off): corner deceleration, which acts only under TRC.
    pub slow_corners: Option<bool>,
    /// `CFC`, `CFTCP`, `CFIN`: where the feed on arcs applies (G group 16).
    pub arc_feed: Option<ArcFeed>,
}

impl Codes {
    /// A G word compensation reads (the reader's G code numbers: `sinumerik_g`), taken.
    pub(super) fn g(&mut self, w: &Word<'_>) -> bool {
        match w.raw.as_ref() {
            "40" => self.select = Some((None, w.column)),
            "41" => self.select = Some((Some(Side::Left), w.column)),
            "42" => self.select = Some((Some(Side::Right), w.column)),
            "450" => self.corners = Some(false),
            "451" => self.corners = Some(true),
            "62" | "621" => self.slow_corners = Some(true),
            _ => return false,
        }
        true
    }

    /// A keyword compensation reads, taken.
    pub(super) fn keyword(&mut self, name: &str, col: usize) -> bool {
        match name {
            "NORM" => self.approach = Some((None, col)),
            "KONT" => self.approach = Some((Some("KONT"), col)),
            "KONTC" => self.approach = Some((Some("KONTC"), col)),
            "KONTT" => self.approach = Some((Some("KONTT"), col)),
            "FENDNORM" => self.slow_corners = Some(false),
            "CFC" => self.arc_feed = Some(ArcFeed::Edge),
            "CFTCP" => self.arc_feed = Some(ArcFeed::Centre),
            "CFIN" => self.arc_feed = Some(ArcFeed::EdgeInside),
            _ => return false,
        }
        true
    }
}

/// What a block may not change while compensation is on (or in the block that selects it, `on`
/// false): the work offset (G54-G57, G500, G505-G599, which the reader writes G54), the edge `D`
/// (the radius then changes over the block, which is not read), inverse-time feed; its column and
/// why.
pub(super) fn refused_while_on(words: &[Word<'_>], edge: Option<usize>, on: bool) -> Option<(usize, String)> {
    if let Some(w) = words.iter().find(|w| w.letter == 'G' && matches!(w.raw.as_ref(), "54" | "55" | "56" | "57")) {
        return Some((w.column, "a settable frame (G54-G57, G500, G505-G599) with tool radius compensation (G41/G42) on is not read: deselect it with G40 before".into()));
    }
    if let Some(w) = words.iter().find(|w| w.letter == 'G' && w.raw == "93") {
        return Some((w.column, "inverse-time feed (G93) with tool radius compensation (G41/G42) is not read (the transition circles' time is not given)".into()));
    }
    match edge {
        Some(c) if on => Some((c, "a tool edge D while tool radius compensation (G41/G42) is on is not read: the radius would change over the block (840Di sl Programming Manual 11/2006 p. 353)".into())),
        _ => None,
    }
}

/// The keywords [`Codes::keyword`] reads.
pub(super) const KEYWORDS: [&str; 8] = ["NORM", "KONT", "KONTC", "KONTT", "FENDNORM", "CFC", "CFTCP", "CFIN"];

/// Whether a keyword may stand in a block while compensation is on: it sets nothing of the
/// contour's frame, tool or machine (messages, acceleration and feed-forward modes, the
/// compressors, the orientation's settings, the contour tolerance).
pub(super) fn harmless(name: &str) -> bool {
    matches!(
        name,
        "MSG"
            | "SOFT"
            | "BRISK"
            | "FFWON"
            | "FFWOF"
            | "FNORM"
            | "COMPOF"
            | "COMPON"
            | "COMPCURV"
            | "COMPCAD"
            | "SETMS"
            | "ORIWKS"
            | "ORIVECT"
            | "ORIPLANE"
            | "ORIMKS"
            | "ORIAXES"
            | "ORIEULER"
            | "ORIRPY"
            | "CYCLE832"
            | "CUT2D"
            | "CDOF"
    )
}

/// Tool radius compensation's state beside the reader: the path held ([`TncComp`]) and the
/// settings, which a refused line takes back ([`Settings`]).
#[derive(Debug, Clone, Default)]
pub(super) struct Trc {
    pub(super) engine: TncComp,
    pub(super) set: Settings,
}

impl Trc {
    /// Compensation selected, or blocks still held.
    pub(super) fn busy(&self) -> bool {
        self.engine.busy()
    }

    /// The side in effect.
    pub(super) fn side(&self) -> Option<Side> {
        self.engine.side()
    }
}

/// The modal settings and the tool compensation reads, a few words: a line keeps a copy to take
/// back if it is refused.
#[derive(Debug, Clone)]
pub(super) struct Settings {
    /// G451 in effect (G450 is the reset state).
    intersection: bool,
    /// DISC's value (0 at reset).
    disc: f64,
    /// OFFN's value, in the program's unit (0 at reset).
    offn: f64,
    /// KONT, KONTC or KONTT in effect (NORM at reset).
    approach: Option<&'static str>,
    /// G62/G621 in effect.
    slow_corners: bool,
    /// Where the feed on arcs applies: on the contour (`CFC`, the reset state: G group 16's
    /// default, Programming Manual 12/2019 p. 1253, 840Di sl 11/2006 p. 484), at the tool centre
    /// (`CFTCP`), on inside arcs' contour only (`CFIN`) (Fundamentals 10.2004 §7.11).
    pub(super) arc_feed: ArcFeed,
    /// The tool `T` selected, and the one `M6` loaded.
    selected: Option<ToolRef>,
    active: Option<ToolRef>,
    /// The edge `D` (D1 at reset, D0: no offsets).
    edge: u32,
    /// Blocks in a row without a move in the plane while compensation is on.
    pub(super) dummies: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Settings { intersection: false, disc: 0.0, offn: 0.0, approach: None, slow_corners: false, arc_feed: ArcFeed::Edge, selected: None, active: None, edge: 1, dummies: 0 }
    }
}

impl Settings {
    /// A block's tool words: `T` selects, `M6` loads the selected tool, `D` the edge.
    pub(super) fn track(&mut self, words: &[Word<'_>], edge: Option<u32>) {
        if let Some(t) = words.iter().find(|w| w.letter == 'T') {
            self.selected = match t.raw.strip_prefix('"').and_then(|r| r.strip_suffix('"')) {
                Some(name) => Some(ToolRef::Name(name.into())),
                None if t.value >= 0.0 && t.value.fract() == 0.0 && t.value <= u32::MAX as f64 => Some(ToolRef::Number(t.value as u32)),
                None => None,
            };
        }
        if words.iter().any(|w| w.letter == 'M' && w.value == 6.0) {
            self.active = self.selected.clone();
        }
        if let Some(e) = edge {
            self.edge = e;
        }
    }

    /// The block's modal settings, kept; `disc` and `offn` as written (OFFN in the program's unit).
    pub(super) fn settle(&mut self, codes: &Codes, disc: Option<f64>, offn: Option<f64>) {
        if let Some(i) = codes.corners {
            self.intersection = i;
        }
        if let Some((a, _)) = codes.approach {
            self.approach = a;
        }
        if let Some(s) = codes.slow_corners {
            self.slow_corners = s;
        }
        if let Some(f) = codes.arc_feed {
            self.arc_feed = f;
        }
        if let Some(d) = disc {
            self.disc = d;
        }
        if let Some(o) = offn {
            self.offn = o;
        }
    }

    /// What of the settings in effect compensation does not read, at selection or while on.
    pub(super) fn unread_setting(&self) -> Option<String> {
        if self.intersection {
            return Some("G451 (outside corners at the intersection of the equidistant paths, the tool backing off at acute ones) is not read; G450 is".into());
        }
        if self.disc != 0.0 {
            return Some(format!("DISC={} (the transition circle at outside corners distorted towards the equidistants' intersection) is not read; DISC=0 is", self.disc));
        }
        if self.offn != 0.0 {
            return Some(format!("OFFN={} (the contour offset by an allowance) is not read; OFFN=0 is", self.offn));
        }
        if let Some(a) = self.approach {
            return Some(format!("{a} (the approach and retraction round the contour's start and end point) is not read; NORM is"));
        }
        if self.slow_corners {
            return Some("G62/G621 (the feed lowered at corners under compensation, by machine data) is not read: FENDNORM first".into());
        }
        None
    }

    /// The active tool's radius for `G41`/`G42` (m): its edge `D1`'s, the tool table's radius; `D0`
    /// none.
    pub(super) fn radius(&self, table: Option<&ToolTable>) -> Result<f64, String> {
        if self.edge == 0 {
            return Ok(0.0);
        }
        let Some(tool) = &self.active else {
            return Err(match &self.selected {
                Some(t) => format!("the radius is the active tool's, and {t} was selected without M6 loading it (a tool change on T alone, MD22550 TOOL_CHANGE_MODE 0, is not read)"),
                None => "the radius is the active tool's, and no tool was loaded (T and M6) before this block".into(),
            });
        };
        if self.edge != 1 {
            return Err(format!("D{}: the tool table gives one cutting edge per tool, D1's; {tool}'s edge D{} is not in it", self.edge, self.edge));
        }
        let table = table.ok_or_else(|| format!("the radius is {tool}'s in the tool table: give it with --tool-table (LinuxCNC's tool.tbl, or a TNC's TOOL.T, whose NAME column names tools)"))?;
        let d = match tool {
            ToolRef::Number(n) => table.diameter(*n).ok_or_else(|| format!("{tool} is not in the tool table"))?,
            ToolRef::Name(name) => table.diameter_by_name(name)?,
        };
        if d < 0.0 {
            return Err(format!("{tool}'s radius in the tool table is negative ({} mm): not read", d / 2.0 / crate::units::MM));
        }
        Ok(d / 2.0)
    }
}

/// A failure as the 840D reports it: where the tool cannot follow the contour the control either
/// stops (bottleneck detection, `CDON`) or looks for an intersection in earlier blocks (`CDOF`),
/// neither of which is read; what this reader does not read is said as it is.
pub(super) fn said(f: &Fail) -> String {
    match f {
        Fail::Contour(why) => {
            format!("{why}; the 840D then stops with an alarm or, under CDOF, cuts the contour short at an intersection with earlier blocks, which is not read: the program stops here")
        }
        Fail::NotRead(why) => why.clone(),
    }
}

/// Why the reader stops: compensation could not go on.
fn stop_message(why: &Fail) -> String {
    format!("tool radius compensation: {}", said(why))
}

impl super::SinumerikReader {
    /// A block while compensation is on, or the one that selects it: its checks, then its move
    /// through compensation. False (with an error) if the block is refused; a compensation that
    /// cannot go on stops the program ([`SinumerikReader::trc_stop`]).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn compensated(
        &mut self,
        words: &[Word<'_>],
        codes: &Codes,
        motion: Option<Motion>,
        machine_coords: bool,
        positions: bool,
        line: usize,
        col: usize,
        number: Option<u64>,
        out: &mut Vec<Block>,
        diags: &mut Diags,
    ) -> bool {
        let on = self.trc.side();
        let refuse = |diags: &mut Diags, c: usize, why: String| {
            diags.error(line, c, format!("tool radius compensation (G41/G42): {why}"));
            false
        };
        if self.interp.tcp() {
            return refuse(diags, col, "with TRAORI on (the tool's orientation free) it is not read: select it with TRAFOOF, as 2D compensation in the plane".into());
        }
        if machine_coords {
            return refuse(diags, col, "machine coordinates (G53, G153, SUPA) while it is on are not read".into());
        }
        if self.mcall.is_some() && positions {
            return refuse(diags, col, "a modal cycle call (MCALL) while it is on is not read".into());
        }
        if let Some(w) = words.iter().find(|w| w.letter == 'G' && matches!(w.raw.as_ref(), "17" | "18" | "19")) {
            if on.is_some() {
                return refuse(diags, w.column, format!("G{}: the plane cannot change while it is on (alarm 10757): deselect it with G40 first", w.raw));
            }
        }
        if super::plane_after(words, self.interp.plane()) != Plane::Xy {
            return refuse(diags, col, "in the plane G18 or G19 it is not read; in G17 it is".into());
        }
        if let Some(w) = words.iter().find(|w| matches!(w.letter, 'A' | 'B' | 'C')) {
            return refuse(diags, w.column, format!("{}: a rotary axis moving while it is on is not read (the contour's plane would turn)", w.letter));
        }
        if let Some(w) = words.iter().find(|w| w.letter == 'M' && w.value == 6.0) {
            return refuse(diags, w.column, "a tool change (M6) while it is on is not read: deselect it with G40 first".into());
        }
        let block_motion = words.iter().rev().find(|w| w.letter == 'G' && matches!(w.raw.as_ref(), "0" | "1" | "2" | "3")).map(|w| w.column);
        let xy = words.iter().any(|w| w.letter == 'X' || w.letter == 'Y');
        let unit = self.interp.unit();
        let tilt = self.interp.tilt();
        // Without TRAORI a frame that tilts the plane leaves compensation in the G17 plane of the
        // basic system (CUT2D, the reset state; CUT2DF, the frame's plane, is refused): not read.
        if self.interp.axes_frame().is_some_and(|r| (r * nalgebra::Vector3::z() - nalgebra::Vector3::z()).norm() > 1e-12) {
            return refuse(diags, col, "under a frame that tilts the plane without TRAORI (ROT/AROT about X or Y) it is not read (compensation stays in the basic system's G17 plane, CUT2D)".into());
        }
        match (on, codes.select) {
            (None, Some((Some(side), c))) => {
                if !matches!(motion, Some(Motion::Rapid | Motion::Linear)) {
                    return refuse(
                        diags,
                        c,
                        "it is selected in a G0 or G1 block (\"TRC can only be selected in a program block with G0 or G1\", 840D sl Function Manual W1 §\"Selecting TRC\")".into(),
                    );
                }
                if !xy {
                    return refuse(
                        diags,
                        c,
                        "a selection block without X or Y: with no axis of the plane \"no selection takes place\" there (Function Manual W1), and where it then does is not read".into(),
                    );
                }
                if let Some(why) = self.trc.set.unread_setting() {
                    return refuse(diags, c, why);
                }
                if self.interp.inverse_time() {
                    return refuse(diags, c, "with inverse-time feed (G93) it is not read (the transition circles' time is not given)".into());
                }
                let r = match self.trc.set.radius(self.interp.tool_table()) {
                    Ok(r) => r,
                    Err(why) => return refuse(diags, c, why),
                };
                let start = self.interp.position();
                let Some(b) = self.interp.block_one(words, line, col, number, diags) else {
                    return false;
                };
                let end = self.interp.position();
                // A corner before the selection, or asked for in it: the approach is no contour
                // element a corner joins (the element before it out as programmed).
                let held = self.corners.refuse_here("the block that selects compensation (G41/G42) is no contour element a corner joins", &mut self.corner_diags);
                self.emit_held(held, line, col, out, diags);
                self.trc.engine.start(side, r, [start[0], start[1], start[2]]);
                self.trc.set.dummies = 0;
                let fed = self.trc.engine.feed(b, start, end, unit, tilt, self.trc.set.arc_feed, out);
                self.trc_result(fed, line, col, diags)
            }
            (Some(now), Some((Some(side), c))) => {
                let why = if side != now {
                    "a change of side (G41 to G42 or back) without G40 between is not read: its manual text is not at hand"
                } else {
                    "G41/G42 again while it is on: what the 840D makes of a second selection is not at hand"
                };
                refuse(diags, c, why.into())
            }
            (Some(_), Some((None, c))) => {
                if !matches!(motion, Some(Motion::Rapid | Motion::Linear)) {
                    return refuse(diags, c, "G40 stands in a G0 or G1 block".into());
                }
                if !xy {
                    return refuse(diags, c, "a G40 block without X or Y: where the tool leaves the contour then is not read".into());
                }
                if let Some(why) = self.trc.set.unread_setting() {
                    return refuse(diags, c, why);
                }
                if self.trc.engine.entry_only() {
                    return refuse(diags, c, "G40 with no contour element since the selection: \"If tool radius compensation is deselected (G40) in the block following tool radius compensation selection, no selection takes place\" (Function Manual W1), which is not read".into());
                }
                let Some(b) = self.interp.block_one(words, line, col, number, diags) else {
                    return false;
                };
                let end = self.interp.position();
                // A corner before the deselection, or asked for in it: the retraction is no contour
                // element a corner joins.
                let held = self.corners.refuse_here("the block that deselects compensation (G40) is no contour element a corner joins", &mut self.corner_diags);
                if !self.emit_held(held, line, col, out, diags) {
                    return true;
                }
                let left = self.trc.engine.leave(b, end, unit, tilt, out);
                self.trc.set.dummies = 0;
                self.trc_result(left, line, col, diags)
            }
            _ => {
                if on.is_some() {
                    if let Some(why) = self.trc.set.unread_setting() {
                        return refuse(diags, col, why);
                    }
                    if motion == Some(Motion::Rapid) && positions {
                        return refuse(
                            diags,
                            block_motion.unwrap_or(col),
                            "a G0 move inside the compensated contour is not read: the transition circle's feed before a rapid is in no manual at hand (G40 first, or G1)".into(),
                        );
                    }
                }
                let start = self.interp.position();
                // The block that may be one empty block too many: the interpreter as it was, to take back.
                let before = (on.is_some() && self.trc.set.dummies >= MAX_DUMMY_BLOCKS).then(|| self.interp.clone());
                let Some(b) = self.interp.block_one(words, line, col, number, diags) else {
                    return false;
                };
                let end = self.interp.position();
                if on.is_some() && (end[0] - start[0]).hypot(end[1] - start[1]) == 0.0 && !self.dummy(line, col, diags) {
                    // Refused: the block's own state (its Z, its F) goes back too.
                    if let Some(before) = before {
                        self.interp = before;
                    }
                    return false;
                } else if on.is_some() && (end[0] - start[0]).hypot(end[1] - start[1]) != 0.0 {
                    self.trc.set.dummies = 0;
                }
                let returns = words.iter().any(|w| w.letter == 'M' && w.value == 17.0);
                let ends = words.iter().any(|w| w.letter == 'M' && (w.value == 2.0 || w.value == 30.0));
                // Chamfers and roundings of the contour before it is offset ([`super::corners`]).
                let h = crate::program::corner_cut::Held { b, start, end, unit, tilt, arc_feed: self.trc.set.arc_feed };
                let held = self.corners.compensated(h, start, &self.interp, ends || returns, &mut self.corner_diags);
                if !self.emit_held(held, line, col, out, diags) {
                    return true;
                }
                if ends {
                    // The program's end: the last element left perpendicular at its end point.
                    let stopped = self.trc.engine.stop(unit, tilt, out);
                    self.trc_result(stopped, line, col, diags);
                } else if returns {
                    self.returned = true;
                }
                true
            }
        }
    }

    /// A block without a move in the plane while compensation is on: counted, and refused past
    /// [`MAX_DUMMY_BLOCKS`] in a row ("A block with a path distance of zero also counts as an
    /// interruption", Programming Manual 840D sl 12/2019 p. 260). True if it may stand.
    pub(super) fn dummy(&mut self, line: usize, col: usize, diags: &mut Diags) -> bool {
        self.trc.set.dummies += 1;
        if self.trc.set.dummies > MAX_DUMMY_BLOCKS {
            diags.error(line, col, format!("tool radius compensation (G41/G42): more than {MAX_DUMMY_BLOCKS} blocks in a row without a move in the plane (machine data MD20250 CUTCOM_MAXNUM_DUMMY_BLOCKS, taken as {MAX_DUMMY_BLOCKS}; alarm 10762 \"Too many empty blocks\")"));
            return false;
        }
        true
    }

    /// Compensation's outcome: a failure stops the program there (true: it went on).
    pub(super) fn trc_result(&mut self, r: Result<(), Fail>, line: usize, col: usize, diags: &mut Diags) -> bool {
        match r {
            Ok(()) => true,
            Err(why) => {
                diags.error(line, col, stop_message(&why));
                self.trc.engine = TncComp::default();
                self.stopped = true;
                false
            }
        }
    }

    /// The program's input has ended with compensation on: the last element is left perpendicular
    /// at its end point and what is held goes out.
    pub(super) fn trc_end(&mut self, line: usize, out: &mut Vec<Block>, diags: &mut Diags) {
        if self.trc.busy() {
            let stopped = self.trc.engine.stop(self.interp.unit(), self.interp.tilt(), out);
            self.trc_result(stopped, line, 1, diags);
        }
    }
}
