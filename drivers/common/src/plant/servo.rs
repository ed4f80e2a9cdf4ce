//! [`ServoAxis`]: what a servo card's analog output moves and its counter
//! reads: a DC motor ([`DcMotor`]) on an amplifier that outputs the
//! card's voltage, with a quadrature encoder ([`QuadEncoder`]) on its
//! shaft. Positions are in revolutions.

use super::{DcMotor, DcMotorParams, EncoderMove, QuadEncoder};

/// The motor of [`ServoAxis::default`]: 2 rev/s per volt, a 20 ms time
/// constant, 0.05 V of friction.
pub const SMALL_SERVO: DcMotorParams = DcMotorParams {
    speed_per_volt: 2.0,
    time_constant: 0.02,
    friction: 0.05,
};

/// A servo motor with an encoder on its shaft.
#[derive(Debug, Clone, PartialEq)]
pub struct ServoAxis {
    /// The motor (position in revolutions).
    pub motor: DcMotor,
    /// The encoder on the shaft.
    pub encoder: QuadEncoder,
    /// The board output that enables the amplifier, numbered as the
    /// board's model numbers its outputs; `None`: always enabled.
    pub amp_enable: Option<usize>,
}

impl Default for ServoAxis {
    /// A [`SMALL_SERVO`] with a 1000-line encoder (4000 counts per
    /// revolution), its amplifier always enabled.
    fn default() -> ServoAxis {
        ServoAxis::new(SMALL_SERVO, 4000)
    }
}

impl ServoAxis {
    /// A motor with `params` and an encoder of `counts_per_rev`, at rest
    /// at 0 (an index position).
    pub fn new(params: DcMotorParams, counts_per_rev: u32) -> ServoAxis {
        ServoAxis {
            motor: DcMotor::new(params),
            encoder: QuadEncoder::new(counts_per_rev),
            amp_enable: None,
        }
    }

    /// Lets `dt_ns` pass with `volts` on the motor; the encoder follows
    /// the shaft. What the encoder's lines did on the way.
    pub fn drive(&mut self, volts: f64, dt_ns: u64) -> EncoderMove {
        self.motor.set_volts(volts);
        self.motor.advance(dt_ns);
        self.encoder.set_revs(self.motor.position())
    }

    /// Turns the shaft to `revs` by hand.
    pub fn turn_to(&mut self, revs: f64) -> EncoderMove {
        self.motor.set_position(revs);
        self.encoder.set_revs(revs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn volts_turn_the_shaft_the_encoder_counts() {
        let mut a = ServoAxis::default();
        let m = a.drive(1.0, 1_000_000_000);
        // (1 - 0.05) V * 2 rev/s/V for 1 s less the 20 ms lag.
        let revs = a.motor.position();
        assert!((revs - 1.9 * (1.0 - 0.02)).abs() < 1e-3, "{revs}");
        assert_eq!(m.delta, a.encoder.count());
        assert_eq!(m.index_pulses, 1);
        let m = a.turn_to(-0.25);
        assert_eq!(a.encoder.count(), -1000);
        assert_eq!(
            (m.first_index, m.index_pulses),
            (Some(4000), 2),
            "backwards: 4000, then 0"
        );
        a.drive(0.0, 1_000_000_000); // coasts to a stop
        assert_eq!(a.drive(0.0, 1_000_000).delta, 0, "held by friction");
    }
}
