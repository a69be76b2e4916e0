//! Flag groups shared by the `fiveaxis` commands, the nodes and the Rerun bridge, declared once:
//! `--machine`, the control's set-up (`--m-code`, `--orientation`) and `--max-listed-regions`. Clap
//! lives here, above the core's plain options.

use crate::machine::{Machine, MachineError, DEFAULT_MACHINE};
use crate::program::{AngleUnit, LengthUnit, MCodeRule, Orientation, ReadOptions, ToolTable};
use std::sync::Arc;
use clap::builder::TypedValueParser;

/// How the control is set up, for every command and node that reads a program: `--m-code`,
/// `--orientation`, `--units`.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct ControlArgs {
    /// What a machine-specific M code does, `CODE=ACTION` with ACTION tcp-on, tcp-off or event
    /// (repeatable; LinuxCNC's vismach five-axis demos: `--m-code 428=tcp-on --m-code 429=tcp-off`).
    /// Beside the machine file's own (`[[m_function]]`); a program with any other M code outside its
    /// control's list (a machine maker's) is refused.
    #[arg(long = "m-code", value_name = "CODE=ACTION")]
    pub m_codes: Vec<MCodeRule>,
    /// How the control interpolates the tool orientation under tool-centre-point management at
    /// program start (the machine's setting; the program's own words, such as Sinumerik's ORIVECT or
    /// ORIAXES and Heidenhain's FUNCTION TCPM ... PATHCTRL VECTOR or AXIS, still switch it). Default: the dialect's, from its maker's documentation.
    #[arg(long = "orientation", value_name = "MODE", value_parser = orientation_parser())]
    pub orientation: Option<Orientation>,
    /// The length unit of the program's numbers, whatever its own unit statements say (G20/G21,
    /// G70/G71, BEGIN PGM ... INCH, APT UNITS/): for a file whose statement contradicts its numbers,
    /// such as Creo CL data that says UNITS / INCHES on millimetres. Each overruled statement is noted.
    #[arg(long = "units", value_name = "UNIT", value_parser = clap::builder::PossibleValuesParser::new(LengthUnit::NAMES).map(|s| s.parse::<LengthUnit>().expect("a listed name parses")))]
    pub units: Option<LengthUnit>,
    /// The unit of the rotary angles in CL data (APT `ROTABL/`): `deg`, the APT vocabulary's, unless
    /// the file's writer uses radians, as SOLIDWORKS CAM's `.clt` does (`ROTABL/ 1.570796,AAXIS`); a
    /// table turn that contradicts the file's `TLAXIS/` is refused, naming the unit that agrees.
    #[arg(long = "cl-angles", value_name = "UNIT", default_value = "deg", value_parser = clap::builder::PossibleValuesParser::new(AngleUnit::NAMES).map(|s| s.parse::<AngleUnit>().expect("a listed name parses")))]
    pub cl_angles: AngleUnit,
    /// The machine's tool table, as LinuxCNC keeps it (`tool.tbl`: `T1 P1 D6 Z0 ;comment`) or as a
    /// Heidenhain TNC does (`TOOL.T`: `BEGIN TOOL.T MM`, a line of column names, a row per tool):
    /// the diameters an RS274NGC program's cutter radius compensation `G41`/`G42` takes by its `D`
    /// word or for the tool in the spindle (`G41.1`/`G42.1` write the diameter themselves), and the
    /// radii (R + DR) a Heidenhain program's `RL`/`RR` (DIN/ISO: `G41`/`G42`) take for the tool it called and a Sinumerik
    /// program's `G41`/`G42` for the tool `M6` loaded (`T5`, or `T="NAME"` by a TNC table's NAME).
    #[arg(long = "tool-table", value_name = "FILE", value_parser = tool_table_parser)]
    pub tool_table: Option<ToolTable>,
    /// The length unit of the tool table's numbers: the machine's (LinuxCNC's `[TRAJ] LINEAR_UNITS`);
    /// a TNC table's header names its own, which stands.
    #[arg(long = "tool-table-units", value_name = "UNIT", default_value = "mm", value_parser = clap::builder::PossibleValuesParser::new(LengthUnit::NAMES).map(|s| s.parse::<LengthUnit>().expect("a listed name parses")))]
    pub tool_table_units: LengthUnit,
    /// A directory where an RS274NGC program's `o<name> call` of a subroutine it does not define finds
    /// `name.ngc` (LinuxCNC's `[RS274NGC] SUBROUTINE_PATH`), and an 840D program's call of `NAME`
    /// finds `NAME.SPF` when it is not beside the program (the control's subprogram and cycle
    /// directories); repeatable, searched in order.
    #[arg(long = "subroutine-path", value_name = "DIR")]
    pub subroutine_path: Vec<std::path::PathBuf>,
}

/// `--tool-table`'s parser: the file read and checked now, its faults named by line.
fn tool_table_parser(path: &str) -> Result<ToolTable, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
    // A TNC writes its tables in ISO 8859-1 (umlauts in a tool's name): read as such where not UTF-8.
    let text = match String::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => e.into_bytes().into_iter().map(char::from).collect(),
    };
    ToolTable::parse(text.strip_prefix('\u{feff}').unwrap_or(&text)).map_err(|e| format!("{path}: {e}"))
}

/// `--orientation`'s parser: the modes' names listed as clap's possible values.
fn orientation_parser() -> impl clap::builder::TypedValueParser<Value = Orientation> {
    clap::builder::PossibleValuesParser::new(Orientation::NAMES).map(|s| s.parse::<Orientation>().expect("a listed name parses"))
}

impl ControlArgs {
    /// The readers' options these flags ask for (other options at their defaults).
    pub fn read_options(&self) -> ReadOptions {
        ReadOptions { m_codes: self.m_codes.clone(), orientation: self.orientation, units: self.units, cl_angles: self.cl_angles, tool_table: self.tool_table.clone().map(|t| Arc::new(t.in_unit(self.tool_table_units))), subroutine_files: (!self.subroutine_path.is_empty()).then(|| Arc::new(crate::program::SubroutineDirs(self.subroutine_path.clone())) as Arc<dyn crate::program::SubroutineFiles>), ..Default::default() }
    }
}

/// `--machine`: which machine, for every command and node that needs one.
#[derive(Debug, Clone, clap::Args)]
pub struct MachineArgs {
    /// Built-in machine name (`fiveaxis machine list`), or a TOML or URDF (.urdf) machine file.
    #[arg(long = "machine", id = "machine", value_name = "MACHINE", default_value = DEFAULT_MACHINE)]
    pub spec: String,
}

impl Default for MachineArgs {
    fn default() -> Self {
        MachineArgs { spec: DEFAULT_MACHINE.into() }
    }
}

impl MachineArgs {
    /// The machine named (an unknown name or an invalid file is an error naming the field).
    pub fn load(&self) -> Result<Machine, MachineError> {
        crate::machine::load(&self.spec)
    }
}

/// How many regions a report lists (`program analyze`, `run`, `analyze`).
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct ListingArgs {
    /// Regions listed in full per list; the rest are counted and folded into one line (JSON:
    /// `unlisted_regions`: count, time inside, worst figures), so an hours-long run's report stays small.
    #[arg(long = "max-listed-regions", value_name = "N", default_value_t = crate::listing::MAX_LISTED)]
    pub max_listed_regions: usize,
}

/// Which recorded JointState streams to read and how their joints are named (`fiveaxis analyze`,
/// `fiveaxis-rerun replay`): one selection rule, [`crate::recorded`].
#[derive(Debug, Clone, Default, clap::Args)]
pub struct RecordedStreamArgs {
    /// sensor_msgs/JointState topics to read (repeatable; default: all, if the recording has no
    /// AxisState).
    #[arg(long = "joint-state-topic", value_name = "TOPIC")]
    pub joint_state_topics: Vec<String>,
    #[command(flatten)]
    pub axis_map: AxisMapArgs,
    /// Read the input as an MTConnect adapter's SHDR log, against this device description (an
    /// agent's Devices.xml or its /probe answer); each machine axis is the actual POSITION or ANGLE
    /// of the device's axis of the same name, or the data item `--axis-map AXIS=ID` names.
    #[arg(long = "mtconnect-devices", value_name = "DEVICES.XML")]
    pub mtconnect_devices: Option<std::path::PathBuf>,
    /// The device of the description the log is for (name or uuid; default: the only one).
    #[arg(long = "mtconnect-device", value_name = "NAME", requires = "mtconnect_devices")]
    pub mtconnect_device: Option<String>,
}

impl RecordedStreamArgs {
    /// The selection on `machine` (an axis map naming an axis the machine lacks is an error).
    pub fn selection(&self, machine: &Machine) -> Result<crate::recorded::Selection, String> {
        Ok(crate::recorded::Selection {
            joint_state_topics: self.joint_state_topics.clone(),
            axis_map: self.axis_map.resolve(machine)?,
            mtconnect: self.mtconnect_devices.as_ref().map(|d| crate::recorded::MtconnectSource { devices: d.clone(), device: self.mtconnect_device.clone() }),
        })
    }
}

/// `--axis-map`: the joint names of a machine bridge's JointState for the machine's axes, for
/// everything that reads one (live or recorded).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct AxisMapArgs {
    /// Joint name for a machine axis in those JointStates: `--axis-map A=joint_a` (repeatable; axis
    /// names case-insensitive; an axis the machine lacks is refused).
    #[arg(long = "axis-map", value_name = "AXIS=JOINT", value_parser = crate::machine::parse_axis_map)]
    pub pairs: Vec<(String, String)>,
}

impl AxisMapArgs {
    /// Machine axis -> joint name, resolved against `machine` (an axis the machine lacks is an error
    /// naming its axes).
    pub fn resolve(&self, machine: &Machine) -> Result<std::collections::BTreeMap<String, String>, String> {
        machine.resolve_axis_map(&self.pairs)
    }
}
