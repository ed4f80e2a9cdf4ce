//! Finding the boards on an EPP bus: each slot's ID byte says what
//! answers there and its firmware revision ([`crate::regs`]).
//!
//! A slot whose ID reads 0x00 or 0xFF, or whose revision nibble is 0xF
//! (a byte left on the bus by a board that does not decode that
//! address), is empty. A board that decodes two slots
//! ([`BoardId::slots`]) hides the second one from the scan. An ID whose
//! kind is none of the five is refused: it is usually a port not in EPP
//! mode or a cable fault, and guessing would drive the wrong registers.

use std::fmt;

use crate::error::PpmcError;
use crate::regs::{id, SLOTS};

/// The kind of board.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// PPMC encoder board.
    Encoder,
    /// PPMC 16-bit DAC board.
    Dac,
    /// PPMC digital I/O board.
    Dio,
    /// Universal Stepper Controller.
    Usc,
    /// Universal PWM Controller.
    Upc,
}

impl Kind {
    /// The ID nibble of the kind.
    pub fn code(self) -> u8 {
        match self {
            Kind::Encoder => id::ENCODER,
            Kind::Dac => id::DAC,
            Kind::Dio => id::DIO,
            Kind::Usc => id::USC,
            Kind::Upc => id::UPC,
        }
    }

    /// Whether the board has encoder counters.
    pub fn has_encoders(self) -> bool {
        matches!(self, Kind::Encoder | Kind::Usc | Kind::Upc)
    }

    /// Whether it is a USC or a UPC (digital I/O, estop, extra port).
    pub fn is_uxc(self) -> bool {
        matches!(self, Kind::Usc | Kind::Upc)
    }
}

impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Kind::Encoder => "PPMC encoder board",
            Kind::Dac => "PPMC DAC board",
            Kind::Dio => "PPMC digital I/O board",
            Kind::Usc => "Universal Stepper Controller",
            Kind::Upc => "Universal PWM Controller",
        })
    }
}

/// A board's ID byte, decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BoardId {
    /// What it is.
    pub kind: Kind,
    /// Its firmware revision (0..14).
    pub rev: u8,
}

impl BoardId {
    /// The ID read in `slot`: `Ok(None)` for an empty slot, an error for
    /// a kind no Pico board has.
    pub fn parse(slot: usize, byte: u8) -> Result<Option<BoardId>, PpmcError> {
        if byte == 0 || byte == 0xFF || byte & 0x0F == 0x0F {
            return Ok(None);
        }
        let kind = match byte & 0xF0 {
            id::ENCODER => Kind::Encoder,
            id::DAC => Kind::Dac,
            id::DIO => Kind::Dio,
            id::USC => Kind::Usc,
            id::UPC => Kind::Upc,
            _ => return Err(PpmcError::UnknownBoard { slot, id: byte }),
        };
        Ok(Some(BoardId {
            kind,
            rev: byte & 0x0F,
        }))
    }

    /// The ID byte.
    pub fn byte(self) -> u8 {
        self.kind.code() | (self.rev & 0x0F)
    }

    /// Slots the board decodes: two for the USC, the UPC and encoder
    /// boards from revision 4 (their timestamp registers), else one.
    pub fn slots(self) -> usize {
        match self.kind {
            Kind::Usc | Kind::Upc => 2,
            Kind::Encoder if self.rev >= 4 => 2,
            _ => 1,
        }
    }

    /// Whether the counters take `index-enable` (revision 2 and later).
    pub fn has_index(self) -> bool {
        self.rev >= 2
    }

    /// Whether the counters have timestamps (encoder board or UPC,
    /// revision 4 and later).
    pub fn has_timestamps(self) -> bool {
        matches!(self.kind, Kind::Encoder | Kind::Upc) && self.rev >= 4
    }

    /// Whether the board has the 8-bit extra port (every USC; UPC from
    /// revision 2).
    pub fn has_extra_port(self) -> bool {
        self.kind == Kind::Usc || (self.kind == Kind::Upc && self.rev >= 2)
    }

    /// Whether the encoder input filter clock can be set (encoder board
    /// from revision 4).
    pub fn has_filter_clock(self) -> bool {
        self.kind == Kind::Encoder && self.rev >= 4
    }
}

/// A board found in a scan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Found {
    /// Its first slot.
    pub slot: usize,
    /// What it is.
    pub id: BoardId,
}

/// Scans the 16 slots, `read_id(slot)` giving each one's ID byte.
/// Slots hidden by a two-slot board are not read.
pub fn scan(mut read_id: impl FnMut(usize) -> u8) -> Result<Vec<Found>, PpmcError> {
    let mut found = Vec::new();
    let mut slot = 0;
    while slot < SLOTS {
        match BoardId::parse(slot, read_id(slot))? {
            Some(id) => {
                found.push(Found { slot, id });
                slot += id.slots();
            }
            None => slot += 1,
        }
    }
    Ok(found)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids() {
        assert_eq!(BoardId::parse(0, 0x00).unwrap(), None);
        assert_eq!(BoardId::parse(0, 0xFF).unwrap(), None);
        assert_eq!(BoardId::parse(0, 0x1F).unwrap(), None);
        let upc = BoardId::parse(0, 0x54).unwrap().unwrap();
        assert_eq!((upc.kind, upc.rev, upc.slots()), (Kind::Upc, 4, 2));
        assert!(upc.has_timestamps() && upc.has_extra_port());
        let enc = BoardId::parse(0, 0x12).unwrap().unwrap();
        assert_eq!((enc.slots(), enc.has_timestamps()), (1, false));
        let e = BoardId::parse(3, 0x73).unwrap_err().to_string();
        assert_eq!(
            e,
            "slot 3 answers with ID 0x73, which is no Pico board (is the port in EPP mode and \
             the cable right?)"
        );
    }

    #[test]
    fn two_slot_boards_hide_their_second_slot() {
        let ids = [
            0x14u8, 0x99, 0x21, 0x32, 0, 0x43, 0x99, 0xFF, 0x54, 0x99, 0, 0, 0, 0, 0, 0,
        ];
        let f = scan(|s| ids[s]).unwrap();
        let got: Vec<_> = f.iter().map(|b| (b.slot, b.id.kind)).collect();
        assert_eq!(
            got,
            [
                (0, Kind::Encoder),
                (2, Kind::Dac),
                (3, Kind::Dio),
                (5, Kind::Usc),
                (8, Kind::Upc)
            ]
        );
    }
}
