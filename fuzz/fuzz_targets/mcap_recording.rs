//! Recordings: a file as `fiveaxis analyze` reads it (MCAP records, chunk compression, CDR
//! messages, the monitor on what decodes) and as `fiveaxis mcap recover` mends it.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fiveaxis_fuzz::targets::mcap_recording(data));
