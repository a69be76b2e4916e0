//! A quill's words in RS274NGC (LinuxCNC's bridgemill: `W`, a linear axis along the tool). Its
//! kinematics (`5axiskins`: the tool tip at the program point less W along the tool, "Motion for the
//! W coordinate is incorporated into the motions of the joints used for X,Y,Z motion", its README)
//! make a W move a move of the tool tip along the tool axis; the reader writes it as one, in the
//! program's X Y Z, from where the tip stood when W left 0. The quill's position follows `G90/G91`,
//! `G53` (machine coordinates) and `G10 L2/L20 P0` (its offset in the active system). Refused: a W
//! move with other axes in its block or any move with the quill out (the tip would be off the
//! program point by a W the other moves do not carry), a W beyond the quill's range, a W move
//! without tool-centre-point kinematics, W in another system's offset (`G10 ... P1`..).

use super::interp::{Dimension, Word};
use super::lex::Diags;
use super::rs274::Rs274Reader;
use crate::machine::Quill;

/// Where the quill is: its machine position and its offset in the active system, m, and the program
/// point the tip left when the quill moved out.
#[derive(Debug, Clone, Copy)]
pub struct QuillState {
    pub quill: Quill,
    machine: f64,
    offset: f64,
    base: Option<[f64; 3]>,
}

impl QuillState {
    pub fn new(quill: Quill) -> Self {
        QuillState { quill, machine: 0.0, offset: 0.0, base: None }
    }
}

impl Rs274Reader {
    /// Take the quill's word out of `words`, moving the quill; a W move alone becomes a move of the
    /// tip along the tool (X Y Z words). False if the line is damaged (said in `diags`).
    pub(super) fn quill_words(&mut self, words: &mut Vec<Word>, line: usize, diags: &mut Diags) -> bool {
        let Some(mut q) = self.quill else { return true };
        let letter = q.quill.letter;
        let axis_words = |words: &[Word]| words.iter().any(|w| "XYZABC".contains(w.letter));
        let Some(k) = words.iter().position(|w| w.letter == letter) else {
            if q.machine != 0.0 && axis_words(words) && !words.iter().any(|w| w.letter == 'G' && w.value == 10.0) {
                diags.error(line, words[0].column, format!("a move with the quill out ({letter} {:.4} mm): the tip would be off the program point, not modelled", q.machine * 1e3));
                return false;
            }
            return true;
        };
        let w = words.remove(k);
        let g = |v: f64| words.iter().any(|w| w.letter == 'G' && (w.value - v).abs() < 1e-9);
        let unit = self.interp.unit();
        let v = w.value * unit;
        if g(10.0) {
            // G10 L2 / L20 P0: the quill's offset in the active system, as the others'.
            let l = words.iter().find(|w| w.letter == 'L').map(|w| w.value);
            let p = words.iter().find(|w| w.letter == 'P').map(|w| w.value);
            match (l, p) {
                (Some(l), Some(p)) if p == 0.0 && (l == 2.0 || l == 20.0) => {
                    q.offset = if l == 20.0 { q.machine - v } else { v };
                    self.quill = Some(q);
                    return true;
                }
                _ => {
                    diags.error(line, w.column, format!("{letter} in G10 other than L2 or L20 with P0 (the active system): not modelled"));
                    return false;
                }
            }
        }
        let to = if g(53.0) {
            v
        } else if self.interp.absolute() {
            q.offset + v
        } else {
            q.machine + v
        };
        if !(q.quill.min..=q.quill.max).contains(&to) {
            diags.error(line, w.column, format!("{letter} would move to {:.3} mm, outside the quill's range {:.3}..{:.3} mm", to * 1e3, q.quill.min * 1e3, q.quill.max * 1e3));
            return false;
        }
        if to == q.machine {
            return true;
        }
        if axis_words(words) {
            diags.error(line, w.column, format!("{letter} with other axes in one block: not modelled (the tip would move along the tool while the others move)"));
            return false;
        }
        if !self.interp.tcp() {
            diags.error(line, w.column, format!("{letter} without tool-centre-point kinematics: where the quill takes the tip is not modelled"));
            return false;
        }
        let Some(axis) = self.interp.tool_axis_now() else {
            diags.error(line, w.column, format!("{letter}: the tool axis is the machine's: read the program on one (--machine)"));
            return false;
        };
        let p = self.interp.position();
        let base = q.base.unwrap_or([p[0], p[1], p[2]]);
        // The tip lies the quill's machine position along the tool from the program point.
        let along = q.quill.sense * to;
        let tip: [f64; 3] = std::array::from_fn(|i| base[i] + along * axis[i]);
        // The tip's program coordinates, absolute whatever G90/G91 say: the block's own words, each
        // with the quill word's text and column for a message (what was written there; formatting
        // the numbers cost an O-word loop's read an eighth of its time).
        let absolute = self.interp.absolute();
        for (i, l) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            let value = if absolute { tip[i] } else { tip[i] - p[i] } / unit;
            words.push(Word { letter: l, value, raw: w.raw.clone(), column: w.column, dimension: Dimension::Modal });
        }
        q.machine = to;
        q.base = if to == 0.0 { None } else { Some(base) };
        self.quill = Some(q);
        true
    }
}
