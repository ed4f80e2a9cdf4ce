//! `loadrt` parameter helpers on top of [`hal_core::module`]: the checks
//! every driver makes, worded one way.
//!
//! * [`Params`]: reads a driver's parsed arguments with defaults, ranges
//!   and per-board/per-channel array counts; every error is a
//!   [`DriverError::BadParam`] naming the module, the parameter and the
//!   item (`hm2_pci: parameter 'config': item 1 "num_encoders=x": ...`).
//! * [`parse_hex`] and [`parse_number`]: addresses as LinuxCNC's drivers
//!   take them (bare hex in hal_parport's `cfg`; C notation with `0x` in
//!   integer parameters such as `base=0x300`).
//! * [`BackendTokens`]: the backend token (`sim` and friends) one way for
//!   all drivers: a token is one of the driver's real backends or starts
//!   with `sim`, and a simulated backend is always available.

use std::ops::RangeInclusive;

use hal_core::module::{parse_c_int, ModuleArgs};

use crate::error::{DriverError, Result};

/// A driver's `loadrt` arguments, read with its module name at hand.
#[derive(Debug, Clone, Copy)]
pub struct Params<'a> {
    module: &'static str,
    args: &'a ModuleArgs,
}

impl<'a> Params<'a> {
    /// The arguments `args` of `module`.
    pub fn new(module: &'static str, args: &'a ModuleArgs) -> Params<'a> {
        Params { module, args }
    }

    /// The module's name.
    pub fn module(&self) -> &'static str {
        self.module
    }

    /// A [`DriverError::BadParam`] for `param`.
    pub fn error(&self, param: &str, reason: impl Into<String>) -> DriverError {
        DriverError::BadParam {
            module: self.module.to_string(),
            param: param.to_string(),
            reason: reason.into(),
        }
    }

    /// A [`DriverError::BadParam`] for item `index` of array `param`, whose
    /// text was `item`.
    pub fn item_error(
        &self,
        param: &str,
        index: usize,
        item: &str,
        reason: impl std::fmt::Display,
    ) -> DriverError {
        self.error(param, format!("item {index} \"{item}\": {reason}"))
    }

    /// A string parameter, or `default`.
    pub fn str_or(&self, name: &str, default: &'a str) -> &'a str {
        self.args.str(name).unwrap_or(default)
    }

    /// An integer parameter, or `default`.
    pub fn int_or(&self, name: &str, default: i64) -> i64 {
        self.args.int(name).unwrap_or(default)
    }

    /// An integer parameter (or `default`) that must lie in `range`.
    pub fn int_in(&self, name: &str, default: i64, range: RangeInclusive<i64>) -> Result<i64> {
        let v = self.int_or(name, default);
        if !range.contains(&v) {
            return Err(self.error(
                name,
                format!("{v} is out of range ({}..={})", range.start(), range.end()),
            ));
        }
        Ok(v)
    }

    /// An integer array with one item per board or channel: `count`
    /// items, those not given (or given empty) set to `default`, each in
    /// `range`; more than `count` items is an error.
    pub fn ints_per(
        &self,
        name: &str,
        count: usize,
        default: i64,
        range: RangeInclusive<i64>,
    ) -> Result<Vec<i64>> {
        let given = self.args.int_array(name);
        self.check_count(name, given.len(), count)?;
        (0..count)
            .map(|i| {
                let v = given.get(i).copied().unwrap_or(default);
                if range.contains(&v) {
                    Ok(v)
                } else {
                    Err(self.item_error(
                        name,
                        i,
                        &v.to_string(),
                        format_args!("out of range ({}..={})", range.start(), range.end()),
                    ))
                }
            })
            .collect()
    }

    /// A string array with one item per board or channel, each parsed by
    /// `parse` (given its index and text; an error says what is wrong,
    /// and is reported naming the item). Items not given, or given empty,
    /// are `default(index)`. More than `count` items is an error.
    pub fn strs_per<T, E: std::fmt::Display>(
        &self,
        name: &str,
        count: usize,
        mut parse: impl FnMut(usize, &str) -> std::result::Result<T, E>,
        mut default: impl FnMut(usize) -> T,
    ) -> Result<Vec<T>> {
        let given = self.args.str_array(name);
        self.check_count(name, given.len(), count)?;
        (0..count)
            .map(|i| match given.get(i).map(String::as_str) {
                Some(text) if !text.is_empty() => {
                    parse(i, text).map_err(|why| self.item_error(name, i, text, why))
                }
                _ => Ok(default(i)),
            })
            .collect()
    }

    fn check_count(&self, name: &str, given: usize, count: usize) -> Result<()> {
        if given > count {
            return Err(self.error(
                name,
                format!("{given} items given, but there are only {count}"),
            ));
        }
        Ok(())
    }

    /// A string parameter that must be one of `allowed` (any case), if
    /// given; returns the allowed spelling.
    pub fn choice(&self, name: &str, allowed: &[&'static str]) -> Result<Option<&'static str>> {
        let Some(v) = self.args.str(name) else {
            return Ok(None);
        };
        allowed
            .iter()
            .find(|a| a.eq_ignore_ascii_case(v))
            .copied()
            .map(Some)
            .ok_or_else(|| self.error(name, format!("'{v}' is not one of {}", allowed.join(", "))))
    }
}

/// Why an address or number token was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NumberError {
    /// Nothing after the prefix.
    #[error("no hex digits")]
    NoDigits,
    /// A character that is not a digit of the radix.
    #[error("'{0}' is not a hex digit")]
    BadHexDigit(char),
    /// Past the largest allowed value.
    #[error("larger than {max:#x}")]
    TooLarge {
        /// The largest allowed value.
        max: u64,
    },
    /// Not a number in C notation.
    #[error("{0}")]
    NotANumber(String),
}

/// Parses a hexadecimal token with an optional `0x`/`0X` prefix (`378`
/// is 0x378, as hal_parport's `cfg` reads addresses), at most `max`.
pub fn parse_hex(token: &str, max: u64) -> std::result::Result<u64, NumberError> {
    let digits = token
        .strip_prefix("0x")
        .or_else(|| token.strip_prefix("0X"))
        .unwrap_or(token);
    if digits.is_empty() {
        return Err(NumberError::NoDigits);
    }
    if let Some(c) = digits.chars().find(|c| !c.is_ascii_hexdigit()) {
        return Err(NumberError::BadHexDigit(c));
    }
    let mut v: u64 = 0;
    for c in digits.chars() {
        v = v * 16 + c.to_digit(16).unwrap_or(0) as u64;
        if v > max {
            return Err(NumberError::TooLarge { max });
        }
    }
    Ok(v)
}

/// Parses a number in C notation (`0x` hex, leading `0` octal, else
/// decimal; as `strtol(s, 0)` and hal-core's integer parameters) that
/// must lie in `0..=max`: an I/O base address, a card ID.
pub fn parse_number(token: &str, max: u64) -> std::result::Result<u64, NumberError> {
    let v = parse_c_int(token, 64).map_err(|e| NumberError::NotANumber(e.to_string()))?;
    if v < 0 {
        return Err(NumberError::NotANumber(format!("'{token}' is negative")));
    }
    if v as u64 > max {
        return Err(NumberError::TooLarge { max });
    }
    Ok(v as u64)
}

/// How a driver reaches its hardware, as chosen at `loadrt`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backend {
    /// A real backend, by its token (`ppdev`, `raw`, ...).
    Real(&'static str),
    /// A simulated board, by its token (`sim`, `simloop`, ...).
    Sim(&'static str),
}

impl Backend {
    /// The token as the driver declares it.
    pub fn token(self) -> &'static str {
        match self {
            Backend::Real(t) | Backend::Sim(t) => t,
        }
    }

    /// Whether it is a simulator.
    pub fn is_sim(self) -> bool {
        matches!(self, Backend::Sim(_))
    }
}

/// A driver's backend tokens: its real backends and its simulator
/// variants. The rule for every driver: tokens are whole words matched in
/// any case; simulator tokens start with `sim` and `sim` itself is always
/// one; no token may be a hex number or a word the driver's own syntax
/// uses, so adding one never changes the meaning of a LinuxCNC string.
#[derive(Debug, Clone, Copy)]
pub struct BackendTokens {
    real: &'static [&'static str],
    sim: &'static [&'static str],
}

impl BackendTokens {
    /// The tokens `real` (hardware backends) and `sim` (simulator
    /// variants, each starting with `sim`; `sim` itself is added if
    /// missing).
    pub const fn new(real: &'static [&'static str], sim: &'static [&'static str]) -> BackendTokens {
        BackendTokens { real, sim }
    }

    /// The backend `token` names, if it is one of these.
    pub fn parse(&self, token: &str) -> Option<Backend> {
        let find =
            |set: &[&'static str]| set.iter().copied().find(|t| t.eq_ignore_ascii_case(token));
        if let Some(t) = find(self.real) {
            return Some(Backend::Real(t));
        }
        if let Some(t) = find(self.sim) {
            return Some(Backend::Sim(t));
        }
        token
            .eq_ignore_ascii_case("sim")
            .then_some(Backend::Sim("sim"))
    }

    /// Every token, `|`-separated, for help texts and messages.
    pub fn list(&self) -> String {
        let mut all: Vec<&str> = self.real.to_vec();
        if !self.sim.iter().any(|t| t.eq_ignore_ascii_case("sim")) {
            all.push("sim");
        }
        all.extend(self.sim.iter().copied());
        all.join("|")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_core::module::{ParamDecl, ParamKind};

    const DECLS: &[ParamDecl] = &[
        ParamDecl {
            name: "config",
            kind: ParamKind::StrArray(4),
            help: "",
        },
        ParamDecl {
            name: "num_chan",
            kind: ParamKind::Int,
            help: "",
        },
        ParamDecl {
            name: "ids",
            kind: ParamKind::IntArray(4),
            help: "",
        },
        ParamDecl {
            name: "sim",
            kind: ParamKind::Str,
            help: "",
        },
    ];

    fn args(a: &[&str]) -> ModuleArgs {
        ModuleArgs::parse("drv", DECLS, a).unwrap()
    }

    #[test]
    fn ranges_and_defaults() {
        let a = args(&["num_chan=9"]);
        let p = Params::new("drv", &a);
        assert_eq!(p.int_or("num_chan", 1), 9);
        assert_eq!(p.int_or("other", 1), 1);
        assert_eq!(p.int_in("num_chan", 1, 1..=16).unwrap(), 9);
        let e = p.int_in("num_chan", 1, 1..=8).unwrap_err();
        assert_eq!(
            e.to_string(),
            "drv: parameter 'num_chan': 9 is out of range (1..=8)"
        );
    }

    #[test]
    fn per_item_arrays_name_the_item() {
        let a = args(&["ids=1,,7", "config=\"num_encoders=2\",,bad"]);
        let p = Params::new("hm2_pci", &a);
        assert_eq!(p.ints_per("ids", 4, 5, 0..=15).unwrap(), vec![1, 0, 7, 5]);
        assert!(p
            .ints_per("ids", 2, 5, 0..=15)
            .unwrap_err()
            .to_string()
            .contains("3 items given, but there are only 2"));
        let e = p.ints_per("ids", 3, 0, 0..=3).unwrap_err().to_string();
        assert_eq!(
            e,
            "hm2_pci: parameter 'ids': item 2 \"7\": out of range (0..=3)"
        );
        let parse = |_: usize, s: &str| -> std::result::Result<u32, &'static str> {
            s.strip_prefix("num_encoders=")
                .and_then(|n| n.parse().ok())
                .ok_or("not num_encoders=N")
        };
        let e = p
            .strs_per("config", 3, parse, |_| 0)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "hm2_pci: parameter 'config': item 2 \"bad\": not num_encoders=N"
        );
        let a = args(&["config=num_encoders=2,"]);
        let p = Params::new("hm2_pci", &a);
        assert_eq!(
            p.strs_per("config", 3, parse, |i| 100 + i as u32).unwrap(),
            vec![2, 101, 102]
        );
    }

    #[test]
    fn choices() {
        let a = args(&["sim=5I25"]);
        let p = Params::new("hm2_pci", &a);
        assert_eq!(p.choice("sim", &["5i25", "5i24"]).unwrap(), Some("5i25"));
        let e = p.choice("sim", &["6i25"]).unwrap_err().to_string();
        assert_eq!(e, "hm2_pci: parameter 'sim': '5I25' is not one of 6i25");
        assert_eq!(p.choice("config", &["x"]).unwrap(), None);
    }

    #[test]
    fn hex_and_c_numbers() {
        assert_eq!(parse_hex("378", 0xffff), Ok(0x378));
        assert_eq!(parse_hex("0X3bC", 0xffff), Ok(0x3bc));
        assert_eq!(parse_hex("0x", 0xffff), Err(NumberError::NoDigits));
        assert_eq!(
            parse_hex("0x37g", 0xffff),
            Err(NumberError::BadHexDigit('g'))
        );
        assert_eq!(
            parse_hex("123456789abcdef", 0xffff)
                .unwrap_err()
                .to_string(),
            "larger than 0xffff"
        );
        assert_eq!(parse_number("0x300", 0xffff), Ok(0x300));
        assert_eq!(parse_number("768", 0xffff), Ok(768));
        assert_eq!(parse_number("010", 0xffff), Ok(8));
        assert!(parse_number("-1", 0xffff)
            .unwrap_err()
            .to_string()
            .contains("negative"));
        assert!(parse_number("0x10000", 0xffff).is_err());
        assert!(parse_number("3o0", 0xffff)
            .unwrap_err()
            .to_string()
            .contains("not a number"));
    }

    #[test]
    fn backend_tokens_one_way() {
        const T: BackendTokens = BackendTokens::new(&["ppdev", "raw"], &["simloop"]);
        assert_eq!(T.parse("PPDEV"), Some(Backend::Real("ppdev")));
        assert_eq!(T.parse("sim"), Some(Backend::Sim("sim")));
        assert_eq!(T.parse("SimLoop"), Some(Backend::Sim("simloop")));
        assert_eq!(T.parse("simx"), None);
        assert_eq!(T.parse("0x378"), None);
        assert_eq!(T.list(), "ppdev|raw|sim|simloop");
        assert!(T.parse("sim").unwrap().is_sim() && !T.parse("raw").unwrap().is_sim());
        assert_eq!(T.parse("raw").unwrap().token(), "raw");
    }
}
