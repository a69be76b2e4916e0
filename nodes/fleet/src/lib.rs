//! A shop's fleet over Zenoh (issue 67): each cell stays on DDS; a gateway per machine forwards its
//! monitor's status (rate-capped), `/diagnostics` and regions under `/site/cell/machine` to the
//! fleet's Zenoh network, with rmw_zenoh's keys and encodings; a head-office view gathers them.
//!
//! The logic here is pure (no I/O, no transport), so it is tested without a network: [`keys`] the
//! names, [`regions`] a stream's closed regions, [`cap`] the rate cap, [`fleet`] the view's state.

/// Streams (a status's `input_topic`) followed per machine: a monitor watches a handful (the
/// commanded, the simulated and a machine's own); a status of a new stream beyond these is not
/// followed (a gateway does not send it, its regions are not gathered, the view does not show it),
/// so that a broken or hostile peer naming a new one in every message cannot grow their memory.
pub const MAX_STREAMS: usize = 16;

pub mod cap;
pub mod fleet;
pub mod keys;
pub mod regions;
