//! The programmable frame `$P_PFRAME` as the 840D chains it (Programming Manual NC programming
//! 6FC5398-2EP40 12/2019 §2.12 "Frames": `TRANS`, `ROT` replace the frame, "old instructions for
//! offsetting, rotation, scaling factor, mirroring" cleared; `ATRANS`, `AROT` are "additive",
//! built on the frame in effect; ROT with several axes turns about Z, then Y', then X'' (MD10600
//! `FRAME_ANGLE_INPUT_MODE` = 1, RPY, ASSUMED: the reset value is the machine maker's); `RPL` turns
//! in the working plane). A point of the frame is `t + R p` in the settable frame.

use nalgebra::{Matrix3, Rotation3, Vector3};

/// A programmable frame: its offset `t` and rotation `r` (columns: the frame's X Y Z).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Frame {
    pub t: Vector3<f64>,
    pub r: Matrix3<f64>,
}

impl Default for Frame {
    fn default() -> Self {
        Frame { t: Vector3::zeros(), r: Matrix3::identity() }
    }
}

/// The frame statements.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Statement {
    Trans,
    Atrans,
    Rot,
    Arot,
}

impl Statement {
    pub(crate) fn from_name(name: &str) -> Option<Statement> {
        Some(match name {
            "TRANS" => Statement::Trans,
            "ATRANS" => Statement::Atrans,
            "ROT" => Statement::Rot,
            "AROT" => Statement::Arot,
            _ => return None,
        })
    }

    pub(crate) fn name(self) -> &'static str {
        match self {
            Statement::Trans => "TRANS",
            Statement::Atrans => "ATRANS",
            Statement::Rot => "ROT",
            Statement::Arot => "AROT",
        }
    }

    /// Whether the statement rotates (its X Y Z are angles).
    pub(crate) fn rotates(self) -> bool {
        matches!(self, Statement::Rot | Statement::Arot)
    }
}

/// The rotation of `ROT X=a Y=b Z=c` (degrees as radians): about Z, then the new Y, then the newest X.
pub(crate) fn rpy(angles: [f64; 3]) -> Matrix3<f64> {
    let [a, b, c] = angles;
    (Rotation3::from_axis_angle(&Vector3::z_axis(), c) * Rotation3::from_axis_angle(&Vector3::y_axis(), b) * Rotation3::from_axis_angle(&Vector3::x_axis(), a)).into_inner()
}

impl Frame {
    /// The frame after `statement` with `values` (offsets in m, or angles in rad about X Y Z; a value
    /// not written is 0): TRANS and ROT replace the frame, ATRANS moves it along its own axes, AROT
    /// turns it about its own axes.
    pub(crate) fn apply(&self, statement: Statement, values: [f64; 3]) -> Frame {
        let v = Vector3::from(values);
        match statement {
            Statement::Trans => Frame { t: v, r: Matrix3::identity() },
            Statement::Atrans => Frame { t: self.t + self.r * v, r: self.r },
            Statement::Rot => Frame { t: Vector3::zeros(), r: rpy(values) },
            Statement::Arot => Frame { t: self.t, r: self.r * rpy(values) },
        }
    }

    /// Whether the frame turns (its rotation is not the identity, to 1e-12).
    pub(crate) fn rotated(&self) -> bool {
        (self.r - Matrix3::identity()).abs().max() > 1e-12
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The manual's translation example (§2.12: `TRANS X10 Y10 Z10`, `ATRANS X5 Y5` is X15 Y15 Z10),
    /// an AROT chain of the Spinner program (`AROT X-90.`, `AROT Z90.`: the frame's Z is the workpiece's
    /// +Y and its X the workpiece's -Z, Rx(-90) Rz(90) worked by hand) and ROT's order (Z, then Y', then X'').
    #[test]
    fn frames_chain_as_the_manual_says() {
        let f = Frame::default().apply(Statement::Trans, [10.0, 10.0, 10.0]).apply(Statement::Atrans, [5.0, 5.0, 0.0]);
        assert_eq!(f.t, Vector3::new(15.0, 15.0, 10.0));
        let d = std::f64::consts::FRAC_PI_2;
        let f = Frame::default().apply(Statement::Arot, [-d, 0.0, 0.0]).apply(Statement::Arot, [0.0, 0.0, d]);
        let close = |a: Vector3<f64>, b: [f64; 3]| (a - Vector3::from(b)).norm() < 1e-12;
        assert!(close(f.r.column(2).into(), [0.0, 1.0, 0.0]), "{}", f.r);
        assert!(close(f.r.column(0).into(), [0.0, 0.0, -1.0]), "{}", f.r);
        // ATRANS after a rotation moves along the turned axes.
        let g = f.apply(Statement::Atrans, [1.0, 0.0, 0.0]);
        assert!(close(g.t, [0.0, 0.0, -1.0]));
        // ROT replaces the offset too; ROT Z90 Y90 turns about Z first.
        let h = g.apply(Statement::Rot, [0.0, d, d]);
        assert_eq!(h.t, Vector3::zeros());
        assert!(close(h.r.column(2).into(), [0.0, 1.0, 0.0]), "Rz(90) Ry(90) e_z = Rz(90) e_x = e_y: {}", h.r);
        assert!(!Frame::default().apply(Statement::Trans, [1.0, 2.0, 3.0]).rotated() && h.rotated());
    }
}
