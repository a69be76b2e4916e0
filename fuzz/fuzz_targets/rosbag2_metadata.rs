//! rosbag2 directories: the input is the bag's `metadata.yaml`, beside one small valid MCAP file
//! (`bag_0.mcap`); the bag is listed, sized and read as `fiveaxis analyze DIR` does.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fiveaxis_fuzz::targets::rosbag2_metadata(data));
