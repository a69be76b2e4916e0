//! The README and the book (`docs/src`, issue 66): the README stays a page (at most 200 lines), every
//! chapter is in the book's SUMMARY, and every relative link of the README and the book reaches a file
//! of the repository (a moved or renamed file breaks the test, not the reader's click).

use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The targets of `[text](target)` links in `text` that are neither web addresses nor anchors.
fn relative_links(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_code = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        let mut rest = line;
        while let Some(k) = rest.find("](") {
            let after = &rest[k + 2..];
            let Some(end) = after.find(')') else { break };
            let target = after[..end].split('#').next().unwrap_or("").trim();
            if !target.is_empty() && !target.contains("://") && !target.starts_with("mailto:") {
                out.push(target.to_string());
            }
            rest = &after[end..];
        }
    }
    out
}

fn pages() -> Vec<PathBuf> {
    let mut pages = vec![root().join("README.md")];
    let mut chapters: Vec<PathBuf> = std::fs::read_dir(root().join("docs/src")).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "md")).collect();
    chapters.sort();
    pages.extend(chapters);
    pages
}

#[test]
fn the_readme_is_a_page_and_the_book_holds_every_chapter() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(lines <= 200, "README.md has {lines} lines: the manual belongs in docs/src");
    // It opens with the two commands a fresh machine runs.
    let first_block: Vec<&str> = readme.split("```sh").nth(1).unwrap().split("```").next().unwrap().lines().filter(|l| !l.trim().is_empty()).collect();
    assert!(first_block[0].starts_with("launch-free-scripts/demo") && first_block[1].starts_with("launch-free-scripts/test"), "{first_block:?}");
    let summary = std::fs::read_to_string(root().join("docs/src/SUMMARY.md")).unwrap();
    let listed = relative_links(&summary);
    for page in pages().iter().skip(1) {
        let name = page.file_name().unwrap().to_string_lossy().into_owned();
        if name != "SUMMARY.md" {
            assert!(listed.contains(&name), "docs/src/{name} is not in SUMMARY.md");
        }
    }
}

#[test]
fn every_relative_link_of_the_readme_and_the_book_reaches_a_file() {
    let mut broken = Vec::new();
    let mut checked = 0;
    for page in pages() {
        let text = std::fs::read_to_string(&page).unwrap();
        for target in relative_links(&text) {
            checked += 1;
            if !page.parent().unwrap().join(&target).exists() {
                broken.push(format!("{}: {target}", page.strip_prefix(root()).unwrap().display()));
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
    assert!(checked >= 20, "{checked} links checked");
}

/// The README's tour runs: each `fiveaxis` command of its sh blocks (continuation lines joined, the
/// comments cut) is run with the tour's placeholders bound to real inputs (`part.h`: the hyperMILL
/// DMU 85 monoBLOCK program of the corpus; `part.ngc`: the paper's SING program, which LinuxCNC ran for
/// the trace; `cnc_bag/`: LinuxCNC's SING trace as a rosbag2 bag written by rosbags), and ends as the tour says: 0, or 1 where a gate
/// fails. The DDS monitor beside a live bridge is the node set's own tests' (tests/dds.rs).
#[test]
fn the_readmes_tour_runs() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let tour = readme.split("## A five-minute tour").nth(1).expect("the tour");
    let mut commands = Vec::new();
    for block in tour.split("```sh").skip(1) {
        let body = block.split("```").next().unwrap();
        let mut joined = String::new();
        for line in body.lines() {
            let code = line.split(" # ").next().unwrap().trim_end();
            joined.push_str(code.trim_end_matches('\\'));
            if !code.ends_with('\\') {
                if !joined.trim().is_empty() {
                    commands.push(joined.trim().to_string());
                }
                joined.clear();
            } else {
                joined.push(' ');
            }
        }
    }
    let scratch = std::env::temp_dir().join(format!("fiveaxis-tour-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).unwrap();
    let bag = scratch.join("cnc_bag");
    let st = std::process::Command::new("python3")
        .arg(root().join("tests/peer/trace_to_rosbag.py"))
        .arg(root().join("recordings/machine/linuxcnc/sing_trace.csv.gz"))
        .arg(&bag)
        .status()
        .unwrap();
    assert!(st.success());
    let part_h = root().join("../shared/outside/programs/heidenhain-klartext_hypermill_dmu85-monoblock-ac_large-3plus2_W5270NS01061A16.h");
    let mut ran = 0;
    for c in &commands {
        let words: Vec<String> = c
            .split_whitespace()
            .map(|w| match w {
                "part.h" => part_h.display().to_string(),
                "part.ngc" => "bundled:SING.I".to_string(),
                "cnc_bag/" => bag.display().to_string(),
                "report.json" | "sing.rrd" => scratch.join(w).display().to_string(),
                _ => w.to_string(),
            })
            .collect();
        if words[0] != "fiveaxis" {
            assert!(c.contains("monitor-machine"), "a tour command not run here: {c}");
            continue;
        }
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_fiveaxis")).args(&words[1..]).current_dir(&scratch).output().unwrap();
        let code = out.status.code();
        let gate = words.iter().any(|w| w == "--max-c-speed-rpm");
        assert!(code == Some(0) || (gate && code == Some(1)), "{c}: exit {code:?}\n{}\n{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        if c.contains("analyze bundled:SING.I") {
            assert!(String::from_utf8_lossy(&out.stdout).contains("175.0 rpm at x 24.984"), "the tour's 175 rpm at x 25 mm");
        }
        ran += 1;
    }
    assert!(ran >= 5, "{ran} of the tour's commands ran: {commands:#?}");
    let _ = std::fs::remove_dir_all(&scratch);
}

/// The book's reference pages (`docs/src/reference/`) are the commands' and nodes' own `--help`,
/// word for word: a changed flag fails this test until the page is made again (`FIVEAXIS_BLESS=1
/// cargo test --test docs` writes them), so the reference cannot rot.
#[test]
fn the_reference_pages_are_the_commands_own_help() {
    let bin = Path::new(env!("CARGO_BIN_EXE_fiveaxis")).parent().unwrap().to_path_buf();
    let pages: [(&str, &str, &[&str]); 17] = [
        ("fiveaxis", "fiveaxis", &[]),
        ("fiveaxis-program-analyze", "fiveaxis", &["program", "analyze"]),
        ("fiveaxis-machine-list", "fiveaxis", &["machine", "list"]),
        ("fiveaxis-machine-show", "fiveaxis", &["machine", "show"]),
        ("fiveaxis-machine-urdf", "fiveaxis", &["machine", "urdf"]),
        ("fiveaxis-run", "fiveaxis", &["run"]),
        ("fiveaxis-analyze", "fiveaxis", &["analyze"]),
        ("fiveaxis-mcap-recover", "fiveaxis", &["mcap", "recover"]),
        ("fiveaxis-avoid", "fiveaxis", &["avoid"]),
        ("fiveaxis-roughness", "fiveaxis", &["roughness"]),
        ("fiveaxis-demo", "fiveaxis", &["demo"]),
        ("fiveaxis-commander", "fiveaxis-commander", &[]),
        ("fiveaxis-simulator", "fiveaxis-simulator", &[]),
        ("fiveaxis-monitor", "fiveaxis-monitor", &[]),
        ("fiveaxis-recorder", "fiveaxis-recorder", &[]),
        ("fiveaxis-rerun", "fiveaxis-rerun", &[]),
        ("fiveaxis-bridge", "fiveaxis-bridge", &[]),
    ];
    let dir = root().join("docs/src/reference");
    let bless = std::env::var_os("FIVEAXIS_BLESS").is_some();
    let mut stale = Vec::new();
    let mut index = String::from("# Reference\n\nEach command's and node's own `--help`, as this version prints it (tests/docs.rs keeps them so).\n\n");
    for (page, exe, args) in pages {
        let path = bin.join(exe);
        assert!(path.exists(), "{} is built by launch-free-scripts/test (cargo build --workspace --bins)", path.display());
        let out = std::process::Command::new(&path).args(args).arg("--help").output().unwrap();
        assert!(out.status.success(), "{exe} {args:?} --help: {}", String::from_utf8_lossy(&out.stderr));
        let help = String::from_utf8(out.stdout).unwrap();
        let title = std::iter::once(exe).chain(args.iter().copied()).collect::<Vec<_>>().join(" ");
        let text = format!("# `{title}`\n\n```text\n{}\n```\n", help.trim_end());
        let file = dir.join(format!("{page}.md"));
        index.push_str(&format!("- [`{title}`]({page}.md)\n"));
        if bless {
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(&file, &text).unwrap();
        } else if std::fs::read_to_string(&file).ok().as_deref() != Some(text.as_str()) {
            stale.push(file.display().to_string());
        }
    }
    let index_file = dir.join("README.md");
    if bless {
        std::fs::write(&index_file, &index).unwrap();
    } else if std::fs::read_to_string(&index_file).ok().as_deref() != Some(index.as_str()) {
        stale.push(index_file.display().to_string());
    }
    assert!(stale.is_empty(), "reference pages that are not the commands' --help (make them again with FIVEAXIS_BLESS=1 cargo test --test docs):\n{}", stale.join("\n"));
    // The book lists them.
    let summary = std::fs::read_to_string(root().join("docs/src/SUMMARY.md")).unwrap();
    assert!(summary.contains("(reference/README.md)"), "SUMMARY.md has no Reference");
}
