//! [`SdoClient`]: reads and writes a node's objects by SDO (hardware.md
//! §6.5): expedited and segmented, both directions, toggle checked,
//! every wait bounded. It blocks while it waits, so it runs at start-up,
//! in the diagnostics helper and in the bring-up tool, never in a
//! realtime function.
//!
//! Hostile or broken servers cannot hold it: each answer has a time-out,
//! an upload longer than [`SdoClient::max_upload`] is aborted with "out
//! of memory", a wrong toggle with "toggle bit not alternated", and an
//! answer that is not the protocol with "command specifier not valid";
//! each time the server is told with an abort frame.

use std::time::{Duration, Instant};

use crate::bus::CanBus;
use crate::codes::AbortCode;
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::regs::{cob, describe_object, sdo};

/// Largest upload accepted by default (bytes).
pub const DEFAULT_MAX_UPLOAD: usize = 4096;

/// An SDO client for one node over one bus endpoint.
pub struct SdoClient<'a> {
    bus: &'a dyn CanBus,
    node: u8,
    timeout: Duration,
    max_upload: usize,
}

impl std::fmt::Debug for SdoClient<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SdoClient")
            .field("bus", &self.bus.describe())
            .field("node", &self.node)
            .field("timeout", &self.timeout)
            .finish()
    }
}

/// Which transfer, for messages.
#[derive(Clone, Copy)]
enum Dir {
    Upload,
    Download,
}

impl<'a> SdoClient<'a> {
    /// A client for `node` (1..=127) on `bus`, waiting up to `timeout`
    /// for each answer.
    pub fn new(bus: &'a dyn CanBus, node: u8, timeout: Duration) -> SdoClient<'a> {
        SdoClient {
            bus,
            node,
            timeout,
            max_upload: DEFAULT_MAX_UPLOAD,
        }
    }

    /// The same with a different upload limit.
    pub fn max_upload(mut self, bytes: usize) -> SdoClient<'a> {
        self.max_upload = bytes;
        self
    }

    /// The node.
    pub fn node(&self) -> u8 {
        self.node
    }

    fn what(dir: Dir, index: u16, sub: u8) -> String {
        let d = match dir {
            Dir::Upload => "upload of",
            Dir::Download => "download to",
        };
        format!("{d} {}", describe_object(index, sub))
    }

    fn request(&self, index: u16, sub: u8, first: u8, payload: [u8; 4]) -> [u8; 8] {
        let i = index.to_le_bytes();
        [
            first, i[0], i[1], sub, payload[0], payload[1], payload[2], payload[3],
        ]
    }

    fn send(&self, data: [u8; 8], dir: Dir, index: u16, sub: u8) -> Result<()> {
        let frame = Frame::new(cob::SDO_RX + u16::from(self.node), &data);
        if self.bus.send(&frame) {
            Ok(())
        } else {
            Err(Error::SendFailed {
                what: format!(
                    "the SDO {} of node {}",
                    Self::what(dir, index, sub),
                    self.node
                ),
                bus: self.bus.describe(),
            })
        }
    }

    /// Tells the server the transfer is over (best effort).
    fn abort(&self, index: u16, sub: u8, code: AbortCode) {
        let data = self.request(index, sub, sdo::ABORT, code.0.to_le_bytes());
        let _ = self
            .bus
            .send(&Frame::new(cob::SDO_RX + u16::from(self.node), &data));
    }

    /// The next answer from the node's SDO server; other frames are
    /// skipped.
    fn answer(&self, dir: Dir, index: u16, sub: u8) -> Result<[u8; 8]> {
        let want = cob::SDO_TX + u16::from(self.node);
        let end = Instant::now() + self.timeout;
        loop {
            let left = end.saturating_duration_since(Instant::now());
            if left.is_zero() {
                self.abort(index, sub, AbortCode::TIMEOUT);
                return Err(Error::SdoTimeout {
                    node: self.node,
                    what: Self::what(dir, index, sub),
                    timeout_ms: self.timeout.as_millis() as u64,
                });
            }
            let Some(f) = self.bus.recv_timeout(left) else {
                continue;
            };
            if f.cob_id() != Some(want) {
                continue;
            }
            if f.len != 8 {
                return Err(self.protocol(
                    dir,
                    index,
                    sub,
                    format!("answer of {} bytes (SDO frames have 8)", f.len),
                ));
            }
            if f.data[0] == sdo::ABORT {
                let code = AbortCode(u32::from_le_bytes([
                    f.data[4], f.data[5], f.data[6], f.data[7],
                ]));
                return Err(Error::SdoAbort {
                    node: self.node,
                    what: Self::what(dir, index, sub),
                    code,
                });
            }
            return Ok(f.data);
        }
    }

    fn protocol(&self, dir: Dir, index: u16, sub: u8, reason: String) -> Error {
        Error::SdoProtocol {
            node: self.node,
            what: Self::what(dir, index, sub),
            reason,
        }
    }

    /// Aborts with `code` and returns the protocol error `reason`.
    fn fail(&self, dir: Dir, index: u16, sub: u8, code: AbortCode, reason: String) -> Error {
        self.abort(index, sub, code);
        self.protocol(dir, index, sub, reason)
    }

    fn check_mux(&self, a: &[u8; 8], dir: Dir, index: u16, sub: u8) -> Result<()> {
        let (i, s) = (u16::from_le_bytes([a[1], a[2]]), a[3]);
        if (i, s) != (index, sub) {
            return Err(self.fail(
                dir,
                index,
                sub,
                AbortCode::GENERAL,
                format!("the answer is for {}", describe_object(i, s)),
            ));
        }
        Ok(())
    }

    /// Reads object `index:sub`.
    pub fn upload(&self, index: u16, sub: u8) -> Result<Vec<u8>> {
        let d = Dir::Upload;
        self.send(
            self.request(index, sub, sdo::UPLOAD_INITIATE, [0; 4]),
            d,
            index,
            sub,
        )?;
        let a = self.answer(d, index, sub)?;
        if a[0] & sdo::CS_MASK != sdo::UPLOAD_INITIATE {
            return Err(self.fail(
                d,
                index,
                sub,
                AbortCode::BAD_COMMAND,
                format!(
                    "command specifier {:#04x} where an upload response belongs",
                    a[0]
                ),
            ));
        }
        self.check_mux(&a, d, index, sub)?;
        if a[0] & sdo::EXPEDITED != 0 {
            let n = if a[0] & sdo::SIZE_INDICATED != 0 {
                4 - usize::from((a[0] >> 2) & 3)
            } else {
                4
            };
            return Ok(a[4..4 + n].to_vec());
        }
        let size = (a[0] & sdo::SIZE_INDICATED != 0)
            .then(|| u32::from_le_bytes([a[4], a[5], a[6], a[7]]) as usize);
        if size.is_some_and(|s| s > self.max_upload) {
            return Err(self.fail(
                d,
                index,
                sub,
                AbortCode::OUT_OF_MEMORY,
                format!(
                    "{} bytes announced, more than the {} accepted",
                    size.unwrap_or(0),
                    self.max_upload
                ),
            ));
        }
        let mut buf = Vec::with_capacity(size.unwrap_or(64));
        let mut toggle = 0u8;
        loop {
            self.send(
                self.request(index, sub, sdo::UPLOAD_SEGMENT | toggle, [0; 4]),
                d,
                index,
                sub,
            )?;
            let s = self.answer(d, index, sub)?;
            if s[0] & sdo::CS_MASK != 0 {
                return Err(self.fail(
                    d,
                    index,
                    sub,
                    AbortCode::BAD_COMMAND,
                    format!(
                        "command specifier {:#04x} where an upload segment belongs",
                        s[0]
                    ),
                ));
            }
            if s[0] & sdo::TOGGLE != toggle {
                return Err(self.fail(
                    d,
                    index,
                    sub,
                    AbortCode::TOGGLE,
                    "toggle bit not alternated in an upload segment".into(),
                ));
            }
            let unused = usize::from((s[0] >> 1) & 7);
            buf.extend_from_slice(&s[1..8 - unused]);
            if buf.len() > size.unwrap_or(self.max_upload).min(self.max_upload) {
                return Err(self.fail(
                    d,
                    index,
                    sub,
                    AbortCode::OUT_OF_MEMORY,
                    format!(
                        "the segments run past {} bytes",
                        size.unwrap_or(self.max_upload)
                    ),
                ));
            }
            if s[0] & sdo::LAST != 0 {
                break;
            }
            toggle ^= sdo::TOGGLE;
        }
        if let Some(size) = size {
            if buf.len() != size {
                return Err(self.protocol(
                    d,
                    index,
                    sub,
                    format!("{} bytes announced, {} sent", size, buf.len()),
                ));
            }
        }
        Ok(buf)
    }

    /// Writes `data` to object `index:sub`.
    pub fn download(&self, index: u16, sub: u8, data: &[u8]) -> Result<()> {
        let d = Dir::Download;
        if data.len() <= 4 {
            let n = data.len() as u8;
            let mut p = [0u8; 4];
            p[..data.len()].copy_from_slice(data);
            let first =
                sdo::DOWNLOAD_INITIATE | (4 - n) << 2 | sdo::EXPEDITED | sdo::SIZE_INDICATED;
            self.send(self.request(index, sub, first, p), d, index, sub)?;
            return self.download_response(d, index, sub);
        }
        let size = (data.len() as u32).to_le_bytes();
        self.send(
            self.request(
                index,
                sub,
                sdo::DOWNLOAD_INITIATE | sdo::SIZE_INDICATED,
                size,
            ),
            d,
            index,
            sub,
        )?;
        self.download_response(d, index, sub)?;
        let mut toggle = 0u8;
        let mut chunks = data.chunks(7).peekable();
        while let Some(chunk) = chunks.next() {
            let last = chunks.peek().is_none();
            let mut f = [0u8; 8];
            f[0] = toggle | ((7 - chunk.len() as u8) << 1) | u8::from(last);
            f[1..1 + chunk.len()].copy_from_slice(chunk);
            self.send(f, d, index, sub)?;
            let a = self.answer(d, index, sub)?;
            if a[0] & !sdo::TOGGLE != sdo::DOWNLOAD_SEGMENT_RESPONSE {
                return Err(self.fail(
                    d,
                    index,
                    sub,
                    AbortCode::BAD_COMMAND,
                    format!(
                        "command specifier {:#04x} where a segment response belongs",
                        a[0]
                    ),
                ));
            }
            if a[0] & sdo::TOGGLE != toggle {
                return Err(self.fail(
                    d,
                    index,
                    sub,
                    AbortCode::TOGGLE,
                    "toggle bit not alternated in a download segment response".into(),
                ));
            }
            toggle ^= sdo::TOGGLE;
        }
        Ok(())
    }

    fn download_response(&self, d: Dir, index: u16, sub: u8) -> Result<()> {
        let a = self.answer(d, index, sub)?;
        if a[0] != sdo::DOWNLOAD_RESPONSE {
            return Err(self.fail(
                d,
                index,
                sub,
                AbortCode::BAD_COMMAND,
                format!(
                    "command specifier {:#04x} where a download response belongs",
                    a[0]
                ),
            ));
        }
        self.check_mux(&a, d, index, sub)
    }

    fn read_n<const N: usize>(&self, index: u16, sub: u8) -> Result<[u8; N]> {
        let v = self.upload(index, sub)?;
        if v.len() < N {
            return Err(self.protocol(
                Dir::Upload,
                index,
                sub,
                format!("{} bytes where {N} belong", v.len()),
            ));
        }
        let mut a = [0u8; N];
        a.copy_from_slice(&v[..N]);
        Ok(a)
    }

    /// Reads a u8 object.
    pub fn read_u8(&self, index: u16, sub: u8) -> Result<u8> {
        Ok(self.read_n::<1>(index, sub)?[0])
    }
    /// Reads a u16 object.
    pub fn read_u16(&self, index: u16, sub: u8) -> Result<u16> {
        Ok(u16::from_le_bytes(self.read_n(index, sub)?))
    }
    /// Reads a u32 object.
    pub fn read_u32(&self, index: u16, sub: u8) -> Result<u32> {
        Ok(u32::from_le_bytes(self.read_n(index, sub)?))
    }
    /// Reads an s8 object.
    pub fn read_i8(&self, index: u16, sub: u8) -> Result<i8> {
        Ok(self.read_u8(index, sub)? as i8)
    }
    /// Reads an s32 object.
    pub fn read_i32(&self, index: u16, sub: u8) -> Result<i32> {
        Ok(self.read_u32(index, sub)? as i32)
    }
    /// Reads a visible string.
    pub fn read_string(&self, index: u16, sub: u8) -> Result<String> {
        let v = self.upload(index, sub)?;
        let end = v.iter().position(|&b| b == 0).unwrap_or(v.len());
        Ok(String::from_utf8_lossy(&v[..end]).into_owned())
    }
    /// Writes a u8 object.
    pub fn write_u8(&self, index: u16, sub: u8, v: u8) -> Result<()> {
        self.download(index, sub, &[v])
    }
    /// Writes a u16 object.
    pub fn write_u16(&self, index: u16, sub: u8, v: u16) -> Result<()> {
        self.download(index, sub, &v.to_le_bytes())
    }
    /// Writes a u32 object.
    pub fn write_u32(&self, index: u16, sub: u8, v: u32) -> Result<()> {
        self.download(index, sub, &v.to_le_bytes())
    }
    /// Writes an s8 object.
    pub fn write_i8(&self, index: u16, sub: u8, v: i8) -> Result<()> {
        self.download(index, sub, &v.to_le_bytes())
    }
    /// Writes an s16 object.
    pub fn write_i16(&self, index: u16, sub: u8, v: i16) -> Result<()> {
        self.download(index, sub, &v.to_le_bytes())
    }
    /// Writes an s32 object.
    pub fn write_i32(&self, index: u16, sub: u8, v: i32) -> Result<()> {
        self.download(index, sub, &v.to_le_bytes())
    }
}
