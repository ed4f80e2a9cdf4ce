//! One board's realtime side: its read and write caches, the registers
//! each function moves (as bitmaps, so a run of registers is one address
//! cycle), and the blocks that turn them into pins.

use hal_core::{HalHost, PinFactory, Result};

use super::digital::{Dins, Douts};
use super::encoder::Encoders;
use super::outputs::{Dacs, Extra, Pwms, Stepgens};
use crate::epp::{block, Epp};
use crate::open::{ExtraUse, Planned};
use crate::regs::{dac, enc, pwm, stepgen, uxc, SLOT_SIZE, SPAN};
use crate::scan::Kind;

/// How many channels of each kind a bus has numbered so far.
#[derive(Debug, Clone, Copy, Default)]
pub struct Numbers {
    encoders: usize,
    dacs: usize,
    stepgens: usize,
    pwms: usize,
    dins: usize,
    douts: usize,
    dac8s: usize,
}

/// One board.
pub struct Slot<H: HalHost> {
    base: u8,
    read_map: u32,
    write_map: u32,
    rd: [u8; SPAN],
    wr: [u8; SPAN],
    strobe: bool,
    enc: Option<Encoders<H>>,
    din: Option<Dins<H>>,
    dout: Option<Douts<H>>,
    dac: Option<Dacs<H>>,
    step: Option<Stepgens<H>>,
    pwm: Option<Pwms<H>>,
    extra: Option<Extra<H>>,
}

impl<H: HalHost> Slot<H> {
    /// Exports board `p`'s pins on bus `bus`, numbering its channels
    /// after those of `n`.
    pub fn export(
        c: &impl PinFactory<H>,
        bus: usize,
        p: &Planned,
        n: &mut Numbers,
    ) -> Result<Self> {
        let id = p.found.id;
        let mut s = Slot {
            base: p.found.slot as u8 * SLOT_SIZE,
            read_map: 0,
            write_map: 0,
            rd: [0; SPAN],
            wr: [0; SPAN],
            strobe: p.strobe,
            enc: None,
            din: None,
            dout: None,
            dac: None,
            step: None,
            pwm: None,
            extra: None,
        };
        if id.kind.is_uxc() {
            let d = Dins::uxc(c, bus, n.dins)?;
            s.read_map |= d.read_map();
            s.din = Some(d);
            n.dins += 16;
            let o = Douts::uxc(c, bus, n.douts)?;
            s.write_map |= o.write_map();
            s.dout = Some(o);
            n.douts += 8;
        }
        match id.kind {
            Kind::Dio => {
                let d = Dins::dio(c, bus, n.dins, p.estop_master)?;
                s.read_map |= d.read_map();
                s.din = Some(d);
                n.dins += 16;
                let o = Douts::dio(c, bus, n.douts, p.estop_master)?;
                s.write_map |= o.write_map();
                s.dout = Some(o);
                n.douts += 8;
            }
            Kind::Dac => {
                s.dac = Some(Dacs::export(c, bus, n.dacs)?);
                s.write_map |= block(dac::DAC0, dac::DAC0 + 7);
                n.dacs += 4;
            }
            Kind::Usc => {
                s.step = Some(Stepgens::export(c, bus, n.stepgens)?);
                s.write_map |= block(stepgen::RATE0, stepgen::WIDTH);
                n.stepgens += 4;
            }
            Kind::Upc => {
                s.pwm = Some(Pwms::export(c, bus, n.pwms, id.rev)?);
                s.write_map |= block(pwm::GEN0, pwm::GEN0 + 7) | block(pwm::CTRL, pwm::FREQ_HI);
                n.pwms += 4;
            }
            Kind::Encoder => {}
        }
        match p.extra {
            ExtraUse::None => {}
            ExtraUse::Dac => {
                s.extra = Some(Extra::dac(c, bus, n.dac8s)?);
                n.dac8s += 1;
            }
            ExtraUse::Douts => {
                s.extra = Some(Extra::douts(c, bus, n.douts)?);
                n.douts += 8;
            }
        }
        if s.extra.is_some() {
            s.write_map |= block(uxc::EXTRA, uxc::EXTRA);
        }
        if id.kind.has_encoders() {
            s.enc = Some(Encoders::export(
                c,
                bus,
                n.encoders,
                id.has_index(),
                p.timestamp,
            )?);
            n.encoders += 4;
            s.read_map |= block(enc::COUNT0, enc::ISR);
            if p.timestamp {
                s.read_map |= block(enc::TS0, enc::TB + 1);
            }
            if id.has_index() {
                s.write_map |= block(enc::INDEX, enc::INDEX);
            }
        }
        Ok(s)
    }

    /// Strobes the counters (the bus's master board) and reads the
    /// board's registers into the cache.
    #[inline]
    pub fn fetch(&mut self, epp: &Epp) {
        if self.strobe {
            let rate = self.base + enc::RATE;
            // Twice: the strobe must last at least 2 us.
            epp.select_write(rate, enc::RATE_STROBE);
            epp.select_write(rate, enc::RATE_STROBE);
            epp.select_write(rate, 0);
        }
        epp.read_map(self.base, self.read_map, &mut self.rd);
    }

    /// Takes the first reading as the counters' reference.
    pub fn prime(&mut self) {
        if let Some(e) = self.enc.as_mut() {
            e.prime(&self.rd);
        }
    }

    /// Publishes the cached readings of a period of `period_s`.
    #[inline]
    pub fn publish(&mut self, period_s: f64) {
        if let Some(e) = self.enc.as_mut() {
            e.read(&self.rd, period_s);
        }
        if let Some(d) = &self.din {
            d.read(&self.rd);
        }
    }

    /// Computes the outputs into the cache and writes them.
    #[inline]
    pub fn write(&mut self, epp: &Epp) {
        let wr = &mut self.wr;
        if let Some(e) = self.enc.as_mut() {
            wr[enc::INDEX as usize] = e.index_bits();
        }
        if let Some(o) = &self.dout {
            o.write(wr);
        }
        if let Some(d) = &self.dac {
            d.write(wr);
        }
        if let Some(s) = &self.step {
            s.write(wr);
        }
        if let Some(p) = self.pwm.as_mut() {
            p.write(wr);
        }
        if let Some(x) = &self.extra {
            x.write(wr);
        }
        epp.write_map(self.base, self.write_map, &self.wr);
    }
}
