//! One analysis job: resolve a program spec (a file, `builtin:NAME` for the paper's continuous paths,
//! or `bundled:NAME` for the paper's NC programs compiled into the binary), read it, sample it on a
//! machine and analyze it. The CLI, the tests and (later) the nodes share this path.

use crate::machine::Machine;
use crate::path::{BuiltinPath, PathOptions, Trajectory};
use crate::program::{self, Dialect, Diagnostic, LoadError, Program, ReadOptions, Severity};
use crate::report::AnalysisReport;
use crate::singularity::{analyze, Analysis, AnalysisOptions};

/// The paper's NC programs, compiled in (`bundled:SING.I`, `bundled:NON_SING.I`).
pub use crate::program::BUNDLED;

/// Everything one job produced.
#[derive(Debug, Clone)]
pub struct Job {
    pub program: Program,
    pub trajectory: Trajectory,
    pub analysis: Analysis,
    pub report: AnalysisReport,
}

/// Errors that stop a job before any analysis (the program's own defects are diagnostics instead).
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    #[error(transparent)]
    Load(#[from] LoadError),
    #[error("unknown built-in path '{0}' (built in: {list})", list = crate::path::builtin_names().join(", "))]
    UnknownBuiltin(String),
    #[error("unknown bundled program '{0}' (bundled: SING.I, NON_SING.I)")]
    UnknownBundled(String),
    #[error("recording: {0}")]
    Record(#[from] crate::record::RecordError),
    #[error("built-in path {name} cannot be run on machine {machine}: {source}")]
    Kinematics { name: String, machine: String, source: crate::kinematics::KinematicsError },
    /// The reading an analysis was made along ([`report_of_reading`]) stopped before the program's
    /// end (the reader's own error says why).
    #[error("the program's reader stopped before the end of the program")]
    FeedCut,
}

/// Options of a job.
#[derive(Debug, Clone, Default)]
pub struct JobOptions {
    pub dialect: Option<Dialect>,
    pub path: PathOptions,
    pub analysis: AnalysisOptions,
    pub read: ReadOptions,
}

impl JobOptions {
    /// These options for a program run on `machine`: its control's M functions, machine coordinates
    /// and kinematics reach the reader (a machine already set stays).
    pub fn on(&self, machine: &Machine) -> JobOptions {
        match self.read.machine {
            Some(_) => self.clone(),
            None => JobOptions { read: self.read.on(machine), ..self.clone() },
        }
    }
}

/// The text and dialect of a `bundled:NAME` spec (`None` for any other spec).
fn bundled(spec: &str, options: &JobOptions) -> Result<Option<(&'static str, Dialect)>, JobError> {
    let Some(name) = spec.strip_prefix("bundled:") else { return Ok(None) };
    let (_, text) = BUNDLED.iter().find(|(n, _)| *n == name).ok_or_else(|| JobError::UnknownBundled(name.into()))?;
    Ok(Some((text, options.dialect.unwrap_or(Dialect::Heidenhain))))
}

/// Where a program spec's text comes from, resolved once so that each consumer reads the same text
/// from its start: compiled in (`bundled:NAME`), or a file ([`program::ProgramFile`]: a pipe, a FIFO
/// or standard input, `-`, is held in a temporary file so that it can be read again).
#[derive(Debug, Clone)]
pub enum ProgramSource {
    Bundled { spec: String, text: &'static str, dialect: Dialect },
    File(program::ProgramFile),
}

impl ProgramSource {
    /// Resolve a program spec (not `builtin:NAME`, a path rather than a program).
    pub fn resolve(spec: &str, options: &JobOptions) -> Result<ProgramSource, JobError> {
        if let Some((text, dialect)) = bundled(spec, options)? {
            return Ok(ProgramSource::Bundled { spec: spec.into(), text, dialect });
        }
        Ok(ProgramSource::File(program::ProgramFile::resolve(spec)?))
    }

    /// The program's name in diagnostics (`stdin` for `-`).
    pub fn name(&self) -> String {
        match self {
            ProgramSource::Bundled { spec, .. } => spec.clone(),
            ProgramSource::File(file) => file.name(),
        }
    }

    /// Read the program whole.
    pub fn read(&self, options: &JobOptions) -> Result<Program, JobError> {
        Ok(match self {
            ProgramSource::Bundled { spec, text, dialect } => program::read(text, *dialect, spec, &options.read),
            ProgramSource::File(file) => file.load(options.dialect, &options.read)?,
        })
    }

    /// Open the program from its start as a stream of blocks.
    pub fn open(&self, options: &JobOptions) -> Result<program::BlockStream, JobError> {
        Ok(match self {
            ProgramSource::Bundled { spec, text, dialect } => program::BlockStream::from_text(text, Some(*dialect), spec, &options.read),
            ProgramSource::File(file) => file.open(options.dialect, &options.read)?,
        })
    }
}

/// Read the program named by `spec`.
pub fn read_spec(spec: &str, options: &JobOptions) -> Result<Program, JobError> {
    ProgramSource::resolve(spec, options)?.read(options)
}

/// Run a job on `spec`.
pub fn run(spec: &str, machine: &Machine, options: &JobOptions) -> Result<Job, JobError> {
    let (program, trajectory) = if let Some(name) = spec.strip_prefix("builtin:") {
        let path = BuiltinPath::by_name(name).ok_or_else(|| JobError::UnknownBuiltin(name.into()))?;
        let traj = path.trajectory(machine, &options.path).map_err(|source| JobError::Kinematics {
            name: spec.into(),
            machine: machine.name.clone(),
            source,
        })?;
        let program = Program { source: spec.into(), dialect: Dialect::Cl, name: Some(name.into()), blocks: vec![], diagnostics: vec![] };
        (program, traj)
    } else {
        return Ok(run_program(read_spec(spec, &options.on(machine))?, machine, options));
    };
    Ok(analyzed(program, trajectory, machine, options))
}

/// Run a job on a program read whole.
fn run_program(program: Program, machine: &Machine, options: &JobOptions) -> Job {
    let trajectory = Trajectory::from_program(&program, machine, &options.path);
    analyzed(program, trajectory, machine, options)
}

/// Analyse a program's trajectory and make its report.
fn analyzed(program: Program, trajectory: Trajectory, machine: &Machine, options: &JobOptions) -> Job {
    let analysis = analyze(&trajectory, machine, &options.analysis);
    let mut extra: Vec<Diagnostic> = trajectory.diagnostics.clone();
    if trajectory.segments.is_empty() && trajectory.stored.is_empty() {
        extra.push(no_moves(program.blocks.len()));
    }
    let report = AnalysisReport::new(&program, machine, &analysis, &trajectory, &extra, options.path.feed_override_mm_per_min);
    Job { program, trajectory, analysis, report }
}

/// Analyse the program named by `spec` as it is read (`fiveaxis program analyze`): blocks, segments
/// and samples are made and dropped as the analysis passes them, so memory does not grow with the
/// program's length. The report is the one [`run`] makes (a built-in path is run whole).
pub fn analyze_streaming(spec: &str, machine: &Machine, options: &JobOptions) -> Result<AnalysisReport, JobError> {
    if spec.starts_with("builtin:") {
        return Ok(run(spec, machine, options)?.report);
    }
    analyze_source(&ProgramSource::resolve(spec, options)?, machine, &options.on(machine))
}

/// [`analyze_streaming`] on a resolved program.
fn analyze_source(source: &ProgramSource, machine: &Machine, options: &JobOptions) -> Result<AnalysisReport, JobError> {
    let mut segments = crate::path::SegmentStream::new(source.open(options)?, machine, &options.path);
    let (analysis, counts) = crate::singularity::analyze_segments(segments.by_ref(), options.path.period, machine, &options.analysis);
    let diagnostics = read_rest(&mut segments, counts.segments);
    let read = crate::report::ReadFacts { source: segments.blocks().source(), blocks: segments.blocks().blocks_read(), samples: counts.samples, period: options.path.period };
    Ok(AnalysisReport::from_parts(&read, diagnostics.iter(), machine, &analysis, options.path.feed_override_mm_per_min))
}

/// The report [`analyze_streaming`] makes, from an analysis made along another consumer's reading of
/// the program (the in-process run's commander, [`crate::singularity::analyze_segments_along`])
/// instead of reading and planning the program again. `stream` is the reading, ended; a segment
/// still in it was not analysed: [`JobError::FeedCut`] (fail closed).
pub fn report_of_reading(
    stream: &mut crate::path::SegmentStream,
    analysis: &crate::singularity::Analysis,
    counts: crate::singularity::StreamCounts,
    machine: &Machine,
    options: &JobOptions,
) -> Result<AnalysisReport, JobError> {
    if stream.next().is_some() {
        return Err(JobError::FeedCut);
    }
    stream.read_to_end();
    let blocks = stream.blocks().blocks_read();
    let diagnostics = with_no_moves(reading_diagnostics(stream), counts.segments, blocks);
    let read = crate::report::ReadFacts { source: stream.blocks().source(), blocks, samples: counts.samples, period: options.path.period };
    Ok(AnalysisReport::from_parts(&read, diagnostics.iter(), machine, analysis, options.path.feed_override_mm_per_min))
}

/// What reading and planning a whole program found ([`Moves::check`]).
#[derive(Debug, Clone)]
pub struct Checked {
    /// The diagnostics, in the report's order (the first 10,000 in full, the rest counted in a last one).
    pub diagnostics: Vec<Diagnostic>,
    pub errors: usize,
    pub blocks: usize,
    pub segments: usize,
    /// Commanded duration, s.
    pub duration_s: f64,
}

/// A job's moves, for consumers that each read them for themselves (the analysis, the commander,
/// the planner and its scout run side by side): a program (a file or `bundled:NAME`) is read again
/// as a stream by each, so none holds it whole; a built-in path (short, and sampled from the path
/// itself) is held.
#[derive(Debug, Clone)]
pub enum Moves {
    Program { source: ProgramSource, options: JobOptions },
    Held(Box<Job>),
}

impl Moves {
    /// The moves of `spec`; a program that cannot be opened is an error here, before any consumer starts.
    pub fn open(spec: &str, machine: &Machine, options: &JobOptions) -> Result<Moves, JobError> {
        if spec.starts_with("builtin:") {
            return Ok(Moves::Held(Box::new(run(spec, machine, options)?)));
        }
        Ok(Moves::Program { source: ProgramSource::resolve(spec, options)?, options: options.on(machine) })
    }

    /// The program's name in diagnostics (`stdin` for `-`).
    pub fn name(&self) -> String {
        match self {
            Moves::Program { source, .. } => source.name(),
            Moves::Held(job) => job.program.source.clone(),
        }
    }

    /// Sample period, s.
    pub fn period(&self) -> f64 {
        match self {
            Moves::Program { options, .. } => options.path.period,
            Moves::Held(job) => job.trajectory.period,
        }
    }

    /// The segments from the start, one at a time (the program is read again as a stream).
    pub fn segments<'a>(&'a self, machine: &'a Machine) -> Result<Box<dyn Iterator<Item = crate::path::Segment> + 'a>, JobError> {
        Ok(match self {
            Moves::Program { source, options } => Box::new(crate::path::SegmentStream::new(source.open(options)?, machine, &options.path)),
            Moves::Held(job) => Box::new(job.trajectory.segments.iter().cloned()),
        })
    }

    /// A program's segments as a stream that also tells what reading it found (`None` for a built-in
    /// path, which is held).
    pub fn segment_stream<'a>(&'a self, machine: &'a Machine) -> Result<Option<crate::path::SegmentStream<'a>>, JobError> {
        Ok(match self {
            Moves::Program { source, options } => Some(crate::path::SegmentStream::new(source.open(options)?, machine, &options.path)),
            Moves::Held(_) => None,
        })
    }

    /// The segments of `passes` runs of the moves one after the other (`None`: endless), as a
    /// machine making part after part: each pass joined to the last by a rapid back to the first
    /// pose ([`crate::path::Passes`]). The first pass is opened here; a later one that cannot be read
    /// again ends the stream with its error in `failed`.
    pub fn passes<'a>(&'a self, machine: &'a Machine, passes: Option<u64>, failed: &'a std::sync::OnceLock<JobError>) -> Result<Box<dyn Iterator<Item = crate::path::Segment> + 'a>, JobError> {
        let mut first = Some(self.segments(machine)?);
        let open = move || {
            first.take().or_else(|| match self.segments(machine) {
                Ok(s) => Some(s),
                Err(e) => {
                    let _ = failed.set(e);
                    None
                }
            })
        };
        Ok(Box::new(crate::path::Passes::new(open, passes, machine)))
    }

    /// The job read whole (the program read again; a built-in path's held job).
    pub fn whole(&self, machine: &Machine) -> Result<Job, JobError> {
        match self {
            Moves::Program { source, options } => Ok(run_program(source.read(options)?, machine, options)),
            Moves::Held(job) => Ok((**job).clone()),
        }
    }

    /// The held trajectory of a built-in path (`None` for a program, which is streamed).
    pub fn held(&self) -> Option<&Trajectory> {
        match self {
            Moves::Program { .. } => None,
            Moves::Held(job) => Some(&job.trajectory),
        }
    }

    /// Read and plan the whole program as a stream, without sampling or analysing it, for its defects:
    /// the diagnostics its report would list. `progress(t, defects)` is called after each segment with
    /// the commanded time (s) planned through and whether a defect was met so far, so that a consumer
    /// running behind can stop before it reaches one.
    pub fn check(&self, machine: &Machine, mut progress: impl FnMut(f64, bool)) -> Result<Checked, JobError> {
        let (source, options) = match self {
            Moves::Held(job) => {
                let diagnostics: Vec<Diagnostic> = job.program.diagnostics.iter().chain(&job.trajectory.diagnostics).cloned().collect();
                let errors = job.report.errors;
                progress(job.trajectory.duration(), errors > 0);
                return Ok(Checked { diagnostics, errors, blocks: job.report.blocks, segments: job.trajectory.segments.len(), duration_s: job.trajectory.duration() });
            }
            Moves::Program { source, options } => (source, options),
        };
        let mut segments = crate::path::SegmentStream::new(source.open(options)?, machine, &options.path);
        let (mut count, mut end) = (0usize, 0.0f64);
        while let Some(seg) = segments.next() {
            count += 1;
            end = seg.t0 + seg.duration;
            progress(end, segments.errors() > 0);
        }
        let diagnostics = read_rest(&mut segments, count);
        let errors = segments.errors() + usize::from(count == 0);
        progress(end, errors > 0);
        Ok(Checked { diagnostics, errors, blocks: segments.blocks().blocks_read(), segments: count, duration_s: end })
    }

    /// The analysis report ([`analyze_streaming`] for a program).
    pub fn report(&self, machine: &Machine) -> Result<AnalysisReport, JobError> {
        match self {
            Moves::Program { source, options } => analyze_source(source, machine, options),
            Moves::Held(job) => Ok(job.report.clone()),
        }
    }
}

/// Read the rest of a program whose planning ended (at its end, or at the duration bound), having
/// planned `segments` moves: the diagnostics of its report, in order (the reader's, the planning's,
/// and the error of a program without a single move).
fn read_rest(stream: &mut crate::path::SegmentStream, segments: usize) -> Vec<Diagnostic> {
    stream.read_to_end();
    with_no_moves(reading_diagnostics(stream), segments, stream.blocks().blocks_read())
}

/// A reading's diagnostics, with the error of a program without a move if `segments` is 0 (of
/// `blocks` read).
fn with_no_moves(mut diagnostics: Vec<Diagnostic>, segments: usize, blocks: usize) -> Vec<Diagnostic> {
    if segments == 0 {
        diagnostics.push(no_moves(blocks));
    }
    diagnostics
}

/// The diagnostics of a stream read to its end: the reader's, then the planning's.
fn reading_diagnostics(stream: &crate::path::SegmentStream) -> Vec<Diagnostic> {
    let mut diagnostics = stream.blocks().diagnostics().to_vec();
    diagnostics.extend(stream.diagnostics().to_vec());
    diagnostics
}

/// The error of a program without a single move: a gate that read nothing never passes (an empty
/// program, only comments, or every block refused is bad input, not a clean result).
fn no_moves(blocks: usize) -> Diagnostic {
    Diagnostic {
        line: 1,
        column: 1,
        severity: Severity::Error,
        message: format!("no moves: {blocks} blocks read and none moves an axis, so there is nothing to analyse"),
    }
}

/// The moves and regions of the program named by `spec` on `machine`, for aligning a machine stream
/// with it (the monitor's and the offline analysis' `--program`); a program with defects is refused,
/// naming them. The program is read here once, as a stream, for its defects and regions; each aligned
/// stream reads it again as it goes (memory does not grow with the program).
pub fn program_plan(spec: &str, machine: &Machine, read: &ReadOptions) -> Result<crate::live::monitor::ProgramPlan, String> {
    use crate::live::monitor::ProgramPlan;
    // Every region's times: the look-ahead needs each one ahead (two numbers per region; the regions
    // themselves are listed to the usual bound).
    let options = JobOptions { read: read.on(machine), ..Default::default() };
    let refuse = |diagnostics: &[Diagnostic], file: &str| {
        let errors: Vec<String> =
            diagnostics.iter().filter(|d| d.severity == Severity::Error).map(|d| format!("{file}:{}:{}: {}", d.line, d.column, d.message)).collect();
        if errors.is_empty() {
            Ok(())
        } else {
            Err(format!("the program has defects:\n{}", errors.join("\n")))
        }
    };
    match Moves::open(spec, machine, &options).map_err(|e| e.to_string())? {
        Moves::Held(job) => {
            // A built-in path: short, run whole (its few regions all listed).
            let diagnostics: Vec<Diagnostic> = job.program.diagnostics.iter().chain(&job.trajectory.diagnostics).cloned().collect();
            refuse(&diagnostics, spec)?;
            if job.trajectory.segments.is_empty() {
                return Err("the program has no moves".into());
            }
            let regions = job.analysis.regions.iter().map(|r| (r.t_start, r.t_end)).collect();
            Ok(ProgramPlan::held(job.trajectory.segments, regions))
        }
        Moves::Program { source, options } => {
            let mut segments = crate::path::SegmentStream::new(source.open(&options).map_err(|e| e.to_string())?, machine, &options.path);
            let mut regions = Vec::new();
            let (_, counts) = crate::singularity::analyze_segments_each(segments.by_ref(), options.path.period, machine, &options.analysis, |r| regions.push((r.t_start, r.t_end)));
            let diagnostics = read_rest(&mut segments, counts.segments);
            refuse(&diagnostics, segments.blocks().source())?;
            let machine = machine.clone();
            let spec = spec.to_string();
            let open: crate::path::align::OpenSegments = std::sync::Arc::new(move || {
                let blocks = source.open(&options).map_err(|e| format!("--program {spec}: {e}"))?;
                Ok(Box::new(crate::path::SegmentStream::owned(blocks, machine.clone(), &options.path))
                    as Box<dyn Iterator<Item = crate::path::Segment> + Send>)
            });
            Ok(ProgramPlan { segments: open, regions })
        }
    }
}

/// Where a machine stream's programmed feed comes from, from the `--program` and `--feed` flags of the
/// monitor and the offline analysis: the program's plan, a fixed feed (mm/min, positive), or assumed.
pub fn feed_source(program: Option<&str>, feed_mm_per_min: Option<f64>, machine: &Machine, read: &ReadOptions) -> Result<crate::live::monitor::FeedSource, String> {
    use crate::live::monitor::FeedSource;
    match (program, feed_mm_per_min) {
        (Some(spec), _) => program_plan(spec, machine, read).map(|p| FeedSource::Program(std::sync::Arc::new(p))).map_err(|e| format!("--program {spec}: {e}")),
        (None, Some(f)) if f.is_finite() && f > 0.0 => Ok(FeedSource::Fixed(f * crate::units::MM_PER_MIN)),
        (None, Some(f)) => Err(format!("--feed {f}: a feed must be a positive number of mm/min")),
        (None, None) => Ok(FeedSource::Assumed),
    }
}

impl Job {
    /// True if the program or its planning had defects.
    pub fn has_errors(&self) -> bool {
        self.report.diagnostics.iter().any(|d| d.severity == Severity::Error)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The report of an analysis made along another consumer's reading of the program, as the
    /// in-process run's commander makes it, against the report of the analysis reading the program
    /// itself; the consumer gets every sample, each with the next one and its segment.
    fn along_report(spec: &str, machine: &Machine, options: &JobOptions, cut_after: Option<usize>) -> Result<(AnalysisReport, usize), JobError> {
        let moves = Moves::open(spec, machine, options)?;
        let mut stream = moves.segment_stream(machine)?.expect("a program is streamed");
        let mut seen = 0usize;
        let mut last_t = f64::NEG_INFINITY;
        let (analysis, counts) = crate::singularity::analyze_segments_along(stream.by_ref().take(cut_after.unwrap_or(usize::MAX)), options.path.period, machine, &options.analysis, |cur, next, seg| {
            assert!(cur.t > last_t && next.is_none_or(|n| n.t > cur.t), "samples in time order");
            assert!(seg.is_some(), "a sample's segment is handed with it");
            last_t = cur.t;
            seen += 1;
        });
        assert_eq!(seen, counts.samples);
        Ok((report_of_reading(&mut stream, &analysis, counts, machine, options)?, seen))
    }

    #[test]
    fn an_analysis_along_another_reading_reports_what_reading_the_program_reports() {
        let m = Machine::hermle_c600u();
        let options = JobOptions::default();
        let dir = std::env::temp_dir().join(format!("fiveaxis-feed-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // A defect (an unknown word) and a program without a move: the diagnostics come from the reading.
        let bad = dir.join("bad.ngc");
        std::fs::write(&bad, "G1 X10 F100\nG1 X20 Q5\nG1 X30 Y5\n").unwrap();
        let empty = dir.join("empty.ngc");
        std::fs::write(&empty, "(only a comment)\n").unwrap();
        for spec in ["bundled:SING.I", "bundled:NON_SING.I", bad.to_str().unwrap(), empty.to_str().unwrap()] {
            let own = analyze_streaming(spec, &m, &options).unwrap();
            let (along, seen) = along_report(spec, &m, &options, None).unwrap();
            assert_eq!(along, own, "{spec}");
            assert_eq!(seen, own.samples, "{spec}: every sample handed over");
        }
        assert!(!analyze_streaming(bad.to_str().unwrap(), &m, &options).unwrap().diagnostics.is_empty());
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn a_reading_that_ended_before_the_programs_end_is_an_error_not_a_report() {
        let m = Machine::hermle_c600u();
        let r = along_report("bundled:SING.I", &m, &JobOptions::default(), Some(10));
        assert!(matches!(r, Err(JobError::FeedCut)), "{r:?}");
    }
}
