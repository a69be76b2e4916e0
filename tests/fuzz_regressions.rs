//! Inputs the fuzzers (`fuzz/run`, fuzz/README.md) found breaking a reader, replayed through the
//! same target bodies the fuzzers run (fuzz/src/targets.rs): each must return without a panic and
//! without any single allocation over 512 MB (the fuzz runs' `-malloc_limit_mb`), which a
//! measuring global allocator here checks. The inputs are in tests/fuzz-regressions/TARGET/.

#[path = "../fuzz/src/targets.rs"]
mod targets;

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The system allocator, keeping the largest single request since it was last reset.
struct Measured;

static LARGEST: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Measured {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST.fetch_max(new_size, Ordering::Relaxed);
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static ALLOCATOR: Measured = Measured;

/// The fuzz runs' limit on one allocation.
const MAX_ALLOCATION: usize = 512 << 20;

#[test]
fn every_input_the_fuzzers_found_returns_cleanly_within_the_allocation_limit() {
    let root = Path::new(env!("FIVEAXIS_ROOT")).join("tests/fuzz-regressions");
    let targets: [(&str, fn(&[u8])); 9] = [
        ("nc_program", targets::nc_program),
        ("mcap_recording", targets::mcap_recording),
        ("rosbag2_metadata", targets::rosbag2_metadata),
        ("cdr_message", targets::cdr_message),
        ("x3p_container", targets::x3p_container),
        ("x3p_main_xml", targets::x3p_main_xml),
        ("csv_profile", targets::csv_profile),
        ("machine_toml", targets::machine_toml),
        ("machine_urdf", targets::machine_urdf),
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
