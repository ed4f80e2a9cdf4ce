//! The IEC 61131-3 timers `ton` (delays a rising edge), `tof` (delays a
//! falling edge) and `tp` (a pulse of fixed length on a rising edge).
//! Each has `in`, `q`, the elapsed time `et` and the time param `pt`, in
//! seconds; a negative `pt` or `et` is reset to 0 with a warning.

use hal_core::{In, Out, Param, Pin, Result, Rw};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;
use crate::notice::Notice;

/// Which timer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// On delay: `q` follows `in` going TRUE after `pt`, at once going
    /// FALSE.
    On,
    /// Off delay: `q` follows `in` going FALSE after `pt`, at once going
    /// TRUE.
    Off,
    /// Pulse: `q` is TRUE for `pt` after a rising edge of `in`.
    Pulse,
}

/// The pin and param values one call reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TimerVars {
    /// Pin `in`.
    pub input: bool,
    /// Pin `q` (read back).
    pub q: bool,
    /// Pin `et` (read back).
    pub et: f64,
    /// Param `pt`.
    pub pt: f64,
}

/// What one call wants reported.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Warnings {
    /// `pt` was negative and has been reset.
    pub negative_pt: bool,
    /// `et` was negative and has been reset.
    pub negative_et: bool,
}

/// One timer's state (only `tp` remembers its input).
#[derive(Debug, Clone, Default)]
pub struct IecTimer {
    in_old: bool,
}

impl IecTimer {
    /// One call of timer `kind`, `fperiod` seconds after the last.
    pub fn step(&mut self, kind: Kind, v: &mut TimerVars, fperiod: f64) -> Warnings {
        let w = Warnings {
            negative_pt: v.pt < 0.0,
            negative_et: v.et < 0.0,
        };
        if w.negative_pt {
            v.pt = 0.0;
        }
        if w.negative_et {
            v.et = 0.0;
        }
        match kind {
            Kind::On => {
                if v.input {
                    if v.et >= v.pt {
                        v.q = true;
                    } else {
                        v.et += fperiod;
                    }
                } else {
                    v.et = 0.0;
                    v.q = false;
                }
            }
            Kind::Off => {
                if v.input {
                    v.q = true;
                    v.et = 0.0;
                } else if v.et >= v.pt {
                    v.q = false;
                } else {
                    v.et += fperiod;
                }
            }
            Kind::Pulse => {
                if (v.input && !self.in_old) || v.q {
                    if v.et < v.pt {
                        v.q = true;
                        v.et += fperiod;
                    } else {
                        v.q = false;
                    }
                } else {
                    v.et = 0.0;
                    v.q = false;
                }
                self.in_old = v.input;
            }
        }
        w
    }
}

/// Builds one timer instance; `texts` are its two warnings.
fn timer(inst: &mut Inst<'_, '_>, kind: Kind, texts: &'static [&'static str]) -> Result<()> {
    let input: Pin<bool, In> = inst.pin_in("in")?;
    let q: Pin<bool, Out> = inst.pin_out("q")?;
    let et: Pin<f64, Out> = inst.pin_out("et")?;
    let pt: Param<f64, Rw> = inst.param_rw("pt", 0.0)?;
    let notice = Notice::new(texts);
    let mut t = IecTimer::default();
    inst.funct("_", true, move |ctx| {
        let old = TimerVars {
            input: input.get(),
            q: q.get(),
            et: et.get(),
            pt: pt.get(),
        };
        let mut v = old;
        let w = t.step(kind, &mut v, ctx.fperiod());
        if w.negative_pt {
            pt.set(v.pt);
            notice.post(0);
        }
        if w.negative_et {
            notice.post(1);
        }
        if v.et != old.et || w.negative_et {
            et.set(v.et);
        }
        if v.q != old.q {
            q.set(v.q);
        }
    })
}

/// The `ton` component.
pub struct Ton;
impl HalComp for Ton {
    const NAME: &'static str = "ton";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        static TEXTS: &[&str] = &[
            "ton: Delay time must be positive, resetting to 0\n",
            "ton: Elapsed time rolled over, resetting to 0\n",
        ];
        timer(inst, Kind::On, TEXTS)
    }
}
halcomp_module!(pub TON, Ton, "IEC TON timer - delay rising edge on a signal");

/// The `tof` component.
pub struct Tof;
impl HalComp for Tof {
    const NAME: &'static str = "tof";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        static TEXTS: &[&str] = &[
            "tof: Delay time must be positive, resetting to 0\n",
            "tof: Elapsed time rolled over, resetting to 0\n",
        ];
        timer(inst, Kind::Off, TEXTS)
    }
}
halcomp_module!(pub TOF, Tof, "IEC TOF timer - delay falling edge on a signal");

/// The `tp` component.
pub struct Tp;
impl HalComp for Tp {
    const NAME: &'static str = "tp";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        static TEXTS: &[&str] = &[
            "tp: Pulse time must be positive, resetting to 0\n",
            "tp: Elapsed time rolled over, resetting to 0\n",
        ];
        timer(inst, Kind::Pulse, TEXTS)
    }
}
halcomp_module!(
    pub TP,
    Tp,
    "IEC TP timer - generate a high pulse of defined duration on rising edge"
);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    /// `q` over a sequence of inputs, 1 ms calls, `pt` 2.5 ms.
    fn trace(kind: Kind, inputs: &[u8]) -> String {
        let mut t = IecTimer::default();
        let mut v = TimerVars {
            pt: 0.0025,
            ..Default::default()
        };
        inputs
            .iter()
            .map(|&i| {
                v.input = i != 0;
                t.step(kind, &mut v, 0.001);
                if v.q {
                    '1'
                } else {
                    '0'
                }
            })
            .collect()
    }

    #[test]
    fn ton_delays_the_rising_edge() {
        // et reaches 3 ms on the third call; q on the fourth.
        assert_eq!(trace(Kind::On, &[1, 1, 1, 1, 1, 0, 1]), "0001100");
    }

    #[test]
    fn tof_delays_the_falling_edge() {
        assert_eq!(trace(Kind::Off, &[1, 0, 0, 0, 0, 0, 1]), "1111001");
    }

    #[test]
    fn tp_makes_a_pulse_that_ignores_the_input_meanwhile() {
        assert_eq!(trace(Kind::Pulse, &[1, 0, 1, 0, 0, 0, 0]), "1110000");
        // A held input does not retrigger.
        assert_eq!(trace(Kind::Pulse, &[1, 1, 1, 1, 1, 1, 1]), "1110000");
    }

    #[test]
    fn negative_times_are_reset_and_reported() {
        let mut t = IecTimer::default();
        let mut v = TimerVars {
            pt: -1.0,
            et: -2.0,
            ..Default::default()
        };
        let w = t.step(Kind::On, &mut v, 0.001);
        assert!(w.negative_pt && w.negative_et);
        assert_eq!((v.pt, v.et), (0.0, 0.0));
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("iec");
        h.load(&TON, &[]).unwrap();
        h.load(&TOF, &[]).unwrap();
        h.load(&TP, &["names=pulse"]).unwrap();
        for p in ["ton.0", "tof.0", "pulse"] {
            h.check_pins(p, &["in bit in 0", "q bit out 0", "et float out 0"]);
            h.check_params(p, &["pt float rw 0"]);
        }
        h.thread(&["ton.0", "tof.0"]);
        h.setp("ton.0.pt", Float(1.0));
        h.expect(&[("ton.0.in", Bit(true))], "ton.0.q", Bit(false));
        h.expect(&[("tof.0.in", Bit(true))], "tof.0.q", Bit(true));
        h.setp("tof.0.pt", Float(-3.0));
        h.expect(&[("tof.0.in", Bit(false))], "tof.0.q", Bit(false));
        assert_eq!(h.getp("tof.0.pt"), Float(0.0));
    }
}
