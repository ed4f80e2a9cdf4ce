//! `xhc_hb04_util`: helpers for the XHC-HB04 pendant: one start/pause
//! button turned into halui's pause, resume and run (by the program
//! state), four low-pass filters on integer inputs, and a divider.

use hal_core::{In, Out, Pin, Result};

use crate::cmath::f64_to_i32;
use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The program state the button acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ProgramState {
    /// Pin `is-paused`.
    pub is_paused: bool,
    /// Pin `is-idle`.
    pub is_idle: bool,
    /// Pin `is-running`.
    pub is_running: bool,
}

/// The start/pause button logic; outputs (pause, run, resume).
#[derive(Debug, Clone, Default)]
pub struct StartPause {
    old: bool,
}

impl StartPause {
    /// One call: the new outputs, or `None` when they stay (the button
    /// did not change, or it was pressed with no program state set).
    pub fn step(&mut self, button: bool, s: ProgramState) -> Option<(bool, bool, bool)> {
        if self.old == button {
            return None;
        }
        self.old = button;
        if !button {
            return Some((false, false, false));
        }
        let mut out = None;
        if s.is_paused {
            out = Some((false, false, true));
        }
        if s.is_running {
            out = Some((true, false, false));
        }
        if s.is_idle {
            out = Some((false, true, false));
        }
        out
    }
}

/// One integer low-pass filter step: the new filter value and output.
pub fn ilowpass(value: f64, input: i32, coef: f64, scale: f64) -> (f64, i32) {
    let c = if coef.abs() < 1.0 { coef.abs() } else { 1.0 };
    let v = value + (f64::from(input) - value) * c;
    (v, f64_to_i32((v * scale - 0.5).ceil()))
}

/// One filter's pins.
struct Filter {
    input: Pin<i32, In>,
    out: Pin<i32, Out>,
    scale: Pin<f64, In>,
    coef: Pin<f64, In>,
}

/// The `xhc_hb04_util` component.
pub struct XhcHb04Util;
impl HalComp for XhcHb04Util {
    const NAME: &'static str = "xhc_hb04_util";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let start_or_pause = inst.pin_in::<bool>("start-or-pause")?;
        let is_paused = inst.pin_in::<bool>("is-paused")?;
        let is_idle = inst.pin_in::<bool>("is-idle")?;
        let is_running = inst.pin_in::<bool>("is-running")?;
        let pause = inst.pin_out::<bool>("pause")?;
        let resume = inst.pin_out::<bool>("resume")?;
        let run = inst.pin_out::<bool>("run")?;
        let ins: Vec<Pin<i32, In>> = (0..4)
            .map(|i| inst.pin_in(&format!("in{i}")))
            .collect::<Result<_>>()?;
        let outs: Vec<Pin<i32, Out>> = (0..4)
            .map(|i| inst.pin_out(&format!("out{i}")))
            .collect::<Result<_>>()?;
        let scales: Vec<Pin<f64, In>> = (0..4)
            .map(|i| inst.pin_in_init(&format!("scale{i}"), 1.0))
            .collect::<Result<_>>()?;
        let coefs: Vec<Pin<f64, In>> = (0..4)
            .map(|i| inst.pin_in_init(&format!("coef{i}"), 1.0))
            .collect::<Result<_>>()?;
        let filters: Vec<Filter> = ins
            .into_iter()
            .zip(outs)
            .zip(scales.into_iter().zip(coefs))
            .map(|((input, out), (scale, coef))| Filter {
                input,
                out,
                scale,
                coef,
            })
            .collect();
        let divide_in = inst.pin_in::<f64>("divide-by-k-in")?;
        let divide_out = inst.pin_out::<f64>("divide-by-k-out")?;
        let k = inst.pin_in_init::<f64>("k", 1.0)?;
        let mut values = [0.0f64; 4];
        let mut button = StartPause::default();
        inst.funct("_", true, move |_| {
            let kv = k.get();
            divide_out.set(if kv == 0.0 {
                1e99
            } else {
                divide_in.get() / kv
            });
            for (value, f) in values.iter_mut().zip(&filters) {
                let (v, o) = ilowpass(*value, f.input.get(), f.coef.get(), f.scale.get());
                *value = v;
                f.out.set(o);
            }
            let s = ProgramState {
                is_paused: is_paused.get(),
                is_idle: is_idle.get(),
                is_running: is_running.get(),
            };
            if let Some((p, r, rs)) = button.step(start_or_pause.get(), s) {
                pause.set(p);
                run.set(r);
                resume.set(rs);
            }
        })
    }
}
halcomp_module!(pub MODULE, XhcHb04Util, "xhc-hb04 convenience utility");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float, S32};

    #[test]
    fn button_acts_by_program_state() {
        let mut b = StartPause::default();
        let idle = ProgramState {
            is_idle: true,
            ..Default::default()
        };
        assert_eq!(b.step(true, idle), Some((false, true, false)), "run");
        assert_eq!(b.step(true, idle), None, "held: nothing new");
        assert_eq!(b.step(false, idle), Some((false, false, false)));
        let running = ProgramState {
            is_running: true,
            ..Default::default()
        };
        assert_eq!(b.step(true, running), Some((true, false, false)), "pause");
        b.step(false, running);
        let paused = ProgramState {
            is_paused: true,
            ..Default::default()
        };
        assert_eq!(b.step(true, paused), Some((false, false, true)), "resume");
    }

    #[test]
    fn filters_round_half_down() {
        assert_eq!(ilowpass(0.0, 10, 1.0, 1.0), (10.0, 10));
        assert_eq!(ilowpass(0.0, 10, 0.25, 1.0), (2.5, 2), "ceil(x - 0.5)");
        assert_eq!(ilowpass(0.0, 10, 0.26, 1.0).1, 3);
        assert_eq!(
            ilowpass(0.0, 10, -5.0, 0.1),
            (10.0, 1),
            "|coef| capped at 1"
        );
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("xhc-util");
        h.load(&MODULE, &[]).unwrap();
        let mut want: Vec<String> = [
            "start-or-pause bit in 0",
            "is-paused bit in 0",
            "is-idle bit in 0",
            "is-running bit in 0",
            "pause bit out 0",
            "resume bit out 0",
            "run bit out 0",
            "divide-by-k-in float in 0",
            "divide-by-k-out float out 0",
            "k float in 1",
        ]
        .map(String::from)
        .to_vec();
        for i in 0..4 {
            want.push(format!("in{i} s32 in 0"));
            want.push(format!("out{i} s32 out 0"));
            want.push(format!("scale{i} float in 1"));
            want.push(format!("coef{i} float in 1"));
        }
        let want: Vec<&str> = want.iter().map(String::as_str).collect();
        h.check_pins("xhc-hb04-util.0", &want);
        h.thread(&["xhc-hb04-util.0"]);
        h.set("xhc-hb04-util.0.k", Float(4.0));
        h.expect(
            &[("xhc-hb04-util.0.divide-by-k-in", Float(2.0))],
            "xhc-hb04-util.0.divide-by-k-out",
            Float(0.5),
        );
        h.expect(
            &[("xhc-hb04-util.0.in2", S32(7))],
            "xhc-hb04-util.0.out2",
            S32(7),
        );
        h.set("xhc-hb04-util.0.is-idle", Bit(true));
        h.expect(
            &[("xhc-hb04-util.0.start-or-pause", Bit(true))],
            "xhc-hb04-util.0.run",
            Bit(true),
        );
    }
}
