//! moveoff's state machine: applying offsets while enabled, recording
//! waypoints on the way out, and returning (along the waypoints, if
//! backtracking) when an enable drops.

use super::limiter::{Limiter, Limits};

/// Most joints an instance may have.
pub const MAX_JOINTS: usize = 9;
/// Waypoints one instance can record.
pub const WAYPOINTS: usize = 1000;
/// Waypoints available while `dbg-waypoint-limit-test` is set.
pub const TEST_WAYPOINTS: usize = 50;
/// The smallest `epsilon` used.
pub const MIN_EPSILON: f64 = 0.0001;

/// The state machine's states (the `dbg-state` values).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum State {
    /// No offset applied.
    #[default]
    Idle = 0,
    /// Following the offset inputs.
    MoveAway = 1,
    /// Returning to zero offset.
    MoveBack = 2,
}

/// The pin values `read-inputs` reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct InputVars {
    /// Pin `power-on`.
    pub power_on: bool,
    /// Pin `move-enable`.
    pub move_enable: bool,
    /// Pin `apply-offsets`.
    pub apply_offsets: bool,
    /// Pin `backtrack-enable`.
    pub backtrack_enable: bool,
    /// Pin `epsilon`.
    pub epsilon: f64,
    /// Pin `waypoint-threshold`.
    pub waypoint_threshold: f64,
    /// Pin `waypoint-sample-secs`.
    pub waypoint_sample_secs: f64,
    /// Pin `dbg-waypoint-limit-test`.
    pub dbg_waypoint_limit_test: bool,
    /// Pins `offset-in-M`.
    pub offset_in: [f64; MAX_JOINTS],
    /// Pins `offset-current-M` (read back).
    pub offset_current: [f64; MAX_JOINTS],
    /// Pin `offset-applied` (read back and written).
    pub offset_applied: bool,
    /// Pin `waypoint-limit` (read back and written).
    pub waypoint_limit: bool,
    /// Pin `warning`.
    pub warning: bool,
}

/// The pin values `write-outputs` reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OutputVars {
    /// Pins `pos-M`.
    pub pos: [f64; MAX_JOINTS],
    /// Pins `fb-M`.
    pub fb: [f64; MAX_JOINTS],
    /// Pins `offset-vel-M`, `offset-accel-M`, `offset-min-M`,
    /// `offset-max-M`.
    pub limits: [Limits; MAX_JOINTS],
    /// Pins `offset-current-M`.
    pub offset_current: [f64; MAX_JOINTS],
    /// Pins `pos-plusoffset-M`.
    pub pos_plusoffset: [f64; MAX_JOINTS],
    /// Pins `fb-minusoffset-M`.
    pub fb_minusoffset: [f64; MAX_JOINTS],
    /// Pin `offset-applied`.
    pub offset_applied: bool,
    /// Pin `waypoint-limit` (read back and written).
    pub waypoint_limit: bool,
    /// Pin `waypoint-ct`.
    pub waypoint_ct: i32,
    /// Pin `waypoint-percent-used`.
    pub waypoint_percent_used: i32,
    /// Pin `dbg-state`.
    pub dbg_state: i32,
}

impl Default for Limits {
    /// The pins' defaults.
    fn default() -> Self {
        Limits {
            min: -1e20,
            max: 1e20,
            maxv: 10.0,
            maxa: 100.0,
        }
    }
}

/// One instance's state, shared by its two functions.
#[derive(Debug, Clone)]
pub struct Moveoff {
    joints: usize,
    state: State,
    next_state: State,
    next_waypoint: usize,
    last_waypoint_time: i64,
    move_threshold: f64,
    min_sample_interval: f64,
    backtrack: bool,
    gave_msg: bool,
    max_waypoints: usize,
    goal: [f64; MAX_JOINTS],
    waypoints: Vec<[f64; MAX_JOINTS]>,
    limiters: [Limiter; MAX_JOINTS],
    eps: f64,
    move_in_progress: bool,
    period: i64,
}

impl Moveoff {
    /// An idle instance for `joints` joints (at most [`MAX_JOINTS`]).
    pub fn new(joints: usize) -> Moveoff {
        Moveoff {
            joints: joints.min(MAX_JOINTS),
            state: State::Idle,
            next_state: State::Idle,
            next_waypoint: 0,
            last_waypoint_time: 0,
            move_threshold: 0.0,
            min_sample_interval: 0.0,
            backtrack: false,
            gave_msg: false,
            max_waypoints: WAYPOINTS,
            goal: [0.0; MAX_JOINTS],
            waypoints: vec![[0.0; MAX_JOINTS]; WAYPOINTS],
            limiters: [Limiter::default(); MAX_JOINTS],
            eps: MIN_EPSILON,
            move_in_progress: false,
            period: 0,
        }
    }

    /// The current state (for tests).
    #[cfg(test)]
    pub fn state(&self) -> State {
        self.state
    }

    fn reset_limiters(&mut self) {
        self.limiters = [Limiter::default(); MAX_JOINTS];
    }

    /// The last recorded waypoint, or the origin before the first.
    fn last_waypoint(&self) -> [f64; MAX_JOINTS] {
        self.next_waypoint
            .checked_sub(1)
            .map_or([0.0; MAX_JOINTS], |i| self.waypoints[i])
    }

    /// `read-inputs` at time `now` (ns) in a thread of `period` ns.
    /// Returns TRUE when the warning message should be printed.
    pub fn read_inputs(&mut self, v: &mut InputVars, now: i64, period: i64) -> bool {
        let n = self.joints;
        let all_enables = v.power_on && v.move_enable && v.apply_offsets;
        self.backtrack = v.backtrack_enable;
        self.period = period;
        if self.state == State::Idle {
            self.move_threshold = v.waypoint_threshold;
            self.min_sample_interval = v.waypoint_sample_secs;
            self.eps = if v.epsilon < MIN_EPSILON {
                MIN_EPSILON
            } else {
                v.epsilon
            };
            self.max_waypoints = if v.dbg_waypoint_limit_test {
                TEST_WAYPOINTS
            } else {
                WAYPOINTS
            };
        }

        // Record a waypoint when far enough and long enough since the
        // last one.
        let since_last = (now - self.last_waypoint_time) as f64 / 1e9;
        match self.state {
            State::Idle => self.next_waypoint = 0,
            State::MoveAway => {
                let last = self.last_waypoint();
                if !v.waypoint_limit
                    && since_last >= self.min_sample_interval
                    && (0..n).any(|r| (v.offset_current[r] - last[r]).abs() > self.move_threshold)
                {
                    let i = self.next_waypoint;
                    self.waypoints[i][..n].copy_from_slice(&v.offset_current[..n]);
                    self.last_waypoint_time = now;
                    self.next_waypoint += 1;
                    v.waypoint_limit = self.next_waypoint > self.max_waypoints - 1;
                }
            }
            State::MoveBack => {}
        }

        match self.state {
            State::Idle => {
                self.last_waypoint_time = now;
                if all_enables {
                    self.next_state = State::MoveAway;
                    self.move_in_progress = true;
                    self.goal[..n].copy_from_slice(&v.offset_in[..n]);
                }
            }
            State::MoveAway => {
                self.move_in_progress = true;
                if all_enables {
                    self.goal[..n].copy_from_slice(&v.offset_in[..n]);
                } else {
                    self.next_state = State::MoveBack;
                    if !v.power_on {
                        self.power_lost(v);
                    } else {
                        self.goal = [0.0; MAX_JOINTS];
                        if self.backtrack && self.next_waypoint > 0 {
                            self.goal = self.waypoints[self.next_waypoint - 1];
                            v.waypoint_limit = false;
                            self.next_waypoint -= 1;
                        }
                    }
                }
            }
            State::MoveBack => {
                if !v.power_on {
                    self.power_lost(v);
                } else {
                    self.move_in_progress = true;
                    if self.backtrack {
                        if self.next_waypoint > 0 {
                            let at_goal = (0..n)
                                .all(|r| (v.offset_current[r] - self.goal[r]).abs() <= self.eps);
                            if at_goal {
                                // LinuxCNC steps to the waypoint at the
                                // index just left (the same one once, and
                                // never the first).
                                self.goal = self.waypoints[self.next_waypoint];
                                self.next_waypoint -= 1;
                            }
                        } else {
                            self.goal = [0.0; MAX_JOINTS];
                        }
                    }
                    if !v.offset_applied {
                        self.next_state = State::Idle;
                        self.move_in_progress = false;
                        self.reset_limiters();
                    }
                }
            }
        }

        let mut print = false;
        if !v.apply_offsets && v.offset_applied {
            v.warning = true;
            print = !self.gave_msg;
            self.gave_msg = true;
        } else {
            self.gave_msg = false;
            v.warning = false;
        }
        print
    }

    /// Power went off: drop the offsets at once.
    fn power_lost(&mut self, v: &mut InputVars) {
        self.reset_limiters();
        self.move_in_progress = false;
        v.offset_applied = false;
        self.next_state = State::Idle;
    }

    /// `write-outputs`.
    pub fn write_outputs(&mut self, v: &mut OutputVars) {
        let n = self.joints;
        let dt = self.period as f64 * 1e-9;
        for r in 0..n {
            if self.move_in_progress {
                if !(v.waypoint_limit && self.state == State::MoveAway) {
                    let last_old = self.limiters[r].old_out;
                    let out = self.limiters[r].step(self.goal[r], &v.limits[r], dt);
                    v.offset_current[r] = out;
                    v.fb_minusoffset[r] = v.fb[r] - out - (last_old - out);
                    v.pos_plusoffset[r] = v.pos[r] + out;
                }
            } else {
                v.pos_plusoffset[r] = v.pos[r];
                v.offset_current[r] = 0.0;
                v.fb_minusoffset[r] = v.fb[r];
            }
        }
        v.offset_applied = self.limiters[..n]
            .iter()
            .any(|l| l.old_out.abs() > self.eps);
        if !v.offset_applied {
            self.next_waypoint = 0;
            v.waypoint_limit = false;
        }
        v.waypoint_ct = self.next_waypoint as i32;
        v.waypoint_percent_used = (100 * self.next_waypoint / self.max_waypoints) as i32;
        v.dbg_state = self.state as i32;
        self.state = self.next_state;
    }
}
