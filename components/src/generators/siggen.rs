//! `siggen`: a signal generator giving square, sawtooth, triangle, sine and
//! cosine waves and a clock bit, all from one phase accumulator per
//! channel.
//!
//! Module parameters: `num_chan=N` (1..16, default 1) or `names=a,b,...`
//! (up to 16), not both. Each channel `P` (`siggen.<i>` or the name) has
//! one function `P.update`.

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{Host, In, Out, Pin, Result};

use crate::halcomp::channel_names;

/// Most channels one load may create.
pub const MAX_CHAN: usize = 16;

/// Angle of one full cycle: twice LinuxCNC's single-precision-like value
/// of pi, so the results match its sampled output bit for bit.
// Deliberately not `std::f64::consts::PI`: the difference is visible.
#[allow(clippy::approx_constant)]
const FULL_TURN: f64 = 2.0 * 3.1415927;

const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "num_chan",
        kind: ParamKind::Int,
        help: "number of signal generators (1-16)",
    },
    ParamDecl {
        name: "names",
        kind: ParamKind::StrArray(MAX_CHAN),
        help: "names of the signal generators, comma separated",
    },
];

/// The `siggen` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "siggen",
    params: PARAMS,
    help: "signal generator: square, sawtooth, triangle, sine, cosine, clock",
    load,
};

/// The values one update produces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Waves {
    /// `-amplitude` in the first half of the cycle, `+amplitude` in the
    /// second, plus offset.
    pub square: f64,
    /// Rises from `-amplitude` to `+amplitude` over the cycle, plus offset.
    pub sawtooth: f64,
    /// Rises over the first half cycle and falls over the second.
    pub triangle: f64,
    /// Sine of the phase, scaled and offset.
    pub sine: f64,
    /// Cosine of the phase, scaled and offset.
    pub cosine: f64,
    /// TRUE in the second half of the cycle.
    pub clock: bool,
}

/// One generator: the phase (`index`, 0..1 for non-negative frequencies)
/// and the waveform formulas.
#[derive(Debug, Clone, Default)]
pub struct SigGen {
    /// Current phase as a fraction of a cycle.
    pub index: f64,
}

impl SigGen {
    /// Advances the phase by one period of `fperiod` seconds and computes
    /// the outputs. `frequency` is the input pin's value; above the
    /// Nyquist limit it is lowered to `0.5 / fperiod`, and the caller
    /// writes it back to the pin. `reset` holds the phase at mid-cycle.
    pub fn update(
        &mut self,
        fperiod: f64,
        frequency: &mut f64,
        amplitude: f64,
        offset: f64,
        reset: bool,
    ) -> Waves {
        let mut step = *frequency * fperiod;
        if step > 0.5 {
            *frequency = 0.5 / fperiod;
            step = 0.5;
        }
        if reset {
            self.index = 0.5;
        } else {
            self.index += step;
        }
        // Only one wrap, and only upwards: a negative frequency lets the
        // phase run down without bound, as in LinuxCNC.
        if self.index >= 1.0 {
            self.index -= 1.0;
        }
        let (sq, clock) = if self.index > 0.5 {
            (1.0, true)
        } else {
            (-1.0, false)
        };
        let saw = (self.index * 2.0) - 1.0;
        let tri = ((saw * 2.0) * sq) - 1.0;
        let angle = self.index * FULL_TURN;
        Waves {
            square: (sq * amplitude) + offset,
            sawtooth: (saw * amplitude) + offset,
            triangle: (tri * amplitude) + offset,
            sine: (angle.sin() * amplitude) + offset,
            cosine: (angle.cos() * amplitude) + offset,
            clock,
        }
    }
}

/// The pins of one channel.
struct Channel {
    square: Pin<f64, Out>,
    sawtooth: Pin<f64, Out>,
    triangle: Pin<f64, Out>,
    sine: Pin<f64, Out>,
    cosine: Pin<f64, Out>,
    clock: Pin<bool, Out>,
    frequency: Pin<f64, In>,
    amplitude: Pin<f64, In>,
    offset: Pin<f64, In>,
    reset: Pin<bool, In>,
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let names = channel_names("siggen", "siggen", 1, MAX_CHAN, args)?;
    let mut b = host.new_rt_component("siggen")?;
    for prefix in names {
        let c = b.component();
        let p = |item: &str| format!("{prefix}.{item}");
        let ch = Channel {
            square: c.pin(&p("square"))?,
            sawtooth: c.pin(&p("sawtooth"))?,
            triangle: c.pin(&p("triangle"))?,
            sine: c.pin(&p("sine"))?,
            cosine: c.pin(&p("cosine"))?,
            clock: c.pin(&p("clock"))?,
            frequency: c.pin_init(&p("frequency"), 1.0)?,
            amplitude: c.pin_init(&p("amplitude"), 1.0)?,
            offset: c.pin(&p("offset"))?,
            reset: c.pin(&p("reset"))?,
        };
        let mut gen = SigGen::default();
        b.funct(&p("update"), true, move |ctx| {
            let f_in = ch.frequency.get();
            let mut freq = f_in;
            let w = gen.update(
                ctx.fperiod(),
                &mut freq,
                ch.amplitude.get(),
                ch.offset.get(),
                ch.reset.get(),
            );
            if freq.to_bits() != f_in.to_bits() {
                ch.frequency.overwrite(freq);
            }
            ch.square.set(w.square);
            ch.clock.set(w.clock);
            ch.sawtooth.set(w.sawtooth);
            ch.triangle.set(w.triangle);
            ch.sine.set(w.sine);
            ch.cosine.set(w.cosine);
        })?;
    }
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::pin_names;
    use hal_core::HalError;

    const T: f64 = 1_000_000.0 * 1e-9;

    #[test]
    fn waveforms_follow_the_phase() {
        let mut g = SigGen::default();
        let mut f = 100.0;
        // 100 Hz at 1 ms: index 0.1 after one call.
        let w = g.update(T, &mut f, 2.0, 0.5, false);
        assert_eq!(f, 100.0);
        assert_eq!(g.index, 100.0 * T);
        assert_eq!(w.square, -1.5);
        assert!(!w.clock);
        let saw = (g.index * 2.0) - 1.0;
        assert_eq!(w.sawtooth, saw * 2.0 + 0.5);
        assert_eq!(w.triangle, (-(saw * 2.0) - 1.0) * 2.0 + 0.5);
        assert_eq!(w.sine, (g.index * FULL_TURN).sin() * 2.0 + 0.5);
        assert_eq!(w.cosine, (g.index * FULL_TURN).cos() * 2.0 + 0.5);
        // Past mid-cycle the square and clock go high.
        for _ in 0..5 {
            g.update(T, &mut f, 2.0, 0.5, false);
        }
        let w = g.update(T, &mut f, 2.0, 0.5, false);
        assert!(g.index > 0.5);
        assert!(w.clock);
        assert_eq!(w.square, 2.5);
    }

    #[test]
    fn phase_wraps_once_at_one() {
        let mut g = SigGen { index: 0.9 };
        let mut f = 300.0; // step 0.3
        g.update(T, &mut f, 1.0, 0.0, false);
        assert_eq!(g.index, (0.9 + 0.3 * 1.0) - 1.0);
        assert!(g.index < 0.5);
    }

    #[test]
    fn nyquist_limit_rewrites_frequency() {
        let mut g = SigGen::default();
        let mut f = 600.0; // step 0.6 > 0.5
        let w = g.update(T, &mut f, 1.0, 0.0, false);
        assert_eq!(f, 0.5 / T);
        assert_eq!(g.index, 0.5);
        assert_eq!(w.square, -1.0);
        // Next step: 0.5 + 0.5 wraps to 0.
        g.update(T, &mut f, 1.0, 0.0, false);
        assert_eq!(g.index, 0.0);
        // Exactly 0.5 is allowed and not rewritten.
        let mut f = 500.0;
        g.update(T, &mut f, 1.0, 0.0, false);
        assert_eq!(f, 500.0);
    }

    #[test]
    fn reset_holds_mid_cycle() {
        let mut g = SigGen { index: 0.3 };
        let mut f = 10.0;
        for _ in 0..3 {
            let w = g.update(T, &mut f, 2.0, 1.0, true);
            assert_eq!(g.index, 0.5);
            assert_eq!(w.square, -1.0);
            assert_eq!(w.sawtooth, 1.0);
            assert_eq!(w.triangle, -1.0);
            assert!(!w.clock);
            assert!((w.sine - 1.0).abs() < 1e-6);
            assert_ne!(w.sine, 1.0, "pi is not exact");
            assert!((w.cosine + 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn negative_frequency_runs_down_without_wrap() {
        let mut g = SigGen::default();
        let mut f = -250.0; // step -0.25
        for _ in 0..8 {
            g.update(T, &mut f, 1.0, 0.0, false);
        }
        assert_eq!(g.index, -2.0);
        let w = g.update(T, &mut f, 1.0, 0.0, false);
        assert!(w.sawtooth < -1.0, "sawtooth leaves its range");
    }

    #[test]
    fn channel_count_and_names() {
        let host = crate::testing::host();
        host.loadrt(&MODULE, &["num_chan=2"]).unwrap();
        let pins = pin_names(&host);
        assert!(pins.contains(&"siggen.1.cosine".to_string()));
        assert!(!pins.iter().any(|p| p.starts_with("siggen.2.")));
        assert_eq!(
            pins.iter().filter(|p| p.starts_with("siggen.0.")).count(),
            11,
            "ten pins and update.time"
        );
        host.unloadrt("siggen").unwrap();
        host.loadrt(&MODULE, &["names=a,b.c"]).unwrap();
        let pins = pin_names(&host);
        assert!(pins.contains(&"b.c.frequency".to_string()));
        assert!(pins.contains(&"a.update.time".to_string()));
        assert_eq!(
            host.instance().pin_value("a.frequency").unwrap(),
            hal_core::Value::Float(1.0)
        );
        host.unloadrt("siggen").unwrap();
        host.loadrt(&MODULE, &["num_chan=0"]).unwrap();
        assert!(pin_names(&host).contains(&"siggen.0.sine".to_string()));
        host.unloadrt("siggen").unwrap();
        host.loadrt(&MODULE, &["num_chan=16"]).unwrap();
        assert!(pin_names(&host).contains(&"siggen.15.sine".to_string()));
    }

    #[test]
    fn bad_module_parameters_fail_the_load() {
        let host = crate::testing::host();
        for bad in [
            &["num_chan=17"][..],
            &["num_chan=-1"],
            &["num_chan=2", "names=a"],
            &["names=a,,b"],
            &["names=a,b,c,d,e,f,g,h,i,j,k,l,m,n,o,p,q"],
        ] {
            let e = host.loadrt(&MODULE, bad).unwrap_err();
            assert!(
                matches!(
                    e,
                    HalError::ModuleParam { .. } | HalError::ModuleLoad { .. }
                ),
                "{bad:?}: {e:?}"
            );
            assert!(pin_names(&host).is_empty(), "{bad:?} left pins behind");
        }
        let e = host.loadrt(&MODULE, &["num_chan=17"]).unwrap_err();
        assert!(e.to_string().contains("num_chan"), "{e}");
    }
}
