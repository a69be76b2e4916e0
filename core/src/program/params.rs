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

/// Highest user-settable numbered parameter: 1-30 subroutine arguments, 31-5000 user parameters.
pub const MAX_USER_PARAMETER: u32 = 5000;
/// Highest numbered parameter LinuxCNC has (its system parameters run 5061-5602).
const MAX_PARAMETER: u32 = 5602;
/// Most distinct named parameters one program may set (the store stays bounded on any input).
pub const MAX_NAMED_PARAMETERS: usize = 100_000;
/// Longest parameter name, characters (LinuxCNC's whole line is 256): with the count above, the store's bound.
pub const MAX_NAME_CHARS: usize = 256;
/// Deepest nesting of brackets, functions and `#` in one value (the reader's recursion stays bounded).
const MAX_DEPTH: usize = 64;
/// LinuxCNC's `TOLERANCE_EQUAL`: EQ and NE compare within it; the other comparisons are strict.
const TOLERANCE_EQUAL: f64 = 1e-4;
/// A decimal meant as an integer (a parameter index) may be this far from it (LinuxCNC manual §11.4.2.4).
const INTEGER_CLOSE: f64 = 1e-4;

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
}

fn err<T>(column: usize, message: impl Into<String>) -> Result<T, ExprError> {
    Err(ExprError { column, message: message.into() })
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

/// The binary operators by precedence group (LinuxCNC manual table 11.5), lowest first.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Op {
    And,
    Or,
    Xor,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    Add,
    Sub,
    Mul,
    Div,
    Mod,
    Pow,
}

impl Op {
    fn precedence(self) -> u8 {
        match self {
            Op::And | Op::Or | Op::Xor => 0,
            Op::Eq | Op::Ne | Op::Gt | Op::Ge | Op::Lt | Op::Le => 1,
            Op::Add | Op::Sub => 2,
            Op::Mul | Op::Div | Op::Mod => 3,
            Op::Pow => 4,
        }
    }

    /// LinuxCNC's `execute_binary`: MOD is non-negative for a positive divisor (`fmod`, then plus
    /// `|b|` if negative), `**` of a negative base needs a whole exponent, logic is on non-zero.
    fn apply(self, a: f64, b: f64, column: usize) -> Result<f64, ExprError> {
        let truth = |x: bool| if x { 1.0 } else { 0.0 };
        let v = match self {
            Op::And => truth(a != 0.0 && b != 0.0),
            Op::Or => truth(a != 0.0 || b != 0.0),
            Op::Xor => truth((a != 0.0) != (b != 0.0)),
            Op::Eq => truth((a - b).abs() < TOLERANCE_EQUAL),
            Op::Ne => truth((a - b).abs() >= TOLERANCE_EQUAL),
            Op::Gt => truth(a > b),
            Op::Ge => truth(a >= b),
            Op::Lt => truth(a < b),
            Op::Le => truth(a <= b),
            Op::Add => a + b,
            Op::Sub => a - b,
            Op::Mul => a * b,
            Op::Div if b == 0.0 => return err(column, "division by zero"),
            Op::Div => a / b,
            Op::Mod if b == 0.0 => return err(column, "MOD by zero"),
            Op::Mod => {
                let r = a % b;
                if r < 0.0 { r + b.abs() } else { r }
            }
            Op::Pow if a < 0.0 && b.fract() != 0.0 => return err(column, format!("{a} ** {b}: a negative number to a non-integer power")),
            Op::Pow => a.powf(b),
        };
        if v.is_finite() { Ok(v) } else { err(column, format!("the result is not a finite number ({a} and {b})")) }
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
}

/// Reads values from one line's characters.
struct Reader<'a> {
    params: &'a Parameters,
    chars: &'a [char],
    depth: usize,
}

impl Parameters {
    /// Parameters that can read these HAL pins (lower-case names) as `#<_hal[name]>`.
    pub fn with_hal_pins(hal_pins: std::collections::BTreeMap<String, f64>) -> Parameters {
        Parameters { hal_pins, ..Default::default() }
    }

    /// Read the real value that starts at `chars[i]` (after blanks): its value and the index after it.
    pub fn real_value(&self, chars: &[char], i: usize) -> Result<(f64, usize), ExprError> {
        Reader { params: self, chars, depth: 0 }.value(i)
    }

    /// Read the parameter setting `#ref = value` that starts at `chars[i] == '#'`: what it sets, the
    /// value, and the index after it. Nothing is set: the caller sets the line's settings after it.
    /// A system parameter or the machine's state is refused: this reader does not model them.
    pub fn setting(&self, chars: &[char], i: usize) -> Result<(Target, f64, usize), ExprError> {
        let mut r = Reader { params: self, chars, depth: 0 };
        let (target, j) = r.reference(i)?;
        match &target {
            Target::Numbered(n) if *n > MAX_USER_PARAMETER => return err(i + 1, format!("{target} is a system parameter (offsets, tool, position): setting it is not modelled")),
            Target::Named(n) if is_machine_state(n) => return err(i + 1, format!("{target} is read-only (the interpreter's or the machine's state)")),
            _ => {}
        }
        let j = r.blank(j);
        if chars.get(j) != Some(&'=') {
            return err(i + 1, format!("{target} stands alone: expected '=' and a value to set it (or a word letter before it)"));
        }
        let (v, k) = r.value(j + 1)?;
        Ok((target, v, k))
    }

    /// Fanuc's macro statement `#i = <expression>` at `chars[i] == '#'`: as [`Parameters::setting`],
    /// but the expression runs on without brackets (FANUC B-64484EN, "Custom macro": "#i = <expression>",
    /// brackets only to group), operators and functions as the parameters read them.
    pub fn macro_setting(&self, chars: &[char], i: usize) -> Result<(Target, f64, usize), ExprError> {
        let mut r = Reader { params: self, chars, depth: 0 };
        let (target, j) = r.reference(i)?;
        if let Target::Numbered(n) = &target {
            if *n > MAX_USER_PARAMETER {
                return err(i + 1, format!("{target} is a system variable (offsets, tool, position): setting it is not modelled"));
            }
        }
        let j = r.blank(j);
        if chars.get(j) != Some(&'=') {
            return err(i + 1, format!("{target} stands alone: expected '=' and an expression to set it (or a word letter before it)"));
        }
        let (v, k) = r.binary(j + 1, 0)?;
        Ok((target, v, k))
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
}

impl Parameters {
    /// Enter a subroutine (LinuxCNC manual, O codes, "Subroutines": `#1`-`#30` are its arguments and
    /// its own, as are the named parameters it sets whose name does not begin with `_`).
    pub fn enter_call(&mut self, args: &[f64]) -> Scope {
        let numbered = (1..=30).filter_map(|n| self.numbered.remove(&n).map(|v| (n, v))).collect();
        let locals: Vec<String> = self.named.keys().filter(|k| !k.starts_with('_')).cloned().collect();
        let named = locals.into_iter().filter_map(|k| self.named.remove(&k).map(|v| (k, v))).collect();
        for (k, v) in args.iter().enumerate() {
            self.numbered.insert(k as u32 + 1, *v);
        }
        Scope { numbered, named }
    }

    /// Leave a subroutine: its own parameters go, the caller's come back.
    pub fn leave_call(&mut self, scope: Scope) {
        for n in 1..=30 {
            self.numbered.remove(&n);
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
        Scope { numbered, named: Vec::new() }
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

impl Reader<'_> {
    fn blank(&self, i: usize) -> usize {
        skip_blanks(self.chars, i)
    }

    fn deeper(&mut self, column: usize) -> Result<(), ExprError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return err(column, format!("a value nested more than {MAX_DEPTH} deep"));
        }
        Ok(())
    }

    /// A real value (LinuxCNC `read_real_value`): `[expr]`, `#ref`, a sign before a non-number, a
    /// unary function, or a number.
    fn value(&mut self, i: usize) -> Result<(f64, usize), ExprError> {
        let i = self.blank(i);
        self.deeper(i + 1)?;
        let out = match self.chars.get(i) {
            None => err(i + 1, "expected a value, found the end of the line"),
            Some('[') => self.expression(i),
            Some('#') => {
                let (target, j) = self.reference(i)?;
                Ok((self.read(&target, i + 1)?, j))
            }
            Some(&c @ ('+' | '-')) if !self.chars.get(self.blank(i + 1)).is_some_and(|n| n.is_ascii_digit() || *n == '.') => {
                let (v, j) = self.value(i + 1)?;
                Ok((if c == '-' { -v } else { v }, j))
            }
            Some(c) if c.is_ascii_alphabetic() => self.function(i),
            Some(_) => self.number(i),
        };
        self.depth -= 1;
        out
    }

    fn number(&self, i: usize) -> Result<(f64, usize), ExprError> {
        let mut j = i;
        if matches!(self.chars.get(j), Some('+' | '-')) {
            j = self.blank(j + 1);
        }
        let digits = j;
        while self.chars.get(j).is_some_and(|c| c.is_ascii_digit() || *c == '.') {
            j += 1;
        }
        let text: String = self.chars[i..j].iter().filter(|c| !c.is_whitespace()).collect();
        match super::lex::parse_number(&text) {
            Some(v) if j > digits => Ok((v, j)),
            _ => {
                let found: String = self.chars[i..].iter().take_while(|c| !c.is_whitespace()).collect();
                err(i + 1, format!("expected a number, a parameter or an expression, found '{}'", super::lex::excerpt(&found)))
            }
        }
    }

    /// `[` expression `]`: operands and binary operators, by precedence, left to right within a group.
    fn expression(&mut self, i: usize) -> Result<(f64, usize), ExprError> {
        let (v, j) = self.binary(i + 1, 0)?;
        let j = self.blank(j);
        match self.chars.get(j) {
            Some(']') => Ok((v, j + 1)),
            Some(_) => {
                let found: String = self.chars[j..].iter().take_while(|c| !c.is_whitespace()).collect();
                err(j + 1, format!("expected an operator or ']', found '{}'", super::lex::excerpt(&found)))
            }
            None => err(i + 1, "'[' is not closed: expected ']' on the same line"),
        }
    }

    /// Precedence climbing: operands joined by operators of group `min` or higher.
    fn binary(&mut self, i: usize, min: u8) -> Result<(f64, usize), ExprError> {
        let (mut left, mut j) = self.value(i)?;
        loop {
            let Some((op, len, at)) = self.operator(j) else { return Ok((left, j)) };
            if op.precedence() < min {
                return Ok((left, j));
            }
            let (right, k) = self.binary(at + len, op.precedence() + 1)?;
            left = op.apply(left, right, at + 1)?;
            j = k;
        }
    }

    /// The binary operator at `i` (after blanks), its length and where it starts.
    fn operator(&self, i: usize) -> Option<(Op, usize, usize)> {
        let i = self.blank(i);
        let c = *self.chars.get(i)?;
        let sym = match c {
            '*' if self.chars.get(i + 1) == Some(&'*') => return Some((Op::Pow, 2, i)),
            '*' => Some(Op::Mul),
            '/' => Some(Op::Div),
            '+' => Some(Op::Add),
            '-' => Some(Op::Sub),
            _ => None,
        };
        if let Some(op) = sym {
            return Some((op, 1, i));
        }
        let word: String = self.chars[i..].iter().take(3).take_while(|c| c.is_ascii_alphabetic()).map(|c| c.to_ascii_uppercase()).collect();
        for (name, op) in [("MOD", Op::Mod), ("AND", Op::And), ("XOR", Op::Xor), ("OR", Op::Or), ("EQ", Op::Eq), ("NE", Op::Ne), ("GT", Op::Gt), ("GE", Op::Ge), ("LT", Op::Lt), ("LE", Op::Le)] {
            if word.starts_with(name) {
                return Some((op, name.len(), i));
            }
        }
        None
    }

    /// A unary function `NAME[arg]` (`ATAN[y]/[x]`, `EXISTS[#<name>]`); angles in degrees.
    fn function(&mut self, i: usize) -> Result<(f64, usize), ExprError> {
        let mut j = i;
        while self.chars.get(j).is_some_and(|c| c.is_ascii_alphabetic()) {
            j += 1;
        }
        let name: String = self.chars[i..j].iter().map(|c| c.to_ascii_uppercase()).collect();
        let open = self.blank(j);
        if self.chars.get(open) != Some(&'[') {
            let found: String = self.chars[i..].iter().take_while(|c| !c.is_whitespace()).collect();
            return err(i + 1, format!("expected a number, a parameter or an expression, found '{}'", super::lex::excerpt(&found)));
        }
        if name == "EXISTS" {
            let k = self.blank(open + 1);
            if self.chars.get(k) != Some(&'#') || self.chars.get(self.blank(k + 1)) != Some(&'<') {
                return err(k + 1, "EXISTS takes a named parameter: EXISTS[#<name>]");
            }
            let (target, k) = self.reference(k)?;
            let k = self.blank(k);
            if self.chars.get(k) != Some(&']') {
                return err(k + 1, "expected ']' after EXISTS's parameter");
            }
            let Target::Named(n) = &target else { unreachable!("checked: a named parameter") };
            if is_machine_state(n) {
                return err(i + 1, format!("EXISTS[{target}]: the interpreter's and machine's parameters are not modelled"));
            }
            return Ok((if self.params.named.contains_key(n) { 1.0 } else { 0.0 }, k + 1));
        }
        let (x, k) = self.expression(open)?;
        let at = i + 1;
        let v = match name.as_str() {
            "ATAN" => {
                let slash = self.blank(k);
                if self.chars.get(slash) != Some(&'/') || self.chars.get(self.blank(slash + 1)) != Some(&'[') {
                    return err(slash + 1, "ATAN takes two arguments: ATAN[y]/[x]");
                }
                // ATAN[y]/[x]: the first argument is the numerator.
                let (den, k2) = self.expression(self.blank(slash + 1))?;
                return Ok((x.atan2(den).to_degrees(), k2));
            }
            "ABS" => x.abs(),
            "ACOS" | "ASIN" if !(-1.0..=1.0).contains(&x) => return err(at, format!("{name}[{x}]: the argument must be -1 to 1")),
            "ACOS" => x.acos().to_degrees(),
            "ASIN" => x.asin().to_degrees(),
            "COS" => x.to_radians().cos(),
            "SIN" => x.to_radians().sin(),
            "TAN" => x.to_radians().tan(),
            "EXP" => x.exp(),
            "LN" if x <= 0.0 => return err(at, format!("LN[{x}]: the argument must be positive")),
            "LN" => x.ln(),
            "SQRT" if x < 0.0 => return err(at, format!("SQRT[{x}]: the argument must not be negative")),
            "SQRT" => x.sqrt(),
            "FIX" => x.floor(),
            "FUP" => x.ceil(),
            "ROUND" => x.round(),
            _ => return err(at, format!("unknown function {name}: expected ABS ACOS ASIN ATAN COS EXISTS EXP FIX FUP LN ROUND SIN SQRT TAN")),
        };
        if v.is_finite() { Ok((v, k)) } else { err(at, format!("{name}[{x}] is not a finite number")) }
    }

    /// `#` and what it names: `<name>` or a real value whose integer is the parameter's number.
    fn reference(&mut self, i: usize) -> Result<(Target, usize), ExprError> {
        let j = self.blank(i + 1);
        if self.chars.get(j) == Some(&'<') {
            let Some(close) = self.chars[j..].iter().position(|&c| c == '>') else {
                return err(j + 1, "'#<' is not closed: expected '>' on the same line");
            };
            let name: String = self.chars[j + 1..j + close].iter().filter(|c| !c.is_whitespace()).flat_map(|c| c.to_lowercase()).collect();
            if name.is_empty() {
                return err(j + 1, "'#<>' names no parameter");
            }
            if name.chars().count() > MAX_NAME_CHARS {
                return err(j + 1, format!("a parameter name longer than {MAX_NAME_CHARS} characters"));
            }
            return Ok((Target::Named(name), j + close + 1));
        }
        self.deeper(i + 1)?;
        let (v, k) = self.value(j)?;
        self.depth -= 1;
        let n = v.round();
        if (v - n).abs() > INTEGER_CLOSE || !(1.0..=MAX_PARAMETER as f64).contains(&n) {
            return err(i + 1, format!("#{v}: a parameter number must be a whole number 1 to {MAX_PARAMETER}"));
        }
        Ok((Target::Numbered(n as u32), k))
    }

    /// A parameter's value, where the program set it (see the module's fail-closed rules).
    fn read(&self, target: &Target, column: usize) -> Result<f64, ExprError> {
        match target {
            Target::Numbered(n) if *n > MAX_USER_PARAMETER => err(column, format!("#{n} is a system parameter (offsets, tool, position): the machine's state is not modelled")),
            Target::Numbered(n) => match self.params.numbered.get(n) {
                Some(&v) => Ok(v),
                None => err(column, format!("#{n} is read before the program sets it (LinuxCNC reads 0, a Fanuc control reads it as vacant): not read")),
            },
            // A HAL pin the machine's configuration gives (LinuxCNC manual §11.4.3.6, HAL_PIN_VARS).
            Target::Named(name) if name.starts_with("_hal[") && name.ends_with(']') && self.params.hal_pins.contains_key(&name[5..name.len() - 1]) => {
                Ok(self.params.hal_pins[&name[5..name.len() - 1]])
            }
            Target::Named(name) if name.starts_with("_hal[") => err(column, format!("{target}: the machine file gives no HAL pin '{}' (its hal_pins table)", name.trim_start_matches("_hal[").trim_end_matches(']'))),
            // Never set: a setting refuses them.
            Target::Named(name) if is_machine_state(name) => err(column, format!("{target} is the interpreter's or the machine's state: not modelled")),
            Target::Named(name) => match self.params.named.get(name) {
                Some(&v) => Ok(v),
                None => err(column, format!("named parameter {target} is not defined (read before it is set)")),
            },
        }
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
        let (v, end) = p.real_value(&chars, 0)?;
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
        let long = format!("#<{}>", "n".repeat(MAX_NAME_CHARS + 1));
        assert!(eval(&p, &long).unwrap_err().message.contains("longer than 256"));
        let deep = format!("{}1{}", "[".repeat(200), "]".repeat(200));
        assert!(eval(&p, &deep).unwrap_err().message.contains("nested more than"));
    }
}
