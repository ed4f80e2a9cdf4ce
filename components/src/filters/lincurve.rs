//! `lincurve`: a piecewise-linear lookup table. The personality gives
//! the number of breakpoints (clamped to 2..=16); inputs outside the
//! table give the end values (no extrapolation).

use hal_core::{Param, Result, Rw};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Most breakpoints an instance can have.
pub const MAX_POINTS: usize = 16;
/// Fewest breakpoints an instance can have.
pub const MIN_POINTS: usize = 2;

/// The number of breakpoints a personality asks for, clamped as the
/// component does at load (so the default 0 gives 2).
pub fn points(personality: i64) -> usize {
    personality.clamp(MIN_POINTS as i64, MAX_POINTS as i64) as usize
}

/// lincurve's state: the segment found by the previous call, where the
/// search starts.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Lincurve {
    /// Index of the segment's left breakpoint.
    pub i: usize,
}

impl Lincurve {
    /// One call: the output for input `x` from breakpoints `xs`/`ys` (the
    /// same length, at least 2). The search is bounded to the table, so
    /// x values that do not increase give some value from the table
    /// rather than reading outside it.
    pub fn step(&mut self, x: f64, xs: &[f64], ys: &[f64]) -> f64 {
        let last = xs.len() - 1;
        if x >= xs[last] {
            return ys[last];
        }
        if x <= xs[0] {
            return ys[0];
        }
        // A table shortened since the previous call (not possible through
        // HAL, where the size is fixed) must not leave `i` outside it.
        self.i = self.i.min(last - 1);
        while self.i < last - 1 && x > xs[self.i + 1] {
            self.i += 1;
        }
        while self.i > 0 && x < xs[self.i] {
            self.i -= 1;
        }
        let i = self.i;
        let f = (x - xs[i]) / (xs[i + 1] - xs[i]);
        ys[i] + f * (ys[i + 1] - ys[i])
    }
}

/// The `lincurve` component.
pub struct LincurveComp;
impl HalComp for LincurveComp {
    const NAME: &'static str = "lincurve";
    const PERSONALITY: bool = true;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let n = points(inst.personality);
        // halcompile creates the pins before the params.
        let input = inst.pin_in::<f64>("in")?;
        let out = inst.pin_out::<f64>("out")?;
        let out_io = inst.pin_io::<f64>("out-io", 0.0)?;
        let mut xp: Vec<Param<f64, Rw>> = Vec::with_capacity(n);
        let mut yp: Vec<Param<f64, Rw>> = Vec::with_capacity(n);
        for k in 0..n {
            xp.push(inst.param_rw::<f64>(&format!("x-val-{k:02}"), 0.0)?);
        }
        for k in 0..n {
            yp.push(inst.param_rw::<f64>(&format!("y-val-{k:02}"), 0.0)?);
        }
        // Scratch copies of the table, allocated here so the function
        // itself does not allocate.
        let mut xs = vec![0.0; n];
        let mut ys = vec![0.0; n];
        let mut st = Lincurve::default();
        inst.funct("_", true, move |_| {
            for (v, p) in xs.iter_mut().zip(&xp) {
                *v = p.get();
            }
            for (v, p) in ys.iter_mut().zip(&yp) {
                *v = p.get();
            }
            let o = st.step(input.get(), &xs, &ys);
            out.set(o);
            out_io.set(o);
        })
    }
}
halcomp_module!(pub LINCURVE, LincurveComp, "one-dimensional lookup table");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn personality_is_clamped() {
        assert_eq!(points(0), 2);
        assert_eq!(points(-5), 2);
        assert_eq!(points(5), 5);
        assert_eq!(points(16), 16);
        assert_eq!(points(40), 16);
    }

    #[test]
    fn interpolates_and_holds_ends() {
        let xs = [0.0, 1.0, 3.0, 4.0];
        let ys = [10.0, 20.0, 0.0, 5.0];
        let mut l = Lincurve::default();
        assert_eq!(l.step(-1.0, &xs, &ys), 10.0);
        assert_eq!(l.step(0.0, &xs, &ys), 10.0);
        assert_eq!(l.step(0.5, &xs, &ys), 15.0);
        assert_eq!(l.step(2.0, &xs, &ys), 10.0);
        assert_eq!(l.i, 1);
        assert_eq!(l.step(3.5, &xs, &ys), 2.5);
        assert_eq!(l.i, 2);
        // Searching back down from the remembered segment.
        assert_eq!(l.step(0.25, &xs, &ys), 12.5);
        assert_eq!(l.i, 0);
        assert_eq!(l.step(4.0, &xs, &ys), 5.0);
        assert_eq!(l.step(1e9, &xs, &ys), 5.0);
    }

    #[test]
    fn default_table_of_zeros() {
        let mut l = Lincurve::default();
        assert_eq!(l.step(1.0, &[0.0, 0.0], &[0.0, 0.0]), 0.0);
        assert_eq!(l.step(-1.0, &[0.0, 0.0], &[0.0, 0.0]), 0.0);
    }

    #[test]
    fn non_increasing_table_stays_in_bounds() {
        let xs = [0.0, 5.0, 2.0, 10.0];
        let ys = [0.0, 1.0, 2.0, 3.0];
        let mut l = Lincurve::default();
        for x in [1.0, 3.0, 6.0, 9.0, 4.0, 0.5] {
            let o = l.step(x, &xs, &ys);
            assert!(l.i < 3);
            assert!(o.is_finite());
        }
    }
}
