//! Each kind of Klartext block parsed into its statement: paths (`L`, `LN`, `C`, `CR`, `CT`, `LP`,
//! `CP`), corners (`RND`, `CHF`), the circle centre `CC`, tool calls, `CALL LBL`, `FUNCTION` and the
//! blocks of one word ([`parse_line`] picks the kind).

use std::borrow::Cow;

use super::{motion_address, parse_val, split_word, FeedWord, KWord, Kind, Shape, Val};
use crate::program::lex::{excerpt, parse_number, upper, Diags};
use crate::program::Orientation;

/// One value word; defects go to `diags`.
pub(super) fn value_word<'a>(addr: &'static str, rest: &'a str, tok: &str, col: usize, line: usize, diags: &mut Diags) -> Option<KWord<'a>> {
    match parse_val(rest) {
        Some(val) => Some(KWord { addr, val, raw: rest, col }),
        None => {
            // A decimal comma (`X35,524`, as a German-language post may write it): Klartext numbers
            // take a decimal point.
            let comma = rest.split_once(',').is_some_and(|(a, b)| {
                let a = a.trim_start_matches(['+', '-']);
                !a.is_empty() && a.bytes().all(|c| c.is_ascii_digit()) && !b.is_empty() && b.bytes().all(|c| c.is_ascii_digit())
            });
            let why = if comma {
                format!(" (a decimal comma: numbers take a decimal point, {addr}{})", rest.replacen(',', ".", 1))
            } else if rest.contains(['(', '*', '/']) || rest.chars().skip(1).any(|c| c == '+' || c == '-') {
                " (an expression, which is not read)".to_string()
            } else {
                String::new()
            };
            diags.error(line, col, format!("{addr}: expected a number or a Q parameter, found '{}'{why}", excerpt(tok)));
            None
        }
    }
}

/// `L`, `LN`, `C`, `CR`, `CT` blocks.
pub(super) fn motion<'a>(toks: &[(&'a str, usize)], key: &str, line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let shape = match key {
        "L" => Shape::Line,
        "LN" => Shape::LineNormal,
        "C" => Shape::Circle,
        "CR" => Shape::CircleRadius,
        "LP" => Shape::LinePolar,
        "CP" => Shape::CirclePolar,
        _ => Shape::CircleTangent,
    };
    let arc = matches!(shape, Shape::Circle | Shape::CircleRadius | Shape::CircleTangent | Shape::CirclePolar);
    let polar = matches!(shape, Shape::LinePolar | Shape::CirclePolar);
    let mut axes: Vec<KWord<'a>> = Vec::with_capacity(if shape == Shape::LineNormal { 9 } else { 5 });
    let (mut ccw, mut radius, mut feed, mut m) = (None, None, FeedWord::None, Vec::new());
    let mut comp = None;
    let mut seen = 0u32;
    let mut words = toks[1..].iter().copied().peekable();
    while let Some((tok, col)) = words.next() {
        let (addr, rest) = split_word(tok);
        // `F MAX` and `F AUTO`, as many posts (hyperMILL among them) write FMAX and FAUTO.
        let spaced = (addr == "F" && rest.is_empty())
            .then(|| words.peek().map(|&(next, _)| upper(next)).filter(|n| n == "MAX" || n == "AUTO"))
            .flatten();
        let addr: Cow<'_, str> = match spaced {
            Some(n) => {
                words.next();
                Cow::Owned(format!("F{n}"))
            }
            None => addr,
        };
        let addr = addr.as_ref();
        // The values after M118 are its own: the handwheel's most travel per axis ("L X+0 Y+38.5 RL
        // F125 M118 X1 Y1", iTNC 530 user's manual, "Superimposing handwheel positioning during
        // program run: M118"), no move of the block.
        if m.iter().any(|w: &KWord<'_>| w.val == Val::Num(118.0)) && motion_address(addr).is_some_and(|(_, bit)| bit < 6) {
            continue;
        }
        match (motion_address(addr), addr) {
            (Some((_, bit)), _) if bit >= 6 && shape != Shape::LineNormal => {
                diags.error(line, col, format!("unexpected word '{}' in an {key} block (NX NY NZ, TX TY TZ belong to LN)", excerpt(tok)))
            }
            (Some((a, bit)), _) => {
                if seen & (1 << bit) != 0 {
                    diags.error(line, col, format!("{a} written twice in one block"));
                }
                seen |= 1 << bit;
                if let Some(w) = value_word(a, rest, tok, col, line, diags) {
                    axes.push(w);
                }
            }
            // Polar coordinates about the pole: radius PR (not on CP: its radius is the start's) and angle PA.
            (None, a @ ("PR" | "IPR" | "PA" | "IPA")) if polar && !(shape == Shape::CirclePolar && a.ends_with("PR")) => {
                let (name, bit) = match a {
                    "PR" => ("PR", 12),
                    "IPR" => ("IPR", 12),
                    "PA" => ("PA", 13),
                    _ => ("IPA", 13),
                };
                if seen & (1 << bit) != 0 {
                    diags.error(line, col, format!("{name} written twice in one block"));
                }
                seen |= 1 << bit;
                if let Some(w) = value_word(name, rest, tok, col, line, diags) {
                    axes.push(w);
                }
            }
            (None, "F") if m.last().is_some_and(|w: &KWord<'_>| w.val == Val::Num(128.0)) => m128_feed(tok, rest, col, line, diags),
            (None, "F") => feed = value_word("F", rest, tok, col, line, diags).map_or(FeedWord::None, FeedWord::Value),
            (None, "FMAX") if rest.is_empty() && !arc => feed = FeedWord::Max,
            (None, "FMAX") if rest.is_empty() => diags.error(line, col, "FMAX on a circle: expected a feed F"),
            (None, "FAUTO") if rest.is_empty() => feed = FeedWord::Auto(col),
            (None, "FU" | "FZ") => diags.error(line, col, format!("{tok}: feed per revolution or per tooth is not supported")),
            (None, "M") => {
                if let Some(w) = value_word("M", rest, tok, col, line, diags) {
                    m.push(w);
                }
            }
            (None, "R" | "RL" | "RR") if comp.is_some() && (rest == "0" || (addr != "R" && rest.is_empty())) => {
                diags.error(line, col, format!("{tok}: a second radius compensation word in one block (one of R0, RL, RR)"))
            }
            (None, "R") if rest == "0" => comp = Some((None, col)),
            // The radius, signed as a coordinate is (iTNC 530 user's manual, "Circular path CR": the
            // sign chooses the arc under or over 180 deg; none is +, as on beside it).
            (None, "R") if shape == Shape::CircleRadius && rest.starts_with(|c: char| matches!(c, '+' | '-' | '.' | 'Q' | 'q') || c.is_ascii_digit()) => {
                radius = value_word("R", rest, tok, col, line, diags)
            }
            (None, "RL" | "RR") if rest.is_empty() && shape == Shape::LineNormal => {
                diags.error(line, col, format!("{tok} in an LN block: three-dimensional tool compensation is not read"))
            }
            (None, "RL" | "RR") if rest.is_empty() => comp = Some((Some(addr == "RL"), col)),
            (None, "DR") if arc && (rest == "+" || rest == "-") && shape != Shape::CircleTangent => ccw = Some(rest == "+"),
            _ => diags.error(line, col, format!("unexpected word '{}' in an {key} block", excerpt(tok))),
        }
    }
    let at = toks[0].1;
    match shape {
        Shape::Circle | Shape::CircleRadius | Shape::CirclePolar if ccw.is_none() => diags.error(line, at, format!("{key}: expected the direction DR+ or DR-")),
        // One of them may be left out: the start's stays ("14 LP PA+60" after "13 LP PR+30 PA+0", TNC
        // 410 User's Manual, "Straight line LP").
        Shape::LinePolar if seen & (3 << 12) == 0 => diags.error(line, at, "LP: expected the polar radius PR (or IPR) or angle PA (or IPA)"),
        Shape::CirclePolar if seen & (1 << 13) == 0 => diags.error(line, at, "CP: expected the polar angle PA (or IPA) of the arc's end"),
        Shape::CircleRadius if radius.is_none() => diags.error(line, at, "CR: expected the radius R+.. (R- for an arc over 180 deg)"),
        // An arc with no end-point coordinate: a full circle about CC for C, an undefined one for CR
        // and CT; which the TNC makes of it is not at hand.
        Shape::Circle | Shape::CircleRadius | Shape::CircleTangent if seen & 0o7 == 0 => {
            diags.error(line, at, format!("{key}: expected the arc's end point (X, Y or Z; for a full circle about CC, its start's coordinates)"))
        }
        Shape::LineNormal => {
            // Bits: X Y Z 0-2, A B C 3-5, NX NY NZ 6-8, TX TY TZ 9-11.
            if seen & 0o707 != 0o707 {
                diags.error(line, at, "LN: expected X Y Z and NX NY NZ, all of them (as the TNC writes LN blocks)");
            }
            if seen & 0o7000 != 0 && seen & 0o7000 != 0o7000 {
                diags.error(line, at, "LN: expected TX TY TZ together");
            }
            if seen & 0o70 != 0 {
                diags.error(line, at, "LN with rotary-axis words: the tool axis is the vector TX TY TZ");
            }
        }
        _ => {}
    }
    Some(Kind::Move { shape, axes, ccw, radius, feed, m, comp })
}

/// A block's tokens with `DR+` or `DR-` parted from a word written right after it (`DR+F2777`): a
/// direction's value is its sign alone, so the next word starts after it. None where there is none.
pub(super) fn joined_direction<'a>(toks: &[(&'a str, usize)]) -> Option<(Vec<(&'a str, usize)>, usize)> {
    // Bytes: the first four are ASCII where it matches, so the split falls on a character's start.
    let joined = |t: &str| {
        let b = t.as_bytes();
        b.len() > 3 && b[..2].eq_ignore_ascii_case(b"DR") && matches!(b[2], b'+' | b'-') && b[3].is_ascii_alphabetic()
    };
    let first = toks.iter().find(|(t, _)| joined(t))?.1;
    let mut out = Vec::with_capacity(toks.len() + 1);
    for &(t, col) in toks {
        if joined(t) {
            out.push((&t[..3], col));
            out.push((&t[3..], col + 3));
        } else {
            out.push((t, col));
        }
    }
    Some((out, first))
}

/// `M128 F1000`: the feed of the linear axes' compensating movements, not the path's
/// ([`crate::program::interp::m128_feed_said`]).
pub(super) fn m128_feed(tok: &str, rest: &str, col: usize, line: usize, diags: &mut Diags) {
    if value_word("F", rest, tok, col, line, diags).is_some() {
        diags.warning(line, col, crate::program::interp::m128_feed_said(&excerpt(tok)));
    }
}

/// `RND R5 F100` and `CHF 12 F250` (iTNC 530 user's manual §6.4: "RND R" the rounding radius, "CHF"
/// the chamfer's side length, each with an optional feed for the corner alone).
pub(super) fn corner<'a>(toks: &[(&'a str, usize)], key: &str, line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let round = key == "RND";
    let before = diags.errors();
    let (mut size, mut feed) = (None, None);
    for &(tok, col) in &toks[1..] {
        let (addr, rest) = split_word(tok);
        match addr.as_ref() {
            "R" if round && size.is_none() => size = value_word("R", rest, tok, col, line, diags),
            // The chamfer's length stands alone, as a number or a Q parameter (`CHF 12`, `CHF Q5`).
            "" | "Q" | "QL" | "QR" if !round && size.is_none() => size = value_word("CHF", tok, tok, col, line, diags),
            "F" if feed.is_none() => feed = value_word("F", rest, tok, col, line, diags),
            _ => diags.error(line, col, format!("unexpected word '{}' in a {key} block (expected {} and an optional feed F)", excerpt(tok), if round { "the radius R" } else { "the side length" })),
        }
    }
    match size {
        Some(size) => Some(Kind::Corner { round, size, feed }),
        None => {
            if diags.errors() == before {
                diags.error(line, toks[0].1, format!("{key}: expected {}", if round { "the rounding radius R" } else { "the chamfer's side length" }));
            }
            None
        }
    }
}

/// `CC X.. Y..`: the pole (circle centre) in the working plane.
pub(super) fn centre<'a>(toks: &[(&'a str, usize)], line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let mut axes = Vec::new();
    for &(tok, col) in &toks[1..] {
        let (addr, rest) = split_word(tok);
        match motion_address(&addr) {
            Some((a, 0..=2)) => {
                if let Some(w) = value_word(a, rest, tok, col, line, diags) {
                    axes.push(w);
                }
            }
            _ => diags.error(line, col, format!("unexpected word '{}' in a CC block: expected the pole's coordinates", excerpt(tok))),
        }
    }
    Some(Kind::Centre(axes))
}

/// The word after a bare `MB` (`M140 MB`, `PLANE ... MB`): `Ok(None)` for MAX, `Ok(Some(w))` for a
/// distance, `Err(())` for a distance whose value is refused (said); `None` where it is neither.
#[allow(clippy::result_unit_err)]
pub(super) fn mb_value<'a>(next: Option<(&'a str, usize)>, line: usize, diags: &mut Diags) -> Option<Result<Option<KWord<'a>>, ()>> {
    match next {
        Some((v, _)) if v.eq_ignore_ascii_case("MAX") => Some(Ok(None)),
        Some((v, vc)) if v.starts_with(|ch: char| ch.is_ascii_digit() || "+-.Q".contains(ch)) => Some(value_word("MB", v, v, vc, line, diags).map(Some).ok_or(())),
        _ => None,
    }
}

/// A block of M functions only (`M128`, `M3 M8`), or `M140 MB MAX F..` (iTNC 530 user's manual,
/// "Miscellaneous functions for contouring behavior", "Retraction from the contour in the tool-axis
/// direction: M140": MB the distance, MAX to the end of the traverse range, F its feed, rapid
/// without one; along the tool axis also when tilted or under M128).
pub(super) fn misc<'a>(toks: &[(&'a str, usize)], line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    if let Some(&(first, col)) = toks.first() {
        if split_word(first) == (Cow::Borrowed("M"), "140") {
            let (mut distance, mut feed, mut mb) = (None, FeedWord::None, false);
            let mut k = 1;
            while let Some(&(tok, c)) = toks.get(k) {
                let (addr, rest) = split_word(tok);
                match (addr.as_ref(), rest) {
                    ("MB", "") if !mb => {
                        mb = true;
                        match mb_value(toks.get(k + 1).copied(), line, diags) {
                            Some(d) => {
                                // A refused distance was said; the block is not used.
                                distance = d.unwrap_or(None);
                                k += 1;
                            }
                            None => diags.error(line, c, "M140 MB: expected a distance or MAX"),
                        }
                    }
                    ("MB", v) if !mb => {
                        mb = true;
                        distance = value_word("MB", v, tok, c, line, diags);
                    }
                    ("F", v) if !v.is_empty() => feed = value_word("F", v, tok, c, line, diags).map_or(FeedWord::None, FeedWord::Value),
                    ("FMAX", "") => feed = FeedWord::Max,
                    _ => diags.error(line, c, format!("unexpected word '{}' in M140: expected MB and a distance or MAX, and F", excerpt(tok))),
                }
                k += 1;
            }
            if !mb {
                diags.error(line, col, "M140 without MB: expected MB and a distance or MAX");
            }
            return Some(Kind::Retract { distance, feed, col });
        }
    }
    let mut m: Vec<KWord<'a>> = Vec::new();
    for &(tok, col) in toks {
        let (addr, rest) = split_word(tok);
        if addr == "M" {
            if let Some(w) = value_word("M", rest, tok, col, line, diags) {
                m.push(w);
            }
        } else if addr == "F" && m.last().is_some_and(|w| w.val == Val::Num(128.0)) {
            m128_feed(tok, rest, col, line, diags);
        } else {
            diags.error(line, col, format!("unexpected word '{}' after an M function", excerpt(tok)));
        }
    }
    Some(Kind::Misc(m))
}

/// `TOOL CALL 5 Z S12000 F500`: events, and the feed FAUTO takes.
pub(super) fn tool_call<'a>(toks: &[(&'a str, usize)], line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let mut events = Vec::new();
    let mut feed = None;
    let mut rest_from = 2;
    if let Some(&(t, _)) = toks.get(2) {
        let u = upper(t);
        let is_axis = matches!(u.as_ref(), "X" | "Y" | "Z");
        if !is_axis && !u.starts_with(['S', 'F', 'D']) || t.starts_with('"') {
            events.push(format!("T{t}"));
            rest_from = 3;
        }
    }
    for (k, &(tok, col)) in toks.iter().enumerate().skip(rest_from) {
        let (addr, rest) = split_word(tok);
        match addr.as_ref() {
            "Z" if rest.is_empty() => {}
            a @ ("X" | "Y") if rest.is_empty() => {
                diags.error(line, col, format!("TOOL CALL with tool axis {a}: only tool axis Z is modelled (the machine file's)"))
            }
            "S" => match parse_val(rest) {
                Some(_) => events.push(format!("S{rest}")),
                None => diags.error(line, col, format!("S: expected a spindle speed, found '{}'", excerpt(tok))),
            },
            "F" => feed = value_word("F", rest, tok, col, line, diags),
            "DL" | "DR" => match parse_val(rest) {
                Some(Val::Num(0.0)) => {}
                _ => diags.error(
                    line,
                    col,
                    format!("{tok}: a tool length or radius delta is not modelled (it moves the tool tip; the tool is the machine file's)"),
                ),
            },
            _ => diags.error(line, col, format!("unexpected word '{}' in TOOL CALL (word {})", excerpt(tok), k + 1)),
        }
    }
    Some(Kind::Tool { events, feed })
}

/// `CALL LBL n [REP m]`.
pub(super) fn call<'a>(toks: &[(&'a str, usize)], line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let Some(&(label, _)) = toks.get(2) else {
        diags.error(line, toks[0].1, "CALL LBL: expected the label");
        return None;
    };
    let mut rep = None;
    let mut k = 3;
    while k < toks.len() {
        let (tok, col) = toks[k];
        let after = tok.get(3..).filter(|_| tok.get(..3).is_some_and(|p| p.eq_ignore_ascii_case("REP")));
        if let Some(r) = after {
            // `REP 3`, `REP3`, `REPQ9`, and the `REP3/3` the TNC displays (count left / count).
            let r = if r.is_empty() && k + 1 < toks.len() {
                k += 1;
                toks[k].0
            } else {
                r
            };
            let count = r.split('/').next().unwrap_or("");
            rep = value_word("REP", count, tok, col, line, diags);
        } else {
            diags.error(line, col, format!("unexpected '{}' in CALL LBL: expected REP n", excerpt(tok)));
        }
        k += 1;
    }
    Some(Kind::Call { label: label.trim_matches('"'), rep })
}

/// `FUNCTION TCPM ...` and `FUNCTION RESET TCPM`.
pub(super) fn function<'a>(toks: &[(&'a str, usize)], line: usize, col: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let words: Vec<Cow<'_, str>> = toks.iter().map(|t| upper(t.0)).collect();
    let words: Vec<&str> = words.iter().map(|w| w.as_ref()).collect();
    match words.get(1..) {
        Some(["RESET", "TCPM"]) => return Some(Kind::Tcp { on: false, orientation: None }),
        Some(["TCPM", ..]) => {}
        _ => {
            diags.error(line, col, format!("FUNCTION {}: not read (it may change the motion)", words.get(1).unwrap_or(&"")));
            return None;
        }
    }
    let mut orientation = None;
    let mut k = 2;
    while k < words.len() {
        let pair = (words[k], words.get(k + 1).copied().unwrap_or(""));
        match pair {
            ("F", "TCP") | ("AXIS", "POS") | ("REFPNT", "TIP-TIP") => k += 2,
            ("PATHCTRL", "AXIS") => {
                orientation = Some(Orientation::AxisLinear);
                k += 2
            }
            ("PATHCTRL", "VECTOR") => {
                orientation = Some(Orientation::GreatCircle);
                k += 2
            }
            ("F", "CONT") => {
                diags.error(line, col, "FUNCTION TCPM F CONT: the feed as a contouring feed over all axes is not modelled (expected F TCP)");
                k += 2
            }
            ("AXIS", "SPAT") => {
                diags.error(line, col, "FUNCTION TCPM AXIS SPAT: rotary words as spatial angles are not modelled (expected AXIS POS)");
                k += 2
            }
            ("REFPNT", other) => {
                diags.error(line, col, format!("FUNCTION TCPM REFPNT {other}: a reference point other than the tool tip is not modelled"));
                k += 2
            }
            // The feed limit of the compensating moves: the axes' limits are the machine file's.
            (f, _) if f.starts_with('F') && parse_number(&f[1..]).is_some() => k += 1,
            (other, _) => {
                diags.error(line, col, format!("FUNCTION TCPM: unexpected '{}'", excerpt(other)));
                k += 1
            }
        }
    }
    Some(Kind::Tcp { on: true, orientation })
}

/// The text of a line from token `k` on, to its comment (`;`), as written.
pub(super) fn text_from<'a>(raw: &'a str, toks: &[(&'a str, usize)], k: usize) -> &'a str {
    let Some(&(t, _)) = toks.get(k) else { return "" };
    // Tokens borrow from `raw`: the offset of the token in it.
    let start = t.as_ptr() as usize - raw.as_ptr() as usize;
    let rest = &raw[start..];
    // A `~` ending the line marks the block going on in the next (a cycle's parameters, one a line):
    // no part of the text.
    let text = rest.split(';').next().unwrap_or(rest).trim_end_matches('\r').trim_end();
    text.strip_suffix('~').map_or(text, str::trim_end)
}

/// `SPL X.. Y.. Z.. [A.. B.. C..] K3X.. K2X.. K1X.. ... [F..]`: the TNC's spline block (iTNC 530
/// User's Manual, "Contour movements – Spline interpolation (software option 2)"): each end-point
/// coordinate with its coefficients K3, K2, K1 in that order; a coefficient is -9.99999999 to
/// +9.99999999 with an exponent -255 to +255, written on it (`K3X-4.688E-002`) or after it
/// (`K2B-0.413 E+2`).
pub(super) fn spline<'a>(toks: &[(&'a str, usize)], line: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let mut ends: Vec<KWord<'a>> = Vec::new();
    let mut coefficients: [[Option<f64>; 3]; 6] = [[None; 3]; 6];
    let mut feed = FeedWord::None;
    let mut seen = 0u32;
    // Axes whose coefficients were refused (said once).
    let mut bad = [false; 6];
    let mut i = 1;
    while i < toks.len() {
        let (tok, col) = toks[i];
        i += 1;
        let b = tok.as_bytes();
        if b.len() > 3 && b[0].eq_ignore_ascii_case(&b'K') && matches!(b[1], b'1'..=b'3') && b[2].is_ascii_alphabetic() {
            let Some(k) = "XYZABC".find(b[2].to_ascii_uppercase() as char) else {
                diags.error(line, col, format!("{}: a spline coefficient of an axis this reader does not move (X Y Z A B C)", excerpt(tok)));
                continue;
            };
            // The exponent written on the value, else in the next word.
            let body = &tok[3..];
            let (mantissa, attached) = match body.find(['E', 'e']) {
                Some(e) => (&body[..e], Some(&body[e + 1..])),
                None => (body, None),
            };
            let exponent = match attached {
                Some(e) => Some(e),
                None => match toks.get(i) {
                    Some((next, _)) if next.len() > 1 && next.as_bytes()[0].eq_ignore_ascii_case(&b'E') && next[1..].bytes().all(|c| c.is_ascii_digit() || c == b'+' || c == b'-') => {
                        i += 1;
                        Some(&next[1..])
                    }
                    _ => None,
                },
            };
            let m = parse_number(mantissa).filter(|m| m.abs() <= 9.99999999 + 1e-12);
            // One sign at most, then digits.
            let e = match exponent {
                None => Some(0),
                Some(e) => {
                    let digits = e.strip_prefix(['+', '-']).unwrap_or(e);
                    let ok = !digits.is_empty() && digits.bytes().all(|c| c.is_ascii_digit()) && digits.len() <= 3;
                    ok.then(|| digits.parse::<i32>().ok()).flatten().map(|v| if e.starts_with('-') { -v } else { v }).filter(|v| v.abs() <= 255)
                }
            };
            if mantissa.contains(['Q', 'q']) {
                diags.error(line, col, format!("{}: a spline coefficient is a number (a Q parameter there is not read)", excerpt(tok)));
                bad[k] = true;
                continue;
            }
            let (Some(m), Some(e)) = (m, e) else {
                diags.error(line, col, format!("{}: expected a spline coefficient -9.99999999 to +9.99999999, its exponent -255 to +255 (iTNC 530 User's Manual, spline interpolation)", excerpt(tok)));
                bad[k] = true;
                continue;
            };
            let order = usize::from(b'3' - b[1]);
            let axis = &mut coefficients[k];
            // "The TNC always expects the spline parameters K for each axis in the sequence K3, K2, K1."
            if axis[order].is_some() || axis[order..].iter().skip(1).any(Option::is_some) || !axis[..order].iter().all(Option::is_some) {
                if !bad[k] {
                    diags.error(line, col, format!("{}: the coefficients of an axis come once each, as K3, K2, K1 in that order", excerpt(tok)));
                }
                bad[k] = true;
                continue;
            }
            axis[order] = Some(m * 10f64.powi(e));
            continue;
        }
        let (addr, rest) = split_word(tok);
        // `F AUTO` as two words, as `L` blocks take it.
        if addr == "F" && rest.is_empty() && toks.get(i).is_some_and(|(n, _)| upper(n) == "AUTO") {
            i += 1;
            feed = FeedWord::Auto(col);
            continue;
        }
        match (motion_address(&addr), addr.as_ref()) {
            (Some((a, bit)), _) if bit < 6 && a.len() == 1 => {
                if seen & (1 << bit) != 0 {
                    diags.error(line, col, format!("{a} written twice in one block"));
                }
                seen |= 1 << bit;
                if let Some(w) = value_word(a, rest, tok, col, line, diags) {
                    ends.push(w);
                }
            }
            (Some((a, bit)), _) if bit < 6 => diags.error(line, col, format!("{a}: a spline's end point is absolute (the manual gives no incremental form)")),
            (None, "FMAX") if rest.is_empty() => diags.error(line, col, "FMAX in a spline block: expected a feed F (a spline at rapid traverse is not in the manual's pages)"),
            (None, "F") if rest.is_empty() => diags.error(line, col, "F without a value in a spline block (F MAX is no spline's feed)"),
            (None, "F") => feed = value_word("F", rest, tok, col, line, diags).map_or(FeedWord::None, FeedWord::Value),
            (None, "FAUTO") if rest.is_empty() => feed = FeedWord::Auto(col),
            (None, "M") => diags.error(line, col, format!("{}: an M function in a spline block is not read (where it acts along the curve)", excerpt(tok))),
            _ => diags.error(line, col, format!("unexpected word '{}' in an SPL block", excerpt(tok))),
        }
    }
    // "For every end-point coordinate in the spline block, the spline parameters K3 to K1 must be
    // programmed"; a coefficient without its coordinate has no end point to start from.
    let at = toks[0].1;
    for k in 0..6 {
        let has_end = seen & (1 << k) != 0;
        let full = coefficients[k].iter().all(Option::is_some);
        let any = coefficients[k].iter().any(Option::is_some);
        let name = ["X", "Y", "Z", "A", "B", "C"][k];
        if bad[k] {
            continue;
        }
        if has_end && !full {
            diags.error(line, at, format!("SPL: the end point's {name} needs its coefficients K3{name}, K2{name} and K1{name}"));
        } else if !has_end && any {
            diags.error(line, at, format!("SPL: coefficients of {name} without an end point {name}"));
        }
    }
    if ends.is_empty() {
        diags.error(line, at, "SPL: expected the spline's end point and its coefficients");
    }
    let coefficients = coefficients.map(|c| Some([c[0]?, c[1]?, c[2]?]));
    Some(Kind::Spline { ends, coefficients, feed })
}
