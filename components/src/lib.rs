//! LinuxCNC-compatible realtime HAL components, loadable with `loadrt`
//! under their LinuxCNC names. components.md (in the shared reference)
//! states each one's behaviour; the golden files check it against
//! LinuxCNC's own output.
//!
//! * `halcomp`: the halcompile conventions (instances, naming) shared by
//!   the simple components; `cmath`: C's float-to-integer conversions.
//! * `infra`: threads, sampler, streamer, threadtest.
//! * `stepgen`: stepgen (every step type, position and velocity control).
//! * `encoder`: encoder, sim_encoder, encoder_ratio.
//! * `counting`: counter.
//! * `generators`: pwmgen, siggen.
//! * `pid`: pid, timedelta.
//! * `logic`: and2, or2, xor2, not; `gates`: logic.
//! * `select`: mux2, mux4, mux8; `choosers`: mux16, mux_generic, select8.
//! * `arith`: mult2, sum2; `math`: abs, abs_s32, abs_s64, div2, scale,
//!   invert, hypot, blend.
//! * `limits`: limit1, limit2, limit3, comp, wcomp, near, deadzone, minmax.
//! * `filters`: lowpass, ilowpass, ddt, integ, biquad, lincurve.
//! * `timing`: edge, flipflop, oneshot, timedelay, toggle, toggle2nist,
//!   debounce, dbounce, updown, charge_pump, estop_latch, sample_hold.
//! * `bits`: bitslice, bitwise; `convert`: the conv_<in>_<out> family.
//! * `notice`: stderr messages posted from realtime functions, written by
//!   a helper thread.

pub mod arith;
pub mod bits;
pub mod choosers;
pub mod cmath;
pub mod convert;
pub mod counting;
pub mod encoder;
pub mod filters;
pub mod gates;
pub mod generators;
pub mod halcomp;
pub mod infra;
pub mod limits;
pub mod logic;
pub mod math;
pub mod notice;
pub mod pid;
pub mod select;
pub mod stepgen;
#[cfg(test)]
pub(crate) mod testing;
pub mod timing;

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
