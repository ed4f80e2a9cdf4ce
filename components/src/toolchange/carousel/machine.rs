//! carousel's state machine: choosing a direction, moving to the pocket,
//! the optional locking reverse pulse or slow alignment move, jogging one
//! pocket, and homing for the relative encodings.

use super::config::{Config, Encoding};
use super::position::{absolute, counts, sense, Reading};

/// The `state` param values.
pub mod states {
    /// Waiting for `enable` or a jog.
    pub const IDLE: i32 = 0;
    /// Choosing the direction (passed through in the same call).
    pub const CHOOSE: i32 = 1;
    /// Moving toward the pocket.
    pub const MOVING: i32 = 2;
    /// Timed reverse pulse that locks a ratchet changer.
    pub const REV_PULSE: i32 = 3;
    /// Waiting `decel-time` for the carousel to stop before aligning.
    pub const DECEL: i32 = 5;
    /// Backing onto the alignment sensor.
    pub const BACK_ON: i32 = 6;
    /// Backing off the alignment sensor again.
    pub const BACK_OFF: i32 = 7;
    /// Creeping forward onto the sensor's edge.
    pub const CREEP: i32 = 8;
    /// In position; waiting for `enable` to drop.
    pub const DONE: i32 = 9;
    /// Homing starts.
    pub const HOME_START: i32 = 10;
    /// Homing: waiting for the index.
    pub const HOME_WAIT: i32 = 11;
    /// Jogging one pocket.
    pub const JOG: i32 = 20;
}
use states::*;

/// Every pin and param value one call reads or writes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CarouselVars {
    /// Pin `pocket-number`.
    pub pocket_number: i32,
    /// Pin `enable`.
    pub enable: bool,
    /// Pin `active`.
    pub active: bool,
    /// Pin `ready`.
    pub ready: bool,
    /// Pin `strobe`: the position sensors are valid.
    pub strobe: bool,
    /// Pin `parity`: the encoder's parity bit.
    pub parity: bool,
    /// Pins `sense-N`.
    pub sense: Vec<bool>,
    /// Pin `rev-pulse` (s).
    pub rev_pulse: f64,
    /// Pin `fwd-dc`.
    pub fwd_dc: f64,
    /// Pin `rev-dc`.
    pub rev_dc: f64,
    /// Pin `hold-dc`.
    pub hold_dc: f64,
    /// Pin `align-dc`.
    pub align_dc: f64,
    /// Pin `decel-time` (s).
    pub decel_time: f64,
    /// Pin `counts`.
    pub counts: i32,
    /// Pin `scale`: counts per pocket.
    pub scale: i32,
    /// Pin `width`: counts around a pocket centre that show the pocket.
    pub width: i32,
    /// Pin `home-offset`: counts from the index to pocket 1.
    pub home_offset: i32,
    /// Pin `index-enable` (I/O).
    pub index_enable: bool,
    /// Pin `jog-fwd`.
    pub jog_fwd: bool,
    /// Pin `jog-rev`.
    pub jog_rev: bool,
    /// Pin `motor-fwd`.
    pub motor_fwd: bool,
    /// Pin `motor-rev`.
    pub motor_rev: bool,
    /// Pin `parity-error`.
    pub parity_error: bool,
    /// Pin `current-position`.
    pub current_position: i32,
    /// Pin `motor-vel`.
    pub motor_vel: f64,
    /// Pin `homed`.
    pub homed: bool,
    /// Pin `unhome`.
    pub unhome: bool,
    /// Param `state`.
    pub state: i32,
    /// Param `homing`.
    pub homing: bool,
    /// Param `timer`.
    pub timer: f64,
    /// Param `motor-dir`: 1 forward, -1 reverse, 0 idle.
    pub motor_dir: i32,
}

/// Per-instance state besides the pins.
#[derive(Debug, Clone, Default)]
pub struct Carousel {
    old_index: bool,
    base_counts: i32,
    target: i32,
    old_unhome: bool,
}

impl Carousel {
    /// The position reading for this call.
    fn read(&mut self, c: &Config, v: &CarouselVars) -> Reading {
        let s = |i| sense(&v.sense, i);
        let step = |pos: i32| {
            let mut p = pos;
            if v.motor_fwd {
                p += 1;
                if p > c.pockets {
                    p -= c.pockets;
                }
            }
            if v.motor_rev {
                p -= 1;
                if p < 1 {
                    p += c.pockets;
                }
            }
            p
        };
        match c.encoding {
            Encoding::Index => {
                let mut position = v.current_position;
                if v.homed && (v.state == MOVING || v.state == JOG) {
                    if !self.old_index && s(1) {
                        position = step(position);
                    }
                    self.old_index = s(1);
                }
                Reading {
                    position,
                    parity: false,
                    align: s(1),
                }
            }
            Encoding::Edge => {
                let mut position = v.current_position;
                if v.homed {
                    if self.old_index != s(1) {
                        position = step(position);
                    }
                    self.old_index = s(1);
                }
                // Alignment is not supported: the signal is always on.
                Reading {
                    position,
                    parity: false,
                    align: true,
                }
            }
            Encoding::Counts => {
                if v.homed {
                    let n = v.counts.wrapping_sub(self.base_counts);
                    counts(c.pockets, n, v.scale, v.width, v.current_position)
                } else {
                    Reading {
                        position: v.current_position,
                        ..Reading::default()
                    }
                }
            }
            _ => absolute(c, &v.sense, v.strobe, v.current_position),
        }
    }

    /// Drives the motor toward `dir` (1 forward, -1 reverse).
    fn run(v: &mut CarouselVars, dir: i32) {
        v.motor_fwd = dir > 0;
        v.motor_rev = dir < 0;
        v.motor_vel = if dir > 0 { v.fwd_dc } else { v.rev_dc };
        v.motor_dir = dir;
    }

    /// Stops the motor in position.
    fn arrive(v: &mut CarouselVars) {
        v.motor_fwd = false;
        v.motor_rev = false;
        v.motor_vel = v.hold_dc;
        v.active = false;
        if v.enable {
            v.ready = true;
        }
    }

    /// One call of a thread whose period is `fperiod` seconds.
    pub fn step(&mut self, c: &Config, v: &mut CarouselVars, fperiod: f64) {
        let r = self.read(c, v);
        if v.strobe {
            v.current_position = r.position;
            v.parity_error = r.parity != ((c.parity != 0) ^ v.parity);
        }
        let mod_pocket = ((v.pocket_number.wrapping_sub(1) % c.pockets) + 1).clamp(1, c.pockets);
        if v.unhome && !self.old_unhome {
            v.homed = false;
        }
        self.old_unhome = v.unhome;
        let align = r.align;

        // Each state either ends this call (None) or names the state to
        // fall into within it.
        let mut state = v.state;
        while let Some(next) = match state {
            IDLE => self.idle(c, v),
            CHOOSE => Some(Self::choose(c, v, mod_pocket)),
            MOVING => {
                Self::moving(v, mod_pocket);
                None
            }
            REV_PULSE | DECEL | BACK_ON | BACK_OFF | CREEP | DONE => {
                Self::settle(state, v, fperiod, align);
                None
            }
            HOME_START => Some(Self::home_start(v)),
            HOME_WAIT => {
                self.home_wait(c, v);
                None
            }
            JOG => {
                self.jog(v, align);
                None
            }
            _ => None,
        } {
            state = next;
        }
    }

    /// Waiting: starts a jog, homing or a move to the requested pocket.
    fn idle(&mut self, c: &Config, v: &mut CarouselVars) -> Option<i32> {
        v.motor_dir = 0;
        if v.jog_fwd || (v.jog_rev && c.bidirectional) {
            if c.encoding.needs_homing() && !v.homed {
                v.state = HOME_START;
                return None;
            }
            self.target = v.current_position + v.jog_fwd as i32 - v.jog_rev as i32;
            if self.target > c.pockets {
                self.target = 1;
            }
            if self.target < 1 {
                self.target = c.pockets;
            }
            if v.jog_fwd {
                Self::run(v, 1);
            }
            if v.jog_rev {
                Self::run(v, -1);
            }
            v.active = true;
            v.state = JOG;
            return None;
        }
        v.motor_vel = v.hold_dc;
        if !v.enable {
            return None;
        }
        v.active = true;
        if c.encoding.needs_homing() && !v.homed {
            v.state = HOME_START;
            return None;
        }
        v.state = CHOOSE;
        v.ready = false;
        Some(CHOOSE)
    }

    /// Chooses the shorter way round (forward only unless bidirectional).
    fn choose(c: &Config, v: &mut CarouselVars, mod_pocket: i32) -> i32 {
        let (cur, half) = (v.current_position, c.pockets / 2);
        let dir = if !c.bidirectional {
            1
        } else if cur < mod_pocket {
            if mod_pocket - cur > half {
                -1
            } else {
                1
            }
        } else if cur - mod_pocket > half {
            1
        } else {
            -1
        };
        Self::run(v, dir);
        v.state = MOVING;
        MOVING
    }

    /// Moving: at the pocket (or disabled), pulses back, decelerates to
    /// align, or stops.
    fn moving(v: &mut CarouselVars, mod_pocket: i32) {
        if v.current_position != mod_pocket && v.enable {
            return;
        }
        if v.rev_pulse > 0.0 {
            v.motor_fwd = false;
            v.motor_rev = true;
            v.motor_vel = v.rev_dc;
            v.timer = v.rev_pulse;
            v.state = REV_PULSE;
        } else if v.align_dc != 0.0 {
            v.motor_vel = 0.0;
            v.timer = v.decel_time;
            v.state = DECEL;
        } else {
            Self::arrive(v);
            v.state = DONE;
        }
    }

    /// The states after the pocket is reached: the reverse pulse, the
    /// deceleration and alignment creep, and done.
    fn settle(state: i32, v: &mut CarouselVars, fperiod: f64, align: bool) {
        match state {
            REV_PULSE => {
                v.timer -= fperiod;
                if v.timer > 0.0 {
                    return;
                }
                v.state = DONE;
                Self::arrive(v);
            }
            DECEL => {
                v.timer -= fperiod;
                if v.timer > 0.0 {
                    return;
                }
                v.motor_vel = -v.align_dc;
                v.state = if v.motor_dir == 1 { BACK_ON } else { BACK_OFF };
            }
            BACK_ON => {
                if align {
                    v.state = BACK_OFF;
                }
            }
            BACK_OFF => {
                if !align {
                    v.motor_vel = v.align_dc;
                    v.state = CREEP;
                }
            }
            CREEP => {
                if align {
                    Self::arrive(v);
                    v.state = DONE;
                }
            }
            _ => {
                if !v.enable {
                    v.state = IDLE;
                }
            }
        }
    }

    /// Starts homing: forward, index armed.
    fn home_start(v: &mut CarouselVars) -> i32 {
        v.homed = false;
        v.homing = true;
        Self::run(v, 1);
        v.index_enable = true;
        v.state = HOME_WAIT;
        HOME_WAIT
    }

    /// Homing: waits for the index (and pocket sensor) edge.
    fn home_wait(&mut self, c: &Config, v: &mut CarouselVars) {
        let s = |i| sense(&v.sense, i);
        let index = if c.encoding == Encoding::Counts {
            s(0)
        } else {
            s(0) && s(1)
        };
        if !v.index_enable || (!self.old_index && index) {
            v.current_position = 1;
            v.homed = true;
            v.homing = false;
            v.active = false;
            v.motor_fwd = false;
            v.motor_rev = false;
            v.motor_vel = 0.0;
            self.base_counts = v.counts.wrapping_sub(v.home_offset);
            if v.align_dc == 0.0 {
                v.state = IDLE;
            } else {
                v.timer = v.decel_time;
                v.state = DECEL;
            }
        }
        // Index and pocket sensor together, in every mode.
        self.old_index = s(0) && s(1);
    }

    /// Jogging: stops at the target pocket (aligned), then waits for the
    /// button's release.
    fn jog(&self, v: &mut CarouselVars, align: bool) {
        if v.current_position != self.target || (v.align_dc != 0.0 && !align) {
            return;
        }
        v.motor_fwd = false;
        v.motor_rev = false;
        v.motor_vel = v.hold_dc;
        v.active = false;
        if v.jog_fwd || v.jog_rev {
            return; // the button must be released first
        }
        if v.align_dc != 0.0 {
            v.motor_vel = -v.align_dc;
            v.timer = v.decel_time;
            v.state = DECEL;
        } else {
            v.state = IDLE;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg(encoding: Encoding, pockets: i32, sense: usize) -> Config {
        Config {
            pockets,
            encoding,
            bidirectional: true,
            sense,
            parity: 0,
        }
    }

    fn vars(sense: usize) -> CarouselVars {
        CarouselVars {
            strobe: true,
            sense: vec![false; sense],
            scale: 100,
            fwd_dc: 1.0,
            rev_dc: -1.0,
            hold_dc: 0.1,
            ..Default::default()
        }
    }

    /// Sets binary sense bits to `pos`.
    fn at(v: &mut CarouselVars, pos: u32) {
        for (i, b) in v.sense.iter_mut().enumerate() {
            *b = pos & (1 << i) != 0;
        }
    }

    #[test]
    fn binary_carousel_takes_the_short_way_and_arrives() {
        let c = Config {
            encoding: Encoding::Binary,
            ..cfg(Encoding::Binary, 8, 4)
        };
        let (mut m, mut v) = (Carousel::default(), vars(4));
        at(&mut v, 2);
        m.step(&c, &mut v, 0.001);
        assert_eq!((v.current_position, v.state, v.motor_vel), (2, IDLE, 0.1));
        // Pocket 8 from 2: six forward or two back; back is shorter.
        v.pocket_number = 8;
        v.enable = true;
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, MOVING);
        assert!(v.active && !v.ready && v.motor_rev && !v.motor_fwd);
        assert_eq!((v.motor_vel, v.motor_dir), (-1.0, -1));
        at(&mut v, 1);
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, MOVING);
        at(&mut v, 8);
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, DONE);
        assert!(v.ready && !v.active && !v.motor_rev);
        assert_eq!(v.motor_vel, 0.1, "holding");
        v.enable = false;
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, IDLE);
        assert!(v.ready, "ready stays until the next move starts");
    }

    #[test]
    fn pocket_numbers_wrap_modulo_the_pockets() {
        let c = cfg(Encoding::Binary, 8, 4);
        let (mut m, mut v) = (Carousel::default(), vars(4));
        at(&mut v, 3);
        v.pocket_number = 11; // pocket 3
        v.enable = true;
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, DONE, "already there");
    }

    #[test]
    fn reverse_pulse_locks_then_finishes() {
        let c = cfg(Encoding::Binary, 8, 4);
        let (mut m, mut v) = (Carousel::default(), vars(4));
        at(&mut v, 4);
        v.pocket_number = 4;
        v.enable = true;
        v.rev_pulse = 0.0025;
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, REV_PULSE);
        assert!(v.motor_rev && v.motor_vel == -1.0);
        m.step(&c, &mut v, 0.001);
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, REV_PULSE);
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, DONE);
        assert!(!v.motor_rev && v.ready);
    }

    #[test]
    fn unidirectional_always_goes_forward() {
        let c = Config {
            bidirectional: false,
            ..cfg(Encoding::Gray, 8, 4)
        };
        let (mut m, mut v) = (Carousel::default(), vars(4));
        v.pocket_number = 8;
        v.enable = true;
        m.step(&c, &mut v, 0.001);
        assert!(v.motor_fwd && v.motor_dir == 1);
    }

    #[test]
    fn index_mode_homes_then_counts_pockets() {
        let c = cfg(Encoding::Index, 6, 2);
        let (mut m, mut v) = (Carousel::default(), vars(2));
        v.enable = true;
        v.pocket_number = 3;
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, HOME_START);
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, HOME_WAIT);
        assert!(v.homing && v.motor_fwd && v.index_enable);
        v.sense = vec![true, true]; // index and pocket sensor
        m.step(&c, &mut v, 0.001);
        assert!(v.homed && !v.homing);
        assert_eq!((v.current_position, v.state), (1, IDLE));
        // Still enabled: the move to pocket 3 starts, forward.
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, MOVING);
        assert!(v.motor_fwd);
        // Two rising edges of the pocket sensor later: pocket 3.
        for _ in 0..2 {
            v.sense = vec![false, false];
            m.step(&c, &mut v, 0.001);
            v.sense = vec![false, true];
            m.step(&c, &mut v, 0.001);
        }
        assert_eq!((v.current_position, v.state), (3, DONE));
        // unhome forgets the home.
        v.unhome = true;
        m.step(&c, &mut v, 0.001);
        assert!(!v.homed);
    }

    #[test]
    fn jog_moves_one_pocket_and_waits_for_release() {
        let c = cfg(Encoding::Binary, 8, 4);
        let (mut m, mut v) = (Carousel::default(), vars(4));
        at(&mut v, 8);
        v.jog_fwd = true;
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, JOG);
        assert!(v.motor_fwd && v.active);
        at(&mut v, 1); // 8 + 1 wraps to 1
        m.step(&c, &mut v, 0.001);
        assert!(!v.motor_fwd && !v.active);
        assert_eq!(v.state, JOG, "button still held");
        v.jog_fwd = false;
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, IDLE);
    }

    #[test]
    fn alignment_backs_on_off_and_creeps_onto_the_edge() {
        let c = cfg(Encoding::Binary, 8, 4);
        let (mut m, mut v) = (Carousel::default(), vars(4));
        at(&mut v, 1);
        v.pocket_number = 2;
        v.enable = true;
        v.align_dc = 0.2;
        v.decel_time = 0.001;
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.motor_dir, 1);
        at(&mut v, 2);
        m.step(&c, &mut v, 0.001);
        assert_eq!((v.state, v.motor_vel), (DECEL, 0.0));
        m.step(&c, &mut v, 0.001);
        assert_eq!((v.state, v.motor_vel), (BACK_ON, -0.2));
        // Binary mode aligns on the strobe: on, off, on again.
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, BACK_OFF);
        v.strobe = false;
        m.step(&c, &mut v, 0.001);
        assert_eq!((v.state, v.motor_vel), (CREEP, 0.2));
        v.strobe = true;
        m.step(&c, &mut v, 0.001);
        assert_eq!(v.state, DONE);
        assert!(v.ready);
    }

    #[test]
    fn parity_error_compares_with_the_parity_bit() {
        let c = Config {
            parity: 1,
            ..cfg(Encoding::Binary, 8, 4)
        };
        let (mut m, mut v) = (Carousel::default(), vars(4));
        at(&mut v, 3); // two bits set: even
        m.step(&c, &mut v, 0.001);
        assert!(v.parity_error, "odd parity expected, no parity bit");
        v.parity = true;
        m.step(&c, &mut v, 0.001);
        assert!(!v.parity_error);
    }

    #[test]
    fn counts_mode_homes_on_the_index_enable_handshake() {
        let c = cfg(Encoding::Counts, 4, 1);
        let (mut m, mut v) = (Carousel::default(), vars(1));
        v.enable = true;
        v.pocket_number = 2;
        v.counts = 1234;
        v.home_offset = 34;
        m.step(&c, &mut v, 0.001);
        m.step(&c, &mut v, 0.001);
        assert!(v.index_enable);
        v.index_enable = false; // the encoder reset at its index
        m.step(&c, &mut v, 0.001);
        assert!(v.homed);
        // base = 1234 - 34: 1300 counts is 100 past home, pocket 2.
        v.counts = 1300;
        m.step(&c, &mut v, 0.001);
        m.step(&c, &mut v, 0.001);
        assert_eq!((v.current_position, v.state), (2, DONE));
    }
}
