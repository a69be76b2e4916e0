//! The corpus programs that read with no defect on their built-in machine: one table for the corpus
//! test (tests/corpus.rs) and the readers bench's real-program rows (benches/readers.rs).

/// A corpus program, the built-in machine it was written for, and any flag its file cannot say.
pub(crate) struct Case {
    pub file: &'static str,
    pub machine: &'static str,
    pub args: &'static [&'static str],
}

/// Programs that read with no defect on their machine, and simulate.
pub(crate) const CLEAN: &[Case] = &[
    Case { file: "linuxcnc-rs274ngc_impeller-7bl-xyzac.ngc", machine: "linuxcnc-xyzac-trt", args: &[] },
    Case { file: "linuxcnc-rs274ngc_boat-xyzac-hermle.ngc", machine: "linuxcnc-xyzac-trt", args: &[] },
    Case { file: "linuxcnc-rs274ngc_boat-xyzbc-hermle.ngc", machine: "linuxcnc-xyzbc-trt", args: &[] },
    Case { file: "linuxcnc-rs274ngc_xyzab-tdr-demo.ngc", machine: "linuxcnc-xyzab-tdr", args: &[] },
    // O-word loops, named parameters and its W quill (tests/readers.rs checks both against LinuxCNC).
    Case { file: "linuxcnc-rs274ngc_bridgemill-5axisgui-oword.ngc", machine: "linuxcnc-bridgemill", args: &[] },
    // Creo's CL data says UNITS / INCHES on millimetres (a 5.4 m part in inches; its feed of 1193.66
    // "IPM" is the converter's F1193.663 mm/min): read with --units mm, as the reader's warning offers.
    Case { file: "apt-cl_creo-proclfile_MULTAX-GOTO-ijk_finition2.ncl", machine: "hobby-rtcp-ab", args: &["--units", "mm"] },
    Case { file: "apt-cl_creo-proclfile-remark-ppword_MULTAX_finition.ncl", machine: "hobby-rtcp-ab", args: &["--units", "mm"] },
    Case { file: "gcode-xyzab-radians_hobby-rtcp-converter_from-creo_finition.nc", machine: "hobby-rtcp-ab", args: &[] },
    Case { file: "haas-ngc-G234_nx-post_umc750-bc_FinalToolPath.txt", machine: "haas-umc-750", args: &[] },
    Case { file: "heidenhain-klartext_hypermill_dmu100p-duoblock-bc_M128_W5270NS01003A25.h", machine: "dmg-dmu-100p-duoblock", args: &[] },
    Case { file: "heidenhain-klartext_hypermill_dmu85-monoblock-ac_large-3plus2_W5270NS01061A16.h", machine: "dmg-dmu-85-monoblock", args: &[] },
    Case { file: "heidenhain-klartext_hypermill_trimill-vu3019_W5269NS01002A21.h", machine: "trimill-vu3019", args: &[] },
    Case { file: "sinumerik-840dsl_nx-post_spinner-u5-620-bc_TRAORI-AROT_Achskreuz.mpf", machine: "spinner-u5-620", args: &[] },
    // SOLIDWORKS CAM for a DMU 50 (the AptPostProcessor project's machine): 3+2 by CSYS, CUTCOM.
    Case { file: "apt-cl_solidworks-cam_boss_GOTO-ijk_CSYS.apt", machine: "dmg-dmu-50", args: &[] },
];
