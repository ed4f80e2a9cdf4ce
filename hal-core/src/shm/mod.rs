//! The shared-memory segment: its mapping, header, process-shared lock, undo
//! journal and allocator. This is the one place where raw memory is touched;
//! everything above works with bounds-checked references to records.

mod alloc;
mod journal;
mod layout;
mod mutex;
mod owner;
mod segment;

pub(crate) use alloc::BlockKind;
pub(crate) use journal::{blob_words as blob_words_of, Txn};
pub(crate) use layout::*;
pub use layout::{latency_bucket, latency_bucket_floor_us};
pub(crate) use segment::Segment;
