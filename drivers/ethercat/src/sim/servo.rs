//! A simulated CiA 402 servo drive over CoE: the power state machine of
//! the shared layer ([`hal_cia402::power::transition`]), the modes CSP,
//! CSV, PP (set-point handshake, profile velocity) and homing through the
//! drive (method in 0x6098, home offset 0x607C), emergencies on a fault,
//! and the process data a typical drive maps by default:
//!
//! | PDO | entries |
//! |---|---|
//! | RxPDO 0x1600 | controlword 0x6040, target position 0x607A, target velocity 0x60FF, modes of operation 0x6060 |
//! | TxPDO 0x1A00 | statusword 0x6041, position actual 0x6064, velocity actual 0x606C, mode display 0x6061, error code 0x603F |
//!
//! The motor follows its set-point exactly (this model is for the
//! protocol, not for tuning: canservo's simulated drive has the motor
//! and loops). Leaving OP while the power stage is on is a
//! communication fault (0x8700), as on a real drive.

use std::any::Any;

use hal_cia402::objects::{cw, mode, obj, sw};
use hal_cia402::power::{transition, Command, PowerState};

use super::device::{dictionary, Application, Device, PdoSpec, INPUTS_AT, OUTPUTS_AT};
use super::od::{dtype, Access, Dictionary};
use crate::wire::coe::{Emergency, ErrorCode};
use crate::wire::sii::Identity;

/// The simulated drives' vendor id (none of a real maker).
pub const SIM_VENDOR: u32 = 0x0000_0E5C;
/// Their product code.
pub const SIM_SERVO: u32 = 0x0000_0402;
/// Error code of a communication fault (left OP while powered).
pub const COMMUNICATION_FAULT: u16 = 0x8700;
/// How long homing searches before it finds home.
const HOMING_NS: u64 = 20_000_000;

/// Where homing is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Homing {
    Idle,
    Searching { since_ns: u64 },
    Attained,
}

/// The drive's application.
#[derive(Debug)]
pub struct Servo {
    /// Power state.
    pub state: PowerState,
    /// Position (counts).
    pub position: f64,
    /// Velocity (counts/s).
    pub velocity: f64,
    prev_cw: u16,
    pending_fault: Option<u16>,
    emergencies: Vec<Emergency>,
    homing: Homing,
    pp_target: Option<f64>,
    /// The controlword each cycle acted on, oldest first (the last
    /// [`APPLIED_KEPT`]): what reached the drive, for tests.
    pub applied: std::collections::VecDeque<u16>,
}

/// How many applied controlwords [`Servo::applied`] keeps.
pub const APPLIED_KEPT: usize = 65_536;

impl Servo {
    /// Raises a drive fault with `code` (over-current, following error,
    /// ...): Fault state, 0x603F, and an emergency.
    pub fn inject_fault(&mut self, code: u16) {
        self.pending_fault = Some(code);
    }

    /// Sends an emergency with `code` and nothing else (a warning a
    /// drive reports while it keeps running, or an error the drive
    /// reports before its state follows).
    pub fn send_emergency(&mut self, code: u16) {
        self.emergencies.push(Emergency {
            code: ErrorCode(code),
            register: 0x01,
            data: [0; 5],
        });
    }

    fn fault(&mut self, od: &mut Dictionary, code: u16) {
        self.state = PowerState::Fault;
        od.set(obj::ERROR_CODE, 0, u64::from(code));
        self.emergencies.push(Emergency {
            code: ErrorCode(code),
            register: 0x01,
            data: [0; 5],
        });
    }

    fn power(&mut self, od: &mut Dictionary, controlword: u16) {
        let rising_reset =
            controlword & cw::FAULT_RESET != 0 && self.prev_cw & cw::FAULT_RESET == 0;
        let command = Command::from_controlword(controlword);
        if command == Command::FaultReset {
            if self.state == PowerState::Fault && rising_reset {
                self.state = PowerState::SwitchOnDisabled;
                od.set(obj::ERROR_CODE, 0, 0);
            }
        } else if let Some(next) = transition(self.state, command) {
            self.state = next;
            if next == PowerState::QuickStopActive {
                // Option code 2: stop, then Switch on disabled.
                self.state = PowerState::SwitchOnDisabled;
            }
        }
    }

    fn motion(&mut self, od: &mut Dictionary, controlword: u16, now_ns: u64, dt: f64) -> u16 {
        let m = od.get_signed(obj::MODES_OF_OPERATION, 0) as i8;
        od.set(obj::MODES_DISPLAY, 0, m as u8 as u64);
        let enabled = self.state == PowerState::OperationEnabled;
        let bit4_rising = controlword & cw::MODE_4 != 0 && self.prev_cw & cw::MODE_4 == 0;
        let before = self.position;
        let mut bits = 0u16;
        if m != mode::HM {
            self.homing = Homing::Idle;
        }
        if m != mode::PP {
            self.pp_target = None;
        }
        match m {
            mode::CSP if enabled => {
                self.position = od.get_signed(obj::TARGET_POSITION, 0) as f64;
                bits |= sw::MODE_12;
            }
            mode::CSV if enabled => {
                self.position += od.get_signed(obj::TARGET_VELOCITY, 0) as f64 * dt;
                bits |= sw::MODE_12;
            }
            mode::PP => {
                if enabled && bit4_rising {
                    self.pp_target = Some(od.get_signed(obj::TARGET_POSITION, 0) as f64);
                }
                if controlword & cw::MODE_4 != 0 && enabled {
                    bits |= sw::MODE_12; // set-point acknowledge
                }
                match self.pp_target {
                    Some(t) if enabled => {
                        let speed = od.get(obj::PROFILE_VELOCITY, 0) as f64;
                        let step = speed * dt;
                        self.position += (t - self.position).clamp(-step, step);
                        if (t - self.position).abs() < 0.5 {
                            bits |= sw::TARGET_REACHED;
                        }
                    }
                    _ => bits |= sw::TARGET_REACHED,
                }
            }
            mode::HM => {
                if enabled && bit4_rising {
                    self.homing = Homing::Searching { since_ns: now_ns };
                }
                match self.homing {
                    Homing::Searching { since_ns } if enabled => {
                        self.position += 1000.0 * dt;
                        if now_ns.saturating_sub(since_ns) >= HOMING_NS {
                            self.position = od.get_signed(obj::HOME_OFFSET, 0) as f64;
                            self.homing = Homing::Attained;
                        }
                    }
                    Homing::Searching { .. } => self.homing = Homing::Idle,
                    Homing::Attained => bits |= sw::MODE_12 | sw::TARGET_REACHED,
                    Homing::Idle => bits |= sw::TARGET_REACHED,
                }
            }
            _ => {}
        }
        self.velocity = if dt > 0.0 {
            (self.position - before) / dt
        } else {
            0.0
        };
        bits
    }
}

impl Application for Servo {
    fn cycle(&mut self, od: &mut Dictionary, outputs_valid: bool, now_ns: u64, dt_ns: u64) {
        let dt = dt_ns as f64 * 1e-9;
        if let Some(code) = self.pending_fault.take() {
            self.fault(od, code);
        }
        let controlword = if outputs_valid {
            od.get(obj::CONTROLWORD, 0) as u16
        } else {
            if self.state.is_powered() {
                self.fault(od, COMMUNICATION_FAULT);
            }
            cw::DISABLE_VOLTAGE
        };
        if self.applied.len() >= APPLIED_KEPT {
            self.applied.pop_front();
        }
        self.applied.push_back(controlword);
        self.power(od, controlword);
        let bits = self.motion(od, controlword, now_ns, dt);
        self.prev_cw = controlword;
        let statusword = self.state.statusword_bits() | bits;
        od.set(obj::STATUSWORD, 0, u64::from(statusword));
        od.set(obj::POSITION_ACTUAL, 0, self.position.round() as i64 as u64);
        od.set(obj::VELOCITY_ACTUAL, 0, self.velocity.round() as i64 as u64);
    }

    fn take_emergency(&mut self) -> Option<Emergency> {
        (!self.emergencies.is_empty()).then(|| self.emergencies.remove(0))
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// A CiA 402 servo drive with DC (SYNC0).
pub fn servo(serial: u32) -> Device {
    let id = Identity {
        vendor: SIM_VENDOR,
        product: SIM_SERVO,
        revision: 1,
        serial,
    };
    let outs = [PdoSpec {
        index: 0x1600,
        name: "RxPDO 1",
        entries: vec![
            (obj::CONTROLWORD, 0, "Controlword", dtype::U16, 16),
            (obj::TARGET_POSITION, 0, "Target position", dtype::I32, 32),
            (obj::TARGET_VELOCITY, 0, "Target velocity", dtype::I32, 32),
            (
                obj::MODES_OF_OPERATION,
                0,
                "Modes of operation",
                dtype::I8,
                8,
            ),
        ],
    }];
    let ins = [PdoSpec {
        index: 0x1A00,
        name: "TxPDO 1",
        entries: vec![
            (obj::STATUSWORD, 0, "Statusword", dtype::U16, 16),
            (
                obj::POSITION_ACTUAL,
                0,
                "Position actual value",
                dtype::I32,
                32,
            ),
            (
                obj::VELOCITY_ACTUAL,
                0,
                "Velocity actual value",
                dtype::I32,
                32,
            ),
            (
                obj::MODES_DISPLAY,
                0,
                "Modes of operation display",
                dtype::I8,
                8,
            ),
            (obj::ERROR_CODE, 0, "Error code", dtype::U16, 16),
        ],
    }];
    let mut od = dictionary(id, "Sim CiA402 Servo", &outs, &ins, &[0x1600], &[0x1A00]);
    od.add(
        obj::DEVICE_TYPE,
        0,
        "Device type",
        (dtype::U32, 32),
        Access::Ro,
        0x0002_0192,
    );
    od.add(
        obj::ERROR_REGISTER,
        0,
        "Error register",
        (dtype::U8, 8),
        Access::Ro,
        0,
    );
    od.add(
        obj::HOME_OFFSET,
        0,
        "Home offset",
        (dtype::I32, 32),
        Access::Rw,
        0,
    );
    od.add(
        obj::PROFILE_VELOCITY,
        0,
        "Profile velocity",
        (dtype::U32, 32),
        Access::Rw,
        100_000,
    );
    od.add(
        obj::PROFILE_ACCELERATION,
        0,
        "Profile acceleration",
        (dtype::U32, 32),
        Access::Rw,
        1_000_000,
    );
    od.add(
        obj::HOMING_METHOD,
        0,
        "Homing method",
        (dtype::I8, 8),
        Access::Rw,
        35,
    );
    let modes = [mode::PP, mode::PV, mode::HM, mode::CSP, mode::CSV];
    let supported = modes
        .iter()
        .filter_map(|m| mode::supported_bit(*m))
        .fold(0, |a, b| a | b);
    od.add(
        obj::SUPPORTED_MODES,
        0,
        "Supported drive modes",
        (dtype::U32, 32),
        Access::Ro,
        u64::from(supported),
    );
    od.add(
        obj::INTERPOLATION_PERIOD,
        0,
        "Interpolation time period",
        (dtype::U8, 8),
        Access::Ro,
        2,
    );
    od.add(
        obj::INTERPOLATION_PERIOD,
        1,
        "Value",
        (dtype::U8, 8),
        Access::Rw,
        1,
    );
    od.add(
        obj::INTERPOLATION_PERIOD,
        2,
        "Index",
        (dtype::I8, 8),
        Access::Rw,
        (-3i8) as u8 as u64,
    );
    Device {
        kind: "servo".into(),
        identity: id,
        name: "Simulated CiA 402 servo drive".into(),
        order: "SimServo".into(),
        group: "Drive".into(),
        mailbox: true,
        dc: true,
        needs_sync0: false,
        od,
        outputs_at: OUTPUTS_AT,
        inputs_at: INPUTS_AT,
        app: Box::new(Servo {
            state: PowerState::SwitchOnDisabled,
            position: 0.0,
            velocity: 0.0,
            prev_cw: 0,
            pending_fault: None,
            emergencies: Vec::new(),
            homing: Homing::Idle,
            pp_target: None,
            applied: std::collections::VecDeque::new(),
        }),
    }
}
