//! The master on EtherCrab.
//!
//! [`Master::start`] spawns the helper thread that owns EtherCrab (its
//! frame storage, `MainDevice` and the group) and drives its frames over
//! a [`Link`] itself: no async runtime, the futures are polled in a loop
//! that sends what EtherCrab queued and feeds back what arrives. The
//! helper brings the segment up (addresses, SII, mailbox, the
//! configuration's SDO writes in PRE-OP, PDO sizes, SAFE-OP, OP) and
//! returns the slaves found; then it serves cycles.
//!
//! The realtime side is a [`Cyclic`]:
//!
//! * [`Cyclic::read`] takes the inputs of the last completed frame from
//!   a lock-free hand-off ([`exchange::Exchange`]). It never waits: if
//!   the frame of the last `write` has not come back it keeps the
//!   previous inputs and counts a late frame. Worst case: a copy of the
//!   input image plus a bounded retry (4 tries) when the helper is
//!   publishing at that instant.
//! * [`Cyclic::write`] publishes the outputs (for slaves that are not
//!   healthy their safe values: the caller's, per slave and meaning,
//!   where it said it makes them ([`Cyclic::caller_makes_safe`]), else
//!   zeros) and the time; it does not wake the
//!   helper, which looks for the write when it is due (a step of 1/40 of
//!   the period at most after it). Worst case: a copy of the output
//!   image and a clock read (vDSO); after an idle spell of four periods
//!   one futex wake. It never waits.
//!
//! The helper sends the frame once it sees it, waits for it up to the PDU
//! timeout (one period by default), and publishes the inputs, the
//! working counter and each slave's AL state; a frame that does not come
//! back is counted as lost, never waited for by the realtime side, and
//! [`LOST_LIMIT`] lost in a row make the link down.
//!
//! Faults: a working counter short of the expected one, a slave not in
//! OP (lost, reset, AL error), or the link down make the affected slaves
//! unhealthy; `write` gives them safe outputs from that period on, and
//! [`Cyclic::fault_reset`] asks the helper to bring slaves in SAFE-OP or
//! PRE-OP back to OP (AL control with error acknowledge). A slave that
//! lost its configuration (power-cycled, replugged: INIT without a
//! station address) is brought back to OP by the helper on its own,
//! between cycles ([`recover`]).

pub mod dc;
pub mod emcy;
pub mod exchange;
pub(crate) mod io;
pub mod layout;
pub mod pll;
mod recover;
mod serve;

use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU16, AtomicU32, AtomicU64, AtomicU8, Ordering::*};
use std::sync::{mpsc, Arc};
use std::thread::{JoinHandle, Thread};
use std::time::Duration;

use ethercrab::std::ethercat_now;
use ethercrab::{MainDevice, MainDeviceConfig, PduStorage, Timeouts};

use crate::error::{Error, Result};
use crate::link::Link;
use crate::regs::al;
use dc::DcCycle;
pub use dc::DcPlan;
use exchange::Exchange;
use io::Io;
pub use layout::{Layout, MappedEntry};
pub use recover::Failure;

/// Slaves per master at most.
pub const MAX_SLAVES: usize = 64;
/// Process image bytes at most.
pub const MAX_PDI: usize = 4096;
const MAX_FRAMES: usize = 16;
/// Frames lost in a row before the master calls the link down (and every
/// slave unhealthy): one late frame on a loaded machine is counted, not
/// a fault; three in a row are.
pub const LOST_LIMIT: u32 = 3;
const FRAME_DATA: usize = PduStorage::element_size(1100);

/// An SDO write of the configuration, done in PRE-OP.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SdoWrite {
    /// Index.
    pub index: u16,
    /// Sub-index; None for complete access.
    pub sub: Option<u8>,
    /// The bytes (little-endian value).
    pub data: Vec<u8>,
}

/// What the configuration says of one slave.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SlavePlan {
    /// Position on the segment.
    pub position: u16,
    /// Name (for messages and pins).
    pub name: String,
    /// Expected vendor id and product code, checked at bring-up.
    pub identity: Option<(u32, u32)>,
    /// SDO writes in PRE-OP, in order.
    pub sdos: Vec<SdoWrite>,
    /// Its SYNC unit (`<dcConf>`), set up in PRE-OP after the SDOs.
    pub dc: Option<DcPlan>,
    /// Poll its mailbox for emergencies during cycles (CiA 402 drives).
    pub emergencies: bool,
}

/// The master's settings.
#[derive(Debug, Clone)]
pub struct MasterConfig {
    /// The servo period (the PDU timeout of a cycle's frame).
    pub period_ns: u64,
    /// The configured slaves (others found on the segment run with
    /// their defaults).
    pub slaves: Vec<SlavePlan>,
    /// How long bring-up may take per state change.
    pub state_timeout: Duration,
    /// How long the helper waits for a cycle's frame before counting it
    /// lost; None: one period. (The realtime side never waits either
    /// way.) A simulated segment in process loses no frame on a wire, so
    /// `loadrt lcec backend=sim` gives it 100 ms: a starved test machine
    /// must not look like a broken cable.
    pub frame_timeout: Option<Duration>,
    /// With SYNC in use, the application time goes to the reference
    /// clock every this many cycles (`refClockSyncCycles`; 0 or less:
    /// never).
    pub ref_clock_sync_cycles: i32,
    /// `syncToRefClock`: the reference clock runs free and the
    /// application time follows it ([`pll`]); the master writes no
    /// time to it.
    pub sync_to_ref_clock: bool,
}

impl Default for MasterConfig {
    fn default() -> MasterConfig {
        MasterConfig {
            period_ns: 1_000_000,
            slaves: Vec::new(),
            state_timeout: Duration::from_secs(5),
            frame_timeout: None,
            ref_clock_sync_cycles: 1,
            sync_to_ref_clock: false,
        }
    }
}

/// A slave as found at bring-up.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlaveInfo {
    /// Position.
    pub position: u16,
    /// Station address.
    pub station: u16,
    /// Name from the SII.
    pub name: String,
    /// Vendor, product, revision, serial.
    pub identity: (u32, u32, u32, u32),
    /// Its inputs in the input image.
    pub inputs: Range<usize>,
    /// Its outputs in the output image.
    pub outputs: Range<usize>,
    /// Where its entries sit in its inputs and outputs.
    pub layout: Layout,
}

/// Counters the realtime side and the helper keep.
#[derive(Debug, Default)]
pub struct Counters {
    /// Cycles written.
    pub cycles: AtomicU64,
    /// `read`s that found no newer frame than the last.
    pub late: AtomicU64,
    /// Frames that did not come back within the PDU timeout.
    pub lost: AtomicU64,
    /// Cycles whose working counter was short.
    pub wkc_short: AtomicU64,
    /// Writes the helper skipped because it was still busy (overruns).
    pub skipped: AtomicU64,
}

/// What the helper and the realtime side share.
#[derive(Debug)]
struct Shared {
    outputs: Exchange,
    inputs: Exchange,
    /// Per slave: AL state byte as the last frame read it.
    states: Box<[AtomicU8]>,
    wkc: AtomicU16,
    expected_wkc: u16,
    link_up: AtomicBool,
    reset: AtomicBool,
    stop: AtomicBool,
    counters: Counters,
    frame_ns: AtomicU32,
    /// CLOCK_MONOTONIC ns of the last `write` (0: none yet): when the
    /// helper expects the next.
    written_at: AtomicU64,
    clocks: Clocks,
    emergencies: emcy::Slots,
    /// Per slave: a different device was found at its position when it
    /// was to be brought back ([`recover`]), and what it is (vendor id
    /// << 32 | product code).
    refused: Box<[AtomicBool]>,
    found: Box<[AtomicU64]>,
    /// Per slave: why the last try to bring it back failed
    /// ([`recover::Failure`] as a code; 0: none).
    recovery: Box<[AtomicU8]>,
}

/// The distributed clocks as the helper and the realtime side see them.
#[derive(Debug, Default)]
struct Clocks {
    /// Some slave's SYNC unit is set up.
    in_use: bool,
    /// EtherCAT time minus CLOCK_MONOTONIC (ns): the application time
    /// of a monotonic time.
    base: i64,
    /// The reference clock's system time as the last frame read it.
    reference: AtomicU64,
    /// The largest clock difference (ns), or [`dc::NOT_HEARD`].
    diff: AtomicU32,
    /// Whether the helper reads the difference each cycle.
    monitor: AtomicBool,
}

/// What the realtime side knows of the clocks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DcStatus {
    /// Some slave's SYNC unit is set up.
    pub in_use: bool,
    /// The reference clock's system time at the last frame (0: none).
    pub reference_time: u64,
    /// The largest clock difference (ns; [`dc::NOT_HEARD`] while the
    /// monitor hears nothing).
    pub diff: u32,
}

/// The non-realtime handle: owns the helper thread.
#[derive(Debug)]
pub struct Master {
    thread: Option<JoinHandle<()>>,
    shared: Arc<Shared>,
    slaves: Vec<SlaveInfo>,
    iface: String,
}

/// The realtime handle: `read` and `write` each period.
#[derive(Debug)]
pub struct Cyclic {
    shared: Arc<Shared>,
    helper: Thread,
    slaves: Vec<SlaveInfo>,
    inputs: Vec<u8>,
    outputs: Vec<u8>,
    staged: Vec<u8>,
    healthy: Vec<bool>,
    /// Per slave: the caller fills its safe outputs itself while it is
    /// unhealthy ([`Cyclic::caller_makes_safe`]); `write` zeroes the
    /// others'.
    caller_safe: Vec<bool>,
    tag: u64,
    last_read_tag: u64,
    wkc: u16,
    /// EtherCAT time minus CLOCK_MONOTONIC (ns).
    app_base: i64,
    /// Per slave: the count of the last emergency taken.
    emcy_seen: Vec<u32>,
    /// CLOCK_MONOTONIC ns of the last `write`.
    last_write_ns: u64,
    /// The servo period (ns).
    period_ns: u64,
}

/// What one `read` found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReadStatus {
    /// The inputs are from the last `write`'s frame.
    pub fresh: bool,
    /// Working counter of that frame.
    pub wkc: u16,
    /// Working counter expected when every slave exchanges its data.
    pub expected_wkc: u16,
    /// The link has carrier.
    pub link_up: bool,
    /// Every slave is in OP and the working counter is complete.
    pub all_op: bool,
}

impl Master {
    /// Starts the helper on `link` and brings the segment to OP.
    pub fn start(link: Box<dyn Link>, cfg: MasterConfig) -> Result<(Master, Cyclic)> {
        let iface = link.describe();
        let period_ns = cfg.period_ns.max(1000);
        let (tx, rx) = mpsc::channel();
        let name = format!(
            "ethercat-{}",
            iface.split_whitespace().next().unwrap_or("sim")
        );
        let thread = std::thread::Builder::new()
            .name(name)
            .spawn(move || helper(link, cfg, tx))
            .map_err(|e| Error::Master {
                iface: iface.clone(),
                step: "starting the helper thread".into(),
                reason: e.to_string(),
            })?;
        let (shared, slaves) = match rx.recv() {
            Ok(Ok(x)) => x,
            Ok(Err(e)) => {
                let _ = thread.join();
                return Err(e);
            }
            Err(_) => {
                let _ = thread.join();
                return Err(Error::Master {
                    iface,
                    step: "bring-up".into(),
                    reason: "the helper thread ended without an answer".into(),
                });
            }
        };
        let cyclic = Cyclic {
            helper: thread.thread().clone(),
            inputs: vec![0; shared.inputs.len()],
            outputs: vec![0; shared.outputs.len()],
            staged: vec![0; shared.outputs.len()],
            healthy: vec![true; slaves.len()],
            caller_safe: vec![false; slaves.len()],
            slaves: slaves.clone(),
            shared: shared.clone(),
            tag: 0,
            last_read_tag: 0,
            last_write_ns: 0,
            period_ns,
            wkc: 0,
            app_base: shared.clocks.base,
            emcy_seen: vec![0; slaves.len()],
        };
        Ok((
            Master {
                thread: Some(thread),
                shared,
                slaves,
                iface,
            },
            cyclic,
        ))
    }

    /// The slaves found.
    pub fn slaves(&self) -> &[SlaveInfo] {
        &self.slaves
    }

    /// The counters.
    pub fn counters(&self) -> &Counters {
        &self.shared.counters
    }

    /// The interface.
    pub fn iface(&self) -> &str {
        &self.iface
    }

    /// Stops the helper (the slaves' watchdogs and state take over).
    pub fn stop(&mut self) {
        self.shared.stop.store(true, Release);
        if let Some(t) = self.thread.take() {
            t.thread().unpark();
            let _ = t.join();
        }
    }
}

impl Drop for Master {
    fn drop(&mut self) {
        self.stop();
    }
}

impl Cyclic {
    /// The slaves.
    pub fn slaves(&self) -> &[SlaveInfo] {
        &self.slaves
    }

    /// Takes the inputs of the last completed frame. Never waits.
    pub fn read(&mut self) -> ReadStatus {
        let sh = &self.shared;
        let fresh = match sh.inputs.read(&mut self.inputs) {
            Some(tag) if tag != self.last_read_tag => {
                self.last_read_tag = tag;
                tag == self.tag
            }
            _ => false,
        };
        if !fresh && self.tag > 0 {
            sh.counters.late.fetch_add(1, Relaxed);
        }
        self.wkc = sh.wkc.load(Acquire);
        let link_up = sh.link_up.load(Relaxed);
        let complete = self.wkc >= sh.expected_wkc;
        let mut all_op = link_up && complete;
        for (i, h) in self.healthy.iter_mut().enumerate() {
            let op = sh.states[i].load(Relaxed) & al::STATE_MASK == al::OP;
            *h = op && link_up && complete;
            all_op &= op;
        }
        ReadStatus {
            fresh,
            wkc: self.wkc,
            expected_wkc: sh.expected_wkc,
            link_up,
            all_op,
        }
    }

    /// The input bytes of slave `i` (empty if out of range).
    pub fn inputs(&self, i: usize) -> &[u8] {
        self.slaves
            .get(i)
            .and_then(|s| self.inputs.get(s.inputs.clone()))
            .unwrap_or(&[])
    }

    /// The output bytes of slave `i`, to fill before `write`.
    pub fn outputs_mut(&mut self, i: usize) -> &mut [u8] {
        match self.slaves.get(i) {
            Some(s) => self.outputs.get_mut(s.outputs.clone()).unwrap_or(&mut []),
            None => &mut [],
        }
    }

    /// Whether slave `i` was healthy at the last `read` (in OP, working
    /// counter complete, link up).
    pub fn healthy(&self, i: usize) -> bool {
        self.healthy.get(i).copied().unwrap_or(false)
    }

    /// The AL state byte of slave `i` as the last frame read it.
    pub fn al_state(&self, i: usize) -> u8 {
        self.shared.states.get(i).map_or(0, |s| s.load(Relaxed))
    }

    /// Slave `i`'s safe outputs are the caller's: while it is unhealthy
    /// the caller puts them in [`Cyclic::outputs_mut`] (per slave and per
    /// meaning: a drive's controlword, an output's level) and `write`
    /// sends them as they are, instead of zeros. One authority over what
    /// goes on the wire, so what the caller reports is what was sent.
    pub fn caller_makes_safe(&mut self, i: usize) {
        if let Some(c) = self.caller_safe.get_mut(i) {
            *c = true;
        }
    }

    /// Publishes the outputs (zeros for unhealthy slaves whose safe
    /// outputs are not the caller's) and the time. Never waits.
    pub fn write(&mut self) {
        self.staged.copy_from_slice(&self.outputs);
        for ((s, ok), own) in self.slaves.iter().zip(&self.healthy).zip(&self.caller_safe) {
            if !ok && !own {
                if let Some(o) = self.staged.get_mut(s.outputs.clone()) {
                    o.fill(0);
                }
            }
        }
        self.tag += 1;
        self.shared.outputs.write(&self.staged, self.tag);
        self.shared
            .written_at
            .store(hal_core::clock::monotonic_ns(), Relaxed);
        self.shared.counters.cycles.fetch_add(1, Relaxed);
        // The helper is not woken: it looks for the write when one is
        // due ([`serve::NextWrite`]); after an idle spell (no write for
        // four periods) it may be parked, and is woken.
        if self.idle_before() {
            self.helper.unpark();
        }
    }

    /// Whether the write before this one was more than four periods ago
    /// (or there was none), so that the helper may be parked.
    fn idle_before(&mut self) -> bool {
        let now = self.shared.written_at.load(Relaxed);
        let idle = now.saturating_sub(self.last_write_ns) > 4 * self.period_ns;
        self.last_write_ns = now;
        idle
    }

    /// Asks the helper to bring slaves that left OP back to it.
    pub fn fault_reset(&self) {
        self.shared.reset.store(true, Release);
        self.helper.unpark();
    }

    /// The counters.
    pub fn counters(&self) -> &Counters {
        &self.shared.counters
    }

    /// The vendor id and product code of the device found at slave `i`'s
    /// position when the master was to bring it back after it lost its
    /// configuration, if that is not the device found at bring-up (the
    /// master refuses to configure it).
    pub fn refused(&self, i: usize) -> Option<(u32, u32)> {
        let flag = self.shared.refused.get(i)?;
        if !flag.load(Acquire) {
            return None;
        }
        let v = self.shared.found.get(i)?.load(Relaxed);
        Some(((v >> 32) as u32, v as u32))
    }

    /// Why the last try to bring slave `i` back (after it lost its
    /// configuration) failed, while it is not back; the helper tries
    /// again every 500 ms.
    pub fn recovery_failure(&self, i: usize) -> Option<Failure> {
        Failure::from_code(self.shared.recovery.get(i)?.load(Relaxed))
    }

    /// The application time (EtherCAT ns) of CLOCK_MONOTONIC time
    /// `mono_ns`: the servo thread's time on the slaves' time base.
    pub fn app_time(&self, mono_ns: u64) -> u64 {
        (mono_ns as i64).wrapping_add(self.app_base) as u64
    }

    /// Whether the helper reads the clocks' difference each cycle
    /// (`dc-sync-monitor`).
    pub fn set_dc_monitor(&self, on: bool) {
        self.shared.clocks.monitor.store(on, Relaxed);
    }

    /// The error code of an emergency slave `i` sent since the last
    /// call, if any (the latest when several came).
    pub fn take_emergency(&mut self, i: usize) -> Option<u16> {
        let (count, code) = self.shared.emergencies.latest(i);
        let seen = self.emcy_seen.get_mut(i)?;
        (count != *seen).then(|| {
            *seen = count;
            code
        })
    }

    /// The clocks as the last frames saw them.
    pub fn dc_status(&self) -> DcStatus {
        let c = &self.shared.clocks;
        DcStatus {
            in_use: c.in_use,
            reference_time: c.reference.load(Relaxed),
            diff: c.diff.load(Relaxed),
        }
    }

    /// How long the helper's last frame took to come back (ns).
    pub fn round_trip_ns(&self) -> u32 {
        self.shared.frame_ns.load(Relaxed)
    }
}

fn master_error(iface: &str, step: &str, e: impl std::fmt::Display) -> Error {
    Error::Master {
        iface: iface.to_string(),
        step: step.to_string(),
        reason: e.to_string(),
    }
}

type Ready = mpsc::Sender<Result<(Arc<Shared>, Vec<SlaveInfo>)>>;

/// The helper thread: bring-up, then cycles until stopped.
fn helper(link: Box<dyn Link>, cfg: MasterConfig, ready: Ready) {
    let iface = link.describe();
    let storage = Box::new(PduStorage::<MAX_FRAMES, FRAME_DATA>::new());
    let Ok((tx, rx, pdu_loop)) = storage.try_split() else {
        let _ = ready.send(Err(master_error(&iface, "frame storage", "already in use")));
        return;
    };
    let timeouts = Timeouts {
        state_transition: cfg.state_timeout,
        // Generous: a loaded machine must not fail a bring-up (50 ms
        // did, now and then, with two masters and their simulators on
        // two busy cores). The cycles do not wait this long: each frame
        // is given up at its period's deadline (serve::with_deadline).
        pdu: Duration::from_millis(200),
        eeprom: Duration::from_millis(500),
        mailbox_echo: Duration::from_millis(500),
        mailbox_response: Duration::from_millis(1000),
        ..Timeouts::default()
    };
    let config = MainDeviceConfig {
        dc_static_sync_iterations: 100,
        ..MainDeviceConfig::default()
    };
    let md = MainDevice::new(pdu_loop, timeouts, config);
    let mut io = Io {
        tx,
        rx,
        link,
        buf: vec![0; 1600],
    };
    let up = bring_up(&md, &mut io, &cfg, &iface);
    let (group, shared, slaves, mut extras) = match up {
        Ok(x) => x,
        Err(e) => {
            let _ = ready.send(Err(e));
            return;
        }
    };
    if ready.send(Ok((shared.clone(), slaves.clone()))).is_err() {
        return;
    }
    serve::serve(&md, &mut io, &group, &shared, &slaves, &cfg, &mut extras);
}

type Group = ethercrab::SubDeviceGroup<
    MAX_SLAVES,
    MAX_PDI,
    ethercrab::DefaultLock,
    ethercrab::subdevice_group::Op,
>;

fn bring_up(
    md: &MainDevice<'_>,
    io: &mut Io<'_>,
    cfg: &MasterConfig,
    iface: &str,
) -> Result<(Group, Arc<Shared>, Vec<SlaveInfo>, serve::Extras)> {
    let group = io
        .block_on(md.init_single_group::<MAX_SLAVES, MAX_PDI>(ethercat_now))
        .map_err(|e| master_error(iface, "scanning the segment (INIT to PRE-OP)", e))?;
    let mut clocks = DcCycle {
        reference: dc::reference(group.iter(md)),
        sync_every: match cfg.sync_to_ref_clock {
            true => 0,
            false => u32::try_from(cfg.ref_clock_sync_cycles).unwrap_or(0),
        },
        ..DcCycle::default()
    };
    for plan in &cfg.slaves {
        let sd = group
            .subdevice(md, usize::from(plan.position))
            .map_err(|_| Error::SlaveMismatch {
                position: plan.position,
                name: plan.name.clone(),
                reason: format!(
                    "configured, but the segment has only {} slaves",
                    group.len()
                ),
            })?;
        apply_plan(md, io, &sd, plan, clocks.reference)?;
        clocks.in_use |= plan.dc.is_some_and(|d| d.assign_activate != 0);
    }
    let mut layouts = Vec::with_capacity(group.len());
    for (i, sd) in group.iter(md).enumerate() {
        layouts.push(layout::read(md, io, &sd, i as u16)?);
    }
    let group = io
        .block_on(group.into_op(md))
        .map_err(|e| master_error(iface, "bringing the segment to OP", e))?;
    let mut mailboxes = emcy::MailboxPoll::default();
    for plan in cfg.slaves.iter().filter(|p| p.emergencies) {
        let i = usize::from(plan.position);
        let mailbox = layouts.get(i).and_then(|l| l.mailbox_in);
        if let (Some(mailbox), Ok(sd)) = (mailbox, group.subdevice(md, i)) {
            mailboxes.polled.push(emcy::Polled {
                slave: i,
                station: sd.configured_address(),
                mailbox,
            });
        }
    }
    let mut slaves = Vec::new();
    let (mut ins, mut outs) = (0usize, 0usize);
    let mut expected = 0u16;
    for (i, sd) in group.iter(md).enumerate() {
        let io_raw = sd.io_raw();
        let (ni, no) = (io_raw.inputs().len(), io_raw.outputs().len());
        drop(io_raw);
        let id = sd.identity();
        expected += if no > 0 { 2 } else { 0 } + u16::from(ni > 0);
        slaves.push(SlaveInfo {
            position: i as u16,
            station: sd.configured_address(),
            name: sd.name().to_string(),
            identity: (id.vendor_id, id.product_id, id.revision, id.serial),
            inputs: ins..ins + ni,
            outputs: outs..outs + no,
            layout: layouts.get(i).cloned().unwrap_or_default(),
        });
        ins += ni;
        outs += no;
    }
    let shared = Arc::new(Shared {
        outputs: Exchange::new(outs),
        inputs: Exchange::new(ins),
        states: (0..slaves.len()).map(|_| AtomicU8::new(al::OP)).collect(),
        wkc: AtomicU16::new(expected),
        expected_wkc: expected,
        link_up: AtomicBool::new(true),
        reset: AtomicBool::new(false),
        stop: AtomicBool::new(false),
        counters: Counters::default(),
        frame_ns: AtomicU32::new(0),
        written_at: AtomicU64::new(0),
        clocks: Clocks {
            in_use: clocks.in_use,
            base: ethercat_now() as i64 - hal_core::clock::monotonic_ns() as i64,
            monitor: AtomicBool::new(true),
            ..Clocks::default()
        },
        emergencies: emcy::Slots::new(slaves.len()),
        refused: (0..slaves.len()).map(|_| AtomicBool::new(false)).collect(),
        found: (0..slaves.len()).map(|_| AtomicU64::new(0)).collect(),
        recovery: (0..slaves.len()).map(|_| AtomicU8::new(0)).collect(),
    });
    let recovery = recover::Recovery::new(md, io, &slaves);
    Ok((
        group,
        shared,
        slaves,
        serve::Extras {
            clocks,
            mailboxes,
            recovery,
        },
    ))
}

/// What the configuration says of one slave, done in PRE-OP: its
/// identity checked, its SDO writes, its SYNC unit.
fn apply_plan<S: std::ops::Deref<Target = ethercrab::SubDevice>>(
    md: &MainDevice<'_>,
    io: &mut Io<'_>,
    sd: &ethercrab::SubDeviceRef<'_, S>,
    plan: &SlavePlan,
    reference: Option<u16>,
) -> Result<()> {
    let mismatch = |reason: String| Error::SlaveMismatch {
        position: plan.position,
        name: plan.name.clone(),
        reason,
    };
    let id = sd.identity();
    if let Some((vid, pid)) = plan.identity {
        if (id.vendor_id, id.product_id) != (vid, pid) {
            return Err(mismatch(format!(
                "configured as vendor {vid:#010x} product {pid:#010x}, found {} (vendor {:#010x} product {:#010x})",
                sd.name(),
                id.vendor_id,
                id.product_id
            )));
        }
    }
    for w in &plan.sdos {
        let sub = match w.sub {
            Some(s) => ethercrab::SubIndex::Index(s),
            None => ethercrab::SubIndex::Complete,
        };
        io.block_on(sd.sdo_write(w.index, sub, w.data.as_slice()))
            .map_err(|e| {
                mismatch(format!(
                    "SDO write of {:#06x}:{:?} ({} bytes) failed: {e}",
                    w.index,
                    w.sub,
                    w.data.len()
                ))
            })?;
    }
    if let Some(d) = &plan.dc {
        dc::configure_sync(md, io, sd, (plan.position, &plan.name), d, reference)?;
    }
    Ok(())
}
