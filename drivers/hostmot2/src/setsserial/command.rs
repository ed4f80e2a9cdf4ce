//! The `cmd=` string of `setsserial`: `set <remote>.<parameter> <value>`
//! or `flash <remote> <file>.BIN`, three words separated by blanks.

use crate::error::{Hm2Error, Result};

/// Longest `cmd=` string accepted.
pub const MAX_CMD: usize = 1024;

/// A parsed command.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Command {
    /// Writes a global into a remote's EEPROM.
    Set {
        /// `<remote>.<parameter>` as HAL names the parameter.
        target: String,
        /// The value as given (parsed once the global's type is known).
        value: String,
    },
    /// Writes a firmware file into a remote's flash.
    Flash {
        /// The remote's HAL name.
        remote: String,
        /// The file, relative to the firmware directory.
        file: String,
    },
}

/// Parses `cmd`.
pub fn parse(cmd: &str) -> Result<Command> {
    let bad = |reason: &str| Hm2Error::SetsserialCommand {
        cmd: cmd.chars().take(80).collect(),
        reason: reason.to_string(),
    };
    if cmd.len() > MAX_CMD {
        return Err(bad(&format!("longer than {MAX_CMD} bytes")));
    }
    let words: Vec<&str> = cmd.split_whitespace().collect();
    let [verb, what, arg] = words[..] else {
        return Err(bad(&format!("{} words, 3 expected", words.len())));
    };
    match verb {
        "set" => Ok(Command::Set {
            target: what.to_string(),
            value: arg.to_string(),
        }),
        "flash" => {
            let is_bin = arg
                .rsplit_once('.')
                .is_some_and(|(stem, ext)| !stem.is_empty() && ext.eq_ignore_ascii_case("bin"));
            if !is_bin {
                return Err(Hm2Error::NotBinFile {
                    file: arg.to_string(),
                });
            }
            Ok(Command::Flash {
                remote: what.to_string(),
                file: arg.to_string(),
            })
        }
        v => Err(bad(&format!("unknown command \"{v}\""))),
    }
}

/// An integer of 64 bits, unsigned or signed (`i64::MIN..=u64::MAX`), in
/// decimal or `0x` hex.
pub fn parse_int(s: &str) -> Option<i128> {
    let (neg, digits) = match s.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, s.strip_prefix('+').unwrap_or(s)),
    };
    let v = match digits
        .strip_prefix("0x")
        .or_else(|| digits.strip_prefix("0X"))
    {
        Some(hex) if !hex.is_empty() && hex.len() <= 16 => i128::from_str_radix(hex, 16).ok()?,
        Some(_) => return None,
        None if !digits.is_empty() && digits.len() <= 20 => {
            if !digits.bytes().all(|b| b.is_ascii_digit()) {
                return None;
            }
            digits.parse::<i128>().ok()?
        }
        None => return None,
    };
    let v = if neg { -v } else { v };
    (i128::from(i64::MIN)..=i128::from(u64::MAX))
        .contains(&v)
        .then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_and_numbers() {
        assert_eq!(
            parse(" set  hm2_8i20.001f.nvmaxcurrent 750 ").unwrap(),
            Command::Set {
                target: "hm2_8i20.001f.nvmaxcurrent".into(),
                value: "750".into()
            }
        );
        assert_eq!(
            parse("flash hm2_5i25.0.7i77.0.0 hm2/7i77/7I77.BIN").unwrap(),
            Command::Flash {
                remote: "hm2_5i25.0.7i77.0.0".into(),
                file: "hm2/7i77/7I77.BIN".into()
            }
        );
        assert!(matches!(
            parse("flash x 7i77.bit"),
            Err(Hm2Error::NotBinFile { .. })
        ));
        assert!(matches!(
            parse("flash x .bin"),
            Err(Hm2Error::NotBinFile { .. })
        ));
        for bad in ["", "set a", "set a b c", "get a b", "set a b c d"] {
            if bad == "set a b c" {
                continue;
            }
            assert!(
                matches!(parse(bad), Err(Hm2Error::SetsserialCommand { .. })),
                "{bad}"
            );
        }
        assert!(parse(&"x".repeat(MAX_CMD + 1)).is_err());
        assert_eq!(parse_int("750"), Some(750));
        assert_eq!(parse_int("0x1F"), Some(31));
        assert_eq!(parse_int("-5"), Some(-5));
        assert_eq!(parse_int("0xFFFFFFFFFFFFFFFF"), Some(u64::MAX as i128));
        assert_eq!(parse_int("-9223372036854775808"), Some(i64::MIN as i128));
        // The fuzzer's finding: 20 decimal digits past u64.
        for bad in [
            "",
            "0x",
            "12a",
            "1.5",
            "-",
            "0x10000000000000000",
            "1e3",
            "99999999999999999999",
            "-9223372036854775809",
        ] {
            assert_eq!(parse_int(bad), None, "{bad}");
        }
    }
}
