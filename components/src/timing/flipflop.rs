//! `flipflop`: a D flip-flop with set and reset.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

use super::write_changed;

/// The pin values one call of `flipflop` reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FlipFlopVars {
    /// Pin `data`.
    pub data: bool,
    /// Pin `clk`.
    pub clk: bool,
    /// Pin `set`.
    pub set: bool,
    /// Pin `reset`.
    pub reset: bool,
    /// I/O pin `out`.
    pub out: bool,
    /// I/O pin `out-not`.
    pub out_not: bool,
}

/// Per-instance state of `flipflop`.
#[derive(Debug, Clone, Default)]
pub struct FlipFlop {
    /// `clk` at the previous call.
    oldclk: bool,
}

impl FlipFlop {
    /// One call. Reset wins over set, set over a rising clock edge.
    /// `out-not` is only written together with `out` (reference-commit
    /// behaviour; 2.9 rewrote it from `out` on every call).
    pub fn step(&mut self, v: &mut FlipFlopVars) {
        let c = v.clk;
        if v.reset {
            v.out = false;
            v.out_not = true;
        } else if v.set {
            v.out = true;
            v.out_not = false;
        } else if c && !self.oldclk {
            v.out = v.data;
            v.out_not = !v.data;
        }
        self.oldclk = c;
    }
}

/// The `flipflop` component.
pub struct FlipFlopComp;
impl HalComp for FlipFlopComp {
    const NAME: &'static str = "flipflop";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let data = inst.pin_in::<bool>("data")?;
        let clk = inst.pin_in::<bool>("clk")?;
        let set = inst.pin_in::<bool>("set")?;
        let reset = inst.pin_in::<bool>("reset")?;
        let out = inst.pin_io::<bool>("out", false)?;
        let out_not = inst.pin_io::<bool>("out-not", false)?;
        let mut state = FlipFlop::default();
        inst.funct("_", false, move |_| {
            let old = FlipFlopVars {
                data: data.get(),
                clk: clk.get(),
                set: set.get(),
                reset: reset.get(),
                out: out.get(),
                out_not: out_not.get(),
            };
            let mut v = old;
            state.step(&mut v);
            write_changed(&out, old.out, v.out);
            write_changed(&out_not, old.out_not, v.out_not);
        })
    }
}
halcomp_module!(pub MODULE, FlipFlopComp, "D flip-flop with set and reset");

#[cfg(test)]
mod tests {
    use super::*;

    fn call(
        ff: &mut FlipFlop,
        v: &mut FlipFlopVars,
        data: bool,
        clk: bool,
        set: bool,
        reset: bool,
    ) {
        v.data = data;
        v.clk = clk;
        v.set = set;
        v.reset = reset;
        ff.step(v);
    }

    #[test]
    fn loads_on_rising_clock_edge_only() {
        let mut ff = FlipFlop::default();
        let mut v = FlipFlopVars::default();
        call(&mut ff, &mut v, true, false, false, false);
        assert!(
            !v.out && !v.out_not,
            "out-not untouched until the first change"
        );
        call(&mut ff, &mut v, true, true, false, false);
        assert!(v.out && !v.out_not);
        // Clock held high: data changes are ignored.
        call(&mut ff, &mut v, false, true, false, false);
        assert!(v.out);
        call(&mut ff, &mut v, false, false, false, false);
        call(&mut ff, &mut v, false, true, false, false);
        assert!(!v.out && v.out_not);
    }

    #[test]
    fn reset_overrides_set_and_both_are_levels() {
        let mut ff = FlipFlop::default();
        let mut v = FlipFlopVars::default();
        call(&mut ff, &mut v, false, false, true, false);
        assert!(v.out && !v.out_not);
        call(&mut ff, &mut v, false, false, true, true);
        assert!(!v.out && v.out_not);
        // A clock edge during reset is consumed: no load afterwards.
        call(&mut ff, &mut v, true, true, false, true);
        call(&mut ff, &mut v, true, true, false, false);
        assert!(!v.out);
    }

    #[test]
    fn first_call_with_clock_high_is_an_edge() {
        let mut ff = FlipFlop::default();
        let mut v = FlipFlopVars::default();
        call(&mut ff, &mut v, true, true, false, false);
        assert!(v.out && !v.out_not);
    }
}
