//! Siemens Sinumerik 840D programs (`.MPF`/`.SPF`), as written from the 840D sl Programming Manual
//! Job Planning (6FC5398-2BP20, 5-axis transformation TRAORI) and Fundamentals: `N` numbers, `;`
//! comments, `G0/G1/G2/G3` (arcs: `I J K` from the start, or `CR=` radius, `TURN=` full turns),
//! `G17-G19`, `G90/G91` with `AC()`/`IC()` for one word, `G93/G94`, `G70/G71` (the geometry's
//! unit; F in the basic system's) and `G700/G710` (F's too), `G54-G57`/`G500`/`G505-G599` (settable
//! frames: the operator's), blending `G64`/`G641`-`G645` and exact stop `G60` (a rapid only),
//! `TRAORI`/`TRAFOOF` (tool-centre point), the tool vector `A3= B3= C3=` (a missing component is 0;
//! it points from the tip to the tool holder), rotary axes `A= B= C=`, `ORIWKS`/`ORIVECT`/`ORIPLANE`
//! (the tool axis on a great circle in the workpiece, the reset state) and `ORIMKS`/`ORIAXES` (the
//! rotary axes linear), the programmable frame (`TRANS`/`ATRANS`/`ROT`/`AROT`, [`frame`]),
//! machine coordinates (`SUPA`, `G53`, `G153`), variables (`DEF REAL`, R parameters: [`vars`]) and
//! expressions ([`expr`], [`lex`]), `MCALL` of the drilling cycles ([`cycles`]), `CYCLE832` (the
//! contour tolerance), the swivel cycle `CYCLE800` on the machine file's data set ([`swivel`]), `T`,
//! `D`, `S`, `M`, `F`, `MSG`, `M30`; tool radius compensation `G41`/`G42` to `G40` ([`trc`]); chamfers
//! and roundings at contour corners (`CHF=`, `CHR=`, `RND=`, `RNDM=`, [`corners`]); jumps
//! and control structures as they run ([`flow`]), and subprograms called by name, found beside the
//! program or on `--subroutine-path` ([`subprogram`]).
//!
//! What changes the motion and is not modelled is an error at its line and column, never skipped:
//! `SCALE`/`MIRROR` frames, `CYCLE800` after a rotated frame or beyond what [`swivel`] reads, other
//! cycles, `CALL` other than `CALL "NAME"` alone, 3D cutter compensation, orientation by angles
//! (`A2=`) or cone/polynomial orientation, exact stop on a feed move.
//!
//! Orientation interpolation: which of ORIWKS/ORIMKS and ORIVECT/ORIAXES governs depends on machine
//! datum MD21104 `ORI_IPO_WITH_G_CODE`; here the one programmed last governs (at reset ORIWKS and
//! ORIVECT agree: the great circle).

mod calls;
mod circles;
mod coordinates;
mod corners;
mod cycles;
mod expr;
mod flow;
mod forms;
mod frame;
mod keywords;
mod polar;
mod lex;
mod subprogram;
mod swivel;
mod trc;
mod vars;

use super::interp::{Dimension, Interpreter, OneShot, Word};
use super::lex::{Columns, Diags};
use super::{Block, Dialect, MCodeRule, Motion, Orientation, Program};
use crate::units::{DEG, MM};
use frame::{Frame, Statement};
use keywords::{is_instruction, sinumerik_g, unread_what, unsupported_keyword, READ_KEYWORDS, LASTING, UNREAD_MOTION};
use lex::Lexed;
use vars::Vars;

pub(crate) use flow::FlowRunner;

/// Read a Sinumerik program on a control whose orientation interpolation starts as `orientation`
/// (the reset state is [`Orientation::GreatCircle`], ORIWKS/ORIVECT).
pub fn read_sinumerik_with(text: &str, m_codes: &[MCodeRule], orientation: Orientation) -> Program {
    super::stream::read_jumping(text, Dialect::Sinumerik, Box::new(FlowRunner::new(&super::Setup::plain(Dialect::Sinumerik, m_codes, orientation))))
}

/// The Sinumerik reader, fed one line at a time.
#[derive(Debug, Clone)]
pub(crate) struct SinumerikReader {
    interp: Interpreter,
    vars: Vars,
    /// The programmable frame (TRANS, ROT and their additive forms), SI.
    frame: Frame,
    /// The tool's offsets are on (a `D` edge other than D0 selected; the reset state's D1).
    tool_offsets: bool,
    /// The drilling cycle `MCALL` made modal, and its line.
    mcall: Option<(cycles::Hole, usize)>,
    /// The swivelled plane `CYCLE800` set (its frame before the programmable one).
    swivel: Option<Frame>,
    /// The machine, for the swivel's kinematics.
    machine: Option<std::sync::Arc<crate::machine::Machine>>,
    /// Tool radius compensation ([`trc`]).
    trc: trc::Trc,
    /// Chamfers and roundings at contour corners ([`corners`]).
    pub(super) corners: corners::Corners,
    /// What the corners said of a line under compensation: added once the line is taken, so that a
    /// corner refused does not refuse the line compensation has already placed.
    pub(super) corner_diags: Diags,
    /// The line just read had M17 (held by compensation or not): the subprogram returns there.
    pub(super) returned: bool,
    /// Tool radius compensation could not go on: the program stops (kept apart from the
    /// interpreter, which a refused line takes back).
    pub(super) stopped: bool,
    /// The line refused a call the control runs (a program, a cycle not read): its name.
    called_unread: Option<String>,
    /// The line's cycle call (`MCALL` or once) was refused: `true` for an alarm of the control,
    /// which stops there; `false` for what this reader does not read ([`SinumerikReader::calls_refused`]).
call_refused: Option<bool>,
    /// `ORIMKS` (tool vectors in the machine's coordinates) was programmed after `ORIWKS` (the reset
    /// state: in the workpiece's, turned with the frame).
    ori_mks: bool,
    /// 3D tool radius compensation (`CUT3DC` ..., refused) in force on the control until `CUT2D`: its
    /// line and name ([`keywords::COMP3D`]).
    comp3d: Option<(usize, String)>,
    /// G group 1's circle in effect, `CIP` or `CT` ([`forms`]).
    circle_mode: Option<forms::CircleMode>,
    /// The direction the contour ends in, for a `CT` ([`forms`]).
    tangent: Option<forms::Tangent>,
    /// The pole and the polar angle and radius ([`polar`]).
    polar: polar::Polar,
}

impl SinumerikReader {
    pub(crate) fn new(setup: &super::Setup) -> Self {
        SinumerikReader {
            interp: setup.interpreter(),
            vars: Vars::default(),
            frame: Frame::default(),
            tool_offsets: true,
            mcall: None,
            swivel: None,
            machine: setup.machine.clone(),
            trc: trc::Trc::default(),
            corners: corners::Corners::default(),
            corner_diags: Diags::default(),
            returned: false,
            stopped: false,
            called_unread: None,
            call_refused: None,
            ori_mks: false,
            comp3d: None,
            circle_mode: None,
            tangent: None,
            polar: polar::Polar::default(),
        }
    }

    /// The G90/G91, plane and length unit a circle of this block is read in: its own G90/G91,
    /// G17-G19 and G70/G71 (G700/G710), else the modal ones.
    fn circle_settings(&self, words: &[Word<'_>]) -> (bool, crate::program::Plane, f64) {
        let g = |v: f64| words.iter().any(|w| w.letter == 'G' && w.value == v);
        let absolute = if g(91.0) {
            false
        } else if g(90.0) {
            true
        } else {
            self.interp.absolute()
        };
        let plane = plane_after(words, self.interp.plane());
        // (The lexer gives G700/G710 as G20/G21.)
        let unit = if g(70.0) || g(20.0) {
            crate::units::INCH
        } else if g(71.0) || g(21.0) {
            MM
        } else {
            self.interp.unit()
        };
        (absolute, plane, unit)
    }

}

/// What a call refused is, which the control runs (a program, a cycle not read): every axis is
/// unknown after it.
const UNREAD_CALL: &str = "a call not read, which the control runs";

/// The cycle calls of a line: an `MCALL` (of a cycle, a program, or alone), a cycle called once.
struct Calls {
    mcall: bool,
    once: Option<String>,
}

impl Calls {
    fn of(keywords: &[lex::Keyword<'_>]) -> Calls {
        let mcall = keywords.iter().any(|k| k.name == "MCALL");
        let once = keywords.iter().find(|k| k.args.is_some() && cycles::Cycle::from_name(&k.name).is_some()).map(|k| k.name.to_string());
        Calls { mcall, once }
    }
}

/// A statement of a line that is not a block of words: `DEF`, as the definitions part writes them.
fn def_statement(text: &str) -> Option<usize> {
    let t = text.trim_start();
    let mut rest = t;
    // An N number before it.
    if rest.starts_with(['N', 'n']) && rest[1..].starts_with(|c: char| c.is_ascii_digit()) {
        let digits = rest[1..].find(|c: char| !c.is_ascii_digit()).map_or(rest.len(), |k| k + 1);
        rest = rest[digits..].trim_start();
    }
    let upper = rest.get(..4).map(str::to_ascii_uppercase);
    (upper.as_deref() == Some("DEF ")).then(|| text.len() - rest.len() + 4)
}

impl super::stream::LineReader for SinumerikReader {
    fn line(&mut self, line: usize, text: &str, out: &mut Vec<Block>, diags: &mut Diags) {
        let text_line = text.trim_end_matches('\r');
        let Some(first) = text_line.find(|c: char| !c.is_whitespace()) else { return };
        if text_line[first..].starts_with('%') {
            return; // `%_N_NAME_MPF` transfer header
        }
        let cols = Columns::new(text_line);
        if let Some(at) = def_statement(text_line) {
            // The comment after the definitions.
            let body = text_line[at..].split(';').next().unwrap_or("");
            if let Err((k, why)) = lex::define(body, &mut self.vars) {
                self.vars.rollback();
                diags.error(line, cols.col(at + k), format!("DEF: {why}"));
            }
            self.vars.commit();
            return;
        }
        let errors_before = diags.errors();
        let first = cols.col(first) - 1;
        let lexed = lex::lex_line(text_line, &cols, line, &mut self.vars, diags);
        // A refused line's CIP or CT does not take effect, and the motion after it is not known
        // ([`UNREAD_MOTION`]).
        let (mode_before, polar_before) = (self.circle_mode, self.polar);
        let unread_motion = lexed.keywords.iter().find_map(|k| UNREAD_MOTION.iter().copied().find(|u| *u == k.name.as_str()));
        // A move of its own the control makes, refused here ([`keywords::refused_move`]).
        let refused_move = lexed.refused_g.and_then(|g| keywords::refused_move(g).map(|m| (format!("G{g}"), m)));
        // Statements that end a hold (not TRANS and ROT, which stand alone), and the axial offsets
        // G58/G59 (the programmable frame's translation, refused: held as a frame).
        let ends: Vec<String> = lexed.keywords.iter().filter(|k| !matches!(k.name.as_str(), "TRANS" | "ROT") && LASTING.iter().any(|l| l.ends.contains(&k.name.as_str()))).map(|k| k.name.to_string()).collect();
        let frame_g = lexed.frame_g;
        let comp3d = lexed.keywords.iter().find(|k| keywords::COMP3D.contains(&k.name.as_str())).map(|k| k.name.to_string());
        // A lasting statement (a frame, a transformation ...): if refused, the control's holds the
        // moves after it until a statement that ends it is read ([`keywords::LASTING`]).
        let lasting: Vec<(String, &'static keywords::Lasting)> = lexed.keywords.iter().filter_map(|k| keywords::lasting(&k.name).map(|l| (k.name.to_string(), l))).collect();
        let axes = crate::program::interp::axes_named(Dialect::Sinumerik, &lexed.words);
        // A line refused that moves axes under CIP or CT in effect, with no G0-G3 of its own: the
        // control made that circle, which is not read, as a line that writes CIP or CT.
        let unread_motion = unread_motion.or_else(|| mode_before.filter(|_| axes.iter().any(|&a| a) && motion_g(&lexed.words).is_none()).map(forms::CircleMode::name));
        // A refused line leaves CIP or CT in effect unless it has a motion of G group 1 (a spline,
        // CIP or CT itself, a circle of theirs, or a threading G33 ...), which the control ran.
        let ends_circle_mode = unread_motion.is_some() || refused_move.as_ref().is_some_and(|(_, (_, _, group1))| *group1);
        let calls = Calls::of(&lexed.keywords);
        self.call_refused = None;
        if diags.errors() > errors_before {
            // What the control did on a refused line is not known here: a CT after it has no tangent.
            self.tangent = None;
            self.calls_refused(&calls, line);
            if let Some(k) = unread_motion {
                self.interp.forget_motion(line, k, unread_what(k), axes);
            }
            if ends_circle_mode {
                self.circle_mode = None;
            }
            self.hold_refused(&lasting, frame_g, line);
            self.moved_unread_g(refused_move, axes, line);
            if let Some(l) = lexed.call_l {
                self.interp.moved_everywhere(line, &format!("L{l}"), UNREAD_CALL);
            }
            self.vars.rollback();
            diags.warning(line, first + 1, format!("line {line} not used: it is damaged"));
            let held = self.corners.interrupt("the block after it was not read", diags);
            self.emit_held(held, line, first + 1, out, diags);
            return;
        }
        // The state a refused block must leave as it was. A block of plain words (a tool vector among
        // them) changes only what the interpreter's own block takes back on a refusal, its vector
        // and its tool edge (most lines: no copy of the interpreter here).
        let plain = lexed.keywords.is_empty()
            && lexed.rpl.is_none()
            && self.mcall.is_none()
            && !lexed.words.iter().any(|w| w.letter == 'G' && matches!(w.raw.as_ref(), "60" | "64" | "9" | "53"));
        let saved = (!plain).then(|| (self.interp.clone(), self.frame, self.mcall.clone(), self.swivel, self.ori_mks));
        let (tool_offsets, vector, refused_line) = (self.tool_offsets, self.interp.pending_vector(), self.interp.refused_line);
        // Compensation's settings, a few words, taken back too (its held path is fed last, once
        // the block is read).
        let trc_settings = self.trc.set.clone();
        let blocks_before = out.len();
        // A comment line alone is no block between two elements a corner joins.
        let written = lexed.number.is_some() || !lexed.words.is_empty() || !lexed.keywords.is_empty() || lexed.vector.is_some() || lexed.edge.is_some() || lexed.corner.any();
        let (start, placed, corners) = (self.interp.position(), self.interp.placed, self.corners.busy() || lexed.corner.any());
        // Under tool radius compensation its own path takes the corners ([`trc`]).
        let trc_before = self.trc.busy();
        // A refused block's feed does not take effect: a later move without one names it
        // ([`Interpreter::after_refused_feed`]; of a refused block's other words the 840D reader says nothing).
        let feed_word = lexed.words.iter().any(|w| w.letter == 'F');
        // A block held (refused for a hold, read all the same): the control made its move, so the
        // tool is where it ends and the axes it writes are known after it, whatever else of its
        // line's state is taken back.
        let held = !plain && self.interp.held(&lexed.words).is_some();
        if !self.block(lexed, line, first + 1, out, diags) || diags.errors() > errors_before {
            self.corners.drop_words();
            self.tangent = None;
            if let Some(saved) = saved {
                let placement = held.then(|| self.interp.placement());
                (self.interp, self.frame, self.mcall, self.swivel, self.ori_mks) = saved;
                if let Some(p) = placement {
                    self.interp.set_placement(p);
                }
            }
            self.tool_offsets = tool_offsets;
            self.trc.set = trc_settings;
            self.returned = false;
            if plain {
                self.interp.restore_pending_vector(vector);
                self.interp.refused_line = refused_line;
            }
            // The restore took back what the interpreter noted of a move in a mode not read.
            self.interp.moved_in_unread_mode(axes);
            self.moved_unread_g(refused_move, axes, line);
            // What the line's statements read ended stays ended (`TRAFOOF G0 X0`), what it
            // refused holds; a call the control runs leaves every axis unknown.
            for name in &ends {
                self.end_holds(name);
            }
            self.hold_refused(&lasting, frame_g, line);
            if let Some(k) = comp3d {
                self.comp3d = Some((line, k));
            }
            if let Some(name) = self.called_unread.take() {
                self.interp.moved_everywhere(line, &name, UNREAD_CALL);
            }
            self.calls_refused(&calls, line);
            (self.circle_mode, self.polar) = (mode_before.filter(|_| !ends_circle_mode), polar_before);
            if let Some(k) = unread_motion {
                self.interp.forget_motion(line, k, unread_what(k), axes);
            }
            self.interp.note_feed(false, feed_word, line);
            out.truncate(blocks_before);
            self.vars.rollback();
            diags.warning(line, first + 1, format!("line {line} not used"));
            // A corner waiting: the block after it was not read, so it joins nothing.
            self.corners.drop_words();
            diags.0.append(&mut self.corner_diags.0);
            if self.stopped {
                // Compensation stopped the program here: what a corner held never runs.
                self.corners = corners::Corners::default();
            } else {
                let held = self.corners.interrupt("the block after it was not read", diags);
                self.emit_held(held, line, first + 1, out, diags);
            }
            return;
        }
        self.vars.commit();
        self.follow(start, placed, &out[blocks_before..], line);
        diags.0.append(&mut self.corner_diags.0);
        if corners && !trc_before && !self.trc.busy() && (written || out.len() > blocks_before) {
            let ends = self.returned || self.stopped || super::stream::ends_program(&out[blocks_before..], &[2.0, 30.0]);
            self.corners.after_line(start, blocks_before, &self.interp, ends, out, diags);
        }
        self.corners.leftover(diags);
    }

    fn not_read(&mut self, line: usize, out: &mut Vec<Block>, diags: &mut Diags) {
        self.tangent = None;
        self.corner_interrupt("the block after it was not read", line, 1, out, diags);
    }
}

impl SinumerikReader {
    /// The block sequence is left (a call, a return): a corner waiting is refused, its blocks out.
    pub(super) fn corner_interrupt(&mut self, why: &str, line: usize, col: usize, out: &mut Vec<Block>, diags: &mut Diags) {
        if self.stopped {
            self.corners = corners::Corners::default();
            return;
        }
        let held = self.corners.interrupt(why, diags);
        self.emit_held(held, line, col, out, diags);
    }

    /// The program's input has ended: a corner waiting has no element after it.
    pub(super) fn corner_end(&mut self, line: usize, out: &mut Vec<Block>, diags: &mut Diags) {
        // Compensation stopped the program: what a corner held there never runs.
        if self.stopped {
            self.corners = corners::Corners::default();
            return;
        }
        let held = self.corners.end(diags);
        self.emit_held(held, line, 1, out, diags);
    }

    /// Blocks a corner held, out in order: through tool radius compensation while it is on (a
    /// failure there stops the program, [`trc`]).
    pub(super) fn emit_held(&mut self, held: Vec<crate::program::corner_cut::Held>, line: usize, col: usize, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        // Compensation stopped the program: what was held after the stop does not run.
        if self.stopped {
            return false;
        }
        for h in held {
            if self.trc.busy() {
                let fed = self.trc.engine.feed(h.b, h.start, h.end, h.unit, h.tilt, h.arc_feed, out);
                if !self.trc_result(fed, line, col, diags) {
                    return false;
                }
            } else {
                out.push(h.b);
            }
        }
        true
    }

    /// Run one block's words; false (or an error in `diags`) if it is refused.
    fn block(&mut self, lexed: Lexed<'_>, line: usize, first_col: usize, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        let errors_before = diags.errors();
        let Lexed { mut words, number, mut keywords, vector, edge, rpl, disc, offn, corner, circle, .. } = lexed;
        // CIP, CT, AR=, polar coordinates: where a block writes them or CIP or CT is in effect (most
        // blocks: none, and nothing to do).
        let mode_written = !keywords.is_empty() && keywords.iter().any(|k| forms::CircleMode::of(&k.name).is_some());
        if (self.circle_mode.is_some() || mode_written || circle.is_some() || words.iter().any(|w| w.letter == 'G' && matches!(w.value as i64, 17..=19 | 110..=112)))
            && !self.circle_forms(&mut words, &mut keywords, circle.map(|c| *c).unwrap_or_default(), line, first_col, diags)
        {
            return false;
        }
        if corner.any() || self.corners.busy() {
            self.corners.take(corner, line, first_col, number);
        }
        // A line of a comment alone is no block compensation counts as empty.
        let written = number.is_some() || !words.is_empty() || !keywords.is_empty() || vector.is_some() || edge.is_some() || disc.is_some() || offn.is_some();
        let m17 = words.iter().any(|w| w.letter == 'M' && w.value == 17.0);
        // Tool radius compensation's codes and keywords, taken out of the block; while it is on (or
        // selected here) what would move its frame, tool or machine is refused.
        let mut codes = trc::Codes::default();
        keywords.retain(|k| !codes.keyword(&k.name, k.col));
        words.retain(|w| !(w.letter == 'G' && codes.g(w)));
        let selecting = matches!(codes.select, Some((Some(_), _)));
        if self.trc.busy() || selecting {
            if let Some(k) = keywords.iter().find(|k| !trc::harmless(&k.name)) {
                diags.error(line, k.col, format!("{} with tool radius compensation (G41/G42) on is not read: deselect it with G40 before", k.name));
                return false;
            }
            if let Some(why) = trc::refused_while_on(&words, edge.map(|e| e.1), self.trc.side().is_some()) {
                diags.error(line, why.0, why.1);
                return false;
            }
        }
        // STOPRE, the preprocessing stop (Programming Manual Job Planning, "Preprocessing stop"), in a
        // block of its own: the blocks after it are prepared only once it is executed, so the motion
        // before it has nothing to blend into and ends in a stop. A stop before the next block, as a
        // dwell of 0 s makes it.
        if let Some(k) = keywords.iter().find(|k| k.name == "STOPRE") {
            if keywords.len() > 1 || !words.is_empty() || k.args.is_some() || vector.is_some() || edge.is_some() || rpl.is_some() {
                diags.error(line, k.col, "STOPRE: the preprocessing stop stands in a block of its own");
                return false;
            }
            out.push(Block { dwell_s: Some(0.0), ..self.interp.still_block(line, first_col, number) });
            return true;
        }
        let mut frame_statement: Option<(Statement, usize)> = None;
        let mut machine_coords: Option<(usize, &str)> = None;
        let mut keywords = keywords.into_iter();
        while let Some(k) = keywords.next() {
            match k.name.as_str() {
                "TRAORI" => match k.args.map(str::trim) {
                    None | Some("1") | Some("") => self.interp.switch_tcp(true),
                    Some(a) => diags.error(line, k.col, format!("TRAORI({a}): only the first orientation transformation, without a basic orientation or offsets, is read")),
                },
                "TRAFOOF" => {
                    self.interp.switch_tcp(false);
                    self.end_holds("TRAFOOF");
                }
                "ORIWKS" | "ORIVECT" | "ORIPLANE" | "ORIMKS" | "ORIAXES" => {
                    let axes = matches!(k.name.as_str(), "ORIMKS" | "ORIAXES");
                    if matches!(k.name.as_str(), "ORIWKS" | "ORIMKS") {
                        self.ori_mks = k.name == "ORIMKS";
                    }
                    self.interp.set_orientation(if axes { Orientation::AxisLinear } else { Orientation::GreatCircle });
                    self.end_holds(&k.name);
                }
                // The rotation vector's absolute interpolation, G group 54's default (Fundamentals
                // 10.2004 §12.3): it governs THETA, not read; it ends ORIROTR/ORIROTT/ORIROTC's hold.
                "ORIROTA" => self.end_holds("ORIROTA"),
                // Angle conventions for A2 B2 C2, which are not read: no effect on these programs.
                "ORIEULER" | "ORIRPY" => {}
                // Acceleration modes and feed-forward: the planner always limits jerk.
                "SOFT" | "BRISK" | "FFWON" | "FFWOF" => {}
                // The feed profile over the block: FNORM (the reset state) is the programmed F throughout.
                "FNORM" => self.end_holds("FNORM"),
                // The compressors (Job Planning §"Compressor"): they join short blocks into a curve
                // within the contour tolerance, as the planner's own smoothing does; COMPOF is off.
                "COMPOF" | "COMPON" | "COMPCURV" | "COMPCAD" => {}
                // An operator message: no motion.
                "MSG" => {}
                // The master spindle (Job Planning, "SETMS"): no motion.
                "SETMS" => {}
                // `EXTERN NAME(REAL, REAL)`: a declaration of another program's parameters for its
                // calls (Job Planning, "EXTERN"), the name and its types its own; no motion (a call
                // itself stays refused).
                "EXTERN" => {
                    keywords.next();
                }
                "TRANS" | "ATRANS" | "ROT" | "AROT" => {
                    if frame_statement.is_some() {
                        diags.error(line, k.col, "two frame statements in one block: each stands in a block of its own");
                    }
                    frame_statement = Statement::from_name(&k.name).map(|s| (s, k.col));
                }
                "SUPA" => machine_coords = Some((k.col, "SUPA")),
                // 2D compensation in the plane G17-G19 sets (the reset state), collision detection off.
                "CUT2D" => self.comp3d = None,
                "CDOF" => {}
                "MCALL" => self.modal_call(keywords.next(), line, diags),
                // A call's other words are its own (`CALL BLOCK LABEL1 TO LABEL0`, Autodesk's posts'
                // program section call): one refusal for the block.
                "CALL" | "PCALL" | "EXTCALL" => {
                    let section = if keywords.as_slice().first().is_some_and(|n| n.name == "BLOCK") { "a program section call (CALL BLOCK .. TO ..) is not read: its manual page is not in reach" } else { "this call of another program is not read (a program called by its name alone in its block is, and CALL \"NAME\" alone)" };
                    diags.error(line, k.col, format!("{}: {section}", k.name));
                    self.called_unread = Some(k.name.to_string());
                    break;
                }
                // What a swivel or a cycle moves is held as a move is ([`Interpreter::holding`]).
                // (A swivel after a refused one, or where the axes are unknown, is read for the
                // plane it sets: below.)
                name if (name == "CYCLE800" || cycles::Cycle::from_name(name).is_some())
                    && self.interp.holding().is_some()
                    && !(name == "CYCLE800" && (self.interp.held_by(&crate::program::interp::SIN_SWIVEL) || self.interp.only_stale())) =>
                {
                    let why = self.interp.holding().unwrap_or_default();
                    diags.error(line, k.col, format!("{}: {why}", k.name));
                    break;
                }
                // After a refused swivel, or where the axes are unknown (after a call not read):
                // this one sets the plane the control has from here (read), but its moves start
                // where the tool is not known, so they are not made (said without refusing the
                // line, whose plane stands). The axes it places (the retraction, the rotary axes
                // turned) are known after it; the others stay unknown until written absolute.
                "CYCLE800" if self.interp.held_by(&crate::program::interp::SIN_SWIVEL) || self.interp.only_stale() => {
                    let (start, errors) = (out.len(), diags.errors());
                    let why = match self.interp.holding() {
                        Some(w) if !self.interp.held_by(&crate::program::interp::SIN_SWIVEL) => format!("CYCLE800: {w}; the plane it sets is read, but its own moves, which start there, are not"),
                        _ => "CYCLE800 after a refused CYCLE800: the plane it sets is read, but its moves start where the control's swivel left the tool, which is not known, so they are not read".to_string(),
                    };
                    let stale = self.interp.take_stale();
                    let placed = self.swivel(&k, line, number, true, out, diags);
                    self.interp.restore_stale(stale);
                    if diags.errors() == errors {
                        // (A deselection, or one that turns nothing, makes no move to refuse.)
                        if out.len() > start {
                            self.corner_diags.error(line, k.col, why);
                        }
                        out.truncate(start);
                        self.interp.end_keyword_hold(&crate::program::interp::SIN_SWIVEL, [true; 3], true);
                        self.interp.placed(placed);
                    }
                }
                "CYCLE800" => {
                    self.swivel(&k, line, number, false, out, diags);
                }
                "CYCLE832" => self.high_speed_settings(&k, line, diags),
                // A drilling cycle called without MCALL drills once where the tool stands (Cycles
                // Programming Guide 11.02 §2.1: the drilling position is approached before the call;
                // "the cycle can also be called modally", §2.2).
                name if cycles::Cycle::from_name(name).is_some() && k.args.is_some() => {
                    let col = k.col;
                    if !words.is_empty() || keywords.len() > 0 {
                        diags.error(line, col, format!("{name}: a cycle called without MCALL stands alone in its block"));
                    } else if self.mcall.is_some() {
                        diags.error(line, col, format!("{name}: a cycle called while MCALL's cycle is in force is not read"));
                    } else {
                        // (Refused, the line's refusal says what the control does: calls_refused.)
                        if self.read_call(Some(k), line, diags).is_none() {
                            self.call_cycle(line, col, number, out, diags);
                        }
                        self.mcall = None;
                    }
                    break;
                }
                name if name.starts_with("CYCLE") && k.args.is_some() => {
                    diags.error(line, k.col, format!("{name}: this cycle is not read (it may move the tool; the drilling cycles CYCLE81-CYCLE89 are)"));
                    self.called_unread = Some(name.to_string());
                }
                // A settable frame statement without axes sets nothing in place of the programmable
                // frame it replaces (§2.12, as TRANS and ROT): the frame is reset, as by TRANS.
                "MIRROR" | "SCALE" if words.is_empty() && keywords.as_slice().is_empty() => {
                    if frame_statement.is_some() {
                        diags.error(line, k.col, "two frame statements in one block: each stands in a block of its own");
                    }
                    frame_statement = Some((Statement::Trans, k.col));
                }
                other => match unsupported_keyword(other) {
                    Some(why) => diags.error(line, k.col, format!("{other}: {why}")),
                    // A name of its own is a subprogram call on the 840D (Fundamentals, "Subprogram call").
                    // A name the flow did not take for a call: with other words in its block, or not
                    // a name a program is called by (NC programming 12/2019 §2.15 "Names": "the first two
                    // characters should be letters or underscores").
                    None => diags.error(line, k.col, format!("{other}: not an instruction read here, nor a call of a program: a program is called by a name whose first two characters are letters or underscores (not two underscores), alone in its block (either may change the motion)")),
                },
            }
        }
        if let Some((e, col)) = edge {
            self.tool_offsets = e != 0.0;
            let _ = col;
        } else if words.iter().any(|w| w.letter == 'T' || (w.letter == 'M' && w.value == 6.0)) {
            // A tool change without a D makes the new tool's edge D1 active (MD20270
            // CUTTING_EDGE_DEFAULT = 1, its default; at T or at M6 as MD22550 says): offsets on.
            self.tool_offsets = true;
        }
        // Reader-level G codes: exact stop (G60, modal; G9, this block) and continuous path (G64,
        // G641-G645: G group 10; Programming Manual Fundamentals, "Exact stop (G60, G9, G601, G602,
        // G603)": the block's motion decelerates to a stop at its end), machine coordinates.
        words.retain(|w| {
            if w.letter != 'G' {
                return true;
            }
            match w.raw.as_ref() {
                "60" => self.interp.exact = crate::program::Exact::Stop,
                "64" => self.interp.exact = crate::program::Exact::Blend,
                "9" => self.interp.exact_once = true,
                "53" => machine_coords = Some((w.column, "G53")),
                _ => return true,
            }
            false
        });
        if let Some((statement, _)) = frame_statement {
            return self.frame_block(statement, &words, rpl, line, diags) && diags.errors() == errors_before;
        }
        if let Some((_, col)) = rpl {
            diags.error(line, col, "RPL= outside a frame statement (ROT, AROT)");
        }
        if diags.errors() > errors_before {
            return false;
        }
        self.trc.set.settle(&codes, disc.map(|d| d.0), offn.map(|o| o.0));
        self.trc.set.track(&words, edge.map(|e| e.0.min(u32::MAX as f64) as u32));
        // A block of only a tool vector still moves.
        // Under ORIWKS the vector is the workpiece's, in the frame: it turns with a rotated frame
        // (ROT, AROT, CYCLE800; Job Planning 03/2006 §7.2, "Reference of the orientation axes":
        // vectors "relate to the active frame and rotate when the frame rotates"). Under ORIMKS it is
        // the machine's, which of the two MD21104 makes govern is not read.
        let turned = self.interp.tilt().filter(|r| (r - nalgebra::Matrix3::identity()).abs().max() > 1e-12);
        let vector = match (vector, turned) {
            (Some(_), Some(_)) if self.ori_mks => {
                diags.error(line, first_col, "tool vector (A3 B3 C3) under ORIMKS in a rotated frame: the machine's coordinates or the frame's, as machine datum MD21104 says, is not read");
                return false;
            }
            (Some(v), Some(r)) => Some((r * nalgebra::Vector3::from(v)).into()),
            (v, _) => v,
        };
        match vector {
            Some(v) => self.interp.set_pending_vector(v),
            None if words.is_empty() && codes.select.is_none() => return self.trc.side().is_none() || !written || self.dummy(line, first_col, diags),
            None => {}
        }
        let (modal_motion, _, _) = self.interp.feed_state();
        let block_motion = words.iter().rev().find(|w| w.letter == 'G' && matches!(w.raw.as_ref(), "0" | "1" | "2" | "3")).map(|w| w.raw.as_ref());
        let motion = match block_motion {
            Some("0") => Some(Motion::Rapid),
            Some("1") => Some(Motion::Linear),
            Some(_) => Some(Motion::ArcCw),
            None => modal_motion,
        };
        let positions = words.iter().any(|w| "XYZABC".contains(w.letter)) || vector.is_some();
        // A milling tool's length goes to the axis normal to the plane (NC programming 12/2019
        // §3.13.3.4 "Tool length and plane change": G17 Z, G18 Y, G19 X), unless setting data SD42940
        // TOOL_LENGTH_CONST keeps it: under G18/G19 with the offsets on, the tool tip stands off the
        // programmed point by the tool's length, which is not read.
        let plane = plane_after(&words, self.interp.plane());
        let kept = self.interp.machine().and_then(|m| m.tool_length_const).and_then(plane_of_g).unwrap_or(plane);
        let length_axis = ['X', 'Y', 'Z'][kept.axes().2];
        if let Some((col, what)) = machine_coords {
            if !self.machine_move(what, col, motion, &words, length_axis, line, diags) {
                return false;
            }
        }
        let col = words.iter().map(|w| w.column).min().unwrap_or(first_col).min(first_col);
        if self.trc.busy() || selecting {
            // The holds: under compensation a held block's path and the corners after it are not
            // known, so the reading stops there, once (as compensation that cannot go on does); so
            // under 3D compensation, which is not read.
            let comp3d = self.comp3d.as_ref().map(|(l, k)| (col, format!("a compensated move while line {l}'s {k} (3D tool radius compensation, not read) is in force on the control until CUT2D")));
            if let Some((c, why)) = self.interp.held(&words).or(comp3d) {
                diags.error(line, c, format!("{why}; under tool radius compensation (G41/G42) the compensated path from here is not known, so the rest of the program is not read"));
                self.trc.engine = crate::program::cutter_comp::TncComp::default();
                self.stopped = true;
                return false;
            }
            let positions = positions || vector.is_some();
            return self.compensated(&words, &codes, motion, machine_coords.is_some(), positions, line, col, number, out, diags);
        }
        // The model's tool is along the spindle, its length on Z: a plane whose assignment is G17's reads.
        if positions && self.tool_offsets && length_axis != 'Z' && machine_coords.is_none() {
            let why = match self.interp.machine().and_then(|m| m.tool_length_const) {
                Some(k) => format!("the machine file's tool_length_const = {k} (SD42940) keeps a milling tool's length on {length_axis} in every plane"),
                None => format!(
                    "under G{} the 840D gives a milling tool's length to {length_axis}, the axis normal to the plane (NC programming 12/2019 §3.13.3.4), unless setting data SD42940 TOOL_LENGTH_CONST keeps it on Z (the machine file's tool_length_const = 17)",
                    if plane == crate::program::Plane::Zx { 18 } else { 19 }
                ),
            };
            diags.error(line, first_col, format!("a move with the tool's offsets on: {why}; the tool tip would stand off the programmed point by the tool's length, which is not read (D0, or G17)"));
            // The plane the line selects stays selected (the control makes the move all the same).
            self.interp.set_plane(plane);
            return false;
        }
        if !self.interp.block(&words, line, col, number, diags, out) {
            return false;
        }
        self.returned = m17;
        // MCALL: a block that moves the tool calls the cycle where it leaves it.
        if positions && self.mcall.is_some() && machine_coords.is_none() {
            return self.call_cycle(line, col, number, out, diags);
        }
        true
    }

    /// A refused block's G code that moves the tool ([`keywords::refused_move`]: its name, what, all
    /// axes, modal): the axes it moves (`axes`: those the block names) are unknown until written
    /// absolute; a modal one's later moves too.
    fn moved_unread_g(&mut self, refused: Option<(String, (&'static str, bool, bool))>, axes: [bool; 6], line: usize) {
        let Some((name, (what, all, modal))) = refused else { return };
        let axes = if all { [true, true, true, axes[3], axes[4], axes[5]] } else { axes };
        if modal {
            self.interp.forget_motion(line, &name, what, axes);
            self.tangent = None;
        } else {
            self.interp.moved_unread(line, &name, what, axes);
        }
    }

    /// A refused line's lasting statements (`lasting`, [`keywords::LASTING`]) and axial offset
    /// (`frame_g`, G58/G59): the control runs them, so they hold the moves after it.
    fn hold_refused(&mut self, lasting: &[(String, &'static keywords::Lasting)], frame_g: Option<&str>, line: usize) {
        for (name, l) in lasting {
            self.interp.hold_keyword(line, name, l.rule);
        }
        if let Some(g) = frame_g {
            self.interp.hold_keyword(line, &format!("G{g}"), &crate::program::interp::SIN_FRAME);
        }
    }

    /// A line refused with a cycle call in it (`calls`), which the control makes all the same unless
    /// it stops at an alarm of the call's own ([`Self::call_refused`]): an `MCALL`, whichever it was,
    /// holds the moves after it until an `MCALL` that is read (the modal call in force is not known);
    /// a cycle called once leaves every axis unknown (it drills where the tool stands, and leaves it
    /// at its retraction plane).
    fn calls_refused(&mut self, calls: &Calls, line: usize) {
        if self.call_refused.take() == Some(true) {
            return;
        }
        if calls.mcall {
            self.mcall = None;
            self.interp.hold_keyword(line, "MCALL", &crate::program::interp::SIN_MCALL);
        } else if let Some(name) = &calls.once {
            self.interp.moved_everywhere(line, name, "a cycle not read, which the control runs");
            self.tangent = None;
        }
    }

    /// A statement read (`name`): the holds of the refused statements it ends ([`keywords::LASTING`]).
    fn end_holds(&mut self, name: &str) {
        for l in LASTING.iter().filter(|l| l.ends.contains(&name)) {
            self.interp.end_keyword_hold(l.rule, [l.linear; 3], l.rotary);
        }
    }

}

/// The block's last G0-G3 (G group 1's motion codes the interpreter reads).
fn motion_g<'w, 'a>(words: &'w [Word<'a>]) -> Option<&'w Word<'a>> {
    words.iter().rev().find(|w| w.letter == 'G' && matches!(w.value as i64, 0..=3) && w.value.fract() == 0.0)
}

/// The plane G17/G18/G19 (`n`) selects.
fn plane_of_g(n: u32) -> Option<crate::program::Plane> {
    match n {
        17 => Some(crate::program::Plane::Xy),
        18 => Some(crate::program::Plane::Zx),
        19 => Some(crate::program::Plane::Yz),
        _ => None,
    }
}

/// The working plane after a line's words: its last G17/G18/G19, else `current`.
pub(super) fn plane_after(words: &[Word], current: crate::program::Plane) -> crate::program::Plane {
    words.iter().rev().find(|w| w.letter == 'G' && matches!(w.raw.as_ref(), "17" | "18" | "19")).and_then(|w| w.raw.parse().ok()).and_then(plane_of_g).unwrap_or(current)
}
