//! The modal state machine shared by the G-code readers: validated words of one block in, a
//! [`Block`] out. A block with a semantic defect changes no modal state and yields no block.

use std::borrow::Cow;

use super::lex::Diags;
use super::{ArcSpec, Block, Dialect, Feed, FeedMode, MCodeAction, MCodeRule, Motion, Orientation, Plane, Targets};
use crate::units::{DEG, INCH, MM};

/// One address word with a valid number.
#[derive(Debug, Clone, PartialEq)]
pub struct Word<'a> {
    pub letter: char,
    pub value: f64,
    /// The value as written (`43.4`, `+14.825`), for messages and G-code sub-numbers: borrowed from
    /// the program's text where it stands there (no allocation per word).
    pub raw: Cow<'a, str>,
    pub column: usize,
    /// Heidenhain `IX+5`: incremental for this word only.
    pub incremental: bool,
}

/// Modal state of a G-code program.
#[derive(Debug, Clone)]
pub struct Interpreter {
    dialect: Dialect,
    unit: f64,
    absolute: bool,
    motion: Option<Motion>,
    feed: Option<f64>,
    feed_mode: FeedMode,
    tcp: bool,
    /// Tool-centre-point kinematics switched on by the machine's own M code or at start (LinuxCNC's
    /// 5axiskins), which G49 (a tool length cancel) leaves on.
    kins_tcp: bool,
    datum: [f64; 3],
    /// Arc plane (G17/G18/G19) and whether I J K are absolute (G90.1) or from the start (G91.1).
    plane: Plane,
    arc_absolute: bool,
    /// Machine-specific M codes and what they do (`--m-code`; shared: a reader clones the
    /// interpreter to roll a refused block back).
    m_codes: std::sync::Arc<[MCodeRule]>,
    /// RS274: the work offsets the program set (`G10 L2 P1..P9`, m; a system it never set is taken as
    /// zero) and the active one (`G54`..`G59.3` = 0..8).
    offsets: [[f64; 3]; 9],
    system: usize,
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
    /// Last programmed absolute value of X Y Z A B C (SI).
    last: [f64; 6],
    /// The contour tolerance the program set (Heidenhain cycle 32, LinuxCNC G64 P/Q).
    tolerance: super::ProgrammedTolerance,
    /// A length unit imposed by the user (`--units`): the program's unit codes are noted, not obeyed.
    forced_unit: Option<super::LengthUnit>,
    /// Radians per program unit of the A, B and C words (degrees, unless the machine's control
    /// reads an axis in radians).
    rotary_unit: [f64; 3],
    /// The machine's coordinates (`G53`, `G28`), if its file places them.
    machine_coords: Option<std::sync::Arc<crate::machine::MachineCoordinates>>,
    /// How the next block is made, overriding the modal state for it alone (a reference return's
    /// legs, a canned cycle's moves).
    pub(crate) oneshot: Option<OneShot>,
    /// Fanuc canned cycles: the active cycle (G73-G89 until G80 or a motion code), its return level
    /// (G98 initial, G99 R point) and the intermediate points G28 stored.
    pub(crate) cycles: super::cycles::CycleState,
    /// The machine's rotary axis letters (for Haas' G28 with no axis: every axis).
    rotary_letters: [Option<char>; 2],
    /// The machine's peck distances (G73's retract, G83's clearance), m.
    peck: [Option<f64>; 2],
    /// How far an arc's end radius may differ from its start radius, m (the machine's control
    /// setting), and, where the control scales it with the radius, the fraction of the radius it may
    /// reach instead (Sinumerik MD21010 `CIRCLE_ERROR_FACTOR`; 0 elsewhere).
    arc_tolerance: f64,
    arc_tolerance_factor: f64,
    /// Haas G254 (dynamic work offset) in effect: no rotary axis may move until G255.
    dwo: bool,
    /// A tilted working plane in effect (Heidenhain PLANE, cycle 19): its frame in the workpiece
    /// (columns: the plane's X Y Z). X Y Z words, `last` and the arcs are in it.
    tilt: Option<nalgebra::Matrix3<f64>>,
    /// Heidenhain M126: rotary axes whose display is reduced below 360 deg take the shorter way;
    /// which letters name such (multi-turn) axes on the machine.
    shortest: bool,
    modulo: [bool; 3],
    /// The machine, whose kinematics place the tool where the program's coordinates change meaning
    /// (a plane tilted or reset, rotary axes moved without TCPM in a tilted plane).
    machine: Option<std::sync::Arc<crate::machine::Machine>>,
    /// Which work offsets (G54-G59.3) the program set (G10 L2, L20).
    offsets_given: [bool; 9],
    /// An additional work offset (Fanuc G54.1 P) is in effect.
    extra_offset: bool,
    /// A preset the program selects but cannot know (Heidenhain cycle 247) is in effect.
    preset_assumed: bool,
    /// Fanuc `G68.2`'s feature coordinate system in effect: its origin (m, in the workpiece
    /// coordinates), which the datum holds on top of the work offset until `G69`.
    pub(crate) feature: Option<[f64; 3]>,
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
            dialect,
            unit: MM,
            absolute: true,
            motion: None,
            feed: None,
            feed_mode: FeedMode::PerMinute,
            tcp: false,
            kins_tcp: false,
            datum: [0.0; 3],
            plane: Plane::Xy,
            arc_absolute: false,
            m_codes: std::sync::Arc::from([]),
            offsets: [[0.0; 3]; 9],
            system: 0,
            tool_vector: false,
            orientation: dialect.default_orientation(),
            centre: [None; 3],
            last_arc: None,
            pending_vector: None,
            last: [0.0; 6],
            tolerance: Default::default(),
            forced_unit: None,
            rotary_unit: [DEG; 3],
            machine_coords: None,
            oneshot: None,
            cycles: Default::default(),
            rotary_letters: [None; 2],
            peck: [None; 2],
            arc_tolerance: match dialect {
                Dialect::Sinumerik => SINUMERIK_CIRCLE_ERROR_CONST,
                Dialect::Klartext | Dialect::Heidenhain => TNC_CIRCLE_TOLERANCE,
                _ => ARC_RADIUS_TOLERANCE,
            },
            arc_tolerance_factor: if dialect == Dialect::Sinumerik { SINUMERIK_CIRCLE_ERROR_FACTOR } else { 0.0 },
            dwo: false,
            tilt: None,
            shortest: false,
            modulo: [false; 3],
            machine: None,
            offsets_given: [false; 9],
            extra_offset: false,
            preset_assumed: false,
            feature: None,
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
            self.modulo = ['A', 'B', 'C'].map(|l| m.axis_index(&l.to_string()).is_some_and(|i| i >= 3 && m.axes[i].limits.is_unlimited()));
            if let Some(t) = m.arc_radius_tolerance {
                self.arc_tolerance = t;
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
        }
        self
    }

    /// Read these machine-specific M codes as told (LinuxCNC remaps such as M428).
    pub fn with_m_codes(mut self, rules: &[MCodeRule]) -> Self {
        self.m_codes = rules.into();
        self
    }

    /// True if the program set work offset `k` (0 = G54) to anything but zero.
    fn offsets_set(&self, k: usize) -> bool {
        self.offsets[k] != [0.0; 3]
    }

    /// `G10 L2 Pn X Y Z`: set work offset n to the values; `G10 L20 Pn X Y Z`: set it so that the
    /// current point reads the values (LinuxCNC G-code reference §G10 L2, §G10 L20); P0 is the active
    /// system. Absolute values only; rotary offsets only where they stay zero.
    fn set_offsets(&self, words: &[Word], next: &mut Interpreter, line: usize, column: usize, diags: &mut Diags) {
        let word = |l: char| words.iter().find(|w| w.letter == l);
        let l20 = match word('L') {
            Some(w) if w.value == 2.0 => false,
            Some(w) if w.value == 20.0 => true,
            Some(w) => return diags.error(line, w.column, format!("G10 L{}: only L2 and L20 (set a work offset) are supported", w.raw)),
            None => return diags.error(line, column, "G10 without L: expected G10 L2 Pn or G10 L20 Pn (set a work offset)"),
        };
        let l = if l20 { "L20" } else { "L2" };
        let p = match word('P') {
            Some(w) if w.value.fract() == 0.0 && (0.0..=9.0).contains(&w.value) => w.value as usize,
            Some(w) => return diags.error(line, w.column, format!("G10 {l} P{}: expected a coordinate system 1 to 9, or 0 for the active one", w.raw)),
            None => return diags.error(line, column, format!("G10 {l} without P: expected the coordinate system (P1 = G54, P0 the active one)")),
        };
        let k_system = if p == 0 { next.system } else { p - 1 };
        if !next.absolute {
            return diags.error(line, column, format!("G10 {l} under G91 (offsets relative to the current ones) is not supported: write it under G90"));
        }
        let mut offsets = next.offsets[k_system];
        for w in words {
            let Some(k) = AXIS_LETTERS.iter().position(|&c| c == w.letter) else { continue };
            if k < 3 {
                // L20: the current point, in the offset-free (G53) frame, less the value it is to read.
                offsets[k] = if l20 { next.last[k] + next.datum[k] - w.value * next.unit } else { w.value * next.unit };
            } else {
                let u = next.rotary_unit[k - 3];
                let offset = if l20 { next.last[k] - w.value * u } else { w.value * u };
                if offset.abs() > 1e-12 {
                    diags.error(line, w.column, format!("G10 {l} {}{}: rotary-axis work offsets are not modelled (this one would be {:.6} deg)", w.letter, w.raw, offset / DEG));
                }
            }
        }
        if k_system == next.system {
            next.move_origin(offsets);
        }
        next.offsets[k_system] = offsets;
        next.offsets_given[k_system] = true;
    }

    /// Put the program origin at `offset` (RS274: the active work offset, m): the machine stays, so
    /// the current point's program coordinates change by the difference.
    fn move_origin(&mut self, offset: [f64; 3]) {
        for k in 0..3 {
            self.last[k] += self.datum[k] - offset[k];
        }
        self.datum = offset;
    }

    /// The last programmed position, absolute program coordinates (m, rad): X Y Z A B C.
    pub fn position(&self) -> [f64; 6] {
        self.last
    }

    /// True while tool-centre-point management is on.
    pub fn tcp(&self) -> bool {
        self.tcp
    }

    /// The arc plane in effect (G17/G18/G19).
    pub fn plane(&self) -> Plane {
        self.plane
    }

    /// The tool axis now, in the program's frame (the workpiece's, or the tilted plane's), from the
    /// rotary axes' last positions: None without a machine.
    pub(crate) fn tool_axis_now(&self) -> Option<nalgebra::Vector3<f64>> {
        let m = self.machine.as_ref()?;
        let axis = m.chain.forward(&self.joints_now()).axis;
        Some(self.tilt.map_or(axis, |r| r.transpose() * axis))
    }

    /// Switch tool-centre-point management (Sinumerik `TRAORI` / `TRAFOOF`).
    pub fn set_tcp(&mut self, on: bool) {
        self.tcp = on;
    }

    /// Switch the orientation interpolation (Sinumerik `ORIVECT`/`ORIAXES`, `ORIWKS`/`ORIMKS`).
    pub fn set_orientation(&mut self, orientation: Orientation) {
        self.orientation = orientation;
    }

    /// The tilted working plane in effect, if any (columns: its X Y Z in the workpiece).
    pub fn tilt(&self) -> Option<nalgebra::Matrix3<f64>> {
        self.tilt
    }

    /// Tilt the working plane (`None`: untilt). The tool stays: the current point is read anew in
    /// the new plane's coordinates (through the machine's kinematics where X Y Z were its axes).
    pub fn set_tilt(&mut self, tilt: Option<nalgebra::Matrix3<f64>>) {
        let axes = self.axes_now();
        self.tilt = tilt;
        self.read_axes(axes);
    }

    /// The rotary positions in the machine's order (its axes 3 and 4), rad, from the last words.
    pub(crate) fn rot_now(&self) -> [f64; 2] {
        self.rotary_letters.map(|l| l.and_then(|l| "ABC".find(l)).map_or(0.0, |k| self.last[3 + k]))
    }

    /// The machine's axes as they stand: [`Interpreter::axes_now`] and [`Interpreter::rot_now`].
    fn joints_now(&self) -> crate::kinematics::Joints {
        let (axes, rot) = (self.axes_now(), self.rot_now());
        [axes.x, axes.y, axes.z, rot[0], rot[1]]
    }

    /// Where the machine's linear axes stand (model frame, m): X Y Z themselves without TCPM or a
    /// tilted plane, else the tool tip placed through the kinematics.
    fn axes_now(&self) -> nalgebra::Vector3<f64> {
        let p = nalgebra::Vector3::new(self.last[0], self.last[1], self.last[2]);
        let d = nalgebra::Vector3::from(self.datum);
        match (&self.machine, self.tilt, self.tcp) {
            (_, None, false) | (None, _, _) => p + d,
            (Some(m), tilt, _) => m.chain.linear_for(&(tilt.map_or(p, |r| r * p) + d), &self.rot_now()),
        }
    }

    /// Where the linear axes go (model frame, m) when the tool backs off along its own axis by
    /// `distance` (m), or as far as the axes' ranges let it (`None`): Heidenhain's `M140 MB`.
    pub(crate) fn retract_target(&self, distance: Option<f64>) -> Result<[f64; 3], String> {
        let m = self.machine.as_ref().ok_or("the tool axis and the travel limits are the machine's: read the program on one (--machine)")?;
        let q = self.joints_now();
        let axes = nalgebra::Vector3::new(q[0], q[1], q[2]);
        let pose = m.chain.forward(&q);
        // The linear axes move the tool along its axis by this much per metre (a unit vector).
        let along = m.chain.linear_for(&(pose.tip + pose.axis), &[q[3], q[4]]) - axes;
        let t = match distance {
            Some(d) => d,
            None => (0..3)
                .filter(|&k| along[k].abs() > 1e-12)
                .map(|k| {
                    let lim = &m.axes[k].limits;
                    ((if along[k] > 0.0 { lim.max } else { lim.min }) - axes[k]) / along[k]
                })
                .fold(f64::INFINITY, f64::min)
                .max(0.0),
        };
        if !t.is_finite() {
            return Err("no linear axis moves along the tool axis".into());
        }
        let to = axes + along * t;
        Ok([to.x, to.y, to.z])
    }

    /// Read the axes standing at `axes` (model frame) in the current coordinates: X Y Z are the axes
    /// without TCPM or a tilted plane, else the tool tip (in the plane where tilted).
    fn read_axes(&mut self, axes: nalgebra::Vector3<f64>) {
        let d = nalgebra::Vector3::from(self.datum);
        let p = match (&self.machine, self.tilt, self.tcp) {
            (_, None, false) | (None, _, _) => axes - d,
            (Some(m), tilt, _) => {
                let rot = self.rot_now();
                let tip = m.chain.forward(&[axes.x, axes.y, axes.z, rot[0], rot[1]]).tip - d;
                tilt.map_or(tip, |r| r.transpose() * tip)
            }
        };
        self.last[..3].copy_from_slice(p.as_slice());
    }

    /// Switch tool-centre-point management and read the current point anew (Sinumerik `TRAORI` /
    /// `TRAFOOF`): the axes stay, their meaning changes, so an axis a later block does not name
    /// stays where it physically is.
    pub fn switch_tcp(&mut self, on: bool) {
        let axes = self.axes_now();
        self.tcp = on;
        self.read_axes(axes);
    }

    /// Set the frame in effect: `datum` (m) and a rotation (`None`: none), as the Sinumerik frames
    /// `TRANS`, `ROT` and their additive forms make them; the current point is read anew in it (the
    /// axes stay).
    pub fn set_frame(&mut self, datum: [f64; 3], tilt: Option<nalgebra::Matrix3<f64>>) {
        let axes = self.axes_now();
        self.datum = datum;
        self.tilt = tilt;
        self.read_axes(axes);
    }

    /// The datum shift in effect, m.
    pub fn datum(&self) -> [f64; 3] {
        self.datum
    }

    /// Shift the program origin (Sinumerik `TRANS`/`ATRANS` frames), m: program coordinates + datum =
    /// coordinates about the rotary axes. The machine stays; axes a later block does not name stay.
    pub fn set_datum(&mut self, datum: [f64; 3]) {
        self.datum = datum;
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

    /// The next block's tool vector (Sinumerik `A3= B3= C3=`, unit, workpiece frame).
    pub fn set_pending_vector(&mut self, v: [f64; 3]) {
        self.pending_vector = Some(v);
    }

    /// Set the program's length unit (Heidenhain header G70/G71, Klartext `BEGIN PGM ... INCH`),
    /// unless the user imposed one: then `Err` names the unit the program's numbers are read in.
    pub fn set_inch(&mut self, inch: bool) -> Result<(), super::LengthUnit> {
        match self.forced_unit {
            Some(u) if (u == super::LengthUnit::Inch) != inch => Err(u),
            Some(_) => Ok(()),
            None => {
                self.unit = if inch { INCH } else { MM };
                Ok(())
            }
        }
    }

    /// Interpret one block's words: the blocks it makes go to `out` (a reference return or a canned
    /// cycle makes several, a block of settings one without targets). Defects go to `diags` and
    /// make nothing, with the state unchanged; false then.
    pub fn block(&mut self, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
        if self.dialect.is_fanuc() {
            if let Some(done) = super::fanuc::expand(self, words, line, column, number, diags, out) {
                return done;
            }
        }
        match self.block_one(words, line, column, number, diags) {
            Some(b) => {
                out.push(b);
                true
            }
            None => false,
        }
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
            feed: self.feed.map(|value_per_min| Feed { value_per_min, mode: self.feed_mode }),
            tcp: self.tcp,
            datum: self.datum,
            orientation: self.orientation,
            events: Vec::new(),
            dwell_s: None,
            tolerance: self.tolerance,
            offset_assumed: self.offset_assumed(),
        }
    }

    /// Whether the datum in effect holds a work offset the program never set, taken as zero: on
    /// Fanuc and Haas every work offset is the operator's (G54, the reset state's, included) unless
    /// the program sets it with G10, G54.1 P's never; on Heidenhain and Sinumerik controls the
    /// workpiece preset (datum) always is (the program's datum shifts are relative to it).
    fn offset_assumed(&self) -> bool {
        self.preset_assumed
            || matches!(self.dialect, Dialect::Heidenhain | Dialect::Klartext | Dialect::Sinumerik)
            || self.dialect.is_fanuc() && (self.extra_offset || !self.offsets_given[self.system])
    }

    /// The modal motion and feed, to restore after a cycle's own moves.
    pub(crate) fn feed_state(&self) -> (Option<Motion>, Option<f64>, FeedMode) {
        (self.motion, self.feed, self.feed_mode)
    }

    /// Restore what [`Interpreter::feed_state`] saved.
    pub(crate) fn restore_feed(&mut self, (motion, feed, mode): (Option<Motion>, Option<f64>, FeedMode)) {
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

    /// The dialect read.
    pub(crate) fn dialect(&self) -> Dialect {
        self.dialect
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

    /// Interpret one block's words into one block (see [`Interpreter::block`]).
    pub(crate) fn block_one(&mut self, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags) -> Option<Block> {
        let shot = self.oneshot.take();
        if shot.is_some_and(|s| s.axes.is_some() && !s.own) && self.tilt.is_some() {
            let why = if self.dialect.is_fanuc() {
                "machine coordinates under a tilted working plane (G68.2): not read (what the control does with them there is not at hand); cancel the plane with G69 first"
            } else {
                "machine coordinates in a tilted working plane: the control refuses them (TNC 426 B ISO §7.3: \"M91 and M92 are not effective in a tilted working plane\"); reset the plane first"
            };
            diags.error(line, column, why);
            return None;
        }
        let mut next = self.clone();
        let errors_before = diags.errors();
        let mut datum_block = false;
        let mut events = Vec::new();
        let mut feed_word: Option<&Word> = None;
        // Heidenhain DIN/ISO and conversational share the TNC's words: modal circle centre I J K,
        // M128/M129, and the TNC's M functions.
        let heid = matches!(self.dialect, Dialect::Heidenhain | Dialect::Klartext);
        // Fanuc-style controls (Fanuc, Haas) and Haas alone.
        let (fanuc, haas) = (self.dialect.is_fanuc(), self.dialect == Dialect::Haas);
        // The TNC's DIN/ISO tool call `T1 G17`: the block's plane code is the tool axis.
        let tool_call = self.dialect == Dialect::Heidenhain && words.iter().any(|w| w.letter == 'T');

        // Modal G codes and M codes first: they govern how the axis words of this block are read.
        // A code that changes the motion and is not modelled is an error (fail closed), never skipped.
        let mut uses: Vec<char> = Vec::new(); // letters besides axes that a code of this block takes
        let mut g10 = false;
        let mut g53 = false;
        let mut dwell_word: Option<&Word> = None;
        let mut blend_word = false;
        for w in words {
            match w.letter {
                'G' => {
                    let code = w.raw.trim_start_matches('+');
                    let code = code.trim_start_matches('0');
                    let code = if code.is_empty() || code.starts_with('.') { format!("0{code}") } else { code.to_string() };
                    let unsupported = |diags: &mut Diags, what: &str| {
                        diags.error(line, w.column, format!("G{} ({what}) is not supported: it changes the motion", w.raw))
                    };
                    match (code.as_str(), heid) {
                        ("0", _) => next.motion = Some(Motion::Rapid),
                        ("1", _) => next.motion = Some(Motion::Linear),
                        ("2", false) => next.motion = Some(Motion::ArcCw),
                        ("3", false) => next.motion = Some(Motion::ArcCcw),
                        ("2", true) => next.motion = Some(Motion::ArcCw),
                        ("3", true) => next.motion = Some(Motion::ArcCcw),
                        // G05: a circle in the direction of the last G02/G03.
                        ("5", true) => match self.last_arc {
                            Some(m) => next.motion = Some(m),
                            None => diags.error(line, w.column, format!("G{}: a circle without its own direction needs a G02 or G03 before it", w.raw)),
                        },
                        ("6" | "12" | "13" | "15" | "16" | "25" | "26" | "27", true) => diags.error(
                            line,
                            w.column,
                            format!("G{} (tangential, polar or rounding arcs) is not supported in Heidenhain DIN/ISO yet: expected G00-G03 or G05", w.raw),
                        ),
                        ("17", _) => next.plane = Plane::Xy,
                        ("18" | "19" | "20", true) if tool_call => diags.error(
                            line,
                            w.column,
                            format!("T with G{}: a tool call along tool axis {} (only tool axis Z, G17, is modelled: the machine file's)", w.raw, ["Y", "X", "IV"][code.as_str().parse::<usize>().unwrap_or(18) - 18]),
                        ),
                        ("18", _) => next.plane = Plane::Zx,
                        ("19", _) => next.plane = Plane::Yz,
                        // Cutter compensation off, canned cycle cancel: no motion of their own.
                        ("40" | "80", _) => {}
                        ("90", _) => next.absolute = true,
                        ("91", _) => next.absolute = false,
                        ("90.1", false) => next.arc_absolute = true,
                        ("91.1", false) => next.arc_absolute = false,
                        ("70", true) | ("20", false) | ("71", true) | ("21", false) => {
                            let inch = code == "70" || code == "20";
                            match next.forced_unit {
                                None => next.unit = if inch { INCH } else { MM },
                                Some(u) if (u == super::LengthUnit::Inch) != inch => diags.warning(
                                    line,
                                    w.column,
                                    format!("G{}: the program says {}; its numbers are read in {} (--units)", w.raw, if inch { "inches" } else { "millimetres" }, u.name()),
                                ),
                                Some(_) => {}
                            }
                        }
                        ("54", true) => datum_block = true,
                        ("54" | "55" | "56" | "57" | "58" | "59" | "59.1" | "59.2" | "59.3", false) => {
                            let k = ["54", "55", "56", "57", "58", "59", "59.1", "59.2", "59.3"].iter().position(|c| *c == code).unwrap_or(0);
                            next.system = k;
                            next.extra_offset = false;
                            if k > 0 && !self.offsets_set(k) && !fanuc && self.dialect != Dialect::Sinumerik {
                                diags.warning(
                                    line,
                                    w.column,
                                    format!("G{}: this program never sets its offsets (G10 L2 P{}): taken as zero", w.raw, k + 1),
                                );
                            }
                        }
                        // LinuxCNC: the block's coordinates are absolute ones without the work offsets
                        // (G-code reference §G53: "machine coordinates", LinuxCNC's world frame, in
                        // which the machine files place the kinematics).
                        ("53", false) if self.dialect == Dialect::Rs274 => {
                            g53 = true;
                            if !next.absolute {
                                diags.error(line, w.column, "G53 under G91: LinuxCNC refuses incremental machine coordinates (write G90 first)");
                            }
                        }
                        ("53", false) => diags.warning(
                            line,
                            w.column,
                            "G53: work offsets are not modelled (G54 is taken as zero), so machine coordinates are read as program coordinates",
                        ),
                        // G98/G99: a canned cycle returns to the initial level or to the R point.
                        ("98" | "99", false) if fanuc => next.cycles.to_r = code == "99",
                        // Additional work offsets (Fanuc G54.1 P1-P48), which the program never sets here.
                        ("54.1", false) if fanuc => {
                            uses.push('P');
                            diags.warning(line, w.column, format!("G{}: additional work offsets are not set by the program: taken as zero", w.raw));
                            next.system = 0;
                            next.extra_offset = true;
                            next.move_origin([0.0; 3]);
                        }
                        // AI contour control (Q1 on, Q0 off): look-ahead feed control, not the path's
                        // geometry (FANUC A-63512EN §2.3: "interpolation data ensures that the machining
                        // follows a specified line or curve").
                        ("5.1", false) if fanuc => uses.push('Q'),
                        // Haas' smoothness: P the level (feed), E the most a corner may be rounded,
                        // which is the path's tolerance (Haas NGC manual, G187; Setting 85).
                        ("187", false) if haas => {
                            uses.extend(['P', 'E']);
                            next.tolerance = match words.iter().find(|w| w.letter == 'E') {
                                Some(e) if e.value >= 0.0 && crate::machine::ContourTolerance::linear_ok(e.value * next.unit) => {
                                    super::ProgrammedTolerance { linear_m: Some(e.value * next.unit), rotary_rad: None }
                                }
                                Some(e) => {
                                    diags.error(line, e.column, format!("G187 E{}: a corner rounding of 0 to 10 mm", e.raw));
                                    next.tolerance
                                }
                                None => super::ProgrammedTolerance::default(),
                            };
                        }
                        // Haas TCPC: X Y Z are the tool tip on the table (as Fanuc's G43.4), H the length.
                        ("234", false) if haas => {
                            (next.tcp, next.tool_vector) = (true, false);
                            uses.push('H');
                        }
                        // Haas DWO: the work offset turns with the rotary table (3+2 positioning only):
                        // "machine = MRZP + Rot(B,C) (G54 - MRZP) + program". With the offsets taken
                        // as zero (the part's origin on the rotary axes, this model's frame) the turned
                        // offset is the offset itself; an offset the program set is not turned here.
                        ("254", false) if haas => {
                            if next.datum != [0.0; 3] {
                                diags.error(line, w.column, "G254 (dynamic work offset) with a work offset the program set: turning it with the table is not modelled");
                            }
                            next.dwo = true;
                        }
                        ("255", false) if haas => next.dwo = false,
                        ("10", false) if fanuc && words.iter().any(|w| w.letter == 'L' && w.value == 20.0) => {
                            diags.error(line, w.column, "G10 L20: Fanuc's additional work offsets (G54.1 Pn) are not modelled");
                        }
                        ("10", false) => {
                            g10 = true;
                            uses.extend(['L', 'P']);
                        }
                        ("92.1" | "92.2", false) => {} // cancel G92 offsets: none are modelled
                        ("93", false) => next.feed_mode = FeedMode::InverseTime,
                        ("94", false) => next.feed_mode = FeedMode::PerMinute,
                        ("95", false) => diags.error(line, w.column, "G95 (feed per revolution) is not supported: expected G93 or G94"),
                        ("43.4", false) => {
                            (next.tcp, next.tool_vector) = (true, false);
                            uses.push('H');
                        }
                        ("43.5", false) => {
                            (next.tcp, next.tool_vector) = (true, true);
                            uses.push('H');
                        }
                        // The TCP G43.4/G43.5 turned on; the kinematics' own stays.
                        ("49", false) => (next.tcp, next.tool_vector) = (next.kins_tcp, false),
                        ("43", false) => {
                            uses.push('H');
                            diags.warning(
                                line,
                                w.column,
                                "G43 tool length offset: the tool length is the machine file's (tool_tip_mm), not the tool table's; \
                                 on a table-table machine it only shifts Z by a constant",
                            )
                        }
                        // Blending within a tolerance: what the planner does (P and Q: below).
                        ("64", false) => {
                            uses.extend(['P', 'Q']);
                            blend_word = true;
                        }
                        ("4", _) => {
                            uses.push('P');
                            dwell_word = Some(w);
                        }
                        ("61" | "61.1", false) => unsupported(diags, "exact stop mode: the planner blends blocks as G64 does"),
                        ("41" | "42" | "41.1" | "42.1", false) => unsupported(diags, "cutter radius compensation"),
                        ("43.1" | "43.2", false) => unsupported(diags, "dynamic tool length offset"),
                        ("68" | "68.2" | "68.3" | "68.4" | "69" | "53.1" | "53.6", false) => unsupported(diags, "coordinate rotation or tilted working plane"),
                        ("5" | "5.1" | "5.2" | "5.3" | "6.2", false) => unsupported(diags, "spline or NURBS motion"),
                        ("28" | "28.1" | "30" | "30.1", false) => unsupported(diags, "move to a stored position"),
                        ("33" | "33.1" | "76" | "38.2" | "38.3" | "38.4" | "38.5", false) => unsupported(diags, "threading or probing"),
                        ("73" | "74" | "81" | "82" | "83" | "84" | "85" | "86" | "87" | "88" | "89", false) => unsupported(diags, "canned cycle"),
                        ("92" | "92.3", false) => unsupported(diags, "coordinate system offset"),
                        ("7" | "8" | "50" | "51" | "52", false) => unsupported(diags, "diameter mode, scaling or local offset"),
                        _ => diags.error(
                            line,
                            w.column,
                            format!("unknown G code G{}: not read (it may change the motion)", w.raw),
                        ),
                    }
                }
                'M' => {
                    let code = w.value as i64;
                    if w.value.fract() != 0.0 || w.value < 0.0 {
                        diags.error(line, w.column, format!("M{}: expected a whole M code number", w.raw));
                        continue;
                    }
                    let rule = self.m_codes.iter().find(|r| i64::from(r.code) == code).map(|r| r.action);
                    match (rule, code, heid) {
                        (Some(MCodeAction::TcpOn), _, _) => (next.tcp, next.kins_tcp) = (true, true),
                        (Some(MCodeAction::TcpOff), _, _) => (next.tcp, next.kins_tcp) = (false, false),
                        (Some(MCodeAction::Event), _, _) => {}
                        (None, 128, true) => next.tcp = true,
                        // M126 / M127: the shorter way for rotary axes shown modulo 360 deg, on / off
                        // (TNC 620 10/2017 §13 "Shorter-path traverse of rotary axes: M126").
                        (None, 126, true) => next.shortest = true,
                        (None, 127, true) => next.shortest = false,
                        (None, 129, true) => next.tcp = false,
                        (None, 0..=9 | 13 | 14 | 30, _) => {}
                        // M91/M92: the Klartext reader made this block a move of the axes (its oneshot).
                        (None, 91 | 92, true) if shot.is_some_and(|s| s.axes.is_some()) => {}
                        (None, _, true) => {
                            if let Err(why) = tnc_m_code(code) {
                                diags.error(line, w.column, format!("M{}: {why}", w.raw));
                            }
                        }
                        // Sinumerik's own M functions (Fundamentals §"Miscellaneous functions (M)": M17
                        // end of subprogram, M19 spindle positioning, M40-M45 gear stages, M70 spindle
                        // to axis mode); any other is the machine maker's.
                        (None, 17 | 19 | 40..=45 | 70, false) if self.dialect == Dialect::Sinumerik => {}
                        (None, _, false) if self.dialect == Dialect::Sinumerik => diags.error(line, w.column, maker_m_function(&w.raw, code)),
                        // LinuxCNC's own M codes that move nothing: spindle orient, overrides, tool, I/O,
                        // with the words they take (G-code reference §M61 Q, §M62-M65 P, §M66 P E L Q,
                        // §M67/M68 E Q).
                        (None, 19 | 48..=53 | 60, false) => {}
                        (None, 61, false) => uses.push('Q'),
                        (None, 62..=65, false) => uses.push('P'),
                        (None, 66, false) => uses.extend(['P', 'E', 'L', 'Q']),
                        (None, 67 | 68, false) => uses.extend(['E', 'Q']),
                        (None, _, false) if fanuc => diags.error(line, w.column, maker_m_function(&w.raw, code)),
                        (None, _, false) => diags.error(
                            line,
                            w.column,
                            format!(
                                "M{} is not an RS274NGC M code: a machine-specific one (LinuxCNC user M100-M199 or a remap) \
                                 whose effect is unknown; say what it does with --m-code {}=tcp-on|tcp-off|event \
                                 (LinuxCNC's vismach five-axis demos: 428=tcp-on, 429=tcp-off)",
                                w.raw, code
                            ),
                        ),
                    }
                    events.push(format!("M{}", w.raw));
                }
                'T' | 'S' => events.push(format!("{}{}", w.letter, w.raw)),
                // Fanuc, Haas: D selects a cutter radius register, used only under G41/G42 (refused).
                'D' if fanuc => events.push(format!("D{}", w.raw)),
                'F' => feed_word = Some(w),
                'N' => {}
                c if AXIS_LETTERS.contains(&c) => {}
                'I' | 'J' | 'K' | 'R' | 'P' | 'Q' | 'H' | 'L' | 'E' if !heid => {} // checked below, with the codes that take them
                'I' | 'J' | 'K' | 'R' if heid => {} // circle centre and radius, read below
                'P' if heid => {} // a polar circle's turns (Klartext CP IPA beyond 360 deg): checked below
                _ => diags.error(
                    line,
                    w.column,
                    format!("unsupported word {}{}: not read (it may change the motion)", w.letter, w.raw),
                ),
            }
        }
        // The block's own motion: a one-shot's, else the modal one.
        let block_motion = shot.map(|s| s.motion).or(next.motion);
        let arc_motion = block_motion.is_some_and(Motion::is_arc);
        let vector_words = next.tool_vector && !arc_motion && !g10;
        if !heid {
            for w in words {
                let ok = match w.letter {
                    'I' | 'J' | 'K' => arc_motion || vector_words,
                    'R' => arc_motion,
                    'P' => arc_motion || uses.contains(&'P'),
                    'Q' | 'H' | 'L' | 'E' => uses.contains(&w.letter),
                    _ => true,
                };
                if !ok {
                    diags.error(line, w.column, format!("word {}{} without a G code that takes it: not read", w.letter, w.raw));
                }
            }
            if next.tool_vector && arc_motion {
                diags.error(line, column, "G02/G03 under G43.5 (tool vector mode) is not supported");
            }
        }
        if let Some(w) = words.iter().find(|w| heid && w.letter == 'P' && !arc_motion) {
            diags.error(line, w.column, format!("word P{} without a circle: not read", w.raw));
        }
        if g10 {
            // The axis words of a G10 block set an offset; they are not a move (skipped below).
            self.set_offsets(words, &mut next, line, column, diags);
        }
        // Sinumerik's settable frames (G54-G57, G505-G599) are the operator's, never set by the
        // program: the datum is the programmable frame's, which its reader keeps.
        if !heid && self.dialect != Dialect::Sinumerik && next.system != self.system {
            next.move_origin(next.offsets[next.system]);
        }

        // LinuxCNC's `G64 P- <Q->`: Q (the naive-CAM tolerance: near-collinear points within it merge
        // into one move; it is P when Q is not given) is how far the path may leave the programmed
        // points, the contour tolerance on the linear axes, program unit; `G64` alone leaves the
        // machine's. (gcodes §G64; interp_convert.cc `convert_control_mode`.)
        if blend_word && self.dialect == Dialect::Rs274 {
            let merge = words.iter().find(|w| w.letter == 'Q').or_else(|| words.iter().find(|w| w.letter == 'P'));
            next.tolerance = match merge {
                None => super::ProgrammedTolerance::default(),
                Some(w) => {
                    // Out of range, the block is refused (and the tolerance before it stays).
                    let v = w.value * next.unit;
                    if !crate::machine::ContourTolerance::linear_ok(v) {
                        let max = crate::machine::ContourTolerance::MAX.linear_m;
                        diags.error(line, w.column, format!("G64 {}{}: the path tolerance must be 0 to {} mm", w.letter, w.raw, max / MM));
                    }
                    super::ProgrammedTolerance { linear_m: Some(v), rotary_rad: None }
                }
            };
        }

        // A dwell's time, s: P in RS274NGC (LinuxCNC: "G4 P- dwell, seconds"), F in Sinumerik ("G4 F",
        // the programmed feed stays) and Heidenhain ("G04 F: dwell time in seconds"): that F is not a
        // feed. Sinumerik's G4 S (spindle revolutions, a time that depends on the speed) is not read.
        let mut dwell_s = None;
        if let Some(g) = dwell_word {
            let letter = if self.dialect.is_rs274_family() { 'P' } else { 'F' };
            let time = if letter == 'F' { feed_word.take() } else { words.iter().find(|w| w.letter == 'P') };
            if let Some(s) = words.iter().find(|w| w.letter == 'S').filter(|_| self.dialect == Dialect::Sinumerik) {
                diags.error(line, s.column, format!("G4 S{}: a dwell in spindle revolutions is not read (expected G4 F, seconds)", s.raw));
            }
            match time {
                // Fanuc and Haas: P in milliseconds (Haas: seconds with a decimal point).
                Some(t) if self.dialect.is_fanuc() => match super::fanuc::dwell(self.dialect, t) {
                    Ok(s) => dwell_s = Some(s),
                    Err(why) => diags.error(line, t.column, format!("G{} {why}", g.raw)),
                },
                Some(t) if t.value >= 0.0 && t.value.is_finite() => {
                    dwell_s = Some(t.value);
                    if self.dialect == Dialect::Rs274 && !t.raw.contains('.') && t.value >= 100.0 {
                        diags.warning(
                            line,
                            t.column,
                            format!("G4 P{}: a dwell of {} s (P is seconds in RS274NGC; a Fanuc control reads a P without a decimal point as milliseconds)", t.raw, t.value),
                        );
                    }
                }
                Some(t) => diags.error(line, t.column, format!("G{} {letter}{}: expected a dwell time of 0 s or more", g.raw, t.raw)),
                None => diags.error(line, g.column, format!("G{} without {letter}: expected the dwell time in seconds ({letter})", g.raw)),
            }
        }
        if let Some(w) = feed_word {
            if !(w.value > 0.0) {
                diags.error(line, w.column, format!("F{}: expected a positive feed", w.raw));
            } else {
                next.feed = Some(match next.feed_mode {
                    FeedMode::PerMinute => w.value * next.unit / MM,
                    FeedMode::InverseTime => w.value,
                });
            }
        }

        let mut targets = Targets::default();
        let mut datum = next.datum;
        for w in words {
            let Some(k) = AXIS_LETTERS.iter().position(|&c| c == w.letter) else { continue };
            if g10 {
                continue;
            }
            let scale = if k < 3 { next.unit } else { next.rotary_unit[k - 3] };
            let v = w.value * scale;
            if datum_block {
                if k < 3 {
                    datum[k] = v;
                } else {
                    diags.warning(line, w.column, format!("{}{} in a datum shift (G54) is not modelled", w.letter, w.raw));
                }
                continue;
            }
            let abs = if let (Some(origin), true) = (shot.and_then(|s| s.axes), k < 3) {
                // Axis positions (machine coordinates): the axes there, read in program coordinates.
                v + origin[k] - next.datum[k]
            } else if g53 && k < 3 {
                v - next.datum[k]
            } else if (next.absolute || shot.is_some_and(|s| s.absolute)) && !w.incremental {
                // M126 (it acts in its own block): a modulo axis goes the shorter way to the position.
                if k >= 3 && next.shortest && next.modulo[k - 3] {
                    crate::kinematics::unwrap_near(v, next.last[k])
                } else {
                    v
                }
            } else {
                next.last[k] + v
            };
            next.last[k] = abs;
            match k {
                0 => targets.x = Some(abs),
                1 => targets.y = Some(abs),
                2 => targets.z = Some(abs),
                3 => targets.a = Some(abs),
                4 => targets.b = Some(abs),
                _ => targets.c = Some(abs),
            }
        }
        next.datum = datum;
        // In a tilted plane the linear words are the plane's: the point, every coordinate of it,
        // in the workpiece; the control places the axes through the kinematics, as under TCPM.
        let linear_words = targets.x.is_some() || targets.y.is_some() || targets.z.is_some();
        if let (Some(r), true) = (next.tilt, linear_words) {
            let w = r * nalgebra::Vector3::new(next.last[0], next.last[1], next.last[2]);
            (targets.x, targets.y, targets.z) = (Some(w.x), Some(w.y), Some(w.z));
            if !next.tcp && (targets.a.is_some() || targets.b.is_some() || targets.c.is_some()) {
                diags.error(line, column, "linear and rotary axis words in one block in a tilted working plane without M128 / FUNCTION TCPM: position the rotary axes in a block of their own");
            }
        }
        if vector_words && words.iter().any(|w| "IJK".contains(w.letter)) {
            targets.tool_axis = tool_vector(words, &targets, line, column, diags);
        }
        if let Some(v) = next.pending_vector.take() {
            let (words, mode) = match self.dialect {
                Dialect::Klartext => ("TX TY TZ", "M128 or FUNCTION TCPM"),
                _ => ("A3 B3 C3", "TRAORI"),
            };
            if !next.tcp {
                diags.error(line, column, format!("tool vector ({words}) without {mode}: the orientation transformation is off"));
            } else if targets.a.is_some() || targets.b.is_some() || targets.c.is_some() {
                diags.error(line, column, format!("block with both a tool vector ({words}) and rotary-axis words: expected one of them"));
            } else {
                targets.tool_axis = Some(v);
            }
        }

        let moves = !targets.is_empty();
        // Haas: "Cancel G254 with G255 immediately after use and before ANY rotary motion" (G254, rule 5).
        if next.dwo && (targets.a.is_some() || targets.b.is_some() || targets.c.is_some()) {
            diags.error(line, column, "a rotary axis moves under G254 (dynamic work offset): Haas forbids it until G255");
        }
        // Sinumerik: "G4 must be programmed in a separate NC block" (Fundamentals, G4): a dwell with a
        // move is an alarm on the control, not a dwell and then a move as LinuxCNC reads it.
        if let (Some(g), true, Dialect::Sinumerik) = (dwell_word, moves, self.dialect) {
            diags.error(line, g.column, "G4 with axis words: Sinumerik runs a dwell only in a block of its own (G4 F, seconds)");
        }
        if moves && block_motion.is_none() {
            diags.error(line, column, "axis words without a motion mode: expected G00 or G01 first");
        }
        let mut arc = None;
        if heid {
            // I J K: the circle centre (the pole), absolute or, under G91, from the last position;
            // modal, and the tool does not move to it (iTNC 530 ISO programming, "Circle center I, J").
            for w in words.iter().filter(|w| "IJK".contains(w.letter)) {
                let k = "IJK".find(w.letter).unwrap_or(0);
                let v = w.value * next.unit;
                next.centre[k] = Some(if next.absolute { v } else { self.last[k] + v });
            }
            if let Some(w) = words.iter().find(|w| w.letter == 'R').filter(|_| !arc_motion) {
                diags.error(line, w.column, format!("R{}: a radius without G02/G03", w.raw));
            }
            if arc_motion && moves {
                let start = [self.last[0], self.last[1], self.last[2]];
                let end = [next.last[0], next.last[1], next.last[2]];
                let (a0, a1, _) = next.plane.axes();
                // The arc as an RS274 arc with an absolute centre: the modal I J K, or the block's R.
                let mut as_rs274: Vec<Word> = words.iter().filter(|w| w.letter == 'R').cloned().collect();
                if as_rs274.is_empty() {
                    for k in [a0, a1] {
                        match next.centre[k] {
                            Some(c) => as_rs274.push(Word { letter: ['I', 'J', 'K'][k], value: c / next.unit, raw: format!("{}", c / next.unit).into(), column, incremental: false }),
                            None => diags.error(line, column, format!("arc without a circle centre: expected {} (and {}) before or in this block, or R", ['I', 'J', 'K'][k], ['I', 'J', 'K'][a0 + a1 - k])),
                        }
                    }
                }
                let st = Interpreter { arc_absolute: true, ..next.clone() };
                if as_rs274.len() == 2 || as_rs274.iter().any(|w| w.letter == 'R') {
                    // A polar circle's turns (P), as RS274's.
                    as_rs274.extend(words.iter().filter(|w| w.letter == 'P').cloned());
                    arc = resolve_arc(&as_rs274, &st, start, end, line, column, diags);
                    // An arc in a tilted plane: its centre in the workpiece, its axes the plane's.
                    if let (Some(r), Some(a)) = (next.tilt, arc.as_mut()) {
                        let c = r * nalgebra::Vector3::from(a.centre);
                        a.centre = [c.x, c.y, c.z];
                        a.frame = Some(ArcSpec::frame_of(&r));
                    }
                }
            }
            if arc_motion {
                next.last_arc = next.motion;
            }
        }
        if arc_motion && !heid && !g10 {
            if moves {
                let start = [self.last[0], self.last[1], self.last[2]];
                let end = [next.last[0], next.last[1], next.last[2]];
                arc = resolve_arc(words, &next, start, end, line, column, diags);
            } else if words.iter().any(|w| "IJKRP".contains(w.letter)) {
                diags.error(line, column, "arc words without an end point: expected X, Y or Z with them");
            }
        }
        if moves && block_motion.is_some_and(|m| m == Motion::Linear || m.is_arc()) {
            match next.feed_mode {
                FeedMode::PerMinute if next.feed.is_none() => {
                    diags.error(line, column, "G01 move without a feed: expected an F word before or in this block")
                }
                FeedMode::InverseTime if feed_word.is_none() => {
                    diags.error(line, column, "G93 inverse-time move without F in the block: expected F (1/min)")
                }
                _ => {}
            }
        }
        let errors_after = diags.errors();
        if errors_after > errors_before {
            // The tool vector belonged to this block: it does not carry over to the next one.
            self.pending_vector = None;
            return None;
        }
        // In a tilted plane without TCPM a move of the rotary axes alone leaves the linear axes where
        // they stand, so the tool tip moves in the plane: read it anew.
        let rotary_only = !linear_words && (targets.a.is_some() || targets.b.is_some() || targets.c.is_some());
        let axes_before = (self.tilt.is_some() && !self.tcp && rotary_only).then(|| self.axes_now());
        *self = next;
        if let Some(axes) = axes_before {
            self.read_axes(axes);
        }
        Some(Block {
            line,
            column,
            number,
            motion: block_motion.unwrap_or(Motion::Linear),
            targets,
            arc,
            feed: self.feed.map(|value_per_min| Feed { value_per_min, mode: self.feed_mode }),
            tcp: (self.tcp || self.tilt.is_some() && (targets.x.is_some() || targets.y.is_some() || targets.z.is_some())) && !shot.is_some_and(|s| s.axes.is_some()),
            datum: self.datum,
            orientation: self.orientation,
            events,
            dwell_s,
            tolerance: self.tolerance,
            // A move of the machine's axes (machine coordinates) is where it is, whatever the datum.
            offset_assumed: self.offset_assumed() && !shot.is_some_and(|s| s.axes.is_some() && !s.own),
        })
    }
}

/// Why a machine maker's M function (on a Sinumerik, Fanuc or Haas control) is refused: what it does
/// is the machine's, said by its file or a flag.
fn maker_m_function(raw: &str, code: i64) -> String {
    format!("M{raw}: the machine maker's M function, whose effect is not known here: its machine file names it ([[m_function]]), or say what it does with --m-code {code}=tcp-on|tcp-off|event")
}

/// How far the radius to an arc's end may differ from the radius to its start, unless the machine
/// file says its control's (`arc_radius_tolerance_mm`, Fanuc parameter No. 3410): LinuxCNC's default
/// `[RS274NGC]CENTER_ARC_RADIUS_TOLERANCE_INCH` 0.00005 in (0.00127 mm); within it the control runs a
/// spiral (the radius changes evenly along the arc), beyond it the block is refused.
pub const ARC_RADIUS_TOLERANCE: f64 = 0.00005 * INCH;

/// Sinumerik's circle end-point check (alarm 14040): the radii to the start and the end may differ
/// by MD21000 `CIRCLE_ERROR_CONST` (default 0.01 mm) or, on larger circles, by the radius times
/// MD21010 `CIRCLE_ERROR_FACTOR` (default 0.001), whichever is larger.
pub const SINUMERIK_CIRCLE_ERROR_CONST: f64 = 0.01 * MM;

/// The TNC's: "The starting and end points of the arc must lie on the circle. Input tolerance: up
/// to 0.016 mm (selectable with MP 7431)" (TNC 407/415/425 user's manual §5, Circular path C around
/// the circle center CC; TNC 410 §6.4 the same): the largest, where the machine file sets none.
pub const TNC_CIRCLE_TOLERANCE: f64 = 0.016 * MM;
pub const SINUMERIK_CIRCLE_ERROR_FACTOR: f64 = 0.001;

/// The circle of a G02/G03 block from its I J K (centre) or R (radius) words (RS274/NGC 3 §3.5.3),
/// `start`/`end` the block's start and end point (program coordinates, m). Defects go to `diags`.
fn resolve_arc(words: &[Word], st: &Interpreter, start: [f64; 3], end: [f64; 3], line: usize, column: usize, diags: &mut Diags) -> Option<ArcSpec> {
    let (a0, a1, an) = st.plane.axes();
    let g = if st.motion == Some(Motion::ArcCw) { "G02" } else { "G03" };
    let offset_letter = ['I', 'J', 'K'];
    let word = |l: char| words.iter().find(|w| w.letter == l);
    if let Some(w) = word(offset_letter[an]) {
        diags.error(line, w.column, format!("{}{}: not an arc-centre word in the {:?} plane (G17/G18/G19)", w.letter, w.raw, st.plane));
        return None;
    }
    let extra_turns = match word('P') {
        None => 0,
        Some(w) if w.value.fract() == 0.0 && (1.0..=1000.0).contains(&w.value) => w.value as u32 - 1,
        Some(w) => {
            diags.error(line, w.column, format!("P{}: expected a whole number of turns, 1 to 1000", w.raw));
            return None;
        }
    };
    let (u0, v0, u1, v1) = (start[a0], start[a1], end[a0], end[a1]);
    let mut centre = start;
    match (word('R'), word(offset_letter[a0]).or(word(offset_letter[a1]))) {
        (Some(r), Some(_)) => {
            diags.error(line, r.column, format!("{g} with both R and a centre (I J K): expected one of them"));
            return None;
        }
        (None, None) => {
            diags.error(line, column, format!("{g} without a centre (I J K) or a radius (R)"));
            return None;
        }
        (None, Some(_)) => {
            for k in [a0, a1] {
                if let Some(w) = word(offset_letter[k]) {
                    let v = w.value * st.unit;
                    centre[k] = if st.arc_absolute { v } else { start[k] + v };
                }
            }
            let r0 = (u0 - centre[a0]).hypot(v0 - centre[a1]);
            let r1 = (u1 - centre[a0]).hypot(v1 - centre[a1]);
            if r0 < 0.1 * ARC_RADIUS_TOLERANCE || r1 < 0.1 * ARC_RADIUS_TOLERANCE {
                diags.error(line, column, format!("{g}: zero-radius arc (the centre is on its start or end point)"));
                return None;
            }
            let allowed = st.arc_tolerance.max(st.arc_tolerance_factor * r0);
            if (r0 - r1).abs() > allowed {
                diags.error(
                    line,
                    column,
                    format!(
                        "{g}: the radius to the end ({:.4} mm) differs from the radius to the start ({:.4} mm) by more than {:.5} mm",
                        r1 / MM,
                        r0 / MM,
                        allowed / MM
                    ),
                );
                return None;
            }
        }
        (Some(r), None) => {
            let radius = r.value * st.unit;
            let half = 0.5 * (u1 - u0).hypot(v1 - v0);
            if half == 0.0 {
                diags.error(line, r.column, format!("{g} R{}: the end point is the start point, so R gives no centre (a full circle needs I J K)", r.raw));
                return None;
            }
            if !(radius.abs() > 0.0) || half - radius.abs() > st.arc_tolerance {
                diags.error(line, r.column, format!("{g} R{}: the radius is too small to reach the end point ({:.4} mm away)", r.raw, 2.0 * half / MM));
                return None;
            }
            let h = (radius * radius - half * half).max(0.0).sqrt();
            // Centre on the left of the chord (turning from the plane's first axis towards its
            // second) for a short counter-clockwise arc; the other side for clockwise, and again for
            // R < 0 (longer than a semicircle).
            let (du, dv) = ((u1 - u0) / (2.0 * half), (v1 - v0) / (2.0 * half));
            let ccw = st.motion == Some(Motion::ArcCcw);
            let side = if ccw == (radius > 0.0) { 1.0 } else { -1.0 };
            centre[a0] = 0.5 * (u0 + u1) - side * h * dv;
            centre[a1] = 0.5 * (v0 + v1) + side * h * du;
        }
    }
    Some(ArcSpec { plane: st.plane, centre, extra_turns, frame: None })
}

/// The tool axis of a `G43.5` block from its `I J K` (all three, any length but zero; normalised as
/// the control does). Rotary-axis words beside a vector would contradict it: an error.
fn tool_vector(words: &[Word], targets: &Targets, line: usize, column: usize, diags: &mut Diags) -> Option<[f64; 3]> {
    let get = |l: char| words.iter().find(|w| w.letter == l).map(|w| w.value);
    let (Some(i), Some(j), Some(k)) = (get('I'), get('J'), get('K')) else {
        diags.error(line, column, "G43.5 tool vector: expected I, J and K together");
        return None;
    };
    if targets.a.is_some() || targets.b.is_some() || targets.c.is_some() {
        diags.error(line, column, "G43.5 block with both a tool vector (I J K) and rotary-axis words: expected one of them");
        return None;
    }
    let n = (i * i + j * j + k * k).sqrt();
    if !(n > 1e-9) {
        diags.error(line, column, "G43.5 tool vector I J K has zero length: expected a direction");
        return None;
    }
    Some([i / n, j / n, k / n])
}

/// Whether a Heidenhain TNC M function (besides M0-M9, M13, M14, M30, M128, M129) leaves the
/// programmed motion as this model runs it (iTNC 530 / TNC 640 User's Manual, "Miscellaneous
/// functions"); `Err` says why not. A machine's own M functions are refused until `--m-code` says.
fn tnc_m_code(code: i64) -> Result<(), &'static str> {
    match code {
        // Tool life, handwheel superposition (no motion of its own), look-ahead for radius
        // compensation (none is read), rotary shortest path off (the reset state), touch probe
        // monitoring, lift-off at NC stop.
        101 | 102 | 118 | 120 | 127 | 141 | 148 | 149 => Ok(()),
        91 | 92 | 130 => Err("positions in the machine coordinate system are not modelled (it changes the motion)"),
        89 | 99 => Err("cycle call: machining cycles are not read (they cut)"),
        103 | 109 | 110 | 116 | 136 => Err("changes how the feed is read: not modelled"),
        94 => Err("reducing the rotary axis display below 360 deg is not modelled (it changes later absolute positions)"),
        114 | 134 | 138 | 140 | 143 | 144 => Err("not modelled (it changes the motion)"),
        _ => Err("not a TNC M function that leaves the motion alone: a machine maker's own, whose effect is unknown; \
                  say what it does with --m-code CODE=tcp-on|tcp-off|event"),
    }
}
