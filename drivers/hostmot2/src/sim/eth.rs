//! The Ethernet face of a simulated board: the LBP16 memory spaces around
//! a HostMot2 model (hostmot2-more.md 1.4 and 5), answering request
//! datagrams as a Mesa Ethernet card does.
//!
//! * Space 0 is the [`Hm2Model`]'s register window (32-bit accesses).
//! * Space 2 is the EEPROM (MAC, IP, name, LED mode); writes need 0x5A02
//!   written to space 6 0x1A earlier in the same datagram.
//! * Space 3 is the flash window: its ID reads back, pages read erased;
//!   writes need 0x5A03 and are counted, not stored.
//! * Space 4 holds the microsecond stamp and the scratch words that
//!   hm2_eth tags its datagrams with (they read back what was written).
//! * Space 6 counts packets and errors, takes the write enable and the
//!   reset (which makes the watchdog bite), and has a scratch word.
//! * Space 7 is the board's name and versions.
//! * Every space but 1 and 5 has an info area.
//!
//! Time: a datagram that writes the read tag (space 4 0x10) is a cycle's
//! read request; with [`EthBoard::with_period`] the board lets one period
//! of simulated time pass before answering it, so a run over the network
//! is as repeatable as one on the PCI simulator. With
//! [`EthBoard::with_wall_clock`] the host's time passes instead. Without
//! either the caller moves time ([`EthBoard::model`]).
//!
//! A datagram that cannot be parsed is counted (space 6 parse errors,
//! bad packets) and gets no answer, like a wrong-length reply the driver
//! would refuse anyway; accesses the board cannot do (a width a space
//! does not have, a space without memory) are counted as memory errors
//! and read as zero.

use super::{boards, machine, Hm2Model};
use crate::image::FirmwareSpec;
use crate::lbp16::{self, addr, enable, space, Command, Width};

/// Bytes of the EEPROM space.
const EEPROM_BYTES: usize = 0x40;
/// Bytes of the timer space.
const TIMER_BYTES: usize = 0x18;
/// Bytes of the control space.
const CTRL_BYTES: usize = 0x20;
/// Bytes of the board-info space.
const INFO_BYTES: usize = 0x16;

/// How a board identifies itself on the network.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EthIdentity {
    /// Space-7 name (`7I96S`, `7I76E-16`), at most 16 bytes.
    pub name: String,
    /// MAC address.
    pub mac: [u8; 6],
    /// IP address in the EEPROM.
    pub ip: [u8; 4],
    /// Flash ID low byte (0x14 = 16 Mbit).
    pub flash_id: u8,
}

impl EthIdentity {
    /// A board named `name` with the default address 192.168.1.121 and a
    /// MAC of Mesa's range.
    pub fn new(name: &str) -> EthIdentity {
        EthIdentity {
            name: name.to_string(),
            mac: [0x00, 0x60, 0x1B, 0x16, 0x00, 0x01],
            ip: [192, 168, 1, 121],
            flash_id: 0x14,
        }
    }
}

/// Ethernet preset `name` ([`boards::ETH_PRESETS`]) running `spec` (its
/// firmware, perhaps with other remotes plugged in), wired to its machine
/// ([`machine::preset`]), named as the card names itself (`7I93`) and
/// holding `ip` in its EEPROM; `None` when `name` is not an Ethernet
/// preset. Time moves only when the caller moves it.
pub fn preset_board(name: &str, spec: FirmwareSpec, ip: [u8; 4]) -> Option<EthBoard> {
    let space7 = boards::eth_name(name)?;
    let model = Hm2Model::with_world(spec, Box::new(machine::preset(name)));
    let identity = EthIdentity {
        ip,
        ..EthIdentity::new(space7)
    };
    Some(EthBoard::new(model, identity))
}

/// A simulated Ethernet board.
pub struct EthBoard {
    model: Hm2Model,
    identity: EthIdentity,
    eeprom: [u8; EEPROM_BYTES],
    timers: [u8; TIMER_BYTES],
    ctrl: [u8; CTRL_BYTES],
    info: [u8; INFO_BYTES],
    flash_address: u32,
    period_ns: Option<u64>,
    /// With a wall clock: when the last datagram came.
    wall: Option<Option<std::time::Instant>>,
    cycles: u64,
    resets: u64,
    /// The write enable of the datagram being executed.
    write_enable: u16,
    /// The datagrams received, when recording.
    recorded: Option<Vec<Vec<u8>>>,
}

impl std::fmt::Debug for EthBoard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EthBoard")
            .field("name", &self.identity.name)
            .field("cycles", &self.cycles)
            .finish()
    }
}

impl EthBoard {
    /// A board serving `model` as `identity`; time moves only when the
    /// caller moves it.
    pub fn new(model: Hm2Model, identity: EthIdentity) -> EthBoard {
        let mut eeprom = [0u8; EEPROM_BYTES];
        // The MAC as three little-endian words, low word first.
        let m = identity.mac;
        for (k, word) in [[m[5], m[4]], [m[3], m[2]], [m[1], m[0]]]
            .iter()
            .enumerate()
        {
            let at = addr::EEPROM_MAC as usize + 2 * k;
            eeprom[at..at + 2].copy_from_slice(word);
        }
        let name = identity.name.as_bytes();
        let n = name.len().min(16);
        eeprom[addr::EEPROM_NAME as usize..][..n].copy_from_slice(&name[..n]);
        let ip = identity.ip;
        let ip_word = u32::from_be_bytes(ip);
        eeprom[addr::EEPROM_IP as usize..][..4].copy_from_slice(&ip_word.to_le_bytes());
        let mut info = [0u8; INFO_BYTES];
        info[..n].copy_from_slice(&name[..n]);
        info[addr::INFO_LBP16_VERSION as usize..][..2].copy_from_slice(&3u16.to_le_bytes());
        info[addr::INFO_FW_VERSION as usize..][..2].copy_from_slice(&16u16.to_le_bytes());
        info[addr::INFO_IP_JUMPERS as usize..][..2].copy_from_slice(&1u16.to_le_bytes());
        EthBoard {
            model,
            identity,
            eeprom,
            timers: [0; TIMER_BYTES],
            ctrl: [0; CTRL_BYTES],
            info,
            flash_address: 0,
            period_ns: None,
            wall: None,
            cycles: 0,
            resets: 0,
            write_enable: 0,
            recorded: None,
        }
    }

    /// Lets `period_ns` of simulated time pass before each cycle's read
    /// request is answered.
    pub fn with_period(mut self, period_ns: u64) -> EthBoard {
        self.period_ns = Some(period_ns);
        self
    }

    /// Lets `period_ns` of simulated time pass before each later cycle's
    /// read request is answered (the driver's thread period, once known).
    pub fn set_period(&mut self, period_ns: u64) {
        if self.wall.is_none() {
            self.period_ns = Some(period_ns);
        }
    }

    /// Lets the host's time pass: before each datagram, the time since
    /// the previous one (for interactive use; runs are not repeatable).
    pub fn with_wall_clock(mut self) -> EthBoard {
        self.wall = Some(None);
        self.period_ns = None;
        self
    }

    /// The HostMot2 model.
    pub fn model(&mut self) -> &mut Hm2Model {
        &mut self.model
    }

    /// How the board identifies itself.
    pub fn identity(&self) -> &EthIdentity {
        &self.identity
    }

    /// Starts (or stops) keeping every datagram received.
    pub fn record(&mut self, on: bool) {
        self.recorded = on.then(Vec::new);
    }

    /// The datagrams kept since recording started, emptied.
    pub fn take_recorded(&mut self) -> Vec<Vec<u8>> {
        self.recorded
            .as_mut()
            .map(std::mem::take)
            .unwrap_or_default()
    }

    /// Read requests of cycles seen (datagrams writing the read tag).
    pub fn cycles(&self) -> u64 {
        self.cycles
    }

    /// Firmware resets asked through space 6.
    pub fn resets(&self) -> u64 {
        self.resets
    }

    /// A space-6 counter.
    pub fn counter(&self, at: u16) -> u16 {
        u16::from_le_bytes([self.ctrl[at as usize], self.ctrl[at as usize + 1]])
    }

    fn bump(&mut self, at: u16) {
        let v = self.counter(at).wrapping_add(1);
        self.ctrl[at as usize..at as usize + 2].copy_from_slice(&v.to_le_bytes());
    }

    /// Executes one request datagram. Returns the reply to send, if any
    /// (into `reply`, which is cleared first).
    pub fn handle(&mut self, datagram: &[u8], reply: &mut Vec<u8>) -> bool {
        reply.clear();
        if let Some(r) = &mut self.recorded {
            if r.len() < 100_000 {
                r.push(datagram.to_vec());
            }
        }
        self.bump(addr::CTRL_RX_PACKETS);
        self.bump(addr::CTRL_RX_UDP);
        // Parse everything first: a malformed datagram does nothing.
        let mut cycle = false;
        let mut reads = false;
        for c in lbp16::parse(datagram) {
            match c {
                Ok(p) => {
                    reads |= !p.cmd.write && p.cmd.count > 0;
                    cycle |= p.cmd.write
                        && !p.cmd.info
                        && p.cmd.space == space::TIMER
                        && p.addr == addr::TIMER_READ_TAG;
                }
                Err(_) => {
                    self.bump(addr::CTRL_PARSE_ERRORS);
                    self.bump(addr::CTRL_RX_BAD);
                    return false;
                }
            }
        }
        if let Some(last) = &mut self.wall {
            let now = std::time::Instant::now();
            if let Some(then) = last.replace(now) {
                self.model.advance((now - then).as_nanos() as u64);
            }
        }
        if cycle {
            self.cycles += 1;
            if let Some(p) = self.period_ns {
                self.model.advance(p);
            }
        }
        self.write_enable = 0;
        for p in lbp16::parse(datagram).flatten() {
            self.execute(p.cmd, p.addr, p.data, reply);
        }
        self.write_enable = 0;
        if reads {
            self.bump(addr::CTRL_TX_PACKETS);
            self.bump(addr::CTRL_TX_UDP);
        }
        reads
    }

    fn execute(&mut self, cmd: Command, at: u16, data: &[u8], reply: &mut Vec<u8>) {
        let w = cmd.width.bytes();
        for i in 0..cmd.count as usize {
            let a = if cmd.increment {
                at.wrapping_add((i * w) as u16)
            } else {
                at
            };
            if cmd.write {
                let mut v = [0u8; 8];
                v[..w].copy_from_slice(&data[i * w..(i + 1) * w]);
                self.write(cmd, a, u64::from_le_bytes(v));
            } else {
                let v = self.read(cmd, a);
                reply.extend_from_slice(&v.to_le_bytes()[..w]);
            }
        }
    }

    fn mem_error(&mut self) {
        self.bump(addr::CTRL_MEM_ERRORS);
    }

    /// Little-endian bytes of a byte-addressed memory.
    fn bytes_at(mem: &[u8], at: u16, w: usize) -> Option<u64> {
        let at = at as usize;
        let b = mem.get(at..at + w)?;
        let mut v = [0u8; 8];
        v[..w].copy_from_slice(b);
        Some(u64::from_le_bytes(v))
    }

    fn read(&mut self, cmd: Command, at: u16) -> u64 {
        let w = cmd.width.bytes();
        if cmd.info {
            return match self.info_area(cmd.space) {
                Some(area) => Self::bytes_at(&area, at, w).unwrap_or_else(|| {
                    self.mem_error();
                    0
                }),
                None => {
                    self.mem_error();
                    0
                }
            };
        }
        let v = match cmd.space {
            space::HM2 if cmd.width == Width::W32 && at % 4 == 0 => {
                Some(self.model.read32(at as usize) as u64)
            }
            space::ETH_EEPROM => Self::bytes_at(&self.eeprom, at, w),
            space::FPGA_FLASH if cmd.width == Width::W32 => match at {
                addr::FLASH_ADDRESS => Some(self.flash_address as u64),
                addr::FLASH_DATA => Some(0xFFFF_FFFF),
                addr::FLASH_ID => Some(self.identity.flash_id as u64),
                addr::FLASH_ERASE => Some(0),
                _ => None,
            },
            space::TIMER => {
                let us = (self.model.now_ns() / 1000) as u16;
                self.timers[..2].copy_from_slice(&us.to_le_bytes());
                Self::bytes_at(&self.timers, at, w)
            }
            space::COMM_CTRL => Self::bytes_at(&self.ctrl, at, w),
            space::BOARD_INFO => Self::bytes_at(&self.info, at, w),
            _ => None,
        };
        v.unwrap_or_else(|| {
            self.mem_error();
            0
        })
    }

    fn put_bytes(mem: &mut [u8], at: u16, w: usize, v: u64) -> bool {
        let at = at as usize;
        match mem.get_mut(at..at + w) {
            Some(b) => {
                b.copy_from_slice(&v.to_le_bytes()[..w]);
                true
            }
            None => false,
        }
    }

    fn write(&mut self, cmd: Command, at: u16, v: u64) {
        let w = cmd.width.bytes();
        if cmd.info {
            self.bump(addr::CTRL_WRITE_ERRORS);
            return;
        }
        let ok = match cmd.space {
            space::HM2 if cmd.width == Width::W32 && at % 4 == 0 => {
                self.model.write32(at as usize, v as u32);
                true
            }
            space::ETH_EEPROM => {
                if self.write_enable != enable::EEPROM {
                    self.bump(addr::CTRL_WRITE_ERRORS);
                    return;
                }
                Self::put_bytes(&mut self.eeprom, at, w, v)
            }
            space::FPGA_FLASH if cmd.width == Width::W32 => match at {
                addr::FLASH_ADDRESS => {
                    self.flash_address = v as u32;
                    true
                }
                addr::FLASH_DATA | addr::FLASH_ERASE => {
                    if self.write_enable != enable::FLASH {
                        self.bump(addr::CTRL_WRITE_ERRORS);
                    }
                    true
                }
                _ => false,
            },
            // The time stamp is read-only; the rest is scratch.
            space::TIMER if at >= 2 => Self::put_bytes(&mut self.timers, at, w, v),
            space::COMM_CTRL => match at {
                addr::CTRL_WRITE_ENABLE => {
                    self.write_enable = v as u16;
                    true
                }
                addr::CTRL_RESET => {
                    if v != 0 {
                        self.reset();
                    }
                    true
                }
                addr::CTRL_CONFIG => true,
                addr::CTRL_LED_MODE..=addr::CTRL_SCRATCH => {
                    Self::put_bytes(&mut self.ctrl, at, w, v)
                }
                _ => {
                    self.bump(addr::CTRL_WRITE_ERRORS);
                    return;
                }
            },
            _ => false,
        };
        if !ok {
            self.mem_error();
        }
    }

    /// A firmware reset: the watchdog bites, so every output is released.
    fn reset(&mut self) {
        self.resets += 1;
        self.model.write32(0x0C00, 0);
        self.model.advance(1000);
    }

    /// The info area of `space`: cookie, memory size and kind, ranges,
    /// address pointer, 8-character name.
    fn info_area(&self, space: u8) -> Option<[u8; 16]> {
        // (writable, type, widths, log2 size, log2 page, log2 erase, name)
        let (writable, kind, widths, size, page, erase, name): (
            bool,
            u16,
            u16,
            u16,
            u16,
            u16,
            &[u8; 8],
        ) = match space {
            space::HM2 => (true, 0x01, 0b0100, 16, 0, 0, b"HostMot2"),
            space::ETH_EEPROM => (true, 0x0E, 0b0010, 7, 4, 0, b"EEPROM  "),
            space::FPGA_FLASH => (true, 0x0F, 0b0100, 21, 8, 16, b"FPGAFLSH"),
            space::TIMER => (true, 0x01, 0b0010, 5, 0, 0, b"Timers  "),
            space::COMM_CTRL => (true, 0x01, 0b0010, 5, 0, 0, b"LBPCtrl "),
            space::BOARD_INFO => (false, 0x01, 0b0010, 5, 0, 0, b"BoardID "),
            _ => return None,
        };
        let mut a = [0u8; 16];
        a[0..2].copy_from_slice(&(0x5A00 | space as u16).to_le_bytes());
        let memsize = (if writable { 0x8000 } else { 0 }) | kind << 8 | widths;
        a[2..4].copy_from_slice(&memsize.to_le_bytes());
        let ranges = erase << 11 | page << 6 | size;
        a[4..6].copy_from_slice(&ranges.to_le_bytes());
        a[8..16].copy_from_slice(name);
        Some(a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lbp16::Request;
    use crate::sim::boards;

    fn board() -> EthBoard {
        let spec = boards::preset("5i25").unwrap();
        EthBoard::new(Hm2Model::new(spec), EthIdentity::new("7I92")).with_period(1_000_000)
    }

    fn ask(b: &mut EthBoard, r: &Request) -> Vec<u8> {
        let mut reply = Vec::new();
        assert!(b.handle(r.bytes(), &mut reply));
        assert_eq!(reply.len(), r.reply_len());
        reply
    }

    #[test]
    fn identification_and_registers() {
        let mut b = board();
        let mut r = Request::new();
        r.read16(space::BOARD_INFO, 0, 8).unwrap();
        r.read16(space::ETH_EEPROM, addr::EEPROM_MAC, 3).unwrap();
        r.hm2_read(0x100, 3).unwrap();
        let reply = ask(&mut b, &r);
        assert_eq!(&reply[..4], b"7I92");
        assert_eq!(
            &reply[16..22],
            &[0x01, 0x00, 0x16, 0x1B, 0x60, 0x00],
            "MAC reversed"
        );
        assert_eq!(&reply[22..26], &0x55AA_CAFEu32.to_le_bytes());
        assert_eq!(&reply[26..34], b"HOSTMOT2");
        assert_eq!(b.counter(addr::CTRL_RX_PACKETS), 1);
        assert_eq!(b.counter(addr::CTRL_TX_PACKETS), 1);
    }

    #[test]
    fn writes_only_get_no_answer_and_tags_read_back() {
        let mut b = board();
        let mut w = Request::new();
        w.hm2_write(0x0200, &[0xC000_0000]).unwrap();
        w.write16(space::TIMER, addr::TIMER_WRITE_TAG, &[7, 0])
            .unwrap();
        let mut reply = Vec::new();
        assert!(!b.handle(w.bytes(), &mut reply));
        assert_eq!(b.model().leds(), 0xC000_0000);
        let mut r = Request::new();
        r.write16(space::TIMER, addr::TIMER_READ_TAG, &[3, 0])
            .unwrap();
        r.read16(space::TIMER, addr::TIMER_READ_TAG, 4).unwrap();
        let reply = ask(&mut b, &r);
        assert_eq!(reply, [3, 0, 0, 0, 7, 0, 0, 0]);
        assert_eq!(b.cycles(), 1);
        assert_eq!(b.model().now_ns(), 1_000_000, "a cycle moved time");
    }

    #[test]
    fn errors_are_counted_and_never_answered() {
        let mut b = board();
        let mut reply = Vec::new();
        assert!(!b.handle(&[0x82, 0x42, 0x00], &mut reply));
        assert_eq!(b.counter(addr::CTRL_PARSE_ERRORS), 1);
        // EEPROM write without the enable; a 16-bit HostMot2 read.
        let mut r = Request::new();
        r.write16(space::ETH_EEPROM, addr::EEPROM_IP, &[1, 2])
            .unwrap();
        r.read16(space::HM2, 0x100, 1).unwrap();
        let reply = ask(&mut b, &r);
        assert_eq!(reply, [0, 0]);
        assert_eq!(b.counter(addr::CTRL_WRITE_ERRORS), 2);
        assert_eq!(b.counter(addr::CTRL_MEM_ERRORS), 1);
        // With the enable in the same datagram the EEPROM takes it.
        let mut r = Request::new();
        r.write16(space::COMM_CTRL, addr::CTRL_WRITE_ENABLE, &[enable::EEPROM])
            .unwrap();
        r.write16(space::ETH_EEPROM, addr::EEPROM_IP, &[0x0179, 0xC0A8])
            .unwrap();
        r.read16(space::ETH_EEPROM, addr::EEPROM_IP, 2).unwrap();
        assert_eq!(ask(&mut b, &r), [0x79, 0x01, 0xA8, 0xC0]);
        // Info areas.
        let mut r = Request::new();
        r.push_read(
            Command {
                info: true,
                ..Command::read(space::HM2, Width::W16, 8)
            },
            0,
        )
        .unwrap();
        let a = ask(&mut b, &r);
        assert_eq!(&a[8..16], b"HostMot2");
    }
}
