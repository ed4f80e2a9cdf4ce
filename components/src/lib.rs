//! LinuxCNC-compatible realtime HAL components, loadable with `loadrt`
//! under their LinuxCNC names.
//!
//! * `halcomp`: the halcompile conventions (instances, naming) shared by
//!   the simple components.
//! * `infra`: `threads`, `sampler`, `streamer` (the test harness).
//! * `logic`: and2, or2, xor2, not.
//! * `convert`: the conv_<in>_<out> family.
//! * `arith`: mult2, sum2.
//! * `select`: mux2, mux4, mux8.
//! * `counting`: counter.
//! * `encoder`: encoder, sim_encoder, encoder_ratio.

pub mod arith;
pub mod cmath;
pub mod convert;
pub mod counting;
pub mod encoder;
pub mod halcomp;
pub mod infra;
pub mod logic;
pub mod select;

use hal_core::ModuleDef;

/// Every module this crate provides.
pub fn modules() -> Vec<&'static ModuleDef> {
    let mut v: Vec<&'static ModuleDef> = vec![
        &infra::threads::MODULE,
        &infra::sampler::MODULE,
        &infra::streamer::MODULE,
        &counting::counter::MODULE,
        &infra::threadtest::MODULE,
    ];
    v.extend(logic::modules());
    v.extend(convert::modules());
    v.extend(arith::modules());
    v.extend(select::modules());
    v.extend(encoder::modules());
    v
}
