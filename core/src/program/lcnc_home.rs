//! LinuxCNC's moves to a stored position, `G28` and `G30`, and their stores `G28.1` and `G30.1`
//! (G-code reference §G28, G28.1; interp_convert.cc convert_home, convert_savehome): a rapid move
//! to the block's axis words (the intermediate point, in the current distance mode and offsets),
//! then a rapid move of the axes named (all of them, none named) to the stored position, which is
//! in machine coordinates (parameters 5161-5166 for G28, 5181-5186 for G30). The stored positions
//! are the machine's state (its parameter file): the machine file's reference points
//! (`[machine_coordinates] reference_points_mm`, the rotary axes at 0, as LinuxCNC's parameters
//! start), or where the program stored them.

use super::fanuc::{apply, settings, shot, word};
use super::interp::{x10, Dimension, Interpreter, OneShot, Word};
use super::lex::Diags;
use super::{Block, Motion};

const AXES: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

/// A block with `G28`, `G30`, `G28.1` or `G30.1`: its settings, then its moves (or the store);
/// `None` for any other block.
pub(crate) fn expand(it: &mut Interpreter, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> Option<bool> {
    let g = words.iter().find(|w| w.letter == 'G' && matches!(x10(w), 280 | 281 | 300 | 301))?;
    let code = x10(g);
    let k = usize::from(code >= 300);
    let axes: Vec<Word> = words.iter().filter(|w| AXES.contains(&w.letter)).cloned().collect();
    // Axis words belong to G28/G30 here: a motion code with them is refused before
    // ([`super::interp::lcnc_refusal`]). G80 takes none: it ends the canned cycle and leaves them to
    // G28/G30 (interp_internal.cc, enhance_block: "cannot use axis values with G80" unless a group 0
    // code covets them).
    if words.iter().any(|w| w.letter == 'G' && x10(w) == 800) {
        it.cycles.active = None;
    }
    if !apply(it, &settings(words, &AXES, &["28", "28.1", "30", "30.1"]), line, column, number, diags, out) {
        return Some(false);
    }
    if code % 10 == 1 {
        // G28.1 / G30.1: the current position, in machine coordinates, becomes the stored one.
        if let Some(w) = axes.first() {
            diags.error(line, w.column, format!("G{} {}{}: G28.1 and G30.1 store where the axes stand; axis words are not read with them", g.raw, w.letter, w.raw));
            return Some(false);
        }
        let (p, at) = (it.position(), it.world_now());
        it.stored_home[k] = Some([at[0], at[1], at[2], p[3], p[4], p[5]]);
        return Some(true);
    }
    let Some(home) = stored(it, k) else {
        let why = match it.machine_coords() {
            None => "the machine file places no machine coordinates ([machine_coordinates]), so the stored position (LinuxCNC's parameters 5161-5166, 5181-5186) is unknown".to_string(),
            Some(_) => format!("the machine file gives no reference point {} (machine_coordinates.reference_points_mm: G28's is the first, G30's the second)", k + 1),
        };
        diags.error(line, g.column, format!("G{}: {why}", g.raw));
        return Some(false);
    };
    // The intermediate point, in the current distance mode (nothing to do where it is where the
    // tool stands: LinuxCNC's move of zero length).
    let still = axes.iter().all(|w| w.value == 0.0 && (!it.absolute() || w.dimension == Dimension::Incremental));
    if !axes.is_empty() && !still && !shot(it, OneShot { motion: Motion::Rapid, absolute: false, axes: None, own: false }, &axes, line, column, number, diags, out) {
        return Some(false);
    }
    // Then the axes named, or every axis, to the stored position read in the program's frame.
    let named: Vec<(char, usize)> = match axes.is_empty() {
        true => AXES.iter().copied().filter(|l| it.has_axis(*l)).map(|l| (l, g.column)).collect(),
        false => axes.iter().map(|w| (w.letter, w.column)).collect(),
    };
    let p = it.program_of_world([home[0], home[1], home[2]]);
    let to: Vec<Word> = named
        .into_iter()
        .map(|(l, column)| {
            let k = AXES.iter().position(|c| *c == l).unwrap_or(0);
            let v = if k < 3 { p[k] / it.unit() } else { home[k] / it.rotary_unit(k - 3) };
            word(l, v, column)
        })
        .collect();
    Some(shot(it, OneShot { motion: Motion::Rapid, absolute: true, axes: None, own: false }, &to, line, column, number, diags, out))
}

/// Stored position `k` (0: G28's, 1: G30's) in the workpiece frame (m, rad): the program's, else
/// the machine file's reference point with the rotary axes at 0.
fn stored(it: &Interpreter, k: usize) -> Option<[f64; 6]> {
    if let Some(h) = it.stored_home[k] {
        return Some(h);
    }
    let m = it.machine_coords()?;
    let r = m.to_axes(*m.references.get(k)?);
    Some([r.x, r.y, r.z, 0.0, 0.0, 0.0])
}
