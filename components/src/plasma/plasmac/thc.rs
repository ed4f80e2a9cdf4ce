//! Torch height control while cutting: when it activates (auto: after
//! steady samples; else `thc-delay` after the cut feed rate is reached),
//! its target voltage (sampled or `cut-volts`, plus `height-override`),
//! the locks that hold it (corner lock: the machine slowed below
//! `cornerlock-threshold` percent of the requested feed, the velocity
//! anti-dive; void lock: the voltage rising faster than
//! `voidlock-slope`; low cut volts) and the correction: a PID on the
//! voltage error, as a Z speed limited to `thc-feed-rate`. In mode 2 the
//! correction is `move-up`/`move-down` at `thc-feed-rate`.

use super::machine::Ctx;

/// What one THC period decides.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ThcStep {
    /// Z offset counts to move (positive: up).
    pub delta: i32,
    /// THC is active.
    pub active: bool,
    /// Corner lock holds it.
    pub cornerlock: bool,
    /// Void lock holds it.
    pub voidlock: bool,
    /// The target voltage.
    pub target: f64,
}

/// The height controller's memory.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Thc {
    /// Active (correcting unless locked).
    pub active: bool,
    /// Seconds at the cut feed rate (delayed activation).
    delay: f64,
    /// Steady samples (auto activation).
    steady: i32,
    /// Sum and count of the target samples.
    sum: f64,
    taken: i32,
    /// The target voltage before the override.
    pub target: f64,
    integral: f64,
    last_err: f64,
    last_volts: f64,
    void_on: i32,
    void_off: i32,
    void_locked: bool,
    /// Seconds without Arc OK (for the arc lost delay).
    pub lost: f64,
}

impl Thc {
    /// Forgets everything (a new cut).
    pub fn reset(&mut self) {
        *self = Thc::default();
    }

    /// One period at arc voltage `volts`, the torch `lit` or not.
    pub fn step(&mut self, c: &Ctx<'_>, volts: f64, lit: bool) -> ThcStep {
        let i = c.i;
        let last = self.last_volts;
        self.last_volts = volts;
        let enabled = i.thc_enable && !i.thc_disable && !i.mesh_enable;
        if !enabled || !lit {
            self.active = false;
            self.integral = 0.0;
            self.delay = 0.0;
            self.steady = 0;
            return ThcStep::default();
        }
        let ovr = if i.feed_override > 0.0 {
            i.feed_override
        } else {
            1.0
        };
        let requested = i.feed_upm * ovr;
        let current = i.current_velocity * 60.0;
        if !self.active {
            self.activate(
                c,
                volts,
                last,
                current >= requested * 0.999 && current > 0.0,
            );
            return ThcStep {
                target: self.target,
                ..ThcStep::default()
            };
        }
        let target = self.target + i.height_override;
        let cornerlock =
            i.cornerlock_enable && current < requested * i.cornerlock_threshold / 100.0;
        let voidlock = self.void_lock(c, volts, last);
        let low = i.low_cut_volts > 0 && volts < f64::from(i.low_cut_volts);
        let mut s = ThcStep {
            active: true,
            cornerlock,
            voidlock,
            target,
            delta: 0,
        };
        if cornerlock || voidlock || low {
            self.integral = 0.0;
            return s;
        }
        let max = i.thc_feed_rate.abs() / 60.0 * c.dt;
        let dz = if i.mode == 2 {
            match (i.move_up, i.move_down) {
                (true, false) => max,
                (false, true) => -max,
                _ => 0.0,
            }
        } else {
            self.pid(c, target - volts) * i.height_per_volt * c.dt
        };
        s.delta = c.counts(dz.clamp(-max, max));
        s
    }

    /// Activation, and the target voltage it takes.
    fn activate(&mut self, c: &Ctx<'_>, volts: f64, last: f64, at_speed: bool) {
        let i = c.i;
        let ready = if i.mode == 2 || !i.thc_auto {
            if at_speed {
                self.delay += c.dt;
            }
            at_speed && self.delay >= i.thc_delay
        } else {
            if volts > 0.0 && (volts - last).abs() <= i.thc_sample_threshold {
                self.steady = self.steady.saturating_add(1);
            } else {
                self.steady = 0;
            }
            self.steady >= i.thc_sample_counts
        };
        if !ready {
            return;
        }
        if i.use_auto_volts && i.mode != 2 {
            self.sum += volts;
            self.taken += 1;
            if self.taken >= i.target_samples.max(1) {
                self.target = self.sum / f64::from(self.taken);
                self.active = true;
            }
        } else {
            self.target = i.cut_volts;
            self.active = true;
        }
    }

    /// Void lock: locks after `voidlock-on-cycles` periods of the voltage
    /// rising faster than `voidlock-slope` V/s, unlocks after
    /// `voidlock-off-cycles` periods below it.
    fn void_lock(&mut self, c: &Ctx<'_>, volts: f64, last: f64) -> bool {
        let i = c.i;
        if !i.voidlock_enable || i.mode == 2 || c.dt <= 0.0 {
            self.void_locked = false;
            return false;
        }
        if (volts - last) / c.dt > f64::from(i.voidlock_slope) {
            self.void_on = self.void_on.saturating_add(1);
            self.void_off = 0;
        } else {
            self.void_off = self.void_off.saturating_add(1);
            self.void_on = 0;
        }
        if self.void_on >= i.voidlock_on_cycles.max(1) {
            self.void_locked = true;
        } else if self.void_off >= i.voidlock_off_cycles.max(1) {
            self.void_locked = false;
        }
        self.void_locked
    }

    /// The PID on the voltage error (volts; positive raises the torch).
    /// Errors within `thc-threshold` make no correction.
    fn pid(&mut self, c: &Ctx<'_>, err: f64) -> f64 {
        let i = c.i;
        if err.abs() < i.thc_threshold {
            self.integral = 0.0;
            self.last_err = err;
            return 0.0;
        }
        self.integral += err * c.dt;
        let deriv = if c.dt > 0.0 {
            (err - self.last_err) / c.dt
        } else {
            0.0
        };
        self.last_err = err;
        let out = i.pid_p_gain * err + i.pid_i_gain * self.integral + i.pid_d_gain * deriv;
        if out.is_finite() {
            out
        } else {
            0.0
        }
    }
}
