//! What the unit tests of several modules share.

use crate::command::{Command, CommandResult};
use crate::core::MotionCore;
use crate::events::Event;
use crate::joint::JointStatus;

/// The servo period of the simulated machines.
pub(crate) const T: f64 = 0.001;

/// Activates every joint of `m` with the test machines' settings: soft
/// limits ±100, 10 u/s, 100 u/s², following error 0.01 at rest and 1 at
/// full speed.
pub(crate) fn configure_test_joints(m: &mut MotionCore) {
    for j in 0..m.num_joints() as i32 {
        for c in [
            Command::JointActivate { joint: j },
            Command::SetJointPositionLimits {
                joint: j,
                min: -100.0,
                max: 100.0,
            },
            Command::SetJointVelLimit {
                joint: j,
                vel: 10.0,
            },
            Command::SetJointAccLimit {
                joint: j,
                acc: 100.0,
            },
            Command::SetJointMinFerror {
                joint: j,
                ferror: 0.01,
            },
            Command::SetJointMaxFerror {
                joint: j,
                ferror: 1.0,
            },
        ] {
            m.command(&c).unwrap();
        }
    }
}

/// Limits every world axis to ±`limit`, 10 u/s and 100 u/s².
pub(crate) fn configure_test_axes(m: &mut MotionCore, limit: f64) {
    for a in 0..crate::kins::NUM_AXES as i32 {
        for c in [
            Command::SetAxisPositionLimits {
                axis: a,
                min: -limit,
                max: limit,
            },
            Command::SetAxisVelLimit { axis: a, vel: 10.0 },
            Command::SetAxisAccLimit {
                axis: a,
                acc: 100.0,
            },
        ] {
            m.command(&c).unwrap();
        }
    }
}

/// The core and its simulated motors.
pub(crate) struct Sim {
    pub m: MotionCore,
    /// Periods between a motor command and the feedback showing it.
    pub lag: usize,
    history: Vec<Vec<f64>>,
    /// A motor that does not move: its feedback stays here.
    pub stuck: Vec<Option<f64>>,
}

impl Sim {
    /// `m` with every motor following its command one period later.
    pub fn new(m: MotionCore) -> Sim {
        let n = m.num_joints();
        Sim {
            m,
            lag: 1,
            history: vec![Vec::new(); n],
            stuck: vec![None; n],
        }
    }

    /// One servo period: the motors report, then the controller runs.
    pub fn cycle(&mut self) {
        for j in 0..self.m.num_joints() {
            let h = &mut self.history[j];
            h.push(self.m.joint(j).motor_pos_cmd);
            let fb = if h.len() >= self.lag {
                h[h.len() - self.lag]
            } else {
                h[0]
            };
            if h.len() > 64 {
                h.remove(0);
            }
            self.m.joint_inputs[j].motor_pos_fb = self.stuck[j].unwrap_or(fb);
        }
        self.m.cycle(T);
    }

    pub fn run(&mut self, n: usize) {
        for _ in 0..n {
            self.cycle();
        }
    }

    /// Runs until no joint moves (at most `limit` periods); returns how many.
    pub fn settle(&mut self, limit: usize) -> usize {
        for n in 0..limit {
            self.cycle();
            if self.m.in_position() {
                return n + 1;
            }
        }
        panic!("still moving after {limit} periods");
    }

    pub fn cmd(&mut self, c: Command) -> CommandResult {
        self.m.command(&c)
    }

    pub fn enable(&mut self) {
        self.cmd(Command::Enable).unwrap();
        self.cycle();
        assert!(self.m.is_enabled());
    }

    pub fn j(&self, j: usize) -> JointStatus {
        self.m.joint(j)
    }

    pub fn events(&self) -> Vec<Event> {
        self.m.events().drain()
    }
}
