//! Running one Klartext statement: its block for the interpreter, its parameters, its tilted plane
//! ([`super::tilt`]) or cycle ([`super::cycles`]), with the run-time state the TNC keeps between
//! blocks.

use std::borrow::Cow;
use std::collections::HashMap;

use super::corners::{Held, Pending, Stop};
use super::{axis_index, label, FeedWord, KWord, Kind, Shape, Stmt, Val};
use crate::machine::ContourTolerance;
use crate::program::interp::{Dimension, Interpreter, OneShot, Word};
use crate::program::cutter_comp::{Side, TncComp};
use crate::program::lex::Diags;
use crate::program::{Block, ProgrammedTolerance};
use crate::units::{DEG, MM};

/// What a preassigned Q parameter the program reads unset holds on the TNC (iTNC 530 user's manual
/// 340 49x-03 §11.11 "Preassigned Q Parameters"), said after the error.
fn preassigned(name: &str) -> &'static str {
    match name {
        "Q108" => " (Q108 is the TNC's: the active tool's radius R + DR, known here from --tool-table after a TOOL CALL of a tool in it)",
        "Q100" | "Q101" | "Q102" | "Q103" | "Q104" | "Q105" | "Q106" | "Q107" => " (the TNC's: a value from the machine's PLC, not known here)",
        "Q110" | "Q111" | "Q112" | "Q114" => " (the TNC's: the spindle, coolant, overlap factor or tool length, not known here)",
        "Q115" | "Q116" | "Q117" | "Q118" | "Q119" => " (the TNC's: a measurement of a touch probe cycle, not known here)",
        _ => "",
    }
}

/// Run-time state besides the interpreter's.
#[derive(Debug, Default)]
pub(super) struct Exec {
    pub(super) q: HashMap<String, f64>,
    /// Q parameters a cycle's parameters set to `MAX` (rapid traverse): no number, a feed only.
    pub(super) q_max: std::collections::HashSet<String>,
    /// The parameters written in the definition of the drilling cycle defined last (the Q
    /// assignments right after its `CYCL DEF`), with their values there (infinite: `MAX`): a
    /// cycle's optional parameter counts only if its definition writes it (another cycle's value,
    /// such as a maker's cycle's Q395, is not its), and one changed before the call is refused.
    pub(super) cycle_params: HashMap<String, f64>,
    /// The statements read since the last `CYCL DEF`, a drilling cycle's, are Q assignments: the
    /// next one is its parameter too.
    pub(super) collecting_params: bool,
    /// The machine, for tilted working planes (its kinematics and limits).
    pub(super) machine: Option<std::sync::Arc<crate::machine::Machine>>,
    /// The cycle defined last (CYCL DEF), which CYCL CALL, M99 and M89 run.
    pub(super) cycle: Option<(u32, usize)>,
    /// The cycle defined last when it is one not read (its number, line): what a call would run.
    pub(super) refused_cycle: Option<(u32, usize)>,
    /// The older cycle 1 PECKING being defined or defined last ([`super::cycles`]).
    pub(super) pecking: Option<Pecking>,
    /// M89: the cycle runs after every positioning block until M99 or CYCL CALL.
    pub(super) modal_call: bool,
    /// The spindle speed of the last TOOL CALL (1/min), for tapping.
    pub(super) spindle: Option<f64>,
    /// The feed of the last TOOL CALL (program units per minute, as written), for FAUTO.
    pub(super) tool_feed: Option<(f64, String)>,
    /// Direction of the contour at its end in the working plane, for CT.
    pub(super) tangent: Option<[f64; 2]>,
    /// The pole CC in the working plane (its two axes and coordinates, m), for LP and CP.
    pub(super) pole: Option<([usize; 2], [f64; 2])>,
    /// The tool of the last TOOL CALL by number, whose radius `RL`/`RR` compensates by.
    pub(super) tool: Option<u32>,
    /// The tool of the last TOOL CALL by name (`TOOL CALL "MILL_D10"`), looked up by the table's NAME.
    pub(super) tool_name: Option<String>,
    /// Radius compensation `RL`/`RR` ([`TncComp`]).
    pub(super) comp: TncComp,
    /// The last contour element, placed once the statement after it shows it is no corner's
    /// ([`super::corners`]).
    pub(super) held: Option<Held>,
    /// An `RND` or `CHF` waiting for the element after it.
    pub(super) pending: Option<Pending>,
    /// Blocks that move nothing (a pole) read after the held element, to go out behind it.
    pub(super) trailing: Vec<Held>,
    /// A cycle 7 value of 0 read in a tilted plane while other axes' shifts stand (its line and
    /// column): read only if the cycle ends with no shift at all (hyperMILL's reset of X, Y and Z).
    pub(super) zeroed_tilted: Option<(usize, usize)>,
}

/// The older cycle 1 PECKING as its blocks `CYCL DEF 1.0` to `1.5` give it: where it begins, its
/// values so far (program unit, s, per minute), and the line of a part refused, which leaves it
/// undefined.
#[derive(Debug, Clone, Default)]
pub(super) struct Pecking {
    pub(super) line: usize,
    pub(super) values: Vec<f64>,
    pub(super) refused: Option<usize>,
}

impl Exec {
    /// Why a parameter read has no value, beyond its not being set: the TNC's own, or a cycle's MAX.
    fn unset_hint(&self, name: &str) -> &'static str {
        if self.q_max.contains(name) {
            " (a cycle's parameters set it to MAX, rapid traverse: a feed, not a number)"
        } else {
            preassigned(name)
        }
    }

    /// A formula's value with the parameters set so far; a defect goes to `diags`.
    pub(super) fn formula(&self, text: &str, line: usize, col: usize, diags: &mut Diags) -> Option<f64> {
        match super::formula::eval(text, &|n| self.q.get(n).copied()) {
            Ok(v) => Some(v),
            Err(e) => {
                let hint = e.unset.as_deref().map_or("", |n| self.unset_hint(n));
                diags.error(line, col, format!("'{}': {}{hint}", crate::program::lex::excerpt(text), e.message));
                None
            }
        }
    }

    /// `TOOL CALL`: the preassigned Q108, the active tool's radius "calculated from: Tool radius R
    /// (Tool table ...), Delta value DR from the tool table, Delta value DR from the TOOL CALL block"
    /// (a delta there other than 0 is refused where it is read), in the program's unit; Q109, the
    /// tool axis, 2 for Z (iTNC 530 user's manual 340 49x-03 §11.11). Without the radius in a
    /// `--tool-table`, Q108 is left unset, and a use of it says why.
    fn preassign_tool(&mut self, interp: &Interpreter) {
        self.q.insert("Q109".into(), 2.0);
        match self.called_tool(interp) {
            Ok((_, d)) => self.q.insert("Q108".into(), d / 2.0 / interp.unit()),
            Err(_) => self.q.remove("Q108"),
        };
    }

    pub(super) fn value(&self, w: &KWord<'_>, line: usize, diags: &mut Diags) -> Option<f64> {
        match &w.val {
            Val::Num(v) => Some(*v),
            Val::Q { name, negative } => match self.q.get(*name) {
                Some(v) => Some(if *negative { -v } else { *v }),
                None => {
                    diags.error(line, w.col, format!("{}: {name} is used before it is set{}", w.addr, self.unset_hint(name)));
                    None
                }
            },
        }
    }

    /// Run one statement, its block to `out`; true if it ends the program (M2, M30). Called through
    /// [`Exec::run`], which holds contour elements for the corners between them.
    pub(super) fn step<'a>(&mut self, s: &Stmt<'a>, interp: &mut Interpreter, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        let unit = interp.unit();
        // A drilling cycle's parameters are the Q assignments right after its CYCL DEF.
        if !matches!(s.kind, Kind::Assign { .. } | Kind::AssignMax { .. } | Kind::CycleDef(_)) {
            self.collecting_params = false;
        }
        // The cycle 7 before this statement set some axes to 0 in a tilted plane and left a shift:
        // whether the TNC zeroes those axes in the tilted system or the workpiece's is not read.
        if !matches!(s.kind, Kind::Datum(..)) {
            if let Some((line, col)) = self.zeroed_tilted.take().filter(|_| interp.datum() != [0.0; 3]) {
                diags.error(line, col, "CYCL DEF 7 of 0 in a tilted working plane leaving a shift on other axes: which system's axes it zeroes is not read (reset X, Y and Z together, or before the PLANE)");
            }
        }
        // The block that starts RL/RR is held with the compensated ones: what cannot run among them
        // cannot run in it either.
        let starts_comp = matches!(&s.kind, Kind::Move { comp: Some((Some(_), _)), .. }) && self.comp.side().is_none();
        if starts_comp && interp.tcp() {
            diags.error(s.line, s.col, "radius compensation RL/RR under M128 / FUNCTION TCPM is not read: reset it first (M129, FUNCTION RESET TCPM)");
            diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
            return false;
        }
        if self.comp.busy() || starts_comp {
            let what = match &s.kind {
                // A cycle called after each move (M89) would drill before the held moves run (the R0
                // block lets them all out first).
                Kind::Move { comp, .. } if self.modal_call && !matches!(comp, Some((None, _))) => Some("a move with the modal cycle call M89 in force"),
                Kind::Plane(_) => Some("a working plane (PLANE, cycle 19)"),
                Kind::Datum(..) => Some("a datum shift (cycle 7)"),
                Kind::Tool { .. } => Some("TOOL CALL"),
                Kind::Retract { .. } => Some("M140"),
                Kind::CycleCall(_) => Some("a cycle call"),
                Kind::Tcp { .. } => Some("FUNCTION TCPM"),
                Kind::Spline { .. } => Some("a spline (SPL)"),
                Kind::Move { m, .. } | Kind::Misc(m) => m.iter().find_map(|w| match w.val {
                    Val::Num(v) if v == 91.0 || v == 92.0 => Some("M91/M92 machine coordinates"),
                    Val::Num(v) if v == 99.0 || v == 89.0 => Some("a cycle call (M99/M89)"),
                    Val::Num(v) if v == 128.0 => Some("M128"),
                    _ => None,
                }),
                _ => None,
            };
            if let Some(what) = what {
                diags.error(s.line, s.col, format!("{what} with radius compensation RL/RR on is not read: end the compensation with an R0 block before it"));
                diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
                return false;
            }
        }
        // Statements that set state and run no block.
        match &s.kind {
            Kind::Assign { name, formula } => {
                match self.formula(formula, s.line, s.col, diags) {
                    Some(v) => {
                        self.q.insert(name.clone(), v);
                        self.q_max.remove(name);
                        // The first value the definition's lines give: a second assignment
                        // after them is a change its call sees ([`Exec::cycle_value`]).
                        if self.collecting_params {
                            self.cycle_params.entry(name.clone()).or_insert(v);
                        }
                    }
                    None => diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line))),
                }
                return false;
            }
            Kind::AssignMax { name } => {
                self.q.remove(name);
                self.q_max.insert(name.clone());
                if self.collecting_params {
                    self.cycle_params.entry(name.clone()).or_insert(f64::INFINITY);
                }
                return false;
            }
            Kind::Tolerance { linear, rotary, reset } => {
                let mut tolerance = if *reset { ProgrammedTolerance::default() } else { interp.tolerance() };
                let max = ContourTolerance::MAX;
                // Each part written: its value in SI (from the program's unit, or deg), within 0..=max.
                let parts: [(_, _, _, _, _, _, fn(f64) -> bool); 2] = [
                    (linear, "32.1 T", unit, max.linear_m, MM, "mm", ContourTolerance::linear_ok),
                    (rotary, "32.2 TA", DEG, max.rotary_rad, DEG, "deg", ContourTolerance::rotary_ok),
                ];
                let [l, r] = parts.map(|(w, name, to_si, max, shown, shown_name, ok)| {
                    let w = w.as_ref()?;
                    let v = self.value(w, s.line, diags)? * to_si;
                    if !ok(v) {
                        diags.error(s.line, w.col, format!("CYCL DEF {name}: {} {shown_name} is outside 0 to {} {shown_name}", v / shown, max / shown));
                        return None;
                    }
                    Some(v)
                });
                tolerance.linear_m = l.or(tolerance.linear_m);
                tolerance.rotary_rad = r.or(tolerance.rotary_rad);
                interp.set_tolerance(tolerance);
                return false;
            }
            Kind::Tcp { on, orientation } => {
                interp.set_tcp(*on);
                if let Some(o) = orientation {
                    interp.set_orientation(*o);
                }
                return false;
            }
            // With no datum shift in effect there is nothing to reset; with cycle 7's, whether this
            // resets it too is not at hand.
            Kind::TransReset => {
                if interp.datum() != [0.0; 3] {
                    diags.error(s.line, s.col, "TRANS DATUM RESET with cycle 7's datum shift in effect: whether it resets that shift too is not at hand (reset it with CYCL DEF 7 X+0 Y+0 Z+0 first)");
                }
                return false;
            }
            Kind::Datum(k, w, incremental) => {
                if let Some(v) = self.value(w, s.line, diags) {
                    // Programmed in a tilted plane, a datum shift acts in the tilted system (TNC 320
                    // Conversational User's Manual 9/2016 p.108, "Transformations in the working plane
                    // coordinate system": cycle 7 among them): shifts here are in the workpiece's. A
                    // shift to 0 is the same in either.
                    let tilted = interp.tilt().is_some_and(|r| (r - nalgebra::Matrix3::identity()).abs().max() > 1e-12);
                    if tilted && v != 0.0 {
                        diags.error(s.line, w.col, format!("CYCL DEF 7 {}{}: a datum shift programmed in a tilted working plane acts in the tilted system, which is not read (shift the datum before the PLANE or cycle 19)", w.addr, w.raw));
                        return false;
                    }
                    if tilted && self.zeroed_tilted.is_none() {
                        self.zeroed_tilted = Some((s.line, w.col));
                    }
                    let mut datum = interp.datum();
                    datum[*k] = if *incremental { datum[*k] + v * unit } else { v * unit };
                    interp.set_datum(datum);
                }
                return false;
            }
            Kind::Plane(p) => {
                // The TNC refuses a plane before it moves: a refused plane leaves no retract either.
                let (start, before) = (out.len(), diags.errors());
                let saved = p.retract.is_some().then(|| interp.clone());
                if let Some((distance, col)) = &p.retract {
                    // MB: M140's retract at the plane's feed, then the plane; a refused retract tilts nothing.
                    let retract = Stmt { line: s.line, col: s.col, number: s.number, kind: Kind::Retract { distance: distance.clone(), feed: p.feed.clone(), col: *col } };
                    self.run(&retract, interp, out, diags);
                    if diags.errors() > before {
                        diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
                        return false;
                    }
                }
                self.plane(p, s, interp, out, diags);
                if let (Some(saved), true) = (saved, diags.errors() > before) {
                    out.truncate(start);
                    *interp = saved;
                    diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
                }
                return false;
            }
            Kind::CycleDef(n) => {
                self.define_cycle(*n, s, interp, diags);
                return false;
            }
            Kind::Pecking { part, value } => {
                self.define_pecking(*part, value.as_ref(), s, diags);
                return false;
            }
            Kind::CycleCall(m) => {
                self.modal_call = false;
                if !m.is_empty() {
                    // Its M functions first (they act at the block's start), as an M block would.
                    let misc = Stmt { line: s.line, col: s.col, number: s.number, kind: Kind::Misc(m.clone()) };
                    if self.run(&misc, interp, out, diags) {
                        return true;
                    }
                }
                self.call_cycle(s, interp, out, diags);
                return false;
            }
            Kind::End | Kind::Label(_) | Kind::Call { .. } | Kind::Jump { .. } | Kind::Corner { .. } => return false,
            Kind::Spline { .. } => return self.spline(s, interp, out, diags),
            _ => {}
        }
        let before = diags.errors();
        let mut words: Vec<Word<'a>> = Vec::with_capacity(12);
        let word = |letter: char, value: f64, raw: Cow<'a, str>, column: usize, incremental: bool| Word { letter, value, raw, column, dimension: if incremental { Dimension::Incremental } else { Dimension::Modal } };
        let mut ends = false;
        let mut vector = None;
        match &s.kind {
            Kind::Stop => words.push(word('M', 0.0, "0".into(), s.col, false)),
            // The interpreter reads a TNC dwell as G04 F, s.
            Kind::Dwell(w) => {
                if let Some(v) = self.value(w, s.line, diags) {
                    words.push(word('G', 4.0, "04".into(), s.col, false));
                    words.push(word('F', v, w.raw.into(), w.col, false));
                }
            }
            Kind::Tool { events, feed } => {
                // The tool by number (`TOOL CALL 5`) or by name (`TOOL CALL "NAME"`, the table's NAME
                // column). A call without a tool (`TOOL CALL Z S5000`: a new speed) keeps the one in
                // the spindle.
                if let Some(t) = events.iter().find_map(|e| e.strip_prefix('T')) {
                    self.tool = t.parse::<u32>().ok();
                    self.tool_name = t.strip_prefix('"').map(|n| n.trim_end_matches('"').to_string());
                    self.preassign_tool(interp);
                }
                if let Some(sp) = events.iter().find_map(|e| e.strip_prefix('S')) {
                    self.spindle = super::parse_val(sp).and_then(|v| match v {
                        Val::Num(n) => Some(n),
                        Val::Q { name, negative } => self.q.get(name).map(|v| if negative { -v } else { *v }),
                    });
                }
                for e in events {
                    let (l, rest) = e.split_at(1);
                    words.push(word(l.chars().next().unwrap_or('T'), 0.0, rest.to_string().into(), s.col, false));
                }
                if let Some(f) = feed {
                    self.tool_feed = self.value(f, s.line, diags).map(|v| (v, f.raw.to_string()));
                }
            }
            Kind::Misc(m) => ends = self.m_words(m, &mut words, s.line, diags),
            Kind::Retract { distance, feed, col } => {
                let d = match distance {
                    Some(w) => self.value(w, s.line, diags).map(|v| Some(v * unit)),
                    None => Some(None),
                };
                if let Some(d) = d {
                    match interp.retract_target(d) {
                        Ok(axes) => {
                            // A move of the axes themselves (origin zero), as M91's are of the machine's.
                            // Without F (or with FMAX) at rapid traverse.
                            let motion = if matches!(feed, FeedWord::Value(_)) { crate::program::Motion::Linear } else { crate::program::Motion::Rapid };
                            interp.oneshot = Some(OneShot { motion, absolute: true, axes: Some([0.0; 3]), own: true });
                            for (k, letter) in ['X', 'Y', 'Z'].into_iter().enumerate() {
                                words.push(word(letter, axes[k] / unit, format!("{}", axes[k] / unit).into(), *col, false));
                            }
                            if let FeedWord::Value(f) = feed {
                                if let Some(v) = self.value(f, s.line, diags) {
                                    words.push(word('F', v, f.raw.into(), f.col, false));
                                }
                            }
                        }
                        Err(why) => diags.error(s.line, *col, format!("M140: {why}")),
                    }
                }
            }
            Kind::Centre(axes) => {
                let pos = interp.position();
                let (a0, a1, _) = interp.plane().axes();
                let mut c = [pos[a0], pos[a1]];
                for w in axes {
                    let k = axis_index(w.addr);
                    let Some(v) = self.value(w, s.line, diags) else { continue };
                    let incremental = w.addr.starts_with('I');
                    let slot = if k == a0 {
                        0
                    } else if k == a1 {
                        1
                    } else {
                        diags.error(
                            s.line,
                            w.col,
                            format!(
                                "CC {}: not an axis of the working plane ({}{}, from the TOOL CALL's axis): \"the TNC assigns a circle to one of the main planes\", \"defined when you set the spindle axis during TOOL CALL\" (TNC 425/415 B/407 user's manual §5, Circles in the main planes)",
                                w.addr,
                                ['X', 'Y', 'Z'][a0],
                                ['X', 'Y', 'Z'][a1]
                            ),
                        );
                        continue;
                    };
                    c[slot] = if incremental { pos[k] + v * unit } else { v * unit };
                }
                for (slot, k) in [a0, a1].into_iter().enumerate() {
                    words.push(word(['I', 'J', 'K'][k], c[slot] / unit, format!("{}", c[slot] / unit).into(), s.col, false));
                }
                self.pole = Some(([a0, a1], c));
            }
            Kind::Move { shape, axes, ccw, radius, feed, m, .. } => {
                let mut tool = [None; 3];
                let mut normal = [None; 3];
                if matches!(shape, Shape::LinePolar | Shape::CirclePolar) {
                    match self.polar(*shape, axes, *ccw, interp, s, diags) {
                        Some((end, turns)) => {
                            let (a0, a1, _) = interp.plane().axes();
                            for (k, v) in [(a0, end[0]), (a1, end[1])] {
                                words.push(word(['X', 'Y', 'Z'][k], v / unit, format!("{}", v / unit).into(), s.col, false));
                            }
                            if turns > 1 {
                                words.push(word('P', turns as f64, format!("{turns}").into(), s.col, false));
                            }
                        }
                        None => return false,
                    }
                }
                for w in axes.iter().filter(|w| !w.addr.ends_with("PR") && !w.addr.ends_with("PA")) {
                    let Some(v) = self.value(w, s.line, diags) else { continue };
                    match w.addr.as_bytes()[0] {
                        b'N' => normal[axis_index(w.addr)] = Some(v),
                        b'T' => tool[axis_index(w.addr)] = Some(v),
                        _ => {
                            let letter = w.addr.as_bytes()[w.addr.len() - 1] as char;
                            words.push(word(letter, v, w.raw.into(), w.col, w.addr.len() == 2))
                        }
                    }
                }
                ends = self.m_words(m, &mut words, s.line, diags);
                let g = match (shape, feed) {
                    (Shape::Line | Shape::LineNormal | Shape::LinePolar, FeedWord::Max) => "0",
                    (Shape::Line | Shape::LineNormal | Shape::LinePolar, _) => "1",
                    (Shape::Circle | Shape::CircleRadius | Shape::CirclePolar, _) if *ccw == Some(true) => "3",
                    (Shape::Circle | Shape::CircleRadius | Shape::CirclePolar, _) => "2",
                    (Shape::CircleTangent, _) => match self.tangent_arc(&words, interp, s, diags) {
                        Some((g, r)) => {
                            words.push(word('R', r, format!("{r}").into(), s.col, false));
                            g
                        }
                        None => "1",
                    },
                };
                words.push(word('G', if g == "0" { 0.0 } else { g.parse().unwrap_or(1.0) }, g.into(), s.col, false));
                if let Some(r) = radius {
                    if let Some(v) = self.value(r, s.line, diags) {
                        words.push(word('R', v, r.raw.into(), r.col, false));
                    }
                }
                if let Ok(Some((v, raw, col))) = self.feed_word(feed, s.line, diags) {
                    words.push(word('F', v, raw, col, false));
                }
                if *shape == Shape::LineNormal {
                    // The TNC moves an LN block's tool along the surface normal by the sum of its
                    // delta values (TNC 640 User's Manual 34059x-02, "3-D compensation without TCPM"):
                    // the tool table's DR or DR2 not 0 for the called tool is an offset not read.
                    if let Some(table) = interp.tool_table() {
                        let numbers: Vec<u32> = match (self.tool, self.tool_name.as_deref()) {
                            (Some(t), _) => vec![t],
                            (None, Some(name)) => table.numbers_named(name).collect(),
                            (None, None) => Vec::new(),
                        };
                        if let Some((t, (dr, dr2))) = numbers.iter().find_map(|&t| table.radius_deltas(t).map(|d| (t, d))) {
                            diags.error(
                                s.line,
                                s.col,
                                format!(
                                    "LN with tool {t}'s deltas DR {:.4} and DR2 {:.4} mm in the tool table: the TNC moves the tool along the surface normal by its delta values (3-D compensation), which is not read",
                                    dr / crate::units::MM,
                                    dr2 / crate::units::MM
                                ),
                            );
                            return false;
                        }
                    }
                    let full = |v: [Option<f64>; 3]| -> Option<[f64; 3]> { Some([v[0]?, v[1]?, v[2]?]) };
                    let m128 = m.iter().any(|w| w.val == Val::Num(128.0));
                    let t = full(tool);
                    if interp.tcp() || m128 {
                        // Under TCPM the tool keeps the orientation T, or without T stands on the normal.
                        let given = if t.is_some() { "TX TY TZ" } else { "NX NY NZ" };
                        if let Some(v) = t.or_else(|| full(normal)) {
                            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                            if n > 1e-9 && n.is_finite() {
                                vector = Some(v.map(|c| c / n));
                            } else {
                                diags.error(s.line, s.col, format!("LN: the vector {given} has zero length: expected a direction"));
                            }
                        }
                    } else if t.is_some() {
                        diags.warning(
                            s.line,
                            s.col,
                            "LN with TX TY TZ but neither M128 nor FUNCTION TCPM: the TNC ignores the tool vector, and so does this reader",
                        );
                    }
                }
            }
            Kind::Assign { .. } | Kind::AssignMax { .. } | Kind::Tcp { .. } | Kind::Tolerance { .. } | Kind::Datum(..) | Kind::TransReset | Kind::End | Kind::Label(_) | Kind::Call { .. } | Kind::Jump { .. } | Kind::Plane(_) | Kind::CycleDef(_) | Kind::Pecking { .. } | Kind::CycleCall(_) | Kind::Corner { .. } | Kind::Spline { .. } => {}
        }
        // M91 / M92: the block's coordinates are the machine's, about its machine datum or the
        // maker's second datum (TNC 426 B ISO §7.3: "M91 and M92 are effective only in the blocks in
        // which they are programmed"; the tool length is not compensated, so they place the axes).
        if let Kind::Move { shape, m, feed, .. } = &s.kind {
            let code = m.iter().find_map(|w| match w.val {
                Val::Num(v) if v == 91.0 || v == 92.0 => Some((v as u32, w.col)),
                _ => None,
            });
            if let Some((code, col)) = code {
                match self.machine_axes(code, interp, *shape, words.iter().any(|w| w.dimension == Dimension::Incremental)) {
                    Ok(origin) => {
                        let motion = if matches!(feed, FeedWord::Max) { crate::program::Motion::Rapid } else { crate::program::Motion::Linear };
                        interp.oneshot = Some(OneShot { motion, absolute: true, axes: Some(origin), own: false });
                    }
                    Err(why) => diags.error(s.line, col, format!("M{code}: {why}")),
                }
            }
        }
        if diags.errors() > before {
            diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
            return false;
        }
        if let Some(v) = vector {
            // In a tilted plane, whether the TNC reads LN's vector in the plane or the workpiece is
            // not at hand.
            if interp.tilt().is_some_and(|r| (r - nalgebra::Matrix3::identity()).abs().max() > 1e-12) {
                diags.error(s.line, s.col, "LN's tool vector in a tilted working plane: whether the TNC takes it in the plane's coordinates or the workpiece's is not read");
                return false;
            }
            interp.set_pending_vector(v);
        }
        // M99 runs the cycle at the block's end point; M89 too, and from there on after every
        // positioning block (TNC 306/406 Technical Manual §7.4, MP7440 bit 1: "Modal cycle-call M89
        // at end of block"; TNC 155: "effective at the end of the appropriate block as a modal" call).
        let (m99, m89) = match &s.kind {
            Kind::Move { m, .. } | Kind::Misc(m) => (m.iter().any(|w| w.val == Val::Num(99.0)), m.iter().any(|w| w.val == Val::Num(89.0))),
            _ => (false, false),
        };
        if m99 || m89 {
            words.retain(|w| !(w.letter == 'M' && (w.value == 99.0 || w.value == 89.0)));
        }
        // RL/RR from R0: the radius is the called tool's, known before the block runs.
        let comp_word = match &s.kind {
            Kind::Move { comp: Some((side, col)), shape, .. } => Some((*side, *col, *shape)),
            _ => None,
        };
        if let Some((None, col, shape)) = comp_word {
            if self.comp.side().is_some() && !matches!(shape, Shape::Line | Shape::LinePolar) {
                diags.error(s.line, col, "R0 in a circle block: compensation ends here in a straight-line block (L) only (an arc from the compensated point to the programmed one is no circle)");
                diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
                return false;
            }
        }
        let mut starting = None;
        if let Some((Some(left), col, shape)) = comp_word {
            let side = if left { Side::Left } else { Side::Right };
            match self.comp.side() {
                Some(now) if now != side => {
                    diags.error(s.line, col, "RL and RR without a block between them: \"Between two program blocks with different radius compensations you must program at least one traversing block in the working plane without radius compensation\" (TNC 620 ISO user's manual, p. 146), an R0 block");
                    diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
                    return false;
                }
                Some(_) => {}
                None => match self.comp_radius(shape, interp) {
                    Ok(r) => starting = Some((side, r)),
                    Err(why) => {
                        diags.error(s.line, col, format!("{}: {why}", if left { "RL" } else { "RR" }));
                        diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
                        return false;
                    }
                },
            }
        }
        let (start, placed) = (interp.position(), interp.placed);
        let result = interp.block_one(&words, s.line, s.col, s.number, diags);
        match result {
            Some(b) => {
                let end = interp.position();
                self.follow(&b, start, placed, end, interp);
                let moved = !b.targets.is_empty();
                if let Some((side, r)) = starting {
                    self.comp.start(side, r, [start[0], start[1], start[2]]);
                }
                let r0 = matches!(comp_word, Some((None, _, _))) && self.comp.side().is_some();
                let placed = if r0 {
                    // R0: the tool leaves the last element perpendicular to it, for the programmed point.
                    self.comp.leave(b, end, unit, interp.tilt(), out).map_err(|why| Stop { line: s.line, col: s.col, why })
                } else {
                    // A contour element at a feed is held while the statement after it may be an
                    // RND or CHF that cuts its end ([`super::corners`]).
                    let element = matches!(b.motion, crate::program::Motion::Linear | crate::program::Motion::ArcCw | crate::program::Motion::ArcCcw)
                        && moved
                        && starting.is_none()
                        && super::corners::not_an_element(&s.kind, true).is_none()
                        && !(self.modal_call || ends);
                    let h = Held { b, start, end, unit, tilt: interp.tilt(), arc_feed: interp.arc_feed() };
                    self.join(h, element, interp, out, diags)
                };
                if let Err(stop) = placed {
                    self.stopped(&stop, diags, interp);
                    return true;
                }
                if m89 {
                    self.modal_call = true;
                }
                if m99 {
                    self.modal_call = false;
                }
                if m99 || m89 || (self.modal_call && moved) {
                    self.call_cycle(s, interp, out, diags);
                }
                ends
            }
            None => {
                diags.warning(s.line, s.col, format!("block {} not used", label(s.number, s.line)));
                false
            }
        }
    }

    /// The compensation value `RL`/`RR` start with: the radius of the tool called last, from the
    /// tool table (the TNC's "R + DR_TAB + DR_Prog", TNC 620 Klartext user's manual 01/2022 p. 134;
    /// a program delta other than 0 is refused where TOOL CALL is read), m.
    fn comp_radius(&self, shape: Shape, interp: &Interpreter) -> Result<f64, String> {
        if !matches!(shape, Shape::Line | Shape::LinePolar) {
            return Err("\"You cannot activate radius compensation in a circle block. Activate it beforehand in a straight-line block\" (TNC 620 ISO user's manual, p. 154)".into());
        }
        let (who, d) = self.called_tool(interp)?;
        crate::program::cutter_comp::tnc_radius(&who, d)
    }

    /// The tool of the last TOOL CALL, by number or by name (`TOOL CALL "MILL_D10"`, the table's
    /// NAME column), as messages name it, and its diameter 2 (R + DR) in the tool table, m; why not.
    fn called_tool(&self, interp: &Interpreter) -> Result<(String, f64), String> {
        match (self.tool, self.tool_name.as_deref()) {
            (Some(tool), _) => Ok((format!("tool {tool}"), crate::program::cutter_comp::tnc_diameter(interp.tool_table(), tool)?)),
            (None, Some(name)) => {
                let table = interp.tool_table().ok_or_else(|| format!("the radius is tool \"{name}\"'s in the tool table: give it with --tool-table (the TNC's TOOL.T, with its NAME column)"))?;
                Ok((format!("tool \"{name}\""), table.diameter_by_name(name)?))
            }
            (None, None) => Err("the radius is the called tool's, and no TOOL CALL by number or name comes before this block".into()),
        }
    }

    /// `LP` and `CP` (iTNC 530 user's manual §6.5 "Path contours—Polar coordinates"): the end point in
    /// the working plane from the pole CC, the polar radius PR (CP: the start's distance to the pole)
    /// and angle PA from the plane's reference axis (X in XY, Y in YZ, Z in ZX), IPR and IPA from
    /// the start's, an LP's radius or angle left out the start's; and a CP's turns (P of its arc:
    /// `IPA+720` is two). A plane axis written beside them, a pole of another plane, a CP whose IPA and DR differ in sign ("Define the same algebraic
    /// sign for the direction of rotation DR and the incremental total angle IPA. The tool may
    /// otherwise move on a wrong path", TNC7 user's manual, Programming a helix) are refused.
    pub(super) fn polar(&self, shape: Shape, axes: &[KWord<'_>], ccw: Option<bool>, interp: &Interpreter, s: &Stmt<'_>, diags: &mut Diags) -> Option<([f64; 2], u64)> {
        let (a0, a1, _) = interp.plane().axes();
        let key = if shape == Shape::LinePolar { "LP" } else { "CP" };
        let Some((_, pole)) = self.pole.filter(|(axes, _)| *axes == [a0, a1]) else {
            diags.error(s.line, s.col, format!("{key}: no pole CC in the working plane before it"));
            return None;
        };
        // A linear word of the working plane (X, Y, Z or IX ...; not the rotary A B C, nor LN's N and T).
        let linear = |a: &str| a.ends_with(['X', 'Y', 'Z']) && !a.starts_with(['N', 'T']);
        if let Some(w) = axes.iter().find(|w| linear(w.addr) && [a0, a1].contains(&axis_index(w.addr))) {
            diags.error(s.line, w.col, format!("{key} with {}: the end point in the working plane is the polar one", w.addr));
            return None;
        }
        let unit = interp.unit();
        let pos = interp.position();
        let (d0, d1) = (pos[a0] - pole[0], pos[a1] - pole[1]);
        let (r_start, pa_start) = (d0.hypot(d1), d1.atan2(d0).to_degrees());
        let mut get = |name: &str| axes.iter().find(|w| w.addr == name).and_then(|w| self.value(w, s.line, diags));
        let (pr, ipr, pa, ipa) = (get("PR"), get("IPR"), get("PA"), get("IPA"));
        let r = match (pr, ipr) {
            (Some(v), _) => v * unit,
            (_, Some(v)) => r_start + v * unit,
            _ => r_start,
        };
        let (pa, turns) = match (pa, ipa) {
            (Some(v), _) => (v, 1),
            (_, Some(v)) => {
                if shape == Shape::CirclePolar && v != 0.0 && (v > 0.0) != (ccw == Some(true)) {
                    diags.error(s.line, s.col, format!("CP IPA{v:+} with DR{}: the TNC wants the same sign for both, or the tool may move on a wrong path", if ccw == Some(true) { "+" } else { "-" }));
                    return None;
                }
                // The TNC's input range of a helix's total angle (TNC 640 User's Manual DIN/ISO 1/2015
                // §19.3 "Input format and unit of TNC functions": "Polar coordinate angle for helical
                // interpolation (CP) -5 400.0000 to 5 400.0000" deg, 15 turns).
                if shape == Shape::CirclePolar && v.abs() > 5400.0 {
                    let col = axes.iter().find(|w| w.addr == "IPA").map_or(s.col, |w| w.col);
                    diags.error(s.line, col, format!("IPA{v:+}: beyond the TNC's input range of a helix's angle, -5400 to +5400 deg"));
                    return None;
                }
                // Whole turns beyond the first (the arc's P), the end where the total angle ends.
                (pa_start + v, ((v.abs() - 1e-9) / 360.0).floor().max(0.0) as u64 + 1)
            }
            // LP without an angle: the start's (a CP has one, checked where it is read).
            _ if shape == Shape::LinePolar => (pa_start, 1),
            _ => return None,
        };
        if !(r >= 0.0 && r.is_finite()) {
            diags.error(s.line, s.col, format!("{key}: a negative polar radius ({:.4})", r / unit));
            return None;
        }
        if shape == Shape::CirclePolar && r_start < 1e-9 {
            diags.error(s.line, s.col, "CP from the pole itself: a circle of radius 0");
            return None;
        }
        let (sin, cos) = pa.to_radians().sin_cos();
        Some(([pole[0] + r * cos, pole[1] + r * sin], turns))
    }

    /// Where M91's or M92's coordinates start ([`Interpreter::tnc_machine_origin`]), for an
    /// absolute `L` block.
    pub(super) fn machine_axes(&self, code: u32, interp: &Interpreter, shape: Shape, incremental: bool) -> Result<[f64; 3], String> {
        if shape != Shape::Line || incremental {
            return Err("machine coordinates are absolute positions of an L block".into());
        }
        interp.tnc_machine_origin(code)
    }

    /// The block's M functions as words; true if one ends the program (M2, M30).
    pub(super) fn m_words<'a>(&self, m: &[KWord<'a>], words: &mut Vec<Word<'a>>, line: usize, diags: &mut Diags) -> bool {
        let mut ends = false;
        for w in m {
            let v = self.value(w, line, diags).unwrap_or(0.0);
            ends |= v == 2.0 || v == 30.0;
            words.push(Word { letter: 'M', value: v, raw: w.raw.into(), column: w.col, dimension: Dimension::Modal });
        }
        ends
    }

    /// `CT`: the arc from the current point, tangent to the contour before it, to the block's end in
    /// the working plane: its direction (G02/G03) and signed radius (negative over 180 deg).
    pub(super) fn tangent_arc(&self, words: &[Word<'_>], interp: &Interpreter, s: &Stmt, diags: &mut Diags) -> Option<(&'static str, f64)> {
        let Some(t) = self.tangent else {
            diags.error(s.line, s.col, "CT: no contour element before it to be tangent to");
            return None;
        };
        let unit = interp.unit();
        let pos = interp.position();
        let (a0, a1, _) = interp.plane().axes();
        let mut end = [pos[a0], pos[a1]];
        for w in words {
            let Some(k) = "XYZ".find(w.letter) else { continue };
            let slot = if k == a0 { 0 } else if k == a1 { 1 } else { continue };
            end[slot] = if w.dimension == Dimension::Incremental { pos[k] + w.value * unit } else { w.value * unit };
        }
        let d = [end[0] - pos[a0], end[1] - pos[a1]];
        let Some((centre, ccw)) = crate::program::tangent::tangent_circle(t, d) else {
            diags.error(s.line, s.col, "CT: the end point lies on the tangent (a straight line, not an arc)");
            return None;
        };
        // Over 180 deg (the end behind the start along the tangent): a negative radius.
        let over_half = d[0] * t[0] + d[1] * t[1] < 0.0;
        let r = centre[0].hypot(centre[1]) / unit * if over_half { -1.0 } else { 1.0 };
        Some((if ccw { "3" } else { "2" }, r))
    }

    /// A block's feed as the interpreter takes it (value, text as written, column): `F` (a number or a
    /// Q parameter), `FAUTO` (the TOOL CALL's feed); `Ok(None)` for `FMAX` or none; `Err` where it
    /// cannot be read (said).
    pub(super) fn feed_word<'a>(&self, feed: &FeedWord<'a>, line: usize, diags: &mut Diags) -> Result<Option<(f64, Cow<'a, str>, usize)>, ()> {
        match feed {
            FeedWord::Value(f) => self.value(f, line, diags).map(|v| Some((v, Cow::Borrowed(f.raw), f.col))).ok_or(()),
            FeedWord::Auto(col) => match &self.tool_feed {
                Some((v, raw)) => Ok(Some((*v, Cow::Owned(raw.clone()), *col))),
                None => {
                    diags.error(line, *col, "FAUTO without a feed in the TOOL CALL before it");
                    Err(())
                }
            },
            FeedWord::Max | FeedWord::None => Ok(None),
        }
    }

    /// Keep the contour's end direction for a later CT ([`crate::program::tangent::end_tangent`]);
    /// a block that moves nothing leaves it.
    pub(super) fn follow(&mut self, b: &Block, start: [f64; 6], placed: [bool; 6], end: [f64; 6], interp: &Interpreter) {
        if b.arc.is_some() || !b.targets.is_empty() {
            self.tangent = crate::program::tangent::end_tangent(b, start, placed, end, interp);
        }
    }
}
