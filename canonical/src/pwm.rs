//! The canonical PWM output: the common part of hostmot2's pwmgen and the
//! software pwmgen.
//!
//! | name | kind | type | dir | meaning |
//! |---|---|---|---|---|
//! | `value` | pin | float | in | command, in user units |
//! | `enable` | pin | bit | in | FALSE: no pulses, outputs off |
//! | `scale` | param | float | rw | value that means 100 % duty (default 1.0) |
//!
//! Behaviour: duty cycle = `value / scale`, clipped to [-1, 1]; its sign
//! is the direction. A NaN command, or a scale within 1e-20 of 0, gives 0
//! duty: the motor stops rather than running away.

use hal_core::{Component, In, Param, Pin, Result, Rw};

use crate::naming::ChannelNames;

/// The duty cycle for a command, as the interface defines it.
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
pub struct Pwm {
    value: Pin<f64, In>,
    enable: Pin<bool, In>,
    scale: Param<f64, Rw>,
}

impl Pwm {
    /// Exports channel `chan` on `comp`.
    pub fn export(comp: &Component, names: &ChannelNames, chan: usize) -> Result<Pwm> {
        Ok(Pwm {
            value: comp.pin(&names.item(chan, "value"))?,
            enable: comp.pin(&names.item(chan, "enable"))?,
            scale: comp.param(&names.item(chan, "scale"), 1.0)?,
        })
    }

    /// The duty cycle in [-1, 1], or `None` while disabled.
    #[inline]
    pub fn duty(&self) -> Option<f64> {
        self.enable
            .get()
            .then(|| duty(self.value.get(), self.scale.get()))
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
