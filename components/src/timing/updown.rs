//! `updown`: an up/down counter of rising edges with reset, optional
//! clamping or wrapping between `min` and `max`.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The pin and param values one call of `updown` reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct UpDownVars {
    /// Pin `countup`.
    pub countup: bool,
    /// Pin `countdown`.
    pub countdown: bool,
    /// Pin `reset` (a level: holds the count at 0 while TRUE).
    pub reset: bool,
    /// Pin `count` (read back).
    pub count: i32,
    /// Param `clamp`.
    pub clamp: bool,
    /// Param `wrap` (takes precedence over `clamp`).
    pub wrap: bool,
    /// Param `max`.
    pub max: i32,
    /// Param `min`.
    pub min: i32,
}

/// Per-instance state of `updown`.
#[derive(Debug, Clone)]
pub struct UpDown {
    oldup: bool,
    olddown: bool,
    /// The first call only records the inputs.
    first: bool,
}

impl Default for UpDown {
    fn default() -> Self {
        UpDown {
            oldup: false,
            olddown: false,
            first: true,
        }
    }
}

impl UpDown {
    /// One call.
    pub fn step(&mut self, v: &mut UpDownVars) {
        let mut c = v.count;
        if self.first {
            self.oldup = v.countup;
            self.olddown = v.countdown;
            self.first = false;
        }
        if !self.oldup && v.countup {
            c = c.wrapping_add(1);
        }
        if !self.olddown && v.countdown {
            c = c.wrapping_sub(1);
        }
        if v.reset {
            c = 0;
        }
        if v.wrap {
            if c > v.max {
                c = v.min;
            } else if c < v.min {
                c = v.max;
            }
        } else if v.clamp {
            if c > v.max {
                c = v.max;
            } else if c < v.min {
                c = v.min;
            }
        }
        v.count = c;
        self.oldup = v.countup;
        self.olddown = v.countdown;
    }
}

/// The `updown` component.
pub struct UpDownComp;
impl HalComp for UpDownComp {
    const NAME: &'static str = "updown";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let countup = inst.pin_in::<bool>("countup")?;
        let countdown = inst.pin_in::<bool>("countdown")?;
        let reset = inst.pin_in::<bool>("reset")?;
        let count = inst.pin_out::<i32>("count")?;
        let clamp = inst.param_rw::<bool>("clamp", false)?;
        let wrap = inst.param_rw::<bool>("wrap", false)?;
        let max = inst.param_rw::<i32>("max", i32::MAX)?;
        let min = inst.param_rw::<i32>("min", 0)?;
        let mut state = UpDown::default();
        inst.funct("_", false, move |_| {
            let mut v = UpDownVars {
                countup: countup.get(),
                countdown: countdown.get(),
                reset: reset.get(),
                count: count.get(),
                clamp: clamp.get(),
                wrap: wrap.get(),
                max: max.get(),
                min: min.get(),
            };
            state.step(&mut v);
            count.set(v.count);
        })
    }
}
halcomp_module!(pub MODULE, UpDownComp, "up/down counter with limits");

#[cfg(test)]
mod tests {
    use super::*;

    fn vars() -> UpDownVars {
        UpDownVars {
            max: i32::MAX,
            ..Default::default()
        }
    }

    /// Feeds (up, down, reset) triples, returning count per call.
    fn run(u: &mut UpDown, v: &mut UpDownVars, seq: &[(bool, bool, bool)]) -> Vec<i32> {
        seq.iter()
            .map(|&(up, down, reset)| {
                v.countup = up;
                v.countdown = down;
                v.reset = reset;
                u.step(v);
                v.count
            })
            .collect()
    }

    #[test]
    fn counts_rising_edges_but_not_on_the_first_call() {
        let mut u = UpDown::default();
        let mut v = vars();
        let seq = [
            (true, false, false),
            (false, false, false),
            (true, false, false),
            (true, false, false),
            (false, true, false),
            (true, true, false),
        ];
        assert_eq!(run(&mut u, &mut v, &seq), [0, 0, 1, 1, 0, 1]);
    }

    #[test]
    fn reset_is_a_level() {
        let mut u = UpDown::default();
        let mut v = vars();
        let seq = [
            (false, false, false),
            (true, false, false),
            (false, false, true),
            (true, false, true),
            (false, false, false),
        ];
        assert_eq!(run(&mut u, &mut v, &seq), [0, 1, 0, 0, 0]);
    }

    #[test]
    fn unlimited_count_wraps_at_s32_limits() {
        let mut u = UpDown::default();
        let mut v = UpDownVars {
            count: i32::MAX,
            ..vars()
        };
        run(
            &mut u,
            &mut v,
            &[(false, false, false), (true, false, false)],
        );
        assert_eq!(v.count, i32::MIN);
        let mut v = UpDownVars {
            count: i32::MIN,
            min: i32::MIN,
            ..vars()
        };
        let mut u = UpDown::default();
        run(
            &mut u,
            &mut v,
            &[(false, false, false), (false, true, false)],
        );
        assert_eq!(v.count, i32::MAX);
    }

    #[test]
    fn clamp_and_wrap() {
        let up = (true, false, false);
        let idle = (false, false, false);
        let down = (false, true, false);
        let mut u = UpDown::default();
        let mut v = UpDownVars {
            clamp: true,
            min: -1,
            max: 1,
            ..vars()
        };
        let r = run(
            &mut u,
            &mut v,
            &[
                idle, up, idle, up, idle, up, idle, down, idle, down, idle, down, idle, down,
            ],
        );
        assert_eq!(r, [0, 1, 1, 1, 1, 1, 1, 0, 0, -1, -1, -1, -1, -1]);
        let mut u = UpDown::default();
        let mut v = UpDownVars {
            wrap: true,
            clamp: true,
            min: 2,
            max: 4,
            ..vars()
        };
        // First call: 0 < min wraps to max.
        let r = run(
            &mut u,
            &mut v,
            &[idle, up, idle, down, idle, down, idle, down],
        );
        assert_eq!(r, [4, 2, 2, 4, 4, 3, 3, 2]);
    }

    #[test]
    fn reset_with_positive_min_yields_min_or_max() {
        let mut u = UpDown::default();
        let mut v = UpDownVars {
            clamp: true,
            min: 3,
            max: 9,
            count: 5,
            reset: true,
            ..vars()
        };
        u.step(&mut v);
        assert_eq!(v.count, 3);
        let mut v = UpDownVars { wrap: true, ..v };
        u.step(&mut v);
        assert_eq!(v.count, 9);
    }
}
