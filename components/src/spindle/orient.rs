//! `orient`: the position command of a spindle orientation (M19) loop.
//! On a rising edge of `enable` it samples the spindle `position` (in
//! revolutions) and commands the nearest position, in the direction
//! `mode` asks for, whose fraction of a turn is `angle`/360; modes 3 to 5
//! first let the encoder find its index. `is-oriented` goes TRUE once the
//! error stayed within `tolerance` degrees for more than 100 calls.
//!
//! `mode`: 0 shortest way, 1 clockwise (up), 2 counter-clockwise (down);
//! 3, 4, 5 the same after homing to the index.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;
use crate::notice::Notice;
use crate::timing::write_changed;

/// Calls the error must stay within tolerance before `is-oriented`.
pub const SETTLE_CALLS: i32 = 100;

/// The texts orient writes to stderr.
pub static TEXTS: &[&str] = &["orient: unhandled mode (not 0 to 5)\n"];

/// The pin values one call reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OrientVars {
    /// Pin `enable`.
    pub enable: bool,
    /// Pin `mode`.
    pub mode: i32,
    /// Pin `position` (revolutions).
    pub position: f64,
    /// Pin `angle` (degrees).
    pub angle: f64,
    /// Pin `tolerance` (degrees).
    pub tolerance: f64,
    /// Pin `command` (read back: kept while not orienting).
    pub command: f64,
    /// Pin `poserr` (degrees).
    pub poserr: f64,
    /// Pin `is-oriented`.
    pub is_oriented: bool,
    /// Pin `index-enable` (I/O).
    pub index_enable: bool,
    /// Param `state`.
    pub state: u32,
}

/// Per-instance state.
#[derive(Debug, Clone, Default)]
pub struct Orient {
    last_enable: bool,
    debounce: i32,
    target_angle: f64,
    latched_position: f64,
}

impl Orient {
    /// One call. Returns TRUE when `mode` was not one the current state
    /// handles (LinuxCNC prints a message then).
    pub fn step(&mut self, v: &mut OrientVars) -> bool {
        let mut bad_mode = false;
        v.is_oriented = false;
        match v.state {
            0 if v.enable => {
                v.index_enable = false;
                if !self.last_enable {
                    v.state = if v.mode > 2 {
                        v.index_enable = true;
                        3
                    } else {
                        1
                    };
                }
            }
            1 => {
                if !v.enable {
                    v.state = 0;
                }
                self.debounce = 0;
                self.latched_position = v.position;
                self.target_angle = v.angle / 360.0;
                v.state = 2;
            }
            2 => {
                if !v.enable {
                    v.state = 0;
                }
                let (p, t) = (self.latched_position, self.target_angle);
                match v.mode % 3 {
                    0 => v.command = (p + 0.5 - t).floor() + t,
                    1 => v.command = (p - t).ceil() + t,
                    2 => v.command = (p - t).floor() + t,
                    _ => bad_mode = true,
                }
                v.poserr = (v.position - v.command) * 360.0;
                if v.poserr.abs() < v.tolerance && self.debounce <= SETTLE_CALLS {
                    self.debounce += 1;
                }
                v.is_oriented = self.debounce > SETTLE_CALLS;
                if v.is_oriented {
                    v.state = 0;
                }
            }
            3 => {
                if !v.enable {
                    v.state = 0;
                }
                self.latched_position = v.position;
                v.state = 4;
            }
            4 => {
                if !v.enable {
                    v.state = 0;
                }
                if !v.index_enable {
                    v.state = 1;
                } else {
                    match v.mode {
                        3 if 0.0 > self.latched_position => v.command = v.position + 0.5,
                        3 => v.command = v.position - 0.5,
                        4 => v.command = v.position + 0.5,
                        5 => v.command = v.position - 0.5,
                        _ => bad_mode = true,
                    }
                }
            }
            _ => {}
        }
        self.last_enable = v.enable;
        bad_mode
    }
}

/// The `orient` component.
pub struct OrientComp;
impl HalComp for OrientComp {
    const NAME: &'static str = "orient";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let enable = inst.pin_in::<bool>("enable")?;
        let mode = inst.pin_in::<i32>("mode")?;
        let position = inst.pin_in::<f64>("position")?;
        let angle = inst.pin_in::<f64>("angle")?;
        let command = inst.pin_out::<f64>("command")?;
        let poserr = inst.pin_out::<f64>("poserr")?;
        let is_oriented = inst.pin_out::<bool>("is-oriented")?;
        let tolerance = inst.pin_in_init::<f64>("tolerance", 0.5)?;
        let index_enable = inst.pin_io::<bool>("index-enable", false)?;
        let state_param = inst.param_ro::<u32>("state", 0)?;
        let notice = Notice::new(TEXTS);
        let mut state = Orient::default();
        inst.funct("_", true, move |_| {
            let old = OrientVars {
                enable: enable.get(),
                mode: mode.get(),
                position: position.get(),
                angle: angle.get(),
                tolerance: tolerance.get(),
                command: command.get(),
                poserr: poserr.get(),
                is_oriented: is_oriented.get(),
                index_enable: index_enable.get(),
                state: state_param.get(),
            };
            let mut v = old;
            if state.step(&mut v) {
                notice.post(0);
            }
            write_changed(&is_oriented, old.is_oriented, v.is_oriented);
            write_changed(&index_enable, old.index_enable, v.index_enable);
            write_changed(&command, old.command, v.command);
            write_changed(&poserr, old.poserr, v.poserr);
            state_param.set(v.state);
        })
    }
}
halcomp_module!(pub MODULE, OrientComp, "PID command for spindle orientation");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float, S32, U32};

    /// Runs calls until the state machine has computed a command.
    fn orient(mode: i32, position: f64, angle: f64) -> f64 {
        let mut o = Orient::default();
        let mut v = OrientVars {
            enable: true,
            mode,
            position,
            angle,
            tolerance: 0.5,
            ..Default::default()
        };
        for _ in 0..3 {
            assert!(!o.step(&mut v));
        }
        assert_eq!(v.state, 2);
        v.command
    }

    #[test]
    fn command_per_mode() {
        // 2.3 rev, target 90 degrees (0.25): shortest is 2.25.
        assert_eq!(orient(0, 2.3, 90.0), 2.25);
        // Clockwise (up) to the next 0.25: 3.25; counter-clockwise: 2.25.
        assert_eq!(orient(1, 2.3, 90.0), 3.25);
        assert_eq!(orient(2, 2.3, 90.0), 2.25);
        // Shortest way may go up.
        assert_eq!(orient(0, 2.7, 0.0), 3.0);
        assert_eq!(orient(0, -0.2, 0.0), 0.0);
    }

    #[test]
    fn oriented_after_settling_and_drops_back_to_waiting() {
        let mut o = Orient::default();
        let mut v = OrientVars {
            enable: true,
            position: 0.25,
            angle: 90.0,
            tolerance: 0.5,
            ..Default::default()
        };
        o.step(&mut v); // edge: state 1
        o.step(&mut v); // latch: state 2
        let mut calls = 0;
        while !v.is_oriented {
            o.step(&mut v);
            calls += 1;
            assert!(calls < 200);
        }
        assert_eq!(calls, SETTLE_CALLS + 1);
        assert_eq!((v.state, v.poserr), (0, 0.0));
        // Still enabled: no new edge, stays waiting and not oriented.
        o.step(&mut v);
        assert!(!v.is_oriented && v.state == 0);
    }

    #[test]
    fn index_modes_wait_for_the_index_then_orient() {
        let mut o = Orient::default();
        let mut v = OrientVars {
            enable: true,
            mode: 4,
            position: 1.2,
            angle: 0.0,
            tolerance: 0.5,
            ..Default::default()
        };
        o.step(&mut v);
        assert!(v.index_enable && v.state == 3);
        o.step(&mut v);
        o.step(&mut v);
        assert_eq!((v.state, v.command), (4, 1.7), "creeps up while searching");
        v.index_enable = false; // the encoder found the index
        o.step(&mut v);
        assert_eq!(v.state, 1);
        o.step(&mut v);
        o.step(&mut v);
        assert_eq!(v.command, 2.0, "mode 4 orients clockwise");
    }

    #[test]
    fn negative_mode_is_reported() {
        let mut o = Orient::default();
        let mut v = OrientVars {
            enable: true,
            mode: -1,
            ..Default::default()
        };
        o.step(&mut v);
        o.step(&mut v);
        assert!(o.step(&mut v), "-1 % 3 is -1: no such mode");
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("orient");
        h.load(&MODULE, &["names=orient"]).unwrap();
        h.check_pins(
            "orient",
            &[
                "enable bit in 0",
                "mode s32 in 0",
                "position float in 0",
                "angle float in 0",
                "command float out 0",
                "poserr float out 0",
                "is-oriented bit out 0",
                "tolerance float in 0.5",
                "index-enable bit io 0",
            ],
        );
        h.check_params("orient", &["state u32 ro 0"]);
        h.thread(&["orient"]);
        h.set("orient.position", Float(0.9));
        h.set("orient.angle", Float(180.0));
        h.set("orient.mode", S32(0));
        h.set("orient.enable", Bit(true));
        // Edge, latch, then the command.
        h.run(3);
        assert_eq!(h.get("orient.command"), Float(0.5));
        assert_eq!(h.getp("orient.state"), U32(2));
    }
}
