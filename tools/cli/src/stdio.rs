//! What the programs do at their edges besides standard output
//! ([`hal_core::stdio`]): arguments that may not be UTF-8, and numbers of
//! seconds that must be checked.

use crate::ToolsError;

/// A standard output that may close under the program.
pub use hal_core::stdio::{checked, closed_stdout, stdout, Stdout};

/// Argument decoding is shared with every program that hosts a
/// user-space component (the VFD programs among them).
pub use hal_core::userspace::{args, args_from, args_or_exit};

/// Parses a number of seconds for a timeout or an interval: finite,
/// greater than zero, at most `max_s`; `what` names it in the error.
pub fn parse_seconds(
    what: &str,
    text: &str,
    max_s: f64,
) -> Result<std::time::Duration, ToolsError> {
    let bad = |reason: String| ToolsError::Seconds {
        what: what.to_string(),
        reason,
    };
    let s: f64 = text
        .trim()
        .parse()
        .map_err(|_| bad(format!("'{text}' is not a number of seconds")))?;
    if !(s.is_finite() && s > 0.0 && s <= max_s) {
        return Err(bad(format!(
            "{text} s is out of range (more than 0, at most {max_s} s)"
        )));
    }
    Ok(std::time::Duration::from_secs_f64(s))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::OsString;
    use std::os::unix::ffi::OsStringExt;

    #[test]
    fn arguments_must_be_utf8() {
        let ok = args_from([OsString::from("a"), OsString::from("é")]).unwrap();
        assert_eq!(ok, ["a", "é"]);
        let e = args_from([OsString::from("a"), OsString::from_vec(vec![0xff, b'x'])]).unwrap_err();
        assert!(e.contains("argument 2") && e.contains("UTF-8"), "{e}");
    }

    #[test]
    fn seconds_are_checked() {
        assert_eq!(
            parse_seconds("-t", "1.5", 60.0).unwrap(),
            std::time::Duration::from_millis(1500)
        );
        for bad in ["1e308", "-1", "0", "NaN", "inf", "", "x", "61"] {
            let e = parse_seconds("-t", bad, 60.0).unwrap_err().to_string();
            assert!(e.starts_with("-t: "), "{e}");
        }
    }
}
