//! Reading what a page watches, tick after tick: pins, parameters and
//! signals through one [`ValueSet`] (their names looked up once, and again
//! only after a structural change; each tick one short hold of the HAL
//! lock and one load per value, as halmeter reads one), functions' and
//! threads' last and longest times. Only what changed since the last tick
//! is formatted and written out.

use std::io::Write as _;

use hal_core::{Instance, Value, ValueKind, ValueSet};
use hal_lang::format::get_value;
use hal_tools::meter::Kind;
use serde::Deserialize;

/// Most items one page may watch: a bound on the work of each tick.
pub const MAX_ITEMS: usize = 2000;

/// One watched object.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
pub struct Item {
    /// `pin`, `param`, `sig`, `funct` or `thread`.
    pub kind: String,
    /// Its HAL name.
    pub name: String,
}

/// The [`ValueSet`] kind of a pin, parameter or signal item.
pub fn value_kind(item: &Item) -> Option<ValueKind> {
    Some(match Kind::from_word(&item.kind)? {
        Kind::Pin => ValueKind::Pin,
        Kind::Param => ValueKind::Param,
        Kind::Signal => ValueKind::Signal,
    })
}

/// What one item read last: a value (compared by its bits, so a NaN that
/// stays NaN is no change), a time's text, or nothing (missing).
#[derive(Debug, Clone, PartialEq)]
enum Seen {
    Missing,
    Value(hal_core::HalType, u64),
    Timed(String),
}

impl Seen {
    fn of(v: Option<Value>) -> Seen {
        v.map_or(Seen::Missing, |v| Seen::Value(v.hal_type(), v.to_bits()))
    }
}

/// A page's watch list, read tick after tick.
pub struct Watched {
    items: Vec<Item>,
    /// The pins, parameters and signals among `items`.
    set: ValueSet,
    /// Per item, its place in `set` (None: a thread or function).
    place: Vec<Option<usize>>,
    /// Whether any item is a thread or a function.
    any_timed: bool,
    /// The set's values of this tick.
    values: Vec<Option<Value>>,
    /// Per item, what the last tick read (None before the first).
    last: Vec<Option<Seen>>,
}

impl Watched {
    /// A watch list of `items`, not read yet.
    pub fn new(items: Vec<Item>) -> Watched {
        let mut names = Vec::new();
        let place = items
            .iter()
            .map(|item| {
                let kind = value_kind(item)?;
                names.push((kind, item.name.clone()));
                Some(names.len() - 1)
            })
            .collect();
        let any_timed = items
            .iter()
            .any(|i| i.kind == "thread" || i.kind == "funct");
        Watched {
            last: vec![None; items.len()],
            items,
            set: ValueSet::new(names),
            place,
            any_timed,
            values: Vec::new(),
        }
    }

    /// Reads every item and writes `"INDEX":"TEXT"` (or `"INDEX":null`
    /// for an item that does not exist) for each that changed since the
    /// last tick (each, at the first), separated by commas, to `out`;
    /// how many it wrote.
    pub fn changes(&mut self, inst: &Instance, out: &mut Vec<u8>) -> usize {
        if !self.set.is_empty() && inst.read_values(&mut self.set, &mut self.values).is_err() {
            // The segment cannot be read (being torn down): all missing.
            self.values = vec![None; self.set.len()];
        }
        let timed = if self.any_timed {
            timed(inst, &self.items)
        } else {
            Vec::new()
        };
        let mut written = 0;
        for (i, place) in self.place.iter().enumerate() {
            let now = match place {
                Some(p) => Seen::of(self.values[*p]),
                None => timed
                    .iter()
                    .find(|(at, _)| *at == i)
                    .map_or(Seen::Missing, |(_, t)| Seen::Timed(t.clone())),
            };
            if self.last[i].as_ref() == Some(&now) {
                continue;
            }
            if written > 0 {
                out.push(b',');
            }
            let text = match &now {
                Seen::Missing => None,
                Seen::Timed(t) => Some(t.clone()),
                Seen::Value(t, bits) => Some(get_value(Value::from_bits(*t, *bits))),
            };
            // Writing to a Vec cannot fail; the texts are plain strings.
            let _ = write!(out, "\"{i}\":");
            let _ = serde_json::to_writer(&mut *out, &text);
            self.last[i] = Some(now);
            written += 1;
        }
        written
    }
}

/// Last and longest run times of the watched threads and functions, by
/// their index in `items`.
fn timed(inst: &Instance, items: &[Item]) -> Vec<(usize, String)> {
    let times = |time: i32, tmax: i32| format!("{time} ns (max {tmax} ns)");
    let threads = inst.threads().unwrap_or_default();
    let functs = inst.functs().unwrap_or_default();
    items
        .iter()
        .enumerate()
        .filter_map(|(i, item)| {
            let found = match item.kind.as_str() {
                "thread" => threads
                    .iter()
                    .find(|t| t.name == item.name)
                    .map(|t| times(t.time_ns, t.tmax_ns)),
                "funct" => functs
                    .iter()
                    .find(|f| f.name == item.name)
                    .map(|f| times(f.time_ns, f.tmax_ns)),
                _ => None,
            };
            found.map(|v| (i, v))
        })
        .collect()
}
