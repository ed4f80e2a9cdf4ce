//! The ADS1115 driver: up to four analog inputs, converted one after the
//! other in single-shot mode.
//!
//! Set-up: CONFIG = single shot, powered down, comparator off, the first
//! channel's multiplexer, the gain and the rate; read back to check the
//! chip took it. A conversion: CONFIG with OS = 1 (start), then, no
//! earlier than the nominal conversion time (1 / rate), CONFIG is read
//! until OS reads 1 (idle), then CONVERSION. The next channel's
//! conversion starts in the same helper cycle. Registers are big-endian
//! and SMBus words little-endian: every word is byte-swapped. A
//! conversion not done after ten times its nominal time (plus 10 ms) is
//! a fault.

use super::{Chip, ChipFault};
use crate::bus::I2cBus;
use crate::regs::ads1115::*;

/// What the channels are: single-ended AIN0.. or differential pairs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AdcSettings {
    /// Channels converted (1..=4 single-ended, 1..=2 differential).
    pub channels: usize,
    /// Channel 0 = AIN0 − AIN1, channel 1 = AIN2 − AIN3.
    pub differential: bool,
    /// PGA code.
    pub pga: u16,
    /// Data rate code.
    pub dr: u16,
}

impl AdcSettings {
    /// The multiplexer code of channel `ch`.
    pub fn mux(&self, ch: usize) -> u16 {
        if self.differential {
            if ch == 0 {
                MUX_DIFF_0_1
            } else {
                MUX_DIFF_2_3
            }
        } else {
            MUX_SINGLE_0 + ch as u16
        }
    }

    /// CONFIG for a single-shot conversion of channel `ch` (OS not set).
    pub fn config(&self, ch: usize) -> u16 {
        (self.mux(ch) << MUX_SHIFT)
            | (self.pga << PGA_SHIFT)
            | MODE_SINGLE
            | (self.dr << DR_SHIFT)
            | COMP_QUE_OFF
    }

    /// Volts per count.
    pub fn lsb_volts(&self) -> f64 {
        lsb_volts(self.pga)
    }
}

/// The latest reading of every channel.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AdcSample {
    /// Conversion results by channel.
    pub counts: [i16; 4],
    /// Conversions finished by channel.
    pub conversions: [u32; 4],
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    Idle,
    Converting { ch: usize, since_ns: u64 },
}

/// One ADS1115.
#[derive(Debug, Clone)]
pub struct Ads1115Chip {
    addr: u8,
    settings: AdcSettings,
    state: State,
    next: usize,
}

/// Big-endian register words over little-endian SMBus words.
fn write_reg(bus: &dyn I2cBus, addr: u8, reg: u8, v: u16) -> Result<(), ChipFault> {
    Ok(bus.write_word_data(addr, reg, v.swap_bytes())?)
}

fn read_reg(bus: &dyn I2cBus, addr: u8, reg: u8) -> Result<u16, ChipFault> {
    Ok(bus.read_word_data(addr, reg)?.swap_bytes())
}

impl Ads1115Chip {
    /// A chip at `addr` with `settings`.
    pub fn new(addr: u8, settings: AdcSettings) -> Ads1115Chip {
        Ads1115Chip {
            addr,
            settings,
            state: State::Idle,
            next: 0,
        }
    }

    /// The settings.
    pub fn settings(&self) -> &AdcSettings {
        &self.settings
    }

    fn start(&mut self, bus: &dyn I2cBus, ch: usize, now_ns: u64) -> Result<(), ChipFault> {
        self.state = State::Idle;
        write_reg(bus, self.addr, CONFIG, self.settings.config(ch) | OS)?;
        self.state = State::Converting {
            ch,
            since_ns: now_ns,
        };
        Ok(())
    }
}

impl Chip for Ads1115Chip {
    type Cmd = ();
    type Sample = AdcSample;

    fn address(&self) -> u8 {
        self.addr
    }

    fn init(&mut self, bus: &dyn I2cBus, _safe: &()) -> Result<(), ChipFault> {
        self.state = State::Idle;
        self.next = 0;
        let cfg = self.settings.config(0);
        write_reg(bus, self.addr, CONFIG, cfg)?;
        if read_reg(bus, self.addr, CONFIG)? & !OS != cfg {
            return Err(ChipFault::LostConfig);
        }
        Ok(())
    }

    fn cycle(
        &mut self,
        bus: &dyn I2cBus,
        _cmd: &(),
        now_ns: u64,
        sample: &mut AdcSample,
    ) -> Result<(), ChipFault> {
        let State::Converting { ch, since_ns } = self.state else {
            return self.start(bus, self.next, now_ns);
        };
        let nominal = conversion_ns(self.settings.dr);
        let waited = now_ns.saturating_sub(since_ns);
        if waited < nominal {
            return Ok(());
        }
        let cfg = read_reg(bus, self.addr, CONFIG)?;
        if cfg & OS == 0 {
            if waited > 10 * nominal + 10_000_000 {
                self.state = State::Idle;
                return Err(ChipFault::Stuck);
            }
            return Ok(());
        }
        if cfg & !OS != self.settings.config(ch) {
            self.state = State::Idle;
            return Err(ChipFault::LostConfig);
        }
        let counts = read_reg(bus, self.addr, CONVERSION)? as i16;
        sample.counts[ch] = counts;
        sample.conversions[ch] = sample.conversions[ch].wrapping_add(1);
        self.next = (ch + 1) % self.settings.channels;
        self.start(bus, self.next, now_ns)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Ads1115, Kind, SimBus};
    use hal_driver::sim::SimClock;
    use std::sync::Arc;

    fn rig(settings: AdcSettings) -> (SimBus, Ads1115Chip) {
        let bus = SimBus::new("sim", Arc::new(SimClock::new(0, 0)));
        bus.add_chip(0x48, Box::new(Ads1115::new()));
        (bus, Ads1115Chip::new(0x48, settings))
    }

    const FOUR: AdcSettings = AdcSettings {
        channels: 4,
        differential: false,
        pga: 1,
        dr: 7,
    };

    /// Runs helper cycles of `step` ns until every channel converted
    /// `n` times.
    fn run(bus: &SimBus, chip: &mut Ads1115Chip, s: &mut AdcSample, step: u64, n: u32) {
        for _ in 0..10_000 {
            bus.advance(step);
            chip.cycle(bus, &(), bus.now_ns(), s).unwrap();
            if s.conversions[..chip.settings.channels]
                .iter()
                .all(|&c| c >= n)
            {
                return;
            }
        }
        panic!("conversions did not finish: {s:?}");
    }

    #[test]
    fn set_up_and_one_conversion_on_the_wire() {
        let (bus, mut chip) = rig(FOUR);
        chip.init(&bus, &()).unwrap();
        let cfg0 = FOUR.config(0);
        // MUX 100 (AIN0), PGA 001, single shot, DR 111, comparator off.
        assert_eq!(cfg0, 0x43E3);
        let t = bus.transfers();
        assert_eq!(
            (t[0].kind, t[0].reg, t[0].bytes()),
            (
                Kind::WriteWord,
                CONFIG,
                &cfg0.swap_bytes().to_le_bytes()[..]
            )
        );
        assert_eq!(
            t[0].bytes(),
            &cfg0.to_be_bytes()[..],
            "MSB first on the wire"
        );
        bus.with_chip::<Ads1115, _>(0x48, |c| c.set_input(0, 1.0));
        bus.clear_log();
        let mut s = AdcSample::default();
        chip.cycle(&bus, &(), bus.now_ns(), &mut s).unwrap();
        bus.advance(conversion_ns(7) / 2);
        chip.cycle(&bus, &(), bus.now_ns(), &mut s).unwrap();
        assert_eq!(bus.transfers().len(), 1, "no poll before the nominal time");
        bus.advance(conversion_ns(7));
        chip.cycle(&bus, &(), bus.now_ns(), &mut s).unwrap();
        let t: Vec<_> = bus.transfers().iter().map(|t| (t.kind, t.reg)).collect();
        assert_eq!(
            t,
            vec![
                (Kind::WriteWord, CONFIG),
                (Kind::ReadWord, CONFIG),
                (Kind::ReadWord, CONVERSION),
                (Kind::WriteWord, CONFIG),
            ]
        );
        assert_eq!(s.counts[0], code_for(1.0, 4.096));
        assert_eq!(s.conversions, [1, 0, 0, 0]);
    }

    #[test]
    fn every_channel_scaled_by_its_gain() {
        let (bus, mut chip) = rig(FOUR);
        chip.init(&bus, &()).unwrap();
        let volts = [0.5, -0.25, 3.3, 5.0];
        bus.with_chip::<Ads1115, _>(0x48, |c| {
            for (n, v) in volts.iter().enumerate() {
                c.set_input(n, *v);
            }
        });
        let mut s = AdcSample::default();
        run(&bus, &mut chip, &mut s, 200_000, 2);
        for (n, v) in volts.iter().enumerate() {
            assert_eq!(s.counts[n], code_for(*v, 4.096), "AIN{n}");
        }
        assert_eq!(s.counts[3], 32767, "5 V clips at ±4.096 V");
        let lsb = chip.settings().lsb_volts();
        assert!((s.counts[0] as f64 * lsb - 0.5).abs() < lsb);
    }

    #[test]
    fn differential_pairs() {
        let settings = AdcSettings {
            channels: 2,
            differential: true,
            pga: 2,
            dr: 4,
        };
        let (bus, mut chip) = rig(settings);
        chip.init(&bus, &()).unwrap();
        bus.with_chip::<Ads1115, _>(0x48, |c| {
            c.set_input(0, 1.2);
            c.set_input(1, 0.2);
            c.set_input(2, 0.0);
            c.set_input(3, 0.5);
        });
        let mut s = AdcSample::default();
        run(&bus, &mut chip, &mut s, 1_000_000, 1);
        assert_eq!(s.counts[0], code_for(1.0, 2.048));
        assert_eq!(s.counts[1], code_for(-0.5, 2.048));
    }

    #[test]
    fn a_stuck_or_reset_chip_is_a_fault() {
        let (bus, mut chip) = rig(FOUR);
        chip.init(&bus, &()).unwrap();
        let mut s = AdcSample::default();
        chip.cycle(&bus, &(), bus.now_ns(), &mut s).unwrap();
        // The chip is reset mid-conversion: CONFIG reads its power-up
        // value, idle, with another multiplexer.
        bus.with_chip::<Ads1115, _>(0x48, |c| *c = Ads1115::new());
        bus.advance(conversion_ns(7));
        assert_eq!(
            chip.cycle(&bus, &(), bus.now_ns(), &mut s),
            Err(ChipFault::LostConfig)
        );
        // A chip that never finishes.
        chip.init(&bus, &()).unwrap();
        chip.cycle(&bus, &(), 0, &mut s).unwrap();
        let mut result = Ok(());
        for t in 1..100 {
            // The model's time stands still: the conversion never ends.
            result = chip.cycle(&bus, &(), t * 1_000_000, &mut s);
            if result.is_err() {
                break;
            }
        }
        assert_eq!(result, Err(ChipFault::Stuck));
    }
}
