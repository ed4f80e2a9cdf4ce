//! The HAL lock (halcmd's `lock`/`unlock`) and the counts `status mem`
//! prints.
//!
//! The lock level lives in the segment header, so a lock set by one
//! process holds for every other. Each operation checks the bit that
//! covers it, as LinuxCNC's HAL library does: loading components
//! ([`lock_bits::LOAD`]), changing links, signals, aliases and thread
//! function lists ([`lock_bits::CONFIG`]), setting parameters
//! ([`lock_bits::PARAMS`]), starting and stopping threads
//! ([`lock_bits::RUN`]). Unloading is never locked, so a locked instance
//! can still be shut down.

use std::sync::atomic::Ordering::*;

use super::Instance;
use crate::error::{HalError, Result};
use crate::shm::BlockKind;

/// LinuxCNC's `HAL_LOCK_*` values.
pub mod lock_bits {
    /// Nothing is locked.
    pub const NONE: u8 = 0;
    /// Loading new components (`loadrt`, `loadusr`, new pins and params).
    pub const LOAD: u8 = 1;
    /// Links, signals, aliases and `addf`/`delf`.
    pub const CONFIG: u8 = 2;
    /// Setting parameters.
    pub const PARAMS: u8 = 4;
    /// Starting and stopping threads.
    pub const RUN: u8 = 8;
    /// halcmd's `lock tune`: loading and configuration locked, tuning
    /// (parameters) still allowed.
    pub const TUNE: u8 = LOAD | CONFIG;
    /// Everything.
    pub const ALL: u8 = 0xff;
}

/// Object counts of an instance: live, and blocks on the free lists
/// waiting for reuse.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HalStatistics {
    /// Bytes of the segment in use.
    pub used: u64,
    /// Size of the segment.
    pub total: u64,
    /// Live and recycled components.
    pub comps: (usize, usize),
    /// Live and recycled pins.
    pub pins: (usize, usize),
    /// Live and recycled parameters.
    pub params: (usize, usize),
    /// Pins and parameters with an alias; aliases are stored in place, so
    /// none is ever recycled.
    pub aliases: (usize, usize),
    /// Live and recycled signals.
    pub signals: (usize, usize),
    /// Live and recycled functions.
    pub functs: (usize, usize),
    /// Live and recycled threads.
    pub threads: (usize, usize),
}

impl Instance {
    /// The current lock level ([`lock_bits`]).
    pub fn lock_level(&self) -> u8 {
        (self.seg.header().lock_level.load(Acquire) & 0xff) as u8
    }

    /// Sets the lock level ([`lock_bits`]).
    pub fn set_lock_level(&self, level: u8) {
        self.seg
            .header()
            .lock_level
            .store(u64::from(level), Release);
    }

    /// Refuses `op` with [`HalError::Locked`] if any of `bits` is locked.
    pub fn check_unlocked(&self, bits: u8, op: &'static str) -> Result<()> {
        if self.lock_level() & bits != 0 {
            Err(HalError::Locked { op })
        } else {
            Ok(())
        }
    }

    /// Object counts for `status mem`.
    pub fn statistics(&self) -> Result<HalStatistics> {
        let pins = self.pins()?;
        let params = self.params()?;
        let aliases = pins.iter().filter(|p| p.orig_name.is_some()).count()
            + params.iter().filter(|p| p.orig_name.is_some()).count();
        Ok(HalStatistics {
            used: self.segment_used(),
            total: self.segment_size(),
            comps: (self.components()?.len(), self.free_blocks(BlockKind::Comp)),
            pins: (pins.len(), self.free_blocks(BlockKind::Pin)),
            params: (params.len(), self.free_blocks(BlockKind::Param)),
            aliases: (aliases, 0),
            signals: (self.signals()?.len(), self.free_blocks(BlockKind::Signal)),
            functs: (self.functs()?.len(), self.free_blocks(BlockKind::Funct)),
            threads: (self.threads()?.len(), self.free_blocks(BlockKind::Thread)),
        })
    }

    /// Blocks on the free list of `kind` (stops at a bad link).
    fn free_blocks(&self, kind: BlockKind) -> usize {
        let seg = &self.seg;
        let mut n = 0;
        let mut cur = seg.header().free[kind as usize].load(Acquire);
        let mut budget = seg.size() / 64 + 1;
        while cur != 0 && budget > 0 {
            budget -= 1;
            n += 1;
            cur = match seg.word(cur.saturating_add(8)) {
                Ok(w) => w.load(Acquire),
                Err(_) => break,
            };
        }
        n
    }
}
