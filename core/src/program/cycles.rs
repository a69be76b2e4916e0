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
}
