//! Mesa's SPI framing (hostmot2-more.md 3.2): every access is a command
//! word and then its data words, all 32 bits, most significant bit first.
//!
//! | bits | field |
//! |---|---|
//! | 31..16 | byte address of the first register |
//! | 15..12 | command: 0xA read, 0xB write |
//! | 11 | address increment (each word the next register) |
//! | 10..4 | burst count, 1..127 words |
//! | 3..0 | zero |
//!
//! A read's data words are shifted back by the board while the host
//! sends filler; a write's are the host's. One message (one chip-select
//! assertion) may hold several frames back to back.
//!
//! [`Command`] encodes and decodes the command word; [`serve`] is the
//! board's side of a message (the simulator's, and what the fuzz target
//! drives): it walks the frames, refusing a word that is not a command
//! or a burst longer than what is left of the message.

use thiserror::Error;

/// The read command.
pub const READ: u8 = 0xA;
/// The write command.
pub const WRITE: u8 = 0xB;
/// The address-increment bit.
pub const INCREMENT: u32 = 1 << 11;
/// The longest burst one command moves.
pub const MAX_BURST: usize = 127;

/// What a command does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Op {
    /// The board sends registers.
    Read,
    /// The host sends registers.
    Write,
}

/// A decoded command word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Command {
    /// Byte address of the first register.
    pub addr: u16,
    /// Read or write.
    pub op: Op,
    /// Whether the address steps 4 bytes per word.
    pub increment: bool,
    /// Words that follow, 1..=[`MAX_BURST`].
    pub count: u8,
}

/// Why a message cannot be served.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum FrameError {
    /// The word where a command was due is none.
    #[error("word {at} of the message (0x{word:08X}) is not a read or write command")]
    NotACommand {
        /// Its place in the message.
        at: usize,
        /// The word.
        word: u32,
    },
    /// A command with a burst count of 0 or low bits set.
    #[error("word {at} of the message (0x{word:08X}) has a burst count of 0 or stray low bits")]
    BadCount {
        /// Its place in the message.
        at: usize,
        /// The word.
        word: u32,
    },
    /// A burst longer than the rest of the message.
    #[error("the command at word {at} moves {count} words but the message ends after {left}")]
    Truncated {
        /// The command's place in the message.
        at: usize,
        /// Words it moves.
        count: usize,
        /// Words left after it.
        left: usize,
    },
}

impl Command {
    /// A read of `count` registers from `addr`, incrementing.
    pub fn read(addr: u16, count: u8) -> Command {
        Command {
            addr,
            op: Op::Read,
            increment: true,
            count,
        }
    }

    /// A write of `count` registers at `addr`, incrementing.
    pub fn write(addr: u16, count: u8) -> Command {
        Command {
            addr,
            op: Op::Write,
            increment: true,
            count,
        }
    }

    /// The command word.
    pub fn encode(self) -> u32 {
        let cmd = match self.op {
            Op::Read => READ,
            Op::Write => WRITE,
        };
        (self.addr as u32) << 16
            | (cmd as u32) << 12
            | if self.increment { INCREMENT } else { 0 }
            | ((self.count as u32) & 0x7F) << 4
    }

    /// Decodes the word at place `at` of a message.
    pub fn decode(word: u32, at: usize) -> Result<Command, FrameError> {
        let op = match (word >> 12) & 0xF {
            c if c == READ as u32 => Op::Read,
            c if c == WRITE as u32 => Op::Write,
            _ => return Err(FrameError::NotACommand { at, word }),
        };
        let count = ((word >> 4) & 0x7F) as u8;
        if count == 0 || word & 0xF != 0 {
            return Err(FrameError::BadCount { at, word });
        }
        Ok(Command {
            addr: (word >> 16) as u16,
            op,
            increment: word & INCREMENT != 0,
            count,
        })
    }

    /// The byte address of word `k` of the burst.
    pub fn addr_of(&self, k: usize) -> u32 {
        if self.increment {
            self.addr as u32 + 4 * k as u32
        } else {
            self.addr as u32
        }
    }
}

/// The board's registers, as [`serve`] reaches them.
pub trait Registers {
    /// Reads the register at byte address `addr`.
    fn read(&mut self, addr: u32) -> u32;
    /// Writes the register at byte address `addr`.
    fn write(&mut self, addr: u32, value: u32);
}

/// Serves one message as the board: `buf` holds what the host sent and,
/// on return, what the board sent back (zeros under command words and
/// write data, the registers under a read's data). Returns the frames
/// served; at the first bad frame it stops and says why, the rest of the
/// message reading back as zeros and nothing of it done.
pub fn serve(buf: &mut [u32], regs: &mut dyn Registers) -> Result<usize, FrameError> {
    let mut at = 0;
    let mut frames = 0;
    while at < buf.len() {
        let word = buf[at];
        let served = Command::decode(word, at).and_then(|c| {
            let left = buf.len() - at - 1;
            if c.count as usize > left {
                Err(FrameError::Truncated {
                    at,
                    count: c.count as usize,
                    left,
                })
            } else {
                Ok(c)
            }
        });
        let c = match served {
            Ok(c) => c,
            Err(e) => {
                buf[at..].fill(0);
                return Err(e);
            }
        };
        buf[at] = 0;
        let data = &mut buf[at + 1..at + 1 + c.count as usize];
        for (k, w) in data.iter_mut().enumerate() {
            match c.op {
                Op::Read => *w = regs.read(c.addr_of(k)),
                Op::Write => {
                    regs.write(c.addr_of(k), *w);
                    *w = 0;
                }
            }
        }
        at += 1 + c.count as usize;
        frames += 1;
    }
    Ok(frames)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A register file of 64 words that records its accesses.
    struct Mock {
        regs: [u32; 64],
        log: Vec<(char, u32)>,
    }

    impl Default for Mock {
        fn default() -> Self {
            Mock {
                regs: [0; 64],
                log: Vec::new(),
            }
        }
    }

    impl Registers for Mock {
        fn read(&mut self, addr: u32) -> u32 {
            self.log.push(('r', addr));
            self.regs[(addr as usize / 4) % 64]
        }
        fn write(&mut self, addr: u32, value: u32) {
            self.log.push(('w', addr));
            self.regs[(addr as usize / 4) % 64] = value;
        }
    }

    #[test]
    fn command_words_are_mesas() {
        assert_eq!(Command::read(0x0100, 4).encode(), 0x0100_A840);
        assert_eq!(Command::write(0x0C00, 1).encode(), 0x0C00_B810);
        let c = Command::decode(0x0100_A840, 0).unwrap();
        assert_eq!(c, Command::read(0x0100, 4));
        let fixed = Command::decode(0x0040_B010, 0).unwrap();
        assert!(!fixed.increment);
        assert_eq!(fixed.addr_of(3), 0x40);
        for k in 1..=MAX_BURST as u8 {
            let c = Command::write(0xFFFC, k);
            assert_eq!(Command::decode(c.encode(), 0), Ok(c));
        }
    }

    #[test]
    fn bad_words_say_what_and_where() {
        assert_eq!(
            Command::decode(0x0100_C840, 3),
            Err(FrameError::NotACommand {
                at: 3,
                word: 0x0100_C840
            })
        );
        assert!(matches!(
            Command::decode(0x0100_A800, 0),
            Err(FrameError::BadCount { .. })
        ));
        assert!(matches!(
            Command::decode(0x0100_A841, 0),
            Err(FrameError::BadCount { .. })
        ));
        let e = FrameError::Truncated {
            at: 2,
            count: 5,
            left: 1,
        };
        assert_eq!(
            e.to_string(),
            "the command at word 2 moves 5 words but the message ends after 1"
        );
    }

    #[test]
    fn a_message_of_several_frames() {
        let mut m = Mock::default();
        let mut buf = vec![
            Command::write(0x0010, 2).encode(),
            0x1111,
            0x2222,
            Command::read(0x000C, 3).encode(),
            0xFFFF_FFFF,
            0xFFFF_FFFF,
            0xFFFF_FFFF,
        ];
        m.regs[3] = 0x3333;
        assert_eq!(serve(&mut buf, &mut m), Ok(2));
        assert_eq!(buf, [0, 0, 0, 0, 0x3333, 0x1111, 0x2222]);
        assert_eq!(
            m.log,
            [
                ('w', 0x10),
                ('w', 0x14),
                ('r', 0x0C),
                ('r', 0x10),
                ('r', 0x14)
            ]
        );
    }

    #[test]
    fn a_bad_frame_stops_the_message_and_does_nothing_of_it() {
        let mut m = Mock::default();
        let mut buf = vec![
            Command::write(0x0000, 1).encode(),
            7,
            Command::write(0x0004, 3).encode(),
            8,
            9,
        ];
        let e = serve(&mut buf, &mut m).unwrap_err();
        assert_eq!(
            e,
            FrameError::Truncated {
                at: 2,
                count: 3,
                left: 2
            }
        );
        assert_eq!(m.regs[0], 7, "the first frame was served");
        assert_eq!(m.regs[1], 0, "the truncated one was not");
        assert_eq!(buf, [0, 0, 0, 0, 0]);
        let mut junk = vec![0x1234_5678, 1, 2];
        assert!(matches!(
            serve(&mut junk, &mut m),
            Err(FrameError::NotACommand { at: 0, .. })
        ));
        assert_eq!(serve(&mut [], &mut m), Ok(0));
    }
}
