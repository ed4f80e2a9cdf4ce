//! Coordinated mode: the queued trajectory planner ([`crate::tp`]) makes
//! the commanded pose every servo period; the inverse kinematics turn it
//! into joint commands (as in teleop mode, without LinuxCNC's cubic
//! interpolator: the planner's output is already limited). In position
//! means: nothing queued and at rest. A homed joint commanded beyond its
//! soft limits stops the queued motion along its path (LinuxCNC only
//! reports it, reference §4.4 "→ Design").

use super::*;
use crate::tp::ScaleInputs;

impl MotionCore {
    /// The scale inputs of this cycle.
    fn scale_inputs(&self) -> ScaleInputs {
        ScaleInputs {
            feed: self.feed_scale,
            rapid: self.rapid_scale,
            adaptive: self.inputs.adaptive_feed,
            feed_hold: self.inputs.feed_hold,
            feed_inhibit: self.inputs.feed_inhibit,
            max_feed_override: self.max_feed_override,
            spindle_at_speed: self.spindles_at_speed(),
            spindle_rps: self.inputs.spindle_speed_in,
            unlocked: self.unlocked_mask(),
            spindle_revs: self.inputs.spindle_revs,
            spindle_index_enable: (0..self.cfg.num_spindles)
                .filter(|&n| self.inputs.spindle_index_enable[n])
                .fold(0, |m, n| m | 1 << n),
            spindle_reverse: self.spindles_reversed(),
        }
    }

    /// COORD position commands.
    pub(super) fn coord_pos_cmds(&mut self, period: f64) {
        self.abort_axis_jogs(true);
        let scales = self.scale_inputs();
        let planned = self.tp.run(&scales);
        if let Some((n, factor)) = self.tp.take_spindle_reversal() {
            // A rigid tap reverses its spindle (and restores it).
            if let Some(s) = self.spindles.get_mut(n) {
                s.speed *= factor;
            }
        }
        self.report_indexer_fault();
        self.carte_pos_cmd = self.add_eoffsets(period, &planned);
        self.net_feed_scale = self.tp.status().net_scale;
        self.carte_pos_cmd_ok = true;
        self.joints_from_world(period);
        self.inpos = self.tp.is_done();
    }

    /// The soft-limit stop: on the cycle a homed joint's command leaves its
    /// soft limits in coordinated mode, the queued motion is aborted.
    pub(super) fn coord_soft_limit_stop(&mut self, was_on_limit: bool) {
        if self.state == MotionState::Coord && self.on_soft_limit && !was_on_limit {
            self.tp.abort();
        }
    }
}
