//! PWMGen (hardware.md 5.9.5): hardware PWM/PDM generators.
//!
//! Each instance is a canonical PWM output ([`canonical::Pwm`]: `value`,
//! `enable`, `scale`; duty = value / scale clipped to ±1) with
//! hostmot2's params `output-type` (1 PWM + direction, 2 up/down, 3 PDM +
//! direction, 4 direction + PWM), `offset-mode` (0 → 50 % duty) and
//! `dither` (firmware v1), and the module params `pwmgen.pwm_frequency`
//! and `pwmgen.pdm_frequency` (Hz, 20 kHz).
//!
//! The PWM frequency takes the finest resolution (12, 11, 10 or 9 bits)
//! whose DDS value fits 16 bits; a frequency above what 9 bits allow is
//! clamped and the param rewritten, as are PDM frequencies outside the
//! DDS range.

use canonical::{ChannelNames, Pwm};
use hal_core::{HalHost, HostParam, Ours, PinFactory, Result as HalResult, Rw};

use crate::firmware::ModuleUse;
use crate::log::Level;
use crate::md::ModuleDescriptor;
use crate::modules::{put, Export, Notify};
use crate::regs::pwmgen as r;
use crate::tram::Slot;
use crate::transport::{Transport, TransportError};

/// Default PWM and PDM frequency, Hz.
pub const DEFAULT_FREQUENCY: u32 = 20_000;

/// The PWM resolution and DDS value for `hz` at `clock_high`, and the
/// frequency that had to be used if `hz` was out of range.
pub fn pwm_dds(hz: u32, clock_high: u32) -> (u32, u32, Option<u32>) {
    let hz = hz.max(1);
    for bits in (9..=12).rev() {
        let dds = hz as u64 * 65536 * (1u64 << bits) / clock_high as u64;
        if dds < 65536 {
            return (bits, dds as u32, None);
        }
    }
    let max = (clock_high as u64 * 65535 / (65536 * 512)) as u32;
    let dds = max as u64 * 65536 * 512 / clock_high as u64;
    (9, dds as u32, Some(max))
}

/// The PDM DDS value for `hz`, and the frequency used if clamped.
pub fn pdm_dds(hz: u32, clock_high: u32) -> (u32, Option<u32>) {
    let dds = hz as u64 * 65536 / clock_high as u64;
    if dds < 1 {
        let hz = clock_high.div_ceil(65536);
        (1, Some(hz))
    } else if dds > 65535 {
        (65535, Some((65535 * clock_high as u64 / 65536) as u32))
    } else {
        (dds as u32, None)
    }
}

/// The PWMVal register for duty `d` (−1..1).
pub fn value_word(d: f64, output_type: u32, pwm_bits: u32, offset: bool, dither: bool) -> u32 {
    let pdm = output_type == 3;
    let t = if dither && !pdm { 1.0625 } else { 1.0 };
    let mag = if offset {
        let full = (1u32 << if pdm { 11 } else { pwm_bits - 1 }) as f64;
        d * (full - t) + full
    } else {
        let full = (1u32 << if pdm { 12 } else { pwm_bits }) as f64;
        d.abs() * (full - t)
    };
    let mut w = (mag.max(0.0) * 65536.0) as u32;
    if d < 0.0 {
        w |= r::VALUE_DIR;
    }
    w
}

struct Chan<H: HalHost = Ours> {
    pwm: Pwm<H>,
    output_type: H::Param<i32, Rw>,
    offset_mode: H::Param<bool, Rw>,
    dither: Option<H::Param<bool, Rw>>,
}

/// What the module registers hold, to rewrite them on change.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Setup {
    pwm_dds: u32,
    pdm_dds: u32,
    bits: u32,
    enables: u32,
}

/// The PWM generator module.
pub struct Pwmgens<H: HalHost = Ours> {
    md: ModuleDescriptor,
    value_write: Slot,
    chans: Vec<Chan<H>>,
    pwm_frequency: H::Param<u32, Rw>,
    pdm_frequency: H::Param<u32, Rw>,
    written: Option<Setup>,
    written_modes: Vec<Option<u32>>,
    /// The PWM resolution for a frequency: (Hz, bits), recomputed when
    /// the frequency changes.
    bits: (u32, u32),
}

impl<H: HalHost> Pwmgens<H> {
    /// Exports the generators in use and registers the value writes.
    pub fn export<F: PinFactory<H>>(x: &mut Export<'_, F>, m: &ModuleUse) -> HalResult<Pwmgens<H>> {
        let prefix = x.prefix.to_string();
        let names = ChannelNames::custom(move |i, item| format!("{prefix}.pwmgen.{i:02}.{item}"));
        let mut chans = Vec::with_capacity(m.instances as usize);
        for i in 0..m.instances as usize {
            let c = x.comp;
            chans.push(Chan {
                pwm: Pwm::export(c, &names, i)?,
                output_type: c.param(&names.item(i, "output-type"), 1)?,
                offset_mode: c.param(&names.item(i, "offset-mode"), false)?,
                dither: if m.md.version >= 1 {
                    Some(c.param(&names.item(i, "dither"), false)?)
                } else {
                    None
                },
            });
        }
        let pwm_frequency = x
            .comp
            .param(&x.name("pwmgen.pwm_frequency"), DEFAULT_FREQUENCY)?;
        let pdm_frequency = x
            .comp
            .param(&x.name("pwmgen.pdm_frequency"), DEFAULT_FREQUENCY)?;
        let value_write = x.tram.add_write(m.md.reg(r::VALUE), m.instances as usize);
        let n = chans.len();
        Ok(Pwmgens {
            md: m.md,
            value_write,
            chans,
            pwm_frequency,
            pdm_frequency,
            written: None,
            written_modes: vec![None; n],
            bits: (0, pwm_dds(0, m.md.clock_hz).0),
        })
    }

    /// Writes every configuration register.
    pub fn force_write(
        &mut self,
        t: &mut dyn Transport,
        say: &Notify,
    ) -> Result<(), TransportError> {
        self.written = None;
        self.written_modes.fill(None);
        self.write_config(t, say)
    }

    fn output_type(c: &Chan<H>, say: &Notify) -> u32 {
        match c.output_type.get() {
            t @ 1..=4 => t as u32,
            _ => {
                c.output_type.set(1);
                say.say(
                    Level::Err,
                    format_args!("pwmgen output-type must be 1 to 4, set to 1"),
                );
                1
            }
        }
    }

    /// Queues the mode, DDS and enable registers that changed.
    pub fn write_config(
        &mut self,
        t: &mut dyn Transport,
        say: &Notify,
    ) -> Result<(), TransportError> {
        let clock = self.md.clock_hz;
        let (bits, pwm_dds, clamped) = pwm_dds(self.pwm_frequency.get(), clock);
        if let Some(hz) = clamped {
            self.pwm_frequency.set(hz);
            say.say(
                Level::Err,
                format_args!("pwmgen pwm_frequency too high for the board, clamped"),
            );
        }
        let (pdm_dds, clamped) = pdm_dds(self.pdm_frequency.get(), clock);
        if let Some(hz) = clamped {
            self.pdm_frequency.set(hz);
            say.say(
                Level::Err,
                format_args!("pwmgen pdm_frequency out of range, clamped"),
            );
        }
        let mut enables = 0;
        for (i, c) in self.chans.iter().enumerate() {
            if c.pwm.duty().is_some() {
                enables |= 1 << i;
            }
        }
        let setup = Setup {
            pwm_dds,
            pdm_dds,
            bits,
            enables,
        };
        for i in 0..self.chans.len() {
            let c = &self.chans[i];
            let ty = Self::output_type(c, say);
            let mut mode = (bits - 9) & r::MODE_WIDTH_MASK;
            mode |= match ty {
                2 => r::OUT_UP_DOWN,
                3 => r::OUT_PDM,
                4 => r::OUT_DIR_PWM,
                _ => r::OUT_PWM_DIR,
            } << r::MODE_OUTPUT_SHIFT;
            if ty != 3 {
                mode |= r::MODE_DOUBLE_BUFFERED;
            }
            if c.dither.as_ref().is_some_and(|d| d.get()) {
                mode |= r::MODE_DITHER;
            }
            if self.written_modes[i] != Some(mode) {
                put(t, self.md.inst_reg(r::MODE, i), mode)?;
                self.written_modes[i] = Some(mode);
            }
        }
        let had = self.written;
        if had.map(|s| s.pwm_dds) != Some(pwm_dds) {
            put(t, self.md.reg(r::PWM_DDS), pwm_dds)?;
        }
        if had.map(|s| s.pdm_dds) != Some(pdm_dds) {
            put(t, self.md.reg(r::PDM_DDS), pdm_dds)?;
        }
        if had.map(|s| s.enables) != Some(enables) {
            put(t, self.md.reg(r::ENABLE), enables)?;
        }
        self.written = Some(setup);
        Ok(())
    }

    /// Computes every value word into the TRAM words, at the resolution
    /// the present `pwm_frequency` gives (so a new frequency and the
    /// values for it take effect in the same cycle).
    pub fn prepare_write(&mut self, buf: &mut [u32]) {
        let hz = self.pwm_frequency.get();
        if self.bits.0 != hz {
            self.bits = (hz, pwm_dds(hz, self.md.clock_hz).0);
        }
        let bits = self.bits.1;
        let words = self.value_write.of_mut(buf);
        for (c, w) in self.chans.iter().zip(words.iter_mut()) {
            let d = c.pwm.duty().unwrap_or(0.0);
            let ty = c.output_type.get().clamp(1, 4) as u32;
            let dither = c.dither.as_ref().is_some_and(|d| d.get());
            *w = value_word(d, ty, bits, c.offset_mode.get(), dither);
        }
    }

    /// Safe state: every generator disabled and at 0, at once.
    pub fn go_safe(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        t.write(self.md.reg(r::ENABLE), &[0])?;
        let zeros = vec![0u32; self.chans.len()];
        t.write(self.md.reg(r::VALUE), &zeros)?;
        if let Some(s) = &mut self.written {
            s.enables = 0;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frequencies() {
        // 20 kHz at 200 MHz: 12 bits, DDS 26843.
        assert_eq!(pwm_dds(20_000, 200_000_000), (12, 26_843, None));
        // 100 kHz: 12 bits would need 134217, 10 bits 33554.
        assert_eq!(pwm_dds(100_000, 200_000_000), (10, 33_554, None));
        let (bits, _, clamped) = pwm_dds(1_000_000, 200_000_000);
        assert_eq!((bits, clamped), (9, Some(390_619)));
        assert_eq!(pdm_dds(20_000, 200_000_000), (6, None));
        assert_eq!(pdm_dds(1, 200_000_000), (1, Some(3052)));
        assert_eq!(pdm_dds(u32::MAX, 200_000_000).0, 65535);
    }

    #[test]
    fn value_words() {
        assert_eq!(
            value_word(0.5, 1, 12, false, false),
            (4095.0 * 0.5 * 65536.0) as u32
        );
        assert_eq!(
            value_word(-1.0, 1, 12, false, false),
            (4095u32 << 16) | r::VALUE_DIR
        );
        assert_eq!(value_word(0.0, 1, 12, true, false), 2048 << 16, "50 %");
        assert_eq!(
            value_word(1.0, 3, 9, false, false),
            4095 << 16,
            "PDM is 12 bits"
        );
        assert_eq!(value_word(0.0, 1, 12, false, false), 0);
    }
}
