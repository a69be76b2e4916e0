//! This reader against LinuxCNC's own interpreter on generated programs.
//! `recordings/programs/linuxcnc/diff/generate.py` writes programs and runs Debian's `rs274` on them
//! (its canonical output, or its refusal): by hand into a directory for
//! [`differential_against_rs274`], which says where the two differ (a refusal on one side only, or
//! moves, centres or feeds apart, as the fixture tests compare), and once into the committed fixture
//! that [`generated_programs_read_as_rs274_runs_them`] holds in every run.

use super::*;

/// The committed fixture (`recordings/programs/linuxcnc/diff/programs.ngcs`, 160 programs of seed 102
/// with `rs274`'s canonical lines or refusal in `rs274.txt`, made by `generate.py --fixture`): each
/// program rs274 runs reads here with no error to the same moves, XY centres and feeds (placed as
/// its canonical layer places them, on LinuxCNC's xyzac-trt sim machine, with rs274's tool table);
/// each program it refuses is refused here too.
#[test]
fn generated_programs_read_as_rs274_runs_them() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/diff");
    let programs = std::fs::read_to_string(dir.join("programs.ngcs")).unwrap();
    let canon = std::fs::read_to_string(dir.join("rs274.txt")).unwrap();
    let split = |text: &str| -> Vec<(String, String)> {
        text.split("%%% ").skip(1).map(|part| {
            let (head, body) = part.split_once('\n').unwrap_or((part, ""));
            (head.trim().to_string(), body.to_string())
        }).collect()
    };
    let (programs, canon) = (split(&programs), split(&canon));
    assert_eq!(programs.len(), 160);
    assert_eq!(programs.len(), canon.len());
    let machine = fiveaxis::machine::Machine::builtin("linuxcnc-xyzac-trt").unwrap();
    let mut options = ReadOptions::default().on(&machine);
    let table = "T1 P1 Z0 D10 ;\nT2 P2 Z5 D6 ;\n";
    options.tool_table = Some(std::sync::Arc::new(fiveaxis::program::ToolTable::parse(table).unwrap().in_unit(fiveaxis::program::LengthUnit::Inch)));
    let (mut read_both, mut refused_both, mut differ) = (0, 0, Vec::new());
    for ((name, text), (head, lines)) in programs.iter().zip(&canon) {
        let p = read(text, Dialect::Rs274, "t.ngc", &options);
        match head.split_once(" refused: ") {
            Some((n, why)) => {
                assert_eq!(n, name);
                if errors(&p).is_empty() {
                    differ.push(format!("{name}: rs274 refuses ({why}), read here"));
                } else {
                    refused_both += 1;
                }
            }
            None => {
                assert_eq!(head, name);
                let same = std::panic::catch_unwind(|| {
                    same_places_as_linuxcnc_of(&p, lines, name);
                });
                match same {
                    Ok(()) => read_both += 1,
                    Err(e) => differ.push(e.downcast_ref::<String>().cloned().unwrap_or_else(|| format!("{name}: differs"))),
                }
            }
        }
    }
    assert!(differ.is_empty(), "{} of {} programs differ from rs274:\n{}", differ.len(), programs.len(), differ.join("\n"));
    // Both kinds are there: programs run to their moves, and programs refused.
    assert!(read_both >= 80 && refused_both >= 40, "{read_both} read, {refused_both} refused");
}

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
