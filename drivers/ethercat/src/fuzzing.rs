//! The bodies of the fuzz targets for every parser of outside bytes in
//! this crate (`fuzz/` names them; `tests/fuzz_parsers.rs` runs them
//! over random and seed inputs), and the seed inputs they start from.
//!
//! * [`frames`]: an Ethernet frame as it arrives from the wire: the frame
//!   parser, the simulated segment processing it as a line of ESCs would,
//!   and EtherCrab's reception with a frame of its own in flight (the
//!   master's side: a hostile frame never panics the host).
//! * [`mailbox`]: a mailbox area as a slave or a master wrote it: the CoE
//!   parsers both ways, the simulated slave's SDO server, and the
//!   master's SDO client taking the bytes as a slave's replies
//!   ([`crate::sdo::fuzz_client`]).
//! * [`sii`]: an SII EEPROM image.
//! * [`xml`]: linuxcnc-ethercat's `ethercat-conf.xml`.
//! * [`segment_file`]: `ethercat-sim`'s segment description, and its
//!   fault commands.
//!
//! Each panics only on a finding: a panic in the code under test or a
//! broken invariant named in its doc comment.

use std::future::Future;
use std::path::Path;
use std::pin::pin;
use std::task::{Context, Waker};

use ethercrab::{Command as EcCommand, MainDevice, MainDeviceConfig, PduStorage, Timeouts};

use crate::lcec::conf;
use crate::regs;
use crate::sim::{self, mailbox::MailboxServer, Outcome, Segment};
use crate::wire::coe::{self, AbortCode, Emergency, ErrorCode, SdoRequest, SdoResponse};
use crate::wire::frame::{self, Command, Frame, FrameBuilder};
use crate::wire::sii::Sii;

/// The segment the frame target sends into: a coupler, outputs, an
/// encoder and a drive (mailbox, DC).
fn fuzz_segment() -> Segment {
    let devices = ["EK1100", "EL2008", "EL5101", "servo"]
        .iter()
        .zip(1u32..)
        .filter_map(|(k, serial)| sim::device_by_name(k, serial))
        .collect();
    Segment::new(devices)
}

/// A frame from the wire.
///
/// Checks: the datagram spans lie inside the frame, in order, without
/// overlap; a parsed frame has as many datagrams as spans; the segment
/// neither panics nor changes the frame's length, and returns only
/// frames the parser accepts; EtherCrab's reception of the bytes as the
/// answer to a frame it has in flight (index patched in, or the
/// segment's genuine answer with the input's bytes written over it)
/// returns an error or a value, never a panic.
pub fn frames(input: &[u8]) {
    if let Ok(spans) = frame::datagram_spans(input) {
        let mut end = frame::ETH_HEADER_LEN + frame::ECAT_HEADER_LEN;
        for s in &spans {
            assert!(s.header >= end && s.data == s.header + frame::DATAGRAM_HEADER_LEN);
            assert!(s.wkc == s.data + s.len && s.wkc + frame::WKC_LEN <= input.len());
            end = s.wkc + frame::WKC_LEN;
        }
        let parsed = Frame::parse(input).expect("spans found, so the frame parses");
        assert_eq!(parsed.datagrams.len(), spans.len());
        let _ = frame::describe(&parsed);
    }
    let mut seg = fuzz_segment();
    let mut copy = input.to_vec();
    let len = copy.len();
    // Twice: the second pass finds the slaves in whatever state the
    // first left them.
    for now in [0, 1_000_000] {
        if seg.process(&mut copy, now) == Outcome::Returned {
            assert!(frame::datagram_spans(&copy).is_ok());
        }
        assert_eq!(copy.len(), len);
    }
    master_receives(input, &mut seg);
}

/// EtherCrab with one register read in flight receives `input` as its
/// answer.
fn master_receives(input: &[u8], seg: &mut Segment) {
    let storage = PduStorage::<2, { PduStorage::element_size(128) }>::new();
    let Ok((mut tx, mut rx, pdu_loop)) = storage.try_split() else {
        return;
    };
    let md = MainDevice::new(pdu_loop, Timeouts::default(), MainDeviceConfig::default());
    let mut read = pin!(EcCommand::fprd(0x1001, regs::AL_STATUS).receive::<u16>(&md));
    let mut cx = Context::from_waker(Waker::noop());
    if read.as_mut().poll(&mut cx).is_ready() {
        return;
    }
    let mut sent = Vec::new();
    while let Some(f) = tx.next_sendable_frame() {
        let _ = f.send_blocking(|d| {
            sent = d.to_vec();
            Ok(d.len())
        });
    }
    let mut reply = input.to_vec();
    let index_at = frame::ETH_HEADER_LEN + frame::ECAT_HEADER_LEN + 1;
    match input.first().map(|b| b % 3) {
        // The input as it is.
        Some(0) | None => {}
        // The input, made to answer the frame in flight.
        Some(1) => {
            if let (Some(r), Some(&i)) = (reply.get_mut(index_at), sent.get(index_at)) {
                *r = i;
            }
        }
        // The segment's answer with the input's bytes written over it,
        // two bytes of position and one of value at a time.
        _ => {
            let mut answer = sent.clone();
            seg.process(&mut answer, 2_000_000);
            if !answer.is_empty() {
                for edit in input[1..].chunks_exact(3) {
                    let at = usize::from(u16::from_le_bytes([edit[0], edit[1]])) % answer.len();
                    answer[at] = edit[2];
                }
            }
            reply = answer;
        }
    }
    let _ = rx.receive_frame(&reply);
    let _ = read.as_mut().poll(&mut cx);
}

/// A mailbox area from either side.
///
/// Checks: every parse is an error or a value; a parsed SDO response or
/// request encodes back into a mailbox that parses to the same message;
/// the simulated SDO server, given the bytes as a request, answers only
/// with mailboxes the master's parser accepts; the SDO client, given the
/// bytes as a run of replies, ends every transfer in a value or an
/// error.
pub fn mailbox(input: &[u8]) {
    if let Ok((h, coe::SlaveMessage::Sdo(resp))) = coe::parse_response(input) {
        let again = coe::encode_response(&resp, h.address, h.counter);
        match coe::parse_response(&again) {
            Ok((_, coe::SlaveMessage::Sdo(back))) => assert_eq!(back, resp),
            other => panic!("{resp:?} encoded to {again:02x?}, parsed as {other:?}"),
        }
    }
    if let Ok((h, coe::MasterMessage::Sdo(req))) = coe::parse_request(input) {
        let again = coe::encode_request(&req, h.counter);
        match coe::parse_request(&again) {
            Ok((_, coe::MasterMessage::Sdo(back))) => assert_eq!(back, req),
            other => panic!("{req:?} encoded to {again:02x?}, parsed as {other:?}"),
        }
    }
    let Some(mut servo) = sim::device_by_name("servo", 1) else {
        return;
    };
    let mut server = MailboxServer::new(true);
    for preop in [true, false] {
        server.request(input, &mut servo.od, preop, 0x1001);
        while let Some(reply) = server.next_reply() {
            if let Err(e) = coe::parse_response(&reply) {
                panic!("the SDO server wrote {reply:02x?}, which does not parse: {e}");
            }
        }
    }
    crate::sdo::fuzz_client(input);
}

/// An SII image.
///
/// Checks: a decoded image encodes to one that decodes to the same
/// contents.
pub fn sii(input: &[u8]) {
    if let Ok(s) = Sii::decode(input, Some("fuzz.bin")) {
        let again = s.encode();
        match Sii::decode(&again, None) {
            Ok(back) => assert_eq!(back, s, "round trip of an accepted image"),
            Err(e) => panic!("an accepted image, written again, is refused: {e}"),
        }
    }
}

/// An `ethercat-conf.xml`.
///
/// Checks: an accepted configuration has a positive application period,
/// PDO entries of 1 to 64 bits whose complex entries fit them, and pins
/// (where the slave's type is supported) with names unique per slave.
pub fn xml(input: &[u8]) {
    let text = String::from_utf8_lossy(input);
    let Ok(cfg) = conf::parse(&text, Path::new("fuzz.xml")) else {
        return;
    };
    for m in &cfg.masters {
        assert!(m.app_time_period > 0);
        for s in &m.slaves {
            for e in s
                .sync_managers
                .iter()
                .flat_map(|sm| &sm.pdos)
                .flat_map(|p| &p.entries)
            {
                assert!((1..=64).contains(&e.bit_len));
                let bits: u32 = e.complex.iter().map(|c| u32::from(c.bit_len)).sum();
                assert!(bits <= u32::from(e.bit_len));
            }
            if let Ok(pins) = crate::lcec::slave_pins(s, Path::new("fuzz.xml")) {
                let mut names: Vec<&str> = pins.iter().map(|p| p.name.as_str()).collect();
                names.sort_unstable();
                let n = names.len();
                names.dedup();
                assert_eq!(n, names.len(), "duplicate pin names in {}", s.name);
            }
        }
    }
}

/// An `ethercat-sim` segment file, and each of its lines as a fault
/// command.
///
/// Checks: an accepted file names at least one slave and builds a
/// segment of that many slaves; an accepted command applies to that
/// segment or says why not.
pub fn segment_file(input: &[u8]) {
    let text = String::from_utf8_lossy(input);
    if let Ok(spec) = sim::file::parse(&text, Path::new("fuzz.seg")) {
        assert!(!spec.slaves.is_empty());
        let mut seg = spec.build().expect("an accepted file builds");
        assert_eq!(seg.slaves().len(), spec.slaves.len());
        for line in text.lines() {
            if let Ok(c) = sim::control::Control::parse(line) {
                let _ = c.apply(&mut seg);
            }
        }
    }
    let mut seg = fuzz_segment();
    for line in text.lines() {
        if let Ok(c) = sim::control::Control::parse(line) {
            let _ = c.apply(&mut seg);
        }
    }
}

/// Seed frames: what a master sends during bring-up and cycles (station
/// addresses, AL control and status, SII access, a mailbox request, DC
/// reads, logical process data), each also as the segment answers it.
pub fn seed_frames() -> Vec<Vec<u8>> {
    let src = [0x10; 6];
    let one = |c: Command, adp: u16, ado: u16, data: &[u8]| -> Vec<u8> {
        let mut b = FrameBuilder::new(src);
        let _ = b.push_physical(c, 1, adp, ado, data);
        b.finish()
    };
    let upload = coe::encode_request(
        &SdoRequest::Upload {
            index: 0x1018,
            sub: 1,
            complete: false,
        },
        1,
    );
    let mut frames = vec![
        one(
            Command::Apwr,
            0,
            regs::STATION_ADDRESS,
            &0x1000u16.to_le_bytes(),
        ),
        one(Command::Brd, 0, regs::AL_STATUS, &[0, 0]),
        one(Command::Fpwr, 0x1001, regs::AL_CONTROL, &[0x12, 0]),
        one(Command::Fprd, 0x1003, regs::AL_STATUS, &[0; 6]),
        one(
            Command::Fpwr,
            0x1003,
            regs::SII_CONTROL,
            &[0, 1, 0x08, 0, 0, 0],
        ),
        one(Command::Fprd, 0x1003, regs::SII_CONTROL, &[0; 12]),
        one(Command::Fpwr, 0x1003, 0x1000, &upload),
        one(Command::Fprd, 0x1003, 0x1080, &[0; 128]),
        one(Command::Brd, 0, 0x0900, &[0; 8]),
        one(Command::Frmw, 0x1000, 0x0910, &[0; 8]),
    ];
    let mut lrw = FrameBuilder::new(src);
    let _ = lrw.push(Command::Lrw, 2, 0x0001_0000, &[0x5A; 24]);
    let _ = lrw.push_physical(Command::Armw, 3, 0, 0x0910, &[0; 8]);
    frames.push(lrw.finish());
    let mut seg = fuzz_segment();
    let answered: Vec<Vec<u8>> = frames
        .iter()
        .map(|f| {
            let mut a = f.clone();
            seg.process(&mut a, 0);
            a
        })
        .collect();
    frames.extend(answered);
    frames
}

/// Seed mailboxes: SDO requests and responses of every kind, an
/// emergency and a mailbox error reply.
pub fn seed_mailboxes() -> Vec<Vec<u8>> {
    let requests = [
        SdoRequest::Upload {
            index: 0x1018,
            sub: 1,
            complete: false,
        },
        SdoRequest::Download {
            index: 0x6060,
            sub: 0,
            complete: false,
            size: Some(1),
            data: vec![8],
        },
        SdoRequest::Download {
            index: 0x8000,
            sub: 1,
            complete: false,
            size: Some(12),
            data: b"hello world!".to_vec(),
        },
        SdoRequest::DownloadSegment {
            toggle: false,
            last: true,
            data: vec![1, 2, 3],
        },
        SdoRequest::UploadSegment { toggle: true },
        SdoRequest::Abort {
            index: 0x1018,
            sub: 1,
            code: AbortCode(0x0504_0000),
        },
    ];
    let responses = [
        SdoResponse::Upload {
            index: 0x1018,
            sub: 1,
            size: None,
            data: vec![2, 0, 0, 0],
        },
        SdoResponse::Upload {
            index: 0x1008,
            sub: 0,
            size: Some(20),
            data: b"SimServo".to_vec(),
        },
        SdoResponse::UploadSegment {
            toggle: false,
            last: true,
            data: b"tail".to_vec(),
        },
        SdoResponse::DownloadAck {
            index: 0x6060,
            sub: 0,
        },
        SdoResponse::DownloadSegmentAck { toggle: true },
        SdoResponse::Abort {
            index: 0x6060,
            sub: 0,
            code: AbortCode(0x0609_0030),
        },
    ];
    let mut out: Vec<Vec<u8>> = requests.iter().map(|r| coe::encode_request(r, 1)).collect();
    out.extend(responses.iter().map(|r| coe::encode_response(r, 0x1001, 2)));
    out.push(coe::encode_emergency(
        &Emergency {
            code: ErrorCode(0x2310),
            register: 0x03,
            data: [1, 2, 3, 4, 5],
        },
        0x1001,
        3,
    ));
    out.push(coe::encode_mailbox_error(
        coe::mailbox_error::UNSUPPORTED_PROTOCOL,
        0x1001,
    ));
    out
}

/// Seed SII images: one of every simulated device.
pub fn seed_sii_images() -> Vec<Vec<u8>> {
    sim::DEVICE_NAMES
        .iter()
        .filter_map(|k| sim::device_by_name(k, 7))
        .map(|d| d.sii().encode())
        .collect()
}
