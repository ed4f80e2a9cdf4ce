//! What homing does to a joint: the narrow set of operations the homing
//! state machine uses on the joint's planner and positions.

use crate::joint::Joint;

/// How far a search move goes when the soft limits give no usable travel.
const LONG_MOVE: f64 = 1e12;

impl Joint {
    /// Starts a search move in the direction of `vel` at speed `|vel|`
    /// (at most the joint's velocity limit). The target is two full
    /// travels away: the move is meant to end with a switch or index
    /// event long before it gets there.
    pub(crate) fn home_move(&mut self, vel: f64) {
        let range = self.cfg.max_pos_limit - self.cfg.min_pos_limit;
        let reach = if range.is_finite() && range > 0.0 && (2.0 * range).is_finite() {
            2.0 * range
        } else {
            LONG_MOVE
        };
        self.free_tp.pos_cmd = if vel > 0.0 {
            self.pos_cmd + reach
        } else {
            self.pos_cmd - reach
        };
        self.free_tp.max_vel = vel.abs().min(self.cfg.vel_limit);
        self.free_tp.enable = true;
    }

    /// Starts the move to `target` at `vel` (> 0; at most the velocity
    /// limit), or at the velocity limit when `vel` ≤ 0.
    pub(crate) fn home_move_to(&mut self, target: f64, vel: f64) {
        self.free_tp.pos_cmd = target;
        self.free_tp.max_vel = if vel > 0.0 {
            vel.min(self.cfg.vel_limit)
        } else {
            self.cfg.vel_limit
        };
        self.free_tp.enable = true;
    }

    /// Brakes the planner to a stop at the acceleration limit.
    pub(crate) fn home_stop(&mut self) {
        self.free_tp.enable = false;
    }

    /// Ends any jog of the joint: a stop at the acceleration limit, or at
    /// once (velocity zeroed) when `immediate`.
    pub(crate) fn end_jogs(&mut self, immediate: bool) {
        if immediate {
            self.free_tp.stop_immediately();
        } else {
            self.free_tp.enable = false;
        }
        self.kb_jog_active = false;
        self.wheel_jog_active = false;
    }

    /// Puts the free planner at rest at `pos` and ends any jog.
    pub(crate) fn rest_planner_at(&mut self, pos: f64) {
        self.free_tp.set_at_rest(pos);
        self.kb_jog_active = false;
        self.wheel_jog_active = false;
    }

    /// Declares the present feedback position to be `x` without moving
    /// the motor: command, feedback and planner shift together and the
    /// motor offset takes the difference, so the motor command does not
    /// change.
    pub(crate) fn set_home_position(&mut self, x: f64) {
        let offset = x - self.pos_fb;
        self.pos_cmd += offset;
        self.coarse_pos += offset;
        self.pos_fb += offset;
        self.free_tp.curr_pos += offset;
        self.free_tp.pos_cmd += offset;
        self.motor_offset -= offset;
    }

    /// After the encoder zeroed its count at the index: the index is
    /// joint position `home_offset`, and the command restarts at the
    /// feedback.
    pub(crate) fn set_index_position(&mut self, home_offset: f64) {
        self.motor_offset = -home_offset;
        self.pos_fb = self.motor_pos_fb - (self.backlash_filt + self.motor_offset);
        self.pos_cmd = self.pos_fb;
        self.coarse_pos = self.pos_fb;
        self.free_tp.curr_pos = self.pos_fb;
        self.free_tp.pos_cmd = self.pos_fb;
    }

    /// Whether a limit switch is tripped.
    pub(crate) fn on_limit(&self) -> bool {
        self.phl || self.nhl
    }
}
