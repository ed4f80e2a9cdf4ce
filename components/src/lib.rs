//! LinuxCNC-compatible realtime HAL components, loadable with `loadrt`
//! under their LinuxCNC names. components.md (in the shared reference)
//! states each one's behaviour; the golden files check it against
//! LinuxCNC's own output.
//!
//! * `halcomp`: the halcompile conventions (instances, naming, and the
//!   `num_chan=`/`names=` channels of the C-style components) shared by
//!   the components; `cmath`: C's float-to-integer conversions and the
//!   cached scale reciprocal.
//! * `infra`: threads, sampler, streamer, threadtest.
//! * `stepgen`: stepgen (every step type, position and velocity control).
//! * `encoder`: encoder, sim_encoder, encoder_ratio.
//! * `counting`: counter.
//! * `generators`: pwmgen, siggen.
//! * `pid`: pid, timedelta.
//! * `gates`: and2, or2, xor2, not, logic.
//! * `selectors`: mux2, mux4, mux8, mux16, mux_generic, select8.
//! * `math`: abs, abs_s32, abs_s64, sum2, mult2, div2, scale, invert,
//!   hypot, blend, constant.
//! * `limits`: limit1, limit2, limit3, comp, wcomp, near, deadzone, minmax.
//! * `filters`: lowpass, ilowpass, ddt, integ, biquad, lincurve.
//! * `timing`: edge, flipflop, oneshot, timedelay, toggle, toggle2nist,
//!   debounce, dbounce, updown, charge_pump, estop_latch, sample_hold.
//! * `bits`: bitslice, bitwise; `convert`: the conv_<in>_<out> family.
//! * `notice`: stderr messages posted from realtime functions, written by
//!   a helper thread.

#![forbid(unsafe_code)]

pub mod bits;
pub mod cmath;
pub mod convert;
pub mod counting;
pub mod encoder;
pub mod filters;
pub mod gates;
pub mod generators;
pub mod halcomp;
pub mod infra;
pub mod joints;
pub mod laser;
pub mod limits;
pub mod math;
pub mod motor;
pub mod notice;
pub mod offsets;
pub mod panel;
pub mod pid;
pub mod plasma;
pub mod selectors;
pub mod shared;
pub mod sim;
pub mod spindle;
pub mod stats;
pub mod stepgen;
#[cfg(test)]
pub(crate) mod testing;
pub mod timing;
pub mod toolchange;

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
    v.extend(convert::modules());
    v.extend(generators::modules());
    v.extend(limits::modules());
    v.extend(filters::modules());
    v.extend(timing::modules());
    v.extend(bits::modules());
    v.extend(gates::modules());
    v.extend(selectors::modules());
    v.extend(math::modules());
    v.extend(stepgen::modules());
    v.extend(pid::modules());
    v.extend(encoder::modules());
    v.extend(sim::modules());
    v.extend(spindle::modules());
    v.extend(plasma::modules());
    v.extend(toolchange::modules());
    v.extend(motor::modules());
    v.extend(offsets::modules());
    v.extend(joints::modules());
    v.extend(panel::modules());
    v.extend(laser::modules());
    v.extend(stats::modules());
    v
}
