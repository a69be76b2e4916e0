//! NC programs: one block model for every dialect, and readers that report every defect.
//!
//! A reader never fails and never panics: it returns the blocks it could read and a diagnostic for
//! each defect (line, column, what it expected). A block with a defect is not used (a damaged value is
//! never read as a number); every good block is kept.

mod apt;
mod chords;
mod cl;
mod corner;
mod corner_cut;
mod cutter_comp;
mod cycles;
mod tnc_cycles;
mod dialect;
mod fanuc;
mod fanuc_corners;
mod fanuc_nurbs;
mod fanuc_rotation;
mod feature;
mod heidenhain;
mod heidenhain_comp;
mod interp;
mod klartext;
mod lcnc_cycles;
mod lcnc_home;
mod later_subs;
mod lcnc_m98;
mod lex;
mod macro_b;
mod modal_context;
mod oword;
mod oword_run;
mod params;
pub mod plane;
mod quill;
mod rs274;
mod setup;
mod sinumerik;
mod stream;
mod tangent;

pub use cl::{read_cl, read_cl_with};
pub use dialect::{Dialect, DETECT_LINES};
pub use heidenhain::{read_heidenhain, read_heidenhain_with};
pub use klartext::{read_klartext_with, MAX_LABELS};
pub use rs274::{read_rs274, read_rs274_setup, read_rs274_with};
pub use setup::{AngleUnit, LengthUnit, Setup};
pub use sinumerik::read_sinumerik_with;
pub use stream::{BlockStream, DiagnosticLog, OpenText, Text, MAX_DIAGNOSTICS, MAX_LINE_BYTES};

use std::fmt;

/// The paper's NC programs (Heidenhain DIN/ISO), compiled in: `bundled:SING.I`, `bundled:NON_SING.I`.
pub const BUNDLED: [(&str, &str); 2] = [
    ("SING.I", include_str!("../../../recordings/programs/SING.I")),
    ("NON_SING.I", include_str!("../../../recordings/programs/NON_SING.I")),
];
/// Modal motion mode of a block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Motion {
    /// G00: positioning at the machine's rapid rate.
    Rapid,
    /// G01: straight line at the programmed feed.
    Linear,
    /// G02: circular (helical) arc, clockwise seen from the positive end of the plane's normal axis.
    #[serde(rename = "arc_cw")]
    ArcCw,
    /// G03: counter-clockwise arc.
    #[serde(rename = "arc_ccw")]
    ArcCcw,
}

impl Motion {
    /// True for G02/G03.
    pub fn is_arc(self) -> bool {
        matches!(self, Motion::ArcCw | Motion::ArcCcw)
    }
}

/// The plane of circular interpolation (G17/G18/G19), named by its two axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Plane {
    /// G17: X Y, normal Z.
    #[default]
    Xy,
    /// G18: Z X, normal Y.
    Zx,
    /// G19: Y Z, normal X.
    Yz,
}

impl Plane {
    /// The plane as messages name it, with its G code: `XY (G17)`.
    pub fn said(self) -> &'static str {
        match self {
            Plane::Xy => "XY (G17)",
            Plane::Zx => "ZX (G18)",
            Plane::Yz => "YZ (G19)",
        }
    }

    /// Indices (0 = X, 1 = Y, 2 = Z) of the plane's first and second axis and of its normal:
    /// `first x second = normal`, so a positive turn (counter-clockwise seen from the normal's
    /// positive end, G03) goes from the first axis towards the second (RS274/NGC 3 §3.5.3).
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::Xy => (0, 1, 2),
            Plane::Zx => (2, 0, 1),
            Plane::Yz => (1, 2, 0),
        }
    }
}

/// The circle of a G02/G03 block, as the reader resolved it (centre or radius format).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ArcSpec {
    pub plane: Plane,
    /// Centre, absolute program coordinates (m); its coordinate along the plane's normal is unused.
    pub centre: [f64; 3],
    /// Full turns beyond the first (LinuxCNC's `P` word minus one; 0 for most arcs).
    pub extra_turns: u32,
    /// The tilted working plane the arc was written in (its columns the plane's X Y Z in the
    /// workpiece): `plane` names the axes of that frame, and `centre` is in the workpiece.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frame: Option<[[f64; 3]; 3]>,
}

impl ArcSpec {
    /// [`ArcSpec::frame`] of a tilted plane or a turned part: the rotation's columns.
    pub fn frame_of(r: &nalgebra::Matrix3<f64>) -> [[f64; 3]; 3] {
        [0, 1, 2].map(|k| [r[(0, k)], r[(1, k)], r[(2, k)]])
    }
}

/// How the control interpolates the tool orientation between a block's start and end under
/// tool-centre-point management.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Orientation {
    /// The rotary axes move linearly in the block (Heidenhain `M128` / `PATHCTRL AXIS`, Sinumerik
    /// `ORIAXES` / `ORIMKS`, LinuxCNC): the tool axis sweeps whatever cone the axes make.
    #[default]
    AxisLinear,
    /// The tool axis turns on the great circle through its start and end directions in the workpiece
    /// at a constant angular rate (Heidenhain `PATHCTRL VECTOR`, Sinumerik `ORIVECT` / `ORIWKS`); the
    /// rotary axes follow by inverse kinematics, so near the pole C turns faster than between its ends.
    GreatCircle,
}

impl Orientation {
    /// The names people give the modes on the command line (`--orientation`), in declaration order.
    pub const NAMES: [&'static str; 2] = ["axis-linear", "great-circle"];
}

impl std::str::FromStr for Orientation {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "axis-linear" => Ok(Orientation::AxisLinear),
            "great-circle" => Ok(Orientation::GreatCircle),
            other => Err(format!("unknown orientation mode '{other}': expected {}", Orientation::NAMES.join(" or "))),
        }
    }
}

/// How the feed word is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FeedMode {
    /// F is a path speed: mm/min of the tool tip (deg/min for a move of rotary axes only).
    PerMinute,
    /// G93: F is the inverse of the block's duration in minutes.
    InverseTime,
}

/// Programmed feed in effect for a block.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Feed {
    /// F as programmed, converted to mm/min (or 1/min in inverse-time mode).
    pub value_per_min: f64,
    /// F for a move of the rotary axes alone, deg/min: the number as programmed, whatever the length
    /// unit (G20's inches convert `value_per_min`, not this).
    pub rotary_per_min: f64,
    pub mode: FeedMode,
}

/// Target words of a block, absolute, SI (m, rad), in program (workpiece, datum-shifted) coordinates.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct Targets {
    pub x: Option<f64>,
    pub y: Option<f64>,
    pub z: Option<f64>,
    pub a: Option<f64>,
    pub b: Option<f64>,
    pub c: Option<f64>,
    /// Tool axis (unit) in the workpiece frame, for cutter-location data.
    pub tool_axis: Option<[f64; 3]>,
}

impl Targets {
    /// True if the block names no axis.
    pub fn is_empty(&self) -> bool {
        self.x.is_none()
            && self.y.is_none()
            && self.z.is_none()
            && self.a.is_none()
            && self.b.is_none()
            && self.c.is_none()
            && self.tool_axis.is_none()
    }
    /// The rotary word for letter `A`, `B` or `C`.
    pub fn rotary(&self, letter: char) -> Option<f64> {
        match letter.to_ascii_uppercase() {
            'A' => self.a,
            'B' => self.b,
            'C' => self.c,
            _ => None,
        }
    }
    /// Set axis `k` of the machine's order: 0-2 X Y Z, 3-5 A B C.
    /// The target of linear axis `k` (0 X, 1 Y, 2 Z), if the block has one.
    pub fn axis(&self, k: usize) -> Option<f64> {
        match k {
            0 => self.x,
            1 => self.y,
            _ => self.z,
        }
    }

    pub fn set_axis(&mut self, k: usize, value: f64) {
        match k {
            0 => self.x = Some(value),
            1 => self.y = Some(value),
            2 => self.z = Some(value),
            3 => self.a = Some(value),
            4 => self.b = Some(value),
            _ => self.c = Some(value),
        }
    }
    /// Set the rotary word for letter `A`, `B` or `C` (other letters are ignored).
    pub fn set_rotary(&mut self, letter: char, value: f64) {
        match letter.to_ascii_uppercase() {
            'A' => self.a = Some(value),
            'B' => self.b = Some(value),
            'C' => self.c = Some(value),
            _ => {}
        }
    }
}

/// Whether the machine stops at the end of a block: blending into the next block (G64, every
/// control's default), exact path (LinuxCNC G61: it stops wherever the next block does not go on in
/// the same direction) or exact stop (LinuxCNC G61.1; Fanuc and Haas G61, one block G09; Sinumerik
/// G60, one block G9: it stops at the end of every block).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Exact {
    #[default]
    Blend,
    Path,
    Stop,
}

impl Exact {
    /// Blending, the default (left out of a block's JSON).
    pub fn is_blend(&self) -> bool {
        *self == Exact::Blend
    }
}

/// One block, with the modal state in effect for it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Block {
    /// 1-based line and column of the block's first word.
    pub line: usize,
    pub column: usize,
    /// Block number (`N`), if written.
    pub number: Option<u64>,
    pub motion: Motion,
    pub targets: Targets,
    /// The circle of a G02/G03 block (`None` for every other motion); boxed, as most blocks of
    /// five-axis work are lines and a block list of millions holds one per block.
    pub arc: Option<Box<ArcSpec>>,
    pub feed: Option<Feed>,
    /// Tool-centre-point management (M128 / G43.4; always on for CL data): X Y Z are the tool tip
    /// in workpiece coordinates and the control keeps it on the programmed line.
    pub tcp: bool,
    /// Datum shift in effect (m): program coordinates + datum = coordinates about the rotary axes.
    pub datum: [f64; 3],
    /// How the tool orientation is interpolated (under TCPM; without it the axes move linearly).
    pub orientation: Orientation,
    /// Non-motion words kept as events, as written (`M13`, `T5`, `S12000`, `M100`).
    pub events: Vec<String>,
    /// A dwell (`G4 P`, Sinumerik `G4 F`, Heidenhain `G04 F`, APT `DELAY/`): the machine stands
    /// still this long, s, before the block's motion (LinuxCNC's order of execution: dwell, then motion).
    pub dwell_s: Option<f64>,
    /// The contour tolerance the program set for this block (Heidenhain cycle 32, LinuxCNC G64 P/Q), if any.
    #[serde(skip_serializing_if = "ProgrammedTolerance::is_unset")]
    pub tolerance: ProgrammedTolerance,
    /// The datum includes a work offset the program selects but never sets (Fanuc's G54-G59 and
    /// G54.1 P, set on the machine by its operator): taken as zero, so where the linear axes stand
    /// is known only up to it, and a linear axis' range cannot be judged.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub offset_assumed: bool,
    /// Whether the machine stops at the block's end ([`Exact`]).
    #[serde(skip_serializing_if = "Exact::is_blend")]
    pub exact: Exact,
}

/// A contour tolerance as a program sets it (Heidenhain `CYCL DEF 32.1 T` and `32.2 TA`, LinuxCNC
/// `G64 P- <Q->` the linear part): each part
/// it leaves unset is the machine's ([`crate::machine::Machine::contour_tolerance`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct ProgrammedTolerance {
    /// On the tool tip or the linear axes, m.
    pub linear_m: Option<f64>,
    /// On the rotary axes, rad.
    pub rotary_rad: Option<f64>,
}

impl ProgrammedTolerance {
    /// True if the program set neither part.
    pub fn is_unset(&self) -> bool {
        *self == ProgrammedTolerance::default()
    }

    /// The tolerance in effect on a machine whose own is `machine`.
    pub fn on(&self, machine: crate::machine::ContourTolerance) -> crate::machine::ContourTolerance {
        crate::machine::ContourTolerance { linear_m: self.linear_m.unwrap_or(machine.linear_m), rotary_rad: self.rotary_rad.unwrap_or(machine.rotary_rad) }
    }
}

/// How bad a diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// Something unsupported or suspicious that was skipped or tolerated.
    Warning,
    /// A defect: the input is damaged; the block holding it is not used.
    Error,
}

/// A defect or a warning, with where it is.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Diagnostic {
    pub line: usize,
    pub column: usize,
    pub severity: Severity,
    pub message: String,
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
        })
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}: {}", self.line, self.column, self.severity, self.message)
    }
}

/// A read program: its blocks and what the reader had to say.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Program {
    /// Where it came from (a path, or `builtin:NAME`).
    pub source: String,
    pub dialect: Dialect,
    /// Program name from the header, if any.
    pub name: Option<String>,
    pub blocks: Vec<Block>,
    pub diagnostics: Vec<Diagnostic>,
}

impl Program {
    /// True if any diagnostic is a defect.
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(|d| d.severity == Severity::Error)
    }
    /// Diagnostics formatted with the source, `file:line:column: severity: message`.
    pub fn report(&self) -> Vec<String> {
        self.diagnostics.iter().map(|d| format!("{}:{}", self.source, d)).collect()
    }
}

/// What a machine-specific M code does: LinuxCNC's user M codes and remaps (its vismach five-axis
/// demos switch kinematics with `M428` (tool-centre point) and `M429` (identity)), a maker's own.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MCodeAction {
    /// Tool-centre-point management on (X Y Z are the tool tip in the workpiece).
    TcpOn,
    /// Tool-centre-point management off (X Y Z are machine axes).
    TcpOff,
    /// No motion: kept as an event.
    Event,
}

/// An action by its name (`--m-code`, a machine file's `[[m_function]]`): tcp-on, tcp-off, event.
impl std::str::FromStr for MCodeAction {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "tcp-on" => Ok(MCodeAction::TcpOn),
            "tcp-off" => Ok(MCodeAction::TcpOff),
            "event" => Ok(MCodeAction::Event),
            other => Err(format!("unknown M code action '{other}': expected tcp-on, tcp-off or event")),
        }
    }
}

/// One `--m-code CODE=ACTION` rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MCodeRule {
    pub code: u32,
    pub action: MCodeAction,
}

impl std::str::FromStr for MCodeRule {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let (code, action) = s.split_once('=').ok_or_else(|| format!("expected CODE=ACTION (e.g. 428=tcp-on), got '{s}'"))?;
        let code = code.trim().trim_start_matches(['M', 'm']);
        let code: u32 = code.parse().map_err(|_| format!("'{code}' is not an M code number"))?;
        Ok(MCodeRule { code, action: action.trim().parse()? })
    }
}

/// Options of the readers.
#[derive(Debug, Clone)]
pub struct ReadOptions {
    /// Feed for CL data without a feed column, mm/min.
    pub cl_feed_mm_per_min: f64,
    /// Machine-specific M codes and what they do (RS274NGC); any other code outside the standard
    /// set is an error.
    pub m_codes: Vec<MCodeRule>,
    /// Orientation interpolation at program start (`None`: the dialect's default,
    /// [`Dialect::default_orientation`]).
    pub orientation: Option<Orientation>,
    /// The machine the program runs on, as its control knows it: the M functions it defines, its
    /// machine coordinates and reference points, its kinematics for tilted working planes.
    pub machine: Option<std::sync::Arc<crate::machine::Machine>>,
    /// The length unit the program's numbers are in, whatever it says (`--units`): for a program
    /// whose unit statement contradicts its numbers (Creo's `UNITS / INCHES` on millimetres).
    pub units: Option<LengthUnit>,
    /// The unit of CL data's rotary angles (`--cl-angles`; APT's own is degrees).
    pub cl_angles: AngleUnit,
    /// The most lines a program's loops, repeats and subprogram calls may run beyond its own lines
    /// (RS274NGC O-words, Klartext's `CALL LBL … REP`): an endless loop is refused there, at the
    /// line it had reached (default [`MAX_RUN_LINES`]).
    pub max_run_lines: usize,
    /// The machine's tool table (LinuxCNC's `tool.tbl`, `--tool-table`): the diameters `G41`/`G42` with
    /// a `D` word compensate by.
    pub tool_table: Option<std::sync::Arc<ToolTable>>,
    /// Where an RS274NGC program's `o<name> call` of a subroutine it does not define finds
    /// `name.ngc` (LinuxCNC's `[RS274NGC] SUBROUTINE_PATH`, `--subroutine-path`).
    pub subroutine_files: Option<std::sync::Arc<dyn SubroutineFiles>>,
}

pub use oword::{SubroutineFiles, MAX_HELD_BYTES};

pub use cutter_comp::ToolTable;

/// The default of [`ReadOptions::max_run_lines`].
pub const MAX_RUN_LINES: usize = 4_000_000;

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions { cl_feed_mm_per_min: 1000.0, m_codes: Vec::new(), orientation: None, machine: None, units: None, cl_angles: AngleUnit::Deg, max_run_lines: MAX_RUN_LINES, tool_table: None, subroutine_files: None }
    }
}

impl ReadOptions {
    /// The orientation interpolation a program in `dialect` starts in: the one asked for, else the
    /// dialect's default.
    pub fn orientation_for(&self, dialect: Dialect) -> Orientation {
        self.orientation.unwrap_or(dialect.default_orientation())
    }

    /// These options for a program run on `machine`.
    pub fn on(&self, machine: &crate::machine::Machine) -> ReadOptions {
        ReadOptions { machine: Some(std::sync::Arc::new(machine.clone())), ..self.clone() }
    }

    /// The M-code rules in effect: the `--m-code` flags first (they override), then the machine's.
    pub fn m_code_rules(&self) -> Vec<MCodeRule> {
        let mut rules = self.m_codes.clone();
        if let Some(m) = &self.machine {
            rules.extend(m.m_functions.iter().filter(|r| !self.m_codes.iter().any(|f| f.code == r.code)));
        }
        rules
    }
}

/// Read `text` in `dialect`; `source` names it in reports.
pub fn read(text: &str, dialect: Dialect, source: &str, options: &ReadOptions) -> Program {
    let mut p = match stream::Reader::new(dialect, options) {
        Some(mut reader) => {
            // A LinuxCNC program with subroutines may call one defined after the call: its text is
            // kept for that (most programs have none, and are not copied).
            if later_subs::may_define_subs(text) {
                reader.with_program_text(|| later_subs::ProgramText::Bytes(text.as_bytes().into()));
            }
            stream::read_whole(reader.get(), text, dialect)
        }
        None => stream::read_jumping(text, dialect, stream::jumping(dialect, options)),
    };
    p.source = source.to_string();
    p
}

#[cfg(test)]
impl Program {
    /// Its diagnostics of `severity`, each as `line:column: message` (the readers' tests).
    pub(crate) fn messages(&self, severity: Severity) -> Vec<String> {
        self.diagnostics.iter().filter(|d| d.severity == severity).map(|d| format!("{}:{}: {}", d.line, d.column, d.message)).collect()
    }
}

/// Errors loading a program file (its content never errors: see [`Program::diagnostics`]).
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("cannot read {path}: {source}")]
    Io { path: String, source: std::io::Error },
    /// A program read whole (the remedies, which rewrite it; a run that keeps its whole simulation)
    /// is longer than [`MAX_WHOLE_PROGRAM_BYTES`]: refused rather than exhaust memory
    /// (a compressed program can unpack to any length).
    #[error("{path}: more than {} MiB of program text to read whole (the `avoid` remedies and `roughness synthesize` read a program whole)", MAX_WHOLE_PROGRAM_BYTES >> 20)]
    TooLong { path: String },
}

/// The longest program text read whole, bytes (1 GiB: about 14 hours of CAM output at a block every
/// 0.1 mm and F2000).
pub const MAX_WHOLE_PROGRAM_BYTES: u64 = 1 << 30;

/// Read a program's text whole from `input`, up to [`MAX_WHOLE_PROGRAM_BYTES`] in all (`text` may
/// already hold its first bytes); `source` names it in errors.
pub fn read_whole_bytes(input: impl std::io::Read, text: &mut Vec<u8>, source: &str) -> Result<(), LoadError> {
    read_whole_within(input, text, source, MAX_WHOLE_PROGRAM_BYTES)
}

fn read_whole_within(input: impl std::io::Read, text: &mut Vec<u8>, source: &str, limit: u64) -> Result<(), LoadError> {
    let room = (limit + 1).saturating_sub(text.len() as u64);
    std::io::Read::read_to_end(&mut std::io::Read::take(input, room), text).map_err(|e| LoadError::Io { path: source.to_string(), source: e })?;
    if text.len() as u64 > limit {
        return Err(LoadError::TooLong { path: source.to_string() });
    }
    Ok(())
}


#[cfg(test)]
mod tests {
    use super::*;

    /// A whole read stops one byte past its bound, whatever the input's length (an endless one
    /// here), and refuses; text up to the bound, with the bytes already read counted, is kept.
    #[test]
    fn a_whole_read_is_bounded() {
        let mut text = b"0 BEGIN".to_vec();
        let r = read_whole_within(std::io::repeat(b'x'), &mut text, "endless.h", 4096);
        assert!(matches!(r, Err(LoadError::TooLong { ref path }) if path == "endless.h"), "{r:?}");
        assert_eq!(text.len(), 4097);
        let mut text = b"0 BEGIN".to_vec();
        read_whole_within(&b" PGM T MM\n"[..], &mut text, "t.h", 17).unwrap();
        assert_eq!(text, b"0 BEGIN PGM T MM\n");
        let mut text = b"0 BEGIN".to_vec();
        assert!(read_whole_within(&b" PGM T MM\n"[..], &mut text, "t.h", 16).is_err());
    }
}
