//! Packet-error accounting of an Ethernet board (hostmot2-more.md 1.7),
//! with LinuxCNC's pins and parameters:
//!
//! | object (`hm2_<b>.<n>.`) | kind | default |
//! |---|---|---|
//! | `packet-read-timeout` | param s32 RW | 80 (% of the period; ≥ 100: ns) |
//! | `packet-error-limit` | param s32 RW | 10 |
//! | `packet-error-increment` | param s32 RW | 2 |
//! | `packet-error-decrement` | param s32 RO | 1 |
//! | `packet-error` | pin bit OUT | TRUE in a cycle with an error |
//! | `packet-error-total` | pin u32 IO | errors so far |
//! | `packet-error-level` | pin s32 OUT | the counter, 0..limit |
//! | `packet-error-exceeded` | pin bit OUT | the counter reached the limit |
//!
//! A detected error (a reply lost, late, short or stale, a write that
//! never arrived) adds `increment` (at least 1) to the counter, clamped
//! to the limit; a clean cycle takes `decrement` (at least 1) away. At
//! the limit the board stops (`io_error`) until the user clears
//! `io_error`, which also zeroes the counter. With the defaults, five
//! errors in a row, or more than one cycle in three lost for a while,
//! stop the board.

use hal_core::{
    HalHost, HostParam, HostPin, Io, Ours, Out, PinFactory, Result as HalResult, Ro, Rw,
};

/// Default `packet-read-timeout`: 80 % of the thread period.
pub const DEFAULT_READ_TIMEOUT: i32 = 80;
/// Default `packet-error-limit`.
pub const DEFAULT_LIMIT: i32 = 10;
/// Default `packet-error-increment`.
pub const DEFAULT_INCREMENT: i32 = 2;
/// Default `packet-error-decrement`.
pub const DEFAULT_DECREMENT: i32 = 1;
/// The shortest read timeout, ns.
pub const MIN_TIMEOUT_NS: u64 = 100_000;

/// The HAL objects.
struct Objects<H: HalHost = Ours> {
    error: H::Pin<bool, Out>,
    total: H::Pin<u32, Io>,
    level: H::Pin<i32, Out>,
    exceeded: H::Pin<bool, Out>,
    read_timeout: H::Param<i32, Rw>,
    limit: H::Param<i32, Rw>,
    increment: H::Param<i32, Rw>,
    decrement: H::Param<i32, Ro>,
}

/// The error counter and its HAL objects (before they exist, the
/// defaults apply).
pub struct PacketErrors<H: HalHost = Ours> {
    counter: i32,
    total: u32,
    objects: Option<Objects<H>>,
}

impl<H: HalHost> Default for PacketErrors<H> {
    fn default() -> Self {
        PacketErrors {
            counter: 0,
            total: 0,
            objects: None,
        }
    }
}

impl<H: HalHost> std::fmt::Debug for PacketErrors<H> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PacketErrors")
            .field("counter", &self.counter)
            .field("total", &self.total)
            .finish()
    }
}

impl<H: HalHost> PacketErrors<H> {
    /// The counter for host `H2`, before any HAL object was made (a
    /// probed board registering in the host it was loaded into).
    pub fn into_host<H2: HalHost>(self) -> PacketErrors<H2> {
        debug_assert!(
            self.objects.is_none(),
            "exported objects stay in their host"
        );
        PacketErrors {
            counter: self.counter,
            total: self.total,
            objects: None,
        }
    }

    /// Exports the pins and params as `<prefix>.packet-*`.
    pub fn export(&mut self, comp: &impl PinFactory<H>, prefix: &str) -> HalResult<()> {
        let n = |s: &str| format!("{prefix}.{s}");
        self.objects = Some(Objects {
            read_timeout: comp.param(&n("packet-read-timeout"), DEFAULT_READ_TIMEOUT)?,
            limit: comp.param(&n("packet-error-limit"), DEFAULT_LIMIT)?,
            increment: comp.param(&n("packet-error-increment"), DEFAULT_INCREMENT)?,
            decrement: comp.param(&n("packet-error-decrement"), DEFAULT_DECREMENT)?,
            error: comp.pin(&n("packet-error"))?,
            total: comp.pin(&n("packet-error-total"))?,
            level: comp.pin(&n("packet-error-level"))?,
            exceeded: comp.pin(&n("packet-error-exceeded"))?,
        });
        Ok(())
    }

    /// `packet-error-limit`.
    pub fn limit(&self) -> i32 {
        self.objects
            .as_ref()
            .map_or(DEFAULT_LIMIT, |o| o.limit.get())
    }

    /// The read timeout for a thread of `period_ns`: `packet-read-timeout`
    /// P ≤ 0 means 80 %, P < 100 is P % of the period, else P ns; never
    /// under 100 µs.
    pub fn timeout_ns(&self, period_ns: i64) -> u64 {
        let p = self
            .objects
            .as_ref()
            .map_or(DEFAULT_READ_TIMEOUT, |o| o.read_timeout.get());
        let p = if p <= 0 { DEFAULT_READ_TIMEOUT } else { p };
        let t = if p < 100 {
            period_ns.max(0) as u64 * p as u64 / 100
        } else {
            p as u64
        };
        t.max(MIN_TIMEOUT_NS)
    }

    /// Counts an error; true when the counter reached the limit (the
    /// board must stop).
    pub fn error(&mut self) -> bool {
        let limit = self.limit();
        let inc = self
            .objects
            .as_ref()
            .map_or(DEFAULT_INCREMENT, |o| o.increment.get())
            .max(1);
        self.counter = self.counter.saturating_add(inc).min(limit.max(0));
        let exceeded = self.counter >= limit;
        match &self.objects {
            Some(o) => {
                self.total = o.total.get().wrapping_add(1);
                o.total.set(self.total);
                o.error.set(true);
                o.level.set(self.counter);
                if exceeded {
                    o.exceeded.set(true);
                }
            }
            None => self.total = self.total.wrapping_add(1),
        }
        exceeded
    }

    /// A cycle without error.
    pub fn clean(&mut self) {
        let dec = self
            .objects
            .as_ref()
            .map_or(DEFAULT_DECREMENT, |o| o.decrement.get())
            .max(1);
        self.counter = self.counter.saturating_sub(dec).max(0);
        if let Some(o) = &self.objects {
            o.error.set(false);
            o.exceeded.set(false);
            o.level.set(self.counter);
        }
    }

    /// Whether the counter is at the limit.
    pub fn exceeded(&self) -> bool {
        self.counter >= self.limit()
    }

    /// The user cleared `io_error`: a counter at the limit starts over.
    pub fn reset(&mut self) {
        if self.exceeded() {
            self.counter = 0;
            if let Some(o) = &self.objects {
                o.level.set(0);
                o.exceeded.set(false);
                o.error.set(false);
            }
        }
    }

    /// The counter.
    pub fn level(&self) -> i32 {
        self.counter
    }

    /// Errors so far.
    pub fn total(&self) -> u32 {
        self.total
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn five_in_a_row_or_one_in_three_stop_the_board() {
        let mut e = PacketErrors::<Ours>::default();
        for k in 1..5 {
            assert!(!e.error(), "error {k}");
        }
        assert!(e.error(), "the fifth reaches 10");
        assert_eq!(e.level(), 10);
        e.reset();
        assert_eq!(e.level(), 0);
        // One in three: +2 -1 -1 per three cycles holds the level.
        for _ in 0..100 {
            assert!(!e.error());
            e.clean();
            e.clean();
        }
        assert_eq!(e.level(), 0);
        // One in two climbs by 1 per two cycles.
        let mut stopped = None;
        for k in 0..100 {
            if e.error() {
                stopped = Some(k);
                break;
            }
            e.clean();
        }
        assert_eq!(stopped, Some(8));
        assert_eq!(e.total(), 114);
    }

    #[test]
    fn timeouts() {
        let e = PacketErrors::<Ours>::default();
        assert_eq!(e.timeout_ns(1_000_000), 800_000);
        assert_eq!(e.timeout_ns(50_000), MIN_TIMEOUT_NS);
        assert_eq!(e.timeout_ns(0), MIN_TIMEOUT_NS);
    }
}
