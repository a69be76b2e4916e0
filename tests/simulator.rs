//! The node set in one process (`fiveaxis run`): the simulated machine stutters on SING.I, holds the
//! feed on NON_SING.I, never exceeds an axis limit; the monitor reproduces the core's figures.

use fiveaxis::live::inprocess::{run, RunOptions, RunOutput};
use fiveaxis::machine::Machine;
use fiveaxis_msgs::AxisState;

fn go(spec: &str) -> RunOutput {
    run(spec, &Machine::hermle_c600u(), &RunOptions { keep_statuses: true, keep_simulation: true, ..Default::default() }).expect("run")
}

fn sim(out: &RunOutput) -> &fiveaxis::live::simulator::Simulation {
    out.simulation.as_ref().expect("kept: keep_simulation")
}

/// Simulated samples of the cutting pass (tool tip within 0.05 mm of the cut's y and z: the servo's
/// contour error; x inside the part).
fn cut(out: &RunOutput, y_mm: f64) -> Vec<AxisState> {
    sim(out)
        .states(&out.job.as_ref().expect("kept with the simulation").trajectory, &Machine::hermle_c600u())
        .into_iter()
        .filter(|s| (s.tool_tip.z * 1e3 + 8.0).abs() < 0.05 && (s.tool_tip.y * 1e3 - y_mm).abs() < 0.05)
        .filter(|s| (0.0..=50.0).contains(&(s.tool_tip.x * 1e3)))
        .collect()
}

#[test]
fn sing_stutters_around_x25_and_recovers() {
    let out = go("bundled:SING.I");
    let cut = cut(&out, 0.0);
    assert!(cut.len() > 1000);
    let f = 2000.0 / 60e3;
    // Below half the programmed feed throughout x 23-27 mm.
    let mid: Vec<_> = cut.iter().filter(|s| (23.0..=27.0).contains(&(s.tool_tip.x * 1e3))).collect();
    assert!(!mid.is_empty());
    for s in &mid {
        assert!(s.path_feed < 0.5 * f, "x {:.3}: {:.0} mm/min", s.tool_tip.x * 1e3, s.path_feed * 60e3);
    }
    // Back at the programmed feed where no axis limit binds (the offline feed limit is F there).
    let m = Machine::hermle_c600u();
    let free: Vec<_> = fiveaxis::singularity::statuses(&out.job.as_ref().expect("kept with the simulation").trajectory, &m)
        .filter(|(s, st)| (5.0..=10.0).contains(&(s.tip.x * 1e3)) && s.tip.z < -7e-3 && st.feed_limit.is_some_and(|l| l.axis.is_none()))
        .collect();
    assert!(!free.is_empty(), "x 5-10 mm is programmed-feed limited");
    let at_f = cut.iter().filter(|s| (5.0..=10.0).contains(&(s.tool_tip.x * 1e3)) && s.path_feed > 0.995 * f).count();
    assert!(at_f > 50, "{at_f} samples at F in x 5-10 mm");
    // One slow region (besides planned stops), around the singularity.
    let slow: Vec<_> = out.report.simulated.slow_regions.iter().filter(|r| !r.at_stop).collect();
    assert_eq!(slow.len(), 1, "{slow:?}");
    assert!(slow[0].x_start_mm < 23.0 && slow[0].x_end_mm > 27.0);
    assert!(out.report.simulated.cycle_time_s > out.report.simulated.commanded_cycle_time_s);
}

#[test]
fn nonsing_holds_the_programmed_feed() {
    let out = go("bundled:NON_SING.I");
    let f = 2000.0 / 60e3;
    let cut = cut(&out, 50.0);
    let mid: Vec<_> = cut.iter().filter(|s| (10.0..=40.0).contains(&(s.tool_tip.x * 1e3))).collect();
    assert!(mid.len() > 500);
    for s in &mid {
        assert!((s.path_feed - f).abs() < 0.005 * f, "x {:.3}: {:.1} mm/min", s.tool_tip.x * 1e3, s.path_feed * 60e3);
    }
    assert!(out.report.simulated.slow_regions.iter().all(|r| r.at_stop), "{:?}", out.report.simulated.slow_regions);
    assert!(out.report.simulated.monitor_regions.is_empty());
    assert!(out.commanded_regions.is_empty());
}

/// The simulated motion, measured independently here by finite differences at the sample period,
/// never exceeds an axis velocity, acceleration or jerk limit.
#[test]
fn simulated_motion_respects_every_axis_limit() {
    for spec in ["bundled:SING.I", "bundled:NON_SING.I", "builtin:paper-sing"] {
        let out = go(spec);
        let m = Machine::hermle_c600u();
        let q = &sim(&out).q;
        let t = sim(&out).period;
        for k in 2..q.len() - 2 {
            for (i, axis) in m.axes.iter().enumerate() {
                let l = axis.limits;
                let v = (q[k + 1][i] - q[k - 1][i]) / (2.0 * t);
                let a = (q[k + 1][i] - 2.0 * q[k][i] + q[k - 1][i]) / (t * t);
                let j = (q[k + 2][i] - 2.0 * q[k + 1][i] + 2.0 * q[k - 1][i] - q[k - 2][i]) / (2.0 * t * t * t);
                assert!(v.abs() <= l.velocity * (1.0 + 1e-9), "{spec} {} v {v} at {k}", axis.name);
                assert!(a.abs() <= l.acceleration * (1.0 + 1e-9), "{spec} {} a {a} at {k}", axis.name);
                assert!(j.abs() <= l.jerk * (1.0 + 1e-9), "{spec} {} j {j} at {k}", axis.name);
            }
        }
        let r = &out.report.simulated;
        assert!(r.max_axis_velocity_ratio <= 1.0 && r.max_axis_acceleration_ratio <= 1.0 && r.max_axis_jerk_ratio <= 1.0);
        assert_eq!(r.lost_samples, 0);
    }
}

/// On the commanded stream the live monitor gives the core's reference figures for SING.I.
#[test]
fn monitor_on_the_commanded_stream_matches_the_reference_figures() {
    let out = go("bundled:SING.I");
    let peak = out.commanded_statuses.iter().map(|s| s.predicted_c_speed.abs()).fold(0.0, f64::max) * 60.0 / std::f64::consts::TAU;
    assert!((peak - 175.0).abs() < 0.5, "peak {peak}");
    assert_eq!(out.commanded_regions.len(), 1, "{:?}", out.commanded_regions);
    let r = &out.commanded_regions[0];
    // Samples are 0.033 mm apart; the region opens on the first sample past x = 22.
    assert!((r.x_start_mm - 22.0).abs() < 0.05 && (r.x_end_mm - 28.0).abs() < 0.05, "{r:?}");
    // On the simulated (blended) stream, the region matches the continuous path's 21.58-28.42 mm.
    let sim = &out.report.simulated.monitor_regions;
    assert_eq!(sim.len(), 1, "{sim:?}");
    assert!((sim[0].x_start_mm - 21.58).abs() < 0.1 && (sim[0].x_end_mm - 28.42).abs() < 0.1, "{:?}", sim[0]);

}

/// The look-ahead: with the commanded stream ahead of the machine's (as a real-time commander is), the
/// monitor counts down to the region on the simulated stream before the machine gets there.
#[test]
fn monitor_look_ahead_counts_down_to_the_region() {
    use fiveaxis::live::monitor::{Monitor, MonitorConfig};
    let m = Machine::hermle_c600u();
    let out = go("bundled:SING.I");
    let commanded = fiveaxis::live::commander::commanded_states(&out.job.as_ref().expect("kept with the simulation").trajectory, &m);
    let simulated = sim(&out).states(&out.job.as_ref().expect("kept with the simulation").trajectory, &m);
    let mut mon = Monitor::new(&m, MonitorConfig::default());
    for st in &commanded {
        mon.on_commanded_ahead(st);
        let _ = mon.on_state("commanded", st, st.header.stamp.as_secs());
    }
    let statuses: Vec<_> = simulated.iter().filter_map(|st| mon.on_state("simulated", st, st.header.stamp.as_secs()).ok()).collect();
    let first = statuses.iter().position(|s| s.in_region).expect("a region on the simulated stream");
    // Just before the region the countdown is short and positive, and it decreases towards it.
    let before = &statuses[first - 30..first];
    assert!(before.iter().all(|s| s.time_to_next_region > 0.0 && s.time_to_next_region < 0.5), "{:?}", before.iter().map(|s| s.time_to_next_region).collect::<Vec<_>>());
    assert!(before.first().unwrap().time_to_next_region > before.last().unwrap().time_to_next_region);
    let warned = statuses[..first].iter().filter(|s| s.time_to_next_region > 0.0 && s.time_to_next_region < 1.0).count();
    assert!(warned > 100, "{warned}");
}

/// `fiveaxis run` makes only what its report shows (`RunOptions::report_only`: no commanded states,
/// no feed limits in the monitor's evaluations): the report is the full node set's, to the byte, on
/// the paper's programs, a dwell program and a raster over two look-ahead windows a row.
#[test]
fn a_report_only_run_reports_what_the_whole_node_set_does() {
    let dir = tempfile::tempdir().unwrap();
    // A raster of 0.01 mm CL poses (benches/long_program.py's surface), 6,000 poses a row.
    let raster = dir.path().join("raster.cl");
    let mut text = String::new();
    for k in 0..14_000 {
        let (row, i) = (k / 6001, k % 6001);
        let u = if row % 2 == 0 { i as f64 * 0.01 } else { 60.0 - i as f64 * 0.01 };
        let (x, y) = (u - 30.0, row as f64 * 0.5 - 10.0);
        let z = 8.0 * (x / 12.0).sin() * (y / 17.0).cos() - 10.0;
        let (nx, ny) = (-8.0 / 12.0 * (x / 12.0).cos() * (y / 17.0).cos(), 8.0 / 17.0 * (x / 12.0).sin() * (y / 17.0).sin());
        let norm = (nx * nx + ny * ny + 1.0f64).sqrt();
        text += &format!("{x:.4} {y:.4} {z:.4} {:.7} {:.7} {:.7} 2000\n", nx / norm, ny / norm, 1.0 / norm);
    }
    std::fs::write(&raster, text).unwrap();
    let m = Machine::hermle_c600u();
    let dwell = concat!(env!("FIVEAXIS_ROOT"), "/recordings/machine/linuxcnc/SING_DWELL.I");
    for spec in ["bundled:SING.I", "bundled:NON_SING.I", dwell, raster.to_str().unwrap()] {
        let report = |report_only| {
            let out = run(spec, &m, &RunOptions { report_only, ..Default::default() }).expect("run");
            serde_json::to_string(&out.report).unwrap()
        };
        let (whole, lean) = (report(false), report(true));
        assert!(whole.contains("\"monitor_regions\""), "{spec}");
        assert_eq!(lean, whole, "{spec}");
    }
}
