//! A SYNTHETIC roughness profile for the paper demo. The repository has no measured data (the paper's
//! Alicona profile, seed 001 Fig. 9, is not available); this model stands in for it and is named
//! synthetic wherever it appears. Real users bring their own X3P or CSV.
//!
//! Model, along the cut at workpiece x (seeded, deterministic):
//! - feed marks of a ball-end mill (radius 5 mm, 2 teeth, 12000 rpm as in the paper): cusps spaced by
//!   the feed per tooth `f_z = f / (n z)` with height `f_z^2 / (8 R)`, at the local simulated feed `f`;
//! - base roughness: Gaussian noise (0.15 um rms) smoothed over 6 um;
//! - rubbing: extra noise of rms `1.2 um * (1 - f/F)^2` where the simulated feed `f` fell below the
//!   programmed `F` (the paper attributes the defect to rubbing at low feed, 23-27 mm);
//! - waviness: 2 um at 20 mm wavelength (form the ISO 16610-21 filter must remove).

use super::Profile;

/// Parameters of the synthetic model (the defaults are the paper's cut).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyntheticModel {
    pub seed: u64,
    /// Sample spacing, m.
    pub spacing: f64,
    pub tool_radius: f64,
    pub teeth: f64,
    pub spindle_rpm: f64,
    pub base_rms: f64,
    pub rubbing_rms: f64,
    pub waviness: f64,
    pub waviness_wavelength: f64,
}

impl Default for SyntheticModel {
    fn default() -> Self {
        SyntheticModel {
            seed: 2017,
            spacing: 2e-6,
            tool_radius: 5e-3,
            teeth: 2.0,
            spindle_rpm: 12_000.0,
            base_rms: 0.15e-6,
            rubbing_rms: 1.2e-6,
            waviness: 2e-6,
            waviness_wavelength: 20e-3,
        }
    }
}

/// splitmix64: a small, well-known seeded generator (no dependency, stable across platforms).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn uniform(&mut self) -> f64 {
        ((self.next() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    /// Standard normal (Box-Muller).
    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// Generate a profile over `[x0, x1]` (m); `feed` gives the simulated tool-tip feed and the
/// programmed feed (m/s) at x, e.g. from a simulation of the program.
pub fn profile(x0: f64, x1: f64, feed: &dyn Fn(f64) -> (f64, f64), model: &SyntheticModel) -> Profile {
    let n = ((x1 - x0) / model.spacing).round() as usize + 1;
    let mut rng = Rng(model.seed);
    let white: Vec<f64> = (0..n).map(|_| rng.normal()).collect();
    let rub: Vec<f64> = (0..n).map(|_| rng.normal()).collect();
    // Smooth the white noise over ~6 um (3 samples each side), keeping unit variance.
    let smooth = |v: &[f64], i: usize| -> f64 {
        let (lo, hi) = (i.saturating_sub(3), (i + 3).min(n - 1));
        v[lo..=hi].iter().sum::<f64>() / ((hi - lo + 1) as f64).sqrt()
    };
    let mut phase = 0.0; // cusp phase, in teeth passes
    let mut x = Vec::with_capacity(n);
    let mut z = Vec::with_capacity(n);
    for i in 0..n {
        let xi = x0 + i as f64 * model.spacing;
        let (f, f_prog) = feed(xi);
        let f = f.max(1e-6);
        let fz = f / (model.spindle_rpm / 60.0 * model.teeth);
        phase += model.spacing / fz;
        let frac = phase.fract() - 0.5; // -0.5..0.5 across one cusp
        let cusp = (frac * fz).powi(2) / (2.0 * model.tool_radius) - fz * fz / (24.0 * model.tool_radius);
        let deficit = if f_prog > 0.0 { (1.0 - f / f_prog).clamp(0.0, 1.0) } else { 0.0 };
        let h = cusp
            + model.base_rms * smooth(&white, i)
            + model.rubbing_rms * deficit * deficit * smooth(&rub, i)
            + model.waviness * (std::f64::consts::TAU * xi / model.waviness_wavelength).sin();
        x.push(xi);
        z.push(h);
    }
    Profile { x, z, source: format!("SYNTHETIC profile (fiveaxis model, seed {})", model.seed) }
}
