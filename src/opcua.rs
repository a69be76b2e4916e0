//! A CNC read over OPC UA, without the transport: where the axes are in the OPC 40502 CNC companion
//! model (`Objects/CncInterface/CncAxisList/<axis>/PosIndirect|PosDirect/ActPos`, with
//! `EngineeringUnits` and `IsRotational`; OPC 40502 §6.8.2 CncAxisType, §7.3.2
//! CncPositionVariableType), and the units an `EUInformation` names (UNECE Recommendation 20 codes,
//! as OPC UA Part 8 §5.6.3 puts them in `UnitId`).

/// The CNC companion model's namespace.
pub const CNC_NAMESPACE: &str = "http://opcfoundation.org/UA/CNC";
/// The namespace of UNECE unit codes in `EUInformation`.
pub const UNECE_NAMESPACE: &str = "http://www.opcfoundation.org/UA/units/un/cefact";
/// Browse names on the way to an axis' position (in the CNC namespace).
pub const CNC_INTERFACE: &str = "CncInterface";
pub const CNC_AXIS_LIST: &str = "CncAxisList";
pub const ACT_POS: &str = "ActPos";

/// Which of an axis' positions to read: its indirect measuring system (the motor encoder every
/// axis has) or its direct one (a scale, where fitted).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Measuring {
    #[default]
    Indirect,
    Direct,
}

impl Measuring {
    /// The CncPositionVariableType component of the axis.
    pub fn browse_name(self) -> &'static str {
        match self {
            Measuring::Indirect => "PosIndirect",
            Measuring::Direct => "PosDirect",
        }
    }
}

/// How the bridge secures its channel to the server: none, or Basic256Sha256 (the policy a
/// Sinumerik's server offers by default) signed, or signed and encrypted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Security {
    #[default]
    None,
    Sign,
    SignAndEncrypt,
}

/// The UNECE code an `EUInformation.UnitId` holds: its letters as a base-256 number (Part 8 §5.6.3:
/// "MMT" is 5066068).
pub fn unece_code(unit_id: i32) -> String {
    let bytes = unit_id.to_be_bytes();
    bytes.iter().skip_while(|b| **b == 0).map(|b| char::from(*b)).collect()
}

/// The factor to SI (m, rad) of a length or angle unit by its UNECE code.
pub fn unece_factor(code: &str) -> Option<f64> {
    Some(match code {
        "MMT" => 1e-3,
        "CMT" => 1e-2,
        "MTR" => 1.0,
        "INH" => 25.4e-3,
        "4H" => 1e-6, // micrometre
        "DD" => std::f64::consts::PI / 180.0,
        "C81" => 1.0,
        _ => return None,
    })
}

/// The factor to SI of an axis' position from its `EngineeringUnits` (namespace URI and unit id),
/// checked against its kind: a linear axis needs a length, a rotary one an angle. Without units
/// (the property missing), mm and degrees, as CNC servers show positions, are assumed only where
/// `assume` says so; otherwise it is an error naming the axis.
pub fn position_factor(axis: &str, rotary: bool, units: Option<(&str, i32)>, assume: bool) -> Result<f64, String> {
    let Some((uri, id)) = units else {
        return if assume {
            Ok(if rotary { std::f64::consts::PI / 180.0 } else { 1e-3 })
        } else {
            Err(format!("axis {axis}: its position has no EngineeringUnits (say --assume-mm-deg to read it in mm or degrees)"))
        };
    };
    let code = unece_code(id);
    if uri.trim_end_matches('/') != UNECE_NAMESPACE.trim_end_matches('/') {
        return Err(format!("axis {axis}: units {code} ({id}) of namespace '{uri}', not UNECE's"));
    }
    let f = unece_factor(&code).ok_or_else(|| format!("axis {axis}: units {code} ({id}) are not a length or an angle"))?;
    let angle = matches!(code.as_str(), "DD" | "C81");
    if angle != rotary {
        return Err(format!("axis {axis}: a {} axis in {code}", if rotary { "rotary" } else { "linear" }));
    }
    Ok(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unece_units() {
        // Part 8's own example: millimetre is "MMT", UnitId 5066068; degree "DD" 17476.
        assert_eq!(unece_code(5_066_068), "MMT");
        assert_eq!(unece_code(17_476), "DD");
        assert_eq!(position_factor("X", false, Some((UNECE_NAMESPACE, 5_066_068)), false), Ok(1e-3));
        assert_eq!(position_factor("C", true, Some((UNECE_NAMESPACE, 17_476)), false), Ok(std::f64::consts::PI / 180.0));
        assert!(position_factor("C", true, Some((UNECE_NAMESPACE, 5_066_068)), false).unwrap_err().contains("rotary axis in MMT"));
        assert!(position_factor("X", false, None, false).unwrap_err().contains("--assume-mm-deg"));
        assert_eq!(position_factor("X", false, None, true), Ok(1e-3));
        // The inch: "INH" = 0x494E48.
        assert_eq!(position_factor("X", false, Some((UNECE_NAMESPACE, 0x49_4E_48)), false), Ok(25.4e-3));
    }
}
