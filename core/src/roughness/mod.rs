//! Measured surface roughness along the part, to lay beside the stutter.
//!
//! - Import a profile: X3P (ISO 25178-72, the open format profilometers such as the Alicona export)
//!   and CSV (x and height columns, units in the header or given).
//! - ISO 16610-21 Gaussian profile filter, cut-off `lambda_c` (default 0.8 mm): the mean line is the
//!   profile convolved with `s(x) = exp(-pi (x / (alpha lambda_c))^2) / (alpha lambda_c)`,
//!   `alpha = sqrt(ln 2 / pi)`; the roughness profile is the profile minus its mean line. Near the ends
//!   the weights are renormalised over the available data (ISO 16610-28's simplest end treatment).
//! - ISO 4287 parameters in sliding windows of five sampling lengths (5 lambda_c): Ra (mean |r|),
//!   Rq (rms), Rz (mean over the five sampling lengths of the highest peak plus the deepest valley).
//! - A seeded synthetic profile for the paper demo ([`synthetic`]); named synthetic wherever it goes.

pub mod synthetic;

/// A measured (or synthetic) height profile along x, SI (m).
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// Positions (m), increasing, and heights (m).
    pub x: Vec<f64>,
    pub z: Vec<f64>,
    /// Where it came from; synthetic profiles say so here.
    pub source: String,
}

/// Errors reading a profile, naming the file and where.
#[derive(Debug, thiserror::Error)]
pub enum RoughnessError {
    #[error("{path}: {source}")]
    Io { path: String, source: std::io::Error },
    #[error("{path}: {message}")]
    Format { path: String, message: String },
}

/// `alpha` of ISO 16610-21: the Gaussian filter transmits 50 % at the cut-off.
pub const ALPHA: f64 = 0.469_718_639_349_825_7; // sqrt(ln 2 / pi)

impl Profile {
    /// Map the profile's own x onto the workpiece x: `x_work = offset + direction * x`.
    pub fn aligned(mut self, offset: f64, reversed: bool) -> Profile {
        let d = if reversed { -1.0 } else { 1.0 };
        for x in &mut self.x {
            *x = offset + d * *x;
        }
        if reversed {
            self.x.reverse();
            self.z.reverse();
        }
        self
    }

    /// Mean spacing of the samples, m.
    pub fn spacing(&self) -> f64 {
        if self.x.len() < 2 {
            return 0.0;
        }
        (self.x[self.x.len() - 1] - self.x[0]) / (self.x.len() - 1) as f64
    }

    /// ISO 16610-21 mean line (waviness) for cut-off `lambda_c` (m), on uniformly spaced samples.
    pub fn mean_line(&self, lambda_c: f64) -> Vec<f64> {
        let n = self.z.len();
        let dx = self.spacing();
        if n == 0 || !(dx > 0.0) {
            return self.z.clone();
        }
        let a = ALPHA * lambda_c;
        // The weights beyond +-lambda_c are below 1e-5 of the peak: truncate there.
        let half = (lambda_c / dx).ceil() as usize;
        let w: Vec<f64> = (0..=half).map(|k| (-std::f64::consts::PI * (k as f64 * dx / a).powi(2)).exp()).collect();
        (0..n)
            .map(|i| {
                let (lo, hi) = (i.saturating_sub(half), (i + half).min(n - 1));
                let (mut s, mut sw) = (0.0, 0.0);
                for j in lo..=hi {
                    let wj = w[i.abs_diff(j)];
                    s += wj * self.z[j];
                    sw += wj;
                }
                s / sw
            })
            .collect()
    }

    /// The roughness profile: the profile minus its ISO 16610-21 mean line.
    pub fn roughness(&self, lambda_c: f64) -> Vec<f64> {
        self.mean_line(lambda_c).iter().zip(&self.z).map(|(m, z)| z - m).collect()
    }

    /// Ra, Rq, Rz in sliding windows of five sampling lengths (`5 lambda_c`), every `step` (m).
    pub fn windows(&self, lambda_c: f64, step: f64) -> Vec<Window> {
        let r = self.roughness(lambda_c);
        let dx = self.spacing();
        if r.is_empty() || !(dx > 0.0) || !(step > 0.0) {
            return Vec::new();
        }
        let lr = ((lambda_c / dx).round() as usize).max(1);
        let len = 5 * lr;
        let stride = ((step / dx).round() as usize).max(1);
        let mut out = Vec::new();
        let mut start = 0;
        while start + len <= r.len() {
            let seg = &r[start..start + len];
            let ra = seg.iter().map(|v| v.abs()).sum::<f64>() / len as f64;
            let rq = (seg.iter().map(|v| v * v).sum::<f64>() / len as f64).sqrt();
            let rz = seg
                .chunks(lr)
                .map(|c| c.iter().fold(f64::NEG_INFINITY, |m, v| m.max(*v)) - c.iter().fold(f64::INFINITY, |m, v| m.min(*v)))
                .sum::<f64>()
                / 5.0;
            out.push(Window { x: self.x[start + len / 2], ra, rq, rz });
            start += stride;
        }
        out
    }
}

/// Roughness parameters of one window, centred at `x` (all m).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Window {
    pub x: f64,
    pub ra: f64,
    pub rq: f64,
    pub rz: f64,
}

/// Pearson correlation of two equally long series (NaN when either is constant).
pub fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len()) as f64;
    if n < 2.0 {
        return f64::NAN;
    }
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma).powi(2);
        sbb += (y - mb).powi(2);
    }
    sab / (saa * sbb).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sine(wavelength: f64, amplitude: f64) -> Profile {
        let dx = 1e-6;
        let x: Vec<f64> = (0..20_000).map(|k| k as f64 * dx).collect();
        let z = x.iter().map(|x| amplitude * (std::f64::consts::TAU * x / wavelength).sin()).collect();
        Profile { x, z, source: "test".into() }
    }

    /// ISO 16610-21: the Gaussian filter passes 50 % of a sine at the cut-off wavelength into the mean
    /// line; long waves pass (exp(-pi alpha^2 (lc/l)^2) transmission), short waves are removed.
    #[test]
    fn gaussian_filter_transmission() {
        for (wl, want) in [(0.8e-3, 0.5), (4e-3, (-std::f64::consts::PI * ALPHA * ALPHA * (0.8f64 / 4.0).powi(2)).exp()), (0.08e-3, 0.0)] {
            let p = sine(wl, 1e-6);
            let m = p.mean_line(0.8e-3);
            // Amplitude of the mean line in the middle (away from the ends).
            let mid = &m[5000..15000];
            let amp = mid.iter().fold(0.0f64, |a, v| a.max(v.abs())) / 1e-6;
            assert!((amp - want).abs() < 0.01, "wavelength {wl}: transmission {amp} vs {want}");
        }
    }

    /// Ra and Rq of a sine of amplitude a: 2a/pi and a/sqrt(2); Rz: 2a.
    #[test]
    fn ra_rq_rz_of_a_sine() {
        let a = 1e-6;
        let p = sine(0.05e-3, a);
        let w = p.windows(0.8e-3, 1e-3);
        assert!(!w.is_empty());
        let mid = &w[w.len() / 2];
        assert!((mid.ra / (2.0 * a / std::f64::consts::PI) - 1.0).abs() < 0.01, "{mid:?}");
        assert!((mid.rq / (a / 2f64.sqrt()) - 1.0).abs() < 0.01);
        assert!((mid.rz / (2.0 * a) - 1.0).abs() < 0.01);
    }

    #[test]
    fn correlation_basics() {
        assert!((correlation(&[1.0, 2.0, 3.0], &[2.0, 4.0, 6.0]) - 1.0).abs() < 1e-12);
        assert!((correlation(&[1.0, 2.0, 3.0], &[3.0, 2.0, 1.0]) + 1.0).abs() < 1e-12);
    }
}
