//! URDF in and out (`robot_description`): a machine as the five joints between a `workpiece` link and a
//! `tool` link, so `robot_state_publisher` and 3D viewers move it on our JointState streams.
//!
//! Conventions (REP 103 units: m, rad, s):
//! - The **workpiece** link is the frame the program's coordinates are in; the **tool** link (or
//!   `tool0`) has its origin at the tool tip and its +z along the tool axis, tip to spindle.
//! - The tool pose in the workpiece frame is `T_workpiece^-1 T_tool` (seed 001 eq. 1-2 on the Hermle):
//!   a prismatic joint on the workpiece side moves the tool the other way, so X/Y/Z may sit on either
//!   side, ahead of the rotary joints of their side. Joints above the two links' common ancestor, and
//!   joints on neither path, do not change the tool pose and are ignored.
//! - Joint names give the axis letters: `X`, `x_axis`, `joint_x` (one single-letter part).
//! - URDF's `<limit>` holds position and velocity only; acceleration and jerk come from
//!   `<fiveaxis:limits joint=".." acceleration=".." jerk=".."/>` children of `<robot>` in the
//!   [`NAMESPACE`] namespace, which other URDF readers ignore.

use super::{LinearAxisFile, Machine, MachineError, MachineFile, RotaryAxisFile};
use crate::kinematics::Carrier;
use crate::units::{DEG, MM_IN_M, MM_PER_MIN};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::collections::BTreeMap;
use crate::xml::escape;
use std::fmt::Write as _;

/// XML namespace of the `<fiveaxis:limits>` extension element.
pub const NAMESPACE: &str = "urn:fiveaxis:urdf:1";
/// The link whose frame holds the program's coordinates.
pub const WORKPIECE_LINK: &str = "workpiece";
/// Link names taken as the tool frame, in order of preference.
pub const TOOL_LINKS: [&str; 2] = ["tool", "tool0"];
/// How far (rad) the three prismatic axes may be from orthogonal, and the workpiece frame at home from
/// theirs: a hand-written `rpy="0 0 1.5708"` is 3.7e-6 rad from a quarter turn. Within it the linear
/// axes are taken along the workpiece frame's axes (under 10 um over a metre of travel).
pub const ALIGNMENT_TOLERANCE_RAD: f64 = 1e-5;
/// Largest URDF text read (bytes): a machine is a few kB; a robot_description with meshes inline is not
/// one we can use.
pub const MAX_BYTES: usize = 16 << 20;

/// The linear axes' letters, in axis order.
const LINEAR: [char; 3] = ['X', 'Y', 'Z'];

/// Read a URDF as a machine; `origin` names it in errors.
pub fn read(text: &str, origin: &str) -> Result<Machine, MachineError> {
    read_with_file(text, origin).map(|(machine, _)| machine)
}

/// Read a URDF as a machine, with the machine file it amounts to (mm, deg: what `machine show` prints).
pub fn read_with_file(text: &str, origin: &str) -> Result<(Machine, MachineFile), MachineError> {
    let (file, joints) = to_machine_file(text, origin)?;
    let machine = file.build(origin).map_err(|e| match e {
        MachineError::Invalid { name, origin, message } => {
            let which = joints.iter().enumerate().map(|(i, j)| format!("rotary[{i}] is {j}")).collect::<Vec<_>>().join(", ");
            MachineError::Invalid { name, origin, message: format!("{message} ({which})") }
        }
        other => other,
    })?;
    Ok((machine, file))
}

/// The machine file a URDF describes, not yet validated as a machine, and where each rotary joint was
/// found (for messages). Structural and value errors name the line:col, joint and field.
fn to_machine_file(text: &str, origin: &str) -> Result<(MachineFile, Vec<String>), MachineError> {
    let err = |message: String| MachineError::Parse { path: origin.to_string(), message };
    if text.len() > MAX_BYTES {
        return Err(err(format!("{} bytes: a URDF machine is at most {MAX_BYTES} bytes", text.len())));
    }
    let doc = roxmltree::Document::parse(text).map_err(|e| err(format!("not XML: {e}")))?;
    Urdf::parse(&doc).and_then(|u| u.machine_file()).map_err(err)
}

/// One URDF joint as read (home transform from its parent link's frame).
struct Joint<'a> {
    node: roxmltree::Node<'a, 'a>,
    at: String,
    name: &'a str,
    kind: &'a str,
    parent: &'a str,
    child: &'a str,
    origin: Isometry3<f64>,
}

struct Urdf<'a> {
    robot: roxmltree::Node<'a, 'a>,
    doc: &'a roxmltree::Document<'a>,
    links: BTreeMap<&'a str, String>,
    joints: Vec<Joint<'a>>,
    /// Joint index by child link.
    parent_joint: BTreeMap<&'a str, usize>,
}

/// A joint on the path between workpiece and tool, in the world frame at home.
struct PathJoint {
    index: usize,
    table_side: bool,
    /// Position along its side's chain, base outwards.
    depth: usize,
    axis: Vector3<f64>,
    point: Vector3<f64>,
}

/// Components within 1e-12 of zero (mm, or of a unit vector) are rounding from rotations: zero them,
/// so `machine show` prints `[1.0, 0.0, 0.0]` for a quarter turn's axis.
fn tidy(v: Vector3<f64>) -> [f64; 3] {
    v.map(|c| if c.abs() < 1e-12 { 0.0 } else { c }).into()
}

fn pos(doc: &roxmltree::Document, node: roxmltree::Node) -> String {
    let p = doc.text_pos_at(node.range().start);
    format!("line {}:{}", p.row, p.col)
}

fn attr<'a>(doc: &roxmltree::Document, node: roxmltree::Node<'a, 'a>, name: &str) -> Result<&'a str, String> {
    node.attribute(name).ok_or_else(|| format!("{}: <{}> has no `{name}` attribute", pos(doc, node), node.tag_name().name()))
}

fn number(doc: &roxmltree::Document, node: roxmltree::Node, name: &str, text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("{}: <{} {name}=\"{text}\">: expected a finite number", pos(doc, node), node.tag_name().name())),
    }
}

/// An optional `"x y z"` attribute (default when absent): three finite numbers.
fn triple(doc: &roxmltree::Document, node: roxmltree::Node, name: &str, default: [f64; 3]) -> Result<Vector3<f64>, String> {
    let Some(text) = node.attribute(name) else { return Ok(Vector3::from(default)) };
    let parts: Vec<&str> = text.split_whitespace().collect();
    if parts.len() != 3 {
        return Err(format!("{}: <{} {name}=\"{text}\">: expected three numbers", pos(doc, node), node.tag_name().name()));
    }
    let mut v = [0.0; 3];
    for (slot, p) in v.iter_mut().zip(&parts) {
        *slot = number(doc, node, name, p).map_err(|_| format!("{}: <{} {name}=\"{text}\">: expected three finite numbers", pos(doc, node), node.tag_name().name()))?;
    }
    Ok(Vector3::from(v))
}

fn child_element<'a>(node: roxmltree::Node<'a, 'a>, name: &str) -> Option<roxmltree::Node<'a, 'a>> {
    node.children().find(|c| c.is_element() && c.tag_name().name() == name && c.tag_name().namespace().is_none())
}

/// The axis letter a joint name gives: the name itself if one letter, else its one single-letter part.
fn axis_letter(name: &str) -> Option<char> {
    let parts: Vec<&str> = name.split(|c: char| !c.is_ascii_alphanumeric()).filter(|p| p.len() == 1 && p.chars().all(|c| c.is_ascii_alphabetic())).collect();
    match parts.as_slice() {
        [one] => one.chars().next().map(|c| c.to_ascii_uppercase()),
        _ => None,
    }
}

impl<'a> Urdf<'a> {
    fn parse(doc: &'a roxmltree::Document<'a>) -> Result<Urdf<'a>, String> {
        let robot = doc.root_element();
        if robot.tag_name().name() != "robot" || robot.tag_name().namespace().is_some() {
            return Err(format!("{}: the root element is <{}>, a URDF's is <robot>", pos(doc, robot), robot.tag_name().name()));
        }
        let mut links = BTreeMap::new();
        let mut joints = Vec::new();
        let mut parent_joint = BTreeMap::new();
        for node in robot.children().filter(|n| n.is_element() && n.tag_name().namespace().is_none()) {
            match node.tag_name().name() {
                "link" => {
                    let name = attr(doc, node, "name")?;
                    if links.insert(name, pos(doc, node)).is_some() {
                        return Err(format!("{}: a second link named '{name}'", pos(doc, node)));
                    }
                }
                "joint" => {
                    let name = attr(doc, node, "name")?;
                    let kind = attr(doc, node, "type")?;
                    let link_of = |tag: &str| -> Result<&'a str, String> {
                        let e = child_element(node, tag).ok_or_else(|| format!("{}: joint '{name}' has no <{tag}>", pos(doc, node)))?;
                        attr(doc, e, "link")
                    };
                    let (parent, child) = (link_of("parent")?, link_of("child")?);
                    let (xyz, rpy) = match child_element(node, "origin") {
                        Some(o) => (triple(doc, o, "xyz", [0.0; 3])?, triple(doc, o, "rpy", [0.0; 3])?),
                        None => (Vector3::zeros(), Vector3::zeros()),
                    };
                    let origin = Isometry3::from_parts(Translation3::from(xyz), UnitQuaternion::from_euler_angles(rpy.x, rpy.y, rpy.z));
                    if joints.iter().any(|j: &Joint| j.name == name) {
                        return Err(format!("{}: a second joint named '{name}'", pos(doc, node)));
                    }
                    if parent_joint.insert(child, joints.len()).is_some() {
                        return Err(format!("{}: joint '{name}': link '{child}' already has a parent joint (a URDF is a tree)", pos(doc, node)));
                    }
                    joints.push(Joint { node, at: pos(doc, node), name, kind, parent, child, origin });
                }
                _ => {}
            }
        }
        for j in &joints {
            for l in [j.parent, j.child] {
                if !links.contains_key(l) {
                    return Err(format!("{}: joint '{}' names link '{l}', which is not defined", j.at, j.name));
                }
            }
        }
        Ok(Urdf { robot, doc, links, joints, parent_joint })
    }

    /// Joint indices from the root down to `link`.
    fn chain_to(&self, link: &str) -> Result<Vec<usize>, String> {
        let mut chain = Vec::new();
        let mut at = link;
        while let Some(&j) = self.parent_joint.get(at) {
            if chain.len() > self.joints.len() {
                return Err(format!("{}: joint '{}' closes a loop (a URDF is a tree)", self.joints[j].at, self.joints[j].name));
            }
            chain.push(j);
            at = self.joints[j].parent;
        }
        chain.reverse();
        Ok(chain)
    }

    fn find_link(&self, names: &[&str]) -> Result<&'a str, String> {
        names.iter().find_map(|n| self.links.get_key_value(*n).map(|(k, _)| *k)).ok_or_else(|| {
            format!(
                "no link named {}: fiveaxis takes the tool pose between link '{WORKPIECE_LINK}' (program coordinates) and link 'tool' (origin at the tool tip, +z tip to spindle); links: {}",
                names.iter().map(|n| format!("'{n}'")).collect::<Vec<_>>().join(" or "),
                self.links.keys().copied().collect::<Vec<_>>().join(", ")
            )
        })
    }

    /// The `<fiveaxis:limits>` of a joint: (acceleration, jerk), SI.
    fn extension_limits(&self, joint: &Joint) -> Result<(f64, f64), String> {
        let doc = self.doc;
        let mut found = None;
        for e in self.robot.children().filter(|n| n.is_element() && n.tag_name().namespace() == Some(NAMESPACE) && n.tag_name().name() == "limits") {
            if attr(doc, e, "joint")? == joint.name {
                if found.is_some() {
                    return Err(format!("{}: a second <fiveaxis:limits> for joint '{}'", pos(doc, e), joint.name));
                }
                let a = number(doc, e, "acceleration", attr(doc, e, "acceleration")?)?;
                let j = number(doc, e, "jerk", attr(doc, e, "jerk")?)?;
                for (what, v) in [("acceleration", a), ("jerk", j)] {
                    if v <= 0.0 {
                        return Err(format!("{}: <fiveaxis:limits joint=\"{}\" {what}=\"{v}\">: must be positive", pos(doc, e), joint.name));
                    }
                }
                found = Some((a, j));
            }
        }
        found.ok_or_else(|| {
            format!(
                "{}: joint '{}': no acceleration and jerk limits (URDF's <limit> has only velocity): add <fiveaxis:limits joint=\"{}\" acceleration=\"..\" jerk=\"..\"/> (m/s^2 and m/s^3, or rad/s^2 and rad/s^3) to <robot>, with xmlns:fiveaxis=\"{NAMESPACE}\"",
                joint.at, joint.name, joint.name
            )
        })
    }

    /// `<limit>`: (lower, upper) when the joint has a range, and velocity, SI.
    fn limits(&self, joint: &Joint) -> Result<(Option<(f64, f64)>, f64), String> {
        let doc = self.doc;
        let l = child_element(joint.node, "limit").ok_or_else(|| format!("{}: joint '{}' ({}) has no <limit>", joint.at, joint.name, joint.kind))?;
        let velocity = number(doc, l, "velocity", attr(doc, l, "velocity")?)?;
        if velocity <= 0.0 {
            return Err(format!("{}: joint '{}' <limit velocity=\"{velocity}\">: must be positive", pos(doc, l), joint.name));
        }
        if joint.kind == "continuous" {
            return Ok((None, velocity));
        }
        let get = |name: &str| -> Result<f64, String> { number(doc, l, name, attr(doc, l, name)?) };
        let (lower, upper) = (get("lower")?, get("upper")?);
        if lower >= upper {
            return Err(format!("{}: joint '{}' <limit lower=\"{lower}\" upper=\"{upper}\">: need lower < upper", pos(doc, l), joint.name));
        }
        Ok((Some((lower, upper)), velocity))
    }

    fn machine_file(&self) -> Result<(MachineFile, Vec<String>), String> {
        let workpiece = self.find_link(&[WORKPIECE_LINK])?;
        let tool = self.find_link(&TOOL_LINKS)?;
        let (to_wp, to_tool) = (self.chain_to(workpiece)?, self.chain_to(tool)?);
        let shared = to_wp.iter().zip(&to_tool).take_while(|(a, b)| a == b).count();
        let root = |link: &'a str, chain: &[usize]| chain.first().map_or(link, |&j| self.joints[j].parent);
        if root(workpiece, &to_wp) != root(tool, &to_tool) {
            return Err(format!("links '{workpiece}' and '{tool}' are not in one tree (no common root link)"));
        }
        // Home poses of every link along both chains, from the common ancestor's frame.
        let mut path = Vec::new();
        let mut home = [Isometry3::identity(); 2];
        for (side, chain) in [&to_wp[shared..], &to_tool[shared..]].into_iter().enumerate() {
            let table_side = side == 0;
            let mut t = Isometry3::identity();
            for (depth, &ji) in chain.iter().enumerate() {
                let j = &self.joints[ji];
                t *= j.origin;
                let movable = match j.kind {
                    "fixed" => false,
                    "prismatic" | "revolute" | "continuous" => true,
                    other => return Err(format!("{}: joint '{}' is {other}: between '{workpiece}' and '{tool}' fiveaxis takes prismatic, revolute, continuous and fixed joints", j.at, j.name)),
                };
                if movable {
                    if child_element(j.node, "mimic").is_some() {
                        return Err(format!("{}: joint '{}' mimics another: a five-axis machine's joints move independently", j.at, j.name));
                    }
                    let axis_node = child_element(j.node, "axis");
                    let local = match axis_node {
                        Some(a) => triple(self.doc, a, "xyz", [1.0, 0.0, 0.0])?,
                        None => Vector3::x(),
                    };
                    let local = local.try_normalize(1e-9).ok_or_else(|| format!("{}: joint '{}' <axis xyz>: a direction must have non-zero length", axis_node.map(|a| pos(self.doc, a)).unwrap_or(j.at.clone()), j.name))?;
                    path.push(PathJoint { index: ji, table_side, depth, axis: t.rotation * local, point: t.translation.vector });
                }
            }
            home[side] = t;
        }
        let [wp, tl] = home;
        let movable: Vec<String> = path.iter().map(|p| format!("'{}' ({})", self.joints[p.index].name, self.joints[p.index].kind)).collect();
        let prismatic: Vec<&PathJoint> = path.iter().filter(|p| self.joints[p.index].kind == "prismatic").collect();
        let rotary: Vec<&PathJoint> = path.iter().filter(|p| self.joints[p.index].kind != "prismatic").collect();
        if prismatic.len() != 3 || !(1..=2).contains(&rotary.len()) {
            return Err(format!(
                "between links '{workpiece}' and '{tool}' there are {} prismatic and {} rotary joints ({}); a five-axis machine has 3 and 2, a four-axis one 3 and 1",
                prismatic.len(),
                rotary.len(),
                if movable.is_empty() { "none".to_string() } else { movable.join(", ") }
            ));
        }
        // Linear axes move ahead of the rotary joints of their side (seed 001 eq. 1: P_M = P_W turned + X).
        for p in &prismatic {
            if let Some(r) = rotary.iter().find(|r| r.table_side == p.table_side && r.depth < p.depth) {
                let (pj, rj) = (&self.joints[p.index], &self.joints[r.index]);
                return Err(format!(
                    "{}: prismatic joint '{}' is carried by rotary joint '{}': fiveaxis models linear axes that move ahead of the rotary axes of their side",
                    pj.at, pj.name, rj.name
                ));
            }
        }
        // The machine frame is the workpiece frame at home; linear axes along its x, y, z.
        let to_machine = wp.inverse();
        let mut linear: [Option<&PathJoint>; 3] = [None, None, None];
        for p in &prismatic {
            let j = &self.joints[p.index];
            let slot = axis_letter(j.name)
                .and_then(|c| LINEAR.iter().position(|&l| l == c))
                .ok_or_else(|| format!("{}: prismatic joint '{}': its name must give the axis letter X, Y or Z (X, x_axis, joint_x)", j.at, j.name))?;
            if linear[slot].is_some() {
                return Err(format!("{}: prismatic joint '{}' is a second {} axis", j.at, j.name, LINEAR[slot]));
            }
            // The tool's motion relative to the workpiece: a table-side slide moves the tool the other way.
            let dir = to_machine.rotation * p.axis * if p.table_side { -1.0 } else { 1.0 };
            let off = (dir - Vector3::ith(slot, 1.0)).norm();
            if off > ALIGNMENT_TOLERANCE_RAD {
                return Err(format!(
                    "{}: prismatic joint '{}' moves the tool along ({:.6}, {:.6}, {:.6}) in the '{workpiece}' frame at home (its `axis`, and for a joint on the workpiece side the opposite): axis {} must move it along +{} (within {ALIGNMENT_TOLERANCE_RAD} rad)",
                    j.at, j.name, dir.x, dir.y, dir.z, LINEAR[slot], LINEAR[slot].to_ascii_lowercase()
                ));
            }
            linear[slot] = Some(p);
        }
        let mut linear_files = Vec::with_capacity(3);
        for (slot, l) in linear.iter().enumerate() {
            let Some(p) = l else { return Err(format!("no prismatic joint for axis {}", LINEAR[slot])) };
            let j = &self.joints[p.index];
            let (range, velocity) = self.limits(j)?;
            let (lower, upper) = range.unwrap_or((0.0, 0.0));
            let (acceleration, jerk) = self.extension_limits(j)?;
            linear_files.push(LinearAxisFile {
                name: LINEAR[slot].to_string(),
                min_mm: lower * MM_IN_M,
                max_mm: upper * MM_IN_M,
                velocity_mm_per_min: velocity / MM_PER_MIN,
                acceleration_mm_per_s2: acceleration * MM_IN_M,
                jerk_mm_per_s3: jerk * MM_IN_M,
            });
        }
        // Rotary slots: document order, but two on one side base outwards (as a machine file lists them).
        let mut rot: Vec<&PathJoint> = rotary.clone();
        rot.sort_by_key(|r| r.index);
        if rot.len() == 2 && rot[0].table_side == rot[1].table_side && rot[0].depth > rot[1].depth {
            rot.swap(0, 1);
        }
        let mut rotary_files = Vec::with_capacity(2);
        let mut places = Vec::with_capacity(2);
        for r in rot {
            let j = &self.joints[r.index];
            let letter = axis_letter(j.name).ok_or_else(|| format!("{}: rotary joint '{}': its name must give the axis letter (A, a_axis, joint_b)", j.at, j.name))?;
            let (range, velocity) = self.limits(j)?;
            let (acceleration, jerk) = self.extension_limits(j)?;
            let axis = to_machine.rotation * r.axis;
            let center = to_machine * nalgebra::Point3::from(r.point);
            rotary_files.push(RotaryAxisFile {
                name: letter.to_string(),
                carrier: if r.table_side { Carrier::Table } else { Carrier::Head },
                axis: tidy(axis),
                center_mm: tidy(center.coords * MM_IN_M),
                min_deg: range.map(|(lo, _)| lo / DEG),
                max_deg: range.map(|(_, hi)| hi / DEG),
                velocity_deg_per_s: velocity / DEG,
                acceleration_deg_per_s2: acceleration / DEG,
                jerk_deg_per_s3: jerk / DEG,
                program_unit: None,
            });
            places.push(format!("joint '{}' at {}", j.name, j.at));
        }
        let tool_home = to_machine * tl;
        let name = self.robot.attribute("name").unwrap_or("urdf").to_string();
        let file = MachineFile {
            description: format!("{name}, read from URDF"),
            name,
            maker: None,
            model: None,
            control: None,
            dialect: None,
            machine_coordinates: None,
            m_functions: Vec::new(),
            hal_pins: Default::default(),
            canned_cycles: None,
            arc_radius_tolerance_mm: None,
            cycle19_spatial: false,
            tcp_at_start: false,
            inch_basic_system: false,
            power_on_motion: None,
            tcp_rotary_feed: None,
            tool_length_const: None,
            tnc_inch_feed: None,
            decimal_point_input: None,
            cycles: Vec::new(),
            swivel: None,
            quill: None,
            tool_axis: tidy(tool_home.rotation * Vector3::z()),
            tool_tip_mm: tidy(tool_home.translation.vector * MM_IN_M),
            contour_tolerance_mm: None,
            contour_tolerance_deg: None,
            linear: linear_files,
            rotary: rotary_files,
        };
        Ok((file, places))
    }
}

/// Shortest text that reads back as the same f64 (Rust's `Display`, never an exponent).
fn f(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v}")
    }
}

fn v3(v: &Vector3<f64>) -> String {
    format!("{} {} {}", f(v.x), f(v.y), f(v.z))
}

/// Write a machine as URDF: a `base` link (the machine frame), the table joints base outwards down to
/// `workpiece`, and X, Y, Z then the head joints down to `tool`. Every link frame is parallel to the
/// machine frame at home. Joints are named after the axes, as our JointStates name them, and listed in
/// the machine's axis order (which is the order [`read`] gives back).
pub fn write(machine: &Machine) -> String {
    let chain = &machine.chain;
    let mut out = String::new();
    let _ = writeln!(out, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        out,
        "<!-- {}. Written by fiveaxis from machine '{}'. The tool pose in link 'workpiece' is that of link 'tool'\n     (origin at the tool tip, +z tip to spindle); m, rad, s. Acceleration and jerk are in fiveaxis:limits.\n     Efforts are 0: fiveaxis does not model forces. -->",
        escape(&machine.description).replace("--", "- -"),
        escape(&machine.name).replace("--", "- -")
    );
    let _ = writeln!(out, "<robot name=\"{}\" xmlns:fiveaxis=\"{NAMESPACE}\">", escape(&machine.name));
    let _ = writeln!(out, "  <link name=\"base\"/>");
    let joint = |name: &str, kind: &str, parent: &str, child: &str, xyz: &Vector3<f64>, rpy: (f64, f64, f64), axis: Option<&Vector3<f64>>, limit: Option<String>| {
        let mut out = format!("  <joint name=\"{}\" type=\"{kind}\">\n", escape(name));
        let _ = writeln!(out, "    <parent link=\"{}\"/>\n    <child link=\"{}\"/>", escape(parent), escape(child));
        let _ = writeln!(out, "    <origin xyz=\"{}\" rpy=\"{} {} {}\"/>", v3(xyz), f(rpy.0), f(rpy.1), f(rpy.2));
        if let Some(a) = axis {
            let _ = writeln!(out, "    <axis xyz=\"{}\"/>", v3(a));
        }
        if let Some(l) = limit {
            let _ = writeln!(out, "    {l}");
        }
        out.push_str("  </joint>\n");
        out
    };
    let axis_joint = |i: usize, parent: &str, child: &str, xyz: &Vector3<f64>, axis: &Vector3<f64>| {
        let l = &machine.axes[i].limits;
        let (kind, limit) = if l.is_unlimited() {
            ("continuous", format!("<limit effort=\"0\" velocity=\"{}\"/>", f(l.velocity)))
        } else {
            let kind = if i < 3 { "prismatic" } else { "revolute" };
            (kind, format!("<limit lower=\"{}\" upper=\"{}\" effort=\"0\" velocity=\"{}\"/>", f(l.min), f(l.max), f(l.velocity)))
        };
        joint(&machine.axes[i].name, kind, parent, child, xyz, (0.0, 0.0, 0.0), Some(axis), Some(limit))
    };
    let link_name = |i: usize, what: &str| format!("{}_{what}", machine.axes[i].name.to_ascii_lowercase());
    // Joint elements by axis index (the mounts after them), and the links.
    let mut joints: [String; 5] = Default::default();
    let mut links = String::new();
    // Workpiece side: the table joints, base outwards.
    let (mut parent, mut at) = ("base".to_string(), Vector3::zeros());
    // A four-axis machine's locked joint (slot 1, unnamed) is not written: its URDF has one rotary joint.
    let written = |slot: usize| !(chain.is_four_axis() && slot == 1);
    for (slot, j) in chain.joints().iter().enumerate().filter(|&(slot, j)| j.carrier == Carrier::Table && written(slot)) {
        let child = link_name(3 + slot, "table");
        joints[3 + slot] = axis_joint(3 + slot, &parent, &child, &(j.center - at), &j.axis);
        let _ = writeln!(links, "  <link name=\"{}\">\n    <visual><origin xyz=\"0 0 -0.03\"/><geometry><cylinder radius=\"0.12\" length=\"0.02\"/></geometry></visual>\n  </link>", escape(&child));
        (parent, at) = (child, j.center);
    }
    let mut mounts = joint("workpiece_mount", "fixed", &parent, WORKPIECE_LINK, &(-at), (0.0, 0.0, 0.0), None, None);
    let _ = writeln!(links, "  <link name=\"{WORKPIECE_LINK}\">\n    <visual><origin xyz=\"0 0 -0.01\"/><geometry><box size=\"0.1 0.1 0.02\"/></geometry></visual>\n  </link>");
    // Tool side: X, Y, Z, then the head joints from the ram outwards.
    parent = "base".to_string();
    for (i, slot) in joints.iter_mut().enumerate().take(3) {
        let child = link_name(i, "slide");
        *slot = axis_joint(i, &parent, &child, &Vector3::zeros(), &Vector3::ith(i, 1.0));
        let _ = writeln!(links, "  <link name=\"{}\"/>", escape(&child));
        parent = child;
    }
    at = Vector3::zeros();
    for (slot, j) in chain.joints().iter().enumerate().filter(|&(slot, j)| j.carrier == Carrier::Head && written(slot)) {
        let child = link_name(3 + slot, "head");
        joints[3 + slot] = axis_joint(3 + slot, &parent, &child, &(j.center - at), &j.axis);
        let _ = writeln!(links, "  <link name=\"{}\">\n    <visual><geometry><sphere radius=\"0.04\"/></geometry></visual>\n  </link>", escape(&child));
        (parent, at) = (child, j.center);
    }
    let tool_axis = chain.tool_axis();
    let turn = UnitQuaternion::rotation_between(&Vector3::z(), &tool_axis).unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI));
    mounts.push_str(&joint("tool_mount", "fixed", &parent, "tool", &(chain.tool_tip() - at), turn.euler_angles(), None, None));
    let _ = writeln!(links, "  <link name=\"tool\">\n    <visual><origin xyz=\"0 0 0.03\"/><geometry><cylinder radius=\"0.005\" length=\"0.06\"/></geometry></visual>\n  </link>");
    out.push_str(&links);
    for j in &joints {
        out.push_str(j);
    }
    out.push_str(&mounts);
    for a in machine.axes.iter().filter(|a| !a.name.is_empty()) {
        let _ = writeln!(out, "  <fiveaxis:limits joint=\"{}\" acceleration=\"{}\" jerk=\"{}\"/>", escape(&a.name), f(a.limits.acceleration), f(a.limits.jerk));
    }
    let _ = writeln!(out, "</robot>");
    out
}

/// True if a `--machine` value names a URDF file (by its extension).
pub fn is_urdf_path(spec: &str) -> bool {
    std::path::Path::new(spec).extension().is_some_and(|e| e.eq_ignore_ascii_case("urdf"))
}
