//! A shop's fleet over Zenoh (issue 67): each cell stays on DDS; a gateway per machine forwards its
//! monitor's status (rate-capped), `/diagnostics` and regions under `/site/cell/machine` to the
//! fleet's Zenoh network, with rmw_zenoh's keys and encodings; a head-office view gathers them.
//!
//! The logic here is pure (no I/O, no transport), so it is tested without a network: [`keys`] the
//! names, [`regions`] a stream's closed regions, [`cap`] the rate cap, [`fleet`] the view's state.

pub mod cap;
pub mod fleet;
pub mod keys;
pub mod regions;
