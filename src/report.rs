//! Reports for people and for CI: the analysis in mm, degrees, rpm and mm/min, as JSON or a table.

use crate::machine::Machine;
use crate::program::{Diagnostic, Program, Severity};
use crate::singularity::{Analysis, FeedLimit, LimitKind, RegionCause};
use crate::units::{MM, MM_PER_MIN, RPM};
use serde::Serialize;
use std::fmt::Write as _;

/// One diagnostic, as reported.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct DiagnosticReport {
    pub file: String,
    pub line: usize,
    pub column: usize,
    pub severity: Severity,
    pub message: String,
}

impl std::fmt::Display for DiagnosticReport {
    /// `file:line:column: severity: message`, as compilers print them.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}:{}: {}: {}", self.file, self.line, self.column, self.severity, self.message)
    }
}

/// One region, as reported.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RegionReport {
    pub id: usize,
    /// Why the region is there: `singularity` when its closest approach lies within 15 deg of the
    /// singular direction, `rotary_feed` otherwise (the rule of live streams and recordings).
    pub cause: crate::singularity::tracker::Cause,
    /// What the path crossed: the secondary axis' speed limit, the distance threshold, or both.
    pub limit: RegionCause,
    pub x_start_mm: f64,
    pub x_end_mm: f64,
    pub y_start_mm: f64,
    pub y_end_mm: f64,
    pub z_start_mm: f64,
    pub z_end_mm: f64,
    pub t_start_s: f64,
    pub t_end_s: f64,
    pub line_start: usize,
    pub line_end: usize,
    pub block_start: Option<u64>,
    pub block_end: Option<u64>,
    pub peak_c_speed_rpm: f64,
    pub peak_x_mm: f64,
    pub min_singularity_distance_deg: f64,
    pub min_feed_limit_mm_per_min: Option<f64>,
    pub limiting_axis: Option<String>,
    pub limit_kind: Option<LimitKind>,
}

/// The fastest the secondary axis turned on a rapid, by finite differences, and where.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RapidPeak {
    pub rpm: f64,
    pub line: usize,
    pub block: Option<u64>,
}

/// The analysis of one program, in people's units. "C" is the machine's secondary rotary axis.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct AnalysisReport {
    pub program: String,
    pub machine: String,
    /// The axis whose speed diverges at the singularity (C on the Hermle); empty on a four-axis machine.
    pub secondary_axis: String,
    /// A four-axis machine's only rotary axis (its name): such a machine has no singular orientation
    /// (the tool keeps its angle to the axis), so the singularity figures are 0 and no region opens.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub four_axis: Option<String>,
    pub blocks: usize,
    pub samples: usize,
    pub sample_period_s: f64,
    pub cycle_time_s: f64,
    pub feed_override_mm_per_min: Option<f64>,
    pub peak_c_speed_rpm: f64,
    pub peak_c_speed_x_mm: f64,
    pub peak_c_speed_y_mm: f64,
    pub peak_c_speed_z_mm: f64,
    pub peak_c_speed_line: usize,
    pub peak_c_speed_block: Option<u64>,
    pub peak_c_speed_fd_rpm: f64,
    /// The finite-difference peak over feed moves alone, and over rapids (the axes at their own
    /// speeds, not along a path) with where it is: a 3+2 program's positioning turns the axis.
    pub peak_c_speed_fd_feed_rpm: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_c_speed_fd_rapid: Option<RapidPeak>,
    pub singular_samples: usize,
    pub min_singularity_distance_deg: Option<f64>,
    pub min_singularity_distance_x_mm: Option<f64>,
    pub min_singularity_distance_all_deg: f64,
    pub c_max_rpm: f64,
    pub min_feed_limit_mm_per_min: Option<f64>,
    pub min_feed_limit_x_mm: Option<f64>,
    pub feed_limiting_axis: Option<String>,
    pub feed_limit_kind: Option<LimitKind>,
    /// The first regions in full (`--max-listed-regions`), and the rest folded.
    pub regions: Vec<RegionReport>,
    pub unlisted_regions: crate::listing::Unlisted,
    pub errors: usize,
    pub warnings: usize,
    pub diagnostics: Vec<DiagnosticReport>,
}

fn axis_name(machine: &Machine, fl: &Option<FeedLimit>) -> Option<String> {
    fl.and_then(|f| f.axis).map(|i| machine.axes[i].name.clone())
}

/// What reading and sampling a program counted, for its report.
#[derive(Debug, Clone, Copy)]
pub struct ReadFacts<'a> {
    /// Where the program came from.
    pub source: &'a str,
    pub blocks: usize,
    pub samples: usize,
    /// Sample period, s.
    pub period: f64,
}

impl AnalysisReport {
    /// Build the report. `extra` are diagnostics from planning (unreachable poses and the like).
    pub fn new(
        program: &Program,
        machine: &Machine,
        analysis: &Analysis,
        traj: &crate::path::Trajectory,
        extra: &[Diagnostic],
        feed_override_mm_per_min: Option<f64>,
    ) -> AnalysisReport {
        let read = ReadFacts { source: &program.source, blocks: program.blocks.len(), samples: traj.sample_count(), period: traj.period };
        Self::from_parts(&read, program.diagnostics.iter().chain(extra), machine, analysis, feed_override_mm_per_min)
    }

    /// Build the report from what reading and sampling counted (a program analysed as a stream has
    /// no block list or trajectory to hand over).
    pub fn from_parts<'d>(
        read: &ReadFacts<'_>,
        all_diagnostics: impl Iterator<Item = &'d Diagnostic>,
        machine: &Machine,
        analysis: &Analysis,
        feed_override_mm_per_min: Option<f64>,
    ) -> AnalysisReport {
        let s = &analysis.summary;
        let rpm = |v: f64| v / RPM;
        let mm = |v: f64| v / MM;
        let mut diagnostics: Vec<DiagnosticReport> = all_diagnostics
            .map(|d| DiagnosticReport {
                file: read.source.to_string(),
                line: d.line,
                column: d.column,
                severity: d.severity,
                message: d.message.clone(),
            })
            .collect();
        diagnostics.sort_by_key(|d| (d.line, d.column));
        let regions = analysis
            .regions
            .iter()
            .map(|r| RegionReport {
                id: r.id,
                cause: crate::singularity::tracker::Cause::of(r.min_distance, crate::singularity::tracker::SINGULAR_WITHIN_DEG.to_radians()),
                limit: r.cause,
                x_start_mm: mm(r.tip_start.x),
                x_end_mm: mm(r.tip_end.x),
                y_start_mm: mm(r.tip_start.y),
                y_end_mm: mm(r.tip_end.y),
                z_start_mm: mm(r.tip_start.z),
                z_end_mm: mm(r.tip_end.z),
                t_start_s: r.t_start,
                t_end_s: r.t_end,
                line_start: r.line_start,
                line_end: r.line_end,
                block_start: r.block_start,
                block_end: r.block_end,
                peak_c_speed_rpm: rpm(r.peak_rate),
                peak_x_mm: mm(r.peak_tip.x),
                min_singularity_distance_deg: r.min_distance.to_degrees(),
                min_feed_limit_mm_per_min: r.min_feed_limit.map(|f| f.feed / MM_PER_MIN),
                limiting_axis: axis_name(machine, &r.min_feed_limit),
                limit_kind: r.min_feed_limit.map(|f| f.kind),
            })
            .collect();
        let errors = diagnostics.iter().filter(|d| d.severity == Severity::Error).count();
        AnalysisReport {
            program: read.source.to_string(),
            machine: machine.name.clone(),
            secondary_axis: machine.axes[machine.secondary_axis()].name.clone(),
            four_axis: machine.chain.is_four_axis().then(|| machine.axes[3].name.clone()),
            blocks: read.blocks,
            samples: read.samples,
            sample_period_s: read.period,
            cycle_time_s: s.cycle_time,
            feed_override_mm_per_min,
            peak_c_speed_rpm: rpm(s.peak_rate),
            peak_c_speed_x_mm: mm(s.peak_tip.x),
            peak_c_speed_y_mm: mm(s.peak_tip.y),
            peak_c_speed_z_mm: mm(s.peak_tip.z),
            peak_c_speed_line: s.peak_line,
            peak_c_speed_block: s.peak_block,
            peak_c_speed_fd_rpm: rpm(s.peak_fd_rate),
            peak_c_speed_fd_feed_rpm: rpm(s.peak_fd_feed_rate),
            peak_c_speed_fd_rapid: s.peak_fd_rapid.map(|(r, line, block)| RapidPeak { rpm: rpm(r), line, block }),
            singular_samples: s.singular_samples,
            min_singularity_distance_deg: s.min_distance.map(f64::to_degrees),
            min_singularity_distance_x_mm: s.min_distance_tip.map(|t| mm(t.x)),
            min_singularity_distance_all_deg: if s.min_distance_all.is_finite() { s.min_distance_all.to_degrees() } else { 0.0 },
            c_max_rpm: rpm(s.rate_limit),
            min_feed_limit_mm_per_min: s.min_feed_limit.map(|f| f.feed / MM_PER_MIN),
            min_feed_limit_x_mm: s.min_feed_limit_tip.map(|t| mm(t.x)),
            feed_limiting_axis: axis_name(machine, &s.min_feed_limit),
            feed_limit_kind: s.min_feed_limit.map(|f| f.kind),
            regions,
            unlisted_regions: analysis.unlisted,
            errors,
            warnings: diagnostics.len() - errors,
            diagnostics,
        }
    }

    /// A short table for people.
    pub fn to_table(&self) -> String {
        let c = &self.secondary_axis;
        let mut o = String::new();
        let _ = writeln!(o, "program    {} ({} blocks, {} samples at {} ms)", self.program, self.blocks, self.samples, self.sample_period_s * 1e3);
        match &self.four_axis {
            Some(a) => writeln!(o, "machine    {} (four-axis: one rotary axis, {a}; no singular orientation)", self.machine),
            None => writeln!(o, "machine    {} (singular axis {c}, limit {:.1} rpm)", self.machine, self.c_max_rpm),
        }
        .ok();
        let _ = writeln!(o, "cycle time {:.2} s at the programmed feed", self.cycle_time_s);
        // A four-axis machine has no singularity figures: its feed limit and diagnostics only.
        if self.four_axis.is_some() {
            self.feed_limit_line(&mut o);
            self.diagnostics_lines(&mut o);
            return o;
        }
        let block = |b: Option<u64>| b.map_or(String::new(), |n| format!("N{n}, "));
        // A peak that rounds to 0.0 rpm has no place worth naming (every sample ties).
        if self.peak_c_speed_rpm < 0.05 {
            let _ = writeln!(o, "peak {c} speed (eq. 5)    {:8.1} rpm (no feed move along the path turns {c})", self.peak_c_speed_rpm);
        } else {
            let _ = writeln!(
                o,
                "peak {c} speed (eq. 5)    {:8.1} rpm at x {:.3} y {:.3} z {:.3} mm ({}line {})",
                self.peak_c_speed_rpm, self.peak_c_speed_x_mm, self.peak_c_speed_y_mm, self.peak_c_speed_z_mm,
                block(self.peak_c_speed_block), self.peak_c_speed_line
            );
        }
        match &self.peak_c_speed_fd_rapid {
            // A rapid turned the axis faster than any feed move (a 3+2 program's positioning).
            Some(r) if r.rpm > self.peak_c_speed_fd_feed_rpm + 0.05 => {
                let _ = writeln!(
                    o,
                    "peak {c} speed (fin. diff) {:8.1} rpm on feed moves; {:.1} rpm on a rapid ({}line {})",
                    self.peak_c_speed_fd_feed_rpm,
                    r.rpm,
                    block(r.block),
                    r.line
                );
            }
            _ => {
                let _ = writeln!(o, "peak {c} speed (fin. diff) {:8.1} rpm", self.peak_c_speed_fd_rpm);
            }
        }
        match (self.min_singularity_distance_deg, self.min_singularity_distance_x_mm) {
            (Some(d), Some(x)) => {
                let _ = writeln!(o, "closest approach          {d:8.3} deg on five-axis moves, at x {x:.3} mm ({:.3} deg overall)", self.min_singularity_distance_all_deg);
            }
            _ => {
                let _ = writeln!(o, "closest approach          no five-axis moves ({:.3} deg overall)", self.min_singularity_distance_all_deg);
            }
        }
        self.feed_limit_line(&mut o);
        if self.singular_samples > 0 {
            let _ = writeln!(o, "on the singularity        {} samples exactly on the singular direction while moving (eq. 5 undefined there)", self.singular_samples);
        }
        if self.regions.is_empty() {
            let _ = writeln!(o, "regions    none: {c} stays within {:.1} rpm", self.c_max_rpm);
        } else {
            let _ = writeln!(o, "regions where {c} speed > {:.1} rpm:", self.c_max_rpm);
            let _ = writeln!(o, "   #   x from     x to   blocks          peak rpm  min dist deg  cause        min feed mm/min");
            for r in &self.regions {
                let number = |b: Option<u64>| b.map_or(-1, |n| i64::try_from(n).unwrap_or(i64::MAX));
                let line = |l: usize| u32::try_from(l).unwrap_or(u32::MAX);
                let blocks = block_span(number(r.block_start), number(r.block_end), line(r.line_start), line(r.line_end));
                let feed = match (r.min_feed_limit_mm_per_min, &r.limiting_axis) {
                    (Some(f), Some(a)) => format!("{f:.0} ({a})"),
                    (Some(f), None) => format!("{f:.0}"),
                    _ => "-".into(),
                };
                let _ = writeln!(
                    o,
                    "{:>4} {:8.3} {:8.3}   {:<14} {:9.1} {:13.3}  {:<12} {}",
                    r.id,
                    r.x_start_mm,
                    r.x_end_mm,
                    blocks,
                    r.peak_c_speed_rpm,
                    r.min_singularity_distance_deg,
                    r.cause.name(),
                    feed
                );
            }
            if let Some(more) = self.unlisted_regions.describe() {
                let _ = writeln!(o, "     {more}");
            }
        }
        self.diagnostics_lines(&mut o);
        o
    }

    /// The table's line of the lowest feed limit and the axis that sets it.
    fn feed_limit_line(&self, o: &mut String) {
        if let (Some(f), Some(x)) = (self.min_feed_limit_mm_per_min, self.min_feed_limit_x_mm) {
            let by = match (&self.feed_limiting_axis, self.feed_limit_kind) {
                (Some(a), Some(k)) => format!("{a} {k:?}").to_lowercase(),
                _ => "programmed".into(),
            };
            let _ = writeln!(o, "lowest feed limit         {f:8.0} mm/min ({by}) at x {x:.3} mm (seed 002 eq. 5)");
        }
    }

    /// The table's diagnostics, one a line.
    fn diagnostics_lines(&self, o: &mut String) {
        if self.diagnostics.is_empty() {
            let _ = writeln!(o, "diagnostics none");
        } else {
            let _ = writeln!(o, "diagnostics {} errors, {} warnings:", self.errors, self.warnings);
            for d in &self.diagnostics {
                let _ = writeln!(o, "  {d}");
            }
        }
    }
}

/// Seconds for people, to 0.01 s: a figure that rounds to zero prints `0.00`, never `-0.00` (the
/// time lost by a stream that ran at exactly its programmed feed sums to a rounding error of either
/// sign). The one place every report prints a region's time lost.
///
/// ```
/// use fiveaxis::report::seconds;
/// assert_eq!(seconds(-1e-15), "0.00");
/// assert_eq!(seconds(-0.004), "0.00");
/// assert_eq!(seconds(-0.02), "-0.02");
/// assert_eq!(seconds(1.5), "1.50");
/// ```
pub fn seconds(s: f64) -> String {
    let text = format!("{s:.2}");
    match text.strip_prefix('-') {
        Some(zero) if zero == "0.00" => zero.to_string(),
        _ => text,
    }
}

/// Blocks for people: `N340-N390` where the program numbers its blocks (`-1`: no number), else its
/// lines `line 12-40` (`0`: unknown), else `no block numbers`. The one place every report names a
/// stretch of a program.
pub fn block_span(block_start: i64, block_end: i64, line_start: u32, line_end: u32) -> String {
    match (block_start, block_end, line_start, line_end) {
        (a, b, _, _) if a >= 0 && b >= 0 => format!("N{a}-N{b}"),
        (_, _, a, b) if a > 0 && b > 0 => format!("line {a}-{b}"),
        _ => "no block numbers".into(),
    }
}
