//! The master's SDO client over a slave's mailbox (CoE): expedited,
//! normal and segmented transfers both ways, complete access, aborts with
//! their meanings. EtherCrab 0.7 writes SDOs of at most 4 bytes; this
//! client writes any length (an lcec `<sdoConfig>` with a long
//! `sdoDataRaw`, `ethercat-tool download` of a string) and reads any
//! length. It talks to the mailbox sync managers with register datagrams
//! through EtherCrab's `MainDevice`, and parses the slave's replies with
//! [`crate::wire::coe`]; an emergency that arrives meanwhile is kept for
//! the caller ([`SdoClient::take_emergencies`]).
//!
//! [`Transfer`] is the protocol without the wire (what to send next,
//! what a reply means), so the fuzz target can feed it hostile replies.

use std::time::{Duration, Instant};

use ethercrab::{Command, MainDevice};

use crate::error::{Error, Result};
use crate::regs::{self, sm};
use crate::wire::coe::{
    self, AbortCode, Emergency, SdoRequest, SdoResponse, SlaveMessage, COE_HEADER_LEN,
    MAILBOX_HEADER_LEN, MIN_SEGMENT, SDO_LEN,
};

/// Bytes an upload may bring at most (a misbehaving slave cannot make
/// the master allocate without bound).
pub const MAX_UPLOAD: usize = 1 << 20;

/// How long one reply may take.
pub const REPLY_TIMEOUT: Duration = Duration::from_millis(1000);

/// Where one slave's mailboxes are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mailboxes {
    /// The slave's station address.
    pub station: u16,
    /// Master → slave mailbox: start and length (SM0).
    pub write: (u16, u16),
    /// Slave → master mailbox: start and length (SM1).
    pub read: (u16, u16),
}

/// The next step of a transfer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Step {
    /// Send this request.
    Send(SdoRequest),
    /// The transfer ended; an upload's data (empty for a download).
    Done(Vec<u8>),
}

/// One SDO transfer as a state machine: [`Transfer::first`], then
/// [`Transfer::on_reply`] with each reply until [`Step::Done`] or an
/// error.
#[derive(Debug, Clone)]
pub struct Transfer {
    index: u16,
    sub: u8,
    complete: bool,
    /// Data still to send (download) or received (upload).
    data: Vec<u8>,
    /// Download: bytes sent so far.
    sent: usize,
    /// Upload: the size the slave announced.
    size: Option<usize>,
    toggle: bool,
    /// Download: segments are under way (the next ack is a segment's).
    segmenting: bool,
    upload: bool,
    /// Data bytes a segment carries at most (from the mailbox size).
    segment_room: usize,
    /// Data bytes a normal initiate request carries at most.
    initiate_room: usize,
}

impl Transfer {
    /// An upload of `index:sub` through a mailbox of `mailbox_len` bytes.
    pub fn upload(index: u16, sub: u8, complete: bool, mailbox_len: usize) -> Transfer {
        Transfer::new(index, sub, complete, Vec::new(), true, mailbox_len)
    }

    /// A download of `data` to `index:sub`.
    pub fn download(
        index: u16,
        sub: u8,
        complete: bool,
        data: Vec<u8>,
        mailbox_len: usize,
    ) -> Transfer {
        Transfer::new(index, sub, complete, data, false, mailbox_len)
    }

    fn new(
        index: u16,
        sub: u8,
        complete: bool,
        data: Vec<u8>,
        upload: bool,
        len: usize,
    ) -> Transfer {
        let overhead = MAILBOX_HEADER_LEN + COE_HEADER_LEN;
        Transfer {
            index,
            sub,
            complete,
            data,
            sent: 0,
            size: None,
            toggle: false,
            segmenting: false,
            upload,
            segment_room: len.saturating_sub(overhead + 1).max(MIN_SEGMENT),
            initiate_room: len.saturating_sub(overhead + SDO_LEN),
        }
    }

    /// What "index:sub" the transfer is for, for messages.
    pub fn what(&self) -> String {
        let dir = if self.upload { "upload" } else { "download" };
        format!("{dir} of {:#06x}:{:02x}", self.index, self.sub)
    }

    /// The first request.
    pub fn first(&mut self) -> SdoRequest {
        if self.upload {
            return SdoRequest::Upload {
                index: self.index,
                sub: self.sub,
                complete: self.complete,
            };
        }
        let n = if self.data.len() <= 4 {
            self.data.len()
        } else {
            self.data.len().min(self.initiate_room)
        };
        self.sent = n;
        SdoRequest::Download {
            index: self.index,
            sub: self.sub,
            complete: self.complete,
            size: Some(u32::try_from(self.data.len()).unwrap_or(u32::MAX)),
            data: self.data[..n].to_vec(),
        }
    }

    fn malformed(&self, reason: impl Into<String>) -> Error {
        Error::malformed(format!("SDO {}", self.what()), reason)
    }

    /// What a reply means: the next request, the end, or an error (an
    /// abort with its code, a reply that does not fit the transfer).
    pub fn on_reply(&mut self, reply: SdoResponse) -> Result<Step> {
        match reply {
            SdoResponse::Abort { code, .. } => Err(Error::SdoAbort {
                slave: String::new(),
                what: self.what(),
                code,
            }),
            r if self.upload => self.upload_reply(r),
            r => self.download_reply(r),
        }
    }

    fn upload_reply(&mut self, r: SdoResponse) -> Result<Step> {
        match (r, self.size) {
            (
                SdoResponse::Upload {
                    index,
                    sub,
                    size,
                    data,
                },
                None,
            ) => {
                if (index, sub) != (self.index, self.sub) {
                    return Err(self.malformed(format!("answer for {index:#06x}:{sub:02x}")));
                }
                let Some(size) = size else {
                    return Ok(Step::Done(data));
                };
                let size = usize::try_from(size).unwrap_or(usize::MAX);
                if size > MAX_UPLOAD {
                    return Err(
                        self.malformed(format!("{size} bytes announced, at most {MAX_UPLOAD}"))
                    );
                }
                self.size = Some(size);
                self.data = data;
                self.data.truncate(size);
                self.after_segment(false)
            }
            (SdoResponse::UploadSegment { toggle, last, data }, Some(size)) => {
                if toggle != self.toggle {
                    return Err(self.malformed("segment with the wrong toggle bit"));
                }
                self.toggle = !self.toggle;
                let room = size - self.data.len();
                self.data.extend_from_slice(&data[..data.len().min(room)]);
                self.after_segment(last)
            }
            (other, _) => Err(self.malformed(format!("unexpected answer {other:?}"))),
        }
    }

    fn after_segment(&mut self, last: bool) -> Result<Step> {
        let size = self.size.unwrap_or(0);
        if self.data.len() >= size || last {
            if self.data.len() < size {
                return Err(self.malformed(format!(
                    "last segment after {} of {size} bytes",
                    self.data.len()
                )));
            }
            return Ok(Step::Done(std::mem::take(&mut self.data)));
        }
        Ok(Step::Send(SdoRequest::UploadSegment {
            toggle: self.toggle,
        }))
    }

    fn download_reply(&mut self, r: SdoResponse) -> Result<Step> {
        match r {
            SdoResponse::DownloadAck { index, sub } if !self.segmenting => {
                if (index, sub) != (self.index, self.sub) {
                    return Err(self.malformed(format!("answer for {index:#06x}:{sub:02x}")));
                }
                self.next_segment()
            }
            SdoResponse::DownloadSegmentAck { toggle } if self.segmenting => {
                if toggle != self.toggle {
                    return Err(self.malformed("acknowledge with the wrong toggle bit"));
                }
                self.next_segment()
            }
            other => Err(self.malformed(format!("unexpected answer {other:?}"))),
        }
    }

    fn next_segment(&mut self) -> Result<Step> {
        if self.sent >= self.data.len() {
            return Ok(Step::Done(Vec::new()));
        }
        let toggle = self.segmenting && !self.toggle;
        self.toggle = toggle;
        self.segmenting = true;
        let n = (self.data.len() - self.sent).min(self.segment_room);
        let data = self.data[self.sent..self.sent + n].to_vec();
        self.sent += n;
        Ok(Step::Send(SdoRequest::DownloadSegment {
            toggle,
            last: self.sent >= self.data.len(),
            data,
        }))
    }
}

/// An SDO client for one slave.
#[derive(Debug)]
pub struct SdoClient<'a> {
    md: &'a MainDevice<'a>,
    mailboxes: Mailboxes,
    counter: u8,
    emergencies: Vec<Emergency>,
    /// How long one reply may take.
    pub timeout: Duration,
}

impl<'a> SdoClient<'a> {
    /// A client for the slave at `station`, its mailboxes read from its
    /// sync manager registers (set up by the bring-up to PRE-OP).
    pub async fn new(md: &'a MainDevice<'a>, station: u16) -> Result<SdoClient<'a>> {
        let regs = Command::fprd(station, regs::SM_BASE)
            .receive_slice(md, 2 * regs::SM_LEN)
            .await
            .map_err(|e| wire_error(station, "reading its sync managers", e))?;
        let w = |at: usize| u16::from_le_bytes([regs[at], regs[at + 1]]);
        let sm1 = usize::from(regs::SM_LEN);
        let mailboxes = Mailboxes {
            station,
            write: (w(0), w(2)),
            read: (w(sm1), w(sm1 + 2)),
        };
        if mailboxes.write.1 < 16 || mailboxes.read.1 < 16 {
            return Err(Error::Master {
                iface: String::new(),
                step: format!("SDO to station {station:#06x}"),
                reason: "the slave has no mailbox (SM0/SM1 not configured): no CoE".into(),
            });
        }
        Ok(SdoClient {
            md,
            mailboxes,
            counter: 0,
            emergencies: Vec::new(),
            timeout: REPLY_TIMEOUT,
        })
    }

    /// The mailboxes used.
    pub fn mailboxes(&self) -> Mailboxes {
        self.mailboxes
    }

    /// Emergencies that arrived during transfers, oldest first.
    pub fn take_emergencies(&mut self) -> Vec<Emergency> {
        std::mem::take(&mut self.emergencies)
    }

    /// Reads `index:sub` (all sub-indices from `sub` with `complete`).
    pub async fn upload(&mut self, index: u16, sub: u8, complete: bool) -> Result<Vec<u8>> {
        let len = usize::from(self.mailboxes.write.1.min(self.mailboxes.read.1));
        self.run(Transfer::upload(index, sub, complete, len)).await
    }

    /// Writes `data` to `index:sub`, in segments if it does not fit.
    pub async fn download(
        &mut self,
        index: u16,
        sub: u8,
        complete: bool,
        data: &[u8],
    ) -> Result<()> {
        let len = usize::from(self.mailboxes.write.1.min(self.mailboxes.read.1));
        self.run(Transfer::download(index, sub, complete, data.to_vec(), len))
            .await
            .map(|_| ())
    }

    async fn run(&mut self, mut t: Transfer) -> Result<Vec<u8>> {
        let mut request = t.first();
        loop {
            let reply = self.exchange(&request, &t).await?;
            match t.on_reply(reply).map_err(|e| self.name_slave(e))? {
                Step::Send(next) => request = next,
                Step::Done(data) => return Ok(data),
            }
        }
    }

    fn name_slave(&self, e: Error) -> Error {
        match e {
            Error::SdoAbort { what, code, .. } => Error::SdoAbort {
                slave: format!("station {:#06x}", self.mailboxes.station),
                what,
                code,
            },
            e => e,
        }
    }

    /// Sends one request and waits for the SDO answer, keeping
    /// emergencies that come first.
    async fn exchange(&mut self, request: &SdoRequest, t: &Transfer) -> Result<SdoResponse> {
        let st = self.mailboxes.station;
        self.counter = self.counter % 7 + 1;
        let mut mailbox = coe::encode_request(request, self.counter);
        let (start, len) = self.mailboxes.write;
        if mailbox.len() > usize::from(len) {
            return Err(t.malformed(format!("request of {} bytes, mailbox {len}", mailbox.len())));
        }
        // The whole area: writing its last byte hands it to the slave.
        mailbox.resize(usize::from(len), 0);
        Command::fpwr(st, start)
            .send(self.md, mailbox.as_slice())
            .await
            .map_err(|e| wire_error(st, "writing its mailbox", e))?;
        let deadline = Instant::now() + self.timeout;
        loop {
            let reply = self.read_mailbox(deadline, t).await?;
            match coe::parse_response(&reply) {
                Ok((_, SlaveMessage::Sdo(r))) => return Ok(r),
                Ok((_, SlaveMessage::Emergency(e))) => {
                    if self.emergencies.len() < 64 {
                        self.emergencies.push(e);
                    }
                }
                Ok((_, SlaveMessage::MailboxError(detail))) => {
                    return Err(t.malformed(format!(
                        "mailbox error {detail}: {}",
                        coe::mailbox_error::meaning(detail)
                    )))
                }
                Ok((_, SlaveMessage::Other { .. })) => {}
                Err(e) => return Err(t.malformed(format!("unreadable answer: {e}"))),
            }
        }
    }

    /// Waits until the slave's mailbox is full and reads it whole.
    async fn read_mailbox(&mut self, deadline: Instant, t: &Transfer) -> Result<Vec<u8>> {
        let st = self.mailboxes.station;
        let status = regs::SM_BASE + regs::SM_LEN + sm::STATUS;
        loop {
            let s: u8 = Command::fprd(st, status)
                .receive(self.md)
                .await
                .map_err(|e| wire_error(st, "reading its mailbox status", e))?;
            if s & sm::STATUS_FULL != 0 {
                break;
            }
            if Instant::now() >= deadline {
                return Err(t.malformed(format!("no answer within {:?}", self.timeout)));
            }
        }
        let (start, len) = self.mailboxes.read;
        let data = Command::fprd(st, start)
            .receive_slice(self.md, len)
            .await
            .map_err(|e| wire_error(st, "reading its mailbox", e))?;
        Ok(data.to_vec())
    }
}

fn wire_error(station: u16, what: &str, e: ethercrab::error::Error) -> Error {
    Error::Master {
        iface: String::new(),
        step: format!("station {station:#06x}: {what}"),
        reason: e.to_string(),
    }
}

/// The fuzz body's part for the client: the bytes cut into replies
/// (2 bytes of length, then the reply) are the answers to an upload and
/// to a long download; each transfer ends in a value or an error within
/// as many steps as replies, and never asks for an upload past
/// [`MAX_UPLOAD`].
#[cfg(any(test, feature = "fuzzing"))]
pub fn fuzz_client(input: &[u8]) {
    let mut replies = Vec::new();
    let mut rest = input;
    while rest.len() >= 2 {
        let n = usize::from(u16::from_le_bytes([rest[0], rest[1]])) % 256;
        let take = n.min(rest.len() - 2);
        replies.push(&rest[2..2 + take]);
        rest = &rest[2 + take..];
    }
    for mut t in [
        Transfer::upload(0x1008, 0, false, 128),
        Transfer::download(0x8000, 1, false, vec![7; 300], 128),
    ] {
        let _ = t.first();
        for r in &replies {
            let Ok((_, SlaveMessage::Sdo(resp))) = coe::parse_response(r) else {
                continue;
            };
            match t.on_reply(resp) {
                Ok(Step::Send(_)) => {}
                Ok(Step::Done(data)) => {
                    assert!(data.len() <= MAX_UPLOAD);
                    break;
                }
                Err(_) => break,
            }
        }
    }
}

/// An abort code's meaning, for callers that print one.
pub fn abort_meaning(code: u32) -> String {
    AbortCode(code).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drive(t: &mut Transfer, replies: Vec<SdoResponse>) -> Result<Vec<Step>> {
        let mut steps = vec![Step::Send(t.first())];
        for r in replies {
            let s = t.on_reply(r)?;
            steps.push(s);
        }
        Ok(steps)
    }

    #[test]
    fn a_long_download_goes_in_segments_with_alternating_toggles() {
        let mut t = Transfer::download(0x8000, 1, false, (0..100).collect(), 32);
        let first = t.first();
        let SdoRequest::Download { size, data, .. } = first else {
            panic!("{first:?}")
        };
        assert_eq!((size, data.len()), (Some(100), 16));
        let s1 = t
            .on_reply(SdoResponse::DownloadAck {
                index: 0x8000,
                sub: 1,
            })
            .unwrap();
        let Step::Send(SdoRequest::DownloadSegment {
            toggle: false,
            last: false,
            data,
        }) = s1
        else {
            panic!("{s1:?}")
        };
        assert_eq!(data.len(), 23);
        let mut toggle = false;
        let mut sent = 16 + 23;
        loop {
            match t
                .on_reply(SdoResponse::DownloadSegmentAck { toggle })
                .unwrap()
            {
                Step::Send(SdoRequest::DownloadSegment {
                    toggle: tg,
                    data,
                    last,
                }) => {
                    assert_eq!(tg, !toggle);
                    toggle = tg;
                    sent += data.len();
                    assert_eq!(last, sent == 100);
                }
                Step::Done(_) => break,
                other => panic!("{other:?}"),
            }
        }
        assert_eq!(sent, 100);
    }

    #[test]
    fn uploads_expedited_and_segmented() {
        let mut t = Transfer::upload(0x1018, 1, false, 128);
        let steps = drive(
            &mut t,
            vec![SdoResponse::Upload {
                index: 0x1018,
                sub: 1,
                size: None,
                data: vec![2, 0, 0, 0],
            }],
        )
        .unwrap();
        assert_eq!(steps[1], Step::Done(vec![2, 0, 0, 0]));
        let mut t = Transfer::upload(0x1008, 0, false, 16);
        let steps = drive(
            &mut t,
            vec![
                SdoResponse::Upload {
                    index: 0x1008,
                    sub: 0,
                    size: Some(10),
                    data: vec![],
                },
                SdoResponse::UploadSegment {
                    toggle: false,
                    last: false,
                    data: b"Sim".to_vec(),
                },
                SdoResponse::UploadSegment {
                    toggle: true,
                    last: true,
                    data: b"Servo..".to_vec(),
                },
            ],
        )
        .unwrap();
        assert_eq!(steps[3], Step::Done(b"SimServo..".to_vec()));
    }

    #[test]
    fn aborts_wrong_toggles_and_short_data_are_errors() {
        let mut t = Transfer::upload(0x1008, 0, false, 16);
        let e = drive(
            &mut t,
            vec![SdoResponse::Abort {
                index: 0x1008,
                sub: 0,
                code: AbortCode(0x0602_0000),
            }],
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("upload of 0x1008:00") && e.contains("0x06020000"),
            "{e}"
        );
        let mut t = Transfer::upload(0x1008, 0, false, 16);
        let e = drive(
            &mut t,
            vec![
                SdoResponse::Upload {
                    index: 0x1008,
                    sub: 0,
                    size: Some(10),
                    data: vec![],
                },
                SdoResponse::UploadSegment {
                    toggle: true,
                    last: false,
                    data: b"x".to_vec(),
                },
            ],
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("toggle"), "{e}");
        let mut t = Transfer::upload(0x1008, 0, false, 16);
        let e = drive(
            &mut t,
            vec![
                SdoResponse::Upload {
                    index: 0x1008,
                    sub: 0,
                    size: Some(10),
                    data: vec![],
                },
                SdoResponse::UploadSegment {
                    toggle: false,
                    last: true,
                    data: b"x".to_vec(),
                },
            ],
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("last segment after 1 of 10"), "{e}");
        let mut t = Transfer::upload(0x1008, 0, false, 16);
        let e = drive(
            &mut t,
            vec![SdoResponse::Upload {
                index: 0x1008,
                sub: 0,
                size: Some(u32::MAX),
                data: vec![],
            }],
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("announced"), "{e}");
        fuzz_client(&[5, 0, 1, 2, 3, 4, 5, 255, 255]);
    }
}
