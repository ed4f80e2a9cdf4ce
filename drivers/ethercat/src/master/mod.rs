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
//! * [`Cyclic::write`] publishes the outputs (safe values, zeros, for
//!   slaves that are not healthy) and wakes the helper (one futex wake
//!   through `Thread::unpark`). Worst case: a copy of the output image
//!   plus that system call; it never waits.
//!
//! The helper sends the frame at once, waits for it up to the PDU
//! timeout (one period by default), and publishes the inputs, the
//! working counter and each slave's AL state; a frame that does not come
//! back is counted as lost, never waited for by the realtime side.
//!
//! Faults: a working counter short of the expected one, a slave not in
//! OP (lost, reset, AL error), or the link down make the affected slaves
//! unhealthy; `write` gives them safe outputs from that period on, and
//! [`Cyclic::fault_reset`] asks the helper to bring slaves in SAFE-OP or
//! PRE-OP back to OP (AL control with error acknowledge).

pub mod exchange;
pub(crate) mod io;

use std::future::Future;
use std::ops::Range;
use std::pin::pin;
use std::sync::atomic::{AtomicBool, AtomicU16, AtomicU32, AtomicU64, AtomicU8, Ordering::*};
use std::sync::{mpsc, Arc};
use std::task::Poll;
use std::thread::{JoinHandle, Thread};
use std::time::{Duration, Instant};

use ethercrab::std::ethercat_now;
use ethercrab::{MainDevice, MainDeviceConfig, PduStorage, SubDeviceState, Timeouts};

use crate::error::{Error, Result};
use crate::link::Link;
use crate::regs::{self, al};
use exchange::Exchange;
use io::Io;

/// Slaves per master at most.
pub const MAX_SLAVES: usize = 64;
/// Process image bytes at most.
pub const MAX_PDI: usize = 4096;
const MAX_FRAMES: usize = 16;
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
}

impl Default for MasterConfig {
    fn default() -> MasterConfig {
        MasterConfig {
            period_ns: 1_000_000,
            slaves: Vec::new(),
            state_timeout: Duration::from_secs(5),
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
    tag: u64,
    last_read_tag: u64,
    wkc: u16,
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
            slaves: slaves.clone(),
            shared: shared.clone(),
            tag: 0,
            last_read_tag: 0,
            wkc: 0,
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

    /// Publishes the outputs (zeros for unhealthy slaves) and wakes the
    /// helper to send the frame. Never waits.
    pub fn write(&mut self) {
        self.staged.copy_from_slice(&self.outputs);
        for (s, ok) in self.slaves.iter().zip(&self.healthy) {
            if !ok {
                if let Some(o) = self.staged.get_mut(s.outputs.clone()) {
                    o.fill(0);
                }
            }
        }
        self.tag += 1;
        self.shared.outputs.write(&self.staged, self.tag);
        self.shared.counters.cycles.fetch_add(1, Relaxed);
        self.helper.unpark();
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
        pdu: Duration::from_millis(50),
        // Generous: a loaded machine must not fail a bring-up.
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
    let (group, shared, slaves) = match up {
        Ok(x) => x,
        Err(e) => {
            let _ = ready.send(Err(e));
            return;
        }
    };
    if ready.send(Ok((shared.clone(), slaves.clone()))).is_err() {
        return;
    }
    serve(&md, &mut io, &group, &shared, &slaves, &cfg);
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
) -> Result<(Group, Arc<Shared>, Vec<SlaveInfo>)> {
    let group = io
        .block_on(md.init_single_group::<MAX_SLAVES, MAX_PDI>(ethercat_now))
        .map_err(|e| master_error(iface, "scanning the segment (INIT to PRE-OP)", e))?;
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
        let id = sd.identity();
        if let Some((vid, pid)) = plan.identity {
            if (id.vendor_id, id.product_id) != (vid, pid) {
                return Err(Error::SlaveMismatch {
                    position: plan.position,
                    name: plan.name.clone(),
                    reason: format!(
                        "configured as vendor {vid:#010x} product {pid:#010x}, found {} (vendor {:#010x} product {:#010x})",
                        sd.name(),
                        id.vendor_id,
                        id.product_id
                    ),
                });
            }
        }
        for w in &plan.sdos {
            let sub = match w.sub {
                Some(s) => ethercrab::SubIndex::Index(s),
                None => ethercrab::SubIndex::Complete,
            };
            io.block_on(sd.sdo_write(w.index, sub, w.data.as_slice()))
                .map_err(|e| Error::SlaveMismatch {
                    position: plan.position,
                    name: plan.name.clone(),
                    reason: format!(
                        "SDO write of {:#06x}:{:?} ({} bytes) failed: {e}",
                        w.index,
                        w.sub,
                        w.data.len()
                    ),
                })?;
        }
    }
    let group = io
        .block_on(group.into_op(md))
        .map_err(|e| master_error(iface, "bringing the segment to OP", e))?;
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
    });
    Ok((group, shared, slaves))
}

fn serve(
    md: &MainDevice<'_>,
    io: &mut Io<'_>,
    group: &Group,
    shared: &Shared,
    slaves: &[SlaveInfo],
    cfg: &MasterConfig,
) {
    let mut out = vec![0u8; shared.outputs.len()];
    let mut inp = vec![0u8; shared.inputs.len()];
    let mut last_writes = 0;
    let period = Duration::from_nanos(cfg.period_ns.max(1000));
    while !shared.stop.load(Acquire) {
        if shared.reset.swap(false, AcqRel) {
            reset_slaves(md, io, group, shared);
        }
        let writes = shared.outputs.writes();
        if writes == last_writes {
            std::thread::park_timeout(period * 4);
            continue;
        }
        if writes > last_writes + 1 {
            shared
                .counters
                .skipped
                .fetch_add(writes - last_writes - 1, Relaxed);
        }
        last_writes = writes;
        let Some(tag) = shared.outputs.read(&mut out) else {
            continue;
        };
        for (s, sd) in slaves.iter().zip(group.iter(md)) {
            let mut raw = sd.io_raw_mut();
            let o = raw.outputs();
            if let Some(src) = out.get(s.outputs.clone()) {
                if o.len() == src.len() {
                    o.copy_from_slice(src);
                }
            }
        }
        shared.link_up.store(io.link.is_up(), Relaxed);
        let started = Instant::now();
        let r = io.block_on(with_deadline(group.tx_rx(md), started + period));
        match r {
            Some(Ok(resp)) => {
                shared.frame_ns.store(
                    started.elapsed().as_nanos().min(u128::from(u32::MAX)) as u32,
                    Relaxed,
                );
                for (i, st) in resp.subdevice_states.iter().enumerate() {
                    if let Some(a) = shared.states.get(i) {
                        a.store(state_byte(*st), Relaxed);
                    }
                }
                if resp.working_counter < shared.expected_wkc {
                    shared.counters.wkc_short.fetch_add(1, Relaxed);
                }
                shared.wkc.store(resp.working_counter, Release);
                for (s, sd) in slaves.iter().zip(group.iter(md)) {
                    let raw = sd.io_raw();
                    if let Some(dst) = inp.get_mut(s.inputs.clone()) {
                        if raw.inputs().len() == dst.len() {
                            dst.copy_from_slice(raw.inputs());
                        }
                    }
                }
                shared.inputs.write(&inp, tag);
            }
            _ => {
                shared.counters.lost.fetch_add(1, Relaxed);
                shared.wkc.store(0, Release);
                // No frame back: as far as the slaves go, the link is down.
                shared.link_up.store(false, Relaxed);
            }
        }
    }
}

/// The future's output, or None once `deadline` passes.
async fn with_deadline<F: Future>(fut: F, deadline: Instant) -> Option<F::Output> {
    let mut fut = pin!(fut);
    std::future::poll_fn(|cx| {
        if let Poll::Ready(v) = fut.as_mut().poll(cx) {
            return Poll::Ready(Some(v));
        }
        if Instant::now() >= deadline {
            return Poll::Ready(None);
        }
        Poll::Pending
    })
    .await
}

fn state_byte(s: SubDeviceState) -> u8 {
    match s {
        SubDeviceState::Init => al::INIT,
        SubDeviceState::PreOp => al::PREOP,
        SubDeviceState::Bootstrap => al::BOOT,
        SubDeviceState::SafeOp => al::SAFEOP,
        SubDeviceState::Op => al::OP,
        SubDeviceState::Other(b) => b,
        SubDeviceState::None => 0,
    }
}

/// Slaves in SAFE-OP or PRE-OP (an AL error, a lost and found slave)
/// are asked back to OP with the error acknowledged.
fn reset_slaves(md: &MainDevice<'_>, io: &mut Io<'_>, group: &Group, shared: &Shared) {
    for (i, sd) in group.iter(md).enumerate() {
        let state = shared.states.get(i).map_or(0, |s| s.load(Relaxed)) & al::STATE_MASK;
        let steps: &[u8] = match state {
            al::OP => &[],
            al::SAFEOP => &[al::OP],
            al::PREOP => &[al::SAFEOP, al::OP],
            _ => &[],
        };
        for &to in steps {
            let request = u16::from(to | al::ERROR);
            let _ = io.block_on(sd.register_write(regs::AL_CONTROL, request));
            let deadline = Instant::now() + Duration::from_millis(500);
            while Instant::now() < deadline {
                match io.block_on(sd.register_read::<u16>(regs::AL_STATUS)) {
                    Ok(s) if s as u8 & al::STATE_MASK == to => break,
                    _ => std::thread::sleep(Duration::from_millis(1)),
                }
            }
        }
    }
}
