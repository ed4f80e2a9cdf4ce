//! [`SdoServer`]: the server side of the SDO protocol, as the simulated
//! drive runs it (hardware.md §6.5, §6.12): expedited and segmented
//! upload and download, toggle checking, abort codes, a size limit and
//! a time-out for transfers a client never finishes. The objects
//! themselves are behind [`ObjectAccess`], so the server knows nothing
//! of the drive.

use crate::codes::AbortCode;
use crate::frame::Frame;
use crate::regs::{cob, sdo};

/// Largest segmented download the server takes (bytes).
pub const MAX_DOWNLOAD: usize = 1024;
/// A transfer idle this long is aborted with "SDO protocol timed out".
pub const TRANSFER_TIMEOUT_NS: u64 = 1_000_000_000;

/// What the server reads and writes.
pub trait ObjectAccess {
    /// The bytes of object `index:sub` (little-endian), or why not.
    fn sdo_read(&mut self, index: u16, sub: u8) -> Result<Vec<u8>, AbortCode>;
    /// Stores `data` in object `index:sub`, or says why not.
    fn sdo_write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), AbortCode>;
    /// Whether `index:sub` exists and may be written, checked before a
    /// segmented download starts.
    fn sdo_check_writable(&mut self, index: u16, sub: u8) -> Result<(), AbortCode>;
}

#[derive(Debug, Default)]
enum Transfer {
    #[default]
    Idle,
    Download {
        index: u16,
        sub: u8,
        size: Option<usize>,
        buf: Vec<u8>,
        toggle: u8,
    },
    Upload {
        index: u16,
        sub: u8,
        data: Vec<u8>,
        pos: usize,
        toggle: u8,
    },
}

/// The SDO server of one node.
#[derive(Debug, Default)]
pub struct SdoServer {
    node: u8,
    transfer: Transfer,
    last_ns: u64,
}

impl SdoServer {
    /// The server of `node`.
    pub fn new(node: u8) -> SdoServer {
        SdoServer {
            node,
            ..SdoServer::default()
        }
    }

    /// Forgets any transfer in progress (NMT reset).
    pub fn reset(&mut self) {
        self.transfer = Transfer::Idle;
    }

    /// Whether a segmented transfer is in progress.
    pub fn busy(&self) -> bool {
        !matches!(self.transfer, Transfer::Idle)
    }

    fn reply(&self, data: [u8; 8]) -> Frame {
        Frame::new(cob::SDO_TX + u16::from(self.node), &data)
    }

    fn abort_frame(&self, index: u16, sub: u8, code: AbortCode) -> Frame {
        let i = index.to_le_bytes();
        let c = code.0.to_le_bytes();
        self.reply([sdo::ABORT, i[0], i[1], sub, c[0], c[1], c[2], c[3]])
    }

    fn abort(&mut self, index: u16, sub: u8, code: AbortCode) -> Option<Frame> {
        self.transfer = Transfer::Idle;
        Some(self.abort_frame(index, sub, code))
    }

    /// Aborts a transfer that has been idle too long; call as time
    /// passes.
    pub fn poll_timeout(&mut self, now_ns: u64) -> Option<Frame> {
        let (index, sub) = match &self.transfer {
            Transfer::Idle => return None,
            Transfer::Download { index, sub, .. } | Transfer::Upload { index, sub, .. } => {
                (*index, *sub)
            }
        };
        if now_ns.saturating_sub(self.last_ns) >= TRANSFER_TIMEOUT_NS {
            return self.abort(index, sub, AbortCode::TIMEOUT);
        }
        None
    }

    /// Handles a request frame from the client; returns the answer, if
    /// the protocol calls for one.
    pub fn handle(
        &mut self,
        req: &Frame,
        objects: &mut impl ObjectAccess,
        now_ns: u64,
    ) -> Option<Frame> {
        self.last_ns = now_ns;
        let d = req.data;
        let (index, sub) = (u16::from_le_bytes([d[1], d[2]]), d[3]);
        if req.len != 8 {
            return self.abort(index, sub, AbortCode::BAD_COMMAND);
        }
        match d[0] >> 5 {
            // Download segment.
            0 => self.download_segment(&d, objects),
            // Download initiate.
            1 => {
                self.transfer = Transfer::Idle;
                if d[0] & sdo::EXPEDITED != 0 {
                    let n = if d[0] & sdo::SIZE_INDICATED != 0 {
                        4 - usize::from((d[0] >> 2) & 3)
                    } else {
                        4
                    };
                    return match objects.sdo_write(index, sub, &d[4..4 + n]) {
                        Ok(()) => {
                            Some(self.reply([sdo::DOWNLOAD_RESPONSE, d[1], d[2], sub, 0, 0, 0, 0]))
                        }
                        Err(code) => self.abort(index, sub, code),
                    };
                }
                let size = (d[0] & sdo::SIZE_INDICATED != 0)
                    .then(|| u32::from_le_bytes([d[4], d[5], d[6], d[7]]) as usize);
                if size.is_some_and(|s| s > MAX_DOWNLOAD) {
                    return self.abort(index, sub, AbortCode::OUT_OF_MEMORY);
                }
                if let Err(code) = objects.sdo_check_writable(index, sub) {
                    return self.abort(index, sub, code);
                }
                self.transfer = Transfer::Download {
                    index,
                    sub,
                    size,
                    buf: Vec::new(),
                    toggle: 0,
                };
                Some(self.reply([sdo::DOWNLOAD_RESPONSE, d[1], d[2], sub, 0, 0, 0, 0]))
            }
            // Upload initiate.
            2 => {
                self.transfer = Transfer::Idle;
                let data = match objects.sdo_read(index, sub) {
                    Ok(v) => v,
                    Err(code) => return self.abort(index, sub, code),
                };
                if data.len() <= 4 {
                    let n = data.len() as u8;
                    let mut f = [
                        0x40 | (4 - n) << 2 | sdo::EXPEDITED | sdo::SIZE_INDICATED,
                        d[1],
                        d[2],
                        sub,
                        0,
                        0,
                        0,
                        0,
                    ];
                    f[4..4 + data.len()].copy_from_slice(&data);
                    return Some(self.reply(f));
                }
                let s = (data.len() as u32).to_le_bytes();
                self.transfer = Transfer::Upload {
                    index,
                    sub,
                    data,
                    pos: 0,
                    toggle: 0,
                };
                Some(self.reply([0x41, d[1], d[2], sub, s[0], s[1], s[2], s[3]]))
            }
            // Upload segment.
            3 => self.upload_segment(d[0]),
            // Abort from the client: no answer.
            4 => {
                self.transfer = Transfer::Idle;
                None
            }
            // Block transfers (5, 6) are optional and not offered; 7 is
            // not a command.
            _ => self.abort(index, sub, AbortCode::BAD_COMMAND),
        }
    }

    fn download_segment(&mut self, d: &[u8; 8], objects: &mut impl ObjectAccess) -> Option<Frame> {
        let Transfer::Download {
            index,
            sub,
            size,
            buf,
            toggle,
        } = &mut self.transfer
        else {
            return self.abort(0, 0, AbortCode::BAD_COMMAND);
        };
        let (index, sub, size) = (*index, *sub, *size);
        if d[0] & sdo::TOGGLE != *toggle {
            return self.abort(index, sub, AbortCode::TOGGLE);
        }
        let unused = usize::from((d[0] >> 1) & 7);
        buf.extend_from_slice(&d[1..8 - unused]);
        let t = *toggle;
        *toggle ^= sdo::TOGGLE;
        if buf.len() > size.unwrap_or(MAX_DOWNLOAD) {
            let code = if size.is_some() {
                AbortCode::LENGTH_HIGH
            } else {
                AbortCode::OUT_OF_MEMORY
            };
            return self.abort(index, sub, code);
        }
        if d[0] & sdo::LAST == 0 {
            return Some(self.reply([sdo::DOWNLOAD_SEGMENT_RESPONSE | t, 0, 0, 0, 0, 0, 0, 0]));
        }
        let data = std::mem::take(buf);
        self.transfer = Transfer::Idle;
        if let Some(s) = size {
            if data.len() < s {
                return self.abort(index, sub, AbortCode::LENGTH_LOW);
            }
        }
        match objects.sdo_write(index, sub, &data) {
            Ok(()) => Some(self.reply([sdo::DOWNLOAD_SEGMENT_RESPONSE | t, 0, 0, 0, 0, 0, 0, 0])),
            Err(code) => self.abort(index, sub, code),
        }
    }

    fn upload_segment(&mut self, cs: u8) -> Option<Frame> {
        let Transfer::Upload {
            index,
            sub,
            data,
            pos,
            toggle,
        } = &mut self.transfer
        else {
            return self.abort(0, 0, AbortCode::BAD_COMMAND);
        };
        let (index, sub) = (*index, *sub);
        if cs & sdo::TOGGLE != *toggle {
            return self.abort(index, sub, AbortCode::TOGGLE);
        }
        let n = (data.len() - *pos).min(7);
        let last = *pos + n == data.len();
        let mut f = [0u8; 8];
        f[0] = *toggle | ((7 - n as u8) << 1) | u8::from(last);
        f[1..1 + n].copy_from_slice(&data[*pos..*pos + n]);
        *pos += n;
        *toggle ^= sdo::TOGGLE;
        if last {
            self.transfer = Transfer::Idle;
        }
        Some(self.reply(f))
    }
}
