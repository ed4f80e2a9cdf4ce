//! panelui's HAL pins, with LinuxCNC's names: for a button with a pin
//! output `PREFIX.NAME` and `PREFIX.NAME-not`; with `STATUS_PIN = true`
//! `PREFIX.NAME-state` and `PREFIX.NAME-state-not`; for a radio group
//! with an output `PREFIX.GROUP` and `PREFIX.GROUP-not`. All are outputs.

use hal_core::{Component, Out, Pin};

use super::config::{OutValue, Output, PinKind};
use super::panel::Panel;

/// An output pin of one of the four types.
enum OutPin {
    Bit(Pin<bool, Out>),
    S32(Pin<i32, Out>),
    U32(Pin<u32, Out>),
    Float(Pin<f64, Out>),
}

impl OutPin {
    fn new(comp: &Component, name: &str, kind: PinKind) -> hal_core::Result<OutPin> {
        Ok(match kind {
            PinKind::Bit => OutPin::Bit(comp.pin(name)?),
            PinKind::S32 => OutPin::S32(comp.pin(name)?),
            PinKind::U32 => OutPin::U32(comp.pin(name)?),
            PinKind::Float => OutPin::Float(comp.pin(name)?),
        })
    }

    /// Sets the pin; a value of another type (which the configuration
    /// never gives) leaves it as it is.
    fn set(&self, v: OutValue) {
        match (self, v) {
            (OutPin::Bit(p), OutValue::Bit(x)) => p.set(x),
            (OutPin::S32(p), OutValue::S32(x)) => p.set(x),
            (OutPin::U32(p), OutValue::U32(x)) => p.set(x),
            (OutPin::Float(p), OutValue::Float(x)) => p.set(x),
            _ => {}
        }
    }
}

/// A pair of pins: the value and its `-not`.
type Pair = (OutPin, OutPin);
/// A button's status pins: `-state` and `-state-not`.
type StatusPair = (Pin<bool, Out>, Pin<bool, Out>);

/// Every pin of the panel.
pub struct PanelPins {
    /// Per button: its output pins, its status pins.
    buttons: Vec<(Option<Pair>, Option<StatusPair>)>,
    groups: Vec<Option<Pair>>,
}

impl PanelPins {
    /// Creates the pins of `panel` on `comp`.
    pub fn create(comp: &Component, panel: &Panel) -> hal_core::Result<PanelPins> {
        let cfg = panel.config();
        let name = |n: &str, suffix: &str| format!("{}.{n}{suffix}", cfg.prefix);
        let pair = |n: &str, kind: PinKind| -> hal_core::Result<Pair> {
            Ok((
                OutPin::new(comp, &name(n, ""), kind)?,
                OutPin::new(comp, &name(n, "-not"), kind)?,
            ))
        };
        let mut buttons = Vec::with_capacity(cfg.buttons.len());
        for b in &cfg.buttons {
            let out = match b.output {
                Output::Pin { kind, .. } => Some(pair(&b.name, kind)?),
                _ => None,
            };
            let status = if b.status_pin {
                Some((
                    comp.pin(&name(&b.name, "-state"))?,
                    comp.pin(&name(&b.name, "-state-not"))?,
                ))
            } else {
                None
            };
            buttons.push((out, status));
        }
        let mut groups = Vec::with_capacity(cfg.groups.len());
        for g in &cfg.groups {
            groups.push(match g.kind {
                Some(kind) => Some(pair(&g.name, kind)?),
                None => None,
            });
        }
        let pins = PanelPins { buttons, groups };
        pins.write(panel);
        Ok(pins)
    }

    /// Sets every pin from the panel's state.
    pub fn write(&self, panel: &Panel) {
        for (i, (out, status)) in self.buttons.iter().enumerate() {
            if let (Some((p, n)), Some((v, nv))) = (out, panel.button_pins(i)) {
                p.set(v);
                n.set(nv);
            }
            if let Some((s, sn)) = status {
                s.set(panel.state(i));
                sn.set(!panel.state(i));
            }
        }
        for (g, pins) in self.groups.iter().enumerate() {
            if let (Some((p, n)), Some((v, nv))) = (pins, panel.group_pins(g)) {
                p.set(v);
                n.set(nv);
            }
        }
    }
}
