//! The tool table LinuxCNC's `G41`/`G42` take their radius from, and the tool in the spindle.

use crate::program::interp::Word;

/// A tool table as LinuxCNC keeps it (`tool.tbl`: `T1 P1 D10 Z0 ;comment`), its diameters: what
/// `G41`/`G42` with a `D` (or the tool in the spindle) compensate by. Its lengths are in the
/// machine's unit (LinuxCNC's `[TRAJ] LINEAR_UNITS`): mm unless [`ToolTable::in_unit`] says inches.
#[derive(Debug, Clone, PartialEq)]
pub struct ToolTable {
    tools: Vec<(u32, f64)>,
    /// Metres per unit of the table's numbers.
    unit: f64,
}

/// The most tools a table may hold (LinuxCNC's CANON_POCKETS_MAX is 1000).
pub const MAX_TOOLS: usize = 100_000;

impl ToolTable {
    /// Read a LinuxCNC tool table: each line `T<n>` with the words `P X Y Z A B C U V W D I J Q`, a
    /// `;` comment. Errors name the line and the word.
    pub fn parse(text: &str) -> Result<ToolTable, String> {
        let mut tools: Vec<(u32, f64)> = Vec::new();
        for (k, raw) in text.lines().enumerate() {
            let line = k + 1;
            let body = raw.split(';').next().unwrap_or("").trim();
            if body.is_empty() {
                continue;
            }
            let (mut tool, mut diameter) = (None, 0.0);
            for word in body.split_whitespace() {
                let mut chars = word.chars();
                let letter = chars.next().map(|c| c.to_ascii_uppercase()).unwrap_or(' ');
                let value: f64 = chars.as_str().parse().map_err(|_| format!("line {line}: '{word}': expected a letter and a number"))?;
                if !value.is_finite() {
                    return Err(format!("line {line}: '{word}': not a finite number"));
                }
                match letter {
                    'T' if value >= 0.0 && value.fract() == 0.0 && value <= u32::MAX as f64 => tool = Some(value as u32),
                    'T' => return Err(format!("line {line}: '{word}': a tool number is a whole number 0 or more")),
                    'D' => diameter = value,
                    'P' | 'X' | 'Y' | 'Z' | 'A' | 'B' | 'C' | 'U' | 'V' | 'W' | 'I' | 'J' | 'Q' => {}
                    _ => return Err(format!("line {line}: '{word}': not a word of a LinuxCNC tool table (T P X Y Z A B C U V W D I J Q)")),
                }
            }
            let Some(tool) = tool else { return Err(format!("line {line}: no T word (the tool's number)")) };
            if tools.len() >= MAX_TOOLS {
                return Err(format!("line {line}: more than {MAX_TOOLS} tools"));
            }
            match tools.iter_mut().find(|(t, _)| *t == tool) {
                Some(entry) => entry.1 = diameter,
                None => tools.push((tool, diameter)),
            }
        }
        Ok(ToolTable { tools, unit: crate::units::MM })
    }

    /// The table with its numbers in `unit` (an inch machine's table).
    pub fn in_unit(mut self, unit: crate::program::LengthUnit) -> ToolTable {
        self.unit = unit.metres();
        self
    }

    /// Set a tool's diameter (m), as `G10 L1 P R` does; false where the table has no such tool.
    pub(crate) fn set_diameter(&mut self, tool: u32, diameter: f64) -> bool {
        match self.tools.iter_mut().find(|(t, _)| *t == tool) {
            Some(entry) => {
                entry.1 = diameter / self.unit;
                true
            }
            None => false,
        }
    }

    /// A tool's diameter, m.
    pub fn diameter(&self, tool: u32) -> Option<f64> {
        self.tools.iter().find(|(t, _)| *t == tool).map(|(_, d)| *d * self.unit)
    }
}

/// The tool selected (`T`) and the one in the spindle (`M6`, `M61 Q`): what `G41`/`G42` without a
/// `D` (or with `D0`) compensate by.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Tools {
    selected: Option<u32>,
    pub(super) spindle: Option<u32>,
}

impl Tools {
    /// The tool a `T` word selected, and the one `M6` or `M61 Q` put in the spindle, where the
    /// program said (LinuxCNC's `#<_selected_tool>`, `#5400`).
    pub(crate) fn known(&self) -> (Option<u32>, Option<u32>) {
        (self.selected, self.spindle)
    }

    /// A block's `T`, `M6` and `M61 Q`.
    pub(super) fn track(&mut self, words: &[Word]) {
        let whole = |w: &&Word| w.value >= 0.0 && w.value.fract() == 0.0 && w.value <= u32::MAX as f64;
        if let Some(t) = words.iter().find(|w| w.letter == 'T').filter(whole) {
            self.selected = Some(t.value as u32);
        }
        if words.iter().any(|w| w.letter == 'M' && w.value == 6.0) {
            self.spindle = self.selected;
        }
        if words.iter().any(|w| w.letter == 'M' && w.value == 61.0) {
            if let Some(q) = words.iter().find(|w| w.letter == 'Q').filter(whole) {
                self.spindle = Some(q.value as u32);
            }
        }
    }
}

