//! One address word of a block as the interpreter takes it: its letter, value, text as written and
//! column, and how it is dimensioned (modal, or absolute, incremental or a modulo axis' way for
//! this word alone).

use std::borrow::Cow;

/// One address word with a valid number.
#[derive(Debug, Clone, PartialEq)]
pub struct Word<'a> {
    pub letter: char,
    pub value: f64,
    /// The value as written (`43.4`, `+14.825`), for messages and G-code sub-numbers: borrowed from
    /// the program's text where it stands there (no allocation per word).
    pub raw: Cow<'a, str>,
    pub column: usize,
    /// Heidenhain `IX+5`, Sinumerik `X=IC(5)`: incremental for this word only; Sinumerik
    /// `X=AC(5)`: absolute for this word only; else as the block's G90/G91 say.
    pub dimension: Dimension,
}

/// How a word's value is dimensioned: as the modal G90/G91 say, or for this word only (Sinumerik
/// Programming Manual Fundamentals, "Absolute dimensions (G90, AC)" and "Incremental dimensions
/// (G91, IC)": "non-modal absolute dimensions ... also for interpolation parameters (I, J, K)").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Dimension {
    #[default]
    Modal,
    Incremental,
    Absolute,
    /// A modulo rotary axis' absolute position (0..360 deg) reached by the way said: Sinumerik's
    /// `DC()`, `ACP()`, `ACN()` (840Di sl Programming Manual 11/2006, "Absolute dimensions for
    /// rotary axes (DC, ACP, ACN)"; Function Manual Axes and Spindles R2 §7.2, "Modulo 360 degrees").
    Modulo(Turn),
}

/// The way a modulo rotary axis turns to an absolute position.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Turn {
    /// `DC`: the shorter way (at most half a turn).
    Shortest,
    /// `ACP`: in the positive direction.
    Positive,
    /// `ACN`: in the negative direction.
    Negative,
}

impl Turn {
    /// Where an axis at `from` ends turned this way to the position `to` (both rad; `to` taken
    /// modulo a turn): less than a turn away, no move where it stands there already.
    pub fn place(self, to: f64, from: f64) -> f64 {
        let tau = std::f64::consts::TAU;
        // Less than a turn: a remainder a rounding short of a whole turn (an axis that stands at
        // the position, reached by arithmetic) is none.
        let within = |d: f64| if d > tau - 1e-9 { 0.0 } else { d };
        match self {
            Turn::Shortest => crate::kinematics::unwrap_near(to, from),
            Turn::Positive => from + within((to - from).rem_euclid(tau)),
            Turn::Negative => from - within((from - to).rem_euclid(tau)),
        }
    }

    /// The word as the program writes it.
    pub fn name(self) -> &'static str {
        match self {
            Turn::Shortest => "DC",
            Turn::Positive => "ACP",
            Turn::Negative => "ACN",
        }
    }
}

impl Dimension {
    /// Whether the word's value is absolute, the modal dimensioning (G90, or G90.1 for circle
    /// centres) being `modal_absolute`.
    pub fn absolute(self, modal_absolute: bool) -> bool {
        match self {
            Dimension::Absolute | Dimension::Modulo(_) => true,
            Dimension::Incremental => false,
            Dimension::Modal => modal_absolute,
        }
    }
}
