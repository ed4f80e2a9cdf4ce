//! Cutting: the move to the cut height, the cut itself (torch, arc
//! lost, sensors, spotting, THC with its Z limits) and its end.

use super::machine::{Ctx, Plasmac};
use super::state::{Fault, State, StopType};

impl Plasmac {
    /// `CUT_HEIGHT`: motion runs while Z goes to the cut height.
    pub(super) fn cut_height(&mut self, c: &Ctx<'_>) {
        if self.arc_lost(c) {
            return;
        }
        self.o.feed_hold = false;
        if self.z_arrived(c) {
            if self.job.recovering {
                self.enter(State::CutRecoveryOff);
            } else {
                self.enter_cut_mode(c);
            }
        }
    }

    /// Enters the cut state of the mode.
    pub(super) fn enter_cut_mode(&mut self, c: &Ctx<'_>) {
        let s = if c.i.mode == 2 {
            State::CutMode2
        } else {
            State::CutMode01
        };
        self.enter(s);
    }

    /// `CUT_MODE_01` / `CUT_MODE_2`: the cut.
    pub(super) fn cut_mode(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        let requested = if self.job.spotting {
            i.spotting_start
        } else {
            i.cutting_start
        };
        if !requested {
            return self.end_of_cut(c);
        }
        if i.breakaway {
            return self.raise(c, Fault::Breakaway);
        }
        if i.float_switch {
            return self.raise(c, Fault::FloatSwitch);
        }
        // torch-off (M62/M64 P3) turns the torch off while motion goes on:
        // the over-cut of a hole.
        self.o.torch_on = i.torch_enable && !i.torch_off;
        if self.arc_lost(c) {
            return;
        }
        if self.job.spotting && self.spot_done(c) {
            return self.end_of_cut(c);
        }
        self.correct(c);
    }

    /// A spot ends `spotting-time` ms after the voltage reached
    /// `spotting-threshold`.
    fn spot_done(&mut self, c: &Ctx<'_>) -> bool {
        if self.senses.volts >= c.i.spotting_threshold {
            self.thc.lost = 0.0;
            self.job.spot_timer += c.dt;
        }
        self.job.spot_timer * 1000.0 >= c.i.spotting_time && self.job.spot_timer > 0.0
    }

    /// One THC period and its outputs; Z past a limit stops the program.
    fn correct(&mut self, c: &Ctx<'_>) {
        let lit = self.o.torch_on && (self.senses.arc_ok || !c.arc_ok_required());
        let s = self.thc.step(c, self.senses.volts, lit);
        self.o.thc_active = s.active;
        self.o.cornerlock_is_locked = s.cornerlock;
        self.o.voidlock_is_locked = s.voidlock;
        self.o.target_volts = s.target;
        self.o.led_up = s.delta > 0;
        self.o.led_down = s.delta < 0;
        if s.delta == 0 {
            return;
        }
        let z = c.base_z + f64::from(self.z.counts.saturating_add(s.delta)) * c.scale;
        if z < c.i.axis_z_min_limit {
            return self.raise(c, Fault::ThcMinLimit);
        }
        if z > c.i.axis_z_max_limit {
            return self.raise(c, Fault::ThcMaxLimit);
        }
        self.z.nudge(s.delta);
    }

    /// The cut is over: hold motion for `pause-at-end`, or finish now.
    fn end_of_cut(&mut self, c: &Ctx<'_>) {
        if c.i.pause_at_end > 0.0 && self.o.torch_on {
            self.o.feed_hold = true;
            self.enter(State::PauseAtEnd);
        } else {
            self.finish_cut(c);
        }
    }

    /// `PAUSE_AT_END`: motion held with the torch still on.
    pub(super) fn pause_at_end(&mut self, c: &Ctx<'_>) {
        self.o.feed_hold = true;
        if self.timer >= c.i.pause_at_end {
            self.finish_cut(c);
        }
    }

    /// Torch off, remember where the cut ended, rise to the safe height
    /// (the top when it is zero or above the top).
    pub(super) fn finish_cut(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        self.o.torch_on = false;
        self.thc.reset();
        self.job.last_end = Some((i.axis_x_position, i.axis_y_position));
        let top = c.top();
        let safe = self.zero.saturating_add(c.counts(i.safe_height));
        self.o.safe_height_is_limited = i.safe_height > 0.0 && safe > top;
        let target = if i.safe_height > 0.0 {
            safe.min(top)
        } else {
            top
        };
        self.z.go(target, c.speed(i.setup_feed_rate));
        self.o.feed_hold = true;
        self.enter(State::SafeHeight);
    }

    /// Stops or pauses a cycle when the program does: checked before
    /// every state of a cycle (not for a manual cut or a probe test).
    pub(super) fn program_left(&mut self, c: &Ctx<'_>) -> bool {
        let i = c.i;
        if self.job.manual {
            let asked = i.cutting_start || i.spotting_start || self.job.probe_test;
            if !asked && self.state.is_probing() {
                self.stop_type = StopType::Stop;
                self.go_top(c);
                return true;
            }
            return false;
        }
        if i.program_is_paused {
            self.stop_type = StopType::Pause;
        } else if !i.program_is_running {
            self.stop_type = StopType::Stop;
        } else {
            return false;
        }
        self.thc.reset();
        self.go_top(c);
        true
    }
}
