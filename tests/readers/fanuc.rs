//! Fanuc's and Haas' coordinate system rotation `G68 X Y R` / `G69` (and in the XZ and YZ planes),
//! against the manuals' rule computed here: a programmed point P goes to C + rot(P - C, R); Fanuc's
//! incremental moves before the first absolute one turn about the tool's position at G68
//! (B-62764EN §15.10).

use super::*;

/// `p` turned about `c` by `deg` counter-clockwise.
fn about(c: [f64; 2], deg: f64, p: [f64; 2]) -> [f64; 2] {
    let (s, k) = deg.to_radians().sin_cos();
    [c[0] + (p[0] - c[0]) * k - (p[1] - c[1]) * s, c[1] + (p[0] - c[0]) * s + (p[1] - c[1]) * k]
}

/// The X Y each move of `p` ends at (mm), in order.
fn xy(p: &Program) -> Vec<[f64; 2]> {
    ends(p).into_iter().map(|e| [e[0], e[1]]).collect()
}

/// Moves, an arc and a drilling cycle's hole under `G68 X10 Y5 R30`, then `G69`: each end (and
/// the arc's centre) where the rule puts it; the tool stays where it is at G68 and G69.
#[test]
fn fanuc_g68_turns_the_program_about_its_centre() {
    let text = "%\nO1000\nG21 G90 G17 G94\nG0 X10. Y0. Z5.\nG1 F500.\nG68 X10. Y5. R30.\nG91 G1 X10.\nG90 G1 X20. Y5.\nG1 Y15.\nG91 X-10.\nG90 G2 X20. Y15. I5. J0.\nG98 G81 X15. Y5. Z-2. R2.\nG80\nG69\nG90 G1 X0. Y0.\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let (c, t) = ([10.0, 5.0], [10.0, 0.0]);
    let want = [
        [10.0, 0.0],                      // G0 X10 Y0, before the rotation
        about(t, 30.0, [20.0, 0.0]),      // G91 X10 before any absolute move: about the tool's position
        about(c, 30.0, [20.0, 5.0]),      // G90 X20 Y5
        about(c, 30.0, [20.0, 15.0]),     // Y15
        about(c, 30.0, [10.0, 15.0]),     // G91 X-10: from the programmed point
        about(c, 30.0, [20.0, 15.0]),     // the arc's end
        about(c, 30.0, [15.0, 5.0]),      // the hole: positioning,
        about(c, 30.0, [15.0, 5.0]),      // to R,
        about(c, 30.0, [15.0, 5.0]),      // to the bottom,
        about(c, 30.0, [15.0, 5.0]),      // and back to the initial level (G98)
        [0.0, 0.0],                       // after G69: as programmed
    ];
    let got = xy(&p);
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!((g[0] - w[0]).abs() < 1e-9 && (g[1] - w[1]).abs() < 1e-9, "move {k}: {g:?}, the rule {w:?}");
    }
    let arc = p.blocks.iter().find_map(|b| b.arc.as_ref()).expect("the G2");
    let centre = about(c, 30.0, [15.0, 15.0]);
    assert!((arc.centre[0] / MM - centre[0]).abs() < 1e-9 && (arc.centre[1] / MM - centre[1]).abs() < 1e-9, "{arc:?}");
}

/// In the XZ and YZ planes (`G18 G68 Z X R`, `G19 G68 Y Z R`; FANUC B-64113EN §11.12: "G17 (G18 or G19): Select the plane
/// that contains the figure to be rotated", the centre "two of the X_, Y_, and Z_ axes that correspond
/// to the current plane selected"; Haas: "Only the values in the plane of rotation are rotated"), the
/// rule computed here in the plane's own coordinates (first axis, second axis: Z X in G18, Y Z in
/// G19), counter-clockwise from the first towards the second; the third axis as programmed. An axis
/// word off the plane in the G68 block is refused.
#[test]
fn fanuc_g68_turns_in_the_xz_and_yz_planes() {
    // G18: (Z, X) about (Z5, X10) by 30 deg; Y untouched.
    let p = read("%
O1000
G21 G90 G18 G94
G0 X10. Y3. Z0.
G1 F500.
G68 Z5. X10. R30.
G1 Z20. X10. Y7.
G1 X15.
G69
G1 X0. Z0.
M30
%
", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let ends: Vec<[f64; 3]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1], a[2]]).collect();
    let zx = |z: f64, x: f64| about([5.0, 10.0], 30.0, [z, x]);
    let (a, b) = (zx(20.0, 10.0), zx(20.0, 15.0));
    let want = [[10.0, 3.0, 0.0], [a[1], 7.0, a[0]], [b[1], 7.0, b[0]], [0.0, 7.0, 0.0]];
    assert_eq!(ends.len(), want.len(), "{ends:?}");
    for (k, (g, w)) in ends.iter().zip(&want).enumerate() {
        assert!((0..3).all(|i| (g[i] - w[i]).abs() < 1e-9), "G18 move {k}: {g:?}, the rule {w:?}");
    }
    // G19: (Y, Z) about the tool's position (no centre words: Y0 Z0) by -90 deg: Y10 goes to Z-10.
    let p = read("%
O1000
G21 G90 G19 G94
G0 X1. Y0. Z0.
G68 R-90.
G1 Y10. F500.
M30
%
", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let last = end_points(&p).last().unwrap().1;
    let yz = about([0.0, 0.0], -90.0, [10.0, 0.0]);
    assert!((last[0] - 1.0).abs() < 1e-9 && (last[1] - yz[0]).abs() < 1e-9 && (last[2] - yz[1]).abs() < 1e-9, "{last:?}, the rule {yz:?}");
    refuses_each(Dialect::Fanuc, &ReadOptions::default(), &[("%
O1000
G21 G90 G18 G94
G68 X0. Y0. R10.
M30
%
", "4:9:", "Y is not one of them")]);
}

/// What the rotation refuses, each where it stands: the manuals' own errors, and what the machine's
/// parameters or settings decide.
#[test]
fn g68_refuses_what_its_rules_leave_to_the_machine() {
    let head = "%\nO1000\nG21 G90 G17 G94 G0 X0. Y0.\n";
    for (dialect, body, at, needle) in [
        (Dialect::Fanuc, "G68 X0. Y0. R10.\nG18\nM30\n%\n", "5:1:", "must not be designated in the mode of coordinate system rotation"),
        (Dialect::Fanuc, "G68 X0. Y0. R10.\nG55\nM30\n%\n", "5:1:", "a work offset changed under coordinate system rotation"),
        (Dialect::Fanuc, "G68 X0. Y0.\nM30\n%\n", "4:1:", "without R"),
        (Dialect::Fanuc, "G68 X0. Y0. R10\nM30\n%\n", "4:13:", "without a decimal point"),
        (Dialect::Fanuc, "G91 G68 X0. Y0. R10.\nM30\n%\n", "4:17:", "under G91"),
        (Dialect::Fanuc, "G68 X0. Y0. R10.\nG1 X5. F100.\nG69\nG91 G1 X1.\nM30\n%\n", "7:8:", "the first move command after G69 must be specified as an absolute command"),
        (Dialect::Haas, "G68 X0. Y0. R10.\nG91 G1 X5. F100.\nM30\n%\n", "5:8:", "an incremental move after G68 before an absolute one"),
        (Dialect::Fanuc, "G68 X0. Y0. R10.\nG28 Z0.\nM30\n%\n", "5:1:", "reference return under coordinate system rotation"),
    ] {
        let p = read(&format!("{head}{body}"), dialect, "t.nc", &ReadOptions::default());
        let (l, c) = at.trim_end_matches(':').split_once(':').unwrap();
        has(&p, l.parse().unwrap(), c.parse().unwrap(), needle);
    }
}

/// A cycle's first block without R: Fanuc's format has it; Haas marks R optional ("*R - Position of
/// the R plane", its G82 page) without saying where the plane then lies, so both refuse it, Haas
/// saying so (a student program of the probe set writes `G82 Z-0.12 F10.`).
#[test]
fn a_first_cycle_block_without_r_is_refused_as_each_control_says() {
    let head = "%\nO1000\nG20 G90 G17 G94 G0 X0. Y0. Z1.\n";
    let p = read(&format!("{head}G82 Z-0.12 F10.\nM30\n%\n"), Dialect::Haas, "t.nc", &ReadOptions::default());
    has(&p, 4, 1, "G82 without R: Haas marks the R plane optional");
    let p = read(&format!("{head}G82 Z-0.12 F10.\nM30\n%\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    has(&p, 4, 1, "G82: a new cycle needs its R point (R)");
}

/// An arc in a plane tilted by `G68.2` (FANUC B-63944EN/02 "Tilted working plane command": the
/// feature frame at X Y Z, turned by the Euler angles I about Z, J about X', K about Z''): its end
/// and its centre are the feature frame's points in the workpiece, origin + R p, with R = Rx(30 deg)
/// for I0 J30 K0, as computed here; the arc lies in the feature frame's XY plane, of radius 10.
#[test]
fn an_arc_in_a_g68_2_plane_has_its_centre_in_the_workpiece() {
    let text = "%\nO1001\nG21 G90 G17 G94\nG0 X0 Y0 Z50.\nG68.2 X10. Y5. Z2. I0 J30. K0\nG0 X30. Y0 Z0\nG1 F500.\nG3 X40. Y10. I0 J10.\nG2 X50. Y20. R10.\nG69\nM30\n%\n";
    let nmv = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&nmv));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let (s, c) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
    let place = |q: [f64; 3]| [10.0 + q[0], 5.0 + c * q[1] - s * q[2], 2.0 + s * q[1] + c * q[2]];
    // (block's line, end and centre in the feature frame, mm): G2 R10 from (40, 10) to (50, 20)
    // clockwise, the shorter arc, has its centre at (50, 10).
    for (line, end, centre) in [(8, [40.0, 10.0, 0.0], [30.0, 10.0, 0.0]), (9, [50.0, 20.0, 0.0], [50.0, 10.0, 0.0])] {
        let b = p.blocks.iter().find(|b| b.line == line && b.motion.is_arc()).unwrap_or_else(|| panic!("the arc on line {line}"));
        let a = b.arc.as_ref().unwrap();
        let at: Vec<f64> = [b.targets.x, b.targets.y, b.targets.z].iter().zip(b.datum).map(|(t, d)| (t.unwrap() + d) / MM).collect();
        let cw: Vec<f64> = a.centre.iter().zip(b.datum).map(|(t, d)| (t + d) / MM).collect();
        let (want_end, want_centre) = (place(end), place(centre));
        for k in 0..3 {
            assert!((at[k] - want_end[k]).abs() < 1e-9, "line {line}: end {at:?}, want {want_end:?}");
            assert!((cw[k] - want_centre[k]).abs() < 1e-9, "line {line}: centre {cw:?}, want {want_centre:?}");
        }
        // The arc's plane is the feature frame's XY: its normal (0, -sin 30, cos 30).
        let f = a.frame.expect("the tilted plane's frame");
        assert!(f[2][0].abs() < 1e-12 && (f[2][1] + s).abs() < 1e-12 && (f[2][2] - c).abs() < 1e-12, "{f:?}");
    }
}
