//! Task's canon for the spindles and the feed mode: M3/M4/M5 and S as
//! motion's SPINDLE_ON and SPINDLE_OFF, constant surface speed (G96 with
//! its D limit) and feed per revolution (G95) as motion's SpindleCss and
//! SetFeedPerRev.

use motion::Command;
use rs274ngc::{Direction, Units};

use super::{Op, TaskCanon};

impl TaskCanon {
    /// Spindle `spindle`'s modal state; `None` (and a fault) for a
    /// number motion has no spindle for.
    pub(super) fn spindle_mut(&mut self, spindle: i32) -> Option<&mut (Direction, f64)> {
        let slot = usize::try_from(spindle)
            .ok()
            .filter(|&n| n < self.spindles.len());
        match slot {
            Some(n) => Some(&mut self.spindles[n]),
            None => {
                self.refuse(&format!("spindle {spindle}"));
                None
            }
        }
    }

    /// Sets spindle `spindle`'s direction and speed (`None`: as they
    /// are) and queues what motion must do: a start or a speed change
    /// while it turns, a stop for M5. A speed set while it stands only
    /// changes the modal state.
    pub(super) fn queue_spindle(
        &mut self,
        spindle: i32,
        direction: Option<Direction>,
        rpm: Option<f64>,
    ) {
        let Some(state) = self.spindle_mut(spindle) else {
            return;
        };
        let stop = direction == Some(Direction::Stopped);
        if let Some(d) = direction {
            state.0 = d;
        }
        if let Some(r) = rpm {
            state.1 = r;
        }
        let (dir, speed) = *state;
        let css_limit = self.css_limit[spindle as usize];
        // With constant surface speed motion turns the spindle at the
        // speed for the radius, at most the limit given with SPINDLE_ON.
        let (rpm, factor) = if css_limit > 0.0 {
            (css_limit, self.css_factor(speed))
        } else {
            (speed, 0.0)
        };
        let command = match dir {
            Direction::Stopped if stop => Command::SpindleOff { spindle },
            Direction::Stopped => return,
            Direction::Clockwise | Direction::CounterClockwise => Command::SpindleOn {
                spindle,
                speed: if dir == Direction::Clockwise {
                    rpm.abs()
                } else {
                    -rpm.abs()
                },
                wait: true,
            },
        };
        if matches!(command, Command::SpindleOn { .. }) {
            // The surface speed first: the limit alone would be the speed
            // for a period.
            let x_offset = self.g5x[0] + self.g92[0] + self.tool_offset[0];
            self.after_moves(Command::SpindleCss {
                spindle,
                factor,
                x_offset,
            });
        }
        self.after_moves(command);
    }

    /// Constant surface speed `surface` (G96 S: metres per minute in
    /// G21, feet per minute in G20) as rpm times radius in machine units.
    pub(super) fn css_factor(&self, surface: f64) -> f64 {
        let program_units_per_min = match self.units {
            Units::Inches => surface * 12.0,
            _ => surface * 1000.0,
        };
        let machine = program_units_per_min * self.units.mm_per_unit() * self.user_per_mm;
        machine.abs() / std::f64::consts::TAU
    }

    /// Before a feed move: motion's feed per revolution as the program's
    /// (G95 F, machine units per revolution; 0 in G93 and G94).
    pub(super) fn sync_feed_mode(&mut self) {
        let want = match self.feed_per_rev {
            Some(spindle) => (
                spindle,
                self.feed * self.units.mm_per_unit() * self.user_per_mm,
            ),
            None => (self.sent_per_rev.0, 0.0),
        };
        if want != self.sent_per_rev {
            self.sent_per_rev = want;
            self.ops.push_back(Op::Motion(Command::SetFeedPerRev {
                spindle: want.0,
                per_rev: want.1,
            }));
        }
    }

    /// After an abort: motion's planner forgot its feed per revolution.
    pub fn planner_reset(&mut self) {
        self.sent_per_rev = (0, 0.0);
    }
}
