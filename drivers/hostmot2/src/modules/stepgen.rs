//! StepGen (hardware.md 5.9.4): hardware step generators.
//!
//! The motion arithmetic is the canonical step generator's
//! ([`canonical::Stepgen`], pins `position-cmd`, `velocity-cmd`,
//! `control-type`, `enable`, `counts`, `position-fb`, `velocity-fb`,
//! params `position-scale`, `maxvel`, `maxaccel`, `steplen`, `stepspace`,
//! `dirsetup`, `dirhold`): `read` publishes the feedback from the
//! firmware's 48-bit DDS accumulator (whose top 32 bits are the position
//! in 16.16 steps), `write` turns the commanded step rate into the Rate
//! register (`steps/s × 2^32 / clock`).
//!
//! hostmot2's extras: `position-reset`, `step_type` (0 step/dir, 1
//! up/down, 2 quadrature, 3..16 table of that many phases from
//! `table-data-0..3`), `swap_step_dir` (firmware 0x42 and later), and
//! with firmware 0xC2 `index-enable`, `probe-enable`, `index-invert`,
//! `probe-invert` and `position-latch`; the debug pins `dbg_ff_vel` (the
//! command's own velocity), `dbg_err_at_match` (command minus feedback),
//! `dbg_pos_minus_prev_cmd`, `dbg_vel_error` (commanded minus feed-forward
//! velocity), `dbg_s_to_match` (distance the command moves in one
//! period) and `dbg_step_rate` (the Rate register).
//!
//! Timing params start at the slowest the hardware does (0x3FFF clocks),
//! as LinuxCNC's do. A timing register holding N makes the firmware wait
//! N + 1 clocks, so N is the time in clocks rounded up, minus one: never
//! shorter than asked, never a clock longer. A time past 0x4000 clocks is
//! clamped and the param rewritten to what the board does.

use canonical::{ChannelNames, Stepgen};
use hal_core::{
    HalHost, HostParam, HostPin, In, Io, Ours, Out, PinFactory, Result as HalResult, Rw,
};

use crate::firmware::ModuleUse;
use crate::log::Level;
use crate::md::ModuleDescriptor;
use crate::modules::{put, Export, Notify};
use crate::regs::stepgen as r;
use crate::tram::Slot;
use crate::transport::{Transport, TransportError};

/// The timing register value for `ns` at `clock`, and the time it gives
/// if it had to be clamped.
pub fn timing_value(ns: u32, clock: u32) -> (u32, Option<u32>) {
    let clocks = (ns as u64 * clock as u64).div_ceil(1_000_000_000);
    let n = clocks.saturating_sub(1);
    if n > r::TIMING_MAX as u64 {
        let longest = (r::TIMING_MAX as u64 + 1) * 1_000_000_000 / clock as u64;
        (r::TIMING_MAX, Some(longest.min(u32::MAX as u64) as u32))
    } else {
        (n as u32, None)
    }
}

/// The Rate register for `steps_per_s` at `clock`, rounded to the
/// nearest step of the register.
pub fn rate_value(steps_per_s: f64, clock: u32) -> u32 {
    let v = steps_per_s * 4_294_967_296.0 / clock as f64;
    let v = if v.is_nan() {
        0.0
    } else {
        v.round().clamp(i32::MIN as f64, i32::MAX as f64)
    };
    v as i32 as u32
}

struct IndexPins<H: HalHost = Ours> {
    position_latch: H::Pin<f64, Out>,
    index_enable: H::Pin<bool, Io>,
    probe_enable: H::Pin<bool, Io>,
    index_invert: H::Pin<bool, In>,
    probe_invert: H::Pin<bool, In>,
}

struct DebugPins<H: HalHost = Ours> {
    pos_minus_prev_cmd: H::Pin<f64, Out>,
    ff_vel: H::Pin<f64, Out>,
    s_to_match: H::Pin<f64, Out>,
    vel_error: H::Pin<f64, Out>,
    err_at_match: H::Pin<f64, Out>,
    step_rate: H::Pin<i32, Out>,
}

struct Chan<H: HalHost = Ours> {
    sg: Stepgen<H>,
    position_reset: H::Pin<bool, In>,
    step_type: H::Param<u32, Rw>,
    swap: Option<H::Param<bool, Rw>>,
    table: [H::Param<u32, Rw>; 4],
    index: Option<IndexPins<H>>,
    dbg: DebugPins<H>,
    prev_acc: u32,
    /// Position in 1/65536 steps.
    subcounts: i64,
    written_timing: Option<[u32; 4]>,
    written_mode: Option<(u32, [u32; 4])>,
}

/// The step generator module.
pub struct Stepgens<H: HalHost = Ours> {
    md: ModuleDescriptor,
    rate_write: Slot,
    acc_read: Slot,
    mode_read: Option<Slot>,
    chans: Vec<Chan<H>>,
}

impl<H: HalHost> Stepgens<H> {
    /// Exports the step generators in use and registers the rate writes,
    /// accumulator reads and (0xC2) mode reads.
    pub fn export<F: PinFactory<H>>(
        x: &mut Export<'_, F>,
        m: &ModuleUse,
    ) -> HalResult<Stepgens<H>> {
        let clock = m.md.clock_hz;
        let slowest = ((r::TIMING_MAX as u64) * 1_000_000_000 / clock as u64) as u32;
        let prefix = x.prefix.to_string();
        let names = ChannelNames::custom(move |i, item| format!("{prefix}.stepgen.{i:02}.{item}"));
        let latching = m.md.version == 0xC2;
        let mut chans = Vec::with_capacity(m.instances as usize);
        for i in 0..m.instances as usize {
            let c = x.comp;
            let n = |item: &str| names.item(i, item);
            let sg = Stepgen::export(c, &names, i)?;
            sg.set_timing_ns([slowest; 4]);
            chans.push(Chan {
                sg,
                position_reset: c.pin(&n("position-reset"))?,
                step_type: c.param(&n("step_type"), 0)?,
                swap: if m.md.version >= 0x42 {
                    Some(c.param(&n("swap_step_dir"), false)?)
                } else {
                    None
                },
                table: [
                    c.param(&n("table-data-0"), 0)?,
                    c.param(&n("table-data-1"), 0)?,
                    c.param(&n("table-data-2"), 0)?,
                    c.param(&n("table-data-3"), 0)?,
                ],
                index: if latching {
                    Some(IndexPins {
                        position_latch: c.pin(&n("position-latch"))?,
                        index_enable: c.pin(&n("index-enable"))?,
                        probe_enable: c.pin(&n("probe-enable"))?,
                        index_invert: c.pin(&n("index-invert"))?,
                        probe_invert: c.pin(&n("probe-invert"))?,
                    })
                } else {
                    None
                },
                dbg: DebugPins {
                    pos_minus_prev_cmd: c.pin(&n("dbg_pos_minus_prev_cmd"))?,
                    ff_vel: c.pin(&n("dbg_ff_vel"))?,
                    s_to_match: c.pin(&n("dbg_s_to_match"))?,
                    vel_error: c.pin(&n("dbg_vel_error"))?,
                    err_at_match: c.pin(&n("dbg_err_at_match"))?,
                    step_rate: c.pin(&n("dbg_step_rate"))?,
                },
                prev_acc: 0,
                subcounts: 0,
                written_timing: None,
                written_mode: None,
            });
        }
        let n = m.instances as usize;
        let rate_write = x.tram.add_write(m.md.reg(r::RATE), n);
        let acc_read = x.tram.add_read(m.md.reg(r::ACCUMULATOR), n);
        let mode_read = latching.then(|| x.tram.add_read(m.md.reg(r::MODE), n));
        Ok(Stepgens {
            md: m.md,
            rate_write,
            acc_read,
            mode_read,
            chans,
        })
    }

    /// Writes the timing registers and the master DDS (the mode registers
    /// follow at the first `write`).
    pub fn force_write(
        &mut self,
        t: &mut dyn Transport,
        say: &Notify,
    ) -> Result<(), TransportError> {
        put(t, self.md.reg(r::MASTER_DDS), 0xFFFF_FFFF)?;
        for c in &mut self.chans {
            c.written_timing = None;
        }
        self.write_timing(t, say)
    }

    /// Takes the first read's accumulators as the starting point.
    pub fn init_from_read(&mut self, buf: &[u32]) {
        for (c, &acc) in self.chans.iter_mut().zip(self.acc_read.of(buf)) {
            c.prev_acc = acc;
            c.subcounts = 0;
        }
    }

    /// Publishes the feedback of every step generator.
    pub fn process_read(&mut self, buf: &[u32]) {
        let accs = self.acc_read.of(buf);
        let modes = self.mode_read.map(|s| s.of(buf));
        for (i, (c, &acc)) in self.chans.iter_mut().zip(accs).enumerate() {
            let before = c.subcounts;
            c.subcounts += acc.wrapping_sub(c.prev_acc) as i32 as i64;
            if let (Some(ix), Some(modes)) = (&c.index, modes) {
                let mode = modes[i];
                let written = c.written_mode.map_or(0, |(m, _)| m);
                let fired = |bit: u32| written & bit != 0 && mode & bit == 0;
                let latch = mode & 0xFFFF_FF00;
                let at = before + latch.wrapping_sub(c.prev_acc) as i32 as i64;
                let scale = c.sg.scale();
                if ix.index_enable.get() && fired(r::MODE_LATCH_ON_INDEX) {
                    ix.position_latch.set(at as f64 / 65536.0 / scale);
                    c.subcounts = acc.wrapping_sub(latch) as i32 as i64;
                    ix.index_enable.set(false);
                } else if ix.probe_enable.get() && fired(r::MODE_LATCH_ON_PROBE) {
                    ix.position_latch.set(at as f64 / 65536.0 / scale);
                    ix.probe_enable.set(false);
                }
            }
            c.prev_acc = acc;
            if c.position_reset.get() {
                c.subcounts = 0;
            }
            c.sg.publish_feedback(c.subcounts >> 16, c.subcounts as f64 / 65536.0);
        }
    }

    /// Computes every step rate into the TRAM words.
    pub fn prepare_write(&mut self, buf: &mut [u32], period_ns: i64) {
        let clock = self.md.clock_hz;
        let rates = self.rate_write.of_mut(buf);
        for (c, word) in self.chans.iter_mut().zip(rates.iter_mut()) {
            let fine = c.subcounts as f64 / 65536.0;
            let cmd = c.sg.command(fine, period_ns);
            let value = rate_value(cmd.rate, clock);
            *word = value;
            let dt = period_ns as f64 * 1e-9;
            let velocity = cmd.rate / c.sg.scale();
            c.dbg.ff_vel.set(cmd.feed_forward);
            c.dbg.err_at_match.set(cmd.position_error);
            c.dbg
                .pos_minus_prev_cmd
                .set(cmd.feed_forward * dt - cmd.position_error);
            c.dbg.vel_error.set(velocity - cmd.feed_forward);
            c.dbg.s_to_match.set(cmd.feed_forward * dt);
            c.dbg.step_rate.set(value as i32);
        }
    }

    fn write_timing(&mut self, t: &mut dyn Transport, say: &Notify) -> Result<(), TransportError> {
        let clock = self.md.clock_hz;
        for (i, c) in self.chans.iter_mut().enumerate() {
            let ns = c.sg.timing_ns();
            if c.written_timing == Some(ns) {
                continue;
            }
            // Register order: DirSetup, DirHold, PulseWidth, PulseIdle.
            let [steplen, stepspace, dirsetup, dirhold] = ns;
            let mut fixed = ns;
            for (k, (reg, v)) in [
                (r::PULSE_WIDTH, steplen),
                (r::PULSE_IDLE, stepspace),
                (r::DIR_SETUP, dirsetup),
                (r::DIR_HOLD, dirhold),
            ]
            .into_iter()
            .enumerate()
            {
                let (value, clamped) = timing_value(v, clock);
                if let Some(longest) = clamped {
                    fixed[k] = longest;
                }
                put(t, self.md.inst_reg(reg, i), value)?;
            }
            if fixed != ns {
                c.sg.set_timing_ns(fixed);
                say.say(
                    Level::Err,
                    format_args!("stepgen timing too long for the board, clamped to 0x3FFF clocks"),
                );
            }
            c.written_timing = Some(fixed);
        }
        Ok(())
    }

    /// Queues the timing and mode registers that changed.
    pub fn write_config(
        &mut self,
        t: &mut dyn Transport,
        say: &Notify,
    ) -> Result<(), TransportError> {
        self.write_timing(t, say)?;
        let version = self.md.version;
        for (i, c) in self.chans.iter_mut().enumerate() {
            let mut step_type = c.step_type.get();
            if step_type > r::TABLE_MAX {
                step_type = r::TABLE_MAX;
                c.step_type.set(step_type);
                say.say(
                    Level::Err,
                    format_args!("stepgen step_type is at most 16, set to 16"),
                );
            }
            let mut mode = match step_type {
                0 => r::TYPE_STEP_DIR,
                1 => r::TYPE_UP_DOWN,
                2 => r::TYPE_QUADRATURE,
                _ => r::TYPE_TABLE,
            };
            if c.swap.as_ref().is_some_and(|s| s.get()) && version >= 0x42 {
                mode |= r::MODE_SWAP;
            }
            if let Some(ix) = &c.index {
                let mut set = |on: bool, bit: u32| {
                    if on {
                        mode |= bit
                    }
                };
                set(ix.index_enable.get(), r::MODE_LATCH_ON_INDEX);
                set(ix.index_invert.get(), r::MODE_INDEX_POLARITY);
                set(ix.probe_enable.get(), r::MODE_LATCH_ON_PROBE);
                set(ix.probe_invert.get(), r::MODE_PROBE_POLARITY);
            }
            let table = if step_type >= 3 {
                [
                    c.table[0].get(),
                    c.table[1].get(),
                    c.table[2].get(),
                    c.table[3].get(),
                ]
            } else {
                [0; 4]
            };
            if c.written_mode == Some((mode, table)) {
                continue;
            }
            if step_type >= 3 {
                // Phases last to first, each phase's pins in a byte.
                for phase in (0..step_type).rev() {
                    let byte = (table[phase as usize / 4] >> (8 * (phase % 4))) & 0xFF;
                    put(t, self.md.inst_reg(r::TABLE_DATA, i), byte)?;
                }
                put(t, self.md.inst_reg(r::TABLE_LENGTH, i), step_type - 1)?;
            }
            put(t, self.md.inst_reg(r::MODE, i), mode)?;
            c.written_mode = Some((mode, table));
        }
        Ok(())
    }

    /// Safe state: every rate 0, at once.
    pub fn go_safe(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        let zeros = vec![0u32; self.chans.len()];
        t.write(self.md.reg(r::RATE), &zeros)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timing_and_rate_values() {
        assert_eq!(timing_value(5000, 100_000_000), (499, None), "500 clocks");
        assert_eq!(timing_value(5001, 100_000_000), (500, None), "rounded up");
        assert_eq!(timing_value(0, 100_000_000), (0, None));
        assert_eq!(
            timing_value(1_000_000, 100_000_000),
            (0x3FFF, Some(163_840)),
            "clamped"
        );
        assert_eq!(rate_value(1_000_000.0, 100_000_000), 42_949_673);
        assert_eq!(
            rate_value(-1_000_000.0, 100_000_000),
            (-42_949_673i32) as u32
        );
        assert_eq!(rate_value(f64::NAN, 100_000_000), 0);
        assert_eq!(rate_value(1e12, 100_000_000), i32::MAX as u32);
    }
}
