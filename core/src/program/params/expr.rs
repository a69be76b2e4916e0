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
            if *n > MAX_USER_PARAMETER {
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

/// The real value that starts at `chars[i]` (after blanks), compiled: it and the index after it.
/// `fanuc`: FIX, FUP, AND, OR and XOR as Fanuc's custom macro B computes them, else as LinuxCNC's.
pub fn value(chars: &[char], i: usize, fanuc: bool) -> Result<(Compiled, usize), ExprError> {
    let mut c = Compiler::new(chars, fanuc);
    let end = c.value(i)?;
    Ok((c.finish(), end))
}

/// [`value`] as an address's (`X[..]`): with `fanuc`, its ROUND rounds to the address's increment.
pub fn address_value(chars: &[char], i: usize, fanuc: bool) -> Result<(Compiled, usize), ExprError> {
    let mut c = Compiler::new(chars, fanuc);
    c.address = true;
    let end = c.value(i)?;
    Ok((c.finish(), end))
}

/// The setting `#ref = value` at `chars[i] == '#'`, compiled. `bare`: Fanuc's macro statement,
/// whose expression runs on without brackets (FANUC B-64484EN, "Custom macro": "#i = <expression>").
/// A system parameter or the machine's state is refused: this reader does not model them.
pub fn setting(chars: &[char], i: usize, bare: bool) -> Result<(Setting, usize), ExprError> {
    let mut c = Compiler::new(chars, bare);
    let (target, j) = c.target(i)?;
    let what = if bare { "an expression" } else { "a value" };
    let system = if bare { "system variable" } else { "system parameter" };
    match &target {
        CompiledTarget::Fixed(Target::Numbered(n)) if bare && *n >= FANUC_SYSTEM => return Err(fanuc_system(*n, i + 1)),
        CompiledTarget::Fixed(t @ Target::Numbered(n)) if *n > MAX_USER_PARAMETER => return err(i + 1, format!("{t} is a {system} (offsets, tool, position): setting it is not modelled")),
        CompiledTarget::Fixed(t @ Target::Named(n)) if !bare && is_machine_state(n) => return err(i + 1, format!("{t} is read-only (the interpreter's or the machine's state)")),
        _ => {}
    }
    let j = c.blank(j);
    if chars.get(j) != Some(&'=') {
        let shown = match &target {
            CompiledTarget::Fixed(t) => t.to_string(),
            CompiledTarget::Indirect(..) => chars[i..j].iter().collect::<String>().trim_end().to_string(),
        };
        return err(i + 1, format!("{shown} stands alone: expected '=' and {what} to set it (or a word letter before it)"));
    }
    let end = if bare { c.binary(j + 1, 0)? } else { c.value(j + 1)? };
    Ok((Setting { target, value: c.finish(), bare }, end))
}

/// A `#` reference as read: a number's value compiled, or a name's span (between `<` and `>`).
enum Ref {
    Value,
    Named(usize, usize),
}

/// The operators met at one level of an expression (between brackets).
#[derive(Debug, Default)]
struct Level {
    /// The first of Fanuc's AND, OR, XOR and its column.
    bitwise: Option<(&'static str, usize)>,
    /// Any other operator.
    other: bool,
}

/// Compiles one value from a line's characters (recursive descent, bounded by [`MAX_DEPTH`]).
struct Compiler<'a> {
    /// The operators of each level open now, innermost last.
    levels: Vec<Level>,
    chars: &'a [char],
    /// Fanuc's rules (FIX, FUP, AND, OR, XOR), else LinuxCNC's.
    fanuc: bool,
    /// An address's value (`X[..]`), not a macro statement's.
    address: bool,
    steps: Vec<Step>,
    depth: usize,
    /// Values held now, and the most held at once.
    held: usize,
    most: usize,
}

impl<'a> Compiler<'a> {
    fn new(chars: &'a [char], fanuc: bool) -> Compiler<'a> {
        Compiler { levels: Vec::new(), address: false, chars, fanuc, steps: Vec::new(), depth: 0, held: 0, most: 0 }
    }

    fn finish(self) -> Compiled {
        Compiled { steps: self.steps, stack: self.most }
    }

    /// Add a step; `pushes` the values it leaves less those it takes (1, 0 or -1).
    fn emit(&mut self, step: Step, pushes: isize) {
        self.held = self.held.saturating_add_signed(pushes);
        self.most = self.most.max(self.held);
        self.steps.push(step);
    }

    fn blank(&self, i: usize) -> usize {
        super::skip_blanks(self.chars, i)
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
    fn value(&mut self, i: usize) -> Result<usize, ExprError> {
        let i = self.blank(i);
        self.deeper(i + 1)?;
        let out = match self.chars.get(i) {
            None => err(i + 1, "expected a value, found the end of the line"),
            Some('[') => self.expression(i),
            Some('#') => match self.reference(i)? {
                (Ref::Value, j) => {
                    self.parameter_of_value(i + 1)?;
                    Ok(j)
                }
                (Ref::Named(a, b), j) => {
                    let name = self.name(a, b)?;
                    self.emit(Step::Named(name.into(), i + 1), 1);
                    Ok(j)
                }
            },
            Some(&c @ ('+' | '-')) if !self.chars.get(self.blank(i + 1)).is_some_and(|n| n.is_ascii_digit() || *n == '.') => {
                let j = self.value(i + 1)?;
                if c == '-' {
                    self.emit(Step::Negate, 0);
                }
                Ok(j)
            }
            Some(c) if c.is_ascii_alphabetic() => self.function(i),
            Some(_) => self.number(i),
        };
        self.depth -= 1;
        out
    }

    /// The value just compiled names a parameter (`#3`, `#[#1 + 1]`): read it, at `column`.
    fn parameter_of_value(&mut self, column: usize) -> Result<(), ExprError> {
        if let Some(Step::Number(v)) = self.steps.last() {
            let k = parameter_number(*v, column, self.fanuc)?;
            self.steps.pop();
            self.emit(Step::Numbered(k, column), 0);
        } else {
            self.emit(Step::Indirect(column), 0);
        }
        Ok(())
    }

    fn number(&mut self, i: usize) -> Result<usize, ExprError> {
        let mut j = i;
        if matches!(self.chars.get(j), Some('+' | '-')) {
            j = self.blank(j + 1);
        }
        let digits = j;
        while self.chars.get(j).is_some_and(|c| c.is_ascii_digit() || *c == '.') {
            j += 1;
        }
        // The sign, digits and point are ASCII: their text on the stack (a long one on the heap).
        let mut stack = [0u8; 64];
        let mut len = 0;
        let mut heap = String::new();
        for c in self.chars[i..j].iter().filter(|c| !c.is_whitespace()) {
            if len < stack.len() {
                stack[len] = *c as u8;
                len += 1;
            } else {
                if heap.is_empty() {
                    heap.push_str(std::str::from_utf8(&stack).unwrap_or_default());
                }
                heap.push(*c);
            }
        }
        let text = if heap.is_empty() { std::str::from_utf8(&stack[..len]).unwrap_or_default() } else { heap.as_str() };
        match crate::program::lex::parse_number(text) {
            Some(v) if j > digits => {
                self.emit(Step::Number(v), 1);
                Ok(j)
            }
            _ => {
                let found: String = self.chars[i..].iter().take_while(|c| !c.is_whitespace()).collect();
                err(i + 1, format!("expected a number, a parameter or an expression, found '{}'", crate::program::lex::excerpt(&found)))
            }
        }
    }

    /// `[` expression `]`: operands and binary operators, by precedence, left to right within a group.
    fn expression(&mut self, i: usize) -> Result<usize, ExprError> {
        let j = self.binary(i + 1, 0)?;
        let j = self.blank(j);
        match self.chars.get(j) {
            Some(']') => Ok(j + 1),
            Some(_) => {
                let found: String = self.chars[j..].iter().take_while(|c| !c.is_whitespace()).collect();
                err(j + 1, format!("expected an operator or ']', found '{}'", crate::program::lex::excerpt(&found)))
            }
            None => err(i + 1, "'[' is not closed: expected ']' on the same line"),
        }
    }

    /// Precedence climbing: operands joined by operators of group `min` or higher. Group 0 starts a
    /// level (inside brackets, or a Fanuc statement's expression), whose operators are checked at its end.
    fn binary(&mut self, i: usize, min: u8) -> Result<usize, ExprError> {
        if min == 0 {
            self.levels.push(Level::default());
            let out = self.binary_in(i, 0);
            let level = self.levels.pop().unwrap_or_default();
            let j = out?;
            // Fanuc's AND, OR and XOR beside arithmetic or a comparison at one level: where FANUC puts
            // them among the others (LinuxCNC's table puts them last) is not in the manuals at hand.
            if let (Some((name, column)), true) = (level.bitwise, level.other) {
                return err(column, format!("{name} beside arithmetic, a comparison or another of AND, OR and XOR without brackets: where FANUC's custom macro puts {name} among the other operators is not read here (bracket its operands, as [4 + 3] {name} 1 or [#1 GT 1] {name} [#2 LT 4])"));
            }
            return Ok(j);
        }
        self.binary_in(i, min)
    }

    fn binary_in(&mut self, i: usize, min: u8) -> Result<usize, ExprError> {
        let mut j = self.value(i)?;
        loop {
            let Some((op, len, at)) = self.operator(j) else { return Ok(j) };
            if op.precedence() < min {
                return Ok(j);
            }
            if let Some(level) = self.levels.last_mut() {
                match op {
                    Op::BitAnd | Op::BitOr | Op::BitXor => {
                        let name = match op {
                            Op::BitAnd => "AND",
                            Op::BitOr => "OR",
                            _ => "XOR",
                        };
                        // AND beside OR or XOR: ranked apart in some tables (AND with * and /,
                        // OR and XOR with + and -), together in others.
                        let first = *level.bitwise.get_or_insert((name, at + 1));
                        if (first.0 == "AND") != (name == "AND") {
                            level.other = true;
                        }
                    }
                    _ => level.other = true,
                }
            }
            j = self.binary_in(at + len, op.precedence() + 1)?;
            self.emit(Step::Binary(op, at + 1), -1);
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
        if !c.is_ascii_alphabetic() {
            return None;
        }
        for (name, op) in [("MOD", Op::Mod), ("AND", Op::And), ("XOR", Op::Xor), ("OR", Op::Or), ("EQ", Op::Eq), ("NE", Op::Ne), ("GT", Op::Gt), ("GE", Op::Ge), ("LT", Op::Lt), ("LE", Op::Le)] {
            if starts_with_word(&self.chars[i..], name) {
                let op = match op {
                    Op::Mod if self.fanuc => Op::ModWhole,
                    Op::And if self.fanuc => Op::BitAnd,
                    Op::Or if self.fanuc => Op::BitOr,
                    Op::Xor if self.fanuc => Op::BitXor,
                    _ => op,
                };
                return Some((op, name.len(), i));
            }
        }
        None
    }

    /// A unary function `NAME[arg]` (`ATAN[y]/[x]`, `EXISTS[#<name>]`).
    fn function(&mut self, i: usize) -> Result<usize, ExprError> {
        let mut j = i;
        while self.chars.get(j).is_some_and(|c| c.is_ascii_alphabetic()) {
            j += 1;
        }
        let word = &self.chars[i..j];
        let open = self.blank(j);
        if self.chars.get(open) != Some(&'[') {
            let found: String = self.chars[i..].iter().take_while(|c| !c.is_whitespace()).collect();
            return err(i + 1, format!("expected a number, a parameter or an expression, found '{}'", crate::program::lex::excerpt(&found)));
        }
        let is = |name: &str| word.len() == name.len() && starts_with_word(word, name);
        if is("EXISTS") {
            let k = self.blank(open + 1);
            if self.chars.get(k) != Some(&'#') {
                return err(k + 1, "EXISTS takes a parameter: EXISTS[#<name>] or EXISTS[#n]");
            }
            if self.chars.get(self.blank(k + 1)) != Some(&'<') {
                // A numbered one: its number read as a value (`#1`, `##1`, `#[expr]`), not its value.
                let (Ref::Value, k2) = self.reference(k)? else { unreachable!("checked: not a named parameter") };
                let k2 = self.blank(k2);
                if self.chars.get(k2) != Some(&']') {
                    return err(k2 + 1, "expected ']' after EXISTS's parameter");
                }
                self.emit(Step::ExistsNumbered(k + 1), 0);
                return Ok(k2 + 1);
            }
            let (Ref::Named(a, b), k) = self.reference(k)? else { unreachable!("checked: a named parameter") };
            let k = self.blank(k);
            if self.chars.get(k) != Some(&']') {
                return err(k + 1, "expected ']' after EXISTS's parameter");
            }
            let name = self.name(a, b)?;
            if is_machine_state(&name) {
                return err(i + 1, format!("EXISTS[#<{name}>]: the interpreter's and machine's parameters are not modelled"));
            }
            self.emit(Step::Exists(name.into()), 1);
            return Ok(k + 1);
        }
        if is("ATAN") {
            let k = self.expression(open)?;
            let slash = self.blank(k);
            if self.chars.get(slash) != Some(&'/') || self.chars.get(self.blank(slash + 1)) != Some(&'[') {
                return err(slash + 1, "ATAN takes two arguments: ATAN[y]/[x]");
            }
            // ATAN[y]/[x]: the first argument is the numerator.
            let k2 = self.expression(self.blank(slash + 1))?;
            self.emit(if self.fanuc { Step::AtanByParameter(i + 1) } else { Step::Atan }, -1);
            return Ok(k2);
        }
        let Some(&(_, f)) = Function::ALL.iter().find(|(name, _)| is(name)) else {
            let name: String = word.iter().map(|c| c.to_ascii_uppercase()).collect();
            return err(i + 1, format!("unknown function {name}: expected ABS ACOS ASIN ATAN COS EXISTS EXP FIX FUP LN ROUND SIN SQRT TAN"));
        };
        let f = match f {
            Function::Fix if self.fanuc => Function::FixTowardZero,
            Function::Fup if self.fanuc => Function::FupAwayFromZero,
            Function::Asin if self.fanuc => Function::AsinByParameter,
            // "When the ROUND function is used in an NC statement address, [it] rounds off the
            // specified value according to the least input increment of the address" (FANUC custom
            // macro B; Haas: "ROUND is rounded to the significant precision" of the address).
            Function::Round if self.fanuc && self.address => {
                return err(i + 1, "ROUND in an address: FANUC and Haas round it to the address's least input increment, not to a whole number; that is not read here (round in a macro statement: #1=ROUND[..])");
            }
            _ => f,
        };
        let k = self.expression(open)?;
        self.emit(Step::Function(f, i + 1), 0);
        Ok(k)
    }

    /// `#` and what it names: `<name>` (the span inside the brackets), or a real value (compiled
    /// here) whose whole number is the parameter's.
    fn reference(&mut self, i: usize) -> Result<(Ref, usize), ExprError> {
        let j = self.blank(i + 1);
        if self.chars.get(j) == Some(&'<') {
            let Some(close) = self.chars[j..].iter().position(|&c| c == '>') else {
                return err(j + 1, "'#<' is not closed: expected '>' on the same line");
            };
            return Ok((Ref::Named(j + 1, j + close), j + close + 1));
        }
        self.deeper(i + 1)?;
        let k = self.value(j)?;
        self.depth -= 1;
        Ok((Ref::Value, k))
    }

    /// A setting's parameter at `chars[i] == '#'`.
    fn target(&mut self, i: usize) -> Result<(CompiledTarget, usize), ExprError> {
        match self.reference(i)? {
            (Ref::Named(a, b), j) => Ok((CompiledTarget::Fixed(Target::Named(self.name(a, b)?)), j)),
            (Ref::Value, j) => {
                let index = Compiled { steps: std::mem::take(&mut self.steps), stack: self.most };
                (self.held, self.most) = (0, 0);
                match index.constant() {
                    Some(v) => Ok((CompiledTarget::Fixed(Target::Numbered(parameter_number(v, i + 1, self.fanuc)?)), j)),
                    None => Ok((CompiledTarget::Indirect(index, i + 1), j)),
                }
            }
        }
    }

    /// The name between `#<` and `>` (`chars[a..b]`) as LinuxCNC keys it: without blanks, lower case.
    fn name(&self, a: usize, b: usize) -> Result<String, ExprError> {
        let name: String = self.chars[a..b].iter().filter(|c| !c.is_whitespace()).flat_map(|c| c.to_lowercase()).collect();
        if name.is_empty() {
            return err(a, "'#<>' names no parameter");
        }
        if name.chars().count() > MAX_NAME_CHARS {
            return err(a, format!("a parameter name longer than {MAX_NAME_CHARS} characters"));
        }
        Ok(name)
    }
}

/// Whether `chars` begins with the ASCII word `upper` in any case.
fn starts_with_word(chars: &[char], upper: &str) -> bool {
    chars.len() >= upper.len() && chars.iter().zip(upper.bytes()).all(|(c, u)| c.to_ascii_uppercase() == u as char)
}

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
