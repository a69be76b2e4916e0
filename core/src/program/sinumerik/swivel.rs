//! `CYCLE800`, the 840D's swivel cycle: a tilted working plane through the machine's swivel data
//! set, and the rotary axes turned to it (SINUMERIK Operate Milling Operating Manual 6FC5398-7CP41
//! 08/2018 §10.6 "Swivel plane"; the parameters `CYCLE800(_FR, _TC, _ST, _MODE, _X0, _Y0, _Z0, _A, _B,
//! _C, _X1, _Y1, _Z1, _DIR, _FR_I [, _DMODE])` and their coding as Siemens' posts and other readers
//! write them, the manual's page with the numeric table not being at hand):
//! - `_FR` the retraction before swivelling: 0 none, 1 machine Z, 2 machine Z then X and Y (to the
//!   data set's retract position), 4 and 5 in the tool's direction (not read);
//! - `_TC` the data set's name, `"0"` deselects; `_ST` ones digit 0 a new plane, 1 additive (the
//!   higher digits, tool-tip follow-up and the like, not read);
//! - `_MODE` bits 7-6 the swivel mode: 00 axis by axis, each 2-bit field from bit 0 naming the axis
//!   (01 X, 10 Y, 11 Z) the first, second and third rotation turn about, each "based on the previous
//!   rotation" (57 is X, then Y', then Z''); 11 (192) the rotary axes' positions directly; solid and
//!   projection angles (01, 10) are not read;
//! - `X0 Y0 Z0` the reference point of the rotation, `X1 Y1 Z1` the zero point of the rotated plane:
//!   a point of the plane is `X0 + R (X1 + p)` in the frame before (the screen form's "reference
//!   point for rotation" and "zero point of rotated surface"; ASSUMED: the cycle keeps the zero at the
//!   reference point, as the FTV5 program's machining at the plane's Z 0 shows);
//! - `_DIR` which of the two solutions: -1 the lower, +1 the higher value of the direction
//!   reference axis (the data set's; here the machine file's, by default the tilting axis), 0 the
//!   frame only, the axes not turned. Pure.

use super::lex::Arg;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// A swivel as the cycle's call gives it (lengths in the program's unit, angles in degrees).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Call {
    /// `_FR`: 0 no retraction, 1 machine Z, 2 machine Z then X and Y.
    pub retract: u8,
    pub data_set: String,
    pub additive: bool,
    /// The rotation (axis by axis), or the rotary axes' positions (direct mode), degrees.
    pub turn: Turn,
    pub x0: Vector3<f64>,
    pub x1: Vector3<f64>,
    /// `_DIR`: -1, 0 or +1.
    pub direction: i8,
}

/// What the angles of a call are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Turn {
    /// Axis by axis: the frame's rotation.
    Frame(Matrix3<f64>),
    /// The rotary axes' positions in the data set's order (its axis 1, axis 2), degrees.
    Direct([f64; 2]),
}

fn get(args: &[Arg], k: usize) -> &Arg {
    args.get(k).unwrap_or(&Arg::Empty)
}

fn value(args: &[Arg], k: usize, name: &str) -> Result<f64, String> {
    get(args, k).value().map_err(|e| format!("{name}: {e}"))
}

/// The rotation `_MODE` (axis by axis) and the three angles (degrees) make: each turn about an axis
/// of the frame the turns before it left.
pub(crate) fn axis_by_axis(mode: u32, angles: [f64; 3]) -> Result<Matrix3<f64>, String> {
    let mut r = Matrix3::identity();
    let mut used = [false; 3];
    for (k, angle) in angles.iter().enumerate() {
        let field = (mode >> (2 * k)) & 0b11;
        if field == 0 || used[field as usize - 1] {
            return Err(format!("_MODE={mode}: the axis sequence (bits 0-5) does not name X, Y and Z once each"));
        }
        used[field as usize - 1] = true;
        let axis = Vector3::ith(field as usize - 1, 1.0);
        r *= Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle.to_radians()).into_inner();
    }
    Ok(r)
}

/// Read a call's arguments: `None` deselects the swivel (`CYCLE800()`, or `_TC` "0").
pub(crate) fn decode(args: &[Arg]) -> Result<Option<Call>, String> {
    if args.iter().all(|a| *a == Arg::Empty) {
        return Ok(None);
    }
    let data_set = match get(args, 1) {
        Arg::Text(t) => t.trim().to_string(),
        Arg::Empty => String::new(),
        Arg::Value(v) => return Err(format!("_TC={v}: expected the swivel data set's name in quotes")),
    };
    if data_set == "0" {
        return Ok(None);
    }
    let retract = match value(args, 0, "_FR")? {
        v if v == 0.0 || v == 1.0 || v == 2.0 => v as u8,
        v => return Err(format!("_FR={v}: only no retraction (0) and the machine axes' retraction (1: Z, 2: Z then X Y) are read")),
    };
    let st = value(args, 2, "_ST")?;
    if st.fract() != 0.0 || !(0.0..=1.0).contains(&st) {
        return Err(format!("_ST={st}: only a new (0) or additive (1) plane is read (the higher digits: tool-tip follow-up, aligning the tool, are not)"));
    }
    let mode = value(args, 3, "_MODE")?;
    if mode.fract() != 0.0 || !(0.0..=255.0).contains(&mode) {
        return Err(format!("_MODE={mode}: expected a bit-coded 0 to 255"));
    }
    let mode = mode as u32;
    let angles = [value(args, 7, "_A")?, value(args, 8, "_B")?, value(args, 9, "_C")?];
    let turn = match mode >> 6 {
        0 => Turn::Frame(axis_by_axis(mode, angles)?),
        3 => Turn::Direct([angles[0], angles[1]]),
        _ => return Err(format!("_MODE={mode}: solid or projection angles are not read (axis by axis and direct are)")),
    };
    let v3 = |k: usize, n: [&str; 3]| -> Result<Vector3<f64>, String> { Ok(Vector3::new(value(args, k, n[0])?, value(args, k + 1, n[1])?, value(args, k + 2, n[2])?)) };
    let (x0, x1) = (v3(4, ["_X0", "_Y0", "_Z0"])?, v3(10, ["_X1", "_Y1", "_Z1"])?);
    let direction = match value(args, 13, "_DIR")? {
        d if d == -1.0 || d == 0.0 || d == 1.0 => d as i8,
        d => return Err(format!("_DIR={d}: expected -1, 0 or +1")),
    };
    Ok(Some(Call { retract, data_set, additive: st == 1.0, turn, x0, x1, direction }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The FTV5 program's first call (`CYCLE800( 1, " R_DATA", 0, 57, 0, 0, 1.433, 28.5492, -25.5438,
    /// 90., 0, 0, 0, 1, )`): mode 57 is X, then Y', then Z'': the plane's Z is Rx(28.5492) Ry(-25.5438)
    /// e_z = (sin b, -sin a cos b, cos a cos b), worked by hand: (-0.431201, -0.431200, 0.792548), 37.576
    /// deg from Z at an azimuth of -135 deg (a CAM plane's signature: equal X and Y).
    #[test]
    fn mode_57_turns_about_x_then_the_new_y_then_the_new_z() {
        let args: Vec<Arg> = [Some(1.0), None, Some(0.0), Some(57.0), Some(0.0), Some(0.0), Some(1.433), Some(28.5492), Some(-25.5438), Some(90.0), Some(0.0), Some(0.0), Some(0.0), Some(1.0), None]
            .iter()
            .enumerate()
            .map(|(k, v)| if k == 1 { Arg::Text(" R_DATA".into()) } else { v.map_or(Arg::Empty, Arg::Value) })
            .collect();
        let c = decode(&args).unwrap().unwrap();
        assert_eq!((c.retract, c.data_set.as_str(), c.direction, c.additive), (1, "R_DATA", 1, false));
        let Turn::Frame(r) = c.turn else { panic!() };
        let (a, b) = (28.5492f64.to_radians(), (-25.5438f64).to_radians());
        let z = Vector3::new(b.sin(), -a.sin() * b.cos(), a.cos() * b.cos());
        assert!((r.column(2) - z).norm() < 1e-12, "{}", r.column(2));
        assert!((z - Vector3::new(-0.431201, -0.431200, 0.792548)).norm() < 2e-6);
        // 27 is Z, then Y', then X''.
        let zyx = axis_by_axis(27, [30.0, 20.0, 10.0]).unwrap();
        let want = Rotation3::from_axis_angle(&Vector3::z_axis(), 30f64.to_radians()) * Rotation3::from_axis_angle(&Vector3::y_axis(), 20f64.to_radians()) * Rotation3::from_axis_angle(&Vector3::x_axis(), 10f64.to_radians());
        assert!((zyx - want.into_inner()).norm() < 1e-12);
        assert!(axis_by_axis(21, [0.0; 3]).is_err(), "X X X");
        assert_eq!(decode(&[]).unwrap(), None);
        assert_eq!(decode(&[Arg::Empty, Arg::Text("0".into())]).unwrap(), None);
    }
}
