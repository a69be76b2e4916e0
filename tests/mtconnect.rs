//! MTConnect offline: cppagent's own demo documents (an Okuma OSP-P300 multitasking machine's
//! Devices.xml and its adapter's SHDR log, ../shared/outside/mtconnect, Apache-2.0) read end to end,
//! each axis at its own rate, counted against an independent reading (tests/peer/shdr_counts.py);
//! and LinuxCNC's SING trace as an adapter would send it (each axis on its own at ~3 Hz, on change,
//! tests/peer/shopfloor_rates.py --shdr) through `fiveaxis analyze`, with the figures checked against
//! numpy's (machine_figures.py).

mod common;
use fiveaxis::mtconnect::{self, devices, AxisItems};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn okuma() -> (PathBuf, PathBuf) {
    (common::outside("mtconnect/demo_agent_okuma.txt"), common::outside("mtconnect/demo_agent_Devices.xml"))
}

fn python(script: &str, args: &[&str]) -> Vec<u8> {
    let out = Command::new("python3").arg(root().join("tests/peer").join(script)).args(args).output().expect("python3 runs");
    assert!(out.status.success(), "{script}: {}", String::from_utf8_lossy(&out.stderr));
    out.stdout
}

fn fiveaxis(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_fiveaxis")).args(args).current_dir(root()).output().unwrap();
    (out.status.code().unwrap_or(-1), format!("{}\n{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr)))
}

#[test]
fn the_okuma_log_reads_end_to_end_at_its_own_rates() {
    let (log, devices_xml) = okuma();
    let all = devices::parse(&std::fs::read_to_string(&devices_xml).unwrap()).unwrap();
    let device = mtconnect::pick(&all, Some("OKUMA")).unwrap();
    let keys = ["X1actw", "YI1actw", "Z1actw", "B1actw", "C3actw"];
    let items = AxisItems {
        ids: keys.map(|k| device.item(k).unwrap_or_else(|| panic!("{k} in the description")).id.clone()),
        to_si: [1e-3, 1e-3, 1e-3, 1f64.to_radians(), 1f64.to_radians()],
    };
    let mut reports = [0u64; 5];
    let mut stamps: Vec<Vec<f64>> = vec![Vec::new(); 5];
    let mut errors = Vec::new();
    let file = std::io::BufReader::new(std::fs::File::open(&log).unwrap());
    let lines = mtconnect::read_log(file, &all, device, &items, |r| match r {
        Ok(r) => {
            for (i, v) in r.values.iter().enumerate() {
                if v.is_some() {
                    reports[i] += 1;
                    stamps[i].push(r.stamp.as_secs());
                }
            }
        }
        Err(e) => errors.push(e),
    })
    .unwrap();
    assert!(errors.is_empty(), "every line of the log parses: {errors:?}");
    let mut args = vec![log.to_str().unwrap(), devices_xml.to_str().unwrap(), "OKUMA"];
    args.extend(keys);
    let reference: serde_json::Value = serde_json::from_slice(&python("shdr_counts.py", &args)).unwrap();
    assert_eq!(lines, reference["lines"].as_u64().unwrap());
    for (i, k) in keys.iter().enumerate() {
        let r = &reference["items"][k];
        assert_eq!(reports[i], r["reports"].as_u64().unwrap(), "{k}");
        let mut gaps: Vec<f64> = stamps[i].windows(2).map(|w| w[1] - w[0]).filter(|g| *g > 0.0).collect();
        gaps.sort_by(f64::total_cmp);
        let median = gaps[gaps.len() / 2];
        assert!((median - r["median_interval_s"].as_f64().unwrap()).abs() < 1e-3, "{k}: median {median} s, independent {}", r["median_interval_s"]);
    }
    // The figures of the same log: X reported 1,330 times, 0.36 s apart (median).
    assert_eq!(reports[0], 1330);
}

#[test]
fn a_device_without_the_machines_axes_is_refused_with_its_candidates() {
    // The Okuma's X has an actual position in machine and in object coordinates: the machine one is
    // taken. It has no axis named Z (its turret's is Z1): the mapping must be named, and the error
    // lists the candidates.
    let (log, devices_xml) = okuma();
    let (code, text) = fiveaxis(&["analyze", log.to_str().unwrap(), "--mtconnect-devices", devices_xml.to_str().unwrap(), "--mtconnect-device", "OKUMA", "--machine", "generic-bc-table"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("axis Z") && text.contains("Z1actm") && text.contains("MACHINE") && text.contains("--axis-map Z=ID"), "{text}");
    assert!(!text.contains("axis X"), "X is found (machine coordinates): {text}");
    // Two devices and none named.
    let (code, text) = fiveaxis(&["analyze", log.to_str().unwrap(), "--mtconnect-devices", devices_xml.to_str().unwrap(), "--machine", "generic-bc-table"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("OKUMA") && text.contains("Mazak") && text.contains("--mtconnect-device"), "{text}");
}

fn sing_shdr(tag: &str) -> (PathBuf, PathBuf) {
    let dir = common::scratch_root().join(format!("mtconnect-{tag}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let log = dir.join("sing.shdr");
    let trace = root().join("recordings/machine/linuxcnc/sing_trace.csv.gz");
    python("shopfloor_rates.py", &[trace.to_str().unwrap(), log.to_str().unwrap(), "per-axis", "--period", "0.33", "--shdr"]);
    let devices = PathBuf::from(format!("{}.devices.xml", log.display()));
    (log, devices)
}

#[test]
fn an_adapters_log_of_the_sing_cut_gives_the_one_region() {
    let (log, devices) = sing_shdr("sing");
    let json = log.with_extension("json");
    let (code, text) = fiveaxis(&[
        "analyze",
        log.to_str().unwrap(),
        "--mtconnect-devices",
        devices.to_str().unwrap(),
        "--machine",
        "hermle-c600u",
        "--program",
        "bundled:SING.I",
        "--max-c-speed-rpm",
        "25",
        "--json",
        json.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{text}");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let regions = v["regions"].as_array().unwrap();
    assert_eq!(regions.len(), 1, "{regions:#?}\n{text}");
    let r = &regions[0];
    let trace = root().join("recordings/machine/linuxcnc/sing_trace.csv.gz");
    let reference: serde_json::Value = serde_json::from_slice(&python("machine_figures.py", &[trace.to_str().unwrap(), "--feed", "2000", "--x-range", "15", "35"])).unwrap();
    let f = |v: &serde_json::Value, k: &str| v[k].as_f64().unwrap_or_else(|| panic!("{k} in {v}"));
    assert_eq!(r["cause"], "singularity");
    assert!((f(r, "x_start_mm") - f(&reference, "x_start_mm")).abs() <= 1.0 && (f(r, "x_end_mm") - f(&reference, "x_end_mm")).abs() <= 1.0, "{r:#}\n{reference:#}");
    let peak = f(r, "peak_c_speed_rpm");
    assert!((peak - f(&reference, "peak_predicted_c_rpm")).abs() <= 0.05 * f(&reference, "peak_predicted_c_rpm"), "peak {peak}");
    assert_eq!(v["streams"][0]["topic"], "mtconnect:C600U");
}

#[test]
fn a_log_with_no_readable_line_fails_closed_naming_the_line() {
    let (log, devices) = sing_shdr("bad");
    // Every timestamp damaged: nothing is read; the first refusal is named by line and column.
    let text = std::fs::read_to_string(&log).unwrap().replace("2026-01-01T", "2026-01-01X");
    std::fs::write(&log, text).unwrap();
    let (code, out) = fiveaxis(&["analyze", log.to_str().unwrap(), "--mtconnect-devices", devices.to_str().unwrap(), "--machine", "hermle-c600u", "--feed", "2000"]);
    assert_eq!(code, 2, "{out}");
    assert!(out.contains("no valid sample") && out.contains("line 1: col 1") && out.contains("ISO 8601"), "{out}");
    // A description that is not one.
    let (code, out) = fiveaxis(&["analyze", log.to_str().unwrap(), "--mtconnect-devices", log.to_str().unwrap(), "--machine", "hermle-c600u", "--feed", "2000"]);
    assert_eq!(code, 2, "{out}");
    assert!(out.contains("MTConnect") && out.contains("XML"), "{out}");
}

/// The Okuma's log through `analyze`, its axes named (work coordinates) on a B/C head model with the
/// MULTUS' B range: every line reporting an axis is a sample or a counted refusal (as many as the
/// independent reading finds), the adapter's second session (its stamps start 14 min earlier) is a
/// new session, not 2,000 samples out of order, and nothing is called lost on a change-only stream.
#[test]
fn the_okuma_log_through_analyze() {
    let (log, devices_xml) = okuma();
    let dir = common::scratch_dir("mtconnect-okuma");
    let (code, text) = fiveaxis(&["machine", "show", "generic-bc-head"]);
    assert_eq!(code, 0, "{text}");
    let model = text.trim().replace("name = \"generic-bc-head\"", "name = \"okuma-multus-like\"").replacen("min_deg = -130.0", "min_deg = -30.0", 1).replacen("max_deg = 130.0", "max_deg = 210.0", 1);
    let file = dir.join("multus.toml");
    std::fs::write(&file, model.trim_start_matches('\n')).unwrap();
    let json = dir.join("okuma.json");
    let mut args = vec!["analyze", log.to_str().unwrap(), "--mtconnect-devices", devices_xml.to_str().unwrap(), "--mtconnect-device", "OKUMA", "--machine", file.to_str().unwrap()];
    args.extend(["--axis-map", "X=X1actw", "--axis-map", "Y=YI1actw", "--axis-map", "Z=Z1actw", "--axis-map", "B=B1actw", "--axis-map", "C=C3actw"]);
    args.extend(["--feed", "1000", "--json", json.to_str().unwrap()]);
    let (code, text) = fiveaxis(&args);
    assert!(code == 0 || code == 1, "no input error: {text}");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let s = &v["streams"][0];
    let reference: serde_json::Value =
        serde_json::from_slice(&python("shdr_counts.py", &[log.to_str().unwrap(), devices_xml.to_str().unwrap(), "OKUMA", "X1actw", "YI1actw", "Z1actw", "B1actw", "C3actw"])).unwrap();
    let samples = s["samples"].as_u64().unwrap();
    let rejected: u64 = ["missing_joint", "non_finite", "out_of_range", "out_of_order", "malformed"].iter().map(|k| s["rejected"][k].as_u64().unwrap()).sum();
    assert_eq!(samples + rejected, reference["lines_with_any"].as_u64().unwrap(), "{s:#}");
    assert_eq!((s["rejected"]["out_of_order"].as_u64(), s["lost"].as_u64()), (Some(0), Some(0)), "{s:#}");
    assert_eq!(rejected, 0, "{s:#}");
}

/// A log none of whose lines reports the device's axes (another machine's adapter log read against
/// this description) is an error, not a pass with nothing read.
#[test]
fn a_log_that_reports_none_of_the_axes_fails_closed() {
    let (_, devices) = sing_shdr("none");
    let (okuma_log, _) = okuma();
    let (code, out) = fiveaxis(&["analyze", okuma_log.to_str().unwrap(), "--mtconnect-devices", devices.to_str().unwrap(), "--machine", "hermle-c600u", "--feed", "2000"]);
    assert_eq!(code, 2, "{out}");
    assert!(out.contains("mtconnect:C600U: nothing in the recording reports the machine's axes") && out.contains("x_act"), "{out}");
}
