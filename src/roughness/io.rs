//! Profile files: CSV (x and height columns) and X3P (ISO 25178-72).

use super::{Profile, RoughnessError};
use std::io::{Read, Write};
use std::path::Path;

/// Units of CSV columns when the header does not name them (factors to metres).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CsvUnits {
    pub x: Option<f64>,
    pub z: Option<f64>,
}

fn unit_factor(name: &str) -> Option<f64> {
    let n = name.to_ascii_lowercase();
    let n = n.trim();
    let tail = n.rsplit(['_', '[', '(', ' ']).next().unwrap_or("").trim_end_matches([']', ')']);
    match tail {
        "m" => Some(1.0),
        "mm" => Some(1e-3),
        "um" | "µm" | "micron" | "microns" => Some(1e-6),
        "nm" => Some(1e-9),
        _ => None,
    }
}

fn fmt_err(path: &str, message: String) -> RoughnessError {
    RoughnessError::Format { path: path.to_string(), message }
}

/// Read a profile by extension: `.x3p` or CSV.
pub fn read_profile(path: &Path, units: CsvUnits) -> Result<Profile, RoughnessError> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("x3p")) {
        read_x3p(path)
    } else {
        read_csv(path, units)
    }
}

/// CSV with an x column and a height column (comma, semicolon, tab or space separated). A header
/// names the columns (`x_mm,height_um`, `x [mm]`, `z (nm)`); `units` gives what the header does not.
/// Non-uniform sampling is resampled linearly to the mean spacing.
pub fn read_csv(path: &Path, units: CsvUnits) -> Result<Profile, RoughnessError> {
    let p = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| RoughnessError::Io { path: p.clone(), source })?;
    let mut header: Option<Vec<String>> = None;
    let (mut x, mut z) = (Vec::new(), Vec::new());
    let (mut xi, mut zi) = (0usize, 1usize);
    let (mut fx, mut fz) = (units.x, units.z);
    for (k, line) in text.lines().enumerate() {
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        // One delimiter per line: comma, semicolon or tab if present, else white space (so that a
        // header may say `x [mm]`).
        let fields: Vec<&str> = match [',', ';', '\t'].into_iter().find(|d| t.contains(*d)) {
            Some(d) => t.split(d).map(str::trim).collect(),
            None => t.split_whitespace().collect(),
        };
        let numbers: Vec<Option<f64>> = fields.iter().map(|f| f.parse::<f64>().ok().filter(|v| v.is_finite())).collect();
        if header.is_none() && x.is_empty() && numbers.iter().any(Option::is_none) {
            let names: Vec<String> = fields.iter().map(|s| s.to_string()).collect();
            xi = names.iter().position(|n| n.to_ascii_lowercase().starts_with('x')).unwrap_or(0);
            zi = names
                .iter()
                .position(|n| {
                    let l = n.to_ascii_lowercase();
                    ["z", "h", "height", "profile", "y"].iter().any(|p| l.starts_with(p)) && !l.starts_with('x')
                })
                .unwrap_or(if xi == 0 { 1 } else { 0 });
            fx = fx.or_else(|| unit_factor(&names[xi]));
            fz = fz.or_else(|| names.get(zi).and_then(|n| unit_factor(n)));
            header = Some(names);
            continue;
        }
        let get = |i: usize| -> Result<f64, RoughnessError> {
            match numbers.get(i) {
                Some(Some(v)) => Ok(*v),
                Some(None) => Err(fmt_err(&p, format!("line {}: column {} is '{}', expected a number", k + 1, i + 1, fields[i]))),
                None => Err(fmt_err(&p, format!("line {}: expected at least {} columns, found {}", k + 1, i.max(1) + 1, fields.len()))),
            }
        };
        x.push(get(xi)?);
        z.push(get(zi)?);
    }
    let (fx, fz) = match (fx, fz) {
        (Some(a), Some(b)) => (a, b),
        _ => return Err(fmt_err(&p, "units unknown: name them in the header (x_mm, height_um) or give them (--x-unit, --z-unit)".into())),
    };
    let x: Vec<f64> = x.into_iter().map(|v| v * fx).collect();
    let z: Vec<f64> = z.into_iter().map(|v| v * fz).collect();
    uniform(x, z, &p)
}

/// Check increasing x and resample to uniform spacing if needed.
fn uniform(x: Vec<f64>, z: Vec<f64>, path: &str) -> Result<Profile, RoughnessError> {
    if x.len() < 3 {
        return Err(fmt_err(path, format!("{} points: too few for a profile", x.len())));
    }
    if let Some(k) = x.windows(2).position(|w| w[1] <= w[0]) {
        return Err(fmt_err(path, format!("x must increase: point {} ({}) is not after point {} ({})", k + 2, x[k + 1], k + 1, x[k])));
    }
    let n = x.len();
    let dx = (x[n - 1] - x[0]) / (n - 1) as f64;
    let even = x.iter().enumerate().all(|(i, v)| (v - (x[0] + i as f64 * dx)).abs() <= 0.01 * dx);
    if even {
        return Ok(Profile { x, z, source: path.to_string() });
    }
    let mut j = 0;
    let xs: Vec<f64> = (0..n).map(|i| x[0] + i as f64 * dx).collect();
    let zs = xs
        .iter()
        .map(|&t| {
            while j + 2 < n && x[j + 1] < t {
                j += 1;
            }
            let f = ((t - x[j]) / (x[j + 1] - x[j])).clamp(0.0, 1.0);
            z[j] + (z[j + 1] - z[j]) * f
        })
        .collect();
    Ok(Profile { x: xs, z: zs, source: format!("{path} (resampled to uniform spacing)") })
}

/// Write `x_mm,height_um` CSV with a comment line first.
pub fn write_csv(profile: &Profile, path: &Path, comment: &str) -> Result<(), RoughnessError> {
    let p = path.display().to_string();
    let mut out = String::with_capacity(profile.x.len() * 24);
    for line in comment.lines() {
        out.push_str("# ");
        out.push_str(line);
        out.push('\n');
    }
    out.push_str("x_mm,height_um\n");
    for (x, z) in profile.x.iter().zip(&profile.z) {
        out.push_str(&format!("{:.4},{:.5}\n", x * 1e3, z * 1e6));
    }
    std::fs::write(path, out).map_err(|source| RoughnessError::Io { path: p, source })
}

fn child<'a>(n: roxmltree::Node<'a, 'a>, name: &str) -> Option<roxmltree::Node<'a, 'a>> {
    n.children().find(|c| c.is_element() && c.tag_name().name() == name)
}

fn path_text<'a>(n: roxmltree::Node<'a, 'a>, names: &[&str]) -> Option<&'a str> {
    let mut cur = n;
    for name in names {
        cur = child(cur, name)?;
    }
    cur.text().map(str::trim)
}

/// Most points read from one X3P profile (one row): 10 M points is 5 m at 0.5 um spacing, beyond any
/// instrument; the reader allocates for one row only, so an areal surface's size does not matter.
pub const MAX_X3P_POINTS: u64 = 10_000_000;
/// Largest `main.xml` read (bytes).
const MAX_MAIN_XML: u64 = 64 << 20;

/// Read an X3P file (ISO 25178-72): a profile (`PRF`), or the middle row of an areal surface (`SUR`).
/// Invalid points (NaN) are interpolated from their neighbours. Sizes are checked against
/// [`MAX_X3P_POINTS`] and against what the data entry holds before anything is allocated.
pub fn read_x3p(path: &Path) -> Result<Profile, RoughnessError> {
    let p = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|source| RoughnessError::Io { path: p.clone(), source })?;
    let mut zip = zip::ZipArchive::new(file).map_err(|e| fmt_err(&p, format!("not an X3P (zip) container: {e}")))?;
    let mut xml = String::new();
    zip.by_name("main.xml")
        .map_err(|e| fmt_err(&p, format!("main.xml: {e}")))?
        .take(MAX_MAIN_XML + 1)
        .read_to_string(&mut xml)
        .map_err(|source| RoughnessError::Io { path: p.clone(), source })?;
    if xml.len() as u64 > MAX_MAIN_XML {
        return Err(fmt_err(&p, format!("main.xml: larger than {MAX_MAIN_XML} bytes")));
    }
    let doc = roxmltree::Document::parse(&xml).map_err(|e| fmt_err(&p, format!("main.xml: {e}")))?;
    let root = doc.root_element();
    let r1 = child(root, "Record1").ok_or_else(|| fmt_err(&p, "main.xml: no Record1".into()))?;
    let kind = path_text(r1, &["FeatureType"]).unwrap_or("");
    let finite = |v: Option<&str>, what: &str| -> Result<f64, RoughnessError> {
        match v.map(|s| s.parse::<f64>()) {
            Some(Ok(x)) if x.is_finite() => Ok(x),
            Some(_) => Err(fmt_err(&p, format!("main.xml: {what} = '{}': not a finite number", v.unwrap_or("")))),
            None => Err(fmt_err(&p, format!("main.xml: {what} missing"))),
        }
    };
    let inc = finite(path_text(r1, &["Axes", "CX", "Increment"]), "Axes/CX/Increment")?;
    if inc <= 0.0 {
        return Err(fmt_err(&p, format!("main.xml: Axes/CX/Increment = {inc}: the point spacing must be positive")));
    }
    let off = match path_text(r1, &["Axes", "CX", "Offset"]) {
        Some(t) => finite(Some(t), "Axes/CX/Offset")?,
        None => 0.0,
    };
    let ztype = path_text(r1, &["Axes", "CZ", "DataType"]).unwrap_or("D").to_string();
    let zinc = match path_text(r1, &["Axes", "CZ", "Increment"]) {
        Some(t) => finite(Some(t), "Axes/CZ/Increment")?,
        None => 1.0,
    };
    if zinc == 0.0 {
        return Err(fmt_err(&p, "main.xml: Axes/CZ/Increment = 0: every height would be 0".into()));
    }
    let r3 = child(root, "Record3").ok_or_else(|| fmt_err(&p, "main.xml: no Record3".into()))?;
    let count = |what: &str| -> Result<u64, RoughnessError> {
        let t = path_text(r3, &["MatrixDimension", what]).ok_or_else(|| fmt_err(&p, format!("main.xml: MatrixDimension/{what} missing")))?;
        t.parse::<u64>().ok().filter(|n| *n >= 1).ok_or_else(|| fmt_err(&p, format!("main.xml: MatrixDimension/{what} = '{t}': expected a whole number of points, at least 1")))
    };
    let (sx, sy) = (count("SizeX")?, count("SizeY")?);
    if sx > MAX_X3P_POINTS {
        return Err(fmt_err(&p, format!("main.xml: MatrixDimension/SizeX = {sx}: a profile of at most {MAX_X3P_POINTS} points is read")));
    }
    let total = sx.checked_mul(sy).ok_or_else(|| fmt_err(&p, format!("main.xml: MatrixDimension {sx} x {sy} points: more than any file holds")))?;
    if !(kind == "PRF" || kind == "SUR") {
        return Err(fmt_err(&p, format!("FeatureType '{kind}': expected PRF (profile) or SUR (surface)")));
    }
    // The middle row: points row*sx .. (row+1)*sx (no overflow: row < sy, so (row+1)*sx <= total).
    let row = sy / 2;
    let (first, n) = (row * sx, sx as usize);
    let mut z: Vec<f64> = if let Some(link) = path_text(r3, &["DataLink", "PointDataLink"]) {
        let (size, conv): (u64, fn(&[u8]) -> f64) = match ztype.as_str() {
            "D" => (8, |b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8]))),
            "F" => (4, |b| f32::from_le_bytes(b.try_into().unwrap_or([0; 4])) as f64),
            "L" => (4, |b| i32::from_le_bytes(b.try_into().unwrap_or([0; 4])) as f64),
            "I" => (2, |b| i16::from_le_bytes(b.try_into().unwrap_or([0; 2])) as f64),
            t => return Err(fmt_err(&p, format!("CZ DataType '{t}': expected D, F, L or I"))),
        };
        let mut entry = zip.by_name(link).map_err(|e| fmt_err(&p, format!("{link}: {e}")))?;
        let short = |got: u64| fmt_err(&p, format!("{link}: {got} bytes for {sx} x {sy} points of {size} bytes"));
        match total.checked_mul(size) {
            Some(need) if entry.size() >= need => {}
            _ => return Err(short(entry.size())),
        }
        // Skip to the row, then read it alone (the entry's claimed size may lie: both reads are bounded).
        let skipped = std::io::copy(&mut (&mut entry).take(first * size), &mut std::io::sink()).map_err(|source| RoughnessError::Io { path: p.clone(), source })?;
        let mut bytes = Vec::with_capacity(n * size as usize);
        (&mut entry).take(sx * size).read_to_end(&mut bytes).map_err(|source| RoughnessError::Io { path: p.clone(), source })?;
        if skipped < first * size || (bytes.len() as u64) < sx * size {
            return Err(short(skipped + bytes.len() as u64));
        }
        let scale = if matches!(ztype.as_str(), "L" | "I") { zinc } else { 1.0 };
        bytes.chunks_exact(size as usize).map(|c| conv(c) * scale).collect()
    } else if let Some(list) = child(r3, "DataList") {
        list.children()
            .filter(|c| c.is_element())
            .skip(first as usize)
            .take(n)
            .map(|c| c.text().map(str::trim).and_then(|t| t.split(';').next_back().and_then(|v| v.trim().parse::<f64>().ok())).unwrap_or(f64::NAN))
            .collect()
    } else {
        return Err(fmt_err(&p, "Record3: neither DataLink nor DataList".into()));
    };
    if z.len() < n {
        return Err(fmt_err(&p, format!("fewer points than MatrixDimension says ({} of row {row}'s {sx})", z.len())));
    }
    // Interpolate invalid points.
    let valid: Vec<usize> = (0..z.len()).filter(|&i| z[i].is_finite()).collect();
    if valid.len() < 3 {
        return Err(fmt_err(&p, "fewer than 3 valid points".into()));
    }
    for i in 0..z.len() {
        if !z[i].is_finite() {
            let k = valid.partition_point(|&v| v < i);
            let (a, b) = (valid[k.saturating_sub(1)], valid[k.min(valid.len() - 1)]);
            z[i] = if a == b { z[a] } else { z[a] + (z[b] - z[a]) * (i - a) as f64 / (b - a) as f64 };
        }
    }
    let x = (0..n).map(|i| off + i as f64 * inc).collect();
    Ok(Profile { x, z, source: p })
}

/// Write a profile as X3P (ISO 25178-72): `main.xml` (PRF, CX incremental, CZ absolute doubles),
/// `bindata/data.bin` (little-endian f64) and `md5checksum.hex`. `comment` goes into Record2.
pub fn write_x3p(profile: &Profile, path: &Path, comment: &str) -> Result<(), RoughnessError> {
    let p = path.display().to_string();
    let io = |source| RoughnessError::Io { path: p.clone(), source };
    let data: Vec<u8> = profile.z.iter().flat_map(|v| v.to_le_bytes()).collect();
    let data_md5 = format!("{:x}", md5::compute(&data));
    let xml = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:schemaLocation="http://www.opengps.eu/2008/ISO5436_2 http://www.opengps.eu/2008/ISO5436_2/ISO5436_2.xsd">
  <Record1>
    <Revision>ISO5436 - 2000</Revision>
    <FeatureType>PRF</FeatureType>
    <Axes>
      <CX><AxisType>I</AxisType><DataType>D</DataType><Increment>{inc:e}</Increment><Offset>{off:e}</Offset></CX>
      <CY><AxisType>I</AxisType><DataType>D</DataType><Increment>1</Increment><Offset>0</Offset></CY>
      <CZ><AxisType>A</AxisType><DataType>D</DataType></CZ>
    </Axes>
  </Record1>
  <Record2>
    <Date>2026-01-01T00:00:00.0+00:00</Date>
    <Creator>fiveaxis</Creator>
    <Instrument><Manufacturer>none</Manufacturer><Model>synthetic</Model><Serial>0</Serial><Version>{ver}</Version></Instrument>
    <CalibrationDate>2026-01-01T00:00:00.0+00:00</CalibrationDate>
    <ProbingSystem><Type>NonContacting</Type><Identification>none</Identification></ProbingSystem>
    <Comment>{comment}</Comment>
  </Record2>
  <Record3>
    <MatrixDimension><SizeX>{n}</SizeX><SizeY>1</SizeY><SizeZ>1</SizeZ></MatrixDimension>
    <DataLink><PointDataLink>bindata/data.bin</PointDataLink><MD5ChecksumPointData>{data_md5}</MD5ChecksumPointData></DataLink>
  </Record3>
  <Record4><ChecksumFile>md5checksum.hex</ChecksumFile></Record4>
</p:ISO5436_2>
"#,
        inc = profile.spacing(),
        off = profile.x.first().copied().unwrap_or(0.0),
        ver = env!("CARGO_PKG_VERSION"),
        comment = crate::xml::escape(comment),
        n = profile.z.len()
    );
    let file = std::fs::File::create(path).map_err(io)?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let zerr = |e: zip::result::ZipError| fmt_err(&p, e.to_string());
    zip.start_file("main.xml", opts).map_err(zerr)?;
    zip.write_all(xml.as_bytes()).map_err(io)?;
    zip.start_file("bindata/data.bin", opts).map_err(zerr)?;
    zip.write_all(&data).map_err(io)?;
    zip.start_file("md5checksum.hex", opts).map_err(zerr)?;
    zip.write_all(format!("{:x} *main.xml\n", md5::compute(xml.as_bytes())).as_bytes()).map_err(io)?;
    zip.finish().map_err(zerr)?;
    Ok(())
}
