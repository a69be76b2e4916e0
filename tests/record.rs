//! Recordings: the MCAP layout rosbag2 readers expect, read back by the mcap crate and by an
//! independent Python reader; recovery after a kill; the offline analysis and its exit codes.

use crate::common;
use fiveaxis::live::inprocess::{run, RunOptions};
use fiveaxis::topics;
use fiveaxis::machine::Machine;
use fiveaxis::record::{from_cdr, recover, OfferedQos, RecordOptions, Recorder, CDR_LE};
use fiveaxis_msgs::{schema, AxisState, JointState, RosMessage, SingularityStatus, Time};
use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    common::scratch_path("record", name)
}

fn record(spec: &str, path: &Path) -> fiveaxis::live::inprocess::RunOutput {
    let options = RunOptions { mcap: Some(path.to_path_buf()), ..Default::default() };
    run(spec, &Machine::hermle_c600u(), &options).unwrap()
}

#[test]
fn rosbag2_layout_and_every_message_read_back() {
    let path = tmp("sing.mcap");
    let out = record("bundled:SING.I", &path);
    let data = std::fs::read(&path).unwrap();
    let summary = mcap::Summary::read(&data).unwrap().expect("a summary");
    let stats = summary.stats.as_ref().expect("statistics");
    assert_eq!(Some(stats.message_count), out.recorded_messages);
    assert!(!summary.chunk_indexes.is_empty());
    assert!(summary.chunk_indexes.iter().all(|c| c.compression == "zstd"));
    for ch in summary.channels.values() {
        let s = ch.schema.as_ref().unwrap();
        assert_eq!(s.encoding, "ros2msg");
        assert_eq!(ch.message_encoding, "cdr");
        assert!(s.name.contains("/msg/"), "{}", s.name);
        assert_eq!(std::str::from_utf8(&s.data).unwrap(), schema::ros2msg(&s.name).unwrap());
        assert!(ch.metadata["offered_qos_profiles"].contains("reliability:"), "{:?}", ch.metadata);
    }
    // Every commanded state decodes to the value the commander produces from the program read whole
    // (the run streamed it); publish time = its stamp.
    let job = fiveaxis::job::run("bundled:SING.I", &Machine::hermle_c600u(), &Default::default()).unwrap();
    let commanded = fiveaxis::live::commander::commanded_states(&job.trajectory, &Machine::hermle_c600u());
    let mut k = 0;
    for msg in mcap::MessageStream::new(&data).unwrap() {
        let msg = msg.unwrap();
        assert_eq!(msg.data[..4], CDR_LE);
        if msg.channel.topic == topics::COMMANDED_STATE.absolute {
            let st: AxisState = from_cdr(&msg.data).unwrap();
            assert_eq!(st, commanded[k]);
            assert_eq!(msg.publish_time, st.header.stamp.as_nanos());
            k += 1;
        }
        if msg.channel.topic == topics::STATUS.absolute {
            let _: SingularityStatus = from_cdr(&msg.data).unwrap();
        }
    }
    assert_eq!(k, commanded.len());
}

/// An independent reader (Foxglove's mcap-ros2-support, decoding from the stored ros2msg schemas)
/// decodes every message, and sampled values equal ours. Installed by launch-free-scripts/test.
#[test]
fn independent_python_reader_decodes_every_message() {
    let path = tmp("nonsing.mcap");
    let _ = record("bundled:NON_SING.I", &path);
    let m = Machine::hermle_c600u();
    let job = fiveaxis::job::run("bundled:NON_SING.I", &m, &Default::default()).unwrap();
    let commanded = fiveaxis::live::commander::commanded_states(&job.trajectory, &m);
    let mut expected = serde_json::Map::new();
    let mut samples = serde_json::Map::new();
    for k in (0..commanded.len()).step_by(997) {
        let s = &commanded[k];
        samples.insert(
            k.to_string(),
            serde_json::json!({
                "position": s.position, "velocity": s.velocity, "name": s.name,
                "programmed_feed": s.programmed_feed, "block_number": s.block_number, "program_line": s.program_line,
                "tool_tip": {"x": s.tool_tip.x, "y": s.tool_tip.y, "z": s.tool_tip.z},
            }),
        );
    }
    expected.insert(topics::COMMANDED_STATE.absolute.into(), serde_json::json!({"count": commanded.len(), "samples": samples}));
    let js: Vec<JointState> = commanded.iter().map(AxisState::to_joint_state).collect();
    expected.insert(
        topics::COMMANDED_JOINTS.absolute.into(),
        serde_json::json!({"count": js.len(), "samples": {"1234": {"name": js[1234].name, "position": js[1234].position}}}),
    );
    let exp = tmp("expected.json");
    std::fs::write(&exp, serde_json::Value::Object(expected).to_string()).unwrap();
    let script = Path::new(env!("FIVEAXIS_ROOT")).join("tests/peer/check_mcap.py");
    let out = Command::new("python3").arg(&script).arg(&path).arg(&exp).output().expect("python3 runs");
    assert!(
        out.status.success(),
        "independent reader: {}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A recorder killed mid-run (the file cut short anywhere) is recovered with every complete chunk:
/// chunks close every second of log time, so at most the last second is lost.
#[test]
fn recovery_keeps_every_complete_chunk() {
    let path = tmp("cut.mcap");
    let mut rec = Recorder::create(&path, RecordOptions::default()).unwrap();
    let ch = rec.add_topic::<AxisState>(topics::SIMULATED_STATE.absolute, OfferedQos::STATE).unwrap();
    let n = 5000u64;
    for k in 0..n {
        let st = AxisState {
            header: fiveaxis_msgs::Header { stamp: Time::from_secs(k as f64 * 1e-3), frame_id: String::new() },
            position: vec![k as f64 * 1e-6; 5],
            ..Default::default()
        };
        rec.write(ch, &st, k * 1_000_000, k * 1_000_000).unwrap();
    }
    rec.finish().unwrap();
    let data = std::fs::read(&path).unwrap();
    let summary = mcap::Summary::read(&data).unwrap().unwrap();
    let chunks = &summary.chunk_indexes;
    assert!(chunks.len() >= 5, "a chunk per second: {}", chunks.len());
    for (i, c) in chunks.iter().enumerate().take(chunks.len() - 1) {
        // Cut inside chunk i+1: everything up to the end of chunk i survives.
        let cut = (chunks[i + 1].chunk_start_offset + chunks[i + 1].chunk_length / 2) as usize;
        let damaged = tmp(&format!("cut-{i}.mcap"));
        std::fs::write(&damaged, &data[..cut]).unwrap();
        let fixed = tmp(&format!("fixed-{i}.mcap"));
        let report = recover(&damaged, &fixed).unwrap();
        let kept = (c.message_end_time / 1_000_000) + 1;
        assert_eq!(report.messages, kept, "cut in chunk {}: {report:?}", i + 1);
        assert!(report.stopped.is_some());
        // The recovered file is complete and reads back in full, values intact.
        let back = std::fs::read(&fixed).unwrap();
        let msgs: Vec<_> = mcap::MessageStream::new(&back).unwrap().map(|m| m.unwrap()).collect();
        assert_eq!(msgs.len() as u64, kept);
        let last: AxisState = from_cdr(&msgs.last().unwrap().data).unwrap();
        assert_eq!(last.position[0], (kept - 1) as f64 * 1e-6);
        assert!(mcap::Summary::read(&back).unwrap().is_some());
    }
    // An unwritable path is a clear error naming it.
    let err = Recorder::create(Path::new("/proc/no/such/dir/x.mcap"), RecordOptions::default()).err().unwrap();
    assert!(err.to_string().contains("/proc/no/such/dir/x.mcap"), "{err}");
}

fn fiveaxis(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("FIVEAXIS_EXE")).args(args).output().unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stdout).into())
}

#[test]
fn offline_analysis_exit_codes_and_json() {
    let sing = tmp("a-sing.mcap");
    record("bundled:SING.I", &sing);
    let json = tmp("a-sing.json");
    let (code, _) = fiveaxis(&["analyze", sing.to_str().unwrap(), "--max-c-speed-rpm", "25", "--json", json.to_str().unwrap()]);
    assert_eq!(code, 1, "SING violates 25 rpm");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert!(v["messages_read"].as_u64().unwrap() > 100_000);
    assert!(!v["violations"].as_array().unwrap().is_empty());
    let r = &v["regions"][0];
    // The program's region (commanded stream, the reference 22-28 mm: the first sample past x = 22
    // opens it), with what the simulated machine did there: the stutter and the time it cost.
    assert!((r["x_start_mm"].as_f64().unwrap() - 22.0).abs() < 0.05 && (r["x_end_mm"].as_f64().unwrap() - 28.0).abs() < 0.05, "{r}");
    assert!((r["peak_c_speed_rpm"].as_f64().unwrap() - 175.0).abs() < 0.5, "{r}");
    assert_eq!(r["actual_topic"], topics::SIMULATED_STATE.absolute);
    assert!(r["lowest_feed_mm_per_min"].as_f64().unwrap() < 0.5 * 2000.0, "{r}");
    assert!(r["time_lost_s"].as_f64().unwrap() > 0.5, "{r}");
    // The simulated stream's own region: the blended path's 21.6-28.4 mm.
    let sim = v["streams"].as_array().unwrap().iter().find(|s| s["topic"] == topics::SIMULATED_STATE.absolute).unwrap();
    let sr = &sim["regions"][0];
    assert!((sr["x_start_mm"].as_f64().unwrap() - 21.6).abs() < 0.1 && (sr["x_end_mm"].as_f64().unwrap() - 28.4).abs() < 0.1, "{sr}");
    let nonsing = tmp("a-nonsing.mcap");
    record("bundled:NON_SING.I", &nonsing);
    let junit = tmp("a-nonsing.xml");
    let (code, _) = fiveaxis(&["analyze", nonsing.to_str().unwrap(), "--max-c-speed-rpm", "25", "--min-distance-deg", "5", "--junit", junit.to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(std::fs::read_to_string(&junit).unwrap().contains("failures=\"0\""));
    // SING's JUnit report, read back by Python's XML parser: one suite, two cases per stream of the
    // JSON report, a failure for each stream's C-speed check with the violation's own text.
    let junit = tmp("a-sing.xml");
    let (code, _) = fiveaxis(&["analyze", sing.to_str().unwrap(), "--max-c-speed-rpm", "25", "--junit", junit.to_str().unwrap()]);
    assert_eq!(code, 1);
    let read = "import json, sys, xml.etree.ElementTree as ET\nroot = ET.parse(sys.argv[1]).getroot()\nsuites = root.findall('testsuite')\nprint(json.dumps({'root': root.tag, 'suites': [{'name': s.get('name'), 'tests': int(s.get('tests')), 'failures': int(s.get('failures')), 'cases': [[c.get('name'), [f.get('message') for f in c.findall('failure')]] for c in s.findall('testcase')]} for s in suites]}))";
    let out = Command::new("python3").args(["-c", read, junit.to_str().unwrap()]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let x: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(x["root"], "testsuites");
    let suite = &x["suites"][0];
    let streams = v["streams"].as_array().unwrap();
    assert_eq!(suite["tests"].as_u64().unwrap() as usize, 2 * streams.len());
    assert_eq!(suite["cases"].as_array().unwrap().len(), 2 * streams.len());
    let failing: Vec<&serde_json::Value> = suite["cases"].as_array().unwrap().iter().filter(|c| !c[1].as_array().unwrap().is_empty()).collect();
    assert_eq!(suite["failures"].as_u64().unwrap() as usize, failing.len());
    let violations: Vec<&str> = v["violations"].as_array().unwrap().iter().map(|s| s.as_str().unwrap()).collect();
    for s in streams {
        let topic = s["topic"].as_str().unwrap();
        let c_speed = suite["cases"].as_array().unwrap().iter().find(|c| c[0] == format!("{topic}:c_speed").as_str()).unwrap();
        let expected = violations.iter().find(|m| m.starts_with(&format!("{topic}:")) && m.contains("predicted C speed"));
        assert_eq!(c_speed[1].as_array().unwrap().first().and_then(|m| m.as_str()), expected.copied(), "{topic}");
    }
    assert!(!failing.is_empty(), "SING fails its C-speed check");
    let bad = tmp("bad.mcap");
    std::fs::write(&bad, b"not an mcap file").unwrap();
    assert_eq!(fiveaxis(&["analyze", bad.to_str().unwrap()]).0, 2);
    assert_eq!(fiveaxis(&["analyze", "/no/such/file.mcap"]).0, 2);

    // Several recordings at once, in parallel: each report is the one it gets alone, the exit code is
    // the worst, the summary names each.
    let many = tmp("many.json");
    let (s, n) = (sing.to_str().unwrap(), nonsing.to_str().unwrap());
    let (code, table) = fiveaxis(&["analyze", n, s, "--max-c-speed-rpm", "25", "--jobs", "2", "--json", many.to_str().unwrap()]);
    assert_eq!(code, 1, "{table}");
    let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&many).unwrap()).unwrap();
    assert_eq!(m["recordings"][1], v, "SING's report among several is its report alone");
    assert_eq!(m["recordings"][0]["file"], n);
    let codes: Vec<u64> = m["summary"].as_array().unwrap().iter().map(|x| x["exit_code"].as_u64().unwrap()).collect();
    assert_eq!(codes, [0, 1]);
    assert!(table.contains("summary of 2 recordings"), "{table}");
    let (code, _) = fiveaxis(&["analyze", n, bad.to_str().unwrap(), s, "--json", many.to_str().unwrap()]);
    assert_eq!(code, 2, "an unreadable recording among several");
    let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&many).unwrap()).unwrap();
    assert_eq!(m["recordings"].as_array().unwrap().len(), 2, "the readable two are still reported");
    assert!(m["summary"][1]["error"].is_string());
    // A directory of recordings: each .mcap file in it on its own.
    let dir = tmp("all-in");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(&sing, dir.join("1.mcap")).unwrap();
    std::fs::copy(&nonsing, dir.join("2.mcap")).unwrap();
    let (code, table) = fiveaxis(&["analyze", "--all-in", dir.to_str().unwrap(), "--max-c-speed-rpm", "25"]);
    assert_eq!(code, 1, "{table}");
    assert!(table.contains("summary of 2 recordings"), "{table}");
    let empty = tmp("all-in-empty");
    std::fs::create_dir_all(&empty).unwrap();
    assert_eq!(fiveaxis(&["analyze", "--all-in", empty.to_str().unwrap()]).0, 2, "a directory with no recording");
}

#[test]
fn type_names_follow_rosbag2() {
    assert_eq!(AxisState::type_name(), "fiveaxis_msgs/msg/AxisState");
    assert_eq!(JointState::type_name(), "sensor_msgs/msg/JointState");
}

/// The analysis' streaming reader (whole-chunk zstd, borrowed messages) against the mcap crate's
/// own MessageStream: the same messages in the same order, byte for byte. On damage it stops with an
/// error naming the chunk after visiting every message before it, and the analysis keeps those.
#[test]
fn streaming_reader_agrees_with_the_mcap_crate_and_stops_at_damage() {
    use fiveaxis::record::read::{for_each_message, summary_channels};
    let path = tmp("stream.mcap");
    record("bundled:SING.I", &path);
    let data = std::fs::read(&path).unwrap();
    let theirs: Vec<_> = mcap::MessageStream::new(&data).unwrap().map(|m| m.unwrap()).collect();
    let mut k = 0usize;
    let n = for_each_message(&path, |m| {
        let t = &theirs[k];
        assert_eq!(m.channel.topic, t.channel.topic);
        assert_eq!(m.channel.schema_name, t.channel.schema.as_ref().unwrap().name);
        assert_eq!(m.channel.message_encoding, t.channel.message_encoding);
        assert_eq!((m.sequence, m.log_time, m.publish_time), (t.sequence, t.log_time, t.publish_time));
        assert_eq!(m.data, &t.data[..]);
        k += 1;
    })
    .unwrap();
    assert_eq!((n as usize, k), (theirs.len(), theirs.len()));
    let channels = summary_channels(&path).unwrap().expect("a summary");
    let summary = mcap::Summary::read(&data).unwrap().unwrap();
    assert_eq!(channels.len(), summary.channels.len());
    for c in &channels {
        assert_eq!(c.topic, summary.channels[&c.id].topic);
    }

    // Cut inside a chunk in the middle: every message of the chunks before it, then the error.
    let chunks = &summary.chunk_indexes;
    assert!(chunks.len() >= 4, "{} chunks", chunks.len());
    let i = chunks.len() / 2;
    let before: u64 = {
        let end = chunks[i].chunk_start_offset;
        // Messages of complete chunks = those the mcap crate reads from a copy cut at chunk i.
        mcap::read::LinearReader::new_with_options(&data[..end as usize], enumset::enum_set!(mcap::read::Options::IgnoreEndMagic))
            .unwrap()
            .filter_map(|r| match r.ok()? {
                mcap::records::Record::Chunk { header, data } => {
                    Some(mcap::read::ChunkReader::new(header, &data).unwrap().filter(|r| matches!(r, Ok(mcap::records::Record::Message { .. }))).count() as u64)
                }
                _ => None,
            })
            .sum()
    };
    assert!(before > 1000);
    let cut = tmp("stream-cut.mcap");
    std::fs::write(&cut, &data[..(chunks[i].chunk_start_offset + chunks[i].chunk_length / 2) as usize]).unwrap();
    let mut seen = 0u64;
    let err = for_each_message(&cut, |_| seen += 1).unwrap_err();
    assert_eq!(seen, before, "{err}");
    assert!(err.to_string().contains("stream-cut.mcap"), "{err}");
    assert_eq!(summary_channels(&cut).unwrap(), None, "a cut file has no summary");

    // A damaged byte inside a chunk's compressed records: that chunk is refused as a whole.
    let mut flipped = data.clone();
    let mid = (chunks[i].chunk_start_offset + chunks[i].chunk_length / 2) as usize;
    flipped[mid] ^= 0x5a;
    let bad = tmp("stream-flipped.mcap");
    std::fs::write(&bad, &flipped).unwrap();
    let mut seen = 0u64;
    let err = for_each_message(&bad, |_| seen += 1).unwrap_err();
    assert_eq!(seen, before, "{err}");
    assert!(err.to_string().contains("chunk starting at log time"), "{err}");

    // The analysis keeps what came before the damage, says where it stopped, and exits 2.
    let json = tmp("stream-cut.json");
    let (code, table) = fiveaxis(&["analyze", cut.to_str().unwrap(), "--json", json.to_str().unwrap()]);
    assert_eq!(code, 2, "{table}");
    assert!(table.contains("DAMAGED"), "{table}");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["messages_read"].as_u64(), Some(before));
    assert!(v["damage"].as_str().is_some_and(|d| d.contains("chunk") || d.contains("MCAP")), "{}", v["damage"]);
    assert!(v["streams"].as_array().is_some_and(|s| !s.is_empty()));
}

/// Each of the program's regions is measured on its own pass: a raster that crosses the singular
/// stretch twice (there at y 0, back at y 1 mm) has two regions at the same x, each losing what one
/// pass alone loses (the second pass is not counted in the first region, nor the time between). So
/// too from the run's JointState stream aligned with the program (`--program`): its program lines
/// come from the alignment, not from the simulator's own messages.
#[test]
fn each_region_is_measured_on_its_own_pass() {
    let pass = |y: f64, forward: bool| -> String {
        (0..=500)
            .map(|k| {
                let x = if forward { k } else { 500 - k } as f64 * 0.1;
                let a = fiveaxis::path::paper_orientation(12.0, x);
                format!("{x:.4},{y},-8,{:.9},{:.9},{:.9}\n", a.x, a.y, a.z)
            })
            .collect()
    };
    // Time lost per region, with the actual stream each comes from: the simulated AxisState stream,
    // and with `--program` the simulated JointState stream aligned with the program.
    let lost = |text: String, name: &str| -> [Vec<(f64, String)>; 2] {
        let cl = tmp(&format!("{name}.cl"));
        std::fs::write(&cl, format!("x,y,z,i,j,k\n{text}")).unwrap();
        let mcap = tmp(&format!("{name}.mcap"));
        record(cl.to_str().unwrap(), &mcap);
        let json = tmp(&format!("{name}.json"));
        let aligned = ["--program", cl.to_str().unwrap(), "--joint-state-topic", "/fiveaxis/simulated/joint_states"];
        [&[][..], &aligned[..]].map(|extra| {
            let mut args = vec!["analyze", mcap.to_str().unwrap(), "--json", json.to_str().unwrap()];
            args.extend(extra);
            let (code, table) = fiveaxis(&args);
            assert_eq!(code, 0, "{table}");
            let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
            v["regions"].as_array().unwrap().iter().map(|r| (r["time_lost_s"].as_f64().unwrap(), r["actual_topic"].as_str().unwrap().to_string())).collect()
        })
    };
    let [one, one_aligned] = lost(pass(0.0, true), "one-pass");
    assert_eq!((one.len(), one_aligned.len()), (1, 1), "{one:?} {one_aligned:?}");
    assert!(one[0].0 > 0.1, "the pass loses time in the region: {one:?}");
    assert_eq!((one[0].1.as_str(), one_aligned[0].1.as_str()), ("/fiveaxis/simulated/axis_state", "/fiveaxis/simulated/joint_states"));
    let two = lost(pass(0.0, true) + &pass(1.0, false), "two-passes");
    for regions in &two {
        assert_eq!(regions.len(), 2, "{regions:?}");
        for (l, topic) in regions {
            assert!((l - one[0].0).abs() < 0.3 * one[0].0, "{topic}: a region's time lost {l} s, one pass alone {} s", one[0].0);
        }
    }
}

/// Offset of the first chunk record's `uncompressed_size` field (MCAP: magic, then opcode u8, length
/// u64 and body per record; a chunk's body starts with start time u64, end time u64, uncompressed size).
fn first_chunk_size_field(data: &[u8]) -> usize {
    let mut at = 8;
    loop {
        let len = u64::from_le_bytes(data[at + 1..at + 9].try_into().unwrap()) as usize;
        if data[at] == 0x06 {
            return at + 9 + 16;
        }
        at += 9 + len;
    }
}

/// A damaged chunk header (issue 15): a claim of 4 GiB uncompressed is refused before anything is
/// allocated (it was reserved before), and a claim of 100 MiB that the data does not hold is found
/// out by decompressing as a stream, not by reserving the claim; both exit 2 naming the chunk.
#[test]
fn chunk_size_claims_are_bounded_before_allocating() {
    let path = tmp("claims.mcap");
    record("builtin:paper-sing", &path);
    let data = std::fs::read(&path).unwrap();
    let field = first_chunk_size_field(&data);
    let real = u64::from_le_bytes(data[field..field + 8].try_into().unwrap());
    assert!(real > 0 && real < 16 << 20, "a normal chunk: {real} bytes");
    for (claim, want) in [(4u64 << 30, "claims 4294967296 bytes uncompressed".to_string()), (100 << 20, format!("{real} bytes uncompressed, header says 104857600"))] {
        let mut bad = data.clone();
        bad[field..field + 8].copy_from_slice(&claim.to_le_bytes());
        let p = tmp(&format!("claim-{claim}.mcap"));
        std::fs::write(&p, &bad).unwrap();
        let out = Command::new(env!("FIVEAXIS_EXE")).args(["analyze", p.to_str().unwrap()]).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr).to_string() + &String::from_utf8_lossy(&out.stdout);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains(&want) && err.contains("chunk starting at log time"), "no '{want}' in: {err}");
    }
}

/// LZ4 chunks (issue 15: rosbag2 and the mcap CLI can write them; they were refused): the SING run
/// rewritten by Foxglove's Python `mcap` writer with LZ4 chunks analyses to the same report as our zstd
/// original, and a copy cut inside a chunk is recovered to every complete chunk.
#[test]
fn lz4_chunks_read_like_zstd_ones() {
    let zstd = tmp("lz4-src.mcap");
    record("bundled:SING.I", &zstd);
    let lz4 = tmp("lz4.mcap");
    let out = Command::new("python3")
        .arg(Path::new(env!("FIVEAXIS_ROOT")).join("tests/peer/rechunk_mcap.py"))
        .args([zstd.to_str().unwrap(), lz4.to_str().unwrap(), "lz4", "262144"])
        .output()
        .expect("python3 runs (mcap comes with mcap-ros2-support from launch-free-scripts/test)");
    let said = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(out.status.success(), "rechunk_mcap.py: {}", String::from_utf8_lossy(&out.stderr));
    let fields: Vec<&str> = said.split_whitespace().collect();
    assert_eq!(fields.first(), Some(&"lz4"), "the rewritten file's chunks: {said}");
    let chunks: usize = fields[1].parse().unwrap();
    assert!(chunks >= 4, "several chunks: {said}");
    let report = |p: &Path, tag: &str| -> serde_json::Value {
        let json = tmp(&format!("lz4-{tag}.json"));
        let (code, _) = fiveaxis(&["analyze", p.to_str().unwrap(), "--max-c-speed-rpm", "25", "--json", json.to_str().unwrap()]);
        assert_eq!(code, 1, "{tag}: SING violates 25 rpm");
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap()
    };
    let (a, b) = (report(&zstd, "zstd"), report(&lz4, "lz4"));
    assert_eq!(b["messages_read"], a["messages_read"]);
    assert_eq!(b["messages_read"].as_u64(), fields[2].parse().ok(), "every message the writer wrote was read");
    assert_eq!(b["regions"], a["regions"], "the same regions from LZ4 chunks");
    assert_eq!(b["violations"], a["violations"]);
    // Cut inside the third chunk: recovery keeps the complete ones, and they analyse.
    let data = std::fs::read(&lz4).unwrap();
    let summary = mcap::Summary::read(&data).unwrap().unwrap();
    let c = &summary.chunk_indexes[2];
    let cut = tmp("lz4-cut.mcap");
    std::fs::write(&cut, &data[..(c.chunk_start_offset + c.chunk_length / 2) as usize]).unwrap();
    let fixed = tmp("lz4-fixed.mcap");
    let rep = recover(&cut, &fixed).unwrap();
    assert!(rep.stopped.is_some(), "{rep:?}");
    // The messages of the first two chunks, as the mcap crate (its own LZ4 decoder) reads the file
    // cut at the third chunk's start.
    let whole: u64 = mcap::MessageStream::new(&data[..c.chunk_start_offset as usize]).unwrap().take_while(Result::is_ok).count() as u64;
    assert!(whole > 0);
    assert_eq!(rep.messages, whole, "{rep:?}");
    let back = std::fs::read(&fixed).unwrap();
    // Every message of the fixed file decodes (an error anywhere fails), and there are as many.
    let mut read = 0u64;
    for m in mcap::MessageStream::new(&back).unwrap() {
        m.unwrap();
        read += 1;
    }
    assert_eq!(read, whole);
}

/// `run` into a bag directory (no `.mcap` name): rosbag2's layout (metadata.yaml version 9 and
/// NAME_0.mcap), which rosbags' reader opens and decodes whole, with as many commanded states as
/// the commander makes of the program read whole; `analyze` takes the directory as it takes the file.
#[test]
fn run_writes_a_rosbag2_directory_rosbags_reads() {
    let bag = tmp("sing_bag");
    let out = record("bundled:SING.I", &bag);
    let files: Vec<String> = std::fs::read_dir(&bag).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    let mut files = files;
    files.sort();
    assert_eq!(files, ["metadata.yaml", "sing_bag_0.mcap"]);
    let peer = Path::new(env!("FIVEAXIS_ROOT")).join("tests/peer/bag_peer.py");
    let check = Command::new("python3").arg(&peer).arg("check").arg(&bag).arg("-").output().expect("python3 runs");
    let report = String::from_utf8_lossy(&check.stdout);
    assert!(check.status.success(), "rosbags: {report}\n{}", String::from_utf8_lossy(&check.stderr));
    let v: serde_json::Value = serde_json::from_str(report.trim()).unwrap();
    assert_eq!(v["version"], 9);
    let job = fiveaxis::job::run("bundled:SING.I", &Machine::hermle_c600u(), &Default::default()).unwrap();
    let commanded = fiveaxis::live::commander::commanded_states(&job.trajectory, &Machine::hermle_c600u());
    assert_eq!(v["topics"][topics::COMMANDED_STATE.absolute]["count"].as_u64(), Some(commanded.len() as u64));
    assert_eq!(v["topics"][topics::COMMANDED_STATE.absolute]["type"], "fiveaxis_msgs/msg/AxisState");
    assert_eq!(v["topics"][topics::COMMANDED_JOINTS.absolute]["count"].as_u64(), Some(commanded.len() as u64));
    let total: u64 = v["topics"].as_object().unwrap().values().map(|t| t["count"].as_u64().unwrap()).sum();
    assert_eq!(Some(total), out.recorded_messages);
    // The same verdict from the directory as from a bare file of the same run.
    let file = tmp("sing_file.mcap");
    let _ = record("bundled:SING.I", &file);
    let (jd, jf) = (tmp("sing_bag.json"), tmp("sing_file.json"));
    let (code_dir, _) = fiveaxis(&["analyze", bag.to_str().unwrap(), "--max-c-speed-rpm", "25", "--json", jd.to_str().unwrap()]);
    let (code_file, _) = fiveaxis(&["analyze", file.to_str().unwrap(), "--max-c-speed-rpm", "25", "--json", jf.to_str().unwrap()]);
    assert_eq!((code_dir, code_file), (1, 1), "SING violates 25 rpm, from either");
    let read = |p: &Path| -> serde_json::Value { serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap() };
    let (a, b) = (read(&jd), read(&jf));
    assert_eq!(a["messages_read"], b["messages_read"]);
    assert_eq!(a["regions"], b["regions"]);
}

/// What Foxglove's Python stream reader (tests/peer/read_linear.py) finds in a file, front to back:
/// (topic, log time, data MD5) per message; None if it does not read through to a footer.
fn read_linear(path: &Path) -> Option<Vec<(String, u64, String)>> {
    let script = Path::new(env!("FIVEAXIS_ROOT")).join("tests/peer/read_linear.py");
    let out = Command::new("python3").arg(&script).arg(path).output().expect("python3 runs");
    if !out.status.success() {
        return None;
    }
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    Some(
        v["messages"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| (m[0].as_str().unwrap().to_string(), m[1].as_u64().unwrap(), m[2].as_str().unwrap().to_string()))
            .collect(),
    )
}

/// The recorder on a full disk (a 1 MiB tmpfs mounted in a private mount namespace): `fiveaxis
/// run --mcap` ends with an error naming the file and the cause, and leaves the file closed at its
/// last whole chunk. An independent stream reader reads it through to its footer without error;
/// its messages are exactly the first ones of the same run recorded on a roomy disk, as many as
/// the error says; `analyze` takes it. The same for a rosbag2 directory, whose metadata.yaml then
/// lists the file with what it kept.
#[test]
fn full_disk_ends_with_a_clear_error_and_a_readable_file() {
    let full = tmp("roomy.mcap");
    let _ = record("bundled:SING.I", &full);
    let reference = read_linear(&full).expect("the roomy recording reads");
    for (name, inner) in [("disk_file", "sing.mcap"), ("disk_dir", "bag")] {
        let mnt = common::scratch_dir(&format!("record/{name}_mnt"));
        let out = common::scratch_dir(&format!("record/{name}_out"));
        let script = r#"mount -t tmpfs -o size=1m tmpfs "$1" || exit 99
"$2" run bundled:SING.I --mcap "$1/$4"; rc=$?
cp -r "$1/." "$3/"; exit $rc"#;
        let run = Command::new("unshare")
            .args(["--mount", "--map-root-user", "sh", "-c", script, "sh"])
            .args([mnt.to_str().unwrap(), env!("FIVEAXIS_EXE"), out.to_str().unwrap(), inner])
            .output()
            .expect("unshare runs (util-linux)");
        let stderr = String::from_utf8_lossy(&run.stderr);
        let code = run.status.code();
        assert_ne!(code, Some(99), "mounting a tmpfs in a user namespace: {stderr}");
        assert_eq!(code, Some(2), "{name}: an output that cannot be written is exit 2: {stderr}");
        assert!(stderr.contains("No space left on device") && stderr.contains(inner), "{name}: the error names the file and the cause: {stderr}");
        let kept: usize = stderr
            .split(" messages), closed and readable")
            .next()
            .and_then(|s| s.rsplit('(').next())
            .and_then(|n| n.trim().parse().ok())
            .unwrap_or_else(|| panic!("{name}: the error says how many messages the file kept: {stderr}"));
        let file = if inner == "bag" { out.join("bag/bag_0.mcap") } else { out.join(inner) };
        let got = read_linear(&file).unwrap_or_else(|| panic!("{name}: {} does not read through to a footer", file.display()));
        assert!(got.len() > 1000, "{name}: most of the 1 MiB holds messages: {}", got.len());
        assert_eq!(got.len(), kept, "{name}: as many messages as the error says");
        assert!(got.len() < reference.len(), "{name}: the disk filled before the end");
        assert_eq!(got[..], reference[..got.len()], "{name}: exactly the first messages of the same run");
        // Our own reader and the offline analysis take it as it is (exit 0 or 1, a verdict, not 2).
        let recording = if inner == "bag" { out.join("bag") } else { file.clone() };
        let n = fiveaxis::record::read::for_each_message(&recording, |_| {}).unwrap();
        assert_eq!(n as usize, kept, "{name}: our reader");
        let (code, _) = fiveaxis(&["analyze", recording.to_str().unwrap()]);
        assert!(code == 0 || code == 1, "{name}: analyze exits {code}");
        if inner == "bag" {
            let meta = std::fs::read_to_string(out.join("bag/metadata.yaml")).expect("metadata.yaml written");
            assert!(meta.contains("bag_0.mcap") && meta.contains(&format!("message_count: {kept}")), "{meta}");
            // rosbags (independent) opens the bag and finds per topic what metadata.yaml says.
            let peer = Path::new(env!("FIVEAXIS_ROOT")).join("tests/peer/bag_peer.py");
            let check = Command::new("python3").arg(&peer).arg("check").arg(out.join("bag")).arg("-").output().expect("python3 runs");
            assert!(check.status.success(), "rosbags: {}\n{}", String::from_utf8_lossy(&check.stdout), String::from_utf8_lossy(&check.stderr));
        }
    }
}
