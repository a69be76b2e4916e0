//! Machine descriptions in TOML, then the machine's forward and inverse kinematics at its home
//! and at a tilted tool axis (what every command does first with a machine).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fiveaxis_fuzz::targets::machine_toml(data));
