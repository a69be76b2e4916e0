//! LinuxCNC's `M70`-`M73` in a program's blocks: the modal state saved in the current call frame,
//! invalidated, restored, or restored when the subroutine returns (M-code reference §M70-M73;
//! interp_convert.cc convert_m, interp_o_word.cc leave_context). The state and its restore are the
//! interpreter's ([`crate::program::interp::ModalState`]); the frames are the O-word calls'.

use super::interp::{ModalState, Word};
use super::lex::Diags;
use super::rs274::Rs274Reader;
use super::Block;

/// The saved state of each call frame (0 the main program): the state, and whether it is restored
/// when the frame's subroutine returns (M73).
#[derive(Debug, Clone, Default)]
pub(crate) struct Contexts(Vec<Option<(ModalState, bool)>>);

impl Contexts {
    /// A call enters frame `depth`: it starts with no saved state.
    pub(crate) fn enter(&mut self, depth: usize) {
        if let Some(c) = self.0.get_mut(depth) {
            *c = None;
        }
    }

    /// The frame `depth` is left: what it restores on return (M73), if anything.
    pub(crate) fn leave(&mut self, depth: usize) -> Option<ModalState> {
        match self.0.get_mut(depth).and_then(Option::take) {
            Some((state, true)) => Some(state),
            _ => None,
        }
    }

    fn slot(&mut self, depth: usize) -> &mut Option<(ModalState, bool)> {
        if self.0.len() <= depth {
            self.0.resize_with(depth + 1, || None);
        }
        &mut self.0[depth]
    }
}

/// M codes LinuxCNC acts on before M70-M73 in a block (its order of execution: feed mode, F, S, T,
/// M6/M61, spindle; they share modal group 7 with M3/M4/M5/M19), which this reader does not split
/// out of the block: with them, the block is refused.
fn acts_before(w: &Word) -> bool {
    match w.letter {
        'F' | 'S' | 'T' => true,
        'G' => matches!(w.value, 93.0 | 94.0 | 95.0),
        'M' => matches!(w.value, 3.0 | 4.0 | 5.0 | 6.0 | 19.0 | 61.0),
        _ => false,
    }
}

impl Rs274Reader {
    /// A block's M70-M73, done before the rest of its words (which stay in `words`); false if it is
    /// refused (the block is then not run).
    pub(super) fn modal_context(&mut self, words: &mut Vec<Word>, line: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
        let is_context = |w: &Word| w.letter == 'M' && matches!(w.value, 70.0 | 71.0 | 72.0 | 73.0);
        let Some(k) = words.iter().position(is_context) else { return true };
        let m = words.remove(k);
        if let Some(w) = words.iter().find(|w| is_context(w) || (w.letter == 'M' && matches!(w.value, 3.0 | 4.0 | 5.0 | 19.0))) {
            diags.error(line, w.column, format!("M{} with M{}: two M codes of modal group 7 in one block (LinuxCNC: \"Two M codes used from same modal group\")", w.raw, m.raw));
            return false;
        }
        if let Some(w) = words.iter().find(|w| acts_before(w)) {
            diags.error(line, w.column, format!("{}{} with M{} in one block: LinuxCNC acts on it before saving or restoring the modal state; not read (write it in a block of its own)", w.letter, w.raw, m.raw));
            return false;
        }
        let depth = self.flow.depth();
        match m.value as u32 {
            70 | 73 => {
                let restore = m.value == 73.0 && depth > 0;
                if m.value == 73.0 && depth == 0 {
                    diags.warning(line, m.column, "M73 in the main program: nothing to return to; the state is saved, as M70 (LinuxCNC: \"M73 at top level\")");
                }
                *self.contexts.slot(depth) = Some((self.interp.modal_state(), restore));
            }
            71 => *self.contexts.slot(depth) = None,
            _ => match self.contexts.slot(depth).clone() {
                Some((state, _)) => return self.interp.restore_modal(&state, line, m.column, number, diags, out),
                None => {
                    diags.error(line, m.column, "M72: Cannot restore context from invalid stack frame - missing M70/M73? (LinuxCNC)");
                    return false;
                }
            },
        }
        true
    }
}
