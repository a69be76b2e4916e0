//! CSV roughness profiles (header-named units, or the first byte picks the command-line units),
//! then filtered and windowed as `fiveaxis analyze --roughness` does.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fiveaxis_fuzz::targets::csv_profile(data));
