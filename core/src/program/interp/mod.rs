//! The modal state machine shared by the G-code readers: validated words of one block in, a
//! [`Block`] out. A block with a semantic defect changes no modal state and yields no block.

use super::lex::Diags;
use super::{Block, Dialect, Feed, FeedMode, MCodeRule, Motion, Orientation, Plane, Targets};
use crate::units::{DEG, INCH, MM};

mod arc;
mod block;
mod codes;
mod frame;
mod g_codes;
mod lasting;
pub(crate) use lasting::{axes_named, axes_said, ran_unread_axes, tnc_m_rule, Rule, SIN_FEED, SIN_SWIVEL, SIN_FRAME, SIN_MCALL, SIN_ORIENT, SIN_ROTATE, SIN_TRANSFORM};
pub(crate) use g_codes::haas_extra_offset;
mod modal;
mod offsets;
mod rotation;
mod state_params;
mod word;

pub(crate) use modal::ModalState;
pub(crate) use rotation::rot;
pub(crate) use block::polar_step;
pub(crate) use codes::{lcnc_group, lcnc_refusal, m128_feed_said, x10};

pub use word::{Dimension, Turn, Word};
pub use arc::{ARC_RADIUS_TOLERANCE, SINUMERIK_CIRCLE_ERROR_CONST, SINUMERIK_CIRCLE_ERROR_FACTOR, TNC_CIRCLE_TOLERANCE};

/// Where a block left the tool ([`Interpreter::placement`]).
pub(crate) struct Placement {
    last: [f64; 6],
    placed: [bool; 6],
    stale: Option<lasting::Stale>,
}

/// Modal state of a G-code program: what a block may change, copied whole ([`State`]), and what it
/// shares or keeps on the heap. Its fields read as the state's (`Deref`).
#[derive(Debug, Clone)]
pub struct Interpreter {
    /// The state a block changes in place and a refused block puts back: one copy of bytes. The
    /// fields below are cloned with it (a reference count each; compensation's moves, when on, a
    /// copy), though only `tool_table` and `comp` ever change in a block.
    st: State,
    /// Machine-specific M codes and what they do (`--m-code`; shared: a reader clones the
    /// interpreter to roll a refused block back).
    m_codes: std::sync::Arc<[MCodeRule]>,
    /// LinuxCNC's cutter radius compensation and the moves it holds ([`super::cutter_comp`]), and the
    /// tool table its `G41`/`G42` take the radius from.
    pub(crate) comp: Option<Box<super::cutter_comp::CompState>>,
    /// Fanuc's NURBS mode (`G06.2`) and the curve it is reading ([`super::fanuc_nurbs`]).
    pub(crate) nurbs: Option<Box<super::fanuc_nurbs::Mode>>,
    /// Modal codes of refused blocks in effect on the control until their cancel ([`lasting`]).
    pub(crate) lasting: Vec<lasting::Lasting>,
    /// The last motion mode not read (its line, name and what it is): moves refused while the mode is
    /// unknown leave their axes unknown.
    pub(crate) forgotten: Option<(usize, String, &'static str)>,
    /// Fanuc's and Haas' additional work offsets a refused `G10 L20` set (P, line): selecting one is
    /// refused.
    pub(crate) refused_offsets: Vec<(u32, usize)>,
    /// The additional work offsets the program set with `G10 L20 Pn` (P, X Y Z in m); shared, as the
    /// interpreter is cloned for each block.
    extra_offsets: std::sync::Arc<Vec<(u32, [f64; 3])>>,
    /// After such a code's cancel: the axes whose position its moves left unknown.
    pub(crate) stale: Option<lasting::Stale>,
    /// The last block refused with a TNC M function the TNC runs (its line and code), for the holds
    /// to take: set where [`Interpreter::block_one`] refuses such a block.
    pub(crate) ran_unread: Option<(usize, i64)>,
    tool_table: Option<std::sync::Arc<super::cutter_comp::ToolTable>>,
    /// The machine's coordinates (`G53`, `G28`), if its file places them.
    machine_coords: Option<std::sync::Arc<crate::machine::MachineCoordinates>>,
    /// The machine, whose kinematics place the tool where the program's coordinates change meaning
    /// (a plane tilted or reset, rotary axes moved without TCPM in a tilted plane).
    machine: Option<std::sync::Arc<crate::machine::Machine>>,
}

/// The part of the modal state that is plain values: copied before each block, so a block with a
/// defect changes nothing.
#[derive(Debug, Clone, Copy)]
pub struct State {
    dialect: Dialect,
    unit: f64,
    /// The length unit of F (m per program unit): the geometry's, but for Sinumerik's G70/G71, which
    /// leave F in the basic system's unit.
    feed_unit: f64,
    absolute: bool,
    motion: Option<Motion>,
    /// F (mm/min, or 1/min in inverse time) and F for a move of the rotary axes alone (deg/min);
    /// per spindle revolution (mm, deg) under G95.
    feed: Option<(f64, f64)>,
    feed_mode: FeedMode,
    /// G95: F is a feed per spindle revolution, the path feed F times the spindle speed S
    /// ([`Interpreter::feed_now`]); `feed_mode` is then [`FeedMode::PerMinute`], as its blocks are.
    per_revolution: bool,
    /// The spindle as the program last commanded it: turning (M3, M4), stopped (M5, M19), or not
    /// commanded yet (None: whatever the machine was doing). A G95 feed move needs it turning.
    pub(crate) spindle_turning: Option<bool>,
    /// The way the last M3/M4 (M13/M14) turned it: counter-clockwise (M4), what LinuxCNC's G74 and
    /// G84 check.
    pub(crate) spindle_ccw: bool,
    tcp: bool,
    /// Tool-centre-point kinematics switched on by the machine's own M code or at start (LinuxCNC's
    /// 5axiskins), which G49 (a tool length cancel) leaves on.
    kins_tcp: bool,
    datum: [f64; 3],
    /// Arc plane (G17/G18/G19) and whether I J K are absolute (G90.1) or from the start (G91.1).
    plane: Plane,
    arc_absolute: bool,
    /// RS274: the work offsets the program set (`G10 L2 P1..P9`, m; a system it never set is taken as
    /// zero) and the active one (`G54`..`G59.3` = 0..8).
    offsets: [[f64; 3]; 9],
    system: usize,
    /// LinuxCNC: the axis offsets of G92 and G52 (m), on top of the active work offset in every
    /// system, and the copy parameters 5211-5213 keep for G92.3 (G92.2 leaves it, G92.1 zeroes it).
    axis_offset: [f64; 3],
    axis_offset_kept: [f64; 3],
    /// Fanuc: the local coordinate system G52 sets (m), the part of `axis_offset` that G92 cancels
    /// axis by axis ([`Interpreter::fanuc_offsets`]).
    pub(crate) local_offset: [f64; 3],
    /// LinuxCNC: each system's rotation about Z (`G10 L2 Pn R`, rad; parameter 5210 + 20n).
    rotation: [f64; 9],
    /// LinuxCNC: the interpreter's current X Y no longer where the machine stands (a rotated system's
    /// offset or rotation changed in use under a G92 offset, [`Interpreter::reframe_active`]): its
    /// next move names X and Y, and the machine goes there, whichever axes the block writes.
    xy_apart: bool,
    /// Blocks stay in the program frame when made (cutter compensation, which offsets them there,
    /// places them in the workpiece when it lets them go): [`Interpreter::to_world`].
    pub(crate) hold_frame: bool,
    /// LinuxCNC: the positions `G28.1` and `G30.1` stored (parameters 5161-5166, 5181-5186), in the
    /// workpiece frame (m, rad), where the program set them; else the machine file's.
    pub(crate) stored_home: [Option<[f64; 6]>; 2],
    /// The control stops at a block it refused (LinuxCNC at a move cutter compensation cannot
    /// make): its reader reads no further.
    pub(crate) halted: bool,
    /// Fanuc's and Haas' coordinate system rotation `G68` in effect, if any.
    pub(crate) rotation2d: Option<crate::program::fanuc_rotation::Rotation>,
    /// The last block refused that held G codes (its line): none of them took effect, which a later
    /// block's defect may stem from (said with it).
    pub(crate) refused_line: Option<usize>,
    /// Haas: the line where a feed move of a rotary axis in G94 without G234 was said, while such
    /// moves follow (said once for them; any other move, a rapid or a feed move of the linear axes
    /// alone or one under G93 or G234, ends the stretch).
    pub(crate) haas_rotary_feed_said: Option<usize>,
    /// The last refused block that carried an F word, while no block read since has set a feed:
    /// what a move without a feed names ([`Interpreter::after_refused_feed`]).
    pub(crate) refused_feed_line: Option<usize>,
    /// `G69` has cancelled it and no move of its plane's axes (these letters) has come since (the
    /// first must be absolute).
    pub(crate) after_g69: Option<[char; 2]>,
    pub(crate) tools: super::cutter_comp::Tools,
    /// The spindle speed the last `S` word set (as written, 1/min), for the macros that read it
    /// (LinuxCNC's `#<_rpm>`, Fanuc's `#4119`); None before any.
    pub(crate) spindle_speed: Option<f64>,
    /// Whether blocks end in a stop (G61, G61.1, G60; G64 blends): the modal mode.
    pub(crate) exact: crate::program::Exact,
    /// Sinumerik's G9 (its reader's): the next block stops at its end.
    pub(crate) exact_once: bool,
    /// Fanuc `G43.5`: tool-centre point with the tool axis written as a vector `I J K`.
    tool_vector: bool,
    /// How the tool orientation is interpolated under TCPM.
    orientation: Orientation,
    /// Heidenhain DIN/ISO: the circle centre `I J K` (absolute program coordinates, m; modal, set
    /// with or before the arc) and the direction of the last G02/G03 (for G05).
    centre: [Option<f64>; 3],
    last_arc: Option<Motion>,
    /// A tool vector the dialect's reader found in the next block (Sinumerik `A3= B3= C3=`), unit.
    pending_vector: Option<[f64; 3]>,
    /// The tool axis the last block with a tool vector wrote (FANUC G43.5 I J K), unit.
    pub(crate) last_vector: Option<[f64; 3]>,
    /// Last programmed absolute value of X Y Z A B C (SI).
    last: [f64; 6],
    /// Whether a move has placed each axis (an absolute position, or an increment from one): before
    /// that, `last` is a zero the program never said. Fanuc's G92 takes the tool's position.
    pub(crate) placed: [bool; 6],
    /// The contour tolerance the program set (Heidenhain cycle 32, LinuxCNC G64 P/Q).
    tolerance: super::ProgrammedTolerance,
    /// A length unit imposed by the user (`--units`): the program's unit codes are noted, not obeyed.
    forced_unit: Option<super::LengthUnit>,
    /// Radians per program unit of the A, B and C words (degrees, unless the machine's control
    /// reads an axis in radians).
    rotary_unit: [f64; 3],
    /// How the next block is made, overriding the modal state for it alone (a reference return's
    /// legs, a canned cycle's moves).
    pub(crate) oneshot: Option<OneShot>,
    /// Fanuc canned cycles: the active cycle (G73-G89 until G80 or a motion code), its return level
    /// (G98 initial, G99 R point) and the intermediate points G28 stored.
    pub(crate) cycles: super::cycles::CycleState,
    /// The machine's rotary axis letters (for Haas' G28 with no axis: every axis).
    rotary_letters: [Option<char>; 2],
    /// The machine's peck distances (G73's retract, G83's clearance), m: Fanuc's parameters.
    peck: [Option<f64>; 2],
    /// LinuxCNC's peck clearances of G73 and G83 where the machine file sets them, m.
    lcnc_peck: [Option<f64>; 2],
    /// How far an arc's end radius may differ from its start radius, m (the machine's control
    /// setting), and, where the control scales it with the radius, the fraction of the radius it may
    /// reach instead (Sinumerik MD21010 `CIRCLE_ERROR_FACTOR`; 0 elsewhere).
    arc_tolerance: f64,
    arc_tolerance_factor: f64,
    /// The program has said its unit (G20/G21, G70/G71, a header), or has been told that it did not.
    unit_stated: bool,
    /// Haas G254 (dynamic work offset) in effect: no rotary axis may move until G255.
    dwo: bool,
    /// X, Y and Z not written since G254: Haas wants them before a cutting move.
    dwo_unplaced: [bool; 3],
    /// The frame's rotation (`tilt`) turns the linear axes' coordinates only, with no transformation
    /// placing the tool (Sinumerik `ROT`/`AROT` without TRAORI or CYCLE800): axes = R p + datum,
    /// whatever the rotary axes; under TCPM it is a tilted plane as any other.
    frame_axes_only: bool,
    /// A tilted working plane in effect (Heidenhain PLANE, cycle 19): its frame in the workpiece
    /// (columns: the plane's X Y Z). X Y Z words, `last` and the arcs are in it.
    tilt: Option<nalgebra::Matrix3<f64>>,
    /// Heidenhain M126: rotary axes whose display is reduced below 360 deg take the shorter way;
    /// which letters name such (multi-turn) axes on the machine.
    shortest: bool,
    /// Heidenhain M109/M110 (M111 resets): the feed on arcs kept at the tool's cutting edge.
    arc_feed: crate::program::cutter_comp::ArcFeed,
    /// Heidenhain M116 (M117 resets): a rotary axis' F read in mm/min.
    m116: bool,
    modulo: [bool; 3],
    /// The program positioned the rotary axis with DC, ACP or ACN (the 840D's modulo positions).
    pub(crate) modulo_said: [bool; 3],
    /// Which work offsets (G54-G59.3) the program set (G10 L2, L20).
    offsets_given: [bool; 9],
    /// An additional work offset (Fanuc G54.1 P, Haas G154 P or G110-G129) is in effect.
    extra_offset: bool,
    /// Which one: its P (Haas' G110-G129 are P1-P20).
    extra_p: u32,
    /// A preset the program selects but cannot know (Heidenhain cycle 247) is in effect.
    preset_assumed: bool,
    /// Fanuc `G68.2`'s feature coordinate system in effect: its origin (m, in the workpiece
    /// coordinates), which the datum holds on top of the work offset until `G69`.
    pub(crate) feature: Option<[f64; 3]>,
}

impl std::ops::Deref for Interpreter {
    type Target = State;
    fn deref(&self) -> &State {
        &self.st
    }
}

impl std::ops::DerefMut for Interpreter {
    fn deref_mut(&mut self) -> &mut State {
        &mut self.st
    }
}

/// How one block is made whatever the modal state says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct OneShot {
    /// Its motion (the modal one stays).
    pub motion: Motion,
    /// Its axis words are absolute, whatever G90/G91 say.
    pub absolute: bool,
    /// Its linear words are axis positions about this origin (the model's frame, m): machine
    /// coordinates (`G53`, `M91`, a reference point: the machine zero), `M92`'s datum, or the axes'
    /// own positions (zero); the block moves the machine's axes, tool-centre-point management or not.
    pub axes: Option<[f64; 3]>,
    /// The axes move from where they stand, not to machine coordinates (Heidenhain's `M140`): as
    /// valid in a tilted working plane, and where they stand rests on the same work offset.
    pub own: bool,
}

impl OneShot {
    /// A move of the machine's axes to words in the control's machine coordinates, if the machine
    /// places them: their origin in the model's frame.
    pub(crate) fn machine_origin(it: &Interpreter) -> Option<[f64; 3]> {
        it.machine_coords.as_ref().map(|m| [m.zero.x, m.zero.y, m.zero.z])
    }
}

const AXIS_LETTERS: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

impl Interpreter {
    pub fn new(dialect: Dialect) -> Self {
        Interpreter {
            st: State {
                dialect,
                unit: MM,
                feed_unit: MM,
                absolute: true,
                motion: None,
                feed: None,
                feed_mode: FeedMode::PerMinute,
                per_revolution: false,
                spindle_turning: None,
                spindle_ccw: false,
                tcp: false,
                kins_tcp: false,
                datum: [0.0; 3],
                plane: Plane::Xy,
                arc_absolute: false,
                offsets: [[0.0; 3]; 9],
                system: 0,
                axis_offset: [0.0; 3],
                local_offset: [0.0; 3],
                axis_offset_kept: [0.0; 3],
                rotation: [0.0; 9],
                xy_apart: false,
                hold_frame: false,
                stored_home: [None; 2],
                halted: false,
                rotation2d: None,
                after_g69: None,
                refused_line: None,
                haas_rotary_feed_said: None,
                refused_feed_line: None,
                exact: crate::program::Exact::Blend,
                exact_once: false,
                tools: Default::default(),
                spindle_speed: None,
                tool_vector: false,
                orientation: dialect.default_orientation(),
                centre: [None; 3],
                last_arc: None,
                pending_vector: None,
                last_vector: None,
                last: [0.0; 6],
                placed: [false; 6],
                tolerance: Default::default(),
                forced_unit: None,
                rotary_unit: [DEG; 3],
                oneshot: None,
                // LinuxCNC's interpreter starts in G99 (interp_setup.cc: `retract_mode(R_PLANE)`); Fanuc's
                // and Haas' reset state is G98.
                cycles: super::cycles::CycleState { to_r: dialect == Dialect::Rs274, ..Default::default() },
                rotary_letters: [None; 2],
                peck: [None; 2],
                lcnc_peck: [None; 2],
                arc_tolerance: match dialect {
                    Dialect::Sinumerik => SINUMERIK_CIRCLE_ERROR_CONST,
                    Dialect::Klartext | Dialect::Heidenhain => TNC_CIRCLE_TOLERANCE,
                    _ => ARC_RADIUS_TOLERANCE,
                },
                arc_tolerance_factor: if dialect == Dialect::Sinumerik { SINUMERIK_CIRCLE_ERROR_FACTOR } else { 0.0 },
                unit_stated: false,
                dwo: false,
                dwo_unplaced: [false; 3],
                frame_axes_only: false,
                tilt: None,
                shortest: false,
                arc_feed: crate::program::cutter_comp::ArcFeed::Centre,
                m116: false,
                modulo: [false; 3],
                modulo_said: [false; 3],
                offsets_given: [false; 9],
                extra_offset: false,
                extra_p: 0,
                preset_assumed: false,
                feature: None,
            },
            m_codes: std::sync::Arc::from([]),
            comp: None,
            nurbs: None,
            lasting: Vec::new(),
            forgotten: None,
            refused_offsets: Vec::new(),
            extra_offsets: std::sync::Arc::default(),
            ran_unread: None,
            stale: None,
            tool_table: None,
            machine_coords: None,
            machine: None,
        }
    }

    /// Read the rotary words in the units this machine's control reads them in.
    pub fn with_machine(mut self, machine: Option<&std::sync::Arc<crate::machine::Machine>>) -> Self {
        self.machine = machine.cloned();
        if let Some(m) = machine {
            self.tcp |= m.tcp_at_start;
            self.kins_tcp |= m.tcp_at_start;
            self.rotary_unit = ['A', 'B', 'C'].map(|l| m.rotary_word_unit(l));
            self.machine_coords = m.machine_coordinates.clone().map(std::sync::Arc::new);
            self.rotary_letters = [3, 4].map(|k| m.axes[k].name.chars().next().map(|c| c.to_ascii_uppercase()));
            self.peck = m.peck_distances;
            self.lcnc_peck = m.linuxcnc_peck_clearances;
            self.modulo = ['A', 'B', 'C'].map(|l| m.axis_index(&l.to_string()).is_some_and(|i| i >= 3 && m.axes[i].limits.is_unlimited()));
            if let Some(t) = m.arc_radius_tolerance {
                self.arc_tolerance = t;
            }
            // Fanuc, Haas: the motion mode the control starts in, as the machine's parameter sets it.
            if self.dialect.is_fanuc() && self.motion.is_none() {
                self.motion = m.power_on_motion;
            }
            // The 840D's basic system: the unit a program starts in, and F's under G70/G71.
            if m.inch_basic_system && self.dialect == Dialect::Sinumerik && self.forced_unit.is_none() {
                (self.unit, self.feed_unit) = (INCH, INCH);
            }
        }
        self
    }

    /// Start with this orientation interpolation (the machine's setting) instead of the dialect's default.
    pub fn with_orientation(mut self, orientation: Orientation) -> Self {
        self.orientation = orientation;
        self
    }

    /// Read every length in `units` whatever the program's own unit codes say (`--units`).
    pub fn with_units(mut self, units: Option<super::LengthUnit>) -> Self {
        self.forced_unit = units;
        if let Some(u) = units {
            self.unit = u.metres();
            self.feed_unit = self.unit;
        }
        self
    }

    /// Read these machine-specific M codes as told (LinuxCNC remaps such as M428).
    pub fn with_m_codes(mut self, rules: &[MCodeRule]) -> Self {
        self.m_codes = rules.into();
        self
    }

    /// The modal motion of G group 1, if one is in effect.
    pub(crate) fn motion(&self) -> Option<Motion> {
        self.motion
    }

    /// The last programmed position, absolute program coordinates (m, rad): X Y Z A B C.
    pub fn position(&self) -> [f64; 6] {
        self.last
    }

    /// Where a held block left the tool: its position, the axes placed and those still unknown, to
    /// keep when its reader takes the rest of its line's state back ([`Interpreter::set_placement`]).
    pub(crate) fn placement(&self) -> Placement {
        Placement { last: self.last, placed: self.placed, stale: self.stale.clone() }
    }

    /// Put back a [`Placement`]: the control made the held block's move, so its end is where the
    /// tool is (the axes it did not write absolute stay unknown).
    pub(crate) fn set_placement(&mut self, p: Placement) {
        (self.last, self.placed, self.stale) = (p.last, p.placed, p.stale);
    }

    /// Put the current point's X and Y at `xy` (program coordinates, m): where the machine stands when
    /// the control takes its position from it (LinuxCNC after a tool change).
    pub(crate) fn set_position_xy(&mut self, xy: [f64; 2]) {
        self.set_position_pair([0, 1], xy);
    }

    /// Put the current point's coordinates `axes` (0 X, 1 Y, 2 Z) at `v` (program coordinates, m).
    pub(crate) fn set_position_pair(&mut self, axes: [usize; 2], v: [f64; 2]) {
        self.last[axes[0]] = v[0];
        self.last[axes[1]] = v[1];
    }

    /// True while tool-centre-point management is on.
    pub fn tcp(&self) -> bool {
        self.tcp
    }

    /// The arc plane in effect (G17/G18/G19).
    pub fn plane(&self) -> Plane {
        self.plane
    }

    /// Switch the orientation interpolation (Sinumerik `ORIVECT`/`ORIAXES`, `ORIWKS`/`ORIMKS`).
    pub fn set_orientation(&mut self, orientation: Orientation) {
        self.orientation = orientation;
    }

    /// How the feed on arcs is read (Heidenhain M109/M110/M111).
    pub(crate) fn arc_feed(&self) -> crate::program::cutter_comp::ArcFeed {
        self.arc_feed
    }

    /// The contour tolerance the program set (Heidenhain cycle 32, LinuxCNC G64 P/Q), for the blocks
    /// that follow.
    pub fn tolerance(&self) -> super::ProgrammedTolerance {
        self.tolerance
    }

    /// Set the contour tolerance for the blocks that follow.
    pub fn set_tolerance(&mut self, tolerance: super::ProgrammedTolerance) {
        self.tolerance = tolerance;
    }

    /// The length unit in effect (m per program unit).
    pub fn unit(&self) -> f64 {
        self.unit
    }

    /// Inverse-time feed (G93) is in effect.
    pub fn inverse_time(&self) -> bool {
        self.feed_mode == FeedMode::InverseTime
    }

    /// The length unit of F (m per program unit): [`Interpreter::unit`] but under Sinumerik's G70/G71.
    pub fn feed_unit(&self) -> f64 {
        self.feed_unit
    }

    /// The next block's tool vector (Sinumerik `A3= B3= C3=`, unit, workpiece frame).
    pub fn set_pending_vector(&mut self, v: [f64; 3]) {
        self.pending_vector = Some(v);
    }

    /// The tool vector a block set for its move, not yet taken (to put back when it is refused).
    pub(crate) fn pending_vector(&self) -> Option<[f64; 3]> {
        self.pending_vector
    }

    /// Put back what [`Interpreter::pending_vector`] gave.
    pub(crate) fn restore_pending_vector(&mut self, v: Option<[f64; 3]>) {
        self.pending_vector = v;
    }

    /// Select the working plane (a line refused for what its move would do leaves the plane it selects).
    pub(crate) fn set_plane(&mut self, plane: Plane) {
        self.plane = plane;
    }

    /// The length F is in per minute (m), where the control reads it in its own unit: the TNC's inch
    /// programs give F in 1/10 inch/min.
    pub(crate) fn set_feed_unit(&mut self, unit: f64) {
        self.feed_unit = unit;
    }

    /// Set the program's length unit (Heidenhain header G70/G71, Klartext `BEGIN PGM ... INCH`),
    /// unless the user imposed one: then `Err` names the unit the program's numbers are read in.
    pub fn set_inch(&mut self, inch: bool) -> Result<(), super::LengthUnit> {
        match self.forced_unit {
            Some(u) if (u == super::LengthUnit::Inch) != inch => Err(u),
            Some(_) => Ok(()),
            None => {
                self.unit = if inch { INCH } else { MM };
                self.feed_unit = self.unit;
                Ok(())
            }
        }
    }

    /// Interpret one block's words: the blocks it makes go to `out` (a reference return or a canned
    /// cycle makes several, a block of settings one without targets). Defects go to `diags` and
    /// make nothing, with the state unchanged; false then.
    pub fn block(&mut self, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
        // LinuxCNC: what its interpreter refuses in the block's words (Fanuc takes the last G of a group).
        if self.dialect == Dialect::Rs274 {
            if let Some((col, why)) = lcnc_refusal(words, self.inverse_time(), self.feed.is_some(), self.tool_table()) {
                diags.error(line, col, why);
                return false;
            }
        }
        let held = self.held(words);
        let start = out.len();
        let done = match super::cutter_comp::block(self, words, line, column, number, diags, out) {
            Some(done) => done,
            None => self.block_plain(words, line, column, number, diags, out),
        };
        if done {
            self.after_held(words, line, true);
            // A mode is known again (a G0-G3), or none is (LinuxCNC's G80): the mode not read has ended.
            if self.motion.is_some() || words.iter().any(|w| w.letter == 'G' && codes::x10(w) == 800) {
                self.forgotten = None;
            }
        } else {
            self.refused_block(words, line);
        }
        self.note_feed(done, words.iter().any(|w| w.letter == 'F'), line);
        // A move under a held code: read for the state, its moves not made.
        if let Some((col, why)) = held {
            out.truncate(start);
            diags.error(line, col, why);
            return false;
        }
        done
    }

    /// After a block is refused (here or by the TNC's DIN/ISO reader under radius compensation): a
    /// move in a motion mode not read, a TNC M function not read that the control runs (the axes
    /// the block names unknown; a cycle call's M89/M99 X Y Z, M94 the rotary axes too), the codes
    /// the control keeps ([`lasting`]).
    pub(crate) fn refused_block(&mut self, words: &[Word], line: usize) {
        self.moved_in_unread_mode(axes_named(self.dialect, words));
        // (A lasting one holds the moves instead, [`lasting`].)
        if let Some((l, m)) = self.ran_unread.take().filter(|&(l, m)| l == line && lasting::tnc_m_rule(m).is_none()) {
            let axes = lasting::ran_unread_axes(m, axes_named(self.dialect, words), self.rotary_axes());
            self.moved_unread(l, &format!("M{m}"), lasting::RAN_UNREAD, axes);
        }
        self.refused(words, line);
    }

    /// [`Interpreter::block`] without cutter radius compensation.
    pub(crate) fn block_plain(&mut self, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
        if self.dialect.is_fanuc() {
            if let Some(done) = super::fanuc::expand(self, words, line, column, number, diags, out) {
                return done;
            }
        }
        if self.dialect != Dialect::Rs274 {
            return self.block_made(words, line, column, number, diags, out);
        }
        // LinuxCNC: made in the program frame, then placed in the workpiece's (a rotated system).
        let start = out.len();
        let done = match super::lcnc_home::expand(self, words, line, column, number, diags, out) {
            Some(done) => done,
            None => match super::lcnc_cycles::expand(self, words, line, column, number, diags, out) {
                Some(done) => done,
                None => self.block_made(words, line, column, number, diags, out),
            },
        };
        if !self.hold_frame && self.rotation_now() != 0.0 {
            for b in &mut out[start..] {
                self.to_world(b);
            }
        }
        done
    }

    /// The block [`Interpreter::block_one`] makes, to `out`; false if a defect.
    fn block_made(&mut self, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
        match self.block_one(words, line, column, number, diags) {
            Some(b) => {
                out.push(b);
                true
            }
            None => false,
        }
    }

    /// The active work offset system (`G54`..`G59.3` = 0..8).
    pub(crate) fn system(&self) -> usize {
        self.system
    }

    /// The tool table `G41`/`G42` take their radius from (`--tool-table`), if given.
    pub(crate) fn tool_table(&self) -> Option<&super::cutter_comp::ToolTable> {
        self.tool_table.as_deref()
    }

    /// The program ends with this tool table (its reader's set-up).
    pub(crate) fn with_tool_table(mut self, table: Option<std::sync::Arc<super::cutter_comp::ToolTable>>) -> Self {
        self.tool_table = table;
        self
    }

    /// The machine the program runs on, if the reader knows it.
    pub(crate) fn machine(&self) -> Option<&std::sync::Arc<crate::machine::Machine>> {
        self.machine.as_ref()
    }

    /// The rotary axes' letters, in the machine's order (its axes 3 and 4).
    pub(crate) fn rotary_letters(&self) -> [Option<char>; 2] {
        self.rotary_letters
    }

    /// The machine's coordinates, where its file places them.
    pub fn machine_coords(&self) -> Option<&crate::machine::MachineCoordinates> {
        self.machine_coords.as_deref()
    }

    /// A block that moves nothing, with the state in effect (a dwell's, a cycle's events').
    pub(crate) fn still_block(&self, line: usize, column: usize, number: Option<u64>) -> Block {
        Block {
            line,
            column,
            number,
            motion: self.motion.unwrap_or(Motion::Linear),
            targets: Targets::default(),
            arc: None,
            feed: self.feed_now(),
            tcp: self.tcp,
            datum: self.datum,
            orientation: self.orientation,
            events: Vec::new(),
            dwell_s: None,
            tolerance: self.tolerance,
            offset_assumed: self.offset_assumed(),
            exact: self.exact,
        }
    }

    /// Whether the datum in effect holds a work offset the program never set, taken as zero: on
    /// Fanuc and Haas every work offset is the operator's (G54, the reset state's, included) unless
    /// the program sets it with G10 (L2 for G54-G59, L20 for the additional ones); on Heidenhain and Sinumerik controls the
    /// workpiece preset (datum) always is (the program's datum shifts are relative to it).
    fn offset_assumed(&self) -> bool {
        self.preset_assumed
            || matches!(self.dialect, Dialect::Heidenhain | Dialect::Klartext | Dialect::Sinumerik)
            || self.dialect.is_fanuc() && if self.extra_offset { self.extra_offset_value(self.extra_p).is_none() } else { !self.offsets_given[self.system] }
    }

    /// The feed in effect, as a block carries it.
    /// Under G95 the feed per minute is F times the spindle speed S, "V = n * F" (SINUMERIK
    /// Function Manual Basic Functions, Feeds (V1) §2.1 "Revolutional feedrate (G95)"; LinuxCNC:
    /// "the controlled point should move a certain number of inches per revolution of the spindle"):
    /// none while no S is set.
    pub(crate) fn feed_now(&self) -> Option<Feed> {
        let per_rev = if self.per_revolution { self.spindle_speed.filter(|s| *s > 0.0)? } else { 1.0 };
        self.feed.map(|(value, rotary)| Feed { value_per_min: value * per_rev, rotary_per_min: rotary * per_rev, mode: self.feed_mode })
    }

    /// G95 (feed per revolution) is in effect.
    pub(crate) fn per_revolution(&self) -> bool {
        self.per_revolution
    }

    /// The modal motion and feed, to restore after a cycle's own moves.
    pub(crate) fn feed_state(&self) -> (Option<Motion>, Option<(f64, f64)>, FeedMode) {
        (self.motion, self.feed, self.feed_mode)
    }

    /// Restore what [`Interpreter::feed_state`] saved.
    pub(crate) fn restore_feed(&mut self, (motion, feed, mode): (Option<Motion>, Option<(f64, f64)>, FeedMode)) {
        (self.motion, self.feed, self.feed_mode) = (motion, feed, mode);
    }

    /// A preset of the machine's table is in effect (Heidenhain cycle 247): its values are the
    /// operator's, taken as the workpiece datum, so linear ranges are not judged.
    pub(crate) fn set_preset_assumed(&mut self) {
        self.preset_assumed = true;
    }

    /// Whether G90 is in effect.
    pub(crate) fn absolute(&self) -> bool {
        self.absolute
    }

    /// M126 is in effect and rotary axis `k` (0 = A) is a modulo one: an absolute position goes the
    /// shorter way.
    pub(crate) fn shortest_way(&self, k: usize) -> bool {
        self.shortest && self.modulo[k]
    }

    /// The dialect read.
    pub(crate) fn dialect(&self) -> Dialect {
        self.dialect
    }

    /// The program's unit of rotary axis `k` (0 = A), rad per unit (deg, or rad on machines whose
    /// control reads radians).
    pub(crate) fn rotary_unit(&self, k: usize) -> f64 {
        self.rotary_unit[k]
    }

    /// Whether rotary axis `k` (0 = A) turns without end (its positions modulo a turn).
    pub(crate) fn modulo(&self, k: usize) -> bool {
        self.modulo[k]
    }

    /// Whether the machine has axis `letter` (X Y Z always; a rotary one if the machine names it).
    pub(crate) fn has_axis(&self, letter: char) -> bool {
        "XYZ".contains(letter) || self.rotary_letters.contains(&Some(letter))
    }

    /// The distance d of a peck cycle (G73's retract, G83's clearance), m: the machine's setting.
    pub(crate) fn peck_clearance(&self, kind: super::cycles::Kind) -> Result<f64, &'static str> {
        match kind {
            super::cycles::Kind::G73 => self.peck[0].ok_or("the machine file gives no G73 retract (canned_cycles.g73_retract_mm: Fanuc parameter No. 5114, Haas Setting 22)"),
            _ => self.peck[1].ok_or("the machine file gives no G83 clearance (canned_cycles.g83_clearance_mm: Fanuc parameter No. 5115)"),
        }
    }

    /// LinuxCNC's peck clearance of G73 or G83, m, where the machine file sets it (LinuxCNC 2.10's
    /// INI settings, `canned_cycles.g73_peck_clearance_mm` and `g83_peck_clearance_mm`).
    pub(crate) fn lcnc_peck_clearance(&self, kind: super::cycles::Kind) -> Option<f64> {
        self.lcnc_peck[usize::from(kind != super::cycles::Kind::G73)]
    }
}
