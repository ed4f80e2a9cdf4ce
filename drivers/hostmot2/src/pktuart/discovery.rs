//! Finding the PktUARTs in the module descriptors: a transmitter and a
//! receiver descriptor with the same number of instances, instance N of
//! each making `<board>.pktuart.N` (as LinuxCNC pairs them).

use crate::error::{Hm2Error, Result};
use crate::md::{self, ModuleDescriptor};
use crate::regs::{gtag, pktuart as r};

/// One PktUART: the register addresses of its two halves.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PktUartInstance {
    /// HAL name (`hm2_5i25.0.pktuart.0`).
    pub name: String,
    /// Instance number.
    pub index: usize,
    /// TX data, count, bit-rate and mode register addresses.
    pub tx: [u32; 4],
    /// RX data, count, bit-rate and mode register addresses.
    pub rx: [u32; 4],
    /// The modules' clock (ClockLow) in Hz.
    pub clock_hz: u32,
    /// Transmitter module version.
    pub tx_version: u8,
    /// Receiver module version.
    pub rx_version: u8,
}

impl PktUartInstance {
    /// LinuxCNC's `hm2_pktuart_get_version`: RX version in bits 4..7, TX
    /// in bits 0..3.
    pub fn version_word(&self) -> u32 {
        u32::from(self.rx_version & 0xF) << 4 | u32::from(self.tx_version & 0xF)
    }
}

/// The PktUARTs of a firmware.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PktUartFirmware {
    /// The instances, in order.
    pub instances: Vec<PktUartInstance>,
}

fn addrs(md: &ModuleDescriptor, inst: usize) -> [u32; 4] {
    [r::DATA, r::COUNT, r::BITRATE, r::MODE].map(|reg| md.inst_reg(reg, inst))
}

impl PktUartFirmware {
    /// The PktUARTs described in `mds` for the board named `prefix`; none
    /// if the firmware has neither half, an error if it has one half
    /// only, two of a half, or halves of different sizes.
    pub fn discover(mds: &[ModuleDescriptor], prefix: &str) -> Result<PktUartFirmware> {
        let find = |tag: u8| -> Result<Option<&ModuleDescriptor>> {
            let mut it = mds.iter().filter(|m| m.gtag == tag);
            let first = it.next();
            if let Some(m) = first {
                if it.next().is_some() {
                    return Err(Hm2Error::DuplicateMd {
                        name: gtag::name(tag).unwrap_or("PktUART"),
                    });
                }
                md::check_pktuart(m)?;
            }
            Ok(first)
        };
        let (tx, rx) = match (find(gtag::PKTUART_TX)?, find(gtag::PKTUART_RX)?) {
            (None, None) => return Ok(PktUartFirmware::default()),
            (Some(t), Some(r)) if t.instances == r.instances => (t, r),
            (t, r) => {
                return Err(Hm2Error::PktUartHalves {
                    tx: t.map_or(0, |m| m.instances),
                    rx: r.map_or(0, |m| m.instances),
                })
            }
        };
        let instances = (0..tx.instances as usize)
            .map(|i| PktUartInstance {
                name: format!("{prefix}.pktuart.{i}"),
                index: i,
                tx: addrs(tx, i),
                rx: addrs(rx, i),
                clock_hz: tx.clock_hz,
                tx_version: tx.version,
                rx_version: rx.version,
            })
            .collect();
        Ok(PktUartFirmware { instances })
    }

    /// The instance called `name`.
    pub fn by_name(&self, name: &str) -> Option<&PktUartInstance> {
        self.instances.iter().find(|i| i.name == name)
    }
}
