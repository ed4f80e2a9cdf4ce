//! Bodies of the fuzz targets for this crate's parsers of outside bytes:
//! the slot scan (the ID bytes the boards answer) and the `sim` board
//! list. They take arbitrary bytes, must never panic, and check what
//! they can of the result. `tests/fuzz_parsers.rs` runs them; the
//! workspace's fuzz crate calls them as they are.

use crate::scan::{scan, BoardId};
use crate::sim::SimSpec;

/// ID bytes of the 16 slots (0xFF past the input): the scan finds boards
/// only where the bytes say so, in slot order, never overlapping, or
/// refuses an unknown kind naming its slot.
pub fn board_ids(bytes: &[u8]) {
    let id = |s: usize| bytes.get(s).copied().unwrap_or(0xFF);
    match scan(id) {
        Ok(found) => {
            let mut next = 0;
            for f in &found {
                assert!(f.slot >= next, "boards overlap");
                assert_eq!(f.id.byte(), id(f.slot));
                next = f.slot + f.id.slots();
            }
        }
        Err(crate::PpmcError::UnknownBoard { slot, id: b }) => assert_eq!(id(slot), b),
        Err(e) => panic!("unexpected: {e}"),
    }
    for b in bytes {
        let _ = BoardId::parse(0, *b);
    }
}

/// `sim=` text: parses or says why; what parses fits in a bus.
pub fn sim_spec(bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    if let Ok(s) = SimSpec::parse(&text) {
        let slots: usize = s.boards.iter().map(|b| b.slots()).sum();
        assert!(slots <= crate::regs::SLOTS);
    }
}
