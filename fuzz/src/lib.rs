//! Coverage-guided fuzzing of every reader (see README.md): the targets' bodies.

pub mod targets;
