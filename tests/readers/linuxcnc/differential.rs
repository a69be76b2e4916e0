//! This reader against LinuxCNC's own interpreter on generated programs.
//! `recordings/programs/linuxcnc/diff/generate.py` writes programs and runs Debian's `rs274` on them
//! (its canonical output, or its refusal): by hand into a directory for
//! [`differential_against_rs274`], which says where the two differ (a refusal on one side only, or
//! moves, centres or feeds apart, as the fixture tests compare), and once into the committed fixture
//! that [`generated_programs_read_as_rs274_runs_them`] holds in every run.

use super::*;

/// How the reader reads programs rs274 ran: on LinuxCNC's sample machine (its machine zero and
/// G28/G30 points are rs274's, 0), with rs274's tool table, which rs274 alone reads in inches (its
/// machine units without an INI).
fn rs274_options(table: Option<&str>) -> ReadOptions {
    let machine = fiveaxis::machine::Machine::builtin("linuxcnc-xyzac-trt").unwrap();
    let mut options = ReadOptions::default().on(&machine);
    options.tool_table = table.map(|t| std::sync::Arc::new(fiveaxis::program::ToolTable::parse(t).unwrap().in_unit(fiveaxis::program::LengthUnit::Inch)));
    options
}

/// Where `p` (program `name`) differs from what rs274 made of it, `Ok` its canonical lines or `Err`
/// its refusal: a refusal on one side only, or moves, centres or feeds apart
/// ([`same_places_as_linuxcnc_of`]); `None` where the two agree.
fn against_rs274(p: &Program, rs274: Result<&str, &str>, name: &str) -> Option<String> {
    let ours = errors(p);
    match (ours.is_empty(), rs274) {
        (true, Err(why)) => Some(format!("{name}: rs274 refuses ({}), read here", why.trim())),
        (false, Ok(_)) => Some(format!("{name}: refused here, rs274 reads it: {}", ours.iter().map(|(l, c, m)| format!("{l}:{c}: {m}")).collect::<Vec<_>>().join(" | "))),
        (false, Err(_)) => None,
        (true, Ok(canon)) => std::panic::catch_unwind(|| {
            same_places_as_linuxcnc_of(p, canon, name);
        })
        .err()
        .map(|e| e.downcast_ref::<String>().cloned().unwrap_or_else(|| format!("{name}: differs")).chars().take(600).collect()),
    }
}

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
    let options = rs274_options(Some("T1 P1 Z0 D10 ;\nT2 P2 Z5 D6 ;\n"));
    let (mut read_both, mut refused_both, mut differ) = (0, 0, Vec::new());
    for ((name, text), (head, lines)) in programs.iter().zip(&canon) {
        let rs274 = match head.split_once(" refused: ") {
            Some((n, why)) => {
                assert_eq!(n, name);
                Err(why)
            }
            None => {
                assert_eq!(head, name);
                Ok(lines.as_str())
            }
        };
        match against_rs274(&read(text, Dialect::Rs274, "t.ngc", &options), rs274, name) {
            Some(d) => differ.push(d),
            None if rs274.is_ok() => read_both += 1,
            None => refused_both += 1,
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
    let options = rs274_options(std::fs::read_to_string(dir.join("tools.tbl")).ok().as_deref());
    let mut names: Vec<_> = std::fs::read_dir(dir).unwrap().filter_map(|e| e.ok()).map(|e| e.path()).filter(|p| p.extension().is_some_and(|x| x == "ngc")).collect();
    names.sort();
    let (mut same, mut differ) = (0, 0);
    std::panic::set_hook(Box::new(|_| {}));
    for ngc in &names {
        let text = std::fs::read_to_string(ngc).unwrap();
        let refused = std::fs::read_to_string(ngc.with_extension("err")).ok().filter(|e| !e.trim().is_empty());
        let canon = if refused.is_none() { std::fs::read_to_string(ngc.with_extension("canon")).unwrap() } else { String::new() };
        let rs274 = refused.as_deref().map_or(Ok(canon.as_str()), Err);
        let name = ngc.file_name().unwrap().to_string_lossy();
        match against_rs274(&read(&text, Dialect::Rs274, "t.ngc", &options), rs274, &name) {
            None => same += 1,
            Some(v) => {
                differ += 1;
                println!("{v}");
            }
        }
    }
    let _ = std::panic::take_hook();
    println!("{same} the same, {differ} differ");
}
