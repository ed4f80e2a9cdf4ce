//! Simulated PWM generators (hardware.md 5.9.5): the value, mode, DDS and
//! enable registers, and the duty cycle, direction and frequency they
//! produce. A motor driver sees the duty signed by the direction output.

use super::world::PwmOut;
use crate::regs::pwmgen as r;

/// The PWM generator module.
#[derive(Debug, Clone, Default)]
pub struct SimPwms {
    /// PWMVal per instance.
    pub values: Vec<u32>,
    /// Mode per instance.
    pub modes: Vec<u32>,
    /// PWM rate DDS.
    pub pwm_dds: u32,
    /// PDM rate DDS.
    pub pdm_dds: u32,
    /// Enable bits.
    pub enable: u32,
}

impl SimPwms {
    /// `n` generators.
    pub fn new(n: usize) -> SimPwms {
        SimPwms {
            values: vec![0; n],
            modes: vec![0; n],
            ..Default::default()
        }
    }

    /// A register read.
    pub fn read(&self, reg: usize, inst: usize) -> u32 {
        match reg {
            r::VALUE => self.values.get(inst).copied().unwrap_or(0),
            r::MODE => self.modes.get(inst).copied().unwrap_or(0),
            r::PWM_DDS => self.pwm_dds,
            r::PDM_DDS => self.pdm_dds,
            r::ENABLE => self.enable,
            _ => 0,
        }
    }

    /// A register write.
    pub fn write(&mut self, reg: usize, inst: usize, v: u32) {
        match reg {
            r::VALUE => {
                if let Some(x) = self.values.get_mut(inst) {
                    *x = v
                }
            }
            r::MODE => {
                if let Some(x) = self.modes.get_mut(inst) {
                    *x = v
                }
            }
            r::PWM_DDS => self.pwm_dds = v & 0xFFFF,
            r::PDM_DDS => self.pdm_dds = v & 0xFFFF,
            r::ENABLE => self.enable = v,
            _ => {}
        }
    }

    /// What generator `i` puts out, before the pins decide whether it
    /// reaches the connector.
    pub fn output(&self, i: usize, clock_high: u32) -> PwmOut {
        let (Some(&value), Some(&mode)) = (self.values.get(i), self.modes.get(i)) else {
            return PwmOut::default();
        };
        let pdm = (mode >> r::MODE_OUTPUT_SHIFT) & 3 == r::OUT_PDM;
        let bits = if pdm {
            12
        } else {
            (mode & r::MODE_WIDTH_MASK) + 9
        };
        let mut duty = ((value >> 16) & ((1 << bits) - 1)) as f64;
        if mode & r::MODE_DITHER != 0 && !pdm {
            duty += (value & 0xFFFF) as f64 / 65536.0;
        }
        let duty = (duty / (1u32 << bits) as f64).min(1.0);
        let enabled = self.enable & (1 << i) != 0;
        let frequency_hz = if pdm {
            clock_high as f64 * self.pdm_dds as f64 / 65536.0
        } else {
            let div = if mode & r::MODE_SYMMETRIC != 0 {
                bits + 1
            } else {
                bits
            };
            clock_high as f64 * self.pwm_dds as f64 / 65536.0 / (1u32 << div) as f64
        };
        PwmOut {
            duty: if !enabled {
                0.0
            } else if value & r::VALUE_DIR != 0 {
                -duty
            } else {
                duty
            },
            enabled,
            frequency_hz,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duty_direction_and_frequency() {
        let mut p = SimPwms::new(2);
        p.write(r::MODE, 0, 3); // 12 bits, PWM/dir
        p.write(r::PWM_DDS, 0, 26_843);
        p.write(r::VALUE, 0, (2048 << 16) | r::VALUE_DIR);
        let o = p.output(0, 200_000_000);
        assert_eq!(o.duty, 0.0, "disabled");
        p.write(r::ENABLE, 0, 1);
        let o = p.output(0, 200_000_000);
        assert_eq!(o.duty, -0.5);
        assert!(
            (o.frequency_hz - 20_000.0).abs() < 1.0,
            "{}",
            o.frequency_hz
        );
        assert_eq!(p.output(5, 200_000_000), PwmOut::default());
    }
}
