//! The canonical step generator, for drivers whose hardware makes the
//! pulses (hostmot2 and the like): the driver reads the hardware's step
//! count, calls [`Stepgen::update`] once per servo period, and programs
//! the returned step rate and the step timing in hardware clocks.
//!
//! | name | kind | type | dir | unit | meaning |
//! |---|---|---|---|---|---|
//! | `position-cmd` | pin | float | in | units | target position (position mode) |
//! | `velocity-cmd` | pin | float | in | units/s | target velocity (velocity mode) |
//! | `control-type` | pin | bit | in | | FALSE position mode, TRUE velocity mode |
//! | `enable` | pin | bit | in | | FALSE: no steps; the rate drops to 0 at once |
//! | `counts` | pin | s32 | out | steps | steps made (low 32 bits) |
//! | `position-fb` | pin | float | out | units | `counts / position-scale` |
//! | `velocity-fb` | pin | float | out | units/s | the commanded rate, in units |
//! | `position-scale` | param | float | rw | steps/unit | default 1.0; within 1e-20 of 0 is replaced by 1.0 ([`usable_scale`]) |
//! | `maxvel` | param | float | rw | units/s | 0: the most the step timing allows |
//! | `maxaccel` | param | float | rw | units/s² | 0: no limit (default 1.0) |
//! | `steplen` | param | u32 | rw | ns | step pulse length |
//! | `stepspace` | param | u32 | rw | ns | least time between pulses |
//! | `dirsetup` | param | u32 | rw | ns | direction stable before a step |
//! | `dirhold` | param | u32 | rw | ns | direction stable after a step |
//!
//! Position mode commands the position command's own velocity (feed
//! forward, so a moving target is followed without lag) plus a correction
//! that closes the remaining error in one period, capped at the speed from
//! which the error can still be stopped at `maxaccel` with the rate held
//! for whole periods; the total is capped by `maxvel` and changes by at
//! most `maxaccel × period` per period. Velocity mode ramps toward
//! `velocity-cmd` within the same limits. The fastest step rate is one
//! step per `steplen + stepspace`. A NaN command or feedback gives rate 0,
//! and limits that are not finite numbers are ignored: nothing here can
//! panic on what a user sets.

use hal_core::{HalHost, HostParam, HostPin, In, Ours, Out, PinFactory, Result, Rw};

use crate::naming::{ChannelNames, Interface};
use crate::usable_scale;

/// The limits one update obeys, in units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Steps per unit (non-zero).
    pub scale: f64,
    /// Units/s; 0 for "as fast as the timing allows".
    pub maxvel: f64,
    /// Units/s²; 0 for none.
    pub maxaccel: f64,
    /// Nanoseconds per step at the fastest: steplen + stepspace.
    pub min_step_ns: u64,
}

impl Limits {
    /// The velocity limit in units/s, from `maxvel` and the step timing.
    pub fn vmax(&self) -> f64 {
        let by_timing = if self.min_step_ns > 0 {
            1e9 / self.min_step_ns as f64 / self.scale.abs()
        } else {
            f64::INFINITY
        };
        if self.maxvel > 0.0 {
            self.maxvel.min(by_timing)
        } else {
            by_timing
        }
    }
}

/// The commanded rate of one period, in units/s, for position mode:
/// `cmd` and `prev_cmd` are this and the previous period's command.
pub fn position_rate(cmd: f64, prev_cmd: f64, fb: f64, v_prev: f64, dt: f64, lim: &Limits) -> f64 {
    let ffw = (cmd - prev_cmd) / dt;
    // The error left once the target's own motion is accounted for: zero
    // while following a steady ramp one period behind.
    let err = cmd - fb - ffw * dt;
    let mut corr = err / dt;
    let a = lim.maxaccel;
    if a > 0.0 && a.is_finite() {
        // The fastest correction from which the error can still be
        // stopped, decelerating by a·dt each period: the largest v with
        // v·dt·(n+1) - a·dt²·n(n+1)/2 <= |err| for v = n·a·dt.
        let step = a * dt;
        let stop = step * ((0.25 + 2.0 * err.abs() / (step * dt)).sqrt() - 0.5);
        corr = corr.max(-stop).min(stop);
    }
    limit(ffw + corr, v_prev, dt, lim)
}

/// The commanded rate of one period, in units/s, for velocity mode.
pub fn velocity_rate(cmd: f64, v_prev: f64, dt: f64, lim: &Limits) -> f64 {
    limit(cmd, v_prev, dt, lim)
}

fn limit(v: f64, v_prev: f64, dt: f64, lim: &Limits) -> f64 {
    if !v.is_finite() || !v_prev.is_finite() {
        return 0.0;
    }
    let vmax = lim.vmax();
    let mut v = if vmax.is_nan() {
        v
    } else {
        v.max(-vmax).min(vmax)
    };
    if lim.maxaccel > 0.0 && lim.maxaccel.is_finite() {
        let dv = lim.maxaccel * dt;
        v = v.max(v_prev - dv).min(v_prev + dv);
    }
    v
}

/// What [`Stepgen::command`] computed for one period.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepCommand {
    /// The step rate to program, steps/s (0 while disabled).
    pub rate: f64,
    /// The position command's own velocity, units/s.
    pub feed_forward: f64,
    /// Position command minus feedback, units.
    pub position_error: f64,
}

/// Step timing in hardware clock ticks, each at least one tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimingTicks {
    /// Step pulse length.
    pub steplen: u32,
    /// Least time between two pulses.
    pub stepspace: u32,
    /// Direction held stable before a step.
    pub dirsetup: u32,
    /// Direction held stable after a step.
    pub dirhold: u32,
}

/// Converts nanoseconds to ticks of a `clock_hz` clock, rounding up.
pub fn ticks(ns: u32, clock_hz: u64) -> u32 {
    let t = (ns as u128 * clock_hz as u128).div_ceil(1_000_000_000);
    t.clamp(1, u32::MAX as u128) as u32
}

/// A canonical step generator channel.
pub struct Stepgen<H: HalHost = Ours> {
    position_cmd: H::Pin<f64, In>,
    velocity_cmd: H::Pin<f64, In>,
    control_type: H::Pin<bool, In>,
    enable: H::Pin<bool, In>,
    counts: H::Pin<i32, Out>,
    position_fb: H::Pin<f64, Out>,
    velocity_fb: H::Pin<f64, Out>,
    position_scale: H::Param<f64, Rw>,
    maxvel: H::Param<f64, Rw>,
    maxaccel: H::Param<f64, Rw>,
    steplen: H::Param<u32, Rw>,
    stepspace: H::Param<u32, Rw>,
    dirsetup: H::Param<u32, Rw>,
    dirhold: H::Param<u32, Rw>,
    rate: f64,
    /// The previous period's position command (for feed forward).
    prev_cmd: Option<f64>,
}

impl Interface for Stepgen {
    const IO_TYPE: &'static str = "stepgen";
}

impl<H: HalHost> Stepgen<H> {
    /// Exports channel `chan` on `comp`.
    pub fn export(comp: &impl PinFactory<H>, names: &ChannelNames, chan: usize) -> Result<Self> {
        let n = |s: &str| names.item(chan, s);
        Ok(Stepgen {
            position_cmd: comp.pin(&n("position-cmd"))?,
            velocity_cmd: comp.pin(&n("velocity-cmd"))?,
            control_type: comp.pin(&n("control-type"))?,
            enable: comp.pin(&n("enable"))?,
            counts: comp.pin(&n("counts"))?,
            position_fb: comp.pin(&n("position-fb"))?,
            velocity_fb: comp.pin(&n("velocity-fb"))?,
            position_scale: comp.param(&n("position-scale"), 1.0)?,
            maxvel: comp.param(&n("maxvel"), 0.0)?,
            maxaccel: comp.param(&n("maxaccel"), 1.0)?,
            steplen: comp.param(&n("steplen"), 0)?,
            stepspace: comp.param(&n("stepspace"), 0)?,
            dirsetup: comp.param(&n("dirsetup"), 0)?,
            dirhold: comp.param(&n("dirhold"), 0)?,
            rate: 0.0,
            prev_cmd: None,
        })
    }

    /// One servo period: `steps` is the hardware's step count (its low 32
    /// bits are published), `fine_position` its position in steps with a
    /// fraction if the hardware has one. Returns the step rate to program,
    /// in steps/s (signed; 0 while disabled).
    pub fn update(&mut self, steps: i64, fine_position: f64, period_ns: i64) -> f64 {
        self.publish_feedback(steps, fine_position);
        self.command(fine_position, period_ns).rate
    }

    /// The feedback half of [`update`](Self::update), for drivers that
    /// read the hardware in one function and program it in another
    /// (hostmot2's `read` and `write`): publishes `counts` and
    /// `position-fb`.
    pub fn publish_feedback(&self, steps: i64, fine_position: f64) {
        let scale = usable_scale(&self.position_scale);
        self.counts.set(steps as i32);
        self.position_fb.set(fine_position / scale);
    }

    /// The command half of [`update`](Self::update): the step rate for
    /// this period from the hardware position `fine_position` (in steps),
    /// with the quantities it was computed from.
    pub fn command(&mut self, fine_position: f64, period_ns: i64) -> StepCommand {
        let scale = usable_scale(&self.position_scale);
        let fb = fine_position / scale;
        let cmd = self.position_cmd.get();
        let prev_cmd = self.prev_cmd.replace(cmd).unwrap_or(cmd);
        let dt = period_ns as f64 * 1e-9;
        let mut out = StepCommand {
            rate: 0.0,
            feed_forward: if period_ns > 0 {
                (cmd - prev_cmd) / dt
            } else {
                0.0
            },
            position_error: cmd - fb,
        };
        if !self.enable.get() || period_ns <= 0 {
            self.rate = 0.0;
            self.velocity_fb.set(0.0);
            return out;
        }
        let lim = Limits {
            scale,
            maxvel: self.maxvel.get(),
            maxaccel: self.maxaccel.get(),
            min_step_ns: self.steplen.get() as u64 + self.stepspace.get() as u64,
        };
        self.rate = if self.control_type.get() {
            velocity_rate(self.velocity_cmd.get(), self.rate, dt, &lim)
        } else {
            position_rate(cmd, prev_cmd, fb, self.rate, dt, &lim)
        };
        self.velocity_fb.set(self.rate);
        out.rate = self.rate * scale;
        out
    }

    /// The position scale in force (steps per unit, never 0).
    pub fn scale(&self) -> f64 {
        usable_scale(&self.position_scale)
    }

    /// The timing params in ns: steplen, stepspace, dirsetup, dirhold.
    pub fn timing_ns(&self) -> [u32; 4] {
        [
            self.steplen.get(),
            self.stepspace.get(),
            self.dirsetup.get(),
            self.dirhold.get(),
        ]
    }

    /// Sets the timing params (ns; same order as
    /// [`timing_ns`](Self::timing_ns)): a driver's defaults, or the
    /// values its hardware can do when a user asked for more.
    pub fn set_timing_ns(&self, ns: [u32; 4]) {
        self.steplen.set(ns[0]);
        self.stepspace.set(ns[1]);
        self.dirsetup.set(ns[2]);
        self.dirhold.set(ns[3]);
    }

    /// The step timing in ticks of a `clock_hz` hardware clock.
    pub fn timing(&self, clock_hz: u64) -> TimingTicks {
        TimingTicks {
            steplen: ticks(self.steplen.get(), clock_hz),
            stepspace: ticks(self.stepspace.get(), clock_hz),
            dirsetup: ticks(self.dirsetup.get(), clock_hz),
            dirhold: ticks(self.dirhold.get(), clock_hz),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIM: Limits = Limits {
        scale: 200.0,
        maxvel: 10.0,
        maxaccel: 50.0,
        min_step_ns: 0,
    };

    /// Simulates the hardware following the commanded rate exactly.
    fn run(cmd: f64, lim: &Limits, periods: usize) -> (f64, Vec<f64>) {
        let dt = 0.001;
        let (mut pos, mut v) = (0.0, 0.0);
        let mut rates = Vec::new();
        for _ in 0..periods {
            v = position_rate(cmd, cmd, pos, v, dt, lim);
            pos += v * dt;
            rates.push(v);
        }
        (pos, rates)
    }

    #[test]
    fn position_mode_arrives_within_the_limits() {
        for target in [10.0, -3.7, 0.001, 25.0] {
            let (pos, rates) = run(target, &LIM, 5000);
            assert!(
                (pos - target).abs() < 1e-9,
                "target {target}: ended at {pos}"
            );
            let mut prev = 0.0;
            for &v in &rates {
                assert!(v.abs() <= LIM.maxvel + 1e-12);
                assert!((v - prev).abs() <= LIM.maxaccel * 0.001 + 1e-9);
                prev = v;
            }
            assert_eq!(*rates.last().unwrap(), 0.0, "stopped at the target");
        }
    }

    #[test]
    fn no_overshoot_for_a_sweep_of_targets() {
        for i in 1..400 {
            let target = i as f64 * 0.037;
            let (pos, rates) = run(target, &LIM, 6000);
            assert!(
                (pos - target).abs() < 1e-9,
                "target {target}: ended at {pos}"
            );
            // Never past the target by half a step (at 200 steps/unit).
            let mut p: f64 = 0.0;
            let mut worst: f64 = 0.0;
            for v in &rates {
                p += v * 0.001;
                worst = worst.max(p - target);
            }
            assert!(
                worst < 0.5 / LIM.scale,
                "target {target}: overshot by {worst}"
            );
        }
    }

    #[test]
    fn a_moving_target_is_followed_without_lag() {
        let (dt, speed) = (0.001, 5.0);
        let (mut pos, mut v, mut prev) = (0.0, 0.0, 0.0);
        let mut worst = 0.0f64;
        for k in 1..3000 {
            let cmd = speed * k as f64 * dt;
            if k > 500 {
                // A command is reached one period after it arrives.
                worst = worst.max((cmd - pos).abs());
            }
            v = position_rate(cmd, prev, pos, v, dt, &LIM);
            prev = cmd;
            pos += v * dt;
        }
        assert!(
            worst <= speed * dt + 1e-9,
            "lag {worst} while following a 5 units/s ramp"
        );
    }

    #[test]
    fn bad_numbers_never_panic() {
        let weird = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 0.0, -1.0, 1e300];
        for &a in &weird {
            for &m in &weird {
                for &x in &weird {
                    let lim = Limits {
                        maxaccel: a,
                        maxvel: m,
                        ..LIM
                    };
                    let v = position_rate(x, 0.0, 1.0, 0.0, 0.001, &lim);
                    let w = position_rate(1.0, x, x, x, 0.001, &lim);
                    let u = velocity_rate(x, 0.0, 0.001, &lim);
                    assert!(
                        v.is_finite() && w.is_finite() && u.is_finite(),
                        "{a} {m} {x}"
                    );
                }
            }
        }
    }

    #[test]
    fn velocity_mode_ramps_and_timing_caps_the_rate() {
        let lim = Limits {
            min_step_ns: 100_000, // 10 kHz at the fastest
            maxvel: 0.0,
            ..LIM
        };
        assert!(
            (lim.vmax() - 50.0).abs() < 1e-9,
            "10 kHz / 200 steps per unit"
        );
        let mut v = 0.0;
        for _ in 0..10 {
            v = velocity_rate(100.0, v, 0.001, &lim);
        }
        assert!((v - 0.5).abs() < 1e-9, "ramping at 50 units/s²: {v}");
        for _ in 0..5000 {
            v = velocity_rate(100.0, v, 0.001, &lim);
        }
        assert!((v - 50.0).abs() < 1e-9, "capped by the step timing: {v}");
        assert_eq!(velocity_rate(f64::NAN, 0.0, 0.001, &lim), 0.0);
    }

    #[test]
    fn ticks_round_up_and_never_vanish() {
        assert_eq!(ticks(5000, 100_000_000), 500);
        assert_eq!(ticks(1, 100_000_000), 1);
        assert_eq!(ticks(0, 100_000_000), 1);
        assert_eq!(ticks(15, 100_000_000), 2);
    }
}
