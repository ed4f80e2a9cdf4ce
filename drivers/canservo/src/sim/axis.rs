//! The mechanics behind a simulated drive: a [`DcMotor`] from the shared
//! plant models, closed by the drive's own cascaded loops (position
//! loop with velocity feed-forward around a velocity loop), plus an
//! optional deterministic noise on the position reading. Positions are
//! in encoder counts; the drive's position actual value is the motor
//! position minus a home origin, which homing moves.

use hal_driver::plant::{DcMotor, DcMotorParams};

use crate::units::counts as saturate;

/// What the drive's loops are asked to do over one control step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Demand {
    /// Power stage off: the motor coasts.
    Off,
    /// Follow a position set-point (counts) with a velocity
    /// feed-forward (counts/s).
    Position {
        /// Set-point.
        setpoint: f64,
        /// Feed-forward.
        feed_forward: f64,
    },
    /// Run at a velocity (counts/s).
    Velocity(f64),
}

/// The axis' constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisParams {
    /// The motor, in counts: speed per volt in counts/s/V.
    pub motor: DcMotorParams,
    /// Power-stage supply (V): the drive voltage is clamped to ±supply.
    pub supply: f64,
    /// Position loop gain (1/s): the lag of the position loop.
    pub position_gain: f64,
    /// Velocity loop gain (dimensionless, > 0).
    pub velocity_gain: f64,
    /// Peak noise added to the position reading (counts; 0 = none).
    pub noise_counts: f64,
}

impl Default for AxisParams {
    /// A 48 V servo: 12 500 counts/s per volt (600 000 counts/s flat
    /// out), 5 ms mechanical time constant, a little friction; loops at
    /// 300/s and 8.
    fn default() -> AxisParams {
        AxisParams {
            motor: DcMotorParams {
                speed_per_volt: 12_500.0,
                time_constant: 0.005,
                friction: 0.05,
            },
            supply: 48.0,
            position_gain: 300.0,
            velocity_gain: 8.0,
            noise_counts: 0.0,
        }
    }
}

/// The motor and its loops.
#[derive(Debug, Clone)]
pub struct Axis {
    params: AxisParams,
    motor: DcMotor,
    origin: f64,
    noise: u64,
    last_volts: f64,
}

impl Axis {
    /// An axis at rest at motor position 0.
    pub fn new(params: AxisParams) -> Axis {
        Axis {
            params,
            motor: DcMotor::new(params.motor),
            origin: 0.0,
            noise: 0x9E37_79B9_7F4A_7C15,
            last_volts: 0.0,
        }
    }

    /// Runs the loops for `dt_ns` under `demand`.
    pub fn step(&mut self, demand: Demand, dt_ns: u64) {
        let v_cmd = match demand {
            Demand::Off => {
                self.motor.set_volts(0.0);
                self.last_volts = 0.0;
                self.motor.advance(dt_ns);
                return;
            }
            Demand::Position {
                setpoint,
                feed_forward,
            } => feed_forward + self.params.position_gain * (setpoint - self.position()),
            Demand::Velocity(v) => v,
        };
        let k = self.params.motor.speed_per_volt.max(1e-9);
        let kv = self.params.velocity_gain;
        let volts = (((1.0 + kv) * v_cmd - kv * self.motor.velocity()) / k)
            .clamp(-self.params.supply, self.params.supply);
        self.last_volts = if volts.is_finite() { volts } else { 0.0 };
        self.motor.set_volts(self.last_volts);
        self.motor.advance(dt_ns);
    }

    /// Position actual (counts from the home origin), exact.
    pub fn position(&self) -> f64 {
        self.motor.position() - self.origin
    }

    /// Position where the motor is, ignoring homing (what switches see).
    pub fn motor_position(&self) -> f64 {
        self.motor.position()
    }

    /// Moves the shaft by hand to motor position `counts`.
    pub fn set_motor_position(&mut self, counts: f64) {
        self.motor.set_position(counts);
    }

    /// Velocity (counts/s).
    pub fn velocity(&self) -> f64 {
        self.motor.velocity()
    }

    /// A reading of the position as the encoder gives it: rounded, with
    /// the configured noise.
    pub fn reading(&mut self) -> i32 {
        let mut p = self.position();
        if self.params.noise_counts > 0.0 {
            // xorshift64: deterministic, so runs repeat.
            self.noise ^= self.noise << 13;
            self.noise ^= self.noise >> 7;
            self.noise ^= self.noise << 17;
            let unit = (self.noise >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
            p += unit * self.params.noise_counts;
        }
        saturate(p)
    }

    /// Redefines the position: from now on `position()` reads `value`
    /// here (homing).
    pub fn rehome(&mut self, value: f64) {
        self.origin = self.motor.position() - value;
    }

    /// Sets a load on the motor, as the drive voltage it takes to hold
    /// (a stalled or jammed axis when larger than the supply).
    pub fn set_load(&mut self, volts: f64) {
        self.motor.set_load(volts);
    }

    /// Motor current as per mille of the supply's stall current: the
    /// share of the drive voltage not balanced by back-EMF.
    pub fn current_per_mille(&self) -> i16 {
        let k = self.params.motor.speed_per_volt.max(1e-9);
        let net = self.last_volts - self.motor.velocity() / k;
        (1000.0 * net / self.params.supply.max(1e-9)).clamp(-32768.0, 32767.0) as i16
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_position_loop_settles_on_its_set_point() {
        let mut a = Axis::new(AxisParams::default());
        for _ in 0..5000 {
            a.step(
                Demand::Position {
                    setpoint: 10_000.0,
                    feed_forward: 0.0,
                },
                100_000,
            );
        }
        assert!((a.position() - 10_000.0).abs() < 2.0, "{}", a.position());
        a.rehome(0.0);
        assert_eq!(a.reading(), 0);
        assert!((a.motor_position() - 10_000.0).abs() < 2.0);
    }

    #[test]
    fn the_velocity_loop_reaches_its_speed_and_coasts_down() {
        let mut a = Axis::new(AxisParams::default());
        for _ in 0..1000 {
            a.step(Demand::Velocity(50_000.0), 100_000);
        }
        assert!((a.velocity() - 50_000.0).abs() < 500.0, "{}", a.velocity());
        for _ in 0..10_000 {
            a.step(Demand::Off, 100_000);
        }
        assert_eq!(a.velocity(), 0.0);
    }
}
