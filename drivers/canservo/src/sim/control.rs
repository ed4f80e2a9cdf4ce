//! The drive side of [`SimDrive`]: the CiA 402 power state machine with
//! its option codes (quick stop, shutdown, disable operation, fault
//! reaction), the modes CSP, CSV, PV and homing, the statusword's
//! mode-specific bits, the following-error monitor and software limits
//! (hardware.md §6.8 to §6.10, §6.12).

use super::axis::Demand;
use super::drive::{Injection, SimDrive};
use crate::codes::ErrorCode;
use crate::frame::Frame;
use crate::power::{transition, Command, PowerState};
use crate::regs::{cw, mode, obj, sw};

/// The drive's control period: the loops and monitors run this often
/// (the loops are stable well past it: the velocity loop's discrete pole
/// is at 0.56 with the default motor and gains).
pub const CONTROL_STEP_NS: u64 = 250_000;
/// A homing search that travels this far without finding its switch
/// ends in a homing error.
const HOMING_MAX_TRAVEL: f64 = 1.0e7;
/// A stopping ramp whose reference reached zero ends after this long
/// even if the axis still moves (a load driving it): the power stage
/// then goes off, as a drive's brake-and-disable timer does.
const RAMP_SETTLE_NS: u64 = 100_000_000;

/// What happens when a stopping ramp reaches standstill.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum RampEnd {
    /// The state has already changed; only the power stage goes off.
    PowerOff,
    /// Quick stop finished: Switch on disabled (option 1..4).
    SwitchOnDisabled,
    /// Quick stop finished: stay in Quick stop active, holding (5..8).
    Hold,
    /// Fault reaction finished: Fault.
    Fault,
}

/// Homing progress.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) enum Homing {
    /// Never started in this mode.
    #[default]
    NotStarted,
    /// Searching the switch in direction `dir` (±1).
    Search { dir: f64, start: f64 },
    /// Leaving the switch in direction `dir`; its edge is home.
    Leave { dir: f64, start: f64 },
    /// Homing attained.
    Done,
    /// Interrupted (bit 4 dropped, mode left).
    Interrupted,
    /// Homing error.
    Error,
}

/// The objects the loops and monitors read every control step, copied
/// out of the dictionary once per advance (they change only when a frame
/// arrives, between advances), so a step costs no dictionary lookups.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Knobs {
    controlword: u16,
    target_velocity: f64,
    position_offset: f64,
    velocity_offset: f64,
    soft_limits: (f64, f64),
    ferr_window: u32,
    ferr_timeout_ns: u64,
    profile_acceleration: f64,
    profile_deceleration: f64,
    velocity_window: f64,
    velocity_threshold: f64,
    homing_switch_bit: u32,
    homing_speeds: (f64, f64),
    pub heartbeat_ns: u64,
    pub consumer_ns: [u64; 4],
}

/// The control state of the drive.
#[derive(Debug, Clone, Default)]
pub(super) struct Control {
    /// The objects of this advance.
    pub knobs: Knobs,
    /// Mode in force (0x6061).
    pub mode: i8,
    /// A mode written to 0x6060, in force at `due`.
    pub mode_pending: Option<(i8, u64)>,
    /// Previous controlword (edges of bits 4 and 7).
    pub prev_controlword: u16,
    /// CSP interpolation: from, to, elapsed and period (ns).
    pub interp_from: f64,
    pub interp_to: f64,
    pub interp_elapsed: u64,
    pub interp_period: u64,
    /// Position set-point the loops follow, and its velocity.
    pub setpoint: f64,
    pub velocity_demand: f64,
    /// Position held when nothing else commands.
    pub hold: f64,
    /// Velocity reference of PV and of stopping ramps.
    pub ramp_v: f64,
    /// A stopping ramp: deceleration and what follows.
    pub ramp: Option<(f64, RampEnd)>,
    /// How long the ramp's reference has been at zero.
    pub ramp_stopped_ns: u64,
    /// Following error (CSP) and how long it has been over the window.
    pub following_error: f64,
    pub ferr_over_ns: u64,
    pub ferr_flag: bool,
    /// PV: time within the velocity window / below the threshold.
    pub pv_reached_ns: u64,
    pub pv_zero_ns: u64,
    /// A software limit clamped the set-point.
    pub internal_limit: bool,
    /// Homing.
    pub homing: Homing,
}

impl SimDrive {
    /// Copies the control objects out of the dictionary.
    pub(super) fn load_knobs(&mut self) {
        let od = &self.od;
        let f = |index: u16, sub: u8| od.get_i64(index, sub) as f64;
        self.ctl.knobs = Knobs {
            controlword: od.get(obj::CONTROLWORD, 0) as u16,
            target_velocity: f(obj::TARGET_VELOCITY, 0),
            position_offset: f(obj::POSITION_OFFSET, 0),
            velocity_offset: f(obj::VELOCITY_OFFSET, 0),
            soft_limits: (f(obj::SOFTWARE_LIMIT, 1), f(obj::SOFTWARE_LIMIT, 2)),
            ferr_window: od.get(obj::FOLLOWING_ERROR_WINDOW, 0),
            ferr_timeout_ns: u64::from(od.get(obj::FOLLOWING_ERROR_TIMEOUT, 0)) * 1_000_000,
            profile_acceleration: f(obj::PROFILE_ACCELERATION, 0),
            profile_deceleration: f(obj::PROFILE_DECELERATION, 0),
            velocity_window: f(obj::VELOCITY_WINDOW, 0),
            velocity_threshold: f(obj::VELOCITY_THRESHOLD, 0),
            homing_switch_bit: match od.get_i64(obj::HOMING_METHOD, 0) {
                17 => 0,
                18 => 1,
                _ => 2,
            },
            homing_speeds: (f(obj::HOMING_SPEEDS, 1), f(obj::HOMING_SPEEDS, 2)),
            heartbeat_ns: u64::from(od.get(obj::PRODUCER_HEARTBEAT, 0)) * 1_000_000,
            consumer_ns: std::array::from_fn(|s| {
                u64::from(od.get(obj::CONSUMER_HEARTBEAT, s as u8 + 1) & 0xFFFF) * 1_000_000
            }),
        };
    }

    /// The last controlword the drive received (0x6040).
    pub fn controlword(&self) -> u16 {
        self.od.get(obj::CONTROLWORD, 0) as u16
    }

    /// The statusword as the drive shows it now.
    pub fn statusword(&self) -> u16 {
        let c = &self.ctl;
        let mut s = self.fsa.statusword_bits();
        if self.injected(Injection::UnderVoltage) && self.fsa != PowerState::Fault {
            s |= sw::WARNING;
        }
        if c.internal_limit {
            s |= sw::INTERNAL_LIMIT;
        }
        let enabled = self.fsa == PowerState::OperationEnabled;
        match c.mode {
            mode::CSP => {
                if enabled {
                    s |= sw::MODE_12;
                }
                if c.ferr_flag {
                    s |= sw::MODE_13;
                }
            }
            mode::CSV if enabled => s |= sw::MODE_12,
            mode::PV => {
                if c.pv_reached_ns >= self.window_ns(obj::VELOCITY_WINDOW_TIME) {
                    s |= sw::TARGET_REACHED;
                }
                if c.pv_zero_ns >= self.window_ns(obj::VELOCITY_THRESHOLD_TIME) {
                    s |= sw::MODE_12;
                }
            }
            mode::HM => {
                let still = self.axis.velocity().abs() < 1.0;
                s |= match c.homing {
                    Homing::Search { .. } | Homing::Leave { .. } => 0,
                    Homing::NotStarted | Homing::Interrupted => sw::TARGET_REACHED,
                    Homing::Done => sw::MODE_12 | sw::TARGET_REACHED,
                    Homing::Error if still => sw::MODE_13 | sw::TARGET_REACHED,
                    Homing::Error => sw::MODE_13,
                };
            }
            _ => {}
        }
        s
    }

    fn window_ns(&self, index: u16) -> u64 {
        u64::from(self.od.get(index, 0)) * 1_000_000
    }

    /// Reacts to new values of the controlword, modes of operation and
    /// targets. `from_pdo`: an RPDO was applied, which is a new CSP data
    /// set, and a mode change through it shows in 0x6061 only after the
    /// drive's mode delay (an SDO write of 0x6060 takes effect at once).
    pub(super) fn command_objects_changed(&mut self, from_pdo: bool, out: &mut Vec<Frame>) {
        let new_data_set = from_pdo;
        let wanted = self.od.get_i64(obj::MODES_OF_OPERATION, 0) as i8;
        let pending = self.ctl.mode_pending.map(|(m, _)| m);
        if wanted != self.ctl.mode && pending != Some(wanted) {
            let delay = if from_pdo { self.cfg.mode_delay_ns } else { 0 };
            self.ctl.mode_pending = Some((wanted, self.now_ns + delay));
            if delay == 0 {
                self.apply_mode();
            }
        } else if wanted == self.ctl.mode {
            self.ctl.mode_pending = None;
        }
        let controlword = self.od.get(obj::CONTROLWORD, 0) as u16;
        self.apply_controlword(controlword, out);
        if new_data_set && self.ctl.mode == mode::CSP {
            self.new_csp_target();
        }
    }

    fn apply_mode(&mut self) {
        let Some((m, _)) = self.ctl.mode_pending.take() else {
            return;
        };
        self.ctl.mode = m;
        self.ctl.homing = Homing::NotStarted;
        let p = self.axis.position();
        self.ctl.hold = p;
        self.ctl.interp_from = p;
        self.ctl.interp_to = p;
        self.ctl.interp_elapsed = u64::MAX / 2;
        self.ctl.ramp_v = self.axis.velocity();
        self.ctl.ferr_over_ns = 0;
        self.ctl.ferr_flag = false;
    }

    fn interpolation_period_ns(&self) -> u64 {
        let value = self.od.get(obj::INTERPOLATION_PERIOD, 1) as u8;
        let index = self.od.get_i64(obj::INTERPOLATION_PERIOD, 2).clamp(-9, 0) as i32;
        (f64::from(value) * 10f64.powi(index + 9)) as u64
    }

    fn new_csp_target(&mut self) {
        let period_ns = self.interpolation_period_ns();
        let c = &mut self.ctl;
        let period = c.interp_period.max(1);
        let t = (c.interp_elapsed as f64 / period as f64).min(1.0);
        c.interp_from += (c.interp_to - c.interp_from) * t;
        c.interp_to = self.od.get_i64(obj::TARGET_POSITION, 0) as f64;
        c.interp_elapsed = 0;
        c.interp_period = period_ns;
    }

    fn apply_controlword(&mut self, controlword: u16, out: &mut Vec<Frame>) {
        let prev = self.ctl.prev_controlword;
        self.ctl.prev_controlword = controlword;
        let command = Command::from_controlword(controlword);
        if command == Command::FaultReset {
            let edge = prev & cw::FAULT_RESET == 0;
            if edge && self.fsa == PowerState::Fault && !self.injected(Injection::UnderVoltage) {
                self.fsa = PowerState::SwitchOnDisabled;
                self.od.set(obj::ERROR_CODE, 0, 0);
                self.emcy(ErrorCode::NONE, out);
            }
            return;
        }
        if self.fsa == PowerState::OperationEnabled && self.ctl.mode == mode::HM {
            self.homing_edges(prev, controlword);
        }
        let Some(next) = transition(self.fsa, command) else {
            return;
        };
        let from = self.fsa;
        let p = self.axis.position();
        match (from, next) {
            (PowerState::OperationEnabled, PowerState::SwitchedOn) => {
                self.stop_by_option(obj::DISABLE_OPERATION_OPTION, RampEnd::PowerOff)
            }
            (PowerState::OperationEnabled, PowerState::ReadyToSwitchOn) => {
                self.stop_by_option(obj::SHUTDOWN_OPTION, RampEnd::PowerOff)
            }
            (PowerState::OperationEnabled, PowerState::QuickStopActive) => {
                let option = self.od.get_i64(obj::QUICK_STOP_OPTION, 0);
                let decel = match option {
                    1 | 5 => self.od.get(obj::PROFILE_DECELERATION, 0),
                    _ => self.od.get(obj::QUICK_STOP_DECELERATION, 0),
                };
                if option == 0 {
                    self.fsa = PowerState::SwitchOnDisabled;
                    self.ctl.ramp = None;
                    return;
                }
                let end = if option >= 5 {
                    RampEnd::Hold
                } else {
                    RampEnd::SwitchOnDisabled
                };
                self.start_ramp(f64::from(decel), end);
            }
            (PowerState::QuickStopActive, PowerState::OperationEnabled) => {
                if self.od.get_i64(obj::QUICK_STOP_OPTION, 0) < 5 {
                    return;
                }
                self.ctl.ramp = None;
            }
            (_, PowerState::OperationEnabled) => {
                // Enable: start from where the axis is; CSP follows
                // 0x607A from here, so a master that did not copy the
                // actual position into it sees the drive jump.
                self.ctl.hold = p;
                self.ctl.interp_from = p;
                self.ctl.interp_to = self.od.get_i64(obj::TARGET_POSITION, 0) as f64;
                self.ctl.interp_elapsed = 0;
                self.ctl.interp_period = self.interpolation_period_ns();
                self.ctl.ramp_v = 0.0;
                self.ctl.ramp = None;
                self.ctl.ferr_over_ns = 0;
                self.ctl.ferr_flag = false;
                self.ctl.homing = Homing::NotStarted;
            }
            (PowerState::QuickStopActive, _) => self.ctl.ramp = None,
            _ => {}
        }
        self.fsa = next;
    }

    /// Disable operation / shutdown from Operation enabled: option 0
    /// coasts, 1 ramps down with the profile deceleration first.
    fn stop_by_option(&mut self, option: u16, end: RampEnd) {
        if self.od.get_i64(option, 0) == 1 {
            let decel = f64::from(self.od.get(obj::PROFILE_DECELERATION, 0));
            self.start_ramp(decel, end);
        } else {
            self.ctl.ramp = None;
        }
    }

    fn start_ramp(&mut self, decel: f64, end: RampEnd) {
        self.ctl.ramp_v = self.axis.velocity();
        self.ctl.ramp_stopped_ns = 0;
        self.ctl.ramp = Some((decel.max(1.0), end));
    }

    /// A fault: EMCY, 0x603F, Fault reaction active per 0x605E, Fault.
    pub(super) fn raise_fault(&mut self, code: ErrorCode, out: &mut Vec<Frame>) {
        if matches!(
            self.fsa,
            PowerState::Fault | PowerState::FaultReactionActive
        ) {
            return;
        }
        self.od.set(obj::ERROR_CODE, 0, i64::from(code.0));
        self.emcy(code, out);
        let option = self.od.get_i64(obj::FAULT_REACTION_OPTION, 0);
        let powered = self.fsa.is_powered();
        if !powered || option == 0 {
            self.fsa = PowerState::Fault;
            self.ctl.ramp = None;
            return;
        }
        let decel = if option == 1 {
            self.od.get(obj::PROFILE_DECELERATION, 0)
        } else {
            self.od.get(obj::QUICK_STOP_DECELERATION, 0)
        };
        self.fsa = PowerState::FaultReactionActive;
        self.start_ramp(f64::from(decel), RampEnd::Fault);
    }

    /// The abort connection option code's reaction (0x6007).
    pub(super) fn reaction_6007(&mut self, out: &mut Vec<Frame>) {
        match self.od.get_i64(obj::ABORT_CONNECTION_OPTION, 0) {
            1 => self.raise_fault(ErrorCode::HEARTBEAT, out),
            2 => {
                if let Some(n) = transition(self.fsa, Command::DisableVoltage) {
                    self.fsa = n;
                    self.ctl.ramp = None;
                }
            }
            3 => self.apply_controlword(cw::QUICK_STOP_CMD, out),
            _ => {}
        }
    }

    fn homing_edges(&mut self, prev: u16, controlword: u16) {
        let was = prev & cw::MODE_4 != 0;
        let is = controlword & cw::MODE_4 != 0;
        if is && !was {
            self.start_homing();
        } else if was
            && !is
            && matches!(
                self.ctl.homing,
                Homing::Search { .. } | Homing::Leave { .. }
            )
        {
            self.ctl.homing = Homing::Interrupted;
            self.ctl.hold = self.axis.position();
        }
    }

    fn start_homing(&mut self) {
        let method = self.od.get_i64(obj::HOMING_METHOD, 0);
        let start = self.axis.position();
        let inputs = self.digital_inputs();
        let (bit, dir) = match method {
            35 | 37 => {
                self.finish_homing();
                return;
            }
            17 => (0, -1.0),
            18 => (1, 1.0),
            19 | 20 => (2, 1.0),
            21 | 22 => (2, -1.0),
            _ => {
                self.ctl.homing = Homing::Error;
                self.ctl.hold = start;
                return;
            }
        };
        self.ctl.homing = if inputs & (1 << bit) != 0 {
            Homing::Leave { dir: -dir, start }
        } else {
            Homing::Search { dir, start }
        };
    }

    fn finish_homing(&mut self) {
        let offset = self.od.get_i64(obj::HOME_OFFSET, 0) as f64;
        self.axis.rehome(offset);
        self.ctl.hold = offset;
        self.ctl.setpoint = offset;
        self.ctl.homing = Homing::Done;
    }

    fn homing_demand(&mut self) -> Demand {
        let (speed_search, speed_zero) = self.ctl.knobs.homing_speeds;
        let p = self.axis.position();
        let on = self.digital_inputs() & (1 << self.ctl.knobs.homing_switch_bit) != 0;
        match self.ctl.homing {
            Homing::Search { dir, start } => {
                if (p - start).abs() > HOMING_MAX_TRAVEL {
                    self.ctl.homing = Homing::Error;
                    self.ctl.hold = p;
                } else if on {
                    self.ctl.homing = Homing::Leave {
                        dir: -dir,
                        start: p,
                    };
                    return Demand::Velocity(-dir * speed_zero);
                } else {
                    return Demand::Velocity(dir * speed_search);
                }
            }
            Homing::Leave { dir, start } => {
                if (p - start).abs() > HOMING_MAX_TRAVEL {
                    self.ctl.homing = Homing::Error;
                    self.ctl.hold = p;
                } else if !on {
                    self.finish_homing();
                } else {
                    return Demand::Velocity(dir * speed_zero);
                }
            }
            _ => {}
        }
        Demand::Position {
            setpoint: self.ctl.hold,
            feed_forward: 0.0,
        }
    }

    fn csp_demand(&mut self, dt_ns: u64) -> Demand {
        let c = &mut self.ctl;
        c.interp_elapsed = c.interp_elapsed.saturating_add(dt_ns);
        let period = c.interp_period.max(1);
        let t = (c.interp_elapsed as f64 / period as f64).min(1.0);
        let mut setpoint = c.interp_from + (c.interp_to - c.interp_from) * t;
        let mut ff = if t < 1.0 {
            (c.interp_to - c.interp_from) / (period as f64 * 1e-9)
        } else {
            0.0
        };
        setpoint += c.knobs.position_offset;
        ff += c.knobs.velocity_offset;
        let (lo, hi) = c.knobs.soft_limits;
        c.internal_limit = false;
        if lo < hi && !(lo..=hi).contains(&setpoint) {
            setpoint = setpoint.clamp(lo, hi);
            ff = 0.0;
            c.internal_limit = true;
        }
        c.setpoint = setpoint;
        c.velocity_demand = ff;
        Demand::Position {
            setpoint,
            feed_forward: ff,
        }
    }

    fn pv_demand(&mut self, dt: f64, controlword: u16) -> Demand {
        let k = self.ctl.knobs;
        let target = if controlword & cw::HALT != 0 {
            0.0
        } else {
            k.target_velocity
        };
        let v = self.ctl.ramp_v;
        let speeding_up = target.abs() > v.abs() && target.signum() == v.signum() || v == 0.0;
        let a = if speeding_up {
            k.profile_acceleration
        } else {
            k.profile_deceleration
        };
        let step = a * dt;
        self.ctl.ramp_v = if (target - v).abs() <= step {
            target
        } else {
            v + step * (target - v).signum()
        };
        self.ctl.velocity_demand = self.ctl.ramp_v;
        Demand::Velocity(self.ctl.ramp_v)
    }

    /// One control period: the demand from state and mode, the loops,
    /// the monitors.
    pub(super) fn control_step(&mut self, dt_ns: u64, out: &mut Vec<Frame>) {
        if let Some((_, due)) = self.ctl.mode_pending {
            if self.now_ns >= due {
                self.apply_mode();
            }
        }
        let dt = dt_ns as f64 * 1e-9;
        let controlword = self.ctl.knobs.controlword;
        let demand = if let Some((decel, end)) = self.ctl.ramp {
            let v = self.ctl.ramp_v;
            let step = decel * dt;
            self.ctl.ramp_v = if v.abs() <= step {
                0.0
            } else {
                v - step * v.signum()
            };
            if self.ctl.ramp_v == 0.0 {
                self.ctl.ramp_stopped_ns += dt_ns;
            }
            let still = self.axis.velocity().abs() < decel * dt * 2.0 + 1.0;
            if self.ctl.ramp_v == 0.0 && (still || self.ctl.ramp_stopped_ns > RAMP_SETTLE_NS) {
                self.ctl.ramp_stopped_ns = 0;
                self.ctl.ramp = None;
                self.ctl.hold = self.axis.position();
                match end {
                    RampEnd::PowerOff => {}
                    RampEnd::SwitchOnDisabled => self.fsa = PowerState::SwitchOnDisabled,
                    RampEnd::Hold => {}
                    RampEnd::Fault => self.fsa = PowerState::Fault,
                }
            }
            Demand::Velocity(self.ctl.ramp_v)
        } else {
            match self.fsa {
                PowerState::OperationEnabled => match self.ctl.mode {
                    mode::CSP => self.csp_demand(dt_ns),
                    mode::CSV => {
                        let v = self.ctl.knobs.target_velocity + self.ctl.knobs.velocity_offset;
                        self.ctl.velocity_demand = v;
                        Demand::Velocity(v)
                    }
                    mode::PV => self.pv_demand(dt, controlword),
                    mode::HM => self.homing_demand(),
                    _ => Demand::Position {
                        setpoint: self.ctl.hold,
                        feed_forward: 0.0,
                    },
                },
                PowerState::QuickStopActive => Demand::Position {
                    setpoint: self.ctl.hold,
                    feed_forward: 0.0,
                },
                _ => Demand::Off,
            }
        };
        self.axis.step(demand, dt_ns);
        self.monitors(dt_ns, out);
    }

    fn monitors(&mut self, dt_ns: u64, out: &mut Vec<Frame>) {
        let enabled = self.fsa == PowerState::OperationEnabled && self.ctl.ramp.is_none();
        if enabled && self.ctl.mode == mode::CSP {
            let ferr = self.ctl.setpoint - self.axis.position();
            self.ctl.following_error = ferr;
            let (window, timeout) = (self.ctl.knobs.ferr_window, self.ctl.knobs.ferr_timeout_ns);
            if window != u32::MAX && ferr.abs() > f64::from(window) {
                self.ctl.ferr_over_ns += dt_ns;
                if self.ctl.ferr_over_ns > timeout {
                    self.ctl.ferr_flag = true;
                    self.raise_fault(ErrorCode::FOLLOWING_ERROR, out);
                }
            } else {
                self.ctl.ferr_over_ns = 0;
                self.ctl.ferr_flag = false;
            }
        } else {
            self.ctl.following_error = 0.0;
        }
        if self.ctl.mode == mode::PV {
            let v = self.axis.velocity();
            let k = self.ctl.knobs;
            let (target, window, threshold) =
                (k.target_velocity, k.velocity_window, k.velocity_threshold);
            let add = |ok: bool, t: u64| if ok { t.saturating_add(dt_ns) } else { 0 };
            self.ctl.pv_reached_ns = add(
                enabled && (v - target).abs() <= window,
                self.ctl.pv_reached_ns,
            );
            self.ctl.pv_zero_ns = add(v.abs() <= threshold, self.ctl.pv_zero_ns);
        }
        if self.ctl.mode != mode::CSP {
            self.ctl.internal_limit = false;
            if self.ctl.mode != mode::PV {
                self.ctl.setpoint = self.ctl.hold;
            }
        }
    }
}
