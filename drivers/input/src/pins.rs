//! One device's HAL pins, named, typed and initialised as LinuxCNC's
//! hal_input makes them (`input.N.key-a`, `input.N.abs-x-position`...),
//! and how its events and the HAL inputs drive them each cycle.

use std::collections::BTreeSet;

use hal_core::{Component, In, Out, Param, Pin, Ro};

use crate::device::InputDevice;
use crate::error::Result;
use crate::names::{code_name, hal_name, last_code, type_name};
use crate::regs::{Event, EV_ABS, EV_KEY, EV_LED, EV_REL, EV_SYN, SYN_DROPPED};
use crate::spec::Parts;

/// `is-pos` and `is-neg` are true past this position, as LinuxCNC's
/// (a joystick at rest is seldom exactly at zero).
pub const IS_POS_NEG_THRESHOLD: f64 = 0.01;

/// A key or button: `input.N.NAME` and `input.N.NAME-not`.
struct KeyPins {
    code: u16,
    on: Pin<bool, Out>,
    not: Pin<bool, Out>,
}

/// A relative axis.
struct RelPins {
    code: u16,
    position: Pin<f64, Out>,
    counts: Pin<i32, Out>,
    reset: Pin<bool, In>,
    scale: Pin<f64, In>,
}

/// An absolute axis.
struct AbsPins {
    code: u16,
    position: Pin<f64, Out>,
    counts: Pin<i32, Out>,
    is_pos: Pin<bool, Out>,
    is_neg: Pin<bool, Out>,
    scale: Pin<f64, In>,
    offset: Pin<f64, In>,
    fuzz: Pin<i32, In>,
    flat: Pin<i32, In>,
    _min: Param<i32, Ro>,
    _max: Param<i32, Ro>,
}

/// An LED: `input.N.NAME` and `input.N.NAME-invert`, both inputs.
struct LedPins {
    code: u16,
    on: Pin<bool, In>,
    invert: Pin<bool, In>,
    last: bool,
}

/// The pins of device `input.N`.
pub struct DevicePins {
    prefix: String,
    parts: Parts,
    keys: Vec<KeyPins>,
    rel: Vec<RelPins>,
    abs: Vec<AbsPins>,
    leds: Vec<LedPins>,
    reported: BTreeSet<(u16, u16)>,
}

/// Whether a float is "true" as Python sees it (zero is not): LinuxCNC
/// divides by `scale or 1`.
fn or_one(scale: f64) -> f64 {
    if scale == 0.0 {
        1.0
    } else {
        scale
    }
}

/// Python's `int()` of a float, saturated to 32 bits (NaN as 0).
fn trunc_i32(v: f64) -> i32 {
    v as i32
}

/// The pin-name stems of a device's codes of one type, in code order.
fn named(dev: &mut dyn InputDevice, kind: u16) -> Result<Vec<(u16, String)>> {
    let Some(max) = last_code(kind) else {
        return Ok(Vec::new());
    };
    Ok(dev
        .codes(kind, max)?
        .into_iter()
        .filter_map(|c| code_name(kind, c).map(|n| (c, hal_name(&n))))
        .collect())
}

impl DevicePins {
    /// Makes the pins of device `index` on `comp` for the features in
    /// `parts`, with their starting values; LEDs are switched off.
    pub fn new(
        comp: &Component,
        index: usize,
        dev: &mut dyn InputDevice,
        parts: Parts,
    ) -> Result<DevicePins> {
        let prefix = format!("input.{index}");
        let p = |stem: &str, what: &str| format!("{prefix}.{stem}{what}");
        let mut d = DevicePins {
            prefix: prefix.clone(),
            parts,
            keys: Vec::new(),
            rel: Vec::new(),
            abs: Vec::new(),
            leds: Vec::new(),
            reported: BTreeSet::new(),
        };
        if parts.keys {
            for (code, n) in named(dev, EV_KEY)? {
                d.keys.push(KeyPins {
                    code,
                    on: comp.pin(&p(&n, ""))?,
                    not: comp.pin_init(&p(&n, "-not"), true)?,
                });
            }
            // LinuxCNC's starts every key released; a key already held
            // is shown held here.
            let mut held = dev.keys_held()?;
            held.sort_unstable();
            d.apply_held(&held);
        }
        if parts.rel {
            for (code, n) in named(dev, EV_REL)? {
                d.rel.push(RelPins {
                    code,
                    position: comp.pin(&p(&n, "-position"))?,
                    counts: comp.pin(&p(&n, "-counts"))?,
                    reset: comp.pin(&p(&n, "-reset"))?,
                    scale: comp.pin_init(&p(&n, "-scale"), 1.0)?,
                });
            }
        }
        if parts.abs {
            for (code, n) in named(dev, EV_ABS)? {
                let info = dev.absinfo(code)?;
                let center = (f64::from(info.minimum) + f64::from(info.maximum)) / 2.0;
                let halfrange = or_one((f64::from(info.maximum) - f64::from(info.minimum)) / 2.0);
                d.abs.push(AbsPins {
                    code,
                    position: comp.pin_init(
                        &p(&n, "-position"),
                        (f64::from(info.value) - center) / halfrange,
                    )?,
                    counts: comp.pin_init(&p(&n, "-counts"), info.value)?,
                    is_pos: comp.pin(&p(&n, "-is-pos"))?,
                    is_neg: comp.pin(&p(&n, "-is-neg"))?,
                    scale: comp.pin_init(&p(&n, "-scale"), halfrange)?,
                    offset: comp.pin_init(&p(&n, "-offset"), center)?,
                    fuzz: comp.pin_init(&p(&n, "-fuzz"), info.fuzz)?,
                    flat: comp.pin_init(&p(&n, "-flat"), info.flat)?,
                    _min: comp.param(&p(&n, "-min"), info.minimum)?,
                    _max: comp.param(&p(&n, "-max"), info.maximum)?,
                });
            }
        }
        if parts.leds {
            for (code, n) in named(dev, EV_LED)? {
                d.leds.push(LedPins {
                    code,
                    on: comp.pin(&p(&n, ""))?,
                    invert: comp.pin(&p(&n, "-invert"))?,
                    last: false,
                });
                dev.write(Event {
                    kind: EV_LED,
                    code,
                    value: 0,
                })?;
            }
        }
        Ok(d)
    }

    /// The pin prefix (`input.N`).
    pub fn prefix(&self) -> &str {
        &self.prefix
    }

    /// Shows exactly the keys in `held` as held.
    fn apply_held(&self, held: &[u16]) {
        for k in &self.keys {
            let on = held.binary_search(&k.code).is_ok();
            k.on.set(on);
            k.not.set(!on);
        }
    }

    /// Applies one event; returns a note to print for an event no pin
    /// takes (once per type and code).
    pub fn apply(&mut self, dev: &mut dyn InputDevice, e: &Event) -> Result<Option<String>> {
        let wanted = match e.kind {
            EV_SYN if e.code == SYN_DROPPED => {
                self.resync(dev)?;
                return Ok(None);
            }
            EV_SYN | crate::regs::EV_SND | crate::regs::EV_MSC | EV_LED => return Ok(None),
            EV_KEY => self.parts.keys,
            EV_REL => self.parts.rel,
            EV_ABS => self.parts.abs,
            _ => true,
        };
        if !wanted {
            return Ok(None);
        }
        let taken = match e.kind {
            EV_KEY => self.key(e),
            EV_REL => self.relative(e),
            EV_ABS => self.absolute(e),
            _ => false,
        };
        if taken || !self.reported.insert((e.kind, e.code)) {
            return Ok(None);
        }
        let code = code_name(e.kind, e.code).unwrap_or_else(|| e.code.to_string());
        Ok(Some(format!(
            "{}: unexpected event {} {code} (no pin for it; not reported again)",
            self.prefix,
            type_name(e.kind)
        )))
    }

    /// Events were lost (the kernel's buffer overflowed): asks the
    /// kernel which keys are held and where the absolute axes are. Lost
    /// relative motion cannot be had again.
    fn resync(&self, dev: &mut dyn InputDevice) -> Result<()> {
        if !self.keys.is_empty() {
            let mut held = dev.keys_held()?;
            held.sort_unstable();
            self.apply_held(&held);
        }
        for a in &self.abs {
            let value = dev.absinfo(a.code)?.value;
            self.absolute(&Event {
                kind: EV_ABS,
                code: a.code,
                value,
            });
        }
        Ok(())
    }

    fn key(&self, e: &Event) -> bool {
        let Ok(i) = self.keys.binary_search_by_key(&e.code, |k| k.code) else {
            return false;
        };
        let on = e.value != 0;
        self.keys[i].on.set(on);
        self.keys[i].not.set(!on);
        true
    }

    fn relative(&self, e: &Event) -> bool {
        let Ok(i) = self.rel.binary_search_by_key(&e.code, |r| r.code) else {
            return false;
        };
        let c = &self.rel[i].counts;
        c.set(c.get().wrapping_add(e.value));
        true
    }

    fn absolute(&self, e: &Event) -> bool {
        let Ok(i) = self.abs.binary_search_by_key(&e.code, |a| a.code) else {
            return false;
        };
        let a = &self.abs[i];
        let (flat, fuzz) = (i64::from(a.flat.get()), i64::from(a.fuzz.get()));
        let center = trunc_i32(a.offset.get());
        let v = i64::from(e.value);
        let c = i64::from(center);
        let value = if v < c - flat || v > c + flat {
            e.value
        } else {
            center
        };
        if (i64::from(value) - i64::from(a.counts.get())).abs() > fuzz {
            a.counts.set(value);
        }
        true
    }

    /// The once-a-cycle part: positions from counts, `reset`, and the
    /// LEDs the HAL inputs changed.
    pub fn cycle(&mut self, dev: &mut dyn InputDevice) -> Result<()> {
        for a in &self.abs {
            let position = (f64::from(a.counts.get()) - a.offset.get()) / or_one(a.scale.get());
            a.position.set(position);
            a.is_neg.set(position < -IS_POS_NEG_THRESHOLD);
            a.is_pos.set(position > IS_POS_NEG_THRESHOLD);
        }
        for r in &self.rel {
            if r.reset.get() {
                r.counts.set(0);
            }
            r.position
                .set(f64::from(r.counts.get()) / or_one(r.scale.get()));
        }
        for l in &mut self.leds {
            let on = l.on.get() != l.invert.get();
            if on != l.last {
                dev.write(Event {
                    kind: EV_LED,
                    code: l.code,
                    value: i32::from(on),
                })?;
                l.last = on;
            }
        }
        Ok(())
    }

    /// What the outputs show when the device is lost or hal_input stops:
    /// every key released, every absolute axis at its offset (a stick
    /// let go), positions recomputed. Relative counts stay (a wheel that
    /// stops turning keeps its count).
    pub fn safe_state(&self) {
        self.apply_held(&[]);
        for a in &self.abs {
            a.counts.set(trunc_i32(a.offset.get()));
            let position = (f64::from(a.counts.get()) - a.offset.get()) / or_one(a.scale.get());
            a.position.set(position);
            a.is_neg.set(position < -IS_POS_NEG_THRESHOLD);
            a.is_pos.set(position > IS_POS_NEG_THRESHOLD);
        }
    }
}
