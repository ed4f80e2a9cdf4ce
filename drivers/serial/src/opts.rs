//! Command lines as LinuxCNC's user-space components read them with
//! `getopt_long`: short options (`-r 9600`, `-r9600`, bundled flags
//! `-gy`), long options (`--rate 9600`, `--rate=9600`, or any unique
//! prefix, `--ra 9600`), and choice values matched by a unique prefix as
//! LinuxCNC's `match_string` does (`--rate 5` is 57600 when no other rate
//! starts with 5).

use crate::error::{Result, SerialError};

/// One option a program takes.
#[derive(Debug, Clone, Copy)]
pub struct OptSpec {
    /// The short letter, if any.
    pub short: Option<char>,
    /// The long name.
    pub long: &'static str,
    /// Whether it takes a value.
    pub takes_value: bool,
}

impl OptSpec {
    /// An option with a value.
    pub const fn value(short: char, long: &'static str) -> OptSpec {
        OptSpec {
            short: Some(short),
            long,
            takes_value: true,
        }
    }

    /// A flag.
    pub const fn flag(short: char, long: &'static str) -> OptSpec {
        OptSpec {
            short: Some(short),
            long,
            takes_value: false,
        }
    }

    /// A long-only flag.
    pub const fn long_flag(long: &'static str) -> OptSpec {
        OptSpec {
            short: None,
            long,
            takes_value: false,
        }
    }

    /// A long-only option with a value.
    pub const fn long_value(long: &'static str) -> OptSpec {
        OptSpec {
            short: None,
            long,
            takes_value: true,
        }
    }
}

/// An option found on the command line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Found {
    /// Its long name (whatever the user wrote).
    pub long: &'static str,
    /// How the user wrote it (`-r`, `--rate`), for messages.
    pub written: String,
    /// Its value, for options that take one.
    pub value: Option<String>,
}

fn usage(msg: String) -> SerialError {
    SerialError::Usage(msg)
}

/// Parses `args` (without the program name) against `specs`, in order.
pub fn parse(specs: &[OptSpec], args: &[String]) -> Result<Vec<Found>> {
    let mut found = Vec::new();
    let mut i = 0;
    while i < args.len() {
        let arg = &args[i];
        i += 1;
        if arg == "--" {
            if let Some(extra) = args.get(i) {
                return Err(usage(format!("unexpected argument '{extra}'")));
            }
            break;
        }
        if let Some(body) = arg.strip_prefix("--") {
            let (name, inline) = match body.split_once('=') {
                Some((n, v)) => (n, Some(v.to_string())),
                None => (body, None),
            };
            let spec = find_long(specs, name)?;
            let value = if spec.takes_value {
                match inline {
                    Some(v) => Some(v),
                    None => {
                        let v = args.get(i).ok_or_else(|| {
                            usage(format!("option '--{}' needs a value", spec.long))
                        })?;
                        i += 1;
                        Some(v.clone())
                    }
                }
            } else if inline.is_some() {
                return Err(usage(format!("option '--{}' takes no value", spec.long)));
            } else {
                None
            };
            found.push(Found {
                long: spec.long,
                written: format!("--{}", spec.long),
                value,
            });
        } else if let Some(letters) = arg.strip_prefix('-').filter(|l| !l.is_empty()) {
            for (at, c) in letters.char_indices() {
                let spec = specs
                    .iter()
                    .find(|s| s.short == Some(c))
                    .ok_or_else(|| usage(format!("unknown option '-{c}'")))?;
                if spec.takes_value {
                    let rest = &letters[at + c.len_utf8()..];
                    let value = if !rest.is_empty() {
                        rest.to_string()
                    } else {
                        let v = args
                            .get(i)
                            .ok_or_else(|| usage(format!("option '-{c}' needs a value")))?;
                        i += 1;
                        v.clone()
                    };
                    found.push(Found {
                        long: spec.long,
                        written: format!("-{c}"),
                        value: Some(value),
                    });
                    break;
                }
                found.push(Found {
                    long: spec.long,
                    written: format!("-{c}"),
                    value: None,
                });
            }
        } else {
            return Err(usage(format!("unexpected argument '{arg}'")));
        }
    }
    Ok(found)
}

fn find_long<'a>(specs: &'a [OptSpec], name: &str) -> Result<&'a OptSpec> {
    if let Some(s) = specs.iter().find(|s| s.long == name) {
        return Ok(s);
    }
    let matches: Vec<&OptSpec> = specs
        .iter()
        .filter(|s| !name.is_empty() && s.long.starts_with(name))
        .collect();
    match matches[..] {
        [one] => Ok(one),
        [] => Err(usage(format!("unknown option '--{name}'"))),
        _ => Err(usage(format!(
            "option '--{name}' is ambiguous ({})",
            matches
                .iter()
                .map(|s| format!("--{}", s.long))
                .collect::<Vec<_>>()
                .join(", ")
        ))),
    }
}

/// The choice `value` names: an exact match, else the only choice it is
/// a prefix of (case-insensitive).
pub fn choice(value: &str, choices: &[&'static str]) -> Option<&'static str> {
    let v = value.to_ascii_lowercase();
    if let Some(c) = choices.iter().find(|c| **c == v) {
        return Some(c);
    }
    let mut prefixed = choices
        .iter()
        .filter(|c| !v.is_empty() && c.starts_with(&v));
    match (prefixed.next(), prefixed.next()) {
        (Some(c), None) => Some(c),
        _ => None,
    }
}

/// A bad value for `found`.
pub fn bad(found: &Found, reason: impl Into<String>) -> SerialError {
    SerialError::BadOption {
        option: found.written.clone(),
        value: found.value.clone().unwrap_or_default(),
        reason: reason.into(),
    }
}

/// The value of an option that takes one.
pub fn value(found: &Found) -> &str {
    found.value.as_deref().unwrap_or("")
}

/// A finite number in `min..=max`.
pub fn number(found: &Found, min: f64, max: f64) -> Result<f64> {
    let v: f64 = value(found)
        .trim()
        .parse()
        .map_err(|_| bad(found, "not a number"))?;
    if !v.is_finite() || v < min || v > max {
        return Err(bad(found, format!("must be between {min} and {max}")));
    }
    Ok(v)
}

/// A whole number in `min..=max`.
pub fn integer(found: &Found, min: i64, max: i64) -> Result<i64> {
    let v: i64 = value(found)
        .trim()
        .parse()
        .map_err(|_| bad(found, "not a whole number"))?;
    if v < min || v > max {
        return Err(bad(found, format!("must be between {min} and {max}")));
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPECS: &[OptSpec] = &[
        OptSpec::value('r', "rate"),
        OptSpec::value('d', "device"),
        OptSpec::flag('g', "debug"),
        OptSpec::flag('y', "regdump"),
        OptSpec::value('x', "register"),
        OptSpec::long_value("response-timeout"),
        OptSpec::long_value("retries"),
    ];

    fn args(a: &[&str]) -> Vec<String> {
        a.iter().map(|s| s.to_string()).collect()
    }

    fn longs(a: &[&str]) -> Vec<(&'static str, Option<String>)> {
        parse(SPECS, &args(a))
            .unwrap()
            .into_iter()
            .map(|f| (f.long, f.value))
            .collect()
    }

    #[test]
    fn getopt_long_forms() {
        assert_eq!(
            longs(&[
                "-r",
                "9600",
                "-d/dev/ttyUSB0",
                "-gy",
                "--register=PD014=30",
                "--ra",
                "5"
            ]),
            [
                ("rate", Some("9600".into())),
                ("device", Some("/dev/ttyUSB0".into())),
                ("debug", None),
                ("regdump", None),
                ("register", Some("PD014=30".into())),
                ("rate", Some("5".into())),
            ]
        );
        assert_eq!(
            longs(&["-gd", "x", "--"]),
            [("debug", None), ("device", Some("x".into()))]
        );
    }

    #[test]
    fn usage_errors_say_what() {
        let err = |a: &[&str]| parse(SPECS, &args(a)).unwrap_err().to_string();
        assert_eq!(err(&["-q"]), "unknown option '-q'");
        assert_eq!(err(&["--rate"]), "option '--rate' needs a value");
        assert_eq!(err(&["-r"]), "option '-r' needs a value");
        assert_eq!(err(&["--debug=1"]), "option '--debug' takes no value");
        assert_eq!(
            err(&["--re", "1"]),
            "option '--re' is ambiguous (--regdump, --register, --response-timeout, --retries)"
        );
        assert_eq!(err(&["stray"]), "unexpected argument 'stray'");
        assert_eq!(err(&["--bogus"]), "unknown option '--bogus'");
    }

    #[test]
    fn choices_by_unique_prefix() {
        const RATES: &[&str] = &["110", "300", "1200", "9600", "19200", "57600", "115200"];
        assert_eq!(choice("5", RATES), Some("57600"));
        assert_eq!(choice("1", RATES), None, "ambiguous");
        assert_eq!(choice("19200", RATES), Some("19200"));
        assert_eq!(choice("110", RATES), Some("110"));
        assert_eq!(choice("", RATES), None);
        assert_eq!(choice("E", &["even", "odd", "none"]), Some("even"));
    }

    #[test]
    fn numbers_in_range() {
        let f = |v: &str| Found {
            long: "max-frequency",
            written: "-F".into(),
            value: Some(v.into()),
        };
        assert_eq!(number(&f("400"), 0.0, 65535.0).unwrap(), 400.0);
        assert_eq!(
            number(&f("nan"), 0.0, 1.0).unwrap_err().to_string(),
            "invalid -F: nan (must be between 0 and 1)"
        );
        assert_eq!(
            number(&f("4x"), 0.0, 1.0).unwrap_err().to_string(),
            "invalid -F: 4x (not a number)"
        );
        assert_eq!(integer(&f("7"), 1, 247).unwrap(), 7);
    }
}
