//! Machines at a simulated board's connectors, made of the shared plant
//! models ([`hal_driver::plant`]): DC servo motors driven by PWM
//! generators and read back by quadrature encoders, stepper axes driven
//! by step generators, and switches on GPIO inputs.
//!
//! A switch is wired between its input and ground: closed contacts read
//! low (`gpio.NNN.in` FALSE, `in_not` TRUE), open contacts read high
//! through the board's pull-up.

use hal_driver::plant::{DcMotor, DcMotorParams, QuadEncoder, StepperAxis, Switch};

use super::world::{EncoderIn, Inputs, Outputs, World};

/// A servo: motor `k` driven by PWM generator `pwm`, its encoder read by
/// encoder instance `encoder`. Motor positions are in revolutions.
#[derive(Debug, Clone)]
pub struct Servo {
    /// The PWM generator driving the motor.
    pub pwm: usize,
    /// The encoder instance reading the shaft.
    pub encoder: usize,
    /// The motor.
    pub motor: DcMotor,
    /// The encoder on its shaft.
    pub shaft: QuadEncoder,
    /// Supply voltage of the amplifier.
    pub supply: f64,
    /// The motor leads are swapped: a positive duty turns the shaft
    /// backwards (its encoder counts down).
    pub reversed: bool,
}

/// A stepper axis driven by step generator `stepgen`.
#[derive(Debug, Clone)]
pub struct Stepper {
    /// The step generator.
    pub stepgen: usize,
    /// The axis.
    pub axis: StepperAxis,
}

/// What a switch is mounted on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mount {
    /// Servo `k` (position in motor revolutions).
    Servo(usize),
    /// Stepper `k` (position in its units).
    Stepper(usize),
}

/// A switch on an axis, wired to I/O pin `io`.
#[derive(Debug, Clone, Copy)]
pub struct InputSwitch {
    /// The I/O pin.
    pub io: usize,
    /// The axis.
    pub on: Mount,
    /// The switch.
    pub switch: Switch,
}

/// A machine: servos, steppers, switches. Encoders without a motor keep
/// the count a test gives them in [`Machine::encoders`].
#[derive(Debug, Clone, Default)]
pub struct Machine {
    /// The servos.
    pub servos: Vec<Servo>,
    /// The stepper axes.
    pub steppers: Vec<Stepper>,
    /// The switches.
    pub switches: Vec<InputSwitch>,
    /// Encoders no servo turns (tests set them).
    pub encoders: Vec<EncoderIn>,
    /// Pins driven from outside by tests (`None`: floating).
    pub pins: Vec<Option<bool>>,
}

/// The motor of the simulated servo machines: 1 rev/s per volt, 20 ms
/// mechanical time constant, 0.2 V of friction.
pub const SERVO_MOTOR: DcMotorParams = DcMotorParams {
    speed_per_volt: 1.0,
    time_constant: 0.02,
    friction: 0.2,
};

impl Machine {
    /// Where axis `m` is.
    pub fn position(&self, m: Mount) -> Option<f64> {
        match m {
            Mount::Servo(k) => self.servos.get(k).map(|s| s.motor.position()),
            Mount::Stepper(k) => self.steppers.get(k).map(|s| s.axis.position()),
        }
    }
}

/// How long before the end of a step of `dt_ns` the shaft crossed into
/// its present count, moving at `velocity` counts/s to `counts`.
fn last_edge_ago(counts: f64, velocity: f64, dt_ns: u64) -> u64 {
    if velocity == 0.0 {
        return dt_ns;
    }
    let past = if velocity > 0.0 {
        counts - counts.floor()
    } else {
        counts.ceil() - counts
    };
    ((past / velocity.abs()) * 1e9).min(dt_ns as f64) as u64
}

impl World for Machine {
    fn advance(&mut self, dt_ns: u64, out: &Outputs, sense: &mut Inputs) {
        for s in &mut self.steppers {
            let n = out.steps.get(s.stepgen).map_or(0, |o| o.steps);
            for _ in 0..n.unsigned_abs() {
                s.axis.step(n > 0);
            }
        }
        for (i, e) in sense.encoders.iter_mut().enumerate() {
            if let Some(mine) = self.encoders.get_mut(i) {
                *e = *mine;
                mine.index_at = None;
                mine.glitch = false;
            }
        }
        for s in &mut self.servos {
            let drive = out.pwm.get(s.pwm).copied().unwrap_or_default();
            if drive.enabled {
                let duty = if s.reversed { -drive.duty } else { drive.duty };
                s.motor.set_duty(duty, s.supply);
            } else {
                s.motor.set_volts(0.0);
            }
            s.motor.advance(dt_ns);
            let cpr = s.shaft.counts_per_rev() as f64;
            let counts = s.motor.position() * cpr;
            let moved = s.shaft.set_revs(s.motor.position());
            if let Some(e) = sense.encoders.get_mut(s.encoder) {
                *e = EncoderIn {
                    count: s.shaft.count(),
                    last_edge_ago_ns: last_edge_ago(counts, s.motor.velocity() * cpr, dt_ns),
                    index_at: moved.first_index,
                    glitch: false,
                    a: s.shaft.a(),
                    b: s.shaft.b(),
                    z: s.shaft.z(),
                };
            }
        }
        for (i, p) in sense.pins.iter_mut().enumerate() {
            *p = self.pins.get(i).copied().flatten();
        }
        for sw in &self.switches {
            if let (Some(pos), Some(p)) = (self.position(sw.on), sense.pins.get_mut(sw.io)) {
                if sw.switch.is_closed(pos) {
                    *p = Some(false);
                }
            }
        }
    }

    fn as_any(&mut self) -> &mut dyn std::any::Any {
        self
    }
}

/// The machine `hm2_pci sim=<board>` connects, by board name:
///
/// * `5i25`: a stepper axis of 100 steps per unit on each of the ten step
///   generators; home switches closing at +10 units for axes 0, 1 and 2
///   on I/O 13, 14 and 15 (P3 DB-25 pins 11, 12, 13).
/// * `6i25`: four servos, PWM generator k driving motor k ([`SERVO_MOTOR`]
///   on a 24 V supply) with encoder k on its shaft (4000 counts, index
///   once per revolution); home switches closing at +2.25 revolutions for
///   servos 0, 1 and 2 on I/O 12, 13 and 14 (P3 DB-25 pins 7, 8, 9).
/// * `5i24`: eight servos as above on PWM/encoder 0..7 and eight stepper
///   axes on step generators 0..7, no switches.
/// * `7i96s`: the `5i25` machine on the 7i96S's five step generators,
///   its home switches on I/O 34, 35, 36 (the first inputs of TB2), and
///   three servos on PWM generators and encoders 0..2 with their motor
///   leads swapped (as [`servo_stepper`]).
/// * `7i93`: [`servo_stepper`] with 4 servos and 8 stepper axes.
/// * `7i92`: the `5i25` machine (switches on I/O 13, 14, 15).
/// * `7i95`: stepper axes on its 6 step generators, home switches on
///   I/O 29, 30, 31 (the first pins of TB1).
/// * `7i76e`: the same with the switches on I/O 17, 18, 19 (P2).
/// * `5i25-7i77`: stepper axes on the five step generators, no switches.
/// * `7i90`: four servos on PWM generators and encoders 0..3, leads
///   swapped as for the 7i96s; stepper axes with home switches on I/O
///   10..12.
pub fn preset(board: &str) -> Machine {
    let steppers_with_switches = |n: usize, first_switch: usize| Machine {
        steppers: (0..n).map(stepper).collect(),
        switches: (0..3)
            .map(|k| InputSwitch {
                io: first_switch + k,
                on: Mount::Stepper(k),
                switch: Switch::at_or_above(10.0),
            })
            .collect(),
        ..Machine::default()
    };
    match board {
        "5i25" => steppers_with_switches(10, 13),
        // The 7i96s's servos are wired as LinuxCNC's hm2-servo samples
        // expect (leads swapped, see `servo_stepper`).
        "7i96s" => Machine {
            servos: servo_stepper(3, 0).servos,
            ..steppers_with_switches(5, 34)
        },
        "7i93" => servo_stepper(4, 8),
        "7i92" => steppers_with_switches(10, 13),
        "7i95" => steppers_with_switches(6, 29),
        "7i76e" => steppers_with_switches(5, 17),
        "5i25-7i77" => Machine {
            steppers: (0..5).map(stepper).collect(),
            ..Machine::default()
        },
        "6i25" => Machine {
            servos: (0..4).map(servo).collect(),
            switches: (0..3)
                .map(|k| InputSwitch {
                    io: 12 + k,
                    on: Mount::Servo(k),
                    switch: Switch::at_or_above(2.25),
                })
                .collect(),
            ..Machine::default()
        },
        // The EPP boards: servos on their encoders and PWM generators,
        // stepper axes with home switches on the first GPIO after the
        // step pins (7I43: I/O 32..34 on P3; 7I90: I/O 10..12 on P1).
        "7i43" | "7i43-2" => Machine {
            servos: (0..4).map(servo).collect(),
            ..steppers_with_switches(4, 32)
        },
        // The 7I90's servos are wired as LinuxCNC's hm2-servo 7i90
        // sample expects (leads swapped, see `servo_stepper`).
        "7i90" => Machine {
            servos: servo_stepper(4, 0).servos,
            ..steppers_with_switches(5, 10)
        },
        // The SPI hats: steppers with home switches on the first GPIO
        // after the encoder and PWM pins (7C80: I/O 18..20; 7C81: 16..18).
        "7c80" => steppers_with_switches(6, 18),
        "7c81" => steppers_with_switches(5, 16),
        "5i24" => Machine {
            servos: (0..8).map(servo).collect(),
            steppers: (0..8).map(stepper).collect(),
            ..Machine::default()
        },
        _ => Machine::default(),
    }
}

/// Servo k: PWM generator k drives a [`SERVO_MOTOR`] on a 24 V supply
/// with encoder k (4000 counts, index once per revolution) on its shaft.
fn servo(k: usize) -> Servo {
    Servo {
        pwm: k,
        encoder: k,
        motor: DcMotor::new(SERVO_MOTOR),
        shaft: QuadEncoder::new(4000),
        supply: 24.0,
        reversed: false,
    }
}

/// Stepper axis k: step generator k, 100 steps per unit.
fn stepper(k: usize) -> Stepper {
    Stepper {
        stepgen: k,
        axis: StepperAxis::new(100.0),
    }
}

/// The machine of a simulated PLX card (`sim=5i20`, ...) running a
/// servo/stepper firmware: a servo on each of its `servos` channels and
/// a stepper axis on each of its `steppers` step generators, no switches.
/// The servos' motor leads are swapped, as LinuxCNC's hm2-servo sample
/// configurations expect (each joint's OUTPUT_SCALE and INPUT_SCALE of
/// opposite signs), so those close their loops unchanged.
pub fn servo_stepper(servos: usize, steppers: usize) -> Machine {
    let reversed = |k| Servo {
        reversed: true,
        ..servo(k)
    };
    Machine {
        servos: (0..servos).map(reversed).collect(),
        steppers: (0..steppers).map(stepper).collect(),
        ..Machine::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_are_placed_within_the_step() {
        assert_eq!(last_edge_ago(10.25, 1000.0, 1_000_000), 250_000);
        assert_eq!(last_edge_ago(9.75, -1000.0, 1_000_000), 250_000);
        assert_eq!(last_edge_ago(10.0, 0.0, 1_000_000), 1_000_000);
        assert_eq!(
            last_edge_ago(10.9, 100.0, 1_000_000),
            1_000_000,
            "at most the step"
        );
    }
}
