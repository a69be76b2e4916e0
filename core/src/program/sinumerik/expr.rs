//! Sinumerik arithmetic as the 840D evaluates it (Job Planning 6FC5398-2BP20, "Arithmetic
//! operations/calculation functions" and "Priority of operators"): `+ - * /`, `DIV` (integer
//! division) and `MOD`, the functions `SIN COS TAN ASIN ACOS ATAN2 SQRT ABS POT TRUNC ROUND LN EXP
//! MINVAL MAXVAL` (angles in degrees), comparisons `== <> > < >= <=` (1 true, 0 false) and `NOT AND
//! OR XOR`. Priorities, tightest first: `NOT`; `* / DIV MOD`; `+ -`; `AND`; `XOR`; `OR`; the
//! comparisons. Pure: a variable's value comes from a lookup.

/// Deepest nesting of brackets and functions in one expression (bounds the recursion).
const MAX_DEPTH: usize = 64;

/// Why an expression cannot be evaluated: where in its text (0-based byte) and why.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ExprError {
    pub at: usize,
    pub message: String,
}

fn err<T>(at: usize, message: impl Into<String>) -> Result<T, ExprError> {
    Err(ExprError { at, message: message.into() })
}

/// A variable's value, by its name in capitals (`R1`, `_X_HOME`): `Err` says why it has none (never
/// defined, or defined and never set).
pub(crate) type Lookup<'a> = &'a dyn Fn(&str) -> Result<f64, String>;

/// Evaluate `text`.
pub(crate) fn eval(text: &str, var: Lookup<'_>) -> Result<f64, ExprError> {
    let mut p = Parser { s: text.as_bytes(), i: 0, depth: 0, var };
    let v = p.compare()?;
    if p.peek().is_some() {
        return err(p.i, format!("unexpected '{}' in the expression", p.rest()));
    }
    if !v.is_finite() {
        return err(0, "the result is not a finite number");
    }
    Ok(v)
}

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
    depth: usize,
    var: Lookup<'a>,
}

/// Round half away from zero (the 840D's `ROUND` and its REAL-to-INT conversion).
pub(crate) fn round(x: f64) -> f64 {
    x.round()
}

impl Parser<'_> {
    fn peek(&mut self) -> Option<u8> {
        while self.s.get(self.i).is_some_and(|c| c.is_ascii_whitespace()) {
            self.i += 1;
        }
        self.s.get(self.i).copied()
    }

    fn rest(&self) -> String {
        String::from_utf8_lossy(&self.s[self.i..(self.i + 12).min(self.s.len())]).into_owned()
    }

    /// The word operator `op` (`DIV`, `AND`) at the cursor, not the start of a longer name.
    fn word(&mut self, op: &str) -> bool {
        self.peek();
        let end = self.i + op.len();
        let here = self.s.get(self.i..end).is_some_and(|w| w.eq_ignore_ascii_case(op.as_bytes()));
        if here && !self.s.get(end).is_some_and(|c| c.is_ascii_alphanumeric() || *c == b'_') {
            self.i = end;
            return true;
        }
        false
    }

    fn deeper(&mut self) -> Result<(), ExprError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return err(self.i, format!("brackets and functions nested deeper than {MAX_DEPTH}"));
        }
        Ok(())
    }

    /// `or (cmp or)?`: a comparison gives 1 or 0.
    fn compare(&mut self) -> Result<f64, ExprError> {
        let a = self.or()?;
        self.peek();
        let ops: [(&str, fn(f64, f64) -> bool); 6] = [("==", |a, b| a == b), ("<>", |a, b| a != b), (">=", |a, b| a >= b), ("<=", |a, b| a <= b), (">", |a, b| a > b), ("<", |a, b| a < b)];
        for (op, f) in ops {
            if self.s[self.i..].starts_with(op.as_bytes()) {
                self.i += op.len();
                let b = self.or()?;
                return Ok(f64::from(u8::from(f(a, b))));
            }
        }
        Ok(a)
    }

    fn or(&mut self) -> Result<f64, ExprError> {
        let mut v = self.xor()?;
        while self.word("OR") {
            let w = self.xor()?;
            v = f64::from(u8::from(v != 0.0 || w != 0.0));
        }
        Ok(v)
    }

    fn xor(&mut self) -> Result<f64, ExprError> {
        let mut v = self.and()?;
        while self.word("XOR") {
            let w = self.and()?;
            v = f64::from(u8::from((v != 0.0) != (w != 0.0)));
        }
        Ok(v)
    }

    fn and(&mut self) -> Result<f64, ExprError> {
        let mut v = self.sum()?;
        while self.word("AND") {
            let w = self.sum()?;
            v = f64::from(u8::from(v != 0.0 && w != 0.0));
        }
        Ok(v)
    }

    fn sum(&mut self) -> Result<f64, ExprError> {
        let mut v = self.product()?;
        while let Some(c @ (b'+' | b'-')) = self.peek() {
            self.i += 1;
            let w = self.product()?;
            v = if c == b'+' { v + w } else { v - w };
        }
        Ok(v)
    }

    fn product(&mut self) -> Result<f64, ExprError> {
        let mut v = self.unary()?;
        loop {
            let at = self.i;
            let op = match self.peek() {
                Some(b'*') => "*",
                Some(b'/') => "/",
                _ if self.word("DIV") => "DIV",
                _ if self.word("MOD") => "MOD",
                _ => return Ok(v),
            };
            if op.len() == 1 {
                self.i += 1;
            }
            let w = self.unary()?;
            v = match op {
                "*" => v * w,
                _ if w == 0.0 => return err(at, "division by zero"),
                "/" => v / w,
                // DIV: the quotient's whole part (the manual: "Integer division"); MOD the remainder.
                "DIV" => (v / w).trunc(),
                _ => v % w,
            };
        }
    }

    /// `NOT unary | ('+'|'-') unary | atom`.
    fn unary(&mut self) -> Result<f64, ExprError> {
        self.deeper()?;
        let v = if self.word("NOT") {
            self.unary().map(|v| f64::from(u8::from(v == 0.0)))
        } else {
            match self.peek() {
                Some(b'+') => {
                    self.i += 1;
                    self.unary()
                }
                Some(b'-') => {
                    self.i += 1;
                    self.unary().map(|v| -v)
                }
                _ => self.atom(),
            }
        };
        self.depth -= 1;
        v
    }

    /// The arguments of a function, after its name: `(a, b, ...)`: the first two (no function
    /// takes more) and how many there were.
    fn arguments(&mut self, name: &str) -> Result<([f64; 2], usize), ExprError> {
        if self.peek() != Some(b'(') {
            return err(self.i, format!("{name}: expected '(' and the function's arguments"));
        }
        self.i += 1;
        let (mut args, mut n) = ([0.0; 2], 0);
        loop {
            let v = self.compare()?;
            if n < 2 {
                args[n] = v;
            }
            n += 1;
            match self.peek() {
                Some(b',') => self.i += 1,
                Some(b')') => {
                    self.i += 1;
                    return Ok((args, n));
                }
                _ => return err(self.i, format!("{name}(: expected ',' or ')'")),
            }
        }
    }

    fn atom(&mut self) -> Result<f64, ExprError> {
        let Some(c) = self.peek() else { return err(self.i, "the expression ends where a value was expected") };
        let at = self.i;
        match c {
            b'(' => {
                self.i += 1;
                let v = self.compare()?;
                if self.peek() != Some(b')') {
                    return err(self.i, "'(' is not closed: expected ')'");
                }
                self.i += 1;
                Ok(v)
            }
            c if c.is_ascii_digit() || c == b'.' => {
                while self.s.get(self.i).is_some_and(|c| c.is_ascii_digit() || *c == b'.') {
                    self.i += 1;
                }
                // 1.5EX3: the 840D's exponent notation is not read.
                let t = std::str::from_utf8(&self.s[at..self.i]).unwrap_or("");
                super::super::lex::parse_number(t).map_or_else(|| err(at, format!("'{t}' is not a number")), Ok)
            }
            b'$' => err(at, format!("system variable '{}': not read (its value is the control's)", self.rest())),
            c if c.is_ascii_alphabetic() || c == b'_' => {
                while self.s.get(self.i).is_some_and(|c| c.is_ascii_alphanumeric() || *c == b'_') {
                    self.i += 1;
                }
                // The name in capitals: on the stack when short (every one a program uses).
                let written = &self.s[at..self.i];
                let mut stack = [0u8; 32];
                let heap;
                let name: &str = if written.len() <= stack.len() {
                    stack[..written.len()].copy_from_slice(written);
                    stack[..written.len()].make_ascii_uppercase();
                    std::str::from_utf8(&stack[..written.len()]).unwrap_or("")
                } else {
                    heap = String::from_utf8_lossy(written).to_ascii_uppercase();
                    &heap
                };
                let is_call = self.peek() == Some(b'(');
                if !is_call {
                    return match name {
                        "TRUE" => Ok(1.0),
                        "FALSE" => Ok(0.0),
                        _ => (self.var)(name).or_else(|why| err(at, why)),
                    };
                }
                self.deeper()?;
                let (args, n) = self.arguments(name)?;
                self.depth -= 1;
                let want = |k: usize| if n == k { Ok(()) } else { err(at, format!("{name}: expected {k} argument{}, found {n}", if k == 1 { "" } else { "s" })) };
                let domain = |ok: bool, v: f64| if ok { Ok(v) } else { err(at, format!("{name}{:?} is outside the function's domain", &args[..n.min(2)])) };
                let x = args[0];
                match name {
                    "SIN" | "COS" | "TAN" | "ASIN" | "ACOS" | "SQRT" | "ABS" | "POT" | "TRUNC" | "ROUND" | "LN" | "EXP" => want(1)?,
                    "ATAN2" | "MINVAL" | "MAXVAL" => want(2)?,
                    _ => return err(at, format!("unknown function {name}: expected SIN COS TAN ASIN ACOS ATAN2 SQRT ABS POT TRUNC ROUND LN EXP MINVAL MAXVAL")),
                }
                let deg = x.to_radians();
                match name {
                    "SIN" => Ok(deg.sin()),
                    "COS" => Ok(deg.cos()),
                    "TAN" => domain(deg.cos().abs() > 1e-12, deg.tan()),
                    "ASIN" => domain((-1.0..=1.0).contains(&x), x.asin().to_degrees()),
                    "ACOS" => domain((-1.0..=1.0).contains(&x), x.acos().to_degrees()),
                    // ATAN2(y, x): the angle of the vector (x, y), degrees.
                    "ATAN2" => domain(x != 0.0 || args[1] != 0.0, x.atan2(args[1]).to_degrees()),
                    "SQRT" => domain(x >= 0.0, x.sqrt()),
                    "ABS" => Ok(x.abs()),
                    "POT" => Ok(x * x),
                    "TRUNC" => Ok(x.trunc()),
                    "ROUND" => Ok(round(x)),
                    "LN" => domain(x > 0.0, x.ln()),
                    "EXP" => domain(x.exp().is_finite(), x.exp()),
                    "MINVAL" => Ok(x.min(args[1])),
                    _ => Ok(x.max(args[1])),
                }
            }
            _ => err(at, format!("unexpected '{}' where a value was expected", self.rest())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(name: &str) -> Result<f64, String> {
        match name {
            "R1" => Ok(2.0),
            "_X_HOME" => Ok(-365.0),
            "R2" => Err("R2 is read before it is set".into()),
            _ => Err(format!("{name} is not defined")),
        }
    }

    /// The manual's priorities and functions, each computed by hand.
    #[test]
    fn expressions_evaluate_as_the_840d_does() {
        let e = |t: &str| eval(t, &v);
        assert_eq!(e("R1+5"), Ok(7.0));
        assert_eq!(e("-R1*3+1"), Ok(-5.0));
        assert_eq!(e("_x_home"), Ok(-365.0));
        assert_eq!(e("7 DIV 2"), Ok(3.0));
        assert_eq!(e("7 MOD 4"), Ok(3.0));
        assert_eq!(e("POT(3)+SQRT(16)"), Ok(13.0));
        assert!((e("SIN(30)").unwrap() - 0.5).abs() < 1e-15);
        assert!((e("ATAN2(1,1)").unwrap() - 45.0).abs() < 1e-12);
        assert!((e("ATAN2(30.5,80.1)").unwrap() - 20.84).abs() < 0.01, "the manual's ATAN2(30.5, 80.1) = 20.84");
        assert_eq!(e("ROUND(2.5)+TRUNC(-1.7)"), Ok(2.0));
        assert_eq!(e("(R1==2) AND NOT (R1>3)"), Ok(1.0));
        // Comparisons bind loosest: R1==2 AND 1 is R1==(2 AND 1).
        assert_eq!(e("R1==2 AND 1"), Ok(0.0));
        assert_eq!(e("1+2*(3-1)"), Ok(5.0));
        assert_eq!(e("MAXVAL(R1,-1)"), Ok(2.0));
        assert!(e("R2+1").unwrap_err().message.contains("before it is set"));
        assert!(e("R9").unwrap_err().message.contains("not defined"));
        assert!(e("1/0").unwrap_err().message.contains("division by zero"));
        assert!(e("$P_UIFR[1]").unwrap_err().message.contains("system variable"));
        assert!(e("FOO(1)").unwrap_err().message.contains("unknown function"));
        assert!(e("(1").is_err() && e("1 2").is_err() && e("").is_err());
        let deep = "(".repeat(200) + "1" + &")".repeat(200);
        assert!(e(&deep).unwrap_err().message.contains("nested deeper"));
    }
}
