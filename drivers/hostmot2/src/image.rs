//! Register images: a declarative firmware description ([`FirmwareSpec`])
//! that becomes the identification area, IDROM, module and pin
//! descriptors of a 64 KiB register window, and [`ImageTransport`], a
//! transport serving a fixed image whose writes are discarded (LinuxCNC's
//! `hm2_test` board, the fuzz target's board).

use crate::idrom::IdromHeader;
use crate::llio::Llio;
use crate::pins::PinDescriptor;
use crate::regs::{self, gtag, md as mdf};
use crate::transport::{
    check_window, ReadQueue, TransferStats, Transport, TransportError, WriteQueue,
};

/// Words in a register window.
pub const WINDOW_WORDS: usize = regs::WINDOW_BYTES / 4;

/// Which IDROM clock a module runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Clock {
    /// ClockLow (ClockTag 1).
    Low,
    /// ClockHigh (ClockTag 2).
    High,
}

/// One module of a firmware.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModuleSpec {
    /// General function tag.
    pub gtag: u8,
    /// Version.
    pub version: u8,
    /// Clock.
    pub clock: Clock,
    /// Instances.
    pub instances: u8,
    /// Base address.
    pub base: u16,
    /// Registers.
    pub num_registers: u8,
    /// MultipleRegisters bitmap.
    pub multiple_registers: u32,
    /// Which IDROM instance stride the module uses (0: 4 bytes, 1: 0x40).
    pub instance_stride_sel: u8,
}

impl ModuleSpec {
    /// A module with the register shape LinuxCNC expects of its GTag
    /// (IOPort, Watchdog, Encoder, StepGen, PWMGen, LED) at the
    /// conventional base address.
    pub fn standard(tag: u8, version: u8, instances: u8) -> ModuleSpec {
        let (base, regs, multiple, clock) = match tag {
            gtag::WATCHDOG => (0x0C00, 3, 0, Clock::Low),
            gtag::IOPORT => (0x1000, 5, 0x1F, Clock::Low),
            gtag::STEPGEN => (0x2000, 10, 0x1FF, Clock::Low),
            gtag::ENCODER => (0x3000, 5, 0x03, Clock::Low),
            gtag::PWMGEN => (0x4000, 5, 0x03, Clock::High),
            gtag::LED => (0x0200, 1, 0, Clock::Low),
            gtag::SSERIAL => (0x5A00, 6, 0x3C, Clock::Low),
            gtag::PKTUART_TX => (0x6000, 4, 0x0F, Clock::Low),
            gtag::PKTUART_RX => (0x6400, 4, 0x0F, Clock::Low),
            _ => (0x5000, 1, 0, Clock::Low),
        };
        ModuleSpec {
            gtag: tag,
            version,
            clock,
            instances,
            base,
            num_registers: regs,
            multiple_registers: multiple,
            // Smart Serial ports are 0x40 apart, the rest 4.
            instance_stride_sel: u8::from(tag == gtag::SSERIAL),
        }
    }

    /// Bytes between instances (the IDROM strides this crate's images use).
    pub fn instance_stride(&self) -> u32 {
        if self.instance_stride_sel == 1 {
            0x40
        } else {
            4
        }
    }

    /// The three descriptor words (both stride selectors 0).
    pub fn words(&self) -> [u32; 3] {
        let clock_tag = match self.clock {
            Clock::Low => mdf::CLOCK_LOW_TAG,
            Clock::High => mdf::CLOCK_HIGH_TAG,
        };
        [
            self.gtag as u32
                | (self.version as u32) << 8
                | (clock_tag as u32) << 16
                | (self.instances as u32) << 24,
            self.base as u32
                | (self.num_registers as u32) << 16
                | (self.instance_stride_sel as u32 & 0xF) << 28,
            self.multiple_registers,
        ]
    }
}

/// A firmware: board identity, IDROM values, modules and pin-out.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FirmwareSpec {
    /// The board type in HAL names (`5i25`).
    pub board: String,
    /// IDROM BoardName, 8 bytes (`MESA5I25`).
    pub board_name: [u8; 8],
    /// FPGA part, for the llio.
    pub fpga_part: String,
    /// FPGASize (KGates, informational).
    pub fpga_size: u32,
    /// FPGAPins (informational).
    pub fpga_pins: u32,
    /// Connector names.
    pub connectors: Vec<String>,
    /// Pins per connector.
    pub port_width: u32,
    /// LEDs on the board.
    pub leds: u32,
    /// ClockLow in Hz.
    pub clock_low: u32,
    /// ClockHigh in Hz.
    pub clock_high: u32,
    /// Modules, in descriptor order.
    pub modules: Vec<ModuleSpec>,
    /// One pin descriptor per I/O pin.
    pub pins: Vec<PinDescriptor>,
    /// The simulator's remote cards on Smart Serial channels (not part of
    /// the firmware's description: what is plugged in).
    pub remotes: Vec<crate::sim::sserial::RemoteSpec>,
}

/// Where the IDROM goes.
pub const IDROM_ADDR: u32 = regs::IDROM_DEFAULT_ADDR as u32;
/// Module descriptors, relative to the IDROM.
pub const MD_OFFSET: u32 = 0x40;
/// Pin descriptors, relative to the IDROM (room for 32 descriptors).
pub const PD_OFFSET: u32 = 0x1C0;

impl FirmwareSpec {
    /// The IDROM header this firmware serves.
    pub fn idrom(&self) -> IdromHeader {
        IdromHeader {
            addr: IDROM_ADDR,
            idrom_type: 3,
            offset_to_modules: MD_OFFSET,
            offset_to_pin_desc: PD_OFFSET,
            board_name: self.board_name,
            fpga_size: self.fpga_size,
            fpga_pins: self.fpga_pins,
            io_ports: self.connectors.len() as u32,
            io_width: self.pins.len() as u32,
            port_width: self.port_width,
            clock_low: self.clock_low,
            clock_high: self.clock_high,
            instance_stride: [4, 0x40],
            register_stride: [0x100, 0x100],
        }
    }

    /// The register image: identification, IDROM, descriptors; every
    /// other word 0.
    pub fn image(&self) -> Vec<u32> {
        let mut img = vec![0u32; WINDOW_WORDS];
        let mut put = |addr: u32, v: u32| img[addr as usize / 4] = v;
        put(regs::COOKIE_ADDR as u32, regs::COOKIE);
        put(regs::CONFIG_NAME_ADDR as u32, u32::from_le_bytes(*b"HOST"));
        put(
            regs::CONFIG_NAME_ADDR as u32 + 4,
            u32::from_le_bytes(*b"MOT2"),
        );
        put(regs::IDROM_OFFSET_ADDR as u32, IDROM_ADDR);
        for (i, w) in self.idrom().to_words().iter().enumerate() {
            put(IDROM_ADDR + 4 * i as u32, *w);
        }
        let mut addr = IDROM_ADDR + MD_OFFSET;
        for m in &self.modules {
            for w in m.words() {
                put(addr, w);
                addr += 4;
            }
        }
        for (i, p) in self.pins.iter().enumerate() {
            put(IDROM_ADDR + PD_OFFSET + 4 * i as u32, p.to_word());
        }
        img
    }

    /// The llio of board number `n` of this type.
    pub fn llio(&self, n: usize) -> Llio {
        Llio {
            name: format!("hm2_{}.{n}", self.board),
            connectors: self.connectors.clone(),
            pins_per_connector: self.port_width,
            num_leds: self.leds,
            fpga_part: self.fpga_part.clone(),
        }
    }

    /// The module of GTag `tag`, if present.
    pub fn module(&self, tag: u8) -> Option<&ModuleSpec> {
        self.modules.iter().find(|m| m.gtag == tag)
    }
}

/// Builds pin descriptors: `pd(tag, unit, sec_pin)`; `gpio()` for a plain pin.
pub fn pd(tag: u8, unit: u8, sec_pin: u8) -> PinDescriptor {
    PinDescriptor {
        sec_pin,
        sec_tag: tag,
        sec_unit: unit,
        primary_tag: regs::pd::PRIMARY_IOPORT,
    }
}

/// A plain GPIO pin descriptor.
pub fn gpio() -> PinDescriptor {
    pd(0, 0, 0)
}

/// A memory window that stores what is written: registers without a
/// board behind them (a benchmark of the driver alone, a stand-in for
/// shared memory in tests).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Memory(pub Vec<u32>);

impl hal_driver::sim::BoardModel for Memory {}

impl hal_driver::sim::MemModel for Memory {
    fn len(&self) -> usize {
        self.0.len() * 4
    }

    fn read32(&mut self, offset: usize) -> u32 {
        self.0.get(offset / 4).copied().unwrap_or(0)
    }

    fn write32(&mut self, offset: usize, value: u32) {
        if let Some(w) = self.0.get_mut(offset / 4) {
            *w = value;
        }
    }
}

/// A transport over a fixed register image: reads copy from it, writes
/// are discarded. LinuxCNC's `hm2_test` board works this way, and so does
/// the IDROM fuzz target.
#[derive(Debug, Clone)]
pub struct ImageTransport {
    image: Vec<u32>,
    reads: ReadQueue,
    writes: WriteQueue,
    stats: TransferStats,
    name: String,
}

impl ImageTransport {
    /// A transport serving `image` (shorter images read 0 past their end).
    pub fn new(mut image: Vec<u32>, name: &str) -> ImageTransport {
        image.resize(WINDOW_WORDS, 0);
        ImageTransport {
            image,
            reads: ReadQueue::default(),
            writes: WriteQueue::default(),
            stats: TransferStats::default(),
            name: name.to_string(),
        }
    }
}

impl Transport for ImageTransport {
    fn read(&mut self, addr: u32, buf: &mut [u32]) -> Result<(), TransportError> {
        check_window(addr, buf.len())?;
        let a = addr as usize / 4;
        buf.copy_from_slice(&self.image[a..a + buf.len()]);
        self.stats.words_read += buf.len() as u64;
        self.stats.read_bursts += 1;
        Ok(())
    }

    fn write(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError> {
        check_window(addr, data.len())?;
        self.stats.words_written += data.len() as u64;
        self.stats.write_bursts += 1;
        Ok(())
    }

    fn reserve(&mut self, reads: usize, _read_words: usize, writes: usize, write_words: usize) {
        self.reads.reserve(reads);
        self.writes.reserve(writes, write_words);
    }

    fn queue_read(&mut self, addr: u32, words: usize) -> Result<(), TransportError> {
        self.reads.push(addr, words)
    }

    fn send_queued_reads(&mut self) -> Result<(), TransportError> {
        Ok(())
    }

    fn receive_queued_reads(&mut self, out: &mut [u32]) -> Result<(), TransportError> {
        let image = &self.image;
        self.reads.receive(out, &mut self.stats, |addr, dst| {
            let a = addr as usize / 4;
            dst.copy_from_slice(&image[a..a + dst.len()]);
        })
    }

    fn queue_write(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError> {
        self.writes.push(addr, data)
    }

    fn send_queued_writes(&mut self) -> Result<(), TransportError> {
        for (_, d) in self.writes.iter() {
            self.stats.words_written += d.len() as u64;
            self.stats.write_bursts += 1;
        }
        self.writes.clear();
        Ok(())
    }

    fn stats(&self) -> TransferStats {
        self.stats
    }

    fn describe(&self) -> String {
        self.name.clone()
    }
}
