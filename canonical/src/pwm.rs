//! The canonical PWM output, for drivers with hardware PWM generators
//! (hostmot2's pwmgen names, which other boards follow). The software
//! pwmgen in the components crate is separate: it keeps LinuxCNC's own
//! pins and arithmetic.
//!
//! | name | kind | type | dir | meaning |
//! |---|---|---|---|---|
//! | `value` | pin | float | in | command, in user units |
//! | `enable` | pin | bit | in | FALSE: no pulses, outputs off |
//! | `scale` | param | float | rw | value that means 100 % duty (default 1.0); within 1e-20 of 0 is replaced by 1.0 ([`usable_scale`]) |
//!
//! Behaviour: duty cycle = `value / scale`, clipped to [-1, 1]; its sign
//! is the direction. A NaN command gives 0 duty: the motor stops rather
//! than running away.

use hal_core::{HalHost, HostPin, In, Ours, PinFactory, Result, Rw};

use crate::naming::{ChannelNames, Interface};
use crate::usable_scale;

/// The duty cycle for a command, as the interface defines it. `scale` is
/// the one [`usable_scale`] leaves; should a direct caller pass one that
/// still divides by zero, or a NaN, the duty is 0.
pub fn duty(value: f64, scale: f64) -> f64 {
    if scale.abs() < 1e-20 || scale.is_nan() {
        return 0.0;
    }
    let d = value / scale;
    if d.is_nan() {
        0.0
    } else {
        d.clamp(-1.0, 1.0)
    }
}

/// A canonical PWM channel.
pub struct Pwm<H: HalHost = Ours> {
    value: H::Pin<f64, In>,
    enable: H::Pin<bool, In>,
    scale: H::Param<f64, Rw>,
}

impl Interface for Pwm {
    const IO_TYPE: &'static str = "pwmgen";
}

impl<H: HalHost> Pwm<H> {
    /// Exports channel `chan` on `comp`.
    pub fn export(comp: &impl PinFactory<H>, names: &ChannelNames, chan: usize) -> Result<Self> {
        Ok(Pwm {
            value: comp.pin(&names.item(chan, "value"))?,
            enable: comp.pin(&names.item(chan, "enable"))?,
            scale: comp.param(&names.item(chan, "scale"), 1.0)?,
        })
    }

    /// The duty cycle in [-1, 1], or `None` while disabled. A scale too
    /// close to 0 is replaced by 1.0, enabled or not.
    #[inline]
    pub fn duty(&self) -> Option<f64> {
        let scale = usable_scale(&self.scale);
        self.enable.get().then(|| duty(self.value.get(), scale))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duty_is_clipped_and_safe() {
        assert_eq!(duty(0.5, 1.0), 0.5);
        assert_eq!(duty(-30.0, 10.0), -1.0);
        assert_eq!(duty(3.0, 2.0), 1.0);
        assert_eq!(duty(f64::NAN, 1.0), 0.0);
        assert_eq!(duty(1.0, 0.0), 0.0);
        assert_eq!(duty(f64::INFINITY, f64::INFINITY), 0.0);
    }
}
