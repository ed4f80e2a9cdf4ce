//! `pwmgen`: software PWM / PDM generator, up to 8 channels.
//!
//! `loadrt pwmgen output_type=T0[,T1,...]` creates one channel per entry
//! (the list ends at the first -1). Output type 0 drives `pwm` only
//! (negative commands give 0), 1 drives `pwm` and `dir`, 2 drives `up` and
//! `down`. Two functions serve every channel: `pwmgen.make-pulses`
//! (integer only, for a fast thread) toggles the outputs, and
//! `pwmgen.update` (floating point) turns `value` into the timing that
//! make-pulses follows.

use std::sync::atomic::{AtomicBool, AtomicI64, AtomicU8, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, In, Io, Out, Pin, Result};

use crate::cmath::{f64_to_i32, f64_to_i64, ScaleCache};

/// Most channels one load may create.
pub const MAX_CHAN: usize = 8;

const PARAMS: &[ParamDecl] = &[ParamDecl {
    name: "output_type",
    kind: ParamKind::IntArray(MAX_CHAN),
    help: "output type of each channel: 0 = pwm, 1 = pwm + dir, 2 = up + down",
}];

/// The `pwmgen` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "pwmgen",
    params: PARAMS,
    help: "software PWM/PDM generator",
    load,
};

/// How make-pulses drives a channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(u8)]
pub enum Mode {
    /// Output low, timers cleared.
    #[default]
    Disabled = 0,
    /// PWM whose period is a whole number of make-pulses periods.
    Pure = 1,
    /// PWM that carries the remainder of each high time to the next.
    Dither = 2,
    /// Pulse density modulation (`pwm-freq` 0).
    Pdm = 3,
}

impl Mode {
    fn from_u8(v: u8) -> Mode {
        match v {
            1 => Mode::Pure,
            2 => Mode::Dither,
            3 => Mode::Pdm,
            _ => Mode::Disabled,
        }
    }
}

/// The timers make-pulses keeps per channel.
#[derive(Debug, Clone, Default)]
pub struct PulseTimers {
    /// Time since the start of the current PWM period (ns).
    pub period_timer: i64,
    /// High time elapsed (PURE), left (DITHER) or accumulated (PDM), ns.
    pub high_timer: i64,
    /// The output state.
    pub curr_output: bool,
}

impl PulseTimers {
    /// One make-pulses call of `p` ns with the timing update computed
    /// (`period` and `high_time` in ns); returns the output state.
    pub fn step(&mut self, mode: Mode, period: i64, high_time: i64, p: i64) -> bool {
        match mode {
            Mode::Pure => {
                if self.curr_output {
                    self.high_timer = self.high_timer.wrapping_add(p);
                    if self.high_timer >= high_time {
                        self.curr_output = false;
                    }
                }
                self.period_timer = self.period_timer.wrapping_add(p);
                if self.period_timer >= period {
                    self.period_timer = 0;
                    self.high_timer = 0;
                    if high_time > 0 {
                        self.curr_output = true;
                    }
                }
            }
            Mode::Dither => {
                if self.curr_output {
                    self.high_timer = self.high_timer.wrapping_sub(p);
                    if self.high_timer <= 0 {
                        self.curr_output = false;
                    }
                }
                self.period_timer = self.period_timer.wrapping_add(p);
                if self.period_timer >= period {
                    self.period_timer = self.period_timer.wrapping_sub(period);
                    self.high_timer = self.high_timer.wrapping_add(high_time);
                    if self.high_timer > 0 {
                        self.curr_output = true;
                    }
                }
            }
            Mode::Pdm => {
                self.high_timer = self.high_timer.wrapping_add(high_time);
                if self.curr_output {
                    self.high_timer = self.high_timer.wrapping_sub(p);
                }
                self.curr_output = self.high_timer > 0;
            }
            Mode::Disabled => {
                self.curr_output = false;
                self.high_timer = 0;
                self.period_timer = 0;
            }
        }
        self.curr_output
    }
}

/// The I/O pins update checks and may correct, as values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// `scale`: `value` of full duty cycle.
    pub scale: f64,
    /// `pwm-freq`: PWM frequency (Hz), 0 for PDM.
    pub pwm_freq: f64,
    /// `min-dc`: smallest duty cycle magnitude.
    pub min_dc: f64,
    /// `max-dc`: largest duty cycle magnitude.
    pub max_dc: f64,
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            scale: 1.0,
            pwm_freq: 0.0,
            min_dc: 0.0,
            max_dc: 1.0,
        }
    }
}

/// The inputs update reads but never rewrites.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Command {
    /// `enable`.
    pub enable: bool,
    /// `dither-pwm`.
    pub dither: bool,
    /// `value`: the commanded output.
    pub value: f64,
    /// `offset`: added to the duty cycle.
    pub offset: f64,
}

/// What update computes for one channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timing {
    /// The mode make-pulses is to run in.
    pub mode: Mode,
    /// PWM period (ns).
    pub period: i64,
    /// High time per period (ns); per make-pulses call in PDM.
    pub high_time: i64,
    /// TRUE for a negative duty cycle.
    pub direction: bool,
    /// The duty cycle actually produced (`curr-dc`).
    pub curr_dc: f64,
    /// Whether this call recomputed the period (make-pulses may briefly
    /// see the channel disabled).
    pub recalculated: bool,
}

/// The state update keeps per channel.
#[derive(Debug, Clone)]
pub struct Generator {
    /// 0, 1 or 2 (see the module doc).
    pub output_type: i32,
    mode: Mode,
    period: i64,
    high_time: i64,
    /// `1 / scale`, starting from LinuxCNC's old scale `scale + 1.0` (so
    /// the default scale is examined at once) and an unset reciprocal.
    scale: ScaleCache,
    old_pwm_freq: f64,
    periods: i32,
    periods_recip: f64,
}

impl Generator {
    /// A channel as loaded: disabled, with a scale that forces the first
    /// reciprocal computation.
    pub fn new(output_type: i32) -> Generator {
        Generator {
            output_type,
            mode: Mode::Disabled,
            period: 50_000,
            high_time: 0,
            scale: ScaleCache::new(Settings::default().scale + 1.0, 0.0),
            old_pwm_freq: -1.0,
            periods: 0,
            periods_recip: 0.0,
        }
    }

    /// One update of this channel. `periodns` is the make-pulses period
    /// (-1 before make-pulses ever ran), `oldperiodns` its value at the
    /// previous update. Corrections to the I/O pins are made in `s`.
    pub fn update(
        &mut self,
        s: &mut Settings,
        cmd: &Command,
        periodns: i64,
        oldperiodns: i64,
    ) -> Timing {
        // Duty-cycle limits: 0 <= min-dc <= max-dc <= 1.
        if s.max_dc > 1.0 {
            s.max_dc = 1.0;
        }
        if s.min_dc > s.max_dc {
            s.min_dc = s.max_dc;
        }
        if s.min_dc < 0.0 {
            s.min_dc = 0.0;
        }
        if s.max_dc < s.min_dc {
            s.max_dc = s.min_dc;
        }
        // The reciprocal of the scale, recomputed only when it changes.
        let scale_recip = self.scale.check(&mut s.scale, 1.0);
        let new_mode = if !cmd.enable {
            Mode::Disabled
        } else if s.pwm_freq == 0.0 {
            Mode::Pdm
        } else if cmd.dither {
            Mode::Dither
        } else {
            Mode::Pure
        };
        // A new frequency forces the period calculation below.
        if s.pwm_freq != self.old_pwm_freq {
            self.mode = Mode::Disabled;
        }
        let recalculated = self.mode != new_mode || periodns != oldperiodns;
        if recalculated {
            self.mode = Mode::Disabled;
            if s.pwm_freq <= 0.0 {
                s.pwm_freq = 0.0;
                self.period = periodns;
            } else {
                // Between 0.5 Hz and two make-pulses periods.
                let fastest = (1e9 / 2.0) / periodns as f64;
                if s.pwm_freq < 0.5 {
                    s.pwm_freq = 0.5;
                } else if s.pwm_freq > fastest {
                    s.pwm_freq = fastest;
                }
                if new_mode == Mode::Pure {
                    // A whole number of make-pulses periods, and the
                    // frequency that actually gives.
                    self.periods = f64_to_i32((1e9 / s.pwm_freq) / periodns as f64 + 0.5);
                    self.periods_recip = 1.0 / self.periods as f64;
                    self.period = (self.periods as i64).wrapping_mul(periodns);
                    s.pwm_freq = 1.0e9 / self.period as f64;
                } else {
                    self.period = f64_to_i64(1.0e9 / s.pwm_freq);
                }
            }
            self.old_pwm_freq = s.pwm_freq;
        }
        // Command to duty cycle, limited in magnitude to min-dc..max-dc.
        let mut dc = cmd.value * scale_recip + cmd.offset;
        if self.output_type == 0 && dc < 0.0 {
            dc = 0.0;
        }
        let (direction, out_dc) = if dc >= 0.0 {
            if dc > s.max_dc {
                dc = s.max_dc;
            } else if dc < s.min_dc {
                dc = s.min_dc;
            }
            (false, dc)
        } else {
            if dc < -s.max_dc {
                dc = -s.max_dc;
            } else if dc > -s.min_dc {
                dc = -s.min_dc;
            }
            (true, -dc)
        };
        let curr_dc = if new_mode == Mode::Pure {
            let hp = f64_to_i32(self.periods as f64 * out_dc + 0.5);
            self.high_time = (hp as i64).wrapping_mul(periodns);
            let produced = hp as f64 * self.periods_recip;
            if dc < 0.0 {
                -produced
            } else {
                produced
            }
        } else {
            self.high_time = f64_to_i64(self.period as f64 * out_dc + 0.5);
            dc
        };
        self.mode = new_mode;
        Timing {
            mode: new_mode,
            period: self.period,
            high_time: self.high_time,
            direction,
            curr_dc,
            recalculated,
        }
    }
}

/// What update hands to make-pulses for one channel (they may run in
/// different threads).
#[derive(Debug, Default)]
struct Shared {
    mode: AtomicU8,
    period: AtomicI64,
    high_time: AtomicI64,
    direction: AtomicBool,
}

/// The output pins of one channel.
enum Outputs {
    /// Type 0: `pwm`.
    Pwm(Pin<bool, Out>),
    /// Type 1: `pwm` and `dir` (written by update).
    PwmDir(Pin<bool, Out>),
    /// Type 2: `up` and `down`.
    UpDown(Pin<bool, Out>, Pin<bool, Out>),
}

/// The pins and state update uses for one channel.
struct UpdateChan {
    scale: Pin<f64, Io>,
    offset: Pin<f64, Io>,
    dither: Pin<bool, Io>,
    pwm_freq: Pin<f64, Io>,
    min_dc: Pin<f64, Io>,
    max_dc: Pin<f64, Io>,
    curr_dc: Pin<f64, Out>,
    enable: Pin<bool, In>,
    value: Pin<f64, In>,
    dir: Option<Pin<bool, Out>>,
    gen: Generator,
    shared: Arc<Shared>,
}

/// What make-pulses uses for one channel.
struct PulseChan {
    outputs: Outputs,
    timers: PulseTimers,
    shared: Arc<Shared>,
}

/// The channel output types from `output_type=`.
fn output_types(args: &ModuleArgs) -> Result<Vec<i32>> {
    let bad = |reason: String| HalError::ModuleParam {
        module: "pwmgen".into(),
        param: "output_type".into(),
        reason,
    };
    let mut types = Vec::new();
    for (i, &t) in args.int_array("output_type").iter().enumerate() {
        if t == -1 {
            break;
        }
        if !(0..=2).contains(&t) {
            return Err(bad(format!(
                "channel {i}: output type {t} is not 0, 1 or 2"
            )));
        }
        types.push(t as i32);
    }
    if types.is_empty() {
        return Err(bad("no channels configured (e.g. output_type=0)".into()));
    }
    Ok(types)
}

/// Writes `new` to an I/O pin if update changed it.
fn write_back(pin: &Pin<f64, Io>, old: f64, new: f64) {
    if old.to_bits() != new.to_bits() {
        pin.set(new);
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let types = output_types(args)?;
    let mut b = host.new_rt_component("pwmgen")?;
    let mut updates = Vec::with_capacity(types.len());
    let mut pulses = Vec::with_capacity(types.len());
    for (n, &t) in types.iter().enumerate() {
        let c = b.component();
        let p = |item: &str| format!("pwmgen.{n}.{item}");
        let shared = Arc::new(Shared::default());
        let outputs = match t {
            0 => Outputs::Pwm(c.pin(&p("pwm"))?),
            1 => Outputs::PwmDir(c.pin(&p("pwm"))?),
            _ => Outputs::UpDown(c.pin(&p("up"))?, c.pin(&p("down"))?),
        };
        let dir = if t == 1 {
            Some(c.pin(&p("dir"))?)
        } else {
            None
        };
        let defaults = Settings::default();
        updates.push(UpdateChan {
            scale: c.pin_init(&p("scale"), defaults.scale)?,
            offset: c.pin(&p("offset"))?,
            dither: c.pin(&p("dither-pwm"))?,
            pwm_freq: c.pin_init(&p("pwm-freq"), defaults.pwm_freq)?,
            min_dc: c.pin_init(&p("min-dc"), defaults.min_dc)?,
            max_dc: c.pin_init(&p("max-dc"), defaults.max_dc)?,
            curr_dc: c.pin(&p("curr-dc"))?,
            enable: c.pin(&p("enable"))?,
            value: c.pin(&p("value"))?,
            dir,
            gen: Generator::new(t),
            shared: shared.clone(),
        });
        pulses.push(PulseChan {
            outputs,
            timers: PulseTimers::default(),
            shared,
        });
    }
    // The make-pulses period, -1 until make-pulses first runs.
    let periodns = Arc::new(AtomicI64::new(-1));
    let pn = periodns.clone();
    b.funct("pwmgen.make-pulses", false, move |ctx| {
        let p = ctx.period();
        pn.store(p, Relaxed);
        for ch in pulses.iter_mut() {
            let sh = &ch.shared;
            let mode = Mode::from_u8(sh.mode.load(Relaxed));
            let out = ch
                .timers
                .step(mode, sh.period.load(Relaxed), sh.high_time.load(Relaxed), p);
            match &ch.outputs {
                Outputs::Pwm(pwm) | Outputs::PwmDir(pwm) => pwm.set(out),
                Outputs::UpDown(up, down) => {
                    let dir = sh.direction.load(Relaxed);
                    up.set(out && !dir);
                    down.set(out && dir);
                }
            }
        }
    })?;
    let mut oldperiodns: i64 = -1;
    b.funct("pwmgen.update", true, move |_| {
        let periodns = periodns.load(Relaxed);
        for ch in updates.iter_mut() {
            let before = Settings {
                scale: ch.scale.get(),
                pwm_freq: ch.pwm_freq.get(),
                min_dc: ch.min_dc.get(),
                max_dc: ch.max_dc.get(),
            };
            let cmd = Command {
                enable: ch.enable.get(),
                dither: ch.dither.get(),
                value: ch.value.get(),
                offset: ch.offset.get(),
            };
            let mut s = before;
            let t = ch.gen.update(&mut s, &cmd, periodns, oldperiodns);
            write_back(&ch.max_dc, before.max_dc, s.max_dc);
            write_back(&ch.min_dc, before.min_dc, s.min_dc);
            write_back(&ch.scale, before.scale, s.scale);
            write_back(&ch.pwm_freq, before.pwm_freq, s.pwm_freq);
            let sh = &ch.shared;
            if t.recalculated {
                // As in LinuxCNC, the channel is disabled while its period
                // changes.
                sh.mode.store(Mode::Disabled as u8, Relaxed);
            }
            sh.period.store(t.period, Relaxed);
            sh.high_time.store(t.high_time, Relaxed);
            sh.direction.store(t.direction, Relaxed);
            sh.mode.store(t.mode as u8, Relaxed);
            ch.curr_dc.set(t.curr_dc);
            if let Some(dir) = &ch.dir {
                dir.set(t.direction);
            }
        }
        oldperiodns = periodns;
    })?;
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::pin_names;

    const P: i64 = 50_000;

    fn cmd(value: f64) -> Command {
        Command {
            enable: true,
            dither: false,
            value,
            offset: 0.0,
        }
    }

    fn freq(f: f64) -> Settings {
        Settings {
            pwm_freq: f,
            ..Settings::default()
        }
    }

    /// Runs make-pulses `n` times with `t`, returning the outputs.
    fn pulses(timers: &mut PulseTimers, t: &Timing, n: usize) -> Vec<bool> {
        (0..n)
            .map(|_| timers.step(t.mode, t.period, t.high_time, P))
            .collect()
    }

    #[test]
    fn pure_pwm_uses_whole_periods() {
        let mut g = Generator::new(0);
        let mut s = freq(2000.0);
        let t = g.update(&mut s, &cmd(0.34), P, -1);
        assert!(t.recalculated);
        assert_eq!(t.mode, Mode::Pure);
        assert_eq!(t.period, 10 * P);
        assert_eq!(s.pwm_freq, 2000.0);
        // 10 * 0.34 + 0.5 = 3.9 -> 3 periods high.
        assert_eq!(t.high_time, 3 * P);
        assert_eq!(t.curr_dc, 3.0 * (1.0 / 10.0));
        let mut timers = PulseTimers::default();
        let out = pulses(&mut timers, &t, 30);
        // The first period starts after the first full period has passed.
        assert_eq!(out[..10].iter().filter(|&&o| o).count(), 1);
        let cycle: Vec<bool> = (0..10).map(|i| i < 3).collect();
        assert_eq!(&out[9..19], &cycle[..]);
        assert_eq!(&out[19..29], &cycle[..]);
        // Nothing changes: no recalculation.
        let t2 = g.update(&mut s, &cmd(0.34), P, P);
        assert!(!t2.recalculated);
    }

    #[test]
    fn pure_pwm_rewrites_frequency_to_the_achievable_one() {
        let mut g = Generator::new(0);
        let mut s = freq(3000.0);
        let t = g.update(&mut s, &cmd(0.5), P, -1);
        // 1e9/3000/50000 = 6.67 -> 7 periods.
        assert_eq!(t.period, 7 * P);
        assert_eq!(s.pwm_freq, 1.0e9 / (7 * P) as f64);
        // Too fast: two make-pulses periods at most.
        let mut s = freq(1e6);
        let t = g.update(&mut s, &cmd(0.5), P, P);
        assert_eq!(t.period, 2 * P);
        assert_eq!(s.pwm_freq, 10_000.0);
        // Too slow: 0.5 Hz at least.
        let mut s = freq(0.1);
        let t = g.update(&mut s, &cmd(0.5), P, P);
        assert_eq!(s.pwm_freq, 0.5);
        assert_eq!(t.period, 40_000 * P);
        // Negative means PDM.
        let mut s = freq(-5.0);
        let t = g.update(&mut s, &cmd(0.5), P, P);
        assert_eq!(s.pwm_freq, 0.0);
        assert_eq!(t.period, P);
        let t = g.update(&mut s, &cmd(0.5), P, P);
        assert_eq!(t.mode, Mode::Pdm);
    }

    #[test]
    fn dither_carries_the_remainder() {
        let mut g = Generator::new(0);
        let mut s = freq(7000.0);
        let c = Command {
            dither: true,
            ..cmd(0.25)
        };
        let t = g.update(&mut s, &c, P, -1);
        assert_eq!(t.mode, Mode::Dither);
        assert_eq!(t.period, f64_to_i64(1.0e9 / 7000.0));
        assert_eq!(s.pwm_freq, 7000.0, "not rewritten in dither mode");
        assert_eq!(t.high_time, f64_to_i64(t.period as f64 * 0.25 + 0.5));
        assert_eq!(t.curr_dc, 0.25);
        let mut timers = PulseTimers::default();
        let n = 7000;
        let high = pulses(&mut timers, &t, n).iter().filter(|&&o| o).count();
        // Over many periods the duty cycle averages out to 25 %.
        assert!((high as f64 / n as f64 - 0.25).abs() < 0.01, "{high}");
    }

    #[test]
    fn pdm_spreads_pulses() {
        let mut g = Generator::new(0);
        let mut s = freq(0.0);
        let t = g.update(&mut s, &cmd(0.5), P, -1);
        assert_eq!(t.mode, Mode::Pdm);
        assert_eq!(t.high_time, 25_000);
        let mut timers = PulseTimers::default();
        let out = pulses(&mut timers, &t, 6);
        assert_eq!(out, [true, false, true, false, true, false]);
        let t = g.update(&mut s, &cmd(0.25), P, P);
        let out = pulses(&mut timers, &t, 8);
        assert_eq!(out.iter().filter(|&&o| o).count(), 2);
    }

    #[test]
    fn duty_cycle_limits_are_corrected_and_applied() {
        let mut g = Generator::new(1);
        let mut s = Settings {
            min_dc: 0.2,
            max_dc: 1.5,
            ..freq(0.0)
        };
        let t = g.update(&mut s, &cmd(0.01), P, -1);
        assert_eq!(s.max_dc, 1.0);
        assert_eq!(t.curr_dc, 0.2);
        assert!(!t.direction);
        let t = g.update(&mut s, &cmd(-0.01), P, P);
        assert_eq!(t.curr_dc, -0.2);
        assert!(t.direction);
        let t = g.update(&mut s, &cmd(-3.0), P, P);
        assert_eq!(t.curr_dc, -1.0);
        assert_eq!(t.high_time, P);
        // min above max: min drops to max.
        let mut s = Settings {
            min_dc: 0.8,
            max_dc: 0.6,
            ..freq(0.0)
        };
        g.update(&mut s, &cmd(0.0), P, P);
        assert_eq!((s.min_dc, s.max_dc), (0.6, 0.6));
        // Both negative: both end at 0.
        let mut s = Settings {
            min_dc: -0.5,
            max_dc: -0.2,
            ..freq(0.0)
        };
        let t = g.update(&mut s, &cmd(0.7), P, P);
        assert_eq!((s.min_dc, s.max_dc), (0.0, 0.0));
        assert_eq!(t.curr_dc, 0.0);
    }

    #[test]
    fn unipolar_output_has_no_negative_duty() {
        let mut g = Generator::new(0);
        let mut s = Settings {
            min_dc: 0.1,
            ..freq(0.0)
        };
        let t = g.update(&mut s, &cmd(-0.5), P, -1);
        assert_eq!(t.curr_dc, 0.1);
        assert!(!t.direction);
    }

    #[test]
    fn scale_and_offset() {
        let mut g = Generator::new(2);
        let mut s = Settings {
            scale: 10.0,
            ..freq(0.0)
        };
        let c = Command {
            offset: 0.1,
            ..cmd(-4.0)
        };
        let t = g.update(&mut s, &c, P, -1);
        assert_eq!(t.curr_dc, -4.0 * (1.0 / 10.0) + 0.1);
        assert!(t.direction);
        // A scale too close to zero is rewritten to 1.
        s.scale = 1e-21;
        let t = g.update(&mut s, &cmd(0.5), P, P);
        assert_eq!(s.scale, 1.0);
        assert_eq!(t.curr_dc, 0.5);
        s.scale = -1e-20;
        let t = g.update(&mut s, &cmd(0.5), P, P);
        assert_eq!(s.scale, -1e-20, "the limit itself is kept");
        assert_eq!(t.curr_dc, -1.0, "-5e19 is limited to -max-dc");
    }

    #[test]
    fn disable_clears_the_output() {
        let mut g = Generator::new(0);
        let mut s = freq(0.0);
        let t = g.update(&mut s, &cmd(1.0), P, -1);
        let mut timers = PulseTimers::default();
        assert!(pulses(&mut timers, &t, 3).iter().all(|&o| o));
        let c = Command {
            enable: false,
            ..cmd(1.0)
        };
        let t = g.update(&mut s, &c, P, P);
        assert_eq!(t.mode, Mode::Disabled);
        assert_eq!(t.curr_dc, 1.0, "curr-dc still follows the command");
        assert!(pulses(&mut timers, &t, 3).iter().all(|&o| !o));
        assert_eq!((timers.high_timer, timers.period_timer), (0, 0));
    }

    #[test]
    fn update_before_make_pulses_falls_back_to_pdm() {
        let mut g = Generator::new(0);
        let mut s = freq(1000.0);
        let t = g.update(&mut s, &cmd(0.5), -1, -1);
        assert_eq!(s.pwm_freq, -5e8);
        assert_eq!(t.mode, Mode::Pure);
        g.update(&mut s, &cmd(0.5), P, -1);
        assert_eq!(s.pwm_freq, 0.0);
        let t = g.update(&mut s, &cmd(0.5), P, P);
        assert_eq!(t.mode, Mode::Pdm);
    }

    #[test]
    fn period_change_recalculates() {
        let mut g = Generator::new(0);
        let mut s = freq(1000.0);
        let t = g.update(&mut s, &cmd(0.5), P, -1);
        assert_eq!(t.period, 20 * P);
        let t = g.update(&mut s, &cmd(0.5), 2 * P, P);
        assert!(t.recalculated);
        assert_eq!(t.period, 20 * P);
        assert_eq!(t.high_time, 5 * 2 * P);
    }

    #[test]
    fn pins_follow_output_types() {
        let host = crate::testing::host();
        host.loadrt(&MODULE, &["output_type=0,1,2,-1,2"]).unwrap();
        let pins = pin_names(&host);
        let common = [
            "curr-dc",
            "dither-pwm",
            "enable",
            "max-dc",
            "min-dc",
            "offset",
            "pwm-freq",
            "scale",
            "value",
        ];
        let mut want: Vec<String> = Vec::new();
        for (n, extra) in [&["pwm"][..], &["dir", "pwm"], &["down", "up"]]
            .iter()
            .enumerate()
        {
            for item in common.iter().chain(extra.iter()) {
                want.push(format!("pwmgen.{n}.{item}"));
            }
        }
        want.push("pwmgen.make-pulses.time".into());
        want.push("pwmgen.update.time".into());
        want.sort();
        assert_eq!(pins, want);
        assert_eq!(
            host.instance().pin_value("pwmgen.1.max-dc").unwrap(),
            hal_core::Value::Float(1.0)
        );
        assert_eq!(
            host.instance().pin_value("pwmgen.1.scale").unwrap(),
            hal_core::Value::Float(1.0)
        );
    }

    #[test]
    fn bad_output_types_fail_the_load() {
        let host = crate::testing::host();
        for bad in [
            &[][..],
            &["output_type=-1"],
            &["output_type=3"],
            &["output_type=0,-2"],
            &["output_type=0,0,0,0,0,0,0,0,0"],
        ] {
            let e = host.loadrt(&MODULE, bad).unwrap_err();
            assert!(
                matches!(&e, HalError::ModuleParam { param, .. } if param == "output_type"),
                "{bad:?}: {e:?}"
            );
            assert!(pin_names(&host).is_empty(), "{bad:?} left pins behind");
        }
        // An empty item is type 0.
        host.loadrt(&MODULE, &["output_type=,1"]).unwrap();
        assert!(pin_names(&host).contains(&"pwmgen.0.pwm".to_string()));
    }
}
