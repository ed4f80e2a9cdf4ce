//! `multiclick`: detects single, double, triple and quadruple clicks on
//! `in`. A click is a press held at most `max-hold-ns`; clicks of one
//! group are at most `max-space-ns` apart. `<n>-click` pulses (for
//! `output-hold-ns`) as soon as the n-th click ends; `<n>-click-only`
//! once the space after it has run out with no further click. A press
//! held too long cancels the group until released.

use hal_core::{Out, Pin, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The state numbers (the `state` pin). Click n (1..4) pressed is state
/// `2n - 1`, released `2n`.
pub mod states {
    /// Waiting for a press.
    pub const IDLE: i32 = 0;
    /// The fourth click has ended.
    pub const FOURTH_CLICK: i32 = 8;
    /// Pressed too long (or a fifth press): waiting for release.
    pub const HELD_TOO_LONG: i32 = 9;
}
use states::*;

/// The params.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ClickParams {
    /// `invert-input`: clicks start with falling edges.
    pub invert_input: bool,
    /// `max-hold-ns`.
    pub max_hold_ns: u32,
    /// `max-space-ns`.
    pub max_space_ns: u32,
    /// `output-hold-ns`.
    pub output_hold_ns: u32,
}

impl Default for ClickParams {
    /// The params' defaults.
    fn default() -> Self {
        ClickParams {
            invert_input: false,
            max_hold_ns: 250_000_000,
            max_space_ns: 250_000_000,
            output_hold_ns: 100_000_000,
        }
    }
}

/// The eight outputs: `[n][0]` is the (n+1)-click pin, `[n][1]` the
/// (n+1)-click-only pin.
pub type Outputs = [[bool; 2]; 4];

/// The detector's state.
#[derive(Debug, Clone, Default)]
pub struct Multiclick {
    state: i32,
    timer: u32,
    timeout: u32,
    /// Time left on each output pulse, as `Outputs`.
    hold: [[u32; 2]; 4],
}

impl Multiclick {
    /// The state number.
    pub fn state(&self) -> i32 {
        self.state
    }

    /// One call after `period` ns; updates `out`.
    pub fn step(&mut self, input: bool, p: &ClickParams, period: i64, out: &mut Outputs) {
        let pressed = input != p.invert_input;
        let period32 = period as u32;
        if self.state != IDLE {
            self.timer = self.timer.wrapping_add(period32);
        }
        for (hold, o) in self.hold.iter_mut().flatten().zip(out.iter_mut().flatten()) {
            if *hold > 0 {
                if i64::from(*hold) > period {
                    *hold -= period32;
                } else {
                    *hold = 0;
                    *o = false;
                }
            }
        }
        match self.state {
            IDLE | 2 | 4 | 6 if pressed => {
                self.state += 1;
                self.timer = 0;
                self.timeout = p.max_hold_ns;
            }
            1 | 3 | 5 | 7 if !pressed => {
                let n = (self.state / 2) as usize;
                self.state += 1;
                self.timer = 0;
                self.timeout = p.max_space_ns;
                out[n][0] = true;
                self.hold[n][0] = p.output_hold_ns;
            }
            FOURTH_CLICK if pressed => self.state = HELD_TOO_LONG,
            HELD_TOO_LONG if !pressed => self.state = IDLE,
            0..=9 => {}
            _ => self.state = IDLE,
        }
        if self.state != IDLE && self.state != HELD_TOO_LONG && self.timer > self.timeout {
            if pressed {
                self.state = HELD_TOO_LONG;
            } else {
                // The space after click n ran out: it was exactly n.
                if self.state % 2 == 0 {
                    let n = (self.state / 2 - 1) as usize;
                    out[n][1] = true;
                    self.hold[n][1] = p.output_hold_ns;
                }
                self.state = IDLE;
            }
        }
    }
}

/// The `multiclick` component.
pub struct MulticlickComp;
impl HalComp for MulticlickComp {
    const NAME: &'static str = "multiclick";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<bool>("in")?;
        let mut pins: Vec<[Pin<bool, Out>; 2]> = Vec::with_capacity(4);
        for n in ["single", "double", "triple", "quadruple"] {
            pins.push([
                inst.pin_out(&format!("{n}-click"))?,
                inst.pin_out(&format!("{n}-click-only"))?,
            ]);
        }
        let state = inst.pin_out::<i32>("state")?;
        let d = ClickParams::default();
        let invert_input = inst.param_rw::<bool>("invert-input", d.invert_input)?;
        let max_hold_ns = inst.param_rw::<u32>("max-hold-ns", d.max_hold_ns)?;
        let max_space_ns = inst.param_rw::<u32>("max-space-ns", d.max_space_ns)?;
        let output_hold_ns = inst.param_rw::<u32>("output-hold-ns", d.output_hold_ns)?;
        let mut m = Multiclick::default();
        inst.funct("_", false, move |ctx| {
            let p = ClickParams {
                invert_input: invert_input.get(),
                max_hold_ns: max_hold_ns.get(),
                max_space_ns: max_space_ns.get(),
                output_hold_ns: output_hold_ns.get(),
            };
            let old: Outputs = std::array::from_fn(|n| [pins[n][0].get(), pins[n][1].get()]);
            let mut out = old;
            m.step(input.get(), &p, ctx.period(), &mut out);
            for n in 0..4 {
                for k in 0..2 {
                    if out[n][k] != old[n][k] {
                        pins[n][k].set(out[n][k]);
                    }
                }
            }
            state.set(m.state());
        })
    }
}
halcomp_module!(pub MODULE, MulticlickComp, "single-, double-, triple-, and quadruple-click detector");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, S32};

    /// Runs a sequence of (input, calls) at 10 ms per call and returns
    /// the calls at which each output first went TRUE.
    fn run(seq: &[(bool, usize)]) -> [[Option<usize>; 2]; 4] {
        let mut m = Multiclick::default();
        let p = ClickParams::default();
        let mut out: Outputs = Default::default();
        let mut first = [[None; 2]; 4];
        let mut call = 0;
        for &(input, calls) in seq {
            for _ in 0..calls {
                m.step(input, &p, 10_000_000, &mut out);
                for n in 0..4 {
                    for k in 0..2 {
                        if out[n][k] && first[n][k].is_none() {
                            first[n][k] = Some(call);
                        }
                    }
                }
                call += 1;
            }
        }
        first
    }

    #[test]
    fn double_click_and_its_only_pulse() {
        let f = run(&[(true, 5), (false, 5), (true, 5), (false, 40)]);
        assert_eq!(f[0][0], Some(5), "single at the first release");
        assert_eq!(f[1][0], Some(15), "double at the second release");
        assert_eq!(f[0][1], None, "a second click followed the first");
        // 250 ms of space after the release at call 15: call 15 + 26.
        assert_eq!(f[1][1], Some(41));
        assert_eq!(f[2][0], None);
    }

    #[test]
    fn a_long_press_is_no_click() {
        let f = run(&[(true, 40), (false, 40)]);
        assert_eq!(f, [[None; 2]; 4]);
    }

    #[test]
    fn four_clicks_then_a_fifth_press_is_ignored() {
        let seq: Vec<(bool, usize)> = (0..5).flat_map(|_| [(true, 3), (false, 3)]).collect();
        let f = run(&seq);
        assert!(f.iter().all(|o| o[0].is_some()));
        assert_eq!(
            f[3][1], None,
            "the fifth press cancelled the quadruple-only"
        );
    }

    #[test]
    fn pulses_last_output_hold() {
        let mut m = Multiclick::default();
        let p = ClickParams::default();
        let mut out: Outputs = Default::default();
        m.step(true, &p, 10_000_000, &mut out);
        m.step(false, &p, 10_000_000, &mut out);
        assert!(out[0][0]);
        let mut calls = 0;
        while out[0][0] {
            m.step(false, &p, 10_000_000, &mut out);
            calls += 1;
        }
        assert_eq!(calls, 10, "100 ms at 10 ms per call");
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("multiclick");
        h.load(&MODULE, &[]).unwrap();
        let mut want = vec!["in bit in 0".to_string(), "state s32 out 0".to_string()];
        for n in ["single", "double", "triple", "quadruple"] {
            want.push(format!("{n}-click bit out 0"));
            want.push(format!("{n}-click-only bit out 0"));
        }
        let want: Vec<&str> = want.iter().map(String::as_str).collect();
        h.check_pins("multiclick.0", &want);
        h.check_params(
            "multiclick.0",
            &[
                "invert-input bit rw 0",
                "max-hold-ns u32 rw 250000000",
                "max-space-ns u32 rw 250000000",
                "output-hold-ns u32 rw 100000000",
            ],
        );
        h.thread(&["multiclick.0"]);
        h.expect(
            &[("multiclick.0.in", Bit(true))],
            "multiclick.0.state",
            S32(1),
        );
        h.expect(
            &[("multiclick.0.in", Bit(false))],
            "multiclick.0.single-click",
            Bit(true),
        );
    }
}
