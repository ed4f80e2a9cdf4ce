//! The mailbox and CANopen over EtherCAT (CoE): the 6-byte mailbox
//! header, the 2-byte CoE header, SDO requests and responses (expedited,
//! normal and segmented transfers, aborts), emergency messages and the
//! mailbox error reply.
//!
//! Requests and responses share command codes, so a body is parsed in
//! the direction it travels: [`parse_request`] (master → slave, what the
//! simulator reads) and [`parse_response`] (slave → master). Neither
//! panics; every length is checked.

use crate::error::{Error, Result};

pub use hal_cia402::codes::{AbortCode, ErrorCode};

/// The mailbox header.
pub const MAILBOX_HEADER_LEN: usize = 6;
/// The CoE header.
pub const COE_HEADER_LEN: usize = 2;
/// An SDO body's fixed part: command, index, sub-index, 4 data bytes.
pub const SDO_LEN: usize = 8;
/// Bytes of data a segment carries at least (padded).
pub const MIN_SEGMENT: usize = 7;

/// Mailbox types (low nibble of header byte 5).
pub mod mailbox_type {
    /// Mailbox error reply.
    pub const ERR: u8 = 0;
    /// ADS over EtherCAT.
    pub const AOE: u8 = 1;
    /// Ethernet over EtherCAT.
    pub const EOE: u8 = 2;
    /// CANopen over EtherCAT.
    pub const COE: u8 = 3;
    /// File access over EtherCAT.
    pub const FOE: u8 = 4;
    /// Servo profile over EtherCAT.
    pub const SOE: u8 = 5;
    /// Vendor specific.
    pub const VOE: u8 = 15;
}

/// CoE services (high nibble of the CoE header).
pub mod service {
    /// Emergency.
    pub const EMERGENCY: u8 = 1;
    /// SDO request.
    pub const SDO_REQUEST: u8 = 2;
    /// SDO response.
    pub const SDO_RESPONSE: u8 = 3;
    /// SDO information.
    pub const SDO_INFO: u8 = 8;
}

/// Mailbox error details (a type-0 reply).
pub mod mailbox_error {
    /// Syntax of the 6-byte header is wrong.
    pub const SYNTAX: u16 = 1;
    /// The protocol is not supported.
    pub const UNSUPPORTED_PROTOCOL: u16 = 2;
    /// The service in the mailbox protocol is not supported.
    pub const SERVICE_NOT_SUPPORTED: u16 = 4;
    /// The mailbox is too short.
    pub const SIZE_TOO_SHORT: u16 = 6;
    /// The length is inconsistent.
    pub const INVALID_SIZE: u16 = 8;

    /// What a detail code means.
    pub fn meaning(detail: u16) -> &'static str {
        match detail {
            1 => "header syntax error",
            2 => "protocol not supported",
            3 => "invalid channel",
            4 => "service not supported",
            5 => "invalid mailbox header",
            6 => "mailbox data too short",
            7 => "no more memory",
            8 => "inconsistent length",
            _ => "unknown mailbox error",
        }
    }
}

/// The mailbox header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MailboxHeader {
    /// Bytes of data after the header.
    pub length: u16,
    /// Station address of the source (slave → master) or destination.
    pub address: u16,
    /// Channel (0..63).
    pub channel: u8,
    /// Priority (0..3).
    pub priority: u8,
    /// Mailbox type ([`mailbox_type`]).
    pub kind: u8,
    /// Counter 1..7 (0: not used), for repeated-request detection.
    pub counter: u8,
}

impl MailboxHeader {
    /// Reads a header and the data it announces from a mailbox buffer
    /// (which may be longer: a sync manager area is read whole).
    pub fn parse(bytes: &[u8]) -> Result<(MailboxHeader, &[u8])> {
        if bytes.len() < MAILBOX_HEADER_LEN {
            return Err(Error::truncated(
                "mailbox header",
                MAILBOX_HEADER_LEN,
                bytes.len(),
            ));
        }
        let h = MailboxHeader {
            length: u16::from_le_bytes([bytes[0], bytes[1]]),
            address: u16::from_le_bytes([bytes[2], bytes[3]]),
            channel: bytes[4] & 0x3F,
            priority: bytes[4] >> 6,
            kind: bytes[5] & 0x0F,
            counter: (bytes[5] >> 4) & 0x07,
        };
        let end = MAILBOX_HEADER_LEN + usize::from(h.length);
        let data = bytes.get(MAILBOX_HEADER_LEN..end).ok_or_else(|| {
            Error::truncated(
                format!("mailbox of announced length {}", h.length),
                end,
                bytes.len(),
            )
        })?;
        Ok((h, data))
    }

    /// The header's six bytes.
    pub fn to_bytes(&self) -> [u8; MAILBOX_HEADER_LEN] {
        let l = self.length.to_le_bytes();
        let a = self.address.to_le_bytes();
        [
            l[0],
            l[1],
            a[0],
            a[1],
            (self.channel & 0x3F) | (self.priority & 3) << 6,
            (self.kind & 0x0F) | (self.counter & 7) << 4,
        ]
    }
}

/// An SDO request (master → slave).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SdoRequest {
    /// Download (write) initiate: expedited (1..4 bytes in the request)
    /// or normal (size, then as much data as the mailbox holds; the rest
    /// follows in segments).
    Download {
        /// Index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Complete access (all sub-indices from `sub`).
        complete: bool,
        /// The whole size, when indicated.
        size: Option<u32>,
        /// Data in this request.
        data: Vec<u8>,
    },
    /// Download segment.
    DownloadSegment {
        /// Toggle bit.
        toggle: bool,
        /// Last segment.
        last: bool,
        /// The segment's data.
        data: Vec<u8>,
    },
    /// Upload (read) initiate.
    Upload {
        /// Index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Complete access.
        complete: bool,
    },
    /// Upload segment request.
    UploadSegment {
        /// Toggle bit.
        toggle: bool,
    },
    /// The master aborts the transfer.
    Abort {
        /// Index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Why.
        code: AbortCode,
    },
}

/// An SDO response (slave → master).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SdoResponse {
    /// Download initiate acknowledged.
    DownloadAck {
        /// Index.
        index: u16,
        /// Sub-index.
        sub: u8,
    },
    /// Download segment acknowledged.
    DownloadSegmentAck {
        /// Toggle bit.
        toggle: bool,
    },
    /// Upload initiate response: expedited (data here, size implied) or
    /// normal (`size` is the whole size; `data` is what fits, the rest
    /// comes by segments).
    Upload {
        /// Index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// The whole size, for a normal transfer.
        size: Option<u32>,
        /// The data in this response.
        data: Vec<u8>,
    },
    /// Upload segment.
    UploadSegment {
        /// Toggle bit.
        toggle: bool,
        /// Last segment.
        last: bool,
        /// The segment's data.
        data: Vec<u8>,
    },
    /// The slave aborts the transfer.
    Abort {
        /// Index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Why.
        code: AbortCode,
    },
}

/// An emergency message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Emergency {
    /// The error code.
    pub code: ErrorCode,
    /// The error register (0x1001).
    pub register: u8,
    /// Manufacturer data.
    pub data: [u8; 5],
}

/// A mailbox message from a slave.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SlaveMessage {
    /// An SDO response.
    Sdo(SdoResponse),
    /// An emergency.
    Emergency(Emergency),
    /// A mailbox error reply (detail, [`mailbox_error`]).
    MailboxError(u16),
    /// A protocol or service this crate does not handle.
    Other {
        /// Mailbox type.
        kind: u8,
        /// CoE service (0 for other protocols).
        service: u8,
    },
}

/// A mailbox message to a slave.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MasterMessage {
    /// An SDO request.
    Sdo(SdoRequest),
    /// A CoE service the simulator does not handle (SDO information,
    /// PDO by mailbox).
    OtherCoe(u8),
    /// Another protocol.
    OtherProtocol(u8),
}

fn coe_header(data: &[u8]) -> Result<(u8, &[u8])> {
    if data.len() < COE_HEADER_LEN {
        return Err(Error::truncated("CoE header", COE_HEADER_LEN, data.len()));
    }
    let h = u16::from_le_bytes([data[0], data[1]]);
    Ok(((h >> 12) as u8, &data[COE_HEADER_LEN..]))
}

fn sdo_fixed(body: &[u8], what: &str) -> Result<(u8, u16, u8, [u8; 4])> {
    if body.len() < SDO_LEN {
        return Err(Error::truncated(what.to_string(), SDO_LEN, body.len()));
    }
    Ok((
        body[0],
        u16::from_le_bytes([body[1], body[2]]),
        body[3],
        [body[4], body[5], body[6], body[7]],
    ))
}

/// Data of an expedited transfer: 4 − n bytes when the size is
/// indicated, else all four.
fn expedited(cmd: u8, data: [u8; 4]) -> Vec<u8> {
    let n = if cmd & 0x01 != 0 {
        usize::from((cmd >> 2) & 3)
    } else {
        0
    };
    data[..4 - n].to_vec()
}

/// Segment data: the segment's bytes less the `n` unused ones (which
/// only count when the data is the 7-byte minimum).
fn segment_data(cmd: u8, rest: &[u8]) -> Vec<u8> {
    let n = usize::from((cmd >> 1) & 7);
    if rest.len() <= MIN_SEGMENT {
        rest[..rest.len().saturating_sub(n)].to_vec()
    } else {
        rest.to_vec()
    }
}

/// Parses a mailbox a master wrote (what a slave reads).
pub fn parse_request(mailbox: &[u8]) -> Result<(MailboxHeader, MasterMessage)> {
    let (h, data) = MailboxHeader::parse(mailbox)?;
    if h.kind != mailbox_type::COE {
        return Ok((h, MasterMessage::OtherProtocol(h.kind)));
    }
    let (svc, body) = coe_header(data)?;
    if svc != service::SDO_REQUEST {
        return Ok((h, MasterMessage::OtherCoe(svc)));
    }
    if body.is_empty() {
        return Err(Error::truncated("SDO request", 1, 0));
    }
    let cmd = body[0];
    let complete = cmd & 0x10 != 0;
    let req = match cmd >> 5 {
        // Download segment.
        0 => SdoRequest::DownloadSegment {
            toggle: cmd & 0x10 != 0,
            last: cmd & 0x01 != 0,
            data: segment_data(cmd, &body[1..]),
        },
        1 => {
            let (_, index, sub, d) = sdo_fixed(body, "SDO download request")?;
            if cmd & 0x02 != 0 {
                SdoRequest::Download {
                    index,
                    sub,
                    complete,
                    size: None,
                    data: expedited(cmd, d),
                }
            } else {
                let size = u32::from_le_bytes(d);
                SdoRequest::Download {
                    index,
                    sub,
                    complete,
                    size: Some(size),
                    data: body[SDO_LEN..].to_vec(),
                }
            }
        }
        2 => {
            let (_, index, sub, _) = sdo_fixed(body, "SDO upload request")?;
            SdoRequest::Upload {
                index,
                sub,
                complete,
            }
        }
        3 => SdoRequest::UploadSegment {
            toggle: cmd & 0x10 != 0,
        },
        4 => {
            let (_, index, sub, d) = sdo_fixed(body, "SDO abort")?;
            SdoRequest::Abort {
                index,
                sub,
                code: AbortCode(u32::from_le_bytes(d)),
            }
        }
        c => {
            return Err(Error::malformed(
                "SDO request",
                format!("command specifier {c} (byte {cmd:#04x}) is not a client command"),
            ))
        }
    };
    Ok((h, MasterMessage::Sdo(req)))
}

/// Parses a mailbox a slave wrote (what a master reads).
pub fn parse_response(mailbox: &[u8]) -> Result<(MailboxHeader, SlaveMessage)> {
    let (h, data) = MailboxHeader::parse(mailbox)?;
    match h.kind {
        mailbox_type::ERR => {
            if data.len() < 4 {
                return Err(Error::truncated("mailbox error reply", 4, data.len()));
            }
            let detail = u16::from_le_bytes([data[2], data[3]]);
            return Ok((h, SlaveMessage::MailboxError(detail)));
        }
        mailbox_type::COE => {}
        kind => return Ok((h, SlaveMessage::Other { kind, service: 0 })),
    }
    let (svc, body) = coe_header(data)?;
    let msg = match svc {
        service::EMERGENCY => {
            if body.len() < 8 {
                return Err(Error::truncated("CoE emergency", 8, body.len()));
            }
            let mut d = [0; 5];
            d.copy_from_slice(&body[3..8]);
            SlaveMessage::Emergency(Emergency {
                code: ErrorCode(u16::from_le_bytes([body[0], body[1]])),
                register: body[2],
                data: d,
            })
        }
        service::SDO_RESPONSE => SlaveMessage::Sdo(parse_sdo_response(body)?),
        // A slave aborts a transfer with service 2; a slave that (wrongly)
        // sends it as a response is read the same way above.
        service::SDO_REQUEST if is_abort(body) => SlaveMessage::Sdo(parse_sdo_response(body)?),
        service => SlaveMessage::Other {
            kind: h.kind,
            service,
        },
    };
    Ok((h, msg))
}

fn parse_sdo_response(body: &[u8]) -> Result<SdoResponse> {
    if body.is_empty() {
        return Err(Error::truncated("SDO response", 1, 0));
    }
    let cmd = body[0];
    Ok(match cmd >> 5 {
        0 => SdoResponse::UploadSegment {
            toggle: cmd & 0x10 != 0,
            last: cmd & 0x01 != 0,
            data: segment_data(cmd, &body[1..]),
        },
        1 => SdoResponse::DownloadSegmentAck {
            toggle: cmd & 0x10 != 0,
        },
        2 => {
            let (_, index, sub, d) = sdo_fixed(body, "SDO upload response")?;
            if cmd & 0x02 != 0 {
                SdoResponse::Upload {
                    index,
                    sub,
                    size: None,
                    data: expedited(cmd, d),
                }
            } else {
                SdoResponse::Upload {
                    index,
                    sub,
                    size: Some(u32::from_le_bytes(d)),
                    data: body[SDO_LEN..].to_vec(),
                }
            }
        }
        3 => {
            let (_, index, sub, _) = sdo_fixed(body, "SDO download response")?;
            SdoResponse::DownloadAck { index, sub }
        }
        4 => {
            let (_, index, sub, d) = sdo_fixed(body, "SDO abort")?;
            SdoResponse::Abort {
                index,
                sub,
                code: AbortCode(u32::from_le_bytes(d)),
            }
        }
        c => {
            return Err(Error::malformed(
                "SDO response",
                format!("command specifier {c} (byte {cmd:#04x}) is not a server command"),
            ))
        }
    })
}

fn mailbox(address: u16, counter: u8, kind: u8, body: &[u8]) -> Vec<u8> {
    let h = MailboxHeader {
        length: body.len() as u16,
        address,
        channel: 0,
        priority: 0,
        kind,
        counter,
    };
    let mut out = h.to_bytes().to_vec();
    out.extend_from_slice(body);
    out
}

fn coe(svc: u8, sdo: &[u8]) -> Vec<u8> {
    let mut out = (u16::from(svc) << 12).to_le_bytes().to_vec();
    out.extend_from_slice(sdo);
    out
}

fn fixed(cmd: u8, index: u16, sub: u8, data: [u8; 4]) -> [u8; SDO_LEN] {
    let i = index.to_le_bytes();
    [cmd, i[0], i[1], sub, data[0], data[1], data[2], data[3]]
}

fn padded(cmd: u8, data: &[u8]) -> Vec<u8> {
    let mut out = vec![cmd];
    out.extend_from_slice(data);
    while out.len() < 1 + MIN_SEGMENT {
        out.push(0);
    }
    out
}

/// Writes an SDO request as a mailbox (address 0: the master).
pub fn encode_request(req: &SdoRequest, counter: u8) -> Vec<u8> {
    let body: Vec<u8> = match req {
        SdoRequest::Download {
            index,
            sub,
            complete,
            size,
            data,
        } => {
            let ca = if *complete { 0x10 } else { 0 };
            match size {
                None if data.len() <= 4 => {
                    let mut d = [0; 4];
                    d[..data.len()].copy_from_slice(data);
                    let n = (4 - data.len() as u8) << 2;
                    fixed(0x23 | n | ca, *index, *sub, d).to_vec()
                }
                _ => {
                    let total = size.unwrap_or(data.len() as u32);
                    let mut b = fixed(0x21 | ca, *index, *sub, total.to_le_bytes()).to_vec();
                    b.extend_from_slice(data);
                    b
                }
            }
        }
        SdoRequest::DownloadSegment { toggle, last, data } => {
            let n = MIN_SEGMENT.saturating_sub(data.len()) as u8;
            padded(u8::from(*toggle) << 4 | n << 1 | u8::from(*last), data)
        }
        SdoRequest::Upload {
            index,
            sub,
            complete,
        } => fixed(
            0x40 | if *complete { 0x10 } else { 0 },
            *index,
            *sub,
            [0; 4],
        )
        .to_vec(),
        SdoRequest::UploadSegment { toggle } => padded(0x60 | u8::from(*toggle) << 4, &[]),
        SdoRequest::Abort { index, sub, code } => {
            fixed(0x80, *index, *sub, code.0.to_le_bytes()).to_vec()
        }
    };
    mailbox(
        0,
        counter,
        mailbox_type::COE,
        &coe(service::SDO_REQUEST, &body),
    )
}

/// Writes an SDO response as a mailbox from station `address`.
pub fn encode_response(resp: &SdoResponse, address: u16, counter: u8) -> Vec<u8> {
    let body: Vec<u8> = match resp {
        SdoResponse::DownloadAck { index, sub } => fixed(0x60, *index, *sub, [0; 4]).to_vec(),
        SdoResponse::DownloadSegmentAck { toggle } => padded(0x20 | u8::from(*toggle) << 4, &[]),
        SdoResponse::Upload {
            index,
            sub,
            size,
            data,
        } => match size {
            None if data.len() <= 4 => {
                let mut d = [0; 4];
                d[..data.len()].copy_from_slice(data);
                let n = (4 - data.len() as u8) << 2;
                fixed(0x43 | n, *index, *sub, d).to_vec()
            }
            _ => {
                let total = size.unwrap_or(data.len() as u32);
                let mut b = fixed(0x41, *index, *sub, total.to_le_bytes()).to_vec();
                b.extend_from_slice(data);
                b
            }
        },
        SdoResponse::UploadSegment { toggle, last, data } => {
            let n = MIN_SEGMENT.saturating_sub(data.len()) as u8;
            padded(u8::from(*toggle) << 4 | n << 1 | u8::from(*last), data)
        }
        SdoResponse::Abort { index, sub, code } => {
            fixed(0x80, *index, *sub, code.0.to_le_bytes()).to_vec()
        }
    };
    mailbox(
        address,
        counter,
        mailbox_type::COE,
        &coe(response_service(resp), &body),
    )
}

/// The CoE service a slave's SDO answer travels under. An abort is an
/// "abort SDO transfer request" (service 2) from either side, as real
/// slaves send it and as SOEM and the IgH master look for it; every
/// other answer is an SDO response (service 3).
fn response_service(resp: &SdoResponse) -> u8 {
    match resp {
        SdoResponse::Abort { .. } => service::SDO_REQUEST,
        _ => service::SDO_RESPONSE,
    }
}

/// Whether an SDO body is an abort transfer (command specifier 4).
fn is_abort(body: &[u8]) -> bool {
    body.first().is_some_and(|cmd| cmd >> 5 == 4)
}

/// Writes an emergency as a mailbox from station `address`.
pub fn encode_emergency(e: &Emergency, address: u16, counter: u8) -> Vec<u8> {
    let c = e.code.0.to_le_bytes();
    let mut body = vec![c[0], c[1], e.register];
    body.extend_from_slice(&e.data);
    mailbox(
        address,
        counter,
        mailbox_type::COE,
        &coe(service::EMERGENCY, &body),
    )
}

/// Writes a mailbox error reply from station `address`.
pub fn encode_mailbox_error(detail: u16, address: u16) -> Vec<u8> {
    let mut body = 1u16.to_le_bytes().to_vec();
    body.extend_from_slice(&detail.to_le_bytes());
    mailbox(address, 0, mailbox_type::ERR, &body)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn req_round_trip(r: SdoRequest) {
        let bytes = encode_request(&r, 3);
        let (h, m) = parse_request(&bytes).unwrap();
        assert_eq!(h.counter, 3);
        assert_eq!(m, MasterMessage::Sdo(r));
    }

    fn resp_round_trip(r: SdoResponse) {
        let bytes = encode_response(&r, 0x1001, 5);
        let (h, m) = parse_response(&bytes).unwrap();
        assert_eq!((h.address, h.counter), (0x1001, 5));
        assert_eq!(m, SlaveMessage::Sdo(r));
    }

    #[test]
    fn sdo_messages_round_trip() {
        req_round_trip(SdoRequest::Download {
            index: 0x6060,
            sub: 0,
            complete: false,
            size: None,
            data: vec![8],
        });
        req_round_trip(SdoRequest::Download {
            index: 0x1C12,
            sub: 0,
            complete: true,
            size: Some(6),
            data: vec![1, 0, 0, 0x16, 0, 0],
        });
        req_round_trip(SdoRequest::DownloadSegment {
            toggle: true,
            last: true,
            data: vec![1, 2, 3],
        });
        req_round_trip(SdoRequest::Upload {
            index: 0x1018,
            sub: 1,
            complete: false,
        });
        req_round_trip(SdoRequest::UploadSegment { toggle: false });
        resp_round_trip(SdoResponse::Upload {
            index: 0x1018,
            sub: 1,
            size: None,
            data: vec![2, 0, 0, 0],
        });
        resp_round_trip(SdoResponse::Upload {
            index: 0x1008,
            sub: 0,
            size: Some(20),
            data: b"simulated".to_vec(),
        });
        resp_round_trip(SdoResponse::UploadSegment {
            toggle: true,
            last: true,
            data: b"drive".to_vec(),
        });
        resp_round_trip(SdoResponse::DownloadAck {
            index: 0x6060,
            sub: 0,
        });
        resp_round_trip(SdoResponse::DownloadSegmentAck { toggle: true });
        resp_round_trip(SdoResponse::Abort {
            index: 0x2000,
            sub: 0,
            code: AbortCode::NO_OBJECT,
        });
    }

    #[test]
    fn a_slave_aborts_under_the_sdo_request_service_and_either_service_is_read() {
        let abort = SdoResponse::Abort {
            index: 0x5555,
            sub: 0,
            code: AbortCode::NO_OBJECT,
        };
        let bytes = encode_response(&abort, 0x1001, 1);
        // Mailbox header (6 bytes), then the CoE header: service in its
        // high nibble.
        assert_eq!(bytes[7] >> 4, service::SDO_REQUEST);
        assert_eq!(bytes[8], 0x80);
        assert_eq!(
            parse_response(&bytes).unwrap().1,
            SlaveMessage::Sdo(abort.clone())
        );
        let mut as_response = bytes.clone();
        as_response[7] = (as_response[7] & 0x0F) | service::SDO_RESPONSE << 4;
        assert_eq!(
            parse_response(&as_response).unwrap().1,
            SlaveMessage::Sdo(abort)
        );
        // Any other request-service body from a slave is not an answer.
        let mut upload = as_response;
        upload[7] = (upload[7] & 0x0F) | service::SDO_REQUEST << 4;
        upload[8] = 0x40;
        assert!(matches!(
            parse_response(&upload).unwrap().1,
            SlaveMessage::Other {
                service: service::SDO_REQUEST,
                ..
            }
        ));
    }

    #[test]
    fn emergency_and_mailbox_error() {
        let e = Emergency {
            code: ErrorCode(0x2310),
            register: 0x03,
            data: [1, 2, 3, 4, 5],
        };
        let (_, m) = parse_response(&encode_emergency(&e, 0x1002, 1)).unwrap();
        assert_eq!(m, SlaveMessage::Emergency(e));
        let (_, m) = parse_response(&encode_mailbox_error(
            mailbox_error::SERVICE_NOT_SUPPORTED,
            1,
        ))
        .unwrap();
        assert_eq!(m, SlaveMessage::MailboxError(4));
    }

    #[test]
    fn short_and_bad_mailboxes_are_errors() {
        assert!(parse_response(&[1, 2]).is_err());
        // Announced length past the buffer.
        assert!(parse_response(&[20, 0, 0, 0, 0, 3, 0, 0x30]).is_err());
        // An SDO response with a client command specifier.
        let mut b = encode_response(&SdoResponse::DownloadAck { index: 1, sub: 0 }, 0, 0);
        b[8] = 0xE0;
        assert!(parse_response(&b).is_err());
        // Trailing bytes past the announced length are ignored.
        let mut b = encode_request(&SdoRequest::UploadSegment { toggle: true }, 0);
        b.extend_from_slice(&[0xAA; 10]);
        assert!(parse_request(&b).is_ok());
    }
}
