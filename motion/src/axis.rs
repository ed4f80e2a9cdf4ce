//! One world axis (X Y Z A B C U V W): its configuration, its jog-wheel
//! inputs and the teleop planner that moves it in teleop mode.
//!
//! In teleop mode each of the nine axes has its own [`SimpleTp`] in world
//! coordinates; their positions make the commanded pose, and the inverse
//! kinematics turn that into joint commands (see `core::teleop`). In the
//! world modes an external offset ([`crate::eoffset`]) may be added to the
//! planned position; the axis's limits then bound the sum.

use crate::eoffset::{EoffsetInputs, ExtOffset};
use crate::simple_tp::SimpleTp;

/// The configuration of an axis (LinuxCNC's `[AXIS_L]` values, sent by
/// the axis configuration commands).
///
/// LinuxCNC's motion module starts its axes zeroed and relies on its task
/// to send the INI values; the defaults here are the INI defaults instead:
/// position limits ±1e99 (reference §8.1) and velocity and acceleration
/// limits 1, as for joints, so that an axis never configured can still be
/// jogged, slowly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisConfig {
    /// Lower position limit.
    pub min_pos_limit: f64,
    /// Upper position limit.
    pub max_pos_limit: f64,
    /// Maximum velocity of teleop jogs.
    pub vel_limit: f64,
    /// Maximum acceleration of teleop jogs.
    pub acc_limit: f64,
    /// Maximum jerk of coordinated moves (S-curve planning; 0: none).
    pub jerk_limit: f64,
    /// `OFFSET_AV_RATIO`: the share of the velocity and acceleration limits
    /// kept for the external offset (0..=0.9; 0: no external offset).
    pub eoffset_ratio: f64,
}

impl AxisConfig {
    /// The velocity limit of planned moves (teleop jogs, the coordinated
    /// planner): what the external offset leaves.
    pub fn plan_vel(&self) -> f64 {
        self.vel_limit * (1.0 - self.eoffset_ratio)
    }

    /// The acceleration limit of planned moves.
    pub fn plan_acc(&self) -> f64 {
        self.acc_limit * (1.0 - self.eoffset_ratio)
    }

    /// The velocity and acceleration limits of the external offset.
    pub fn eoffset_limits(&self) -> (f64, f64) {
        (
            self.vel_limit * self.eoffset_ratio,
            self.acc_limit * self.eoffset_ratio,
        )
    }
}

impl Default for AxisConfig {
    fn default() -> Self {
        AxisConfig {
            min_pos_limit: -1e99,
            max_pos_limit: 1e99,
            vel_limit: 1.0,
            acc_limit: 1.0,
            jerk_limit: 0.0,
            eoffset_ratio: 0.0,
        }
    }
}

/// An axis's jog-wheel inputs (`axis.L.jog-*`), read every servo cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisInputs {
    /// `axis.L.jog-counts`.
    pub jog_counts: i32,
    /// `axis.L.jog-enable`.
    pub jog_enable: bool,
    /// `axis.L.jog-scale`: distance per count.
    pub jog_scale: f64,
    /// `axis.L.jog-vel-mode`: stop when the wheel stops.
    pub jog_vel_mode: bool,
    /// `axis.L.jog-accel-fraction` (default 1; used only within (0, 1]).
    pub jog_accel_fraction: f64,
    /// `axis.L.eoffset-*`.
    pub eoffset: EoffsetInputs,
}

impl Default for AxisInputs {
    fn default() -> Self {
        AxisInputs {
            jog_counts: 0,
            jog_enable: false,
            jog_scale: 0.0,
            jog_vel_mode: false,
            jog_accel_fraction: 1.0,
            eoffset: EoffsetInputs::default(),
        }
    }
}

/// The controller's state of one axis.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Axis {
    /// Configuration.
    pub(crate) cfg: AxisConfig,
    /// The teleop planner: its position is the axis's commanded position
    /// in teleop mode.
    pub(crate) teleop_tp: SimpleTp,
    /// A keyboard (command) jog is moving the axis.
    pub(crate) kb_jog_active: bool,
    /// The jog wheel is moving the axis.
    pub(crate) wheel_jog_active: bool,
    /// `jog-counts` as last seen.
    pub(crate) old_jog_counts: i32,
    /// The external offset.
    pub(crate) eoffset: ExtOffset,
}

/// A copy of an axis's state for readers outside the controller.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisStatus {
    /// The homing configuration.
    pub config: AxisConfig,
    /// Teleop planner target (`axis.L.teleop-pos-cmd`).
    pub teleop_pos_cmd: f64,
    /// Teleop planner position.
    pub teleop_pos: f64,
    /// Teleop planner velocity (`axis.L.teleop-vel-cmd`).
    pub teleop_vel_cmd: f64,
    /// Teleop planner velocity limit (`axis.L.teleop-vel-lim`).
    pub teleop_vel_lim: f64,
    /// Teleop planner enabled (`axis.L.teleop-tp-enable`).
    pub teleop_tp_enable: bool,
    /// Teleop planner moving.
    pub teleop_tp_active: bool,
    /// A keyboard (command) jog is active.
    pub kb_jog_active: bool,
    /// A jog-wheel jog is active.
    pub wheel_jog_active: bool,
    /// The applied external offset (`axis.L.eoffset`).
    pub eoffset: f64,
    /// The requested external offset (`axis.L.eoffset-request`).
    pub eoffset_request: f64,
}

/// The acceleration of a wheel jog: `acc_limit × fraction` for a fraction
/// in (0, 1], else `acc_limit` (a fraction of 0 would leave the planner
/// unable to stop).
pub(crate) fn wheel_acc(acc_limit: f64, fraction: f64) -> f64 {
    if fraction > 0.0 && fraction <= 1.0 {
        acc_limit * fraction
    } else {
        acc_limit
    }
}

impl Axis {
    /// A copy of the state.
    pub fn status(&self) -> AxisStatus {
        let tp = &self.teleop_tp;
        AxisStatus {
            config: self.cfg,
            teleop_pos_cmd: tp.pos_cmd,
            teleop_pos: tp.curr_pos,
            teleop_vel_cmd: tp.curr_vel,
            teleop_vel_lim: tp.max_vel,
            teleop_tp_enable: tp.enable,
            teleop_tp_active: tp.active,
            kb_jog_active: self.kb_jog_active,
            wheel_jog_active: self.wheel_jog_active,
            eoffset: self.eoffset.applied(),
            eoffset_request: self.eoffset.request(),
        }
    }

    /// The limits of the planned position: the axis's, less the applied
    /// external offset (their sum must stay within the axis's).
    pub(crate) fn planned_limits(&self) -> (f64, f64) {
        let o = self.eoffset.applied();
        (self.cfg.min_pos_limit - o, self.cfg.max_pos_limit - o)
    }

    /// Whether a keyboard or wheel jog is in progress.
    pub(crate) fn jogging(&self) -> bool {
        self.kb_jog_active || self.wheel_jog_active
    }

    /// Puts the planner at rest at `pos`, disabled, and ends any jog (on
    /// entering a world mode or leaving teleop).
    pub(crate) fn set_at_rest(&mut self, pos: f64) {
        self.teleop_tp.set_at_rest(pos);
        self.kb_jog_active = false;
        self.wheel_jog_active = false;
    }

    /// Ends the jog: a stop at the acceleration limit, or at once
    /// (velocity zeroed) when `immediate`.
    pub(crate) fn abort(&mut self, immediate: bool) {
        if immediate {
            self.teleop_tp.stop_immediately();
        } else {
            self.teleop_tp.enable = false;
        }
        self.kb_jog_active = false;
        self.wheel_jog_active = false;
    }

    /// One teleop period (LinuxCNC's `axis_calc_motion` plus the limit
    /// check): the velocity limit is re-clamped to the axis's planning
    /// limit (it may have been lowered during the jog), the acceleration is
    /// the axis's planning limit (a fraction of it for wheel jogs), the
    /// planner advances with `scale` applied to its velocity limit, and a
    /// position beyond a limit is stopped hard there. The limits are those
    /// of the planned position ([`Axis::planned_limits`]): with an external
    /// offset applied, the sum stops on the axis's limit.
    ///
    /// The hard stop differs from LinuxCNC in two ways, both so that it
    /// cannot leave the planner stuck: the position is clamped onto the
    /// limit (LinuxCNC restores the previous position, up to a period's
    /// travel short of it, and a planner still aiming past the limit then
    /// retries every period), and the planner is disabled there, ending the
    /// jog. Only moves further out are stopped, so an axis that is beyond
    /// a limit (entered teleop there, or its limits were changed) can be
    /// jogged back in.
    pub(crate) fn update(&mut self, period: f64, scale: f64, accel_fraction: f64) {
        let cfg = self.cfg;
        let (min, max) = self.planned_limits();
        let tp = &mut self.teleop_tp;
        if tp.max_vel > cfg.plan_vel() {
            tp.max_vel = cfg.plan_vel();
        }
        tp.max_acc = if self.wheel_jog_active {
            wheel_acc(cfg.plan_acc(), accel_fraction)
        } else {
            cfg.plan_acc()
        };
        let old = tp.curr_pos;
        tp.update(period, scale);
        let new = tp.curr_pos;
        let stop_at = if new > max && new > old {
            Some(old.max(max))
        } else if new < min && new < old {
            Some(old.min(min))
        } else {
            None
        };
        if let Some(pos) = stop_at {
            tp.curr_pos = pos;
            tp.stop_immediately();
            tp.active = false;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: f64 = 0.001;

    fn axis(min: f64, max: f64) -> Axis {
        Axis {
            cfg: AxisConfig {
                min_pos_limit: min,
                max_pos_limit: max,
                vel_limit: 10.0,
                acc_limit: 100.0,
                ..AxisConfig::default()
            },
            ..Axis::default()
        }
    }

    #[test]
    fn defaults_are_the_ini_defaults() {
        let c = AxisConfig::default();
        assert_eq!((c.min_pos_limit, c.max_pos_limit), (-1e99, 1e99));
        assert_eq!((c.vel_limit, c.acc_limit), (1.0, 1.0));
        assert_eq!(AxisInputs::default().jog_accel_fraction, 1.0);
    }

    #[test]
    fn the_velocity_limit_is_reclamped_every_period() {
        let mut a = axis(-100.0, 100.0);
        a.teleop_tp.max_vel = 50.0;
        a.teleop_tp.pos_cmd = 50.0;
        a.teleop_tp.enable = true;
        for _ in 0..1000 {
            a.update(T, 1.0, 1.0);
            assert!(a.teleop_tp.curr_vel <= 10.0);
        }
        assert_eq!(a.teleop_tp.max_vel, 10.0);
        assert_eq!(a.teleop_tp.curr_vel, 10.0);
    }

    #[test]
    fn a_move_past_a_limit_stops_hard_on_it() {
        let mut a = axis(-1.0, 1.0);
        // Aim past the limit (as after a limit was lowered mid-jog).
        a.teleop_tp.max_vel = 10.0;
        a.teleop_tp.pos_cmd = 5.0;
        a.teleop_tp.enable = true;
        let mut n = 0;
        while a.teleop_tp.curr_pos < 1.0 {
            a.update(T, 1.0, 1.0);
            assert!(a.teleop_tp.curr_pos <= 1.0);
            n += 1;
            assert!(n < 10_000);
        }
        assert_eq!(a.teleop_tp.curr_pos, 1.0);
        assert_eq!(a.teleop_tp.curr_vel, 0.0);
        assert!(!a.teleop_tp.enable && !a.teleop_tp.active);
        a.update(T, 1.0, 1.0);
        assert_eq!(a.teleop_tp.curr_pos, 1.0, "and stays there");
        assert!(!a.teleop_tp.active);
    }

    #[test]
    fn an_axis_beyond_a_limit_moves_back_in_but_not_further_out() {
        let mut a = axis(-1.0, 1.0);
        a.set_at_rest(3.0);
        a.teleop_tp.max_vel = 10.0;
        a.teleop_tp.enable = true;
        a.teleop_tp.pos_cmd = 4.0;
        a.update(T, 1.0, 1.0);
        assert_eq!(a.teleop_tp.curr_pos, 3.0, "held where it is");
        assert!(!a.teleop_tp.enable);
        a.teleop_tp.enable = true;
        a.teleop_tp.pos_cmd = 0.0;
        a.update(T, 1.0, 1.0);
        assert!(a.teleop_tp.curr_pos < 3.0, "inwards is allowed");
        assert!(a.teleop_tp.enable);
        // The negative side likewise.
        a.set_at_rest(-3.0);
        a.teleop_tp.enable = true;
        a.teleop_tp.pos_cmd = -5.0;
        a.update(T, 1.0, 1.0);
        assert_eq!(a.teleop_tp.curr_pos, -3.0);
    }

    #[test]
    fn wheel_jogs_use_the_accel_fraction_and_abort_ends_jogs() {
        let mut a = axis(-100.0, 100.0);
        a.wheel_jog_active = true;
        a.teleop_tp.max_vel = 10.0;
        a.teleop_tp.pos_cmd = 10.0;
        a.teleop_tp.enable = true;
        a.update(T, 1.0, 0.5);
        assert_eq!(a.teleop_tp.max_acc, 50.0);
        assert_eq!(a.teleop_tp.curr_vel, 50.0 * T);
        a.update(T, 1.0, 0.0);
        assert_eq!(a.teleop_tp.max_acc, 100.0, "0 is outside (0, 1]");
        assert_eq!(wheel_acc(100.0, 1.5), 100.0);
        a.abort(false);
        assert!(!a.jogging() && !a.teleop_tp.enable);
        assert!(a.teleop_tp.curr_vel > 0.0, "a controlled stop keeps speed");
        a.abort(true);
        assert_eq!(a.teleop_tp.curr_vel, 0.0);
        assert_eq!(a.teleop_tp.pos_cmd, a.teleop_tp.curr_pos);
    }
}
