//! The bring-up tool's own master: EtherCrab over a [`Link`], the
//! segment scanned and brought to PRE-OP (addresses, mailboxes), then
//! one slave at a time: its AL state, state requests, its SII, SDOs.
//! Nothing cyclic: the tool is for a segment no running `lcec` owns.

use std::time::{Duration, Instant};

use ethercrab::std::ethercat_now;
use ethercrab::subdevice_group::PreOp;
use ethercrab::{Command, MainDevice, MainDeviceConfig, PduStorage, SubDeviceGroup, Timeouts};

use crate::error::{Error, Result};
use crate::link::Link;
use crate::master::io::Io;
use crate::master::{MAX_PDI, MAX_SLAVES};
use crate::regs::{self, al};
use crate::sdo::SdoClient;
use crate::wire::sii::{self, Sii};

const FRAMES: usize = 8;
const FRAME_DATA: usize = PduStorage::element_size(1100);
/// SII bytes read at most (a 32 kbit EEPROM; larger ones are cut).
pub const MAX_SII: usize = 4096;

type Group = SubDeviceGroup<MAX_SLAVES, MAX_PDI, ethercrab::DefaultLock, PreOp>;

/// A slave as the tool lists it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Listed {
    /// Ring position.
    pub position: u16,
    /// Station address.
    pub station: u16,
    /// Station alias (0: none).
    pub alias: u16,
    /// AL state byte (state and error bit).
    pub al_status: u8,
    /// Vendor, product, revision, serial.
    pub identity: (u32, u32, u32, u32),
}

/// The segment, at PRE-OP, with EtherCrab driven over the link.
pub struct Bus<'a> {
    md: &'a MainDevice<'a>,
    io: Io<'a>,
    group: Group,
    iface: String,
}

impl std::fmt::Debug for Bus<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Bus").field("iface", &self.iface).finish()
    }
}

/// Scans the segment on `link`, brings it to PRE-OP and runs `f` on it.
pub fn with_bus<T>(link: Box<dyn Link>, f: impl FnOnce(&mut Bus<'_>) -> Result<T>) -> Result<T> {
    let iface = link.describe();
    let storage = PduStorage::<FRAMES, FRAME_DATA>::new();
    let (tx, rx, pdu_loop) = storage.try_split().map_err(|_| Error::Master {
        iface: iface.clone(),
        step: "frame storage".into(),
        reason: "already in use".into(),
    })?;
    // A bring-up tool waits on nothing else: a frame late by a loaded
    // machine's scheduling (or a simulator's) must not end the command.
    let timeouts = Timeouts {
        pdu: Duration::from_millis(1000),
        eeprom: Duration::from_millis(500),
        mailbox_echo: Duration::from_millis(500),
        mailbox_response: Duration::from_millis(1000),
        ..Timeouts::default()
    };
    let md = MainDevice::new(pdu_loop, timeouts, MainDeviceConfig::default());
    let mut io = Io {
        tx,
        rx,
        link,
        buf: vec![0; 1600],
    };
    let group = io
        .block_on(md.init_single_group::<MAX_SLAVES, MAX_PDI>(ethercat_now))
        .map_err(|e| Error::Master {
            iface: iface.clone(),
            step: "scanning the segment (INIT to PRE-OP)".into(),
            reason: e.to_string(),
        })?;
    let mut bus = Bus {
        md: &md,
        io,
        group,
        iface,
    };
    f(&mut bus)
}

impl Bus<'_> {
    /// The interface's description.
    pub fn iface(&self) -> &str {
        &self.iface
    }

    /// Slaves found.
    pub fn len(&self) -> usize {
        self.group.len()
    }

    /// Whether no slave was found.
    pub fn is_empty(&self) -> bool {
        self.group.len() == 0
    }

    fn station(&self, position: u16) -> Result<u16> {
        self.group
            .subdevice(self.md, usize::from(position))
            .map(|s| s.configured_address())
            .map_err(|_| Error::Master {
                iface: self.iface.clone(),
                step: format!("slave {position}"),
                reason: format!("no such slave (the segment has {})", self.group.len()),
            })
    }

    fn wire(&self, position: u16, what: &str, e: impl std::fmt::Display) -> Error {
        Error::Master {
            iface: self.iface.clone(),
            step: format!("slave {position}: {what}"),
            reason: e.to_string(),
        }
    }

    /// Every slave with its state.
    pub fn list(&mut self) -> Result<Vec<Listed>> {
        let mut out = Vec::new();
        for p in 0..self.group.len() {
            let position = u16::try_from(p).unwrap_or(u16::MAX);
            let (station, alias, id) = {
                let sd = self
                    .group
                    .subdevice(self.md, p)
                    .map_err(|e| self.wire(position, "listing", e))?;
                let id = sd.identity();
                (
                    sd.configured_address(),
                    sd.alias_address(),
                    (id.vendor_id, id.product_id, id.revision, id.serial),
                )
            };
            let al_status = self.al_status(position)?.0;
            out.push(Listed {
                position,
                station,
                alias,
                al_status,
                identity: id,
            });
        }
        Ok(out)
    }

    /// A slave's AL status byte and AL status code.
    pub fn al_status(&mut self, position: u16) -> Result<(u8, u16)> {
        let st = self.station(position)?;
        let md = self.md;
        let raw = self
            .io
            .block_on(async {
                let s: u16 = Command::fprd(st, regs::AL_STATUS).receive(md).await?;
                let c: u16 = Command::fprd(st, regs::AL_STATUS_CODE).receive(md).await?;
                Ok::<_, ethercrab::error::Error>((s, c))
            })
            .map_err(|e| self.wire(position, "reading its AL status", e))?;
        Ok(((raw.0 & 0xFF) as u8, raw.1))
    }

    /// Asks a slave for an AL state (acknowledging an error) and waits up
    /// to `timeout` for it; an error names the state reached and the AL
    /// status code.
    pub fn request_state(&mut self, position: u16, state: u8, timeout: Duration) -> Result<()> {
        let st = self.station(position)?;
        let md = self.md;
        let request = u16::from(state) | u16::from(al::ERROR);
        self.io
            .block_on(Command::fpwr(st, regs::AL_CONTROL).send(md, request))
            .map_err(|e| self.wire(position, "writing AL control", e))?;
        let deadline = Instant::now() + timeout;
        loop {
            let (s, code) = self.al_status(position)?;
            if s & al::STATE_MASK == state && s & al::ERROR == 0 {
                return Ok(());
            }
            if s & al::ERROR != 0 || Instant::now() >= deadline {
                return Err(self.wire(
                    position,
                    &format!("requesting {}", al::name(state)),
                    format!(
                        "it is in {}{}, AL status code {code:#06x} ({})",
                        al::name(s & al::STATE_MASK),
                        if s & al::ERROR != 0 {
                            " with an error"
                        } else {
                            ""
                        },
                        regs::al_code::meaning(code)
                    ),
                ));
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// A slave's SII, as many bytes as its size word says (at most
    /// [`MAX_SII`]).
    pub fn sii_bytes(&mut self, position: u16) -> Result<Vec<u8>> {
        let md = self.md;
        let sd = self
            .group
            .subdevice(md, usize::from(position))
            .map_err(|e| self.wire(position, "SII", e))?;
        let mut size_word = [0u8; 2];
        self.io
            .block_on(sd.eeprom_read_raw(md, sii::WORD_SIZE as u16, &mut size_word))
            .map_err(|e| self.wire(position, "reading its SII size", e))?;
        // The size word counts kibibits less one.
        let kbit = usize::from(u16::from_le_bytes(size_word)) + 1;
        let len = (kbit * 128).clamp(sii::WORD_CATEGORIES * 2, MAX_SII);
        let mut buf = vec![0u8; len];
        let n = self
            .io
            .block_on(sd.eeprom_read_raw(md, 0, &mut buf))
            .map_err(|e| self.wire(position, "reading its SII", e))?;
        buf.truncate(n);
        Ok(buf)
    }

    /// A slave's SII, decoded.
    pub fn sii(&mut self, position: u16) -> Result<Sii> {
        let bytes = self.sii_bytes(position)?;
        Sii::decode(&bytes, Some(&format!("slave {position}")))
    }

    /// Reads an SDO.
    pub fn upload(
        &mut self,
        position: u16,
        index: u16,
        sub: u8,
        complete: bool,
    ) -> Result<Vec<u8>> {
        let st = self.station(position)?;
        let md = self.md;
        self.io
            .block_on(async {
                let mut c = SdoClient::new(md, st).await?;
                c.upload(index, sub, complete).await
            })
            .map_err(|e| name_position(e, position, &self.iface))
    }

    /// Writes an SDO (segmented when longer than the mailbox holds).
    pub fn download(
        &mut self,
        position: u16,
        index: u16,
        sub: u8,
        complete: bool,
        data: &[u8],
    ) -> Result<()> {
        let st = self.station(position)?;
        let md = self.md;
        self.io
            .block_on(async {
                let mut c = SdoClient::new(md, st).await?;
                c.download(index, sub, complete, data).await
            })
            .map_err(|e| name_position(e, position, &self.iface))
    }
}

fn name_position(e: Error, position: u16, iface: &str) -> Error {
    match e {
        Error::Master {
            iface: i,
            step,
            reason,
        } if i.is_empty() => Error::Master {
            iface: iface.to_string(),
            step: format!("slave {position}: {step}"),
            reason,
        },
        Error::SdoAbort { what, code, .. } => Error::SdoAbort {
            slave: position.to_string(),
            what,
            code,
        },
        e => e,
    }
}
