//! Codes a block's words may carry whose reading is a rule of its own: makers' M functions, the
//! TNC's M functions, Fanuc's G43.5 tool vector.

use super::block::{BlockCodes, Reader};
use super::{Interpreter, OneShot, Word};
use crate::program::cutter_comp::ArcFeed;
use crate::program::{Dialect, MCodeAction};
use crate::program::lex::Diags;
use crate::program::params::INTEGER_CLOSE;
use crate::program::Targets;

/// Why a machine maker's M function (on a Sinumerik, Fanuc or Haas control) is refused: what it does
/// is the machine's, said by its file or a flag.
pub(super) fn maker_m_function(raw: &str, code: i64) -> String {
    format!("M{raw}: the machine maker's M function, whose effect is not known here: its machine file names it ([[m_function]]), or say what it does with --m-code {code}=tcp-on|tcp-off|event")
}

/// The tool axis of a `G43.5` block from its `I J K` (all three, any length but zero; normalised as
/// the control does). Rotary-axis words beside a vector would contradict it: an error.
pub(super) fn tool_vector(words: &[Word], targets: &Targets, line: usize, column: usize, diags: &mut Diags) -> Option<[f64; 3]> {
    let get = |l: char| words.iter().find(|w| w.letter == l).map(|w| w.value);
    let (Some(i), Some(j), Some(k)) = (get('I'), get('J'), get('K')) else {
        diags.error(line, column, "G43.5 tool vector: expected I, J and K together");
        return None;
    };
    if targets.a.is_some() || targets.b.is_some() || targets.c.is_some() {
        diags.error(line, column, "G43.5 block with both a tool vector (I J K) and rotary-axis words: expected one of them");
        return None;
    }
    let n = (i * i + j * j + k * k).sqrt();
    if !(n > 1e-9) {
        diags.error(line, column, "G43.5 tool vector I J K has zero length: expected a direction");
        return None;
    }
    Some([i / n, j / n, k / n])
}

/// Whether a Heidenhain TNC M function (besides M0-M9, M13, M14, M30, M128, M129) leaves the
/// programmed motion as this model runs it (iTNC 530 / TNC 640 User's Manual, "Miscellaneous
/// functions"); `Err` says why not, `Err(None)` where it is not the TNC's but the machine maker's
/// own, refused until the machine file or `--m-code` says what it does.
pub(super) fn tnc_m_code(code: i64) -> Result<(), Option<&'static str>> {
    match code {
        // Tool life, handwheel superposition (no motion of its own), look-ahead for radius
        // compensation (M120: its blocks LA, how many, is refused as a word), rotary shortest path
        // off (the reset state), touch probe
        // monitoring, lift-off at NC stop.
        101 | 102 | 118 | 120 | 127 | 141 | 148 | 149 => Ok(()),
        // A replacement tool's radius: its check off / on (M108 also resets M107; TNC7 basic user's
        // manual 81762x-18, "Checking the radius of the replacement tool with M108"): no motion.
        107 | 108 => Ok(()),
        // Resets to the state this model runs: M137 of M136 (the feed in mm/min again, iTNC 530
        // user's manual, "Feed rate in millimeters per spindle revolution: M136"), M113 of M112.
        113 | 137 => Ok(()),
        // The resets of M114, M134 and M144 (iTNC 530 user's manual 60642x-03 §12.5-12.6), which
        // this model refuses and holds until them ([`super::lasting`]): with none in effect, nothing.
        115 | 135 | 145 => Ok(()),
        // Radius compensation at contour steps and open corners (TNC 620 user's manual 81760x-02
        // §10.4, "Machining small contour steps: M97", "Machining open contour corners: M98").
        97 | 98 => Err(Some("the TNC's M function for radius compensation at small contour steps (M97) or open contour corners (M98): not modelled (it changes the tool path)")),
        // Rounding arcs the TNC inserts between straight lines within a tolerance, and the points
        // it leaves out for them (TNC 426/430 user's manual, "Insert rounding arc between straight
        // lines: M112", M124).
        112 | 124 => Err(Some("the TNC's rounding of the path between straight lines within a tolerance (M112, M124): not modelled (it changes the tool path)")),
        91 | 92 | 130 => Err(Some("positions in the machine coordinate system are not modelled (it changes the motion)")),
        89 | 99 => Err(Some("cycle call: machining cycles are not read (they cut)")),
        103 | 136 => Err(Some("changes how the feed is read: not modelled")),
        94 => Err(Some("reducing the rotary axis display below 360 deg is not modelled (it changes later absolute positions)")),
        114 | 134 | 138 | 140 | 143 | 144 => Err(Some("not modelled (it changes the motion)")),
        _ => Err(None),
    }
}

/// What a TNC program's `F` after `M128` in its block is (`M128 F1000`, iTNC 530 ISO user's manual
/// 340 49x-04 §7.5: "After M128 you can program another feed rate, at which the TNC will carry out
/// the compensation movements in the linear axes", bounded by MP7471; "L X+0 Y+38.5 IB-15 RL F125
/// M128 F1000"): the warning that says so, as neither it nor MP7471 is modelled (the machine file's
/// axis limits bound those movements). `written`: the word as the program has it.
pub(crate) fn m128_feed_said(written: &str) -> String {
    format!("{written}: the feed of the linear axes' compensating movements under M128, not the path's feed; not modelled (the machine file's axis limits bound them, as the TNC's MP7471 does)")
}

/// The modal motions of G group 01 that the G-code readers (LinuxCNC, Fanuc, Haas) do not read, by
/// code times ten: LinuxCNC's splines G5, G5.1, G5.2 and NURBS G5.3 (G-code reference), Fanuc's
/// NURBS G06.2 (read by [`crate::program::fanuc_nurbs`] on Fanuc, not Haas), G06.1 (spline) and the
/// 3D circles G02.4/G03.4 (FANUC B-64484EN). Refused, and the moves after them without a G0-G3 of
/// their own with them ([`Interpreter::forget_motion`]). Fanuc's G05 is no motion (high-speed
/// machining, group 00). Threading and probing are motions of that group too: G33 (FANUC B-64484EN
/// "Thread cutting", group 01), LinuxCNC's G33.1, G38.2-G38.5 and G76 (its modal group 1, whose G76
/// is a threading cycle; Fanuc's is a canned cycle, held as one).
pub(crate) fn unread_motion(dialect: crate::program::Dialect, code_x10: i64) -> Option<&'static str> {
    use crate::program::Dialect;
    match code_x10 {
        // Fanuc's G05 is no motion; its G06.2 is read (a refusal is the curve's defect, an alarm).
        50 | 62 if dialect == Dialect::Fanuc => None,
        50 | 51 | 52 | 53 | 61 | 62 => Some("spline or NURBS motion"),
        24 | 34 => Some("3D circular interpolation"),
        330 => Some("threading or probing"),
        331 | 382 | 383 | 384 | 385 | 760 if dialect == Dialect::Rs274 => Some("threading or probing"),
        _ => None,
    }
}

/// A move of one block the G-code readers do not read and the control makes (code × 10), where it
/// leaves the axes it names being what this reader does not know: Fanuc's and Haas' G27 (reference
/// position return check), G29 (return from the reference position), G31 (skip: it stops where the
/// signal comes), G60 (single-direction positioning), and G28/G30/G53 where they are refused (no
/// machine coordinates in the machine file); LinuxCNC's G28/G30 and Haas' G28 without axis words
/// move every axis.
pub(crate) fn unread_move(dialect: crate::program::Dialect, code_x10: i64) -> Option<&'static str> {
    match code_x10 {
        270 | 290 | 310 | 600 if dialect.is_fanuc() => Some("a move this reader does not read"),
        530 if dialect.is_fanuc() => Some("a move in machine coordinates"),
        280 | 300 => Some("a move to a stored position"),
        _ => None,
    }
}

/// A G word's code times ten, as LinuxCNC numbers them (G41.1 is 411): no text to compare.
pub(crate) fn x10(w: &Word) -> i64 {
    (w.value * 10.0).round() as i64
}

/// LinuxCNC's modal group of a G code, given as its number times ten (interp_array.cc `_gees`,
/// after [NCMS] and [Fanuc]): "only one g_code from any one group may appear on a line". Group 0 is
/// the non-modal codes, 1 the motions and canned cycles; `None` for a code outside the table (the
/// interpreter refuses it by itself).
pub(crate) fn lcnc_group(code_x10: i64) -> Option<u8> {
    Some(match code_x10 {
        40 | 100 | 280 | 281 | 300 | 301 | 520 | 530 | 920 | 921 | 922 | 923 => 0,
        0 | 10 | 20 | 30 | 50 | 51 | 52 | 53 | 330 | 331 | 382 | 383 | 384 | 385 | 700 | 710 | 711 | 712 | 720 | 721 | 722 | 730 | 740 | 760 | 800 | 810 | 820 | 830 | 840 | 850 | 860 | 870 | 880 | 890 => 1,
        170 | 171 | 180 | 181 | 190 | 191 => 2,
        900 | 910 => 3,
        901 | 911 => 4,
        930 | 940 | 950 => 5,
        200 | 210 => 6,
        400 | 410 | 411 | 420 | 421 => 7,
        430 | 431 | 432 | 490 => 8,
        980 | 990 => 10,
        540 | 550 | 560 | 570 | 580 | 590 | 591 | 592 | 593 => 12,
        610 | 611 | 640 => 13,
        960 | 970 => 14,
        70 | 80 => 15,
        _ => return None,
    })
}

/// LinuxCNC's modal group of an M code (`None` for a code outside the table, which the interpreter
/// refuses by itself): one of each group in a block (interp_array.cc `_ems`, after [NCMS]; as
/// Debian's rs274 2.9 refuses each pair, recordings/programs/linuxcnc/words): 4 stopping, 5 I/O, 6
/// tool change, 7 spindle and modal state (M70-M73), 8 coolant, 9 override switches, 10
/// user-defined.
fn lcnc_m_group(code: f64) -> Option<u8> {
    if code.fract() != 0.0 {
        return None;
    }
    Some(match code as i64 {
        0 | 1 | 2 | 30 | 60 => 4,
        62..=68 => 5,
        6 | 61 => 6,
        3 | 4 | 5 | 19 | 70..=73 => 7,
        7..=9 => 8,
        48..=53 => 9,
        100..=199 => 10,
        _ => return None,
    })
}

/// The second code of one modal group in a block, the first, and the group (`group` of a `letter`
/// word; LinuxCNC reads one of each).
fn second_of_group<'w, 'a>(words: &'w [Word<'a>], letter: char, group: impl Fn(&Word) -> Option<u8>) -> Option<(&'w Word<'a>, &'w Word<'a>, u8)> {
    let mut seen: [Option<&Word>; 16] = [None; 16];
    for w in words.iter().filter(|w| w.letter == letter) {
        let Some(g) = group(w).filter(|&g| g < 16) else { continue };
        if let Some(first) = seen[g as usize] {
            return Some((w, first, g));
        }
        seen[g as usize] = Some(w);
    }
    None
}

/// The block writes an axis word, as LinuxCNC counts them: its nine axes, and polar coordinates
/// (`@`, `^`), which are X and Y. What its rules on G52/G92, G53 and motion without axes ask.
pub(crate) fn lcnc_axis_words(words: &[Word]) -> bool {
    words.iter().any(|w| matches!(w.letter, 'X' | 'Y' | 'Z' | 'A' | 'B' | 'C' | 'U' | 'V' | 'W' | '@' | '^'))
}

/// What LinuxCNC refuses in a block's words, where this reader would run it or leave it be: its
/// column and why, with LinuxCNC's own message (rs274ngc_errors.cc, as Debian's rs274 2.9 prints
/// it), in the order it checks them. Two G codes or two M codes of one modal group; a code of group
/// 0 that takes the axis words (G10, G28, G30, G52, G92: interp_array.cc, "those in group 0 which
/// require coordinate values may not be on the same line as those in group 1 (except g80)") with a
/// motion code, a G52/G92 without an axis word, an arc code without R, I, J or K, a negative S, a T
/// that is negative or not whole (within [`INTEGER_CLOSE`], NIST IR 6556 §3.3.2's "close enough"),
/// an M61 without a tool number Q of 0 or more, an M19 whose R, P or Q is out of its range; in a
/// block that moves no axis, a G1, G2 or G3 without F in inverse time, and a G1 with no feed (none
/// set yet, or a G93/G94/G95 since, which zero it); a tool the machine's tool table (`tools`, where
/// given) does not list. The state before the block: inverse time (`inverse_time`), and a feed set
/// (`feed_set`). (G53 without axes is [`super::Interpreter::block_one`]'s, with its motion.)
pub(crate) fn lcnc_refusal(words: &[Word], inverse_time: bool, feed_set: bool, tools: Option<&crate::program::cutter_comp::ToolTable>) -> Option<(usize, String)> {
    if let Some((w, first, g)) = second_of_group(words, 'G', |w| lcnc_group(x10(w))) {
        return Some((w.column, format!("G{} with G{}: two G codes of modal group {g} in one block (LinuxCNC: \"Two G-codes used from same modal group\")", w.raw, first.raw)));
    }
    if let Some((w, first, g)) = second_of_group(words, 'M', |w| lcnc_m_group(w.value)) {
        return Some((w.column, format!("M{} with M{}: two M codes of modal group {g} in one block (LinuxCNC: \"Two M codes used from same modal group\")", w.raw, first.raw)));
    }
    let axes = lcnc_axis_words(words);
    let g = |code_x10: i64| words.iter().find(|w| w.letter == 'G' && x10(w) == code_x10);
    let takes_axes = words.iter().find(|w| w.letter == 'G' && matches!(x10(w), 100 | 280 | 300 | 520 | 920));
    let motion = words.iter().find(|w| w.letter == 'G' && lcnc_group(x10(w)) == Some(1) && x10(w) != 800);
    if let (Some(a), Some(m)) = (takes_axes, motion) {
        return Some((m.column, format!("G{} with G{}: two G codes that both use axis words in one block (LinuxCNC: \"Cannot use two g codes that both use axis values\")", m.raw, a.raw)));
    }
    if let Some(w) = g(520).or_else(|| g(920)).filter(|_| !axes) {
        return Some((w.column, format!("G{} without an axis word (LinuxCNC: \"All axes missing with g52 or g92\")", w.raw)));
    }
    if let Some(w) = g(20).or_else(|| g(30)).filter(|_| !words.iter().any(|w| matches!(w.letter, 'R' | 'I' | 'J' | 'K'))) {
        return Some((w.column, format!("G{} without its radius R or centre I J K (LinuxCNC: \"R i j k words all missing for arc\")", w.raw)));
    }
    if let Some(w) = words.iter().find(|w| w.letter == 'S' && w.value < 0.0) {
        return Some((w.column, format!("S{}: a negative spindle speed (LinuxCNC: \"Negative spindle speed used\")", w.raw)));
    }
    if let Some(w) = words.iter().find(|w| w.letter == 'T' && (w.value < 0.0 || (w.value - w.value.round()).abs() > INTEGER_CLOSE)) {
        let why = if w.value < 0.0 { "Negative tool id (tool not found)" } else { "Non integer value for integer" };
        return Some((w.column, format!("T{}: a tool number is a whole number of 0 or more (LinuxCNC: \"{why}\")", w.raw)));
    }
    // The feed: F in the block, else none where the block or an earlier one changed the feed mode.
    let mode = words.iter().rev().find(|w| w.letter == 'G' && matches!(x10(w), 930 | 940 | 950));
    let has_f = words.iter().any(|w| w.letter == 'F');
    let inverse = mode.map_or(inverse_time, |w| x10(w) == 930);
    // (A block that moves is refused so by the feed's own checks, which say more.)
    if let Some(w) = words.iter().find(|w| w.letter == 'G' && matches!(x10(w), 10 | 20 | 30)).filter(|_| !has_f && !axes) {
        if inverse {
            let what = if x10(w) == 10 { "g1" } else { "arc" };
            return Some((w.column, format!("G{} in inverse time (G93) without F, the block's time (LinuxCNC: \"F word missing with inverse time {what} move\")", w.raw)));
        }
        if x10(w) == 10 && (mode.is_some() || !feed_set) {
            return Some((w.column, format!("G{} with no feed: none set yet, or none since a G93, G94 or G95 (LinuxCNC: \"Cannot do g1 with zero feed rate\")", w.raw)));
        }
    }
    // M19, the spindle's orientation: R its angle 0-360 deg, P its way 0, 1 or 2, Q a time > 0.
    if words.iter().any(|w| w.letter == 'M' && w.value == 19.0) {
        let word = |l: char| words.iter().find(|w| w.letter == l);
        if let Some(r) = word('R').filter(|r| !(0.0..=360.0).contains(&r.value)) {
            return Some((r.column, format!("M19 R{}: the orientation is 0 to 360 deg (LinuxCNC: \"R value must be within 0..360 with M19\")", r.raw)));
        }
        if let Some(p) = word('P') {
            if (p.value - p.value.round()).abs() > INTEGER_CLOSE {
                return Some((p.column, format!("M19 P{}: the way to turn is a whole number (LinuxCNC: \"P value not an integer with M19 G2 or G3\")", p.raw)));
            }
            if !(0.0..=2.0).contains(&p.value.round()) {
                return Some((p.column, format!("M19 P{}: the way to turn is 0, 1 or 2 (LinuxCNC: \"P value must be 0,1,or 2 with M19\")", p.raw)));
            }
        }
        if let Some(q) = word('Q').filter(|q| q.value <= 0.0) {
            return Some((q.column, format!("M19 Q{}: the time to orient is more than 0 s (LinuxCNC: \"Q word with M19 requires a value > 0\")", q.raw)));
        }
    }
    if let Some(w) = words.iter().find(|w| w.letter == 'M' && w.value == 61.0) {
        if !words.iter().any(|q| q.letter == 'Q' && q.value >= 0.0) {
            return Some((w.column, "M61 without the tool number Q, 0 or more (LinuxCNC: \"Need non-negative Q-word to specify tool number with M61\")".to_string()));
        }
    }
    // T0 is no tool.
    let listed = |t: &Word| tools.is_none_or(|table| table.diameter(t.value.round() as u32).is_some());
    if let Some(t) = words.iter().find(|w| w.letter == 'T' && w.value >= 1.0 && !listed(w)) {
        let n = t.value.round();
        return Some((t.column, format!("T{}: tool {n} is not in the tool table (LinuxCNC: \"Requested tool {n} not found in the tool table\")", t.raw)));
    }
    None
}

/// One M word of a block: `next` is the state the block changes, `before` the state before it, `shot`
/// the block's one-shot move (the Klartext reader's M91/M92). Part of [`Interpreter::block_one`].
#[allow(clippy::too_many_arguments)]
pub(super) fn m_code(next: &mut Interpreter, before: &Interpreter, w: &Word, shot: Option<OneShot>, line: usize, r: Reader, c: &mut BlockCodes<'_, '_>, diags: &mut Diags) {
    let Reader { heid, fanuc, .. } = r;
    let rs274 = before.dialect == Dialect::Rs274;
    let code = w.value as i64;
    if w.value.fract() != 0.0 || w.value < 0.0 {
        diags.error(line, w.column, format!("M{}: expected a whole M code number", w.raw));
        return;
    }
    let rule = before.m_codes.iter().find(|r| i64::from(r.code) == code).map(|r| r.action);
    match (rule, code, heid) {
        (Some(MCodeAction::TcpOn), _, _) => (next.tcp, next.kins_tcp) = (true, true),
        (Some(MCodeAction::TcpOff), _, _) => (next.tcp, next.kins_tcp) = (false, false),
        (Some(MCodeAction::Event), _, _) => {}
        (None, 128, true) => next.tcp = true,
        // M126 / M127: the shorter way for rotary axes shown modulo 360 deg, on / off
        // (TNC 620 10/2017 §13 "Shorter-path traverse of rotary axes: M126").
        (None, 126, true) => next.shortest = true,
        (None, 127, true) => next.shortest = false,
        (None, 129, true) => next.tcp = false,
        // M109/M110/M111: the feed on arcs at the tool's cutting edge, inside and
        // outside contours / inside only / reset (iTNC 530 ISO user's manual 340 49x-02
        // §7.4 "Feed rate for circular arcs"): what radius compensation makes of it.
        (None, 109, true) => next.arc_feed = ArcFeed::Edge,
        (None, 110, true) => next.arc_feed = ArcFeed::EdgeInside,
        (None, 111, true) => next.arc_feed = ArcFeed::Centre,
        // M116/M117: a rotary axis' feed in mm/min, on / off (iTNC 530 user's manual
        // 60642x-03 §12.5), checked below where it acts.
        (None, 116, true) => next.m116 = true,
        (None, 117, true) => next.m116 = false,
        // The spindle: M3/M4 turn it, M5 stops it (LinuxCNC: M19 orients it, stopped);
        // the TNC's M13/M14 turn it with the coolant on.
        (None, 3 | 4, _) | (None, 13 | 14, true) => (next.spindle_turning, next.spindle_ccw) = (Some(true), matches!(code, 4 | 14)),
        (None, 5, _) => next.spindle_turning = Some(false),
        (None, 19, false) => {
            next.spindle_turning = Some(false);
            if rs274 {
                c.uses.extend(['R', 'Q', 'P']);
            }
        }
        // LinuxCNC's tool change stops the spindle (Debian's rs274 2.9 gives STOP_SPINDLE_TURNING
        // before CHANGE_TOOL; a G86 after it is "Spindle not turning in g86").
        (None, 6, false) if rs274 => next.spindle_turning = Some(false),
        (None, 0..=9 | 13 | 14 | 30, _) => {}
        // M91/M92: the Klartext reader made this block a move of the axes (its oneshot).
        (None, 91 | 92, true) if shot.is_some_and(|s| s.axes.is_some()) => {}
        (None, _, true) => {
            match tnc_m_code(code) {
                Ok(()) => {}
                Err(why) => {
                    // The TNC runs it (the machine maker's too): said to the readers' holds.
                    c.ran_unread = Some(code);
                    match why {
                        Some(why) => diags.error(line, w.column, format!("M{}: {why}", w.raw)),
                        None => diags.error(line, w.column, maker_m_function(&w.raw, code)),
                    }
                }
            }
        }
        // Sinumerik's own M functions (Fundamentals §"Miscellaneous functions (M)": M17
        // end of subprogram, M19 spindle positioning (above: it stops the spindle), M40-M45 gear stages, M70 spindle
        // to axis mode); any other is the machine maker's.
        (None, 17 | 40..=45 | 70, false) if before.dialect == Dialect::Sinumerik => {}
        (None, _, false) if before.dialect == Dialect::Sinumerik => diags.error(line, w.column, maker_m_function(&w.raw, code)),
        // LinuxCNC's own M codes that move nothing: spindle orient, overrides, tool, I/O,
        // with the words they take (G-code reference §M19 R Q P, §M61 Q, §M62-M65 P,
        // §M66 P E L Q, §M67/M68 E Q).
        // M99 in the main program: its end (the reader's; super::super::lcnc_m98).
        (None, 99, false) if rs274 => {}
        (None, 98, false) if rs274 => diags.error(line, w.column, "M98 calls a Fanuc-style subprogram only as the first word of its line (after its N number): LinuxCNC reads it there, as a block of its own"),
        (None, 48..=53 | 60, false) if rs274 => {}
        (None, 61, false) if rs274 => c.uses.push('Q'),
        (None, 62..=65, false) if rs274 => c.uses.push('P'),
        (None, 66, false) if rs274 => c.uses.extend(['P', 'E', 'L', 'Q']),
        (None, 67 | 68, false) if rs274 => c.uses.extend(['E', 'Q']),
        (None, _, false) if fanuc => diags.error(line, w.column, maker_m_function(&w.raw, code)),
        (None, _, false) => diags.error(
            line,
            w.column,
            format!(
                "M{} is not an RS274NGC M code: a machine-specific one (LinuxCNC user M100-M199 or a remap) \
                 whose effect is unknown: its machine file names it ([[m_function]]), or say what it does \
                 with --m-code {}=tcp-on|tcp-off|event \
                 (LinuxCNC's vismach five-axis demos: 428=tcp-on, 429=tcp-off)",
                w.raw, code
            ),
        ),
    }
    c.events.push(format!("M{}", w.raw));
}
