//! Analog jogging, as LinuxCNC's halui has it: `halui.joint.N.analog`
//! and `halui.axis.L.analog` (a joystick, typically -1 to 1) jog at that
//! fraction of the jog speed while outside `halui.joint.jog-deadband`
//! (`halui.axis.jog-deadband`, 0.2 at start as in LinuxCNC); back inside
//! the deadband, the jog stops.

use hal_core::{Component, In, Pin};

use super::logic::Action;
use super::pins::Layout;
use crate::task_manual::Jogged;

/// The deadband both start with, as in LinuxCNC.
const DEFAULT_DEADBAND: f64 = 0.2;

/// The analog jog pins.
pub struct AnalogPins {
    inputs: Vec<(Jogged, Pin<f64, In>)>,
    joint_deadband: Pin<f64, In>,
    axis_deadband: Pin<f64, In>,
}

/// One analog input as read: what it jogs, its value, its deadband and
/// the jog speed (units per minute) it scales.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalogReading {
    /// The joint or axis.
    pub what: Jogged,
    /// The input's value.
    pub value: f64,
    /// Values this far from 0 or nearer do not jog.
    pub deadband: f64,
    /// `halui.joint.jog-speed` or `halui.axis.jog-speed`.
    pub speed: f64,
}

impl AnalogPins {
    /// Creates `halui.joint.N.analog`, `halui.axis.L.analog` and the two
    /// deadbands.
    pub fn create(comp: &Component, layout: &Layout<'_>) -> hal_core::Result<AnalogPins> {
        let mut inputs = Vec::new();
        for j in 0..layout.joints {
            let what = Jogged::Joint(i32::try_from(j).unwrap_or(i32::MAX));
            inputs.push((what, comp.pin(&format!("halui.joint.{j}.analog"))?));
        }
        for &(axis, letter) in layout.axes {
            let what = Jogged::Axis(i32::try_from(axis).unwrap_or(i32::MAX));
            inputs.push((what, comp.pin(&format!("halui.axis.{letter}.analog"))?));
        }
        Ok(AnalogPins {
            inputs,
            joint_deadband: comp.pin_init("halui.joint.jog-deadband", DEFAULT_DEADBAND)?,
            axis_deadband: comp.pin_init("halui.axis.jog-deadband", DEFAULT_DEADBAND)?,
        })
    }

    /// Every input as read now; `speed` gives the jog speed of a joint or
    /// an axis.
    pub fn readings(&self, speed: impl Fn(Jogged) -> f64) -> Vec<AnalogReading> {
        self.inputs
            .iter()
            .map(|(what, pin)| AnalogReading {
                what: *what,
                value: pin.get(),
                deadband: match what {
                    Jogged::Joint(_) => self.joint_deadband.get(),
                    Jogged::Axis(_) => self.axis_deadband.get(),
                },
                speed: speed(*what),
            })
            .collect()
    }
}

/// What one input did last.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Last {
    value: f64,
    speed: f64,
    jogging: bool,
}

/// The analog jogs' memory between cycles.
#[derive(Debug, Default)]
pub struct AnalogJogs {
    last: Vec<Last>,
}

impl AnalogJogs {
    /// The jog starts and stops the readings ask for: a jog at `value` ×
    /// jog speed when the value (or the speed) changed outside the
    /// deadband, a stop when the value came back inside. The first
    /// readings only start the memory: a stick held at start-up does
    /// not jog until it moves.
    pub fn actions(&mut self, readings: &[AnalogReading]) -> Vec<Action> {
        let fresh = |r: &AnalogReading| Last {
            value: r.value,
            speed: r.speed,
            jogging: false,
        };
        if self.last.len() != readings.len() {
            self.last = readings.iter().map(fresh).collect();
            return Vec::new();
        }
        let mut out = Vec::new();
        for (r, last) in readings.iter().zip(&mut self.last) {
            let outside = r.value.abs() > r.deadband;
            let changed = r.value != last.value || r.speed != last.speed;
            if outside && (changed || !last.jogging) {
                out.push(Action::JogStart(r.what, r.value));
                last.jogging = true;
            } else if !outside && last.jogging {
                out.push(Action::JogStop(r.what));
                last.jogging = false;
            }
            last.value = r.value;
            last.speed = r.speed;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reading(value: f64, speed: f64) -> [AnalogReading; 1] {
        [AnalogReading {
            what: Jogged::Joint(1),
            value,
            deadband: 0.2,
            speed,
        }]
    }

    #[test]
    fn a_stick_jogs_outside_the_deadband_and_stops_inside() {
        let mut a = AnalogJogs::default();
        let j = Jogged::Joint(1);
        assert!(a.actions(&reading(0.9, 60.0)).is_empty(), "held at start");
        assert_eq!(a.actions(&reading(0.9, 60.0)), [Action::JogStart(j, 0.9)]);
        assert!(a.actions(&reading(0.9, 60.0)).is_empty(), "no repeat");
        assert_eq!(a.actions(&reading(-0.5, 60.0)), [Action::JogStart(j, -0.5)]);
        assert_eq!(
            a.actions(&reading(-0.5, 120.0)),
            [Action::JogStart(j, -0.5)],
            "a new speed"
        );
        assert_eq!(a.actions(&reading(0.1, 120.0)), [Action::JogStop(j)]);
        assert!(a.actions(&reading(-0.15, 120.0)).is_empty(), "inside");
        assert!(a.actions(&reading(0.2, 120.0)).is_empty(), "on the edge");
    }
}
