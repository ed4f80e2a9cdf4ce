//! The analog output of LinuxCNC's servo-card drivers (hal_stg,
//! hal_motenc): the adcout io-type in the shape those drivers gave it,
//! which their users' HAL files rely on.
//!
//! | name | kind | type | dir | unit | meaning |
//! |---|---|---|---|---|---|
//! | `value` | pin | float | in | user units | value to write |
//! | `offset` | param | float | rw | user units | subtracted from `value` first (default 0.0) |
//! | `gain` | param | float | rw | volts per user unit | applied after the offset (default 1.0) |
//!
//! Behaviour: volts = `(value - offset) * gain`, clamped to the
//! converter's range; a NaN (from upstream or from the params) gives 0 V.
//! There is no `enable` pin: such cards' outputs are always live, and the
//! amplifier enable is one of the card's digital outputs.
//!
//! This differs from [`AdcOut`](crate::AdcOut) (`value * scale +
//! offset`, an offset in volts, an `enable` pin that starts FALSE) on
//! purpose: a LinuxCNC HAL file that sets `dac-offset` in user units and
//! never touches an enable pin must drive the same voltage here.

use hal_core::{HalHost, HostParam, HostPin, In, Ours, PinFactory, Result, Rw};

use crate::naming::{ChannelNames, Interface};

/// An analog output of a servo card, LinuxCNC's form.
pub struct DacOut<H: HalHost = Ours> {
    value: H::Pin<f64, In>,
    offset: H::Param<f64, Rw>,
    gain: H::Param<f64, Rw>,
}

impl Interface for DacOut {
    const IO_TYPE: &'static str = "adcout";
}

impl<H: HalHost> DacOut<H> {
    /// Exports channel `chan`'s `value` pin and its `offset` and `gain`
    /// params on `comp`.
    pub fn export(comp: &impl PinFactory<H>, names: &ChannelNames, chan: usize) -> Result<Self> {
        Ok(DacOut {
            value: comp.pin(&names.item(chan, "value"))?,
            offset: comp.param(&names.item(chan, "offset"), 0.0)?,
            gain: comp.param(&names.item(chan, "gain"), 1.0)?,
        })
    }

    /// The volts to output: `(value - offset) * gain`, within
    /// `low..=high`; 0 V (clamped into the range) when that is NaN.
    #[inline]
    pub fn volts(&self, low: f64, high: f64) -> f64 {
        let v = (self.value.get() - self.offset.get()) * self.gain.get();
        let v = if v.is_nan() { 0.0 } else { v };
        // Not f64::clamp: it panics when low > high.
        v.max(low).min(high)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_core::{ComponentKind, Host, HostConfig, Value};

    #[test]
    fn offset_before_gain_then_clamp() {
        let host = Host::create(HostConfig::for_tests("canon-dacout")).unwrap();
        let inst = host.instance();
        let comp = inst.new_component("card", ComponentKind::User).unwrap();
        let names = ChannelNames::custom(|c, n| format!("card.{c}.dac-{n}"));
        let dac = DacOut::export(&comp, &names, 2).unwrap();
        assert_eq!(dac.volts(-10.0, 10.0), 0.0);
        inst.set_pin("card.2.dac-value", Value::Float(3.0)).unwrap();
        inst.set_param("card.2.dac-offset", Value::Float(1.0))
            .unwrap();
        inst.set_param("card.2.dac-gain", Value::Float(2.0))
            .unwrap();
        assert_eq!(dac.volts(-10.0, 10.0), 4.0, "(3 - 1) * 2");
        inst.set_pin("card.2.dac-value", Value::Float(100.0))
            .unwrap();
        assert_eq!(dac.volts(-10.0, 10.0), 10.0);
        inst.set_pin("card.2.dac-value", Value::Float(-100.0))
            .unwrap();
        assert_eq!(dac.volts(-10.0, 10.0), -10.0);
        inst.set_pin("card.2.dac-value", Value::Float(f64::NAN))
            .unwrap();
        assert_eq!(dac.volts(-10.0, 10.0), 0.0);
        assert_eq!(dac.volts(1.0, 10.0), 1.0, "0 V clamped into the range");
    }
}
