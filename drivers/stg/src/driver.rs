//! One Servo-To-Go at register level: initialisation, counters, index
//! registers, DACs, ADC and digital ports. No HAL here: values in, values
//! out. Every access stays inside the board's two windows.

use std::sync::atomic::{AtomicU8, Ordering::Relaxed};
use std::sync::Arc;

use hal_driver::bus::PortBus;
use hal_driver::sim::Clock;

use crate::detect::Model;
use crate::dio::Dio;
use crate::regs;

/// How long the ADC multiplexer settles before a conversion starts.
pub const MUX_SETTLE_NS: u64 = 4_000;

/// A board's registers.
pub struct Stg {
    bus: Arc<dyn PortBus>,
    base: u16,
    model: Model,
    dio: Dio,
    settle_clock: Arc<dyn Clock>,
    /// Model I: INTC as last written. Model II: CNTRL0.
    control: AtomicU8,
}

impl std::fmt::Debug for Stg {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Stg")
            .field("bus", &self.bus.describe())
            .field("base", &format_args!("{:#x}", self.base))
            .field("model", &self.model)
            .field("dio", &self.dio.to_string())
            .finish()
    }
}

impl Stg {
    /// A `model` board at `base` on `bus`, its digital ports set up as
    /// `dio`; `settle_clock` times the ADC multiplexer's settling.
    pub fn new(
        bus: Arc<dyn PortBus>,
        base: u16,
        model: Model,
        dio: Dio,
        settle_clock: Arc<dyn Clock>,
    ) -> Stg {
        Stg {
            bus,
            base,
            model,
            dio,
            settle_clock,
            control: AtomicU8::new(0),
        }
    }

    /// The bus.
    pub fn bus(&self) -> &Arc<dyn PortBus> {
        &self.bus
    }

    /// The base address.
    pub fn base(&self) -> u16 {
        self.base
    }

    /// Model I or II.
    pub fn model(&self) -> Model {
        self.model
    }

    /// The digital ports' directions.
    pub fn dio(&self) -> Dio {
        self.dio
    }

    #[inline]
    fn port(&self, off: u16) -> u16 {
        self.base.wrapping_add(off)
    }

    #[inline]
    fn out(&self, off: u16, v: u8) {
        self.bus.outb(self.port(off), v);
    }

    #[inline]
    fn inp(&self, off: u16) -> u8 {
        self.bus.inb(self.port(off))
    }

    /// The model's initialisation (hardware.md §3.8): interrupt or index
    /// registers, digital port directions, every counter in x4 with the
    /// index loading its latch, every DAC at 0 V. On a Model I the 8259
    /// is told to return IRR on reads, at its own address (LinuxCNC
    /// wrote that command to port 0x0a by mistake).
    pub fn init(&self) {
        let abc = self.dio.abc_control();
        let d = self.dio.d_control(self.model.is_two());
        match self.model {
            Model::One => {
                let intc = regs::INTC_AUTOZERO | regs::IRQ5;
                self.out(regs::D_DIR, regs::MODEL1_D_IN);
                self.set_intc(intc);
                self.out(regs::IRR_OR_IDLEN, regs::PIC_ICW1);
                self.out(regs::IMR_OR_SELDI, 0x00); // ICW2
                self.out(regs::IMR_OR_SELDI, 0xFF); // mask everything
                self.out(regs::IRR_OR_IDLEN, regs::PIC_READ_IRR);
                self.out(regs::ABC_DIR, abc);
                // Programming 8255 #2 clears INTC: mask interrupts
                // meanwhile, restore INTC after.
                self.out(regs::IMR_OR_SELDI, 0xFF);
                self.out(regs::D_DIR, d);
                self.set_intc(intc);
                self.out(regs::IMR_OR_SELDI, 0xFF);
            }
            Model::Two => {
                let cntrl0 = regs::CNTRL0_AUTOZERO | regs::CNTRL0_CAL | regs::IRQ5;
                self.out(regs::D_DIR, regs::MODEL2_D_IN);
                self.out(regs::IRR_OR_IDLEN, 0);
                self.out(regs::IMR_OR_SELDI, 0);
                self.set_cntrl0(cntrl0);
                self.out(regs::ABC_DIR, abc);
                let cntrl1 = self.inp(regs::CNTRL1);
                self.out(regs::CNTRL1, 0xFF);
                self.out(regs::D_DIR, d);
                self.set_cntrl0(cntrl0);
                self.out(regs::CNTRL1, (cntrl1 & 0x0F) | 0xF0);
                self.out(regs::IDL, 0);
            }
        }
        for k in 0..regs::CHANNELS {
            let ctl = regs::counter_control(k);
            for cmd in [
                regs::LS_RESET,
                regs::LS_ICR_INDEX_LOADS_OL,
                regs::LS_OCCR_DEFAULT,
                regs::LS_QR_X4,
            ] {
                self.out(ctl, cmd);
            }
        }
        self.zero_dacs();
        if self.model == Model::One {
            self.out(regs::D_DIR, regs::MODEL1_AUTOZERO_ON);
        }
    }

    fn set_intc(&self, v: u8) {
        self.out(regs::INTC_OR_PORT_D, v);
        self.control.store(v, Relaxed);
    }

    fn set_cntrl0(&self, v: u8) {
        self.out(regs::PORT_D_OR_CNTRL0, v);
        self.control.store(v, Relaxed);
    }

    /// Reads the board test register once (advances the signature; on a
    /// Model I clears the even axis's index latch).
    #[inline]
    pub fn brdtst(&self) -> u8 {
        self.inp(regs::BRDTST)
    }

    /// Counter `k` now: CNTR to OL, then its three bytes.
    #[inline]
    pub fn latch_count(&self, k: usize) -> u32 {
        self.out(regs::counter_control(k), regs::LS_LATCH);
        self.read_bytes(k)
    }

    /// Counter `k`'s latch as the index left it (no latch command).
    #[inline]
    pub fn index_count(&self, k: usize) -> u32 {
        self.out(regs::counter_control(k), regs::LS_RESET_POINTER);
        self.read_bytes(k)
    }

    #[inline]
    fn read_bytes(&self, k: usize) -> u32 {
        let data = regs::counter_data(k);
        let b0 = self.inp(data) as u32;
        let b1 = self.inp(data) as u32;
        let b2 = self.inp(data) as u32;
        b0 | b1 << 8 | b2 << 16
    }

    /// Writes DAC `n`'s word.
    #[inline]
    pub fn write_dac(&self, n: usize, word: u16) {
        self.bus.outw(self.port(regs::dac(n)), word);
    }

    /// Every DAC to 0 V.
    pub fn zero_dacs(&self) {
        for n in 0..regs::CHANNELS {
            self.write_dac(n, regs::DAC_ZERO);
        }
    }

    /// Reads digital port `p` (A = 0 .. D = 3).
    #[inline]
    pub fn read_port(&self, p: usize) -> u8 {
        self.inp(regs::dio_ports(self.model.is_two())[p])
    }

    /// Writes digital port `p`.
    #[inline]
    pub fn write_port(&self, p: usize, v: u8) {
        self.out(regs::dio_ports(self.model.is_two())[p], v);
    }

    /// Model II: the axes whose index may latch.
    #[inline]
    pub fn set_index_enables(&self, mask: u8) {
        self.out(regs::IRR_OR_IDLEN, mask);
    }

    /// Model II: the latched index flags.
    #[inline]
    pub fn index_flags(&self) -> u8 {
        self.inp(regs::IDL)
    }

    /// Model II: clears every latched index flag.
    #[inline]
    pub fn clear_index_flags(&self) {
        self.out(regs::IDL, 0);
    }

    /// Model I: the 8259's IRR (latched and live index of the selected
    /// pair, end of conversion).
    #[inline]
    pub fn irr(&self) -> u8 {
        self.inp(regs::IRR_OR_IDLEN)
    }

    /// Model I: watches the index of axis pair `pair` (axes 2·pair and
    /// 2·pair + 1) at the level `active_high`; writes INTC only when
    /// that changes it.
    #[inline]
    pub fn select_index_pair(&self, pair: usize, active_high: bool) {
        let old = self.control.load(Relaxed);
        let mut v = old & !(3 << regs::INTC_IXS_SHIFT | regs::INTC_IXLVL);
        v |= ((pair & 3) as u8) << regs::INTC_IXS_SHIFT;
        if active_high {
            v |= regs::INTC_IXLVL;
        }
        if v != old {
            self.set_intc(v);
        }
    }

    /// Model I: clears both index latches of the selected pair (odd,
    /// then even); returns the board test byte the even clear read.
    #[inline]
    pub fn clear_index_latches(&self) -> u8 {
        self.inp(regs::D_DIR);
        self.brdtst()
    }

    /// Whether the conversion started last is done: Model I end of
    /// conversion in IRR, Model II busy clear in BRDTST.
    #[inline]
    pub fn adc_done(&self) -> bool {
        match self.model {
            Model::One => self.irr() & regs::IRR_EOC != 0,
            Model::Two => self.brdtst() & regs::BRDTST_ADC_BUSY == 0,
        }
    }

    /// ADC channel `n`'s result, as a signed count.
    #[inline]
    pub fn adc_result(&self, n: usize) -> i32 {
        regs::adc_count(self.bus.inw(self.port(regs::adc(n))))
    }

    /// Selects ADC channel `n`, lets the multiplexer settle, and starts
    /// a conversion.
    #[inline]
    pub fn adc_start(&self, n: usize) {
        match self.model {
            Model::One => {
                self.bus.inw(self.port(regs::adc(n)));
                self.settle();
                self.bus.outw(self.port(regs::adc(n)), 0);
            }
            Model::Two => {
                let old = self.control.load(Relaxed);
                let v = (old & 0x07)
                    | (n as u8 & 7) << regs::CNTRL0_MUX_SHIFT
                    | regs::CNTRL0_AUTOZERO
                    | regs::CNTRL0_CAL;
                self.set_cntrl0(v);
                self.settle();
                self.bus.outw(self.port(regs::adc(0)), 0);
            }
        }
    }

    /// Waits [`MUX_SETTLE_NS`] on the settle clock (LinuxCNC wrote to
    /// port 0x80 four times instead; this driver touches no port but the
    /// board's).
    fn settle(&self) {
        let start = self.settle_clock.now_ns();
        while self.settle_clock.now_ns().wrapping_sub(start) < MUX_SETTLE_NS {
            std::hint::spin_loop();
        }
    }
}

#[cfg(test)]
mod tests;
