//! Real CAM output (`../shared/outside/programs`, 23 programs from public repositories, see its
//! SOURCES.md): each program read by `fiveaxis program analyze` on the built-in machine of its maker
//! and model, with no defect, and simulated by `fiveaxis run`. Issue 64's corpus; a program not yet
//! read is listed in [`NOT_YET`] with what stops it, so the list can only shrink.

mod common;

use std::process::Command;

/// A corpus program, the built-in machine it was written for, and any flag its file cannot say.
struct Case {
    file: &'static str,
    machine: &'static str,
    args: &'static [&'static str],
}

/// Programs that read with no defect on their machine, and simulate.
const CLEAN: &[Case] = &[
    Case { file: "linuxcnc-rs274ngc_impeller-7bl-xyzac.ngc", machine: "linuxcnc-xyzac-trt", args: &[] },
    Case { file: "linuxcnc-rs274ngc_boat-xyzac-hermle.ngc", machine: "linuxcnc-xyzac-trt", args: &[] },
    Case { file: "linuxcnc-rs274ngc_boat-xyzbc-hermle.ngc", machine: "linuxcnc-xyzbc-trt", args: &[] },
    Case { file: "linuxcnc-rs274ngc_xyzab-tdr-demo.ngc", machine: "linuxcnc-xyzab-tdr", args: &[] },
];

/// Programs of the corpus not read yet, with what stops them (printed, not asserted).
const NOT_YET: &[(&str, &str)] = &[
    ("linuxcnc-rs274ngc_bridgemill-5axisgui-oword.ngc", "O-words; the W quill, a sixth axis"),
    ("haas-ngc-G234_nx-post_umc750-bc_FinalToolPath.txt", "Haas dialect, machine"),
    ("haas-fanuc-style_nx-post_vf2-trunnion-ab_Haas_5T.nc", "Haas dialect, canned cycles, machine"),
    ("fanuc-G43.4_nx-post_mori-nmv5000-bc_near-B0_MS_NMV_sample_output.nc", "Fanuc dialect, G28, cycles, machine"),
    ("fanuc-G43.4_nx-post_mori-nmv5000-bc_mm_MS_NMV_sample_mm.nc", "Fanuc dialect, G06.2 NURBS, G28, cycles, machine"),
    ("heidenhain-klartext_nx-post_dmg-dmc100-bc_M128-simultaneous_Sample_part.h", "PLANE, cycles, M91/M140, machine"),
    ("heidenhain-millplus-iso_nx-post_dmg-dmc160u-bc_G7-G141_sample_part.nc", "MillPlus dialect, machine"),
    ("heidenhain-klartext_hypermill_trimill-vu3019_W5269NS01002A21.h", "PLANE, cycles, Q arithmetic, M91, machine"),
    ("heidenhain-klartext_hypermill_dmu100p-duoblock-bc_M128_W5270NS01003A25.h", "PLANE STAY with Q120-Q122, cycles, M91/M92, machine"),
    ("heidenhain-klartext_hypermill_dmu85-monoblock-ac_large-3plus2_W5270NS01061A16.h", "PLANE, Q jumps, M91, machine"),
    ("heidenhain-klartext-french_deckel-dmc75v_CYCL19_training_deckel.h", "cycle 19, cycles, polar arcs, radius compensation, CALL PGM"),
    ("sinumerik-840dsl_nx-post_spinner-u5-620-bc_TRAORI-AROT_Achskreuz.mpf", "DEF variables, frames, CYCLE800, machine"),
    ("sinumerik-840d_nx-post_dmu70evo-bc_TRAORI-C-unwound_Sample_part.mpf", "SUPA, MCALL cycles, machine"),
    ("sinumerik-840d_nx-post_cincinnati-ftv5_CYCLE800-TRAORI1_sample.mpf", "CYCLE800, MCALL cycles, machine"),
    ("apt-cl_creo-proclfile_MULTAX-GOTO-ijk_finition2.ncl", "UNITS/INCHES on millimetre coordinates, machine"),
    ("apt-cl_creo-proclfile-remark-ppword_MULTAX_finition.ncl", "PPWORD, CAMERA, machine"),
    ("gcode-xyzab-radians_hobby-rtcp-converter_from-creo_finition.nc", "rotaries in radians, machine"),
    ("apt-cl_solidworks-cam_boss_GOTO-ijk_CSYS.apt", "CSYS frames, CUTCOM, INSERT, machine"),
    ("apt-cl_solidworks-cam_interface-glue_ROTABL-TLAXIS.clt", "ROTABL, TLAXIS, CIRCLE forms, cycles, machine"),
];

fn fiveaxis(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_fiveaxis")).args(args).output().unwrap()
}

/// The corpus is whole: every program of SOURCES.md is either read or listed as not yet read.
#[test]
fn every_corpus_program_is_accounted_for() {
    let dir = common::outside("programs");
    let mut files: Vec<String> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).filter(|f| f != "SOURCES.md").collect();
    files.sort();
    assert_eq!(files.len(), 23, "{files:?}");
    let mut listed: Vec<String> = CLEAN.iter().map(|c| c.file.to_string()).chain(NOT_YET.iter().map(|(f, _)| f.to_string())).collect();
    listed.sort();
    assert_eq!(files, listed);
    eprintln!("{} of 23 read with no defect; not yet:", CLEAN.len());
    for (f, why) in NOT_YET {
        eprintln!("  {f}: {why}");
    }
}

/// Each program read with no defect on its machine (exit 0, no error diagnostic), then simulated by `run`.
#[test]
fn corpus_programs_read_and_run_on_their_machines() {
    for case in CLEAN {
        let path = common::outside(&format!("programs/{}", case.file));
        let path = path.to_str().unwrap();
        for command in [&["program", "analyze"][..], &["run"][..]] {
            let mut args: Vec<&str> = command.to_vec();
            args.extend([path, "--machine", case.machine]);
            args.extend(case.args);
            let out = fiveaxis(&args);
            let stdout = String::from_utf8_lossy(&out.stdout);
            let errors: Vec<&str> = stdout.lines().filter(|l| l.contains(": error:")).collect();
            assert!(
                out.status.code() == Some(0) && errors.is_empty(),
                "{} {}: exit {:?}, errors {errors:#?}\n{}",
                command.join(" "),
                case.file,
                out.status.code(),
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
}
