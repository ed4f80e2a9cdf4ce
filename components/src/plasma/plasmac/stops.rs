//! Leaving a cut: the safe height, the top (after a stop, a pause or an
//! error) and what may happen while waiting there paused (paused motion,
//! consumable change, cut recovery, torch pulse, ohmic test), the end of
//! a cut and of a job.

use super::machine::{Ctx, Plasmac};
use super::state::{State, StopType};

impl Plasmac {
    /// `SAFE_HEIGHT`: motion held until Z is at the safe height.
    pub(super) fn safe_height(&mut self, c: &Ctx<'_>) {
        self.o.torch_on = false;
        self.o.feed_hold = true;
        if self.z_arrived(c) {
            self.enter(State::EndCut);
        }
    }

    /// `END_CUT`: the cut is over; the job goes on while a program runs.
    pub(super) fn end_cut(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        self.o.torch_on = false;
        self.o.feed_hold = false;
        self.o.ohmic_enable = false;
        self.job.spotting = false;
        self.job.probe_test = false;
        self.job.recovering = false;
        self.job.spot_timer = 0.0;
        self.o.cut_recovering = false;
        if i.program_is_running && !i.program_is_paused && self.stop_type != StopType::Stop {
            self.stop_type = StopType::None;
            self.enter(State::Idle);
        } else {
            self.enter(State::EndJob);
        }
    }

    /// `END_JOB`: takes every offset back, then idle.
    pub(super) fn end_job(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        self.o.feed_hold = false;
        self.z.go(0, c.speed(i.setup_feed_rate));
        self.x.go(0, c.speed(i.xy_feed_rate));
        self.y.go(0, c.speed(i.xy_feed_rate));
        let xy_home = self.x.arrived(i.x_offset_current, c.scale)
            && self.y.arrived(i.y_offset_current, c.scale);
        if self.z_arrived(c) && xy_home {
            self.stop_type = StopType::None;
            self.job.manual = false;
            self.o.consumable_changing = false;
            self.o.cut_recovering = false;
            self.enter(State::Idle);
        }
    }

    /// `MAX_HEIGHT`: rises to the top, then waits for what the stop
    /// type allows: a stop ends the job; a pause or an error waits for
    /// resume (the cut starts again from the probe) and meanwhile allows
    /// the paused actions.
    pub(super) fn max_height(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        self.o.torch_on = false;
        self.o.feed_hold = false;
        if !self.job.waiting {
            if self.z_arrived(c) {
                self.job.waiting = true;
            }
            return;
        }
        if self.job.manual {
            if !i.cutting_start && !i.spotting_start && !self.job.probe_test {
                self.enter(State::EndCut);
            }
            return;
        }
        if self.stop_type == StopType::Stop || (!i.program_is_running && !i.program_is_paused) {
            self.stop_type = StopType::Stop;
            return self.enter(State::EndCut);
        }
        if i.program_is_paused {
            self.job.paused_seen = true;
            return self.paused_action(c);
        }
        if self.job.paused_seen && i.program_is_running {
            // Resumed.
            self.stop_type = StopType::None;
            self.job.paused_seen = false;
            if i.cutting_start || i.spotting_start {
                self.start_cycle(c);
            } else {
                self.enter(State::EndCut);
            }
        }
    }

    /// What may start while paused at the top.
    fn paused_action(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        if i.consumable_change && self.stop_type != StopType::None {
            self.enter(State::ConsumableChangeOn);
        } else if i.cut_recovery {
            self.enter(State::CutRecoveryOn);
        } else if i.paused_motion_speed != 0.0 {
            self.o.program_resume = true;
            self.enter(State::PausedMotion);
        } else if self.job.pulse_pending && i.torch_enable {
            self.job.pulse_pending = false;
            self.job.back_to = State::MaxHeight;
            self.enter(State::TorchPulse);
        } else if i.ohmic_test {
            self.job.back_to = State::MaxHeight;
            self.enter(State::OhmicTest);
        }
    }

    /// `PAUSED_MOTION`: motion runs along the path (backwards for a
    /// negative speed) at `paused-motion-speed` while it is not zero,
    /// then pauses again.
    pub(super) fn paused_motion(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        if !i.program_is_running && !i.program_is_paused {
            self.o.paused_motion = false;
            self.stop_type = StopType::Stop;
            return self.enter(State::EndCut);
        }
        if i.paused_motion_speed != 0.0 {
            self.o.paused_motion = true;
            self.o.adaptive_feed = i.paused_motion_speed.clamp(-1.0, 1.0);
            return;
        }
        self.o.paused_motion = false;
        self.o.adaptive_feed = 0.0;
        self.o.program_resume = false;
        self.o.program_pause = true;
        self.job.paused_seen = false;
        self.enter(State::MaxHeight);
    }

    /// `CONSUMABLE_CHANGE_ON`: X/Y go to `x-offset`/`y-offset` (held
    /// within the X and Y limits) while the change is asked for.
    pub(super) fn consumable_change_on(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        self.o.consumable_changing = true;
        let v = c.speed(i.xy_feed_rate);
        let (x, y) = c.xy_within_limits(i.x_offset, i.y_offset);
        self.x.go(x, v);
        self.y.go(y, v);
        if !i.consumable_change {
            self.enter(State::ConsumableChangeOff);
        }
    }

    /// `CONSUMABLE_CHANGE_OFF`: X/Y come back, then wait at the top.
    pub(super) fn consumable_change_off(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        let v = c.speed(i.xy_feed_rate);
        self.x.go(0, v);
        self.y.go(0, v);
        if self.x.arrived(i.x_offset_current, c.scale)
            && self.y.arrived(i.y_offset_current, c.scale)
        {
            self.o.consumable_changing = false;
            self.enter(State::MaxHeight);
        }
    }

    /// `CUT_RECOVERY_ON`: X/Y follow `x-offset`/`y-offset` (the GUI moves
    /// them); on resume the cut starts again there.
    pub(super) fn cut_recovery_on(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        self.o.cut_recovering = true;
        let v = c.speed(i.xy_feed_rate);
        let (x, y) = c.xy_within_limits(i.x_offset, i.y_offset);
        self.x.go(x, v);
        self.y.go(y, v);
        if i.program_is_paused {
            self.job.paused_seen = true;
            if !i.cut_recovery && i.x_offset == 0 && i.y_offset == 0 {
                self.o.cut_recovering = false;
                self.enter(State::MaxHeight);
            }
            return;
        }
        if !i.program_is_running {
            self.stop_type = StopType::Stop;
            return self.enter(State::EndCut);
        }
        if self.job.paused_seen {
            self.job.paused_seen = false;
            self.stop_type = StopType::None;
            self.job.recovering = true;
            self.start_cycle(c);
        }
    }

    /// `CUT_RECOVERY_OFF`: cutting, with the path held, X/Y go back to the
    /// path at the cut feed rate; then the cut goes on.
    pub(super) fn cut_recovery_off(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        if self.arc_lost(c) {
            return;
        }
        self.o.feed_hold = true;
        let v = c.speed(i.cut_feed_rate);
        self.x.go(0, v);
        self.y.go(0, v);
        if self.x.arrived(i.x_offset_current, c.scale)
            && self.y.arrived(i.y_offset_current, c.scale)
        {
            self.o.feed_hold = false;
            self.o.cut_recovering = false;
            self.job.recovering = false;
            self.enter_cut_mode(c);
        }
    }
}
