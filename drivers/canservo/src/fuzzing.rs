//! The body of the fuzz target for everything that parses CAN frames from
//! outside: the realtime engine's reception (TPDOs, EMCY, heartbeats,
//! error frames, unknown identifiers), the SDO client reading a server's
//! answers, the simulated drive (NMT, SDO server, PDO engine, SYNC) and
//! the bring-up tool's frame decoder.
//! The other parsers of outside text have bodies here too: the per-drive
//! SDO file ([`drive_file`]) and the `loadrt` parameters
//! ([`module_params`]).
//! The workspace's `fuzz/` crate was not on main when this driver was
//! written, so the bodies live here as `pub fn`s of bytes and proptests
//! (`tests/fuzz_frames.rs`, `tests/fuzz_files.rs`) run each over more
//! than 100 000 random frames or inputs on stable; a `fuzz/` target only
//! needs to call them.
//!
//! What [`frames`] checks beyond "no panic": a `read` never takes more
//! frames than its budget (a flood cannot stall the cycle), and an SDO
//! transfer against a hostile server ends.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use std::path::Path;

use hal_core::module::ModuleArgs;

use crate::bus::CanBus;
use crate::config;
use crate::drivefile::DriveFile;
use crate::engine::{DriveInputs, Engine, EngineConfig};
use crate::frame::Frame;
use crate::sdo::SdoClient;
use crate::sim::{SimDrive, SimDriveConfig};
use crate::startup::Mode;

/// Node ids the fuzzer aims at.
const NODES: [u8; 2] = [1, 2];

/// A bus that hands out queued frames and swallows what is sent.
#[derive(Debug, Default)]
struct QueueBus {
    queue: Mutex<VecDeque<Frame>>,
    taken: Mutex<usize>,
}

impl QueueBus {
    fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
        m.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl CanBus for QueueBus {
    fn send(&self, _: &Frame) -> bool {
        true
    }
    fn try_recv(&self) -> Option<Frame> {
        let f = Self::lock(&self.queue).pop_front();
        if f.is_some() {
            *Self::lock(&self.taken) += 1;
        }
        f
    }
    fn recv_timeout(&self, _: Duration) -> Option<Frame> {
        self.try_recv()
    }
    fn errors(&self) -> u64 {
        0
    }
    fn describe(&self) -> String {
        "fuzz queue".into()
    }
}

/// Decodes fuzz bytes into frames, 11 bytes each: two for the
/// identifier (biased towards the CANopen objects of the fuzzed nodes),
/// one for kind and length, eight of data.
pub fn decode(data: &[u8]) -> Vec<Frame> {
    const BASES: [u16; 12] = [
        0x000, 0x080, 0x180, 0x280, 0x380, 0x200, 0x580, 0x600, 0x700, 0x080, 0x100, 0x000,
    ];
    data.chunks(11)
        .map(|c| {
            let b = |i: usize| c.get(i).copied().unwrap_or(0);
            let sel = b(0);
            let id = if sel & 0x80 != 0 {
                u32::from(u16::from_le_bytes([b(0), b(1)]) & 0x7FF)
            } else {
                let base = BASES[usize::from(sel) % BASES.len()];
                let node = if b(1) & 0x80 != 0 {
                    b(1) & 0x7F
                } else {
                    NODES[usize::from(b(1)) % 2]
                };
                u32::from(base + u16::from(node))
            };
            let flags = match b(2) >> 5 {
                0 => crate::frame::CAN_ERR_FLAG,
                1 => crate::frame::CAN_RTR_FLAG,
                2 => crate::frame::CAN_EFF_FLAG,
                _ => 0,
            };
            let mut d = [0u8; 8];
            for (i, v) in d.iter_mut().enumerate() {
                *v = b(3 + i);
            }
            Frame::from_raw(id | flags, b(2) & 0x0F, d)
        })
        .collect()
}

/// Runs every frame parser on the frames in `data`; panics only if an
/// invariant breaks. Returns the number of frames used.
pub fn frames(data: &[u8]) -> usize {
    let frames = decode(data);
    engine_reception(&frames);
    sdo_answers(&frames);
    drive_reception(&frames);
    let decoder = crate::decode::Decoder::canservo(&NODES, true);
    for f in &frames {
        assert!(!decoder.describe(f).is_empty());
    }
    frames.len()
}

fn engine_reception(frames: &[Frame]) {
    let bus = Arc::new(QueueBus::default());
    let cfg = EngineConfig {
        rx_budget: 8,
        ..EngineConfig::default()
    };
    let mut engine = Engine::without_startup(bus.clone(), &NODES, Mode::Csp, cfg);
    let inputs = [DriveInputs {
        enable: true,
        ..DriveInputs::default()
    }; 2];
    QueueBus::lock(&bus.queue).extend(frames.iter().copied());
    let mut now = 0u64;
    for _ in 0..frames.len() / 8 + 2 {
        let before = *QueueBus::lock(&bus.taken);
        engine.read(now, &inputs);
        let took = *QueueBus::lock(&bus.taken) - before;
        assert!(took <= 8, "a read took {took} frames, more than its budget");
        for st in engine.status() {
            assert!(!st.position_fb.is_nan() && !st.velocity_fb.is_nan());
        }
        engine.write(now, 1_000_000, &inputs);
        now += 1_000_000;
    }
}

fn sdo_answers(frames: &[Frame]) {
    // Every request is answered by the next fuzz frame, as if it came
    // from node 1's server.
    let bus = QueueBus::default();
    QueueBus::lock(&bus.queue).extend(frames.iter().map(|f| {
        let mut f = *f;
        if f.kind == crate::frame::FrameKind::Data && f.id & 0x7F == 1 {
            f.id = 0x581;
            f.extended = false;
        }
        f
    }));
    let sdo = SdoClient::new(&bus, 1, Duration::from_micros(1)).max_upload(64);
    let _ = sdo.upload(0x1008, 0);
    let _ = sdo.download(0x2000, 1, &[1, 2, 3, 4, 5, 6, 7, 8, 9]);
    let _ = sdo.read_u32(0x1000, 0);
}

fn drive_reception(frames: &[Frame]) {
    let mut d = SimDrive::new(SimDriveConfig::new(1));
    let mut out = Vec::new();
    d.power_up(&mut out);
    for (i, f) in frames.iter().enumerate() {
        d.receive(f, &mut out);
        if i % 4 == 0 {
            d.advance(250_000, &mut out);
        }
        assert!(out.len() < 10_000, "the drive keeps answering");
        out.clear();
    }
    d.advance(10_000_000, &mut out);
}

/// Parses `data` as a drive file. Checks besides "no panic": an error
/// names the file and a line of it; an accepted file's writes are in
/// line order, each value fits its type, and the writes written out as
/// `INDEX:SUB TYPE VALUE` lines parse back to the same writes. Returns
/// the number of writes.
pub fn drive_file(data: &[u8]) -> usize {
    let Ok(text) = std::str::from_utf8(data) else {
        // `DriveFile::load` refuses what is not UTF-8 before parsing.
        return 0;
    };
    let path = Path::new("fuzz.sdo");
    let lines = text.lines().count();
    match DriveFile::parse(path, text) {
        Err(e) => {
            let said = e.to_string();
            assert!(said.starts_with("drive file fuzz.sdo, line "), "{said}");
            match e {
                crate::Error::DriveFile { line, .. } => {
                    assert!(
                        (1..=lines).contains(&line),
                        "line {line} of {lines}: {said}"
                    )
                }
                other => panic!("not a line error: {other}"),
            }
            0
        }
        Ok(file) => {
            let mut last = 0;
            let mut again = String::new();
            for w in &file.writes {
                assert!(
                    w.line > last && w.line <= lines,
                    "line {} after {last}",
                    w.line
                );
                last = w.line;
                let (lo, hi) = w.ty.range();
                assert!((lo..=hi).contains(&w.value), "{w:?}");
                assert_eq!(w.ty.decode(&w.ty.bytes(w.value)), Some(w.value), "{w:?}");
                again += &format!("{:04X}:{:02X} {} {}\n", w.index, w.sub, w.ty, w.value);
            }
            let back = DriveFile::parse(path, &again).expect("written-out writes parse");
            let strip = |f: &DriveFile| -> Vec<_> {
                f.writes
                    .iter()
                    .map(|w| (w.index, w.sub, w.ty, w.value))
                    .collect()
            };
            assert_eq!(strip(&back), strip(&file));
            file.writes.len()
        }
    }
}

/// Reads `data` as the words of a `loadrt canservo` line (split at
/// whitespace) and parses them as the module does, up to opening the
/// bus. Checks besides "no panic": every error names the module; an
/// accepted line has one node plan, scale and home position per drive,
/// node ids 1..=127 without repeats and scales that are finite and not
/// zero. Returns whether it was accepted.
///
/// Words naming drive files read real files: the fuzzed bytes reach
/// [`DriveFile::load`] as paths, which reads only regular files, at most
/// [`crate::drivefile::MAX_FILE_BYTES`] of each.
pub fn module_params(data: &[u8]) -> bool {
    let text = String::from_utf8_lossy(data);
    let words: Vec<&str> = text.split_whitespace().collect();
    let parsed = ModuleArgs::parse(config::NAME, config::PARAMS, &words)
        .map_err(|e| e.to_string())
        .and_then(|args| config::parse(&args).map_err(|e| e.to_string()));
    match parsed {
        Err(e) => {
            assert!(e.contains("canservo"), "{e}");
            false
        }
        Ok(c) => {
            let n = c.plans.len();
            assert!((1..=config::MAX_DRIVES).contains(&n));
            assert_eq!((c.scales.len(), c.sim_home.len()), (n, n));
            for (i, p) in c.plans.iter().enumerate() {
                assert!((1..=127).contains(&p.node), "{p:?}");
                assert!(c.plans[..i].iter().all(|q| q.node != p.node));
            }
            assert!(c.scales.iter().all(|s| s.is_finite() && *s != 0.0));
            assert!(c.engine.period_ns > 0 && c.engine.tpdo_misses > 0);
            true
        }
    }
}
