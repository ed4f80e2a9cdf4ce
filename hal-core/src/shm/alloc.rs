//! Block kinds of the segment allocator. Each fixed-size kind has its own
//! free list, so a freed block is only ever reused as the same kind of
//! record (a value cell stays a value cell).

use std::mem::size_of;

use super::layout::*;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(usize)]
pub(crate) enum BlockKind {
    Comp = 0,
    Pin = 1,
    Param = 2,
    Signal = 3,
    Cell = 4,
    Funct = 5,
    Entry = 6,
    Thread = 7,
    Region = 8,
    Blob = 9,
    /// 64-byte blocks carved into four [`Pair`]s.
    Pairs = 10,
}

impl BlockKind {
    /// Block size of fixed kinds; `None` for blobs.
    pub(crate) fn size(self) -> Option<u64> {
        let s = match self {
            BlockKind::Comp => size_of::<CompRec>(),
            BlockKind::Pin => size_of::<PinRec>(),
            BlockKind::Param => size_of::<ParamRec>(),
            BlockKind::Signal => size_of::<SigRec>(),
            BlockKind::Cell => size_of::<CellRec>(),
            BlockKind::Funct => size_of::<FunctRec>(),
            BlockKind::Entry => size_of::<EntryRec>(),
            BlockKind::Thread => size_of::<ThreadRec>(),
            BlockKind::Region => size_of::<RegionRec>(),
            BlockKind::Blob => return None,
            BlockKind::Pairs => 4 * size_of::<Pair>(),
        };
        Some((s as u64).next_multiple_of(64))
    }
}
