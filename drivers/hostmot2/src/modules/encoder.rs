//! Encoder (hardware.md 5.9.3): hardware quadrature counters.
//!
//! The count arithmetic is the canonical encoder's
//! ([`canonical::EncoderCore`]: the 16-bit counter extended to 64 bits,
//! `reset`, the index zeroing, velocity from the time between counts) with
//! its pins under the canonical names (`count`, `rawcounts`, `position`,
//! `position-latched`, `velocity`, `velocity-rpm`, `reset`,
//! `index-enable`, `scale`, `vel-timeout`). The time base is the board's:
//! each count carries the timestamp counter's value when it happened, so
//! velocity is measured between real edges, not between reads.
//!
//! hostmot2's extras: `rawlatch`, `count-latched`,
//! `position-interpolated`, `no_clear_on_index` (latch at the index
//! without zeroing), `probe-enable`/`probe-invert` (firmware 0x83: latch
//! on a probe edge), `quad-error`/`quad-error-enable`, the live inputs
//! `input-a`/`-b`/`-index`, params `index-invert`, `index-mask`,
//! `index-mask-invert`, `counter-mode`, `filter`, and the module pins
//! `encoder.sample-frequency` and `encoder.hires-timestamp`.
//!
//! The index handshake is the firmware's: `write` sets "latch on index,
//! once" in the control register; when a later `read` sees the firmware
//! cleared that bit, the latched count is where the index was.

use canonical::EncoderCore;
use hal_core::{
    HalHost, HostParam, HostPin, In, Io, Ours, Out, PinFactory, Result as HalResult, Rw,
};

use crate::firmware::ModuleUse;
use crate::md::ModuleDescriptor;
use crate::modules::{put, Export};
use crate::regs::encoder as r;
use crate::tram::Slot;
use crate::transport::{Transport, TransportError};

/// Default filter sample frequency, Hz.
pub const DEFAULT_SAMPLE_FREQUENCY: u32 = 25_000_000;

/// The 16-bit difference `a - b` as a signed number.
#[inline]
fn diff16(a: u32, b: u32) -> i64 {
    (a.wrapping_sub(b) as u16 as i16) as i64
}

/// The timestamp divider for the timestamp clock.
pub fn tsdiv(clock: u32, hires: bool) -> u32 {
    let f = if hires { 10_000_000 } else { 2_000_000 };
    (clock / f).saturating_sub(2)
}

/// The filter rate register for a sample frequency, and the frequency it
/// gives.
pub fn filter_rate(clock: u32, sample_hz: u32) -> (u32, u32) {
    if sample_hz >= clock {
        return (0xFFF, clock);
    }
    let rate = (clock / sample_hz.max(1)).saturating_sub(2).min(0x7FF);
    (rate, clock / (rate + 2))
}

/// A channel's probe pins: `probe-enable` and `probe-invert`.
type ProbePins<H> = (<H as HalHost>::Pin<bool, In>, <H as HalHost>::Pin<bool, In>);

struct Chan<H: HalHost = Ours> {
    core: EncoderCore,
    rawcounts: H::Pin<i32, Out>,
    rawlatch: H::Pin<i32, Out>,
    count: H::Pin<i32, Out>,
    count_latched: H::Pin<i32, Out>,
    position: H::Pin<f64, Out>,
    position_interpolated: H::Pin<f64, Out>,
    position_latched: H::Pin<f64, Out>,
    velocity: H::Pin<f64, Out>,
    velocity_rpm: H::Pin<f64, Out>,
    reset: H::Pin<bool, In>,
    index_enable: H::Pin<bool, Io>,
    no_clear_on_index: H::Pin<bool, In>,
    probe: Option<ProbePins<H>>,
    quad_error: H::Pin<bool, Out>,
    quad_error_enable: H::Pin<bool, In>,
    input_a: H::Pin<bool, Out>,
    input_b: H::Pin<bool, Out>,
    input_index: H::Pin<bool, Out>,
    scale: H::Param<f64, Rw>,
    vel_timeout: H::Param<f64, Rw>,
    index_invert: H::Param<bool, Rw>,
    index_mask: H::Param<bool, Rw>,
    index_mask_invert: H::Param<bool, Rw>,
    counter_mode: H::Param<bool, Rw>,
    filter: H::Param<bool, Rw>,
    /// The control word last written.
    written: Option<u32>,
    prev_qee: bool,
    prev_hw: u32,
    prev_raw: i64,
    prev_count: i64,
    last_change_ns: u64,
}

/// The encoder module.
pub struct Encoders<H: HalHost = Ours> {
    md: ModuleDescriptor,
    has_probe: bool,
    tsc_read: Slot,
    counter_read: Slot,
    latch_read: Slot,
    chans: Vec<Chan<H>>,
    sample_frequency: H::Pin<u32, In>,
    hires: H::Pin<bool, In>,
    written_tsdiv: Option<u32>,
    written_filter: Option<u32>,
    tsdiv: u32,
    prev_tsc: u32,
    now_ns: u64,
    ns_rem: u128,
}

impl<H: HalHost> Encoders<H> {
    /// Exports the encoders in use and registers TSCount, the counters and
    /// the latch/control words, in that order (the timestamp must be read
    /// before the counts).
    pub fn export<F: PinFactory<H>>(
        x: &mut Export<'_, F>,
        m: &ModuleUse,
    ) -> HalResult<Encoders<H>> {
        let has_probe = m.md.version == 0x83;
        let mut chans = Vec::with_capacity(m.instances as usize);
        for i in 0..m.instances as usize {
            let c = x.comp;
            let n = |item: &str| x.name(&format!("encoder.{i:02}.{item}"));
            chans.push(Chan {
                core: EncoderCore::new(16),
                rawcounts: c.pin(&n("rawcounts"))?,
                rawlatch: c.pin(&n("rawlatch"))?,
                count: c.pin(&n("count"))?,
                count_latched: c.pin(&n("count-latched"))?,
                position: c.pin(&n("position"))?,
                position_interpolated: c.pin(&n("position-interpolated"))?,
                position_latched: c.pin(&n("position-latched"))?,
                velocity: c.pin(&n("velocity"))?,
                velocity_rpm: c.pin(&n("velocity-rpm"))?,
                reset: c.pin(&n("reset"))?,
                index_enable: c.pin(&n("index-enable"))?,
                no_clear_on_index: c.pin(&n("no_clear_on_index"))?,
                probe: if has_probe {
                    Some((c.pin(&n("probe-enable"))?, c.pin(&n("probe-invert"))?))
                } else {
                    None
                },
                quad_error: c.pin(&n("quad-error"))?,
                quad_error_enable: c.pin(&n("quad-error-enable"))?,
                input_a: c.pin(&n("input-a"))?,
                input_b: c.pin(&n("input-b"))?,
                input_index: c.pin(&n("input-index"))?,
                scale: c.param(&n("scale"), 1.0)?,
                vel_timeout: c.param(&n("vel-timeout"), 0.5)?,
                index_invert: c.param(&n("index-invert"), false)?,
                index_mask: c.param(&n("index-mask"), false)?,
                index_mask_invert: c.param(&n("index-mask-invert"), false)?,
                counter_mode: c.param(&n("counter-mode"), false)?,
                filter: c.param(&n("filter"), true)?,
                written: None,
                prev_qee: false,
                prev_hw: 0,
                prev_raw: 0,
                prev_count: 0,
                last_change_ns: 0,
            });
        }
        let sample_frequency = x.comp.pin_init(
            &x.name("encoder.sample-frequency"),
            DEFAULT_SAMPLE_FREQUENCY,
        )?;
        let hires = x.comp.pin(&x.name("encoder.hires-timestamp"))?;
        let n = m.instances as usize;
        let tsc_read = x.tram.add_read(m.md.reg(r::TSCOUNT), 1);
        let counter_read = x.tram.add_read(m.md.reg(r::COUNTER), n);
        let latch_read = x.tram.add_read(m.md.reg(r::LATCH_CONTROL), n);
        Ok(Encoders {
            md: m.md,
            has_probe,
            tsc_read,
            counter_read,
            latch_read,
            chans,
            sample_frequency,
            hires,
            written_tsdiv: None,
            written_filter: None,
            tsdiv: tsdiv(m.md.clock_hz, false),
            prev_tsc: 0,
            now_ns: 0,
            ns_rem: 0,
        })
    }

    /// Writes the control words and the module registers.
    pub fn force_write(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        self.written_tsdiv = None;
        self.written_filter = None;
        for c in &mut self.chans {
            c.written = None;
        }
        self.write_config(t)
    }

    /// Takes the first read's counts and timestamp as the starting point.
    pub fn init_from_read(&mut self, buf: &[u32]) {
        self.prev_tsc = self.tsc_read.of(buf)[0] & 0xFFFF;
        let counters = self.counter_read.of(buf);
        for (c, &w) in self.chans.iter_mut().zip(counters) {
            let hw = w & 0xFFFF;
            c.prev_hw = hw;
            let out = c.core.update(hw as u64, None, 0, false, u64::MAX);
            c.prev_raw = out.rawcounts;
            c.prev_count = out.count;
        }
    }

    /// Nanoseconds per timestamp tick, as (numerator, denominator).
    #[inline]
    fn tick_ns(&self) -> (u128, u128) {
        (
            (self.tsdiv as u128 + 2) * 1_000_000_000,
            self.md.clock_hz as u128,
        )
    }

    /// Publishes every encoder from this cycle's words.
    pub fn process_read(&mut self, buf: &[u32]) {
        let tsc = self.tsc_read.of(buf)[0] & 0xFFFF;
        let (num, den) = self.tick_ns();
        let dticks = (tsc.wrapping_sub(self.prev_tsc) & 0xFFFF) as u128;
        self.prev_tsc = tsc;
        let total = dticks * num + self.ns_rem;
        self.now_ns += (total / den) as u64;
        self.ns_rem = total % den;
        let now_ns = self.now_ns;
        let counters = self.counter_read.of(buf);
        let latches = self.latch_read.of(buf);
        for ((c, &cw), &lw) in self.chans.iter_mut().zip(counters).zip(latches) {
            let hw = cw & 0xFFFF;
            let stamp = cw >> 16;
            let latch = lw >> 16;
            let ctl = lw & 0xFFFF;
            c.input_a.set(ctl & r::INPUT_A != 0);
            c.input_b.set(ctl & r::INPUT_B != 0);
            c.input_index.set(ctl & r::INPUT_INDEX != 0);
            c.quad_error
                .set(c.quad_error_enable.get() && ctl & r::QUAD_ERROR != 0);
            let written = c.written.unwrap_or(0);
            let index_fired = written & r::LATCH_ON_INDEX != 0 && ctl & r::LATCH_ON_INDEX == 0;
            let probe_fired =
                !index_fired && written & r::LATCH_ON_PROBE != 0 && ctl & r::LATCH_ON_PROBE == 0;
            // When did the last count happen? Its timestamp is at most
            // 0xFFFF ticks old.
            let changed = hw != c.prev_hw;
            let at_ns = if changed {
                let age = (tsc.wrapping_sub(stamp) & 0xFFFF) as u128;
                let age_ns = (age * num / den) as u64;
                now_ns.saturating_sub(age_ns).max(c.last_change_ns)
            } else {
                now_ns
            };
            if changed {
                c.last_change_ns = at_ns;
            }
            let latch_raw = c.prev_raw + diff16(latch, c.prev_hw);
            let zero_before = c.prev_raw - c.prev_count;
            let clear = index_fired && !c.no_clear_on_index.get();
            let timeout = c.vel_timeout.get();
            let timeout_ns = if timeout > 0.0 {
                (timeout * 1e9).min(u64::MAX as f64) as u64
            } else {
                0
            };
            let out = c.core.update(
                hw as u64,
                clear.then_some(latch as u64),
                at_ns,
                c.reset.get(),
                timeout_ns,
            );
            let scale = canonical::usable_scale(&c.scale);
            if index_fired || probe_fired {
                let at = latch_raw - zero_before;
                c.rawlatch.set(latch_raw as i32);
                c.count_latched.set(at as i32);
                c.position_latched.set(at as f64 / scale);
                if index_fired {
                    c.index_enable.set(false);
                } else if let Some((enable, _)) = &c.probe {
                    enable.overwrite(false);
                }
            }
            c.prev_hw = hw;
            c.prev_raw = out.rawcounts;
            c.prev_count = out.count;
            let position = out.count as f64 / scale;
            let velocity = out.velocity / scale;
            c.count.set(out.count as i32);
            c.rawcounts.set(out.rawcounts as i32);
            c.position.set(position);
            c.velocity.set(velocity);
            c.velocity_rpm.set(velocity * 60.0);
            let since = now_ns.saturating_sub(c.last_change_ns);
            let interpolated = if velocity != 0.0 && since < timeout_ns {
                position + velocity * since as f64 * 1e-9
            } else {
                position
            };
            c.position_interpolated.set(interpolated);
        }
    }

    /// The control word the pins ask for.
    #[inline]
    fn control(&self, c: &Chan<H>) -> u32 {
        let index = c.index_enable.get();
        let (probe, probe_invert) = match &c.probe {
            Some((e, i)) if self.has_probe => (e.get(), i.get()),
            _ => (false, false),
        };
        let mut w = 0;
        let mut set = |on: bool, bit: u32| {
            if on {
                w |= bit
            }
        };
        set(index, r::LATCH_ON_INDEX);
        set(!index && probe, r::LATCH_ON_PROBE);
        set(index || probe, r::JUST_ONCE);
        set(probe_invert, r::PROBE_POLARITY);
        set(c.index_invert.get(), r::INDEX_POLARITY);
        set(c.index_mask.get(), r::INDEX_MASK);
        set(c.index_mask_invert.get(), r::INDEX_MASK_POLARITY);
        set(c.counter_mode.get(), r::COUNTER_MODE);
        set(c.filter.get(), r::FILTER);
        w
    }

    /// Queues the control words and module registers that changed.
    pub fn write_config(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        let clock = self.md.clock_hz;
        let div = tsdiv(clock, self.hires.get());
        if self.written_tsdiv != Some(div) {
            put(t, self.md.reg(r::TSDIV), div)?;
            self.written_tsdiv = Some(div);
            self.tsdiv = div;
        }
        let (rate, achieved) = filter_rate(clock, self.sample_frequency.get());
        if self.written_filter != Some(rate) {
            put(t, self.md.reg(r::FILTER_RATE), rate)?;
            self.written_filter = Some(rate);
        }
        if self.sample_frequency.get() != achieved {
            self.sample_frequency.overwrite(achieved);
        }
        for i in 0..self.chans.len() {
            let c = &self.chans[i];
            let mut word = self.control(c);
            let qee = c.quad_error_enable.get();
            if qee && !c.prev_qee {
                word |= r::QUAD_ERROR;
            }
            let c = &mut self.chans[i];
            c.prev_qee = qee;
            if c.written != Some(word) {
                put(t, self.md.inst_reg(r::LATCH_CONTROL, i), word)?;
                c.written = Some(word);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dividers() {
        assert_eq!(tsdiv(100_000_000, false), 48);
        assert_eq!(tsdiv(100_000_000, true), 8);
        assert_eq!(tsdiv(1_000_000, false), 0);
        assert_eq!(filter_rate(100_000_000, 25_000_000), (2, 25_000_000));
        assert_eq!(filter_rate(100_000_000, 100_000_000), (0xFFF, 100_000_000));
        assert_eq!(filter_rate(100_000_000, 3_000_000), (31, 3_030_303));
        assert_eq!(filter_rate(100_000_000, 0).0, 0x7FF);
        assert_eq!(diff16(2, 0xFFFE), 4);
        assert_eq!(diff16(0xFFFE, 2), -4);
    }
}
