//! Reading what a page watches: pins, parameters and signals through
//! halmeter's reading (one short read each) or, for long lists, one
//! snapshot per kind; functions' and threads' last and longest times.

use std::collections::HashMap;

use hal_core::Instance;
use hal_lang::format::get_value;
use hal_tools::meter::{read, Kind};
use serde::Deserialize;

/// Most items one page may watch: a bound on the work of each tick.
pub const MAX_ITEMS: usize = 2000;

/// From this many pins, parameters and signals on, a tick reads one
/// snapshot per kind (one pass over the instance) instead of one read per
/// item.
const SNAPSHOT_FROM: usize = 32;

/// One watched object.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
pub struct Item {
    /// `pin`, `param`, `sig`, `funct` or `thread`.
    pub kind: String,
    /// Its HAL name.
    pub name: String,
}

/// The current values of `items`, in order; `None` for one that does not
/// exist (any more).
pub fn values(inst: &Instance, items: &[Item]) -> Vec<Option<String>> {
    let metered = items
        .iter()
        .filter(|i| Kind::from_word(&i.kind).is_some())
        .count();
    let table = if metered >= SNAPSHOT_FROM {
        Some(snapshot(inst, items))
    } else {
        None
    };
    let timed = timed(inst, items);
    items
        .iter()
        .map(|item| {
            if let Some(t) = timed.get(&(item.kind.as_str(), item.name.as_str())) {
                return Some(t.clone());
            }
            let kind = Kind::from_word(&item.kind)?;
            match &table {
                Some(t) => t.get(&(kind_key(kind), item.name.as_str())).cloned(),
                None => read(inst, Some(kind), &item.name)
                    .ok()
                    .map(|(_, v)| get_value(v)),
            }
        })
        .collect()
}

fn kind_key(kind: Kind) -> &'static str {
    match kind {
        Kind::Pin => "pin",
        Kind::Param => "param",
        Kind::Signal => "sig",
    }
}

/// Values of every pin, parameter and signal, of the kinds `items` has.
fn snapshot<'a>(inst: &Instance, items: &'a [Item]) -> HashMap<(&'static str, &'a str), String> {
    let wanted = |k: Kind| items.iter().any(|i| Kind::from_word(&i.kind) == Some(k));
    let mut all: HashMap<(&'static str, String), String> = HashMap::new();
    if wanted(Kind::Pin) {
        for p in inst.pins().unwrap_or_default() {
            all.insert(("pin", p.name), get_value(p.value));
        }
    }
    if wanted(Kind::Param) {
        for p in inst.params().unwrap_or_default() {
            all.insert(("param", p.name), get_value(p.value));
        }
    }
    if wanted(Kind::Signal) {
        for s in inst.signals().unwrap_or_default() {
            all.insert(("sig", s.name), get_value(s.value));
        }
    }
    items
        .iter()
        .filter_map(|i| {
            let key = kind_key(Kind::from_word(&i.kind)?);
            let v = all.get(&(key, i.name.clone()))?.clone();
            Some(((key, i.name.as_str()), v))
        })
        .collect()
}

/// Last and longest run times of the watched threads and functions.
fn timed<'a>(inst: &Instance, items: &'a [Item]) -> HashMap<(&'a str, &'a str), String> {
    let mut out = HashMap::new();
    if !items
        .iter()
        .any(|i| i.kind == "thread" || i.kind == "funct")
    {
        return out;
    }
    let times = |time: i32, tmax: i32| format!("{time} ns (max {tmax} ns)");
    let threads = inst.threads().unwrap_or_default();
    let functs = inst.functs().unwrap_or_default();
    for item in items {
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
        if let Some(v) = found {
            out.insert((item.kind.as_str(), item.name.as_str()), v);
        }
    }
    out
}
