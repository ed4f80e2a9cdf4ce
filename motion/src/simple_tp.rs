//! The single-axis trapezoidal planner (LinuxCNC `simple_tp`), used for
//! every joint in free mode (jogs, homing moves), for each world axis in
//! teleop mode and for each axis's external offset.
//!
//! Each period it asks for the largest velocity from which the target can
//! still be reached without overshoot when braking at the acceleration
//! limit in discrete steps, clamps it to the velocity limit, slews the
//! velocity towards it by at most `A·T`, and integrates the position with
//! one forward-Euler step. The arithmetic follows LinuxCNC operation by
//! operation, so positions match bit for bit.

/// The state of one planner. The target and limits may change at any time;
/// the profile re-plans from the current position and velocity.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SimpleTp {
    /// Target position.
    pub pos_cmd: f64,
    /// Velocity limit (a magnitude).
    pub max_vel: f64,
    /// Acceleration limit (a magnitude).
    pub max_acc: f64,
    /// When false the planner brakes to a stop and forgets its target.
    pub enable: bool,
    /// Current position.
    pub curr_pos: f64,
    /// Current velocity.
    pub curr_vel: f64,
    /// Whether motion is in progress: set while away from the target or
    /// while the velocity is not exactly zero.
    pub active: bool,
}

impl SimpleTp {
    /// The dead band around the target: errors within it count as zero.
    /// Written as LinuxCNC evaluates it, `((A·T)·T)·0.001`.
    pub fn tiny_dp(max_acc: f64, period: f64) -> f64 {
        max_acc * period * period * 0.001
    }

    /// Advances one period of `period` seconds with the velocity limit
    /// `max_vel · vel_scale` (`vel_scale` is the free-mode SCALE; 1.0
    /// leaves the limit exactly as set).
    pub fn update(&mut self, period: f64, vel_scale: f64) {
        let max_vel = self.max_vel * vel_scale;
        self.active = false;
        let max_dv = self.max_acc * period;
        let tiny_dp = Self::tiny_dp(self.max_acc, period);
        let mut vel_req;
        if self.enable {
            let pos_err = self.pos_cmd - self.curr_pos;
            if pos_err > tiny_dp {
                vel_req = -max_dv + (2.0 * self.max_acc * pos_err + max_dv * max_dv).sqrt();
                self.active = true;
            } else if pos_err < -tiny_dp {
                vel_req = max_dv - (-2.0 * self.max_acc * pos_err + max_dv * max_dv).sqrt();
                self.active = true;
            } else {
                vel_req = 0.0;
            }
        } else {
            vel_req = 0.0;
            // Forget the target so that re-enabling does not move.
            self.pos_cmd = self.curr_pos;
        }
        if vel_req > max_vel {
            vel_req = max_vel;
        } else if vel_req < -max_vel {
            vel_req = -max_vel;
        }
        if vel_req > self.curr_vel + max_dv {
            self.curr_vel += max_dv;
        } else if vel_req < self.curr_vel - max_dv {
            self.curr_vel -= max_dv;
        } else {
            self.curr_vel = vel_req;
        }
        if self.curr_vel != 0.0 {
            self.active = true;
        }
        self.curr_pos += self.curr_vel * period;
    }

    /// Stops at once: the velocity becomes zero and the target the current
    /// position (jog-stop-immediate, disable).
    pub fn stop_immediately(&mut self) {
        self.enable = false;
        self.curr_vel = 0.0;
        self.pos_cmd = self.curr_pos;
    }

    /// Puts the planner at rest at `pos`: disabled, no velocity, target
    /// `pos` (mode changes, re-synchronising to a joint's command).
    pub fn set_at_rest(&mut self, pos: f64) {
        self.curr_pos = pos;
        self.pos_cmd = pos;
        self.curr_vel = 0.0;
        self.enable = false;
        self.active = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: f64 = 0.001;

    fn planner(v: f64, a: f64) -> SimpleTp {
        SimpleTp {
            max_vel: v,
            max_acc: a,
            enable: true,
            ..SimpleTp::default()
        }
    }

    /// Runs until inactive (or `limit` periods), returning the velocities.
    fn run(tp: &mut SimpleTp, limit: usize) -> Vec<f64> {
        let mut vs = Vec::new();
        for _ in 0..limit {
            tp.update(T, 1.0);
            vs.push(tp.curr_vel);
            if !tp.active {
                break;
            }
        }
        vs
    }

    #[test]
    fn step_response_is_a_trapezoid_within_the_limits() {
        let mut tp = planner(10.0, 100.0);
        tp.pos_cmd = 2.0;
        let vs = run(&mut tp, 100_000);
        assert!(!tp.active);
        assert!((tp.curr_pos - 2.0).abs() <= SimpleTp::tiny_dp(100.0, T));
        let dv = 100.0 * T;
        let mut prev = 0.0;
        for &v in &vs {
            assert!(v.abs() <= 10.0);
            assert!((v - prev).abs() <= dv * (1.0 + 1e-12));
            assert!(v >= 0.0, "no overshoot, so never backwards");
            prev = v;
        }
        // It reaches the velocity limit and cruises.
        assert!(vs.iter().filter(|&&v| v == 10.0).count() > 50);
        // First step: exactly A·T.
        assert_eq!(vs[0], dv);
    }

    #[test]
    fn first_cycle_numbers() {
        let mut tp = planner(1.0, 10.0);
        tp.pos_cmd = 1.0;
        tp.update(T, 1.0);
        // vel_req = -0.01 + sqrt(20 + 1e-4) is far above; slew by A·T.
        assert_eq!(tp.curr_vel, 10.0 * T);
        assert_eq!(tp.curr_pos, 10.0 * T * T);
        assert!(tp.active);
    }

    #[test]
    fn reversal_goes_through_zero_at_slope_a() {
        let mut tp = planner(5.0, 50.0);
        tp.pos_cmd = 10.0;
        for _ in 0..300 {
            tp.update(T, 1.0);
        }
        assert_eq!(tp.curr_vel, 5.0);
        tp.pos_cmd = -10.0;
        let mut prev = tp.curr_vel;
        let mut saw_zero = false;
        for _ in 0..400 {
            tp.update(T, 1.0);
            let d = tp.curr_vel - prev;
            assert!((-50.0 * T * (1.0 + 1e-12)..=0.0).contains(&d));
            saw_zero |= tp.curr_vel.abs() < 1e-12;
            prev = tp.curr_vel;
        }
        assert!(saw_zero);
        assert!(tp.curr_vel < 0.0);
    }

    #[test]
    fn lowering_the_limit_decelerates_at_a() {
        let mut tp = planner(5.0, 50.0);
        tp.pos_cmd = 100.0;
        for _ in 0..200 {
            tp.update(T, 1.0);
        }
        assert_eq!(tp.curr_vel, 5.0);
        tp.max_vel = 1.0;
        let mut n = 0;
        while tp.curr_vel > 1.0 {
            let before = tp.curr_vel;
            tp.update(T, 1.0);
            assert!((before - tp.curr_vel - 50.0 * T).abs() < 1e-9 || tp.curr_vel == 1.0);
            n += 1;
        }
        assert!((80..=81).contains(&n), "{n}");
        assert_eq!(tp.curr_vel, 1.0);
    }

    #[test]
    fn disable_brakes_at_a_and_forgets_the_target() {
        let mut tp = planner(5.0, 50.0);
        tp.pos_cmd = 100.0;
        for _ in 0..200 {
            tp.update(T, 1.0);
        }
        tp.enable = false;
        let mut steps = 0;
        while tp.active {
            tp.update(T, 1.0);
            steps += 1;
        }
        // 5 / (50·T) = 100 braking steps (one more if rounding leaves a crumb).
        assert!((100..=101).contains(&steps), "{steps}");
        assert_eq!(tp.curr_vel, 0.0);
        assert_eq!(tp.pos_cmd, tp.curr_pos);
        let here = tp.curr_pos;
        tp.enable = true;
        tp.update(T, 1.0);
        assert_eq!(tp.curr_pos, here, "re-enabling does not move");
    }

    #[test]
    fn retarget_while_decelerating() {
        let mut tp = planner(5.0, 50.0);
        tp.pos_cmd = 1.0;
        while tp.curr_pos < 0.9 {
            tp.update(T, 1.0);
        }
        tp.pos_cmd = 1.5;
        let vs = run(&mut tp, 10_000);
        assert!(vs.iter().all(|&v| v >= 0.0));
        assert!((tp.curr_pos - 1.5).abs() <= SimpleTp::tiny_dp(50.0, T));
    }

    #[test]
    fn scale_limits_the_velocity() {
        let mut tp = planner(4.0, 100.0);
        tp.pos_cmd = 10.0;
        for _ in 0..1000 {
            tp.update(T, 0.25);
            assert!(tp.curr_vel <= 1.0);
        }
        assert_eq!(tp.curr_vel, 1.0);
        // Zero scale: a controlled stop that keeps the target.
        let mut n = 0;
        while tp.curr_vel > 0.0 {
            tp.update(T, 0.0);
            n += 1;
        }
        assert!((10..=11).contains(&n), "{n}");
        assert_eq!(tp.pos_cmd, 10.0);
        assert!(tp.active, "still away from the target");
    }

    #[test]
    fn stop_immediately_zeroes_velocity() {
        let mut tp = planner(4.0, 100.0);
        tp.pos_cmd = 10.0;
        for _ in 0..100 {
            tp.update(T, 1.0);
        }
        tp.stop_immediately();
        let here = tp.curr_pos;
        tp.update(T, 1.0);
        assert_eq!(tp.curr_pos, here);
        assert!(!tp.active);
    }
}
