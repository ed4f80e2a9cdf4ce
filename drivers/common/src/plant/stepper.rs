//! [`StepperAxis`]: a stepper motor and its axis, moved by step/dir
//! pulses (a board's step output sampled each time it changes) or by a
//! step rate (a board whose step generator's pulses are too fast to
//! model one by one). The motor never loses a step.

/// A stepper-driven axis.
#[derive(Debug, Clone, PartialEq)]
pub struct StepperAxis {
    steps_per_unit: f64,
    steps: i64,
    step_line: bool,
    rate: f64,
    /// Fraction of a step accumulated from the rate.
    fraction: f64,
}

impl StepperAxis {
    /// An axis at step 0 with `steps_per_unit` steps per position unit
    /// (non-zero).
    pub fn new(steps_per_unit: f64) -> StepperAxis {
        StepperAxis {
            steps_per_unit: if steps_per_unit == 0.0 {
                1.0
            } else {
                steps_per_unit
            },
            steps: 0,
            step_line: false,
            rate: 0.0,
            fraction: 0.0,
        }
    }

    /// Samples the driver's step and direction lines: a rising edge of
    /// `step` moves one step, forward if `forward` (the board model knows
    /// its direction polarity).
    pub fn pulse(&mut self, step: bool, forward: bool) {
        if step && !self.step_line {
            self.step(forward);
        }
        self.step_line = step;
    }

    /// Moves one step.
    pub fn step(&mut self, forward: bool) {
        self.steps += if forward { 1 } else { -1 };
    }

    /// Sets a continuous step rate (steps per second, signed).
    pub fn set_rate(&mut self, steps_per_s: f64) {
        self.rate = steps_per_s;
    }

    /// The step rate.
    pub fn rate(&self) -> f64 {
        self.rate
    }

    /// Lets `dt_ns` pass at the present rate, keeping the fraction of a
    /// step for later.
    pub fn advance(&mut self, dt_ns: u64) {
        self.fraction += self.rate * dt_ns as f64 * 1e-9;
        let whole = self.fraction.trunc();
        self.steps += whole as i64;
        self.fraction -= whole;
    }

    /// Steps taken from the origin.
    pub fn steps(&self) -> i64 {
        self.steps
    }

    /// Position in units.
    pub fn position(&self) -> f64 {
        self.steps as f64 / self.steps_per_unit
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rising_edges_count_in_the_direction_given() {
        let mut a = StepperAxis::new(200.0);
        for _ in 0..3 {
            a.pulse(true, true);
            a.pulse(true, true); // still high: no second step
            a.pulse(false, true);
        }
        a.pulse(true, false);
        a.pulse(false, false);
        assert_eq!(a.steps(), 2);
        assert_eq!(a.position(), 0.01);
    }

    #[test]
    fn a_rate_accumulates_fractions() {
        let mut a = StepperAxis::new(1.0);
        a.set_rate(1000.0);
        for _ in 0..500 {
            a.advance(999_000); // 0.999 steps each
        }
        assert_eq!(a.steps(), 499, "499.5 steps so far");
        a.advance(500_000);
        assert_eq!(a.steps(), 500);
        a.set_rate(-250.0);
        a.advance(2_000_000_000);
        assert_eq!(a.steps(), 0);
    }
}
