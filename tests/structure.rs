//! The layout issue 16 asks for, checked: the core crate (the math) depends on no I/O, transport,
//! CLI or drawing crate, and its sources touch no file system, network or process.

use std::path::Path;
use std::process::Command;

/// Crates the core must not pull in, directly or through another.
const FORBIDDEN: [&str; 10] = ["mcap", "zstd", "zip", "indicatif", "clap", "tokio", "ros2-client", "rustdds", "rerun", "anyhow"];

#[test]
fn core_depends_on_no_io_transport_cli_or_drawing_crate() {
    let root = Path::new(env!("FIVEAXIS_ROOT"));
    let out = Command::new(env!("CARGO"))
        .args(["tree", "--offline", "-p", "fiveaxis-core", "-e", "normal", "--prefix", "none", "--format", "{p}"])
        .current_dir(root)
        .output()
        .expect("cargo runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "cargo tree: {}", String::from_utf8_lossy(&out.stderr));
    let crates: Vec<&str> = text.lines().filter_map(|l| l.split_whitespace().next()).collect();
    assert!(crates.contains(&"fiveaxis-core") && crates.contains(&"nalgebra"), "the tree lists the core and its math: {text}");
    let found: Vec<&&str> = FORBIDDEN.iter().filter(|f| crates.contains(f)).collect();
    assert!(found.is_empty(), "the core pulls in {found:?}:\n{text}");
}

#[test]
fn core_sources_touch_no_file_system_network_or_process() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("core/src");
    let mut files = vec![dir];
    let mut read = 0;
    let mut hits = Vec::new();
    while let Some(p) = files.pop() {
        if p.is_dir() {
            files.extend(std::fs::read_dir(&p).unwrap().map(|e| e.unwrap().path()));
            continue;
        }
        if p.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        read += 1;
        let text = std::fs::read_to_string(&p).unwrap();
        for (n, line) in text.lines().enumerate() {
            if ["std::fs", "File::open", "File::create", "std::net", "std::process", "std::env"].iter().any(|w| line.contains(w)) {
                hits.push(format!("{}:{}: {}", p.display(), n + 1, line.trim()));
            }
        }
    }
    assert!(read > 20, "read the core's sources ({read} files)");
    assert!(hits.is_empty(), "I/O in the core:\n{}", hits.join("\n"));
}

/// Every test file is built: the tests package builds its files as modules of one executable
/// (`integration.rs`; autotests is off, so that the files stay in `tests/` beside the package's own
/// build script and library) or, the fuzzers' regressions, as an executable of their own; a file
/// neither names would never run.
#[test]
fn every_test_file_is_built() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("tests");
    let manifest = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
    let main = std::fs::read_to_string(dir.join("integration.rs")).unwrap();
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .filter(|n| n != "build" && n != "lib" && n != "integration")
        .collect();
    files.sort();
    assert!(files.len() > 30 && files.contains(&"structure".to_string()), "read the test files: {files:?}");
    let built = |n: &String| main.lines().any(|l| l == format!("mod {n};")) || manifest.contains(&format!("[[test]]\nname = \"{n}\"\npath = \"{n}.rs\"\n"));
    let missing: Vec<&String> = files.iter().filter(|n| !built(n)).collect();
    assert!(missing.is_empty(), "neither tests/integration.rs nor tests/Cargo.toml builds {missing:?}");
}
