//! Unit factors: the library is SI (m, rad, s, REP 103); people read mm, degrees, rpm and mm/min.
//! Multiply a value in the named unit by the factor to get SI; divide to get back.

/// One millimetre in metres.
pub const MM: f64 = 1e-3;
/// Millimetres in one metre: multiply m by it for mm (exact, where dividing by [`MM`] turns 0.35 m
/// into 349.99999999999994 mm).
pub const MM_IN_M: f64 = 1e3;
/// One inch in metres.
pub const INCH: f64 = 25.4e-3;
/// One degree in radians.
pub const DEG: f64 = std::f64::consts::PI / 180.0;
/// One mm/min in m/s.
pub const MM_PER_MIN: f64 = 1e-3 / 60.0;
/// One degree per minute in rad/s.
pub const DEG_PER_MIN: f64 = DEG / 60.0;
/// One revolution per minute in rad/s.
pub const RPM: f64 = 2.0 * std::f64::consts::PI / 60.0;

/// A speed in m/s as mm/min (for reports: `v * 60e3`, the factor written once).
pub fn mm_per_min(v_m_per_s: f64) -> f64 {
    v_m_per_s * 60e3
}
