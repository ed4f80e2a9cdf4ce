//! The cyclic engine: what the `read` and `write` functions do each
//! servo period, for every drive on one bus.
//!
//! * `read`: [`CanBus::tick`], then every frame waiting (up to a budget,
//!   so a flood cannot hold the cycle): TPDOs, EMCYs, heartbeats, error
//!   frames. Then supervision, per drive: TPDOs after the last SYNC,
//!   heartbeat age and state byte, the drive's own Fault, homing
//!   progress. Then the feedback ([`DriveStatus`]).
//! * `write`: per drive the controlword from the power-state planner
//!   (`enable`, the fault latch, `fault-reset`), the mode byte and the
//!   target, as RPDO1; then SYNC; then the master's heartbeat when due.
//!
//! Both use only the endpoint's non-blocking calls: no system call that
//! can wait, no allocation, no lock (the simulated bus excepted, see
//! [`crate::bus::SimBus`]).
//!
//! # Faults
//!
//! Every detection trips the drive's
//! [`FaultLatch`](hal_driver::fault::FaultLatch) in the `read` of the
//! period it is seen in (bus errors trip every drive), logs one line with
//! the drive, the node and the cause, and asks the helper for the drive's
//! error register and history. From that period's `write` on, the drive
//! gets quick stop (controlword 0x0002) for up to `quick_stop_ns`, then
//! disable voltage (0x0000) for as long as the latch holds. Recovery
//! takes a rising edge on `fault-reset`: a drive-side fault (EMCY, Fault
//! state, homing error) gets the CiA 402 fault-reset edge and the latch
//! clears when the drive leaves Fault; a communication fault (bus-off,
//! controller error, no ACK, missed heartbeat, node out of Operational,
//! missing TPDOs, failed sends) has the helper bring the node up again
//! from NMT reset, and the latch clears when that succeeds. Either way
//! `enable` must then go low and high again before the drive is enabled.
//!
//! Unload, exit and a panic elsewhere bring every drive to a safe state
//! from outside the realtime functions ([`Engine::go_safe`], module
//! `safe`): every frame of it is checked, and each drive must confirm
//! disable voltage.

mod cell;
mod drive;
pub mod faults;
mod safe;
mod shared;

use std::sync::Arc;

use hal_driver::LogSink;

pub use cell::RtCell;
use drive::DriveRt;
pub use safe::{SafeReport, Unconfirmed};
pub use shared::{DriveShared, Restart};

use crate::bus::CanBus;
use crate::frame::{Frame, FrameKind};
use crate::power::PowerState;
use crate::regs::{cob, err, nmt};
use crate::startup::{DeviceIdentity, Mode, NodeInfo, NodePlan};

/// Frames read per `read` at most.
pub const DEFAULT_RX_BUDGET: usize = 256;

/// Settings of the cyclic engine.
#[derive(Debug, Clone)]
pub struct EngineConfig {
    /// Whether `write` sends SYNC (false: another device produces it).
    pub sync_producer: bool,
    /// Consecutive periods without a drive's TPDOs before it faults.
    pub tpdo_misses: u32,
    /// A drive whose heartbeat is older than this faults (0 = not
    /// watched).
    pub heartbeat_timeout_ns: u64,
    /// The master's heartbeat: node id and period.
    pub master_heartbeat: Option<(u8, u64)>,
    /// How long a faulted drive gets quick stop before disable voltage.
    pub quick_stop_ns: u64,
    /// The servo period the drives were set up for (0 = not checked).
    pub period_ns: u64,
    /// Frames read per cycle at most.
    pub rx_budget: usize,
}

impl Default for EngineConfig {
    fn default() -> EngineConfig {
        EngineConfig {
            sync_producer: true,
            tpdo_misses: 3,
            heartbeat_timeout_ns: 300_000_000,
            master_heartbeat: Some((127, 100_000_000)),
            quick_stop_ns: 1_000_000_000,
            period_ns: 0,
            rx_budget: DEFAULT_RX_BUDGET,
        }
    }
}

/// One drive's inputs for a cycle (from its HAL pins and params): the
/// shared CiA 402 layer's.
pub use hal_cia402::DriveInputs;

/// One drive's outputs for a cycle (to its HAL pins).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DriveStatus {
    /// `position-fb` (user units). While the drive homes it echoes
    /// `position-cmd`, so the motion core's following error stays calm.
    pub position_fb: f64,
    /// `velocity-fb` (user units/s).
    pub velocity_fb: f64,
    /// The statusword.
    pub statusword: u16,
    /// The power state it shows.
    pub state: Option<PowerState>,
    /// 0x6061.
    pub mode_display: i8,
    /// The drive's error code: the last EMCY's, else 0x603F.
    pub error_code: u16,
    /// `amp-fault`: the latch is tripped or the drive is in Fault.
    pub amp_fault: bool,
    /// `fault-code`: the latch's fault code (0 = clear).
    pub fault_code: u32,
    /// Operation enabled and not faulted.
    pub enabled: bool,
    /// Drive-internal homing finished this cycle: `home` goes false.
    pub home_clear: bool,
    /// Drive-internal homing in progress.
    pub homing: bool,
    /// The last homing succeeded.
    pub home_complete: bool,
    /// The heartbeat's NMT state byte.
    pub nmt_state: u8,
    /// 0x1001 as the helper last read it.
    pub error_register: u32,
    /// Malformed frames from this drive.
    pub bad_frames: u32,
}

/// The engine of one bus.
pub struct Engine {
    bus: Arc<dyn CanBus>,
    drives: Vec<DriveRt>,
    by_node: [u8; 128],
    cfg: EngineConfig,
    log: Option<LogSink>,
    helper: bool,
    status: Vec<DriveStatus>,
    sync_sent: bool,
    next_master_heartbeat: u64,
    tx_fail_cycles: u32,
    error_frames: u64,
    frames_read: u64,
}

impl std::fmt::Debug for Engine {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Engine")
            .field("bus", &self.bus.describe())
            .field("drives", &self.drives.len())
            .finish()
    }
}

impl Engine {
    /// The engine for `nodes` (an operational network's) on `bus`, the
    /// realtime endpoint. `shared` holds one entry per node; `helper`
    /// says whether a helper thread serves restarts (without one, a
    /// fault reset of a communication fault only clears the latch and
    /// starts supervising afresh).
    pub fn new(
        bus: Arc<dyn CanBus>,
        nodes: Vec<NodeInfo>,
        shared: Vec<Arc<DriveShared>>,
        cfg: EngineConfig,
        log: Option<LogSink>,
        helper: bool,
    ) -> Engine {
        let mut by_node = [0u8; 128];
        let drives: Vec<DriveRt> = nodes
            .iter()
            .zip(shared)
            .enumerate()
            .map(|(i, (n, s))| {
                by_node[usize::from(n.plan.node & 0x7F)] = i as u8 + 1;
                DriveRt::new(i, n.plan.node, n.plan.mode, s)
            })
            .collect();
        let status = vec![DriveStatus::default(); drives.len()];
        Engine {
            bus,
            drives,
            by_node,
            cfg,
            log,
            helper,
            status,
            sync_sent: false,
            next_master_heartbeat: 0,
            tx_fail_cycles: 0,
            error_frames: 0,
            frames_read: 0,
        }
    }

    /// An engine for drives at `nodes` in `mode` that were not brought
    /// up by this process (no identity known, no helper): for replaying
    /// recorded traffic and for fuzzing the reception.
    pub fn without_startup(
        bus: Arc<dyn CanBus>,
        nodes: &[u8],
        mode: Mode,
        cfg: EngineConfig,
    ) -> Engine {
        let infos = nodes
            .iter()
            .map(|&node| NodeInfo {
                plan: NodePlan {
                    node,
                    mode,
                    file: None,
                },
                identity: DeviceIdentity::default(),
            })
            .collect();
        let shared = nodes
            .iter()
            .map(|_| Arc::new(DriveShared::default()))
            .collect();
        Engine::new(bus, infos, shared, cfg, None, false)
    }

    /// Number of drives.
    pub fn len(&self) -> usize {
        self.drives.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.drives.is_empty()
    }

    /// The node of drive `i`.
    pub fn node(&self, i: usize) -> u8 {
        self.drives[i].node
    }

    /// The feedback of the last `read`.
    pub fn status(&self) -> &[DriveStatus] {
        &self.status
    }

    /// The controlword and target last sent to drive `i`.
    pub fn last_command(&self, i: usize) -> (u16, i32) {
        (self.drives[i].controlword(), self.drives[i].target())
    }

    /// Error frames and frames read so far.
    pub fn counters(&self) -> (u64, u64) {
        (self.error_frames, self.frames_read)
    }

    /// The bus endpoint's failed sends and receives.
    pub fn bus_errors(&self) -> u64 {
        self.bus.errors()
    }

    fn trip_all(&mut self, fault: &'static hal_driver::fault::Fault) {
        for d in &mut self.drives {
            d.trip(fault, self.log.as_ref(), 0);
        }
    }

    fn bus_error(&mut self, f: &Frame) {
        self.error_frames += 1;
        let class = f.id;
        if class & err::BUSOFF != 0 {
            self.trip_all(&faults::BUS_OFF);
        }
        let serious = err::CRTL_RX_OVERFLOW
            | err::CRTL_TX_OVERFLOW
            | err::CRTL_RX_PASSIVE
            | err::CRTL_TX_PASSIVE;
        if class & err::CRTL != 0 && f.data[1] & serious != 0 || class & err::TX_TIMEOUT != 0 {
            self.trip_all(&faults::CONTROLLER);
        }
        if class & err::ACK != 0 {
            self.trip_all(&faults::NO_ACK);
        }
    }

    fn dispatch(&mut self, f: &Frame, now_ns: u64) {
        if f.kind == FrameKind::Error {
            self.bus_error(f);
            return;
        }
        let Some(id) = f.cob_id() else { return };
        let Some((base, node)) = cob::split(id) else {
            return;
        };
        let i = self.by_node[usize::from(node)];
        if i == 0 {
            return;
        }
        self.drives[usize::from(i - 1)].take(base, f, now_ns, self.log.as_ref());
    }

    /// The `read` function: reception, supervision, feedback.
    pub fn read(&mut self, now_ns: u64, inputs: &[DriveInputs]) {
        self.bus.tick(now_ns);
        for d in &mut self.drives {
            d.begin_cycle();
        }
        for _ in 0..self.cfg.rx_budget {
            let Some(f) = self.bus.try_recv() else { break };
            self.frames_read += 1;
            self.dispatch(&f, now_ns);
        }
        let expect = self.sync_sent;
        let (misses, hb) = (self.cfg.tpdo_misses, self.cfg.heartbeat_timeout_ns);
        for (i, d) in self.drives.iter_mut().enumerate() {
            d.supervise(now_ns, expect, misses, hb, self.log.as_ref());
            let inp = inputs.get(i).copied().unwrap_or_default();
            self.status[i] = d.status(&inp);
        }
    }

    /// The `write` function: RPDOs, SYNC, the master's heartbeat.
    /// `period_ns` is the calling thread's period.
    pub fn write(&mut self, now_ns: u64, period_ns: i64, inputs: &[DriveInputs]) {
        let want = self.cfg.period_ns;
        if want > 0 && (period_ns.unsigned_abs()).abs_diff(want) > want / 100 {
            self.trip_all(&faults::PERIOD);
        }
        let mut failed = false;
        for (i, d) in self.drives.iter_mut().enumerate() {
            let inp = inputs.get(i).copied().unwrap_or_default();
            if let Some(f) = d.rpdo(&inp, now_ns, self.cfg.quick_stop_ns, self.helper) {
                failed |= !self.bus.send(&f);
            }
        }
        if self.cfg.sync_producer {
            let ok = self.bus.send(&Frame::new(cob::SYNC, &[]));
            failed |= !ok;
            self.sync_sent = ok;
        } else {
            self.sync_sent = true;
        }
        if let Some((node, period)) = self.cfg.master_heartbeat {
            if now_ns >= self.next_master_heartbeat {
                let hb = Frame::new(cob::HEARTBEAT + u16::from(node), &[nmt::STATE_OPERATIONAL]);
                failed |= !self.bus.send(&hb);
                self.next_master_heartbeat = now_ns.max(self.next_master_heartbeat) + period;
            }
        }
        if failed {
            self.tx_fail_cycles += 1;
            if self.tx_fail_cycles >= 3 {
                self.trip_all(&faults::TX_FAILED);
            }
        } else {
            self.tx_fail_cycles = 0;
        }
    }
}
