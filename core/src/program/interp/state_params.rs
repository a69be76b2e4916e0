//! LinuxCNC's predefined parameters that read the interpreter's state (LinuxCNC manual §11.4.3.4
//! "Predefined Named Parameters", interp_namedparams.cc `lookup_named_param`; numbered ones of
//! §11.4.2.7: `#5220` the coordinate system, `#5400` the tool, `#5420`-`#5425` the current
//! position): the values this reader knows. The spindle's state (but the speed S last set),
//! coolant, overrides, tool length offsets and the line number are not modelled and stay refused.

use super::Interpreter;
use crate::program::params::StateParameters;
use crate::program::{FeedMode, Motion, Plane};
use crate::units::MM;

impl Interpreter {
    /// Named and numbered parameters of the state now, values in the program's units (deg for
    /// the rotary axes), as LinuxCNC gives them.
    pub(crate) fn state_parameters(&self) -> StateParameters {
        let flag = |b: bool| if b { 1.0 } else { 0.0 };
        let unit = self.unit;
        let mut named: Vec<(&'static str, f64)> = vec![
            ("_metric", flag(self.unit == MM)),
            ("_imperial", flag(self.unit != MM)),
            ("_absolute", flag(self.absolute)),
            ("_incremental", flag(!self.absolute)),
            ("_inverse_time", flag(self.feed_mode == FeedMode::InverseTime)),
            ("_units_per_minute", flag(self.feed_mode == FeedMode::PerMinute && !self.per_revolution())),
            ("_units_per_rev", flag(self.per_revolution())),
            // G54..G59 as 540..590, G59.1..G59.3 as 591..593.
            ("_coord_system", if self.system < 6 { 540.0 + 10.0 * self.system as f64 } else { 585.0 + self.system as f64 }),
            ("_plane", match self.plane {
                Plane::Xy => 170.0,
                Plane::Zx => 180.0,
                Plane::Yz => 190.0,
            }),
            // LinuxCNC's R_PLANE is G99's return to the R point.
            ("_retract_r_plane", flag(self.cycles.to_r)),
            ("_retract_old_z", flag(!self.cycles.to_r)),
            ("_ijk_absolute_mode", flag(self.arc_absolute)),
            ("_lathe_diameter_mode", 0.0),
            ("_lathe_radius_mode", 1.0),
            ("_feed", self.feed_in_program_units().unwrap_or(0.0)),
            // "Return the current value of S, not the actual spindle speed" (0 before any S).
            ("_rpm", self.spindle_speed.unwrap_or(0.0)),
            // The control runs the program (milltask), not a preview.
            ("_task", 1.0),
        ];
        let comp = self.comp.as_ref().and_then(|c| c.on.as_ref());
        named.push(("_ccomp", comp.map_or(400.0, |c| if c.side == crate::program::cutter_comp::Side::Left { 410.0 } else { 420.0 })));
        // The motion mode as a G code times ten; G80 after a cycle's cancel and at the start.
        let motion = match (&self.cycles.active, self.motion) {
            (Some(a), _) => a.kind.code().parse::<f64>().ok().map(|g| g * 10.0),
            (None, Some(Motion::Rapid)) => Some(0.0),
            (None, Some(Motion::Linear)) => Some(10.0),
            (None, Some(Motion::ArcCw)) => Some(20.0),
            (None, Some(Motion::ArcCcw)) => Some(30.0),
            (None, None) => Some(800.0),
        };
        if let Some(m) = motion {
            named.push(("_motion_mode", m));
        }
        let mut numbered = vec![(5220, self.system as f64 + 1.0)];
        let (selected, spindle) = self.tools.known();
        if let Some(t) = selected {
            named.push(("_selected_tool", t as f64));
        }
        if let Some(t) = spindle {
            named.push(("_current_tool", t as f64));
            numbered.push((5400, t as f64));
        }
        // Where the tool stands: LinuxCNC's is the compensated tool's under cutter compensation,
        // which this reader holds as the programmed point: not given then.
        if comp.is_none() {
            let p = self.last;
            let at = [p[0] / unit, p[1] / unit, p[2] / unit, p[3] / self.rotary_unit[0], p[4] / self.rotary_unit[1], p[5] / self.rotary_unit[2]];
            let world = self.world_now().map(|v| v / unit);
            for (k, name) in ["_x", "_y", "_z", "_a", "_b", "_c"].into_iter().enumerate() {
                named.push((name, at[k]));
                numbered.push((5420 + k as u32, at[k]));
            }
            for (k, name) in ["_abs_x", "_abs_y", "_abs_z"].into_iter().enumerate() {
                named.push((name, world[k]));
            }
            // Rotary axes have no offsets here.
            for (k, name) in ["_abs_a", "_abs_b", "_abs_c"].into_iter().enumerate() {
                named.push((name, at[3 + k]));
            }
        }
        StateParameters { named, numbered }
    }

    /// Fanuc's and Haas' modal information of the blocks run so far, the G code groups this reader
    /// holds (FANUC custom macro B, system variables "#4001-#4030: G codes of groups 01-30", #4109 F,
    /// #4119 S, #4120 T; Haas' macro variables #4001-#4021, the group codes, numbered as Fanuc's for these):
    /// 01 motion (6.2 in NURBS mode; not under a canned cycle, whose group is 09), 02 plane, 03 G90/G91, 05 G93/G94, 06
    /// G20/G21, 07 G40 (compensation is refused, so always off), 09 the cycle or G80, 10 G98/G99;
    /// Fanuc's 14 the work offset G54-G59, F in the program's unit and the T selected.
    pub(crate) fn fanuc_modal_information(&self) -> StateParameters {
        let mut numbered: Vec<(u32, f64)> = Vec::with_capacity(12);
        if self.nurbs.is_some() {
            // NURBS interpolation is group 01's G06.2 (B-63324EN §4.17, "G06.2: NURBS interpolation mode").
            numbered.push((4001, 6.2));
        } else if self.cycles.active.is_none() {
            if let Some(g) = match self.motion {
                Some(Motion::Rapid) => Some(0.0),
                Some(Motion::Linear) => Some(1.0),
                Some(Motion::ArcCw) => Some(2.0),
                Some(Motion::ArcCcw) => Some(3.0),
                _ => None,
            } {
                numbered.push((4001, g));
            }
        }
        numbered.push((4002, match self.plane {
            Plane::Xy => 17.0,
            Plane::Zx => 18.0,
            Plane::Yz => 19.0,
        }));
        numbered.push((4003, if self.absolute { 90.0 } else { 91.0 }));
        numbered.push((4005, if self.feed_mode == FeedMode::InverseTime { 93.0 } else if self.per_revolution() { 95.0 } else { 94.0 }));
        numbered.push((4006, if self.unit == MM { 21.0 } else { 20.0 }));
        numbered.push((4007, 40.0));
        numbered.push((4009, self.cycles.active.as_ref().and_then(|a| a.kind.code().parse::<f64>().ok()).unwrap_or(80.0)));
        numbered.push((4010, if self.cycles.to_r { 99.0 } else { 98.0 }));
        if self.dialect == crate::program::Dialect::Fanuc {
            if self.system < 6 && !self.extra_offset {
                numbered.push((4014, 54.0 + self.system as f64));
            }
            if let Some(f) = self.feed_in_program_units() {
                numbered.push((4109, f));
            }
            // #4119 S: the speed the program last set (the control's own before it is not known).
            if let Some(s) = self.spindle_speed {
                numbered.push((4119, s));
            }
            if let (Some(t), _) = self.tools.known() {
                numbered.push((4120, t as f64));
            }
        }
        StateParameters { named: Vec::new(), numbered }
    }
}
