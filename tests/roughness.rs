//! Roughness profiles: X3P and CSV import, the synthetic example, and the analysis beside the stutter.

use crate::common;
use fiveaxis::roughness::{read_csv, read_profile, read_x3p, synthetic, write_x3p, CsvUnits, Profile};
use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    common::scratch_path("rough", name)
}

fn flat_feed(_: f64) -> (f64, f64) {
    (2000.0 / 60e3, 2000.0 / 60e3)
}

#[test]
fn x3p_round_trip_keeps_every_point() {
    let p = synthetic::profile(0.0, 2e-3, &flat_feed, &synthetic::SyntheticModel::default());
    let path = tmp("p.x3p");
    write_x3p(&p, &path, "test <&> comment").unwrap();
    let back = read_x3p(&path).unwrap();
    assert_eq!(back.z, p.z);
    for (a, b) in back.x.iter().zip(&p.x) {
        assert!((a - b).abs() < 1e-12);
    }
    // The container has what ISO 25178-72 asks for.
    let mut zip = zip::ZipArchive::new(std::fs::File::open(&path).unwrap()).unwrap();
    for name in ["main.xml", "bindata/data.bin", "md5checksum.hex"] {
        assert!(zip.by_name(name).is_ok(), "{name}");
    }
}

/// A copy of the X3P at `from` with main.xml edited by `edit` and data.bin replaced by `data` if given.
fn edited_x3p(from: &Path, to: &Path, edit: &dyn Fn(String) -> String, data: Option<&[u8]>) {
    use std::io::{Read, Write};
    let mut zin = zip::ZipArchive::new(std::fs::File::open(from).unwrap()).unwrap();
    let mut zout = zip::ZipWriter::new(std::fs::File::create(to).unwrap());
    for i in 0..zin.len() {
        let mut e = zin.by_index(i).unwrap();
        let name = e.name().to_string();
        let mut bytes = Vec::new();
        e.read_to_end(&mut bytes).unwrap();
        if name == "main.xml" {
            bytes = edit(String::from_utf8(bytes).unwrap()).into_bytes();
        } else if let (Some(d), true) = (data, name.ends_with(".bin")) {
            bytes = d.to_vec();
        }
        zout.start_file(name, zip::write::SimpleFileOptions::default()).unwrap();
        zout.write_all(&bytes).unwrap();
    }
    zout.finish().unwrap();
}

/// Hostile X3P headers (issue 15): sizes that overflow `size * SizeX * SizeY` (a panic in debug builds
/// before), sizes the data cannot hold, and a negative, zero or NaN point spacing, each refused with
/// the field named; nothing is allocated for points the file does not hold.
#[test]
fn x3p_sizes_and_spacing_are_checked_before_allocating() {
    let p = synthetic::profile(0.0, 2e-3, &flat_feed, &synthetic::SyntheticModel::default());
    let good = tmp("good.x3p");
    write_x3p(&p, &good, "").unwrap();
    let n = p.z.len();
    let size_x = format!("<SizeX>{n}</SizeX>");
    let cases: Vec<(&str, Box<dyn Fn(String) -> String>, Option<Vec<u8>>, &str)> = vec![
        ("overflow", Box::new(move |x: String| x.replace(&format!("<SizeX>{n}</SizeX><SizeY>1</SizeY>"), "<SizeX>4</SizeX><SizeY>2305843009213693952</SizeY>")), None, "points of 8 bytes"),
        ("product-overflow", Box::new(move |x: String| x.replace(&format!("<SizeX>{n}</SizeX><SizeY>1</SizeY>"), "<SizeX>1000</SizeX><SizeY>18446744073709551615</SizeY>")), None, "more than any file holds"),
        ("huge-row", Box::new({ let s = size_x.clone(); move |x: String| x.replace(&s, "<SizeX>4611686018427387904</SizeX>") }), None, "MatrixDimension/SizeX = 4611686018427387904"),
        ("negative-size", Box::new({ let s = size_x.clone(); move |x: String| x.replace(&s, "<SizeX>-5</SizeX>") }), None, "MatrixDimension/SizeX = '-5'"),
        ("short-data", Box::new(|x: String| x), Some(vec![0u8; 64]), "64 bytes for"),
        ("negative-spacing", Box::new(|x: String| { let a = x.find("<Increment>").unwrap(); let b = x[a..].find("</Increment>").unwrap() + a; format!("{}<Increment>-1e-6{}", &x[..a], &x[b..]) }), None, "Axes/CX/Increment = -0.000001"),
        ("zero-spacing", Box::new(|x: String| { let a = x.find("<Increment>").unwrap(); let b = x[a..].find("</Increment>").unwrap() + a; format!("{}<Increment>0{}", &x[..a], &x[b..]) }), None, "Axes/CX/Increment = 0"),
        ("nan-spacing", Box::new(|x: String| { let a = x.find("<Increment>").unwrap(); let b = x[a..].find("</Increment>").unwrap() + a; format!("{}<Increment>NaN{}", &x[..a], &x[b..]) }), None, "Axes/CX/Increment = 'NaN'"),
    ];
    for (name, edit, data, want) in &cases {
        let path = tmp(&format!("{name}.x3p"));
        edited_x3p(&good, &path, edit.as_ref(), data.as_deref());
        match read_x3p(&path) {
            Ok(_) => panic!("{name}: read"),
            Err(e) => assert!(e.to_string().contains(want), "{name}: {e}"),
        }
    }
    // An areal surface: only the middle row is read (SUR, 3 rows: row 1 of the data).
    let sur = tmp("sur.x3p");
    let mut data = Vec::new();
    for row in 0..3 {
        for v in &p.z {
            data.extend_from_slice(&(v + row as f64).to_le_bytes());
        }
    }
    edited_x3p(&good, &sur, &|x: String| x.replace("<FeatureType>PRF</FeatureType>", "<FeatureType>SUR</FeatureType>").replace("<SizeY>1</SizeY>", "<SizeY>3</SizeY>"), Some(&data));
    let back = read_x3p(&sur).unwrap();
    assert_eq!(back.z.len(), n);
    assert!(back.z.iter().zip(&p.z).all(|(a, b)| *a == b + 1.0), "the middle row");
}

#[test]
fn csv_units_from_header_or_flags_and_errors_name_the_line() {
    let path = tmp("a.csv");
    std::fs::write(&path, "# comment\nx [mm];height (nm)\n0;100\n0.001;200\n0.002;300\n").unwrap();
    let p = read_csv(&path, CsvUnits::default()).unwrap();
    assert!((p.x[2] - 2e-6).abs() < 1e-15 && (p.z[2] - 300e-9).abs() < 1e-18);
    std::fs::write(&path, "0,1\n1,2\n2,3\n").unwrap();
    assert!(read_csv(&path, CsvUnits::default()).unwrap_err().to_string().contains("units unknown"));
    let p = read_csv(&path, CsvUnits { x: Some(1e-3), z: Some(1e-6) }).unwrap();
    assert_eq!(p.z.len(), 3);
    std::fs::write(&path, "x_mm,height_um\n0,1\n1,oops\n2,3\n").unwrap();
    let e = read_csv(&path, CsvUnits::default()).unwrap_err().to_string();
    assert!(e.contains("line 3") && e.contains("oops"), "{e}");
    std::fs::write(&path, "x_mm,height_um\n0,1\n2,1\n1,3\n").unwrap();
    assert!(read_csv(&path, CsvUnits::default()).unwrap_err().to_string().contains("must increase"));
    // Uneven spacing is resampled.
    std::fs::write(&path, "x_mm,height_um\n0,0\n1,1\n3,3\n4,4\n").unwrap();
    let p = read_csv(&path, CsvUnits::default()).unwrap();
    assert!(p.source.contains("resampled") && (p.z[2] - 2.6666666666666665e-6).abs() < 1e-12, "{:?}", p.z);
    assert!(read_profile(Path::new("/no/such.x3p"), CsvUnits::default()).is_err());
    let bad = tmp("bad.x3p");
    std::fs::write(&bad, b"not a zip").unwrap();
    assert!(read_x3p(&bad).unwrap_err().to_string().contains("not an X3P"));
}

#[test]
fn synthetic_profile_is_seeded_and_rougher_where_the_feed_drops() {
    let m = synthetic::SyntheticModel::default();
    let dip = |x: f64| (if (0.02..0.03).contains(&x) { 250.0 } else { 2000.0 } / 60e3, 2000.0 / 60e3);
    let a = synthetic::profile(0.0, 0.05, &dip, &m);
    let b = synthetic::profile(0.0, 0.05, &dip, &m);
    assert_eq!(a, b, "same seed, same profile");
    let c = synthetic::profile(0.0, 0.05, &dip, &synthetic::SyntheticModel { seed: 1, ..m });
    assert_ne!(a.z, c.z);
    assert!(a.source.contains("SYNTHETIC"));
    let w = a.windows(0.8e-3, 0.5e-3);
    let ra = |lo: f64, hi: f64| {
        let v: Vec<f64> = w.iter().filter(|w| w.x > lo && w.x < hi).map(|w| w.ra).collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    assert!(ra(0.022, 0.028) > 3.0 * ra(0.005, 0.015), "{} vs {}", ra(0.022, 0.028), ra(0.005, 0.015));
}

/// The committed example is exactly what `fiveaxis roughness synthesize` makes (regenerate with
/// recordings/regenerate after changing the simulator or the model).
#[test]
fn committed_synthetic_profile_is_reproducible() {
    let out = tmp("regen.csv");
    let status = Command::new(env!("FIVEAXIS_EXE")).args(["roughness", "synthesize", "--out"]).arg(&out).output().unwrap();
    assert!(status.status.success());
    let committed = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/roughness/SYNTHETIC_sing_profile.csv");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), std::fs::read_to_string(committed).unwrap());
}

/// `fiveaxis analyze` on the SING run with the synthetic profile: the region 22-28 mm, its overlap
/// with the rough stretch, exit 1 at 25 rpm; the NON_SING run exits 0.
#[test]
fn analyze_sing_with_roughness() {
    let m = fiveaxis::machine::Machine::hermle_c600u();
    let rec = |spec: &str, name: &str| {
        let path = tmp(name);
        let o = fiveaxis::live::inprocess::RunOptions { mcap: Some(path.clone()), ..Default::default() };
        fiveaxis::live::inprocess::run(spec, &m, &o).unwrap();
        path
    };
    let sing = rec("bundled:SING.I", "sing.mcap");
    let rough = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/roughness/SYNTHETIC_sing_profile.x3p");
    let json = tmp("sing.json");
    let out = Command::new(env!("FIVEAXIS_EXE"))
        .args(["analyze", sing.to_str().unwrap(), "--roughness", rough.to_str().unwrap(), "--max-c-speed-rpm", "25", "--json", json.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stdout));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let r = &v["regions"][0];
    assert!((r["x_start_mm"].as_f64().unwrap() - 22.0).abs() < 0.05 && (r["x_end_mm"].as_f64().unwrap() - 28.0).abs() < 0.05, "{r}");
    assert!(r["lowest_feed_mm_per_min"].as_f64().unwrap() < 1000.0);
    let (inside, outside) = (v["roughness_ra_inside_um"].as_f64().unwrap(), v["roughness_ra_outside_um"].as_f64().unwrap());
    assert!(inside > 2.0 * outside, "Ra inside {inside} um, outside {outside} um");
    let overlap = v["roughness"]["rough_overlap_with_regions"].as_f64().unwrap();
    assert!(overlap > 0.3, "{overlap}");
    let nonsing = rec("bundled:NON_SING.I", "nonsing.mcap");
    let code = Command::new(env!("FIVEAXIS_EXE")).args(["analyze", nonsing.to_str().unwrap(), "--max-c-speed-rpm", "25"]).output().unwrap().status.code();
    assert_eq!(code, Some(0));
    // The committed X3P reads back with every point of its CSV twin.
    let x3p: Profile = read_profile(&rough, CsvUnits::default()).unwrap();
    let csv = read_profile(&rough.with_extension("csv"), CsvUnits::default()).unwrap();
    assert_eq!(x3p.z.len(), csv.z.len());
    assert!(x3p.z.iter().zip(&csv.z).all(|(a, b)| (a - b).abs() < 1e-11), "CSV holds heights to 0.01 nm");
}
