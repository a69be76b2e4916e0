//! The recorder over real DDS: stopped by SIGINT and recovered after SIGKILL, split by duration,
//! `--all` as a rosbag2 directory, a used directory or a bad topic refused, a full disk.

use super::*;

/// The recorder over DDS: SIGINT finishes a complete file holding every commanded sample; after
/// SIGKILL, `fiveaxis mcap recover` keeps everything up to at most about a second before the kill.
#[test]
fn recorder_finishes_on_sigint_and_is_recovered_after_sigkill() {
    let b = bins();
    let dir = common::scratch_dir("dds-rec");
    let (full, killed, kill_ns) = (dir.join("full.mcap"), dir.join("killed.mcap"), dir.join("kill_ns"));
    let script = format!(
        r#"set -e
B="{b}"
"$B/fiveaxis-recorder" --output "{full}" --topic commanded/axis_state:AxisState &
R1=$!
"$B/fiveaxis-recorder" --output "{killed}" --topic commanded/axis_state:AxisState &
R2=$!
sleep 0.5
"$B/fiveaxis-commander" builtin:paper-sing --use-sim-time --speed 0.5 --min-subscribers 2 &
C=$!
sleep 2.5
date +%s%N > "{kill_ns}"
kill -KILL $R2
wait $C
sleep 0.5
kill -INT $R1
wait $R1
"#,
        b = b.display(),
        full = full.display(),
        killed = killed.display(),
        kill_ns = kill_ns.display()
    );
    let out = netns_bash(&script);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // SIGINT: a complete file with all 1501 samples of the path.
    let data = std::fs::read(&full).unwrap();
    let summary = mcap::Summary::read(&data).unwrap().expect("finished file has a summary");
    assert_eq!(summary.stats.unwrap().message_count, 1501);
    // SIGKILL: recovered up to about a second before the kill.
    let fixed = dir.join("fixed.mcap");
    let report = fiveaxis::record::recover(&killed, &fixed).unwrap();
    let back = std::fs::read(&fixed).unwrap();
    let last_log = mcap::MessageStream::new(&back).unwrap().map(|m| m.unwrap().log_time).max().unwrap();
    let killed_at: u64 = std::fs::read_to_string(&kill_ns).unwrap().trim().parse().unwrap();
    assert!(report.messages > 0);
    assert!(killed_at - last_log < 1_600_000_000, "lost {:.2} s before the kill", (killed_at - last_log) as f64 * 1e-9);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The recorder splits by duration into NAME_0.mcap, NAME_1.mcap, ...: every file complete, every
/// sample in exactly one of them.
#[test]
fn recorder_splits_by_duration() {
    let b = bins();
    let dir = common::scratch_dir("dds-split");
    let script = format!(
        r#"set -e
B="{b}"
"$B/fiveaxis-recorder" --output "{out}" --topic commanded/axis_state:AxisState --split-duration-s 1 &
R=$!
"$B/fiveaxis-commander" builtin:paper-sing --use-sim-time --speed 0.5
sleep 0.5
kill -INT $R
wait $R
"#,
        b = b.display(),
        out = dir.join("run.mcap").display()
    );
    let out = netns_bash(&script);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut total = 0;
    let mut files = 0;
    for k in 0.. {
        let Ok(data) = std::fs::read(dir.join(format!("run_{k}.mcap"))) else { break };
        let summary = mcap::Summary::read(&data).unwrap().expect("each split is a complete file");
        total += summary.stats.unwrap().message_count;
        files += 1;
    }
    assert!(files >= 3, "{files} files for about 4 s of recording");
    assert_eq!(total, 1501);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `fiveaxis-recorder --all` beside an independent Cyclone DDS peer publishing as rmw_cyclonedds
/// does: a rosbag2 directory that rosbags' reader opens, holding the peer's JointState and
/// std_msgs/String (a type fiveaxis has no definition of: stored with an empty one, as `ros2 bag`
/// does) byte for byte as sent, each decoding to the values sent, metadata.yaml's counts matching.
#[test]
fn recorder_all_writes_a_rosbag2_directory_of_what_it_received() {
    let b = bins();
    let dir = common::scratch_dir("dds-bag");
    let (bag, sent) = (dir.join("cell_bag"), dir.join("sent.json"));
    let peer = Path::new(env!("FIVEAXIS_ROOT")).join("tests/peer/bag_peer.py");
    let script = format!(
        r#"set -e
"{b}/fiveaxis-recorder" --all --output "{bag}" --duration-s 15 &
R=$!
python3 "{peer}" publish --out "{sent}" --count 300
kill -INT $R
wait $R
"#,
        b = b.display(),
        bag = bag.display(),
        sent = sent.display(),
        peer = peer.display(),
    );
    let out = netns_bash(&script);
    assert!(out.status.success(), "{}\n{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(bag.join("metadata.yaml").exists() && bag.join("cell_bag_0.mcap").exists());
    let check = Command::new("python3").arg(&peer).arg("check").arg(&bag).arg(&sent).output().expect("python3 runs");
    let report = String::from_utf8_lossy(&check.stdout);
    assert!(check.status.success(), "rosbags: {report}\n{}", String::from_utf8_lossy(&check.stderr));
    let v: serde_json::Value = serde_json::from_str(report.trim()).unwrap();
    assert_eq!(v["version"], 9);
    assert_eq!(v["topics"]["/cnc/joint_states"]["type"], "sensor_msgs/msg/JointState");
    assert_eq!(v["topics"]["/cnc/joint_states"]["definition"], true);
    assert_eq!(v["topics"]["/cnc/joint_states"]["count"], 300);
    assert_eq!(v["topics"]["/chatter"]["type"], "std_msgs/msg/String");
    assert_eq!(v["topics"]["/chatter"]["definition"], false);
    assert_eq!(v["topics"]["/chatter"]["count"], 300);
    // Our own reader takes the directory too.
    let files = fiveaxis::record::read::recording_files(&bag).unwrap();
    assert_eq!(files, vec![bag.join("cell_bag_0.mcap")]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The recorder refuses, before joining DDS, what it cannot record: exit 2 naming the reason.
#[test]
fn recorder_refuses_a_used_bag_directory_and_a_bad_topic() {
    let b = bins();
    let dir = common::scratch_dir("dds-bag-refused");
    std::fs::create_dir_all(dir.join("used")).unwrap();
    std::fs::write(dir.join("used/metadata.yaml"), "rosbag2_bagfile_information: {}\n").unwrap();
    let cases: [(&[&str], &str); 3] = [
        (&["--output", "used"], "not empty"),
        (&["--output", "new", "--topic", "/a"], "expected TOPIC:TYPE"),
        (&["--output", "new", "--topic", "/a:NoSuchType"], "unknown type 'NoSuchType'"),
    ];
    for (args, why) in cases {
        let out = Command::new(b.join("fiveaxis-recorder")).args(args).current_dir(&dir).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(why), "{args:?}: no {why:?} in {err}");
    }
    // Nothing already there was touched, nothing new was made.
    assert_eq!(std::fs::read_to_string(dir.join("used/metadata.yaml")).unwrap(), "rosbag2_bagfile_information: {}\n");
    assert!(!dir.join("new").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The recorder node on a full disk (a 1 MiB tmpfs in a private mount namespace) ends as `fiveaxis
/// run --mcap` does: exit 2 naming the file and the cause, the file closed at its last whole chunk
/// and read through by our reader, as many messages as the error says.
#[test]
fn recorder_on_a_full_disk_exits_2_with_a_closed_readable_file() {
    let b = bins();
    let mnt = common::scratch_dir("dds-full-disk-mnt");
    let out = common::scratch_dir("dds-full-disk-out");
    let script = format!(
        r#"B="{b}"
unshare --mount --map-root-user sh -c 'mount -t tmpfs -o size=1m tmpfs "$1" || exit 99
"$2/fiveaxis-recorder" --output "$1/rec.mcap" --topic commanded/axis_state:AxisState --topic commanded/joint_states:JointState; rc=$?
cp -r "$1/." "$3/"; exit $rc' sh "{mnt}" "$B" "{out}" &
R=$!
sleep 0.5
"$B/fiveaxis-commander" bundled:SING.I --use-sim-time --speed 8 --passes 4 --min-subscribers 1 > /dev/null 2>&1 &
C=$!
# The disk fills within seconds; the commander's four passes (about a minute) only bound the wait.
while kill -0 $R 2> /dev/null && kill -0 $C 2> /dev/null; do sleep 0.1; done
kill $C 2> /dev/null
for i in $(seq 50); do kill -0 $C 2> /dev/null || break; sleep 0.1; done
kill -KILL $C 2> /dev/null; wait $C; echo "commander exit $?" >&2
for i in $(seq 100); do kill -0 $R 2> /dev/null || break; sleep 0.1; done
kill -INT $R 2> /dev/null
wait $R; echo "recorder exit $?" >&2
"#,
        b = b.display(),
        mnt = mnt.display(),
        out = out.display()
    );
    let run = netns_bash(&script);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!stderr.contains("recorder exit 99"), "mounting a tmpfs in a user namespace: {stderr}");
    assert!(stderr.contains("recorder exit 2"), "{stderr}");
    assert!(stderr.contains("No space left on device") && stderr.contains("rec.mcap"), "the error names the file and the cause: {stderr}");
    let kept: u64 = stderr
        .split(" messages), closed and readable")
        .next()
        .and_then(|s| s.rsplit('(').next())
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("the error says how many messages the file kept: {stderr}"));
    let n = fiveaxis::record::read::for_each_message(&out.join("rec.mcap"), |_| {}).unwrap();
    assert!(n > 1000, "most of the 1 MiB holds messages: {n}: {stderr}");
    assert_eq!(n, kept);
    let _ = std::fs::remove_dir_all(&out);
}
