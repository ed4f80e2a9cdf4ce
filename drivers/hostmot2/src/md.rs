//! Module descriptors (hardware.md 5.4): reading them, and the shape each
//! supported module must have (hardware.md 5.7 steps 9 and 10).

use crate::error::{Hm2Error, Result};
use crate::idrom::IdromHeader;
use crate::regs::{self, gtag, md as f};
use crate::transport::Transport;

/// One module descriptor, with its strides and clock resolved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModuleDescriptor {
    /// Position in the descriptor list.
    pub index: usize,
    /// Where it was read.
    pub addr: u32,
    /// General function tag.
    pub gtag: u8,
    /// Version.
    pub version: u8,
    /// ClockTag (1 = ClockLow, 2 = ClockHigh).
    pub clock_tag: u8,
    /// Instances in the firmware.
    pub instances: u8,
    /// Address of register 0 of instance 0.
    pub base_address: u16,
    /// Registers.
    pub num_registers: u8,
    /// Resolved register stride.
    pub register_stride: u32,
    /// Resolved instance stride.
    pub instance_stride: u32,
    /// MultipleRegisters: bit r set = register r exists per instance.
    pub multiple_registers: u32,
    /// The module's clock in Hz (from ClockTag).
    pub clock_hz: u32,
    /// The three raw words.
    pub words: [u32; 3],
}

impl ModuleDescriptor {
    /// Decodes a record read at `addr`, checking ClockTag and the stride
    /// selectors in LinuxCNC's order.
    pub fn decode(
        index: usize,
        addr: u32,
        w: [u32; 3],
        idrom: &IdromHeader,
    ) -> Result<ModuleDescriptor> {
        let clock_tag = (w[0] >> 16) as u8;
        let clock_hz = match clock_tag {
            f::CLOCK_LOW_TAG => idrom.clock_low,
            f::CLOCK_HIGH_TAG => idrom.clock_high,
            tag => return Err(Hm2Error::BadClockTag { index, addr, tag }),
        };
        let reg_sel = ((w[1] >> 24) & 0x0F) as u8;
        let register_stride = match reg_sel {
            0 | 1 => idrom.register_stride[reg_sel as usize],
            selector => {
                return Err(Hm2Error::BadRegisterStride {
                    index,
                    addr,
                    selector,
                })
            }
        };
        let inst_sel = (w[1] >> 28) as u8;
        let instance_stride = match inst_sel {
            0 | 1 => idrom.instance_stride[inst_sel as usize],
            selector => {
                return Err(Hm2Error::BadInstanceStride {
                    index,
                    addr,
                    selector,
                })
            }
        };
        Ok(ModuleDescriptor {
            index,
            addr,
            gtag: w[0] as u8,
            version: (w[0] >> 8) as u8,
            clock_tag,
            instances: (w[0] >> 24) as u8,
            base_address: w[1] as u16,
            num_registers: (w[1] >> 16) as u8,
            register_stride,
            instance_stride,
            multiple_registers: w[2],
            clock_hz,
            words: w,
        })
    }

    /// Address of module-wide register `reg` (wrapping: [`check_window`]
    /// has made sure the registers in use fit the window).
    #[inline]
    pub fn reg(&self, reg: usize) -> u32 {
        (self.base_address as u32).wrapping_add((reg as u32).wrapping_mul(self.register_stride))
    }

    /// Address of register `reg` of instance `inst`.
    #[inline]
    pub fn inst_reg(&self, reg: usize, inst: usize) -> u32 {
        self.reg(reg)
            .wrapping_add((inst as u32).wrapping_mul(self.instance_stride))
    }

    /// LinuxCNC's name of the module.
    pub fn name(&self) -> String {
        gtag::name(self.gtag)
            .map(str::to_string)
            .unwrap_or_else(|| format!("(unknown-gtag-{})", self.gtag))
    }

    /// Whether (NumRegisters, InstanceStride, MultipleRegisters) match.
    fn shape_is(&self, num_registers: u8, instance_stride: u32, multiple: u32) -> bool {
        self.num_registers == num_registers
            && self.instance_stride == instance_stride
            && self.multiple_registers == multiple
    }

    fn inconsistent(&self, headline: String) -> Hm2Error {
        Hm2Error::InconsistentMd {
            headline,
            version: self.version,
            num_registers: self.num_registers,
            instance_stride: self.instance_stride,
            multiple_registers: self.multiple_registers,
        }
    }

    /// Debug lines describing the descriptor (`debug_module_descriptors=1`).
    pub fn describe(&self) -> Vec<String> {
        vec![
            format!("Module Descriptor {} at 0x{:04X}:", self.index, self.addr),
            format!("    General Function Tag: {} ({})", self.gtag, self.name()),
            format!("    Version: {}", self.version),
            format!(
                "    Clock Tag: {} ({} MHz)",
                self.clock_tag,
                self.clock_hz as f64 / 1e6
            ),
            format!("    Instances: {}", self.instances),
            format!("    Base Address: 0x{:04X}", self.base_address),
            format!("    -- Num Registers: {}", self.num_registers),
            format!("    Register Stride: 0x{:08X}", self.register_stride),
            format!("    -- Instance Stride: 0x{:08X}", self.instance_stride),
            format!(
                "    -- Multiple Registers: 0x{:08X}",
                self.multiple_registers
            ),
        ]
    }
}

/// Reads the descriptors until GTag 0 or 48 records.
pub fn read_all(t: &mut dyn Transport, idrom: &IdromHeader) -> Result<Vec<ModuleDescriptor>> {
    let mut mds = Vec::new();
    for index in 0..regs::MAX_MODULE_DESCRIPTORS {
        let addr = idrom.addr as u64 + idrom.offset_to_modules as u64 + (index * f::BYTES) as u64;
        let op = || format!("error reading Module Descriptor {index} (at 0x{addr:04x})");
        let addr32 = u32::try_from(addr).map_err(|_| Hm2Error::Transport {
            op: op(),
            source: crate::transport::TransportError::OutOfWindow {
                addr: u32::MAX,
                words: f::WORDS,
            },
        })?;
        let mut w = [0u32; f::WORDS];
        t.read(addr32, &mut w)
            .map_err(|source| Hm2Error::Transport { op: op(), source })?;
        if w[0] as u8 == gtag::END {
            break;
        }
        mds.push(ModuleDescriptor::decode(index, addr32, w, idrom)?);
    }
    Ok(mds)
}

/// Checks that every register of a module the driver uses lies in the
/// 64 KiB window. LinuxCNC does not check this (a wild RegisterStride
/// would make it access memory past the BAR); here it is a load error.
pub fn check_window(md: &ModuleDescriptor) -> Result<()> {
    check_extent(md, 4)
}

/// Checks that a module's last register of its last instance, plus
/// `tail` bytes, ends inside the window.
fn check_extent(md: &ModuleDescriptor, tail: u64) -> Result<()> {
    let last_reg = md.num_registers.saturating_sub(1) as u64;
    let last_inst = md.instances.saturating_sub(1) as u64;
    let end = md.base_address as u64
        + last_reg * md.register_stride as u64
        + last_inst * md.instance_stride as u64
        + tail;
    if end > regs::WINDOW_BYTES as u64 {
        return Err(Hm2Error::MdOutsideWindow {
            index: md.index,
            addr: md.addr,
            name: md.name(),
            end,
        });
    }
    Ok(())
}

/// Checks an IOPort descriptor: (v0, 5 registers, stride 4, 0x1F).
pub fn check_ioport(md: &ModuleDescriptor) -> Result<()> {
    if md.version == 0 && md.shape_is(5, 4, 0x1F) {
        Ok(())
    } else {
        Err(md.inconsistent("inconsistent Module Descriptor for IOPort, not loading driver".into()))
    }
}

/// Checks a Watchdog descriptor: (v0, 3, 4, 0).
pub fn check_watchdog(md: &ModuleDescriptor) -> Result<()> {
    if md.version == 0 && md.shape_is(3, 4, 0) {
        Ok(())
    } else {
        Err(md
            .inconsistent("inconsistent Module Descriptor for Watchdog, not loading driver".into()))
    }
}

/// Checks an Encoder descriptor: versions 1, 2, 3 and 0x83 with (5, 4,
/// 0x03). Returns a warning for version 1.
pub fn check_encoder(md: &ModuleDescriptor) -> Result<Option<&'static str>> {
    match md.version {
        1 | 2 | 3 | 0x83 if md.shape_is(5, 4, 0x03) => {
            Ok((md.version == 1).then_some("Encoder v1, index logic is buggy"))
        }
        _ => Err(md.inconsistent("inconsistent Encoder Module Descriptor!".into())),
    }
}

/// Checks a StepGen descriptor: versions 0, 1, 2, 0x42 and 0xC2 with (10,
/// 4, 0x1FF). Returns a warning for the old versions.
pub fn check_stepgen(md: &ModuleDescriptor) -> Result<Option<&'static str>> {
    match md.version {
        0 | 1 | 2 | 0x42 | 0xC2 if md.shape_is(10, 4, 0x1FF) => Ok(match md.version {
            0 => Some("WARNING: this firmware has stepgen v0!\nWARNING: upgrade your firmware!"),
            1 => Some("WARNING: this firmware has stepgen v1!\nWARNING: upgrade your firmware!"),
            _ => None,
        }),
        _ => Err(md.inconsistent(format!(
            "unknown stepgen MD:\n    Version = {}, expected 0-2, 0x42 or 0xC2",
            md.version
        ))),
    }
}

/// Checks a PWMGen descriptor: versions 0 and 1 with (5, 4, 0x03).
pub fn check_pwmgen(md: &ModuleDescriptor) -> Result<()> {
    match md.version {
        0 | 1 if md.shape_is(5, 4, 0x03) => Ok(()),
        v => Err(md.inconsistent(format!("Unsupported PWM firmware version {v}"))),
    }
}

/// Checks an LED descriptor: (v0, 1, 4, 0).
pub fn check_led(md: &ModuleDescriptor) -> Result<()> {
    if md.version == 0 && md.shape_is(1, 4, 0) {
        Ok(())
    } else {
        Err(md.inconsistent("inconsistent Module Descriptor for LED, not loading driver".into()))
    }
}

/// Checks a Smart Serial descriptor: (v0, 6 registers, instance stride
/// 0x40, 0x3C); the layout of firmware before revision 22 (5 registers,
/// 0x1F) is refused with LinuxCNC's message. Its per-channel registers
/// must fit the window too.
pub fn check_sserial(md: &ModuleDescriptor) -> Result<()> {
    if md.version == 0 && md.shape_is(5, 0x40, 0x1F) {
        return Err(md.inconsistent(
            "The bitfile contains Smart Serial modules for a firmware revision < rev22. \
             This Driver now requires rev22 or newer firmwares"
                .into(),
        ));
    }
    if md.version != 0 || !md.shape_is(6, 0x40, 0x3C) {
        return Err(md.inconsistent("inconsistent Module Descriptor!".into()));
    }
    // The last register of the last port, channel 7.
    check_extent(md, 4 * crate::sserial::MAX_CHANNELS as u64)
}

/// Checks a PktUART transmitter or receiver descriptor: four registers,
/// each per instance (MultipleRegisters 0x0F), instances 4 bytes apart in
/// the firmware Mesa ships; versions 2 and up (LinuxCNC's hm2_modbus
/// refuses older ones and they lack the 24-bit rate word).
pub fn check_pktuart(md: &ModuleDescriptor) -> Result<()> {
    if md.num_registers != 4 || md.multiple_registers != 0x0F {
        return Err(md.inconsistent("inconsistent Module Descriptor for PktUART".into()));
    }
    if md.version < 2 {
        return Err(md.inconsistent(format!(
            "PktUART version {} is not supported (version 2 or later needed)",
            md.version
        )));
    }
    check_window(md)
}
