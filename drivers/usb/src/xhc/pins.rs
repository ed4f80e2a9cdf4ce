//! The component's HAL pins, named as LinuxCNC's xhc-hb04 names them,
//! and how the pendant's state is written to them.

use hal_core::{Component, In, Out, Pin};

use super::buttons::{self, Button};
use super::report::{Display, Switch};
use super::state::{Pendant, Velocity};

/// The axis letters of the per-axis pins, in switch order.
pub const AXES: [char; 4] = ['x', 'y', 'z', 'a'];

/// One button's pins: the button itself and, for zero, goto-zero and
/// half, one per axis.
struct ButtonPins {
    code: u8,
    pin: Pin<bool, Out>,
    per_axis: Option<[Pin<bool, Out>; 4]>,
}

/// Every pin.
pub struct Pins {
    absolute: [Pin<f64, In>; 4],
    relative: [Pin<f64, In>; 4],
    feed_override: Pin<f64, In>,
    feed_value: Pin<f64, In>,
    spindle_override: Pin<f64, In>,
    spindle_rps: Pin<f64, In>,
    inch_icon: Pin<bool, In>,
    buttons: Vec<ButtonPins>,
    enable_off: Pin<bool, Out>,
    enable_axis: [Pin<bool, Out>; 4],
    enable_feed: Pin<bool, Out>,
    enable_spindle: Pin<bool, Out>,
    counts: Pin<i32, Out>,
    counts_neg: Pin<i32, Out>,
    scale: Pin<f64, Out>,
    max_velocity: Pin<f64, In>,
    velocity: Pin<f64, Out>,
    increment: Pin<f64, Out>,
    plus: [Pin<bool, Out>; 4],
    minus: [Pin<bool, Out>; 4],
    /// `stepsize-up`.
    pub stepsize_up: Pin<bool, In>,
    /// `stepsize-down`.
    pub stepsize_down: Pin<bool, In>,
    stepsize: Pin<i32, Out>,
    sleeping: Pin<bool, Out>,
    /// `connected`.
    pub connected: Pin<bool, Out>,
    require_pendant: Pin<bool, Out>,
}

/// Four pins `<m>.<axis>.<what>` or `<m>.<prefix><axis>`.
fn four<T: hal_core::PinValue, D: hal_core::Direction>(
    name: impl Fn(char) -> String,
    comp: &Component,
) -> hal_core::Result<[Pin<T, D>; 4]> {
    Ok([
        comp.pin(&name('x'))?,
        comp.pin(&name('y'))?,
        comp.pin(&name('z'))?,
        comp.pin(&name('a'))?,
    ])
}

impl Pins {
    /// Makes the pins on `comp`, named `<m>.*`.
    pub fn new(
        comp: &Component,
        m: &str,
        list: &[Button],
        require: bool,
    ) -> hal_core::Result<Pins> {
        let p = |n: &str| format!("{m}.{n}");
        let mut buttons = Vec::with_capacity(list.len());
        for b in list {
            let per_axis = if buttons::has_axis_pins(&b.name) {
                Some(four(|a| format!("{m}.{}-{a}", b.name), comp)?)
            } else {
                None
            };
            buttons.push(ButtonPins {
                code: b.code,
                pin: comp.pin(&p(&b.name))?,
                per_axis,
            });
        }
        let pins = Pins {
            absolute: four(|a| format!("{m}.{a}.pos-absolute"), comp)?,
            relative: four(|a| format!("{m}.{a}.pos-relative"), comp)?,
            feed_override: comp.pin(&p("feed-override"))?,
            feed_value: comp.pin(&p("feed-value"))?,
            spindle_override: comp.pin(&p("spindle-override"))?,
            spindle_rps: comp.pin(&p("spindle-rps"))?,
            inch_icon: comp.pin(&p("inch-icon"))?,
            buttons,
            enable_off: comp.pin(&p("jog.enable-off"))?,
            enable_axis: four(|a| format!("{m}.jog.enable-{a}"), comp)?,
            enable_feed: comp.pin(&p("jog.enable-feed-override"))?,
            enable_spindle: comp.pin(&p("jog.enable-spindle-override"))?,
            counts: comp.pin(&p("jog.counts"))?,
            counts_neg: comp.pin(&p("jog.counts-neg"))?,
            scale: comp.pin(&p("jog.scale"))?,
            max_velocity: comp.pin(&p("jog.max-velocity"))?,
            velocity: comp.pin(&p("jog.velocity"))?,
            increment: comp.pin(&p("jog.increment"))?,
            plus: four(|a| format!("{m}.jog.plus-{a}"), comp)?,
            minus: four(|a| format!("{m}.jog.minus-{a}"), comp)?,
            stepsize_up: comp.pin(&p("stepsize-up"))?,
            stepsize_down: comp.pin(&p("stepsize-down"))?,
            stepsize: comp.pin(&p("stepsize"))?,
            sleeping: comp.pin(&p("sleeping"))?,
            connected: comp.pin(&p("connected"))?,
            require_pendant: comp.pin(&p("require_pendant"))?,
        };
        pins.require_pendant.set(require);
        Ok(pins)
    }

    /// Writes what the last report said.
    pub fn write_pendant(&self, s: &Pendant) {
        self.counts.set(s.counts);
        self.counts_neg.set(s.counts.wrapping_neg());
        self.enable_off.set(s.off());
        for (i, pin) in self.enable_axis.iter().enumerate() {
            pin.set(s.axis_enabled(i));
        }
        self.enable_feed.set(s.switch == Switch::Feed);
        self.enable_spindle.set(s.switch == Switch::Spindle);
        for b in &self.buttons {
            let held = s.button == b.code;
            b.pin.set(held);
            if let Some(axes) = &b.per_axis {
                for (i, pin) in axes.iter().enumerate() {
                    pin.set(held && s.axis_enabled(i));
                }
            }
        }
        self.sleeping.set(s.sleeping);
    }

    /// Writes the step size and the jog scale it gives.
    pub fn write_stepsize(&self, stepsize: i32) {
        self.stepsize.set(stepsize);
        self.scale.set(f64::from(stepsize) * 0.001);
    }

    /// The jog scale and `jog.max-velocity`, for the velocity outputs.
    pub fn velocity_inputs(&self) -> (f64, f64) {
        (self.scale.get(), self.max_velocity.get())
    }

    /// Writes the velocity outputs; plus/minus only for the axis the
    /// switch is on.
    pub fn write_velocity(&self, s: &Pendant, v: &Velocity) {
        self.velocity.set(v.velocity);
        self.increment.set(v.increment);
        for i in 0..AXES.len() {
            let on = s.axis_enabled(i);
            self.plus[i].set(on && v.direction > 0);
            self.minus[i].set(on && v.direction < 0);
        }
    }

    /// What the display is to show.
    pub fn display(&self, s: &Pendant, stepsize: i32) -> Display {
        Display {
            relative: self.relative.each_ref().map(|p| p.get()),
            absolute: self.absolute.each_ref().map(|p| p.get()),
            feed_override: self.feed_override.get(),
            spindle_override: self.spindle_override.get(),
            feed: self.feed_value.get(),
            spindle_rps: self.spindle_rps.get(),
            stepsize,
            inch: self.inch_icon.get(),
            show_a: s.switch == Switch::A,
        }
    }
}
