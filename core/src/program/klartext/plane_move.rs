//! `PLANE ... MOVE DIST.. [F..]`: the compensating move of the tilt (TNC 620 User's Manual 10/2017,
//! "The PLANE function", automatic positioning, and TNC 320 User's Manual 5/2013 p. 366: "The TNC
//! tilts the tool (or table) relative to the tool tip. The DIST parameter shifts the center of
//! rotation of the positioning movement relative to the current position of the tool tip"; "If the
//! tool is already at the given distance to the workpiece before positioning, then the tool is at
//! the same relative position after positioning"). The centre is DIST below the tip along the tool
//! axis, fixed on the workpiece while the rotary axes turn; the tip ends DIST above it along the new
//! tool axis. Made as tool-tip chords (TCPM blocks) within 1 µm and 0.001 deg of that motion.


use super::exec::Exec;
use super::*;
use crate::program::chords::{Chording, CHORD_TOLERANCE_M, CHORD_TOLERANCE_RAD};
use crate::program::interp::{Dimension, Interpreter, Word};
use crate::program::Block;
use crate::units::DEG;

impl Exec {
    /// The MOVE from where the tool stands to the rotary positions `rot` (machine order, rad), the
    /// blocks to `out`, in the frame in effect before the plane; false (said) if it cannot be made.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn plane_move(&mut self, dist: &KWord<'_>, feed: &FeedWord<'_>, rot: [f64; 2], letters: &[char; 2], machine: &crate::machine::Machine, s: &Stmt<'_>, interp: &mut Interpreter, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        let unit = interp.unit();
        let Some(d) = self.value(dist, s.line, diags) else { return false };
        // The TNC's input range for a length: at most 99 999.9999.
        if !(d.abs() <= 99_999.999_9) {
            diags.error(s.line, dist.col, "PLANE ... MOVE DIST: a distance of -99999.9999 to +99999.9999");
            return false;
        }
        let Some(k) = letters.map(|l| "ABC".find(l)).iter().copied().collect::<Option<Vec<usize>>>() else {
            diags.error(s.line, s.col, "PLANE ... MOVE: the machine's rotary axes are not named A, B or C");
            return false;
        };
        let d = d * unit;
        let q0 = interp.joints_now();
        let rot0 = [q0[3], q0[4]];
        // M126: a modulo axis goes the shorter way, as the TURN block's words do.
        let rot = [0, 1].map(|j| if interp.shortest_way(k[j]) { crate::kinematics::unwrap_near(rot[j], rot0[j]) } else { rot[j] });
        let pose0 = machine.chain.forward(&q0);
        let centre = pose0.tip - pose0.axis * d;
        let datum = nalgebra::Vector3::from(interp.datum());
        let tilt = interp.tilt();
        let rot_units = [interp.rotary_unit(k[0]), interp.rotary_unit(k[1])];
        // The motion by s from 0 to 1: X Y Z the tip in the program's frame (program units), the
        // two rotary axes (their units), the others as they stand.
        let here = interp.position();
        let at = |t: f64| {
            let r = [rot0[0] + t * (rot[0] - rot0[0]), rot0[1] + t * (rot[1] - rot0[1])];
            let axis = machine.chain.forward(&[q0[0], q0[1], q0[2], r[0], r[1]]).axis;
            let tip = centre + axis * d - datum;
            let p = tilt.map_or(tip, |m| m.transpose() * tip);
            let mut v = [p.x / unit, p.y / unit, p.z / unit, here[3] / DEG, here[4] / DEG, here[5] / DEG];
            for j in 0..2 {
                v[3 + k[j]] = r[j] / rot_units[j];
            }
            v
        };
        let mut axes = [true, true, true, false, false, false];
        let mut tolerance = [CHORD_TOLERANCE_M / unit; 6];
        for j in 0..2 {
            axes[3 + k[j]] = true;
            tolerance[3 + k[j]] = CHORD_TOLERANCE_RAD / rot_units[j];
        }
        let mut points = Vec::new();
        if !(Chording { axes, tolerance }).chords(&at, 0.0, 1.0, &mut points) {
            diags.error(s.line, s.col, format!("PLANE ... MOVE: the compensating move {}", Chording::too_many()));
            return false;
        }
        let Ok(feed_word) = self.feed_word(feed, s.line, diags) else { return false };
        // The chords are the tool tip's (TCPM on for them); made whole or not at all.
        let saved = interp.clone();
        let tcp = interp.tcp();
        interp.switch_tcp(true);
        let mut made = Vec::with_capacity(points.len());
        for (n, p) in points.iter().enumerate() {
            let g = if feed_word.is_some() { 1.0 } else { 0.0 };
            let mut words: Vec<Word> = vec![Word { letter: 'G', value: g, raw: if g == 1.0 { "1".into() } else { "0".into() }, column: s.col, dimension: Dimension::Modal }];
            for j in (0..6).filter(|j| axes[*j]) {
                words.push(Word { letter: ['X', 'Y', 'Z', 'A', 'B', 'C'][j], value: p[j], raw: format!("{}", p[j]).into(), column: s.col, dimension: Dimension::Absolute });
            }
            if let Some((v, raw, col)) = feed_word.as_ref().filter(|_| n == 0) {
                words.push(Word { letter: 'F', value: *v, raw: raw.clone(), column: *col, dimension: Dimension::Modal });
            }
            match interp.block_one(&words, s.line, s.col, s.number, diags) {
                Some(b) => made.push(b),
                None => {
                    *interp = saved;
                    return false;
                }
            }
        }
        interp.switch_tcp(tcp);
        out.extend(made);
        true
    }
}
