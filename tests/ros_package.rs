//! The node set as ROS 2 packages (issue 14 item 2), checked with what runs without a ROS install:
//! colcon itself (colcon-core, colcon-ros, colcon-cargo, colcon-ros-cargo with cargo-ament-build,
//! from PyPI into target/colcon-py by launch-free-scripts/test) finds every package with its build
//! type and dependencies; the launch files, run with recording stand-ins for ROS 2's `launch` and
//! `launch_ros` (not on PyPI; tests/peer/launch_check.py), start packages colcon finds, executables
//! they build, with parameters each real executable lists and accepts.

use crate::common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("FIVEAXIS_ROOT"))
}

/// `python3 -m colcon ARGS` over the repository, with the colcon installed under target/.
fn colcon(args: &[&str]) -> String {
    let py = root().join("target/colcon-py");
    assert!(py.join("colcon_ros_cargo").exists(), "colcon is not installed in {}: run launch-free-scripts/test", py.display());
    let path = format!("{}:{}", py.join("bin").display(), std::env::var("PATH").unwrap_or_default());
    let logs = common::scratch_dir("colcon-log");
    let out = Command::new("python3")
        .args(["-m", "colcon", "--log-base"])
        .arg(&logs)
        .args(args)
        .args(["--base-paths", "."])
        .current_dir(root())
        .env("PYTHONPATH", &py)
        .env("PATH", path)
        .output()
        .expect("python3 runs");
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(out.status.success(), "colcon {args:?}: {text}\n{}", String::from_utf8_lossy(&out.stderr));
    text
}

fn bin(name: &str) -> PathBuf {
    Path::new(env!("FIVEAXIS_EXE")).parent().unwrap().join(name)
}

/// The ROS parameters an executable lists at the end of its `--help`.
fn listed_parameters(exe: &Path) -> Vec<String> {
    let out = Command::new(exe).arg("--help").output().unwrap();
    let help = String::from_utf8_lossy(&out.stdout).to_string();
    let section = help.split("ROS 2 parameters").nth(1).unwrap_or_else(|| panic!("{} --help lists no ROS parameters", exe.display()));
    section.lines().skip(1).take_while(|l| l.starts_with("  ")).filter_map(|l| l.split_whitespace().next().map(str::to_string)).collect()
}

#[test]
fn colcon_finds_every_package_with_its_build_type() {
    let listed: BTreeMap<String, (String, String)> = colcon(&["list"])
        .lines()
        .filter_map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            (f.len() == 3).then(|| (f[0].to_string(), (f[1].to_string(), f[2].to_string())))
        })
        .collect();
    for node in ["commander", "simulator", "monitor", "recorder", "rerun", "bridge"] {
        assert_eq!(listed.get(&format!("fiveaxis_{node}")), Some(&(format!("nodes/{node}"), "(ament_cargo)".to_string())), "{listed:?}");
    }
    assert_eq!(listed.get("fiveaxis_msgs"), Some(&("msgs".to_string(), "(ros.ament_cmake)".to_string())), "{listed:?}");
    assert_eq!(listed.get("fiveaxis_bringup"), Some(&("bringup".to_string(), "(ros.ament_cmake)".to_string())), "{listed:?}");
    // The launch package runs the node packages; they run with the interface package.
    let info = colcon(&["info", "fiveaxis_bringup"]);
    let run = info.lines().find(|l| l.trim_start().starts_with("run:")).unwrap_or_else(|| panic!("{info}"));
    for dep in ["fiveaxis_commander", "fiveaxis_simulator", "fiveaxis_monitor", "fiveaxis_recorder", "fiveaxis_bridge", "launch", "launch_ros"] {
        assert!(run.split_whitespace().any(|d| d == dep), "fiveaxis_bringup does not run {dep}: {info}");
    }
    let info = colcon(&["info", "fiveaxis_monitor"]);
    assert!(info.contains("fiveaxis_msgs"), "{info}");
}

#[test]
fn launch_files_start_built_executables_with_parameters_they_accept() {
    let dir = common::scratch_dir("launch-check");
    let cases: [(&str, &[&str], &[&str]); 5] = [
        ("node_set.launch.py", &[], &["commander", "simulator", "monitor", "recorder"]),
        ("monitor_machine.launch.py", &[], &["monitor"]),
        ("monitor_machine.launch.py", &["axis_map=X=joint_0,Y=joint_1,Z=joint_2,A=joint_3,C=joint_4", "bag=shift_bag", "program=bundled:SING.I"], &["monitor", "recorder"]),
        ("monitor_machine.launch.py", &["mtconnect_agent=http://agent:5000", "mtconnect_device=C600U", "axis_map=Z=z_act", "bag=shift_bag"], &["bridge", "monitor", "recorder"]),
        ("monitor_machine.launch.py", &["opcua_server=opc.tcp://cnc:4840", "program=bundled:SING.I"], &["bridge", "monitor"]),
    ];
    for (k, (file, overrides, expected)) in cases.iter().enumerate() {
        let out = Command::new("python3").arg(root().join("tests/peer/launch_check.py")).arg(root().join("bringup/launch").join(file)).args(*overrides).output().unwrap();
        assert!(out.status.success(), "{file}: {}", String::from_utf8_lossy(&out.stderr));
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let nodes = v["nodes"].as_array().unwrap();
        let started: Vec<&str> = nodes.iter().map(|n| n["executable"].as_str().unwrap()).collect();
        let want: Vec<String> = expected.iter().map(|n| format!("fiveaxis-{n}")).collect();
        assert_eq!(started.len(), want.len(), "{file} {overrides:?}: {started:?}");
        assert!(want.iter().all(|w| started.contains(&w.as_str())), "{file} {overrides:?}: {started:?}");
        for n in nodes {
            let (package, exe) = (n["package"].as_str().unwrap(), n["executable"].as_str().unwrap());
            // The package is the executable's Cargo package (nodes/NAME) and builds that executable.
            let crate_dir = root().join("nodes").join(package.trim_start_matches("fiveaxis_"));
            let manifest = std::fs::read_to_string(crate_dir.join("Cargo.toml")).unwrap_or_else(|_| panic!("{file}: no crate for package {package}"));
            assert!(manifest.contains(&format!("name = \"{package}\"")) && manifest.contains(&format!("name = \"{exe}\"")), "{file}: {package} does not build {exe}");
            assert!(std::fs::read_to_string(crate_dir.join("package.xml")).unwrap().contains(&format!("<name>{package}</name>")));
            // Every parameter is one the executable declares ...
            let exe_path = bin(exe);
            let known = listed_parameters(&exe_path);
            let params = n["parameters"].as_object().unwrap();
            for name in params.keys() {
                assert!(known.contains(name), "{file}: {exe} has no parameter {name} (its parameters: {known:?})");
            }
            // ... and accepts with its value, given as launch_ros gives it (a params file under /**, the
            // node's name and namespace as remaps); `-- --help` stops the node once its arguments are read.
            let yaml = format!("/**:\n  ros__parameters:\n{}", params.iter().map(|(k, v)| format!("    {k}: {v}\n")).collect::<String>());
            let pfile = dir.join(format!("{k}-{exe}.yaml"));
            std::fs::write(&pfile, yaml).unwrap();
            let run = Command::new(&exe_path)
                .args(["--ros-args", "-r"])
                .arg(format!("__node:={}", n["name"].as_str().unwrap()))
                .arg("-r")
                .arg(format!("__ns:={}", n["namespace"].as_str().unwrap()))
                .arg("--params-file")
                .arg(&pfile)
                .args(["--", "--help"])
                .output()
                .unwrap();
            assert_eq!(run.status.code(), Some(0), "{file}: {exe} refuses its parameters: {}", String::from_utf8_lossy(&run.stderr));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
