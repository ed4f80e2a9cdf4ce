//! `sim_encoder`: simulated quadrature encoder output with an index pulse
//! once per revolution (components.md §12.1).
//!
//! `sim-encoder.update-speed` (floating point) turns `speed` into a phase
//! increment [`SpeedCalc`]; `sim-encoder.make-pulses` (integer) adds it to
//! a phase accumulator and steps the quadrature state each time the
//! accumulator crosses a multiple of 2^31 ([`PulseGen`]).

use std::sync::atomic::{AtomicI64, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, In, Io, Out, Pin, Result};

use super::{CHANNEL_PARAMS, MAX_CHAN};
use crate::cmath::{f64_to_i64, ScaleCache};
use crate::halcomp::channel_names;

/// The `sim_encoder` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "sim_encoder",
    params: CHANNEL_PARAMS,
    help: "simulated quadrature encoder (num_chan=1-8, default 1, or names=)",
    load,
};

/// The period assumed until make-pulses has run once (ns).
pub const INITIAL_PERIOD_NS: i64 = 50_000;

/// The make-pulses half of one channel: phase accumulator and quadrature
/// state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PulseGen {
    accum: u64,
    /// Quadrature state 0..3.
    qstate: i32,
    /// Position within the revolution, 0..ppr-1.
    cycle: i64,
}

/// The outputs of one make-pulses step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Phases {
    /// `phase-A`.
    pub a: bool,
    /// `phase-B`.
    pub b: bool,
    /// `phase-Z`.
    pub z: bool,
}

impl PulseGen {
    /// A channel as loaded.
    pub fn new() -> PulseGen {
        PulseGen::default()
    }

    /// One make-pulses call: adds `addval` to the accumulator and steps
    /// once if it crossed a multiple of 2^31. `rawcounts` is the pin (read
    /// and written), `ppr` the pulses-per-revolution pin.
    #[inline]
    pub fn step(&mut self, addval: i64, ppr: u32, rawcounts: &mut i32) -> Phases {
        let before = self.accum >> 31;
        self.accum = self.accum.wrapping_add(addval as u64);
        if (before ^ (self.accum >> 31)) != 0 {
            // Quirk: bit 31 and above of the increment decide the
            // direction, so an increment of exactly 2^31 runs backwards.
            if (addval >> 31) != 0 {
                *rawcounts = rawcounts.wrapping_sub(1);
                self.qstate -= 1;
                if self.qstate < 0 {
                    self.qstate = 3;
                    self.cycle -= 1;
                    if self.cycle < 0 {
                        self.cycle += ppr as i64;
                    }
                }
            } else {
                *rawcounts = rawcounts.wrapping_add(1);
                self.qstate += 1;
                if self.qstate > 3 {
                    self.qstate = 0;
                    self.cycle += 1;
                    if self.cycle >= ppr as i64 {
                        self.cycle -= ppr as i64;
                    }
                }
            }
        }
        let (a, b) = match self.qstate {
            0 => (true, false),
            1 => (true, true),
            2 => (false, true),
            _ => (false, false),
        };
        Phases {
            a,
            b,
            z: self.qstate == 0 && self.cycle == 0,
        }
    }
}

/// The module-wide timing update-speed derives from the period
/// make-pulses last ran with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    old_periodns: i64,
    /// Largest step rate (steps per second): one per make-pulses period.
    maxf: f64,
    /// Accumulator increment per step/s.
    freqscale: f64,
}

impl Timing {
    /// The load-time values, for a 50 µs period.
    pub fn new() -> Timing {
        let mut t = Timing {
            old_periodns: INITIAL_PERIOD_NS,
            maxf: 0.0,
            freqscale: 0.0,
        };
        t.recompute(INITIAL_PERIOD_NS);
        t
    }

    fn recompute(&mut self, periodns: i64) {
        let periodfp = periodns as f64 * 1e-9;
        self.maxf = 1.0 / periodfp;
        self.freqscale = (1073741824.0 * 2.0) / self.maxf;
        self.old_periodns = periodns;
    }

    /// Follows a change of the make-pulses period.
    #[inline]
    pub fn update(&mut self, periodns: i64) {
        if periodns != self.old_periodns {
            self.recompute(periodns);
        }
    }
}

impl Default for Timing {
    fn default() -> Self {
        Timing::new()
    }
}

/// The update-speed half of one channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedCalc {
    /// `1 / scale`, starting from LinuxCNC's old scale 0.0 and reciprocal
    /// 1.0.
    scale: ScaleCache,
}

impl Default for SpeedCalc {
    fn default() -> Self {
        SpeedCalc {
            scale: ScaleCache::new(0.0, 1.0),
        }
    }
}

impl SpeedCalc {
    /// A channel as loaded.
    pub fn new() -> SpeedCalc {
        SpeedCalc::default()
    }

    /// One update-speed call: the accumulator increment for `speed`
    /// (revolutions per second times `scale`). `scale` is the io pin; a
    /// near-zero scale is replaced by 1.0.
    #[inline]
    pub fn addval(&mut self, t: &Timing, speed: f64, scale: &mut f64, ppr: u32) -> i64 {
        let scale_mult = self.scale.check(scale, 1.0);
        let mut f = (speed * scale_mult) * ppr as f64 * 4.0;
        if f > t.maxf {
            f = t.maxf;
        } else if f < -t.maxf {
            f = -t.maxf;
        }
        f64_to_i64(f * t.freqscale)
    }
}

struct PulseChan {
    ppr: Pin<u32, Io>,
    rawcounts: Pin<i32, In>,
    phase_a: Pin<bool, Out>,
    phase_b: Pin<bool, Out>,
    phase_z: Pin<bool, Out>,
    gen: PulseGen,
    addval: Arc<AtomicI64>,
}

struct SpeedChan {
    ppr: Pin<u32, Io>,
    scale: Pin<f64, Io>,
    speed: Pin<f64, In>,
    calc: SpeedCalc,
    addval: Arc<AtomicI64>,
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let names = channel_names("sim_encoder", "sim-encoder", 1, MAX_CHAN, args)?;
    let mut b = host.new_rt_component("sim_encoder")?;
    let mut pulses = Vec::with_capacity(names.len());
    let mut speeds = Vec::with_capacity(names.len());
    for name in &names {
        let c = b.component();
        let p = |item: &str| format!("{name}.{item}");
        let ppr: Pin<u32, Io> = c.pin_init(&p("ppr"), 100)?;
        let scale = c.pin_init(&p("scale"), 1.0)?;
        let speed = c.pin(&p("speed"))?;
        let phase_a = c.pin(&p("phase-A"))?;
        let phase_b = c.pin(&p("phase-B"))?;
        let phase_z = c.pin(&p("phase-Z"))?;
        let rawcounts = c.pin(&p("rawcounts"))?;
        let addval = Arc::new(AtomicI64::new(0));
        pulses.push(PulseChan {
            ppr: ppr.clone(),
            rawcounts,
            phase_a,
            phase_b,
            phase_z,
            gen: PulseGen::new(),
            addval: addval.clone(),
        });
        speeds.push(SpeedChan {
            ppr,
            scale,
            speed,
            calc: SpeedCalc::new(),
            addval,
        });
    }
    // The period make-pulses last ran with, read by update-speed.
    let periodns = Arc::new(AtomicI64::new(INITIAL_PERIOD_NS));
    let pns = periodns.clone();
    b.funct("sim-encoder.make-pulses", false, move |ctx| {
        pns.store(ctx.period(), Relaxed);
        for ch in pulses.iter_mut() {
            let mut raw = ch.rawcounts.get();
            let ph = ch.gen.step(ch.addval.load(Relaxed), ch.ppr.get(), &mut raw);
            ch.rawcounts.overwrite(raw);
            ch.phase_a.set(ph.a);
            ch.phase_b.set(ph.b);
            ch.phase_z.set(ph.z);
        }
    })?;
    let mut timing = Timing::new();
    b.funct("sim-encoder.update-speed", true, move |_| {
        timing.update(periodns.load(Relaxed));
        for ch in speeds.iter_mut() {
            let s0 = ch.scale.get();
            let mut s = s0;
            let addval = ch
                .calc
                .addval(&timing, ch.speed.get(), &mut s, ch.ppr.get());
            if s.to_bits() != s0.to_bits() {
                ch.scale.set(s);
            }
            ch.addval.store(addval, Relaxed);
        }
    })?;
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timing_defaults_to_50us() {
        let t = Timing::new();
        assert_eq!(t.maxf, 1.0 / (50_000f64 * 1e-9));
        assert_eq!(t.freqscale, 2147483648.0 / t.maxf);
        let mut t2 = t;
        t2.update(50_000);
        assert_eq!(t2, t);
        t2.update(25_000);
        assert_eq!(t2.maxf, 1.0 / (25_000f64 * 1e-9));
    }

    #[test]
    fn forward_motion_makes_quadrature_and_index() {
        let t = Timing::new();
        let mut calc = SpeedCalc::new();
        let mut scale = 1.0;
        // 10 rev/s * 100 ppr * 4 = 4000 steps/s; 20000 periods/s: one
        // step every 5 calls.
        let addval = calc.addval(&t, 10.0, &mut scale, 100);
        assert_eq!(addval, f64_to_i64(4000.0 * t.freqscale));
        let mut g = PulseGen::new();
        let mut raw = 0;
        let mut seen = Vec::new();
        let mut z_count = 0;
        for _ in 0..2000 * 5 {
            let ph = g.step(addval, 100, &mut raw);
            if seen.last() != Some(&(ph.a, ph.b)) {
                seen.push((ph.a, ph.b));
            }
            if ph.z {
                z_count += 1;
            }
        }
        assert!((1999..=2000).contains(&raw), "{raw}");
        // Sequence 10 -> 11 -> 01 -> 00 -> 10 (A leads B).
        assert_eq!(
            &seen[..5],
            &[
                (true, false),
                (true, true),
                (false, true),
                (false, false),
                (true, false)
            ]
        );
        // Z is high for one step (several calls) per 400 steps.
        assert!(z_count > 0);
    }

    #[test]
    fn first_negative_step_is_immediate() {
        let t = Timing::new();
        let mut calc = SpeedCalc::new();
        let mut scale = 1.0;
        let addval = calc.addval(&t, -1.0, &mut scale, 100);
        assert!(addval < 0);
        let mut g = PulseGen::new();
        let mut raw = 0;
        let ph = g.step(addval, 100, &mut raw);
        assert_eq!(raw, -1);
        assert_eq!((ph.a, ph.b, ph.z), (false, false, false));
        assert_eq!(g.cycle, 99);
        // Positive motion needs 2^31 / addval calls first.
        let mut g = PulseGen::new();
        let mut raw = 0;
        g.step(1 << 30, 100, &mut raw);
        assert_eq!(raw, 0);
        g.step(1 << 30, 100, &mut raw);
        assert_eq!(raw, 1);
    }

    #[test]
    fn speed_is_clamped_and_exact_max_runs_backwards() {
        let t = Timing::new();
        let mut calc = SpeedCalc::new();
        let mut scale = 1.0;
        let addval = calc.addval(&t, 1e9, &mut scale, 100);
        assert_eq!(addval, 1 << 31);
        let neg = calc.addval(&t, -1e9, &mut scale, 100);
        assert_eq!(neg, -(1 << 31));
        // Quirk: an increment of exactly 2^31 counts as reverse.
        let mut g = PulseGen::new();
        let mut raw = 0;
        g.step(addval, 100, &mut raw);
        assert_eq!(raw, -1);
        // NaN speed: C's conversion gives i64::MIN.
        assert_eq!(calc.addval(&t, f64::NAN, &mut scale, 100), i64::MIN);
    }

    #[test]
    fn tiny_scale_becomes_one() {
        let t = Timing::new();
        let mut calc = SpeedCalc::new();
        // Quirk: the remembered scale starts at 0.0, so a scale of exactly
        // 0 before the first update is taken as unchanged: not corrected,
        // and the multiplier stays 1.
        let mut scale = 0.0;
        let a = calc.addval(&t, 1.0, &mut scale, 100);
        assert_eq!(scale, 0.0);
        assert_eq!(a, f64_to_i64(400.0 * t.freqscale));
        let mut scale = 1e-21;
        let a = calc.addval(&t, 1.0, &mut scale, 100);
        assert_eq!(scale, 1.0);
        assert_eq!(a, f64_to_i64(400.0 * t.freqscale));
        let mut scale = 2.0;
        let a = calc.addval(&t, 1.0, &mut scale, 100);
        assert_eq!(a, f64_to_i64(200.0 * t.freqscale));
    }

    #[test]
    fn cycle_wraps_with_ppr() {
        // An increment just below 2^31 steps on every call but the first.
        let up = (1i64 << 31) - 1;
        let mut g = PulseGen::new();
        let mut raw = 0;
        // The start position is the index: Z is high until the first step.
        assert!(g.step(up, 3, &mut raw).z);
        assert_eq!(raw, 0);
        let mut zs = Vec::new();
        for _ in 0..12 {
            zs.push(g.step(up, 3, &mut raw).z);
        }
        assert_eq!(raw, 12);
        // ppr 3: the index (qstate 0, cycle 0) comes every 12 steps.
        assert_eq!(zs.iter().filter(|&&z| z).count(), 1);
        assert!(zs[11]);
        assert_eq!((g.qstate, g.cycle), (0, 0));
        // Backwards, cycle wraps below 0 to ppr - 1.
        g.step(-(1 << 31), 3, &mut raw);
        assert_eq!((g.qstate, g.cycle, raw), (3, 2, 11));
        // rawcounts wraps as s32.
        let mut raw = i32::MIN;
        let mut g = PulseGen::new();
        g.step(-1, 3, &mut raw);
        assert_eq!(raw, i32::MAX);
    }

    #[test]
    fn loads_with_defaults_and_rejects_bad_params() {
        let h = crate::testing::host();
        h.loadrt(&MODULE, &[] as &[&str]).unwrap();
        let inst = h.instance();
        assert_eq!(
            inst.pin_value("sim-encoder.0.ppr").unwrap(),
            hal_core::Value::U32(100)
        );
        let f: Vec<String> = inst.functs().unwrap().into_iter().map(|f| f.name).collect();
        assert!(f.contains(&"sim-encoder.make-pulses".to_string()));
        assert!(f.contains(&"sim-encoder.update-speed".to_string()));
        let h = crate::testing::host();
        assert!(h.loadrt(&MODULE, &["num_chan=9".to_string()]).is_err());
        h.loadrt(&MODULE, &["names=a,b,c,d,e,f,g,h".to_string()])
            .unwrap();
        assert!(h.instance().pin_value("h.phase-Z").is_ok());
    }
}
