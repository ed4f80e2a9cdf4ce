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
//! * `generators`: pwmgen, siggen.
//! * `limits`: limit1, limit2, limit3, comp, wcomp, near, deadzone, minmax.
//! * `filters`: lowpass, ilowpass, ddt, integ, biquad, lincurve.
//! * `timing`: edge, flipflop, oneshot, timedelay, toggle, toggle2nist,
//!   debounce, dbounce, updown, charge_pump, estop_latch, sample_hold.
//! * `bits`: bitslice, bitwise.
//! * `stepgen`: the software step generator.
//! * `pid`: pid, timedelta.
//! * `encoder`: encoder, sim_encoder, encoder_ratio.

pub mod arith;
pub mod bits;
pub mod cmath;
pub mod convert;
pub mod counting;
pub mod filters;
pub mod generators;
//! * `gates`: logic (personality-configured gate).
//! * `choosers`: mux16, mux_generic, select8.
//! * `math`: abs, abs_s32, abs_s64, div2, scale, invert, hypot, blend.

pub mod arith;
pub mod choosers;
pub mod cmath;
pub mod convert;
pub mod counting;
pub mod gates;
pub mod encoder;
pub mod halcomp;
pub mod infra;
pub mod limits;
pub mod logic;
pub mod math;
pub mod pid;
pub mod select;
pub mod timing;
pub mod stepgen;

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
    v.extend(generators::modules());
    v.extend(limits::modules());
    v.extend(filters::modules());
    v.extend(timing::modules());
    v.extend(bits::modules());
    v.extend(gates::modules());
    v.extend(choosers::modules());
    v.extend(math::modules());
    v.extend(stepgen::modules());
    v.extend(pid::modules());
    v.extend(encoder::modules());
    v
}
