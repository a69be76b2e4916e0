//! The TOML machine description (units in field names: mm, deg, mm/min) and its validation.

use super::{joint, Axis, AxisKind, AxisLimits, ContourTolerance, Machine, MachineError};
use crate::kinematics::{Carrier, TwoRotaryChain};
use crate::units::{DEG, MM, MM_PER_MIN};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// A whole machine file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MachineFile {
    pub name: String,
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub description: String,
    /// Who makes the machine, as program headers write it (`Haas`, `DMG`, `Mori Seiki`); `generic`
    /// for a model of a kinematic class rather than of one machine.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub maker: Option<String>,
    /// The model, as program headers write it (`UMC-750`, `DMU 70 eVo`); for a generic machine, its
    /// class (`A/C table-table`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
    /// The control that runs it, as its maker names it (`Heidenhain iTNC 530`, `Siemens 840D sl`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control: Option<String>,
    /// The dialect its control reads (`fanuc`, `haas`, `rs274`, `klartext`, `sinumerik`, ...): a
    /// generic G-code file for this machine is read in it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dialect: Option<String>,
    /// Tool axis O_M in the spindle frame at home (unit vector; default +Z).
    #[serde(default = "default_tool_axis")]
    pub tool_axis: [f64; 3],
    /// Tool tip at home relative to the linear-axis origin, mm (head machines: pivot minus tool length).
    #[serde(default)]
    pub tool_tip_mm: [f64; 3],
    /// The control's contour tolerance where a program sets none (cycle 32 `T`), mm; default 0.002.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contour_tolerance_mm: Option<f64>,
    /// The same on the rotary axes (cycle 32 `TA`), deg; default 0.002.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contour_tolerance_deg: Option<f64>,
    pub linear: Vec<LinearAxisFile>,
    /// Two rotary axes, in chain order from the machine base outwards on each side; or one (a four-axis
    /// machine, which has no singular orientation).
    pub rotary: Vec<RotaryAxisFile>,
    /// Where the control's machine coordinates lie (`G53`, `M91`, `SUPA`, `G28`); without it a
    /// program's machine-coordinate moves are refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub machine_coordinates: Option<MachineCoordinatesFile>,
    /// M functions this machine's control defines beyond its dialect's own (a maker's, a LinuxCNC
    /// remap such as vismach's `M428`), each with what it does to the motion.
    #[serde(default, rename = "m_function", skip_serializing_if = "Vec::is_empty")]
    pub m_functions: Vec<MFunctionFile>,
    /// How far an arc's end may lie off its circle (end radius less start radius) before the control
    /// refuses it, mm: Fanuc's parameter No. 3410, LinuxCNC's CENTER_ARC_RADIUS_TOLERANCE (default
    /// 0.00127 mm, LinuxCNC's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arc_radius_tolerance_mm: Option<f64>,
    /// Heidenhain cycle 19's angles are spatial angles (machine parameter MP7500 bit 1 = 1), not the
    /// rotary axes' positions (bit 1 = 0, the default).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub cycle19_spatial: bool,
    /// The control starts with tool-centre-point kinematics on (LinuxCNC's bridgemill starts in
    /// 5axiskins): a program's X Y Z are the tool tip before any M code switches them.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub tcp_at_start: bool,
    /// Siemens: the control's basic system is inch (MD10240 SCALING_SYSTEM_IS_METRIC = 0): a program
    /// without G70/G71 is in inches, and F is in inch/min under G70 and G71 alike (G700/G710 set it).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub inch_basic_system: bool,
    /// Fanuc, Haas: the motion mode the control is in at power-on and reset, `G00` or `G01` (FANUC
    /// parameter No. 3402 bit 0, G01): what axis words before a program's first G00/G01 do. Without
    /// it they are refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub power_on_motion: Option<String>,
    /// Heidenhain TNC: the unit of F in an inch program, `"tenths"` (1/10 inch/min: the TNC7 user's
    /// manual, "Cutting data") or `"whole"` (inch/min, as NX's sample posts write it). Without it an
    /// inch program's F is read in tenths and the program is refused once at its header.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tnc_inch_feed: Option<String>,
    /// Sinumerik: setting data SD42940 TOOL_LENGTH_CONST, the plane whose assignment of a milling tool's
    /// length to the axes holds whatever G17-G19 is programmed (17: its length stays on Z); 0 (the
    /// length goes to the axis normal to each plane) or absent: moves under G18/G19 with the tool's
    /// offsets on are refused (the length is not known).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tool_length_const: Option<u32>,
    /// FANUC: how a feed move of the rotary axes alone under tool-centre-point control (G43.4/G43.5: the
    /// tool tip stands on the workpiece) is fed, `"programmed"` (at F: parameter No. 19696 bit 6 RFC = 1)
    /// or `"max-cutting"` (at the maximum cutting feedrate, parameter No. 1422: RFC = 0, not modelled).
    /// Without it such a move is refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tcp_rotary_feed: Option<String>,
    /// Fanuc, Haas: what a length, angle or time written without a decimal point counts, `"increments"`
    /// (least input increments, `X5` is 0.005 mm: FANUC parameter No. 3401 bit 0 DPI = 0, Haas Setting
    /// 162 "Default to float" off; the default) or `"calculator"` (`X5` is 5 mm: DPI = 1, Setting 162 on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub decimal_point_input: Option<String>,
    /// The control's canned-cycle settings that shape their motion.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub canned_cycles: Option<CannedCyclesFile>,
    /// Cycles of the machine maker's own that set the control's dynamics and move nothing (DMG's
    /// Heidenhain cycle 392 ATC), by number.
    #[serde(default, rename = "cycle", skip_serializing_if = "Vec::is_empty")]
    pub cycles: Vec<CycleFile>,
    /// The Sinumerik swivel data set `CYCLE800` uses ($TC_CARR...): without it a swivel is refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub swivel: Option<SwivelFile>,
    /// A quill: a sixth, linear axis along the tool (LinuxCNC bridgemill's W); without it its
    /// words are refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quill: Option<QuillFile>,
    /// LinuxCNC HAL pins a program may read (`#<_hal[name]>` with `[RS274NGC]HAL_PIN_VARS = 1`,
    /// LinuxCNC manual §11.4.3.6), with the values the configuration gives them.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub hal_pins: std::collections::BTreeMap<String, f64>,
}

/// `[machine_coordinates]`: the control's machine coordinate system in this file's frame.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MachineCoordinatesFile {
    /// The linear axes' positions in this file's frame (the frame of `center_mm` and the axis
    /// ranges) where the control's machine coordinates read X0 Y0 Z0, mm.
    pub zero_mm: [f64; 3],
    /// Reference points in machine coordinates, mm: the first is where `G28` goes (Fanuc's reference
    /// position, parameter 1240), the others `G30 P2`, `P3`, ... Default: the first at the machine zero.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub reference_points_mm: Vec<[f64; 3]>,
    /// Heidenhain `M92`'s datum (the machine maker's, such as the tool change position), in machine
    /// coordinates, mm; without it `M92` is refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub m92_datum_mm: Option<[f64; 3]>,
}

/// `[canned_cycles]`: the control's settings of its peck cycles.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CannedCyclesFile {
    /// G73's retract after each peck, mm (Fanuc parameter No. 5114, Haas Setting 22).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub g73_retract_mm: Option<f64>,
    /// G83's stop short of the last depth on the way back down, mm (Fanuc parameter No. 5115).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub g83_clearance_mm: Option<f64>,
    /// LinuxCNC's G73 back-off after each peck, mm (LinuxCNC 2.10's `[RS274NGC]G73_PECK_CLEARANCE`;
    /// 2.9 has none and backs off 0.010 in, `G83_RAPID_DELTA`). Programs read as LinuxCNC's take
    /// only these two keys: the Fanuc ones above are another control's parameters.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub g73_peck_clearance_mm: Option<f64>,
    /// LinuxCNC's G83 stop short of the last depth, mm (2.10's `[RS274NGC]G83_PECK_CLEARANCE`; 2.9:
    /// 0.010 in).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub g83_peck_clearance_mm: Option<f64>,
}

/// `[swivel]`: the Sinumerik swivel data set `CYCLE800` turns the working plane with ($TC_CARR1-65,
/// set at commissioning; its kinematics are this file's).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SwivelFile {
    /// The names a program may call it by (`_TC`, as `"R_DATA"`; blanks around a name are not part
    /// of it).
    pub names: Vec<String>,
    /// Where `_FR` 1 and 2 retract to before swivelling, machine coordinates, mm ($TC_CARR38-40): 1
    /// moves Z there, 2 Z and then X and Y.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub retract_mm: Option<[f64; 3]>,
    /// The rotary axis whose higher (`_DIR` +1) or lower (-1) value picks the solution (the data
    /// set's direction reference): the tilting axis unless named.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction_axis: Option<String>,
}

/// `[quill]`: a linear axis that moves the tool along its own axis, the tool tip going with it.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct QuillFile {
    /// Its address letter in programs (`W`).
    pub name: String,
    pub min_mm: f64,
    pub max_mm: f64,
    pub velocity_mm_per_min: f64,
    /// Which way a positive move takes the tool tip: +1 towards the spindle (out of the work), -1
    /// away from it.
    pub sense: f64,
    /// What it is and where the figures come from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub what: Option<String>,
}

/// `[[cycle]]`: one of the machine maker's cycles that moves nothing.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CycleFile {
    /// The cycle's number (`392` for `CYCL DEF 392`).
    pub number: u32,
    /// What it is, and why it moves nothing.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub what: String,
}

/// `[[m_function]]`: one M function of this machine's control.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MFunctionFile {
    /// The M number (`428` for `M428`).
    pub code: u32,
    /// What it does to the motion: `tcp-on`, `tcp-off`, or `event` (no motion of its own).
    pub action: String,
    /// What it is, for people (`rotary brake on`, the maker's manual).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub what: String,
}

fn default_tool_axis() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

/// A linear axis of a machine file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LinearAxisFile {
    pub name: String,
    pub min_mm: f64,
    pub max_mm: f64,
    pub velocity_mm_per_min: f64,
    pub acceleration_mm_per_s2: f64,
    pub jerk_mm_per_s3: f64,
}

/// A rotary axis of a machine file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RotaryAxisFile {
    pub name: String,
    /// "table" (turns the workpiece) or "head" (turns the spindle).
    pub carrier: Carrier,
    /// Direction about which a positive move turns its carrier (right-handed), machine frame at home.
    pub axis: [f64; 3],
    /// A point on the axis, machine frame at home, mm.
    #[serde(default)]
    pub center_mm: [f64; 3],
    /// Range in degrees; omit both for an unlimited (multi-turn) axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_deg: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_deg: Option<f64>,
    pub velocity_deg_per_s: f64,
    pub acceleration_deg_per_s2: f64,
    pub jerk_deg_per_s3: f64,
    /// The unit its control reads this axis' program words in: `deg` (the default, every
    /// industrial control) or `rad` (a hobby control whose rotary axis is set up in radians).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub program_unit: Option<String>,
}

fn vec3(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

/// A vector field: finite in every component.
fn finite(field: &str, v: [f64; 3]) -> Result<Vector3<f64>, String> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(vec3(v))
    } else {
        Err(format!("`{field}` = {v:?}: every component must be finite"))
    }
}

/// A direction field: finite and of non-zero length (normalised).
fn direction(field: &str, v: [f64; 3]) -> Result<Vector3<f64>, String> {
    let d = finite(field, v)?;
    d.try_normalize(1e-9).ok_or_else(|| format!("`{field}` = {v:?}: a direction must have non-zero length"))
}

/// Angle between two unit directions, folded to [0, 90] degrees (parallel or antiparallel: 0).
fn line_angle_deg(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.cross(b).norm().atan2(a.dot(b).abs()).to_degrees()
}

/// Two rotary axes closer to parallel than this, or a tool axis this close to its primary axis, make
/// no five-axis machine (the orientation map loses a degree of freedom).
const MIN_CHAIN_ANGLE_DEG: f64 = 1.0;

impl MachineFile {
    /// Validate and build the machine (SI inside); `origin` names the file in errors. Every refusal
    /// names the field, as `rotary[1].axis`.
    pub fn build(&self, origin: &str) -> Result<Machine, MachineError> {
        self.build_checked().map_err(|message| MachineError::Invalid { name: self.name.clone(), origin: origin.to_string(), message })
    }

    /// The chain of a five-axis machine's two rotary joints (file order), checked: not parallel, and
    /// the primary axis tilts the tool.
    fn five_axis_chain(&self, joints: &[crate::kinematics::RotaryJoint], tool_axis: Vector3<f64>, tool_tip: Vector3<f64>) -> Result<TwoRotaryChain, String> {
        let between = line_angle_deg(&joints[0].axis, &joints[1].axis);
        if between < MIN_CHAIN_ANGLE_DEG {
            return Err(format!(
                "`rotary[0].axis` ({}) and `rotary[1].axis` ({}) are {between:.3} deg from parallel: two parallel rotary axes turn the tool about one line, not a five-axis machine",
                self.rotary[0].name, self.rotary[1].name
            ));
        }
        let chain = TwoRotaryChain::new([joints[0].clone(), joints[1].clone()], tool_axis, tool_tip * MM).map_err(|e| e.to_string())?;
        let r1 = 1 - chain.secondary_slot();
        let tilt = line_angle_deg(&tool_axis, &joints[r1].axis);
        if tilt < MIN_CHAIN_ANGLE_DEG {
            return Err(format!(
                "`tool_axis` is {tilt:.3} deg from `rotary[{r1}].axis` ({}), the primary rotary axis: turning it does not tilt the tool, so the tool axis cannot leave a cone about `rotary[{}].axis`",
                self.rotary[r1].name,
                1 - r1
            ));
        }
        Ok(chain)
    }

    /// The chain of a four-axis machine's one rotary joint, checked: it tilts the tool.
    fn four_axis_chain(&self, joint: &crate::kinematics::RotaryJoint, tool_axis: Vector3<f64>, tool_tip: Vector3<f64>) -> Result<TwoRotaryChain, String> {
        let tilt = line_angle_deg(&tool_axis, &joint.axis);
        if tilt < MIN_CHAIN_ANGLE_DEG {
            return Err(format!("`tool_axis` is {tilt:.3} deg from `rotary[0].axis` ({}), the only rotary axis: turning it does not tilt the tool", self.rotary[0].name));
        }
        TwoRotaryChain::four_axis(joint.clone(), tool_axis, tool_tip * MM).map_err(|e| e.to_string())
    }

    fn build_checked(&self) -> Result<Machine, String> {
        if self.linear.len() != 3 {
            return Err(format!("needs exactly 3 [[linear]] axes, found {}", self.linear.len()));
        }
        if !(1..=2).contains(&self.rotary.len()) {
            return Err(format!("needs 2 [[rotary]] axes (a five-axis machine) or 1 (a four-axis machine), found {}", self.rotary.len()));
        }
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let mut axes: Vec<Axis> = Vec::with_capacity(5);
        for (i, l) in self.linear.iter().enumerate() {
            let f = format!("linear[{i}]");
            if !(l.min_mm.is_finite() && l.max_mm.is_finite() && l.min_mm < l.max_mm) {
                return Err(format!("`{f}.min_mm` = {}, `{f}.max_mm` = {} ({}): need finite min_mm < max_mm", l.min_mm, l.max_mm, l.name));
            }
            for (field, v) in [("velocity_mm_per_min", l.velocity_mm_per_min), ("acceleration_mm_per_s2", l.acceleration_mm_per_s2), ("jerk_mm_per_s3", l.jerk_mm_per_s3)] {
                if !positive(v) {
                    return Err(format!("`{f}.{field}` = {v} ({}): must be positive and finite", l.name));
                }
            }
            axes.push(Axis {
                name: l.name.clone(),
                kind: AxisKind::Linear,
                limits: AxisLimits {
                    min: l.min_mm * MM,
                    max: l.max_mm * MM,
                    velocity: l.velocity_mm_per_min * MM_PER_MIN,
                    acceleration: l.acceleration_mm_per_s2 * MM,
                    jerk: l.jerk_mm_per_s3 * MM,
                },
            });
        }
        let mut joints = Vec::with_capacity(2);
        let mut word_units = Vec::with_capacity(2);
        for (i, r) in self.rotary.iter().enumerate() {
            let f = format!("rotary[{i}]");
            let (min, max) = match (r.min_deg, r.max_deg) {
                (None, None) => (f64::NEG_INFINITY, f64::INFINITY),
                (Some(a), Some(b)) if a.is_finite() && b.is_finite() && a < b => (a * DEG, b * DEG),
                (a, b) => return Err(format!("`{f}.min_deg` = {a:?}, `{f}.max_deg` = {b:?} ({}): give both, finite, min_deg < max_deg, or neither (unlimited)", r.name)),
            };
            for (field, v) in [("velocity_deg_per_s", r.velocity_deg_per_s), ("acceleration_deg_per_s2", r.acceleration_deg_per_s2), ("jerk_deg_per_s3", r.jerk_deg_per_s3)] {
                if !positive(v) {
                    return Err(format!("`{f}.{field}` = {v} ({}): must be positive and finite", r.name));
                }
            }
            let axis = direction(&format!("{f}.axis"), r.axis)?;
            let center = finite(&format!("{f}.center_mm"), r.center_mm)?;
            axes.push(Axis {
                name: r.name.clone(),
                kind: AxisKind::Rotary,
                limits: AxisLimits {
                    min,
                    max,
                    velocity: r.velocity_deg_per_s * DEG,
                    acceleration: r.acceleration_deg_per_s2 * DEG,
                    jerk: r.jerk_deg_per_s3 * DEG,
                },
            });
            joints.push(joint(&r.name, r.carrier, axis, center * MM));
            word_units.push(match r.program_unit.as_deref() {
                None | Some("deg") => DEG,
                Some("rad") => 1.0,
                Some(other) => return Err(format!("`{f}.program_unit` = \"{other}\" ({}): expected \"deg\" or \"rad\"", r.name)),
            });
        }
        if self.rotary.len() == 1 {
            // A four-axis machine: its fifth axis is the chain's locked joint, unnamed (no program
            // word reaches it) and held at 0 (range 0..0); its dynamics are the rotary axis' own.
            let limits = AxisLimits { min: 0.0, max: 0.0, ..axes[3].limits };
            axes.push(Axis { name: String::new(), kind: AxisKind::Rotary, limits });
            word_units.push(DEG);
        }
        let mut names: Vec<String> = axes.iter().map(|a| a.name.to_ascii_uppercase()).collect();
        names.sort();
        names.dedup();
        if names.len() != 5 {
            return Err(format!("axis names must be distinct: {:?}", axes.iter().map(|a| a.name.as_str()).collect::<Vec<_>>()));
        }
        let tool_axis = direction("tool_axis", self.tool_axis)?;
        let tool_tip = finite("tool_tip_mm", self.tool_tip_mm)?;
        let chain = match joints.len() {
            1 => self.four_axis_chain(&joints[0], tool_axis, tool_tip)?,
            _ => self.five_axis_chain(&joints, tool_axis, tool_tip)?,
        };
        let axes: [Axis; 5] = axes.try_into().map_err(|_| "five axes".to_string())?;
        let tolerance = |field: &str, value: Option<f64>, unit: f64, default: f64, max: f64, ok: fn(f64) -> bool| match value {
            None => Ok(default),
            Some(v) if ok(v * unit) => Ok(v * unit),
            Some(v) => Err(format!("`{field}` = {v}: expected a tolerance from 0 to {}", max / unit)),
        };
        let (d, m) = (ContourTolerance::DEFAULT, ContourTolerance::MAX);
        let contour_tolerance = ContourTolerance {
            linear_m: tolerance("contour_tolerance_mm", self.contour_tolerance_mm, MM, d.linear_m, m.linear_m, ContourTolerance::linear_ok)?,
            rotary_rad: tolerance("contour_tolerance_deg", self.contour_tolerance_deg, DEG, d.rotary_rad, m.rotary_rad, ContourTolerance::rotary_ok)?,
        };
        let mut m_functions = Vec::with_capacity(self.m_functions.len());
        for (i, m) in self.m_functions.iter().enumerate() {
            let action = m.action.parse::<crate::program::MCodeAction>().map_err(|e| format!("`m_function[{i}].action` (M{}): {e}", m.code))?;
            if self.m_functions[..i].iter().any(|o| o.code == m.code) {
                return Err(format!("`m_function[{i}].code` = {}: M{} is defined twice", m.code, m.code));
            }
            m_functions.push(crate::program::MCodeRule { code: m.code, action });
        }
        let machine_coordinates = match &self.machine_coordinates {
            None => None,
            Some(c) => {
                let zero = finite("machine_coordinates.zero_mm", c.zero_mm)? * MM;
                let mut references = Vec::with_capacity(c.reference_points_mm.len().max(1));
                for (i, r) in c.reference_points_mm.iter().enumerate() {
                    references.push(finite(&format!("machine_coordinates.reference_points_mm[{i}]"), *r)? * MM);
                }
                if references.is_empty() {
                    references.push(Vector3::zeros());
                }
                let m92_datum = c.m92_datum_mm.map(|d| finite("machine_coordinates.m92_datum_mm", d)).transpose()?.map(|d| d * MM);
                Some(super::MachineCoordinates { zero, references, m92_datum })
            }
        };
        let mut hal_pins = std::collections::BTreeMap::new();
        for (name, v) in &self.hal_pins {
            if !v.is_finite() {
                return Err(format!("`hal_pins.\"{name}\"` = {v}: must be finite"));
            }
            hal_pins.insert(name.to_ascii_lowercase(), *v);
        }
        let arc_radius_tolerance = match self.arc_radius_tolerance_mm {
            None => None,
            Some(t) if t.is_finite() && t > 0.0 && t <= 1.0 => Some(t * MM),
            Some(t) => return Err(format!("`arc_radius_tolerance_mm` = {t}: expected more than 0 and at most 1 mm")),
        };
        let power_on_motion = match self.power_on_motion.as_deref().map(str::trim) {
            None => None,
            Some(g) if g.eq_ignore_ascii_case("G00") || g.eq_ignore_ascii_case("G0") => Some(crate::program::Motion::Rapid),
            Some(g) if g.eq_ignore_ascii_case("G01") || g.eq_ignore_ascii_case("G1") => Some(crate::program::Motion::Linear),
            Some(g) => return Err(format!("`power_on_motion` = \"{g}\": expected \"G00\" or \"G01\" (FANUC parameter No. 3402 bit 0)")),
        };
        let tnc_inch_feed_tenths = match self.tnc_inch_feed.as_deref().map(str::trim) {
            None => None,
            Some("tenths") => Some(true),
            Some("whole") => Some(false),
            Some(v) => return Err(format!("`tnc_inch_feed` = \"{v}\": expected \"tenths\" (1/10 inch/min) or \"whole\" (inch/min)")),
        };
        let tool_length_const = match self.tool_length_const {
            None | Some(0) => None,
            Some(p @ (17 | 18 | 19)) => Some(p),
            Some(v) => return Err(format!("`tool_length_const` = {v}: expected 0, 17, 18 or 19 (Sinumerik setting data SD42940 TOOL_LENGTH_CONST, the plane whose tool length assignment holds)")),
        };
        let tcp_rotary_feed = match self.tcp_rotary_feed.as_deref().map(str::trim) {
            None => None,
            Some("programmed") => Some(crate::machine::TcpRotaryFeed::Programmed),
            Some("max-cutting") => Some(crate::machine::TcpRotaryFeed::MaxCutting),
            Some(v) => return Err(format!("`tcp_rotary_feed` = \"{v}\": expected \"programmed\" or \"max-cutting\" (FANUC parameter No. 19696 bit 6 RFC)")),
        };
        let calculator_input = match self.decimal_point_input.as_deref().map(str::trim) {
            None | Some("increments") => false,
            Some("calculator") => true,
            Some(v) => return Err(format!("`decimal_point_input` = \"{v}\": expected \"increments\" or \"calculator\" (FANUC parameter No. 3401 bit 0 DPI, Haas Setting 162)")),
        };
        let mut peck = [None; 4];
        if let Some(c) = &self.canned_cycles {
            let keys = [
                ("canned_cycles.g73_retract_mm", c.g73_retract_mm),
                ("canned_cycles.g83_clearance_mm", c.g83_clearance_mm),
                ("canned_cycles.g73_peck_clearance_mm", c.g73_peck_clearance_mm),
                ("canned_cycles.g83_peck_clearance_mm", c.g83_peck_clearance_mm),
            ];
            for (k, (field, v)) in keys.into_iter().enumerate() {
                match v {
                    None => {}
                    Some(d) if d.is_finite() && (0.0..=100.0).contains(&d) => peck[k] = Some(d * MM),
                    Some(d) => return Err(format!("`{field}` = {d}: expected 0 to 100 mm")),
                }
            }
        }
        let swivel = match &self.swivel {
            None => None,
            Some(w) => {
                if w.names.is_empty() || w.names.iter().any(|n| n.trim().is_empty()) {
                    return Err("`swivel.names`: name the data set (a name that is not blank)".into());
                }
                let retract = w.retract_mm.map(|r| finite("swivel.retract_mm", r)).transpose()?.map(|r| r * MM);
                let direction_axis = match &w.direction_axis {
                    None => None,
                    Some(n) => Some(self.rotary.iter().position(|r| r.name.eq_ignore_ascii_case(n)).map(|k| 3 + k).ok_or_else(|| format!("`swivel.direction_axis` = {n:?}: not one of the rotary axes"))?),
                };
                Some(super::Swivel { names: w.names.iter().map(|n| n.trim().to_string()).collect(), retract, direction_axis })
            }
        };
        let quill = match &self.quill {
            None => None,
            Some(q) => {
                let letter = match q.name.trim().to_ascii_uppercase().as_str() {
                    l @ ("U" | "V" | "W") => l.chars().next().unwrap_or('W'),
                    other => return Err(format!("`quill.name` = {other:?}: expected U, V or W (X Y Z A B C are the five axes')")),
                };
                if !(q.min_mm.is_finite() && q.max_mm.is_finite() && q.min_mm < q.max_mm) {
                    return Err(format!("`quill.min_mm`..`quill.max_mm` = {}..{}: expected a finite range, min below max", q.min_mm, q.max_mm));
                }
                if !(q.velocity_mm_per_min.is_finite() && q.velocity_mm_per_min > 0.0) {
                    return Err(format!("`quill.velocity_mm_per_min` = {}: expected a positive speed", q.velocity_mm_per_min));
                }
                if q.sense != 1.0 && q.sense != -1.0 {
                    return Err(format!("`quill.sense` = {}: expected 1 or -1", q.sense));
                }
                Some(super::Quill { letter, min: q.min_mm * MM, max: q.max_mm * MM, velocity: q.velocity_mm_per_min * MM / 60.0, sense: q.sense })
            }
        };
        let text = |field: &str, v: &Option<String>| match v {
            Some(s) if s.trim().is_empty() => Err(format!("`{field}` is empty: give it or leave it out")),
            _ => Ok(v.clone()),
        };
        let dialect = self.dialect.as_deref().map(|d| d.parse::<crate::program::Dialect>().map_err(|e| format!("`dialect`: {e}"))).transpose()?;
        Ok(Machine {
            dialect,
            name: self.name.clone(),
            description: self.description.clone(),
            maker: text("maker", &self.maker)?,
            model: text("model", &self.model)?,
            control: text("control", &self.control)?,
            axes,
            chain,
            contour_tolerance,
            machine_coordinates,
            m_functions,
            hal_pins,
            rotary_word_units: [word_units[0], word_units[1]],
            peck_distances: [peck[0], peck[1]],
            linuxcnc_peck_clearances: [peck[2], peck[3]],
            arc_radius_tolerance,
            cycle19_spatial: self.cycle19_spatial,
            tcp_at_start: self.tcp_at_start,
            inch_basic_system: self.inch_basic_system,
            power_on_motion,
            tcp_rotary_feed,
            tool_length_const,
            tnc_inch_feed_tenths,
            calculator_input,
            state_cycles: self.cycles.iter().map(|c| c.number).collect(),
            swivel,
            quill,
        })
    }
}
