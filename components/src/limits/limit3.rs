//! limit3's planner: each call picks the next output so that it follows
//! the input while keeping position within `[min, max]`, speed within
//! `maxv` and acceleration within `maxa`, looking ahead to where the
//! output would stop (or meet the input) at full deceleration.
//!
//! The expressions are grouped exactly as in the reference so results
//! agree with LinuxCNC to the last bit.

use crate::cmath::f64_to_i32;

/// Tolerance used throughout the planner.
const EPS: f64 = 1e-9;

/// The pin values one call of limit3 reads (apart from `out`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limit3Inputs {
    /// `in`: the position to follow.
    pub input: f64,
    /// `enable`: when FALSE the target is 0.0 instead of `in`.
    pub enable: bool,
    /// `load`: jump to the clamped target at once.
    pub load: bool,
    /// `min`: lowest allowed output.
    pub min: f64,
    /// `max`: highest allowed output.
    pub max: f64,
    /// `maxv`: largest speed (units per second).
    pub maxv: f64,
    /// `maxa`: largest acceleration (units per second squared).
    pub maxa: f64,
    /// `smooth-steps`: how many periods ahead the planner starts easing
    /// into the target.
    pub smooth_steps: u32,
}

impl Default for Limit3Inputs {
    /// The pins' defaults.
    fn default() -> Self {
        Limit3Inputs {
            input: 0.0,
            enable: true,
            load: false,
            min: -1e20,
            max: 1e20,
            maxv: 1e20,
            maxa: 1e7,
            smooth_steps: 2,
        }
    }
}

/// limit3's state between calls.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Limit3 {
    /// The target position of the previous call.
    pub in_pos_old: f64,
    /// The output before the previous call wrote it.
    pub out_old: f64,
}

impl Limit3 {
    /// One call: `out_now` is the current value of the `out` pin, `t` the
    /// period in seconds (fperiod). Returns the new output.
    pub fn step(&mut self, p: &Limit3Inputs, out_now: f64, t: f64) -> f64 {
        let x = if p.enable { p.input } else { 0.0 };
        let (o, target) = self.plan(p, x, out_now, t);
        self.out_old = out_now;
        self.in_pos_old = target;
        o
    }

    /// The new output and the target position to remember.
    fn plan(&self, p: &Limit3Inputs, x: f64, out_now: f64, t: f64) -> (f64, f64) {
        if p.load {
            let l = p.max.min(p.min.max(x));
            return (l, l);
        }
        let (min, max, maxv, maxa) = (p.min, p.max, p.maxv, p.maxa);
        let in_vel = (x - self.in_pos_old) / t;
        let out_vel = (out_now - self.out_old) / t;
        let min_vel = (out_vel + (-maxa) * t).max(-maxv);
        let max_vel = (out_vel + maxa * t).min(maxv);
        let min_pos = out_now + min_vel * t;
        let max_pos = out_now + max_vel * t;
        let valid = |pos: f64| pos <= max_pos && pos >= min_pos;

        // Where the output would stop at full deceleration from the
        // fastest speed each way.
        let st_max = ((0.0 - max_vel) / maxa).abs() + t;
        let st_min = ((0.0 - min_vel) / maxa).abs() + t;
        let sp_max = out_now + ((0.0 + max_vel) / 2.0) * st_max;
        let sp_min = out_now + ((0.0 + min_vel) / 2.0) * st_min;
        // Where output and input would meet when matching the input's
        // speed at full acceleration.
        let iv_tmax = ((in_vel - max_vel) / maxa).abs() - t;
        let iv_tmin = ((in_vel - min_vel) / maxa).abs() - t;
        let op_max = max_pos + ((in_vel + max_vel) / 2.0) * iv_tmax;
        let op_min = min_pos + ((in_vel + min_vel) / 2.0) * iv_tmin;
        let ip_max = x + in_vel * iv_tmax;
        let ip_min = x + in_vel * iv_tmin;

        let mut vel_diff = -out_vel;
        let mut ach_min = sp_min;
        let mut ach_max = sp_max;
        let (g_min, g_max, g_cur, g_prev);
        if sp_max > max + EPS && !valid(max) {
            (g_min, g_max, g_cur, g_prev) = (max, max, max, max);
        } else if sp_min < min - EPS && !valid(min) {
            (g_min, g_max, g_cur, g_prev) = (min, min, min, min);
        } else if x >= max && ip_max > op_max {
            (g_min, g_max, g_cur, g_prev) = (max, max, max, max);
        } else if x <= min && ip_min < op_min {
            (g_min, g_max, g_cur, g_prev) = (min, min, min, min);
        } else {
            (g_min, g_max, g_cur, g_prev) = (ip_min, ip_max, x, self.in_pos_old);
            vel_diff = out_vel - in_vel;
            ach_min = op_min;
            ach_max = op_max;
        }

        let pos_diff = out_now - g_prev;
        let tt = if vel_diff.abs() < EPS {
            0.0
        } else {
            pos_diff / ((vel_diff + 0.0) / 2.0)
        };

        if valid(g_cur) && tt.abs() <= t {
            return (g_cur, x);
        }
        if ach_max < g_max + EPS {
            return (max_pos, x);
        }
        if ach_min > g_min - EPS {
            return (min_pos, x);
        }
        if tt.abs() < t * f64::from(p.smooth_steps) {
            let sg = if tt >= 0.0 { 1.0 } else { -1.0 };
            // C truncates the number of periods to an int.
            let ti = f64::from(f64_to_i32((tt - EPS * sg) / t + sg)) * t;
            let a = (vel_diff - 0.0) / ti;
            let v = out_vel + a * t;
            let s = v * t;
            return (max_pos.min(min_pos.max(out_now + s)), x);
        }
        if g_max + EPS < ach_max && g_prev > out_now {
            return (min_pos, x);
        }
        if g_min - EPS > ach_min && g_prev < out_now {
            return (max_pos, x);
        }
        ((min_pos + max_pos) / 2.0, x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: f64 = 1_000_000.0 * 1e-9;

    /// Runs `n` calls with fixed inputs, feeding the output back.
    fn run(p: &Limit3Inputs, n: usize) -> Vec<f64> {
        let mut st = Limit3::default();
        let mut out = 0.0;
        (0..n)
            .map(|_| {
                out = st.step(p, out, T);
                out
            })
            .collect()
    }

    #[test]
    fn velocity_limit_ramps_linearly() {
        let p = Limit3Inputs {
            input: 500.0,
            maxv: 500.0,
            ..Default::default()
        };
        let v = run(&p, 800);
        for (k, o) in v.iter().enumerate() {
            assert_eq!(format!("{o:.6}"), format!("{:.6}", 0.5 * (k + 1) as f64));
        }
    }

    #[test]
    fn acceleration_limit_and_stop_at_max() {
        let p = Limit3Inputs {
            input: 500.0,
            maxv: 500.0,
            maxa: 1000.0,
            max: 160.0,
            ..Default::default()
        };
        let v = run(&p, 800);
        assert_eq!(format!("{:.6}", v[0]), "0.001000");
        assert_eq!(format!("{:.6}", v[1]), "0.003000");
        assert_eq!(format!("{:.6}", v[2]), "0.006000");
        // Stops exactly at max, never beyond.
        assert!(v.iter().all(|&o| o <= 160.0 + 1e-9));
        assert_eq!(format!("{:.6}", v[799]), "160.000000");
        // Acceleration never exceeds maxa (with rounding slack).
        let mut prev = (0.0, 0.0);
        for &o in &v {
            let vel = (o - prev.0) / T;
            assert!(((vel - prev.1) / T).abs() <= 1000.0 * 1.001);
            prev = (o, vel);
        }
    }

    #[test]
    fn load_jumps_and_records_previous_output() {
        let mut st = Limit3::default();
        let p = Limit3Inputs {
            input: 7.0,
            load: true,
            max: 5.0,
            ..Default::default()
        };
        assert_eq!(st.step(&p, 1.5, T), 5.0);
        assert_eq!(st.out_old, 1.5);
        assert_eq!(st.in_pos_old, 5.0);
    }

    #[test]
    fn disabled_targets_zero() {
        let mut st = Limit3 {
            in_pos_old: 0.0,
            out_old: 0.0,
        };
        let p = Limit3Inputs {
            input: 3.0,
            enable: false,
            ..Default::default()
        };
        assert_eq!(st.step(&p, 0.0, T), 0.0);
    }

    #[test]
    fn zero_maxa_propagates_like_c() {
        let p = Limit3Inputs {
            input: 1.0,
            maxa: 0.0,
            ..Default::default()
        };
        let mut st = Limit3::default();
        // Division by zero gives inf/NaN rather than a panic.
        let _ = st.step(&p, 0.0, T);
    }
}
