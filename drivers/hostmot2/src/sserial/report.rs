//! What discovery found on a board's Smart Serial ports, as text (the
//! board tool's `sserial` command): per port the processor's revision,
//! per card its name, unit, mode and modes, its process data with the
//! HAL names they get, and its globals with their values.

use std::fmt::Write as _;

use super::records::{data_type as t, DataRecord};
use crate::modules::sserial::discovery::SserialFirmware;

fn type_name(ty: u8) -> &'static str {
    match ty {
        t::PAD => "pad",
        t::BITS => "bits",
        t::UNSIGNED => "unsigned",
        t::SIGNED => "signed",
        t::NV_UNSIGNED => "nv unsigned",
        t::NV_SIGNED => "nv signed",
        t::STREAM => "stream",
        t::BOOLEAN => "boolean",
        t::ENCODER => "encoder",
        t::FLOAT => "float",
        t::NV_FLOAT => "nv float",
        _ => "unknown",
    }
}

fn direction(r: &DataRecord) -> &'static str {
    match (r.is_in(), r.is_out()) {
        (true, true) => "both",
        (true, false) => "in",
        _ => "out",
    }
}

/// A record's unit as shown: nothing for a unitless one (`None`).
fn unit_text(unit: &str) -> &str {
    if unit.eq_ignore_ascii_case("none") {
        ""
    } else {
        unit
    }
}

/// The HAL objects a record becomes (their names after the card's prefix).
fn hal_names(n: String, r: &DataRecord) -> String {
    match r.data_type {
        t::PAD => String::new(),
        t::BITS if r.bits > 1 => format!("{n}-00 .. {n}-{:02}", r.bits - 1),
        t::BITS => format!("{n}-00"),
        t::ENCODER => format!("{n}.count, {n}.position, ..."),
        _ => n,
    }
}

/// The report of every port of `f` on board `board` (`hm2_7i96s.0`).
pub fn report(f: &SserialFirmware, board: &str) -> String {
    let mut s = String::new();
    for p in &f.ports {
        let _ = writeln!(
            s,
            "Smart Serial port {}: firmware version {}, {} channel(s), {} card(s)",
            p.index,
            p.revision,
            p.channels,
            p.remotes.len()
        );
        for r in &p.remotes {
            let raw = r.raw_name.to_le_bytes();
            let raw: String = raw
                .iter()
                .map(|&b| if b.is_ascii_graphic() { b as char } else { '?' })
                .collect();
            let mode_name = r
                .modes
                .iter()
                .find(|m| m.index == r.mode)
                .map_or("?", |m| m.name.as_str());
            let _ = writeln!(
                s,
                "  channel {}: {raw}, unit 0x{:08X}, mode {} ({mode_name})",
                r.channel, r.unit, r.mode
            );
            let modes: Vec<String> = r
                .modes
                .iter()
                .map(|m| {
                    format!(
                        "{} {}{}",
                        m.index,
                        m.name,
                        if m.software { "" } else { " (hardware)" }
                    )
                })
                .collect();
            let _ = writeln!(s, "    modes: {}", modes.join(", "));
            let (i, o) = r.widths();
            let _ = writeln!(
                s,
                "    process data ({i} bits in, {o} bits out), HAL names under {board}.{}.{}.{}.:",
                r.name(),
                p.index,
                r.channel
            );
            for d in &r.process {
                let range = if d.min != d.max {
                    format!("{}..{} {}", d.min, d.max, unit_text(&d.unit))
                } else {
                    unit_text(&d.unit).to_string()
                };
                let _ = writeln!(
                    s,
                    "      {:<5}{:<10}{:>3}  {:<20}{:<12}{}",
                    direction(d),
                    type_name(d.data_type),
                    d.bits,
                    d.name,
                    range,
                    hal_names(r.hal_name(d), d)
                );
            }
            let _ = writeln!(s, "    globals:");
            for (g, v) in &r.globals {
                let _ = writeln!(
                    s,
                    "      {:<20}= {v} (0x{v:X}){}{}",
                    r.hal_name(g),
                    if unit_text(&g.unit).is_empty() {
                        String::new()
                    } else {
                        format!(" {}", g.unit)
                    },
                    if g.is_out() { "" } else { ", read only" }
                );
            }
        }
    }
    if f.ports.is_empty() {
        s.push_str("no Smart Serial port in use\n");
    }
    s
}
