//! The README and the book (`docs/src`, issue 66): the README stays a page (at most 200 lines), every
//! chapter is in the book's SUMMARY, and every relative link of the README and the book reaches a file
//! of the repository (a moved or renamed file breaks the test, not the reader's click).

use crate::common;

use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("FIVEAXIS_ROOT"))
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
    let md = |d: &str| -> Vec<PathBuf> { std::fs::read_dir(root().join(d)).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "md")).collect() };
    let mut chapters = md("docs/src");
    chapters.extend(md("docs/src/design"));
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
        let name = page.strip_prefix(root().join("docs/src")).unwrap().to_string_lossy().into_owned();
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
    let commands = tour_commands();
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
            assert!(c.contains("monitor-machine"), "a tour command not run here: {c}"); // the_readmes_live_commands_run_against_peers_on_this_host
            continue;
        }
        let out = std::process::Command::new(env!("FIVEAXIS_EXE")).args(&words[1..]).current_dir(&scratch).output().unwrap();
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
/// cargo test -p fiveaxis-tests --test integration docs::` writes them), so the reference cannot rot.
#[test]
fn the_reference_pages_are_the_commands_own_help() {
    let bin = Path::new(env!("FIVEAXIS_EXE")).parent().unwrap().to_path_buf();
    let pages: [(&str, &str, &[&str]); 21] = [
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
        ("fiveaxis-fleet", "fiveaxis-fleet", &[]),
        ("fiveaxis-fleet-gateway", "fiveaxis-fleet", &["gateway"]),
        ("fiveaxis-fleet-router", "fiveaxis-fleet", &["router"]),
        ("fiveaxis-fleet-view", "fiveaxis-fleet", &["view"]),
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
    let index_file = dir.join("index.md");
    if bless {
        std::fs::write(&index_file, &index).unwrap();
    } else if std::fs::read_to_string(&index_file).ok().as_deref() != Some(index.as_str()) {
        stale.push(index_file.display().to_string());
    }
    assert!(stale.is_empty(), "reference pages that are not the commands' --help (make them again with cargo build --workspace --bins && FIVEAXIS_BLESS=1 cargo test -p fiveaxis-tests --test integration docs::):\n{}", stale.join("\n"));
    // The book lists them.
    let summary = std::fs::read_to_string(root().join("docs/src/SUMMARY.md")).unwrap();
    assert!(summary.contains("(reference/index.md)"), "SUMMARY.md has no Reference");
}

/// A command or script a book page shows, in page order.
#[derive(Debug)]
enum Step {
    /// A `console` block's `$ command` (continuation lines joined), the output the page shows after it
    /// and the exit status it says (`# exit N` at its end; 0 otherwise).
    Console { line: usize, command: String, shown: Vec<String>, exit: i32 },
    /// An `sh` block, run as one script; `no_run` for `sh,no-run` blocks (see [`cannot_run_here`]).
    Script { line: usize, body: String, no_run: bool },
}

/// The `console` and `sh` blocks of a page (fences may be indented, as in list items).
fn steps(page: &str) -> Vec<Step> {
    let mut steps = Vec::new();
    let mut lines = page.lines().enumerate();
    while let Some((n, l)) = lines.next() {
        let fence = l.trim_start();
        let Some(info) = fence.strip_prefix("```") else { continue };
        let indent = l.len() - fence.len();
        let mut body = Vec::new();
        for (_, l) in lines.by_ref() {
            if l.trim_start().starts_with("```") {
                break;
            }
            body.push(l.get(indent..).unwrap_or(l.trim_start()).to_string());
        }
        let info: Vec<&str> = info.split(',').map(str::trim).collect();
        match info[0] {
            "sh" => steps.push(Step::Script { line: n + 1, body: body.join("\n"), no_run: info.contains(&"no-run") }),
            "console" => {
                let mut k = 0;
                while k < body.len() {
                    let Some(first) = body[k].strip_prefix("$ ") else { panic!("line {}: a console block's output before its command: {:?}", n + 2 + k, body[k]) };
                    let line = n + 2 + k;
                    let mut command = first.to_string();
                    while command.ends_with('\\') {
                        command.pop();
                        k += 1;
                        command.push(' ');
                        command.push_str(body[k].trim());
                    }
                    k += 1;
                    let mut shown = Vec::new();
                    while k < body.len() && !body[k].starts_with("$ ") {
                        shown.push(body[k].clone());
                        k += 1;
                    }
                    let exit = command.split_once("# exit ").map_or(0, |(_, e)| e.trim().parse().unwrap_or_else(|_| panic!("line {line}: `# exit N`")));
                    steps.push(Step::Console { line, command, shown, exit });
                }
            }
            _ => {}
        }
    }
    steps
}

/// Whether `actual` output shows what the page `shown`: line by line with runs of blanks as one, where
/// a line `...` stands for any number of lines and a line ending in `...` for any line beginning so.
fn shows(shown: &[String], actual: &[&str]) -> bool {
    let norm = |s: &str| s.split_whitespace().collect::<Vec<_>>().join(" ");
    let line_ok = |e: &str, a: &str| match norm(e).strip_suffix("...") {
        Some(prefix) => norm(a).starts_with(prefix.trim_end()),
        None => norm(e) == norm(a),
    };
    // ok[i][j]: shown[i..] matches actual[j..].
    let (m, n) = (shown.len(), actual.len());
    let mut ok = vec![vec![false; n + 1]; m + 1];
    ok[m][n] = true;
    for i in (0..m).rev() {
        for j in (0..=n).rev() {
            ok[i][j] = if shown[i].trim() == "..." { ok[i + 1][j] || (j < n && ok[i][j + 1]) } else { j < n && line_ok(&shown[i], actual[j]) && ok[i + 1][j + 1] };
        }
    }
    ok[0][0]
}

/// The page's commands run in order, from a scratch folder that sees the repository's `recordings`,
/// `machines`, `tests` and `launch-free-scripts` as a clone's root does, with the test build's
/// executables on the path (`fiveaxis`, and the nodes the scripts start: FIVEAXIS_BIN), inside a
/// private loopback-only network namespace. Returns the scratch folder, for checks of what they wrote.
fn run_page(name: &str) -> PathBuf {
    let page = std::fs::read_to_string(root().join("docs/src").join(name)).unwrap();
    let scratch = sandbox(&format!("book-{}", name.trim_end_matches(".md")), &["recordings", "machines", "tests", "launch-free-scripts"]);
    let run = |script: &str| sandboxed(&scratch, script, &[]);
    let steps = steps(&page);
    assert!(!steps.is_empty(), "{name}: no commands");
    for step in &steps {
        match step {
            Step::Script { body, no_run: true, line } => {
                for c in commands(body) {
                    assert!(cannot_run_here(&c), "{name}:{line}: `{c}` is in a no-run block but can run here");
                }
            }
            Step::Script { body, line, .. } => {
                let out = run(&format!("{body}\nwait"));
                assert!(out.status.success(), "{name}:{line}: exit {:?}\n{}\n{}", out.status.code(), String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
            }
            Step::Console { line, command, shown, exit } => {
                let out = run(command);
                let stdout = String::from_utf8_lossy(&out.stdout);
                let actual: Vec<&str> = stdout.lines().collect();
                assert_eq!(out.status.code(), Some(*exit), "{name}:{line}: {command}\n{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
                assert!(shows(shown, &actual), "{name}:{line}: {command}\nthe page shows:\n{}\nit printed:\n{stdout}", shown.join("\n"));
            }
        }
    }
    scratch
}

/// A fresh scratch folder for a documented command, seeing the repository's folders `links` as a
/// clone's root does.
fn sandbox(tag: &str, links: &[&str]) -> PathBuf {
    let scratch = common::scratch_dir(tag);
    for d in links {
        std::os::unix::fs::symlink(root().join(d), scratch.join(d)).unwrap();
    }
    scratch
}

/// `script` run by bash (`set -euo pipefail`) in `scratch`, inside a private loopback-only network
/// namespace, with the test build's executables on the path and as the scripts' FIVEAXIS_BIN, and
/// `env` beside them.
fn sandboxed(scratch: &Path, script: &str, env: &[(&str, &Path)]) -> std::process::Output {
    let bin = Path::new(env!("FIVEAXIS_EXE")).parent().unwrap();
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    std::process::Command::new(root().join("launch-free-scripts/netns-run"))
        .args(["bash", "-c", &format!("set -euo pipefail\n{script}")])
        .current_dir(scratch)
        .env("PATH", path)
        .env("FIVEAXIS_BIN", bin)
        .envs(env.iter().copied())
        .output()
        .unwrap()
}

/// The commands of the README's five-minute tour (its `sh` blocks).
fn tour_commands() -> Vec<String> {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let tour = readme.split("## A five-minute tour").nth(1).expect("the tour");
    tour.split("```sh").skip(1).flat_map(|block| commands(block.split("```").next().unwrap())).collect()
}

/// A script's commands: continuation lines joined, comments and blank lines left out.
fn commands(body: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut joined = String::new();
    for line in body.lines() {
        let code = line.split(" #").next().unwrap().trim();
        if code.starts_with('#') || (code.is_empty() && joined.is_empty()) {
            continue;
        }
        joined.push_str(code.trim_end_matches('\\'));
        if code.ends_with('\\') {
            joined.push(' ');
        } else {
            out.push(std::mem::take(&mut joined));
        }
    }
    out
}

/// What a `sh,no-run` block may hold: what cannot run in the tests, and why.
fn cannot_run_here(c: &str) -> bool {
    // Release builds and benchmarks (the tests are a debug build; the benchmarks run for minutes).
    let builds = c.starts_with("cargo build --release") || c.starts_with("cargo bench") || c.starts_with("benches/") || c == "launch-free-scripts/demo" || c.starts_with("export PATH=");
    // A viewer's window, ROS 2's own CLI (no ROS installation here), the repository's recordings rewritten.
    let elsewhere = c.starts_with("pip install rerun-sdk") || c.starts_with("fiveaxis-rerun live --connect") || c.starts_with("ros2 ") || c.starts_with("recordings/regenerate");
    // A real machine: its agent, adapter, OPC UA server or ROS 2 bridge, by the page's example address.
    let machine = ["http://agent:", "cnc:7878", "opc.tcp://cnc:", "opc.tcp://sinumerik:", "--joint-states /cnc/"].iter().any(|a| c.contains(a)) || c.starts_with("export FIVEAXIS_OPCUA_PASSWORD");
    builds || elsewhere || machine
}

#[test]
fn shown_output_matches_with_elisions() {
    let s = |v: &[&str]| v.iter().map(|l| l.to_string()).collect::<Vec<_>>();
    assert!(shows(&s(&["a", "...", "d"]), &["a", "b", "c", "d"]));
    assert!(shows(&s(&["a  b", "..."]), &["a b", "x"]));
    assert!(shows(&s(&["gen   A/C ...", "..."]), &["gen A/C table"]));
    assert!(!shows(&s(&["a", "d"]), &["a", "b", "d"]));
    assert!(!shows(&s(&["a"]), &["a", "b"]));
    assert!(!shows(&s(&["a", "...", "e"]), &["a", "b", "d"]));
}

/// Getting started: its commands print what the page shows (the paper's 175 rpm region at x 22-28 mm,
/// and none on the reoriented program).
#[test]
fn the_getting_started_page_runs() {
    let scratch = run_page("getting-started.md");
    let _ = std::fs::remove_dir_all(&scratch);
}

/// Your machine in 15 minutes: the machine from a URDF, the Klartext twin of the paper's program on it,
/// a live monitor beside an MTConnect adapter replaying LinuxCNC's trace at 3 Hz per axis, and the CI
/// gate on the adapter's log. Beyond the shown output: the live monitor found the one region at x
/// 22-28 mm (+-1) with nothing lost, and the JUnit report names the violation.
#[test]
fn the_your_machine_page_runs() {
    let scratch = run_page("your-machine.md");
    let live: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(scratch.join("live.json")).expect("the live run's summary")).unwrap();
    let input = live.as_array().unwrap().iter().find(|i| i["topic"] == "/fiveaxis/machine/joint_states").unwrap_or_else(|| panic!("{live:#}"));
    assert_eq!(input["lost"], 0, "{input:#}");
    let regions = input["regions"].as_array().unwrap();
    assert_eq!(regions.len(), 1, "{input:#}");
    let (x0, x1) = (regions[0]["x_start_mm"].as_f64().unwrap(), regions[0]["x_end_mm"].as_f64().unwrap());
    assert!((x0 - 22.0).abs() <= 1.0 && (x1 - 28.0).abs() <= 1.0, "live region x {x0}-{x1}");
    assert_eq!(regions[0]["cause"], "singularity");
    let junit = std::fs::read_to_string(scratch.join("report.xml")).unwrap();
    assert!(junit.contains("<failure") && junit.contains("170.6 rpm"), "{junit}");
    let _ = std::fs::remove_dir_all(&scratch);
}

/// mdBook, once `launch-free-scripts/test` has installed it into `target/tools` beside the build and the
/// tests: its install is under way while `mdbook-install.pending` is there, and says how it ended in
/// `mdbook-install.status` (waited for up to 15 minutes, a second at a time).
fn installed_mdbook() -> std::path::PathBuf {
    let tools = root().join("target/tools");
    let (pending, status) = (tools.join("mdbook-install.pending"), tools.join("mdbook-install.status"));
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(900);
    while pending.exists() && !status.exists() {
        assert!(std::time::Instant::now() < deadline, "mdBook's install ({}) has not ended in 15 minutes", pending.display());
        std::thread::sleep(std::time::Duration::from_secs(1));
    }
    if let Ok(s) = std::fs::read_to_string(&status) {
        let log = std::fs::read_to_string(root().join("target/mdbook-install.log")).unwrap_or_default();
        assert_eq!(s.trim(), "0", "installing mdBook failed: {log}");
    }
    let mdbook = tools.join("bin/mdbook");
    assert!(mdbook.exists(), "{} is installed by launch-free-scripts/test (cargo install mdbook)", mdbook.display());
    mdbook
}

/// The book builds with mdBook (`launch-free-scripts/test` installs it into `target/tools`), a chapter
/// missing from disk fails the build (`create-missing = false`), and every relative link and image of
/// the built HTML reaches a file of the output: the link check on what a reader clicks, after mdBook
/// turned `.md` links into `.html` (a link out of the book, such as to the repository's README, breaks).
#[test]
fn the_book_builds_and_its_links_resolve() {
    let mdbook = installed_mdbook();
    let out_dir = std::env::temp_dir().join(format!("fiveaxis-book-html-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out_dir);
    let out = std::process::Command::new(&mdbook).arg("build").arg(root().join("docs")).arg("-d").arg(&out_dir).output().unwrap();
    let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "mdbook build docs: {said}");
    assert!(!said.contains("[WARN]") && !said.contains("[ERROR]"), "mdbook build docs: {said}");
    let mut html = Vec::new();
    let mut dirs = vec![out_dir.clone()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|e| e == "html") {
                html.push(p);
            }
        }
    }
    let (mut broken, mut checked) = (Vec::new(), 0);
    for page in &html {
        let text = std::fs::read_to_string(page).unwrap();
        for attr in ["href=\"", "src=\""] {
            for piece in text.split(attr).skip(1) {
                let target = piece.split('"').next().unwrap();
                let path = target.split(['#', '?']).next().unwrap();
                // (The 404 page's `/` is the site's root, wherever the book is served.)
                if path.is_empty() || path.starts_with('/') || target.contains("://") || target.starts_with("mailto:") || target.starts_with("javascript:") {
                    continue;
                }
                checked += 1;
                let file = page.parent().unwrap().join(path);
                if !(file.is_file() || file.join("index.html").is_file()) {
                    broken.push(format!("{}: {target}", page.strip_prefix(&out_dir).unwrap().display()));
                }
            }
        }
    }
    broken.sort();
    broken.dedup();
    assert!(broken.is_empty(), "broken links in the built book:\n{}", broken.join("\n"));
    assert!(html.len() >= 20 && checked >= 200, "{} pages, {checked} links", html.len());
    let _ = std::fs::remove_dir_all(&out_dir);
}

/// The book's other pages with commands, each run as [`run_page`] runs them (what they print beyond
/// an exit status and the output they show is each feature's own tests').
#[test]
fn the_in_process_page_runs() {
    let _ = std::fs::remove_dir_all(run_page("in-process.md"));
}

#[test]
fn the_node_set_page_runs() {
    let _ = std::fs::remove_dir_all(run_page("node-set.md"));
}

#[test]
fn the_programs_page_runs() {
    let _ = std::fs::remove_dir_all(run_page("programs.md"));
}

#[test]
fn the_recording_page_runs() {
    let scratch = run_page("recording.md");
    // The recording cut short was mended into one that reads.
    assert!(scratch.join("fixed.mcap").is_file());
    let _ = std::fs::remove_dir_all(scratch);
}

#[test]
fn the_remedies_page_runs() {
    let _ = std::fs::remove_dir_all(run_page("remedies.md"));
}

#[test]
fn the_rerun_page_runs() {
    let scratch = run_page("rerun.md");
    for f in ["sing.rrd", "replay.rrd", "live.rrd"] {
        assert!(std::fs::metadata(scratch.join(f)).map(|m| m.len() > 10_000).unwrap_or(false), "{f}");
    }
    let _ = std::fs::remove_dir_all(scratch);
}

/// Every page of the book that shows commands is run by a test above (the benchmarks' page holds only
/// `cargo bench`, which no test runs).
#[test]
fn every_page_with_commands_is_run() {
    let tests = std::fs::read_to_string(root().join("tests/docs.rs")).unwrap();
    for page in pages().iter().skip(1) {
        let text = std::fs::read_to_string(page).unwrap();
        let runnable = steps(&text).iter().any(|s| !matches!(s, Step::Script { no_run: true, .. }));
        let name = page.file_name().unwrap().to_string_lossy().into_owned();
        if runnable {
            assert!(tests.contains(&format!("run_page(\"{name}\")")), "{name} shows commands that no test runs");
        }
    }
}

/// The README's live commands (`monitor-machine` beside a machine's ROS 2 bridge, MTConnect agent,
/// OPC UA server and a Sinumerik's server) run as shown, each against an independent peer standing in
/// for the machine on this host: Cyclone DDS publishing LinuxCNC's SING trace as JointState on domain 7,
/// an MTConnect agent serving it per axis at about 3 Hz, asyncua's OPC 40502 server and asyncua as a
/// Sinumerik (its own NC variables, a user, Basic256Sha256) at 100 ms. The machines' names become
/// 127.0.0.1, the password a test one, `part.ngc` the paper's program LinuxCNC ran, and the monitor is
/// told to stop once the stream has ended (`--exit-when-idle-s 3 --summary-json`); each finds the one
/// region at x 22-28 mm (+-1) and loses nothing.
#[test]
fn the_readmes_live_commands_run_against_peers_on_this_host() {
    let live: Vec<String> = tour_commands().into_iter().filter(|c| c.contains("monitor-machine")).collect();
    assert_eq!(live.len(), 4, "{live:#?}");
    let scratch = sandbox("readme-live", &["launch-free-scripts"]);
    let trace = root().join("recordings/machine/linuxcnc/sing_trace.csv.gz");
    let peer = |p: &str| root().join("tests/peer").join(p).display().to_string();
    let nodeset = root().join("target/npm/node_modules/node-opcua-nodesets/nodesets/Opc.Ua.CNC.NodeSet.xml");
    assert!(nodeset.exists(), "{} is installed by launch-free-scripts/test (npm)", nodeset.display());
    let st = std::process::Command::new("python3").args([&peer("shopfloor_rates.py"), trace.to_str().unwrap(), "agent.shdr", "per-axis", "--period", "0.33", "--shdr"]).current_dir(&scratch).status().unwrap();
    assert!(st.success());
    for (k, command) in live.iter().enumerate() {
        let (machine, topic) = if command.contains("--joint-states") {
            // On the domain the command names (`ROS_DOMAIN_ID=7 ...`).
            let domain = command.strip_prefix("ROS_DOMAIN_ID=").and_then(|r| r.split_whitespace().next()).unwrap_or("0");
            (format!("python3 '{}' publish '{}' --domain-id {domain} --start 8.0 --end 17.5 --wait-subscribers 1 --wait-s 30 > peer.json", peer("cyclone_bridge.py"), trace.display()), "/cnc/joint_states")
        } else if command.contains("--mtconnect-agent") {
            (format!("python3 '{}' agent agent.shdr agent.shdr.devices.xml --port 5000 --start 8.5 --end 17.5 --linger 2 > peer.json", peer("mtconnect_peer.py")), "/fiveaxis/machine/joint_states")
        } else if command.contains("sinumerik") {
            (format!("python3 '{}' '{}' --sinumerik --user OpcUaClient:s3cret --secure server-pki --port 4840 --start 8.0 --end 17.5 --linger 2 --wait-subscription 60 > peer.json", peer("opcua_cnc_server.py"), trace.display()), "/fiveaxis/machine/joint_states")
        } else {
            (format!("python3 '{}' '{}' --nodeset '{}' --port 4840 --start 8.0 --end 17.5 --linger 2 --wait-subscription 60 > peer.json", peer("opcua_cnc_server.py"), trace.display(), nodeset.display()), "/fiveaxis/machine/joint_states")
        };
        let shown = command
            .replace("http://agent:5000", "http://127.0.0.1:5000")
            .replace("opc.tcp://cnc:4840", "opc.tcp://127.0.0.1:4840/fiveaxis")
            .replace("opc.tcp://sinumerik:4840", "opc.tcp://127.0.0.1:4840/fiveaxis")
            .replace("FIVEAXIS_OPCUA_PASSWORD=...", "FIVEAXIS_OPCUA_PASSWORD=s3cret")
            .replace("part.ngc", "bundled:SING.I");
        let summary = format!("summary{k}.json");
        let script = format!("{machine} &\nP=$!\n{shown} --exit-when-idle-s 3 --summary-json {summary}\nwait $P");
        let out = sandboxed(&scratch, &script, &[("FIVEAXIS_OPCUA_PKI", &scratch.join(format!("pki{k}")))]);
        let said = format!("{command}\n{}\n{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(out.status.success(), "{said}");
        let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(scratch.join(&summary)).unwrap_or_else(|e| panic!("{e}: {said}"))).unwrap();
        let input = v.as_array().unwrap().iter().find(|i| i["topic"] == topic).unwrap_or_else(|| panic!("{v:#}\n{said}"));
        assert_eq!(input["lost"], 0, "{input:#}\n{said}");
        let regions = input["regions"].as_array().unwrap();
        assert_eq!(regions.len(), 1, "{input:#}\n{said}");
        let (x0, x1) = (regions[0]["x_start_mm"].as_f64().unwrap(), regions[0]["x_end_mm"].as_f64().unwrap());
        assert!((x0 - 22.0).abs() <= 1.0 && (x1 - 28.0).abs() <= 1.0 && regions[0]["cause"] == "singularity", "region x {x0}-{x1}: {said}");
    }
    let _ = std::fs::remove_dir_all(&scratch);
}
