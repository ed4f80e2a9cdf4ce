//! `stepgen`: the software step-pulse generator. Up to 16 channels, each
//! in position or velocity mode, driving one of 16 waveforms (step/dir,
//! up/down, or a phase table).
//!
//! Three functions process every channel in channel order:
//! `stepgen.make-pulses` (integer DDS, fastest thread),
//! `stepgen.update-freq` (the velocity controller) and
//! `stepgen.capture-position` (feedback). The logic lives in host-free
//! structs ([`pulses`], [`freq`]) that [`model`] runs without a host (for
//! tests and benchmarks); this module is the HAL glue.
//!
//! Load: `loadrt stepgen step_type=T0,T1,... [ctrl_type=p|v,...]
//! [user_step_type=b0,b1,...]`.

pub mod freq;
pub mod model;
pub mod pulses;
pub mod steptype;

use std::sync::atomic::{AtomicI64, AtomicU64, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, In, Out, Param, Pin, PinValue, Result, Ro, Rw};

use crate::cmath::ScaleCache;
use freq::{FreqCtl, FreqParams, FreqTiming, INITIAL_PERIOD_NS, INITIAL_SCALE_CACHE};
use pulses::{Dds, PulseGen, PulseTiming};
use steptype::{phase_name, StepType, MAX_CYCLE};

/// Most channels one load creates.
pub const MAX_CHAN: usize = 16;

const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "step_type",
        kind: ParamKind::IntArray(MAX_CHAN),
        help: "stepping types for up to 16 channels (0-15)",
    },
    ParamDecl {
        name: "ctrl_type",
        kind: ParamKind::StrArray(MAX_CHAN),
        help: "control type (p = position, v = velocity) for up to 16 channels",
    },
    ParamDecl {
        name: "user_step_type",
        kind: ParamKind::IntArray(MAX_CYCLE),
        help: "phase patterns (5 bits each) of step type 15",
    },
];

/// The `stepgen` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "stepgen",
    params: PARAMS,
    help: "software step pulse generator, up to 16 channels",
    load,
};

/// Every module of this family.
pub fn modules() -> Vec<&'static ModuleDef> {
    vec![&MODULE]
}

/// One channel as the module parameters configure it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChannelConfig {
    /// The output waveform.
    pub step_type: StepType,
    /// Velocity mode (`velocity-cmd`) rather than position mode.
    pub velocity_mode: bool,
}

fn param_error(param: &str, reason: String) -> HalError {
    HalError::ModuleParam {
        module: "stepgen".into(),
        param: param.into(),
        reason,
    }
}

/// Works out the channels from the module parameters. `step_type` lists
/// one type per channel, ending at the first -1; `ctrl_type` gives each
/// channel's mode by its first letter (`p`/`P` or empty: position,
/// `v`/`V`: velocity); `user_step_type` is type 15's table, ending at the
/// first -1.
pub fn parse_config(args: &ModuleArgs) -> Result<Vec<ChannelConfig>> {
    let patterns: Vec<i64> = args
        .int_array("user_step_type")
        .iter()
        .copied()
        .take_while(|&v| v != -1)
        .collect();
    // Type 15's table, built once for every channel of that type. As in
    // LinuxCNC the patterns are checked even if no channel uses them; only
    // their absence waits for a type-15 channel to be an error.
    let user = if patterns.is_empty() {
        None
    } else {
        Some(StepType::user(&patterns).map_err(|r| param_error("user_step_type", r.to_string()))?)
    };
    let ctrl = args.str_array("ctrl_type");
    let mut chans = Vec::new();
    for (n, &t) in args.int_array("step_type").iter().enumerate() {
        if t == -1 {
            break;
        }
        let step_type = match t {
            0..=14 => StepType::builtin(t as u8),
            15 => Some(user.ok_or_else(|| {
                param_error(
                    "user_step_type",
                    format!("channel {n} has step type 15: give at least one pattern"),
                )
            })?),
            _ => None,
        }
        .ok_or_else(|| {
            param_error(
                "step_type",
                format!("bad stepping type {t} for channel {n} (must be 0-15)"),
            )
        })?;
        let velocity_mode = match ctrl.get(n).and_then(|s| s.chars().next()) {
            None | Some('p' | 'P') => false,
            Some('v' | 'V') => true,
            Some(_) => {
                return Err(param_error(
                    "ctrl_type",
                    format!(
                        "bad control type '{}' for channel {n} (must be p or v)",
                        ctrl[n]
                    ),
                ))
            }
        };
        chans.push(ChannelConfig {
            step_type,
            velocity_mode,
        });
    }
    if chans.is_empty() {
        return Err(param_error(
            "step_type",
            "no channels configured (give step_type=T0,T1,...)".into(),
        ));
    }
    Ok(chans)
}

/// Per-channel state that more than one function touches; the functions
/// may run in different threads, so it is atomic.
struct Shared {
    accum: AtomicI64,
    addval: AtomicI64,
    target_addval: AtomicI64,
    deltalim: AtomicI64,
    /// The `position-scale` cache of update-freq and capture-position
    /// ([`ScaleCache`] fields, as f64 bits). It is one cache, as in
    /// LinuxCNC: with one per function, a near-zero scale written again
    /// after one function corrected it would be corrected by the other,
    /// where LinuxCNC leaves it alone.
    old_scale: AtomicU64,
    scale_recip: AtomicU64,
}

impl Shared {
    fn new() -> Shared {
        let d = Dds::default();
        let c = INITIAL_SCALE_CACHE;
        Shared {
            accum: AtomicI64::new(d.accum),
            addval: AtomicI64::new(d.addval),
            target_addval: AtomicI64::new(d.target_addval),
            deltalim: AtomicI64::new(d.deltalim),
            old_scale: AtomicU64::new(c.old_scale.to_bits()),
            scale_recip: AtomicU64::new(c.recip.to_bits()),
        }
    }

    /// The DDS registers as they are now.
    #[inline(always)]
    fn dds(&self) -> Dds {
        Dds {
            accum: self.accum.load(Relaxed),
            addval: self.addval.load(Relaxed),
            target_addval: self.target_addval.load(Relaxed),
            deltalim: self.deltalim.load(Relaxed),
        }
    }

    /// Stores the DDS registers that differ from `before`. The other
    /// function may write `addval` and `accum` meanwhile; a register this
    /// function left alone is not overwritten.
    #[inline(always)]
    fn store_dds(&self, before: &Dds, after: &Dds) {
        for (reg, old, new) in [
            (&self.accum, before.accum, after.accum),
            (&self.addval, before.addval, after.addval),
            (
                &self.target_addval,
                before.target_addval,
                after.target_addval,
            ),
            (&self.deltalim, before.deltalim, after.deltalim),
        ] {
            if old != new {
                reg.store(new, Relaxed);
            }
        }
    }

    fn scale_cache(&self) -> ScaleCache {
        ScaleCache::new(
            f64::from_bits(self.old_scale.load(Relaxed)),
            f64::from_bits(self.scale_recip.load(Relaxed)),
        )
    }

    fn store_scale_cache(&self, c: &ScaleCache) {
        self.old_scale.store(c.old_scale.to_bits(), Relaxed);
        self.scale_recip.store(c.recip.to_bits(), Relaxed);
    }
}

/// Writes `new` to a parameter the function may have changed, only if it
/// did (bitwise, so -0.0 becoming 0.0 counts), so a concurrent `setp` of
/// an untouched parameter is not overwritten.
#[inline(always)]
fn write_back<T: PinValue>(p: &Param<T, Rw>, old: T, new: T) {
    if old.to_bits() != new.to_bits() {
        p.set(new);
    }
}

/// The timing parameters of one channel; `stepspace` exists for types 0
/// and 1, `setup` (`dirsetup`) for type 0; `hold` is `dirhold` or
/// `dirdelay`.
#[derive(Clone)]
struct TimingParams {
    steplen: Param<u32, Rw>,
    stepspace: Option<Param<u32, Rw>>,
    setup: Option<Param<u32, Rw>>,
    hold: Param<u32, Rw>,
}

impl TimingParams {
    #[inline(always)]
    fn pulse_timing(&self) -> PulseTiming {
        PulseTiming {
            steplen: self.steplen.get(),
            hold: self.hold.get(),
            setup: self.setup.as_ref().map_or(0, Param::get),
        }
    }
}

struct PulseChan {
    gen: PulseGen,
    shared: Arc<Shared>,
    enable: Pin<bool, In>,
    timing: TimingParams,
    rawcounts: Param<i32, Ro>,
    /// Output pins in output-bit order (step, dir / up, down / phases).
    outputs: Vec<Pin<bool, Out>>,
}

struct FreqChan {
    ctl: FreqCtl,
    shared: Arc<Shared>,
    enable: Pin<bool, In>,
    cmd: Pin<f64, In>,
    timing: TimingParams,
    position_scale: Param<f64, Rw>,
    maxvel: Param<f64, Rw>,
    maxaccel: Param<f64, Rw>,
    frequency: Param<f64, Ro>,
}

struct CaptureChan {
    shared: Arc<Shared>,
    position_scale: Param<f64, Rw>,
    counts: Pin<i32, Out>,
    position_fb: Pin<f64, Out>,
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let cfg = parse_config(args)?;
    let mut b = host.new_rt_component("stepgen")?;
    let mut pulse = Vec::with_capacity(cfg.len());
    let mut update = Vec::with_capacity(cfg.len());
    let mut capture = Vec::with_capacity(cfg.len());
    for (n, ch) in cfg.iter().enumerate() {
        let c = b.component();
        let name = |item: &str| format!("stepgen.{n}.{item}");
        let st = &ch.step_type;
        let rawcounts: Param<i32, Ro> = c.param(&name("rawcounts"), 0)?;
        let counts: Pin<i32, Out> = c.pin(&name("counts"))?;
        let position_scale: Param<f64, Rw> = c.param(&name("position-scale"), 1.0)?;
        let cmd: Pin<f64, In> = c.pin(&name(if ch.velocity_mode {
            "velocity-cmd"
        } else {
            "position-cmd"
        }))?;
        let enable: Pin<bool, In> = c.pin(&name("enable"))?;
        let position_fb: Pin<f64, Out> = c.pin(&name("position-fb"))?;
        let frequency: Param<f64, Ro> = c.param(&name("frequency"), 0.0)?;
        let maxvel: Param<f64, Rw> = c.param(&name("maxvel"), 0.0)?;
        let maxaccel: Param<f64, Rw> = c.param(&name("maxaccel"), 0.0)?;
        let steplen = c.param(&name("steplen"), 1u32)?;
        let stepspace = if st.has_stepspace() {
            Some(c.param(&name("stepspace"), 1u32)?)
        } else {
            None
        };
        let (setup, hold) = if st.has_setup() {
            (
                Some(c.param(&name("dirsetup"), 1u32)?),
                c.param(&name("dirhold"), 1u32)?,
            )
        } else {
            (None, c.param(&name("dirdelay"), 1u32)?)
        };
        let outputs: Vec<Pin<bool, Out>> = match st.kind() {
            0 => vec![c.pin(&name("step"))?, c.pin(&name("dir"))?],
            1 => vec![c.pin(&name("up"))?, c.pin(&name("down"))?],
            _ => (0..st.phases())
                .map(|p| c.pin(&name(phase_name(p))))
                .collect::<Result<_>>()?,
        };
        let timing = TimingParams {
            steplen,
            stepspace,
            setup,
            hold,
        };
        let shared = Arc::new(Shared::new());
        pulse.push(PulseChan {
            gen: PulseGen::new(*st),
            shared: shared.clone(),
            enable: enable.clone(),
            timing: timing.clone(),
            rawcounts,
            outputs,
        });
        update.push(FreqChan {
            ctl: FreqCtl::new(st, ch.velocity_mode),
            shared: shared.clone(),
            enable,
            cmd,
            timing,
            position_scale: position_scale.clone(),
            maxvel,
            maxaccel,
            frequency,
        });
        capture.push(CaptureChan {
            shared,
            position_scale,
            counts,
            position_fb,
        });
    }

    // make-pulses' period, which update-freq reads (module-global in
    // LinuxCNC; 50 µs until make-pulses first runs).
    let periodns = Arc::new(AtomicI64::new(INITIAL_PERIOD_NS));

    let period_w = periodns.clone();
    b.funct("stepgen.make-pulses", false, move |ctx| {
        let period = ctx.period();
        period_w.store(period, Relaxed);
        for ch in pulse.iter_mut() {
            make_pulses_channel(ch, period);
        }
    })?;

    let mut timing = FreqTiming::default();
    b.funct("stepgen.update-freq", true, move |ctx| {
        let pns = periodns.load(Relaxed);
        let newperiod = timing.update(pns, ctx.period());
        for ch in update.iter_mut() {
            update_freq_channel(ch, &timing, newperiod, pns);
        }
    })?;

    b.funct("stepgen.capture-position", true, move |_| {
        for ch in capture.iter() {
            let mut cache = ch.shared.scale_cache();
            let before = cache;
            let old_s = ch.position_scale.get();
            let mut s = old_s;
            let (counts, fb) = freq::capture(ch.shared.accum.load(Relaxed), &mut s, &mut cache);
            write_back(&ch.position_scale, old_s, s);
            if cache != before {
                ch.shared.store_scale_cache(&cache);
            }
            ch.counts.set(counts);
            ch.position_fb.set(fb);
        }
    })?;
    b.ready()
}

/// make-pulses for one channel: loads the shared registers, runs the
/// generator, stores what it changed and drives the outputs.
#[inline(always)]
fn make_pulses_channel(ch: &mut PulseChan, period: i64) {
    let sh = &*ch.shared;
    let before = sh.dds();
    let mut dds = before;
    let timing = &ch.timing;
    let r = ch
        .gen
        .update(period, ch.enable.get(), || timing.pulse_timing(), &mut dds);
    sh.store_dds(&before, &dds);
    if r.advanced {
        ch.rawcounts.set(dds.counts());
    }
    let bits = ch.gen.outputs();
    for (i, pin) in ch.outputs.iter().enumerate() {
        pin.set(bits >> i & 1 != 0);
    }
}

/// update-freq for one channel: loads its parameters, runs the
/// controller, writes back what changed and hands the result to
/// make-pulses.
#[inline(always)]
fn update_freq_channel(ch: &mut FreqChan, timing: &FreqTiming, newperiod: bool, periodns: i64) {
    let t = &ch.timing;
    let before = FreqParams {
        position_scale: ch.position_scale.get(),
        maxvel: ch.maxvel.get(),
        maxaccel: ch.maxaccel.get(),
        steplen: t.steplen.get(),
        stepspace: t.stepspace.as_ref().map_or(0, Param::get),
        setup: t.setup.as_ref().map_or(0, Param::get),
        hold: t.hold.get(),
        frequency: ch.frequency.get(),
    };
    let mut p = before;
    let sh = &*ch.shared;
    let mut cache = sh.scale_cache();
    let cache_before = cache;
    let dds_before = sh.dds();
    let mut dds = dds_before;
    ch.ctl
        .update(
            timing,
            newperiod,
            periodns,
            &mut cache,
            &mut p,
            ch.enable.get(),
            ch.cmd.get(),
            dds.accum,
        )
        .apply(&mut dds);
    if cache != cache_before {
        sh.store_scale_cache(&cache);
    }
    write_back(&ch.position_scale, before.position_scale, p.position_scale);
    write_back(&ch.maxvel, before.maxvel, p.maxvel);
    write_back(&ch.maxaccel, before.maxaccel, p.maxaccel);
    write_back(&t.steplen, before.steplen, p.steplen);
    if let Some(sp) = &t.stepspace {
        write_back(sp, before.stepspace, p.stepspace);
    }
    if let Some(su) = &t.setup {
        write_back(su, before.setup, p.setup);
    }
    write_back(&t.hold, before.hold, p.hold);
    ch.frequency.set(p.frequency);
    // Last, as in LinuxCNC: the new rate for make-pulses.
    sh.store_dds(&dds_before, &dds);
}

#[cfg(test)]
mod tests;
