//! Lighting the torch: the move to the pierce height, the start with its
//! retries, the pierce delay and the puddle jump; also the torch pulse
//! and the scribe, which use the torch's outputs without a cut.

use super::machine::{Ctx, Plasmac};
use super::state::{Fault, State};

impl Plasmac {
    /// `PIERCE_HEIGHT`: waits for the move; a probe test stops here, a
    /// disabled torch goes on without firing (a dry run).
    pub(super) fn pierce_height(&mut self, c: &Ctx<'_>) {
        if !self.z_arrived(c) {
            return;
        }
        if self.job.probe_test {
            self.enter(State::ProbeTest);
        } else if c.i.torch_enable {
            self.enter(State::TorchOn);
        } else {
            self.enter(State::PierceDelay);
        }
    }

    /// `TORCH_ON`: fires the torch.
    pub(super) fn torch_on(&mut self, _c: &Ctx<'_>) {
        self.o.torch_on = true;
        self.o.pierce_count = self.o.pierce_count.saturating_add(1);
        self.job.arc_starts = self.job.arc_starts.saturating_add(1);
        self.enter(State::ArcOk);
    }

    /// `ARC_OK`: waits `arc-fail-delay` for Arc OK; on a failure the
    /// torch goes off for `restart-delay` and fires again, up to
    /// `arc-max-starts` times.
    pub(super) fn arc_ok(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        if !self.o.torch_on {
            if self.timer >= i.restart_delay {
                self.enter(State::TorchOn);
            }
            return;
        }
        if !c.arc_ok_required() || self.senses.arc_ok {
            return self.enter(State::PierceDelay);
        }
        if self.timer >= i.arc_fail_delay {
            self.o.torch_on = false;
            if self.job.arc_starts >= i.arc_max_starts.max(1) {
                return self.raise(c, Fault::NoArc);
            }
            self.timer = 0.0;
        }
    }

    /// `PIERCE_DELAY`: waits out the pierce, then the puddle jump or the
    /// cut height.
    pub(super) fn pierce_delay(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        if self.arc_lost(c) {
            return;
        }
        if self.timer < i.pierce_delay {
            return;
        }
        if i.puddle_jump_height > 0.0 && i.puddle_jump_delay > 0.0 {
            self.z_to_height(c, i.pierce_height * i.puddle_jump_height / 100.0);
            self.o.feed_hold = false;
            self.enter(State::PuddleJump);
        } else {
            self.z_to_height(c, i.cut_height);
            self.o.feed_hold = false;
            self.enter(State::CutHeight);
        }
    }

    /// `PUDDLE_JUMP`: motion runs at the puddle jump height for its delay.
    pub(super) fn puddle_jump(&mut self, c: &Ctx<'_>) {
        if self.arc_lost(c) {
            return;
        }
        if self.timer >= c.i.puddle_jump_delay && self.z_arrived(c) {
            self.z_to_height(c, c.i.cut_height);
            self.enter(State::CutHeight);
        }
    }

    /// Arc OK lost for `arc-lost-delay` while the torch should be lit:
    /// raises the fault and says so.
    pub(super) fn arc_lost(&mut self, c: &Ctx<'_>) -> bool {
        if !self.o.torch_on || !c.arc_ok_required() || self.senses.arc_ok {
            self.thc.lost = 0.0;
            return false;
        }
        self.thc.lost += c.dt;
        if self.thc.lost >= c.i.arc_lost_delay {
            self.raise(c, Fault::ArcLost);
            return true;
        }
        false
    }

    /// `TORCHPULSE`: the torch is on for `torch-pulse-time` (while the
    /// start is held if that is zero).
    pub(super) fn torch_pulse(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        let on = if i.torch_pulse_time > 0.0 {
            self.timer < i.torch_pulse_time
        } else {
            i.torch_pulse_start
        };
        self.o.torch_on = on && i.torch_enable;
        if !self.o.torch_on {
            let back = self.job.back_to;
            self.enter(back);
        }
    }

    /// `SCRIBING`: arm, then on, then motion, until the scribe stops.
    pub(super) fn scribing(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        if !i.scribe_start {
            self.o.scribe_arm = false;
            self.o.scribe_on = false;
            self.o.feed_hold = false;
            return self.enter(State::Idle);
        }
        self.o.scribe_arm = true;
        self.o.scribe_on = self.timer >= i.scribe_arm_delay;
        self.o.feed_hold = self.timer < i.scribe_arm_delay + i.scribe_on_delay;
    }
}
