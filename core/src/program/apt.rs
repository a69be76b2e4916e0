//! APT cutter-location data (CLDATA as text, ISO 4343: what NX, CATIA, SOLIDWORKS CAM, NCL and
//! Fusion's APT post write before post-processing): `GOTO/x,y,z[,i,j,k]` tool-tip poses with their
//! tool axis (a GOTO of three keeps the last axis), `FEDRAT/` (MMPM or IPM, before or after the
//! value), `RAPID` (the next motion only), `UNITS/`, `MULTAX`, `TLAXIS/`, `FROM/`, `GODLTA/`, and
//! `CIRCLE/` arcs about X, Y or Z ended by the next GOTO. A statement runs on over lines ending in
//! `$`; `$$` starts a comment. `DELAY/t` is a dwell of t seconds. Statements that do not move the tool are kept as events (`SPINDL`,
//! `COOLNT`, `LOADTL`, `STOP`, an `INSERT`ed note) or passed over (`PARTNO`, `PPRINT`, `CUTTER`,
//! `BOX`, `MOVE_ATTRIB`); any other statement, or one of these in a form that changes the motion in a
//! way not read (feed per revolution, `INSERT`ed NC code, cycles, a helix of several turns, a part
//! frame turned against the machine's), is refused where it stands. NX's `MSYS/` places the part's
//! frame (MCS), in which the GOTOs are: its origin is the part zero a work offset sets, so it is
//! passed over when its axes are the machine's, and refused when they are turned.
//!
//! SOLIDWORKS CAM (as the AptPostProcessor project's `clsplit` reads it): `CSYS/` [R | t] is a 3+2
//! operation's working plane, whose Z column is its tool axis, the GOTOs staying in the part's frame
//! (`TRNTYP/WORLD`); a translation is refused. `CUTCOM/LEFT|RIGHT` leaves the GOTOs the tool centre's
//! path (CL data are cutter locations; the control adds only the register's wear, noted once). Its
//! `.clt` turns the table with `ROTABL/a,AAXIS,TABLE,CCLW` (ICAM's vocabulary: `a` the position,
//! `INCR` a step; CCLW right-handed about the axis) and writes the GOTOs and CIRCLEs in the part so
//! turned, the tool along its Z: the turn must put the tool along `TLAXIS/`, which is how its radians
//! are told from degrees (`--cl-angles rad`). A `CYCLE/` other than ON/OFF is refused, with the
//! holes at its GOTOs up to `CYCLE/OFF`.
//!
//! CIRCLE's direction depends on its writer: `CIRCLE/xc,yc,zc,i,j,k,r` (ISO, Creo) and
//! SOLIDWORKS CAM's `CIRCLE/xc,yc,zc,i,j,k` (no radius) turn counter-clockwise about (i,j,k), and
//! its `.clt`'s `CIRCLE/xc,yc,zc,i,j,k,r,CLOCKWISE|COUNTERCLOCKWISE` as the word says, seen from
//! the axis' tip;
//! NX's eleven-number `CIRCLE/xc,yc,zc,i,j,k,r,tol,ratio,d,e` turns clockwise about it (NX's own
//! definition, and NCL's APT reader `aptsrc.f`: "11 parameter UG circle for which positive rotation
//! is clockwise"). Other counts are refused.

use super::cl::{parse_field, unit_tool_axis};
use super::lex::{excerpt, Diags};
use super::{ArcSpec, Block, Feed, FeedMode, Motion, Orientation, Plane, Targets};
use crate::units::MM;

/// Millimetres per inch (`UNITS/INCHES`, `FEDRAT/IPM`).
const MM_PER_INCH: f64 = 25.4;

/// A part larger than this (mm, 4 m: beyond the travels of the machines CAM writes five-axis
/// programs for) in a program that says inches suggests its numbers are millimetres.
const LARGEST_PART_MM: f64 = 4000.0;

/// The longest statement, continuation lines included, in bytes: a CLDATA record is short, so a
/// longer one is damage (or a `$` on every line), refused rather than held.
const MAX_STATEMENT_BYTES: usize = 64 * 1024;

/// Whether a line of cutter-location data is an APT statement (a major word such as `GOTO/`,
/// `RAPID`, `PARTNO`, or a `$$` comment) rather than a plain `x y z i j k` row.
pub(crate) fn is_apt_line(t: &str) -> bool {
    if t.starts_with("$$") {
        return true;
    }
    let (word, rest) = major_word(t);
    word.starts_with(|c: char| c.is_ascii_alphabetic()) && (rest.starts_with('/') || BARE.contains(&word.to_ascii_uppercase().as_str()))
}

/// Whether a line is an APT `GOTO/` (a motion statement no NC dialect writes), for the dialect's guess.
pub(crate) fn is_goto(l: &str) -> bool {
    let (word, rest) = major_word(l.trim_start());
    word.eq_ignore_ascii_case("GOTO") && rest.starts_with('/')
}

/// A statement's major word as written (letters, digits, `_`, `-`: `GOTO`, `END-OF-PATH`,
/// `CSI_SET_FLUTE_LENGTH`) and what follows it, from its first non-blank.
fn major_word(s: &str) -> (&str, &str) {
    let end = s.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '-')).unwrap_or(s.len());
    (&s[..end], s[end..].trim_start())
}

/// Whether a line reads as an APT statement of its own: a major word (a letter first) and its `/`,
/// or one of the major words written without one.
fn looks_like_statement(l: &str) -> bool {
    let (word, rest) = major_word(l.trim_start());
    word.starts_with(|c: char| c.is_ascii_alphabetic()) && (rest.starts_with('/') || BARE.iter().any(|b| word.eq_ignore_ascii_case(b)))
}

/// Major words written without a slash, as the first statement of a file may be.
const BARE: [&str; 13] = ["RAPID", "FINI", "END", "STOP", "OPSTOP", "PARTNO", "PPRINT", "REMARK", "INSERT", "MULTAX", "GOHOME", "END-OF-PATH", "TOOL"];

/// A `CIRCLE/` waiting for the `GOTO/` that ends it.
#[derive(Debug, Clone, Copy)]
struct Circle {
    centre: [f64; 3],
    plane: Plane,
    ccw: bool,
    /// None: the distance from the centre to the arc's start (SOLIDWORKS CAM writes no radius).
    radius: Option<f64>,
    line: usize,
    column: usize,
}

/// Whether a `CYCLE/` is in force, and whether it is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum CycleState {
    Off,
    /// A cycle that is not read is in force: its GOTOs are hole positions, refused with it.
    Unread,
}

/// The APT reader, fed one line at a time.
#[derive(Debug, Clone)]
pub(crate) struct AptReader {
    orientation: Orientation,
    /// A statement continued (`$`): its text so far, line and column.
    pending: Option<(String, usize, usize)>,
    /// A `$$` comment continued (`$` at its end, as Creo writes its `$$->` records over lines).
    comment_continues: bool,
    /// Millimetres per program unit.
    unit: f64,
    /// The unit the user imposed (`--units`): UNITS/ and FEDRAT/IPM are then noted, not obeyed.
    forced: Option<super::LengthUnit>,
    /// Where the program said UNITS/INCHES (line, column), for the size check at its end.
    inches_at: Option<(usize, usize)>,
    /// The extent of the tool tips read (mm): lowest and highest of each axis.
    extent: Option<([f64; 3], [f64; 3])>,
    feed: f64,
    /// Whether a FEDRAT has been read (else the default feed applies, with a warning once).
    fedrat: bool,
    rapid: bool,
    /// MULTAX as last written (None: never, as NX writes none).
    multax: Option<bool>,
    tool_axis: [f64; 3],
    /// The tool tip (mm) after the last motion.
    at: Option<[f64; 3]>,
    circle: Option<Circle>,
    events: Vec<String>,
    /// The unit of `ROTABL/`'s angles (`--cl-angles`).
    angles: super::AngleUnit,
    /// The table's turn from `ROTABL/` (A, B, C, rad, absolute): the GOTOs are in the part turned by it.
    table: [f64; 3],
    /// Where the last ROTABL was read, and the TLAXIS/ given (line, column, axis), for the check
    /// that the turned table puts the tool where TLAXIS says.
    rotabl_at: (usize, usize),
    tlaxis: Option<(usize, usize, [f64; 3])>,
    /// The table turn and TLAXIS have been checked against each other since either changed.
    frame_checked: bool,
    /// `CYCLE/` state: the GOTOs of a cycle that is not read are the holes it drills, not motion.
    cycle: CycleState,
    /// Pro/NC's contour points under CUTCOM are the part's profile, not the tool centre.
    on_profile: bool,
    /// CUTCOM's note has been given.
    cutcom_noted: bool,
    /// Where the latest event was read.
    event_at: (usize, usize),
    finished: bool,
}

impl AptReader {
    pub(crate) fn new(default_feed_mm_per_min: f64, orientation: Orientation, forced: Option<super::LengthUnit>, angles: super::AngleUnit) -> Self {
        AptReader {
            orientation,
            pending: None,
            comment_continues: false,
            unit: forced.map_or(1.0, |u| u.metres() / MM),
            forced,
            inches_at: None,
            extent: None,
            feed: default_feed_mm_per_min,
            fedrat: false,
            rapid: false,
            multax: None,
            tool_axis: [0.0, 0.0, 1.0],
            at: None,
            circle: None,
            events: Vec::new(),
            angles,
            table: [0.0; 3],
            rotabl_at: (0, 0),
            tlaxis: None,
            frame_checked: false,
            cycle: CycleState::Off,
            cutcom_noted: false,
            on_profile: false,
            event_at: (0, 0),
            finished: false,
        }
    }

    /// Read one line: a statement, its start, its continuation or a comment.
    pub(crate) fn line(&mut self, line: usize, l: &str, out: &mut Vec<Block>, diags: &mut Diags) {
        // Pro/NC says where its contour points lie under CUTCOM, in a comment (`$$->`) or a REMARK:
        // `CUTCOM_GEOMETRY_TYPE / OUTPUT_ON_CENTER` (the tool centre) or `OUTPUT_ON_PROFILE` ("the
        // output switches from the center to the edge of the tool", Creo's CL data output help).
        if let Some(k) = memchr::memchr(b'_', l.as_bytes()).and_then(|_| l.find("CUTCOM_GEOMETRY_TYPE")) {
            self.on_profile = l[k..].contains("OUTPUT_ON_PROFILE");
        }
        // A `$$` comment whose line ends in `$` goes on over the next line (Pro/CLfile writes its
        // `$$-> CSYS / ...` record over three such lines); a statement continued stays continued.
        if std::mem::take(&mut self.comment_continues) {
            // Pro/CLfile's go on with numbers; a statement there was meant as one (APT: `$$` makes the
            // rest of the line a comment, its `$` too), and which it is is not read.
            if looks_like_statement(l) {
                diags.error(line, l.len() - l.trim_start().len() + 1, "a statement after a `$$` comment ending in `$`: whether the comment goes on over it (as Pro/CLfile's records do) or it is a statement is not read");
                return;
            }
            self.comment_continues = l.trim_end().ends_with('$');
            return;
        }
        // Literal text (PPRINT, PARTNO, INSERT, REMARK) ending in `$` before a statement: the same.
        if let Some((text, _, _)) = &self.pending {
            let (word, _) = major_word(text.trim_start());
            if ["PPRINT", "PARTNO", "INSERT", "REMARK"].iter().any(|w| word.eq_ignore_ascii_case(w)) && looks_like_statement(l) {
                let word = word.to_ascii_uppercase();
                self.pending = None;
                diags.error(line, l.len() - l.trim_start().len() + 1, format!("a statement after {word} text ending in `$`: whether the text goes on over it or it is a statement is not read"));
                return;
            }
        }
        let code = match l.find("$$") {
            Some(k) => {
                if self.pending.is_none() && l[..k].trim().is_empty() {
                    let comment = l[k + 2..].trim_end();
                    self.comment_continues = comment.ends_with('$') && !comment.ends_with("$$");
                }
                &l[..k]
            }
            None => l,
        };
        let trimmed = code.trim_end();
        let (body, continues) = match trimmed.strip_suffix('$') {
            Some(b) => (b, true),
            None => (trimmed, false),
        };
        let (mut text, at_line, column) = match self.pending.take() {
            Some(p) => p,
            None => {
                if body.trim().is_empty() && !continues {
                    return;
                }
                let column = l[..l.len() - l.trim_start().len()].chars().count() + 1;
                (String::new(), line, column)
            }
        };
        if text.len() + body.len() > MAX_STATEMENT_BYTES {
            diags.error(at_line, column, format!("statement longer than {MAX_STATEMENT_BYTES} bytes over its continuation lines: not read"));
            return;
        }
        text.push_str(body);
        if continues {
            self.pending = Some((text, at_line, column));
            return;
        }
        self.statement(at_line, column, text.trim(), out, diags);
    }

    /// A block of the statement at `line:column` that moves nothing yet: tool-tip poses (always under
    /// TCPM, no datum), the orientation mode, and the events read since the last block.
    fn block(&mut self, line: usize, column: usize) -> Block {
        Block {
            line,
            column,
            number: None,
            motion: Motion::Linear,
            targets: Targets::default(),
            arc: None,
            feed: None,
            tcp: true,
            datum: [0.0; 3],
            orientation: self.orientation,
            events: std::mem::take(&mut self.events),
            dwell_s: None,
            tolerance: Default::default(),
            // CL data are in the part's frame; where the part lies on the machine is the operator's
            // set-up (a work offset or preset), which the file never states.
            offset_assumed: true,
            exact: crate::program::Exact::Blend,
        }
    }

    /// The input has ended: a continued statement or a circle left open is a defect; events after the
    /// last motion in a file with neither FINI nor END-OF-PATH are a block of their own, at the last.
    pub(crate) fn finish(&mut self, out: &mut Vec<Block>, diags: &mut Diags) {
        if !self.events.is_empty() {
            let (line, column) = self.event_at;
            out.push(self.block(line, column));
        }
        if let Some((_, line, column)) = self.pending.take() {
            diags.error(line, column, "the program ends inside this statement (its last line ends in '$')");
        }
        if let Some(c) = self.circle.take() {
            diags.error(c.line, c.column, "CIRCLE without the GOTO that ends it");
        }
        // A program in inches whose part is larger than any machine's table: say so, and how to
        // read it in millimetres if its numbers are (never guessed).
        if let (Some((line, col)), Some((lo, hi))) = (self.inches_at, self.extent) {
            let span = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
            if span > LARGEST_PART_MM {
                diags.warning(
                    line,
                    col,
                    format!("UNITS/INCHES: the tool tips span {:.1} m in inches, more than any machine's travel; if the file's numbers are millimetres, read it with --units mm", span / 1000.0),
                );
            }
        }
    }

    fn statement(&mut self, line: usize, col: usize, s: &str, out: &mut Vec<Block>, diags: &mut Diags) {
        // The major word, then `/` and its arguments, or free text (`PARTNO name`).
        let (w, rest) = major_word(s);
        let (word, args) = (w.to_ascii_uppercase(), rest.strip_prefix('/'));
        if self.finished {
            diags.error(line, col, format!("{} after FINI (the end of the CL data)", excerpt(&word)));
            return;
        }
        let values = |diags: &mut Diags| -> Option<(Vec<f64>, Vec<String>)> {
            let (mut nums, mut minors) = (Vec::new(), Vec::new());
            let fields: Vec<&str> = args.unwrap_or("").split(',').map(str::trim).collect();
            for (k, &f) in fields.iter().enumerate() {
                // A trailing comma ends the list (SOLIDWORKS CAM's `CUTTER/ 6.0,...,102.0,`); an
                // empty field between two is a value missing, which is not read as a shift of the rest.
                if f.is_empty() && fields[k + 1..].iter().any(|g| !g.is_empty()) {
                    diags.error(line, col, format!("{word}: field {} is empty (two commas with nothing between): not read", k + 1));
                    return None;
                }
                if f.is_empty() {
                    continue;
                }
                match parse_field(f) {
                    Some(v) => nums.push(v),
                    None if is_minor_word(f) => minors.push(f.to_ascii_uppercase()),
                    None => {
                        diags.error(line, col, format!("{word}: expected a number or a minor word, found '{}'", excerpt(f)));
                        return None;
                    }
                }
            }
            Some((nums, minors))
        };
        let circle_open = self.circle.is_some();
        match word.as_str() {
            // The holes of a cycle that is not read: refused with the cycle, where it stands.
            "GOTO" | "FROM" | "GODLTA" if self.cycle == CycleState::Unread => {}
            "GOTO" | "FROM" | "GODLTA" => {
                let Some((v, minors)) = values(diags) else { return };
                if !minors.is_empty() {
                    diags.error(line, col, format!("{word}/ with '{}': only numbers are read", minors[0]));
                    return;
                }
                // Under a table turned by ROTABL/ the numbers are in the turned part (see `turned`).
                let turn = table_rotation(&self.table);
                let turned = turn != nalgebra::Matrix3::identity();
                let to_part = |p: [f64; 3]| -> [f64; 3] { (turn * nalgebra::Vector3::from(p)).into() };
                let (tip, axis) = match (word.as_str(), v.len(), self.at) {
                    (_, 3 | 6, _) if word != "GODLTA" => (to_part([v[0], v[1], v[2]].map(|c| c * self.unit)), v.get(3..6).map(|a| to_part([a[0], a[1], a[2]]))),
                    ("GODLTA", 3, Some(p)) => {
                        let d = to_part([v[0], v[1], v[2]].map(|c| c * self.unit));
                        ([p[0] + d[0], p[1] + d[1], p[2] + d[2]], None)
                    }
                    ("GODLTA", 1, Some(p)) => (std::array::from_fn(|k| p[k] + self.tool_axis[k] * v[0] * self.unit), None),
                    ("GODLTA", 1 | 3, None) => {
                        diags.error(line, col, "GODLTA before any position (GOTO or FROM): no point to move from");
                        return;
                    }
                    (_, n, _) => {
                        let want = if word == "GODLTA" { "dx,dy,dz or a distance along the tool axis" } else { "x,y,z or x,y,z,i,j,k" };
                        diags.error(line, col, format!("{word}/ expects {want}: found {n} numbers"));
                        return;
                    }
                };
                if axis.is_some() && self.multax == Some(false) {
                    diags.error(line, col, format!("{word}/ with a tool axis under MULTAX/OFF"));
                    return;
                }
                if let Some(a) = axis {
                    let Some(unit) = unit_tool_axis(a, line, col, diags) else { return };
                    self.tool_axis = unit;
                } else if turned {
                    // A turned table presents its Z to the spindle: the tool lies along it.
                    self.tool_axis = to_part([0.0, 0.0, 1.0]);
                    if !std::mem::replace(&mut self.frame_checked, true) {
                        self.check_turn(diags);
                    }
                }
                if word == "FROM" && (self.at.is_some() || circle_open) {
                    diags.error(line, col, "FROM after the first position: a start point only opens the CL data");
                    return;
                }
                let circle = self.circle.take();
                if circle.is_some() && word != "GOTO" {
                    diags.error(line, col, format!("{word} after CIRCLE: the circle's end must be a GOTO"));
                    return;
                }
                let rapid = std::mem::take(&mut self.rapid);
                let (mut motion, mut arc) = (if rapid || word == "FROM" { Motion::Rapid } else { Motion::Linear }, None);
                if let (Some(c), true) = (&circle, rapid) {
                    // Pro/NC: with ARC_FEED 0 "the RAPID statement is output before the CIRCLE
                    // statement": an arc at rapid, which no control's G00 makes.
                    diags.error(line, col, format!("RAPID before the CIRCLE of line {}: an arc at rapid is not read", c.line));
                    return;
                }
                if let Some(c) = circle {
                    let Some(start) = self.at else {
                        diags.error(c.line, c.column, "CIRCLE before any position: the arc has no start");
                        return;
                    };
                    // The circle is in the turned part's frame, as its centre and axis were written.
                    let local = |p: [f64; 3]| -> [f64; 3] { (turn.transpose() * nalgebra::Vector3::from(p)).into() };
                    let (i, j, _) = c.plane.axes();
                    let r = |p: &[f64; 3]| ((p[i] - c.centre[i]).powi(2) + (p[j] - c.centre[j]).powi(2)).sqrt();
                    let (r0, r1) = (r(&local(start)), r(&local(tip)));
                    let radius = c.radius.unwrap_or(r0);
                    let tol = 1e-3 * radius.max(1.0) + 1e-3;
                    if !(radius > 1e-6) || (r0 - radius).abs() > tol || (r1 - radius).abs() > tol {
                        diags.error(
                            line,
                            col,
                            format!("CIRCLE of line {} (radius {:.4} mm): the arc's start and end lie {:.4} and {:.4} mm from its centre", c.line, radius, r0, r1),
                        );
                        return;
                    }
                    motion = if c.ccw { Motion::ArcCcw } else { Motion::ArcCw };
                    let frame = turned.then(|| ArcSpec::frame_of(&turn));
                    arc = Some(ArcSpec { plane: c.plane, centre: to_part(c.centre).map(|v| v * MM), extra_turns: 0, frame });
                }
                if motion != Motion::Rapid && self.at.is_some() && !std::mem::replace(&mut self.fedrat, true) {
                    diags.warning(line, col, format!("{word} before any FEDRAT/: at the default CL feed, {} mm/min", self.feed));
                }
                self.at = Some(tip);
                self.extent = Some(match self.extent {
                    None => (tip, tip),
                    Some((lo, hi)) => (std::array::from_fn(|k| lo[k].min(tip[k])), std::array::from_fn(|k| hi[k].max(tip[k]))),
                });
                out.push(Block {
                    motion,
                    targets: Targets { x: Some(tip[0] * MM), y: Some(tip[1] * MM), z: Some(tip[2] * MM), tool_axis: Some(self.tool_axis), ..Targets::default() },
                    arc: arc.map(Box::new),
                    feed: Some(Feed { value_per_min: self.feed, rotary_per_min: self.feed, mode: FeedMode::PerMinute }),
                    ..self.block(line, col)
                });
                return;
            }
            _ if circle_open => {
                diags.error(line, col, format!("{} after CIRCLE: the circle's end must be the next statement, a GOTO", excerpt(&word)));
                self.circle = None;
                return;
            }
            "RAPID" => match values(diags) {
                Some((v, m)) if v.is_empty() && m.is_empty() => self.rapid = true,
                Some(_) => diags.error(line, col, "RAPID with words: only RAPID (the next motion at the rapid rate) is read"),
                None => {}
            },
            "FEDRAT" => {
                let Some((v, minors)) = values(diags) else { return };
                let mut per_unit = self.unit;
                for m in &minors {
                    match m.as_str() {
                        "MMPM" => per_unit = 1.0,
                        // Under --units, the file's numbers are in that unit, its feeds per minute too.
                        "IPM" if self.forced.is_some() => per_unit = self.unit,
                        "IPM" => per_unit = MM_PER_INCH,
                        "MMPR" | "IPR" => {
                            diags.error(line, col, format!("FEDRAT/{m}: a feed per revolution is not read"));
                            return;
                        }
                        _ => {
                            diags.error(line, col, format!("FEDRAT/ with '{m}': expected MMPM or IPM"));
                            return;
                        }
                    }
                }
                match v.as_slice() {
                    [f] if *f > 0.0 => {
                        self.feed = f * per_unit;
                        self.fedrat = true;
                    }
                    _ => diags.error(line, col, format!("FEDRAT/ expects one positive feed: found {:?}", v)),
                }
            }
            "UNITS" | "UNIT" => {
                let Some((v, minors)) = values(diags) else { return };
                let inch = match (v.len(), minors.first().map(String::as_str)) {
                    (0, Some("MM")) if minors.len() == 1 => false,
                    (0, Some("INCHES" | "INCH")) if minors.len() == 1 => true,
                    _ => return diags.error(line, col, "UNITS/ expects MM or INCHES"),
                };
                match self.forced {
                    Some(u) if (u == super::LengthUnit::Inch) != inch => {
                        diags.warning(line, col, format!("UNITS/{}: the program's numbers are read in {} (--units)", minors[0], u.name()))
                    }
                    Some(_) => {}
                    None => {
                        self.unit = if inch { MM_PER_INCH } else { 1.0 };
                        self.inches_at = inch.then_some((line, col));
                    }
                }
            }
            "MULTAX" => {
                // GOTO's count says whether it carries the tool axis; MULTAX only announces it.
                let Some((v, minors)) = values(diags) else { return };
                match (v.len(), minors.first().map(String::as_str), minors.len()) {
                    (0, None | Some("ON"), 0 | 1) => self.multax = Some(true),
                    (0, Some("OFF"), 1) => self.multax = Some(false),
                    _ => diags.error(line, col, "MULTAX expects nothing, ON or OFF"),
                }
            }
            "TLAXIS" => {
                let Some((v, minors)) = values(diags) else { return };
                if v.len() != 3 || !minors.is_empty() {
                    diags.error(line, col, "TLAXIS/ expects a tool axis i,j,k (a fixed direction; other forms are not read)");
                    return;
                }
                if let Some(unit) = unit_tool_axis([v[0], v[1], v[2]], line, col, diags) {
                    self.tool_axis = unit;
                    self.tlaxis = Some((line, col, unit));
                    self.frame_checked = false;
                }
            }
            "CIRCLE" => {
                let Some((v, minors)) = values(diags) else { return };
                if minors.iter().any(|m| m == "TIMES") {
                    diags.error(line, col, "CIRCLE/ with TIMES: a helix of several turns is not read");
                    return;
                }
                // Counter-clockwise about the axis, but for NX's eleven numbers (see the module's doc).
                let sense = match minors.as_slice() {
                    [] => None,
                    [w] if w == "COUNTERCLOCKWISE" || w == "CCLW" => Some(1.0),
                    [w] if w == "CLOCKWISE" || w == "CLW" => Some(-1.0),
                    _ => {
                        diags.error(line, col, format!("CIRCLE/ with '{}': only CLOCKWISE or COUNTERCLOCKWISE (seen from the axis' tip) is read", minors.join(",")));
                        return;
                    }
                };
                let (radius, about) = match (v.len(), sense) {
                    (6, None) => (None, 1.0),
                    (7, None) => (Some(v[6]), 1.0),
                    // SOLIDWORKS CAM's .clt: the radius, then the sense about (i,j,k) in words.
                    (7, Some(s)) => (Some(v[6]), s),
                    (11, None) => (Some(v[6]), -1.0),
                    _ => {
                        diags.error(line, col, format!("CIRCLE/ expects xc,yc,zc,i,j,k[,r] or NX's eleven numbers: found {} numbers{}", v.len(), if minors.is_empty() { "" } else { " and words" }));
                        return;
                    }
                };
                let norm = (v[3] * v[3] + v[4] * v[4] + v[5] * v[5]).sqrt();
                let axis = [v[3], v[4], v[5]].map(|c| c / norm);
                // Seen from its axis's tip, the tool goes counter-clockwise about (i,j,k).
                let plane = [(Plane::Yz, 0), (Plane::Zx, 1), (Plane::Xy, 2)].into_iter().find(|&(_, k)| norm > 1e-9 && (axis[k].abs() - 1.0).abs() < 1e-9);
                let Some((plane, k)) = plane else {
                    diags.error(line, col, "CIRCLE/ about an axis other than X, Y or Z is not read");
                    return;
                };
                if radius.is_some_and(|r| !(r > 0.0)) {
                    diags.error(line, col, "CIRCLE/ expects a positive radius");
                    return;
                }
                let centre = [v[0], v[1], v[2]].map(|c| c * self.unit);
                self.circle = Some(Circle { centre, plane, ccw: axis[k] * about > 0.0, radius: radius.map(|r| r * self.unit), line, column: col });
            }
            "SPINDL" | "COOLNT" | "LOADTL" | "LOAD" | "SELCTL" | "SELECT" | "STOP" | "OPSTOP" | "END" => {
                self.events.push(s.to_string());
                self.event_at = (line, col);
            }
            // DELAY/t: the tool stands still t seconds (ISO 4343); DELAY/n,REV (spindle turns) is not read.
            "DELAY" => {
                let Some((v, minors)) = values(diags) else { return };
                match (v.as_slice(), minors.is_empty()) {
                    ([t], true) if *t >= 0.0 => out.push(Block { dwell_s: Some(*t), ..self.block(line, col) }),
                    _ => diags.error(line, col, "DELAY/ expects a time in seconds (DELAY/n,REV, in spindle turns, is not read)"),
                }
            }
            // The end of the program or of a tool path: the events after its last motion (spindle and
            // coolant off) are a block of their own, not lost with no block to carry them.
            "FINI" | "END-OF-PATH" => {
                if !self.events.is_empty() {
                    out.push(self.block(line, col));
                }
                self.finished |= word == "FINI";
            }
            "PARTNO" | "PPRINT" | "TPRINT" | "REMARK" | "MACHIN" | "MODE" | "CUTTER" | "TLDATA" | "TOOL" | "PAINT" | "DISPLY" | "SEQNO"
            | "CLRSRF" | "OPNAME" | "OPERATION" | "AUTOPS" => {}
            // SOLIDWORKS CAM's operation brackets (a feature's name) and the stock's box: no motion.
            "OPFEATSTART" | "OPFEATEND" | "BOX" => {}
            // SOLIDWORKS CAM's kind of the moves that follow (lead-in, link, lead-out): no motion.
            "MOVE_ATTRIB" => {
                let Some((v, minors)) = values(diags) else { return };
                if !v.is_empty() || !minors.iter().all(|m| ["LEADIN", "LEADOUT", "LINK", "CUT", "END_ATTRIB"].contains(&m.as_str())) {
                    diags.error(line, col, "MOVE_ATTRIB/ expects LEADIN, LINK, LEADOUT or CUT, then END_ATTRIB");
                }
            }
            // ROTABL/a,AAXIS|BAXIS|CAXIS[,TABLE][,CCLW] (ICAM's vocabulary): the table turns to a
            // (INCR: by a), and the GOTOs that follow are in the part so turned, their tool along its Z.
            "ROTABL" => {
                let Some((v, minors)) = values(diags) else { return };
                let axis = minors.iter().find_map(|m| ["AAXIS", "BAXIS", "CAXIS"].iter().position(|a| a == m));
                let known = minors.iter().all(|m| ["AAXIS", "BAXIS", "CAXIS", "TABLE", "CCLW", "INCR", "ATANGL"].contains(&m.as_str()));
                let (Some(k), [a], true) = (axis, v.as_slice(), known) else {
                    let why = if minors.iter().any(|m| m == "CLW") {
                        "CLW (whether it negates the angle or only picks the way round differs between APT writers)"
                    } else if minors.iter().any(|m| m == "RAM" || m == "HEAD") {
                        "a head's turn"
                    } else {
                        "other forms"
                    };
                    diags.error(line, col, format!("ROTABL/ expects an angle and AAXIS, BAXIS or CAXIS [,TABLE] [,CCLW]: {why} not read"));
                    return;
                };
                let a = a * self.angles.radians();
                let was = self.table[k];
                self.table[k] = if minors.iter().any(|m| m == "INCR") { was + a } else { a };
                if was != 0.0 || self.table[k] != 0.0 {
                    self.rotabl_at = (line, col);
                }
                self.frame_checked = false;
                if self.table.iter().filter(|t| t.sin().abs() > 1e-9 || t.cos() < 0.0).count() > 1 {
                    diags.error(line, col, "ROTABL/: the table turned about two axes at once (the order of the turns is not established)");
                    self.table = [0.0; 3];
                }
            }
            // CYCLE/ON ... CYCLE/OFF: a drilling (or other) cycle at each GOTO between them.
            "CYCLE" => {
                let fields: Vec<&str> = args.unwrap_or("").split(',').map(str::trim).filter(|f| !f.is_empty()).collect();
                match fields.as_slice() {
                    [w] if w.eq_ignore_ascii_case("OFF") => self.cycle = CycleState::Off,
                    // SOLIDWORKS CAM writes ON before the cycle's definition.
                    [w] if w.eq_ignore_ascii_case("ON") => {}
                    _ => {
                        let kind = excerpt(fields.first().copied().unwrap_or(""));
                        let bad = fields.iter().position(|f| parse_field(f).is_none() && !is_minor_word(f));
                        let why = match bad {
                            Some(k) => format!("field {} '{}' is neither a number nor a word (a comma missing?)", k + 1, excerpt(fields[k])),
                            None => "cycles in CL data are not read".to_string(),
                        };
                        diags.error(line, col, format!("CYCLE/{kind}: {why}; the holes at its GOTOs up to CYCLE/OFF are not read"));
                        self.cycle = CycleState::Unread;
                    }
                }
            }
            // A vocabulary entry (post-processor word and its number, Creo's GPOST table): no motion.
            "PPWORD" => {}
            // Pro/CLfile's output frame (3 x 4, rows) against the model: the GOTOs are already in it
            // (Creo's two CL files of one tool path differ by CAMERA's translation exactly), so it is
            // where the program's coordinates are, not a transform to apply.
            "CAMERA" => {
                let Some((v, minors)) = values(diags) else { return };
                if v.len() != 12 || !minors.is_empty() {
                    diags.error(line, col, format!("CAMERA/ expects a 3 x 4 matrix (12 numbers): found {}", v.len()));
                }
            }
            "MSYS" => {
                let Some((v, _)) = values(diags) else { return };
                let axes = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
                if v.len() != 9 || v[3..].iter().zip(axes).any(|(a, b)| (a - b).abs() > 1e-6) {
                    diags.error(line, col, "MSYS/: a part frame (MCS) turned against the machine's is not read (its X and Y axes must be the machine's)");
                }
            }
            // SOLIDWORKS CAM's tool data (flute and extension lengths).
            w if w.starts_with("CSI_SET_") => {}
            // CL data are cutter locations (the tool centre's path): CUTCOM only hands the control's
            // compensation the register's wear (a worn or reground tool), which no program states.
            "CUTCOM" => {
                let Some((v, minors)) = values(diags) else { return };
                match (v.as_slice(), minors.as_slice()) {
                    ([], [w]) if w == "OFF" || w == "ON" => {}
                    ([] | [_], [w]) if (w == "LEFT" || w == "RIGHT") && self.on_profile => {
                        diags.error(line, col, format!("CUTCOM/{w} with Pro/NC's CUTCOM_GEOMETRY_TYPE OUTPUT_ON_PROFILE: the GOTOs are the part's profile, which the control offsets by the tool's radius; not read"));
                    }
                    ([] | [_], [w]) if w == "LEFT" || w == "RIGHT" => {
                        if !std::mem::replace(&mut self.cutcom_noted, true) {
                            diags.warning(line, col, format!("CUTCOM/{w}: the GOTOs are the tool centre's path; the control's compensation adds only its register's wear, not modelled"));
                        }
                    }
                    _ => diags.error(line, col, "CUTCOM/ expects LEFT, RIGHT [,register], ON or OFF"),
                }
            }
            // SOLIDWORKS CAM's working plane (a 3 x 4 matrix [R | t], rows): its Z column is the tool
            // axis of a 3+2 operation, in the part's frame, in which the GOTOs stay (TRNTYP/WORLD).
            "CSYS" => {
                let Some((v, minors)) = values(diags) else { return };
                if v.len() != 12 || !minors.is_empty() {
                    diags.error(line, col, format!("CSYS/ expects a 3 x 4 matrix (12 numbers): found {}", v.len()));
                    return;
                }
                let r = nalgebra::Matrix3::new(v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10]);
                if (r * r.transpose() - nalgebra::Matrix3::identity()).abs().max() > 1e-5 || r.determinant() < 0.0 {
                    diags.error(line, col, "CSYS/: the matrix is not a rotation (orthonormal, right-handed)");
                } else if [v[3], v[7], v[11]].iter().any(|t| t.abs() > 1e-9) {
                    diags.error(line, col, "CSYS/ with a translation: whether the GOTOs are moved by it is not established (only an origin at the part's is read)");
                } else {
                    self.tool_axis = [v[2], v[6], v[10]];
                }
            }
            "TRNTYP" => {
                let Some((v, minors)) = values(diags) else { return };
                if minors != ["WORLD"] || v.iter().any(|a| *a != 0.0) {
                    diags.error(line, col, "TRNTYP/: only WORLD,0,0,0 (the GOTOs in the part's frame) is read");
                }
            }
            // Text handed to the post: a note (a holder, the stock's size) is kept as an event; NC
            // code the post would pass to the control (G01 ..., M6, X10., and a control's words in
            // capitals, `L Z+100 R0 FMAX M91`, `TRAORI`, `CYCL DEF 7.0`) is not read. A note is text
            // in brackets or a comment's, or text with small letters (SOLIDWORKS CAM's
            // `[HOLDER=...] 6MM CRB`, `Stock Size X95. Y150.`).
            "INSERT" => {
                let text = args.unwrap_or(rest).trim();
                let b = text.as_bytes();
                let word = b.first().is_some_and(|c| c.is_ascii_alphabetic()) && b.get(1).is_some_and(|c| c.is_ascii_digit() || b"+-.".contains(c)) || text.starts_with('%');
                let note = text.starts_with(['[', '(', ';']) || text.bytes().any(|c| c.is_ascii_lowercase());
                let code = word || !note && text.bytes().any(|c| c.is_ascii_alphabetic());
                if code {
                    diags.error(line, col, format!("INSERT/ passes NC code to the control ('{}'): not read", excerpt(text)));
                } else {
                    self.events.push(s.to_string());
                    self.event_at = (line, col);
                }
            }
            "" => diags.error(line, col, format!("expected an APT statement (a major word such as GOTO/), found '{}'", excerpt(s))),
            _ => diags.error(line, col, format!("APT statement {} is not read", excerpt(&word))),
        }
    }
}

/// Whether a statement's field is a minor word (`AAXIS`, `END_ATTRIB`): a letter, then letters,
/// digits or `_`.
fn is_minor_word(f: &str) -> bool {
    f.as_bytes().first().is_some_and(u8::is_ascii_alphabetic) && f.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
}

/// The rotation of a table turned by `t` (A, B, C about +X, +Y, +Z, rad; at most one of them, as
/// ROTABL/ refuses two): a point written in the turned part is at `R p` in the part.
fn table_rotation(t: &[f64; 3]) -> nalgebra::Matrix3<f64> {
    let r = |axis: nalgebra::Unit<nalgebra::Vector3<f64>>, a: f64| if a == 0.0 { nalgebra::Matrix3::identity() } else { *nalgebra::Rotation3::from_axis_angle(&axis, a).matrix() };
    r(nalgebra::Vector3::x_axis(), t[0]) * r(nalgebra::Vector3::y_axis(), t[1]) * r(nalgebra::Vector3::z_axis(), t[2])
}

impl AptReader {
    /// The table's turn puts the tool (its Z) where TLAXIS/ says, if it said: else the angles are in
    /// the other unit (SOLIDWORKS CAM's radians) or the file contradicts itself; said once per turn.
    fn check_turn(&self, diags: &mut Diags) {
        let Some((tl, tc, want)) = self.tlaxis else { return };
        let along = |turn: nalgebra::Matrix3<f64>| (turn * nalgebra::Vector3::z()).angle(&nalgebra::Vector3::from(want));
        if along(table_rotation(&self.table)) < 1e-4 {
            return;
        }
        let (line, col) = self.rotabl_at;
        let other = if self.angles == super::AngleUnit::Rad { super::AngleUnit::Deg } else { super::AngleUnit::Rad };
        let t = table_rotation(&self.table.map(|a| a / self.angles.radians() * other.radians()));
        let hint = if along(t) < 1e-4 {
            format!("; read in {} (--cl-angles {}) it does", if other == super::AngleUnit::Rad { "radians" } else { "degrees" }, other.name())
        } else {
            String::new()
        };
        let z = table_rotation(&self.table) * nalgebra::Vector3::z();
        diags.error(
            line,
            col,
            format!("ROTABL/: the table so turned puts the tool along ({:.4},{:.4},{:.4}) in the part, not along TLAXIS/ of line {tl}:{tc} ({:.4},{:.4},{:.4}){hint}", z.x, z.y, z.z, want[0], want[1], want[2]),
        );
    }
}
