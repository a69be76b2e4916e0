//! The coordinate systems a block states: the programmable frame (`TRANS`/`ATRANS`/`ROT`/`AROT`,
//! [`super::frame`]) put in effect inside the swivel's, and moves in machine coordinates (`SUPA`,
//! `G53`, `G153`). Part of [`super::SinumerikReader`].

use super::frame::{Frame, Statement};
use super::{Diags, Motion, OneShot, Word, DEG};

impl super::SinumerikReader {
    /// Put the programmable frame in effect, inside the swivel's if one is: the interpreter's datum
    /// and rotation follow them (the frame chain's order, K2 §2.4.5.8: `$P_PARTFRAME : ... :
    /// $P_PFRAME`).
    pub(super) fn set_frame(&mut self, frame: Frame) {
        self.frame = frame;
        let whole = match self.swivel {
            Some(s) => Frame { t: s.t + s.r * frame.t, r: s.r * frame.r },
            None => frame,
        };
        let t = whole.t;
        // Without CYCLE800's swivel data (TCARR) the frame turns the axes' coordinates alone until
        // TRAORI places the tool through the kinematics.
        self.interp.set_frame([t.x, t.y, t.z], whole.rotated().then_some(whole.r), self.swivel.is_none());
    }

    /// `TRANS`/`ATRANS`/`ROT`/`AROT` with X Y Z (offsets or angles, degrees) or `RPL=` (a rotation in
    /// the working plane): a block of its own ("Frame statements must be programmed in a separate
    /// NC block", NC programming 12/2019 §2.12).
    pub(super) fn frame_block(&mut self, statement: Statement, words: &[Word], rpl: Option<(f64, usize)>, line: usize, diags: &mut Diags) -> bool {
        let unit = self.interp.unit();
        let mut values = [0.0; 3];
        for w in words {
            match "XYZ".find(w.letter) {
                Some(k) => values[k] = if statement.rotates() { w.value * DEG } else { w.value * unit },
                // A frame's offset or rotation of a rotary axis (TRANS C=10): not read.
                None if matches!(w.letter, 'A' | 'B' | 'C') => diags.error(line, w.column, format!("{}={} in a {} block: a frame's offset of a rotary axis is not read (it changes the axis' positions)", w.letter, w.raw, statement.name())),
                None => diags.error(line, w.column, format!("{}={} in a {} block: a frame statement stands in a block of its own", w.letter, w.raw, statement.name())),
            }
        }
        if let Some((angle, c)) = rpl {
            if !statement.rotates() {
                diags.error(line, c, format!("RPL= in a {} block: only ROT and AROT turn", statement.name()));
            } else if words.iter().any(|w| "XYZ".contains(w.letter)) {
                diags.error(line, c, "RPL= with axis angles: a rotation in the plane or about the axes, not both");
            } else {
                let (_, _, normal) = self.interp.plane().axes();
                values[normal] = angle * DEG;
            }
        }
        let next = self.frame.apply(statement, values);
        self.set_frame(next);
        // TRANS and ROT replace the programmable frame: a refused frame statement's hold ends.
        if matches!(statement, Statement::Trans | Statement::Rot) {
            self.end_holds(statement.name());
        }
        true
    }

    /// `SUPA`, `G53`, `G153`: the block's linear words are machine coordinates (Fundamentals §3.6
    /// "Frame suppression": non-modal, all frames off; SUPA also the handwheel and external offsets,
    /// none of which is modelled); `D0` must have switched the tool's offsets off for a Z position
    /// (with them on, the position is the tool tip's, whose length is not known here).
    pub(super) fn machine_move(&mut self, what: &str, col: usize, motion: Option<Motion>, words: &[Word], length_axis: char, line: usize, diags: &mut Diags) -> bool {
        if self.interp.tcp() {
            diags.error(line, col, format!("{what} under TRAORI: machine coordinates with the transformation on are not modelled (TRAFOOF first)"));
            return false;
        }
        if self.frame.rotated() || self.swivel.is_some() {
            diags.error(line, col, format!("{what} with a rotated frame or a swivelled plane (CYCLE800) in effect is not modelled"));
            return false;
        }
        if let Some(z) = words.iter().find(|w| w.letter == length_axis).filter(|_| self.tool_offsets) {
            diags.error(line, z.column, format!("{what} {length_axis} with the tool's offsets on: the tool tip's machine position needs the tool's length, which the 840D gives to {length_axis} here (write D0 in the block, as posts do)"));
            return false;
        }
        let motion = match motion {
            Some(m @ (Motion::Rapid | Motion::Linear)) => m,
            None => Motion::Rapid,
            Some(_) => {
                diags.error(line, col, format!("{what} with a circle: machine coordinates are reached by G0 or G1"));
                return false;
            }
        };
        let linear = words.iter().any(|w| "XYZ".contains(w.letter));
        let origin = OneShot::machine_origin(&self.interp);
        if origin.is_none() && linear {
            diags.error(line, col, format!("{what}: the machine file places no machine coordinates ([machine_coordinates] zero_mm)"));
            return false;
        }
        self.interp.oneshot = Some(OneShot { motion, absolute: true, axes: origin, own: false });
        true
    }
}
