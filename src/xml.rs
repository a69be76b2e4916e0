//! XML text escaping, one place for the files we write (JUnit reports, X3P's main.xml, URDF).

/// `s` escaped for XML element text and double-quoted attribute values.
pub(crate) fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}
