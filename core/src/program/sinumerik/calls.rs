//! The cycles a block calls: a drilling cycle, once or modally (`MCALL CYCLE81`-`CYCLE89`, as its
//! moves where the tool stands), the swivel `CYCLE800` and the high-speed settings `CYCLE832`.
//! Part of [`super::SinumerikReader`].

use super::frame::Frame;
use super::lex::{self, Keyword};
use super::{cycles, swivel, Block, Diags, Dimension, Motion, OneShot, Word, DEG, MM};
use crate::program::{Plane, ProgrammedTolerance};
use std::borrow::Cow;

impl super::SinumerikReader {
    /// `MCALL CYCLE8x(...)`: the cycle is called after each later block that moves (its
    /// parameters read once, here); `MCALL` alone ends it, and one read ends the hold of one refused
    /// (the line's refusal places it: [`super::SinumerikReader::calls_refused`]).
    pub(super) fn modal_call(&mut self, call: Option<Keyword<'_>>, line: usize, diags: &mut Diags) {
        if self.read_call(call, line, diags).is_none() {
            self.interp.end_keyword_hold(&crate::program::interp::SIN_MCALL, [true; 3], true);
        }
    }

    /// A cycle called (with `MCALL`, or once: `call`), read into the modal call; `None` if read,
    /// else whether it was refused for an alarm of the control (not for what is not read here).
    pub(super) fn read_call(&mut self, call: Option<Keyword<'_>>, line: usize, diags: &mut Diags) -> Option<bool> {
        let Some(call) = call else {
            self.mcall = None;
            return None;
        };
        let Some(cycle) = cycles::Cycle::from_name(&call.name) else {
            let why = if call.name == "CYCLE76" { " (CYCLE76 is rectangular spigot milling, not boring: Milling Operating Manual 03/2010 §8.2.4)" } else { "" };
            diags.error(line, call.col, format!("MCALL {}: only the drilling cycles CYCLE81-CYCLE89 are read as modal calls{why}", call.name));
            return Some(false);
        };
        let args = match lex::call_arguments(call.args.unwrap_or(""), &mut self.vars) {
            Ok(a) => a,
            Err((_, why)) => {
                diags.error(line, call.col, format!("{}: {why}", call.name));
                return Some(false);
            }
        };
        match cycles::decode(cycle, &args, self.interp.unit() / MM) {
            Ok(hole) => {
                self.mcall = Some((hole, line));
                None
            }
            Err(r) => {
                diags.error(line, call.col, format!("{}: {}", call.name, r.why));
                self.call_refused = Some(r.alarm);
                Some(r.alarm)
            }
        }
    }

    /// The modal cycle's moves where the tool stands, as blocks of this line; a rapid to where the
    /// tool already is makes none.
    pub(super) fn call_cycle(&mut self, line: usize, col: usize, number: Option<u64>, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        let Some((hole, _)) = self.mcall.clone() else { return true };
        if self.interp.plane() != Plane::Xy {
            diags.error(line, col, "a drilling cycle outside the G17 plane (drilling along X or Y) is not modelled");
            return false;
        }
        let saved = self.interp.feed_state();
        // F as programmed (in the feed's unit, which G70 leaves in the basic system's).
        let modal_f = saved.1.map(|(_, programmed)| programmed);
        // A tapping feed is the pitch (a length of the geometry's unit) per turn, written as F.
        let geometry_per_feed_unit = self.interp.unit() / self.interp.feed_unit();
        let mut feeds = 0;
        // The cycle's levels (RTP, RFP, DP) are absolute whatever G90/G91 say (the cycles' parameter
        // tables: "RTP retraction plane (absolute)", "DP final drilling depth (absolute)").
        let word = |letter: char, v: f64| {
            let dimension = if letter == 'Z' { Dimension::Absolute } else { Dimension::Modal };
            Word { letter, value: v, raw: Cow::Owned(format!("{v}")), column: col, dimension }
        };
        for step in hole.steps {
            let block = match step {
                cycles::Step::Rapid(z) if (self.interp.position()[2] - z * self.interp.unit()).abs() < 1e-12 => continue,
                cycles::Step::Rapid(z) => self.interp.block_one(&[word('G', 0.0), word('Z', z)], line, col, number, diags),
                cycles::Step::Feed(z, f) => {
                    // CYCLE83's first infeed at FRF times F; tapping at the pitch times the speed in, then out.
                    let f = match (f, hole.first_feed_factor, hole.tapping) {
                        (Some(f), _, _) => Some(f),
                        (None, _, Some((pitch, s_in, s_out))) => Some(pitch * geometry_per_feed_unit * if feeds == 0 { s_in } else { s_out }),
                        (None, Some(k), None) if feeds == 0 => modal_f.map(|f| f * k),
                        (None, _, None) => None,
                    };
                    feeds += 1;
                    let mut w = vec![word('G', 1.0), word('Z', z)];
                    w.extend(f.map(|f| word('F', f)));
                    self.interp.block_one(&w, line, col, number, diags)
                }
                cycles::Step::Dwell(t) => Some(Block { dwell_s: Some(t), ..self.interp.still_block(line, col, number) }),
                cycles::Step::Stop => Some(Block { events: vec!["M5".into(), "M0".into()], ..self.interp.still_block(line, col, number) }),
            };
            match block {
                Some(b) => out.push(b),
                None => return false,
            }
            // A feed of the cycle's own does not stay (the cycles restore F; SAVE restores G0/G1).
            self.interp.restore_feed(saved);
        }
        true
    }

    /// `CYCLE800` ([`swivel`]): the swivelled plane's frame, the retraction and the rotary axes
    /// turned to it as the data set's kinematics (the machine file's) give them, as blocks of this
    /// line; `CYCLE800()` deselects it (the axes stay). Returns the axes (X Y Z A B C) it moved to
    /// known positions: the retraction's, the rotary axes turned.
    /// `unknown`: where the axes are is not known (after a refused swivel or a call not read).
    pub(super) fn swivel(&mut self, k: &Keyword<'_>, line: usize, number: Option<u64>, unknown: bool, out: &mut Vec<Block>, diags: &mut Diags) -> [bool; 6] {
        let col = k.col;
        let args = match lex::call_arguments(k.args.unwrap_or(""), &mut self.vars) {
            Ok(a) => a,
            Err((_, why)) => return refused(diags.error(line, col, format!("CYCLE800: {why}"))),
        };
        let call = match swivel::decode(&args) {
            Ok(Some(c)) => c,
            Ok(None) => {
                self.swivel = None;
                self.set_frame(self.frame);
                return [false; 6];
            }
            Err(why) => return refused(diags.error(line, col, format!("CYCLE800: {why}"))),
        };
        let Some(machine) = self.machine.clone() else {
            return refused(diags.error(line, col, "CYCLE800: a swivel needs the machine's kinematics (--machine)"));
        };
        let Some(data) = machine.swivel.clone() else {
            return refused(diags.error(line, col, format!("CYCLE800: the machine file gives no swivel data set ([swivel]) for \"{}\"", call.data_set)));
        };
        if !data.names.contains(&call.data_set) {
            return refused(diags.error(line, col, format!("CYCLE800: _TC \"{}\": the machine's swivel data set is {:?}", call.data_set, data.names)));
        }
        if self.interp.tcp() {
            return refused(diags.error(line, col, "CYCLE800 under TRAORI: a swivel with the transformation on (tool-tip follow-up) is not read; TRAFOOF first"));
        }
        if self.swivel.is_none() && self.frame.rotated() {
            // How a new or additive swivel meets the programmable frame's rotation (which frames it
            // keeps, where its retraction in machine coordinates goes) is not in the pages at hand.
            return refused(diags.error(line, col, "CYCLE800 after a rotated frame (ROT, AROT, RPL) without a swivel before it: how the swivel meets the programmed rotation is not read; reset the frame first (ROT)"));
        }
        if unknown && call.additive {
            return refused(diags.error(line, col, "CYCLE800 _ST=1 (additive) builds on the swivelled plane before it, which is not known here (a refused CYCLE800 or a call not read came before): the plane it sets is not known"));
        }
        let unit = self.interp.unit();
        let letters: [char; 2] = [3, 4].map(|i| machine.axes[i].name.chars().next().unwrap_or('?').to_ascii_uppercase());
        let pos = self.interp.position();
        let current = letters.map(|l| "ABC".find(l).map_or(0.0, |i| pos[3 + i]));
        let r = match call.turn {
            swivel::Turn::Frame(r) => r,
            swivel::Turn::Direct(d) => machine.chain.tool_frame(&d.map(|v| v * DEG)),
        };
        let plane = Frame { t: (call.x0 + r * call.x1) * unit, r };
        let plane = match (call.additive, self.swivel) {
            (true, Some(s)) => Frame { t: s.t + s.r * plane.t, r: s.r * plane.r },
            _ => plane,
        };
        // The axes' positions for the plane (its Z, with the programmable frame's rotation, along the tool).
        let mut free = None;
        let rot = match call.turn {
            swivel::Turn::Direct(d) => Some(d.map(|v| v * DEG)),
            _ if call.direction == 0 => None,
            _ => {
                let tilting = 3 + (1 - machine.chain.secondary_slot());
                if data.direction_axis.is_some_and(|a| a != tilting) {
                    return refused(diags.error(line, col, "CYCLE800: _DIR referred to the swivel's other axis (swivel.direction_axis) is not modelled; the tilting axis is"));
                }
                let plus = call.direction > 0;
                let solve = |seq: bool| crate::program::plane::solve(&machine, &(plane.r * self.frame.r), current, crate::program::plane::Choice { seq: Some(seq), table_rot: None });
                let sol = match solve(plus) {
                    Ok(s) => s,
                    Err(why) => match solve(!plus) {
                        Ok(s) => {
                            diags.warning(line, col, format!("CYCLE800 _DIR={}: {why}; the control takes the other solution (Operating Manual §10.6: \"the alternative position is automatically selected\")", call.direction));
                            s
                        }
                        Err(_) => return refused(diags.error(line, col, format!("CYCLE800: {why}"))),
                    },
                };
                if let Some(pole) = sol.pole {
                    free = Some(pole.free_axis);
                    let name = &machine.axes[pole.free_axis].name;
                    let was = if unknown { " (where this reader last knew it: it is not known here)" } else { "" };
                    diags.warning(line, col, format!("CYCLE800 at the pole: the tool lies along {name}'s axis, which leaves {name} free (\"the NC calculates two solutions\"); read as staying at {:.3} deg{was}: the program depends on the control here", pole.coord_rot.to_degrees()));
                }
                Some(sol.rot)
            }
        };
        // The swivel before this one goes; the retraction, the axes turned, then the new plane.
        self.swivel = None;
        self.set_frame(self.frame);
        let mut placed = [false; 6];
        let word = |letter: char, v: f64| Word { letter, value: v, raw: Cow::Owned(format!("{v}")), column: col, dimension: Dimension::Modal };
        if let Some(rot) = rot {
            if call.retract > 0 {
                if self.frame.rotated() {
                    return refused(diags.error(line, col, format!("CYCLE800 _FR={} with a rotated frame (ROT, AROT, RPL) in effect: where its retraction in machine coordinates goes under the programmed rotation is not read; reset the frame first (ROT)", call.retract)));
                }
                let (Some(to), Some(origin)) = (data.retract, OneShot::machine_origin(&self.interp)) else {
                    return refused(diags.error(line, col, format!("CYCLE800 _FR={}: the data set's retract position (swivel.retract_mm) or the machine coordinates are not in the machine file", call.retract)));
                };
                let legs: &[&[usize]] = if call.retract == 1 { &[&[2]] } else { &[&[2], &[0, 1]] };
                // After the whole retraction (`_FR` 2) the machine's X Y Z are known, and so the
                // program's in the new plane; after Z alone (`_FR` 1) its X and Y are not, and a
                // plane's rotation mixes them into every program axis.
                if call.retract == 2 {
                    placed[..3].fill(true);
                }
                for leg in legs {
                    let mut w = vec![word('G', 0.0)];
                    w.extend(leg.iter().map(|&k| word(['X', 'Y', 'Z'][k], to[k] / unit)));
                    self.interp.oneshot = Some(OneShot { motion: Motion::Rapid, absolute: true, axes: Some(origin), own: false });
                    match self.interp.block_one(&w, line, col, number, diags) {
                        Some(b) => out.push(b),
                        None => return [false; 6],
                    }
                }
            }
            let mut w = vec![word('G', 0.0)];
            w.extend((0..2).map(|i| word(letters[i], rot[i] / DEG)));
            let saved = self.interp.feed_state();
            match self.interp.block_one(&w, line, col, number, diags) {
                Some(b) => out.push(b),
                None => return [false; 6],
            }
            self.interp.restore_feed(saved);
            // The rotary axes turned to the plane's positions, but one left free at the pole, which
            // stays where it was, and one whose travel holds the position a turn either way too,
            // which takes the turn nearest where it was.
            for (i, l) in letters.iter().enumerate() {
                let limits = &machine.axes[3 + i].limits;
                let one_turn = ![rot[i] + std::f64::consts::TAU, rot[i] - std::f64::consts::TAU].iter().any(|v| limits.contains(*v));
                if let Some(k) = "ABC".find(*l).filter(|_| free != Some(3 + i) && one_turn) {
                    placed[3 + k] = true;
                }
            }
        }
        self.swivel = Some(plane);
        self.set_frame(self.frame);
        placed
    }

    /// `CYCLE832(_TOL, _TOLM, _OTOL)` (NC programming 12/2019 §3.25, "High Speed Settings"): the
    /// contour tolerance `_TOL` for the blocks that follow, a continuous-path mode; `_TOLM`'s
    /// units digit 0 (or no arguments) deselects it: the machine's tolerance again.
    pub(super) fn high_speed_settings(&mut self, k: &Keyword<'_>, line: usize, diags: &mut Diags) {
        let text = match machining_types(k.args.unwrap_or("")) {
            Ok(t) => t,
            Err(name) => return diags.error(line, k.col, format!("CYCLE832: {name}: a machining type with an orientation tolerance (_TOLM tens digit 1, _OTOL) is not read")),
        };
        let args = match lex::call_arguments(&text, &mut self.vars) {
            Ok(a) => a,
            Err((_, why)) => return diags.error(line, k.col, format!("CYCLE832: {why}")),
        };
        let get = |i: usize| args.get(i).map_or(Ok(0.0), |a| a.value());
        let (tol, tolm) = match (get(0), get(1)) {
            (Ok(t), Ok(m)) => (t, m),
            (Err(e), _) | (_, Err(e)) => return diags.error(line, k.col, format!("CYCLE832: {e}")),
        };
        if tolm.fract() != 0.0 || tolm < 0.0 {
            return diags.error(line, k.col, format!("CYCLE832: _TOLM={tolm}: expected a whole, decimal-coded number"));
        }
        // Deselection: the machine's tolerance and continuous-path mode G64 (NX's 840D post writes
        // `FFWOF UPATH SOFT COMPOF G64` as its equivalent where the control has no CYCLE832).
        if (tolm as u64) % 10 == 0 {
            self.interp.set_tolerance(ProgrammedTolerance::default());
            self.interp.exact = crate::program::Exact::Blend;
            return;
        }
        let t = tol * self.interp.unit();
        if !(tol > 0.0) || !crate::machine::ContourTolerance::linear_ok(t) {
            return diags.error(line, k.col, format!("CYCLE832: _TOL={tol}: the contour tolerance must be positive and at most {} mm", crate::machine::ContourTolerance::MAX.linear_m / MM));
        }
        if (tolm as u64 / 10) % 10 == 1 {
            diags.error(line, k.col, "CYCLE832: an orientation tolerance (_TOLM tens digit 1, _OTOL) is not read");
            return;
        }
        self.interp.set_tolerance(ProgrammedTolerance { linear_m: Some(t), rotary_rad: None });
        self.interp.exact = crate::program::Exact::Blend;
    }
}


/// CYCLE832's machining types by their plain-text names, as the cycle defines them (SINUMERIK
/// Operate, "High-speed settings": deselection `_OFF`, roughing `_ROUGH`, rough-finishing `_SEMIFIN`,
/// finishing `_FINISH`; Programming Manual 12/2019 §3.25, `_TOLM` units digit 0 deselection, 1
/// finishing, 2 rough-finishing, 3 roughing) put in as their numbers; `Err` names an `_ORI_` type
/// (with an orientation tolerance, which is not read).
/// A swivel refused (its error said): it placed no axis.
fn refused(_: ()) -> [bool; 6] {
    [false; 6]
}

fn machining_types(args: &str) -> Result<Cow<'_, str>, String> {
    const TYPES: [(&str, &str); 4] = [("_OFF", "0"), ("_FINISH", "1"), ("_SEMIFIN", "2"), ("_ROUGH", "3")];
    if !args.contains('_') {
        return Ok(Cow::Borrowed(args));
    }
    let mut out = String::with_capacity(args.len());
    let b = args.as_bytes();
    let mut i = 0;
    while i < b.len() {
        let ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
        if ident(b[i]) {
            let start = i;
            while i < b.len() && ident(b[i]) {
                i += 1;
            }
            let word = &args[start..i];
            let upper = word.to_ascii_uppercase();
            match TYPES.iter().find(|(n, _)| *n == upper) {
                Some((_, v)) => out.push_str(v),
                None if matches!(upper.as_str(), "_ORI_FINISH" | "_ORI_SEMIFIN" | "_ORI_ROUGH") => return Err(word.to_string()),
                None => out.push_str(word),
            }
        } else {
            let ch = args[i..].chars().next().unwrap_or(' ');
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    Ok(Cow::Owned(out))
}
