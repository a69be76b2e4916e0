//! NC reader throughput on one core (issue 11 target: >= 1 M blocks/s): a one-million-block
//! five-axis program in each dialect, written here (the long-program bench's wavy surface, a pose
//! every 0.1 mm, tool axis on the surface normal). Prints blocks/s and MB/s per dialect, best of
//! five reads, read two ways: whole, as the remedies and the bundled programs are (`program::read`,
//! every block held: 1 M blocks of the size printed, and the page faults of that memory), and
//! streamed, as `program analyze`, `run` and the nodes read a file (`BlockStream`, each block dropped
//! once handed out: memory flat in the program's length).
//!
//! usage: cargo bench --bench readers [-- BLOCKS] [DIALECT]     (default 1000000, every dialect;
//! DIALECT one of rs274 heidenhain sinumerik klartext fanuc haas cl apt, or a loop: rs274loop
//! fanucloop sinumerikloop klartextloop make a quarter of BLOCKS moves in a loop of the dialect's
//! parameter language, each computed from expressions, and print the blocks they run per second;
//! corpus: only the real programs below; corpus:TEXT those whose file name holds TEXT, to profile one)
//!
//! Then the real programs of `../shared/outside/programs` that read with no defect (issue 64's
//! corpus, tests/corpus/cases.rs), each streamed from its file on its built-in machine as `program
//! analyze` reads it: lines per second per program and per dialect, against the same target. Their
//! lines are 15-65 bytes where the written programs' blocks above are 59-117 (Klartext's LN blocks
//! the longest), so these rows say what shops' programs cost. Skipped where `../shared` is not
//! beside the clone.

use clap::Parser;
use fiveaxis::program::{read, BlockStream, Dialect, ProgramFile, ReadOptions};
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;
use std::time::Instant;

#[path = "../tests/corpus/cases.rs"]
mod corpus_cases;

/// Pose k of the raster: tip (mm), unit tool axis, and its A/C angles (deg) on the Hermle (seed 001
/// eq. 2: O_W = (sin C sin A, cos C sin A, cos A)).
fn pose(k: usize) -> ([f64; 3], [f64; 3], [f64; 2]) {
    let (per_line, step) = (1000usize, 0.1);
    let (row, i) = (k / (per_line + 1), k % (per_line + 1));
    let u = if row % 2 == 0 { i as f64 * step } else { 100.0 - i as f64 * step };
    let (x, y) = (u - 50.0, (row % 200) as f64 * 0.5 - 50.0);
    let (a, l1, l2) = (8.0, 12.0, 17.0);
    let z = a * (x / l1).sin() * (y / l2).cos() - 10.0;
    let n = [-(a / l1) * (x / l1).cos() * (y / l2).cos(), (a / l2) * (x / l1).sin() * (y / l2).sin(), 1.0];
    let norm = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let o = n.map(|c| c / norm);
    let (aa, cc) = (o[2].acos().to_degrees(), o[0].atan2(o[1]).to_degrees());
    ([x, y, z], o, [aa, cc])
}

/// A program making `moves` moves in a loop of its dialect's parameter language: each pass
/// evaluates its X Y Z and orientation from the loop counter (a wavy raster as above, in
/// expressions), so a parameter program's cost per block run can be set beside a written one's
/// (issue 64: "parameter programs cost no more than their blocks"). The program and the blocks
/// (lines) it runs in all: the loop's lines on every pass, its setup once.
fn loop_program(dialect: Dialect, moves: usize) -> (String, usize) {
    match dialect {
        // LinuxCNC O-words (manual, "O Codes"): the test, the move, the count, the loop's end.
        Dialect::Rs274 => (
            format!(
                "G21 G90 G94\nG1 F2000\n#<k> = 0\no1 while [#<k> LT {moves}]\n\
                 G1 X[[#<k> MOD 1001] * 0.1 - 50] Y[[FIX[#<k> / 1001] MOD 200] * 0.5 - 50] Z[8 * SIN[[#<k> MOD 1001] * 0.48] - 10] A[10 + 5 * COS[#<k> * 0.01]] C[#<k> * 0.02]\n\
                 #<k> = [#<k> + 1]\no1 endwhile\nM2\n"
            ),
            4 * moves + 5,
        ),
        // Fanuc custom macro B (B-64484EN, "Custom macro"): WHILE [..] DO1 ... END1 under G43.4.
        Dialect::Fanuc => (
            format!(
                "%\nO1000\nG21 G90 G94\nG43.4 H1\nG1 F2000.\n#100 = 0\nWHILE [#100 LT {moves}] DO1\n\
                 G1 X[[#100 MOD 1001] * 0.1 - 50] Y[[FIX[#100 / 1001] MOD 200] * 0.5 - 50] Z[8 * SIN[[#100 MOD 1001] * 0.48] - 10] A[10 + 5 * COS[#100 * 0.01]] C[#100 * 0.02]\n\
                 #100 = #100 + 1\nEND1\nM30\n%\n"
            ),
            4 * moves + 7,
        ),
        // Sinumerik 840D (Job Planning, "Program loop with alternative WHILE"): the tool axis as a
        // vector (A3 B3 C3) under TRAORI, CNT a user variable (a single letter is an address).
        Dialect::Sinumerik => (
            format!(
                "DEF INT CNT\nG71 G90 G94\nTRAORI\nG1 F2000\nCNT=0\nWHILE CNT<{moves}\n\
                 G1 X=(CNT MOD 1001)*0.1-50 Y=((CNT DIV 1001) MOD 200)*0.5-50 Z=8*SIN((CNT MOD 1001)*0.48)-10 A3=SIN(10+5*COS(CNT*0.01))*SIN(CNT*0.02) B3=SIN(10+5*COS(CNT*0.01))*COS(CNT*0.02) C3=COS(10+5*COS(CNT*0.01))\n\
                 CNT=CNT+1\nENDWHILE\nM30\n"
            ),
            4 * moves + 7,
        ),
        // Heidenhain Klartext (TNC 320 §9.9 formulas, FN 12 jump to a label): the Q parameters of a
        // move, the move, the count and the jump back.
        Dialect::Klartext => (
            format!(
                "0 BEGIN PGM LOOP MM\n1 L M128\n2 L F2000\n3 Q1 = 0\n4 LBL 1\n\
                 5 Q10 = (Q1 % 1001) * 0.1 - 50\n6 Q11 = (INT (Q1 / 1001) % 200) * 0.5 - 50\n\
                 7 Q12 = 8 * SIN ((Q1 % 1001) * 0.48) - 10\n8 Q13 = 10 + 5 * COS (Q1 * 0.01)\n9 Q14 = Q1 * 0.02\n\
                 10 L X+Q10 Y+Q11 Z+Q12 A+Q13 C+Q14\n11 Q1 = Q1 + 1\n12 FN 12: IF +Q1 LT +{moves} GOTO LBL 1\n13 END PGM LOOP MM\n"
            ),
            9 * moves + 6,
        ),
        _ => unreachable!("no loop for {dialect:?}"),
    }
}

/// The program in `dialect` (APT CL data: `apt` with [`Dialect::Cl`]).
fn program(dialect: Dialect, apt: bool, blocks: usize) -> String {
    let mut s = String::with_capacity(blocks * 80);
    let body = |s: &mut String, k: usize| {
        let (p, o, r) = pose(k);
        let n = 10 * (k + 1);
        let _ = match dialect {
            Dialect::Cl if apt => writeln!(s, "GOTO/{:.4},{:.4},{:.4},{:.7},{:.7},{:.7}", p[0], p[1], p[2], o[0], o[1], o[2]),
            Dialect::Rs274 | Dialect::Fanuc | Dialect::Haas => writeln!(s, "N{n} G1 X{:.4} Y{:.4} Z{:.4} A{:.4} C{:.4}", p[0], p[1], p[2], r[0], r[1]),
            Dialect::Heidenhain => writeln!(s, "N{n} G01 X{:+.4} Y{:+.4} Z{:+.4} A{:+.4} C{:+.4} *", p[0], p[1], p[2], r[0], r[1]),
            Dialect::Sinumerik => writeln!(s, "N{n} G1 X{:.4} Y{:.4} Z{:.4} A3={:.7} B3={:.7} C3={:.7}", p[0], p[1], p[2], o[0], o[1], o[2]),
            Dialect::Klartext => writeln!(s, "{} LN X{:+.4} Y{:+.4} Z{:+.4} NX{:+.7} NY{:+.7} NZ{:+.7} TX{:+.7} TY{:+.7} TZ{:+.7}", k + 3, p[0], p[1], p[2], o[0], o[1], o[2], o[0], o[1], o[2]),
            Dialect::Cl => writeln!(s, "{:.4} {:.4} {:.4} {:.7} {:.7} {:.7} 2000", p[0], p[1], p[2], o[0], o[1], o[2]),
        };
    };
    match dialect {
        Dialect::Rs274 => s.push_str("G21 G90 G94\nG1 F2000\n"),
        Dialect::Heidenhain => s.push_str("%LONG G71 *\nN1 M128 *\nN2 G01 F2000 *\n"),
        Dialect::Sinumerik => s.push_str("G71 G90 G94\nTRAORI\nG1 F2000\n"),
        Dialect::Klartext => s.push_str("0 BEGIN PGM LONG MM\n1 L M128\n2 L F2000\n"),
        // Fanuc's and Haas' tool-centre point (G43.4, G234) with the length register H1.
        Dialect::Fanuc => s.push_str("%\nO1000\nG21 G90 G94\nG43.4 H1\nG1 F2000.\n"),
        Dialect::Haas => s.push_str("%\nO1000\nG21 G90 G94\nG234 H1\nG1 F2000.\n"),
        Dialect::Cl if apt => s.push_str("PARTNO/LONG\nUNITS/MM\nMULTAX\nFEDRAT/2000,MMPM\n"),
        Dialect::Cl => {}
    }
    for k in 0..blocks {
        body(&mut s, k);
    }
    match dialect {
        Dialect::Heidenhain => s.push_str("N999999999 %LONG G71 *\n"),
        Dialect::Klartext => {
            let _ = writeln!(s, "{} END PGM LONG MM", blocks + 3);
        }
        Dialect::Fanuc | Dialect::Haas => s.push_str("M30\n%\n"),
        Dialect::Cl if apt => s.push_str("FINI\n"),
        _ => {}
    }
    s
}

/// Reads timed per program and form, the best one printed: this machine's neighbours take a share
/// of it now and then, which only the best of several reads leaves out.
const ROUNDS: usize = 5;

fn main() {
    let blocks: usize = std::env::args().skip(1).find_map(|a| a.parse().ok()).unwrap_or(1_000_000);
    let only = std::env::args().skip(1).find(|a| a.parse::<usize>().is_err() && !a.starts_with('-'));
    // `corpus`, or `corpus:TEXT` for the real programs whose name holds TEXT.
    let corpus = only.as_ref().and_then(|o| if o.eq_ignore_ascii_case("corpus") { Some("") } else { o.get(..7).filter(|p| p.eq_ignore_ascii_case("corpus:")).map(|_| &o[7..]) });
    if let Some(named) = corpus {
        real_programs(named);
        return;
    }
    println!("reading a {blocks}-block five-axis program, one core, best of {ROUNDS} (target >= 1 M blocks/s)");
    println!("bytes a block holds in memory: {}", std::mem::size_of::<fiveaxis::program::Block>());
    let forms = [
        ("Rs274", Dialect::Rs274, false),
        ("Heidenhain", Dialect::Heidenhain, false),
        ("Sinumerik", Dialect::Sinumerik, false),
        ("Klartext", Dialect::Klartext, false),
        ("Fanuc", Dialect::Fanuc, false),
        ("Haas", Dialect::Haas, false),
        ("Cl", Dialect::Cl, false),
        ("Apt", Dialect::Cl, true),
    ];
    // Parameter programs: the blocks they run per second against the same target, and the moves.
    let loops = [("Rs274Loop", Dialect::Rs274), ("FanucLoop", Dialect::Fanuc), ("SinumerikLoop", Dialect::Sinumerik), ("KlartextLoop", Dialect::Klartext)];
    let wanted = |name: &str| only.as_ref().is_none_or(|o| name.eq_ignore_ascii_case(o));
    // Every program first, then each read in turn ROUNDS times over (the best of each kept): a slow
    // spell of this machine's neighbours falls on some rounds of every program, not all of one.
    let mut written: Vec<Bench> = forms.iter().filter(|f| wanted(f.0)).map(|&(name, dialect, apt)| Bench::new(name, program(dialect, apt, blocks), dialect, blocks)).collect();
    // A quarter of BLOCKS moves: within the default budget of lines loops may run (4 M).
    let moves = blocks / 4;
    let mut looped: Vec<Bench> = loops
        .iter()
        .filter(|l| wanted(l.0))
        .map(|&(name, dialect)| {
            let (text, run) = loop_program(dialect, moves);
            Bench { run, ..Bench::new(name, text, dialect, moves) }
        })
        .collect();
    for _ in 0..ROUNDS {
        for b in &mut written {
            b.read();
            b.stream();
        }
        for b in &mut looped {
            b.read();
        }
    }
    if !written.is_empty() {
        println!("{:<12} {:>8} {:>14} {:>8} {:>8} {:>16} {:>8}", "dialect", "MB", "M blocks/s", "MB/s", "target", "streamed M b/s", "target");
    }
    for b in &written {
        let (rate, srate) = (blocks as f64 / b.best / 1e6, blocks as f64 / b.best_streamed / 1e6);
        let mb = b.text.len() as f64 / 1e6;
        println!("{:<12} {:>8.1} {:>14.2} {:>8.0} {:>8} {:>16.2} {:>8}", b.name, mb, rate, mb / b.best, mark(rate), srate, mark(srate));
    }
    if !looped.is_empty() {
        println!("{:<14} {:>8} {:>16} {:>12} {:>8}", "loop", "moves", "M blocks run/s", "M moves/s", "target");
    }
    for b in &looped {
        let rate = b.run as f64 / b.best / 1e6;
        println!("{:<14} {:>8} {:>16.2} {:>12.2} {:>8}", b.name, moves, rate, moves as f64 / b.best / 1e6, mark(rate));
    }
    if only.is_none() {
        real_programs("");
    }
}

/// The corpus programs that read clean, each streamed from its file on its built-in machine (the
/// flags its file cannot say given as `program analyze` takes them): lines per second per program,
/// then per dialect (all its programs' lines over their summed times). A line is a block written; a
/// program whose loops make more blocks than it has lines (LinuxCNC's bridge mill) is counted by
/// its blocks. The programs are read in turn, [`PASSES`] times over, each program's best read
/// kept: a slow spell of this machine's neighbours (they took a third off one program's rate for
/// seconds at a time) then falls on some passes of every program rather than on all of one.
fn real_programs(named: &str) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/outside/programs");
    if !dir.is_dir() {
        println!("real programs: {} not found, skipped", dir.display());
        return;
    }
    struct Timed {
        name: String,
        path: std::path::PathBuf,
        options: ReadOptions,
        bytes: usize,
        file_lines: usize,
        blocks: usize,
        dialect: String,
        best: f64,
    }
    let mut programs: Vec<Timed> = corpus_cases::CLEAN
        .iter()
        .filter(|case| case.file.contains(named))
        .map(|case| {
            let path = dir.join(case.file);
            let machine = fiveaxis::machine::Machine::builtin(case.machine).unwrap_or_else(|e| panic!("{}: {e}", case.machine));
            // The flags as `program analyze` parses them.
            let flags = Flags::try_parse_from(std::iter::once("bench").chain(case.args.iter().copied())).unwrap_or_else(|e| panic!("{}: {e}", case.file));
            let options = flags.control.read_options();
            let text = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let file_lines = text.iter().filter(|&&b| b == b'\n').count().max(1);
            Timed { name: case.file.to_string(), path, options: options.on(&machine), bytes: text.len(), file_lines, blocks: 0, dialect: String::new(), best: f64::INFINITY }
        })
        .collect();
    println!("real programs ({}), streamed on their machines, read in turn {PASSES} times, the best of each", dir.display());
    for _ in 0..PASSES {
        for p in &mut programs {
            // A small program is read again for 20 ms: its read takes well under one.
            let started = Instant::now();
            while p.best.is_infinite() || started.elapsed().as_secs_f64() < 0.02 {
                let t = Instant::now();
                let mut stream = ProgramFile::Path(p.path.clone()).open(None, &p.options).unwrap_or_else(|e| panic!("{}: {e}", p.name));
                let blocks = stream.by_ref().count();
                p.best = p.best.min(t.elapsed().as_secs_f64());
                assert_eq!(stream.diagnostics().errors(), 0, "{}: read with errors", p.name);
                assert!(blocks > 0, "{}: no blocks", p.name);
                (p.blocks, p.dialect) = (blocks, format!("{:?}", stream.dialect()));
            }
        }
    }
    println!("{:<44} {:<10} {:>8} {:>8} {:>12} {:>8} {:>8}", "program", "dialect", "lines", "B/line", "M lines/s", "MB/s", "target");
    println!("{:<44} {:<10} {:>8}", "", "", "(or blocks made)");
    let mut dialects: BTreeMap<&str, (usize, usize, f64, usize)> = BTreeMap::new();
    for p in &programs {
        let lines = p.file_lines.max(p.blocks);
        let rate = lines as f64 / p.best / 1e6;
        let name: String = p.name.chars().take(44).collect();
        println!("{:<44} {:<10} {:>8} {:>8.1} {:>12.2} {:>8.0} {:>8}", name, p.dialect, lines, p.bytes as f64 / p.file_lines as f64, rate, p.bytes as f64 / p.best / 1e6, mark(rate));
        let d = dialects.entry(&p.dialect).or_default();
        *d = (d.0 + lines, d.1 + p.bytes, d.2 + p.best, d.3 + p.file_lines);
    }
    println!("{:<10} {:>8} {:>8} {:>12} {:>8} {:>8}", "dialect", "lines", "B/line", "M lines/s", "MB/s", "target");
    for (dialect, (lines, bytes, s, file_lines)) in dialects {
        let rate = lines as f64 / s / 1e6;
        println!("{:<10} {:>8} {:>8.1} {:>12.2} {:>8.0} {:>8}", dialect, lines, bytes as f64 / file_lines as f64, rate, bytes as f64 / s / 1e6, mark(rate));
    }
}

/// The control's flags a corpus program is read with (`--units`, `--cl-angles` ...).
#[derive(clap::Parser)]
struct Flags {
    #[command(flatten)]
    control: fiveaxis::program::ControlArgs,
}

/// "met" where `rate` (M blocks or lines a second) reaches the 1 M target.
fn mark(rate: f64) -> &'static str {
    if rate >= 1.0 { "met" } else { "MISSED" }
}

/// How many times the real programs are read in turn.
const PASSES: usize = 10;

/// A written program and its best read times so far (s).
struct Bench {
    name: &'static str,
    text: String,
    dialect: Dialect,
    /// The blocks (or moves, for a loop) a read must make at least.
    least: usize,
    /// Blocks a loop runs in all (its lines on every pass).
    run: usize,
    /// Blocks the whole read made: the stream must hand out as many.
    blocks: usize,
    best: f64,
    best_streamed: f64,
}

impl Bench {
    fn new(name: &'static str, text: String, dialect: Dialect, least: usize) -> Bench {
        Bench { name, text, dialect, least, run: 0, blocks: 0, best: f64::INFINITY, best_streamed: f64::INFINITY }
    }

    /// One whole read, timed; a read with an error, or with fewer blocks than written, stops the bench.
    fn read(&mut self) {
        let t = Instant::now();
        let p = read(&self.text, self.dialect, "bench", &ReadOptions::default());
        self.best = self.best.min(t.elapsed().as_secs_f64());
        assert!(!p.has_errors(), "{}: {:?}", self.name, &p.diagnostics[..p.diagnostics.len().min(3)]);
        assert!(p.blocks.len() >= self.least, "{}: {} blocks read of {}", self.name, p.blocks.len(), self.least);
        self.blocks = p.blocks.len();
    }

    /// One streamed read, timed, each block taken and dropped as `program analyze` takes them; it
    /// must hand out the blocks the whole read made, with no error.
    fn stream(&mut self) {
        let t = Instant::now();
        let mut stream = BlockStream::from_text(&self.text, Some(self.dialect), "bench", &ReadOptions::default());
        let n = stream.by_ref().count();
        self.best_streamed = self.best_streamed.min(t.elapsed().as_secs_f64());
        assert_eq!(stream.diagnostics().errors(), 0, "{}: streamed with errors", self.name);
        assert_eq!(n, self.blocks, "{}: {n} blocks streamed, {} read whole", self.name, self.blocks);
    }
}
