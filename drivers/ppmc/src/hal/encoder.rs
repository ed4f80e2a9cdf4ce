//! The four counters of an encoder board, USC or UPC: LinuxCNC's
//! `ppmc.<bus>.encoder.<n>.*` pins, and their arithmetic.
//!
//! The board's counters are 24 bits wide; each reading is extended to 32
//! bits by the signed 24-bit step from the previous one, so `count` does
//! not wrap at ±2^23. With `index-enable` TRUE the driver arms the
//! board's clear-on-index bit; the board then clears the counter at the
//! next index pulse and flags it. A flagged index on an armed counter is
//! taken as the clear when the new reading is nearer zero than to the
//! previous count (the pulse may have come just before the arm reached
//! the board, when it flags the index without clearing); `index-enable`
//! then goes FALSE and `count` restarts from the counts made since the
//! pulse.
//!
//! `velocity` is the counts moved this period over the period. With
//! timestamps (`timestamp=`, encoder board or UPC revision 4 and later)
//! it is the counts moved over the time between the board's last two
//! counts instead; while nothing counts, at most one count over the time
//! since the last one, 0 once that falls below `min-speed-estimate` or
//! after 65.5 ms; and 0 in the period a counter reverses.

use canonical::{usable_scale, ChannelNames};
use hal_core::{HalHost, HostParam, HostPin, Io, Out, PinFactory, Result, Rw};

use crate::regs::{enc, get_le, SPAN};

/// One counter's pins and params.
struct Channel<H: HalHost> {
    position: H::Pin<f64, Out>,
    count: H::Pin<i32, Out>,
    delta: H::Pin<i32, Out>,
    index: H::Pin<bool, Out>,
    velocity: H::Pin<f64, Out>,
    index_enable: Option<H::Pin<bool, Io>>,
    scale: H::Param<f64, Rw>,
    min_speed: Option<H::Param<f64, Rw>>,
    st: State,
}

/// One counter's arithmetic state.
#[derive(Debug, Clone, Copy, Default)]
struct State {
    count: i32,
    last_raw: u32,
    prevdir: i8,
    stamp: u16,
    counts_since_timeout: u32,
    velocity: f64,
}

/// The signed value of a 24-bit field.
#[inline]
pub fn sext24(v: u32) -> i32 {
    ((v << 8) as i32) >> 8
}

/// A board's four counters.
pub struct Encoders<H: HalHost> {
    ch: Vec<Channel<H>>,
    timestamps: bool,
    /// The clear-on-index bits last written to the board.
    armed: u8,
}

impl<H: HalHost> Encoders<H> {
    /// Exports counters `first..first + 4` of bus `bus`; `index`: the
    /// board takes `index-enable`; `timestamps`: velocity from the
    /// board's timestamps (and `min-speed-estimate`).
    pub fn export(
        c: &impl PinFactory<H>,
        bus: usize,
        first: usize,
        index: bool,
        timestamps: bool,
    ) -> Result<Encoders<H>> {
        let names =
            ChannelNames::custom(move |n, item| format!("ppmc.{bus}.encoder.{n:02}.{item}"));
        let ch = (first..first + 4)
            .map(|n| {
                let name = |item: &str| names.item(n, item);
                Ok(Channel {
                    scale: c.param(&name("scale"), 1.0)?,
                    position: c.pin(&name("position"))?,
                    count: c.pin(&name("count"))?,
                    delta: c.pin(&name("delta"))?,
                    index: c.pin(&name("index"))?,
                    velocity: c.pin(&name("velocity"))?,
                    index_enable: if index {
                        Some(c.pin(&name("index-enable"))?)
                    } else {
                        None
                    },
                    min_speed: if index && timestamps {
                        Some(c.param(&name("min-speed-estimate"), 0.0)?)
                    } else {
                        None
                    },
                    st: State::default(),
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Encoders {
            ch,
            timestamps,
            armed: 0,
        })
    }

    /// Takes the first reading as every counter's zero reference (the
    /// counters were just cleared).
    pub fn prime(&mut self, rd: &[u8; SPAN]) {
        for (i, ch) in self.ch.iter_mut().enumerate() {
            let raw = get_le(rd, enc::COUNT0 + enc::COUNT_BYTES * i as u8, 3);
            ch.st.last_raw = raw;
            ch.st.count = sext24(raw);
            ch.st.stamp = get_le(rd, enc::TS0 + 2 * i as u8, 2) as u16;
        }
    }

    /// Publishes the registers read (`rd`) of a period of `period_s`.
    pub fn read(&mut self, rd: &[u8; SPAN], period_s: f64) {
        let isr = rd[enc::ISR as usize];
        let timebase = get_le(rd, enc::TB, 2) as u16;
        for (i, ch) in self.ch.iter_mut().enumerate() {
            let raw = get_le(rd, enc::COUNT0 + enc::COUNT_BYTES * i as u8, 3);
            let seen = isr & (1 << i) != 0;
            ch.index.set(seen);
            let step = sext24(raw.wrapping_sub(ch.st.last_raw) & 0xFF_FFFF);
            let mut count = ch.st.count.wrapping_add(step);
            let mut cleared = false;
            if seen && self.armed & (1 << i) != 0 {
                let since = sext24(raw);
                if since.unsigned_abs() <= step.unsigned_abs() {
                    cleared = true;
                    count = since;
                    if let Some(p) = &ch.index_enable {
                        p.set(false);
                    }
                }
            }
            let delta = count.wrapping_sub(ch.st.count);
            ch.st.last_raw = raw;
            ch.st.count = count;
            let scale = usable_scale(&ch.scale);
            ch.count.set(count);
            ch.delta.set(delta);
            ch.position.set(count as f64 / scale);
            if !cleared {
                let plain = if period_s > 0.0 {
                    delta as f64 / (period_s * scale)
                } else {
                    0.0
                };
                ch.st.velocity = if self.timestamps {
                    let stamp = get_le(rd, enc::TS0 + 2 * i as u8, 2) as u16;
                    let min = ch.min_speed.as_ref().map_or(0.0, |p| p.get());
                    stamped_velocity(&mut ch.st, delta, stamp, timebase, plain, scale, min)
                } else {
                    plain
                };
            }
            if delta > 0 {
                ch.st.prevdir = 1;
            } else if delta < 0 {
                ch.st.prevdir = -1;
            }
            ch.velocity.set(ch.st.velocity);
        }
    }

    /// The clear-on-index bits to write: the counters whose
    /// `index-enable` is TRUE.
    pub fn index_bits(&mut self) -> u8 {
        self.armed = self
            .ch
            .iter()
            .enumerate()
            .filter(|(_, c)| c.index_enable.as_ref().is_some_and(|p| p.get()))
            .fold(0, |m, (i, _)| m | 1 << i);
        self.armed
    }
}

/// The velocity from the board's timestamps (microsecond ticks, 16 bits).
fn stamped_velocity(
    st: &mut State,
    delta: i32,
    stamp: u16,
    timebase: u16,
    plain: f64,
    scale: f64,
    min_speed: f64,
) -> f64 {
    let tick = 1.0 / enc::TIMEBASE_HZ;
    let old = std::mem::replace(&mut st.stamp, stamp);
    if delta != 0 {
        let dt = stamp.wrapping_sub(old);
        let reversed = (st.prevdir > 0 && delta < 0) || (st.prevdir < 0 && delta > 0);
        let v = if st.counts_since_timeout < 2 || dt == 0 {
            st.counts_since_timeout += 1;
            plain
        } else {
            delta as f64 / (dt as f64 * tick * scale)
        };
        return if reversed { 0.0 } else { v };
    }
    if st.counts_since_timeout == 0 {
        return 0.0;
    }
    let waited = timebase.wrapping_sub(stamp);
    if waited >= 65500 {
        st.counts_since_timeout = 0;
        return 0.0;
    }
    let bound = 1.0 / (scale.abs() * waited.max(1) as f64 * tick);
    if bound < min_speed {
        st.counts_since_timeout = 0;
        return 0.0;
    }
    if st.velocity.abs() > bound {
        bound.copysign(st.velocity)
    } else {
        st.velocity
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sign_extension() {
        assert_eq!(sext24(0xFF_FFFF), -1);
        assert_eq!(sext24(0x7F_FFFF), 0x7F_FFFF);
        assert_eq!(sext24(0x80_0000), -0x80_0000);
    }

    #[test]
    fn stamped_velocity_follows_the_time_between_counts() {
        let mut st = State {
            counts_since_timeout: 2,
            prevdir: 1,
            velocity: 0.0,
            ..State::default()
        };
        st.stamp = 1000;
        // 5 counts over 500 us at scale 1: 10000 counts/s.
        let v = stamped_velocity(&mut st, 5, 1500, 1600, 5000.0, 1.0, 0.0);
        assert!((v - 10_000.0).abs() < 1e-9, "{v}");
        st.velocity = v;
        // Nothing for 2000 us: at most one count over that.
        let v = stamped_velocity(&mut st, 0, 1500, 3500, 0.0, 1.0, 0.0);
        assert!((v - 500.0).abs() < 1e-9, "{v}");
        st.velocity = v;
        // Below min-speed-estimate: 0.
        let v = stamped_velocity(&mut st, 0, 1500, 3500, 0.0, 1.0, 600.0);
        assert_eq!(v, 0.0);
        // A reversal reads 0.
        st.counts_since_timeout = 3;
        let v = stamped_velocity(&mut st, -1, 1600, 1700, -1000.0, 1.0, 0.0);
        assert_eq!(v, 0.0);
    }
}
