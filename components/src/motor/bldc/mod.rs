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
use hal_core::{HalError, Host, In, Io, Out, Param, Pin, Result, Ro, Rw};

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

/// The pins and parameters of one bldc instance; which exist depends on
/// the personality.
struct BldcPins {
    hall: [Option<Pin<bool, In>>; 3],
    hall_error: Option<Pin<bool, Out>>,
    fanuc: [Option<Pin<bool, In>>; 4],
    value: Pin<f64, In>,
    lead_angle: Option<Pin<f64, In>>,
    rev: Pin<bool, In>,
    frequency: Option<Pin<f64, In>>,
    initvalue: Option<Pin<f64, In>>,
    rawcounts: Option<Pin<i32, In>>,
    index_enable: Option<Pin<bool, Io>>,
    init: Option<Pin<bool, In>>,
    init_done: Option<Pin<bool, Out>>,
    values: Option<[Pin<f64, Out>; 3]>,
    on: Option<[Pin<bool, Out>; 3]>,
    high: Option<[Pin<f64, Out>; 3]>,
    low: Option<[Pin<f64, Out>; 3]>,
    high_on: Option<[Pin<bool, Out>; 3]>,
    low_on: Option<[Pin<bool, Out>; 3]>,
    hall_out: Option<[Pin<bool, Out>; 3]>,
    fanuc_out: Option<[Pin<bool, Out>; 4]>,
    phase_angle: Pin<f64, Out>,
    rotor_angle: Pin<f64, Out>,
    out: Pin<f64, Out>,
    out_dir: Pin<bool, Out>,
    out_abs: Pin<f64, Out>,
    in_type: Param<i32, Ro>,
    out_type: Param<i32, Ro>,
    scale: Option<Param<i32, Rw>>,
    poles: Option<Param<i32, Rw>>,
    encoder_offset: Option<Param<i32, Rw>>,
    offset_measured: Option<Param<i32, Ro>>,
    drive_offset: Param<f64, Rw>,
    output_pattern: Option<Param<u32, Rw>>,
    pattern: Option<Param<u32, Rw>>,
}

impl BldcPins {
    /// Exports the pins and parameters personality `p` asks for.
    fn export(inst: &mut Inst<'_, '_>, p: u32) -> Result<BldcPins> {
        let hall_in = p & HALL != 0;
        let fanuc_in = p & FANUC != 0;
        let encoder = p & (ABSOLUTE | QUADRATURE) != 0;
        let homing_pins = p & (HALL | QUADRATURE) == QUADRATURE;
        let out_kind = p & 0xf00;
        Ok(BldcPins {
            hall: [
                pin_in_if(inst, hall_in, "hall1", false)?,
                pin_in_if(inst, hall_in, "hall2", false)?,
                pin_in_if(inst, hall_in, "hall3", false)?,
            ],
            hall_error: pin_out_if::<bool>(inst, hall_in, "hall-error")?,
            fanuc: [
                pin_in_if(inst, fanuc_in, "C1", false)?,
                pin_in_if(inst, fanuc_in, "C2", false)?,
                pin_in_if(inst, fanuc_in, "C4", false)?,
                pin_in_if(inst, fanuc_in, "C8", false)?,
            ],
            value: inst.pin_in::<f64>("value")?,
            lead_angle: pin_in_if(inst, encoder, "lead-angle", 90.0)?,
            rev: inst.pin_in::<bool>("rev")?,
            frequency: pin_in_if(inst, p & 0x0f == 0, "frequency", 0.0)?,
            initvalue: pin_in_if(inst, p & QUADRATURE != 0, "initvalue", 0.2)?,
            rawcounts: pin_in_if(inst, encoder, "rawcounts", 0i32)?,
            index_enable: if p & INDEX != 0 {
                Some(inst.pin_io::<bool>("index-enable", false)?)
            } else {
                None
            },
            init: pin_in_if(inst, homing_pins, "init", false)?,
            init_done: pin_out_if::<bool>(inst, homing_pins, "init-done")?,
            values: outs_if::<f64, 3>(inst, out_kind == 0, ["A-value", "B-value", "C-value"])?,
            on: outs_if::<bool, 3>(inst, out_kind == 0x100, ["A-on", "B-on", "C-on"])?,
            high: outs_if::<f64, 3>(inst, out_kind == 0x200, ["A-high", "B-high", "C-high"])?,
            low: outs_if::<f64, 3>(inst, out_kind == 0x200, ["A-low", "B-low", "C-low"])?,
            high_on: outs_if::<bool, 3>(
                inst,
                out_kind == 0x300,
                ["A-high-on", "B-high-on", "C-high-on"],
            )?,
            low_on: outs_if::<bool, 3>(
                inst,
                out_kind == 0x300,
                ["A-low-on", "B-low-on", "C-low-on"],
            )?,
            hall_out: outs_if::<bool, 3>(
                inst,
                p & HALL_OUT != 0,
                ["hall1-out", "hall2-out", "hall3-out"],
            )?,
            fanuc_out: outs_if::<bool, 4>(
                inst,
                p & FANUC_OUT != 0,
                ["C1-out", "C2-out", "C4-out", "C8-out"],
            )?,
            phase_angle: inst.pin_out::<f64>("phase-angle")?,
            rotor_angle: inst.pin_out::<f64>("rotor-angle")?,
            out: inst.pin_out::<f64>("out")?,
            out_dir: inst.pin_out::<bool>("out-dir")?,
            out_abs: inst.pin_out::<f64>("out-abs")?,
            in_type: inst.param_ro::<i32>("in-type", -1)?,
            out_type: inst.param_ro::<i32>("out-type", -1)?,
            scale: encoder.then(|| inst.param_rw("scale", 512)).transpose()?,
            poles: encoder.then(|| inst.param_rw("poles", 4)).transpose()?,
            encoder_offset: (p & (ABSOLUTE | INDEX) != 0)
                .then(|| inst.param_rw("encoder-offset", 0))
                .transpose()?,
            offset_measured: (p & QUADRATURE != 0)
                .then(|| inst.param_ro("offset-measured", 0))
                .transpose()?,
            drive_offset: inst.param_rw::<f64>("drive-offset", 0.0)?,
            output_pattern: (p & HALL_OUT != 0)
                .then(|| inst.param_rw("output-pattern", 25))
                .transpose()?,
            pattern: hall_in.then(|| inst.param_rw("pattern", 25)).transpose()?,
        })
    }

    /// Everything the controller reads, in one snapshot.
    fn read(&self) -> BldcVars {
        BldcVars {
            hall: std::array::from_fn(|k| get(&self.hall[k], false)),
            fanuc: std::array::from_fn(|k| get(&self.fanuc[k], false)),
            value: self.value.get(),
            lead_angle: get(&self.lead_angle, 0.0),
            rev: self.rev.get(),
            frequency: get(&self.frequency, 0.0),
            initvalue: get(&self.initvalue, 0.0),
            rawcounts: get(&self.rawcounts, 0),
            init: get(&self.init, false),
            scale: param_get(&self.scale, 0),
            poles: param_get(&self.poles, 0),
            encoder_offset: param_get(&self.encoder_offset, 0),
            drive_offset: self.drive_offset.get(),
            output_pattern: param_get(&self.output_pattern, 0),
            index_enable: get(&self.index_enable, false),
            pattern: param_get(&self.pattern, 0),
            init_done: get(&self.init_done, false),
            in_type: self.in_type.get(),
            out_type: self.out_type.get(),
            offset_measured: param_get(&self.offset_measured, 0),
            phase_angle: self.phase_angle.get(),
            rotor_angle: self.rotor_angle.get(),
            hall_error: get(&self.hall_error, false),
            value_out: match (&self.values, &self.high) {
                (Some(v), _) | (None, Some(v)) => std::array::from_fn(|k| v[k].get()),
                _ => [0.0; 3],
            },
            on: read_all(&self.on, false),
            low: read_all(&self.low, 0.0),
            high_on: read_all(&self.high_on, false),
            low_on: read_all(&self.low_on, false),
            hall_out: read_all(&self.hall_out, false),
            fanuc_out: read_all(&self.fanuc_out, false),
            out: self.out.get(),
            out_dir: self.out_dir.get(),
            out_abs: self.out_abs.get(),
        }
    }

    /// Writes what the controller changed from `old` to `v`.
    fn write(&self, old: &BldcVars, v: &BldcVars) {
        set(&self.hall_error, old.hall_error, v.hall_error);
        set(&self.index_enable, old.index_enable, v.index_enable);
        set(&self.init_done, old.init_done, v.init_done);
        if let Some(pat) = &self.pattern {
            if old.pattern != v.pattern {
                pat.set(v.pattern);
            }
        }
        if let Some(o) = &self.offset_measured {
            if old.offset_measured != v.offset_measured {
                o.set(v.offset_measured);
            }
        }
        if old.in_type != v.in_type {
            self.in_type.set(v.in_type);
        }
        if old.out_type != v.out_type {
            self.out_type.set(v.out_type);
        }
        set_all(&self.values, old.value_out, v.value_out);
        set_all(&self.high, old.value_out, v.value_out);
        set_all(&self.low, old.low, v.low);
        set_all(&self.on, old.on, v.on);
        set_all(&self.high_on, old.high_on, v.high_on);
        set_all(&self.low_on, old.low_on, v.low_on);
        set_all(&self.hall_out, old.hall_out, v.hall_out);
        set_all(&self.fanuc_out, old.fanuc_out, v.fanuc_out);
        if old.phase_angle != v.phase_angle {
            self.phase_angle.set(v.phase_angle);
        }
        if old.rotor_angle != v.rotor_angle {
            self.rotor_angle.set(v.rotor_angle);
        }
        if old.out != v.out {
            self.out.set(v.out);
        }
        if old.out_dir != v.out_dir {
            self.out_dir.set(v.out_dir);
        }
        if old.out_abs != v.out_abs {
            self.out_abs.set(v.out_abs);
        }
    }
}

/// The values of optional output pins, `d` when they do not exist.
fn read_all<T: hal_core::PinValue, const N: usize>(p: &Option<[Pin<T, Out>; N]>, d: T) -> [T; N] {
    p.as_ref()
        .map_or([d; N], |v| std::array::from_fn(|k| v[k].get()))
}

fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
    let p = inst.personality as u32;
    let pins = BldcPins::export(inst, p)?;
    let notice = Notice::new(TEXTS);
    let mut bldc = Bldc::new(p);
    inst.funct("_", true, move |ctx| {
        let old = pins.read();
        let mut v = old;
        if let Some(m) = bldc.step(&mut v, ctx.period()) {
            notice.post(m as usize);
        }
        pins.write(&old, &v);
    })
}

#[cfg(test)]
mod tests;
