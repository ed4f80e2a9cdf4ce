//! `edge`: detects rising, falling or both edges of a bit and emits a
//! pulse of at least one call, `out-width-ns` long.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

use super::write_changed;

/// The pin and param values one call of `edge` reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct EdgeVars {
    /// Pin `in`.
    pub input: bool,
    /// Pin `out` (read back).
    pub out: bool,
    /// Pin `out-invert`.
    pub out_invert: bool,
    /// Param `both`: trigger on either edge.
    pub both: bool,
    /// Param `in-edge`: TRUE selects falling edges, FALSE rising.
    pub in_edge: bool,
    /// Param `out-width-ns`.
    pub out_width_ns: i32,
    /// Param `time-left-ns` (read back).
    pub time_left_ns: i32,
    /// Param `last-in` (read back).
    pub last_in: bool,
}

/// Per-instance state of `edge`.
#[derive(Debug, Clone)]
pub struct Edge {
    /// No edge is looked for on the very first call.
    first: bool,
}

impl Default for Edge {
    fn default() -> Self {
        Edge { first: true }
    }
}

impl Edge {
    /// One call with thread period `period` ns.
    pub fn step(&mut self, v: &mut EdgeVars, period: i64) {
        let x = v.input;
        let mut tl = v.time_left_ns;
        if tl > 0 {
            // int minus long, stored back into an int: keep the low bits.
            tl = (tl as i64).wrapping_sub(period) as i32;
            v.time_left_ns = tl;
        }
        if !self.first {
            let rise = x && !v.last_in;
            let fall = !x && v.last_in;
            let want = if v.both {
                rise || fall
            } else if v.in_edge {
                fall
            } else {
                rise
            };
            if want {
                v.time_left_ns = v.out_width_ns;
                v.out = true;
            } else if tl > 0 {
                v.out = true;
            } else {
                v.time_left_ns = 0;
                v.out = false;
            }
        } else {
            self.first = false;
        }
        v.last_in = x;
        v.out_invert = !v.out;
    }
}

/// The `edge` component.
pub struct EdgeComp;
impl HalComp for EdgeComp {
    const NAME: &'static str = "edge";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<bool>("in")?;
        let out = inst.pin_out::<bool>("out")?;
        let out_invert = inst.pin_out::<bool>("out-invert")?;
        let both = inst.param_rw::<bool>("both", false)?;
        let in_edge = inst.param_rw::<bool>("in-edge", true)?;
        let out_width_ns = inst.param_rw::<i32>("out-width-ns", 0)?;
        let time_left_ns = inst.param_ro::<i32>("time-left-ns", 0)?;
        let last_in = inst.param_ro::<bool>("last-in", false)?;
        let mut state = Edge::default();
        inst.funct("_", false, move |ctx| {
            let old = EdgeVars {
                input: input.get(),
                out: out.get(),
                out_invert: out_invert.get(),
                both: both.get(),
                in_edge: in_edge.get(),
                out_width_ns: out_width_ns.get(),
                time_left_ns: time_left_ns.get(),
                last_in: last_in.get(),
            };
            let mut v = old;
            state.step(&mut v, ctx.period());
            if v.time_left_ns != old.time_left_ns {
                time_left_ns.set(v.time_left_ns);
            }
            write_changed(&out, old.out, v.out);
            last_in.set(v.last_in);
            write_changed(&out_invert, old.out_invert, v.out_invert);
        })
    }
}
halcomp_module!(pub MODULE, EdgeComp, "edge detector with a pulse output");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing;

    /// Runs `inputs` through a fresh edge; returns (out, out-invert) per call.
    fn run(vars: EdgeVars, inputs: &[bool], period: i64) -> Vec<(bool, bool)> {
        let mut e = Edge::default();
        let mut v = vars;
        inputs
            .iter()
            .map(|&x| {
                v.input = x;
                e.step(&mut v, period);
                (v.out, v.out_invert)
            })
            .collect()
    }

    fn rising() -> EdgeVars {
        EdgeVars {
            in_edge: false,
            ..Default::default()
        }
    }

    #[test]
    fn first_call_never_triggers_and_sets_out_invert() {
        let r = run(rising(), &[true, true, false, true], 1000);
        assert_eq!(
            r,
            [(false, true), (false, true), (false, true), (true, false)]
        );
        let falling = EdgeVars {
            in_edge: true,
            ..Default::default()
        };
        // Starting high and falling at once: the first call only records.
        let r = run(falling, &[true, false, false], 1000);
        assert_eq!(r, [(false, true), (true, false), (false, true)]);
    }

    #[test]
    fn both_edges() {
        let v = EdgeVars {
            both: true,
            ..Default::default()
        };
        let r: Vec<bool> = run(v, &[false, true, true, false, false], 1000)
            .into_iter()
            .map(|p| p.0)
            .collect();
        assert_eq!(r, [false, true, false, true, false]);
    }

    #[test]
    fn pulse_lasts_ceil_width_over_period_calls() {
        for (width, calls) in [(0, 1), (999, 1), (1000, 1), (1001, 2), (2500, 3), (3000, 3)] {
            let v = EdgeVars {
                out_width_ns: width,
                ..rising()
            };
            let mut inputs = vec![false, true];
            inputs.extend([true; 6]);
            let highs = run(v, &inputs, 1000).iter().filter(|p| p.0).count();
            assert_eq!(highs, calls, "width {width}");
        }
    }

    #[test]
    fn time_left_counts_down_and_ends_at_zero() {
        let mut e = Edge::default();
        let mut v = EdgeVars {
            out_width_ns: 2500,
            ..rising()
        };
        let mut seen = Vec::new();
        for x in [false, true, true, true, true] {
            v.input = x;
            e.step(&mut v, 1000);
            seen.push(v.time_left_ns);
        }
        assert_eq!(seen, [0, 2500, 1500, 500, 0]);
    }

    #[test]
    fn new_edge_restarts_the_pulse() {
        let v = EdgeVars {
            both: true,
            out_width_ns: 2500,
            ..Default::default()
        };
        let r: Vec<bool> = run(v, &[false, true, true, false, false, false, false], 1000)
            .into_iter()
            .map(|p| p.0)
            .collect();
        assert_eq!(r, [false, true, true, true, true, true, false]);
    }

    #[test]
    fn time_left_wraps_like_c() {
        let mut e = Edge { first: false };
        let mut v = EdgeVars {
            time_left_ns: 5,
            ..rising()
        };
        e.step(&mut v, i64::from(i32::MAX) + 10);
        // 5 - (2^31 + 9) wraps to a positive int: the pulse continues.
        assert_eq!(
            v.time_left_ns,
            5i64.wrapping_sub(i64::from(i32::MAX) + 10) as i32
        );
        assert!(v.time_left_ns > 0 && v.out);
    }

    #[test]
    fn loads_with_halcompile_names() {
        let host = testing::host();
        testing::load(&host, &MODULE, &["names=e1"]).unwrap();
        assert_eq!(
            testing::pin_names(&host),
            ["e1.in", "e1.out", "e1.out-invert", "e1.time"]
        );
        assert!(testing::param_names(&host).contains(&"e1.time-left-ns".to_string()));
        assert_eq!(testing::funct_names(&host), ["e1"]);
        assert_eq!(
            host.instance().param_value("e1.in-edge").unwrap(),
            hal_core::Value::Bit(true)
        );
    }
}
