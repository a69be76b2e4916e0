//! Real CAM output (`../shared/outside/programs`, 23 programs from public repositories, see its
//! SOURCES.md): each program read by `fiveaxis program analyze` on the built-in machine of its maker
//! and model, with no defect, and simulated by `fiveaxis run`. Issue 64's corpus; a program not yet
//! read is listed in [`NOT_YET`] with what stops it, so the list can only shrink.

use crate::common;

use std::process::Command;

mod cases;
use cases::{Case, CLEAN};

/// Programs refused on their machine with one clear message each: a defect of the program as its
/// control reads it (the file, machine, flags and the message's telling part).
const REFUSED: &[(&str, &str, &[&str], &str)] = &[
    // NX's sample posts for the NMV5000 write G83 with Q0.0: a peck of nothing never reaches the
    // hole's bottom (a FANUC control alarms, PS0045).
    ("fanuc-G43.4_nx-post_mori-nmv5000-bc_near-B0_MS_NMV_sample_output.nc", "mori-seiki-nmv5000", &[], "862:29: error: Q0.0: a peck depth must be positive (FANUC alarm PS0045"),
    ("fanuc-G43.4_nx-post_mori-nmv5000-bc_mm_MS_NMV_sample_mm.nc", "mori-seiki-nmv5000", &[], "630:24: error: Q0.0: a peck depth must be positive (FANUC alarm PS0045"),
    // SOLIDWORKS CAM's .clt turns an A table (no machine named: the generic A/C table-table) by ROTABL
    // in radians; its one drilling cycle lacks a comma between two numbers.
    (
        "apt-cl_solidworks-cam_interface-glue_ROTABL-TLAXIS.clt",
        "generic-ac-table",
        &["--cl-angles", "rad"],
        "12:1: error: CYCLE/DRILL: field 10 '46.927686 46.927686 DWEL",
    ),
];

/// Programs refused for defects of their own at several places, each checked by its own test below
/// (the file, its machine, what the control refuses).
const DEFECTIVE: &[(&str, &str, &str)] = &[
    (
        "sinumerik-840d_nx-post_dmu70evo-bc_TRAORI-C-unwound_Sample_part.mpf",
        "dmg-dmu-70-evo",
        "every drilling cycle NX's post calls has its retraction plane below the reference plane (alarm 61101) or FRF empty (a feed of 0), and a CYCLE76 (spigot milling) for boring",
    ),
    (
        "heidenhain-klartext_nx-post_dmg-dmc100-bc_M128-simultaneous_Sample_part.h",
        "dmg-dmc-100u",
        "NX's post writes 23 circle centres CC X Y Z for arcs in the Y-Z plane at B-90 (the TNC puts a circle in XY, its working plane: half circles of radius 0); some operations lie 2.5-5.6 m from the others, so its machine-coordinate moves take the axes beyond the 55 x 28 x 28 in travels; its feeds are whole inch/min where the TNC7 reads an inch program's F in tenths",
    ),
    (
        "sinumerik-840d_nx-post_cincinnati-ftv5_CYCLE800-TRAORI1_sample.mpf",
        "cincinnati-ftv5",
        "NX's post writes M202(tolerance) (no 840D syntax), TRAOOF for TRAFOOF, G503 (no 840D G code) and a CYCLE84 without a pitch (alarm 61001)",
    ),
    (
        "haas-fanuc-style_nx-post_vf2-trunnion-ab_Haas_5T.nc",
        "haas-vf2-tr",
        "its five-axis operation feeds A and B in G94 without G234 (line 544 on), where Haas asks for G93 inverse time (Mill NGC Operator's Manual, Five-Axis Programming Notes) and would feed the rotary axes at the part diameter of Settings 34/79, the job's; and NX's G83 with Q0.0 (977:41, a peck of nothing, FANUC alarm PS0045)",
    ),
    (
        "heidenhain-klartext-french_deckel-dmc75v_CYCL19_training_deckel.h",
        "deckel-dmc-75v",
        "M91 in a tilted working plane (TNC 426 B ISO §7.3); with the tool table its `;DIA OUTIL` comments give, the TNC stops at its first pocket (\"Tool radius too large\": an approach arc R3 inside the contour for tool 3 of 10 mm); CALL PGM TNC:\\FIN calls a program not given. After that stop lie its cycles 202 and 203 (not read) and CP IPA+360 with DR- (the TNC wants one sign)",
    ),
];

/// Programs of the corpus not read yet, with what stops them (printed, not asserted).
const NOT_YET: &[(&str, &str)] = &[
    ("heidenhain-millplus-iso_nx-post_dmg-dmc160u-bc_G7-G141_sample_part.nc", "the MillPlus ISO dialect: no MillPlus manual in reach for G7's angle order, G141, G74 L1, G174 (only NX's and Autodesk's posts); the same part as the DMC 100 U's, its G141 operations at 200-334 in under G70. Refused once, naming MillPlus (the_millplus_program_is_refused_once_naming_its_language)"),
];

fn fiveaxis(args: &[&str]) -> std::process::Output {
    Command::new(env!("FIVEAXIS_EXE")).args(args).output().unwrap()
}

/// The corpus is whole: every program of SOURCES.md is either read or listed as not yet read.
#[test]
fn every_corpus_program_is_accounted_for() {
    let dir = common::outside("programs");
    let mut files: Vec<String> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).filter(|f| f != "SOURCES.md").collect();
    files.sort();
    assert_eq!(files.len(), 23, "{files:?}");
    let mut listed: Vec<String> = CLEAN
        .iter()
        .map(|c| c.file.to_string())
        .chain(REFUSED.iter().map(|(f, _, _, _)| f.to_string()))
        .chain(DEFECTIVE.iter().map(|(f, _, _)| f.to_string()))
        .chain(NOT_YET.iter().map(|(f, _)| f.to_string()))
        .collect();
    listed.sort();
    assert_eq!(files, listed);
    eprintln!("{} of 23 read with no defect, {} refused with one message, {} for several defects of their own; not yet:", CLEAN.len(), REFUSED.len(), DEFECTIVE.len());
    for (f, _, why) in DEFECTIVE {
        eprintln!("  defective {f}: {why}");
    }
    for (f, why) in NOT_YET {
        eprintln!("  {f}: {why}");
    }
}

/// Each program read with no defect on its machine (exit 0, no error diagnostic), then simulated by
/// `run`; two commands at a time (the long CL programs take a while in a debug build).
#[test]
fn corpus_programs_read_and_run_on_their_machines() {
    let jobs: Vec<(&Case, &str)> = CLEAN.iter().flat_map(|c| [(c, "analyze"), (c, "run")]).collect();
    let next = std::sync::atomic::AtomicUsize::new(0);
    let failures = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| loop {
                let Some(&(case, command)) = jobs.get(next.fetch_add(1, std::sync::atomic::Ordering::Relaxed)) else { break };
                let path = common::outside(&format!("programs/{}", case.file));
                let mut args: Vec<&str> = if command == "run" { vec!["run"] } else { vec!["program", "analyze"] };
                args.extend([path.to_str().unwrap(), "--machine", case.machine]);
                args.extend(case.args);
                let out = fiveaxis(&args);
                let stdout = String::from_utf8_lossy(&out.stdout);
                let errors: Vec<String> = stdout.lines().filter(|l| l.contains(": error:")).map(String::from).collect();
                if out.status.code() != Some(0) || !errors.is_empty() {
                    failures.lock().unwrap().push(format!("{command} {}: exit {:?}, errors {errors:#?}\n{}", case.file, out.status.code(), String::from_utf8_lossy(&out.stderr)));
                }
            });
        }
    });
    let failures = failures.into_inner().unwrap();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Each refused program: exit 2 and exactly one error, the expected one.
#[test]
fn refused_corpus_programs_say_one_clear_thing() {
    for (file, machine, flags, message) in REFUSED {
        let path = common::outside(&format!("programs/{file}"));
        let mut args = vec!["program", "analyze", path.to_str().unwrap(), "--machine", machine];
        args.extend(*flags);
        let out = fiveaxis(&args);
        let stdout = String::from_utf8_lossy(&out.stdout);
        let errors: Vec<&str> = stdout.lines().filter(|l| l.contains(": error:")).collect();
        assert_eq!(out.status.code(), Some(2), "{file}");
        assert!(errors.len() == 1 && errors[0].contains(message), "{file}: {errors:#?}");
    }
}

/// hyperMILL writes the axes its post expects above each tilted plane (`; B180 C270` before
/// `PLANE SPATIAL SPA90 SPB0 SPC90 STAY SEQ+ TABLE ROT`, then `L B+Q121 C+Q122`): on the DMU 100P
/// duoBLOCK the TNC's solution (SEQ+, Q121 and Q122) puts the axes there, to 0.001 deg (C modulo 360).
#[test]
fn hypermills_plane_comments_are_the_axes_the_plane_gives() {
    use fiveaxis::machine::Machine;
    use fiveaxis::program::{read, Dialect, ReadOptions};
    let machine = Machine::builtin("dmg-dmu-100p-duoblock").unwrap();
    let bytes = std::fs::read(common::outside("programs/heidenhain-klartext_hypermill_dmu100p-duoblock-bc_M128_W5270NS01003A25.h")).unwrap();
    let text: String = bytes.iter().map(|&b| b as char).collect(); // ISO 8859-1
    let p = read(&text, Dialect::Klartext, "dmu100p", &ReadOptions::default().on(&machine));
    assert!(!p.has_errors(), "{:?}", p.report());
    let lines: Vec<&str> = text.lines().collect();
    let mut checked = 0;
    for (i, l) in lines.iter().enumerate() {
        let Some(c) = l.split_once("; B").map(|(_, r)| r) else { continue };
        let Some((b, c)) = c.trim().split_once(" C") else { continue };
        let (Ok(b), Ok(c)) = (b.parse::<f64>(), c.parse::<f64>()) else { continue };
        // The positioning block after the plane that follows the comment.
        let k = (i..lines.len()).find(|&k| lines[k].contains("B+Q121 C+Q122")).unwrap();
        let block = p.blocks.iter().find(|bl| bl.line == k + 1).unwrap_or_else(|| panic!("line {}", k + 1));
        let (gb, gc) = (block.targets.b.unwrap().to_degrees(), block.targets.c.unwrap().to_degrees());
        let dc = (gc - c).rem_euclid(360.0);
        assert!((gb - b).abs() < 1e-3 && dc.min(360.0 - dc) < 1e-3, "line {}: hyperMILL B{b} C{c}, the TNC's plane B{gb:.3} C{gc:.3}", i + 1);
        checked += 1;
    }
    assert!(checked >= 6, "{checked} planes checked");
}

/// The hobby converter's G-code (rotaries in radians) and the Creo CL data it was made from
/// (`finition.ncl`, read with `--units mm`) describe the same tool poses on `hobby-rtcp-ab`: the
/// converter kept a GOTO when it lay more than 10 mm from the last one kept (nclReader.py `MINDIST`),
/// and our forward kinematics of each G-code block's X Y Z A B gives that GOTO's tool tip and axis.
/// This checks the machine file (axes, centres, radians) against the converter's own formula.
#[test]
fn the_hobby_converters_gcode_is_its_cl_data_on_its_machine() {
    use fiveaxis::machine::Machine;
    use fiveaxis::program::{read, Dialect, ReadOptions};
    let machine = Machine::builtin("hobby-rtcp-ab").unwrap();
    let text = |f: &str| std::fs::read_to_string(common::outside(&format!("programs/{f}"))).unwrap();
    let mm = ReadOptions { units: Some("mm".parse().unwrap()), ..ReadOptions::default() }.on(&machine);
    let cl = read(&text("apt-cl_creo-proclfile-remark-ppword_MULTAX_finition.ncl"), Dialect::Cl, "cl", &mm);
    let nc = read(&text("gcode-xyzab-radians_hobby-rtcp-converter_from-creo_finition.nc"), Dialect::Rs274, "nc", &ReadOptions::default().on(&machine));
    assert!(!cl.has_errors() && !nc.has_errors());
    // The GOTOs the converter kept, in order.
    let mut kept = Vec::new();
    let mut last = [0.0f64; 3];
    for b in &cl.blocks {
        let (Some(x), Some(y), Some(z), Some(axis)) = (b.targets.x, b.targets.y, b.targets.z, b.targets.tool_axis) else { continue };
        let tip = [x * 1e3, y * 1e3, z * 1e3];
        if (0..3).map(|k| (tip[k] - last[k]).powi(2)).sum::<f64>().sqrt() > 10.0 {
            kept.push((tip, axis));
            last = tip;
        }
    }
    assert_eq!(kept.len(), nc.blocks.len(), "one G-code block per GOTO kept");
    let (mut worst_tip, mut worst_axis) = (0.0f64, 0.0f64);
    for (b, (tip, axis)) in nc.blocks.iter().zip(&kept) {
        let t = &b.targets;
        let q = [t.x.unwrap(), t.y.unwrap(), t.z.unwrap(), t.b.unwrap(), t.a.unwrap()];
        let pose = machine.forward(&q);
        worst_tip = worst_tip.max((0..3).map(|k| (pose.tip[k] * 1e3 - tip[k]).powi(2)).sum::<f64>().sqrt());
        // The converter's angles are exact where the tool axis has no j (a = asin(j) - pi/2); the CL
        // data's j stays within 1e-5 of 0.
        worst_axis = worst_axis.max((0..3).map(|k| (pose.axis[k] - axis[k]).powi(2)).sum::<f64>().sqrt());
    }
    eprintln!("{} poses: worst tip {worst_tip:.2e} mm, axis {worst_axis:.2e}", kept.len());
    assert!(worst_tip < 1e-3 && worst_axis < 1e-4, "worst tip {worst_tip} mm, axis {worst_axis}");
}

/// The stutter NX's Fanuc post for the NMV5000 writes: the spiral out of B = 0 (VARIABLE_CONTOUR_MCS9,
/// lines 439-785: `B0.0 C315.` then `X-.0004 B-.274 C369.167`, 54 deg of C in 0.0004 in at F9.8
/// in/min). Its C speed per block, computed independently from the program's words with numpy
/// (tests/peer/block_speeds.py: under G43.4 the tip moves straight at F, the rotary axes linear in
/// the block), against `program analyze`: the same peak at the same line, the region from the first
/// block over the machine's C limit to the last, close to the singular direction (within the 15 deg
/// the monitor calls a singularity).
#[test]
fn the_nmv5000_spiral_out_of_b0_is_found_as_computed_independently() {
    let file = common::outside("programs/fanuc-G43.4_nx-post_mori-nmv5000-bc_near-B0_MS_NMV_sample_output.nc");
    let out = fiveaxis(&["program", "analyze", file.to_str().unwrap(), "--machine", "mori-seiki-nmv5000", "--json"]);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let limit = report["c_max_rpm"].as_f64().unwrap();
    let peer = Command::new("python3")
        .args([concat!(env!("FIVEAXIS_ROOT"), "/tests/peer/block_speeds.py"), file.to_str().unwrap(), "439", "785", "C", &limit.to_string(), "X0 Y0 Z-.3881 B0 C315 F9.8"])
        .output()
        .unwrap();
    assert!(peer.status.success(), "{}", String::from_utf8_lossy(&peer.stderr));
    let numpy: serde_json::Value = serde_json::from_slice(&peer.stdout).unwrap();
    let (ours, theirs) = (report["peak_c_speed_rpm"].as_f64().unwrap(), numpy["peak_rpm"].as_f64().unwrap());
    eprintln!("peak C: ours {ours:.3} rpm at line {}, numpy {theirs:.3} rpm at line {}", report["peak_c_speed_line"], numpy["peak_line"]);
    assert!((ours - theirs).abs() <= 1e-3 * theirs, "peak C: ours {ours} rpm, numpy {theirs} rpm");
    assert_eq!(report["peak_c_speed_line"], numpy["peak_line"]);
    let over: Vec<u64> = numpy["over_limit_lines"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap()).collect();
    let regions: Vec<(u64, u64, f64)> = report["regions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r["line_start"].as_u64().unwrap(), r["line_end"].as_u64().unwrap(), r["min_singularity_distance_deg"].as_f64().unwrap()))
        .filter(|r| r.1 >= 439 && r.0 <= 785)
        .collect();
    assert_eq!((regions[0].0, regions.last().unwrap().1), (over[0], *over.last().unwrap()), "{regions:?}");
    let inside = over.iter().filter(|n| regions.iter().any(|r| r.0 <= **n && **n <= r.1)).count();
    assert!(inside as f64 >= 0.95 * over.len() as f64, "{inside} of {} blocks over the limit in our regions", over.len());
    assert!(regions[0].2 < 15.0, "the first region's closest approach {} deg", regions[0].2);
    assert_eq!(first_region_cause(&report, 439), "singularity");
    eprintln!("{} blocks over {limit:.0} rpm (numpy), {inside} inside the regions {regions:?}", over.len());
}

/// The cause `program analyze` gives the first region from `line` on.
fn first_region_cause(report: &serde_json::Value, line: u64) -> String {
    let r = report["regions"].as_array().unwrap().iter().find(|r| r["line_end"].as_u64().unwrap() >= line).expect("a region");
    r["cause"].as_str().unwrap().to_string()
}

/// NX's 840D post for the DMU 70 eVo: `G00 B0.0`, `G00 C185.644`, `TRAORI`, then the spiral out of
/// B = 0 (VARIABLE_CONTOUR_MCS9, lines 480-828: `G01 X.9857 Y.9845 B.387 C9.03 F9.8`, 176.6 deg of C in
/// 0.0014 in). Its C speed per block from the program's words with numpy (tests/peer/block_speeds.py:
/// under TRAORI the tip moves straight at F, the block's C change over its time) against `program
/// analyze` on the machine's file: the same peak at the same line, every block over the C limit inside
/// a region, the regions from the first such block to the last (or the block after it, whose 29.997
/// rpm the planner's smoothing across the block end takes over 30), cause `singularity`.
#[test]
fn the_dmu70_evo_spiral_out_of_b0_is_found_as_computed_independently() {
    let file = common::outside("programs/sinumerik-840d_nx-post_dmu70evo-bc_TRAORI-C-unwound_Sample_part.mpf");
    let out = fiveaxis(&["program", "analyze", file.to_str().unwrap(), "--machine", "dmg-dmu-70-evo", "--json"]);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let limit = report["c_max_rpm"].as_f64().unwrap();
    let peer = Command::new("python3")
        .args([concat!(env!("FIVEAXIS_ROOT"), "/tests/peer/block_speeds.py"), file.to_str().unwrap(), "480", "828", "C", &limit.to_string(), "X.9843 Y.9843 Z1.5804 B0 C185.644 F9.8"])
        .output()
        .unwrap();
    assert!(peer.status.success(), "{}", String::from_utf8_lossy(&peer.stderr));
    let numpy: serde_json::Value = serde_json::from_slice(&peer.stdout).unwrap();
    let (ours, theirs) = (report["peak_c_speed_rpm"].as_f64().unwrap(), numpy["peak_rpm"].as_f64().unwrap());
    eprintln!("peak C: ours {ours:.3} rpm at line {}, numpy {theirs:.3} rpm at line {}", report["peak_c_speed_line"], numpy["peak_line"]);
    assert!((ours - theirs).abs() <= 1e-3 * theirs, "peak C: ours {ours} rpm, numpy {theirs} rpm");
    assert_eq!(report["peak_c_speed_line"], numpy["peak_line"]);
    let over: Vec<u64> = numpy["over_limit_lines"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap()).collect();
    let regions: Vec<(u64, u64)> = report["regions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r["line_start"].as_u64().unwrap(), r["line_end"].as_u64().unwrap()))
        .filter(|r| r.1 >= 480 && r.0 <= 828)
        .collect();
    let (first, last) = (regions[0].0, regions.last().unwrap().1);
    assert!(first == over[0] && (last == *over.last().unwrap() || last == over.last().unwrap() + 1), "regions {regions:?}, numpy over the limit {over:?}");
    assert!(over.iter().all(|n| regions.iter().any(|r| r.0 <= *n && *n <= r.1)), "{over:?} not all inside {regions:?}");
    assert!(report["regions"].as_array().unwrap().iter().filter(|r| r["line_end"].as_u64().unwrap() >= 480 && r["line_start"].as_u64().unwrap() <= 828).all(|r| r["cause"] == "singularity"));
    eprintln!("{} blocks over {limit:.0} rpm (numpy), regions {regions:?}", over.len());

    // Each block lasts its tip path over F, however finely the planner cuts the tool axis' great
    // circle beside the pole (pieces under 1 um had been timed as rotary moves: 30 s a block).
    use fiveaxis::machine::Machine;
    use fiveaxis::path::{PathOptions, Trajectory};
    use fiveaxis::program::{read, Dialect, ReadOptions};
    let machine = Machine::builtin("dmg-dmu-70-evo").unwrap();
    let text = std::fs::read_to_string(&file).unwrap();
    let program = read(&text, Dialect::Sinumerik, "dmu70", &ReadOptions::default().on(&machine));
    let traj = Trajectory::from_program(&program, &machine, &PathOptions::default());
    let mut worst = (0.0f64, 0u64);
    for (line, theirs) in numpy["seconds"].as_object().unwrap() {
        let line: usize = line.parse().unwrap();
        let ours: f64 = traj.segments.iter().filter(|s| s.line == line).map(|s| s.duration).sum();
        let theirs = theirs.as_f64().unwrap();
        let err = (ours - theirs).abs() / theirs;
        if err > worst.0 {
            worst = (err, line as u64);
        }
    }
    eprintln!("{} blocks timed, worst relative difference {:.1e} at line {}", numpy["seconds"].as_object().unwrap().len(), worst.0, worst.1);
    assert!(worst.0 < 1e-6, "line {}: block time differs from numpy's by {:.3e} (relative)", worst.1, worst.0);
}

/// NX's Haas post for the UMC-750 (G234 TCPC): the variable-axis operation
/// VARIABLE_AXIS_GUIDING_CURVES_CURVE_FILLET (lines 12869-15499, every block G01 at F10 in/min) swings C
/// fast far from the pole (390.9 rpm, line 13158, B 81.7 deg) and comes within 4.2 deg of B = 0 near its
/// end. Per block with numpy (tests/peer/block_speeds.py, as for the NMV5000): the same peak at the same
/// line; every block over the C limit inside a region, the regions from the first to the last of them;
/// each region's closest approach between the smallest angle of B to the pole over its blocks (B linear
/// in the block) and that at the ends inside it, to 0.01 deg; its cause `singularity` exactly where the
/// blocks come within 15 deg.
#[test]
fn the_umc750_variable_axis_operation_is_found_as_computed_independently() {
    let file = common::outside("programs/haas-ngc-G234_nx-post_umc750-bc_FinalToolPath.txt");
    let out = fiveaxis(&["program", "analyze", file.to_str().unwrap(), "--machine", "haas-umc-750", "--json"]);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let limit = report["c_max_rpm"].as_f64().unwrap();
    let peer = Command::new("python3")
        .args([concat!(env!("FIVEAXIS_ROOT"), "/tests/peer/block_speeds.py"), file.to_str().unwrap(), "12870", "15499", "C", &limit.to_string(), "X.1384 Y3.6787 Z.8764 B93.722 C-268.761 F10", "B"])
        .output()
        .unwrap();
    assert!(peer.status.success(), "{}", String::from_utf8_lossy(&peer.stderr));
    let numpy: serde_json::Value = serde_json::from_slice(&peer.stdout).unwrap();
    let (ours, theirs) = (report["peak_c_speed_rpm"].as_f64().unwrap(), numpy["peak_rpm"].as_f64().unwrap());
    eprintln!("peak C: ours {ours:.3} rpm at line {}, numpy {theirs:.3} rpm at line {}", report["peak_c_speed_line"], numpy["peak_line"]);
    assert!((ours - theirs).abs() <= 1e-3 * theirs, "peak C: ours {ours} rpm, numpy {theirs} rpm");
    assert_eq!(report["peak_c_speed_line"], numpy["peak_line"]);
    let over: Vec<u64> = numpy["over_limit_lines"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap()).collect();
    let regions: Vec<&serde_json::Value> = report["regions"].as_array().unwrap().iter().filter(|r| r["line_end"].as_u64().unwrap() >= 12870 && r["line_start"].as_u64().unwrap() <= 15499).collect();
    let span = |r: &serde_json::Value| (r["line_start"].as_u64().unwrap(), r["line_end"].as_u64().unwrap());
    assert_eq!((span(regions[0]).0, span(regions.last().unwrap()).1), (over[0], *over.last().unwrap()));
    let inside = over.iter().filter(|n| regions.iter().any(|r| span(r).0 <= **n && **n <= span(r).1)).count();
    assert!(inside as f64 >= 0.95 * over.len() as f64, "{inside} of {} blocks over the limit in our regions", over.len());
    let tilt = numpy["tilt_deg"].as_object().unwrap();
    let mut singular = 0;
    let at = |l: u64, k: usize| tilt.get(&l.to_string()).and_then(|v| v[k].as_f64());
    for r in &regions {
        let (a, b) = span(r);
        // The region lies within its blocks (no closer than they come) and holds the ends of all
        // but its last (no farther than those).
        let closest = (a..=b).filter_map(|l| at(l, 0)).fold(f64::INFINITY, f64::min);
        let ends = (a..b).filter_map(|l| at(l, 1)).fold(f64::INFINITY, f64::min);
        let d = r["min_singularity_distance_deg"].as_f64().unwrap();
        assert!(d >= closest - 0.01 && d <= ends + 0.01, "region {a}-{b}: closest {d} deg; numpy: the blocks come to {closest}, their ends inside to {ends}");
        assert_eq!(r["cause"], if closest <= 15.0 { "singularity" } else { "rotary_feed" }, "region {a}-{b}");
        singular += usize::from(closest <= 15.0);
    }
    assert!(singular >= 5, "{singular} regions near B = 0");
    eprintln!("{} blocks over {limit:.0} rpm (numpy), {inside} inside {} regions, {singular} of them within 15 deg of B = 0", over.len(), regions.len());
}

/// The FTV5 program's defects, as the 840D reads them: an error on each line NX's post wrote
/// `M202(...)` (a bracket after an M number), `TRAOOF`, `G503`, and on the `MCALL CYCLE84` whose MPIT
/// and PIT are both empty (alarm 61001): its CYCLE800 swivels, TRAORI(1) operations and the rest read
/// (the swivels' angles: tests/sinumerik.rs). And what they leave: `TRAOOF`, a program not found,
/// which the control would run, leaves every axis unknown (X, Y, Z, and the FTV5's A and C); the
/// `CYCLE800` after it sets its plane (read) but its moves are not read, and it turns A and C to
/// known positions but retracts machine Z only (`_FR` 1), so the first move after it starts from an
/// unknown X, Y and Z. A move from unknown axes is refused and makes those it writes known; a
/// deselection `CYCLE800()` moves nothing. The refused `MCALL CYCLE84` is an alarm, at which the
/// control stops: said once, the moves after it read as the rest of the program.
#[test]
fn the_ftv5_programs_defects_are_refused_as_the_840d_refuses_them() {
    let file = common::outside("programs/sinumerik-840d_nx-post_cincinnati-ftv5_CYCLE800-TRAORI1_sample.mpf");
    let text = std::fs::read_to_string(&file).unwrap();
    let every = || "XYZAC".chars().collect::<Vec<char>>();
    let mut unknown = Vec::<char>::new();
    let mut expected: Vec<(usize, String)> = Vec::new();
    for (i, l) in text.lines().enumerate() {
        let (line, l) = (i + 1, l.trim());
        let cycle84_without_pitch = l.split_once("MCALL CYCLE84(").is_some_and(|(_, a)| {
            let a: Vec<&str> = a.split(',').map(str::trim).collect();
            a.get(7).is_none_or(|m| m.is_empty()) && a.get(8).is_none_or(|p| p.is_empty())
        });
        // A block of words, an address and its number first (not CYCLE800, MCALL ...).
        let moves = l.starts_with(['G', 'X', 'Y', 'Z', 'A', 'C']) && l[1..].starts_with(|c: char| c.is_ascii_digit() || "-.+".contains(c)) && !l.contains("G503");
        let why = if l.contains("M202(") {
            "not 840D syntax".to_string()
        } else if l == "TRAOOF" {
            unknown = every();
            "TRAOOF: a call of the subprogram TRAOOF, whose file (TRAOOF.SPF) is neither beside the program".to_string()
        } else if l.contains("G503") {
            "G503: unknown G code".to_string()
        } else if cycle84_without_pitch {
            "alarm 61001".to_string()
        } else if l.starts_with("CYCLE800(") && l != "CYCLE800()" && !unknown.is_empty() {
            unknown.retain(|c| !"AC".contains(*c));
            "the plane it sets is read, but its own moves, which start there, are not".to_string()
        } else if moves && !unknown.is_empty() {
            let said = match unknown.len() {
                1 => unknown[0].to_string(),
                n => format!("{} and {}", unknown[..n - 1].iter().map(|c| c.to_string()).collect::<Vec<_>>().join(", "), unknown[n - 1]),
            };
            let once = format!("once {said} {} written absolute", if unknown.len() == 1 { "is" } else { "are" });
            unknown.retain(|c| !l.split_whitespace().any(|w| w.starts_with(*c)));
            expected.push((line, "a move from where the moves under line".to_string()));
            once
        } else {
            continue;
        };
        expected.push((line, why));
    }
    let out = fiveaxis(&["program", "analyze", file.to_str().unwrap(), "--machine", "cincinnati-ftv5"]);
    assert_eq!(out.status.code(), Some(2));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let errors: Vec<(usize, &str)> = stdout.lines().filter(|l| l.contains(": error:")).map(|e| (e.split(".mpf:").nth(1).unwrap().split(':').next().unwrap().parse().unwrap(), e)).collect();
    let mut lines: Vec<usize> = expected.iter().map(|e| e.0).collect();
    lines.dedup();
    assert_eq!(errors.iter().map(|e| e.0).collect::<Vec<_>>(), lines, "{errors:#?}");
    for (line, why) in &expected {
        let e = errors.iter().find(|e| e.0 == *line).map_or("", |e| e.1);
        assert!(e.contains(why.as_str()), "line {line}: {e}, expected {why:?}");
    }
    eprintln!("{} lines refused: {:?}", errors.len(), expected);
}

/// The DMU 70 eVo program's defects, as the 840D reads them: an error on each `MCALL CYCLE..` line
/// whose cycle would move (RFP != DP); each names the alarm (61101: RTP on the depth's side of RFP),
/// the empty FRF of CYCLE83 (its first infeed at F0) or CYCLE76 (spigot milling). An alarm is said
/// once (the control stops there). CYCLE76, not read, the control runs after every move: those
/// moves are held until `MCALL` alone, after which X, Y, Z, B and C are unknown; a move from unknown
/// axes is refused and makes those it writes known. No error elsewhere.
#[test]
fn the_dmu70_evo_programs_drilling_cycles_are_refused_as_the_840d_refuses_them() {
    let file = common::outside("programs/sinumerik-840d_nx-post_dmu70evo-bc_TRAORI-C-unwound_Sample_part.mpf");
    let text = std::fs::read_to_string(&file).unwrap();
    let (mut unknown, mut held) = (Vec::<char>::new(), None::<usize>);
    let mut expected: Vec<(usize, String)> = Vec::new();
    for (i, l) in text.lines().enumerate() {
        let line = i + 1;
        let words: Vec<&str> = l.split_whitespace().filter(|w| !w.starts_with('N')).collect();
        let written = |c: char| words.iter().any(|w| w.starts_with(c) && w[1..].starts_with(|d: char| d.is_ascii_digit() || "-.+".contains(d)));
        let moves = "XYZBC".chars().any(written);
        if let Some((_, call)) = l.split_once("MCALL CYCLE") {
            let args = call.split_once('(').unwrap().1.trim_end().trim_end_matches(')');
            let a: Vec<&str> = args.split(',').collect();
            if call.starts_with("76") {
                held = Some(line);
                expected.push((line, "CYCLE76".into()));
            } else if a.get(1) != a.get(3) || a.get(4).is_some_and(|d| !d.is_empty()) {
                // RFP = DP (and no DPR): the cycle returns at once (CYCLE81-84.SPF).
                expected.push((line, String::new()));
            }
        } else if l.trim_start_matches(|c: char| c == 'N' || c.is_ascii_digit()).trim() == "MCALL" {
            if held.take().is_some() {
                unknown = "XYZBC".chars().collect();
            }
        } else if let (Some(at), true) = (held, moves) {
            expected.push((line, format!("a move while line {at}'s MCALL (a modal call (MCALL) refused) is in effect")));
        } else if moves && !unknown.is_empty() {
            expected.push((line, "a move from where the moves under line".into()));
            unknown.retain(|c| !written(*c));
        }
    }
    let out = fiveaxis(&["program", "analyze", file.to_str().unwrap(), "--machine", "dmg-dmu-70-evo"]);
    assert_eq!(out.status.code(), Some(2));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let errors: Vec<&str> = stdout.lines().filter(|l| l.contains(": error:")).collect();
    let lines: Vec<usize> = errors.iter().map(|e| e.split(".mpf:").nth(1).unwrap().split(':').next().unwrap().parse().unwrap()).collect();
    assert_eq!(lines, expected.iter().map(|e| e.0).collect::<Vec<_>>(), "{errors:#?}");
    for (e, (line, why)) in errors.iter().zip(&expected) {
        let cause = why.is_empty() && (e.contains("alarm 61101") || e.contains("FRF=0"));
        assert!(cause || !why.is_empty() && e.contains(why.as_str()), "line {line}: {e}, expected {why:?}");
    }
    eprintln!("{} lines refused: {:?}", lines.len(), lines);
}

/// SOLIDWORKS CAM's boss for a DMU 50: its second set-up (`CSYS/0,0,1.,0,1.,0,0,0,0,1.,0,0`, every
/// GOTO with the tool along +X) puts the table at B 90, C 0 on `dmg-dmu-50`, as the AptPostProcessor
/// project's own post computes it for this file (its test output `boss/12.h`: "axis 1.000 0.000
/// 0.000 rot 0.000 tilt 90.000"; B = acos(k), C = atan2(j, i)); B -90 lies outside the table's range.
#[test]
fn the_solidworks_boss_second_setup_tilts_the_dmu50_table_as_its_post_does() {
    use fiveaxis::kinematics::Pose;
    use fiveaxis::machine::Machine;
    use fiveaxis::program::{read, Dialect, ReadOptions};
    let machine = Machine::builtin("dmg-dmu-50").unwrap();
    let text = std::fs::read_to_string(common::outside("programs/apt-cl_solidworks-cam_boss_GOTO-ijk_CSYS.apt")).unwrap();
    let p = read(&text, Dialect::Cl, "boss.apt", &ReadOptions::default().on(&machine));
    assert!(!p.has_errors(), "{:?}", p.report());
    let deg = fiveaxis::units::DEG;
    let mut checked = 0;
    for b in p.blocks.iter().filter(|b| b.line > 5551) {
        let (Some(x), Some(y), Some(z), Some(axis)) = (b.targets.x, b.targets.y, b.targets.z, b.targets.tool_axis) else { continue };
        let pose = Pose { tip: nalgebra::Vector3::new(x, y, z), axis: nalgebra::Vector3::from(axis) };
        let q = machine.inverse_in_rotary_ranges(&pose, &[0.0; 5]).unwrap();
        let (bb, c) = (q[3] / deg, (q[4] / deg).rem_euclid(360.0));
        assert!((bb - 90.0).abs() < 1e-9 && c.min(360.0 - c) < 1e-9, "line {}: B {bb} C {c}", b.line);
        checked += 1;
    }
    assert_eq!(checked, 5751, "every GOTO of the second set-up");
}

/// The DMC 100 U program's defects, as the TNC reads it: an error at the Z of each `CC X.. Y.. Z..`
/// (found here by scanning the file), arc errors only on `C` blocks of the operations that hold such
/// centres (in the working plane XY those circles have no radius, or two), range errors only on the
/// M91 moves of its start-up subprogram (lines 7 and 8: from where the far operations left the
/// axes) and one at the header (the unit of an inch program's F, which the machine file does not
/// settle); nothing else. Its `M140 MB MAX F99999` (line 5) and DMG's M57 read clean.
#[test]
fn the_dmc100u_programs_defects_are_refused_as_the_tnc_reads_them() {
    let file = common::outside("programs/heidenhain-klartext_nx-post_dmg-dmc100-bc_M128-simultaneous_Sample_part.h");
    let text: String = std::fs::read(&file).unwrap().iter().map(|&b| b as char).collect();
    let lines: Vec<&str> = text.lines().collect();
    let words = |i: usize| lines[i - 1].split_whitespace().collect::<Vec<_>>();
    let cc_xyz: Vec<usize> = (1..=lines.len()).filter(|&i| words(i).get(1) == Some(&"CC") && ["X", "Y", "Z"].iter().all(|a| words(i).iter().any(|t| t.starts_with(a)))).collect();
    assert_eq!(cc_xyz.len(), 23);
    // Each line's operation (counted by TOOL CALL), and the operations that hold such a centre.
    let op: Vec<usize> = lines.iter().scan(0, |n, l| {
        *n += usize::from(l.contains("TOOL CALL"));
        Some(*n)
    }).collect();
    let ops_with_cc: Vec<usize> = cc_xyz.iter().map(|&i| op[i - 1]).collect();
    // Its feeds are whole inch/min (F78.7 is 2000 mm/min), where an inch program's F is in 1/10
    // inch/min on the TNC7 (the machine file does not say which, so the header is refused once and
    // F read in tenths): at a tenth of NX's feeds the program runs 77 h, beyond the default bound.
    // Its errors are the reader's and each block's, not the samples': sampled every 100 ms (2.8 M
    // samples, not 278 M at 1 ms, 100 CPU-s of a debug build) they are the same.
    let out = fiveaxis(&["program", "analyze", file.to_str().unwrap(), "--machine", "dmg-dmc-100u", "--max-program-hours", "100", "--period-ms", "100"]);
    assert_eq!(out.status.code(), Some(2));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let errors: Vec<(usize, &str)> = stdout.lines().filter(|l| l.contains(": error:")).map(|e| (e.split(".h:").nth(1).unwrap().split(':').next().unwrap().parse().unwrap(), e)).collect();
    let mut centres = Vec::new();
    for (line, e) in &errors {
        if e.contains("CC Z: not an axis of the working plane") {
            centres.push(*line);
        } else if *line == 1 && e.contains("tnc_inch_feed") {
        } else if e.contains("zero-radius arc") || e.contains("the radius to the end") {
            assert!(words(*line).get(1) == Some(&"C") && ops_with_cc.contains(&op[line - 1]), "line {line}: {e}");
        } else {
            assert!((*line == 7 || *line == 8) && e.contains("outside its range"), "line {line}: {e}");
        }
    }
    assert_eq!(centres, cc_xyz);
}

/// The Deckel DMC 75V program (on its four-axis model), as the TNC reads it with the tool table its
/// `;DIA OUTIL = d` comments give (each after its `TOOL CALL n`: tool n of radius d / 2, written here):
/// an error at each M91 in a tilted working plane (after a `CYCL DEF 19.1` with angles, until one
/// without), found here by scanning the file, up to the first contour the tool cannot follow, where
/// the TNC stops ("Tool radius too large": found here as the first `CR .. R+r DR+` with r below the
/// tool's radius after an RL block, the tool inside the arc), and its `CALL PGM` of a program not given. Nothing else; the report
/// names the machine four-axis.
#[test]
fn the_deckel_programs_defects_are_refused_as_the_tnc_reads_them() {
    let file = common::outside("programs/heidenhain-klartext-french_deckel-dmc75v_CYCL19_training_deckel.h");
    let text: String = std::fs::read(&file).unwrap().iter().map(|&b| b as char).collect();
    let lines: Vec<&str> = text.lines().collect();
    let dir = common::scratch_dir("deckel");
    // The tool table, and the expected errors, from the file's own lines.
    let (mut table, mut tool, mut radius) = (String::from("BEGIN TOOL.T MM\nT       NAME       L           R\n"), 0u32, std::collections::BTreeMap::new());
    let (mut tilted, mut rl, mut m91, mut stop, mut call) = (false, false, Vec::new(), None, Vec::new());
    for (i, l) in lines.iter().enumerate() {
        let w: Vec<&str> = l.split_whitespace().collect();
        if let Some(k) = w.iter().position(|t| *t == "CALL") {
            if w.get(k + 1) == Some(&"PGM") {
                call.push(i + 1);
            } else if k > 0 && w[k - 1] == "TOOL" {
                tool = w[k + 1].parse().unwrap();
            }
        }
        if let Some(d) = l.strip_prefix(";DIA OUTIL = ") {
            let d: f64 = d.split_whitespace().next().unwrap().parse().unwrap();
            if radius.insert(tool, d / 2.0).is_none() {
                table += &format!("{tool:<8}T{tool:<9} +100        +{}\n", d / 2.0);
            }
        }
        if l.contains("CYCL DEF 19.1") {
            tilted = w.len() > 4;
        }
        if tilted && w.contains(&"M91") && stop.is_none() {
            m91.push(i + 1);
        }
        if w.get(1) == Some(&"L") {
            rl = w.contains(&"RL") || (rl && !w.contains(&"R0"));
        }
        // Left of a counter-clockwise arc: the tool is inside it.
        if rl && w.get(1) == Some(&"CR") && w.contains(&"DR+") && stop.is_none() {
            let r: f64 = w.iter().find_map(|t| t.strip_prefix("R+")).unwrap().parse().unwrap();
            if r < radius[&tool] {
                stop = Some(i + 1);
            }
        }
    }
    table += "[END]\n";
    let tools = dir.join("TOOL.T");
    std::fs::write(&tools, table).unwrap();
    let stop = stop.expect("a contour the tool cannot follow");
    assert!(!m91.is_empty() && call.len() == 1, "{m91:?} {call:?}");
    let out = fiveaxis(&["program", "analyze", file.to_str().unwrap(), "--machine", "deckel-dmc-75v", "--tool-table", tools.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("four-axis: one rotary axis, A; no singular orientation"), "{stdout}");
    let errors: Vec<(usize, &str)> = stdout.lines().filter(|l| l.contains(": error:")).map(|e| (e.split(".h:").nth(1).unwrap().split(':').next().unwrap().parse().unwrap(), e)).collect();
    let at = |what: &str| errors.iter().filter(|(_, e)| e.contains(what)).map(|(l, _)| *l).collect::<Vec<_>>();
    assert_eq!(at("machine coordinates in a tilted working plane"), m91, "{errors:#?}");
    assert_eq!(at("Tool radius too large"), [stop], "{errors:#?}");
    assert_eq!(at("CALL PGM"), call, "{errors:#?}");
    assert_eq!(errors.len(), m91.len() + 1 + call.len(), "{errors:#?}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The Haas VF-2 TR program's two defects, found here from its text: its first feed move (G01, G02
/// or G03 in effect) that turns A or B, with neither G93 nor G234 anywhere in the program, is said
/// once for the five-axis operation it opens (Haas asks for G93 for simultaneous motion, or G234 for
/// G94); its G83 with `Q0.0` is refused at the Q word. No other error; the operation's moves are
/// read as written (a region of B speed is found in it).
#[test]
fn the_vf2_programs_defects_are_refused_as_haas_reads_them() {
    let path = common::outside("programs/haas-fanuc-style_nx-post_vf2-trunnion-ab_Haas_5T.nc");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(!text.contains("G93") && !text.contains("G234"), "the program sets no inverse time and no TCPC");
    let (mut motion, mut ab, mut first) = (0, [0.0f64; 2], None);
    for (i, l) in text.lines().enumerate() {
        let words: Vec<&str> = l.split_whitespace().collect();
        for w in &words {
            if let Some(g) = w.strip_prefix('G').and_then(|g| g.parse::<u32>().ok()).filter(|g| *g <= 3) {
                motion = g;
            }
        }
        for (k, letter) in ['A', 'B'].into_iter().enumerate() {
            if let Some(v) = words.iter().find_map(|w| w.strip_prefix(letter).and_then(|v| v.parse::<f64>().ok())) {
                if motion >= 1 && v != ab[k] && first.is_none() {
                    first = Some(i + 1);
                }
                ab[k] = v;
            }
        }
    }
    let first = first.expect("a feed move of A or B");
    let (peck_line, peck_col) = text.lines().enumerate().find_map(|(i, l)| (l.starts_with("G83") && l.contains("Q0.0")).then(|| (i + 1, l.find("Q0.0").unwrap() + 1))).unwrap();
    let out = fiveaxis(&["program", "analyze", path.to_str().unwrap(), "--machine", "haas-vf2-tr"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let errors: Vec<&str> = stdout.lines().filter(|l| l.contains(": error:")).collect();
    assert_eq!(out.status.code(), Some(2), "{stdout}");
    assert_eq!(errors.len(), 2, "{errors:#?}");
    assert!(errors[0].contains(&format!(":{first}:1: error: a feed move of a rotary axis in G94 without G234")) && errors[0].contains("said once"), "{errors:#?}");
    assert!(errors[1].contains(&format!(":{peck_line}:{peck_col}: error: Q0.0")), "{errors:#?}");
    assert!(stdout.contains("regions where B speed"), "{stdout}");
}

/// The MillPlus program is not read as G-code (its `.nc` name says RS274, where nearly every block
/// would be an error): it is refused once, at its first tilted plane `G7 A5= B5= C5=`, naming the
/// language; the only other error is that nothing was read.
#[test]
fn the_millplus_program_is_refused_once_naming_its_language() {
    let path = common::outside("programs/heidenhain-millplus-iso_nx-post_dmg-dmc160u-bc_G7-G141_sample_part.nc");
    let text = std::fs::read_to_string(&path).unwrap();
    // Its first G7 block, found here independently of the reader.
    let (line, g7) = text.lines().enumerate().find(|(_, l)| l.contains(" G7 ") && l.contains("A5=")).map(|(i, l)| (i + 1, l.find("G7").unwrap() + 1)).unwrap();
    let out = fiveaxis(&["program", "analyze", path.to_str().unwrap(), "--machine", "generic-bc-head"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let errors: Vec<&str> = stdout.lines().filter(|l| l.contains(": error:")).collect();
    assert_eq!(out.status.code(), Some(2), "{stdout}");
    assert_eq!(errors.len(), 2, "{errors:#?}");
    assert!(errors.iter().any(|e| e.contains(&format!(":{line}:{g7}: error:")) && e.contains("Heidenhain MillPlus")), "{errors:#?}");
    assert!(errors.iter().any(|e| e.contains("no moves: 0 blocks read")), "{errors:#?}");
    // Given as RS274 on purpose, it is read as such (and refused block by block).
    let forced = fiveaxis(&["program", "analyze", path.to_str().unwrap(), "--machine", "generic-bc-head", "--dialect", "rs274"]);
    let forced_out = String::from_utf8_lossy(&forced.stdout);
    assert_eq!(forced.status.code(), Some(2));
    assert!(!forced_out.contains("Heidenhain MillPlus") && forced_out.matches(": error:").count() > 100, "{forced_out}");
}
