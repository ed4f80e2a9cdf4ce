//! EtherCAT frames: an Ethernet II header with EtherType 0x88A4, the
//! 2-byte EtherCAT header (length, type 1), then datagrams, each a
//! 10-byte header (command, index, address, length with the "more
//! follows" bit, IRQ), its data and a 2-byte working counter.
//!
//! [`Frame::parse`] checks every length against the bytes there and
//! never panics; [`FrameBuilder`] writes frames (the tool, tests, the
//! benchmark); [`datagram_spans`] gives the sim the place of each
//! datagram so it can work on the frame in place.

use crate::error::{Error, Result};

/// The EtherCAT EtherType.
pub const ETHERTYPE: u16 = 0x88A4;
/// Ethernet II header: destination, source, EtherType.
pub const ETH_HEADER_LEN: usize = 14;
/// The EtherCAT frame header.
pub const ECAT_HEADER_LEN: usize = 2;
/// A datagram's header.
pub const DATAGRAM_HEADER_LEN: usize = 10;
/// A datagram's working counter.
pub const WKC_LEN: usize = 2;
/// The shortest Ethernet frame without FCS: shorter frames are padded.
pub const MIN_FRAME_LEN: usize = 60;
/// The longest standard Ethernet frame without FCS.
pub const MAX_FRAME_LEN: usize = 1514;
/// The most datagram data one frame can carry.
pub const MAX_DATA: usize =
    MAX_FRAME_LEN - ETH_HEADER_LEN - ECAT_HEADER_LEN - DATAGRAM_HEADER_LEN - WKC_LEN;
/// EtherCAT header type: datagrams (the only one processed by slaves).
pub const TYPE_DATAGRAMS: u8 = 1;
/// Datagram length field: the 11 bits of the length.
const LEN_MASK: u16 = 0x07FF;
/// Datagram length field: the frame has circulated once.
const CIRCULATED: u16 = 1 << 14;
/// Datagram length field: another datagram follows.
const MORE: u16 = 1 << 15;

/// A datagram command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Command {
    /// No operation.
    Nop = 0,
    /// Auto-increment physical read.
    Aprd = 1,
    /// Auto-increment physical write.
    Apwr = 2,
    /// Auto-increment physical read-write.
    Aprw = 3,
    /// Configured-address physical read.
    Fprd = 4,
    /// Configured-address physical write.
    Fpwr = 5,
    /// Configured-address physical read-write.
    Fprw = 6,
    /// Broadcast read.
    Brd = 7,
    /// Broadcast write.
    Bwr = 8,
    /// Broadcast read-write.
    Brw = 9,
    /// Logical read.
    Lrd = 10,
    /// Logical write.
    Lwr = 11,
    /// Logical read-write.
    Lrw = 12,
    /// Auto-increment read, multiple write.
    Armw = 13,
    /// Configured-address read, multiple write.
    Frmw = 14,
}

impl Command {
    /// The command with code `c`.
    pub fn from_u8(c: u8) -> Option<Command> {
        use Command::*;
        Some(match c {
            0 => Nop,
            1 => Aprd,
            2 => Apwr,
            3 => Aprw,
            4 => Fprd,
            5 => Fpwr,
            6 => Fprw,
            7 => Brd,
            8 => Bwr,
            9 => Brw,
            10 => Lrd,
            11 => Lwr,
            12 => Lrw,
            13 => Armw,
            14 => Frmw,
            _ => return None,
        })
    }

    /// The mnemonic.
    pub fn name(self) -> &'static str {
        use Command::*;
        match self {
            Nop => "NOP",
            Aprd => "APRD",
            Apwr => "APWR",
            Aprw => "APRW",
            Fprd => "FPRD",
            Fpwr => "FPWR",
            Fprw => "FPRW",
            Brd => "BRD",
            Bwr => "BWR",
            Brw => "BRW",
            Lrd => "LRD",
            Lwr => "LWR",
            Lrw => "LRW",
            Armw => "ARMW",
            Frmw => "FRMW",
        }
    }

    /// Whether the address is logical (32 bits through FMMUs).
    pub fn is_logical(self) -> bool {
        matches!(self, Command::Lrd | Command::Lwr | Command::Lrw)
    }
}

/// A datagram read out of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Datagram<'a> {
    /// The command (None: a code no slave knows, passed on untouched).
    pub command: Option<Command>,
    /// The raw command byte.
    pub command_byte: u8,
    /// The index the master matches replies by.
    pub index: u8,
    /// The 32-bit address: ADP (low half) and ADO (high half), or the
    /// logical address.
    pub address: u32,
    /// The frame has circulated (a slave with a closed loop saw it).
    pub circulated: bool,
    /// Another datagram follows.
    pub more: bool,
    /// The IRQ field.
    pub irq: u16,
    /// The data.
    pub data: &'a [u8],
    /// The working counter.
    pub wkc: u16,
}

impl Datagram<'_> {
    /// The position/station address (ADP) of a physical command.
    pub fn adp(&self) -> u16 {
        self.address as u16
    }

    /// The register offset (ADO) of a physical command.
    pub fn ado(&self) -> u16 {
        (self.address >> 16) as u16
    }
}

/// A parsed EtherCAT frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Frame<'a> {
    /// Destination MAC.
    pub destination: [u8; 6],
    /// Source MAC.
    pub source: [u8; 6],
    /// The datagrams, in order.
    pub datagrams: Vec<Datagram<'a>>,
}

/// Where one datagram sits in a frame (byte offsets from the start of
/// the Ethernet frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DatagramSpan {
    /// Its header.
    pub header: usize,
    /// Its data.
    pub data: usize,
    /// The data's length.
    pub len: usize,
    /// Its working counter.
    pub wkc: usize,
}

/// Checks the Ethernet and EtherCAT headers and returns the EtherCAT
/// payload's range (datagrams), for frames of type 1.
fn payload_range(bytes: &[u8]) -> Result<std::ops::Range<usize>> {
    let min = ETH_HEADER_LEN + ECAT_HEADER_LEN;
    if bytes.len() < min {
        return Err(Error::truncated("EtherCAT frame headers", min, bytes.len()));
    }
    let ethertype = u16::from_be_bytes([bytes[12], bytes[13]]);
    if ethertype != ETHERTYPE {
        return Err(Error::NotEtherCat { ethertype });
    }
    let header = u16::from_le_bytes([bytes[14], bytes[15]]);
    let len = usize::from(header & LEN_MASK);
    let kind = (header >> 12) as u8;
    if kind != TYPE_DATAGRAMS {
        return Err(Error::malformed(
            "EtherCAT header",
            format!("type {kind} (only 1, datagrams, is processed by slaves)"),
        ));
    }
    let end = min + len;
    if end > bytes.len() {
        return Err(Error::truncated(
            format!("EtherCAT frame of length {len}"),
            end,
            bytes.len(),
        ));
    }
    Ok(min..end)
}

/// Finds the datagrams of a frame (type 1) without copying anything.
pub fn datagram_spans(bytes: &[u8]) -> Result<Vec<DatagramSpan>> {
    let range = payload_range(bytes)?;
    let mut spans = Vec::new();
    let mut at = range.start;
    loop {
        if at + DATAGRAM_HEADER_LEN > range.end {
            return Err(Error::truncated(
                format!("datagram {} header at byte {at}", spans.len() + 1),
                at + DATAGRAM_HEADER_LEN,
                range.end,
            ));
        }
        let len_field = u16::from_le_bytes([bytes[at + 6], bytes[at + 7]]);
        let len = usize::from(len_field & LEN_MASK);
        let data = at + DATAGRAM_HEADER_LEN;
        let wkc = data + len;
        if wkc + WKC_LEN > range.end {
            return Err(Error::truncated(
                format!(
                    "datagram {} of {len} data bytes at byte {at}",
                    spans.len() + 1
                ),
                wkc + WKC_LEN,
                range.end,
            ));
        }
        spans.push(DatagramSpan {
            header: at,
            data,
            len,
            wkc,
        });
        at = wkc + WKC_LEN;
        if len_field & MORE == 0 {
            return Ok(spans);
        }
    }
}

impl<'a> Frame<'a> {
    /// Parses a whole Ethernet frame (no FCS).
    pub fn parse(bytes: &'a [u8]) -> Result<Frame<'a>> {
        let spans = datagram_spans(bytes)?;
        let mac = |at: usize| -> [u8; 6] {
            let mut m = [0; 6];
            m.copy_from_slice(&bytes[at..at + 6]);
            m
        };
        let datagrams = spans
            .iter()
            .map(|s| {
                let h = &bytes[s.header..s.data];
                let len_field = u16::from_le_bytes([h[6], h[7]]);
                Datagram {
                    command: Command::from_u8(h[0]),
                    command_byte: h[0],
                    index: h[1],
                    address: u32::from_le_bytes([h[2], h[3], h[4], h[5]]),
                    circulated: len_field & CIRCULATED != 0,
                    more: len_field & MORE != 0,
                    irq: u16::from_le_bytes([h[8], h[9]]),
                    data: &bytes[s.data..s.data + s.len],
                    wkc: u16::from_le_bytes([bytes[s.wkc], bytes[s.wkc + 1]]),
                }
            })
            .collect();
        Ok(Frame {
            destination: mac(0),
            source: mac(6),
            datagrams,
        })
    }
}

/// Builds a frame datagram by datagram.
#[derive(Debug, Clone)]
pub struct FrameBuilder {
    bytes: Vec<u8>,
    last_header: Option<usize>,
}

impl FrameBuilder {
    /// A frame from `source` to the broadcast address.
    pub fn new(source: [u8; 6]) -> FrameBuilder {
        let mut bytes = Vec::with_capacity(MIN_FRAME_LEN);
        bytes.extend_from_slice(&[0xFF; 6]);
        bytes.extend_from_slice(&source);
        bytes.extend_from_slice(&ETHERTYPE.to_be_bytes());
        bytes.extend_from_slice(&[0, 0]);
        FrameBuilder {
            bytes,
            last_header: None,
        }
    }

    /// The datagram data bytes still free.
    pub fn room(&self) -> usize {
        (MAX_FRAME_LEN - self.bytes.len()).saturating_sub(DATAGRAM_HEADER_LEN + WKC_LEN)
    }

    /// Adds a datagram; returns the offset of its data in the frame, or
    /// an error if the frame is full.
    pub fn push(
        &mut self,
        command: Command,
        index: u8,
        address: u32,
        data: &[u8],
    ) -> Result<usize> {
        if data.len() > self.room() || data.len() > usize::from(LEN_MASK) {
            return Err(Error::malformed(
                format!("{} datagram of {} bytes", command.name(), data.len()),
                format!("only {} bytes left in the frame", self.room()),
            ));
        }
        if let Some(h) = self.last_header {
            let mut lf = u16::from_le_bytes([self.bytes[h + 6], self.bytes[h + 7]]);
            lf |= MORE;
            self.bytes[h + 6..h + 8].copy_from_slice(&lf.to_le_bytes());
        }
        let header = self.bytes.len();
        self.bytes.push(command as u8);
        self.bytes.push(index);
        self.bytes.extend_from_slice(&address.to_le_bytes());
        self.bytes
            .extend_from_slice(&(data.len() as u16).to_le_bytes());
        self.bytes.extend_from_slice(&[0, 0]);
        let at = self.bytes.len();
        self.bytes.extend_from_slice(data);
        self.bytes.extend_from_slice(&[0, 0]);
        self.last_header = Some(header);
        Ok(at)
    }

    /// Adds a physical datagram (ADP, ADO).
    pub fn push_physical(
        &mut self,
        command: Command,
        index: u8,
        adp: u16,
        ado: u16,
        data: &[u8],
    ) -> Result<usize> {
        self.push(command, index, u32::from(adp) | u32::from(ado) << 16, data)
    }

    /// The finished frame, padded to the Ethernet minimum.
    pub fn finish(mut self) -> Vec<u8> {
        let len = (self.bytes.len() - ETH_HEADER_LEN - ECAT_HEADER_LEN) as u16;
        let header = len | u16::from(TYPE_DATAGRAMS) << 12;
        self.bytes[14..16].copy_from_slice(&header.to_le_bytes());
        if self.bytes.len() < MIN_FRAME_LEN {
            self.bytes.resize(MIN_FRAME_LEN, 0);
        }
        self.bytes
    }
}

/// A short description of a frame's datagrams, for logs and the tool:
/// "LRW 0x00010000 len 12 wkc 3; FPRD 1001:0130 len 2 wkc 1".
pub fn describe(frame: &Frame<'_>) -> String {
    let parts: Vec<String> = frame
        .datagrams
        .iter()
        .map(|d| match d.command {
            Some(c) if c.is_logical() => format!(
                "{} {:#010x} len {} wkc {}",
                c.name(),
                d.address,
                d.data.len(),
                d.wkc
            ),
            Some(c) => format!(
                "{} {:04x}:{:04x} len {} wkc {}",
                c.name(),
                d.adp(),
                d.ado(),
                d.data.len(),
                d.wkc
            ),
            None => format!("command {:#04x} len {}", d.command_byte, d.data.len()),
        })
        .collect();
    parts.join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn build_and_parse_round_trip() {
        let mut b = FrameBuilder::new([0x10; 6]);
        b.push_physical(Command::Fprd, 7, 0x1001, 0x0130, &[0, 0])
            .unwrap();
        b.push(Command::Lrw, 8, 0x0001_0000, &[1, 2, 3]).unwrap();
        let bytes = b.finish();
        assert_eq!(bytes.len(), MIN_FRAME_LEN);
        let f = Frame::parse(&bytes).unwrap();
        assert_eq!(f.source, [0x10; 6]);
        assert_eq!(f.datagrams.len(), 2);
        let d = &f.datagrams[0];
        assert_eq!(
            (d.command, d.index, d.adp(), d.ado()),
            (Some(Command::Fprd), 7, 0x1001, 0x130)
        );
        assert!(d.more);
        assert!(!f.datagrams[1].more);
        assert_eq!(f.datagrams[1].data, &[1, 2, 3]);
        assert_eq!(
            describe(&f),
            "FPRD 1001:0130 len 2 wkc 0; LRW 0x00010000 len 3 wkc 0"
        );
    }

    #[test]
    fn bad_frames_are_errors() {
        assert!(matches!(
            Frame::parse(&[0; 10]),
            Err(Error::Truncated { .. })
        ));
        let mut ip = vec![0u8; 60];
        ip[12] = 0x08;
        assert!(matches!(
            Frame::parse(&ip),
            Err(Error::NotEtherCat { ethertype: 0x0800 })
        ));
        let mut b = FrameBuilder::new([0; 6]);
        b.push(Command::Brd, 0, 0, &[0; 4]).unwrap();
        let mut bytes = b.finish();
        // Claim more data than the frame holds.
        bytes[22] = 0xFF;
        bytes[23] = 0x07;
        let e = Frame::parse(&bytes).unwrap_err().to_string();
        assert!(e.contains("datagram 1"), "{e}");
        // "More follows" with nothing after.
        let mut b = FrameBuilder::new([0; 6]);
        b.push(Command::Brd, 0, 0, &[0; 2]).unwrap();
        let mut bytes = b.finish();
        bytes[23] |= 0x80;
        assert!(Frame::parse(&bytes).is_err());
    }

    #[test]
    fn a_full_frame_refuses_more() {
        let mut b = FrameBuilder::new([0; 6]);
        b.push(Command::Lrw, 0, 0, &vec![0; MAX_DATA]).unwrap();
        assert!(b.push(Command::Brd, 1, 0, &[0; 2]).is_err());
        assert_eq!(b.finish().len(), MAX_FRAME_LEN);
    }
}
