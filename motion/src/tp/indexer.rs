//! Locking indexers (`[AXIS_L]LOCKING_INDEXER_JOINT`): a rapid that
//! moves such an axis is queued as a segment that carries the indexer's
//! joint. It is never blended into or out of. Before it moves the planner
//! raises the joint's unlock request and waits, at rest, for
//! `joint.N.is-unlocked`; it then moves; at its end the request drops and
//! the planner waits, at rest, for is-unlocked to fall before the next
//! segment starts. While any of this runs `motion.motion-type` reads 6
//! (LinuxCNC's "rotary unlock for traverse"). An abort brakes the move to
//! rest first; clearing the queue then drops the request without waiting
//! for the lock (nothing is queued to wait for it).
//!
//! LinuxCNC waits for the indexer without a limit. Here each wait gives up
//! after [`INDEXER_TIMEOUT`] seconds: the planner reports the joint and
//! which wait failed, and aborts the queue (an indexer that never answers
//! would otherwise hang the program with no message).

use super::Planner;

/// Seconds the planner waits for a locking indexer to report itself
/// unlocked, or locked again, before it gives up (a choice of this
/// suite: LinuxCNC waits without a limit; ten seconds leaves a slow
/// hydraulic or pneumatic clamp time, yet faults well before an operator
/// would wonder).
pub const INDEXER_TIMEOUT: f64 = 10.0;

/// Where a locking indexer's move stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IndexerPhase {
    /// `unlock` raised; waiting at rest for `is-unlocked`.
    Unlocking,
    /// Unlocked: the segment moves.
    Moving,
    /// The move ended and `unlock` dropped; waiting at rest for
    /// `is-unlocked` to fall.
    Locking,
}

/// The indexer handshake in progress.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct IndexerRun {
    /// The joint.
    pub joint: usize,
    pub phase: IndexerPhase,
    /// Seconds waited in this phase.
    pub waited: f64,
}

/// A wait that ran out (see [`INDEXER_TIMEOUT`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IndexerFault {
    /// The joint.
    pub joint: usize,
    /// True if it did not unlock, false if it did not lock again.
    pub unlocking: bool,
}

/// Whether bit `joint` of `mask` is set.
fn bit(mask: u32, joint: usize) -> bool {
    joint < 32 && mask & (1 << joint) != 0
}

impl Planner {
    /// The next segment pushed is a locking indexer's move of `joint`.
    pub fn set_indexer_pending(&mut self, joint: Option<usize>) {
        self.indexer_pending = joint;
    }

    /// The joint whose `unlock` the planner asks for now, if any.
    pub fn indexer_unlock(&self) -> Option<usize> {
        self.indexer
            .filter(|r| r.phase != IndexerPhase::Locking)
            .map(|r| r.joint)
    }

    /// The indexer handshake's phase, if one runs.
    pub fn indexer_phase(&self) -> Option<IndexerPhase> {
        self.indexer.map(|r| r.phase)
    }

    /// A wait that ran out since the last call (the queue is aborting).
    pub fn take_indexer_fault(&mut self) -> Option<IndexerFault> {
        self.indexer_fault.take()
    }

    /// The handshake's part of one period, given the joints' is-unlocked
    /// bits (`unlocked`, bit n: joint n). True while the planner waits at
    /// rest (nothing else runs this period).
    pub(super) fn indexer_step(&mut self, unlocked: u32) -> bool {
        if self.indexer.is_none() {
            let starting = self.s == 0.0 && self.v == 0.0;
            match self.queue.front().and_then(|h| h.indexer) {
                Some(joint) if starting => {
                    self.indexer = Some(IndexerRun {
                        joint: usize::from(joint),
                        phase: IndexerPhase::Unlocking,
                        waited: 0.0,
                    });
                }
                _ => return false,
            }
        }
        let Some(mut run) = self.indexer else {
            return false;
        };
        let waiting = match run.phase {
            IndexerPhase::Moving => return false,
            IndexerPhase::Unlocking => !bit(unlocked, run.joint),
            IndexerPhase::Locking => bit(unlocked, run.joint),
        };
        if !waiting {
            self.indexer = match run.phase {
                IndexerPhase::Unlocking => Some(IndexerRun {
                    phase: IndexerPhase::Moving,
                    ..run
                }),
                _ => None,
            };
            // Unlocked: the move starts this period. Locked: the next
            // segment may start this period.
            return false;
        }
        self.v = 0.0;
        self.a = 0.0;
        run.waited += self.period;
        if run.waited > INDEXER_TIMEOUT {
            self.indexer = None;
            self.indexer_fault = Some(IndexerFault {
                joint: run.joint,
                unlocking: run.phase == IndexerPhase::Unlocking,
            });
            self.abort();
        } else {
            self.indexer = Some(run);
        }
        true
    }

    /// The segment `done` just ended: an indexer's move relocks.
    pub(super) fn indexer_segment_done(&mut self, done_indexer: Option<u8>) {
        if let (Some(_), Some(run)) = (done_indexer, self.indexer.as_mut()) {
            run.phase = IndexerPhase::Locking;
            run.waited = 0.0;
        }
    }
}
