//! `bldc`: commutation for brushless DC motors and AC servos. Each
//! instance turns one kind of rotor feedback (none, Hall sensors, Fanuc
//! Gray code, absolute or incremental encoder) into one kind of drive
//! output (three bipolar values, six high/low values, gate bits, emulated
//! Hall or Gray signals), sinusoidal when the feedback allows it.
//!
//! `loadrt bldc cfg=qi6,aH` makes one instance per comma-separated
//! entry; each letter of an entry sets a personality bit (see
//! [`control`]): inputs `n` (none), `h`, `a`, `q`, `i`, `f`; outputs `B`,
//! `6`, `H`, `F`; `T` forces trapezoidal commutation.

pub mod control;
pub mod tables;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, In, Out, Param, Pin, Result, Ro, Rw};

use crate::error::CompError;
use crate::halcomp::{hal_name, load_instances, personality_of, Inst};
use crate::notice::Notice;
use control::*;

/// Most instances one load may create.
pub const MAX_CHAN: usize = 8;

/// bldc's module parameters.
pub const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "cfg",
        kind: ParamKind::StrArray(MAX_CHAN),
        help: "description of each motor: input letters n h a q i f, output letters B 6 H F T",
    },
    crate::halcomp::PERSONALITY,
];

/// The `bldc` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "bldc",
    params: PARAMS,
    help: "BLDC and AC-servo control",
    load,
};

/// The personality bits one `cfg` entry sets.
pub fn cfg_bits(cfg: &str) -> std::result::Result<u32, CompError> {
    if cfg.is_empty() {
        return Err(CompError::EmptyBldcEntry);
    }
    cfg.chars().try_fold(0, |bits, c| {
        Ok(bits
            | match c {
                'n' => 0,
                'h' => HALL,
                'a' => ABSOLUTE,
                'q' => QUADRATURE,
                'i' => INDEX,
                'f' => FANUC,
                'B' => BITS_OUT,
                '6' => SIX,
                'H' => HALL_OUT,
                'F' => FANUC_OUT,
                'T' => TRAPEZOIDAL,
                _ => {
                    return Err(CompError::BadBldcLetter {
                        letter: c,
                        entry: cfg.to_string(),
                    })
                }
            })
    })
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let cfg = args.str_array("cfg");
    if cfg.is_empty() {
        return Err(HalError::ModuleLoad {
            module: "bldc".into(),
            reason: "cfg= is required: one entry of feedback and output letters per motor".into(),
        });
    }
    let base = hal_name(MODULE.name);
    let instances = cfg
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let bits = cfg_bits(c).map_err(|e| HalError::ModuleParam {
                module: "bldc".into(),
                param: "cfg".into(),
                reason: e.to_string(),
            })?;
            let given = personality_of(args, i, 0) as u32;
            Ok((format!("{base}.{i}"), i64::from(given | bits)))
        })
        .collect::<Result<Vec<_>>>()?;
    load_instances(host, MODULE.name, instances, |inst, _| build(inst))
}

/// An input pin that exists when `cond`.
fn pin_in_if<T: hal_core::PinValue>(
    inst: &mut Inst<'_, '_>,
    cond: bool,
    item: &str,
    init: T,
) -> Result<Option<Pin<T, In>>> {
    cond.then(|| inst.pin_in_init(item, init)).transpose()
}

/// An output pin that exists when `cond`.
fn pin_out_if<T: hal_core::PinValue>(
    inst: &mut Inst<'_, '_>,
    cond: bool,
    item: &str,
) -> Result<Option<Pin<T, Out>>> {
    cond.then(|| inst.pin_out(item)).transpose()
}

/// Three (or four) output pins named after the phases that exist when
/// `cond`.
fn outs_if<T: hal_core::PinValue, const N: usize>(
    inst: &mut Inst<'_, '_>,
    cond: bool,
    names: [&str; N],
) -> Result<Option<[Pin<T, Out>; N]>> {
    if !cond {
        return Ok(None);
    }
    let v = names
        .iter()
        .map(|n| inst.pin_out(n))
        .collect::<Result<Vec<_>>>()?;
    Ok(v.try_into().ok())
}

fn get<T: hal_core::PinValue, D: hal_core::handles::Direction>(p: &Option<Pin<T, D>>, d: T) -> T {
    p.as_ref().map_or(d, Pin::get)
}

fn set<T: hal_core::PinValue + PartialEq, D: hal_core::handles::Writable>(
    p: &Option<Pin<T, D>>,
    old: T,
    new: T,
) {
    if let Some(p) = p {
        if old != new {
            p.set(new);
        }
    }
}

fn set_all<T: hal_core::PinValue + PartialEq, const N: usize>(
    p: &Option<[Pin<T, Out>; N]>,
    old: [T; N],
    new: [T; N],
) {
    if let Some(p) = p {
        for k in 0..N {
            if old[k] != new[k] {
                p[k].set(new[k]);
            }
        }
    }
}

fn param_get<T: hal_core::PinValue, A: hal_core::handles::ParamAccess>(
    p: &Option<Param<T, A>>,
    d: T,
) -> T {
    p.as_ref().map_or(d, Param::get)
}

fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
    let p = inst.personality as u32;
    let hall_in = p & HALL != 0;
    let fanuc_in = p & FANUC != 0;
    let encoder = p & (ABSOLUTE | QUADRATURE) != 0;
    let homing_pins = p & (HALL | QUADRATURE) == QUADRATURE;
    let out_kind = p & 0xf00;

    let hall: [Option<Pin<bool, In>>; 3] = [
        pin_in_if(inst, hall_in, "hall1", false)?,
        pin_in_if(inst, hall_in, "hall2", false)?,
        pin_in_if(inst, hall_in, "hall3", false)?,
    ];
    let hall_error = pin_out_if::<bool>(inst, hall_in, "hall-error")?;
    let fanuc: [Option<Pin<bool, In>>; 4] = [
        pin_in_if(inst, fanuc_in, "C1", false)?,
        pin_in_if(inst, fanuc_in, "C2", false)?,
        pin_in_if(inst, fanuc_in, "C4", false)?,
        pin_in_if(inst, fanuc_in, "C8", false)?,
    ];
    let value = inst.pin_in::<f64>("value")?;
    let lead_angle = pin_in_if(inst, encoder, "lead-angle", 90.0)?;
    let rev = inst.pin_in::<bool>("rev")?;
    let frequency = pin_in_if(inst, p & 0x0f == 0, "frequency", 0.0)?;
    let initvalue = pin_in_if(inst, p & QUADRATURE != 0, "initvalue", 0.2)?;
    let rawcounts = pin_in_if(inst, encoder, "rawcounts", 0i32)?;
    let index_enable = if p & INDEX != 0 {
        Some(inst.pin_io::<bool>("index-enable", false)?)
    } else {
        None
    };
    let init = pin_in_if(inst, homing_pins, "init", false)?;
    let init_done = pin_out_if::<bool>(inst, homing_pins, "init-done")?;
    let values = outs_if::<f64, 3>(inst, out_kind == 0, ["A-value", "B-value", "C-value"])?;
    let on = outs_if::<bool, 3>(inst, out_kind == 0x100, ["A-on", "B-on", "C-on"])?;
    let high = outs_if::<f64, 3>(inst, out_kind == 0x200, ["A-high", "B-high", "C-high"])?;
    let low = outs_if::<f64, 3>(inst, out_kind == 0x200, ["A-low", "B-low", "C-low"])?;
    let high_on = outs_if::<bool, 3>(
        inst,
        out_kind == 0x300,
        ["A-high-on", "B-high-on", "C-high-on"],
    )?;
    let low_on = outs_if::<bool, 3>(
        inst,
        out_kind == 0x300,
        ["A-low-on", "B-low-on", "C-low-on"],
    )?;
    let hall_out = outs_if::<bool, 3>(
        inst,
        p & HALL_OUT != 0,
        ["hall1-out", "hall2-out", "hall3-out"],
    )?;
    let fanuc_out = outs_if::<bool, 4>(
        inst,
        p & FANUC_OUT != 0,
        ["C1-out", "C2-out", "C4-out", "C8-out"],
    )?;
    let phase_angle = inst.pin_out::<f64>("phase-angle")?;
    let rotor_angle = inst.pin_out::<f64>("rotor-angle")?;
    let out = inst.pin_out::<f64>("out")?;
    let out_dir = inst.pin_out::<bool>("out-dir")?;
    let out_abs = inst.pin_out::<f64>("out-abs")?;

    let in_type = inst.param_ro::<i32>("in-type", -1)?;
    let out_type = inst.param_ro::<i32>("out-type", -1)?;
    let scale: Option<Param<i32, Rw>> = encoder.then(|| inst.param_rw("scale", 512)).transpose()?;
    let poles: Option<Param<i32, Rw>> = encoder.then(|| inst.param_rw("poles", 4)).transpose()?;
    let encoder_offset: Option<Param<i32, Rw>> = (p & (ABSOLUTE | INDEX) != 0)
        .then(|| inst.param_rw("encoder-offset", 0))
        .transpose()?;
    let offset_measured: Option<Param<i32, Ro>> = (p & QUADRATURE != 0)
        .then(|| inst.param_ro("offset-measured", 0))
        .transpose()?;
    let drive_offset = inst.param_rw::<f64>("drive-offset", 0.0)?;
    let output_pattern: Option<Param<u32, Rw>> = (p & HALL_OUT != 0)
        .then(|| inst.param_rw("output-pattern", 25))
        .transpose()?;
    let pattern: Option<Param<u32, Rw>> =
        hall_in.then(|| inst.param_rw("pattern", 25)).transpose()?;

    let notice = Notice::new(TEXTS);
    let mut bldc = Bldc::new(p);
    inst.funct("_", true, move |ctx| {
        let old = BldcVars {
            hall: std::array::from_fn(|k| get(&hall[k], false)),
            fanuc: std::array::from_fn(|k| get(&fanuc[k], false)),
            value: value.get(),
            lead_angle: get(&lead_angle, 0.0),
            rev: rev.get(),
            frequency: get(&frequency, 0.0),
            initvalue: get(&initvalue, 0.0),
            rawcounts: get(&rawcounts, 0),
            init: get(&init, false),
            scale: param_get(&scale, 0),
            poles: param_get(&poles, 0),
            encoder_offset: param_get(&encoder_offset, 0),
            drive_offset: drive_offset.get(),
            output_pattern: param_get(&output_pattern, 0),
            index_enable: get(&index_enable, false),
            pattern: param_get(&pattern, 0),
            init_done: get(&init_done, false),
            in_type: in_type.get(),
            out_type: out_type.get(),
            offset_measured: param_get(&offset_measured, 0),
            phase_angle: phase_angle.get(),
            rotor_angle: rotor_angle.get(),
            hall_error: get(&hall_error, false),
            value_out: match (&values, &high) {
                (Some(v), _) | (None, Some(v)) => std::array::from_fn(|k| v[k].get()),
                _ => [0.0; 3],
            },
            on: on
                .as_ref()
                .map_or([false; 3], |v| std::array::from_fn(|k| v[k].get())),
            low: low
                .as_ref()
                .map_or([0.0; 3], |v| std::array::from_fn(|k| v[k].get())),
            high_on: high_on
                .as_ref()
                .map_or([false; 3], |v| std::array::from_fn(|k| v[k].get())),
            low_on: low_on
                .as_ref()
                .map_or([false; 3], |v| std::array::from_fn(|k| v[k].get())),
            hall_out: hall_out
                .as_ref()
                .map_or([false; 3], |v| std::array::from_fn(|k| v[k].get())),
            fanuc_out: fanuc_out
                .as_ref()
                .map_or([false; 4], |v| std::array::from_fn(|k| v[k].get())),
            out: out.get(),
            out_dir: out_dir.get(),
            out_abs: out_abs.get(),
        };
        let mut v = old;
        if let Some(m) = bldc.step(&mut v, ctx.period()) {
            notice.post(m as usize);
        }
        set(&hall_error, old.hall_error, v.hall_error);
        set(&index_enable, old.index_enable, v.index_enable);
        set(&init_done, old.init_done, v.init_done);
        if let Some(pat) = &pattern {
            if old.pattern != v.pattern {
                pat.set(v.pattern);
            }
        }
        if let Some(o) = &offset_measured {
            if old.offset_measured != v.offset_measured {
                o.set(v.offset_measured);
            }
        }
        if old.in_type != v.in_type {
            in_type.set(v.in_type);
        }
        if old.out_type != v.out_type {
            out_type.set(v.out_type);
        }
        set_all(&values, old.value_out, v.value_out);
        set_all(&high, old.value_out, v.value_out);
        set_all(&low, old.low, v.low);
        set_all(&on, old.on, v.on);
        set_all(&high_on, old.high_on, v.high_on);
        set_all(&low_on, old.low_on, v.low_on);
        set_all(&hall_out, old.hall_out, v.hall_out);
        set_all(&fanuc_out, old.fanuc_out, v.fanuc_out);
        if old.phase_angle != v.phase_angle {
            phase_angle.set(v.phase_angle);
        }
        if old.rotor_angle != v.rotor_angle {
            rotor_angle.set(v.rotor_angle);
        }
        if old.out != v.out {
            out.set(v.out);
        }
        if old.out_dir != v.out_dir {
            out_dir.set(v.out_dir);
        }
        if old.out_abs != v.out_abs {
            out_abs.set(v.out_abs);
        }
    })
}

#[cfg(test)]
mod tests;
