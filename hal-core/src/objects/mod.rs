//! The HAL objects and the operations on them. [`Instance`] is a process's
//! view of one HAL instance; every operation here works directly on the
//! shared segment under the structural lock, so any process can do it.

pub(crate) mod alias;
mod component;
pub(crate) mod funct;
pub(crate) mod index;
mod info;
pub(crate) mod list;
mod liveness;
mod owner;
mod param;
mod pin;
mod region;
mod signal;
mod status;
mod value_set;

use std::sync::atomic::Ordering::*;
use std::sync::Arc;

pub use alias::AliasKind;
pub use component::{Component, ComponentKind};
pub use info::*;
pub(crate) use liveness::HostLock;
pub use region::Region;
pub use status::{lock_bits, HalStatistics};
pub use value_set::{ValueKind, ValueSet};

use crate::error::{HalError, Result};
use crate::shm::{Segment, Txn};

/// A process's handle on a HAL instance. Cheap to clone.
#[derive(Clone)]
pub struct Instance {
    pub(crate) seg: Arc<Segment>,
}

impl Instance {
    /// Attaches to the running instance `name`, or fails with
    /// [`HalError::NotRunning`] if no live host serves it.
    pub fn attach(name: &str) -> Result<Instance> {
        validate_instance_name(name)?;
        if !liveness::host_alive(name)? {
            // A user outside the hal group may not see the lock of a
            // running host at all; its segment tells them why.
            crate::paths::segment_access(name)?;
            return Err(HalError::NotRunning {
                instance: name.to_string(),
            });
        }
        Ok(Instance {
            seg: Arc::new(Segment::attach(name)?),
        })
    }

    /// Attaches to the instance named by `HAL_INSTANCE`, or `default`.
    pub fn attach_default() -> Result<Instance> {
        Instance::attach(&instance_from_env())
    }

    /// The instance name.
    pub fn name(&self) -> &str {
        self.seg.instance()
    }

    /// A counter bumped by every committed structural change; tools use it to
    /// know when to refresh what they display.
    pub fn generation(&self) -> u64 {
        self.seg.header().generation.load(Acquire)
    }

    /// Size of the shared segment in bytes.
    pub fn segment_size(&self) -> u64 {
        self.seg.size()
    }

    /// Bytes of the segment in use by objects (the allocator's high-water mark).
    pub fn segment_used(&self) -> u64 {
        self.seg.header().alloc_top.load(Relaxed)
    }

    /// Period of the first thread created in the instance (0 before any).
    pub fn base_period(&self) -> i64 {
        self.seg.header().base_period.load(Relaxed) as i64
    }

    /// Whether the host is alive (its lock is held).
    pub fn host_alive(&self) -> bool {
        liveness::host_alive(self.name()).unwrap_or(false)
    }

    pub(crate) fn tx<T>(&self, f: impl FnOnce(&mut Txn<'_>) -> Result<T>) -> Result<T> {
        self.seg.transaction(f)
    }
}

/// The instance name from `HAL_INSTANCE`, or `default`.
pub fn instance_from_env() -> String {
    std::env::var("HAL_INSTANCE")
        .ok()
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "default".to_string())
}

/// Instance names become file names, so they are restricted further than
/// other names: letters, digits, `-`, `_` and `.`, not starting with `.`.
pub fn validate_instance_name(name: &str) -> Result<()> {
    let ok = !name.is_empty()
        && name.len() <= 100
        && !name.starts_with('.')
        && name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_' || b == b'.');
    if ok {
        Ok(())
    } else {
        Err(HalError::BadName {
            kind: "instance",
            name: name.to_string(),
            reason: "use 1-100 letters, digits, '-', '_' or '.', not starting with '.'",
        })
    }
}

impl Instance {
    /// Test support: starts a structural change (a half-created signal
    /// `name` on the list, a component id taken), then stalls for `stall`
    /// while holding the lock, then fails. Killing the process during the
    /// stall is how tests show that a dead lock holder's change is rolled
    /// back and the instance is not wedged.
    #[doc(hidden)]
    pub fn debug_stall_mid_change(&self, name: &str, stall: std::time::Duration) -> Result<()> {
        use crate::shm::{BlockKind, SigRec};
        self.tx(|tx| {
            let h = tx.header();
            tx.set(&h.next_comp_id, h.next_comp_id.load(Relaxed) + 1)?;
            let (off, rec) = tx.alloc::<SigRec>(BlockKind::Signal)?;
            rec.name.init(name);
            list::insert_sorted(tx, &h.signals, off, rec)?;
            std::thread::sleep(stall);
            Err(HalError::BadValue {
                what: "debug_stall_mid_change".into(),
                reason: "stalled change abandoned".into(),
            })
        })
    }
}
