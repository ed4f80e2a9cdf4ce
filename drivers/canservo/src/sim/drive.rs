//! [`SimDrive`]: a simulated CiA 402 servo drive on a CAN bus
//! (hardware.md §6.12). This file holds the communication side: NMT
//! slave with boot-up and the four states, heartbeat producer and
//! consumer, the SDO server on the object dictionary with the drive's
//! own write rules, the PDO engine (SYNC, synchronous and event-driven
//! types, RTR, the SYNC counter) and EMCY. The drive side (power state
//! machine, modes, homing, monitors) is in `control.rs`.

use hal_driver::plant::Switch;

use super::axis::{Axis, AxisParams};
use super::dictionary::{self, Identity};
use super::od::Od;
use super::pdo::{self, Dir, RpdoState, TpdoState, PDOS};
use crate::codes::{AbortCode, ErrorCode};
use crate::frame::{Frame, FrameKind};
use crate::power::PowerState;
use crate::regs::{cob, nmt, obj};
use crate::sdo::{ObjectAccess, SdoServer};

/// How a simulated drive is built.
#[derive(Debug, Clone)]
pub struct SimDriveConfig {
    /// Node id (1..=127).
    pub node: u8,
    /// What it reports in 0x1000, 0x1008 and 0x1018.
    pub identity: Identity,
    /// Motor and loops.
    pub axis: AxisParams,
    /// Delay before 0x6061 shows a newly written 0x6060 (ns).
    pub mode_delay_ns: u64,
    /// Home switch, in motor counts.
    pub home_switch: Option<Switch>,
    /// Negative limit switch, in motor counts.
    pub negative_limit: Option<Switch>,
    /// Positive limit switch, in motor counts.
    pub positive_limit: Option<Switch>,
}

impl SimDriveConfig {
    /// A drive at `node` with the simulator's identity and motor, a 1 ms
    /// mode change delay and no switches.
    pub fn new(node: u8) -> SimDriveConfig {
        SimDriveConfig {
            node,
            identity: Identity::simulated(node),
            axis: AxisParams::default(),
            mode_delay_ns: 1_000_000,
            home_switch: None,
            negative_limit: None,
            positive_limit: None,
        }
    }
}

/// NMT state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NmtState {
    /// Initialising (left with the boot-up message).
    Initialising,
    /// Pre-operational: SDO, no PDO.
    PreOperational,
    /// Operational.
    Operational,
    /// Stopped: NMT and heartbeat only.
    Stopped,
}

impl NmtState {
    /// The heartbeat state byte.
    pub fn byte(self) -> u8 {
        match self {
            NmtState::Initialising => nmt::STATE_BOOTUP,
            NmtState::PreOperational => nmt::STATE_PRE_OPERATIONAL,
            NmtState::Operational => nmt::STATE_OPERATIONAL,
            NmtState::Stopped => nmt::STATE_STOPPED,
        }
    }
}

/// Faults and misbehaviour a test can inject.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Injection {
    /// A continuous over-current: EMCY 0x2310 and Fault.
    OverCurrent,
    /// A jammed axis (a load past the supply), so the drive's own
    /// following-error monitor trips (EMCY 0x8611, Fault) once it is
    /// asked to move; stays until cleared.
    FollowingError,
    /// The heartbeat stops (everything else goes on); until cleared.
    HeartbeatLoss,
    /// The node sends nothing at all (a broken transmitter); until
    /// cleared.
    Mute,
    /// DC-link under-voltage: EMCY 0x3220 and Fault, and the fault
    /// cannot be reset until cleared.
    UnderVoltage,
}

/// A consumer heartbeat entry's runtime state.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Consumer {
    pub last_ns: u64,
    pub armed: bool,
}

/// A simulated CiA 402 drive.
#[derive(Debug)]
pub struct SimDrive {
    pub(super) cfg: SimDriveConfig,
    pub(super) od: Od,
    pub(super) nmt: NmtState,
    pub(super) sdo: SdoServer,
    pub(super) fsa: PowerState,
    pub(super) axis: Axis,
    pub(super) now_ns: u64,
    pub(super) present: bool,
    hb_next_ns: u64,
    consumers: [Consumer; 4],
    emcy_pending: Option<[u8; 8]>,
    emcy_last_ns: Option<u64>,
    rpdo: [RpdoState; 4],
    tpdo: [TpdoState; 4],
    pub(super) ctl: super::control::Control,
    pub(super) injected: Vec<Injection>,
}

impl SimDrive {
    /// A drive that has not booted yet (see [`power_up`](Self::power_up)).
    pub fn new(cfg: SimDriveConfig) -> SimDrive {
        let od = dictionary::build(cfg.node, &cfg.identity);
        let axis = Axis::new(cfg.axis);
        SimDrive {
            sdo: SdoServer::new(cfg.node),
            od,
            nmt: NmtState::Initialising,
            fsa: PowerState::NotReadyToSwitchOn,
            axis,
            now_ns: 0,
            present: true,
            hb_next_ns: 0,
            consumers: [Consumer::default(); 4],
            emcy_pending: None,
            emcy_last_ns: None,
            rpdo: Default::default(),
            tpdo: Default::default(),
            ctl: Default::default(),
            injected: Vec::new(),
            cfg,
        }
    }

    /// Powers the drive up: self-test, boot-up message, Pre-operational,
    /// Switch on disabled.
    pub fn power_up(&mut self, out: &mut Vec<Frame>) {
        self.od.restore(0x0000..=0xFFFF);
        self.boot(out);
        self.fsa = PowerState::SwitchOnDisabled;
    }

    /// The node id.
    pub fn node(&self) -> u8 {
        self.cfg.node
    }

    /// Whether the drive is on the bus (false: unplugged, it neither
    /// receives nor sends nor acknowledges).
    pub fn is_present(&self) -> bool {
        self.present
    }

    /// Plugs or unplugs the drive.
    pub fn set_present(&mut self, present: bool) {
        self.present = present;
    }

    /// NMT state.
    pub fn nmt_state(&self) -> NmtState {
        self.nmt
    }

    /// Power state.
    pub fn power_state(&self) -> PowerState {
        self.fsa
    }

    /// The drive's simulated time (ns).
    pub fn now_ns(&self) -> u64 {
        self.now_ns
    }

    /// An object's value (0 if it does not exist), as the drive holds it
    /// now.
    pub fn object(&mut self, index: u16, sub: u8) -> i64 {
        self.refresh_objects();
        self.od.get_i64(index, sub)
    }

    /// Sets an object without the SDO checks (a test setting up the
    /// drive as an integrator would have stored it).
    pub fn set_object(&mut self, index: u16, sub: u8, value: i64) {
        self.od.set(index, sub, value);
    }

    /// Position actual (counts), exact.
    pub fn position(&self) -> f64 {
        self.axis.position()
    }

    /// Velocity (counts/s).
    pub fn velocity(&self) -> f64 {
        self.axis.velocity()
    }

    /// Moves the shaft by hand to motor position `counts`.
    pub fn set_motor_position(&mut self, counts: f64) {
        self.axis.set_motor_position(counts);
    }

    /// The switches (motor counts).
    pub fn set_switches(
        &mut self,
        home: Option<Switch>,
        negative: Option<Switch>,
        positive: Option<Switch>,
    ) {
        self.cfg.home_switch = home;
        self.cfg.negative_limit = negative;
        self.cfg.positive_limit = positive;
    }

    /// Injects a fault or a misbehaviour.
    pub fn inject(&mut self, what: Injection, out: &mut Vec<Frame>) {
        match what {
            Injection::OverCurrent => self.raise_fault(ErrorCode::OVER_CURRENT, out),
            Injection::UnderVoltage => {
                self.injected.push(what);
                self.raise_fault(ErrorCode::UNDER_VOLTAGE, out);
            }
            Injection::FollowingError => {
                self.injected.push(what);
                self.axis.set_load(self.cfg.axis.supply * 10.0);
            }
            Injection::HeartbeatLoss | Injection::Mute => self.injected.push(what),
        }
    }

    /// Clears every lasting injection.
    pub fn clear_injections(&mut self) {
        self.injected.clear();
        self.axis.set_load(0.0);
    }

    pub(super) fn injected(&self, what: Injection) -> bool {
        self.injected.contains(&what)
    }

    fn send(&self, out: &mut Vec<Frame>, f: Frame) {
        if self.present && !self.injected(Injection::Mute) {
            out.push(f);
        }
    }

    /// NMT reset: boot-up message, Pre-operational.
    fn boot(&mut self, out: &mut Vec<Frame>) {
        self.nmt = NmtState::Initialising;
        self.sdo.reset();
        self.rpdo = Default::default();
        self.tpdo = Default::default();
        self.consumers = [Consumer::default(); 4];
        self.emcy_pending = None;
        self.send(
            out,
            Frame::new(
                cob::HEARTBEAT + u16::from(self.cfg.node),
                &[nmt::STATE_BOOTUP],
            ),
        );
        self.nmt = NmtState::PreOperational;
        self.hb_next_ns = self.now_ns;
    }

    /// A frame on the bus reaches the drive.
    pub fn receive(&mut self, f: &Frame, out: &mut Vec<Frame>) {
        if !self.present
            || self.nmt == NmtState::Initialising && self.fsa == PowerState::NotReadyToSwitchOn
        {
            return;
        }
        if f.kind == FrameKind::Remote {
            self.on_remote(f, out);
            return;
        }
        let Some(id) = f.cob_id() else { return };
        let me = u16::from(self.cfg.node);
        if id == cob::NMT {
            if f.len >= 2 && (f.data[1] == 0 || f.data[1] == self.cfg.node) {
                self.on_nmt(f.data[0], out);
            }
            return;
        }
        let sync_cob = self.od.get(obj::COB_ID_SYNC, 0);
        if u32::from(id) == sync_cob & 0x7FF && sync_cob & obj::COB_INVALID == 0 {
            if f.len <= 1 {
                self.on_sync(f, out);
            }
            return;
        }
        if id == cob::SDO_RX + me {
            if matches!(self.nmt, NmtState::PreOperational | NmtState::Operational) {
                let mut server = std::mem::take(&mut self.sdo);
                let answer = server.handle(f, self, self.now_ns);
                self.sdo = server;
                if let Some(a) = answer {
                    self.send(out, a);
                }
                self.flush_emcy(out);
            }
            return;
        }
        if (0x701..=0x77F).contains(&id) {
            if f.len >= 1 && f.data[0] != nmt::STATE_BOOTUP {
                self.on_heartbeat((id - cob::HEARTBEAT) as u8);
            }
            return;
        }
        for n in 0..PDOS {
            if pdo::is_valid(&self.od, Dir::Rpdo, n) && pdo::cob_id(&self.od, Dir::Rpdo, n) == id {
                self.on_rpdo(n, f, out);
                return;
            }
        }
    }

    fn on_nmt(&mut self, cs: u8, out: &mut Vec<Frame>) {
        let was_operational = self.nmt == NmtState::Operational;
        match cs {
            nmt::START => {
                if self.nmt != NmtState::Operational {
                    self.tpdo = Default::default();
                }
                self.nmt = NmtState::Operational;
            }
            nmt::STOP => self.nmt = NmtState::Stopped,
            nmt::ENTER_PRE_OPERATIONAL => self.nmt = NmtState::PreOperational,
            nmt::RESET_COMMUNICATION => {
                self.od.restore(0x1000..=0x1FFF);
                self.boot(out);
            }
            nmt::RESET_NODE => {
                self.od.restore(0x0000..=0xFFFF);
                self.fsa = PowerState::SwitchOnDisabled;
                self.ctl = Default::default();
                self.boot(out);
            }
            _ => {}
        }
        if was_operational && self.nmt != NmtState::Operational {
            self.communication_lost(out);
        }
    }

    fn on_heartbeat(&mut self, node: u8) {
        for s in 0..4u8 {
            let v = self.od.get(obj::CONSUMER_HEARTBEAT, s + 1);
            if (v >> 16) as u8 == node && v & 0xFFFF != 0 {
                self.consumers[usize::from(s)] = Consumer {
                    last_ns: self.now_ns,
                    armed: true,
                };
            }
        }
    }

    /// The reaction to a lost master: 0x6007 on the power stage, then
    /// 0x1029 sub 1 on the NMT state.
    fn communication_lost(&mut self, out: &mut Vec<Frame>) {
        self.reaction_6007(out);
    }

    fn consumer_timeout(&mut self, out: &mut Vec<Frame>) {
        self.emcy(ErrorCode::HEARTBEAT, out);
        self.reaction_6007(out);
        match self.od.get(obj::ERROR_BEHAVIOUR, 1) {
            0 if self.nmt == NmtState::Operational => self.nmt = NmtState::PreOperational,
            2 => self.nmt = NmtState::Stopped,
            _ => {}
        }
    }

    fn on_sync(&mut self, f: &Frame, out: &mut Vec<Frame>) {
        if self.nmt != NmtState::Operational {
            return;
        }
        let counter = (f.len == 1).then_some(f.data[0]);
        let counting = self.od.get(obj::SYNC_COUNTER_OVERFLOW, 0) != 0;
        self.refresh_objects();
        // TPDOs are sampled at SYNC, before the RPDOs latched with it
        // take effect: the statusword answers a controlword one cycle on.
        for n in 0..PDOS {
            if !pdo::is_valid(&self.od, Dir::Tpdo, n) {
                continue;
            }
            let t = pdo::transmission_type(&self.od, Dir::Tpdo, n);
            let data = pdo::pack(&self.od, n);
            let cob_id = pdo::cob_id(&self.od, Dir::Tpdo, n);
            let start = self.od.get(obj::TPDO_COMM + n, 6) as u8;
            let st = &mut self.tpdo[usize::from(n)];
            match t {
                0 if st.last != Some(data) => {
                    st.last = Some(data);
                    st.last_ns = self.now_ns;
                    let frame = Frame::new(cob_id, &data.0[..usize::from(data.1)]);
                    self.send(out, frame);
                }
                1..=240 => {
                    if !st.started {
                        // With a SYNC start value the first transmission
                        // is at the SYNC whose counter equals it; without
                        // one, at the t-th SYNC.
                        let by_counter = counting && start != 0;
                        st.started = !by_counter || counter == Some(start);
                        st.syncs = if by_counter { u32::from(t) - 1 } else { 0 };
                    }
                    if st.started {
                        st.syncs += 1;
                        if st.syncs >= u32::from(t) {
                            st.syncs = 0;
                            st.last = Some(data);
                            st.last_ns = self.now_ns;
                            let frame = Frame::new(cob_id, &data.0[..usize::from(data.1)]);
                            self.send(out, frame);
                        }
                    }
                }
                252 => st.sampled = Some(data),
                _ => {}
            }
        }
        let mut applied = false;
        for n in 0..PDOS {
            if let Some((data, len)) = self.rpdo[usize::from(n)].latched.take() {
                pdo::unpack(&mut self.od, n, &data[..usize::from(len)]);
                applied = true;
            }
        }
        if applied {
            self.command_objects_changed(true, out);
        }
        self.flush_emcy(out);
    }

    fn on_rpdo(&mut self, n: u16, f: &Frame, out: &mut Vec<Frame>) {
        if self.nmt != NmtState::Operational {
            return;
        }
        let (_, _, len) = pdo::mapping(&self.od, Dir::Rpdo, n);
        if usize::from(f.len) < len {
            self.emcy(ErrorCode::PDO_LENGTH, out);
            return;
        }
        if usize::from(f.len) > len {
            self.emcy(ErrorCode::PDO_TOO_LONG, out);
            return;
        }
        if pdo::transmission_type(&self.od, Dir::Rpdo, n) <= 240 {
            self.rpdo[usize::from(n)].latched = Some((f.data, f.len));
        } else {
            pdo::unpack(&mut self.od, n, f.payload());
            self.command_objects_changed(true, out);
        }
    }

    fn on_remote(&mut self, f: &Frame, out: &mut Vec<Frame>) {
        if self.nmt != NmtState::Operational || f.extended {
            return;
        }
        for n in 0..PDOS {
            let comm = self.od.get(obj::TPDO_COMM + n, 1);
            if comm & (obj::COB_INVALID | obj::COB_NO_RTR) != 0 || (comm & 0x7FF) != f.id {
                continue;
            }
            let data = match pdo::transmission_type(&self.od, Dir::Tpdo, n) {
                253 => {
                    self.refresh_objects();
                    Some(pdo::pack(&self.od, n))
                }
                252 => self.tpdo[usize::from(n)].sampled,
                _ => None,
            };
            if let Some((d, len)) = data {
                self.send(out, Frame::new(f.id as u16, &d[..usize::from(len)]));
            }
        }
    }

    /// Sends EMCY `code` and records it in 0x1001 and 0x1003.
    pub(super) fn emcy(&mut self, code: ErrorCode, out: &mut Vec<Frame>) {
        let reg = error_register(code.0);
        self.od.set(obj::ERROR_REGISTER, 0, i64::from(reg));
        if code.0 != 0 {
            let count = (self.od.get(obj::ERROR_HISTORY, 0) as u8).min(7);
            for s in (1..=count).rev() {
                let v = self.od.get(obj::ERROR_HISTORY, s);
                self.od.set(obj::ERROR_HISTORY, s + 1, i64::from(v));
            }
            self.od.set(obj::ERROR_HISTORY, 1, i64::from(code.0));
            self.od.set(obj::ERROR_HISTORY, 0, i64::from(count + 1));
        }
        let c = code.0.to_le_bytes();
        self.emcy_pending = Some([c[0], c[1], reg, 0, 0, 0, 0, 0]);
        self.flush_emcy(out);
    }

    fn flush_emcy(&mut self, out: &mut Vec<Frame>) {
        let Some(data) = self.emcy_pending else {
            return;
        };
        if !matches!(self.nmt, NmtState::PreOperational | NmtState::Operational) {
            return;
        }
        let cob_id = self.od.get(obj::COB_ID_EMCY, 0);
        if cob_id & obj::COB_INVALID != 0 {
            self.emcy_pending = None;
            return;
        }
        let inhibit = u64::from(self.od.get(obj::EMCY_INHIBIT, 0)) * 100_000;
        if let Some(last) = self.emcy_last_ns {
            if self.now_ns < last + inhibit {
                return;
            }
        }
        self.emcy_pending = None;
        self.emcy_last_ns = Some(self.now_ns);
        self.send(out, Frame::new((cob_id & 0x7FF) as u16, &data));
    }

    /// Lets `dt_ns` of simulated time pass. The loops, monitors and
    /// heartbeats run every control step inside it; the SDO time-out,
    /// EMCY inhibit and event-driven TPDO timers at its end, so their
    /// resolution is the caller's advance (one servo period on the bus).
    pub fn advance(&mut self, dt_ns: u64, out: &mut Vec<Frame>) {
        if self.fsa == PowerState::NotReadyToSwitchOn {
            self.now_ns += dt_ns;
            return;
        }
        self.load_knobs();
        let mut left = dt_ns;
        while left > 0 {
            let step = left.min(super::control::CONTROL_STEP_NS);
            self.control_step(step, out);
            self.now_ns += step;
            left -= step;
            self.heartbeats(out);
        }
        self.timers(out);
        self.refresh_objects();
    }

    fn timers(&mut self, out: &mut Vec<Frame>) {
        if let Some(a) = self.sdo.poll_timeout(self.now_ns) {
            self.send(out, a);
        }
        self.flush_emcy(out);
        self.heartbeats(out);
        if self.nmt == NmtState::Operational {
            self.event_tpdos(out);
        }
    }

    /// The heartbeat producer and the consumer time-outs, from the
    /// periods copied out of the dictionary for this advance.
    fn heartbeats(&mut self, out: &mut Vec<Frame>) {
        let k = self.ctl.knobs;
        let hb = k.heartbeat_ns;
        if hb > 0 && self.now_ns >= self.hb_next_ns && self.nmt != NmtState::Initialising {
            if !self.injected(Injection::HeartbeatLoss) {
                let f = Frame::new(
                    cob::HEARTBEAT + u16::from(self.cfg.node),
                    &[self.nmt.byte()],
                );
                self.send(out, f);
            }
            self.hb_next_ns = (self.hb_next_ns + hb).max(self.now_ns + hb / 2);
        }
        for (s, timeout) in k.consumer_ns.iter().enumerate() {
            let c = &mut self.consumers[s];
            if c.armed && *timeout > 0 && self.now_ns > c.last_ns + timeout {
                c.armed = false;
                self.consumer_timeout(out);
            }
        }
    }

    fn event_tpdos(&mut self, out: &mut Vec<Frame>) {
        for n in 0..PDOS {
            if !pdo::is_valid(&self.od, Dir::Tpdo, n)
                || pdo::transmission_type(&self.od, Dir::Tpdo, n) < 254
            {
                continue;
            }
            self.refresh_objects();
            let data = pdo::pack(&self.od, n);
            let inhibit = u64::from(self.od.get(obj::TPDO_COMM + n, 3)) * 100_000;
            let timer = u64::from(self.od.get(obj::TPDO_COMM + n, 5)) * 1_000_000;
            let cob_id = pdo::cob_id(&self.od, Dir::Tpdo, n);
            let st = &mut self.tpdo[usize::from(n)];
            let since = self.now_ns.saturating_sub(st.last_ns);
            let changed = st.last != Some(data) && (st.last.is_none() || since >= inhibit);
            let timed = timer > 0 && since >= timer;
            if changed || timed {
                st.last = Some(data);
                st.last_ns = self.now_ns;
                let frame = Frame::new(cob_id, &data.0[..usize::from(data.1)]);
                self.send(out, frame);
            }
        }
    }

    /// Writes the drive's live values into their objects.
    pub(super) fn refresh_objects(&mut self) {
        let reading = self.axis.reading();
        let sw = self.statusword();
        let inputs = self.digital_inputs();
        let volts = if self.injected(Injection::UnderVoltage) {
            12_000
        } else {
            48_000
        };
        let od = &mut self.od;
        od.set(obj::STATUSWORD, 0, i64::from(sw));
        od.set(obj::MODES_DISPLAY, 0, i64::from(self.ctl.mode));
        od.set(obj::POSITION_ACTUAL, 0, i64::from(reading));
        od.set(obj::POSITION_INTERNAL, 0, i64::from(reading));
        od.set(
            obj::VELOCITY_ACTUAL,
            0,
            i64::from(crate::units::counts(self.axis.velocity())),
        );
        od.set(
            obj::POSITION_DEMAND,
            0,
            i64::from(crate::units::counts(self.ctl.setpoint)),
        );
        od.set(
            obj::VELOCITY_DEMAND,
            0,
            i64::from(crate::units::counts(self.ctl.velocity_demand)),
        );
        od.set(
            obj::FOLLOWING_ERROR_ACTUAL,
            0,
            i64::from(crate::units::counts(self.ctl.following_error)),
        );
        let current = self.axis.current_per_mille();
        od.set(obj::CURRENT_ACTUAL, 0, i64::from(current));
        od.set(obj::TORQUE_ACTUAL, 0, i64::from(current));
        od.set(obj::DIGITAL_INPUTS, 0, i64::from(inputs));
        od.set(obj::DC_LINK_VOLTAGE, 0, volts);
    }

    /// 0x60FD: bit 0 negative limit, 1 positive limit, 2 home switch.
    pub(super) fn digital_inputs(&self) -> u32 {
        let p = self.axis.motor_position();
        let on = |s: &Option<Switch>| s.is_some_and(|s| s.is_closed(p));
        u32::from(on(&self.cfg.negative_limit))
            | u32::from(on(&self.cfg.positive_limit)) << 1
            | u32::from(on(&self.cfg.home_switch)) << 2
    }
}

/// 0x1001 for an error code: bit 0 for any error, plus the category bit.
fn error_register(code: u16) -> u8 {
    if code == 0 {
        return 0;
    }
    1 | match code >> 12 {
        0x2 => 0x02,
        0x3 => 0x04,
        0x4 => 0x08,
        0x8 if code >> 8 == 0x86 => 0x20,
        0x8 => 0x10,
        0xF => 0x80,
        _ => 0,
    }
}

impl ObjectAccess for SimDrive {
    fn sdo_read(&mut self, index: u16, sub: u8) -> Result<Vec<u8>, AbortCode> {
        self.refresh_objects();
        self.od.read(index, sub)
    }

    fn sdo_check_writable(&mut self, index: u16, sub: u8) -> Result<(), AbortCode> {
        let e = self.od.find(index, sub)?;
        if matches!(e.access, super::od::Access::Ro | super::od::Access::Const) {
            return Err(AbortCode::READ_ONLY);
        }
        Ok(())
    }

    fn sdo_write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        let value = self.od.check_write(index, sub, data)?;
        pdo::check_write(&self.od, index, sub, value)?;
        match (index, sub) {
            (obj::ERROR_HISTORY, 0) if value != 0 => return Err(AbortCode::INVALID_VALUE),
            (obj::COB_ID_SYNC, 0) if value as u32 & obj::COB_SYNC_PRODUCER != 0 => {
                return Err(AbortCode::INVALID_VALUE)
            }
            (obj::STORE, 1) if value as u32 != obj::SIGNATURE_SAVE => {
                return Err(AbortCode::CANNOT_STORE)
            }
            (obj::RESTORE, 1) if value as u32 != obj::SIGNATURE_LOAD => {
                return Err(AbortCode::CANNOT_STORE)
            }
            (obj::SYNC_COUNTER_OVERFLOW, 0) if value == 1 || value > 240 => {
                return Err(AbortCode::INVALID_VALUE)
            }
            (obj::CONSUMER_HEARTBEAT, s) => {
                let node = (value >> 16) as u8;
                let dup = (1..=4u8).any(|o| {
                    let v = self.od.get(obj::CONSUMER_HEARTBEAT, o);
                    o != s && node != 0 && (v >> 16) as u8 == node && v & 0xFFFF != 0
                });
                if dup && value & 0xFFFF != 0 {
                    return Err(AbortCode::INCOMPATIBLE);
                }
            }
            (obj::MODES_OF_OPERATION, 0) => {
                let ok = value == 0
                    || crate::regs::mode::supported_bit(value as i8)
                        .is_some_and(|b| dictionary::SUPPORTED_MODES & b != 0);
                if !ok {
                    return Err(AbortCode::INVALID_VALUE);
                }
            }
            _ => {}
        }
        self.od.commit(index, sub, data, value);
        let mut out = Vec::new();
        match (index, sub) {
            (obj::ERROR_HISTORY, 0) => {
                for s in 1..=8 {
                    self.od.set(obj::ERROR_HISTORY, s, 0);
                }
            }
            (obj::STORE, 1) => self.od.store(0x1000..=0x6FFF),
            (obj::RESTORE, 1) => {
                // Takes effect at the next reset, as on real drives; the
                // simulator keeps no separate stored set, so restoring
                // reloads the build defaults now.
                let fresh = dictionary::build(self.cfg.node, &self.cfg.identity);
                self.od = fresh;
            }
            (obj::PRODUCER_HEARTBEAT, 0) => {
                self.hb_next_ns = self.now_ns;
                self.load_knobs();
            }
            (obj::CONSUMER_HEARTBEAT, s) => {
                self.consumers[usize::from(s.clamp(1, 4) - 1)] = Consumer::default();
                self.load_knobs();
            }
            (obj::CONTROLWORD, 0)
            | (obj::MODES_OF_OPERATION, 0)
            | (obj::TARGET_POSITION, 0)
            | (obj::TARGET_VELOCITY, 0) => self.command_objects_changed(false, &mut out),
            _ => {}
        }
        // Frames a write causes (EMCY of a state change) go out with the
        // next frame the drive sends; the simulator keeps them pending.
        if let Some(f) = out.into_iter().find(|f| f.id & 0x780 == 0x080) {
            self.emcy_pending = Some(f.data);
        }
        Ok(())
    }
}
