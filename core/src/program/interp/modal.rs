//! LinuxCNC's saved modal state (`M70` save, `M71` invalidate, `M72` restore, `M73` save and
//! restore on return; M-code reference §M70-M73): what is saved, and the restore, which LinuxCNC
//! makes by running the G code of what differs (interp_convert.cc `restore_settings`: `G20`/`G21`
//! first, then one block of ` F%.1f` and the G codes of each group that changed, `gen_settings`).

use std::borrow::Cow;

use super::{Dimension, Interpreter, Word};
use crate::program::lex::Diags;
use crate::program::{Block, Exact, FeedMode, Plane, ProgrammedTolerance};
use crate::units::INCH;

/// The modal state M70 saves, of what this reader models: units, plane, distance and arc distance
/// mode, feed mode and feed, the spindle's speed and whether it turns (which a G95 feed needs), the
/// coordinate system, retract mode, whether G92 offsets apply, the path control mode and its
/// tolerance, and whether cutter compensation is on. (The coolant and override M codes it restores
/// move nothing; tool length offsets and lathe diameter mode are not modelled.)
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ModalState {
    inch: bool,
    plane: Plane,
    absolute: bool,
    arc_absolute: bool,
    feed_mode: FeedMode,
    /// G95 rather than G94.
    per_revolution: bool,
    /// S, and the spindle turning (M3/M4) or stopped (M5): `gen_settings` writes ` S%.0f`,
    /// `gen_m_codes` the spindle's M code.
    speed: Option<f64>,
    spindle_turning: Option<bool>,
    spindle_ccw: bool,
    /// F in the program's unit per minute (or inverse time), if set: [`Interpreter::feed_in_program_units`].
    feed: Option<f64>,
    system: usize,
    to_r: bool,
    g92_applied: bool,
    exact: Exact,
    tolerance: ProgrammedTolerance,
    comp: bool,
}

impl Interpreter {
    /// F as LinuxCNC's interpreter holds it: the path feed in the program's unit per minute (its
    /// task converts it when the unit changes), or the inverse time as written.
    pub(crate) fn feed_in_program_units(&self) -> Option<f64> {
        self.feed.map(|(per_min, raw)| match self.feed_mode {
            FeedMode::PerMinute => per_min * crate::units::MM / self.feed_unit,
            FeedMode::InverseTime => raw,
        })
    }

    /// The modal state now (M70, M73).
    pub(crate) fn modal_state(&self) -> ModalState {
        ModalState {
            inch: self.unit == INCH,
            plane: self.plane,
            absolute: self.absolute,
            arc_absolute: self.arc_absolute,
            feed_mode: self.feed_mode,
            per_revolution: self.per_revolution,
            speed: self.spindle_speed,
            spindle_turning: self.spindle_turning,
            spindle_ccw: self.spindle_ccw,
            feed: self.feed_in_program_units(),
            system: self.system,
            to_r: self.cycles.to_r,
            g92_applied: self.axis_offset != [0.0; 3],
            exact: self.exact,
            tolerance: self.tolerance,
            comp: self.comp.as_ref().is_some_and(|c| c.on.is_some()),
        }
    }

    /// Restore `saved` as LinuxCNC does (M72, or a subroutine's return after M73): the units by
    /// their code, then one block of F (to 0.1, as `gen_settings` writes it) and the codes of the
    /// groups that differ, read as any block (a system change re-reads the current point; under
    /// cutter compensation the same refusals). Its blocks go to `out`; false if one is refused.
    /// F and S are written back whether they differ or not, as LinuxCNC 2.9.0 and later do
    /// (interp_convert.cc gen_settings, its comparison masked for issue 1987); the Debian 12
    /// snapshot's rs274 (2.9.0~pre1, before that change) writes them only where they differ, so
    /// its feed after M72 can keep more decimals than 2.9's, rounded to 0.1.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn restore_modal(&mut self, saved: &ModalState, line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
        let now = self.modal_state();
        let word = |letter: char, raw: String| Word { letter, value: raw.parse().unwrap_or(0.0), raw: Cow::Owned(raw), column, dimension: Dimension::Modal };
        if saved.inch != now.inch && !self.block(&[word('G', if saved.inch { "20" } else { "21" }.into())], line, column, number, diags, out) {
            return false;
        }
        if saved.comp && !now.comp {
            diags.error(line, column, "the restored modal state has cutter radius compensation on, which this one turned off: turning it on again (with the tool's radius) is not read");
            return false;
        }
        let mut words = Vec::new();
        // LinuxCNC writes F0.0 for a feed never set, and for one under 0.05 (F%.1f: a feed per
        // revolution of 0.014 mm comes back as 0); here such a feed is left unset, so that a feed
        // move before the next F is refused, as LinuxCNC refuses a feed of zero.
        let written = saved.feed.map(|f| format!("{f:.1}")).filter(|w| w.parse::<f64>().is_ok_and(|f| f > 0.0));
        if let Some(w) = &written {
            words.push(word('F', w.clone()));
        }
        let mut code = |differs: bool, g: &str| {
            if differs {
                words.push(word('G', g.to_string()));
            }
        };
        code(saved.plane != now.plane, match saved.plane {
            Plane::Xy => "17",
            Plane::Zx => "18",
            Plane::Yz => "19",
        });
        code(saved.comp != now.comp, "40");
        code(saved.absolute != now.absolute, if saved.absolute { "90" } else { "91" });
        code(saved.feed_mode != now.feed_mode || saved.per_revolution != now.per_revolution, match (saved.feed_mode, saved.per_revolution) {
            (FeedMode::InverseTime, _) => "93",
            (FeedMode::PerMinute, true) => "95",
            (FeedMode::PerMinute, false) => "94",
        });
        code(saved.system != now.system, ["54", "55", "56", "57", "58", "59", "59.1", "59.2", "59.3"][saved.system]);
        code(saved.to_r != now.to_r, if saved.to_r { "99" } else { "98" });
        code(saved.arc_absolute != now.arc_absolute, if saved.arc_absolute { "90.1" } else { "91.1" });
        code(saved.g92_applied != now.g92_applied, if saved.g92_applied { "92.3" } else { "92.2" });
        code(saved.exact != now.exact, match saved.exact {
            Exact::Blend => "64",
            Exact::Path => "61",
            Exact::Stop => "61.1",
        });
        // S%.0f: the speed as LinuxCNC writes it back, a whole number.
        (self.spindle_speed, self.spindle_turning, self.spindle_ccw) = (saved.speed.map(f64::round), saved.spindle_turning, saved.spindle_ccw);
        if !words.is_empty() && !self.block(&words, line, column, number, diags, out) {
            return false;
        }
        if written.is_none() {
            self.feed = None;
        }
        self.tolerance = saved.tolerance;
        true
    }
}
