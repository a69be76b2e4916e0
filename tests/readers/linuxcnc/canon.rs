//! LinuxCNC's own interpreter's output (`rs274`'s canonical calls, fixtures made by make_canon.sh)
//! read back, and our moves held against it: the end points, kinds, arc centres and feeds.

use super::*;

/// The end points LinuxCNC's own interpreter (`rs274`, Debian 12's linuxcnc-uspace) makes of a program:
/// its canonical STRAIGHT_FEED/STRAIGHT_TRAVERSE(x, y, z, a, b, c) lines (mm, deg; see make_canon.sh).
pub(super) fn linuxcnc_canon(name: &str) -> Vec<(Motion, [f64; 6])> {
    let path = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters").join(name);
    std::fs::read_to_string(&path)
        .unwrap()
        .lines()
        .map(|l| {
            let motion = if l.starts_with("STRAIGHT_FEED(") { Motion::Linear } else { Motion::Rapid };
            let inner = &l[l.find('(').unwrap() + 1..l.rfind(')').unwrap()];
            let v: Vec<f64> = inner.split(',').map(|x| x.trim().parse().unwrap()).collect();
            (motion, [v[0], v[1], v[2], v[3], v[4], v[5]])
        })
        .collect()
}

/// LinuxCNC's canonical moves with their kind (STRAIGHT_TRAVERSE, STRAIGHT_FEED, ARC_FEED in its
/// plane's axis order): end points in mm and deg, an arc's centre in its plane (mm). rs274 prints
/// positions in the program's unit (USE_LENGTH_UNITS), in the current coordinate frame (make_canon.sh's
/// second list).
pub(super) fn linuxcnc_moves(name: &str) -> Vec<(Motion, [f64; 6], Option<[f64; 2]>)> {
    let path = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters").join(name);
    let (mut inch, mut plane) = (false, "XY");
    let mut out = Vec::new();
    for l in std::fs::read_to_string(&path).unwrap().lines() {
        let inner = &l[l.find('(').unwrap() + 1..l.rfind(')').unwrap()];
        let v: Vec<f64> = inner.split(',').filter_map(|x| x.trim().parse().ok()).collect();
        let mm = |x: f64| if inch { x * 25.4 } else { x };
        match &l[..l.find('(').unwrap()] {
            "USE_LENGTH_UNITS" => inch = inner.contains("INCHES"),
            "SELECT_PLANE" => plane = if inner.contains("XZ") { "XZ" } else if inner.contains("YZ") { "YZ" } else { "XY" },
            "ARC_FEED" => {
                let turn = v[4];
                let (x, y, z) = match plane { "XY" => (v[0], v[1], v[5]), "XZ" => (v[1], v[5], v[0]), _ => (v[5], v[0], v[1]) };
                let centre = (plane == "XY").then(|| [mm(v[2]), mm(v[3])]);
                out.push((if turn < 0.0 { Motion::ArcCw } else { Motion::ArcCcw }, [mm(x), mm(y), mm(z), v[6], v[7], v[8]], centre));
            }
            kind => out.push((if kind == "STRAIGHT_FEED" { Motion::Linear } else { Motion::Rapid }, [mm(v[0]), mm(v[1]), mm(v[2]), v[3], v[4], v[5]], None)),
        }
    }
    out
}

/// Our moves against `name.canon`: the same kinds, end points and arc centres to rs274's 4 decimals
/// (of an inch, under G20).
pub(super) fn same_moves_as_linuxcnc(name: &str, p: &Program) {
    assert!(errors(p).is_empty(), "{name}: {:?}", errors(p));
    let ours = end_points(p);
    let centres: Vec<Option<[f64; 2]>> = p.blocks.iter().filter(|b| !b.targets.is_empty()).map(|b| b.arc.as_ref().map(|a| [a.centre[0] / MM, a.centre[1] / MM])).collect();
    let theirs = linuxcnc_moves(&format!("{name}.canon"));
    assert_eq!(ours.len(), theirs.len(), "{name}: moves\nours {ours:?}\ntheirs {theirs:?}");
    let close = |a: f64, b: f64| (a - b).abs() <= 0.5e-4 * 25.4 + 1e-9;
    for (k, (((m, a), c), (n, b, d))) in ours.iter().zip(&centres).zip(&theirs).enumerate() {
        assert_eq!(m, n, "{name}: move {k}: ours {a:?}, LinuxCNC {b:?}");
        assert!((0..6).all(|i| close(a[i], b[i])), "{name}: move {k}: ours {a:?}, LinuxCNC {b:?}");
        if let (Some(c), Some(d)) = (c, d) {
            assert!(close(c[0], d[0]) && close(c[1], d[1]), "{name}: move {k}'s centre: ours {c:?}, LinuxCNC {d:?}");
        }
    }
}

/// `v` turned by `deg` about Z (rs274ngc's `rotate`).
pub(super) fn turned(v: [f64; 2], deg: f64) -> [f64; 2] {
    let (s, c) = deg.to_radians().sin_cos();
    [v[0] * c - v[1] * s, v[0] * s + v[1] * c]
}

/// LinuxCNC's moves placed where its canonical layer puts the axes (emccanon.cc
/// rotate_and_offset_pos: XY = rot(p + G92 offset, R) + G5x offset, Z = p + both offsets), from
/// rs274's positions in the program frame and the offsets and rotation it sets (mm, deg); an XY
/// arc's centre placed alike; a feed move's feed, mm/min (in inverse time too: LinuxCNC's
/// interpreter gives the canonical layer the feed it works out, interp_inverse.cc; in units per
/// revolution, SET_FEED_MODE(spindle, 1), the feed times the spindle speed SET_SPINDLE_SPEED set).
pub(super) fn linuxcnc_world_of(canon: &str) -> Vec<Placed> {
    let (mut inch, mut plane, mut g5x, mut g92, mut r) = (false, "XY", [0.0; 3], [0.0; 3], 0.0);
    let (mut feed, mut per_rev, mut speed) = (0.0, false, 0.0);
    // The feed as set, and the last move's end placed (mm, deg): a move of the rotary axes alone
    // takes its feed in degrees a minute, whatever the length unit.
    let (mut feed_raw, mut last) = (0.0, [0.0; 6]);
    let mut out = Vec::new();
    for l in canon.lines() {
        let inner = &l[l.find('(').unwrap() + 1..l.rfind(')').unwrap()];
        let v: Vec<f64> = inner.split(',').filter_map(|x| x.trim().parse().ok()).collect();
        let mm = |x: f64| if inch { x * 25.4 } else { x };
        // A feed move's feed, mm/min.
        let path_feed = feed * if per_rev { speed } else { 1.0 };
        // Offsets in mm as set (the canonical layer keeps them in its own units), positions in
        // the program's unit as it moves.
        let place = |p: [f64; 3]| {
            let xy = turned([mm(p[0]) + g92[0], mm(p[1]) + g92[1]], r);
            [xy[0] + g5x[0], xy[1] + g5x[1], mm(p[2]) + g92[2] + g5x[2]]
        };
        match &l[..l.find('(').unwrap()] {
            "USE_LENGTH_UNITS" => inch = inner.contains("INCHES"),
            "SELECT_PLANE" => plane = if inner.contains("XZ") { "XZ" } else if inner.contains("YZ") { "YZ" } else { "XY" },
            "SET_G5X_OFFSET" => g5x = [mm(v[1]), mm(v[2]), mm(v[3])],
            "SET_G92_OFFSET" => g92 = [mm(v[0]), mm(v[1]), mm(v[2])],
            "SET_XY_ROTATION" => r = v[0],
            // In the program's unit when it is set, as emccanon.cc SET_FEED_RATE converts it
            // (FROM_PROG_LEN), per minute or, in feed per revolution, per turn.
            "SET_FEED_RATE" => (feed, feed_raw) = (mm(v[0]), v[0]),
            "SET_FEED_MODE" => per_rev = v[1] == 1.0,
            "SET_SPINDLE_SPEED" => speed = v[1],
            "ARC_FEED" => {
                let (x, y, z) = match plane { "XY" => (v[0], v[1], v[5]), "XZ" => (v[1], v[5], v[0]), _ => (v[5], v[0], v[1]) };
                let e = place([x, y, z]);
                last = [e[0], e[1], e[2], v[6], v[7], v[8]];
                let centre = (plane == "XY").then(|| place([v[2], v[3], z])).map(|c| [c[0], c[1]]);
                out.push((if v[4] < 0.0 { Motion::ArcCw } else { Motion::ArcCcw }, [e[0], e[1], e[2], v[6], v[7], v[8]], centre, Some(path_feed)));
            }
            kind @ ("STRAIGHT_FEED" | "STRAIGHT_TRAVERSE") => {
                let e = place([v[0], v[1], v[2]]);
                let now = [e[0], e[1], e[2], v[3], v[4], v[5]];
                // rs274's 4 decimals, of an inch where the unit changed since the last move.
                let rotary_only = (0..3).all(|k| (now[k] - last[k]).abs() < 0.75e-4 * 25.4) && (3..6).any(|k| (now[k] - last[k]).abs() > 1e-9);
                last = now;
                let f = (kind == "STRAIGHT_FEED").then_some(if rotary_only && !per_rev { feed_raw } else { path_feed });
                out.push((if kind == "STRAIGHT_FEED" { Motion::Linear } else { Motion::Rapid }, [e[0], e[1], e[2], v[3], v[4], v[5]], None, f));
            }
            // The states this comparison does not place (the path control mode).
            _ => {}
        }
    }
    out
}

/// A move placed in the workpiece: its kind, end (mm, deg), an XY arc's centre (mm) and a feed
/// move's feed (mm/min).
pub(super) type Placed = (Motion, [f64; 6], Option<[f64; 2]>, Option<f64>);

/// Our moves placed in the workpiece (targets plus datum, mm and deg; XY arcs' centres too), against
/// [`linuxcnc_world_of`] of `canon`: the same kinds and points to rs274's 4 decimals. Rapid moves that
/// go nowhere are left out on both sides (rs274 makes one of G28's intermediate point where the
/// tool stands; this reader none). Ours returned.
pub(super) fn same_places_as_linuxcnc(p: &Program, canon: &Path) -> Vec<Placed> {
    same_places_as_linuxcnc_of(p, &std::fs::read_to_string(canon).unwrap(), &canon.display().to_string())
}

/// The fixture `name` of recordings/programs/linuxcnc/parameters (`name.ngc`) read as RS274 with
/// `options`, its moves placed as rs274's `name.canon` places them ([`same_places_as_linuxcnc`]):
/// ours returned.
pub(super) fn fixture_as_linuxcnc(name: &str, options: &ReadOptions) -> Vec<Placed> {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let text = std::fs::read_to_string(dir.join(format!("{name}.ngc"))).unwrap();
    let p = read(&text, Dialect::Rs274, &format!("{name}.ngc"), options);
    same_places_as_linuxcnc(&p, &dir.join(format!("{name}.canon")))
}

/// [`same_places_as_linuxcnc`] of rs274's lines given as text, `name` naming them.
pub(super) fn same_places_as_linuxcnc_of(p: &Program, canon: &str, name: &str) -> Vec<Placed> {
    assert!(errors(p).is_empty(), "{name}: {:?}", errors(p));
    let moving = |v: Vec<Placed>| -> Vec<Placed> {
        let mut at = [0.0; 6];
        v.into_iter()
            .filter(|m| {
                // Within rs274's rounding (its 4 decimals, turned): no move.
                let still = m.0 == Motion::Rapid && (0..6).all(|i| (m.1[i] - at[i]).abs() <= 0.75e-4 * 25.4);
                at = m.1;
                !still
            })
            .collect()
    };
    let theirs = moving(linuxcnc_world_of(canon));
    let mut at = [0.0; 6];
    let ours: Vec<Placed> = p
        .blocks
        .iter()
        .filter(|b| !b.targets.is_empty())
        .map(|b| {
            let t = &b.targets;
            let from = at;
            for (k, v) in [t.x, t.y, t.z, t.a, t.b, t.c].into_iter().enumerate() {
                if let Some(v) = v {
                    at[k] = if k < 3 { (v + b.datum[k]) / MM } else { v / DEG };
                }
            }
            let centre = b.arc.as_ref().filter(|a| a.plane == fiveaxis::program::Plane::Xy).map(|a| [(a.centre[0] + b.datum[0]) / MM, (a.centre[1] + b.datum[1]) / MM]);
            // Inverse time: the move's length over its time (an arc's: its helix, as LinuxCNC's
            // interp_inverse.cc find_arc_length takes it).
            let length = match b.arc.as_deref() {
                // find_straight_length: X Y Z's, or where they stay, A B C's (deg).
                None => {
                    let d = |r: std::ops::Range<usize>| r.map(|k| (at[k] - from[k]).powi(2)).sum::<f64>().sqrt();
                    if d(0..3) > 1e-9 { d(0..3) } else { d(3..6) }
                }
                Some(a) => {
                    let (i, j, k) = match a.plane { fiveaxis::program::Plane::Xy => (0, 1, 2), fiveaxis::program::Plane::Zx => (2, 0, 1), _ => (1, 2, 0) };
                    let c = [(a.centre[0] + b.datum[0]) / MM, (a.centre[1] + b.datum[1]) / MM, (a.centre[2] + b.datum[2]) / MM];
                    let (s, e) = ((from[j] - c[j]).atan2(from[i] - c[i]), (at[j] - c[j]).atan2(at[i] - c[i]));
                    let radius = (from[i] - c[i]).hypot(from[j] - c[j]);
                    // G3 turns counter-clockwise seen from the plane's normal, from the first axis to the second.
                    let mut sweep = if b.motion == Motion::ArcCcw { e - s } else { s - e };
                    sweep = sweep.rem_euclid(std::f64::consts::TAU);
                    if sweep < 1e-9 {
                        sweep = std::f64::consts::TAU;
                    }
                    let sweep = sweep + std::f64::consts::TAU * f64::from(a.extra_turns);
                    (radius * sweep).hypot(at[k] - from[k])
                }
            };
            // A move of the rotary axes alone is fed in degrees a minute (`rotary_per_min`).
            let rotary_only = b.arc.is_none() && (0..3).all(|k| (at[k] - from[k]).abs() < 1e-9) && (3..6).any(|k| (at[k] - from[k]).abs() > 1e-9);
            let feed = b.feed.filter(|_| b.motion != Motion::Rapid).map(|f| match f.mode {
                // A move of no length takes no time, whatever its feed (rs274 sets 0.1 then): NaN, not compared.
                FeedMode::InverseTime if length < 1e-12 => f64::NAN,
                FeedMode::InverseTime => f.value_per_min * length,
                _ if rotary_only => f.rotary_per_min,
                _ => f.value_per_min,
            });
            (b.motion, at, centre, feed)
        })
        .collect();
    let ours = moving(ours);
    assert_eq!(ours.len(), theirs.len(), "{name}: moves\nours {ours:?}\ntheirs {theirs:?}");
    // rs274's 4 decimals (of an inch, under G20), turned: a coordinate off by up to 1.5 of them.
    let close = |a: f64, b: f64| (a - b).abs() <= 0.75e-4 * 25.4;
    for (k, ((m, a, c, f), (n, b, d, g))) in ours.iter().zip(&theirs).enumerate() {
        assert_eq!(m, n, "{name}: move {k}: ours {a:?}, LinuxCNC {b:?}");
        assert!(f.zip(*g).is_none_or(|(f, g)| f.is_nan() || (f - g).abs() <= 1e-4 * 25.4) && f.is_some() == g.is_some(), "{name}: move {k}'s feed: ours {f:?}, LinuxCNC {g:?}");
        assert!((0..6).all(|i| close(a[i], b[i])), "{name}: move {k}: ours {a:?}, LinuxCNC {b:?}");
        if let (Some(c), Some(d)) = (c, d) {
            assert!(close(c[0], d[0]) && close(c[1], d[1]), "{name}: move {k}'s centre: ours {c:?}, LinuxCNC {d:?}");
        }
    }
    ours
}
