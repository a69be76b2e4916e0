//! Programs read and analysed as streams (`fiveaxis program analyze`): the same blocks, diagnostics
//! and report as the program read whole, in memory that does not grow with the program.

use crate::common;
use fiveaxis::job::{self, JobOptions};
use fiveaxis::machine::Machine;
use fiveaxis::program::{self, BlockStream, Dialect, MCodeAction, MCodeRule, ReadOptions, MAX_LINE_BYTES};
use proptest::prelude::*;
use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> &'static str {
    env!("FIVEAXIS_EXE")
}

fn tmp(name: &str) -> PathBuf {
    common::scratch_path("stream", name)
}

/// LinuxCNC's vismach demos switch TCP with M428/M429.
fn linuxcnc() -> ReadOptions {
    ReadOptions {
        m_codes: vec![MCodeRule { code: 428, action: MCodeAction::TcpOn }, MCodeRule { code: 429, action: MCodeAction::TcpOff }],
        ..Default::default()
    }
}

/// Every program of the repository (the impeller unpacked), with the reader options it needs.
fn corpus() -> Vec<(PathBuf, ReadOptions)> {
    let root = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs");
    let mut out = Vec::new();
    for dir in ["", "damaged", "twins", "linuxcnc"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            if path.is_dir() || name.ends_with(".md") || name == "make-twins" {
                continue;
            }
            let options = if dir == "linuxcnc" { linuxcnc() } else { ReadOptions::default() };
            if name.ends_with(".gz") {
                let mut text = Vec::new();
                let gz = Command::new("gzip").arg("-dc").arg(&path).output().expect("gzip runs");
                text.extend(gz.stdout);
                let unpacked = tmp(name.trim_end_matches(".gz"));
                std::fs::write(&unpacked, text).unwrap();
                out.push((unpacked, options));
            } else {
                out.push((path, options));
            }
        }
    }
    assert!(out.len() >= 12, "{out:?}");
    out
}

#[test]
fn a_streamed_program_is_the_program_read_whole() {
    for (path, options) in corpus() {
        let whole = program::load(&path, None, &options).unwrap();
        let mut stream = fiveaxis::program::open(&path, None, &options).unwrap();
        let blocks: Vec<_> = stream.by_ref().collect();
        assert_eq!(stream.dialect(), whole.dialect, "{}", path.display());
        assert_eq!(stream.name(), whole.name.as_deref(), "{}", path.display());
        let diagnostics = stream.diagnostics().to_vec();
        // A damaged copy whose block numbers go backwards is put back in number order only when
        // read whole (a stream cannot reorder): the same blocks, and every diagnostic but the note
        // on the order.
        let note = |m: &str| m.contains("block-number order") || m.contains("kept in file order");
        let mut streamed = blocks.clone();
        if whole.diagnostics.iter().any(|d| d.message.contains("put back in block-number order")) {
            streamed.sort_by_key(|b| b.number);
        }
        assert_eq!(streamed, whole.blocks, "{}", path.display());
        let (a, b): (Vec<_>, Vec<_>) = (diagnostics.iter().filter(|d| !note(&d.message)).collect(), whole.diagnostics.iter().filter(|d| !note(&d.message)).collect());
        assert_eq!(a, b, "{}", path.display());
        assert_eq!(diagnostics.len(), whole.diagnostics.len(), "{}", path.display());
        assert_eq!(stream.blocks_read(), whole.blocks.len());
    }
}

#[test]
fn program_analyze_as_a_stream_reports_what_the_whole_analysis_does() {
    let m = Machine::hermle_c600u();
    let mut specs: Vec<(String, ReadOptions)> = vec![("bundled:SING.I".into(), ReadOptions::default()), ("bundled:NON_SING.I".into(), ReadOptions::default())];
    specs.extend(corpus().into_iter().filter(|(p, _)| !p.to_string_lossy().contains("xyzbc")).map(|(p, o)| (p.display().to_string(), o)));
    for (spec, read) in specs {
        let options = JobOptions { read, ..Default::default() };
        let whole = job::run(&spec, &m, &options).unwrap().report;
        if whole.diagnostics.iter().any(|d| d.message.contains("put back in block-number order")) {
            continue; // a damaged copy only reading whole puts back in order (see above)
        }
        let streamed = job::analyze_streaming(&spec, &m, &options).unwrap();
        assert_eq!(serde_json::to_value(&whole).unwrap(), serde_json::to_value(&streamed).unwrap(), "{spec}");
    }
    // The paper's figures through the stream (seed 001: 175 rpm at x 25 mm on SING.I's blocks).
    let r = job::analyze_streaming("bundled:SING.I", &m, &JobOptions::default()).unwrap();
    assert!((r.peak_c_speed_rpm - 175.0).abs() < 0.1 && (r.peak_c_speed_x_mm - 25.0).abs() < 0.1, "{} rpm at {} mm", r.peak_c_speed_rpm, r.peak_c_speed_x_mm);
}

/// The `--json` report of `fiveaxis ARGS` with stdin from `input`, its program's name (the keys
/// `program` and `file`, wherever they stand) replaced, and the exit code.
fn report_unnamed(args: &[&str], input: Option<&Path>) -> (i32, serde_json::Value) {
    fn unname(v: &mut serde_json::Value) {
        match v {
            serde_json::Value::Object(m) => {
                for (k, x) in m.iter_mut() {
                    if k == "program" || k == "file" {
                        *x = serde_json::Value::Null;
                    } else {
                        unname(x);
                    }
                }
            }
            serde_json::Value::Array(a) => a.iter_mut().for_each(unname),
            _ => {}
        }
    }
    let mut cmd = Command::new(bin());
    cmd.args(args).arg("--json");
    if let Some(input) = input {
        cmd.stdin(std::fs::File::open(input).unwrap());
    }
    let out = cmd.output().unwrap();
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"), "{args:?}");
    let mut v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{args:?}: {e}: {}", String::from_utf8_lossy(&out.stderr)));
    unname(&mut v);
    (out.status.code().unwrap_or(-1), v)
}

/// A program from a pipe reads as its file: every part of a run reads the program from its start
/// for itself (the commander, the planner and its scout, the check), so a FIFO (`<(zcat P.gz)`) or
/// standard input (`-`) is held in a temporary file (before, the first reader emptied the pipe and
/// the others read "no moves"). Every program of the repository through a FIFO of the same name
/// (`program analyze`), and three through standard input (`run`, dialect from the content: the
/// LinuxCNC program opens with six-word `;` comments, which once read as CL data), report what their
/// files do, name aside.
#[test]
fn a_program_from_a_pipe_or_standard_input_reads_as_its_file() {
    let dir = common::scratch_dir("stream-fifo");
    let m_codes = ["--m-code", "428=tcp-on", "--m-code", "429=tcp-off"];
    for (path, options) in corpus().into_iter().filter(|(p, _)| !p.to_string_lossy().contains("xyzbc")) {
        let fifo = dir.join(path.file_name().unwrap());
        assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        let mut writer = Command::new("sh").arg("-c").arg(format!("cat '{}' > '{}'", path.display(), fifo.display())).spawn().unwrap();
        let flags: &[&str] = if options.m_codes.is_empty() { &[] } else { &m_codes };
        let (file, fifo_args) = (path.to_str().unwrap(), fifo.to_str().unwrap());
        let piped = report_unnamed(&[&["program", "analyze", fifo_args], flags].concat(), None);
        let _ = writer.kill();
        let _ = writer.wait();
        let read = report_unnamed(&[&["program", "analyze", file], flags].concat(), None);
        assert!(read.1["blocks"].as_u64().unwrap() > 10, "{file}: {}", read.1);
        assert_eq!(piped, read, "{file} through a FIFO");
    }
    let root = Path::new(env!("FIVEAXIS_ROOT"));
    let stdin_cases: [(&str, &[&str]); 3] = [
        ("recordings/machine/linuxcnc/SING.ngc", &m_codes),
        ("recordings/programs/twins/SING_840d.mpf", &[]),
        ("recordings/programs/SING.I", &[]),
    ];
    for (file, flags) in stdin_cases {
        let path = root.join(file);
        let piped = report_unnamed(&[&["run", "-"], flags].concat(), Some(&path));
        let read = report_unnamed(&[&["run", path.to_str().unwrap()], flags].concat(), None);
        assert_eq!(read.0, 0, "{file}: {}", read.1);
        assert!(read.1["simulated"]["samples"].as_u64().unwrap() > 20_000, "{file}: {}", read.1);
        assert_eq!(piped, read, "{file} on standard input");
    }
}

/// A compressed program reads as its text: LinuxCNC's impeller demo as the repository keeps it
/// (`.ngc.gz`, made by gzip) and in zstd (libzstd's encoder), known by their first bytes and read
/// as their inner name's dialect; a truncated one is refused naming it (exit 2), never read short.
#[test]
fn a_compressed_program_reads_as_its_text() {
    let gz = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/impeller-7bl-xyzac.ngc.gz");
    let bytes = std::fs::read(&gz).unwrap();
    let text = Command::new("gzip").arg("-dc").arg(&gz).output().expect("gzip runs").stdout;
    let plain = tmp("impeller.ngc");
    std::fs::write(&plain, &text).unwrap();
    let zst = tmp("impeller.ngc.zst");
    std::fs::write(&zst, zstd::encode_all(&text[..], 3).unwrap()).unwrap();
    let truncated = tmp("impeller-truncated.ngc.gz");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    let flags = ["--m-code", "428=tcp-on", "--m-code", "429=tcp-off"];
    fn args<'a>(p: &'a Path, flags: &[&'a str]) -> Vec<&'a str> {
        [&["program", "analyze", p.to_str().unwrap()][..], flags].concat()
    }
    let read = report_unnamed(&args(&plain, &flags), None);
    assert_eq!(read.0, 0, "{}", read.1);
    assert_eq!(read.1["blocks"].as_u64(), Some(4498), "the impeller's 4,498 blocks (issue 13)");
    for compressed in [&gz, &zst] {
        assert_eq!(report_unnamed(&args(compressed, &flags), None), read, "{}", compressed.display());
    }
    let out = Command::new(bin()).args(args(&truncated, &flags)).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("impeller-truncated.ngc.gz") && !err.contains("panicked"), "{err}");
}

#[test]
fn line_endings_bad_bytes_and_overlong_lines_stream_as_they_read() {
    let mut text = b"G21 G90\r\nG1 X1 F100\r\nG1 X2 (caf\xc3\xa9 \xff)\nG1 X3".to_vec();
    let whole = program::read(&String::from_utf8_lossy(&text), Dialect::Rs274, "t", &ReadOptions::default());
    let path = tmp("endings.ngc");
    std::fs::write(&path, &text).unwrap();
    let mut s = fiveaxis::program::open(&path, None, &ReadOptions::default()).unwrap();
    let blocks: Vec<_> = s.by_ref().collect();
    assert_eq!(blocks, whole.blocks);
    assert_eq!(s.diagnostics().to_vec(), whole.diagnostics);
    assert_eq!(blocks.len(), 4);
    // A line longer than the bound is an error at its line; the lines after it are still read.
    text = b"G21 G90\nG1 X1 F100\n(".to_vec();
    text.extend(std::iter::repeat_n(b'x', MAX_LINE_BYTES + 10));
    text.extend(b")\nG1 X5\n");
    std::fs::write(&path, &text).unwrap();
    let mut s = fiveaxis::program::open(&path, None, &ReadOptions::default()).unwrap();
    let blocks: Vec<_> = s.by_ref().collect();
    assert_eq!(blocks.iter().map(|b| b.line).collect::<Vec<_>>(), vec![1, 2, 4]);
    let d = s.diagnostics().to_vec();
    assert!(d.iter().any(|d| d.line == 3 && d.column == 1 && d.message.contains("longer than")), "{d:?}");
}

/// A Klartext jump lands on the line after its label however the bytes before it read: CR LF line
/// ends, bytes that are not UTF-8, characters of two bytes and a line over the length bound (skipped,
/// an error at its line) all count in the file offsets the reader jumps to; a label's name ends
/// before the line end (`LBL "TWO` with its closing quote missing is still `TWO`, as the run reads it).
#[test]
fn klartext_jumps_land_on_their_labels_past_odd_bytes() {
    let mut text = b"0 BEGIN PGM J MM\r\n1 L X+0 Y+0 Z+0 R0 F100\r\n; caf\xc3\xa9 \xff\r\n;".to_vec();
    text.extend(std::iter::repeat_n(b'x', MAX_LINE_BYTES + 10));
    text.extend(b"\r\n2 LBL 1\r\n3 L IX+1\r\n4 CALL LBL 1 REP2\r\n5 CALL LBL \"TWO\"\r\n6 L Z+10 M30\r\n7 LBL \"TWO\r\n8 L IY+1\r\n9 LBL 0\r\n10 END PGM J MM\r\n");
    let path = tmp("jumps.h");
    std::fs::write(&path, &text).unwrap();
    let mut s = fiveaxis::program::open(&path, None, &ReadOptions::default()).unwrap();
    let blocks: Vec<_> = s.by_ref().collect();
    let mm = 1e-3;
    let run: Vec<(usize, Option<f64>, Option<f64>)> = blocks.iter().map(|b| (b.line, b.targets.x.map(|v| v / mm), b.targets.y.map(|v| v / mm))).collect();
    let close = |a: Option<f64>, b: Option<f64>| a.zip(b).is_none_or(|(a, b)| (a - b).abs() < 1e-9) && a.is_some() == b.is_some();
    let want = [(2, Some(0.0), Some(0.0)), (6, Some(1.0), None), (6, Some(2.0), None), (6, Some(3.0), None), (11, None, Some(1.0)), (9, None, None)];
    assert_eq!(run.len(), want.len(), "{run:?}");
    for (r, w) in run.iter().zip(&want) {
        assert!(r.0 == w.0 && close(r.1, w.1) && close(r.2, w.2), "{run:?}");
    }
    let d = s.diagnostics().to_vec();
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].line == 4 && d[0].message.contains("longer than"), "{d:?}");
    let _ = std::fs::remove_file(&path);
}

/// A dense CL program of `n` poses (a raster with the tool axis tilting), as CAM writes it, and its
/// duration at its F2000: the tool tip's straight steps between the poses as written, summed.
fn dense_cl(n: usize) -> (String, f64) {
    let mut s = String::with_capacity(n * 60);
    let (mut length_mm, mut last): (f64, Option<[f64; 3]>) = (0.0, None);
    for k in 0..n {
        let (row, i) = (k / 1001, k % 1001);
        let u = if row % 2 == 0 { i as f64 * 0.1 } else { 100.0 - i as f64 * 0.1 };
        let (x, y) = (u - 50.0, (row % 200) as f64 * 0.5 - 50.0);
        let a = (x / 12.0).cos() * 0.3;
        let line = format!("{x:.4} {y:.4} {:.4} {:.7} 0.0000000 {:.7} 2000\n", 8.0 * (x / 12.0).sin() - 10.0, -a.sin(), a.cos());
        let p: Vec<f64> = line.split_whitespace().take(3).map(|v| v.parse().unwrap()).collect();
        if let Some(q) = last {
            length_mm += ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
        }
        last = Some([p[0], p[1], p[2]]);
        s.push_str(&line);
    }
    (s, length_mm / 2000.0 * 60.0)
}

/// `program analyze PATH` under a 64 MB address-space limit: it succeeds with `blocks` blocks and a
/// cycle time of `duration_s`.
fn analyze_in_64_mb(path: &Path, blocks: usize, duration_s: f64) {
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v 65536; exec '{}' program analyze '{}' --json", bin(), path.display()))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["blocks"].as_u64(), Some(blocks as u64), "{}", v["diagnostics"]);
    let t = v["cycle_time_s"].as_f64().unwrap();
    assert!((t - duration_s).abs() < 1e-6 * duration_s, "{t} s, expected {duration_s} s");
}

#[test]
fn program_analyze_of_an_hours_long_program_fits_in_64_mb() {
    // 600,000 poses (over half an hour at F2000): read whole, its text (36 MB) and blocks (~180 MB)
    // alone would not fit; streamed, the analysis holds a window.
    let path = tmp("dense.cl");
    let (text, duration) = dense_cl(600_000);
    std::fs::write(&path, text).unwrap();
    analyze_in_64_mb(&path, 600_000, duration);
    let _ = std::fs::remove_file(&path);
}

/// A long Klartext program as CAM writes it for a TNC under M128: `n` LN poses (a raster with
/// the tool axis tilting, TX TY TZ) in a section run twice (`LBL 1` ... `CALL LBL 1 REP1`), and a
/// subprogram after M30 (`LBL 9`: up 5 mm and back) called before the section and after it, so the
/// reader jumps the length of the file each way. Also the blocks it runs and its duration at F2000:
/// the tool tip's straight steps in the order the TNC runs them, summed.
fn dense_klartext(n: usize) -> (String, usize, f64) {
    let pose = |k: usize| {
        let (row, i) = (k / 1001, k % 1001);
        let u = if row % 2 == 0 { i as f64 * 0.1 } else { 100.0 - i as f64 * 0.1 };
        let (x, y) = (u - 50.0, (row % 200) as f64 * 0.5 - 50.0);
        let a = (x / 12.0).cos() * 0.3;
        ([x, y, 8.0 * (x / 12.0).sin() - 10.0], [-a.sin(), 0.0, a.cos()])
    };
    let mut s = String::with_capacity(n * 120 + 1000);
    s.push_str("0 BEGIN PGM DENSE MM\n1 TOOL CALL 1 Z S12000 F2000\n2 L X-50 Y-50 Z+10 R0 FAUTO M128\n3 CALL LBL 9\n4 LBL 1\n");
    let mut raster = Vec::with_capacity(n);
    for k in 0..n {
        let (p, t) = pose(k);
        let line = format!(
            "{} LN X{:+.4} Y{:+.4} Z{:+.4} NX{:+.7} NY{:+.7} NZ{:+.7} TX{:+.7} TY{:+.7} TZ{:+.7}\n",
            k + 5, p[0], p[1], p[2], t[0], t[1], t[2], t[0], t[1], t[2]
        );
        // The position as written (4 decimals), as the control reads it.
        let v: Vec<f64> = line.split_whitespace().skip(2).take(3).map(|w| w[1..].parse().unwrap()).collect();
        raster.push([v[0], v[1], v[2]]);
        s.push_str(&line);
    }
    let b = n + 5;
    s.push_str(&format!("{b} CALL LBL 1 REP1\n{} CALL LBL 9\n{} L Z+50 R0 M30\n{} LBL 9\n{} L IZ+5\n{} L IZ-5\n{} LBL 0\n{} END PGM DENSE MM\n", b + 1, b + 2, b + 3, b + 4, b + 5, b + 6, b + 7));
    let lift = |p: [f64; 3]| [[p[0], p[1], p[2] + 5.0], p];
    let last = raster[n - 1];
    // From the origin, where the reader starts, to the first point.
    let mut run = vec![[0.0, 0.0, 0.0], [-50.0, -50.0, 10.0]];
    run.extend(lift(run[1]));
    run.extend(raster.iter().chain(&raster));
    run.extend(lift(last));
    run.push([last[0], last[1], 50.0]);
    let length_mm: f64 = run.windows(2).map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2) + (w[1][2] - w[0][2]).powi(2)).sqrt()).sum();
    // A block per point but the origin, and the TOOL CALL (the tool change, no motion).
    (s, run.len(), length_mm / 2000.0 * 60.0)
}

/// Klartext, whose calls and repeats jump about the file, streams too: a long program with a
/// repeated section and a subprogram at its end (400,000 blocks, 22 minutes at F2000) reads in 64 MB
/// (read whole, its text, 23 MB, and its blocks would not fit), with every block the TNC runs and the
/// duration of its tool path. Gzip'ed and on standard input (each read again at every jump) a shorter
/// one reports the same as its file.
#[test]
fn a_long_klartext_program_streams_in_64_mb() {
    let path = tmp("dense.h");
    let (text, blocks, duration) = dense_klartext(200_000);
    std::fs::write(&path, &text).unwrap();
    analyze_in_64_mb(&path, blocks, duration);

    let (text, blocks, _) = dense_klartext(20_000);
    std::fs::write(&path, &text).unwrap();
    let plain = report_unnamed(&["program", "analyze", path.to_str().unwrap()], None);
    assert_eq!(plain.1["blocks"].as_u64(), Some(blocks as u64));
    let gz = tmp("dense.h.gz");
    assert!(Command::new("sh").arg("-c").arg(format!("gzip -1c '{}' > '{}'", path.display(), gz.display())).status().unwrap().success());
    assert_eq!(report_unnamed(&["program", "analyze", gz.to_str().unwrap()], None), plain, "gzip'ed");
    assert_eq!(report_unnamed(&["program", "analyze", "-", "--dialect", "klartext"], Some(&path)), plain, "on standard input");
    for p in [path, gz] {
        let _ = std::fs::remove_file(p);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
    /// Arbitrary bytes read as a stream give the blocks and diagnostics of the text read whole, in
    /// every dialect read line by line.
    #[test]
    fn arbitrary_bytes_stream_as_they_read(bytes in proptest::collection::vec(prop_oneof![Just(b'\n'), Just(b'\r'), Just(b' '), Just(b'X'), Just(b'G'), Just(b'1'), Just(b'.'), Just(b'*'), Just(b'N'), Just(0xffu8), any::<u8>()], 0..400), d in 0usize..4) {
        let dialect = [Dialect::Rs274, Dialect::Cl, Dialect::Heidenhain, Dialect::Sinumerik][d];
        let text = String::from_utf8_lossy(&bytes).to_string();
        let whole = program::read(&text, dialect, "p", &ReadOptions::default());
        let mut s = BlockStream::from_text(&text, Some(dialect), "p", &ReadOptions::default());
        let blocks: Vec<_> = s.by_ref().collect();
        if !whole.diagnostics.iter().any(|d| d.message.contains("out of order")) {
            prop_assert_eq!(blocks, whole.blocks);
            prop_assert_eq!(s.diagnostics().to_vec(), whole.diagnostics);
        }
    }
}

/// Sums, maxima and minima of a JSON region list's fields from `skip` on.
fn folded(regions: &[serde_json::Value], skip: usize, peak: &str, closest: &str, feed: &str) -> (usize, f64, f64, f64, f64) {
    let rest = &regions[skip..];
    let f = |r: &serde_json::Value, k: &str| r[k].as_f64().unwrap();
    (
        rest.len(),
        rest.iter().map(|r| f(r, "t_end_s") - f(r, "t_start_s")).sum(),
        rest.iter().map(|r| f(r, peak)).fold(f64::NEG_INFINITY, f64::max),
        rest.iter().map(|r| f(r, closest)).fold(f64::INFINITY, f64::min),
        rest.iter().map(|r| f(r, feed)).fold(f64::INFINITY, f64::min),
    )
}

fn assert_folded(u: &serde_json::Value, want: (usize, f64, f64, f64, f64), first_id: u64, what: &str) {
    assert_eq!(u["count"].as_u64(), Some(want.0 as u64), "{what}: {u}");
    assert_eq!(u["first_id"].as_u64(), Some(first_id), "{what}: {u}");
    let close = |k: &str, v: f64| assert!((u[k].as_f64().unwrap() - v).abs() <= 1e-9 * v.abs().max(1.0), "{what}: {k} {u} against {v}");
    close("time_inside_s", want.1);
    close("peak_c_speed_rpm", want.2);
    close("min_singularity_distance_deg", want.3);
    close("min_feed_mm_per_min", want.4);
}

#[test]
fn region_lists_past_their_cap_are_counted_and_folded() {
    // Seven rows of the hours-long benchmark's raster (benches/long_program.py, 22 s at F2000): the
    // surface normal passes near the pole twice a row, so regions come by the dozen, as they come by
    // the ten thousand in its 10-hour program; the report lists the first ones and folds the rest
    // into a count, their time and their worst figures.
    let path = tmp("rows.cl");
    let script = Path::new(env!("FIVEAXIS_ROOT")).join("benches/long_program.py");
    assert!(Command::new("python3").arg(script).arg("0.006").arg(&path).status().unwrap().success());
    let json = |args: &[&str]| -> serde_json::Value {
        let out = Command::new(bin()).args(args).arg(&path).arg("--json").output().unwrap();
        assert!(out.status.code().is_some_and(|c| c < 2), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let whole = json(&["program", "analyze"]);
    let all = whole["regions"].as_array().unwrap().clone();
    assert!(all.len() > 4, "{} regions", all.len());
    assert_eq!(whole["unlisted_regions"]["count"].as_u64(), Some(0));
    let capped = json(&["program", "analyze", "--max-listed-regions", "2"]);
    assert_eq!(capped["regions"].as_array().unwrap()[..], all[..2]);
    assert_folded(&capped["unlisted_regions"], folded(&all, 2, "peak_c_speed_rpm", "min_singularity_distance_deg", "min_feed_limit_mm_per_min"), 3, "program analyze");

    // `run`: the analysis, the monitor's regions on the simulated stream and the slow regions.
    let whole = json(&["run"]);
    let capped = json(&["run", "--max-listed-regions", "2"]);
    assert_eq!(capped["regions"], json(&["program", "analyze", "--max-listed-regions", "2"])["regions"]);
    let monitor = whole["simulated"]["monitor_regions"].as_array().unwrap().clone();
    assert!(monitor.len() > 4, "{} monitor regions", monitor.len());
    assert_eq!(capped["simulated"]["monitor_regions"].as_array().unwrap()[..], monitor[..2]);
    let first = monitor[2]["id"].as_u64().unwrap();
    assert_folded(&capped["simulated"]["unlisted_monitor_regions"], folded(&monitor, 2, "peak_c_speed_rpm", "min_singularity_distance_deg", "min_path_feed_mm_per_min"), first, "run's monitor");
    let lost: f64 = monitor[2..].iter().map(|r| r["time_lost_s"].as_f64().unwrap()).sum();
    assert!((capped["simulated"]["unlisted_monitor_regions"]["time_lost_s"].as_f64().unwrap() - lost).abs() < 1e-9);
    let slow = whole["simulated"]["slow_regions"].as_array().unwrap();
    let listed = capped["simulated"]["slow_regions"].as_array().unwrap();
    assert_eq!(listed.len(), slow.len().min(2));
    assert_eq!(capped["simulated"]["unlisted_slow_regions"]["count"].as_u64(), Some(slow.len().saturating_sub(2) as u64));
    let stops = slow.iter().filter(|r| r["at_stop"] == true).count();
    assert_eq!(capped["simulated"]["planned_stops"].as_u64(), Some(stops as u64));

    // `analyze` of the run's recording: the regions of the commanded stream, and each stream's.
    let mcap = tmp("rows.mcap");
    assert!(Command::new(bin()).arg("run").arg(&path).arg("--mcap").arg(&mcap).output().unwrap().status.code().is_some_and(|c| c < 2));
    let offline = |cap: &str| -> serde_json::Value {
        let out = tmp(&format!("rows-{cap}.json"));
        let st = Command::new(bin()).arg("analyze").arg(&mcap).args(["--max-listed-regions", cap, "--json"]).arg(&out).output().unwrap();
        assert!(st.status.code().is_some_and(|c| c < 2), "{}", String::from_utf8_lossy(&st.stderr));
        serde_json::from_slice(&std::fs::read(out).unwrap()).unwrap()
    };
    let (whole, capped) = (offline("1000"), offline("2"));
    let all = whole["regions"].as_array().unwrap();
    assert!(all.len() > 4, "{whole}");
    assert_eq!(capped["regions"].as_array().unwrap()[..], all[..2]);
    assert_eq!(capped["unlisted_regions"]["count"].as_u64(), Some(all.len() as u64 - 2));
    for (w, c) in whole["streams"].as_array().unwrap().iter().zip(capped["streams"].as_array().unwrap()) {
        let n = w["regions"].as_array().unwrap().len();
        assert_eq!(c["regions"].as_array().unwrap().len(), n.min(2), "{}", w["topic"]);
        assert_eq!(c["unlisted_regions"]["count"].as_u64(), Some(n.saturating_sub(2) as u64), "{}", w["topic"]);
    }
    let _ = std::fs::remove_file(&mcap);
    let _ = std::fs::remove_file(&path);
}
