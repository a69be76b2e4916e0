//! RS274NGC values compiled once, evaluated on each pass (LinuxCNC manual §11.4.4-11.4.8): a line
//! an O-word loop runs a thousand times is read once, its expressions kept as postfix steps.
//!
//! A real value is a number, a parameter, an expression, a unary function or one of those with a
//! sign (`X-#3`). What only the text decides (syntax, unknown functions, names too long, nesting)
//! is refused when compiled; what depends on the parameters (one read before it is set, a division
//! by zero, `SQRT` of a negative) when evaluated. Columns are 1-based characters of the text read.

use super::{err, is_machine_state, ExprError, Parameters, Target, INTEGER_CLOSE, MAX_NAME_CHARS, MAX_PARAMETER, MAX_USER_PARAMETER};

/// Deepest nesting of brackets, functions and `#` in one value (the compiler's recursion stays bounded).
const MAX_DEPTH: usize = 64;
/// LinuxCNC's `TOLERANCE_EQUAL` as Debian 12's 2.9.0~pre1 has it (the reference control here, whose
/// `rs274` made the tests' canon files): EQ and NE compare within 0.0001, the other comparisons are
/// strict. LinuxCNC's releases from June 2023 (commit 014777a8, in 2.9.0) compare within 1e-6 and
/// make LE and GE true within it too.
const TOLERANCE_EQUAL: f64 = 1e-4;
/// Values an evaluation holds on the stack before it takes the heap.
const STACK: usize = 16;

/// Run `f` with room for `most` values: on the stack up to [`STACK`], else on the heap (a compiled
/// expression's evaluation, here and in the 840D's).
pub(crate) fn with_stack<R>(most: usize, f: impl FnOnce(&mut [f64]) -> R) -> R {
    if most <= STACK {
        f(&mut [0.0; STACK])
    } else {
        f(&mut vec![0.0; most])
    }
}

/// The binary operators by precedence group (LinuxCNC manual table 11.5), lowest first.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Op {
    And,
    Or,
    Xor,
    /// Fanuc's AND, OR, XOR: on the bits of whole numbers ("#i = #j OR #k: logical sum (bit by
    /// bit)", FANUC custom macro B, arithmetic and logic operations; Haas: `1 OR 2` is 3).
    BitAnd,
    BitOr,
    BitXor,
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
    /// Fanuc's MOD: of whole numbers 0 or more only (the sign and rounding of others are not at hand).
    ModWhole,
    Pow,
}

impl Op {
    fn precedence(self) -> u8 {
        match self {
            Op::And | Op::Or | Op::Xor | Op::BitAnd | Op::BitOr | Op::BitXor => 0,
            Op::Eq | Op::Ne | Op::Gt | Op::Ge | Op::Lt | Op::Le => 1,
            Op::Add | Op::Sub => 2,
            Op::Mul | Op::Div | Op::Mod | Op::ModWhole => 3,
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
            Op::BitAnd | Op::BitOr | Op::BitXor => {
                let whole = |x: f64| (x.fract() == 0.0 && (0.0..=u32::MAX as f64).contains(&x)).then_some(x as u64);
                let (Some(x), Some(y)) = (whole(a), whole(b)) else {
                    return err(column, format!("{a} and {b}: Fanuc's AND, OR and XOR act on the bits of whole numbers 0 or more"));
                };
                (match self {
                    Op::BitAnd => x & y,
                    Op::BitOr => x | y,
                    _ => x ^ y,
                }) as f64
            }
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
            Op::ModWhole if b == 0.0 => return err(column, "MOD by zero"),
            Op::ModWhole if a < 0.0 || b < 0.0 || a.fract() != 0.0 || b.fract() != 0.0 => {
                return err(column, format!("{a} MOD {b}: FANUC's MOD of a negative or fractional number (how it rounds and signs it) is not read; it is read for whole numbers 0 or more"))
            }
            Op::ModWhole => a % b,
            Op::Pow if a < 0.0 && b.fract() != 0.0 => return err(column, format!("{a} ** {b}: a negative number to a non-integer power")),
            Op::Pow => a.powf(b),
        };
        if v.is_finite() { Ok(v) } else { err(column, format!("the result is not a finite number ({a} and {b})")) }
    }
}

/// The unary functions of one argument (LinuxCNC manual §11.4.8); angles in degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Function {
    Abs,
    Acos,
    Asin,
    Cos,
    Sin,
    Tan,
    Exp,
    Ln,
    Sqrt,
    Fix,
    Fup,
    Round,
    /// Fanuc's FIX and FUP: toward and away from zero ("#2 = -1.2: FUP[#2] is -2.0, FIX[#2] is
    /// -1.0", FANUC custom macro B, rounding up and down), where LinuxCNC's are floor and ceiling.
    FixTowardZero,
    FupAwayFromZero,
    /// Fanuc's ASIN: -90 to 90 deg or 270 to 90 deg by parameter 6004#0 (NAT); a negative one refused.
    AsinByParameter,
}

/// Why Fanuc's ATAN or ASIN of a negative angle is refused: the range is the control's parameter.
fn by_nat(name: &str, v: f64) -> String {
    format!("{name} is {v} deg, or {} deg, as FANUC's parameter 6004#0 (NAT) gives the range (-180 to 180 and -90 to 90, or 0 to 360 and 270 to 90), which is not read here", v + 360.0)
}

impl Function {
    const ALL: [(&'static str, Function); 12] = [
        ("ABS", Function::Abs),
        ("ACOS", Function::Acos),
        ("ASIN", Function::Asin),
        ("COS", Function::Cos),
        ("SIN", Function::Sin),
        ("TAN", Function::Tan),
        ("EXP", Function::Exp),
        ("LN", Function::Ln),
        ("SQRT", Function::Sqrt),
        ("FIX", Function::Fix),
        ("FUP", Function::Fup),
        ("ROUND", Function::Round),
    ];

    fn name(self) -> &'static str {
        match self {
            Function::FixTowardZero => "FIX",
            Function::FupAwayFromZero => "FUP",
            Function::AsinByParameter => "ASIN",
            _ => Function::ALL.iter().find(|(_, f)| *f == self).map_or("?", |(n, _)| n),
        }
    }

    fn apply(self, x: f64, column: usize) -> Result<f64, ExprError> {
        let name = self.name();
        let v = match self {
            Function::Abs => x.abs(),
            Function::Acos | Function::Asin | Function::AsinByParameter if !(-1.0..=1.0).contains(&x) => return err(column, format!("{name}[{x}]: the argument must be -1 to 1")),
            Function::AsinByParameter if x < 0.0 => return err(column, by_nat(&format!("ASIN[{x}]"), x.asin().to_degrees())),
            Function::AsinByParameter => x.asin().to_degrees(),
            Function::Acos => x.acos().to_degrees(),
            Function::Asin => x.asin().to_degrees(),
            Function::Cos => x.to_radians().cos(),
            Function::Sin => x.to_radians().sin(),
            Function::Tan => x.to_radians().tan(),
            Function::Exp => x.exp(),
            Function::Ln if x <= 0.0 => return err(column, format!("LN[{x}]: the argument must be positive")),
            Function::Ln => x.ln(),
            Function::Sqrt if x < 0.0 => return err(column, format!("SQRT[{x}]: the argument must not be negative")),
            Function::Sqrt => x.sqrt(),
            Function::Fix => x.floor(),
            Function::Fup => x.ceil(),
            Function::Round => x.round(),
            Function::FixTowardZero => x.trunc(),
            Function::FupAwayFromZero => x.signum() * x.abs().ceil(),
        };
        if v.is_finite() { Ok(v) } else { err(column, format!("{name}[{x}] is not a finite number")) }
    }
}

/// One step of a compiled value, in postfix order; columns are where the step's text starts.
#[derive(Debug, Clone, PartialEq)]
enum Step {
    Number(f64),
    /// `#n` of a written number.
    Numbered(u32, usize),
    /// `#` of the value on top of the stack: its whole number names the parameter.
    Indirect(usize),
    /// `#<name>`, lower case without blanks.
    Named(Box<str>, usize),
    /// `EXISTS[#<name>]`.
    Exists(Box<str>),
    /// `EXISTS[#n]`: whether the whole number on top of the stack is one of LinuxCNC's
    /// parameters (interp_read.cc read_parameter: 1 <= n < RS274NGC_MAX_PARAMETERS).
    ExistsNumbered(usize),
    Negate,
    Function(Function, usize),
    /// `ATAN[y]/[x]`: the two values on top, y below x.
    Atan,
    /// Fanuc's `ATAN[y]/[x]`, a negative angle refused (its range is parameter 6004#0's), at a column.
    AtanByParameter(usize),
    Binary(Op, usize),
}

/// A value compiled from a line's text: evaluate it against the parameters as they stand.
#[derive(Debug, Clone, PartialEq)]
pub struct Compiled {
    steps: Vec<Step>,
    /// The most values the steps hold at once.
    stack: usize,
}

/// A setting's parameter: named in the text, or a number computed when it runs (`#[#1 + 1] = 5`).
#[derive(Debug, Clone, PartialEq)]
pub enum CompiledTarget {
    Fixed(Target),
    Indirect(Compiled, usize),
}

/// A parameter setting `#ref = value`, compiled.
#[derive(Debug, Clone, PartialEq)]
pub struct Setting {
    pub target: CompiledTarget,
    pub value: Compiled,
    /// Fanuc's macro statement (its manual says "system variable").
    pub bare: bool,
}

impl Compiled {
    /// The value, with the parameters as they stand.
    pub fn eval(&self, params: &Parameters) -> Result<f64, ExprError> {
        with_stack(self.stack, |stack| self.eval_in(params, stack))
    }

    /// [`Compiled::eval`] with its values in `stack`.
    fn eval_in(&self, params: &Parameters, stack: &mut [f64]) -> Result<f64, ExprError> {
        let mut n = 0;
        for step in &self.steps {
            match step {
                Step::Number(v) => {
                    stack[n] = *v;
                    n += 1;
                }
                Step::Numbered(k, col) => {
                    stack[n] = params.read_numbered(*k, *col)?;
                    n += 1;
                }
                Step::Indirect(col) => stack[n - 1] = params.read_numbered(parameter_number(stack[n - 1], *col, params.fanuc)?, *col)?,
                Step::Named(name, col) => {
                    stack[n] = params.read_named(name, *col)?;
                    n += 1;
                }
                Step::Exists(name) => {
                    stack[n] = if params.has_named(name) { 1.0 } else { 0.0 };
                    n += 1;
                }
                Step::ExistsNumbered(col) => {
                    let v = stack[n - 1];
                    if (v - v.round()).abs() > INTEGER_CLOSE {
                        return err(*col, format!("EXISTS[#{v}]: a parameter number must be a whole number"));
                    }
                    stack[n - 1] = if v.round() >= 1.0 && v.round() < MAX_PARAMETER as f64 { 1.0 } else { 0.0 };
                }
                Step::Negate => stack[n - 1] = -stack[n - 1],
                Step::Function(f, col) => stack[n - 1] = f.apply(stack[n - 1], *col)?,
                Step::Atan => {
                    n -= 1;
                    stack[n - 1] = stack[n - 1].atan2(stack[n]).to_degrees();
                }
                Step::AtanByParameter(col) => {
                    n -= 1;
                    let v = stack[n - 1].atan2(stack[n]).to_degrees();
                    if v < 0.0 {
                        return err(*col, by_nat(&format!("ATAN[{}]/[{}]", stack[n - 1], stack[n]), v));
                    }
                    stack[n - 1] = v;
                }
                Step::Binary(op, col) => {
                    n -= 1;
                    stack[n - 1] = op.apply(stack[n - 1], stack[n], *col)?;
                }
            }
        }
        Ok(stack[0])
    }

    /// The memory it holds beyond its own struct, bytes.
    pub fn size(&self) -> usize {
        self.steps.capacity() * std::mem::size_of::<Step>()
            + self.steps.iter().map(|s| match s {
                Step::Named(n, _) | Step::Exists(n) => n.len(),
                _ => 0,
            }).sum::<usize>()
    }

    /// The value if it is a written number.
    fn constant(&self) -> Option<f64> {
        match self.steps[..] {
            [Step::Number(v)] => Some(v),
            _ => None,
        }
    }
}

impl Setting {
    /// The memory it holds beyond its own struct, bytes.
    pub fn size(&self) -> usize {
        self.value.size()
            + match &self.target {
                CompiledTarget::Fixed(Target::Named(n)) => n.len(),
                CompiledTarget::Fixed(Target::Numbered(_)) => 0,
                CompiledTarget::Indirect(c, _) => c.size(),
            }
    }

    /// The parameter it sets and the value, with the parameters as they stand (a computed index
    /// naming a system parameter is refused as a written one is).
    pub fn run(&self, params: &Parameters) -> Result<(Target, f64), ExprError> {
        let target = self.target.eval(params)?;
        if let (CompiledTarget::Indirect(_, column), Target::Numbered(n)) = (&self.target, &target) {
            if self.bare && *n >= FANUC_SYSTEM {
                return Err(fanuc_system(*n, *column));
            }
            if *n > MAX_USER_PARAMETER && (self.bare || *n != super::DEBUG_FLAG) {
                let system = if self.bare { "system variable" } else { "system parameter" };
                return err(*column, format!("{target} is a {system} (offsets, tool, position): setting it is not modelled"));
            }
        }
        Ok((target, self.value.eval(params)?))
    }
}

impl CompiledTarget {
    /// The parameter it names with the parameters as they stand (`column`: the `#`'s).
    pub fn eval(&self, params: &Parameters) -> Result<Target, ExprError> {
        match self {
            CompiledTarget::Fixed(t) => Ok(t.clone()),
            CompiledTarget::Indirect(c, column) => Ok(Target::Numbered(parameter_number(c.eval(params)?, *column, params.fanuc)?)),
        }
    }
}

/// The first of Fanuc's system variables, which a macro may not set here: #1000 and up are the
/// control's (interface signals, tool offsets, the macro alarm #3000, clocks, modal information,
/// positions; FANUC custom macro B, "Types of variables": local #1-#33, common #100-#199 and
/// #500-#999).
const FANUC_SYSTEM: u32 = 1000;

/// The defect of setting Fanuc's system variable `#n` (n >= [`FANUC_SYSTEM`]) at `column`: the
/// macro alarm `#3000` stops the run there.
fn fanuc_system(n: u32, column: usize) -> ExprError {
    let message = match n {
        3000 => "#3000 is the macro alarm: setting it stops the control with an alarm here (the program does not run on)".to_string(),
        _ => format!("#{n} is a system variable of the control (#1000 and up: signals, offsets, alarms, clocks, modal state, positions): setting it is not modelled"),
    };
    ExprError { column, message, stops: n == 3000 }
}

/// The highest variable number a Fanuc macro may name: its addresses take up to eight digits (the
/// 30i's system variables and optional common variables run past #100000); past #999 each is the
/// control's ([`FANUC_SYSTEM`]), refused as such when read or set.
const FANUC_MAX_VARIABLE: u32 = 99_999_999;

/// A value meant as a parameter's number: a whole number 1 to [`MAX_PARAMETER`] (LinuxCNC's), or
/// to [`FANUC_MAX_VARIABLE`] with `fanuc`.
fn parameter_number(v: f64, column: usize, fanuc: bool) -> Result<u32, ExprError> {
    let n = v.round();
    let max = if fanuc { FANUC_MAX_VARIABLE } else { MAX_PARAMETER };
    if (v - n).abs() > INTEGER_CLOSE || !(1.0..=max as f64).contains(&n) {
        let what = if fanuc { "a variable number must be a whole number 1 to" } else { "a parameter number must be a whole number 1 to" };
        let vacant = if n == 0.0 { " (Fanuc's #0 is its vacant variable, whose empty value is not read)" } else { "" };
        return err(column, format!("#{v}: {what} {max}{vacant}"));
    }
    Ok(n as u32)
}

mod compile;
pub use compile::{address_value, setting, value};

#[cfg(test)]
mod tests {
    use super::*;

    /// A loop's line read once and run with the parameters of each pass: the same values as the
    /// text read each time, and a parameter read before it is set is refused on the pass that reads it.
    #[test]
    fn compiled_once_evaluated_per_pass() {
        let chars: Vec<char> = "[[#<k> MOD 7] * 0.5 - ATAN[#<k>]/[2] + FIX[#<k> / 3]]".chars().collect();
        let (c, end) = value(&chars, 0, false).unwrap();
        assert_eq!(end, chars.len());
        let mut p = Parameters::default();
        assert!(c.eval(&p).unwrap_err().message.contains("not defined"));
        for k in 0..20 {
            p.set(Target::Named("k".into()), k as f64, 1).unwrap();
            let kf = k as f64;
            let want = (kf % 7.0) * 0.5 - kf.atan2(2.0).to_degrees() + (kf / 3.0).floor();
            assert!((c.eval(&p).unwrap() - want).abs() < 1e-12, "k {k}");
        }
    }

    /// `#[#1 + 1] = 5` sets the parameter its index names when it runs; `#2` is read through `#[...]`.
    #[test]
    fn indirect_settings_name_their_parameter_when_run() {
        let chars: Vec<char> = "#[#1 + 1] = [#[#1] * 2]".chars().collect();
        let (s, end) = setting(&chars, 0, false).unwrap();
        assert_eq!(end, chars.len());
        let mut p = Parameters::default();
        p.set(Target::Numbered(1), 3.0, 1).unwrap();
        p.set(Target::Numbered(3), 4.0, 1).unwrap();
        assert_eq!(s.target.eval(&p).unwrap(), Target::Numbered(4));
        assert_eq!(s.value.eval(&p).unwrap(), 8.0);
        p.set(Target::Numbered(1), 5000.5, 1).unwrap();
        assert!(s.target.eval(&p).unwrap_err().message.contains("whole number"));
    }
}
