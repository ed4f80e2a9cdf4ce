//! Digital and analog outputs set in step with the queued motion (M62,
//! M63, M67): a set asked for is held pending until the next segment is
//! queued, travels with it, and is written when that segment starts
//! (reference "SET_DOUT / SET_AOUT"). The outputs themselves
//! (`motion.digital-out-NN`, `motion.analog-out-NN`) live here too, so
//! immediate writes (M64, M65, M68) and synchronised ones meet in one
//! place. Everything is allocated when the planner is built.

use std::collections::VecDeque;

use crate::sizes::MAX_IO;

/// How many segments carrying output changes may be queued at once.
pub const SYNC_SETS: usize = 256;

/// The values of the synchronised outputs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IoOutputs {
    /// `motion.digital-out-NN`.
    pub dout: [bool; MAX_IO],
    /// `motion.analog-out-NN`.
    pub aout: [f64; MAX_IO],
}

impl Default for IoOutputs {
    fn default() -> Self {
        IoOutputs {
            dout: [false; MAX_IO],
            aout: [0.0; MAX_IO],
        }
    }
}

/// Output changes waiting for a segment: one value per output at most
/// (a later one replaces an earlier one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyncSet {
    dout_mask: u64,
    dout: u64,
    aout_mask: u64,
    aout: [f64; MAX_IO],
}

impl Default for SyncSet {
    fn default() -> Self {
        SyncSet {
            dout_mask: 0,
            dout: 0,
            aout_mask: 0,
            aout: [0.0; MAX_IO],
        }
    }
}

impl SyncSet {
    /// Whether it changes nothing.
    pub fn is_empty(&self) -> bool {
        self.dout_mask == 0 && self.aout_mask == 0
    }

    /// Digital output `index` (below [`MAX_IO`]) to `on`.
    pub fn set_dout(&mut self, index: usize, on: bool) {
        let bit = 1u64 << index;
        self.dout_mask |= bit;
        if on {
            self.dout |= bit;
        } else {
            self.dout &= !bit;
        }
    }

    /// Analog output `index` (below [`MAX_IO`]) to `value`.
    pub fn set_aout(&mut self, index: usize, value: f64) {
        self.aout_mask |= 1u64 << index;
        self.aout[index] = value;
    }

    /// Writes the changes into `out`.
    pub fn apply(&self, out: &mut IoOutputs) {
        for i in 0..MAX_IO {
            let bit = 1u64 << i;
            if self.dout_mask & bit != 0 {
                out.dout[i] = self.dout & bit != 0;
            }
            if self.aout_mask & bit != 0 {
                out.aout[i] = self.aout[i];
            }
        }
    }
}

/// The pending set, the sets travelling with queued segments (in queue
/// order), and the outputs.
#[derive(Debug)]
pub(crate) struct SyncIo {
    pub pending: SyncSet,
    queued: VecDeque<SyncSet>,
    pub outputs: IoOutputs,
}

impl Default for SyncIo {
    fn default() -> Self {
        SyncIo {
            pending: SyncSet::default(),
            queued: VecDeque::with_capacity(SYNC_SETS),
            outputs: IoOutputs::default(),
        }
    }
}

impl SyncIo {
    /// Whether a segment queued now could take the pending set.
    pub fn has_room(&self) -> bool {
        self.pending.is_empty() || self.queued.len() < SYNC_SETS
    }

    /// Hands the pending set to a segment being queued; true if there
    /// was one (the segment then carries it).
    pub fn attach(&mut self) -> bool {
        if self.pending.is_empty() || self.queued.len() >= SYNC_SETS {
            return false;
        }
        self.queued.push_back(self.pending);
        self.pending = SyncSet::default();
        true
    }

    /// A segment carrying a set starts: its changes are written.
    pub fn fire(&mut self) {
        if let Some(set) = self.queued.pop_front() {
            set.apply(&mut self.outputs);
        }
    }

    /// Forgets every change not yet written (abort, disable).
    pub fn clear(&mut self) {
        self.pending = SyncSet::default();
        self.queued.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_set_travels_with_its_segment_and_the_last_value_wins() {
        let mut s = SyncIo::default();
        assert!(!s.attach(), "nothing pending");
        s.pending.set_dout(3, true);
        s.pending.set_dout(3, false);
        s.pending.set_dout(63, true);
        s.pending.set_aout(1, 2.5);
        assert!(s.attach());
        assert!(s.pending.is_empty());
        assert_eq!(s.outputs, IoOutputs::default(), "not before it starts");
        s.fire();
        assert!(!s.outputs.dout[3] && s.outputs.dout[63]);
        assert_eq!(s.outputs.aout[1], 2.5);
        s.pending.set_dout(0, true);
        s.clear();
        assert!(!s.attach());
    }
}
