//! X3P `main.xml` and its point data: the input, split at the first `\0\0`, is `main.xml` and
//! `bindata/data.bin`, stored in a valid zip, so that mutations reach the XML and size checks
//! rather than the container's CRCs. Then filtered and windowed as in `x3p_container`.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fiveaxis_fuzz::targets::x3p_main_xml(data));
