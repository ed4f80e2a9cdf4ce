//! `filter_kalman`: a one-dimensional Kalman filter (constant model) for
//! noisy measurements, with process covariance `Qk` and measurement
//! covariance `Rk`. `reset` restarts it (output 0); `passthrough` copies
//! the measurement. The state is kept in single precision, as in
//! LinuxCNC.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The covariances' default: the smallest normal f32.
pub const DEFAULT_COVARIANCE: f64 = 1.17549e-38;

/// The filter's state.
#[derive(Debug, Clone, Default)]
pub struct Kalman {
    xk_last: f32,
    pk_last: f32,
    initialized: bool,
}

impl Kalman {
    /// One call: returns the estimate (`xk-out`).
    pub fn step(&mut self, zk: f64, reset: bool, passthrough: bool, rk: f64, qk: f64) -> f64 {
        if reset || !self.initialized {
            self.xk_last = 0.0;
            self.pk_last = 1.0;
            self.initialized = true;
            if reset {
                return 0.0;
            }
        }
        if passthrough {
            return zk;
        }
        let xk = f64::from(self.xk_last);
        let pk = f64::from(self.pk_last) + qk;
        let yk = zk - xk;
        let sk = rk + pk;
        let kk = pk / sk;
        let xk = xk + kk * yk;
        let pk = (1.0 - kk) * pk;
        self.xk_last = xk as f32;
        self.pk_last = pk as f32;
        xk
    }
}

/// The `filter_kalman` component.
pub struct FilterKalman;
impl HalComp for FilterKalman {
    const NAME: &'static str = "filter_kalman";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        // The `debug` pin exists for compatibility; the values it would
        // print are on the pins, for halmeter or halsampler.
        let _debug = inst.pin_in::<bool>("debug")?;
        let passthrough = inst.pin_in::<bool>("passthrough")?;
        let reset = inst.pin_in::<bool>("reset")?;
        let zk = inst.pin_in::<f64>("zk")?;
        let xk_out = inst.pin_out::<f64>("xk-out")?;
        let rk = inst.param_rw::<f64>("Rk", DEFAULT_COVARIANCE)?;
        let qk = inst.param_rw::<f64>("Qk", DEFAULT_COVARIANCE)?;
        let mut k = Kalman::default();
        inst.funct("_", true, move |_| {
            xk_out.set(k.step(zk.get(), reset.get(), passthrough.get(), rk.get(), qk.get()))
        })
    }
}
halcomp_module!(pub MODULE, FilterKalman, "unidimensional Kalman filter");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    #[test]
    fn converges_on_a_constant_and_smooths_noise() {
        let mut k = Kalman::default();
        let mut x = 0.0;
        for i in 0..200 {
            let noise = if i % 2 == 0 { 0.5 } else { -0.5 };
            x = k.step(10.0 + noise, false, false, 0.25, 1e-5);
        }
        assert!((x - 10.0).abs() < 0.1, "{x}");
        // The first step with tiny covariances trusts the measurement.
        let mut k = Kalman::default();
        let x = k.step(4.0, false, false, DEFAULT_COVARIANCE, DEFAULT_COVARIANCE);
        assert_eq!(x, 4.0);
        assert_eq!(k.xk_last, 4.0f32);
    }

    #[test]
    fn reset_and_passthrough() {
        let mut k = Kalman::default();
        k.step(5.0, false, false, 1.0, 1.0);
        assert_eq!(
            k.step(5.0, true, true, 1.0, 1.0),
            0.0,
            "reset beats passthrough"
        );
        assert_eq!(k.step(7.0, false, true, 1.0, 1.0), 7.0);
        assert_eq!(k.xk_last, 0.0, "passthrough leaves the state");
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("kalman");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "filter-kalman.0",
            &[
                "debug bit in 0",
                "passthrough bit in 0",
                "reset bit in 0",
                "zk float in 0",
                "xk-out float out 0",
            ],
        );
        h.check_params(
            "filter-kalman.0",
            &["Rk float rw 1.17549e-38", "Qk float rw 1.17549e-38"],
        );
        h.thread(&["filter-kalman.0"]);
        h.set("filter-kalman.0.passthrough", Bit(true));
        h.expect(
            &[("filter-kalman.0.zk", Float(3.0))],
            "filter-kalman.0.xk-out",
            Float(3.0),
        );
    }
}
