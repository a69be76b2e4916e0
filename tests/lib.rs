//! fiveaxis's integration tests: `tests/*.rs`, modules of one executable (`integration.rs`), with the
//! helpers they share in `tests/common`. A package of their own, so that they build unoptimised while the library they test
//! stays optimised; they find the repository in `env!("FIVEAXIS_ROOT")` and the `fiveaxis` executable,
//! which the workspace builds beside the node executables, in `env!("FIVEAXIS_EXE")` (build.rs).
//! This library target holds no code: Cargo wants one besides the tests.
