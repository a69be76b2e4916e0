//! The soak test's two-minute version (issue 15 item 3): `launch-free-scripts/soak` runs the DDS
//! node set on a looped program at 1 kHz and judges memory, losses, latency and the recording from
//! outside the nodes (/proc, and the recording read by Foxglove's MCAP reader). Its own test binary,
//! so that it runs alone rather than beside the other DDS tests.

use crate::common;
use std::path::Path;
use std::process::Command;

#[test]
fn soak_for_two_minutes_loses_nothing_in_flat_memory() {
    let bins = Path::new(env!("FIVEAXIS_EXE")).parent().unwrap().to_path_buf();
    for b in ["fiveaxis-commander", "fiveaxis-simulator", "fiveaxis-monitor", "fiveaxis-recorder"] {
        assert!(bins.join(b).exists(), "{b} is not built in {}: run launch-free-scripts/test (or cargo build --workspace --bins)", bins.display());
    }
    let out = common::scratch_dir("soak");
    let run = Command::new(Path::new(env!("FIVEAXIS_ROOT")).join("launch-free-scripts/soak"))
        .args(["--duration-s", "120", "--warmup-s", "60", "--out"])
        .arg(&out)
        .env("FIVEAXIS_BIN", &bins)
        .output()
        .expect("the soak script runs");
    let said = format!("{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("soak.json")).unwrap_or_default())
        .unwrap_or_else(|e| panic!("no soak.json ({e}):\n{said}"));
    assert!(run.status.success(), "soak failed ({}):\n{said}", run.status);
    assert_eq!(report["failures"].as_array().map(Vec::len), Some(0), "{said}");
    // Both streams ran the whole two minutes at 1 kHz (a pass of SING.I is 33 s: three passes and
    // more), and everything sent was received by the monitor and recorded.
    for topic in fiveaxis::topics::MONITORED.map(|t| t.name) {
        let s = &report["streams"][topic];
        let sent = s["sent"].as_u64().unwrap_or(0);
        assert!(sent > 110_000, "{topic}: only {sent} samples in 120 s:\n{said}");
        assert_eq!(s["recorded"].as_u64(), Some(sent), "{said}");
        assert_eq!(s["monitor_samples"].as_u64(), Some(sent), "{said}");
        assert_eq!(s["monitor_lost"].as_u64(), Some(0), "{said}");
        assert_eq!(s["recorded_stamp_gaps_samples"].as_u64(), Some(0), "{said}");
    }
    for node in ["commander", "simulator", "monitor", "recorder"] {
        let g = report["nodes"][node]["rss_growth_after_warmup"].as_f64().unwrap_or(f64::NAN);
        assert!(g <= 0.10, "{node}: resident memory grew {:.1} % after the first minute:\n{said}", 100.0 * g);
    }
    assert_eq!(report["recording"]["recovered_messages"], report["recording"]["messages"], "{said}");
    let _ = std::fs::remove_dir_all(&out);
}
