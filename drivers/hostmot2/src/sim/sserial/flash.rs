//! A simulated remote card's firmware flash, as `setsserial flash`
//! reaches it (hostmot2-more.md 2.3): in flash access mode (the
//! non-volatile access command with interface 0 = 2) the card's
//! addresses from [`ADDR`] on are the flash controller's registers and
//! writes below them fill the write buffer; a command byte at
//! [`COMMAND`] erases the block at the address or programs the buffer
//! there, and a cookie read then says the card is in step.
//!
//! The sizes are the simulator's choice (no source read documents a
//! card's): 64 KiB of flash in 1 KiB erase blocks, 64-byte writes.

pub use crate::sserial::flash::{ADDR, COMMAND, COOKIE, ERASE, ERASE_SIZE, WRITE, WRITE_SIZE};

/// The flash of a simulated card.
#[derive(Debug, Clone)]
pub struct SimFlash {
    /// The flash array (erased bytes read 0xFF).
    pub bytes: Vec<u8>,
    /// log2 of the erase block size.
    pub erase_shift: u8,
    /// log2 of the write size.
    pub write_shift: u8,
    /// What a cookie read answers (tests change it to break the sync).
    pub cookie: u8,
    /// Blocks erased.
    pub erases: u32,
    /// Chunks programmed.
    pub writes: u32,
    /// An erase or write outside the flash was asked: the card is out
    /// of step and its cookie reads 0 until the next good command.
    pub lost: bool,
    addr: u32,
    buffer: Vec<u8>,
}

impl Default for SimFlash {
    fn default() -> SimFlash {
        SimFlash::new(16, 10, 6)
    }
}

impl SimFlash {
    /// An erased flash of 2^`size_shift` bytes.
    pub fn new(size_shift: u8, erase_shift: u8, write_shift: u8) -> SimFlash {
        SimFlash {
            bytes: vec![0xFF; 1 << size_shift],
            erase_shift,
            write_shift,
            cookie: COOKIE,
            erases: 0,
            writes: 0,
            lost: false,
            addr: 0,
            buffer: vec![0xFF; 1 << write_shift],
        }
    }

    /// The cookie a special read answers.
    pub fn cookie(&self) -> u8 {
        if self.lost {
            0
        } else {
            self.cookie
        }
    }

    /// A read of `n` bytes at `addr` in flash access mode.
    pub fn read(&self, addr: u16, n: usize) -> u64 {
        let mut v = 0u64;
        for i in 0..n.min(8) {
            v |= u64::from(self.byte(addr.wrapping_add(i as u16))) << (8 * i);
        }
        v
    }

    fn byte(&self, at: u16) -> u8 {
        match at {
            ADDR..=0x8003 => self.addr.to_le_bytes()[(at - ADDR) as usize],
            ERASE_SIZE => self.erase_shift,
            WRITE_SIZE => self.write_shift,
            a if a < ADDR => self.buffer.get(a as usize).copied().unwrap_or(0),
            _ => 0,
        }
    }

    /// A write of `n` bytes of `v` at `addr` in flash access mode.
    pub fn write(&mut self, addr: u16, n: usize, v: u64) {
        for i in 0..n.min(8) {
            self.put(addr.wrapping_add(i as u16), (v >> (8 * i)) as u8);
        }
    }

    fn put(&mut self, at: u16, b: u8) {
        match at {
            ADDR..=0x8003 => {
                let mut a = self.addr.to_le_bytes();
                a[(at - ADDR) as usize] = b;
                self.addr = u32::from_le_bytes(a);
            }
            COMMAND => self.command(b),
            a if a < ADDR => {
                if let Some(slot) = self.buffer.get_mut(a as usize) {
                    *slot = b;
                }
            }
            _ => {}
        }
    }

    fn command(&mut self, c: u8) {
        let at = self.addr as usize;
        let len = match c {
            ERASE => 1usize << self.erase_shift,
            WRITE => 1usize << self.write_shift,
            _ => {
                self.lost = true;
                return;
            }
        };
        // Both act on whole aligned blocks inside the flash.
        let Some(block) = self
            .bytes
            .get_mut(at..at.saturating_add(len))
            .filter(|_| at % len == 0)
        else {
            self.lost = true;
            return;
        };
        self.lost = false;
        if c == ERASE {
            block.fill(0xFF);
            self.erases += 1;
        } else {
            // Programming only clears bits, as NOR flash does.
            for (f, b) in block.iter_mut().zip(&self.buffer) {
                *f &= *b;
            }
            self.buffer.fill(0xFF);
            self.writes += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erase_then_write_a_chunk() {
        let mut f = SimFlash::new(12, 10, 6);
        assert_eq!(f.read(ERASE_SIZE, 1), 10);
        assert_eq!(f.read(WRITE_SIZE, 1), 6);
        f.bytes[1024] = 0;
        f.write(ADDR, 4, 1024);
        f.write(COMMAND, 1, ERASE as u64);
        assert_eq!(f.bytes[1024], 0xFF);
        f.write(8, 8, 0x0102_0304_0506_0708);
        f.write(ADDR, 4, 1024 + 64);
        f.write(COMMAND, 1, WRITE as u64);
        assert_eq!(
            f.bytes[1024 + 64 + 8..1024 + 64 + 16],
            [8, 7, 6, 5, 4, 3, 2, 1]
        );
        assert_eq!((f.erases, f.writes, f.cookie()), (1, 1, COOKIE));
        // Past the end: out of step.
        f.write(ADDR, 4, 1 << 12);
        f.write(COMMAND, 1, ERASE as u64);
        assert_eq!(f.cookie(), 0);
    }
}
