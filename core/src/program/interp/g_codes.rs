//! A block's G codes: the modal state each sets, and what it says of the block's other words (the
//! letters it takes, the codes applied once the block's modal codes are). Part of
//! [`Interpreter::block_one`].

use super::block::{BlockCodes, Reader};
use super::{Interpreter, Word};
use crate::program::lex::Diags;
use crate::program::{Dialect, Exact, FeedMode, Motion, Plane};
use crate::units::{INCH, MM};

/// One G word of a block: `next` is the state the block changes, `before` the state before it.
#[allow(clippy::too_many_arguments)]
pub(super) fn g_code<'w, 't>(next: &mut Interpreter, before: &Interpreter, w: &'w Word<'t>, words: &[Word], line: usize, r: Reader, c: &mut BlockCodes<'w, 't>, diags: &mut Diags) {
    let Reader { heid, fanuc, haas, tool_call, defines } = r;
    let code = w.raw.trim_start_matches('+');
    let code = code.trim_start_matches('0');
    // Borrowed as written but for a code of zeros (`G0`, `G00`, `G0.1`): no allocation per G word.
    let code: std::borrow::Cow<str> = if code.is_empty() || code.starts_with('.') { format!("0{code}").into() } else { code.into() };
    let unsupported = |diags: &mut Diags, what: &str| {
        diags.error(line, w.column, format!("G{} ({what}) is not supported: it changes the motion", w.raw))
    };
    // A modal motion of group 01 not read (splines, NURBS, 3D circles): one list for the code and for
    // the moves after it ([`super::codes::unread_motion`]).
    let unread = if heid { None } else { super::codes::unread_motion(before.dialect, super::x10(w)) };
    match (code.as_ref(), heid) {
        ("0", _) => next.motion = Some(Motion::Rapid),
        ("1", _) => next.motion = Some(Motion::Linear),
        ("2", false) => next.motion = Some(Motion::ArcCw),
        ("3", false) => next.motion = Some(Motion::ArcCcw),
        ("2", true) => next.motion = Some(Motion::ArcCw),
        ("3", true) => next.motion = Some(Motion::ArcCcw),
        // G05: a circle in the direction of the last G02/G03.
        ("5", true) => match before.last_arc {
            Some(m) => next.motion = Some(m),
            None => diags.error(line, w.column, format!("G{}: a circle without its own direction needs a G02 or G03 before it", w.raw)),
        },
        ("6" | "12" | "13" | "15" | "16" | "25" | "26" | "27", true) => diags.error(
            line,
            w.column,
            format!("G{} (tangential, polar or rounding arcs) is not supported in Heidenhain DIN/ISO yet: expected G00-G03 or G05", w.raw),
        ),
        // TNC 360 ISO Programming, cycle example: "N10 G30 G17 X+0 Y+0 Z-20 *",
        // "N20 G31 X+100 Y+100 Z+0 *" (Define workpiece blank), "N30 G99 T1 L+0 R+4 *"
        // (Tool definition): drawing and tool data, no motion.
        ("30" | "31" | "99", true) if defines => {}
        ("17", _) => next.plane = Plane::Xy,
        ("18" | "19" | "20", true) if tool_call => diags.error(
            line,
            w.column,
            format!("T with G{}: a tool call along tool axis {} (only tool axis Z, G17, is modelled: the machine file's)", w.raw, ["Y", "X", "IV"][code.parse::<usize>().unwrap_or(18) - 18]),
        ),
        ("18", _) => next.plane = Plane::Zx,
        ("19", _) => next.plane = Plane::Yz,
        // Cutter compensation off, canned cycle cancel: no motion of their own.
        // LinuxCNC's G80 is of the motion group: no motion mode after it, so axis
        // words need a G0/G1 again (LinuxCNC: "Cannot use axis values with G80",
        // "without a G code that uses them"). Fanuc's cycles are a group of their own.
        ("80", _) if before.dialect == Dialect::Rs274 => next.motion = None,
        // The TNC's DIN/ISO G80 is the working plane, cycle 19 (iTNC 530 ISO user's manual, "WORKING
        // PLANE (Cycle G80)"): not read ([`super::lasting`] holds the moves after it).
        ("80", true) => unsupported(diags, "the working plane, cycle 19"),
        ("40" | "80", _) => {}
        ("90", _) => next.absolute = true,
        ("91", _) => next.absolute = false,
        ("90.1", false) => next.arc_absolute = true,
        ("91.1", false) => next.arc_absolute = false,
        ("70", true) | ("20", false) | ("71", true) | ("21", false) | ("70" | "71", false) if heid || before.dialect == Dialect::Sinumerik || code.starts_with('2') => {
            let inch = code == "70" || code == "20";
            next.unit_stated = true;
            // Sinumerik's G70/G71 are the geometry's unit only: "Feedrate functions are
            // not affected by G70/G71" (840Di sl Programming Manual 6FC5398-1BP10,
            // "Inch/metric dimensions"), F stays in the basic system's; G700/G710
            // (read as G20/G21) set both.
            let feed_too = !(before.dialect == Dialect::Sinumerik && code.starts_with('7'));
            // The TNC's DIN/ISO unit is the program's, set in its header (`%NAME G71 *`)
            // and end lines; a block that says another is refused, not obeyed.
            let header_only = before.dialect == Dialect::Heidenhain && next.forced_unit.is_none() && (next.unit == INCH) != inch;
            if header_only {
                diags.error(line, w.column, format!("G{} in a block: the TNC takes the program's unit from its header (%NAME G70 or G71), which says otherwise", w.raw));
            }
            match next.forced_unit {
                None if header_only => {}
                None => {
                    next.unit = if inch { INCH } else { MM };
                    if feed_too {
                        next.feed_unit = next.unit;
                    } else if next.feed_unit != next.unit {
                        let (f, g7) = if next.feed_unit == MM { ("mm/min", "G700") } else { ("inch/min", "G710") };
                        diags.warning(line, w.column, format!("G{}: F stays in {f}, the basic system's (the machine file's inch_basic_system); {g7} would read it in the program's unit", w.raw));
                    }
                }
                Some(u) if (u == crate::program::LengthUnit::Inch) != inch => diags.warning(
                    line,
                    w.column,
                    format!("G{}: the program says {}; its numbers are read in {} (--units)", w.raw, if inch { "inches" } else { "millimetres" }, u.name()),
                ),
                Some(_) => {}
            }
        }
        ("54", true) => c.datum_block = true,
        ("54" | "55" | "56" | "57" | "58" | "59" | "59.1" | "59.2" | "59.3", false) => {
            let k = ["54", "55", "56", "57", "58", "59", "59.1", "59.2", "59.3"].iter().position(|c| *c == code.as_ref()).unwrap_or(0);
            next.system = k;
            next.extra_offset = false;
            if k > 0 && !before.offsets_set(k) && !fanuc && before.dialect != Dialect::Sinumerik {
                diags.warning(
                    line,
                    w.column,
                    format!("G{}: this program never sets its offsets (G10 L2 P{}): taken as zero", w.raw, k + 1),
                );
            }
        }
        // LinuxCNC: the block's coordinates are absolute ones without the work offsets
        // (G-code reference §G53: "machine coordinates", LinuxCNC's world frame, in
        // which the machine files place the kinematics).
        ("53", false) if before.dialect == Dialect::Rs274 => {
            c.g53 = true;
            if !next.absolute {
                diags.error(line, w.column, "G53 under G91: LinuxCNC refuses incremental machine coordinates (write G90 first)");
            }
        }
        ("53", false) => diags.warning(
            line,
            w.column,
            "G53: work offsets are not modelled (G54 is taken as zero), so machine coordinates are read as program coordinates",
        ),
        // G98/G99: a canned cycle returns to the initial level or to the R point.
        ("98" | "99", false) if fanuc || before.dialect == Dialect::Rs274 => next.cycles.to_r = code == "99",
        // Additional work offsets: Fanuc's G54.1 P1-P48 (P300), Haas' G154 P1-P99, and G110-G129 the
        // same as G154 P1-P20 (Haas, "Programmable Offsets": G10 L20 P1-P20 set G110-G129, P1-P99
        // G154 P1-P99). The program's G10 L20 Pn sets one; else it is the operator's, taken as zero.
        ("54.1", false) if fanuc => select_extra_offset(next, before, w, words, line, c, diags),
        (code, false) if haas && haas_extra_offset(code) => select_extra_offset(next, before, w, words, line, c, diags),
        // AI contour control (Q1 on, Q0 off): look-ahead feed control, not the path's
        // geometry (FANUC A-63512EN §2.3: "interpolation data ensures that the machining
        // follows a specified line or curve").
        // Q1 with R1-R10, the machining condition (precision level), feed control as well; Q2
        // (smooth interpolation) and Q3 (nano smoothing) make a curve through the points (FANUC's
        // G05.1 formats, "G05.1 Q1 R1; AI contour control, Machining condition selecting function").
        ("5.1", false) if fanuc => {
            c.uses.push('Q');
            let q = words.iter().find(|q| q.letter == 'Q');
            match q.map(|q| q.value) {
                Some(v) if v == 0.0 => {}
                Some(v) if v == 1.0 => {
                    c.uses.push('R');
                    if let Some(r) = words.iter().find(|r| r.letter == 'R').filter(|r| !(r.value.fract() == 0.0 && (1.0..=10.0).contains(&r.value))) {
                        diags.error(line, r.column, format!("G05.1 Q1 R{}: expected a machining condition R1 to R10", r.raw));
                    }
                }
                Some(v) if v == 2.0 || v == 3.0 => unsupported(diags, "smooth or nano smoothing interpolation: the control makes a curve through the points"),
                _ => diags.error(line, q.map_or(w.column, |q| q.column), "G05.1: expected Q1 (AI contour control on, R1-R10 its machining condition) or Q0 (off)"),
            }
        }
        // High-precision contour control, `G05 P10000` on and `G05 P0` off (FANUC Series
        // 16i/18i-MB, "High-precision contour control"): look-ahead feed control as AI
        // contour is. G05 with another P is high-speed cycle machining (binary data).
        ("5", false) if fanuc && !haas && words.iter().any(|p| p.letter == 'P' && (p.value == 0.0 || p.value == 10000.0)) => c.uses.push('P'),
        ("5", false) if fanuc && !haas => unsupported(diags, "high-speed cycle machining (only G05 P10000 and G05 P0, high-precision contour control on and off, are read)"),
        // Haas' smoothness: P the level (feed), E the most a corner may be rounded,
        // which is the path's tolerance (Haas NGC manual, G187; Setting 85).
        ("187", false) if haas => {
            c.uses.extend(['P', 'E']);
            next.tolerance = match words.iter().find(|w| w.letter == 'E') {
                Some(e) if e.value >= 0.0 && crate::machine::ContourTolerance::linear_ok(e.value * next.unit) => {
                    crate::program::ProgrammedTolerance { linear_m: Some(e.value * next.unit), rotary_rad: None }
                }
                Some(e) => {
                    diags.error(line, e.column, format!("G187 E{}: a corner rounding of 0 to 10 mm", e.raw));
                    next.tolerance
                }
                None => crate::program::ProgrammedTolerance::default(),
            };
        }
        // Haas TCPC: X Y Z are the tool tip on the table (as Fanuc's G43.4), H the length.
        ("234", false) if haas => {
            (next.tcp, next.tool_vector) = (true, false);
            c.uses.push('H');
        }
        // Haas DWO: the work offset turns with the rotary table (3+2 positioning only):
        // "machine = MRZP + Rot(B,C) (G54 - MRZP) + program". With the offsets taken
        // as zero (the part's origin on the rotary axes, this model's frame) the turned
        // offset is the offset itself; an offset the program set is not turned here.
        ("254", false) if haas => {
            if next.datum != [0.0; 3] {
                diags.error(line, w.column, "G254 (dynamic work offset) with a work offset the program set: turning it with the table is not modelled");
            }
            next.dwo = true;
            next.dwo_unplaced = [true; 3];
        }
        ("255", false) if haas => next.dwo = false,
        ("10", false) => {
            c.g10 = true;
            c.uses.extend(['L', 'P']);
            if before.dialect == Dialect::Rs274 {
                c.uses.push('R'); // G10 L2 R: the system's rotation
            }
        }
        // (Two codes of group 0 in one block: Interpreter::block refuses them.)
        ("92" | "92.1" | "92.2" | "92.3" | "52", false) if before.dialect == Dialect::Rs274 => c.g92 = Some(code.to_string()),
        // Fanuc and Haas: G92 shifts every work system; Fanuc's G52 sets the local system
        // ([`Interpreter::fanuc_offsets`]).
        ("92", false) if fanuc => c.g92 = Some(code.to_string()),
        ("52", false) if before.dialect == Dialect::Fanuc => c.g92 = Some(code.to_string()),
        // Fanuc's G92.1 (workpiece coordinate system preset) takes back what G92 and G52 shifted:
        // with nothing shifted it has nothing to do; its rule for a shift is in no manual in reach.
        ("92.1" | "92.2", false) if fanuc && before.axis_offset != [0.0; 3] => {
            diags.error(line, w.column, format!("G{} with a G92 or G52 offset set: how the control presets the work coordinate system is not read (cancel the offset with G92 or G52 first)", w.raw))
        }
        // Nothing shifted: nothing to preset; its axis words (IP0) are its own, no move.
        ("92.1" | "92.2", false) if fanuc => c.g92 = Some(code.to_string()),
        // A change of feed mode leaves no feed: Siemens, "In the event of switching
        // between G93, G94 and G95, the path feedrate value has to be reprogrammed"
        // (Programming Manual Fundamentals, "Feedrate (G93, G94, G95, F ...)");
        // LinuxCNC sets the feed to 0 on every G94 (Interp::convert_feed_mode).
        ("93", false) => {
            if next.feed_mode != FeedMode::InverseTime {
                next.feed = None;
            }
            (next.feed_mode, next.per_revolution) = (FeedMode::InverseTime, false);
        }
        ("94", false) => {
            if next.feed_mode != FeedMode::PerMinute || next.per_revolution || before.dialect == Dialect::Rs274 {
                next.feed = None;
            }
            (next.feed_mode, next.per_revolution) = (FeedMode::PerMinute, false);
        }
        // G95, feed per revolution: LinuxCNC sets the feed to 0 on every G95 as on G94
        // (Interp::convert_feed_mode); Siemens deletes F on a change of G93/G94/G95 (as
        // above); for Fanuc and Haas whether F is kept is not at hand, so it is not kept
        // either (a feed move then wants an F written under G95).
        ("95", false) if !heid && !haas => {
            if !next.per_revolution || before.dialect == Dialect::Rs274 {
                next.feed = None;
            }
            (next.feed_mode, next.per_revolution) = (FeedMode::PerMinute, true);
        }
        ("95", false) if haas => diags.error(line, w.column, "G95 (feed per revolution): not in the Haas mill manual pages at hand, so not read: expected G93 or G94"),
        ("95", false) => diags.error(line, w.column, "G95 (feed per revolution) is not supported: expected G93 or G94"),
        ("43.4", false) => {
            (next.tcp, next.tool_vector) = (true, false);
            c.uses.push('H');
        }
        ("43.5", false) => {
            (next.tcp, next.tool_vector) = (true, true);
            c.uses.push('H');
        }
        // The TCP G43.4/G43.5 turned on; the kinematics' own stays.
        ("49", false) => (next.tcp, next.tool_vector) = (next.kins_tcp, false),
        ("43", false) => {
            c.uses.push('H');
            diags.warning(
                line,
                w.column,
                "G43 tool length offset: the tool length is the machine file's (tool_tip_mm), not the tool table's; \
                 on a table-table machine it only shifts Z by a constant",
            )
        }
        // Blending within a tolerance: what the planner does (P and Q: below).
        ("64", false) => {
            c.uses.extend(['P', 'Q']);
            c.blend_word = true;
            next.exact = Exact::Blend;
        }
        // LinuxCNC: G61 exact path, G61.1 exact stop (G-code reference §G61, G61.1;
        // the planner's TC_TERM_COND_EXACT and _STOP). Fanuc and Haas: G61 exact stop
        // mode, G09 exact stop for one block ("the tool is decelerated at the end
        // point of a block, then an in-position check is made": FANUC B-64484EN,
        // "Exact stop (G09, G61)"; Haas Mill Operator's Manual, G09 and G61).
        ("61", false) if before.dialect == Dialect::Rs274 => {
            next.exact = Exact::Path;
            diags.warning(
                line,
                w.column,
                "G61 (exact path): the machine stops wherever the next block does not go on in the same direction; \
                 LinuxCNC passes a kink of little acceleration at a reduced speed instead, here a stop",
            );
        }
        ("61.1", false) if before.dialect == Dialect::Rs274 => next.exact = Exact::Stop,
        ("61", false) if fanuc => next.exact = Exact::Stop,
        // Fanuc's automatic override for inner corners, G62, of G61's and G64's group:
        // "valid until G61 or G64 is specified", the feed overridden "when the tool
        // moves along an inner corner during cutter compensation" (FANUC Series 0i
        // Operator's Manual B-64154EN §5.4, Table 5.4): without compensation (which
        // is refused) it runs as G64 does.
        ("62", false) if before.dialect == Dialect::Fanuc => next.exact = Exact::Blend,
        ("9", false) if fanuc => c.exact_stop_here = true,
        ("4", _) => {
            c.uses.push('P');
            c.dwell_word = Some(w);
        }
        // Scaling and mirror image cancel (FANUC B-64484EN "Scaling", "Programmable mirror image";
        // Haas G50/G50.1): G51 and G51.1 are refused, so none is in effect here and the cancel changes
        // nothing (after a refused one, [`super::lasting`] ends its hold).
        ("50" | "50.1", false) if fanuc => {}
        // Normal direction control cancel (FANUC B-64484EN "Normal direction control"): G41.1/G42.1
        // are refused, so none is in effect here.
        ("40.1", false) if before.dialect == Dialect::Fanuc => {}
        // The cancels of the polar coordinate command and polar coordinate interpolation (FANUC
        // B-64484EN "Polar coordinate command (G15, G16)", "Polar coordinate interpolation (G12.1,
        // G13.1)"): G16 and G12.1 are refused, so neither is in effect here (after a refused one,
        // [`super::lasting`] ends its hold).
        ("15" | "13.1", false) if before.dialect == Dialect::Fanuc => {}
        ("61" | "61.1", false) => unsupported(diags, "exact stop mode: the planner blends blocks as G64 does"),
        ("41.1" | "42.1", false) if before.dialect == Dialect::Fanuc => unsupported(diags, "normal direction control"),
        ("41" | "42" | "41.1" | "42.1", false) => unsupported(diags, "cutter radius compensation"),
        ("51.1", false) if fanuc => unsupported(diags, "programmable mirror image"),
        ("43.1" | "43.2", false) => unsupported(diags, "dynamic tool length offset"),
        // LinuxCNC has none of them (its rotation is G10 L2 R): in its dialect, a FANUC or Haas
        // program read as RS274NGC, its dialect guessed from a `.nc` name on a machine without a control.
        ("68" | "68.2" | "68.3" | "68.4" | "69" | "53.1" | "53.6", false) => match before.dialect {
            Dialect::Rs274 => diags.error(line, w.column, format!("G{}: no LinuxCNC code (FANUC's and Haas' coordinate rotation or tilted working plane){RS274_NOT_FANUC}", w.raw)),
            _ => unsupported(diags, "coordinate rotation or tilted working plane"),
        },
        _ if unread.is_some() => unsupported(diags, unread.unwrap_or_default()),
        ("28" | "28.1" | "30" | "30.1", false) => unsupported(diags, "move to a stored position"),
        ("33" | "33.1" | "76" | "38.2" | "38.3" | "38.4" | "38.5", false) => unsupported(diags, "threading or probing"),
        ("73" | "74" | "81" | "82" | "83" | "84" | "85" | "86" | "87" | "88" | "89", false) => unsupported(diags, "canned cycle"),
        ("92" | "92.3", false) => unsupported(diags, "coordinate system offset"),
        // LinuxCNC's lathe modes; FANUC's G07/G08 are other functions, not read (the unknown code's
        // message below).
        ("7" | "8", false) if before.dialect == Dialect::Rs274 => unsupported(diags, "lathe diameter or radius mode"),
        ("50" | "51" | "52", false) => unsupported(diags, "scaling or local offset"),
        _ => diags.error(
            line,
            w.column,
            format!("unknown G code G{}: not read (it may change the motion){}", w.raw, if before.dialect == Dialect::Rs274 { RS274_NOT_FANUC } else { "" }),
        ),
    }
}

/// What a G code LinuxCNC does not have says in the RS274NGC dialect: the program may be another
/// control's, read as LinuxCNC's because its name (`.nc`) and its machine said no other.
const RS274_NOT_FANUC: &str = "; read as LinuxCNC's RS274NGC: a FANUC or Haas program is read with --dialect fanuc or haas, or on a built-in machine of its control";

/// Selecting an additional work offset: Fanuc's `G54.1 Pn`, Haas' `G154 Pn` and `G110`-`G129` (P1-P20).
/// One a refused `G10 L20` set is refused (its moves are held, [`super::lasting`]).
#[allow(clippy::too_many_arguments)]
fn select_extra_offset<'w, 't>(next: &mut Interpreter, before: &Interpreter, w: &'w Word<'t>, words: &[Word], line: usize, c: &mut BlockCodes<'w, 't>, diags: &mut Diags) {
    let code = super::x10(w);
    let (p, column, said) = if code == 541 || code == 1540 {
        c.uses.push('P');
        // Fanuc's P1-P48 (P300 with the option); Haas' G154 (and G54.1) P1-P99.
        let most = extra_offsets_most(before.dialect);
        match words.iter().find(|p| p.letter == 'P') {
            Some(p) if p.value.fract() == 0.0 && (1.0..=most).contains(&p.value) => (p.value as u32, p.column, format!(" P{}", p.raw)),
            Some(p) if before.dialect == Dialect::Haas => return diags.error(line, p.column, format!("G{} P{}: expected P1 to P99 (an additional work offset)", w.raw, p.raw)),
            Some(p) => return diags.error(line, p.column, format!("G{} P{}: expected P1 to P48 (P300 with the option), an additional work offset", w.raw, p.raw)),
            None if code == 1540 => return diags.error(line, w.column, "G154 without P: expected P1 to P99 (an additional work offset)"),
            None => return diags.error(line, w.column, format!("G{} without P: expected P1 to P48 (an additional work offset)", w.raw)),
        }
    } else {
        (haas_offset_p(code), w.column, String::new())
    };
    if let Some(at) = before.offset_refused(f64::from(p)) {
        return diags.error(line, column, format!("G{}{said}: line {at}'s G10 L20 P{p} set this offset, and was refused (not read): the moves in it are not read either", w.raw));
    }
    if before.extra_offset_value(p).is_none() {
        diags.warning(line, w.column, format!("G{}: additional work offsets are not set by the program (G10 L20 P{p}): taken as zero", w.raw));
    }
    next.system = 0;
    next.extra_offset = true;
    next.extra_p = p;
}

/// The additional work offset a block selects (its P, and the code as a message names it: `54.1`,
/// `154`, `110`), in the dialect's codes.
pub(crate) fn extra_offset_selected(dialect: Dialect, words: &[Word]) -> Option<(u32, String)> {
    let p = words.iter().find(|w| w.letter == 'P').map(|w| w.value).filter(|p| p.fract() == 0.0 && (1.0..=300.0).contains(p));
    words.iter().filter(|w| w.letter == 'G').find_map(|w| {
        let code = super::x10(w);
        let named = w.raw.trim_start_matches('0').to_string();
        match (dialect, code) {
            (Dialect::Fanuc | Dialect::Haas, 541) | (Dialect::Haas, 1540) => p.map(|p| (p as u32, named)),
            (Dialect::Haas, 1100..=1290) if code % 10 == 0 => Some((haas_offset_p(code), named)),
            _ => None,
        }
    })
}

/// The additional offset Haas' `G110`-`G129` (code × 10) name: P1-P20, as `G154 P1`-`P20` (Haas,
/// "Programmable Offsets").
fn haas_offset_p(code_x10: i64) -> u32 {
    (code_x10 / 10 - 109) as u32
}

/// The highest additional work offset P: Fanuc's P300 (P1-P48 without the option), Haas' P99.
pub(super) fn extra_offsets_most(dialect: Dialect) -> f64 {
    if dialect == Dialect::Haas { 99.0 } else { 300.0 }
}

/// Haas' additional work offsets: `G154` (with P1-P99) and `G110`-`G129`.
pub(crate) fn haas_extra_offset(code: &str) -> bool {
    code == "154" || code.parse::<u32>().is_ok_and(|n| (110..=129).contains(&n))
}
