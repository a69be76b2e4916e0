//! The TNC's drilling cycles as the motion they make along the working plane's tool axis: cycles
//! 200 DRILLING, 201 REAMING, 203 UNIVERSAL DRILLING, 207 RIGID TAPPING, 209 TAPPING WITH CHIP
//! BREAKING, 240 CENTERING, 241 SINGLE-LIP DEEP-HOLE DRILLING and the older cycle 1 PECKING. Pure: levels (absolute, m), dwells (s) and which of the
//! cycle's feeds each move takes; [`super::klartext`] reads the Q parameters and makes the blocks.

use super::cycles::MAX_PECKS;

/// Which of a cycle's feeds a move takes: the plunging feed Q206 (a tapping cycle's pitch times the
/// speed), the retraction feed Q208 (0: Q206's; MAX: rapid), or the pre-positioning feed Q253.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TncFeed {
    Plunge,
    Retract,
    Preposition,
}

/// One move or dwell of a TNC cycle: a rapid (FMAX) or a feed move to a level, or a dwell (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum TncStep {
    Rapid(f64),
    Feed(f64, TncFeed),
    Dwell(f64),
}

/// The depth of the `k`-th infeed of `step` down from `from` (absolute, m), or `bottom` once it is
/// reached: counted, not summed, so that rounding leaves no sliver of a last infeed (20 mm in
/// pecks of 3 summed to 19.999999999999996 mm, and a 4e-15 mm peck followed).
fn infeed(from: f64, step: f64, k: u32, bottom: f64) -> f64 {
    let next = from - f64::from(k) * step;
    if next <= bottom + 1e-9 {
        bottom
    } else {
        next
    }
}

/// The levels a TNC drilling cycle works between, absolute along the tool axis of the working plane
/// (m): the surface Q203, the set-up clearance Q200 and 2nd set-up clearance Q204 above it, the depth
/// Q201 (negative: below the surface).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TncLevels {
    pub surface: f64,
    pub clearance: f64,
    pub clearance2: f64,
    pub depth: f64,
}

impl TncLevels {
    /// The set-up clearance above the surface: where the cycle starts and a retraction ends.
    fn top(&self) -> f64 {
        self.surface + self.clearance
    }

    /// The hole's bottom.
    fn bottom(&self) -> f64 {
        self.surface + self.depth
    }

    /// Where the cycle ends: at the set-up clearance or, if larger, the 2nd set-up clearance.
    fn out(&self) -> f64 {
        self.surface + self.clearance.max(self.clearance2)
    }
}

/// A Heidenhain drilling cycle's parameters (m, s): its levels, the plunging depth Q202 (0: at
/// once), the dwells at the top Q210 and at the bottom Q211, and the feed the tool comes back out
/// of the hole at (`None`: rapid; tapping: its plunging feed; reaming: the retraction feed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TncHole {
    pub levels: TncLevels,
    pub plunge: f64,
    pub dwell_top_s: f64,
    pub dwell_bottom_s: f64,
    pub out_at: Option<TncFeed>,
}

/// The moves of a Heidenhain drilling cycle at the current position (TNC 426/430 User's Manual
/// §8.3, cycle 200 DRILLING: "the TNC positions the tool in the spindle axis at rapid traverse FMAX
/// to the set-up clearance above the workpiece surface"; drills to each plunging depth at feed,
/// "returns the tool at FMAX to the set-up clearance, dwells there, and then moves at FMAX to the
/// set-up clearance above the" depth reached; at the bottom dwells and retracts at FMAX to the
/// set-up clearance or, if larger, the 2nd set-up clearance. Cycle 240 CENTERING is one plunge;
/// cycle 207 RIGID TAPPING comes back at feed; cycle 201 REAMING, one plunge, comes back at its
/// retraction feed Q208, "the traversing speed of the tool when retracting from the hole", to the
/// set-up clearance, as cycle 203 does: iTNC 530 User's Manual DIN/ISO, cycle 201's parameters; the
/// page of its run is not at hand). A depth of 0 makes nothing.
pub(crate) fn tnc_hole(h: &TncHole) -> Vec<TncStep> {
    let l = &h.levels;
    let (top, bottom) = (l.top(), l.bottom());
    if l.depth == 0.0 {
        return Vec::new();
    }
    let mut steps = vec![TncStep::Rapid(top)];
    let q = if h.plunge > 0.0 { h.plunge } else { f64::INFINITY };
    for k in 1.. {
        let next = infeed(l.surface, q, k, bottom);
        steps.push(TncStep::Feed(next, TncFeed::Plunge));
        if next <= bottom {
            break;
        }
        steps.push(TncStep::Rapid(top));
        if h.dwell_top_s > 0.0 {
            steps.push(TncStep::Dwell(h.dwell_top_s));
        }
        steps.push(TncStep::Rapid(next + l.clearance));
    }
    if h.dwell_bottom_s > 0.0 {
        steps.push(TncStep::Dwell(h.dwell_bottom_s));
    }
    if let Some(feed) = h.out_at {
        steps.push(TncStep::Feed(top, feed));
    }
    steps.push(TncStep::Rapid(l.out()));
    steps
}

/// The older TNC cycle 1 PECKING (`CYCL DEF 1.0` to `1.5`): its set-up clearance, total hole depth
/// and pecking depth (magnitudes, program length unit converted to m; the working direction is
/// negative), dwell at the bottom (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TncPecking {
    pub setup: f64,
    pub depth: f64,
    pub peck: f64,
    pub dwell_s: f64,
}

impl TncPecking {
    /// How many infeeds the hole takes.
    pub(crate) fn pecks(&self) -> f64 {
        (self.depth / self.peck).ceil()
    }

    /// The advanced stop distance t the control computes, m: 0.6 mm for a total hole depth up to
    /// 30 mm, else the depth / 50, at most 7 mm.
    pub(crate) fn advanced_stop(&self) -> f64 {
        let mm = crate::units::MM;
        if self.depth <= 30.0 * mm {
            0.6 * mm
        } else {
            (self.depth / 50.0).min(7.0 * mm)
        }
    }
}

/// Cycle 1 PECKING's moves from the tool's position `start` (absolute along the tool axis, m), as
/// the TNC 426/425/415 B/407 manual (ISO Programming, 280 580, §8.2 "PECKING (G83)", the same cycle
/// with the same five inputs) gives its process: the tool drills from the starting point to the
/// first pecking depth at feed, retracts at rapid to the starting position and advances again to
/// the depth reached less the advanced stop distance t, drills the next infeed at feed, and so on
/// to the total hole depth (measured from the surface, the set-up clearance below the start); after
/// the dwell at the bottom it retracts at rapid to the starting position. A pecking depth at least
/// the total depth drills it in one pass.
pub(crate) fn tnc_pecking(start: f64, c: &TncPecking) -> Vec<TncStep> {
    let surface = start - c.setup;
    let bottom = surface - c.depth;
    let t = c.advanced_stop();
    let mut steps = Vec::new();
    for k in 1.. {
        let next = infeed(surface, c.peck, k, bottom);
        steps.push(TncStep::Feed(next, TncFeed::Plunge));
        if next <= bottom {
            break;
        }
        steps.push(TncStep::Rapid(start));
        steps.push(TncStep::Rapid(next + t));
    }
    if c.dwell_s > 0.0 {
        steps.push(TncStep::Dwell(c.dwell_s));
    }
    steps.push(TncStep::Rapid(start));
    steps
}

/// Cycle 203 UNIVERSAL DRILLING's parameters (m, s): as [`TncHole`]'s, with the decrement Q212 and
/// the minimum plunging depth Q205, the chip breaks before each retraction Q213 and the distance the
/// tool backs off at each Q256.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TncUniversal {
    pub levels: TncLevels,
    pub plunge: f64,
    pub decrement: f64,
    pub min_plunge: f64,
    pub breaks: u32,
    pub break_distance: f64,
    pub dwell_top_s: f64,
    pub dwell_bottom_s: f64,
}

/// Cycle 203's moves (iTNC 530 User's Manual, cycle 203's parameters: Q212 "decreases the plunging
/// depth Q202 after each infeed", Q205 limits the infeed if a decrement is entered, Q213 chip breaks
/// "before the TNC retracts the tool out of the hole", each backing off by Q256, Q210 the dwell "at
/// set-up clearance after the TNC has retracted it out of the hole", Q208 the feed out of the hole,
/// its Q206 if 0). The run as cycle 200's: FMAX to the set-up clearance, each infeed at Q206; after
/// Q213 chip breaks (none if 0) out at Q208 to the set-up clearance, dwell Q210, FMAX back to the
/// set-up clearance above the depth reached; at the bottom dwell Q211, out at Q208, FMAX to the 2nd
/// set-up clearance. A chip break backs off at Q208 (a move out of the hole; the pages at hand give
/// no other feed for it). The decrement never makes an infeed larger than the one before. An error
/// where the infeeds would shrink to nothing or number more than [`MAX_PECKS`].
pub(crate) fn tnc_universal(c: &TncUniversal) -> Result<Vec<TncStep>, String> {
    let l = &c.levels;
    let (top, bottom) = (l.top(), l.bottom());
    if l.depth == 0.0 {
        return Ok(Vec::new());
    }
    let total = -l.depth;
    let mut step = if c.plunge > 0.0 { c.plunge } else { total };
    let mut steps = vec![TncStep::Rapid(top)];
    let (mut reached, mut broken) = (0.0, 0);
    for n in 1.. {
        if n > MAX_PECKS {
            return Err(format!("more than {MAX_PECKS} infeeds: a typo?"));
        }
        reached += step;
        // Within a nanometre of the bottom is the bottom: no sliver of an infeed is left to rounding.
        let z = if reached >= total - 1e-9 { bottom } else { l.surface - reached };
        steps.push(TncStep::Feed(z, TncFeed::Plunge));
        if z <= bottom {
            break;
        }
        if broken < c.breaks {
            broken += 1;
            if c.break_distance > 0.0 {
                steps.push(TncStep::Feed(z + c.break_distance, TncFeed::Retract));
            }
        } else {
            broken = 0;
            steps.push(TncStep::Feed(top, TncFeed::Retract));
            if c.dwell_top_s > 0.0 {
                steps.push(TncStep::Dwell(c.dwell_top_s));
            }
            steps.push(TncStep::Rapid(z + l.clearance));
        }
        if c.decrement > 0.0 {
            step = (step - c.decrement).max(c.min_plunge.min(step));
            if step <= 0.0 {
                return Err("the decrement Q212 brings the plunging depth to 0 before the depth is reached (Q205, the minimum plunging depth, is 0)".into());
            }
        }
    }
    if c.dwell_bottom_s > 0.0 {
        steps.push(TncStep::Dwell(c.dwell_bottom_s));
    }
    steps.push(TncStep::Feed(top, TncFeed::Retract));
    steps.push(TncStep::Rapid(l.out()));
    Ok(steps)
}

/// Cycle 209 TAPPING WITH CHIP BREAKING's parameters (m): its levels, the infeed depth after which
/// the chip is broken Q257 (0: none) and how far the tool backs off to break it, Q256 times the
/// pitch Q239 (`None`, Q256 = 0: out of the hole to the set-up clearance).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TncChipTapping {
    pub levels: TncLevels,
    pub infeed: f64,
    pub back_off: Option<f64>,
}

/// Cycle 209's moves, from its parameters' definitions (TNC 320 User's Manual for cycle programming
/// 9/2016 §4.4, p. 102: Q257 "Plunging depth after which the TNC breaks the chip. No chip breaking
/// if 0 is entered"; Q256 "The TNC multiplies the pitch Q239 by the programmed value and retracts
/// the tool by the calculated value during chip breaking. If you enter Q256 = 0, the TNC retracts
/// the tool completely from the hole (to the set-up clearance)"; Q403 increases "the retraction
/// feed rate when retracting"), in cycle 207's frame: FMAX to the set-up clearance, each infeed at
/// the tapping feed, each chip break and the way out at the retraction feed, FMAX to the 2nd set-up
/// clearance. The page of its run is not at hand. An error where the infeeds number more than
/// [`MAX_PECKS`].
pub(crate) fn tnc_chip_tapping(c: &TncChipTapping) -> Result<Vec<TncStep>, String> {
    let l = &c.levels;
    let (top, bottom) = (l.top(), l.bottom());
    if l.depth == 0.0 {
        return Ok(Vec::new());
    }
    let q = if c.infeed > 0.0 { c.infeed } else { f64::INFINITY };
    if q.is_finite() && super::cycles::too_many_pecks(l.depth, q) {
        return Err(format!("more than {MAX_PECKS} infeeds: a typo?"));
    }
    let mut steps = vec![TncStep::Rapid(top)];
    for k in 1.. {
        let next = infeed(l.surface, q, k, bottom);
        steps.push(TncStep::Feed(next, TncFeed::Plunge));
        if next <= bottom {
            break;
        }
        let back = c.back_off.map_or(top, |d| (next + d).min(top));
        steps.push(TncStep::Feed(back, TncFeed::Retract));
    }
    steps.push(TncStep::Feed(top, TncFeed::Retract));
    steps.push(TncStep::Rapid(l.out()));
    Ok(steps)
}

/// Cycle 241 SINGLE-LIP DEEP-HOLE DRILLING's parameters (m, s): its levels, the deepened starting
/// point Q379 (a distance below the surface: a pilot hole's depth) and the dwell at the bottom Q211.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TncSingleLip {
    pub levels: TncLevels,
    pub start: f64,
    pub dwell_bottom_s: f64,
}

/// Cycle 241's moves in one infeed: FMAX to the set-up clearance above the surface; with a deepened
/// starting point, at the pre-positioning feed Q253 to the set-up clearance above it (a pilot hole
/// entered slowly, its spindle speed Q427); drilling at Q206 to the depth; the dwell Q211; out at
/// Q208 (0: Q206) to the set-up clearance; FMAX to the 2nd set-up clearance. The run is the
/// cycle's as TNC programs (Autodesk's post, hyperMILL's) use it; the manual's page for it is not
/// at hand. An error if the starting point is at or below the depth.
pub(crate) fn tnc_single_lip(c: &TncSingleLip) -> Result<Vec<TncStep>, String> {
    let l = &c.levels;
    let (top, bottom) = (l.top(), l.bottom());
    if l.depth == 0.0 {
        return Ok(Vec::new());
    }
    if c.start >= -l.depth {
        return Err("the deepened starting point Q379 is at or below the depth Q201".into());
    }
    let mut steps = vec![TncStep::Rapid(top)];
    if c.start > 0.0 {
        steps.push(TncStep::Feed(l.surface - c.start + l.clearance, TncFeed::Preposition));
    }
    steps.push(TncStep::Feed(bottom, TncFeed::Plunge));
    if c.dwell_bottom_s > 0.0 {
        steps.push(TncStep::Dwell(c.dwell_bottom_s));
    }
    steps.push(TncStep::Feed(top, TncFeed::Retract));
    steps.push(TncStep::Rapid(l.out()));
    Ok(steps)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cycle 200 as the manual describes it, with the hyperMILL program's values (Q200=2 set-up
    /// clearance, Q201=-6.5 depth, Q202=2.5 plunge, Q203=0 surface, Q204=50 2nd clearance).
    #[test]
    fn tnc_drilling_moves_as_the_manual_describes() {
        use TncFeed::*;
        use TncStep::*;
        let h = TncHole { levels: TncLevels { surface: 0.0, clearance: 2.0, clearance2: 50.0, depth: -6.5 }, plunge: 2.5, dwell_top_s: 0.5, dwell_bottom_s: 1.0, out_at: None };
        assert_eq!(
            tnc_hole(&h),
            vec![Rapid(2.0), Feed(-2.5, Plunge), Rapid(2.0), Dwell(0.5), Rapid(-0.5), Feed(-5.0, Plunge), Rapid(2.0), Dwell(0.5), Rapid(-3.0), Feed(-6.5, Plunge), Dwell(1.0), Rapid(50.0)]
        );
        assert_eq!(tnc_hole(&TncHole { plunge: 6.5, dwell_top_s: 0.0, dwell_bottom_s: 0.0, ..h }), vec![Rapid(2.0), Feed(-6.5, Plunge), Rapid(50.0)]);
        assert_eq!(tnc_hole(&TncHole { plunge: 0.0, out_at: Some(Plunge), dwell_top_s: 0.0, dwell_bottom_s: 0.0, levels: TncLevels { clearance2: 0.0, ..h.levels }, ..h }), vec![Rapid(2.0), Feed(-6.5, Plunge), Feed(2.0, Plunge), Rapid(2.0)]);
        assert!(tnc_hole(&TncHole { levels: TncLevels { depth: 0.0, ..h.levels }, ..h }).is_empty());
    }

    /// Cycle 1 PECKING as the manual's process runs it, by hand: from Z2 with a set-up clearance of
    /// 2 (surface at 0), a total depth of 10 and pecks of 4, t = 0.6 mm (depth up to 30 mm): feed to
    /// -4, rapid to 2 and down to -3.4, feed to -8, rapid to 2 and down to -7.4, feed to -10, dwell,
    /// rapid to 2. A 40 mm hole's t is 40/50 = 0.8 mm; a 500 mm hole's is capped at 7 mm.
    #[test]
    fn tnc_pecking_moves_as_the_manual_describes() {
        use TncFeed::*;
        use TncStep::*;
        let mm = crate::units::MM;
        let c = TncPecking { setup: 2.0 * mm, depth: 10.0 * mm, peck: 4.0 * mm, dwell_s: 0.5 };
        let got: Vec<TncStep> = tnc_pecking(2.0 * mm, &c);
        let want = [Feed(-4.0, Plunge), Rapid(2.0), Rapid(-3.4), Feed(-8.0, Plunge), Rapid(2.0), Rapid(-7.4), Feed(-10.0, Plunge), Dwell(0.5), Rapid(2.0)];
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(want) {
            match (*g, w) {
                (Feed(a, _), Feed(b, _)) | (Rapid(a), Rapid(b)) => assert!((a / mm - b).abs() < 1e-9, "{got:?}"),
                (Dwell(a), Dwell(b)) => assert_eq!(a, b),
                _ => panic!("{got:?}"),
            }
        }
        assert_eq!(c.pecks(), 3.0);
        // One pass where the peck reaches the bottom; no dwell step for 0 s.
        let once = tnc_pecking(0.0, &TncPecking { peck: 10.0 * mm, dwell_s: 0.0, ..c });
        assert_eq!(once.len(), 2, "{once:?}");
        assert!(matches!(once[0], Feed(z, Plunge) if (z / mm + 12.0).abs() < 1e-9) && matches!(once[1], Rapid(z) if z == 0.0), "{once:?}");
        assert!((TncPecking { depth: 40.0 * mm, ..c }.advanced_stop() / mm - 0.8).abs() < 1e-9);
        assert!((TncPecking { depth: 30.0 * mm, ..c }.advanced_stop() / mm - 0.6).abs() < 1e-9);
        assert!((TncPecking { depth: 500.0 * mm, ..c }.advanced_stop() / mm - 7.0).abs() < 1e-9);
    }

    /// Whether two runs are the same moves, levels to 1e-9.
    fn same(got: &[TncStep], want: &[TncStep]) -> bool {
        got.len() == want.len()
            && got.iter().zip(want).all(|(g, w)| match (*g, *w) {
                (TncStep::Rapid(a), TncStep::Rapid(b)) | (TncStep::Dwell(a), TncStep::Dwell(b)) => (a - b).abs() < 1e-9,
                (TncStep::Feed(a, f), TncStep::Feed(b, h)) => (a - b).abs() < 1e-9 && f == h,
                _ => false,
            })
    }

    /// Cycle 203 by its parameters' rules, worked by hand: a 20 deep hole from a surface at 0,
    /// set-up clearance 2, plunges of 5 less 1 each (at least 3), two chip breaks of 0.2 before each
    /// retraction: infeeds to -5, -9 (5 + 4), -12 (+3, the minimum), -15, -18 and the bottom; a
    /// retraction after the third infeed (its dwell Q210 at the top, then FMAX to 2 above -12).
    #[test]
    fn tnc_universal_drilling_moves_by_its_parameters() {
        use TncFeed::*;
        use TncStep::*;
        let deep = |depth: f64| TncLevels { surface: 0.0, clearance: 2.0, clearance2: 50.0, depth };
        let c = TncUniversal { levels: deep(-20.0), plunge: 5.0, decrement: 1.0, min_plunge: 3.0, breaks: 2, break_distance: 0.2, dwell_top_s: 0.5, dwell_bottom_s: 0.2 };
        let want = [
            Rapid(2.0),
            Feed(-5.0, Plunge),
            Feed(-4.8, Retract),
            Feed(-9.0, Plunge),
            Feed(-8.8, Retract),
            Feed(-12.0, Plunge),
            Feed(2.0, Retract),
            Dwell(0.5),
            Rapid(-10.0),
            Feed(-15.0, Plunge),
            Feed(-14.8, Retract),
            Feed(-18.0, Plunge),
            Feed(-17.8, Retract),
            Feed(-20.0, Plunge),
            Dwell(0.2),
            Feed(2.0, Retract),
            Rapid(50.0),
        ];
        let got = tnc_universal(&c).unwrap();
        assert!(same(&got, &want), "{got:?}");
        // No chip breaks (Q213=0): out of the hole after every infeed, as cycle 200 but at Q208.
        let plain = TncUniversal { levels: deep(-12.0), decrement: 0.0, breaks: 0, dwell_top_s: 0.0, dwell_bottom_s: 0.0, ..c };
        let want = [Rapid(2.0), Feed(-5.0, Plunge), Feed(2.0, Retract), Rapid(-3.0), Feed(-10.0, Plunge), Feed(2.0, Retract), Rapid(-8.0), Feed(-12.0, Plunge), Feed(2.0, Retract), Rapid(50.0)];
        let got = tnc_universal(&plain).unwrap();
        assert!(same(&got, &want), "{got:?}");
        // A decrement without a minimum: 5 + 4 + 3 + 2 reaches 14, but 5 + 4 + 3 + 2 + 1 never 20.
        let shrinking = TncUniversal { min_plunge: 0.0, ..plain };
        assert!(tnc_universal(&TncUniversal { levels: deep(-14.0), decrement: 1.0, ..shrinking }).is_ok());
        assert!(tnc_universal(&TncUniversal { levels: deep(-20.0), decrement: 1.0, ..shrinking }).unwrap_err().contains("Q212"));
        // A minimum above the plunging depth makes no infeed larger: 5 throughout.
        let got = tnc_universal(&TncUniversal { min_plunge: 8.0, decrement: 1.0, ..plain }).unwrap();
        assert!(same(&got, &[Rapid(2.0), Feed(-5.0, Plunge), Feed(2.0, Retract), Rapid(-3.0), Feed(-10.0, Plunge), Feed(2.0, Retract), Rapid(-8.0), Feed(-12.0, Plunge), Feed(2.0, Retract), Rapid(50.0)]), "{got:?}");
        // Infeeds of a micrometre in a 100 mm hole are a typo, not 100,000 moves.
        assert!(tnc_universal(&TncUniversal { levels: deep(-0.1), plunge: 1e-6, ..plain }).unwrap_err().contains("infeeds"));
        assert!(tnc_universal(&TncUniversal { levels: deep(0.0), ..c }).unwrap().is_empty());
    }

    /// Cycle 201 REAMING with a hyperMILL program's values (Q200=5, Q201=-15, Q203=1, Q204=29), by
    /// its parameters: FMAX to 6, ream to -14 at Q206, dwell Q211, out at Q208 to 6, FMAX to 30.
    #[test]
    fn tnc_reaming_comes_out_at_its_retraction_feed() {
        use TncFeed::*;
        use TncStep::*;
        let h = TncHole { levels: TncLevels { surface: 1.0, clearance: 5.0, clearance2: 29.0, depth: -15.0 }, plunge: 0.0, dwell_top_s: 0.0, dwell_bottom_s: 0.5, out_at: Some(Retract) };
        assert!(same(&tnc_hole(&h), &[Rapid(6.0), Feed(-14.0, Plunge), Dwell(0.5), Feed(6.0, Retract), Rapid(30.0)]), "{:?}", tnc_hole(&h));
    }

    /// Cycle 209 with a hyperMILL program's values (Q200=3, Q201=-48, Q239=+2, Q203=0, Q204=50,
    /// Q257=25, Q256=1), by its parameters' rules worked by hand: a chip break after 25 backs off
    /// 1 x 2 = 2; Q256=0 backs out to the set-up clearance; Q257=0 taps in one infeed.
    #[test]
    fn tnc_tapping_breaks_chips_by_its_parameters() {
        use TncFeed::*;
        use TncStep::*;
        let levels = TncLevels { surface: 0.0, clearance: 3.0, clearance2: 50.0, depth: -48.0 };
        let c = TncChipTapping { levels, infeed: 25.0, back_off: Some(2.0) };
        let got = tnc_chip_tapping(&c).unwrap();
        assert!(same(&got, &[Rapid(3.0), Feed(-25.0, Plunge), Feed(-23.0, Retract), Feed(-48.0, Plunge), Feed(3.0, Retract), Rapid(50.0)]), "{got:?}");
        let got = tnc_chip_tapping(&TncChipTapping { back_off: None, ..c }).unwrap();
        assert!(same(&got, &[Rapid(3.0), Feed(-25.0, Plunge), Feed(3.0, Retract), Feed(-48.0, Plunge), Feed(3.0, Retract), Rapid(50.0)]), "{got:?}");
        let got = tnc_chip_tapping(&TncChipTapping { infeed: 0.0, ..c }).unwrap();
        assert!(same(&got, &[Rapid(3.0), Feed(-48.0, Plunge), Feed(3.0, Retract), Rapid(50.0)]), "{got:?}");
        // A back-off longer than the way up stops at the set-up clearance; a micrometre infeed is a typo.
        let got = tnc_chip_tapping(&TncChipTapping { back_off: Some(40.0), ..c }).unwrap();
        assert!(same(&got, &[Rapid(3.0), Feed(-25.0, Plunge), Feed(3.0, Retract), Feed(-48.0, Plunge), Feed(3.0, Retract), Rapid(50.0)]), "{got:?}");
        assert!(tnc_chip_tapping(&TncChipTapping { infeed: 1e-6, ..c }).unwrap_err().contains("infeeds"));
        assert!(tnc_chip_tapping(&TncChipTapping { levels: TncLevels { depth: 0.0, ..levels }, ..c }).unwrap().is_empty());
    }

    /// Cycle 241 as the DMU program uses it: surface 0, set-up clearance 3, a pilot hole to 16
    /// entered at Q253 to 3 above its bottom (-13), drilled at Q206 to -272.441, out at Q208,
    /// FMAX to the 2nd set-up clearance 30.
    #[test]
    fn tnc_single_lip_drilling_enters_the_pilot_hole_at_its_feed() {
        use TncFeed::*;
        use TncStep::*;
        let c = TncSingleLip { levels: TncLevels { surface: 0.0, clearance: 3.0, clearance2: 30.0, depth: -272.441 }, start: 16.0, dwell_bottom_s: 0.0 };
        let got = tnc_single_lip(&c).unwrap();
        assert!(same(&got, &[Rapid(3.0), Feed(-13.0, Preposition), Feed(-272.441, Plunge), Feed(3.0, Retract), Rapid(30.0)]), "{got:?}");
        // No deepened start: drilling from the set-up clearance; a dwell at the bottom.
        let got = tnc_single_lip(&TncSingleLip { start: 0.0, dwell_bottom_s: 1.5, ..c }).unwrap();
        assert!(same(&got, &[Rapid(3.0), Feed(-272.441, Plunge), Dwell(1.5), Feed(3.0, Retract), Rapid(30.0)]), "{got:?}");
        assert!(tnc_single_lip(&TncSingleLip { start: 272.441, ..c }).is_err());
    }
}
