//! The simulated bus: register-level models of the chips at their
//! addresses behind the same [`I2cBus`] trait as `/dev/i2c-N`.
//!
//! A model sees what a chip sees on the wire: a write transfer (the bytes
//! after the address, the first normally the register pointer) or a
//! read transfer (bytes from its current pointer) ([`ChipModel`]). The
//! bus turns each SMBus transfer into those: byte data is `[reg, v]` or
//! `[reg]` then one byte read; word data two bytes, low first; block
//! data the bytes in order. A chip that is not there (never added, or
//! [`SimBus::unplug`]ged) does not acknowledge: ENXIO, as i2c-dev
//! reports it. [`SimBus::fail_next`] makes transfers fail with EIO (a
//! glitch on the wires); [`SimBus::set_busy`] makes an address look owned
//! by a kernel driver (EBUSY at claim).
//!
//! Every transfer is logged with its time ([`Transfer`]), so tests check
//! register sequences. Time passes for the models only through
//! [`SimBus::advance`] or, under `loadrt`, through the helper thread's
//! [`I2cBus::tick`] on a clock that follows it.
//!
//! The bus state sits behind a `Mutex`: the simulator only, taken by the
//! helper thread and by tests, never by a realtime function.

pub mod ads1115;
pub mod mcp23017;
pub mod pca9685;

use std::any::Any;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::{Arc, Mutex, MutexGuard};

use hal_driver::sim::SimClock;

use crate::bus::{BusError, I2cBus, BLOCK_MAX};

pub use ads1115::Ads1115;
pub use mcp23017::Mcp23017;
pub use pca9685::Pca9685;

/// How many transfers the log keeps (the newest).
pub const LOG_CAPACITY: usize = 4096;

/// A chip as the bus sees it.
pub trait ChipModel: Send + 'static {
    /// A write transfer: the bytes after the address.
    fn write(&mut self, bytes: &[u8]);
    /// A read transfer: fills `out` from the chip's pointer on.
    fn read(&mut self, out: &mut [u8]);
    /// Lets `dt_ns` of time pass (conversions finish, oscillators
    /// settle).
    fn advance(&mut self, dt_ns: u64) {
        let _ = dt_ns;
    }
    /// What the chip is, for messages.
    fn describe(&self) -> String;
    /// The model, for [`SimBus::with_chip`].
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

/// The SMBus transfer kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Write byte data.
    WriteByte,
    /// Read byte data.
    ReadByte,
    /// Write word data.
    WriteWord,
    /// Read word data.
    ReadWord,
    /// Write I2C block data.
    WriteBlock,
    /// Read I2C block data.
    ReadBlock,
}

impl Kind {
    /// Whether the transfer writes to the chip.
    pub fn is_write(self) -> bool {
        matches!(self, Kind::WriteByte | Kind::WriteWord | Kind::WriteBlock)
    }
}

/// One transfer that reached a chip.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Transfer {
    /// When, on the bus's clock, ns.
    pub time_ns: u64,
    /// The chip's address.
    pub addr: u8,
    /// The kind.
    pub kind: Kind,
    /// The register.
    pub reg: u8,
    len: u8,
    data: [u8; BLOCK_MAX],
}

impl Transfer {
    /// The data bytes, in wire order.
    pub fn bytes(&self) -> &[u8] {
        &self.data[..self.len as usize]
    }
}

struct Slot {
    addr: u8,
    model: Box<dyn ChipModel>,
    present: bool,
}

struct BusState {
    chips: Vec<Slot>,
    fail_next: u32,
    busy: Vec<u8>,
    log: VecDeque<Transfer>,
}

/// A simulated I2C bus.
pub struct SimBus {
    name: String,
    state: Mutex<BusState>,
    clock: Arc<SimClock>,
    errors: AtomicU64,
}

impl std::fmt::Debug for SimBus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SimBus").field("name", &self.name).finish()
    }
}

impl SimBus {
    /// An empty bus called `name` on `clock`.
    pub fn new(name: &str, clock: Arc<SimClock>) -> SimBus {
        SimBus {
            name: name.into(),
            state: Mutex::new(BusState {
                chips: Vec::new(),
                fail_next: 0,
                busy: Vec::new(),
                log: VecDeque::with_capacity(LOG_CAPACITY),
            }),
            clock,
            errors: AtomicU64::new(0),
        }
    }

    fn lock(&self) -> MutexGuard<'_, BusState> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Puts `model` at `addr`, unless a chip is there already; whether it
    /// was added.
    pub fn add_chip(&self, addr: u8, model: Box<dyn ChipModel>) -> bool {
        let mut s = self.lock();
        if s.chips.iter().any(|c| c.addr == addr) {
            return false;
        }
        s.chips.push(Slot {
            addr,
            model,
            present: true,
        });
        true
    }

    /// Runs `f` on the model at `addr`, if it is an `M` (the plant API:
    /// set inputs, read outputs).
    pub fn with_chip<M: ChipModel, R>(&self, addr: u8, f: impl FnOnce(&mut M) -> R) -> Option<R> {
        let mut s = self.lock();
        let slot = s.chips.iter_mut().find(|c| c.addr == addr)?;
        slot.model.as_any_mut().downcast_mut::<M>().map(f)
    }

    /// The chip at `addr` stops answering (unplugged, unpowered).
    pub fn unplug(&self, addr: u8) {
        self.set_present(addr, false);
    }

    /// The chip at `addr` answers again, its registers as they were (use
    /// the model's own reset for a power cycle).
    pub fn plug(&self, addr: u8) {
        self.set_present(addr, true);
    }

    fn set_present(&self, addr: u8, present: bool) {
        if let Some(c) = self.lock().chips.iter_mut().find(|c| c.addr == addr) {
            c.present = present;
        }
    }

    /// The next `n` transfers fail with EIO, whatever their address.
    pub fn fail_next(&self, n: u32) {
        self.lock().fail_next = n;
    }

    /// Claiming `addr` fails with EBUSY, as when a kernel driver owns it.
    pub fn set_busy(&self, addr: u8) {
        self.lock().busy.push(addr);
    }

    /// The logged transfers, oldest first.
    pub fn transfers(&self) -> Vec<Transfer> {
        self.lock().log.iter().copied().collect()
    }

    /// The logged transfers to `addr`.
    pub fn transfers_to(&self, addr: u8) -> Vec<Transfer> {
        self.lock()
            .log
            .iter()
            .filter(|t| t.addr == addr)
            .copied()
            .collect()
    }

    /// Forgets the logged transfers.
    pub fn clear_log(&self) {
        self.lock().log.clear();
    }

    /// Lets `dt_ns` pass for every chip.
    pub fn advance(&self, dt_ns: u64) {
        self.clock.advance(dt_ns);
        for c in self.lock().chips.iter_mut() {
            c.model.advance(dt_ns);
        }
    }

    /// The bus's time, ns.
    pub fn now_ns(&self) -> u64 {
        self.clock.peek()
    }

    /// One transfer: `f` runs on the chip at `addr` if the transfer gets
    /// there; the transfer is logged with the bytes `f` returns.
    fn transfer<R>(
        &self,
        addr: u8,
        kind: Kind,
        reg: u8,
        f: impl FnOnce(&mut dyn ChipModel) -> (R, [u8; BLOCK_MAX], usize),
    ) -> Result<R, BusError> {
        let mut s = self.lock();
        let result = if s.fail_next > 0 {
            s.fail_next -= 1;
            Err(BusError(libc::EIO))
        } else {
            match s.chips.iter_mut().find(|c| c.addr == addr && c.present) {
                None => Err(BusError(libc::ENXIO)),
                Some(slot) => Ok(f(&mut *slot.model)),
            }
        };
        match result {
            Ok((r, data, len)) => {
                if s.log.len() == LOG_CAPACITY {
                    s.log.pop_front();
                }
                let time_ns = self.clock.peek();
                s.log.push_back(Transfer {
                    time_ns,
                    addr,
                    kind,
                    reg,
                    len: len as u8,
                    data,
                });
                Ok(r)
            }
            Err(e) => {
                self.errors.fetch_add(1, Relaxed);
                Err(e)
            }
        }
    }

    fn write(&self, addr: u8, kind: Kind, reg: u8, data: &[u8]) -> Result<(), BusError> {
        if data.len() > BLOCK_MAX {
            return Err(BusError(libc::EINVAL));
        }
        self.transfer(addr, kind, reg, |chip| {
            let mut wire = [0u8; BLOCK_MAX + 1];
            wire[0] = reg;
            wire[1..=data.len()].copy_from_slice(data);
            chip.write(&wire[..=data.len()]);
            let mut logged = [0u8; BLOCK_MAX];
            logged[..data.len()].copy_from_slice(data);
            ((), logged, data.len())
        })
    }

    fn read(&self, addr: u8, kind: Kind, reg: u8, out: &mut [u8]) -> Result<(), BusError> {
        if out.len() > BLOCK_MAX {
            return Err(BusError(libc::EINVAL));
        }
        let n = out.len();
        let data = self.transfer(addr, kind, reg, |chip| {
            chip.write(&[reg]);
            let mut got = [0u8; BLOCK_MAX];
            chip.read(&mut got[..n]);
            (got, got, n)
        })?;
        out.copy_from_slice(&data[..n]);
        Ok(())
    }
}

impl I2cBus for SimBus {
    fn claim(&self, addr: u8) -> Result<(), BusError> {
        if self.lock().busy.contains(&addr) {
            return Err(BusError(libc::EBUSY));
        }
        Ok(())
    }

    fn write_byte_data(&self, addr: u8, reg: u8, value: u8) -> Result<(), BusError> {
        self.write(addr, Kind::WriteByte, reg, &[value])
    }

    fn read_byte_data(&self, addr: u8, reg: u8) -> Result<u8, BusError> {
        let mut b = [0u8; 1];
        self.read(addr, Kind::ReadByte, reg, &mut b)?;
        Ok(b[0])
    }

    fn write_word_data(&self, addr: u8, reg: u8, value: u16) -> Result<(), BusError> {
        self.write(addr, Kind::WriteWord, reg, &value.to_le_bytes())
    }

    fn read_word_data(&self, addr: u8, reg: u8) -> Result<u16, BusError> {
        let mut b = [0u8; 2];
        self.read(addr, Kind::ReadWord, reg, &mut b)?;
        Ok(u16::from_le_bytes(b))
    }

    fn write_block(&self, addr: u8, reg: u8, data: &[u8]) -> Result<(), BusError> {
        self.write(addr, Kind::WriteBlock, reg, data)
    }

    fn read_block(&self, addr: u8, reg: u8, out: &mut [u8]) -> Result<(), BusError> {
        self.read(addr, Kind::ReadBlock, reg, out)
    }

    fn errors(&self) -> u64 {
        self.errors.load(Relaxed)
    }

    fn describe(&self) -> String {
        self.name.clone()
    }

    fn tick(&self, now_ns: u64) {
        let dt = self.clock.follow(now_ns);
        if dt > 0 {
            for c in self.lock().chips.iter_mut() {
                c.model.advance(dt);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A register file: what i2c-stub is.
    struct Regs {
        regs: [u8; 256],
        pointer: u8,
    }

    impl Default for Regs {
        fn default() -> Self {
            Regs {
                regs: [0; 256],
                pointer: 0,
            }
        }
    }

    impl ChipModel for Regs {
        fn write(&mut self, bytes: &[u8]) {
            if let Some((&p, data)) = bytes.split_first() {
                self.pointer = p;
                for &b in data {
                    self.regs[self.pointer as usize] = b;
                    self.pointer = self.pointer.wrapping_add(1);
                }
            }
        }
        fn read(&mut self, out: &mut [u8]) {
            for b in out {
                *b = self.regs[self.pointer as usize];
                self.pointer = self.pointer.wrapping_add(1);
            }
        }
        fn describe(&self) -> String {
            "register file".into()
        }
        fn as_any_mut(&mut self) -> &mut dyn Any {
            self
        }
    }

    #[test]
    fn smbus_transfers_map_to_wire_bytes_and_are_logged() {
        let bus = SimBus::new("sim-i2c-0", Arc::new(SimClock::new(0, 0)));
        bus.add_chip(0x40, Box::<Regs>::default());
        bus.write_word_data(0x40, 0x10, 0xBEEF).unwrap();
        assert_eq!(
            bus.read_byte_data(0x40, 0x10).unwrap(),
            0xEF,
            "low byte first"
        );
        assert_eq!(bus.read_byte_data(0x40, 0x11).unwrap(), 0xBE);
        bus.write_block(0x40, 0x20, &[1, 2, 3]).unwrap();
        let mut out = [0u8; 3];
        bus.read_block(0x40, 0x20, &mut out).unwrap();
        assert_eq!(out, [1, 2, 3]);
        assert_eq!(bus.read_word_data(0x40, 0x21).unwrap(), 0x0302);
        bus.advance(500);
        bus.write_byte_data(0x40, 0x30, 9).unwrap();
        let t = bus.transfers();
        assert_eq!(t.len(), 7);
        assert_eq!(
            (t[0].kind, t[0].reg, t[0].bytes()),
            (Kind::WriteWord, 0x10, &[0xEF, 0xBE][..])
        );
        assert_eq!((t[4].kind, t[4].bytes()), (Kind::ReadBlock, &[1, 2, 3][..]));
        assert_eq!((t[6].time_ns, t[6].bytes()), (500, &[9][..]));
        assert_eq!(bus.with_chip::<Regs, _>(0x40, |r| r.regs[0x30]), Some(9));
    }

    #[test]
    fn missing_chips_glitches_and_busy_addresses() {
        let bus = SimBus::new("sim-i2c-0", Arc::new(SimClock::new(0, 0)));
        bus.add_chip(0x20, Box::<Regs>::default());
        assert_eq!(bus.read_byte_data(0x21, 0), Err(BusError(libc::ENXIO)));
        bus.unplug(0x20);
        assert_eq!(bus.write_byte_data(0x20, 0, 1), Err(BusError(libc::ENXIO)));
        bus.plug(0x20);
        bus.fail_next(2);
        assert_eq!(bus.read_byte_data(0x20, 0), Err(BusError(libc::EIO)));
        assert_eq!(bus.read_byte_data(0x20, 0), Err(BusError(libc::EIO)));
        assert_eq!(bus.read_byte_data(0x20, 0), Ok(0));
        assert_eq!(bus.errors(), 4);
        assert_eq!(bus.transfers().len(), 1, "failed transfers reach no chip");
        bus.set_busy(0x20);
        assert_eq!(bus.claim(0x20), Err(BusError(libc::EBUSY)));
        assert_eq!(bus.claim(0x21), Ok(()));
        assert!(!bus.add_chip(0x20, Box::<Regs>::default()));
        assert_eq!(
            bus.write_block(0x20, 0, &[0; 33]),
            Err(BusError(libc::EINVAL))
        );
    }
}
