//! Helpers shared by the integration tests (each test crate uses a part of them).
#![allow(dead_code)]

use nalgebra::Vector3;

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
