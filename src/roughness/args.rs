//! The command-line options that load a roughness profile, shared by `fiveaxis analyze` and the
//! Rerun bridge so both read and align a profile the same way.

use super::{read_profile, CsvUnits, Profile};
use std::path::PathBuf;

/// Where the roughness profile comes from and how it lies along the workpiece x.
#[derive(Debug, Clone, clap::Args)]
pub struct RoughnessArgs {
    /// A measured roughness profile (X3P or CSV) across the part.
    #[arg(long)]
    pub roughness: Option<PathBuf>,
    /// Workpiece x of the profile's x = 0, mm.
    #[arg(long = "roughness-offset-mm", default_value_t = 0.0)]
    pub roughness_offset_mm: f64,
    /// The profile runs against the workpiece x.
    #[arg(long = "roughness-reversed")]
    pub roughness_reversed: bool,
    /// ISO 16610-21 cut-off lambda_c, mm.
    #[arg(long = "cutoff-mm", default_value_t = 0.8)]
    pub cutoff_mm: f64,
    /// CSV x unit when its header does not say: m, mm, um or nm.
    #[arg(long = "x-unit")]
    pub x_unit: Option<String>,
    /// CSV height unit when its header does not say: m, mm, um or nm.
    #[arg(long = "z-unit")]
    pub z_unit: Option<String>,
}

impl RoughnessArgs {
    /// The profile aligned to the workpiece x, and the cut-off (m); None without `--roughness`.
    /// Errors name the file or the flag at fault.
    pub fn load(&self) -> Result<Option<(Profile, f64)>, String> {
        let Some(path) = &self.roughness else { return Ok(None) };
        if !(self.cutoff_mm > 0.0) || !self.cutoff_mm.is_finite() {
            return Err(format!("--cutoff-mm must be a positive length, got {}", self.cutoff_mm));
        }
        let unit = |flag: &str, u: &Option<String>| -> Result<Option<f64>, String> {
            match u.as_deref() {
                None => Ok(None),
                Some("m") => Ok(Some(1.0)),
                Some("mm") => Ok(Some(1e-3)),
                Some("um") | Some("µm") => Ok(Some(1e-6)),
                Some("nm") => Ok(Some(1e-9)),
                Some(o) => Err(format!("{flag}: unknown unit '{o}': m, mm, um or nm")),
            }
        };
        let units = CsvUnits { x: unit("--x-unit", &self.x_unit)?, z: unit("--z-unit", &self.z_unit)? };
        let profile = read_profile(path, units).map_err(|e| e.to_string())?;
        Ok(Some((profile.aligned(self.roughness_offset_mm * 1e-3, self.roughness_reversed), self.cutoff_mm * 1e-3)))
    }
}
