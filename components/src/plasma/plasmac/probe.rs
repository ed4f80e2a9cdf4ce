//! Starting a cycle from idle and finding the top of the stock: a fast
//! move down to the probe start height, a slow one until the float
//! switch (or the ohmic probe) triggers, a creep up until it releases;
//! that height (plus the float switch travel or the ohmic probe offset)
//! is zero. Also the probe test and the ohmic test.

use super::machine::{Ctx, Plasmac};
use super::state::{Fault, State, StopType};

impl Plasmac {
    /// `IDLE`: waits for a request.
    pub(super) fn idle(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        self.o.feed_hold = false;
        self.o.torch_on = false;
        self.o.ohmic_enable = false;
        self.o.scribe_arm = false;
        self.o.scribe_on = false;
        self.stop_type = StopType::None;
        if self.job.pulse_pending && i.torch_enable {
            self.job.pulse_pending = false;
            self.job.back_to = State::Idle;
            self.enter(State::TorchPulse);
        } else if i.ohmic_test {
            self.job.back_to = State::Idle;
            self.enter(State::OhmicTest);
        } else if self.job.scribe_pending {
            self.job.scribe_pending = false;
            self.enter(State::Scribing);
        } else if self.job.probe_test_pending {
            self.job.probe_test_pending = false;
            self.job.probe_test = true;
            self.job.manual = true;
            self.o.probe_test_error = false;
            self.start_cycle(c);
        } else if self.job.start_pending {
            self.job.start_pending = false;
            self.job.spotting = i.spotting_start && !i.cutting_start;
            self.job.manual = !i.program_is_running;
            self.start_cycle(c);
        } else if !i.program_is_running && (self.z.counts != 0 || self.z.target != 0) {
            self.enter(State::EndJob);
        }
    }

    /// Starts a cut, spot or probe test: feed hold on, then probe, or go
    /// straight to the pierce height when the IHS may be skipped.
    pub(super) fn start_cycle(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        self.o.feed_hold = true;
        self.thc.reset();
        self.job.arc_starts = 0;
        if !i.homed {
            return self.raise(c, Fault::NotHomed);
        }
        if c.sensor() {
            return self.raise(c, Fault::SensorBeforeProbe);
        }
        let near_last = self.job.last_end.is_some_and(|(x, y)| {
            (i.axis_x_position - x).hypot(i.axis_y_position - y) < i.skip_ihs_distance
        });
        if near_last && !self.job.probe_test && !self.job.recovering {
            self.z_to_height(c, i.pierce_height);
            return self.enter(State::PierceHeight);
        }
        let start = c.counts_at(i.axis_z_min_limit + i.probe_start_height);
        if start < self.z.counts {
            self.z.go(start, c.speed(i.setup_feed_rate));
            self.enter(State::ProbeHeight);
        } else {
            self.enter(State::ProbeDown);
        }
    }

    /// Stops the Z offset where motion has it now.
    fn z_hold_here(&mut self, c: &Ctx<'_>) {
        let here = c.counts(c.i.z_offset_current);
        self.z.counts = here;
        self.z.go(here, 1);
    }

    /// `PROBE_HEIGHT`: fast down to the probe start height.
    pub(super) fn probe_height(&mut self, c: &Ctx<'_>) {
        if c.sensor() {
            self.job.ohmic_hit = !c.i.float_switch && !c.i.breakaway;
            self.z_hold_here(c);
            return self.enter(State::ProbeUp);
        }
        if self.z_arrived(c) {
            self.enter(State::ProbeDown);
        }
    }

    /// `PROBE_DOWN`: slow down until a sensor triggers; the Z minimum
    /// limit is an error (a probe test only flags it).
    pub(super) fn probe_down(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        self.o.ohmic_enable = i.ohmic_probe_enable;
        let ohmic = i.ohmic_probe_enable && i.ohmic_probe;
        if ohmic || i.float_switch || i.breakaway {
            self.job.ohmic_hit = ohmic;
            self.o.ohmic_enable = ohmic;
            self.z_hold_here(c);
            return self.enter(State::ProbeUp);
        }
        let bottom = c.counts_at(i.axis_z_min_limit);
        if self.z.counts <= bottom && self.z_arrived(c) {
            if self.job.probe_test {
                self.o.probe_test_error = true;
                self.stop_type = StopType::Stop;
                return self.go_top(c);
            }
            return self.raise(c, Fault::ProbeMinLimit);
        }
        self.z.go(bottom, c.speed(i.probe_feed_rate));
    }

    /// `PROBE_UP`: creeps up until the sensor releases.
    pub(super) fn probe_up(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        let held = if self.job.ohmic_hit {
            i.ohmic_probe
        } else {
            i.float_switch || i.breakaway
        };
        if held {
            if self.z.counts < c.top() {
                self.z.nudge(i.probe_final_speed.max(1));
            }
        } else {
            self.z_hold_here(c);
            self.enter(State::ZeroHeight);
        }
    }

    /// `ZERO_HEIGHT`: takes the top of the stock as zero and moves to the
    /// pierce height.
    pub(super) fn zero_height(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        let above = if self.job.ohmic_hit {
            i.ohmic_probe_offset
        } else {
            i.float_switch_travel
        };
        self.zero = self.z.counts.saturating_add(c.counts(above));
        self.o.ohmic_enable = false;
        self.z_to_height(c, i.pierce_height);
        self.enter(State::PierceHeight);
    }

    /// `PROBE_TEST`: holds at the pierce height while the test is held.
    pub(super) fn probe_test(&mut self, c: &Ctx<'_>) {
        if !c.i.probe_test {
            self.job.probe_test = false;
            self.o.feed_hold = false;
            self.enter(State::EndCut);
        }
    }

    /// `OHMIC_TEST`: the ohmic probe is enabled while the test is held.
    pub(super) fn ohmic_test(&mut self, c: &Ctx<'_>) {
        self.o.ohmic_enable = c.i.ohmic_test;
        if !c.i.ohmic_test {
            let back = self.job.back_to;
            self.enter(back);
        }
    }
}
