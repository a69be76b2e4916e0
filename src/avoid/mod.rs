//! Remedies for a singular tool path. Reorientation of the workpiece on a jig (seed 001 §3, eq. 7):
//! the tool path relative to the workpiece stays the same, the jig turns it (and so the tool axes)
//! by `R = R_x(theta_x) R_z(theta_z)`, which moves the singularity elsewhere on the orientation
//! sphere; the best angles keep the peak predicted C speed lowest within the machine's A range and the
//! tilt the user allows.

use crate::job::JobOptions;
use crate::machine::Machine;
use crate::path::Trajectory;
use crate::program::{Block, Program, Targets};
use crate::singularity::analyze;
use crate::units::DEG;
use nalgebra::{Rotation3, Vector3};

pub mod refine;
pub mod smooth;

/// The figures a remedy is judged by: the program's (seed 001 eq. 5 at the programmed feed) and what
/// the simulator (planner with the machine's v/a/j limits) makes of it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Figures {
    pub peak_c_speed_rpm: f64,
    pub min_singularity_distance_deg: f64,
    /// Simulated cycle time, s.
    pub cycle_time_s: f64,
    /// Cycle time at the programmed feeds, s.
    pub programmed_time_s: f64,
    /// Simulated minus programmed, s.
    pub time_lost_s: f64,
    /// Lowest simulated tool-tip feed on the feed moves, planned stops (corners, ends) excluded, mm/min.
    pub min_cut_feed_mm_min: f64,
    /// Largest simulated |v|/v_max, |a|/a_max, |j|/j_max over the axes (planner set-points).
    pub max_limit_ratio: [f64; 3],
    /// Largest change of the tool axis against the original program, degrees (0 for the original).
    pub max_orientation_deviation_deg: f64,
}

/// Why a program cannot be reoriented.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AvoidError {
    #[error("{0}")]
    Refused(String),
}

/// The jig rotation of eq. (7).
pub fn jig(theta_x: f64, theta_z: f64) -> Rotation3<f64> {
    Rotation3::from_axis_angle(&Vector3::x_axis(), theta_x) * Rotation3::from_axis_angle(&Vector3::z_axis(), theta_z)
}

/// CL data starts at its first pose (the first block with targets), where no segment ends: that
/// block and the first segment, which starts there. None for NC programs (they start at home).
pub(crate) fn start_pose<'a>(program: &Program, traj: &'a Trajectory) -> Option<(usize, &'a crate::path::Segment)> {
    if !program.dialect.starts_at_first_pose() {
        return None;
    }
    let b = program.blocks.iter().position(|b| !b.targets.is_empty())?;
    traj.segments.first().filter(|seg| b < seg.block).map(|seg| (b, seg))
}

/// The program turned by the jig rotation `r` (about the workpiece origin): TCPM blocks get the rotated
/// tool tip and tool axis as CL targets (A/C follow from the inverse kinematics); blocks without TCPM
/// (positioning in machine coordinates, away from the part) are unchanged.
pub fn reoriented(program: &Program, machine: &Machine, r: &Rotation3<f64>, options: &JobOptions) -> Program {
    let traj = Trajectory::from_program(program, machine, &options.path);
    let mut out = program.clone();
    let mut prev_tcp = false;
    let turned = |tip: &Vector3<f64>, q: &crate::kinematics::Joints| {
        let (t, a) = (r * tip, r * machine.forward(q).axis);
        Targets { x: Some(t.x), y: Some(t.y), z: Some(t.z), tool_axis: Some([a.x, a.y, a.z]), ..Targets::default() }
    };
    // CL data's first pose is where its first cut starts: turned too, and the lead-in to it.
    if let Some((b, seg)) = start_pose(program, &traj).filter(|(b, _)| program.blocks[*b].tcp) {
        out.blocks[b].targets = turned(&seg.tip0, &seg.q0);
        prev_tcp = true;
    }
    for s in &traj.segments {
        // A dwell's block keeps its time and position (its motion, if any, has a segment of its own).
        if s.kind == crate::path::SegmentKind::Dwell {
            continue;
        }
        let tcp = program.blocks[s.block].tcp;
        if tcp {
            let b: &mut Block = &mut out.blocks[s.block];
            b.targets = turned(&s.tip1, &s.q1);
            // The lead-in to a TCPM stretch now also turns the tool: make it a positioning move (as a
            // post-processor would), not a cut that starts wherever the axes were parked.
            if !prev_tcp {
                b.motion = crate::program::Motion::Rapid;
            }
        }
        prev_tcp = tcp;
    }
    out.source = format!("{} (reoriented)", program.source);
    out
}

/// The analysis figures of a program (peak predicted C speed, closest approach, programmed time).
fn analysed(program: &Program, machine: &Machine, options: &JobOptions) -> Result<(Trajectory, Figures), AvoidError> {
    let traj = Trajectory::from_program(program, machine, &options.path);
    if let Some(d) = traj.diagnostics.iter().find(|d| d.severity == crate::program::Severity::Error) {
        return Err(AvoidError::Refused(format!("line {}: {}", d.line, d.message)));
    }
    let a = analyze(&traj, machine, &options.analysis);
    let f = Figures {
        peak_c_speed_rpm: a.summary.peak_rate / crate::units::RPM,
        min_singularity_distance_deg: a.summary.min_distance.unwrap_or(std::f64::consts::FRAC_PI_2).to_degrees(),
        cycle_time_s: a.summary.cycle_time,
        programmed_time_s: a.summary.cycle_time,
        time_lost_s: 0.0,
        min_cut_feed_mm_min: f64::NAN,
        max_limit_ratio: [0.0; 3],
        max_orientation_deviation_deg: 0.0,
    };
    Ok((traj, f))
}

/// Figures of a program on a machine: the analysis, then the simulator re-run on it.
pub fn figures(program: &Program, machine: &Machine, options: &JobOptions) -> Result<Figures, AvoidError> {
    let (traj, mut f) = analysed(program, machine, options)?;
    let (sim, figures) = crate::live::sim_report::simulate_measured(&traj, machine, &Default::default(), |_, _| true);
    f.cycle_time_s = figures.duration_s;
    f.time_lost_s = f.cycle_time_s - f.programmed_time_s;
    f.max_limit_ratio = sim.planned_ratio;
    // Lowest feed on the feed moves, the planned stops (corners, the program's ends) excluded: the
    // same measure as `fiveaxis run` reports.
    let lowest = crate::units::mm_per_min(figures.lowest_feed);
    f.min_cut_feed_mm_min = if lowest.is_finite() { lowest } else { f64::NAN };
    Ok(f)
}

/// The result of a reorientation search.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Reorientation {
    pub theta_x_deg: f64,
    pub theta_z_deg: f64,
    pub before: Figures,
    pub after: Figures,
}

/// Search the jig angles: theta_x within +-`max_tilt` (rad), theta_z over the full turn, on a grid then
/// refined; poses the machine cannot reach (A range) are excluded. Lowest peak C speed wins (ties: the
/// larger closest approach, then the smaller tilt).
pub fn search(program: &Program, machine: &Machine, max_tilt: f64, options: &JobOptions) -> Result<(Reorientation, Program), AvoidError> {
    let before = figures(program, machine, options)?;
    let score = |tx: f64, tz: f64| -> Option<(Figures, Program)> {
        let p = reoriented(program, machine, &jig(tx, tz), options);
        analysed(&p, machine, options).ok().map(|(_, f)| (f, p))
    };
    let better = |a: &(f64, f64, Figures), b: &(f64, f64, Figures)| {
        let key = |x: &(f64, f64, Figures)| (x.2.peak_c_speed_rpm * 1e3).round();
        key(a) < key(b) || (key(a) == key(b) && (a.2.min_singularity_distance_deg > b.2.min_singularity_distance_deg + 1e-6 || a.0.abs() < b.0.abs()))
    };
    let mut best: Option<(f64, f64, Figures)> = None;
    let steps_x = 10;
    for i in 0..=2 * steps_x {
        let tx = -max_tilt + max_tilt * i as f64 / steps_x as f64;
        for j in 0..12 {
            let tz = j as f64 * 30.0 * DEG;
            if let Some((f, _)) = score(tx, tz) {
                let cand = (tx, tz, f);
                if best.as_ref().is_none_or(|b| better(&cand, b)) {
                    best = Some(cand);
                }
            }
        }
    }
    let (mut tx, mut tz, mut f) = best.ok_or_else(|| AvoidError::Refused("no jig angle keeps the tool path within the machine's ranges".into()))?;
    // Refine around the best grid point.
    let (mut dx, mut dz) = (max_tilt / steps_x as f64, 30.0 * DEG);
    for _ in 0..4 {
        dx /= 2.0;
        dz /= 2.0;
        for (ix, iz) in [(-1.0, 0.0), (1.0, 0.0), (0.0, -1.0), (0.0, 1.0)] {
            let (cx, cz) = ((tx + ix * dx).clamp(-max_tilt, max_tilt), tz + iz * dz);
            if let Some((cf, _)) = score(cx, cz) {
                let cand = (cx, cz, cf);
                if better(&cand, &(tx, tz, f)) {
                    (tx, tz, f) = cand;
                }
            }
        }
    }
    let program = reoriented(program, machine, &jig(tx, tz), options);
    // Relative to the workpiece the tool axes do not change (the jig turns both): deviation 0.
    let after = figures(&program, machine, options)?;
    Ok((Reorientation { theta_x_deg: tx.to_degrees(), theta_z_deg: tz.to_degrees().rem_euclid(360.0), before, after }, program))
}

/// What the control does besides moving at one block, as the written program's lines: before the
/// block's motion (tool, spindle and coolant on), after it (stops; the TNC's spindle and coolant off,
/// which it runs at the block's end), and whether it changes the tool (TCPM must be off then).
#[derive(Debug, Default)]
struct BlockEvents {
    before: Vec<String>,
    after: Vec<String>,
    tool_change: bool,
    /// The tool number in the spindle after this block's change (for G43.4's H: its length).
    tool: Option<String>,
}

/// One event's words in the written program; see [`block_events`].
struct EventWords {
    text: String,
    after: bool,
    tool_change: bool,
    /// The tool number it names (a call, or a T word a later M6 changes to).
    tool: Option<String>,
}

/// The events of every block of `program` in the written dialect: as written when the program is of
/// the written dialect's family, else translated (APT's `SPINDL/`, `COOLNT/`, `LOADTL/`; a tool called
/// as `T n G17` in DIN/ISO, at its `M6` when the program changes tools with M6, so that a `T` alone
/// is the preselection it is there). What the writer writes itself (TCPM on and off, the program end)
/// or what does nothing on the control (APT's `END`, a preselection) is left out; an event it cannot
/// write is an error, rather than a program that would cut with the spindle off or the wrong tool.
/// APT's events are statements run in order: one line each.
fn block_events(program: &Program, heid: bool, options: &JobOptions) -> Result<Vec<BlockEvents>, AvoidError> {
    use crate::program::{Dialect, MCodeAction};
    let source = program.dialect;
    let tnc = matches!(source, Dialect::Heidenhain | Dialect::Klartext);
    let same = matches!((source, heid), (Dialect::Rs274, false)) || (tnc && heid);
    let m_code = |e: &str| e.strip_prefix('M').and_then(|r| r.parse::<f64>().ok()).filter(|c| c.fract() == 0.0 && *c >= 0.0).map(|c| c as u32);
    let has_m6 = program.blocks.iter().flat_map(|b| &b.events).any(|e| m_code(e) == Some(6));
    let mut selected: Option<String> = None;
    let mut word = |ev: &str| -> Result<Option<EventWords>, AvoidError> {
        let cannot = |why: &str| AvoidError::Refused(format!("event '{ev}' cannot be written in {}: {why}", if heid { "Heidenhain DIN/ISO" } else { "RS274NGC" }));
        let plain = |text: &str| Ok(Some(EventWords { text: text.to_string(), after: false, tool_change: false, tool: None }));
        let call = |n: &str| -> Result<Option<EventWords>, AvoidError> {
            match n.trim().parse::<f64>() {
                Ok(t) if t >= 0.0 && t.fract() == 0.0 => {
                    Ok(Some(EventWords { text: if heid { format!("T{t} G17") } else { format!("T{t} M6") }, after: false, tool_change: true, tool: Some(t.to_string()) }))
                }
                _ => Err(cannot("not a tool number")),
            }
        };
        if source == Dialect::Cl {
            // APT: MAJOR/minor,... (ISO 4343).
            let (major, args) = ev.split_once('/').unwrap_or((ev, ""));
            let args: Vec<String> = args.split(',').map(|a| a.trim().to_ascii_uppercase()).filter(|a| !a.is_empty()).collect();
            let has = |w: &str| args.iter().any(|a| a == w);
            // The first number that is not a gear range's.
            let number = args.iter().enumerate().filter(|(i, _)| *i == 0 || args[i - 1] != "RANGE").find_map(|(_, a)| a.parse::<f64>().ok());
            return match major.trim().to_ascii_uppercase().as_str() {
                "SPINDL" if has("OFF") => plain("M5"),
                "SPINDL" if has("SFM") || has("SMM") => Err(cannot("a constant surface speed is not written")),
                "SPINDL" => {
                    let dir = if has("CCLW") { "M4" } else { "M3" };
                    plain(&number.map_or(dir.to_string(), |n| format!("S{n} {dir}")))
                }
                "COOLNT" if has("OFF") => plain("M9"),
                "COOLNT" if has("MIST") => plain("M7"),
                "COOLNT" if has("ON") || has("FLOOD") || args.is_empty() => plain("M8"),
                "COOLNT" => Err(cannot("only ON, FLOOD, MIST and OFF are written")),
                "LOADTL" => call(args.first().map_or("", |a| a.as_str())),
                "LOAD" if has("TOOL") => call(&number.map_or(String::new(), |n| n.to_string())),
                "SELECT" | "SELCTL" | "END" => Ok(None),
                "STOP" => plain("M0"),
                "OPSTOP" => plain("M1"),
                _ => Err(cannot("not a known APT event")),
            };
        }
        let (letter, rest) = ev.split_at(ev.chars().next().map_or(0, char::len_utf8));
        match letter {
            "M" => {
                let code = m_code(ev).ok_or_else(|| cannot("not an M code"))?;
                let tcp = options.read.m_codes.iter().any(|r| r.code == code && matches!(r.action, MCodeAction::TcpOn | MCodeAction::TcpOff));
                if tcp || matches!(code, 2 | 30) || (tnc && matches!(code, 128 | 129)) {
                    return Ok(None);
                }
                // When each runs: stops after the block's motion (LinuxCNC's order of execution and
                // the TNC's); the TNC also runs spindle and coolant off and the tool change at the end.
                let after = matches!(code, 0 | 1 | 60) || (tnc && matches!(code, 5 | 6 | 9));
                let tool_change = code == 6;
                if code == 6 && !same {
                    // The tool selected before changes at the M6: DIN/ISO's call `T n G17`, RS274NGC's
                    // `T n M6` (its T was not written: a preselection there too). A bare M6 with no
                    // tool selected changes to what the control has selected, in RS274NGC as written.
                    return match (heid, selected.take()) {
                        (_, Some(t)) => call(&t),
                        (true, None) => Err(cannot("M6 without a tool selected before it")),
                        (false, None) => Ok(Some(EventWords { text: ev.to_string(), after, tool_change, tool: None })),
                    };
                }
                if same || matches!(code, 0 | 1 | 3 | 4 | 5 | 7 | 8 | 9) {
                    return Ok(Some(EventWords { text: ev.to_string(), after, tool_change, tool: None }));
                }
                // The TNC's spindle on with coolant on (clockwise, counter-clockwise).
                if tnc && matches!(code, 13 | 14) {
                    return plain(if code == 13 { "M3 M8" } else { "M4 M8" });
                }
                Err(cannot("a machine's own M code, with no known meaning in the written dialect"))
            }
            "S" if rest.parse::<f64>().is_ok() => plain(ev),
            "T" if same && !heid => Ok(Some(EventWords { text: ev.to_string(), after: false, tool_change: false, tool: Some(rest.to_string()) })),
            // A T that an M6 changes to later is a preselection.
            "T" if has_m6 && !tnc => {
                selected = Some(rest.to_string());
                Ok(None)
            }
            "T" => call(rest),
            _ => Err(cannot("not a tool, spindle, coolant or stop word")),
        }
    };
    let mut all = Vec::with_capacity(program.blocks.len());
    // The tool number last named (a T word, or LOADTL's), which a change puts in the spindle.
    let mut named: Option<String> = None;
    for b in &program.blocks {
        let mut e = BlockEvents::default();
        let (mut before, mut after) = (Vec::new(), Vec::new());
        for ev in &b.events {
            if let Some(w) = word(ev)? {
                if w.tool.is_some() {
                    named = w.tool;
                }
                // A call (T n G17, T n M6) or an M6 of its own changes to the tool named.
                if w.tool_change {
                    e.tool = named.clone();
                }
                e.tool_change |= w.tool_change;
                if w.after { after.push(w.text) } else { before.push(w.text) }
            }
        }
        if source == Dialect::Cl {
            (e.before, e.after) = (before, after);
        } else {
            e.before.extend((!before.is_empty()).then(|| before.join(" ")));
            e.after.extend((!after.is_empty()).then(|| after.join(" ")));
        }
        all.push(e);
    }
    Ok(all)
}

/// Refuse a program [`write_program`] cannot write in `dialect` without changing its motion: a contour
/// tolerance the program set (cycle 32, G64 P) shapes the motion. RS274NGC writes the linear one as
/// LinuxCNC's `G64 P` (read back as the same tolerance); a rotary one (cycle 32's TA) has no RS274NGC
/// form, and the DIN/ISO writer writes none (G62's words are not known here): the program would run
/// under the control's own, so it is refused rather than dropped. Callers check before a long search.
pub fn check_writable(program: &Program, dialect: crate::program::Dialect) -> Result<(), AvoidError> {
    let heid = dialect == crate::program::Dialect::Heidenhain;
    let unwritable = |t: &crate::program::ProgrammedTolerance| if heid { !t.is_unset() } else { t.rotary_rad.is_some() };
    match program.blocks.iter().find(|b| unwritable(&b.tolerance)) {
        Some(b) => {
            let what = if heid { "contour tolerance" } else { "rotary-axis tolerance (cycle 32's TA)" };
            Err(AvoidError::Refused(format!("line {}: the program's {what} cannot be written in {dialect:?}; it would run under the control's own", b.line)))
        }
        None => Ok(()),
    }
}

/// Write a program's planned moves as an NC program in `dialect` (Heidenhain DIN/ISO with M128, or
/// RS274NGC with G43.4), axes in mm and degrees, feeds in mm/min: what a reoriented program is run as.
pub fn write_program(program: &Program, machine: &Machine, dialect: crate::program::Dialect, options: &JobOptions) -> Result<String, AvoidError> {
    use crate::path::SegmentKind;
    use std::fmt::Write as _;
    let heid = dialect == crate::program::Dialect::Heidenhain;
    check_writable(program, dialect)?;
    let traj = Trajectory::from_program(program, machine, &options.path);
    let names = machine.axis_names();
    let name = program.name.clone().unwrap_or_else(|| "FIVEAXIS".into()).replace(' ', "_");
    let mut out = String::new();
    let mut n = 0;
    let mut line = |out: &mut String, text: &str| {
        n += 10;
        if heid {
            let _ = writeln!(out, "N{n} {text} *");
        } else {
            let _ = writeln!(out, "N{n} {text}");
        }
    };
    if heid {
        let _ = writeln!(out, "%{name} G71 *");
    } else {
        // RS274 comments do not nest: no parentheses inside.
        let source = program.source.replace('(', "[").replace(')', "]");
        let _ = writeln!(out, "%\n({name}: written by fiveaxis from {source})");
    }
    line(&mut out, if heid { "G90" } else { "G21 G90 G94" });
    // TCPM on and off: M128/M129 (DIN/ISO); in RS274NGC the machine's own M codes where the user
    // declared them (`--m-code 428=tcp-on`: LinuxCNC's five-axis configurations switch kinematics
    // with a remap), else G43.4/G49.
    let declared = |action: crate::program::MCodeAction| options.read.m_codes.iter().find(|r| r.action == action).map(|r| format!("M{}", r.code));
    // G43.4 takes the tool's length from the H word: the tool in the spindle, where the program says.
    let tcp_switch = |on: bool, tool: Option<&str>| match (heid, on) {
        (true, true) => "M128".to_string(),
        (true, false) => "M129".to_string(),
        (false, true) => declared(crate::program::MCodeAction::TcpOn).unwrap_or_else(|| tool.map_or("G43.4".into(), |t| format!("G43.4 H{t}"))),
        (false, false) => declared(crate::program::MCodeAction::TcpOff).unwrap_or_else(|| "G49".into()),
    };
    let mut tcp = false;
    let mut tolerance: Option<f64> = None;
    let mut datum = Vector3::zeros();
    // CL data starts where its first pose is, not at the machine's home: a post positions the tool
    // there first (a rapid), or the written program would cut its first step from wherever it stands.
    let mut start = start_pose(program, &traj).is_some();
    // Each block's events on lines of their own, before and after its motion; a tool change with
    // TCPM off (the next TCPM move switches it on again, with the new tool's length).
    let events = block_events(program, heid, options)?;
    let tcp_off = tcp_switch(false, None);
    // The tool in the spindle at each block's motion.
    let spindle: Vec<Option<&str>> = events
        .iter()
        .scan(None, |t: &mut Option<&str>, e| {
            if e.tool_change {
                *t = e.tool.as_deref();
            }
            Some(*t)
        })
        .collect();
    let emit = |out: &mut String, line: &mut dyn FnMut(&mut String, &str), tcp: &mut bool, b: usize, before: bool| {
        let e = &events[b];
        if before && e.tool_change && *tcp {
            line(out, &tcp_off);
            *tcp = false;
        }
        for l in if before { &e.before } else { &e.after } {
            line(out, l);
        }
    };
    let mut next_block = 0;
    let mut moving: Option<usize> = None;
    for s in &traj.segments {
        if s.block >= next_block {
            // The block that moved last is done; the blocks up to this one run their events.
            if let Some(b) = moving.take() {
                emit(&mut out, &mut line, &mut tcp, b, false);
            }
            for b in next_block..=s.block {
                emit(&mut out, &mut line, &mut tcp, b, true);
                if b < s.block {
                    emit(&mut out, &mut line, &mut tcp, b, false);
                }
            }
            moving = Some(s.block);
            next_block = s.block + 1;
        }
        // The positioning to the start, then the segment's own move (a dwell writes only its time).
        let start_move = std::mem::take(&mut start).then_some((SegmentKind::Rapid, s.q0, s.tip0));
        let own = (s.kind != SegmentKind::Dwell).then_some((s.kind, s.q1, s.tip1));
        for (kind, q, tip) in start_move.into_iter().chain(own) {
            let want_tcp = program.blocks[s.block].tcp;
            if s.datum != datum && heid {
                datum = s.datum;
                line(&mut out, &format!("G54 X{:+.3} Y{:+.3} Z{:+.3}", datum.x * 1e3, datum.y * 1e3, datum.z * 1e3));
            }
            if want_tcp != tcp {
                tcp = want_tcp;
                line(&mut out, &tcp_switch(tcp, spindle[s.block]));
            }
            let want_tolerance = program.blocks[s.block].tolerance.linear_m;
            if want_tolerance != tolerance {
                tolerance = want_tolerance;
                line(&mut out, &tolerance.map_or("G64".into(), |t| format!("G64 P{:.4}", t * 1e3)));
            }
            let (x, y, z) = if tcp { (tip.x, tip.y, tip.z) } else { (q[0] - s.datum.x, q[1] - s.datum.y, q[2] - s.datum.z) };
            let words = format!(
                "X{:+.4} Y{:+.4} Z{:+.4} {}{:+.4} {}{:+.4}",
                x * 1e3,
                y * 1e3,
                z * 1e3,
                names[3],
                q[3].to_degrees(),
                names[4],
                q[4].to_degrees()
            );
            let feed = program.blocks[s.block].feed.map(|f| f.value_per_min).unwrap_or(0.0);
            match kind {
                SegmentKind::Rapid => line(&mut out, &format!("G00 {words}")),
                _ => line(&mut out, &format!("G01 {words} F{feed:.0}")),
            }
        }
        if s.kind == SegmentKind::Dwell {
            // Heidenhain DIN/ISO: G04 F is the time, s; RS274NGC: G4 P, s.
            line(&mut out, &if heid { format!("G04 F{:.3}", s.duration) } else { format!("G4 P{:.3}", s.duration) });
        }
    }
    if let Some(b) = moving.take() {
        emit(&mut out, &mut line, &mut tcp, b, false);
    }
    for b in next_block..program.blocks.len() {
        emit(&mut out, &mut line, &mut tcp, b, true);
        emit(&mut out, &mut line, &mut tcp, b, false);
    }
    if tcp {
        line(&mut out, &tcp_off);
    }
    line(&mut out, if heid { "M30" } else { "M2" });
    if heid {
        let _ = writeln!(out, "N999999 %{name} G71 *");
    } else {
        out.push_str("%\n");
    }
    Ok(out)
}
