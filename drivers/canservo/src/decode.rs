//! Frames in words, for people watching a bus (the bring-up tool's
//! `watch`): NMT, SYNC, EMCY with the error's meaning, SDO requests and
//! answers with the object's name and abort meanings, heartbeats, and
//! PDOs decoded field by field through a mapping, either the driver's
//! own process image or the one read from the drives.

use std::collections::HashMap;
use std::time::Duration;

use crate::bus::CanBus;
use crate::codes::{AbortCode, ErrorCode};
use crate::frame::{Frame, FrameKind};
use crate::power::PowerState;
use crate::regs::{cob, describe_object, err, nmt, obj, sdo};
use crate::sdo::SdoClient;

/// One mapped object: index, sub-index, bits.
type Entry = (u16, u8, u8);

/// Decodes frames for display.
#[derive(Debug, Clone, Default)]
pub struct Decoder {
    pdos: HashMap<u16, (String, Vec<Entry>)>,
}

impl Decoder {
    /// A decoder that knows no PDO mapping (PDOs are shown raw).
    pub fn new() -> Decoder {
        Decoder::default()
    }

    /// The driver's process image (see [`crate::startup`]) for `nodes`.
    pub fn canservo(nodes: &[u8], position_mode: bool) -> Decoder {
        let target = if position_mode {
            obj::TARGET_POSITION
        } else {
            obj::TARGET_VELOCITY
        };
        let mut d = Decoder::new();
        for &n in nodes {
            let n16 = u16::from(n);
            d.pdos.insert(
                cob::RPDO[0] + n16,
                (
                    format!("RPDO1 node {n}"),
                    vec![
                        (obj::CONTROLWORD, 0, 16),
                        (target, 0, 32),
                        (obj::MODES_OF_OPERATION, 0, 8),
                    ],
                ),
            );
            d.pdos.insert(
                cob::TPDO[0] + n16,
                (
                    format!("TPDO1 node {n}"),
                    vec![
                        (obj::STATUSWORD, 0, 16),
                        (obj::POSITION_ACTUAL, 0, 32),
                        (obj::MODES_DISPLAY, 0, 8),
                    ],
                ),
            );
            d.pdos.insert(
                cob::TPDO[1] + n16,
                (
                    format!("TPDO2 node {n}"),
                    vec![(obj::VELOCITY_ACTUAL, 0, 32), (obj::ERROR_CODE, 0, 16)],
                ),
            );
        }
        d
    }

    /// The mappings the drives at `nodes` hold now, read by SDO; PDOs a
    /// drive does not answer for are left out.
    pub fn read_from(bus: &dyn CanBus, nodes: &[u8], timeout: Duration) -> Decoder {
        let mut d = Decoder::new();
        for &n in nodes {
            let sdo = SdoClient::new(bus, n, timeout);
            for (kind, comm, map) in [
                ("RPDO", obj::RPDO_COMM, obj::RPDO_MAP),
                ("TPDO", obj::TPDO_COMM, obj::TPDO_MAP),
            ] {
                for p in 0..4u16 {
                    let Ok(cob_id) = sdo.read_u32(comm + p, 1) else {
                        continue;
                    };
                    if cob_id & obj::COB_INVALID != 0 {
                        continue;
                    }
                    let Ok(count) = sdo.read_u8(map + p, 0) else {
                        continue;
                    };
                    let entries: Vec<Entry> = (1..=count.min(8))
                        .filter_map(|s| sdo.read_u32(map + p, s).ok())
                        .map(|e| ((e >> 16) as u16, (e >> 8) as u8, e as u8))
                        .collect();
                    d.pdos.insert(
                        (cob_id & 0x7FF) as u16,
                        (format!("{kind}{} node {n}", p + 1), entries),
                    );
                }
            }
        }
        d
    }

    /// `f` in words.
    pub fn describe(&self, f: &Frame) -> String {
        match f.kind {
            FrameKind::Error => return describe_error(f),
            FrameKind::Remote => {
                return format!("remote request for {:03X} ({} bytes)", f.id, f.len)
            }
            FrameKind::Data if f.extended => {
                return format!("29-bit frame {:08X}: {}", f.id, hex(f.payload()))
            }
            FrameKind::Data => {}
        }
        let id = f.id as u16;
        let d = f.payload();
        if id == cob::NMT {
            return describe_nmt(d);
        }
        if id == cob::SYNC {
            return match d {
                [] => "SYNC".into(),
                [c] => format!("SYNC counter {c}"),
                _ => format!("SYNC with {} bytes (malformed)", d.len()),
            };
        }
        if let Some((name, entries)) = self.pdos.get(&id) {
            return format!("{name}: {}", describe_pdo(entries, d));
        }
        let Some((base, node)) = cob::split(id) else {
            return format!("{id:03X}: {}", hex(d));
        };
        match base {
            cob::EMCY => describe_emcy(node, d),
            cob::SDO_RX => format!("SDO request to node {node}: {}", describe_sdo(d, true)),
            cob::SDO_TX => format!("SDO answer from node {node}: {}", describe_sdo(d, false)),
            cob::HEARTBEAT => match d {
                [nmt::STATE_BOOTUP] => format!("boot-up node {node}"),
                [s] => format!("heartbeat node {node}: {}", nmt_state(*s)),
                _ => format!("heartbeat node {node} with {} bytes (malformed)", d.len()),
            },
            b => format!("{} node {node}: {}", pdo_name(b), hex(d)),
        }
    }
}

fn hex(d: &[u8]) -> String {
    d.iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

fn pdo_name(base: u16) -> &'static str {
    match base {
        0x180 => "TPDO1",
        0x280 => "TPDO2",
        0x380 => "TPDO3",
        0x480 => "TPDO4",
        0x200 => "RPDO1",
        0x300 => "RPDO2",
        0x400 => "RPDO3",
        0x500 => "RPDO4",
        _ => "frame",
    }
}

/// The NMT state byte in words.
pub fn nmt_state(s: u8) -> &'static str {
    match s {
        nmt::STATE_BOOTUP => "boot-up",
        nmt::STATE_STOPPED => "stopped",
        nmt::STATE_OPERATIONAL => "operational",
        nmt::STATE_PRE_OPERATIONAL => "pre-operational",
        _ => "unknown state",
    }
}

fn describe_nmt(d: &[u8]) -> String {
    let [cs, node, ..] = d else {
        return format!("NMT with {} bytes (malformed)", d.len());
    };
    let what = match *cs {
        nmt::START => "start",
        nmt::STOP => "stop",
        nmt::ENTER_PRE_OPERATIONAL => "enter pre-operational",
        nmt::RESET_NODE => "reset node",
        nmt::RESET_COMMUNICATION => "reset communication",
        _ => "unknown command",
    };
    let whom = if *node == 0 {
        "all nodes".to_string()
    } else {
        format!("node {node}")
    };
    format!("NMT {what} {whom}")
}

fn describe_emcy(node: u8, d: &[u8]) -> String {
    if d.len() < 3 {
        return format!("EMCY node {node} with {} bytes (malformed)", d.len());
    }
    let code = ErrorCode(u16::from_le_bytes([d[0], d[1]]));
    if code.0 == 0 {
        return format!(
            "EMCY node {node}: error reset, error register {:#04x}",
            d[2]
        );
    }
    format!("EMCY node {node}: {code}, error register {:#04x}", d[2])
}

fn describe_sdo(d: &[u8], request: bool) -> String {
    if d.len() != 8 {
        return format!("{} bytes (malformed: SDO frames have 8)", d.len());
    }
    let object = describe_object(u16::from_le_bytes([d[1], d[2]]), d[3]);
    let value = u32::from_le_bytes([d[4], d[5], d[6], d[7]]);
    let cs = d[0];
    if cs == sdo::ABORT {
        return format!("abort {object}: {}", AbortCode(value));
    }
    let expedited_len = |cs: u8| {
        if cs & 0x01 != 0 {
            4 - usize::from((cs >> 2) & 3)
        } else {
            4
        }
    };
    match (request, cs >> 5) {
        (true, 2) => format!("upload {object}"),
        (true, 1) if cs & sdo::EXPEDITED != 0 => {
            format!("download {object} = {}", hex(&d[4..4 + expedited_len(cs)]))
        }
        (true, 1) => format!("segmented download {object}, {value} bytes"),
        (true, 3) => format!("upload segment (toggle {})", (cs >> 4) & 1),
        (true, 0) => format!(
            "download segment (toggle {}{})",
            (cs >> 4) & 1,
            if cs & 1 != 0 { ", last" } else { "" }
        ),
        (false, 2) if cs & sdo::EXPEDITED != 0 => {
            format!("{object} = {}", hex(&d[4..4 + expedited_len(cs)]))
        }
        (false, 2) => format!("{object}: segmented upload of {value} bytes"),
        (false, 3) => format!("download of {object} done"),
        (false, 1) => format!("download segment acknowledged (toggle {})", (cs >> 4) & 1),
        (false, 0) => {
            let n = 7 - usize::from((cs >> 1) & 7);
            format!(
                "upload segment {:?}{}",
                String::from_utf8_lossy(&d[1..1 + n]),
                if cs & 1 != 0 { " (last)" } else { "" }
            )
        }
        _ => format!("command specifier {cs:#04x} (not SDO)"),
    }
}

fn describe_pdo(entries: &[Entry], d: &[u8]) -> String {
    let mapped: usize = entries.iter().map(|e| usize::from(e.2 / 8)).sum();
    if mapped != d.len() {
        return format!(
            "{} bytes where the mapping has {mapped}: {}",
            d.len(),
            hex(d)
        );
    }
    let mut at = 0usize;
    let mut parts = Vec::new();
    for &(index, sub, bits) in entries {
        let n = usize::from(bits / 8);
        if n == 0 || at + n > d.len() || n > 4 {
            parts.push(format!("{} missing", describe_object(index, sub)));
            break;
        }
        let mut b = [0u8; 4];
        b[..n].copy_from_slice(&d[at..at + n]);
        let raw = u32::from_le_bytes(b);
        let signed = match n {
            1 => i64::from(raw as u8 as i8),
            2 => i64::from(raw as u16 as i16),
            _ => i64::from(raw as i32),
        };
        let name = describe_object(index, sub);
        parts.push(match index {
            obj::STATUSWORD => {
                let s = PowerState::from_statusword(raw as u16)
                    .map_or("undefined state", PowerState::name);
                format!("{name} {:#06x} ({s})", raw)
            }
            obj::CONTROLWORD | obj::ERROR_CODE => format!("{name} {:#06x}", raw),
            _ => format!("{name} {signed}"),
        });
        at += n;
    }
    if at < d.len() {
        parts.push(format!("{} extra bytes", d.len() - at));
    }
    parts.join(", ")
}

fn describe_error(f: &Frame) -> String {
    let c = f.id;
    let mut parts = Vec::new();
    for (bit, name) in [
        (err::TX_TIMEOUT, "TX timeout"),
        (err::LOSTARB, "lost arbitration"),
        (err::PROT, "protocol violation"),
        (err::TRX, "transceiver"),
        (err::ACK, "no acknowledge"),
        (err::BUSOFF, "bus off"),
        (err::BUSERROR, "bus error"),
        (err::RESTARTED, "controller restarted"),
    ] {
        if c & bit != 0 {
            parts.push(name.to_string());
        }
    }
    if c & err::CRTL != 0 {
        let b = f.data[1];
        let mut what = Vec::new();
        for (bit, name) in [
            (err::CRTL_RX_OVERFLOW, "RX overflow"),
            (err::CRTL_TX_OVERFLOW, "TX overflow"),
            (err::CRTL_RX_WARNING, "RX warning"),
            (err::CRTL_TX_WARNING, "TX warning"),
            (err::CRTL_RX_PASSIVE, "RX error passive"),
            (err::CRTL_TX_PASSIVE, "TX error passive"),
            (err::CRTL_ACTIVE, "back to error active"),
        ] {
            if b & bit != 0 {
                what.push(name);
            }
        }
        parts.push(format!("controller: {}", what.join(", ")));
    }
    if c & err::CNT != 0 {
        parts.push(format!("error counters TX {} RX {}", f.data[6], f.data[7]));
    }
    format!("error frame: {}", parts.join("; "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_in_words() {
        let d = Decoder::canservo(&[1], true);
        let cases = [
            (Frame::new(0x000, &[0x01, 0]), "NMT start all nodes"),
            (Frame::new(0x080, &[]), "SYNC"),
            (
                Frame::new(0x181, &[0x37, 0x02, 0xD2, 0x04, 0, 0, 8]),
                "TPDO1 node 1: 0x6041:00 (statusword) 0x0237 (operation enabled), \
                 0x6064:00 (position actual value) 1234, 0x6061:00 (modes of operation display) 8",
            ),
            (Frame::new(0x181, &[0x37]), "TPDO1 node 1: 1 bytes where the mapping has 7: 37"),
            (
                Frame::new(0x082, &[0x10, 0x23, 0x03, 0, 0, 0, 0, 0]),
                "EMCY node 2: 0x2310 (continuous over-current), error register 0x03",
            ),
            (Frame::new(0x602, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]), "SDO request to node 2: upload 0x1000:00 (device type)"),
            (
                Frame::new(0x582, &[0x80, 0x00, 0x20, 0, 0, 0, 2, 6]),
                "SDO answer from node 2: abort 0x2000:00: 0x06020000 (object does not exist in the object dictionary)",
            ),
            (Frame::new(0x702, &[0x05]), "heartbeat node 2: operational"),
            (Frame::new(0x702, &[0x00]), "boot-up node 2"),
            (Frame::new(0x282, &[1, 2]), "TPDO2 node 2: 01 02"),
            (Frame::error(err::BUSOFF, [0; 8]), "error frame: bus off"),
        ];
        for (f, want) in cases {
            assert_eq!(d.describe(&f), want);
        }
    }
}
