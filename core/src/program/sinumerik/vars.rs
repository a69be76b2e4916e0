//! The variables of an 840D program: `DEF REAL`/`INT`/`BOOL` variables and the channel's R
//! parameters, by name, with their values once set, each program level's own set aside while a
//! subprogram runs; what a refused block set is undone. Bounded: at most [`MAX_VARIABLES`].

use super::expr;
use std::collections::HashMap;

/// Most variables one program may define (DEF and R parameters together): bounds the table.
pub(crate) const MAX_VARIABLES: usize = 10_000;

/// Highest R parameter number read (R0-R999: the 840D's MD28050 `MM_NUM_R_PARAM` allows up to 32535;
/// its default is 100).
const MAX_R: u32 = 999;

/// A variable's data type (DEF REAL, INT, BOOL): what an assignment to it keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Type {
    Real,
    Int,
    Bool,
}

/// The variables of a program: DEF variables and R parameters, by name in capitals, with a value
/// once set.
#[derive(Debug, Clone, Default)]
pub(crate) struct Vars {
    map: HashMap<String, (Type, Option<f64>)>,
    /// What the current block changed (each name's entry before it), to undo if the block is refused.
    journal: Vec<(String, Option<(Type, Option<f64>)>)>,
    /// The names of the calling levels' own variables, while a subprogram runs (for messages).
    outer: Vec<Vec<String>>,
    /// The expressions of lines run again, compiled once ([`Vars::eval`]).
    compiled: expr::Cache,
    /// The line being read runs again (a loop's pass, a jump back, a subprogram called again): its
    /// expressions are kept compiled.
    pub(crate) again: bool,
}

/// A program level's own variables, set aside while a subprogram runs.
#[derive(Debug, Clone, Default)]
pub(crate) struct Level(HashMap<String, (Type, Option<f64>)>);

/// `R12`: an R parameter's name (R, then its number).
fn r_number(name: &str) -> Option<u32> {
    let digits = name.strip_prefix('R')?;
    (!digits.is_empty() && digits.len() <= 5 && digits.bytes().all(|b| b.is_ascii_digit())).then(|| digits.parse().ok()).flatten()
}

impl Vars {
    /// The value of `name` (capitals), or why it has none.
    pub(crate) fn get(&self, name: &str) -> Result<f64, String> {
        value(&self.map, &self.outer, name)
    }

    /// The value of the expression `text` with these variables; compiled once for a line that runs
    /// again.
    pub(crate) fn eval(&mut self, text: &str) -> Result<f64, expr::ExprError> {
        let Vars { map, outer, compiled, again, .. } = self;
        let var = |name: &str| value(map, outer, name);
        if *again { compiled.eval(text, &var) } else { expr::eval(text, &var) }
    }

    /// Whether `name` is a variable an assignment may set.
    pub(crate) fn is_variable(&self, name: &str) -> bool {
        self.map.contains_key(name) || r_number(name).is_some_and(|n| n <= MAX_R)
    }

    /// A subprogram's level begins: the caller's own variables (DEF: each program level's, its LUD)
    /// are set aside and given back; R parameters stay (the channel's, every level sees them).
    pub(crate) fn enter_level(&mut self) -> Level {
        let own = self.take_own();
        self.outer.push(own.keys().cloned().collect());
        Level(own)
    }

    /// The subprogram's level ends: its own variables go, the caller's come back.
    pub(crate) fn leave_level(&mut self, caller: Level) {
        self.take_own();
        self.map.extend(caller.0);
        self.outer.pop();
    }

    /// This level's own variables, taken out; the R parameters stay.
    fn take_own(&mut self) -> HashMap<String, (Type, Option<f64>)> {
        self.journal.clear();
        let (r, own) = std::mem::take(&mut self.map).into_iter().partition(|(name, _)| r_number(name).is_some());
        self.map = r;
        own
    }

    /// A PROC's parameter, defined with its caller's value (`None`: not given, so read before set).
    pub(crate) fn parameter(&mut self, name: &str, ty: Type, value: Option<f64>) -> Result<(), String> {
        self.define(name, ty, Some(0.0))?;
        if let Some(entry) = self.map.get_mut(name) {
            entry.1 = value.map(|v| keep(ty, v));
        }
        Ok(())
    }

    /// The block read well: keep what it set.
    pub(crate) fn commit(&mut self) {
        self.journal.clear();
    }

    /// The block was refused: undo what it set.
    pub(crate) fn rollback(&mut self) {
        while let Some((name, before)) = self.journal.pop() {
            match before {
                Some(entry) => self.map.insert(name, entry),
                None => self.map.remove(&name),
            };
        }
    }

    fn remember(&mut self, name: &str) {
        let before = self.map.get(name).copied();
        self.journal.push((name.to_string(), before));
    }

    /// `DEF type name[=value]`; without a value it is 0 ("If no explicit initialization value is
    /// defined ... the variable is set to the data type's implicit initialization value. INT: 0,
    /// REAL: 0.0", SINUMERIK Programming Manual 12/2019 6FC5398-2EP40-0BA0 §3.1.1 "Definition (DEF)
    /// of user variables"; BOOL's FALSE is 0).
    pub(crate) fn define(&mut self, name: &str, ty: Type, value: Option<f64>) -> Result<(), String> {
        if self.map.contains_key(name) {
            return Err(format!("{name} is defined twice"));
        }
        if r_number(name).is_some() || name.len() < 2 {
            return Err(format!("{name}: not a variable name (R parameters need no DEF; a name has two characters or more)"));
        }
        if self.map.len() >= MAX_VARIABLES {
            return Err(format!("more than {MAX_VARIABLES} variables"));
        }
        self.remember(name);
        self.map.insert(name.to_string(), (ty, Some(keep(ty, value.unwrap_or(0.0)))));
        Ok(())
    }

    /// `name = value`: an INT keeps the value rounded, a BOOL whether it is not 0.
    pub(crate) fn assign(&mut self, name: &str, value: f64) -> Result<(), String> {
        if self.map.contains_key(name) {
            self.remember(name);
        }
        if let Some((ty, v)) = self.map.get_mut(name) {
            *v = Some(keep(*ty, value));
            return Ok(());
        }
        match r_number(name) {
            Some(n) if n <= MAX_R => {
                if self.map.len() >= MAX_VARIABLES {
                    return Err(format!("more than {MAX_VARIABLES} variables"));
                }
                self.remember(name);
                self.map.insert(name.to_string(), (Type::Real, Some(value)));
                Ok(())
            }
            Some(n) => Err(format!("R{n}: R parameters are read up to R{MAX_R}")),
            None => Err(format!("{name} is not defined (DEF) in this program")),
        }
    }
}

/// The value of the variable `name` (capitals) in `map`, or why it has none (`outer`: the calling
/// levels' own names, for the message).
fn value(map: &HashMap<String, (Type, Option<f64>)>, outer: &[Vec<String>], name: &str) -> Result<f64, String> {
    match map.get(name) {
        Some((_, Some(v))) => Ok(*v),
        // Only a PROC's parameter has no value: the main program's, which no call gave one.
        Some((_, None)) => Err(format!("{name} is a parameter of the program's PROC, which its call gives: this program is a subprogram (read the program that calls it)")),
        None if r_number(name).is_some() => Err(format!("{name} is read before this program sets it (R parameters keep what earlier programs left)")),
        None if outer.first().is_some_and(|l| l.iter().any(|n| n == name)) => Err(format!(
            "{name} is not defined (DEF) in this subprogram: the main program's variable, which a subprogram sees only where the main program's are program-global (PUD, by machine datum MD11120)"
        )),
        None if outer.iter().any(|l| l.iter().any(|n| n == name)) => Err(format!("{name} is not defined (DEF) in this subprogram: a calling subprogram's own variable (each program level's are its own)")),
        None => Err(format!("{name} is not defined (DEF) in this program")),
    }
}

/// The value a variable of type `ty` keeps (the 840D converts REAL to INT by rounding).
fn keep(ty: Type, v: f64) -> f64 {
    match ty {
        Type::Real => v,
        Type::Int => expr::round(v),
        Type::Bool => f64::from(u8::from(v != 0.0)),
    }
}
