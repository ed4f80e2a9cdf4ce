//! [`RtCell`]: the state `canservo.read` and `canservo.write` share,
//! handed to one of them at a time without a lock. The cell is the
//! shared driver layer's ([`hal_driver::rt_cell`]).

pub use hal_driver::rt_cell::RtCell;
