//! Watchdog (hardware.md 5.9.2): `watchdog.has_bit` (bit IO) and
//! `watchdog.timeout_ns` (u32 RW, 5 ms).
//!
//! Asleep until the first `write`, which arms it with `timeout_ns`; every
//! `write` pets it through TRAM. When `write` stops for longer than the
//! timeout, the firmware bites: every I/O pin becomes an input (pulled
//! high), so nothing is driven. `read` then sets `has_bit` and says so
//! once; clearing `has_bit` makes the next `write` rewrite the board's
//! whole configuration and re-arm the watchdog.

use hal_core::{HalHost, HostParam, HostPin, Io, Ours, PinFactory, Result as HalResult, Rw};

use crate::firmware::ModuleUse;
use crate::log::Level;
use crate::md::ModuleDescriptor;
use crate::modules::{put, Export, Notify};
use crate::regs::watchdog as r;
use crate::tram::Slot;
use crate::transport::{Transport, TransportError};

/// Default timeout, ns.
pub const DEFAULT_TIMEOUT_NS: u32 = 5_000_000;

/// The timer value for a timeout: ticks of `clock` minus one, at most
/// 0x7FFFFFFF (bit 31 disables the watchdog), and the timeout that value
/// really gives when it had to be clamped.
pub fn timer_value(timeout_ns: u32, clock: u32) -> (u32, Option<u32>) {
    let ticks = (timeout_ns as u64 * clock as u64 / 1_000_000_000).max(1);
    let value = ticks - 1;
    if value >= r::TIMER_DISABLED as u64 {
        let max = r::TIMER_DISABLED - 1;
        let ns = ((max as u64 + 1) * 1_000_000_000 / clock as u64).min(u32::MAX as u64);
        (max, Some(ns as u32))
    } else {
        (value as u32, None)
    }
}

/// The watchdog module.
pub struct Watchdog<H: HalHost = Ours> {
    md: ModuleDescriptor,
    status_read: Slot,
    pet_write: Slot,
    has_bit: H::Pin<bool, Io>,
    timeout_ns: H::Param<u32, Rw>,
    /// The timeout the timer was last armed with (`None`: not armed).
    armed: Option<u32>,
    /// A bite was seen and reported; cleared when the user resets.
    bitten: bool,
    warned_period: Option<(u32, i64)>,
}

/// What `read` found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WatchdogEvent {
    /// Nothing new.
    Quiet,
    /// The watchdog bit since the last read.
    Bit,
}

impl<H: HalHost> Watchdog<H> {
    /// Exports the pin and param and registers the status read and the pet.
    pub fn export<F: PinFactory<H>>(
        x: &mut Export<'_, F>,
        m: &ModuleUse,
    ) -> HalResult<Watchdog<H>> {
        let has_bit = x.comp.pin(&x.name("watchdog.has_bit"))?;
        let timeout_ns = x
            .comp
            .param(&x.name("watchdog.timeout_ns"), DEFAULT_TIMEOUT_NS)?;
        let status_read = x.tram.add_read(m.md.reg(r::STATUS), 1);
        let pet_write = x.tram.add_write(m.md.reg(r::COOKIE_REG), 1);
        Ok(Watchdog {
            md: m.md,
            status_read,
            pet_write,
            has_bit,
            timeout_ns,
            armed: None,
            bitten: false,
            warned_period: None,
        })
    }

    /// At load: disabled, status cleared.
    pub fn force_write(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        put(t, self.md.reg(r::TIMER), r::TIMER_DISABLED)?;
        put(t, self.md.reg(r::STATUS), 0)?;
        self.armed = None;
        Ok(())
    }

    /// Looks at the status word.
    #[inline]
    pub fn process_read(&mut self, buf: &[u32], say: &Notify) -> WatchdogEvent {
        let status = self.status_read.of(buf)[0];
        if status & r::STATUS_HAS_BIT != 0 && !self.bitten {
            self.bitten = true;
            self.has_bit.set(true);
            say.say(
                Level::Err,
                format_args!("Watchdog has bit! (set the .has_bit pin to False to resume)"),
            );
            return WatchdogEvent::Bit;
        }
        WatchdogEvent::Quiet
    }

    /// Whether the user cleared `has_bit` after a bite: the board must be
    /// reconfigured before it may drive anything again.
    #[inline]
    pub fn wants_recovery(&self) -> bool {
        self.bitten && !self.has_bit.get()
    }

    /// Forgets the bite (the caller rewrites the configuration).
    pub fn recovered(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        self.bitten = false;
        self.armed = None;
        put(t, self.md.reg(r::STATUS), 0)
    }

    /// Pets, through TRAM.
    #[inline]
    pub fn prepare_write(&self, buf: &mut [u32]) {
        self.pet_write.of_mut(buf)[0] = r::PET;
    }

    /// Arms the timer at the first write and after a change of
    /// `timeout_ns`; does nothing while `has_bit` is set.
    pub fn write_config(
        &mut self,
        t: &mut dyn Transport,
        period_ns: i64,
        say: &Notify,
    ) -> Result<(), TransportError> {
        if self.has_bit.get() {
            return Ok(());
        }
        let timeout = self.timeout_ns.get();
        if self.armed != Some(timeout) {
            let (value, clamped) = timer_value(timeout, self.md.clock_hz);
            let timeout = match clamped {
                Some(ns) => {
                    self.timeout_ns.set(ns);
                    say.say(
                        Level::Err,
                        format_args!(
                            "watchdog timeout_ns too long, clamped to the longest the board can do"
                        ),
                    );
                    ns
                }
                None => timeout,
            };
            put(t, self.md.reg(r::TIMER), value)?;
            put(t, self.md.reg(r::STATUS), 0)?;
            self.armed = Some(timeout);
        }
        if period_ns > 0
            && (timeout as f64) < 1.5 * period_ns as f64
            && self.warned_period != Some((timeout, period_ns))
        {
            self.warned_period = Some((timeout, period_ns));
            say.say(Level::Warn, format_args!("Watchdog timeout is less than 1.5 times the thread period: it will probably bite"));
        }
        Ok(())
    }

    /// Pets the watchdog outside TRAM (`pet_watchdog`): nothing while
    /// `has_bit` is set or before the first `write` armed it.
    pub fn pet_now(&self, t: &mut dyn Transport) -> Result<(), TransportError> {
        if self.has_bit.get() || self.armed.is_none() {
            return Ok(());
        }
        t.write(self.md.reg(r::COOKIE_REG), &[r::PET])
    }

    /// Makes the watchdog bite at once (unload and safe state): the
    /// firmware then stops driving every pin.
    pub fn bite_now(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        self.armed = None;
        t.write(self.md.reg(r::TIMER), &[0])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timer_values() {
        assert_eq!(timer_value(5_000_000, 100_000_000), (499_999, None));
        assert_eq!(timer_value(0, 100_000_000), (0, None));
        let (v, clamped) = timer_value(u32::MAX, 1_000_000_000);
        assert_eq!(v, 0x7FFF_FFFF);
        assert_eq!(clamped, Some(2_147_483_648));
    }
}
