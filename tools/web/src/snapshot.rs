//! The whole instance as JSON, for the page's tree: halcmd's `show` of
//! pins, parameters, signals (with writer and readers), functions and
//! threads, values formatted as halcmd formats them.

use hal_core::{Instance, PinDir, SignalInfo};
use hal_lang::format::get_value;
use serde_json::{json, Value as Json};

/// Everything the tree shows, read in one pass per kind.
pub fn show(inst: &Instance) -> hal_core::Result<Json> {
    let pins: Vec<Json> = inst
        .pins()?
        .into_iter()
        .map(|p| {
            json!({
                "name": p.name,
                "owner": p.owner,
                "type": p.hal_type.name(),
                "dir": p.dir.label(),
                "value": get_value(p.value),
                "signal": p.signal,
            })
        })
        .collect();
    let params: Vec<Json> = inst
        .params()?
        .into_iter()
        .map(|p| {
            json!({
                "name": p.name,
                "owner": p.owner,
                "type": p.hal_type.name(),
                "dir": p.dir.label(),
                "value": get_value(p.value),
            })
        })
        .collect();
    let signals: Vec<Json> = inst.signals()?.iter().map(signal).collect();
    let functs: Vec<Json> = inst
        .functs()?
        .into_iter()
        .map(|f| {
            json!({
                "name": f.name,
                "owner": f.owner,
                "reentrant": f.reentrant,
                "users": f.users,
                "time": f.time_ns,
                "tmax": f.tmax_ns,
            })
        })
        .collect();
    let threads: Vec<Json> = inst
        .threads()?
        .into_iter()
        .map(|t| {
            json!({
                "name": t.name,
                "period": t.period,
                "running": t.running,
                "functs": t.functs,
                "time": t.time_ns,
                "tmax": t.tmax_ns,
                "overruns": t.overruns,
                "cycles": t.cycles,
            })
        })
        .collect();
    Ok(json!({
        "instance": inst.name(),
        "pins": pins,
        "params": params,
        "signals": signals,
        "functs": functs,
        "threads": threads,
    }))
}

/// A signal with its writer, its I/O pins and its readers.
fn signal(s: &SignalInfo) -> Json {
    let with = |dir: PinDir| -> Vec<&str> {
        s.pins
            .iter()
            .filter(|(_, d)| *d == dir)
            .map(|(n, _)| n.as_str())
            .collect()
    };
    json!({
        "name": s.name,
        "type": s.hal_type.name(),
        "value": get_value(s.value),
        "writer": with(PinDir::Out).first(),
        "bidirs": with(PinDir::Io),
        "readers": with(PinDir::In),
    })
}
