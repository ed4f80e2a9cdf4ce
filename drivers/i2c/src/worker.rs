//! The bus's helper thread: one non-realtime thread per I2C bus (per HAL
//! instance) runs every chip on the bus once per cycle, whichever module
//! loaded it, exchanging values with the chips' realtime functions
//! through [`crate::handoff`].
//!
//! * [`BusWorker`]: the thread and the bus. Found or made by [`worker`]
//!   per instance and bus key, shared by the modules' chips, stopped and
//!   joined when the last chip leaves.
//! * [`ChipRunner`]: one chip on the thread: its [`Chip`] driver, the
//!   helper's ends of the hand-offs, and the fault handling below.
//!
//! A cycle starts every [`CYCLE_NS`] (or when the previous one ends, if
//! the transfers took longer), reads the clock once, and services each
//! chip in the order loaded.
//!
//! Failures never block or end the thread. A failed transfer (no
//! answer, a bus error) or a chip found reset counts in the chip's error
//! count and trips its fault latch; the first trip is said once in the
//! realtime log. While tripped, the chip's outputs are held in their
//! safe state, and its inputs keep their last good values. The chip is
//! set up again every [`RETRY_NS`] until it answers; from then on its
//! inputs are fresh again, but its outputs stay safe until a rising edge
//! of its `fault-reset` pin clears the latch (a reset asked for while
//! the chip still fails is ignored).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::*};
use std::sync::{Arc, Mutex, MutexGuard, Weak};
use std::thread::JoinHandle;
use std::time::Duration;

use hal_driver::fault::{Fault, FaultLatch, SafeState};
use hal_driver::LogSink;

use crate::bus::I2cBus;
use crate::chips::{Chip, ChipFault, Command};
use crate::error::I2cError;
use crate::handoff::{CmdFeed, Flags, Handoff, Status, StatusFeed};
use crate::sim::SimBus;

/// The helper thread's cycle: 1 ms.
pub const CYCLE_NS: u64 = 1_000_000;

/// How often a failed chip is tried again: 100 ms.
pub const RETRY_NS: u64 = 100_000_000;

/// How long the safe-state hook waits for the helper thread.
pub const SAFE_TIMEOUT: Duration = Duration::from_millis(500);

static CHIP_FAILED: Fault = Fault::new(
    1,
    "chip not answering or reset; outputs held safe until fault-reset",
);

/// What the helper thread runs for each chip.
pub trait Task: Send + Sync {
    /// One cycle of this chip at `now_ns`.
    fn service(&self, bus: &dyn I2cBus, now_ns: u64);
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    Running,
    Failed { retry_at: u64 },
}

struct RunnerState<C: Chip> {
    chip: C,
    cmd: CmdFeed<C::Cmd>,
    status_feed: StatusFeed<C::Sample>,
    status: Status<C::Sample>,
    phase: Phase,
    latch: FaultLatch,
    resets_seen: u64,
    last_cmd: C::Cmd,
}

/// One chip as the helper thread runs it.
pub struct ChipRunner<C: Chip> {
    name: String,
    flags: Arc<Flags>,
    log: LogSink,
    state: Mutex<RunnerState<C>>,
}

impl<C: Chip> ChipRunner<C> {
    /// A runner for `chip` (already set up) called `name`, with new
    /// hand-offs, saying faults through `log` (the host's realtime log,
    /// or any [`LogSink`]); and the hand-offs' realtime ends.
    pub fn new(
        name: &str,
        chip: C,
        log: impl Into<LogSink>,
    ) -> (Arc<ChipRunner<C>>, RealtimeEnds<C>) {
        let h = Handoff::<C::Cmd, C::Sample>::new();
        let resets_seen = h.flags.reset_requests();
        (
            Arc::new(ChipRunner {
                name: name.to_string(),
                flags: h.flags.clone(),
                log: log.into(),
                state: Mutex::new(RunnerState {
                    chip,
                    cmd: h.cmd_feed,
                    status_feed: h.status_feed,
                    status: Status::default(),
                    phase: Phase::Running,
                    latch: FaultLatch::new(name),
                    resets_seen,
                    last_cmd: C::Cmd::default(),
                }),
            }),
            RealtimeEnds {
                cmd: h.cmd_port,
                status: h.status_port,
                flags: h.flags,
            },
        )
    }

    fn lock(&self) -> MutexGuard<'_, RunnerState<C>> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The chip's status as last published.
    pub fn status(&self) -> Status<C::Sample> {
        self.lock().status
    }

    fn fail(&self, st: &mut RunnerState<C>, bus: &dyn I2cBus, e: ChipFault, now_ns: u64) {
        st.status.errors = st.status.errors.wrapping_add(1);
        st.phase = Phase::Failed {
            retry_at: now_ns.saturating_add(RETRY_NS),
        };
        if st.latch.trip(&CHIP_FAILED) {
            self.log.err(format_args!(
                "{}: {} address {:#04x}: {e}; outputs held safe until {}.fault-reset",
                self.name,
                bus.describe(),
                st.chip.address(),
                self.name
            ));
        }
    }
}

impl<C: Chip> Task for ChipRunner<C> {
    fn service(&self, bus: &dyn I2cBus, now_ns: u64) {
        let mut guard = self.lock();
        let st = &mut *guard;
        let safe_request = self.flags.safe_request();
        let resets = self.flags.reset_requests();
        let reset_asked = resets != st.resets_seen;
        st.resets_seen = resets;
        let cmd = st.cmd.latest();
        st.last_cmd = cmd;
        // A fault reset counts only when asked while the chip worked.
        let was_running = st.phase == Phase::Running;
        if let Phase::Failed { retry_at } = st.phase {
            let ready = now_ns >= retry_at;
            if ready {
                match st.chip.init(bus, &cmd.safe()) {
                    Ok(()) => {
                        st.phase = Phase::Running;
                        // Said at the error level, like the fault: the
                        // operator waits for it to reset the fault.
                        self.log.err(format_args!(
                            "{}: {} address {:#04x} answers again and is set up; outputs stay safe until {}.fault-reset",
                            self.name,
                            bus.describe(),
                            st.chip.address(),
                            self.name
                        ));
                    }
                    Err(e) => self.fail(st, bus, e, now_ns),
                }
            }
            if st.phase != Phase::Running {
                // Nothing can be written: the hook need not wait.
                self.flags.safe_applied(safe_request);
                st.status.fault = true;
                st.status_feed.publish(st.status);
                return;
            }
        }
        if reset_asked && was_running && st.latch.is_tripped() {
            st.latch.reset();
            self.log
                .info(format_args!("{}: fault reset, outputs enabled", self.name));
        }
        let safe = self.flags.holding_safe() || st.latch.is_tripped();
        let used = if safe { cmd.safe() } else { cmd };
        match st.chip.cycle(bus, &used, now_ns, &mut st.status.sample) {
            Ok(()) => {
                st.status.cycles += 1;
                if safe {
                    self.flags.safe_applied(safe_request);
                }
            }
            Err(e) => self.fail(st, bus, e, now_ns),
        }
        st.status.fault = st.latch.is_tripped();
        st.status_feed.publish(st.status);
    }
}

/// The realtime ends of a chip's hand-offs.
pub struct RealtimeEnds<C: Chip> {
    /// For the `write` function.
    pub cmd: crate::handoff::CmdPort<C::Cmd>,
    /// For the `read` function.
    pub status: crate::handoff::StatusPort<C::Sample>,
    /// For the safe-state hook.
    pub flags: Arc<Flags>,
}

/// The safe-state hook of one chip.
pub struct ChipSafe {
    /// The chip's flags.
    pub flags: Arc<Flags>,
}

impl SafeState for ChipSafe {
    /// Holds the outputs safe and waits (up to [`SAFE_TIMEOUT`]) until the
    /// helper thread has written them.
    fn go_safe(&self) {
        self.flags.go_safe(SAFE_TIMEOUT);
    }
}

struct Shared {
    bus: Arc<dyn I2cBus>,
    tasks: Mutex<Vec<(u64, Arc<dyn Task>)>>,
    claims: Mutex<Vec<(u8, String)>>,
    stop: AtomicBool,
    cycles: AtomicU64,
    next_id: AtomicU64,
}

impl Shared {
    fn run(&self) {
        while !self.stop.load(Acquire) {
            let start = hal_core::clock::monotonic_ns();
            self.bus.tick(start);
            let tasks: Vec<Arc<dyn Task>> =
                lock(&self.tasks).iter().map(|(_, t)| t.clone()).collect();
            for t in &tasks {
                t.service(&*self.bus, start);
            }
            self.cycles.fetch_add(1, Release);
            let end = start + CYCLE_NS;
            let now = hal_core::clock::monotonic_ns();
            if now < end {
                std::thread::sleep(Duration::from_nanos(end - now));
            } else {
                std::thread::yield_now();
            }
        }
    }
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// The helper thread of one bus.
pub struct BusWorker {
    key: String,
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    sim: Option<Arc<SimBus>>,
}

impl std::fmt::Debug for BusWorker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BusWorker").field("key", &self.key).finish()
    }
}

impl BusWorker {
    /// Starts the helper thread of `bus` (`sim`: the same bus, when it is
    /// simulated).
    fn start(
        key: &str,
        bus: Arc<dyn I2cBus>,
        sim: Option<Arc<SimBus>>,
    ) -> std::io::Result<BusWorker> {
        let shared = Arc::new(Shared {
            bus,
            tasks: Mutex::new(Vec::new()),
            claims: Mutex::new(Vec::new()),
            stop: AtomicBool::new(false),
            cycles: AtomicU64::new(0),
            next_id: AtomicU64::new(0),
        });
        let s = shared.clone();
        let thread = std::thread::Builder::new()
            .name(format!("i2c {key}"))
            .spawn(move || s.run())?;
        Ok(BusWorker {
            key: key.to_string(),
            shared,
            thread: Some(thread),
            sim,
        })
    }

    /// The bus.
    pub fn bus(&self) -> &Arc<dyn I2cBus> {
        &self.shared.bus
    }

    /// The bus as a simulator, if it is one.
    pub fn sim(&self) -> Option<&Arc<SimBus>> {
        self.sim.as_ref()
    }

    /// Helper cycles completed so far.
    pub fn cycles(&self) -> u64 {
        self.shared.cycles.load(Acquire)
    }

    /// Reserves `addr` for `owner` (a chip's HAL name); the reservation
    /// ends when the returned value is dropped. The error names the chip
    /// that has it.
    pub fn reserve(self: &Arc<Self>, addr: u8, owner: &str) -> Result<Reservation, I2cError> {
        let mut claims = lock(&self.shared.claims);
        if let Some((_, by)) = claims.iter().find(|(a, _)| *a == addr) {
            return Err(I2cError::AddressInUse {
                chip: owner.to_string(),
                bus: self.bus().describe(),
                addr,
                by: by.clone(),
            });
        }
        claims.push((addr, owner.to_string()));
        Ok(Reservation {
            worker: self.clone(),
            addr,
        })
    }

    /// Runs `task` every cycle until the returned value is dropped.
    pub fn attach(self: &Arc<Self>, task: Arc<dyn Task>) -> Attachment {
        let id = self.shared.next_id.fetch_add(1, Relaxed);
        lock(&self.shared.tasks).push((id, task));
        Attachment {
            worker: self.clone(),
            id,
        }
    }
}

impl Drop for BusWorker {
    /// Stops the thread (it finishes its cycle) and waits for it.
    fn drop(&mut self) {
        self.shared.stop.store(true, Release);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// An address reserved on a bus.
pub struct Reservation {
    worker: Arc<BusWorker>,
    addr: u8,
}

impl Drop for Reservation {
    fn drop(&mut self) {
        lock(&self.worker.shared.claims).retain(|(a, _)| *a != self.addr);
    }
}

/// A task attached to a bus's helper thread; detached when dropped.
pub struct Attachment {
    worker: Arc<BusWorker>,
    id: u64,
}

impl Attachment {
    /// The worker.
    pub fn worker(&self) -> &Arc<BusWorker> {
        &self.worker
    }
}

impl Drop for Attachment {
    fn drop(&mut self) {
        lock(&self.worker.shared.tasks).retain(|(id, _)| *id != self.id);
    }
}

type Entry = (String, String, Weak<BusWorker>);

/// A bus as [`worker`]'s `open` gives it: the bus, and the same bus as a
/// simulator if it is one.
pub type OpenedBus = (Arc<dyn I2cBus>, Option<Arc<SimBus>>);
static WORKERS: Mutex<Vec<Entry>> = Mutex::new(Vec::new());

/// The helper thread of bus `key` in HAL instance `instance`, started
/// with the bus `open` gives if there is none yet.
pub fn worker<E>(
    instance: &str,
    key: &str,
    open: impl FnOnce() -> Result<OpenedBus, E>,
    spawn_failed: impl FnOnce(std::io::Error) -> E,
) -> Result<Arc<BusWorker>, E> {
    let mut all = lock(&WORKERS);
    all.retain(|(_, _, w)| w.strong_count() > 0);
    if let Some(w) = all
        .iter()
        .find(|(i, k, _)| i == instance && k == key)
        .and_then(|(_, _, w)| w.upgrade())
    {
        return Ok(w);
    }
    let (bus, sim) = open()?;
    let w = Arc::new(BusWorker::start(key, bus, sim).map_err(spawn_failed)?);
    all.push((instance.to_string(), key.to_string(), Arc::downgrade(&w)));
    Ok(w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chips::{DioCmd, Mcp23017Chip};
    use crate::sim::Mcp23017;
    use hal_core::RtLog;
    use hal_driver::sim::SimClock;

    /// A runner for an MCP23017 at 0x20 with port A outputs, port B
    /// inputs, on an explicit-clock bus.
    fn rig() -> (
        Arc<SimBus>,
        Arc<ChipRunner<Mcp23017Chip>>,
        RealtimeEnds<Mcp23017Chip>,
        RtLog,
    ) {
        let bus = Arc::new(SimBus::new("sim-i2c-9", Arc::new(SimClock::new(0, 0))));
        bus.add_chip(0x20, Box::new(Mcp23017::new()));
        let mut chip = Mcp23017Chip::new(0x20, 0xFF00, 0);
        chip.init(&*bus, &DioCmd::default()).unwrap();
        let log = RtLog::new(16);
        let (runner, ends) = ChipRunner::new("mcp23017.0", chip, log.clone());
        (bus, runner, ends, log)
    }

    fn said(log: &RtLog) -> Vec<String> {
        let mut v = Vec::new();
        log.drain(|_, t| v.push(t.to_string()));
        v
    }

    #[test]
    fn commands_out_samples_in() {
        let (bus, runner, mut rt, _) = rig();
        rt.cmd.publish(DioCmd {
            out: 0x00A5,
            safe: 0,
        });
        bus.with_chip::<Mcp23017, _>(0x20, |c| c.set_input(9, true));
        runner.service(&*bus, 0);
        let s = *rt.status.latest();
        assert_eq!(s.sample & 0x02FF, 0x02A5);
        assert!(!s.fault && s.errors == 0 && s.cycles == 1);
        bus.with_chip::<Mcp23017, _>(0x20, |c| assert_eq!(c.pins() & 0xFF, 0xA5));
    }

    #[test]
    fn a_missing_chip_faults_holds_inputs_retries_and_needs_a_reset() {
        let (bus, runner, mut rt, log) = rig();
        rt.cmd.publish(DioCmd {
            out: 0x00FF,
            safe: 0x0001,
        });
        bus.with_chip::<Mcp23017, _>(0x20, |c| c.set_input(8, true));
        runner.service(&*bus, 0);
        assert_eq!(rt.status.latest().sample & 0x01FF, 0x01FF);
        bus.unplug(0x20);
        let mut t = 1_000_000;
        runner.service(&*bus, t);
        let s = *rt.status.latest();
        assert!(s.fault);
        assert_eq!(s.errors, 1);
        assert_eq!(s.sample & 0x01FF, 0x01FF, "inputs keep their last values");
        let msgs = said(&log);
        assert_eq!(msgs.len(), 1, "{msgs:?}");
        assert!(
            msgs[0].contains("mcp23017.0: sim-i2c-9 address 0x20: ")
                && msgs[0].contains("no answer"),
            "{msgs:?}"
        );
        // No retry before RETRY_NS: no more errors.
        t += 1_000_000;
        runner.service(&*bus, t);
        assert_eq!(rt.status.latest().errors, 1);
        // A retry while still missing: one more error, said no more.
        t += RETRY_NS;
        runner.service(&*bus, t);
        assert_eq!(rt.status.latest().errors, 2);
        assert!(said(&log).is_empty());
        // A fault reset while the chip is missing is ignored.
        rt.status.fault_reset(true);
        rt.status.fault_reset(false);
        // Back, power-cycled: set up again, inputs fresh, outputs safe.
        bus.with_chip::<Mcp23017, _>(0x20, |c| {
            c.power_cycle();
            c.set_input(8, false);
        });
        bus.plug(0x20);
        t += RETRY_NS;
        runner.service(&*bus, t);
        let s = *rt.status.latest();
        assert!(s.fault, "still latched");
        assert_eq!(s.sample & 0x0100, 0, "inputs fresh");
        bus.with_chip::<Mcp23017, _>(0x20, |c| {
            assert_eq!(c.iodir(), 0xFF00, "set up again");
            assert_eq!(c.pins() & 0xFF, 0x01, "outputs at their safe levels");
        });
        assert!(said(&log)[0].contains("answers again"));
        runner.service(&*bus, t + 1);
        assert!(rt.status.latest().fault, "the earlier reset did not count");
        // The reset: outputs come back.
        rt.status.fault_reset(true);
        runner.service(&*bus, t + 2);
        assert!(!rt.status.latest().fault);
        bus.with_chip::<Mcp23017, _>(0x20, |c| assert_eq!(c.pins() & 0xFF, 0xFF));
        assert_eq!(rt.status.latest().errors, 2);
    }

    #[test]
    fn the_safe_state_hook_waits_for_the_outputs_and_write_resumes() {
        let (bus, runner, mut rt, _) = rig();
        rt.cmd.publish(DioCmd {
            out: 0x00F0,
            safe: 0x000F,
        });
        runner.service(&*bus, 0);
        let (b, r) = (bus.clone(), runner.clone());
        let stop = Arc::new(AtomicBool::new(false));
        let s2 = stop.clone();
        let helper = std::thread::spawn(move || {
            let mut t = 0;
            while !s2.load(Relaxed) {
                t += 1_000_000;
                r.service(&*b, t);
                std::thread::sleep(Duration::from_micros(200));
            }
        });
        ChipSafe {
            flags: rt.flags.clone(),
        }
        .go_safe();
        bus.with_chip::<Mcp23017, _>(0x20, |c| assert_eq!(c.pins() & 0xFF, 0x0F));
        rt.cmd.publish(DioCmd {
            out: 0x00F0,
            safe: 0x000F,
        });
        let end = std::time::Instant::now() + Duration::from_secs(30);
        while bus
            .with_chip::<Mcp23017, _>(0x20, |c| c.pins() & 0xFF)
            .unwrap()
            != 0xF0
        {
            assert!(std::time::Instant::now() < end, "write did not resume");
            std::thread::sleep(Duration::from_millis(1));
        }
        stop.store(true, Relaxed);
        helper.join().unwrap();
    }

    #[test]
    fn workers_are_shared_per_instance_and_bus_and_stop_with_their_last_user() {
        let open = || -> Result<OpenedBus, std::io::Error> {
            let b = Arc::new(SimBus::new("s", Arc::new(SimClock::following_thread())));
            Ok((b.clone(), Some(b)))
        };
        let a = worker("wk-1", "sim.1", open, |e| e).unwrap();
        let b = worker(
            "wk-1",
            "sim.1",
            || Err(std::io::Error::other("not called")),
            |e| e,
        )
        .unwrap();
        assert!(Arc::ptr_eq(&a, &b));
        let c = worker("wk-2", "sim.1", open, |e| e).unwrap();
        assert!(!Arc::ptr_eq(&a, &c));
        let r = a.reserve(0x40, "pca9685.0").unwrap();
        assert!(matches!(
            a.reserve(0x40, "mcp23017.0"),
            Err(I2cError::AddressInUse { by, .. }) if by == "pca9685.0"
        ));
        drop(r);
        assert!(a.reserve(0x40, "mcp23017.0").is_ok());
        let end = std::time::Instant::now() + Duration::from_secs(30);
        while a.cycles() < 3 {
            assert!(std::time::Instant::now() < end, "helper thread runs");
            std::thread::sleep(Duration::from_millis(1));
        }
        let gone = Arc::downgrade(&a);
        drop((a, b, c));
        assert!(gone.upgrade().is_none(), "stopped with its last user");
        assert!(
            worker("wk-1", "sim.1", open, |e| e).is_ok(),
            "a new one starts"
        );
    }
}
