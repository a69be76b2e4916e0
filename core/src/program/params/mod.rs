//! RS274NGC parameters and expressions as LinuxCNC reads them (LinuxCNC manual §11.4.3-11.4.8):
//! numbered `#31`, named `#<name>` and `#<_global>` parameters, `[...]` expressions with the binary
//! operators in their five precedence groups, and the unary functions (angles in degrees).
//!
//! A real value is a number, a parameter, an expression, a unary function or one of those with a
//! sign (`X-#3`). A line's parameter settings take effect after every value on it is read (`#3=6
//! G1 X#3` moves to the old `#3`). Pure: no I/O, columns are 1-based characters of the line.
//!
//! Fail closed where the program's meaning would depend on state this reader does not have: a named
//! parameter read before it is set is an error (as in LinuxCNC), so is a numbered one (LinuxCNC
//! reads 0, a Fanuc control reads it as vacant and drops the word), and so is any parameter of the
//! machine's state (numbered 5001 and up: offsets, tool, position; predefined named ones such as
//! `#<_x>`, `#<_ini[...]>`).

use std::collections::HashMap;

pub mod expr;

/// Highest user-settable numbered parameter: 1-30 subroutine arguments, 31-5000 user parameters.
pub const MAX_USER_PARAMETER: u32 = 5000;
/// Highest numbered parameter LinuxCNC has (its system parameters run 5061-5602).
const MAX_PARAMETER: u32 = 5602;
/// LinuxCNC's flag for `(DEBUG,)` output, the one system parameter a program may set here: it moves
/// nothing ("5599 - Flag for controlling the output of (DEBUG,) statements. 1=output, 0=no output;
/// default=1. Volatile.", interp_parameter_def.hh; LinuxCNC's sample `offsets.ngc` sets it).
pub(crate) const DEBUG_FLAG: u32 = 5599;
/// Most distinct named parameters one program may set (the store stays bounded on any input).
pub const MAX_NAMED_PARAMETERS: usize = 100_000;
/// Longest parameter name, characters (LinuxCNC's whole line is 256): with the count above, the store's bound.
pub const MAX_NAME_CHARS: usize = 256;
/// A decimal meant as an integer (a parameter index, a tool number) may be this far from it (LinuxCNC
/// manual §11.4.2.4).
pub(crate) const INTEGER_CLOSE: f64 = 1e-4;

/// LinuxCNC's predefined read-only named parameters (manual §11.4.3.4-11.4.3.5): the interpreter's
/// and the machine's state, which this reader does not model.
const PREDEFINED: [&str; 56] = [
    "_vmajor", "_vminor", "_line", "_motion_mode", "_plane", "_ccomp", "_metric", "_imperial", "_absolute",
    "_incremental", "_inverse_time", "_units_per_minute", "_units_per_rev", "_coord_system", "_tool_offset",
    "_retract_r_plane", "_retract_old_z", "_spindle_rpm_mode", "_spindle_css_mode", "_ijk_absolute_mode",
    "_lathe_diameter_mode", "_lathe_radius_mode", "_spindle_on", "_spindle_cw", "_mist", "_flood",
    "_speed_override", "_feed_override", "_adaptive_feed", "_feed_hold", "_feed", "_rpm", "_x", "_y", "_z",
    "_a", "_b", "_c", "_u", "_v", "_w", "_abs_x", "_abs_y", "_abs_z", "_abs_a", "_abs_b", "_abs_c",
    "_current_tool", "_current_pocket", "_selected_tool", "_selected_pocket", "_value", "_value_returned",
    "_task", "_call_level", "_remap_level",
];

/// A value that could not be read: where (1-based column) and why.
#[derive(Debug, Clone, PartialEq)]
pub struct ExprError {
    pub column: usize,
    pub message: String,
    /// The control stops here (Fanuc's macro alarm `#3000`): nothing after it runs.
    pub stops: bool,
}

fn err<T>(column: usize, message: impl Into<String>) -> Result<T, ExprError> {
    Err(ExprError { column, message: message.into(), stops: false })
}

/// A parameter a setting writes.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    Numbered(u32),
    Named(String),
}

impl std::fmt::Display for Target {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Target::Numbered(n) => write!(f, "#{n}"),
            Target::Named(s) => write!(f, "#<{s}>"),
        }
    }
}

/// The parameters a program has set.
#[derive(Debug, Clone, Default)]
pub struct Parameters {
    numbered: HashMap<u32, f64>,
    named: HashMap<String, f64>,
    /// The machine's HAL pins a program may read (`#<_hal[name]>`), by lower-case pin name, as its
    /// configuration sets them (the machine file's `hal_pins`).
    hal_pins: std::collections::BTreeMap<String, f64>,
    /// The interpreter's state as LinuxCNC's predefined parameters give it (`#<_x>`, `#<_metric>`,
    /// `#5420`, ...), where the reader knows it: set before each line is read ([`Parameters::set_state`]).
    state: StateParameters,
    /// Fanuc and Haas: #1000 and up are the control's system variables, not the program's.
    fanuc: bool,
}

/// The interpreter's state as LinuxCNC's predefined parameters give it: named ones (`_x`) and
/// numbered ones (`5420`), with their values.
#[derive(Debug, Clone, Default)]
pub struct StateParameters {
    pub named: Vec<(&'static str, f64)>,
    pub numbered: Vec<(u32, f64)>,
}

impl Parameters {
    /// Parameters that can read these HAL pins (lower-case names) as `#<_hal[name]>`.
    pub fn with_hal_pins(hal_pins: std::collections::BTreeMap<String, f64>) -> Parameters {
        Parameters { hal_pins, ..Default::default() }
    }

    /// Read the real value that starts at `chars[i]` (after blanks): its value and the index after it
    /// (`fanuc`: by Fanuc's rules for FIX, FUP, AND, OR and XOR).
    pub fn real_value(&self, chars: &[char], i: usize, fanuc: bool) -> Result<(f64, usize), ExprError> {
        let (c, end) = expr::value(chars, i, fanuc)?;
        Ok((c.eval(self)?, end))
    }

    /// Fanuc's macro statement `#i = <expression>` at `chars[i] == '#'`: what it sets, the value
    /// and the index after it. Nothing is set (the caller does). The expression runs on without
    /// brackets (FANUC B-64484EN, "Custom macro": "#i = <expression>", brackets only to group).
    pub fn macro_setting(&self, chars: &[char], i: usize) -> Result<(Target, f64, usize), ExprError> {
        let (s, end) = expr::setting(chars, i, true)?;
        let (target, v) = s.run(self)?;
        Ok((target, v, end))
    }

    /// The interpreter's state now, as its predefined named and numbered parameters (LinuxCNC
    /// manual §11.4.3.4, §11.4.2.7): what a line reads of them. One not given stays refused.
    pub fn set_state(&mut self, state: StateParameters) {
        self.state = state;
    }

    /// Read `#1000` and up as Fanuc's and Haas' system variables (those of the state given by
    /// [`Parameters::set_state`]; any other is refused as the control's).
    pub fn fanuc_system_variables(&mut self) {
        self.fanuc = true;
    }

    /// Set a parameter (a line's settings, after every value on the line was read).
    pub fn set(&mut self, target: Target, value: f64, column: usize) -> Result<(), ExprError> {
        match target {
            Target::Numbered(n) => {
                self.numbered.insert(n, value);
            }
            Target::Named(name) => {
                if self.named.len() >= MAX_NAMED_PARAMETERS && !self.named.contains_key(&name) {
                    return err(column, format!("more than {MAX_NAMED_PARAMETERS} named parameters"));
                }
                self.named.insert(name, value);
            }
        }
        Ok(())
    }
}

/// What a subroutine call set aside: the caller's `#1`-`#30` and its local named parameters.
#[derive(Debug, Clone)]
pub struct Scope {
    numbered: Vec<(u32, f64)>,
    named: Vec<(String, f64)>,
    /// `#1`-`#30` were left to the subroutine as they stood (a Fanuc-style `M98` call).
    kept_numbered: bool,
}

impl Parameters {
    /// Enter a subroutine (LinuxCNC manual, O codes, "Subroutines": `#1`-`#30` are its arguments and
    /// its own, as are the named parameters it sets whose name does not begin with `_`). Those the
    /// call does not give are 0 ("zero the remaining params", interp_read.cc read_o).
    pub fn enter_call(&mut self, args: &[f64]) -> Scope {
        let numbered = (1..=30).filter_map(|n| self.numbered.remove(&n).map(|v| (n, v))).collect();
        let named = self.take_named_locals();
        for k in 0..30 {
            self.numbered.insert(k as u32 + 1, args.get(k).copied().unwrap_or(0.0));
        }
        Scope { numbered, named, kept_numbered: false }
    }

    /// Enter a Fanuc-style subprogram (`M98`; LinuxCNC's interp_o_word.cc execute_call, "M98: pass
    /// #1..#30 from parent"): `#1`-`#30` stay as they are, shared with the caller; the named
    /// parameters it sets whose name does not begin with `_` are its own, as a subroutine's.
    pub fn enter_m98(&mut self) -> Scope {
        Scope { numbered: Vec::new(), named: self.take_named_locals(), kept_numbered: true }
    }

    /// The caller's named parameters without a leading `_` (its own), set aside for a call.
    fn take_named_locals(&mut self) -> Vec<(String, f64)> {
        let locals: Vec<String> = self.named.keys().filter(|k| !k.starts_with('_')).cloned().collect();
        locals.into_iter().filter_map(|k| self.named.remove(&k).map(|v| (k, v))).collect()
    }

    /// Leave a subroutine: its own parameters go, the caller's come back.
    pub fn leave_call(&mut self, scope: Scope) {
        if !scope.kept_numbered {
            for n in 1..=30 {
                self.numbered.remove(&n);
            }
        }
        self.named.retain(|k, _| k.starts_with('_'));
        self.numbered.extend(scope.numbered);
        self.named.extend(scope.named);
    }
}

impl Parameters {
    /// Enter a Fanuc macro (`G65`): the local variables `#1`-`#33` are its own, vacant but for its
    /// arguments (FANUC B-64484EN, "Custom macro", local variables and argument specification I).
    pub fn enter_locals(&mut self, args: &[(u32, f64)]) -> Scope {
        let numbered = (1..=33).filter_map(|n| self.numbered.remove(&n).map(|v| (n, v))).collect();
        self.numbered.extend(args.iter().copied());
        Scope { numbered, named: Vec::new(), kept_numbered: false }
    }

    /// Leave a Fanuc macro: its locals go, the caller's come back.
    pub fn leave_locals(&mut self, scope: Scope) {
        for n in 1..=33 {
            self.numbered.remove(&n);
        }
        self.numbered.extend(scope.numbered);
    }
}

/// The index of the first character at or after `i` that is not a space or tab.
pub fn skip_blanks(chars: &[char], mut i: usize) -> usize {
    while chars.get(i).is_some_and(|c| *c == ' ' || *c == '\t') {
        i += 1;
    }
    i
}

impl Parameters {
    /// A numbered parameter's value, where the program set it (see the module's fail-closed rules).
    fn read_numbered(&self, n: u32, column: usize) -> Result<f64, ExprError> {
        // The control's own (Fanuc's and Haas' from #1000, LinuxCNC's above #5000): the state given,
        // or refused.
        if !self.fanuc && n == DEBUG_FLAG {
            return Ok(self.numbered.get(&n).copied().unwrap_or(1.0));
        }
        if if self.fanuc { n >= 1000 } else { n > MAX_USER_PARAMETER } {
            if let Some(&(_, v)) = self.state.numbered.iter().find(|(k, _)| *k == n) {
                return Ok(v);
            }
            return err(column, match self.fanuc {
                true => format!("#{n} is a system variable of the control (#1000 and up: signals, offsets, clocks, positions, modal information beyond the G code groups, F, S and T this reader holds): not read"),
                false => format!("#{n} is a system parameter (offsets, tool, position): the machine's state is not modelled"),
            });
        }
        match self.numbered.get(&n) {
            Some(&v) => Ok(v),
            None => err(column, format!("#{n} is read before the program sets it (LinuxCNC reads 0, a Fanuc control reads it as vacant): not read")),
        }
    }

    /// A named parameter's value (`name` lower case, without blanks). The machine's HAL pins and
    /// state are read as such whatever the program set (a Fanuc macro may write `#<_x>`, which then
    /// still reads as the machine's state).
    fn read_named(&self, name: &str, column: usize) -> Result<f64, ExprError> {
        // The machine's names all start with '_' (most a program's own do not: no look at them).
        if name.starts_with('_') {
            // A HAL pin the machine's configuration gives (LinuxCNC manual §11.4.3.6, HAL_PIN_VARS).
            if let Some(pin) = name.strip_prefix("_hal[").and_then(|n| n.strip_suffix(']')) {
                return match self.hal_pins.get(pin) {
                    Some(&v) => Ok(v),
                    None => err(column, format!("#<{name}>: the machine file gives no HAL pin '{pin}' (its hal_pins table)")),
                };
            }
            if let Some(pin) = name.strip_prefix("_hal[") {
                return err(column, format!("#<{name}>: the machine file gives no HAL pin '{pin}' (its hal_pins table)"));
            }
            if let Some(&(_, v)) = self.state.named.iter().find(|(k, _)| *k == name) {
                return Ok(v);
            }
            if is_machine_state(name) {
                return err(column, format!("#<{name}> is the interpreter's or the machine's state: not modelled"));
            }
        }
        match self.named.get(name) {
            Some(&v) => Ok(v),
            None => err(column, format!("named parameter #<{name}> is not defined (read before it is set)")),
        }
    }

    /// Whether the program has set this named parameter (`EXISTS`).
    fn has_named(&self, name: &str) -> bool {
        self.named.contains_key(name)
    }
}

/// A predefined named parameter (LinuxCNC's read-only state, INI values or HAL pins).
fn is_machine_state(name: &str) -> bool {
    PREDEFINED.contains(&name) || name.starts_with("_ini[") || name.starts_with("_hal[")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(p: &Parameters, s: &str) -> Result<f64, ExprError> {
        let chars: Vec<char> = s.chars().collect();
        let (v, end) = p.real_value(&chars, 0, false)?;
        assert_eq!(end, chars.len(), "{s}: read up to {end}");
        Ok(v)
    }

    /// The precedence example of the LinuxCNC manual §11.4.6: `[2.0 / 3 * 1.5 - 5.5 / 11.0]` is 0.5.
    #[test]
    fn groups_and_left_to_right() {
        let p = Parameters::default();
        assert!((eval(&p, "[2.0 / 3 * 1.5 - 5.5 / 11.0]").unwrap() - 0.5).abs() < 1e-15);
        assert_eq!(eval(&p, "[2 ** 3 ** 2]").unwrap(), 64.0);
        assert_eq!(eval(&p, "[1 + 2 * 3 EQ 7 AND 1]").unwrap(), 1.0);
        assert_eq!(eval(&p, "[1 + acos[0] - [2 ** [4.0/2]]]").unwrap(), 87.0);
    }

    #[test]
    fn refusals_name_their_column() {
        let mut p = Parameters::default();
        p.set(Target::Named("a".into()), 1.0, 1).unwrap();
        for (s, col, what) in [
            ("[1/0]", 3, "division by zero"),
            ("[1 + 2", 1, "not closed"),
            ("#<b>", 1, "not defined"),
            ("#7", 1, "before the program sets it"),
            ("#5221", 1, "system parameter"),
            ("#<_x>", 1, "machine's state"),
            ("SQRT[-1]", 1, "must not be negative"),
            ("FOO[1]", 1, "unknown function FOO"),
            ("[#<a> # 2]", 7, "expected an operator"),
        ] {
            let e = eval(&p, s).unwrap_err();
            assert_eq!(e.column, col, "{s}: {e:?}");
            assert!(e.message.contains(what), "{s}: {e:?}");
        }
        // The machine's state reads as such even where a program (a Fanuc macro) wrote it.
        p.set(Target::Named("_x".into()), 5.0, 1).unwrap();
        assert!(eval(&p, "#<_x>").unwrap_err().message.contains("machine's state"));
        let long = format!("#<{}>", "n".repeat(MAX_NAME_CHARS + 1));
        assert!(eval(&p, &long).unwrap_err().message.contains("longer than 256"));
        let deep = format!("{}1{}", "[".repeat(200), "]".repeat(200));
        assert!(eval(&p, &deep).unwrap_err().message.contains("nested more than"));
    }
}
