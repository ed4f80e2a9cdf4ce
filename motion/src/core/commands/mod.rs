//! Applying one command ([`MotionCore::command`]): the dispatch to the
//! handlers of each mode, and the value checks they share.
//!
//! The handlers: `machine` (abort, enable and disable, the legacy
//! amplifier commands), `joints` (free mode: joint jogs, activation,
//! the limit override, the SCALE), `homing` (home, unhome, the homing
//! configuration), `settings` (joint limits, screw compensation, the
//! world home); teleop mode's axis jogs and limits are in `teleop`,
//! coordinated mode's queueing and planner commands in `queue`.

use super::queue::{MoveCaps, Override};
use super::spindle::SpindleLimits;
use super::*;
use crate::command::{Command, CommandResult, Quantity, Reject};
use crate::sizes::{AF_ENABLED, FH_ENABLED, FS_ENABLED, SS_ENABLED};
use crate::tp::ArcBlends;

mod homing;
mod joints;
mod machine;
mod machine_setup;
mod settings;

impl MotionCore {
    /// Applies one command. On `Err` nothing changed. Reads the
    /// machine-wide inputs (`motion.enable`, `motion.jog-inhibit`) from
    /// [`Self::inputs`].
    pub fn command(&mut self, cmd: &Command) -> CommandResult {
        // One arm per command, grouped by mode: the dispatch table.
        use Command as C;
        match *cmd {
            // The machine.
            C::Abort => self.abort(),
            C::Enable => self.enable(),
            C::Disable => self.disable(),
            C::Free => self.request_mode(Mode::Free),
            C::Teleop => self.request_mode(Mode::Teleop),
            C::Coord => self.request_mode(Mode::Coord),
            C::EnableAmplifier { joint } | C::DisableAmplifier { joint } => self.amplifier(joint),
            // Free mode.
            C::JogCont { joint, vel } => self.jog_cont(joint, vel),
            C::JogIncr { joint, vel, offset } => self.jog_incr(joint, vel, offset),
            C::JogAbs { joint, vel, pos } => self.jog_abs(joint, vel, pos),
            C::JogAbort { joint } => self.jog_abort(joint),
            C::JointActivate { joint } => self.activate(joint),
            C::JointDeactivate { joint } => self.deactivate(joint),
            C::OverrideLimits { joint } => self.override_limits(joint),
            C::Scale { scale } => self.set_scale(scale),
            // Homing.
            C::Home { joint } => self.home(joint),
            C::Unhome { joint } => self.unhome(joint),
            C::SetJointHomingParams { joint, config } => self.set_homing_params(joint, config),
            C::UpdateJointHomingParams {
                joint,
                offset,
                home,
                sequence,
            } => self.update_homing_params(joint, offset, home, sequence),
            // Joint and world settings.
            C::SetJointPositionLimits { joint, min, max } => self.set_joint_limits(joint, min, max),
            C::SetJointVelLimit { joint, vel } => self.set_joint_vel_limit(joint, vel),
            C::SetJointAccLimit { joint, acc } => self.set_joint_acc_limit(joint, acc),
            C::SetJointJerkLimit { joint, jerk } => self.set_joint_jerk_limit(joint, jerk),
            C::SetJointMinFerror { joint, ferror } => self.set_min_ferror(joint, ferror),
            C::SetJointMaxFerror { joint, ferror } => self.set_max_ferror(joint, ferror),
            C::SetJointBacklash { joint, backlash } => self.set_backlash(joint, backlash),
            C::SetJointMotorOffset { joint, offset } => self.set_motor_offset(joint, offset),
            C::SetJointComp {
                joint,
                nominal,
                forward,
                reverse,
            } => self.add_comp(joint, nominal, forward, reverse),
            C::ClearJointComp { joint } => self.clear_comp(joint),
            C::SetWorldHome { pose } => self.set_world_home(pose),
            C::SetNumJoints { joints } => self.set_num_joints(joints),
            C::SetNumSpindles { spindles } => self.set_num_spindles(spindles),
            C::SetToolOffset { offset } => self.set_tool_offset(offset),
            // Teleop mode.
            C::AxisJogCont { axis, vel } => self.axis_jog_cont(axis, vel),
            C::AxisJogIncr { axis, vel, offset } => self.axis_jog_incr(axis, vel, offset),
            C::AxisJogAbs { axis, vel, pos } => self.axis_jog_abs(axis, vel, pos),
            C::AxisJogAbort { axis } => self.axis_jog_abort(axis),
            C::SetAxisPositionLimits { axis, min, max } => {
                self.set_axis_position_limits(axis, min, max)
            }
            C::SetAxisVelLimit { axis, vel } => self.set_axis_vel_limit(axis, vel),
            C::SetAxisAccLimit { axis, acc } => self.set_axis_acc_limit(axis, acc),
            C::SetAxisJerkLimit { axis, jerk } => self.set_axis_jerk_limit(axis, jerk),
            C::SetAxisEoffsetRatio { axis, ratio } => self.set_axis_eoffset_ratio(axis, ratio),
            C::SetAxisLockingIndexer { axis, joint } => self.set_axis_locking_indexer(axis, joint),
            // Coordinated mode.
            C::Line {
                end,
                vel,
                ini_maxvel,
                acc,
                kind,
                id,
            } => self.queue_line(end, vel, MoveCaps::new(ini_maxvel, acc)?, kind, id),
            C::Circle {
                end,
                center,
                normal,
                turns,
                vel,
                ini_maxvel,
                acc,
                id,
            } => {
                let caps = MoveCaps::new(ini_maxvel, acc)?;
                self.queue_circle(end, (center, normal, turns), vel, caps, id)
            }
            C::Dwell { seconds, id } => self.queue_dwell(seconds, id),
            C::RigidTap {
                end,
                vel,
                scale,
                id,
            } => self.queue_rigid_tap(end, vel, scale, id),
            C::Probe {
                end,
                vel,
                probe,
                id,
            } => self.queue_probe(end, vel, probe, id),
            C::ClearProbeFlags => self.clear_probe_flags(),
            C::SetProbeErrInhibit { jog, home } => {
                self.probe_err_inhibit = (jog, home);
                Ok(())
            }
            C::SetTermCond { cond, tolerance } => self.set_term_cond(cond, tolerance),
            C::Pause => self.pause(),
            C::Resume => self.resume(),
            C::Step => self.step(),
            C::FeedScale { scale } => self.set_override(Override::Feed, scale),
            C::RapidScale { scale } => self.set_override(Override::Rapid, scale),
            C::SetMaxFeedOverride { scale } => self.set_override(Override::Max, scale),
            C::FeedScaleEnable { on } => self.set_enable(FS_ENABLED, on),
            C::FeedHoldEnable { on } => self.set_enable(FH_ENABLED, on),
            C::AdaptiveFeedEnable { on } => self.set_enable(AF_ENABLED, on),
            C::SpindleScaleEnable { on } => self.set_enable(SS_ENABLED, on),
            C::SetVelLimit { vel } => self.set_traj_limit(Quantity::VelocityLimit, vel),
            C::SetAccLimit { acc } => self.set_traj_limit(Quantity::AccelerationLimit, acc),
            C::SetJerkLimit { jerk } => self.set_traj_limit(Quantity::JerkLimit, jerk),
            C::SetPlannerType { planner } => self.set_planner_type(planner),
            C::SetVel { vel, ini_maxvel } => self.set_traj_vel(vel, ini_maxvel),
            C::SetupArcBlends {
                enable,
                fallback,
                depth,
                gap_cycles,
                ramp_freq,
            } => self.set_arc_blends(ArcBlends {
                enable,
                fallback,
                depth,
                gap_cycles,
                ramp_freq,
            }),
            // Spindles.
            C::SpindleOn {
                spindle,
                speed,
                wait,
            } => self.spindle_on(spindle, speed, wait),
            C::SpindleOff { spindle } => self.spindle_off(spindle),
            C::SpindleScale { spindle, scale } => self.spindle_scale(spindle, scale),
            C::SetSpindleParams {
                spindle,
                max_pos,
                min_pos,
                max_neg,
                min_neg,
            } => self.set_spindle_params(
                spindle,
                SpindleLimits {
                    max_pos,
                    min_pos,
                    max_neg,
                    min_neg,
                },
            ),
            C::SpindleBrake { spindle, on } => self.spindle_brake(spindle, on),
            C::SpindleOrient {
                spindle,
                angle,
                mode,
            } => self.spindle_orient(spindle, angle, mode),
            C::SetFeedPerRev { spindle, per_rev } => self.set_feed_per_rev(spindle, per_rev),
            C::SpindleSync {
                spindle,
                per_rev,
                velocity_mode,
            } => self.spindle_sync(spindle, per_rev, velocity_mode),
            C::SpindleCss {
                spindle,
                factor,
                x_offset,
            } => self.spindle_css(spindle, factor, x_offset),
            // Digital and analog outputs.
            C::SetDout { index, on, now } => self.set_dout(index, on, now),
            C::SetAout { index, value, now } => self.set_aout(index, value, now),
        }
    }

    // ----------------------------------------------------------------
    // The value checks the handlers share

    pub(super) fn joint_index(&self, joint: i32) -> Result<usize, Reject> {
        if joint >= 0 && (joint as usize) < self.joints_in_use {
            Ok(joint as usize)
        } else {
            Err(Reject::NoSuchJoint {
                joint,
                num_joints: self.joints_in_use,
            })
        }
    }

    pub(super) fn finite(what: Quantity, value: f64) -> Result<f64, Reject> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(Reject::BadValue { what, value })
        }
    }

    pub(super) fn non_negative(what: Quantity, value: f64) -> Result<f64, Reject> {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(Reject::BadValue { what, value })
        }
    }

    pub(super) fn positive(what: Quantity, value: f64) -> Result<f64, Reject> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(Reject::BadValue { what, value })
        }
    }
}
