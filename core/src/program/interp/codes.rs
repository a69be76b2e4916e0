//! Codes a block's words may carry whose reading is a rule of its own: makers' M functions, the
//! TNC's M functions, Fanuc's G43.5 tool vector.

use super::Word;
use crate::program::lex::Diags;
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
/// functions"); `Err` says why not. A machine's own M functions are refused until `--m-code` says.
pub(super) fn tnc_m_code(code: i64) -> Result<(), &'static str> {
    match code {
        // Tool life, handwheel superposition (no motion of its own), look-ahead for radius
        // compensation (none is read), rotary shortest path off (the reset state), touch probe
        // monitoring, lift-off at NC stop.
        101 | 102 | 118 | 120 | 127 | 141 | 148 | 149 => Ok(()),
        91 | 92 | 130 => Err("positions in the machine coordinate system are not modelled (it changes the motion)"),
        89 | 99 => Err("cycle call: machining cycles are not read (they cut)"),
        103 | 109 | 110 | 116 | 136 => Err("changes how the feed is read: not modelled"),
        94 => Err("reducing the rotary axis display below 360 deg is not modelled (it changes later absolute positions)"),
        114 | 134 | 138 | 140 | 143 | 144 => Err("not modelled (it changes the motion)"),
        _ => Err("not a TNC M function that leaves the motion alone: a machine maker's own, whose effect is unknown; \
                  say what it does with --m-code CODE=tcp-on|tcp-off|event"),
    }
}

/// LinuxCNC's modal group of a G code (interp_array.cc `_gees`, after [NCMS] and [Fanuc]): "only one
/// g_code from any one group may appear on a line". Group 0 is the non-modal codes, 1 the motions and
/// canned cycles; `None` for a code outside the table (the interpreter refuses it by itself).
pub(crate) fn lcnc_group(code: &str) -> Option<u8> {
    Some(match code {
        "4" | "10" | "28" | "28.1" | "30" | "30.1" | "52" | "53" | "92" | "92.1" | "92.2" | "92.3" => 0,
        "0" | "1" | "2" | "3" | "5" | "5.1" | "5.2" | "5.3" | "33" | "33.1" | "38.2" | "38.3" | "38.4" | "38.5" | "70" | "71" | "71.1" | "71.2" | "72" | "72.1" | "72.2" | "73" | "74" | "76" | "80" | "81" | "82" | "83" | "84" | "85" | "86" | "87" | "88" | "89" => 1,
        "17" | "17.1" | "18" | "18.1" | "19" | "19.1" => 2,
        "90" | "91" => 3,
        "90.1" | "91.1" => 4,
        "93" | "94" | "95" => 5,
        "20" | "21" => 6,
        "40" | "41" | "41.1" | "42" | "42.1" => 7,
        "43" | "43.1" | "43.2" | "49" => 8,
        "98" | "99" => 10,
        "54" | "55" | "56" | "57" | "58" | "59" | "59.1" | "59.2" | "59.3" => 12,
        "61" | "61.1" | "64" => 13,
        "96" | "97" => 14,
        "7" | "8" => 15,
        _ => return None,
    })
}
