//! The 840D's words as the reader takes them: the instructions it knows (read or refused, any other
//! name alone in a block calls a program of that name), the modal motions it does not read, and its
//! G codes as the shared interpreter reads them.

use super::trc;

/// Whether `name` (capitals) is an instruction the reader knows, read or refused ([`super::SinumerikReader::block`]'s
/// keywords, the cycles): any other name alone in a block calls the program of that name.
pub(super) fn is_instruction(name: &str) -> bool {
    READ_KEYWORDS.contains(&name) || trc::KEYWORDS.contains(&name) || name.starts_with("CYCLE") || unsupported_keyword(name).is_some()
}

/// The keywords [`super::SinumerikReader::block`] reads.
pub(super) const READ_KEYWORDS: [&str; 33] = [
    "CIP", "CT", "STOPRE", "TRAORI", "TRAFOOF", "ORIWKS", "ORIVECT", "ORIPLANE", "ORIMKS", "ORIAXES", "ORIROTA", "ORIEULER", "ORIRPY", "SOFT", "BRISK", "FFWON", "FFWOF", "FNORM", "COMPOF", "COMPON", "COMPCURV", "COMPCAD", "MSG", "SETMS", "EXTERN", "TRANS", "ATRANS", "ROT", "AROT", "SUPA", "MCALL", "CUT2D", "CDOF",
];

/// The modal motions of G group 1 whose line is refused (splines and polynomials, not read; `CIP`
/// and `CT`, read, on a line refused for another reason): after one, a move must give its own G0-G3
/// ([`crate::program::interp::Interpreter::forget_motion`]).
pub(super) const UNREAD_MOTION: [&str; 6] = ["BSPLINE", "ASPLINE", "CSPLINE", "POLY", "CIP", "CT"];

/// What an [`UNREAD_MOTION`] keyword is, for the messages of the moves after it.
pub(super) fn unread_what(k: &str) -> &'static str {
    match k {
        "POLY" => "polynomial interpolation",
        "CIP" => "a circle through an intermediate point",
        "CT" => "a circle with a tangential transition",
        _ => "spline interpolation",
    }
}

/// A statement refused whose effect lasts on the control ([`super::Interpreter::hold_keyword`]):
/// the statements it is one of, its hold, the statements read that end it, and what its held moves
/// leave unknown then (X Y Z; the rotary axes).
pub(super) struct Lasting {
    pub names: &'static [&'static str],
    pub rule: &'static crate::program::interp::Rule,
    pub ends: &'static [&'static str],
    pub linear: bool,
    pub rotary: bool,
}

/// The 840D's lasting statements not read (Fundamentals and Job Planning: frames until TRANS/ROT,
/// transformations until TRAFOOF, the orientation interpolation's G group 51 until another of it,
/// the rotation vector's interpolation (G group 54) until ORIROTA, the feed profile until FNORM; 3D compensation, which acts only under G41/G42, is the reader's
/// [`COMP3D`]). An orientation interpolation reaches
/// the programmed orientation at each block's end (its path between differs), a feed profile only
/// times the path: neither leaves a position unknown.
pub(super) const LASTING: [Lasting; 6] = [
    Lasting { names: &["SCALE", "ASCALE", "MIRROR", "AMIRROR", "ROTS", "AROTS", "CROTS"], rule: &crate::program::interp::SIN_FRAME, ends: &["TRANS", "ROT"], linear: true, rotary: false },
    Lasting { names: &["TRANSMIT", "TRACYL", "TRAANG", "TRAORI"], rule: &crate::program::interp::SIN_TRANSFORM, ends: &["TRAFOOF"], linear: true, rotary: true },
    Lasting { names: &["ORICONCW", "ORICONCCW", "ORICONTO", "ORICONIO", "ORICURVE", "ORIPATH", "ORIPATHS"], rule: &crate::program::interp::SIN_ORIENT, ends: &["ORIVECT", "ORIPLANE", "ORIAXES"], linear: false, rotary: false },
    Lasting { names: &["ORIROTR", "ORIROTT", "ORIROTC"], rule: &crate::program::interp::SIN_ROTATE, ends: &["ORIROTA"], linear: false, rotary: false },
    // A swivel refused: ended by a CYCLE800 that is read ([`super::SinumerikReader`]'s), not by a name.
    Lasting { names: &["CYCLE800"], rule: &crate::program::interp::SIN_SWIVEL, ends: &[], linear: true, rotary: true },
    Lasting { names: &["FLIN", "FCUB", "FPO"], rule: &crate::program::interp::SIN_FEED, ends: &["FNORM"], linear: false, rotary: false },
];

/// 3D tool radius compensation's statements (`CUT3DC` ..., `CUT2DF`), not read, in force until `CUT2D`:
/// they act only with tool radius compensation on (G41/G42), so only compensated blocks are refused.
pub(super) const COMP3D: [&str; 7] = ["CUT3DC", "CUT3DF", "CUT3DFS", "CUT3DFF", "CUT3DCC", "CUT3DCCD", "CUT2DF"];

/// The lasting statement `name` is one of, if any.
pub(super) fn lasting(name: &str) -> Option<&'static Lasting> {
    LASTING.iter().find(|l| l.names.contains(&name))
}

/// Why a keyword the reader knows is refused (`None`: a name it does not know).
pub(super) fn unsupported_keyword(k: &str) -> Option<&'static str> {
    Some(match k {
        "SCALE" | "ASCALE" | "MIRROR" | "AMIRROR" | "ROTS" | "AROTS" | "CROTS" => "frame scaling, mirroring or solid-angle rotation is not modelled (it changes the motion)",
        "TRAFOOF_" | "TRANSMIT" | "TRACYL" | "TRAANG" => "this transformation is not modelled",
        "ORICONCW" | "ORICONCCW" | "ORICONTO" | "ORICONIO" | "ORICURVE" | "ORIPATH" | "ORIPATHS" => {
            "this orientation interpolation (cone, curve or path-relative) is not modelled"
        }
        "ORIROTR" | "ORIROTT" | "ORIROTC" => "this interpolation of the tool's rotation vector (relative, tangential or to the path) is not modelled (ORIROTA, the absolute one, is read)",
        // Job Planning, "Spline interpolation" and "Polynomial interpolation": the path between the
        // points is a curve whose knots and end conditions are the control's (BSPLINE without PL).
        "BSPLINE" | "ASPLINE" | "CSPLINE" | "BAUTO" | "BNAT" | "BTAN" | "EAUTO" | "ENAT" | "ETAN" | "POLY" | "POLYPATH" => {
            "spline or polynomial interpolation is not read (the path between the points is a curve the control makes)"
        }
        "OFFN" => "OFFN is written OFFN=<value>",
        "CUT2DF" | "CUT3DC" | "CUT3DF" | "CUT3DFS" | "CUT3DFF" | "CUT3DCC" | "CUT3DCCD" => "3D tool radius compensation (or 2D in a frame's plane) is not modelled",
        "CDON" | "CDOF2" => "collision detection (bottleneck detection over several blocks) with tool radius compensation is not read; CDOF is",
        "FGROUP" | "FGREF" => "feed reference axes are not modelled (they change how F is read)",
        "FLIN" | "FCUB" | "FPO" => "a feed profile over the block is not modelled (it changes the speed along it)",
        "GOTOF" | "GOTOB" | "GOTO" | "GOTOC" | "REPEAT" | "REPEATB" | "UNTIL" | "IF" | "ELSE" | "ENDIF" | "WHILE" | "ENDWHILE" | "FOR" | "ENDFOR" | "LOOP" | "ENDLOOP" => {
            "program control after other words of a block is not read (a jump or a control structure stands at the block's start)"
        }
        "CALL" | "PCALL" | "EXTCALL" => "this call of another program is not read (a program called by its name alone in its block is, and CALL \"NAME\" alone)",
        "PROC" | "RET" => "a PROC or RET stands at its block's start",
        "DEF" => "a definition stands at the start of its line, in the definitions part",
        _ => return None,
    })
}

/// A Sinumerik G code this reader refuses that moves the tool (its code as written): what it is, and
/// whether it moves every axis (a reference or fixed point approach, G74/G75; smooth approach and
/// retraction, G140-G348, the plane's axes and the tool's) rather than the axes it names, and
/// whether it is a motion of G group 1 (threading G33-G35, tapping G331/G332), which later blocks
/// without a G0-G3 of their own keep (Fundamentals, "Thread cutting"; G63 is one block's).
pub(super) fn refused_move(code: &str) -> Option<(&'static str, bool, bool)> {
    Some(match code.trim_start_matches('0') {
        "74" | "75" => ("a reference or fixed point approach", true, false),
        "33" | "34" | "35" | "331" | "332" => ("threading or tapping", false, true),
        "63" => ("tapping", false, false),
        "140" | "141" | "142" | "143" | "147" | "148" | "247" | "248" | "347" | "348" | "340" | "341" => ("smooth approach or retraction", true, false),
        _ => return None,
    })
}

/// A Sinumerik G code as the shared interpreter reads it (`Ok(None)`: no effect on the path), or why
/// it is refused.
pub(super) fn sinumerik_g(code: &str) -> Result<Option<&'static str>, &'static str> {
    let n = code.trim_start_matches('0');
    Ok(Some(match n {
        "" => "0",
        "1" => "1",
        "2" => "2",
        "3" => "3",
        "17" => "17",
        "18" => "18",
        "19" => "19",
        "40" => "40",
        "90" => "90",
        "91" => "91",
        "93" => "93",
        "94" => "94",
        "54" => "54",
        "55" => "55",
        "56" => "56",
        "57" => "57",
        // Settable frames off, or the 6th to 99th settable frame: the operator's, as G54's.
        "500" => "54",
        s if s.len() == 3 && s.starts_with('5') && ("505".."600").contains(&s) => "54",
        // G70/G71 the geometry's unit, G700/G710 the feed's too (the interpreter tells them apart).
        "70" => "70",
        "71" => "71",
        "700" => "20",
        "710" => "21",
        // Continuous-path modes (G group 10): the reader's; smoothing within a tolerance is what the
        // planner does.
        "64" | "641" | "642" | "643" | "644" | "645" => "64",
        // Exact stop (G group 10) and its window (G group 12, which only G60 reads).
        "60" => "60",
        "601" | "602" | "603" => return Ok(None),
        // Corner deceleration (G group 57), which acts only under tool radius compensation ([`trc`]).
        "62" | "621" => return Ok(Some(if n == "62" { "62" } else { "621" })),
        "9" => "9",
        "4" => "4",
        // Tool radius compensation and its corners ([`trc`]).
        "41" => "41",
        "42" => "42",
        "450" => "450",
        "451" => "451",
        // Frames suppressed for the block: machine coordinates (the reader's, as SUPA).
        "53" | "153" => "53",
        // Revolutional feed (the interpreter's G95: F times the master spindle's speed).
        "95" => "95",
        "96" | "97" => return Err("constant cutting speed is not supported"),
        // The pole of polar coordinates ([`super::polar`]), taken out of the block by the reader.
        "110" => "110",
        "111" => "111",
        "112" => "112",
        "25" | "26" | "74" | "75" => return Err("working-area limits and reference-point moves are not supported"),
        "140" | "141" | "142" | "143" | "147" | "148" | "247" | "248" | "347" | "348" | "340" | "341" => return Err("smooth approach and retraction (SAR) is not read"),
        "33" | "331" | "332" | "63" => return Err("threading and tapping are not supported"),
        _ => return Err("unknown G code: not read (it may change the motion)"),
    }))
}
