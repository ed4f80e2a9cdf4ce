//! The safe state from outside the realtime functions (unload, exit,
//! after a panic elsewhere): quick stop, then disable voltage, with
//! every frame accounted for.
//!
//! The realtime `write` sends without waiting, as it must. Here nothing
//! may be lost: a frame the transmit queue refuses (it is full, the
//! controller is busy) is sent again once there is room, within a bound;
//! and sending is not taken for arrival (a slow receiver drops what its
//! own queue cannot hold), so disable voltage goes out again to every
//! drive until a statusword received after it shows the drive disabled
//! (switch on disabled, not ready to switch on, or fault), or the bound
//! passes. What could not be sent and which drives never confirmed is
//! logged with the drive and its node, and returned.

use std::time::{Duration, Instant};

use super::Engine;
use crate::bus::CanBus;
use crate::frame::Frame;
use crate::power::PowerState;
use crate::regs::{cob, cw, nmt};

/// How long one frame may wait for room in the transmit queue.
const FRAME_WAIT: Duration = Duration::from_millis(50);
/// How long one wait for room lasts before the send is tried again.
const RETRY_EVERY: Duration = Duration::from_millis(2);
/// The quick-stop frames' period.
const STOP_EVERY: Duration = Duration::from_millis(5);
/// How often disable voltage goes again to the drives yet to confirm it.
const DISABLE_EVERY: Duration = Duration::from_millis(20);
/// How long the drives get to confirm disable voltage at least; more if
/// their heartbeats may lag longer ([`Engine::disable_limit`]).
pub const DISABLE_LIMIT: Duration = Duration::from_secs(2);
/// The longest quick stop, whatever `quick_stop_ns` says.
const QUICK_STOP_MAX_NS: u64 = 2_000_000_000;

/// A drive that did not confirm disable voltage.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Unconfirmed {
    /// Its node id.
    pub node: u8,
    /// The state its last statusword showed (None if none was valid).
    pub state: Option<PowerState>,
    /// Whether any statusword arrived after disable voltage was sent.
    pub answered: bool,
}

/// What [`Engine::go_safe`] achieved.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SafeReport {
    /// Drives that did not confirm disable voltage in time.
    pub unconfirmed: Vec<Unconfirmed>,
    /// Frames that could not be queued within their wait, quick stop and
    /// disable voltage together.
    pub unsent: u64,
}

impl SafeReport {
    /// Whether every frame went out and every drive confirmed.
    pub fn is_complete(&self) -> bool {
        self.unconfirmed.is_empty() && self.unsent == 0
    }
}

/// Sends `frame`, waiting for room in the transmit queue until
/// `deadline`; false if it could not be queued by then.
pub fn send_within(bus: &dyn CanBus, frame: &Frame, deadline: Instant) -> bool {
    loop {
        if bus.send(frame) {
            return true;
        }
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return false;
        }
        bus.wait_writable(left.min(RETRY_EVERY));
    }
}

/// Whether a drive in `state` has its power stage off.
fn disabled(state: Option<PowerState>) -> bool {
    matches!(
        state,
        Some(PowerState::SwitchOnDisabled | PowerState::NotReadyToSwitchOn | PowerState::Fault)
    )
}

impl Engine {
    /// Puts every drive in a safe state from outside the realtime
    /// functions: quick stop until the drives have stopped or
    /// `quick_stop_ns` (at most 2 s) has passed, then disable voltage
    /// until each drive confirms it (at most [`Engine::disable_limit`]). Every
    /// send is checked and retried (see the module documentation); the
    /// report, also logged, says what did not succeed. Sleeps between
    /// rounds, so it is not for realtime use.
    pub fn go_safe(&mut self) -> SafeReport {
        let mut report = SafeReport::default();
        self.quick_stop_phase(&mut report);
        self.disable_phase(&mut report);
        self.log_report(&report);
        report
    }

    fn quick_stop_phase(&mut self, report: &mut SafeReport) {
        let start = Instant::now();
        let limit = Duration::from_nanos(self.cfg.quick_stop_ns.min(QUICK_STOP_MAX_NS));
        let all: Vec<usize> = (0..self.drives.len()).collect();
        loop {
            report.unsent += self.send_round(cw::QUICK_STOP_CMD, &all, Instant::now() + FRAME_WAIT);
            self.receive_after(STOP_EVERY);
            let moving = self.drives.iter().any(|d| {
                matches!(
                    d.state_now(),
                    Some(PowerState::OperationEnabled | PowerState::QuickStopActive)
                )
            });
            if !moving || start.elapsed() >= limit {
                return;
            }
        }
    }

    /// How long the drives get to confirm disable voltage: [`DISABLE_LIMIT`],
    /// or twice the heartbeat timeout if that is longer (a drive whose
    /// heartbeat may be that late is still taken as alive, so its
    /// statusword may be too; a slow receiver works off its queue).
    pub fn disable_limit(&self) -> Duration {
        DISABLE_LIMIT.max(Duration::from_nanos(
            self.cfg.heartbeat_timeout_ns.saturating_mul(2),
        ))
    }

    fn disable_phase(&mut self, report: &mut SafeReport) {
        let end = Instant::now() + self.disable_limit();
        let before: Vec<u32> = self.drives.iter().map(|d| d.tpdo1_count()).collect();
        let fresh = |e: &Engine, i: usize| e.drives[i].tpdo1_count() != before[i];
        let mut pending: Vec<usize> = (0..self.drives.len()).collect();
        while !pending.is_empty() {
            let deadline = (Instant::now() + FRAME_WAIT).min(end);
            report.unsent += self.send_round(cw::DISABLE_VOLTAGE, &pending, deadline);
            self.receive_after(DISABLE_EVERY);
            pending.retain(|&i| !(fresh(self, i) && disabled(self.drives[i].state_now())));
            if Instant::now() >= end {
                break;
            }
        }
        report.unconfirmed = pending
            .iter()
            .map(|&i| Unconfirmed {
                node: self.drives[i].node,
                state: self.drives[i].state_now(),
                answered: fresh(self, i),
            })
            .collect();
    }

    /// Sends `controlword` in RPDO1 to the drives at `which`, then SYNC,
    /// then the master's heartbeat when due (drives that watch it would
    /// fault while being stopped), each within `deadline`; the number
    /// that could not be sent.
    fn send_round(&mut self, controlword: u16, which: &[usize], deadline: Instant) -> u64 {
        let mut unsent = 0;
        let c = controlword.to_le_bytes();
        for &i in which {
            let d = &self.drives[i];
            let t = d.target().to_le_bytes();
            let m = d.mode.number() as u8;
            let f = Frame::new(
                cob::RPDO[0] + u16::from(d.node),
                &[c[0], c[1], t[0], t[1], t[2], t[3], m],
            );
            if !send_within(&*self.bus, &f, deadline) {
                unsent += 1;
            }
        }
        if !send_within(&*self.bus, &Frame::new(cob::SYNC, &[]), deadline) {
            unsent += 1;
        }
        if let Some((node, period)) = self.cfg.master_heartbeat {
            let now = hal_core::clock::monotonic_ns();
            if now >= self.next_master_heartbeat {
                let hb = Frame::new(cob::HEARTBEAT + u16::from(node), &[nmt::STATE_OPERATIONAL]);
                if !send_within(&*self.bus, &hb, deadline) {
                    unsent += 1;
                }
                self.next_master_heartbeat = now + period;
            }
        }
        unsent
    }

    /// Waits `pause`, then takes what arrived (the simulated bus's time
    /// moves with the wall clock here).
    fn receive_after(&mut self, pause: Duration) {
        std::thread::sleep(pause);
        self.bus.tick(hal_core::clock::monotonic_ns());
        for _ in 0..self.cfg.rx_budget.saturating_mul(4) {
            let Some(f) = self.bus.try_recv() else { break };
            let now = hal_core::clock::monotonic_ns();
            self.dispatch(&f, now);
        }
    }

    fn log_report(&self, report: &SafeReport) {
        let Some(log) = &self.log else { return };
        if report.unsent > 0 {
            log.err(format_args!(
                "canservo: {} safe-state frame(s) could not be sent, each after waiting {} ms \
                 for room (transmit queue full or bus off)",
                report.unsent,
                FRAME_WAIT.as_millis()
            ));
        }
        for u in &report.unconfirmed {
            let label = self
                .drives
                .iter()
                .find(|d| d.node == u.node)
                .map_or("canservo", |d| d.label());
            let why = match (u.answered, u.state) {
                (false, _) => "it sent no statusword after it".to_string(),
                (true, Some(s)) => format!("its statusword still shows {}", s.name()),
                (true, None) => "its statusword shows no valid state".to_string(),
            };
            log.err(format_args!(
                "{label}: disable voltage not confirmed within {:.1} s ({why}); \
                 the drive may still be powered",
                self.disable_limit().as_secs_f64()
            ));
        }
        if report.is_complete() {
            log.info(format_args!(
                "canservo: every drive confirmed disable voltage"
            ));
        }
    }
}
