//! The actual stream's five-axis samples, kept for the figures that need the whole recording first
//! (each region's lowest feed and time lost, known once the regions are): the first
//! [`IN_MEMORY`] in memory, the rest spilled to an unlinked temporary file, so memory stays flat
//! whatever the recording's length. Read back once, in order, by [`region_figures`].

use std::io::{BufReader, BufWriter, Read, Seek, SeekFrom, Write};

/// Cut samples kept in memory before the rest go to a temporary file (48 MB).
pub const IN_MEMORY: usize = 1 << 20;

/// A sample of simultaneous five-axis motion of an actual stream.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cut {
    /// Stamp (s), workpiece x (m), tool-tip step from the previous sample (m), path and programmed
    /// feed (m/s), program line (0: unknown).
    pub t: f64,
    pub x: f64,
    pub ds: f64,
    pub feed: f64,
    pub programmed: f64,
    pub line: u32,
}

const RECORD: usize = 5 * 8 + 4;

impl Cut {
    fn to_bytes(self) -> [u8; RECORD] {
        let mut b = [0u8; RECORD];
        for (k, v) in [self.t, self.x, self.ds, self.feed, self.programmed].into_iter().enumerate() {
            b[8 * k..8 * k + 8].copy_from_slice(&v.to_le_bytes());
        }
        b[40..].copy_from_slice(&self.line.to_le_bytes());
        b
    }

    fn from_bytes(b: &[u8; RECORD]) -> Cut {
        let f = |k: usize| f64::from_le_bytes(b[8 * k..8 * k + 8].try_into().expect("8 bytes"));
        Cut { t: f(0), x: f(1), ds: f(2), feed: f(3), programmed: f(4), line: u32::from_le_bytes(b[40..].try_into().expect("4 bytes")) }
    }
}

/// The cut samples of one stream, in arrival order.
#[derive(Debug, Default)]
pub struct CutLog {
    memory: Vec<Cut>,
    spill: Option<BufWriter<std::fs::File>>,
    spilled: u64,
    /// Every sample has a program line, and the lines never decrease (regions are then matched by line).
    by_line: bool,
    last_line: u32,
    error: Option<std::io::Error>,
}

impl CutLog {
    pub fn new() -> CutLog {
        CutLog { by_line: true, ..Default::default() }
    }

    pub fn len(&self) -> u64 {
        self.memory.len() as u64 + self.spilled
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// True if the samples can be matched to regions by program line (known on every one, never
    /// decreasing).
    pub fn by_line(&self) -> bool {
        !self.is_empty() && self.by_line
    }

    pub fn push(&mut self, c: Cut) {
        self.by_line &= c.line > 0 && c.line >= self.last_line;
        self.last_line = c.line;
        if self.memory.len() < IN_MEMORY {
            self.memory.push(c);
            return;
        }
        if self.error.is_some() {
            return;
        }
        if self.spill.is_none() {
            match tempfile::tempfile() {
                Ok(f) => self.spill = Some(BufWriter::with_capacity(1 << 20, f)),
                Err(e) => {
                    self.error = Some(std::io::Error::new(e.kind(), format!("cannot open a temporary file for the cut samples beyond the first {IN_MEMORY}: {e}")));
                    return;
                }
            }
        }
        if let Some(w) = self.spill.as_mut() {
            match w.write_all(&c.to_bytes()) {
                Ok(()) => self.spilled += 1,
                Err(e) => self.error = Some(std::io::Error::new(e.kind(), format!("cannot write the cut samples to a temporary file after {} of them: {e}", self.len()))),
            }
        }
    }

    /// Every sample in arrival order. An error if the temporary file failed (the figures would miss
    /// samples: not reported as if complete).
    pub fn for_each(&mut self, mut f: impl FnMut(&Cut)) -> std::io::Result<()> {
        if let Some(e) = &self.error {
            return Err(std::io::Error::new(e.kind(), e.to_string()));
        }
        self.memory.iter().for_each(&mut f);
        let Some(w) = self.spill.take() else { return Ok(()) };
        let io = |e: std::io::Error| std::io::Error::new(e.kind(), format!("reading the cut samples back from the temporary file: {e}"));
        let mut file = w.into_inner().map_err(|e| io(e.into_error()))?;
        file.seek(SeekFrom::Start(0)).map_err(io)?;
        let mut r = BufReader::with_capacity(1 << 20, &mut file);
        let mut b = [0u8; RECORD];
        for _ in 0..self.spilled {
            r.read_exact(&mut b).map_err(io)?;
            f(&Cut::from_bytes(&b));
        }
        drop(r);
        self.spill = Some(BufWriter::new(file));
        Ok(())
    }
}

/// What a region's samples of the actual stream show.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegionFigures {
    /// Lowest tool-tip feed (m/s; infinite without a sample).
    pub lowest: f64,
    /// Time lost against the programmed feed, s (`None` without a sample).
    pub lost: Option<f64>,
}

/// A region to measure: its program lines and its x range (m).
#[derive(Debug, Clone, Copy)]
pub struct RegionSpan {
    pub lines: (u32, u32),
    pub x: (f64, f64),
}

/// The figures of each region over the samples inside it, in one pass over `cuts`. With program lines
/// on both sides (`cuts.by_line()` and the region's lines known), a region's samples are those of its
/// lines (one pass: a raster crossing the same x again is another pass) within its x range; without,
/// every sample within its x range. Time lost sums, over consecutive samples inside, the time taken
/// less the time at the programmed feed.
pub fn region_figures(cuts: &mut CutLog, regions: &[RegionSpan], mut each: impl FnMut(&Cut)) -> std::io::Result<Vec<RegionFigures>> {
    let by_line = cuts.by_line();
    let lined = |r: &RegionSpan| by_line && r.lines.0 > 0 && r.lines.1 >= r.lines.0;
    // Regions matched by line, in order of their first line; the others are checked on every sample.
    let mut order: Vec<usize> = (0..regions.len()).filter(|&i| lined(&regions[i])).collect();
    order.sort_by_key(|&i| regions[i].lines.0);
    let by_x: Vec<usize> = (0..regions.len()).filter(|&i| !lined(&regions[i])).collect();
    let zero: f64 = std::iter::empty::<f64>().sum();
    let mut acc: Vec<(f64, f64, Option<Cut>)> = vec![(f64::INFINITY, zero, None); regions.len()];
    let (mut next, mut active): (usize, Vec<usize>) = (0, Vec::new());
    let visit = |i: usize, c: &Cut, acc: &mut Vec<(f64, f64, Option<Cut>)>| {
        let r = &regions[i];
        if c.x < r.x.0 || c.x > r.x.1 {
            return;
        }
        let a = &mut acc[i];
        a.0 = a.0.min(c.feed);
        if let Some(p) = a.2 {
            a.1 += (c.t - p.t) - if c.programmed > 0.0 { c.ds / c.programmed } else { 0.0 };
        }
        a.2 = Some(*c);
    };
    cuts.for_each(|c| {
        each(c);
        if by_line {
            while next < order.len() && regions[order[next]].lines.0 <= c.line {
                active.push(order[next]);
                next += 1;
            }
            // Lines never decrease: a region whose lines are behind is done.
            active.retain(|&i| regions[i].lines.1 >= c.line);
            for &i in &active {
                visit(i, c, &mut acc);
            }
        }
        for &i in &by_x {
            visit(i, c, &mut acc);
        }
    })?;
    Ok(acc.into_iter().map(|(lowest, lost, last)| RegionFigures { lowest, lost: last.map(|_| lost) }).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cut(k: usize) -> Cut {
        let u = k as f64;
        Cut { t: u * 1e-3, x: (u * 0.37).sin() * 0.05, ds: 1e-5 * (1.0 + (u * 0.11).cos().abs()), feed: 0.02 + 0.01 * (u * 0.05).sin(), programmed: 0.0333, line: 1 + (k / 700) as u32 }
    }

    /// Spilled samples come back bit for bit, in order, after the in-memory ones.
    #[test]
    fn spilled_samples_read_back_in_order() {
        let mut log = CutLog::new();
        let n = IN_MEMORY + 12_345;
        (0..n).for_each(|k| log.push(cut(k)));
        assert!(log.by_line());
        let mut k = 0;
        log.for_each(|c| {
            assert_eq!(*c, cut(k));
            k += 1;
        })
        .unwrap();
        assert_eq!(k, n);
    }

    /// The one-pass figures equal a direct filter of the samples per region (the definition).
    #[test]
    fn figures_equal_the_direct_filter() {
        let all: Vec<Cut> = (0..20_000).map(cut).collect();
        let mut log = CutLog::new();
        all.iter().for_each(|c| log.push(*c));
        let regions = [
            RegionSpan { lines: (3, 5), x: (-0.01, 0.02) },
            RegionSpan { lines: (4, 4), x: (-0.05, 0.05) },
            RegionSpan { lines: (0, 0), x: (0.0, 0.01) },
            RegionSpan { lines: (20, 29), x: (0.03, 0.04) },
            RegionSpan { lines: (90, 95), x: (-1.0, 1.0) },
        ];
        let got = region_figures(&mut log, &regions, |_| {}).unwrap();
        for (r, g) in regions.iter().zip(&got) {
            let inside: Vec<&Cut> = all
                .iter()
                .filter(|c| c.x >= r.x.0 && c.x <= r.x.1 && (r.lines.0 == 0 || (c.line >= r.lines.0 && c.line <= r.lines.1)))
                .collect();
            let lowest = inside.iter().map(|c| c.feed).fold(f64::INFINITY, f64::min);
            let lost: f64 = inside.windows(2).map(|w| (w[1].t - w[0].t) - w[1].ds / w[1].programmed).sum();
            assert_eq!(g.lowest, lowest);
            assert_eq!(g.lost, (!inside.is_empty()).then_some(lost));
        }
    }
}
