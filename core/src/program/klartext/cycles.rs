//! `CYCL DEF` blocks: which cycle, its parameters, and the cycles read here (7 datum shift, 9 dwell,
//! 19 working plane, 32 tolerance, the drilling cycles and the machine maker's own).

use super::*;

/// `CYCL DEF 32.0 TOLERANCE` / `32.1 T0.05` / `32.2 HSC-MODE:0 TA0.5` (TNC 620 Cycle Programming, 340
/// 56x-03, §12.5): the contour tolerance on the path (program unit) and, under M128/TCPM, on the rotary
/// axes (deg), for the blocks after it. `32.1` without `T` resets both to the machine's (its file's
/// `contour_tolerance_mm`/`_deg`). `HSC-MODE:0` and `:1` (finishing, roughing) choose the maker's
/// filter within the same tolerance.
pub(super) fn tolerance_cycle<'a>(toks: &[(&'a str, usize)], part: &str, line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let col = toks[0].1;
    let rest = &toks[3.min(toks.len())..];
    match part {
        // The cycle's name, in the control's language.
        "0" if rest.len() <= 1 => None,
        "1" if rest.is_empty() => Some(Kind::Tolerance { linear: None, rotary: None, reset: true }),
        "1" if rest.len() == 1 && upper(rest[0].0).starts_with('T') => {
            let (tok, c) = rest[0];
            value_word("T", &tok[1..], tok, c, line, diags).map(|w| Kind::Tolerance { linear: Some(w), rotary: None, reset: false })
        }
        "2" if !rest.is_empty() => {
            let mut rotary = None;
            for &(tok, c) in rest {
                let u = upper(tok);
                if let Some(mode) = u.strip_prefix("HSC-MODE:") {
                    match mode {
                        // HSC-MODE:1 (roughing) picks the maker's other filter: "Even if the control
                        // does not move the axes with reduced speed, it will always comply with the
                        // tolerance that you have defined" (TNC7 basic User's Manual 81762x-19, cycle
                        // 32), so T stays the bound the planner keeps either way.
                        "0" | "1" => {}
                        _ => {
                            diags.error(line, c, format!("CYCL DEF 32.2: expected HSC-MODE:0 or HSC-MODE:1, found '{}'", excerpt(tok)));
                            return None;
                        }
                    }
                } else if u.starts_with("TA") {
                    rotary = Some(value_word("TA", &tok[2..], tok, c, line, diags)?);
                } else {
                    diags.error(line, c, format!("CYCL DEF 32.2: expected HSC-MODE:0 and TA (the rotary axes' tolerance, deg), found '{}'", excerpt(tok)));
                    return None;
                }
            }
            rotary.map(|w| Kind::Tolerance { linear: None, rotary: Some(w), reset: false })
        }
        _ => {
            diags.error(line, col, "CYCL DEF 32: expected CYCL DEF 32.0 TOLERANCE, CYCL DEF 32.1 T followed by the tolerance, or CYCL DEF 32.2 HSC-MODE:0 TA followed by the rotary axes' tolerance, deg");
            None
        }
    }
}

/// `CYCL DEF 7.0 DATUM SHIFT` / `7.1 X+..` / `7.2 Y+..` / `7.3 Z+..`, `CYCL DEF 9.0 DWELL TIME` /
/// `9.1 DWELL 1.5` (German `V.ZEIT`: the dwell, s, active where it is defined); every other cycle is refused.
pub(super) fn cycle<'a>(toks: &[(&'a str, usize)], line: usize, defined: &mut bool, diags: &mut Diags) -> Option<Kind<'a>> {
    let col = toks[0].1;
    let number = toks.get(2).map_or("", |t| t.0);
    let (cycle, part) = number.split_once('.').unwrap_or((number, ""));
    if cycle == "9" {
        return match (part, toks.len()) {
            ("0", _) => None,
            // 9.1, its label (in the control's language), the time.
            ("1", 5) => value_word("DWELL", toks[4].0, toks[4].0, toks[4].1, line, diags).map(Kind::Dwell),
            _ => {
                diags.error(line, col, format!("CYCL DEF {number}: expected CYCL DEF 9.0 DWELL TIME or CYCL DEF 9.1 DWELL followed by the time, s"));
                None
            }
        };
    }
    if cycle == "32" {
        return tolerance_cycle(toks, part, line, diags);
    }
    if cycle == "19" {
        return cycle19(toks, part, line, diags);
    }
    if cycle != "7" {
        return match (cycle, part.is_empty(), cycle.parse::<u32>()) {
            ("8" | "10" | "11" | "26", _, _) => {
                diags.error(line, col, format!("CYCL DEF {number}: mirroring, rotation or scaling is not modelled"));
                None
            }
            // A cycle and its name; its Q parameters follow on the lines after it. Whether it is read
            // is the runner's (the machine's own cycles are in its file).
            (_, true, Ok(n)) => Some(Kind::CycleDef(n)),
            _ => {
                diags.error(line, col, format!("CYCL DEF {number}: expected a cycle number"));
                None
            }
        };
    }
    if part == "0" {
        *defined = true;
        return None;
    }
    if !*defined {
        diags.error(line, col, format!("CYCL DEF {number} without CYCL DEF 7.0 before it"));
        return None;
    }
    let Some(&(tok, wcol)) = toks.get(3) else {
        diags.error(line, col, format!("CYCL DEF {number}: expected an axis value such as X+10"));
        return None;
    };
    if tok.starts_with('#') {
        diags.error(line, wcol, "CYCL DEF 7 with a datum table (#): not modelled");
        return None;
    }
    let (addr, rest) = split_word(tok);
    let (a, incremental) = match motion_address(&addr) {
        Some((a, 0..=2)) => (a, a.starts_with('I')),
        _ => {
            diags.error(line, wcol, format!("CYCL DEF {number}: expected X, Y or Z, found '{}' (a rotary datum shift is not modelled)", excerpt(tok)));
            return None;
        }
    };
    if toks.len() > 4 {
        diags.error(line, toks[4].1, format!("CYCL DEF {number}: one axis per block"));
    }
    let k = axis_index(a);
    value_word(a, rest, tok, wcol, line, diags).map(|w| Kind::Datum(k, w, incremental))
}
