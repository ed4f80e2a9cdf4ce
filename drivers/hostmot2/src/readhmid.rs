//! A board's identification as `mesaflash --readhmid` prints it
//! (hostmot2-more.md 3.3): the configuration name, the IDROM, every module
//! and the pin-out per connector, in mesaflash's layout and words.
//!
//! It reads as mesaflash does (cookie, name, IDROM, then up to 32 module
//! descriptors to the first empty one and the IOWidth pin descriptors, at
//! most 144) and checks only what it needs to print, so it shows firmware
//! the driver would refuse.

use std::fmt::Write as _;

use crate::error::{Hm2Error, Result};
use crate::idrom::{self, IdromHeader};
use crate::pins::{self, PinDescriptor};
use crate::regs::{self, gtag};
use crate::transport::Transport;

/// Module descriptors mesaflash reads.
const MAX_MDS: usize = 32;
/// Pin descriptors mesaflash reads at most.
const MAX_PDS: u32 = 144;

fn read(t: &mut dyn Transport, addr: u32, buf: &mut [u32], what: &str) -> Result<()> {
    t.read(addr, buf).map_err(|source| Hm2Error::Transport {
        op: format!("error reading {what}"),
        source,
    })
}

/// The cookie and name checked, the IDROM header as it is (unchecked).
fn header(t: &mut dyn Transport) -> Result<IdromHeader> {
    idrom::check_identity(t)?;
    let mut w = [0u32; 1];
    read(
        t,
        regs::IDROM_OFFSET_ADDR as u32,
        &mut w,
        "the IDROM offset",
    )?;
    let addr = w[0] & 0xFFFF;
    let mut words = [0u32; regs::idrom::WORDS];
    read(t, addr, &mut words, "the IDROM")?;
    Ok(IdromHeader::from_words(addr, &words))
}

/// One module descriptor's raw fields.
struct RawMd {
    tag: u8,
    version: u8,
    clock_tag: u8,
    instances: u8,
    base: u16,
    registers: u8,
    reg_sel: u8,
    inst_sel: u8,
}

fn read_mds(t: &mut dyn Transport, h: &IdromHeader) -> Result<Vec<RawMd>> {
    let mut v = Vec::new();
    for i in 0..MAX_MDS {
        let addr = h
            .addr
            .wrapping_add(h.offset_to_modules)
            .wrapping_add(12 * i as u32);
        let mut w = [0u32; 3];
        read(t, addr, &mut w, "module descriptors")?;
        if w == [0; 3] {
            break;
        }
        v.push(RawMd {
            tag: w[0] as u8,
            version: (w[0] >> 8) as u8,
            clock_tag: (w[0] >> 16) as u8,
            instances: (w[0] >> 24) as u8,
            base: w[1] as u16,
            registers: (w[1] >> 16) as u8,
            reg_sel: ((w[1] >> 24) & 0xF) as u8,
            inst_sel: (w[1] >> 28) as u8,
        });
    }
    Ok(v)
}

fn mhz(hz: u32, places: usize) -> String {
    format!("{:.*} MHz", places, hz as f64 / 1e6)
}

/// mesaflash's connector pin column for bit `bit` (or I/O number `io`).
fn pin_column(port_width: u32, bit: u32, io: u32) -> u32 {
    match port_width {
        17 => pins::DB25_ORDER.get(bit as usize).copied().unwrap_or(0),
        24 => 2 * bit + 1,
        32 => io,
        _ => 0,
    }
}

/// Reads the board behind `t` and renders it as `--readhmid` does;
/// `connectors` are the board's connector names (`??` where unknown).
pub fn read_hmid(t: &mut dyn Transport, connectors: &[String]) -> Result<String> {
    let h = header(t)?;
    let mut w = [0u32; 1];
    let mds = read_mds(t, &h)?;
    let npins = h.io_width.min(MAX_PDS);
    let mut pds = Vec::with_capacity(npins as usize);
    for i in 0..npins {
        let a = h
            .addr
            .wrapping_add(h.offset_to_pin_desc)
            .wrapping_add(4 * i);
        read(t, a, &mut w, "pin descriptors")?;
        pds.push(PinDescriptor::from_word(w[0]));
    }
    Ok(render(&h, &mds, &pds, connectors))
}

/// A one-line identification: `MESA5I25 (HostMot2, IDROM type 3, 2 × 17
/// I/O)`, or why the board is not a HostMot2 one.
pub fn identify(t: &mut dyn Transport) -> Result<String> {
    let h = header(t)?;
    Ok(format!(
        "{} (HostMot2, IDROM type {}, {} × {} I/O)",
        h.board_name(),
        h.idrom_type,
        h.io_ports,
        h.port_width
    ))
}

/// The register names of a module, by GTag (LinuxCNC's and the regmap's).
pub fn register_names(tag: u8) -> &'static [&'static str] {
    match tag {
        gtag::IOPORT => &["Data", "DDR", "AltSource", "OpenDrain", "OutputInvert"],
        gtag::WATCHDOG => &["Timer", "Status", "Reset"],
        gtag::ENCODER => &["Counter", "Latch/Control", "TSDiv", "TSCount", "FilterRate"],
        gtag::STEPGEN => &[
            "Rate",
            "Accumulator",
            "Mode",
            "DirSetup",
            "DirHold",
            "PulseWidth",
            "PulseIdle",
            "TableData",
            "TableLength",
            "MasterDDS",
        ],
        gtag::PWMGEN => &["PWMVal", "Mode", "PWMRate", "PDMRate", "Enable"],
        gtag::LED => &["LEDs"],
        _ => &[],
    }
}

fn render(h: &IdromHeader, mds: &[RawMd], pds: &[PinDescriptor], connectors: &[String]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "Configuration Name: HOSTMOT2\n");
    let _ = writeln!(s, "General configuration information:\n");
    let _ = writeln!(s, "  BoardName : {}", h.board_name());
    let _ = writeln!(s, "  FPGA Size: {} KGates", h.fpga_size);
    let _ = writeln!(s, "  FPGA Pins: {}", h.fpga_pins);
    let _ = writeln!(s, "  Number of IO Ports: {}", h.io_ports);
    let _ = writeln!(s, "  Width of one I/O port: {}", h.port_width);
    let _ = writeln!(s, "  Clock Low frequency: {}", mhz(h.clock_low, 4));
    let _ = writeln!(s, "  Clock High frequency: {}", mhz(h.clock_high, 4));
    let _ = writeln!(s, "  IDROM Type: {}", h.idrom_type);
    let _ = writeln!(s, "  Instance Stride 0: {}", h.instance_stride[0]);
    let _ = writeln!(s, "  Instance Stride 1: {}", h.instance_stride[1]);
    let _ = writeln!(s, "  Register Stride 0: {}", h.register_stride[0]);
    let _ = writeln!(s, "  Register Stride 1: {}", h.register_stride[1]);
    let _ = writeln!(s, "\nModules in configuration:");
    for m in mds {
        let name = gtag::mesaflash_name(m.tag)
            .map(str::to_string)
            .unwrap_or_else(|| format!("(unknown-gtag-{})", m.tag));
        let clock = match m.clock_tag {
            1 => h.clock_low,
            2 => h.clock_high,
            _ => 0,
        };
        let reg_stride = h.register_stride[(m.reg_sel & 1) as usize];
        let inst_stride = h.instance_stride[(m.inst_sel & 1) as usize];
        let _ = writeln!(s, "\n  Module: {name}");
        let _ = writeln!(s, "  There are {} of {name} in configuration", m.instances);
        let _ = writeln!(s, "  Version: {}", m.version);
        let _ = writeln!(s, "  Registers: {}", m.registers);
        let _ = writeln!(s, "  BaseAddress: {:04X}", m.base);
        let _ = writeln!(s, "  ClockFrequency: {}", mhz(clock, 3));
        let _ = writeln!(s, "  Register Stride: {reg_stride} bytes");
        let _ = writeln!(s, "  Instance Stride: {inst_stride} bytes");
    }
    let _ = writeln!(s, "Configuration pin-out:");
    let width = h.port_width.max(1);
    for (port, chunk) in pds.chunks(width as usize).enumerate() {
        let conn = connectors.get(port).map_or("??", String::as_str);
        let head = if width == 17 {
            "DB25 pin#"
        } else {
            "Pin#     "
        };
        let _ = writeln!(s, "\nIO Connections for {conn}");
        let _ = writeln!(
            s,
            "{head}             I/O   Pri. func    Sec. func        Chan     Sec. Pin func   Sec. Pin Dir\n"
        );
        for (bit, d) in chunk.iter().enumerate() {
            let io = port as u32 * width + bit as u32;
            let _ = write!(
                s,
                "{:2}                    {:3}   {:<8}     ",
                pin_column(width, bit as u32, io),
                io,
                gtag::mesaflash_name(d.primary_tag).unwrap_or("Unknown")
            );
            let sec = if d.sec_tag == 0 {
                None
            } else {
                Some(
                    gtag::mesaflash_name(d.sec_tag)
                        .map(str::to_string)
                        .unwrap_or_else(|| format!("Unknown-Gtag{}", d.sec_tag)),
                )
            };
            let Some(sec) = sec else {
                let _ = writeln!(s, "{:<15}", "None");
                continue;
            };
            let _ = write!(s, "{sec:<15}");
            if d.is_global() {
                let _ = write!(s, " Global    ");
            } else {
                let _ = write!(s, " {:2}        ", d.sec_unit);
            }
            let func = pins::mesaflash_function_name(d.sec_tag, d.sec_pin, d.sec_unit);
            let dir = if d.is_output() { "(Out)" } else { "(In)" };
            let _ = writeln!(s, "{func:<12}    {dir}");
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::ImageTransport;
    use crate::sim::boards;

    #[test]
    fn the_5i25_reads_as_mesaflash_shows_it() {
        let spec = boards::preset("5i25").unwrap();
        let mut t = ImageTransport::new(spec.image(), "t");
        let text = read_hmid(&mut t, &spec.connectors).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "Configuration Name: HOSTMOT2");
        assert!(text.contains("\n  BoardName : MESA5I25\n  FPGA Size: 9 KGates\n"));
        assert!(text.contains("  Clock Low frequency: 100.0000 MHz\n"));
        assert!(text.contains(
            "\n  Module: WatchDog\n  There are 1 of WatchDog in configuration\n  Version: 0\n  \
             Registers: 3\n  BaseAddress: 0C00\n  ClockFrequency: 100.000 MHz\n  \
             Register Stride: 256 bytes\n  Instance Stride: 4 bytes\n"
        ));
        assert!(text.contains("  Module: QCount\n"));
        assert!(text.contains(
            "Instance Stride: 4 bytes\nConfiguration pin-out:\n\nIO Connections for P3\n"
        ));
        assert!(text.contains(
            " 1                      0   IOPort       StepGen          0        Step/Table1     (Out)\n"
        ));
        assert!(text.contains(
            "14                      1   IOPort       StepGen          0        Dir/Table2      (Out)\n"
        ));
        assert!(text.contains(
 " 9                     12   IOPort       QCount           0        Quad-IDX        (In)\n"
        ));
        assert!(text.contains("\nIO Connections for P2\n"));
        assert!(text.contains(" 1                     17   IOPort       StepGen          5        Step/Table1     (Out)\n"));
        assert!(text.ends_with("13                     33   IOPort       None           \n"));
    }

    #[test]
    fn no_board_no_listing() {
        let mut t = ImageTransport::new(vec![0; 16], "t");
        let e = read_hmid(&mut t, &[]).unwrap_err();
        assert!(e.to_string().starts_with("invalid cookie"));
    }
}
