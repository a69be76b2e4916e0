//! A development aid, run by hand: this reader against LinuxCNC's own interpreter on generated
//! programs. `recordings/programs/linuxcnc/diff/generate.py` writes programs and runs Debian's `rs274`
//! on them (its canonical output, or its refusal); this reads each program and says where the two
//! differ: a refusal on one side only, or moves, centres or feeds apart (as the fixture tests compare).

use super::*;

/// `FIVEAXIS_DIFF_DIR=<dir> cargo test ... differential -- --ignored --nocapture`: one line per
/// program that differs, and a count.
#[test]
#[ignore]
fn differential_against_rs274() {
    let Ok(dir) = std::env::var("FIVEAXIS_DIFF_DIR") else { return };
    let dir = Path::new(&dir);
    // LinuxCNC's sample machine: its machine zero and G28/G30 points are rs274's (0).
    let machine = fiveaxis::machine::Machine::builtin("linuxcnc-xyzac-trt").unwrap();
    let mut options = ReadOptions::default().on(&machine);
    if let Ok(t) = std::fs::read_to_string(dir.join("tools.tbl")) {
        // rs274 alone reads a tool table in inches (its machine units without an INI).
        options.tool_table = Some(std::sync::Arc::new(fiveaxis::program::ToolTable::parse(&t).unwrap().in_unit(fiveaxis::program::LengthUnit::Inch)));
    }
    let mut names: Vec<_> = std::fs::read_dir(dir).unwrap().filter_map(|e| e.ok()).map(|e| e.path()).filter(|p| p.extension().is_some_and(|x| x == "ngc")).collect();
    names.sort();
    let (mut same, mut differ) = (0, 0);
    std::panic::set_hook(Box::new(|_| {}));
    for ngc in &names {
        let text = std::fs::read_to_string(ngc).unwrap();
        let p = read(&text, Dialect::Rs274, "t.ngc", &options);
        let ours = errors(&p);
        let refused = std::fs::read_to_string(ngc.with_extension("err")).ok().filter(|e| !e.trim().is_empty());
        let verdict = match (ours.is_empty(), &refused) {
            (true, Some(e)) => Some(format!("rs274 refuses, we read: {}", e.trim())),
            (false, None) => Some(format!("we refuse, rs274 reads: {}", ours.iter().map(|(l, c, m)| format!("{l}:{c}: {m}")).collect::<Vec<_>>().join(" | "))),
            (false, Some(_)) => None,
            (true, None) => {
                let canon = ngc.with_extension("canon");
                std::panic::catch_unwind(|| {
                    same_places_as_linuxcnc(&p, &canon);
                })
                .err()
                .map(|e| e.downcast_ref::<String>().cloned().unwrap_or_else(|| "panic".into()).chars().take(600).collect())
            }
        };
        match verdict {
            None => same += 1,
            Some(v) => {
                differ += 1;
                println!("{}: {v}", ngc.file_name().unwrap().to_string_lossy());
            }
        }
    }
    let _ = std::panic::take_hook();
    println!("{same} the same, {differ} differ");
}
