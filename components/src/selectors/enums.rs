//! `enum`: converts between an enumerated value and one bit per value.
//! Each instance is described by a `;`-separated list: `D` (decode: a
//! u32 `input` sets the matching `<name>-out` bit) or `E` (encode: the
//! set `<name>-in` bit puts its value on the u32 `output`), then the
//! value names. Values count from 0 up; an empty entry (`;;`) skips a
//! value. Each name also gets a `<name>-val` pin holding its value.
//!
//! `loadrt enum enums=D;stop;run;;fault,E;low;high names=state,level`
//! (names optional: `enum-decode.NN` / `enum-encode.NN` otherwise).

use crate::error::CompError;
use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, In, Out, Pin, Result};

/// Most instances.
pub const MAX_CHAN: usize = 256;

/// One instance's description.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EnumSpec {
    /// TRUE to encode (bits in, value out), FALSE to decode.
    pub encode: bool,
    /// Each named value with its number.
    pub values: Vec<(String, u32)>,
}

impl EnumSpec {
    /// Parses `D;a;b;;c` or `E;...`.
    pub fn parse(s: &str) -> std::result::Result<EnumSpec, CompError> {
        let mut parts = s.split(';');
        let encode = match parts.next().and_then(|m| m.chars().next()) {
            Some('E' | 'e') => true,
            Some('D' | 'd') => false,
            _ => {
                return Err(CompError::EnumMode {
                    spec: s.to_string(),
                })
            }
        };
        let mut values = Vec::new();
        let mut v = 0u32;
        let mut pending_skip = 0u32;
        let mut rest: Vec<&str> = parts.collect();
        if rest.last() == Some(&"") {
            return Err(CompError::EnumTrailingSemicolon {
                spec: s.to_string(),
            });
        }
        for name in rest.drain(..) {
            if name.is_empty() {
                pending_skip += 1;
            } else {
                v += pending_skip;
                pending_skip = 0;
                values.push((name.to_string(), v));
                v += 1;
            }
        }
        Ok(EnumSpec { encode, values })
    }
}

/// The decoded bits for `input`.
pub fn decode(input: u32, values: impl Iterator<Item = u32>) -> impl Iterator<Item = bool> {
    values.map(move |v| v == input)
}

/// The encoded value: the value of the last set bit, 0 when none.
pub fn encode(bits: impl Iterator<Item = (bool, u32)>) -> u32 {
    bits.filter(|&(b, _)| b).last().map_or(0, |(_, v)| v)
}

/// The module parameters.
pub const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "enums",
        kind: ParamKind::StrArray(MAX_CHAN),
        help: "states of each instance, ; delimited, starting with E (encode) or D (decode)",
    },
    ParamDecl {
        name: "names",
        kind: ParamKind::StrArray(MAX_CHAN),
        help: "instance names (optional)",
    },
];

/// The `enum` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "enum",
    params: PARAMS,
    help: "enumerate integer values into bits",
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let bad = |param: &str, reason: String| HalError::ModuleParam {
        module: "enum".into(),
        param: param.into(),
        reason,
    };
    let enums = args.str_array("enums");
    let names = args.str_array("names");
    if enums.is_empty() {
        return Err(bad(
            "enums",
            "at least one enumeration list is required".into(),
        ));
    }
    if !names.is_empty() && names.len() != enums.len() {
        return Err(bad(
            "names",
            format!("{} names for {} enumerations", names.len(), enums.len()),
        ));
    }
    let specs: Vec<EnumSpec> = enums
        .iter()
        .map(|e| EnumSpec::parse(e).map_err(|r| bad("enums", r.to_string())))
        .collect::<Result<_>>()?;
    let mut b = host.new_rt_component("enum")?;
    for (i, spec) in specs.into_iter().enumerate() {
        let this = match names.get(i) {
            Some(n) if !n.is_empty() => n.clone(),
            Some(_) => return Err(bad("names", format!("name {i} is empty"))),
            None if spec.encode => format!("enum-encode.{i:02}"),
            None => format!("enum-decode.{i:02}"),
        };
        let c = b.component();
        let mut vals: Vec<Pin<u32, In>> = Vec::with_capacity(spec.values.len());
        if spec.encode {
            let output: Pin<u32, Out> = c.pin(&format!("{this}.output"))?;
            let mut bits: Vec<Pin<bool, In>> = Vec::with_capacity(spec.values.len());
            for (name, v) in &spec.values {
                bits.push(c.pin(&format!("{this}.{name}-in"))?);
                vals.push(c.pin_init(&format!("{this}.{name}-val"), *v)?);
            }
            b.funct(&format!("{this}.encode"), false, move |_| {
                output.set(encode(
                    bits.iter().zip(&vals).map(|(b, v)| (b.get(), v.get())),
                ))
            })?;
        } else {
            let input: Pin<u32, In> = c.pin(&format!("{this}.input"))?;
            let mut bits: Vec<Pin<bool, Out>> = Vec::with_capacity(spec.values.len());
            for (name, v) in &spec.values {
                bits.push(c.pin(&format!("{this}.{name}-out"))?);
                vals.push(c.pin_init(&format!("{this}.{name}-val"), *v)?);
            }
            b.funct(&format!("{this}.decode"), false, move |_| {
                let on = decode(input.get(), vals.iter().map(Pin::get));
                for (bit, on) in bits.iter().zip(on) {
                    bit.set(on);
                }
            })?;
        }
    }
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, U32};

    #[test]
    fn parsing_counts_values_and_skips() {
        let s = EnumSpec::parse("D;stop;run;;fault").unwrap();
        assert!(!s.encode);
        assert_eq!(
            s.values,
            [("stop".into(), 0), ("run".into(), 1), ("fault".into(), 3)]
        );
        let s = EnumSpec::parse("e;;;x").unwrap();
        assert!(s.encode);
        assert_eq!(s.values, [("x".into(), 2)]);
        assert!(EnumSpec::parse("X;a").is_err());
        assert!(EnumSpec::parse("D;a;").is_err());
        assert_eq!(EnumSpec::parse("D").unwrap().values, []);
    }

    #[test]
    fn encode_takes_the_last_set_bit() {
        assert_eq!(encode([(true, 1), (false, 2), (true, 5)].into_iter()), 5);
        assert_eq!(encode([(false, 1)].into_iter()), 0);
        let d: Vec<bool> = decode(2, [1, 2, 3].into_iter()).collect();
        assert_eq!(d, [false, true, false]);
    }

    #[test]
    fn pins_functions_and_a_run() {
        let mut h = TestHost::new("enum");
        for bad in [&[][..], &["enums=Q;a"], &["enums=D;a,E;b", "names=x"]] {
            h.check_load_fails(&MODULE, bad);
        }
        h.load(&MODULE, &["enums=D;stop;;run,E;lo;hi"]).unwrap();
        h.check_pins(
            "enum-decode.00",
            &[
                "input u32 in 0",
                "stop-out bit out 0",
                "stop-val u32 in 0",
                "run-out bit out 0",
                "run-val u32 in 2",
            ],
        );
        h.check_pins(
            "enum-encode.01",
            &[
                "output u32 out 0",
                "lo-in bit in 0",
                "lo-val u32 in 0",
                "hi-in bit in 0",
                "hi-val u32 in 1",
            ],
        );
        assert_eq!(
            h.functs(),
            ["enum-decode.00.decode", "enum-encode.01.encode"]
        );
        h.thread(&["enum-decode.00.decode", "enum-encode.01.encode"]);
        h.expect(&[], "enum-decode.00.stop-out", Bit(true));
        h.expect(
            &[("enum-decode.00.input", U32(2))],
            "enum-decode.00.run-out",
            Bit(true),
        );
        h.expect(
            &[("enum-encode.01.hi-in", Bit(true))],
            "enum-encode.01.output",
            U32(1),
        );
    }
}
