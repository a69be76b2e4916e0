//! fiveaxis's integration tests in one executable: a module per file of `tests/` (each a domain: the
//! readers, the DDS node set, the recordings …), with the helpers they share in `tests/common`. One
//! executable rather than one per file: each links the library and its dependencies, 36 of them took
//! 41 CPU-s of a clean build (session 61). nextest still runs each test in a process of its own
//! (`.config/nextest.toml`, whose filters name a file's tests as `test(/^file::/)`).

mod common;

mod apt;
mod arcs;
mod avoid;
mod cdr;
mod chains;
mod cli;
mod corpus;
mod dds;
mod dialects;
mod docs;
mod dwell;
mod exact_stop;
mod exit_codes;
mod fleet;
mod kinematics;
mod lookahead;
mod machine_live;
mod machine_trace;
mod monitor;
mod mtconnect;
mod paper_figures;
mod path;
mod readers;
mod record;
mod rerun;
mod ros_args;
mod ros_package;
mod roughness;
mod shopfloor;
mod simulator;
mod sinumerik;
mod soak;
mod sqlite_bags;
mod stream;
mod structure;
mod urdf;
