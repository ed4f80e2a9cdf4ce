//! `safety_latch`: a latch for error signals with a count that errors
//! raise by `harm` and good calls lower by `heal`, clamped to
//! `[min, max]`; at `threshold` the error output sets, and stays set
//! until `reset` (if `latching`) or until the count drops again. While
//! not enabled the input passes straight through.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The pin values one call reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SafetyLatchVars {
    /// Pin `error-in`.
    pub error_in: bool,
    /// Pin `heal`.
    pub heal: i32,
    /// Pin `harm`.
    pub harm: i32,
    /// Pin `latching`.
    pub latching: bool,
    /// Pin `reset`.
    pub reset: bool,
    /// Pin `threshold`.
    pub threshold: i32,
    /// Pin `min`.
    pub min: i32,
    /// Pin `max`.
    pub max: i32,
    /// Pin `enable`.
    pub enable: bool,
    /// Pin `count` (read back).
    pub count: i32,
    /// Pin `error-out`.
    pub error_out: bool,
    /// Pin `ok-out`.
    pub ok_out: bool,
}

impl Default for SafetyLatchVars {
    /// The pins' defaults.
    fn default() -> Self {
        SafetyLatchVars {
            error_in: false,
            heal: 1,
            harm: 1,
            latching: true,
            reset: false,
            threshold: 100,
            min: 0,
            max: 1000,
            enable: true,
            count: 0,
            error_out: false,
            ok_out: true,
        }
    }
}

/// The latch's state.
#[derive(Debug, Clone, Default)]
pub struct SafetyLatch {
    last_reset: bool,
}

impl SafetyLatch {
    /// One call.
    pub fn step(&mut self, v: &mut SafetyLatchVars) {
        if !v.enable {
            v.error_out = v.error_in;
            v.ok_out = !v.error_in;
            v.count = 0;
        } else {
            if v.reset && !self.last_reset {
                v.count = 0;
                v.error_out = false;
                v.ok_out = true;
            }
            v.count = if v.error_in {
                v.count.wrapping_add(v.harm)
            } else {
                v.count.wrapping_sub(v.heal)
            };
            let at_least_min = if v.count > v.min { v.count } else { v.min };
            v.count = if at_least_min < v.max {
                at_least_min
            } else {
                v.max
            };
            if v.count >= v.threshold {
                v.error_out = true;
                v.ok_out = false;
            } else if !v.latching {
                v.error_out = false;
                v.ok_out = true;
            }
        }
        self.last_reset = v.reset;
    }
}

/// The `safety_latch` component.
pub struct SafetyLatchComp;
impl HalComp for SafetyLatchComp {
    const NAME: &'static str = "safety_latch";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let d = SafetyLatchVars::default();
        let error_in = inst.pin_in_init("error-in", d.error_in)?;
        let heal = inst.pin_in_init("heal", d.heal)?;
        let harm = inst.pin_in_init("harm", d.harm)?;
        let latching = inst.pin_in_init("latching", d.latching)?;
        let reset = inst.pin_in_init("reset", d.reset)?;
        let threshold = inst.pin_in_init("threshold", d.threshold)?;
        let min = inst.pin_in_init("min", d.min)?;
        let max = inst.pin_in_init("max", d.max)?;
        let enable = inst.pin_in_init("enable", d.enable)?;
        let count = inst.pin_out_init("count", d.count)?;
        let error_out = inst.pin_out_init("error-out", d.error_out)?;
        let ok_out = inst.pin_out_init("ok-out", d.ok_out)?;
        let mut latch = SafetyLatch::default();
        inst.funct("_", false, move |_| {
            let mut v = SafetyLatchVars {
                error_in: error_in.get(),
                heal: heal.get(),
                harm: harm.get(),
                latching: latching.get(),
                reset: reset.get(),
                threshold: threshold.get(),
                min: min.get(),
                max: max.get(),
                enable: enable.get(),
                count: count.get(),
                error_out: error_out.get(),
                ok_out: ok_out.get(),
            };
            latch.step(&mut v);
            count.set(v.count);
            error_out.set(v.error_out);
            ok_out.set(v.ok_out);
        })
    }
}
halcomp_module!(pub MODULE, SafetyLatchComp, "latch for error signals");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, S32};

    #[test]
    fn errors_accumulate_to_the_threshold_and_latch() {
        let mut l = SafetyLatch::default();
        let mut v = SafetyLatchVars {
            threshold: 3,
            error_in: true,
            ..Default::default()
        };
        for _ in 0..2 {
            l.step(&mut v);
        }
        assert!(!v.error_out && v.ok_out && v.count == 2);
        l.step(&mut v);
        assert!(v.error_out && !v.ok_out);
        // Healing lowers the count, but the latch holds.
        v.error_in = false;
        for _ in 0..5 {
            l.step(&mut v);
        }
        assert_eq!(v.count, 0, "clamped at min");
        assert!(v.error_out);
        // A reset edge clears it.
        v.reset = true;
        l.step(&mut v);
        assert!(!v.error_out && v.ok_out);
    }

    #[test]
    fn non_latching_follows_the_count_and_disabled_passes_through() {
        let mut l = SafetyLatch::default();
        let mut v = SafetyLatchVars {
            threshold: 2,
            harm: 5,
            latching: false,
            max: 3,
            error_in: true,
            ..Default::default()
        };
        l.step(&mut v);
        assert_eq!((v.count, v.error_out), (3, true), "clamped at max");
        v.error_in = false;
        l.step(&mut v);
        assert_eq!((v.count, v.error_out, v.ok_out), (2, true, false));
        l.step(&mut v);
        assert_eq!((v.count, v.error_out, v.ok_out), (1, false, true));
        v.enable = false;
        v.error_in = true;
        l.step(&mut v);
        assert_eq!((v.count, v.error_out, v.ok_out), (0, true, false));
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("safety-latch");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "safety-latch.0",
            &[
                "error-in bit in 0",
                "heal s32 in 1",
                "harm s32 in 1",
                "latching bit in 1",
                "reset bit in 0",
                "threshold s32 in 100",
                "min s32 in 0",
                "max s32 in 1000",
                "enable bit in 1",
                "count s32 out 0",
                "error-out bit out 0",
                "ok-out bit out 1",
            ],
        );
        h.thread(&["safety-latch.0"]);
        h.set("safety-latch.0.threshold", S32(1));
        h.expect(
            &[("safety-latch.0.error-in", Bit(true))],
            "safety-latch.0.error-out",
            Bit(true),
        );
    }
}
