//! The frame the program's coordinates are in: the datum, a tilted working plane or a Sinumerik
//! frame, tool-centre-point management, and where the machine's axes stand in it (through the
//! kinematics where the coordinates are the tool tip's). Switching any of them leaves the axes
//! where they are and reads the current point anew.

use super::Interpreter;

impl Interpreter {
    /// The tool axis now, in the program's frame (the workpiece's, or the tilted plane's), from the
    /// rotary axes' last positions: None without a machine.
    pub(crate) fn tool_axis_now(&self) -> Option<nalgebra::Vector3<f64>> {
        let m = self.machine.as_ref()?;
        let axis = m.chain.forward(&self.joints_now()).axis;
        Some(self.tilt.map_or(axis, |r| r.transpose() * axis))
    }

    /// Switch tool-centre-point management (Sinumerik `TRAORI` / `TRAFOOF`).
    pub fn set_tcp(&mut self, on: bool) {
        self.tcp = on;
    }

    /// Where a TNC's M91 (machine datum) or M92 (the maker's datum) coordinates start, in the
    /// model's frame; why not, if TCPM is on or the machine file does not place them. (TNC 426 B ISO
    /// §7.3: "M91 and M92 are effective only in the blocks in which they are programmed"; the tool
    /// length is not compensated, so they place the axes.)
    pub(crate) fn tnc_machine_origin(&self, code: u32) -> Result<[f64; 3], String> {
        if self.tcp {
            return Err("machine coordinates under M128 / FUNCTION TCPM: the TNC wants it reset first (M129, FUNCTION RESET TCPM)".into());
        }
        let machine = self.machine_coords().ok_or("the machine file places no machine coordinates ([machine_coordinates] zero_mm)")?;
        let datum = match code {
            92 => machine.m92_datum.ok_or("the machine file gives no M92 datum (machine_coordinates.m92_datum_mm)")?,
            _ => nalgebra::Vector3::zeros(),
        };
        let o = machine.to_axes(datum);
        Ok([o.x, o.y, o.z])
    }

    /// The tilted working plane in effect, if any (columns: its X Y Z in the workpiece).
    pub fn tilt(&self) -> Option<nalgebra::Matrix3<f64>> {
        self.tilt
    }

    /// Tilt the working plane (`None`: untilt). The tool stays: the current point is read anew in
    /// the new plane's coordinates (through the machine's kinematics where X Y Z were its axes).
    pub fn set_tilt(&mut self, tilt: Option<nalgebra::Matrix3<f64>>) {
        let axes = self.axes_now();
        self.tilt = tilt;
        self.read_axes(axes);
    }

    /// The rotary positions in the machine's order (its axes 3 and 4), rad, from the last words.
    pub(crate) fn rot_now(&self) -> [f64; 2] {
        self.rotary_letters.map(|l| l.and_then(|l| "ABC".find(l)).map_or(0.0, |k| self.last[3 + k]))
    }

    /// The machine's axes as they stand: [`Interpreter::axes_now`] and [`Interpreter::rot_now`].
    pub(crate) fn joints_now(&self) -> crate::kinematics::Joints {
        let (axes, rot) = (self.axes_now(), self.rot_now());
        [axes.x, axes.y, axes.z, rot[0], rot[1]]
    }

    /// Where the machine's linear axes stand (model frame, m): X Y Z themselves without TCPM or a
    /// tilted plane, turned by a frame that turns the axes alone ([`Interpreter::axes_frame`]), else
    /// the tool tip placed through the kinematics.
    pub(super) fn axes_now(&self) -> nalgebra::Vector3<f64> {
        let p = nalgebra::Vector3::new(self.last[0], self.last[1], self.last[2]);
        let d = nalgebra::Vector3::from(self.datum);
        if let Some(r) = self.axes_frame() {
            return r * p + d;
        }
        match (&self.machine, self.tilt, self.tcp) {
            (_, None, false) | (None, _, _) => p + d,
            (Some(m), tilt, _) => m.chain.linear_for(&(tilt.map_or(p, |r| r * p) + d), &self.rot_now()),
        }
    }

    /// Where the linear axes go (model frame, m) when the tool backs off along its own axis by
    /// `distance` (m), or as far as the axes' ranges let it (`None`): Heidenhain's `M140 MB`.
    pub(crate) fn retract_target(&self, distance: Option<f64>) -> Result<[f64; 3], String> {
        let m = self.machine.as_ref().ok_or("the tool axis and the travel limits are the machine's: read the program on one (--machine)")?;
        let q = self.joints_now();
        let axes = nalgebra::Vector3::new(q[0], q[1], q[2]);
        let pose = m.chain.forward(&q);
        // The linear axes move the tool along its axis by this much per metre (a unit vector).
        let along = m.chain.linear_for(&(pose.tip + pose.axis), &[q[3], q[4]]) - axes;
        let t = match distance {
            Some(d) => d,
            None => (0..3)
                .filter(|&k| along[k].abs() > 1e-12)
                .map(|k| {
                    let lim = &m.axes[k].limits;
                    ((if along[k] > 0.0 { lim.max } else { lim.min }) - axes[k]) / along[k]
                })
                .fold(f64::INFINITY, f64::min)
                .max(0.0),
        };
        if !t.is_finite() {
            return Err("no linear axis moves along the tool axis".into());
        }
        let to = axes + along * t;
        Ok([to.x, to.y, to.z])
    }

    /// Read the axes standing at `axes` (model frame) in the current coordinates: X Y Z are the axes
    /// without TCPM or a tilted plane (turned back by a frame that turns the axes alone), else the
    /// tool tip (in the plane where tilted).
    pub(super) fn read_axes(&mut self, axes: nalgebra::Vector3<f64>) {
        let d = nalgebra::Vector3::from(self.datum);
        let p = match (&self.machine, self.tilt, self.tcp, self.axes_frame()) {
            (_, _, _, Some(r)) => r.transpose() * (axes - d),
            (_, None, false, _) | (None, _, _, _) => axes - d,
            (Some(m), tilt, _, None) => {
                let rot = self.rot_now();
                let tip = m.chain.forward(&[axes.x, axes.y, axes.z, rot[0], rot[1]]).tip - d;
                tilt.map_or(tip, |r| r.transpose() * tip)
            }
        };
        self.last[..3].copy_from_slice(p.as_slice());
    }

    /// Switch tool-centre-point management and read the current point anew (Sinumerik `TRAORI` /
    /// `TRAFOOF`): the axes stay, their meaning changes, so an axis a later block does not name
    /// stays where it physically is.
    pub fn switch_tcp(&mut self, on: bool) {
        let axes = self.axes_now();
        self.tcp = on;
        self.read_axes(axes);
    }

    /// Set the frame in effect: `datum` (m) and a rotation (`None`: none), as the Sinumerik frames
    /// `TRANS`, `ROT` and their additive forms make them; the current point is read anew in it (the
    /// axes stay). `axes_only`: without TCPM the rotation turns the linear axes' coordinates alone
    /// ([`Interpreter::axes_frame`]), rather than placing the tool tip through the kinematics.
    pub fn set_frame(&mut self, datum: [f64; 3], tilt: Option<nalgebra::Matrix3<f64>>, axes_only: bool) {
        let axes = self.axes_now();
        self.datum = datum;
        self.tilt = tilt;
        self.frame_axes_only = axes_only;
        self.read_axes(axes);
    }

    /// The rotation in effect turns only the linear axes' coordinates (a Sinumerik frame without
    /// TRAORI or CYCLE800; Fundamentals 12/2019 §"Frames": a frame maps the workpiece coordinate
    /// system onto the basic one, which without a transformation is the axes').
    pub(crate) fn axes_frame(&self) -> Option<nalgebra::Matrix3<f64>> {
        self.tilt.filter(|_| self.frame_axes_only && !self.tcp)
    }

    /// A tilted working plane that places the tool tip: its coordinates are the workpiece's, which
    /// the control puts the axes at through the kinematics (a TNC's PLANE, CYCLE800, G68.2), where
    /// a frame of the linear axes alone ([`Self::axes_frame`]) turns their coordinates only.
    pub(crate) fn tilt_places_tip(&self) -> bool {
        self.tilt.is_some() && self.axes_frame().is_none()
    }

    /// The datum shift in effect, m.
    pub fn datum(&self) -> [f64; 3] {
        self.datum
    }

    /// Shift the program origin (the TNC's cycle 7), m: program coordinates + datum = coordinates
    /// about the rotary axes. The machine stays: the tool's position is the new origin's from here on
    /// (in a tilted plane, the plane's coordinates of it), so an incremental move goes from where it
    /// stands, and axes a later block does not name stay.
    pub fn set_datum(&mut self, datum: [f64; 3]) {
        let moved = nalgebra::Vector3::from(self.datum) - nalgebra::Vector3::from(datum);
        let moved = self.tilt.map_or(moved, |r| r.transpose() * moved);
        for k in 0..3 {
            self.last[k] += moved[k];
        }
        self.datum = datum;
    }
}
