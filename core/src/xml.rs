//! XML text escaping, one place for the XML we write by hand (X3P's main.xml, URDF; JUnit reports
//! are written with quick-junit).

/// `s` escaped for XML element text and double-quoted attribute values.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}
