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

/// What a state did in this cycle.
enum Step {
    /// Hand over to this state now.
    Next(HomeState),
    /// Done for this cycle (a move runs, or something is awaited).
    Wait,
}

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
        for _ in 0..MAX_HANDOVERS {
            match self.run_state(jt, period)? {
                Step::Next(next) => self.go(next),
                Step::Wait => return Ok(()),
            }
        }
        Ok(())
    }

    /// Runs the current state once.
    fn run_state(&mut self, jt: &mut Joint, period: f64) -> Result<Step, HomeFault> {
        use HomeState::*;
        let (search, latch) = (self.cfg.search_vel, self.cfg.latch_vel);
        let sw = jt.home_sw;
        match self.state {
            Idle | Abort => Ok(Step::Wait),
            Start => self.start(jt),
            Unlock => {
                self.unlock = true;
                Ok(Step::Next(UnlockWait))
            }
            UnlockWait => Ok(self.after_unlock()),
            // The switch: search for it, back off, latch on an edge.
            InitialBackoffStart => Ok(self.start_move(jt, period, -search, InitialBackoffWait)),
            InitialBackoffWait => self.wait_move(jt, !sw, InitialSearchStart),
            InitialSearchStart => Ok(self.initial_search(jt, period)),
            InitialSearchWait => self.wait_move(jt, sw, SetCoarsePosition),
            SetCoarsePosition => {
                jt.set_home_position(self.cfg.offset);
                let back_off = (search > 0.0) == (latch > 0.0);
                Ok(Step::Next(if back_off {
                    FinalBackoffStart
                } else {
                    FallSearchStart
                }))
            }
            FinalBackoffStart => {
                let fault = HomeFault::SwitchInactiveBeforeBackoff;
                self.switch_move(jt, period, (true, fault), -search, FinalBackoffWait)
            }
            FinalBackoffWait => self.wait_move(jt, !sw, RiseSearchStart),
            RiseSearchStart => {
                let fault = HomeFault::SwitchActiveBeforeLatch;
                self.switch_move(jt, period, (false, fault), latch, RiseSearchWait)
            }
            RiseSearchWait => self.latch_move(jt, sw),
            FallSearchStart => {
                let fault = HomeFault::SwitchInactiveBeforeLatch;
                self.switch_move(jt, period, (true, fault), latch, FallSearchWait)
            }
            FallSearchWait => self.latch_move(jt, !sw),
            // Where the joint is: the switch, the index, the encoder.
            SetSwitchPosition => Ok(self.set_switch_position(jt)),
            IndexOnlyStart => {
                if !self.settled(jt, period) {
                    return Ok(Step::Wait);
                }
                jt.set_home_position(self.cfg.offset);
                self.index_request = true;
                Ok(self.begin_move(jt, latch, IndexSearchWait))
            }
            IndexSearchStart => {
                self.index_request = true;
                Ok(Step::Next(IndexSearchWait))
            }
            IndexSearchWait => {
                let seen = self.index_seen(jt);
                self.wait_move(jt, seen, SetIndexPosition)
            }
            SetIndexPosition => Ok(self.set_index_position(jt)),
            // The move to HOME, the lock, done.
            FinalMoveStart => Ok(self.final_move_start(jt, period)),
            FinalMoveWait => self.final_move_wait(jt),
            Lock => {
                self.unlock = false;
                Ok(Step::Next(LockWait))
            }
            LockWait => Ok(if self.unlock_first() && self.is_unlocked {
                Step::Wait
            } else {
                Step::Next(Finished)
            }),
            Finished => Ok(self.finish(jt)),
        }
    }

    /// Whether the joint is a locking indexer.
    fn unlock_first(&self) -> bool {
        self.cfg.flags.contains(HomeFlags::UNLOCK_FIRST)
    }

    /// START: refuses a closed shared switch, ends at once for a homed
    /// joint that must not re-home, otherwise unhomes the joint.
    fn start(&mut self, jt: &mut Joint) -> Result<Step, HomeFault> {
        let f = self.cfg.flags;
        let absolute = f.contains(HomeFlags::ABSOLUTE_ENCODER);
        if f.contains(HomeFlags::IS_SHARED) && !absolute && jt.home_sw {
            return Err(HomeFault::SharedSwitchClosed);
        }
        if f.contains(HomeFlags::NO_REHOME) && jt.homed {
            self.go(HomeState::Idle);
            return Ok(Step::Wait);
        }
        jt.homing = true;
        jt.homed = false;
        jt.end_jogs(false);
        Ok(Step::Next(if absolute {
            HomeState::SetSwitchPosition
        } else if self.unlock_first() {
            HomeState::Unlock
        } else {
            HomeState::UnlockWait
        }))
    }

    /// UNLOCK_WAIT: once unlocked, the first move of the configured way
    /// of homing.
    fn after_unlock(&self) -> Step {
        if self.unlock_first() && !self.is_unlocked {
            return Step::Wait;
        }
        let (search, latch) = (self.cfg.search_vel, self.cfg.latch_vel);
        let index = self.cfg.flags.contains(HomeFlags::USE_INDEX);
        // The configuration was checked when it was set, so the
        // combinations not listed cannot occur; they home in place rather
        // than move.
        Step::Next(if search != 0.0 && latch != 0.0 {
            HomeState::InitialSearchStart
        } else if search == 0.0 && latch != 0.0 && index {
            HomeState::IndexOnlyStart
        } else {
            HomeState::SetSwitchPosition
        })
    }

    /// Starts a homing move at `vel` and waits for it in `wait`.
    fn begin_move(&mut self, jt: &mut Joint, vel: f64, wait: HomeState) -> Step {
        jt.home_move(vel);
        self.go(wait);
        Step::Wait
    }

    /// A move's start state: once settled, the move at `vel`.
    fn start_move(&mut self, jt: &mut Joint, period: f64, vel: f64, wait: HomeState) -> Step {
        if !self.settled(jt, period) {
            return Step::Wait;
        }
        self.begin_move(jt, vel, wait)
    }

    /// A move's start state that needs the home switch `closed` (else
    /// `fault`).
    fn switch_move(
        &mut self,
        jt: &mut Joint,
        period: f64,
        (closed, fault): (bool, HomeFault),
        vel: f64,
        wait: HomeState,
    ) -> Result<Step, HomeFault> {
        if !self.settled(jt, period) {
            return Ok(Step::Wait);
        }
        if jt.home_sw != closed {
            return Err(fault);
        }
        Ok(self.begin_move(jt, vel, wait))
    }

    /// INITIAL_SEARCH_START: on the switch already, back off first.
    fn initial_search(&mut self, jt: &mut Joint, period: f64) -> Step {
        if !self.settled(jt, period) {
            return Step::Wait;
        }
        if jt.home_sw {
            Step::Next(HomeState::InitialBackoffStart)
        } else {
            self.begin_move(jt, self.cfg.search_vel, HomeState::InitialSearchWait)
        }
    }

    /// A move's wait state: until `done` the move must go on; then it
    /// stops and `next` follows.
    fn wait_move(&self, jt: &mut Joint, done: bool, next: HomeState) -> Result<Step, HomeFault> {
        if !done {
            return self.moving_checks(jt).map(|()| Step::Wait);
        }
        jt.home_stop();
        Ok(Step::Next(next))
    }

    /// A latch move's wait state: once `edge`, on to the index search, or
    /// stop at the switch position.
    fn latch_move(&self, jt: &mut Joint, edge: bool) -> Result<Step, HomeFault> {
        if !edge {
            return self.moving_checks(jt).map(|()| Step::Wait);
        }
        if self.cfg.flags.contains(HomeFlags::USE_INDEX) {
            return Ok(Step::Next(HomeState::IndexSearchStart));
        }
        jt.home_stop();
        Ok(Step::Next(HomeState::SetSwitchPosition))
    }

    /// SET_SWITCH_POSITION: HOME_OFFSET here, or for an absolute encoder
    /// the raw motor position plus HOME_OFFSET.
    fn set_switch_position(&mut self, jt: &mut Joint) -> Step {
        let f = self.cfg.flags;
        if !f.contains(HomeFlags::ABSOLUTE_ENCODER) {
            jt.set_home_position(self.cfg.offset);
            return Step::Next(HomeState::FinalMoveStart);
        }
        let x = jt.motor_pos_fb - jt.backlash_filt + self.cfg.offset;
        jt.set_home_position(x);
        Step::Next(if f.contains(HomeFlags::NO_FINAL_MOVE) {
            HomeState::Finished
        } else {
            HomeState::FinalMoveStart
        })
    }

    /// SET_INDEX_POSITION: HOME_OFFSET at the index.
    fn set_index_position(&mut self, jt: &mut Joint) -> Step {
        self.index_request = false;
        // The feedback was stood in for by the command in this cycle:
        // derive it from the motor again.
        jt.set_index_position(self.cfg.offset);
        if self.cfg.flags.contains(HomeFlags::INDEX_NO_ENCODER_RESET) {
            // The count did not restart at the index: shift it.
            jt.set_home_position(self.cfg.offset);
        }
        Step::Next(HomeState::FinalMoveStart)
    }

    /// FINAL_MOVE_START: once settled, the move to HOME (a synchronised
    /// group's members wait for the sequence manager to start them
    /// together).
    fn final_move_start(&mut self, jt: &mut Joint, period: f64) -> Step {
        if !self.settled(jt, period) {
            return Step::Wait;
        }
        let absolute = self.cfg.flags.contains(HomeFlags::ABSOLUTE_ENCODER);
        if self.cfg.is_synchronized() && !absolute {
            self.ready_final = true;
        } else {
            self.start_final_move(jt);
        }
        Step::Wait
    }

    /// FINAL_MOVE_WAIT: until the joint is at HOME.
    fn final_move_wait(&self, jt: &mut Joint) -> Result<Step, HomeFault> {
        if jt.on_limit() && !self.cfg.flags.contains(HomeFlags::IGNORE_LIMITS) {
            return Err(HomeFault::HitLimit);
        }
        if jt.free_tp.active {
            return Ok(Step::Wait);
        }
        jt.home_stop();
        Ok(Step::Next(HomeState::Lock))
    }

    /// FINISHED: the joint is homed.
    fn finish(&mut self, jt: &mut Joint) -> Step {
        jt.homing = false;
        jt.homed = true;
        if !self.cfg.flags.contains(HomeFlags::NO_FINAL_MOVE) {
            // The planner stops within its dead band: land exactly on
            // HOME.
            jt.free_tp.curr_pos = self.cfg.home;
            jt.free_tp.pos_cmd = self.cfg.home;
        }
        self.go(HomeState::Idle);
        Step::Wait
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
