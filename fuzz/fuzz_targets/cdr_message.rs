//! CDR messages as they arrive from DDS or a recording: the first byte picks the decoder (the
//! buffer-reusing readers of AxisState and JointState, and the serde path the DDS subscriptions
//! take for every subscribed type).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fiveaxis_fuzz::targets::cdr_message(data));
