//! The charts across the part: |C| speed, feed and roughness against the workpiece x in mm, stacked in
//! one 2D view so that they share one x axis, drawn only over the cutting passes.
//!
//! Rerun's plots run along a timeline, and a timeline has no unit (a sequence reads `#25 000`), so
//! these charts are drawn as 2D geometry: x in mm is the view's x, each chart maps its values onto a
//! band of the view, and the axes, grid, tick labels (mm, rpm, mm/min, um) and legends are drawn with
//! it. A pass is [`fiveaxis::scene::PassTracker`]'s; passes at a clearance height are left out
//! ([`fiveaxis::scene::in_contact`]). The layout is pure ([`Layout`]); [`Across`] keeps the passes
//! (bounded) and logs them.

use fiveaxis::scene::{in_contact, Row, PASS_MIN_LENGTH_MM};
use rerun::components::Radius;
use rerun::RecordingStream;
use std::collections::{BTreeMap, BTreeSet};

/// Samples kept per pass and stream; past it every other one is dropped (the chart resolution is far
/// coarser).
const PASS_CAP: usize = 16_384;
/// Passes kept per stream (the oldest go first): an hours-long raster keeps its latest.
const MAX_PASSES: usize = 48;

/// Round numbers for axis ticks: about `n` steps of 1, 2 or 5 times a power of ten covering `lo..hi`.
pub fn nice_step(lo: f64, hi: f64, n: f64) -> f64 {
    let raw = ((hi - lo).abs() / n.max(1.0)).max(1e-9);
    let mag = 10f64.powf(raw.log10().floor());
    let f = raw / mag;
    mag * if f <= 1.0 {
        1.0
    } else if f <= 2.0 {
        2.0
    } else if f <= 5.0 {
        5.0
    } else {
        10.0
    }
}

/// `lo..hi` widened to multiples of `step`.
fn snap(lo: f64, hi: f64, step: f64) -> (f64, f64) {
    let (a, b) = ((lo / step).floor() * step, (hi / step).ceil() * step);
    if b - a < step {
        (a, a + step)
    } else {
        (a, b)
    }
}

/// Format a tick value without trailing zeros noise.
fn tick_text(v: f64, step: f64) -> String {
    let decimals = if step >= 1.0 { 0 } else { (-step.log10()).ceil() as usize };
    format!("{v:.decimals$}")
}

/// `v` with `decimals` decimals, never "-0.00".
fn fixed(v: f64, decimals: usize) -> String {
    let scale = 10f64.powi(decimals as i32);
    format!("{:.decimals$}", (v * scale).round() / scale + 0.0)
}

/// A line segment in the view, from one point to another.
pub type Segment = [[f32; 2]; 2];

/// One chart's value range and its band in the view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Band {
    pub lo: f64,
    pub hi: f64,
    pub step: f64,
    /// View y of the band's top (the view's y grows downwards) and its height.
    pub top: f64,
    pub height: f64,
}

impl Band {
    /// View y of value `v`.
    pub fn y(&self, v: f64) -> f32 {
        (self.top + self.height * (1.0 - (v - self.lo) / (self.hi - self.lo))) as f32
    }
}

/// The stacked charts: a common x range (mm) and one band per chart.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    pub x_lo: f64,
    pub x_hi: f64,
    pub x_step: f64,
    pub bands: Vec<Band>,
}

impl Layout {
    /// Charts over `x_lo..x_hi` mm with value ranges `ranges` (each `(min, max)`), top to bottom. Each
    /// band is 0.17 of the width high, with room between them for the x tick labels and titles.
    pub fn new(x_lo: f64, x_hi: f64, ranges: &[(f64, f64)]) -> Layout {
        let x_step = nice_step(x_lo, x_hi, 10.0);
        let (x_lo, x_hi) = snap(x_lo, x_hi, x_step);
        let w = x_hi - x_lo;
        let (height, gap) = (0.17 * w, 0.085 * w);
        let bands = ranges
            .iter()
            .enumerate()
            .map(|(i, &(lo, hi))| {
                let (lo, hi) = if hi > lo { (lo, hi) } else { (lo - 1.0, lo + 1.0) };
                let step = nice_step(lo, hi, 4.0);
                let (lo, hi) = snap(lo, hi, step);
                Band { lo, hi, step, top: i as f64 * (height + gap), height }
            })
            .collect();
        Layout { x_lo, x_hi, x_step, bands }
    }

    fn ticks(lo: f64, hi: f64, step: f64) -> impl Iterator<Item = f64> {
        let n = ((hi - lo) / step).round() as i64;
        (0..=n).map(move |k| lo + k as f64 * step)
    }

    /// Frame and grid lines of band `b`.
    pub fn grid(&self, b: &Band) -> (Vec<Segment>, Vec<Segment>) {
        let (x0, x1) = (self.x_lo as f32, self.x_hi as f32);
        let (top, bottom) = (b.top as f32, (b.top + b.height) as f32);
        let frame = vec![[[x0, top], [x1, top]], [[x1, top], [x1, bottom]], [[x1, bottom], [x0, bottom]], [[x0, bottom], [x0, top]]];
        let mut grid: Vec<Segment> = Self::ticks(self.x_lo, self.x_hi, self.x_step).map(|x| [[x as f32, top], [x as f32, bottom]]).collect();
        grid.extend(Self::ticks(b.lo, b.hi, b.step).map(|v| [[x0, b.y(v)], [x1, b.y(v)]]));
        (frame, grid)
    }

    /// Tick labels of band `b`: positions and texts (x in mm below the band, values left of it).
    pub fn labels(&self, b: &Band, unit: &str) -> Vec<([f32; 2], String)> {
        let w = self.x_hi - self.x_lo;
        let below = (b.top + b.height + 0.022 * w) as f32;
        let mut out: Vec<([f32; 2], String)> =
            Self::ticks(self.x_lo, self.x_hi, self.x_step).map(|x| ([x as f32, below], format!("{} mm", tick_text(x, self.x_step)))).collect();
        let left = (self.x_lo - 0.045 * w) as f32;
        out.extend(Self::ticks(b.lo, b.hi, b.step).map(|v| ([left, b.y(v)], format!("{} {unit}", tick_text(v, b.step)))));
        out
    }
}

/// The values of one sample on a pass, per chart series.
#[derive(Default)]
struct PassData {
    x: Vec<f64>,
    c_speed: Vec<f64>,
    c_predicted: Vec<f64>,
    feed: Vec<f64>,
    programmed: Vec<f64>,
    /// Keep one sample in `stride`; `seen` counts the pass's samples.
    stride: usize,
    seen: usize,
    x_min: f64,
    x_max: f64,
    z_min: f64,
    /// Largest kept value of the measured and predicted |C| speed (rpm), the path feed and the
    /// programmed feed (mm/min), for the charts' ranges without a scan of every pass.
    c_speed_max: f64,
    c_predicted_max: f64,
    feed_max: f64,
    programmed_max: f64,
    y_sum: f64,
    n: f64,
}

impl PassData {
    fn new() -> PassData {
        PassData { stride: 1, x_min: f64::INFINITY, x_max: f64::NEG_INFINITY, z_min: f64::INFINITY, ..Default::default() }
    }
    fn push(&mut self, r: &Row) {
        let [x, y, z] = r.tool_tip_mm;
        self.x_min = self.x_min.min(x);
        self.x_max = self.x_max.max(x);
        self.z_min = self.z_min.min(z);
        self.y_sum += y;
        self.n += 1.0;
        self.seen += 1;
        if !(self.seen - 1).is_multiple_of(self.stride) {
            return;
        }
        let (c, cp, f, fp) = (r.c_speed_rpm.abs(), r.predicted_c_speed_rpm.abs(), r.path_feed_mm_min, r.programmed_feed_mm_min);
        self.c_speed_max = speed_max(self.c_speed_max, c);
        self.c_predicted_max = speed_max(self.c_predicted_max, cp);
        self.feed_max = feed_max(self.feed_max, f);
        self.programmed_max = feed_max(self.programmed_max, fp);
        self.x.push(x);
        self.c_speed.push(c);
        self.c_predicted.push(cp);
        self.feed.push(f);
        self.programmed.push(fp);
        if self.x.len() >= PASS_CAP {
            for v in [&mut self.x, &mut self.c_speed, &mut self.c_predicted, &mut self.feed, &mut self.programmed] {
                let kept: Vec<f64> = v.iter().step_by(2).copied().collect();
                *v = kept;
            }
            self.stride *= 2;
            // The ranges follow what is kept, as the lines drawn do.
            self.c_speed_max = self.c_speed.iter().copied().fold(0.0, speed_max);
            self.c_predicted_max = self.c_predicted.iter().copied().fold(0.0, speed_max);
            self.feed_max = self.feed.iter().copied().fold(0.0, feed_max);
            self.programmed_max = self.programmed.iter().copied().fold(0.0, feed_max);
        }
    }
    fn length(&self) -> f64 {
        self.x_max - self.x_min
    }
    fn y_mean(&self) -> f64 {
        self.y_sum / self.n.max(1.0)
    }
}

/// The larger of a running maximum and a finite value (a |C| speed, rpm).
fn speed_max(m: f64, v: f64) -> f64 {
    if v.is_finite() { m.max(v) } else { m }
}

/// The same for a feed (mm/min): feeds of 1e7 mm/min and more are not plotted to scale.
fn feed_max(m: f64, v: f64) -> f64 {
    if v.is_finite() && v < 1e7 { m.max(v) } else { m }
}

/// Colours of the series (the same as the time plots').
pub fn color(name: &str) -> [u8; 3] {
    match name {
        "commanded" => [66, 133, 244],
        "simulated" => [255, 140, 0],
        "machine" => [52, 168, 83],
        "predicted" => [219, 68, 55],
        "programmed" => [150, 150, 150],
        "limit" | "axis_limit" => [190, 190, 190],
        "roughness" => [200, 200, 200],
        "ra" => [230, 200, 60],
        _ => [200, 200, 200],
    }
}

/// The roughness profile along x: (x mm, height um) after the filter, the sliding Ra (x mm, um), the
/// label's prefix (e.g. "SYNTHETIC ") and the cut-off, mm.
struct ProfileLines {
    heights: Vec<(f64, f64)>,
    ra: Vec<(f64, f64)>,
    label: String,
    lambda_c_mm: f64,
}

/// What a full draw was made for: the layout, the passes drawn (stream, number), the profile's pass.
type DrawnFor = (Layout, Vec<(&'static str, u32)>, Option<u32>);

/// The passes seen so far, and what to draw of them.
pub struct Across {
    passes: BTreeMap<(&'static str, u32), PassData>,
    profile: Option<ProfileLines>,
    /// The pass the profile was measured on: the one nearest this workpiece y (mm), if given.
    profile_y_mm: Option<f64>,
    contact_band_mm: f64,
    c_limit_rpm: f64,
    rotary: String,
    /// The stream whose passes carry the program's figures (predicted C speed, programmed feed).
    lead: Option<&'static str>,
    dirty: bool,
    /// Passes with samples since the last draw: when the layout and the set of passes drawn are
    /// unchanged, only these are redrawn (a live run's flushes stay proportional to what arrived).
    changed: BTreeSet<(&'static str, u32)>,
    /// What the last full draw was made for.
    last: Option<DrawnFor>,
    drawn: BTreeSet<String>,
}

impl Across {
    pub fn new(contact_band_mm: f64, profile_y_mm: Option<f64>) -> Across {
        Across {
            passes: BTreeMap::new(),
            profile: None,
            profile_y_mm,
            contact_band_mm,
            c_limit_rpm: f64::NAN,
            rotary: "C".into(),
            lead: None,
            dirty: false,
            changed: BTreeSet::new(),
            last: None,
            drawn: BTreeSet::new(),
        }
    }

    /// Set the roughness profile (x mm, um) and its Ra, labelled `label` (cut-off `lambda_c_mm`).
    pub fn set_profile(&mut self, heights: Vec<(f64, f64)>, ra: Vec<(f64, f64)>, label: String, lambda_c_mm: f64) {
        self.profile = Some(ProfileLines { heights, ra, label, lambda_c_mm });
        self.dirty = true;
        self.last = None;
    }

    /// Take one row; `lead` says whether its stream carries the program's figures.
    pub fn row(&mut self, r: &Row, lead: bool) {
        let Some(mark) = r.pass else { return };
        if lead {
            self.lead = Some(r.stream);
        }
        self.c_limit_rpm = r.c_limit_rpm;
        self.rotary.clone_from(&r.rotary[1]);
        let key = (r.stream, mark.id);
        if mark.starts || !self.passes.contains_key(&key) {
            self.passes.insert(key, PassData::new());
            let of_stream: Vec<(&'static str, u32)> = self.passes.keys().filter(|k| k.0 == r.stream).copied().collect();
            for old in of_stream.iter().take(of_stream.len().saturating_sub(MAX_PASSES)) {
                self.passes.remove(old);
            }
        }
        if let Some(p) = self.passes.get_mut(&key) {
            p.push(r);
        }
        self.changed.insert(key);
        self.dirty = true;
    }

    /// The passes drawn: long enough and in contact with the part.
    fn cutting(&self) -> Vec<(&'static str, u32)> {
        let long: Vec<_> = self.passes.iter().filter(|(_, p)| p.length() >= PASS_MIN_LENGTH_MM).collect();
        let floor = long.iter().map(|(_, p)| p.z_min).fold(f64::INFINITY, f64::min);
        long.into_iter().filter(|(_, p)| in_contact(p.z_min, floor, self.contact_band_mm)).map(|(k, _)| *k).collect()
    }

    /// The pass number the roughness profile belongs to: nearest `--roughness-y-mm`, else the first
    /// cutting pass of the lead stream that covers most of the profile's x range.
    fn profile_pass(&self, cutting: &[(&'static str, u32)]) -> Option<u32> {
        let heights = &self.profile.as_ref()?.heights;
        let (p0, p1) = (heights.first()?.0, heights.last()?.0);
        let lead = self.lead?;
        let ours: Vec<(u32, &PassData)> = cutting.iter().filter(|k| k.0 == lead).map(|k| (k.1, &self.passes[k])).collect();
        if let Some(y) = self.profile_y_mm {
            return ours.iter().min_by(|a, b| (a.1.y_mean() - y).abs().total_cmp(&(b.1.y_mean() - y).abs())).map(|p| p.0);
        }
        let cover = |p: &PassData| (p.x_max.min(p1) - p.x_min.max(p0)).max(0.0);
        ours.iter().fold(None::<(u32, f64)>, |best, (id, p)| if best.is_none_or(|b| cover(p) > b.1 + 1e-9) { Some((*id, cover(p))) } else { best }).map(|b| b.0)
    }

    /// Redraw what changed (static entities under `across/`); nothing when nothing did.
    pub fn draw(&mut self, rec: &RecordingStream) -> anyhow::Result<()> {
        if !self.dirty {
            return Ok(());
        }
        self.dirty = false;
        let cutting = self.cutting();
        let profile_pass = self.profile_pass(&cutting);
        let (mut x_lo, mut x_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut c_max, mut f_max) = (self.c_limit_rpm.max(0.0) * 1.25, 0.0f64);
        for k in &cutting {
            let p = &self.passes[k];
            x_lo = x_lo.min(p.x_min);
            x_hi = x_hi.max(p.x_max);
            c_max = c_max.max(p.c_speed_max);
            f_max = f_max.max(p.feed_max);
            if Some(k.0) == self.lead {
                c_max = c_max.max(p.c_predicted_max);
                f_max = f_max.max(p.programmed_max);
            }
        }
        let mut r_max = 0.0f64;
        if let Some(h) = self.profile.as_ref().map(|p| &p.heights) {
            if let (Some(a), Some(b)) = (h.first(), h.last()) {
                x_lo = x_lo.min(a.0);
                x_hi = x_hi.max(b.0);
            }
            r_max = h.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
        }
        if !x_lo.is_finite() {
            return Ok(());
        }
        let r_max = if r_max > 0.0 { r_max } else { 1.0 };
        let layout = Layout::new(x_lo, x_hi, &[(0.0, c_max.max(1.0)), (0.0, f_max.max(1.0)), (-r_max, r_max)]);
        let changed = std::mem::take(&mut self.changed);
        let what = (layout.clone(), cutting.clone(), profile_pass);
        let full = self.last.as_ref() != Some(&what);
        self.last = Some(what);
        let mut now: BTreeSet<String> = BTreeSet::new();
        let rot = self.rotary.clone();
        let titles = [
            format!("|{rot}| speed, rpm: measured on each stream, predicted by eq. 5 (red), limit (grey)"),
            "path feed, mm/min: programmed (grey), commanded and simulated".to_string(),
            self.profile.as_ref().map_or("roughness: no profile given (--roughness)".to_string(), |p| format!("{}roughness profile, um, lambda_c {} mm; Ra over 5 lambda_c (yellow)", p.label, p.lambda_c_mm)),
        ];
        let units = ["rpm", "mm/min", "um"];
        let w = layout.x_hi - layout.x_lo;
        for (i, b) in layout.bands.iter().enumerate().filter(|_| full) {
            let (frame, grid) = layout.grid(b);
            let path = format!("across/axes/{i}");
            rec.log_static(
                path.as_str(),
                &rerun::LineStrips2D::new(frame.iter().chain(&grid).map(|s| s.to_vec()))
                    .with_colors(frame.iter().map(|_| [150, 150, 150]).chain(grid.iter().map(|_| [60, 60, 60])).map(|[r, g, b]| rerun::Color::from_rgb(r, g, b)).collect::<Vec<_>>())
                    .with_radii([Radius::new_ui_points(0.5)])
                    .with_draw_order(-10.0),
            )?;
            now.insert(path);
            let (pos, text): (Vec<[f32; 2]>, Vec<String>) = layout.labels(b, units[i]).into_iter().unzip();
            let path = format!("across/ticks/{i}");
            rec.log_static(path.as_str(), &rerun::Points2D::new(pos).with_labels(text).with_radii([0.0f32]).with_colors([[170, 170, 170]]).with_show_labels(true))?;
            now.insert(path);
            let path = format!("across/titles/{i}");
            rec.log_static(
                path.as_str(),
                &rerun::Points2D::new([[(layout.x_lo + 0.5 * w) as f32, (b.top - 0.03 * w) as f32]]).with_labels([titles[i].clone()]).with_radii([0.0f32]).with_colors([[220, 220, 220]]).with_show_labels(true),
            )?;
            now.insert(path);
        }
        let strip = |x: &[f64], v: &[f64], b: &Band| -> Vec<Vec<[f32; 2]>> {
            // Split at non-finite values; clamp to the band so a spike stays inside its chart.
            let mut out = vec![Vec::new()];
            for (x, v) in x.iter().zip(v) {
                if v.is_finite() {
                    if let Some(s) = out.last_mut() {
                        s.push([*x as f32, b.y(v.clamp(b.lo, b.hi))]);
                    }
                } else if out.last().is_some_and(|s| !s.is_empty()) {
                    out.push(Vec::new());
                }
            }
            out.retain(|s| s.len() > 1);
            out
        };
        let (bc, bf, br) = (layout.bands[0], layout.bands[1], layout.bands[2]);
        let mut log_line = |path: String, lines: Vec<Vec<[f32; 2]>>, name: &str, width: f32, order: f32| -> anyhow::Result<()> {
            if lines.is_empty() {
                return Ok(());
            }
            rec.log_static(path.as_str(), &rerun::LineStrips2D::new(lines).with_colors([color(name)]).with_radii([Radius::new_ui_points(width)]).with_draw_order(order))?;
            now.insert(path);
            Ok(())
        };
        for k in cutting.iter().filter(|k| full || changed.contains(*k)) {
            let p = &self.passes[k];
            let (st, id) = *k;
            let main = profile_pass.is_none_or(|pp| pp == id);
            let width = if main { 1.2 } else { 0.6 };
            let lead = Some(st) == self.lead;
            log_line(format!("across/c_speed/pass_{id}/{st}"), strip(&p.x, &p.c_speed, &bc), st, width, 3.0)?;
            log_line(format!("across/feed/pass_{id}/{st}"), strip(&p.x, &p.feed, &bf), st, width, 3.0)?;
            if lead {
                // The prediction on top, thinner, so the measured line under it still shows.
                log_line(format!("across/c_speed/pass_{id}/predicted"), strip(&p.x, &p.c_predicted, &bc), "predicted", 0.7 * width, 4.0)?;
                log_line(format!("across/feed/pass_{id}/programmed"), strip(&p.x, &p.programmed, &bf), "programmed", width, 1.0)?;
            }
        }
        if full && self.c_limit_rpm.is_finite() {
            let y = bc.y(self.c_limit_rpm.clamp(bc.lo, bc.hi));
            log_line("across/c_speed/limit".into(), vec![vec![[layout.x_lo as f32, y], [layout.x_hi as f32, y]]], "limit", 0.8, 1.0)?;
        }
        if let Some(ProfileLines { heights: h, ra, .. }) = self.profile.as_ref().filter(|_| full) {
            let (x, v): (Vec<f64>, Vec<f64>) = h.iter().copied().unzip();
            log_line("across/roughness/profile".into(), strip(&x, &v, &br), "roughness", 0.6, 2.0)?;
            let (x, v): (Vec<f64>, Vec<f64>) = ra.iter().copied().unzip();
            log_line("across/roughness/ra".into(), strip(&x, &v, &br), "ra", 1.2, 3.0)?;
        }
        // Legend of the pass lines: which pass is drawn bold, and where it runs.
        let mut legend: Vec<String> = Vec::new();
        for k in cutting.iter().filter(|k| Some(k.0) == self.lead) {
            let p = &self.passes[k];
            let tag = if profile_pass == Some(k.1) { ", roughness measured here (bold)" } else { "" };
            legend.push(format!("pass {}: x {} to {} mm at y {} mm, z {} mm{tag}", k.1, fixed(p.x_min, 1), fixed(p.x_max, 1), fixed(p.y_mean(), 2), fixed(p.z_min, 2)));
        }
        let streams: BTreeSet<&str> = cutting.iter().map(|k| k.0).collect();
        let names: Vec<&str> = streams.into_iter().collect();
        let bottom = layout.bands.last().map_or(0.0, |b| b.top + b.height) + 0.06 * w;
        let mut pos = Vec::new();
        let mut text = Vec::new();
        let mut colors = Vec::new();
        for (j, s) in names.iter().enumerate() {
            pos.push([(layout.x_lo + j as f64 * 0.14 * w) as f32, bottom as f32]);
            text.push(s.to_string());
            colors.push(rerun::Color::from_rgb(color(s)[0], color(s)[1], color(s)[2]));
        }
        for (j, l) in legend.iter().take(6).enumerate() {
            pos.push([(layout.x_lo + 0.5 * w) as f32, (bottom + (j as f64 + 1.0) * 0.03 * w) as f32]);
            text.push(l.clone());
            colors.push(rerun::Color::from_rgb(200, 200, 200));
        }
        if !pos.is_empty() {
            rec.log_static("across/legend", &rerun::Points2D::new(pos).with_labels(text).with_colors(colors).with_radii([0.0f32]).with_show_labels(true))?;
            now.insert("across/legend".into());
        }
        if full {
            for gone in self.drawn.difference(&now) {
                rec.log_static(gone.as_str(), &rerun::Clear::flat())?;
            }
            self.drawn = now;
        } else {
            self.drawn.extend(now);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(nice_step(0.0, 50.0, 10.0), 5.0);
        assert_eq!(nice_step(0.0, 175.0, 4.0), 50.0);
        assert_eq!(nice_step(-2.3, 2.3, 4.0), 2.0);
        let l = Layout::new(0.0, 50.0, &[(0.0, 175.0), (0.0, 2000.0), (-2.3, 2.3)]);
        assert_eq!((l.x_lo, l.x_hi, l.x_step), (0.0, 50.0, 5.0));
        assert_eq!((l.bands[0].lo, l.bands[0].hi), (0.0, 200.0));
        assert_eq!((l.bands[2].lo, l.bands[2].hi), (-4.0, 4.0));
        // Value hi at the band's top, lo at its bottom; bands do not overlap.
        let b = l.bands[1];
        assert!((b.y(b.hi) as f64 - b.top).abs() < 1e-4 && (b.y(b.lo) as f64 - (b.top + b.height)).abs() < 1e-4);
        assert!(l.bands[0].top + l.bands[0].height < l.bands[1].top);
        let labels = l.labels(&l.bands[0], "rpm");
        assert!(labels.iter().any(|(_, t)| t == "25 mm") && labels.iter().any(|(_, t)| t == "150 rpm"), "{labels:?}");
    }
}
