//! Machine model: three linear and two rotary axes with their limits, and the kinematic chain that
//! links the machine axes to the tool pose in the workpiece frame. A four-axis machine (one rotary
//! axis) fills the second rotary slot with a locked, unnamed axis held at 0 (`TwoRotaryChain::four_axis`).
//!
//! Machines are described in TOML (the built-in ones live in `machines/*.toml` and are compiled in).
//! File fields carry people's units in their names (mm, deg, mm/min); the model itself is SI
//! (m, rad, s), as REP 103 asks of everything that crosses the bus.

mod file;
pub mod urdf;

pub use file::{CannedCyclesFile, CycleFile, LinearAxisFile, MFunctionFile, MachineCoordinatesFile, MachineFile, QuillFile, RotaryAxisFile, SwivelFile};

use crate::kinematics::{unwrap_near, Carrier, Joints, KinematicsError, Pose, RotaryJoint, TwoRotaryChain};
use nalgebra::Vector3;

/// Number of machine axes: X, Y, Z and two rotary axes.
pub const AXES: usize = 5;

/// Whether an axis translates (m) or rotates (rad).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AxisKind {
    Linear,
    Rotary,
}

/// Position range and dynamic limits of one axis, SI (m or rad, per s, s^2, s^3).
/// An unlimited (multi-turn) rotary axis has an infinite range.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct AxisLimits {
    pub min: f64,
    pub max: f64,
    pub velocity: f64,
    pub acceleration: f64,
    pub jerk: f64,
}

impl AxisLimits {
    /// True if `q` lies in the position range (with a small tolerance for rounding in programs).
    pub fn contains(&self, q: f64) -> bool {
        const TOL: f64 = 1e-9;
        q >= self.min - TOL && q <= self.max + TOL
    }
    /// True for a rotary axis without end stops.
    pub fn is_unlimited(&self) -> bool {
        self.min == f64::NEG_INFINITY && self.max == f64::INFINITY
    }
}

/// One machine axis.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Axis {
    pub name: String,
    pub kind: AxisKind,
    pub limits: AxisLimits,
}

/// A five-axis machine: axes `[X, Y, Z, R1st, R2nd]` (rotaries in the file's order) and its chain; a
/// four-axis machine's `R2nd` is the chain's locked joint: unnamed, range 0..0.
#[derive(Debug, Clone)]
pub struct Machine {
    pub name: String,
    pub description: String,
    /// Who makes it, as program headers write it (`Haas`); `generic` for a kinematic class's model.
    pub maker: Option<String>,
    /// The model as program headers write it (`UMC-750`), or a generic model's class.
    pub model: Option<String>,
    /// The control that runs it (`Heidenhain iTNC 530`).
    pub control: Option<String>,
    /// The dialect its control reads: generic G-code files for it are read in it.
    pub dialect: Option<crate::program::Dialect>,
    pub axes: [Axis; AXES],
    pub chain: TwoRotaryChain,
    /// The control's contour tolerance where a program sets none (Heidenhain cycle 32 `T`/`TA`).
    pub contour_tolerance: ContourTolerance,
    /// Where the control's machine coordinates lie, if the machine file says.
    pub machine_coordinates: Option<MachineCoordinates>,
    /// M functions its control defines beyond the dialect's own, with what they do.
    pub m_functions: Vec<crate::program::MCodeRule>,
    /// LinuxCNC HAL pins a program may read, by lower-case name, with their configured values.
    pub hal_pins: std::collections::BTreeMap<String, f64>,
    /// Radians per program unit of each rotary axis' words, in file order (degrees but on a control
    /// set up in radians).
    pub rotary_word_units: [f64; 2],
    /// The peck cycles' distances, m: G73's retract and G83's clearance (Fanuc No. 5114, 5115).
    pub peck_distances: [Option<f64>; 2],
    /// LinuxCNC's G73 and G83 peck clearances, m (2.10's `G73_PECK_CLEARANCE`, `G83_PECK_CLEARANCE`):
    /// what programs read as LinuxCNC's take, 2.9's 0.254 mm where unset.
    pub linuxcnc_peck_clearances: [Option<f64>; 2],
    /// How far an arc's end radius may differ from its start radius, m (the control's setting).
    pub arc_radius_tolerance: Option<f64>,
    /// Heidenhain cycle 19's angles are spatial angles (MP7500 bit 1), not axis positions.
    pub cycle19_spatial: bool,
    /// The control starts with tool-centre-point kinematics on.
    pub tcp_at_start: bool,
    /// Siemens: the basic system is inch (MD10240 = 0), the unit of F under G70/G71.
    pub inch_basic_system: bool,
    /// Fanuc, Haas: the motion mode at power-on and reset (FANUC parameter No. 3402 bit 0), if the
    /// file gives it.
    pub power_on_motion: Option<crate::program::Motion>,
    /// FANUC: how a feed move of the rotary axes alone under G43.4/G43.5 is fed (parameter No. 19696
    /// bit 6 RFC), if the file gives it.
    pub tcp_rotary_feed: Option<TcpRotaryFeed>,
    /// Sinumerik: the plane whose tool length assignment holds in every plane (setting data SD42940
    /// TOOL_LENGTH_CONST: 17 keeps a milling tool's length on Z), if the file gives one.
    pub tool_length_const: Option<u32>,
    /// Heidenhain TNC: an inch program's F is in 1/10 inch/min (true) or inch/min (false), if the file
    /// says.
    pub tnc_inch_feed_tenths: Option<bool>,
    /// Fanuc, Haas: a number without a decimal point is in the program's unit, `X5` 5 mm
    /// (calculator-type input: FANUC parameter No. 3401 bit 0 DPI = 1, Haas Setting 162 on), not in
    /// least input increments.
    pub calculator_input: bool,
    /// The machine maker's cycles that move nothing (they set the control's dynamics), by number.
    pub state_cycles: Vec<u32>,
    /// The Sinumerik swivel data set (`CYCLE800`), if the file gives it.
    pub swivel: Option<Swivel>,
    /// A quill along the tool, if the machine has one (LinuxCNC bridgemill's W).
    pub quill: Option<Quill>,
}

/// FANUC's feed of a move of the rotary axes alone under tool-centre-point control, where the tool
/// tip stands on the workpiece (A-79348E, parameter No. 19696 bit 6 RFC: "the feedrate of the rotation
/// axis is: 0: The maximum cutting feedrate (parameter No. 1422). 1: A specified feedrate.").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TcpRotaryFeed {
    /// RFC = 1: at the programmed F (degrees per minute).
    Programmed,
    /// RFC = 0: at the maximum cutting feedrate, parameter No. 1422 (not modelled: refused).
    MaxCutting,
}

/// A quill: a linear axis that moves the tool tip along the tool's own axis, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quill {
    /// Its address letter (`W`).
    pub letter: char,
    pub min: f64,
    pub max: f64,
    /// Its top speed, m/s.
    pub velocity: f64,
    /// +1: a positive move takes the tip towards the spindle; -1: away from it.
    pub sense: f64,
}

/// A Sinumerik swivel data set: its names, where it retracts (machine coordinates, m) and the axis
/// `_DIR` refers to (3 or 4; `None`: the tilting axis).
#[derive(Debug, Clone, PartialEq)]
pub struct Swivel {
    pub names: Vec<String>,
    pub retract: Option<Vector3<f64>>,
    pub direction_axis: Option<usize>,
}

/// The control's machine coordinate system (`G53`, `M91`, `SUPA`) and reference points (`G28`,
/// `G30`, `M92`), SI.
#[derive(Debug, Clone, PartialEq)]
pub struct MachineCoordinates {
    /// The linear axes' positions in the model's frame where the machine coordinates read zero, m.
    pub zero: Vector3<f64>,
    /// Reference points in machine coordinates, m: `G28` goes to the first, `G30 Pn` to the n-th.
    pub references: Vec<Vector3<f64>>,
    /// Heidenhain `M92`'s datum in machine coordinates, m.
    pub m92_datum: Option<Vector3<f64>>,
}

impl MachineCoordinates {
    /// The linear axes' positions in the model's frame for a point in machine coordinates (m).
    pub fn to_axes(&self, machine: Vector3<f64>) -> Vector3<f64> {
        machine + self.zero
    }
}

/// A control's contour tolerance: how far the path may leave a programmed point that it smooths
/// away (Heidenhain cycle 32 `T` and `TA`, LinuxCNC `G64 P/Q`; Sinumerik's `CTOL`/`OTOL` are not read). The planner and the monitor
/// skip a block end point as a spline knot within it ([`crate::singularity::Knots`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ContourTolerance {
    /// On the tool tip (TCPM) or the linear axes, m.
    pub linear_m: f64,
    /// On the rotary axes, rad.
    pub rotary_rad: f64,
}

impl ContourTolerance {
    /// Where neither the machine file nor the program sets one: 2 um and 0.002 deg (ASSUMED: finer
    /// than a finishing tolerance, 0.005-0.05 mm, and coarser than a CAM post's 4-decimal rounding).
    pub const DEFAULT: ContourTolerance = ContourTolerance { linear_m: 2e-6, rotary_rad: 0.002 * std::f64::consts::PI / 180.0 };

    /// Largest tolerance a program or machine file may set: 10 mm and 10 deg (cycle 32's input range).
    pub const MAX: ContourTolerance = ContourTolerance { linear_m: 0.01, rotary_rad: 10.0 * std::f64::consts::PI / 180.0 };

    /// True if `v` (m) is a linear tolerance a program or machine file may set: 0 to [`Self::MAX`].
    pub fn linear_ok(v: f64) -> bool {
        (0.0..=Self::MAX.linear_m).contains(&v)
    }

    /// True if `v` (rad) is a rotary tolerance a program or machine file may set: 0 to [`Self::MAX`].
    pub fn rotary_ok(v: f64) -> bool {
        (0.0..=Self::MAX.rotary_rad).contains(&v)
    }
}

impl Default for ContourTolerance {
    fn default() -> Self {
        ContourTolerance::DEFAULT
    }
}

/// Errors building a machine from a description.
#[derive(Debug, thiserror::Error)]
pub enum MachineError {
    #[error("unknown machine '{0}' (built in: {list})", list = BUILTIN_NAMES.join(", "))]
    Unknown(String),
    #[error("cannot read machine file {path}: {source}")]
    Io { path: String, source: std::io::Error },
    #[error("machine file {path}: {message}")]
    Parse { path: String, message: String },
    #[error("machine '{name}' ({origin}): {message}")]
    Invalid { name: String, origin: String, message: String },
    #[error("machine '{name}' is a four-axis machine (one rotary axis, no singular orientation): {what} takes a machine with two rotary axes; `fiveaxis program analyze` and `fiveaxis run` read its programs")]
    FourAxis { name: String, what: &'static str },
}

/// The built-in machines and their files: the papers' (seed 001-003), the LinuxCNC sample configs' (one
/// of each family: table-table, table-head, head-head), a 45 deg nutating head, the corpus machines of
/// issue 64 (the Deckel DMC 75V a four-axis one) and a generic model of each kinematic class
/// (`generic-*`, wide ranges).
const BUILTIN_FILES: [(&str, &str); 29] = [
    ("hermle-c600u", include_str!("../../../machines/hermle-c600u.toml")),
    ("mikron-ucp710", include_str!("../../../machines/mikron-ucp710.toml")),
    ("seed003-ttttr", include_str!("../../../machines/seed003-ttttr.toml")),
    ("dmu-style-b45", include_str!("../../../machines/dmu-style-b45.toml")),
    ("linuxcnc-xyzbc-trt", include_str!("../../../machines/linuxcnc-xyzbc-trt.toml")),
    ("linuxcnc-xyzac-trt", include_str!("../../../machines/linuxcnc-xyzac-trt.toml")),
    ("linuxcnc-xyzab-tdr", include_str!("../../../machines/linuxcnc-xyzab-tdr.toml")),
    ("linuxcnc-max5", include_str!("../../../machines/linuxcnc-max5.toml")),
    ("linuxcnc-bridgemill", include_str!("../../../machines/linuxcnc-bridgemill.toml")),
    ("hobby-rtcp-ab", include_str!("../../../machines/hobby-rtcp-ab.toml")),
    ("haas-umc-750", include_str!("../../../machines/haas-umc-750.toml")),
    ("haas-vf2-tr", include_str!("../../../machines/haas-vf2-tr.toml")),
    ("mori-seiki-nmv5000", include_str!("../../../machines/mori-seiki-nmv5000.toml")),
    ("dmg-dmu-100p-duoblock", include_str!("../../../machines/dmg-dmu-100p-duoblock.toml")),
    ("dmg-dmu-85-monoblock", include_str!("../../../machines/dmg-dmu-85-monoblock.toml")),
    ("trimill-vu3019", include_str!("../../../machines/trimill-vu3019.toml")),
    ("dmg-dmu-70-evo", include_str!("../../../machines/dmg-dmu-70-evo.toml")),
    ("spinner-u5-620", include_str!("../../../machines/spinner-u5-620.toml")),
    ("cincinnati-ftv5", include_str!("../../../machines/cincinnati-ftv5.toml")),
    ("dmg-dmu-50", include_str!("../../../machines/dmg-dmu-50.toml")),
    ("dmg-dmc-100u", include_str!("../../../machines/dmg-dmc-100u.toml")),
    ("deckel-dmc-75v", include_str!("../../../machines/deckel-dmc-75v.toml")),
    ("generic-ac-table", include_str!("../../../machines/generic-ac-table.toml")),
    ("generic-bc-table", include_str!("../../../machines/generic-bc-table.toml")),
    ("generic-ab-table", include_str!("../../../machines/generic-ab-table.toml")),
    ("generic-b45-table", include_str!("../../../machines/generic-b45-table.toml")),
    ("generic-b45-head", include_str!("../../../machines/generic-b45-head.toml")),
    ("generic-ac-head", include_str!("../../../machines/generic-ac-head.toml")),
    ("generic-bc-head", include_str!("../../../machines/generic-bc-head.toml")),
];

/// The machine every command and node takes when none is named: the paper's Hermle C600U (A/C table).
pub const DEFAULT_MACHINE: &str = "hermle-c600u";

/// Names of the built-in machines (those of [`BUILTIN_FILES`], in order).
pub const BUILTIN_NAMES: [&str; BUILTIN_FILES.len()] = {
    let mut names = [""; BUILTIN_FILES.len()];
    let mut i = 0;
    while i < names.len() {
        names[i] = BUILTIN_FILES[i].0;
        i += 1;
    }
    names
};

impl Machine {
    /// A built-in machine by name.
    pub fn builtin(name: &str) -> Result<Machine, MachineError> {
        let text = builtin_file(name).ok_or_else(|| MachineError::Unknown(name.to_string()))?;
        Machine::from_toml_str(text, &format!("builtin:{name}"))
    }

    /// The Hermle C600U of seed 001 (the default machine).
    pub fn hermle_c600u() -> Machine {
        Machine::builtin(DEFAULT_MACHINE).expect("built-in machine file is valid")
    }

    /// Parse a TOML machine description; `origin` names it in errors.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Machine, MachineError> {
        let file: MachineFile = toml::from_str(text)
            .map_err(|e| MachineError::Parse { path: origin.to_string(), message: e.to_string() })?;
        file.build(origin)
    }

    /// This machine, if it has two rotary axes; a four-axis machine is refused for `what` (a command
    /// or node whose streams, recordings or remedies name five axes).
    pub fn five_axis(self, what: &'static str) -> Result<Machine, MachineError> {
        if self.chain.is_four_axis() {
            return Err(MachineError::FourAxis { name: self.name, what });
        }
        Ok(self)
    }

    /// Index of the axis called `name` (case-insensitive).
    pub fn axis_index(&self, name: &str) -> Option<usize> {
        self.axes.iter().position(|a| a.name.eq_ignore_ascii_case(name))
    }

    /// Axis index of the secondary rotary axis: the one whose direction is fixed in the workpiece frame
    /// and whose speed diverges at the singularity (seed 001 §2.4; C on the Hermle).
    pub fn secondary_axis(&self) -> usize {
        3 + self.chain.secondary_slot()
    }

    /// Axis index of the primary rotary axis (A on the Hermle).
    pub fn primary_axis(&self) -> usize {
        3 + (1 - self.chain.secondary_slot())
    }

    /// Limits of all five axes, in axis order.
    pub fn limits(&self) -> [AxisLimits; AXES] {
        std::array::from_fn(|i| self.axes[i].limits)
    }

    /// The singular tool direction in the workpiece frame (unit vector; its opposite is singular too).
    pub fn singular_direction(&self) -> Vector3<f64> {
        self.chain.singular_direction()
    }

    /// The machine as people name it: maker and model (`Haas UMC-750`, `generic A/C table-table`),
    /// or its name where the file gives neither.
    pub fn label(&self) -> String {
        match (&self.maker, &self.model) {
            (Some(a), Some(b)) => format!("{a} {b}"),
            (Some(a), None) | (None, Some(a)) => a.clone(),
            (None, None) => self.name.clone(),
        }
    }

    /// The rule for M function `code` this machine's control defines, if any.
    pub fn m_function(&self, code: u32) -> Option<crate::program::MCodeAction> {
        self.m_functions.iter().find(|r| r.code == code).map(|r| r.action)
    }

    /// Radians per program unit of the rotary word `letter` (A, B or C) on this machine: its axis'
    /// `program_unit`, degrees for a letter it lacks.
    pub fn rotary_word_unit(&self, letter: char) -> f64 {
        (0..2).find(|&k| self.axes[3 + k].name.eq_ignore_ascii_case(&letter.to_string())).map_or(crate::units::DEG, |k| self.rotary_word_units[k])
    }

    /// Names of the axes, in order.
    pub fn axis_names(&self) -> [String; AXES] {
        std::array::from_fn(|i| self.axes[i].name.clone())
    }
}

pub(crate) fn joint(name: &str, carrier: Carrier, axis: Vector3<f64>, center: Vector3<f64>) -> RotaryJoint {
    RotaryJoint { name: name.to_string(), carrier, axis: axis.normalize(), center }
}

impl Machine {
    /// Forward kinematics: axis values -> tool pose in the workpiece frame.
    pub fn forward(&self, q: &Joints) -> Pose {
        self.chain.forward(q)
    }

    /// Both raw inverse solutions (rotary angles wrapped to (-pi, pi], no limits applied), seed 001
    /// Table 1. At the singularity the secondary angle is undefined and set to 0.
    pub fn inverse_all(&self, pose: &Pose) -> Result<[Joints; 2], KinematicsError> {
        check_pose(pose)?;
        let sol = self.chain.orientation_solutions(&pose.axis)?;
        Ok(sol.solutions.map(|rot| {
            let l = self.chain.linear_for(&pose.tip, &rot);
            [l.x, l.y, l.z, rot[0], rot[1]]
        }))
    }

    /// The rotary angles that point the tool along `axis`, the solution nearest `seed` once unwrapped
    /// (axis ranges not checked; at the singularity the secondary keeps the seed's value).
    pub fn rotaries_near(&self, axis: &Vector3<f64>, seed: &[f64; 2]) -> Option<[f64; 2]> {
        self.nearest_rotaries(axis, seed, |_, target, prev| Ok(unwrap_near(target, prev))).ok()
    }

    /// Where the rotary ranges rather than the geometry chose `chosen`: the solution nearest
    /// `previous` with no range applied ([`Machine::rotaries_near`]) puts a rotary axis outside its
    /// range, and `chosen` turns the axes further from `previous`. The axis' slot (0, 1) and the
    /// angle it would have reached, rad.
    pub fn range_forced(&self, axis: &Vector3<f64>, previous: &[f64; 2], chosen: &[f64; 2]) -> Option<(usize, f64)> {
        let free = self.rotaries_near(axis, previous)?;
        let cost = |r: &[f64; 2]| (r[0] - previous[0]).abs() + (r[1] - previous[1]).abs();
        if cost(chosen) <= cost(&free) + 1e-9 {
            return None;
        }
        (0..2).find(|&k| !self.axes[3 + k].limits.contains(free[k])).map(|k| (k, free[k]))
    }

    /// Of the two rotary solutions for `axis`, the one closest to `previous` with each angle placed
    /// by `place(slot, angle, previous angle)` (a placement error rules the solution out; the first
    /// such error is returned if both are). At the singularity the secondary axis keeps its previous
    /// value (seed 001 Table 1: C undefined).
    fn nearest_rotaries(
        &self,
        axis: &Vector3<f64>,
        previous: &[f64; 2],
        place: impl Fn(usize, f64, f64) -> Result<f64, KinematicsError>,
    ) -> Result<[f64; 2], KinematicsError> {
        let sol = self.chain.orientation_solutions(axis)?;
        let sec = self.chain.secondary_slot();
        let mut best: Option<(f64, [f64; 2])> = None;
        let mut first_violation: Option<KinematicsError> = None;
        'solutions: for raw in sol.solutions {
            let mut rot = [0.0; 2];
            for slot in 0..2 {
                let target = if sol.singular && slot == sec { previous[slot] } else { raw[slot] };
                match place(slot, target, previous[slot]) {
                    Ok(v) => rot[slot] = v,
                    Err(e) => {
                        first_violation.get_or_insert(e);
                        continue 'solutions;
                    }
                }
            }
            let cost = (rot[0] - previous[0]).abs() + (rot[1] - previous[1]).abs();
            if best.is_none_or(|(c, _)| cost < c - 1e-12) {
                best = Some((cost, rot));
            }
        }
        best.map(|(_, rot)| rot).ok_or_else(|| first_violation.unwrap_or(KinematicsError::Unreachable))
    }

    /// Inverse kinematics for continuous motion: of the two solutions, the one whose rotary angles are
    /// closest to `previous` once unwrapped (multi-turn axes take the turn nearest `previous`, so C can
    /// read 386.198 deg), within every axis range. At the singularity the secondary axis keeps its
    /// previous value (seed 001 Table 1: C undefined).
    pub fn inverse(&self, pose: &Pose, previous: &Joints) -> Result<Joints, KinematicsError> {
        let q = self.inverse_in_rotary_ranges(pose, previous)?;
        for (axis, &v) in self.axes.iter().zip(&q).take(3) {
            let lim = &axis.limits;
            if !lim.contains(v) {
                return Err(KinematicsError::OutOfRange {
                    axis: axis.name.clone(),
                    value: v / crate::units::MM,
                    min: lim.min / crate::units::MM,
                    max: lim.max / crate::units::MM,
                    unit: "mm",
                });
            }
        }
        Ok(q)
    }

    /// [`Machine::inverse`] with the rotary ranges only: where the part lies on the machine is not
    /// known (a work offset the program never states), so the linear axes' ranges cannot be judged.
    pub fn inverse_in_rotary_ranges(&self, pose: &Pose, previous: &Joints) -> Result<Joints, KinematicsError> {
        check_pose(pose)?;
        if !previous.iter().all(|v| v.is_finite()) {
            return Err(KinematicsError::NotFinite);
        }
        let rot = self.nearest_rotaries(&pose.axis, &[previous[3], previous[4]], |slot, target, prev| {
            let limits = &self.axes[3 + slot].limits;
            nearest_turn_within(target, prev, limits).ok_or_else(|| KinematicsError::OutOfRange {
                axis: self.axes[3 + slot].name.clone(),
                value: unwrap_near(target, prev).to_degrees(),
                min: limits.min.to_degrees(),
                max: limits.max.to_degrees(),
                unit: "deg",
            })
        })?;
        let l = self.chain.linear_for(&pose.tip, &rot);
        Ok([l.x, l.y, l.z, rot[0], rot[1]])
    }
}

fn check_pose(pose: &Pose) -> Result<(), KinematicsError> {
    if pose.tip.iter().chain(pose.axis.iter()).all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(KinematicsError::NotFinite)
    }
}

/// The representative `target + 2 pi k` nearest `prev` inside `limits`, if any.
fn nearest_turn_within(target: f64, prev: f64, limits: &AxisLimits) -> Option<f64> {
    let near = unwrap_near(target, prev);
    if limits.contains(near) {
        return Some(near);
    }
    // A limited range wider than one turn may hold another representative; try the neighbours.
    let tau = std::f64::consts::TAU;
    [near - tau, near + tau]
        .into_iter()
        .filter(|v| limits.contains(*v))
        .min_by(|a, b| (a - prev).abs().total_cmp(&(b - prev).abs()))
}

/// A `--work-offset-mm X,Y,Z` flag: the control's active work offset (a G54-style datum, as its offset
/// table holds it, in the machine's workpiece frame), mm in, m out. A machine stream's tool tip less it
/// is the program's point.
pub fn parse_work_offset(s: &str) -> Result<nalgebra::Vector3<f64>, String> {
    let v: Vec<f64> = s.split(',').map(|c| c.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|e| format!("expected X,Y,Z in mm, got '{s}': {e}"))?;
    match v.as_slice() {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(nalgebra::Vector3::new(*x, *y, *z) * crate::units::MM),
        _ => Err(format!("expected three finite numbers X,Y,Z in mm, got '{s}'")),
    }
}

/// One `AXIS=JOINT` pair of an `--axis-map` flag: which joint of a machine bridge's JointState is which
/// machine axis.
pub fn parse_axis_map(s: &str) -> Result<(String, String), String> {
    match s.split_once('=') {
        Some((a, j)) if !a.is_empty() && !j.is_empty() => Ok((a.to_string(), j.to_string())),
        _ => Err(format!("expected AXIS=JOINT, got '{s}'")),
    }
}

impl Machine {
    /// An `--axis-map` for this machine: axis names case-insensitive (`a=a_joint` is A), each axis
    /// once, and an axis the machine lacks refused with the machine's axes named.
    pub fn resolve_axis_map(&self, pairs: &[(String, String)]) -> Result<std::collections::BTreeMap<String, String>, String> {
        let mut map = std::collections::BTreeMap::new();
        for (axis, joint) in pairs {
            let a = self.axes.iter().find(|a| a.name.eq_ignore_ascii_case(axis)).ok_or_else(|| {
                format!("--axis-map {axis}={joint}: machine {} has no axis '{axis}' (its axes: {})", self.name, self.axis_names().join(" "))
            })?;
            if map.insert(a.name.clone(), joint.clone()).is_some() {
                return Err(format!("--axis-map names axis {} twice", a.name));
            }
        }
        Ok(map)
    }

    /// The `--axis-map` flags a user needs for a JointState with `joints`: each axis to the joint
    /// `given` names, else the joint named by the axis letter alone or with a separator (`x`,
    /// `x_joint`, `joint_x`, `axis-x`), else a placeholder.
    pub fn suggest_axis_map(&self, joints: &[String], given: &std::collections::BTreeMap<String, String>) -> String {
        self.axes
            .iter()
            .map(|a| {
                let letter = a.name.to_ascii_lowercase();
                let found = given.get(&a.name).cloned().or_else(|| {
                    joints
                        .iter()
                        .find(|j| {
                            let j = j.to_ascii_lowercase();
                            j == letter || j.split(|c: char| !c.is_ascii_alphanumeric()).any(|part| part == letter)
                        })
                        .cloned()
                });
                format!("--axis-map {}={}", a.name, found.unwrap_or_else(|| "<joint>".into()))
            })
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// The TOML text of a built-in machine.
pub fn builtin_file(name: &str) -> Option<&'static str> {
    BUILTIN_FILES.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

