//! Homing: finding each joint's reference and declaring its position.
//!
//! * [`HomingConfig`] (in the leaf `vocab`, shared with the commands):
//!   the `HOME_*` options and which combinations are usable.
//! * [`state`]: the per-joint states (LinuxCNC's numbers) and failures.
//! * `machine`: one joint's state machine.
//! * `moves`: the few operations homing performs on a joint.
//! * this module: the sequence manager, which homes one joint, one
//!   synchronised group, or all joints in HOME_SEQUENCE order.
//!
//! Homing only changes the joint's motor offset (motor position = joint
//! position + offset); the motor command never jumps.
//!
//! Deliberate differences from LinuxCNC:
//! * a failure aborts only the joints of the running sequence; joints
//!   homed before keep their reference (LinuxCNC unhomes every joint);
//! * homing is cancelled at once when motion is disabled, not on the next
//!   enable;
//! * the settle delay applies before the final move too;
//! * requests that cannot run (sequence gaps, a closed shared switch, a
//!   homed joint that must not re-home) are refused with a reason instead
//!   of ending silently or failing later; so are configurations that
//!   cannot work (a locking indexer without unlock pins, or one with an
//!   absolute encoder that would make its final move locked);
//! * a joint is synchronised when any joint of its HOME_SEQUENCE
//!   magnitude is negative (LinuxCNC too, but only once homing starts);
//! * a jog-abort cancels homing only for a joint homing at that moment,
//!   not for one that finished or waits for its turn;
//! * a disable during homing is reported as a homing abort too.
//!
//! As in LinuxCNC, homing moves ignore the free-mode SCALE, so the latch
//! speed, and with it the repeatability, does not depend on the override.
//! Known limits: a synchronised group's absolute-encoder members start
//! their final moves on their own, and an index seen by the encoder in
//! the very cycle homing is aborted is not corrected for (both as in
//! LinuxCNC).

mod machine;
mod moves;
pub mod state;

pub use crate::vocab::{ConfigProblem, HomeFlags, HomingConfig, MAX_HOME_ALL_SEQUENCE};
pub use machine::HOME_DELAY;
pub use state::{HomeFault, HomeState};

pub(crate) use machine::JointHoming;

use crate::events::{Event, EventRing};
use crate::joint::Joint;
use crate::sizes::MAX_JOINTS;
use crate::vocab::Reject;

/// Where the sequence manager is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Sequence {
    /// Nothing to do.
    #[default]
    Idle,
    /// Start the joints of the current sequence number.
    StartJoints,
    /// Wait until every joint of the current number is idle.
    WaitJoints,
}

/// The homing state of every joint and the sequence manager.
#[derive(Debug, Clone, Default)]
pub(crate) struct Homing {
    pub joints: Vec<JointHoming>,
    sequence: Sequence,
    /// The sequence number (magnitude) being homed.
    current: u32,
}

impl Homing {
    /// Homing records for `n` joints, all idle with the default
    /// configuration.
    pub fn new(n: usize) -> Homing {
        Homing {
            joints: vec![JointHoming::default(); n],
            sequence: Sequence::Idle,
            current: 0,
        }
    }

    /// Whether a homing sequence is running.
    pub fn is_active(&self) -> bool {
        self.sequence != Sequence::Idle
    }

    /// Whether joint `j` takes part in the running sequence.
    pub fn in_sequence(&self, j: usize) -> bool {
        self.is_active() && self.joints[j].in_sequence
    }

    /// Starts homing `target` (a joint, or −1 for all joints in
    /// HOME_SEQUENCE order). The caller has checked the motion-wide
    /// requirements (enabled, free mode, not inhibited, nothing homing).
    /// On `Err` nothing changed.
    pub fn request(&mut self, target: i32, jts: &mut [Joint]) -> Result<(), Reject> {
        let n = jts.len().min(self.joints.len());
        let mut member = [false; MAX_JOINTS];
        let first: u32;
        if target == -1 {
            // Which magnitudes are used; home-all magnitudes are ≤ 100.
            let mut used = [false; MAX_HOME_ALL_SEQUENCE as usize + 1];
            for j in 0..n {
                if jts[j].active && self.joints[j].cfg.in_home_all() {
                    member[j] = true;
                    used[self.joints[j].cfg.sequence.unsigned_abs() as usize] = true;
                }
            }
            let Some(lowest) = used.iter().position(|&u| u) else {
                return Err(Reject::NothingToHome);
            };
            if lowest > 1 {
                return Err(Reject::HomeSequenceGap { missing: 1 });
            }
            let highest = used.iter().rposition(|&u| u).unwrap_or(lowest);
            if let Some(gap) = (lowest..=highest).find(|&k| !used[k]) {
                return Err(Reject::HomeSequenceGap {
                    missing: gap as i32,
                });
            }
            first = lowest as u32;
        } else if target >= 0 && (target as usize) < n {
            let j = target as usize;
            if !jts[j].active {
                return Err(Reject::JointInactive { joint: j });
            }
            let cfg = self.joints[j].cfg;
            first = cfg.sequence.unsigned_abs();
            if cfg.is_synchronized() {
                for k in 0..n {
                    if jts[k].active && self.joints[k].cfg.sequence.unsigned_abs() == first {
                        member[k] = true;
                    }
                }
            } else {
                if cfg.flags.contains(HomeFlags::NO_REHOME) && jts[j].homed {
                    return Err(Reject::AlreadyHomed { joint: j });
                }
                member[j] = true;
            }
        } else {
            return Err(Reject::NoSuchJoint {
                joint: target,
                num_joints: n,
            });
        }
        // A shared switch that is closed now would abort at once.
        for j in 0..n {
            let cfg = &self.joints[j].cfg;
            if member[j]
                && cfg.sequence.unsigned_abs() == first
                && cfg.flags.contains(HomeFlags::IS_SHARED)
                && !cfg.flags.contains(HomeFlags::ABSOLUTE_ENCODER)
                && jts[j].home_sw
            {
                return Err(Reject::SharedHomeSwitchClosed { joint: j });
            }
        }
        // Accepted. A negative number anywhere makes its group synchronised.
        for j in 0..n {
            if !member[j] {
                continue;
            }
            let mag = self.joints[j].cfg.sequence.unsigned_abs();
            let sync = (0..n).any(|k| {
                member[k]
                    && self.joints[k].cfg.sequence.unsigned_abs() == mag
                    && self.joints[k].cfg.is_synchronized()
            });
            if sync {
                self.joints[j].cfg.sequence = -(mag as i32);
            }
        }
        for j in 0..n {
            let jh = &mut self.joints[j];
            jh.in_sequence = member[j];
            if member[j] && !(jh.cfg.flags.contains(HomeFlags::NO_REHOME) && jts[j].homed) {
                jts[j].homed = false;
            }
        }
        self.current = first;
        self.sequence = Sequence::StartJoints;
        Ok(())
    }

    /// One cycle of homing (free mode only): the sequence manager, every
    /// homing joint's state machine, then the synchronised final moves.
    pub fn run(&mut self, jts: &mut [Joint], period: f64, events: &EventRing) {
        let n = jts.len().min(self.joints.len());
        let current = self.current;
        let of_current =
            |jh: &JointHoming| jh.in_sequence && jh.cfg.sequence.unsigned_abs() == current;
        if self.sequence == Sequence::StartJoints {
            let mut started = false;
            for jh in self.joints[..n].iter_mut().filter(|jh| of_current(jh)) {
                jh.reset();
                jh.go(HomeState::Start);
                started = true;
            }
            if !started {
                self.finish();
                return;
            }
            self.sequence = Sequence::WaitJoints;
        }
        if self.sequence != Sequence::WaitJoints {
            return;
        }
        for j in 0..n {
            let jh = &mut self.joints[j];
            if !jh.in_sequence || jh.state == HomeState::Idle {
                continue;
            }
            if let Err(fault) = jh.step(&mut jts[j], period) {
                events.push(Event::HomingAborted {
                    joint: j,
                    fault,
                    state: jh.state,
                });
                self.abort(jts);
                return;
            }
        }
        // A synchronised group starts its final moves together, once every
        // joint that moves is ready.
        let movers = |jh: &&mut JointHoming| {
            of_current(jh)
                && jh.cfg.is_synchronized()
                && !jh.cfg.flags.contains(HomeFlags::ABSOLUTE_ENCODER)
                && jh.state != HomeState::Idle
        };
        let mut any = false;
        let mut all_ready = true;
        for jh in self.joints[..n].iter_mut().filter(movers) {
            any = true;
            all_ready &= jh.state == HomeState::FinalMoveStart && jh.ready_final;
        }
        if any && all_ready {
            for (jh, jt) in self.joints[..n].iter_mut().zip(jts.iter_mut()) {
                if movers(&jh) {
                    jh.start_final_move(jt);
                }
            }
        }
        if self.joints[..n]
            .iter()
            .filter(|jh| of_current(jh))
            .all(|jh| jh.state == HomeState::Idle)
        {
            self.current += 1;
            self.sequence = Sequence::StartJoints;
        }
    }

    /// Ends the sequence normally.
    fn finish(&mut self) {
        for jh in &mut self.joints {
            jh.in_sequence = false;
        }
        self.sequence = Sequence::Idle;
    }

    /// Stops the running sequence: its joints that are not homed yet stop
    /// their moves and stay unhomed; joints homed earlier keep their
    /// reference. Nothing happens when no sequence runs.
    pub fn abort(&mut self, jts: &mut [Joint]) {
        if !self.is_active() {
            return;
        }
        for (jh, jt) in self.joints.iter_mut().zip(jts.iter_mut()) {
            if jh.in_sequence && jh.state != HomeState::Idle {
                jt.homing = false;
                jt.homed = false;
                jt.home_stop();
                jh.reset();
            }
        }
        self.finish();
    }

    /// Cancels the sequence if joint `j` is homing in it now (not if it
    /// finished or has yet to start: a jog-abort sent for such a joint
    /// must not end the others' homing).
    pub fn cancel_joint(&mut self, j: usize, jts: &mut [Joint]) {
        if self.in_sequence(j) && self.joints[j].state != HomeState::Idle {
            self.abort(jts);
        }
    }

    /// Whether joint `j` belongs to a synchronised group: some joint with
    /// the same HOME_SEQUENCE magnitude has a negative one.
    pub fn is_synchronized(&self, j: usize) -> bool {
        let mag = self.joints[j].cfg.sequence.unsigned_abs();
        self.joints
            .iter()
            .any(|k| k.cfg.is_synchronized() && k.cfg.sequence.unsigned_abs() == mag)
    }

    /// The output stage: `index-enable` edges.
    pub fn update_outputs(&mut self) {
        for jh in &mut self.joints {
            jh.update_index_output();
        }
    }
}

#[cfg(test)]
mod tests;
