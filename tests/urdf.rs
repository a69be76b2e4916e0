//! Machines as URDF (`robot_description`): every built-in machine written, then read back by an
//! independent parser (yourdfpy, PyPI: tests/peer/urdf_fk.py) and by ours with forward kinematics equal
//! to 1e-9 mm; a URDF written by hand for the Hermle gives seed 001's figures; impossible URDFs are
//! refused naming the joint and line, exit 2.

use fiveaxis::job::{self, JobOptions};
use fiveaxis::machine::{urdf, Machine, BUILTIN_NAMES};
use fiveaxis::units::MM;
use nalgebra::Vector3;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common;
use crate::common::Rng;

/// Tool tip agreement, mm, and tool axis agreement (unit vector components).
const TIP_TOL_MM: f64 = 1e-9;
const AXIS_TOL: f64 = 1e-12;

/// The hand-written Hermle URDF (machines/urdf/hermle-c600u.urdf).
const HAND_WRITTEN: &str = include_str!("../machines/urdf/hermle-c600u.urdf");
const HAND_WRITTEN_PATH: &str = "machines/urdf/hermle-c600u.urdf";

fn temp_dir(what: &str) -> PathBuf {
    common::scratch_dir(&format!("urdf-{what}"))
}

/// Random axis values inside every range (multi-turn rotaries within two turns), SI.
fn random_joints(m: &Machine, rng: &mut Rng, n: usize) -> Vec<[f64; 5]> {
    (0..n)
        .map(|_| {
            std::array::from_fn(|i| {
                let l = &m.axes[i].limits;
                let span = 4.0 * std::f64::consts::PI;
                rng.range(l.min.max(-span), l.max.min(span))
            })
        })
        .collect()
}

/// A tool pose: tip (mm) and axis.
type Pose = (Vector3<f64>, Vector3<f64>);

/// yourdfpy's tool pose in the workpiece frame (tip mm, axis) for each row; `names` are the URDF's
/// joint names for the five axes, in axis order.
fn yourdfpy_fk(file: &Path, names: &[String], rows: &[[f64; 5]], dir: &Path) -> Vec<Pose> {
    yourdfpy_fk_many(&[(file.to_path_buf(), names.to_vec(), rows.to_vec())], dir).remove(0)
}

/// [`yourdfpy_fk`] for several URDF files in one Python process (its imports take a second).
fn yourdfpy_fk_many(jobs: &[(PathBuf, Vec<String>, Vec<[f64; 5]>)], dir: &Path) -> Vec<Vec<Pose>> {
    let mut args = Vec::new();
    for (k, (file, names, rows)) in jobs.iter().enumerate() {
        let (joints, out) = (dir.join(format!("joints-{k}.csv")), dir.join(format!("fk-{k}.csv")));
        // A four-axis machine's locked axis (unnamed, always 0) is no joint of its URDF.
        let named: Vec<usize> = (0..names.len()).filter(|&i| !names[i].is_empty()).collect();
        let mut csv = named.iter().map(|&i| names[i].as_str()).collect::<Vec<_>>().join(",") + "\n";
        for r in rows {
            csv += &named.iter().map(|&i| format!("{:?}", r[i])).collect::<Vec<_>>().join(",");
            csv += "\n";
        }
        std::fs::write(&joints, csv).unwrap();
        args.extend([file.clone(), joints, out]);
    }
    let st = Command::new("python3")
        .arg(concat!(env!("FIVEAXIS_ROOT"), "/tests/peer/urdf_fk.py"))
        .args(&args)
        .status()
        .expect("python3 runs (yourdfpy comes from launch-free-scripts/test)");
    assert!(st.success(), "urdf_fk.py failed on {args:?}");
    jobs.iter()
        .enumerate()
        .map(|(k, (file, _, rows))| {
            let text = std::fs::read_to_string(dir.join(format!("fk-{k}.csv"))).unwrap();
            let poses: Vec<Pose> = text
                .lines()
                .skip(1)
                .map(|l| {
                    let v: Vec<f64> = l.split(',').map(|c| c.parse().unwrap()).collect();
                    (Vector3::new(v[0], v[1], v[2]), Vector3::new(v[3], v[4], v[5]))
                })
                .collect();
            assert_eq!(poses.len(), rows.len(), "{}: one pose per row", file.display());
            poses
        })
        .collect()
}

/// Largest tip (mm) and axis differences between our forward kinematics and `poses`.
fn worst(m: &Machine, rows: &[[f64; 5]], poses: &[(Vector3<f64>, Vector3<f64>)]) -> (f64, f64) {
    rows.iter().zip(poses).fold((0.0f64, 0.0f64), |(t, a), (q, (tip_mm, axis))| {
        let p = m.forward(q);
        (t.max((p.tip / MM - tip_mm).amax()), a.max((p.axis - axis).amax()))
    })
}

#[test]
fn every_built_in_machine_written_as_urdf_reads_back_with_the_same_kinematics() {
    let dir = temp_dir("builtin");
    let mut rng = Rng(0x5eed_0012);
    let (mut machines, mut jobs) = (Vec::new(), Vec::new());
    for name in BUILTIN_NAMES {
        let m = Machine::builtin(name).unwrap();
        let text = urdf::write(&m);
        let file = dir.join(format!("{name}.urdf"));
        std::fs::write(&file, &text).unwrap();
        jobs.push((file, m.axis_names().to_vec(), random_joints(&m, &mut rng, 60)));
        machines.push((name, m, text));
    }
    // The independent parser, every machine in one run: the URDF's joints are named after the axes.
    let theirs = yourdfpy_fk_many(&jobs, &dir);
    for (((name, m, text), (_, _, rows)), poses) in machines.iter().zip(&jobs).zip(&theirs) {
        let (tip, axis) = worst(m, rows, poses);
        assert!(tip <= TIP_TOL_MM && axis <= AXIS_TOL, "{name}: yourdfpy differs by {tip:.2e} mm, {axis:.2e} in the axis");
        // Ours: the same axes, limits, secondary axis and forward kinematics.
        let back = urdf::read(text, name).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(back.axis_names(), m.axis_names(), "{name}");
        assert_eq!(back.secondary_axis(), m.secondary_axis(), "{name}");
        for (a, b) in back.axes.iter().zip(&m.axes) {
            let (la, lb) = (a.limits, b.limits);
            for (what, x, y) in [("min", la.min, lb.min), ("max", la.max, lb.max), ("velocity", la.velocity, lb.velocity), ("acceleration", la.acceleration, lb.acceleration), ("jerk", la.jerk, lb.jerk)] {
                assert!(x == y || (x - y).abs() <= 1e-12 * y.abs(), "{name} {} {what}: {x} vs {y}", a.name);
            }
        }
        let poses: Vec<_> = rows.iter().map(|q| back.forward(q)).map(|p| (p.tip / MM, p.axis)).collect();
        let (tip, axis) = worst(m, rows, &poses);
        assert!(tip <= TIP_TOL_MM && axis <= AXIS_TOL, "{name}: read back differs by {tip:.2e} mm, {axis:.2e} in the axis");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The Hermle described by hand (table on a Y saddle, A trunnion frame turned a quarter turn, column
/// in X, ram in Z, a 250 mm tool): the same machine as seed 001's, so SING.I gives the paper's figures.
#[test]
fn hand_written_hermle_urdf_gives_the_papers_figures() {
    let path = concat!(env!("FIVEAXIS_ROOT"), "/machines/urdf/hermle-c600u.urdf");
    let m = fiveaxis::machine::load(path).unwrap();
    assert_eq!(m.axis_names(), ["X", "Y", "Z", "A", "C"].map(String::from));
    assert_eq!(m.axes[m.secondary_axis()].name, "C", "C is the secondary axis (seed 001 §2.4)");
    let j = job::run("bundled:SING.I", &m, &JobOptions::default()).unwrap();
    assert_eq!(j.report.errors, 0, "{:?}", j.report.diagnostics);
    // Seed 001: block x 24-25 turns C 148.494 -> 180 deg in 1 mm at 2000 mm/min: 175.0 rpm; the blocks
    // from x 22 to 28 mm ask more than the 25 rpm of the table.
    assert!((j.report.peak_c_speed_rpm - 175.0).abs() <= 0.05, "peak {}", j.report.peak_c_speed_rpm);
    assert_eq!(j.report.regions.len(), 1, "{:?}", j.report.regions);
    let r = &j.report.regions[0];
    assert!((r.x_start_mm - 22.0).abs() < 1e-6 && (r.x_end_mm - 28.0).abs() < 1e-6, "region x {}-{}", r.x_start_mm, r.x_end_mm);
    assert_eq!((r.block_start, r.block_end), (Some(340), Some(390)));
    // yourdfpy on the same file (its joints are x_axis ... c_axis) agrees with our reading of it, and
    // both with the built-in machine of seed 001 eq. 1-2.
    let dir = temp_dir("hand");
    let hermle = Machine::hermle_c600u();
    let rows = random_joints(&m, &mut Rng(0x4e71e), 60);
    let names: Vec<String> = ["x_axis", "y_axis", "z_axis", "a_axis", "c_axis"].map(String::from).to_vec();
    let poses = yourdfpy_fk(Path::new(path), &names, &rows, &dir);
    for (who, machine) in [("our reading", &m), ("built-in hermle-c600u", &hermle)] {
        let (tip, axis) = worst(machine, &rows, &poses);
        assert!(tip <= TIP_TOL_MM && axis <= AXIS_TOL, "{who} differs from yourdfpy by {tip:.2e} mm, {axis:.2e}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A rounded quarter turn (`1.5708`, 3.7e-6 rad off) is read; a slide 1e-4 rad off its axis is not.
#[test]
fn rounded_angles_are_read_and_skewed_slides_are_refused() {
    let rounded = HAND_WRITTEN.replace("1.5707963267948966", "1.5708");
    assert_ne!(rounded, HAND_WRITTEN);
    let m = urdf::read(&rounded, "rounded").unwrap();
    let a = m.chain.joints()[0].axis;
    assert!((a - Vector3::x()).norm() < 1e-5, "A axis {a}");
    let skewed = HAND_WRITTEN.replace("<axis xyz=\"1 0 0\"/>", "<axis xyz=\"1 0.0001 0\"/>");
    assert_ne!(skewed, HAND_WRITTEN);
    let e = urdf::read(&skewed, "skewed").unwrap_err().to_string();
    assert!(e.contains("'x_axis'") && e.contains("must move it along +x") && e.contains("line "), "{e}");
}

/// Impossible machines in URDF: each is refused, by `machine show` and by a command that loads the
/// machine, with exit 2 and the joint (or link) and the place named.
#[test]
fn impossible_urdf_machines_are_refused_naming_the_joint() {
    let dir = temp_dir("refused");
    let h = HAND_WRITTEN;
    let c_axis_local = "<axis xyz=\"0 0 1\"/>\n    <limit effort=\"1000\"";
    let swap_y_and_a = h
        .replace("<parent link=\"bed\"/>\n    <child link=\"saddle\"/>", "<parent link=\"trunnion\"/>\n    <child link=\"saddle\"/>")
        .replace("<parent link=\"saddle\"/>\n    <child link=\"trunnion\"/>", "<parent link=\"bed\"/>\n    <child link=\"trunnion\"/>")
        .replace("<parent link=\"trunnion\"/>\n    <child link=\"rotary_table\"/>", "<parent link=\"saddle\"/>\n    <child link=\"rotary_table\"/>");
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        ("zero-axis", h.replace(c_axis_local, "<axis xyz=\"0 0 0\"/>\n    <limit effort=\"1000\""), vec!["'c_axis'", "non-zero length", "line "]),
        ("parallel", h.replace(c_axis_local, "<axis xyz=\"1 0 0\"/>\n    <limit effort=\"1000\""), vec!["from parallel", "joint 'c_axis' at line", "joint 'a_axis' at line"]),
        ("nan-origin", h.replace("xyz=\"0 0 0.25\"", "xyz=\"0 0 nan\""), vec!["xyz=\"0 0 nan\"", "finite numbers", "line "]),
        ("two-numbers", h.replace("xyz=\"0 0 0.25\"", "xyz=\"0 0.25\""), vec!["expected three numbers", "line "]),
        ("no-velocity", h.replacen(" velocity=\"0.5833333333333334\"", "", 1), vec!["`velocity`", "line "]),
        ("no-acceleration", h.replace("  <fiveaxis:limits joint=\"z_axis\" acceleration=\"5\" jerk=\"50\"/>\n", ""), vec!["'z_axis'", "acceleration and jerk", "line "]),
        ("negative-jerk", h.replace("joint=\"z_axis\" acceleration=\"5\" jerk=\"50\"", "joint=\"z_axis\" acceleration=\"5\" jerk=\"-50\""), vec!["z_axis", "jerk=\"-50\"", "positive"]),
        ("floating", h.replace("<joint name=\"z_axis\" type=\"prismatic\">", "<joint name=\"z_axis\" type=\"floating\">"), vec!["'z_axis'", "floating", "line "]),
        ("carried-slide", swap_y_and_a, vec!["'y_axis' is carried by rotary joint 'a_axis'", "line "]),
        ("no-workpiece", h.replace("\"workpiece\"", "\"part\""), vec!["no link named 'workpiece'", "part"]),
        ("skewed-slide", h.replace("<axis xyz=\"1 0 0\"/>", "<axis xyz=\"0 1 0\"/>"), vec!["'x_axis'", "must move it along +x"]),
        ("no-letter", h.replace("a_axis", "tilt"), vec!["'tilt'", "axis letter"]),
        ("mimic", h.replace(c_axis_local, &format!("<mimic joint=\"a_axis\"/>\n    {c_axis_local}")), vec!["'c_axis'", "mimics"]),
        ("undefined-link", h.replace("<child link=\"workpiece\"/>", "<child link=\"workpeice\"/>"), vec!["'workpeice'", "not defined", "line "]),
        ("two-parents", h.replace("<child link=\"column\"/>", "<child link=\"ram\"/>"), vec!["'ram'", "already has a parent", "line "]),
        ("inverted-range", h.replace("lower=\"-1.9198621771937625\"", "lower=\"2\""), vec!["'a_axis'", "lower < upper", "line "]),
        ("four-slides", h.replace("<joint name=\"part_on_table\" type=\"fixed\">", "<joint name=\"part_on_table\" type=\"prismatic\">"), vec!["4 prismatic and 2 rotary", "'part_on_table'"]),
        ("not-xml", h[..h.len() / 2].to_string(), vec!["not XML"]),
        ("dtd", format!("<!DOCTYPE robot [<!ENTITY a \"aaaa\">]>\n{}", &h[h.find("<robot").unwrap()..]), vec!["not XML"]),
        ("not-a-robot", "<sdf version=\"1.9\"/>".to_string(), vec!["<sdf>", "<robot>"]),
    ];
    common::assert_machine_files_refused(&dir, "urdf", h, &cases);
    std::fs::remove_dir_all(&dir).ok();
}

/// `machine urdf` writes what `machine show` reads back as the same machine file, and a URDF machine runs
/// every command that takes `--machine`.
#[test]
fn machine_urdf_command_writes_a_file_the_cli_reads() {
    let dir = temp_dir("cli");
    let file = dir.join("b45.urdf");
    let out = Command::new(env!("FIVEAXIS_EXE")).args(["machine", "urdf", "dmu-style-b45", "--out"]).arg(&file).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let show = Command::new(env!("FIVEAXIS_EXE")).args(["machine", "show"]).arg(&file).output().unwrap();
    assert_eq!(show.status.code(), Some(0), "{}", String::from_utf8_lossy(&show.stderr));
    let toml = String::from_utf8_lossy(&show.stdout);
    let shown = Machine::from_toml_str(&toml, "shown").unwrap();
    let b45 = Machine::builtin("dmu-style-b45").unwrap();
    let rows = random_joints(&b45, &mut Rng(45), 20);
    let poses: Vec<_> = rows.iter().map(|q| shown.forward(q)).map(|p| (p.tip / MM, p.axis)).collect();
    let (tip, axis) = worst(&b45, &rows, &poses);
    assert!(tip <= TIP_TOL_MM && axis <= AXIS_TOL, "machine show of the URDF differs by {tip:.2e} mm, {axis:.2e}");
    let out = Command::new(env!("FIVEAXIS_EXE")).args(["run", "bundled:SING.I", "--json", "--machine", HAND_WRITTEN_PATH]).current_dir(env!("FIVEAXIS_ROOT")).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    std::fs::remove_dir_all(&dir).ok();
}
