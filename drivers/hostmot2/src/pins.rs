//! Pin descriptors (hardware.md 5.6): reading them, giving each I/O pin to
//! GPIO or to a module instance (`hm2_configure_pins`), and the names a
//! pin's function has in LinuxCNC's log, in HAL aliases and in mesaflash.

use crate::error::{Hm2Error, Result};
use crate::idrom::IdromHeader;
use crate::log::MessageLog;
use crate::regs::{gtag, pd};
use crate::transport::Transport;

/// One pin descriptor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PinDescriptor {
    /// Which pin of the secondary module; bit 7 = the module drives it.
    pub sec_pin: u8,
    /// GTag of the secondary module (0 = none).
    pub sec_tag: u8,
    /// Instance of the secondary module; bit 7 = every instance.
    pub sec_unit: u8,
    /// Primary function (3 = IOPort).
    pub primary_tag: u8,
}

impl PinDescriptor {
    /// Decodes a descriptor word.
    pub fn from_word(w: u32) -> PinDescriptor {
        PinDescriptor {
            sec_pin: w as u8,
            sec_tag: (w >> 8) as u8,
            sec_unit: (w >> 16) as u8,
            primary_tag: (w >> 24) as u8,
        }
    }

    /// The descriptor word.
    pub fn to_word(self) -> u32 {
        self.sec_pin as u32
            | (self.sec_tag as u32) << 8
            | (self.sec_unit as u32) << 16
            | (self.primary_tag as u32) << 24
    }

    /// Whether the secondary module drives the pin.
    pub fn is_output(&self) -> bool {
        self.sec_pin & pd::OUTPUT != 0
    }

    /// The secondary pin number without the output bit.
    pub fn function(&self) -> u8 {
        self.sec_pin & !pd::OUTPUT
    }

    /// Whether the pin serves every instance of its module.
    pub fn is_global(&self) -> bool {
        self.sec_unit & pd::GLOBAL_UNIT != 0
    }
}

/// Reads IOWidth descriptors, one word each, checking every one.
pub fn read_all(
    t: &mut dyn Transport,
    idrom: &IdromHeader,
    connectors: u32,
) -> Result<Vec<PinDescriptor>> {
    let mut pins = Vec::with_capacity(idrom.io_width as usize);
    for pin in 0..idrom.io_width {
        let addr = idrom.addr as u64 + idrom.offset_to_pin_desc as u64 + 4 * pin as u64;
        let op = || format!("error reading Pin Descriptor {pin} (at 0x{addr:04x})");
        let addr = u32::try_from(addr).map_err(|_| Hm2Error::Transport {
            op: op(),
            source: crate::transport::TransportError::OutOfWindow {
                addr: u32::MAX,
                words: 1,
            },
        })?;
        let mut w = [0u32; 1];
        t.read(addr, &mut w)
            .map_err(|source| Hm2Error::Transport { op: op(), source })?;
        let d = PinDescriptor::from_word(w[0]);
        match d.primary_tag {
            0 => {
                return Err(Hm2Error::PinListEnds {
                    pin,
                    expected: idrom.io_width,
                })
            }
            pd::PRIMARY_IOPORT => {}
            tag => {
                return Err(Hm2Error::PinNotIoPort {
                    pin,
                    tag,
                    name: gtag::name(tag).unwrap_or("unknown").to_string(),
                })
            }
        }
        let port = pin / idrom.port_width;
        if port >= connectors {
            return Err(Hm2Error::BadPinPort { pin, port });
        }
        let bit = pin % idrom.port_width;
        if bit > 31 {
            return Err(Hm2Error::BadPinBit { pin, bit });
        }
        pins.push(d);
    }
    Ok(pins)
}

/// Who drives or reads an I/O pin after allocation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PinOwner {
    /// A full GPIO: HAL decides direction, open drain and inversion.
    Gpio,
    /// An input or output of a module instance.
    Module {
        /// The module's GTag.
        gtag: u8,
        /// The instance (`None` for a pin serving every instance).
        unit: Option<u8>,
        /// The function, without the output bit.
        function: u8,
        /// Whether the module drives the pin (it becomes an output at
        /// the first `write`, not at load).
        output: bool,
    },
}

/// One I/O pin after allocation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IoPin {
    /// I/O number (0-based, across connectors).
    pub io: u32,
    /// Connector (IOPort instance).
    pub port: u32,
    /// Bit within the connector.
    pub bit: u32,
    /// Its descriptor.
    pub desc: PinDescriptor,
    /// Who uses it.
    pub owner: PinOwner,
}

impl IoPin {
    /// Whether a module drives the pin.
    pub fn is_module_output(&self) -> bool {
        matches!(self.owner, PinOwner::Module { output: true, .. })
    }
}

/// Instances in use of each supported module, for pin allocation.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct InstancesUsed {
    /// Encoders.
    pub encoders: u32,
    /// Step generators.
    pub stepgens: u32,
    /// PWM generators.
    pub pwmgens: u32,
    /// Per Smart Serial port, the channels with a card (bit mask).
    pub sserial: [u8; crate::sserial::MAX_PORTS],
    /// PktUARTs (all the firmware has, as LinuxCNC takes them).
    pub pktuarts: u32,
}

impl InstancesUsed {
    fn of(&self, tag: u8) -> u32 {
        match tag {
            gtag::ENCODER => self.encoders,
            gtag::STEPGEN => self.stepgens,
            gtag::PWMGEN => self.pwmgens,
            gtag::PKTUART_TX | gtag::PKTUART_RX => self.pktuarts,
            _ => 0,
        }
    }
}

/// Gives each pin to GPIO or to an enabled module instance
/// (`hm2_configure_pins`): a pin goes to its secondary module when that
/// module is supported and the pin's instance is in use (a pin serving
/// every instance when any is); step generator outputs past
/// `stepgen_width` stay GPIO. With no IOPort instance no pin can be
/// configured, and each attempt is logged as LinuxCNC logs it.
pub fn allocate(
    descs: &[PinDescriptor],
    port_width: u32,
    ioport_instances: u32,
    used: &InstancesUsed,
    stepgen_width: u32,
    log: &mut MessageLog,
) -> Vec<IoPin> {
    let valid = ioport_instances as u64 * port_width as u64;
    let mut out = Vec::with_capacity(descs.len());
    for (i, d) in descs.iter().enumerate() {
        let io = i as u32;
        if io as u64 >= valid {
            log.err(format!("hm2_set_pin_source: invalid pin number {io}"));
            log.err(format!(
                "hm2_set_pin_direction_immediate: invalid pin number {io}"
            ));
        }
        let (n, unit_used) = if d.sec_tag == gtag::SSERIAL {
            // A channel's pins go to the module only when it has a card.
            let mask = used.sserial.get(d.sec_unit as usize).copied().unwrap_or(0);
            let chan = crate::sserial::PinRole::of(d.sec_pin).map(|r| r.channel());
            let on = chan.is_some_and(|c| c < 8 && mask & (1 << c) != 0);
            (u32::from(on), on)
        } else {
            let n = used.of(d.sec_tag);
            let unit_used = if d.is_global() {
                n > 0
            } else {
                (d.sec_unit as u32) < n
            };
            (n, unit_used)
        };
        let masked =
            d.sec_tag == gtag::STEPGEN && d.is_output() && d.function() as u32 > stepgen_width;
        let owner = if n > 0 && unit_used && !masked && (io as u64) < valid {
            PinOwner::Module {
                gtag: d.sec_tag,
                unit: (!d.is_global()).then_some(d.sec_unit),
                function: d.function(),
                output: d.is_output(),
            }
        } else {
            PinOwner::Gpio
        };
        out.push(IoPin {
            io,
            port: io / port_width.max(1),
            bit: io % port_width.max(1),
            desc: *d,
            owner,
        });
    }
    out
}

/// LinuxCNC's log name of a secondary function (`IO Pin ...` lines).
pub fn log_function_name(tag: u8, function: u8, output: bool) -> String {
    let s = match (tag, function, output) {
        (gtag::ENCODER, 1, _) => "A",
        (gtag::ENCODER, 2, _) => "B",
        (gtag::ENCODER, 3, _) => "Index",
        (gtag::ENCODER, 4, _) => "IndexMask",
        (gtag::ENCODER, 5, _) => "Probe",
        (gtag::STEPGEN, 1, true) => "Step",
        (gtag::STEPGEN, 2, true) => "Direction",
        (gtag::STEPGEN, n @ 3..=8, true) => return format!("Table{}Pin", n - 1),
        (gtag::STEPGEN, 1, false) => "Index",
        (gtag::STEPGEN, 2, false) => "Probe",
        (gtag::PWMGEN, 1, _) => "Out0 (PWM or Up)",
        (gtag::PWMGEN, 2, _) => "Out1 (Dir or Down)",
        (gtag::PWMGEN, 3, _) => "Not-Enable",
        (gtag::PKTUART_TX, 1, _) => "TX Data",
        (gtag::PKTUART_TX, 2, _) => "Drv Enable",
        (gtag::PKTUART_RX, 1, _) => "RX Data",
        (gtag::SSERIAL, f, o) => {
            // Function codes keep the SecPin's high nibble (without the
            // output bit): rx 0x0n, tx 0x0n out, txen 0x1n, ntxen 0x2n.
            let n = f & 0x0F;
            return match (f >> 4, o) {
                (0, false) => format!("RX{}", n.wrapping_sub(1)),
                (0, true) => format!("TX{}", n.wrapping_sub(1)),
                (1, _) => format!("TXEN{}", n.wrapping_sub(1)),
                (2, _) => format!("NTXEN{}", n.wrapping_sub(1)),
                _ => format!("unknown-pin-{function}"),
            };
        }
        _ => return format!("unknown-pin-{function}"),
    };
    s.to_string()
}

/// The HAL name of a module output pin, as used in the
/// `<board>.<module>.<NN>.<name>.invert_output` aliases.
pub fn hal_function_name(tag: u8, function: u8) -> Option<String> {
    Some(match (tag, function) {
        (gtag::STEPGEN, 1) => "step".into(),
        (gtag::STEPGEN, 2) => "direction".into(),
        (gtag::STEPGEN, n @ 3..=8) => format!("table{}", n - 1),
        (gtag::PWMGEN, 1) => "out0".into(),
        (gtag::PWMGEN, 2) => "out1".into(),
        (gtag::PWMGEN, 3) => "enable".into(),
        _ => return None,
    })
}

/// The module name in HAL names (`stepgen`, `pwmgen`, `encoder`).
pub fn hal_module_name(tag: u8) -> Option<&'static str> {
    Some(match tag {
        gtag::ENCODER => "encoder",
        gtag::STEPGEN => "stepgen",
        gtag::PWMGEN => "pwmgen",
        _ => return None,
    })
}

/// mesaflash's name of a secondary function (`--readhmid`).
pub fn mesaflash_function_name(tag: u8, sec_pin: u8, unit: u8) -> String {
    const STEPGEN: [&str; 8] = [
        "Step/Table1",
        "Dir/Table2",
        "Table3",
        "Table4",
        "Table5",
        "Table6",
        "Table7",
        "Table8",
    ];
    const QCOUNT: [&str; 5] = ["Quad-A", "Quad-B", "Quad-IDX", "Quad-IDXM", "Quad-Probe"];
    const PWM: [&str; 3] = ["PWM", "Dir", "/Enable"];
    if tag == gtag::SSERIAL {
        let c = sec_pin & 0x0F;
        return match sec_pin & 0xF0 {
            0x00 => format!("RXData{}", c.wrapping_sub(1)),
            0x80 => format!("TXData{}", c.wrapping_sub(1)),
            0x90 => format!("TXEn{}", c.wrapping_sub(1)),
            0xA0 => format!("TestPin{}", c.wrapping_sub(1)),
            _ => format!("Unknown-Gtag{tag}-Chan{unit}-Pin{sec_pin}"),
        };
    }
    let table: &[&str] = match tag {
        gtag::STEPGEN => &STEPGEN,
        gtag::ENCODER => &QCOUNT,
        gtag::PWMGEN => &PWM,
        _ => &[],
    };
    let k = (sec_pin & 0x0F) as usize;
    match k.checked_sub(1).and_then(|k| table.get(k)) {
        Some(s) => s.to_string(),
        None => format!("Unknown-Gtag{tag}-Chan{unit}-Pin{sec_pin}"),
    }
}

/// The DB-25 pin of each bit of a 17-pin connector.
pub const DB25_ORDER: [u32; 17] = [1, 14, 2, 15, 3, 16, 4, 17, 5, 6, 7, 8, 9, 10, 11, 12, 13];

/// The connector pin LinuxCNC's log shows for bit `bit` of a connector
/// `port_width` wide, or `None` for a width it does not know.
pub fn connector_pin(port_width: u32, bit: u32) -> Option<u32> {
    match port_width {
        24 => Some(2 * bit + 1),
        17 => DB25_ORDER.get(bit as usize).copied(),
        19 | 21 | 27 | 29 | 30 | 32 => Some(bit + 1),
        _ => None,
    }
}

/// The pin-usage lines LinuxCNC logs after allocation.
pub fn usage_lines(pins: &[IoPin], connectors: &[String], port_width: u32) -> Vec<String> {
    let mut v = vec![format!("{} I/O Pins used:", pins.len())];
    for p in pins {
        let conn = connectors
            .get(p.port as usize)
            .map(String::as_str)
            .unwrap_or("??");
        let place = match connector_pin(port_width, p.bit) {
            Some(n) => format!("{conn}-{n:02}"),
            None => format!("{conn}-?? (invalid port width {port_width})"),
        };
        let what = match p.owner {
            PinOwner::Gpio => "IOPort".to_string(),
            PinOwner::Module {
                gtag: tag,
                unit,
                function,
                output,
            } => format!(
                "{} #{}, pin {} ({})",
                gtag::name(tag).unwrap_or("unknown"),
                unit.map_or("all".to_string(), |u| u.to_string()),
                log_function_name(tag, function, output),
                if output { "Output" } else { "Input" }
            ),
        };
        v.push(format!("    IO Pin {:03} ({place}): {what}", p.io));
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pd(word: u32) -> PinDescriptor {
        PinDescriptor::from_word(word)
    }

    #[test]
    fn descriptor_words_round_trip() {
        let d = pd(0x0300_0581);
        assert_eq!(
            (d.sec_pin, d.sec_tag, d.sec_unit, d.primary_tag),
            (0x81, 5, 0, 3)
        );
        assert!(d.is_output());
        assert_eq!(d.function(), 1);
        assert_eq!(d.to_word(), 0x0300_0581);
    }

    #[test]
    fn allocation_follows_the_enabled_instances() {
        let descs = [
            pd(0x0300_0581), // stepgen 0 step
            pd(0x0300_0582), // stepgen 0 dir
            pd(0x0300_0583), // stepgen 0 table2: masked by stepgen_width 2
            pd(0x0301_0581), // stepgen 1 step: not enabled
            pd(0x0300_0401), // encoder 0 A (input)
            pd(0x0380_0403), // encoder index, global
            pd(0x0300_0000), // plain GPIO
            pd(0x0300_0701), // unsupported module: GPIO
        ];
        let used = InstancesUsed {
            encoders: 1,
            stepgens: 1,
            pwmgens: 0,
            ..InstancesUsed::default()
        };
        let mut log = MessageLog::default();
        let pins = allocate(&descs, 8, 1, &used, 2, &mut log);
        assert!(log.messages().is_empty());
        let owners: Vec<bool> = pins.iter().map(|p| p.owner != PinOwner::Gpio).collect();
        assert_eq!(owners, [true, true, false, false, true, true, false, false]);
        assert!(pins[0].is_module_output());
        assert!(!pins[4].is_module_output());
        assert_eq!(
            pins[5].owner,
            PinOwner::Module {
                gtag: 4,
                unit: None,
                function: 3,
                output: false
            }
        );
    }

    #[test]
    fn without_an_ioport_every_pin_is_reported() {
        let descs = [pd(0x0300_0000); 3];
        let mut log = MessageLog::default();
        let pins = allocate(&descs, 24, 0, &InstancesUsed::default(), 2, &mut log);
        assert!(pins.iter().all(|p| p.owner == PinOwner::Gpio));
        let lines = log.lines("", crate::log::Level::Err);
        assert_eq!(lines.len(), 6);
        assert_eq!(lines[0], "hm2_set_pin_source: invalid pin number 0");
        assert_eq!(
            lines[5],
            "hm2_set_pin_direction_immediate: invalid pin number 2"
        );
    }

    #[test]
    fn connector_pins_and_names() {
        assert_eq!(connector_pin(24, 2), Some(5));
        assert_eq!(connector_pin(17, 1), Some(14));
        assert_eq!(connector_pin(17, 16), Some(13));
        assert_eq!(connector_pin(32, 31), Some(32));
        assert_eq!(connector_pin(5, 0), None);
        assert_eq!(mesaflash_function_name(5, 0x81, 0), "Step/Table1");
        assert_eq!(mesaflash_function_name(4, 0x01, 0), "Quad-A");
        assert_eq!(mesaflash_function_name(6, 0x83, 0), "/Enable");
        assert_eq!(
            mesaflash_function_name(9, 0x81, 2),
            "Unknown-Gtag9-Chan2-Pin129"
        );
        assert_eq!(log_function_name(5, 3, true), "Table2Pin");
        assert_eq!(hal_function_name(6, 3).as_deref(), Some("enable"));
    }
}
