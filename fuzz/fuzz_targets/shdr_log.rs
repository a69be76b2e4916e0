//! An MTConnect adapter's SHDR stream, line by line against a five-axis device, each axis value
//! taken, as `fiveaxis analyze --shdr` and the bridge's adapter client read it.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fiveaxis_fuzz::targets::shdr_log(data));
