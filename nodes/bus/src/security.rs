//! DDS Security (SROS2) from the ROS 2 environment, as rcl reads it: `ROS_SECURITY_ENABLE=true`
//! turns it on; the enclave (`--ros-args --enclave /NAME`, default `/`, or `ROS_SECURITY_ENCLAVE_OVERRIDE`)
//! is the folder `$ROS_SECURITY_KEYSTORE/enclaves/NAME` holding `identity_ca.cert.pem`, `cert.pem`,
//! `key.pem`, `permissions_ca.cert.pem`, `governance.p7s` and `permissions.p7s` (the names rmw_dds_common
//! looks for); `ROS_SECURITY_STRATEGY=Enforce` makes a missing enclave an error, otherwise
//! (`Permissive`, rcl's default) the node runs unsecured with a warning.
//!
//! RustDDS's builtin plugins do the rest: PKI-DH authentication (ECDSA P-256), signed governance and
//! permissions, AES-GCM. Where they fall short of the specification the node refuses rather than run
//! weaker than asked, or lose every sample: a `crl.pem` in the enclave (RustDDS checks no revocation
//! list), an encrypted `key.pem` (it reads no key password) and a governance asking for payload
//! protection (`data_protection_kind` SIGN or ENCRYPT: RustDDS 0.15.1's readers reject every such
//! sample) are errors. Submessage protection (`metadata_protection_kind` ENCRYPT) encrypts each DATA
//! submessage whole, payload included.

use std::path::{Path, PathBuf};

/// The files an enclave must hold (rmw_dds_common's names).
pub const ENCLAVE_FILES: [&str; 6] = ["identity_ca.cert.pem", "cert.pem", "key.pem", "permissions_ca.cert.pem", "governance.p7s", "permissions.p7s"];

/// What the environment asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Security {
    /// Security off (ROS_SECURITY_ENABLE not `true`).
    Off,
    /// Asked for, but the enclave is missing or incomplete under the permissive strategy: run
    /// unsecured, saying why.
    Permissive(String),
    /// The enclave folder to authenticate with.
    Enclave(PathBuf),
}

/// Why security could not be set up.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SecurityError {
    #[error("{0}")]
    Enforced(String),
    #[error("enclave name '{0}' must be absolute (start with '/'), with no '..' or empty parts")]
    BadEnclave(String),
    #[error("{0}: a certificate revocation list is present, but RustDDS 0.15 checks none; refusing to run as if no certificate were revoked")]
    Crl(PathBuf),
    #[error("{0}: the private key is password-protected, which RustDDS 0.15 cannot read; use an unencrypted key.pem (as `ros2 security create_enclave` makes)")]
    EncryptedKey(PathBuf),
    #[error(
        "{0}: data_protection_kind {1} (payload protection), which RustDDS 0.15.1 cannot exchange: every sample would be dropped by its reader. \
         Use data_protection_kind NONE with metadata_protection_kind ENCRYPT, which encrypts each DATA submessage whole, payload included \
         (launch-free-scripts/keystore writes such a governance)"
    )]
    PayloadProtection(PathBuf, String),
}

/// The payload protection a governance document asks for on some topic (`SIGN` or `ENCRYPT`), if
/// any: RustDDS 0.15.1 delivers no sample under it. The S/MIME file carries the XML in clear text.
fn payload_protection(governance: &str) -> Option<String> {
    governance
        .split("<data_protection_kind>")
        .skip(1)
        .filter_map(|rest| rest.split('<').next())
        .map(str::trim)
        .find(|k| !k.eq_ignore_ascii_case("NONE"))
        .map(str::to_string)
}

/// Read the security settings: `get` reads the environment, `enclave` is `--ros-args --enclave`.
/// Files are checked on disk.
pub fn from_env(get: impl Fn(&str) -> Option<String>, enclave: Option<&str>) -> Result<Security, SecurityError> {
    // rcl: exactly "true" enables it.
    if get("ROS_SECURITY_ENABLE").as_deref() != Some("true") {
        return Ok(Security::Off);
    }
    let enforce = get("ROS_SECURITY_STRATEGY").as_deref() == Some("Enforce");
    let name = get("ROS_SECURITY_ENCLAVE_OVERRIDE").filter(|s| !s.is_empty()).or_else(|| enclave.map(str::to_string)).unwrap_or_else(|| "/".into());
    if !name.starts_with('/')
        || name.split('/').skip(1).any(|p| p == ".." || p == ".")
        || (name.len() > 1 && name.split('/').skip(1).any(str::is_empty))
    {
        return Err(SecurityError::BadEnclave(name));
    }
    let missing = |why: String| if enforce { Err(SecurityError::Enforced(why)) } else { Ok(Security::Permissive(why)) };
    let Some(keystore) = get("ROS_SECURITY_KEYSTORE").filter(|s| !s.is_empty()) else {
        return missing("ROS_SECURITY_ENABLE=true but ROS_SECURITY_KEYSTORE is not set".into());
    };
    let dir = Path::new(&keystore).join("enclaves").join(name.trim_start_matches('/'));
    if !dir.is_dir() {
        return missing(format!("no enclave folder {} for enclave '{name}' in keystore {keystore}", dir.display()));
    }
    let absent: Vec<&str> = ENCLAVE_FILES.iter().copied().filter(|f| !dir.join(f).is_file()).collect();
    if !absent.is_empty() {
        return missing(format!("enclave {} lacks {}", dir.display(), absent.join(", ")));
    }
    if dir.join("crl.pem").exists() {
        return Err(SecurityError::Crl(dir.join("crl.pem")));
    }
    let key = dir.join("key.pem");
    let text = std::fs::read_to_string(&key).map_err(|e| SecurityError::Enforced(format!("{}: {e}", key.display())))?;
    if text.contains("ENCRYPTED") {
        return Err(SecurityError::EncryptedKey(key));
    }
    let gov = dir.join("governance.p7s");
    let text = std::fs::read_to_string(&gov).map_err(|e| SecurityError::Enforced(format!("{}: {e}", gov.display())))?;
    if let Some(kind) = payload_protection(&text) {
        return Err(SecurityError::PayloadProtection(gov, kind));
    }
    Ok(Security::Enclave(dir))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn env(pairs: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
        let m: HashMap<String, String> = pairs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect();
        move |k| m.get(k).cloned()
    }

    fn enclave(root: &Path, name: &str) -> PathBuf {
        let d = root.join("enclaves").join(name.trim_start_matches('/'));
        std::fs::create_dir_all(&d).unwrap();
        for f in ENCLAVE_FILES {
            std::fs::write(d.join(f), if f == "key.pem" { "-----BEGIN PRIVATE KEY-----\n" } else { "x" }).unwrap();
        }
        d
    }

    #[test]
    fn reads_the_environment_as_rcl_does() {
        let ks = tempfile::tempdir().unwrap();
        let root = ks.path().to_str().unwrap();
        let node = enclave(ks.path(), "/fiveaxis/monitor");
        assert_eq!(from_env(env(&[]), Some("/fiveaxis/monitor")), Ok(Security::Off));
        assert_eq!(from_env(env(&[("ROS_SECURITY_ENABLE", "1")]), None), Ok(Security::Off));
        let on = [("ROS_SECURITY_ENABLE", "true"), ("ROS_SECURITY_KEYSTORE", root)];
        assert_eq!(from_env(env(&on), Some("/fiveaxis/monitor")), Ok(Security::Enclave(node.clone())));
        // The override wins over --enclave.
        let over = [on[0], on[1], ("ROS_SECURITY_ENCLAVE_OVERRIDE", "/fiveaxis/monitor")];
        assert_eq!(from_env(env(&over), Some("/other")), Ok(Security::Enclave(node.clone())));
        // Missing enclave: permissive runs unsecured, Enforce refuses.
        assert!(matches!(from_env(env(&on), Some("/absent")), Ok(Security::Permissive(w)) if w.contains("absent")));
        let strict = [on[0], on[1], ("ROS_SECURITY_STRATEGY", "Enforce")];
        assert!(matches!(from_env(env(&strict), Some("/absent")), Err(SecurityError::Enforced(w)) if w.contains("absent")));
        assert!(matches!(from_env(env(&[strict[0], strict[2]]), None), Err(SecurityError::Enforced(w)) if w.contains("ROS_SECURITY_KEYSTORE")));
        // A file missing is named.
        std::fs::remove_file(node.join("permissions.p7s")).unwrap();
        assert!(matches!(from_env(env(&strict), Some("/fiveaxis/monitor")), Err(SecurityError::Enforced(w)) if w.contains("permissions.p7s")));
        // What RustDDS cannot honour is refused, whatever the strategy.
        let n2 = enclave(ks.path(), "/n2");
        std::fs::write(n2.join("crl.pem"), "x").unwrap();
        assert!(matches!(from_env(env(&on), Some("/n2")), Err(SecurityError::Crl(_))));
        let n3 = enclave(ks.path(), "/n3");
        std::fs::write(n3.join("key.pem"), "-----BEGIN ENCRYPTED PRIVATE KEY-----\n").unwrap();
        assert!(matches!(from_env(env(&on), Some("/n3")), Err(SecurityError::EncryptedKey(_))));
        // A governance asking for payload protection (sros2's default) is refused, naming the kind.
        let n4 = enclave(ks.path(), "/n4");
        std::fs::write(
            n4.join("governance.p7s"),
            "<metadata_protection_kind>ENCRYPT</metadata_protection_kind>\n<data_protection_kind>ENCRYPT</data_protection_kind>",
        )
        .unwrap();
        assert!(matches!(from_env(env(&on), Some("/n4")), Err(SecurityError::PayloadProtection(_, k)) if k == "ENCRYPT"));
        std::fs::write(
            n4.join("governance.p7s"),
            "<data_protection_kind>NONE</data_protection_kind><data_protection_kind> SIGN </data_protection_kind>",
        )
        .unwrap();
        assert!(matches!(from_env(env(&on), Some("/n4")), Err(SecurityError::PayloadProtection(_, k)) if k == "SIGN"));
        std::fs::write(
            n4.join("governance.p7s"),
            "<metadata_protection_kind>ENCRYPT</metadata_protection_kind><data_protection_kind>NONE</data_protection_kind>",
        )
        .unwrap();
        assert!(matches!(from_env(env(&on), Some("/n4")), Ok(Security::Enclave(_))));
        for bad in ["rel", "/a/../b", "/a//b"] {
            assert!(matches!(from_env(env(&on), Some(bad)), Err(SecurityError::BadEnclave(_))), "{bad}");
        }
    }
}
