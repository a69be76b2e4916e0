//! `fiveaxis demo`: the embedded default, the node set in one process on the paper's two programs
//! and two continuous paths, on the Hermle: predicted and simulated figures side by side.

use crate::exit::{Outcome, OK};
use clap::Args;
use fiveaxis::machine::Machine;

#[derive(Args)]
pub struct DemoArgs {
    /// Print one JSON object per program (one per line).
    #[arg(long)]
    json: bool,
}

pub fn main(a: &DemoArgs) -> Outcome {
    let json = a.json;
    let machine = Machine::hermle_c600u();
    if !json {
        println!("fiveaxis demo: the paper's paths on the {} (C limit 25 rpm), F2000 mm/min", machine.name);
        println!("commander + simulator + monitor in one process, no DDS\n");
        println!("predicted (seed 001 eq. 5, axes linear per block as programmed):");
        println!("{:<24} {:>12} {:>10} {:>14} {:>16}", "program", "peak C rpm", "at x mm", "closest deg", "C > 25 rpm, x mm");
    }
    let specs = ["builtin:paper-sing", "bundled:SING.I", "builtin:paper-nonsing", "bundled:NON_SING.I"];
    let mut runs = Vec::new();
    for spec in specs {
        let out = fiveaxis::live::inprocess::run(spec, &machine, &Default::default()).map_err(anyhow::Error::from)?;
        if json {
            println!("{}", serde_json::to_string(&out.report)?);
            continue;
        }
        let r = &out.report.analysis;
        let regions = if r.regions.is_empty() {
            "none".to_string()
        } else {
            r.regions.iter().map(|g| format!("{:.2}-{:.2}", g.x_start_mm, g.x_end_mm)).collect::<Vec<_>>().join(", ")
        };
        println!(
            "{:<24} {:>12.1} {:>10.2} {:>14.3} {:>16}",
            spec,
            r.peak_c_speed_rpm,
            r.peak_c_speed_x_mm,
            r.min_singularity_distance_deg.unwrap_or(f64::NAN),
            regions
        );
        runs.push((spec, out));
    }
    if !json {
        println!("\nsimulated machine (A/C 150 deg/s, 600 deg/s^2; look-ahead planner, servo):");
        println!("{:<24} {:>10} {:>16} {:>22} {:>12}", "program", "cycle s", "lowest mm/min", "feed < 50 %, x mm", "max a/a_max");
        for (spec, out) in &runs {
            let s = &out.report.simulated;
            let slow: Vec<String> = s.slow_regions.iter().filter(|r| !r.at_stop).map(|r| format!("{:.1}-{:.1}", r.x_start_mm, r.x_end_mm)).collect();
            println!(
                "{:<24} {:>10.2} {:>16.0} {:>22} {:>12.3}",
                spec,
                s.cycle_time_s,
                s.min_feed_mm_per_min,
                if slow.is_empty() { "none".to_string() } else { slow.join(", ") },
                s.max_axis_acceleration_ratio
            );
        }
        println!("\nDetails: fiveaxis run bundled:SING.I   fiveaxis program analyze FILE   (--json for CI)");
    }
    Ok(OK)
}
