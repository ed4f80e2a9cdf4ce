//! Reading what a page watches: pins, parameters and signals through
//! halmeter's reading, functions' and threads' last and longest times.

use hal_core::Instance;
use hal_lang::format::get_value;
use hal_tools::meter::{read, Kind};
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

/// The current values of `items`, in order; `None` for one that does not
/// exist (any more).
pub fn values(inst: &Instance, items: &[Item]) -> Vec<Option<String>> {
    let timed = items
        .iter()
        .any(|i| i.kind == "thread" || i.kind == "funct");
    let (threads, functs) = if timed {
        (
            inst.threads().unwrap_or_default(),
            inst.functs().unwrap_or_default(),
        )
    } else {
        (Vec::new(), Vec::new())
    };
    let times = |time: i32, tmax: i32| format!("{time} ns (max {tmax} ns)");
    items
        .iter()
        .map(|item| match item.kind.as_str() {
            "thread" => threads
                .iter()
                .find(|t| t.name == item.name)
                .map(|t| times(t.time_ns, t.tmax_ns)),
            "funct" => functs
                .iter()
                .find(|f| f.name == item.name)
                .map(|f| times(f.time_ns, f.tmax_ns)),
            word => {
                let kind = Kind::from_word(word)?;
                read(inst, Some(kind), &item.name)
                    .ok()
                    .map(|(_, v)| get_value(v))
            }
        })
        .collect()
}
