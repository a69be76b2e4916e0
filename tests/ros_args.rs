//! The nodes started as `ros2 run` and launch files start them (`--ros-args -r __ns:= -r __node:= -p
//! NAME:=VALUE --params-file FILE`), checked from outside: an independent DDS participant (Cyclone
//! DDS from PyPI, tests/peer/ros_graph.py) reads the node's name and namespace from
//! `ros_discovery_info`, its topics from DDS discovery and its parameters through its
//! `list_parameters` / `get_parameters` services. Each node runs in a private network namespace.

use crate::common;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("FIVEAXIS_ROOT"))
}

fn bin(name: &str) -> PathBuf {
    let b = Path::new(env!("FIVEAXIS_EXE")).parent().unwrap().join(name);
    assert!(b.exists(), "{name} is not built in {}: run launch-free-scripts/test (or cargo build --workspace --bins)", b.parent().unwrap().display());
    b
}

/// A parameters file for the node: one wildcard section for every node, one for /cell1/m1 by name.
const PARAMS: &str = "/**:\n  ros__parameters:\n    some_other_nodes_parameter: 1\n/cell1/m1:\n  ros__parameters:\n";

/// Start `node` with the ROS arguments and `own` (its subcommand and flags) plus the
/// node-specific parameters `params` (YAML lines under ros__parameters); return what the peer saw.
fn start(tag: &str, node: &str, own: &str, params: &str, extra_ros: &str) -> (Value, String) {
    let dir = common::scratch_dir(&format!("rosargs-{tag}"));
    let file = dir.join("params.yaml");
    std::fs::write(&file, format!("{PARAMS}{params}")).unwrap();
    let script = format!(
        "'{node}' {own} --ros-args -r __ns:=/cell1 -r __node:=m1 -p machine:=hermle-c600u --params-file '{file}' {extra_ros} > '{d}/node.log' 2>&1 &
        P=$!
        python3 '{peer}' --node /cell1/m1 --timeout-s 30 > '{d}/seen.json'
        kill -TERM $P; wait $P || true",
        node = bin(node).display(),
        file = file.display(),
        d = dir.display(),
        peer = root().join("tests/peer/ros_graph.py").display(),
    );
    let out = Command::new(root().join("launch-free-scripts/netns-run")).args(["bash", "-c", &script]).output().expect("netns-run runs");
    let log = std::fs::read_to_string(dir.join("node.log")).unwrap_or_default();
    assert!(out.status.success(), "{tag}: {}\n{}\nnode: {log}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let seen: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("seen.json")).unwrap()).unwrap_or_else(|e| panic!("{tag}: {e}\nnode: {log}"));
    let _ = std::fs::remove_dir_all(&dir);
    (seen, log)
}

fn has(list: &Value, topic: &str, ty: &str) -> bool {
    list.as_array().unwrap().iter().any(|p| p[0] == topic && p[1] == ty)
}

/// The checks every node shares: its name and namespace, `machine` from `-p`, the parameters of its
/// own settings with their types, the wildcard's unknown parameter skipped with a warning.
fn check_common(tag: &str, seen: &Value, log: &str) -> serde_json::Map<String, Value> {
    assert_eq!(seen["node"], serde_json::json!({"namespace": "/cell1", "name": "m1"}), "{tag}: nodes seen {}\n{log}", seen["nodes"]);
    assert!(has(&seen["publications"], "/rosout", "rcl_interfaces/msg/Log"), "{tag}: {}", seen["publications"]);
    let params = seen["parameters"].as_object().unwrap_or_else(|| panic!("{tag}: no parameters served: {seen}\n{log}")).clone();
    assert_eq!(params["machine"], "hermle-c600u", "{tag}");
    assert_eq!(seen["parameter_types"]["machine"], "string", "{tag}");
    for ros_name in ["namespace", "node_name", "remap", "some_other_nodes_parameter"] {
        assert!(!params.contains_key(ros_name), "{tag}: {ros_name} must not be a parameter");
    }
    assert!(log.contains("some_other_nodes_parameter") && log.contains("skipped"), "{tag}: the wildcard's unknown parameter is reported:\n{log}");
    params
}

#[test]
fn commander_and_simulator_take_ros_arguments() {
    for (node, topic) in [("fiveaxis-commander", "commanded"), ("fiveaxis-simulator", "simulated")] {
        // The program and rate come from the file; a remap moves the state topic out of the namespace.
        let (seen, log) = start(
            topic,
            node,
            "",
            "    program: bundled:SING.I\n    rate: 500.0\n    wait_for_subscriber_s: 60.0\n    fast: true\n    use_sim_time: true\n",
            &format!("-r {topic}/axis_state:=/cnc/state"),
        );
        let params = check_common(node, &seen, &log);
        assert_eq!(
            (params["program"].as_str(), params["rate"].as_f64(), params["fast"].as_bool()),
            (Some("bundled:SING.I"), Some(500.0), Some(true)),
            "{node}: {params:?}"
        );
        assert_eq!(seen["parameter_types"]["rate"], "double");
        assert_eq!(seen["parameter_types"]["fast"], "bool");
        assert_eq!(params["use_sim_time"].as_bool(), Some(true), "{node}: ROS 2's own parameter, from the file");
        assert_eq!(seen["parameter_types"]["min_subscribers"], "integer");
        assert!(has(&seen["publications"], "/cnc/state", "fiveaxis_msgs/msg/AxisState"), "{node}: remapped: {}", seen["publications"]);
        assert!(
            has(&seen["publications"], &format!("/cell1/{topic}/joint_states"), "sensor_msgs/msg/JointState"),
            "{node}: in the namespace: {}",
            seen["publications"]
        );
        assert!(!has(&seen["publications"], &format!("/fiveaxis/{topic}/axis_state"), "fiveaxis_msgs/msg/AxisState"));
    }
}

#[test]
fn monitor_recorder_and_rerun_bridge_take_ros_arguments() {
    let dir = common::scratch_dir("rosargs-out");
    let (seen, log) = start("monitor", "fiveaxis-monitor", "", "    stale_ms: 50.0\n    input: [commanded/axis_state]\n", "");
    let params = check_common("monitor", &seen, &log);
    assert_eq!(params["stale_ms"].as_f64(), Some(50.0));
    assert_eq!(params["input"], serde_json::json!(["commanded/axis_state"]));
    assert!(has(&seen["subscriptions"], "/cell1/commanded/axis_state", "fiveaxis_msgs/msg/AxisState"), "{}", seen["subscriptions"]);
    assert!(has(&seen["publications"], "/cell1/monitor/status", "fiveaxis_msgs/msg/SingularityStatus"), "{}", seen["publications"]);

    let mcap = dir.join("rec.mcap");
    let (seen, log) = start("recorder", "fiveaxis-recorder", "", &format!("    output: {}\n    duration_s: 60.0\n", mcap.display()), "");
    let params = check_common("recorder", &seen, &log);
    assert_eq!(params["output"].as_str(), Some(mcap.to_str().unwrap()));
    // The recorder's readers are raw RustDDS readers, which ros2-client cannot list in the node's
    // entry: seen through DDS discovery, on the node's participant.
    assert!(
        has(&seen["participant_subscriptions"], "/cell1/simulated/axis_state", "fiveaxis_msgs/msg/AxisState"),
        "{}",
        seen["participant_subscriptions"]
    );
    assert!(mcap.exists(), "the recorder wrote its file where the parameter said");

    let rrd = dir.join("live.rrd");
    let (seen, log) = start("rerun", "fiveaxis-rerun", "live", &format!("    save: {}\n", rrd.display()), "");
    let params = check_common("rerun", &seen, &log);
    assert_eq!(params["save"].as_str(), Some(rrd.to_str().unwrap()));
    assert!(has(&seen["subscriptions"], "/cell1/commanded/axis_state", "fiveaxis_msgs/msg/AxisState"), "{}", seen["subscriptions"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// What cannot be used ends the node before it joins the graph, exit 2, naming the argument.
#[test]
fn bad_ros_arguments_are_refused_with_exit_2() {
    for (args, needle) in [
        (vec!["--ros-args", "-p", "rat:=5.0"], "rat"),
        (vec!["--ros-args", "-p", "rate:=fast"], "expected a number"),
        (vec!["--ros-args", "--params-file", "/nonexistent/p.yaml"], "/nonexistent/p.yaml"),
        (vec!["--rate", "5", "--ros-args", "-p", "rate:=6.0"], "give one"),
        // Off real time, wall-clock stamps would not be the program's.
        (vec!["--fast"], "use_sim_time"),
        (vec!["--ros-args", "-p", "speed:=2.0"], "use_sim_time"),
    ] {
        let out = Command::new(bin("fiveaxis-commander")).arg("bundled:SING.I").args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    // DDS Security asked for and enforced, with no keystore to take the enclave from.
    let out = Command::new(bin("fiveaxis-commander"))
        .args(["bundled:SING.I", "--ros-args", "--enclave", "/e"])
        .env("ROS_SECURITY_ENABLE", "true")
        .env("ROS_SECURITY_STRATEGY", "Enforce")
        .env_remove("ROS_SECURITY_KEYSTORE")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "--enclave /e under Enforce without a keystore: {err}");
    assert!(err.contains("ROS_SECURITY_KEYSTORE"), "{err}");
}
