//! `toggle` (a push button toggles `out`) and `toggle2nist` (a button or
//! switch drives separate on/off pulses for a device with an is-on
//! feedback).

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

use super::write_changed;

/// Debounce values outside 1..=10000 are replaced by this one.
pub const DEFAULT_DEBOUNCE: u32 = 2;

/// Whether a debounce count is accepted as is.
fn debounce_ok(d: u32) -> bool {
    (1..=10000).contains(&d)
}

/// The pin and param values one call of `toggle` reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ToggleVars {
    /// Pin `in`.
    pub input: bool,
    /// I/O pin `out`.
    pub out: bool,
    /// Param `debounce` (calls); rewritten to 2 when out of range.
    pub debounce: u32,
}

/// Per-instance state of `toggle`.
#[derive(Debug, Clone, Default)]
pub struct Toggle {
    /// Up/down integrator of `in`, 0..=debounce.
    cnt: i32,
    /// Whether the current press has already toggled `out`.
    debounced: bool,
}

impl Toggle {
    /// One call.
    pub fn step(&mut self, v: &mut ToggleVars) {
        if !debounce_ok(v.debounce) {
            v.debounce = DEFAULT_DEBOUNCE;
        }
        // d <= 10000, so it fits the int counter.
        let d = v.debounce as i32;
        if v.input {
            self.cnt = self.cnt.wrapping_add(1);
            if self.cnt >= d {
                self.cnt = d;
                if !self.debounced {
                    v.out = !v.out;
                }
                self.debounced = true;
            }
        } else {
            self.cnt = self.cnt.wrapping_sub(1);
            if self.cnt <= 0 {
                self.cnt = 0;
                self.debounced = false;
            }
        }
    }
}

/// The `toggle` component.
pub struct ToggleComp;
impl HalComp for ToggleComp {
    const NAME: &'static str = "toggle";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<bool>("in")?;
        let out = inst.pin_io::<bool>("out", false)?;
        let debounce = inst.param_rw::<u32>("debounce", DEFAULT_DEBOUNCE)?;
        let mut state = Toggle::default();
        inst.funct("_", false, move |_| {
            let old = ToggleVars {
                input: input.get(),
                out: out.get(),
                debounce: debounce.get(),
            };
            let mut v = old;
            state.step(&mut v);
            if v.debounce != old.debounce {
                debounce.set(v.debounce);
            }
            write_changed(&out, old.out, v.out);
        })
    }
}
halcomp_module!(pub TOGGLE, ToggleComp, "push-on, push-off from a momentary button");

/// The pin values one call of `toggle2nist` reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Toggle2nistVars {
    /// Pin `in`.
    pub input: bool,
    /// Pin `is-on`: the device's state.
    pub is_on: bool,
    /// Pin `debounce` (calls); out-of-range values act as 2.
    pub debounce: u32,
    /// Pin `max-pulse-length` (calls).
    pub max_pulse_length: u32,
    /// Pin `on` (read back).
    pub on: bool,
    /// Pin `off` (read back).
    pub off: bool,
}

/// Per-instance state of `toggle2nist` (reference-commit version, with
/// debounce and a maximum pulse length).
#[derive(Debug, Clone, Default)]
pub struct Toggle2nist {
    /// Calls `in` has been in its new state.
    cnt: u32,
    /// Free-running count of idle calls (see the quirk in `step`).
    pulse: u32,
    /// Debounced state of `in`.
    state: bool,
}

impl Toggle2nist {
    /// One call. A debounced rising edge of `in` while the device is off
    /// pulses `on`; a debounced falling edge while it is on pulses `off`.
    /// A pulse ends when `is-on` confirms it or when the idle counter
    /// passes `max-pulse-length`; that counter runs on every idle call
    /// and is not restarted by a new pulse, as in LinuxCNC.
    pub fn step(&mut self, v: &mut Toggle2nistVars) {
        let x = v.input;
        let ison = v.is_on;
        let d = if debounce_ok(v.debounce) {
            v.debounce
        } else {
            DEFAULT_DEBOUNCE
        };
        if x && !self.state {
            self.cnt = self.cnt.wrapping_add(1);
            if self.cnt >= d {
                if !ison {
                    v.on = true;
                    v.off = false;
                }
                self.state = true;
                self.cnt = 0;
            }
        } else if !x && self.state {
            self.cnt = self.cnt.wrapping_add(1);
            if self.cnt >= d {
                if ison {
                    v.on = false;
                    v.off = true;
                }
                self.state = false;
                self.cnt = 0;
            }
        } else if (!ison && v.off) || (ison && v.on) || self.pulse > v.max_pulse_length {
            v.on = false;
            v.off = false;
            self.cnt = 0;
            self.pulse = 0;
        } else {
            self.cnt = 0;
            self.pulse = self.pulse.wrapping_add(1);
        }
    }
}

/// The `toggle2nist` component.
pub struct Toggle2nistComp;
impl HalComp for Toggle2nistComp {
    const NAME: &'static str = "toggle2nist";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<bool>("in")?;
        let is_on = inst.pin_in::<bool>("is-on")?;
        let debounce = inst.pin_in_init::<u32>("debounce", DEFAULT_DEBOUNCE)?;
        let max_pulse_length = inst.pin_in_init::<u32>("max-pulse-length", 100)?;
        let on = inst.pin_out::<bool>("on")?;
        let off = inst.pin_out::<bool>("off")?;
        let mut state = Toggle2nist::default();
        inst.funct("_", false, move |_| {
            let old = Toggle2nistVars {
                input: input.get(),
                is_on: is_on.get(),
                debounce: debounce.get(),
                max_pulse_length: max_pulse_length.get(),
                on: on.get(),
                off: off.get(),
            };
            let mut v = old;
            state.step(&mut v);
            write_changed(&on, old.on, v.on);
            write_changed(&off, old.off, v.off);
        })
    }
}
halcomp_module!(
    pub TOGGLE2NIST,
    Toggle2nistComp,
    "toggle button to separate on/off pulses for devices with is-on feedback"
);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing;

    fn press(t: &mut Toggle, v: &mut ToggleVars, inputs: &[bool]) -> Vec<bool> {
        inputs
            .iter()
            .map(|&x| {
                v.input = x;
                t.step(v);
                v.out
            })
            .collect()
    }

    #[test]
    fn toggle_once_per_debounced_press() {
        let mut t = Toggle::default();
        let mut v = ToggleVars {
            debounce: 3,
            ..Default::default()
        };
        let r = press(
            &mut t,
            &mut v,
            &[true, true, true, true, true, false, false, false],
        );
        assert_eq!(r, [false, false, true, true, true, true, true, true]);
        let r = press(&mut t, &mut v, &[true, true, true]);
        assert_eq!(r, [true, true, false]);
    }

    #[test]
    fn toggle_integrates_rather_than_counting_consecutive_samples() {
        let mut t = Toggle::default();
        let mut v = ToggleVars {
            debounce: 3,
            ..Default::default()
        };
        // Up 2, down 1, up 2: reaches 3 on the last call.
        let r = press(&mut t, &mut v, &[true, true, false, true, true]);
        assert_eq!(r, [false, false, false, false, true]);
        // Released only partly: no re-arm, so no second toggle.
        let r = press(&mut t, &mut v, &[false, false, true, true, true]);
        assert_eq!(r, [true; 5]);
    }

    #[test]
    fn toggle_rewrites_out_of_range_debounce() {
        for bad in [0, 10001, u32::MAX] {
            let mut t = Toggle::default();
            let mut v = ToggleVars {
                debounce: bad,
                ..Default::default()
            };
            let r = press(&mut t, &mut v, &[true, true]);
            assert_eq!(v.debounce, 2);
            assert_eq!(r, [false, true]);
        }
        let mut v = ToggleVars {
            debounce: 10000,
            ..Default::default()
        };
        Toggle::default().step(&mut v);
        assert_eq!(v.debounce, 10000);
    }

    #[test]
    fn toggle_follows_external_writes_of_out() {
        let mut t = Toggle::default();
        let mut v = ToggleVars {
            debounce: 1,
            out: true,
            ..Default::default()
        };
        press(&mut t, &mut v, &[true]);
        assert!(!v.out);
    }

    fn t2n_vars() -> Toggle2nistVars {
        Toggle2nistVars {
            debounce: 2,
            max_pulse_length: 100,
            ..Default::default()
        }
    }

    #[test]
    fn toggle2nist_pulses_on_then_off_until_confirmed() {
        let mut t = Toggle2nist::default();
        let mut v = t2n_vars();
        v.input = true;
        t.step(&mut v);
        assert!(!v.on, "debounce 2: not yet");
        t.step(&mut v);
        assert!(v.on && !v.off);
        // Device reports on: the pulse ends.
        v.is_on = true;
        t.step(&mut v);
        assert!(!v.on && !v.off);
        v.input = false;
        t.step(&mut v);
        t.step(&mut v);
        assert!(!v.on && v.off);
        v.is_on = false;
        t.step(&mut v);
        assert!(!v.on && !v.off);
    }

    #[test]
    fn toggle2nist_ignores_rising_edge_while_on() {
        let mut t = Toggle2nist::default();
        let mut v = Toggle2nistVars {
            is_on: true,
            ..t2n_vars()
        };
        v.input = true;
        t.step(&mut v);
        t.step(&mut v);
        assert!(!v.on && !v.off);
    }

    #[test]
    fn toggle2nist_bad_debounce_acts_as_two_without_rewriting() {
        let mut t = Toggle2nist::default();
        let mut v = Toggle2nistVars {
            debounce: 0,
            ..t2n_vars()
        };
        v.input = true;
        t.step(&mut v);
        assert!(!v.on);
        t.step(&mut v);
        assert!(v.on);
        assert_eq!(v.debounce, 0);
    }

    #[test]
    fn toggle2nist_max_pulse_counts_idle_calls() {
        let mut t = Toggle2nist::default();
        let mut v = Toggle2nistVars {
            max_pulse_length: 3,
            debounce: 1,
            ..t2n_vars()
        };
        // Idle calls advance the free-running counter to 2.
        t.step(&mut v);
        t.step(&mut v);
        v.input = true;
        t.step(&mut v);
        assert!(v.on);
        // Device never confirms: counter 3, then 4 > 3 ends the pulse.
        let mut lengths = 1;
        for _ in 0..10 {
            t.step(&mut v);
            if !v.on {
                break;
            }
            lengths += 1;
        }
        assert_eq!(lengths, 3);
    }

    #[test]
    fn both_load_with_their_items() {
        let host = testing::host();
        testing::load(&host, &TOGGLE, &["count=2"]).unwrap();
        testing::load(&host, &TOGGLE2NIST, &[]).unwrap();
        let pins = testing::pin_names(&host);
        for p in [
            "toggle.1.in",
            "toggle.1.out",
            "toggle2nist.0.debounce",
            "toggle2nist.0.max-pulse-length",
            "toggle2nist.0.is-on",
            "toggle2nist.0.on",
            "toggle2nist.0.off",
        ] {
            assert!(pins.contains(&p.to_string()), "{p}");
        }
        assert!(testing::param_names(&host).contains(&"toggle.0.debounce".to_string()));
    }
}
