//! `loadrt` modules: realtime components and drivers compiled into the
//! host, each with a declared table of module parameters.
//!
//! Rust has no stable ABI, so nothing is loaded from disk: the host binary
//! builds a [`Registry`] of every [`ModuleDef`] it was linked with, and
//! `loadrt NAME key=value ...` parses the arguments against the module's
//! table (as LinuxCNC parses them) before calling its `load` function.

use crate::error::{HalError, Result};
use crate::exec::Host;

/// The type of a module parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamKind {
    /// A C `int` (32 bits), parsed like `strtol(s, 0)`.
    Int,
    /// A C `long` (64 bits), parsed like `strtol(s, 0)`.
    Long,
    /// A string, taken verbatim (commas included).
    Str,
    /// Up to N comma-separated ints; an empty item is 0.
    IntArray(usize),
    /// Up to N comma-separated longs; an empty item is 0.
    LongArray(usize),
    /// Up to N comma-separated strings; an empty item is "".
    StrArray(usize),
}

/// One declared module parameter.
#[derive(Debug, Clone, Copy)]
pub struct ParamDecl {
    /// The key `loadrt` takes (`count`, `cfg`, `names`).
    pub name: &'static str,
    /// What the value must parse as.
    pub kind: ParamKind,
    /// One line for the module's help text.
    pub help: &'static str,
}

/// A parsed argument.
#[derive(Debug, Clone, PartialEq)]
pub enum ArgValue {
    /// An `Int` or `Long` parameter's value.
    Int(i64),
    /// A `Str` parameter's value, quotes removed.
    Str(String),
    /// An `IntArray` or `LongArray` parameter's items.
    IntArray(Vec<i64>),
    /// A `StrArray` parameter's items.
    StrArray(Vec<String>),
}

/// The arguments of one `loadrt`, checked against the module's table.
#[derive(Debug, Clone, Default)]
pub struct ModuleArgs {
    values: Vec<(&'static str, ArgValue)>,
    raw: Vec<String>,
}

impl ModuleArgs {
    /// Parses `key=value` words for `module` against `decls`. Every `"` is
    /// removed first, as LinuxCNC does.
    pub fn parse<S: AsRef<str>>(
        module: &str,
        decls: &[ParamDecl],
        args: &[S],
    ) -> Result<ModuleArgs> {
        let mut out = ModuleArgs::default();
        for arg in args {
            let arg = arg.as_ref().replace('"', "");
            let bad = |param: &str, reason: String| HalError::ModuleParam {
                module: module.to_string(),
                param: param.to_string(),
                reason,
            };
            let Some((key, value)) = arg.split_once('=') else {
                // A bare parameter name: say what its value is (its help
                // lists the choices, e.g. the boards of a `sim`).
                let reason = match decls.iter().find(|d| d.name == arg) {
                    Some(d) => format!("expected {arg}=VALUE: {}", d.help),
                    None => "expected name=value".into(),
                };
                return Err(bad(&arg, reason));
            };
            let decl = decls.iter().find(|d| d.name == key).ok_or_else(|| {
                let known: Vec<&str> = decls.iter().map(|d| d.name).collect();
                bad(
                    key,
                    if known.is_empty() {
                        format!("unknown parameter ({module} takes none)")
                    } else {
                        format!("unknown parameter ({module} takes {})", known.join(", "))
                    },
                )
            })?;
            let parsed = match decl.kind {
                ParamKind::Int => {
                    ArgValue::Int(parse_c_int(value, 32).map_err(|r| bad(key, r.to_string()))?)
                }
                ParamKind::Long => {
                    ArgValue::Int(parse_c_int(value, 64).map_err(|r| bad(key, r.to_string()))?)
                }
                ParamKind::Str => ArgValue::Str(value.to_string()),
                ParamKind::IntArray(n) | ParamKind::LongArray(n) => {
                    let bits = if matches!(decl.kind, ParamKind::IntArray(_)) {
                        32
                    } else {
                        64
                    };
                    let items: Vec<&str> = value.split(',').collect();
                    if items.len() > n {
                        return Err(bad(key, format!("can only take {n} arguments")));
                    }
                    ArgValue::IntArray(
                        items
                            .iter()
                            .map(|s| {
                                if s.is_empty() {
                                    Ok(0)
                                } else {
                                    parse_c_int(s, bits)
                                }
                            })
                            .collect::<crate::Result<_>>()
                            .map_err(|r| bad(key, r.to_string()))?,
                    )
                }
                ParamKind::StrArray(n) => {
                    let items: Vec<String> = value.split(',').map(str::to_string).collect();
                    if items.len() > n {
                        return Err(bad(key, format!("can only take {n} arguments")));
                    }
                    ArgValue::StrArray(items)
                }
            };
            out.values.retain(|(k, _)| *k != decl.name);
            out.values.push((decl.name, parsed));
            out.raw.push(arg);
        }
        Ok(out)
    }

    fn get(&self, name: &str) -> Option<&ArgValue> {
        self.values.iter().find(|(k, _)| *k == name).map(|(_, v)| v)
    }

    /// An int or long parameter, if given.
    pub fn int(&self, name: &str) -> Option<i64> {
        match self.get(name) {
            Some(ArgValue::Int(v)) => Some(*v),
            _ => None,
        }
    }

    /// A string parameter, if given.
    pub fn str(&self, name: &str) -> Option<&str> {
        match self.get(name) {
            Some(ArgValue::Str(s)) => Some(s),
            _ => None,
        }
    }

    /// The items given for an int array (empty if not given).
    pub fn int_array(&self, name: &str) -> &[i64] {
        match self.get(name) {
            Some(ArgValue::IntArray(v)) => v,
            _ => &[],
        }
    }

    /// The items given for a string array (empty if not given).
    pub fn str_array(&self, name: &str) -> &[String] {
        match self.get(name) {
            Some(ArgValue::StrArray(v)) => v,
            _ => &[],
        }
    }

    /// The arguments as given (quotes removed), joined by spaces: what
    /// `save` writes after `loadrt NAME`.
    pub fn raw(&self) -> String {
        self.raw.join(" ")
    }
}

/// The radix C's base-0 conversions pick for unsigned digits `t` (`0x`
/// hex, a leading `0` octal, else decimal), and the digits after the
/// prefix.
pub fn c_radix(t: &str) -> (u32, &str) {
    if let Some(h) = t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        (16, h)
    } else if t.len() > 1 && t.starts_with('0') {
        (8, &t[1..])
    } else {
        (10, t)
    }
}

/// Parses an integer as C's `strtol(s, &end, 0)` with the whole string
/// required: optional sign, `0x` hex, leading `0` octal, else decimal.
pub fn parse_c_int(s: &str, bits: u32) -> crate::Result<i64> {
    let not_a_number = || HalError::NotANumber {
        text: s.to_string(),
    };
    let t = s.trim_start();
    let (neg, t) = match t.as_bytes().first() {
        Some(b'-') => (true, &t[1..]),
        Some(b'+') => (false, &t[1..]),
        _ => (false, t),
    };
    let (radix, digits) = c_radix(t);
    if digits.is_empty() {
        return Err(not_a_number());
    }
    let mag = u128::from_str_radix(digits, radix).map_err(|_| not_a_number())?;
    let v = if neg { -(mag as i128) } else { mag as i128 };
    let (lo, hi) = if bits == 32 {
        (i32::MIN as i128, i32::MAX as i128)
    } else {
        (i64::MIN as i128, i64::MAX as i128)
    };
    if v < lo || v > hi {
        return Err(HalError::NumberOutOfRange {
            text: s.to_string(),
        });
    }
    Ok(v as i64)
}

/// A loadable module.
pub struct ModuleDef {
    /// The name `loadrt` uses (`and2`, `threads`, `hal_parport`, ...).
    pub name: &'static str,
    /// Its module parameters.
    pub params: &'static [ParamDecl],
    /// A one-line description.
    pub help: &'static str,
    /// Creates the module's components (and threads) in the host. On an
    /// error the host removes whatever it created.
    pub load: fn(&Host, &ModuleArgs) -> Result<()>,
}

impl std::fmt::Debug for ModuleDef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ModuleDef")
            .field("name", &self.name)
            .finish()
    }
}

/// The modules a host binary offers.
#[derive(Debug, Default, Clone)]
pub struct Registry {
    defs: Vec<&'static ModuleDef>,
}

impl Registry {
    /// An empty registry.
    pub fn new() -> Registry {
        Registry::default()
    }

    /// Adds modules; a later module with the same name replaces an earlier.
    pub fn add(&mut self, defs: &[&'static ModuleDef]) -> &mut Self {
        for d in defs {
            self.defs.retain(|e| e.name != d.name);
            self.defs.push(d);
        }
        self
    }

    /// Finds a module by its `loadrt` name.
    pub fn find(&self, name: &str) -> Option<&'static ModuleDef> {
        self.defs.iter().copied().find(|d| d.name == name)
    }

    /// All module names, sorted.
    pub fn names(&self) -> Vec<&'static str> {
        let mut v: Vec<_> = self.defs.iter().map(|d| d.name).collect();
        v.sort_unstable();
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DECLS: &[ParamDecl] = &[
        ParamDecl {
            name: "count",
            kind: ParamKind::Int,
            help: "",
        },
        ParamDecl {
            name: "period1",
            kind: ParamKind::Long,
            help: "",
        },
        ParamDecl {
            name: "names",
            kind: ParamKind::Str,
            help: "",
        },
        ParamDecl {
            name: "depth",
            kind: ParamKind::IntArray(8),
            help: "",
        },
        ParamDecl {
            name: "cfg",
            kind: ParamKind::StrArray(2),
            help: "",
        },
    ];

    fn parse(args: &[&str]) -> Result<ModuleArgs> {
        ModuleArgs::parse("m", DECLS, args)
    }

    #[test]
    fn parses_like_linuxcnc() {
        let a = parse(&[
            "count=0x10",
            "period1=25000",
            "names=\"a,b\"",
            "depth=1,,017",
            "cfg=ff,",
        ])
        .unwrap();
        assert_eq!(a.int("count"), Some(16));
        assert_eq!(a.int("period1"), Some(25000));
        assert_eq!(a.str("names"), Some("a,b"));
        assert_eq!(a.int_array("depth"), &[1, 0, 15]);
        assert_eq!(a.str_array("cfg"), &["ff".to_string(), String::new()]);
        assert_eq!(
            a.raw(),
            "count=0x10 period1=25000 names=a,b depth=1,,017 cfg=ff,"
        );
        assert_eq!(a.int("missing"), None);
    }

    #[test]
    fn rejects_bad_arguments_naming_the_parameter() {
        for (args, param, reason) in [
            (&["count"][..], "count", "expected count=VALUE: "),
            (&["7"][..], "7", "expected name=value"),
            (&["bogus=1"][..], "bogus", "unknown parameter"),
            (&["count=12x"][..], "count", "not a number"),
            (&["count=2147483648"][..], "count", "out of range"),
            (&["cfg=a,b,c"][..], "cfg", "can only take 2 arguments"),
            (&["depth=1,2,3,4,5,6,7,8,9"][..], "depth", "can only take 8"),
        ] {
            match parse(args) {
                Err(HalError::ModuleParam {
                    param: p,
                    reason: r,
                    ..
                }) => {
                    assert_eq!(p, param);
                    assert!(r.contains(reason), "{r}");
                }
                other => panic!("{args:?}: {other:?}"),
            }
        }
        assert_eq!(parse_c_int("-0x1f", 32).ok(), Some(-31));
        assert_eq!(parse_c_int("0", 32).ok(), Some(0));
        assert_eq!(parse_c_int("9223372036854775807", 64).ok(), Some(i64::MAX));
        assert!(parse_c_int("", 32).is_err());
        assert!(parse_c_int("08", 32).is_err());
    }
}
