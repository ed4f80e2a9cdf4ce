//! The PCA9685 driver: 16 PWM outputs.
//!
//! Set-up (every step one byte-data write): MODE1 = SLEEP | AI (asleep,
//! so PRE_SCALE may change; all-call off), PRE_SCALE, MODE2 (INVRT,
//! OUTDRV), ALL_LED_OFF_H = full off (every output off), MODE1 = AI
//! (awake). The outputs are off from the set-up on, so nothing needs
//! RESTART; the oscillator's 500 µs start-up only delays the first pulse.
//!
//! Each cycle writes the channels whose count changed, consecutive ones
//! together (one block write per run of up to eight channels, 4 bytes
//! each, auto-increment), and every [`CHECK_EVERY`](super::CHECK_EVERY)
//! cycles reads MODE1 back: a chip asleep or without auto-increment was
//! reset.

use super::{CheckTimer, Chip, ChipFault, Command};
use crate::bus::{I2cBus, BLOCK_MAX};
use crate::regs::pca9685::*;

/// Each channel's on-time in ticks of 4096: 0 is full off, 4096 full on.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PwmCmd {
    /// Counts by channel.
    pub counts: [u16; CHANNELS],
}

impl Command for PwmCmd {
    /// Every channel full off.
    fn safe(&self) -> Self {
        PwmCmd::default()
    }
}

impl PwmCmd {
    /// The count for a duty cycle: negative and NaN are off, 1 and more
    /// full on.
    pub fn counts_for(duty: f64) -> u16 {
        if duty.is_nan() || duty <= 0.0 {
            0
        } else {
            (duty.min(1.0) * TICKS as f64).round() as u16
        }
    }
}

/// One PCA9685.
#[derive(Debug, Clone)]
pub struct Pca9685Chip {
    addr: u8,
    prescale: u8,
    mode2: u8,
    /// The counts the chip has; None where unknown.
    written: [Option<u16>; CHANNELS],
    check: CheckTimer,
}

/// MODE1 while running: awake, auto-increment, all-call off.
const MODE1_RUN: u8 = MODE1_AI;

impl Pca9685Chip {
    /// A chip at `addr` running at PRE_SCALE `prescale`, outputs inverted
    /// with `invert`, open drain with `open_drain`.
    pub fn new(addr: u8, prescale: u8, invert: bool, open_drain: bool) -> Pca9685Chip {
        let mut mode2 = if open_drain { 0 } else { MODE2_OUTDRV };
        if invert {
            mode2 |= MODE2_INVRT;
        }
        Pca9685Chip {
            addr,
            prescale,
            mode2,
            written: [None; CHANNELS],
            check: CheckTimer::default(),
        }
    }

    /// Writes the channels whose counts differ from what the chip has.
    fn write_changed(&mut self, bus: &dyn I2cBus, cmd: &PwmCmd) -> Result<(), ChipFault> {
        let per_block = BLOCK_MAX / 4;
        let mut ch = 0;
        while ch < CHANNELS {
            if self.written[ch] == Some(cmd.counts[ch]) {
                ch += 1;
                continue;
            }
            let first = ch;
            let mut bytes = [0u8; BLOCK_MAX];
            while ch < CHANNELS
                && ch - first < per_block
                && self.written[ch] != Some(cmd.counts[ch])
            {
                let k = 4 * (ch - first);
                bytes[k..k + 4].copy_from_slice(&channel_bytes(cmd.counts[ch]));
                ch += 1;
            }
            let n = ch - first;
            // A failed write leaves those channels unknown.
            self.written[first..ch].fill(None);
            bus.write_block(self.addr, led_on_l(first), &bytes[..4 * n])?;
            for c in first..ch {
                self.written[c] = Some(cmd.counts[c]);
            }
        }
        Ok(())
    }
}

impl Chip for Pca9685Chip {
    type Cmd = PwmCmd;
    type Sample = ();

    fn address(&self) -> u8 {
        self.addr
    }

    fn init(&mut self, bus: &dyn I2cBus, _safe: &PwmCmd) -> Result<(), ChipFault> {
        self.written = [None; CHANNELS];
        let a = self.addr;
        bus.write_byte_data(a, MODE1, MODE1_SLEEP | MODE1_AI)?;
        bus.write_byte_data(a, PRE_SCALE, self.prescale)?;
        bus.write_byte_data(a, MODE2, self.mode2)?;
        bus.write_byte_data(a, ALL_LED_OFF_H, FULL)?;
        bus.write_byte_data(a, MODE1, MODE1_RUN)?;
        // Every channel's OFF_H now says full off, and the rest of its
        // registers are as they were: unknown.
        self.check.restart();
        Ok(())
    }

    fn cycle(
        &mut self,
        bus: &dyn I2cBus,
        cmd: &PwmCmd,
        _now_ns: u64,
        _sample: &mut (),
    ) -> Result<(), ChipFault> {
        if self.check.due() {
            let mode1 = bus.read_byte_data(self.addr, MODE1)?;
            if mode1 & (MODE1_SLEEP | MODE1_AI | MODE1_ALLCALL) != MODE1_RUN {
                return Err(ChipFault::LostConfig);
            }
        }
        self.write_changed(bus, cmd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Kind, Pca9685, SimBus};
    use hal_driver::sim::SimClock;
    use std::sync::Arc;

    fn rig() -> (SimBus, Pca9685Chip) {
        let bus = SimBus::new("sim", Arc::new(SimClock::new(0, 0)));
        bus.add_chip(0x41, Box::new(Pca9685::new()));
        (bus, Pca9685Chip::new(0x41, 121, false, false))
    }

    #[test]
    fn counts_from_duty() {
        assert_eq!(PwmCmd::counts_for(0.5), 2048);
        assert_eq!(PwmCmd::counts_for(-0.5), 0);
        assert_eq!(PwmCmd::counts_for(f64::NAN), 0);
        assert_eq!(PwmCmd::counts_for(1.2), 4096);
        assert_eq!(PwmCmd::counts_for(1.0 / 8192.0), 1, "rounds");
    }

    #[test]
    fn set_up_sequence() {
        let (bus, mut chip) = rig();
        chip.init(&bus, &PwmCmd::default()).unwrap();
        let t: Vec<_> = bus
            .transfers()
            .iter()
            .map(|t| (t.kind, t.reg, t.bytes().to_vec()))
            .collect();
        assert_eq!(
            t,
            vec![
                (Kind::WriteByte, MODE1, vec![0x30]),
                (Kind::WriteByte, PRE_SCALE, vec![121]),
                (Kind::WriteByte, MODE2, vec![0x04]),
                (Kind::WriteByte, ALL_LED_OFF_H, vec![0x10]),
                (Kind::WriteByte, MODE1, vec![0x20]),
            ]
        );
        bus.advance(WAKE_NS);
        bus.with_chip::<Pca9685, _>(0x41, |c| {
            assert!(!c.asleep());
            assert!((c.frequency() - 50.0).abs() < 0.2);
            assert!(c.totem_pole() && !c.inverted());
            assert_eq!(
                c.prescale_writes_ignored + c.early_restarts + c.testmode_writes,
                0
            );
        });
        let mut inv = Pca9685Chip::new(0x41, 3, true, true);
        inv.init(&bus, &PwmCmd::default()).unwrap();
        bus.with_chip::<Pca9685, _>(0x41, |c| {
            assert!(c.inverted() && !c.totem_pole());
            assert_eq!(c.reg(PRE_SCALE), 3);
        });
    }

    #[test]
    fn writes_changed_channels_in_runs_of_up_to_eight() {
        let (bus, mut chip) = rig();
        chip.init(&bus, &PwmCmd::default()).unwrap();
        bus.advance(WAKE_NS);
        let mut cmd = PwmCmd::default();
        for (ch, c) in cmd.counts.iter_mut().enumerate() {
            *c = 256 * ch as u16;
        }
        bus.clear_log();
        chip.cycle(&bus, &cmd, 0, &mut ()).unwrap();
        let t = bus.transfers();
        // Two blocks of 8 channels (no check right after the set-up).
        assert_eq!(
            (t[0].kind, t[0].reg, t[0].bytes().len()),
            (Kind::WriteBlock, led_on_l(0), 32)
        );
        assert_eq!(
            (t[1].kind, t[1].reg, t[1].bytes().len()),
            (Kind::WriteBlock, led_on_l(8), 32)
        );
        assert_eq!(t.len(), 2);
        bus.with_chip::<Pca9685, _>(0x41, |c| {
            for ch in 0..16 {
                assert_eq!(c.duty(ch), ch as f64 / 16.0, "channel {ch}");
            }
        });
        // Nothing changed: nothing written.
        bus.clear_log();
        chip.cycle(&bus, &cmd, 0, &mut ()).unwrap();
        assert!(bus.transfers().is_empty());
        // Channels 3, 4 and 9 change: two writes.
        cmd.counts[3] = 4096;
        cmd.counts[4] = 1;
        cmd.counts[9] = 0;
        chip.cycle(&bus, &cmd, 0, &mut ()).unwrap();
        let t = bus.transfers();
        assert_eq!(t.len(), 2);
        assert_eq!(
            (t[0].reg, t[0].bytes()),
            (led_on_l(3), &[0, 0x10, 0, 0, 0, 0, 1, 0][..])
        );
        assert_eq!(
            (t[1].reg, t[1].bytes()),
            (led_on_l(9), &[0, 0, 0, 0x10][..])
        );
        bus.with_chip::<Pca9685, _>(0x41, |c| {
            assert_eq!((c.duty(3), c.duty(4), c.duty(9)), (1.0, 1.0 / 4096.0, 0.0));
        });
    }

    #[test]
    fn a_reset_chip_is_noticed_and_a_failed_write_is_retried() {
        let (bus, mut chip) = rig();
        chip.init(&bus, &PwmCmd::default()).unwrap();
        let mut cmd = PwmCmd::default();
        cmd.counts[0] = 100;
        chip.cycle(&bus, &cmd, 0, &mut ()).unwrap();
        bus.fail_next(1);
        cmd.counts[0] = 200;
        assert!(matches!(
            chip.cycle(&bus, &cmd, 0, &mut ()),
            Err(ChipFault::Bus(_))
        ));
        chip.cycle(&bus, &cmd, 0, &mut ()).unwrap();
        bus.with_chip::<Pca9685, _>(0x41, |c| assert_eq!(c.reg(led_on_l(0) + 2), 200));
        bus.with_chip::<Pca9685, _>(0x41, |c| c.power_cycle());
        let mut faults = 0;
        for _ in 0..super::super::CHECK_EVERY {
            if chip.cycle(&bus, &cmd, 0, &mut ()) == Err(ChipFault::LostConfig) {
                faults += 1;
            }
        }
        assert_eq!(faults, 1, "noticed at the next check");
    }
}
