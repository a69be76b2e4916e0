//! The compiler of RS274NGC and Fanuc custom macro values: recursive descent over a line's
//! characters into the postfix steps [`super::Compiled`] runs, bounded by [`super::MAX_DEPTH`];
//! what only the text decides (syntax, unknown functions, names too long, nesting) is refused here.

use super::*;

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
        CompiledTarget::Fixed(t @ Target::Numbered(n)) if *n > MAX_USER_PARAMETER && (bare || *n != super::super::DEBUG_FLAG) => return err(i + 1, format!("{t} is a {system} (offsets, tool, position): setting it is not modelled")),
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
        super::super::skip_blanks(self.chars, i)
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
