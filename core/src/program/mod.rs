//! NC programs: one block model for every dialect, and readers that report every defect.
//!
//! A reader never fails and never panics: it returns the blocks it could read and a diagnostic for
//! each defect (line, column, what it expected). A block with a defect is not used (a damaged value is
//! never read as a number); every good block is kept.

mod apt;
mod cl;
mod corner;
mod corner_cut;
mod cutter_comp;
mod cycles;
mod fanuc;
mod fanuc_corners;
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

pub use cl::{read_cl, read_cl_with};
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
use std::path::Path;

/// The dialects the readers understand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Dialect {
    /// Heidenhain DIN/ISO (`%NAME G71 *`, `N10 G01 X+0 *`).
    Heidenhain,
    /// RS274NGC (LinuxCNC, Fanuc style).
    Rs274,
    /// Cutter-location data: one `x y z i j k` pose per line, or APT CLDATA (`GOTO/x,y,z,i,j,k`).
    Cl,
    /// Siemens Sinumerik 840D (`.MPF`, `TRAORI`, tool vectors `A3= B3= C3=`).
    Sinumerik,
    /// Heidenhain conversational (Klartext, `.H`: `BEGIN PGM NAME MM`, `L X+0 Y+0 R0 F1000`).
    Klartext,
    /// Fanuc Series 30i/31i and the controls that follow it (Mori Seiki's MAPPS): G-code as
    /// RS274NGC, with Fanuc's own reference returns, canned cycles, dwell in ms and codes.
    Fanuc,
    /// Haas NGC mills: Fanuc-style G-code with Haas' own rules (G28 with no axis homes every axis,
    /// G234 TCPC, G254 DWO, G187, dwell in seconds, L as the repeat count).
    Haas,
}

/// How many of a program's first lines its dialect is judged from.
pub const DETECT_LINES: usize = 2000;

/// A dialect by the names people call it (`--dialect`): heidenhain (din, iso), rs274 (ngc, gcode,
/// linuxcnc), cl, sinumerik (840d, siemens), klartext (conversational), fanuc, haas; case-insensitive.
impl std::str::FromStr for Dialect {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "heidenhain" | "din" | "iso" => Ok(Dialect::Heidenhain),
            "rs274" | "ngc" | "gcode" | "linuxcnc" => Ok(Dialect::Rs274),
            "cl" => Ok(Dialect::Cl),
            "sinumerik" | "840d" | "siemens" => Ok(Dialect::Sinumerik),
            "klartext" | "conversational" => Ok(Dialect::Klartext),
            "fanuc" => Ok(Dialect::Fanuc),
            "haas" => Ok(Dialect::Haas),
            _ => Err(format!("unknown dialect '{s}': expected heidenhain, rs274, cl, sinumerik, klartext, fanuc or haas")),
        }
    }
}

impl Dialect {
    /// True if a program in this dialect starts at its first pose (CL data: the first line is where
    /// the tool is), false if its first move starts from the machine's home (NC programs).
    pub fn starts_at_first_pose(self) -> bool {
        self == Dialect::Cl
    }

    /// True if, without tool-centre-point control, a move of linear and rotary axes together takes F
    /// along a path whose rotary part counts degrees as the program's length unit: Fanuc's (FANUC
    /// B-63174EN §4.2, "G91 G01 X20.0 C40.0 F300.0 ... time = sqrt(20^2 + 40^2) / 300"). LinuxCNC and
    /// Siemens give F to the linear axes, the rotary ones following.
    pub fn counts_degrees_in_feed_path(self) -> bool {
        self == Dialect::Fanuc
    }

    /// How a control of this dialect interpolates the tool orientation under tool-centre-point
    /// management unless told otherwise. Heidenhain: `M128` moves the rotary axes linearly (as
    /// FUNCTION TCPM's `PATHCTRL AXIS`, with which "the tool circumference does not describe a defined
    /// path"). RS274NGC: LinuxCNC interpolates the joints linearly (src/emc/tp/tc.c; its TCP
    /// kinematics map the axes only), and Fanuc's G43.4/G43.5 by default move "the two rotary axes
    /// independently" (30i Tool Posture Control, A-79294E: the great circle is an option). CL data:
    /// the control that runs it decides; axis-linear, as the post-processed program runs on a TNC.
    pub fn default_orientation(self) -> Orientation {
        match self {
            Dialect::Heidenhain | Dialect::Rs274 | Dialect::Cl | Dialect::Klartext | Dialect::Fanuc | Dialect::Haas => Orientation::AxisLinear,
            // ORIWKS and ORIVECT are the reset state (840D sl Programming Manual Job Planning
            // 03/2006 §7.1.2: "The default setting is ORIWKS"; G group 51 default ORIVECT, large-circle
            // interpolation, Fundamentals 10/2004 §12.3).
            Dialect::Sinumerik => Orientation::GreatCircle,
        }
    }

    /// True for the Fanuc-style dialects (Fanuc, Haas): reference returns, canned cycles and work
    /// offsets as Fanuc reads them.
    pub fn is_fanuc(self) -> bool {
        matches!(self, Dialect::Fanuc | Dialect::Haas)
    }

    /// True for the dialects read by the RS274 reader (LinuxCNC, Fanuc, Haas).
    pub fn is_rs274_family(self) -> bool {
        matches!(self, Dialect::Rs274 | Dialect::Fanuc | Dialect::Haas)
    }

    /// The dialect of a program for a machine whose control reads `control`: a file whose content
    /// or name says nothing beyond generic G-code (what [`Dialect::detect`] calls RS274NGC) is read
    /// in the control's own G-code dialect.
    pub fn detect_for(path: Option<&Path>, text: &str, control: Option<Dialect>) -> Dialect {
        match (Dialect::detect(path, text), control) {
            (Dialect::Rs274, Some(c)) if c.is_rs274_family() => c,
            (d, _) => d,
        }
    }

    /// The refusal of a program whose dialect was detected (`given` false) as the RS274 family but
    /// whose first lines are in a language no reader follows ([`Dialect::unread_language`]).
    pub fn unread(given: bool, detected: Dialect, text: &str) -> Option<Diagnostic> {
        (!given && detected.is_rs274_family()).then(|| Dialect::unread_language(text)).flatten()
    }

    /// A program that its name or first lines send to the RS274 family but that is written in a
    /// language no reader here follows: Heidenhain MillPlus's ISO dialect, recognised by a `G7` block
    /// with MillPlus's angle words `A5=` `B5=` `C5=` (its tilted working plane, as NX's and Autodesk's
    /// MillPlus posts write it; no RS274 word holds `=`). Read as G-code it would give an error on
    /// nearly every block: refused once instead, at that block (within the first [`DETECT_LINES`]).
    pub fn unread_language(text: &str) -> Option<Diagnostic> {
        text.lines().take(DETECT_LINES).enumerate().find_map(|(i, raw)| {
            // A line without `=` or `7` holds neither the angle words nor `G7`: passed over without
            // the copy below (most lines of most programs).
            if !raw.contains('=') || !raw.contains('7') {
                return None;
            }
            // The code of the line: no `( )` comment, nothing after `;`.
            let mut code = String::with_capacity(raw.len());
            let mut depth = 0usize;
            for c in raw.chars().take_while(|&c| c != ';') {
                match c {
                    '(' => depth += 1,
                    ')' => depth = depth.saturating_sub(1),
                    _ if depth == 0 => code.push(c.to_ascii_uppercase()),
                    _ => code.push(' '),
                }
            }
            let words: Vec<&str> = code.split_whitespace().collect();
            let g7 = words.iter().position(|w| *w == "G7" || *w == "G07")?;
            words.iter().any(|w| ["A5=", "B5=", "C5="].iter().any(|a| w.starts_with(a))).then(|| Diagnostic {
                line: i + 1,
                column: code.find(words[g7]).map_or(1, |b| code[..b].chars().count() + 1),
                severity: Severity::Error,
                message: format!(
                    "{}: a Heidenhain MillPlus program (its tilted plane G7 with A5= B5= C5=): fiveaxis does not read MillPlus ISO (its G7, G141 and G74 follow no manual within reach); nothing was read",
                    words.join(" ")
                ),
            })
        })
    }

    /// Guess the dialect from the file name, then from the text.
    pub fn detect(path: Option<&Path>, text: &str) -> Dialect {
        let ext = path
            .and_then(|p| p.extension())
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        // The first line that is not a comment (`;` in every dialect, `#` in CL data, `(` in RS274NGC):
        // a comment's words say nothing of the dialect (a `; ...` header of six words is not CL data).
        let first = text.lines().map(str::trim).find(|l| !l.is_empty() && !l.starts_with([';', '#', '('])).unwrap_or("");
        // Content that only one dialect writes decides before the extension (`.h` is both
        // Heidenhain's DIN/ISO and conversational; `.nc` is used by every control).
        let upper = |l: &str| l.to_ascii_uppercase();
        // One pass over the first lines: Klartext's `BEGIN PGM` in the first 50, APT's `GOTO/` and
        // the 840D's words in all of them (each looked for until found).
        let (mut klartext, mut goto, mut sinumerik) = (false, false, false);
        for (i, l) in text.lines().take(DETECT_LINES).enumerate() {
            if i < 50 && !klartext {
                let u = upper(l);
                let body = u.trim_start().trim_start_matches(|c: char| c.is_ascii_digit()).trim_start();
                klartext = body.starts_with("BEGIN PGM");
            }
            goto = goto || apt::is_goto(l);
            sinumerik = sinumerik || sinumerik_word(&l.as_bytes()[..memchr::memchr(b';', l.as_bytes()).unwrap_or(l.len())]);
            if klartext || goto && sinumerik {
                break;
            }
        }
        if klartext {
            return Dialect::Klartext;
        }
        // APT CLDATA: a motion statement (`GOTO/`) no NC dialect writes, or a first statement that is
        // APT's (`PARTNO`, `$$`, `MACHIN/`, ...), as the CL reader itself takes it.
        if apt::is_apt_line(first) || goto {
            return Dialect::Cl;
        }
        match ext.as_str() {
            "i" | "iso" => return Dialect::Heidenhain,
            "mpf" | "spf" => return Dialect::Sinumerik,
            _ if sinumerik => return Dialect::Sinumerik,
            "h" => return Dialect::Heidenhain,
            "ngc" | "nc" | "gcode" | "tap" | "cnc" => return Dialect::Rs274,
            "cl" | "csv" | "cls" | "apt" | "clsf" | "aptsource" => return Dialect::Cl,
            _ => {}
        }
        if first.starts_with('%') && first.ends_with('*') || text.contains(" *\n") {
            Dialect::Heidenhain
        } else if first
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
            .count()
            >= 6
            && !first.chars().next().is_some_and(|c| c.is_ascii_alphabetic() && "GMNXYZgmnxyz".contains(c))
        {
            Dialect::Cl
        } else {
            Dialect::Rs274
        }
    }
}

/// Words only the 840D writes among the dialects read here (its transformations, orientation modes,
/// swivel cycle, tool-vector words, and G codes of its own), in capitals.
const SINUMERIK_WORDS: [&[u8]; 12] = [b"TRAORI", b"TRAFOOF", b"ORIWKS", b"ORIMKS", b"ORIVECT", b"ORIAXES", b"CYCLE800", b"A3=", b"B3=", b"C3=", b"G642", b"G500"];

/// Whether `code` holds one of [`SINUMERIK_WORDS`] in any case: a pass over its bytes, comparing
/// only where a word's first letter stands, and only the words it starts (no copy of the line in
/// capitals).
fn sinumerik_word(code: &[u8]) -> bool {
    // For each byte, the words it starts (bit k: word k), in either case: from the words themselves.
    const STARTS: [u16; 256] = {
        let mut t = [0u16; 256];
        let mut k = 0;
        while k < SINUMERIK_WORDS.len() {
            let c = SINUMERIK_WORDS[k][0];
            t[c as usize] |= 1 << k;
            t[c.to_ascii_lowercase() as usize] |= 1 << k;
            k += 1;
        }
        t
    };
    code.iter().enumerate().any(|(i, c)| {
        let mut words = STARTS[usize::from(*c)];
        while words != 0 {
            let w = SINUMERIK_WORDS[words.trailing_zeros() as usize];
            if code[i..].get(..w.len()).is_some_and(|s| s.eq_ignore_ascii_case(w)) {
                return true;
            }
            words &= words - 1;
        }
        false
    })
}

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

    /// The 840D's words are found in any case, anywhere in a line's code, as the line copied in
    /// capitals and searched word by word finds them (the definition the scanner replaces), over
    /// 200,000 lines drawn from pieces of the words, in either case, with `=`, `;`, blanks and a
    /// non-ASCII letter.
    #[test]
    fn sinumerik_words_are_found_as_in_the_line_in_capitals() {
        let mut next = lex::xorshift(0x1234_5678_9ABC_DEF1);
        let pieces = ["TRA", "tra", "ORI", "oRi", "FOOF", "WKS", "mks", "VECT", "AXES", "CYCLE", "cycle", "800", "A3", "b3", "C", "3=", "=", "G6", "g5", "42", "00", " ", ";", "Ä", "X1"];
        let mut found = 0;
        for _ in 0..200_000 {
            let len = (next() % 10) as usize;
            let line: String = (0..len).map(|_| pieces[(next() % pieces.len() as u64) as usize]).collect();
            let code = line.split(';').next().unwrap_or("");
            let reference = SINUMERIK_WORDS.iter().any(|w| code.to_ascii_uppercase().contains(std::str::from_utf8(w).unwrap()));
            assert_eq!(sinumerik_word(code.as_bytes()), reference, "{line:?}");
            found += usize::from(reference);
        }
        // Both answers drawn often enough to tell them apart.
        assert!((1_000..199_000).contains(&found), "{found} lines with a word");
    }

    /// MillPlus is recognised by G7 with its angle words in code, at the G7; never in a comment,
    /// and never by G7 or an `A5` alone.
    #[test]
    fn millplus_is_recognised_by_its_tilted_plane() {
        let d = Dialect::unread_language("%\nN10 G17\nN20 G7 A5=15. B5=0.0 C5=210. B7=254 C7=255\n").unwrap();
        assert_eq!((d.line, d.column, d.severity), (3, 5, Severity::Error));
        assert!(d.message.contains("MillPlus"), "{}", d.message);
        for text in ["N20 (G7 A5=15.) G1 X1\n", "N20 G1 X1 ; G7 A5=15.\n", "N20 G7 X1\n", "N20 G1 A5 X1\n", "G17 G7\nG1 A5.0\n"] {
            assert_eq!(Dialect::unread_language(text), None, "{text:?}");
        }
    }
}
