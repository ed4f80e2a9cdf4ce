//! `biquad`: a second-order IIR filter in transposed direct form II.
//! The coefficients are either set by hand (`type` 0) or computed for a
//! low-pass (1) or notch (2) filter on each rising edge of `enable`.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The value of pi the reference uses (truncated to 12 decimals); the
/// exact constant would change the coefficients in the last bits.
#[allow(clippy::approx_constant)]
pub const PI: f64 = 3.141592653589;

/// Default of the `Q` pin (LinuxCNC's literal, not exactly 1/sqrt(2)).
#[allow(clippy::approx_constant)]
pub const DEFAULT_Q: f64 = 0.7071;

/// The filter coefficients (the `n0`..`n2`, `d1`, `d2` params).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coeffs {
    /// Numerator coefficient of x\[k\].
    pub n0: f64,
    /// Numerator coefficient of x\[k-1\].
    pub n1: f64,
    /// Numerator coefficient of x\[k-2\].
    pub n2: f64,
    /// Denominator coefficient of y\[k-1\].
    pub d1: f64,
    /// Denominator coefficient of y\[k-2\].
    pub d2: f64,
}

impl Default for Coeffs {
    /// The params' defaults: the identity filter.
    fn default() -> Self {
        Coeffs {
            n0: 1.0,
            n1: 0.0,
            n2: 0.0,
            d1: 0.0,
            d2: 0.0,
        }
    }
}

/// Computes normalised coefficients for `kind` (1 low-pass, 2 notch) at
/// corner/centre frequency `f0` (Hz) and quality `q`, for a thread of
/// `period_ns`. `None` when the request is out of range (above Nyquist,
/// `q` outside 0.5..=2) or the kind unknown.
pub fn design(kind: u32, f0: f64, q: f64, period_ns: i64) -> Option<Coeffs> {
    let fs = 1.0 / (period_ns as f64 * 1e-9);
    // Written as two comparisons on purpose: a NaN `q` passes this test
    // (as in C), which a range `contains` would not.
    #[allow(clippy::manual_range_contains)]
    let out_of_range = f0 > fs / 2.0 || q > 2.0 || q < 0.5;
    if out_of_range {
        return None;
    }
    let w0 = 2.0 * PI * f0 / fs;
    let alpha = w0.sin() / (2.0 * q);
    let c = w0.cos();
    let (b0, b1, b2) = match kind {
        1 => ((1.0 - c) / 2.0, 1.0 - c, (1.0 - c) / 2.0),
        2 => (1.0, -2.0 * c, 1.0),
        _ => return None,
    };
    let a0 = 1.0 + alpha;
    let a1 = -2.0 * c;
    let a2 = 1.0 - alpha;
    Some(Coeffs {
        n0: b0 / a0,
        n1: b1 / a0,
        n2: b2 / a0,
        d1: a1 / a0,
        d2: a2 / a0,
    })
}

/// The values one call reads and may change (pins and params).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BiquadIo {
    /// `in`.
    pub input: f64,
    /// `enable`.
    pub enable: bool,
    /// `type`: 0 direct coefficients, 1 low-pass, 2 notch.
    pub kind: u32,
    /// `f0` (Hz).
    pub f0: f64,
    /// `Q`.
    pub q: f64,
    /// The coefficient params.
    pub coeffs: Coeffs,
    /// `s1`: first state (an output pin).
    pub s1: f64,
    /// `s2`: second state (an output pin).
    pub s2: f64,
    /// `valid`: whether the coefficients are in use.
    pub valid: bool,
}

impl Default for BiquadIo {
    /// The pins' and params' defaults.
    fn default() -> Self {
        BiquadIo {
            input: 0.0,
            enable: false,
            kind: 0,
            f0: 250.0,
            q: DEFAULT_Q,
            coeffs: Coeffs::default(),
            s1: 0.0,
            s2: 0.0,
            valid: false,
        }
    }
}

/// biquad's private state.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Biquad {
    /// `enable` at the previous call, for edge detection.
    pub last_enable: bool,
}

impl Biquad {
    /// One call: updates `io` in place and returns the new `out`. Returns
    /// also whether the coefficients were recomputed (so the caller
    /// writes the params back only then).
    pub fn step(&mut self, io: &mut BiquadIo, period_ns: i64) -> (f64, bool) {
        let mut designed = false;
        if self.last_enable != io.enable {
            self.last_enable = io.enable;
            if io.enable {
                if io.kind != 0 {
                    io.valid = false;
                    if let Some(c) = design(io.kind, io.f0, io.q, period_ns) {
                        io.coeffs = c;
                        io.s2 = 0.0;
                        io.s1 = 0.0;
                        designed = true;
                        io.valid = true;
                    }
                } else {
                    io.valid = true;
                }
            }
        }
        if !io.enable || !io.valid {
            return (io.input, designed);
        }
        let x = io.input;
        let c = io.coeffs;
        let out = x * c.n0 + io.s1;
        io.s1 = (x * c.n1 - out * c.d1) + io.s2;
        io.s2 = x * c.n2 - out * c.d2;
        (out, designed)
    }
}

/// The `biquad` component.
pub struct BiquadComp;
impl HalComp for BiquadComp {
    const NAME: &'static str = "biquad";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let out = inst.pin_out::<f64>("out")?;
        let enable = inst.pin_in::<bool>("enable")?;
        let valid = inst.pin_out::<bool>("valid")?;
        let kind = inst.pin_in::<u32>("type")?;
        let f0 = inst.pin_in_init::<f64>("f0", 250.0)?;
        let q = inst.pin_in_init::<f64>("Q", DEFAULT_Q)?;
        let d1 = inst.param_rw::<f64>("d1", 0.0)?;
        let d2 = inst.param_rw::<f64>("d2", 0.0)?;
        let n0 = inst.param_rw::<f64>("n0", 1.0)?;
        let n1 = inst.param_rw::<f64>("n1", 0.0)?;
        let n2 = inst.param_rw::<f64>("n2", 0.0)?;
        let s1 = inst.pin_out::<f64>("s1")?;
        let s2 = inst.pin_out::<f64>("s2")?;
        let mut st = Biquad::default();
        inst.funct("_", true, move |ctx| {
            let mut io = BiquadIo {
                input: input.get(),
                enable: enable.get(),
                kind: kind.get(),
                f0: f0.get(),
                q: q.get(),
                coeffs: Coeffs {
                    n0: n0.get(),
                    n1: n1.get(),
                    n2: n2.get(),
                    d1: d1.get(),
                    d2: d2.get(),
                },
                s1: s1.get(),
                s2: s2.get(),
                valid: valid.get(),
            };
            let (o, designed) = st.step(&mut io, ctx.period());
            if designed {
                n0.set(io.coeffs.n0);
                n1.set(io.coeffs.n1);
                n2.set(io.coeffs.n2);
                d1.set(io.coeffs.d1);
                d2.set(io.coeffs.d2);
            }
            valid.set(io.valid);
            out.set(o);
            s1.set(io.s1);
            s2.set(io.s2);
        })
    }
}
halcomp_module!(pub BIQUAD, BiquadComp, "biquad IIR filter");

#[cfg(test)]
mod tests {
    use super::*;

    const P: i64 = 1_000_000;

    #[test]
    fn disabled_and_identity_pass_through() {
        let mut b = Biquad::default();
        let mut io = BiquadIo::default();
        for (x, en) in [(1.0, false), (2.0, true), (-3.0, true), (4.0, false)] {
            io.input = x;
            io.enable = en;
            let (o, designed) = b.step(&mut io, P);
            assert_eq!(o, x);
            assert!(!designed);
        }
        // Type 0 sets valid on the rising edge and keeps it afterwards.
        assert!(io.valid);
    }

    #[test]
    fn lowpass_design_has_unit_dc_gain() {
        let c = design(1, 50.0, DEFAULT_Q, P).unwrap();
        let dc = (c.n0 + c.n1 + c.n2) / (1.0 + c.d1 + c.d2);
        assert!((dc - 1.0).abs() < 1e-12);
        // The filter settles at the input.
        let mut b = Biquad::default();
        let mut io = BiquadIo {
            kind: 1,
            f0: 50.0,
            enable: true,
            input: 1.0,
            ..Default::default()
        };
        let mut o = 0.0;
        for _ in 0..2000 {
            o = b.step(&mut io, P).0;
        }
        assert!(io.valid);
        assert!((o - 1.0).abs() < 1e-9);
    }

    #[test]
    fn notch_rejects_its_frequency() {
        let c = design(2, 60.0, 2.0, P).unwrap();
        assert_eq!(c.n0, c.n2);
        assert!(design(2, 60.0, 2.1, P).is_none());
        assert!(design(2, 60.0, 0.49, P).is_none());
        assert!(design(1, 501.0, 1.0, P).is_none());
        assert!(design(3, 60.0, 1.0, P).is_none());
        // As in C, a NaN Q fails neither comparison and is accepted.
        assert!(design(1, 60.0, f64::NAN, P).is_some());
    }

    #[test]
    fn bad_design_leaves_valid_false_and_passes_through() {
        let mut b = Biquad::default();
        let mut io = BiquadIo {
            kind: 1,
            f0: 1e6,
            enable: true,
            input: 2.5,
            ..Default::default()
        };
        assert_eq!(b.step(&mut io, P), (2.5, false));
        assert!(!io.valid);
    }

    #[test]
    fn coefficients_only_change_on_rising_edge() {
        let mut b = Biquad::default();
        let mut io = BiquadIo {
            kind: 1,
            f0: 50.0,
            enable: true,
            ..Default::default()
        };
        assert!(b.step(&mut io, P).1);
        let c = io.coeffs;
        io.f0 = 100.0;
        assert!(!b.step(&mut io, P).1);
        assert_eq!(io.coeffs, c);
        io.enable = false;
        b.step(&mut io, P);
        io.enable = true;
        assert!(b.step(&mut io, P).1);
        assert_ne!(io.coeffs, c);
    }
}
