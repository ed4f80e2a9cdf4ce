//! A register model of the PCA9685 (hardware.md 7.2): the register file
//! with its power-up values, auto-increment, PRE_SCALE writable only
//! while asleep, the ALL_LED broadcast registers, the oscillator's
//! 500 µs start-up after SLEEP is cleared, RESTART, and each output's
//! duty cycle from its ON/OFF counts.
//!
//! Misuse a driver must avoid is counted, not hidden: PRE_SCALE written
//! while awake (ignored, as by the chip), RESTART before the oscillator
//! settled, any write to the test-mode register.

use std::any::Any;

use super::ChipModel;
use crate::regs::pca9685::*;

/// The chip.
#[derive(Debug, Clone)]
pub struct Pca9685 {
    regs: [u8; 256],
    pointer: u8,
    now_ns: u64,
    /// When the oscillator is stable after the last wake-up.
    settled_at: u64,
    /// PRE_SCALE writes refused because the chip was awake.
    pub prescale_writes_ignored: u32,
    /// RESTART written while asleep or within 500 µs of waking.
    pub early_restarts: u32,
    /// Writes to the test-mode register.
    pub testmode_writes: u32,
}

impl Default for Pca9685 {
    fn default() -> Self {
        Self::new()
    }
}

impl Pca9685 {
    /// A chip at power-up.
    pub fn new() -> Pca9685 {
        let mut regs = [0u8; 256];
        regs[MODE1 as usize] = MODE1_RESET;
        regs[MODE2 as usize] = MODE2_RESET;
        regs[SUBADR1 as usize] = 0xE2;
        regs[SUBADR2 as usize] = 0xE4;
        regs[SUBADR3 as usize] = 0xE8;
        regs[ALLCALLADR as usize] = 0xE0;
        for ch in 0..CHANNELS {
            regs[led_on_l(ch) as usize + 3] = FULL;
        }
        regs[PRE_SCALE as usize] = PRE_SCALE_RESET;
        Pca9685 {
            regs,
            pointer: 0,
            now_ns: 0,
            settled_at: 0,
            prescale_writes_ignored: 0,
            early_restarts: 0,
            testmode_writes: 0,
        }
    }

    /// A register's value.
    pub fn reg(&self, r: u8) -> u8 {
        self.regs[r as usize]
    }

    /// Whether the chip sleeps (oscillator off, outputs off).
    pub fn asleep(&self) -> bool {
        self.regs[MODE1 as usize] & MODE1_SLEEP != 0
    }

    /// The PWM frequency, Hz.
    pub fn frequency(&self) -> f64 {
        frequency(self.regs[PRE_SCALE as usize])
    }

    /// Whether MODE2 inverts the outputs.
    pub fn inverted(&self) -> bool {
        self.regs[MODE2 as usize] & MODE2_INVRT != 0
    }

    /// Whether the outputs are totem pole (else open drain).
    pub fn totem_pole(&self) -> bool {
        self.regs[MODE2 as usize] & MODE2_OUTDRV != 0
    }

    /// Channel `ch`'s duty cycle (share of the cycle the output is on)
    /// as the registers program it: 0 while asleep or before the
    /// oscillator settled; full off wins over full on.
    pub fn duty(&self, ch: usize) -> f64 {
        if self.asleep() || self.now_ns < self.settled_at {
            return 0.0;
        }
        let base = led_on_l(ch) as usize;
        let r = &self.regs[base..base + 4];
        if r[3] & FULL != 0 {
            return 0.0;
        }
        if r[1] & FULL != 0 {
            return 1.0;
        }
        let on = r[0] as u16 | ((r[1] as u16 & 0x0F) << 8);
        let off = r[2] as u16 | ((r[3] as u16 & 0x0F) << 8);
        ((off + TICKS - on) % TICKS) as f64 / TICKS as f64
    }

    /// The share of the cycle channel `ch`'s pin is high (the duty,
    /// inverted when MODE2 says so).
    pub fn pin_high(&self, ch: usize) -> f64 {
        let d = self.duty(ch);
        if self.inverted() {
            1.0 - d
        } else {
            d
        }
    }

    /// A power cycle: every register back to its power-up value.
    pub fn power_cycle(&mut self) {
        let now = self.now_ns;
        *self = Pca9685::new();
        self.now_ns = now;
    }

    fn next(&self, p: u8) -> u8 {
        if self.regs[MODE1 as usize] & MODE1_AI == 0 {
            p
        } else if p == led_on_l(CHANNELS - 1) + 3 {
            MODE1
        } else {
            p.wrapping_add(1)
        }
    }

    fn write_reg(&mut self, r: u8, v: u8) {
        match r {
            MODE1 => {
                let old = self.regs[MODE1 as usize];
                let was_asleep = old & MODE1_SLEEP != 0;
                let sleeps = v & MODE1_SLEEP != 0;
                let mut new = v & !MODE1_RESTART;
                if v & MODE1_RESTART != 0 {
                    if sleeps || self.now_ns < self.settled_at {
                        self.early_restarts += 1;
                        new |= old & MODE1_RESTART;
                    }
                } else {
                    new |= old & MODE1_RESTART;
                }
                if was_asleep && !sleeps {
                    self.settled_at = self.now_ns + WAKE_NS;
                }
                if !was_asleep && sleeps {
                    // Going to sleep with the PWM running: the chip
                    // remembers it in RESTART.
                    new |= MODE1_RESTART;
                }
                self.regs[MODE1 as usize] = new;
            }
            PRE_SCALE => {
                if self.asleep() {
                    self.regs[PRE_SCALE as usize] = v;
                } else {
                    self.prescale_writes_ignored += 1;
                }
            }
            ALL_LED_ON_L..=ALL_LED_OFF_H => {
                let k = (r - ALL_LED_ON_L) as usize;
                for ch in 0..CHANNELS {
                    self.regs[led_on_l(ch) as usize + k] = v;
                }
            }
            TESTMODE => self.testmode_writes += 1,
            _ => self.regs[r as usize] = v,
        }
    }

    fn read_reg(&self, r: u8) -> u8 {
        match r {
            // Write-only broadcast registers read as zero.
            ALL_LED_ON_L..=ALL_LED_OFF_H => 0,
            _ => self.regs[r as usize],
        }
    }
}

impl ChipModel for Pca9685 {
    fn write(&mut self, bytes: &[u8]) {
        let Some((&p, data)) = bytes.split_first() else {
            return;
        };
        self.pointer = p;
        for &b in data {
            self.write_reg(self.pointer, b);
            self.pointer = self.next(self.pointer);
        }
    }

    fn read(&mut self, out: &mut [u8]) {
        for b in out {
            *b = self.read_reg(self.pointer);
            self.pointer = self.next(self.pointer);
        }
    }

    fn advance(&mut self, dt_ns: u64) {
        self.now_ns += dt_ns;
    }

    fn describe(&self) -> String {
        "simulated PCA9685".into()
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_up_state() {
        let c = Pca9685::new();
        assert!(c.asleep());
        assert_eq!(c.reg(MODE1), 0x11);
        assert_eq!(c.reg(MODE2), 0x04);
        assert!((c.frequency() - 196.9).abs() < 0.1);
        assert_eq!(c.reg(0x09), 0x10, "LED0_OFF_H full off");
        assert_eq!(c.duty(0), 0.0);
    }

    #[test]
    fn prescale_only_asleep_and_the_oscillator_needs_500us() {
        let mut c = Pca9685::new();
        c.write(&[PRE_SCALE, 121]);
        assert_eq!(c.reg(PRE_SCALE), 121);
        c.write(&[MODE1, MODE1_AI]);
        c.write(&[PRE_SCALE, 3]);
        assert_eq!(c.reg(PRE_SCALE), 121, "ignored while awake");
        assert_eq!(c.prescale_writes_ignored, 1);
        c.write(&[led_on_l(2), 0, 0, 0x00, 0x08]);
        assert_eq!(c.duty(2), 0.0, "oscillator not settled yet");
        c.write(&[MODE1, MODE1_AI | MODE1_RESTART]);
        assert_eq!(c.early_restarts, 1);
        c.advance(WAKE_NS);
        assert_eq!(c.duty(2), 0.5);
    }

    #[test]
    fn auto_increment_broadcast_and_full_on_off() {
        let mut c = Pca9685::new();
        c.write(&[MODE1, MODE1_AI]);
        c.advance(WAKE_NS);
        // Channels 0 and 1 in one transfer.
        c.write(&[led_on_l(0), 0, 0, 0, 0x04, 0, FULL, 0, 0]);
        assert_eq!(c.duty(0), 0.25);
        assert_eq!(c.duty(1), 1.0);
        c.write(&[led_on_l(3), 0x00, 0x0F, 0x00, 0x01]);
        assert_eq!(
            c.duty(3),
            (0x100 + 4096 - 0xF00) as f64 / 4096.0,
            "wraps around"
        );
        c.write(&[ALL_LED_OFF_H, FULL]);
        assert!((0..16).all(|ch| c.duty(ch) == 0.0), "full off wins");
        let mut b = [0u8; 1];
        c.write(&[ALL_LED_OFF_H]);
        c.read(&mut b);
        assert_eq!(b[0], 0, "broadcast registers read zero");
        c.write(&[MODE2, MODE2_INVRT | MODE2_OUTDRV]);
        c.write(&[led_on_l(4), 0, 0, 0, 0x04]);
        assert_eq!(c.pin_high(4), 0.75);
        c.write(&[TESTMODE, 1]);
        assert_eq!(c.testmode_writes, 1);
        // Without AI the pointer stays: both bytes land in MODE2.
        c.write(&[MODE1, 0]);
        c.write(&[MODE2, 0x04, 0x10]);
        assert_eq!(c.reg(MODE2), 0x10);
        assert_eq!(c.reg(SUBADR1), 0xE2);
    }
}
