//! Task's canon for the spindles and the feed mode: M3/M4/M5 and S as
//! motion's SPINDLE_ON and SPINDLE_OFF, constant surface speed (G96 with
//! its D limit) and feed per revolution (G95) as motion's SpindleCss and
//! SetFeedPerRev, and spindle-synchronised motion (G33, G33.1, G76) as
//! motion's SpindleSync.

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
        if self.synched.is_some() {
            // Locked to the spindle's position: the feed mode waits.
            return;
        }
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

    /// After an abort: motion's planner forgot its feed per revolution
    /// and its synchronisation.
    pub fn planner_reset(&mut self) {
        self.sent_per_rev = (0, 0.0);
        self.synched = None;
    }

    /// START_SPEED_FEED_SYNCH: the feed moves that follow go `per_rev`
    /// program units per revolution of `spindle`, locked to its position
    /// (or, `velocity_mode`, to its speed).
    pub(super) fn start_synch(&mut self, spindle: i32, per_rev: f64, velocity_mode: bool) {
        if self.spindle_mut(spindle).is_none() {
            return;
        }
        let per_rev = per_rev * self.units.mm_per_unit() * self.user_per_mm;
        if velocity_mode {
            // As G95: the feed mode's bookkeeping sends it.
            self.synched = None;
            self.sent_per_rev = (spindle, per_rev);
        } else {
            self.synched = Some((spindle, per_rev));
        }
        self.ops.push_back(Op::Motion(Command::SpindleSync {
            spindle,
            per_rev,
            velocity_mode,
        }));
    }

    /// STOP_SPEED_FEED_SYNCH: motion's synchronisation off (which ends a
    /// feed per revolution too: the next feed move sends it again).
    pub(super) fn stop_synch(&mut self) {
        let spindle = self.synched.map_or(self.sent_per_rev.0, |s| s.0);
        self.synched = None;
        self.sent_per_rev = (spindle, 0.0);
        self.ops.push_back(Op::Motion(Command::SpindleSync {
            spindle,
            per_rev: 0.0,
            velocity_mode: false,
        }));
    }

    /// RIGID_TAP (G33.1): motion taps to `end` (program X, Y, Z) and
    /// comes back; the queue ends where it was.
    pub(super) fn queue_rigid_tap(&mut self, line: i32, end: (f64, f64, f64), scale: f64) {
        if self.synched.is_none() {
            return self.refuse("rigid tapping (G33.1) without spindle synchronisation");
        }
        let mut at = self.to_program(self.goal);
        (at.x, at.y, at.z) = end;
        let bottom = self.to_machine(&at);
        let vel = self.synched_speed().unwrap_or(self.feed_per_second());
        self.ops.push_back(Op::Motion(Command::RigidTap {
            end: motion::Pose(bottom),
            vel,
            scale,
            id: line,
        }));
    }

    /// The programmed path speed of a synchronised feed move (machine
    /// units per second): the pitch at the spindle's programmed speed.
    /// Motion follows the spindle instead; the speed only has to be a
    /// valid one.
    pub(super) fn synched_speed(&self) -> Option<f64> {
        let (spindle, per_rev) = self.synched?;
        let rpm = self.spindles.get(spindle as usize).map_or(0.0, |s| s.1);
        let v = per_rev * rpm.abs() / 60.0;
        (v.is_finite() && v > 0.0).then_some(v)
    }
}
