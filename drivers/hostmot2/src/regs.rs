//! The HostMot2 register map (hardware.md 5.2 to 5.9): fixed addresses,
//! the IDROM header layout, module and pin descriptor fields, general
//! function tags and the bits of each module's registers.
//!
//! Addresses are byte addresses in the board's 64 KiB window; registers
//! are 32 bits wide and 4-aligned.

/// Size of the register window every HostMot2 board decodes.
pub const WINDOW_BYTES: usize = 0x1_0000;

/// Address of the IOCookie.
pub const COOKIE_ADDR: u16 = 0x0100;
/// The value the cookie must read.
pub const COOKIE: u32 = 0x55AA_CAFE;
/// Address of the 8-byte configuration name.
pub const CONFIG_NAME_ADDR: u16 = 0x0104;
/// The configuration name every HostMot2 firmware carries.
pub const CONFIG_NAME: &[u8; 8] = b"HOSTMOT2";
/// Address of the word whose low 16 bits hold the IDROM's address.
pub const IDROM_OFFSET_ADDR: u16 = 0x010C;
/// Where firmware normally puts the IDROM.
pub const IDROM_DEFAULT_ADDR: u16 = 0x0400;
/// The LED register (LEDs in the most significant byte).
pub const LED_ADDR: u16 = 0x0200;

/// Most module descriptors the loader reads (LinuxCNC's limit).
pub const MAX_MODULE_DESCRIPTORS: usize = 48;
/// Most I/O pins the loader accepts (LinuxCNC's limit).
pub const MAX_IO_PINS: u32 = 1000;
/// Most connectors an llio may declare.
pub const MAX_CONNECTORS: usize = 8;
/// Lowest clock an IDROM may declare, in Hz.
pub const MIN_CLOCK_HZ: u32 = 1_000_000;

/// The IDROM header: 16 little-endian words, offsets from the IDROM start.
pub mod idrom {
    /// Words in the header.
    pub const WORDS: usize = 16;
    /// IDROMType: 2 or 3.
    pub const TYPE: usize = 0x00;
    /// OffsetToModules, relative to the IDROM.
    pub const OFFSET_TO_MODULES: usize = 0x04;
    /// OffsetToPinDesc, relative to the IDROM.
    pub const OFFSET_TO_PIN_DESC: usize = 0x08;
    /// BoardNameLow (4 ASCII bytes).
    pub const BOARD_NAME_LOW: usize = 0x0C;
    /// BoardNameHigh (4 ASCII bytes).
    pub const BOARD_NAME_HIGH: usize = 0x10;
    /// FPGASize (informational).
    pub const FPGA_SIZE: usize = 0x14;
    /// FPGAPins (informational).
    pub const FPGA_PINS: usize = 0x18;
    /// IOPorts: IOPort instances, one per connector.
    pub const IO_PORTS: usize = 0x1C;
    /// IOWidth: total I/O pins.
    pub const IO_WIDTH: usize = 0x20;
    /// PortWidth: pins per connector.
    pub const PORT_WIDTH: usize = 0x24;
    /// ClockLow in Hz.
    pub const CLOCK_LOW: usize = 0x28;
    /// ClockHigh in Hz.
    pub const CLOCK_HIGH: usize = 0x2C;
    /// InstanceStride0.
    pub const INSTANCE_STRIDE0: usize = 0x30;
    /// InstanceStride1.
    pub const INSTANCE_STRIDE1: usize = 0x34;
    /// RegisterStride0.
    pub const REGISTER_STRIDE0: usize = 0x38;
    /// RegisterStride1.
    pub const REGISTER_STRIDE1: usize = 0x3C;
}

/// General function tags (hardware.md 5.5).
pub mod gtag {
    /// End of the module descriptor list.
    pub const END: u8 = 0;
    /// IRQ logic.
    pub const IRQ_LOGIC: u8 = 1;
    /// Watchdog.
    pub const WATCHDOG: u8 = 2;
    /// IOPort.
    pub const IOPORT: u8 = 3;
    /// Quadrature counter.
    pub const ENCODER: u8 = 4;
    /// Step generator.
    pub const STEPGEN: u8 = 5;
    /// PWM generator.
    pub const PWMGEN: u8 = 6;
    /// Translation RAM.
    pub const TRANSLATION_RAM: u8 = 11;
    /// Muxed encoder.
    pub const MUXED_ENCODER: u8 = 12;
    /// Muxed encoder select.
    pub const MUXED_ENCODER_SEL: u8 = 13;
    /// HM2 DPLL.
    pub const HM2DPLL: u8 = 26;
    /// PktUART transmitter.
    pub const PKTUART_TX: u8 = 0x1B;
    /// PktUART receiver.
    pub const PKTUART_RX: u8 = 0x1C;
    /// The LEDs.
    pub const LED: u8 = 0x80;
    /// Smart Serial.
    pub const SSERIAL: u8 = 0xC1;

    /// LinuxCNC's name of a function (`hm2_get_general_function_name`),
    /// used in its messages.
    pub fn name(tag: u8) -> Option<&'static str> {
        Some(match tag {
            2 => "Watchdog",
            3 => "IOPort",
            4 => "Encoder",
            5 => "StepGen",
            6 => "PWMGen",
            7 => "SPI",
            8 => "SSI",
            9 => "UART Transmit Channel",
            10 => "UART Receive Channel",
            11 => "TranslationRAM",
            12 => "Muxed Encoder",
            13 => "Muxed Encoder Select",
            14 => "Buffered SPI Interface",
            15 => "Decoded Buffered SPI Interface",
            16 => "Old DPLL",
            17 => "Muxed Encoder Mim",
            18 => "Muxed Encoder Select Mim",
            19 => "3-Phase PWM",
            20 => "WaveGen",
            21 => "DAQ FIFO",
            22 => "BinOsc",
            23 => "DDMA",
            24 => "BiSS",
            25 => "Fanuc Abs Encoder",
            26 => "Hm2 Phase-Locked-Loop",
            27 => "PktUART Transmit Channel",
            28 => "PktUART Receive Channel",
            30 => "InMux Input Mux",
            35 => "InM Input Module",
            42 => "Data Painter",
            43 => "XY2mod Galvo Interface",
            44 => "RC PWM Generator",
            45 => "OutM Output Module",
            64 => "LIOPort",
            0x80 => "LED",
            0xC0 => "Resolver",
            0xC1 => "Smart Serial Interface",
            0xC2 => "Twiddler",
            0xC3 => "SSR",
            0xC6 => "Smart Serial Interface B",
            0xC7 => "OneShot",
            0xC8 => "PeriodM",
            _ => return None,
        })
    }

    /// mesaflash's name of a function (`--readhmid` output).
    pub fn mesaflash_name(tag: u8) -> Option<&'static str> {
        Some(match tag {
            1 => "IRQLogic",
            2 => "WatchDog",
            3 => "IOPort",
            4 => "QCount",
            5 => "StepGen",
            6 => "PWM",
            7 => "SPI",
            8 => "SSI",
            9 => "UARTTX",
            10 => "UARTRX",
            11 => "AddrX",
            12 => "MuxedQCount",
            13 => "MuxedQCountSel",
            14 => "BufSPI",
            15 => "DBSPI",
            16 => "DPLL",
            19 => "TPPWM",
            20 => "WaveGen",
            21 => "DAQFIFO",
            22 => "BinOsc",
            23 => "DDMA",
            24 => "BISS",
            25 => "FAbs",
            26 => "HM2DPLL",
            27 => "PktUARTTX",
            28 => "PktUARTRX",
            30 => "InMux",
            35 => "InM",
            42 => "DataPainter",
            43 => "XY2Mod",
            44 => "RCPWM",
            45 => "OutM",
            64 => "LIOPort",
            0x80 => "LED",
            0xC0 => "ResolverMod",
            0xC1 => "SSerial",
            0xC2 => "Twiddler",
            0xC3 => "SSR",
            0xC6 => "SSerialB",
            0xC7 => "OneShot",
            0xC8 => "PeriodM",
            _ => return None,
        })
    }
}

/// Module descriptor fields (hardware.md 5.4): three words per record.
pub mod md {
    /// Words per record.
    pub const WORDS: usize = 3;
    /// Bytes per record.
    pub const BYTES: usize = 12;
    /// ClockTag value selecting ClockLow.
    pub const CLOCK_LOW_TAG: u8 = 1;
    /// ClockTag value selecting ClockHigh.
    pub const CLOCK_HIGH_TAG: u8 = 2;
}

/// Pin descriptor fields (hardware.md 5.6).
pub mod pd {
    /// SecPin bit: the secondary module drives this pin.
    pub const OUTPUT: u8 = 0x80;
    /// SecUnit bit: the pin serves every instance of its module.
    pub const GLOBAL_UNIT: u8 = 0x80;
    /// PrimaryTag every pin descriptor must carry.
    pub const PRIMARY_IOPORT: u8 = 3;
}

/// IOPort register indices (per instance).
pub mod ioport {
    /// Data: output latch on write, pin levels on read.
    pub const DATA: usize = 0;
    /// Data direction: 1 = output.
    pub const DDR: usize = 1;
    /// Alternate source: 1 = the secondary module drives the pin.
    pub const ALT_SOURCE: usize = 2;
    /// Open drain.
    pub const OPEN_DRAIN: usize = 3;
    /// Output invert.
    pub const OUTPUT_INVERT: usize = 4;
}

/// Watchdog registers and bits.
pub mod watchdog {
    /// Timer register index: timeout in ClockLow ticks.
    pub const TIMER: usize = 0;
    /// Status register index.
    pub const STATUS: usize = 1;
    /// Reset (pet) register index.
    pub const COOKIE_REG: usize = 2;
    /// Timer bit that disables the watchdog (and that a bite sets).
    pub const TIMER_DISABLED: u32 = 0x8000_0000;
    /// Status bit: the watchdog has bitten.
    pub const STATUS_HAS_BIT: u32 = 1;
    /// The word that pets the watchdog.
    pub const PET: u32 = 0x5A00_0000;
}

/// Encoder registers and control bits.
pub mod encoder {
    /// Counter register index (per instance).
    pub const COUNTER: usize = 0;
    /// Latch/control register index (per instance).
    pub const LATCH_CONTROL: usize = 1;
    /// Timestamp divider register index.
    pub const TSDIV: usize = 2;
    /// Timestamp counter register index.
    pub const TSCOUNT: usize = 3;
    /// Filter rate register index.
    pub const FILTER_RATE: usize = 4;

    /// Quadrature error (sticky; writing 1 clears).
    pub const QUAD_ERROR: u32 = 1 << 15;
    /// Index gate needs A and B high.
    pub const AB_MASK_POLARITY: u32 = 1 << 14;
    /// Latch the count on probe.
    pub const LATCH_ON_PROBE: u32 = 1 << 13;
    /// Probe active high.
    pub const PROBE_POLARITY: u32 = 1 << 12;
    /// Input filter: 15 samples instead of 3.
    pub const FILTER: u32 = 1 << 11;
    /// Counter mode: A counts, B gives the direction.
    pub const COUNTER_MODE: u32 = 1 << 10;
    /// Use the index mask input.
    pub const INDEX_MASK: u32 = 1 << 9;
    /// Index mask active high.
    pub const INDEX_MASK_POLARITY: u32 = 1 << 8;
    /// Gate the index with A and B.
    pub const QUAD_FILTER_INDEX: u32 = 1 << 7;
    /// Clear/latch once, then self-clear the enable bits.
    pub const JUST_ONCE: u32 = 1 << 6;
    /// Clear the count on index.
    pub const CLEAR_ON_INDEX: u32 = 1 << 5;
    /// Latch the count on index.
    pub const LATCH_ON_INDEX: u32 = 1 << 4;
    /// Index active high (rising edge).
    pub const INDEX_POLARITY: u32 = 1 << 3;
    /// Live index input.
    pub const INPUT_INDEX: u32 = 1 << 2;
    /// Live B input.
    pub const INPUT_B: u32 = 1 << 1;
    /// Live A input.
    pub const INPUT_A: u32 = 1 << 0;
    /// Control bits a write changes (everything but the live inputs).
    pub const WRITABLE: u32 = 0xFFF8;
}

/// StepGen registers and mode bits.
pub mod stepgen {
    /// Rate register index (per instance).
    pub const RATE: usize = 0;
    /// Accumulator register index (per instance).
    pub const ACCUMULATOR: usize = 1;
    /// Mode register index (per instance).
    pub const MODE: usize = 2;
    /// Direction setup time register index.
    pub const DIR_SETUP: usize = 3;
    /// Direction hold time register index.
    pub const DIR_HOLD: usize = 4;
    /// Pulse width register index.
    pub const PULSE_WIDTH: usize = 5;
    /// Pulse idle width register index.
    pub const PULSE_IDLE: usize = 6;
    /// Table data register index.
    pub const TABLE_DATA: usize = 7;
    /// Table length register index.
    pub const TABLE_LENGTH: usize = 8;
    /// Master DDS register index (module-wide).
    pub const MASTER_DDS: usize = 9;

    /// Mode bits 1..0: the step type.
    pub const MODE_TYPE_MASK: u32 = 0x3;
    /// Step type code: step and direction.
    pub const TYPE_STEP_DIR: u32 = 0;
    /// Step type code: up and down.
    pub const TYPE_UP_DOWN: u32 = 1;
    /// Step type code: quadrature.
    pub const TYPE_QUADRATURE: u32 = 2;
    /// Step type code: table.
    pub const TYPE_TABLE: u32 = 3;
    /// Swap the step and direction outputs (version 0x42 and later).
    pub const MODE_SWAP: u32 = 1 << 2;
    /// Latch the accumulator on index (version 0xC2).
    pub const MODE_LATCH_ON_INDEX: u32 = 1 << 4;
    /// Index active high.
    pub const MODE_INDEX_POLARITY: u32 = 1 << 5;
    /// Latch the accumulator on probe (version 0xC2).
    pub const MODE_LATCH_ON_PROBE: u32 = 1 << 6;
    /// Probe active high.
    pub const MODE_PROBE_POLARITY: u32 = 1 << 7;
    /// Largest value of a timing register (14 bits).
    pub const TIMING_MAX: u32 = 0x3FFF;
    /// Most phases of a table.
    pub const TABLE_MAX: u32 = 16;
}

/// PWMGen registers and mode bits.
pub mod pwmgen {
    /// PWM value register index (per instance).
    pub const VALUE: usize = 0;
    /// Mode register index (per instance).
    pub const MODE: usize = 1;
    /// PWM rate DDS register index.
    pub const PWM_DDS: usize = 2;
    /// PDM rate DDS register index.
    pub const PDM_DDS: usize = 3;
    /// Enable register index.
    pub const ENABLE: usize = 4;

    /// Value bit 31: direction (negative).
    pub const VALUE_DIR: u32 = 1 << 31;
    /// Mode bits 1..0: width code (bits − 9).
    pub const MODE_WIDTH_MASK: u32 = 0x3;
    /// Symmetric (triangle) PWM.
    pub const MODE_SYMMETRIC: u32 = 1 << 2;
    /// Output mode field shift (bits 4..3).
    pub const MODE_OUTPUT_SHIFT: u32 = 3;
    /// Output mode: PWM on Out0, direction on Out1.
    pub const OUT_PWM_DIR: u32 = 0;
    /// Output mode: direction on Out0, PWM on Out1.
    pub const OUT_DIR_PWM: u32 = 1;
    /// Output mode: up on Out0, down on Out1.
    pub const OUT_UP_DOWN: u32 = 2;
    /// Output mode: PDM on Out0, direction on Out1.
    pub const OUT_PDM: u32 = 3;
    /// Double-buffered value (applied at the start of a cycle).
    pub const MODE_DOUBLE_BUFFERED: u32 = 1 << 5;
    /// Dither (version 1).
    pub const MODE_DITHER: u32 = 1 << 6;
}

/// The PLX 9030 bridge of the 5i20 and 4i65 (hardware.md 5.1): its
/// local-configuration registers are I/O BAR 1, the FPGA's configuration
/// data port is I/O BAR 2.
pub mod plx9030 {
    /// The configuration-registers BAR.
    pub const CTRL_BAR: usize = 1;
    /// The bitstream data-port BAR.
    pub const DATA_BAR: usize = 2;
    /// GPIO control/status register (GPIOC), offset in BAR 1.
    pub const GPIOC: u16 = 0x54;
    /// GPIO3 data: the FPGA's DONE (input; 1 = configured).
    pub const DONE: u32 = 1 << 11;
    /// GPIO4 data: the FPGA's /INIT (input; low while clearing its
    /// memory, and after a CRC error).
    pub const INIT: u32 = 1 << 14;
    /// GPIO5 data: /LED (output, active low).
    pub const LED: u32 = 1 << 17;
    /// GPIO7 data: /WRITE (output, active low: the data port feeds the
    /// FPGA's configuration port).
    pub const WRITE: u32 = 1 << 23;
    /// GPIO8 data: /PROGRAM (output, active low: clears the FPGA).
    pub const PROGRAM: u32 = 1 << 26;
    /// Local address space bus region descriptors LAS0BRD..LAS3BRD.
    pub const LAS_BRD: [u16; 4] = [0x28, 0x2C, 0x30, 0x34];
    /// LASxBRD bit: READY# input enable.
    pub const LAS_BRD_READY: u32 = 1 << 1;
}

/// The PLX 9054/9056 bridge of the 5i21, 5i22, 5i23, 4i68, 4i69 and 3x20
/// (hardware.md 5.1): configuration registers in I/O BAR 1, the data
/// port in I/O BAR 2.
pub mod plx9054 {
    /// The configuration-registers BAR.
    pub const CTRL_BAR: usize = 1;
    /// The bitstream data-port BAR.
    pub const DATA_BAR: usize = 2;
    /// Control register (CNTRL), offset in BAR 1.
    pub const CNTRL: u16 = 0x6C;
    /// USERo: the FPGA's /PROGRAM (output, active low).
    pub const PROGRAM: u32 = 1 << 16;
    /// USERi: the FPGA's DONE (input; 1 = configured).
    pub const DONE: u32 = 1 << 17;
    /// Makes the USERi pin (DONE) a user input.
    pub const DONE_ENABLE: u32 = 1 << 18;
    /// Makes the USERo pin (/PROGRAM) a user output.
    pub const PROGRAM_ENABLE: u32 = 1 << 19;
}

/// How long LinuxCNC's FPGA loader waits, counted in bridge register
/// reads (hardware.md 5.1).
pub mod fpga_wait {
    /// Reads while waiting for /INIT after /PROGRAM is released (9030),
    /// and reads of delay after the /PROGRAM pulse (9054).
    pub const INIT_READS: u32 = 3300;
    /// Reads while waiting for DONE after the bitstream (9054).
    pub const DONE_READS: u32 = 20_000;
}

/// PktUART registers and bits (Mesa's regmap, as LinuxCNC's
/// `hostmot2-serial.h` names them). The transmitter and the receiver are
/// separate modules (GTags 0x1B and 0x1C) with the same four registers
/// per instance.
pub mod pktuart {
    /// Data register index: a write (TX) queues four bytes, low byte
    /// first; a read (RX) pops four.
    pub const DATA: usize = 0;
    /// Count register index: a TX write queues a frame of that many
    /// bytes; an RX read pops one received frame's size and status.
    pub const COUNT: usize = 1;
    /// Bit-rate register index: baud x 2^24 / ClockLow (v2+); on the
    /// receiver bits 24..31 hold the high byte of the input filter.
    pub const BITRATE: usize = 2;
    /// Mode/status register index.
    pub const MODE: usize = 3;
    /// The word that, written to a mode register, aborts the transfer in
    /// progress and empties the data and count FIFOs.
    pub const CLEAR: u32 = 0x8001_0000;
    /// Frames the count FIFO of either direction holds.
    pub const MAX_FRAMES: usize = 16;
    /// The largest frame, in bytes (the 10-bit count).
    pub const MAX_FRAME_BYTES: usize = 1023;

    /// The mode/status bits the transmitter and receiver registers share
    /// (each half's own bits are in [`tx`] and [`rx`]).
    pub mod line {
        /// RO: the data FIFO holds data.
        pub const HAS_DATA: u32 = 1 << 21;
        /// WO (v3+): the inter-frame delay counts in units of 4 bit times.
        pub const IF_SCALE: u32 = 1 << 20;
        /// WO (v3+): two stop bits.
        pub const STOP_BITS2: u32 = 1 << 19;
        /// WO: odd parity (with `PARITY_EN`).
        pub const PARITY_ODD: u32 = 1 << 18;
        /// WO: parity enable.
        pub const PARITY_EN: u32 = 1 << 17;
        /// RO: frames queued (TX) or received (RX), bits 16..20.
        pub const NFRAMES_SHIFT: u32 = 16;
        /// Inter-frame delay in bit times, bits 8..15.
        pub const IF_DELAY_SHIFT: u32 = 8;
        /// RO: sending (TX) or receiving a frame (RX).
        pub const BUSY: u32 = 1 << 7;
    }

    /// Transmitter mode/status bits.
    pub mod tx {
        pub use super::line::*;
        /// The RS-485 driver is on.
        pub const DRIVE_EN: u32 = 1 << 6;
        /// The RS-485 driver turns on by itself while sending.
        pub const DRIVE_AUTO: u32 = 1 << 5;
        /// RO: the send-count FIFO overflowed.
        pub const SCFIFO_ERROR: u32 = 1 << 4;
        /// Driver-enable to start-of-data delay, bits 0..3.
        pub const DRIVE_DELAY_MASK: u32 = 0xF;
    }

    /// Receiver mode/status bits.
    pub mod rx {
        pub use super::line::*;
        /// RO: a data FIFO read found it empty.
        pub const BAD_POP: u32 = 1 << 30;
        /// Input filter (low byte), bits 22..29, in ClockLow periods.
        pub const FILTER_SHIFT: u32 = 22;
        /// RO: input masked (the transmitter is sending).
        pub const MASKED: u32 = 1 << 6;
        /// Sticky: a parity error.
        pub const PARITY_ERROR: u32 = 1 << 5;
        /// Sticky: the receive-count FIFO overflowed.
        pub const RCFIFO_ERROR: u32 = 1 << 4;
        /// The receiver is on.
        pub const RX_EN: u32 = 1 << 3;
        /// Input is masked while the transmitter sends (half duplex).
        pub const RX_MASK_EN: u32 = 1 << 2;
        /// Sticky: no stop bit where one was due.
        pub const OVERRUN_ERROR: u32 = 1 << 1;
        /// Sticky: a false start bit.
        pub const START_BIT_ERROR: u32 = 1 << 0;
    }

    /// Receive-count word bits (one per received frame).
    pub mod rcr {
        /// Longest gap between two characters, in bit times, bits 24..31
        /// (v3+).
        pub const ICHAR_SHIFT: u32 = 24;
        /// The frame had a parity error.
        pub const PARITY_ERROR: u32 = 1 << 16;
        /// The frame had an overrun (missing stop bit).
        pub const OVERRUN_ERROR: u32 = 1 << 15;
        /// The frame had a false start bit.
        pub const START_BIT_ERROR: u32 = 1 << 14;
        /// Frame size in bytes, bits 0..9.
        pub const NBYTES_MASK: u32 = 0x3FF;
        /// Any error bit of a frame.
        pub const ERRORS: u32 = PARITY_ERROR | OVERRUN_ERROR | START_BIT_ERROR;
    }

    /// The frame count in a mode/status word.
    pub fn nframes(mode: u32) -> usize {
        ((mode >> 16) & 0x1F) as usize
    }
}
