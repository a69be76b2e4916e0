//! Inputs the fuzzers (`fuzz/run`, fuzz/README.md) found breaking a reader, replayed through the
//! same target bodies the fuzzers run (fuzz/src/targets.rs): each must return without a panic and
//! without any single allocation over 512 MB (the fuzz runs' `-malloc_limit_mb`), which a
//! measuring global allocator here checks. The inputs are in tests/fuzz-regressions/TARGET/.
//! The allocator also keeps the most memory held at once, for the readers' memory bounds.

#[path = "../fuzz/src/targets.rs"]
mod targets;

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The system allocator, keeping the largest single request since it was last reset.
struct Measured;

static LARGEST: AtomicUsize = AtomicUsize::new(0);
/// Bytes held now, and the most held at once since it was last reset.
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
/// The tests here measure the whole process: one at a time.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn held(more: usize) {
    let now = LIVE.fetch_add(more, Ordering::Relaxed) + more;
    PEAK.fetch_max(now, Ordering::Relaxed);
}

unsafe impl GlobalAlloc for Measured {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        held(layout.size());
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        held(layout.size());
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST.fetch_max(new_size, Ordering::Relaxed);
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        held(new_size);
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static ALLOCATOR: Measured = Measured;

/// The fuzz runs' limit on one allocation.
const MAX_ALLOCATION: usize = 512 << 20;

#[test]
fn every_input_the_fuzzers_found_returns_cleanly_within_the_allocation_limit() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let root = Path::new(env!("FIVEAXIS_ROOT")).join("tests/fuzz-regressions");
    let targets: [(&str, fn(&[u8])); 11] = [
        ("nc_program", targets::nc_program),
        ("mcap_recording", targets::mcap_recording),
        ("rosbag2_metadata", targets::rosbag2_metadata),
        ("cdr_message", targets::cdr_message),
        ("x3p_container", targets::x3p_container),
        ("x3p_main_xml", targets::x3p_main_xml),
        ("csv_profile", targets::csv_profile),
        ("machine_toml", targets::machine_toml),
        ("machine_urdf", targets::machine_urdf),
        ("shdr_log", targets::shdr_log),
        ("mtconnect_agent", targets::mtconnect_agent),
    ];
    let mut dirs: Vec<String> = std::fs::read_dir(&root).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    dirs.retain(|d| !targets.iter().any(|(t, _)| t == d));
    assert!(dirs.is_empty(), "folders that name no target: {dirs:?}");
    let mut replayed = 0;
    for (target, run) in targets {
        let Ok(entries) = std::fs::read_dir(root.join(target)) else { continue };
        for entry in entries {
            let path = entry.unwrap().path();
            let data = std::fs::read(&path).unwrap();
            LARGEST.store(0, Ordering::Relaxed);
            let outcome = std::panic::catch_unwind(|| run(&data));
            let largest = LARGEST.load(Ordering::Relaxed);
            assert!(outcome.is_ok(), "{}: panicked", path.display());
            assert!(largest <= MAX_ALLOCATION, "{}: one allocation of {largest} bytes (limit {MAX_ALLOCATION})", path.display());
            replayed += 1;
        }
    }
    assert!(replayed > 0, "no regression input replayed");
    let _ = std::fs::remove_dir_all(targets::scratch_dir());
}

/// Lines a loop runs again are kept as read (compiled), within a bound on the memory they hold
/// (64 MiB; a line as read holds several times its text), whatever their count: a loop over 600
/// lines of 2,000 computed words each, run three times, in a Fanuc WHILE loop and a LinuxCNC O-word
/// repeat. The most memory held while each is read stays under 150 MB: about 75 MB here in session
/// 62, where keeping every line (the bound lifted) held about 290 MB.
#[test]
fn lines_a_loop_runs_again_are_kept_within_their_memory_bound() {
    use fiveaxis::program::{read, Dialect, ReadOptions};
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let body: String = (0..600).map(|_| format!("G1{}\n", " X[#1+1]".repeat(2_000))).collect();
    let programs = [
        (Dialect::Fanuc, format!("%\nO1000\n#1 = 0\nWHILE [#1 LT 3] DO1\n{body}#1 = #1 + 1\nEND1\nM30\n%\n")),
        (Dialect::Rs274, format!("#1 = 0\no100 repeat [3]\n{body}o100 endrepeat\nM2\n")),
    ];
    for (dialect, text) in programs {
        let base = LIVE.load(Ordering::Relaxed);
        PEAK.store(base, Ordering::Relaxed);
        let p = read(&text, dialect, "kept.nc", &ReadOptions::default());
        let peak = PEAK.load(Ordering::Relaxed).saturating_sub(base);
        // Each line's 2,000 X words are refused by the interpreter (one X a block): the reading is
        // what is measured, and it ran every pass.
        assert!(p.diagnostics.len() >= 600, "{dialect:?}: {} diagnostics", p.diagnostics.len());
        eprintln!("{dialect:?}: most held {:.1} MB", peak as f64 / 1e6);
        assert!(peak < 150_000_000, "{dialect:?}: {peak} bytes held at once");
    }
}
