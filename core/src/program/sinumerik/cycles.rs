//! The 840D's drilling and boring cycles `CYCLE81`-`CYCLE89` as the moves they make along the tool
//! axis where a block under `MCALL` leaves the tool (SINUMERIK 840D sl/840D Cycles Programming
//! Manual 6FC5398-3BP20 11/2006 §2.1; the rules below follow Siemens' own cycle source, cycles
//! package V06.02.09 `CYCLE81.SPF`-`CYCLE84.SPF`: the depth DP, or DPR from the reference plane,
//! "DPR wins"; RFP = DP moves nothing; alarm 61101 when the retraction plane RTP lies on the depth's
//! side of RFP; every cycle first goes by G0 to RFP + SDIS and ends by G0 at RTP, moving only the
//! tool axis). CYCLE85-CYCLE89 have no source here: their sequences are the manual's as posts and
//! other readers use them, and the same template's checks are ASSUMED for them. Values stay in the
//! program's unit. Pure.

use super::lex::Arg;

/// A drilling or boring cycle, by its name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Cycle {
    /// CYCLE81 drilling, centering: G1 to the depth, G0 out.
    C81,
    /// CYCLE82 drilling, counterboring: a dwell at the depth.
    C82,
    /// CYCLE83 deep-hole drilling: infeeds with degression, chip breaking or swarf removal.
    C83,
    /// CYCLE84 rigid tapping: G331 in at the pitch, dwell, G332 out at the pitch.
    C84,
    /// CYCLE85 boring 1: in at FFR, dwell, out at RFF.
    C85,
    /// CYCLE86 boring 2: in, dwell, oriented spindle stop, lift-off, G0 out.
    C86,
    /// CYCLE87 boring 3: in, M5, M0 (the operator restarts), G0 out.
    C87,
    /// CYCLE88 boring 4: in, dwell, M5, M0, G0 out.
    C88,
    /// CYCLE89 boring 5: in, dwell, out at the same feed.
    C89,
}

impl Cycle {
    pub(crate) fn from_name(name: &str) -> Option<Cycle> {
        Some(match name {
            "CYCLE81" => Cycle::C81,
            "CYCLE82" => Cycle::C82,
            "CYCLE83" => Cycle::C83,
            "CYCLE84" => Cycle::C84,
            "CYCLE85" => Cycle::C85,
            "CYCLE86" => Cycle::C86,
            "CYCLE87" => Cycle::C87,
            "CYCLE88" => Cycle::C88,
            "CYCLE89" => Cycle::C89,
            _ => return None,
        })
    }
}

/// One move of a cycle along the tool axis (absolute, program unit): a rapid, or a feed at its own
/// F or the modal one (`None`), a dwell (s), or the program stop of CYCLE87/88 (M5 M0: the operator
/// restarts the program).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Step {
    Rapid(f64),
    Feed(f64, Option<f64>),
    Dwell(f64),
    Stop,
}

/// A hole's moves as the cycle called makes them, once its parameters are read: the same at every
/// position the modal call reaches ("parameters are transferred once"). A feed of `None` is the modal
/// F; `first_feed_factor` scales the modal F of CYCLE83's first infeed (FRF).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Hole {
    pub steps: Vec<Step>,
    pub first_feed_factor: Option<f64>,
    /// Tapping: the pitch (program unit per revolution) and the spindle speeds in and out (rpm): the
    /// feed is their product.
    pub tapping: Option<(f64, f64, f64)>,
}

// Most infeeds one CYCLE83 hole makes (bounds the moves a degression can ask): every dialect's.
use crate::program::cycles::MAX_PECKS;

fn get(args: &[Arg], k: usize) -> &Arg {
    args.get(k).unwrap_or(&Arg::Empty)
}

fn value(args: &[Arg], k: usize, name: &str) -> Result<f64, String> {
    get(args, k).value().map_err(|e| format!("{name}: {e}"))
}

/// A dwell parameter: seconds (a negative one counts spindle revolutions, which is not read).
fn dwell(args: &[Arg], k: usize, name: &str) -> Result<f64, String> {
    let t = value(args, k, name)?;
    if t < 0.0 {
        return Err(format!("{name}={t}: a dwell in spindle revolutions (negative) is not read"));
    }
    Ok(t)
}

fn sign(x: f64) -> f64 {
    if x < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// Why a cycle's call is refused: `alarm` where the control stops at it (a defect of the program
/// that the cycle alarms at), else what this reader does not read, which the control runs.
#[derive(Debug)]
pub(crate) struct Refusal {
    pub why: String,
    pub alarm: bool,
}

impl From<String> for Refusal {
    fn from(why: String) -> Refusal {
        Refusal { why, alarm: false }
    }
}

/// A defect the control stops at, with its alarm.
fn alarm(why: impl Into<String>) -> Refusal {
    Refusal { why: why.into(), alarm: true }
}

/// The moves `cycle` makes with `args`; `mm_per_unit` is the program's length unit. Why not: the
/// parameter the control refuses, with its alarm, or what is not read.
pub(crate) fn decode(cycle: Cycle, args: &[Arg], mm_per_unit: f64) -> Result<Hole, Refusal> {
    let (rtp, rfp) = (value(args, 0, "RTP")?, value(args, 1, "RFP")?);
    let sdis = value(args, 2, "SDIS")?.abs();
    let dpr = value(args, 4, "DPR")?.abs();
    let mut dp = value(args, 3, "DP")?;
    if dpr != 0.0 {
        if rtp == rfp {
            return Err(alarm("a relative depth DPR with the retraction plane RTP on the reference plane RFP (alarm 61101)"));
        }
        dp = rfp - sign(rtp - rfp) * dpr;
    }
    let mut hole = Hole { steps: Vec::new(), first_feed_factor: None, tapping: None };
    if rfp == dp {
        return Ok(hole); // the cycle returns at once: no motion
    }
    let down = sign(rfp - dp);
    // CYCLE83's source has no such check; the others' have it (CYCLE85-89 ASSUMED).
    if cycle != Cycle::C83 && rtp != rfp && sign(rtp - rfp) != down {
        return Err(alarm(format!("RTP={rtp} lies on the depth's side of RFP={rfp} (DP {dp}): reference plane defined incorrectly (alarm 61101)")));
    }
    let start = rfp + sdis * down;
    let s = &mut hole.steps;
    s.push(Step::Rapid(start));
    let spindle_direction = |k: usize| -> Result<(), Refusal> {
        match value(args, k, "SDIR")? {
            d if d == 3.0 || d == 4.0 => Ok(()),
            d => Err(alarm(format!("SDIR={d}: the spindle direction must be 3 (M3) or 4 (M4) (alarm 61102)"))),
        }
    };
    match cycle {
        Cycle::C81 => s.push(Step::Feed(dp, None)),
        Cycle::C82 => {
            s.push(Step::Feed(dp, None));
            s.push(Step::Dwell(dwell(args, 5, "DTB")?));
        }
        Cycle::C85 => {
            let (ffr, rff) = (value(args, 6, "FFR")?, value(args, 7, "RFF")?);
            if !(ffr > 0.0) || !(rff > 0.0) {
                return Err(alarm(format!("FFR={ffr}, RFF={rff}: boring 1 feeds in at FFR and out at RFF, both must be positive (a feed of 0 is an alarm)")));
            }
            s.push(Step::Feed(dp, Some(ffr)));
            s.push(Step::Dwell(dwell(args, 5, "DTB")?));
            s.push(Step::Feed(start, Some(rff)));
        }
        Cycle::C86 => {
            spindle_direction(6)?;
            for (k, name) in [(7, "RPA"), (8, "RPO"), (9, "RPAP")] {
                let v = value(args, k, name)?;
                if v != 0.0 {
                    return Err(format!("{name}={v}: the lift-off after the oriented spindle stop is not modelled").into());
                }
            }
            s.push(Step::Feed(dp, None));
            s.push(Step::Dwell(dwell(args, 5, "DTB")?));
        }
        Cycle::C87 => {
            spindle_direction(5)?;
            s.push(Step::Feed(dp, None));
            s.push(Step::Stop);
        }
        Cycle::C88 => {
            spindle_direction(6)?;
            s.push(Step::Feed(dp, None));
            s.push(Step::Dwell(dwell(args, 5, "DTB")?));
            s.push(Step::Stop);
        }
        Cycle::C89 => {
            s.push(Step::Feed(dp, None));
            s.push(Step::Dwell(dwell(args, 5, "DTB")?));
            s.push(Step::Feed(start, None));
        }
        Cycle::C84 => {
            hole.tapping = Some(tapping(args, mm_per_unit)?);
            let dtb = dwell(args, 5, "DTB")?;
            let s = &mut hole.steps;
            s.push(Step::Feed(dp, None));
            s.push(Step::Dwell(dtb));
            s.push(Step::Feed(start, None));
        }
        Cycle::C83 => {
            let (first_factor, infeeds) = deep_hole(args, rfp, dp, start, down, mm_per_unit)?;
            hole.first_feed_factor = Some(first_factor);
            hole.steps.extend(infeeds);
        }
    }
    hole.steps.push(Step::Rapid(rtp));
    hole.steps.retain(|s| !matches!(s, Step::Dwell(t) if *t == 0.0));
    Ok(hole)
}

/// CYCLE84's pitch and spindle speeds (`_PTAB` 0: the program's unit; MPIT a metric size M3 to
/// M48, PIT a pitch; both empty, or disagreeing, alarm 61001), SST in and SST1 out (SST1 empty: SST).
fn tapping(args: &[Arg], mm_per_unit: f64) -> Result<(f64, f64, f64), Refusal> {
    // _AXN (13th): the tool axis, 1 to 3 the geometry axes, 0 the plane's (as CYCLE83's).
    let axn = value(args, 12, "_AXN")?;
    if axn != 0.0 && axn != 3.0 {
        return Err(format!("_AXN={axn}: tapping along another axis than the plane's tool axis is not modelled").into());
    }
    for (k, name) in [(13, "_PTAB"), (15, "_VARI")] {
        let v = value(args, k, name)?;
        if v != 0.0 {
            return Err(format!("{name}={v}: only a pitch in the program's unit and tapping in one pass are read").into());
        }
    }
    let (mpit, pit) = (value(args, 7, "MPIT")?, value(args, 8, "PIT")?.abs());
    let by_size = if mpit != 0.0 {
        let p = metric_pitch(mpit.abs()).ok_or_else(|| alarm(format!("MPIT={mpit}: not a metric thread M3 to M48 (alarm 61001)")))?;
        Some(p / mm_per_unit)
    } else {
        None
    };
    let pitch = match (by_size, pit) {
        (None, p) if p == 0.0 => return Err(alarm("rigid tapping without a pitch: MPIT and PIT are both empty (alarm 61001)")),
        (None, p) => p,
        (Some(m), p) if p != 0.0 && (m - p).abs() > 1e-9 => return Err(alarm(format!("MPIT={mpit} and PIT={p} disagree (alarm 61001)"))),
        (Some(m), _) => m,
    };
    let sst = value(args, 10, "SST")?;
    if !(sst > 0.0) {
        return Err(format!("SST={sst}: tapping needs its spindle speed").into());
    }
    let sst1 = value(args, 11, "SST1")?;
    Ok((pitch, sst, if sst1 > 0.0 { sst1 } else { sst }))
}

/// Coarse metric thread pitches, mm, by nominal size (ISO 261), as CYCLE84's MPIT names them.
fn metric_pitch(size: f64) -> Option<f64> {
    const TABLE: [(f64, f64); 15] = [(3.0, 0.5), (4.0, 0.7), (5.0, 0.8), (6.0, 1.0), (8.0, 1.25), (10.0, 1.5), (12.0, 1.75), (14.0, 2.0), (16.0, 2.0), (20.0, 2.5), (24.0, 3.0), (30.0, 3.5), (36.0, 4.0), (42.0, 4.5), (48.0, 5.0)];
    TABLE.iter().find(|(s, _)| *s == size).map(|(_, p)| *p)
}

/// CYCLE83(RTP, RFP, SDIS, DP, DPR, FDEP, FDPR, DAM, DTB, DTS, FRF, VARI, _AXN, _MDEP, _VRT, _DTD,
/// _DIS1), as `CYCLE83.SPF` computes it: the first depth (FDPR wins over FDEP; both empty: absolute
/// 0; past DP: DP; on the wrong side of RFP alarm 61107) fed at FRF times the modal F, then infeeds
/// by the degression DAM (> 0: each DAM less, never under DAM; < 0: each |DAM| times the last, never
/// under _MDEP; 0: the first infeed's length again), the last split so none is too short; after each,
/// chip breaking (VARI 0) backs off _VRT (default 1 mm) at rapid, swarf removal (VARI 1) goes back to
/// RFP + SDIS, dwells DTS and comes down at rapid to 0.6 mm above the depth reached (or 1/50 of it from
/// RFP, up to 7 mm; _DIS1 if given). DTB dwells at each intermediate depth, _DTD (default DTB) at DP.
fn deep_hole(args: &[Arg], rfp: f64, dp: f64, start: f64, down: f64, mm_per_unit: f64) -> Result<(f64, Vec<Step>), Refusal> {
    let frf = value(args, 10, "FRF")?;
    if !(frf > 0.0) {
        return Err(alarm(format!("FRF={frf}: the first infeed runs at FRF times the feed, a feed of 0 (an alarm); expected 0.001 to 1")));
    }
    let axn = value(args, 12, "_AXN")?;
    if axn != 0.0 && axn != 3.0 {
        return Err(format!("_AXN={axn}: drilling along another axis than the plane's tool axis is not modelled").into());
    }
    let mut fdep = value(args, 5, "FDEP")?;
    let fdpr_given = value(args, 6, "FDPR")?.abs();
    if fdpr_given != 0.0 {
        fdep = rfp - down * fdpr_given;
    }
    let mut fdpr = (rfp - fdep).abs();
    if fdpr != 0.0 && sign(rfp - fdep) != down {
        return Err(alarm(format!("the first depth {fdep} lies on the wrong side of RFP={rfp} (alarm 61107)")));
    }
    if (fdep - dp) * down < 0.0 {
        fdep = dp;
        fdpr = (rfp - dp).abs();
    }
    let mut dam = value(args, 7, "DAM")?;
    let (dtb, dts) = (dwell(args, 8, "DTB")?, dwell(args, 9, "DTS")?);
    let swarf_removal = match value(args, 11, "VARI")? {
        v if v == 0.0 => false,
        v if v == 1.0 => true,
        v => return Err(format!("VARI={v}: expected 0 (chip breaking) or 1 (swarf removal)").into()),
    };
    let mut mdep = value(args, 13, "_MDEP")?;
    let vrt = match value(args, 14, "_VRT")? {
        v if v > 0.0 => v,
        _ => 1.0 / mm_per_unit,
    };
    let dtd = match dwell(args, 15, "_DTD")? {
        t if t == 0.0 => dtb,
        t => t,
    };
    let dis1 = value(args, 16, "_DIS1")?;
    let mut steps = Vec::new();
    let (mut z, mut inc, mut inc9) = (fdep, fdpr, fdpr);
    for n in 0.. {
        if n > MAX_PECKS {
            return Err(format!("more than {MAX_PECKS} infeeds").into());
        }
        steps.push(Step::Feed(z, None));
        steps.push(Step::Dwell(if z == dp { dtd } else { dtb }));
        if z == dp {
            break;
        }
        if dam == 0.0 {
            dam = -1.0;
            mdep = fdpr;
        }
        let next = if dam < 0.0 {
            inc = (inc * -dam).max(mdep);
            let next = z - down * inc;
            if (next - dp) * down < 0.0 {
                dp
            } else if (next - dp) * down < mdep {
                z - (z - dp) / 2.0
            } else {
                next
            }
        } else {
            inc9 = (inc9 - dam).max(dam);
            let rem = (z - dp).abs();
            if rem - inc9 >= dam {
                if rem > 2.0 * dam {
                    z - inc9 * down
                } else if rem > dam {
                    z - rem / 2.0 * down
                } else {
                    dp
                }
            } else if rem > inc9 {
                if rem > 2.0 * dam {
                    dp + dam * down
                } else {
                    z - rem / 2.0 * down
                }
            } else {
                dp
            }
        };
        if next == z {
            return Err(format!("the infeed from {z} is 0 (RFP, FDEP, FDPR and DAM give no depth to go by): the cycle never advances").into());
        }
        if swarf_removal {
            steps.push(Step::Rapid(start));
            steps.push(Step::Dwell(dts));
            let from_rfp_mm = (rfp - z).abs() * mm_per_unit;
            let mut above = if from_rfp_mm <= 30.0 { 0.6 } else { (from_rfp_mm / 50.0).min(7.0) } / mm_per_unit;
            if dis1 > 0.0 {
                above = dis1;
            }
            steps.push(Step::Rapid(z + above * down));
        } else {
            steps.push(Step::Rapid(z + vrt * down));
        }
        z = next;
    }
    Ok((frf, steps))
}

#[cfg(test)]
mod tests {
    use super::*;
    use Step::*;

    fn args(v: &[Option<f64>]) -> Vec<Arg> {
        v.iter().map(|x| x.map_or(Arg::Empty, Arg::Value)).collect()
    }

    /// The cycles' rules, each worked by hand from the source's lines: DPR wins over DP, RFP = DP
    /// moves nothing, RTP on the depth's side is alarm 61101 (not for CYCLE83), the boring cycles'
    /// sequences.
    #[test]
    fn cycles_move_as_the_source_says() {
        let c81 = decode(Cycle::C81, &args(&[Some(10.0), Some(0.0), Some(2.0), Some(-5.0)]), 1.0).unwrap();
        assert_eq!(c81.steps, vec![Rapid(2.0), Feed(-5.0, None), Rapid(10.0)]);
        let dpr = decode(Cycle::C81, &args(&[Some(10.0), Some(0.0), Some(2.0), Some(-9.0), Some(4.0)]), 1.0).unwrap();
        assert_eq!(dpr.steps[1], Feed(-4.0, None), "DPR wins");
        assert!(decode(Cycle::C81, &args(&[Some(10.0), Some(3.0), Some(2.0), Some(3.0)]), 1.0).unwrap().steps.is_empty());
        // The DMU 70 eVo post's calls: the clearance as RTP, below RFP.
        let e = decode(Cycle::C81, &args(&[Some(0.2362), Some(2.728), Some(0.2362), Some(2.5311), None]), 25.4).unwrap_err();
        assert!(e.alarm && e.why.contains("61101"), "{e:?}");
        let c89 = decode(Cycle::C89, &args(&[Some(10.0), Some(0.0), Some(2.0), Some(-5.0), None, Some(0.5)]), 1.0).unwrap();
        assert_eq!(c89.steps, vec![Rapid(2.0), Feed(-5.0, None), Dwell(0.5), Feed(2.0, None), Rapid(10.0)]);
        let c85 = decode(Cycle::C85, &args(&[Some(10.0), Some(0.0), Some(2.0), Some(-5.0), None, None, Some(100.0), Some(250.0)]), 1.0).unwrap();
        assert_eq!(c85.steps, vec![Rapid(2.0), Feed(-5.0, Some(100.0)), Feed(2.0, Some(250.0)), Rapid(10.0)]);
        assert!(decode(Cycle::C85, &args(&[Some(10.0), Some(0.0), Some(2.0), Some(-5.0), None, Some(9.8), Some(0.0)]), 1.0).is_err());
        assert!(decode(Cycle::C86, &args(&[Some(10.0), Some(0.0), Some(2.0), Some(-5.0), None, Some(3.0)]), 1.0).unwrap_err().why.contains("61102"));
        let c88 = decode(Cycle::C88, &args(&[Some(10.0), Some(0.0), Some(2.0), Some(-5.0), None, Some(1.0), Some(3.0)]), 1.0).unwrap();
        assert_eq!(c88.steps, vec![Rapid(2.0), Feed(-5.0, None), Dwell(1.0), Stop, Rapid(10.0)]);
        assert!(decode(Cycle::C84, &args(&[Some(10.0), Some(0.0), Some(2.0), Some(-5.0)]), 1.0).unwrap_err().why.contains("61001"));
        let tap = decode(Cycle::C84, &args(&[Some(10.0), Some(0.0), Some(2.0), Some(-5.0), None, None, None, Some(8.0), None, None, Some(500.0)]), 1.0).unwrap();
        assert_eq!(tap.tapping, Some((1.25, 500.0, 500.0)), "M8: 1.25 mm pitch");
    }

    /// CYCLE83 as its source computes it, worked by hand: RFP 0, SDIS 1, DP -10, FDEP -4, DAM 1
    /// (infeeds to -4, then 3 and 2 deep: -7, -9, then the last 1 to -10), chip breaking by 1 mm; the
    /// same with swarf removal comes back to RFP + SDIS and down at rapid to 0.6 above the depth.
    #[test]
    fn deep_hole_drilling_follows_the_source() {
        let a = args(&[Some(5.0), Some(0.0), Some(1.0), Some(-10.0), None, Some(-4.0), None, Some(1.0), None, None, Some(0.5), Some(0.0)]);
        let h = decode(Cycle::C83, &a, 1.0).unwrap();
        // z -4: inc9 = max(4 - 1, 1) = 3, rem 6: 6 - 3 >= 1 and 6 > 2 -> -7; z -7: inc9 2, rem 3:
        // 3 - 2 >= 1, 3 > 2 -> -9; z -9: inc9 1, rem 1: 1 - 1 < 1, rem > inc9? no -> DP.
        assert_eq!(
            h.steps,
            vec![Rapid(1.0), Feed(-4.0, None), Rapid(-3.0), Feed(-7.0, None), Rapid(-6.0), Feed(-9.0, None), Rapid(-8.0), Feed(-10.0, None), Rapid(5.0)]
        );
        assert_eq!(h.first_feed_factor, Some(0.5));
        let mut swarf = a.clone();
        swarf[11] = Arg::Value(1.0);
        let h = decode(Cycle::C83, &swarf, 1.0).unwrap();
        assert_eq!(&h.steps[..5], &[Rapid(1.0), Feed(-4.0, None), Rapid(1.0), Rapid(-3.4), Feed(-7.0, None)]);
        // FDEP beyond DP: one infeed; FRF empty: the first infeed at F0, refused.
        let one = decode(Cycle::C83, &args(&[Some(5.0), Some(0.0), Some(1.0), Some(-10.0), None, Some(-20.0), None, None, None, None, Some(1.0)]), 1.0).unwrap();
        assert_eq!(one.steps, vec![Rapid(1.0), Feed(-10.0, None), Rapid(5.0)]);
        assert!(decode(Cycle::C83, &args(&[Some(5.0), Some(0.0), Some(1.0), Some(-10.0), None, Some(-20.0)]), 1.0).unwrap_err().why.contains("FRF"));
        // No first depth to go by: RFP 0, FDEP and FDPR empty, DAM 0.
        assert!(decode(Cycle::C83, &args(&[Some(5.0), Some(0.0), Some(1.0), Some(-10.0), None, None, None, None, None, None, Some(1.0)]), 1.0).unwrap_err().why.contains("never advances"));
    }
}
