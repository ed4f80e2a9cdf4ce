//! `mux_generic`: a multiplexer whose input and output types and number
//! of inputs are chosen per instance by a format string
//! (`loadrt mux_generic config="ff4,bs2,su8"`).

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, HalType, Host, In, Out, Pin, RawPin, Result, Ro, Value};

use crate::cmath::{f64_to_i32, f64_to_u32};
use crate::convert::c_convert;
use crate::error::CompError;

/// Most instances one load creates (entries of `config`).
pub const MAX_INSTANCES: usize = 100;
/// Most inputs one instance may have; a larger number is capped to it.
pub const MAX_SIZE: u32 = 1024;

const PARAMS: &[ParamDecl] = &[ParamDecl {
    name: "config",
    kind: ParamKind::StrArray(MAX_INSTANCES),
    help: "format of each instance: input type, number of inputs, output type (e.g. ff4,bs2)",
}];

/// The `mux_generic` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "mux_generic",
    params: PARAMS,
    help: "multiplexer with selectable input and output types",
    load,
};

/// One instance's parsed format string.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// Number of data inputs (2..=1024).
    pub size: u32,
    /// Type of the data inputs.
    pub in_type: HalType,
    /// Type of the output.
    pub out_type: HalType,
}

fn type_letter(c: char) -> Option<HalType> {
    match c.to_ascii_lowercase() {
        'b' => Some(HalType::Bit),
        'f' => Some(HalType::Float),
        's' => Some(HalType::S32),
        'u' => Some(HalType::U32),
        _ => None,
    }
}

impl Config {
    /// Parses a format string: decimal digits anywhere make up the number
    /// of inputs (left to right, capped at 1024); the first type letter
    /// is the input type, an optional second one the output type.
    pub fn parse(s: &str) -> std::result::Result<Config, CompError> {
        let format = || s.to_string();
        let mut size: u32 = 0;
        let mut types: Vec<HalType> = Vec::with_capacity(2);
        for c in s.chars() {
            if let Some(d) = c.to_digit(10) {
                size = (size * 10 + d).min(MAX_SIZE);
            } else if let Some(t) = type_letter(c) {
                if types.len() == 2 {
                    return Err(CompError::MuxTypes { format: format() });
                }
                types.push(t);
            } else {
                return Err(CompError::MuxLetter {
                    format: format(),
                    letter: c,
                });
            }
        }
        let Some(&in_type) = types.first() else {
            return Err(CompError::MuxNoType { format: format() });
        };
        if size < 2 {
            return Err(CompError::MuxTooSmall {
                format: format(),
                size,
            });
        }
        Ok(Config {
            size,
            in_type,
            out_type: types.get(1).copied().unwrap_or(in_type),
        })
    }

    /// How many `sel-bit` pins the instance has: k when the size is 2^k or
    /// 2^k + 1, none otherwise.
    pub fn select_bits(&self) -> u32 {
        let n = self.size;
        if n.is_power_of_two() {
            n.trailing_zeros()
        } else if (n - 1).is_power_of_two() {
            (n - 1).trailing_zeros()
        } else {
            0
        }
    }
}

/// Converts a selected input value to the output type. Where mux_generic
/// differs from a C cast it says so: a float is TRUE beyond +-2e-7, float
/// to s32/u32 saturates (NaN gives C's value), and s32/u32 clamp to each
/// other's range; everything else is the C conversion.
pub fn convert(v: Value, to: HalType) -> Value {
    match (v, to) {
        (Value::Float(f), HalType::Bit) => Value::Bit(f.abs() > 2e-7),
        (Value::Float(f), HalType::S32) => Value::S32(if f > 2147483647.0 {
            i32::MAX
        } else if f < -2147483648.0 {
            i32::MIN
        } else {
            // NaN ends here and gives C's i32::MIN.
            f64_to_i32(f)
        }),
        (Value::Float(f), HalType::U32) => Value::U32(if f > 4294967295.0 {
            u32::MAX
        } else if f < 0.0 {
            0
        } else {
            f64_to_u32(f)
        }),
        (Value::S32(x), HalType::U32) => Value::U32(x.max(0) as u32),
        (Value::U32(x), HalType::S32) => Value::S32(x.min(i32::MAX as u32) as i32),
        (v, to) => c_convert(v, to),
    }
}

/// The debounce and selection state kept in the `selected` and `elapsed`
/// params.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Selection {
    /// The selection in use (before clamping to the last input).
    pub selected: u32,
    /// Microseconds spent waiting with a different selection pending.
    pub elapsed: u32,
}

impl Selection {
    /// One call: `sel` is the sum of the select bits and `sel-int`. Returns
    /// the input to output, or `None` when the output stays (suppressed,
    /// or a new selection still debouncing).
    pub fn update(
        &mut self,
        sel: u32,
        suppress_no_input: bool,
        debounce_us: u32,
        period_ns: i64,
        size: u32,
    ) -> Option<usize> {
        if suppress_no_input && sel == 0 {
            return None;
        }
        if sel != self.selected && self.elapsed < debounce_us {
            self.elapsed = self.elapsed.wrapping_add((period_ns / 1000) as u32);
            return None;
        }
        self.selected = sel;
        self.elapsed = 0;
        // LinuxCNC compares signed and reads out of bounds from 2^31 up;
        // the unsigned clamp keeps every selection in range.
        Some(sel.min(size - 1) as usize)
    }
}

/// The select value from the select bits and `sel-int` (u32, wrapping).
pub fn select_value(bits: impl IntoIterator<Item = bool>, sel_int: u32) -> u32 {
    super::bits_value(bits).wrapping_add(sel_int)
}

/// One instance's handles.
struct Instance {
    cfg: Config,
    sel_bits: Vec<Pin<bool, In>>,
    sel_int: Pin<u32, In>,
    inputs: Vec<RawPin<In>>,
    suppress: Pin<bool, In>,
    debounce_us: Pin<u32, In>,
    elapsed: hal_core::Param<u32, Ro>,
    selected: hal_core::Param<u32, Ro>,
    out: RawPin<Out>,
}

/// The formats of a `config=` array (mux_generic's and demux_generic's),
/// one per instance; `module` and `example` go into the errors.
pub fn parse_configs(module: &str, example: &str, args: &ModuleArgs) -> Result<Vec<Config>> {
    let bad = |reason: String| HalError::ModuleParam {
        module: module.into(),
        param: "config".into(),
        reason,
    };
    let config = args.str_array("config");
    if config.is_empty() {
        return Err(bad(format!(
            "missing: give one format per instance, e.g. config=\"{example}\""
        )));
    }
    config
        .iter()
        .enumerate()
        .map(|(i, s)| Config::parse(s).map_err(|e| bad(format!("instance {i}: {e}"))))
        .collect()
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let cfgs = parse_configs(MODULE.name, "ff4,bs2", args)?;
    let mut b = host.new_rt_component(MODULE.name)?;
    for (n, cfg) in cfgs.into_iter().enumerate() {
        let prefix = format!("mux-gen.{n:02}");
        let (tin, tout) = (cfg.in_type.name(), cfg.out_type.name());
        let c = b.component();
        let inst = Instance {
            cfg,
            sel_bits: (0..cfg.select_bits())
                .map(|i| c.pin(&format!("{prefix}.sel-bit-{i:02}")))
                .collect::<Result<_>>()?,
            sel_int: c.pin(&format!("{prefix}.sel-int"))?,
            inputs: (0..cfg.size)
                .map(|i| c.pin_raw(&format!("{prefix}.in-{tin}-{i:02}"), cfg.in_type))
                .collect::<Result<_>>()?,
            suppress: c.pin(&format!("{prefix}.suppress-no-input"))?,
            debounce_us: c.pin(&format!("{prefix}.debounce-us"))?,
            elapsed: c.param(&format!("{prefix}.elapsed"), 0)?,
            selected: c.param(&format!("{prefix}.selected"), 0)?,
            out: c.pin_raw(&format!("{prefix}.out-{tout}"), cfg.out_type)?,
        };
        b.funct(&prefix, true, move |ctx| {
            let s = select_value(inst.sel_bits.iter().map(Pin::get), inst.sel_int.get());
            let mut st = Selection {
                selected: inst.selected.get(),
                elapsed: inst.elapsed.get(),
            };
            let pick = st.update(
                s,
                inst.suppress.get(),
                inst.debounce_us.get(),
                ctx.period(),
                inst.cfg.size,
            );
            inst.selected.set(st.selected);
            inst.elapsed.set(st.elapsed);
            if let Some(k) = pick {
                let v = inst.inputs[k].value();
                inst.out.set_bits(convert(v, inst.cfg.out_type).to_bits());
            }
        })?;
    }
    b.ready()
}
