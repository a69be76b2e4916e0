//! Region lists bounded for hours-long runs: a report lists its first regions in full (at most
//! [`MAX_LISTED`] by default) and folds the rest into [`Unlisted`] (how many, the time inside, the
//! worst figures), so a 10-hour raster's 36,000 regions cost the memory of the cap, not of the program.

use serde::Serialize;

/// Regions listed in full per list unless the user asks for another cap (`--max-listed-regions`).
pub const MAX_LISTED: usize = 1000;

/// One region's figures as the fold sees them, in people's units (None: the list has no such figure).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Figures {
    /// The region's number (None: the list's regions are not numbered).
    pub id: Option<u64>,
    /// Time inside the region, s, and the time it cost beyond the programmed feed, s.
    pub time_s: f64,
    pub time_lost_s: Option<f64>,
    pub peak_c_speed_rpm: Option<f64>,
    pub min_singularity_distance_deg: Option<f64>,
    /// The lowest feed figure of the list's regions (feed limit, actual feed or simulated feed).
    pub min_feed_mm_per_min: Option<f64>,
}

/// A region type a bounded list can fold.
pub trait Listed {
    fn figures(&self) -> Figures;
}

/// The regions past the cap: how many, the first one's id, their total time and their extremes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Unlisted {
    pub count: usize,
    pub first_id: Option<u64>,
    pub time_inside_s: f64,
    pub time_lost_s: Option<f64>,
    pub peak_c_speed_rpm: Option<f64>,
    pub min_singularity_distance_deg: Option<f64>,
    pub min_feed_mm_per_min: Option<f64>,
}

fn fold_opt(a: Option<f64>, b: Option<f64>, f: fn(f64, f64) -> f64) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(f(a, b)),
        (a, b) => a.or(b),
    }
}

impl Unlisted {
    /// Takes one more region's figures.
    pub fn fold(&mut self, f: Figures) {
        self.count += 1;
        if self.count == 1 {
            self.first_id = f.id;
        }
        self.time_inside_s += f.time_s;
        self.time_lost_s = fold_opt(self.time_lost_s, f.time_lost_s, |a, b| a + b);
        self.peak_c_speed_rpm = fold_opt(self.peak_c_speed_rpm, f.peak_c_speed_rpm, f64::max);
        self.min_singularity_distance_deg = fold_opt(self.min_singularity_distance_deg, f.min_singularity_distance_deg, f64::min);
        self.min_feed_mm_per_min = fold_opt(self.min_feed_mm_per_min, f.min_feed_mm_per_min, f64::min);
    }

    /// True when every region is listed.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// One line for people, or None when every region is listed.
    pub fn describe(&self) -> Option<String> {
        if self.count == 0 {
            return None;
        }
        let from = self.first_id.map_or(String::new(), |id| format!("from #{id}, "));
        let mut s = format!("... and {} more regions ({from}not listed: raise --max-listed-regions): {:.2} s inside", self.count, self.time_inside_s);
        if let Some(l) = self.time_lost_s {
            s += &format!(", {l:.2} s lost");
        }
        if let Some(p) = self.peak_c_speed_rpm {
            s += &format!(", peak {p:.1} rpm");
        }
        if let Some(d) = self.min_singularity_distance_deg {
            s += &format!(", closest {d:.3} deg");
        }
        if let Some(f) = self.min_feed_mm_per_min {
            s += &format!(", feed down to {f:.0} mm/min");
        }
        Some(s)
    }
}

/// Appends `item` to `list` while it holds fewer than `cap`, else folds it into `unlisted`.
pub fn push<T: Listed>(list: &mut Vec<T>, unlisted: &mut Unlisted, cap: usize, item: T) {
    if list.len() < cap {
        list.push(item);
    } else {
        unlisted.fold(item.figures());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct R(u64, f64);
    impl Listed for R {
        fn figures(&self) -> Figures {
            Figures { id: Some(self.0), time_s: 1.0, peak_c_speed_rpm: Some(self.1), ..Figures::default() }
        }
    }

    #[test]
    fn keeps_the_first_and_folds_the_rest() {
        let (mut list, mut u) = (Vec::new(), Unlisted::default());
        for (k, rpm) in [30.0, 50.0, 40.0, 90.0, 35.0].into_iter().enumerate() {
            push(&mut list, &mut u, 2, R(k as u64 + 1, rpm));
        }
        assert_eq!(list.iter().map(|r| r.0).collect::<Vec<_>>(), [1, 2]);
        assert_eq!((u.count, u.first_id, u.time_inside_s, u.peak_c_speed_rpm), (3, Some(3), 3.0, Some(90.0)));
        assert_eq!((u.time_lost_s, u.min_feed_mm_per_min), (None, None));
    }
}
