//! What the realtime side and the non-realtime helper share per drive:
//! the shared CiA 402 layer's atomics ([`hal_cia402::shared`]).

pub use hal_cia402::shared::{DriveShared, Restart};
