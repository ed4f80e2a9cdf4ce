//! IOPort (hardware.md 5.9.1): every I/O pin's HAL presence and the
//! port registers.
//!
//! Every pin has `gpio.NNN.in` and `.in_not` (canonical digital input,
//! LinuxCNC's `in_not` spelling). A full GPIO also has the canonical
//! digital output (`out`, with `invert_output` as its `invert`) and the
//! params `is_output` and `is_opendrain`. A module output pin has
//! `invert_output` and `is_opendrain`, aliased as
//! `<module>.<NN>.<function>.invert_output` (and `.is_opendrain`).
//!
//! A full GPIO's inversion is applied to the Data bit (the canonical
//! digital output's level); a module output's in the OutputInvert
//! register, since the module, not the latch, drives it. Pins look the
//! same from outside either way. Module output pins become outputs at
//! the first `write`, not at load, so nothing is driven before the HAL
//! thread runs. `OpenDrain` is set only for pins that are outputs, so an
//! input never pulls its line low.

use canonical::{ChannelNames, DigIn, DigOut};
use hal_core::{HalHost, HostParam, Ours, PinFactory, Result as HalResult, Rw};

use crate::firmware::ModuleUse;
use crate::md::ModuleDescriptor;
use crate::modules::{put, Export};
use crate::pins::{self, IoPin, PinOwner};
use crate::regs::{ioport as r, MAX_CONNECTORS};
use crate::tram::Slot;
use crate::transport::{Transport, TransportError};

/// HAL objects of one I/O pin.
struct GpioPin<H: HalHost = Ours> {
    io: IoPin,
    input: DigIn<H>,
    /// Full GPIO only: the canonical digital output and `is_output`.
    output: Option<(DigOut<H>, H::Param<bool, Rw>)>,
    /// Full GPIO and module outputs: `is_opendrain`.
    opendrain: Option<H::Param<bool, Rw>>,
    /// Module outputs: `invert_output` (for GPIO it is the DigOut's).
    module_invert: Option<H::Param<bool, Rw>>,
    /// A module output driven from load on, not from the first `write`
    /// (Smart Serial: the links run before the HAL thread does).
    immediate: bool,
}

/// The register values derived from the pins, per port.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PortRegs {
    /// Data direction.
    pub ddr: u32,
    /// Alternate source.
    pub alt_source: u32,
    /// Open drain.
    pub open_drain: u32,
    /// Output invert.
    pub invert: u32,
}

/// Reads one register's value out of a [`PortRegs`].
type RegField = fn(&PortRegs) -> u32;

/// Output pins of one module function: (module tag, unit, function) and their I/O numbers.
type OutputGroup = ((u8, Option<u8>, u8), Vec<u32>);

/// The IOPort module.
pub struct IoPort<H: HalHost = Ours> {
    md: ModuleDescriptor,
    ports: usize,
    pins: Vec<GpioPin<H>>,
    data_read: Slot,
    data_write: Slot,
    written: Vec<PortRegs>,
    scratch: Vec<PortRegs>,
    gpio_words: Vec<u32>,
    started: bool,
}

/// GPIO item names: canonical items with LinuxCNC's hm2 spellings.
fn gpio_names(prefix: &str) -> ChannelNames {
    let prefix = prefix.to_string();
    ChannelNames::custom(move |io, item| {
        let item = match item {
            "in-not" => "in_not",
            "invert" => "invert_output",
            other => other,
        };
        format!("{prefix}.gpio.{io:03}.{item}")
    })
}

impl<H: HalHost> IoPort<H> {
    /// Exports every pin and registers the data regions.
    pub fn export<F: PinFactory<H>>(
        x: &mut Export<'_, F>,
        m: &ModuleUse,
        io_pins: &[IoPin],
    ) -> HalResult<IoPort<H>> {
        let names = gpio_names(x.prefix);
        let mut pins = Vec::with_capacity(io_pins.len());
        for p in io_pins {
            let io = p.io as usize;
            let input = DigIn::export(x.comp, &names, io)?;
            let (output, opendrain, module_invert) = match p.owner {
                PinOwner::Gpio => {
                    let out = DigOut::export(x.comp, &names, io)?;
                    let od = x.comp.param(&names.item(io, "is_opendrain"), false)?;
                    let is_out = x.comp.param(&names.item(io, "is_output"), false)?;
                    (Some((out, is_out)), Some(od), None)
                }
                PinOwner::Module { output: true, .. } => {
                    let inv = x.comp.param(&names.item(io, "invert_output"), false)?;
                    let od = x.comp.param(&names.item(io, "is_opendrain"), false)?;
                    (None, Some(od), Some(inv))
                }
                PinOwner::Module { .. } => (None, None, None),
            };
            pins.push(GpioPin {
                io: *p,
                input,
                output,
                opendrain,
                module_invert,
                immediate: matches!(
                    p.owner,
                    PinOwner::Module {
                        gtag: crate::regs::gtag::SSERIAL,
                        ..
                    }
                ),
            });
        }
        alias_module_outputs(x, io_pins)?;
        let ports = m.instances as usize;
        let data_read = x.tram.add_read(m.md.reg(r::DATA), ports);
        let data_write = x.tram.add_write(m.md.reg(r::DATA), ports);
        Ok(IoPort {
            md: m.md,
            ports,
            pins,
            data_read,
            data_write,
            written: vec![PortRegs::default(); ports],
            scratch: vec![PortRegs::default(); ports],
            gpio_words: vec![0; ports],
            started: false,
        })
    }

    /// The register values the pins ask for now, into `out` (one per port).
    pub fn wanted(&self, out: &mut [PortRegs]) {
        out.fill(PortRegs::default());
        for p in &self.pins {
            if let Some(regs) = out.get_mut(p.io.port as usize) {
                self.accumulate(p, regs);
            }
        }
    }

    #[inline]
    fn accumulate(&self, p: &GpioPin<H>, regs: &mut PortRegs) {
        let bit = 1u32 << p.io.bit;
        let od = p.opendrain.as_ref().is_some_and(|o| o.get());
        match (&p.output, &p.module_invert) {
            (Some((_, is_output)), _) => {
                if is_output.get() {
                    regs.ddr |= bit;
                    if od {
                        regs.open_drain |= bit;
                    }
                }
            }
            (None, Some(inv)) => {
                regs.alt_source |= bit;
                if self.started || p.immediate {
                    regs.ddr |= bit;
                    if od {
                        regs.open_drain |= bit;
                    }
                }
                if inv.get() {
                    regs.invert |= bit;
                }
            }
            (None, None) => regs.alt_source |= bit,
        }
    }

    /// Writes every configuration register: invert, open drain,
    /// alternate source, then direction last to avoid glitches. No
    /// allocation: it also runs in `write` when a board recovers.
    pub fn force_write(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        let mut want = std::mem::take(&mut self.written);
        self.wanted(&mut want);
        let mut words = [0u32; MAX_CONNECTORS];
        let words = &mut words[..self.ports];
        let fields: [(usize, RegField); 4] = [
            (r::OUTPUT_INVERT, |p| p.invert),
            (r::OPEN_DRAIN, |p| p.open_drain),
            (r::ALT_SOURCE, |p| p.alt_source),
            (r::DDR, |p| p.ddr),
        ];
        let mut result = Ok(());
        for (reg, get) in fields {
            for (w, p) in words.iter_mut().zip(&want) {
                *w = get(p);
            }
            result = result.and_then(|()| t.queue_write(self.md.reg(reg), words));
        }
        self.written = want;
        result
    }

    /// Marks the module outputs as driven from now on (the first `write`).
    pub fn start(&mut self) {
        self.started = true;
    }

    /// Queues the configuration registers that changed.
    pub fn write_config(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        let mut want = std::mem::take(&mut self.scratch);
        self.wanted(&mut want);
        let mut result = Ok(());
        for (port, (w, had)) in want.iter().zip(self.written.iter_mut()).enumerate() {
            let inst = |reg| self.md.inst_reg(reg, port);
            for (reg, new, old) in [
                (r::OPEN_DRAIN, w.open_drain, had.open_drain),
                (r::OUTPUT_INVERT, w.invert, had.invert),
                (r::ALT_SOURCE, w.alt_source, had.alt_source),
                (r::DDR, w.ddr, had.ddr),
            ] {
                if new != old {
                    result = result.and_then(|()| put(t, inst(reg), new));
                }
            }
            *had = *w;
        }
        self.scratch = want;
        result
    }

    /// Fills the Data words (one per port) with the GPIO outputs.
    #[inline]
    fn data_words(&self, data: &mut [u32]) {
        data.fill(0);
        for p in &self.pins {
            if let Some((out, _)) = &p.output {
                if out.level() {
                    data[p.io.port as usize] |= 1 << p.io.bit;
                }
            }
        }
    }

    /// Fills this module's TRAM write words.
    #[inline]
    pub fn prepare_write(&self, buf: &mut [u32]) {
        self.data_words(self.data_write.of_mut(buf));
    }

    /// Publishes every pin's level from this module's TRAM read words.
    #[inline]
    pub fn process_read(&self, buf: &[u32]) {
        self.publish(self.data_read.of(buf));
    }

    fn publish(&self, data: &[u32]) {
        for p in &self.pins {
            p.input
                .update(data[p.io.port as usize] & (1 << p.io.bit) != 0);
        }
    }

    /// `read_gpio`: reads the Data registers outside TRAM.
    pub fn read_gpio(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        let mut words = std::mem::take(&mut self.gpio_words);
        let r = t.read(self.md.reg(r::DATA), &mut words);
        if r.is_ok() {
            self.publish(&words);
        }
        self.gpio_words = words;
        r
    }

    /// `write_gpio`: writes the Data registers and the changed
    /// configuration outside TRAM.
    pub fn write_gpio(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        let mut words = std::mem::take(&mut self.gpio_words);
        self.data_words(&mut words);
        let r = t.write(self.md.reg(r::DATA), &words);
        self.gpio_words = words;
        r?;
        self.write_config(t)
    }

    /// Safe state without a watchdog to bite: every pin an input, no
    /// open drain pulling low (written at once, outside the queue).
    pub fn go_safe(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        let zeros = [0u32; MAX_CONNECTORS];
        t.write(self.md.reg(r::DDR), &zeros[..self.ports])?;
        t.write(self.md.reg(r::OPEN_DRAIN), &zeros[..self.ports])?;
        for w in &mut self.written {
            w.ddr = 0;
            w.open_drain = 0;
        }
        self.started = false;
        Ok(())
    }
}

/// Creates `<module>.<NN>[.<k>].<function>.invert_output` and
/// `.is_opendrain` aliases for the module output pins.
fn alias_module_outputs<H: HalHost, F: PinFactory<H>>(
    x: &Export<'_, F>,
    io_pins: &[IoPin],
) -> HalResult<()> {
    let mut groups: Vec<OutputGroup> = Vec::new();
    for p in io_pins {
        if let PinOwner::Module {
            gtag,
            unit,
            function,
            output: true,
        } = p.owner
        {
            let key = (gtag, unit, function);
            match groups.iter_mut().find(|(k, _)| *k == key) {
                Some((_, v)) => v.push(p.io),
                None => groups.push((key, vec![p.io])),
            }
        }
    }
    for ((tag, unit, function), ios) in groups {
        let (Some(module), Some(fname)) = (
            pins::hal_module_name(tag),
            pins::hal_function_name(tag, function),
        ) else {
            continue;
        };
        let unit = unit.map_or("all".to_string(), |u| format!("{u:02}"));
        for (k, io) in ios.iter().enumerate() {
            let stem = if ios.len() > 1 {
                format!("{}.{module}.{unit}.{k}.{fname}", x.prefix)
            } else {
                format!("{}.{module}.{unit}.{fname}", x.prefix)
            };
            for item in ["invert_output", "is_opendrain"] {
                x.comp.alias_param(
                    &format!("{}.gpio.{io:03}.{item}", x.prefix),
                    &format!("{stem}.{item}"),
                )?;
            }
        }
    }
    Ok(())
}
