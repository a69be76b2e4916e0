//! LinuxCNC's cutter radius compensation in the XY plane (`G41`/`G42` with a tool table's diameter,
//! `G41.1`/`G42.1` with the diameter in the block, `G40`), as its interpreter makes it: the tool
//! centre offset by the radius to the left or right of the programmed contour (interp_convert.cc
//! `convert_cutter_compensation_on/off`, `convert_straight_comp1/2`, `convert_arc_comp1/2`;
//! interp_queue.cc `move_endpoint_and_flush`). The first move after `G41` ends perpendicular to its
//! own direction (an arc: to its end's radius); at each later corner an arc about the programmed
//! corner goes round a convex one, and the move before is cut back to where the offset paths meet in a
//! concave one, which is why the last compensated move is held until the next one comes. Errors are
//! LinuxCNC's own (an entry move no longer than the radius, a corner the tool cannot reach without
//! gouging, an arc smaller than the tool); what LinuxCNC refuses with compensation on is refused.
//!
//! [`geometry`] has LinuxCNC's corner rules, [`tools`] the tool table and the tool in the spindle.

mod geometry;
mod tnc;
mod tools;

pub(crate) use tnc::{said as tnc_said, TncComp};

pub use tools::ToolTable;
pub(crate) use tools::{tnc_diameter, tnc_radius, Tools};

use super::interp::{x10, Interpreter, Word};
use super::lex::Diags;
use super::{Block, Dialect, Motion, Plane};
use geometry::{arc, straight};

/// Why compensation cannot go on: a contour the tool cannot follow (its message LinuxCNC's where it
/// has one; the TNC stops there too, [`tnc::said`]), or a move whose compensated motion no control
/// rule at hand gives.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Fail {
    Contour(String),
    NotRead(String),
}

impl Fail {
    /// The reason alone.
    pub(crate) fn why(&self) -> &str {
        match self {
            Fail::Contour(why) | Fail::NotRead(why) => why,
        }
    }
}

impl From<&str> for Fail {
    fn from(why: &str) -> Fail {
        Fail::Contour(why.to_string())
    }
}

impl From<String> for Fail {
    fn from(why: String) -> Fail {
        Fail::Contour(why)
    }
}

impl std::fmt::Display for Fail {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.why())
    }
}

/// How a TNC reads the feed on arcs (M109/M110/M111, iTNC 530 ISO user's manual 340 49x-02 §7.4):
/// the programmed feed "to the path of the tool center" (M111, the standard), or kept at the tool's
/// cutting edge on arcs of inside and outside contours (M109) or of inside ones only (M110). The
/// contours' insides are radius compensation's: without it the tool centre runs on the contour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) enum ArcFeed {
    #[default]
    Centre,
    Edge,
    EdgeInside,
}

/// Which side of the contour the tool runs on, looking along the motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Side {
    Left,
    Right,
}

/// A move or another block held while compensation decides the corner after it.
#[derive(Debug, Clone)]
enum Held {
    /// A straight move and the direction it was programmed in (the gouge check's).
    Straight { block: Block, dir: [f64; 2], rapid: bool },
    /// An arc: its centre, turns (counter-clockwise positive, LinuxCNC's `turn`) and sweep as queued.
    Arc { block: Block, centre: [f64; 2], turn: i32, original: f64 },
    Other(Block),
}

/// Whose rules place the tool where compensation starts and at outside corners.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Rule {
    /// LinuxCNC: the entry move ends perpendicular to its own direction; a rapid goes straight
    /// round a convex corner.
    LinuxCnc,
    /// A Heidenhain TNC: the block that starts compensation ends perpendicular to the contour's
    /// first element at its start, and every outside corner gets a transitional arc ([`tnc`]).
    Tnc,
}

impl Rule {
    /// Corners within this angle (rad) are taken as none: LinuxCNC's `TOLERANCE_CONCAVE_CORNER`
    /// (interp_internal.hh, 0.05 rad), under which it neither rounds nor intersects (a concave
    /// corner of 2.8 deg is cut in by up to r(1 - cos 0.05)); the TNC rounds every outside corner
    /// and intersects every inside one: only a corner below 0.001 rad is none, where the straight
    /// way is within r(1 - cos 0.001) = 5e-7 r of both (CAM output's rounded tangent transitions
    /// make no arcs of a micrometre).
    pub(super) fn small_corner(self) -> f64 {
        match self {
            Rule::LinuxCnc => 0.05,
            Rule::Tnc => 1e-3,
        }
    }
}

/// Compensation in effect (`G41`, `G42`, `G41.1`, `G42.1` until `G40`; a TNC's `RL`/`RR` until `R0`).
#[derive(Debug, Clone)]
pub(crate) struct Comp {
    pub(crate) rule: Rule,
    /// TNC: the block that started compensation is held ending at its programmed point, until the
    /// contour's first element says where the tool stands there.
    entry_held: bool,
    pub(crate) side: Side,
    /// The tool's radius, m (0: the moves run as programmed).
    radius: f64,
    /// No move has been compensated yet (the next is the entry move).
    first: bool,
    /// Where the tool centre is (program coordinates, m).
    current: [f64; 3],
}

/// Compensation's state beside the interpreter's: the mode, the held moves, LinuxCNC's `endpoint`
/// (where the held moves start, for the gouge checks), the tool in the spindle.
#[derive(Debug, Clone, Default)]
pub(crate) struct CompState {
    pub(crate) on: Option<Comp>,
    queue: Vec<Held>,
    endpoint: Option<[f64; 2]>,
    /// The move after G40 must be straight (LinuxCNC's `arc_not_allowed`), and starts from the
    /// programmed point: LinuxCNC puts its current point there (`current = program`), so a move
    /// without X or Y goes back to the programmed X and Y; where the tool stands (X, Y) until then. A
    /// tool change before that move takes the point from where the tool stands instead (LinuxCNC
    /// resynchronises its position from the machine after `M6`).
    arc_not_allowed: bool,
    resync: Option<[f64; 2]>,
    /// Arcs inserted about outside corners so far (a rapid's straight way round counts too): where
    /// a feed rule on arcs meets one, its feed there is in no manual ([`tnc::TncComp::feed`]).
    corner_arcs: usize,
}

/// The most blocks compensation holds while it waits for the next move in the plane: the blocks
/// between two contour elements (Z moves, M functions) are held so the corner can be settled first,
/// and a program of millions of them without a move in the plane would hold them all.
pub(crate) const MAX_HELD: usize = 10_000;

impl CompState {
    /// Whether no more blocks may be held ([`MAX_HELD`]); why, for the error.
    pub(crate) fn full(&self) -> Option<String> {
        (self.queue.len() >= MAX_HELD).then(|| format!("more than {MAX_HELD} blocks without a move in the working plane while radius compensation is on are not read (each is held until the next contour element settles the corner before it)"))
    }

    /// Nothing to do for a block without compensation codes, and nothing to keep (LinuxCNC's
    /// `endpoint` outlives a compensation: a later one's first arc leaves it as it was).
    fn idle(&self) -> bool {
        self.on.is_none() && self.queue.is_empty() && !self.arc_not_allowed && self.resync.is_none() && self.endpoint.is_none()
    }
}

/// What LinuxCNC refuses while compensation is on, in its order of execution (G-code reference,
/// "Order of Execution"): the M codes that act before the block's `G40`/`G41`/`G42` (so they are
/// judged by the state before it), then the G codes that act after it (judged by the state after). The
/// messages are LinuxCNC's (interp_convert.cc), or say what is not modelled under it.
fn refused_m_under_comp(m: f64) -> Option<&'static str> {
    Some(match m {
        6.0 => "Cannot change tools with cutter radius compensation on",
        // LinuxCNC takes M61 but then takes its position from the last move it issued, which cuts
        // the held move short.
        61.0 => "M61 with cutter radius compensation on: LinuxCNC then takes its position from the machine, short of the held move (not read)",
        62.0 => "Cannot set motion output with cutter radius compensation on",
        63.0 => "Cannot set motion digital output with cutter radius compensation on",
        64.0 | 65.0 => "Cannot set auxiliary digital output with cutter radius compensation on",
        66.0 => "Cannot wait for digital input with cutter radius compensation on",
        67.0 => "Cannot set motion analog output with cutter radius compensation on",
        68.0 => "Cannot set auxiliary analog output with cutter radius compensation on",
        48.0 | 50.0 | 51.0 | 52.0 | 53.0 => "Cannot enable overrides with cutter radius compensation on",
        49.0 => "Cannot disable overrides with cutter radius compensation on",
        _ => return None,
    })
}

fn refused_g_under_comp(code: &str, radius: f64) -> Option<&'static str> {
    Some(match code {
        "43" | "43.1" | "43.2" | "49" => "Cannot change tool offset with cutter radius compensation on",
        "54" | "55" | "56" | "57" | "58" | "59" | "59.1" | "59.2" | "59.3" => "Cannot change coordinate systems with cutter radius compensation on",
        "61" | "61.1" | "64" => "Cannot change control mode with cutter radius compensation on",
        "98" | "99" => "Cannot change retract mode with cutter radius compensation on",
        "52" | "92" => "Cannot change axis offsets with cutter radius comp",
        "92.1" | "92.2" | "92.3" => "axis offsets taken away or restored with cutter radius compensation on are not read",
        "53" if radius > 0.0 => "Cannot use g53 with cutter radius comp",
        "28" | "30" | "28.1" | "30.1" => "a move to a stored position with cutter radius compensation on",
        "43.4" | "43.5" => "tool-centre-point control with cutter radius compensation on is not read",
        "93" if radius > 0.0 => "inverse time with cutter radius compensation: how LinuxCNC times an inserted corner is not read",
        "73" | "74" | "76" | "81" | "82" | "83" | "84" | "85" | "86" | "87" | "88" | "89" => "Cannot use canned cycles with cutter compensation on",
        "5" | "5.1" | "5.2" | "5.3" => "Cannot convert spline with cutter radius compensation",
        _ => return None,
    })
}

/// A block of an RS274NGC program (LinuxCNC): compensation's codes and moves, or `None` where
/// compensation has nothing to do with it (off, nothing held, no code of its own).
#[allow(clippy::too_many_arguments)]
pub(crate) fn block(it: &mut Interpreter, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> Option<bool> {
    if it.dialect() != Dialect::Rs274 {
        return None;
    }
    let code = |w: &Word| super::fanuc::code(w);
    // Most blocks: no compensation code, none in effect; only the tool is followed.
    let mut comp_word = None;
    let mut tool_words = false;
    for w in words {
        match w.letter {
            'G' if comp_word.is_none() && matches!(x10(w), 400 | 410 | 411 | 420 | 421) => comp_word = Some(w),
            'T' | 'M' => tool_words = true,
            _ => {}
        }
    }
    if comp_word.is_none() && it.comp.is_none() {
        if tool_words {
            it.tools.track(words);
        }
        return None;
    }
    let stops = words.iter().any(|w| w.letter == 'M' && matches!(w.value, 0.0 | 1.0 | 2.0 | 30.0 | 60.0));
    let tool_change = words.iter().any(|w| w.letter == 'M' && w.value == 6.0);
    let m61 = words.iter().any(|w| w.letter == 'M' && w.value == 61.0);
    let saved = it.clone();
    // The state, out of the interpreter while the block is read (back at the end; `saved` has it too).
    let mut st: Box<CompState> = it.comp.take().unwrap_or_default();
    let unit = it.unit();
    let metric = unit == crate::units::MM;
    let fail = |it: &mut Interpreter, diags: &mut Diags, col: usize, why: &str| {
        *it = saved.clone();
        diags.error(line, col, why.to_string());
        Some(false)
    };
    // A move the compensation cannot make (a gouge, a radius too small for an arc or an entry):
    // LinuxCNC stops there, and the move it held stays unresolved, so every later move would
    // meet it again. Reading ends at it, as the control does.
    let halt = |it: &mut Interpreter, diags: &mut Diags, col: usize, why: &str| {
        *it = saved.clone();
        it.comp = None;
        it.halted = true;
        diags.error(line, col, format!("{why} (LinuxCNC stops here: the rest of the program is not read)"));
        Some(false)
    };
    let mut emit: Vec<Block> = Vec::new();
    // The M codes and the plane, which act before G40/G41/G42 in the block, judged by the state
    // before it (interp_convert.cc convert_set_plane: "Cannot change planes with cutter radius
    // compensation on").
    if st.on.is_some() {
        if let Some((w, why)) = words.iter().filter(|w| w.letter == 'M').find_map(|w| refused_m_under_comp(w.value).map(|why| (w, why))) {
            return fail(it, diags, w.column, &format!("M{}: {why}", w.raw));
        }
        if let Some(w) = words.iter().find(|w| w.letter == 'G' && matches!(code(w).as_str(), "18" | "19")) {
            return fail(it, diags, w.column, &format!("G{}: Cannot change planes with cutter radius compensation on", w.raw));
        }
    }
    if let (Some(w), true) = (comp_word, tool_change) {
        if code(w) != "40" {
            return fail(it, diags, w.column, &format!("G{} with a tool change in its block: LinuxCNC takes the radius of the tool before the change (write M6 in a block before it)", w.raw));
        }
    }
    // G40/G41/G42 (modal group 7) act before the block's motion.
    let mut stripped: Vec<Word> = words.to_vec();
    if let Some(w) = comp_word {
        let c = code(w);
        // The code itself, and the D (and a G41.1's L) it takes.
        let own = |x: &Word| (x.letter == 'G' && x.column == w.column) || (x.letter == 'D' && c != "40") || (x.letter == 'L' && c.ends_with(".1"));
        stripped.retain(|x| !own(x));
        if c == "40" {
            if let Some(comp) = st.on.take() {
                if comp.radius > 0.0 && !comp.first {
                    if let Err(why) = st.move_endpoint_and_flush([comp.current[0], comp.current[1]], metric, unit, &mut emit) {
                        return halt(it, diags, w.column, &why.to_string());
                    }
                    st.dequeue(&mut emit);
                    st.arc_not_allowed = true;
                    st.resync = Some([comp.current[0], comp.current[1]]);
                }
            }
        } else {
            let plane_word = words.iter().filter(|x| x.letter == 'G').map(code).find(|k| matches!(k.as_str(), "17" | "18" | "19"));
            if plane_word.as_deref().map_or(it.plane() != Plane::Xy, |k| k != "17") {
                return fail(it, diags, w.column, &format!("G{}: cutter radius compensation is read in the XY plane (G17) only (LinuxCNC's XZ compensation is for lathes)", w.raw));
            }
            if st.on.is_some() {
                return fail(it, diags, w.column, "Cannot turn cutter radius comp on when on");
            }
            let d = words.iter().find(|x| x.letter == 'D');
            let mut side = if c.starts_with("41") { Side::Left } else { Side::Right };
            let radius = if c.ends_with(".1") {
                if let Some(l) = words.iter().find(|x| x.letter == 'L') {
                    return fail(it, diags, l.column, &format!("G{} with L word, but plane is not G18 (L{}: a lathe tool's orientation)", w.raw, l.raw));
                }
                match d {
                    Some(d) => d.value * unit / 2.0,
                    None => return fail(it, diags, w.column, &format!("G{} with no D word (LinuxCNC: the D word is the tool's diameter)", w.raw)),
                }
            } else {
                // LinuxCNC's is_near_int: the integer `(int)(D + 0.5)` within 0.0001 of D (so a negative
                // D fails it); D0 or no D is the tool in the spindle.
                let tool = match d {
                    Some(d) => {
                        let near = (d.value + 0.5).trunc();
                        if !((near - d.value).abs() < 1e-4) || !(0.0..=u32::MAX as f64).contains(&near) {
                            return fail(it, diags, d.column, &format!("D{}: G{} requires D word to be a whole number", d.raw, w.raw));
                        }
                        near as u32
                    }
                    None => 0,
                };
                let tool = match (tool, it.tools.spindle) {
                    (0, Some(t)) => t,
                    (0, None) => return fail(it, diags, d.map_or(w.column, |d| d.column), &format!("G{}: the radius is the tool in the spindle's, and no T ... M6 (or M61 Q) before it says which (the one left in the spindle is not known here)", w.raw)),
                    (t, _) => t,
                };
                let Some(table) = it.tool_table() else {
                    return fail(it, diags, w.column, &format!("G{}: the radius is tool {tool}'s in the machine's tool table: give it with --tool-table (LinuxCNC's tool.tbl), or write G{}.1 D<diameter>", w.raw, &c));
                };
                match table.diameter(tool) {
                    Some(dia) => dia / 2.0,
                    None => return fail(it, diags, d.map_or(w.column, |d| d.column), &format!("Requested tool {tool} not found in the tool table")),
                }
            };
            // A negative radius (a diameter below the nominal one) runs on the other side.
            let radius = if radius < 0.0 {
                side = if side == Side::Left { Side::Right } else { Side::Left };
                -radius
            } else {
                radius
            };
            let p = it.position();
            st.on = Some(Comp { rule: Rule::LinuxCnc, entry_held: false, side, radius, first: true, current: [p[0], p[1], p[2]] });
        }
    }
    // The G codes that act after G40/G41/G42 in the block, judged by the state after it.
    if let Some(radius) = st.on.as_ref().map(|c| c.radius) {
        for w in words.iter().filter(|w| w.letter == 'G') {
            let c = code(w);
            let why = match c.as_str() {
                // LinuxCNC refuses a change of the active system's offsets only (interp_convert.cc convert_setup).
                "10" => {
                    let p = words.iter().find(|x| x.letter == 'P').map_or(0.0, |x| x.value);
                    let l = words.iter().find(|x| x.letter == 'L').map_or(0.0, |x| x.value);
                    ((l == 2.0 || l == 20.0) && (p == 0.0 || p as usize == it.system() + 1)).then_some("Cannot change the active coordinate system with cutter radius compensation on")
                }
                // Machine coordinates are turned back into the rotated frame before compensation
                // sees them; this reader does not hold that case.
                "53" if it.rotation_now() != 0.0 => Some("machine coordinates (G53) with cutter radius compensation on in a rotated coordinate system are not read"),
                _ => refused_g_under_comp(&c, radius),
            };
            if let Some(why) = why {
                return fail(it, diags, w.column, &format!("G{}: {why}", w.raw));
            }
        }
    }
    let op = it.position();
    let mut made = Vec::new();
    // Compensation offsets the moves in the program frame: they are placed in the workpiece's as
    // they go out (a rotated system, which cannot change while it is on).
    it.hold_frame = true;
    let ok = it.block_plain(&stripped, line, column, number, diags, &mut made);
    it.hold_frame = false;
    if !ok {
        *it = saved.clone();
        return Some(false);
    }
    let p = it.position();
    let straight_code = words.iter().any(|w| w.letter == 'G' && matches!(x10(w), 0 | 10));
    if st.resync.is_some() && st.on.is_none() && straight_code && made.iter().all(|b| b.targets.is_empty()) {
        // `G1` alone after G40: LinuxCNC's straight move from its current point, which G40 put at
        // the programmed one (interp_convert.cc convert_straight): the tool goes back there (below).
        let mut b = match made.iter().position(|b| b.targets.is_empty()) {
            Some(k) => made.remove(k),
            None => it.still_block(line, column, number),
        };
        b.motion = it.feed_state().0.unwrap_or(Motion::Linear);
        (b.targets.x, b.targets.y) = (Some(op[0]), Some(op[1]));
        made.insert(0, b);
    }
    let moves: Vec<usize> = (0..made.len()).filter(|&k| !made[k].targets.is_empty()).collect();
    // The move after G40 is straight (LinuxCNC: "The move just after exiting cutter compensation mode
    // must be straight, not an arc").
    if st.arc_not_allowed {
        if let Some(&k) = moves.first() {
            if made[k].motion.is_arc() {
                return fail(it, diags, column, "The move just after exiting cutter compensation mode must be straight, not an arc");
            }
            st.arc_not_allowed = false;
        }
    }
    if st.resync.is_some() {
        if let Some(&k) = moves.first() {
            // From the programmed point before the block (a canned cycle's first move too).
            let t = &mut made[k].targets;
            t.x = t.x.or(Some(op[0]));
            t.y = t.y.or(Some(op[1]));
            st.resync = None;
        } else if tool_change || m61 {
            if let Some(xy) = st.resync.take() {
                it.set_position_xy(xy);
            }
        }
    }
    let active = st.on.as_ref().is_some_and(|c| c.radius > 0.0);
    if active && moves.len() > 1 {
        return fail(it, diags, column, "a block of several moves with cutter radius compensation on");
    }
    for b in made {
        if let Some(why) = st.full() {
            return fail(it, diags, column, &why);
        }
        // Without compensation, and blocks that move nothing: out, after any held move.
        if !active || b.targets.is_empty() {
            if st.queue.is_empty() {
                emit.push(b);
            } else {
                st.queue.push(Held::Other(b));
            }
            continue;
        }
        let result = match (&b.arc, b.motion) {
            (Some(spec), m) if m.is_arc() => {
                if spec.plane != Plane::Xy || spec.frame.is_some() {
                    return fail(it, diags, column, "an arc outside the XY plane with cutter radius compensation on");
                }
                let turns = spec.extra_turns as i32 + 1;
                let turn = if m == Motion::ArcCw { -turns } else { turns };
                arc(&mut st, &b, xyz(op), xyz(p), [spec.centre[0], spec.centre[1]], turn, metric, unit, &mut emit)
            }
            (_, Motion::Rapid | Motion::Linear) => straight(&mut st, &b, xyz(op), xyz(p), metric, unit, &mut emit),
            _ => Err("a move other than G0, G1, G2 or G3 with cutter radius compensation on".into()),
        };
        if let Err(why) = result {
            return halt(it, diags, column, &why.to_string());
        }
    }
    // A stop (M0, M1, M2, M30, M60) sends every held move (convert_stop); M2 and M30 end compensation.
    if stops {
        if let Some(comp) = st.on.clone() {
            if let Err(why) = st.move_endpoint_and_flush([comp.current[0], comp.current[1]], metric, unit, &mut emit) {
                return halt(it, diags, column, &why.to_string());
            }
        }
        st.dequeue(&mut emit);
        if words.iter().any(|w| w.letter == 'M' && matches!(w.value, 2.0 | 30.0)) {
            st.on = None;
        }
    }
    it.tools.track(words);
    it.comp = if st.idle() { None } else { Some(st) };
    for b in &mut emit {
        it.to_world(b);
    }
    out.extend(emit);
    Some(true)
}

fn xyz(p: [f64; 6]) -> [f64; 3] {
    [p[0], p[1], p[2]]
}

/// The end of the program's text with moves still held: LinuxCNC never sends them (only the next
/// move, `G40` or a stop does; at the end of the file its queue is dropped), so neither is any here,
/// and that is said.
pub(crate) fn finish(it: &mut Interpreter, diags: &mut Diags) {
    let Some(st) = it.comp.take() else { return };
    let held = st.queue.iter().find_map(|h| match h {
        Held::Straight { block, .. } | Held::Arc { block, .. } => Some(block.line),
        Held::Other(_) => None,
    });
    if let Some(line) = held {
        diags.warning(line, 1, format!("the compensated move of line {line} is never run: LinuxCNC sends a move it holds for cutter radius compensation only at the next move, G40 or a stop (M0, M1, M2, M30, M60), and the program ends before any"));
    }
}
