//! The Rerun bridge: [`fiveaxis::scene`] rows and events logged to a Rerun recording stream, with
//! a default layout (blueprint) that opens on the comparison a user came for: across the part (x in
//! mm, cutting passes only) the C speed, the feed and the roughness profile stacked on one x axis;
//! over time every sample; the machine moving beside the tool axis on the unit sphere.
//!
//! Entities (units in the names where they are not obvious):
//! - `across/{c_speed,feed}/pass_N/{stream,predicted,programmed}`, `across/c_speed/limit`,
//!   `across/roughness/{profile,ra}` and the charts' axes, ticks, titles and legend ([`across`]): 2D,
//!   x in mm;
//! - over time: `c_speed/{commanded,simulated,machine,predicted,limit}` rpm,
//!   `feed/{programmed,commanded,simulated,machine,axis_limit}` mm/min, `axes/{A,C}/{stream}` degrees,
//!   `distance/{stream}` degrees to the singularity;
//! - `events/regions` and `events/feed_limit` text logs; `orientation/*` the unit sphere, singular
//!   direction and cone, tool axis and its trace; `machine/*` the machine's bed, rotary parts (their
//!   transforms follow the axes), the cut path on the table and the tool, mm.
//!
//! Timeline: `time` (the samples' stamps, s since the first).

pub mod across;

use across::{color, Across};
use fiveaxis::machine::Machine;
use fiveaxis::roughness::Profile;
use fiveaxis::scene::{self, machine_pose, Event, PartPose, Row, TIMELINE_TIME};
use rerun::blueprint::{Blueprint, BlueprintPanel, ContainerLike, Horizontal, SelectionPanel, Spatial2DView, Spatial3DView, TextLogView, TimePanel, TimeSeriesView, Vertical};
use rerun::{RecordingStream, TimeColumn};
use std::collections::BTreeMap;

/// Application id of our recordings (the viewer groups recordings by it).
pub const APP_ID: &str = "fiveaxis";

/// Rows buffered per entity before a columnar send.
const BATCH: usize = 2000;
/// Every how many rows of a stream the 3D views get a sample (1 kHz streams: 50 Hz).
const DECIMATE_3D: u64 = 20;
/// Points kept of each 3D trace (the oldest half is thinned past it).
const TRACE_CAP: usize = 20_000;
/// Tool length drawn in the machine view, mm.
const TOOL_MM: f32 = 80.0;

/// A scalar series being buffered.
#[derive(Default)]
struct Series {
    t: Vec<f64>,
    v: Vec<f64>,
}

/// Where the bridge's figures go and how the passes are told apart.
#[derive(Debug, Clone)]
pub struct BridgeOptions {
    /// Height band of the passes in contact, mm ([`scene::CONTACT_BAND_MM`]).
    pub contact_band_mm: f64,
    /// The workpiece y (mm) of the pass the roughness profile was measured on.
    pub roughness_y_mm: Option<f64>,
}

impl Default for BridgeOptions {
    fn default() -> Self {
        BridgeOptions { contact_band_mm: scene::CONTACT_BAND_MM, roughness_y_mm: None }
    }
}

/// Logs scene rows and events to a Rerun stream.
pub struct Bridge {
    rec: RecordingStream,
    machine: Machine,
    series: BTreeMap<String, Series>,
    styled: std::collections::BTreeSet<String>,
    rows_per_stream: BTreeMap<&'static str, u64>,
    trace: BTreeMap<&'static str, Vec<[f32; 3]>>,
    /// The cut path in the table frame (the workpiece as the table carries it), per stream.
    cut: BTreeMap<&'static str, Vec<[f32; 3]>>,
    /// Entity paths of the moving parts, nested as they carry each other (see [`part_paths`]).
    parts: PartPaths,
    /// The stream that moves the machine view: machine, else simulated, else commanded.
    mover: Option<&'static str>,
    across: Across,
    cone_deg: Option<f64>,
    singular: [f64; 3],
    has_commanded: bool,
    last_limiting: Option<String>,
}

/// Root entities of the machine's table side and of its head (the head's transform is the linear axes').
const TABLE: &str = "machine/table";
const HEAD: &str = "machine/head";

/// Entity paths of the rotary parts, each under the part that carries it and named by its axis
/// (`machine/table/A/C`, `machine/head/B`), in the order of the chain's table and head slots (the
/// order of [`machine_pose`]'s parts).
struct PartPaths {
    table: Vec<String>,
    head: Vec<String>,
}

impl PartPaths {
    /// Where the workpiece rides: the innermost table part (the table root on a head/head machine).
    fn workpiece_carrier(&self) -> &str {
        self.table.last().map_or(TABLE, String::as_str)
    }
    /// Where the tool rides: the innermost head part (the head root on a table/table machine).
    fn tool_carrier(&self) -> &str {
        self.head.last().map_or(HEAD, String::as_str)
    }
}

fn part_paths(m: &Machine) -> PartPaths {
    let nest = |root: &str, slots: &[usize]| {
        slots
            .iter()
            .scan(root.to_string(), |path, &slot| {
                *path = format!("{path}/{}", m.axes[3 + slot].name);
                Some(path.clone())
            })
            .collect()
    };
    PartPaths { table: nest(TABLE, m.chain.table_slots()), head: nest(HEAD, m.chain.head_slots()) }
}

fn rank(stream: &str) -> u8 {
    match stream {
        "machine" => 3,
        "simulated" => 2,
        _ => 1,
    }
}

/// An nalgebra vector as Rerun's `[f32; 3]`.
fn v3(v: nalgebra::Vector3<f64>) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

fn quat(r: [f64; 4]) -> rerun::Quaternion {
    rerun::Quaternion::from_xyzw(r.map(|v| v as f32))
}

/// Rotation taking +z onto `dir` (for the cylinders, which stand along z).
fn z_onto(dir: nalgebra::Vector3<f64>) -> rerun::Quaternion {
    let q = nalgebra::UnitQuaternion::rotation_between(&nalgebra::Vector3::z(), &dir)
        .unwrap_or_else(|| nalgebra::UnitQuaternion::from_axis_angle(&nalgebra::Vector3::x_axis(), std::f64::consts::PI));
    let c = q.coords;
    quat([c.x, c.y, c.z, c.w])
}

impl Bridge {
    /// A bridge over `rec` for `machine`. Logs the static parts: the unit sphere, the singular
    /// direction, the machine's shapes.
    pub fn new(rec: RecordingStream, machine: &Machine, options: &BridgeOptions) -> anyhow::Result<Bridge> {
        let singular: [f64; 3] = machine.singular_direction().into();
        rec.log_static("orientation/unit_sphere", &rerun::LineStrips3D::new(scene::sphere_wireframe(singular)).with_colors([[90, 90, 90]]).with_radii([0.002f32]))?;
        let s = singular.map(|v| v as f32);
        rec.log_static(
            "orientation/singular_direction",
            &rerun::Arrows3D::from_vectors([[s[0] * 1.2, s[1] * 1.2, s[2] * 1.2], [-s[0] * 1.2, -s[1] * 1.2, -s[2] * 1.2]])
                .with_colors([[219, 68, 55]])
                .with_labels(["singular direction", ""]),
        )?;
        let parts = part_paths(machine);
        Self::log_machine_shapes(&rec, machine, &parts)?;
        Ok(Bridge {
            rec,
            machine: machine.clone(),
            series: BTreeMap::new(),
            styled: Default::default(),
            rows_per_stream: BTreeMap::new(),
            trace: BTreeMap::new(),
            cut: BTreeMap::new(),
            parts,
            mover: None,
            across: Across::new(options.contact_band_mm, options.roughness_y_mm),
            cone_deg: None,
            singular,
            has_commanded: false,
            last_limiting: None,
        })
    }

    /// The machine's parts as simple shapes in their own frames (mm): the bed, each table part (a
    /// cradle for the outer one, a round table for the inner one), the tool and spindle on the head.
    fn log_machine_shapes(rec: &RecordingStream, m: &Machine, parts: &PartPaths) -> anyhow::Result<()> {
        let down = -m.chain.tool_axis();
        let joint = |slot: usize| (m.chain.joints()[slot].center * 1e3, m.chain.joints()[slot].axis);
        let grey = [120, 120, 130];
        rec.log_static(
            "machine/bed",
            &rerun::Boxes3D::from_centers_and_half_sizes([v3(down * 330.0)], [[400.0f32, 300.0, 40.0]])
                .with_quaternions([z_onto(-down)])
                .with_colors([[70, 70, 75]])
                .with_fill_mode(rerun::FillMode::Solid),
        )?;
        let table = m.chain.table_slots();
        for (k, (&slot, path)) in table.iter().zip(&parts.table).enumerate() {
            let (c, a) = joint(slot);
            if k + 1 < table.len() {
                // A cradle: long along its axis, below the axis line.
                let centre = c + down * 120.0;
                rec.log_static(
                    format!("{path}/shape").as_str(),
                    &rerun::Boxes3D::from_centers_and_half_sizes([v3(centre)], [[260.0f32, 20.0, 150.0]])
                        .with_quaternions([z_onto(down.cross(&a).try_normalize(1e-9).unwrap_or(nalgebra::Vector3::y()))])
                        .with_colors([grey])
                        .with_fill_mode(rerun::FillMode::Solid),
                )?;
            } else {
                // The round table the workpiece is clamped on, its top through the axis' centre.
                let centre = c - a * 15.0 * a.dot(&-down).signum();
                rec.log_static(
                    format!("{path}/shape").as_str(),
                    &rerun::Cylinders3D::from_lengths_and_radii([30.0f32], [150.0f32])
                        .with_centers([v3(centre)])
                        .with_quaternions([z_onto(a)])
                        .with_colors([[150, 150, 160]])
                        .with_fill_mode(rerun::FillMode::Solid),
                )?;
            }
        }
        for (&slot, path) in m.chain.head_slots().iter().zip(&parts.head) {
            let (c, a) = joint(slot);
            rec.log_static(
                format!("{path}/shape").as_str(),
                &rerun::Cylinders3D::from_lengths_and_radii([120.0f32], [60.0f32]).with_centers([v3(c)]).with_quaternions([z_onto(a)]).with_colors([grey]),
            )?;
        }
        let (tip, axis) = (m.chain.tool_tip() * 1e3, m.chain.tool_axis());
        let tool_c = tip + axis * (TOOL_MM as f64 / 2.0);
        let spindle_c = tip + axis * (TOOL_MM as f64 + 100.0);
        rec.log_static(
            format!("{}/tool", parts.tool_carrier()).as_str(),
            &rerun::Cylinders3D::from_lengths_and_radii([TOOL_MM, 200.0], [5.0f32, 50.0])
                .with_centers([v3(tool_c), v3(spindle_c)])
                .with_quaternions([z_onto(axis), z_onto(axis)])
                .with_colors([[230, 230, 240], [80, 110, 160]])
                .with_fill_mode(rerun::FillMode::Solid),
        )?;
        Ok(())
    }

    /// The recording stream (to flush or disconnect).
    pub fn stream(&self) -> &RecordingStream {
        &self.rec
    }

    fn scalar(&mut self, entity: String, label: &str, t: f64, v: f64) -> anyhow::Result<()> {
        if !v.is_finite() {
            return Ok(());
        }
        if self.styled.insert(entity.clone()) {
            let style_key = entity.rsplit('/').next().unwrap_or("");
            self.rec.log_static(entity.as_str(), &rerun::SeriesLines::new().with_names([label]).with_colors([color(style_key)]))?;
        }
        let s = self.series.entry(entity.clone()).or_default();
        s.t.push(t);
        s.v.push(v);
        if s.t.len() >= BATCH {
            let s = std::mem::take(s);
            self.send(&entity, s)?;
        }
        Ok(())
    }

    fn send(&self, entity: &str, s: Series) -> anyhow::Result<()> {
        if !s.t.is_empty() {
            self.rec.send_columns(entity, [TimeColumn::new_duration_secs(TIMELINE_TIME, s.t)], rerun::Scalars::new(s.v).columns_of_unit_batches()?)?;
        }
        Ok(())
    }

    /// Log one row (and the events that came with it).
    pub fn row(&mut self, r: &Row) -> anyhow::Result<()> {
        let (t, st) = (r.t_s, r.stream);
        self.has_commanded |= st == "commanded";
        // The program's figures come from the commanded stream; without one (a machine's bridge), from
        // the stream at hand.
        let lead = st == "commanded" || !self.has_commanded && st != "simulated";
        self.across.row(r, lead);
        self.scalar(format!("c_speed/{st}"), &format!("|{}| speed, {st} (rpm)", r.rotary[1]), t, r.c_speed_rpm.abs())?;
        self.scalar(format!("feed/{st}"), &format!("path feed, {st} (mm/min)"), t, r.path_feed_mm_min)?;
        self.scalar(format!("axes/{}/{st}", r.rotary[0]), &format!("{}, {st} (deg)", r.rotary[0]), t, r.a_deg)?;
        self.scalar(format!("axes/{}/{st}", r.rotary[1]), &format!("{}, {st} (deg)", r.rotary[1]), t, r.c_deg)?;
        self.scalar(format!("distance/{st}"), &format!("distance to the singularity, {st} (deg)"), t, r.distance_deg)?;
        if lead {
            self.scalar("c_speed/predicted".into(), &format!("|{}| speed predicted, eq. 5 (rpm)", r.rotary[1]), t, r.predicted_c_speed_rpm.abs())?;
            self.scalar("c_speed/limit".into(), &format!("{} speed limit (rpm)", r.rotary[1]), t, r.c_limit_rpm)?;
            if r.programmed_feed_mm_min > 0.0 {
                self.scalar("feed/programmed".into(), "programmed feed (mm/min)", t, r.programmed_feed_mm_min)?;
                self.scalar("feed/axis_limit".into(), "feed the axis limits allow, seed 002 eq. 5 (mm/min)", t, r.feed_limit_mm_min)?;
                // Which axis limits the feed, when that changes (on a pass).
                let limiting = if r.limiting_axis.is_empty() { "programmed feed".to_string() } else { format!("axis {}", r.limiting_axis) };
                if r.pass.is_some() && self.last_limiting.as_ref() != Some(&limiting) {
                    self.rec.set_duration_secs(TIMELINE_TIME, t);
                    self.rec.log("events/feed_limit", &rerun::TextLog::new(format!("{st}: feed limited by the {limiting} from x {:.3} mm", r.tool_tip_mm[0])).with_level("DEBUG"))?;
                    self.last_limiting = Some(limiting);
                }
            }
        }
        if r.in_region {
            self.cone(r.distance_deg)?;
        }
        let n = self.rows_per_stream.entry(st).or_default();
        *n += 1;
        if *n % DECIMATE_3D == 1 {
            self.rec.set_duration_secs(TIMELINE_TIME, t);
            let axis = r.tool_axis.map(|v| v as f32);
            push_capped(self.trace.entry(st).or_default(), axis);
            self.rec.log(format!("orientation/tool_axis/{st}"), &rerun::Arrows3D::from_vectors([axis]).with_colors([color(st)]).with_radii([0.008f32]))?;
            if r.q.iter().all(|v| v.is_finite()) {
                let on_table = self.machine.forward(&r.q).tip * 1e3;
                push_capped(self.cut.entry(st).or_default(), v3(on_table));
                if self.mover.is_none_or(|m| rank(st) >= rank(m)) {
                    self.mover = Some(st);
                    self.move_machine(&r.q)?;
                }
            }
            if self.trace[st].len() % 500 == 1 {
                self.log_traces()?;
            }
        }
        Ok(())
    }

    /// The machine's parts at axis values `q` (at the current time).
    fn move_machine(&self, q: &fiveaxis::kinematics::Joints) -> anyhow::Result<()> {
        let pose = machine_pose(&self.machine, q);
        let tf = |p: &PartPose| rerun::Transform3D::from_translation_rotation(p.translation_mm.map(|v| v as f32), quat(p.rotation_xyzw));
        for (p, path) in pose.table.iter().zip(&self.parts.table) {
            self.rec.log(path.as_str(), &tf(p))?;
        }
        self.rec.log(HEAD, &rerun::Transform3D::from_translation(pose.head_linear_mm.map(|v| v as f32)))?;
        for (p, path) in pose.head.iter().zip(&self.parts.head) {
            self.rec.log(path.as_str(), &tf(p))?;
        }
        Ok(())
    }

    fn log_traces(&self) -> anyhow::Result<()> {
        for (st, pts) in &self.trace {
            self.rec.log_static(format!("orientation/trace/{st}"), &rerun::LineStrips3D::new([pts.clone()]).with_colors([color(st)]).with_radii([0.003f32]))?;
        }
        for (st, pts) in &self.cut {
            self.rec.log_static(
                format!("{}/cut/{st}", self.parts.workpiece_carrier()).as_str(),
                &rerun::LineStrips3D::new([pts.clone()]).with_colors([color(st)]).with_radii([rerun::components::Radius::new_ui_points(1.5)]),
            )?;
        }
        Ok(())
    }

    /// Log region events as text entries; the cone follows the largest distance at which a region
    /// was seen.
    pub fn events(&mut self, events: &[Event]) -> anyhow::Result<()> {
        for e in events {
            self.rec.set_duration_secs(TIMELINE_TIME, e.t_s);
            let level = if e.enters { "WARN" } else { "INFO" };
            self.rec.log("events/regions", &rerun::TextLog::new(e.text.clone()).with_level(level))?;
        }
        Ok(())
    }

    /// The singular cone: tool axes closer to the singular direction than the farthest in-region
    /// sample so far (where C went over its limit).
    fn cone(&mut self, d: f64) -> anyhow::Result<()> {
        if self.cone_deg.is_none_or(|c| d > c + 1e-3) {
            self.cone_deg = Some(d);
            self.rec.log_static(
                "orientation/singular_cone",
                &rerun::LineStrips3D::new(scene::singular_cone(self.singular, d.to_radians()))
                    .with_colors([[219, 68, 55]])
                    .with_radii([0.004f32]),
            )?;
        }
        Ok(())
    }

    /// Lay a roughness profile along the workpiece x (its height after the ISO 16610-21 filter, and
    /// windowed Ra), labelled with the profile's source (e.g. SYNTHETIC).
    pub fn roughness(&mut self, profile: &Profile, lambda_c: f64) -> anyhow::Result<()> {
        let (heights, ra) = scene::roughness_series(profile, lambda_c);
        let label = if profile.source.to_ascii_uppercase().contains("SYNTHETIC") { "SYNTHETIC " } else { "" };
        self.across.set_profile(heights, ra, label.to_string(), lambda_c * 1e3);
        self.rec.log_static("events/roughness_source", &rerun::TextDocument::new(format!("roughness profile: {}", profile.source)))?;
        Ok(())
    }

    /// Send what is buffered and redraw the charts across the part (call now and then when live, and
    /// at the end).
    pub fn flush(&mut self) -> anyhow::Result<()> {
        for (entity, s) in std::mem::take(&mut self.series) {
            self.send(&entity, s)?;
        }
        self.log_traces()?;
        self.across.draw(&self.rec)?;
        Ok(())
    }
}

/// Append to a trace, thinning its older half past [`TRACE_CAP`] points.
fn push_capped(v: &mut Vec<[f32; 3]>, p: [f32; 3]) {
    v.push(p);
    if v.len() > TRACE_CAP {
        let half = v.len() / 2;
        let thinned: Vec<[f32; 3]> = v[..half].iter().step_by(2).chain(&v[half..]).copied().collect();
        *v = thinned;
    }
}

/// The default layout. Left: across the part (the stacked 2D charts against x in mm) above the |C|
/// speed and the feed over time. Right: the machine beside the tool axis on the unit sphere, the
/// distance and the rotary axes over time, the region log. The `time` timeline is selected; side
/// panels start collapsed so the views get the window. Also returns the blueprint paths of the time
/// plots, whose time axes [`send_layout`] sets to the whole range.
pub fn blueprint() -> (Blueprint, Vec<String>) {
    let plots = [
        TimeSeriesView::new("|C| speed over time (rpm)").with_contents(["c_speed/**"]),
        TimeSeriesView::new("feed over time (mm/min)").with_contents(["feed/**"]),
        TimeSeriesView::new("distance to the singularity over time (deg)").with_contents(["distance/**"]),
        TimeSeriesView::new("rotary axes over time (deg)").with_contents(["axes/**"]),
    ];
    let plots: Vec<ContainerLike> = plots.into_iter().map(Into::into).collect();
    let paths: Vec<String> = plots
        .iter()
        .filter_map(|v| match v {
            ContainerLike::View(v) => Some(v.blueprint_path().to_string()),
            _ => None,
        })
        .collect();
    let Ok([c, feed, dist, axes]) = <[ContainerLike; 4]>::try_from(plots) else { unreachable!("four plots") };
    let across = Spatial2DView::new("across the part: cutting passes against the workpiece x (mm)").with_contents(["across/**"]);
    let left = Vertical::new([across.into(), Horizontal::new([c, feed]).into()]).with_row_shares([3.2, 1.3]);
    let views_3d = Horizontal::new([
        Spatial3DView::new("machine (simulated axes; mm)").with_contents(["machine/**"]).into(),
        Spatial3DView::new("tool axis on the unit sphere").with_contents(["orientation/**"]).into(),
    ]);
    let right = Vertical::new([views_3d.into(), dist, axes, TextLogView::new("regions and feed limits").with_contents(["events/**"]).into()])
        .with_row_shares([2.4, 1.0, 1.0, 1.1]);
    let bp = Blueprint::new(Horizontal::new([left.into(), right.into()]).with_column_shares([3.0, 2.0]))
        .with_time_panel(TimePanel::new().with_timeline(TIMELINE_TIME).with_play_state(rerun::blueprint::components::PlayState::Paused).with_state(rerun::blueprint::components::PanelState::Collapsed))
        .with_blueprint_panel(BlueprintPanel::new().with_state(rerun::blueprint::components::PanelState::Collapsed))
        .with_selection_panel(SelectionPanel::new().with_state(rerun::blueprint::components::PanelState::Collapsed))
        .with_auto_views(false);
    (bp, paths)
}

/// Send the default layout to `rec` as its default blueprint, with every plot's time axis showing the
/// whole recording (the Rust blueprint builder cannot set view properties, so they are
/// logged into the same blueprint store here).
pub fn send_layout(rec: &RecordingStream) -> anyhow::Result<()> {
    use rerun::external::re_sdk_types::blueprint::{archetypes::TimeAxis, components as bc};
    use rerun::external::re_sdk_types::datatypes::{TimeRange, TimeRangeBoundary};
    use rerun::log::LogMsg;
    let (bp, plots) = blueprint();
    let (collector, storage) = rerun::RecordingStreamBuilder::new(APP_ID).blueprint().memory()?;
    bp.send(&collector, rerun::blueprint::BlueprintActivation { make_active: false, make_default: true })?;
    collector.flush_blocking()?;
    let msgs = storage.take();
    let Some(cmd) = msgs.iter().find_map(|m| match m {
        LogMsg::BlueprintActivationCommand(c) => Some(c.clone()),
        _ => None,
    }) else {
        anyhow::bail!("the blueprint produced no activation command");
    };
    let mut out: Vec<LogMsg> = msgs.into_iter().filter(|m| !matches!(m, LogMsg::BlueprintActivationCommand(_)) && *m.store_id() == cmd.blueprint_id).collect();
    let (props, pstore) = rerun::RecordingStreamBuilder::new(APP_ID).recording_id(cmd.blueprint_id.recording_id().clone()).blueprint().memory()?;
    props.set_time_sequence("blueprint", 0);
    let whole = bc::TimeRange(TimeRange { start: TimeRangeBoundary::Infinite, end: TimeRangeBoundary::Infinite });
    for path in &plots {
        props.log(format!("{path}/TimeAxis"), &TimeAxis::new().with_view_range(whole))?;
    }
    props.flush_blocking()?;
    out.extend(pstore.take().into_iter().filter(|m| matches!(m, LogMsg::ArrowMsg(..)) && *m.store_id() == cmd.blueprint_id));
    rec.send_blueprint(out, cmd);
    Ok(())
}
