//! X3P files as they come (a zip container): read as a roughness profile, then filtered and
//! windowed as `fiveaxis analyze --roughness` does (lambda_c 0.8 mm, a window every 0.5 mm).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fiveaxis_fuzz::targets::x3p_container(data));
