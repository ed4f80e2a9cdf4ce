//! Helpers of the Servo-To-Go HAL tests: the layer's test helpers, the
//! simulated board a `loadrt` published, functions in a 1 ms thread.
#![allow(dead_code, unused_imports)]

use std::sync::Arc;

use hal_core::Host;
use hal_driver::sim::SimBoard;
pub use hal_driver::testing::{bit, float, host, log_lines, s32, set, value as get, wait};
use hal_stg::sim::StgModel;

/// The simulated board the driver published.
pub fn board(host: &Host) -> Arc<SimBoard<StgModel>> {
    hal_driver::sim::find(host.instance().name(), "stg").expect("no simulated stg")
}

/// Runs `functs` in a 1 ms thread `servo`, in order.
pub fn run(host: &Host, functs: &[&str]) {
    hal_driver::testing::run(host, "servo", 1_000_000, functs);
}
