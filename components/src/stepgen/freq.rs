//! `stepgen.update-freq` and `stepgen.capture-position`: the velocity
//! controller that sets the DDS rate, and the position feedback,
//! independent of HAL pins.

use crate::cmath::{f64_to_i64, ScaleCache};

use super::pulses::{Dds, HALF_STEP, PICKOFF};
use super::steptype::StepType;

/// `2^PICKOFF` as a float: accumulator units per step.
const ONE_STEP_F: f64 = (1i64 << PICKOFF) as f64;

/// make-pulses' period as the module assumes it until make-pulses first
/// runs (ns). **Quirk** kept from LinuxCNC: update-freq uses this even
/// when the real thread period differs.
pub const INITIAL_PERIOD_NS: i64 = 50_000;

/// update-freq's own period as assumed before its first call (ns).
pub const INITIAL_DT_NS: i64 = 1_000_000;

/// Smallest multiple of `inc` that is >= `v` (0 for 0), in unsigned
/// 64-bit arithmetic, truncated to the 32-bit parameter it is stored in.
pub fn ceil_mult(v: u32, inc: i64) -> u32 {
    let inc = inc as u64;
    if v == 0 || inc == 0 {
        return v;
    }
    inc.wrapping_mul((u64::from(v) - 1) / inc + 1) as u32
}

/// The module-wide time constants update-freq derives from the two
/// periods, recomputed when a period changes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreqTiming {
    old_periodns: i64,
    /// make-pulses period in seconds.
    pub periodfp: f64,
    /// Converts steps/s into `addval` units.
    pub freqscale: f64,
    /// Converts steps/s² into `addval` change per make-pulses call.
    pub accelscale: f64,
    old_dtns: i64,
    /// update-freq period in seconds.
    pub dt: f64,
    /// `1 / dt`.
    pub recip_dt: f64,
}

impl Default for FreqTiming {
    /// The load-time values (50 µs make-pulses period, 1 ms update-freq
    /// period).
    fn default() -> FreqTiming {
        let periodfp = INITIAL_PERIOD_NS as f64 * 1e-9;
        let freqscale = ONE_STEP_F * periodfp;
        let dt = INITIAL_DT_NS as f64 * 1e-9;
        FreqTiming {
            old_periodns: INITIAL_PERIOD_NS,
            periodfp,
            freqscale,
            accelscale: freqscale * periodfp,
            old_dtns: INITIAL_DT_NS,
            dt,
            recip_dt: 1.0 / dt,
        }
    }
}

impl FreqTiming {
    /// Takes in make-pulses' last period `periodns` and update-freq's own
    /// `dtns`; returns true if make-pulses' period changed (every channel
    /// must then re-round its timing parameters).
    pub fn update(&mut self, periodns: i64, dtns: i64) -> bool {
        let mut newperiod = false;
        if periodns != self.old_periodns {
            self.old_periodns = periodns;
            self.periodfp = periodns as f64 * 1e-9;
            self.freqscale = ONE_STEP_F * self.periodfp;
            self.accelscale = self.freqscale * self.periodfp;
            newperiod = true;
        }
        if dtns != self.old_dtns {
            self.old_dtns = dtns;
            self.dt = dtns as f64 * 1e-9;
            self.recip_dt = 1.0 / self.dt;
        }
        newperiod
    }
}

/// `1 / 2^PICKOFF`, folded into the scale reciprocal so that it converts
/// accumulator units straight to position units.
const STEP_UNIT: f64 = 1.0 / ONE_STEP_F;

/// The `position-scale` cache update-freq and capture-position share, in
/// its load-time state: old scale and reciprocal 0.0. **Quirk:** an exact
/// 0.0 scale the first time equals the initial old scale and is never
/// corrected.
pub const INITIAL_SCALE_CACHE: ScaleCache = ScaleCache::new(0.0, 0.0);

/// capture-position for one channel: returns (`counts`, `position-fb`).
#[inline]
pub fn capture(accum: i64, scale: &mut f64, cache: &mut ScaleCache) -> (i32, f64) {
    let counts = (accum >> PICKOFF) as i32;
    let recip = cache.check(scale, STEP_UNIT);
    (counts, accum.wrapping_sub(HALF_STEP) as f64 * recip)
}

/// The channel parameters update-freq reads and may rewrite. Timing
/// values are in ns; `hold` is `dirhold` (type 0) or `dirdelay`; `setup`
/// is `dirsetup` (type 0, else 0) and `stepspace` is 0 for types >= 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreqParams {
    /// `position-scale`: steps per position unit (corrected if tiny).
    pub position_scale: f64,
    /// `maxvel` in position units/s (lowered to the hardware limit).
    pub maxvel: f64,
    /// `maxaccel` in position units/s² (lowered to the hardware limit).
    pub maxaccel: f64,
    /// `steplen` (rounded up to whole make-pulses periods).
    pub steplen: u32,
    /// `stepspace` (types 0, 1; else 0).
    pub stepspace: u32,
    /// `dirsetup` (type 0; else 0).
    pub setup: u32,
    /// `dirhold` (type 0) or `dirdelay` (other types).
    pub hold: u32,
    /// The `frequency` param: current rate in steps/s, also the
    /// controller's velocity state.
    pub frequency: f64,
}

impl Default for FreqParams {
    /// The parameters' load-time values.
    fn default() -> FreqParams {
        FreqParams {
            position_scale: 1.0,
            maxvel: 0.0,
            maxaccel: 0.0,
            steplen: 1,
            stepspace: 1,
            setup: 1,
            hold: 1,
            frequency: 0.0,
        }
    }
}

/// What update-freq tells make-pulses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FreqOut {
    /// Disabled: `addval` and `target_addval` are set to 0 (the motor
    /// stops at once, without a ramp).
    Stopped,
    /// Enabled: the new `target_addval` and `deltalim`.
    Target {
        /// The rate make-pulses ramps `addval` toward.
        target_addval: i64,
        /// The largest `addval` change per make-pulses call.
        deltalim: i64,
    },
}

impl FreqOut {
    /// Writes this result into the DDS registers make-pulses reads.
    #[inline(always)]
    pub fn apply(self, dds: &mut Dds) {
        match self {
            FreqOut::Stopped => {
                dds.addval = 0;
                dds.target_addval = 0;
            }
            FreqOut::Target {
                target_addval,
                deltalim,
            } => {
                dds.target_addval = target_addval;
                dds.deltalim = deltalim;
            }
        }
    }
}

/// What update-freq keeps per channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreqCtl {
    kind: u8,
    velocity_mode: bool,
    /// Scaled position command of the previous call (position mode).
    pub old_pos_cmd: f64,
    old_steplen: u32,
    old_stepspace: u32,
    old_hold: u32,
    old_setup: u32,
}

impl FreqCtl {
    /// A channel of `step_type`, position or velocity mode, in its
    /// load-time state.
    pub fn new(step_type: &StepType, velocity_mode: bool) -> FreqCtl {
        FreqCtl {
            kind: step_type.kind(),
            velocity_mode,
            old_pos_cmd: 0.0,
            old_steplen: u32::MAX,
            old_stepspace: u32::MAX,
            old_hold: u32::MAX,
            old_setup: u32::MAX,
        }
    }

    /// One update-freq call for this channel. `t` are the module's time
    /// constants after [`FreqTiming::update`] returned `newperiod`;
    /// `periodns` is make-pulses' period; `cmd` is `position-cmd` or
    /// `velocity-cmd`; `accum` the DDS accumulator.
    #[allow(clippy::too_many_arguments)]
    pub fn update(
        &mut self,
        t: &FreqTiming,
        newperiod: bool,
        periodns: i64,
        cache: &mut ScaleCache,
        p: &mut FreqParams,
        enable: bool,
        cmd: f64,
        accum: i64,
    ) -> FreqOut {
        // Only the correction matters here; the reciprocal is computed for
        // capture-position, which shares the cache.
        cache.check(&mut p.position_scale, STEP_UNIT);
        let s = p.position_scale;
        self.round_timing(newperiod, periodns, p);
        if !enable {
            if !self.velocity_mode {
                self.old_pos_cmd = cmd * s;
            }
            p.frequency = 0.0;
            return FreqOut::Stopped;
        }
        let (max_freq, max_ac) = Self::limits(t, p, s);
        p.frequency = if self.velocity_mode {
            Self::velocity_target(t, p.frequency, cmd * s, max_freq, max_ac)
        } else {
            self.position_target(t, p.frequency, cmd * s, accum, max_freq, max_ac)
        };
        FreqOut::Target {
            target_addval: f64_to_i64(p.frequency * t.freqscale),
            deltalim: f64_to_i64(max_ac * t.accelscale),
        }
    }

    /// Rounds the timing parameters up to whole make-pulses periods and
    /// writes them back (all of them again after a new period).
    fn round_timing(&mut self, newperiod: bool, periodns: i64, p: &mut FreqParams) {
        if newperiod {
            self.old_steplen = u32::MAX;
            self.old_stepspace = u32::MAX;
            self.old_hold = u32::MAX;
            self.old_setup = u32::MAX;
        }
        if p.steplen != self.old_steplen {
            if p.steplen == 0 {
                p.steplen = 1;
            }
            self.old_steplen = ceil_mult(p.steplen, periodns);
            p.steplen = self.old_steplen;
        }
        if p.stepspace != self.old_stepspace {
            self.old_stepspace = ceil_mult(p.stepspace, periodns);
            p.stepspace = self.old_stepspace;
        }
        if p.setup != self.old_setup {
            self.old_setup = ceil_mult(p.setup, periodns);
            p.setup = self.old_setup;
        }
        if p.hold != self.old_hold {
            if p.hold.wrapping_add(p.setup) == 0 && self.kind < 2 {
                p.hold = 1;
            }
            self.old_hold = ceil_mult(p.hold, periodns);
            p.hold = self.old_hold;
        }
    }

    /// The velocity and acceleration limits in steps/s and steps/s²,
    /// lowering `maxvel` and `maxaccel` to what the step timing allows.
    fn limits(t: &FreqTiming, p: &mut FreqParams, s: f64) -> (f64, f64) {
        let min_step_period = p.steplen.wrapping_add(p.stepspace);
        let mut max_freq = 1.0 / (f64::from(min_step_period) * 1e-9);
        let abs_s = s.abs();
        if p.maxvel <= 0.0 {
            p.maxvel = 0.0;
        } else if p.maxvel * abs_s > max_freq {
            // LinuxCNC also prints a message, once per channel, giving
            // the requested and the possible step rates; that is not
            // reproduced (the lowered parameter shows the limit).
            p.maxvel = max_freq / abs_s;
        } else {
            max_freq = p.maxvel * abs_s;
        }
        let mut max_ac = max_freq * t.recip_dt;
        if p.maxaccel <= 0.0 {
            p.maxaccel = 0.0;
        } else if p.maxaccel * abs_s > max_ac {
            p.maxaccel = max_ac / abs_s;
        } else {
            max_ac = p.maxaccel * abs_s;
        }
        (max_freq, max_ac)
    }

    /// Position mode: the velocity (steps/s) that follows the position
    /// command `pos_cmd` (steps) within the limits.
    fn position_target(
        &mut self,
        t: &FreqTiming,
        curr_vel: f64,
        pos_cmd: f64,
        accum: i64,
        max_freq: f64,
        max_ac: f64,
    ) -> f64 {
        let mut new_vel;
        let dt = t.dt;
        let recip_dt = t.recip_dt;
        let vel_cmd = (pos_cmd - self.old_pos_cmd) * recip_dt;
        self.old_pos_cmd = pos_cmd;
        let curr_pos = accum.wrapping_sub(HALF_STEP) as f64 * (1.0 / ONE_STEP_F);
        // Time to match the commanded velocity at full acceleration,
        // and the position error that would remain.
        let mut match_ac = if vel_cmd > curr_vel { max_ac } else { -max_ac };
        let match_time = (vel_cmd - curr_vel) / match_ac;
        let avg_v = (vel_cmd + curr_vel) * 0.5;
        let est_out = curr_pos + avg_v * match_time;
        let est_cmd = pos_cmd + vel_cmd * (match_time - 1.5 * dt);
        let est_err = est_out - est_cmd;
        if match_time < dt {
            // Reachable within one period: close the position error.
            if est_err.abs() < 0.0001 {
                new_vel = vel_cmd;
            } else {
                new_vel = vel_cmd - 0.5 * est_err * recip_dt;
                if new_vel > curr_vel + max_ac * dt {
                    new_vel = curr_vel + max_ac * dt;
                } else if new_vel < curr_vel - max_ac * dt {
                    new_vel = curr_vel - max_ac * dt;
                }
            }
        } else {
            // Still ramping: accelerate toward the command, or the
            // other way if that shrinks the predicted error.
            let dv = -2.0 * match_ac * dt;
            let dp = dv * match_time;
            if (est_err + dp * 2.0).abs() < est_err.abs() {
                match_ac = -match_ac;
            }
            new_vel = curr_vel + match_ac * dt;
        }
        if new_vel > max_freq {
            new_vel = max_freq;
        } else if new_vel < -max_freq {
            new_vel = -max_freq;
        }
        new_vel
    }

    /// Velocity mode: the velocity (steps/s) that ramps toward `vel_cmd`
    /// (steps/s) within the limits.
    fn velocity_target(
        t: &FreqTiming,
        frequency: f64,
        vel_cmd: f64,
        max_freq: f64,
        max_ac: f64,
    ) -> f64 {
        let mut vel_cmd = vel_cmd;
        if vel_cmd > max_freq {
            vel_cmd = max_freq;
        } else if vel_cmd < -max_freq {
            vel_cmd = -max_freq;
        }
        let dv = max_ac * t.dt;
        if vel_cmd > frequency + dv {
            frequency + dv
        } else if vel_cmd < frequency - dv {
            frequency - dv
        } else {
            vel_cmd
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ctl(kind: u8, velocity: bool) -> FreqCtl {
        FreqCtl::new(&StepType::builtin(kind).unwrap(), velocity)
    }

    fn params(kind: u8) -> FreqParams {
        FreqParams {
            setup: if kind == 0 { 1 } else { 0 },
            stepspace: if kind < 2 { 1 } else { 0 },
            ..FreqParams::default()
        }
    }

    #[test]
    fn ceil_mult_rounds_up_to_multiples() {
        assert_eq!(ceil_mult(0, 50_000), 0);
        assert_eq!(ceil_mult(1, 50_000), 50_000);
        assert_eq!(ceil_mult(50_000, 50_000), 50_000);
        assert_eq!(ceil_mult(50_001, 50_000), 100_000);
        // Computed in 64 bits, stored in 32: the top wraps.
        assert_eq!(ceil_mult(u32::MAX, 50_000), (50_000u64 * 85_900) as u32);
    }

    #[test]
    fn load_time_constants_are_the_50us_and_1ms_values() {
        let t = FreqTiming::default();
        assert_eq!(t.periodfp, 50_000.0 * 1e-9);
        assert_eq!(t.freqscale, 268_435_456.0 * (50_000.0 * 1e-9));
        assert_eq!(t.accelscale, t.freqscale * t.periodfp);
        assert_eq!(t.dt, 1_000_000.0 * 1e-9);
        assert_eq!(t.recip_dt, 1.0 / t.dt);
        let mut t2 = t;
        assert!(!t2.update(50_000, 1_000_000));
        assert_eq!(t2, t);
        assert!(t2.update(25_000, 25_000));
        assert_eq!(t2.periodfp, 25_000.0 * 1e-9);
        assert_eq!(t2.dt, 25_000.0 * 1e-9);
        assert!(!t2.update(25_000, 100_000));
    }

    #[test]
    fn scale_correction_and_the_zero_quirk() {
        let mut c = INITIAL_SCALE_CACHE;
        let mut s = 0.0;
        c.check(&mut s, STEP_UNIT);
        assert_eq!((s, c.recip), (0.0, 0.0), "0.0 at first is never seen");
        let (_, fb) = capture(HALF_STEP + (5 << PICKOFF), &mut s, &mut c);
        assert_eq!(fb, 0.0);
        let mut s = 1e-30;
        c.check(&mut s, STEP_UNIT);
        assert_eq!(s, 1.0);
        assert_eq!(c.old_scale, 1e-30);
        assert_eq!(c.recip, 1.0 / ONE_STEP_F);
        let mut s = -2.0;
        let (counts, fb) = capture(HALF_STEP + (5 << PICKOFF), &mut s, &mut c);
        assert_eq!((counts, fb), (5, -2.5));
        // Once 0.0 follows another scale it is corrected.
        let mut s = 0.0;
        c.check(&mut s, STEP_UNIT);
        assert_eq!(s, 1.0);
    }

    #[test]
    fn capture_floors_counts_and_keeps_sub_step_position() {
        let mut c = INITIAL_SCALE_CACHE;
        let mut s = 4.0;
        let (counts, fb) = capture(-(1 << (PICKOFF - 2)), &mut s, &mut c);
        assert_eq!(counts, -1);
        assert_eq!(fb, -0.75 / 4.0);
    }

    #[test]
    fn timing_params_round_to_the_period_and_rerun_on_new_period() {
        let mut f = ctl(0, false);
        let t = FreqTiming::default();
        let mut cache = INITIAL_SCALE_CACHE;
        let mut p = params(0);
        p.steplen = 0;
        p.stepspace = 60_000;
        p.setup = 0;
        p.hold = 0;
        f.update(&t, false, 50_000, &mut cache, &mut p, false, 0.0, HALF_STEP);
        assert_eq!(
            (p.steplen, p.stepspace, p.setup, p.hold),
            (50_000, 100_000, 0, 50_000),
            "steplen 0 -> 1, hold+setup 0 -> hold 1, then rounded"
        );
        // A new period re-rounds the (already rounded) values.
        f.update(&t, true, 30_000, &mut cache, &mut p, false, 0.0, HALF_STEP);
        assert_eq!(
            (p.steplen, p.stepspace, p.setup, p.hold),
            (60_000, 120_000, 0, 60_000)
        );
        // Unchanged values are not rounded again without a new period.
        f.update(&t, false, 70_000, &mut cache, &mut p, false, 0.0, HALF_STEP);
        assert_eq!(p.steplen, 60_000);
        // Types >= 2 may have a zero dirdelay.
        let mut f = ctl(2, false);
        let mut p = params(2);
        p.hold = 0;
        f.update(&t, false, 50_000, &mut cache, &mut p, false, 0.0, HALF_STEP);
        assert_eq!((p.hold, p.setup, p.stepspace), (0, 0, 0));
    }

    #[test]
    fn disabled_stops_at_once_and_tracks_the_command() {
        let mut f = ctl(0, false);
        let t = FreqTiming::default();
        let mut cache = INITIAL_SCALE_CACHE;
        let mut p = params(0);
        p.position_scale = 10.0;
        p.frequency = 1234.0;
        let out = f.update(&t, false, 50_000, &mut cache, &mut p, false, 2.5, HALF_STEP);
        assert_eq!(out, FreqOut::Stopped);
        assert_eq!(p.frequency, 0.0);
        assert_eq!(f.old_pos_cmd, 25.0);
    }

    #[test]
    fn maxvel_and_maxaccel_are_limited_by_the_hardware() {
        let mut f = ctl(0, true);
        let t = FreqTiming::default();
        let mut cache = INITIAL_SCALE_CACHE;
        let mut p = params(0);
        p.steplen = 50_000;
        p.stepspace = 50_000;
        p.position_scale = -100.0;
        p.maxvel = 1000.0; // 100000 steps/s, above 1/100 µs = 10000
        p.maxaccel = 1e9;
        let out = f.update(&t, false, 50_000, &mut cache, &mut p, true, 1e9, HALF_STEP);
        let max_freq = 1.0 / (100_000.0 * 1e-9);
        assert_eq!(p.maxvel, max_freq / 100.0);
        assert_eq!(p.maxaccel, max_freq * t.recip_dt / 100.0);
        // Velocity mode with full acceleration: one dt of ramp, reversed
        // by the negative scale.
        assert_eq!(p.frequency, -(max_freq * t.recip_dt * t.dt));
        assert_eq!(
            out,
            FreqOut::Target {
                target_addval: f64_to_i64(p.frequency * t.freqscale),
                deltalim: f64_to_i64(max_freq * t.recip_dt * t.accelscale),
            }
        );
        // Negative limits read as "none" and are set to 0.
        p.maxvel = -1.0;
        p.maxaccel = -1.0;
        f.update(&t, false, 50_000, &mut cache, &mut p, true, 0.0, HALF_STEP);
        assert_eq!((p.maxvel, p.maxaccel), (0.0, 0.0));
    }

    #[test]
    fn velocity_mode_ramps_by_maxaccel_per_dt() {
        let mut f = ctl(2, true);
        let mut t = FreqTiming::default();
        let np = t.update(25_000, 25_000);
        let mut cache = INITIAL_SCALE_CACHE;
        let mut p = params(2);
        p.position_scale = 2000.0;
        p.maxvel = 5.0;
        p.maxaccel = 400.0;
        let mut freqs = Vec::new();
        for i in 0..2000 {
            f.update(
                &t,
                np && i == 0,
                25_000,
                &mut cache,
                &mut p,
                true,
                2.0,
                HALF_STEP,
            );
            freqs.push(p.frequency);
        }
        let dv = 400.0 * 2000.0 * t.dt;
        assert_eq!(freqs[0], dv);
        assert_eq!(freqs[1], dv + dv);
        // Settles exactly on the command, 4000 steps/s.
        assert_eq!(*freqs.last().unwrap(), 4000.0);
        assert!(freqs.windows(2).all(|w| w[1] >= w[0]));
    }

    #[test]
    fn position_mode_without_limits_jumps_to_the_command_velocity() {
        let mut f = ctl(0, false);
        let t = FreqTiming::default();
        let mut cache = INITIAL_SCALE_CACHE;
        let mut p = params(0);
        // Already at the commanded position: no motion.
        let out = f.update(&t, false, 50_000, &mut cache, &mut p, true, 0.0, HALF_STEP);
        assert_eq!(p.frequency, 0.0);
        assert!(matches!(
            out,
            FreqOut::Target {
                target_addval: 0,
                ..
            }
        ));
    }
}
