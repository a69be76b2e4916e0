//! One Sinumerik block's words, as the 840D reads a block (Fundamentals 6FC5398-1BP10 §2.2 "Block
//! structure": `N` number, `/` skip, words of an address and a value, `X=<expression>` where the
//! value is computed, extended addresses `A3=`, `CR=`, `TURN=`, keywords with or without arguments
//! `CYCLE800(...)`, `;` comment), and `DEF` statements, which define the variables ([`super::vars`])
//! its expressions read. Values are evaluated here, in the block's order: an assignment is in effect
//! for the words after it.

use crate::program::interp::{Dimension, Turn, Word};
use crate::program::lex::{excerpt, number_prefix_len, parse_number, parse_number_prefix, upper, word_end, Columns, Diags};
use std::borrow::Cow;

use super::vars::{Type, Vars};

/// A keyword of a block (`TRAORI`, `SUPA`, `CYCLE800(...)`): its name in capitals, its arguments'
/// text inside the brackets, and its column.
#[derive(Debug, Clone)]
pub(crate) struct Keyword<'a> {
    pub name: String,
    pub args: Option<&'a str>,
    pub col: usize,
}

/// A block's words.
pub(crate) struct Lexed<'a> {
    pub words: Vec<Word<'a>>,
    pub number: Option<u64>,
    pub keywords: Vec<Keyword<'a>>,
    /// A3 B3 C3, unit.
    pub vector: Option<[f64; 3]>,
    /// `D`: the tool edge selected (0: the tool's offsets off), and its column.
    pub edge: Option<(f64, usize)>,
    /// `RPL=`: a frame's rotation in the working plane, degrees, and its column.
    pub rpl: Option<(f64, usize)>,
    /// `DISC=` (the transition circle's distortion, 0 to 100) and `OFFN=` (the contour's offset),
    /// tool radius compensation's settings ([`super::trc`]), with their columns.
    pub disc: Option<(f64, usize)>,
    pub offn: Option<(f64, usize)>,
    /// `CHF=`, `CHR=`, `RND=`, `RNDM=`, `FRC=`, `FRCM=`: the corner at the block's end
    /// ([`super::corners`]).
    pub corner: super::corners::Words,
    /// The first G code refused that moves the tool, as written (`74`): the holds take its move
    /// ([`super::keywords::refused_move`]).
    pub refused_g: Option<&'a str>,
    /// `G58`/`G59` (axial programmable offsets, refused): the frame they change holds the moves.
    pub frame_g: Option<&'a str>,
    /// `L47` among other words (refused): the program it calls, which the control runs.
    pub call_l: Option<&'a str>,
    /// The words of circles given otherwise and of polar coordinates, boxed: few lines have them.
    pub circle: Option<Box<CircleWords>>,
}

/// A line's words of [`super::circles`] and [`super::polar`].
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct CircleWords {
    /// `I1=`, `J1=`, `K1=`: a `CIP` circle's intermediate point.
    pub through: super::circles::Through,
    /// `AR=`: a circle's opening angle, deg.
    pub ar: super::circles::Opening,
    /// `AP=` and `RP=`: polar angle (deg) and radius.
    pub ap: super::polar::PolarWord,
    pub rp: super::polar::PolarWord,
}

/// Whether a word operator (DIV, AND ...) starts at byte `j` of `b`.
fn word_op_at(b: &[u8], j: usize) -> bool {
    let ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    // (Their first letters first: the next word's address is seldom one of them.)
    b.get(j).is_some_and(|c| matches!(c.to_ascii_uppercase(), b'D' | b'M' | b'A' | b'O' | b'X' | b'N'))
        && ["DIV", "MOD", "AND", "OR", "XOR", "NOT"].iter().any(|op| {
            let e = j + op.len();
            b.get(j..e).is_some_and(|w| w.eq_ignore_ascii_case(op.as_bytes())) && !b.get(e).copied().is_some_and(ident)
        })
}

/// Whether a number that ends at byte `e` ends the expression it starts, by [`expression_end`]'s
/// rule: at the line's end, a `;`, or blanks not followed by an operator (`X=10 + 5` goes on).
fn number_ends_expression(b: &[u8], e: usize) -> bool {
    match b.get(e) {
        None | Some(b';') => true,
        Some(c) if c.is_ascii_whitespace() => {
            let j = e + b[e..].iter().take_while(|c| c.is_ascii_whitespace()).count();
            j >= b.len() || b[j] == b';' || !(b"+-*/=<>)".contains(&b[j]) || word_op_at(b, j))
        }
        _ => false,
    }
}

/// Where the expression that starts at byte `start` ends: at a blank or `;` outside brackets and
/// strings, unless an operator stands before or after the blank (`X=R1 + 5`).
fn expression_end(b: &[u8], start: usize) -> usize {
    let n = b.len();
    let ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let word_op_at = |j: usize| word_op_at(b, j);
    // A word operator ending just before `j`.
    let word_op_before = |j: usize| {
        // Each ends in a letter: a value's last digit ends none.
        if j == start || !b[j - 1].is_ascii_alphabetic() {
            return false;
        }
        let mut k = j;
        while k > start && ident(b[k - 1]) {
            k -= 1;
        }
        k < j && word_op_at(k) && (k == start || !ident(b[k - 1]))
    };
    // The bytes that end an expression or change its nesting: blanks, `;`, brackets and quotes (a
    // value's digits, signs, letters and operators pass by one table look-up each).
    const SPECIAL: [bool; 256] = {
        let mut t = [false; 256];
        let mut c = 0;
        while c < 256 {
            t[c] = matches!(c as u8, b'"' | b'(' | b'[' | b')' | b']' | b';') || (c as u8).is_ascii_whitespace();
            c += 1;
        }
        t
    };
    let (mut i, mut depth, mut in_str) = (start, 0i32, false);
    while i < n {
        let c = b[i];
        if in_str {
            in_str = c != b'"';
            i += 1;
            continue;
        }
        if !SPECIAL[usize::from(c)] {
            i += 1;
            continue;
        }
        match c {
            b'"' => in_str = true,
            b'(' | b'[' => depth += 1,
            b')' | b']' => {
                depth -= 1;
                if depth < 0 {
                    return i;
                }
            }
            b';' if depth == 0 => return i,
            c if c.is_ascii_whitespace() && depth == 0 => {
                let mut j = i;
                while j < n && b[j].is_ascii_whitespace() {
                    j += 1;
                }
                if j >= n || b[j] == b';' {
                    return i;
                }
                let prev = b[start..i].iter().rev().copied().find(|c| !c.is_ascii_whitespace());
                let after_op = prev.is_none_or(|p| b"+-*/=<>(,".contains(&p)) || word_op_before(i);
                let before_op = b"+-*/=<>)".contains(&b[j]) || word_op_at(j);
                if !(after_op || before_op) {
                    return i;
                }
                i = j;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    n
}

/// The end of the bracketed arguments that open at byte `open` (`(`), past the `)`, outside strings;
/// `None` if the line ends first.
pub(super) fn arguments_end(b: &[u8], open: usize) -> Option<usize> {
    let (mut depth, mut in_str) = (0usize, false);
    for (k, &c) in b.iter().enumerate().skip(open) {
        match c {
            b'"' => in_str = !in_str,
            b'(' if !in_str => depth += 1,
            b')' if !in_str => {
                depth -= 1;
                if depth == 0 {
                    return Some(k + 1);
                }
            }
            _ => {}
        }
    }
    None
}

/// Split one line into words; assignments go to `vars` as they are read; defects go to `diags`.
/// Works on bytes: every character that can form a word is ASCII, and any other one is reported
/// where it stands.
pub(crate) fn lex_line<'a>(src: &'a str, cols: &Columns<'_>, line: usize, vars: &mut Vars, diags: &mut Diags) -> Lexed<'a> {
    let b = src.as_bytes();
    let n = b.len();
    let mut out = Lexed { words: Vec::with_capacity(8), number: None, keywords: Vec::new(), vector: None, edge: None, rpl: None, disc: None, offn: None, corner: Default::default(), refused_g: None, frame_g: None, call_l: None, circle: None };
    let mut vec3: [Option<f64>; 3] = [None; 3];
    let mut vec_col = 0;
    let mut i = src.find(|c: char| !c.is_whitespace()).unwrap_or(n);
    if i < n && b[i] == b'/' {
        if b.get(i + 1).is_some_and(u8::is_ascii_digit) {
            // Skip levels (/0 to /9 on some controls) are not in the manuals in reach: refused, not guessed.
            let level: String = src[i..].chars().take_while(|c| *c == '/' || c.is_ascii_digit()).collect();
            diags.error(line, cols.col(i), format!("block skip level '{level}' is not read (only the plain skip '/' is)"));
            return out;
        }
        diags.warning(line, cols.col(i), "block skip '/' is not modelled: the block is run");
        i += 1;
    }
    // The end of a token from byte `from`: the next whitespace or ';' (an ASCII byte, so on a
    // character boundary), or the line's end.
    let token_end = |from: usize| word_end(b, from);
    while i < n {
        let c = b[i];
        if c.is_ascii_whitespace() || !src.is_char_boundary(i) {
            i += 1;
            continue;
        }
        if c == b';' {
            break;
        }
        let col = cols.col(i);
        let word_start = i;
        if !c.is_ascii_alphabetic() && c != b'_' {
            let end = token_end(i).max(i + 1);
            let end = (end..=n).find(|&e| src.is_char_boundary(e)).unwrap_or(n);
            if c == b'"' {
                // A text where no word takes one: `CALL "NAME"` calls a program only alone in its block.
                diags.error(line, col, format!("{}: a text where no word takes one (CALL \"NAME\" calls a program alone in its block, a blank after CALL)", excerpt(&src[i..end])));
            } else {
                diags.error(line, col, format!("unexpected '{}': expected a word such as G1 or X=10.5", excerpt(&src[i..end])));
            }
            i = end;
            continue;
        }
        // The address: letters, then digits that belong to it when '=' follows (A3=, CR=, R1=,
        // _VAR_2=) or when it is a keyword (CYCLE800).
        let mut j = i;
        while j < n && (b[j].is_ascii_alphabetic() || b[j] == b'_') {
            j += 1;
        }
        let mut k = j;
        // One letter, digits, then a letter: a word and the next written without a blank (`G2X10`,
        // `X10CR=5`, `G1X=10`), not one name (a name starts with two letters or `_`).
        let mut glued = false;
        if j == i + 1 {
            while k < n && b[k].is_ascii_digit() {
                k += 1;
            }
            glued = k > j && k < n && b[k].is_ascii_alphabetic();
        }
        if glued {
            k = j;
        } else {
            while k < n && (b[k].is_ascii_alphanumeric() || b[k] == b'_') {
                k += 1;
            }
        }
        let mut e = k;
        while e < n && (b[e] == b' ' || b[e] == b'\t') {
            e += 1;
        }
        let with_eq = e < n && b[e] == b'=' && b.get(e + 1) != Some(&b'=');
        let letters = &src[i..j];
        // Keywords: more than one letter and no '=' (TRAORI, SUPA, MSG(...), CYCLE800(...)).
        if !with_eq && letters.len() > 1 {
            let name = src[i..k].to_ascii_uppercase();
            let mut end = k;
            let mut args = None;
            let mut a = k;
            while a < n && (b[a] == b' ' || b[a] == b'\t') {
                a += 1;
            }
            if a < n && b[a] == b'(' {
                match arguments_end(b, a) {
                    Some(close) => {
                        args = Some(&src[a + 1..close - 1]);
                        end = close;
                    }
                    None => {
                        diags.error(line, col, format!("{name}(: the bracket is not closed on this line"));
                        return out;
                    }
                }
            }
            out.keywords.push(Keyword { name, args, col });
            i = end;
            continue;
        }
        // Upper case as written almost always: borrowed then, no allocation per word.
        let address = upper(if with_eq { &src[i..k] } else { letters });
        let value_start = if with_eq { e + 1 } else { j };
        let mut v = value_start;
        while with_eq && v < n && (b[v] == b' ' || b[v] == b'\t') {
            v += 1;
        }
        if address == "T" && v < n && b[v] == b'"' {
            // T="NAME": a tool called by name (an event, as T5 is).
            match src[v + 1..].find('"') {
                Some(p) => {
                    let e = v + 1 + p + 1;
                    out.words.push(Word { letter: 'T', value: 0.0, raw: src[v..e].into(), column: col, dimension: Dimension::Modal });
                    i = e;
                }
                None => {
                    diags.error(line, col, "T=\"...: the tool name's quote is not closed on this line");
                    i = n;
                }
            }
            continue;
        }
        // The value: an expression after '=', else a number written straight after the address.
        let mut dimension = Dimension::Modal;
        // Most values are a number alone (`A3=0.1234567`, `X10.5`): read in one pass, ending where
        // the expression or the word would; anything else takes the full path below.
        let number = parse_number_prefix(&b[v..]).filter(|&(_, len)| {
            let e = v + len;
            if with_eq { number_ends_expression(b, e) } else { b.get(e).is_none_or(|&c| c.is_ascii_alphabetic() || c.is_ascii_whitespace() || c == b';') }
        });
        let (value, text): (f64, &'a str) = if let Some((x, len)) = number {
            i = v + len;
            (x, &src[v..i])
        } else if with_eq {
            let end = expression_end(b, v);
            let text = &src[v..end];
            i = end.max(v + 1).min(n);
            while i < n && !src.is_char_boundary(i) {
                i += 1;
            }
            // AC()/IC() dimension an axis or a circle centre's word; anywhere else they are refused.
            let dimensioned_word = matches!(address.as_ref(), "X" | "Y" | "Z" | "A" | "B" | "C" | "I" | "J" | "K" | "I1" | "J1" | "K1" | "AP");
            let trimmed = text.trim();
            match parse_number(trimmed) {
                Some(x) => (x, trimmed),
                None => match if dimensioned_word { dimensioned(text, vars) } else { value_of(text, vars).map(|x| (x, Dimension::Modal)) } {
                    Ok((_, Dimension::Modulo(t))) if !matches!(address.as_ref(), "A" | "B" | "C") => {
                        diags.error(line, cols.col(v), format!("{address}={}: {}() positions a modulo rotary axis (A, B, C), not {address}", excerpt(text), t.name()));
                        continue;
                    }
                    Ok((x, d)) => {
                        dimension = d;
                        (x, trimmed)
                    }
                    Err(why) => {
                        diags.error(line, cols.col(v), format!("{address}={}: {why}", excerpt(text)));
                        continue;
                    }
                },
            }
        } else {
            let start = v;
            let end = v + number_prefix_len(&src[v..]);
            let text = &src[start..end];
            let stop = token_end(end);
            i = stop.max(i + 1);
            // A word is an address letter and a sequence of digits (Programming Manual
            // Fundamentals 12/2019 §2.2.2.1 "Blocks and block components"); blanks and tabs only
            // separate words (its table of characters, p. 52): a letter after the digits starts the next
            // word, as in `T1D1M6` and `G1X10Y20`.
            let next_word = end < n && b[end].is_ascii_alphabetic();
            match parse_number(text).filter(|_| stop == end || next_word) {
                Some(x) => {
                    if next_word {
                        i = end;
                    }
                    (x, text)
                }
                None if end < n && b[end] == b'(' => {
                    // M202(0.0059): a bracket after an address' number is no 840D word (an M value is
                    // a whole number; a subprogram's name starts with two letters).
                    let found = &src[word_start..token_end(word_start)];
                    diags.error(line, col, format!("{}: an address with a bracketed argument is not 840D syntax (an M function takes a whole number; a subprogram's name starts with two letters)", excerpt(found)));
                    continue;
                }
                None => {
                    let found = &src[start..token_end(start)];
                    let hint = if found.is_empty() { "" } else { " (a computed value is written with '=': X=R1+5)" };
                    diags.error(line, col, format!("{address}: expected a number, found '{}'{hint}", excerpt(found)));
                    continue;
                }
            }
        };
        let word = |letter: char, value: f64, raw: Cow<'a, str>| Word { letter, value, raw, column: col, dimension };
        match address.as_ref() {
            "N" if with_eq => diags.error(line, col, "N=: a block number is written N10"),
            "N" if value.fract() == 0.0 && value >= 0.0 => out.number = Some(value as u64),
            "N" => diags.error(line, col, format!("expected a whole block number after 'N', found '{text}'")),
            "G" => match super::sinumerik_g(text) {
                Ok(Some(g)) => out.words.push(word('G', parse_number(g).unwrap_or(0.0), g.into())),
                Ok(None) => {}
                Err(why) => {
                    if out.refused_g.is_none() && super::keywords::refused_move(text).is_some() {
                        out.refused_g = Some(text);
                    }
                    if matches!(text.trim_start_matches('0'), "58" | "59") {
                        out.frame_g = Some(text);
                    }
                    diags.error(line, col, format!("G{text}: {why}"));
                }
            },
            "X" | "Y" | "Z" | "A" | "B" | "C" | "I" | "J" | "K" | "F" | "M" | "S" | "T" => {
                // A computed coordinate's or feed's text is its expression as written (for messages;
                // formatting the number costs more than reading it); M, S and T carry the number.
                let computed = with_eq && matches!(address.as_ref(), "M" | "S" | "T") && parse_number(text).is_none();
                let raw: Cow<'a, str> = if computed { Cow::Owned(format!("{value}")) } else { text.into() };
                out.words.push(word(address.as_bytes()[0] as char, value, raw));
            }
            "D" if value.fract() == 0.0 && value >= 0.0 => out.edge = Some((value, col)),
            "D" => diags.error(line, col, format!("D{text}: expected a tool edge number (D0 switches the offsets off)")),
            "H" => diags.error(line, col, format!("H{text}: auxiliary function not read")),
            // `L47` calls the subprogram L47 (Fundamentals, "Subprogram call"): another program.
            "L" if !with_eq => {
                diags.error(line, col, format!("L{text}: a call of the subprogram L{text} (another program, not read; the motion would depend on it)"));
                out.call_l = out.call_l.or(Some(text));
            }
            "A3" | "B3" | "C3" => {
                vec3[usize::from(address.as_bytes()[0] - b'A')] = Some(value);
                vec_col = if vec_col == 0 { col } else { vec_col };
            }
            "CR" => out.words.push(word('R', value, text.into())),
            "AR" if with_eq => out.circle.get_or_insert_default().ar = Some((value, col)),
            "AP" if with_eq => out.circle.get_or_insert_default().ap = Some((value, dimension, col)),
            "RP" if with_eq => out.circle.get_or_insert_default().rp = Some((value, dimension, col)),
            "I1" | "J1" | "K1" if with_eq => {
                let k = usize::from(address.as_bytes()[0] - b'I');
                let c = out.circle.get_or_insert_default();
                if c.through[k].is_some() {
                    diags.error(line, col, format!("{address} written twice in one block"));
                }
                c.through[k] = Some((value, dimension, col));
            }
            // Read as P, the turns count G2/G3 take (P n+1); written twice, which one counts is not read.
            // Refused here, not by the interpreter's check of a letter written twice: CT's and CIP's
            // forms rewrite the block's words before it (sinumerik/circles.rs), a straight CT dropping P.
            "TURN" if out.words.iter().any(|w| w.letter == 'P') => diags.error(line, col, "TURN written twice in one block (which one counts is not read)"),
            "TURN" if value.fract() == 0.0 && (0.0..1000.0).contains(&value) => out.words.push(word('P', value + 1.0, format!("{}", value + 1.0).into())),
            "TURN" => diags.error(line, col, format!("TURN={text}: expected a whole number of turns, 0 to 999")),
            "RPL" => out.rpl = Some((value, col)),
            "DISC" if with_eq => out.disc = Some((value, col)),
            "OFFN" if with_eq => out.offn = Some((value, col)),
            "CHF" | "CHR" | "RND" | "RNDM" | "FRC" | "FRCM" if with_eq => {
                if let Err(why) = out.corner.set(address.as_ref(), value, col) {
                    diags.error(line, col, why);
                }
            }
            name if with_eq && vars.is_variable(name) => {
                if let Err(why) = vars.assign(name, value) {
                    diags.error(line, col, why);
                }
            }
            name if with_eq => diags.error(line, col, format!("{name}={text}: {} (it may change the motion)", unknown_address(name))),
            name => diags.error(line, col, format!("unsupported word {name}{text}: not read (it may change the motion)")),
        }
    }
    if vec3.iter().any(Option::is_some) {
        let v = vec3.map(|c| c.unwrap_or(0.0)); // a component not written is 0 (840D: not modal)
        let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if norm > 1e-9 {
            out.vector = Some(v.map(|c| c / norm));
        } else {
            diags.error(line, vec_col, "tool vector A3 B3 C3 has zero length: expected a direction");
        }
    }
    out
}

/// What an address with '=' the reader does not know is.
fn unknown_address(name: &str) -> &'static str {
    if name.starts_with('$') {
        "a system variable, not set here"
    } else if matches!(name, "SD" | "PL") {
        "a spline's degree or parameter interval (BSPLINE), which is not read"
    } else if name.len() == 2 && name.as_bytes()[1].is_ascii_digit() {
        "an extended address (a further axis or spindle), not read"
    } else {
        "not a variable this program defines (DEF), nor an address read here"
    }
}

/// The value of an expression (`R1+5`, `_X_HOME`), where no dimension may be given (`AC(5)` reads
/// as its value in brackets, as before; an `IC()` is refused).
fn value_of(text: &str, vars: &mut Vars) -> Result<f64, String> {
    match dimensioned(text, vars)? {
        (_, Dimension::Incremental) => Err("IC(): an incremental value is written on an axis or a circle centre (X=IC(5), I=IC(2))".into()),
        (_, Dimension::Modulo(t)) => Err(format!("{}(): not read here (it is read on a rotary axis' word, as in C={}(90))", t.name(), t.name())),
        (v, _) => Ok(v),
    }
}

/// The value of an expression and its dimension for this word: `AC(...)` absolute and `IC(...)`
/// incremental whatever G90/G91 say (Programming Manual Fundamentals, "Absolute dimensions (G90,
/// AC)": "With preset incremental dimensions (G91), the AC command can be used to set non-modal
/// absolute dimensions for individual axes"; "Incremental dimensions (G91, IC)").
fn dimensioned(text: &str, vars: &mut Vars) -> Result<(f64, Dimension), String> {
    let t = text.trim();
    let head = |h: &[u8]| t.len() > h.len() && t.as_bytes()[..h.len()].eq_ignore_ascii_case(h) && t.ends_with(')');
    let (inner, dimension) = if head(b"AC(") {
        (&t[3..t.len() - 1], Dimension::Absolute)
    } else if head(b"IC(") {
        (&t[3..t.len() - 1], Dimension::Incremental)
    } else if head(b"DC(") {
        (&t[3..t.len() - 1], Dimension::Modulo(Turn::Shortest))
    } else if head(b"ACP(") {
        (&t[4..t.len() - 1], Dimension::Modulo(Turn::Positive))
    } else if head(b"ACN(") {
        (&t[4..t.len() - 1], Dimension::Modulo(Turn::Negative))
    } else {
        (t, Dimension::Modal)
    };
    let v = vars.eval(inner).map_err(|e| format!("{} (at '{}')", e.message, excerpt(&inner[e.at.min(inner.len())..])))?;
    Ok((v, dimension))
}

/// The arguments of a call (`CYCLE81(2.5,0,,-10)`): each a value, a string, or empty; `vars` give the
/// expressions' values. Why not, with the byte offset in `text` where it fails.
pub(crate) fn call_arguments(text: &str, vars: &mut Vars) -> Result<Vec<Arg>, (usize, String)> {
    let b = text.as_bytes();
    let mut args = Vec::new();
    let (mut start, mut depth, mut in_str) = (0usize, 0i32, false);
    for k in 0..=b.len() {
        let c = b.get(k).copied();
        match c {
            Some(b'"') => in_str = !in_str,
            Some(b'(') if !in_str => depth += 1,
            Some(b')') if !in_str => depth -= 1,
            Some(b',') | None if !in_str && depth == 0 => {
                let piece = &text[start..k];
                let t = piece.trim();
                let at = start + (piece.len() - piece.trim_start().len());
                args.push(if t.is_empty() {
                    Arg::Empty
                } else if t.starts_with('"') {
                    match t[1..].strip_suffix('"') {
                        Some(s) if !s.contains('"') => Arg::Text(s.to_string()),
                        _ => return Err((at, format!("'{}': a string is one quoted text", excerpt(t)))),
                    }
                } else {
                    match parse_number(t).map_or_else(|| value_of(t, vars), Ok) {
                        Ok(v) => Arg::Value(v),
                        Err(why) => return Err((at, why)),
                    }
                });
                start = k + 1;
            }
            _ => {}
        }
        if args.len() > 64 {
            return Err((start, "more than 64 arguments".into()));
        }
    }
    if in_str {
        return Err((text.len(), "a string is not closed".into()));
    }
    Ok(args)
}

/// One argument of a call.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Arg {
    Empty,
    Value(f64),
    Text(String),
}

impl Arg {
    /// The argument's value; an empty one is 0 (the cycles' default for a parameter not written).
    pub(crate) fn value(&self) -> Result<f64, String> {
        match self {
            Arg::Empty => Ok(0.0),
            Arg::Value(v) => Ok(*v),
            Arg::Text(t) => Err(format!("\"{t}\": expected a number")),
        }
    }
}

/// `DEF REAL a, b=1`: define the variables (REAL, INT, BOOL; the text after `DEF`). Why not, with
/// the byte offset in `text` where it fails.
pub(crate) fn define(text: &str, vars: &mut Vars) -> Result<(), (usize, String)> {
    let t = text.trim_start();
    let lead = text.len() - t.len();
    let (ty_name, rest) = t.split_once(|c: char| c.is_whitespace()).unwrap_or((t, ""));
    let ty = match ty_name.to_ascii_uppercase().as_str() {
        "REAL" => Type::Real,
        "INT" => Type::Int,
        "BOOL" => Type::Bool,
        "LUD" | "PUD" | "GUD" | "NCK" | "CHAN" => return Err((lead, format!("DEF {ty_name}: a data range (global user data) is not read: define the program's own variables (DEF REAL name)"))),
        other => return Err((lead, format!("DEF {other}: only REAL, INT and BOOL variables are read"))),
    };
    let rest_at = text.len() - rest.len();
    let mut at = rest_at;
    for piece in rest.split(',') {
        let (name, init) = match piece.split_once('=') {
            Some((n, v)) => (n.trim(), Some(v)),
            None => (piece.trim(), None),
        };
        let name_at = at + (piece.len() - piece.trim_start().len());
        let ok_name = name.len() >= 2 && name.bytes().all(|c| c.is_ascii_alphanumeric() || c == b'_') && name.as_bytes()[0] != b'$' && !name.as_bytes()[0].is_ascii_digit();
        if !ok_name {
            return Err((name_at, format!("'{}': expected a variable name (letters, digits, '_'; arrays are not read)", excerpt(name))));
        }
        let value = match init {
            None => None,
            Some(v) => Some(parse_number(v.trim()).map_or_else(|| value_of(v, vars), Ok).map_err(|why| (name_at, why))?),
        };
        vars.define(&name.to_ascii_uppercase(), ty, value).map_err(|why| (name_at, why))?;
        at += piece.len() + 1;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A value's expression runs on past a blank only beside an operator (Programming Manual
    /// Job Planning, "Arithmetic operators": DIV, MOD and the logical ones are words): each value
    /// worked here from the rule, blanks before and after the word operators.
    #[test]
    fn word_operators_join_an_expression_across_blanks() {
        let mut vars = Vars::default();
        let src = "N10 R1=7 MOD 4 X=R1 DIV 2 Y=R1 AND 0 Z=10 MOD 4 A=R1 B=ANDY C=2 F=R1 XOR 1";
        let mut diags = Diags::default();
        let l = lex_line(src, &Columns::new(src), 1, &mut vars, &mut diags);
        // `B=ANDY`: a name beginning as AND does, not the operator (no such variable: an error at it).
        assert_eq!(diags.0.len(), 1, "{:?}", diags.0);
        assert!(diags.0[0].message.starts_with("B=ANDY"), "{:?}", diags.0);
        assert_eq!(vars.get("R1"), Ok(3.0));
        let got: Vec<(char, f64)> = l.words.iter().map(|w| (w.letter, w.value)).collect();
        // 3 DIV 2 = 1; 3 AND 0 = 0; 10 MOD 4 = 2; A=R1 ends at its blank (A begins no operator here).
        assert_eq!(got, vec![('X', 1.0), ('Y', 0.0), ('Z', 2.0), ('A', 3.0), ('C', 2.0), ('F', 0.0)]);
    }

    /// A value that starts with a number is that number only where the expression ends after it
    /// (the one-pass read of a plain number): an operator after a blank carries it on, a letter
    /// after an address' digits starts the next word, and a second point is no number.
    #[test]
    fn a_number_ends_a_value_only_where_its_expression_ends() {
        let src = "G1X10.5Y-2 Z=10 + 5 A=2 *3 B=-.5 C=4.5;X=9";
        let (mut vars, mut diags) = (Vars::default(), Diags::default());
        let l = lex_line(src, &Columns::new(src), 1, &mut vars, &mut diags);
        assert!(diags.0.is_empty(), "{:?}", diags.0);
        let got: Vec<(char, f64, &str)> = l.words.iter().map(|w| (w.letter, w.value, w.raw.as_ref())).collect();
        assert_eq!(got, vec![('G', 1.0, "1"), ('X', 10.5, "10.5"), ('Y', -2.0, "-2"), ('Z', 15.0, "10 + 5"), ('A', 6.0, "2 *3"), ('B', -0.5, "-.5"), ('C', 4.5, "4.5")]);
        for (src, col) in [("X=1.2.3", 3), ("X1.2.3", 1), ("X=5)", 4)] {
            let mut diags = Diags::default();
            let l = lex_line(src, &Columns::new(src), 1, &mut Vars::default(), &mut diags);
            assert!(diags.0.first().is_some_and(|d| d.column == col), "{src}: {:?}", diags.0);
            // (`X=5)`: the value 5 ends at the bracket, the bracket is the error and refuses the line.)
            assert!(src.ends_with(')') || l.words.iter().all(|w| w.letter != 'X'), "{src}: {:?}", l.words.iter().map(|w| w.value).collect::<Vec<_>>());
        }
    }

    #[test]
    fn blocks_read_their_variables_in_order() {
        let mut vars = Vars::default();
        define(" REAL _X_HOME, _Y_HOME=2*3, _N", &mut vars).unwrap();
        define("INT _K=2.5", &mut vars).unwrap();
        assert_eq!(vars.get("_Y_HOME"), Ok(6.0));
        assert_eq!(vars.get("_K"), Ok(3.0), "REAL to INT rounds");
        // Defined without a value: 0, the type's implicit initialization value.
        assert_eq!(vars.get("_X_HOME"), Ok(0.0));
        assert!(define("REAL _X_HOME", &mut vars).unwrap_err().1.contains("twice"));
        assert!(define("STRING[8] S", &mut vars).is_err());
        let src = "N120 _X_HOME=-365. R1=_X_HOME+5 G0 X=R1 Y=_Y_HOME * 2 Z=AC(1) D0 ; home";
        let mut diags = Diags::default();
        let l = lex_line(src, &Columns::new(src), 1, &mut vars, &mut diags);
        assert!(diags.0.is_empty(), "{:?}", diags.0);
        assert_eq!(l.number, Some(120));
        assert_eq!(vars.get("R1"), Ok(-360.0));
        let xyz: Vec<(char, f64)> = l.words.iter().filter(|w| "XYZ".contains(w.letter)).map(|w| (w.letter, w.value)).collect();
        assert_eq!(xyz, vec![('X', -360.0), ('Y', 12.0), ('Z', 1.0)]);
        assert_eq!(l.edge.map(|e| e.0), Some(0.0));
        // AC() and IC() dimension their word only; on a feed, IC() is refused.
        let dims: Vec<(char, Dimension)> = l.words.iter().filter(|w| "XYZ".contains(w.letter)).map(|w| (w.letter, w.dimension)).collect();
        assert_eq!(dims, vec![('X', Dimension::Modal), ('Y', Dimension::Modal), ('Z', Dimension::Absolute)]);
        let src = "G1 X=IC(R1+361) I=AC(2) F=IC(5)";
        let l = lex_line(src, &Columns::new(src), 1, &mut vars, &mut diags);
        let dims: Vec<(char, f64, Dimension)> = l.words.iter().filter(|w| w.letter != 'G').map(|w| (w.letter, w.value, w.dimension)).collect();
        assert_eq!(dims, vec![('X', 1.0, Dimension::Incremental), ('I', 2.0, Dimension::Absolute)]);
        assert_eq!(diags.0.iter().map(|d| d.column).collect::<Vec<_>>(), vec![27], "{:?}", diags.0);
        diags.0.clear();
        let bad = "G1 X=R7 Y=_NOPE Z=IC(2";
        let l = lex_line(bad, &Columns::new(bad), 2, &mut vars, &mut diags);
        assert!(l.words.iter().all(|w| w.letter == 'G'));
        let cols: Vec<usize> = diags.0.iter().map(|d| d.column).collect();
        assert_eq!(cols, vec![6, 11, 19], "{:?}", diags.0);
        assert_eq!(call_arguments(" 1, \" R_DATA\", ,2*R1, ", &mut vars), Ok(vec![Arg::Value(1.0), Arg::Text(" R_DATA".into()), Arg::Empty, Arg::Value(-720.0), Arg::Empty]));
    }
}
