//! One block's words interpreted: modal G codes, M functions, feed, targets and arcs, into a
//! [`Block`] (the [`Interpreter`]'s state changes only when the block has no defect).

use super::arc::resolve_arc;
use super::codes::{m_code, tool_vector};
use super::g_codes::g_code;
use super::{Dimension, Interpreter, Word, AXIS_LETTERS};
use crate::program::lex::Diags;
use crate::program::{ArcSpec, Block, Dialect, Exact, FeedMode, Motion, Plane, Targets};
use crate::units::MM;

/// Which reader a block is read for, as the codes' rules ask it.
#[derive(Clone, Copy)]
pub(super) struct Reader {
    /// Heidenhain DIN/ISO and conversational share the TNC's words: modal circle centre I J K,
    /// M128/M129, and the TNC's M functions.
    pub heid: bool,
    /// Fanuc-style controls (Fanuc, Haas).
    pub fanuc: bool,
    pub haas: bool,
    /// The TNC's DIN/ISO tool call `T1 G17`: the block's plane code is the tool axis.
    pub tool_call: bool,
    /// The TNC's DIN/ISO blank form or tool definition: the block's words define, they do not move.
    pub defines: bool,
}

/// What a block's G and M codes said beyond the modal state they set.
#[derive(Default)]
pub(super) struct BlockCodes<'w, 't> {
    /// Letters besides the axes that a code of this block takes.
    pub uses: Vec<char>,
    /// `G10`: the block's axis words set an offset.
    pub g10: bool,
    /// LinuxCNC's G92, G92.1-G92.3 and G52: the code, applied once the block's modal codes are.
    pub g92: Option<String>,
    /// This block ends in a stop (Fanuc's and Haas' G09, Sinumerik's G9).
    pub exact_stop_here: bool,
    /// LinuxCNC's `G53`: the block's coordinates are machine coordinates.
    pub g53: bool,
    /// The dwell's `G4`.
    pub dwell_word: Option<&'w Word<'t>>,
    /// `G64`: blending within a tolerance.
    pub blend_word: bool,
    /// The TNC's DIN/ISO datum shift `G54`.
    pub datum_block: bool,
    /// The block's M, S, T and D words, said as events.
    pub events: Vec<String>,
    /// A TNC M function this model refuses and the TNC runs (its code): where the block leaves the
    /// tool is not known.
    pub ran_unread: Option<i64>,
}

impl Interpreter {
    /// Interpret one block's words into one block (see [`Interpreter::block`]).
    pub(crate) fn block_one(&mut self, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags) -> Option<Block> {
        // The TNC's M118 takes the axis values after it in its block: the handwheel's most travel
        // ("L X+0 Y+38.5 RL F125 M118 X1 Y1", iTNC 530 user's manual, "Superimposing handwheel
        // positioning during program run: M118"), no move; the move's are before it.
        let m118 = words.iter().find(|w| w.letter == 'M' && w.value == 118.0).map(|w| w.column);
        let handwheel: Vec<Word>;
        let after = |w: &Word, m: usize| w.column > m && AXIS_LETTERS.contains(&w.letter);
        let words = match m118 {
            Some(m) if matches!(self.dialect, Dialect::Heidenhain | Dialect::Klartext) && words.iter().any(|w| after(w, m)) => {
                handwheel = words.iter().filter(|w| !after(w, m)).cloned().collect();
                handwheel.as_slice()
            }
            _ => words,
        };
        let shot = self.oneshot.take();
        // Said by this block only, where it is refused ([`Interpreter::refused_block`]).
        self.ran_unread = None;
        if shot.is_some_and(|s| s.axes.is_some() && !s.own) && self.tilt.is_some() {
            let why = if self.dialect.is_fanuc() {
                "machine coordinates under a tilted working plane (G68.2): not read (what the control does with them there is not at hand); cancel the plane with G69 first"
            } else {
                "machine coordinates in a tilted working plane: the control refuses them (TNC 426 B ISO §7.3: \"M91 and M92 are not effective in a tilted working plane\"); reset the plane first"
            };
            diags.error(line, column, why);
            return None;
        }
        // The state before the block, put back if the block has a defect (the state changes only when
        // it has none); the block changes the state in place.
        let mut before = self.clone();
        let next = &mut *self;
        let errors_before = diags.errors();
        let mut feed_word: Option<&Word> = None;
        // Heidenhain DIN/ISO and conversational share the TNC's words: modal circle centre I J K,
        // M128/M129, and the TNC's M functions.
        let heid = matches!(before.dialect, Dialect::Heidenhain | Dialect::Klartext);
        // Fanuc-style controls (Fanuc, Haas) and Haas alone.
        let (fanuc, haas) = (before.dialect.is_fanuc(), before.dialect == Dialect::Haas);
        // The TNC's DIN/ISO tool call `T1 G17`: the block's plane code is the tool axis.
        let tool_call = before.dialect == Dialect::Heidenhain && words.iter().any(|w| w.letter == 'T');
        // An axis, centre, radius, feed, dwell or turns (P), peck (Q) or spindle speed written twice:
        // LinuxCNC refuses every letter but G and M twice ("Multiple X words on one line", NIST IR
        // 6556 §3.3.2: "a line may have only one word with a given letter" but G and M; Debian's
        // rs274 2.9 says so for A-F, H-L, P-T, X-Z), as the TNC does; which one another control
        // takes is not read, so those that change the motion are refused too. The first one said:
        // a block of thousands of words says one thing.
        const ONCE: u32 = letters_mask("XYZABCIJKRFPQS");
        const ONCE_LINUXCNC: u32 = !letters_mask("GM") & letters_mask("ABCDEFGHIJKLMNOPQRSTUVWXYZ");
        let once = if before.dialect == Dialect::Rs274 { ONCE_LINUXCNC } else { ONCE };
        let mut seen = 0u32;
        for w in words {
            let bit = if w.letter.is_ascii_uppercase() { 1u32 << (w.letter as u32 - 'A' as u32) } else { 0 };
            if bit & once & seen != 0 {
                diags.error(line, w.column, format!("{}{}: {} written twice in one block (which one counts is not read)", w.letter, w.raw, w.letter));
                break;
            }
            seen |= bit;
        }

        // Modal G codes and M codes first: they govern how the axis words of this block are read.
        // A code that changes the motion and is not modelled is an error (fail closed), never skipped.
        // The TNC's DIN/ISO blank form (G30 MIN point, G31 MAX point) and tool definition (G99 T L R):
        // their words define, they do not move (as Klartext's BLK FORM and TOOL DEF).
        let defines = before.dialect == Dialect::Heidenhain && words.iter().any(|w| w.letter == 'G' && matches!(w.value, 30.0 | 31.0 | 99.0));
        let reader = Reader { heid, fanuc, haas, tool_call, defines };
        // Fanuc's and Haas' G09 (Sinumerik's G9, set by its reader): this block ends in a stop.
        let mut c = BlockCodes { exact_stop_here: std::mem::take(&mut next.exact_once), ..BlockCodes::default() };
        for w in words {
            match w.letter {
                'G' => g_code(next, &before, w, words, line, reader, &mut c, diags),
                'M' => m_code(next, &before, w, shot, line, reader, &mut c, diags),
                // A tool definition's T (G99) calls no tool.
                'T' | 'S' if defines => {}
                'T' | 'S' => {
                    if w.letter == 'S' {
                        next.spindle_speed = Some(w.value);
                    }
                    c.events.push(format!("{}{}", w.letter, w.raw));
                }
                // Fanuc, Haas: D selects a cutter radius register, used only under G41/G42 (refused).
                'D' if fanuc => c.events.push(format!("D{}", w.raw)),
                'F' => feed_word = Some(w),
                'N' => {}
                c if AXIS_LETTERS.contains(&c) => {}
                '@' | '^' if before.dialect == Dialect::Rs274 => {} // polar coordinates, read below
                'I' | 'J' | 'K' | 'R' | 'P' | 'Q' | 'H' | 'L' | 'E' if !heid => {} // checked below, with the codes that take them
                'L' | 'R' if defines => {} // a tool definition's length and radius
                'I' | 'J' | 'K' | 'R' if heid => {} // circle centre and radius, read below
                'P' if heid => {} // a polar circle's turns (Klartext CP IPA beyond 360 deg): checked below
                _ => diags.error(
                    line,
                    w.column,
                    format!("unsupported word {}{}: not read (it may change the motion)", w.letter, w.raw),
                ),
            }
        }
        let BlockCodes { uses, g10, g92, exact_stop_here, g53, dwell_word, blend_word, datum_block, events, ran_unread } = c;
        // The block's own motion: a one-shot's, else the modal one.
        let block_motion = shot.map(|s| s.motion).or(next.motion);
        let arc_motion = block_motion.is_some_and(Motion::is_arc);
        // LinuxCNC: "Must use g0 or g1 with g53" (interp_check.cc check_g_codes): the block's motion,
        // which it has only where it writes axis words (polar `@` `^` are X and Y), G0 or G1.
        if g53 && before.dialect == Dialect::Rs274 {
            let axes = super::codes::lcnc_axis_words(words);
            if !axes || !matches!(block_motion, Some(Motion::Rapid | Motion::Linear)) {
                let what = if axes { "G53 with a motion other than G0 or G1" } else { "G53 without an axis word: no move" };
                diags.error(line, column, format!("{what}: LinuxCNC refuses it (\"Must use g0 or g1 with g53\")"));
            }
        }
        let vector_words = next.tool_vector && !arc_motion && !g10;
        if !heid {
            for w in words {
                let ok = match w.letter {
                    'I' | 'J' | 'K' => arc_motion || vector_words,
                    'R' => arc_motion || uses.contains(&'R'),
                    // P on an arc: LinuxCNC's count of turns; FANUC's and Haas' arcs take no P.
                    'P' => arc_motion && !fanuc || uses.contains(&'P'),
                    // Fanuc, Haas: H alone selects the tool length offset (the one in use, in G43 mode),
                    // a length this model takes from the machine file, as it takes G43's.
                    'H' if fanuc && !uses.contains(&'H') => {
                        diags.warning(line, w.column, format!("H{}: a tool length offset number; the tool length is the machine file's (tool_tip_mm), not the offset's", w.raw));
                        true
                    }
                    'Q' | 'H' | 'L' | 'E' => uses.contains(&w.letter),
                    _ => true,
                };
                if !ok {
                    // The earlier refused block is said only where this block has no defect of its
                    // own before the word (a code of its own refused is the cause then).
                    let earlier = if diags.errors() == errors_before { before.after_refused() } else { String::new() };
                    // The 840D's TURN=n is read as P n+1: named as written.
                    let word = match w.letter {
                        'R' => format!("{}{}", before.dialect.radius_address(), w.raw),
                        'P' if before.dialect == Dialect::Sinumerik => format!("TURN={}", w.value - 1.0),
                        _ => format!("{}{}", w.letter, w.raw),
                    };
                    diags.error(line, w.column, format!("word {word} without a G code that takes it: not read{earlier}"));
                }
            }
            if next.tool_vector && arc_motion {
                diags.error(line, column, "G02/G03 under G43.5 (tool vector mode) is not supported");
            }
        }
        // LinuxCNC, Fanuc and Haas start in the unit their setting says (LinuxCNC's startup code or
        // LINEAR_UNITS, Fanuc parameter No. 0000 INI, Haas Setting 9): a program that moves before
        // it says G20 or G21 is read in mm, and that is said once.
        if before.dialect.is_rs274_family() && !next.unit_stated && next.forced_unit.is_none() && !g10 && words.iter().any(|w| matches!(w.letter, 'X' | 'Y' | 'Z')) {
            (before.unit_stated, next.unit_stated) = (true, true);
            diags.warning(
                line,
                column,
                "no G20/G21 before the first move: lengths are read in millimetres, which the control's setting decides (LinuxCNC's startup code, Fanuc parameter No. 0000 INI, Haas Setting 9); --units inch if it is set to inches",
            );
        }
        if let Some(w) = words.iter().find(|w| heid && w.letter == 'P' && !arc_motion) {
            diags.error(line, w.column, format!("word P{} without a circle: not read", w.raw));
        }
        if g10 {
            // The axis words of a G10 block set an offset; they are not a move (skipped below).
            before.set_offsets(words, next, line, column, diags);
        }
        // Sinumerik's settable frames (G54-G57, G505-G599) are the operator's, never set by the
        // program: the datum is the programmable frame's, which its reader keeps. LinuxCNC's axis
        // offsets (G92, G52) apply in every system.
        // Fanuc's G54.1 Pn counts as system 0 with the offset its G10 L20 Pn set (else zero, the
        // operator's), G92's shift on top ("all work coordinate systems (G54-59, G110-129)", Haas G92).
        let extra_changed = before.extra_offset != next.extra_offset || next.extra_offset && before.extra_p != next.extra_p;
        if !heid && before.dialect != Dialect::Sinumerik && (next.system != before.system || extra_changed) {
            if next.rotation[before.system] != 0.0 || next.rotation_now() != 0.0 {
                next.current_into_system(before.system, next.system);
            } else {
                let (axis, base) = (next.axis_offset, next.work_offset());
                next.move_origin(std::array::from_fn(|k| base[k] + axis[k]));
            }
        }
        if let Some(code) = &g92 {
            // Its axis words set the offset; they are not a move (skipped below).
            before.axis_offsets(code, words, next, line, diags);
        }

        // LinuxCNC's `G64 P- <Q->`: Q (the naive-CAM tolerance: near-collinear points within it merge
        // into one move; it is P when Q is not given) is how far the path may leave the programmed
        // points, the contour tolerance on the linear axes, program unit; `G64` alone leaves the
        // machine's. (gcodes §G64; interp_convert.cc `convert_control_mode`.)
        if blend_word && before.dialect == Dialect::Rs274 {
            let merge = words.iter().find(|w| w.letter == 'Q').or_else(|| words.iter().find(|w| w.letter == 'P'));
            next.tolerance = match merge {
                None => crate::program::ProgrammedTolerance::default(),
                Some(w) => {
                    // Out of range, the block is refused (and the tolerance before it stays).
                    let v = w.value * next.unit;
                    if !crate::machine::ContourTolerance::linear_ok(v) {
                        let max = crate::machine::ContourTolerance::MAX.linear_m;
                        diags.error(line, w.column, format!("G64 {}{}: the path tolerance must be 0 to {} mm", w.letter, w.raw, max / MM));
                    }
                    crate::program::ProgrammedTolerance { linear_m: Some(v), rotary_rad: None }
                }
            };
        }

        // A dwell's time, s: P in RS274NGC (LinuxCNC: "G4 P- dwell, seconds"), F in Sinumerik ("G4 F",
        // the programmed feed stays) and Heidenhain ("G04 F: dwell time in seconds"): that F is not a
        // feed. Sinumerik's G4 S (spindle revolutions, a time that depends on the speed) is not read.
        let mut dwell_s = None;
        // FANUC's `G04 X2.5`: the X is the dwell's time, no move.
        let mut x_dwell = false;
        if let Some(g) = dwell_word {
            let letter = if before.dialect.is_rs274_family() { 'P' } else { 'F' };
            let time = if letter == 'F' { feed_word.take() } else { words.iter().find(|w| w.letter == 'P') };
            if let Some(s) = words.iter().find(|w| w.letter == 'S').filter(|_| before.dialect == Dialect::Sinumerik) {
                diags.error(line, s.column, format!("G4 S{}: a dwell in spindle revolutions is not read (expected G4 F, seconds)", s.raw));
            }
            // Fanuc and Haas: a G04 block's X is the dwell's time ("G04 X_ ;" or "G04 P_ ;", FANUC
            // B-64484EN "Dwell (G04)"), never a move; beside P, or any other axis word with G04, what
            // the control does is not read here.
            let axis = words.iter().find(|w| AXIS_LETTERS.contains(&w.letter) && (w.letter != 'X' || time.is_some()));
            if let Some(a) = axis.filter(|_| before.dialect.is_fanuc()) {
                diags.error(line, a.column, format!("G{} with {}{}: in a G04 block X is the dwell's time (FANUC \"G04 X_ ; or G04 P_ ;\"), not a move; a G04 block with axis words is not read (write the move in a block of its own)", g.raw, a.letter, a.raw));
            }
            match time {
                // Fanuc and Haas: P in milliseconds (Haas: seconds with a decimal point).
                Some(t) if before.dialect.is_fanuc() => match crate::program::fanuc::dwell(before.dialect, t) {
                    Ok(s) => dwell_s = Some(s),
                    Err(why) => diags.error(line, t.column, format!("G{} {why}", g.raw)),
                },
                Some(t) if t.value >= 0.0 && t.value.is_finite() => {
                    dwell_s = Some(t.value);
                    if before.dialect == Dialect::Rs274 && !t.raw.contains('.') && t.value >= 100.0 {
                        diags.warning(
                            line,
                            t.column,
                            format!("G4 P{}: a dwell of {} s (P is seconds in RS274NGC; a Fanuc control reads a P without a decimal point as milliseconds)", t.raw, t.value),
                        );
                    }
                }
                Some(t) => diags.error(line, t.column, format!("G{} {letter}{}: expected a dwell time of 0 s or more", g.raw, t.raw)),
                // FANUC also takes the time as X: seconds with a decimal point ("G04 X_ ;", B-64484EN
                // "Dwell"); without one, in least increments unless the machine is calculator-type
                // (whose unit for a dwell is not at hand: refused), and Haas' X is not in its manual.
                None if before.dialect.is_fanuc() => match words.iter().find(|w| w.letter == 'X') {
                    Some(x) if before.dialect == Dialect::Fanuc && x.raw.contains('.') && x.value >= 0.0 && x.value.is_finite() => {
                        dwell_s = Some(x.value);
                        x_dwell = true;
                    }
                    Some(x) if before.dialect == Dialect::Haas => diags.error(line, x.column, format!("G{} X{}: Haas' dwell is P (seconds with a decimal point, milliseconds without); X is not read", g.raw, x.raw)),
                    Some(x) if x.raw.contains('.') => diags.error(line, x.column, format!("G{} X{}: a dwell must be 0 s or more", g.raw, x.raw)),
                    Some(x) => diags.error(line, x.column, format!("G{} X{}: a dwell written with X is read on FANUC only in seconds with a decimal point (write it with a point, or P in milliseconds)", g.raw, x.raw)),
                    None => diags.error(line, g.column, format!("G{} without P: expected the dwell time (P, milliseconds on Fanuc; seconds with a decimal point on Haas)", g.raw)),
                },
                None => diags.error(line, g.column, format!("G{} without {letter}: expected the dwell time in seconds ({letter})", g.raw)),
            }
        }
        if let Some(w) = feed_word {
            if !(w.value > 0.0) {
                diags.error(line, w.column, format!("F{}: expected a positive feed", w.raw));
            } else {
                // A move of the rotary axes alone takes F in degrees per minute whatever the length
                // unit (LinuxCNC's SET_FEED_RATE: the angular feed is FROM_PROG_ANG(rate), no inch
                // conversion; a degree is no length).
                // LinuxCNC sets F (its step 4) before G20/G21 (step 16) in the order of execution,
                // and its task keeps the feed across the change (emccanon.cc SET_FEED_RATE,
                // GET_EXTERNAL_FEED_RATE): F is in the unit before the block's.
                let unit = if before.dialect == Dialect::Rs274 { before.feed_unit } else { next.feed_unit };
                next.feed = Some(match next.feed_mode {
                    FeedMode::PerMinute => (w.value * unit / MM, w.value),
                    FeedMode::InverseTime => (w.value, w.value),
                });
            }
        }

        let polar_end = match before.dialect == Dialect::Rs274 && words.iter().any(|w| matches!(w.letter, '@' | '^')) {
            true if g10 || g92.is_some() => {
                diags.error(line, column, "polar coordinates (@, ^) in a block whose axis words set an offset (G10, G52, G92) are not read");
                None
            }
            true => polar(words, next, g53, line, diags),
            false => None,
        };
        let mut targets = Targets::default();
        let mut datum = next.datum;
        for w in words {
            let Some(k) = AXIS_LETTERS.iter().position(|&c| c == w.letter) else { continue };
            if g10 || defines || g92.is_some() || x_dwell && w.letter == 'X' {
                continue;
            }
            let scale = if k < 3 { next.unit } else { next.rotary_unit[k - 3] };
            let v = w.value * scale;
            if datum_block {
                if k >= 3 {
                    diags.error(line, w.column, format!("{}{} in a datum shift (G54): a rotary axis' shift is not read", w.letter, w.raw));
                } else if !w.dimension.absolute(next.absolute) {
                    // As cycle 7's IX, it would shift from the last shift; not read in DIN/ISO.
                    diags.error(line, w.column, format!("{}{} in a datum shift (G54) under G91: an incremental shift is not read (write it absolute, from the workpiece datum)", w.letter, w.raw));
                } else {
                    datum[k] = v;
                }
                continue;
            }
            // An increment from a position no move has placed places nothing.
            let relative = !(k < 3 && (g53 || shot.is_some_and(|s| s.axes.is_some())))
                && !matches!(w.dimension, super::Dimension::Modulo(_))
                && !w.dimension.absolute(next.absolute || shot.is_some_and(|s| s.absolute));
            let abs = if let (Some(origin), true) = (shot.and_then(|s| s.axes), k < 3) {
                // Axis positions (machine coordinates): the axes there, read in program coordinates.
                v + origin[k] - next.datum[k]
            } else if g53 && k < 2 && next.rotation_now() != 0.0 {
                continue; // both together, below
            } else if g53 && k < 3 {
                v - next.datum[k]
            } else if let super::Dimension::Modulo(turn) = w.dimension {
                // DC, ACP, ACN: a position of a modulo rotary axis, 0 to 360 deg, and the way to it.
                if k < 3 || !next.modulo[k - 3] {
                    let why = if k < 3 { "a linear axis" } else { "a rotary axis with end stops in the machine file (a modulo axis has none)" };
                    diags.error(line, w.column, format!("{}={}: {} positions a modulo rotary axis, and {} is {why}", w.letter, w.raw, turn.name(), w.letter));
                    continue;
                }
                if !(0.0..360.0).contains(&(v / crate::units::DEG)) {
                    diags.error(line, w.column, format!("{}={}: a modulo axis' position is 0 to 360 deg (less than a turn)", w.letter, w.raw));
                    continue;
                }
                next.modulo_said[k - 3] = true;
                turn.place(v, next.last[k])
            } else if k >= 3 && next.modulo_said[k - 3] && w.dimension.absolute(next.absolute || shot.is_some_and(|s| s.absolute)) && !(next.shortest && next.modulo[k - 3]) && {
                let deg = |a: f64| a / crate::units::DEG;
                !(0.0..360.0).contains(&deg(next.last[k])) || !(0.0..360.0).contains(&deg(v))
            } {
                // A modulo axis (DC, ACP or ACN said so) positioned with G90: where it stands is
                // shown 0 to 360 deg, and whether G90 goes there as AC (the sign of the difference)
                // or as on an endless axis, machine datum MD30455 says; where the two differ, not read.
                diags.error(line, w.column, format!("{}{}: a plain position of an axis DC/ACP/ACN made modulo, beyond 0-360 deg or from beyond it: how G90 turns it is the machine datum MD30455's (write it with DC, ACP or ACN)", w.letter, w.raw));
                continue;
            } else if w.dimension.absolute(next.absolute || shot.is_some_and(|s| s.absolute)) {
                // M126 (it acts in its own block): a modulo axis goes the shorter way to the position.
                if k >= 3 && next.shortest && next.modulo[k - 3] {
                    crate::kinematics::unwrap_near(v, next.last[k])
                } else {
                    v
                }
            } else {
                next.last[k] + v
            };
            next.last[k] = abs;
            next.placed[k] |= !relative;
            targets.set_axis(k, abs);
        }
        if g53 && next.rotation_now() != 0.0 {
            // Machine X and Y in a rotated system (interp_find.cc find_ends, G53): the point the
            // block leaves out stays where it is, and the program frame's point is turned back.
            let given = |l: char| words.iter().find(|w| w.letter == l).map(|w| w.value * next.unit);
            let (x, y) = (given('X'), given('Y'));
            if x.is_some() || y.is_some() {
                let (g5x, g92, r) = (next.offsets[next.system], next.axis_offset, next.rotation_now());
                let here = super::rotation::rot([next.last[0] + g92[0], next.last[1] + g92[1]], r);
                let m = [x.map_or(here[0], |x| x - g5x[0]), y.map_or(here[1], |y| y - g5x[1])];
                let p = super::rotation::rot(m, -r);
                for k in 0..2 {
                    next.last[k] = p[k] - g92[k];
                    next.placed[k] = true;
                    targets.set_axis(k, next.last[k]);
                }
            }
        }
        if let Some(xy) = polar_end {
            for (k, v) in xy.into_iter().enumerate() {
                next.last[k] = v;
                next.placed[k] = true;
                targets.set_axis(k, v);
            }
        }
        // A datum shift leaves the tool where it is: its position is the new origin's from here on
        // (an incremental move after it goes from where the tool stands).
        if datum_block {
            next.move_origin(datum);
        }
        // In a tilted plane the linear words are the plane's: the point, every coordinate of it,
        // in the workpiece; the control places the axes through the kinematics, as under TCPM.
        let linear_words = targets.x.is_some() || targets.y.is_some() || targets.z.is_some();
        if let (Some(r), true) = (next.tilt, linear_words) {
            let w = r * nalgebra::Vector3::new(next.last[0], next.last[1], next.last[2]);
            (targets.x, targets.y, targets.z) = (Some(w.x), Some(w.y), Some(w.z));
            if !next.tcp && next.tilt_places_tip() && (targets.a.is_some() || targets.b.is_some() || targets.c.is_some()) {
                let tcp = match next.dialect {
                    Dialect::Sinumerik => "TRAORI",
                    d if d.is_fanuc() => "G43.4",
                    _ => "M128 / FUNCTION TCPM",
                };
                diags.error(line, column, format!("linear and rotary axis words in one block in a tilted working plane without {tcp}: position the rotary axes in a block of their own"));
            }
        }
        if vector_words && words.iter().any(|w| "IJK".contains(w.letter)) {
            targets.tool_axis = tool_vector(words, &targets, line, column, diags);
        }
        if let Some(v) = next.pending_vector.take() {
            let (words, mode) = match before.dialect {
                Dialect::Klartext => ("TX TY TZ", "M128 or FUNCTION TCPM"),
                _ => ("A3 B3 C3", "TRAORI"),
            };
            if !next.tcp {
                diags.error(line, column, format!("tool vector ({words}) without {mode}: the orientation transformation is off"));
            } else if targets.a.is_some() || targets.b.is_some() || targets.c.is_some() {
                diags.error(line, column, format!("block with both a tool vector ({words}) and rotary-axis words: expected one of them"));
            } else {
                targets.tool_axis = Some(v);
            }
        }

        // LinuxCNC: "No axis words and one or more offsets must be programmed for full circles" (both,
        // under G90.1; G-code reference §G2/G3): the arc ends where it starts. Fanuc and Haas the same:
        // "When X_, Y_, and Z_ are all omitted (the end point is the same as the start point) and the
        // center is specified with I_, J_, and K_, a 360° arc (circle) is specified" (FANUC B-64484EN,
        // "Circular interpolation"; Haas Mill Operator's Manual, G02/G03: a full circle takes I J K,
        // not R). Sinumerik: "If the circle is programmed with a center point but no end point, the
        // result is a full circle" (840D Programming Manual Fundamentals 10.2004 §4.6).
        if (matches!(before.dialect, Dialect::Rs274 | Dialect::Sinumerik) || fanuc) && arc_motion && targets.is_empty() && !g10 && !words.iter().any(|w| w.letter == 'R') {
            let (a0, a1, _) = next.plane.axes();
            let offset = |k: usize| words.iter().any(|w| w.letter == ['I', 'J', 'K'][k]);
            if if next.arc_absolute { offset(a0) && offset(a1) } else { offset(a0) || offset(a1) } {
                for k in [a0, a1] {
                    targets.set_axis(k, next.last[k]);
                }
            }
        }
        let moves = !targets.is_empty();
        // Haas: "Cancel G254 with G255 immediately after use and before ANY rotary motion" (G254, rule 5).
        if next.dwo && (targets.a.is_some() || targets.b.is_some() || targets.c.is_some()) {
            diags.error(line, column, "a rotary axis moves under G254 (dynamic work offset): Haas forbids it until G255");
        }
        // "G254 (DWO) is intended for 3+1 and 3+2 machining ... Cancel G254 with G255 any time
        // simultaneous 4- or 5-axis machining is performed" (Haas UMC-750 manual, G254 rule 6): both
        // in force after the block's codes (the block that makes it so, and every move under them).
        if next.dwo && next.tcp && before.dialect == Dialect::Haas && (moves || !(before.dwo && before.tcp)) {
            diags.error(line, column, "G234 (TCPC) and G254 (dynamic work offset) together: Haas wants G255 before simultaneous machining (G254 is for 3+2), so this is not read");
        }
        // Haas: a feed move of a rotary axis without TCPC takes F in inches (mm) per minute at the part
        // diameter Setting 34 (4th axis) or 79 (5th) gives ("the control must know the diameter of
        // the part being machined ... to compute angular feedrate"), a setting of the job, not read;
        // how a move with linear axes too shares F is not stated, and the manual asks for G93 there:
        // "G93 inverse time feed mode must be in effect for simultaneous 4- or 5-axis motion; however,
        // if your mill supports Tool Center Point Control (G234), you may use G94" (Haas Mill NGC
        // Operator's Manual, 2017, Five-Axis Programming Notes; Settings 34 and 79).
        // Said at the first such move of a stretch, not refused: the moves after it (an operation of
        // hundreds) stand as written, their mode and positions kept, and the program is refused once.
        let feed_move = block_motion.is_some_and(|m| m != Motion::Rapid);
        let haas_rotary_feed = (haas && !next.tcp && next.feed_mode == FeedMode::PerMinute && feed_move && (3..6).any(|k| (next.last[k] - before.last[k]).abs() > 1e-12))
            .then(|| (0..3).any(|k| (next.last[k] - before.last[k]).abs() > 1e-12));
        // "After G254 is invoked, you must specify an X, Y, and Z position prior to any cutting
        // command" (Haas UMC-750 operator's manual, G254): a feed move before all three are written.
        for (k, t) in [targets.x, targets.y, targets.z].into_iter().enumerate() {
            if t.is_some() {
                next.dwo_unplaced[k] = false;
            }
        }
        if next.dwo && block_motion.is_some_and(|m| m != Motion::Rapid) && moves && next.dwo_unplaced.iter().any(|u| *u) {
            let missing: String = "XYZ".chars().zip(next.dwo_unplaced).filter(|(_, u)| *u).map(|(c, _)| c).collect();
            diags.error(line, column, format!("a cutting move under G254 before {missing} is written: Haas wants X, Y and Z given after G254, before any cutting command"));
        }
        // Sinumerik: "G4 must be programmed in a separate NC block" (Fundamentals, G4): a dwell with a
        // move is an alarm on the control, not a dwell and then a move as LinuxCNC reads it.
        if let (Some(g), true, Dialect::Sinumerik) = (dwell_word, moves, before.dialect) {
            diags.error(line, g.column, "G4 with axis words: Sinumerik runs a dwell only in a block of its own (G4 F, seconds)");
        }
        if moves && block_motion.is_none() {
            // Fanuc's and Haas' power-on motion mode is a setting of the machine (FANUC parameter
            // 3402 bit 0: G00 or G01), not the program's: not assumed.
            let start = match before.dialect {
                _ if before.refused_line.is_some() => "",
                Dialect::Fanuc => " (the control's power-on mode, G00 or G01 by its parameter 3402 bit 0, is the machine's setting: its machine file's power_on_motion)",
                Dialect::Haas => " (the control's power-on mode is the machine's setting: its machine file's power_on_motion)",
                _ => "",
            };
            diags.error(line, column, format!("axis words without a motion mode: expected G00 or G01 first{start}{}", before.after_refused()));
        }
        let mut arc = None;
        // A FANUC arc under G93, timed by its angle ([`fanuc_arc_frn`]).
        let mut fanuc_frn_arc = false;
        if heid {
            // I J K: the circle centre (the pole), absolute or, under G91, from the last position;
            // modal, and the tool does not move to it (iTNC 530 ISO programming, "Circle center I, J").
            for w in words.iter().filter(|w| "IJK".contains(w.letter)) {
                let k = "IJK".find(w.letter).unwrap_or(0);
                let v = w.value * next.unit;
                next.centre[k] = Some(if next.absolute { v } else { before.last[k] + v });
            }
            if let Some(w) = words.iter().find(|w| w.letter == 'R').filter(|_| !arc_motion && !defines) {
                diags.error(line, w.column, format!("R{}: a radius without G02/G03", w.raw));
            }
            if arc_motion && moves {
                let start = [before.last[0], before.last[1], before.last[2]];
                let end = [next.last[0], next.last[1], next.last[2]];
                let (a0, a1, _) = next.plane.axes();
                // The arc as an RS274 arc with an absolute centre: the modal I J K, or the block's R.
                let mut as_rs274: Vec<Word> = words.iter().filter(|w| w.letter == 'R').cloned().collect();
                if as_rs274.is_empty() {
                    for k in [a0, a1] {
                        if let Some(c) = next.centre[k] {
                            as_rs274.push(Word { letter: ['I', 'J', 'K'][k], value: c / next.unit, raw: format!("{}", c / next.unit).into(), column, dimension: Dimension::Modal });
                        }
                    }
                    // Said once, in the dialect's words (Klartext's centre is its CC pole).
                    if as_rs274.len() < 2 {
                        let (i, j) = (['I', 'J', 'K'][a0], ['I', 'J', 'K'][a1]);
                        let want = if before.dialect == Dialect::Klartext { "a circle centre CC before this block".to_string() } else { format!("{i} and {j} before or in this block, or R") };
                        diags.error(line, column, format!("arc without a circle centre: expected {want}"));
                    }
                }
                let mut st = next.clone();
                st.arc_absolute = true;
                if as_rs274.len() == 2 || as_rs274.iter().any(|w| w.letter == 'R') {
                    // A polar circle's turns (P), as RS274's.
                    as_rs274.extend(words.iter().filter(|w| w.letter == 'P').cloned());
                    arc = resolve_arc(&as_rs274, &st, start, end, line, column, diags.errors() > errors_before, diags);
                }
            }
            if arc_motion {
                next.last_arc = next.motion;
            }
        }
        if arc_motion && !heid && !g10 {
            if moves {
                let start = [before.last[0], before.last[1], before.last[2]];
                let end = [next.last[0], next.last[1], next.last[2]];
                arc = resolve_arc(words, next, start, end, line, column, diags.errors() > errors_before, diags);
                // FANUC times an arc by its own rules. On a helix, or with a rotary axis, F is along the
                // arc or along the whole path as parameter HTG says (B-63783EN §6.7), not read here.
                // Under G93 F is the feed over the arc's radius ("FRN = feedrate / arc radius",
                // B-62764EN §5 "Inverse time feed": "the feedrate is calculated not from the actual amount
                // of movement in the block but from the arc radius"), so the arc of angle th takes th / FRN
                // minutes: read once the block is made ([`fanuc_arc_frn`]).
                if before.dialect == Dialect::Fanuc && arc.is_some() {
                    let (_, _, an) = next.plane.axes();
                    let normal = (end[an] - start[an]).abs() > 1e-12;
                    let rotary = (3..6).any(|k| (next.last[k] - before.last[k]).abs() > 1e-12);
                    if normal || rotary {
                        let why = "a helix (or an arc with a rotary axis): FANUC feeds along the arc or along the whole path as parameter HTG says, which is not read";
                        diags.error(line, column, format!("{}: {why}", if block_motion == Some(Motion::ArcCw) { "G02" } else { "G03" }));
                    }
                    fanuc_frn_arc = next.feed_mode == FeedMode::InverseTime;
                }
            } else if words.iter().any(|w| "IJKR".contains(w.letter) || (w.letter == 'P' && !uses.contains(&'P'))) {
                // (A P that another code of the block takes, G4's or G64's, is not the arc's.)
                diags.error(line, column, "arc words without an end point: expected X, Y or Z with them");
            }
        }
        // An arc in a tilted plane (a TNC's PLANE, a Sinumerik frame or CYCLE800, Fanuc's G68.2): its
        // centre in the workpiece, as its end point is, its axes the plane's.
        if let (Some(r), Some(a)) = (next.tilt, arc.as_mut()) {
            let c = r * nalgebra::Vector3::from(a.centre);
            a.centre = [c.x, c.y, c.z];
            a.frame = Some(ArcSpec::frame_of(&r));
        }
        if moves && block_motion.is_some_and(|m| m == Motion::Linear || m.is_arc()) {
            match next.feed_mode {
                FeedMode::PerMinute if next.feed.is_none() => {
                    let why = if before.feed.is_some() { " (the change of feed mode left none)" } else { "" };
                    let g = match block_motion {
                        Some(Motion::ArcCw) => "G02",
                        Some(Motion::ArcCcw) => "G03",
                        _ => "G01",
                    };
                    // A refused block before may have carried the F word (not said where this block's
                    // own change of feed mode left none).
                    let refused = if why.is_empty() { before.after_refused_feed() } else { String::new() };
                    diags.error(line, column, format!("{g} move without a feed: expected an F word before or in this block{why}{refused}"))
                }
                FeedMode::InverseTime if feed_word.is_none() => {
                    diags.error(line, column, "G93 inverse-time move without F in the block: expected F (1/min)")
                }
                // LinuxCNC refuses a G95 feed move at S0 ("Cannot feed with zero spindle speed in feed
                // per rev mode", Interp::convert_straight, convert_arc); with the spindle stopped its
                // axes wait on the spindle's turns, as any control's do: a time not modelled.
                FeedMode::PerMinute if next.per_revolution && next.feed.is_some() => {
                    if !next.spindle_speed.is_some_and(|s| s > 0.0) {
                        diags.error(line, column, "G95 feed move without a spindle speed: Cannot feed with zero spindle speed in feed per rev mode (expected S before or in this block)");
                    } else if next.spindle_turning != Some(true) {
                        let why = if next.spindle_turning.is_none() { "no M3 or M4 has started it in this program" } else { "M5 stopped it (or M19, or on LinuxCNC a tool change M6)" };
                        diags.error(line, column, format!("G95 feed move with the spindle not turning ({why}): the axes would wait on its turns, which is not modelled"));
                    }
                }
                _ => {}
            }
        }
        // M116: "The TNC interprets the programmed feed rate in a rotary axis in mm/min", computed at
        // the block's start from the tool's distance to the rotary axis' centre, on rotary tables;
        // "in combination with M128 [only] if you used the M138 function" (iTNC 530 user's manual
        // 60642x-03 §12.5): under TCPM the feed is the tool tip's as always. Without TCPM, a feed move of
        // a rotary axis would run at a speed this model does not compute.
        if heid && next.m116 && !next.tcp && moves && block_motion.is_some_and(|m| m != Motion::Rapid) && (3..6).any(|k| next.last[k] != before.last[k]) {
            diags.error(line, column, "a rotary axis moving at a feed with M116 in force and neither M128 nor FUNCTION TCPM: the TNC reads its F in mm/min at the tool's distance from the rotary axis, which is not modelled (M117 resets M116)");
        }
        // FANUC under G43.4: a feed move of the rotary axes alone leaves the tool tip standing on the
        // workpiece, and the control feeds them at F or at the maximum cutting feedrate (parameter
        // No. 1422) as parameter No. 19696 bit 6 RFC says (A-79348E): the machine file's tcp_rotary_feed.
        if before.dialect == Dialect::Fanuc
            && next.tcp
            && !next.kins_tcp
            && moves
            && block_motion.unwrap_or(next.motion.unwrap_or(Motion::Rapid)) == Motion::Linear
            && next.feed_mode == FeedMode::PerMinute
            && (0..3).all(|k| (next.last[k] - before.last[k]).abs() <= 1e-12)
            && ((3..6).any(|k| (next.last[k] - before.last[k]).abs() > 1e-12)
                || targets.tool_axis.is_some_and(|v| {
                    let unit = |v: [f64; 3]| nalgebra::Vector3::from(v).normalize();
                    next.last_vector.is_none_or(|p| (unit(p) - unit(v)).norm() > 1e-12)
                }))
        {
            let rfc = next.machine.as_ref().and_then(|m| m.tcp_rotary_feed);
            if rfc != Some(crate::machine::TcpRotaryFeed::Programmed) {
                let why = match rfc {
                    Some(_) => "at the maximum cutting feedrate (parameter No. 1422, the machine file's tcp_rotary_feed = \"max-cutting\"), which is not modelled",
                    None => "at F or at the maximum cutting feedrate (parameter No. 1422) as parameter No. 19696 bit 6 RFC says, which the machine file does not give (tcp_rotary_feed = \"programmed\" or \"max-cutting\")",
                };
                diags.error(line, column, format!("a feed move of the rotary axes alone under G43.4/G43.5 (the tool tip stands on the workpiece): FANUC feeds them {why}"));
            }
        }
        let errors_after = diags.errors();
        if errors_after == errors_before && haas {
            match haas_rotary_feed {
                Some(simultaneous) if self.haas_rotary_feed_said.is_none() => {
                    let rule = if simultaneous { "Haas asks for G93 inverse time for simultaneous 4- or 5-axis motion, or G234 (TCPC) for G94 (Mill NGC Operator's Manual, Five-Axis Programming Notes); " } else { "" };
                    diags.error(line, column, format!("a feed move of a rotary axis in G94 without G234: {rule}Haas feeds the rotary axis at the part diameter of Setting 34 or 79, which is not read (G93 inverse time, or G234, is read); said once for the feed moves of rotary axes after it until G93, G234, a rapid or a feed move of the linear axes alone, which are timed as a G94 move is here (F along the linear axes' path, or in deg/min for rotary axes alone)"));
                    self.haas_rotary_feed_said = Some(line);
                }
                Some(_) => {}
                // Any other move ends the stretch: a feed move of the linear axes alone, or a rapid
                // (a retract or a positioning between operations).
                None if moves => self.haas_rotary_feed_said = None,
                None => {}
            }
        }
        if errors_after > errors_before {
            *self = before;
            // The tool vector belonged to this block: it does not carry over to the next one.
            self.pending_vector = None;
            self.ran_unread = ran_unread.map(|m| (line, m));
            return None;
        }
        // In a tilted plane without TCPM a move of the rotary axes alone leaves the linear axes where
        // they stand, so the tool tip moves in the plane: read it anew.
        let rotary_only = !linear_words && (targets.a.is_some() || targets.b.is_some() || targets.c.is_some());
        let axes_before = (!before.tcp && before.tilt_places_tip() && rotary_only).then(|| before.axes_now());
        if let Some(axes) = axes_before {
            self.read_axes(axes);
        }
        let mut b = Block {
            line,
            column,
            number,
            motion: block_motion.unwrap_or(Motion::Linear),
            targets,
            arc: arc.map(Box::new),
            feed: self.feed_now(),
            tcp: (self.tcp || self.tilt_places_tip() && (targets.x.is_some() || targets.y.is_some() || targets.z.is_some())) && !shot.is_some_and(|s| s.axes.is_some()),
            datum: self.datum,
            orientation: self.orientation,
            events,
            dwell_s,
            tolerance: self.tolerance,
            // A move of the machine's axes (machine coordinates) is where it is, whatever the datum.
            offset_assumed: self.offset_assumed() && !shot.is_some_and(|s| s.axes.is_some() && !s.own),
            exact: if exact_stop_here { Exact::Stop } else { self.exact },
        };
        if fanuc_frn_arc {
            fanuc_arc_frn(&mut b, [before.last[0], before.last[1], before.last[2]], [self.last[0], self.last[1], self.last[2]]);
        }
        if let Some(v) = b.targets.tool_axis {
            self.last_vector = Some(v);
        }
        self.fill_xy(&mut b);
        // Fanuc's and Haas' G68: the block placed about the centre, Fanuc's tool position at G68 for
        // incremental moves until an absolute one (machine coordinates are not turned).
        let last = self.last;
        let absolute = self.absolute;
        if let Some(r) = self.rotation2d.as_mut().filter(|_| shot.is_none_or(|s| s.axes.is_none())) {
            let modal = absolute || shot.is_some_and(|s| s.absolute);
            let letters = r.letters();
            if words.iter().any(|w| letters.contains(&w.letter) && w.dimension.absolute(modal)) {
                r.until_absolute = None;
            }
            r.place(&mut b, &last);
        }
        Some(b)
    }
}

/// A FANUC arc under G93 (its plane's, no helix): F is FRN = feedrate / arc radius (B-62764EN §5
/// "Inverse time feed"), so the arc of angle th from `start` takes th / FRN minutes; the block's
/// inverse time becomes FRN / th, the form every inverse-time block has.
fn fanuc_arc_frn(b: &mut Block, start: [f64; 3], end: [f64; 3]) {
    let (Some(arc), Some(feed)) = (b.arc.as_deref(), b.feed.as_mut()) else { return };
    let sweep = crate::path::ArcPath::new(arc, b.motion == Motion::ArcCcw, nalgebra::Vector3::from(start), nalgebra::Vector3::from(end)).sweep.abs();
    if sweep > 0.0 {
        feed.value_per_min /= sweep;
    }
}

/// The bits of these capital letters (A is bit 0), for a block's letters checked at a glance.
const fn letters_mask(letters: &str) -> u32 {
    let b = letters.as_bytes();
    let (mut mask, mut k) = (0u32, 0);
    while k < b.len() {
        mask |= 1 << (b[k] - b'A');
        k += 1;
    }
    mask
}

/// LinuxCNC's polar coordinates (G-code reference, "Polar Coordinates"; interp_find.cc find_ends):
/// `@` the distance from the program origin and `^` the angle from +X (deg) of the end point in the
/// XY plane. Under G90 a word left out keeps the current point's; under G91 `@` adds to the distance
/// and `^` to the angle, about the origin. The end point (program coordinates, m), or None with the
/// error LinuxCNC gives.
fn polar(words: &[Word], next: &Interpreter, g53: bool, line: usize, diags: &mut Diags) -> Option<[f64; 2]> {
    let find = |c: char| words.iter().filter(|w| w.letter == c).collect::<Vec<_>>();
    let (radius, theta) = (find('@'), find('^'));
    let column = radius.iter().chain(&theta).map(|w| w.column).min().unwrap_or(1);
    let refuse = |diags: &mut Diags, why: &str| {
        diags.error(line, column, format!("polar coordinates: {why} (LinuxCNC refuses it so)"));
        None
    };
    if radius.len() > 1 || theta.len() > 1 {
        return refuse(diags, "@ or ^ written twice in one block");
    }
    if next.plane != Plane::Xy {
        return refuse(diags, "\"Cannot use polar coordinate except in G17 plane\"");
    }
    if words.iter().any(|w| matches!(w.letter, 'X' | 'Y')) {
        return refuse(diags, "\"Cannot specify both polar coordinate and X word\" (or Y)");
    }
    if g53 {
        return refuse(diags, "\"Cannot use polar coordinates with G53\"");
    }
    let (r, t) = (radius.first().map(|w| w.value * next.unit), theta.first().map(|w| w.value.to_radians()));
    let (x, y) = (next.last[0], next.last[1]);
    let at_origin = x == 0.0 && y == 0.0;
    let end = |r: f64, t: f64| [r * t.cos(), r * t.sin()];
    if next.absolute {
        match (r, t) {
            (Some(r), Some(t)) => Some(end(r, t)),
            (Some(_), None) if at_origin => refuse(diags, "\"Must specify angle in polar coordinate if at the origin\""),
            (Some(r), None) => Some(end(r, y.atan2(x))),
            (None, Some(t)) => Some(end(x.hypot(y), t)),
            (None, None) => None,
        }
    } else {
        // The distance first, then the angle, each about the origin (find_ends, MODE_INCREMENTAL).
        let mut p = [x, y];
        if let Some(r) = r {
            let Some(q) = polar_step(p, r, 0.0) else {
                return refuse(diags, "\"Incremental motion with polar coordinates is indeterminate when at the origin\"");
            };
            p = q;
        }
        if let Some(t) = t {
            let Some(q) = polar_step(p, 0.0, t) else {
                return refuse(diags, "\"G91 motion with polar coordinates is indeterminate when at the origin\"");
            };
            p = q;
        }
        Some(p)
    }
}

/// LinuxCNC's incremental polar step (interp_find.cc find_ends under G91, interp_cycles.cc
/// CYCLE_MACRO): the point `p` (m) `dr` further from the program origin and turned `dt` (rad) about
/// it; `None` at the origin, where its direction is not defined.
pub(crate) fn polar_step(p: [f64; 2], dr: f64, dt: f64) -> Option<[f64; 2]> {
    if p == [0.0, 0.0] {
        return None;
    }
    let (r, t) = (p[0].hypot(p[1]) + dr, p[1].atan2(p[0]) + dt);
    Some([r * t.cos(), r * t.sin()])
}
