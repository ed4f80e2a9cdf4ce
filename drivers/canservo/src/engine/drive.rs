//! One drive's realtime side: what its TPDOs, EMCYs and heartbeats say,
//! the supervision that turns silence and faults into a tripped latch,
//! the power-state planner behind the `enable` pin, the fault-reset
//! sequence, drive-internal homing, and its RPDO.

use std::sync::atomic::Ordering::Relaxed;
use std::sync::Arc;

use hal_core::RtLog;
use hal_driver::fault::{Fault, FaultLatch};

use super::faults;
use super::shared::{DriveShared, Restart};
use super::{DriveInputs, DriveStatus};
use crate::codes::ErrorCode;
use crate::frame::Frame;
use crate::power::{next_command, Goal, PowerState};
use crate::regs::{cob, cw, mode, nmt, sw};
use crate::startup::Mode;
use crate::units::{counts as axis_saturate, usable_scale as usable};

/// Drive-internal homing, as the realtime side runs it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Homing {
    /// Not homing.
    Idle,
    /// Mode 6 requested; waiting for 0x6061 to show it.
    Switching,
    /// Bit 4 set; waiting for "homing attained" or an error.
    Running,
    /// Back to the configured mode; waiting for 0x6061.
    Returning,
}

/// The fault-reset sequence sent to a drive in Fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Reset {
    /// None in progress.
    Idle,
    /// Bit 7 low for one cycle, so the next cycle is an edge.
    Low,
    /// Bit 7 high until the drive leaves Fault (or `left` cycles pass).
    High { left: u32 },
}

/// Cycles bit 7 stays high waiting for the drive to leave Fault.
const RESET_CYCLES: u32 = 50;

/// One drive.
#[derive(Debug)]
pub(super) struct DriveRt {
    pub node: u8,
    pub mode: Mode,
    /// "canservo.0 (node 2)", for log lines.
    label: String,
    pub latch: FaultLatch,
    pub shared: Arc<DriveShared>,
    // What the drive said.
    statusword: u16,
    position: i32,
    mode_display: i8,
    velocity: i32,
    error_code: u16,
    emcy_code: u16,
    nmt_state: u8,
    seen_tpdo1: bool,
    seen_tpdo2: bool,
    /// TPDO1s taken so far (wrapping): tells a fresh statusword.
    tpdo1_count: u32,
    misses: u32,
    last_heartbeat_ns: Option<u64>,
    pub bad_frames: u32,
    // What the master does.
    controlword: u16,
    target: i32,
    homing: Homing,
    home_complete: bool,
    home_clear: bool,
    home_prev: bool,
    home_served: bool,
    tracking: bool,
    needs_enable_edge: bool,
    fault_reset_prev: bool,
    reset: Reset,
    quick_stop_ns: Option<u64>,
    restarting: bool,
    after_restart: bool,
    comm_lost: bool,
}

impl DriveRt {
    pub fn new(index: usize, node: u8, mode: Mode, shared: Arc<DriveShared>) -> DriveRt {
        let label = format!("canservo.{index} (node {node})");
        DriveRt {
            node,
            mode,
            latch: FaultLatch::new(label.clone()),
            label,
            shared,
            statusword: 0,
            position: 0,
            mode_display: 0,
            velocity: 0,
            error_code: 0,
            emcy_code: 0,
            nmt_state: nmt::STATE_OPERATIONAL,
            seen_tpdo1: false,
            seen_tpdo2: false,
            tpdo1_count: 0,
            misses: 0,
            last_heartbeat_ns: None,
            bad_frames: 0,
            controlword: cw::DISABLE_VOLTAGE,
            target: 0,
            homing: Homing::Idle,
            home_complete: false,
            home_clear: false,
            home_prev: false,
            home_served: false,
            tracking: true,
            needs_enable_edge: false,
            fault_reset_prev: false,
            reset: Reset::Idle,
            quick_stop_ns: None,
            restarting: false,
            after_restart: false,
            comm_lost: false,
        }
    }

    fn state(&self) -> Option<PowerState> {
        PowerState::from_statusword(self.statusword)
    }

    /// The power state the last statusword showed.
    pub fn state_now(&self) -> Option<PowerState> {
        self.state()
    }

    /// TPDO1s (statuswords) taken so far, wrapping.
    pub fn tpdo1_count(&self) -> u32 {
        self.tpdo1_count
    }

    /// "canservo.0 (node 2)".
    pub fn label(&self) -> &str {
        &self.label
    }

    /// Trips the latch with `fault` and says so once, with the node and,
    /// for drive errors, the error code and its meaning.
    pub fn trip(&mut self, fault: &'static Fault, log: Option<&RtLog>, code: u16) {
        // A communication fault decides how to recover even when another
        // fault tripped the latch first (a node reset also makes the
        // drive send an EMCY).
        self.comm_lost |= faults::needs_restart(fault);
        if !self.latch.trip(fault) {
            return;
        }
        self.shared.request_diagnosis();
        if let Some(log) = log {
            if code != 0 {
                let c = ErrorCode(code);
                log.err(format_args!(
                    "{}: {}: error code {:#06x} ({}); drive disabled",
                    self.label,
                    fault.reason,
                    c.0,
                    c.meaning()
                ));
            } else {
                log.err(format_args!(
                    "{}: {}; drive disabled",
                    self.label, fault.reason
                ));
            }
        }
    }

    /// Forgets what the TPDOs said before this cycle's reception.
    pub fn begin_cycle(&mut self) {
        self.seen_tpdo1 = false;
        self.seen_tpdo2 = false;
    }

    /// A frame for this node; returns false if it is not one of its
    /// COB-IDs.
    pub fn take(&mut self, base: u16, f: &Frame, now_ns: u64, log: Option<&RtLog>) -> bool {
        let d = &f.data;
        match base {
            b if b == cob::TPDO[0] => {
                if f.len == 7 {
                    self.statusword = u16::from_le_bytes([d[0], d[1]]);
                    self.position = i32::from_le_bytes([d[2], d[3], d[4], d[5]]);
                    self.mode_display = d[6] as i8;
                    self.seen_tpdo1 = true;
                    self.tpdo1_count = self.tpdo1_count.wrapping_add(1);
                } else {
                    self.bad_frames = self.bad_frames.wrapping_add(1);
                }
            }
            b if b == cob::TPDO[1] => {
                if f.len == 6 {
                    self.velocity = i32::from_le_bytes([d[0], d[1], d[2], d[3]]);
                    self.error_code = u16::from_le_bytes([d[4], d[5]]);
                    self.seen_tpdo2 = true;
                } else {
                    self.bad_frames = self.bad_frames.wrapping_add(1);
                }
            }
            cob::EMCY => {
                if f.len >= 2 {
                    let code = u16::from_le_bytes([d[0], d[1]]);
                    if code != 0 && !self.restarting {
                        self.emcy_code = code;
                        self.trip(&faults::EMCY, log, code);
                    }
                } else {
                    self.bad_frames = self.bad_frames.wrapping_add(1);
                }
            }
            cob::HEARTBEAT => {
                if f.len >= 1 {
                    self.nmt_state = d[0];
                    self.last_heartbeat_ns = Some(now_ns);
                } else {
                    self.bad_frames = self.bad_frames.wrapping_add(1);
                }
            }
            _ => return false,
        }
        true
    }

    /// Supervision after this cycle's frames are in: TPDOs after the last
    /// SYNC, heartbeat age and state, the drive's own Fault.
    pub fn supervise(
        &mut self,
        now_ns: u64,
        expect_tpdo: bool,
        miss_limit: u32,
        hb_timeout_ns: u64,
        log: Option<&RtLog>,
    ) {
        if self.restarting {
            self.poll_restart(log);
            return;
        }
        if self.after_restart && self.seen_tpdo1 {
            self.after_restart = false;
            if matches!(
                self.state(),
                Some(PowerState::Fault | PowerState::FaultReactionActive)
            ) {
                self.reset = Reset::Low;
            } else {
                self.latch.reset();
                self.needs_enable_edge = true;
            }
        }
        if expect_tpdo {
            if self.seen_tpdo1 && self.seen_tpdo2 {
                self.misses = 0;
            } else {
                self.misses += 1;
                if self.misses >= miss_limit.max(1) {
                    self.trip(&faults::TPDO_MISSING, log, 0);
                }
            }
        }
        if hb_timeout_ns > 0 {
            match self.last_heartbeat_ns {
                None => self.last_heartbeat_ns = Some(now_ns),
                Some(t) if now_ns.saturating_sub(t) > hb_timeout_ns => {
                    self.trip(&faults::HEARTBEAT, log, 0)
                }
                Some(_) => {}
            }
        }
        if self.nmt_state != nmt::STATE_OPERATIONAL {
            self.trip(&faults::NMT_STATE, log, 0);
        }
        if matches!(
            self.state(),
            Some(PowerState::Fault | PowerState::FaultReactionActive)
        ) {
            self.trip(&faults::DRIVE_FAULT, log, self.error_code);
        }
        if self.homing == Homing::Running && self.mode_display == mode::HM {
            let s = self.statusword;
            if s & sw::MODE_13 != 0 {
                self.trip(&faults::HOMING, log, 0);
                self.homing = Homing::Returning;
            } else if s & sw::MODE_12 != 0 && s & sw::TARGET_REACHED != 0 {
                self.homing = Homing::Returning;
                self.home_complete = true;
                self.tracking = true;
                self.home_clear = true;
            }
        }
    }

    fn poll_restart(&mut self, log: Option<&RtLog>) {
        match self.shared.restart() {
            Restart::Done => {
                self.shared.set_restart(Restart::Idle);
                self.restarting = false;
                self.fresh_supervision();
                // The latch clears once the first TPDO shows the drive
                // is not in Fault (else after its fault reset too).
                self.after_restart = true;
                if let Some(log) = log {
                    log.info(format_args!(
                        "{}: brought up again after the fault reset",
                        self.label
                    ));
                }
            }
            Restart::Failed => {
                self.shared.set_restart(Restart::Idle);
                self.restarting = false;
                self.fresh_supervision();
            }
            _ => {}
        }
    }

    fn fresh_supervision(&mut self) {
        self.comm_lost = false;
        self.misses = 0;
        self.last_heartbeat_ns = None;
        self.nmt_state = nmt::STATE_OPERATIONAL;
        self.emcy_code = 0;
        self.statusword = 0;
        self.seen_tpdo1 = false;
        self.seen_tpdo2 = false;
    }

    /// The fault-reset pin's rising edge.
    fn fault_reset(&mut self, helper: bool) {
        let Some(fault) = self.latch.fault() else {
            if self.state() == Some(PowerState::Fault) {
                self.reset = Reset::Low;
            }
            return;
        };
        if self.comm_lost || faults::needs_restart(fault) {
            if helper {
                self.restarting = true;
                self.shared.set_restart(Restart::Requested);
            } else {
                self.fresh_supervision();
                self.latch.reset();
                self.needs_enable_edge = true;
            }
        } else {
            self.emcy_code = 0;
            if self.state() == Some(PowerState::Fault) {
                self.reset = Reset::Low;
            } else {
                self.latch.reset();
                self.needs_enable_edge = true;
            }
        }
    }

    /// This cycle's outputs: the feedback after reception.
    pub fn status(&mut self, inp: &DriveInputs) -> DriveStatus {
        let scale = usable(inp.scale);
        let home_clear = std::mem::take(&mut self.home_clear);
        let echo = matches!(self.homing, Homing::Switching | Homing::Running);
        let position_fb = if echo {
            inp.position_cmd
        } else {
            f64::from(self.position) / scale
        };
        let drive_fault = matches!(
            self.state(),
            Some(PowerState::Fault | PowerState::FaultReactionActive)
        );
        DriveStatus {
            position_fb,
            velocity_fb: f64::from(self.velocity) / scale,
            statusword: self.statusword,
            state: self.state(),
            mode_display: self.mode_display,
            error_code: if self.emcy_code != 0 {
                self.emcy_code
            } else {
                self.error_code
            },
            amp_fault: self.latch.is_tripped() || drive_fault,
            fault_code: self.latch.code(),
            enabled: self.state() == Some(PowerState::OperationEnabled) && !self.latch.is_tripped(),
            home_clear,
            homing: self.homing != Homing::Idle,
            home_complete: self.home_complete,
            nmt_state: self.nmt_state,
            error_register: self.shared.error_register.load(Relaxed),
            bad_frames: self.bad_frames,
        }
    }

    /// Plans this cycle's controlword, mode and target, and makes the
    /// RPDO. None while the node is being brought up again.
    pub fn rpdo(
        &mut self,
        inp: &DriveInputs,
        now_ns: u64,
        quick_stop_ns: u64,
        helper: bool,
    ) -> Option<Frame> {
        if inp.fault_reset && !self.fault_reset_prev {
            self.fault_reset(helper);
        }
        self.fault_reset_prev = inp.fault_reset;
        if self.restarting {
            return None;
        }
        if !inp.enable {
            self.needs_enable_edge = false;
        }
        let state = self.state();
        let tripped = self.latch.is_tripped();
        // The fault-reset sequence (a drive-side fault).
        let mut controlword = match self.reset {
            Reset::Low => {
                self.reset = Reset::High { left: RESET_CYCLES };
                Some(cw::DISABLE_VOLTAGE)
            }
            Reset::High { left } => {
                if state != Some(PowerState::Fault) || left == 0 {
                    self.reset = Reset::Idle;
                    if state != Some(PowerState::Fault) && state.is_some() {
                        self.latch.reset();
                        self.needs_enable_edge = true;
                    }
                    Some(cw::DISABLE_VOLTAGE)
                } else {
                    self.reset = Reset::High { left: left - 1 };
                    Some(cw::FAULT_RESET_CMD)
                }
            }
            Reset::Idle => None,
        };
        let goal = if tripped {
            let since = *self.quick_stop_ns.get_or_insert(now_ns);
            if now_ns.saturating_sub(since) < quick_stop_ns {
                Goal::QuickStop
            } else {
                Goal::Disabled
            }
        } else {
            self.quick_stop_ns = None;
            if inp.enable && !self.needs_enable_edge {
                Goal::Enabled
            } else {
                Goal::Disabled
            }
        };
        let base = *controlword.get_or_insert_with(|| next_command(state, goal));
        let enabled = state == Some(PowerState::OperationEnabled) && goal == Goal::Enabled;
        self.plan_homing(inp, enabled);
        let scale = usable(inp.scale);
        let (mode_cmd, bit4) = match self.homing {
            Homing::Idle | Homing::Returning => (self.mode.number(), false),
            Homing::Switching => (mode::HM, false),
            Homing::Running => (mode::HM, true),
        };
        let position_mode = self.mode.is_position() && self.homing == Homing::Idle;
        if self.homing == Homing::Returning && self.mode_display == self.mode.number() {
            self.homing = Homing::Idle;
        }
        // The target: the actual position (or zero speed) unless the drive
        // is enabled, in its own mode and the command is in step with it.
        let target = if position_mode {
            let wanted = axis_saturate(inp.position_cmd * scale);
            if !enabled {
                self.tracking = true;
            }
            if self.tracking && enabled {
                let tolerance = (inp.command_tolerance.abs() * scale.abs()).max(1.0);
                if (f64::from(wanted) - f64::from(self.position)).abs() <= tolerance {
                    self.tracking = false;
                }
            }
            if enabled && !self.tracking {
                wanted
            } else {
                self.position
            }
        } else if self.mode.is_position() {
            self.position
        } else if enabled && self.homing == Homing::Idle {
            axis_saturate(inp.velocity_cmd * scale)
        } else {
            0
        };
        self.target = target;
        self.controlword = base | if bit4 { cw::MODE_4 } else { 0 };
        let t = target.to_le_bytes();
        let c = self.controlword.to_le_bytes();
        Some(Frame::new(
            cob::RPDO[0] + u16::from(self.node),
            &[c[0], c[1], t[0], t[1], t[2], t[3], mode_cmd as u8],
        ))
    }

    /// Homing follows the `home` level, so a request made while the
    /// drive is still enabling starts once it is enabled; one request
    /// homes once (`home_served` until `home` falls).
    fn plan_homing(&mut self, inp: &DriveInputs, enabled: bool) {
        let rising = inp.home && !self.home_prev;
        self.home_prev = inp.home;
        if rising {
            self.home_complete = false;
        }
        if !inp.home {
            self.home_served = false;
        }
        match self.homing {
            Homing::Idle if inp.home && enabled && !self.home_served => {
                self.home_served = true;
                self.homing = Homing::Switching;
            }
            Homing::Switching | Homing::Running if !inp.home || !enabled => {
                self.homing = Homing::Returning
            }
            Homing::Switching if self.mode_display == mode::HM => self.homing = Homing::Running,
            _ => {}
        }
    }

    /// The last controlword sent.
    pub fn controlword(&self) -> u16 {
        self.controlword
    }

    /// The last target sent.
    pub fn target(&self) -> i32 {
        self.target
    }
}
