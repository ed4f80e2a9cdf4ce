//! LinuxCNC-compatible realtime HAL components, loadable with `loadrt`
//! under their LinuxCNC names. components.md (in the shared reference)
//! states each one's behaviour; the golden files check it against
//! LinuxCNC's own output.
//!
//! * `halcomp`: the halcompile conventions (instances, naming, and the
//!   `num_chan=`/`names=` channels of the C-style components) shared by
//!   the components; `cmath`: C's float-to-integer conversions and the
//!   cached scale reciprocal.
//! * `infra`: threads, sampler, streamer, scope_rt, threadtest.
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
//! * `bits`: bitslice, bitwise, bin2gray, gray2bin, bitmerge,
//!   weighted_sum; `convert`: the conv_<in>_<out> family.
//! * `sim`: sim_home_switch, sim_spindle, sim_axis_hardware, sim_parport,
//!   sphereprobe, steptest, axistest.
//! * `spindle`: gearchange, orient, spindle, spindle_monitor.
//! * `toolchange`: carousel. `motor`: bldc, clarke2, clarke3, clarkeinv.
//! * `offsets`: moveoff, eoffset_per_angle. `joints`: gantry,
//!   differential, corexy_by_hal.
//! * `plasma`: thc, thcud, ohmic, plasmac. `laser`: laserpower.
//! * `panel`: xhc_hb04_util, anglejog, message, matrix_kb,
//!   sim_matrix_kb. `stats`: histobins, latencybins.
//! * In the families above as well: match8, lut5, maj3, tristate_bit,
//!   tristate_float (gates); demux, demux_generic, enum, output_buffer,
//!   multiswitch (selectors); scaled_s32_sums, offset, knob2float,
//!   feedcomp, joyhandle (math); limit_axis, simple_tp (limits);
//!   filter_kalman, led_dim (filters); ton, tof, tp, time, reset,
//!   safety_latch, watchdog, multiclick (timing); supply (generators).
//! * `notice`: stderr messages posted from realtime functions, written by
//!   a helper thread. `shared`: state two functions of one component
//!   share. `fuzzing` (feature `fuzzing`): the all-or-nothing `loadrt`
//!   invariant, a fuzz-target body.

#![forbid(unsafe_code)]

mod bits;
mod cmath;
mod convert;
mod counting;
pub mod encoder;
mod error;
mod filters;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
mod gates;
mod generators;
pub mod halcomp;
pub mod infra;
mod joints;
mod laser;
mod limits;
mod math;
mod motor;
mod notice;
mod offsets;
mod panel;
pub mod pid;
mod plasma;
mod selectors;
pub mod shared;
mod sim;
mod spindle;
mod stats;
pub mod stepgen;
#[cfg(test)]
pub(crate) mod testing;
mod timing;
mod toolchange;

pub use error::CompError;
/// The `raster_program` fuzz target's body (the bytes of raster's port).
pub use laser::raster::fuzz_program as fuzz_raster_program;

use hal_core::ModuleDef;

/// Every module this crate provides.
pub fn modules() -> Vec<&'static ModuleDef> {
    let mut v: Vec<&'static ModuleDef> = vec![
        &infra::threads::MODULE,
        &infra::sampler::MODULE,
        &infra::scope_rt::MODULE,
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

#[cfg(test)]
mod module_list_tests {
    #[test]
    fn every_module_name_is_unique() {
        let mut names: Vec<&str> = super::modules().iter().map(|m| m.name).collect();
        let n = names.len();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), n, "a module name is registered twice");
    }
}
