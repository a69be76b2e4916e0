//! Q parameter arithmetic as the TNC evaluates it: formulas `Q1 = (Q2 + 3) * SIN Q3`, the `FN 0`
//! to `FN 8` and `FN 13` functions, and the values `FN 9` to `FN 12` compare. Pure: values come from
//! a lookup of the parameters set so far.
//!
//! From the TNC 320 User's Manual DIN/ISO 3/2014 §9.9 "Entering formulas directly" (`Q15 = 3^3`,
//! `PI`, `LN`, `LOG`, `EXP`, `NEG`, `INT`, `ABS`, `FRAC`, `SGN`, `SQ`, `SQRT`, `%` the remainder:
//! "Q12 = 400 % 360, result: Q12 = 40"; angles in degrees) and the TNC's FN functions (FN 0 assign,
//! FN 1 +, FN 2 -, FN 3 *, FN 4 DIV, FN 5 SQRT, FN 6 SIN, FN 7 COS, FN 8 LEN the root of the sum of
//! squares). Functions bind tightest (`SIN 30^2` is (SIN 30)^2),
//! then `^` (to the right, a sign before it applying to the power: `-Q1^2` is -(Q1^2)), then
//! `* / %`, then `+ -`.

/// Deepest nesting of brackets and functions in one formula (bounds the recursion).
const MAX_DEPTH: usize = 64;

/// Why a formula cannot be evaluated: where in its text (0-based byte) and why. `unset` names a
/// parameter read before it was set.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FormulaError {
    pub at: usize,
    pub message: String,
    pub unset: Option<String>,
}

fn err<T>(at: usize, message: impl Into<String>) -> Result<T, FormulaError> {
    Err(FormulaError { at, message: message.into(), unset: None })
}

/// Evaluate `text`; `q` gives a parameter's value (by its name in capitals, `Q12`, `QL3`), or
/// `None` if it was never set.
pub(crate) fn eval(text: &str, q: &dyn Fn(&str) -> Option<f64>) -> Result<f64, FormulaError> {
    let mut p = Parser { s: text.as_bytes(), i: 0, depth: 0, q };
    let v = p.sum()?;
    p.blank();
    if p.i < p.s.len() {
        return err(p.i, format!("unexpected '{}' in the formula", p.rest()));
    }
    if !v.is_finite() {
        return err(0, "the result is not a finite number");
    }
    Ok(v)
}

/// Whether `text` is a formula (its syntax only: every parameter read as 1).
pub(crate) fn check(text: &str) -> Result<(), FormulaError> {
    match eval(text, &|_| Some(1.0)) {
        Ok(_) => Ok(()),
        // A value that is out of a function's domain with every parameter at 1 is not a syntax error.
        Err(e) if e.message.starts_with("the result") || e.message.contains("outside") || e.message.contains("division by zero") => Ok(()),
        Err(e) => Err(e),
    }
}

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
    depth: usize,
    q: &'a dyn Fn(&str) -> Option<f64>,
}

impl Parser<'_> {
    fn blank(&mut self) {
        while self.s.get(self.i).is_some_and(|c| c.is_ascii_whitespace()) {
            self.i += 1;
        }
    }

    fn rest(&self) -> String {
        String::from_utf8_lossy(&self.s[self.i..(self.i + 12).min(self.s.len())]).into_owned()
    }

    fn peek(&mut self) -> Option<u8> {
        self.blank();
        self.s.get(self.i).copied()
    }

    fn deeper(&mut self) -> Result<(), FormulaError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return err(self.i, format!("brackets and functions nested deeper than {MAX_DEPTH}"));
        }
        Ok(())
    }

    /// `term (('+' | '-') term)*`
    fn sum(&mut self) -> Result<f64, FormulaError> {
        let mut v = self.product()?;
        while let Some(c @ (b'+' | b'-')) = self.peek() {
            self.i += 1;
            let w = self.product()?;
            v = if c == b'+' { v + w } else { v - w };
        }
        Ok(v)
    }

    /// `signed (('*' | '/' | '%') signed)*`
    fn product(&mut self) -> Result<f64, FormulaError> {
        let mut v = self.signed()?;
        while let Some(c @ (b'*' | b'/' | b'%')) = self.peek() {
            let at = self.i;
            self.i += 1;
            let w = self.signed()?;
            v = match c {
                b'*' => v * w,
                _ if w == 0.0 => return err(at, "division by zero"),
                b'/' => v / w,
                _ => v % w,
            };
        }
        Ok(v)
    }

    /// Signs, then what `then` reads: a sign applies to all of it.
    fn signs(&mut self, then: fn(&mut Self) -> Result<f64, FormulaError>) -> Result<f64, FormulaError> {
        self.deeper()?;
        let v = match self.peek() {
            Some(b'+') => {
                self.i += 1;
                self.signs(then)
            }
            Some(b'-') => {
                self.i += 1;
                self.signs(then).map(|v| -v)
            }
            _ => then(self),
        };
        self.depth -= 1;
        v
    }

    /// `('+' | '-') signed | power`: a sign applies to the power after it (`-Q1^2` is -(Q1^2)).
    fn signed(&mut self) -> Result<f64, FormulaError> {
        self.signs(Self::power)
    }

    /// `atom ('^' signed)?`, to the right.
    fn power(&mut self) -> Result<f64, FormulaError> {
        let base = self.atom()?;
        if self.peek() == Some(b'^') {
            self.i += 1;
            let e = self.signed()?;
            let v = base.powf(e);
            return if v.is_finite() { Ok(v) } else { err(self.i, format!("{base}^{e} is outside the numbers")) };
        }
        Ok(base)
    }

    /// A function's argument: signs, then an atom (`SIN -30`, `SQRT Q1`; `SIN 30^2` is (SIN 30)^2).
    fn argument(&mut self) -> Result<f64, FormulaError> {
        self.signs(Self::atom)
    }

    /// A bracket, a parameter, `PI`, a number, or a function of an argument.
    fn atom(&mut self) -> Result<f64, FormulaError> {
        self.deeper()?;
        let v = self.atom_inner();
        self.depth -= 1;
        v
    }

    fn atom_inner(&mut self) -> Result<f64, FormulaError> {
        let at = match self.peek() {
            None => return err(self.i, "the formula ends where a value was expected"),
            Some(_) => self.i,
        };
        match self.s[at] {
            b'(' => {
                self.i += 1;
                let v = self.sum()?;
                if self.peek() != Some(b')') {
                    return err(self.i, "'(' is not closed: expected ')'");
                }
                self.i += 1;
                Ok(v)
            }
            c if c.is_ascii_digit() || c == b'.' => {
                let start = self.i;
                while self.s.get(self.i).is_some_and(|c| c.is_ascii_digit() || *c == b'.') {
                    self.i += 1;
                }
                let t = std::str::from_utf8(&self.s[start..self.i]).unwrap_or("");
                t.parse::<f64>().or_else(|_| err(start, format!("'{t}' is not a number")))
            }
            c if c.is_ascii_alphabetic() => {
                let start = self.i;
                while self.s.get(self.i).is_some_and(|c| c.is_ascii_alphabetic()) {
                    self.i += 1;
                }
                let name = std::str::from_utf8(&self.s[start..self.i]).unwrap_or("").to_ascii_uppercase();
                if matches!(name.as_str(), "Q" | "QL" | "QR") && self.s.get(self.i).is_some_and(|c| c.is_ascii_digit()) {
                    let digits = self.i;
                    while self.s.get(self.i).is_some_and(|c| c.is_ascii_digit()) {
                        self.i += 1;
                    }
                    let full = format!("{name}{}", std::str::from_utf8(&self.s[digits..self.i]).unwrap_or(""));
                    return match (self.q)(&full) {
                        Some(v) => Ok(v),
                        None => Err(FormulaError { at: start, message: format!("{full} is read before it is set"), unset: Some(full) }),
                    };
                }
                if name == "PI" {
                    return Ok(std::f64::consts::PI);
                }
                let x = self.argument()?;
                let deg = x.to_radians();
                let domain = |ok: bool, v: f64| if ok { Ok(v) } else { err(start, format!("{name} {x} is outside the function's domain")) };
                match name.as_str() {
                    "SIN" => Ok(deg.sin()),
                    "COS" => Ok(deg.cos()),
                    "TAN" => domain(deg.cos().abs() > 1e-12, deg.tan()),
                    "ASIN" => domain((-1.0..=1.0).contains(&x), x.asin().to_degrees()),
                    "ACOS" => domain((-1.0..=1.0).contains(&x), x.acos().to_degrees()),
                    "ATAN" => Ok(x.atan().to_degrees()),
                    "SQ" => Ok(x * x),
                    "SQRT" => domain(x >= 0.0, x.sqrt()),
                    "LN" => domain(x > 0.0, x.ln()),
                    "LOG" => domain(x > 0.0, x.log10()),
                    "EXP" => domain(x.exp().is_finite(), x.exp()),
                    "NEG" => Ok(-x),
                    "INT" => Ok(x.trunc()),
                    "ABS" => Ok(x.abs()),
                    "FRAC" => Ok(x.fract()),
                    "SGN" => Ok(if x >= 0.0 { 1.0 } else { -1.0 }),
                    _ => err(start, format!("unknown function {name}: expected SIN COS TAN ASIN ACOS ATAN SQ SQRT LN LOG EXP NEG INT ABS FRAC SGN or PI")),
                }
            }
            _ => err(at, format!("unexpected '{}' where a value was expected", self.rest())),
        }
    }
}

/// The formula an `FN` function computes from its operands' texts (`FN 1: Q1 = +Q2 + +3` has `+Q2`
/// and `+3`), or why it is not one of the arithmetic functions.
pub(crate) fn fn_formula(number: u32, operands: &str) -> Result<String, String> {
    // Split `a OP b` at the operator word or sign the function writes between its operands.
    let two = |op: &str| -> Result<(String, String), String> {
        let u = operands.to_ascii_uppercase();
        // The operator: the first one after the first operand's own sign and value.
        let skip = u.trim_start().len() - u.trim_start().trim_start_matches(['+', '-']).len() + (u.len() - u.trim_start().len());
        match u[skip..].find(op) {
            Some(k) => Ok((operands[..skip + k].trim().to_string(), operands[skip + k + op.len()..].trim().to_string())),
            None => Err(format!("FN {number}: expected two values joined by {op}")),
        }
    };
    Ok(match number {
        0 => format!("({})", operands.trim()),
        1 => two("+").map(|(a, b)| format!("({a})+({b})"))?,
        2 => two("-").map(|(a, b)| format!("({a})-({b})"))?,
        3 => two("*").map(|(a, b)| format!("({a})*({b})"))?,
        4 => two("DIV").map(|(a, b)| format!("({a})/({b})"))?,
        5 => format!("SQRT({})", operands.trim().trim_start_matches("SQRT").trim_start_matches("sqrt")),
        6 => format!("SIN({})", operands.trim().trim_start_matches("SIN").trim_start_matches("sin")),
        7 => format!("COS({})", operands.trim().trim_start_matches("COS").trim_start_matches("cos")),
        8 => two("LEN").map(|(a, b)| format!("SQRT(({a})^2+({b})^2)"))?,
        _ => return Err(format!("FN {number}: not an arithmetic function (FN 0 to FN 8)")),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(name: &str) -> Option<f64> {
        match name {
            "Q1" => Some(2.0),
            "Q2" => Some(-3.0),
            "QL5" => Some(0.5),
            _ => None,
        }
    }

    /// The manual's examples and the precedence rules, evaluated.
    #[test]
    fn formulas_evaluate_as_the_tnc_does() {
        let v = |t: &str| eval(t, &q).unwrap();
        assert_eq!(v("3^3"), 27.0);
        assert_eq!(v("400 % 360"), 40.0);
        assert_eq!(v("+Q1 + -Q2 * 2"), 8.0);
        assert_eq!(v("(Q1 + 1) * Q2"), -9.0);
        assert_eq!(v("2^3^2"), 512.0);
        assert_eq!(v("SGN Q2"), -1.0);
        assert_eq!(v("INT 2.7 + FRAC 2.5"), 2.5);
        assert!((v("SIN 30") - 0.5).abs() < 1e-15);
        assert!((v("ATAN 1") - 45.0).abs() < 1e-12);
        assert!((v("PI") - std::f64::consts::PI).abs() < 1e-15);
        assert_eq!(v("SQ QL5"), 0.25);
        assert_eq!(v("NEG Q1"), -2.0);
        assert_eq!(v("-Q1^2"), -4.0);
        let e = eval("Q1 / (Q1 - 2)", &q).unwrap_err();
        assert!(e.message.contains("division by zero"), "{e:?}");
        let e = eval("Q1 + Q77", &q).unwrap_err();
        assert_eq!((e.at, e.unset.as_deref()), (5, Some("Q77")));
        assert!(eval("(Q1 + 1", &q).is_err() && eval("Q1 +", &q).is_err() && eval("FOO 2", &q).is_err() && eval("SQRT -1", &q).is_err());
        assert!(check("SQRT(Q1) / Q9").is_ok() && check("Q1 ++").is_err());
        let deep = format!("{}1{}", "(".repeat(100), ")".repeat(100));
        assert!(eval(&deep, &q).unwrap_err().message.contains("nested"));
    }

    /// FN 0 to FN 8 as formulas.
    #[test]
    fn fn_functions_are_formulas() {
        let v = |n: u32, t: &str| eval(&fn_formula(n, t).unwrap(), &q).unwrap();
        assert_eq!(v(0, "+Q1"), 2.0);
        assert_eq!(v(1, "+Q1 + +3"), 5.0);
        assert_eq!(v(2, "-Q1 - -3"), 1.0);
        assert_eq!(v(3, "+Q1 * -Q2"), 6.0);
        assert_eq!(v(4, "-Q2 DIV +3"), 1.0);
        assert_eq!(v(5, "SQRT 16"), 4.0);
        assert_eq!(v(8, "+3 LEN +4"), 5.0);
        assert!(fn_formula(14, "1").is_err());
    }
}
