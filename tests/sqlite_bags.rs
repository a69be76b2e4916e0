//! rosbag2's SQLite3 storage (Humble's default) read as MCAP is (issue 66): every SQLite3 bag of
//! `../shared/outside/bags` (rosbag2's own test resources, a real robot arm's Humble recordings)
//! read to as many messages per topic as its `metadata.yaml` says rosbag2 wrote, split files in
//! their order, per-message and whole-file zstd; a bag made by an independent writer (`rosbags`)
//! from LinuxCNC's trace gives the same `analyze` report as its MCAP twin.

use crate::common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A bag's message count per topic as its metadata.yaml says (`topics_with_message_count`: each
/// entry's `name:` and `message_count:`, in whichever order the writer put them), read line by line.
fn metadata_counts(dir: &Path) -> BTreeMap<String, u64> {
    let text = std::fs::read_to_string(dir.join("metadata.yaml")).unwrap();
    let mut out = BTreeMap::new();
    let (mut in_topics, mut entry) = (false, (None::<String>, None::<u64>));
    let flush = |entry: &mut (Option<String>, Option<u64>), out: &mut BTreeMap<String, u64>| {
        if let (Some(n), Some(c)) = std::mem::take(entry) {
            out.insert(n, c);
        }
    };
    for line in text.lines() {
        let indent = line.len() - line.trim_start().len();
        let mut t = line.trim();
        if t.starts_with("topics_with_message_count:") {
            in_topics = true;
            continue;
        }
        if !in_topics || t.is_empty() {
            continue;
        }
        // The list's entries sit deeper than the bag's keys (2 spaces), or at their level behind "- ".
        if indent <= 2 && !t.starts_with('-') {
            in_topics = false;
            continue;
        }
        if let Some(rest) = t.strip_prefix("- ") {
            flush(&mut entry, &mut out);
            t = rest.trim();
        }
        if let Some(n) = t.strip_prefix("name:") {
            entry.0 = Some(n.trim().trim_matches(['"', '\'']).to_string());
        } else if let Some(c) = t.strip_prefix("message_count:") {
            entry.1 = Some(c.trim().parse().unwrap());
        }
    }
    flush(&mut entry, &mut out);
    out
}

/// The SQLite3 bag directories under `root` (a metadata.yaml that says sqlite3 beside its files).
fn sqlite_bags(root: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(root).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            sqlite_bags(&p, out);
        } else if p.file_name().is_some_and(|n| n == "metadata.yaml") && std::fs::read_to_string(&p).unwrap().contains("storage_identifier: sqlite3") {
            out.push(p.parent().unwrap().to_path_buf());
        }
    }
}

#[test]
fn every_sqlite3_bag_reads_to_the_counts_its_metadata_gives() {
    let mut bags = Vec::new();
    sqlite_bags(&common::outside("bags"), &mut bags);
    bags.sort();
    // rosbag2's reindex fixtures keep the metadata reindexing should write apart from their files
    // (target_metadata/NAME/metadata.yaml lists NAME/NAME_0.db3 ...): each read as the bag they make
    // together, through links in a scratch directory (per-message zstd, whole-file zstd, split files).
    let scratch = std::env::temp_dir().join(format!("fiveaxis-sqlite-{}", std::process::id()));
    let mut read = Vec::new();
    for bag in &bags {
        let Some(name) = bag.parent().filter(|p| p.ends_with("target_metadata")).and_then(|_| bag.file_name()) else {
            read.push((bag.clone(), bag.clone()));
            continue;
        };
        let dir = scratch.join(bag.strip_prefix(common::outside("bags")).unwrap());
        std::fs::create_dir_all(&dir).unwrap();
        let files = bag.parent().unwrap().parent().unwrap().join(name);
        let _ = std::os::unix::fs::symlink(bag.join("metadata.yaml"), dir.join("metadata.yaml"));
        // Newer fixtures list NAME/NAME_0.db3, older ones NAME_0.db3: both are linked.
        let _ = std::os::unix::fs::symlink(&files, dir.join(name));
        for f in std::fs::read_dir(&files).unwrap() {
            let f = f.unwrap().path();
            let _ = std::os::unix::fs::symlink(&f, dir.join(f.file_name().unwrap()));
        }
        read.push((bag.clone(), dir));
    }
    let mut checked = (0, 0);
    for (bag, dir) in &read {
        let want = metadata_counts(bag);
        let mut got: BTreeMap<String, u64> = want.keys().map(|k| (k.clone(), 0)).collect();
        // Every CDR message, its zstd undone where the bag compressed it, opens with a CDR
        // encapsulation header (00 01 or 00 00, then two zero bytes), not a zstd frame's magic.
        let mut not_cdr = 0;
        let result = fiveaxis::record::read::for_each_message(dir, |m| {
            *got.entry(m.channel.topic.clone()).or_default() += 1;
            not_cdr += usize::from(m.channel.message_encoding == "cdr" && !(m.data.len() >= 4 && m.data[0] == 0 && m.data[1] <= 1 && m.data[2..4] == [0, 0]));
        });
        assert_eq!(not_cdr, 0, "{}: messages without a CDR header", bag.display());
        let total = result.unwrap_or_else(|e| panic!("{}: {e}", bag.display()));
        assert_eq!(got, want, "{}", bag.display());
        assert_eq!(total, want.values().sum::<u64>(), "{}", bag.display());
        checked = (checked.0 + 1, checked.1 + total);
    }
    let _ = std::fs::remove_dir_all(&scratch);
    assert!(checked.0 >= 27 && checked.1 > 60_000, "{checked:?} bags and messages");
    eprintln!("{} SQLite3 bags, {} messages, each topic's count as its metadata.yaml gives", checked.0, checked.1);
}

/// LinuxCNC's 1 kHz trace of the paper's SING cut written twice by rosbags (tests/peer/
/// trace_to_rosbag.py), as a SQLite3 bag and as an MCAP one, with foreign topics beside it: `fiveaxis
/// analyze` prints the same report for both, byte for byte but for the bag's name, and the same JSON,
/// with the region the MCAP tests check against numpy (tests/machine_trace.rs).
#[test]
fn a_sqlite3_bag_and_its_mcap_twin_give_the_same_analysis() {
    let root = Path::new(env!("FIVEAXIS_ROOT"));
    let write = |storage: &str| -> PathBuf {
        let out = common::scratch_root().join(format!("twin-{storage}"));
        let _ = std::fs::remove_dir_all(&out);
        let st = std::process::Command::new("python3")
            .arg(root.join("tests/peer/trace_to_rosbag.py"))
            .arg(root.join("recordings/machine/linuxcnc/sing_trace.csv.gz"))
            .arg(&out)
            .args(["--storage", storage])
            .status()
            .expect("python3 runs (rosbags comes from launch-free-scripts/test)");
        assert!(st.success(), "trace_to_rosbag.py --storage {storage} failed");
        out
    };
    let (sqlite, mcap) = (write("sqlite3"), write("mcap"));
    assert!(std::fs::read_dir(&sqlite).unwrap().any(|e| e.unwrap().path().extension().is_some_and(|x| x == "db3")), "rosbags wrote a .db3");
    let analyze = |bag: &Path| -> (i32, String, String) {
        let json = bag.with_extension("json");
        let mut args = vec!["analyze", bag.to_str().unwrap(), "--joint-state-topic", "/cnc/joint_states", "--machine", "hermle-c600u", "--program", "bundled:SING.I", "--max-c-speed-rpm", "25", "--json", json.to_str().unwrap()];
        for m in ["X=x_joint", "Y=y_joint", "Z=z_joint", "A=a_joint", "C=c_joint"] {
            args.extend(["--axis-map", m]);
        }
        let out = std::process::Command::new(env!("FIVEAXIS_EXE")).args(&args).current_dir(root).output().unwrap();
        let name = bag.to_str().unwrap();
        let text = String::from_utf8_lossy(&out.stdout).replace(name, "BAG");
        let json = std::fs::read_to_string(&json).unwrap().replace(name, "BAG");
        (out.status.code().unwrap_or(-1), text, json)
    };
    let (a, b) = (analyze(&sqlite), analyze(&mcap));
    assert_eq!(a.0, 1, "the SING cut asks more than 25 rpm: exit 1\n{}", a.1);
    assert_eq!(a.1, b.1, "the reports differ");
    assert_eq!(a.2, b.2, "the JSON reports differ");
    let v: serde_json::Value = serde_json::from_str(&a.2).unwrap();
    let r = &v["regions"][0];
    assert!(v["regions"].as_array().unwrap().len() == 1 && (r["x_start_mm"].as_f64().unwrap() - 22.0).abs() < 1.0 && (r["x_end_mm"].as_f64().unwrap() - 28.0).abs() < 1.0, "{r:#}");
}

/// A damaged SQLite3 file (bytes cut, flipped or not a database at all) is refused naming the file,
/// never a panic; the messages before the damage were visited.
#[test]
fn damaged_sqlite3_files_are_refused_naming_the_file() {
    let source = common::outside("bags/rosbag2/rosbag2_py/test/resources/sqlite3/talker/talker.db3");
    let bytes = std::fs::read(&source).unwrap();
    let dir = common::scratch_root().join("sqlite-damage");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut seed = 0x5EED_u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    let mut refused = 0;
    for k in 0..40 {
        let mut b = bytes.clone();
        match k % 4 {
            0 => b.truncate((next() as usize) % b.len()),
            1 => {
                for _ in 0..16 {
                    let i = (next() as usize) % b.len();
                    b[i] ^= 1 << (next() % 8);
                }
            }
            2 => b = b"not a database at all".to_vec(),
            _ => b.iter_mut().skip(100).step_by(97).for_each(|x| *x = !*x),
        }
        let f = dir.join(format!("damaged_{k}.db3"));
        std::fs::write(&f, &b).unwrap();
        match fiveaxis::record::read::for_each_message(&f, |_| {}) {
            Ok(_) => {}
            Err(e) => {
                assert!(e.to_string().contains(&format!("damaged_{k}.db3")), "{e}");
                refused += 1;
            }
        }
    }
    assert!(refused >= 10, "{refused} of 40 damaged files refused");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A bag directory without metadata.yaml (a recorder killed before writing it) is read as its
/// `.db3` files in split order: `_10` after `_9`, whole-file zstd (`.db3.zstd`) as well. Eleven splits
/// of rosbag2's talker fixture, compressed here as talker_0.db3.zstd .. talker_10.db3.zstd, read to
/// eleven times its messages, in that order.
#[test]
fn a_bag_without_metadata_reads_its_splits_in_order() {
    let source = common::outside("bags/rosbag2/rosbag2_py/test/resources/sqlite3/talker/talker.db3");
    let dir = common::scratch_root().join("sqlite-splits");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let packed = zstd::encode_all(std::fs::read(&source).unwrap().as_slice(), 3).unwrap();
    for k in 0..11 {
        std::fs::write(dir.join(format!("talker_{k}.db3.zstd")), &packed).unwrap();
    }
    let files = fiveaxis::record::read::recording_files(&dir).unwrap();
    let names: Vec<String> = files.iter().map(|f| f.file_name().unwrap().to_string_lossy().into_owned()).collect();
    let want: Vec<String> = (0..11).map(|k| format!("talker_{k}.db3.zstd")).collect();
    assert_eq!(names, want);
    let mut files_seen = Vec::new();
    let n = fiveaxis::record::read::for_each_message(&dir, |m| {
        if files_seen.last() != Some(&m.file) {
            files_seen.push(m.file);
        }
    })
    .unwrap();
    assert_eq!(n, 11 * 20);
    assert_eq!(files_seen, (0..11).collect::<Vec<_>>());
    let _ = std::fs::remove_dir_all(&dir);
}
