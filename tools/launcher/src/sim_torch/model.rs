//! The arc voltage of `sim-torch`: zero while `start` is off; after a
//! start, a rise to the cut voltage over `on-delay-in` cycles, an
//! overshoot of `overshoot-in` percent that peaks `ramp-up-in` percent
//! of the way through `cycles-in` cycles and falls back, then the cut
//! voltage plus `offset-in` with noise (`void` makes it climb by
//! `void_ramp` volts a cycle, up to 300 V). Inputs are held to the
//! ranges sim-torch accepts.

/// Highest voltage a void reaches.
const VOID_MAX: f64 = 300.0;

/// The pin values one cycle reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorchInputs {
    /// `start`.
    pub start: bool,
    /// `voltage-in`: the cut voltage (50 to 150).
    pub voltage: f64,
    /// `offset-in`: added to the cut voltage (-10 to 10).
    pub offset: f64,
    /// `cut-noise-in`: noise amplitude while cutting.
    pub cut_noise: f64,
    /// `ramp-noise-in`: noise amplitude during the overshoot.
    pub ramp_noise: f64,
    /// `cycles-in`: cycles of the overshoot.
    pub cycles: i32,
    /// `on-delay-in`: cycles from start to the cut voltage (0 to 100).
    pub on_delay: i32,
    /// `overshoot-in`: overshoot, percent of the cut voltage (0 to 100).
    pub overshoot: i32,
    /// `ramp-up-in`: share of the overshoot cycles spent rising (0 to 100).
    pub ramp_up: i32,
    /// `void`.
    pub void: bool,
    /// `void_ramp`: volts a cycle a void adds.
    pub void_ramp: i32,
}

impl Default for TorchInputs {
    /// sim-torch's defaults.
    fn default() -> Self {
        TorchInputs {
            start: false,
            voltage: 100.0,
            offset: 0.0,
            cut_noise: 0.75,
            ramp_noise: 5.0,
            cycles: 200,
            on_delay: 10,
            overshoot: 50,
            ramp_up: 80,
            void: false,
            void_ramp: 0,
        }
    }
}

/// The simulated torch.
#[derive(Debug, Clone, PartialEq)]
pub struct Torch {
    /// Cycles since the start.
    cycle: u64,
    /// Cycles in the current void.
    void_cycle: u64,
    /// Noise generator state (xorshift).
    seed: u64,
}

impl Default for Torch {
    fn default() -> Self {
        Torch {
            cycle: 0,
            void_cycle: 0,
            seed: 0x9e37_79b9_7f4a_7c15,
        }
    }
}

impl Torch {
    /// One cycle: the arc voltage.
    pub fn step(&mut self, i: &TorchInputs) -> f64 {
        if !i.start {
            self.cycle = 0;
            self.void_cycle = 0;
            return 0.0;
        }
        let volts = clamp_or(i.voltage, 50.0, 150.0, 100.0);
        let offset = clamp_or(i.offset, -10.0, 10.0, 0.0);
        let on_delay = u64::from(i.on_delay.clamp(0, 100).unsigned_abs());
        let over = volts * f64::from(i.overshoot.clamp(0, 100)) / 100.0;
        let cycles = u64::from(i.cycles.unsigned_abs());
        let up = cycles * u64::from(i.ramp_up.clamp(0, 100).unsigned_abs()) / 100;
        let n = self.cycle;
        self.cycle = self.cycle.saturating_add(1);
        if n < on_delay {
            return volts * (n + 1) as f64 / on_delay as f64;
        }
        let k = n - on_delay;
        if k < cycles {
            let rise = if k < up {
                over * (k + 1) as f64 / up as f64
            } else {
                over * (cycles - k) as f64 / (cycles - up) as f64
            };
            let noise = self.noise(i.ramp_noise);
            return volts + rise + noise;
        }
        if i.void {
            self.void_cycle = self.void_cycle.saturating_add(1);
            let v = volts + f64::from(i.void_ramp) * self.void_cycle as f64;
            return v.min(VOID_MAX);
        }
        self.void_cycle = 0;
        let noise = self.noise(i.cut_noise);
        volts + offset + noise
    }

    /// A uniform value in `[-amplitude, amplitude]`.
    fn noise(&mut self, amplitude: f64) -> f64 {
        let mut x = self.seed;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.seed = x;
        let unit = (x >> 11) as f64 / (1u64 << 53) as f64;
        let a = if amplitude.is_finite() {
            amplitude.abs()
        } else {
            0.0
        };
        (unit * 2.0 - 1.0) * a
    }
}

/// `v` held to `lo..=hi`, or `default` when it is not a number.
fn clamp_or(v: f64, lo: f64, hi: f64, default: f64) -> f64 {
    if v.is_nan() {
        default
    } else {
        v.clamp(lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rises_overshoots_and_settles_at_the_cut_voltage() {
        let mut t = Torch::default();
        let mut i = TorchInputs {
            start: true,
            cut_noise: 0.0,
            ramp_noise: 0.0,
            ..TorchInputs::default()
        };
        let v: Vec<f64> = (0..400).map(|_| t.step(&i)).collect();
        assert_eq!(v[0], 10.0);
        assert_eq!(v[9], 100.0);
        // The peak: 50 % over, 80 % of the way through 200 cycles.
        let peak = v.iter().cloned().fold(0.0, f64::max);
        assert_eq!(peak, 150.0);
        assert_eq!(v[10 + 159], 150.0);
        assert_eq!(v[399], 100.0);
        i.offset = 25.0; // held to 10
        assert_eq!(t.step(&i), 110.0);
        i.void = true;
        i.void_ramp = 100;
        assert_eq!(t.step(&i), 200.0);
        assert_eq!(t.step(&i), 300.0);
        assert_eq!(t.step(&i), 300.0);
        i.start = false;
        assert_eq!(t.step(&i), 0.0);
    }

    #[test]
    fn noise_stays_within_its_amplitude_and_odd_inputs_are_held() {
        let mut t = Torch::default();
        let i = TorchInputs {
            start: true,
            on_delay: 0,
            cycles: 0,
            voltage: f64::NAN,
            ..TorchInputs::default()
        };
        for _ in 0..1000 {
            let v = t.step(&i);
            assert!((99.25..=100.75).contains(&v), "{v}");
        }
        let i = TorchInputs {
            start: true,
            on_delay: -5,
            cycles: -3,
            ramp_up: 0,
            overshoot: 500,
            ..TorchInputs::default()
        };
        let mut t = Torch::default();
        for _ in 0..10 {
            assert!(t.step(&i).is_finite());
        }
    }
}
