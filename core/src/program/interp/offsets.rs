//! Work offsets and tool data a program sets: `G10 L2`/`L20` (work offsets), LinuxCNC's `G10 L1`
//! (a tool's radius), `G92`/`G52` (axis offsets), and the program origin they move.

use super::{rotation, Interpreter, Word, AXIS_LETTERS};
use crate::program::lex::Diags;
use crate::program::Dialect;
use crate::units::DEG;

impl Interpreter {
    /// The active work offset (m): the program's for G54-G59.3; under an additional one (Fanuc's
    /// G54.1 Pn, Haas' G154 Pn) what the program's `G10 L20 Pn` set, else zero (the operator's).
    pub(super) fn work_offset(&self) -> [f64; 3] {
        if self.extra_offset { self.extra_offset_value(self.extra_p).unwrap_or([0.0; 3]) } else { self.offsets[self.system] }
    }

    /// The additional work offset `p` (m), if the program set it (`G10 L20 Pn`).
    pub(super) fn extra_offset_value(&self, p: u32) -> Option<[f64; 3]> {
        self.extra_offsets.iter().find(|(q, _)| *q == p).map(|(_, o)| *o)
    }

    /// True if the program set work offset `k` (0 = G54) to anything but zero.
    pub(super) fn offsets_set(&self, k: usize) -> bool {
        self.offsets[k] != [0.0; 3]
    }

    /// `G10 L2 Pn X Y Z`: set work offset n to the values; `G10 L20 Pn X Y Z`: set it so that the
    /// current point reads the values (LinuxCNC G-code reference §G10 L2, §G10 L20); P0 is the active
    /// system. Absolute values only (LinuxCNC: under G91 too); rotary offsets only where they stay zero.
    pub(super) fn set_offsets(&self, words: &[Word], next: &mut Interpreter, line: usize, column: usize, diags: &mut Diags) {
        let word = |l: char| words.iter().find(|w| w.letter == l);
        if self.dialect == Dialect::Rs274 && word('L').is_some_and(|w| w.value == 1.0) {
            return self.set_tool(words, next, line, column, diags);
        }
        let l20 = match word('L') {
            Some(w) if w.value == 2.0 => false,
            Some(w) if w.value == 20.0 => true,
            Some(w) => return diags.error(line, w.column, format!("G10 L{}: only L2 and L20 (set a work offset) are supported", w.raw)),
            None => return diags.error(line, column, "G10 without L: expected G10 L2 Pn or G10 L20 Pn (set a work offset)"),
        };
        if l20 && self.dialect.is_fanuc() {
            return self.set_extra_offset(words, next, line, column, diags);
        }
        let l = if l20 { "L20" } else { "L2" };
        let p = match word('P') {
            Some(w) if w.value.fract() == 0.0 && (0.0..=9.0).contains(&w.value) => w.value as usize,
            Some(w) => return diags.error(line, w.column, format!("G10 {l} P{}: expected a coordinate system 1 to 9, or 0 for the active one", w.raw)),
            None => return diags.error(line, column, format!("G10 {l} without P: expected the coordinate system (P1 = G54, P0 the active one)")),
        };
        // Fanuc's P0 is the external workpiece zero offset, under every system: not modelled.
        if p == 0 && self.dialect.is_fanuc() {
            return diags.error(line, word('P').map_or(column, |w| w.column), format!("G10 {l} P0: the external workpiece zero offset (every work system's) is not modelled"));
        }
        let k_system = if p == 0 { next.system } else { p - 1 };
        // LinuxCNC: "Being in incremental distance mode has no effect on the action of G10"
        // (interp_convert.cc convert_setup; rs274 2.9 sets L2's and L20's values alike under G91).
        if !next.absolute && self.dialect != Dialect::Rs274 {
            return diags.error(line, column, format!("G10 {l} under G91 (offsets relative to the current ones) is not supported: write it under G90"));
        }
        let mut offsets = next.offsets[k_system];
        // LinuxCNC's R: the system's rotation about Z, deg (not in L20, which keeps it).
        let mut r = next.rotation[k_system];
        if let Some(w) = word('R').filter(|_| self.dialect == Dialect::Rs274) {
            if l20 {
                return diags.error(line, w.column, "G10 L20 R: R not allowed in G10 L20 (LinuxCNC)");
            }
            r = w.value * DEG;
        }
        // Either system rotated: X and Y are set together, below, or by the rotation's rules.
        let turned = r != 0.0 || next.rotation_now() != 0.0;
        if l20 && turned {
            // interp_convert.cc convert_setup, L20 in a rotated system: the current point read in
            // system n, and the offset that puts it at the values given, both turned by its R.
            let c = next.point_in_system(next.system, k_system);
            let given = |l: char| word(l).map(|w| w.value * next.unit);
            let old = rotation::rot(c, r);
            let want = rotation::rot([given('X').unwrap_or(c[0]), given('Y').unwrap_or(c[1])], r);
            offsets[0] = old[0] + offsets[0] - want[0];
            offsets[1] = old[1] + offsets[1] - want[1];
        }
        for w in words {
            let Some(k) = AXIS_LETTERS.iter().position(|&c| c == w.letter) else { continue };
            if k < 2 && l20 && turned {
                continue; // above
            } else if k < 3 {
                // L20: the current point, in the offset-free (G53) frame, less the value it is to read.
                offsets[k] = if l20 { next.last[k] + next.datum[k] - next.axis_offset[k] - w.value * next.unit } else { w.value * next.unit };
            } else {
                let u = next.rotary_unit[k - 3];
                let offset = if l20 { next.last[k] - w.value * u } else { w.value * u };
                if offset.abs() > 1e-12 {
                    diags.error(line, w.column, format!("G10 {l} {}{}: rotary-axis work offsets are not modelled (this one would be {:.6} deg)", w.letter, w.raw, offset / DEG));
                }
            }
        }
        // Under G54.1 Pn the system set is not the one in use.
        let active = k_system == next.system && !next.extra_offset;
        if active && turned {
            next.reframe_active(offsets, r);
        } else if active {
            next.move_origin(std::array::from_fn(|k| offsets[k] + next.axis_offset[k]));
        }
        next.offsets[k_system] = offsets;
        next.rotation[k_system] = r;
        next.offsets_given[k_system] = true;
    }

    /// Fanuc's `G10 L20 Pn IP` and Haas' `G10 L20 Pn X Y Z`: the additional work offset n's values
    /// (from the machine zero, as G10 L2's), which `G54.1 Pn` (Fanuc) or `G154 Pn` and `G110`-`G129`
    /// for P1-P20 (Haas) select: Mitsubishi M700V Programming Manual §14.10 (a FANUC-compatible
    /// control), "G10 L20 Pn X__ Y__ Z__", extended workpiece coordinate system offset amount
    /// setting; Haas, "Programmable Offsets": "L20 Auxiliary work coordinate origin for G110-G129",
    /// "P1-P20 G110-G129", "P1-P99 G154 P1-P99", "G10 L20 P2 G90 X100. Y80. Sets offset G111 to
    /// X100. Y80. from the home position". Axes not named keep theirs; absolute values only (G91 adds
    /// to the offset, which no manual at hand says for these); rotary offsets only where zero.
    fn set_extra_offset(&self, words: &[Word], next: &mut Interpreter, line: usize, column: usize, diags: &mut Diags) {
        let word = |l: char| words.iter().find(|w| w.letter == l);
        let (haas, most) = (self.dialect == Dialect::Haas, super::g_codes::extra_offsets_most(self.dialect));
        let p = match word('P') {
            Some(w) if w.value.fract() == 0.0 && (1.0..=most).contains(&w.value) => w.value as u32,
            Some(w) => {
                let range = if haas { "P1 to P99 (G154 P1-P99; P1-P20 also G110-G129)" } else { "P1 to P48 (P300 with the option: G54.1 P1-P300)" };
                return diags.error(line, w.column, format!("G10 L20 P{}: expected {range}, an additional work offset", w.raw));
            }
            None => return diags.error(line, column, "G10 L20 without P: expected the additional work offset it sets (P1 = G54.1 P1)"),
        };
        if !next.absolute {
            return diags.error(line, column, "G10 L20 under G91 (values added to the offset) is not read: write it under G90");
        }
        let mut offsets = self.extra_offset_value(p).unwrap_or([0.0; 3]);
        for w in words {
            let Some(k) = AXIS_LETTERS.iter().position(|&c| c == w.letter) else { continue };
            if k < 3 {
                offsets[k] = w.value * next.unit;
            } else if w.value != 0.0 {
                return diags.error(line, w.column, format!("G10 L20 {}{}: rotary-axis work offsets are not modelled", w.letter, w.raw));
            }
        }
        if next.extra_offset && next.extra_p == p {
            next.move_origin(std::array::from_fn(|k| offsets[k] + next.axis_offset[k]));
        }
        // Known again, if a refused G10 L20 had set it before.
        next.refused_offsets.retain(|(q, _)| *q != p);
        let table = std::sync::Arc::make_mut(&mut next.extra_offsets);
        match table.iter_mut().find(|(q, _)| *q == p) {
            Some(slot) => slot.1 = offsets,
            None => table.push((p, offsets)),
        }
    }

    /// LinuxCNC's `G10 L1 P R`: tool P's radius R in the tool table, for cutter compensation to take
    /// (G-code reference §G10 L1; interp_convert.cc convert_setup_tool: the tool must be in the
    /// table, a block without offsets is refused). Its length and other offsets are stored by
    /// LinuxCNC for `G43`; here the tool length is the machine file's (warned of where not zero).
    fn set_tool(&self, words: &[Word], next: &mut Interpreter, line: usize, column: usize, diags: &mut Diags) {
        let word = |l: char| words.iter().find(|w| w.letter == l);
        let tool = match word('P') {
            Some(w) if w.value >= 0.0 && (w.value - w.value.round()).abs() < 1e-4 && w.value <= u32::MAX as f64 => w.value.round() as u32,
            Some(w) => return diags.error(line, w.column, format!("G10 L1 P{}: expected a tool number", w.raw)),
            None => return diags.error(line, column, "G10 L1 without P: expected the tool number"),
        };
        if next.tool_table.as_ref().is_none_or(|t| t.diameter(tool).is_none()) {
            return diags.error(line, column, format!("G10 L1 P{tool}: Requested tool {tool} not found in the tool table (LinuxCNC; give the machine's with --tool-table)"));
        }
        let offsets: Vec<&Word> = words.iter().filter(|w| AXIS_LETTERS.contains(&w.letter)).collect();
        let r = word('R');
        if offsets.is_empty() && r.is_none() {
            return diags.error(line, column, "G10 L1 without offsets has no effect (LinuxCNC)");
        }
        if let Some(w) = offsets.iter().find(|w| w.value != 0.0) {
            diags.warning(line, w.column, format!("G10 L1 {}{}: tool offsets are not read (a G43 tool length is the machine file's tool_tip_mm)", w.letter, w.raw));
        }
        if let Some(r) = r {
            let unit = next.unit;
            if let Some(table) = next.tool_table.as_mut() {
                std::sync::Arc::make_mut(table).set_diameter(tool, 2.0 * r.value * unit);
            }
        }
    }

    /// Put the program origin at `offset` (RS274: the active work offset, m): the machine stays, so
    /// the current point's program coordinates change by the difference.
    pub(super) fn move_origin(&mut self, offset: [f64; 3]) {
        for k in 0..3 {
            self.last[k] += self.datum[k] - offset[k];
        }
        self.datum = offset;
    }

    /// LinuxCNC's axis offsets (G-code reference §G92, §G52; interp_convert.cc convert_axis_offsets):
    /// `G92` moves the origin so that the current point has the block's coordinates, `G52` sets the
    /// offset itself, `G92.1`/`G92.2` take it away (G92.1 zeroes the copy G92.3 restores). Incremental
    /// mode has no effect on them. Rotary-axis offsets are not modelled: a word that would make one
    /// is an error.
    pub(super) fn axis_offsets(&self, code: &str, words: &[Word], next: &mut Interpreter, line: usize, diags: &mut Diags) {
        if self.dialect.is_fanuc() {
            return self.fanuc_offsets(code, words, next, line, diags);
        }
        let work = next.offsets[next.system];
        let mut offset = next.axis_offset;
        match code {
            "92" | "52" => {
                for w in words {
                    let Some(k) = AXIS_LETTERS.iter().position(|&c| c == w.letter) else { continue };
                    if k >= 3 {
                        let turned = if code == "92" { next.last[k] - w.value * next.rotary_unit[k - 3] } else { w.value * next.rotary_unit[k - 3] };
                        if turned.abs() > 1e-12 {
                            diags.error(line, w.column, format!("G{code} {}{}: rotary-axis offsets are not modelled (this one would be {:.6} deg)", w.letter, w.raw, turned / DEG));
                        }
                        continue;
                    }
                    let v = w.value * next.unit;
                    offset[k] = if code == "92" { next.last[k] + next.datum[k] - work[k] - v } else { v };
                }
                next.axis_offset_kept = offset;
            }
            "92.1" => {
                offset = [0.0; 3];
                next.axis_offset_kept = offset;
            }
            "92.2" => offset = [0.0; 3],
            _ => offset = next.axis_offset_kept, // 92.3
        }
        next.axis_offset = offset;
        next.move_origin(std::array::from_fn(|k| work[k] + offset[k]));
    }
    /// Fanuc's `G92 IP` and `G52 IP` (Haas: G92 only). G92 sets the work coordinate system "so that
    /// the present position of the tool ... become the commanded coordinates", and "the other
    /// workpiece coordinate systems ... move in parallel" (Mitsubishi M700V Programming Manual §14.10,
    /// a FANUC-compatible control; Haas Mill Operator's Manual 96-8000, G92, Setting 33 FANUC: it
    /// "shifts all work coordinate systems (G54-59, G110-129)"); it "cancels any G52 in effect for
    /// the commanded axes" (Haas, ibid.). G52 sets "a local coordinate system ... in all the workpiece
    /// coordinate systems (G54 to G59)", its origin at the position given in the workpiece system,
    /// `G52 X0 Y0 Z0` cancelling it (SINUMERIK ISO Milling 04.07 §3.1, the FANUC dialect; GSK 980MDc
    /// §3.19). Axes not named keep theirs. Both are kept in `axis_offset`, the G52 part also in
    /// `local_offset`. Refused where no manual in reach says what the control does: under G91, under
    /// tool centre point control, under Haas DWO (G254); rotary-axis offsets are not modelled.
    fn fanuc_offsets(&self, code: &str, words: &[Word], next: &mut Interpreter, line: usize, diags: &mut Diags) {
        if code == "92.1" || code == "92.2" {
            // Nothing is shifted (g_codes refuses it otherwise): `G92.1 IP0` presets nothing.
            for w in words.iter().filter(|w| AXIS_LETTERS.contains(&w.letter) && w.value != 0.0) {
                diags.error(line, w.column, format!("G{code} {}{}: expected IP0 (the axes to preset, each with 0)", w.letter, w.raw));
            }
            return;
        }
        let column = words.iter().find(|w| w.letter == 'G' && w.value == if code == "92" { 92.0 } else { 52.0 }).map_or(1, |w| w.column);
        if !words.iter().any(|w| AXIS_LETTERS.contains(&w.letter)) {
            return diags.error(line, column, format!("G{code} without an axis word: expected G{code} X.. Y.. Z.."));
        }
        let why = if !next.absolute {
            "under G91 (incremental)"
        } else if next.tcp {
            "under tool centre point control"
        } else if next.dwo {
            "under dynamic work offsets (G254)"
        } else {
            ""
        };
        if !why.is_empty() {
            return diags.error(line, column, format!("G{code} {why}: how the control sets the coordinate system there is not read (write it under G90, with the mode off)"));
        }
        let work = next.work_offset();
        let mut offset = next.axis_offset;
        for w in words {
            let Some(k) = AXIS_LETTERS.iter().position(|&c| c == w.letter) else { continue };
            // G92 takes where the tool stands: an axis no move has placed stands where the operator
            // left it, which the program does not say.
            if code == "92" && !next.placed[k] {
                diags.error(line, w.column, format!("G92 {}{}: no move before it placed {} (the control takes where the tool stands, which the program does not say): position the axis first (an absolute move, G28 or G53)", w.letter, w.raw, w.letter));
                continue;
            }
            if k >= 3 {
                let turned = if code == "92" { next.last[k] - w.value * next.rotary_unit[k - 3] } else { w.value * next.rotary_unit[k - 3] };
                if turned.abs() > 1e-12 {
                    diags.error(line, w.column, format!("G{code} {}{}: rotary-axis offsets are not modelled (this one would be {:.6} deg)", w.letter, w.raw, turned / DEG));
                }
                continue;
            }
            let v = w.value * next.unit;
            if code == "92" {
                // The current point, in the frame without G92 and G52, less the value it is to read.
                offset[k] = next.last[k] + next.datum[k] - work[k] - v;
                next.local_offset[k] = 0.0;
            } else {
                offset[k] += v - next.local_offset[k];
                next.local_offset[k] = v;
            }
        }
        next.axis_offset = offset;
        next.move_origin(std::array::from_fn(|k| work[k] + offset[k]));
    }
}
