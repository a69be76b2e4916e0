//! Helpers shared by the integration tests (each test crate uses a part of them).
#![allow(dead_code)]

use nalgebra::Vector3;
use std::path::{Path, PathBuf};

/// This test binary's scratch area: `target/tmp` (Cargo's `CARGO_TARGET_TMPDIR`), which outlives
/// the run, so every helper below first removes what an earlier run left.
pub fn scratch_root() -> &'static Path {
    Path::new(env!("CARGO_TARGET_TMPDIR"))
}

/// A fresh, empty directory `name` for one test.
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = scratch_root().join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A bash loop that waits (up to 30 s) until a server listens on 127.0.0.1:`port`, for the live tests'
/// scripts: a peer is started in the background, its client once it can be reached.
pub fn wait_for_port_sh(port: u16) -> String {
    format!("for i in $(seq 600); do (exec 3<>/dev/tcp/127.0.0.1/{port}) 2>/dev/null && break; sleep 0.05; done")
}

/// A fresh path `name` (nothing there) in the directory `dir` that several tests of a binary share.
pub fn scratch_path(dir: &str, name: &str) -> PathBuf {
    let dir = scratch_root().join(dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    let _ = std::fs::remove_file(&path);
    let _ = std::fs::remove_dir_all(&path);
    path
}

/// A small deterministic generator (xorshift64*), so that a failure names a reproducible case.
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
    pub fn unit(&mut self) -> Vector3<f64> {
        loop {
            let v = Vector3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }
    /// A random unit vector perpendicular to `o`.
    pub fn across(&mut self, o: &Vector3<f64>) -> Vector3<f64> {
        loop {
            let v = self.unit();
            let p = v - o * o.dot(&v);
            if p.norm() > 0.1 {
                return p.normalize();
            }
        }
    }
}

/// Each case `(name, file text, what the error says)` is written to `dir/name.ext` and refused with
/// exit 2 by `machine show` and by `program analyze --machine`, the error naming the file and saying
/// each of its phrases; `base` is the valid file the cases were made from (a case equal to it tests
/// nothing).
pub fn assert_machine_files_refused(dir: &std::path::Path, ext: &str, base: &str, cases: &[(&str, String, Vec<&str>)]) {
    for (name, text, want) in cases {
        assert_ne!(text.as_str(), base, "{name}: the case did not change the file");
        let path = dir.join(format!("{name}.{ext}"));
        std::fs::write(&path, text).unwrap();
        let p = path.to_str().unwrap();
        for args in [vec!["machine", "show", p], vec!["program", "analyze", "bundled:SING.I", "--machine", p]] {
            let out = std::process::Command::new(env!("FIVEAXIS_EXE")).args(&args).output().unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{name} {args:?}: {err}");
            for w in want {
                assert!(err.contains(w) && err.contains(p), "{name} {args:?}: no '{w}' in: {err}");
            }
        }
    }
}

/// A file of `../shared/outside/` (real programs, bags and machine data from outside the project;
/// CI has `../shared` beside the clone, and the project never copies them). Missing, the test fails
/// saying so: a test that read nothing must not pass.
pub fn outside(relative: &str) -> PathBuf {
    let path = Path::new(env!("FIVEAXIS_ROOT")).join("../shared/outside").join(relative);
    assert!(path.exists(), "{} is missing: the tests read ../shared/outside beside the clone (see DEVELOPERS.md)", path.display());
    path
}
