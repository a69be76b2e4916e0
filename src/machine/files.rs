//! Machine files: what `--machine` names (a built-in machine, or a TOML or URDF file) read from
//! disk here, so that the core parses text only.

use fiveaxis_core::machine::{builtin_file, urdf, Machine, MachineError};
use std::path::Path;

/// The machine `spec` names: a built-in name, or else a path to a URDF (`.urdf`) or TOML machine
/// file (an unknown name or an invalid file is an error naming the field).
pub fn load(spec: &str) -> Result<Machine, MachineError> {
    if builtin_file(spec).is_some() {
        return Machine::builtin(spec);
    }
    if urdf::is_urdf_path(spec) {
        return urdf::read(&read_machine_file(spec)?, spec);
    }
    Machine::from_toml_str(&description_text(spec)?, spec)
}

/// The TOML text a `--machine` names: a built-in machine's, or else a machine file's (a `.toml` path
/// or one that exists); anything else is an unknown machine.
pub fn description_text(spec: &str) -> Result<std::borrow::Cow<'static, str>, MachineError> {
    if let Some(text) = builtin_file(spec) {
        return Ok(text.into());
    }
    let path = Path::new(spec);
    if path.extension().is_some_and(|e| e == "toml") || path.exists() {
        return read_machine_file(spec).map(Into::into);
    }
    Err(MachineError::Unknown(spec.to_string()))
}

/// Largest machine file read (bytes): a machine is a few kB.
pub const MAX_MACHINE_FILE_BYTES: u64 = urdf::MAX_BYTES as u64;

/// A machine file's text, read no further than [`MAX_MACHINE_FILE_BYTES`] (a larger one is refused).
pub fn read_machine_file(spec: &str) -> Result<String, MachineError> {
    use std::io::Read as _;
    let io = |source| MachineError::Io { path: spec.to_string(), source };
    let mut text = String::new();
    std::fs::File::open(spec).map_err(io)?.take(MAX_MACHINE_FILE_BYTES + 1).read_to_string(&mut text).map_err(io)?;
    if text.len() as u64 > MAX_MACHINE_FILE_BYTES {
        return Err(MachineError::Parse { path: spec.to_string(), message: format!("more than {MAX_MACHINE_FILE_BYTES} bytes: a machine file is a few kB") });
    }
    Ok(text)
}
