//! The program a publishing node was given, streamed and checked at once: the node publishes within a
//! second of start whatever the program's length, and still never publishes motion past a defect.
//!
//! A checker thread reads and plans the whole program ahead of the publisher ([`Moves::check`], about
//! a thousand times faster than real time). The node waits for it up to [`SETTLE`]: a program whose
//! check ends in that time is refused with nothing published if it has defects. A longer one starts
//! publishing while the check goes on; a state is held back until the check has passed its time, and
//! a defect found later stops the node there with exit code 2, the defect named by line and column.

use crate::EXIT_INPUT;
use fiveaxis::job::{Checked, JobOptions, Moves};
use fiveaxis::machine::Machine;
use fiveaxis_msgs::AxisState;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long a node waits by default for the whole program's check before it starts publishing
/// (`--check-before-publish-s`).
pub const SETTLE: Duration = Duration::from_secs(1);

/// How far the checker has come: commanded time planned through (f64 bits; infinite once ended
/// clean), and whether it met a defect.
#[derive(Debug, Default)]
struct Progress {
    through: AtomicU64,
    defect: AtomicBool,
    ended: AtomicBool,
}

/// Marks the check ended when the checker thread ends: checked through the end if it ended clean, a
/// defect otherwise.
struct Ended {
    progress: Arc<Progress>,
    clean: bool,
}

impl Drop for Ended {
    fn drop(&mut self) {
        if self.clean {
            self.progress.through.store(f64::INFINITY.to_bits(), Ordering::Release);
        } else {
            self.progress.defect.store(true, Ordering::Release);
        }
        self.progress.ended.store(true, Ordering::Release);
    }
}

/// The check of a node's program, running beside the publisher.
pub struct Gate {
    progress: Arc<Progress>,
    handle: Option<JoinHandle<Result<Checked, String>>>,
    result: Option<Result<Checked, String>>,
    program: String,
}

impl Gate {
    /// Start checking `moves` on `machine`.
    pub fn start(program: &str, moves: &Moves, machine: &Machine) -> Gate {
        let progress = Arc::new(Progress::default());
        let (p, moves, machine) = (progress.clone(), moves.clone(), machine.clone());
        let handle = std::thread::Builder::new()
            .name("program-check".into())
            .spawn(move || {
                // However the check ends (a panic included), the publisher learns it: a defect unless
                // it ended clean.
                let mut end = Ended { progress: p.clone(), clean: false };
                let r = moves.check(&machine, |t, defect| {
                    // The defect first: a reader that sees the time advanced sees the defect too.
                    if defect {
                        p.defect.store(true, Ordering::Release);
                    }
                    p.through.store(t.to_bits(), Ordering::Release);
                }).map_err(|e| e.to_string());
                end.clean = matches!(&r, Ok(c) if c.errors == 0);
                r
            })
            .ok();
        Gate { progress, handle, result: None, program: program.into() }
    }

    /// Wait for the check up to `limit`; the whole check's result if it has ended by then.
    pub fn settle(&mut self, limit: Duration) -> Option<&Result<Checked, String>> {
        let start = Instant::now();
        while self.handle.as_ref().is_some_and(|h| !h.is_finished()) && start.elapsed() < limit {
            std::thread::sleep(Duration::from_millis(2));
        }
        if self.handle.as_ref().is_some_and(|h| h.is_finished()) {
            self.join();
        }
        self.result.as_ref()
    }

    fn join(&mut self) {
        if let Some(h) = self.handle.take() {
            self.result = Some(h.join().unwrap_or_else(|_| Err("the program check stopped unexpectedly".into())));
        }
    }

    /// True once a defect was found (the node must stop).
    pub fn defect(&self) -> bool {
        self.progress.defect.load(Ordering::Acquire)
    }

    /// The states of `states` whose time the check has passed, waiting for it where the publisher is
    /// ahead; ends at the first defect (or once `stop` says so).
    pub fn guard<'a, I: Iterator<Item = AxisState> + 'a>(&'a self, states: I, stop: impl Fn() -> bool + 'a) -> impl Iterator<Item = AxisState> + 'a {
        let p = &self.progress;
        let mut states = states;
        std::iter::from_fn(move || {
            let st = states.next()?;
            let t = st.header.stamp.as_secs();
            loop {
                let through = f64::from_bits(p.through.load(Ordering::Acquire));
                if p.defect.load(Ordering::Acquire) || stop() {
                    return None;
                }
                if t <= through || p.ended.load(Ordering::Acquire) {
                    return Some(st);
                }
                std::thread::sleep(Duration::from_micros(200));
            }
        })
    }

    /// After publishing: wait for the check to end and report it. Defects are printed, each with its
    /// line and column, and the node exits with [`EXIT_INPUT`]; warnings are logged. `published`:
    /// whether any state went out; `interrupted`: the node was asked to stop (it does not wait for a
    /// check still running then).
    pub fn finish(mut self, published: bool, interrupted: bool) {
        if interrupted && !self.progress.ended.load(Ordering::Acquire) {
            return;
        }
        self.settle(Duration::MAX);
        report(&self.program, self.result.take(), published);
    }
}

/// Report a check's result; exit [`EXIT_INPUT`] on an unreadable program or one with defects.
fn report(program: &str, result: Option<Result<Checked, String>>, published: bool) {
    match result {
        None => {
            eprintln!("error: {program}: the program check could not run");
            std::process::exit(EXIT_INPUT);
        }
        Some(Err(e)) => {
            eprintln!("error: reading {program}: {e}");
            std::process::exit(EXIT_INPUT);
        }
        Some(Ok(c)) if c.errors > 0 => {
            for d in &c.diagnostics {
                eprintln!("{program}:{d}");
            }
            if published {
                eprintln!("error: {program} has defects: stopped before the first (what came before it was published)");
            } else {
                eprintln!("error: {program} has defects: refused (nothing published)");
            }
            std::process::exit(EXIT_INPUT);
        }
        Some(Ok(c)) => {
            for d in &c.diagnostics {
                tracing::warn!("{program}:{d}");
            }
        }
    }
}

/// Open the program a publishing node was given and start its check ([`Gate`]), waiting for it up to
/// `settle` (default [`SETTLE`]). Fails closed: a program that cannot be opened, or whose check ends
/// within `settle` with defects (a damaged word,
/// an unreachable pose, a feed that makes it run past `--max-program-hours`), ends the node here with
/// exit code 2 and each defect named by line and column, before anything is published.
pub fn open_program(program: &str, options: &JobOptions, machine: &Machine, settle: Duration) -> (Moves, Gate) {
    let moves = match Moves::open(program, machine, options) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("error: reading {program}: {e}");
            std::process::exit(EXIT_INPUT);
        }
    };
    let name = moves.name();
    let program = name.as_str();
    let mut gate = Gate::start(program, &moves, machine);
    if gate.handle.is_none() {
        eprintln!("error: {program}: cannot start the program check (no thread)");
        std::process::exit(EXIT_INPUT);
    }
    if let Some(r) = gate.settle(settle) {
        if let Ok(c) = r {
            tracing::info!(program, blocks = c.blocks, duration_s = c.duration_s, errors = c.errors, "program checked");
        }
        if gate.defect() {
            let r = gate.result.take();
            report(program, r, false);
        }
    } else {
        tracing::info!(program, "program still being checked: publishing meanwhile, stopping at a defect");
    }
    (moves, gate)
}

/// After publishing `sent` samples of `program` pass after pass ([`Moves::passes`]): a later pass
/// that could not be read again (`failed`) ends the node with exit code 2, naming why.
pub fn finish_passes(program: &str, failed: &std::sync::OnceLock<fiveaxis::job::JobError>, sent: usize) {
    if let Some(e) = failed.get() {
        eprintln!("error: reading {program} again for its next pass: {e} (stopped after {sent} samples)");
        std::process::exit(EXIT_INPUT);
    }
}
