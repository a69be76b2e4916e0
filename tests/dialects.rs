//! Twins: the same tool path written in two dialects gives the same sampled trajectory and the same
//! analysis. SING.I (Heidenhain DIN/ISO, A/C words under M128) against its Fanuc-style twin
//! (recordings/programs/twins/SING_fanuc.nc: G10 L2 work offset, G43.5 with tool vectors I J K), both
//! interpolating the rotary axes linearly between blocks (axis-linear, as M128 does).

use fiveaxis::job::{self, JobOptions};
use fiveaxis::machine::Machine;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn sing_and_its_fanuc_tool_vector_twin_agree() {
    let machine = Machine::hermle_c600u();
    let options = JobOptions::default();
    let heid = job::run("bundled:SING.I", &machine, &options).unwrap();
    let twin_path = root().join("recordings/programs/twins/SING_fanuc.nc");
    let fanuc = job::run(&twin_path.display().to_string(), &machine, &options).unwrap();
    assert!(!heid.has_errors() && !fanuc.has_errors(), "{:#?}", fanuc.report.diagnostics);
    assert!(fanuc.report.diagnostics.is_empty(), "{:#?}", fanuc.report.diagnostics);

    // Sample by sample: tool tip (program coordinates) to 1e-6 mm, tool axis to 1e-6.
    let a: Vec<_> = heid.trajectory.samples(&machine).collect();
    let b: Vec<_> = fanuc.trajectory.samples(&machine).collect();
    assert_eq!(a.len(), b.len(), "sample counts");
    let (mut tip, mut axis) = (0.0f64, 0.0f64);
    for (x, y) in a.iter().zip(&b) {
        tip = tip.max((x.tip - y.tip).norm() * 1e3);
        axis = axis.max((x.axis - y.axis).norm());
    }
    assert!(tip <= 1e-6 && axis <= 1e-6, "largest difference: tip {tip:e} mm, axis {axis:e}");

    // The same figures: the paper's 175 rpm over x 22-28 mm (N340-N390), closest approach 1 deg.
    for r in [&heid.report, &fanuc.report] {
        assert!((r.peak_c_speed_rpm - 175.0).abs() < 0.05, "{}", r.peak_c_speed_rpm);
        assert!((r.min_singularity_distance_deg.unwrap() - 1.0).abs() < 1e-3);
        assert_eq!(r.regions.len(), 1);
        let g = &r.regions[0];
        assert!((g.x_start_mm - 22.0).abs() < 0.01 && (g.x_end_mm - 28.0).abs() < 0.01, "{} .. {}", g.x_start_mm, g.x_end_mm);
        assert_eq!((g.block_start, g.block_end), (Some(340), Some(390)));
    }
    assert!((heid.report.peak_c_speed_rpm - fanuc.report.peak_c_speed_rpm).abs() < 1e-6);
    assert!((heid.report.cycle_time_s - fanuc.report.cycle_time_s).abs() < 1e-9);
}

#[test]
fn the_fanuc_twin_is_what_its_script_writes() {
    // The committed twin is reproducible: the script run again writes the same bytes.
    let dir = std::env::temp_dir().join(format!("fiveaxis-twins-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("twins")).unwrap();
    std::fs::copy(root().join("recordings/programs/SING.I"), dir.join("SING.I")).unwrap();
    std::fs::copy(root().join("recordings/programs/twins/make-twins"), dir.join("twins/make-twins")).unwrap();
    let st = std::process::Command::new("python3").arg(dir.join("twins/make-twins")).status().unwrap();
    assert!(st.success());
    let again = std::fs::read(dir.join("twins/SING_fanuc.nc")).unwrap();
    let committed = std::fs::read(root().join("recordings/programs/twins/SING_fanuc.nc")).unwrap();
    assert!(again == committed, "recordings/programs/twins/SING_fanuc.nc differs from what make-twins writes");
    let _ = std::fs::remove_dir_all(dir);
}
