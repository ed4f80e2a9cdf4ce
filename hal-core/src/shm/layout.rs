//! `#[repr(C)]` layouts of everything stored in the segment.
//!
//! Every field is an atomic 64-bit word (or a run of them), so a process
//! reading while another writes never sees a torn value and never races in
//! Rust's sense. Links are offsets from the segment base, 0 meaning none.
//! Every record starts with a tag naming its kind and a `next` link: the
//! object list it is on while alive, the free list once freed.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use super::mutex::RobustMutex;

/// "HALSEGM1" as little-endian bytes.
pub(crate) const MAGIC: u64 = u64::from_le_bytes(*b"HALSEGM1");
/// Bumped whenever any layout in this file changes.
pub(crate) const LAYOUT_VERSION: u64 = 4;

/// A thread's switch bit (executor and [`ThreadRec`]'s `options`):
/// per-function timing is off.
pub(crate) const THREAD_NO_FUNCT_TIMING: u64 = 1;
/// A thread's switch bit: late cycles run back to back.
pub(crate) const THREAD_CATCH_UP: u64 = 2;
/// Entries of the undo journal.
pub(crate) const JOURNAL_CAP: usize = 65536;
/// Buckets of a thread's wake-up latency histogram (see [`latency_bucket`]).
pub(crate) const HIST_BUCKETS: usize = 64;

/// A name stored inline: byte 0 holds the length, bytes 1..=255 the text.
#[repr(C)]
pub(crate) struct Name([AtomicU64; 32]);

impl Name {
    pub(crate) fn bytes(&self) -> ([u8; 256], usize) {
        let mut buf = [0u8; 256];
        for (i, w) in self.0.iter().enumerate() {
            buf[i * 8..i * 8 + 8].copy_from_slice(&w.load(Relaxed).to_le_bytes());
        }
        let len = buf[0] as usize;
        (buf, len)
    }

    /// The stored name; invalid UTF-8 (a corrupted segment) is replaced.
    pub(crate) fn get(&self) -> String {
        let (buf, len) = self.bytes();
        String::from_utf8_lossy(&buf[1..1 + len]).into_owned()
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.0[0].load(Relaxed) & 0xff == 0
    }

    /// Whether the stored name equals `s`.
    #[cfg(test)]
    pub(crate) fn eq_str(&self, s: &str) -> bool {
        self.eq_key(&Name::encode(s))
    }

    /// Whether the stored name equals a name encoded with [`Name::encode`];
    /// stops at the first differing word (the first holds the length).
    pub(crate) fn eq_key(&self, key: &[u64; 32]) -> bool {
        let len = (key[0] & 0xff) as usize;
        let words = (len + 1).div_ceil(8);
        self.0[..words]
            .iter()
            .zip(key)
            .all(|(w, k)| w.load(Relaxed) == *k)
    }

    /// Byte-wise order of the stored name against an encoded key (as C's
    /// strcmp orders them).
    pub(crate) fn cmp_key(&self, key: &[u64; 32]) -> std::cmp::Ordering {
        for (i, (w, k)) in self.0.iter().zip(key).enumerate() {
            let (mut a, mut b) = (w.load(Relaxed).to_le_bytes(), k.to_le_bytes());
            if i == 0 {
                // Byte 0 is the length, not part of the text.
                a[0] = 0;
                b[0] = 0;
            }
            match a.cmp(&b) {
                std::cmp::Ordering::Equal => {}
                other => return other,
            }
            if a.contains(&0) && i > 0 {
                break;
            }
        }
        std::cmp::Ordering::Equal
    }

    /// Encodes `s` (at most 255 bytes, checked by the caller) into words.
    pub(crate) fn encode(s: &str) -> [u64; 32] {
        let mut buf = [0u8; 256];
        let n = s.len().min(255);
        buf[0] = n as u8;
        buf[1..1 + n].copy_from_slice(&s.as_bytes()[..n]);
        let mut words = [0u64; 32];
        for (i, w) in words.iter_mut().enumerate() {
            *w = u64::from_le_bytes(buf[i * 8..i * 8 + 8].try_into().unwrap_or([0; 8]));
        }
        words
    }

    /// Stores a name into a record nobody else can reach yet.
    pub(crate) fn init(&self, s: &str) {
        for (w, v) in self.0.iter().zip(Name::encode(s)) {
            w.store(v, Relaxed);
        }
    }

    pub(crate) fn words(&self) -> &[AtomicU64; 32] {
        &self.0
    }
}

/// The segment header, at offset 0.
#[repr(C)]
pub(crate) struct Header {
    pub magic: AtomicU64,
    pub version: AtomicU64,
    pub size: AtomicU64,
    pub host_pid: AtomicU64,
    pub mutex: RobustMutex,
    /// First free byte of the bump allocator.
    pub alloc_top: AtomicU64,
    /// Free list heads, one per [`super::BlockKind`].
    pub free: [AtomicU64; 16],
    pub comps: ObjList,
    pub pins: ObjList,
    pub params: ObjList,
    pub signals: ObjList,
    pub functs: ObjList,
    /// Newest (slowest) thread first; not indexed (there are few).
    pub threads: AtomicU64,
    pub regions: ObjList,
    /// Root of the tree of aliased pins by their original names.
    pub pin_aliases: AtomicU64,
    /// Root of the tree of aliased params by their original names.
    pub param_aliases: AtomicU64,
    pub next_comp_id: AtomicU64,
    pub next_funct_id: AtomicU64,
    /// Period of the first thread ever created; 0 before.
    pub base_period: AtomicU64,
    /// Bumped by every committed structural change.
    pub generation: AtomicU64,
    /// Grace-period epoch: bumped whenever something is retired that a
    /// running thread might still touch.
    pub grace_epoch: AtomicU64,
    /// Value cells waiting for every thread to pass a cycle boundary.
    pub limbo: AtomicU64,
    pub journal_len: AtomicU64,
    pub journal_off: AtomicU64,
    /// Non-zero once a realtime function panicked; holds the funct record.
    pub fault_funct: AtomicU64,
    /// Set by `setexact_for_test_suite_only`-style callers; informational.
    pub exact_base_period: AtomicU64,
    /// halcmd's `lock` level: LinuxCNC's `HAL_LOCK_*` bits (see
    /// `objects::status`).
    pub lock_level: AtomicU64,
    /// The block pairs are being carved from, and how many it has given.
    pub pair_block: AtomicU64,
    pub pair_used: AtomicU64,
    /// Freed pairs of pins and of params (linked through their first word).
    pub free_pin_pairs: AtomicU64,
    pub free_param_pairs: AtomicU64,
    pub reserved: [AtomicU64; 15],
}

/// The head of a name-sorted object list and the root of the search tree
/// over it (see `objects::index`). Dereferences to the list's first link,
/// which is all a walk needs.
#[repr(C)]
pub(crate) struct ObjList {
    pub first: AtomicU64,
    pub root: AtomicU64,
}

impl std::ops::Deref for ObjList {
    type Target = AtomicU64;

    fn deref(&self) -> &AtomicU64 {
        &self.first
    }
}

pub(crate) trait Record {
    const TAG: u64;
}

macro_rules! record {
    ($(#[$m:meta])* $name:ident, $tag:expr, { $($(#[$fm:meta])* $field:ident : $ty:ty),* $(,)? }) => {
        $(#[$m])*
        #[repr(C)]
        pub(crate) struct $name {
            pub tag: AtomicU64,
            pub next: AtomicU64,
            $($(#[$fm])* pub $field: $ty),*
        }
        impl Record for $name {
            const TAG: u64 = $tag;
        }
    };
}

record!(
    /// A HAL component.
    CompRec, 0x434f_4d50, {
    /// Tree links of the name index.
    left: AtomicU64,
    right: AtomicU64,
    name: Name,
    id: AtomicU64,
    /// [`crate::ComponentKind`] code.
    kind: AtomicU64,
    ready: AtomicU64,
    pid: AtomicU64,
    /// Blob holding the `loadrt` arguments, 0 if none.
    args: AtomicU64,
    /// The objects it owns, each kind on a list through their
    /// `owner_next` (newest first), so that removing a component visits
    /// only its own objects.
    own_pins: AtomicU64,
    own_params: AtomicU64,
    own_functs: AtomicU64,
    own_regions: AtomicU64,
});

record!(
    /// A pin. Its slot holds the offset of the value cell in use: its own
    /// cell (the word after the slot) while unlinked, the signal's cell
    /// once linked. Both live in a [`Pair`].
    /// offset while unlinked, the signal's cell once linked.
    PinRec, 0x5049_4e00, {
    /// Tree links of the name index.
    left: AtomicU64,
    right: AtomicU64,
    name: Name,
    /// The name before `alias`, empty when the pin has no alias.
    orig_name: Name,
    /// Tree links of the alias index (by `orig_name`), while aliased.
    alias_left: AtomicU64,
    alias_right: AtomicU64,
    type_code: AtomicU64,
    dir: AtomicU64,
    owner: AtomicU64,
    /// Next on the owner's list of pins.
    owner_next: AtomicU64,
    signal: AtomicU64,
    /// Neighbours on the signal's list of pins while linked.
    sig_prev: AtomicU64,
    sig_next: AtomicU64,
    /// The [`Pair`] holding the slot and the pin's own cell.
    hot: AtomicU64,
});

record!(
    /// A parameter; its value lives inline.
    ParamRec, 0x5041_5241, {
    /// Tree links of the name index.
    left: AtomicU64,
    right: AtomicU64,
    name: Name,
    orig_name: Name,
    alias_left: AtomicU64,
    alias_right: AtomicU64,
    type_code: AtomicU64,
    dir: AtomicU64,
    owner: AtomicU64,
    /// Next on the owner's list of params.
    owner_next: AtomicU64,
    /// The [`Pair`] whose first word is the value.
    hot: AtomicU64,
});

record!(
    /// A signal; its value lives in a separate cell so that a freed cell is
    /// only ever reused as a cell.
    SigRec, 0x5349_4700, {
    /// Tree links of the name index.
    left: AtomicU64,
    right: AtomicU64,
    name: Name,
    type_code: AtomicU64,
    cell: AtomicU64,
    writers: AtomicU64,
    bidirs: AtomicU64,
    readers: AtomicU64,
    /// The pins linked to it, through their `sig_prev`/`sig_next` (in no
    /// particular order).
    first_pin: AtomicU64,
});

record!(
    /// A signal's value cell. `epoch` is the grace epoch at which it was
    /// retired while in limbo.
    CellRec, 0x4345_4c4c, {
    epoch: AtomicU64,
    value: AtomicU64,
});

record!(
    /// A function's metadata; its code lives in the host's private table.
    FunctRec, 0x4655_4e43, {
    /// Tree links of the name index.
    left: AtomicU64,
    right: AtomicU64,
    name: Name,
    owner: AtomicU64,
    /// Next on the owner's list of functions.
    owner_next: AtomicU64,
    code_id: AtomicU64,
    uses_fp: AtomicU64,
    reentrant: AtomicU64,
    users: AtomicU64,
    time_pin: AtomicU64,
    tmax_param: AtomicU64,
    tmax_inc_param: AtomicU64,
});

record!(
    /// One function in a thread's list.
    EntryRec, 0x454e_5452, {
    funct: AtomicU64,
});

record!(
    /// A thread, with its function list, timing and latency statistics.
    ThreadRec, 0x5448_5244, {
    name: Name,
    owner: AtomicU64,
    period: AtomicU64,
    priority: AtomicU64,
    uses_fp: AtomicU64,
    /// CPU to pin to plus one; 0 for the default placement.
    cpu: AtomicU64,
    /// The executor's switch bits (function timing off, catch-up), as the
    /// host last set them; for `show thread` and `save` in other processes.
    options: AtomicU64,
    functs: AtomicU64,
    /// The last entry of `functs` (0 when empty), where `addf` appends.
    functs_last: AtomicU64,
    /// Functions run once, on the first cycle after start (`initf`).
    init_functs: AtomicU64,
    time_pin: AtomicU64,
    tmax_param: AtomicU64,
    beat_pin: AtomicU64,
    /// Non-zero while the executor runs the function list.
    running: AtomicU64,
    /// Grace epoch the executor saw at its last cycle boundary; `u64::MAX`
    /// while it holds no references (parked or gone).
    seen_epoch: AtomicU64,
    overruns: AtomicU64,
    cycles: AtomicU64,
    lat_min_ns: AtomicU64,
    lat_max_ns: AtomicU64,
    hist: [AtomicU64; HIST_BUCKETS],
});

record!(
    /// A named memory region allocated by a component.
    RegionRec, 0x5245_4749, {
    /// Tree links of the name index.
    left: AtomicU64,
    right: AtomicU64,
    name: Name,
    owner: AtomicU64,
    /// Next on the owner's list of regions.
    owner_next: AtomicU64,
    blob: AtomicU64,
    size: AtomicU64,
});

record!(
    /// A variable-sized block; `capacity` bytes of data follow the record.
    BlobRec, 0x424c_4f42, {
    capacity: AtomicU64,
    len: AtomicU64,
});

/// The words realtime code reaches through a pin or param handle: a pin's
/// slot and own cell, a param's value (and a spare word). Pairs are packed
/// four to a 64-byte block in the order they are made, so the words one
/// component's function reaches share a few cache lines instead of taking
/// one line of a 640-byte record each. 16-byte aligned; not a record (no
/// tag): only a record's `hot` offset leads to one.
#[repr(C)]
pub(crate) struct Pair {
    pub first: AtomicU64,
    pub second: AtomicU64,
}

impl PinRec {
    /// The pin's slot (`first`) and own cell (`second`).
    pub(crate) fn words<'a>(&self, seg: &'a super::Segment) -> crate::Result<&'a Pair> {
        seg.pair(self.hot.load(Relaxed))
    }
}

impl ParamRec {
    /// The param's value word (`first`).
    pub(crate) fn words<'a>(&self, seg: &'a super::Segment) -> crate::Result<&'a Pair> {
        seg.pair(self.hot.load(Relaxed))
    }
}

/// Which free list a freed pair returns to: a pin's pair is only reused by
/// a pin (its own cell stays a value cell), a param's by a param.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PairPool {
    Pin,
    Param,
}

/// Bucket of a wake-up latency: 0..=15 are 1 us wide (0-16 us), then
/// 16..=63 grow by 2^(1/4) steps up to about 64 ms; the last takes the rest.
pub fn latency_bucket(ns: u64) -> usize {
    let us = ns / 1000;
    if us < 16 {
        return us as usize;
    }
    let log2 = 63 - us.leading_zeros() as u64; // >= 4
    let frac = (us >> (log2 - 2)) & 3; // two bits of mantissa
    let b = 16 + (log2 - 4) * 4 + frac;
    (b as usize).min(HIST_BUCKETS - 1)
}

/// Lower edge in microseconds of a latency bucket.
pub fn latency_bucket_floor_us(bucket: usize) -> u64 {
    if bucket < 16 {
        return bucket as u64;
    }
    let b = (bucket - 16) as u64;
    let log2 = 4 + b / 4;
    let frac = b % 4;
    (1u64 << log2) + (frac << (log2 - 2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        let n = Name([const { AtomicU64::new(0) }; 32]);
        n.init("joint.0.motor-pos-cmd");
        assert_eq!(n.get(), "joint.0.motor-pos-cmd");
        assert!(n.eq_str("joint.0.motor-pos-cmd"));
        assert!(!n.eq_str("joint.0.motor-pos"));
        let long = "x".repeat(255);
        n.init(&long);
        assert_eq!(n.get(), long);
    }

    #[test]
    fn latency_buckets_are_monotonic() {
        let mut last = 0;
        for us in 0..100_000u64 {
            let b = latency_bucket(us * 1000);
            assert!(b >= last && b < HIST_BUCKETS);
            assert!(latency_bucket_floor_us(b) <= us || b == HIST_BUCKETS - 1);
            last = b;
        }
        assert_eq!(latency_bucket(15_999), 15);
        assert_eq!(latency_bucket(16_000), 16);
    }
}
