//! One joint's homing state machine.
//!
//! Each servo cycle in free mode, [`JointHoming::step`] runs the joint's
//! state and any states it hands over to at once (setting a position,
//! moving on from a finished wait); a state that starts a move hands over
//! in the next cycle, after the planner has run. Every state that starts
//! a move first waits for the joint to stand still and then [`HOME_DELAY`]
//! more, so motion has ceased and switches have settled. LinuxCNC skips
//! that delay before the final move; here it applies there too.

use super::state::{HomeFault, HomeState};
use crate::joint::Joint;
use crate::vocab::{HomeFlags, HomingConfig};

/// Seconds a joint stands still before each homing move starts.
pub const HOME_DELAY: f64 = 0.1;

/// More hand-overs than any path through the states takes in one cycle.
const MAX_HANDOVERS: usize = 32;

/// The homing state of one joint.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct JointHoming {
    /// Configuration.
    pub cfg: HomingConfig,
    /// Where the state machine is.
    pub state: HomeState,
    /// Cycles counted towards [`HOME_DELAY`].
    pause: u32,
    /// Homing wants the encoder's index armed.
    pub index_request: bool,
    /// `index-enable` has been driven true for the present request.
    pub index_written: bool,
    /// What the output stage must write to `index-enable` this cycle.
    pub index_drive: Option<bool>,
    /// `joint.N.unlock`.
    pub unlock: bool,
    /// `joint.N.is-unlocked`, latched at the start of the cycle.
    pub is_unlocked: bool,
    /// Part of the running homing sequence.
    pub in_sequence: bool,
    /// Synchronised joint ready for its final move, waiting for its group.
    pub ready_final: bool,
    /// Every state entered, for tests.
    #[cfg(test)]
    pub trace: Vec<HomeState>,
}

impl JointHoming {
    /// Enters `state` with a fresh settle delay.
    pub(crate) fn go(&mut self, state: HomeState) {
        #[cfg(test)]
        if self.state != state {
            self.trace.push(state);
        }
        self.state = state;
        self.pause = 0;
    }

    /// Resets to idle with the index disarmed and the indexer locked.
    pub(crate) fn reset(&mut self) {
        self.go(HomeState::Idle);
        self.index_request = false;
        self.unlock = false;
        self.ready_final = false;
    }

    /// Whether the joint stands still and has done so for [`HOME_DELAY`].
    fn settled(&mut self, jt: &Joint, period: f64) -> bool {
        if jt.free_tp.active {
            self.pause = 0;
            return false;
        }
        let need = if period > 0.0 {
            (HOME_DELAY / period).round().clamp(1.0, 1e9) as u32
        } else {
            1
        };
        if self.pause < need {
            self.pause += 1;
            false
        } else {
            true
        }
    }

    /// The checks of every state that waits for an event during a move.
    fn moving_checks(&self, jt: &Joint) -> Result<(), HomeFault> {
        if jt.on_limit() && !self.cfg.flags.contains(HomeFlags::IGNORE_LIMITS) {
            return Err(HomeFault::HitLimit);
        }
        if !jt.free_tp.active {
            return Err(HomeFault::EndOfMove);
        }
        Ok(())
    }

    /// Whether the encoder has seen the index this request armed: the
    /// pin was driven true in an earlier cycle and now reads false.
    pub(crate) fn index_seen(&self, jt: &Joint) -> bool {
        self.state == HomeState::IndexSearchWait
            && self.index_request
            && self.index_written
            && !jt.index_enable
    }

    /// Starts the move to HOME.
    pub(crate) fn start_final_move(&mut self, jt: &mut Joint) {
        jt.home_move_to(self.cfg.home, self.cfg.final_vel);
        self.ready_final = false;
        self.go(HomeState::FinalMoveWait);
    }

    /// Runs this cycle's states. On `Err` the caller aborts the sequence;
    /// `self.state` is then the state that failed.
    pub(crate) fn step(&mut self, jt: &mut Joint, period: f64) -> Result<(), HomeFault> {
        use HomeState::*;
        let f = self.cfg.flags;
        let search = self.cfg.search_vel;
        let latch = self.cfg.latch_vel;
        let index = f.contains(HomeFlags::USE_INDEX);
        for _ in 0..MAX_HANDOVERS {
            let next = match self.state {
                Idle | Abort => return Ok(()),
                Start => {
                    let absolute = f.contains(HomeFlags::ABSOLUTE_ENCODER);
                    if f.contains(HomeFlags::IS_SHARED) && !absolute && jt.home_sw {
                        return Err(HomeFault::SharedSwitchClosed);
                    }
                    if f.contains(HomeFlags::NO_REHOME) && jt.homed {
                        self.go(Idle);
                        return Ok(());
                    }
                    jt.homing = true;
                    jt.homed = false;
                    jt.end_jogs(false);
                    if absolute {
                        SetSwitchPosition
                    } else if f.contains(HomeFlags::UNLOCK_FIRST) {
                        Unlock
                    } else {
                        UnlockWait
                    }
                }
                Unlock => {
                    self.unlock = true;
                    UnlockWait
                }
                UnlockWait => {
                    if f.contains(HomeFlags::UNLOCK_FIRST) && !self.is_unlocked {
                        return Ok(());
                    }
                    // The configuration was checked when it was set, so
                    // the combinations not listed cannot occur; they home
                    // in place rather than move.
                    if search != 0.0 && latch != 0.0 {
                        InitialSearchStart
                    } else if search == 0.0 && latch != 0.0 && index {
                        IndexOnlyStart
                    } else {
                        SetSwitchPosition
                    }
                }
                InitialBackoffStart => {
                    if !self.settled(jt, period) {
                        return Ok(());
                    }
                    jt.home_move(-search);
                    self.go(InitialBackoffWait);
                    return Ok(());
                }
                InitialBackoffWait => {
                    if jt.home_sw {
                        return self.moving_checks(jt);
                    }
                    jt.home_stop();
                    InitialSearchStart
                }
                InitialSearchStart => {
                    if !self.settled(jt, period) {
                        return Ok(());
                    }
                    if jt.home_sw {
                        InitialBackoffStart
                    } else {
                        jt.home_move(search);
                        self.go(InitialSearchWait);
                        return Ok(());
                    }
                }
                InitialSearchWait => {
                    if !jt.home_sw {
                        return self.moving_checks(jt);
                    }
                    jt.home_stop();
                    SetCoarsePosition
                }
                SetCoarsePosition => {
                    jt.set_home_position(self.cfg.offset);
                    if (search > 0.0) == (latch > 0.0) {
                        FinalBackoffStart
                    } else {
                        FallSearchStart
                    }
                }
                FinalBackoffStart => {
                    if !self.settled(jt, period) {
                        return Ok(());
                    }
                    if !jt.home_sw {
                        return Err(HomeFault::SwitchInactiveBeforeBackoff);
                    }
                    jt.home_move(-search);
                    self.go(FinalBackoffWait);
                    return Ok(());
                }
                FinalBackoffWait => {
                    if jt.home_sw {
                        return self.moving_checks(jt);
                    }
                    jt.home_stop();
                    RiseSearchStart
                }
                RiseSearchStart => {
                    if !self.settled(jt, period) {
                        return Ok(());
                    }
                    if jt.home_sw {
                        return Err(HomeFault::SwitchActiveBeforeLatch);
                    }
                    jt.home_move(latch);
                    self.go(RiseSearchWait);
                    return Ok(());
                }
                RiseSearchWait => {
                    if !jt.home_sw {
                        return self.moving_checks(jt);
                    }
                    if index {
                        IndexSearchStart
                    } else {
                        jt.home_stop();
                        SetSwitchPosition
                    }
                }
                FallSearchStart => {
                    if !self.settled(jt, period) {
                        return Ok(());
                    }
                    if !jt.home_sw {
                        return Err(HomeFault::SwitchInactiveBeforeLatch);
                    }
                    jt.home_move(latch);
                    self.go(FallSearchWait);
                    return Ok(());
                }
                FallSearchWait => {
                    if jt.home_sw {
                        return self.moving_checks(jt);
                    }
                    if index {
                        IndexSearchStart
                    } else {
                        jt.home_stop();
                        SetSwitchPosition
                    }
                }
                SetSwitchPosition => {
                    if f.contains(HomeFlags::ABSOLUTE_ENCODER) {
                        // Joint position = raw motor position + HOME_OFFSET.
                        let x = jt.motor_pos_fb - jt.backlash_filt + self.cfg.offset;
                        jt.set_home_position(x);
                        if f.contains(HomeFlags::NO_FINAL_MOVE) {
                            Finished
                        } else {
                            FinalMoveStart
                        }
                    } else {
                        jt.set_home_position(self.cfg.offset);
                        FinalMoveStart
                    }
                }
                IndexOnlyStart => {
                    if !self.settled(jt, period) {
                        return Ok(());
                    }
                    jt.set_home_position(self.cfg.offset);
                    self.index_request = true;
                    jt.home_move(latch);
                    self.go(IndexSearchWait);
                    return Ok(());
                }
                IndexSearchStart => {
                    self.index_request = true;
                    IndexSearchWait
                }
                IndexSearchWait => {
                    if !self.index_seen(jt) {
                        return self.moving_checks(jt);
                    }
                    jt.home_stop();
                    SetIndexPosition
                }
                SetIndexPosition => {
                    self.index_request = false;
                    // The feedback was stood in for by the command in this
                    // cycle: derive it from the motor again.
                    jt.set_index_position(self.cfg.offset);
                    if f.contains(HomeFlags::INDEX_NO_ENCODER_RESET) {
                        // The count did not restart at the index: shift it.
                        jt.set_home_position(self.cfg.offset);
                    }
                    FinalMoveStart
                }
                FinalMoveStart => {
                    if !self.settled(jt, period) {
                        return Ok(());
                    }
                    if self.cfg.is_synchronized() && !f.contains(HomeFlags::ABSOLUTE_ENCODER) {
                        // The sequence manager starts the group together.
                        self.ready_final = true;
                        return Ok(());
                    }
                    self.start_final_move(jt);
                    return Ok(());
                }
                FinalMoveWait => {
                    if jt.on_limit() && !f.contains(HomeFlags::IGNORE_LIMITS) {
                        return Err(HomeFault::HitLimit);
                    }
                    if jt.free_tp.active {
                        return Ok(());
                    }
                    jt.home_stop();
                    Lock
                }
                Lock => {
                    self.unlock = false;
                    LockWait
                }
                LockWait => {
                    if f.contains(HomeFlags::UNLOCK_FIRST) && self.is_unlocked {
                        return Ok(());
                    }
                    Finished
                }
                Finished => {
                    jt.homing = false;
                    jt.homed = true;
                    if !f.contains(HomeFlags::NO_FINAL_MOVE) {
                        // The planner stops within its dead band: land
                        // exactly on HOME.
                        jt.free_tp.curr_pos = self.cfg.home;
                        jt.free_tp.pos_cmd = self.cfg.home;
                    }
                    self.go(Idle);
                    return Ok(());
                }
            };
            self.go(next);
        }
        Ok(())
    }

    /// Computes this cycle's `index-enable` write: true on the rising edge
    /// of the request, false on its falling edge, nothing otherwise (the
    /// encoder writes the same signal).
    pub(crate) fn update_index_output(&mut self) {
        self.index_drive = None;
        if self.index_request && !self.index_written {
            self.index_drive = Some(true);
            self.index_written = true;
        } else if !self.index_request && self.index_written {
            self.index_drive = Some(false);
            self.index_written = false;
        }
    }
}
