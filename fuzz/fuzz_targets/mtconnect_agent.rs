//! An MTConnect agent's answers (HTTP heads, chunked and multipart `/sample` streams, `/probe` and
//! streams documents), as the bridge's agent client reads them.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fiveaxis_fuzz::targets::mtconnect_agent(data));
