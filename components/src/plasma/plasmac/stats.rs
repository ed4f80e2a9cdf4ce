//! The job statistics QtPlasmaC shows: run, paused, rapid, probe, torch
//! and cut times, cut length and pierce count, reset when a program
//! starts.

use super::machine::Ctx;
use super::pins::Outputs;
use super::state::State;

/// What the statistics remember between calls.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Stats {
    was_running: bool,
    last_xy: (f64, f64),
}

impl Stats {
    /// One period.
    pub fn update(&mut self, c: &Ctx<'_>, o: &mut Outputs, state: State) {
        let i = c.i;
        let dt = c.dt;
        if i.program_is_running && !self.was_running {
            o.run_time = 0.0;
            o.paused_time = 0.0;
            o.rapid_time = 0.0;
            o.probe_time = 0.0;
            o.torch_time = 0.0;
            o.cut_time = 0.0;
            o.cut_length = 0.0;
            o.pierce_count = 0;
        }
        self.was_running = i.program_is_running;
        if i.program_is_running {
            o.run_time += dt;
            if i.program_is_paused {
                o.paused_time += dt;
            } else if i.motion_type == 1 {
                o.rapid_time += dt;
            }
        }
        if state.is_probing() {
            o.probe_time += dt;
        }
        let xy = (i.axis_x_position, i.axis_y_position);
        if o.torch_on {
            o.torch_time += dt;
            if matches!(state, State::CutMode01 | State::CutMode2) {
                o.cut_time += dt;
                let d = (xy.0 - self.last_xy.0).hypot(xy.1 - self.last_xy.1);
                if d.is_finite() {
                    o.cut_length += d;
                }
            }
        }
        self.last_xy = xy;
    }
}
