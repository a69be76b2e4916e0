//! Where the tests find the repository and the workspace's executables: the repository is this
//! package's parent, and Cargo puts the executables in the profile's folder of the target directory,
//! three levels above this script's OUT_DIR (`target/debug/build/fiveaxis-tests-<hash>/out`).
use std::path::PathBuf;

fn main() {
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("Cargo sets CARGO_MANIFEST_DIR"));
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("Cargo sets OUT_DIR"));
    let root = manifest.parent().expect("the tests package lies in the repository");
    let executables = out.ancestors().nth(3).expect("OUT_DIR is target/<profile>/build/<package>/out");
    println!("cargo::rustc-env=FIVEAXIS_ROOT={}", root.display());
    println!("cargo::rustc-env=FIVEAXIS_EXE={}", executables.join("fiveaxis").display());
    println!("cargo::rerun-if-changed=build.rs");
}
