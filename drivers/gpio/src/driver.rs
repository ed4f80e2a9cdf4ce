//! The read/write/reset algorithm on line requests, independent of HAL
//! pins: the HAL binding gathers output bits from pins, calls this, and
//! publishes input bits.
//!
//! * `read`: one bulk read per input request.
//! * `write`: one bulk write per output request whose bits changed since
//!   the last write (the request starts every output at its inactive
//!   level, so the cache starts at 0), remembering when it wrote.
//! * `reset`: for every output request with a `reset=` line at its active
//!   level, busy-waits until `reset_ns` after that request's last write,
//!   then returns those lines to their inactive level in one bulk write.
//!   With `write` then `reset` in the same thread, a line held TRUE gives
//!   one pulse of `reset_ns` per period, as `parport.N.reset` does.
//! * Values are logical: an inverted output is requested active-low, so
//!   the kernel does the inversion and "inactive" is 0 for every line.
//!
//! The state lives in atomics: `write` and `reset` may run in different
//! threads (LinuxCNC asks for one thread; nothing enforces it).

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::Arc;

use hal_driver::sim::Clock;

use crate::chip::{LineError, LineRequest};
use crate::regs::low_bits;

/// `reset_ns` as `reset` uses it: at most a quarter of the thread's
/// period (truncating like C), as LinuxCNC clamps it.
#[inline]
pub fn clamp_reset(reset_ns: u32, period_ns: i64) -> u32 {
    let quarter = (period_ns / 4).clamp(0, u32::MAX as i64) as u32;
    reset_ns.min(quarter)
}

/// Input lines of one request.
pub struct InputBank {
    req: Box<dyn LineRequest>,
    mask: u64,
}

impl InputBank {
    /// The `lines` lines of `req`.
    pub fn new(req: Box<dyn LineRequest>, lines: usize) -> InputBank {
        InputBank {
            req,
            mask: low_bits(lines),
        }
    }

    /// Reads every line; bit k = line k.
    #[inline]
    pub fn read(&self) -> Result<u64, LineError> {
        self.req.get(self.mask)
    }

    /// The request.
    pub fn request(&self) -> &dyn LineRequest {
        &*self.req
    }
}

/// Output lines of one request.
pub struct OutputBank {
    req: Box<dyn LineRequest>,
    mask: u64,
    reset_mask: u64,
    /// The bits last written (0 after the request: every output starts
    /// inactive).
    cache: AtomicU64,
    /// When they were written (clock ns).
    written_at: AtomicU64,
}

impl OutputBank {
    /// The `lines` lines of `req`, those in `reset_mask` being `reset=`
    /// lines.
    pub fn new(req: Box<dyn LineRequest>, lines: usize, reset_mask: u64) -> OutputBank {
        let mask = low_bits(lines);
        OutputBank {
            req,
            mask,
            reset_mask: reset_mask & mask,
            cache: AtomicU64::new(0),
            written_at: AtomicU64::new(0),
        }
    }

    /// The request.
    pub fn request(&self) -> &dyn LineRequest {
        &*self.req
    }

    /// The bits last written.
    pub fn written(&self) -> u64 {
        self.cache.load(Relaxed)
    }

    /// Drives the lines with `bits` if they differ from the last write.
    #[inline]
    pub fn write(&self, bits: u64, clock: &dyn Clock) -> Result<(), LineError> {
        let bits = bits & self.mask;
        if bits != self.cache.load(Relaxed) {
            self.req.set(bits, self.mask)?;
            self.written_at.store(clock.now_ns(), Relaxed);
            self.cache.store(bits, Relaxed);
        }
        Ok(())
    }

    /// Returns the active `reset=` lines to inactive, no earlier than
    /// `reset_ns` after the last write (busy-waiting on `clock`).
    #[inline]
    pub fn reset(&self, reset_ns: u32, clock: &dyn Clock) -> Result<(), LineError> {
        let cached = self.cache.load(Relaxed);
        let active = cached & self.reset_mask;
        if active == 0 {
            return Ok(());
        }
        let deadline = self.written_at.load(Relaxed).wrapping_add(reset_ns as u64);
        while clock.now_ns() < deadline {
            std::hint::spin_loop();
        }
        self.req.set(0, active)?;
        self.cache.store(cached & !active, Relaxed);
        Ok(())
    }

    /// Every line inactive, written unconditionally; failures are only
    /// counted (the chip may be gone).
    pub fn go_safe(&self) {
        let _ = self.req.set(0, self.mask);
        self.cache.store(0, Relaxed);
    }
}

/// Every request of the driver and its clock.
pub struct Driver {
    /// Input requests.
    pub inputs: Vec<InputBank>,
    /// Output requests.
    pub outputs: Vec<OutputBank>,
    /// Times writes and reset deadlines.
    pub clock: Arc<dyn Clock>,
}

impl Driver {
    /// `hal_gpio.reset` over every output request with the clamped
    /// `reset_ns`; the first failure is returned after all were tried.
    #[inline]
    pub fn reset(&self, reset_ns: u32) -> Result<(), LineError> {
        let mut result = Ok(());
        for bank in &self.outputs {
            if let Err(e) = bank.reset(reset_ns, &*self.clock) {
                result = result.and(Err(e));
            }
        }
        result
    }

    /// Every output inactive.
    pub fn go_safe(&self) {
        for bank in &self.outputs {
            bank.go_safe();
        }
    }

    /// Failed accesses over all requests.
    pub fn errors(&self) -> u64 {
        self.inputs
            .iter()
            .map(|b| b.req.errors())
            .chain(self.outputs.iter().map(|b| b.req.errors()))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cfg::{Bias, Direction, Drive};
    use crate::chip::LineSetting;
    use crate::sim::{LineEvent, SimChip};
    use hal_driver::sim::SimClock;

    fn out(offset: u32, active_low: bool) -> LineSetting {
        LineSetting {
            offset,
            direction: Direction::Output,
            active_low,
            drive: Drive::PushPull,
            bias: Bias::AsIs,
        }
    }

    /// A chip with 4 outputs (line 1 inverted), lines 2 and 3 reset
    /// lines, on a clock that steps 10 ns per reading.
    fn rig() -> (OutputBank, Arc<SimChip>, Arc<SimClock>) {
        let clock = Arc::new(SimClock::new(1_000, 10));
        let chip = Arc::new(SimChip::new(
            "gpiochip0",
            "t",
            &["A", "B", "C", "D"],
            clock.clone(),
        ));
        let req = chip
            .request(
                &[out(0, false), out(1, true), out(2, false), out(3, true)],
                "t",
            )
            .unwrap();
        chip.clear_events();
        (OutputBank::new(Box::new(req), 4, 0b1100), chip, clock)
    }

    #[test]
    fn clamp_is_a_quarter_period_truncated() {
        assert_eq!(clamp_reset(30_000, 100_000), 25_000);
        assert_eq!(clamp_reset(5_000, 100_000), 5_000);
        assert_eq!(clamp_reset(u32::MAX, 50_003), 12_500);
        assert_eq!(clamp_reset(7, 3), 0);
        assert_eq!(clamp_reset(7, -5), 0);
        assert_eq!(clamp_reset(7, i64::MAX), 7);
    }

    #[test]
    fn write_only_on_change_and_inversion_by_the_kernel() {
        let (b, chip, _) = rig();
        b.write(0, &*Arc::new(SimClock::new(0, 0))).unwrap();
        assert_eq!(chip.sets(), 0, "outputs start inactive: nothing to write");
        assert_eq!(
            (0..4).map(|o| chip.level(o)).collect::<Vec<_>>(),
            [false, true, false, true],
            "inverted lines sit high from the request on"
        );
        let c = SimClock::new(0, 0);
        b.write(0b0011, &c).unwrap();
        b.write(0b0011, &c).unwrap();
        assert_eq!(chip.sets(), 1);
        assert_eq!(
            (0..4).map(|o| chip.level(o)).collect::<Vec<_>>(),
            [true, false, false, true]
        );
        b.go_safe();
        assert_eq!(
            (0..4).map(|o| chip.level(o)).collect::<Vec<_>>(),
            [false, true, false, true]
        );
        assert_eq!(b.written(), 0);
    }

    #[test]
    fn reset_makes_one_pulse_of_reset_ns_per_write() {
        let (b, chip, clock) = rig();
        let c: &dyn Clock = &*clock;
        // Three periods of 100 us: write all four TRUE, then reset.
        for period in 0..3u64 {
            let start = 1_000 + period * 100_000;
            while clock.peek() < start {
                clock.advance(start - clock.peek());
            }
            b.write(0b1111, c).unwrap();
            b.reset(clamp_reset(5_000, 100_000), c).unwrap();
        }
        // Line 2 (plain): rises at each write, falls 5 us later.
        let ev = chip.events_of(2);
        assert_eq!(ev.len(), 6, "{ev:?}");
        for p in 0..3 {
            let (rise, fall) = (ev[2 * p], ev[2 * p + 1]);
            assert!(rise.level && !fall.level);
            let width = fall.time_ns - rise.time_ns;
            assert!((5_000..5_100).contains(&width), "pulse {p}: {width} ns");
        }
        // Line 3 (inverted reset line): the same pulses, electrically low.
        let ev = chip.events_of(3);
        assert_eq!(ev.len(), 6);
        assert!(!ev[0].level && ev[1].level);
        // Lines 0 and 1 are not reset lines: they stay active.
        assert_eq!(
            chip.events_of(0),
            vec![LineEvent {
                time_ns: chip.events_of(0)[0].time_ns,
                offset: 0,
                level: true
            }]
        );
        assert_eq!(b.written(), 0b0011);
        // Two bulk writes per period (write, reset), none more.
        assert_eq!(chip.sets(), 6);
    }

    #[test]
    fn reset_with_nothing_active_writes_nothing_and_waits_for_nothing() {
        let (b, chip, clock) = rig();
        let c: &dyn Clock = &*clock;
        b.write(0b0001, c).unwrap();
        let t = clock.peek();
        b.reset(1_000_000, c).unwrap();
        assert_eq!(clock.peek(), t, "no busy-wait");
        assert_eq!(chip.sets(), 1);
    }

    #[test]
    fn failures_reach_the_caller_and_are_counted() {
        let (b, chip, clock) = rig();
        let c: &dyn Clock = &*clock;
        chip.remove();
        assert_eq!(b.write(1, c), Err(LineError(libc::ENODEV)));
        assert_eq!(b.written(), 0, "a failed write changes nothing");
        b.go_safe();
        assert_eq!(b.request().errors(), 2);
    }
}
