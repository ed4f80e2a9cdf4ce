//! bldc's per-call logic: the rotor angle from the configured feedback
//! (none, Hall sensors, Fanuc Gray code, absolute or incremental encoder
//! with its homing sequences), then the drive outputs from it.

use super::tables::{find, ANGLES, COMMUTATION, GRAY_ANGLES, GRAY_CODES, PATTERNS, PHASES};
use crate::cmath::f64_to_i32;

/// Personality bit: Hall sensor input (`h`).
pub const HALL: u32 = 0x01;
/// Personality bit: absolute encoder (`a`).
pub const ABSOLUTE: u32 = 0x02;
/// Personality bit: incremental encoder (`q`).
pub const QUADRATURE: u32 = 0x04;
/// Personality bit: encoder index as the home reference (`i`).
pub const INDEX: u32 = 0x08;
/// Personality bit: Fanuc Gray-code input (`f`).
pub const FANUC: u32 = 0x10;
/// Personality bit: bit-level outputs (`B`).
pub const BITS_OUT: u32 = 0x100;
/// Personality bit: six outputs instead of three (`6`).
pub const SIX: u32 = 0x200;
/// Personality bit: emulated Hall outputs (`H`).
pub const HALL_OUT: u32 = 0x400;
/// Personality bit: emulated Fanuc Gray-code outputs (`F`).
pub const FANUC_OUT: u32 = 0x800;
/// Personality bit: force trapezoidal commutation (`T`).
pub const TRAPEZOIDAL: u32 = 0x8000;

/// The input type once homed, or with an absolute encoder.
const SINE: i32 = 0x02;
/// The input type that disables the motor after a configuration error.
const DISABLED: i32 = -2;
/// The input type before the first call has set it up.
const UNSET: i32 = -1;

/// The magnetic alignment sequence: time left (s) at each breakpoint,
/// the current (fraction of `initvalue`) and the angle (turns) there.
const ALIGN_TIME: [f64; 6] = [2.4, 2.0, 1.2, 0.8, 0.4, 0.0];
const ALIGN_CURRENT: [f64; 6] = [0.0, 1.0, 1.0, 1.0, 1.0, 1.0];
const ALIGN_ANGLE: [f64; 6] = [0.0, 0.0, -0.25, 0.25, 0.0, 0.0];

const COS120: f64 = -0.5;
const SIN120: f64 = 0.866_025_403_784_438_6;
const TWO_PI: f64 = std::f64::consts::TAU;

/// What bldc reports on stderr.
pub static TEXTS: &[&str] = &[
    "bldc: only Hall patterns 0 to 47 exist; pattern reset to 0\n",
    "bldc: error in the homing sequence: init done without a state\n",
    "bldc: Hall sensors and an absolute encoder on one motor: only the encoder is used\n",
    "bldc: absolute and incremental encoders on one motor: motor disabled\n",
    "bldc: an index alone cannot commutate a motor: motor disabled\n",
    "bldc: an index with Hall sensors is not supported: trapezoidal commutation used\n",
    "bldc: an absolute encoder needs no index: the index is ignored\n",
    "bldc: unknown input type: motor disabled\n",
    "bldc: Hall outputs cannot be combined with bit outputs: Hall outputs used\n",
    "bldc: Hall outputs cannot be six-wire: three-wire Hall outputs used\n",
    "bldc: bit outputs cannot be combined with Gray-code outputs: Gray code used\n",
    "bldc: Hall and Gray-code outputs cannot be combined: Hall outputs used\n",
    "bldc: unsupported output type: motor disabled\n",
];

/// Index into [`TEXTS`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Message {
    BadPattern = 0,
    HomingState,
    HallAndAbsolute,
    TwoEncoders,
    IndexOnly,
    HallAndIndex,
    AbsoluteAndIndex,
    UnknownInput,
    HallAndBits,
    SixWireHall,
    BitsAndGray,
    HallAndGray,
    UnknownOutput,
}

/// What the input stage of one call found.
enum Sensed {
    /// The angles are set: commutate (trapezoidal on Hall phases `ph`
    /// when `trap`).
    Angles {
        /// Trapezoidal commutation.
        trap: bool,
        /// The Hall phase bits.
        ph: u8,
    },
    /// Nothing more this call; maybe a message to print.
    Done(Option<Message>),
}

impl Sensed {
    /// Angles set, no Hall phases: sinusoidal unless forced trapezoidal.
    const NO_PHASES: Sensed = Sensed::Angles { trap: false, ph: 0 };
}

/// Every pin and param value one call reads or writes (those the
/// personality does not create stay at their defaults).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(missing_docs)]
pub struct BldcVars {
    // Inputs.
    pub hall: [bool; 3],
    pub fanuc: [bool; 4],
    pub value: f64,
    pub lead_angle: f64,
    pub rev: bool,
    pub frequency: f64,
    pub initvalue: f64,
    pub rawcounts: i32,
    pub init: bool,
    pub scale: i32,
    pub poles: i32,
    pub encoder_offset: i32,
    pub drive_offset: f64,
    pub output_pattern: u32,
    // Read and written.
    pub index_enable: bool,
    pub pattern: u32,
    pub init_done: bool,
    pub in_type: i32,
    pub out_type: i32,
    pub offset_measured: i32,
    pub phase_angle: f64,
    pub rotor_angle: f64,
    // Outputs.
    pub hall_error: bool,
    /// A-value, B-value, C-value (or A-high.. in six-wire mode).
    pub value_out: [f64; 3],
    /// A-on, B-on, C-on.
    pub on: [bool; 3],
    /// A-low, B-low, C-low.
    pub low: [f64; 3],
    /// A-high-on, B-high-on, C-high-on.
    pub high_on: [bool; 3],
    /// A-low-on, B-low-on, C-low-on.
    pub low_on: [bool; 3],
    pub hall_out: [bool; 3],
    pub fanuc_out: [bool; 4],
    pub out: f64,
    pub out_dir: bool,
    pub out_abs: f64,
}

/// Per-instance state besides the pins.
#[derive(Debug, Clone)]
pub struct Bldc {
    /// The instance's personality bits.
    pub personality: u32,
    old_init: bool,
    old_ph: u8,
    old_pattern: i64,
    counter: f64,
    long_rawcounts: i64,
    old_long_rawcounts: i64,
    old_rawcounts: i32,
    force_trap: bool,
}

impl Bldc {
    /// A controller for `personality`.
    pub fn new(personality: u32) -> Bldc {
        Bldc {
            personality,
            old_init: false,
            old_ph: 0,
            old_pattern: -1,
            counter: 0.0,
            long_rawcounts: 0,
            old_long_rawcounts: 0,
            old_rawcounts: 0,
            force_trap: false,
        }
    }

    /// Counts per electrical turn over two, as LinuxCNC's integer
    /// `2 * scale / poles` (0 for zero poles, where LinuxCNC would
    /// crash).
    fn counts_per_half(v: &BldcVars) -> i32 {
        v.scale.wrapping_mul(2).checked_div(v.poles).unwrap_or(0)
    }

    /// The encoder offset for a rotor at `angle` now.
    fn offset_at(&self, v: &BldcVars, angle: f64) -> i32 {
        f64_to_i32(self.long_rawcounts as f64 - angle * f64::from(Self::counts_per_half(v)))
    }

    /// One call of a thread of `period` ns. Returns a message to print.
    pub fn step(&mut self, v: &mut BldcVars, period: i64) -> Option<Message> {
        let mut volts = if v.rev { -v.value } else { v.value };
        v.out_dir = volts < 0.0;
        v.out_abs = volts.abs();
        self.track_counts(v);
        let (mut trap, mut ph) = match self.sense(v, period, &mut volts) {
            Sensed::Angles { trap, ph } => (trap, ph),
            Sensed::Done(message) => return message,
        };
        if !trap {
            // The trapezoidal excitation for this rotor angle.
            let i = (0..8)
                .take_while(|&i| v.rotor_angle > ANGLES[i] - 3.0 / 36.0)
                .count()
                .min(7);
            ph = PHASES[i];
        }
        if self.force_trap {
            trap = true;
        }
        v.out = volts;
        v.out_abs = volts.abs();
        self.outputs(v, ph, trap)
    }

    /// Re-arms quadrature initialisation on a rising `init` and extends
    /// the encoder's raw count to 64 bits.
    fn track_counts(&mut self, v: &mut BldcVars) {
        let p = self.personality;
        if p & (HALL | QUADRATURE) == QUADRATURE {
            if v.init && !self.old_init && v.init_done {
                v.init_done = false;
                v.in_type = UNSET;
            } else {
                self.old_init = v.init;
            }
        }
        if p & (ABSOLUTE | QUADRATURE) != 0 {
            self.old_long_rawcounts = self.long_rawcounts;
            self.long_rawcounts += i64::from(v.rawcounts.wrapping_sub(self.old_rawcounts));
            self.old_rawcounts = v.rawcounts;
        }
    }

    /// The rotor and phase angles from the inputs the personality has, by
    /// the input stage the component is in (`v.in_type`); the stages that
    /// align or home may change `volts`.
    fn sense(&mut self, v: &mut BldcVars, period: i64, volts: &mut f64) -> Sensed {
        match v.in_type {
            DISABLED => Sensed::Done(None),
            UNSET => {
                self.start(v);
                Sensed::Done(None)
            }
            0x00 => {
                v.phase_angle += v.frequency * period as f64 / 1_000_000_000.0;
                v.phase_angle -= v.phase_angle.floor();
                v.rotor_angle = v.phase_angle;
                Sensed::NO_PHASES
            }
            0x01 | 0x05 | 0x0d => self.sense_hall(v),
            0x10 | 0x14 | 0x1c => self.sense_fanuc(v),
            0x04 => self.align(v, period, volts),
            0x0c => self.seek_index(v, period, volts),
            SINE => {
                self.sense_encoder(v);
                Sensed::NO_PHASES
            }
            _ => Sensed::Done(Some(Self::refuse(v))),
        }
    }

    /// The first call: the input and output types from the personality.
    fn start(&mut self, v: &mut BldcVars) {
        let p = self.personality;
        v.in_type = (p & 0xff) as i32;
        if v.in_type & INDEX as i32 != 0 {
            v.index_enable = true;
        }
        self.counter = ALIGN_TIME[0];
        v.out_type = (p & 0x7f00) as i32;
        self.force_trap = p & TRAPEZOIDAL != 0;
    }

    /// Hall sensors (with homing to a Hall edge or to the index).
    fn sense_hall(&mut self, v: &mut BldcVars) -> Sensed {
        if v.pattern as usize >= PATTERNS {
            v.pattern = 0;
            return Sensed::Done(Some(Message::BadPattern));
        }
        let hall = (v.hall[0] as usize) << 2 | (v.hall[1] as usize) << 1 | v.hall[2] as usize;
        let ph = COMMUTATION[v.pattern as usize * 8 + hall];
        // A Hall state the pattern never shows has no angle: 0.
        let i = find(&PHASES, 0, ph);
        v.rotor_angle = ANGLES.get(i).copied().unwrap_or(0.0);
        v.rotor_angle -= v.rotor_angle.floor();
        v.phase_angle = if v.out_dir {
            v.rotor_angle + 0.25
        } else {
            v.rotor_angle - 0.25
        };
        v.phase_angle -= v.phase_angle.floor();
        if ph & self.old_ph == 0 {
            v.hall_error = true;
        }
        if i64::from(v.pattern) != self.old_pattern {
            v.hall_error = false;
        }
        if !self.force_trap {
            let i = find(&PHASES, 1, ph);
            if v.in_type == 0x05 && self.old_ph != 0 && ph != self.old_ph && i < 7 {
                // Homing to the Hall edge just crossed.
                v.rotor_angle = if PHASES[i - 1] == self.old_ph {
                    (ANGLES[i] + ANGLES[i - 1]) / 2.0
                } else {
                    (ANGLES[i] + ANGLES[i + 1]) / 2.0
                };
                self.home_to_edge(v);
            } else if v.in_type == 0x0d && !v.index_enable {
                v.offset_measured = self.long_rawcounts as i32;
                v.in_type = SINE;
            }
            self.old_ph = ph;
            self.old_pattern = i64::from(v.pattern);
        }
        Sensed::Angles { trap: true, ph }
    }

    /// Fanuc Gray-code commutation (with homing to a code edge or to the
    /// index).
    fn sense_fanuc(&mut self, v: &mut BldcVars) -> Sensed {
        let ph = v.fanuc[0] as u8
            | (v.fanuc[1] as u8) << 1
            | (v.fanuc[2] as u8) << 2
            | (v.fanuc[3] as u8) << 3;
        let i = find(&GRAY_CODES[..16], 0, ph);
        v.rotor_angle = GRAY_ANGLES[i] + 0.03125;
        v.rotor_angle -= v.rotor_angle.floor();
        v.phase_angle = if v.out_dir {
            v.rotor_angle - 0.25
        } else {
            v.rotor_angle + 0.25
        };
        v.phase_angle -= v.phase_angle.floor();
        if !self.force_trap {
            if v.in_type == 0x14 && self.old_ph != 0 && ph != self.old_ph {
                let i = find(&GRAY_CODES[..15], 1, ph);
                // LinuxCNC compares with the Hall sequence here
                // (reading past it for later codes); past its
                // end nothing matches.
                v.rotor_angle = if PHASES.get(i - 1) == Some(&self.old_ph) {
                    GRAY_ANGLES[i]
                } else {
                    GRAY_ANGLES[i + 1]
                };
                self.home_to_edge(v);
            } else if v.in_type == 0x1c && !v.index_enable {
                v.offset_measured = self.long_rawcounts as i32;
                v.in_type = SINE;
            }
            self.old_ph = ph;
        }
        Sensed::Angles { trap: false, ph }
    }

    /// An incremental encoder without sensors: pulls the rotor to known
    /// angles along the alignment ramp, then takes the offset.
    fn align(&mut self, v: &mut BldcVars, period: i64, volts: &mut f64) -> Sensed {
        if !v.init {
            return Sensed::Done(None);
        }
        if v.init_done {
            return Sensed::Done(Some(Message::HomingState));
        }
        if self.counter <= 0.0 {
            v.offset_measured = self.offset_at(v, v.phase_angle);
            self.counter = ALIGN_TIME[0];
            self.old_init = true;
            v.init_done = true;
            v.in_type = SINE;
            return Sensed::Done(None);
        }
        v.init_done = false;
        // The breakpoint segment the counter is in (i in 1..=5).
        let i = (0..6)
            .take_while(|&i| ALIGN_TIME[i] >= self.counter)
            .count()
            .clamp(1, 5);
        let frac = |t: &[f64; 6]| {
            t[i - 1]
                + (t[i] - t[i - 1]) * (self.counter - ALIGN_TIME[i - 1])
                    / (ALIGN_TIME[i] - ALIGN_TIME[i - 1])
        };
        *volts = v.initvalue * frac(&ALIGN_CURRENT);
        v.phase_angle = frac(&ALIGN_ANGLE);
        v.phase_angle -= v.phase_angle.floor();
        self.counter -= period as f64 * 1e-9;
        v.rotor_angle = v.phase_angle - v.drive_offset / 360.0;
        v.rotor_angle -= v.rotor_angle.floor();
        Sensed::NO_PHASES
    }

    /// An encoder with index: turns slowly until the index latches.
    fn seek_index(&mut self, v: &mut BldcVars, period: i64, volts: &mut f64) -> Sensed {
        if !v.init {
            return Sensed::Done(None);
        }
        if !v.index_enable {
            v.offset_measured = self.long_rawcounts as i32;
            self.counter = ALIGN_TIME[0];
            self.old_init = true;
            v.init_done = true;
            v.in_type = SINE;
        } else if !v.init_done {
            // Turn slowly until the encoder latches its index.
            if v.initvalue < 0.0 {
                v.rotor_angle -= period as f64 / 1_000_000_000.0;
            } else {
                v.rotor_angle += period as f64 / 1_000_000_000.0;
            }
            v.rotor_angle -= v.rotor_angle.floor();
            v.phase_angle = v.rotor_angle;
            *volts = v.initvalue.abs();
        }
        Sensed::NO_PHASES
    }

    /// Sinusoidal commutation from the encoder count and the measured
    /// offset, with the lead angle.
    fn sense_encoder(&self, v: &mut BldcVars) {
        let lead = if v.out_dir && !self.force_trap {
            v.lead_angle / -360.0
        } else {
            v.lead_angle / 360.0
        };
        let lagcomped = self.long_rawcounts + (self.long_rawcounts - self.old_long_rawcounts) / 2;
        let electrical = lagcomped
            .wrapping_sub(i64::from(v.offset_measured))
            .wrapping_sub(i64::from(v.encoder_offset))
            .wrapping_mul(i64::from(v.poles))
            / 2;
        v.rotor_angle = electrical as f64 / f64::from(v.scale);
        v.rotor_angle -= v.rotor_angle.floor();
        v.phase_angle = v.rotor_angle + lead;
        v.phase_angle -= v.phase_angle.floor();
    }

    /// An input combination the component cannot use: the stage it falls
    /// back to, and what to tell the user.
    fn refuse(v: &mut BldcVars) -> Message {
        let (next, message) = match v.in_type {
            0x03 | 0x0b => (SINE, Message::HallAndAbsolute),
            0x06 | 0x07 | 0x0e | 0x0f => (DISABLED, Message::TwoEncoders),
            0x08 => (DISABLED, Message::IndexOnly),
            0x09 => (0x01, Message::HallAndIndex),
            0x0a => (SINE, Message::AbsoluteAndIndex),
            _ => (DISABLED, Message::UnknownInput),
        };
        v.in_type = next;
        message
    }

    /// Switches to sinusoidal commutation once homed on a sensor edge,
    /// with `v.rotor_angle` set to the edge's angle.
    fn home_to_edge(&mut self, v: &mut BldcVars) {
        v.rotor_angle -= v.rotor_angle.floor();
        v.phase_angle = if v.out_dir {
            v.rotor_angle - 0.25
        } else {
            v.rotor_angle + 0.25
        };
        v.phase_angle -= v.phase_angle.floor();
        v.offset_measured = self.offset_at(v, v.rotor_angle);
        v.in_type = SINE;
    }

    /// The drive outputs for excitation `ph` (trapezoidal) or the phase
    /// angle (sinusoidal).
    fn outputs(&mut self, v: &mut BldcVars, ph: u8, trap: bool) -> Option<Message> {
        let reversed = |ph: u8| (ph & 0o70) >> 3 | (ph & 0o7) << 3;
        let sine = |v: &BldcVars| {
            let s = (v.phase_angle * TWO_PI).sin();
            let c = (v.phase_angle * TWO_PI).cos();
            [c, c * COS120 + s * SIN120, c * COS120 - s * SIN120]
        };
        match v.out_type {
            0 => {
                if trap {
                    for k in 0..3 {
                        v.value_out[k] = if ph & (0o40 >> k) != 0 {
                            v.out
                        } else if ph & (0o4 >> k) != 0 {
                            -v.out
                        } else {
                            0.0
                        };
                    }
                } else {
                    let w = sine(v);
                    for (o, w) in v.value_out.iter_mut().zip(w) {
                        *o = v.out_abs * w;
                    }
                }
            }
            0x100 => {
                // LinuxCNC's three-wire bit mode, kept exactly: the first
                // high-side phase found is set, then the first low-side
                // one cleared.
                let ph = if v.out_dir { reversed(ph) } else { ph };
                match (0..3).find(|&k| ph & (0o40 >> k) != 0) {
                    Some(k) => v.on[k] = true,
                    None => v.on = [false; 3],
                }
                match (0..3).find(|&k| ph & (0o4 >> k) != 0) {
                    Some(k) => v.on[k] = false,
                    None => v.on = [false; 3],
                }
            }
            0x200 => {
                if trap {
                    let ph = if v.out_dir { reversed(ph) } else { ph };
                    for k in 0..3 {
                        (v.value_out[k], v.low[k]) = if ph & (0o40 >> k) != 0 {
                            (v.out_abs, 0.0)
                        } else if ph & (0o4 >> k) != 0 {
                            (0.0, v.out_abs)
                        } else {
                            (0.0, 0.0)
                        };
                    }
                } else {
                    let w = sine(v);
                    for ((high, low), w) in v.value_out.iter_mut().zip(&mut v.low).zip(w) {
                        (*high, *low) = if w >= 0.0 {
                            (v.out_abs * w, 0.0)
                        } else {
                            (0.0, -v.out_abs * w)
                        };
                    }
                }
            }
            0x300 => {
                let (high, low) = if v.out_dir { (0o4, 0o40) } else { (0o40, 0o4) };
                for k in 0..3 {
                    v.high_on[k] = ph & (high >> k) != 0;
                    v.low_on[k] = ph & (low >> k) != 0;
                }
            }
            0x400 => {
                let pattern = v.output_pattern as usize;
                let hall = if pattern < PATTERNS {
                    find(&COMMUTATION[pattern * 8..pattern * 8 + 8], 0, ph)
                } else {
                    8
                };
                v.hall_out = [hall & 4 != 0, hall & 2 != 0, hall & 1 != 0];
            }
            0x800 => {
                let i = (0..16)
                    .take_while(|&i| GRAY_ANGLES[i] + 0.0625 < v.rotor_angle)
                    .count();
                let code = GRAY_CODES[i];
                v.fanuc_out = std::array::from_fn(|k| code & (1 << k) != 0);
            }
            0x500 => {
                v.out_type = 0x400;
                return Some(Message::HallAndBits);
            }
            0x600 | 0x700 => {
                v.out_type = 0x400;
                return Some(Message::SixWireHall);
            }
            0x900 | 0xa00 | 0xb00 => {
                v.out_type = 0x800;
                return Some(Message::BitsAndGray);
            }
            0xc00 => {
                v.out_type = 0x400;
                return Some(Message::HallAndGray);
            }
            _ => {
                v.in_type = DISABLED;
                return Some(Message::UnknownOutput);
            }
        }
        None
    }
}
