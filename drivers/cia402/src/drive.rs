//! One CiA 402 drive's realtime control, whatever fieldbus carries its
//! process data: what the statusword says, the fault latch and its log
//! line, the power-state planner behind the `enable` pin, the fault-reset
//! sequence, drive-internal homing, tracking of the position command, and
//! the controlword, target and mode to send.
//!
//! The fieldbus keeps its own supervision state (CAN: TPDO misses,
//! heartbeat, NMT state; EtherCAT: working counter, AL state) in the
//! controller's `link` ([`LinkSupervision`]), decodes its frames into
//! [`DriveControl::observe_status`] and friends, trips the latch with its
//! own faults, and packs [`Plan`] into its frames. The communication
//! faults it declares through `needs_restart` are recovered by bringing
//! the drive up again (the helper thread, through [`DriveShared`]); the
//! drive-side faults by the CiA 402 fault reset.

use std::sync::Arc;

use hal_driver::fault::{Fault, FaultLatch};
use hal_driver::LogSink;

use crate::codes::ErrorCode;
use crate::faults;
use crate::objects::{cw, mode, sw};
use crate::power::{next_command, Goal, PowerState};
use crate::shared::{DriveShared, Restart};
use crate::units::{counts as axis_saturate, usable_scale as usable};
use crate::Mode;

/// The fieldbus side of a drive's supervision.
pub trait LinkSupervision {
    /// Forgets what the link's supervision knew: after a restart, or when
    /// a fault reset starts supervising afresh.
    fn fresh(&mut self);
}

/// One drive's inputs for a cycle (from its HAL pins and params).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriveInputs {
    /// `enable`.
    pub enable: bool,
    /// `fault-reset` (acts on the rising edge).
    pub fault_reset: bool,
    /// `position-cmd` (user units; CSP and PP).
    pub position_cmd: f64,
    /// `velocity-cmd` (user units/s; PV and CSV).
    pub velocity_cmd: f64,
    /// `home` (a rising edge starts drive-internal homing).
    pub home: bool,
    /// `position-scale`: counts per user unit.
    pub scale: f64,
    /// `command-tolerance`: how close `position-cmd` must come to the
    /// actual position before a freshly enabled or homed drive follows it.
    pub command_tolerance: f64,
}

impl Default for DriveInputs {
    fn default() -> DriveInputs {
        DriveInputs {
            enable: false,
            fault_reset: false,
            position_cmd: 0.0,
            velocity_cmd: 0.0,
            home: false,
            scale: 1.0,
            command_tolerance: 0.01,
        }
    }
}

/// What a cycle's control says back to the HAL pins.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Feedback {
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
}

/// What to send to the drive this cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Plan {
    /// The controlword.
    pub controlword: u16,
    /// The target: position (CSP, PP) or velocity (PV, CSV) in counts.
    pub target: i32,
    /// Modes of operation (0x6060).
    pub mode: i8,
}

/// Where a restart stands, as supervision sees it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Restarting {
    /// No restart: supervise.
    No,
    /// The helper is bringing the drive up: nothing to supervise.
    Yes,
    /// It just ended (done or failed): supervision starts afresh next
    /// cycle.
    Ended,
}

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

/// One drive's control, with its fieldbus supervision `L`.
#[derive(Debug)]
pub struct DriveControl<L> {
    /// The fieldbus side of supervision.
    pub link: L,
    /// The configured mode.
    pub mode: Mode,
    /// "canservo.0 (node 2)", "lcec.0.X (slave 3)": for log lines.
    label: String,
    /// The drive's fault latch.
    pub latch: FaultLatch,
    /// What the helper thread shares.
    pub shared: Arc<DriveShared>,
    needs_restart: fn(&Fault) -> bool,
    // What the drive said.
    statusword: u16,
    position: i32,
    mode_display: i8,
    velocity: i32,
    error_code: u16,
    emcy_code: u16,
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
    /// PP: the last target the drive acknowledged (set-point handshake).
    pp_acked: Option<i32>,
}

impl<L: LinkSupervision> DriveControl<L> {
    /// A drive labelled `label` in `mode`; `needs_restart` says which
    /// faults are the fieldbus's communication faults.
    pub fn new(
        label: String,
        mode: Mode,
        shared: Arc<DriveShared>,
        link: L,
        needs_restart: fn(&Fault) -> bool,
    ) -> DriveControl<L> {
        DriveControl {
            link,
            mode,
            latch: FaultLatch::new(label.clone()),
            label,
            shared,
            needs_restart,
            statusword: 0,
            position: 0,
            mode_display: 0,
            velocity: 0,
            error_code: 0,
            emcy_code: 0,
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
            pp_acked: None,
        }
    }

    /// The label of log lines.
    pub fn label(&self) -> &str {
        &self.label
    }

    /// The power state the last statusword showed.
    pub fn state_now(&self) -> Option<PowerState> {
        PowerState::from_statusword(self.statusword)
    }

    /// Trips the latch with `fault` and says so once, with the label and,
    /// for drive errors, the error code and its meaning.
    pub fn trip(&mut self, fault: &'static Fault, log: Option<&LogSink>, code: u16) {
        // A communication fault decides how to recover even when another
        // fault tripped the latch first (a node reset also makes the
        // drive send an EMCY).
        self.comm_lost |= (self.needs_restart)(fault);
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

    /// The statusword, position actual and mode display of this cycle.
    pub fn observe_status(&mut self, statusword: u16, position: i32, mode_display: i8) {
        self.statusword = statusword;
        self.position = position;
        self.mode_display = mode_display;
    }

    /// The velocity actual and error code (0x603F) of this cycle.
    pub fn observe_velocity(&mut self, velocity: i32, error_code: u16) {
        self.velocity = velocity;
        self.error_code = error_code;
    }

    /// An emergency message with `code` (0 = error reset, ignored).
    pub fn emcy(&mut self, code: u16, log: Option<&LogSink>) {
        if code != 0 && !self.restarting {
            self.emcy_code = code;
            self.trip(&faults::EMCY, log, code);
        }
    }

    /// Whether the helper is bringing the drive up again.
    pub fn is_restarting(&self) -> bool {
        self.restarting
    }

    /// The first step of a cycle's supervision: a restart in progress is
    /// polled; while one runs there is nothing else to supervise.
    pub fn poll_restart(&mut self, log: Option<&LogSink>) -> Restarting {
        if !self.restarting {
            return Restarting::No;
        }
        match self.shared.restart() {
            Restart::Done => {
                self.shared.set_restart(Restart::Idle);
                self.restarting = false;
                self.fresh_supervision();
                // The latch clears once the first status shows the drive
                // is not in Fault (else after its fault reset too).
                self.after_restart = true;
                if let Some(log) = log {
                    log.info(format_args!(
                        "{}: brought up again after the fault reset",
                        self.label
                    ));
                }
                Restarting::Ended
            }
            Restart::Failed => {
                self.shared.set_restart(Restart::Idle);
                self.restarting = false;
                self.fresh_supervision();
                Restarting::Ended
            }
            _ => Restarting::Yes,
        }
    }

    /// After a restart, the first status received (`status_seen`)
    /// decides: a drive in Fault gets the fault reset, else the latch
    /// clears.
    pub fn after_restart(&mut self, status_seen: bool) {
        if self.after_restart && status_seen {
            self.after_restart = false;
            if matches!(
                self.state_now(),
                Some(PowerState::Fault | PowerState::FaultReactionActive)
            ) {
                self.reset = Reset::Low;
            } else {
                self.latch.reset();
                self.comm_lost = false;
                self.needs_enable_edge = true;
            }
        }
    }

    /// The drive's own supervision, after the link's: Fault in the
    /// statusword, homing progress.
    pub fn supervise_drive(&mut self, log: Option<&LogSink>) {
        if matches!(
            self.state_now(),
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

    fn fresh_supervision(&mut self) {
        self.comm_lost = false;
        self.emcy_code = 0;
        self.statusword = 0;
        self.link.fresh();
    }

    /// The fault-reset pin's rising edge.
    fn fault_reset(&mut self, helper: bool) {
        let Some(fault) = self.latch.fault() else {
            if self.state_now() == Some(PowerState::Fault) {
                self.reset = Reset::Low;
            }
            return;
        };
        if self.comm_lost || (self.needs_restart)(fault) {
            if helper {
                self.restarting = true;
                self.shared.set_restart(Restart::Requested);
            } else {
                // The bus owner brings the link back on its own time (an
                // EtherCAT slave returns to OP some cycles later): the
                // latch is reset at the first status seen from now on, as
                // after a helper's restart, so that a reset given while
                // the line is still down is not lost to the next trip.
                self.fresh_supervision();
                self.after_restart = true;
            }
        } else {
            self.emcy_code = 0;
            if self.state_now() == Some(PowerState::Fault) {
                self.reset = Reset::Low;
            } else {
                self.latch.reset();
                self.needs_enable_edge = true;
            }
        }
    }

    /// This cycle's feedback, after reception and supervision.
    pub fn feedback(&mut self, inp: &DriveInputs) -> Feedback {
        let scale = usable(inp.scale);
        let home_clear = std::mem::take(&mut self.home_clear);
        let echo = matches!(self.homing, Homing::Switching | Homing::Running);
        let position_fb = if echo {
            inp.position_cmd
        } else {
            f64::from(self.position) / scale
        };
        let state = self.state_now();
        let drive_fault = matches!(
            state,
            Some(PowerState::Fault | PowerState::FaultReactionActive)
        );
        Feedback {
            position_fb,
            velocity_fb: f64::from(self.velocity) / scale,
            statusword: self.statusword,
            state,
            mode_display: self.mode_display,
            error_code: if self.emcy_code != 0 {
                self.emcy_code
            } else {
                self.error_code
            },
            amp_fault: self.latch.is_tripped() || drive_fault,
            fault_code: self.latch.code(),
            enabled: state == Some(PowerState::OperationEnabled) && !self.latch.is_tripped(),
            home_clear,
            homing: self.homing != Homing::Idle,
            home_complete: self.home_complete,
        }
    }

    /// Plans this cycle's controlword, target and mode. None while the
    /// drive is being brought up again (send nothing).
    pub fn plan(
        &mut self,
        inp: &DriveInputs,
        now_ns: u64,
        quick_stop_ns: u64,
        helper: bool,
    ) -> Option<Plan> {
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
        let state = self.state_now();
        // Whether the latch held before the reset sequence's step (which
        // may clear it) decides this cycle's goal.
        let tripped = self.latch.is_tripped();
        let mut controlword = self.reset_step(state);
        let goal = self.goal(tripped, inp, now_ns, quick_stop_ns);
        let base = *controlword.get_or_insert_with(|| next_command(state, goal));
        let enabled = state == Some(PowerState::OperationEnabled) && goal == Goal::Enabled;
        self.plan_homing(inp, enabled);
        let (mode_cmd, bit4) = match self.homing {
            Homing::Idle | Homing::Returning => (self.mode.number(), false),
            Homing::Switching => (mode::HM, false),
            Homing::Running => (mode::HM, true),
        };
        if self.homing == Homing::Returning && self.mode_display == self.mode.number() {
            self.homing = Homing::Idle;
        }
        let target = self.target_for(inp, enabled);
        let set_point = self.pp_set_point(target, enabled);
        self.target = target;
        self.controlword = base | if bit4 || set_point { cw::MODE_4 } else { 0 };
        if set_point {
            self.controlword |= cw::CHANGE_SET_IMMEDIATELY;
        }
        Some(Plan {
            controlword: self.controlword,
            target,
            mode: mode_cmd,
        })
    }

    /// The fault-reset sequence's controlword this cycle, if one runs.
    fn reset_step(&mut self, state: Option<PowerState>) -> Option<u16> {
        match self.reset {
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
        }
    }

    /// What the power stage should do: quick stop then disable while the
    /// latch holds, else follow `enable` (after a fresh edge).
    fn goal(&mut self, tripped: bool, inp: &DriveInputs, now_ns: u64, quick_stop_ns: u64) -> Goal {
        if tripped {
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
        }
    }

    /// The target: the actual position (or zero speed) unless the drive
    /// is enabled, in its own mode and the command is in step with it.
    fn target_for(&mut self, inp: &DriveInputs, enabled: bool) -> i32 {
        let scale = usable(inp.scale);
        let position_mode = self.mode.is_position() && self.homing == Homing::Idle;
        if position_mode {
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
        }
    }

    /// Profile position's set-point handshake: bit 4 ("new set-point")
    /// while a target the drive has not acknowledged (statusword bit 12)
    /// is pending; dropped for a cycle once it is, so the next one is a
    /// new edge.
    fn pp_set_point(&mut self, target: i32, enabled: bool) -> bool {
        if self.mode != Mode::Pp || self.homing != Homing::Idle || !enabled {
            self.pp_acked = None;
            return false;
        }
        let acknowledged = self.statusword & sw::MODE_12 != 0;
        let pending = self.controlword & cw::MODE_4 != 0;
        if pending && acknowledged {
            self.pp_acked = Some(self.target);
            return false;
        }
        pending || self.pp_acked != Some(target)
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
