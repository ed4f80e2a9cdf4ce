//! The canonical encoder, for drivers with hardware counters (stg,
//! motenc, hostmot2): a narrow wrapping hardware count becomes a 64-bit
//! count; `reset` and the index-enable handshake move its zero; position
//! and velocity follow.
//!
//! | name | kind | type | dir | unit | meaning |
//! |---|---|---|---|---|---|
//! | `count` | pin | s32 | out | counts | counts since reset or index (low 32 bits) |
//! | `rawcounts` | pin | s32 | out | counts | counts since load, never zeroed (low 32 bits) |
//! | `position` | pin | float | out | user units | `count / scale`, from the full 64-bit count |
//! | `position-latched` | pin | float | out | user units | position where the last index fired |
//! | `velocity` | pin | float | out | units/s | estimated velocity |
//! | `velocity-rpm` | pin | float | out | units/min | `velocity * 60` |
//! | `reset` | pin | bit | in | | while TRUE, count and position are 0 |
//! | `index-enable` | pin | bit | io | | set TRUE to zero the count at the next index; cleared when it happens |
//! | `scale` | param | float | rw | counts/unit | default 1.0; a value within 1e-20 of 0 is replaced by 1.0 ([`usable_scale`]) |
//! | `vel-timeout` | param | float | rw | s | no count for this long: velocity 0 (default 0.5) |
//!
//! Velocity comes from the time between counts, not counts per period, so
//! it stays smooth at a few counts per second: when the count changes,
//! velocity = counts moved / time since the previous change; while it does
//! not, velocity is at most one count / time waited (it falls as 1/t,
//! keeping its sign), and 0 after `vel-timeout`.

use hal_core::{HalHost, HostParam, HostPin, In, Io, Ours, Out, PinFactory, Result, Rw};

use crate::naming::{ChannelNames, Interface};
use crate::usable_scale;

/// The encoder's arithmetic, independent of pins.
#[derive(Debug, Clone)]
pub struct EncoderCore {
    bits: u32,
    last_hw: u64,
    /// Counts since load, extended to 64 bits.
    raw: i64,
    /// `raw` value that `count` is measured from.
    zero: i64,
    last_change_raw: i64,
    /// When the count last changed; `None` before the first reading.
    last_change_ns: Option<u64>,
    velocity: f64,
}

/// What one update produced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EncoderOutputs {
    /// Counts since the last reset or index, for the `count` pin.
    pub count: i64,
    /// Counts since load, never zeroed, for the `rawcounts` pin.
    pub rawcounts: i64,
    /// Counts (relative to zero) where the index fired in this update.
    pub index_count: Option<i64>,
    /// Counts per second.
    pub velocity: f64,
}

impl EncoderCore {
    /// An encoder whose hardware counter is `bits` wide (1 to 64).
    pub fn new(bits: u32) -> EncoderCore {
        EncoderCore {
            bits: bits.clamp(1, 64),
            last_hw: 0,
            raw: 0,
            zero: 0,
            last_change_raw: 0,
            last_change_ns: None,
            velocity: 0.0,
        }
    }

    /// The signed distance from the last hardware value to `hw`.
    fn delta(&self, hw: u64) -> i64 {
        let shift = 64 - self.bits;
        ((hw.wrapping_sub(self.last_hw) << shift) as i64) >> shift
    }

    /// One update: `hw` is the hardware counter, `index_hw` the counter
    /// value latched at an index pulse since the last update (if the
    /// hardware saw one and index-enable was armed), `now_ns` the time of
    /// the reading, `reset` the reset pin, `vel_timeout_ns` the timeout.
    pub fn update(
        &mut self,
        hw: u64,
        index_hw: Option<u64>,
        now_ns: u64,
        reset: bool,
        vel_timeout_ns: u64,
    ) -> EncoderOutputs {
        if self.last_change_ns.is_none() {
            // The first reading defines zero.
            self.last_hw = hw;
            self.last_change_ns = Some(now_ns);
        }
        let moved = self.delta(hw);
        let index_raw = index_hw.map(|i| self.raw + self.delta(i));
        self.raw = self.raw.wrapping_add(moved);
        self.last_hw = hw;
        let mut index_count = None;
        if let Some(i) = index_raw {
            index_count = Some(i - self.zero);
            self.zero = i;
        }
        if reset {
            self.zero = self.raw;
        }
        self.velocity = self.estimate(now_ns, vel_timeout_ns);
        EncoderOutputs {
            count: self.raw - self.zero,
            rawcounts: self.raw,
            index_count,
            velocity: self.velocity,
        }
    }

    fn estimate(&mut self, now_ns: u64, timeout_ns: u64) -> f64 {
        let since = self.last_change_ns.unwrap_or(now_ns);
        let dt = now_ns.saturating_sub(since);
        let moved = self.raw - self.last_change_raw;
        if moved != 0 {
            if dt == 0 {
                // No time has passed: keep these counts for the next
                // update's interval rather than losing them.
                return self.velocity;
            }
            self.last_change_raw = self.raw;
            self.last_change_ns = Some(now_ns);
            return moved as f64 * 1e9 / dt as f64;
        }
        if dt >= timeout_ns {
            return 0.0;
        }
        // No count yet: the speed is at most one count over the wait.
        let bound = 1e9 / dt.max(1) as f64;
        if self.velocity.abs() > bound {
            bound.copysign(self.velocity)
        } else {
            self.velocity
        }
    }
}

/// A canonical encoder channel: the core plus its pins and params.
pub struct Encoder<H: HalHost = Ours> {
    core: EncoderCore,
    count: H::Pin<i32, Out>,
    rawcounts: H::Pin<i32, Out>,
    position: H::Pin<f64, Out>,
    position_latched: H::Pin<f64, Out>,
    velocity: H::Pin<f64, Out>,
    velocity_rpm: H::Pin<f64, Out>,
    reset: H::Pin<bool, In>,
    index_enable: H::Pin<bool, Io>,
    scale: H::Param<f64, Rw>,
    vel_timeout: H::Param<f64, Rw>,
}

impl Interface for Encoder {
    const IO_TYPE: &'static str = "encoder";
}

impl<H: HalHost> Encoder<H> {
    /// Exports channel `chan` on `comp` for a `bits`-wide counter.
    pub fn export(
        comp: &impl PinFactory<H>,
        names: &ChannelNames,
        chan: usize,
        bits: u32,
    ) -> Result<Self> {
        let n = |s: &str| names.item(chan, s);
        Ok(Encoder {
            core: EncoderCore::new(bits),
            count: comp.pin(&n("count"))?,
            rawcounts: comp.pin(&n("rawcounts"))?,
            position: comp.pin(&n("position"))?,
            position_latched: comp.pin(&n("position-latched"))?,
            velocity: comp.pin(&n("velocity"))?,
            velocity_rpm: comp.pin(&n("velocity-rpm"))?,
            reset: comp.pin(&n("reset"))?,
            index_enable: comp.pin(&n("index-enable"))?,
            scale: comp.param(&n("scale"), 1.0)?,
            vel_timeout: comp.param(&n("vel-timeout"), 0.5)?,
        })
    }

    /// Whether the driver should arm its hardware index latch.
    #[inline]
    pub fn index_armed(&self) -> bool {
        self.index_enable.get()
    }

    /// Publishes a reading; `index_hw` is the latched counter value if the
    /// hardware saw an index while armed.
    pub fn update(&mut self, hw: u64, index_hw: Option<u64>, now_ns: u64) {
        let scale = usable_scale(&self.scale);
        let timeout = self.vel_timeout.get();
        let timeout_ns = if timeout > 0.0 {
            (timeout * 1e9).min(u64::MAX as f64) as u64
        } else {
            0
        };
        let index_hw = index_hw.filter(|_| self.index_enable.get());
        let out = self
            .core
            .update(hw, index_hw, now_ns, self.reset.get(), timeout_ns);
        if let Some(at) = out.index_count {
            self.index_enable.set(false);
            self.position_latched.set(at as f64 / scale);
        }
        self.count.set(out.count as i32);
        self.rawcounts.set(out.rawcounts as i32);
        self.position.set(out.count as f64 / scale);
        let v = out.velocity / scale;
        self.velocity.set(v);
        self.velocity_rpm.set(v * 60.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: u64 = 1_000_000;
    const TIMEOUT: u64 = 500 * MS;

    #[test]
    fn a_narrow_counter_extends_across_wraps() {
        let mut e = EncoderCore::new(16);
        e.update(65530, None, 0, false, TIMEOUT);
        let o = e.update(4, None, MS, false, TIMEOUT); // +10 across the wrap
        assert_eq!(o.count, 10);
        let o = e.update(65000, None, 2 * MS, false, TIMEOUT); // -540
        assert_eq!(o.count, -530);
        // Many turns forward, 30000 counts at a time.
        let mut hw = 65000u64;
        let mut t = 2 * MS;
        for _ in 0..10 {
            hw = (hw + 30000) & 0xffff;
            t += MS;
            e.update(hw, None, t, false, TIMEOUT);
        }
        assert_eq!(
            e.update(hw, None, t + MS, false, TIMEOUT).count,
            -530 + 300_000
        );
    }

    #[test]
    fn reset_and_index_move_the_zero() {
        let mut e = EncoderCore::new(32);
        e.update(100, None, 0, false, TIMEOUT);
        assert_eq!(e.update(150, None, MS, false, TIMEOUT).count, 50);
        assert_eq!(e.update(160, None, 2 * MS, true, TIMEOUT).count, 0, "reset");
        assert_eq!(e.update(170, None, 3 * MS, false, TIMEOUT).count, 10);
        // Index latched at hw 175, we read 180.
        let o = e.update(180, Some(175), 4 * MS, false, TIMEOUT);
        assert_eq!(o.index_count, Some(15));
        assert_eq!(o.count, 5);
        assert_eq!(o.rawcounts, 80);
    }

    #[test]
    fn velocity_from_time_between_counts() {
        let mut e = EncoderCore::new(32);
        e.update(0, None, 0, false, TIMEOUT);
        // One count every 10 ms: 100 counts/s although most reads see none.
        let mut last = 0.0;
        for k in 1..=50u64 {
            for j in 0..10 {
                let t = (k - 1) * 10 * MS + j * MS + MS;
                last = e
                    .update(k - 1 + (j == 9) as u64, None, t, false, TIMEOUT)
                    .velocity;
            }
        }
        assert!((last - 100.0).abs() < 1e-6, "{last}");
        // Stopped: bounded by one count over the wait, then 0.
        let v = e
            .update(50, None, 500 * MS + 100 * MS, false, TIMEOUT)
            .velocity;
        assert!(v > 0.0 && v <= 10.0 + 1e-9, "{v}");
        assert_eq!(
            e.update(50, None, 500 * MS + 600 * MS, false, TIMEOUT)
                .velocity,
            0.0
        );
    }

    #[test]
    fn counts_in_an_update_without_time_are_kept() {
        let mut e = EncoderCore::new(32);
        e.update(0, None, 0, false, TIMEOUT);
        e.update(10, None, MS, false, TIMEOUT);
        e.update(20, None, MS, false, TIMEOUT); // same instant
        let v = e.update(30, None, 2 * MS, false, TIMEOUT).velocity;
        assert!((v - 20_000.0).abs() < 1e-6, "20 counts over 1 ms: {v}");
    }

    #[test]
    fn velocity_keeps_its_sign_while_slowing() {
        let mut e = EncoderCore::new(32);
        e.update(1000, None, 0, false, TIMEOUT);
        e.update(990, None, MS, false, TIMEOUT);
        let v = e.update(990, None, 50 * MS, false, TIMEOUT).velocity;
        assert!(v < 0.0 && v >= -1e9 / (49.0 * MS as f64) - 1e-9, "{v}");
    }
}
