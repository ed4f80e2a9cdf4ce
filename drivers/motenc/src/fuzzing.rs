//! Bodies of the fuzz targets for this crate's parsers of outside bytes:
//! register contents at identification, ADC result words, and the
//! `sim_boards` items. They take arbitrary bytes, must never panic, and
//! check what they can of the result. `tests/fuzz_parsers.rs` runs them
//! for 100 000 cases; the workspace's fuzz crate can call them as they
//! are.

use hal_driver::bus::{RegWindow, ALL_ONES};

use crate::board::{identify, BoardKind};
use crate::error::MotencError;
use crate::open::parse_board_kind;
use crate::regs;

/// A register window holding the words of `bytes` (little-endian, 0
/// past the end) at the offsets identification reads.
struct Words {
    version: u32,
    status: u32,
}

impl RegWindow for Words {
    fn len(&self) -> usize {
        regs::WINDOW_LEN
    }
    fn read32(&self, offset: usize) -> u32 {
        match offset {
            regs::BOARD_VERSION => self.version,
            o if o == regs::status_control(0) => self.status,
            _ => 0,
        }
    }
    fn write32(&self, _: usize, _: u32) {}
    fn errors(&self) -> u64 {
        0
    }
    fn describe(&self) -> String {
        "fuzzed registers".into()
    }
}

fn word(bytes: &[u8], i: usize) -> u32 {
    let mut w = [0u8; 4];
    for (j, b) in w.iter_mut().enumerate() {
        *b = bytes.get(4 * i + j).copied().unwrap_or(0);
    }
    u32::from_le_bytes(w)
}

/// boardVersion and statusControl as the first two words: identification
/// accepts exactly versions 0 and 1, names "nothing answers" only for
/// all ones in both, and reads the jumpers from bits 17..16. The third
/// word, as an ADC result, converts within the 14-bit range.
pub fn registers(bytes: &[u8]) {
    let (version, status) = (word(bytes, 0), word(bytes, 1));
    match identify(&Words { version, status }) {
        Ok(id) => {
            assert!(version <= 1);
            assert_eq!(Some(id.kind), BoardKind::from_version(version));
            assert_eq!(id.jumper_id as u32, (status >> 16) & 3);
        }
        Err(MotencError::NoAnswer { .. }) => assert!(version == ALL_ONES && status == ALL_ONES),
        Err(MotencError::UnknownVersion { found, .. }) => assert_eq!(found, version),
        Err(e) => panic!("unexpected: {e}"),
    }
    let adc = regs::adc_count(word(bytes, 2));
    assert!((-8192..=8191).contains(&adc));
}

/// A `sim_boards` item.
pub fn board_kind_item(bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    if let Ok(k) = parse_board_kind(&text) {
        let t = text.to_ascii_lowercase();
        assert!(t.ends_with(if k == BoardKind::Motenc100 {
            "100"
        } else {
            "lite"
        }));
    }
}
