//! Canned drilling cycles as the motion they make along the drilling axis, from the R point down to
//! the hole's bottom and back: Fanuc's and Haas' G73, G74, G76, G81-G86, G89 (FANUC Series
//! 30i/31i/32i-MA User's Manual B-63944EN, §5.1 "Canned cycle for drilling": the R point, G98 back
//! to the initial level, G99 to the R point; §5.1.6 G83, the clearance d of parameter No. 5115;
//! Haas Mill Operator's Manual 96-8000, "Canned cycles": G73's retract of Setting 22). Pure: no
//! words, no state but the cycle's own; [`super::fanuc`] turns the steps into blocks.

/// The cycles' G codes (as normalised, `81`), in the order of [`Kind`]'s variants.
pub(crate) const CODES: [&str; 12] = ["73", "74", "76", "81", "82", "83", "84", "85", "86", "87", "88", "89"];

/// The cycles, in the order of their [`CODES`].
const KINDS: [Kind; 12] = [Kind::G73, Kind::G74, Kind::G76, Kind::G81, Kind::G82, Kind::G83, Kind::G84, Kind::G85, Kind::G86, Kind::G87, Kind::G88, Kind::G89];

/// A drilling cycle, by its G code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// G73: high-speed peck drilling (retract d after each peck, parameter 5114 / Haas Setting 22).
    G73,
    /// G74: left-hand tapping (feed down, dwell, spindle reversed, feed up).
    G74,
    /// G76: fine boring (feed down, dwell, oriented stop, rapid up; a shift Q is the machine's).
    G76,
    /// G81: drilling (feed down, rapid up).
    G81,
    /// G82: drilling with a dwell at the bottom.
    G82,
    /// G83: peck drilling (back to the R point after each peck, down again to d above the last).
    G83,
    /// G84: tapping.
    G84,
    /// G85: boring (feed down, feed up to the R point).
    G85,
    /// G86: boring (feed down, spindle stop, rapid up).
    G86,
    /// G87: back boring (rapid down to the R point below the part, feed up to Z, rapid out to the
    /// initial level; without Q no shift).
    G87,
    /// G88: boring (feed down, dwell, spindle stop, the program waits while the operator may retract
    /// by hand, then rapid to the return level).
    G88,
    /// G89: boring with a dwell (feed down, dwell, feed up to the R point).
    G89,
}

impl Kind {
    /// The cycle a G code (as normalised, `81`) names.
    pub(crate) fn from_code(code: &str) -> Option<Kind> {
        CODES.iter().position(|c| *c == code).map(|i| KINDS[i])
    }

    /// Its G code, as normalised (`81`).
    pub(crate) fn code(self) -> &'static str {
        CODES[self as usize]
    }

    /// Whether the cycle pecks (needs its machine's clearance d).
    pub(crate) fn pecks(self) -> bool {
        matches!(self, Kind::G73 | Kind::G83)
    }
}

/// The active cycle, in absolute program coordinates along the drilling axis (m, s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Active {
    pub kind: Kind,
    /// The hole's bottom.
    pub bottom: f64,
    /// The R point.
    pub r: f64,
    /// The peck depth (G73, G83), positive; under `reduce` the first peck.
    pub peck: Option<f64>,
    /// Haas' G83 with I J K: each peck after the first `peck` (I) less by the first of these (J),
    /// never under the second (K) (Haas Mill Operator's Manual 96-8000, G83).
    pub reduce: Option<(f64, f64)>,
    /// The dwell at the bottom, s.
    pub dwell_s: Option<f64>,
    /// The level the tool stood at when the cycle was first commanded (G98 returns to it).
    pub initial: f64,
}

/// Cycle state of the interpreter: the active cycle, the return level, the intermediate point
/// Fanuc's G28 stored (per axis, program coordinates).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct CycleState {
    pub active: Option<Active>,
    /// G99 (back to the R point) rather than G98 (back to the initial level, the reset state).
    pub to_r: bool,
    /// LinuxCNC's words that stay from one cycle block to the next.
    pub linuxcnc: super::lcnc_cycles::Sticky,
}

/// One move of a hole, along the drilling axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Step {
    Rapid(f64),
    Feed(f64),
    Dwell(f64),
}

/// The moves of one hole from the R point (the tool stands there) to the bottom and back to the
/// return level. `clearance` is the machine's d: G73's retract, G83's stop above the last depth.
pub(crate) fn hole(a: &Active, to_r: bool, clearance: f64) -> Vec<Step> {
    // G87 returns to the initial level whatever G98/G99 say (its R point is below the part).
    let back = if to_r && a.kind != Kind::G87 { a.r } else { a.initial };
    // Drilling goes from r down to bottom (or up, if the R point is below: the direction is the sign).
    let down = if a.bottom <= a.r { -1.0 } else { 1.0 };
    let mut steps = Vec::new();
    let dwell = |steps: &mut Vec<Step>| {
        if let Some(t) = a.dwell_s.filter(|t| *t > 0.0) {
            steps.push(Step::Dwell(t));
        }
    };
    match a.kind {
        Kind::G81 => steps.push(Step::Feed(a.bottom)),
        Kind::G87 => steps.push(Step::Feed(a.bottom)),
        Kind::G82 | Kind::G76 | Kind::G86 | Kind::G88 => {
            steps.push(Step::Feed(a.bottom));
            dwell(&mut steps);
        }
        Kind::G73 | Kind::G83 => {
            let first = a.peck.unwrap_or(f64::INFINITY).abs();
            // Within a nanometre of the bottom is the bottom: pecks summed in floating point leave a
            // sliver otherwise (-8.5 - 1.5 mm is -9.999999999999998 mm).
            let past = |depth: f64| (depth - a.bottom) * down >= -1e-9;
            let mut depth = a.r;
            let mut n = 0.0;
            loop {
                let q = a.reduce.map_or(first, |(less, least)| (first - n * less).max(least));
                n += 1.0;
                let next = if past(depth + down * q) { a.bottom } else { depth + down * q };
                if depth != a.r {
                    // G83: back down at rapid to d short of the last depth; G73 is already there.
                    if a.kind == Kind::G83 {
                        steps.push(Step::Rapid(depth - down * clearance));
                    }
                }
                steps.push(Step::Feed(next));
                if next == a.bottom {
                    break;
                }
                steps.push(Step::Rapid(if a.kind == Kind::G83 { a.r } else { next - down * clearance }));
                depth = next;
            }
            dwell(&mut steps);
        }
        Kind::G74 | Kind::G84 | Kind::G85 | Kind::G89 => {
            steps.push(Step::Feed(a.bottom));
            dwell(&mut steps);
            steps.push(Step::Feed(a.r));
        }
    }
    steps.push(Step::Rapid(back));
    // A return to where the tool already is moves nothing.
    let mut at = a.r;
    steps.retain(|s| match *s {
        Step::Rapid(z) | Step::Feed(z) => std::mem::replace(&mut at, z) != z,
        Step::Dwell(_) => true,
    });
    steps
}

/// The most pecks a hole may take (a peck depth a thousand times too small is a typo, and each
/// peck makes blocks).
pub(crate) const MAX_PECKS: usize = 10_000;

/// Whether a hole `depth` deep in pecks (or plunges) of `peck` takes more than [`MAX_PECKS`].
pub(crate) fn too_many_pecks(depth: f64, peck: f64) -> bool {
    (depth / peck).abs() > MAX_PECKS as f64
}

/// The most moves one cycle block may make, its repeats (Fanuc's K, LinuxCNC's L) times each
/// hole's: a block's moves are held until it has run, and K9999 holes of 9,091 pecks each (27
/// million moves, gigabytes) are a typo, as is a peck too small ([`MAX_PECKS`]).
pub(crate) const MAX_CYCLE_MOVES: usize = 200_000;

/// About how many moves `repeats` holes make, each `depth` deep (m) in pecks of `peck` (None: one
/// plunge): three per peck and four more per hole at most; an error giving that count where it
/// exceeds [`MAX_CYCLE_MOVES`].
pub(crate) fn check_cycle_moves(repeats: usize, depth: f64, peck: Option<f64>) -> Result<(), f64> {
    let pecks = peck.filter(|q| *q > 0.0).map_or(1.0, |q| (depth.abs() / q).ceil().max(1.0));
    let moves = repeats as f64 * (3.0 * pecks + 4.0);
    if moves > MAX_CYCLE_MOVES as f64 {
        Err(moves)
    } else {
        Ok(())
    }
}

/// The moves of one hole of a LinuxCNC canned cycle, from the R point `r` (the tool stands there)
/// down to `bottom` and out to `clear` (G99: `r`; G98: the level before the cycles, or `r` if that
/// was below it): LinuxCNC 2.9's interp_cycles.cc, `convert_cycle_g73` ... `g89`. G73 backs off
/// `delta` after each `peck`; G83 goes out to R and comes back down to `delta` above the depth
/// reached; G74/G84 (a floating tap holder) and G89 dwell `dwell_s` and feed out to `clear`; G85
/// feeds out to R, then rapids to `clear`; G82 and G86 dwell and rapid out. G76, G87 and G88 are
/// no drilling cycles of LinuxCNC's: nothing.
pub(crate) fn lcnc_hole(kind: Kind, r: f64, bottom: f64, clear: f64, peck: f64, dwell_s: f64, delta: f64) -> Vec<Step> {
    use Step::*;
    let dwell = |steps: &mut Vec<Step>| {
        if dwell_s > 0.0 {
            steps.push(Dwell(dwell_s));
        }
    };
    let mut steps = Vec::new();
    match kind {
        Kind::G81 => steps.extend([Feed(bottom), Rapid(clear)]),
        Kind::G82 | Kind::G86 => {
            steps.push(Feed(bottom));
            dwell(&mut steps);
            steps.push(Rapid(clear));
        }
        Kind::G73 | Kind::G83 => {
            let mut depth = r - peck;
            while depth > bottom && steps.len() < 3 * MAX_PECKS {
                steps.push(Feed(depth));
                if kind == Kind::G83 {
                    steps.push(Rapid(r));
                }
                steps.push(Rapid(depth + delta));
                depth -= peck;
            }
            steps.extend([Feed(bottom), Rapid(clear)]);
        }
        Kind::G74 | Kind::G84 | Kind::G89 => {
            steps.push(Feed(bottom));
            dwell(&mut steps);
            steps.push(Feed(clear));
        }
        Kind::G85 => steps.extend([Feed(bottom), Feed(r), Rapid(clear)]),
        Kind::G76 | Kind::G87 | Kind::G88 => {}
    }
    steps
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

/// A Heidenhain drilling cycle's parameters, absolute along the tool axis of the working plane (m,
/// s): the surface Q203, the set-up clearance Q200 and 2nd set-up clearance Q204 above it, the
/// depth Q201 (negative: below the surface), the plunging depth Q202 (0: at once), the dwells at the
/// top Q210 and at the bottom Q211, and whether the tool comes back at feed (tapping).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TncHole {
    pub surface: f64,
    pub clearance: f64,
    pub clearance2: f64,
    pub depth: f64,
    pub plunge: f64,
    pub dwell_top_s: f64,
    pub dwell_bottom_s: f64,
    pub feed_out: bool,
}

/// The moves of a Heidenhain drilling cycle at the current position (TNC 426/430 User's Manual
/// §8.3, cycle 200 DRILLING: "the TNC positions the tool in the spindle axis at rapid traverse FMAX
/// to the set-up clearance above the workpiece surface"; drills to each plunging depth at feed,
/// "returns the tool at FMAX to the set-up clearance, dwells there, and then moves at FMAX to the
/// set-up clearance above the" depth reached; at the bottom dwells and retracts at FMAX to the
/// set-up clearance or, if larger, the 2nd set-up clearance. Cycle 240 CENTERING is one plunge;
/// cycle 207 RIGID TAPPING comes back at feed). A depth of 0 makes nothing.
pub(crate) fn tnc_hole(h: &TncHole) -> Vec<Step> {
    let (top, bottom) = (h.surface + h.clearance, h.surface + h.depth);
    if h.depth == 0.0 {
        return Vec::new();
    }
    let mut steps = vec![Step::Rapid(top)];
    let q = if h.plunge > 0.0 { h.plunge } else { f64::INFINITY };
    for k in 1.. {
        let next = infeed(h.surface, q, k, bottom);
        steps.push(Step::Feed(next));
        if next <= bottom {
            break;
        }
        steps.push(Step::Rapid(top));
        if h.dwell_top_s > 0.0 {
            steps.push(Step::Dwell(h.dwell_top_s));
        }
        steps.push(Step::Rapid(next + h.clearance));
    }
    if h.dwell_bottom_s > 0.0 {
        steps.push(Step::Dwell(h.dwell_bottom_s));
    }
    if h.feed_out {
        steps.push(Step::Feed(top));
    }
    steps.push(Step::Rapid(h.surface + h.clearance.max(h.clearance2)));
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
pub(crate) fn tnc_pecking(start: f64, c: &TncPecking) -> Vec<Step> {
    let surface = start - c.setup;
    let bottom = surface - c.depth;
    let t = c.advanced_stop();
    let mut steps = Vec::new();
    for k in 1.. {
        let next = infeed(surface, c.peck, k, bottom);
        steps.push(Step::Feed(next));
        if next <= bottom {
            break;
        }
        steps.push(Step::Rapid(start));
        steps.push(Step::Rapid(next + t));
    }
    if c.dwell_s > 0.0 {
        steps.push(Step::Dwell(c.dwell_s));
    }
    steps.push(Step::Rapid(start));
    steps
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each cycle's code names it, and it has that code.
    #[test]
    fn codes_and_kinds_name_each_other() {
        for (i, k) in KINDS.iter().enumerate() {
            assert_eq!(*k as usize, i);
            assert_eq!(Kind::from_code(k.code()), Some(*k));
        }
        assert_eq!(Kind::from_code("81").map(Kind::code), Some("81"));
        assert_eq!(Kind::from_code("80"), None);
    }

    fn cycle(kind: Kind, peck: Option<f64>) -> Active {
        Active { kind, bottom: -10.0, r: 2.0, peck, reduce: None, dwell_s: Some(0.5), initial: 50.0 }
    }

    /// Each cycle's moves as the Fanuc manual draws them (B-63944EN §5.1.x figures): G81 feed and
    /// rapid out; G89 feeds out; G83 back to R after each peck and down to d above the last depth;
    /// G73 backs off d; G98 returns to the initial level, G99 to R.
    #[test]
    fn holes_move_as_the_manual_draws_them() {
        use Step::*;
        assert_eq!(hole(&cycle(Kind::G81, None), false, 0.1), vec![Feed(-10.0), Rapid(50.0)]);
        assert_eq!(hole(&cycle(Kind::G81, None), true, 0.1), vec![Feed(-10.0), Rapid(2.0)]);
        assert_eq!(hole(&cycle(Kind::G89, None), true, 0.1), vec![Feed(-10.0), Dwell(0.5), Feed(2.0)]);
        assert_eq!(hole(&cycle(Kind::G89, None), false, 0.1), vec![Feed(-10.0), Dwell(0.5), Feed(2.0), Rapid(50.0)]);
        assert_eq!(
            hole(&cycle(Kind::G83, Some(5.0)), true, 0.25),
            vec![Feed(-3.0), Rapid(2.0), Rapid(-2.75), Feed(-8.0), Rapid(2.0), Rapid(-7.75), Feed(-10.0), Dwell(0.5), Rapid(2.0)]
        );
        assert_eq!(hole(&cycle(Kind::G73, Some(5.0)), false, 0.25), vec![Feed(-3.0), Rapid(-2.75), Feed(-8.0), Rapid(-7.75), Feed(-10.0), Dwell(0.5), Rapid(50.0)]);
        // A peck deeper than the hole drills it in one go.
        assert_eq!(hole(&cycle(Kind::G83, Some(50.0)), true, 0.25), vec![Feed(-10.0), Dwell(0.5), Rapid(2.0)]);
    }

    /// Cycle 200 as the manual describes it, with the hyperMILL program's values (Q200=2 set-up
    /// clearance, Q201=-6.5 depth, Q202=2.5 plunge, Q203=0 surface, Q204=50 2nd clearance).
    #[test]
    fn tnc_drilling_moves_as_the_manual_describes() {
        use Step::*;
        let h = TncHole { surface: 0.0, clearance: 2.0, clearance2: 50.0, depth: -6.5, plunge: 2.5, dwell_top_s: 0.5, dwell_bottom_s: 1.0, feed_out: false };
        assert_eq!(
            tnc_hole(&h),
            vec![Rapid(2.0), Feed(-2.5), Rapid(2.0), Dwell(0.5), Rapid(-0.5), Feed(-5.0), Rapid(2.0), Dwell(0.5), Rapid(-3.0), Feed(-6.5), Dwell(1.0), Rapid(50.0)]
        );
        assert_eq!(tnc_hole(&TncHole { plunge: 6.5, dwell_top_s: 0.0, dwell_bottom_s: 0.0, ..h }), vec![Rapid(2.0), Feed(-6.5), Rapid(50.0)]);
        assert_eq!(tnc_hole(&TncHole { plunge: 0.0, feed_out: true, dwell_top_s: 0.0, dwell_bottom_s: 0.0, clearance2: 0.0, ..h }), vec![Rapid(2.0), Feed(-6.5), Feed(2.0), Rapid(2.0)]);
        assert!(tnc_hole(&TncHole { depth: 0.0, ..h }).is_empty());
    }

    /// Cycle 1 PECKING as the manual's process runs it, by hand: from Z2 with a set-up clearance of
    /// 2 (surface at 0), a total depth of 10 and pecks of 4, t = 0.6 mm (depth up to 30 mm): feed to
    /// -4, rapid to 2 and down to -3.4, feed to -8, rapid to 2 and down to -7.4, feed to -10, dwell,
    /// rapid to 2. A 40 mm hole's t is 40/50 = 0.8 mm; a 500 mm hole's is capped at 7 mm.
    #[test]
    fn tnc_pecking_moves_as_the_manual_describes() {
        use Step::*;
        let mm = crate::units::MM;
        let c = TncPecking { setup: 2.0 * mm, depth: 10.0 * mm, peck: 4.0 * mm, dwell_s: 0.5 };
        let got: Vec<Step> = tnc_pecking(2.0 * mm, &c);
        let want = [Feed(-4.0), Rapid(2.0), Rapid(-3.4), Feed(-8.0), Rapid(2.0), Rapid(-7.4), Feed(-10.0), Dwell(0.5), Rapid(2.0)];
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(want) {
            match (*g, w) {
                (Feed(a), Feed(b)) | (Rapid(a), Rapid(b)) => assert!((a / mm - b).abs() < 1e-9, "{got:?}"),
                (Dwell(a), Dwell(b)) => assert_eq!(a, b),
                _ => panic!("{got:?}"),
            }
        }
        assert_eq!(c.pecks(), 3.0);
        // One pass where the peck reaches the bottom; no dwell step for 0 s.
        let once = tnc_pecking(0.0, &TncPecking { peck: 10.0 * mm, dwell_s: 0.0, ..c });
        assert_eq!(once.len(), 2, "{once:?}");
        assert!(matches!(once[0], Feed(z) if (z / mm + 12.0).abs() < 1e-9) && matches!(once[1], Rapid(z) if z == 0.0), "{once:?}");
        assert!((TncPecking { depth: 40.0 * mm, ..c }.advanced_stop() / mm - 0.8).abs() < 1e-9);
        assert!((TncPecking { depth: 30.0 * mm, ..c }.advanced_stop() / mm - 0.6).abs() < 1e-9);
        assert!((TncPecking { depth: 500.0 * mm, ..c }.advanced_stop() / mm - 7.0).abs() < 1e-9);
    }
}
