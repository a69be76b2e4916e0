//! Pieces shared by the readers: strict number syntax and diagnostics collection.

use super::{Diagnostic, Severity};

/// A decimal number as NC programs write it: `+14.825`, `-8`, `.5`, `3.`. Nothing else is a number
/// (no exponents, no embedded spaces, no `C.L..`), so a damaged value is never read as one.
pub fn parse_number(s: &str) -> Option<f64> {
    let body = s.strip_prefix(['+', '-']).unwrap_or(s);
    if body.is_empty() {
        return None;
    }
    let mut digits = 0;
    let mut dots = 0;
    for c in body.chars() {
        match c {
            '0'..='9' => digits += 1,
            '.' => dots += 1,
            _ => return None,
        }
    }
    if digits == 0 || dots > 1 {
        return None;
    }
    s.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// Length of the longest prefix of `s` made of number characters (`+-.0-9`).
pub fn number_prefix_len(s: &str) -> usize {
    s.char_indices()
        .find(|&(i, c)| !(c.is_ascii_digit() || c == '.' || ((c == '+' || c == '-') && i == 0)))
        .map(|(i, _)| i)
        .unwrap_or(s.len())
}

/// Diagnostics being collected for one program.
#[derive(Debug, Default)]
pub struct Diags(pub Vec<Diagnostic>);

impl Diags {
    pub fn error(&mut self, line: usize, column: usize, message: impl Into<String>) {
        self.0.push(Diagnostic { line, column, severity: Severity::Error, message: message.into() });
    }
    pub fn warning(&mut self, line: usize, column: usize, message: impl Into<String>) {
        self.0.push(Diagnostic { line, column, severity: Severity::Warning, message: message.into() });
    }
}

/// Shorten a damaged piece of text for a message.
pub fn excerpt(s: &str) -> String {
    let mut out: String = s.chars().take(24).collect();
    if s.chars().count() > 24 {
        out.push('…');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn numbers() {
        assert_eq!(parse_number("+14.825"), Some(14.825));
        assert_eq!(parse_number("-8"), Some(-8.0));
        assert_eq!(parse_number(".5"), Some(0.5));
        assert_eq!(parse_number("3."), Some(3.0));
        for bad in [".L..", "", "+", ".", "1.2.3", "1e5", "23 162", "nan", "inf"] {
            assert_eq!(parse_number(bad), None, "{bad}");
        }
    }
}
