//! The tool table LinuxCNC's `G41`/`G42` and a TNC's `RL`/`RR` take their radius from (LinuxCNC's
//! `tool.tbl` or the TNC's `TOOL.T`), and the tool in the spindle.

use crate::program::interp::Word;

/// A tool table, its diameters: what `G41`/`G42` with a `D` (or the tool in the spindle) and a
/// Klartext `RL`/`RR` (the called tool) compensate by. Read from LinuxCNC's `tool.tbl`
/// (`T1 P1 D10 Z0 ;comment`), whose lengths are in the machine's unit (LinuxCNC's
/// `[TRAJ] LINEAR_UNITS`): mm unless [`ToolTable::in_unit`] says inches; or from a Heidenhain TNC's
/// `TOOL.T`, whose first line names its unit (`BEGIN TOOL.T MM`), which then stands.
#[derive(Debug, Clone, PartialEq)]
pub struct ToolTable {
    tools: Vec<(u32, f64)>,
    /// A TNC table's tool names (its NAME column, in capitals as the control keeps them) and numbers.
    names: Vec<(String, u32)>,
    /// A TNC table's tools whose radius deltas DR or DR2 are not 0: (tool, DR, DR2), in its unit.
    /// Three-dimensional compensation (LN blocks) moves the tool along the normal by them.
    deltas: Vec<(u32, f64, f64)>,
    /// Metres per unit of the table's numbers.
    unit: f64,
    /// The unit is the table's own (a TNC table's header), which [`ToolTable::in_unit`] leaves.
    unit_from_header: bool,
}

/// The most tools a table may hold (LinuxCNC's CANON_POCKETS_MAX is 1000).
pub const MAX_TOOLS: usize = 100_000;

/// A TNC's numbered tool call's diameter 2 (R + DR) in the tool table (`--tool-table`), m; why not
/// (no table given, the tool not in it). Klartext's `TOOL CALL 5` and DIN/ISO's `T5 G17` alike.
pub(crate) fn tnc_diameter(table: Option<&ToolTable>, tool: u32) -> Result<f64, String> {
    let table = table.ok_or_else(|| format!("the radius is tool {tool}'s in the tool table: give it with --tool-table (the TNC's TOOL.T, or LinuxCNC's tool.tbl)"))?;
    table.diameter(tool).ok_or_else(|| format!("tool {tool} is not in the tool table"))
}

/// The radius a TNC's `RL`/`RR` (DIN/ISO `G41`/`G42`) compensate by for the tool `who` of diameter
/// `d` (m): what the TNC makes of a negative R + DR is not in the manuals read here.
pub(crate) fn tnc_radius(who: &str, d: f64) -> Result<f64, String> {
    if d < 0.0 {
        return Err(format!("{who}'s radius in the tool table (R + DR) is negative ({} mm): not read", d / 2.0 / crate::units::MM));
    }
    Ok(d / 2.0)
}

impl ToolTable {
    /// Read a tool table: a Heidenhain TNC's `TOOL.T` where the first line that is not blank starts
    /// with `BEGIN` (its rows' T, R and DR, by the columns its second line names), else LinuxCNC's
    /// `tool.tbl` (each line `T<n>` with the words `P X Y Z A B C U V W D I J Q`, a `;` comment).
    /// Errors name the line and the word or column. A tool listed twice takes its last line's.
    pub fn parse(text: &str) -> Result<ToolTable, String> {
        let first = text.lines().map(str::trim_start).find(|l| !l.is_empty()).unwrap_or("");
        if first.get(..5).is_some_and(|w| w.eq_ignore_ascii_case("BEGIN")) {
            return ToolTable::tnc(text);
        }
        let mut tools: Vec<(u32, f64)> = Vec::new();
        for (k, raw) in text.lines().enumerate() {
            let line = k + 1;
            let body = raw.split(';').next().unwrap_or("").trim();
            if body.is_empty() {
                continue;
            }
            let (mut tool, mut diameter) = (None, 0.0);
            for word in body.split_whitespace() {
                let mut chars = word.chars();
                let letter = chars.next().map(|c| c.to_ascii_uppercase()).unwrap_or(' ');
                let value: f64 = chars.as_str().parse().map_err(|_| format!("line {line}: '{word}': expected a letter and a number"))?;
                if !value.is_finite() {
                    return Err(format!("line {line}: '{word}': not a finite number"));
                }
                match letter {
                    'T' if value >= 0.0 && value.fract() == 0.0 && value <= u32::MAX as f64 => tool = Some(value as u32),
                    'T' => return Err(format!("line {line}: '{word}': a tool number is a whole number 0 or more")),
                    'D' => diameter = value,
                    'P' | 'X' | 'Y' | 'Z' | 'A' | 'B' | 'C' | 'U' | 'V' | 'W' | 'I' | 'J' | 'Q' => {}
                    _ => return Err(format!("line {line}: '{word}': not a word of a LinuxCNC tool table (T P X Y Z A B C U V W D I J Q)")),
                }
            }
            let Some(tool) = tool else { return Err(format!("line {line}: no T word (the tool's number)")) };
            add(&mut tools, line, tool, diameter)?;
        }
        Ok(ToolTable { tools, names: Vec::new(), deltas: Vec::new(), unit: crate::units::MM, unit_from_header: false })
    }

    /// Read a Heidenhain TNC tool table (`TOOL.T`, as the control writes it and pyLSV2's
    /// table_reader reads it): `BEGIN <name>.T MM` (or `INCH`, perhaps `Version: '...'` after),
    /// perhaps a `#STRUCTBEGIN`..`#STRUCTEND` or `TableDescription (`..`)` block, a line of column
    /// names, one line per tool with each value under its column's name, and `[END]`. A column's
    /// text runs from its name's first character to the next name's. Each tool's diameter is
    /// 2 (R + DR), the table's part of the TNC's compensation value R + DR_TAB + DR_PROG (TNC 620
    /// user's manual 01/2022 p. 134); an empty DR is 0, an empty T or R an error. A header without
    /// a unit leaves it to [`ToolTable::in_unit`].
    fn tnc(text: &str) -> Result<ToolTable, String> {
        let mut lines = text.lines().enumerate().map(|(k, raw)| (k + 1, raw)).filter(|(_, raw)| !raw.trim().is_empty());
        let Some((begin, header)) = lines.next() else { return Err("no BEGIN line".into()) };
        // The words after the table's name, up to a `Version:`: MM or INCH where the header names one.
        let unit = header
            .split_whitespace()
            .skip(2)
            .take_while(|w| !w.get(..7).is_some_and(|v| v.eq_ignore_ascii_case("VERSION")))
            .find_map(|w| match w.to_ascii_uppercase().as_str() {
                "MM" => Some(crate::units::MM),
                "INCH" => Some(crate::units::INCH),
                _ => None,
            });
        let no_names = || format!("line {begin}: no line of column names after BEGIN");
        let (mut at, mut names) = lines.next().ok_or_else(no_names)?;
        // A description of the columns (pyLSV2's table types 2 and 3), which the names' line follows.
        let structure = names.trim_start().starts_with("#STRUCTBEGIN");
        if structure || names.trim_start().starts_with("TableDescription") {
            let (open, closing) = (at, if structure { "#STRUCTEND" } else { ")" });
            let closes = |raw: &str| if structure { raw.trim_start().starts_with(closing) } else { raw.starts_with(closing) };
            loop {
                let (_, raw) = lines.next().ok_or_else(|| format!("line {open}: the description of the columns has no end ('{closing}' at a line's start)"))?;
                if closes(raw) {
                    break;
                }
            }
            (at, names) = lines.next().ok_or_else(no_names)?;
        }
        let cols = columns(names);
        let span = |name: &str| cols.iter().position(|c| c.0 == name).map(|k| (cols[k].1, cols.get(k + 1).map(|c| c.1)));
        let Some(t_span) = span("T") else { return Err(format!("line {at}: no column T (the tool's number) among the column names")) };
        let Some(r_span) = span("R") else { return Err(format!("line {at}: no column R (the tool's radius) among the column names")) };
        let dr_span = span("DR");
        let dr2_span = span("DR2");
        let mut deltas: Vec<(u32, f64, f64)> = Vec::new();
        let name_span = span("NAME");
        let mut tools: Vec<(u32, f64)> = Vec::new();
        let mut named: Vec<(String, u32)> = Vec::new();
        let mut ended = false;
        for (line, raw) in lines {
            if ended {
                return Err(format!("line {line}: text after [END]"));
            }
            if raw.trim().eq_ignore_ascii_case("[END]") {
                ended = true;
                continue;
            }
            let t = cell(raw, t_span);
            if t.is_empty() {
                return Err(format!("line {line}: column T is empty (the tool's number)"));
            }
            let tool: u32 = t.parse().map_err(|_| format!("line {line}: column T: '{t}': a tool number is a whole number 0 or more"))?;
            let r = cell(raw, r_span);
            if r.is_empty() {
                return Err(format!("line {line}: column R is empty (the tool's radius)"));
            }
            let radius = number(line, "R", r)?;
            let delta = match dr_span.map(|s| cell(raw, s)).filter(|d| !d.is_empty()) {
                Some(d) => number(line, "DR", d)?,
                None => 0.0,
            };
            let diameter = 2.0 * (radius + delta);
            if !diameter.is_finite() {
                return Err(format!("line {line}: columns R and DR: 2 (R + DR) is not a finite number"));
            }
            add(&mut tools, line, tool, diameter)?;
            let delta2 = match dr2_span.map(|s| cell(raw, s)).filter(|d| !d.is_empty()) {
                Some(d) => number(line, "DR2", d)?,
                None => 0.0,
            };
            // A tool listed again takes its last line's deltas.
            deltas.retain(|(t, _, _)| *t != tool);
            if delta != 0.0 || delta2 != 0.0 {
                deltas.push((tool, delta, delta2));
            }
            // A tool listed again takes its last line's name, or none.
            named.retain(|(_, t)| *t != tool);
            if let Some(name) = name_span.map(|s| cell(raw, s)).filter(|n| !n.is_empty()) {
                named.push((name.to_ascii_uppercase(), tool));
            }
        }
        Ok(ToolTable { tools, names: named, deltas, unit: unit.unwrap_or(crate::units::MM), unit_from_header: unit.is_some() })
    }

    /// The table with its numbers in `unit` (an inch machine's LinuxCNC table). A TNC table whose
    /// header names its unit (`BEGIN TOOL.T INCH`) keeps that one, as the control reads it by its
    /// header whatever `--tool-table-units` says.
    pub fn in_unit(mut self, unit: crate::program::LengthUnit) -> ToolTable {
        if !self.unit_from_header {
            self.unit = unit.metres();
        }
        self
    }

    /// Set a tool's diameter (m), as `G10 L1 P R` does; false where the table has no such tool.
    pub(crate) fn set_diameter(&mut self, tool: u32, diameter: f64) -> bool {
        match self.tools.iter_mut().find(|(t, _)| *t == tool) {
            Some(entry) => {
                entry.1 = diameter / self.unit;
                true
            }
            None => false,
        }
    }

    /// The radius deltas DR and DR2 (m) of a TNC table's tool where either is not 0.
    pub fn radius_deltas(&self, tool: u32) -> Option<(f64, f64)> {
        self.deltas.iter().find(|(t, _, _)| *t == tool).map(|&(_, dr, dr2)| (dr * self.unit, dr2 * self.unit))
    }

    /// The numbers of a TNC table's tools named `name` (capitals and small letters alike).
    pub fn numbers_named<'a>(&'a self, name: &'a str) -> impl Iterator<Item = u32> + 'a {
        self.names.iter().filter(move |(n, _)| n.eq_ignore_ascii_case(name)).map(|&(_, t)| t)
    }

    /// A tool's diameter, m.
    pub fn diameter(&self, tool: u32) -> Option<f64> {
        self.tools.iter().find(|(t, _)| *t == tool).map(|(_, d)| *d * self.unit)
    }

    /// The diameter (m) of the tool a TNC's `TOOL CALL "name"` calls, by the table's NAME column
    /// (capitals and small letters alike: the control keeps names in capitals). A name is not
    /// unique: "If you define identical tool names for multiple tools, the control looks for the
    /// tool" in the spindle, then the magazine, then the table, the one "with least remaining tool
    /// life" among several (TNC7 user's manual 81762x-16, "Tool name"), so tools sharing the name
    /// must share the diameter for it to be known here; why not, else.
    pub fn diameter_by_name(&self, name: &str) -> Result<f64, String> {
        let raw = |tool: u32| self.tools.iter().find(|(t, _)| *t == tool).map(|(_, d)| *d);
        let mut found = self.names.iter().filter(|(n, _)| n.eq_ignore_ascii_case(name)).map(|&(_, t)| (t, raw(t)));
        let Some((first, Some(d))) = found.next() else {
            return Err(format!("no tool named \"{name}\" in the tool table (its NAME column)"));
        };
        if let Some((other, od)) = found.find(|(_, od)| *od != Some(d)) {
            let shown = |d: Option<f64>| d.map_or("none".to_string(), |d| format!("{}", d * self.unit / 2.0 / crate::units::MM));
            return Err(format!(
                "tools {first} and {other} are both named \"{name}\" with radii (R + DR) {} and {} mm: which one the TNC calls depends on the magazine and the tools' lives (TNC7 user's manual, \"Tool name\")",
                shown(Some(d)),
                shown(od)
            ));
        }
        Ok(d * self.unit)
    }
}

/// Put a tool's diameter in the table, a later line's replacing an earlier one's; past
/// [`MAX_TOOLS`] lines of tools, an error.
fn add(tools: &mut Vec<(u32, f64)>, line: usize, tool: u32, diameter: f64) -> Result<(), String> {
    if tools.len() >= MAX_TOOLS {
        return Err(format!("line {line}: more than {MAX_TOOLS} tools"));
    }
    match tools.iter_mut().find(|(t, _)| *t == tool) {
        Some(entry) => entry.1 = diameter,
        None => tools.push((tool, diameter)),
    }
    Ok(())
}

/// A TNC table's column names and the character each starts at.
fn columns(names: &str) -> Vec<(&str, usize)> {
    let mut out = Vec::new();
    let mut word: Option<(usize, usize)> = None; // (byte, character) where the name starts
    for (n, (b, c)) in names.char_indices().enumerate() {
        match (c.is_whitespace(), word) {
            (false, None) => word = Some((b, n)),
            (true, Some((start, first))) => {
                out.push((&names[start..b], first));
                word = None;
            }
            _ => {}
        }
    }
    if let Some((start, first)) = word {
        out.push((&names[start..], first));
    }
    out
}

/// A row's text from character `from` to before `to` (to its end without), trimmed: a TNC
/// table's value under its column's name; empty where the row is shorter.
fn cell(row: &str, (from, to): (usize, Option<usize>)) -> &str {
    let byte = |n: usize| row.char_indices().nth(n).map_or(row.len(), |(b, _)| b);
    let start = byte(from);
    let end = to.map_or(row.len(), byte).max(start);
    row[start..end].trim()
}

/// A TNC table's value, a finite number (`+5`, `-0.02`).
fn number(line: usize, column: &str, text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("line {line}: column {column}: '{text}': not a number")),
    }
}

/// The tool selected (`T`) and the one in the spindle (`M6`, `M61 Q`): what `G41`/`G42` without a
/// `D` (or with `D0`) compensate by.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Tools {
    selected: Option<u32>,
    pub(super) spindle: Option<u32>,
}

impl Tools {
    /// The tool a `T` word selected, and the one `M6` or `M61 Q` put in the spindle, where the
    /// program said (LinuxCNC's `#<_selected_tool>`, `#5400`).
    pub(crate) fn known(&self) -> (Option<u32>, Option<u32>) {
        (self.selected, self.spindle)
    }

    /// A block's `T`, `M6` and `M61 Q`.
    pub(super) fn track(&mut self, words: &[Word]) {
        let whole = |w: &&Word| w.value >= 0.0 && w.value.fract() == 0.0 && w.value <= u32::MAX as f64;
        if let Some(t) = words.iter().find(|w| w.letter == 'T').filter(whole) {
            self.selected = Some(t.value as u32);
        }
        if words.iter().any(|w| w.letter == 'M' && w.value == 6.0) {
            self.spindle = self.selected;
        }
        if words.iter().any(|w| w.letter == 'M' && w.value == 61.0) {
            if let Some(q) = words.iter().find(|w| w.letter == 'Q').filter(whole) {
                self.spindle = Some(q.value as u32);
            }
        }
    }
}


#[cfg(test)]
mod tests {
    use super::*;
    use crate::program::LengthUnit;

    /// A TNC 640's TOOL.T (its first columns, laid out as pyLSV2's test table from a programming
    /// station is): tool 1 R+1, tool 5 R+5 with DR-0.02, tool 12 R+3.4 with DR empty.
    const TOOL_T: &str = "\
BEGIN TOOL.T MM Version: 'Update:110.24'
T       NAME                            L           R           R2          DL        DR        DR2       TL RT      TIME1 TIME2 CUR_TIME TYP      DOC
1       MILL_D2_ROUGH                   +30         +1          +0          +0        +0        +0                   0     0     0        0        roughing
5       MILL_D10                        +60         +5          +0          +0        -0.02     +0                   0     0     0        0        worn 0.02
12      DRILL_D6.8                      +85.5       +3.4        +0          +0                  +0                   0     0     0        0
[END]
";

    fn close(got: Option<f64>, want: f64) -> bool {
        got.is_some_and(|d| (d - want).abs() < 1e-12)
    }

    /// Each tool's diameter is 2 (R + DR) in the header's mm: tool 1 2 (1 + 0) = 2 mm = 0.002 m;
    /// tool 5 2 (5 - 0.02) = 9.96 mm = 0.00996 m; tool 12 2 (3.4 + 0) = 6.8 mm = 0.0068 m (an
    /// empty DR is 0). `--tool-table-units inch` leaves the header's mm.
    #[test]
    fn a_tnc_table_gives_r_plus_dr() {
        let table = ToolTable::parse(TOOL_T).unwrap();
        assert!(close(table.diameter(1), 0.002), "{table:?}");
        assert!(close(table.diameter(5), 0.00996), "{table:?}");
        assert!(close(table.diameter(12), 0.0068), "{table:?}");
        assert_eq!(table.diameter(2), None);
        let inch = table.clone().in_unit(LengthUnit::Inch);
        assert_eq!(inch, table);
        // Without [END], and with blank lines before BEGIN and after the rows, the same.
        let open = format!("\n  \n{}\n\n", TOOL_T.trim_end().strip_suffix("[END]").unwrap());
        assert_eq!(ToolTable::parse(&open), Ok(table));
    }

    /// An inch table (the name spaced from `.T`, as some controls write it): tool 3 R+0.25 DR+0.01
    /// is 2 (0.25 + 0.01) = 0.52 in = 0.52 x 25.4 mm = 13.208 mm = 0.013208 m, whatever
    /// `--tool-table-units` says; a header without a unit leaves it to that (0.52 mm).
    #[test]
    fn a_tnc_tables_header_names_its_unit() {
        let text = "BEGIN TOOL    .T INCH\nT    NAME   R       DR\n3    BALL   +0.25   +0.01\n[END]\n";
        let table = ToolTable::parse(text).unwrap();
        assert!(close(table.diameter(3), 0.013208), "{table:?}");
        assert!(close(table.in_unit(LengthUnit::Mm).diameter(3), 0.013208));
        let bare = ToolTable::parse(&text.replace(" INCH", "")).unwrap();
        assert!(close(bare.diameter(3), 0.00052));
        assert!(close(bare.in_unit(LengthUnit::Inch).diameter(3), 0.013208));
    }

    /// Faults name the line and the column: no R among the names (line 2), a comma for the point
    /// (line 4, R), an empty T or R, text after [END], a description of the columns without end.
    #[test]
    fn a_tnc_tables_faults_name_line_and_column() {
        let err = |text: &str| ToolTable::parse(text).unwrap_err();
        assert_eq!(err("BEGIN TOOL.T MM\nT    NAME   L       DR\n1    A      +30     +0\n[END]\n"), "line 2: no column R (the tool's radius) among the column names");
        assert_eq!(err("BEGIN TOOL.T MM\nNAME   R\nA      +1\n"), "line 2: no column T (the tool's number) among the column names");
        let bad = TOOL_T.replace("+5          +0", "+2,5        +0");
        assert_eq!(err(&bad), "line 4: column R: '+2,5': not a number");
        assert_eq!(err(&TOOL_T.replace("-0.02", "-O.02")), "line 4: column DR: '-O.02': not a number");
        assert_eq!(err(&TOOL_T.replace("\n12 ", "\n   ")), "line 5: column T is empty (the tool's number)");
        assert_eq!(err(&TOOL_T.replace("\n5  ", "\n5.1")), "line 4: column T: '5.1': a tool number is a whole number 0 or more");
        assert_eq!(err(&TOOL_T.replace("+3.4", "    ")), "line 5: column R is empty (the tool's radius)");
        assert_eq!(err(&format!("{TOOL_T}\nT99\n")), "line 8: text after [END]");
        assert_eq!(err("BEGIN TOOL.T MM\n"), "line 1: no line of column names after BEGIN");
        assert_eq!(err("BEGIN TOOL.T MM\n#STRUCTBEGIN\n   NAME = T\n"), "line 2: the description of the columns has no end ('#STRUCTEND' at a line's start)");
        // A description of the columns before their names is passed over.
        let described = "BEGIN TOOL.T MM\nTableDescription (\n  columns:= [\n    CfgColumnDescription (\n      key:=\"T\"\n    )\n  ]\n)\nT    R\n7    +2\n[END]\n";
        assert!(close(ToolTable::parse(described).unwrap().diameter(7), 0.004));
    }

    /// A LinuxCNC table reads as before: D is the diameter in the machine's unit, `in_unit` sets
    /// it (T2 D0.25 in inches is 0.25 x 25.4 = 6.35 mm), a tool listed twice takes its last line.
    #[test]
    fn a_linuxcnc_table_still_reads() {
        let table = ToolTable::parse("; tools\nT1 P1 D10 Z0 ;end mill\nT2 P2 D0.25\nT1 P1 D8\n").unwrap();
        assert!(close(table.diameter(1), 0.008));
        assert!(close(table.clone().in_unit(LengthUnit::Inch).diameter(2), 0.00635));
        assert_eq!(ToolTable::parse("T1 D10\nX1\n").unwrap_err(), "line 2: no T word (the tool's number)");
    }
}
