//! The fuzz targets' bodies, one function per reader, shared by the libFuzzer binaries
//! (`fuzz_targets/`) and by the regression test that replays what the fuzzers once found
//! (`tests/fuzz_regressions.rs`, which includes this file). Each takes any bytes and must return
//! without a panic, a hang or an allocation over 512 MB.
//!
//! The readers under test take paths, so inputs are written to scratch files in this process's
//! own directory (on /dev/shm when there is one) first.
#![allow(dead_code)]

use fiveaxis::analysis::{analyze_mcap, OfflineOptions};
use fiveaxis::machine::urdf;
use fiveaxis::machine::Machine;
use fiveaxis::program::{read, Dialect, ReadOptions};
use fiveaxis::record::from_cdr;
use fiveaxis::record::read::summary_channels;
use fiveaxis::record::read::{for_each_message, recording_files, recording_len};
use fiveaxis::record::recover;
use fiveaxis::roughness::read_x3p;
use fiveaxis::roughness::{read_csv, CsvUnits};
use fiveaxis_msgs::{AxisState, Clock, DiagnosticArray, JointState, SingularityStatus};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// This process's scratch directory (created once).
pub fn scratch_dir() -> &'static Path {
    static DIR: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        let base = if Path::new("/dev/shm").is_dir() { PathBuf::from("/dev/shm") } else { std::env::temp_dir() };
        let dir = base.join(format!("fiveaxis-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch directory");
        dir
    })
}

/// Write `data` to the scratch file `name` and return its path.
pub fn scratch_file(name: &str, data: &[u8]) -> PathBuf {
    let path = scratch_dir().join(name);
    std::fs::write(&path, data).expect("scratch file");
    path
}

/// A tiny valid MCAP recording (two AxisStates of the SING program), for targets that need one
/// beside what they fuzz.
pub fn small_recording() -> &'static [u8] {
    include_bytes!("../seeds/small.mcap")
}

/// What every command does first with a machine it has read: its forward kinematics at home and
/// at a tilted pose, the inverse back, and the rotary solutions near a tool axis off the singular one.
pub fn exercise(machine: &fiveaxis::machine::Machine) {
    let home = [0.0; 5];
    let tilted = [10.0, -20.0, 30.0, 0.4, 1.2];
    for q in [home, tilted] {
        let pose = machine.forward(&q);
        let _ = machine.inverse(&pose, &q);
        let _ = machine.inverse_all(&pose);
        let _ = machine.rotaries_near(&pose.axis, &[q[3], q[4]]);
    }
    let _ = machine.singular_direction();
    let _ = machine.limits();
}

/// CDR messages as they arrive from DDS or a recording: the first byte picks the decoder (the
/// buffer-reusing readers of AxisState and JointState, and the serde path the DDS subscriptions
/// take for every subscribed type).
pub fn cdr_message(data: &[u8]) {
    let Some((&pick, body)) = data.split_first() else { return };
    match pick % 7 {
        0 => {
            let _ = AxisState::default().read_cdr(body);
        }
        1 => {
            let _ = JointState::default().read_cdr(body);
        }
        2 => {
            let _ = from_cdr::<AxisState>(body);
        }
        3 => {
            let _ = from_cdr::<JointState>(body);
        }
        4 => {
            let _ = from_cdr::<SingularityStatus>(body);
        }
        5 => {
            let _ = from_cdr::<DiagnosticArray>(body);
        }
        _ => {
            let _ = from_cdr::<Clock>(body);
        }
    }
}

const UNITS: [Option<f64>; 4] = [None, Some(1.0), Some(1e-3), Some(1e-6)];

/// CSV roughness profiles (header-named units, or the first byte picks the command-line units),
/// then filtered and windowed as `fiveaxis analyze --roughness` does.
pub fn csv_profile(data: &[u8]) {
    let Some((&pick, body)) = data.split_first() else { return };
    let units = CsvUnits { x: UNITS[(pick & 3) as usize], z: UNITS[((pick >> 2) & 3) as usize] };
    let path = scratch_file("in.csv", body);
    if let Ok(profile) = read_csv(&path, units) {
        let _ = profile.windows(0.8e-3, 0.5e-3);
    }
}

/// Machine descriptions in TOML, then the machine's forward and inverse kinematics at its home
/// and at a tilted tool axis (what every command does first with a machine).
pub fn machine_toml(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(machine) = Machine::from_toml_str(text, "fuzz") {
        exercise(&machine);
    }
}

/// Machine descriptions in URDF, then the same kinematics as `machine_toml`.
pub fn machine_urdf(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(machine) = urdf::read(text, "fuzz") {
        exercise(&machine);
    }
}

/// Recordings: a file as `fiveaxis analyze` reads it (MCAP records, chunk compression, CDR
/// messages, the monitor on what decodes) and as `fiveaxis mcap recover` mends it.
pub fn mcap_recording(data: &[u8]) {
    let path = scratch_file("in.mcap", data);
    let _ = summary_channels(&path);
    let _ = analyze_mcap(&path, &Machine::hermle_c600u(), &OfflineOptions::default());
    let _ = recover(&path, &scratch_dir().join("out.mcap"));
}

const DIALECTS: [Dialect; 7] = [Dialect::Heidenhain, Dialect::Rs274, Dialect::Cl, Dialect::Sinumerik, Dialect::Klartext, Dialect::Fanuc, Dialect::Haas];

/// NC and CL program readers: the first byte picks the dialect (Heidenhain DIN/ISO, RS274NGC, CL,
/// Sinumerik, Klartext, Fanuc, Haas), the rest is the program text (not UTF-8: replaced, as
/// `program::load` does). Loops and calls run at most 20,000 lines beyond the program's own (the
/// readers' bound, `max_run_lines`, set low so that an endless loop ends well within the 10 s an
/// input may take).
pub fn nc_program(data: &[u8]) {
    let Some((&pick, body)) = data.split_first() else { return };
    let text = String::from_utf8_lossy(body);
    let _ = Dialect::detect(None, &text);
    // Every other program a call asks for (an 840D subprogram, a LinuxCNC subroutine's file) is
    // this one again: calls run, nest and recurse on the same mutated text.
    let again = Arc::new(SelfAgain(body.to_vec())) as Arc<dyn fiveaxis::program::SubroutineFiles>;
    // A tool table, so that radius compensation (RL/RR, G41/G42) runs rather than stops at the radius.
    static TOOLS: std::sync::OnceLock<Arc<fiveaxis::program::ToolTable>> = std::sync::OnceLock::new();
    let tools = TOOLS.get_or_init(|| {
        let text = "BEGIN TOOL.T MM\nT    NAME       R      DR\n1    MILL_D2    +1     +0\n3    MILL_D6    +3     +0\n4    MILL_D8    +4     -0.01\n5    BIG        +25    +0\n[END]\n";
        Arc::new(fiveaxis::program::ToolTable::parse(text).expect("the fuzz tool table"))
    });
    let options = ReadOptions { max_run_lines: 20_000, subroutine_files: Some(again), tool_table: Some(tools.clone()), ..ReadOptions::default() };
    // Every other round of dialects reads on the Hermle, whose kinematics the tilted planes
    // (PLANE, CYCLE800, G68.2), machine moves and TCPM need.
    static HERMLE: std::sync::OnceLock<Machine> = std::sync::OnceLock::new();
    let options = if (pick as usize / DIALECTS.len()) % 2 == 1 { options.on(HERMLE.get_or_init(Machine::hermle_c600u)) } else { options };
    let program = read(&text, DIALECTS[pick as usize % DIALECTS.len()], "fuzz", &options);
    let _ = program.report();
}

/// A file search that finds the program under test under any name asked for.
#[derive(Debug)]
struct SelfAgain(Vec<u8>);

impl fiveaxis::program::SubroutineFiles for SelfAgain {
    fn find_file(&self, names: &[String], _any_case: bool, _own_dir: bool) -> Result<Option<(String, Vec<u8>)>, String> {
        Ok(names.first().map(|n| (n.clone(), self.0.clone())))
    }
}

/// rosbag2 directories: the input is the bag's `metadata.yaml`, beside one small valid MCAP file
/// (`bag_0.mcap`); the bag is listed, sized and read as `fiveaxis analyze DIR` does.
pub fn rosbag2_metadata(data: &[u8]) {
    let bag = scratch_dir().join("bag");
    if !bag.is_dir() {
        std::fs::create_dir_all(&bag).expect("bag directory");
        std::fs::write(bag.join("bag_0.mcap"), small_recording()).expect("bag file");
    }
    std::fs::write(bag.join("metadata.yaml"), data).expect("metadata.yaml");
    let _ = recording_files(&bag);
    let _ = recording_len(&bag);
    let _ = for_each_message(&bag, |_| {});
}

/// X3P files as they come (a zip container): read as a roughness profile, then filtered and
/// windowed as `fiveaxis analyze --roughness` does (lambda_c 0.8 mm, a window every 0.5 mm).
pub fn x3p_container(data: &[u8]) {
    let path = scratch_file("in.x3p", data);
    if let Ok(profile) = read_x3p(&path) {
        let _ = profile.windows(0.8e-3, 0.5e-3);
    }
}

/// X3P `main.xml` and its point data: the input, split at the first `\0\0`, is `main.xml` and
/// `bindata/data.bin`, stored in a valid zip, so that mutations reach the XML and size checks
/// rather than the container's CRCs. Then filtered and windowed as in `x3p_container`.
pub fn x3p_main_xml(data: &[u8]) {
    let split = data.windows(2).position(|w| w == [0, 0]);
    let (xml, bin) = match split {
        Some(i) => (&data[..i], &data[i + 2..]),
        None => (data, &[][..]),
    };
    let path = scratch_dir().join("xml.x3p");
    let file = std::fs::File::create(&path).expect("scratch x3p");
    let mut zip = zip::ZipWriter::new(file);
    let stored = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    zip.start_file("main.xml", stored).expect("zip entry");
    zip.write_all(xml).expect("zip write");
    zip.start_file("bindata/data.bin", stored).expect("zip entry");
    zip.write_all(bin).expect("zip write");
    zip.finish().expect("zip finish");
    if let Ok(profile) = read_x3p(&path) {
        let _ = profile.windows(0.8e-3, 0.5e-3);
    }
}

/// The device the MTConnect targets read against: a five-axis B/C head (the built-in
/// `generic-bc-head`) whose data items carry the SHDR keys and ids of the Okuma adapter's log in
/// `../shared/outside/mtconnect` (so that its lines, the seeds, reach the axes), a path position,
/// a message and a condition (their several SHDR fields), written here.
const MTCONNECT_DEVICE: &str = r#"<MTConnectDevices><Devices><Device id="dev" name="OKUMA" uuid="OKUMA.123456">
<DataItems><DataItem category="EVENT" id="Lavail" name="avail" type="AVAILABILITY"/>
<DataItem category="EVENT" id="Lmsg" name="message" type="MESSAGE"/>
<DataItem category="CONDITION" id="Lsystem" name="system" type="SYSTEM"/></DataItems>
<Components><Axes id="axes"><Components>
<Linear id="x" name="X"><DataItems><DataItem category="SAMPLE" id="LX1actw" name="X1actw" type="POSITION" subType="ACTUAL" units="MILLIMETER" nativeUnits="MILLIMETER" coordinateSystem="WORK"/></DataItems></Linear>
<Linear id="y" name="Y"><DataItems><DataItem category="SAMPLE" id="LYI1actw" name="YI1actw" type="POSITION" subType="ACTUAL" units="MILLIMETER" nativeUnits="INCH"/></DataItems></Linear>
<Linear id="z" name="Z"><DataItems><DataItem category="SAMPLE" id="LZ1actw" name="Z1actw" type="POSITION" subType="ACTUAL" units="MILLIMETER"/></DataItems></Linear>
<Rotary id="b" name="B"><DataItems><DataItem category="SAMPLE" id="LB1actw" name="B1actw" type="ANGLE" subType="ACTUAL" units="DEGREE"/></DataItems></Rotary>
<Rotary id="c" name="C"><DataItems><DataItem category="SAMPLE" id="LC3actw" name="C3actw" type="ANGLE" subType="ACTUAL" units="DEGREE" nativeUnits="RADIAN"/></DataItems></Rotary>
</Components></Axes><Controller id="cont"><Components><Path id="path"><DataItems>
<DataItem category="SAMPLE" id="Lp1LPathPos" name="p1LPathPos" type="PATH_POSITION" subType="ACTUAL" units="MILLIMETER_3D"/>
</DataItems></Path></Components></Controller></Components></Device></Devices></MTConnectDevices>"#;

/// The machine the MTConnect targets find axes for (built once, not per input).
fn mtconnect_machine() -> &'static Machine {
    static MACHINE: std::sync::OnceLock<Machine> = std::sync::OnceLock::new();
    MACHINE.get_or_init(|| Machine::builtin("generic-bc-head").expect("generic-bc-head"))
}

/// [`MTCONNECT_DEVICE`] read, and its axes found for `generic-bc-head` by the Okuma log's keys, in
/// the adapter's units (`nativeUnits`) or the agent's (`units`); read once.
fn mtconnect_device(units: fiveaxis::mtconnect::UnitsOf) -> &'static (Vec<fiveaxis::mtconnect::devices::Device>, fiveaxis::mtconnect::AxisItems) {
    use fiveaxis::mtconnect::{axis_items, devices, UnitsOf};
    type Read = (Vec<devices::Device>, fiveaxis::mtconnect::AxisItems);
    static ADAPTER: std::sync::OnceLock<Read> = std::sync::OnceLock::new();
    static AGENT: std::sync::OnceLock<Read> = std::sync::OnceLock::new();
    let cell = if units == UnitsOf::Adapter { &ADAPTER } else { &AGENT };
    cell.get_or_init(|| {
        let all = devices::parse(MTCONNECT_DEVICE).expect("the targets' device");
        let map = [("X", "X1actw"), ("Y", "YI1actw"), ("Z", "Z1actw"), ("B", "B1actw"), ("C", "C3actw")].map(|(a, k)| (a.to_string(), k.to_string())).into_iter().collect();
        let axes = axis_items(&all[0], mtconnect_machine(), &map, units).expect("the targets' axes");
        (all, axes)
    })
}

/// An MTConnect adapter's SHDR stream (a log of it, as `fiveaxis analyze --shdr` and the bridge's
/// adapter client read it): every line against [`MTCONNECT_DEVICE`], each axis value taken.
pub fn shdr_log(data: &[u8]) {
    let (all, axes) = mtconnect_device(fiveaxis::mtconnect::UnitsOf::Adapter);
    let _ = fiveaxis::mtconnect::read_log(data, all, &all[0], axes, |_| {});
}

/// An MTConnect agent's answers as the bridge's agent client reads them (src/mtconnect/live.rs).
/// The first byte picks what the rest is: an HTTP answer (its head, then the documents of a
/// multipart `/sample` stream, chunked or not, or a whole body), a `/probe` document (each device's
/// axes looked for on `generic-bc-head`) or a streams document (each observation of an axis of
/// [`MTCONNECT_DEVICE`] read as a number).
pub fn mtconnect_agent(data: &[u8]) {
    use fiveaxis::mtconnect::http::{read_body, read_head, Chunked, Parts};
    use std::io::BufReader;
    let Some((&pick, rest)) = data.split_first() else { return };
    match pick % 3 {
        0 => {
            let mut r = BufReader::new(rest);
            let Ok(head) = read_head(&mut r) else { return };
            match head.boundary() {
                Some(b) if head.chunked() => agent_parts(Parts::new(BufReader::new(Chunked::new(r)), &b)),
                Some(b) => agent_parts(Parts::new(r, &b)),
                None => {
                    if let Ok(body) = read_body(&head, &mut r) {
                        agent_probe(&body);
                        agent_streams(&body);
                    }
                }
            }
        }
        1 => agent_probe(rest),
        _ => agent_streams(rest),
    }
}

/// Each document of a multipart stream, as a streams document.
fn agent_parts<R: std::io::BufRead>(mut parts: fiveaxis::mtconnect::http::Parts<R>) {
    while let Ok(Some(part)) = parts.next_part() {
        agent_streams(&part);
    }
}

/// A `/probe` answer: its devices, the one picked, and each one's axes found for `generic-bc-head`
/// by their components' names and, in turn, by the Okuma log's keys.
fn agent_probe(doc: &[u8]) {
    use fiveaxis::mtconnect::{axis_items, devices, pick, UnitsOf};
    let Ok(all) = devices::parse(&String::from_utf8_lossy(doc)) else { return };
    let _ = pick(&all, None);
    let _ = pick(&all, Some("OKUMA"));
    let machine = mtconnect_machine();
    let map = [("X", "X1actw"), ("C", "C3actw")].map(|(a, k)| (a.to_string(), k.to_string())).into_iter().collect();
    for d in &all {
        let _ = axis_items(d, machine, &Default::default(), UnitsOf::Agent);
        let _ = axis_items(d, machine, &map, UnitsOf::Adapter);
        for i in &d.items {
            let _ = i.shdr_fields();
        }
    }
}

/// A streams document: its header, and each observation of an axis of [`MTCONNECT_DEVICE`] read.
fn agent_streams(doc: &[u8]) {
    let Ok(s) = fiveaxis::mtconnect::streams::parse(&String::from_utf8_lossy(doc)) else { return };
    let (_, axes) = mtconnect_device(fiveaxis::mtconnect::UnitsOf::Agent);
    for o in &s.observations {
        if let Some(i) = axes.axis_of(&o.data_item_id) {
            let _ = axes.value(i, &o.value);
        }
        let _ = o.stamp.as_secs();
    }
}
