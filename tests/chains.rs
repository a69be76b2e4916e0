//! Every kind of two-rotary machine (seed 001 §2.4): the predicted secondary-axis rate against a
//! numerical derivative of the machine's own inverse kinematics, never against the formula.

use fiveaxis::kinematics::{unwrap_near, wrap_pi, Carrier, RotaryJoint, TwoRotaryChain};
use fiveaxis::machine::{Machine, BUILTIN_NAMES};
use fiveaxis::units::DEG;
use nalgebra::{Rotation3, Unit, Vector3};

use crate::common;
use crate::common::Rng;

fn rotate(axis: &Vector3<f64>, angle: f64, v: &Vector3<f64>) -> Vector3<f64> {
    Rotation3::from_axis_angle(&Unit::new_normalize(*axis), angle) * v
}

/// The inverse-kinematics solution nearest `near` (both rotaries unwrapped to it).
fn ik_near(chain: &TwoRotaryChain, o: &Vector3<f64>, near: &[f64; 2]) -> Option<[f64; 2]> {
    let sols = chain.orientation_solutions(o).ok()?;
    sols.solutions
        .iter()
        .map(|s| [unwrap_near(s[0], near[0]), unwrap_near(s[1], near[1])])
        .min_by(|a, b| {
            let d = |s: &[f64; 2]| (s[0] - near[0]).abs() + (s[1] - near[1]).abs();
            d(a).total_cmp(&d(b))
        })
}

/// d r2/dt of the IK solution along `o(t)` at t = 0, by Richardson-extrapolated central differences.
fn numerical_rate(chain: &TwoRotaryChain, path: &dyn Fn(f64) -> Vector3<f64>, rot0: &[f64; 2], h: f64) -> Option<f64> {
    let r2 = chain.secondary_slot();
    let at = |t: f64| ik_near(chain, &path(t), rot0).map(|s| s[r2]);
    let central = |h: f64| Some((at(h)? - at(-h)?) / (2.0 * h));
    let (d1, d2) = (central(h)?, central(h / 2.0)?);
    Some((4.0 * d2 - d1) / 3.0)
}

/// Checks `cases` random paths through orientations drawn by `start`, returning how many were checked.
/// `start` gives rotary angles; the path leaves their tool axis in a random direction with a random
/// curvature, at a rate of 0.05-2 rad/s.
fn check_chain(name: &str, chain: &TwoRotaryChain, rng: &mut Rng, cases: usize, start: &mut dyn FnMut(&mut Rng) -> Option<[f64; 2]>) -> usize {
    let mut checked = 0;
    let mut worst: (f64, String) = (0.0, String::new());
    for case in 0..cases {
        let Some(rot0) = start(rng) else { continue };
        let o0 = chain.orientation(&rot0);
        // Near the rim of a non-orthogonal chain's reachable cone the two branches meet and the
        // primary axis folds back: the IK's branch is not defined by continuity there. Skip within 2 deg.
        let sols = chain.orientation_solutions(&o0).unwrap();
        let apart = |k: usize| wrap_pi(sols.solutions[0][k] - sols.solutions[1][k]).abs();
        if apart(0) < 2.0 * DEG && apart(1) < 2.0 * DEG {
            continue;
        }
        let v = rng.across(&o0) * rng.range(0.05, 2.0);
        let u = rng.unit() * rng.range(0.0, 1.0);
        let path = move |t: f64| (o0 + v * t + u * t * t).normalize();
        let predicted = chain.secondary_rate(&o0, &v, &rot0);
        // The step: small against the time the tool takes to pass the pole at this distance, and
        // against the time r2 takes to turn a milliradian.
        let dist = chain.singular_direction().cross(&o0).norm();
        let h = 1e-4 / (v.norm() / dist).max(predicted.abs()).max(1.0);
        let Some(numeric) = numerical_rate(chain, &path, &rot0, h) else { continue };
        let err = (predicted - numeric).abs() / numeric.abs().max(1e-3);
        if err > worst.0 {
            worst = (err, format!("case {case}: rot {:?} deg, predicted {predicted}, numeric {numeric}", rot0.map(|r| r / DEG)));
        }
        checked += 1;
    }
    assert!(worst.0 <= 1e-6, "{name}: relative error {:.3e} ({})", worst.0, worst.1);
    checked
}

/// Random angles within the machine's rotary ranges.
fn in_range(m: &Machine) -> impl FnMut(&mut Rng) -> Option<[f64; 2]> + '_ {
    move |rng: &mut Rng| {
        let r = |rng: &mut Rng, i: usize| {
            let l = m.axes[3 + i].limits;
            if l.is_unlimited() {
                rng.range(-720.0 * DEG, 720.0 * DEG)
            } else {
                rng.range(l.min, l.max)
            }
        };
        Some([r(rng, 0), r(rng, 1)])
    }
}

/// Angles whose tool axis lies 0.05-2 deg from the pole, on either branch.
fn near_pole(chain: &TwoRotaryChain) -> impl FnMut(&mut Rng) -> Option<[f64; 2]> + '_ {
    move |rng: &mut Rng| {
        // The pole is the singular line: the direction or its opposite, whichever the tool reaches.
        let s = chain.singular_direction() * if rng.next() < 0.5 { 1.0 } else { -1.0 };
        let o = rotate(&rng.across(&s), rng.range(0.05, 2.0) * DEG, &s);
        let sols = chain.orientation_solutions(&o).ok()?;
        Some(sols.solutions[(rng.next() * 2.0) as usize])
    }
}

#[test]
fn every_built_in_machine_predicts_the_secondary_rate_of_its_own_inverse() {
    let mut rng = Rng(0x5EED_0001);
    for name in BUILTIN_NAMES {
        let m = Machine::builtin(name).unwrap();
        // A four-axis machine has no secondary axis to predict (its own test below).
        if m.chain.is_four_axis() {
            continue;
        }
        let anywhere = check_chain(name, &m.chain, &mut rng, 400, &mut in_range(&m));
        let pole = check_chain(name, &m.chain, &mut rng, 400, &mut near_pole(&m.chain));
        assert!(anywhere > 300 && pole > 150, "{name}: only {anywhere} and {pole} paths checked");
    }
}

/// Random chains: any two non-parallel axes, any carriers, the tool at home anywhere on the cone
/// that reaches the pole (a nutating head or table at any angle, or none at all).
#[test]
fn random_two_rotary_chains_predict_the_secondary_rate_of_their_own_inverse() {
    let mut rng = Rng(0x5EED_0002);
    let mut total = 0;
    for k in 0..60 {
        let a1 = rng.unit();
        let a2 = loop {
            let a = rng.unit();
            if a.cross(&a1).norm() > 0.2 {
                break a;
            }
        };
        let carriers = [Carrier::Table, Carrier::Head];
        let (c1, c2) = (carriers[k % 2], carriers[(k / 2) % 2]);
        // The tool at home on the cone about r1 that passes through r2, so the pole is reachable
        // (r2: the inner table axis, else the outer head axis).
        let r2 = if c2 == Carrier::Table { 1 } else { 0 };
        let (ar1, ar2) = if r2 == 1 { (a1, a2) } else { (a2, a1) };
        let tool = rotate(&ar1, rng.range(-3.0, 3.0), &ar2);
        let joint = |name: &str, carrier, axis: Vector3<f64>, rng: &mut Rng| RotaryJoint {
            name: name.into(),
            carrier,
            axis,
            center: Vector3::new(rng.range(-0.1, 0.1), rng.range(-0.1, 0.1), rng.range(-0.1, 0.1)),
        };
        // File order is base outwards on each side; for table-head the table joint is r2 whatever its slot.
        let joints = [joint("P", c1, a1, &mut rng), joint("Q", c2, a2, &mut rng)];
        let Ok(chain) = TwoRotaryChain::new(joints, tool, Vector3::new(0.0, 0.0, -0.1)) else { continue };
        assert_eq!(chain.secondary_slot(), r2);
        let label = format!("random chain {k} ({c1:?}/{c2:?})");
        let any = &mut |rng: &mut Rng| Some([rng.range(-7.0, 7.0), rng.range(-7.0, 7.0)]);
        total += check_chain(&label, &chain, &mut rng, 60, any);
        total += check_chain(&label, &chain, &mut rng, 60, &mut near_pole(&chain));
    }
    assert!(total > 5000, "only {total} paths checked");
}

/// Eq. (5) as printed (`dTheta_h/dt / sin A`) is exact only on orthogonal chains: on a 45 deg nutating
/// head 2 deg from the pole it is off by far more than the tolerance above, which the exact rate meets.
#[test]
fn printed_eq_5_is_not_exact_on_a_nutating_head() {
    let s = Vector3::z();
    let b = Vector3::new(0.0, -1.0, 1.0).normalize(); // 45 deg head axis in the Y-Z plane
    let chain = TwoRotaryChain::new(
        [
            RotaryJoint { name: "C".into(), carrier: Carrier::Table, axis: s, center: Vector3::zeros() },
            RotaryJoint { name: "B".into(), carrier: Carrier::Head, axis: b, center: Vector3::zeros() },
        ],
        s,
        Vector3::zeros(),
    )
    .unwrap();
    let mut rng = Rng(0x5EED_0003);
    let mut worst_printed: f64 = 0.0;
    let checked = check_chain("nutating", &chain, &mut rng, 200, &mut |rng: &mut Rng| {
        let o = rotate(&rng.across(&s), 2.0 * DEG, &s);
        let rot = chain.orientation_solutions(&o).ok()?.solutions[0];
        // The printed formula, with the table's sign, against the numerical derivative.
        let v = rng.across(&o);
        let n = s.cross(&o);
        let printed = -v.dot(&n) / n.norm_squared();
        let path = move |t: f64| (o + v * t).normalize();
        let numeric = numerical_rate(&chain, &path, &rot, 1e-6)?;
        worst_printed = worst_printed.max((printed - numeric).abs() / numeric.abs().max(1e-3));
        Some(rot)
    });
    assert!(checked > 150);
    assert!(worst_printed > 0.1, "the printed eq. (5) was within {worst_printed:.3e}");
}


/// The LinuxCNC machines against LinuxCNC's own kinematics modules: machines/linuxcnc/kins_fixtures.py
/// called the installed modules' kinematicsForward on random joints (with a tool length where the module
/// takes one); our forward kinematics must give the same program point to 1e-9 mm.
#[test]
fn linuxcnc_machines_match_the_controls_own_kinematics_modules() {
    let root = std::path::Path::new(env!("FIVEAXIS_ROOT"));
    let text = std::fs::read_to_string(root.join("machines/linuxcnc/kins_fixtures.csv")).unwrap();
    let mut counts = std::collections::BTreeMap::new();
    let mut worst: f64 = 0.0;
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let v: Vec<f64> = f[1..].iter().map(|s| s.parse().unwrap()).collect();
        let (tool, q, world) = (v[0], &v[1..6], Vector3::new(v[6], v[7], v[8]));
        let file = fiveaxis::machine::builtin_file(f[0]).unwrap();
        let with_tool = file.replacen("tool_tip_mm = [0.0, 0.0, 0.0]", &format!("tool_tip_mm = [0.0, 0.0, {}]", -tool), 1);
        let m = Machine::from_toml_str(&with_tool, f[0]).unwrap();
        let joints = [q[0] * 1e-3, q[1] * 1e-3, q[2] * 1e-3, q[3] * DEG, q[4] * DEG];
        let tip_mm = m.forward(&joints).tip * 1e3;
        let program = world - Vector3::new(0.0, 0.0, tool);
        let err = (tip_mm - program).norm();
        assert!(err < 1e-9, "{}: joints {q:?} T {tool}: ours {tip_mm:?}, LinuxCNC's {program:?}", f[0]);
        worst = worst.max(err);
        *counts.entry((f[0].to_string(), tool as i64)).or_insert(0) += 1;
    }
    // Every LinuxCNC machine, with a tool where its module takes one.
    for (name, tools) in [("linuxcnc-xyzbc-trt", [0, 10]), ("linuxcnc-xyzac-trt", [0, 10]), ("linuxcnc-xyzab-tdr", [0, 30]), ("linuxcnc-bridgemill", [0, 100]), ("linuxcnc-max5", [0, 0])] {
        for t in tools {
            assert!(counts.get(&(name.to_string(), t)).copied().unwrap_or(0) >= 40, "{name} T{t}: {counts:?}");
        }
    }
    eprintln!("worst {worst:.2e} mm over {} rows", counts.values().sum::<usize>());
}

/// Impossible machine files: each is refused with exit 2 by `machine show` and by a command that loads
/// the machine, the field named.
#[test]
fn impossible_machine_files_are_refused_naming_the_field() {
    let dir = common::scratch_dir("chains");
    let hermle = fiveaxis::machine::builtin_file("hermle-c600u").unwrap();
    let four_axis = fiveaxis::machine::builtin_file("deckel-dmc-75v").unwrap();
    let a_axis = "axis = [1.0, 0.0, 0.0]";
    let cases: Vec<(&str, String, &str)> = vec![
        ("inf-tool", hermle.replace("tool_axis = [0.0, 0.0, 1.0]", "tool_axis = [inf, 0.0, 0.0]"), "`tool_axis`"),
        ("zero-tool", hermle.replace("tool_axis = [0.0, 0.0, 1.0]", "tool_axis = [0.0, 0.0, 0.0]"), "`tool_axis`"),
        ("nan-tip", hermle.replace("tool_tip_mm = [0.0, 0.0, 0.0]", "tool_tip_mm = [0.0, nan, 0.0]"), "`tool_tip_mm`"),
        ("nan-center", hermle.replacen("center_mm = [0.0, 0.0, 0.0]", "center_mm = [nan, 0.0, 0.0]", 1), "`rotary[0].center_mm`"),
        ("zero-axis", hermle.replace(a_axis, "axis = [0.0, 0.0, 0.0]"), "`rotary[0].axis`"),
        ("parallel", hermle.replace(a_axis, "axis = [0.0, 0.0, -2.0]"), "`rotary[0].axis` (A) and `rotary[1].axis` (C)"),
        ("tool-on-primary", hermle.replace("tool_axis = [0.0, 0.0, 1.0]", "tool_axis = [1.0, 0.0, 0.0]"), "`tool_axis` is 0.000 deg from `rotary[0].axis`"),
        ("missing-axis", hermle.replace(&format!("{a_axis}\n"), ""), "missing field `axis`"),
        ("negative-speed", hermle.replacen("velocity_deg_per_s = 150.0", "velocity_deg_per_s = -150.0", 1), "`rotary[0].velocity_deg_per_s`"),
        ("inverted-range", hermle.replace("min_deg = -110.0", "min_deg = 120.0"), "`rotary[0].min_deg`"),
        ("inf-travel", hermle.replacen("max_mm = 300.0", "max_mm = inf", 1), "`linear[0].min_mm`"),
        ("grad", hermle.replacen("jerk_deg_per_s3 = 6000.0", "jerk_deg_per_s3 = 6000.0\nprogram_unit = \"grad\"", 1), "`rotary[0].program_unit`"),
        ("m-action", format!("{hermle}\n[[m_function]]\ncode = 10\naction = \"brake\"\n"), "`m_function[0].action` (M10)"),
        ("m-twice", format!("{hermle}\n[[m_function]]\ncode = 10\naction = \"event\"\n[[m_function]]\ncode = 10\naction = \"event\"\n"), "`m_function[1].code`"),
        ("nan-zero", format!("{hermle}\n[machine_coordinates]\nzero_mm = [0.0, nan, 0.0]\n"), "`machine_coordinates.zero_mm`"),
        ("empty-maker", hermle.replacen("maker = \"Hermle\"", "maker = \" \"", 1), "`maker` is empty"),
        ("no-rotary", format!("rotary = []\n{}", hermle.split("[[rotary]]").next().unwrap()), "needs 2 [[rotary]] axes (a five-axis machine) or 1 (a four-axis machine), found 0"),
        ("three-rotary", format!("{hermle}\n[[rotary]]\nname = \"B\"\ncarrier = \"head\"\naxis = [0.0, 1.0, 0.0]\ncenter_mm = [0.0, 0.0, 0.0]\nvelocity_deg_per_s = 10.0\nacceleration_deg_per_s2 = 10.0\njerk_deg_per_s3 = 10.0\n"), "found 3"),
        ("four-axis-tool-on-a", four_axis.replace("tool_axis = [0.0, 0.0, 1.0]", "tool_axis = [-1.0, 0.0, 0.0]"), "`tool_axis` is 0.000 deg from `rotary[0].axis` (A), the only rotary axis"),
    ];
    let cases: Vec<(&str, String, Vec<&str>)> = cases.into_iter().map(|(name, text, field)| (name, text, vec![field])).collect();
    common::assert_machine_files_refused(&dir, "toml", hermle, &cases);
    // A valid file passes `machine show`, and its text comes back.
    let ok = dir.join("ok.toml");
    std::fs::write(&ok, hermle).unwrap();
    let out = std::process::Command::new(env!("FIVEAXIS_EXE")).args(["machine", "show", ok.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(String::from_utf8_lossy(&out.stdout), hermle);
    std::fs::remove_dir_all(&dir).ok();
}

/// The generic model of each kinematic class (issue 64): `machine list` names it `generic <class>`,
/// home is its pole (the tool along the secondary axis), and tilting the primary axis by t turns the
/// tool away from the pole by t, or on a 45 deg nutating axis by acos((1 + cos t) / 2) (the cone's
/// spherical geometry: 60 deg at t = 90, 90 deg at t = 180).
#[test]
fn generic_models_of_each_class_have_their_pole_and_tilt_where_the_class_has_them() {
    let classes = [
        ("generic-ac-table", "A/C table-table", false),
        ("generic-bc-table", "B/C table-table", false),
        ("generic-ab-table", "A/B table-table", false),
        ("generic-b45-table", "B/C 45 deg nutating table", true),
        ("generic-b45-head", "B/C 45 deg nutating head over a C table", true),
        ("generic-ac-head", "A/C fork head", false),
        ("generic-bc-head", "B/C fork head", false),
    ];
    let list = std::process::Command::new(env!("FIVEAXIS_EXE")).args(["machine", "list"]).output().unwrap();
    let list = String::from_utf8_lossy(&list.stdout);
    for (name, class, nutating) in classes {
        assert!(list.lines().any(|l| l.starts_with(name) && l.contains(&format!("generic {class}"))), "{name} not listed as generic {class}:\n{list}");
        let m = Machine::builtin(name).unwrap();
        assert_eq!(m.label(), format!("generic {class}"));
        let pole = m.singular_direction();
        let primary = m.primary_axis();
        for t_deg in [0.0, 30.0, 60.0, 90.0, 120.0] {
            let mut q = [0.0; 5];
            q[primary] = t_deg * DEG;
            // The secondary axis turns about the pole: it must not change the angle.
            q[m.secondary_axis()] = 37.0 * DEG;
            let away = m.forward(&q).axis.angle(&pole).min(m.forward(&q).axis.angle(&-pole)) / DEG;
            let t = t_deg * DEG;
            let expected = if nutating { ((1.0 + t.cos()) / 2.0).acos() / DEG } else { t_deg };
            let expected = expected.min(180.0 - expected);
            assert!((away - expected).abs() < 1e-9, "{name}: primary at {t_deg} deg puts the tool {away} deg from the pole, expected {expected}");
        }
        // Wide ranges: a part anywhere within 4 m and the tool tilted up to 89 deg is reachable.
        let lim = m.limits();
        assert!((0..3).all(|k| lim[k].min <= -4.0 && lim[k].max >= 4.0), "{name}: linear ranges {lim:?}");
    }
}

/// A four-axis machine (the Deckel DMC 75V: an A table about +X through the part zero), against its
/// transform written out here: a workpiece point p lies at R_x(A) p in the machine (the table turns it
/// by A), so the axes X Y Z put the tip at p = R_x(-A) (X, Y, Z), and the tool axis in the workpiece is
/// R_x(-A) z = (0, sin A, cos A). The inverse gives A back for each orientation on that circle and
/// refuses every other one; the locked fifth axis stays at 0, nothing asks it to turn (the secondary
/// rate is 0 on any path) and the tool keeps 90 deg from the rotary axis, so no pole is ever near.
#[test]
fn a_four_axis_machine_turns_the_part_about_its_one_axis_and_has_no_pole() {
    let m = Machine::builtin("deckel-dmc-75v").unwrap();
    assert!(m.chain.is_four_axis());
    assert_eq!(m.axis_names().to_vec(), ["X", "Y", "Z", "A", ""]);
    assert_eq!((m.axes[4].limits.min, m.axes[4].limits.max), (0.0, 0.0), "the locked axis is held at 0");
    let mut rng = Rng(0x5EED_0044);
    for _ in 0..500 {
        let a = rng.range(-720.0 * DEG, 720.0 * DEG);
        let lin = Vector3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), rng.range(-0.1, 0.4));
        let pose = m.forward(&[lin.x, lin.y, lin.z, a, 0.0]);
        let back = Rotation3::from_axis_angle(&Vector3::x_axis(), -a);
        assert!((pose.tip - back * lin).norm() < 1e-12, "A {a}: tip {} vs {}", pose.tip, back * lin);
        let axis = Vector3::new(0.0, a.sin(), a.cos());
        assert!((pose.axis - axis).norm() < 1e-12, "A {a}: axis {} vs {axis}", pose.axis);
        let sols = m.chain.orientation_solutions(&axis).unwrap();
        for s in sols.solutions {
            assert!(wrap_pi(s[0] - a).abs() < 1e-9 && s[1] == 0.0, "A {a}: {s:?}");
        }
        // No path turns the locked axis, and the tool stays square to A.
        let v = rng.across(&axis);
        assert_eq!(m.chain.secondary_rate(&axis, &v, &[a, 0.0]), 0.0);
        assert!((m.singular_direction().dot(&axis)).abs() < 1e-12);
        // Off the circle: out of this machine's reach.
        let across_circle = axis.cross(&Vector3::x()).normalize();
        let tilted = rotate(&across_circle, rng.range(0.01, 1.5) * if rng.next() < 0.5 { -1.0 } else { 1.0 }, &axis);
        assert!(m.chain.orientation_solutions(&tilted).is_err(), "A {a}: {tilted} reached");
    }
}
