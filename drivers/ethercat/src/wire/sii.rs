//! The SII (slave information interface) EEPROM: 16-bit words, the fixed
//! area (PDI configuration, alias, checksum, identity, mailbox layout,
//! protocols) and the categories after word 0x40 (strings, general, FMMU
//! usage, sync managers, TxPDOs, RxPDOs), each a type word, a length in
//! words and its data, ended by 0xFFFF.
//!
//! [`Sii::encode`] writes an image (the simulator's EEPROM, generated
//! from a device description); [`Sii::decode`] reads one (the tool's
//! `sii-read`, images from files), refusing a wrong checksum, categories
//! running past the end and string indices that do not exist.

use crate::error::{Error, Result};

/// Word address of the configured station alias.
pub const WORD_ALIAS: usize = 0x0004;
/// Word address of the checksum (low byte) of words 0..7.
pub const WORD_CHECKSUM: usize = 0x0007;
/// Word address of the vendor id (u32).
pub const WORD_VENDOR: usize = 0x0008;
/// Word address of the product code (u32).
pub const WORD_PRODUCT: usize = 0x000A;
/// Word address of the revision (u32).
pub const WORD_REVISION: usize = 0x000C;
/// Word address of the serial number (u32).
pub const WORD_SERIAL: usize = 0x000E;
/// Word address of the standard receive mailbox offset.
pub const WORD_MAILBOX: usize = 0x0018;
/// Word address of the supported mailbox protocols.
pub const WORD_PROTOCOLS: usize = 0x001C;
/// Word address of the EEPROM size (KiBit − 1).
pub const WORD_SIZE: usize = 0x003E;
/// Word address of the layout version.
pub const WORD_VERSION: usize = 0x003F;
/// Word address of the first category.
pub const WORD_CATEGORIES: usize = 0x0040;

/// Category types.
pub mod category {
    /// Strings.
    pub const STRINGS: u16 = 10;
    /// General information.
    pub const GENERAL: u16 = 30;
    /// FMMU usage.
    pub const FMMU: u16 = 40;
    /// Sync managers.
    pub const SYNC_MANAGERS: u16 = 41;
    /// TxPDOs (slave → master).
    pub const TXPDO: u16 = 50;
    /// RxPDOs (master → slave).
    pub const RXPDO: u16 = 51;
    /// Distributed clocks.
    pub const DC: u16 = 60;
    /// End of categories.
    pub const END: u16 = 0xFFFF;
}

/// Mailbox protocols (word 0x1C).
pub mod protocol {
    /// CoE.
    pub const COE: u16 = 1 << 2;
}

/// CoE details (general category).
pub mod coe_details {
    /// SDO supported.
    pub const SDO: u8 = 1 << 0;
    /// SDO information.
    pub const SDO_INFO: u8 = 1 << 1;
    /// PDO assignment by SDO.
    pub const PDO_ASSIGN: u8 = 1 << 2;
    /// PDO configuration by SDO.
    pub const PDO_CONFIG: u8 = 1 << 3;
    /// SDO complete access.
    pub const COMPLETE_ACCESS: u8 = 1 << 5;
}

/// FMMU usage codes.
pub mod fmmu_usage {
    /// Unused.
    pub const UNUSED: u8 = 0;
    /// Outputs.
    pub const OUTPUTS: u8 = 1;
    /// Inputs.
    pub const INPUTS: u8 = 2;
    /// Sync manager status (mailbox polling).
    pub const SM_STATUS: u8 = 3;
}

/// Sync manager types (the SII's last byte of an SM entry).
pub mod sm_type {
    /// Unused.
    pub const UNUSED: u8 = 0;
    /// Mailbox out (master → slave).
    pub const MAILBOX_OUT: u8 = 1;
    /// Mailbox in (slave → master).
    pub const MAILBOX_IN: u8 = 2;
    /// Process data outputs.
    pub const OUTPUTS: u8 = 3;
    /// Process data inputs.
    pub const INPUTS: u8 = 4;
}

/// Vendor id, product code, revision, serial.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Identity {
    /// Vendor id.
    pub vendor: u32,
    /// Product code.
    pub product: u32,
    /// Revision number.
    pub revision: u32,
    /// Serial number.
    pub serial: u32,
}

/// The standard mailbox layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MailboxLayout {
    /// Receive (master → slave) mailbox offset.
    pub rx_offset: u16,
    /// Its size.
    pub rx_size: u16,
    /// Send (slave → master) mailbox offset.
    pub tx_offset: u16,
    /// Its size.
    pub tx_size: u16,
    /// Supported protocols ([`protocol`]).
    pub protocols: u16,
}

/// A sync manager entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SyncManager {
    /// Physical start address.
    pub start: u16,
    /// Default length.
    pub length: u16,
    /// Control byte.
    pub control: u8,
    /// Enable byte (bit 0: enable).
    pub enable: u8,
    /// Type ([`sm_type`]).
    pub kind: u8,
}

/// A PDO entry.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct PdoEntry {
    /// Object index (0 for a gap).
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// Name.
    pub name: String,
    /// CoE data type.
    pub data_type: u8,
    /// Bit length.
    pub bits: u8,
}

/// A PDO as the SII describes it.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Pdo {
    /// Index (0x16xx RxPDO, 0x1Axx TxPDO).
    pub index: u16,
    /// The sync manager it belongs to by default.
    pub sm: u8,
    /// Name.
    pub name: String,
    /// Flags (bit 0 mandatory, bit 4 fixed content, ...).
    pub flags: u16,
    /// Entries.
    pub entries: Vec<PdoEntry>,
}

/// What an SII image holds.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Sii {
    /// Configured station alias.
    pub alias: u16,
    /// Identity.
    pub identity: Identity,
    /// Mailbox layout (None: no mailbox).
    pub mailbox: Option<MailboxLayout>,
    /// The device name (general category, from the strings).
    pub name: String,
    /// Group name.
    pub group: String,
    /// Order code.
    pub order: String,
    /// CoE details ([`coe_details`]).
    pub coe_details: u8,
    /// FMMU usage ([`fmmu_usage`]).
    pub fmmus: Vec<u8>,
    /// Sync managers.
    pub sync_managers: Vec<SyncManager>,
    /// TxPDOs (inputs).
    pub tx_pdos: Vec<Pdo>,
    /// RxPDOs (outputs).
    pub rx_pdos: Vec<Pdo>,
    /// Whether the device has a DC category (cyclic sync supported).
    pub dc: bool,
}

/// The SII checksum: CRC-8 (polynomial 0x07, initial 0xFF) of bytes 0..14.
pub fn checksum(bytes: &[u8]) -> u8 {
    let mut crc: u8 = 0xFF;
    for &b in bytes.iter().take(14) {
        crc ^= b;
        for _ in 0..8 {
            crc = if crc & 0x80 != 0 {
                crc << 1 ^ 0x07
            } else {
                crc << 1
            };
        }
    }
    crc
}

/// The strings of an image being written, deduplicated; index 0 is "no
/// string".
#[derive(Default)]
struct Strings(Vec<String>);

impl Strings {
    fn index(&mut self, s: &str) -> u8 {
        if s.is_empty() {
            return 0;
        }
        if let Some(i) = self.0.iter().position(|x| x == s) {
            return i as u8 + 1;
        }
        if self.0.len() >= 255 {
            return 0;
        }
        self.0.push(s.chars().take(255).collect());
        self.0.len() as u8
    }
}

fn push_category(out: &mut Vec<u8>, kind: u16, mut data: Vec<u8>) {
    if data.len() % 2 == 1 {
        data.push(0);
    }
    out.extend_from_slice(&kind.to_le_bytes());
    out.extend_from_slice(&((data.len() / 2) as u16).to_le_bytes());
    out.extend_from_slice(&data);
}

impl Sii {
    /// The image's bytes (an even count: words), with a valid checksum.
    pub fn encode(&self) -> Vec<u8> {
        let mut out = vec![0u8; WORD_CATEGORIES * 2];
        let put16 = |out: &mut Vec<u8>, word: usize, v: u16| {
            out[word * 2..word * 2 + 2].copy_from_slice(&v.to_le_bytes())
        };
        let put32 = |out: &mut Vec<u8>, word: usize, v: u32| {
            out[word * 2..word * 2 + 4].copy_from_slice(&v.to_le_bytes())
        };
        // PDI control: digital I/O without mailbox, SPI with one.
        put16(
            &mut out,
            0,
            if self.mailbox.is_some() {
                0x0005
            } else {
                0x0004
            },
        );
        put16(&mut out, WORD_ALIAS, self.alias);
        let crc = checksum(&out);
        put16(&mut out, WORD_CHECKSUM, u16::from(crc));
        put32(&mut out, WORD_VENDOR, self.identity.vendor);
        put32(&mut out, WORD_PRODUCT, self.identity.product);
        put32(&mut out, WORD_REVISION, self.identity.revision);
        put32(&mut out, WORD_SERIAL, self.identity.serial);
        if let Some(m) = self.mailbox {
            put16(&mut out, WORD_MAILBOX, m.rx_offset);
            put16(&mut out, WORD_MAILBOX + 1, m.rx_size);
            put16(&mut out, WORD_MAILBOX + 2, m.tx_offset);
            put16(&mut out, WORD_MAILBOX + 3, m.tx_size);
            put16(&mut out, WORD_PROTOCOLS, m.protocols);
        }
        put16(&mut out, WORD_SIZE, 7); // 8 KiBit
        put16(&mut out, WORD_VERSION, 1);

        let mut strings = Strings::default();
        let group = strings.index(&self.group);
        let order = strings.index(&self.order);
        let name = strings.index(&self.name);
        let mut cats = Vec::new();
        let mut general = vec![0u8; 32];
        general[0] = group;
        general[1] = 0;
        general[2] = order;
        general[3] = name;
        general[5] = self.coe_details;
        general[14] = group;
        // Physical ports 0 and 1: MII.
        general[16] = 0x11;
        push_category(&mut cats, category::GENERAL, general);
        if !self.fmmus.is_empty() {
            push_category(&mut cats, category::FMMU, self.fmmus.clone());
        }
        if !self.sync_managers.is_empty() {
            let mut d = Vec::new();
            for s in &self.sync_managers {
                d.extend_from_slice(&s.start.to_le_bytes());
                d.extend_from_slice(&s.length.to_le_bytes());
                d.extend_from_slice(&[s.control, 0, s.enable, s.kind]);
            }
            push_category(&mut cats, category::SYNC_MANAGERS, d);
        }
        for (kind, pdos) in [
            (category::TXPDO, &self.tx_pdos),
            (category::RXPDO, &self.rx_pdos),
        ] {
            for p in pdos.iter() {
                let mut d = Vec::new();
                d.extend_from_slice(&p.index.to_le_bytes());
                d.push(p.entries.len().min(255) as u8);
                d.push(p.sm);
                d.push(0);
                d.push(strings.index(&p.name));
                d.extend_from_slice(&p.flags.to_le_bytes());
                for e in p.entries.iter().take(255) {
                    d.extend_from_slice(&e.index.to_le_bytes());
                    d.push(e.sub);
                    d.push(strings.index(&e.name));
                    d.push(e.data_type);
                    d.push(e.bits);
                    d.extend_from_slice(&[0, 0]);
                }
                push_category(&mut cats, kind, d);
            }
        }
        if self.dc {
            // One DC operation mode: SYNC0 with the cycle of the master.
            let mut d = vec![0u8; 24];
            d[20] = 0; // assign-activate low byte set by the master
            push_category(&mut cats, category::DC, d);
        }
        let mut s = vec![strings.0.len() as u8];
        for x in &strings.0 {
            s.push(x.len() as u8);
            s.extend_from_slice(x.as_bytes());
        }
        push_category(&mut out, category::STRINGS, s);
        out.extend_from_slice(&cats);
        out.extend_from_slice(&category::END.to_le_bytes());
        out.extend_from_slice(&[0xFF, 0xFF]);
        // The size word: kibibits less one, at least the 8 kibit of a
        // small EEPROM, enough for the whole image.
        let kbit = (out.len() * 8).div_ceil(1024).max(8);
        let size = u16::try_from(kbit - 1).unwrap_or(u16::MAX).to_le_bytes();
        out[WORD_SIZE * 2..WORD_SIZE * 2 + 2].copy_from_slice(&size);
        out
    }

    /// Reads an image; `source_name` names it in errors.
    pub fn decode(bytes: &[u8], source_name: Option<&str>) -> Result<Sii> {
        let err = |word: usize, reason: String| Error::Sii {
            source_name: source_name.map(str::to_string),
            word,
            reason,
        };
        if bytes.len() < WORD_CATEGORIES * 2 {
            return Err(err(
                bytes.len() / 2,
                format!(
                    "{} bytes, the fixed area alone is {}",
                    bytes.len(),
                    WORD_CATEGORIES * 2
                ),
            ));
        }
        let w16 = |word: usize| u16::from_le_bytes([bytes[word * 2], bytes[word * 2 + 1]]);
        let w32 = |word: usize| u32::from(w16(word)) | u32::from(w16(word + 1)) << 16;
        let crc = checksum(bytes);
        if u16::from(crc) != w16(WORD_CHECKSUM) & 0xFF {
            return Err(err(
                WORD_CHECKSUM,
                format!(
                    "checksum {:#04x}, words 0..6 give {crc:#04x}",
                    w16(WORD_CHECKSUM) & 0xFF
                ),
            ));
        }
        let protocols = w16(WORD_PROTOCOLS);
        let mut sii = Sii {
            alias: w16(WORD_ALIAS),
            identity: Identity {
                vendor: w32(WORD_VENDOR),
                product: w32(WORD_PRODUCT),
                revision: w32(WORD_REVISION),
                serial: w32(WORD_SERIAL),
            },
            mailbox: (protocols != 0 || w16(WORD_MAILBOX + 1) != 0).then(|| MailboxLayout {
                rx_offset: w16(WORD_MAILBOX),
                rx_size: w16(WORD_MAILBOX + 1),
                tx_offset: w16(WORD_MAILBOX + 2),
                tx_size: w16(WORD_MAILBOX + 3),
                protocols,
            }),
            ..Sii::default()
        };
        let cats = categories(bytes).map_err(|(word, reason)| err(word, reason))?;
        let strings = match cats.iter().find(|c| c.kind == category::STRINGS) {
            Some(c) => decode_strings(c.data).map_err(|r| err(c.word, r))?,
            None => Vec::new(),
        };
        let string = |word: usize, i: u8| -> Result<String> {
            if i == 0 {
                return Ok(String::new());
            }
            strings.get(usize::from(i) - 1).cloned().ok_or_else(|| {
                err(
                    word,
                    format!("string index {i}, the image has {} strings", strings.len()),
                )
            })
        };
        for c in &cats {
            match c.kind {
                category::GENERAL => {
                    if c.data.len() < 6 {
                        return Err(err(c.word, "general category shorter than 6 bytes".into()));
                    }
                    sii.group = string(c.word, c.data[0])?;
                    sii.order = string(c.word, c.data[2])?;
                    sii.name = string(c.word, c.data[3])?;
                    sii.coe_details = c.data[5];
                }
                category::FMMU => {
                    // The category is padded to whole words with unused
                    // entries.
                    let used = c.data.iter().rposition(|&u| u != fmmu_usage::UNUSED);
                    sii.fmmus = c.data[..used.map_or(0, |u| u + 1)].to_vec();
                }
                category::SYNC_MANAGERS => {
                    sii.sync_managers = c
                        .data
                        .chunks_exact(8)
                        .map(|d| SyncManager {
                            start: u16::from_le_bytes([d[0], d[1]]),
                            length: u16::from_le_bytes([d[2], d[3]]),
                            control: d[4],
                            enable: d[6],
                            kind: d[7],
                        })
                        .collect()
                }
                category::TXPDO | category::RXPDO => {
                    let pdo = decode_pdo(c.data, &|i| string(c.word, i)).map_err(|e| match e {
                        PdoError::Short(r) => err(c.word, r),
                        PdoError::Other(e) => e,
                    })?;
                    if c.kind == category::TXPDO {
                        sii.tx_pdos.push(pdo)
                    } else {
                        sii.rx_pdos.push(pdo)
                    }
                }
                category::DC => sii.dc = true,
                _ => {}
            }
        }
        Ok(sii)
    }
}

/// One category: its type, where it starts (word) and its data.
struct Category<'a> {
    kind: u16,
    word: usize,
    data: &'a [u8],
}

fn categories(bytes: &[u8]) -> std::result::Result<Vec<Category<'_>>, (usize, String)> {
    let mut out = Vec::new();
    let mut word = WORD_CATEGORIES;
    loop {
        let at = word * 2;
        if at + 2 > bytes.len() {
            // An image may end right after its last category.
            return Ok(out);
        }
        let kind = u16::from_le_bytes([bytes[at], bytes[at + 1]]);
        if kind == category::END {
            return Ok(out);
        }
        if at + 4 > bytes.len() {
            return Err((word, "category header cut off".into()));
        }
        let len = usize::from(u16::from_le_bytes([bytes[at + 2], bytes[at + 3]]));
        let data = bytes.get(at + 4..at + 4 + len * 2).ok_or_else(|| {
            (
                word,
                format!(
                    "category {kind} of {len} words runs past the end of the image ({} words)",
                    bytes.len() / 2
                ),
            )
        })?;
        out.push(Category { kind, word, data });
        word += 2 + len;
    }
}

fn decode_strings(data: &[u8]) -> std::result::Result<Vec<String>, String> {
    let Some((&count, mut rest)) = data.split_first() else {
        return Ok(Vec::new());
    };
    let mut out = Vec::with_capacity(usize::from(count));
    for i in 0..count {
        let Some((&len, r)) = rest.split_first() else {
            return Err(format!("string {} of {count} is missing", i + 1));
        };
        let s = r
            .get(..usize::from(len))
            .ok_or_else(|| format!("string {} of {len} bytes runs past the category", i + 1))?;
        out.push(String::from_utf8_lossy(s).into_owned());
        rest = &r[usize::from(len)..];
    }
    Ok(out)
}

enum PdoError {
    Short(String),
    Other(Error),
}

fn decode_pdo(
    data: &[u8],
    string: &dyn Fn(u8) -> Result<String>,
) -> std::result::Result<Pdo, PdoError> {
    if data.len() < 8 {
        return Err(PdoError::Short("PDO category shorter than 8 bytes".into()));
    }
    let count = usize::from(data[2]);
    let need = 8 + count * 8;
    if data.len() < need {
        return Err(PdoError::Short(format!(
            "PDO {:#06x} announces {count} entries ({need} bytes), the category has {}",
            u16::from_le_bytes([data[0], data[1]]),
            data.len()
        )));
    }
    let mut entries = Vec::with_capacity(count);
    for e in data[8..need].chunks_exact(8) {
        entries.push(PdoEntry {
            index: u16::from_le_bytes([e[0], e[1]]),
            sub: e[2],
            name: string(e[3]).map_err(PdoError::Other)?,
            data_type: e[4],
            bits: e[5],
        });
    }
    Ok(Pdo {
        index: u16::from_le_bytes([data[0], data[1]]),
        sm: data[3],
        name: string(data[5]).map_err(PdoError::Other)?,
        flags: u16::from_le_bytes([data[6], data[7]]),
        entries,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Sii {
        Sii {
            alias: 7,
            identity: Identity {
                vendor: 2,
                product: 0x03F0_3052,
                revision: 0x0011_0000,
                serial: 42,
            },
            mailbox: None,
            name: "EL1008".into(),
            group: "DigIn".into(),
            order: "EL1008 8Ch. Dig. Input 24V, 3ms".into(),
            coe_details: 0,
            fmmus: vec![fmmu_usage::INPUTS],
            sync_managers: vec![SyncManager {
                start: 0x1000,
                length: 1,
                control: 0x00,
                enable: 1,
                kind: sm_type::INPUTS,
            }],
            tx_pdos: vec![Pdo {
                index: 0x1A00,
                sm: 0,
                name: "Channel 1".into(),
                flags: 0x10,
                entries: vec![PdoEntry {
                    index: 0x6000,
                    sub: 1,
                    name: "Input".into(),
                    data_type: 1,
                    bits: 1,
                }],
            }],
            rx_pdos: vec![],
            dc: false,
        }
    }

    #[test]
    fn round_trip() {
        let s = sample();
        let bytes = s.encode();
        assert_eq!(bytes.len() % 2, 0);
        assert_eq!(Sii::decode(&bytes, None).unwrap(), s);
    }

    #[test]
    fn errors_name_the_word() {
        let mut bytes = sample().encode();
        bytes[8] ^= 1; // the alias, under the checksum
        let e = Sii::decode(&bytes, Some("el1008.bin"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("el1008.bin") && e.contains("checksum") && e.contains("0x0007"),
            "{e}"
        );
        let mut bytes = sample().encode();
        // First category (strings) claims 0x7FFF words.
        bytes[WORD_CATEGORIES * 2 + 2] = 0xFF;
        bytes[WORD_CATEGORIES * 2 + 3] = 0x7F;
        let e = Sii::decode(&bytes, None).unwrap_err().to_string();
        assert!(e.contains("runs past the end"), "{e}");
        assert!(Sii::decode(&[0; 10], None).is_err());
    }
}
