//! The servo cycle ([`MotionCore::cycle`]) in LinuxCNC's order: homing
//! inputs, kinematics switch, joint inputs and following error, forward
//! kinematics of the feedback, probe, faults, mode transitions, jog wheels,
//! homing, position commands per mode with the backup soft-limit check,
//! backlash and the motor commands.

use super::*;
use crate::axis::wheel_acc;
use crate::command::Direction;
use crate::events::Event;
use crate::homing::HomeFault;

impl MotionCore {
    // ----------------------------------------------------------------
    // The servo cycle

    /// One servo cycle of `period` seconds (LinuxCNC's `period * 1e-9`).
    pub fn cycle(&mut self, period: f64) {
        self.latch_homing_inputs();
        self.switch_kinematics();
        self.process_inputs();
        self.forward_kins_feedback();
        self.process_probe();
        self.process_spindle_orient();
        self.check_for_faults();
        self.set_operating_mode();
        self.handle_jog_wheels();
        self.handle_axis_jog_wheels();
        self.take_eoffset_inputs(period);
        let mut homed_all_now = false;
        if self.state == MotionState::Free {
            let was_homing = self.homing.is_active();
            self.homing.run(&mut self.joints, period, &self.events);
            homed_all_now = was_homing && !self.homing.is_active() && self.is_all_homed();
        }
        self.get_pos_cmds(period);
        self.eoffset_flags(period);
        if homed_all_now {
            // As LinuxCNC: once homing has homed every joint, motion goes
            // to teleop mode by itself (world jogs from then on). Entered
            // after this cycle's commands, so at the exact HOME positions.
            // A refusal (kinematics that cannot reproduce the joints)
            // leaves motion in free mode.
            let _ = self.request_mode(Mode::Teleop);
        }
        self.compute_backlash(period);
        self.motor_commands();
        self.homing.update_outputs();
        self.heartbeat = self.heartbeat.wrapping_add(1);
    }

    pub(super) fn latch_homing_inputs(&mut self) {
        for ((jt, jh), inp) in self
            .joints
            .iter_mut()
            .zip(&mut self.homing.joints)
            .zip(&self.joint_inputs)
        {
            jt.home_sw = inp.home_sw;
            jt.index_enable = inp.index_enable;
            jh.is_unlocked = inp.is_unlocked;
        }
    }

    /// Switchable kinematics follow `motion.switchkins-type`.
    pub(super) fn switch_kinematics(&mut self) {
        if !self.kins.is_switchable() {
            return;
        }
        let t = c_int(self.inputs.switchkins_type);
        if t == self.switchkins_type {
            return;
        }
        self.switchkins_type = t;
        match self.kins.switch_to(t) {
            Err(_) => {
                self.events.push(Event::KinsSwitchFailed { kins_type: t });
                self.error = true;
            }
            Ok(()) => {
                let n = self.load_positions(|jt| jt.pos_cmd);
                let _ = self.kins.forward(
                    &self.positions[..n],
                    &mut self.carte_pos_cmd,
                    &mut self.kins_flags,
                );
                self.world_kins_switched();
            }
        }
    }

    pub(super) fn process_inputs(&mut self) {
        let enables = self.enables_new;
        let mut scale = 1.0;
        if enables & FH_ENABLED != 0 && self.inputs.feed_hold {
            scale = 0.0;
        }
        if enables & SS_ENABLED != 0 && self.inputs.feed_inhibit {
            scale = 0.0;
        }
        self.net_feed_scale = scale;

        for ((jt, jh), inp) in self
            .joints
            .iter_mut()
            .zip(&self.homing.joints)
            .zip(&self.joint_inputs)
        {
            if !jt.active {
                continue;
            }
            // In the cycle the encoder reports the index its count may
            // have jumped: homing re-derives the feedback right after.
            let index_hit = jh.index_seen(jt);
            jt.process_inputs(inp, index_hit);
        }
        self.extra_joints_ferror();

        if self.jog_is_active && (self.inputs.jog_stop || self.inputs.jog_stop_immediate) {
            let immediate = self.inputs.jog_stop_immediate;
            for jt in &mut self.joints {
                if jt.kb_jog_active || jt.wheel_jog_active {
                    jt.end_jogs(immediate);
                }
            }
            self.stop_axis_jogs(immediate);
            self.jog_is_active = false;
            self.events.push(Event::JogStopped { immediate });
        }
    }

    /// Homed extra joints are commanded from `posthome-cmd`; motion does not
    /// plan or check them.
    pub(super) fn extra_joints_ferror(&mut self) {
        let first_extra = self.kins_joints;
        for jt in &mut self.joints[first_extra..] {
            if jt.active && jt.homed {
                jt.ferror = 0.0;
                jt.ferror_flag = false;
            }
        }
    }

    /// Copies a position of each kinematic joint into the kinematics
    /// scratch; returns how many there are.
    pub(super) fn load_positions(&mut self, of: impl Fn(&Joint) -> f64) -> usize {
        let n = self.kins_joints;
        for (p, jt) in self.positions.iter_mut().zip(&self.joints[..n]) {
            *p = of(jt);
        }
        n
    }

    /// Forward kinematics of the loaded positions into `pose`, with
    /// LinuxCNC's validity rules: identity kinematics always compute and
    /// are valid once every joint is homed; kinematics of both kinds
    /// compute only once homed, starting from the world home when the
    /// previous result was not valid. `None` for kinematics without a
    /// usable forward direction (the caller decides).
    pub(super) fn forward_pose(&mut self, n: usize, pose: &mut Pose, was_ok: bool) -> Option<bool> {
        let all_homed = self.is_all_homed();
        let q = &self.positions[..n];
        match self.kins_type {
            KinematicsType::Identity => {
                let _ = self.kins.forward(q, pose, &mut self.kins_flags);
                Some(all_homed)
            }
            KinematicsType::Both if all_homed => {
                if !was_ok {
                    *pose = self.world_home;
                }
                Some(self.kins.forward(q, pose, &mut self.kins_flags).is_ok())
            }
            KinematicsType::Both => Some(false),
            KinematicsType::InverseOnly | KinematicsType::ForwardOnly => None,
        }
    }

    pub(super) fn forward_kins_feedback(&mut self) {
        let n = self.load_positions(|jt| jt.pos_fb);
        let mut pose = self.carte_pos_fb;
        let ok = self.forward_pose(n, &mut pose, self.carte_pos_fb_ok);
        self.carte_pos_fb = pose;
        match ok {
            Some(ok) => self.carte_pos_fb_ok = ok,
            None => {
                // Without forward kinematics the world command stands in
                // for the feedback in the world modes (as LinuxCNC does);
                // in free mode there is none.
                let world = matches!(self.state, MotionState::Teleop | MotionState::Coord);
                if world {
                    self.carte_pos_fb = self.carte_pos_cmd;
                }
                self.carte_pos_fb_ok = world;
            }
        }
    }

    /// A probe contact while jogging stops the jogs (no probing moves in
    /// free mode) and aborts homing, unless SET_PROBE_ERR_INHIBIT says
    /// otherwise.
    pub(super) fn process_probe(&mut self) {
        let (jog_ok, home_ok) = self.probe_err_inhibit;
        let probe = self.inputs.probe_input;
        if self.coord_probe(probe) {
            self.old_probe = probe;
            return;
        }
        if probe && !self.old_probe && self.state == MotionState::Coord && !self.tp.is_done() {
            self.tp.abort();
            self.error = true;
            self.events.push(Event::ProbeTrippedDuringMove);
        }
        if probe && !self.old_probe && self.homing.is_active() && !home_ok {
            if let Some(joint) = (0..self.joints.len()).find(|&j| self.joints[j].homing) {
                self.events.push(Event::HomingAborted {
                    joint,
                    fault: HomeFault::ProbeTripped,
                    state: self.homing.joints[joint].state,
                });
            }
            self.homing.abort(&mut self.joints);
        }
        if probe && !self.old_probe && !jog_ok {
            let mut stopped = false;
            for jt in &mut self.joints {
                if jt.active && jt.free_tp.enable && !jt.homing {
                    jt.free_tp.enable = false;
                    stopped = true;
                }
            }
            if stopped {
                self.events.push(Event::ProbeTrippedDuringJog);
            }
            if self.stop_axis_jogs_on_probe() {
                self.events.push(Event::ProbeTrippedDuringAxisJog);
            }
        }
        self.old_probe = probe;
    }

    /// A probing move (G38.x, reference §8.6): the input is sampled once
    /// per servo cycle; when it shows what the move looks for, the
    /// feedback pose of that cycle is latched and the motion stops along
    /// the path; a move that ends without it is an error (G38.2, G38.4)
    /// or just a result (G38.3, G38.5). True while a probing move runs.
    fn coord_probe(&mut self, input: bool) -> bool {
        let executing = if self.state == MotionState::Coord {
            self.tp.probe_segment()
        } else {
            None
        };
        if let Some((kind, id)) = executing {
            if !self.probe.probing {
                self.probe.probing = true;
                self.probe.kind = kind;
                self.probe.id = id;
            }
        }
        if !self.probe.probing {
            return false;
        }
        if input != self.probe.kind.trip_on_clear {
            self.probe.pos = self.carte_pos_fb;
            self.probe.probing = false;
            self.probe.tripped = true;
            self.tp.abort();
        } else if executing.map(|(_, id)| id) != Some(self.probe.id) {
            // The move ended without the change.
            self.probe.probing = false;
            self.probe.pos = self.carte_pos_fb;
            self.probe.tripped = false;
            if !self.probe.kind.no_error {
                self.error = true;
                self.tp.abort();
                self.events.push(Event::ProbeNoContact {
                    trip_on_clear: self.probe.kind.trip_on_clear,
                });
            }
        }
        true
    }

    /// Ends probing without a result (abort, disable).
    pub(super) fn end_probing(&mut self) {
        self.probe.probing = false;
    }

    pub(super) fn check_for_faults(&mut self) {
        if self.enabled && !self.inputs.enable {
            self.events.push(Event::EnableInputStopped);
            self.enabling = false;
        }
        for n in 0..self.cfg.num_spindles {
            if self.enabled && self.inputs.spindle_amp_fault[n] {
                self.events.push(Event::SpindleAmpFault { spindle: n });
                self.enabling = false;
            }
        }
        for n in 0..self.cfg.num_misc_error {
            if self.enabled && self.inputs.misc_error[n] {
                self.events.push(Event::MiscError { input: n });
                self.enabling = false;
            }
        }
        let mask = self.override_limit_mask;
        for (n, jt) in self.joints.iter_mut().enumerate() {
            if !(jt.active && jt.enabled) {
                continue;
            }
            let neg_ovr = mask & (1 << (2 * n)) != 0;
            let pos_ovr = mask & (2 << (2 * n)) != 0;
            if ((jt.phl && !pos_ovr) || (jt.nhl && !neg_ovr)) && !jt.homing {
                if !jt.error {
                    self.events.push(Event::JointOnLimit { joint: n });
                }
                jt.error = true;
                self.enabling = false;
            }
            if jt.fault {
                if !jt.error {
                    self.events.push(Event::JointAmpFault { joint: n });
                }
                jt.error = true;
                self.enabling = false;
            }
            if jt.ferror_flag {
                if !jt.error {
                    let trip = crate::fault::FollowingErrorTrip {
                        error: jt.ferror,
                        limit: jt.ferror_limit,
                    };
                    self.events.push_following_error(n, trip);
                }
                jt.error = true;
                self.enabling = false;
            }
        }
    }

    pub(super) fn set_operating_mode(&mut self) {
        if !self.enabling && self.enabled {
            if let Some(joint) = (0..self.joints.len()).find(|&j| self.joints[j].homing) {
                self.events.push(Event::HomingAborted {
                    joint,
                    fault: HomeFault::Disabled,
                    state: self.homing.joints[joint].state,
                });
            }
            self.homing.abort(&mut self.joints);
            for jt in &mut self.joints {
                jt.free_tp.enable = false;
                jt.free_tp.curr_vel = 0.0;
                if jt.active {
                    jt.inpos = true;
                    jt.enabled = false;
                }
            }
            self.world_disable_edge();
            self.stop_spindles();
            self.enabled = false;
        }
        if self.enabling && !self.enabled {
            self.homing.abort(&mut self.joints);
            for jt in &mut self.joints {
                jt.free_tp.curr_pos = jt.pos_cmd;
                if jt.active {
                    jt.enabled = true;
                }
                jt.error = false;
            }
            self.enabled = true;
            self.error = false;
            self.reset_eoffsets();
            self.world_enable_edge();
        }
        self.state = self.operating_state();
    }

    pub(super) fn get_pos_cmds(&mut self, period: f64) {
        match self.state {
            MotionState::Free => {
                // (1) is the forward kinematics of the previous cycle's (2).
                let n = self.load_positions(|jt| jt.coarse_pos);
                self.inpos = true;
                for (j, jt) in self.joints.iter_mut().enumerate() {
                    if !jt.active || (j >= n && jt.homed) {
                        continue;
                    }
                    jt.free_tp.max_acc = if jt.wheel_jog_active {
                        wheel_acc(jt.cfg.acc_limit, self.joint_inputs[j].jog_accel_fraction)
                    } else {
                        jt.cfg.acc_limit
                    };
                    // Homing moves ignore the jog override: the latch speed
                    // must not change with it, and a zero override would
                    // stall homing for ever.
                    let scale = if jt.homing { 1.0 } else { self.scale };
                    jt.free_tp.update(period, scale);
                    jt.pos_cmd = jt.free_tp.curr_pos;
                    jt.coarse_pos = jt.free_tp.curr_pos;
                    jt.vel_cmd = jt.free_tp.curr_vel;
                    jt.acc_cmd = 0.0;
                    jt.jerk_cmd = 0.0;
                    if jt.free_tp.active {
                        jt.inpos = false;
                        self.inpos = false;
                        if self.override_limit_mask != 0 {
                            self.overriding = true;
                        }
                    } else {
                        jt.inpos = true;
                        jt.kb_jog_active = false;
                        jt.wheel_jog_active = false;
                    }
                }
                if self.overriding && self.inpos {
                    self.override_limit_mask = 0;
                    self.overriding = false;
                }
                let mut pose = self.carte_pos_cmd;
                let ok = self.forward_pose(n, &mut pose, self.carte_pos_cmd_ok);
                self.carte_pos_cmd = pose;
                self.carte_pos_cmd_ok = ok.unwrap_or(false);
            }
            MotionState::Teleop => self.teleop_pos_cmds(period),
            MotionState::Coord => self.coord_pos_cmds(period),
            MotionState::Disabled => {
                self.carte_pos_cmd = self.carte_pos_fb;
                for jt in &mut self.joints {
                    jt.pos_cmd = jt.pos_fb;
                    jt.vel_cmd = 0.0;
                    jt.acc_cmd = 0.0;
                }
            }
        }
        let was_on_limit = self.on_soft_limit;
        self.check_soft_limits();
        self.teleop_soft_limit_stop();
        self.coord_soft_limit_stop(was_on_limit);
    }

    /// The backup check: a homed joint commanded outside its soft limits
    /// raises the motion error once, when it happens.
    pub(super) fn check_soft_limits(&mut self) {
        let mut onlimit = false;
        for jt in &mut self.joints {
            jt.soft_limit = None;
            if jt.active && jt.homed {
                if jt.pos_cmd > jt.cfg.max_pos_limit + 1e-12 {
                    jt.soft_limit = Some(Direction::Positive);
                    onlimit = true;
                } else if jt.pos_cmd < jt.cfg.min_pos_limit - 1e-12 {
                    jt.soft_limit = Some(Direction::Negative);
                    onlimit = true;
                }
            }
        }
        if onlimit {
            if !self.on_soft_limit {
                for (n, jt) in self.joints.iter().enumerate() {
                    if let Some(dir) = jt.soft_limit {
                        self.events.push(Event::SoftLimitExceeded { joint: n, dir });
                    }
                }
                self.error = true;
            }
            self.on_soft_limit = true;
        } else {
            self.on_soft_limit = false;
        }
    }

    pub(super) fn compute_backlash(&mut self, period: f64) {
        let n = self.kins_joints;
        for (j, jt) in self.joints.iter_mut().enumerate() {
            if !jt.active || (j >= n && jt.homed) {
                continue;
            }
            jt.backlash_comp(period);
        }
    }

    /// (4) the motor commands, and the machine-wide outputs derived from
    /// the joints.
    pub(super) fn motor_commands(&mut self) {
        let n = self.kins_joints;
        let mut v2 = 0.0;
        let mut jogging = false;
        for (j, jt) in self.joints.iter_mut().enumerate() {
            if j >= n && jt.homed {
                // A homed extra joint follows its `posthome-cmd` input.
                jt.motor_pos_cmd = self.joint_inputs[j].posthome_cmd + jt.motor_offset;
            } else {
                jt.motor_pos_cmd = jt.pos_cmd + jt.backlash_filt + jt.motor_offset;
            }
            if jt.active && jt.free_tp.active {
                v2 += jt.vel_cmd * jt.vel_cmd;
            }
            jogging |= jt.kb_jog_active || jt.wheel_jog_active;
        }
        let v2 = v2 + self.teleop_vel_squared();
        self.current_vel = if self.state == MotionState::Coord {
            self.tp.status().current_vel
        } else if v2 > 0.0 {
            v2.sqrt()
        } else {
            0.0
        };
        self.jog_is_active = jogging || self.axis_jogging();
    }
}
