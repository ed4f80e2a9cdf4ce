//! [`SimBus`]: an in-process CAN bus with simulated CiA 402 drives on it,
//! and [`SimEndpoint`], one socket's view of it.
//!
//! Frames travel on a simulated wire: each is stamped with the time it
//! was sent (plus an optional latency) and reaches the drives and the
//! other endpoints when simulated time gets there. Time moves only when
//! told: by [`SimBus::advance`] in tests, or under `loadrt` by the HAL
//! thread's time that the driver's `read` passes through
//! [`CanBus::tick`] (the bus then runs on a
//! [`SimClock::following_thread`]). Waiting endpoints
//! ([`CanBus::recv_timeout`]) deliver what is due at the present time,
//! so start-up's SDO exchanges complete without time passing.
//!
//! Bus behaviour (§6.12): frames nobody acknowledges (no drive present)
//! raise ACK error frames; bus-off can be switched on, after which every
//! send fails and error frames say so; frames matching a filter can be
//! lost; a latency can be added; an endpoint whose queue overflows gets
//! a controller RX-overflow error frame.
//!
//! The bus state sits in a `Mutex`, which realtime code otherwise must
//! not take: this is the simulator only (as the shared layer's
//! `SimBoard`), each call holds it briefly, and the other takers are the
//! start-up, the diagnostics helper and tests.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use hal_driver::sim::SimClock;

use super::{CanBus, Filter, Filters};
use crate::frame::{Frame, FrameKind};
use crate::regs::err;
use crate::sim::{SimDrive, SimDriveConfig};

/// Frames an endpoint queues before it overflows.
const ENDPOINT_QUEUE: usize = 4096;
/// Frames on the wire before sends fail (a full transmit queue).
const WIRE_LIMIT: usize = 16_384;
/// Deliveries per pump, so a storm cannot hold a caller for long.
const PUMP_BUDGET: usize = 100_000;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    Endpoint(usize),
    Drive(u8),
    External,
}

#[derive(Debug)]
struct Wire {
    due: u64,
    frame: Frame,
    from: Source,
}

#[derive(Debug)]
struct Slot {
    filters: Filters,
    queue: VecDeque<Frame>,
    overflow_said: bool,
    alive: bool,
}

/// Traffic counters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BusStats {
    /// Frames put on the wire (sent by endpoints, drives or injection).
    pub frames: u64,
    /// Their worst-case length in bit times ([`Frame::wire_bits_worst`]).
    pub wire_bits: u64,
}

#[derive(Debug)]
struct BusState {
    drives: Vec<SimDrive>,
    slots: Vec<Slot>,
    wire: VecDeque<Wire>,
    device_now: u64,
    bus_off: bool,
    latency_ns: u64,
    losses: Vec<(Filter, u32)>,
    scratch: Vec<Frame>,
    stats: BusStats,
    /// Frames one endpoint may have on the wire, not yet delivered,
    /// before its sends fail (its transmit queue).
    tx_limit: usize,
}

/// An in-process CAN bus with simulated drives.
#[derive(Debug)]
pub struct SimBus {
    state: Mutex<BusState>,
    clock: Arc<SimClock>,
}

impl SimBus {
    /// An empty bus on its own explicit clock at 0.
    pub fn new() -> Arc<SimBus> {
        SimBus::with_clock(Arc::new(SimClock::new(0, 0)))
    }

    /// An empty bus on `clock` ([`SimClock::following_thread`] under
    /// `loadrt`).
    pub fn with_clock(clock: Arc<SimClock>) -> Arc<SimBus> {
        Arc::new(SimBus {
            state: Mutex::new(BusState {
                drives: Vec::new(),
                slots: Vec::new(),
                wire: VecDeque::new(),
                device_now: clock.peek(),
                bus_off: false,
                latency_ns: 0,
                losses: Vec::new(),
                scratch: Vec::new(),
                stats: BusStats::default(),
                tx_limit: WIRE_LIMIT,
            }),
            clock,
        })
    }

    /// An explicit-clock bus with a default simulated drive at each of
    /// `nodes`.
    pub fn with_drives(nodes: &[u8]) -> Arc<SimBus> {
        let bus = SimBus::new();
        for &n in nodes {
            bus.add_drive(SimDriveConfig::new(n));
        }
        bus
    }

    fn lock(&self) -> MutexGuard<'_, BusState> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The bus clock.
    pub fn clock(&self) -> &Arc<SimClock> {
        &self.clock
    }

    /// Simulated time (ns).
    pub fn now_ns(&self) -> u64 {
        self.clock.peek()
    }

    /// Connects and powers up a drive (it sends its boot-up message).
    pub fn add_drive(&self, cfg: SimDriveConfig) {
        let mut st = self.lock();
        let mut d = SimDrive::new(cfg);
        let mut out = std::mem::take(&mut st.scratch);
        out.clear();
        d.power_up(&mut out);
        let node = d.node();
        st.drives.push(d);
        let now = self.clock.peek();
        for f in out.drain(..) {
            st.put_on_wire(now, f, Source::Drive(node));
        }
        st.scratch = out;
    }

    /// The node ids of the drives on the bus.
    pub fn nodes(&self) -> Vec<u8> {
        self.lock().drives.iter().map(SimDrive::node).collect()
    }

    /// Runs `f` on the drive at `node` (None if there is none); frames
    /// it makes the drive send (an injected fault's EMCY) go on the
    /// wire.
    pub fn with_drive<R>(
        &self,
        node: u8,
        f: impl FnOnce(&mut SimDrive, &mut Vec<Frame>) -> R,
    ) -> Option<R> {
        let mut st = self.lock();
        let i = st.drives.iter().position(|d| d.node() == node)?;
        let mut out = std::mem::take(&mut st.scratch);
        out.clear();
        let r = f(&mut st.drives[i], &mut out);
        let now = st.device_now;
        for fr in out.drain(..) {
            st.put_on_wire(now, fr, Source::Drive(node));
        }
        st.scratch = out;
        Some(r)
    }

    /// Opens an endpoint with `filters`.
    pub fn open(self: &Arc<Self>, filters: Filters) -> SimEndpoint {
        let mut st = self.lock();
        st.slots.push(Slot {
            filters,
            queue: VecDeque::new(),
            overflow_said: false,
            alive: true,
        });
        SimEndpoint {
            bus: self.clone(),
            id: st.slots.len() - 1,
            errors: AtomicU64::new(0),
        }
    }

    /// Moves simulated time on by `ns` and delivers what falls due.
    pub fn advance(&self, ns: u64) {
        self.clock.advance(ns);
        self.pump();
    }

    /// Delivers everything due at the present simulated time.
    pub fn pump(&self) {
        let now = self.clock.peek();
        self.lock().run_until(now);
    }

    /// Puts the bus in bus-off (every send fails, endpoints get a BUSOFF
    /// error frame) or brings it back (a RESTARTED error frame).
    pub fn set_bus_off(&self, off: bool) {
        let mut st = self.lock();
        if st.bus_off == off {
            return;
        }
        st.bus_off = off;
        let class = if off { err::BUSOFF } else { err::RESTARTED };
        st.error_frame(Frame::error(class, [0; 8]));
    }

    /// Delays every later frame by `ns`.
    pub fn set_latency(&self, ns: u64) {
        self.lock().latency_ns = ns;
    }

    /// Limits each endpoint's transmit queue to `frames` frames on the
    /// wire not yet delivered: further sends fail until time delivers
    /// some (with a latency, a slow bus; a full queue as a busy
    /// controller has it).
    pub fn set_tx_limit(&self, frames: usize) {
        self.lock().tx_limit = frames.min(WIRE_LIMIT);
    }

    /// Loses the next `count` frames that pass `filter`.
    pub fn lose(&self, filter: Filter, count: u32) {
        self.lock().losses.push((filter, count));
    }

    /// Puts `frame` on the wire as if another node had sent it.
    pub fn inject(&self, frame: Frame) {
        let now = self.clock.peek();
        self.lock().put_on_wire(now, frame, Source::External);
    }

    /// Delivers a controller error frame to the endpoints that asked
    /// for its class, as the kernel does.
    pub fn inject_error(&self, frame: Frame) {
        self.lock().error_frame(frame);
    }

    /// Traffic so far.
    pub fn stats(&self) -> BusStats {
        self.lock().stats
    }
}

impl BusState {
    fn put_on_wire(&mut self, now: u64, frame: Frame, from: Source) {
        if frame.kind == FrameKind::Error {
            return;
        }
        self.stats.frames += 1;
        self.stats.wire_bits += u64::from(frame.wire_bits_worst());
        let due = now + self.latency_ns;
        let at = self
            .wire
            .iter()
            .rposition(|w| w.due <= due)
            .map_or(0, |i| i + 1);
        self.wire.insert(at, Wire { due, frame, from });
    }

    fn error_frame(&mut self, frame: Frame) {
        for s in self.slots.iter_mut().filter(|s| s.alive) {
            if s.filters.accepts(&frame) && s.queue.len() < ENDPOINT_QUEUE {
                s.queue.push_back(frame);
            }
        }
    }

    fn send(&mut self, now: u64, id: usize, frame: &Frame) -> bool {
        if frame.kind == FrameKind::Error || self.bus_off || self.wire.len() >= WIRE_LIMIT {
            return false;
        }
        if self.tx_limit < WIRE_LIMIT {
            let queued = self
                .wire
                .iter()
                .filter(|w| w.from == Source::Endpoint(id))
                .count();
            if queued >= self.tx_limit {
                return false;
            }
        }
        if !self.drives.iter().any(SimDrive::is_present) {
            self.error_frame(Frame::error(err::ACK, [0; 8]));
        }
        self.put_on_wire(now, *frame, Source::Endpoint(id));
        true
    }

    fn run_until(&mut self, t: u64) {
        for _ in 0..PUMP_BUDGET {
            match self.wire.front().map(|w| w.due) {
                Some(due) if due <= t => {
                    if due > self.device_now {
                        self.advance_drives(due - self.device_now);
                    }
                    if let Some(w) = self.wire.pop_front() {
                        self.deliver(w);
                    }
                }
                _ if self.device_now < t => self.advance_drives(t - self.device_now),
                _ => return,
            }
        }
    }

    fn advance_drives(&mut self, dt: u64) {
        let mut out = std::mem::take(&mut self.scratch);
        let end = self.device_now + dt;
        for i in 0..self.drives.len() {
            out.clear();
            self.drives[i].advance(dt, &mut out);
            let node = self.drives[i].node();
            for f in out.drain(..) {
                self.put_on_wire(end, f, Source::Drive(node));
            }
        }
        self.device_now = end;
        self.scratch = out;
    }

    fn deliver(&mut self, w: Wire) {
        if let Some(i) = self
            .losses
            .iter()
            .position(|(f, n)| *n > 0 && f.matches(&w.frame))
        {
            self.losses[i].1 -= 1;
            if self.losses[i].1 == 0 {
                self.losses.remove(i);
            }
            return;
        }
        for (i, s) in self.slots.iter_mut().enumerate() {
            if !s.alive || w.from == Source::Endpoint(i) || !s.filters.accepts(&w.frame) {
                continue;
            }
            if s.queue.len() < ENDPOINT_QUEUE {
                s.queue.push_back(w.frame);
                s.overflow_said = false;
            } else if !s.overflow_said && s.filters.error_mask & err::CRTL != 0 {
                s.overflow_said = true;
                let mut d = [0u8; 8];
                d[1] = err::CRTL_RX_OVERFLOW;
                // Replaces the oldest frame, so the news is not lost.
                s.queue.pop_front();
                s.queue.push_back(Frame::error(err::CRTL, d));
            }
        }
        let mut out = std::mem::take(&mut self.scratch);
        let now = self.device_now;
        for i in 0..self.drives.len() {
            let node = self.drives[i].node();
            if w.from == Source::Drive(node) {
                continue;
            }
            out.clear();
            self.drives[i].receive(&w.frame, &mut out);
            for f in out.drain(..) {
                self.put_on_wire(now, f, Source::Drive(node));
            }
        }
        self.scratch = out;
    }
}

/// One endpoint of a [`SimBus`].
#[derive(Debug)]
pub struct SimEndpoint {
    bus: Arc<SimBus>,
    id: usize,
    errors: AtomicU64,
}

impl SimEndpoint {
    /// The bus.
    pub fn bus(&self) -> &Arc<SimBus> {
        &self.bus
    }
}

impl Drop for SimEndpoint {
    fn drop(&mut self) {
        let mut st = self.bus.lock();
        if let Some(s) = st.slots.get_mut(self.id) {
            s.alive = false;
            s.queue = VecDeque::new();
        }
    }
}

impl CanBus for SimEndpoint {
    fn send(&self, frame: &Frame) -> bool {
        let now = self.bus.clock.peek();
        let ok = self.bus.lock().send(now, self.id, frame);
        if !ok {
            self.errors.fetch_add(1, Relaxed);
        }
        ok
    }

    fn try_recv(&self) -> Option<Frame> {
        self.bus.lock().slots.get_mut(self.id)?.queue.pop_front()
    }

    fn recv_timeout(&self, timeout: Duration) -> Option<Frame> {
        let end = Instant::now() + timeout;
        loop {
            self.bus.pump();
            if let Some(f) = self.try_recv() {
                return Some(f);
            }
            if Instant::now() >= end {
                return None;
            }
            std::thread::sleep(Duration::from_micros(100));
        }
    }

    /// Pauses a millisecond, then lets a bus that follows the wall clock
    /// deliver what fell due (which frees its transmit queues).
    fn wait_writable(&self, timeout: Duration) {
        std::thread::sleep(timeout.min(Duration::from_millis(1)));
        self.tick(hal_core::clock::monotonic_ns());
    }

    fn errors(&self) -> u64 {
        self.errors.load(Relaxed)
    }

    fn describe(&self) -> String {
        format!("simulated CAN bus (endpoint {})", self.id)
    }

    fn tick(&self, now_ns: u64) {
        self.bus.clock.follow(now_ns);
        self.bus.pump();
    }
}

/// Runs a [`SimBus`]'s time with the wall clock in a background thread
/// until dropped: for tools and tests that talk to simulated drives the
/// way they would to real ones, through blocking SDO and waits.
#[derive(Debug)]
pub struct WallClock {
    stop: Arc<std::sync::atomic::AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl WallClock {
    /// Starts moving `bus`'s time on in steps of about `step`.
    pub fn run(bus: Arc<SimBus>, step: Duration) -> WallClock {
        let stop = Arc::new(std::sync::atomic::AtomicBool::new(false));
        let s = stop.clone();
        let thread = std::thread::spawn(move || {
            let mut last = Instant::now();
            while !s.load(Relaxed) {
                std::thread::sleep(step);
                let now = Instant::now();
                bus.advance((now - last).as_nanos() as u64);
                last = now;
            }
        });
        WallClock {
            stop,
            thread: Some(thread),
        }
    }
}

impl Drop for WallClock {
    fn drop(&mut self) {
        self.stop.store(true, Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
