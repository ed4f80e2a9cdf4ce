//! [`DcMotor`]: a DC servo motor with its load, driven by a voltage (or a
//! PWM duty cycle times the supply).
//!
//! First-order mechanics: `τ·dv/dt = K·(u − load − F·sign(v)) − v`, with
//! `u` the drive voltage, `K` the no-load speed per volt, `τ` the
//! mechanical time constant (inertia over viscous damping), `F` Coulomb
//! friction and `load` a constant torque (gravity on a vertical axis),
//! both expressed as the drive voltage that balances them. A motor at
//! rest stays at rest while `|u − load| ≤ F` (stiction).
//!
//! Between input changes the equation is integrated exactly (exponential
//! solution, stopping exactly where friction brings the motor to rest),
//! so the result does not depend on how a simulation slices time.

/// A motor's constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DcMotorParams {
    /// Steady-state speed per volt without friction or load (position
    /// units per second per volt).
    pub speed_per_volt: f64,
    /// Mechanical time constant in seconds (> 0).
    pub time_constant: f64,
    /// Coulomb friction, as the drive voltage it takes to overcome (≥ 0).
    pub friction: f64,
}

/// A DC motor and what it moves.
#[derive(Debug, Clone, PartialEq)]
pub struct DcMotor {
    params: DcMotorParams,
    volts: f64,
    load: f64,
    velocity: f64,
    position: f64,
}

/// Smallest time constant used (a zero would divide by zero).
const MIN_TAU: f64 = 1e-9;

impl DcMotor {
    /// A motor at rest at position 0, no drive, no load.
    pub fn new(params: DcMotorParams) -> DcMotor {
        DcMotor {
            params: DcMotorParams {
                time_constant: params.time_constant.max(MIN_TAU),
                friction: params.friction.abs(),
                ..params
            },
            volts: 0.0,
            load: 0.0,
            velocity: 0.0,
            position: 0.0,
        }
    }

    /// The motor's constants.
    pub fn params(&self) -> DcMotorParams {
        self.params
    }

    /// Drives it with `volts`.
    pub fn set_volts(&mut self, volts: f64) {
        self.volts = volts;
    }

    /// Drives it with a PWM `duty` cycle (−1..1, sign = direction) of a
    /// `supply` voltage: the average voltage the motor sees.
    pub fn set_duty(&mut self, duty: f64, supply: f64) {
        self.volts = duty.clamp(-1.0, 1.0) * supply;
    }

    /// The drive voltage.
    pub fn volts(&self) -> f64 {
        self.volts
    }

    /// Sets a constant load torque, as the drive voltage that balances it
    /// (positive: pushes towards negative positions).
    pub fn set_load(&mut self, load_volts: f64) {
        self.load = load_volts;
    }

    /// Speed in position units per second.
    pub fn velocity(&self) -> f64 {
        self.velocity
    }

    /// Position in units.
    pub fn position(&self) -> f64 {
        self.position
    }

    /// Moves the shaft by hand (the motor keeps its speed).
    pub fn set_position(&mut self, position: f64) {
        self.position = position;
    }

    /// Lets `dt_ns` pass under the present drive and load.
    pub fn advance(&mut self, dt_ns: u64) {
        let DcMotorParams {
            speed_per_volt: k,
            time_constant: tau,
            friction,
        } = self.params;
        let drive = self.volts - self.load;
        let mut t = dt_ns as f64 * 1e-9;
        while t > 0.0 {
            let s = if self.velocity != 0.0 {
                self.velocity.signum()
            } else if drive.abs() <= friction {
                return; // held by stiction
            } else {
                drive.signum()
            };
            let v_ss = k * (drive - friction * s);
            if self.velocity != 0.0 && v_ss * s < 0.0 {
                // Decelerating through zero: friction stops it there.
                let t0 = tau * ((self.velocity - v_ss) / -v_ss).ln();
                if t0 < t {
                    self.integrate(v_ss, t0, tau);
                    self.velocity = 0.0;
                    t -= t0;
                    continue;
                }
            }
            self.integrate(v_ss, t, tau);
            t = 0.0;
        }
    }

    /// Exact solution over `t` seconds towards steady speed `v_ss`.
    fn integrate(&mut self, v_ss: f64, t: f64, tau: f64) {
        let decay = (-t / tau).exp();
        self.position += v_ss * t + (self.velocity - v_ss) * tau * (1.0 - decay);
        self.velocity = v_ss + (self.velocity - v_ss) * decay;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: DcMotorParams = DcMotorParams {
        speed_per_volt: 100.0,
        time_constant: 0.1,
        friction: 0.0,
    };

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9 * b.abs().max(1.0)
    }

    #[test]
    fn step_response_by_hand() {
        // 2 V on K = 100/s/V, tau = 0.1 s: v(t) = 200 (1 - e^-t/tau),
        // x(t) = 200 (t - tau (1 - e^-t/tau)). At t = tau:
        // v = 200 (1 - 1/e) = 126.424..., x = 200 * 0.1 / e = 7.3575...
        let mut m = DcMotor::new(P);
        m.set_volts(2.0);
        m.advance(100_000_000);
        let e = (-1.0f64).exp();
        assert!(close(m.velocity(), 200.0 * (1.0 - e)), "{}", m.velocity());
        assert!(close(m.position(), 20.0 * e), "{}", m.position());
        // Slicing time differently gives the same answer.
        let mut n = DcMotor::new(P);
        n.set_volts(2.0);
        for _ in 0..1000 {
            n.advance(100_000);
        }
        assert!(close(n.velocity(), m.velocity()) && close(n.position(), m.position()));
        // Far past tau it runs at K * u.
        m.advance(5_000_000_000);
        assert!(close(m.velocity(), 200.0));
    }

    #[test]
    fn pwm_duty_is_average_voltage_both_ways() {
        let mut m = DcMotor::new(P);
        m.set_duty(-0.25, 24.0);
        assert_eq!(m.volts(), -6.0);
        m.advance(10_000_000_000);
        assert!(close(m.velocity(), -600.0));
        m.set_duty(3.0, 24.0);
        assert_eq!(m.volts(), 24.0, "duty clamps to 100 %");
    }

    #[test]
    fn friction_holds_then_stops_it_exactly() {
        let mut m = DcMotor::new(DcMotorParams { friction: 0.5, ..P });
        m.set_volts(0.4);
        m.advance(1_000_000_000);
        assert_eq!((m.velocity(), m.position()), (0.0, 0.0), "below friction");
        m.set_volts(1.5);
        m.advance(10_000_000_000);
        assert!(close(m.velocity(), 100.0), "K (u - F) = 100");
        // Coasting from 100/s with u = 0: towards -K F = -50/s, zero at
        // t0 = tau ln(150/50) = 0.10986 s, having gone
        // -50 t0 + 150 tau (1 - 1/3) = 10 - 5 ln 3 = 4.5069 further.
        let x0 = m.position();
        m.set_volts(0.0);
        m.advance(1_000_000_000);
        assert_eq!(m.velocity(), 0.0, "stopped, not reversing");
        assert!(
            close(m.position() - x0, 10.0 - 5.0 * 3f64.ln()),
            "{}",
            m.position() - x0
        );
    }

    #[test]
    fn load_shifts_the_balance() {
        let mut m = DcMotor::new(P);
        m.set_load(1.0);
        m.advance(10_000_000_000);
        assert!(close(m.velocity(), -100.0), "an unpowered axis falls");
        m.set_volts(1.0);
        m.advance(10_000_000_000);
        assert!(m.velocity().abs() < 1e-9, "1 V holds it");
    }
}
