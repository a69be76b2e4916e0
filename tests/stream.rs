//! Programs read and analysed as streams (`fiveaxis program analyze`): the same blocks, diagnostics
//! and report as the program read whole, in memory that does not grow with the program.

use fiveaxis::job::{self, JobOptions};
use fiveaxis::machine::Machine;
use fiveaxis::program::{self, BlockStream, Dialect, MCodeAction, MCodeRule, ReadOptions, MAX_LINE_BYTES};
use proptest::prelude::*;
use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_fiveaxis")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fiveaxis-stream-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
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
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("recordings/programs");
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
        let mut stream = BlockStream::open(&path, None, &options).unwrap();
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

#[test]
fn line_endings_bad_bytes_and_overlong_lines_stream_as_they_read() {
    let mut text = b"G21 G90\r\nG1 X1 F100\r\nG1 X2 (caf\xc3\xa9 \xff)\nG1 X3".to_vec();
    let whole = program::read(&String::from_utf8_lossy(&text), Dialect::Rs274, "t", &ReadOptions::default());
    let path = tmp("endings.ngc");
    std::fs::write(&path, &text).unwrap();
    let mut s = BlockStream::open(&path, None, &ReadOptions::default()).unwrap();
    let blocks: Vec<_> = s.by_ref().collect();
    assert_eq!(blocks, whole.blocks);
    assert_eq!(s.diagnostics().to_vec(), whole.diagnostics);
    assert_eq!(blocks.len(), 4);
    // A line longer than the bound is an error at its line; the lines after it are still read.
    text = b"G21 G90\nG1 X1 F100\n(".to_vec();
    text.extend(std::iter::repeat_n(b'x', MAX_LINE_BYTES + 10));
    text.extend(b")\nG1 X5\n");
    std::fs::write(&path, &text).unwrap();
    let mut s = BlockStream::open(&path, None, &ReadOptions::default()).unwrap();
    let blocks: Vec<_> = s.by_ref().collect();
    assert_eq!(blocks.iter().map(|b| b.line).collect::<Vec<_>>(), vec![1, 2, 4]);
    let d = s.diagnostics().to_vec();
    assert!(d.iter().any(|d| d.line == 3 && d.column == 1 && d.message.contains("longer than")), "{d:?}");
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

#[test]
fn program_analyze_of_an_hours_long_program_fits_in_64_mb() {
    // 600,000 poses (over half an hour at F2000): read whole, its text (36 MB) and blocks (~180 MB)
    // alone would not fit; streamed, the analysis holds a window.
    let path = tmp("dense.cl");
    let (text, duration) = dense_cl(600_000);
    std::fs::write(&path, text).unwrap();
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v 65536; exec '{}' program analyze '{}' --json", bin(), path.display()))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{text}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["blocks"].as_u64(), Some(600_000));
    let t = v["cycle_time_s"].as_f64().unwrap();
    assert!((t - duration).abs() < 1e-6 * duration, "{t} s, expected {duration} s");
    let _ = std::fs::remove_file(&path);
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
