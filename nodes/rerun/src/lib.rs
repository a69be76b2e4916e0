//! The Rerun bridge: [`fiveaxis::scene`] rows and events logged to a Rerun recording stream, with
//! a default layout (blueprint) that opens on the comparison a user came for: C speed and feed
//! against the workpiece x, the roughness profile below them.
//!
//! Entities (units in the names where they are not obvious):
//! - `c_speed/{commanded,simulated,machine}` |C speed| measured on each stream, `c_speed/predicted`
//!   (seed 001 eq. 5 at the programmed feed), `c_speed/limit`, rpm;
//! - `feed/programmed`, `feed/{commanded,simulated,machine}`, `feed/axis_limit` (seed 002 eq. 5), mm/min;
//! - `axes/{A,C}/{stream}` degrees; `distance/{stream}` degrees to the singularity;
//! - `roughness/profile` and `roughness/ra` in um (on the x timeline only);
//! - `events/regions` text log; `orientation/*` the unit sphere, singular direction and cone, tool
//!   axis and its trace; `toolpath/*` the tool tip in the workpiece frame, mm.
//!
//! Timelines: `time` (the samples' stamps, s since the first) and `workpiece_x_um` (integer um).

use fiveaxis::roughness::Profile;
use fiveaxis::scene::{self, Event, Row, TIMELINE_TIME, TIMELINE_X_UM};
use rerun::blueprint::{Blueprint, ContainerLike, Horizontal, Spatial3DView, Tabs, TextLogView, TimePanel, TimeSeriesView, Vertical};
use rerun::{RecordingStream, TimeColumn};
use std::collections::BTreeMap;

/// Application id of our recordings (the viewer groups recordings by it).
pub const APP_ID: &str = "fiveaxis";

/// Rows buffered per entity before a columnar send.
const BATCH: usize = 2000;
/// Every how many rows of a stream the 3D views get a sample (1 kHz streams: 50 Hz).
const DECIMATE_3D: u64 = 20;

/// A scalar series being buffered: rows with an x, and rows without (rapids).
#[derive(Default)]
struct Series {
    t: Vec<f64>,
    x: Vec<i64>,
    v: Vec<f64>,
    t_only: Vec<f64>,
    v_only: Vec<f64>,
}

impl Series {
    fn push(&mut self, t: f64, x: Option<i64>, v: f64) {
        if !v.is_finite() {
            return;
        }
        match x {
            Some(x) => {
                self.t.push(t);
                self.x.push(x);
                self.v.push(v);
            }
            None => {
                self.t_only.push(t);
                self.v_only.push(v);
            }
        }
    }
    fn len(&self) -> usize {
        self.t.len() + self.t_only.len()
    }
}

/// Logs scene rows and events to a Rerun stream.
pub struct Bridge {
    rec: RecordingStream,
    series: BTreeMap<String, Series>,
    styled: std::collections::BTreeSet<String>,
    rows_per_stream: BTreeMap<&'static str, u64>,
    trace: BTreeMap<&'static str, Vec<[f32; 3]>>,
    path: BTreeMap<&'static str, Vec<[f32; 3]>>,
    cone_deg: Option<f64>,
    singular: [f64; 3],
    has_commanded: bool,
    last_limiting: Option<String>,
}

/// Colours: commanded blue, simulated orange, machine green, predicted red, limits grey.
fn color(name: &str) -> [u8; 3] {
    match name {
        "commanded" => [66, 133, 244],
        "simulated" => [255, 140, 0],
        "machine" => [52, 168, 83],
        "predicted" => [219, 68, 55],
        "programmed" => [120, 120, 120],
        "limit" | "axis_limit" => [160, 160, 160],
        _ => [200, 200, 200],
    }
}

impl Bridge {
    /// A bridge over `rec`, for a machine whose singular direction (workpiece frame) is `singular`.
    /// Logs the static parts: the unit sphere, the singular direction, the styles.
    pub fn new(rec: RecordingStream, singular: [f64; 3]) -> anyhow::Result<Bridge> {
        rec.log_static("orientation/unit_sphere", &rerun::LineStrips3D::new(scene::sphere_wireframe(singular)).with_colors([[90, 90, 90]]).with_radii([0.002f32]))?;
        let s = singular.map(|v| v as f32);
        rec.log_static(
            "orientation/singular_direction",
            &rerun::Arrows3D::from_vectors([[s[0] * 1.2, s[1] * 1.2, s[2] * 1.2], [-s[0] * 1.2, -s[1] * 1.2, -s[2] * 1.2]])
                .with_colors([[219, 68, 55]])
                .with_labels(["singular direction", ""]),
        )?;
        Ok(Bridge {
            rec,
            series: BTreeMap::new(),
            styled: Default::default(),
            rows_per_stream: BTreeMap::new(),
            trace: BTreeMap::new(),
            path: BTreeMap::new(),
            cone_deg: None,
            singular,
            has_commanded: false,
            last_limiting: None,
        })
    }

    /// The recording stream (to flush or disconnect).
    pub fn stream(&self) -> &RecordingStream {
        &self.rec
    }

    fn scalar(&mut self, entity: String, label: &str, t: f64, x: Option<i64>, v: f64) -> anyhow::Result<()> {
        if self.styled.insert(entity.clone()) {
            let style_key = entity.rsplit('/').next().unwrap_or("");
            self.rec.log_static(entity.as_str(), &rerun::SeriesLines::new().with_names([label]).with_colors([color(style_key)]))?;
        }
        let s = self.series.entry(entity.clone()).or_default();
        s.push(t, x, v);
        if s.len() >= BATCH {
            let s = std::mem::take(s);
            self.send(&entity, s)?;
        }
        Ok(())
    }

    fn send(&self, entity: &str, s: Series) -> anyhow::Result<()> {
        if !s.t.is_empty() {
            self.rec.send_columns(
                entity,
                [TimeColumn::new_duration_secs(TIMELINE_TIME, s.t), TimeColumn::new_sequence(TIMELINE_X_UM, s.x)],
                rerun::Scalars::new(s.v).columns_of_unit_batches()?,
            )?;
        }
        if !s.t_only.is_empty() {
            self.rec.send_columns(entity, [TimeColumn::new_duration_secs(TIMELINE_TIME, s.t_only)], rerun::Scalars::new(s.v_only).columns_of_unit_batches()?)?;
        }
        Ok(())
    }

    /// Log one row (and the events that came with it).
    pub fn row(&mut self, r: &Row) -> anyhow::Result<()> {
        let (t, x, st) = (r.t_s, r.x_um, r.stream);
        self.has_commanded |= st == "commanded";
        // The program's figures come from the commanded stream; without one (a machine's bridge), from
        // the stream at hand.
        let lead = st == "commanded" || !self.has_commanded && st != "simulated";
        self.scalar(format!("c_speed/{st}"), &format!("|{}| speed, {st} (rpm)", r.rotary[1]), t, x, r.c_speed_rpm.abs())?;
        self.scalar(format!("feed/{st}"), &format!("path feed, {st} (mm/min)"), t, x, r.path_feed_mm_min)?;
        self.scalar(format!("axes/{}/{st}", r.rotary[0]), &format!("{}, {st} (deg)", r.rotary[0]), t, x, r.a_deg)?;
        self.scalar(format!("axes/{}/{st}", r.rotary[1]), &format!("{}, {st} (deg)", r.rotary[1]), t, x, r.c_deg)?;
        self.scalar(format!("distance/{st}"), &format!("distance to the singularity, {st} (deg)"), t, x, r.distance_deg)?;
        if lead {
            self.scalar("c_speed/predicted".into(), &format!("|{}| speed predicted, eq. 5 (rpm)", r.rotary[1]), t, x, r.predicted_c_speed_rpm.abs())?;
            self.scalar("c_speed/limit".into(), &format!("{} speed limit (rpm)", r.rotary[1]), t, x, r.c_limit_rpm)?;
            if r.programmed_feed_mm_min > 0.0 {
                self.scalar("feed/programmed".into(), "programmed feed (mm/min)", t, x, r.programmed_feed_mm_min)?;
                self.scalar("feed/axis_limit".into(), "feed the axis limits allow, seed 002 eq. 5 (mm/min)", t, x, r.feed_limit_mm_min)?;
                // Which axis limits the feed, when that changes (in the cut).
                let limiting = if r.limiting_axis.is_empty() { "programmed feed".to_string() } else { format!("axis {}", r.limiting_axis) };
                if x.is_some() && self.last_limiting.as_ref() != Some(&limiting) {
                    self.set_time(t, x);
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
            let axis = r.tool_axis.map(|v| v as f32);
            let tip = r.tool_tip_mm.map(|v| v as f32);
            self.trace.entry(st).or_default().push(axis);
            self.path.entry(st).or_default().push(tip);
            self.set_time(t, x);
            self.rec.log(format!("orientation/tool_axis/{st}"), &rerun::Arrows3D::from_vectors([axis]).with_colors([color(st)]).with_radii([0.008f32]))?;
            self.rec.log(format!("toolpath/tip/{st}"), &rerun::Points3D::new([tip]).with_colors([color(st)]).with_radii([0.6f32]))?;
            if self.trace[st].len() % 500 == 1 {
                self.log_traces()?;
            }
        }
        Ok(())
    }

    fn set_time(&self, t: f64, x: Option<i64>) {
        self.rec.set_duration_secs(TIMELINE_TIME, t);
        match x {
            Some(x) => self.rec.set_time_sequence(TIMELINE_X_UM, x),
            None => self.rec.disable_timeline(TIMELINE_X_UM),
        }
    }

    fn log_traces(&self) -> anyhow::Result<()> {
        for (st, pts) in &self.trace {
            self.rec.log_static(format!("orientation/trace/{st}"), &rerun::LineStrips3D::new([pts.clone()]).with_colors([color(st)]).with_radii([0.003f32]))?;
        }
        for (st, pts) in &self.path {
            self.rec.log_static(format!("toolpath/path/{st}"), &rerun::LineStrips3D::new([pts.clone()]).with_colors([color(st)]).with_radii([0.15f32]))?;
        }
        Ok(())
    }

    /// Log region events as text entries on both timelines; the cone follows the largest distance
    /// at which a region was seen.
    pub fn events(&mut self, events: &[Event]) -> anyhow::Result<()> {
        for e in events {
            self.set_time(e.t_s, e.x_um);
            let level = if e.enters { "WARN" } else { "INFO" };
            self.rec.log("events/regions", &rerun::TextLog::new(e.text.clone()).with_level(level))?;
        }
        Ok(())
    }

    /// The singular cone: tool axes closer to the singular direction than the farthest in-region
    /// sample so far (where C went over its limit), or `default_deg` before any region.
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

    /// Log a roughness profile along the workpiece x (its height after the ISO 16610-21 filter, and
    /// windowed Ra), labelled with the profile's source (e.g. SYNTHETIC).
    pub fn roughness(&mut self, profile: &Profile, lambda_c: f64) -> anyhow::Result<()> {
        let (heights, ra) = scene::roughness_series(profile, lambda_c);
        let label = if profile.source.to_ascii_uppercase().contains("SYNTHETIC") { "SYNTHETIC " } else { "" };
        for (entity, name, data) in [("roughness/profile", format!("{label}roughness profile, lambda_c {} mm (um)", lambda_c * 1e3), heights), ("roughness/ra", format!("{label}Ra over 5 lambda_c (um)"), ra)] {
            self.rec.log_static(entity, &rerun::SeriesLines::new().with_names([name]).with_colors([[110, 110, 110]]))?;
            for chunk in data.chunks(BATCH * 10) {
                self.rec.send_columns(
                    entity,
                    [TimeColumn::new_sequence(TIMELINE_X_UM, chunk.iter().map(|p| p.0))],
                    rerun::Scalars::new(chunk.iter().map(|p| p.1)).columns_of_unit_batches()?,
                )?;
            }
        }
        self.rec.log_static("roughness/source", &rerun::TextDocument::new(format!("roughness profile: {}", profile.source)))?;
        Ok(())
    }

    /// Send what is buffered (call now and then when live, and at the end).
    pub fn flush(&mut self) -> anyhow::Result<()> {
        for (entity, s) in std::mem::take(&mut self.series) {
            self.send(&entity, s)?;
        }
        self.log_traces()?;
        Ok(())
    }
}

/// The default layout: C speed and feed against x with the roughness below (left), the tool axis on
/// the unit sphere, the axes, the distance and the region log (right); the x timeline selected. Also
/// returns the blueprint paths of the plots, whose time axes [`send_layout`] sets to the whole range.
pub fn blueprint() -> (Blueprint, Vec<String>) {
    let plots = [
        TimeSeriesView::new("C speed across the part (rpm)").with_contents(["c_speed/**"]),
        TimeSeriesView::new("feed across the part (mm/min)").with_contents(["feed/**"]),
        TimeSeriesView::new("roughness across the part (um)").with_contents(["roughness/**"]),
        TimeSeriesView::new("distance to the singularity (deg)").with_contents(["distance/**"]),
        TimeSeriesView::new("rotary axes (deg)").with_contents(["axes/**"]),
    ];
    let plots: Vec<ContainerLike> = plots.into_iter().map(Into::into).collect();
    let paths: Vec<String> = plots
        .iter()
        .filter_map(|v| match v {
            ContainerLike::View(v) => Some(v.blueprint_path().to_string()),
            _ => None,
        })
        .collect();
    let Ok([c, feed, rough, dist, axes]) = <[ContainerLike; 5]>::try_from(plots) else { unreachable!("five plots") };
    let left = Vertical::new([c, feed, rough]).with_row_shares([2.0, 2.0, 1.5]);
    let views_3d = Tabs::new([
        Spatial3DView::new("tool axis on the unit sphere").with_contents(["orientation/**"]).into(),
        Spatial3DView::new("tool path (mm, workpiece frame)").with_contents(["toolpath/**"]).into(),
    ]);
    let right = Vertical::new([views_3d.into(), dist, axes, TextLogView::new("regions and feed limits").with_contents(["events/**"]).into()])
        .with_row_shares([3.0, 1.2, 1.2, 1.6]);
    let bp = Blueprint::new(Horizontal::new([left.into(), right.into()]).with_column_shares([3.0, 2.0]))
        .with_time_panel(TimePanel::new().with_timeline(TIMELINE_X_UM).with_play_state(rerun::blueprint::components::PlayState::Paused))
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
