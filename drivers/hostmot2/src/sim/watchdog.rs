//! Simulated watchdog (hardware.md 5.9.2): the timer counts ClockLow
//! ticks down while bit 31 is clear; when it passes zero it sets bit 31
//! and the has-bitten status, and the board releases every pin. Writing
//! the timer loads it; writing 0x5A in the cookie register's top byte
//! reloads the last timeout written.

use crate::regs::watchdog as r;

/// The watchdog registers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SimWatchdog {
    /// Timer: ticks left, bit 31 = disabled.
    pub timer: u32,
    /// The last value written to the timer.
    pub reload: u32,
    /// Status: bit 0 = has bitten.
    pub status: u32,
}

impl Default for SimWatchdog {
    fn default() -> Self {
        SimWatchdog {
            timer: r::TIMER_DISABLED,
            reload: r::TIMER_DISABLED,
            status: 0,
        }
    }
}

impl SimWatchdog {
    /// A register read.
    pub fn read(&self, reg: usize) -> u32 {
        match reg {
            r::TIMER => self.timer,
            r::STATUS => self.status,
            _ => 0,
        }
    }

    /// A register write.
    pub fn write(&mut self, reg: usize, v: u32) {
        match reg {
            r::TIMER => {
                self.timer = v;
                self.reload = v;
            }
            r::STATUS => self.status = v & r::STATUS_HAS_BIT,
            r::COOKIE_REG if v >> 24 == 0x5A => self.timer = self.reload,
            _ => {}
        }
    }

    /// Counts `ticks` of ClockLow; returns true when it bites.
    pub fn advance(&mut self, ticks: u64) -> bool {
        if self.timer & r::TIMER_DISABLED != 0 {
            return false;
        }
        // The timer value v bites after v + 1 ticks.
        if ticks > self.timer as u64 {
            self.timer = r::TIMER_DISABLED;
            self.status |= r::STATUS_HAS_BIT;
            true
        } else {
            self.timer -= ticks as u32;
            false
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bites_after_value_plus_one_ticks_unless_petted() {
        let mut w = SimWatchdog::default();
        assert!(!w.advance(1 << 40), "disabled at power-up");
        w.write(r::TIMER, 99);
        assert!(!w.advance(99));
        w.write(r::COOKIE_REG, r::PET);
        assert!(!w.advance(60));
        w.write(r::COOKIE_REG, 0x1200_0000); // not a pet
        assert!(!w.advance(39));
        assert!(w.advance(1), "bites on tick 100 after the pet");
        assert_eq!(w.read(r::STATUS), 1);
        assert!(!w.advance(1000), "stays bitten, disabled");
        w.write(r::STATUS, 0);
        assert_eq!(w.read(r::STATUS), 0);
    }
}
