//! Writing an [`Mbccb`] back to the bytes `mesambccc` produces: the data
//! segment starts with an empty fragment (so no pointer is 0), type
//! tables are padded with empty fragments so their records are 4-byte
//! aligned, pin names carry their NUL.

use super::mbccb::{Command, Init, Mbccb, HEADER_LEN, RECORD_LEN, SIGNATURE};

struct Segment(Vec<u8>);

impl Segment {
    /// Appends a fragment; returns its pointer.
    fn push(&mut self, bytes: &[u8]) -> u32 {
        let at = self.0.len() as u32;
        self.0.push(bytes.len().min(255) as u8);
        self.0.extend_from_slice(&bytes[..bytes.len().min(255)]);
        at
    }

    /// Pads with empty fragments until a fragment pushed next has its
    /// contents 4-byte aligned.
    fn align(&mut self) {
        while (self.0.len() + 1) % 4 != 0 {
            self.0.push(0);
        }
    }
}

fn record(r: &mut [u8; RECORD_LEN], at: usize, bytes: &[u8]) {
    r[at..at + bytes.len()].copy_from_slice(bytes);
}

/// The file's bytes.
pub fn encode(m: &Mbccb) -> Vec<u8> {
    let mut data = Segment(vec![0]);
    let mut inits = Vec::with_capacity(m.inits.len() * RECORD_LEN);
    for i in &m.inits {
        inits.extend_from_slice(&init_record(i, &mut data));
    }
    let mut cmds = Vec::with_capacity(m.commands.len() * RECORD_LEN);
    for c in &m.commands {
        cmds.extend_from_slice(&command_record(c, &mut data));
    }
    let mut out = Vec::with_capacity(HEADER_LEN + inits.len() + cmds.len() + data.0.len());
    out.extend_from_slice(SIGNATURE);
    out.extend_from_slice(&m.baudrate.to_be_bytes());
    for v in [m.format, m.txdelay, m.rxdelay, m.drvdelay, m.icdelay, 0] {
        out.extend_from_slice(&v.to_be_bytes());
    }
    out.extend_from_slice(&[0u8; 28]);
    for v in [inits.len(), cmds.len(), data.0.len()] {
        out.extend_from_slice(&(v as u32).to_be_bytes());
    }
    out.extend_from_slice(&inits);
    out.extend_from_slice(&cmds);
    out.extend_from_slice(&data.0);
    out
}

fn htype_code(t: super::mbccb::HalType) -> u8 {
    use super::mbccb::HalType::*;
    match t {
        Bit => 1,
        Float => 2,
        S32 => 3,
        U32 => 4,
        S64 => 6,
        U64 => 7,
    }
}

/// An init record; its request goes into `data`.
fn init_record(i: &Init, data: &mut Segment) -> [u8; RECORD_LEN] {
    let mut r = [0u8; RECORD_LEN];
    match i {
        Init::Delay { us } => record(&mut r, 24, &us.to_be_bytes()),
        Init::Comms {
            baud,
            flags,
            rxdelay,
            txdelay,
            drvdelay,
            icdelay,
        } => {
            record(&mut r, 2, &flags.to_be_bytes());
            record(&mut r, 4, &1u16.to_be_bytes());
            record(&mut r, 6, &rxdelay.to_be_bytes());
            record(&mut r, 8, &txdelay.to_be_bytes());
            record(&mut r, 10, &drvdelay.to_be_bytes());
            record(&mut r, 12, &icdelay.to_be_bytes());
            record(&mut r, 24, &baud.to_be_bytes());
        }
        Init::Packet {
            mbid,
            func,
            flags,
            timeout_us,
            pdu,
        } => {
            r[0] = *mbid;
            r[1] = *func;
            record(&mut r, 2, &flags.to_be_bytes());
            record(&mut r, 24, &timeout_us.to_be_bytes());
            record(&mut r, 28, &data.push(pdu).to_be_bytes());
        }
    }
    r
}

/// A command record; its type table and pin names go into `data`.
fn command_record(c: &Command, data: &mut Segment) -> [u8; RECORD_LEN] {
    let mut r = [0u8; RECORD_LEN];
    r[0] = c.mbid;
    r[1] = c.func;
    record(&mut r, 2, &c.flags.to_be_bytes());
    record(&mut r, 4, &c.addr.to_be_bytes());
    record(&mut r, 6, &(c.pins.len() as u16).to_be_bytes());
    record(&mut r, 8, &c.regcnt.to_be_bytes());
    record(&mut r, 20, &c.interval_us.to_be_bytes());
    record(&mut r, 24, &c.timeout_us.to_be_bytes());
    if matches!(c.func, 3 | 4 | 6 | 16) {
        data.align();
        let table: Vec<u8> = c
            .pins
            .iter()
            .flat_map(|p| [p.mtype.0, htype_code(p.htype), p.flags, p.regofs])
            .collect();
        record(&mut r, 16, &data.push(&table).to_be_bytes());
    }
    let mut first = None;
    for p in &c.pins {
        let mut name = p.name.as_bytes().to_vec();
        name.push(0);
        let at = data.push(&name);
        first.get_or_insert(at);
    }
    record(&mut r, 28, &first.unwrap_or(0).to_be_bytes());
    r
}
