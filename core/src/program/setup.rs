//! What a reader is told of the control that runs the program: [`super::ReadOptions`] resolved for one
//! dialect (the M functions in effect, the orientation interpolation at start, a length unit the
//! user imposes, the machine with its machine coordinates and kinematics).

use super::interp::Interpreter;
use super::{Dialect, MCodeRule, Orientation, ReadOptions};
use crate::machine::Machine;
use std::sync::Arc;

/// A length unit a program's numbers are read in (`--units`), overriding what the program says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LengthUnit {
    #[default]
    Mm,
    Inch,
}

impl LengthUnit {
    /// Metres per unit.
    pub fn metres(self) -> f64 {
        match self {
            LengthUnit::Mm => crate::units::MM,
            LengthUnit::Inch => crate::units::INCH,
        }
    }

    /// The unit's name as people write it.
    pub fn name(self) -> &'static str {
        match self {
            LengthUnit::Mm => "mm",
            LengthUnit::Inch => "inch",
        }
    }

    /// The names `--units` takes.
    pub const NAMES: [&'static str; 2] = ["mm", "inch"];
}

impl std::str::FromStr for LengthUnit {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "mm" => Ok(LengthUnit::Mm),
            "inch" | "in" | "inches" => Ok(LengthUnit::Inch),
            other => Err(format!("unknown length unit '{other}': expected mm or inch")),
        }
    }
}

/// The unit of the rotary angles in CL data (`--cl-angles`): APT's `ROTABL/` is in degrees (ICAM's
/// vocabulary), but SOLIDWORKS CAM's `.clt` writes radians (`ROTABL/ 1.570796,AAXIS`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AngleUnit {
    #[default]
    Deg,
    Rad,
}

impl AngleUnit {
    /// Radians per unit.
    pub fn radians(self) -> f64 {
        match self {
            AngleUnit::Deg => crate::units::DEG,
            AngleUnit::Rad => 1.0,
        }
    }

    /// The unit's name as people write it.
    pub fn name(self) -> &'static str {
        match self {
            AngleUnit::Deg => "deg",
            AngleUnit::Rad => "rad",
        }
    }

    /// The names `--cl-angles` takes.
    pub const NAMES: [&'static str; 2] = ["deg", "rad"];
}

impl std::str::FromStr for AngleUnit {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "deg" | "degrees" => Ok(AngleUnit::Deg),
            "rad" | "radians" => Ok(AngleUnit::Rad),
            other => Err(format!("unknown angle unit '{other}': expected deg or rad")),
        }
    }
}

/// The options of one read, for one dialect.
#[derive(Debug, Clone)]
pub struct Setup {
    pub dialect: Dialect,
    /// M-code rules in effect: the `--m-code` flags, then the machine's own.
    pub m_codes: Vec<MCodeRule>,
    /// Orientation interpolation at program start.
    pub orientation: Orientation,
    /// A length unit imposed on the program (`--units`): its own unit statements are then noted, not obeyed.
    pub units: Option<LengthUnit>,
    /// The machine, where the read is for one.
    pub machine: Option<Arc<Machine>>,
    /// Feed for CL data without one, mm/min.
    pub cl_feed_mm_per_min: f64,
    /// The unit of CL data's rotary angles (`ROTABL/`).
    pub cl_angles: AngleUnit,
    /// Lines loops, repeats and calls may run beyond the program's own ([`ReadOptions::max_run_lines`]).
    pub max_run_lines: usize,
    /// The machine's tool table ([`ReadOptions::tool_table`]).
    pub tool_table: Option<Arc<super::ToolTable>>,
    /// Where LinuxCNC subroutines of other files come from ([`ReadOptions::subroutine_files`]).
    pub subroutine_files: Option<Arc<dyn super::SubroutineFiles>>,
}

impl Setup {
    /// A setup with these M-code rules and orientation, nothing else (the readers' plain entry points).
    pub fn plain(dialect: Dialect, m_codes: &[MCodeRule], orientation: Orientation) -> Setup {
        ReadOptions { m_codes: m_codes.to_vec(), orientation: Some(orientation), ..ReadOptions::default() }.setup(dialect)
    }

    /// The G-code interpreter this setup starts.
    pub fn interpreter(&self) -> Interpreter {
        Interpreter::new(self.dialect).with_m_codes(&self.m_codes).with_orientation(self.orientation).with_units(self.units).with_machine(self.machine.as_ref()).with_tool_table(self.tool_table.clone())
    }
}

impl ReadOptions {
    /// These options resolved for a program in `dialect`.
    pub fn setup(&self, dialect: Dialect) -> Setup {
        Setup {
            dialect,
            m_codes: self.m_code_rules(),
            orientation: self.orientation_for(dialect),
            units: self.units,
            machine: self.machine.clone(),
            cl_feed_mm_per_min: self.cl_feed_mm_per_min,
            cl_angles: self.cl_angles,
            max_run_lines: self.max_run_lines,
            tool_table: self.tool_table.clone(),
            subroutine_files: self.subroutine_files.clone(),
        }
    }
}
