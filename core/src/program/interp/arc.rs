//! Circles of G02/G03 blocks: centre from I J K or R, and how far the end may lie off the circle
//! as each control checks it.

use super::{Interpreter, Word};
use crate::program::lex::Diags;
use crate::program::{ArcSpec, Motion};
use crate::units::{INCH, MM};

/// How far the radius to an arc's end may differ from the radius to its start on Fanuc and Haas,
/// unless the machine file says its control's (`arc_radius_tolerance_mm`, Fanuc parameter No. 3410),
/// and how far an R arc's chord may exceed its diameter everywhere: LinuxCNC's `RADIUS_TOLERANCE_INCH`
/// 0.00005 in (0.00127 mm, interp_internal.hh); within it the control runs a spiral (the radius
/// changes evenly along the arc), beyond it the block is refused.
pub const ARC_RADIUS_TOLERANCE: f64 = 0.00005 * INCH;

/// LinuxCNC 2.9's centre-format arc check (interp_arc.cc `arc_data_ijk`): the radii to the start and
/// the end may differ by `CENTER_ARC_RADIUS_TOLERANCE_MM` (2 x 0.01 x sqrt 2 mm in a G21 program;
/// `_INCH` 2 x 0.001 x sqrt 2 in under G20; the INI's, or the machine file's `arc_radius_tolerance_mm`,
/// replaces it), or by up to 100 times that where they differ by no more than 0.1 % of the larger.
pub const LINUXCNC_CENTER_TOLERANCE_MM: f64 = 2.0 * 0.01 * std::f64::consts::SQRT_2 * MM;
pub const LINUXCNC_CENTER_TOLERANCE_INCH: f64 = 2.0 * 0.001 * std::f64::consts::SQRT_2 * INCH;

/// Sinumerik's circle end-point check (alarm 14040): the radii to the start and the end may differ
/// by MD21000 `CIRCLE_ERROR_CONST` (default 0.01 mm) or, on larger circles, by the radius times
/// MD21010 `CIRCLE_ERROR_FACTOR` (default 0.001), whichever is larger.
pub const SINUMERIK_CIRCLE_ERROR_CONST: f64 = 0.01 * MM;

/// The TNC's: "The starting and end points of the arc must lie on the circle. Input tolerance: up
/// to 0.016 mm (selectable with MP 7431)" (TNC 407/415/425 user's manual §5, Circular path C around
/// the circle center CC; TNC 410 §6.4 the same): the largest, where the machine file sets none.
pub const TNC_CIRCLE_TOLERANCE: f64 = 0.016 * MM;
pub const SINUMERIK_CIRCLE_ERROR_FACTOR: f64 = 0.001;

/// The circle of a G02/G03 block from its I J K (centre) or R (radius) words (RS274/NGC 3 §3.5.3),
/// `start`/`end` the block's start and end point (program coordinates, m). Defects go to `diags`;
/// `own_defect`: the block has a defect of its own already, which an earlier refused block is then
/// not named as the cause of.
pub(super) fn resolve_arc(words: &[Word], st: &Interpreter, start: [f64; 3], end: [f64; 3], line: usize, column: usize, own_defect: bool, diags: &mut Diags) -> Option<ArcSpec> {
    let (a0, a1, an) = st.plane.axes();
    let cw = st.motion == Some(Motion::ArcCw);
    // Named as the program writes it: Klartext's circle turns by DR- (clockwise) or DR+.
    let g = match (st.dialect, cw) {
        (crate::program::Dialect::Klartext, true) => "the circle DR-",
        (crate::program::Dialect::Klartext, false) => "the circle DR+",
        (_, true) => "G02",
        (_, false) => "G03",
    };
    let offset_letter = ['I', 'J', 'K'];
    let word = |l: char| words.iter().find(|w| w.letter == l);
    if let Some(w) = word(offset_letter[an]) {
        let earlier = if own_defect { String::new() } else { st.after_refused() };
        diags.error(line, w.column, format!("{}{}: not an arc-centre word in the {} plane{earlier}", w.letter, w.raw, st.plane.said()));
        return None;
    }
    let extra_turns = match word('P') {
        None => 0,
        Some(w) if w.value.fract() == 0.0 && (1.0..=1000.0).contains(&w.value) => w.value as u32 - 1,
        Some(w) => {
            diags.error(line, w.column, format!("P{}: expected a whole number of turns, 1 to 1000", w.raw));
            return None;
        }
    };
    let (u0, v0, u1, v1) = (start[a0], start[a1], end[a0], end[a1]);
    let mut centre = start;
    let r_addr = st.dialect.radius_address();
    match (word('R'), word(offset_letter[a0]).or(word(offset_letter[a1]))) {
        (Some(r), Some(_)) => {
            diags.error(line, r.column, format!("{g} with both {r_addr} and a centre (I J K): expected one of them"));
            return None;
        }
        (None, None) => {
            // The modal G02/G03 may be a refused block's motion code's to replace (G01 R10 refused).
            let earlier = if own_defect { String::new() } else { st.after_refused() };
            diags.error(line, column, format!("{g} without a centre (I J K) or a radius ({r_addr}){earlier}"));
            return None;
        }
        (None, Some(_)) => {
            // Absolute centres (G90.1): both words, as LinuxCNC wants them ("J word missing in
            // absolute center arc", interp_convert.cc convert_arc); a word left out is no offset of 0.
            if let Some(k) = [a0, a1].into_iter().find(|&k| st.arc_absolute && word(offset_letter[k]).is_none()) {
                diags.error(line, column, format!("{g}: {} word missing in an absolute-centre arc (G90.1: both centre words, as LinuxCNC wants them)", offset_letter[k]));
                return None;
            }
            for k in [a0, a1] {
                if let Some(w) = word(offset_letter[k]) {
                    let v = w.value * st.unit;
                    centre[k] = if w.dimension.absolute(st.arc_absolute) { v } else { start[k] + v };
                }
            }
            let r0 = (u0 - centre[a0]).hypot(v0 - centre[a1]);
            let r1 = (u1 - centre[a0]).hypot(v1 - centre[a1]);
            // LinuxCNC refuses a radius under its RADIUS_TOLERANCE, 0.00005 in (0.00127 mm in a G21
            // program: Debian's rs274 2.9 refuses 0.00101 mm and 0.00004 in, reads 0.0015 mm and
            // 0.00005 in); elsewhere a centre on the start or end point, a tenth of it.
            let least = if st.dialect == crate::program::Dialect::Rs274 { ARC_RADIUS_TOLERANCE } else { 0.1 * ARC_RADIUS_TOLERANCE };
            if r0 < least || r1 < least {
                diags.error(line, column, format!("{g}: zero-radius arc, a radius under {:.5} mm (the centre on its start or end point; LinuxCNC: \"Zero-radius arc\")", least / MM));
                return None;
            }
            let error = (r0 - r1).abs();
            let (refused, allowed) = if st.dialect == crate::program::Dialect::Rs274 {
                // The machine file's tolerance replaces LinuxCNC's default, as its INI's does.
                let tol = st.machine().and_then(|m| m.arc_radius_tolerance).unwrap_or(if st.unit == INCH { LINUXCNC_CENTER_TOLERANCE_INCH } else { LINUXCNC_CENTER_TOLERANCE_MM });
                let within = if error / r0.max(r1) > 0.001 { tol } else { 100.0 * tol };
                (error > within, within)
            } else {
                let allowed = st.arc_tolerance.max(st.arc_tolerance_factor * r0);
                (error > allowed, allowed)
            };
            if refused {
                diags.error(
                    line,
                    column,
                    format!(
                        "{g}: the radius to the end ({:.4} mm) differs from the radius to the start ({:.4} mm) by more than {:.5} mm",
                        r1 / MM,
                        r0 / MM,
                        allowed / MM
                    ),
                );
                return None;
            }
        }
        (Some(r), None) => {
            let radius = r.value * st.unit;
            let r_word = format!("{r_addr}{}", r.raw);
            let half = 0.5 * (u1 - u0).hypot(v1 - v0);
            if half == 0.0 {
                diags.error(line, r.column, format!("{g} {r_word}: the end point is the start point, so {r_addr} gives no centre (a full circle needs I J K)"));
                return None;
            }
            if !(radius.abs() > 0.0) || half - radius.abs() > st.arc_tolerance {
                diags.error(line, r.column, format!("{g} {r_word}: the radius is too small to reach the end point ({:.4} mm away)", 2.0 * half / MM));
                return None;
            }
            let h = (radius * radius - half * half).max(0.0).sqrt();
            // Centre on the left of the chord (turning from the plane's first axis towards its
            // second) for a short counter-clockwise arc; the other side for clockwise, and again for
            // R < 0 (longer than a semicircle).
            let (du, dv) = ((u1 - u0) / (2.0 * half), (v1 - v0) / (2.0 * half));
            let ccw = st.motion == Some(Motion::ArcCcw);
            let side = if ccw == (radius > 0.0) { 1.0 } else { -1.0 };
            centre[a0] = 0.5 * (u0 + u1) - side * h * dv;
            centre[a1] = 0.5 * (v0 + v1) + side * h * du;
        }
    }
    Some(ArcSpec { plane: st.plane, centre, extra_turns, frame: None })
}
