//! Identification: cookie, configuration name and the IDROM header, read
//! and checked in LinuxCNC's order with its words (hardware.md 5.2, 5.3,
//! 5.7 steps 5 to 7).

use crate::error::{Hm2Error, Result};
use crate::llio::Llio;
use crate::regs::{self, idrom as f};
use crate::transport::Transport;

/// The IDROM header of a board.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IdromHeader {
    /// Absolute address of the IDROM (low 16 bits of 0x010C).
    pub addr: u32,
    /// IDROMType (2 or 3).
    pub idrom_type: u32,
    /// OffsetToModules, relative to the IDROM.
    pub offset_to_modules: u32,
    /// OffsetToPinDesc, relative to the IDROM.
    pub offset_to_pin_desc: u32,
    /// BoardNameLow and BoardNameHigh, 8 ASCII bytes (`MESA5I25`).
    pub board_name: [u8; 8],
    /// FPGASize (informational).
    pub fpga_size: u32,
    /// FPGAPins (informational).
    pub fpga_pins: u32,
    /// IOPorts.
    pub io_ports: u32,
    /// IOWidth.
    pub io_width: u32,
    /// PortWidth.
    pub port_width: u32,
    /// ClockLow in Hz.
    pub clock_low: u32,
    /// ClockHigh in Hz.
    pub clock_high: u32,
    /// InstanceStride0 and InstanceStride1.
    pub instance_stride: [u32; 2],
    /// RegisterStride0 and RegisterStride1.
    pub register_stride: [u32; 2],
}

impl IdromHeader {
    /// Decodes the 16 header words read at `addr`.
    pub fn from_words(addr: u32, w: &[u32; f::WORDS]) -> IdromHeader {
        let at = |off: usize| w[off / 4];
        let mut board_name = [0u8; 8];
        board_name[..4].copy_from_slice(&at(f::BOARD_NAME_LOW).to_le_bytes());
        board_name[4..].copy_from_slice(&at(f::BOARD_NAME_HIGH).to_le_bytes());
        IdromHeader {
            addr,
            idrom_type: at(f::TYPE),
            offset_to_modules: at(f::OFFSET_TO_MODULES),
            offset_to_pin_desc: at(f::OFFSET_TO_PIN_DESC),
            board_name,
            fpga_size: at(f::FPGA_SIZE),
            fpga_pins: at(f::FPGA_PINS),
            io_ports: at(f::IO_PORTS),
            io_width: at(f::IO_WIDTH),
            port_width: at(f::PORT_WIDTH),
            clock_low: at(f::CLOCK_LOW),
            clock_high: at(f::CLOCK_HIGH),
            instance_stride: [at(f::INSTANCE_STRIDE0), at(f::INSTANCE_STRIDE1)],
            register_stride: [at(f::REGISTER_STRIDE0), at(f::REGISTER_STRIDE1)],
        }
    }

    /// The 16 header words (what a simulator serves).
    pub fn to_words(&self) -> [u32; f::WORDS] {
        let mut w = [0u32; f::WORDS];
        let mut put = |off: usize, v: u32| w[off / 4] = v;
        let name = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        put(f::TYPE, self.idrom_type);
        put(f::OFFSET_TO_MODULES, self.offset_to_modules);
        put(f::OFFSET_TO_PIN_DESC, self.offset_to_pin_desc);
        put(f::BOARD_NAME_LOW, name(&self.board_name[..4]));
        put(f::BOARD_NAME_HIGH, name(&self.board_name[4..]));
        put(f::FPGA_SIZE, self.fpga_size);
        put(f::FPGA_PINS, self.fpga_pins);
        put(f::IO_PORTS, self.io_ports);
        put(f::IO_WIDTH, self.io_width);
        put(f::PORT_WIDTH, self.port_width);
        put(f::CLOCK_LOW, self.clock_low);
        put(f::CLOCK_HIGH, self.clock_high);
        put(f::INSTANCE_STRIDE0, self.instance_stride[0]);
        put(f::INSTANCE_STRIDE1, self.instance_stride[1]);
        put(f::REGISTER_STRIDE0, self.register_stride[0]);
        put(f::REGISTER_STRIDE1, self.register_stride[1]);
        w
    }

    /// The board name, non-printables shown as `?`.
    pub fn board_name(&self) -> String {
        show_ascii(&self.board_name)
    }
}

/// Bytes as text, each non-printable byte as `?` (LinuxCNC's rendering).
pub fn show_ascii(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|&b| {
            if b.is_ascii_graphic() || b == b' ' {
                b as char
            } else {
                '?'
            }
        })
        .collect()
}

fn read(t: &mut dyn Transport, addr: u32, buf: &mut [u32], op: &str) -> Result<()> {
    t.read(addr, buf).map_err(|source| Hm2Error::Transport {
        op: op.to_string(),
        source,
    })
}

/// Reads the cookie and the configuration name: is this HostMot2?
pub fn check_identity(t: &mut dyn Transport) -> Result<()> {
    let mut cookie = [0u32; 1];
    read(
        t,
        regs::COOKIE_ADDR as u32,
        &mut cookie,
        "error reading hm2 cookie",
    )?;
    if cookie[0] != regs::COOKIE {
        return Err(Hm2Error::BadCookie { found: cookie[0] });
    }
    let mut name = [0u32; 2];
    read(
        t,
        regs::CONFIG_NAME_ADDR as u32,
        &mut name,
        "error reading HM2 Config Name",
    )?;
    let mut bytes = [0u8; 8];
    bytes[..4].copy_from_slice(&name[0].to_le_bytes());
    bytes[4..].copy_from_slice(&name[1].to_le_bytes());
    if &bytes != regs::CONFIG_NAME {
        return Err(Hm2Error::BadConfigName {
            found: show_ascii(&bytes),
        });
    }
    Ok(())
}

/// Reads the IDROM header and checks it against the board, in LinuxCNC's
/// order: type, PortWidth, IOWidth, IOPorts, the pin limit, ClockLow,
/// ClockHigh.
pub fn read_header(t: &mut dyn Transport, llio: &Llio) -> Result<IdromHeader> {
    let mut w = [0u32; 1];
    read(
        t,
        regs::IDROM_OFFSET_ADDR as u32,
        &mut w,
        "error reading IDROM type",
    )?;
    let addr = w[0] & 0xFFFF;
    read(t, addr, &mut w, "error reading IDROM type")?;
    if w[0] != 2 && w[0] != 3 {
        return Err(Hm2Error::BadIdromType { found: w[0] });
    }
    let mut words = [0u32; f::WORDS];
    read(t, addr, &mut words, "error reading IDROM")?;
    let h = IdromHeader::from_words(addr, &words);
    check_header(&h, llio)?;
    Ok(h)
}

/// The header checks of [`read_header`], on a decoded header.
pub fn check_header(h: &IdromHeader, llio: &Llio) -> Result<()> {
    if h.idrom_type != 2 && h.idrom_type != 3 {
        return Err(Hm2Error::BadIdromType {
            found: h.idrom_type,
        });
    }
    if h.port_width != llio.pins_per_connector {
        return Err(Hm2Error::BadPortWidth {
            found: h.port_width,
            expected: llio.pins_per_connector,
        });
    }
    if h.io_ports as u64 * h.port_width as u64 != h.io_width as u64 {
        return Err(Hm2Error::InconsistentIoWidth {
            io_width: h.io_width,
            io_ports: h.io_ports,
            port_width: h.port_width,
        });
    }
    if h.io_ports != llio.connectors.len() as u32 {
        return Err(Hm2Error::BadIoPorts {
            found: h.io_ports,
            expected: llio.connectors.len() as u32,
        });
    }
    if h.io_width > regs::MAX_IO_PINS {
        return Err(Hm2Error::TooManyPins { found: h.io_width });
    }
    if h.clock_low < regs::MIN_CLOCK_HZ {
        return Err(Hm2Error::ClockLowTooLow { found: h.clock_low });
    }
    if h.clock_high < regs::MIN_CLOCK_HZ {
        return Err(Hm2Error::ClockHighTooLow {
            found: h.clock_high,
        });
    }
    Ok(())
}

/// Debug lines describing the header (LinuxCNC's `debug_idrom=1`).
pub fn describe(h: &IdromHeader) -> Vec<String> {
    vec![
        format!("IDROM at 0x{:04X}:", h.addr),
        format!("    IDRomType: {}", h.idrom_type),
        format!("    Offset to Modules: 0x{:08X}", h.offset_to_modules),
        format!(
            "    Offset to Pin Description: 0x{:08X}",
            h.offset_to_pin_desc
        ),
        format!("    Board Name: {}", h.board_name()),
        format!("    FPGA Size: {}", h.fpga_size),
        format!("    FPGA Pins: {}", h.fpga_pins),
        format!("    IOPorts: {}", h.io_ports),
        format!("    IOWidth: {}", h.io_width),
        format!("    PortWidth: {}", h.port_width),
        format!("    Clock Low: {} Hz", h.clock_low),
        format!("    Clock High: {} Hz", h.clock_high),
        format!("    Instance Stride 0: 0x{:08X}", h.instance_stride[0]),
        format!("    Instance Stride 1: 0x{:08X}", h.instance_stride[1]),
        format!("    Register Stride 0: 0x{:08X}", h.register_stride[0]),
        format!("    Register Stride 1: 0x{:08X}", h.register_stride[1]),
    ]
}
