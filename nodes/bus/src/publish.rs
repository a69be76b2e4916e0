//! Publishing a program's axis states in time, and the pacer that paces and stamps them.

use crate::Shutdown;
use ros2_client::dds::Publisher;
use serde::Serialize;
use std::time::{Duration, Instant};

/// Publish axis states in time (each also as JointState; and as /clock when given: the commander
/// gives it only with `use_sim_time`), paced and stamped by `pacer`, until done or shutdown. A publish that times out on a subscriber that cannot keep up drops that
/// sample (counted, warned at most once a second; the monitor sees the gap): the stream never stops for
/// one slow reader. Returns (sent, dropped).
///
/// The first sample waits up to `first_ack_wait` until every matched subscriber has acknowledged
/// it (the pacing then starts over from there, or in wall time catches up on a short wait): a subscriber is matched before it can read, and
/// under DDS Security before the key exchange that lets it decrypt has completed, so without the
/// wait it lost the stream's first samples (a secure recorder kept 575-1025 of 1501 in half the runs
/// at speed 4).
pub fn publish_states(
    states: impl IntoIterator<Item = fiveaxis_msgs::AxisState>,
    state_pub: &Publisher<fiveaxis_msgs::AxisState>,
    joint_pub: &Publisher<fiveaxis_msgs::JointState>,
    clock_pub: Option<&Publisher<fiveaxis_msgs::Clock>>,
    pacer: &Pacer,
    first_ack_wait: Duration,
    shutdown: &Shutdown,
) -> (usize, usize) {
    let (mut sent, mut dropped) = (0usize, 0usize);
    let mut last_warn: Option<Instant> = None;
    let mut pacer = *pacer;
    let mut first = true;
    for mut st in states {
        if shutdown.requested() {
            tracing::info!("stopping on signal after {sent} samples");
            break;
        }
        let t = st.header.stamp.as_secs();
        pacer.wait_until(t);
        st.header.stamp = pacer.stamp(t);
        let joints = st.to_joint_state();
        if let Some(c) = clock_pub {
            // The clock first, so that a node stamping by /clock is not behind the sample.
            let _ = c.publish(fiveaxis_msgs::Clock { clock: st.header.stamp });
        }
        let ok = state_pub.publish(st).is_ok() & joint_pub.publish(joints).is_ok();
        if std::mem::take(&mut first) && !first_ack_wait.is_zero() {
            let began = Instant::now();
            if !first_sample_acknowledged(state_pub, joint_pub, clock_pub, first_ack_wait, shutdown) {
                tracing::warn!(
                    "a matched subscriber did not acknowledge the first sample within {} s (under DDS Security: its key exchange did not complete): publishing on",
                    first_ack_wait.as_secs_f64()
                );
            }
            // Program-time stamps do not move with the pacing, so it starts over after the wait.
            // Wall-time stamps are due times: a short wait is caught up (a burst of at most half a
            // second of samples, within the writers' history), so the stamps stay regular (the soak
            // counts a gap of 1.5 ms); only a longer one moves the pacing, leaving a gap there.
            let waited = began.elapsed();
            if !pacer.stamps_wall_time() || waited > CATCH_UP_MAX {
                pacer = pacer.delayed(waited);
            }
        }
        if ok {
            sent += 1;
        } else {
            dropped += 1;
            if last_warn.is_none_or(|t| t.elapsed() >= Duration::from_secs(1)) {
                tracing::warn!(dropped, "a subscriber is not keeping up: samples dropped");
                last_warn = Some(Instant::now());
            }
        }
    }
    if dropped > 0 {
        tracing::warn!(sent, dropped, "done, with samples dropped by slow subscribers");
    } else {
        tracing::info!(sent, "done");
    }
    // Let reliable delivery finish before the participant goes away.
    std::thread::sleep(Duration::from_millis(500));
    (sent, dropped)
}

/// The longest wait for the first sample's acknowledgement that wall-time pacing catches up on.
const CATCH_UP_MAX: Duration = Duration::from_millis(500);

/// Wait up to `max_wait` until every matched subscriber of the three publishers has acknowledged
/// what they published; false on timeout (shutdown ends the wait early, as acknowledged).
fn first_sample_acknowledged(
    state_pub: &Publisher<fiveaxis_msgs::AxisState>,
    joint_pub: &Publisher<fiveaxis_msgs::JointState>,
    clock_pub: Option<&Publisher<fiveaxis_msgs::Clock>>,
    max_wait: Duration,
    shutdown: &Shutdown,
) -> bool {
    let end = Instant::now() + max_wait;
    let slice = Duration::from_millis(100);
    fn acked<M: Serialize>(p: &Publisher<M>, end: Instant, slice: Duration, shutdown: &Shutdown) -> bool {
        retry_until(end, shutdown, slice, |d| p.wait_for_acknowledgments(d).unwrap_or(false)).unwrap_or(true)
    }
    acked(state_pub, end, slice, shutdown) && acked(joint_pub, end, slice, shutdown) && clock_pub.is_none_or(|c| acked(c, end, slice, shutdown))
}

/// Call `attempt` with how long it may block (`slice`, less near `end`) until it succeeds:
/// Some(true); or `end` passes: Some(false); or shutdown is asked: None.
pub(crate) fn retry_until(end: Instant, shutdown: &Shutdown, slice: Duration, mut attempt: impl FnMut(Duration) -> bool) -> Option<bool> {
    loop {
        if shutdown.requested() {
            return None;
        }
        let left = end.saturating_duration_since(Instant::now());
        if attempt(slice.min(left)) {
            return Some(true);
        }
        if left <= slice {
            return Some(false);
        }
    }
}

/// Paces a loop against the wall clock: sample time `t` (s) is due at `start + t / speed`; and
/// stamps it: program time `t` (ROS 2's sim time), or the wall time it is due at.
#[derive(Debug, Clone, Copy)]
pub struct Pacer {
    start: Instant,
    speed: Option<f64>,
    /// The wall clock at `start`, ns since the Unix epoch, when stamping wall time.
    wall: Option<u128>,
}

impl Pacer {
    /// `speed` None: as fast as possible. Stamps program time.
    pub fn new(speed: Option<f64>) -> Pacer {
        Pacer { start: Instant::now(), speed, wall: None }
    }

    /// Whether it stamps wall time (else program time).
    pub fn stamps_wall_time(&self) -> bool {
        self.wall.is_some()
    }

    /// The same pacing started `d` later: every sample is due, and stamped in wall time, `d` later.
    pub fn delayed(self, d: Duration) -> Pacer {
        Pacer { start: self.start + d, wall: self.wall.map(|w| w + d.as_nanos()), ..self }
    }

    /// Stamp the wall time each sample is due at, from the wall clock now (the pacer's start).
    pub fn stamping_wall_time(self) -> Pacer {
        let wall = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
        Pacer { wall: Some(wall.saturating_sub(self.start.elapsed().as_nanos())), ..self }
    }

    /// The stamp of sample time `t` (s): `t` itself in program time, else the wall time it is due
    /// at (start + t / speed), to the nanosecond.
    pub fn stamp(&self, t: f64) -> fiveaxis_msgs::Time {
        match self.wall {
            None => fiveaxis_msgs::Time::from_secs(t),
            Some(w) => {
                let dt = (t / self.speed.unwrap_or(1.0)).max(0.0);
                fiveaxis_msgs::Time::from_nanos((w + (dt * 1e9).round() as u128).min(u64::MAX as u128) as u64)
            }
        }
    }
    pub fn wait_until(&self, t: f64) {
        if let Some(speed) = self.speed {
            let due = self.start + Duration::from_secs_f64((t / speed).max(0.0));
            let now = Instant::now();
            if due > now {
                std::thread::sleep(due - now);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_delayed_pacer_is_due_and_stamps_wall_time_that_much_later() {
        // 4x: sample time 2 s is due 0.5 s after the start.
        let p = Pacer::new(Some(4.0)).stamping_wall_time();
        let d = Pacer::delayed(p, Duration::from_millis(1500));
        assert_eq!(d.start - p.start, Duration::from_millis(1500));
        let ns = |t: fiveaxis_msgs::Time| t.sec as i128 * 1_000_000_000 + t.nanosec as i128;
        assert_eq!(ns(d.stamp(2.0)) - ns(p.stamp(2.0)), 1_500_000_000);
        assert_eq!(ns(p.stamp(2.0)) - ns(p.stamp(0.0)), 500_000_000);
        // Program time stamps do not move.
        let sim = Pacer::new(Some(4.0));
        assert_eq!(ns(Pacer::delayed(sim, Duration::from_secs(3)).stamp(2.0)), 2_000_000_000);
    }
}
