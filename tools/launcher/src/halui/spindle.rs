//! halui's spindle pins, with LinuxCNC 2.9's names (`halui.spindle.N.*`,
//! N from 0 to `[TRAJ]SPINDLES` − 1): the buttons `start`, `stop`,
//! `forward`, `reverse`, `increase`, `decrease`, `brake-on`, `brake-off`
//! as task's `spindle` requests; the override's `count-enable`, `counts`,
//! `scale`, `direct-value`, `increase`, `decrease` and `reset` (back to
//! one) as `spindle N override`; and the status pins `is-on`, `runs-forward`,
//! `runs-backward`, `brake-is-on`, `override.value` from motion's
//! snapshot.

use hal_core::{Component, In, Out, Pin};
use hal_lang::ini::Ini;

use super::logic::{Edges, OverrideCounter, OverrideInputs};
use crate::error::LaunchError;

/// What a spindle button asks task for (the words after `spindle N`).
const BUTTONS: [(&str, &[&str]); 8] = [
    ("start", &["forward"]),
    ("stop", &["off"]),
    ("forward", &["forward"]),
    ("reverse", &["reverse"]),
    ("increase", &["increase"]),
    ("decrease", &["decrease"]),
    ("brake-on", &["brake", "on"]),
    ("brake-off", &["brake", "off"]),
];

/// `[TRAJ]SPINDLES` (default 1; 1 to 8).
pub fn count(ini: &Ini) -> Result<usize, LaunchError> {
    let n = ini.int("TRAJ", "SPINDLES")?.unwrap_or(1);
    Ok(n.clamp(1, motion::sizes::MAX_SPINDLES as i64) as usize)
}

/// One spindle's pins.
pub struct SpindlePins {
    buttons: Vec<Pin<bool, In>>,
    count_enable: Pin<bool, In>,
    counts: Pin<i32, In>,
    scale: Pin<f64, In>,
    direct_value: Pin<bool, In>,
    increase: Pin<bool, In>,
    decrease: Pin<bool, In>,
    reset: Pin<bool, In>,
    value: Pin<f64, Out>,
    is_on: Pin<bool, Out>,
    runs_forward: Pin<bool, Out>,
    runs_backward: Pin<bool, Out>,
    brake_is_on: Pin<bool, Out>,
}

impl SpindlePins {
    /// Creates spindle `n`'s pins on halui's component.
    pub fn new(comp: &Component, n: usize) -> hal_core::Result<SpindlePins> {
        let p = |item: &str| format!("halui.spindle.{n}.{item}");
        let mut buttons = Vec::with_capacity(BUTTONS.len());
        for (name, _) in BUTTONS {
            buttons.push(comp.pin(&p(name))?);
        }
        Ok(SpindlePins {
            buttons,
            count_enable: comp.pin_init(&p("override.count-enable"), true)?,
            counts: comp.pin(&p("override.counts"))?,
            // 0.1 at start, as in LinuxCNC.
            scale: comp.pin_init(&p("override.scale"), 0.1)?,
            direct_value: comp.pin(&p("override.direct-value"))?,
            increase: comp.pin(&p("override.increase"))?,
            decrease: comp.pin(&p("override.decrease"))?,
            reset: comp.pin(&p("override.reset"))?,
            value: comp.pin_init(&p("override.value"), 1.0)?,
            is_on: comp.pin(&p("is-on"))?,
            runs_forward: comp.pin(&p("runs-forward"))?,
            runs_backward: comp.pin(&p("runs-backward"))?,
            brake_is_on: comp.pin(&p("brake-is-on"))?,
        })
    }

    /// The buttons' values: the eight of [`BUTTONS`], then the override's
    /// increase, decrease and reset.
    fn pressed(&self) -> Vec<bool> {
        let mut v: Vec<bool> = self.buttons.iter().map(Pin::get).collect();
        v.push(self.increase.get());
        v.push(self.decrease.get());
        v.push(self.reset.get());
        v
    }

    fn override_inputs(&self) -> OverrideInputs {
        OverrideInputs {
            count_enable: self.count_enable.get(),
            counts: self.counts.get(),
            scale: self.scale.get(),
            direct_value: self.direct_value.get(),
        }
    }

    /// The status pins from motion's view of this spindle.
    fn write(&self, s: &motion::channel::SpindleState) {
        let turning = s.on && s.speed != 0.0;
        self.is_on.set(s.on);
        self.runs_forward.set(turning && s.speed > 0.0);
        self.runs_backward.set(turning && s.speed < 0.0);
        self.brake_is_on.set(s.brake);
        self.value.set(s.scale);
    }
}

/// What halui keeps between cycles for each spindle.
#[derive(Debug, Default)]
pub struct SpindleHalui {
    edges: Vec<Edges>,
    counters: Vec<OverrideCounter>,
}

impl SpindleHalui {
    /// One cycle: status pins from `motion`; button edges and override
    /// counts become the requests `ask` sends (only while task answers,
    /// `task_up`).
    pub fn cycle(
        &mut self,
        pins: &[SpindlePins],
        motion: Option<&motion::MotionStatus>,
        task_up: bool,
        mut ask: impl FnMut(&[&str]) -> bool,
    ) {
        self.edges.resize_with(pins.len(), Edges::default);
        self.counters
            .resize_with(pins.len(), OverrideCounter::default);
        for (n, p) in pins.iter().enumerate() {
            let state = motion.and_then(|m| m.spindles.get(n));
            if let Some(s) = state {
                p.write(s);
            }
            let changes = self.edges[n].changes(&p.pressed());
            let inputs = p.override_inputs();
            let current = state.map_or(1.0, |s| s.scale);
            let counted = self.counters[n].target(&inputs, current);
            if !task_up {
                continue;
            }
            let spindle = n.to_string();
            for (i, now) in changes {
                if !now {
                    continue;
                }
                match BUTTONS.get(i) {
                    Some((_, words)) => {
                        let mut w = vec!["spindle", spindle.as_str()];
                        w.extend_from_slice(words);
                        ask(&w);
                    }
                    None => {
                        let v = match i - BUTTONS.len() {
                            0 => current + inputs.scale,
                            1 => current - inputs.scale,
                            _ => 1.0,
                        };
                        let v = v.max(0.0).to_string();
                        ask(&["spindle", &spindle, "override", &v]);
                    }
                }
            }
            if let Some(v) = counted {
                let v = v.max(0.0).to_string();
                ask(&["spindle", &spindle, "override", &v]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spindle_count_comes_from_traj_spindles() {
        assert_eq!(count(&Ini::parse("")).unwrap(), 1);
        assert_eq!(count(&Ini::parse("[TRAJ]\nSPINDLES = 2\n")).unwrap(), 2);
        assert_eq!(count(&Ini::parse("[TRAJ]\nSPINDLES = 20\n")).unwrap(), 8);
        assert!(count(&Ini::parse("[TRAJ]\nSPINDLES = two\n")).is_err());
    }
}
