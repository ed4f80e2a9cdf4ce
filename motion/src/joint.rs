//! One joint: its configuration, its HAL inputs, and the state the
//! controller keeps for it (the seven position quantities of the joint
//! chain, the flags and the free-mode planner).

use crate::command::Direction;
use crate::comp::CompTable;
use crate::simple_tp::SimpleTp;

/// The configuration of a joint. The defaults are LinuxCNC's module
/// defaults, before any configuration command.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointConfig {
    /// Lower soft limit.
    pub min_pos_limit: f64,
    /// Upper soft limit.
    pub max_pos_limit: f64,
    /// Maximum velocity.
    pub vel_limit: f64,
    /// Maximum acceleration.
    pub acc_limit: f64,
    /// Following-error limit at standstill.
    pub min_ferror: f64,
    /// Following-error limit at `vel_limit` (scaled with speed).
    pub max_ferror: f64,
    /// Backlash, taken up half each way at every reversal.
    pub backlash: f64,
    /// Maximum jerk (S-curve planning; 0: no jerk limit).
    pub jerk_limit: f64,
}

impl Default for JointConfig {
    fn default() -> Self {
        JointConfig {
            min_pos_limit: -1.0,
            max_pos_limit: 1.0,
            vel_limit: 1.0,
            acc_limit: 1.0,
            min_ferror: 0.01,
            max_ferror: 1.0,
            backlash: 0.0,
            jerk_limit: 0.0,
        }
    }
}

/// A joint's HAL inputs, read at the start of every servo cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointInputs {
    /// `joint.N.motor-pos-fb`.
    pub motor_pos_fb: f64,
    /// `joint.N.pos-lim-sw-in`.
    pub pos_lim_sw: bool,
    /// `joint.N.neg-lim-sw-in`.
    pub neg_lim_sw: bool,
    /// `joint.N.amp-fault-in`.
    pub amp_fault: bool,
    /// `joint.N.home-sw-in`.
    pub home_sw: bool,
    /// `joint.N.index-enable` as read back.
    pub index_enable: bool,
    /// `joint.N.jog-counts`.
    pub jog_counts: i32,
    /// `joint.N.jog-enable`.
    pub jog_enable: bool,
    /// `joint.N.jog-scale`.
    pub jog_scale: f64,
    /// `joint.N.jog-vel-mode`.
    pub jog_vel_mode: bool,
    /// `joint.N.jog-accel-fraction`.
    pub jog_accel_fraction: f64,
    /// `joint.N.posthome-cmd` (extra joints only).
    pub posthome_cmd: f64,
    /// `joint.N.is-unlocked` (locking indexers only).
    pub is_unlocked: bool,
}

impl Default for JointInputs {
    fn default() -> Self {
        JointInputs {
            motor_pos_fb: 0.0,
            pos_lim_sw: false,
            neg_lim_sw: false,
            amp_fault: false,
            home_sw: false,
            index_enable: false,
            jog_counts: 0,
            jog_enable: false,
            jog_scale: 0.0,
            jog_vel_mode: false,
            jog_accel_fraction: 1.0,
            posthome_cmd: 0.0,
            is_unlocked: false,
        }
    }
}

/// The controller's state of one joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// Configuration.
    pub(crate) cfg: JointConfig,
    /// Amplifier enabled (LinuxCNC's joint ENABLE flag).
    pub(crate) enabled: bool,
    /// Active: read, planned and checked.
    pub(crate) active: bool,
    /// In position (free planner at rest).
    pub(crate) inpos: bool,
    /// Error flag: why motion was disabled, until cleared.
    pub(crate) error: bool,
    /// Positive hard limit switch tripped.
    pub(crate) phl: bool,
    /// Negative hard limit switch tripped.
    pub(crate) nhl: bool,
    /// Following error over its limit.
    pub(crate) ferror_flag: bool,
    /// Amplifier fault input.
    pub(crate) fault: bool,
    /// The joint's position reference is known.
    pub(crate) homed: bool,
    /// The joint is homing.
    pub(crate) homing: bool,
    /// Home switch, latched at the start of the cycle.
    pub(crate) home_sw: bool,
    /// Index-enable as read back, latched at the start of the cycle.
    pub(crate) index_enable: bool,

    /// (2) Command before interpolation.
    pub(crate) coarse_pos: f64,
    /// (3) Command after interpolation.
    pub(crate) pos_cmd: f64,
    pub(crate) vel_cmd: f64,
    pub(crate) acc_cmd: f64,
    pub(crate) jerk_cmd: f64,
    /// Raw backlash correction (jumps at reversals).
    pub(crate) backlash_corr: f64,
    /// Rate-limited backlash correction, applied to the motor.
    pub(crate) backlash_filt: f64,
    pub(crate) backlash_vel: f64,
    /// Homing offset: motor position = joint position + motor offset.
    pub(crate) motor_offset: f64,
    /// (4) Command to the drive.
    pub(crate) motor_pos_cmd: f64,
    /// (5) Feedback from the drive.
    pub(crate) motor_pos_fb: f64,
    /// (6) Joint feedback.
    pub(crate) pos_fb: f64,
    pub(crate) ferror: f64,
    pub(crate) ferror_limit: f64,
    pub(crate) ferror_high_mark: f64,

    /// The free-mode planner.
    pub(crate) free_tp: SimpleTp,
    pub(crate) kb_jog_active: bool,
    pub(crate) wheel_jog_active: bool,
    pub(crate) min_jog_limit: f64,
    pub(crate) max_jog_limit: f64,
    pub(crate) old_jog_counts: i32,
    /// Whether the backup soft-limit check found this joint outside.
    pub(crate) soft_limit: Option<Direction>,
    /// Leadscrew-error compensation (replaces the backlash when filled).
    pub(crate) comp: CompTable,
}

impl Default for Joint {
    fn default() -> Self {
        let cfg = JointConfig::default();
        Joint {
            cfg,
            enabled: false,
            active: false,
            inpos: true,
            error: false,
            phl: false,
            nhl: false,
            ferror_flag: false,
            fault: false,
            homed: false,
            homing: false,
            home_sw: false,
            index_enable: false,
            coarse_pos: 0.0,
            pos_cmd: 0.0,
            vel_cmd: 0.0,
            acc_cmd: 0.0,
            jerk_cmd: 0.0,
            backlash_corr: 0.0,
            backlash_filt: 0.0,
            backlash_vel: 0.0,
            motor_offset: 0.0,
            motor_pos_cmd: 0.0,
            motor_pos_fb: 0.0,
            pos_fb: 0.0,
            ferror: 0.0,
            ferror_limit: cfg.min_ferror,
            ferror_high_mark: 0.0,
            free_tp: SimpleTp::default(),
            kb_jog_active: false,
            wheel_jog_active: false,
            min_jog_limit: 0.0,
            max_jog_limit: 0.0,
            old_jog_counts: 0,
            soft_limit: None,
            comp: CompTable::default(),
        }
    }
}

/// A copy of a joint's state for readers outside the controller.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointStatus {
    /// The homing configuration.
    pub config: JointConfig,
    /// The joint is active.
    pub active: bool,
    /// Amplifier enabled.
    pub enabled: bool,
    /// At rest.
    pub in_position: bool,
    /// What was wrong.
    pub error: bool,
    /// The positive limit switch is tripped.
    pub pos_hard_limit: bool,
    /// The negative limit switch is tripped.
    pub neg_hard_limit: bool,
    /// The following error is over its limit.
    pub following_error: bool,
    /// The amplifier reports a fault.
    pub faulted: bool,
    /// The joint is homed.
    pub homed: bool,
    /// The joint is homing.
    pub homing: bool,
    /// Commanded position before interpolation.
    pub coarse_pos: f64,
    /// Commanded position.
    pub pos_cmd: f64,
    /// Commanded velocity.
    pub vel_cmd: f64,
    /// Commanded acceleration.
    pub acc_cmd: f64,
    /// Motor position command.
    pub motor_pos_cmd: f64,
    /// Motor position feedback.
    pub motor_pos_fb: f64,
    /// Joint position feedback.
    pub pos_fb: f64,
    /// Motor position minus joint position (set by homing).
    pub motor_offset: f64,
    /// The backlash (or compensation) correction wanted.
    pub backlash_corr: f64,
    /// The backlash (or compensation) correction applied, rate limited.
    pub backlash_filt: f64,
    /// The backlash take-up's velocity.
    pub backlash_vel: f64,
    /// Following error.
    pub ferror: f64,
    /// The following-error limit now.
    pub ferror_limit: f64,
    /// The largest |following error| seen.
    pub ferror_high_mark: f64,
    /// Free planner target, velocity limit and enable.
    pub free_pos_cmd: f64,
    /// The free planner's velocity limit.
    pub free_vel_lim: f64,
    /// The free planner is enabled.
    pub free_tp_enable: bool,
    /// The free planner moves.
    pub free_tp_active: bool,
    /// A keyboard (command) jog is active.
    pub kb_jog_active: bool,
    /// A jog-wheel jog is active.
    pub wheel_jog_active: bool,
}

impl Joint {
    /// A copy of the state.
    pub fn status(&self) -> JointStatus {
        JointStatus {
            config: self.cfg,
            active: self.active,
            enabled: self.enabled,
            in_position: self.inpos,
            error: self.error,
            pos_hard_limit: self.phl,
            neg_hard_limit: self.nhl,
            following_error: self.ferror_flag,
            faulted: self.fault,
            homed: self.homed,
            homing: self.homing,
            coarse_pos: self.coarse_pos,
            pos_cmd: self.pos_cmd,
            vel_cmd: self.vel_cmd,
            acc_cmd: self.acc_cmd,
            motor_pos_cmd: self.motor_pos_cmd,
            motor_pos_fb: self.motor_pos_fb,
            pos_fb: self.pos_fb,
            motor_offset: self.motor_offset,
            backlash_corr: self.backlash_corr,
            backlash_filt: self.backlash_filt,
            backlash_vel: self.backlash_vel,
            ferror: self.ferror,
            ferror_limit: self.ferror_limit,
            ferror_high_mark: self.ferror_high_mark,
            free_pos_cmd: self.free_tp.pos_cmd,
            free_vel_lim: self.free_tp.max_vel,
            free_tp_enable: self.free_tp.enable,
            free_tp_active: self.free_tp.active,
            kb_jog_active: self.kb_jog_active,
            wheel_jog_active: self.wheel_jog_active,
        }
    }

    /// Reads the feedback and switches of an active joint: joint
    /// feedback (6) from motor feedback (5), following error against the
    /// previous cycle's command and its speed-scaled limit, the hard-limit
    /// and amp-fault flags. In the cycle homing sees the index
    /// (`index_hit`) the raw count may have jumped, so the feedback is
    /// taken to equal the command; homing corrects it right after.
    pub(crate) fn process_inputs(&mut self, inp: &JointInputs, index_hit: bool) {
        self.motor_pos_fb = inp.motor_pos_fb;
        self.pos_fb = if index_hit {
            self.pos_cmd
        } else {
            self.motor_pos_fb - (self.backlash_filt + self.motor_offset)
        };
        self.ferror = self.pos_cmd - self.pos_fb;
        let abs_ferror = self.ferror.abs();
        if abs_ferror > self.ferror_high_mark {
            self.ferror_high_mark = abs_ferror;
        }
        self.ferror_limit = if self.cfg.vel_limit > 0.0 {
            self.cfg.max_ferror * self.vel_cmd.abs() / self.cfg.vel_limit
        } else {
            0.0
        };
        if self.ferror_limit < self.cfg.min_ferror {
            self.ferror_limit = self.cfg.min_ferror;
        }
        // A NaN error (a NaN feedback) trips it too.
        self.ferror_flag = abs_ferror.is_nan() || abs_ferror > self.ferror_limit;
        self.phl = inp.pos_lim_sw;
        self.nhl = inp.neg_lim_sw;
        self.fault = inp.amp_fault;
    }

    /// Recomputes the jog limits: the soft limits once homed, otherwise
    /// one full travel either side of the feedback position.
    pub(crate) fn refresh_jog_limits(&mut self) {
        if self.homed {
            self.min_jog_limit = self.cfg.min_pos_limit;
            self.max_jog_limit = self.cfg.max_pos_limit;
        } else {
            let range = self.cfg.max_pos_limit - self.cfg.min_pos_limit;
            self.min_jog_limit = self.pos_fb - range;
            self.max_jog_limit = self.pos_fb + range;
        }
    }

    /// Updates the backlash (or compensation table) correction from the
    /// commanded direction and moves the applied (filtered) value towards
    /// it with half the joint's velocity and acceleration, in LinuxCNC's
    /// arithmetic with two differences:
    /// * the take-up speed does not follow the feed scale (LinuxCNC's
    ///   follows it, so a feed hold freezes a take-up half way: reference
    ///   §9.3 "→ Design");
    /// * LinuxCNC "cruises" even when its velocity has decayed to a
    ///   rounding crumb (1e-17), so the take-up can stall a fraction short
    ///   of the correction for ever (backlash 0.02 at 10 u/s, 100 u/s²,
    ///   1 ms stops at 0.00995 instead of 0.01). Here a cruise slower than
    ///   one acceleration step accelerates instead, so the take-up always
    ///   lands exactly on the correction.
    ///
    /// With a compensation table the correction is the table's trim for
    /// the direction of motion at the commanded position; standing still
    /// keeps the last one (as LinuxCNC).
    pub(crate) fn backlash_comp(&mut self, period: f64) {
        // Not at rest (a NaN command keeps the last correction).
        if !self.vel_cmd.is_nan() && self.vel_cmd != 0.0 {
            let forward = self.vel_cmd > 0.0;
            self.backlash_corr = if self.comp.is_empty() {
                if forward {
                    0.5 * self.cfg.backlash
                } else {
                    -0.5 * self.cfg.backlash
                }
            } else {
                self.comp.trim(self.pos_cmd, forward)
            };
        }
        let v_max = 0.5 * self.cfg.vel_limit;
        let a_max = 0.5 * self.cfg.acc_limit;
        let v = self.backlash_vel;
        if self.backlash_corr >= self.backlash_filt {
            let s_to_go = self.backlash_corr - self.backlash_filt;
            if s_to_go > 0.0 {
                let ds_vel = v * period;
                let mut dv_acc = a_max * period;
                let ds_stop = 0.5 * (v + dv_acc) * (v + dv_acc) / a_max;
                if s_to_go <= ds_stop + ds_vel {
                    if v > dv_acc {
                        let ds_acc = 0.5 * dv_acc * period;
                        self.backlash_vel -= dv_acc;
                        self.backlash_filt += ds_vel - ds_acc;
                    } else {
                        self.backlash_vel = 0.0;
                        self.backlash_filt = self.backlash_corr;
                    }
                } else {
                    if v + dv_acc > v_max {
                        dv_acc = v_max - v;
                    }
                    let ds_acc = 0.5 * dv_acc * period;
                    let ds_stop = 0.5 * (v + dv_acc) * (v + dv_acc) / a_max;
                    if s_to_go > ds_stop + ds_vel + ds_acc || v < a_max * period {
                        self.backlash_vel += dv_acc;
                        self.backlash_filt += ds_vel + ds_acc;
                    } else {
                        self.backlash_filt += ds_vel;
                    }
                }
            } else if s_to_go < 0.0 {
                self.backlash_vel = 0.0;
                self.backlash_filt = self.backlash_corr;
            }
        } else {
            let s_to_go = self.backlash_filt - self.backlash_corr;
            if s_to_go > 0.0 {
                let ds_vel = -v * period;
                let mut dv_acc = a_max * period;
                let ds_stop = 0.5 * (v - dv_acc) * (v - dv_acc) / a_max;
                if s_to_go <= ds_stop + ds_vel {
                    if -v > dv_acc {
                        let ds_acc = 0.5 * dv_acc * period;
                        self.backlash_vel += dv_acc;
                        self.backlash_filt -= ds_vel - ds_acc;
                    } else {
                        self.backlash_vel = 0.0;
                        self.backlash_filt = self.backlash_corr;
                    }
                } else {
                    if -v + dv_acc > v_max {
                        dv_acc = v_max + v;
                    }
                    let ds_acc = 0.5 * dv_acc * period;
                    let ds_stop = 0.5 * (v - dv_acc) * (v - dv_acc) / a_max;
                    if s_to_go > ds_stop + ds_vel + ds_acc || -v < a_max * period {
                        self.backlash_vel -= dv_acc;
                        self.backlash_filt -= ds_vel + ds_acc;
                    } else {
                        self.backlash_filt -= ds_vel;
                    }
                }
            } else if s_to_go < 0.0 {
                self.backlash_vel = 0.0;
                self.backlash_filt = self.backlash_corr;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn active() -> Joint {
        Joint {
            active: true,
            ..Joint::default()
        }
    }

    #[test]
    fn feedback_removes_backlash_and_offset() {
        let mut j = active();
        j.motor_offset = 2.0;
        j.backlash_filt = 0.25;
        j.pos_cmd = 1.0;
        j.process_inputs(
            &JointInputs {
                motor_pos_fb: 3.5,
                ..Default::default()
            },
            false,
        );
        assert_eq!(j.pos_fb, 3.5 - (0.25 + 2.0));
        assert_eq!(j.ferror, 1.0 - 1.25);
        assert_eq!(j.ferror_high_mark, 0.25);
    }

    #[test]
    fn following_error_limit_scales_with_speed_and_never_drops_below_min() {
        let mut j = active();
        j.cfg.vel_limit = 10.0;
        j.cfg.max_ferror = 0.5;
        j.cfg.min_ferror = 0.01;
        j.vel_cmd = -4.0;
        j.pos_cmd = 0.0;
        j.process_inputs(
            &JointInputs {
                motor_pos_fb: 0.19,
                ..Default::default()
            },
            false,
        );
        assert_eq!(j.ferror_limit, 0.5 * 4.0 / 10.0);
        assert!(!j.ferror_flag);
        j.process_inputs(
            &JointInputs {
                motor_pos_fb: 0.2000001,
                ..Default::default()
            },
            false,
        );
        assert!(j.ferror_flag, "over the limit trips");
        // At rest the limit is the minimum.
        j.vel_cmd = 0.0;
        j.process_inputs(
            &JointInputs {
                motor_pos_fb: 0.009,
                ..Default::default()
            },
            false,
        );
        assert_eq!(j.ferror_limit, 0.01);
        assert!(!j.ferror_flag);
        j.process_inputs(
            &JointInputs {
                motor_pos_fb: -0.011,
                ..Default::default()
            },
            false,
        );
        assert!(j.ferror_flag);
        // No velocity limit: the minimum applies.
        j.cfg.vel_limit = 0.0;
        j.vel_cmd = 100.0;
        j.process_inputs(&JointInputs::default(), false);
        assert_eq!(j.ferror_limit, 0.01);
        assert_eq!(j.ferror_high_mark, 0.2000001);
    }

    #[test]
    fn switches_and_fault_follow_the_inputs() {
        let mut j = active();
        j.process_inputs(
            &JointInputs {
                pos_lim_sw: true,
                amp_fault: true,
                ..Default::default()
            },
            false,
        );
        assert!(j.phl && !j.nhl && j.fault);
        j.process_inputs(
            &JointInputs {
                neg_lim_sw: true,
                ..Default::default()
            },
            false,
        );
        assert!(!j.phl && j.nhl && !j.fault);
    }

    #[test]
    fn jog_limits_depend_on_homing() {
        let mut j = active();
        j.cfg.min_pos_limit = -10.0;
        j.cfg.max_pos_limit = 30.0;
        j.pos_fb = 5.0;
        j.refresh_jog_limits();
        assert_eq!((j.min_jog_limit, j.max_jog_limit), (-35.0, 45.0));
        j.homed = true;
        j.refresh_jog_limits();
        assert_eq!((j.min_jog_limit, j.max_jog_limit), (-10.0, 30.0));
    }

    #[test]
    fn backlash_take_up_never_stalls_short() {
        let mut j = active();
        j.cfg.backlash = 0.02;
        j.cfg.vel_limit = 10.0;
        j.cfg.acc_limit = 100.0;
        j.vel_cmd = 1.0;
        for _ in 0..100 {
            j.backlash_comp(0.001);
        }
        assert_eq!(j.backlash_filt, 0.01);
        assert_eq!(j.backlash_vel, 0.0);
    }

    #[test]
    fn backlash_is_taken_up_with_limited_speed_and_acceleration() {
        let mut j = active();
        j.cfg.backlash = 0.1;
        j.cfg.vel_limit = 10.0;
        j.cfg.acc_limit = 100.0;
        let t = 0.001;
        j.vel_cmd = 1.0;
        let mut prev_v = 0.0;
        let mut n = 0;
        loop {
            j.backlash_comp(t);
            assert_eq!(j.backlash_corr, 0.05);
            assert!(j.backlash_vel <= 5.0 + 1e-12, "half the joint speed");
            assert!(
                (j.backlash_vel - prev_v).abs() <= 50.0 * t + 1e-12,
                "half the accel"
            );
            assert!(j.backlash_filt <= 0.05 + 1e-12);
            prev_v = j.backlash_vel;
            n += 1;
            if j.backlash_filt == 0.05 && j.backlash_vel == 0.0 {
                break;
            }
            assert!(n < 10_000);
        }
        // Standing still keeps the last direction's correction.
        j.vel_cmd = 0.0;
        j.backlash_comp(t);
        assert_eq!(j.backlash_filt, 0.05);
        // Reversal: the full backlash the other way.
        j.vel_cmd = -1.0;
        for _ in 0..10_000 {
            j.backlash_comp(t);
            assert!(j.backlash_vel >= -5.0 - 1e-12);
        }
        assert_eq!(j.backlash_corr, -0.05);
        assert_eq!(j.backlash_filt, -0.05);
        assert_eq!(j.backlash_vel, 0.0);
    }
}
