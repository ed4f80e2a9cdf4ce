//! Counting components: counter.

pub mod counter;
