//! The canonical device interfaces: the one definition of each io-type.
//!
//! A driver exports an io-type by calling its `export` function and gets
//! the pins and params below, named `<device>.<num>.<io-type>.<chan>.<name>`
//! (see [`ChannelNames`]; each interface holds its io-type in
//! [`Interface::IO_TYPE`]), together with the shared behaviour. Every
//! driver's digital input therefore looks and behaves like every other's.
//!
//! # digin: digital input
//! | name | kind | type | dir | meaning |
//! |---|---|---|---|---|
//! | `in` | pin | bit | out | state of the hardware input |
//! | `in-not` | pin | bit | out | the same, inverted |
//!
//! Behaviour: the driver's `read` calls [`DigIn::update`] with the raw
//! level; both pins are written every time.
//!
//! # digout: digital output
//! | name | kind | type | dir | meaning |
//! |---|---|---|---|---|
//! | `out` | pin | bit | in | value to write |
//! | `invert` | param | bit | rw | invert before writing (default FALSE) |
//!
//! Behaviour: the driver's `write` drives the hardware with
//! [`DigOut::level`] = `out XOR invert`. Its safe state is the level for
//! `out` FALSE, the driver's choice of "off".
//!
//! # adcin: analog input
//! | name | kind | type | dir | unit | meaning |
//! |---|---|---|---|---|---|
//! | `value` | pin | float | out | user units | `(reading * scale) - offset` |
//! | `scale` | param | float | rw | user units per volt | default 1.0 |
//! | `offset` | param | float | rw | user units | default 0.0 |
//! | `bit_weight` | param | float | rw | volts per count | value of one LSB |
//! | `hw_offset` | param | float | rw | volts | reading with 0 V applied |
//!
//! Behaviour: for a converter that gives counts, the reading in volts is
//! `counts * bit_weight - hw_offset` ([`AdcIn::update_counts`]); a driver
//! that reads volts directly calls [`AdcIn::update_volts`].
//!
//! # adcout: analog output
//! | name | kind | type | dir | unit | meaning |
//! |---|---|---|---|---|---|
//! | `value` | pin | float | in | user units | value to write |
//! | `enable` | pin | bit | in | | FALSE: the hardware outputs 0 |
//! | `scale` | param | float | rw | volts per user unit | default 1.0 |
//! | `offset` | param | float | rw | volts | default 0.0 |
//! | `high_limit` | param | float | rw | volts | upper clamp (optional) |
//! | `low_limit` | param | float | rw | volts | lower clamp (optional) |
//! | `bit_weight` | param | float | rw | volts per count | (optional) |
//! | `hw_offset` | param | float | rw | volts | output for count 0 (optional) |
//!
//! Behaviour: [`AdcOut::volts`] is `value * scale + offset` (0 V if that
//! is NaN), clamped to the limits when the driver exports them, or `None`
//! while `enable` is FALSE (the hardware's zero). [`AdcOut::counts`] turns volts into
//! converter counts with `bit_weight` and `hw_offset`, rounded and clamped
//! to the converter's range.
//!
//! LinuxCNC's servo-card drivers (hal_stg, hal_motenc) shape their analog
//! outputs differently (`(value - offset) * gain`, no enable pin); they
//! export [`DacOut`], that shape kept under the same io-type.
//!
//! # encoder, stepgen and pwm
//! For drivers with hardware counters, step and PWM generators:
//! [`encoder`], [`stepgen`] and [`pwm`] define the pins (hostmot2's
//! names, which other boards follow) and the shared behaviour: wide counts
//! from narrow counters, reset and the index-enable handshake, velocity
//! from the time between counts; the step rate that reaches a position
//! within maxvel and maxaccel, step timing in hardware clocks; duty cycle
//! from value and scale. Each module's docs hold its table. Their io-types
//! are `encoder`, `stepgen` and `pwmgen`; a scale they divide by follows
//! one rule, [`usable_scale`].
//!
//! # Hosts
//! Every interface is generic over the HAL its pins live in
//! ([`hal_core::HalHost`]), with ours ([`hal_core::Ours`]) as the default:
//! `DigOut` is `DigOut<Ours>`, and `DigOut::export(&component, ...)`
//! infers the host from the [`hal_core::PinFactory`] it is given. A
//! driver declared once for both hosts holds `DigOut<H>` and exports it
//! through its host's factory; the code is monomorphised per host.
//! [`Interface::IO_TYPE`] is the same in every host and is implemented on
//! the default form.
//!
//! The software components (stepgen, encoder, pwmgen in the components
//! crate) keep LinuxCNC's historic names and exact arithmetic, which
//! existing configurations and LinuxCNC's own test outputs depend on.

#![forbid(unsafe_code)]

mod adc;
mod dac;
mod dig;
mod encoder;
mod naming;
pub mod pwm;
pub mod stepgen;

pub use adc::{AdcIn, AdcOut, AdcOutOptions, Converter};
pub use dac::DacOut;
pub use dig::{DigIn, DigOut};
pub use encoder::{Encoder, EncoderCore, EncoderOutputs};
pub use naming::{ChannelNames, Interface};
pub use pwm::Pwm;
pub use stepgen::Stepgen;

use hal_core::{HostParam, Rw};

/// The value of a scale param that the interface divides by, under
/// LinuxCNC's rule (its encoder, stepgen and pwmgen alike): a value within
/// 1e-20 of 0, or NaN, is replaced by 1.0 and written back into the
/// param, so the user sees the value in force.
#[inline]
pub fn usable_scale(scale: &impl HostParam<f64, Rw>) -> f64 {
    let s = scale.get();
    if s.abs() < 1e-20 || s.is_nan() {
        scale.set(1.0);
        1.0
    } else {
        s
    }
}
