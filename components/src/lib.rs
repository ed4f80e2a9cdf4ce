//! LinuxCNC-compatible realtime HAL components, loadable with `loadrt`
//! under their LinuxCNC names.
//!
//! * `infra`: `threads`, `sampler`, `streamer` (the test harness).

pub mod infra;

use hal_core::ModuleDef;

/// Every module this crate provides.
pub fn modules() -> Vec<&'static ModuleDef> {
    vec![
        &infra::threads::MODULE,
        &infra::sampler::MODULE,
        &infra::streamer::MODULE,
    ]
}
