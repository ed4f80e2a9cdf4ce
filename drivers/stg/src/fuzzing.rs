//! Bodies of the fuzz targets for this crate's parsers of outside bytes:
//! the `dio` module parameter and the board test register's contents.
//! They take arbitrary bytes, must never panic, and check what they can
//! of the result. `tests/fuzz_parsers.rs` runs them for 100 000 cases;
//! the workspace's fuzz crate can call them as they are.

use hal_driver::bus::PortBus;

use crate::detect::{probe, Model};
use crate::dio::Dio;
use crate::error::StgError;

/// `dio=` text: parses, and what parses prints back as given, in capitals.
pub fn dio_param(bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    if let Ok(d) = Dio::parse(&text) {
        assert_eq!(d.to_string(), text.to_ascii_uppercase());
    }
}

/// Board test register bytes (the first eight, 0xff after): probing
/// gives a model exactly for a true signature, "nothing answers" only
/// for all 0xff; checking single bytes never panics.
pub fn board_test_register(bytes: &[u8]) {
    let reads: Vec<u8> = (0..8)
        .map(|i| bytes.get(i).copied().unwrap_or(0xFF))
        .collect();
    let bus = Replay(std::sync::Mutex::new(reads.clone().into_iter()));
    let signature = reads
        .iter()
        .filter(|b| *b & 0x80 != 0)
        .fold(0u8, |v, b| v | 1 << ((b >> 4) & 7));
    match probe(&bus, 0x300) {
        Ok(m) => assert_eq!(m.signature(), signature),
        Err(StgError::NothingAnswers { .. }) => assert!(reads.iter().all(|&b| b == 0xFF)),
        Err(StgError::NotAnStg { signature: s, .. }) => {
            assert_eq!(s, signature);
            assert!(Model::from_signature(s).is_none());
        }
        Err(e) => panic!("unexpected: {e}"),
    }
    for b in bytes {
        let _ = (Model::One.brdtst_ok(*b), Model::Two.brdtst_ok(*b));
    }
}

/// A port bus whose byte reads replay a list, then read 0xff.
struct Replay(std::sync::Mutex<std::vec::IntoIter<u8>>);

impl PortBus for Replay {
    fn inb(&self, _: u16) -> u8 {
        self.0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .next()
            .unwrap_or(0xFF)
    }
    fn outb(&self, _: u16, _: u8) {}
    fn inw(&self, _: u16) -> u16 {
        0xFFFF
    }
    fn outw(&self, _: u16, _: u16) {}
    fn inl(&self, _: u16) -> u32 {
        u32::MAX
    }
    fn outl(&self, _: u16, _: u32) {}
    fn errors(&self) -> u64 {
        0
    }
    fn describe(&self) -> String {
        "replayed bytes".into()
    }
}
