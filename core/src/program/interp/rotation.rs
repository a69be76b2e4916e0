//! LinuxCNC's rotation of a coordinate system about Z (`G10 L2 Pn R-`, G-code reference §G10 L2:
//! "R - rotation around the Z axis"). Its interpreter keeps the current point in the rotated
//! program frame and the canonical layer places the axes (emccanon.cc `rotate_and_offset_pos`):
//! machine XY = rot(p + G92 offset, R) + G5x offset. The same order here: the interpreter reads in
//! the program frame, and a block leaves it in the workpiece's ([`Interpreter::to_world`]).

use super::Interpreter;
use crate::program::{ArcSpec, Block, Plane};

/// `v` turned by `angle` (rad) about Z, counter-clockwise (rs274ngc's `rotate`).
pub(crate) fn rot(v: [f64; 2], angle: f64) -> [f64; 2] {
    if angle == 0.0 {
        return v;
    }
    let (s, c) = angle.sin_cos();
    [v[0] * c - v[1] * s, v[0] * s + v[1] * c]
}

impl Interpreter {
    /// The active system's rotation about Z, rad (0 but where a LinuxCNC program set one).
    pub(crate) fn rotation_now(&self) -> f64 {
        self.rotation[self.system]
    }

    /// Where the current point stands in X and Y without the work offset of system `from` turned in
    /// and added: rot(p + G92 offset, R) + offset (the canonical layer's position), m.
    pub(super) fn machine_xy(&self, from: usize) -> [f64; 2] {
        let g5x = self.offsets[from];
        let t = rot([self.last[0] + self.axis_offset[0], self.last[1] + self.axis_offset[1]], self.rotation[from]);
        [t[0] + g5x[0], t[1] + g5x[1]]
    }

    /// The current point's X Y read in system `to` (interp_find.cc `find_current_in_system`): the
    /// machine stays, p = rot(machine - offset, -R) - G92 offset, the active system's being `from`.
    pub(super) fn point_in_system(&self, from: usize, to: usize) -> [f64; 2] {
        let m = self.machine_xy(from);
        let (g5x, g92) = (self.offsets[to], self.axis_offset);
        let p = rot([m[0] - g5x[0], m[1] - g5x[1]], -self.rotation[to]);
        [p[0] - g92[0], p[1] - g92[1]]
    }

    /// The current point read in system `to`, which becomes the active one's ([`Self::point_in_system`]).
    pub(super) fn current_into_system(&mut self, from: usize, to: usize) {
        let (g5x, g92) = (self.offsets[to], self.axis_offset);
        let p = self.point_in_system(from, to);
        (self.last[0], self.last[1]) = (p[0], p[1]);
        self.last[2] += self.offsets[from][2] - g5x[2];
        self.datum = std::array::from_fn(|k| g5x[k] + g92[k]);
    }

    /// The active system's offset set to `g5x` and its rotation to `r` (interp_convert.cc
    /// convert_setup on the system in use): p = rot(rot(p, R) + old offset - offset, -r). The G92
    /// offset is not turned in here, as LinuxCNC does not turn it.
    pub(super) fn reframe_active(&mut self, g5x: [f64; 3], r: f64) {
        let k = self.system;
        let (old, r_old) = (self.offsets[k], self.rotation[k]);
        let machine = self.machine_xy(k);
        let t = rot([self.last[0], self.last[1]], r_old);
        let p = rot([t[0] + old[0] - g5x[0], t[1] + old[1] - g5x[1]], -r);
        (self.last[0], self.last[1]) = (p[0], p[1]);
        self.last[2] += old[2] - g5x[2];
        self.offsets[k] = g5x;
        self.rotation[k] = r;
        self.datum = std::array::from_fn(|k| g5x[k] + self.axis_offset[k]);
        // Under a G92 offset the point read so is not where the machine stands: its next move goes there.
        let now = self.machine_xy(k);
        self.xy_apart |= (now[0] - machine[0]).abs() > 1e-12 || (now[1] - machine[1]).abs() > 1e-12;
    }

    /// A block made in the rotated program frame, placed in the workpiece's: X Y turned by the
    /// active rotation (both are set: [`Interpreter::fill_xy`]), the datum the offset plus the turned
    /// G92 offset, an arc's centre turned and, off the XY plane, its frame the turned one.
    pub(crate) fn to_world(&self, b: &mut Block) {
        let r = self.rotation_now();
        if r == 0.0 {
            return;
        }
        if let (Some(x), Some(y)) = (b.targets.x, b.targets.y) {
            let t = rot([x, y], r);
            (b.targets.x, b.targets.y) = (Some(t[0]), Some(t[1]));
        }
        let (g5x, g92) = (self.offsets[self.system], rot([self.axis_offset[0], self.axis_offset[1]], r));
        b.datum = [g5x[0] + g92[0], g5x[1] + g92[1], b.datum[2]];
        if let Some(a) = b.arc.as_mut() {
            let c = rot([a.centre[0], a.centre[1]], r);
            (a.centre[0], a.centre[1]) = (c[0], c[1]);
            if a.plane != Plane::Xy {
                let z = nalgebra::Rotation3::from_axis_angle(&nalgebra::Vector3::z_axis(), r);
                a.frame = Some(ArcSpec::frame_of(z.matrix()));
            }
        }
    }

    /// Where the current point stands in the workpiece (LinuxCNC's machine coordinates, the G53
    /// frame), m: X Y as the canonical layer places them, Z with both offsets.
    pub(crate) fn world_now(&self) -> [f64; 3] {
        let xy = self.machine_xy(self.system);
        [xy[0], xy[1], self.last[2] + self.offsets[self.system][2] + self.axis_offset[2]]
    }

    /// A point of the workpiece frame read in the program's (interp_find.cc find_relative):
    /// p = rot(w - offset, -R) - G92 offset, m.
    pub(crate) fn program_of_world(&self, w: [f64; 3]) -> [f64; 3] {
        let (g5x, g92) = (self.offsets[self.system], self.axis_offset);
        let p = rot([w[0] - g5x[0], w[1] - g5x[1]], -self.rotation_now());
        [p[0] - g92[0], p[1] - g92[1], w[2] - g5x[2] - g92[2]]
    }

    /// Under a rotated coordinate system (LinuxCNC's `G10 L2 R`) a move of X or Y alone is one of
    /// both in the workpiece: the other, where the block leaves it, written into `b` (its
    /// program-frame targets) so that [`to_world`] turns the point. (Fanuc's `G68` fills its own
    /// plane's pair where it places the block.) Where the interpreter's X Y are not the machine's
    /// (`xy_apart`), any move names both: LinuxCNC's canonical moves carry every axis
    /// (interp_convert.cc convert_straight), so the machine goes to the interpreter's point, in a Z
    /// move too.
    ///
    /// [`to_world`]: Interpreter::to_world
    pub(crate) fn fill_xy(&mut self, b: &mut Block) {
        let apart = self.xy_apart && !b.targets.is_empty();
        if apart || self.rotation_now() != 0.0 && (b.targets.x.is_some() || b.targets.y.is_some()) {
            b.targets.x = b.targets.x.or(Some(self.last[0]));
            b.targets.y = b.targets.y.or(Some(self.last[1]));
            self.xy_apart = false;
        }
    }
}
