//! A simulated slave's mailbox: the CoE SDO server (expedited, normal
//! and segmented transfers both ways, complete access, aborts with the
//! dictionary's codes and the protocol's: toggle, unknown command),
//! emergencies queued behind replies, and mailbox error replies for
//! what it does not speak.

use std::collections::VecDeque;

use super::od::Dictionary;
use crate::wire::coe::{
    self, encode_emergency, encode_mailbox_error, encode_response, mailbox_error, AbortCode,
    Emergency, MasterMessage, SdoRequest, SdoResponse, COE_HEADER_LEN, MAILBOX_HEADER_LEN, SDO_LEN,
};

/// Replies waiting at most (older ones are dropped, as a full queue
/// would on a device).
const MAX_QUEUED: usize = 16;

/// A transfer in progress.
#[derive(Debug, Clone)]
enum Transfer {
    /// Uploading `data` from `at`; the next segment has `toggle`.
    Upload {
        data: Vec<u8>,
        at: usize,
        toggle: bool,
    },
    /// Downloading into `index:sub` until `size` bytes are in.
    Download {
        index: u16,
        sub: u8,
        complete: bool,
        size: usize,
        data: Vec<u8>,
        toggle: bool,
    },
}

/// The server.
#[derive(Debug)]
pub struct MailboxServer {
    enabled: bool,
    replies: VecDeque<Vec<u8>>,
    transfer: Option<Transfer>,
    counter: u8,
    /// Bytes of a mailbox (both directions have the same size here).
    size: usize,
}

impl MailboxServer {
    /// A server (`enabled`: the device has a mailbox).
    pub fn new(enabled: bool) -> MailboxServer {
        MailboxServer {
            enabled,
            replies: VecDeque::new(),
            transfer: None,
            counter: 0,
            size: usize::from(super::device::MAILBOX_SIZE),
        }
    }

    /// Forgets transfers and queued replies (INIT).
    pub fn reset(&mut self) {
        self.replies.clear();
        self.transfer = None;
    }

    fn next_counter(&mut self) -> u8 {
        self.counter = self.counter % 7 + 1;
        self.counter
    }

    fn push(&mut self, reply: Vec<u8>) {
        if self.replies.len() >= MAX_QUEUED {
            self.replies.pop_front();
        }
        self.replies.push_back(reply);
    }

    /// Queues an emergency.
    pub fn queue_emergency(&mut self, e: &Emergency, address: u16) {
        if self.enabled {
            let c = self.next_counter();
            self.push(encode_emergency(e, address, c));
        }
    }

    /// The next reply to put into the mailbox, if any.
    pub fn next_reply(&mut self) -> Option<Vec<u8>> {
        self.replies.pop_front()
    }

    /// The master read the mailbox.
    pub fn consumed(&mut self) {}

    /// A request from the master (the whole mailbox area).
    pub fn request(&mut self, mailbox: &[u8], od: &mut Dictionary, preop: bool, address: u16) {
        let reply = match coe::parse_request(mailbox) {
            Err(_) => encode_mailbox_error(mailbox_error::SIZE_TOO_SHORT, address),
            Ok((_, MasterMessage::OtherProtocol(_))) => {
                encode_mailbox_error(mailbox_error::UNSUPPORTED_PROTOCOL, address)
            }
            Ok((_, MasterMessage::OtherCoe(_))) => {
                encode_mailbox_error(mailbox_error::SERVICE_NOT_SUPPORTED, address)
            }
            Ok((_, MasterMessage::Sdo(req))) => {
                let resp = self.sdo(req, od, preop);
                let Some(resp) = resp else { return };
                let c = self.next_counter();
                encode_response(&resp, address, c)
            }
        };
        self.push(reply);
    }

    /// Data bytes an upload initiate response carries at most.
    fn initiate_room(&self) -> usize {
        self.size - MAILBOX_HEADER_LEN - COE_HEADER_LEN - SDO_LEN
    }

    /// Data bytes a segment carries at most.
    fn segment_room(&self) -> usize {
        self.size - MAILBOX_HEADER_LEN - COE_HEADER_LEN - 1
    }

    fn sdo(&mut self, req: SdoRequest, od: &mut Dictionary, preop: bool) -> Option<SdoResponse> {
        let abort = |index, sub, code| Some(SdoResponse::Abort { index, sub, code });
        match req {
            SdoRequest::Upload {
                index,
                sub,
                complete,
            } => {
                self.transfer = None;
                match od.upload(index, sub, complete) {
                    Err(code) => abort(index, sub, code),
                    Ok(data) if data.len() <= 4 && !complete => Some(SdoResponse::Upload {
                        index,
                        sub,
                        size: None,
                        data,
                    }),
                    Ok(data) => {
                        let room = self.initiate_room();
                        let first = data[..data.len().min(room)].to_vec();
                        if data.len() > room {
                            self.transfer = Some(Transfer::Upload {
                                at: room,
                                data: data.clone(),
                                toggle: false,
                            });
                        }
                        Some(SdoResponse::Upload {
                            index,
                            sub,
                            size: Some(data.len() as u32),
                            data: first,
                        })
                    }
                }
            }
            SdoRequest::UploadSegment { toggle } => match self.transfer.take() {
                Some(Transfer::Upload {
                    data,
                    at,
                    toggle: t,
                }) if t == toggle => {
                    let end = (at + self.segment_room()).min(data.len());
                    let last = end == data.len();
                    let seg = data[at..end].to_vec();
                    if !last {
                        self.transfer = Some(Transfer::Upload {
                            data,
                            at: end,
                            toggle: !t,
                        });
                    }
                    Some(SdoResponse::UploadSegment {
                        toggle,
                        last,
                        data: seg,
                    })
                }
                Some(Transfer::Upload { .. }) => abort(0, 0, AbortCode::TOGGLE),
                _ => abort(0, 0, AbortCode::BAD_COMMAND),
            },
            SdoRequest::Download {
                index,
                sub,
                complete,
                size,
                data,
            } => {
                self.transfer = None;
                let total = size.map_or(data.len(), |s| s as usize);
                if total > 65_536 {
                    return abort(index, sub, AbortCode::OUT_OF_MEMORY);
                }
                if data.len() >= total {
                    return Some(
                        match od.download(index, sub, complete, &data[..total], preop) {
                            Ok(()) => SdoResponse::DownloadAck { index, sub },
                            Err(code) => SdoResponse::Abort { index, sub, code },
                        },
                    );
                }
                self.transfer = Some(Transfer::Download {
                    index,
                    sub,
                    complete,
                    size: total,
                    data,
                    toggle: false,
                });
                Some(SdoResponse::DownloadAck { index, sub })
            }
            SdoRequest::DownloadSegment { toggle, last, data } => match self.transfer.take() {
                Some(Transfer::Download {
                    index,
                    sub,
                    complete,
                    size,
                    data: mut got,
                    toggle: t,
                }) => {
                    if t != toggle {
                        return abort(index, sub, AbortCode::TOGGLE);
                    }
                    got.extend_from_slice(&data);
                    if got.len() > size {
                        return abort(index, sub, AbortCode::LENGTH_HIGH);
                    }
                    if last {
                        if got.len() != size {
                            return abort(index, sub, AbortCode::LENGTH_LOW);
                        }
                        if let Err(code) = od.download(index, sub, complete, &got, preop) {
                            return abort(index, sub, code);
                        }
                    } else {
                        self.transfer = Some(Transfer::Download {
                            index,
                            sub,
                            complete,
                            size,
                            data: got,
                            toggle: !t,
                        });
                    }
                    Some(SdoResponse::DownloadSegmentAck { toggle })
                }
                _ => abort(0, 0, AbortCode::BAD_COMMAND),
            },
            SdoRequest::Abort { .. } => {
                self.transfer = None;
                None
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::od::{dtype, Access};
    use crate::wire::coe::{encode_request, parse_response, SlaveMessage};

    fn od() -> Dictionary {
        let mut d = Dictionary::default();
        d.add(0x6060, 0, "mode", (dtype::I8, 8), Access::Rw, 8);
        d.add_string(0x1008, "name", &"x".repeat(300));
        d
    }

    fn ask(s: &mut MailboxServer, od: &mut Dictionary, r: SdoRequest) -> SlaveMessage {
        let mut bytes = encode_request(&r, 1);
        bytes.resize(128, 0);
        s.request(&bytes, od, true, 0x1001);
        parse_response(&s.next_reply().unwrap()).unwrap().1
    }

    #[test]
    fn segmented_upload_and_toggle_errors() {
        let (mut s, mut d) = (MailboxServer::new(true), od());
        let SlaveMessage::Sdo(SdoResponse::Upload {
            size: Some(300),
            data,
            ..
        }) = ask(
            &mut s,
            &mut d,
            SdoRequest::Upload {
                index: 0x1008,
                sub: 0,
                complete: false,
            },
        )
        else {
            panic!("normal upload expected")
        };
        let mut got = data;
        let mut toggle = false;
        loop {
            let SlaveMessage::Sdo(SdoResponse::UploadSegment { last, data, .. }) =
                ask(&mut s, &mut d, SdoRequest::UploadSegment { toggle })
            else {
                panic!("segment expected")
            };
            got.extend_from_slice(&data);
            toggle = !toggle;
            if last {
                break;
            }
        }
        assert_eq!(got, vec![b'x'; 300]);
        ask(
            &mut s,
            &mut d,
            SdoRequest::Upload {
                index: 0x1008,
                sub: 0,
                complete: false,
            },
        );
        let m = ask(&mut s, &mut d, SdoRequest::UploadSegment { toggle: true });
        assert!(
            matches!(
                m,
                SlaveMessage::Sdo(SdoResponse::Abort {
                    code: AbortCode::TOGGLE,
                    ..
                })
            ),
            "{m:?}"
        );
    }

    #[test]
    fn download_and_aborts() {
        let (mut s, mut d) = (MailboxServer::new(true), od());
        let m = ask(
            &mut s,
            &mut d,
            SdoRequest::Download {
                index: 0x6060,
                sub: 0,
                complete: false,
                size: None,
                data: vec![9],
            },
        );
        assert!(matches!(
            m,
            SlaveMessage::Sdo(SdoResponse::DownloadAck { index: 0x6060, .. })
        ));
        assert_eq!(d.get(0x6060, 0), 9);
        let m = ask(
            &mut s,
            &mut d,
            SdoRequest::Upload {
                index: 0x7777,
                sub: 0,
                complete: false,
            },
        );
        assert!(matches!(
            m,
            SlaveMessage::Sdo(SdoResponse::Abort {
                code: AbortCode::NO_OBJECT,
                ..
            })
        ));
        // A garbage mailbox gets a mailbox error, never a panic.
        s.request(&[0xFF; 3], &mut d, true, 1);
        assert!(matches!(
            parse_response(&s.next_reply().unwrap()).unwrap().1,
            SlaveMessage::MailboxError(_)
        ));
    }
}
