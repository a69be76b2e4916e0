//! Dwells: RS274NGC `G4 P` (s), Sinumerik `G4 F` (s), Heidenhain DIN/ISO `G04 F` (s), Heidenhain
//! conversational `CYCL DEF 9.1 DWELL` (s) and APT `DELAY/` (s). Each dialect's dwell holds every
//! axis still for its time, in the commanded stream and on the simulated machine (which stops
//! before it), and forms it cannot time (spindle revolutions, a missing or negative time) are
//! refused at line:col. The simulated dwell is checked against LinuxCNC's own timing of the same
//! program (recordings/machine/linuxcnc/sing_dwell_trace.csv.gz, made by `make-traces`).

use crate::common;
use fiveaxis::machine::Machine;
use fiveaxis::path::{PathOptions, SegmentKind, Trajectory};
use fiveaxis::planner::{plan_each, PlanConfig};
use fiveaxis::program::{read, Dialect, Program, ReadOptions, Severity};
use std::path::Path;
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("FIVEAXIS_ROOT"))
}

fn program(text: &str, dialect: Dialect) -> Program {
    read(text, dialect, "test", &ReadOptions::default())
}

fn errors(p: &Program) -> Vec<(usize, usize, String)> {
    p.diagnostics.iter().filter(|d| d.severity == Severity::Error).map(|d| (d.line, d.column, d.message.clone())).collect()
}

/// The same cut in each dialect: X0 -> X10 at 600 mm/min, a 2.5 s dwell, X10 -> X20 at the modal
/// feed. Lines starting with `!` are the dwell (left out for the program without it).
const CUTS: [(Dialect, &str); 5] = [
    (Dialect::Rs274, "G21 G90 G94\nG0 X0 Y0 Z10\nG1 X10 F600\n!G4 P2.5\nG1 X20\nM2\n"),
    (Dialect::Sinumerik, "G90 G71\nG0 X0 Y0 Z10\nG1 X10 F600\n!G4 F2.5\nG1 X20\nM30\n"),
    (Dialect::Heidenhain, "%DW G71 *\nN10 G90 *\nN20 G00 X+0 Y+0 Z+10 *\nN30 G01 X+10 F600 *\n!N40 G04 F2.5 *\nN50 G01 X+20 *\nN60 M30 *\nN999999 %DW G71 *\n"),
    (
        Dialect::Klartext,
        "BEGIN PGM DW MM\nL X+0 Y+0 Z+10 FMAX\nL X+10 F600\n!CYCL DEF 9.0 DWELL TIME\n!CYCL DEF 9.1 DWELL 2.5\nL X+20\nEND PGM DW MM\n",
    ),
    (Dialect::Cl, "UNITS/MM\nGOTO/0,0,10,0,0,1\nFEDRAT/600\nGOTO/10,0,10\n!DELAY/2.5\nGOTO/20,0,10\nFINI\n"),
];

fn text(cut: &str, dwell: bool) -> String {
    cut.lines().filter_map(|l| match l.strip_prefix('!') {
        Some(d) => dwell.then_some(d),
        None => Some(l),
    }).map(|l| format!("{l}\n")).collect()
}

#[test]
fn every_dialect_holds_its_dwell_in_the_commanded_stream() {
    let machine = Machine::hermle_c600u();
    let options = PathOptions::default();
    for (dialect, cut) in CUTS {
        let with = program(&text(cut, true), dialect);
        let without = program(&text(cut, false), dialect);
        assert!(with.diagnostics.is_empty() && without.diagnostics.is_empty(), "{dialect:?}: {:#?} {:#?}", with.diagnostics, without.diagnostics);
        let (a, b) = (Trajectory::from_program(&with, &machine, &options), Trajectory::from_program(&without, &machine, &options));
        // The dwell adds its time and nothing else: the same moves at the same feed.
        assert!((a.duration() - b.duration() - 2.5).abs() < 1e-9, "{dialect:?}: {} s with the dwell, {} s without", a.duration(), b.duration());
        let dwells: Vec<_> = a.segments.iter().filter(|s| s.kind == SegmentKind::Dwell).collect();
        assert_eq!(dwells.len(), 1, "{dialect:?}");
        let d = dwells[0];
        assert!((d.duration - 2.5).abs() < 1e-12 && d.q0 == d.q1, "{dialect:?}: {d:?}");
        assert!((d.tip0.x - 0.010).abs() < 1e-12, "{dialect:?}: the dwell is at X10, found {} mm", d.tip0.x * 1e3);
        let moves: Vec<_> = a.segments.iter().filter(|s| s.kind != SegmentKind::Dwell).map(|s| (s.duration, s.feed)).collect();
        let moves_without: Vec<_> = b.segments.iter().map(|s| (s.duration, s.feed)).collect();
        assert_eq!(moves, moves_without, "{dialect:?}: a dwell's F is its time, not a feed");
        // Every commanded sample in the dwell is at X10, still.
        let still = a.samples(&machine).filter(|s| s.t > d.t0 && s.t < d.t0 + d.duration).map(|s| (s.q[0] - 0.010).abs()).fold(0.0f64, f64::max);
        assert!(still < 1e-12, "{dialect:?}: X moves by {still} m during the dwell");
    }
}

#[test]
fn the_simulated_machine_stops_then_dwells() {
    let machine = Machine::hermle_c600u();
    let options = PathOptions::default();
    for (dialect, cut) in CUTS {
        let traj = Trajectory::from_program(&program(&text(cut, true), dialect), &machine, &options);
        let mut x = Vec::new();
        plan_each(&traj.segments, &machine, &PlanConfig::default(), |p| {
            x.push(p.q[0]);
            true
        });
        // The longest stretch at X10 (to 1 nm): the dwell, plus the samples at rest either side.
        let at_ten: Vec<bool> = x.iter().map(|v| (v - 0.010).abs() < 1e-9).collect();
        let longest = at_ten.split(|b| !b).map(<[bool]>::len).max().unwrap_or(0);
        assert!((2500..=2520).contains(&longest), "{dialect:?}: {longest} samples at X10, expected the 2500 of the dwell and a few at rest");
    }
}

#[test]
fn dwells_that_cannot_be_timed_are_refused_where_they_stand() {
    let cases: [(Dialect, &str, usize, usize, &str); 8] = [
        (Dialect::Rs274, "G21 G90\nG1 X1 F100\nG4\n", 3, 1, "without P"),
        (Dialect::Rs274, "G21 G90\nG1 X1 F100\nG4 P-1\n", 3, 4, "0 s or more"),
        (Dialect::Sinumerik, "G90 G71\nG1 X1 F100\nG4 S30\n", 3, 4, "spindle revolutions"),
        // Sinumerik runs G4 only in a block of its own (an alarm otherwise), unlike LinuxCNC.
        (Dialect::Sinumerik, "G90 G71\nG1 X1 F100\nG4 F2 X2\n", 3, 1, "block of its own"),
        (Dialect::Heidenhain, "%DW G71 *\nN10 G01 X+1 F100 *\nN20 G04 *\nN999999 %DW G71 *\n", 3, 5, "without F"),
        (Dialect::Klartext, "BEGIN PGM DW MM\nL X+1 F100\nCYCL DEF 9.1 DWELL\nEND PGM DW MM\n", 3, 1, "CYCL DEF 9.1"),
        // A shop's dwell written without the blank the TNC's editor puts before the cycle's number.
        (Dialect::Klartext, "BEGIN PGM DW MM\nL X+1 F100\nCYCL DEF9.0 VARAKOZASI IDO\nCYCL DEF9.1 V.IDO2\nEND PGM DW MM\n", 3, 6, "blank between CYCL DEF and the cycle's number (CYCL DEF 9.0)"),
        (Dialect::Cl, "GOTO/0,0,10\nFEDRAT/100\nGOTO/1,0,10\nDELAY/10,REV\nGOTO/2,0,10\n", 4, 1, "spindle turns"),
    ];
    for (dialect, text, line, col, why) in cases {
        let p = program(text, dialect);
        let e = errors(&p);
        assert!(e.iter().any(|(l, c, m)| (*l, *c) == (line, col) && m.contains(why)), "{dialect:?} {text:?}: expected an error at {line}:{col} ({why}), got {e:#?}");
    }
    // Through the CLI: exit 2, the place named.
    let dir = common::scratch_root().join("dwell");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("no_time.ngc");
    std::fs::write(&path, "G21 G90\nG1 X1 F100\nG4\nM2\n").unwrap();
    let out = Command::new(env!("FIVEAXIS_EXE")).args(["program", "analyze"]).arg(&path).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let all = format!("{}{err}", String::from_utf8_lossy(&out.stdout));
    assert_eq!(out.status.code(), Some(2), "{all}");
    assert!(all.contains("3:1") && all.contains("without P"), "{all}");
}

/// A dwell that would run the program past its bound on duration stops planning there, named.
#[test]
fn a_dwell_beyond_the_duration_bound_is_an_error() {
    let machine = Machine::hermle_c600u();
    let p = program("G21 G90\nG1 X1 F100\nG4 P100000.0\nG1 X2\nM2\n", Dialect::Rs274);
    let options = PathOptions { max_duration_s: 3600.0, ..PathOptions::default() };
    let (segments, diags) = fiveaxis::path::plan(&p, &machine, &options);
    assert!(segments.iter().all(|s| s.kind != SegmentKind::Dwell), "{segments:#?}");
    assert!(diags.iter().any(|d| d.line == 3 && d.severity == Severity::Error && d.message.contains("dwell")), "{diags:#?}");
}

/// The paper's SING cut with a 2.5 s dwell at X19 (N305), simulated, against LinuxCNC running its
/// RS274NGC translation (G4 P2.5): the machine stands still as long on both, and the whole cut
/// takes as much longer as it does on LinuxCNC, whose trace is read here by Python (gzip, csv).
#[test]
fn a_dwell_is_timed_as_linuxcnc_times_it() {
    let machine = Machine::hermle_c600u();
    let options = PathOptions::default();
    let dir = root().join("recordings/machine/linuxcnc");
    let mut ours = Vec::new();
    for name in ["SING_DWELL.I", "SING_DWELL.ngc", "SING.ngc"] {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        let dialect = if name.ends_with(".I") { Dialect::Heidenhain } else { Dialect::Rs274 };
        let opts = if dialect == Dialect::Rs274 { ReadOptions { m_codes: vec!["428=tcp-on".parse().unwrap(), "429=tcp-off".parse().unwrap()], ..ReadOptions::default() } } else { ReadOptions::default() };
        let p = read(&text, dialect, name, &opts);
        assert!(errors(&p).is_empty(), "{name}: {:#?}", p.diagnostics);
        let traj = Trajectory::from_program(&p, &machine, &options);
        let mut q = Vec::new();
        plan_each(&traj.segments, &machine, &PlanConfig::default(), |s| {
            q.push(s.q);
            true
        });
        ours.push((name, still_s(&q, 1e-3), q.len() as f64 * 1e-3));
    }
    let py = r#"
import csv, gzip, sys
rows = list(csv.DictReader(gzip.open(sys.argv[1], "rt")))
q = [[float(r[k]) for k in ("x_mm", "y_mm", "z_mm", "a_deg", "c_deg")] for r in rows]
line = [int(r["program_line"]) for r in rows]
g4 = next(i + 1 for i, l in enumerate(open(sys.argv[2])) if " G4 P" in l)
# The longest run of samples whose every axis moves under 1e-6 mm (deg) per ms: during it the
# trace's program line is 0 (LinuxCNC's dwell carries none); the motion before it is the line before
# the G4, the motion after it the line after.
best, run, end = 0, 0, 0
for i in range(1, len(q)):
    if max(abs(a - b) for a, b in zip(q[i], q[i - 1])) < 1e-6:
        run += 1
        if run > best:
            best, end = run, i
    else:
        run = 0
before = next(l for l in reversed(line[: end - best]) if l)
after = next(l for l in line[end + 1 :] if l)
assert (before, after) == (g4 - 1, g4 + 1), (before, after, g4)
sing = sum(1 for _ in gzip.open(sys.argv[3], "rt")) - 1
print(best * 1e-3, len(q) * 1e-3, sing * 1e-3)
"#;
    let out = Command::new("python3").args(["-c", py]).arg(dir.join("sing_dwell_trace.csv.gz")).arg(dir.join("SING_DWELL.ngc")).arg(dir.join("sing_trace.csv.gz")).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: Vec<f64> = String::from_utf8_lossy(&out.stdout).split_whitespace().map(|s| s.parse().unwrap()).collect();
    let (linuxcnc_still, linuxcnc_added) = (v[0], v[1] - v[2]);
    eprintln!("LinuxCNC: still {linuxcnc_still} s, the dwell adds {linuxcnc_added} s; ours (name, still s, cycle s): {ours:?}");
    assert!(linuxcnc_still > 2.4, "LinuxCNC's trace holds still {linuxcnc_still} s at the G4 line");
    for (name, still, _) in &ours[..2] {
        assert!((still - linuxcnc_still).abs() < 0.05, "{name}: still for {still} s, LinuxCNC {linuxcnc_still} s");
    }
    // The stop the dwell asks for costs the simulated machine the jerk filter's width more than it
    // costs LinuxCNC 2.9, whose planner limits acceleration only (a trapezoid): a moving average of
    // width T delays the braking by T/2 and the start by T/2.
    let window = machine.limits().iter().map(|l| 2.0 * l.acceleration / l.jerk).fold(0.0, f64::max);
    let added = ours[1].2 - ours[2].2;
    assert!(
        (added - window - linuxcnc_added).abs() < 0.05,
        "the dwell adds {added} s to the simulated cut (jerk filter {window} s), {linuxcnc_added} s on LinuxCNC"
    );
}

/// The longest stretch over which no axis moves more than 1e-6 mm (deg) per period, s.
fn still_s(q: &[[f64; 5]], period: f64) -> f64 {
    let (mut best, mut run) = (0usize, 0usize);
    for w in q.windows(2) {
        let step = (0..5).map(|i| if i < 3 { (w[1][i] - w[0][i]).abs() * 1e3 } else { (w[1][i] - w[0][i]).abs().to_degrees() }).fold(0.0f64, f64::max);
        if step < 1e-6 {
            run += 1;
            best = best.max(run);
        } else {
            run = 0;
        }
    }
    best as f64 * period
}
