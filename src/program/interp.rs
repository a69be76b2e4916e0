//! The modal state machine shared by the G-code readers: validated words of one block in, a
//! [`Block`] out. A block with a semantic defect changes no modal state and yields no block.

use super::lex::Diags;
use super::{Block, Dialect, Feed, FeedMode, Motion, Targets};
use crate::units::{DEG, INCH, MM};

/// One address word with a valid number.
#[derive(Debug, Clone, PartialEq)]
pub struct Word {
    pub letter: char,
    pub value: f64,
    /// The value as written (`43.4`, `+14.825`), for messages and G-code sub-numbers.
    pub raw: String,
    pub column: usize,
    /// Heidenhain `IX+5`: incremental for this word only.
    pub incremental: bool,
}

/// Modal state of a G-code program.
#[derive(Debug, Clone)]
pub struct Interpreter {
    dialect: Dialect,
    unit: f64,
    absolute: bool,
    motion: Option<Motion>,
    feed: Option<f64>,
    feed_mode: FeedMode,
    tcp: bool,
    datum: [f64; 3],
    /// Last programmed absolute value of X Y Z A B C (SI).
    last: [f64; 6],
}

const AXIS_LETTERS: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

impl Interpreter {
    pub fn new(dialect: Dialect) -> Self {
        Interpreter {
            dialect,
            unit: MM,
            absolute: true,
            motion: None,
            feed: None,
            feed_mode: FeedMode::PerMinute,
            tcp: false,
            datum: [0.0; 3],
            last: [0.0; 6],
        }
    }

    /// Set the program's length unit (Heidenhain header G70/G71).
    pub fn set_inch(&mut self, inch: bool) {
        self.unit = if inch { INCH } else { MM };
    }

    /// Interpret one block's words. Defects go to `diags` and yield `None` with the state unchanged.
    pub fn block(
        &mut self,
        words: &[Word],
        line: usize,
        column: usize,
        number: Option<u64>,
        diags: &mut Diags,
    ) -> Option<Block> {
        let mut next = self.clone();
        let errors_before = diags.0.iter().filter(|d| d.severity == super::Severity::Error).count();
        let mut datum_block = false;
        let mut events = Vec::new();
        let mut feed_word: Option<&Word> = None;
        let heid = self.dialect == Dialect::Heidenhain;

        // Modal G codes and M codes first: they govern how the axis words of this block are read.
        for w in words {
            match w.letter {
                'G' => {
                    let code = w.raw.trim_start_matches('+');
                    let code = code.trim_start_matches('0');
                    let code = if code.is_empty() || code.starts_with('.') { format!("0{code}") } else { code.to_string() };
                    match (code.as_str(), heid) {
                        ("0", _) => next.motion = Some(Motion::Rapid),
                        ("1", _) => next.motion = Some(Motion::Linear),
                        ("2" | "3" | "5" | "6", _) => diags.error(
                            line,
                            w.column,
                            format!("G{} (circular or spline motion) is not supported: expected G00 or G01", w.raw),
                        ),
                        ("17" | "18" | "19" | "40" | "80", _) => {}
                        ("90", _) => next.absolute = true,
                        ("91", _) => next.absolute = false,
                        ("70", true) | ("20", false) => next.unit = INCH,
                        ("71", true) | ("21", false) => next.unit = MM,
                        ("54", true) => datum_block = true,
                        ("54", false) => {}
                        ("55" | "56" | "57" | "58" | "59", false) => diags.warning(
                            line,
                            w.column,
                            format!("G{}: work offsets are not modelled; coordinates are read as written", w.raw),
                        ),
                        ("93", false) => next.feed_mode = FeedMode::InverseTime,
                        ("94", false) => next.feed_mode = FeedMode::PerMinute,
                        ("95", false) => diags.error(line, w.column, "G95 (feed per revolution) is not supported: expected G93 or G94"),
                        ("43.4", false) => next.tcp = true,
                        ("49", false) => next.tcp = false,
                        ("43" | "61" | "61.1" | "64", false) => diags.warning(
                            line,
                            w.column,
                            format!("G{} is not modelled and was ignored", w.raw),
                        ),
                        _ => diags.warning(line, w.column, format!("unsupported G code G{} ignored", w.raw)),
                    }
                }
                'M' => {
                    let code = w.value as i64;
                    if w.value.fract() != 0.0 || w.value < 0.0 {
                        diags.error(line, w.column, format!("M{}: expected a whole M code number", w.raw));
                        continue;
                    }
                    match (code, heid) {
                        (128, true) => next.tcp = true,
                        (129, true) => next.tcp = false,
                        (0..=9 | 13 | 14 | 30, _) | (126 | 127, true) | (60, false) => {}
                        (_, true) => diags.warning(line, w.column, format!("unknown M code M{} kept as an event", w.raw)),
                        (_, false) => {}
                    }
                    events.push(format!("M{}", w.raw));
                }
                'T' | 'S' => events.push(format!("{}{}", w.letter, w.raw)),
                'F' => feed_word = Some(w),
                'N' => {}
                c if AXIS_LETTERS.contains(&c) => {}
                _ => diags.warning(
                    line,
                    w.column,
                    format!("unsupported word {}{} ignored", w.letter, w.raw),
                ),
            }
        }

        if let Some(w) = feed_word {
            if !(w.value > 0.0) {
                diags.error(line, w.column, format!("F{}: expected a positive feed", w.raw));
            } else {
                next.feed = Some(match next.feed_mode {
                    FeedMode::PerMinute => w.value * next.unit / MM,
                    FeedMode::InverseTime => w.value,
                });
            }
        }

        let mut targets = Targets::default();
        let mut datum = next.datum;
        for w in words {
            let Some(k) = AXIS_LETTERS.iter().position(|&c| c == w.letter) else { continue };
            let scale = if k < 3 { next.unit } else { DEG };
            let v = w.value * scale;
            if datum_block {
                if k < 3 {
                    datum[k] = v;
                } else {
                    diags.warning(line, w.column, format!("{}{} in a datum shift (G54) is not modelled", w.letter, w.raw));
                }
                continue;
            }
            let abs = if next.absolute && !w.incremental { v } else { next.last[k] + v };
            next.last[k] = abs;
            match k {
                0 => targets.x = Some(abs),
                1 => targets.y = Some(abs),
                2 => targets.z = Some(abs),
                3 => targets.a = Some(abs),
                4 => targets.b = Some(abs),
                _ => targets.c = Some(abs),
            }
        }
        next.datum = datum;

        let moves = !targets.is_empty();
        if moves && next.motion.is_none() {
            diags.error(line, column, "axis words without a motion mode: expected G00 or G01 first");
        }
        if moves && next.motion == Some(Motion::Linear) {
            match next.feed_mode {
                FeedMode::PerMinute if next.feed.is_none() => {
                    diags.error(line, column, "G01 move without a feed: expected an F word before or in this block")
                }
                FeedMode::InverseTime if feed_word.is_none() => {
                    diags.error(line, column, "G93 inverse-time move without F in the block: expected F (1/min)")
                }
                _ => {}
            }
        }
        let errors_after = diags.0.iter().filter(|d| d.severity == super::Severity::Error).count();
        if errors_after > errors_before {
            return None;
        }
        *self = next;
        Some(Block {
            line,
            column,
            number,
            motion: self.motion.unwrap_or(Motion::Linear),
            targets,
            feed: self.feed.map(|value_per_min| Feed { value_per_min, mode: self.feed_mode }),
            tcp: self.tcp,
            datum: self.datum,
            events,
        })
    }
}
