//! Offline analysis of a recording, for CI: the monitor recomputed over every axis-state message of
//! an MCAP file (ours, or any rosbag2 MCAP with a machine bridge's JointState plus a machine model),
//! regions with their x range, peak predicted C speed, lowest feed and time lost, and threshold checks.

use crate::live::joint_map::unmapped_hint;
use crate::live::monitor::{FeedSource, InputId, InputSummary, Monitor, MonitorConfig, Rejected};
use crate::recorded::{read_states, Selection, Unread};
use crate::singularity::measured::Motion;
use crate::machine::Machine;
use crate::record::RecordError;
use nalgebra::Vector3;
use fiveaxis_msgs::AxisState;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Options of the offline analysis.
#[derive(Debug, Clone, Default)]
pub struct OfflineOptions {
    pub monitor: MonitorConfig,
    /// Fail when the predicted C speed exceeds this (rpm).
    pub max_c_speed_rpm: Option<f64>,
    /// Fail when a moving tool axis comes closer than this to the singularity (degrees).
    pub min_distance_deg: Option<f64>,
    /// Which JointState streams to analyse, and their joints' names for the machine's axes.
    pub selection: Selection,
    /// A measured roughness profile (aligned to the workpiece x) and its filter cut-off (m).
    pub roughness: Option<(crate::roughness::Profile, f64)>,
    /// Where a machine stream's programmed feed comes from (`--program`, `--feed`, else assumed).
    pub feed_source: FeedSource,
    /// A stream with more than this share of its samples rejected fails the analysis (exit 2).
    pub max_rejected_share: f64,
}

/// The share of rejected samples above which an input is refused, unless told otherwise: 1 %.
pub const MAX_REJECTED_SHARE: f64 = 0.01;


/// A region of the program, with what the actual (simulated or machine) stream did there.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RegionReport {
    pub x_start_mm: f64,
    pub x_end_mm: f64,
    pub block_start: i64,
    pub block_end: i64,
    /// Program lines (0: unknown), for programs without block numbers.
    pub line_start: u32,
    pub line_end: u32,
    pub peak_c_speed_rpm: f64,
    /// The stream the region comes from, and the actual stream the feed figures come from.
    pub topic: String,
    pub actual_topic: Option<String>,
    pub lowest_feed_mm_per_min: Option<f64>,
    pub time_lost_s: Option<f64>,
    /// Why the region was opened: `singularity` or `rotary_feed`.
    pub cause: Option<crate::singularity::tracker::Cause>,
    /// Each end of the region is known to within this much path, mm: the spacing of the stream's
    /// samples around it (a few micrometres at 1 kHz, millimetres at a few hertz).
    pub x_resolution_mm: f64,
}

/// Roughness along the part against the regions.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RoughnessReport {
    pub source: String,
    pub cutoff_mm: f64,
    pub windows: usize,
    pub roughness_ra_inside_um: Option<f64>,
    pub roughness_ra_outside_um: Option<f64>,
    pub roughness_rz_inside_um: Option<f64>,
    pub roughness_rz_outside_um: Option<f64>,
    /// Where Ra exceeds twice its median: the rough stretch, and how much of it lies in a region.
    pub rough_x_start_mm: Option<f64>,
    pub rough_x_end_mm: Option<f64>,
    pub rough_overlap_with_regions: Option<f64>,
    /// Pearson correlation along x between Ra and the actual stream's feed deficit (1 - f/F).
    pub correlation_ra_feed_deficit: Option<f64>,
}

/// One analysed stream: the monitor's summary of it, with what only the analysis of the whole
/// recording knows.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct StreamReport {
    /// Counters, rejections by reason, sample period, motion kinds, the programmed feed assumed, and
    /// the regions (the first in full, the rest folded: `--max-listed-regions`).
    #[serde(flatten)]
    pub input: InputSummary,
    /// Messages that did not decode at all.
    pub undecodable: u64,
    pub peak_c_speed_rpm: f64,
    pub min_singularity_distance_deg: f64,
    /// Machine streams read as JointState or MTConnect: the longest a pose waited for every axis to
    /// be known at its instant (the per-axis merge's latency), s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub merge_latency_s: Option<f64>,
}

/// The report of `fiveaxis analyze`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct OfflineReport {
    pub file: String,
    pub machine: String,
    pub messages_read: u64,
    /// Why reading stopped before the end (a damaged or cut recording): the report covers the
    /// messages before it. None for a sound file.
    pub damage: Option<String>,
    /// Messages of analysed topics that did not decode.
    pub messages_undecodable: u64,
    pub streams: Vec<StreamReport>,
    /// The program's regions (from the commanded stream; else the machine's or the simulated one's),
    /// with the actual stream's lowest feed and time lost over each; past the listing cap, that
    /// stream's regions folded (their time lost is the stream's own: a machine stream's).
    pub regions: Vec<RegionReport>,
    pub unlisted_regions: crate::listing::Unlisted,
    pub violations: Vec<String>,
    /// Why the input cannot be trusted (exit 2): a topic asked for is absent, a stream has no valid
    /// sample, too many samples were rejected, joints could not be mapped, units look wrong.
    pub input_errors: Vec<String>,
    pub roughness: Option<RoughnessReport>,
    /// Flattened for CI: Ra inside and outside the regions, um.
    pub roughness_ra_inside_um: Option<f64>,
    pub roughness_ra_outside_um: Option<f64>,
}

mod cuts;

use cuts::{Cut, CutLog, RegionSpan};

/// What the analysis keeps per stream (topic) while reading.
struct Stream {
    input: InputId,
    /// Rejected samples whose positions would fit the axis ranges in mm and degrees.
    fits_mm_deg: u64,
    /// The previous valid sample: tool tip (workpiece, m), tool axis, linear axes (m), stamp (s).
    last: Option<(Vector3<f64>, fiveaxis_msgs::Vector3, [f64; 3], f64)>,
    last_line: Option<u32>,
    cuts: CutLog,
    peak_c_speed_rpm: f64,
    min_distance_deg: f64,
}

/// Analyse the recording at `path` on `machine`.
pub fn analyze_mcap(path: &Path, machine: &Machine, options: &OfflineOptions) -> Result<OfflineReport, RecordError> {
    analyze_mcap_with_progress(path, machine, options, &mut |_, _| {})
}

/// [`analyze_mcap`], calling `progress(bytes read, file size)` now and then (for a progress bar).
/// The file is streamed (memory stays flat whatever its size) and each message decoded in place.
pub fn analyze_mcap_with_progress(
    path: &Path,
    machine: &Machine,
    options: &OfflineOptions,
    // Dynamic, so that a progress bar's code stays out of the per-message loop (called rarely).
    progress: &mut dyn FnMut(u64, u64),
) -> Result<OfflineReport, RecordError> {
    let mut monitor = Monitor::new(machine, options.monitor);
    monitor.set_feed_source(options.feed_source.clone());
    // The report keeps regions, counters, C speeds and distances, never a sample's feed limit.
    monitor.set_regions_only(true);
    let mut report = OfflineReport {
        file: path.display().to_string(),
        machine: machine.name.clone(),
        messages_read: 0,
        damage: None,
        messages_undecodable: 0,
        streams: Vec::new(),
        regions: Vec::new(),
        unlisted_regions: Default::default(),
        violations: Vec::new(),
        input_errors: Vec::new(),
        roughness: None,
        roughness_ra_inside_um: None,
        roughness_ra_outside_um: None,
    };
    // By stream number of the read (in order of first message).
    let mut streams: Vec<Stream> = Vec::new();
    let read = read_states(path, machine, &options.selection, progress, |msg| {
        if msg.stream == streams.len() {
            streams.push(Stream {
                input: monitor.input(msg.topic),
                fits_mm_deg: 0,
                last: None,
                last_line: None,
                cuts: CutLog::new(),
                peak_c_speed_rpm: 0.0,
                min_distance_deg: f64::INFINITY,
            });
        }
        let k = msg.stream;
        let state = match msg.sample {
            Ok(s) => s,
            Err(Unread::Undecodable) => return,
            Err(Unread::Unmapped(e)) => {
                monitor.reject(streams[k].input, &e);
                return;
            }
            Err(Unread::Session { change_only }) => {
                monitor.new_session(streams[k].input);
                monitor.set_change_only(streams[k].input, change_only);
                streams[k].last = None;
                streams[k].last_line = None;
                return;
            }
        };
        let log_s = msg.log_time as f64 * 1e-9;
        // No look-ahead (`on_commanded_ahead`): it only serves the live warning "region ahead in
        // N s", which a report of the whole recording does not need, and it would keep every
        // commanded sample in memory.
        let stream = &mut streams[k];
        let status = match monitor.evaluate_merged(stream.input, state, msg.uncertainty.as_ref(), log_s) {
            Ok(s) => s,
            Err(e) if e.is_out_of_range() => {
                if fits_in_mm_deg(machine, &state.position) {
                    stream.fits_mm_deg += 1;
                }
                return;
            }
            Err(_) => return,
        };
        if state.source == AxisState::SOURCE_MACHINE {
            // A machine stream: the monitor measured its path (forward kinematics, the programmed or
            // assumed feed, the motion kind); the closest approach and the feed figures are taken
            // on its feed moves.
            let t = status.stamp.as_secs();
            let tip = status.workpiece_position;
            let ds = stream.last.map_or(0.0, |(pt, ..)| (tip - pt).norm());
            // Simultaneous five-axis motion (a feed move with the tool axis turning): the closest
            // approach counts there (parking at A = 0 is harmless), and the feed figures come from it.
            if status.motion == Motion::Feed && status.turning {
                // The program line is the alignment's (a JointState carries none).
                stream.cuts.push(Cut { t, x: tip.x, ds, feed: status.path_feed, programmed: status.programmed_feed, line: status.program_line });
            }
            if let Some(d) = status.five_axis_distance {
                stream.min_distance_deg = stream.min_distance_deg.min(d.to_degrees());
            }
            stream.last = Some((tip, Default::default(), [0.0; 3], t));
            stream.peak_c_speed_rpm = stream.peak_c_speed_rpm.max(status.predicted_c_speed.abs() / crate::units::RPM);
            return;
        }
        // The closest approach counts on simultaneous five-axis motion (tool tip and tool axis both
        // moving), as in the program analysis: parking at A = 0 is harmless.
        // A rotary-only positioning move turns the table under a parked tool: the linear machine
        // axes stay still there, so they must move too.
        let (tip, axis) = (status.workpiece_position, state.tool_axis);
        let lin = [state.position[0], state.position[1], state.position[2]];
        // A step across a block boundary mixes two moves: only steps within one block count.
        let same_block = stream.last_line.is_none_or(|l| l == state.program_line);
        stream.last_line = Some(state.program_line);
        // Meaningful motion, not a servo settling: the tip at >= 1 % of the programmed feed, the
        // tool axis turning at >= 0.01 deg/s.
        let t = state.header.stamp.as_secs();
        let step = stream.last.filter(|_| same_block).and_then(|(pt, pa, pl, pt_s)| {
            let dt = t - pt_s;
            if dt <= 0.0 {
                return None;
            }
            let ds = (tip - pt).norm();
            let turn = ((axis.x - pa.x).powi(2) + (axis.y - pa.y).powi(2) + (axis.z - pa.z).powi(2)).sqrt() / dt;
            // With program information the programmed motion decides (a rotary-only move has no
            // programmed tip feed, whatever the servo's contour error does); without it, 1 mm/min.
            let min_speed = match (state.program_line > 0, state.programmed_feed > 0.0) {
                (true, true) => 0.01 * state.programmed_feed,
                (true, false) => f64::INFINITY,
                (false, _) => crate::units::MM_PER_MIN,
            };
            let linear = (0..3).any(|i| (lin[i] - pl[i]).abs() > 1e-9);
            (ds / dt >= min_speed && turn >= 0.01f64.to_radians() && linear).then_some(ds)
        });
        if let Some(ds) = step {
            // The feed figures come from the actual stream (machine or simulated): only those keep
            // their cut samples (memory grows with them, not with the commanded stream).
            if state.source != AxisState::SOURCE_COMMANDED {
                stream.cuts.push(Cut { t, x: tip.x, ds, feed: state.path_feed, programmed: state.programmed_feed, line: state.program_line });
            }
            stream.min_distance_deg = stream.min_distance_deg.min(status.singularity_distance.to_degrees());
        }
        stream.last = Some((tip, axis, lin, t));
        // The peak is the path's: a rapid runs its axes at their limits by definition.
        if state.motion != AxisState::MOTION_RAPID {
            stream.peak_c_speed_rpm = stream.peak_c_speed_rpm.max(status.predicted_c_speed.abs() / crate::units::RPM);
        }
    });
    // Damage after good messages: the report keeps everything read before it, and says so.
    let read = read?;
    report.messages_read = read.messages_read;
    report.messages_undecodable = read.undecodable();
    report.damage = read.damage.as_ref().map(ToString::to_string);
    monitor.finish();
    // The read's stream number of each report stream (the report lists them in topic order).
    let by_topic: BTreeMap<&str, usize> = read.streams.iter().enumerate().map(|(k, s)| (s.topic.as_str(), k)).collect();
    let mut order = Vec::new();
    for summary in monitor.summary() {
        // Every input of the monitor is a stream of the read.
        let Some(&k) = by_topic.get(summary.topic.as_str()) else { continue };
        let min_d = streams[k].min_distance_deg;
        order.push(k);
        report.streams.push(StreamReport {
            input: summary,
            undecodable: read.streams[k].undecodable,
            peak_c_speed_rpm: streams[k].peak_c_speed_rpm,
            min_singularity_distance_deg: if min_d.is_finite() { min_d } else { 180.0 },
            merge_latency_s: read.streams[k].merge_latency_s,
        });
    }
    report.input_errors = input_errors(machine, options, &report.streams, &order, &read, &streams);
    // The actual stream (a machine's, else the simulated one) and its cut samples, taken out for
    // the region figures (read back once).
    let actual = [AxisState::SOURCE_MACHINE, AxisState::SOURCE_SIMULATED].iter().find_map(|src| report.streams.iter().position(|s| s.input.source == *src));
    let mut actual_cuts: Option<CutLog> = actual.map(|i| std::mem::take(&mut streams[order[i]].cuts));
    let actual = actual.map(|k| report.streams[k].input.topic.clone());
    let spill_error = |source| RecordError::Io { path: path.to_path_buf(), source };
    // The feed deficit along x, for the roughness correlation (kept only when a profile is given),
    // gathered on the one pass over the cut samples.
    let mut deficit: Vec<(f64, f64)> = Vec::new();
    let keep_deficit = options.roughness.is_some();
    let mut gather = |c: &Cut| {
        if keep_deficit && c.programmed > 0.0 {
            deficit.push((c.x, (1.0 - c.feed / c.programmed).clamp(0.0, 1.0)));
        }
    };
    let mut cuts_read = false;
    for source in [AxisState::SOURCE_COMMANDED, AxisState::SOURCE_MACHINE, AxisState::SOURCE_SIMULATED] {
        if let Some(s) = report.streams.iter().map(|s| &s.input).find(|s| s.source == source && !s.regions.is_empty()) {
            report.unlisted_regions = s.unlisted_regions;
            if s.source != AxisState::SOURCE_MACHINE {
                // Only a machine stream's regions carry their own feed and time lost.
                report.unlisted_regions.time_lost_s = None;
                report.unlisted_regions.min_feed_mm_per_min = None;
            }
            // The lowest feed and time lost over each region: a machine stream's region carries its
            // own pass; otherwise the actual stream's five-axis samples within its x range.
            let figures = match (&mut actual_cuts, s.source == AxisState::SOURCE_MACHINE) {
                (Some(cuts), false) => {
                    let spans: Vec<RegionSpan> = s
                        .regions
                        .iter()
                        .map(|r| RegionSpan { lines: (r.line_start, r.line_end), x: (r.x_start_mm.min(r.x_end_mm) * 1e-3, r.x_start_mm.max(r.x_end_mm) * 1e-3) })
                        .collect();
                    cuts_read = true;
                    Some(cuts::region_figures(cuts, &spans, &mut gather).map_err(spill_error)?)
                }
                _ => None,
            };
            report.regions = s
                .regions
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let (actual_topic, lowest, lost) = if s.source == AxisState::SOURCE_MACHINE {
                        (Some(s.topic.clone()), r.min_path_feed_mm_per_min * crate::units::MM_PER_MIN, Some(r.time_lost_s))
                    } else {
                        let f = figures.as_ref().map(|f| f[i]);
                        let lost = f.and_then(|f| f.lost);
                        (lost.is_some().then(|| actual.clone()).flatten(), f.map_or(f64::INFINITY, |f| f.lowest), lost)
                    };
                    RegionReport {
                        x_start_mm: r.x_start_mm,
                        x_end_mm: r.x_end_mm,
                        block_start: r.block_start,
                        block_end: r.block_end,
                        line_start: r.line_start,
                        line_end: r.line_end,
                        peak_c_speed_rpm: r.peak_c_speed_rpm,
                        topic: s.topic.clone(),
                        actual_topic,
                        lowest_feed_mm_per_min: lowest.is_finite().then_some(lowest / crate::units::MM_PER_MIN),
                        time_lost_s: lost,
                        cause: Some(r.cause),
                        x_resolution_mm: r.x_resolution_mm,
                    }
                })
                .collect();
            break;
        }
    }
    if let Some((profile, cutoff)) = &options.roughness {
        if let Some(cuts) = actual_cuts.as_mut().filter(|_| !cuts_read) {
            cuts.for_each(&mut gather).map_err(spill_error)?;
        }
        let r = roughness_report(profile, *cutoff, &report.regions, deficit);
        report.roughness_ra_inside_um = r.roughness_ra_inside_um;
        report.roughness_ra_outside_um = r.roughness_ra_outside_um;
        report.roughness = Some(r);
    }
    for s in &report.streams {
        if let Some(limit) = options.max_c_speed_rpm {
            if s.peak_c_speed_rpm > limit {
                report.violations.push(format!("{}: predicted C speed {:.1} rpm exceeds {limit} rpm", s.input.topic, s.peak_c_speed_rpm));
            }
        }
        if let Some(d) = options.min_distance_deg {
            if s.min_singularity_distance_deg < d {
                report.violations.push(format!("{}: tool axis {:.3} deg from the singularity, below {d} deg", s.input.topic, s.min_singularity_distance_deg));
            }
        }
    }
    Ok(report)
}

/// True if positions rejected as out of range would fit every axis range read as mm and degrees: the
/// publisher did not convert to REP 103's m and rad.
fn fits_in_mm_deg(machine: &Machine, position: &[f64]) -> bool {
    position.len() == crate::machine::AXES
        && machine.axes.iter().zip(position).all(|(a, v)| {
            let si = if a.kind == crate::machine::AxisKind::Rotary { v.to_radians() } else { v * 1e-3 };
            v.is_finite() && a.limits.contains(si)
        })
}

/// The reasons the analysis cannot be trusted: each becomes exit 2 with its message.
fn input_errors(
    machine: &Machine,
    options: &OfflineOptions,
    streams: &[StreamReport],
    // The read's stream number of each of `streams`.
    order: &[usize],
    read: &crate::recorded::StatesRead,
    analysed: &[Stream],
) -> Vec<String> {
    // A topic asked for and absent, or nothing to read.
    let mut errors = read.selection_errors(&options.selection);
    // A stream read that gave the monitor nothing at all, not even a refusal (an MTConnect log none
    // of whose lines reports one of the machine's axes): nothing was read from it.
    for (k, stream) in read.streams.iter().enumerate() {
        if !order.contains(&k) {
            let names = stream.joint_names.as_deref().map_or(String::new(), |n| format!(" (looked for: {})", n.join(", ")));
            errors.push(format!("{}: nothing in the recording reports the machine's axes{names}", stream.topic));
        }
    }
    for (report, &k) in streams.iter().zip(order) {
        let (names, fits) = (&read.streams[k].joint_names, analysed[k].fits_mm_deg);
        let s = &report.input;
        let rejected = s.rejected.total() + report.undecodable;
        let total = s.samples + rejected;
        if s.rejected.missing_joint > 0 {
            let found = names.as_deref().unwrap_or_default();
            errors.push(format!(
                "{}: {} samples without a joint for every machine axis; {}",
                s.topic,
                s.rejected.missing_joint,
                unmapped_hint(machine, found, &options.selection.axis_map)
            ));
        }
        // An MTConnect log's values were converted from the units its device states.
        if s.rejected.out_of_range > 0 && fits * 2 >= s.rejected.out_of_range && !read.streams[k].mtconnect {
            errors.push(format!(
                "{}: {} samples outside the axis ranges would fit them read as mm and degrees: JointState positions must be in m and rad (REP 103)",
                s.topic, s.rejected.out_of_range
            ));
        }
        if let Some(why) = &s.program_unreadable {
            errors.push(format!("{}: not aligned with the program: {why}", s.topic));
        }
        let first = read.first_malformed.get(&k).map_or(String::new(), |m| format!("; the first: {m}"));
        if s.samples == 0 {
            errors.push(format!("{}: no valid sample ({rejected} rejected: {}){first}", s.topic, reasons(&s.rejected, report.undecodable)));
        } else if total > 0 && rejected as f64 > options.max_rejected_share * total as f64 {
            errors.push(format!(
                "{}: {rejected} of {total} samples rejected ({:.1} %, above the {:.1} % allowed): {}",
                s.topic,
                100.0 * rejected as f64 / total as f64,
                100.0 * options.max_rejected_share,
                reasons(&s.rejected, report.undecodable)
            ) + &first);
        }
    }
    errors
}

fn reasons(r: &Rejected, undecodable: u64) -> String {
    let parts: Vec<String> = [
        (r.missing_joint, "missing joint"),
        (r.non_finite, "NaN/Inf"),
        (r.out_of_range, "out of range"),
        (r.out_of_order, "out of order"),
        (r.malformed, "malformed"),
        (undecodable, "undecodable"),
    ]
    .iter()
    .filter(|(n, _)| *n > 0)
    .map(|(n, w)| format!("{n} {w}"))
    .collect();
    if parts.is_empty() { "none".into() } else { parts.join(", ") }
}

/// `by_x`: the actual stream's feed deficit (1 - feed / programmed, clamped to 0..1) at each
/// five-axis sample's x (m), in arrival order.
fn roughness_report(profile: &crate::roughness::Profile, cutoff: f64, regions: &[RegionReport], mut by_x: Vec<(f64, f64)>) -> RoughnessReport {
    let windows = profile.windows(cutoff, 0.1e-3);
    let in_region = |x: f64| regions.iter().any(|r| x * 1e3 >= r.x_start_mm.min(r.x_end_mm) && x * 1e3 <= r.x_start_mm.max(r.x_end_mm));
    let mean = |v: Vec<f64>| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64 * 1e6);
    let (inside, outside): (Vec<&crate::roughness::Window>, Vec<&crate::roughness::Window>) = windows.iter().partition(|w| in_region(w.x));
    let mut ras: Vec<f64> = windows.iter().map(|w| w.ra).collect();
    ras.sort_by(f64::total_cmp);
    let median = ras.get(ras.len() / 2).copied().unwrap_or(0.0);
    let rough: Vec<&crate::roughness::Window> = windows.iter().filter(|w| w.ra > 2.0 * median).collect();
    let (rs, re) = (rough.first().map(|w| w.x), rough.last().map(|w| w.x));
    let overlap = (!rough.is_empty()).then(|| rough.iter().filter(|w| in_region(w.x)).count() as f64 / rough.len() as f64);
    // Feed deficit at each window's x (nearest five-axis sample of the actual stream).
    by_x.sort_by(|a, b| a.0.total_cmp(&b.0));
    let corr = (!by_x.is_empty()).then(|| {
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for w in &windows {
            if w.x < by_x[0].0 || w.x > by_x[by_x.len() - 1].0 {
                continue;
            }
            let k = by_x.partition_point(|p| p.0 < w.x).min(by_x.len() - 1);
            a.push(w.ra);
            b.push(by_x[k].1);
        }
        crate::roughness::correlation(&a, &b)
    });
    RoughnessReport {
        source: profile.source.clone(),
        cutoff_mm: cutoff * 1e3,
        windows: windows.len(),
        roughness_ra_inside_um: mean(inside.iter().map(|w| w.ra).collect()),
        roughness_ra_outside_um: mean(outside.iter().map(|w| w.ra).collect()),
        roughness_rz_inside_um: mean(inside.iter().map(|w| w.rz).collect()),
        roughness_rz_outside_um: mean(outside.iter().map(|w| w.rz).collect()),
        rough_x_start_mm: rs.map(|x| x * 1e3),
        rough_x_end_mm: re.map(|x| x * 1e3),
        rough_overlap_with_regions: overlap,
        correlation_ra_feed_deficit: corr.filter(|c| c.is_finite()),
    }
}

fn cause_name(c: Option<crate::singularity::tracker::Cause>) -> &'static str {
    c.map_or("cause unknown", crate::singularity::tracker::Cause::name)
}



/// JUnit XML for several recordings (written with `quick-junit`): one `<testsuite>` per report, and
/// one with an error for each recording that could not be read at all (`(file, why)`).
pub fn junit_testsuites(reports: &[OfflineReport], unreadable: &[(&str, &str)]) -> Result<String, quick_junit::SerializeError> {
    use quick_junit::{NonSuccessKind, Report, TestCase, TestCaseStatus, TestSuite};
    let mut report = Report::new("fiveaxis analyze");
    for r in reports {
        report.add_test_suite(r.junit_suite());
    }
    for (file, why) in unreadable {
        let mut status = TestCaseStatus::non_success(NonSuccessKind::Error);
        status.set_message(*why);
        let mut case = TestCase::new("read", status);
        case.set_classname("fiveaxis.analyze");
        let mut suite = TestSuite::new(format!("fiveaxis analyze {file}"));
        suite.add_test_case(case);
        report.add_test_suite(suite);
    }
    report.to_string()
}

impl OfflineReport {
    /// JUnit XML: one test case per stream and check (C speed, distance to the singularity).
    pub fn to_junit(&self) -> Result<String, quick_junit::SerializeError> {
        junit_testsuites(std::slice::from_ref(self), &[])
    }

    /// The `<testsuite>` of this recording: a failure per check a stream violated, with its message.
    fn junit_suite(&self) -> quick_junit::TestSuite {
        use quick_junit::{NonSuccessKind, TestCase, TestCaseStatus, TestSuite};
        let mut suite = TestSuite::new(format!("fiveaxis analyze {}", self.file));
        for s in &self.streams {
            for (check, needle) in [("c_speed", "predicted C speed"), ("singularity_distance", "from the singularity")] {
                let fail = self.violations.iter().find(|v| v.starts_with(&format!("{}:", s.input.topic)) && v.contains(needle));
                let status = match fail {
                    Some(f) => {
                        let mut st = TestCaseStatus::non_success(NonSuccessKind::Failure);
                        st.set_message(f.as_str());
                        st
                    }
                    None => TestCaseStatus::success(),
                };
                let mut case = TestCase::new(format!("{}:{check}", s.input.topic), status);
                case.set_classname("fiveaxis.analyze");
                suite.add_test_case(case);
            }
        }
        suite
    }

    /// A short table for people.
    pub fn to_table(&self) -> String {
        use std::fmt::Write as _;
        let mut o = String::new();
        let _ = writeln!(o, "recording  {} ({} messages, machine {})", self.file, self.messages_read, self.machine);
        if let Some(d) = &self.damage {
            let _ = writeln!(o, "DAMAGED    reading stopped after {} messages: {d}", self.messages_read);
        }
        for report in &self.streams {
            let s = &report.input;
            let _ = writeln!(
                o,
                "{}: {} samples ({} invalid, {} out of order, {} lost), peak C {:.1} rpm, closest {:.3} deg",
                s.topic, s.samples, s.invalid, s.out_of_order, s.lost, report.peak_c_speed_rpm, report.min_singularity_distance_deg
            );
            if let Some(f) = &s.feed_source {
                let _ = writeln!(o, "  machine stream: feed {f}; {} samples on feed moves (highest feed held 0.1 s {:.0} mm/min), {} on rapids", s.feed_samples, s.max_path_feed_mm_per_min, s.rapid_samples);
            }
            if s.rejected.total() + report.undecodable > 0 {
                let _ = writeln!(o, "  rejected: {}", reasons(&s.rejected, report.undecodable));
            }
            if let Some(l) = report.merge_latency_s.filter(|l| *l > 0.01) {
                let _ = writeln!(o, "  axes merged per axis into poses: a pose waited up to {l:.2} s for every axis to be known");
            }
            if s.unconfirmed_regions > 0 {
                let _ = writeln!(
                    o,
                    "  {} stretch(es) where the demand passed the limit over less path than the merged poses' uncertainty: not regions",
                    s.unconfirmed_regions
                );
            }
            for r in &s.regions {
                let _ = writeln!(
                    o,
                    "  region {} ({}): x {:.3} to {:.3} mm, {}, peak C {:.1} rpm, feed down to {:.0} mm/min, {} s lost",
                    r.id,
                    cause_name(Some(r.cause)),
                    r.x_start_mm,
                    r.x_end_mm,
                    crate::report::block_span(r.block_start, r.block_end, r.line_start, r.line_end),
                    r.peak_c_speed_rpm,
                    r.min_path_feed_mm_per_min,
                    crate::report::seconds(r.time_lost_s)
                );
            }
            if let Some(more) = s.unlisted_regions.describe() {
                let _ = writeln!(o, "  {more}");
            }
        }
        for r in &self.regions {
            let feed = match (r.lowest_feed_mm_per_min, r.time_lost_s, &r.actual_topic) {
                (Some(f), Some(t), Some(a)) => format!(", {a}: feed down to {f:.0} mm/min, {} s lost", crate::report::seconds(t)),
                _ => String::new(),
            };
            let _ = writeln!(o, "region     x {:.3} to {:.3} mm ({}, {}), peak C {:.1} rpm{feed}", r.x_start_mm, r.x_end_mm, crate::report::block_span(r.block_start, r.block_end, r.line_start, r.line_end), cause_name(r.cause), r.peak_c_speed_rpm);
        }
        if let Some(more) = self.unlisted_regions.describe() {
            let _ = writeln!(o, "region     {more}");
        }
        if let Some(r) = &self.roughness {
            let f = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
            let _ = writeln!(o, "roughness  {} (lambda_c {} mm, {} windows of 5 lambda_c)", r.source, r.cutoff_mm, r.windows);
            let _ = writeln!(o, "           Ra inside the regions {} um, outside {} um; Rz inside {} um, outside {} um", f(r.roughness_ra_inside_um), f(r.roughness_ra_outside_um), f(r.roughness_rz_inside_um), f(r.roughness_rz_outside_um));
            if let (Some(a), Some(b)) = (r.rough_x_start_mm, r.rough_x_end_mm) {
                let _ = writeln!(o, "           rough stretch (Ra > 2x median) x {a:.2} to {b:.2} mm, {:.0} % of it inside the regions", r.rough_overlap_with_regions.unwrap_or(0.0) * 100.0);
            }
            if let Some(c) = r.correlation_ra_feed_deficit {
                let _ = writeln!(o, "           correlation of Ra with the feed deficit along x: {c:.2}");
            }
        }
        for e in &self.input_errors {
            let _ = writeln!(o, "INPUT      {e}");
        }
        if self.violations.is_empty() {
            let _ = writeln!(o, "violations none");
        } else {
            for v in &self.violations {
                let _ = writeln!(o, "violation  {v}");
            }
        }
        o
    }
}
