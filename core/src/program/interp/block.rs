//! One block's words interpreted: modal G codes, M functions, feed, targets and arcs, into a
//! [`Block`] (the [`Interpreter`]'s state changes only when the block has no defect).

use super::arc::resolve_arc;
use super::codes::{maker_m_function, tnc_m_code, tool_vector};
use crate::program::cutter_comp::ArcFeed;
use super::{Dimension, Interpreter, Word, AXIS_LETTERS};
use crate::program::lex::Diags;
use crate::program::{ArcSpec, Block, Dialect, Exact, FeedMode, MCodeAction, Motion, Plane, Targets};
use crate::units::{INCH, MM};

impl Interpreter {
    /// Interpret one block's words into one block (see [`Interpreter::block`]).
    pub(crate) fn block_one(&mut self, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags) -> Option<Block> {
        let shot = self.oneshot.take();
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
        let mut datum_block = false;
        let mut events = Vec::new();
        let mut feed_word: Option<&Word> = None;
        // Heidenhain DIN/ISO and conversational share the TNC's words: modal circle centre I J K,
        // M128/M129, and the TNC's M functions.
        let heid = matches!(before.dialect, Dialect::Heidenhain | Dialect::Klartext);
        // Fanuc-style controls (Fanuc, Haas) and Haas alone.
        let (fanuc, haas) = (before.dialect.is_fanuc(), before.dialect == Dialect::Haas);
        // The TNC's DIN/ISO tool call `T1 G17`: the block's plane code is the tool axis.
        let tool_call = before.dialect == Dialect::Heidenhain && words.iter().any(|w| w.letter == 'T');
        // An axis, centre, radius or feed written twice: LinuxCNC refuses it ("Multiple X words on one
        // line", NIST IR 6556 §3.3.2: "a line may have only one word with a given letter" but G and
        // M), as the TNC does; which one another control takes is not read, so refused too.
        // The first one said: a block of thousands of words says one thing.
        const ONCE: u32 = letters_mask("XYZABCIJKRF");
        let mut seen = 0u32;
        for w in words {
            let bit = if w.letter.is_ascii_uppercase() { 1u32 << (w.letter as u32 - 'A' as u32) } else { 0 };
            if bit & ONCE & seen != 0 {
                diags.error(line, w.column, format!("{}{}: {} written twice in one block (which one counts is not read)", w.letter, w.raw, w.letter));
                break;
            }
            seen |= bit;
        }

        // Modal G codes and M codes first: they govern how the axis words of this block are read.
        // A code that changes the motion and is not modelled is an error (fail closed), never skipped.
        let mut uses: Vec<char> = Vec::new(); // letters besides axes that a code of this block takes
        let mut g10 = false;
        // LinuxCNC's G92, G92.1-G92.3 and G52: the code, applied once the block's modal codes are.
        let mut g92: Option<String> = None;
        // Fanuc's and Haas' G09 (Sinumerik's G9, set by its reader): this block ends in a stop.
        let mut exact_stop_here = std::mem::take(&mut next.exact_once);
        // The TNC's DIN/ISO blank form (G30 MIN point, G31 MAX point) and tool definition (G99 T L R):
        // their words define, they do not move (as Klartext's BLK FORM and TOOL DEF).
        let defines = before.dialect == Dialect::Heidenhain && words.iter().any(|w| w.letter == 'G' && matches!(w.value, 30.0 | 31.0 | 99.0));
        let mut g53 = false;
        let mut dwell_word: Option<&Word> = None;
        let mut blend_word = false;
        for w in words {
            match w.letter {
                'G' => {
                    let code = w.raw.trim_start_matches('+');
                    let code = code.trim_start_matches('0');
                    // Borrowed as written but for a code of zeros (`G0`, `G00`, `G0.1`): no allocation per G word.
                    let code: std::borrow::Cow<str> = if code.is_empty() || code.starts_with('.') { format!("0{code}").into() } else { code.into() };
                    let unsupported = |diags: &mut Diags, what: &str| {
                        diags.error(line, w.column, format!("G{} ({what}) is not supported: it changes the motion", w.raw))
                    };
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
                        ("54", true) => datum_block = true,
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
                            g53 = true;
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
                        // Additional work offsets (Fanuc G54.1 P1-P48), which the program never sets here.
                        ("54.1", false) if fanuc => {
                            uses.push('P');
                            diags.warning(line, w.column, format!("G{}: additional work offsets are not set by the program: taken as zero", w.raw));
                            next.system = 0;
                            next.extra_offset = true;
                            next.move_origin([0.0; 3]);
                        }
                        // AI contour control (Q1 on, Q0 off): look-ahead feed control, not the path's
                        // geometry (FANUC A-63512EN §2.3: "interpolation data ensures that the machining
                        // follows a specified line or curve").
                        ("5.1", false) if fanuc => uses.push('Q'),
                        // High-precision contour control, `G05 P10000` on and `G05 P0` off (FANUC Series
                        // 16i/18i-MB, "High-precision contour control"): look-ahead feed control as AI
                        // contour is. G05 with another P is high-speed cycle machining (binary data).
                        ("5", false) if fanuc && !haas && words.iter().any(|p| p.letter == 'P' && (p.value == 0.0 || p.value == 10000.0)) => uses.push('P'),
                        ("5", false) if fanuc && !haas => unsupported(diags, "high-speed cycle machining (only G05 P10000 and G05 P0, high-precision contour control on and off, are read)"),
                        // Haas' smoothness: P the level (feed), E the most a corner may be rounded,
                        // which is the path's tolerance (Haas NGC manual, G187; Setting 85).
                        ("187", false) if haas => {
                            uses.extend(['P', 'E']);
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
                            uses.push('H');
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
                        }
                        ("255", false) if haas => next.dwo = false,
                        ("10", false) if fanuc && words.iter().any(|w| w.letter == 'L' && w.value == 20.0) => {
                            diags.error(line, w.column, "G10 L20: Fanuc's additional work offsets (G54.1 Pn) are not modelled");
                        }
                        ("10", false) => {
                            g10 = true;
                            uses.extend(['L', 'P']);
                            if before.dialect == Dialect::Rs274 {
                                uses.push('R'); // G10 L2 R: the system's rotation
                            }
                        }
                        // (Two codes of group 0 in one block: Interpreter::block refuses them.)
                        ("92" | "92.1" | "92.2" | "92.3" | "52", false) if before.dialect == Dialect::Rs274 => g92 = Some(code.to_string()),
                        ("92.1" | "92.2", false) => {} // cancel G92 offsets: none are modelled
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
                            uses.push('H');
                        }
                        ("43.5", false) => {
                            (next.tcp, next.tool_vector) = (true, true);
                            uses.push('H');
                        }
                        // The TCP G43.4/G43.5 turned on; the kinematics' own stays.
                        ("49", false) => (next.tcp, next.tool_vector) = (next.kins_tcp, false),
                        ("43", false) => {
                            uses.push('H');
                            diags.warning(
                                line,
                                w.column,
                                "G43 tool length offset: the tool length is the machine file's (tool_tip_mm), not the tool table's; \
                                 on a table-table machine it only shifts Z by a constant",
                            )
                        }
                        // Blending within a tolerance: what the planner does (P and Q: below).
                        ("64", false) => {
                            uses.extend(['P', 'Q']);
                            blend_word = true;
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
                        ("9", false) if fanuc => exact_stop_here = true,
                        ("4", _) => {
                            uses.push('P');
                            dwell_word = Some(w);
                        }
                        ("61" | "61.1", false) => unsupported(diags, "exact stop mode: the planner blends blocks as G64 does"),
                        ("41" | "42" | "41.1" | "42.1", false) => unsupported(diags, "cutter radius compensation"),
                        ("43.1" | "43.2", false) => unsupported(diags, "dynamic tool length offset"),
                        ("68" | "68.2" | "68.3" | "68.4" | "69" | "53.1" | "53.6", false) => unsupported(diags, "coordinate rotation or tilted working plane"),
                        ("5" | "5.1" | "5.2" | "5.3" | "6.2", false) => unsupported(diags, "spline or NURBS motion"),
                        ("28" | "28.1" | "30" | "30.1", false) => unsupported(diags, "move to a stored position"),
                        ("33" | "33.1" | "76" | "38.2" | "38.3" | "38.4" | "38.5", false) => unsupported(diags, "threading or probing"),
                        ("73" | "74" | "81" | "82" | "83" | "84" | "85" | "86" | "87" | "88" | "89", false) => unsupported(diags, "canned cycle"),
                        ("92" | "92.3", false) => unsupported(diags, "coordinate system offset"),
                        ("7" | "8" | "50" | "51" | "52", false) => unsupported(diags, "diameter mode, scaling or local offset"),
                        _ => diags.error(
                            line,
                            w.column,
                            format!("unknown G code G{}: not read (it may change the motion)", w.raw),
                        ),
                    }
                }
                'M' => {
                    let code = w.value as i64;
                    if w.value.fract() != 0.0 || w.value < 0.0 {
                        diags.error(line, w.column, format!("M{}: expected a whole M code number", w.raw));
                        continue;
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
                        (None, 3 | 4, _) | (None, 13 | 14, true) => next.spindle_turning = Some(true),
                        (None, 5, _) => next.spindle_turning = Some(false),
                        (None, 19, false) => {
                            next.spindle_turning = Some(false);
                            if before.dialect == Dialect::Rs274 {
                                uses.extend(['R', 'Q', 'P']);
                            }
                        }
                        (None, 0..=9 | 13 | 14 | 30, _) => {}
                        // M91/M92: the Klartext reader made this block a move of the axes (its oneshot).
                        (None, 91 | 92, true) if shot.is_some_and(|s| s.axes.is_some()) => {}
                        (None, _, true) => {
                            if let Err(why) = tnc_m_code(code) {
                                diags.error(line, w.column, format!("M{}: {why}", w.raw));
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
                        (None, 99, false) if before.dialect == Dialect::Rs274 => {}
                        (None, 98, false) if before.dialect == Dialect::Rs274 => diags.error(line, w.column, "M98 calls a Fanuc-style subprogram only as the first word of its line (after its N number): LinuxCNC reads it there, as a block of its own"),
                        (None, 48..=53 | 60, false) => {}
                        (None, 61, false) => uses.push('Q'),
                        (None, 62..=65, false) => uses.push('P'),
                        (None, 66, false) => uses.extend(['P', 'E', 'L', 'Q']),
                        (None, 67 | 68, false) => uses.extend(['E', 'Q']),
                        (None, _, false) if fanuc => diags.error(line, w.column, maker_m_function(&w.raw, code)),
                        (None, _, false) => diags.error(
                            line,
                            w.column,
                            format!(
                                "M{} is not an RS274NGC M code: a machine-specific one (LinuxCNC user M100-M199 or a remap) \
                                 whose effect is unknown; say what it does with --m-code {}=tcp-on|tcp-off|event \
                                 (LinuxCNC's vismach five-axis demos: 428=tcp-on, 429=tcp-off)",
                                w.raw, code
                            ),
                        ),
                    }
                    events.push(format!("M{}", w.raw));
                }
                // A tool definition's T (G99) calls no tool.
                'T' | 'S' if defines => {}
                'T' | 'S' => {
                    if w.letter == 'S' {
                        next.spindle_speed = Some(w.value);
                    }
                    events.push(format!("{}{}", w.letter, w.raw));
                }
                // Fanuc, Haas: D selects a cutter radius register, used only under G41/G42 (refused).
                'D' if fanuc => events.push(format!("D{}", w.raw)),
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
        // The block's own motion: a one-shot's, else the modal one.
        let block_motion = shot.map(|s| s.motion).or(next.motion);
        let arc_motion = block_motion.is_some_and(Motion::is_arc);
        let vector_words = next.tool_vector && !arc_motion && !g10;
        if !heid {
            for w in words {
                let ok = match w.letter {
                    'I' | 'J' | 'K' => arc_motion || vector_words,
                    'R' => arc_motion || uses.contains(&'R'),
                    'P' => arc_motion || uses.contains(&'P'),
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
                    diags.error(line, w.column, format!("word {}{} without a G code that takes it: not read{earlier}", w.letter, w.raw));
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
        if !heid && before.dialect != Dialect::Sinumerik && next.system != before.system {
            if next.rotation[before.system] != 0.0 || next.rotation_now() != 0.0 {
                next.current_into_system(before.system, next.system);
            } else {
                let axis = next.axis_offset;
                next.move_origin(std::array::from_fn(|k| next.offsets[next.system][k] + axis[k]));
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
        if let Some(g) = dwell_word {
            let letter = if before.dialect.is_rs274_family() { 'P' } else { 'F' };
            let time = if letter == 'F' { feed_word.take() } else { words.iter().find(|w| w.letter == 'P') };
            if let Some(s) = words.iter().find(|w| w.letter == 'S').filter(|_| before.dialect == Dialect::Sinumerik) {
                diags.error(line, s.column, format!("G4 S{}: a dwell in spindle revolutions is not read (expected G4 F, seconds)", s.raw));
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
                // Fanuc and Haas also take the time as X (seconds); that form is not read here.
                None if before.dialect.is_fanuc() => match words.iter().find(|w| w.letter == 'X') {
                    Some(x) => diags.error(line, x.column, format!("G{} X{}: a dwell written with X is not read (write P, in milliseconds on Fanuc)", g.raw, x.raw)),
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
            if g10 || defines || g92.is_some() {
                continue;
            }
            let scale = if k < 3 { next.unit } else { next.rotary_unit[k - 3] };
            let v = w.value * scale;
            if datum_block {
                if k < 3 {
                    datum[k] = v;
                } else {
                    diags.warning(line, w.column, format!("{}{} in a datum shift (G54) is not modelled", w.letter, w.raw));
                }
                continue;
            }
            let abs = if let (Some(origin), true) = (shot.and_then(|s| s.axes), k < 3) {
                // Axis positions (machine coordinates): the axes there, read in program coordinates.
                v + origin[k] - next.datum[k]
            } else if g53 && k < 2 && next.rotation_now() != 0.0 {
                continue; // both together, below
            } else if g53 && k < 3 {
                v - next.datum[k]
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
                    targets.set_axis(k, next.last[k]);
                }
            }
        }
        if let Some(xy) = polar_end {
            for (k, v) in xy.into_iter().enumerate() {
                next.last[k] = v;
                targets.set_axis(k, v);
            }
        }
        next.datum = datum;
        // In a tilted plane the linear words are the plane's: the point, every coordinate of it,
        // in the workpiece; the control places the axes through the kinematics, as under TCPM.
        let linear_words = targets.x.is_some() || targets.y.is_some() || targets.z.is_some();
        if let (Some(r), true) = (next.tilt, linear_words) {
            let w = r * nalgebra::Vector3::new(next.last[0], next.last[1], next.last[2]);
            (targets.x, targets.y, targets.z) = (Some(w.x), Some(w.y), Some(w.z));
            if !next.tcp && next.axes_frame().is_none() && (targets.a.is_some() || targets.b.is_some() || targets.c.is_some()) {
                diags.error(line, column, "linear and rotary axis words in one block in a tilted working plane without M128 / FUNCTION TCPM: position the rotary axes in a block of their own");
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
        // not R).
        if (before.dialect == Dialect::Rs274 || fanuc) && arc_motion && targets.is_empty() && !g10 && !words.iter().any(|w| w.letter == 'R') {
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
        // Sinumerik: "G4 must be programmed in a separate NC block" (Fundamentals, G4): a dwell with a
        // move is an alarm on the control, not a dwell and then a move as LinuxCNC reads it.
        if let (Some(g), true, Dialect::Sinumerik) = (dwell_word, moves, before.dialect) {
            diags.error(line, g.column, "G4 with axis words: Sinumerik runs a dwell only in a block of its own (G4 F, seconds)");
        }
        if moves && block_motion.is_none() {
            diags.error(line, column, "axis words without a motion mode: expected G00 or G01 first");
        }
        let mut arc = None;
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
                    diags.error(line, column, format!("{g} move without a feed: expected an F word before or in this block{why}"))
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
                        let why = if next.spindle_turning.is_none() { "no M3 or M4 has started it in this program" } else { "M5 stopped it" };
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
        let errors_after = diags.errors();
        if errors_after > errors_before {
            *self = before;
            // The tool vector belonged to this block: it does not carry over to the next one.
            self.pending_vector = None;
            return None;
        }
        // In a tilted plane without TCPM a move of the rotary axes alone leaves the linear axes where
        // they stand, so the tool tip moves in the plane: read it anew.
        let rotary_only = !linear_words && (targets.a.is_some() || targets.b.is_some() || targets.c.is_some());
        let axes_before = (before.tilt.is_some() && !before.tcp && before.axes_frame().is_none() && rotary_only).then(|| before.axes_now());
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
            tcp: (self.tcp || self.tilt.is_some() && self.axes_frame().is_none() && (targets.x.is_some() || targets.y.is_some() || targets.z.is_some())) && !shot.is_some_and(|s| s.axes.is_some()),
            datum: self.datum,
            orientation: self.orientation,
            events,
            dwell_s,
            tolerance: self.tolerance,
            // A move of the machine's axes (machine coordinates) is where it is, whatever the datum.
            offset_assumed: self.offset_assumed() && !shot.is_some_and(|s| s.axes.is_some() && !s.own),
            exact: if exact_stop_here { Exact::Stop } else { self.exact },
        };
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
