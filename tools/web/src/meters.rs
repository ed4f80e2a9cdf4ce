//! Meters: a pin, signal or parameter shown with its value and the
//! smallest and largest value seen since the meter started, read at each
//! tick of the live stream the way the stream reads its values (one
//! [`ValueSet`]: one short hold of the HAL lock, one load per value; the
//! realtime threads never wait on it). A page resets its meters by
//! opening a new stream.

use hal_core::{Instance, Value, ValueSet};
use hal_lang::format::get_value;
use hal_scope::scope::capture::numeric;
use serde::Serialize;

use crate::error::WebError;
use crate::watch::{value_kind, Item};

/// Most meters one page may show.
pub const MAX_METERS: usize = 16;

/// What a meter shows.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reading {
    /// The value as halcmd prints it; `None` while the object is missing.
    pub value: Option<String>,
    /// The smallest value seen (bits as 0 and 1), NaN never counted.
    pub min: Option<f64>,
    /// The largest value seen.
    pub max: Option<f64>,
}

impl Reading {
    fn update(&mut self, v: Value) {
        self.value = Some(get_value(v));
        let x = numeric(v.hal_type(), v.to_bits());
        if x.is_nan() {
            return;
        }
        self.min = Some(self.min.map_or(x, |m| m.min(x)));
        self.max = Some(self.max.map_or(x, |m| m.max(x)));
    }
}

/// The meters of one stream.
#[derive(Debug)]
pub struct Meters {
    set: ValueSet,
    values: Vec<Option<Value>>,
    seen: Vec<Reading>,
}

impl Meters {
    /// Meters on `items` (pins, signals or parameters), checked.
    pub fn new(items: &[Item]) -> Result<Meters, WebError> {
        if items.len() > MAX_METERS {
            return Err(WebError::TooManyMeters { max: MAX_METERS });
        }
        let items = items
            .iter()
            .map(|i| match value_kind(i) {
                Some(k) => Ok((k, i.name.clone())),
                None => Err(WebError::MeterKind {
                    kind: i.kind.clone(),
                    name: i.name.clone(),
                }),
            })
            .collect::<Result<Vec<_>, _>>()?;
        let seen = vec![
            Reading {
                value: None,
                min: None,
                max: None,
            };
            items.len()
        ];
        Ok(Meters {
            set: ValueSet::new(items),
            values: Vec::new(),
            seen,
        })
    }

    /// Reads every meter once; the readings, in order.
    pub fn read(&mut self, inst: &Instance) -> &[Reading] {
        if self.set.is_empty() {
            return &self.seen;
        }
        if inst.read_values(&mut self.set, &mut self.values).is_err() {
            self.values = vec![None; self.set.len()];
        }
        for (value, seen) in self.values.iter().zip(&mut self.seen) {
            match value {
                Some(v) => seen.update(*v),
                // Gone (unloaded): the value goes, what was seen stays.
                None => seen.value = None,
            }
        }
        &self.seen
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_and_max_follow_the_values() {
        let mut r = Meters::new(&[Item {
            kind: "pin".into(),
            name: "x".into(),
        }])
        .unwrap();
        let seen = &mut r.seen[0];
        for v in [2.5, -1.0, f64::NAN, 0.5] {
            seen.update(Value::Float(v));
        }
        assert_eq!((seen.min, seen.max), (Some(-1.0), Some(2.5)));
        assert_eq!(seen.value.as_deref(), Some("0.5"));
        let mut b = Reading {
            value: None,
            min: None,
            max: None,
        };
        b.update(Value::Bit(true));
        assert_eq!(
            (b.min, b.max, b.value.as_deref()),
            (Some(1.0), Some(1.0), Some("TRUE"))
        );
    }

    #[test]
    fn only_pins_signals_and_params_are_meters() {
        let item = |k: &str| Item {
            kind: k.into(),
            name: "n".into(),
        };
        assert!(Meters::new(&[item("sig"), item("param")]).is_ok());
        let e = Meters::new(&[item("thread")]).unwrap_err();
        assert!(e.to_string().contains("not a 'thread'"), "{e}");
        assert!(Meters::new(&vec![item("pin"); MAX_METERS + 1]).is_err());
    }
}
