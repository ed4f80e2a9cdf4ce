//! [`SimBoard`]: a board model behind a register bus, so a driver cannot
//! tell the simulator from the hardware.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::{Arc, Mutex, MutexGuard};

use super::clock::{Clock, SimClock};
use super::log::{Access, AccessLog, Dir, Width};
use crate::bus::{PortBus, RegWindow, SpiBus, ALL_ONES};

/// What every board model has: time and a name.
pub trait BoardModel: Send + 'static {
    /// Lets `dt_ns` of simulated time pass: counters count, watchdogs
    /// count down, motors move. The only way time passes for a model.
    fn advance(&mut self, dt_ns: u64) {
        let _ = dt_ns;
    }

    /// What the board is, for messages ("simulated 5i25").
    fn describe(&self) -> String {
        "simulated board".into()
    }
}

/// A board with a 32-bit register window (a PCI card's BAR).
pub trait MemModel: BoardModel {
    /// The window's size in bytes.
    fn len(&self) -> usize;

    /// Whether the window is empty.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Reads the register at byte `offset` (4-aligned and inside the
    /// window: the harness refuses other accesses before the model sees
    /// them). A read may have side effects, as on hardware (latches,
    /// clear-on-read).
    fn read32(&mut self, offset: usize) -> u32;

    /// Writes the register at byte `offset` (checked as for `read32`).
    fn write32(&mut self, offset: usize, value: u32);
}

/// A board on I/O ports (an ISA card, a parallel port).
pub trait PortModel: BoardModel {
    /// Reads `width` at absolute `port`; a port the board does not decode
    /// reads all ones, as an empty ISA bus does.
    fn read(&mut self, port: u16, width: Width) -> u32;

    /// Writes `width` at absolute `port` (ignored where nothing decodes).
    fn write(&mut self, port: u16, width: Width, value: u32);
}

/// A device on an SPI link: each message is exchanged word for word.
pub trait SpiModel: BoardModel {
    /// One message: `buf` holds the words the host shifts out and, on
    /// return, the words the device shifted back.
    fn exchange(&mut self, buf: &mut [u32]);
}

struct Inner<M> {
    model: M,
    log: Option<AccessLog>,
}

/// A simulated board: a model behind [`RegWindow`] (for a [`MemModel`])
/// or [`PortBus`] (for a [`PortModel`]), with simulated time and an
/// optional [`AccessLog`].
///
/// The model sits in a `Mutex`, which realtime code otherwise must not
/// take: this is the simulator only, each access holds the lock for a few
/// instructions, and the only other takers are tests and tools through
/// [`with`](Self::with), so it is uncontended in practice. Bursts take it
/// once.
pub struct SimBoard<M> {
    inner: Mutex<Inner<M>>,
    clock: Arc<SimClock>,
    stamp: Option<Arc<dyn Clock>>,
    errors: AtomicU64,
}

impl<M: BoardModel + std::fmt::Debug> std::fmt::Debug for SimBoard<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SimBoard")
            .field("model", &self.lock().model)
            .field("now_ns", &self.now_ns())
            .finish()
    }
}

impl<M: BoardModel> SimBoard<M> {
    /// A board running `model` on its own explicit clock at 0 (time
    /// moves only by [`advance`](Self::advance)), without a log.
    pub fn new(model: M) -> SimBoard<M> {
        SimBoard {
            inner: Mutex::new(Inner { model, log: None }),
            clock: Arc::new(SimClock::new(0, 0)),
            stamp: None,
            errors: AtomicU64::new(0),
        }
    }

    /// Runs on `clock` instead: [`SimClock::following_thread`] under
    /// `loadrt`, or a clock a test shares with the driver.
    pub fn with_clock(mut self, clock: Arc<SimClock>) -> SimBoard<M> {
        self.clock = clock;
        self
    }

    /// Records accesses into `log`.
    pub fn with_log(self, log: AccessLog) -> SimBoard<M> {
        self.lock().log = Some(log);
        self
    }

    /// Stamps log records with `clock`'s readings instead of the board's
    /// time: for a driver whose own timing a test checks against that
    /// clock (hal_parport's `reset` waits on its clock after `write`).
    pub fn stamp_log_with(mut self, clock: Arc<dyn Clock>) -> SimBoard<M> {
        self.stamp = Some(clock);
        self
    }

    fn lock(&self) -> MutexGuard<'_, Inner<M>> {
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The plant API: runs `f` on the model (set shaft positions,
    /// switches, voltages; read what the board drives).
    pub fn with<R>(&self, f: impl FnOnce(&mut M) -> R) -> R {
        f(&mut self.lock().model)
    }

    /// Lets `dt_ns` of simulated time pass.
    pub fn advance(&self, dt_ns: u64) {
        self.clock.advance(dt_ns);
        self.lock().model.advance(dt_ns);
    }

    /// The board's simulated time in ns.
    pub fn now_ns(&self) -> u64 {
        self.clock.peek()
    }

    /// The board's clock.
    pub fn clock(&self) -> &Arc<SimClock> {
        &self.clock
    }

    /// The logged accesses, oldest first (empty without a log).
    pub fn accesses(&self) -> Vec<Access> {
        self.lock()
            .log
            .as_ref()
            .map_or_else(Vec::new, |l| l.records().copied().collect())
    }

    /// How many accesses were logged since the last clear, including any
    /// the log no longer holds.
    pub fn access_count(&self) -> u64 {
        self.lock().log.as_ref().map_or(0, AccessLog::total)
    }

    /// Forgets the logged accesses.
    pub fn clear_log(&self) {
        if let Some(l) = self.lock().log.as_mut() {
            l.clear();
        }
    }

    /// Accesses refused before they reached the model (misaligned or
    /// outside the window).
    pub fn refused(&self) -> u64 {
        self.errors.load(Relaxed)
    }

    /// Logs one access, reading the stamp clock only when the log wants
    /// it (a stepping clock must step only for logged accesses).
    #[inline]
    fn record(&self, inner: &mut Inner<M>, addr: u64, width: Width, value: u32, dir: Dir) {
        if let Some(log) = inner.log.as_mut().filter(|l| l.wants(dir)) {
            let time_ns = match &self.stamp {
                Some(c) => c.now_ns(),
                None => self.clock.peek(),
            };
            log.record(Access {
                time_ns,
                addr,
                width,
                value,
                dir,
            });
        }
    }

    /// Follows the HAL thread's time, if the clock does.
    #[inline]
    fn tick_model(&self, now_ns: u64) {
        let dt = self.clock.follow(now_ns);
        if dt > 0 {
            self.lock().model.advance(dt);
        }
    }
}

impl<M: MemModel> SimBoard<M> {
    /// Whether `words` registers from `offset` are a valid access.
    #[inline]
    fn fits(&self, model: &M, offset: usize, words: usize) -> bool {
        let ok = offset % 4 == 0
            && words
                .checked_mul(4)
                .and_then(|b| b.checked_add(offset))
                .is_some_and(|end| end <= model.len());
        if !ok {
            self.errors.fetch_add(1, Relaxed);
        }
        ok
    }
}

impl<M: MemModel> RegWindow for SimBoard<M> {
    fn len(&self) -> usize {
        self.lock().model.len()
    }

    #[inline]
    fn read32(&self, offset: usize) -> u32 {
        let mut g = self.lock();
        if !self.fits(&g.model, offset, 1) {
            return ALL_ONES;
        }
        let v = g.model.read32(offset);
        self.record(&mut g, offset as u64, Width::Long, v, Dir::Read);
        v
    }

    #[inline]
    fn write32(&self, offset: usize, value: u32) {
        let mut g = self.lock();
        if self.fits(&g.model, offset, 1) {
            g.model.write32(offset, value);
            self.record(&mut g, offset as u64, Width::Long, value, Dir::Write);
        }
    }

    fn read_burst(&self, offset: usize, out: &mut [u32]) {
        let mut g = self.lock();
        if !self.fits(&g.model, offset, out.len()) {
            out.fill(ALL_ONES);
            return;
        }
        for (i, v) in out.iter_mut().enumerate() {
            let at = offset + 4 * i;
            *v = g.model.read32(at);
            self.record(&mut g, at as u64, Width::Long, *v, Dir::Read);
        }
    }

    fn write_burst(&self, offset: usize, data: &[u32]) {
        let mut g = self.lock();
        if !self.fits(&g.model, offset, data.len()) {
            return;
        }
        for (i, v) in data.iter().enumerate() {
            let at = offset + 4 * i;
            g.model.write32(at, *v);
            self.record(&mut g, at as u64, Width::Long, *v, Dir::Write);
        }
    }

    fn errors(&self) -> u64 {
        self.refused()
    }

    fn describe(&self) -> String {
        self.lock().model.describe()
    }

    #[inline]
    fn tick(&self, now_ns: u64) {
        self.tick_model(now_ns)
    }
}

impl<M: PortModel> SimBoard<M> {
    #[inline]
    fn port_read(&self, port: u16, width: Width) -> u32 {
        let mut g = self.lock();
        let v = g.model.read(port, width);
        self.record(&mut g, port as u64, width, v, Dir::Read);
        v
    }

    #[inline]
    fn port_write(&self, port: u16, width: Width, value: u32) {
        let mut g = self.lock();
        g.model.write(port, width, value);
        self.record(&mut g, port as u64, width, value, Dir::Write);
    }
}

impl<M: PortModel> PortBus for SimBoard<M> {
    #[inline]
    fn inb(&self, port: u16) -> u8 {
        self.port_read(port, Width::Byte) as u8
    }
    #[inline]
    fn outb(&self, port: u16, value: u8) {
        self.port_write(port, Width::Byte, value as u32)
    }
    #[inline]
    fn inw(&self, port: u16) -> u16 {
        self.port_read(port, Width::Word) as u16
    }
    #[inline]
    fn outw(&self, port: u16, value: u16) {
        self.port_write(port, Width::Word, value as u32)
    }
    #[inline]
    fn inl(&self, port: u16) -> u32 {
        self.port_read(port, Width::Long)
    }
    #[inline]
    fn outl(&self, port: u16, value: u32) {
        self.port_write(port, Width::Long, value)
    }
    fn errors(&self) -> u64 {
        self.refused()
    }
    fn describe(&self) -> String {
        self.lock().model.describe()
    }
    #[inline]
    fn tick(&self, now_ns: u64) {
        self.tick_model(now_ns)
    }
}

impl<M: SpiModel> SpiBus for SimBoard<M> {
    fn transfer(&self, buf: &mut [u32], _speed_hz: u32) {
        self.lock().model.exchange(buf);
    }
    fn errors(&self) -> u64 {
        self.refused()
    }
    fn describe(&self) -> String {
        self.lock().model.describe()
    }
    fn tick(&self, now_ns: u64) {
        self.tick_model(now_ns)
    }
}
