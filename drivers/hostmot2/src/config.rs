//! The per-board config string (hardware.md 5.10, hostmot2(9)):
//! space-separated tokens such as `num_encoders=3 num_pwmgens=3
//! num_stepgens=0 enable_raw`.
//!
//! Every token LinuxCNC accepts is accepted. Counts (`num_<module>s=N`)
//! are −1 for "all instances" (the default), 0 for none, N for the first
//! N; numbers are read as C's `strtol(s, 0)` reads them (decimal, `0x`
//! hex, leading-0 octal) but, unlike LinuxCNC, a token that is not a
//! number is refused instead of read as 0.
//!
//! `sserial_port_N=<modes>` (N = 0..3) gives Smart Serial port N's
//! channels their modes, left to right: a digit starts the channel in
//! that mode, a lower-case `x` disables it (its pins stay GPIO), any
//! other character is skipped and takes no channel; channels not named
//! start in mode 0. The first such token limits the ports used to those
//! named with a digit (`num_sserials`, as LinuxCNC counts it).
//!
//! `firmware=<file>` names the bitfile the board's FPGA is loaded from
//! (PLX-bridged boards, [`crate::fpga`]); boards with flash ignore it, as
//! LinuxCNC's do. Not supported, and said so: the absolute-encoder and
//! other module tokens (`ssi_chan_N`, `num_3pwmgens`, ...) are accepted
//! and validated as LinuxCNC does, but those modules are not supported
//! yet: their descriptors are ignored and their pins stay GPIO.

use hal_core::module::parse_c_int;

use crate::error::{Hm2Error, Result};

/// The parsed config string of one board.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Config {
    /// `firmware=`: the bitfile to load, relative to the firmware directory.
    pub firmware: Option<String>,
    /// Encoders to use (−1 = all).
    pub num_encoders: i32,
    /// Step generators to use (−1 = all).
    pub num_stepgens: i32,
    /// PWM generators to use (−1 = all).
    pub num_pwmgens: i32,
    /// LEDs to export (−1 = all the board has).
    pub num_leds: i32,
    /// PktUARTs to use (−1 = all), for hm2_modbus.
    pub num_pktuarts: i32,
    /// Step generator output pins taken from GPIO (default 2).
    pub stepgen_width: i32,
    /// Export the raw register access pins.
    pub enable_raw: bool,
    /// `sserial_port_N` mode strings, as given.
    pub sserial_ports: [Option<String>; 4],
    /// Smart Serial ports to use (−1 = all): 0 after the first
    /// `sserial_port_N` token, raised to N + 1 by each one with a digit.
    pub num_sserials: i32,
    /// Counts of modules this driver does not support, as given
    /// (`num_3pwmgens` ...), kept so `save` and messages can show them.
    pub unsupported: Vec<(String, i32)>,
    /// Format strings of absolute encoders (`ssi_chan_0=...`), as given.
    pub abs_encoder_formats: Vec<(String, String)>,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            firmware: None,
            num_encoders: -1,
            num_stepgens: -1,
            num_pwmgens: -1,
            num_leds: -1,
            num_pktuarts: -1,
            stepgen_width: 2,
            enable_raw: false,
            sserial_ports: Default::default(),
            num_sserials: -1,
            unsupported: Vec::new(),
            abs_encoder_formats: Vec::new(),
        }
    }
}

/// `num_<module>s` keys of modules this driver ignores.
const UNSUPPORTED_COUNTS: &[&str] = &[
    "num_3pwmgens",
    "num_rcpwmgens",
    "num_resolvers",
    "num_bspis",
    "num_uarts",
    "num_dplls",
    "num_inmuxs",
    "num_inms",
    "num_outms",
    "num_ssrs",
    "num_xy2mods",
    "num_oneshots",
    "num_periodms",
];

fn number(token: &str, value: &str) -> Result<i32> {
    parse_c_int(value, 32)
        .map(|v| v as i32)
        .map_err(|e| Hm2Error::BadConfigValue {
            token: token.to_string(),
            reason: e.to_string(),
        })
}

fn count(token: &str, value: &str) -> Result<i32> {
    let n = number(token, value)?;
    if n < -1 {
        return Err(Hm2Error::BadConfigValue {
            token: token.to_string(),
            reason: "must be -1 (all), 0 (none) or a count".into(),
        });
    }
    Ok(n)
}

/// Parses one board's config string.
pub fn parse(s: &str) -> Result<Config> {
    let mut c = Config::default();
    for token in s.split_ascii_whitespace() {
        let (key, value) = match token.split_once('=') {
            Some((k, v)) => (k, Some(v)),
            None => (token, None),
        };
        match (key, value) {
            ("enable_raw", None) => c.enable_raw = true,
            ("firmware", Some(f)) => c.firmware = Some(f.to_string()),
            ("num_encoders", Some(v)) => c.num_encoders = count(token, v)?,
            ("num_stepgens", Some(v)) => c.num_stepgens = count(token, v)?,
            ("num_pwmgens", Some(v)) => c.num_pwmgens = count(token, v)?,
            ("num_leds", Some(v)) => c.num_leds = count(token, v)?,
            ("num_pktuarts", Some(v)) => c.num_pktuarts = count(token, v)?,
            ("stepgen_width", Some(v)) => {
                let w = number(token, v)?;
                if !(0..=8).contains(&w) {
                    return Err(Hm2Error::BadConfigValue {
                        token: token.to_string(),
                        reason: "a stepgen has 0 to 8 output pins".into(),
                    });
                }
                c.stepgen_width = w;
            }
            (k, Some(v)) if UNSUPPORTED_COUNTS.contains(&k) => {
                let n = count(token, v)?;
                c.unsupported.retain(|(name, _)| name != k);
                c.unsupported.push((k.to_string(), n));
            }
            (k, Some(v)) if k.starts_with("sserial_port_") => {
                let port = match &k["sserial_port_".len()..] {
                    "0" => 0,
                    "1" => 1,
                    "2" => 2,
                    "3" => 3,
                    _ => return Err(Hm2Error::BadSserialTag),
                };
                if v.len() > 8 {
                    return Err(Hm2Error::BadConfigValue {
                        token: token.to_string(),
                        reason: "at most 8 channel modes".into(),
                    });
                }
                c.sserial_ports[port] = Some(v.to_string());
                c.num_sserials = c.num_sserials.max(0);
                if v.bytes().any(|b| b.is_ascii_digit()) {
                    c.num_sserials = c.num_sserials.max(port as i32 + 1);
                }
            }
            (k, Some(v))
                if ["ssi_chan_", "biss_chan_", "fanuc_chan_"].iter().any(|p| {
                    k.strip_prefix(p)
                        .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
                }) =>
            {
                c.abs_encoder_formats.push((k.to_string(), v.to_string()));
            }
            _ => {
                return Err(Hm2Error::InvalidToken {
                    token: token.to_string(),
                })
            }
        }
    }
    Ok(c)
}

impl Config {
    /// The modes of Smart Serial `port`'s eight channels: `None` for a
    /// channel disabled with `x`, else the mode (0 unless given).
    pub fn sserial_modes(&self, port: usize) -> [Option<u8>; crate::sserial::MAX_CHANNELS] {
        let mut modes = [Some(0); crate::sserial::MAX_CHANNELS];
        let Some(s) = self.sserial_ports.get(port).and_then(|s| s.as_deref()) else {
            return modes;
        };
        let mut chan = 0;
        for b in s.bytes() {
            let m = match b {
                b'0'..=b'9' => Some(b - b'0'),
                b'x' => None,
                _ => continue,
            };
            if let Some(slot) = modes.get_mut(chan) {
                *slot = m;
            }
            chan += 1;
        }
        modes
    }
}

/// How many instances of a module to use: `requested` of `available`
/// (−1 = all). More than available is refused with LinuxCNC's message.
pub fn instances(key: &'static str, requested: i32, available: u32) -> Result<u32> {
    match requested {
        -1 => Ok(available),
        n if n >= 0 && n as u32 <= available => Ok(n as u32),
        n => Err(Hm2Error::TooManyRequested {
            key,
            requested: n,
            available,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linuxcnc_strings_parse() {
        let c = parse("num_encoders=3 num_pwmgens=0x3  num_stepgens=010 enable_raw").unwrap();
        assert_eq!(
            (c.num_encoders, c.num_pwmgens, c.num_stepgens),
            (3, 3, 8),
            "decimal, hex, octal"
        );
        assert!(c.enable_raw);
        assert_eq!(parse("").unwrap(), Config::default());
        let c = parse("sserial_port_0=0XXX num_3pwmgens=-1 ssi_chan_2=pos%24g stepgen_width=4")
            .unwrap();
        assert_eq!(c.sserial_ports[0].as_deref(), Some("0XXX"));
        assert_eq!(c.unsupported, vec![("num_3pwmgens".to_string(), -1)]);
        assert_eq!(c.abs_encoder_formats.len(), 1);
        assert_eq!(c.stepgen_width, 4);
    }

    #[test]
    fn every_refusal_says_why() {
        let cases: &[(&str, &str)] = &[
            (
                "num_encoders=3 bogus",
                "invalid token in config string: \"bogus\"",
            ),
            (
                "num_encoders",
                "invalid token in config string: \"num_encoders\"",
            ),
            ("enable_raw=1", "invalid token"),
            (
                "num_encoders=x",
                "invalid value in config string: \"num_encoders=x\"",
            ),
            ("num_stepgens=-2", "must be -1"),
            ("stepgen_width=9", "0 to 8"),
            ("firmware", "invalid token in config string: \"firmware\""),
            (
                "sserial_port_4=0000",
                "sserial_port tag must be in the form",
            ),
            ("sserial_port_0=000000000", "at most 8"),
            ("ssi_chan_=x", "invalid token"),
        ];
        for (s, want) in cases {
            let e = parse(s).unwrap_err().to_string();
            assert!(e.contains(want), "{s}: {e}");
        }
    }

    #[test]
    fn sserial_modes_as_linuxcnc_reads_them() {
        let c = parse("").unwrap();
        assert_eq!(c.num_sserials, -1);
        assert_eq!(c.sserial_modes(2), [Some(0); 8]);
        let c = parse("sserial_port_0=0XXX").unwrap();
        assert_eq!(c.num_sserials, 1);
        assert_eq!(
            c.sserial_modes(0),
            [Some(0); 8],
            "X is skipped, not disabled"
        );
        let c = parse("sserial_port_1=1x2-x sserial_port_0=xxxxxxxx").unwrap();
        assert_eq!(c.num_sserials, 2);
        assert_eq!(
            c.sserial_modes(1),
            [
                Some(1),
                None,
                Some(2),
                None,
                Some(0),
                Some(0),
                Some(0),
                Some(0)
            ]
        );
        assert_eq!(c.sserial_modes(0), [None; 8]);
        let c = parse("sserial_port_0=xxxxxxxx").unwrap();
        assert_eq!(c.num_sserials, 0, "only x: the module is disabled");
    }

    #[test]
    fn instance_counts() {
        assert_eq!(instances("num_encoders", -1, 4), Ok(4));
        assert_eq!(instances("num_encoders", 2, 4), Ok(2));
        assert_eq!(
            instances("num_encoders", 5, 4).unwrap_err().to_string(),
            "config.num_encoders=5, but only 4 are available, not loading driver"
        );
    }
}
