//! Q-parameter statements: assignments `Q1 = formula`, `FN 0`-`FN 8` and the conditional jumps
//! `FN 9`-`FN 12` (TNC 320 User's Manual §9, "Programming: Q parameters"); formulas are [`super::formula`]'s.

use super::*;

/// The comparison of a conditional jump (FN 9 EQU, FN 10 NE, FN 11 GT, FN 12 LT).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Cmp {
    Eq,
    Ne,
    Gt,
    Lt,
}

impl Cmp {
    pub(super) fn holds(self, a: f64, b: f64) -> bool {
        match self {
            Cmp::Eq => a == b,
            Cmp::Ne => a != b,
            Cmp::Gt => a > b,
            Cmp::Lt => a < b,
        }
    }
}

/// Whether `u` (in capitals) is `prefix` followed by a number (`Q1`, `QS330`).
fn numbered(u: &str, prefix: &str) -> bool {
    u.strip_prefix(prefix).is_some_and(|d| !d.is_empty() && d.bytes().all(|c| c.is_ascii_digit()))
}

/// A Q parameter's name in capitals (`Q1`, `QL3`, `QR20`), if `s` is one.
pub(super) fn q_name(s: &str) -> Option<String> {
    let u = s.trim().to_ascii_uppercase();
    ["QL", "QR", "Q"].iter().any(|p| numbered(&u, p)).then_some(u)
}

/// `Q1 = formula` (TNC 320 DIN/ISO 3/2014 §9.9, "Entering formulas directly"); `in_cycle` for a
/// cycle's parameter (a `~` line after its `CYCL DEF`), where a feed may be `MAX`, rapid traverse
/// (`Q208= MAX ;RETRACTION FEED RATE`, as the TNC's editor writes the FMAX soft key).
pub(super) fn assign<'a>(raw: &'a str, toks: &[(&'a str, usize)], in_cycle: bool, line: usize, col: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let text = text_from(raw, toks, 0);
    let Some((lhs, rhs)) = text.split_once('=') else {
        diags.error(line, col, format!("'{}': expected Qn = a value or formula", excerpt(text)));
        return None;
    };
    // A string parameter set to a text (`QS330="T1"` in a touch probe cycle's list; iTNC 530
    // user's manual §10, "String parameters"): no number of the motion's; a string formula is not
    // read.
    let upper = lhs.trim().to_ascii_uppercase();
    if numbered(&upper, "QS") {
        let value = rhs.trim();
        if !(value.len() >= 2 && value.starts_with('"') && value.ends_with('"') && !value[1..value.len() - 1].contains('"')) {
            diags.error(line, col, format!("{upper} = {}: a string formula is not read (a text in quotes is)", excerpt(value)));
        }
        return None;
    }
    let Some(name) = q_name(lhs) else {
        diags.error(line, col, format!("'{}': expected a Q parameter name such as Q1", excerpt(lhs.trim())));
        return None;
    };
    if rhs.trim().eq_ignore_ascii_case("MAX") {
        if in_cycle {
            return Some(Kind::AssignMax { name });
        }
        diags.error(line, col, format!("{name} = MAX: MAX (rapid traverse) is written among a cycle's parameters, the lines after its CYCL DEF that end in '~'"));
        return None;
    }
    formula_kind(name, Cow::Borrowed(rhs.trim()), line, col + text.find('=').map_or(0, |k| k + 1), diags)
}

pub(super) fn formula_kind<'a>(name: String, formula: Cow<'a, str>, line: usize, col: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    match formula::check(&formula) {
        Ok(()) => Some(Kind::Assign { name, formula }),
        Err(e) => {
            diags.error(line, col + e.at, format!("{name} = {}: {}", excerpt(&formula), e.message));
            None
        }
    }
}

/// `FN n: ...`: the arithmetic functions FN 0 to FN 8 (a formula), the jumps FN 9 to FN 12.
pub(super) fn fn_statement<'a>(raw: &'a str, toks: &[(&'a str, usize)], line: usize, col: usize, diags: &mut Diags) -> Option<Kind<'a>> {
    let text = text_from(raw, toks, 1);
    let Some((number, body)) = text.split_once(':') else {
        diags.error(line, col, format!("FN {}: expected FN n: followed by its operands", excerpt(text)));
        return None;
    };
    let Ok(n) = number.trim().parse::<u32>() else {
        diags.error(line, col, format!("FN {}: expected a function number", excerpt(number)));
        return None;
    };
    match n {
        0..=8 => {
            let Some((lhs, rhs)) = body.split_once('=') else {
                diags.error(line, col, format!("FN {n}: expected Qn = its operands"));
                return None;
            };
            let Some(name) = q_name(lhs) else {
                diags.error(line, col, format!("FN {n}: '{}' is not a Q parameter", excerpt(lhs.trim())));
                return None;
            };
            match formula::fn_formula(n, rhs) {
                Ok(f) => formula_kind(name, Cow::Owned(f), line, col, diags),
                Err(why) => {
                    diags.error(line, col, why);
                    None
                }
            }
        }
        9..=12 => {
            // IF a OP b GOTO LBL label
            let u = body.to_ascii_uppercase();
            let (op, cmp) = [("EQU", Cmp::Eq), ("NE", Cmp::Ne), ("GT", Cmp::Gt), ("LT", Cmp::Lt)][(n - 9) as usize];
            let (Some(if_at), Some(op_at), Some(goto_at)) = (u.find("IF"), u.find(op), u.find("GOTO")) else {
                diags.error(line, col, format!("FN {n}: expected IF a {op} b GOTO LBL label"));
                return None;
            };
            if !(if_at < op_at && op_at < goto_at) {
                diags.error(line, col, format!("FN {n}: expected IF a {op} b GOTO LBL label"));
                return None;
            }
            let a = body[if_at + 2..op_at].trim().to_string();
            let b = body[op_at + op.len()..goto_at].trim().to_string();
            let after = body[goto_at + 4..].trim_start();
            let Some(label) = after.get(..3).filter(|l| l.eq_ignore_ascii_case("LBL")).map(|_| after[3..].trim().trim_matches('"')) else {
                diags.error(line, col, format!("FN {n}: expected GOTO LBL and the label"));
                return None;
            };
            for v in [&a, &b] {
                if let Err(e) = formula::check(v) {
                    diags.error(line, col, format!("FN {n}: '{}': {}", excerpt(v), e.message));
                    return None;
                }
            }
            if label.is_empty() {
                diags.error(line, col, format!("FN {n}: GOTO LBL without a label"));
                return None;
            }
            // The label borrows from the line's text.
            let start = label.as_ptr() as usize - raw.as_ptr() as usize;
            Some(Kind::Jump { a, cmp, b, label: &raw[start..start + label.len()] })
        }
        _ => {
            diags.error(line, col, format!("FN {n}: not read (only the arithmetic FN 0 to FN 8 and the jumps FN 9 to FN 12)"));
            None
        }
    }
}
