//! Validation of HAL object names.
//!
//! LinuxCNC names are single tokens: halcmd splits lines at whitespace, treats
//! `#` as a comment, `=` as assignment and `<=`/`=>`/`<=>` as arrows, and
//! quotes with `"`. A name therefore must not contain whitespace, control
//! characters, or any of `#`, `=`, `"`, `'`, `\`, `<`, `>`, `$`, `;`, and must not
//! be empty. Everything else printable in ASCII is allowed (LinuxCNC configs
//! use upper case, `_`, `:`, `[`, `]`, `+`, `/` in names). The length limit is
//! 255 bytes, a deliberate extension over LinuxCNC's limit.

use crate::error::HalError;

/// Longest name accepted, in bytes.
pub const MAX_NAME_LEN: usize = 255;

const FORBIDDEN: &[u8] = b"#=\"'\\<>$;";

/// Checks `name` against the HAL naming rules; `kind` names the object in the
/// error ("pin", "signal", ...).
pub fn validate(kind: &'static str, name: &str) -> Result<(), HalError> {
    let bad = |reason: &'static str| HalError::BadName {
        kind,
        name: name.to_string(),
        reason,
    };
    if name.is_empty() {
        return Err(bad("name is empty"));
    }
    if name.len() > MAX_NAME_LEN {
        return Err(HalError::NameTooLong {
            kind,
            name: name.to_string(),
            len: name.len(),
            max: MAX_NAME_LEN,
        });
    }
    for b in name.bytes() {
        if !(0x21..=0x7e).contains(&b) {
            return Err(bad(
                "names may only contain printable ASCII characters without spaces",
            ));
        }
        if FORBIDDEN.contains(&b) {
            return Err(bad("names must not contain any of # = \" ' \\ < > $ ;"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_linuxcnc_style_names() {
        for n in [
            "and2.0.in0",
            "hm2_5i25.0.encoder.00.count",
            "motion.spindle-speed-out",
            "__servo",
            "joint.0.motor-pos-cmd",
            "ddt.in-vel",
            "parport.0.pin-01-out",
            "X:1[2]+a/b",
        ] {
            validate("pin", n).unwrap();
        }
        validate("pin", &"a".repeat(255)).unwrap();
    }

    #[test]
    fn rejects_bad_names() {
        for n in ["", "a b", "a#b", "x=1", "tab\tname", "q\"", "arrow=>", "é"] {
            assert!(
                matches!(validate("pin", n), Err(HalError::BadName { .. })),
                "{n:?} accepted"
            );
        }
        assert!(matches!(
            validate("signal", &"a".repeat(256)),
            Err(HalError::NameTooLong {
                len: 256,
                max: 255,
                ..
            })
        ));
    }
}
