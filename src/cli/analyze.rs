//! `fiveaxis analyze`: recordings (MCAP files, rosbag2 bags) analysed offline: the monitor
//! recomputed on every stream, regions, threshold checks for CI; several recordings in parallel, one
//! report each and a summary, the worst exit code.

use crate::args::positive;
use crate::exit::{bad_input, write_output, Outcome, BAD_INPUT, OK, VIOLATED};
use anyhow::Context;
use clap::Args;
use fiveaxis::args::{ListingArgs, MachineArgs};
use fiveaxis::machine::Machine;

#[derive(Args)]
pub struct OfflineArgs {
    /// The recordings: MCAP files or rosbag2 bag directories (a directory of split files is one bag).
    #[arg(required_unless_present = "all_in")]
    recordings: Vec<std::path::PathBuf>,
    /// Also every recording directly in this directory, each on its own: its `.mcap` files and its
    /// bag directories, in name order.
    #[arg(long = "all-in", value_name = "DIR")]
    all_in: Option<std::path::PathBuf>,
    /// Recordings analysed at once (default: one per core).
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,
    #[command(flatten)]
    machine: MachineArgs,
    /// Fail (exit 1) when the predicted C speed exceeds this, rpm.
    #[arg(long = "max-c-speed-rpm")]
    max_c_speed_rpm: Option<f64>,
    /// Fail (exit 1) when a moving tool axis comes closer than this to the singularity, degrees.
    #[arg(long = "min-distance-deg")]
    min_distance_deg: Option<f64>,
    #[command(flatten)]
    streams: fiveaxis::args::RecordedStreamArgs,
    /// The program the machine ran (a file, `-` for standard input, bundled:NAME): machine streams are aligned with its moves
    /// for the programmed feed, block numbers and rapids.
    #[arg(long, conflicts_with = "feed_mm_per_min")]
    program: Option<String>,
    /// The control's active work offset (G54-style datum) `X,Y,Z` in mm: a machine stream's tool tip
    /// less it is the program's point (without --program; with one, its datum is used).
    #[arg(long = "work-offset-mm", value_name = "X,Y,Z", value_parser = fiveaxis::machine::parse_work_offset, allow_hyphen_values = true, conflicts_with = "program")]
    work_offset: Option<nalgebra::Vector3<f64>>,
    /// The programmed feed of every feed move of a machine stream, mm/min (without --program).
    #[arg(long = "feed", value_name = "MM_PER_MIN")]
    feed_mm_per_min: Option<f64>,
    #[command(flatten)]
    control: fiveaxis::program::ControlArgs,
    /// Refuse a stream (exit 2) with more than this share of its samples rejected, percent.
    #[arg(long = "max-rejected-percent", default_value_t = 100.0 * fiveaxis::analysis::MAX_REJECTED_SHARE)]
    max_rejected_percent: f64,
    /// Write the report as JSON here.
    #[arg(long)]
    json: Option<std::path::PathBuf>,
    /// Write a JUnit XML report here.
    #[arg(long)]
    junit: Option<std::path::PathBuf>,
    #[command(flatten)]
    roughness: fiveaxis::roughness::RoughnessArgs,
    #[command(flatten)]
    listing: ListingArgs,
}

pub fn main(a: &OfflineArgs) -> Outcome {
    positive("--max-c-speed-rpm", a.max_c_speed_rpm)?;
    positive("--min-distance-deg", a.min_distance_deg)?;
    positive("--feed", a.feed_mm_per_min)?;
    let machine = a.machine.load().and_then(|m| m.five_axis("`fiveaxis analyze` of recordings")).map_err(bad_input)?;
    let selection = a.streams.selection(&machine).map_err(bad_input)?;
    let feed_source = fiveaxis::job::feed_source(a.program.as_deref(), a.feed_mm_per_min, &machine, &a.control.read_options()).map_err(bad_input)?;
    if !(a.max_rejected_percent >= 0.0 && a.max_rejected_percent <= 100.0) {
        return Err(bad_input(format!("--max-rejected-percent {} is not a percentage", a.max_rejected_percent)));
    }
    let roughness = a.roughness.load().map_err(bad_input)?;
    let options = fiveaxis::analysis::OfflineOptions {
        roughness,
        max_c_speed_rpm: a.max_c_speed_rpm,
        min_distance_deg: a.min_distance_deg,
        selection,
        feed_source,
        max_rejected_share: a.max_rejected_percent / 100.0,
        monitor: fiveaxis::live::monitor::MonitorConfig { work_offset: a.work_offset.unwrap_or_default(), max_listed_regions: a.listing.max_listed_regions, ..Default::default() },
    };
    let recordings = recordings_of(a).map_err(bad_input)?;
    if let [one] = recordings.as_slice() {
        return offline_one(a, one, &machine, &options);
    }
    offline_many(a, &recordings, &machine, &options)
}

/// The recordings an `analyze` names: those given, then those in `--all-in` (MCAP and SQLite3 files
/// and bag directories, by name); none is an error.
fn recordings_of(a: &OfflineArgs) -> Result<Vec<std::path::PathBuf>, String> {
    let mut all = a.recordings.clone();
    if let Some(dir) = &a.all_in {
        let entries = std::fs::read_dir(dir).map_err(|e| format!("--all-in {}: {e}", dir.display()))?;
        let mut found: Vec<std::path::PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| if p.is_dir() { fiveaxis::record::read::recording_files(p).is_ok() } else { p.extension().is_some_and(|e| e.eq_ignore_ascii_case("mcap")) || fiveaxis::record::sqlite::is_db3(p) })
            .collect();
        if found.is_empty() {
            return Err(format!("--all-in {}: no .mcap or .db3 file or bag directory in it", dir.display()));
        }
        found.sort();
        all.extend(found);
    }
    Ok(all)
}

/// Exit code of one recording's report: 2 if its input cannot be trusted or is damaged, 1 if a
/// threshold is violated, else 0.
fn offline_code(report: &fiveaxis::analysis::OfflineReport) -> u8 {
    if !report.input_errors.is_empty() || report.damage.is_some() {
        BAD_INPUT
    } else if !report.violations.is_empty() {
        VIOLATED
    } else {
        OK
    }
}

/// `fiveaxis analyze` on one recording: a progress bar on long files, the table, JSON and JUnit.
fn offline_one(a: &OfflineArgs, recording: &std::path::Path, machine: &Machine, options: &fiveaxis::analysis::OfflineOptions) -> Outcome {
    // A progress bar on long files, on stderr; indicatif hides it when stderr is not a terminal.
    let bar = indicatif::ProgressBar::with_draw_target(None, indicatif::ProgressDrawTarget::stderr());
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {bytes}/{total_bytes} ({eta})")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    bar.set_message("analysing");
    let mut progress = |done: u64, total: u64| {
        if total >= 32 << 20 {
            bar.set_length(total);
            bar.set_position(done);
        }
    };
    let result = fiveaxis::analysis::analyze_mcap_with_progress(recording, machine, options, &mut progress);
    bar.finish_and_clear();
    let report = match result {
        Ok(r) => r,
        Err(e) => return Err(bad_input(format!("cannot analyse {}: {e}", recording.display()))),
    };
    print!("{}", report.to_table());
    if let Some(p) = &a.json {
        write_output(p, serde_json::to_string_pretty(&report)?)?;
    }
    if let Some(p) = &a.junit {
        write_output(p, report.to_junit().context("writing JUnit XML")?)?;
    }
    report_problems(recording, &report);
    Ok(offline_code(&report))
}

/// Say on stderr why a recording's report is not clean (input errors, damage).
fn report_problems(recording: &std::path::Path, report: &fiveaxis::analysis::OfflineReport) {
    for e in &report.input_errors {
        eprintln!("fiveaxis: {}: {e}", recording.display());
    }
    if let Some(d) = &report.damage {
        // The report covers what was readable; the input itself is damaged: exit 2.
        eprintln!(
            "fiveaxis: {} is damaged ({d}); the report covers the {} messages before it (`fiveaxis mcap recover` rebuilds a sound file)",
            recording.display(),
            report.messages_read
        );
    }
}

/// One recording's line in the summary of a multi-recording `analyze`.
#[derive(serde::Serialize)]
struct RecordingSummary {
    file: String,
    exit_code: u8,
    messages_read: u64,
    regions: usize,
    violations: usize,
    /// Why it could not be analysed at all, if so.
    error: Option<String>,
}

/// `fiveaxis analyze` on several recordings, `--jobs` at a time (each on its own core): the reports in
/// the order given, a summary, JSON `{"recordings": [...], "summary": [...]}`, JUnit `<testsuites>`.
fn offline_many(a: &OfflineArgs, recordings: &[std::path::PathBuf], machine: &Machine, options: &fiveaxis::analysis::OfflineOptions) -> Outcome {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let jobs = a.jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())).clamp(1, recordings.len());
    let next = AtomicUsize::new(0);
    let results: Vec<std::sync::Mutex<Option<Result<fiveaxis::analysis::OfflineReport, String>>>> = recordings.iter().map(|_| std::sync::Mutex::new(None)).collect();
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(path) = recordings.get(k) else { break };
                let r = fiveaxis::analysis::analyze_mcap(path, machine, options).map_err(|e| e.to_string());
                *results[k].lock().unwrap_or_else(|p| p.into_inner()) = Some(r);
            });
        }
    });
    let mut summary = Vec::new();
    let mut reports = Vec::new();
    let mut worst = 0u8;
    for (path, slot) in recordings.iter().zip(results) {
        let r = slot.into_inner().unwrap_or_else(|p| p.into_inner()).unwrap_or_else(|| Err("not analysed".into()));
        let file = path.display().to_string();
        let line = match r {
            Ok(report) => {
                print!("{}", report.to_table());
                println!();
                report_problems(path, &report);
                let code = offline_code(&report);
                let line = RecordingSummary { file, exit_code: code, messages_read: report.messages_read, regions: report.regions.len() + report.unlisted_regions.count, violations: report.violations.len(), error: None };
                reports.push(report);
                line
            }
            Err(e) => {
                eprintln!("fiveaxis: cannot analyse {file}: {e}");
                RecordingSummary { file, exit_code: BAD_INPUT, messages_read: 0, regions: 0, violations: 0, error: Some(e) }
            }
        };
        worst = worst.max(line.exit_code);
        summary.push(line);
    }
    println!("summary of {} recordings ({jobs} at a time)", summary.len());
    println!("  exit  messages  regions  violations  recording");
    for s in &summary {
        println!("  {:>4}  {:>8}  {:>7}  {:>10}  {}{}", s.exit_code, s.messages_read, s.regions, s.violations, s.file, s.error.as_ref().map_or(String::new(), |e| format!(" (cannot analyse: {e})")));
    }
    if let Some(p) = &a.json {
        let all = serde_json::json!({ "recordings": reports, "summary": summary });
        write_output(p, serde_json::to_string_pretty(&all)?)?;
    }
    if let Some(p) = &a.junit {
        let unreadable: Vec<(&str, &str)> = summary.iter().filter_map(|s| s.error.as_deref().map(|e| (s.file.as_str(), e))).collect();
        write_output(p, fiveaxis::analysis::junit_testsuites(&reports, &unreadable).context("writing JUnit XML")?)?;
    }
    Ok(worst)
}
