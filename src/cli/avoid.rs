//! `fiveaxis avoid`: the three remedies for a singular program, each with a before/after table:
//! reorientation on a jig (seed 001 eq. 7), C-axis smoothing (seed 002), CL refinement (seed 003).

use crate::exit::{bad_input, write_output, Outcome, Stop, OK};
use clap::Subcommand;
use fiveaxis::args::{ControlArgs, MachineArgs};
use fiveaxis::job::{self, JobOptions};
use fiveaxis::machine::Machine;
use fiveaxis::program::Dialect;
use fiveaxis::units::DEG;

#[derive(Subcommand)]
pub enum AvoidCmd {
    /// Reorient the workpiece on a jig (seed 001 §3, eq. 7): search the jig angles that minimise the peak
    /// predicted C speed within the tilt bound; the tool path relative to the workpiece is unchanged.
    Reorient {
        /// A program, or builtin:NAME (taken as CL data every 0.1 mm).
        program: String,
        #[command(flatten)]
        machine: MachineArgs,
        #[command(flatten)]
        control: ControlArgs,
        /// Largest jig tilt allowed, degrees.
        #[arg(long = "max-tilt-deg", default_value_t = 10.0)]
        max_tilt_deg: f64,
        /// Write the reoriented program here (RS274NGC stays RS274NGC; every other input, builtins too, is written as Heidenhain DIN/ISO).
        #[arg(long)]
        out: Option<std::path::PathBuf>,
        /// Print one JSON object with `before`, `after`, `theta_x_deg`, `theta_z_deg`.
        #[arg(long)]
        json: bool,
    },
    /// Smooth the C axis through the singularity (seed 002): the tool axis passes the singular point,
    /// C and A follow C3 connecting curves within the machine's v/a/j limits at the programmed feed.
    /// Ball-end tools only (the ball centre stays on the path).
    Smooth {
        /// A program, or builtin:NAME (taken as CL data every 0.1 mm).
        program: String,
        #[command(flatten)]
        machine: MachineArgs,
        #[command(flatten)]
        control: ControlArgs,
        /// The cutter: ball:R_MM (required: flat:R_MM and bull:R_MM:r_MM are refused).
        #[arg(long)]
        tool: fiveaxis::avoid::smooth::Tool,
        /// Write the smoothed program here (RS274NGC stays RS274NGC; every other input, builtins too, is written as Heidenhain DIN/ISO).
        #[arg(long)]
        out: Option<std::path::PathBuf>,
        /// Print one JSON object with `before`, `after` and `passages`.
        #[arg(long)]
        json: bool,
    },
    /// Refine CL data near the singularity (seed 003 §5): densify where the tool-axis angle, the step
    /// or a rotary-axis change between neighbours exceeds a threshold, on the IK branch that avoids
    /// 180 deg C flips; reports the overcut the original discretisation causes.
    Refine {
        /// CL data (or a TCPM program read as CL), builtin:NAME or builtin:semi-cylinder.
        program: String,
        #[command(flatten)]
        machine: MachineArgs,
        #[command(flatten)]
        control: ControlArgs,
        /// Largest tool-axis angle between neighbours, degrees.
        #[arg(long = "max-angle-deg", default_value_t = 1.0)]
        max_angle_deg: f64,
        /// Largest tool-tip step, mm.
        #[arg(long = "max-step-mm", default_value_t = 1.0)]
        max_step_mm: f64,
        /// Largest rotary-axis change between neighbours, degrees.
        #[arg(long = "max-axis-step-deg", default_value_t = 2.0)]
        max_axis_step_deg: f64,
        /// Write the refined program here (RS274NGC stays RS274NGC; every other input is written as Heidenhain DIN/ISO).
        #[arg(long)]
        out: Option<std::path::PathBuf>,
        /// Print one JSON object with `before`, `after` and the chord errors.
        #[arg(long)]
        json: bool,
    },
}

pub fn main(c: &AvoidCmd) -> Outcome {
    match c {
        AvoidCmd::Reorient { program, machine, control, max_tilt_deg, out, json } => reorient(program, machine, &options(control), *max_tilt_deg, out.as_deref(), *json),
        AvoidCmd::Smooth { program, machine, control, tool, out, json } => smooth(program, machine, &options(control), *tool, out.as_deref(), *json),
        AvoidCmd::Refine { program, machine, control, max_angle_deg, max_step_mm, max_axis_step_deg, out, json } => {
            let opts = fiveaxis::avoid::refine::RefineOptions { max_step: max_step_mm * fiveaxis::units::MM, max_angle: max_angle_deg * DEG, max_axis_step: max_axis_step_deg * DEG };
            refine(program, machine, &options(control), &opts, out.as_deref(), *json)
        }
    }
}


/// The job options of an `avoid` command: the control's set-up (`--m-code`, `--orientation`), the
/// rest at their defaults.
fn options(control: &ControlArgs) -> JobOptions {
    JobOptions { read: control.read_options(), ..JobOptions::default() }
}

/// The machine and program of an `avoid` command (files, bundled:, builtin: paths as CL every 0.1 mm,
/// builtin:semi-cylinder); programs with defects are bad input.
fn avoid_input(program: &str, machine: &MachineArgs, what: &str, options: &JobOptions, out: Option<&std::path::Path>) -> Result<(Machine, fiveaxis::program::Program), Stop> {
    let machine = machine.load().and_then(|m| m.five_axis("`fiveaxis avoid`")).map_err(bad_input)?;
    let prog = if program == "builtin:semi-cylinder" {
        fiveaxis::avoid::refine::semi_cylinder()
    } else if let Some(name) = program.strip_prefix("builtin:") {
        match fiveaxis::path::BuiltinPath::by_name(name) {
            Some(p) => p.cl_program(0.1),
            None => return Err(bad_input(format!("unknown built-in path '{name}' (also builtin:semi-cylinder)"))),
        }
    } else {
        job::read_spec(program, &options.on(&machine)).map_err(bad_input)?
    };
    if prog.has_errors() {
        for d in prog.report() {
            eprintln!("{d}");
        }
        return Err(bad_input(format!("{program} has defects: refusing to {what} it")));
    }
    // What cannot be written is refused before the remedy's search, not after it.
    if let Some(path) = out {
        fiveaxis::avoid::check_writable(&prog, out_dialect(&prog)).map_err(|e| bad_input(format!("cannot write {}: {e}", path.display())))?;
    }
    Ok((machine, prog))
}

/// The dialect a remedied program is written in: RS274NGC stays RS274NGC, anything else becomes
/// Heidenhain DIN/ISO.
fn out_dialect(prog: &fiveaxis::program::Program) -> Dialect {
    if prog.dialect == Dialect::Rs274 {
        Dialect::Rs274
    } else {
        Dialect::Heidenhain
    }
}

/// The before/after table every remedy prints.
fn remedy_table(before: &fiveaxis::avoid::Figures, after: &fiveaxis::avoid::Figures) {
    println!("{:<34} {:>12} {:>12}", "", "before", "after");
    println!("{:<34} {:>12.1} {:>12.1}", "peak C speed (eq. 5), rpm", before.peak_c_speed_rpm, after.peak_c_speed_rpm);
    println!("{:<34} {:>12.3} {:>12.3}", "closest approach, deg", before.min_singularity_distance_deg, after.min_singularity_distance_deg);
    println!("{:<34} {:>12.2} {:>12.2}", "simulated cycle time, s", before.cycle_time_s, after.cycle_time_s);
    println!("{:<34} {:>12.2} {:>12.2}", "time lost against F, s", before.time_lost_s, after.time_lost_s);
    println!("{:<34} {:>12.0} {:>12.0}", "lowest feed in the cuts, mm/min", before.min_cut_feed_mm_min, after.min_cut_feed_mm_min);
    println!("{:<34} {:>12.3} {:>12.3}", "max orientation change, deg", before.max_orientation_deviation_deg, after.max_orientation_deviation_deg);
}

/// Write the remedied program to `out` (RS274NGC stays RS274NGC, anything else becomes Heidenhain DIN/ISO).
fn write_out(prog: &fiveaxis::program::Program, new: &fiveaxis::program::Program, machine: &Machine, out: Option<&std::path::Path>, options: &JobOptions) -> Result<(), Stop> {
    if let Some(path) = out {
        let text = fiveaxis::avoid::write_program(new, machine, out_dialect(prog), options).map_err(|e| bad_input(format!("cannot write {}: {e}", path.display())))?;
        write_output(path, text)?;
    }
    Ok(())
}

fn smooth(program: &str, machine: &MachineArgs, options: &JobOptions, tool: fiveaxis::avoid::smooth::Tool, out: Option<&std::path::Path>, json: bool) -> Outcome {
    let (machine, prog) = avoid_input(program, machine, "smooth", &options, out)?;
    let (new, s) = fiveaxis::avoid::smooth::smooth(&prog, &machine, tool, &options).map_err(|e| bad_input(format!("cannot smooth {program}: {e}")))?;
    let (before, mut after) = match (fiveaxis::avoid::figures(&prog, &machine, &options), fiveaxis::avoid::figures(&new, &machine, &options)) {
        (Ok(b), Ok(a)) => (b, a),
        (Err(e), _) | (_, Err(e)) => return Err(bad_input(format!("cannot smooth {program}: {e}"))),
    };
    after.max_orientation_deviation_deg = s.max_orientation_deviation_deg;
    write_out(&prog, &new, &machine, out, &options)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&serde_json::json!({ "before": before, "after": after, "passages": s.passages, "max_ball_centre_error_mm": s.max_ball_centre_error_m * 1e3, "valid_for": "ball-end tools only" }))?);
        return Ok(OK);
    }
    println!("C-axis smoothing of {program} on {} (seed 002)", machine.name);
    println!("valid for ball-end tools only: the ball centre stays on the path, the tool axis changes");
    if s.passages.is_empty() {
        println!("no singular passage: nothing changed");
    }
    for p in &s.passages {
        println!(
            "passage        x {:.3} mm (closest {:.3} deg): window x {:.3} to {:.3} mm ({:.1} mm of path), {} points changed; C at {:.2}/{:.2}/{:.2} of its v/a/j limits; tool axis changed by up to {:.3} deg",
            p.x_singular_mm, p.original_distance_deg, p.x_start_mm, p.x_end_mm, p.window_length_mm, p.points_changed, p.c_limit_ratio[0], p.c_limit_ratio[1], p.c_limit_ratio[2], p.max_orientation_deviation_deg
        );
    }
    println!("ball centre    within {:.4} um of the original", s.max_ball_centre_error_m * 1e6);
    remedy_table(&before, &after);
    if let Some(path) = out {
        println!("wrote {}", path.display());
    }
    Ok(OK)
}

fn refine(program: &str, machine: &MachineArgs, options: &JobOptions, opts: &fiveaxis::avoid::refine::RefineOptions, out: Option<&std::path::Path>, json: bool) -> Outcome {
    let (machine, prog) = avoid_input(program, machine, "refine", &options, out)?;
    let refined = fiveaxis::avoid::refine::refine(&prog, &machine, opts, &options)
        .and_then(|(new, r)| fiveaxis::avoid::refine::conventional(&prog, &machine, &options).map(|c| (new, r, c)));
    let (new, r, conventional) = refined.map_err(|e| bad_input(format!("cannot refine {program}: {e}")))?;
    let (before, after) = match (fiveaxis::avoid::figures(&conventional, &machine, &options), fiveaxis::avoid::figures(&new, &machine, &options)) {
        (Ok(b), Ok(a)) => (b, a),
        (Err(e), _) | (_, Err(e)) => return Err(bad_input(format!("cannot refine {program}: {e}"))),
    };
    write_out(&prog, &new, &machine, out, &options)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&serde_json::json!({ "before": before, "after": after, "refinement": r }))?);
        return Ok(OK);
    }
    println!("CL refinement of {program} on {} (seed 003 §5); before = the conventional post (A >= 0 branch)", machine.name);
    println!("points         {} -> {} (tool tips within {:.4} um of the original CL polyline)", r.points_before, r.points_after, r.max_tip_error_m * 1e6);
    println!("{:<34} {:>12} {:>12}", "", "before", "after");
    println!("{:<34} {:>12.1} {:>12.1}", "largest C step, deg", r.before.max_c_step_deg, r.after.max_c_step_deg);
    println!("{:<34} {:>12} {:>12}", "180 deg C flips", r.before.c_flips, r.after.c_flips);
    println!("{:<34} {:>12.4} {:>12.4}", "overcut without TCPM, mm", r.before.overcut_mm, r.after.overcut_mm);
    println!("{:<34} {:>12.4} {:>12.4}", "undercut without TCPM, mm", r.before.undercut_mm, r.after.undercut_mm);
    println!("{:<34} {:>12.4} {:>12.4}", "tip off the chord without TCPM, mm", r.before.max_deviation_mm, r.after.max_deviation_mm);
    remedy_table(&before, &after);
    if let Some(path) = out {
        println!("wrote {}", path.display());
    }
    Ok(OK)
}

fn reorient(program: &str, machine: &MachineArgs, options: &JobOptions, max_tilt_deg: f64, out: Option<&std::path::Path>, json: bool) -> Outcome {
    if !(max_tilt_deg.is_finite() && max_tilt_deg > 0.0 && max_tilt_deg <= 90.0) {
        return Err(bad_input(format!("--max-tilt-deg must be in (0, 90], got {max_tilt_deg}")));
    }
    let (machine, prog) = avoid_input(program, machine, "reorient", options, out)?;
    let (r, new) = fiveaxis::avoid::search(&prog, &machine, max_tilt_deg * DEG, &options).map_err(|e| bad_input(format!("cannot reorient {program}: {e}")))?;
    write_out(&prog, &new, &machine, out, &options)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&r)?);
    } else {
        println!("reorientation of {program} on {} (jig tilt within {max_tilt_deg} deg)", machine.name);
        println!("jig angles     theta_x {:.2} deg, theta_z {:.2} deg (seed 001 eq. 7)", r.theta_x_deg, r.theta_z_deg);
        remedy_table(&r.before, &r.after);
        if let Some(path) = out {
            println!("wrote {}", path.display());
        }
    }
    Ok(OK)
}
