//! Coordinated mode.
//!
//! Coordinated mode: there is no queued trajectory planner yet (SET_LINE,
//! SET_CIRCLE, PROBE and friends come with it), so coordinated mode holds
//! the pose it was entered with, as LinuxCNC does with an empty queue, and
//! runs the inverse kinematics every cycle; it is always in position.

use super::*;

impl MotionCore {
    /// COORD position commands: the pose is held (no queued planner yet).
    pub(super) fn coord_pos_cmds(&mut self, period: f64) {
        self.abort_axis_jogs(true);
        self.carte_pos_cmd_ok = true;
        self.joints_from_world(period);
        self.inpos = true;
    }
}
