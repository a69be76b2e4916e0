//! NC and CL program readers: the first byte picks the dialect (Heidenhain DIN/ISO, RS274NGC, CL,
//! Sinumerik, Klartext, Fanuc, Haas; every other round of seven on the Hermle's kinematics), the rest
//! is the program text (not UTF-8: replaced, as `program::load` does).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fiveaxis_fuzz::targets::nc_program(data));
