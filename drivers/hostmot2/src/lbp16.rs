//! LBP16, the protocol Mesa's Ethernet cards speak over UDP
//! (hostmot2-more.md 1.3, 1.4): the command word, the memory spaces and
//! their addresses, building request datagrams without allocating, and
//! parsing them (the simulator's side).
//!
//! A request datagram holds commands back to back: a 16-bit command word,
//! a 16-bit address, and for writes the data. Everything is
//! little-endian. The board answers a datagram that has reads with one
//! datagram holding the data of every read in order and nothing else; a
//! datagram of writes only gets no answer.

/// The UDP port every board listens on.
pub const UDP_PORT: u16 = 27181;
/// Largest request or write datagram the driver builds (LinuxCNC's
/// buffer size, well below an Ethernet frame).
pub const MAX_REQUEST: usize = 1400;
/// Largest reply the driver accepts: one unfragmented UDP payload on a
/// 1500-byte Ethernet link.
pub const MAX_REPLY: usize = 1472;
/// Most transfers one command moves.
pub const MAX_COUNT: usize = 127;

/// Command word bits.
pub mod bits {
    /// 1 = write, 0 = read.
    pub const WRITE: u16 = 0x8000;
    /// A 16-bit address word follows the command.
    pub const ADDRESS: u16 = 0x4000;
    /// Access the space's info area instead of its memory.
    pub const INFO: u16 = 0x2000;
    /// Memory space field shift (bits 12..10).
    pub const SPACE_SHIFT: u16 = 10;
    /// Memory space field mask, shifted down.
    pub const SPACE_MASK: u16 = 0x7;
    /// Transfer size field shift (bits 9..8).
    pub const SIZE_SHIFT: u16 = 8;
    /// Address auto-increment.
    pub const INCREMENT: u16 = 0x0080;
    /// Transfer count mask (bits 6..0).
    pub const COUNT_MASK: u16 = 0x007F;
}

/// The memory spaces.
pub mod space {
    /// The HostMot2 register file (32-bit, 64 KiB).
    pub const HM2: u8 = 0;
    /// The Ethernet controller's registers.
    pub const ETH_CHIP: u8 = 1;
    /// The configuration EEPROM (MAC, IP, name).
    pub const ETH_EEPROM: u8 = 2;
    /// A window on the FPGA configuration flash.
    pub const FPGA_FLASH: u8 = 3;
    /// LBP timers and the scratch words hm2_eth tags its datagrams with.
    pub const TIMER: u8 = 4;
    /// LBP16 control and status: counters, write enable, reset.
    pub const COMM_CTRL: u8 = 6;
    /// Board identification: name, protocol and firmware versions.
    pub const BOARD_INFO: u8 = 7;
}

/// Addresses inside the spaces (byte addresses, 16-bit words unless said).
pub mod addr {
    /// Space 2: MAC address, low, middle, high word.
    pub const EEPROM_MAC: u16 = 0x02;
    /// Space 2: board name, 16 bytes.
    pub const EEPROM_NAME: u16 = 0x10;
    /// Space 2: IP address, low word then high word.
    pub const EEPROM_IP: u16 = 0x20;
    /// Space 2: LED mode.
    pub const EEPROM_LED_MODE: u16 = 0x28;
    /// Space 3: flash address (32-bit).
    pub const FLASH_ADDRESS: u16 = 0x00;
    /// Space 3: flash data (32-bit).
    pub const FLASH_DATA: u16 = 0x04;
    /// Space 3: flash ID (32-bit; low byte 0x10..0x15 = 1..32 Mbit).
    pub const FLASH_ID: u16 = 0x08;
    /// Space 3: sector erase (32-bit).
    pub const FLASH_ERASE: u16 = 0x0C;
    /// Space 4: microsecond time stamp.
    pub const TIMER_US: u16 = 0x00;
    /// Space 4: the read tag hm2_eth writes and reads back (32-bit as
    /// two 16-bit words).
    pub const TIMER_READ_TAG: u16 = 0x10;
    /// Space 4: the write tag hm2_eth writes with every write datagram.
    pub const TIMER_WRITE_TAG: u16 = 0x14;
    /// Space 6: error flags.
    pub const CTRL_ERRORS: u16 = 0x00;
    /// Space 6: parse errors.
    pub const CTRL_PARSE_ERRORS: u16 = 0x02;
    /// Space 6: memory errors.
    pub const CTRL_MEM_ERRORS: u16 = 0x04;
    /// Space 6: write errors.
    pub const CTRL_WRITE_ERRORS: u16 = 0x06;
    /// Space 6: packets received.
    pub const CTRL_RX_PACKETS: u16 = 0x08;
    /// Space 6: UDP packets received.
    pub const CTRL_RX_UDP: u16 = 0x0A;
    /// Space 6: bad packets received.
    pub const CTRL_RX_BAD: u16 = 0x0C;
    /// Space 6: packets sent.
    pub const CTRL_TX_PACKETS: u16 = 0x0E;
    /// Space 6: UDP packets sent.
    pub const CTRL_TX_UDP: u16 = 0x10;
    /// Space 6: bad packets sent.
    pub const CTRL_TX_BAD: u16 = 0x12;
    /// Space 6: LED mode (0 = HostMot2 drives the LEDs).
    pub const CTRL_LED_MODE: u16 = 0x14;
    /// Space 6: debug LED pointer.
    pub const CTRL_DEBUG_LED: u16 = 0x16;
    /// Space 6: scratch word (the driver tags its single reads with it).
    pub const CTRL_SCRATCH: u16 = 0x18;
    /// Space 6: write enable (0x5A02 EEPROM, 0x5A03 flash), for the rest
    /// of the datagram.
    pub const CTRL_WRITE_ENABLE: u16 = 0x1A;
    /// Space 6: firmware reset (any non-zero value).
    pub const CTRL_RESET: u16 = 0x1C;
    /// Space 6: FPGA configuration port (reload).
    pub const CTRL_CONFIG: u16 = 0x1E;
    /// Space 7: board name, 16 ASCII bytes, NUL-padded.
    pub const INFO_NAME: u16 = 0x00;
    /// Space 7: LBP16 protocol version.
    pub const INFO_LBP16_VERSION: u16 = 0x10;
    /// Space 7: Ethernet firmware version.
    pub const INFO_FW_VERSION: u16 = 0x12;
    /// Space 7: IP address jumpers at boot.
    pub const INFO_IP_JUMPERS: u16 = 0x14;
}

/// Write-enable values for space 6 0x1A.
pub mod enable {
    /// Enables EEPROM writes.
    pub const EEPROM: u16 = 0x5A02;
    /// Enables flash writes and erases.
    pub const FLASH: u16 = 0x5A03;
}

/// The size of one transfer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Width {
    /// 8 bits.
    W8,
    /// 16 bits.
    W16,
    /// 32 bits.
    W32,
    /// 64 bits (no tool uses it).
    W64,
}

impl Width {
    /// Bytes per transfer.
    pub const fn bytes(self) -> usize {
        match self {
            Width::W8 => 1,
            Width::W16 => 2,
            Width::W32 => 4,
            Width::W64 => 8,
        }
    }

    const fn code(self) -> u16 {
        match self {
            Width::W8 => 0,
            Width::W16 => 1,
            Width::W32 => 2,
            Width::W64 => 3,
        }
    }

    const fn from_code(c: u16) -> Width {
        match c & 3 {
            0 => Width::W8,
            1 => Width::W16,
            2 => Width::W32,
            _ => Width::W64,
        }
    }
}

/// One command's word, decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Command {
    /// A write (else a read).
    pub write: bool,
    /// An address word follows.
    pub has_address: bool,
    /// The space's info area instead of its memory.
    pub info: bool,
    /// The memory space, 0..7.
    pub space: u8,
    /// Transfer size.
    pub width: Width,
    /// The address increments after each transfer.
    pub increment: bool,
    /// Transfers, 0..127.
    pub count: u8,
}

impl Command {
    /// A read of `count` transfers with an address and auto-increment.
    pub const fn read(space: u8, width: Width, count: u8) -> Command {
        Command {
            write: false,
            has_address: true,
            info: false,
            space,
            width,
            increment: true,
            count,
        }
    }

    /// A write of `count` transfers with an address and auto-increment.
    pub const fn write(space: u8, width: Width, count: u8) -> Command {
        Command {
            write: true,
            ..Command::read(space, width, count)
        }
    }

    /// The command word.
    pub const fn word(&self) -> u16 {
        (if self.write { bits::WRITE } else { 0 })
            | (if self.has_address { bits::ADDRESS } else { 0 })
            | (if self.info { bits::INFO } else { 0 })
            | ((self.space as u16 & bits::SPACE_MASK) << bits::SPACE_SHIFT)
            | (self.width.code() << bits::SIZE_SHIFT)
            | (if self.increment { bits::INCREMENT } else { 0 })
            | (self.count as u16 & bits::COUNT_MASK)
    }

    /// Decodes a command word.
    pub const fn from_word(w: u16) -> Command {
        Command {
            write: w & bits::WRITE != 0,
            has_address: w & bits::ADDRESS != 0,
            info: w & bits::INFO != 0,
            space: ((w >> bits::SPACE_SHIFT) & bits::SPACE_MASK) as u8,
            width: Width::from_code(w >> bits::SIZE_SHIFT),
            increment: w & bits::INCREMENT != 0,
            count: (w & bits::COUNT_MASK) as u8,
        }
    }

    /// Bytes of data this command moves.
    pub const fn data_len(&self) -> usize {
        self.count as usize * self.width.bytes()
    }
}

/// A datagram did not fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Full;

/// A request datagram being built in a fixed buffer: pushing never
/// allocates, so it is usable in realtime functions. It also counts the
/// bytes the board's reply will have.
#[derive(Clone)]
pub struct Request {
    buf: [u8; MAX_REQUEST],
    len: usize,
    reply: usize,
}

impl Default for Request {
    fn default() -> Request {
        Request::new()
    }
}

impl std::fmt::Debug for Request {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Request")
            .field("bytes", &self.bytes())
            .field("reply", &self.reply)
            .finish()
    }
}

impl Request {
    /// An empty request.
    pub const fn new() -> Request {
        Request {
            buf: [0; MAX_REQUEST],
            len: 0,
            reply: 0,
        }
    }

    /// Empties it.
    #[inline]
    pub fn clear(&mut self) {
        self.len = 0;
        self.reply = 0;
    }

    /// The datagram so far.
    #[inline]
    pub fn bytes(&self) -> &[u8] {
        &self.buf[..self.len]
    }

    /// Whether nothing was pushed.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Bytes of the reply the board will send.
    #[inline]
    pub fn reply_len(&self) -> usize {
        self.reply
    }

    /// Marks the current length, to undo pushes with [`truncate`](Self::truncate).
    #[inline]
    pub fn mark(&self) -> (usize, usize) {
        (self.len, self.reply)
    }

    /// Goes back to a [`mark`](Self::mark).
    #[inline]
    pub fn truncate(&mut self, mark: (usize, usize)) {
        self.len = mark.0.min(self.len);
        self.reply = mark.1.min(self.reply);
    }

    #[inline]
    fn put(&mut self, bytes: &[u8]) {
        self.buf[self.len..self.len + bytes.len()].copy_from_slice(bytes);
        self.len += bytes.len();
    }

    /// Appends a read command of `cmd.count` transfers at `addr`.
    pub fn push_read(&mut self, cmd: Command, addr: u16) -> Result<(), Full> {
        let cmd = Command {
            write: false,
            ..cmd
        };
        let header = if cmd.has_address { 4 } else { 2 };
        if self.len + header > MAX_REQUEST || self.reply + cmd.data_len() > MAX_REPLY {
            return Err(Full);
        }
        self.put(&cmd.word().to_le_bytes());
        if cmd.has_address {
            self.put(&addr.to_le_bytes());
        }
        self.reply += cmd.data_len();
        Ok(())
    }

    /// Appends a write command whose data is `data` (its length must be
    /// `cmd.count` transfers).
    pub fn push_write(&mut self, cmd: Command, addr: u16, data: &[u8]) -> Result<(), Full> {
        let cmd = Command { write: true, ..cmd };
        debug_assert_eq!(data.len(), cmd.data_len());
        let header = if cmd.has_address { 4 } else { 2 };
        if self.len + header + data.len() > MAX_REQUEST {
            return Err(Full);
        }
        self.put(&cmd.word().to_le_bytes());
        if cmd.has_address {
            self.put(&addr.to_le_bytes());
        }
        self.put(data);
        Ok(())
    }

    /// Appends reads of `words` HostMot2 registers from `addr`, split
    /// into commands of at most 127 words. All or nothing.
    pub fn hm2_read(&mut self, addr: u32, words: usize) -> Result<(), Full> {
        let mark = self.mark();
        let mut at = addr;
        let mut left = words;
        while left > 0 {
            let n = left.min(MAX_COUNT);
            let r = self.push_read(Command::read(space::HM2, Width::W32, n as u8), at as u16);
            if r.is_err() {
                self.truncate(mark);
                return r;
            }
            at += 4 * n as u32;
            left -= n;
        }
        Ok(())
    }

    /// Appends writes of `data` to HostMot2 registers from `addr`, split
    /// into commands of at most 127 words. All or nothing.
    pub fn hm2_write(&mut self, addr: u32, data: &[u32]) -> Result<(), Full> {
        let mark = self.mark();
        let mut at = addr;
        for chunk in data.chunks(MAX_COUNT) {
            let cmd = Command::write(space::HM2, Width::W32, chunk.len() as u8);
            let header = 4;
            if self.len + header + 4 * chunk.len() > MAX_REQUEST {
                self.truncate(mark);
                return Err(Full);
            }
            self.put(&cmd.word().to_le_bytes());
            self.put(&(at as u16).to_le_bytes());
            for w in chunk {
                self.put(&w.to_le_bytes());
            }
            at += 4 * chunk.len() as u32;
        }
        Ok(())
    }

    /// Appends a write of 16-bit words to `space` at `addr`.
    pub fn write16(&mut self, space: u8, addr: u16, words: &[u16]) -> Result<(), Full> {
        let mut data = [0u8; 2 * MAX_COUNT];
        let n = words.len().min(MAX_COUNT);
        for (i, w) in words[..n].iter().enumerate() {
            data[2 * i..2 * i + 2].copy_from_slice(&w.to_le_bytes());
        }
        self.push_write(
            Command::write(space, Width::W16, n as u8),
            addr,
            &data[..2 * n],
        )
    }

    /// Appends a read of `count` 16-bit words from `space` at `addr`.
    pub fn read16(&mut self, space: u8, addr: u16, count: u8) -> Result<(), Full> {
        self.push_read(Command::read(space, Width::W16, count), addr)
    }
}

/// Why a request datagram cannot be parsed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParseError {
    /// The datagram ends inside a command word or address.
    Truncated {
        /// Byte offset of the command.
        at: usize,
    },
    /// A command without the address bit (its meaning is unknown).
    NoAddress {
        /// Byte offset of the command.
        at: usize,
    },
    /// A write whose data goes past the end of the datagram.
    DataTruncated {
        /// Byte offset of the command.
        at: usize,
        /// Data bytes the command needs.
        needed: usize,
        /// Bytes left.
        left: usize,
    },
}

impl std::fmt::Display for ParseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ParseError::Truncated { at } => {
                write!(f, "datagram ends inside the command at byte {at}")
            }
            ParseError::NoAddress { at } => {
                write!(f, "command at byte {at} has no address word")
            }
            ParseError::DataTruncated { at, needed, left } => write!(
                f,
                "write at byte {at} needs {needed} data bytes, {left} left"
            ),
        }
    }
}

/// One parsed command of a request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Parsed<'a> {
    /// The command.
    pub cmd: Command,
    /// Its address.
    pub addr: u16,
    /// A write's data (empty for reads).
    pub data: &'a [u8],
}

/// The commands of a request datagram, in order.
#[derive(Debug, Clone)]
pub struct Commands<'a> {
    bytes: &'a [u8],
    at: usize,
    failed: bool,
}

/// Parses a request datagram.
pub fn parse(bytes: &[u8]) -> Commands<'_> {
    Commands {
        bytes,
        at: 0,
        failed: false,
    }
}

impl<'a> Iterator for Commands<'a> {
    type Item = Result<Parsed<'a>, ParseError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed || self.at >= self.bytes.len() {
            return None;
        }
        let at = self.at;
        let rest = &self.bytes[at..];
        let fail = |s: &mut Self, e| {
            s.failed = true;
            Some(Err(e))
        };
        if rest.len() < 2 {
            return fail(self, ParseError::Truncated { at });
        }
        let cmd = Command::from_word(u16::from_le_bytes([rest[0], rest[1]]));
        if !cmd.has_address {
            return fail(self, ParseError::NoAddress { at });
        }
        if rest.len() < 4 {
            return fail(self, ParseError::Truncated { at });
        }
        let addr = u16::from_le_bytes([rest[2], rest[3]]);
        let mut used = 4;
        let data = if cmd.write {
            let needed = cmd.data_len();
            let left = rest.len() - 4;
            if left < needed {
                return fail(self, ParseError::DataTruncated { at, needed, left });
            }
            used += needed;
            &rest[4..4 + needed]
        } else {
            &rest[..0]
        };
        self.at += used;
        Some(Ok(Parsed { cmd, addr, data }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn command_words_match_the_documented_examples() {
        // "read 8 bytes at 0x104" is 82 42 04 01 on the wire.
        let c = Command::read(space::HM2, Width::W32, 2);
        assert_eq!(c.word().to_le_bytes(), [0x82, 0x42]);
        // The MAC read: 0x4983, space 2, 16-bit, 3 words.
        assert_eq!(
            Command::read(space::ETH_EEPROM, Width::W16, 3).word(),
            0x4983
        );
        // The name probe: 0x5D88, space 7, 16-bit, 8 words.
        assert_eq!(
            Command::read(space::BOARD_INFO, Width::W16, 8).word(),
            0x5D88
        );
        // hm2_eth's bookkeeping: 0x5901, 0xD182, 0x5184.
        assert_eq!(
            Command::read(space::COMM_CTRL, Width::W16, 1).word() & !bits::INCREMENT,
            0x5901
        );
        assert_eq!(Command::write(space::TIMER, Width::W16, 2).word(), 0xD182);
        assert_eq!(Command::read(space::TIMER, Width::W16, 4).word(), 0x5184);
        for w in [0x4983u16, 0x5D88, 0xD182, 0x2C01, 0xCE40, 0x0000, 0xFFFF] {
            assert_eq!(Command::from_word(w).word(), w);
        }
    }

    #[test]
    fn requests_split_long_regions_and_count_the_reply() {
        let mut r = Request::new();
        r.hm2_read(0x1000, 300).unwrap();
        let cmds: Vec<_> = parse(r.bytes()).map(Result::unwrap).collect();
        assert_eq!(cmds.len(), 3);
        assert_eq!((cmds[0].addr, cmds[0].cmd.count), (0x1000, 127));
        assert_eq!((cmds[1].addr, cmds[1].cmd.count), (0x1000 + 508, 127));
        assert_eq!(cmds[2].cmd.count, 46);
        assert_eq!(r.reply_len(), 1200);
        // A reply that would not fit one frame is refused, all or nothing.
        let before = r.mark();
        assert_eq!(r.hm2_read(0x2000, 100), Err(Full));
        assert_eq!(r.mark(), before);

        let mut w = Request::new();
        w.hm2_write(0x0C00, &[0x5A00_0000]).unwrap();
        assert_eq!(w.bytes(), &[0x81, 0xC2, 0x00, 0x0C, 0x00, 0x00, 0x00, 0x5A]);
        assert_eq!(w.reply_len(), 0);
        let data: Vec<u32> = (0..400).collect();
        assert_eq!(w.hm2_write(0x1000, &data), Err(Full), "over 1400 bytes");
        assert_eq!(w.bytes().len(), 8);
    }

    #[test]
    fn parse_refuses_what_it_cannot_read() {
        fn p(b: &[u8]) -> Vec<Result<Parsed<'_>, ParseError>> {
            parse(b).collect()
        }
        assert_eq!(p(&[0x82]), vec![Err(ParseError::Truncated { at: 0 })]);
        assert_eq!(
            p(&[0x82, 0x02, 0, 0]),
            vec![Err(ParseError::NoAddress { at: 0 })]
        );
        assert_eq!(
            p(&[0x82, 0x42, 0x00]),
            vec![Err(ParseError::Truncated { at: 0 })]
        );
        let v = p(&[0x81, 0xC2, 0x00, 0x0C, 1, 2]);
        assert_eq!(
            v,
            vec![Err(ParseError::DataTruncated {
                at: 0,
                needed: 4,
                left: 2
            })]
        );
        // A good command before a bad one is still given.
        let v = p(&[0x81, 0x42, 0x00, 0x01, 0xFF]);
        assert!(v[0].is_ok());
        assert_eq!(v[1], Err(ParseError::Truncated { at: 4 }));
        assert!(p(&[]).is_empty());
    }
}
