//! moveoff's limiter: one step of an older form of limit3's planner,
//! following a goal within position, velocity and acceleration limits.
//!
//! **Quirk** (LinuxCNC's, kept): from rest with a speed a hair below
//! zero and the goal below, the planner's look-ahead picks the wrong
//! ramp every other step, and the output creeps slowly away from the
//! goal instead of going to it. It happens where a move was stopped
//! short of its goal (the waypoint limit does that).

/// Limits of one joint's offset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Lowest offset.
    pub min: f64,
    /// Highest offset.
    pub max: f64,
    /// Largest speed.
    pub maxv: f64,
    /// Largest acceleration.
    pub maxa: f64,
}

/// The limiter's memory for one joint.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Limiter {
    /// The (clamped) goal of the previous step.
    pub old_in: f64,
    /// The output of the previous step.
    pub old_out: f64,
    /// The speed of the previous step.
    pub old_v: f64,
}

impl Limiter {
    /// One step of `dt` seconds toward `goal`; returns the new output.
    pub fn step(&mut self, goal: f64, l: &Limits, dt: f64) -> f64 {
        let mut target = goal;
        if goal < l.min {
            target = l.min;
        }
        if goal > l.max {
            target = l.max;
        }
        let prev_in = self.old_in;
        self.old_in = target;

        let in_v = (target - prev_in) / dt;
        let mut min_v = self.old_v - l.maxa * dt;
        if min_v < -l.maxv {
            min_v = -l.maxv;
        }
        let mut max_v = self.old_v + l.maxa * dt;
        if max_v > l.maxv {
            max_v = l.maxv;
        }
        let min_out = self.old_out + min_v * dt;
        let max_out = self.old_out + max_v * dt;
        let (out, v) = if target >= min_out && target <= max_out && in_v >= min_v && in_v <= max_v {
            (target, (target - self.old_out) / dt)
        } else {
            // Ramp toward the goal's speed, or away if that ends closer.
            let mut ramp_a = if in_v > self.old_v { l.maxa } else { -l.maxa };
            let match_time = (in_v - self.old_v) / ramp_a;
            let avg_v = (in_v + self.old_v + ramp_a * dt) * 0.5;
            let est_out = self.old_out + avg_v * match_time;
            let est_in = prev_in + in_v * match_time;
            let err = est_out - est_in;
            let dv = -2.0 * ramp_a * dt;
            let dp = dv * match_time;
            if (err + dp * 2.0).abs() < err.abs() {
                ramp_a = -ramp_a;
            }
            if ramp_a < 0.0 {
                (min_out, min_v)
            } else {
                (max_out, max_v)
            }
        };
        self.old_out = out;
        self.old_v = v;
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const L: Limits = Limits {
        min: -1e20,
        max: 1e20,
        maxv: 10.0,
        maxa: 100.0,
    };

    #[test]
    fn a_reachable_goal_is_followed_exactly() {
        let mut l = Limiter::default();
        assert_eq!(l.step(0.0001, &L, 0.001), 0.0001);
        assert!((l.old_v - 0.1).abs() < 1e-12);
    }

    #[test]
    fn a_far_goal_is_reached_within_the_limits() {
        let mut l = Limiter::default();
        let mut prev = (0.0, 0.0);
        for _ in 0..2000 {
            let out = l.step(1.0, &L, 0.001);
            let v = (out - prev.0) / 0.001;
            assert!(v.abs() <= L.maxv + 1e-9, "speed {v}");
            assert!(((v - prev.1) / 0.001).abs() <= L.maxa + 1e-6, "accel");
            prev = (out, v);
        }
        assert!(
            (prev.0 - 1.0).abs() < 1e-9,
            "settles on the goal: {}",
            prev.0
        );
    }

    #[test]
    fn quirk_rest_with_a_tiny_negative_speed_never_starts() {
        let mut l = Limiter {
            old_in: 0.0,
            old_out: 0.4,
            old_v: -1e-16,
        };
        for _ in 0..1000 {
            l.step(0.0, &L, 0.001);
        }
        assert!(l.old_out >= 0.4, "{}", l.old_out);
        // From exact rest it goes.
        let mut l = Limiter { old_v: 0.0, ..l };
        for _ in 0..1000 {
            l.step(0.0, &L, 0.001);
        }
        assert!(l.old_out.abs() < 1e-9, "{}", l.old_out);
    }

    #[test]
    fn the_goal_is_clamped_to_the_position_limits() {
        let mut l = Limiter::default();
        let lim = Limits {
            min: -0.5,
            max: 0.5,
            ..L
        };
        for _ in 0..2000 {
            l.step(3.0, &lim, 0.001);
        }
        assert!((l.old_out - 0.5).abs() < 1e-9);
        assert_eq!(l.old_in, 0.5);
    }
}
