//! The control's set-up flags shared by every command and node that reads a program (`--m-code`,
//! `--orientation`): clap lives here, above the readers' plain [`ReadOptions`].

use crate::program::{MCodeRule, Orientation, ReadOptions};
use clap::builder::TypedValueParser;

/// How the control is set up, for every command and node that reads a program: `--m-code`,
/// `--orientation`.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct ControlArgs {
    /// What a machine-specific M code does, `CODE=ACTION` with ACTION tcp-on, tcp-off or event
    /// (repeatable; LinuxCNC's vismach five-axis demos: `--m-code 428=tcp-on --m-code 429=tcp-off`).
    /// An RS274NGC program with any other non-standard M code is refused.
    #[arg(long = "m-code", value_name = "CODE=ACTION")]
    pub m_codes: Vec<MCodeRule>,
    /// How the control interpolates the tool orientation under tool-centre-point management at
    /// program start (the machine's setting; the program's own words, such as Sinumerik's ORIVECT or
    /// ORIAXES and Heidenhain's FUNCTION TCPM ... PATHCTRL VECTOR or AXIS, still switch it). Default: the dialect's, from its maker's documentation.
    #[arg(long = "orientation", value_name = "MODE", value_parser = orientation_parser())]
    pub orientation: Option<Orientation>,
}

/// `--orientation`'s parser: the modes' names listed as clap's possible values.
fn orientation_parser() -> impl clap::builder::TypedValueParser<Value = Orientation> {
    clap::builder::PossibleValuesParser::new(Orientation::NAMES).map(|s| s.parse::<Orientation>().expect("a listed name parses"))
}

impl ControlArgs {
    /// The readers' options these flags ask for (other options at their defaults).
    pub fn read_options(&self) -> ReadOptions {
        ReadOptions { m_codes: self.m_codes.clone(), orientation: self.orientation, ..Default::default() }
    }
}
