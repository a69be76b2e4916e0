//! Machine descriptions in URDF, then the same kinematics as `machine_toml`.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fiveaxis_fuzz::targets::machine_urdf(data));
